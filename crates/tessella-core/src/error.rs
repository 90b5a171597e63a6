//! Errors of the core crate. Each message says what was wrong and, where it can, how to fix it.

use thiserror::Error;

/// A mesh that cannot be refined as given.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    #[error("the mesh has no triangles")]
    NoTriangles,
    #[error("vertex {vertex} has a non-finite coordinate {value:?}; remove NaN/infinite positions before refining")]
    NonFinitePosition { vertex: usize, value: [f32; 3] },
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
}

/// Refinement options or sizes that cannot be honoured.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RefineError {
    #[error("level 0 is not a refinement; the level is the number of segments per coarse edge, 1 or more")]
    LevelZero,
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
    #[error("Phong shape factor alpha must be finite (usually within 0..=1), got {0}")]
    BadAlpha(f32),
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Tags(#[from] crate::tags::TagError),
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
