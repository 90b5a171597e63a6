//! The data of an animated mesh, as glTF 2.0 defines it. Plain data: public fields, no
//! behaviour beyond what reads them; [`Poser::new`](super::Poser::new) checks it once.

/// A node's transform relative to its parent (glTF `node.matrix` or `translation`, `rotation`,
/// `scale`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    /// Translation, then rotation (a unit quaternion `[x, y, z, w]`), then scale: the node's
    /// matrix is `T · R · S`.
    Trs {
        translation: [f32; 3],
        rotation: [f32; 4],
        scale: [f32; 3],
    },
    /// A column-major 4×4 matrix. glTF forbids animating such a node.
    Matrix([f32; 16]),
}

impl Default for Transform {
    fn default() -> Transform {
        Transform::Trs {
            translation: [0.0; 3],
            rotation: [0.0, 0.0, 0.0, 1.0],
            scale: [1.0; 3],
        }
    }
}

/// A node of the scene graph.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Node {
    pub name: Option<String>,
    /// The parent node's index; `None` for a root.
    pub parent: Option<u32>,
    pub transform: Transform,
    /// The node's morph target weights (glTF `node.weights`), which override its mesh's
    /// default weights; a `weights` channel animates them.
    pub weights: Option<Vec<f32>>,
}

/// A skin: the joints (node indices) and their inverse bind matrices (column-major; the
/// identity where the file gives none).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Skin {
    pub name: Option<String>,
    pub joints: Vec<u32>,
    pub inverse_binds: Vec<[f32; 16]>,
    /// glTF `skin.skeleton`: informative only (posing does not need it).
    pub skeleton: Option<u32>,
}

/// One morph target of a mesh instance: displacements added to its positions and normals.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MorphTarget {
    pub positions: Vec<[f32; 3]>,
    pub normals: Option<Vec<[f32; 3]>>,
}

/// One set of four joint influences per vertex (glTF `JOINTS_n` / `WEIGHTS_n`): joint indices
/// into the instance's skin's `joints`, and their weights (normalised integers already turned
/// into floats).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Influences {
    pub joints: Vec<[u16; 4]>,
    pub weights: Vec<[f32; 4]>,
}

/// One mesh drawn by one node: its vertices are `first_vertex..first_vertex + positions.len()`
/// of the animated mesh, in the mesh's own space (before any node transform).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Instance {
    /// The node that draws the mesh.
    pub node: u32,
    /// The node's skin; `None` for a mesh moved by its node's world transform alone.
    pub skin: Option<u32>,
    pub first_vertex: u32,
    pub positions: Vec<[f32; 3]>,
    /// `None` where the file gives no normals: the posed mesh then has its normals computed by
    /// the core from the posed positions.
    pub normals: Option<Vec<[f32; 3]>>,
    pub targets: Vec<MorphTarget>,
    /// The mesh's default morph weights (glTF `mesh.weights`; zeros where absent).
    pub default_weights: Vec<f32>,
    /// `JOINTS_0`/`WEIGHTS_0`, then `_1`, ...: empty without a skin.
    pub influences: Vec<Influences>,
}

/// How a sampler interpolates between its keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolation {
    /// Linear; rotations by spherical linear interpolation (slerp).
    Linear,
    /// The previous key's value until the next key.
    Step,
    /// Cubic Hermite spline: each key holds an in-tangent, a value and an out-tangent.
    CubicSpline,
}

/// What a channel animates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
    /// The node's morph target weights.
    Weights,
}

/// Keyframes: `times` in seconds, increasing; `values` flattened, per key the property's
/// components (3, 4 for a rotation, the target count for weights), three times that for
/// [`Interpolation::CubicSpline`] (in-tangent, value, out-tangent).
#[derive(Debug, Clone, PartialEq)]
pub struct Sampler {
    pub interpolation: Interpolation,
    pub times: Vec<f32>,
    pub values: Vec<f32>,
}

/// One animated property of one node.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    pub node: u32,
    pub property: Property,
    pub sampler: Sampler,
}

/// A named animation (glTF `animation`): channels played together.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Clip {
    pub name: String,
    pub channels: Vec<Channel>,
}

/// A mesh whose vertices move with a scene graph, skins, morph targets and clips. Its
/// triangles never change; each pose gives new positions and normals for the same vertices.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AnimatedMesh {
    /// Triangles over every instance's vertices (the instances' ranges one after the other).
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates of every vertex, if every instance has them.
    pub uvs: Option<Vec<[f32; 2]>>,
    pub nodes: Vec<Node>,
    pub skins: Vec<Skin>,
    pub instances: Vec<Instance>,
    pub clips: Vec<Clip>,
}
