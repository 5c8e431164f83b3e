//! Fuzz target `ply_mesh`: arbitrary bytes into `prism::fuzz::ply_mesh` (see `crates/lab/src/fuzz.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| prism::fuzz::ply_mesh(data, &prism::DefaultPlugins));
