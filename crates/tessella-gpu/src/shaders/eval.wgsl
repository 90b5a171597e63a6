// Patch evaluation: the generic weighted sum of tessella-core's `eval_point` (refine/cpu/kernels.rs).
// The schemes' formulas live in Rust only: the CPU builds each coarse triangle's control net
// (K points, 6 normal-net entries) and the pattern's stencil rows
// (value[K] | du[K] | dv[K] | normal weights[6] | l[3]); here we only combine them.
// K and the row stride are uniforms, so every basis (cubic K=10, PNG1 K=21, ...) runs unchanged.

// TessellaEvalParams is printed from its Rust twin (gpu_types.rs) before this file.

@group(0) @binding(0) var<storage, read> tessella_stencil: array<f32>;
@group(0) @binding(1) var<storage, read> tessella_net_points: array<f32>;
@group(0) @binding(2) var<storage, read> tessella_net_normals: array<f32>;
@group(0) @binding(3) var<uniform> tessella_eval_params: TessellaEvalParams;
// Canonical edges (crate::canonical): boundary control points per edge, per pattern row its
// edge and both directions' weights, per face which edges run canonically.
@group(0) @binding(6) var<storage, read> tessella_edge_table: array<u32>;

// TESSELLA_NORMAL_NET_LEN, TESSELLA_EDGE_ROWS_AT, TESSELLA_EDGE_ROW_LEN, TESSELLA_MODE_REAL:
// prepended from Rust (wgsl_constants.rs). Every name this module declares starts with
// `tessella_` (`Tessella`, `TESSELLA_`): engines include it beside their own (docs/engine.md).

struct TessellaSurfacePoint {
    position: vec3<f32>,
    normal: vec3<f32>,
    // The row's barycentric coordinates (l1, l2, l3).
    l: vec3<f32>,
}

fn tessella_net_point(face: u32, k: u32) -> vec3<f32> {
    let i = (face * tessella_eval_params.k + k) * 3u - tessella_eval_params.points_base;
    return vec3<f32>(tessella_net_points[i], tessella_net_points[i + 1u], tessella_net_points[i + 2u]);
}

fn tessella_net_normal(face: u32, k: u32) -> vec3<f32> {
    let i = (face * TESSELLA_NORMAL_NET_LEN + k) * 3u - tessella_eval_params.normals_base;
    return vec3<f32>(tessella_net_normals[i], tessella_net_normals[i + 1u], tessella_net_normals[i + 2u]);
}

// The control points a net: TESSELLA_FIXED_K where the module was made for one basis (a
// constant bound the compiler unrolls: a third less time on lavapipe), else the uniform's.
fn tessella_k() -> u32 {
    if (TESSELLA_FIXED_K != 0u) {
        return TESSELLA_FIXED_K;
    }
    return tessella_eval_params.k;
}

// sum_k w_k C_k with w read from `stencil` starting at `first`, in the CPU's order.
fn tessella_combine_points(face: u32, first: u32) -> vec3<f32> {
    var acc = vec3<f32>(0.0);
    for (var k = 0u; k < tessella_k(); k++) {
        acc += tessella_stencil[first + k] * tessella_net_point(face, k);
    }
    return acc;
}

// Evaluates stencil row `row` on coarse triangle `face` (same fallbacks as `eval_point`).
fn tessella_eval_patch(face: u32, row: u32) -> TessellaSurfacePoint {
    let k = tessella_k();
    let base = row * tessella_eval_params.stride;
    var out: TessellaSurfacePoint;
    out.position = tessella_combine_points(face, base);
    // The normal's steps are the CPU's (tessella_patch_normal, generated in patch.rs).
    out.normal = tessella_patch_normal(face, base);
    let l0 = base + 3u * k + TESSELLA_NORMAL_NET_LEN;
    out.l = vec3<f32>(tessella_stencil[l0], tessella_stencil[l0 + 1u], tessella_stencil[l0 + 2u]);
    tessella_edge_point(face, row, &out);
    return out;
}

// The edge tables' reads `tessella_canonical_edge_point` takes (the table's head: per edge
// its four boundary control points, then its three normal-net entries; crate::canonical).
fn tessella_edge_control(edge: u32, i: u32) -> u32 {
    return tessella_edge_table[1u + edge * 4u + i];
}

fn tessella_edge_normal_control(edge: u32, i: u32) -> u32 {
    return tessella_edge_table[13u + edge * 3u + i];
}

// A point on coarse edge k is evaluated from the edge's own four control points (and three
// normal-net entries) in canonical order, from the corner with the lower position id, with
// weights made on the CPU: the two faces sharing the edge compute the same floats in the same
// order (the generated tessella_canonical_edge_point, the CPU's canonical::edge_sum_of), so its
// vertices are bit-identical. "Real" normals stay the face's own.
fn tessella_edge_point(face: u32, row: u32, out: ptr<function, TessellaSurfacePoint>) {
    let r = TESSELLA_EDGE_ROWS_AT + row * TESSELLA_EDGE_ROW_LEN;
    let code = tessella_edge_table[r];
    if (code == 0u) {
        return;
    }
    let k = code - 1u;
    let forward = tessella_edge_forward(tessella_edge_table[tessella_edge_table[0] + face], k);
    let w = r + 1u + select(7u, 0u, forward);
    let value = vec4<f32>(
        bitcast<f32>(tessella_edge_table[w]),
        bitcast<f32>(tessella_edge_table[w + 1u]),
        bitcast<f32>(tessella_edge_table[w + 2u]),
        bitcast<f32>(tessella_edge_table[w + 3u]),
    );
    let normal = vec3<f32>(
        bitcast<f32>(tessella_edge_table[w + 4u]),
        bitcast<f32>(tessella_edge_table[w + 5u]),
        bitcast<f32>(tessella_edge_table[w + 6u]),
    );
    let e = tessella_canonical_edge_point(face, k, forward, value, normal, (*out).normal);
    (*out).position = e.p;
    (*out).normal = e.n;
}
