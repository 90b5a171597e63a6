// Adaptive levels that change every frame (tessella_core::refine::instanced). The vertex buffer
// holds the point codes of the spacing's parts, built once; per face a record (tessellator: four
// rulers; grid: edge segments, grid level and geomorph factors; both: canonical edge bits), per
// instance `face | side << 30`. A vertex turns its code into a barycentric point with its face's
// record, evaluates the basis there and sums the control net. Points on a coarse edge are
// evaluated from the edge's four boundary control points in canonical direction with weights
// from the edge's own data, the same floats on both faces. Prepended (adaptive.rs): the record
// layout and the basis, normal-net and edge weights generated from tessella-core's formulas
// (tessella_core::shader: `tessella_patch_sum`, `tessella_normal_net_sum`,
// `tessella_edge_weights`, `tessella_canonical_edge`, `tessella_canonical_edge_point`,
// `tessella_locate`, `tessella_tessellator_point`, `tessella_grid_*`, `TESSELLA_*` constants),
// the normal's glue (`tessella_adaptive_normal`), the point on the tessellator's spacings
// (`tessella_tessellator_adaptive_point`, shader::adaptive_point) and the printed
// TessellaAdaptiveParams; appended: adaptive_draw.wgsl (the vertex
// shader) or adaptive_capture.wgsl (a compute read-back of the same points).

// Set by the renderer before this file, so that each pipeline compiles only its own basis,
// normal mode and spacing (a branch on a uniform still costs its whole body on a software
// rasteriser): TESSELLA_BASIS_K (10 cubic, 21 PNG1), TESSELLA_NORMAL_MODE (0 linear, 1 quadratic, 2 real:
// NormalMode order), TESSELLA_GRID (grid spacing, else a tessellator spacing).

// TessellaAdaptiveParams is printed from its Rust twin (gpu_types.rs) before this file.

@group(0) @binding(0) var<storage, read> tessella_net_points: array<f32>;
@group(0) @binding(1) var<storage, read> tessella_net_normals: array<f32>;
@group(0) @binding(2) var<uniform> tessella_adaptive_params: TessellaAdaptiveParams;
@group(0) @binding(3) var<storage, read> tessella_records: array<u32>;

// TESSELLA_MODE_REAL, TESSELLA_NORMAL_NET_LEN: prepended from Rust (wgsl_constants.rs).

// The control nets the generated sums read.
fn tessella_net_point(face: u32, k: u32) -> vec3<f32> {
    let i = (face * TESSELLA_BASIS_K + k) * 3u;
    return vec3<f32>(tessella_net_points[i], tessella_net_points[i + 1u], tessella_net_points[i + 2u]);
}

fn tessella_net_normal(face: u32, k: u32) -> vec3<f32> {
    let i = (face * TESSELLA_NORMAL_NET_LEN + k) * 3u;
    return vec3<f32>(tessella_net_normals[i], tessella_net_normals[i + 1u], tessella_net_normals[i + 2u]);
}

// Word k of ruler r (0..2 the outer levels in GL order, 3 the inner level) of the record at
// `rec`: what the generated `tessella_locate` (the tessellator's placement, from
// tessella_core::tessellator) reads.
fn tessella_ruler_word(rec: u32, r: u32, k: u32) -> u32 {
    return tessella_records[rec + TESSELLA_RULER_WORDS * r + k];
}

// The edge tables' reads `tessella_canonical_edge_point` takes: edge `edge`'s boundary control
// points and normal-net entries (canonical::edge_controls, edge_normal_controls).
fn tessella_edge_control(edge: u32, i: u32) -> u32 {
    return tessella_adaptive_params.edge_controls[edge][i];
}

fn tessella_edge_normal_control(edge: u32, i: u32) -> u32 {
    return tessella_adaptive_params.edge_normals[edge][i];
}

// A point's surface, accumulated (geomorphing blends several): position, Du, Dv and the normal
// net's sum; on a coarse edge also the canonical weights of its boundary curve and normal
// restriction.
struct TessellaSums {
    p: vec3<f32>,
    du: vec3<f32>,
    dv: vec3<f32>,
    n: vec3<f32>,
    edge_w: vec4<f32>,
    edge_n: vec3<f32>,
}

// Adds `scale` times the surface of `face` at `l`: the basis' sums and the normal net's, both
// generated straight-line code.
fn tessella_add_point(acc: ptr<function, TessellaSums>, face: u32, l: vec3<f32>, scale: f32) {
    let s = tessella_patch_sum(face, l);
    (*acc).p += scale * s.p;
    if (TESSELLA_NORMAL_MODE == TESSELLA_MODE_REAL) {
        (*acc).du += scale * s.du;
        (*acc).dv += scale * s.dv;
    }
    (*acc).n += scale * tessella_normal_net_sum(face, l);
}

// Canonical weights at (a, b): a the canonical start corner's barycentric weight.
fn tessella_add_edge(acc: ptr<function, TessellaSums>, a: f32, b: f32, scale: f32) {
    let w = tessella_edge_weights(a, b);
    (*acc).edge_w += scale * w.value;
    (*acc).edge_n += scale * w.normal;
}

// Adds a point of a grid plan (`xyz` barycentric, `w` its weight) unless its weight is zero.
fn tessella_add_plan_point(acc: ptr<function, TessellaSums>, face: u32, q: vec4<f32>) {
    if (q.w != 0.0) {
        tessella_add_point(acc, face, q.xyz, q.w);
    }
}

// Adds a canonical edge point of a grid plan (`x`, `y` its a, b, `z` its weight) unless its
// weight is zero.
fn tessella_add_plan_edge(acc: ptr<function, TessellaSums>, q: vec3<f32>) {
    if (q.z != 0.0) {
        tessella_add_edge(acc, q.x, q.y, q.z);
    }
}

// Grid point (i, j) of a face: its surface into `acc`, summed over the plan the generated
// `tessella_grid_edge_plan` or `tessella_grid_inner_plan` gives (the snap and the geomorph
// sources of refine::grid_point, which the CPU's patterns and stencils run); returns the
// barycentric point and its edge (TESSELLA_NO_EDGE off the edges).
fn tessella_grid_point(face: u32, rec: u32, face_forward: u32, i: u32, j: u32, acc: ptr<function, TessellaSums>) -> vec4<f32> {
    let segments = vec3<u32>(
        tessella_records[rec + TESSELLA_GRID_SEGMENTS_WORD],
        tessella_records[rec + TESSELLA_GRID_SEGMENTS_WORD + 1u],
        tessella_records[rec + TESSELLA_GRID_SEGMENTS_WORD + 2u],
    );
    let alpha = vec3<f32>(
        bitcast<f32>(tessella_records[rec + TESSELLA_GRID_MORPH_WORD]),
        bitcast<f32>(tessella_records[rec + TESSELLA_GRID_MORPH_WORD + 1u]),
        bitcast<f32>(tessella_records[rec + TESSELLA_GRID_MORPH_WORD + 2u]),
    );
    let alpha_inner = bitcast<f32>(tessella_records[rec + TESSELLA_GRID_INNER_MORPH_WORD]);
    let big = tessella_records[rec + TESSELLA_GRID_LEVEL_WORD];
    // Only the point's own case is computed: inside an edge, or not.
    let edge = tessella_grid_edge(big, i, j);
    var g: TessellaGridPlan;
    if (edge == TESSELLA_NO_EDGE) {
        g = tessella_grid_inner_plan(big, i, j, alpha_inner);
    } else {
        g = tessella_grid_edge_plan(edge, big, i, j, segments, alpha, face_forward);
    }
    // Constant indices: a value array indexed in a loop may be put in memory.
    tessella_add_plan_point(acc, face, g.points[0]);
    tessella_add_plan_point(acc, face, g.points[1]);
    tessella_add_plan_point(acc, face, g.points[2]);
    tessella_add_plan_point(acc, face, g.points[3]);
    tessella_add_plan_edge(acc, g.edge_points[0]);
    tessella_add_plan_edge(acc, g.edge_points[1]);
    tessella_add_plan_edge(acc, g.edge_points[2]);
    return vec4<f32>(g.l, f32(g.edge));
}

struct TessellaAdaptivePoint {
    position: vec3<f32>,
    normal: vec3<f32>,
    // Barycentric in the coarse triangle.
    l: vec3<f32>,
}

// The point `vcode` (a point code; the top two bits are ignored) names on instance `inst`
// (`face | side << 30`).
fn tessella_adaptive_point(vcode: u32, inst: u32) -> TessellaAdaptivePoint {
    let face = inst & 0x3fffffffu;
    let code = vcode & 0x3fffffffu;
    let rec = face * TESSELLA_RECORD_WORDS;
    if (!TESSELLA_GRID) {
        // The tessellator's 16.16 placement read back and evaluated, a coarse edge's point in
        // canonical order: the core's adaptive point (generated in adaptive.rs).
        return tessella_tessellator_adaptive_point(face, rec, code, inst >> 30u);
    }
    let face_forward = tessella_records[rec + TESSELLA_FORWARD_WORD];
    var acc: TessellaSums;
    let g = tessella_grid_point(face, rec, face_forward, code & 0xffu, (code >> 8u) & 0xffu, &acc);
    let edge = u32(g.w);
    // The normal's steps are the CPU's (tessella_adaptive_normal, generated in adaptive.rs).
    var point = TessellaAdaptivePoint(acc.p, tessella_adaptive_normal(face, acc.du, acc.dv, acc.n), g.xyz);
    if (edge != TESSELLA_NO_EDGE) {
        // The edge's own data in canonical order, summed in the same order on both faces
        // (the generated tessella_canonical_edge_point, the CPU's canonical::edge_sum_of),
        // at the weights the grid plan blended.
        let forward = tessella_edge_forward(face_forward, edge);
        let e = tessella_canonical_edge_point(face, edge, forward, acc.edge_w, acc.edge_n, point.normal);
        point.position = e.p;
        point.normal = e.n;
    }
    return point;
}
