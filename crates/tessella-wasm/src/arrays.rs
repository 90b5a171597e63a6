//! Flat typed arrays (what JS passes) to the core's arrays, with the checks that say which
//! argument was wrong. Values themselves (NaN, indices out of range) are the core's to check.

/// `values` as points of 3 (`positions`, `normals`): its length must be a multiple of 3.
pub fn points(values: &[f32], what: &str) -> Result<Vec<[f32; 3]>, String> {
    Ok(as_points(values, what)?.to_vec())
}

/// [`points`] without a copy.
pub fn as_points<'a>(values: &'a [f32], what: &str) -> Result<&'a [[f32; 3]], String> {
    if !values.len().is_multiple_of(3) {
        return Err(format!(
            "{what} has {} numbers, not a multiple of 3 (x, y, z per vertex)",
            values.len()
        ));
    }
    Ok(bytemuck::cast_slice(values))
}

/// `values` as texture coordinates, 2 numbers per vertex.
pub fn uvs(values: &[f32]) -> Result<Vec<[f32; 2]>, String> {
    if !values.len().is_multiple_of(2) {
        return Err(format!(
            "uvs has {} numbers, not a multiple of 2 (u, v per vertex)",
            values.len()
        ));
    }
    Ok(bytemuck::cast_slice(values).to_vec())
}

/// `values` as triangles, 3 vertex indices each.
pub fn triangles(values: &[u32]) -> Result<Vec<[u32; 3]>, String> {
    if !values.len().is_multiple_of(3) {
        return Err(format!(
            "indices has {} entries, not a multiple of 3 (one triangle is 3 indices)",
            values.len()
        ));
    }
    Ok(bytemuck::cast_slice(values).to_vec())
}

/// The exports of a class that JS feeds frame by frame through [`FrameInputs`] (its field
/// `inputs`, or its field `$via`'s): `positionsInput(len)` and `normalsInput(len)`, the input
/// arrays for `len` numbers (resized only when `len` changes) as addresses in wasm memory, and
/// `frame(normals)`, which runs the (field's) `step` on the frame now in them (`normals`:
/// whether the normals input holds this frame's normals; otherwise they are computed). On error
/// the class keeps the last good frame.
macro_rules! frame_input_exports {
    ($class:ty $(, via $via:ident)?) => {
        #[wasm_bindgen::prelude::wasm_bindgen]
        impl $class {
            /// The positions input for `len` numbers; its address in wasm memory.
            #[wasm_bindgen(js_name = positionsInput)]
            pub fn positions_input(&mut self, len: usize) -> *mut f32 {
                self$(.$via)?.inputs.positions_ptr(len)
            }
            /// The normals input for `len` numbers; its address in wasm memory.
            #[wasm_bindgen(js_name = normalsInput)]
            pub fn normals_input(&mut self, len: usize) -> *mut f32 {
                self$(.$via)?.inputs.normals_ptr(len)
            }
            /// Takes the frame now in the inputs (`normals`: whether the normals input holds
            /// it); on error the last good frame stays.
            pub fn frame(&mut self, normals: bool) -> Result<(), wasm_bindgen::JsError> {
                self$(.$via)?.step(normals).map_err(crate::errors::text)
            }
        }
    };
}
pub(crate) use frame_input_exports;

/// The exports of a class that poses an animated file through its field `poser`
/// (`tessella_core::animation::Poser`): `vertexCount()` and `hasNormals()` (whether the file
/// has normals; otherwise each pose's normals are computed).
macro_rules! poser_exports {
    ($class:ty) => {
        #[wasm_bindgen::prelude::wasm_bindgen]
        impl $class {
            /// The file's vertex count.
            #[wasm_bindgen(js_name = vertexCount)]
            pub fn vertex_count(&self) -> usize {
                self.poser.vertex_count()
            }
            /// Whether the file has normals (otherwise each pose's normals are computed).
            #[wasm_bindgen(js_name = hasNormals)]
            pub fn has_normals(&self) -> bool {
                self.poser.has_normals()
            }
        }
    };
}
pub(crate) use poser_exports;

/// A frame's positions and, when it has them, its normals.
pub type FramePoints<'a> = (&'a [[f32; 3]], Option<&'a [[f32; 3]]>);

/// The input arrays JS writes a frame into through views over wasm memory, kept between
/// frames so that a frame allocates nothing once their lengths settle.
#[derive(Default)]
pub struct FrameInputs {
    positions: Vec<f32>,
    normals: Vec<f32>,
}

impl FrameInputs {
    /// The positions input resized to `len` numbers (only when `len` changes); its address.
    pub fn positions_ptr(&mut self, len: usize) -> *mut f32 {
        self.positions.resize(len, 0.0);
        self.positions.as_mut_ptr()
    }

    /// The normals input resized to `len` numbers; its address.
    pub fn normals_ptr(&mut self, len: usize) -> *mut f32 {
        self.normals.resize(len, 0.0);
        self.normals.as_mut_ptr()
    }

    /// Copies a frame in, as JS would have written it (without `normals` the normals input is
    /// left as it was).
    pub fn set(&mut self, positions: &[f32], normals: Option<&[f32]>) {
        self.positions.clear();
        self.positions.extend_from_slice(positions);
        if let Some(n) = normals {
            self.normals.clear();
            self.normals.extend_from_slice(n);
        }
    }

    /// The positions input, flat.
    pub fn positions(&self) -> &[f32] {
        &self.positions
    }

    /// The normals input, flat, when the frame has normals (`given`).
    pub fn normals(&self, given: bool) -> Option<&[f32]> {
        given.then_some(self.normals.as_slice())
    }

    /// The inputs as points (see [`as_points`]); normals only when `given`.
    pub fn points(&self, given: bool) -> Result<FramePoints<'_>, String> {
        let positions = as_points(&self.positions, "positions")?;
        let normals = self
            .normals(given)
            .map(|n| as_points(n, "normals"))
            .transpose()?;
        Ok((positions, normals))
    }
}

/// Flattens points for JS.
pub fn flat<const N: usize>(values: &[[f32; N]]) -> &[f32]
where
    [f32; N]: bytemuck::Pod,
{
    bytemuck::cast_slice(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_that_are_not_whole_points_are_refused_by_name() {
        assert_eq!(points(&[0.0; 6], "positions").unwrap().len(), 2);
        let err = points(&[0.0; 7], "normals").unwrap_err();
        assert!(err.starts_with("normals has 7 numbers"), "{err}");
        assert!(triangles(&[0, 1]).unwrap_err().contains("multiple of 3"));
        assert!(uvs(&[0.0; 3]).unwrap_err().contains("multiple of 2"));
        assert_eq!(
            triangles(&[0, 1, 2, 2, 1, 3]).unwrap(),
            vec![[0, 1, 2], [2, 1, 3]]
        );
    }
}
