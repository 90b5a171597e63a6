//! Command-line arguments.

use clap::builder::{PossibleValue, TypedValueParser};
use clap::{Args, ValueEnum};
use std::ffi::OsStr;
use std::marker::PhantomData;
use std::path::PathBuf;
use std::str::FromStr;
use tessella_core::refine::Spacing;
use tessella_core::{Backend, Named, NormalMode, Scheme, UnknownName};

/// A scheme named on the command line (parsed by the core, [`tessella_core::names`]); Phong's
/// shape factor comes from `--alpha`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchemeArg(pub Scheme);

impl SchemeArg {
    /// The scheme, with Phong's shape factor `alpha` (the picture commands, built with `gpu`).
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    pub fn scheme(self, alpha: f32) -> Scheme {
        self.0.with_alpha(alpha)
    }
}

/// A normal mode named on the command line (parsed by the core).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalsArg(pub NormalMode);

impl From<NormalsArg> for NormalMode {
    fn from(n: NormalsArg) -> NormalMode {
        n.0
    }
}

/// Where refinement runs (the core's [`Backend`], under the name the commands use).
pub type BackendArg = Backend;

/// Parses a name the core defines ([`tessella_core::names`]): help lists the core's names with
/// their descriptions, and a bad name gets the core's message, which lists the valid ones.
#[derive(Debug)]
pub struct CoreName<T>(PhantomData<fn() -> T>);

impl<T> CoreName<T> {
    pub fn new() -> CoreName<T> {
        CoreName(PhantomData)
    }
}

impl<T> Default for CoreName<T> {
    fn default() -> Self {
        CoreName::new()
    }
}

impl<T> Clone for CoreName<T> {
    fn clone(&self) -> Self {
        CoreName::new()
    }
}

impl<T> TypedValueParser for CoreName<T>
where
    T: Named + FromStr<Err = UnknownName> + Clone + Send + Sync + 'static,
{
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        let text = value.to_string_lossy();
        text.parse::<T>().map_err(|e| {
            let arg = arg.map_or_else(String::new, |a| format!(" for '{a}'"));
            clap::Error::raw(
                clap::error::ErrorKind::InvalidValue,
                format!("invalid value '{text}'{arg}: {e}\n"),
            )
            .with_cmd(cmd)
        })
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(
            T::ALL
                .iter()
                .map(|v| PossibleValue::new(v.name()).help(v.description())),
        ))
    }
}

/// `--scheme` values.
fn scheme_parser() -> impl TypedValueParser<Value = SchemeArg> {
    CoreName::<Scheme>::new().map(SchemeArg)
}

/// The surface's flags of `refine`, `render` and `view`: the scheme and its shape.
#[derive(Debug, Clone, Copy, Args)]
pub struct ShapeArgs {
    /// Surface built over each coarse triangle.
    #[arg(long, value_parser = scheme_parser(), default_value = "pn")]
    pub scheme: SchemeArg,
    /// Phong shape factor: 0 is flat, 1 the full projection.
    #[arg(long, default_value_t = 0.75, value_parser = parse_alpha, allow_hyphen_values = true)]
    pub alpha: f32,
    /// How refined normals are made (default: the scheme's own).
    #[arg(long, value_parser = CoreName::<NormalMode>::new().map(NormalsArg))]
    pub normals: Option<NormalsArg>,
}

/// The pose flags of `refine` and `render`.
#[derive(Debug, Clone, Args)]
pub struct PoseFlags {
    /// Pose one of the input's animation clips (a glTF file's animations, by name or index)
    /// before refining: morph targets, then skinning.
    #[arg(long, value_name = "NAME|INDEX")]
    pub clip: Option<String>,
    /// Seconds into the clip; a time past its end holds its last pose.
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, requires = "clip")]
    pub time: f32,
}

#[derive(Debug, Clone, Args)]
pub struct RefineArgs {
    /// Input mesh (.obj, .ply, .gltf, .glb, .stl).
    pub input: PathBuf,
    /// Output mesh (.obj, .ply, .gltf, .glb, .stl); the format follows the extension.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub pose: PoseFlags,
    /// Segments per coarse edge: each triangle becomes LEVEL² triangles (grid). With a
    /// tessellator --spacing a fractional level (e.g. 5.5), clamped to the spacing's range.
    #[arg(short, long, default_value_t = 8.0, value_parser = parse_level, allow_negative_numbers = true)]
    pub level: f64,
    /// How levels divide each edge: grid, or the GPU tessellator's equal / fractional-odd /
    /// fractional-even spacing.
    #[arg(long, value_parser = CoreName::<Spacing>::new(), default_value = "grid")]
    pub spacing: Spacing,
    #[command(flatten)]
    pub lod: LodArgs,
    /// Image size for --lod screen, WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Add PLY vertex properties `face` (the coarse triangle) and `bary1..3` (barycentric
    /// coordinates in its corner order) saying where each refined vertex comes from.
    #[arg(long)]
    pub write_origin: bool,
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Give every coarse triangle its own vertices instead of sharing them along coarse edges.
    #[arg(long)]
    pub soup: bool,
    /// Write PLY as ASCII instead of binary little-endian.
    #[arg(long)]
    pub ply_ascii: bool,
    /// Memory to work in (e.g. 512MiB, 8GiB): the pieces in flight when the output is
    /// streamed, a cap on the output when it is refined in memory.
    #[arg(long, default_value = "8GiB", value_parser = parse_bytes)]
    pub max_memory: u64,
    /// Refine the whole output in memory before writing it (capped by --max-memory) instead
    /// of streaming it piece by piece; the same file, the reference the streamed one is
    /// checked against.
    #[arg(long)]
    pub in_memory: bool,
    /// Where to refine.
    #[arg(long, value_parser = CoreName::<Backend>::new(), default_value = "auto")]
    pub backend: Backend,
    #[command(flatten)]
    pub tags: TagArgs,
    /// Also print the surface-quality report (G1 defect, watertightness, distance from the
    /// coarse mesh).
    #[arg(long)]
    pub report: bool,
    /// Move refined vertices along their normals: `sine:AMP,FREQ` (a·sin(f‖P‖), GMR section 4),
    /// `perlin:AMP,FREQ[,SEED]`, or `heightmap:IMAGE,AMP` (needs UVs).
    #[arg(long, value_name = "SPEC")]
    pub displace: Option<String>,
    /// glTF in and out: give each primitive its own level, so that refined edges are about
    /// LENGTH long in world space (at most level 64), instead of one --level for all.
    #[arg(long, value_name = "LENGTH", conflicts_with = "level")]
    pub max_edge: Option<f32>,
    /// glTF in and out: the refined TANGENT of primitives that have one: `recomputed`
    /// (MikkTSpace on the refined mesh) or `carried` (the file's, interpolated and made
    /// orthogonal to the refined normal; about twice as fast).
    #[arg(long, value_name = "HOW", default_value = "recomputed", value_parser = ["recomputed", "carried"])]
    pub tangents: String,
    /// glTF in and out: how many JOINTS_n/WEIGHTS_n sets skinned primitives get: `input` (as
    /// many as the file has; three.js and Bevy read the first only) or up to N (1-8) sets where
    /// a refined vertex blends more influences than the file's sets hold.
    #[arg(long, value_name = "N", default_value = "input")]
    pub joint_sets: String,
    /// glTF in and out: merge the default scene into one mesh in world space, as for other
    /// formats, instead of writing the scene back with its nodes, materials and animations.
    #[arg(long)]
    pub flatten: bool,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input mesh (.obj, .ply, .gltf, .glb, .stl).
    pub input: PathBuf,
    /// Output picture (.png).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub pose: PoseFlags,
    /// Segments per coarse edge (the refinement pattern drawn for every triangle). With a
    /// tessellator --spacing a fractional level (e.g. 5.5), clamped to the spacing's range.
    #[arg(short, long, default_value_t = 16.0, value_parser = parse_level, allow_negative_numbers = true)]
    pub level: f64,
    /// How levels divide each edge: grid, or the GPU tessellator's equal / fractional-odd /
    /// fractional-even spacing.
    #[arg(long, value_parser = CoreName::<Spacing>::new(), default_value = "grid")]
    pub spacing: Spacing,
    #[command(flatten)]
    pub lod: LodArgs,
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Picture size, WIDTHxHEIGHT (of the whole picture with --compare: the panels share it).
    #[arg(long, default_value = "800x800", value_parser = parse_size)]
    pub size: (u32, u32),
    #[command(flatten)]
    pub view: ViewFlags,
    /// Colour the surface by this per-vertex field of the input (a PLY vertex property, a glTF
    /// `_NAME` attribute), with a colour bar and its range.
    #[arg(long, value_name = "NAME")]
    pub color_by: Option<String>,
    /// Colormap for --color-by: viridis or coolwarm.
    #[arg(long, default_value = "viridis", requires = "color_by")]
    pub colormap: String,
    /// Field values at the colormap's ends, MIN,MAX (default: the field's own range).
    #[arg(
        long,
        value_name = "MIN,MAX",
        value_parser = parse_range,
        allow_hyphen_values = true,
        requires = "color_by"
    )]
    pub range: Option<[f32; 2]>,
    /// Side-by-side labelled panels, one per scheme, e.g. `flat,pn,png1` (overrides --scheme).
    #[arg(long, value_parser = scheme_parser(), value_delimiter = ',')]
    pub compare: Vec<SchemeArg>,
    /// Displacement, as for `refine --displace`.
    #[arg(long, value_name = "SPEC")]
    pub displace: Option<String>,
    #[command(flatten)]
    pub tags: TagArgs,
    /// What draws the picture: `gpu` (wgpu, the instanced refinement pattern, Blinn-Phong) or
    /// `gl` (the OpenGL 4 hardware tessellator, coloured by normal; the grid is drawn with
    /// equal spacing).
    #[arg(long, value_enum, default_value = "gpu")]
    pub backend: RenderBackendArg,
}

/// How `render` and `view` look at the surface: the camera's orbit and the wireframe.
#[derive(Debug, Clone, Copy, Args)]
pub struct ViewFlags {
    /// Orbit the camera about the vertical axis, degrees.
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    pub yaw: f32,
    /// Camera elevation, degrees.
    #[arg(long, default_value_t = 20.0, allow_negative_numbers = true)]
    pub pitch: f32,
    /// 1 frames the whole mesh; larger values move closer.
    #[arg(long, default_value_t = 1.0)]
    pub zoom: f32,
    /// Overlay the refinement pattern's edges.
    #[arg(long)]
    pub wireframe: bool,
}

/// Who draws `tessella render`'s picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RenderBackendArg {
    /// wgpu: one instanced refinement pattern per coarse triangle (a software adapter when
    /// there is no GPU).
    Gpu,
    /// OpenGL 4 tessellation shaders through EGL (Mesa's llvmpipe without a GPU).
    Gl,
}

/// `animate --skinning`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SkinningArg {
    /// Pose on the CPU, build the nets there, upload them.
    Cpu,
    /// Skin and build the nets on the GPU from the frame's joint matrices.
    Gpu,
}

#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// Input mesh.
    pub input: PathBuf,
    /// Folder for the frames (frame_000.png, ...).
    #[arg(short, long)]
    pub output: PathBuf,
    #[arg(long, value_parser = scheme_parser(), default_value = "pn")]
    pub scheme: SchemeArg,
    #[arg(short, long, default_value_t = 16)]
    pub level: u32,
    /// Phong shape factor: 0 is flat, 1 the full projection.
    #[arg(long, default_value_t = 0.75, value_parser = parse_alpha, allow_hyphen_values = true)]
    pub alpha: f32,
    /// Number of frames.
    #[arg(long, default_value_t = 8)]
    pub frames: u32,
    /// Largest twist, degrees.
    #[arg(long, default_value_t = 60.0)]
    pub twist: f32,
    /// Instead of the twist: play this animation clip of the input (a glTF file's animation,
    /// by name or index) from its start, posed per frame (morph targets, skinning).
    #[arg(long, value_name = "NAME|INDEX", conflicts_with = "fly_in")]
    pub clip: Option<String>,
    /// With --clip: frames per second of the clip's time.
    #[arg(long, default_value_t = 24.0, requires = "clip")]
    pub fps: f32,
    /// With --clip: where each frame is posed and its control nets built. `gpu` uploads the
    /// frame's joint matrices (and morph weights) alone; it needs normals in the file and the
    /// flat, phong, pn or pn-aen scheme.
    #[arg(long, value_enum, default_value_t = SkinningArg::Cpu, requires = "clip")]
    pub skinning: SkinningArg,
    /// Instead of the twist: fly the camera towards the mesh (zoom 0.8 to 2.5) with levels from
    /// the screen (`--lod screen:PX` of each frame's camera) and fractional-odd spacing, so the
    /// levels grow smoothly frame by frame.
    #[arg(long)]
    pub fly_in: bool,
    /// With --fly-in: pixels per refined edge.
    #[arg(long, default_value_t = 8.0, requires = "fly_in")]
    pub pixels: f32,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "400x400", value_parser = parse_size)]
    pub size: (u32, u32),
}

#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Mesh file (.obj, .ply, .gltf, .glb, .stl); default: the first bundled sample.
    pub input: Option<PathBuf>,
    /// Segments per coarse edge; fractional with a tessellator --spacing (grid: geomorphed).
    #[arg(short, long, default_value_t = 8.0, allow_negative_numbers = true)]
    pub level: f64,
    /// How levels divide each edge: grid, equal, fractional-odd, fractional-even.
    #[arg(long, value_parser = CoreName::<Spacing>::new(), default_value = "grid")]
    pub spacing: Spacing,
    /// Per-edge levels from the current camera, every frame: `screen:PX`,
    /// `distance:NEAR,FAR,MAX` or `tolerance:D`.
    #[arg(long, value_name = "SPEC")]
    pub lod: Option<String>,
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Window size, WIDTHxHEIGHT (pixels).
    #[arg(long, default_value = "800x600", value_parser = parse_size)]
    pub size: (u32, u32),
    #[command(flatten)]
    pub view: ViewFlags,
    /// Side-by-side panels, one per scheme, e.g. `flat,pn,png1` (overrides --scheme).
    #[arg(long, value_parser = scheme_parser(), value_delimiter = ',')]
    pub compare: Vec<SchemeArg>,
    /// Displacement: `sine:AMP,FREQ` or `perlin:AMP,FREQ[,SEED]`.
    #[arg(long, value_name = "SPEC")]
    pub displace: Option<String>,
    /// Sidecar tags JSON, as for `refine --tags`.
    #[arg(long, value_name = "FILE")]
    pub tags: Option<PathBuf>,
    /// Deformation played over time: none, twist or bend.
    #[arg(long, default_value = "none")]
    pub animate: String,
    /// Play this animation clip of the input (a glTF file's, by name or index); it overrides
    /// --animate. Space plays and pauses, `,` and `.` step a frame back and forth.
    #[arg(long, value_name = "NAME|INDEX")]
    pub clip: Option<String>,
    /// With --clip: open paused at this many seconds into the clip.
    #[arg(
        long,
        value_name = "SECONDS",
        requires = "clip",
        allow_negative_numbers = true
    )]
    pub time: Option<f32>,
    /// Draw this many frames, then exit (with --screenshot: save the last one first).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Where screenshots go (`s`, or the last of --frames); default tessella-view-N.png.
    #[arg(long, value_name = "PNG")]
    pub screenshot: Option<PathBuf>,
}

/// Per-edge adaptive levels and the camera they are seen from (`refine` and `render`).
#[derive(Debug, Clone, Args)]
pub struct LodArgs {
    /// Per-edge adaptive levels (crack-free): `tolerance:D` (flat triangles within D of the
    /// curved surface), `screen:PX` (PX pixels per refined edge) or `distance:NEAR,FAR,MAX`
    /// (MAX segments near the camera, 1 beyond FAR). Screen and distance see from --camera:
    /// `refine` needs it (and --size for screen); `render` uses the picture's own camera and
    /// size unless --camera is given.
    #[arg(long, value_name = "SPEC")]
    pub lod: Option<String>,
    /// Camera for --lod screen/distance: EYE_X,EYE_Y,EYE_Z,TARGET_X,TARGET_Y,TARGET_Z,FOV_DEG
    /// (`render`'s default: the picture's camera from --yaw, --pitch, --zoom).
    #[arg(long, value_name = "EYE,TARGET,FOV", allow_hyphen_values = true)]
    pub camera: Option<String>,
}

/// Creases and shape tags, for `--scheme st` (all tags) and `--scheme png1` (sharp edges).
/// Hard edges in the file (one position, several normals) become creases on their own.
#[derive(Debug, Clone, Args)]
pub struct TagArgs {
    /// Sidecar JSON with per-edge sharpness and per-vertex tension/sharpness/bias/crease
    /// (format: `tessella_io::tags` docs and the README). PLY inputs may carry the same as
    /// vertex properties and an `edge` element.
    #[arg(long = "tags", value_name = "FILE")]
    pub file: Option<PathBuf>,
    /// Also crease every edge whose two faces bend by more than this many degrees.
    #[arg(long, value_name = "DEG")]
    pub crease_angle: Option<f32>,
}

#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Mesh file to inspect.
    pub input: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also compare the surface quality of every scheme: normal jump across coarse edges (the G1
    /// defect), gaps (watertightness), distance from the coarse mesh.
    #[arg(long)]
    pub quality: bool,
    /// Level whose pattern samples the distance from the coarse mesh (with --quality), and
    /// the level a glTF scene's primitives are shown with.
    #[arg(long, default_value_t = 8)]
    pub level: u32,
    /// glTF: show the level `refine --max-edge LENGTH` gives each primitive.
    #[arg(long, value_name = "LENGTH")]
    pub max_edge: Option<f32>,
    #[command(flatten)]
    pub tags: TagArgs,
}

#[derive(Debug, Args)]
pub struct PatternArgs {
    /// Segments per edge (grid: a whole number); with a tessellator spacing, the inner and all
    /// three outer levels.
    #[arg(short, long, allow_negative_numbers = true)]
    pub level: Option<f64>,
    /// grid, or the GPU tessellator's equal / fractional-odd / fractional-even spacing.
    #[arg(long, value_parser = CoreName::<Spacing>::new(), default_value = "grid")]
    pub spacing: Spacing,
    /// Tessellator inner level (overrides --level).
    #[arg(long, allow_negative_numbers = true)]
    pub inner: Option<f32>,
    /// Tessellator outer levels A,B,C in GL order: the edges l1 = 0, l2 = 0, l3 = 0 (overrides
    /// --level). An outer level <= 0 or NaN culls the patch: the pattern is empty.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "A,B,C"
    )]
    pub outer: Vec<f32>,
    /// Write to this file instead of standard output; a `.svg` name writes a drawing instead
    /// of JSON.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also draw the pattern into this SVG file.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct SamplesArgs {
    /// Folder to write the samples into (created if missing).
    #[arg(short, long, default_value = "samples")]
    pub output: PathBuf,
}

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Segments per coarse edge.
    #[arg(short, long, default_value_t = 8)]
    pub level: u32,
    /// Also write each refined sample here as OBJ.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Mesh to refine (default: the bundled 5120-triangle icosphere).
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Levels to measure, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [8u32, 16, 32, 64])]
    pub levels: Vec<u32>,
    /// Repetitions per measurement (the median is reported).
    #[arg(long, default_value_t = 15)]
    pub repeat: usize,
    /// Also measure the GPU: compute refinement against the CPU, the GMR Figure 7 experiment
    /// (static refined vertex buffer vs instanced pattern), and PN vs PNG1 frame time.
    #[arg(long)]
    pub gpu: bool,
    /// Also measure the OpenGL tessellator: quadratic ("fake") against real normals (time per
    /// vertex), and the hardware tessellator against the instanced pattern against the CPU at
    /// about equal triangle counts (ratios; absolute times only on a hardware GPU).
    #[arg(long)]
    pub gl: bool,
    /// Print the CPU measurements (bandwidth, one-shot, per frame, file writers) as one JSON
    /// object instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Measure the memory bandwidth only (fill, copy, fresh memory) and stop: what the peer
    /// script compares with numpy's own fill.
    #[arg(long)]
    pub bandwidth_only: bool,
}

/// Parses `800x600`.
/// Phong's shape factor: any finite number (NaN and infinities are refused here, whatever the
/// scheme, as the Python package refuses them).
pub fn parse_alpha(text: &str) -> Result<f32, String> {
    let alpha: f32 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if !alpha.is_finite() {
        return Err(format!(
            "alpha must be finite (usually within 0..=1), got {text}"
        ));
    }
    Ok(alpha)
}

/// `WIDTHxHEIGHT` (the core's `size` option).
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let [w, h] = tessella_core::refine::parse_size(text).map_err(|e| e.message)?;
    Ok((w, h))
}

/// `MIN,MAX` of `--range`: two finite numbers, `MIN < MAX`.
pub fn parse_range(text: &str) -> Result<[f32; 2], String> {
    let parsed: Option<Vec<f32>> = text.split(',').map(|x| x.trim().parse().ok()).collect();
    match parsed.as_deref() {
        Some(&[lo, hi]) if lo.is_finite() && hi.is_finite() && lo < hi => Ok([lo, hi]),
        _ => Err("give MIN,MAX, two finite numbers with MIN < MAX".into()),
    }
}

/// `512MiB`, `8GiB`, `1.5G`, `1000000` into bytes (the core's `max-memory` option).
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    tessella_core::refine::parse_bytes(text).map_err(|e| e.message)
}

/// One level for every edge (the core's `level` option): a finite number above 0.
pub fn parse_level(text: &str) -> Result<f64, String> {
    tessella_core::refine::parse_level(text).map_err(|e| e.message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_bytes("8GiB"), Ok(8 << 30));
        assert_eq!(parse_bytes("512 MiB"), Ok(512 << 20));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert!(parse_bytes("lots").is_err());
        assert!(parse_bytes("3 parsecs").is_err());
        assert_eq!(parse_size("640x480"), Ok((640, 480)));
        assert!(parse_size("640").is_err());
        assert!(parse_size("0x10").is_err());
    }
}
