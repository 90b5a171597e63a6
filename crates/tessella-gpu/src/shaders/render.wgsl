// Instanced rendering with a refinement pattern (GMR section 3.2): the pattern's points are one
// vertex buffer (a stencil row index per point), drawn once per coarse triangle (instance); the
// vertex shader evaluates the instance's patch at the row and hands the point to the caller's
// `shade_vertex`. Prepended: eval.wgsl, displace.wgsl, vertex.wgsl; appended: the shading.

// The draw's own tables, after the patch's bindings in group 0. Instance -> coarse triangle
// (faces grouped by pattern, one draw per pattern).
@group(0) @binding(7) var<storage, read> tessella_instance_faces: array<u32>;
// Per coarse triangle: its three corners' texture coordinates (6 floats), for height maps.
@group(0) @binding(8) var<storage, read> tessella_face_uvs: array<f32>;

// A pattern vertex: its stencil row, and in the top two bits its corner in the pattern triangle
// (the unrolled draw lists every triangle's three corners; the indexed draw leaves them 0).
@vertex
fn tessella_vs_pattern(@location(0) code: u32, @builtin(instance_index) instance: u32) -> VsOut {
    let face = tessella_instance_faces[instance];
    let sp = tessella_eval_patch(face, code & 0x3fffffffu);
    var p = sp.position;
    if (TESSELLA_DISPLACE_KIND != 0u) {
        let i = face * 6u;
        let l = sp.l;
        let uv = vec2<f32>(
            l.x * tessella_face_uvs[i] + l.y * tessella_face_uvs[i + 2u] + l.z * tessella_face_uvs[i + 4u],
            l.x * tessella_face_uvs[i + 1u] + l.y * tessella_face_uvs[i + 3u] + l.z * tessella_face_uvs[i + 5u],
        );
        p += tessella_displacement(p, uv) * tessella_displace_direction(face, l, sp.normal);
    }
    return shade_vertex(TessellaVertex(p, sp.normal, sp.l, tessella_corner(code >> 30u), face));
}

// A static, fully refined vertex buffer (the baseline of GMR Figure 7).
@vertex
fn tessella_vs_static(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VsOut {
    return shade_vertex(TessellaVertex(position, normal, vec3<f32>(0.5), vec3<f32>(0.5), TESSELLA_NO_FACE));
}
