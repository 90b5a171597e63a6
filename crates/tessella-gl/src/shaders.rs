//! The GLSL of the backend. The basis weights (cubic Bernstein, PNG1's rational weights as dual
//! numbers) and the normal net's weights are generated from tessella-core's own Rust functions
//! ([`tessella_core::shader`]); what is written here is the stages' own code: the levels, the
//! control shader's net builders (van Veen's design: the patch's net built on the GPU from its
//! corners, a second copy of `tessella_core::scheme` tied to it by the CPU comparison tests) and
//! the evaluation shader's sums.

use tessella_core::shader::{self, Lang, NetBuilder};
use tessella_core::tessellator::Partitioning;
use tessella_core::Basis;

/// The four stages' sources for one spacing.
#[derive(Debug, Clone)]
pub struct ShaderSources {
    pub vertex: String,
    pub control: String,
    pub evaluation: String,
    pub fragment: String,
}

const HEADER: &str = "#version 430 core\n";

/// The coarse vertex, passed on to the control shader (unused when the nets come from buffers).
const VERTEX: &str = r#"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
out vec3 v_position;
out vec3 v_normal;
void main() {
    v_position = a_position;
    v_normal = a_normal;
}
"#;

/// Levels: a uniform, or per face from a buffer (GL order: outer[0] is the edge l1 = 0). The
/// control net: built here from the patch's corners (flat, Phong, PN with the builders
/// generated from tessella-core's `scheme` functions; PNG1 from a 6-vertex patch that adds each
/// edge's opposite neighbour corner, [`PNG1_NET`]), as van Veen's control shader does, or copied
/// from the buffers the CPU filled (`u_nets == 0`: PN-AEN, scalar-tagged, quadratic elements).
/// The tests compare every vertex with the CPU.
const CONTROL_DECLARATIONS: &str = r#"
layout(vertices = 1) out;
uniform int u_per_face;
uniform float u_level;
uniform int u_k;
// 0: nets from the buffers; 1 flat, 2 Phong, 3 PN, 4 PNG1.
uniform int u_nets;
// 0 linear, 1 quadratic, 2 real (the net is the linear one then: the fallback).
uniform int u_normals;
uniform float u_alpha;
layout(std430, binding = 0) readonly buffer Points { float pts[]; };
layout(std430, binding = 1) readonly buffer Normals { float nrm[]; };
layout(std430, binding = 2) readonly buffer Levels { float levels[]; };
// PNG1, per face and edge: flags (1: has a neighbour, 2: sharp) and kappa.
layout(std430, binding = 3) readonly buffer Edges { float edge_data[]; };
in vec3 v_position[];
in vec3 v_normal[];
patch out vec3 tc_pts[21];
patch out vec3 tc_nrm[6];
"#;

/// The cubic and normal nets from the generated builders (declared before this).
const CONTROL: &str = r#"
// The nets from the generated builders (tessella_core::shader::net_builder, the CPU's own
// scheme functions).
void cubic_net(vec3 p[3], vec3 n[3]) {
    vec3 c[10];
    if (u_nets == 3) {
        tessella_pn_points(p, n, c);
    } else if (u_nets == 2) {
        tessella_phong_points(p, n, u_alpha, c);
    } else {
        tessella_flat_points(p, n, c);
    }
    for (int i = 0; i < 10; ++i) { tc_pts[i] = c[i]; }
}
void normal_net(vec3 p[3], vec3 n[3]) {
    vec3 m[6];
    if (u_normals == 1) {
        tessella_quadratic_normals(p, n, m);
    } else {
        tessella_linear_normals(p, n, m);
    }
    for (int i = 0; i < 6; ++i) { tc_nrm[i] = m[i]; }
}
"#;

/// PNG1's control net in double precision (tessella-core `scheme/png1.rs`, which builds it in
/// f64), for the control shader.
const PNG1_NET: &str = r#"
dvec3 d_normalize_or(dvec3 x, dvec3 fallback) {
    double r = 1.0LF / sqrt(dot(x, x));
    return (!isinf(r) && !isnan(r) && r > 0.0LF) ? x * r : fallback;
}
dvec3 any_orthonormal(dvec3 n) {
    double s = n.z >= 0.0LF ? 1.0LF : -1.0LF;
    double a = -1.0LF / (s + n.z);
    double b = n.x * n.y * a;
    return dvec3(b, s + n.y * n.y * a, -n.y);
}
dvec3 tangent_point(dvec3 a, dvec3 n, dvec3 x) {
    dvec3 d = x - a;
    dvec3 proj = d - dot(d, n) * n;
    double len = sqrt(dot(proj, proj));
    if (len > 1e-300LF && !isinf(len) && !isnan(len)) {
        return a + proj * (sqrt(dot(d, d)) / len / 3.0LF);
    }
    return a + any_orthonormal(n) * (sqrt(dot(d, d)) / 3.0LF);
}
dvec3 transfer(dvec3 x, dvec3 s0, dvec3 s1, dvec3 ns, dvec3 d0, dvec3 d1, dvec3 nd) {
    dvec3 ts = s1 - s0;
    dvec3 td = d1 - d0;
    double ls = sqrt(dot(ts, ts));
    double ld = sqrt(dot(td, td));
    if (ls == 0.0LF || ld == 0.0LF) { return d0 + (x - s0); }
    dvec3 ms = cross(ns, ts) / ls;
    dvec3 md = cross(nd, td) / ld;
    dvec3 r = x - s0;
    double xi = dot(r, ts) / (ls * ls);
    double eta = dot(r, ms) / ls;
    return d0 + xi * td + (eta * ld) * md;
}
dvec3 tri_normal(dvec3 a, dvec3 b, dvec3 o) {
    return d_normalize_or(cross(b - a, o - a), dvec3(0.0LF));
}
int own_slot(int k, int offset) { return 3 + (4 * k + offset) % 12; }
void png1_net(vec3 pf[3], vec3 nf[3], vec3 opposite[3]) {
    dvec3 p[3] = dvec3[3](dvec3(pf[0]), dvec3(pf[1]), dvec3(pf[2]));
    dvec3 n[3];
    for (int i = 0; i < 3; ++i) { n[i] = d_normalize_or(dvec3(nf[i]), dvec3(0.0LF, 0.0LF, 1.0LF)); }
    dvec3 net[21];
    for (int i = 0; i < 3; ++i) { net[i] = p[i]; }
    for (int k = 0; k < 3; ++k) {
        int a = k, b = (k + 1) % 3, c = (k + 2) % 3;
        float flags = edge_data[(gl_PrimitiveID * 3 + k) * 2];
        double kappa = double(edge_data[(gl_PrimitiveID * 3 + k) * 2 + 1]);
        bool has_opposite = mod(flags, 2.0) == 1.0;
        bool sharp = flags >= 2.0;
        dvec3 e_a = tangent_point(p[a], n[a], p[b]);
        dvec3 e_b = tangent_point(p[b], n[b], p[a]);
        dvec3 f_a = tangent_point(p[a], n[a], p[c]);
        dvec3 f_b = tangent_point(p[b], n[b], p[c]);
        dvec3 n_t = tri_normal(p[a], p[b], p[c]);
        dvec3 n_sum = (!sharp && has_opposite)
            ? n_t + tri_normal(p[b], p[a], dvec3(opposite[k])) : n_t;
        dvec3 e1 = e_b - e_a;
        dvec3 t = d_normalize_or(e1, dvec3(0.0LF));
        dvec3 nm = d_normalize_or(n_sum - dot(n_sum, t) * t, dvec3(0.0LF));
        if (nm == dvec3(0.0LF)) {
            dvec3 s = n[a] + n[b];
            nm = d_normalize_or(s - dot(s, t) * t, dvec3(0.0LF));
            if (nm == dvec3(0.0LF)) { nm = any_orthonormal(t); }
        }
        dvec3 centre_a = transfer(f_a, p[a], e_a, n[a], e_a, e_b, nm);
        dvec3 cross_a = transfer(f_a, p[a], e_a, n[a], e_b, p[b], n[b]);
        dvec3 centre_b = transfer(f_b, e_b, p[b], n[b], e_a, e_b, nm);
        dvec3 cross_b = transfer(f_b, e_b, p[b], n[b], p[a], e_a, n[a]);
        if (sharp) {
            dvec3 shift = kappa * n_t;
            centre_a += shift;
            cross_a += shift;
            centre_b += shift;
            cross_b += shift;
        }
        net[own_slot(k, 0)] = e_a;
        net[own_slot(k, 2)] = e_b;
        net[own_slot(k, 4) + 1] = cross_a;
        net[own_slot(k, 10) + 1] = cross_b;
        net[15 + 2 * k] = centre_a;
        net[16 + 2 * k] = centre_b;
    }
    // Own slots not set above hold the neighbouring edge's points (own_slot(k, 0..2) of
    // every k covers them all).
    for (int i = 0; i < 21; ++i) { tc_pts[i] = vec3(net[i]); }
    if (u_normals == 1) {
        // The smoothed normals (section 3.3): mid-edge coefficients 4 M_e - (Na + Nb).
        vec3 mids[3] = vec3[3](vec3(0.5, 0.5, 0.0), vec3(0.0, 0.5, 0.5), vec3(0.5, 0.0, 0.5));
        for (int k = 0; k < 3; ++k) {
            vec3 w[21];
            tessella_png1_weights(mids[k], w);
            dvec3 du = dvec3(0.0LF), dv = dvec3(0.0LF);
            for (int i = 0; i < 21; ++i) { du += double(w[i].y) * net[i]; dv += double(w[i].z) * net[i]; }
            // The corner normals as given (the CPU's smoothed_normal_net takes them so).
            dvec3 na = dvec3(nf[k]), nb = dvec3(nf[(k + 1) % 3]);
            dvec3 m = d_normalize_or(cross(du, dv), d_normalize_or(na + nb, dvec3(0.0LF)));
            tc_nrm[k] = nf[k];
            tc_nrm[3 + k] = vec3(4.0LF * m - (na + nb));
        }
    } else {
        for (int i = 0; i < 3; ++i) {
            tc_nrm[i] = nf[i];
            tc_nrm[3 + i] = nf[i] + nf[(i + 1) % 3];
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
patch in vec3 tc_pts[21];
patch in vec3 tc_nrm[6];
out vec3 tf_position;
out vec3 tf_normal;
out vec3 tf_coord;
flat out int tf_face;
vec3 ctrl(int f, int k) { return tc_pts[k]; }
vec3 nctrl(int f, int k) { return tc_nrm[k]; }
void main() {
    // gl_TessCoord (u, v, w) is (l1, l2, l3): u = 1 at P1 (tessella_core::tessellator).
    vec3 l = gl_TessCoord;
    int f = gl_PrimitiveID;
    vec3 w[21];
    if (u_k == 21) { tessella_png1_weights(l, w); } else { tessella_cubic_weights(l, w); }
    vec3 p = vec3(0.0);
    vec3 du = vec3(0.0);
    vec3 dv = vec3(0.0);
    for (int k = 0; k < u_k; ++k) {
        vec3 c = ctrl(f, k);
        p += w[k].x * c;
        du += w[k].y * c;
        dv += w[k].z * c;
    }
    // The normal glue is the CPU's (tessella_core::shader::surface_normal, prepended).
    vec3 n = vec3(0.0);
    if (u_real != 0) { n = tessella_real_normal(du, dv); }
    if (n == vec3(0.0)) {
        float nw[6];
        tessella_normal_weights(l, nw);
        for (int j = 0; j < 6; ++j) { n += nw[j] * nctrl(f, j); }
    }
    n = tessella_unit_or_zero(n);
    if (n == vec3(0.0)) { n = tessella_corner_normal(ctrl(f, 0), ctrl(f, 1), ctrl(f, 2)); }
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

fn layout(spacing: Partitioning) -> &'static str {
    match spacing {
        Partitioning::Equal => "equal_spacing",
        Partitioning::FractionalOdd => "fractional_odd_spacing",
        Partitioning::FractionalEven => "fractional_even_spacing",
    }
}

/// The control shader's entry: levels, then the net from the buffers or built here.
const CONTROL_MAIN: &str = r#"
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
        int f = gl_PrimitiveID;
        if (u_nets == 0) {
            for (int k = 0; k < u_k; ++k) {
                int b = (f * u_k + k) * 3;
                tc_pts[k] = vec3(pts[b], pts[b + 1], pts[b + 2]);
            }
            for (int k = 0; k < 6; ++k) {
                int b = (f * 6 + k) * 3;
                tc_nrm[k] = vec3(nrm[b], nrm[b + 1], nrm[b + 2]);
            }
        } else {
            vec3 p[3] = vec3[3](v_position[0], v_position[1], v_position[2]);
            vec3 n[3] = vec3[3](v_normal[0], v_normal[1], v_normal[2]);
            if (u_nets == 4) {
                vec3 o[3] = vec3[3](v_position[3], v_position[4], v_position[5]);
                png1_net(p, n, o);
            } else {
                cubic_net(p, n);
                normal_net(p, n);
            }
        }
    }
}
"#;

/// The sources for `spacing`.
pub fn glsl_sources(spacing: Partitioning) -> ShaderSources {
    ShaderSources {
        vertex: format!("{HEADER}{VERTEX}"),
        control: format!(
            "{HEADER}{CONTROL_DECLARATIONS}{}{CONTROL}{}{PNG1_NET}{CONTROL_MAIN}",
            NetBuilder::ALL
                .map(|b| shader::net_builder(Lang::Glsl, b))
                .concat(),
            shader::weights(Lang::Glsl, Basis::Png1)
        ),
        evaluation: format!(
            "{HEADER}layout(triangles, {}, ccw) in;\n{}{}{}{}{EVALUATION}",
            layout(spacing),
            shader::weights(Lang::Glsl, Basis::Cubic),
            shader::weights(Lang::Glsl, Basis::Png1),
            shader::normal_net(Lang::Glsl),
            shader::surface_normal(Lang::Glsl)
        ),
        fragment: format!("{HEADER}{FRAGMENT}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_takes_the_generated_weights_it_calls() {
        let s = glsl_sources(Partitioning::Equal);
        for (stage, text, calls) in [
            ("control", &s.control, &["tessella_png1_weights"][..]),
            (
                "evaluation",
                &s.evaluation,
                &[
                    "tessella_png1_weights",
                    "tessella_cubic_weights",
                    "tessella_normal_weights",
                ][..],
            ),
        ] {
            for f in calls {
                assert_eq!(
                    text.matches(&format!("void {f}(")).count(),
                    1,
                    "{stage}: {f}"
                );
                assert!(
                    text.matches(&format!("{f}(")).count() >= 2,
                    "{stage} calls {f}"
                );
            }
        }
        // The normal glue: the generated functions once, each called, none typed here.
        assert_eq!(
            s.evaluation
                .matches(&shader::surface_normal(Lang::Glsl))
                .count(),
            1
        );
        for f in [
            "tessella_real_normal",
            "tessella_unit_or_zero",
            "tessella_corner_normal",
        ] {
            assert_eq!(
                s.evaluation.matches(&format!("vec3 {f}(")).count(),
                1,
                "{f}"
            );
            assert!(
                s.evaluation.matches(&format!("{f}(")).count() >= 2,
                "calls {f}"
            );
        }
        assert!(!EVALUATION.contains("1e-12") && !EVALUATION.contains("cross("));
    }
}
