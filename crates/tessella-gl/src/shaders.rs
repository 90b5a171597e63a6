//! The GLSL of the backend. The evaluation's sums (the patch's with the cubic Bernstein or
//! PNG1's rational weights, the normal net's), the normal's steps and the control shader's net
//! builders (van Veen's design: the patch's net built on the GPU from its corners; PNG1's in
//! doubles) are generated from tessella-core's own Rust functions ([`tessella_core::shader`]);
//! what is written here is the stages' own code: the levels, which builder a patch takes and
//! what feeds it, and where the evaluation reads its control points.

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
/// edge's opposite neighbour corner, [`PNG1_NET`], with the generated double-precision
/// builder), as van Veen's control shader does, or copied
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

/// PNG1's control net for the control shader: the points from the generated
/// `tessella_png1_net` (traced from tessella-core's `scheme::png1::control_points_of`, in
/// doubles as the CPU builds it in `f64`), fed from the patch and this face's edge table; then
/// the normal net the mode asks for.
const PNG1_NET: &str = r#"
void png1_net(vec3 pf[3], vec3 nf[3], vec3 opposite[3]) {
    dvec3 p[3] = dvec3[3](dvec3(pf[0]), dvec3(pf[1]), dvec3(pf[2]));
    dvec3 n[3] = dvec3[3](dvec3(nf[0]), dvec3(nf[1]), dvec3(nf[2]));
    dvec3 q[3] = dvec3[3](dvec3(opposite[0]), dvec3(opposite[1]), dvec3(opposite[2]));
    double smooth_edge[3], sharp[3], kappa[3];
    for (int k = 0; k < 3; ++k) {
        float flags = edge_data[(gl_PrimitiveID * 3 + k) * 2];
        bool has_opposite = mod(flags, 2.0) == 1.0;
        sharp[k] = flags >= 2.0 ? 1.0LF : 0.0LF;
        smooth_edge[k] = (has_opposite && flags < 2.0) ? 1.0LF : 0.0LF;
        kappa[k] = double(edge_data[(gl_PrimitiveID * 3 + k) * 2 + 1]);
    }
    dvec3 net[21];
    tessella_png1_net(p, n, q, smooth_edge, sharp, kappa, net);
    for (int i = 0; i < 21; ++i) { tc_pts[i] = vec3(net[i]); }
    if (u_normals == 1) {
        // The corner normals as given (the CPU's smoothed_normal_net takes them so).
        dvec3 m[6];
        tessella_png1_normals(net, dvec3[3](dvec3(nf[0]), dvec3(nf[1]), dvec3(nf[2])), m);
        for (int i = 0; i < 6; ++i) { tc_nrm[i] = vec3(m[i]); }
    } else {
        for (int i = 0; i < 3; ++i) {
            tc_nrm[i] = nf[i];
            tc_nrm[3 + i] = nf[i] + nf[(i + 1) % 3];
        }
    }
}

"#;

/// The evaluation stage's declarations: it writes position, normal (net or `Du × Dv`),
/// tessellation coordinate and face, for transform feedback and for drawing.
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
"#;

/// What the evaluation stage evaluates a patch from: the control points and normal net the
/// control stage passed (`ctrl`, `nctrl`), the real normal where `u_real`; it sets `p` and
/// `normal`.
fn evaluation_sources() -> shader::EvalSources<'static> {
    fn point(k: usize) -> String {
        format!("ctrl(f, {k})")
    }
    fn net_normal(k: usize) -> String {
        format!("nctrl(f, {k})")
    }
    shader::EvalSources {
        point: &point,
        net_normal: &net_normal,
        real: shader::RealNormal::When("u_real != 0"),
        into: [Some("p"), Some("normal")],
    }
}

/// The evaluation's entry point: for the program's basis (`u_k`), the generated evaluation of
/// the patch's point and unit normal ([`shader::evaluate`], the real normal where `u_real`).
fn evaluation_main() -> String {
    let evaluation = |basis: Basis| {
        let text = shader::evaluate(Lang::Glsl, basis, &evaluation_sources());
        text.lines()
            .map(|l| format!("    {l}\n"))
            .collect::<String>()
    };
    format!(
        r#"
void main() {{
    // gl_TessCoord (u, v, w) is (l1, l2, l3): u = 1 at P1 (tessella_core::tessellator).
    vec3 l = gl_TessCoord;
    int f = gl_PrimitiveID;
    vec3 p;
    vec3 normal;
    // The patch's point and normal (tessella_core::shader::evaluate), for PNG1's 21 points or
    // the cubic 10.
    if (u_k == 21) {{
{}    }} else {{
{}    }}
    tf_position = p;
    tf_normal = normal;
    tf_coord = l;
    tf_face = f;
    gl_Position = u_view_proj * vec4(p, 1.0);
}}
"#,
        evaluation(Basis::Png1),
        evaluation(Basis::Cubic)
    )
}

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
            "{HEADER}{CONTROL_DECLARATIONS}{}{CONTROL}{}{}{PNG1_NET}{CONTROL_MAIN}",
            NetBuilder::ALL
                .map(|b| shader::net_builder(Lang::Glsl, b))
                .concat(),
            shader::png1_net_glsl(),
            shader::png1_normals_glsl()
        ),
        evaluation: format!(
            "{HEADER}layout(triangles, {}, ccw) in;\n{}{EVALUATION}{}",
            layout(spacing),
            shader::surface_normal(Lang::Glsl),
            evaluation_main()
        ),
        fragment: format!("{HEADER}{FRAGMENT}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_takes_the_generated_code_it_calls() {
        let s = glsl_sources(Partitioning::Equal);
        for f in ["tessella_png1_net", "tessella_png1_normals"] {
            assert_eq!(s.control.matches(&format!("void {f}(")).count(), 1, "{f}");
            assert!(
                s.control.matches(&format!("{f}(")).count() >= 2,
                "calls {f}"
            );
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
        // Each basis's point and normal: one generated evaluation, once, over the control
        // stage's points and normal net, the real normal where u_real; none typed here.
        let point = |k: usize| format!("ctrl(f, {k})");
        let net_normal = |k: usize| format!("nctrl(f, {k})");
        let mut typed = evaluation_main();
        for basis in [Basis::Cubic, Basis::Png1] {
            let sources = shader::EvalSources {
                point: &point,
                net_normal: &net_normal,
                real: shader::RealNormal::When("u_real != 0"),
                into: [Some("p"), Some("normal")],
            };
            let text = shader::evaluate(Lang::Glsl, basis, &sources);
            let indented: String = text.lines().map(|l| format!("    {l}\n")).collect();
            assert_eq!(s.evaluation.matches(&indented).count(), 1, "{basis:?}");
            typed = typed.replace(&indented, "");
        }
        for typed in [EVALUATION, typed.as_str()] {
            assert!(!typed.contains("for (int k"), "a sum typed by hand");
            assert!(!typed.contains("1e-12") && !typed.contains("cross("));
            assert!(!typed.contains("tessella_unit_or_zero") && !typed.contains("tessella_corner"));
            assert!(!typed.contains("tessella_real_normal") && !typed.contains(" * c0"));
        }
        // PNG1's net: no formula of its own here, only the generated builders fed.
        for typed in ["cross(", "sqrt(", "normalize", "dot("] {
            assert!(!PNG1_NET.contains(typed), "{typed}");
        }
    }
}
