//! The data of an animated mesh, as glTF 2.0 defines it. Plain data: public fields, no
//! behaviour beyond what reads them; [`Poser::new`](super::Poser::new) checks it once.

/// A node's transform relative to its parent (glTF `node.matrix` or `translation`, `rotation`,
/// `scale`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    /// Translation, then rotation (a unit quaternion `[x, y, z, w]`), then scale: the node's
    /// matrix is `T · R · S`.
    Trs {
        /// The translation.
        translation: [f32; 3],
        /// The rotation, a unit quaternion `[x, y, z, w]`.
        rotation: [f32; 4],
        /// The scale along each axis.
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
    /// The node's name (glTF `node.name`), for messages and lookups.
    pub name: Option<String>,
    /// The parent node's index; `None` for a root.
    pub parent: Option<u32>,
    /// The node's local transform.
    pub transform: Transform,
    /// The node's morph target weights (glTF `node.weights`), which override its mesh's
    /// default weights; a `weights` channel animates them.
    pub weights: Option<Vec<f32>>,
}

/// A skin: the joints (node indices) and their inverse bind matrices (column-major; the
/// identity where the file gives none).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Skin {
    /// The skin's name (glTF `skin.name`).
    pub name: Option<String>,
    /// The joints: node indices, in the order the influences' joint indices refer to.
    pub joints: Vec<u32>,
    /// One inverse bind matrix per joint (column-major), taking mesh space to the joint's space at bind time.
    pub inverse_binds: Vec<[f32; 16]>,
    /// glTF `skin.skeleton`: informative only (posing does not need it).
    pub skeleton: Option<u32>,
}

/// One morph target of a mesh instance: displacements added to its positions and normals.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MorphTarget {
    /// Position displacements, one per vertex of the instance.
    pub positions: Vec<[f32; 3]>,
    /// Normal displacements, one per vertex, or `None` where the target leaves normals alone.
    pub normals: Option<Vec<[f32; 3]>>,
}

/// One set of four joint influences per vertex (glTF `JOINTS_n` / `WEIGHTS_n`): joint indices
/// into the instance's skin's `joints`, and their weights (normalised integers already turned
/// into floats).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Influences {
    /// Per vertex, four indices into the skin's `joints`.
    pub joints: Vec<[u16; 4]>,
    /// Per vertex, the four joints' weights (not negative; divided by their sum over all sets when posing).
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
    /// The instance's first vertex in the animated mesh: the previous instances' vertex count.
    pub first_vertex: u32,
    /// The vertex positions in the mesh's own space.
    pub positions: Vec<[f32; 3]>,
    /// `None` where the file gives no normals: the posed mesh then has its normals computed by
    /// the core from the posed positions.
    pub normals: Option<Vec<[f32; 3]>>,
    /// The morph targets, each with one displacement per vertex.
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
#[non_exhaustive]
pub enum Property {
    /// The node's translation (3 components).
    Translation,
    /// The node's rotation (4 components, a quaternion `[x, y, z, w]`).
    Rotation,
    /// The node's scale (3 components).
    Scale,
    /// The node's morph target weights.
    Weights,
}

/// Keyframes: `times` in seconds, increasing; `values` flattened, per key the property's
/// components (3, 4 for a rotation, the target count for weights), three times that for
/// [`Interpolation::CubicSpline`] (in-tangent, value, out-tangent).
#[derive(Debug, Clone, PartialEq)]
pub struct Sampler {
    /// How values between keys are found.
    pub interpolation: Interpolation,
    /// Key times in seconds, finite and strictly increasing.
    pub times: Vec<f32>,
    /// The keys' values, flattened (see [`Sampler`]).
    pub values: Vec<f32>,
}

/// One animated property of one node.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// The animated node's index.
    pub node: u32,
    /// The animated property.
    pub property: Property,
    /// The keyframes.
    pub sampler: Sampler,
}

/// A named animation (glTF `animation`): channels played together.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Clip {
    /// The clip's name (glTF `animation.name`; may be empty).
    pub name: String,
    /// The animated properties.
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
    /// The scene graph's nodes.
    pub nodes: Vec<Node>,
    /// The skins.
    pub skins: Vec<Skin>,
    /// The mesh instances, their vertices one after the other.
    pub instances: Vec<Instance>,
    /// The clips.
    pub clips: Vec<Clip>,
}
