//! Fuzz target `mit6837_scene`: arbitrary bytes into `prism::fuzz::mit6837_scene` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::mit6837_scene(data, &prism::DefaultPlugins));
