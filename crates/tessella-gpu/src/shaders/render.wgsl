// Instanced rendering with a refinement pattern (GMR section 3.2): the pattern's points are one
// vertex buffer (a stencil row index per point), drawn once per coarse triangle (instance); the
// vertex shader evaluates the instance's patch at the row. Prepended: eval.wgsl, displace.wgsl,
// shade.wgsl.

// A pattern vertex: its stencil row, and in the top two bits its corner in the pattern triangle
// (the wireframe draw lists every triangle's three corners; the indexed draw leaves them 0).
@vertex
fn vs_pattern(@location(0) code: u32, @builtin(instance_index) instance: u32) -> VsOut {
    let face = instance_faces[instance];
    let row = code & 0x3fffffffu;
    let corner = code >> 30u;
    let sp = tessella_eval_patch(face, row);
    var p = sp.position;
    if (TESSELLA_DISPLACE_KIND != 0u) {
        let i = face * 6u;
        let l = sp.l;
        let uv = vec2<f32>(
            l.x * face_uvs[i] + l.y * face_uvs[i + 2u] + l.z * face_uvs[i + 4u],
            l.x * face_uvs[i + 1u] + l.y * face_uvs[i + 3u] + l.z * face_uvs[i + 5u],
        );
        p += tessella_displacement(p, uv) * tessella_displace_direction(face, l, sp.normal);
    }
    var out: VsOut;
    out.clip = u.view_proj * vec4<f32>(p, 1.0);
    out.world = p;
    out.normal = sp.normal;
    out.l = sp.l;
    out.tri = vec3<f32>(f32(corner == 0u), f32(corner == 1u), f32(corner == 2u));
    out.field = vec2<f32>(0.0);
    if (colormap[0].z > 0.0) {
        // P2 shape functions (tessella_core::mesh::quadratic::shape_functions).
        let l = sp.l;
        let i = face * 6u;
        out.field = vec2<f32>(
            l.x * (2.0 * l.x - 1.0) * face_field[i] + l.y * (2.0 * l.y - 1.0) * face_field[i + 1u]
                + l.z * (2.0 * l.z - 1.0) * face_field[i + 2u] + 4.0 * l.x * l.y * face_field[i + 3u]
                + 4.0 * l.y * l.z * face_field[i + 4u] + 4.0 * l.z * l.x * face_field[i + 5u],
            1.0,
        );
    }
    return out;
}

// A static, fully refined vertex buffer (the baseline of GMR Figure 7).
@vertex
fn vs_static(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VsOut {
    var out: VsOut;
    out.clip = u.view_proj * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.l = vec3<f32>(0.5);
    out.tri = vec3<f32>(0.5);
    out.field = vec2<f32>(0.0);
    return out;
}

