//! `readAnimated`: a glTF/GLB file's skins, morph targets and clips (tessella-io's in-memory
//! reader), validated and posed by the core's [`Poser`]; the file system is never touched.
//!
//! The JS side resolves a clip given by name to its index ([`Animated::clip_index`]) and
//! passes indices, `None` for the rest pose.

use crate::files::GltfBuffers;
use crate::refine::Arrays;
use crate::{arrays, errors, files};
use tessella_core::animation::Poser;
use wasm_bindgen::prelude::*;

/// An animated mesh read from a file, ready to pose.
#[wasm_bindgen]
pub struct Animated {
    poser: Poser,
}

crate::arrays::poser_exports!(Animated);

#[wasm_bindgen]
impl Animated {
    /// The triangles' corners, 3 vertex indices per triangle.
    pub fn indices(&self) -> Vec<u32> {
        bytemuck::cast_slice(&self.poser.model().triangles).to_vec()
    }

    /// The clips' names, in the file's order.
    pub fn clips(&self) -> Vec<String> {
        self.poser.clip_names().map(String::from).collect()
    }

    /// The index of the clip named `name` (or, when none has that name, of decimal index
    /// `name`).
    #[wasm_bindgen(js_name = clipIndex)]
    pub fn clip_index(&self, name: &str) -> Result<u32, JsError> {
        self.poser
            .clip_index(name)
            .map(|i| i as u32)
            .map_err(|e| errors::text(errors::message(&e)))
    }

    /// Clip `clip`'s duration in seconds: the shortest decimal that is the file's `f32` (0.8,
    /// not 0.800000011920929).
    pub fn duration(&self, clip: u32) -> Result<f64, JsError> {
        self.poser
            .duration(clip as usize)
            .map(shortest)
            .map_err(|e| errors::text(errors::message(&e)))
    }

    /// The pose at `time` seconds of clip `clip` (`None`: the rest pose).
    pub fn pose(&self, clip: Option<u32>, time: f64) -> Result<Arrays, JsError> {
        self.pose_arrays(clip, time).map_err(errors::text)
    }
}

impl Animated {
    /// Reads and validates an animated glTF/GLB file; `given`: a `.gltf` file's external
    /// buffers by relative URI ([`files::GltfBuffers::given`]).
    pub fn read(bytes: &[u8], format: &str, given: &[(&str, &[u8])]) -> Result<Animated, String> {
        let model = tessella_io::read_animated_bytes(&files::file_name(format), bytes, given)
            .map_err(|e| errors::message(&e))?;
        let poser = Poser::new(model).map_err(|e| {
            format!(
                "invalid animation in {}: {}",
                files::file_name(format),
                errors::message(&e)
            )
        })?;
        Ok(Animated { poser })
    }

    /// [`Animated::pose`] with a `String` error: posed normals when the file has normals,
    /// otherwise normals computed by the core from the posed mesh.
    pub fn pose_arrays(&self, clip: Option<u32>, time: f64) -> Result<Arrays, String> {
        if !time.is_finite() {
            return Err(format!(
                "time must be a finite number of seconds, got {time}"
            ));
        }
        let clip = clip.map(|c| c as usize);
        let time = time as f32;
        let message = |e: tessella_core::AnimationError| errors::message(&e);
        if self.poser.has_normals() {
            let (positions, normals) = self.poser.pose(clip, time).map_err(message)?;
            let normals = normals.ok_or("the posed mesh has no normals")?;
            Ok(Arrays::points(
                bytemuck::allocation::cast_vec(positions),
                bytemuck::allocation::cast_vec(normals),
            ))
        } else {
            let mesh = self.poser.mesh(clip, time).map_err(message)?;
            Ok(Arrays::points(
                arrays::flat(mesh.positions()).to_vec(),
                arrays::flat(mesh.normals()).to_vec(),
            ))
        }
    }
}

/// `value` as the `f64` of its shortest decimal (what JS would print for the `f32` it is).
fn shortest(value: f32) -> f64 {
    value.to_string().parse().unwrap_or(value as f64)
}

/// `readAnimated` for JS: see `js/src/index.js`.
#[wasm_bindgen(js_name = readAnimated)]
pub fn read_js(bytes: &[u8], format: &str, buffers: &GltfBuffers) -> Result<Animated, JsError> {
    buffers
        .given()
        .and_then(|given| Animated::read(bytes, format, &given))
        .map_err(errors::text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Animated {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../samples/animated-creature.glb"
        );
        Animated::read(&std::fs::read(path).unwrap(), "glb", &[]).unwrap()
    }

    #[test]
    fn the_sample_poses_and_bad_input_is_refused_by_name() {
        let a = sample();
        assert_eq!(a.clips(), ["wave", "hop", "breathe"]);
        assert_eq!(a.indices().len(), 960);
        assert_eq!(shortest(a.poser.duration(1).unwrap()), 0.8);
        let mut pose = a.pose_arrays(Some(1), 0.3).unwrap();
        assert_eq!(pose.take_positions().len(), a.vertex_count() * 3);
        assert_eq!(pose.take_normals().len(), a.vertex_count() * 3);
        let err = a.pose_arrays(Some(0), f64::NAN).unwrap_err();
        assert!(err.contains("finite"), "{err}");
        let err = a.pose_arrays(Some(7), 0.0).unwrap_err();
        assert!(err.contains('7'), "{err}");
        let err = Animated::read(b"v 0 0 0\n", "obj", &[]).err().unwrap();
        assert!(err.contains("only glTF"), "{err}");
        assert!(Animated::read(b"garbage", "glb", &[]).is_err());
    }
}
