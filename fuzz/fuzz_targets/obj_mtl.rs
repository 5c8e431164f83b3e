//! Fuzz target `obj_mtl`: arbitrary bytes into `prism::fuzz::obj_mtl` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::obj_mtl(data, &prism::DefaultPlugins));
