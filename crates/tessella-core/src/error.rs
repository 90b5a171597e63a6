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

/// An animated mesh that cannot be posed as given, or a pose that cannot be made: each message
/// names the clip, channel, skin, instance, node or vertex at fault.
///
/// Clips are named by index and name (`clip 0 "walk"`); channels, skins, instances, nodes and
/// vertices by index (a vertex's index is within its instance).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum AnimationError {
    #[error("node {node}'s parent is node {parent}, but there are only {nodes} nodes")]
    ParentOutOfRange {
        node: usize,
        parent: u32,
        nodes: usize,
    },
    #[error(
        "node {node} is its own ancestor (a cycle in the parents); the nodes must form a tree"
    )]
    ParentCycle { node: usize },
    #[error("node {node} has a non-finite {what}; transforms must be finite numbers")]
    NonFiniteTransform { node: usize, what: &'static str },
    #[error("skin {skin} names node {node} as joint {joint}, but there are only {nodes} nodes")]
    JointNodeOutOfRange {
        skin: usize,
        joint: usize,
        node: u32,
        nodes: usize,
    },
    #[error("skin {skin} has {got} inverse bind matrices for {expected} joints; give one per joint (the identity where there is none)")]
    InverseBindCount {
        skin: usize,
        got: usize,
        expected: usize,
    },
    #[error("skin {skin}'s inverse bind matrix of joint {joint} is {reason}; it must be a finite invertible matrix")]
    BadInverseBind {
        skin: usize,
        joint: usize,
        reason: &'static str,
    },
    #[error("instance {instance} is drawn by node {node}, but there are only {nodes} nodes")]
    InstanceNodeOutOfRange {
        instance: usize,
        node: u32,
        nodes: usize,
    },
    #[error("instance {instance} uses skin {skin}, but there are only {skins} skins")]
    SkinOutOfRange {
        instance: usize,
        skin: u32,
        skins: usize,
    },
    #[error("instance {instance} starts at vertex {first_vertex}, but the instances before it end at vertex {expected}; instances' vertices follow one another from 0")]
    InstanceRange {
        instance: usize,
        first_vertex: u32,
        expected: usize,
    },
    #[error("instance {instance}'s {what} has {got} entries for its {expected} positions")]
    AttributeLength {
        instance: usize,
        what: String,
        got: usize,
        expected: usize,
    },
    #[error("{what} has {got} weights, but {expected} morph targets")]
    WeightCount {
        what: String,
        got: usize,
        expected: usize,
    },
    #[error("instances {first} and {second} are both drawn by node {node} but have {counts:?} morph targets; the primitives of one mesh share their target count")]
    TargetCountMismatch {
        node: usize,
        first: usize,
        second: usize,
        counts: [usize; 2],
    },
    #[error("instance {instance}'s {what} of vertex {vertex} is not finite")]
    NonFiniteAttribute {
        instance: usize,
        what: String,
        vertex: usize,
    },
    #[error("instance {instance} has skin {skin} but no joint influences (JOINTS_0/WEIGHTS_0)")]
    NoInfluences { instance: usize, skin: u32 },
    #[error("instance {instance}, vertex {vertex}: influence set {set} names joint {joint}, but skin {skin} has only {joints} joints")]
    JointOutOfRange {
        instance: usize,
        vertex: usize,
        set: usize,
        joint: u16,
        skin: u32,
        joints: usize,
    },
    #[error("instance {instance}, vertex {vertex}: influence set {set} has weight {value}; weights must be finite and not negative")]
    BadWeight {
        instance: usize,
        vertex: usize,
        set: usize,
        value: f32,
    },
    #[error("instance {instance}, vertex {vertex}: all its joint weights are zero; a skinned vertex needs some weight")]
    ZeroWeights { instance: usize, vertex: usize },
    #[error("the texture coordinates hold {got} entries for {expected} vertices")]
    UvCount { got: usize, expected: usize },
    #[error("triangle {face} uses vertex {index}, but the instances have only {count} vertices")]
    TriangleIndex {
        face: usize,
        index: u32,
        count: usize,
    },
    #[error("clip {clip} {clip_name:?} channel {channel} animates node {node}, but there are only {nodes} nodes")]
    ChannelNode {
        clip: usize,
        clip_name: String,
        channel: usize,
        node: u32,
        nodes: usize,
    },
    #[error("clip {clip} {clip_name:?} channel {channel} animates the {property} of node {node}, which has a matrix; glTF allows only nodes with translation/rotation/scale to be animated")]
    ChannelOnMatrix {
        clip: usize,
        clip_name: String,
        channel: usize,
        node: usize,
        property: &'static str,
    },
    #[error("clip {clip} {clip_name:?} channel {channel} animates the morph weights of node {node}, which draws no mesh")]
    WeightsWithoutMesh {
        clip: usize,
        clip_name: String,
        channel: usize,
        node: usize,
    },
    #[error("clip {clip} {clip_name:?} channel {channel}'s sampler has no keys")]
    NoKeys {
        clip: usize,
        clip_name: String,
        channel: usize,
    },
    #[error("clip {clip} {clip_name:?} channel {channel}: key time {key} ({time}) is {reason}; key times must be finite and strictly increasing")]
    BadKeyTime {
        clip: usize,
        clip_name: String,
        channel: usize,
        key: usize,
        time: f32,
        reason: &'static str,
    },
    #[error("clip {clip} {clip_name:?} channel {channel} has {got} values for {keys} keys of {components} components{cubic}; expected {expected}", cubic = if *cubic { " (×3 for CUBICSPLINE)" } else { "" })]
    ValueCount {
        clip: usize,
        clip_name: String,
        channel: usize,
        got: usize,
        keys: usize,
        components: usize,
        cubic: bool,
        expected: usize,
    },
    #[error("clip {clip} {clip_name:?} channel {channel}: value {index} is not finite")]
    NonFiniteValue {
        clip: usize,
        clip_name: String,
        channel: usize,
        index: usize,
    },
    #[error("no clip {clip:?}: give a clip's name or an index below {count} (clips: {names})")]
    UnknownClip {
        clip: String,
        count: usize,
        names: String,
    },
    #[error("the time {0} is not a finite number of seconds")]
    BadTime(f32),
    #[error("the {what} buffer holds {got} entries; the animated mesh has {expected} vertices")]
    BufferLength {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error(
        "{got} {what} were given; the animated mesh takes {expected} (see Poser::deform_into)"
    )]
    DeformCount {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("{what} {index} is not finite")]
    NonFiniteDeform { what: &'static str, index: usize },
    #[error("normals were asked for, but some instance has none; pass no normal buffer and let the core compute them (see Poser::has_normals)")]
    NoNormals,
    #[error("the posed mesh: {0}")]
    Mesh(#[from] MeshError),
}
