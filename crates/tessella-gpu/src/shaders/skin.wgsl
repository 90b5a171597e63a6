// GPU skinning (skinner.rs): one thread per coarse vertex poses it from the frame's deform
// matrices and morph weights, as tessella_core::animation::Poser::pose_into does: morph
// targets first, then the vertex's matrices blended by its weights divided by their sum, the
// point moved by the blend, the normal by tessella_skin_normal (generated from
// tessella_core::animation::skin_normal_of: the cofactor matrix with the determinant's sign,
// renormalised, falling back to the morphed rest normal, else +Z). Prepended: the generated
// tessella_skin_normal.

// SkinParams is printed from its Rust twin (gpu_types.rs) before this file.

@group(0) @binding(0) var<uniform> params: SkinParams;
// Per vertex: rest position xyz, rest normal xyz; then the morph deltas.
@group(0) @binding(1) var<storage, read> rest: array<f32>;
// Per vertex and slot: (matrix index, weight bits); then the morph records.
@group(0) @binding(2) var<storage, read> table: array<u32>;
// Per frame: the deform matrices (column-major 4x4), then the morph weights.
@group(0) @binding(3) var<storage, read> frame: array<f32>;
// Per vertex `out_stride` f32: position xyz at `position_first`, normal xyz at
// `normal_first` (SKINNED_VERTEX_BYTES: 8 f32, at 0 and 4; the padding stays zero).
@group(0) @binding(4) var<storage, read_write> skinned: array<f32>;

fn rest_vec3(i: u32) -> vec3<f32> {
    return vec3<f32>(rest[i], rest[i + 1u], rest[i + 2u]);
}

fn matrix_column(m: u32, c: u32) -> vec4<f32> {
    let i = m * 16u + c * 4u;
    return vec4<f32>(frame[i], frame[i + 1u], frame[i + 2u], frame[i + 3u]);
}

@compute @workgroup_size(64)
fn cs_skin(@builtin(global_invocation_id) gid: vec3<u32>) {
    let v = gid.y * params.row + gid.x;
    if (v >= params.vertex_count) {
        return;
    }
    var p = rest_vec3(v * 6u);
    var n = rest_vec3(v * 6u + 3u);
    let record = params.morphs_at + v * 3u;
    let targets = table[record];
    let weight_base = params.weights_at + table[record + 1u];
    let delta_base = table[record + 2u];
    for (var t = 0u; t < targets; t = t + 1u) {
        let w = frame[weight_base + t];
        let d = (delta_base + t) * 3u;
        p = p + w * rest_vec3(params.deltas_at + d);
        n = n + w * rest_vec3(params.normal_deltas_at + d);
    }
    var c0 = vec4<f32>(0.0);
    var c1 = vec4<f32>(0.0);
    var c2 = vec4<f32>(0.0);
    var c3 = vec4<f32>(0.0);
    var sum = 0.0;
    for (var k = 0u; k < params.slots; k = k + 1u) {
        let e = (v * params.slots + k) * 2u;
        let m = table[e];
        let w = bitcast<f32>(table[e + 1u]);
        c0 = c0 + w * matrix_column(m, 0u);
        c1 = c1 + w * matrix_column(m, 1u);
        c2 = c2 + w * matrix_column(m, 2u);
        c3 = c3 + w * matrix_column(m, 3u);
        sum = sum + w;
    }
    let s = 1.0 / sum;
    c0 = c0 * s;
    c1 = c1 * s;
    c2 = c2 * s;
    c3 = c3 * s;
    let posed = c0.xyz * p.x + c1.xyz * p.y + c2.xyz * p.z + c3.xyz;
    let normal = tessella_skin_normal(mat3x3<f32>(c0.xyz, c1.xyz, c2.xyz), n);
    let o = v * params.out_stride;
    skinned[o + params.position_first] = posed.x;
    skinned[o + params.position_first + 1u] = posed.y;
    skinned[o + params.position_first + 2u] = posed.z;
    skinned[o + params.normal_first] = normal.x;
    skinned[o + params.normal_first + 1u] = normal.y;
    skinned[o + params.normal_first + 2u] = normal.z;
}
