//! Fuzz target `pbrt_scene`: arbitrary bytes into `prism::fuzz::pbrt_scene` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::pbrt_scene(data, &prism::DefaultPlugins));
