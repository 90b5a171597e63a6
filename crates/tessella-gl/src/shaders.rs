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

/// The evaluation's entry point: the generated sums of the program's basis, then the generated
/// normal steps.
fn evaluation_main() -> String {
    let point = |k: usize| format!("ctrl(f, {k})");
    let sums = |basis: Basis| {
        let sources = shader::SumSources {
            point: &point,
            into: [Some("p"), Some("du"), Some("dv")],
        };
        let glue = shader::patch_sum(Lang::Glsl, basis, &sources);
        glue.lines()
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
    vec3 du;
    vec3 dv;
    // The patch's sums (tessella_core::shader::patch_sum), for PNG1's 21 points or the cubic 10.
    if (u_k == 21) {{
{}    }} else {{
{}    }}
    // The normal's steps are the CPU's (tessella_patch_normal, generated: patch_normal).
    vec3 n = tessella_patch_normal(f, l, du, dv);
    tf_position = p;
    tf_normal = n;
    tf_coord = l;
    tf_face = f;
    gl_Position = u_view_proj * vec4(p, 1.0);
}}
"#,
        sums(Basis::Png1),
        sums(Basis::Cubic)
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

/// A patch point's unit normal, `vec3 tessella_patch_normal(int f, vec3 l, vec3 du, vec3 dv)`:
/// the core's normal steps ([`shader::normal_glue`]) over the point's derivatives, its normal
/// net and its corners.
fn patch_normal() -> String {
    let net = shader::normal_net_sum(Lang::Glsl, &|k| format!("nctrl(f, {k})"), "n");
    let glue = shader::normal_glue(
        Lang::Glsl,
        &shader::NormalSources {
            real: Some(shader::RealNormalSource {
                when: Some("u_real != 0"),
                du: "du",
                dv: "dv",
            }),
            net: &net,
            corners: ["ctrl(f, 0)", "ctrl(f, 1)", "ctrl(f, 2)"],
        },
    );
    format!(
        "vec3 tessella_patch_normal(int f, vec3 l, vec3 du, vec3 dv) {{\n{glue}    return n;\n}}\n"
    )
}

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
            "{HEADER}layout(triangles, {}, ccw) in;\n{}{EVALUATION}{}{}",
            layout(spacing),
            shader::surface_normal(Lang::Glsl),
            patch_normal(),
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
        // The normal net's sum: the generated one, once, in the normal's steps.
        let net = shader::normal_net_sum(Lang::Glsl, &|k| format!("nctrl(f, {k})"), "n");
        let indented: String = net.lines().map(|l| format!("        {l}\n")).collect();
        assert_eq!(
            s.evaluation.matches(&indented).count(),
            1,
            "{}",
            s.evaluation
        );
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
        // The normal's steps: the generated glue, once; none typed here.
        assert_eq!(s.evaluation.matches(&patch_normal()).count(), 1);
        // The sums: the generated ones of both bases, once each; none typed here.
        for basis in [Basis::Cubic, Basis::Png1] {
            let point = |k: usize| format!("ctrl(f, {k})");
            let sums = shader::patch_sum(
                Lang::Glsl,
                basis,
                &shader::SumSources {
                    point: &point,
                    into: [Some("p"), Some("du"), Some("dv")],
                },
            );
            let indented: String = sums.lines().map(|l| format!("    {l}\n")).collect();
            assert_eq!(s.evaluation.matches(&indented).count(), 1, "{basis:?}");
        }
        let main = evaluation_main();
        for typed in [EVALUATION, main.as_str()] {
            assert!(!typed.contains("for (int k"), "a sum typed by hand");
            assert!(!typed.contains("1e-12") && !typed.contains("cross("));
            assert!(!typed.contains("tessella_unit_or_zero") && !typed.contains("tessella_corner"));
        }
        // PNG1's net: no formula of its own here, only the generated builders fed.
        for typed in ["cross(", "sqrt(", "normalize", "dot("] {
            assert!(!PNG1_NET.contains(typed), "{typed}");
        }
    }
}
