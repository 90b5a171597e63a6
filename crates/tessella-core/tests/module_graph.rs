//! Two checks on how the code depends on itself, both read from the source text (so a new module
//! or file is covered as soon as it exists; comments, doc links included, are ignored; code in
//! `#[cfg(test)]` modules counts):
//!
//! 1. tessella-core's top-level modules (`src/<name>.rs` with `src/<name>/**`) depend on each
//!    other without cycles: one module's code may name another's (`crate::other::...`, or a
//!    `super::` chain that climbs to the crate root), never the other way round as well,
//!    directly or through others.
//! 2. In every crate of the workspace (`crates/*/src`, and `python/src`), the FILES depend on each
//!    other without cycles. Each `.rs` file is a node named by its module path
//!    (`refine/plan/table.rs` → `refine::plan::table`, `refine/mod.rs` → `refine`,
//!    `lib.rs`/`main.rs` → the crate root). The edges:
//!    - a path written from `crate::`, `super::` or `self::`, in a `use` or in code, is an edge
//!      from the file it is written in to the file that defines what it names: the path is
//!      followed through modules as far as they go, and through `pub use` re-exports to where
//!      the item is defined. So a child using `super::Item` is an edge to the parent's file
//!      when `Item` is defined there, and to the sibling's when the parent only re-exports it;
//!    - a private `use` of any form (`use child::X;` included) is an edge, as it is a use;
//!    - NOT edges: a parent's `mod child;` and its `pub use child::X` (or `self::child::X`)
//!      re-exports of its own descendants: they are the module tree and its public face, not a
//!      use; and `pub(in crate::...)` visibilities. Paths inside a file's inline modules
//!      (`mod tests { use super::*; }`) count from that inline module, and a file's edges to
//!      itself are dropped;
//!    - not seen: a parent's code naming a child's item through its own re-export by the bare
//!      name (`Plan` after `pub use plan::Plan;`). A `mod.rs` that is only declarations and
//!      re-exports has no such code; put code that uses the children in a file of its own.
//!
//!    The test prints the cycle it finds, with the file that makes each step.

mod source_tree;

use source_tree::{is_ident, rust_files, strip_comments, workspace_crates};
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

// ---------------------------------------------------------------------------------------------
// File-level graph, for every crate of the workspace.

/// `code` (comments already stripped) with the insides of string and char literals blanked, so
/// braces and paths in them are not read as code.
fn blank_literals(code: &str) -> String {
    let chars: Vec<char> = code.chars().collect();
    let mut out = String::with_capacity(code.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let prev_ident = i > 0 && is_ident(chars[i - 1]);
        if c == '"' || (c == 'r' && !prev_ident && matches!(chars.get(i + 1), Some('"' | '#'))) {
            // Plain (possibly b"...") or raw string.
            let mut j = i;
            let mut hashes = 0;
            let raw = c == 'r';
            if raw {
                j += 1;
                while chars.get(j) == Some(&'#') {
                    hashes += 1;
                    j += 1;
                }
                if chars.get(j) != Some(&'"') {
                    out.push(c);
                    i += 1;
                    continue;
                }
            }
            out.push('"');
            j += 1;
            while j < chars.len() {
                let n = chars[j];
                if !raw && n == '\\' {
                    out.push(' ');
                    out.push(' ');
                    j += 2;
                    continue;
                }
                if n == '"' && (0..hashes).all(|h| chars.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                out.push(if n == '\n' { '\n' } else { ' ' });
                j += 1;
            }
            out.push('"');
            i = j;
            continue;
        }
        if c == '\'' {
            let literal_end = match chars.get(i + 1) {
                Some('\\') => (i + 3..(i + 12).min(chars.len())).find(|&k| chars[k] == '\''),
                Some(_) if chars.get(i + 2) == Some(&'\'') => Some(i + 2),
                _ => None,
            };
            if let Some(end) = literal_end {
                out.push_str("' '");
                i = end + 1;
                continue;
            }
        }
        out.push(c);
        i += 1;
    }
    out
}

/// Parses a use tree or a plain path at the start of `s`: the full paths it names (segments;
/// `self` inside a group is the group's prefix, `*` is kept as a segment), with the alias or
/// last name each is known by, and the rest of `s`.
fn parse_tree<'a>(s: &'a str, prefix: &[String], out: &mut Vec<(Vec<String>, String)>) -> &'a str {
    let mut path = prefix.to_vec();
    let mut s = skip_space(s);
    loop {
        if let Some(group) = s.strip_prefix('{') {
            s = group;
            loop {
                s = skip_space(s);
                if let Some(rest) = s.strip_prefix('}') {
                    return rest;
                }
                if let Some(rest) = s.strip_prefix(',') {
                    s = rest;
                    continue;
                }
                let before = s.len();
                s = parse_tree(s, &path, out);
                if s.len() == before {
                    // Something not understood: skip one char rather than loop.
                    s = &s[s.chars().next().map_or(0, char::len_utf8)..];
                }
            }
        }
        if let Some(rest) = s.strip_prefix('*') {
            path.push("*".to_string());
            out.push((path, "*".to_string()));
            return rest;
        }
        let (name, rest) = take_ident(s);
        if name.is_empty() {
            if path.len() > prefix.len() {
                let last = path.last().cloned().unwrap_or_default();
                out.push((path, last));
            }
            return s;
        }
        if name == "self" && !path.is_empty() && path.len() == prefix.len() {
            // `{self, ...}`: the prefix itself.
        } else {
            path.push(name.to_string());
        }
        s = skip_space(rest);
        if let Some(next) = s.strip_prefix("::") {
            s = skip_space(next);
            continue;
        }
        let mut known_as = path.last().cloned().unwrap_or_default();
        if let Some(alias) = s.strip_prefix("as") {
            if alias.starts_with(|c: char| c.is_whitespace()) {
                let (a, rest) = take_ident(skip_space(alias));
                known_as = a.to_string();
                s = rest;
            }
        }
        out.push((path, known_as));
        return s;
    }
}

/// Turns a written path into one from the crate root, seen from module `base`: `crate::` from the
/// root, `self::` from `base`, each `super::` one level up; a path starting with a child module
/// of `base` from there. `None` for anything else (an external crate, a local name).
fn absolute(
    written: &[String],
    base: &[String],
    modules: &BTreeSet<Vec<String>>,
) -> Option<Vec<String>> {
    let first = written.first()?;
    let mut at: Vec<String>;
    let mut rest = &written[1..];
    match first.as_str() {
        "crate" => at = Vec::new(),
        "self" => at = base.to_vec(),
        "super" => {
            at = base.to_vec();
            at.pop()?;
            while rest.first().is_some_and(|s| s == "super") {
                at.pop()?;
                rest = &rest[1..];
            }
        }
        _ => {
            at = base.to_vec();
            at.push(first.clone());
            if !modules.contains(&at) {
                return None;
            }
        }
    }
    at.extend(rest.iter().cloned());
    Some(at)
}

/// What one file says: its uses (absolute paths) and its `pub use` re-exports (name → path).
#[derive(Default)]
struct FileRefs {
    uses: Vec<Vec<String>>,
    reexports: BTreeMap<String, Vec<String>>,
}

fn file_refs(module: &[String], text: &str, modules: &BTreeSet<Vec<String>>) -> FileRefs {
    let code = blank_literals(&strip_comments(text));
    let bytes = code.as_bytes();
    let mut refs = FileRefs::default();
    let mut depth = 0usize;
    // Inline modules open in this file: (name, brace depth inside them).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut pending_mod: Option<String> = None;
    let mut i = 0;
    while i < code.len() {
        let rest = &code[i..];
        let c = rest.chars().next().expect("in range");
        let at_word = i == 0 || !(is_ident(bytes[i - 1] as char) || bytes[i - 1] == b'$');
        let base: Vec<String> = module
            .iter()
            .cloned()
            .chain(inline.iter().map(|(n, _)| n.clone()))
            .collect();
        match c {
            '{' => {
                depth += 1;
                if let Some(name) = pending_mod.take() {
                    inline.push((name, depth));
                }
                i += 1;
                continue;
            }
            '}' => {
                if inline.last().is_some_and(|&(_, d)| d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
                continue;
            }
            ';' => {
                pending_mod = None;
                i += 1;
                continue;
            }
            _ => {}
        }
        if at_word && is_ident(c) {
            let (word, after) = take_ident(rest);
            if word == "mod" {
                let (name, after_name) = take_ident(skip_space(after));
                if !name.is_empty() && skip_space(after_name).starts_with('{') {
                    pending_mod = Some(name.to_string());
                }
                i += word.len();
                continue;
            }
            if word == "use" && after.starts_with(|c: char| c.is_whitespace()) {
                let before = code[..i].trim_end();
                let public = before.ends_with("pub")
                    || before.ends_with(')') && {
                        let open = before.rfind('(').unwrap_or(0);
                        before[..open].trim_end().ends_with("pub")
                    };
                let mut paths = Vec::new();
                let end = parse_tree(after, &[], &mut paths);
                for (written, known_as) in paths {
                    let Some(abs) = absolute(&written, &base, modules) else {
                        continue;
                    };
                    let own_child = abs.len() > module.len() && abs.starts_with(module);
                    if public && inline.is_empty() && known_as != "*" {
                        refs.reexports.insert(known_as, abs.clone());
                    }
                    if !(public && own_child) {
                        refs.uses.push(abs);
                    }
                }
                i = code.len() - end.len();
                continue;
            }
            if matches!(word, "crate" | "super" | "self") && after.starts_with("::") {
                let in_visibility = code[..i].trim_end().ends_with("pub(in");
                let mut paths = Vec::new();
                let end = parse_tree(rest, &[], &mut paths);
                if !in_visibility {
                    for (written, _) in paths {
                        if let Some(abs) = absolute(&written, &base, modules) {
                            refs.uses.push(abs);
                        }
                    }
                }
                i = code.len() - end.len();
                continue;
            }
            i += word.len();
            continue;
        }
        i += c.len_utf8();
    }
    refs
}

/// The module (file) that defines what `path` names: modules followed as far as they go, then
/// a re-export of the module reached followed to its source.
fn resolve(
    path: &[String],
    modules: &BTreeSet<Vec<String>>,
    reexports: &BTreeMap<Vec<String>, BTreeMap<String, Vec<String>>>,
    hops: usize,
) -> Vec<String> {
    let mut at: Vec<String> = Vec::new();
    for (k, seg) in path.iter().enumerate() {
        let mut next = at.clone();
        next.push(seg.clone());
        if modules.contains(&next) {
            at = next;
            continue;
        }
        if hops < 16 {
            if let Some(target) = reexports.get(&at).and_then(|m| m.get(seg)) {
                let mut full = target.clone();
                full.extend(path[k + 1..].iter().cloned());
                return resolve(&full, modules, reexports, hops + 1);
            }
        }
        break;
    }
    at
}

fn node_name(module: &[String]) -> String {
    if module.is_empty() {
        "crate".to_string()
    } else {
        module.join("::")
    }
}

/// File → the files it uses, with a path that makes each edge, for the crate whose sources are
/// in `src`.
fn file_graph(src: &Path) -> BTreeMap<String, BTreeMap<String, PathBuf>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.retain(|f| !f.starts_with(src.join("bin")));
    let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_path(src, f)).collect();
    let mut per_file = Vec::new();
    let mut reexports: BTreeMap<Vec<String>, BTreeMap<String, Vec<String>>> = BTreeMap::new();
    for file in &files {
        let module = module_path(src, file);
        let text = std::fs::read_to_string(file).expect("source is readable");
        let refs = file_refs(&module, &text, &modules);
        reexports
            .entry(module.clone())
            .or_default()
            .extend(refs.reexports);
        per_file.push((module, file.clone(), refs.uses));
    }
    let mut edges: BTreeMap<String, BTreeMap<String, PathBuf>> = BTreeMap::new();
    for (module, file, uses) in per_file {
        let out = edges.entry(node_name(&module)).or_default();
        for used in uses {
            let target = resolve(&used, &modules, &reexports, 0);
            if target != module {
                out.entry(node_name(&target))
                    .or_insert_with(|| file.clone());
            }
        }
    }
    edges
}

fn describe_cycle(cycle: &[String], edges: &BTreeMap<String, BTreeMap<String, PathBuf>>) -> String {
    let steps: Vec<String> = cycle
        .windows(2)
        .map(|w| {
            format!(
                "{} -> {} (in {})",
                w[0],
                w[1],
                edges[&w[0]][&w[1]].display()
            )
        })
        .collect();
    format!("{}:\n  {}", cycle.join(" -> "), steps.join("\n  "))
}

#[test]
fn no_file_level_import_cycle_in_any_crate() {
    let mut found = Vec::new();
    let crates = workspace_crates();
    assert!(
        crates.len() >= 8,
        "the workspace's crates are found: {crates:?}"
    );
    for src in crates {
        let edges = file_graph(&src);
        // Every cycle is reported, not only the first: each found is cut at its last step and
        // the search run again.
        let mut cut = edges.clone();
        while let Some(cycle) = find_cycle(&cut) {
            found.push(format!(
                "in {}: file cycle {}",
                src.display(),
                describe_cycle(&cycle, &edges)
            ));
            let n = cycle.len();
            cut.get_mut(&cycle[n - 2])
                .expect("a node of the cycle")
                .remove(&cycle[n - 1]);
        }
    }
    assert!(
        found.is_empty(),
        "{}\nmove the shared piece into one of the files or a file both use",
        found.join("\n")
    );
}

/// tessella-core's refinement is two layers: `refine::plan` (built once per topology and
/// levels) and `refine::cpu` (the evaluator on top of it). The plan layer never imports the
/// evaluator.
#[test]
fn the_plan_layer_never_imports_the_evaluator() {
    let edges = file_graph(&src());
    let plan_files: Vec<&String> = edges
        .keys()
        .filter(|k| k.starts_with("refine::plan"))
        .collect();
    assert!(
        plan_files.len() > 5,
        "the plan layer's files: {plan_files:?}"
    );
    let wrong: Vec<String> = plan_files
        .iter()
        .flat_map(|from| {
            edges[*from]
                .iter()
                .filter(|(to, _)| to.starts_with("refine::cpu") || to.as_str() == "refine")
                .map(move |(to, file)| format!("{from} -> {to} (in {})", file.display()))
        })
        .collect();
    assert!(
        wrong.is_empty(),
        "the plan layer imports the evaluator:\n  {}",
        wrong.join("\n  ")
    );
}

#[test]
fn the_file_graph_sees_known_dependencies() {
    let edges = file_graph(&src());
    for (from, to) in [
        ("scheme", "basis"),
        ("refine::plan::canonical", "basis::png1"),
        ("refine::plan::table", "refine::plan::layout"),
        ("refine::cpu::uniform", "refine::cpu::kernels"),
        ("refine::cpu::evaluate", "refine::plan::table"),
    ] {
        assert!(
            edges.get(from).is_some_and(|m| m.contains_key(to)),
            "{from} -> {to} not found; edges of {from}: {:?}",
            edges.get(from)
        );
    }
}

#[test]
fn the_file_reader_follows_super_self_reexports_and_inline_modules() {
    let v = |s: &str| -> Vec<String> {
        if s.is_empty() {
            Vec::new()
        } else {
            s.split("::").map(str::to_string).collect()
        }
    };
    let modules: BTreeSet<Vec<String>> = ["", "a", "a::b", "a::c", "a::d", "e"]
        .iter()
        .map(|m| v(m))
        .collect();
    // a/mod.rs: declarations and re-exports of its children are no edges; its own items are.
    let parent = file_refs(
        &v("a"),
        "mod b; mod c;\npub use b::{Bee, Bee2 as B2};\npub use self::c::See;\npub(crate) use crate::e::Ee;\n\
         use d::Private;\npub struct Own;\nfn f() { let s = \"crate::e::X {\"; let c = '{'; }",
        &modules,
    );
    assert_eq!(parent.uses, vec![v("e::Ee"), v("a::d::Private")]);
    assert_eq!(parent.reexports.get("B2"), Some(&v("a::b::Bee2")));
    assert_eq!(parent.reexports.get("See"), Some(&v("a::c::See")));
    // a/b.rs: `super::Own` is the parent; `super::See` is the sibling c, through the re-export.
    let child = file_refs(
        &v("a::b"),
        "use super::{Own, See, d::{self, Dee}};\n// use crate::e;\n\
         pub(in crate::a) fn g() { super::super::e::h::<u8>(); self::x(); }\n\
         #[cfg(test)] mod tests { use super::*; use crate::a::c::tests::helper; }",
        &modules,
    );
    assert_eq!(
        child.uses,
        vec![
            v("a::Own"),
            v("a::See"),
            v("a::d"),
            v("a::d::Dee"),
            v("e::h"),
            v("a::b::x"),
            v("a::b::*"),
            v("a::c::tests::helper"),
        ]
    );
    let mut reexports = BTreeMap::new();
    reexports.insert(v("a"), parent.reexports);
    let at = |p: &str| node_name(&resolve(&v(p), &modules, &reexports, 0));
    assert_eq!(at("a::Own"), "a");
    assert_eq!(at("a::See"), "a::c");
    assert_eq!(at("a::B2"), "a::b");
    assert_eq!(at("a::d::Dee"), "a::d");
    assert_eq!(at("a::c::tests::helper"), "a::c");
    assert_eq!(at("e::h"), "e");
}
