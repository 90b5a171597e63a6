//! The workspace's Rust sources as the source-reading tests see them: the crates' `src`
//! folders, their `.rs` files, and their text without comments (shared by `module_graph.rs`
//! and `architecture.rs`).
#![allow(dead_code)] // each test file uses its own subset

use std::path::{Path, PathBuf};

/// Every `.rs` file below `dir`, into `out`.
pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("module folder is readable") {
        let path = entry.expect("folder entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The sources of every crate of the workspace: `crates/*/src` and `python/src`.
pub fn workspace_crates() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .and_then(Path::parent)
        .expect("the workspace root")
        .to_path_buf();
    let mut out: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .expect("crates/ is readable")
        .map(|e| e.expect("crates/ entry").path().join("src"))
        .filter(|p| p.is_dir())
        .collect();
    let python = root.join("python/src");
    if python.is_dir() {
        out.push(python);
    }
    out.sort();
    out
}

/// `text` with `//` and `/* */` comments blanked out (string literals kept as they are).
pub fn strip_comments(text: &str) -> String {
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

/// A character of a Rust identifier.
pub fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}
