// Adaptive levels that change every frame (tessella_core::refine::instanced). The vertex buffer
// holds the point codes of the spacing's parts, built once; per face a record (tessellator: four
// rulers; grid: edge segments, grid level and geomorph factors; both: canonical edge bits), per
// instance `face | side << 30`. A vertex turns its code into a barycentric point with its face's
// record, evaluates the basis there and sums the control net. Points on a coarse edge are
// evaluated from the edge's four boundary control points in canonical direction with weights
// from the edge's own data, the same floats on both faces. Prepended (adaptive.rs): the record
// layout and the basis, normal-net and edge weights generated from tessella-core's formulas
// (tessella_core::shader: `tessella_patch_sum`, `tessella_normal_net_sum`,
// `tessella_edge_weights`, `TESSELLA_*` constants); appended: adaptive_draw.wgsl (the vertex
// shader) or adaptive_capture.wgsl (a compute read-back of the same points).

// Set by the renderer before this file, so that each pipeline compiles only its own basis,
// normal mode and spacing (a branch on a uniform still costs its whole body on a software
// rasteriser): TESSELLA_BASIS_K (10 cubic, 21 PNG1), TESSELLA_NORMAL_MODE (0 linear, 1 quadratic, 2 real:
// NormalMode order), TESSELLA_GRID (grid spacing, else a tessellator spacing).

struct TessellaAdaptiveParams {
    // Per edge k (corner k to k + 1): its boundary curve's control points
    // (canonical::edge_controls), then its normal-net entries (xyz).
    edge_controls: array<vec4<u32>, 3>,
    edge_normals: array<vec4<u32>, 3>,
}

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

fn tessella_step_point(e: u32, n: u32, s: u32) -> vec3<f32> {
    var l = vec3<f32>(0.0);
    l[e] = f32(n - s) / f32(n);
    l[(e + 1u) % 3u] = f32(s) / f32(n);
    return l;
}

// Grid point (i, j) of a face (refine::instanced::grid_point, with refine::morph's blend):
// its surface into `acc`; returns the barycentric point and its edge (TESSELLA_NO_EDGE off the edges).
fn tessella_grid_point(face: u32, rec: u32, face_forward: u32, i: u32, j: u32, acc: ptr<function, TessellaSums>) -> vec4<f32> {
    let big = tessella_records[rec + TESSELLA_GRID_LEVEL_WORD];
    let kk = big - i - j;
    var e = TESSELLA_NO_EDGE;
    var step = 0u;
    if (j == 0u && i != 0u && kk != 0u) {
        e = 0u;
        step = i;
    } else if (kk == 0u && i != 0u && j != 0u) {
        e = 1u;
        step = j;
    } else if (i == 0u && j != 0u && kk != 0u) {
        e = 2u;
        step = big - j;
    }
    if (e != TESSELLA_NO_EDGE) {
        let n = tessella_records[rec + TESSELLA_GRID_SEGMENTS_WORD + e];
        let s = (2u * step * n + big) / (2u * big);
        if (s == 0u || s == n) {
            // Snapped onto a corner.
            var l = vec3<f32>(0.0);
            l[select((e + 1u) % 3u, e, s == 0u)] = 1.0;
            tessella_add_point(acc, face, l, 1.0);
            return vec4<f32>(l, f32(TESSELLA_NO_EDGE));
        }
        let l = tessella_step_point(e, n, s);
        let alpha = bitcast<f32>(tessella_records[rec + TESSELLA_GRID_MORPH_WORD + e]);
        let forward = ((face_forward >> e) & 1u) != 0u;
        let sc = select(n - s, s, forward);
        tessella_add_point(acc, face, l, select(1.0, alpha, alpha < 1.0));
        tessella_add_edge(acc, f32(n - sc) / f32(n), f32(sc) / f32(n), select(1.0, alpha, alpha < 1.0));
        if (alpha < 1.0) {
            // refine::morph::edge_sources: the two level-(n - 1) steps around it.
            let m = n - 1u;
            let x = s * m;
            let xc = sc * m;
            for (var h = 0u; h < 2u; h++) {
                let beta = select(f32(n - x % n), f32(x % n), h == 1u) / f32(n);
                let beta_c = select(f32(n - xc % n), f32(xc % n), h == 1u) / f32(n);
                let t = x / n + h;
                let tc = xc / n + h;
                if (beta > 0.0) {
                    tessella_add_point(acc, face, tessella_step_point(e, m, t), (1.0 - alpha) * beta);
                }
                if (beta_c > 0.0) {
                    tessella_add_edge(acc, f32(m - tc) / f32(m), f32(tc) / f32(m), (1.0 - alpha) * beta_c);
                }
            }
        }
        return vec4<f32>(l, f32(e));
    }
    let l = vec3<f32>(f32(kk), f32(i), f32(j)) / f32(big);
    let alpha = bitcast<f32>(tessella_records[rec + TESSELLA_GRID_INNER_MORPH_WORD]);
    let corner = (i == 0u && j == 0u) || i == big || j == big;
    if (alpha >= 1.0 || corner) {
        tessella_add_point(acc, face, l, 1.0);
        return vec4<f32>(l, f32(TESSELLA_NO_EDGE));
    }
    tessella_add_point(acc, face, l, alpha);
    // refine::morph::grid_sources: the level-(big - 1) triangle holding the point.
    let n = big;
    let m = big - 1u;
    let x = i * m;
    let y = j * m;
    let cx = x / n;
    let cy = y / n;
    let rx = x % n;
    let ry = y % n;
    var ci: array<vec2<u32>, 3>;
    var cb: array<u32, 3>;
    if (rx + ry <= n) {
        ci = array<vec2<u32>, 3>(vec2<u32>(cx, cy), vec2<u32>(cx + 1u, cy), vec2<u32>(cx, cy + 1u));
        cb = array<u32, 3>(n - rx - ry, rx, ry);
    } else {
        ci = array<vec2<u32>, 3>(vec2<u32>(cx + 1u, cy), vec2<u32>(cx + 1u, cy + 1u), vec2<u32>(cx, cy + 1u));
        cb = array<u32, 3>(n - ry, rx + ry - n, n - rx);
    }
    for (var h = 0u; h < 3u; h++) {
        if (cb[h] > 0u) {
            let c = ci[h];
            let lt = vec3<f32>(f32(m - c.x - c.y), f32(c.x), f32(c.y)) / f32(m);
            tessella_add_point(acc, face, lt, (1.0 - alpha) * f32(cb[h]) / f32(n));
        }
    }
    return vec4<f32>(l, f32(TESSELLA_NO_EDGE));
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
    let face_forward = tessella_records[rec + TESSELLA_FORWARD_WORD];
    var acc: TessellaSums;
    var l: vec3<f32>;
    var edge = TESSELLA_NO_EDGE;
    if (!TESSELLA_GRID) {
        let p = tessella_locate(rec, code, inst >> 30u);
        let lf = vec3<u32>(p.x, p.y, TESSELLA_FIXED_ONE - p.x - p.y);
        l = vec3<f32>(lf) / f32(TESSELLA_FIXED_ONE);
        tessella_add_point(&acc, face, l, 1.0);
        edge = p.z;
        if (edge != TESSELLA_NO_EDGE) {
            let forward = ((face_forward >> edge) & 1u) != 0u;
            let a = select(TESSELLA_FIXED_ONE - lf[edge], lf[edge], forward);
            tessella_add_edge(&acc, f32(a) / f32(TESSELLA_FIXED_ONE), f32(TESSELLA_FIXED_ONE - a) / f32(TESSELLA_FIXED_ONE), 1.0);
        }
    } else {
        let g = tessella_grid_point(face, rec, face_forward, code & 0xffu, (code >> 8u) & 0xffu, &acc);
        l = g.xyz;
        edge = u32(g.w);
    }

    // The normal glue is the CPU's (tessella_core::shader::surface_normal, prepended).
    var p = acc.p;
    var n = vec3<f32>(0.0);
    if (TESSELLA_NORMAL_MODE == TESSELLA_MODE_REAL) {
        n = tessella_real_normal(acc.du, acc.dv);
    }
    if (all(n == vec3<f32>(0.0))) {
        n = acc.n;
    }
    if (edge != TESSELLA_NO_EDGE) {
        // The edge's own data in canonical order, summed in the same order on both faces.
        let forward = ((face_forward >> edge) & 1u) != 0u;
        let ctrl = tessella_adaptive_params.edge_controls[edge];
        var q = vec3<f32>(0.0);
        for (var i = 0u; i < 4u; i++) {
            q += acc.edge_w[i] * tessella_net_point(face, ctrl[select(3u - i, i, forward)]);
        }
        p = q;
        if (TESSELLA_NORMAL_MODE != TESSELLA_MODE_REAL) {
            let nc = tessella_adaptive_params.edge_normals[edge];
            var m = vec3<f32>(0.0);
            for (var i = 0u; i < 3u; i++) {
                m += acc.edge_n[i] * tessella_net_normal(face, nc[select(2u - i, i, forward)]);
            }
            let unit = tessella_unit_or_zero(m);
            if (any(unit != vec3<f32>(0.0))) {
                n = unit;
            }
        }
    }
    var unit = tessella_unit_or_zero(n);
    if (all(unit == vec3<f32>(0.0))) {
        unit = tessella_corner_normal(tessella_net_point(face, 0u), tessella_net_point(face, 1u), tessella_net_point(face, 2u));
    }
    return TessellaAdaptivePoint(p, unit, l);
}
