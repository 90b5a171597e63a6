// What tessella's render vertex shaders hand the caller's shading, per drawn vertex: they call
// `shade_vertex(v: TessellaVertex) -> VsOut`, which the shading's WGSL defines with its own
// `VsOut`, its bindings in group 1 and its fragment shader `fs_main` (crate::Shading).

struct TessellaVertex {
    // The surface point (displaced where the renderer displaces) and its unit normal.
    position: vec3<f32>,
    normal: vec3<f32>,
    // The barycentric point in the coarse triangle.
    l: vec3<f32>,
    // The vertex's corner of its pattern triangle, one-hot; interpolated, the barycentric point
    // in the pattern triangle (draws of unrolled triangles only; indexed draws give corner 0).
    corner: vec3<f32>,
    // The coarse triangle; TESSELLA_NO_FACE for an already refined vertex buffer.
    face: u32,
}

const TESSELLA_NO_FACE: u32 = 0xffffffffu;

// The one-hot vector of corner `c` (0, 1 or 2).
fn tessella_corner(c: u32) -> vec3<f32> {
    return vec3<f32>(f32(c == 0u), f32(c == 1u), f32(c == 2u));
}
