//! The crate's top-level modules (`src/<name>.rs` with `src/<name>/**`) depend on each other
//! without cycles: one module's code may name another's (`crate::other::...`, or a `super::` chain
//! that climbs to the crate root), never the other way round as well, directly or through others.
//!
//! The graph is read from the source text, so a new module is covered as soon as it exists.
//! Comments (doc links included) are ignored; code in `#[cfg(test)]` modules counts.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Top-level module name → the `.rs` files that make it up.
fn modules(src: &Path) -> BTreeMap<String, Vec<PathBuf>> {
    let mut out: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
    for entry in std::fs::read_dir(src).expect("src/ is readable") {
        let path = entry.expect("src/ entry").path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            let files = out.entry(name).or_default();
            rust_files(&path, files);
        } else if path.extension().is_some_and(|e| e == "rs") && name != "lib" && name != "main" {
            out.entry(name).or_default().push(path);
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("module folder is readable") {
        let path = entry.expect("folder entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file below `src/`: `basis.rs` → `[basis]`, `scheme/mod.rs` →
/// `[scheme]`, `scheme/png1.rs` → `[scheme, png1]`.
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).expect("file below src/");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().expect("a file name");
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" {
        parts.push(stem.to_string());
    }
    parts
}

/// `text` with `//` and `/* */` comments blanked out (string literals kept as they are).
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let mut depth = 0usize;
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if depth > 0 {
            if c == '*' && chars.peek() == Some(&'/') {
                chars.next();
                depth -= 1;
            } else if c == '/' && chars.peek() == Some(&'*') {
                chars.next();
                depth += 1;
            } else if c == '\n' {
                out.push('\n');
            }
            continue;
        }
        if in_string {
            out.push(c);
            if c == '\\' {
                if let Some(n) = chars.next() {
                    out.push(n);
                }
            } else if c == '"' {
                in_string = false;
            }
            continue;
        }
        match c {
            '"' => {
                in_string = true;
                out.push(c);
            }
            // A raw string (r"...", r#"..."#), copied whole: no escapes, quotes inside.
            'r' if !out.ends_with(is_ident) && matches!(chars.peek(), Some('"' | '#')) => {
                out.push(c);
                let mut hashes = 0;
                while chars.peek() == Some(&'#') {
                    chars.next();
                    out.push('#');
                    hashes += 1;
                }
                if chars.peek() == Some(&'"') {
                    out.push(chars.next().expect("peeked"));
                    let close = format!("\"{}", "#".repeat(hashes));
                    let mut body = String::new();
                    for n in chars.by_ref() {
                        body.push(n);
                        if body.ends_with(&close) {
                            break;
                        }
                    }
                    out.push_str(&body);
                }
            }
            // A char literal ('"', '\'', 'x'), copied whole so its quote starts no string;
            // a lifetime ('a) is left as it is.
            '\'' => {
                out.push(c);
                let mut ahead = chars.clone();
                let literal = match ahead.next() {
                    Some('\\') => ahead.next().is_some() && ahead.next() == Some('\''),
                    Some(_) => ahead.next() == Some('\''),
                    None => false,
                };
                if literal {
                    while let Some(n) = chars.next() {
                        out.push(n);
                        if n == '\\' {
                            if let Some(e) = chars.next() {
                                out.push(e);
                            }
                        } else if n == '\'' {
                            break;
                        }
                    }
                }
            }
            '/' if chars.peek() == Some(&'/') => {
                for n in chars.by_ref() {
                    if n == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                chars.next();
                depth = 1;
            }
            _ => out.push(c),
        }
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

fn skip_space(s: &str) -> &str {
    s.trim_start()
}

fn take_ident(s: &str) -> (&str, &str) {
    let end = s.find(|c: char| !is_ident(c)).unwrap_or(s.len());
    (&s[..end], &s[end..])
}

/// The first path segments after the crate root in `rest` (what follows `crate::`): one name,
/// or the names at the start of each item of a `{a, b::c, d}` group.
fn first_segments(rest: &str) -> Vec<String> {
    let rest = skip_space(rest);
    if let Some(group) = rest.strip_prefix('{') {
        let mut names = Vec::new();
        let mut depth = 0usize;
        let mut item_start = true;
        let mut s = group;
        while let Some(c) = s.chars().next() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => break,
                '}' => depth -= 1,
                ',' if depth == 0 => item_start = true,
                c if c.is_whitespace() => {}
                c if item_start && depth == 0 && is_ident(c) => {
                    let (name, _) = take_ident(s);
                    names.push(name.to_string());
                    item_start = false;
                    s = &s[name.len()..];
                    continue;
                }
                _ => item_start = false,
            }
            s = &s[c.len_utf8()..];
        }
        names
    } else {
        let (name, _) = take_ident(rest);
        if name.is_empty() {
            Vec::new()
        } else {
            vec![name.to_string()]
        }
    }
}

/// Names of top-level items a file's code reaches from the crate root: `crate::x`,
/// `crate::{x, y}`, and `super::` chains that climb to the root (`path` is the file's module
/// path).
fn root_references(code: &str, path: &[String]) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let bytes = code.as_bytes();
    let mut i = 0;
    while i < code.len() {
        let at_word = i == 0 || !(is_ident(bytes[i - 1] as char) || bytes[i - 1] == b'$');
        let rest = &code[i..];
        if at_word && rest.starts_with("crate::") {
            out.extend(first_segments(&rest["crate::".len()..]));
            i += "crate::".len();
            continue;
        }
        if at_word && rest.starts_with("super::") {
            let mut ups = 0;
            let mut s = rest;
            while let Some(next) = s.strip_prefix("super::") {
                ups += 1;
                s = skip_space(next);
            }
            if ups >= path.len() {
                out.extend(first_segments(s));
            }
            i += rest.len() - s.len();
            continue;
        }
        i += rest.chars().next().map_or(1, char::len_utf8);
    }
    out
}

/// Module → the other modules it names, with a file that names each.
fn graph(src: &Path) -> BTreeMap<String, BTreeMap<String, PathBuf>> {
    let modules = modules(src);
    let mut edges: BTreeMap<String, BTreeMap<String, PathBuf>> = BTreeMap::new();
    for (name, files) in &modules {
        let out = edges.entry(name.clone()).or_default();
        for file in files {
            let text = std::fs::read_to_string(file).expect("source is readable");
            let code = strip_comments(&text);
            for target in root_references(&code, &module_path(src, file)) {
                if target != *name && modules.contains_key(&target) {
                    out.entry(target).or_insert_with(|| file.clone());
                }
            }
        }
    }
    edges
}

/// A cycle of the graph, as the list of modules along it (first = last), if there is one.
fn find_cycle(edges: &BTreeMap<String, BTreeMap<String, PathBuf>>) -> Option<Vec<String>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    fn visit(
        node: &str,
        edges: &BTreeMap<String, BTreeMap<String, PathBuf>>,
        marks: &mut BTreeMap<String, Mark>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        marks.insert(node.to_string(), Mark::Open);
        stack.push(node.to_string());
        for next in edges.get(node).into_iter().flat_map(|m| m.keys()) {
            match marks.get(next.as_str()).copied().unwrap_or(Mark::New) {
                Mark::Open => {
                    let start = stack.iter().position(|n| n == next).expect("on the stack");
                    let mut cycle = stack[start..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                Mark::New => {
                    if let Some(cycle) = visit(next, edges, marks, stack) {
                        return Some(cycle);
                    }
                }
                Mark::Done => {}
            }
        }
        stack.pop();
        marks.insert(node.to_string(), Mark::Done);
        None
    }
    let mut marks = BTreeMap::new();
    for node in edges.keys() {
        if marks.get(node).copied().unwrap_or(Mark::New) == Mark::New {
            if let Some(cycle) = visit(node, edges, &mut marks, &mut Vec::new()) {
                return Some(cycle);
            }
        }
    }
    None
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn top_level_modules_form_no_cycle() {
    let edges = graph(&src());
    if let Some(cycle) = find_cycle(&edges) {
        let steps: Vec<String> = cycle
            .windows(2)
            .map(|w| {
                let file = &edges[&w[0]][&w[1]];
                format!("{} -> {} (in {})", w[0], w[1], file.display())
            })
            .collect();
        panic!(
            "module cycle {}:\n  {}\nmove the shared piece into one of them or a module both use",
            cycle.join(" -> "),
            steps.join("\n  ")
        );
    }
}

#[test]
fn the_graph_sees_known_dependencies() {
    // The reader finds real uses, so an empty graph cannot pass the test above by accident.
    let edges = graph(&src());
    for (from, to) in [
        ("scheme", "basis"),
        ("mesh", "error"),
        ("stencil", "pattern"),
    ] {
        assert!(
            edges.get(from).is_some_and(|m| m.contains_key(to)),
            "{from} -> {to} not found; edges: {edges:?}"
        );
    }
}

#[test]
fn the_reader_handles_groups_super_chains_and_comments() {
    let code = strip_comments(
        "use crate::{alpha::X, beta, gamma::{a, b}};\n\
         // use crate::delta;\n\
         /* crate::epsilon */ let s = \"// not a comment\"; fn f() { super::super::zeta::g(); }\n\
         let q = '\"'; let r = '\\''; fn l<'a>(x: &'a str) {} crate::iota;\n\
         let j = r#\"{\"a\": \"//\"}\"#; crate::kappa;\n\
         use super::eta; my_crate::theta;",
    );
    let found = root_references(&code, &["m".to_string(), "n".to_string()]);
    let expected: BTreeSet<String> = ["alpha", "beta", "gamma", "iota", "kappa", "zeta"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(found, expected);

    let edge = |a: &str, b: &str| (a.to_string(), b.to_string());
    let mut edges: BTreeMap<String, BTreeMap<String, PathBuf>> = BTreeMap::new();
    for (a, b) in [
        edge("a", "b"),
        edge("b", "c"),
        edge("c", "a"),
        edge("c", "d"),
    ] {
        edges.entry(a).or_default().insert(b, PathBuf::new());
    }
    let cycle = find_cycle(&edges).expect("a -> b -> c -> a is a cycle");
    assert_eq!(cycle.first(), cycle.last());
    assert_eq!(cycle.len(), 4);
    edges.get_mut("c").unwrap().remove("a");
    assert_eq!(find_cycle(&edges), None);
}
