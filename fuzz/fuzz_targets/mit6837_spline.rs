//! Fuzz target `mit6837_spline`: arbitrary bytes into `prism::fuzz::mit6837_spline` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::mit6837_spline(data, &prism::DefaultPlugins));
