//! Errors of the core crate. Each message says what was wrong and, where it can, how to fix it.

use thiserror::Error;

/// A mesh that cannot be refined as given.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    #[error("the mesh has no triangles")]
    NoTriangles,
    #[error("vertex {vertex} has a non-finite coordinate {value:?}; remove NaN/infinite positions before refining")]
    NonFinitePosition { vertex: usize, value: [f32; 3] },
    /// A coordinate so large that control points built from it overflow f32 (found by fuzzing
    /// `refine`: a finite 1.7e38 gave infinite refined positions).
    #[error("vertex {vertex} has a coordinate beyond ±{max:e} ({value:?}); scale the mesh down before refining")]
    PositionTooLarge {
        vertex: usize,
        value: [f32; 3],
        max: f32,
    },
    #[error("triangle {face} uses vertex {index}, but the mesh has only {count} vertices")]
    IndexOutOfRange {
        face: usize,
        index: u32,
        count: usize,
    },
    #[error(
        "triangle {face} uses vertex {index} twice ({indices:?}); remove degenerate triangles"
    )]
    RepeatedIndex {
        face: usize,
        index: u32,
        indices: [u32; 3],
    },
    #[error("triangle {face} has zero area (its corners are collinear or coincide); remove degenerate triangles")]
    ZeroArea { face: usize },
    #[error("{what} has {got} entries but the mesh has {expected} vertices")]
    AttributeCount {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("vertex {vertex} has a zero-length normal; fix the normal or drop all normals so they are recomputed")]
    ZeroNormal { vertex: usize },
    #[error("vertex {vertex} has a non-finite normal {value:?}; fix the normal or drop all normals so they are recomputed")]
    NonFiniteNormal { vertex: usize, value: [f32; 3] },
    #[error("vertex {vertex} has a non-finite texture coordinate {value:?}")]
    NonFiniteUv { vertex: usize, value: [f32; 2] },
    #[error("the mesh has {count} vertices; at most {max} fit 32-bit indices")]
    TooManyVertices { count: usize, max: usize },
    #[error(
        "{got} faces have mid-edge nodes but the mesh has {expected} faces; give one row per face"
    )]
    MidNodeCount { got: usize, expected: usize },
    #[error("second-order face {face}: {reason}")]
    BadMidNode { face: usize, reason: String },
    #[error("faces {} and {} share the edge {}-{} but not its mid-edge node: {detail}", faces[0], faces[1], edge[0], edge[1])]
    MidNodeMismatch {
        faces: [usize; 2],
        edge: [u32; 2],
        detail: String,
    },
    #[error("second-order face {face} is inverted or folded: its Jacobian does not point along its corner triangle's normal at barycentric {at:?}; check the mid-edge nodes' order (edges 0-1, 1-2, 2-0) and positions")]
    InvertedElement { face: usize, at: [f32; 3] },
}

/// Refinement options or sizes that cannot be honoured.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RefineError {
    #[error("level 0 is not a refinement; the level is the number of segments per coarse edge, 1 or more")]
    LevelZero,
    #[error("bad levels: {0}")]
    BadLevels(String),
    #[error(
        "level {level} on {faces} triangles would make {vertices} vertices and {triangles} triangles, \
         about {bytes_human} of memory, over the limit of {limit_human}; choose a lower level \
         or raise the limit"
    )]
    TooLarge {
        level: u32,
        faces: usize,
        vertices: u64,
        triangles: u64,
        bytes: u64,
        bytes_human: String,
        limit: u64,
        limit_human: String,
    },
    #[error("level {level} would make {vertices} output vertices, more than 32-bit indices can address (4294967295); choose a lower level")]
    IndexOverflow { level: u32, vertices: u64 },
    #[error(
        "Phong shape factor alpha must be finite and within -16..=16 (usually 0..=1), got {0}"
    )]
    BadAlpha(f32),
    #[error("bad vertex format: {0}")]
    BadVertexFormat(String),
    #[error("the output's {what} hold {got} entries, the refined mesh needs {need}")]
    OutputTooSmall {
        what: String,
        got: usize,
        need: usize,
    },
    #[error("texture coordinates were asked for, but the mesh has none")]
    NoUvs,
    #[error("this frame was made by another plan; make frames with the plan that evaluates them")]
    ForeignFrame,
    #[error("the mesh does not have the plan's topology ({reason}); make a new plan for it")]
    TopologyMismatch { reason: String },
    #[error("the refined mesh has {vertices} vertices, more than {index_bits}-bit indices can address; use 32-bit indices")]
    IndicesTooNarrow { vertices: u64, index_bits: u32 },
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Tags(#[from] TagError),
}

/// Bad tags: what is wrong and how to fix it.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum TagError {
    #[error("{what} names vertex {vertex}, but the mesh has only {count} vertices; use indices of the mesh the tags were made for")]
    UnknownVertex {
        what: String,
        vertex: u32,
        count: usize,
    },
    #[error("{what} is {value} ; tags must be finite numbers")]
    NotFinite { what: String, value: f32 },
    #[error("{what} is {value}, outside {range}")]
    OutOfRange {
        what: String,
        value: f32,
        range: &'static str,
    },
    #[error(
        "edge tag on vertices {a} and {b}, but no triangle has that edge; tag edges of the mesh"
    )]
    NotAnEdge { a: u32, b: u32 },
    #[error("edge tag on vertices {a} and {b}, a boundary or non-manifold edge: a crease needs exactly two faces; remove the tag")]
    BoundaryEdge { a: u32, b: u32 },
    #[error("vertex {vertex} has {count} creased edges: the scalar-tagged scheme allows one crease (two creased edges) through a vertex; remove some edge tags or use PNG1 / PN-AEN")]
    TooManyCreases { vertex: u32, count: usize },
    #[error("triangle {face} has {count} vertices with a crease direction; the scalar-tagged scheme allows at most 2 per triangle")]
    TooManyCreasedVertices { face: usize, count: usize },
    #[error("crease angle must be a finite number of degrees in 0..=180, got {0}")]
    BadAngle(f32),
}

/// Formats a byte count for messages: `1.5 GiB`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}
