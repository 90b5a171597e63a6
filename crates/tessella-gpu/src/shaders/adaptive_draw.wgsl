// The vertex shader of the adaptive renderer: a part's vertex (its point code, and in the top two
// bits its corner in the pattern triangle: the unrolled draw lists every triangle's three
// corners, the indexed draw leaves them 0) on the instance's face, handed to the caller's
// `shade_vertex`. Prepended: the generated weights (adaptive.rs), adaptive.wgsl, vertex.wgsl;
// appended: the shading.

// The draw's own table, beside adaptive.wgsl's group 0: per instance `face | side << 30`.
@group(0) @binding(4) var<storage, read> tessella_instances: array<u32>;

@vertex
fn tessella_vs_adaptive(@location(0) vcode: u32, @builtin(instance_index) instance: u32) -> VsOut {
    let inst = tessella_instances[instance];
    let sp = tessella_adaptive_point(vcode, inst);
    return shade_vertex(TessellaVertex(sp.position, sp.normal, sp.l, tessella_corner(vcode >> 30u), inst & 0x3fffffffu));
}
