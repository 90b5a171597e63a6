//! The CPU measurements of `tessella bench`: the machine's memory bandwidth, then refinement
//! measured against it and against baselines timed in the same run: one-shot refinement on all
//! cores against one core, every scheme refined per frame (the roofline table), a deforming mesh
//! updated per frame against rebuilt per frame, and the file writers. [`Report`] holds them all;
//! serialised, it is `tessella bench --json`.

mod animated;
mod frames;
mod write;

pub use animated::{animated, animated_table, AnimatedRow};
pub use frames::{
    deforming, deforming_table, median, roofline, roofline_schemes, roofline_table, Bandwidth,
    DeformRow, RooflineRow, BYTES_PER_VERTEX,
};
pub use write::{writers, writers_table, WriteRow};

use anyhow::Context;
use serde::Serialize;
use std::time::{Duration, Instant};
use tessella_core::{samples, Mesh, RefineOptions, RefinedMesh, Refiner, Scheme};

/// Median time of `repeat` refinements into reused buffers.
fn time_refine(refiner: &Refiner, repeat: usize) -> Duration {
    let mut out = RefinedMesh::default();
    refiner.refine_into(&mut out, &|_| {}); // warm up: allocate, fault pages in
    median(
        (0..repeat)
            .map(|_| {
                let start = Instant::now();
                refiner.refine_into(&mut out, &|_| {});
                start.elapsed()
            })
            .collect(),
    )
}

/// One row of the one-shot table: PN refined with indices into reused buffers.
#[derive(Debug, Clone, Serialize)]
pub struct OneShotRow {
    pub level: u32,
    pub vertices: u64,
    pub triangles: u64,
    /// Topology, control nets, stencil and layout.
    pub prepare_ms: f64,
    pub ms: f64,
    pub vertices_per_s: f64,
    pub one_thread_ms: f64,
    pub one_thread_vertices_per_s: f64,
    /// `Refiner::refine`: new arrays every call (what Python's `tessella.refine` does).
    pub fresh_ms: f64,
    pub fresh_vertices_per_s: f64,
    /// Bytes of the output: positions, normals, triangles.
    pub output_bytes: u64,
    /// Output bytes per second of the fresh call over the fresh-memory fill rate.
    pub fresh_of_fresh_fill: f64,
}

/// Everything `tessella bench` measures on the CPU, in one run; serialised, it is what
/// `tessella bench --json` prints.
#[derive(Debug, Serialize)]
pub struct Report {
    pub mesh: String,
    pub faces: usize,
    pub repeat: usize,
    pub bandwidth: Bandwidth,
    pub one_shot: Vec<OneShotRow>,
    pub per_frame: Vec<RooflineRow>,
    pub deforming: Vec<DeformRow>,
    /// The animated sample on an icosphere of 5,120 triangles playing its `wave` clip (with the
    /// creature only).
    pub animated: Vec<AnimatedRow>,
    /// The mesh refined at `write_level`, written in every format.
    pub write_level: u32,
    pub writers: Vec<WriteRow>,
}

impl Report {
    /// Measures `mesh` (named `name` in the tables) at `levels`, median of `repeat`, against
    /// `bandwidth`: one-shot, per frame, deforming (also the bundled creature when
    /// `with_creature`), and the file writers at the largest level up to 32.
    pub fn measure(
        name: String,
        mesh: &Mesh,
        levels: &[u32],
        repeat: usize,
        bandwidth: Bandwidth,
        with_creature: bool,
    ) -> anyhow::Result<Report> {
        let one_shot = one_shot(mesh, levels, repeat, &bandwidth)?;
        let per_frame = roofline(mesh, levels, repeat, &bandwidth)?;
        let mut deforming = deforming(&name, mesh, levels, repeat, &bandwidth)?;
        let mut animated_rows = Vec::new();
        if with_creature {
            let poser = tessella_core::animation::Poser::new(samples::animated_creature(4))?;
            animated_rows = animated("animated creature", &poser, "wave", levels, repeat)?;
            let creature = samples::creature();
            deforming.extend(frames::deforming(
                "creature", &creature, levels, repeat, &bandwidth,
            )?);
        }
        // Writers: the largest level up to 32 (a few hundred MB at most of files).
        let write_level = levels
            .iter()
            .copied()
            .filter(|&l| l <= 32)
            .max()
            .unwrap_or(levels.iter().copied().min().unwrap_or(1));
        let refined = Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, write_level))?.refine();
        let writers = writers(&refined, repeat, &bandwidth)?;
        Ok(Report {
            mesh: name,
            faces: mesh.face_count(),
            repeat,
            bandwidth,
            one_shot,
            per_frame,
            deforming,
            animated: animated_rows,
            write_level,
            writers,
        })
    }

    /// The report as `tessella bench` prints it: the bandwidth line, then each table under its
    /// heading.
    pub fn tables(&self) -> String {
        let b = &self.bandwidth;
        let mut s = format!("{}\n\n", bandwidth_line(b));
        s += &format!(
            "One-shot refinement, PN, welded, positions + quadratic normals + indices, into reused buffers and into new arrays (the output bytes against the fresh-memory fill rate); {} ({} coarse triangles); median of {}:\n\n",
            self.mesh, self.faces, self.repeat
        );
        s += &one_shot_table(&self.one_shot, b.threads);
        s += &format!(
            "\nPer frame (plan and nets reused, indices not rewritten), positions + normals into reused arrays, against the fill rate; {}:\n\n",
            self.mesh
        );
        s += &roofline_table(&self.per_frame);
        s += "\nDeforming mesh (twisting), PN: plan update + evaluate against rebuilding everything per frame:\n\n";
        s += &deforming_table(&self.deforming);
        if !self.animated.is_empty() {
            s += "\nAnimated (skinned, morphing; the `wave` clip), PN: pose + nets + evaluate per frame against the refinement alone:\n\n";
            s += &animated_table(&self.animated);
        }
        s += &format!(
            "\nFile writers, {} refined at level {} ({} vertices), against the copy bandwidth:\n\n",
            self.mesh,
            self.write_level,
            self.per_frame
                .iter()
                .find(|r| r.level == self.write_level)
                .map_or(0, |r| r.vertices)
        );
        s += &writers_table(&self.writers);
        s
    }
}

fn one_shot(
    mesh: &Mesh,
    levels: &[u32],
    repeat: usize,
    bandwidth: &Bandwidth,
) -> anyhow::Result<Vec<OneShotRow>> {
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .context("cannot start a one-thread pool")?;
    let mut rows = Vec::new();
    for &level in levels {
        let start = Instant::now();
        let refiner = Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, level))?;
        let prepare = start.elapsed();
        let vertices = refiner.layout().vertex_count;
        let many = time_refine(&refiner, repeat);
        let one = single.install(|| time_refine(&refiner, repeat));
        let fresh = median(
            (0..repeat)
                .map(|_| {
                    let start = Instant::now();
                    let out = refiner.refine();
                    let time = start.elapsed();
                    std::hint::black_box(out);
                    time
                })
                .collect(),
        );
        let rate = |d: Duration| vertices as f64 / d.as_secs_f64();
        let output_bytes = vertices * 24 + refiner.layout().triangle_count * 12;
        rows.push(OneShotRow {
            fresh_ms: fresh.as_secs_f64() * 1e3,
            fresh_vertices_per_s: rate(fresh),
            output_bytes,
            fresh_of_fresh_fill: output_bytes as f64
                / fresh.as_secs_f64()
                / bandwidth.fresh_fill_bytes_per_s,
            level,
            vertices,
            triangles: refiner.layout().triangle_count,
            prepare_ms: prepare.as_secs_f64() * 1e3,
            ms: many.as_secs_f64() * 1e3,
            vertices_per_s: rate(many),
            one_thread_ms: one.as_secs_f64() * 1e3,
            one_thread_vertices_per_s: rate(one),
        });
    }
    Ok(rows)
}

fn one_shot_table(rows: &[OneShotRow], threads: usize) -> String {
    let mut s = format!(
        "| level | vertices | triangles | prepare (ms) | reused, {threads} threads (ms) | M vertices/s | 1 thread (ms) | M vertices/s | speed-up | new arrays (ms) | M vertices/s | of fresh fill |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {:.2} | {:.1} | {:.2} | {:.1} | {:.2}x | {:.2} | {:.1} | {:.0}% |\n",
            r.level,
            r.vertices,
            r.triangles,
            r.prepare_ms,
            r.ms,
            r.vertices_per_s / 1e6,
            r.one_thread_ms,
            r.one_thread_vertices_per_s / 1e6,
            r.ms.recip() * r.one_thread_ms,
            r.fresh_ms,
            r.fresh_vertices_per_s / 1e6,
            100.0 * r.fresh_of_fresh_fill
        );
    }
    s
}

/// The bandwidth figures, one line.
pub fn bandwidth_line(b: &Bandwidth) -> String {
    let gb = |x: f64| x / 1e9;
    format!(
        "Memory bandwidth, {} threads: fill {:.1} GB/s (plain stores {:.1}, non-temporal {:.1}; plain, 1 thread {:.1}), copy {:.1} GB/s (read + write; memcpy {:.1}, non-temporal {:.1}), fill of freshly allocated memory {:.1} GB/s (page faults included)",
        b.threads,
        gb(b.fill_bytes_per_s),
        gb(b.fill_plain_bytes_per_s),
        gb(b.fill_nt_bytes_per_s),
        gb(b.fill_plain_one_thread_bytes_per_s),
        gb(b.copy_bytes_per_s.max(b.copy_nt_bytes_per_s)),
        gb(b.copy_bytes_per_s),
        gb(b.copy_nt_bytes_per_s),
        gb(b.fresh_fill_bytes_per_s)
    )
}
