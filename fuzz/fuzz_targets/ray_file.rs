//! Fuzz target `ray_file`: arbitrary bytes into `prism::fuzz::ray_file` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::ray_file(data, &prism::DefaultPlugins));
