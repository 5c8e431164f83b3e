//! Fuzz target `exr_image`: arbitrary bytes into `prism::fuzz::exr_image` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::exr_image(data, &prism::DefaultPlugins));
