//! `Refiner`: one plan for a deforming mesh, refined every frame into the same output arrays.
//!
//! The JS side writes each frame's positions (and normals) into input arrays this object owns
//! (views over wasm memory), calls [`Refiner::frame`], and reads the outputs through views
//! over wasm memory too: after the first frame nothing is allocated (but the normals recomputed
//! when none are given, as the core's `Plan::update` does).

use crate::{arrays, errors, options::Options, refine};
use tessella_core::refine::{Frame, Plan, VertexOutput};
use tessella_core::RefineOptions;
use wasm_bindgen::prelude::*;

/// What is built on the first frame: the plan (topology by the first positions), its frame and
/// the outputs.
struct Built {
    plan: Plan,
    /// Owns the first frame's mesh, which it moves every frame.
    frame: Frame<'static>,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Option<Vec<[f32; 2]>>,
    indices: Vec<u32>,
}

#[wasm_bindgen]
pub struct Refiner {
    triangles: Vec<u32>,
    uvs: Option<Vec<f32>>,
    options: RefineOptions,
    inputs: arrays::FrameInputs,
    built: Option<Built>,
}

crate::arrays::frame_input_exports!(Refiner);

#[wasm_bindgen]
impl Refiner {
    /// Checks the options now; the mesh is checked on the first frame.
    #[wasm_bindgen(constructor)]
    pub fn new(indices: &[u32], uvs: Option<Vec<f32>>, options: &str) -> Result<Refiner, JsError> {
        Refiner::with(indices, uvs, options).map_err(errors::text)
    }

    #[wasm_bindgen(js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.built.as_ref().map_or(0, |b| b.positions.len())
    }
    #[wasm_bindgen(js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.built.as_ref().map_or(0, |b| b.indices.len() / 3)
    }
    #[wasm_bindgen(js_name = hasUvs)]
    pub fn has_uvs(&self) -> bool {
        self.built.as_ref().is_some_and(|b| b.uvs.is_some())
    }
    /// Addresses of the outputs in wasm memory (null before the first frame).
    #[wasm_bindgen(js_name = positionsOutput)]
    pub fn positions_output(&self) -> *const f32 {
        self.built
            .as_ref()
            .map_or(std::ptr::null(), |b| b.positions.as_ptr().cast())
    }
    #[wasm_bindgen(js_name = normalsOutput)]
    pub fn normals_output(&self) -> *const f32 {
        self.built
            .as_ref()
            .map_or(std::ptr::null(), |b| b.normals.as_ptr().cast())
    }
    #[wasm_bindgen(js_name = uvsOutput)]
    pub fn uvs_output(&self) -> *const f32 {
        match self.built.as_ref().and_then(|b| b.uvs.as_ref()) {
            Some(uvs) => uvs.as_ptr().cast(),
            None => std::ptr::null(),
        }
    }
    #[wasm_bindgen(js_name = indicesOutput)]
    pub fn indices_output(&self) -> *const u32 {
        self.built
            .as_ref()
            .map_or(std::ptr::null(), |b| b.indices.as_ptr())
    }
}

impl Refiner {
    /// [`Refiner::new`] with a `String` error.
    pub fn with(indices: &[u32], uvs: Option<Vec<f32>>, options: &str) -> Result<Refiner, String> {
        let options = Options::from_json(options)?.refine;
        arrays::triangles(indices)?;
        Ok(Refiner {
            triangles: indices.to_vec(),
            uvs,
            options,
            inputs: Default::default(),
            built: None,
        })
    }

    /// A frame from flat arrays (what [`Refiner::frame`] does after JS filled the inputs).
    pub fn step_with(&mut self, positions: &[f32], normals: Option<&[f32]>) -> Result<(), String> {
        self.inputs.set(positions, normals);
        self.step(normals.is_some())
    }

    fn step(&mut self, with_normals: bool) -> Result<(), String> {
        let Some(built) = &mut self.built else {
            let mesh = refine::mesh(
                self.inputs.positions(),
                &self.triangles,
                self.inputs.normals(with_normals),
                self.uvs.as_deref(),
            )?;
            let (plan, frame) =
                Plan::with_frame(mesh, &self.options).map_err(|e| errors::message(&e))?;
            let n = plan.vertex_count();
            let mut built = Built {
                indices: bytemuck::cast_slice(plan.indices()).to_vec(),
                positions: vec![[0.0; 3]; n],
                normals: vec![[0.0; 3]; n],
                uvs: plan.has_uvs().then(|| vec![[0.0; 2]; n]),
                plan,
                frame,
            };
            evaluate(&mut built)?;
            self.built = Some(built);
            return Ok(());
        };
        let (positions, normals) = self.inputs.points(with_normals)?;
        built
            .plan
            .update(&mut built.frame, positions, normals)
            .map_err(|e| errors::message(&e))?;
        evaluate(built)
    }
}

fn evaluate(built: &mut Built) -> Result<(), String> {
    let out = VertexOutput::Separate {
        positions: &mut built.positions,
        normals: Some(&mut built.normals),
        uvs: built.uvs.as_deref_mut(),
    };
    built
        .plan
        .evaluate(&built.frame, out)
        .map_err(|e| errors::message(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outputs(r: &Refiner) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
        let b = r.built.as_ref().unwrap();
        (b.positions.clone(), b.normals.clone(), b.indices.clone())
    }

    #[test]
    fn frames_equal_one_shot_refinement_and_a_bad_frame_keeps_the_last() {
        let m = tessella_core::samples::creature();
        let indices: &[u32] = bytemuck::cast_slice(m.triangles());
        let json = r#"{"scheme":"pn","level":4}"#;
        let mut r = Refiner::with(indices, None, json).unwrap();
        let (moved, _) = tessella_core::samples::twist(&m, 30.0);
        for positions in [m.positions(), &moved[..]] {
            r.step_with(arrays::flat(positions), None).unwrap();
            let mut want =
                refine::refine_arrays(arrays::flat(positions), indices, None, None, json).unwrap();
            let (p, n, i) = outputs(&r);
            assert_eq!(arrays::flat(&p), want.take_positions());
            assert_eq!(arrays::flat(&n), want.take_normals());
            assert_eq!(i, want.take_indices());
        }
        let before = outputs(&r);
        let mut bad = moved.clone();
        bad[3][1] = f32::NAN;
        let err = r.step_with(arrays::flat(&bad), None).unwrap_err();
        assert!(err.contains("non-finite coordinate"), "{err}");
        let err = r.step_with(&arrays::flat(&moved)[3..], None).unwrap_err();
        assert!(err.contains("vertices"), "{err}");
        assert!(outputs(&r) == before, "a refused frame changed the outputs");
    }
}
