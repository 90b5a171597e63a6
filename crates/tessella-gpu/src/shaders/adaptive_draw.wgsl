// The vertex shader of the adaptive renderer: a part's vertex (its point code, and in the top two
// bits its corner in the pattern triangle: the wireframe draw lists every triangle's three
// corners, the indexed draw leaves them 0) on the instance's face. Prepended: the generated
// weights (adaptive.rs), shade.wgsl, adaptive.wgsl.

@vertex
fn vs_adaptive(@location(0) vcode: u32, @builtin(instance_index) instance: u32) -> VsOut {
    let sp = adaptive_point(vcode, instance_faces[instance]);
    let corner = vcode >> 30u;
    var out: VsOut;
    out.clip = u.view_proj * vec4<f32>(sp.position, 1.0);
    out.world = sp.position;
    out.normal = sp.normal;
    out.l = sp.l;
    out.tri = vec3<f32>(f32(corner == 0u), f32(corner == 1u), f32(corner == 2u));
    out.field = vec2<f32>(0.0);
    return out;
}
