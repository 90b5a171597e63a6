//! The web page's `bench()` (tessella-viewer's `WebViewer::bench` calls [`run`]): the GMR
//! paper's Figure 7 (a static buffer of the refined mesh against the refinement pattern: frame
//! time and GPU footprint), PN against flat and PNG1 against PN at the PNG1 paper's sizes, and
//! the adaptive renderer with levels moving every frame, all on the viewer's own device. The
//! measuring is [`crate::gpu`]'s, awaited frame by frame, so it never blocks a page and is the
//! same code as `tessella bench` natively. The report is JSON (camelCase names) plus the
//! Markdown tables.

use crate::gpu::{
    changing_levels_async, changing_levels_table, figure7_async, figure7_table, mesh_with_faces,
    ratio, scheme_frame_times_async, Figure7Config,
};
use serde::Deserialize;
use serde_json::{json, Value};
use tessella_core::Scheme;
use tessella_gpu::{GpuContext, GpuError};

/// Why [`run`] or [`BenchConfig::from_json`] failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BenchError {
    /// A bad configuration, refused before anything runs (the message names the field).
    #[error("bench: {0}")]
    Config(String),
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// What to run; every field has the papers' value as its default.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct BenchConfig {
    /// Coarse triangle counts of Figure 7 (GMR: 10, 100, 1000).
    pub faces: Vec<usize>,
    /// Pattern levels of Figure 7 (GMR: 64 and 128, patterns of 64×64 and 128×128).
    pub levels: Vec<u32>,
    /// Frames timed per configuration (the median is reported).
    pub frames: u32,
    /// The offscreen target's size.
    pub size: [u32; 2],
    /// Figure 7's scheme.
    pub scheme: String,
    /// Coarse triangle counts of the scheme comparison (the PNG1 paper: 200 and 1084).
    pub scheme_faces: Vec<usize>,
    /// Its levels (the PNG1 paper: 8, 9, 10).
    pub scheme_levels: Vec<u32>,
    /// Highest per-edge level of the moving-levels experiment.
    pub moving_top: f32,
    /// Which experiments: any of "figure7", "schemes", "moving".
    pub parts: Vec<String>,
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            faces: vec![10, 100, 1000],
            levels: vec![64, 128],
            frames: 10,
            size: [512, 512],
            scheme: "pn".into(),
            scheme_faces: vec![200, 1084],
            scheme_levels: vec![8, 9, 10],
            moving_top: 24.0,
            parts: PARTS.iter().map(|p| p.to_string()).collect(),
        }
    }
}

const PARTS: [&str; 3] = ["figure7", "schemes", "moving"];

/// The largest values accepted, each and all together: a benchmark that would run for
/// hours is refused up front.
const MAX_FACES: usize = 100_000;
const MAX_LEVEL: u32 = 256;
const MAX_FRAMES: u32 = 1000;
/// Triangles drawn by the whole run (the defaults draw about 5e8).
const MAX_TRIANGLES: f64 = 2e10;

fn bad(message: String) -> BenchError {
    BenchError::Config(message)
}

impl BenchConfig {
    /// The configuration from a JSON object (missing fields take the defaults).
    pub fn from_json(value: &Value) -> Result<BenchConfig, BenchError> {
        let config = if value.is_null() {
            BenchConfig::default()
        } else {
            serde_json::from_value(value.clone()).map_err(|e| bad(e.to_string()))?
        };
        config.validate()?;
        Ok(config)
    }

    fn validate(&self) -> Result<(), BenchError> {
        let faces = self.faces.iter().chain(&self.scheme_faces);
        if let Some(f) = faces.clone().find(|&&f| f == 0 || f > MAX_FACES) {
            return Err(bad(format!("{f} coarse triangles: give 1..={MAX_FACES}")));
        }
        let levels = self.levels.iter().chain(&self.scheme_levels);
        if let Some(l) = levels.clone().find(|&&l| l == 0 || l > MAX_LEVEL) {
            return Err(bad(format!("level {l}: give 1..={MAX_LEVEL}")));
        }
        // Each field may be in range and the whole still far too much to draw.
        let drawn = |faces: &[usize], levels: &[u32], draws: f64| {
            let sum = |v: &mut dyn Iterator<Item = f64>| v.sum::<f64>();
            sum(&mut faces.iter().map(|&f| f as f64))
                * sum(&mut levels.iter().map(|&l| (l as f64).powi(2)))
                * draws
        };
        let triangles = (drawn(&self.faces, &self.levels, 2.0)
            + drawn(&self.scheme_faces, &self.scheme_levels, 3.0))
            * (self.frames as f64 + 1.0);
        if triangles > MAX_TRIANGLES {
            return Err(bad(format!(
                "about {triangles:.1e} triangles to draw in all: give at most {MAX_TRIANGLES:.0e} (fewer faces, levels or frames)"
            )));
        }
        if self.frames == 0 || self.frames > MAX_FRAMES {
            return Err(bad(format!(
                "frames {}: give 1..={MAX_FRAMES}",
                self.frames
            )));
        }
        if self.size.iter().any(|&s| s == 0 || s > 8192) {
            return Err(bad(format!(
                "size {}x{}: give 1..=8192 per side",
                self.size[0], self.size[1]
            )));
        }
        if !(self.moving_top.is_finite() && (1.0..=64.0).contains(&self.moving_top)) {
            return Err(bad(format!("movingTop {}: give 1..=64", self.moving_top)));
        }
        if let Some(p) = self.parts.iter().find(|p| !PARTS.contains(&p.as_str())) {
            return Err(bad(format!("unknown part {p:?}: give any of {PARTS:?}")));
        }
        self.figure7_scheme().map(|_| ())
    }

    fn figure7_scheme(&self) -> Result<Scheme, BenchError> {
        self.scheme
            .parse::<Scheme>()
            .map_err(|e| bad(format!("scheme: {e}")))
    }

    fn runs(&self, part: &str) -> bool {
        self.parts.iter().any(|p| p == part)
    }
}

/// Runs the configured experiments on `ctx` and returns the report: `adapter`, `figure7`,
/// `schemes`, `moving` (each a list of rows) and `markdown` (the tables).
pub async fn run(ctx: &GpuContext, config: &BenchConfig) -> Result<Value, BenchError> {
    config.validate()?;
    let size = (config.size[0], config.size[1]);
    let mut markdown = format!("Adapter: {}\n\n", ctx.adapter_label());
    let mut figure7 = Vec::new();
    if config.runs("figure7") {
        let rows = figure7_async(
            ctx,
            &Figure7Config {
                faces: config.faces.clone(),
                levels: config.levels.clone(),
                frames: config.frames,
                size,
                scheme: config.figure7_scheme()?,
            },
        )
        .await?;
        markdown += "## Figure 7: static buffer against refinement pattern\n\n";
        markdown += &figure7_table(&rows);
        figure7 = rows
            .iter()
            .map(|r| {
                json!({
                    "faces": r.faces,
                    "level": r.level,
                    "staticMs": r.static_ms,
                    "staticVertices": r.static_vertices,
                    "staticBytes": r.static_bytes,
                    "staticNote": r.static_note,
                    "patternMs": r.pattern_ms,
                    "patternVertices": r.pattern_vertices,
                    "patternBytes": r.pattern_bytes,
                    "frameRatio": r.frame_ratio(),
                    "footprintRatio": r.footprint_ratio(),
                    "footprintGoal": 1.0 / r.faces.max(1) as f64,
                    "picturesDiffer": r.pictures_differ,
                })
            })
            .collect();
    }
    let mut schemes = Vec::new();
    if config.runs("schemes") {
        markdown += "\n## Schemes: PN against flat, PNG1 against PN\n\n";
        markdown += "| coarse triangles | level | flat ms | PN ms | PNG1 ms | PN/flat frame time | PNG1/PN frame rate |\n|---:|---:|---:|---:|---:|---:|---:|\n";
        for &faces in &config.scheme_faces {
            let mesh = mesh_with_faces(faces)?;
            for &level in &config.scheme_levels {
                let rows = scheme_frame_times_async(
                    ctx,
                    &mesh,
                    &[Scheme::Flat, Scheme::Pn, Scheme::Png1],
                    level,
                    config.frames,
                    size,
                )
                .await?;
                let [flat, pn, png1] = [0, 1, 2].map(|i| rows[i].frame_ms);
                let (pn_over_flat, png1_rate) = (ratio(pn, flat), ratio(pn, png1));
                let shown = |r: Option<f64>| r.map_or("—".into(), |r| format!("{r:.2}x"));
                markdown += &format!(
                    "| {faces} | {level} | {flat:.2} | {pn:.2} | {png1:.2} | {} | {} |\n",
                    shown(pn_over_flat),
                    shown(png1_rate)
                );
                schemes.push(json!({
                    "faces": faces,
                    "level": level,
                    "flatMs": flat,
                    "pnMs": pn,
                    "png1Ms": png1,
                    "pnOverFlat": pn_over_flat,
                    "png1RateOverPn": png1_rate,
                }));
            }
        }
    }
    let mut moving = Vec::new();
    if config.runs("moving") {
        let mesh = tessella_core::samples::icosphere(2);
        let rows =
            changing_levels_async(ctx, &mesh, config.moving_top, config.frames, size).await?;
        markdown += "\n## Levels moving every frame: a new plan per frame against the adaptive renderer\n\n";
        markdown += &changing_levels_table(&rows);
        moving = rows
            .iter()
            .map(|r| {
                json!({
                    "spacing": r.spacing,
                    "faces": r.faces,
                    "triangles": r.triangles,
                    "rebuildMs": r.rebuild_ms,
                    "rebuildBytes": r.rebuild_bytes,
                    "adaptiveMs": r.adaptive_ms,
                    "adaptiveBytes": r.adaptive_bytes,
                    "setLevelsMs": r.set_levels_ms,
                    "patternDrawMs": r.pattern_draw_ms,
                    "adaptiveDrawMs": r.adaptive_draw_ms,
                })
            })
            .collect();
    }
    Ok(json!({
        "adapter": ctx.adapter_label(),
        "figure7": figure7,
        "schemes": schemes,
        "moving": moving,
        "markdown": markdown,
    }))
}
