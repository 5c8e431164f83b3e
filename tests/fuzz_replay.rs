//! The fuzzers' findings, replayed on the stable toolchain so CI guards them forever: every file of
//! `tests/fuzz_corpus/TARGET/` (inputs that crashed, aborted or hung a target before their fix, plus a few small
//! seeds) goes through the same entry point as `fuzz/fuzz_targets/TARGET.rs` and must return, quickly.

use crate::common::root;
use std::time::{Duration, Instant};

#[test]
fn every_input_that_once_crashed_a_fuzz_target_now_returns() {
    let corpus = root().join("tests/fuzz_corpus");
    let mut replayed = 0;
    for (name, entry) in prism::fuzz::TARGETS {
        let dir = corpus.join(name);
        let Ok(files) = std::fs::read_dir(&dir) else { continue };
        let mut files: Vec<_> = files.flatten().map(|f| f.path()).filter(|p| p.is_file()).collect();
        files.sort();
        for f in files {
            let data = std::fs::read(&f).unwrap();
            let t0 = Instant::now();
            let run = std::panic::catch_unwind(|| entry(&data, &prism::DefaultPlugins));
            assert!(run.is_ok(), "{name}: {} panics", f.display());
            let took = t0.elapsed();
            assert!(took < Duration::from_secs(20), "{name}: {} takes {took:?} (a hang before its fix)", f.display());
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no corpus under {}", corpus.display());
}

#[test]
fn every_fuzz_target_has_a_corpus_directory_and_a_target_file() {
    for (name, entry) in prism::fuzz::TARGETS {
        assert!(root().join("tests/fuzz_corpus").join(name).is_dir(), "tests/fuzz_corpus/{name} is missing");
        assert!(root().join("fuzz/fuzz_targets").join(format!("{name}.rs")).is_file(), "fuzz target {name} is missing");
        // The entry points accept anything, the empty input included.
        entry(&[], &prism::DefaultPlugins);
        entry(b"\xff\xfe\x00garbage(((", &prism::DefaultPlugins);
    }
}
