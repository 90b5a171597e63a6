//! The mesh the crate's unit tests build surfaces from.

/// The icosphere of one subdivision and its triangles as flat `u32` indices.
pub(crate) fn sample() -> (tessella_core::Mesh, Vec<u32>) {
    let m = tessella_core::samples::icosphere(1);
    let indices = bytemuck::cast_slice(m.triangles()).to_vec();
    (m, indices)
}
