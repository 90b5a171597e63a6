// Displacement of evaluated surface points (GMR section 4): an offset along a direction.
// The offsets are generated from tessella-core's displace.rs (shader::displace_wgsl); this
// file holds the bindings, their reads, the choice of kind and the direction, whose Rust twin
// is FaceFrame::direction (it reads the face records this file's bindings hold); the
// GPU-vs-CPU tests compare them.

// TessellaDisplaceParams is printed from its Rust twin (gpu_types.rs) before this file.

@group(0) @binding(4) var<uniform> tessella_displace_params: TessellaDisplaceParams;
// Kind 2: Perlin's permutation, 512 entries (as f32). Kind 3: heights, row 0 at the image top.
// Then, from faces_at, per coarse face: mask, M1, M2, M3 (10 floats; core's FaceFrame).
@group(0) @binding(5) var<storage, read> tessella_displace_data: array<f32>;

// The reads the generated offsets (tessella_core::shader::displace_wgsl: tessella_perlin,
// tessella_height_map, tessella_sine, from the Rust source in tessella-core's displace.rs) call.
fn tessella_perm(i: u32) -> u32 {
    return u32(tessella_displace_data[i]);
}

// Texel (x, y), signed coordinates as u32 bits, repeating; row 0 at the image top.
fn tessella_height_texel(xw: u32, yw: u32) -> f32 {
    let x = bitcast<i32>(xw);
    let y = bitcast<i32>(yw);
    let w = i32(tessella_displace_params.map_width);
    let h = i32(tessella_displace_params.map_height);
    let xx = ((x % w) + w) % w;
    let yy = ((y % h) + h) % h;
    return tessella_displace_data[yy * w + xx];
}

// The scalar offset along the unit normal at surface point `p` with texture coordinate `uv`.
fn tessella_displacement(p: vec3<f32>, uv: vec2<f32>) -> f32 {
    let a = tessella_displace_params.amplitude;
    let f = tessella_displace_params.frequency;
    switch TESSELLA_DISPLACE_KIND {
        case 1u: { return tessella_sine(a, f, p); }
        case 2u: { return a * tessella_perlin(f * p); }
        case 3u: {
            let size = vec2<f32>(f32(tessella_displace_params.map_width), f32(tessella_displace_params.map_height));
            return a * tessella_height_map(uv, size);
        }
        default: { return 0.0; }
    }
}

// The direction a refined point moves along: FaceFrame::direction. `l` is the point's
// barycentric coordinates on coarse triangle `face`, exactly as the stencil stores them (corner
// c: l_c == 1; inside edge k, from corner k to k+1: the opposite coordinate is 0), `n` its
// refined normal. Split corners and points inside split edges (mask bits 3+c and k) move along
// normalize(l1 M1 + l2 M2 + l3 M3), the same on both sides of a hard edge, so it stays closed;
// every other point (and a vanishing sum) along n.
fn tessella_displace_direction(face: u32, l: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    if (TESSELLA_DISPLACE_KIND == 0u || tessella_displace_params.faces_at == 0xffffffffu) {
        return n;
    }
    let at = tessella_displace_params.faces_at + face * 10u;
    let mask = u32(tessella_displace_data[at]);
    // No split corner or edge: n, as tessella_direction gives it, without its work.
    if (mask == 0u) {
        return n;
    }
    let m1 = vec3<f32>(tessella_displace_data[at + 1u], tessella_displace_data[at + 2u], tessella_displace_data[at + 3u]);
    let m2 = vec3<f32>(tessella_displace_data[at + 4u], tessella_displace_data[at + 5u], tessella_displace_data[at + 6u]);
    let m3 = vec3<f32>(tessella_displace_data[at + 7u], tessella_displace_data[at + 8u], tessella_displace_data[at + 9u]);
    return tessella_direction(mask, m1, m2, m3, l, n);
}
