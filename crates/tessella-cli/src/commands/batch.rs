//! `tessella batch`: refine many files with the same options, on all cores, resumable.
//!
//! Outputs that exist are complete (every write gets its name only once it is whole), so a
//! killed batch resumes by skipping them. Outputs are left in the system's cache and flushed to
//! the disk together when the batch ends (`--sync-each`: one `fsync` per file instead). Named
//! temporary files a killed run left in the output folder (only where the system has no
//! unnamed files) are removed when the next run starts. `manifest.jsonl` in the output folder gets one
//! row per input as each finishes.

use super::refine::refine_file;
use crate::args::RefineArgs;
use crate::args_batch::BatchArgs;
use crate::progress;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;
use tessella_io::{Durability, Format};

/// The manifest's file name in the output folder.
pub const MANIFEST: &str = "manifest.jsonl";

/// A mistake in how the batch was asked for (exit code 2), not in a file.
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for UsageError {}

fn usage(message: String) -> anyhow::Error {
    UsageError(message).into()
}

/// One manifest row.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Row {
    pub input: PathBuf,
    pub output: PathBuf,
    /// `ok`, `skipped` (the output existed: counts from the run that made it, when its
    /// manifest had them) or `failed`.
    pub status: String,
    pub input_triangles: Option<u64>,
    pub vertices: Option<u64>,
    pub triangles: Option<u64>,
    pub seconds: Option<f64>,
    /// Whether the output was written piece by piece (bounded memory).
    pub streamed: Option<bool>,
    pub error: Option<String>,
}

pub fn run(args: &BatchArgs) -> anyhow::Result<()> {
    let format = Format::from_path(Path::new(&format!("x.{}", args.format))).map_err(|_| {
        usage(format!(
            "--format {}: give ply, obj, glb, gltf or stl",
            args.format
        ))
    })?;
    if args.refine.write_origin && format != Format::Ply {
        return Err(usage(format!(
            "--write-origin writes PLY vertex properties; it needs --format ply, not {}",
            args.format
        )));
    }
    let jobs = inputs(&args.inputs, &args.refine.output, &args.format)?;
    let out_dir = &args.refine.output;
    std::fs::create_dir_all(out_dir).map_err(|e| {
        usage(format!(
            "cannot create the output folder {}: {e}",
            out_dir.display()
        ))
    })?;
    remove_stale_temporaries(out_dir);

    // Rows of outputs that exist already are carried over from the last manifest.
    let manifest_path = out_dir.join(MANIFEST);
    let old = read_manifest(&manifest_path);
    let (skip, todo): (Vec<_>, Vec<_>) = jobs
        .into_iter()
        .partition(|(_, output)| !args.force && output.exists());
    let skipped: Vec<Row> = skip
        .into_iter()
        .map(|(input, output)| match old.get(&input) {
            // The last run's counts, marked as not redone.
            Some(row) if row.output == output && row.status != "failed" => Row {
                status: "skipped".into(),
                ..row.clone()
            },
            _ => Row {
                input,
                output,
                status: "skipped".into(),
                input_triangles: None,
                vertices: None,
                triangles: None,
                seconds: None,
                streamed: None,
                error: None,
            },
        })
        .collect();
    let mut text = Vec::new();
    for row in &skipped {
        serde_json::to_writer(&mut text, row)?;
        text.push(b'\n');
    }
    tessella_io::write_atomic(&manifest_path, |w| w.write_all(&text))
        .map_err(|e| usage(format!("cannot write the manifest: {e}")))?;
    let manifest = Mutex::new(
        std::fs::OpenOptions::new()
            .append(true)
            .open(&manifest_path)
            .map_err(|e| usage(format!("cannot open {}: {e}", manifest_path.display())))?,
    );

    let shown = progress::shown();
    progress::quiet();
    let bar = match shown {
        true => files_bar(todo.len() as u64),
        false => indicatif::ProgressBar::hidden(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()?;
    // One flush of the whole file system at the end costs far less than one per small file,
    // and a killed process loses nothing either way: the kernel keeps what was written.
    let durability = Durability::synced_if(args.sync_each);
    let started = Instant::now();
    let rows: Vec<Row> = pool.install(|| {
        todo.into_par_iter()
            .map(|(input, output)| {
                let row = refine_one(&args.refine, &input, &output, durability);
                if let Some(e) = &row.error {
                    bar.suspend(|| eprintln!("failed: {e}"));
                }
                let line = serde_json::to_string(&row).expect("rows serialise");
                // A manifest that cannot be appended to is reported once per row, and the
                // batch goes on: the outputs themselves are what matters.
                let mut file = manifest.lock().unwrap_or_else(|e| e.into_inner());
                if let Err(e) = writeln!(file, "{line}").and_then(|()| file.flush()) {
                    bar.suspend(|| eprintln!("cannot append to the manifest: {e}"));
                }
                bar.inc(1);
                row
            })
            .collect()
    });
    bar.finish_and_clear();
    if durability == Durability::Cached {
        tessella_io::sync_folder(out_dir).map_err(|e| {
            anyhow::anyhow!("the outputs are written but not flushed to the disk: {e}")
        })?;
    }
    let failed = rows.iter().filter(|r| r.status == "failed").count();
    eprintln!(
        "{} refined, {} skipped (already there), {} failed in {:.2} s; manifest: {}",
        rows.len() - failed,
        skipped.len(),
        failed,
        started.elapsed().as_secs_f64(),
        manifest_path.display()
    );
    if failed > 0 {
        anyhow::bail!(
            "{failed} of {} files failed (see the messages above and {})",
            rows.len() + skipped.len(),
            manifest_path.display()
        );
    }
    Ok(())
}

fn files_bar(total: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(total),
        indicatif::ProgressDrawTarget::stderr(),
    );
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{msg} [{bar:40}] {pos}/{len} files {per_sec} eta {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message("batch");
    bar
}

/// Refines one file into its row; errors (and panics) become the row's message.
fn refine_one(options: &RefineArgs, input: &Path, output: &Path, durability: Durability) -> Row {
    let args = RefineArgs {
        input: input.to_path_buf(),
        output: output.to_path_buf(),
        ..options.clone()
    };
    let start = Instant::now();
    let made = output
        .parent()
        .map_or(Ok(()), std::fs::create_dir_all)
        .map_err(|e| anyhow::anyhow!("cannot create {}: {e}", output.display()))
        .and_then(|()| {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                refine_file(&args, false, durability)
            }))
            .unwrap_or_else(|_| {
                Err(anyhow::anyhow!(
                    "internal error (a panic); please report it"
                ))
            })
        });
    let seconds = Some(start.elapsed().as_secs_f64());
    match made {
        Ok(done) => Row {
            input: args.input,
            output: args.output,
            status: "ok".into(),
            input_triangles: Some(done.input_triangles as u64),
            vertices: Some(done.vertices),
            triangles: Some(done.triangles),
            seconds,
            streamed: Some(done.streamed),
            error: None,
        },
        Err(e) => Row {
            input: args.input,
            output: args.output,
            status: "failed".into(),
            input_triangles: None,
            vertices: None,
            triangles: None,
            seconds,
            streamed: None,
            error: Some(format!("{e:#}")),
        },
    }
}

/// Mesh files named by `inputs` (files, folders searched recursively, glob patterns) and each
/// one's output in `out_dir`: a folder's files keep their paths below the folder, the others
/// their names; the extension becomes `ext`.
fn inputs(
    inputs: &[PathBuf],
    out_dir: &Path,
    ext: &str,
) -> anyhow::Result<Vec<(PathBuf, PathBuf)>> {
    let mut found: Vec<(PathBuf, PathBuf)> = Vec::new();
    for input in inputs {
        let text = input.to_string_lossy();
        if input.is_dir() {
            let mut files = Vec::new();
            walk(input, &mut files)
                .map_err(|e| usage(format!("cannot list {}: {e}", input.display())))?;
            files.sort();
            for file in files {
                let relative = file.strip_prefix(input).unwrap_or(&file).to_path_buf();
                found.push((file, relative));
            }
        } else if input.exists() {
            found.push((
                input.clone(),
                input.file_name().map(PathBuf::from).unwrap_or_default(),
            ));
        } else if text.contains(['*', '?', '[']) {
            let paths =
                glob::glob(&text).map_err(|e| usage(format!("bad pattern {text:?}: {e}")))?;
            let mut matched = 0;
            for path in paths {
                let path = path.map_err(|e| usage(format!("{text:?}: {e}")))?;
                if path.is_file() {
                    matched += 1;
                    let name = path.file_name().map(PathBuf::from).unwrap_or_default();
                    found.push((path, name));
                }
            }
            if matched == 0 {
                return Err(usage(format!("the pattern {text:?} matches no file")));
            }
        } else {
            return Err(usage(format!(
                "{}: no such file or folder",
                input.display()
            )));
        }
    }
    if found.is_empty() {
        return Err(usage("no mesh files among the inputs".into()));
    }
    let mut outputs: HashMap<PathBuf, PathBuf> = HashMap::new();
    let mut jobs = Vec::with_capacity(found.len());
    for (input, relative) in found {
        let output = out_dir.join(relative.with_extension(ext));
        if let Some(first) = outputs.insert(output.clone(), input.clone()) {
            return Err(usage(format!(
                "{} and {} would both be written to {}; batch them into separate folders",
                first.display(),
                input.display(),
                output.display()
            )));
        }
        jobs.push((input, output));
    }
    Ok(jobs)
}

/// Files with a mesh extension below `dir`.
fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            walk(&path, out)?;
        } else if Format::from_path(&path).is_ok() {
            out.push(path);
        }
    }
    Ok(())
}

/// Removes the temporary files (`.tessella-*.tmp`) a killed run left below `dir`. One batch
/// at a time per output folder: another one's files in progress would go too.
fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if path.is_dir() {
            remove_stale_temporaries(&path);
        } else if name.starts_with(tessella_io::TEMP_PREFIX)
            && name.ends_with(tessella_io::TEMP_SUFFIX)
        {
            if let Err(e) = std::fs::remove_file(&path) {
                eprintln!("note: cannot remove the stale {}: {e}", path.display());
            }
        }
    }
}

/// The last manifest's rows by input (unreadable lines are ignored: rows are rewritten).
fn read_manifest(path: &Path) -> BTreeMap<PathBuf, Row> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .filter_map(|line| serde_json::from_str::<Row>(line).ok())
        .map(|row| (row.input.clone(), row))
        .collect()
}
