//! `tessella bench`'s file-writing table: a refined mesh written in every format, timed two
//! ways. "encode + write" is the writer into a file in the page cache (what the formatter and
//! the system call cost, the measure); "atomic + fsync" is what `tessella refine` does
//! (temporary file, flushed to the disk, renamed), which a slow disk bounds.

use super::frames::{median, Bandwidth};
use serde::Serialize;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::{Duration, Instant};
use tessella_core::RefinedMesh;
use tessella_io::{MeshView, WriteOptions};

/// One row of [`writers`].
#[derive(Debug, Clone, Serialize)]
pub struct WriteRow {
    pub format: String,
    pub bytes: u64,
    /// Encoding and writing into the page cache.
    pub ms: f64,
    pub bytes_per_s: f64,
    /// `bytes_per_s` over the machine's copy bandwidth.
    pub of_copy: f64,
    /// `write_mesh`: temporary file, fsync, rename.
    pub atomic_ms: f64,
}

/// The formats timed, by file name.
const FILES: [&str; 5] = ["out.ply", "out.glb", "out.obj", "ascii.ply", "out.stl"];

fn write_once(dir: &Path, file: &str, view: &MeshView) -> anyhow::Result<(Duration, u64)> {
    let path = dir.join(file);
    let start = Instant::now();
    let mut out = BufWriter::new(std::fs::File::create(&path)?);
    let w: &mut dyn Write = &mut out;
    match file {
        "out.ply" => tessella_io::ply::write(w, view, false)?,
        "ascii.ply" => tessella_io::ply::write(w, view, true)?,
        "out.glb" => tessella_io::gltf::write(w, view, true)?,
        "out.obj" => tessella_io::obj::write(w, view)?,
        "out.stl" => tessella_io::stl::write(w, view)?,
        other => anyhow::bail!("no writer for {other}"),
    }
    out.flush()?;
    let time = start.elapsed();
    let bytes = std::fs::metadata(&path)?.len();
    std::fs::remove_file(&path)?;
    Ok((time, bytes))
}

/// Times every writer on `mesh` (median of `repeat`, at least 3).
pub fn writers(
    mesh: &RefinedMesh,
    repeat: usize,
    bandwidth: &Bandwidth,
) -> anyhow::Result<Vec<WriteRow>> {
    let dir = tempfile::tempdir()?;
    let view = MeshView::from(mesh);
    let repeat = repeat.clamp(3, 7);
    let mut rows = Vec::new();
    for file in FILES {
        let mut bytes = 0;
        let mut times = Vec::new();
        for _ in 0..repeat {
            let (time, b) = write_once(dir.path(), file, &view)?;
            times.push(time);
            bytes = b;
        }
        let time = median(times);
        let path = dir.path().join(file);
        let options = WriteOptions {
            ply_ascii: file == "ascii.ply",
            ..Default::default()
        };
        let start = Instant::now();
        tessella_io::write_mesh(&path, view, &options)?;
        let atomic = start.elapsed();
        std::fs::remove_file(&path)?;
        let rate = bytes as f64 / time.as_secs_f64();
        rows.push(WriteRow {
            format: match file {
                "out.ply" => "PLY binary",
                "ascii.ply" => "PLY ascii",
                "out.glb" => "GLB",
                "out.obj" => "OBJ",
                _ => "STL",
            }
            .to_string(),
            bytes,
            ms: time.as_secs_f64() * 1e3,
            bytes_per_s: rate,
            of_copy: rate / bandwidth.copy_bytes_per_s,
            atomic_ms: atomic.as_secs_f64() * 1e3,
        });
    }
    Ok(rows)
}

/// Markdown table of [`writers`] rows.
pub fn writers_table(rows: &[WriteRow]) -> String {
    let mut s = String::from(
        "| format | MB | encode + write (ms) | GB/s | of copy bandwidth | atomic + fsync (ms) |\n\
         |---|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {:.1} | {:.1} | {:.2} | {:.0}% | {:.1} |\n",
            r.format,
            r.bytes as f64 / 1e6,
            r.ms,
            r.bytes_per_s / 1e9,
            100.0 * r.of_copy,
            r.atomic_ms
        );
    }
    s
}
