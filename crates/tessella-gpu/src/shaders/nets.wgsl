// Control nets built on the GPU from the caller's coarse vertices (net_builder.rs): one thread
// per face writes its K cubic control points and its six normal-net entries, in the layout of
// tessella-core's PatchNets (points[f*K..], normals[f*6..]), with the builders generated from
// the CPU's own Rust (tessella_core::shader::net_builder). The scheme's call,
// `tessella_nets_points(face, p, n)`, and the normal net's, `tessella_nets_normals(p, n)`, are
// prepended from Rust with the builders, TESSELLA_NETS_K and TESSELLA_NORMAL_NET_LEN.

// NetsParams is printed from its Rust twin (gpu_types.rs) before this file.

@group(0) @binding(0) var<uniform> params: NetsParams;
// The triangles (3 words a face), then PN-AEN's across table (6 vertices a face).
@group(0) @binding(1) var<storage, read> topology: array<u32>;
// The caller's buffers, bound from their offsets (they may be one interleaved buffer).
@group(0) @binding(2) var<storage, read> in_positions: array<f32>;
@group(0) @binding(3) var<storage, read> in_normals: array<f32>;
@group(0) @binding(4) var<storage, read_write> out_points: array<f32>;
@group(0) @binding(5) var<storage, read_write> out_normals: array<f32>;
// The evaluator's coarse vertices (corners copy them), or a placeholder.
@group(0) @binding(6) var<storage, read_write> out_coarse: array<f32>;

fn coarse_position(v: u32) -> vec3<f32> {
    let i = v * params.positions_stride + params.positions_first;
    return vec3<f32>(in_positions[i], in_positions[i + 1u], in_positions[i + 2u]);
}

// Normalised in f32, as tessella_core::Mesh normalises given normals (in f64).
fn coarse_normal(v: u32) -> vec3<f32> {
    let i = v * params.normals_stride + params.normals_first;
    let n = vec3<f32>(in_normals[i], in_normals[i + 1u], in_normals[i + 2u]);
    return n / sqrt(dot(n, n));
}

// WGSL passes no storage pointers to functions: one writer per output.
fn put_point(i: u32, v: vec3<f32>) {
    out_points[i] = v.x;
    out_points[i + 1u] = v.y;
    out_points[i + 2u] = v.z;
}

fn put_normal(i: u32, v: vec3<f32>) {
    out_normals[i] = v.x;
    out_normals[i + 1u] = v.y;
    out_normals[i + 2u] = v.z;
}

fn put_coarse(i: u32, v: vec3<f32>) {
    out_coarse[i] = v.x;
    out_coarse[i + 1u] = v.y;
    out_coarse[i + 2u] = v.z;
}

@compute @workgroup_size(64)
fn tessella_build_nets(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    // Rows of dispatches past the per-dimension limit (net_builder.rs).
    let i = gid.x + gid.y * groups.x * 64u;
    if (params.copy_coarse != 0u && i < params.vertices) {
        put_coarse(params.coarse_positions_at + i * 3u, coarse_position(i));
        put_coarse(params.coarse_normals_at + i * 3u, coarse_normal(i));
    }
    if (i >= params.faces) {
        return;
    }
    var p: array<vec3<f32>, 3>;
    var n: array<vec3<f32>, 3>;
    for (var c = 0u; c < 3u; c++) {
        let v = topology[i * 3u + c];
        p[c] = coarse_position(v);
        n[c] = coarse_normal(v);
    }
    var net = tessella_nets_points(i, p, n);
    for (var k = 0u; k < TESSELLA_NETS_K; k++) {
        put_point((i * TESSELLA_NETS_K + k) * 3u, net[k]);
    }
    var normals = tessella_nets_normals(p, n);
    for (var k = 0u; k < TESSELLA_NORMAL_NET_LEN; k++) {
        put_normal((i * TESSELLA_NORMAL_NET_LEN + k) * 3u, normals[k]);
    }
}
