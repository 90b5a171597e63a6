// Displacement of evaluated surface points (GMR section 4): an offset along a direction.
// Mirrors tessella-core's src/displace.rs (the Rust twin: offsets, FaceFrame::direction):
// change both together; the GPU-vs-CPU tests compare them.

struct TessellaDisplaceParams {
    // The kind is the constant TESSELLA_DISPLACE_KIND (patch.rs compiles it in): 0 none,
    // 1 sine a*sin(f*|P|), 2 Perlin a*noise(f*P), 3 height map a*h(uv).
    amplitude: f32,
    frequency: f32,
    map_width: u32,
    map_height: u32,
    faces_at: u32, // first face record in displace_data, or 0xffffffff for none
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(4) var<uniform> tessella_displace_params: TessellaDisplaceParams;
// Kind 2: Perlin's permutation, 512 entries (as f32). Kind 3: heights, row 0 at the image top.
// Then, from faces_at, per coarse face: mask, M1, M2, M3 (10 floats; core's FaceFrame).
@group(0) @binding(5) var<storage, read> tessella_displace_data: array<f32>;

fn tessella_perm(i: i32) -> i32 {
    return i32(tessella_displace_data[i & 511]);
}

// a + t (b - a), written out so the Rust twin rounds the same way.
fn tessella_lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + t * (b - a);
}

fn tessella_fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Gradient of Perlin's "Improving noise" (2002): 12 cube-edge directions, chosen by 4 hash bits.
fn tessella_grad(hash: i32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15;
    let u = select(y, x, h < 8);
    var v = z;
    if (h < 4) {
        v = y;
    } else if (h == 12 || h == 14) {
        v = x;
    }
    return select(-u, u, (h & 1) == 0) + select(-v, v, (h & 2) == 0);
}

fn tessella_perlin(p: vec3<f32>) -> f32 {
    let f = floor(p);
    let xi = i32(f.x) & 255;
    let yi = i32(f.y) & 255;
    let zi = i32(f.z) & 255;
    let x = p.x - f.x;
    let y = p.y - f.y;
    let z = p.z - f.z;
    let u = tessella_fade(x);
    let v = tessella_fade(y);
    let w = tessella_fade(z);
    let a = tessella_perm(xi) + yi;
    let aa = tessella_perm(a) + zi;
    let ab = tessella_perm(a + 1) + zi;
    let b = tessella_perm(xi + 1) + yi;
    let ba = tessella_perm(b) + zi;
    let bb = tessella_perm(b + 1) + zi;
    let x1 = tessella_lerp(tessella_grad(tessella_perm(aa), x, y, z), tessella_grad(tessella_perm(ba), x - 1.0, y, z), u);
    let x2 = tessella_lerp(tessella_grad(tessella_perm(ab), x, y - 1.0, z), tessella_grad(tessella_perm(bb), x - 1.0, y - 1.0, z), u);
    let y1 = tessella_lerp(x1, x2, v);
    let x3 = tessella_lerp(tessella_grad(tessella_perm(aa + 1), x, y, z - 1.0), tessella_grad(tessella_perm(ba + 1), x - 1.0, y, z - 1.0), u);
    let x4 = tessella_lerp(tessella_grad(tessella_perm(ab + 1), x, y - 1.0, z - 1.0), tessella_grad(tessella_perm(bb + 1), x - 1.0, y - 1.0, z - 1.0), u);
    let y2 = tessella_lerp(x3, x4, v);
    return tessella_lerp(y1, y2, w);
}

fn tessella_height_texel(x: i32, y: i32) -> f32 {
    let w = i32(tessella_displace_params.map_width);
    let h = i32(tessella_displace_params.map_height);
    let xx = ((x % w) + w) % w;
    let yy = ((y % h) + h) % h;
    return tessella_displace_data[yy * w + xx];
}

// Bilinear, repeating; v = 0 is the image's bottom row.
fn tessella_height_map(uv: vec2<f32>) -> f32 {
    let px = uv.x * f32(tessella_displace_params.map_width) - 0.5;
    let py = (1.0 - uv.y) * f32(tessella_displace_params.map_height) - 0.5;
    let x0 = floor(px);
    let y0 = floor(py);
    let tx = px - x0;
    let ty = py - y0;
    let ix = i32(x0);
    let iy = i32(y0);
    let top = tessella_lerp(tessella_height_texel(ix, iy), tessella_height_texel(ix + 1, iy), tx);
    let bottom = tessella_lerp(tessella_height_texel(ix, iy + 1), tessella_height_texel(ix + 1, iy + 1), tx);
    return tessella_lerp(top, bottom, ty);
}

// The scalar offset along the unit normal at surface point `p` with texture coordinate `uv`.
fn tessella_displacement(p: vec3<f32>, uv: vec2<f32>) -> f32 {
    let a = tessella_displace_params.amplitude;
    let f = tessella_displace_params.frequency;
    switch TESSELLA_DISPLACE_KIND {
        case 1u: { return a * sin(f * length(p)); }
        case 2u: { return a * tessella_perlin(f * p); }
        case 3u: { return a * tessella_height_map(uv); }
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
    if (mask == 0u) {
        return n;
    }
    var bit = 0u;
    if (l.x == 1.0) {
        bit = 8u;
    } else if (l.y == 1.0) {
        bit = 16u;
    } else if (l.z == 1.0) {
        bit = 32u;
    } else if (l.z == 0.0) {
        bit = 1u;
    } else if (l.x == 0.0) {
        bit = 2u;
    } else if (l.y == 0.0) {
        bit = 4u;
    }
    if ((mask & bit) == 0u) {
        return n;
    }
    let m1 = vec3<f32>(tessella_displace_data[at + 1u], tessella_displace_data[at + 2u], tessella_displace_data[at + 3u]);
    let m2 = vec3<f32>(tessella_displace_data[at + 4u], tessella_displace_data[at + 5u], tessella_displace_data[at + 6u]);
    let m3 = vec3<f32>(tessella_displace_data[at + 7u], tessella_displace_data[at + 8u], tessella_displace_data[at + 9u]);
    let s = l.x * m1 + l.y * m2 + l.z * m3;
    let len2 = dot(s, s);
    if (!(len2 > 1e-12)) {
        return n;
    }
    return s / sqrt(len2);
}
