//! The files of `crates/render/src/passes/` import each other in one direction only: no file reaches, through
//! `super::NAME` or `crate::render::NAME`, a file that reaches it back. A circle among them
//! (issue #41: ten files once held each other through texture-unit constants kept in lit.rs)
//! means no file can be read or changed without the others; this test reads the sources and
//! names the circle if one comes back.
//!
//! `mod.rs` is the hub (frame context, `Pass`, the module list) and is left out of the graph:
//! every pass names it and it names every pass. A name it re-exports (`use upload::SceneGpu`)
//! counts as the file that defines it. Comments and `#[cfg(test)]` modules are not imports.
use crate::common::repo;
use std::collections::{BTreeMap, BTreeSet};

/// file stem -> (file stem it imports -> names taken through that file).
type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// The source without comments and without `#[cfg(test)] mod ... { }` blocks.
fn production_code(source: &str) -> String {
    let mut out = String::new();
    let mut lines = source.lines().peekable();
    while let Some(line) = lines.next() {
        if line.trim() == "#[cfg(test)]" {
            if let Some(next) = lines.peek() {
                let next = next.trim();
                if next.starts_with("mod ") && next.ends_with('{') {
                    // A test module at the top level closes with a `}` in column 0.
                    for skipped in lines.by_ref() {
                        if skipped == "}" {
                            break;
                        }
                    }
                    continue;
                }
            }
        }
        let code = line.find("//").map_or(line, |at| &line[..at]);
        out.push_str(code);
        out.push('\n');
    }
    out
}

fn ident_at(text: &str) -> &str {
    let end = text
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    &text[..end]
}

/// The paths named after every `prefix` in `code`, as (first segment, rest of the path's
/// segments): `super::lit::View` gives ("lit", "View"); `super::{lit::View, FrameCx}` gives
/// ("lit", "View") and ("FrameCx", "").
fn paths_after<'a>(code: &'a str, prefix: &str) -> Vec<(&'a str, &'a str)> {
    let mut found = Vec::new();
    for (at, _) in code.match_indices(prefix) {
        if code[..at].ends_with("::") {
            continue; // the second `super::` of `super::super::`
        }
        let rest = &code[at + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let close = group.find('}').unwrap_or(group.len());
            for item in group[..close].split(',') {
                let item = item.trim();
                let first = ident_at(item);
                let after = item[first.len()..].trim_start_matches("::");
                found.push((first, ident_at(after)));
            }
        } else {
            let first = ident_at(rest);
            let after = rest[first.len()..].strip_prefix("::").unwrap_or("");
            found.push((first, ident_at(after)));
        }
    }
    found.retain(|(first, _)| !first.is_empty());
    found
}

/// The graph of `files` (stem -> source); `hub` is mod.rs's source, whose `use FILE::Name`
/// re-exports send `super::Name` to FILE.
fn graph(files: &BTreeMap<String, String>, hub: &str) -> Graph {
    let mut reexports: BTreeMap<String, String> = BTreeMap::new();
    for line in production_code(hub).lines() {
        let line = line.trim();
        let Some(path) = line
            .strip_prefix("pub(crate) use ")
            .or_else(|| line.strip_prefix("pub use "))
            .or_else(|| line.strip_prefix("use "))
        else {
            continue;
        };
        let first = ident_at(path);
        if files.contains_key(first) {
            let last = path.trim_end_matches(';').rsplit("::").next().unwrap_or("");
            for name in last.trim_matches(|c| c == '{' || c == '}').split(',') {
                reexports.insert(ident_at(name.trim()).to_string(), first.to_string());
            }
        }
    }
    let mut graph = Graph::new();
    for (stem, source) in files {
        let code = production_code(source);
        let arrows = graph.entry(stem.clone()).or_default();
        for prefix in ["super::", "crate::passes::"] {
            for (first, name) in paths_after(&code, prefix) {
                let (target, name) = if files.contains_key(first) {
                    (first.to_string(), name.to_string())
                } else if let Some(file) = reexports.get(first) {
                    (file.clone(), first.to_string())
                } else {
                    continue; // an item of mod.rs itself
                };
                if target != *stem {
                    // `use super::lit;` takes the module itself.
                    let name = if name.is_empty() { "self".into() } else { name };
                    arrows.entry(target).or_default().insert(name);
                }
            }
        }
    }
    graph
}

/// One circle of the graph as its files in order (the first repeated at the end), if any.
fn find_cycle(graph: &Graph) -> Option<Vec<String>> {
    // Depth-first search; a file met again while still on the path closes a circle.
    fn visit(
        graph: &Graph,
        file: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|f| f == file) {
            let mut cycle = path[at..].to_vec();
            cycle.push(file.to_string());
            return Some(cycle);
        }
        if done.contains(file) {
            return None;
        }
        path.push(file.to_string());
        for next in graph.get(file).into_iter().flat_map(|a| a.keys()) {
            if let Some(cycle) = visit(graph, next, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        done.insert(file.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|file| visit(graph, file, &mut Vec::new(), &mut done))
}

/// Every file that reaches itself through the arrows: the files held in some circle.
fn in_circles(graph: &Graph) -> Vec<&str> {
    let reaches = |from: &str| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from];
        while let Some(file) = todo.pop() {
            for next in graph.get(file).into_iter().flat_map(|a| a.keys()) {
                if seen.insert(next.as_str()) {
                    todo.push(next);
                }
            }
        }
        seen.contains(from)
    };
    graph
        .keys()
        .map(String::as_str)
        .filter(|f| reaches(f))
        .collect()
}

/// The circle with the names each arrow takes, one arrow a line.
fn describe(graph: &Graph, cycle: &[String]) -> String {
    cycle
        .windows(2)
        .map(|w| {
            let names: Vec<&str> = graph[&w[0]][&w[1]].iter().map(String::as_str).collect();
            format!("  {}.rs -> {}.rs: {}\n", w[0], w[1], names.join(", "))
        })
        .collect()
}

fn sources(pairs: &[(&str, &str)]) -> BTreeMap<String, String> {
    pairs
        .iter()
        .map(|(stem, text)| (stem.to_string(), text.to_string()))
        .collect()
}

#[test]
fn imports_are_read_from_paths_groups_and_reexports_but_not_comments_or_tests() {
    let files = sources(&[
        (
            "a",
            "use super::{b::X, FrameCx};\n// super::c::Y\nfn f() { super::c::z(); }\n",
        ),
        ("b", "use crate::passes::c;\nuse super::Hidden;\n"),
        (
            "c",
            "const K: u32 = 1;\n#[cfg(test)]\nmod tests {\n    use super::super::a;\n}\n",
        ),
    ]);
    let g = graph(&files, "mod a;\npub(crate) use c::Hidden;\n");
    let arrows = |from: &str| -> Vec<(String, Vec<String>)> {
        g[from]
            .iter()
            .map(|(to, names)| (to.clone(), names.iter().cloned().collect()))
            .collect()
    };
    assert_eq!(
        arrows("a"),
        [
            ("b".into(), vec!["X".into()]),
            ("c".into(), vec!["z".into()])
        ]
    );
    assert_eq!(
        arrows("b"),
        [("c".into(), vec!["Hidden".into(), "self".into()])]
    );
    assert!(arrows("c").is_empty());
    assert_eq!(find_cycle(&g), None);
    assert!(in_circles(&g).is_empty());

    let circle = sources(&[
        ("a", "use super::b::X;\n"),
        ("b", "fn f() { super::c::y() }\n"),
        ("c", "const Z: u32 = super::a::W;\n"),
    ]);
    let g = graph(&circle, "");
    assert_eq!(find_cycle(&g).unwrap(), ["a", "b", "c", "a"]);
    assert_eq!(in_circles(&g), ["a", "b", "c"]);
}

#[test]
fn render_files_import_each_other_in_one_direction() {
    let dir = repo().join("crates/render/src/passes");
    let mut files = BTreeMap::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) == Some("rs") {
            let stem = path.file_stem().unwrap().to_str().unwrap().to_string();
            files.insert(stem, std::fs::read_to_string(&path).unwrap());
        }
    }
    let hub = files
        .remove("mod")
        .expect("crates/render/src/passes/mod.rs");
    assert!(
        files.len() > 20,
        "crates/render/src/passes holds {} files",
        files.len()
    );
    let g = graph(&files, &hub);
    let arrows: usize = g.values().map(BTreeMap::len).sum();
    assert!(
        arrows > 20,
        "only {arrows} arrows among crates/render/src/passes files: is the parser blind?"
    );
    if let Some(cycle) = find_cycle(&g) {
        panic!(
            "crates/render/src/passes files import each other in a circle:\n{}files held in circles: {}",
            describe(&g, &cycle),
            in_circles(&g).join(", ")
        );
    }
}
