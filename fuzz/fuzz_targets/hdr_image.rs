//! Fuzz target `hdr_image`: arbitrary bytes into `prism::fuzz::hdr_image` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::hdr_image(data, &prism::DefaultPlugins));
