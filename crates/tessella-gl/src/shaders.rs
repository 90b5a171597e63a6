//! The GLSL of the backend. The cubic Bernstein weights are generated from
//! [`CUBIC_ORDER`](tessella_core::basis::CUBIC_ORDER) (the table `Basis::Cubic` and the stencils
//! use); PNG1's weights follow `tessella_core::basis::png1` line by line, as dual numbers
//! `(value, ∂u, ∂v)` in a `vec3`, and are tied to it by the CPU comparison tests.

use tessella_core::basis::CUBIC_ORDER;
use tessella_core::tessellator::Spacing;

/// The four stages' sources for one spacing.
#[derive(Debug, Clone)]
pub struct ShaderSources {
    pub vertex: String,
    pub control: String,
    pub evaluation: String,
    pub fragment: String,
}

const HEADER: &str = "#version 430 core\n";

const VERTEX: &str = "void main() {}\n";

/// Levels: a uniform, or per face from a buffer (GL order: outer[0] is the edge l1 = 0).
const CONTROL: &str = r#"
layout(vertices = 1) out;
uniform int u_per_face;
uniform float u_level;
layout(std430, binding = 2) readonly buffer Levels { float levels[]; };
void main() {
    if (gl_InvocationID == 0) {
        if (u_per_face != 0) {
            int b = gl_PrimitiveID * 4;
            gl_TessLevelOuter[0] = levels[b];
            gl_TessLevelOuter[1] = levels[b + 1];
            gl_TessLevelOuter[2] = levels[b + 2];
            gl_TessLevelInner[0] = levels[b + 3];
        } else {
            gl_TessLevelOuter[0] = u_level;
            gl_TessLevelOuter[1] = u_level;
            gl_TessLevelOuter[2] = u_level;
            gl_TessLevelInner[0] = u_level;
        }
    }
}
"#;

/// Dual numbers and PNG1's weights (basis/png1.rs `weights_dual`).
const PNG1: &str = r#"
vec3 dmul(vec3 a, vec3 b) { return vec3(a.x * b.x, a.y * b.x + a.x * b.y, a.z * b.x + a.x * b.z); }
vec3 ddiv(vec3 a, vec3 b) {
    float q = a.x / b.x;
    return vec3(q, (a.y - q * b.y) / b.x, (a.z - q * b.z) / b.x);
}
void png1_weights(vec3 bl, out vec3 w[21]) {
    vec3 l[3] = vec3[3](vec3(bl.x, -1.0, -1.0), vec3(bl.y, 1.0, 0.0), vec3(bl.z, 0.0, 1.0));
    vec3 one = vec3(1.0, 0.0, 0.0);
    for (int i = 0; i < 21; ++i) { w[i] = vec3(0.0); }
    for (int i = 0; i < 3; ++i) { w[i] = dmul(dmul(l[i], l[i]), l[i]); }
    for (int k = 0; k < 3; ++k) {
        vec3 a = l[k];
        vec3 b = l[(k + 1) % 3];
        vec3 c = l[(k + 2) % 3];
        vec3 own = dmul(one - c, one - c);
        vec3 crs = dmul(c, c);
        vec3 den = own + crs;
        own = ddiv(own, den);
        crs = ddiv(crs, den);
        vec3 near_a = 3.0 * dmul(dmul(a, a), b);
        vec3 near_b = 3.0 * dmul(dmul(a, b), b);
        int sa = 3 + (4 * k) % 12;
        int sb = 3 + (4 * k + 2) % 12;
        w[sa] = dmul(near_a, own);
        w[sa + 1] = dmul(near_a, crs);
        w[sb] = dmul(near_b, own);
        w[sb + 1] = dmul(near_b, crs);
    }
    vec3 sigma = dmul(l[0], l[1]) + dmul(l[1], l[2]) + dmul(l[2], l[0]);
    if (sigma.x != 0.0) {
        vec3 b111 = 6.0 * dmul(dmul(l[0], l[1]), l[2]);
        for (int k = 0; k < 3; ++k) {
            vec3 a = l[k];
            vec3 b = l[(k + 1) % 3];
            vec3 den = a + b - 2.0 * dmul(a, b);
            if (den.x == 0.0) { continue; }
            vec3 t = ddiv(ddiv(dmul(b111, dmul(a, b)), sigma), den);
            w[15 + 2 * k] = dmul(t, dmul(one - b, a));
            w[16 + 2 * k] = dmul(t, dmul(one - a, b));
        }
    }
}
"#;

/// Position, normal (net or `Du × Dv`), tessellation coordinate and face, for transform
/// feedback and for drawing.
const EVALUATION: &str = r#"
uniform int u_k;
uniform int u_real;
uniform mat4 u_view_proj;
layout(std430, binding = 0) readonly buffer Points { float pts[]; };
layout(std430, binding = 1) readonly buffer Normals { float nrm[]; };
out vec3 tf_position;
out vec3 tf_normal;
out vec3 tf_coord;
flat out int tf_face;
vec3 ctrl(int f, int k) { int b = (f * u_k + k) * 3; return vec3(pts[b], pts[b + 1], pts[b + 2]); }
vec3 nctrl(int f, int k) { int b = (f * 6 + k) * 3; return vec3(nrm[b], nrm[b + 1], nrm[b + 2]); }
void main() {
    // gl_TessCoord (u, v, w) is (l1, l2, l3): u = 1 at P1 (tessella_core::tessellator).
    vec3 l = gl_TessCoord;
    int f = gl_PrimitiveID;
    vec3 w[21];
    if (u_k == 21) { png1_weights(l, w); } else { cubic_weights(l, w); }
    vec3 p = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int k = 0; k < u_k; ++k) {
        vec3 c = ctrl(f, k);
        p += w[k].x * c;
        du += w[k].y * c;
        dv += w[k].z * c;
    }
    vec3 n = vec3(0.0);
    if (u_real != 0) {
        vec3 c = cross(du, dv);
        if (dot(c, c) > 1e-12 * dot(du, du) * dot(dv, dv)) { n = c; }
    }
    if (n == vec3(0.0)) {
        float nw[6] = float[6](l.x * l.x, l.y * l.y, l.z * l.z, l.x * l.y, l.y * l.z, l.z * l.x);
        for (int j = 0; j < 6; ++j) { n += nw[j] * nctrl(f, j); }
    }
    float len = length(n);
    if (len > 0.0 && !isinf(len)) {
        n /= len;
    } else {
        vec3 a = ctrl(f, 0);
        vec3 e = cross(ctrl(f, 1) - a, ctrl(f, 2) - a);
        n = length(e) > 0.0 ? normalize(e) : vec3(0.0, 0.0, 1.0);
    }
    tf_position = p;
    tf_normal = n;
    tf_coord = l;
    tf_face = f;
    gl_Position = u_view_proj * vec4(p, 1.0);
}
"#;

/// Colour by normal (the paper's pictures), for drawing.
const FRAGMENT: &str = r#"
in vec3 tf_normal;
uniform int u_wire;
out vec4 colour;
void main() {
    colour = u_wire != 0 ? vec4(0.05, 0.06, 0.1, 1.0) : vec4(0.5 * normalize(tf_normal) + 0.5, 1.0);
}
"#;

fn power(var: &str, n: u8) -> String {
    match n {
        0 => "1.0".into(),
        _ => vec![var; n as usize].join(" * "),
    }
}

fn factorial(n: u8) -> f64 {
    (1..=n as u32).product::<u32>() as f64
}

/// `cubic_weights`: the Bernstein polynomials of [`CUBIC_ORDER`] and their `Du`, `Dv`
/// (`Du = ∂/∂l2 − ∂/∂l1`, `Dv = ∂/∂l3 − ∂/∂l1`), generated term by term.
pub fn cubic_glsl() -> String {
    let vars = ["l.x", "l.y", "l.z"];
    let mut s = String::from("void cubic_weights(vec3 l, out vec3 w[21]) {\n");
    s += "    for (int i = 10; i < 21; ++i) { w[i] = vec3(0.0); }\n";
    for (k, e) in CUBIC_ORDER.iter().enumerate() {
        let c = 6.0 / (factorial(e[0]) * factorial(e[1]) * factorial(e[2]));
        let mono = |d: Option<usize>| -> String {
            match d {
                Some(m) if e[m] == 0 => "0.0".into(),
                _ => {
                    let coef = c * d.map_or(1.0, |m| e[m] as f64);
                    let mut parts = vec![format!("{coef:?}")];
                    for (i, v) in vars.iter().enumerate() {
                        let p = e[i] - u8::from(d == Some(i));
                        if p > 0 {
                            parts.push(power(v, p));
                        }
                    }
                    parts.join(" * ")
                }
            }
        };
        let (d1, d2, d3) = (mono(Some(0)), mono(Some(1)), mono(Some(2)));
        s += &format!(
            "    w[{k}] = vec3({}, ({d2}) - ({d1}), ({d3}) - ({d1}));\n",
            mono(None)
        );
    }
    s += "}\n";
    s
}

fn layout(spacing: Spacing) -> &'static str {
    match spacing {
        Spacing::Equal => "equal_spacing",
        Spacing::FractionalOdd => "fractional_odd_spacing",
        Spacing::FractionalEven => "fractional_even_spacing",
    }
}

/// The sources for `spacing`.
pub fn glsl_sources(spacing: Spacing) -> ShaderSources {
    ShaderSources {
        vertex: format!("{HEADER}{VERTEX}"),
        control: format!("{HEADER}{CONTROL}"),
        evaluation: format!(
            "{HEADER}layout(triangles, {}, ccw) in;\n{}{PNG1}{EVALUATION}",
            layout(spacing),
            cubic_glsl()
        ),
        fragment: format!("{HEADER}{FRAGMENT}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_is_generated_for_every_control_point() {
        let s = cubic_glsl();
        for k in 0..10 {
            assert!(s.contains(&format!("w[{k}] = vec3(")), "{s}");
        }
        // b111 = 6 l1 l2 l3
        assert!(s.contains("w[9] = vec3(6.0 * l.x * l.y * l.z"), "{s}");
    }
}
