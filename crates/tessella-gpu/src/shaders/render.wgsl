// Instanced rendering with a refinement pattern (GMR section 3.2): the pattern's points are one
// vertex buffer (a stencil row index per point), drawn once per coarse triangle (instance); the
// vertex shader evaluates the instance's patch at the row. Blinn-Phong shading, optional
// wireframe of the pattern. Prepended: eval.wgsl, displace.wgsl.

struct RenderUniforms {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light_dir: vec4<f32>,
    base_color: vec4<f32>,
    wire_color: vec4<f32>, // a: line width in pixels
    flags: vec4<u32>,      // x: wireframe, y: pattern level, z: facet normals
}

@group(1) @binding(0) var<uniform> u: RenderUniforms;
// Per coarse triangle: its three corners' texture coordinates (6 floats), for height maps.
@group(1) @binding(1) var<storage, read> face_uvs: array<f32>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) l: vec3<f32>,
}

@vertex
fn vs_pattern(@location(0) row: u32, @builtin(instance_index) face: u32) -> VsOut {
    let sp = eval_patch(face, row);
    var p = sp.position;
    if (displace_params.kind != 0u) {
        let i = face * 6u;
        let l = sp.l;
        let uv = vec2<f32>(
            l.x * face_uvs[i] + l.y * face_uvs[i + 2u] + l.z * face_uvs[i + 4u],
            l.x * face_uvs[i + 1u] + l.y * face_uvs[i + 3u] + l.z * face_uvs[i + 5u],
        );
        p += displacement(p, uv) * displace_direction(face, l, sp.normal);
    }
    var out: VsOut;
    out.clip = u.view_proj * vec4<f32>(p, 1.0);
    out.world = p;
    out.normal = sp.normal;
    out.l = sp.l;
    return out;
}

// A static, fully refined vertex buffer (the baseline of GMR Figure 7).
@vertex
fn vs_static(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VsOut {
    var out: VsOut;
    out.clip = u.view_proj * vec4<f32>(position, 1.0);
    out.world = position;
    out.normal = normal;
    out.l = vec3<f32>(0.5);
    return out;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Derivatives first, in uniform control flow.
    let facet = cross(dpdx(in.world), dpdy(in.world));
    let grid = in.l * f32(u.flags.y);
    let grid_width = fwidth(grid);

    let view = normalize(u.eye.xyz - in.world);
    var n = normalize(in.normal);
    if (u.flags.z != 0u && dot(facet, facet) > 0.0) {
        n = normalize(facet);
        if (dot(n, view) < 0.0) {
            n = -n;
        }
    } else if (!front) {
        n = -n;
    }
    let light = u.light_dir.xyz;
    let half_vector = normalize(light + view);
    let diffuse = max(dot(n, light), 0.0);
    let specular = pow(max(dot(n, half_vector), 0.0), 48.0) * select(0.0, 1.0, diffuse > 0.0);
    var color = u.base_color.rgb * (0.12 + 0.88 * diffuse) + vec3<f32>(0.35 * specular);

    if (u.flags.x != 0u) {
        // Pattern edges are where some l_i * N is an integer; distance to them in pixels.
        let d = abs(grid - round(grid)) / max(grid_width, vec3<f32>(1e-6));
        let dist = min(d.x, min(d.y, d.z));
        let line = 1.0 - smoothstep(u.wire_color.a - 0.5, u.wire_color.a + 0.5, dist);
        color = mix(color, u.wire_color.rgb, line);
    }
    return vec4<f32>(color, 1.0);
}
