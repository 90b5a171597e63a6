// tessella-view's shading (appearance.rs), appended to tessella-gpu's vertex stage, which
// calls `shade_vertex` with each drawn point (a `TessellaVertex`). Blinn-Phong shading under one
// light, an optional scalar field through a colormap, an optional wireframe of the pattern:
// coarse edges bold and dark, the pattern's own edges thin and light, fading out where they
// would be denser than a few pixels. Prepended from Rust: COLORMAP_ENTRIES and the generated
// `tessella_p2_weights` (tessella_core::shader).

struct RenderUniforms {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light_dir: vec4<f32>,
    base_color: vec4<f32>,
    wire_color: vec4<f32>, // coarse edges; a: their largest half-width in pixels
    flags: vec4<u32>,      // x: wireframe, y: unused, z: facet normals,
                           // w: 1 << 24 | sRGB8 colour of back faces (the inside seen through
                           //    a crack), 0: back faces shaded like front ones
}

@group(1) @binding(0) var<uniform> u: RenderUniforms;
// Per coarse triangle: a scalar field's P2 net (corners, then mid-edges 0-1, 1-2, 2-0).
@group(1) @binding(1) var<storage, read> face_field: array<f32>;
// [low, high, samples, 0], then `samples` sRGB colours; samples 0: no field colouring. A
// uniform, so the vertex stage binds one storage buffer here beside the renderer's seven
// (WebGPU's default limit is eight).
@group(1) @binding(2) var<uniform> colormap: array<vec4<f32>, COLORMAP_ENTRIES>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) l: vec3<f32>,
    // Barycentric coordinates inside the pattern triangle (unrolled draws only).
    @location(3) tri: vec3<f32>,
    // x: the field's value, y: 1 where the vertex has one.
    @location(4) field: vec2<f32>,
}

fn shade_vertex(v: TessellaVertex) -> VsOut {
    var out: VsOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.l = v.l;
    out.tri = v.corner;
    out.field = vec2<f32>(0.0);
    if (colormap[0].z > 0.0) {
        // A point of an already refined vertex buffer has no face and keeps the base colour:
        // a select, not `&&` in the condition, which lavapipe miscompiles (it crashes).
        let on = v.face != TESSELLA_NO_FACE;
        let i = select(0u, v.face * 6u, on);
        // Constant indices into the generated weights.
        let w = tessella_p2_weights(v.l);
        let value = w[0] * face_field[i] + w[1] * face_field[i + 1u] + w[2] * face_field[i + 2u]
            + w[3] * face_field[i + 3u] + w[4] * face_field[i + 4u] + w[5] * face_field[i + 5u];
        out.field = vec2<f32>(value, select(0.0, 1.0, on));
    }
    return out;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Derivatives first, in uniform control flow.
    let facet = cross(dpdx(in.world), dpdy(in.world));
    let coarse_width = fwidth(in.l);
    let tri_width = fwidth(in.tri);

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
    let cm = colormap[0];
    if (cm.z > 0.0 && in.field.y > 0.5) {
        // The colormap's samples spread over [low, high], interpolated in sRGB; lit diffusely
        // only (a white highlight would read as another value).
        let n_samples = u32(cm.z);
        let t = clamp((in.field.x - cm.x) / max(cm.y - cm.x, 1e-30), 0.0, 1.0);
        let s = t * f32(n_samples - 1u);
        let k = min(u32(floor(s)), n_samples - 1u);
        let k1 = min(k + 1u, n_samples - 1u);
        let c = mix(colormap[1u + k].rgb, colormap[1u + k1].rgb, s - f32(k));
        let lin = select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
        color = lin * (0.3 + 0.7 * diffuse);
    }

    if (u.flags.x != 0u) {
        // Distances in pixels to the pattern triangle's edges and to the coarse edges.
        let tri_d = in.tri / max(tri_width, vec3<f32>(1e-6));
        let coarse_d = in.l / max(coarse_width, vec3<f32>(1e-6));
        // Sizes in pixels (across one barycentric unit) of the pattern and coarse triangles.
        let tri_px = 1.0 / max(max(tri_width.x, tri_width.y), max(tri_width.z, 1e-6));
        let coarse_px = 1.0 / max(max(coarse_width.x, coarse_width.y), max(coarse_width.z, 1e-6));
        // Pattern edges: thin, a darker shade of the surface, fading out below 3-8 pixels.
        let fine = 1.0 - smoothstep(0.0, 0.9, min(tri_d.x, min(tri_d.y, tri_d.z)));
        let fine_alpha = 0.45 * smoothstep(3.0, 8.0, tri_px);
        color = mix(color, color * 0.45, fine * fine_alpha);
        // Coarse edges: bold and dark, thinner (never below a hairline) on small triangles.
        let half = clamp(0.06 * coarse_px, 0.35, u.wire_color.a);
        let dist = min(coarse_d.x, min(coarse_d.y, coarse_d.z));
        let line = 1.0 - smoothstep(half - 0.5, half + 0.5, dist);
        color = mix(color, u.wire_color.rgb, line);
    }
    if (!front && u.flags.w != 0u) {
        let c = vec3<f32>(f32(u.flags.w & 255u), f32((u.flags.w >> 8u) & 255u), f32((u.flags.w >> 16u) & 255u)) / 255.0;
        // sRGB to linear (the target re-encodes).
        color = select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
    }
    return vec4<f32>(color, 1.0);
}
