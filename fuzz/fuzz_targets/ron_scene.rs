//! Fuzz target `ron_scene`: arbitrary bytes into `prism::fuzz::ron_scene` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::ron_scene(data, &prism::DefaultPlugins));
