//! What Bevy's glTF loader does not keep and tessella needs, read by a glTF extension handler
//! while Bevy loads a file and put on each mesh entity:
//! - joint influence sets past the first (`JOINTS_1`/`WEIGHTS_1`, ...), which Bevy does not
//!   read (it skins with four influences a vertex). glTF 2.0 allows any number of sets;
//!   tessella's skinning blends them all, as `tessella refine --clip` does. They become
//!   [`ExtraInfluences`], which the plugin's posing adds to Bevy's first set.
//! - whether the file had normals. Bevy invents flat ones for a primitive without (splitting
//!   every vertex), which would refine faceted; [`InventedNormals`] has the plugin compute
//!   smooth ones instead, as glTF asks and as the CLI and three.js do.

use bevy::asset::LoadContext;
use bevy::ecs::world::EntityWorldMut;
use bevy::gltf::extensions::{ErasedGltfExtensionHandler, GltfExtensionHandler};
use bevy::gltf::gltf;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use tessella_core::animation::Influences;

/// A mesh entity's joint influence sets after the first: per set, four joint indices and four
/// weights a vertex.
#[derive(Component, Reflect, Clone, Debug, Default, PartialEq)]
#[reflect(Component, Default, Clone)]
pub struct ExtraInfluences {
    /// Per set, per vertex, four indices into the skin's joints.
    pub joints: Vec<Vec<[u16; 4]>>,
    /// Per set, per vertex, the four joints' weights.
    pub weights: Vec<Vec<[f32; 4]>>,
}

impl ExtraInfluences {
    /// The sets as tessella's [`Influences`].
    pub fn sets(&self) -> Vec<Influences> {
        self.joints
            .iter()
            .zip(&self.weights)
            .map(|(j, w)| Influences {
                joints: j.clone(),
                weights: w.clone(),
            })
            .collect()
    }
}

/// On a mesh entity whose normals are not the author's (Bevy's glTF loader made them flat for
/// a primitive without `NORMAL`): the plugin ignores them and refines with tessella's computed
/// normals, smooth across vertices that share a position (glTF: "client implementations
/// should calculate flat normals"; a curved surface is what the user asked for by adding
/// `Tessellate`). Add it to a mesh of your own to get the same.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[reflect(Component, Default, Clone)]
pub struct InventedNormals;

/// Reads the extra sets of every primitive, and which have no normals, while a file loads
/// (keyed by mesh and primitive index), then hands each spawned mesh entity its primitive's.
#[derive(Default, Clone)]
pub(crate) struct GltfExtrasReader {
    found: HashMap<(usize, usize), ExtraInfluences>,
    without_normals: bevy::platform::collections::HashSet<(usize, usize)>,
}

/// Sets `JOINTS_n`/`WEIGHTS_n` for n = 1, 2, ... until one is missing.
fn read_extra(primitive: &gltf::Primitive, buffers: &[Vec<u8>]) -> ExtraInfluences {
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| d.as_slice()));
    let mut extra = ExtraInfluences::default();
    for set in 1.. {
        let (Some(joints), Some(weights)) = (reader.read_joints(set), reader.read_weights(set))
        else {
            break;
        };
        extra.joints.push(joints.into_u16().collect());
        extra.weights.push(weights.into_f32().collect());
    }
    extra
}

impl GltfExtensionHandler for GltfExtrasReader {
    fn dyn_clone(&self) -> Box<dyn ErasedGltfExtensionHandler> {
        Box::new(self.clone())
    }

    #[allow(clippy::too_many_arguments)]
    fn on_gltf_primitive(
        &mut self,
        _load_context: &mut LoadContext<'_>,
        _gltf_document: &gltf::Gltf,
        gltf_mesh: &gltf::Mesh,
        gltf_primitive: &gltf::Primitive,
        buffer_data: &[Vec<u8>],
        _custom_vertex_attributes: &HashMap<Box<str>, bevy::mesh::MeshVertexAttribute>,
        _on_skinned_nodes: bool,
        _on_non_skinned_nodes: bool,
        _user_mesh: &mut Option<Mesh>,
    ) -> impl bevy::tasks::ConditionalSendFuture<Output = ()> {
        let key = (gltf_mesh.index(), gltf_primitive.index());
        let extra = read_extra(gltf_primitive, buffer_data);
        if !extra.joints.is_empty() {
            self.found.insert(key, extra);
        }
        if gltf_primitive.get(&gltf::Semantic::Normals).is_none() {
            self.without_normals.insert(key);
        }
        async {}
    }

    fn on_spawn_mesh_and_material(
        &mut self,
        _load_context: &mut LoadContext<'_>,
        primitive: &gltf::Primitive,
        mesh: &gltf::Mesh,
        _material: &gltf::Material,
        entity: &mut EntityWorldMut,
        _material_label: &str,
    ) {
        let key = (mesh.index(), primitive.index());
        if let Some(extra) = self.found.get(&key) {
            entity.insert(extra.clone());
        }
        if self.without_normals.contains(&key) {
            entity.insert(InventedNormals);
        }
    }
}

/// Adds the reader to Bevy's glTF loader (when the app has one).
pub(crate) fn register(app: &mut App) {
    app.register_type::<ExtraInfluences>()
        .register_type::<InventedNormals>();
    let Some(handlers) = app
        .world()
        .get_resource::<bevy::gltf::extensions::GltfExtensionHandlers>()
    else {
        return;
    };
    match handlers.0.try_write() {
        Some(mut list) => list.push(Box::new(GltfExtrasReader::default())),
        None => error!("cannot add tessella's glTF reader: the handler list is busy"),
    }
}
