//! Fuzz target `film_file`: arbitrary bytes into `prism::fuzz::film_file` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::film_file(data, &prism::DefaultPlugins));
