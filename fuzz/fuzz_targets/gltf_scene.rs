//! Fuzz target `gltf_scene`: arbitrary bytes into `prism::fuzz::gltf_scene` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::gltf_scene(data, &prism::DefaultPlugins));
