// Compute refinement: one kernel evaluates every output vertex of a chunk, one writes every
// output triangle of a chunk. Output order and indices are those of tessella-core's
// OutputLayout (refine/plan/layout.rs): welded = corners | edges (lower -> higher vertex index) |
// interiors; soup = (N+1)(N+2)/2 pattern points per face. Prepended: eval.wgsl, displace.wgsl.

// RefineParams is printed from its Rust twin (gpu_types.rs) before this file.

const NONE: u32 = 0xffffffffu;

@group(1) @binding(0) var<uniform> params: RefineParams;
@group(1) @binding(1) var<storage, read> mesh_u32: array<u32>;
@group(1) @binding(2) var<storage, read> mesh_f32: array<f32>;
// One output binding for both kernels (vertices as f32 bits, or indices), so the compute stage
// binds 8 storage buffers, WebGPU's default limit.
@group(1) @binding(3) var<storage, read_write> out_words: array<u32>;

fn put3(i: u32, v: vec3<f32>) {
    out_words[i] = bitcast<u32>(v.x);
    out_words[i + 1u] = bitcast<u32>(v.y);
    out_words[i + 2u] = bitcast<u32>(v.z);
}

fn input_vec3(at: u32, v: u32) -> vec3<f32> {
    let i = at + v * 3u;
    return vec3<f32>(mesh_f32[i], mesh_f32[i + 1u], mesh_f32[i + 2u]);
}

fn input_uv(v: u32) -> vec2<f32> {
    let i = params.uvs_at + v * 2u;
    return vec2<f32>(mesh_f32[i], mesh_f32[i + 1u]);
}

fn corner(face: u32, c: u32) -> u32 {
    return mesh_u32[params.triangles_at + face * 3u + c];
}

// Same sum order as the CPU's interpolate_uv.
fn face_uv(face: u32, l: vec3<f32>) -> vec2<f32> {
    let a = input_uv(corner(face, 0u));
    let b = input_uv(corner(face, 1u));
    let c = input_uv(corner(face, 2u));
    return vec2<f32>(l.x * a.x + l.y * b.x + l.z * c.x, l.x * a.y + l.y * b.y + l.z * c.y);
}

// Is edge slot k of `face` stored in the same direction as the face runs along it?
fn forward(face: u32, k: u32, e: u32) -> bool {
    return corner(face, k) == mesh_u32[params.edges_at + e * 2u];
}

// Writes a vertex displaced along `dir` (displace_direction: the normal, or the shared
// direction on hard edges and split corners).
fn write_vertex(local: u32, p: vec3<f32>, n: vec3<f32>, dir: vec3<f32>, uv: vec2<f32>) {
    // Displace after evaluation, once per output slot: shared vertices stay shared.
    let q = p + tessella_displacement(p, uv) * dir;
    // Interleaved as the caller's VertexFormat says.
    let i = params.out_base + local * params.out_stride;
    put3(i + params.out_position, q);
    if (params.out_normal != NONE) {
        put3(i + params.out_normal, n);
    }
    if (params.out_uv != NONE) {
        out_words[i + params.out_uv] = bitcast<u32>(uv.x);
        out_words[i + params.out_uv + 1u] = bitcast<u32>(uv.y);
    }
}

@compute @workgroup_size(64)
fn refine_vertices(@builtin(global_invocation_id) gid: vec3<u32>) {
    let local = gid.x;
    if (local >= params.count) {
        return;
    }
    let g = params.first + local;
    if (params.adaptive != 0u) {
        adaptive_vertex(local, g);
        return;
    }
    let m = params.level - 1u;
    var face: u32;
    var row: u32;
    if (params.weld != 0u) {
        if (g < params.input_vertices) {
            // Corners: the input position exactly; the normal of the owning patch.
            let owner = mesh_u32[params.vertex_owner_at + g];
            var n = input_vec3(params.normals_at, g);
            var dir = n;
            if (owner != NONE) {
                let c = mesh_u32[params.corner_points_at + (owner & 3u)];
                let corner_point = tessella_eval_patch(owner >> 2u, c);
                n = corner_point.normal;
                dir = tessella_displace_direction(owner >> 2u, corner_point.l, n);
            }
            var uv = vec2<f32>(0.0);
            if (params.has_uv != 0u) {
                uv = input_uv(g);
            }
            write_vertex(local, input_vec3(params.positions_at, g), n, dir, uv);
            return;
        } else if (g < params.interior_base) {
            // Edges: evaluated on the owning face, stored from the lower vertex index up.
            let e = (g - params.edge_base) / m;
            let s = (g - params.edge_base) % m;
            let owner = mesh_u32[params.edge_owner_at + e];
            face = owner >> 2u;
            let k = owner & 3u;
            let step = select(m - 1u - s, s, forward(face, k, e));
            row = mesh_u32[params.edge_points_at + k * m + step];
        } else {
            let i = g - params.interior_base;
            face = i / params.interior_per_face;
            row = mesh_u32[params.interior_points_at + i % params.interior_per_face];
        }
    } else {
        face = g / params.points_per_face;
        row = g % params.points_per_face;
    }
    let sp = tessella_eval_patch(face, row);
    var p = sp.position;
    let code = mesh_u32[params.point_codes_at + row];
    if (params.weld == 0u && (code >> 30u) == 0u) {
        // Soup corners also copy the input position exactly.
        p = input_vec3(params.positions_at, corner(face, code & 3u));
    }
    var uv = vec2<f32>(0.0);
    if (params.has_uv != 0u) {
        uv = face_uv(face, sp.l);
    }
    write_vertex(local, p, sp.normal, tessella_displace_direction(face, sp.l, sp.normal), uv);
}

// One output vertex of an adaptive plan (tessella-core's AdaptiveJob): the lookup names the face
// that evaluates it and its row in the tiles' concatenated stencil. Corners copy the input
// position; points on coarse edges are evaluated canonically by eval_patch (the edge table has
// every tile's rows); a coarse vertex no face uses keeps its input normal.
fn adaptive_vertex(local: u32, g: u32) {
    let face = mesh_u32[params.lookup_at + g * 2u];
    let word = mesh_u32[params.lookup_at + g * 2u + 1u];
    if (face == NONE) {
        var uv = vec2<f32>(0.0);
        if (params.has_uv != 0u) {
            uv = input_uv(word);
        }
        let n = input_vec3(params.normals_at, word);
        write_vertex(local, input_vec3(params.positions_at, word), n, n, uv);
        return;
    }
    let row = word & 0x3fffffffu;
    let c = word >> 30u;
    let sp = tessella_eval_patch(face, row);
    var p = sp.position;
    if (c != 0u) {
        p = input_vec3(params.positions_at, corner(face, c - 1u));
    }
    var uv = vec2<f32>(0.0);
    if (params.has_uv != 0u) {
        uv = face_uv(face, sp.l);
    }
    write_vertex(local, p, sp.normal, tessella_displace_direction(face, sp.l, sp.normal), uv);
}

// Output vertex of pattern point `p` on `face` (the CPU's welded_triangles map).
fn output_vertex(face: u32, p: u32) -> u32 {
    if (params.weld == 0u) {
        return face * params.points_per_face + p;
    }
    let code = mesh_u32[params.point_codes_at + p];
    let kind = code >> 30u;
    if (kind == 0u) {
        return corner(face, code & 3u);
    }
    if (kind == 1u) {
        let m = params.level - 1u;
        let k = (code >> 28u) & 3u;
        let s = code & 0x0fffffffu;
        let e = mesh_u32[params.face_edges_at + face * 3u + k];
        return params.edge_base + e * m + select(m - 1u - s, s, forward(face, k, e));
    }
    return params.interior_base + face * params.interior_per_face + (code & 0x3fffffffu);
}

@compute @workgroup_size(64)
fn refine_indices(@builtin(global_invocation_id) gid: vec3<u32>) {
    let local = gid.x;
    if (local >= params.count) {
        return;
    }
    let t = params.first + local;
    let per_face = params.level * params.level;
    let face = t / per_face;
    let j = t % per_face;
    for (var c = 0u; c < 3u; c++) {
        let p = mesh_u32[params.pattern_triangles_at + j * 3u + c];
        out_words[local * 3u + c] = output_vertex(face, p);
    }
}
