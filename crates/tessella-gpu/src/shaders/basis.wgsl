// PNG1's basis weights at a barycentric point, for pipelines whose points are not a stencil's
// rows (adaptive.wgsl: fractional levels move the points every frame; its cubic case is written
// out there). The twin of tessella_core::basis::png1 (`weights_dual`, as dual numbers
// (value, d/du, d/dv)). Each weight is a vec3: value, Du, Dv, with Du = d/dl2 - d/dl1 and
// Dv = d/dl3 - d/dl1.

const PNG1_K: u32 = 21u;

fn dmul(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.x * b.x, a.y * b.x + a.x * b.y, a.z * b.x + a.x * b.z);
}

fn ddiv(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let q = a.x / b.x;
    return vec3<f32>(q, (a.y - q * b.y) / b.x, (a.z - q * b.z) / b.x);
}

// PNG1's 21 weights (PNG1_ORDER): corners, per edge own/cross versions of its two slots, then
// per edge the two centre candidates.
fn png1_weights(bl: vec3<f32>, w: ptr<function, array<vec3<f32>, 21>>) {
    var l = array<vec3<f32>, 3>(
        vec3<f32>(bl.x, -1.0, -1.0),
        vec3<f32>(bl.y, 1.0, 0.0),
        vec3<f32>(bl.z, 0.0, 1.0),
    );
    let one = vec3<f32>(1.0, 0.0, 0.0);
    for (var i = 0u; i < 21u; i++) {
        (*w)[i] = vec3<f32>(0.0);
    }
    for (var i = 0u; i < 3u; i++) {
        (*w)[i] = dmul(dmul(l[i], l[i]), l[i]);
    }
    for (var k = 0u; k < 3u; k++) {
        let a = l[k];
        let b = l[(k + 1u) % 3u];
        let c = l[(k + 2u) % 3u];
        var own = dmul(one - c, one - c);
        var crs = dmul(c, c);
        let den = own + crs;
        own = ddiv(own, den);
        crs = ddiv(crs, den);
        let near_a = 3.0 * dmul(dmul(a, a), b);
        let near_b = 3.0 * dmul(dmul(a, b), b);
        let sa = 3u + (4u * k) % 12u;
        let sb = 3u + (4u * k + 2u) % 12u;
        (*w)[sa] = dmul(near_a, own);
        (*w)[sa + 1u] = dmul(near_a, crs);
        (*w)[sb] = dmul(near_b, own);
        (*w)[sb + 1u] = dmul(near_b, crs);
    }
    let sigma = dmul(l[0], l[1]) + dmul(l[1], l[2]) + dmul(l[2], l[0]);
    if (sigma.x != 0.0) {
        let b111 = 6.0 * dmul(dmul(l[0], l[1]), l[2]);
        for (var k = 0u; k < 3u; k++) {
            let a = l[k];
            let b = l[(k + 1u) % 3u];
            let den = a + b - 2.0 * dmul(a, b);
            if (den.x == 0.0) {
                continue;
            }
            let t = ddiv(ddiv(dmul(b111, dmul(a, b)), sigma), den);
            (*w)[15u + 2u * k] = dmul(t, dmul(one - b, a));
            (*w)[16u + 2u * k] = dmul(t, dmul(one - a, b));
        }
    }
}
