//! The layering inside `prism-core`, whose order is written once, in the table of `crates/core/src/lib.rs`: a
//! module may use the modules of its own layer and of the layers before it, never one after it, and no two
//! modules may use each other (directly or through others). Cargo holds the layers between crates; this test holds
//! them between the folders of the one crate where cargo cannot. It reads the source: every `crate::module` path
//! in code (comments and string literals aside), use-trees included.

use crate::common::root;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Module name -> layer number, from the `| N | [`module`], ... |` rows of the crate's header.
fn declared_layers(lib: &str) -> BTreeMap<String, u32> {
    let mut layers = BTreeMap::new();
    for line in lib.lines() {
        let Some(row) = line.strip_prefix("//! | ") else { continue };
        let Some((n, mods)) = row.split_once(" | ") else { continue };
        let Ok(n) = n.trim().parse::<u32>() else { continue };
        for part in mods.split("[`").skip(1) {
            let name: String = part.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            if part[name.len()..].starts_with("`]") {
                assert!(layers.insert(name.clone(), n).is_none(), "module `{name}` is listed twice");
            }
        }
    }
    layers
}

/// The source without comments and string literals (so doc links and messages are not imports).
fn code_only(src: &str) -> String {
    let b = src.as_bytes();
    let (mut out, mut i) = (String::with_capacity(src.len()), 0);
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            i += 2;
            while i < b.len() && !b[i..].starts_with(b"*/") {
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' && (i == 0 || b[i - 1] != b'\'') {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else {
            let ch = src[i..].chars().next().unwrap_or(' ');
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// The top-level modules named by `crate::` paths in `code`: `crate::a::...` and each item of `crate::{a, b::c}`.
fn used_modules(code: &str) -> BTreeSet<String> {
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    let mut used = BTreeSet::new();
    for (at, _) in code.match_indices("crate::") {
        let rest = &code[at + "crate::".len()..];
        if let Some(tree) = rest.strip_prefix('{') {
            let (mut depth, mut item_start) = (0, true);
            for (k, ch) in tree.char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => item_start = true,
                    c if item_start && !c.is_whitespace() => {
                        used.insert(ident(&tree[k..]));
                        item_start = false;
                    }
                    _ => {}
                }
            }
        } else {
            used.insert(ident(rest));
        }
    }
    used.retain(|m| !m.is_empty());
    used
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Module -> (used module -> the first file that uses it), for every top-level module of `src`.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeMap<String, String>> {
    let mut files = vec![];
    rust_files(src, &mut files);
    let mut graph: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(src).unwrap().to_string_lossy().replace('\\', "/");
        if rel == "lib.rs" {
            continue;
        }
        let module = rel.split('/').next().unwrap().trim_end_matches(".rs").to_string();
        let code = code_only(&std::fs::read_to_string(&f).unwrap());
        let entry = graph.entry(module.clone()).or_default();
        for used in used_modules(&code) {
            if used != module {
                entry.entry(used).or_insert_with(|| rel.clone());
            }
        }
    }
    graph
}

/// A cycle of the graph, if it has one (depth-first search).
fn find_cycle(graph: &BTreeMap<String, BTreeMap<String, String>>) -> Option<Vec<String>> {
    fn visit(
        m: &str,
        graph: &BTreeMap<String, BTreeMap<String, String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_string(), 1);
        stack.push(m.to_string());
        for next in graph.get(m).into_iter().flat_map(|e| e.keys()) {
            match state.get(next.as_str()) {
                Some(1) => {
                    let from = stack.iter().position(|s| s == next).unwrap_or(0);
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                Some(_) => {}
                None => {
                    if let Some(c) = visit(next, graph, state, stack) {
                        return Some(c);
                    }
                }
            }
        }
        stack.pop();
        state.insert(m.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in graph.keys() {
        if !state.contains_key(m.as_str())
            && let Some(c) = visit(m, graph, &mut state, &mut vec![])
        {
            return Some(c);
        }
    }
    None
}

#[test]
fn core_modules_use_only_their_own_and_earlier_layers_and_form_no_cycle() {
    let src = root().join("crates/core/src");
    let layers = declared_layers(&std::fs::read_to_string(src.join("lib.rs")).unwrap());
    let graph = module_graph(&src);
    for m in graph.keys() {
        assert!(layers.contains_key(m), "module `{m}` of prism-core is missing from the layer table in its lib.rs");
    }
    let mut wrong = vec![];
    for (m, uses) in &graph {
        for (used, file) in uses {
            match (layers.get(m), layers.get(used)) {
                (Some(a), Some(b)) if b > a => {
                    wrong.push(format!("{file}: `{m}` (layer {a}) uses `{used}` (layer {b})"))
                }
                (_, None) => wrong.push(format!("{file}: `crate::{used}` is not a module of the layer table")),
                _ => {}
            }
        }
    }
    assert!(wrong.is_empty(), "imports against the layer order:\n{}", wrong.join("\n"));
    if let Some(cycle) = find_cycle(&graph) {
        let hops: Vec<String> =
            cycle.windows(2).map(|w| format!("{} -> {} ({})", w[0], w[1], graph[&w[0]][&w[1]])).collect();
        panic!("an import cycle between prism-core's modules:\n{}", hops.join("\n"));
    }
}

#[test]
fn the_layer_check_sees_use_trees_and_ignores_comments_and_strings() {
    let code = code_only(
        "use crate::{geometry::Ray, sampling::{Sampler, warp}};\n// crate::scene in a comment\n\
         let s = \"crate::film\"; let x = crate::math::unit_vector(v); /* crate::lights */",
    );
    let used: Vec<String> = used_modules(&code).into_iter().collect();
    assert_eq!(used, ["geometry", "math", "sampling"]);
    let mut g: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    g.entry("a".into()).or_default().insert("b".into(), "a.rs".into());
    g.entry("b".into()).or_default().insert("c".into(), "b.rs".into());
    assert!(find_cycle(&g).is_none());
    g.entry("c".into()).or_default().insert("a".into(), "c.rs".into());
    assert_eq!(find_cycle(&g).unwrap(), ["a", "b", "c", "a"]);
}
