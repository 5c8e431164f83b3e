//! Fuzz target `integrator_spec`: arbitrary bytes into `prism::fuzz::integrator_spec` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::integrator_spec(data, &prism::DefaultPlugins));
