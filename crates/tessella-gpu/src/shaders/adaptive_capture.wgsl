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
    captured[o] = sp.position.x;
    captured[o + 1u] = sp.position.y;
    captured[o + 2u] = sp.position.z;
    captured[o + 3u] = sp.normal.x;
    captured[o + 4u] = sp.normal.y;
    captured[o + 5u] = sp.normal.z;
    captured[o + 6u] = sp.l.x;
    captured[o + 7u] = sp.l.y;
    captured[o + 8u] = sp.l.z;
}
