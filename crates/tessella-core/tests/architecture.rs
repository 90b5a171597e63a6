//! Claims ARCHITECTURE.md makes about the code, checked on the source text of every crate
//! (`crates/*/src`, Bevy's included, and `python/src`): each test reads what the page says
//! where it can, so the page and the code cannot part silently.

mod source_tree;

use source_tree::{rust_files, strip_comments, workspace_crates};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Every crate's files with their text, comments removed: `(path, code)`.
fn sources() -> Vec<(PathBuf, String)> {
    let mut files = Vec::new();
    for src in workspace_crates() {
        rust_files(&src, &mut files);
    }
    files.sort();
    files
        .into_iter()
        .map(|f| {
            let text = std::fs::read_to_string(&f).expect("a readable source file");
            (f, strip_comments(&text))
        })
        .collect()
}

fn architecture_md() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md")
}

/// The names in backticks on the line of ARCHITECTURE.md that starts with `lead`.
fn listed(lead: &str) -> BTreeSet<String> {
    let page = architecture_md();
    let line = page
        .lines()
        .find(|l| l.starts_with(lead))
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has no line starting {lead:?}"));
    line.split('`')
        .skip(1)
        .step_by(2)
        .map(String::from)
        .collect()
}

/// The match arms on a `NormalMode` variant in `code`: `NormalMode::X =>` or
/// `NormalMode::X | NormalMode::Y =>` (a value built, `=> NormalMode::X`, is not one).
fn normal_mode_arms(code: &str) -> usize {
    let mut arms = 0;
    let mut rest = code;
    while let Some(at) = rest.find("NormalMode::") {
        let mut after = &rest[at + "NormalMode::".len()..];
        after = after.trim_start_matches(|c: char| c.is_alphanumeric() || c == '_');
        let mut tail = after.trim_start();
        while let Some(more) = tail.strip_prefix('|') {
            let more = more.trim_start();
            let more = more.strip_prefix("NormalMode::").unwrap_or(more);
            tail = more
                .trim_start_matches(|c: char| c.is_alphanumeric() || c == '_')
                .trim_start();
        }
        if tail.starts_with("=>") {
            arms += 1;
        }
        rest = tail;
    }
    arms
}

/// "A normal mode reaches the shaders through one core function, `shader::normal_mode_code`,
/// so no backend matches on it": no crate but the core has a match arm on a `NormalMode`.
#[test]
fn no_backend_matches_on_normal_mode() {
    let core = Path::new("tessella-core").join("src");
    let mut found = Vec::new();
    for (file, code) in sources() {
        if file.ancestors().any(|dir| dir.ends_with(&core)) {
            continue; // the core: where the modes are mapped
        }
        let arms = normal_mode_arms(&code);
        if arms > 0 {
            found.push(format!("{} ({arms} arms)", file.display()));
        }
    }
    assert!(
        found.is_empty(),
        "NormalMode matched outside the core: {found:?}"
    );
    // The reader sees arms, alone and in alternatives, and not values.
    assert_eq!(
        normal_mode_arms("match m { NormalMode::Linear => 0, _ => 1 }"),
        1
    );
    assert_eq!(
        normal_mode_arms("NormalMode::Linear | NormalMode::Real => m,"),
        1
    );
    assert_eq!(normal_mode_arms("Key::Linear => NormalMode::Linear,"), 0);
}

/// The public enums of `code`: `(name, marked #[non_exhaustive])`, the marking looked for in
/// the attributes just above.
fn public_enums(code: &str) -> Vec<(String, bool)> {
    let lines: Vec<&str> = code.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(rest) = line.trim_start().strip_prefix("pub enum ") else {
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let mut marked = false;
        for above in lines[..i].iter().rev() {
            let above = above.trim();
            if above.is_empty() {
                continue; // a doc comment, blanked
            }
            if !above.starts_with("#[") && !above.starts_with(')') && !above.ends_with(',') {
                break;
            }
            marked |= above.contains("non_exhaustive");
        }
        out.push((name, marked));
    }
    out
}

/// "The enums expected to grow are `#[non_exhaustive]`; these stay exhaustive on purpose":
/// every public enum of the library crates is one or the other, and each one the page lists
/// as exhaustive exists and is.
#[test]
fn public_enums_are_non_exhaustive_unless_listed() {
    let closed = listed("Exhaustive on purpose:");
    assert!(closed.len() >= 3, "{closed:?}");
    let mut open_unlisted = Vec::new();
    let mut seen_closed = BTreeSet::new();
    for (file, code) in sources() {
        let path = file.to_string_lossy();
        // The binary's argument enums, the benchmarks and the Python extension's own types
        // are not Rust library API.
        if ["tessella-cli/", "tessella-bench/", "python/src"]
            .iter()
            .any(|p| path.contains(p))
        {
            continue;
        }
        for (name, marked) in public_enums(&code) {
            if marked {
                assert!(
                    !closed.contains(&name),
                    "{name} is listed as exhaustive but is not"
                );
            } else if closed.contains(&name) {
                seen_closed.insert(name);
            } else {
                open_unlisted.push(format!("{name} ({path})"));
            }
        }
    }
    assert!(
        open_unlisted.is_empty(),
        "public enums neither #[non_exhaustive] nor listed in ARCHITECTURE.md: {open_unlisted:?}"
    );
    let missing: Vec<_> = closed.difference(&seen_closed).collect();
    assert!(
        missing.is_empty(),
        "listed as exhaustive but not found: {missing:?}"
    );
}

/// "Without the `bandwidth` feature no public function of the core fills or copies a slice with
/// streaming stores": each top-level `pub fn` of the streaming-store file is behind it.
#[test]
fn streaming_stores_are_public_only_for_the_bandwidth_benchmark() {
    let (_, code) = sources()
        .into_iter()
        .find(|(f, _)| f.ends_with("tessella-core/src/refine/cpu/nontemporal.rs"))
        .expect("the core's streaming stores");
    let lines: Vec<&str> = code.lines().collect();
    let mut public = 0;
    for (i, line) in lines.iter().enumerate() {
        if line.starts_with("pub fn ") {
            public += 1;
            let gated = lines[..i]
                .iter()
                .rev()
                .map(|l| l.trim())
                .take_while(|l| l.is_empty() || l.starts_with("#["))
                .any(|l| l == "#[cfg(feature = \"bandwidth\")]");
            assert!(gated, "not behind the bandwidth feature: {line}");
        }
    }
    assert_eq!(public, 2, "stream_copy and stream_fill");
}

/// The crates a crate's manifest depends on (its `[dependencies]` and target-specific
/// dependencies, optional ones included; not its dev-dependencies): the `tessella-*` names.
fn tessella_dependencies(manifest: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut in_dependencies = false;
    for line in manifest.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            in_dependencies = line.ends_with("dependencies]")
                && !line.ends_with("dev-dependencies]")
                && !line.ends_with("build-dependencies]");
            continue;
        }
        if in_dependencies && line.starts_with("tessella-") {
            let name: String = line
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '-')
                .collect();
            out.insert(name);
        }
    }
    out
}

/// "The layers, and what each may import": the core imports no other crate of ours; the
/// backends (tessella-io, -gpu, -gl) import the core only, never each other; the pictures
/// (tessella-view) the backends and the core; nothing below the applications imports one. Read
/// from every crate's Cargo.toml (Bevy's and the Python package's included).
#[test]
fn crates_depend_down_the_layers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let layer = |name: &str| match name {
        "tessella-core" => 0,
        "tessella-io" | "tessella-gpu" | "tessella-gl" => 1,
        "tessella-view" => 2,
        _ => 3, // the applications: the CLI, Python, wasm, the viewer, Bevy, the benchmarks
    };
    let mut manifests: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .expect("crates/")
        .map(|e| e.expect("an entry").path().join("Cargo.toml"))
        .filter(|p| p.is_file())
        .collect();
    manifests.push(root.join("python/Cargo.toml"));
    let mut seen = 0;
    for manifest in manifests {
        let text = std::fs::read_to_string(&manifest).expect("a manifest");
        let name = text
            .lines()
            .find_map(|l| l.strip_prefix("name = \""))
            .and_then(|l| l.strip_suffix('"'))
            .expect("the package's name")
            .to_string();
        seen += 1;
        for dependency in tessella_dependencies(&text) {
            let (from, to) = (layer(&name), layer(&dependency));
            assert!(
                from == 3 || to < from,
                "{name} (layer {from}) depends on {dependency} (layer {to})"
            );
            if from == 1 {
                assert_eq!(
                    dependency, "tessella-core",
                    "a backend depends on {dependency}"
                );
            }
        }
    }
    assert!(seen >= 12, "{seen} manifests");
    let sample = "[dependencies]\ntessella-core.workspace = true\n[dev-dependencies]\ntessella-io = { path = \"x\" }\n[target.'cfg(x)'.dependencies]\ntessella-gpu = { path = \"y\", optional = true }\n";
    assert_eq!(
        tessella_dependencies(sample),
        BTreeSet::from(["tessella-core".to_string(), "tessella-gpu".to_string()])
    );
}
