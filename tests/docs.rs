//! The book under `docs/` and the README hold together: every plugin's reference page is its `//!` header (the one
//! text, as Mitsuba generates its plugin docs), every page is in `SUMMARY.md`, every relative link and `#anchor`
//! resolves, and the README stays a page for users (at most 250 lines, no work diary).
//!
//! `PRISM_BLESS=1 cargo test --release docs::` rewrites the plugin pages from the headers.

use crate::common::root;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The integrator plugins with a reference page: every folder under `plugins/`.
fn plugins() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("plugins"))
        .unwrap()
        .flatten()
        .filter(|e| e.path().join("src/lib.rs").is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The reference page of plugin `name`: a note saying where it comes from, then its crate's `//!` header.
fn page_from_header(name: &str) -> String {
    let src = std::fs::read_to_string(root().join("plugins").join(name).join("src/lib.rs")).unwrap();
    let mut page = format!("<!-- generated from plugins/{name}/src/lib.rs's //! header: edit it there -->\n");
    for line in src.lines().take_while(|l| l.starts_with("//!")) {
        let text = line.strip_prefix("//!").unwrap_or("");
        page.push_str(text.strip_prefix(' ').unwrap_or(text));
        page.push('\n');
    }
    page
}

#[test]
fn each_plugin_reference_page_is_generated_from_the_plugins_header() {
    let bless = std::env::var_os("PRISM_BLESS").is_some();
    let names = plugins();
    assert!(names.len() >= 4, "plugins found: {names:?}");
    for name in &names {
        let path = root().join("docs/plugins").join(format!("{name}.md"));
        let want = page_from_header(name);
        assert!(want.lines().nth(1).is_some_and(|l| l.starts_with("# ")), "plugins/{name}: the header needs a # title");
        if bless {
            std::fs::write(&path, &want).unwrap();
            continue;
        }
        let have = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            have == want,
            "docs/plugins/{name}.md differs from the //! header of plugins/{name}/src/lib.rs: edit the header and run \
             PRISM_BLESS=1 cargo test --release docs::"
        );
    }
}

/// Every Markdown file of the book, relative to `docs/`.
fn book_pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, base: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, base, out);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p.strip_prefix(base).unwrap().to_path_buf());
            }
        }
    }
    let docs = root().join("docs");
    let mut out = vec![];
    walk(&docs, &docs, &mut out);
    out.sort();
    out
}

/// The `(text, target)` of every inline Markdown link and image outside code (fenced blocks and code spans).
fn links(md: &str) -> Vec<String> {
    let mut out = vec![];
    let mut fenced = false;
    for line in md.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Drop code spans.
        let mut plain = String::new();
        for (i, part) in line.split('`').enumerate() {
            if i % 2 == 0 {
                plain.push_str(part);
            }
        }
        let mut rest = plain.as_str();
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].split_whitespace().next().unwrap_or("").to_string());
            rest = &after[end..];
        }
    }
    out
}

/// GitHub's and mdBook's anchor of a heading: lower case, spaces to `-`, punctuation other than `-` and `_` dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(md: &str) -> BTreeSet<String> {
    let mut fenced = false;
    let mut out = BTreeSet::new();
    for line in md.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced && line.starts_with('#') {
            out.insert(anchor(line.trim_start_matches('#')));
        }
    }
    out
}

/// Broken relative links of the Markdown file `file` (absolute): missing files and missing `#anchors`.
fn broken_links(file: &Path) -> Vec<String> {
    let md = std::fs::read_to_string(file).unwrap();
    let dir = file.parent().unwrap();
    let mut broken = vec![];
    for target in links(&md) {
        if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, frag) = target.split_once('#').unwrap_or((&target, ""));
        let dest = if path.is_empty() { file.to_path_buf() } else { dir.join(path) };
        if !dest.exists() {
            broken.push(format!("{}: {target} (no such file)", file.display()));
        } else if !frag.is_empty() && dest.extension().is_some_and(|x| x == "md") {
            let text = std::fs::read_to_string(&dest).unwrap();
            if !anchors(&text).contains(frag) {
                broken.push(format!("{}: {target} (no heading with that anchor)", file.display()));
            }
        }
    }
    broken
}

#[test]
fn every_relative_link_of_the_book_and_the_readme_resolves() {
    let docs = root().join("docs");
    let mut broken = broken_links(&root().join("README.md"));
    for page in book_pages() {
        broken.extend(broken_links(&docs.join(page)));
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn every_page_of_the_book_is_in_its_summary() {
    let summary = std::fs::read_to_string(root().join("docs/SUMMARY.md")).unwrap();
    let listed: BTreeSet<String> = links(&summary).into_iter().collect();
    let missing: Vec<String> = book_pages()
        .into_iter()
        .map(|p| p.to_string_lossy().replace('\\', "/"))
        .filter(|p| p != "SUMMARY.md" && !listed.contains(p))
        .collect();
    assert!(missing.is_empty(), "pages not in docs/SUMMARY.md: {missing:?}");
}

#[test]
fn the_readme_is_a_page_for_users() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 250, "README.md has {lines} lines: the rest belongs in the book");
    for word in ["session", "sessions"] {
        let hit = readme.lines().find(|l| l.to_lowercase().split(|c: char| !c.is_alphanumeric()).any(|w| w == word));
        assert!(hit.is_none(), "README.md reads as a work diary: {hit:?}");
    }
    for command in ["cargo run --release -- render scenes/cornell_box.ron", "cargo test --release"] {
        assert!(readme.contains(command), "README.md must show `{command}`");
    }
}

#[test]
fn the_link_checker_finds_missing_files_and_anchors() {
    let md = "See [a](a.md#two), [b](b.md), `[c](c.md)`, ![img](x.png).\n```\n[d](d.md)\n```\n# Two words, here\n";
    assert_eq!(links(md), ["a.md#two", "b.md", "x.png"]);
    assert_eq!(anchor(" Two words, here"), "two-words-here");
    assert!(anchors(md).contains("two-words-here"));
}
