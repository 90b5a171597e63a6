// Reads back what the adaptive renderer draws: one job per drawn vertex, `(instance word, point
// code)`, written as position, normal and barycentric point (9 floats). Prepended: the generated
// weights (adaptive.rs), adaptive.wgsl.

@group(1) @binding(0) var<storage, read> jobs: array<vec2<u32>>;
@group(1) @binding(1) var<storage, read_write> captured: array<f32>;

@compute @workgroup_size(64)
fn cs_capture(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.x + id.y * groups.x * 64u;
    if (i >= arrayLength(&jobs)) {
        return;
    }
    let job = jobs[i];
    let sp = tessella_adaptive_point(job.y, job.x);
    let o = i * 9u;
    let columns = mat3x3<f32>(sp.position, sp.normal, sp.l);
    for (var k = 0u; k < 9u; k++) {
        captured[o + k] = columns[k / 3u][k % 3u];
    }
}
