//! Fuzz target `film_resume`: arbitrary bytes into `prism::fuzz::film_resume` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::film_resume(data, &prism::DefaultPlugins));
