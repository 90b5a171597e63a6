//! One-shot refinement (`refine`) and the arrays it returns.

use crate::{arrays, errors, options::Options};
use tessella_core::{Mesh, Refiner};
use wasm_bindgen::prelude::*;

/// A mesh as flat arrays: positions and normals (3 per vertex), uvs (2 per vertex, when the
/// input had them), indices (3 per triangle). JS takes each array once (a copy into JS memory;
/// the wasm side is freed).
#[wasm_bindgen]
#[derive(Debug, Default)]
pub struct Arrays {
    positions: Vec<f32>,
    normals: Vec<f32>,
    uvs: Option<Vec<f32>>,
    indices: Vec<u32>,
    normals_computed: bool,
    /// Per refined vertex: its coarse face ([`u32::MAX`] for a vertex no face uses) and
    /// barycentric coordinates in it, when asked for.
    origin: Option<(Vec<u32>, Vec<f32>)>,
}

#[wasm_bindgen]
impl Arrays {
    #[wasm_bindgen(js_name = takePositions)]
    pub fn take_positions(&mut self) -> Vec<f32> {
        std::mem::take(&mut self.positions)
    }
    #[wasm_bindgen(js_name = takeNormals)]
    pub fn take_normals(&mut self) -> Vec<f32> {
        std::mem::take(&mut self.normals)
    }
    #[wasm_bindgen(js_name = takeUvs)]
    pub fn take_uvs(&mut self) -> Option<Vec<f32>> {
        self.uvs.take()
    }
    #[wasm_bindgen(js_name = takeIndices)]
    pub fn take_indices(&mut self) -> Vec<u32> {
        std::mem::take(&mut self.indices)
    }
    /// The coarse face of each refined vertex (when `origin` was asked for).
    #[wasm_bindgen(js_name = takeFaces)]
    pub fn take_faces(&mut self) -> Option<Vec<u32>> {
        self.origin.as_mut().map(|o| std::mem::take(&mut o.0))
    }
    /// The barycentric coordinates of each refined vertex in its face, 3 per vertex.
    #[wasm_bindgen(js_name = takeBarycentric)]
    pub fn take_barycentric(&mut self) -> Option<Vec<f32>> {
        self.origin.as_mut().map(|o| std::mem::take(&mut o.1))
    }
    /// Whether the normals were computed (the input had none).
    #[wasm_bindgen(getter, js_name = normalsComputed)]
    pub fn normals_computed(&self) -> bool {
        self.normals_computed
    }
}

impl Arrays {
    /// Moves the arrays out of a refined mesh (no copy).
    pub fn from_refined(out: tessella_core::RefinedMesh) -> Arrays {
        Arrays {
            positions: bytemuck::allocation::cast_vec(out.positions),
            normals: bytemuck::allocation::cast_vec(out.normals),
            uvs: out.uvs.map(bytemuck::allocation::cast_vec),
            indices: bytemuck::allocation::cast_vec(out.triangles),
            normals_computed: false,
            origin: None,
        }
    }
    /// Copies a coarse mesh's arrays.
    /// Positions and normals alone (a pose: the indices never change).
    pub fn points(positions: Vec<f32>, normals: Vec<f32>) -> Arrays {
        Arrays {
            positions,
            normals,
            ..Arrays::default()
        }
    }

    pub fn from_mesh(mesh: &Mesh) -> Arrays {
        Arrays {
            positions: arrays::flat(mesh.positions()).to_vec(),
            normals: arrays::flat(mesh.normals()).to_vec(),
            uvs: mesh.uvs().map(|u| arrays::flat(u).to_vec()),
            indices: bytemuck::cast_slice(mesh.triangles()).to_vec(),
            normals_computed: mesh.normals_computed(),
            origin: None,
        }
    }
}

/// Builds and validates a mesh from flat arrays (the core's checks and messages).
pub fn mesh(
    positions: &[f32],
    indices: &[u32],
    normals: Option<&[f32]>,
    uvs: Option<&[f32]>,
) -> Result<Mesh, String> {
    let positions = arrays::points(positions, "positions")?;
    let normals = normals.map(|n| arrays::points(n, "normals")).transpose()?;
    let uvs = uvs.map(arrays::uvs).transpose()?;
    let triangles = arrays::triangles(indices)?;
    Mesh::new(positions, normals, uvs, triangles).map_err(|e| errors::message(&e))
}

/// Refines a mesh given as flat arrays with options given as JSON (see [`Options`]).
pub fn refine_arrays(
    positions: &[f32],
    indices: &[u32],
    normals: Option<&[f32]>,
    uvs: Option<&[f32]>,
    options: &str,
) -> Result<Arrays, String> {
    let Options {
        refine: options,
        origin,
    } = Options::from_json(options)?;
    let mesh = mesh(positions, indices, normals, uvs)?;
    let refiner = Refiner::new(&mesh, &options).map_err(|e| errors::message(&e))?;
    let mut out = Arrays::from_refined(refiner.refine());
    if origin {
        let (faces, bary) = refiner.plan().origin();
        out.origin = Some((faces, bytemuck::allocation::cast_vec(bary)));
    }
    Ok(out)
}

/// `refine` for JS: see `js/src/index.js`.
#[wasm_bindgen(js_name = refine)]
pub fn refine_js(
    positions: &[f32],
    indices: &[u32],
    normals: Option<Vec<f32>>,
    uvs: Option<Vec<f32>>,
    options: &str,
) -> Result<Arrays, JsError> {
    refine_arrays(
        positions,
        indices,
        normals.as_deref(),
        uvs.as_deref(),
        options,
    )
    .map_err(errors::text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessella_core::{RefineOptions, Scheme};

    #[test]
    fn flat_arrays_refine_to_the_core_bits() {
        let m = tessella_core::samples::icosphere(1);
        let positions = arrays::flat(m.positions());
        let normals = arrays::flat(m.normals());
        let indices: &[u32] = bytemuck::cast_slice(m.triangles());
        let mut got = refine_arrays(
            positions,
            indices,
            Some(normals),
            None,
            r#"{"scheme":"png1","level":5}"#,
        )
        .unwrap();
        let want = tessella_core::refine(&m, &RefineOptions::new(Scheme::Png1, 5)).unwrap();
        assert_eq!(got.take_positions(), arrays::flat(&want.positions));
        assert_eq!(got.take_normals(), arrays::flat(&want.normals));
        assert_eq!(
            got.take_indices(),
            bytemuck::cast_slice::<_, u32>(&want.triangles)
        );
    }

    #[test]
    fn bad_meshes_get_the_cores_messages() {
        let p = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let err = refine_arrays(&p, &[0, 1, 3], None, None, "{}").unwrap_err();
        assert!(
            err.contains("uses vertex 3, but the mesh has only 3"),
            "{err}"
        );
        let mut nan = p;
        nan[4] = f32::NAN;
        let err = refine_arrays(&nan, &[0, 1, 2], None, None, "{}").unwrap_err();
        assert!(err.contains("non-finite coordinate"), "{err}");
        let err = refine_arrays(&p, &[0, 1, 2], None, None, r#"{"level":100000}"#).unwrap_err();
        assert!(err.contains("over the limit"), "{err}");
    }
}
