//! A skinned, morphing character played per frame on the CPU: pose (morph targets, skinning)
//! → nets (`Plan::update`) → evaluate into reused buffers, against the refinement alone
//! (evaluate with the nets as they are) timed in the same run.

use super::frames::{median, FrameOutput};
use anyhow::Context;
use serde::Serialize;
use std::time::{Duration, Instant};
use tessella_core::animation::Poser;
use tessella_core::refine::Plan;
use tessella_core::{RefineOptions, Scheme};

/// One level of the animated table: median milliseconds per frame of each step.
#[derive(Debug, Clone, Serialize)]
pub struct AnimatedRow {
    pub mesh: String,
    pub faces: usize,
    pub level: u32,
    pub vertices: usize,
    /// Posing the coarse mesh (morph targets, then skinning).
    pub pose_ms: f64,
    /// Building the frame's nets from the posed mesh.
    pub nets_ms: f64,
    /// Evaluating the refined vertices (positions + normals) into reused buffers.
    pub evaluate_ms: f64,
    /// The three together, timed as one.
    pub frame_ms: f64,
    /// The refinement alone: evaluate with the nets unchanged.
    pub refine_alone_ms: f64,
}

/// Plays `clip` of `poser` (PN, welded) at `levels`, frames `1/30 s` apart, median of `repeat`.
pub fn animated(
    name: &str,
    poser: &Poser,
    clip: &str,
    levels: &[u32],
    repeat: usize,
) -> anyhow::Result<Vec<AnimatedRow>> {
    let clip = poser.clip_index(clip)?;
    let rest = poser.mesh(None, 0.0)?;
    let n = poser.vertex_count();
    let mut coarse = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
    let mut rows = Vec::new();
    for &level in levels {
        let options = RefineOptions::new(Scheme::Pn, level);
        let plan = Plan::new(&rest, &options)?;
        let mut frame = plan.frame(&rest)?;
        let out_n = plan.vertex_count();
        let mut out = FrameOutput::new(&plan);
        let (p, nr) = (&mut coarse.0, &mut coarse.1);
        // Frame `k`, at `k / 30` s: pose, nets, evaluate, each timed, and the three together.
        let mut step = |k: usize| -> anyhow::Result<[Duration; 4]> {
            let start = Instant::now();
            poser.pose_into(Some(clip), k as f32 / 30.0, p, Some(nr))?;
            let posed = start.elapsed();
            plan.update(&mut frame, p, Some(nr))?;
            let built = start.elapsed();
            out.evaluate(&plan, &frame)?;
            let done = start.elapsed();
            Ok([posed, built - posed, done - built, done])
        };
        step(0).context("warm-up frame")?;
        let frames: Vec<[Duration; 4]> =
            (1..=repeat).map(&mut step).collect::<anyhow::Result<_>>()?;
        let column = |i: usize| median(frames.iter().map(|f| f[i]).collect());
        let alone = median(
            (0..repeat)
                .map(|_| -> anyhow::Result<Duration> {
                    let start = Instant::now();
                    out.evaluate(&plan, &frame)?;
                    Ok(start.elapsed())
                })
                .collect::<anyhow::Result<_>>()?,
        );
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        rows.push(AnimatedRow {
            mesh: name.to_string(),
            faces: rest.face_count(),
            level,
            vertices: out_n,
            pose_ms: ms(column(0)),
            nets_ms: ms(column(1)),
            evaluate_ms: ms(column(2)),
            frame_ms: ms(column(3)),
            refine_alone_ms: ms(alone),
        });
    }
    Ok(rows)
}

/// Markdown table of [`animated`] rows.
pub fn animated_table(rows: &[AnimatedRow]) -> String {
    let mut s = String::from(
        "| mesh | coarse triangles | level | vertices | pose (ms) | nets (ms) | evaluate (ms) | frame (ms) | refine alone (ms) | frame / refine alone |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2}x |\n",
            r.mesh,
            r.faces,
            r.level,
            r.vertices,
            r.pose_ms,
            r.nets_ms,
            r.evaluate_ms,
            r.frame_ms,
            r.refine_alone_ms,
            r.frame_ms / r.refine_alone_ms
        );
    }
    s
}
