//! Several hundred hostile inputs, generated (deterministically) by class, each run through the `prism` binary
//! with a timeout. Every run must end in a render (exit 0) or a clean one-line error (exit 1, one `error:` line,
//! no panic); inputs known to be bad must be errors, inputs known to be good must render. The counts by class and
//! outcome are printed and written to `target/hostile-report.md` (summarised in docs/guide/reliability.md).
//!
//! Classes: forged and truncated images (`images.rs`), mutated RON, 6.837 and OBJ/MTL scenes (`scenes.rs`),
//! hostile command-line values, file kinds, outputs and film files (`cli.rs`), mutated glTF, PLY and pbrt files
//! (`formats.rs`), texture headers beyond the caps, report suites and folders, and untrusted scenes under
//! `--allow-read` (`inputs.rs`).

mod cli;
mod formats;
mod images;
mod inputs;
mod scenes;

use crate::common::{Run, prism_run};
use std::collections::BTreeMap;
use std::ffi::OsString;
use std::path::Path;
use std::time::Duration;

/// What a case's input is known to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expect {
    /// Bad input: must be a clean error.
    Error,
    /// Good input: must render.
    Ok,
    /// A mutation that may or may not be valid: either is fine.
    Either,
}

pub struct Case {
    pub class: &'static str,
    pub name: String,
    pub args: Vec<OsString>,
    pub expect: Expect,
}

impl Case {
    pub fn new(
        class: &'static str,
        name: impl Into<String>,
        args: &[&dyn AsRef<std::ffi::OsStr>],
        expect: Expect,
    ) -> Self {
        Case { class, name: name.into(), args: args.iter().map(|a| a.as_ref().to_os_string()).collect(), expect }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    Rendered,
    CleanError,
    /// A known-bad input accepted, or a known-good one refused.
    Wrong,
    /// Exit 1 without exactly one `error:` line, or another exit code.
    UnclearError,
    Panic,
    Abort,
    Hang,
}

fn classify(r: &Run, expect: Expect) -> Outcome {
    if r.timed_out {
        return Outcome::Hang;
    }
    if r.panicked() {
        return Outcome::Panic;
    }
    match r.code {
        None => Outcome::Abort,
        Some(0) if expect == Expect::Error => Outcome::Wrong,
        Some(0) => Outcome::Rendered,
        Some(1) if r.is_clean_error() && expect == Expect::Ok => Outcome::Wrong,
        Some(1) if r.is_clean_error() => Outcome::CleanError,
        Some(_) => Outcome::UnclearError,
    }
}

/// A scratch directory for one class of cases.
pub fn dir(class: &str) -> std::path::PathBuf {
    crate::common::scratch(&format!("hostile-{class}"))
}

pub fn path_str(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

#[test]
fn several_hundred_hostile_inputs_end_in_a_render_or_a_clean_error() {
    let mut cases = Vec::new();
    cases.extend(images::cases());
    cases.extend(scenes::cases());
    cases.extend(cli::cases());
    cases.extend(formats::cases());
    cases.extend(inputs::cases());
    assert!(cases.len() >= 1000, "only {} cases", cases.len());
    let mut counts: BTreeMap<&str, BTreeMap<Outcome, usize>> = BTreeMap::new();
    let mut failures = Vec::new();
    let mut slowest = Vec::new();
    for c in &cases {
        let args: Vec<&std::ffi::OsStr> = c.args.iter().map(|a| a.as_os_str()).collect();
        let start = std::time::Instant::now();
        let r = prism_run(&args, Duration::from_secs(30));
        slowest.push((start.elapsed(), c.class, c.name.clone()));
        let o = classify(&r, c.expect);
        *counts.entry(c.class).or_default().entry(o).or_default() += 1;
        if o > Outcome::CleanError {
            failures.push(format!(
                "[{}] {} ({:?}, expected {:?}): {:?}\n  stderr: {}",
                c.class,
                c.name,
                o,
                c.expect,
                c.args,
                r.stderr.trim()
            ));
        }
    }
    let names = [
        (Outcome::Rendered, "rendered"),
        (Outcome::CleanError, "clean error"),
        (Outcome::Wrong, "wrong verdict"),
        (Outcome::UnclearError, "unclear error"),
        (Outcome::Panic, "panic"),
        (Outcome::Abort, "abort"),
        (Outcome::Hang, "hang"),
    ];
    let mut report = String::from("| class | inputs |");
    for (_, n) in names {
        report += &format!(" {n} |");
    }
    report += "\n|---|---:|";
    report += &"---:|".repeat(names.len());
    report += "\n";
    let mut total = BTreeMap::new();
    for (class, by) in &counts {
        report += &format!("| {class} | {} |", by.values().sum::<usize>());
        for (o, _) in names {
            let n = by.get(&o).copied().unwrap_or(0);
            *total.entry(o).or_insert(0) += n;
            report += &format!(" {n} |");
        }
        report += "\n";
    }
    report += &format!("| **all** | **{}** |", cases.len());
    for (o, _) in names {
        report += &format!(" **{}** |", total.get(&o).copied().unwrap_or(0));
    }
    report += "\n";
    slowest.sort_by_key(|s| std::cmp::Reverse(s.0));
    report += "\nSlowest cases:\n\n";
    for (t, class, name) in slowest.iter().take(25) {
        report += &format!("- {:.2} s [{class}] {name}\n", t.as_secs_f64());
    }
    eprintln!("{report}");
    // A report's forged manifest named a file outside its folder: nothing outside may have been removed.
    assert!(dir("reports").join("a-file").is_file(), "a report removed a file outside its folder");
    let out = crate::common::root().join("target/hostile-report.md");
    let _ = std::fs::write(out, &report);
    assert!(
        failures.is_empty(),
        "{} of {} hostile inputs failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
