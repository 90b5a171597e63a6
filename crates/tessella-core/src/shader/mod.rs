//! WGSL and GLSL generated from the core's formulas, so every backend evaluates the formula
//! the CPU does from one source.
//!
//! The bases' weights ([`crate::basis::cubic_weights`], [`crate::basis::png1::weights_of`]),
//! the normal net's weights ([`crate::basis::normal_weights`]) and a canonical edge's weights
//! ([`crate::refine::canonical::EdgeWeights`]) are Rust functions generic over
//! [`crate::scalar::Real`]. The CPU runs them in `f64`; the functions here run them once with a
//! traced number and print what was recorded as a shader function of straight-line code (no
//! arrays indexed in loops, which some compilers put in memory). A shader file holds only what
//! is its own (bindings, entry points, the order it sums in) and calls these.
//!
//! Every name declared here starts with `tessella_` (`Tessella` for the structs, such as
//! `TessellaPatchSum`), so an engine can include the code beside its own. The sums read control points through two
//! functions the including shader defines:
//!
//! - `tessella_net_point(face: u32, k: u32) -> vec3<f32>`: control point `k` of `face`;
//! - `tessella_net_normal(face: u32, k: u32) -> vec3<f32>`: normal-net entry `k`.
//!
//! ```
//! use tessella_core::shader::{self, Lang};
//! use tessella_core::Basis;
//! let wgsl = shader::weights(Lang::Wgsl, Basis::Png1);
//! assert!(wgsl.starts_with("fn tessella_png1_weights(l: vec3<f32>) -> array<vec3<f32>, 21>"));
//! ```

mod emit;
mod lang;
mod trace;

pub use lang::Lang;

use crate::basis::{normal_weights, Basis, NORMAL_NET_LEN};
use crate::mesh::quadratic::shape_functions;
use crate::refine::canonical::EdgeWeights;
use crate::scalar::Word;
use crate::scalar::{Dual, Real, V3};
use crate::scheme::{NormalMode, Scheme};
use emit::Body;
use trace::{trace, Expr, UExpr};

/// Length of the weight arrays [`weights`]' GLSL fills: the largest basis (PNG1's 21), so one
/// array serves every basis; entries past the basis' own are left unwritten. (The backends sum
/// through [`patch_sum`], which needs no array; the functions stay for an engine's own sums.)
pub const GLSL_WEIGHTS_LEN: usize = crate::basis::png1::PNG1_LEN;

/// The basis' name in the generated functions (`tessella_{name}_weights`): `cubic`, `png1`.
pub fn basis_name(basis: Basis) -> &'static str {
    match basis {
        Basis::Cubic => "cubic",
        Basis::Png1 => "png1",
    }
}

/// The barycentric point `l` as traced inputs named by its components.
fn traced_l() -> [Expr; 3] {
    ["l.x", "l.y", "l.z"].map(Expr::input)
}

/// `tessella_<basis>_weights`: per control point its weight, `Du` and `Dv` (a `vec3`) at the
/// barycentric point `l`.
///
/// - WGSL: `fn tessella_<basis>_weights(l: vec3<f32>) -> array<vec3<f32>, K>`;
/// - GLSL: `void tessella_<basis>_weights(vec3 l, out vec3 w[GLSL_WEIGHTS_LEN])`.
pub fn weights(lang: Lang, basis: Basis) -> String {
    let (tape, w) = trace(|| basis.weights_of(traced_l()));
    let outputs: Vec<Expr> = w.iter().flat_map(|d| [d.v, d.du, d.dv]).collect();
    let body = Body::new(&tape, lang, &outputs);
    let name = basis_name(basis);
    let k = basis.len();
    let vec3 = |d: &Dual<Expr>| {
        let [v, du, dv] = [d.v, d.du, d.dv].map(|e| body.name(e));
        match lang {
            Lang::Wgsl => format!("vec3<f32>({v}, {du}, {dv})"),
            Lang::Glsl => format!("vec3({v}, {du}, {dv})"),
        }
    };
    let mut s = match lang {
        Lang::Wgsl => {
            format!("fn tessella_{name}_weights(l: vec3<f32>) -> array<vec3<f32>, {k}> {{\n")
        }
        Lang::Glsl => {
            format!("void tessella_{name}_weights(vec3 l, out vec3 w[{GLSL_WEIGHTS_LEN}]) {{\n")
        }
    };
    s += &body.statements;
    match lang {
        Lang::Wgsl => {
            let items: Vec<String> = w
                .iter()
                .map(|d| format!("        {},\n", vec3(d)))
                .collect();
            s += &format!(
                "    return array<vec3<f32>, {k}>(\n{}    );\n",
                items.concat()
            );
        }
        Lang::Glsl => {
            for (i, d) in w.iter().enumerate() {
                s += &format!("    w[{i}] = {};\n", vec3(d));
            }
        }
    }
    s + "}\n"
}

/// Where a host's patch sum reads and what it sets, for [`patch_sum`].
pub struct SumSources<'a> {
    /// Control point `k` as an expression of the host's (a read of its nets, a local).
    pub point: &'a dyn Fn(usize) -> String,
    /// The variables (declared by the host) that get the point, `Du` and `Dv`: `None` for a
    /// sum the host does not need, whose weights are then not computed.
    pub into: [Option<&'a str>; 3],
}

/// The statements of a patch's point and derivatives at the barycentric point `l` (named so
/// by the host) for `basis`: `Σ w_k(l) C_k` with the weights traced from the basis' Rust
/// ([`weights`]' formulas, as straight-line code), each sum in index order, skipping the terms
/// whose weight is the constant zero. They declare the control points `c0..` (from
/// [`SumSources::point`]) and the weights' temporaries `t<n>`, then assign each asked-for sum.
/// Indented for a function body. Every backend that evaluates a patch from computed weights
/// prints its sums here: the adaptive renderer ([`patch_sum_wgsl`]), the GL evaluation shader
/// and the wasm GLSL and WGSL.
///
/// ```
/// use tessella_core::shader::{self, Lang, SumSources};
/// use tessella_core::Basis;
/// let point = |k: usize| format!("ctrl(f, {k})");
/// let glsl = shader::patch_sum(Lang::Glsl, Basis::Cubic, &SumSources {
///     point: &point,
///     into: [Some("p"), None, None],
/// });
/// assert!(glsl.contains("    vec3 c9 = ctrl(f, 9);\n"));
/// assert!(glsl.contains("    p = ") && !glsl.contains("    du = "));
/// ```
pub fn patch_sum(lang: Lang, basis: Basis, sources: &SumSources) -> String {
    let (tape, w) = trace(|| basis.weights_of(traced_l()));
    let parts = |d: &Dual<Expr>| [d.v, d.du, d.dv];
    let outputs: Vec<Expr> = w
        .iter()
        .flat_map(|d| {
            parts(d)
                .into_iter()
                .zip(sources.into)
                .filter_map(|(e, into)| into.map(|_| e))
        })
        .collect();
    let body = Body::new(&tape, lang, &outputs);
    let mut s = body.statements.clone();
    let declare = match lang {
        Lang::Wgsl => "let",
        Lang::Glsl => "vec3",
    };
    for k in 0..w.len() {
        s += &format!("    {declare} c{k} = {};\n", (sources.point)(k));
    }
    for (part, into) in sources.into.iter().enumerate() {
        let Some(into) = into else { continue };
        let terms: Vec<String> = w
            .iter()
            .enumerate()
            .map(|(k, d)| (parts(d)[part], k))
            .filter(|&(e, _)| !body.is_zero(e))
            .map(|(e, k)| format!("{} * c{k}", body.name(e)))
            .collect();
        // A sum whose every weight is the constant zero is zero (no basis has one).
        let sum = match (terms.is_empty(), lang) {
            (false, _) => terms.join(" + "),
            (true, Lang::Wgsl) => "vec3<f32>(0.0)".into(),
            (true, Lang::Glsl) => "vec3(0.0)".into(),
        };
        s += &format!("    {into} = {sum};\n");
    }
    s
}

/// WGSL: `fn tessella_patch_sum(face: u32, l: vec3<f32>) -> TessellaPatchSum` for `basis` (a
/// pipeline compiles one basis), the patch's point and derivatives at `l`:
/// [`patch_sum`] with the control points from `tessella_net_point(face, k)`.
pub fn patch_sum_wgsl(basis: Basis) -> String {
    let point = |k: usize| format!("tessella_net_point(face, {k}u)");
    let sums = patch_sum(
        Lang::Wgsl,
        basis,
        &SumSources {
            point: &point,
            into: [Some("s.p"), Some("s.du"), Some("s.dv")],
        },
    );
    let mut s = String::from(PATCH_SUM_STRUCT_WGSL);
    s += "\nfn tessella_patch_sum(face: u32, l: vec3<f32>) -> TessellaPatchSum {\n";
    s += "    var s: TessellaPatchSum;\n";
    s += &sums;
    s + "    return s;\n}\n"
}

/// The struct [`patch_sum_wgsl`]'s function returns (declared with it).
const PATCH_SUM_STRUCT_WGSL: &str =
    "struct TessellaPatchSum {\n    p: vec3<f32>,\n    du: vec3<f32>,\n    dv: vec3<f32>,\n}\n";

/// The statements of the normal net's sum at the barycentric point `l` (named so by the
/// host): `into = Σ w_k(l) N_k` over the six entries (`l1², l2², l3², l1 l2, l2 l3, l3 l1`,
/// [`crate::basis::normal_weights`], traced), in index order, with entry `k` from `normal(k)`,
/// an expression of the host's. They declare the entries `m0..m5` and temporaries `tn<n>`
/// (apart from [`patch_sum`]'s, so both can stand in one function) and assign `into`, which
/// the host declared. Indented for a function body. Every backend that sums a normal net at
/// computed weights prints it here: the adaptive renderer ([`normal_net_sum_wgsl`]), the GL
/// evaluation shader and the wasm GLSL and WGSL (as [`normal_glue`]'s net source).
///
/// ```
/// use tessella_core::shader::{self, Lang};
/// let glsl = shader::normal_net_sum(Lang::Glsl, &|k| format!("nctrl(f, {k})"), "n");
/// assert!(glsl.contains("    vec3 m5 = nctrl(f, 5);\n"));
/// assert!(glsl.contains("    n = tn3 * m0 + "));
/// ```
pub fn normal_net_sum(lang: Lang, normal: &dyn Fn(usize) -> String, into: &str) -> String {
    let (tape, w) = trace(|| normal_weights(traced_l()));
    let body = Body::prefixed(&tape, lang, &w, "tn");
    let declare = match lang {
        Lang::Wgsl => "let",
        Lang::Glsl => "vec3",
    };
    let mut s = body.statements.clone();
    for k in 0..NORMAL_NET_LEN {
        s += &format!("    {declare} m{k} = {};\n", normal(k));
    }
    let terms: Vec<String> = (0..NORMAL_NET_LEN)
        .map(|k| format!("{} * m{k}", body.name(w[k])))
        .collect();
    s + &format!("    {into} = {};\n", terms.join(" + "))
}

/// WGSL: `fn tessella_normal_net_sum(face: u32, l: vec3<f32>) -> vec3<f32>`, [`normal_net_sum`]
/// with the entries from `tessella_net_normal(face, k)`.
pub fn normal_net_sum_wgsl() -> String {
    let normal = |k: usize| format!("tessella_net_normal(face, {k}u)");
    format!(
        "fn tessella_normal_net_sum(face: u32, l: vec3<f32>) -> vec3<f32> {{\n    \
         var n: vec3<f32>;\n{}    return n;\n}}\n",
        normal_net_sum(Lang::Wgsl, &normal, "n")
    )
}

/// WGSL: `fn tessella_p2_weights(l: vec3<f32>) -> array<f32, 6>`, the six-node triangle's
/// shape functions at `l` ([`crate::mesh::quadratic::shape_functions`]: corners, then the
/// mid-edges of edges 0-1, 1-2, 2-0). A P2 field's value is their sum with its six nodal values.
pub fn p2_weights_wgsl() -> String {
    let (tape, w) = trace(|| shape_functions(traced_l()));
    let body = Body::new(&tape, Lang::Wgsl, &w);
    let items: Vec<String> = w.iter().map(|e| body.name(*e)).collect();
    format!(
        "fn tessella_p2_weights(l: vec3<f32>) -> array<f32, 6> {{\n{}    return array<f32, 6>({});\n}}\n",
        body.statements,
        items.join(", ")
    )
}

/// WGSL: `fn tessella_edge_weights(a: f32, b: f32) -> TessellaEdgeWeights` (and the struct):
/// the weights of a point of a canonical edge ([`EdgeWeights`]), `a` the canonical start
/// corner's barycentric weight: the boundary cubic's four (`value`) and the normal net's edge
/// restriction's three (`normal`).
pub fn edge_weights_wgsl() -> String {
    let (tape, (value, normal)) = trace(|| EdgeWeights::new_of(Expr::input("a"), Expr::input("b")));
    let outputs: Vec<Expr> = value.iter().chain(&normal).copied().collect();
    let body = Body::new(&tape, Lang::Wgsl, &outputs);
    let v = value.map(|e| body.name(e)).join(", ");
    let n = normal.map(|e| body.name(e)).join(", ");
    format!(
        "struct TessellaEdgeWeights {{\n    value: vec4<f32>,\n    normal: vec3<f32>,\n}}\n\n\
         fn tessella_edge_weights(a: f32, b: f32) -> TessellaEdgeWeights {{\n{}    \
         return TessellaEdgeWeights(vec4<f32>({v}), vec3<f32>({n}));\n}}\n",
        body.statements
    )
}

/// A control-net builder the GPU can run from a triangle's three corners (positions `p`,
/// normals `n`), generated from the scheme's own Rust ([`crate::scheme`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NetBuilder {
    /// The flat triangle's cubic net (`scheme::flat::points`): `tessella_flat_points`.
    FlatPoints,
    /// Phong tessellation's cubic net with shape factor `alpha` (`scheme::phong::points`):
    /// `tessella_phong_points`.
    PhongPoints,
    /// PN triangles' cubic net (`scheme::pn::points`): `tessella_pn_points`.
    PnPoints,
    /// The linear normal net (`scheme::normal_net::linear_of`): `tessella_linear_normals`.
    LinearNormals,
    /// Vlachos' quadratic normal net (`scheme::normal_net::quadratic_of`):
    /// `tessella_quadratic_normals`.
    QuadraticNormals,
    /// PN-AEN's cubic net ([`crate::scheme::pn_aen::points`]): `tessella_pn_aen_points`, which
    /// takes a third array, `m`, the other side's normals at each edge's start and end
    /// (`[a0, b0, a1, b1, a2, b2]`; the face's own corner normals where an edge has no other
    /// side, see [`crate::scheme::pn_aen::across_vertices`]).
    PnAenPoints,
}

impl NetBuilder {
    /// Every builder.
    pub const ALL: [NetBuilder; 6] = [
        NetBuilder::FlatPoints,
        NetBuilder::PhongPoints,
        NetBuilder::PnPoints,
        NetBuilder::LinearNormals,
        NetBuilder::QuadraticNormals,
        NetBuilder::PnAenPoints,
    ];

    /// The generated function's name.
    pub fn function_name(self) -> &'static str {
        match self {
            NetBuilder::FlatPoints => "tessella_flat_points",
            NetBuilder::PhongPoints => "tessella_phong_points",
            NetBuilder::PnPoints => "tessella_pn_points",
            NetBuilder::LinearNormals => "tessella_linear_normals",
            NetBuilder::QuadraticNormals => "tessella_quadratic_normals",
            NetBuilder::PnAenPoints => "tessella_pn_aen_points",
        }
    }

    /// The builder of `scheme`'s control points where the GPU builds them from a face's corners
    /// (and, for PN-AEN, the normals across its edges): flat, Phong, PN and PN-AEN. `None` for
    /// the schemes whose nets read more (PNG1's neighbours, tags, mid-edge nodes): those nets
    /// are built on the CPU.
    pub fn points_for(scheme: &Scheme) -> Option<NetBuilder> {
        match scheme {
            Scheme::Flat => Some(NetBuilder::FlatPoints),
            Scheme::Phong { .. } => Some(NetBuilder::PhongPoints),
            Scheme::Pn => Some(NetBuilder::PnPoints),
            Scheme::PnAen => Some(NetBuilder::PnAenPoints),
            _ => None,
        }
    }

    /// The normal net a mode builds: Vlachos' quadratic one, or the linear one (linear and real
    /// normals, as [`crate::scheme`] builds them).
    pub fn normals_for(mode: NormalMode) -> NetBuilder {
        match mode {
            NormalMode::Quadratic => NetBuilder::QuadraticNormals,
            _ => NetBuilder::LinearNormals,
        }
    }

    /// The net for traced corners (and `alpha`, which only Phong reads, and the other sides'
    /// normals `m`, which only PN-AEN reads).
    fn build<T: Real>(self, p: [V3<T>; 3], n: [V3<T>; 3], alpha: T, m: [V3<T>; 6]) -> Vec<V3<T>> {
        use crate::scheme::{flat, normal_net, phong, pn, pn_aen};
        match self {
            NetBuilder::PnAenPoints => pn_aen::points(p, n, m).to_vec(),
            NetBuilder::FlatPoints => flat::points(p).to_vec(),
            NetBuilder::PhongPoints => phong::points(p, n, alpha).to_vec(),
            NetBuilder::PnPoints => pn::points(p, n).to_vec(),
            NetBuilder::LinearNormals => normal_net::linear_of(n).to_vec(),
            NetBuilder::QuadraticNormals => normal_net::quadratic_of(p, n).to_vec(),
        }
    }
}

/// A net builder's inputs: the corners `p`, `n`, Phong's `alpha` and PN-AEN's other sides'
/// normals `m`.
struct NetInputs<T> {
    p: [V3<T>; 3],
    n: [V3<T>; 3],
    alpha: T,
    m: [V3<T>; 6],
}

/// The traced inputs `p[i]`, `n[i]`, `alpha` and `m[i]` of a net builder.
fn traced_corners() -> NetInputs<Expr> {
    let corner = |array: &str, i: usize| {
        V3::new(
            Expr::input(&format!("{array}[{i}].x")),
            Expr::input(&format!("{array}[{i}].y")),
            Expr::input(&format!("{array}[{i}].z")),
        )
    };
    NetInputs {
        p: [0, 1, 2].map(|i| corner("p", i)),
        n: [0, 1, 2].map(|i| corner("n", i)),
        alpha: Expr::input("alpha"),
        m: [0, 1, 2, 3, 4, 5].map(|i| corner("m", i)),
    }
}

/// A control-net builder as a shader function of the corners `p`, `n` (and `alpha` for
/// Phong, `m` for PN-AEN), returning (WGSL) or filling (GLSL) its `K` points:
///
/// - WGSL: `fn tessella_pn_points(p: array<vec3<f32>, 3>, n: array<vec3<f32>, 3>) ->
///   array<vec3<f32>, 10>`;
/// - GLSL: `void tessella_pn_points(vec3 p[3], vec3 n[3], out vec3 c[10])`;
/// - PN-AEN: `fn tessella_pn_aen_points(p: array<vec3<f32>, 3>, n: array<vec3<f32>, 3>,
///   m: array<vec3<f32>, 6>) -> array<vec3<f32>, 10>`, GLSL
///   `void tessella_pn_aen_points(vec3 p[3], vec3 n[3], vec3 m[6], out vec3 c[10])`.
pub fn net_builder(lang: Lang, builder: NetBuilder) -> String {
    let (tape, net) = trace(|| {
        let NetInputs { p, n, alpha, m } = traced_corners();
        builder.build(p, n, alpha, m)
    });
    let outputs: Vec<Expr> = net.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
    let body = Body::new(&tape, lang, &outputs);
    let name = builder.function_name();
    let k = net.len();
    let alpha = builder == NetBuilder::PhongPoints;
    let across = builder == NetBuilder::PnAenPoints;
    let point = |v: &V3<Expr>| {
        let [x, y, z] = [v.x, v.y, v.z].map(|e| body.name(e));
        match lang {
            Lang::Wgsl => format!("vec3<f32>({x}, {y}, {z})"),
            Lang::Glsl => format!("vec3({x}, {y}, {z})"),
        }
    };
    match lang {
        Lang::Wgsl => {
            let alpha = match (alpha, across) {
                (true, _) => ", alpha: f32",
                (_, true) => ", m: array<vec3<f32>, 6>",
                _ => "",
            };
            let items: Vec<String> = net
                .iter()
                .map(|v| format!("        {},\n", point(v)))
                .collect();
            format!(
                "fn {name}(p: array<vec3<f32>, 3>, n: array<vec3<f32>, 3>{alpha}) -> array<vec3<f32>, {k}> {{\n{}    return array<vec3<f32>, {k}>(\n{}    );\n}}\n",
                body.statements,
                items.concat()
            )
        }
        Lang::Glsl => {
            let alpha = match (alpha, across) {
                (true, _) => ", float alpha",
                (_, true) => ", vec3 m[6]",
                _ => "",
            };
            let mut s = format!(
                "void {name}(vec3 p[3], vec3 n[3]{alpha}, out vec3 c[{k}]) {{\n{}",
                body.statements
            );
            for (i, v) in net.iter().enumerate() {
                s += &format!("    c[{i}] = {};\n", point(v));
            }
            s + "}\n"
        }
    }
}

/// A face's packed net traced: `points`' control points then `normals`' entries, three floats
/// an entry (`PatchNets::pack_texels`'s order), from the corners [`traced_corners`] names.
fn traced_packed_net(points: NetBuilder, normals: NetBuilder) -> (trace::Tape, Vec<Expr>) {
    let (tape, (c, m)) = trace(|| {
        let NetInputs { p, n, alpha, m } = traced_corners();
        (points.build(p, n, alpha, m), normals.build(p, n, alpha, m))
    });
    let floats = c.iter().chain(&m).flat_map(|v| [v.x, v.y, v.z]).collect();
    (tape, floats)
}

/// GLSL (ES 3.00) `vec4 tessella_net_texel(vec3 p[3], vec3 n[3], float alpha, vec3 m[6], int
/// j)`: texel `j` of a face's packed net (`points`' control points, then `normals`' six entries,
/// three floats an entry one after the other, four floats a texel, zeros past the last; `texels`
/// texels, as `PatchNets::pack_texels` packs them), from the corners `p`, `n` (and Phong's
/// `alpha`, PN-AEN's other sides' normals `m`, which the other builders do not read).
///
/// A fragment shader that writes one texel a fragment calls this: each texel's branch computes
/// only the operations its four floats need, where building the whole net in every fragment
/// built it once per texel of the net.
pub fn net_texel_glsl(points: NetBuilder, normals: NetBuilder, texels: usize) -> String {
    let (tape, floats) = traced_packed_net(points, normals);
    assert!(
        floats.len() <= 4 * texels,
        "{} floats do not fit in {texels} texels",
        floats.len()
    );
    let mut s = String::from(
        "vec4 tessella_net_texel(vec3 p[3], vec3 n[3], float alpha, vec3 m[6], int j) {\n",
    );
    for j in 0..texels {
        let chunk = &floats[(4 * j).min(floats.len())..(4 * j + 4).min(floats.len())];
        let body = Body::new(&tape, Lang::Glsl, chunk);
        let mut values: Vec<String> = chunk.iter().map(|&e| body.name(e)).collect();
        values.resize(4, "0.0".to_string());
        s += &format!("    if (j == {j}) {{\n");
        for line in body.statements.lines() {
            s += &format!("    {line}\n");
        }
        s += &format!("        return vec4({});\n    }}\n", values.join(", "));
    }
    s + "    return vec4(0.0);\n}\n"
}

/// PNG1's net builder traced with the inputs [`png1_net_glsl`] names.
fn traced_png1_net() -> (trace::Tape, [V3<Expr>; crate::basis::png1::PNG1_LEN]) {
    use crate::scheme::png1::{control_points_of, Png1EdgeOf};
    trace(|| {
        let v = traced_vector;
        let edges = [0, 1, 2].map(|k| Png1EdgeOf {
            opposite: v("q", k),
            smooth: Expr::input(&format!("smooth_edge[{k}]")),
            sharp: Expr::input(&format!("sharp[{k}]")),
            kappa: Expr::input(&format!("kappa[{k}]")),
        });
        control_points_of(
            [0, 1, 2].map(|i| v("p", i)),
            [0, 1, 2].map(|i| v("n", i)),
            edges,
        )
    })
}

/// GLSL 4.00 `void tessella_png1_net(dvec3 p[3], dvec3 n[3], dvec3 q[3], double smooth_edge[3],
/// double sharp[3], double kappa[3], out dvec3 c[21])`: PNG1's 21 control points in double
/// precision, traced from [`crate::scheme::png1::control_points_of`], the builder the CPU runs
/// in `f64`. Per edge `k`: `q[k]` the neighbour's corner opposite it, `smooth_edge[k]` `1.0`
/// where that neighbour's plane joins the middle plane (else `0.0`), `sharp[k]` `1.0` on a
/// sharp edge moved by `kappa[k]`. The OpenGL control shader builds PNG1's nets with it.
pub fn png1_net_glsl() -> String {
    let (tape, net) = traced_png1_net();
    double_function(
        &format!(
            "tessella_png1_net(dvec3 p[3], dvec3 n[3], dvec3 q[3], double smooth_edge[3], \
             double sharp[3], double kappa[3], out dvec3 c[{}])",
            net.len()
        ),
        "c",
        &tape,
        &net,
    )
}

/// A GLSL `void` function `signature` in doubles whose body computes `values` from `tape` into
/// its `out dvec3` array `out`.
fn double_function(signature: &str, out: &str, tape: &trace::Tape, values: &[V3<Expr>]) -> String {
    let outputs: Vec<Expr> = values.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
    let body = Body::doubles(tape, &outputs);
    let mut s = format!("void {signature} {{\n{}", body.statements);
    for (i, v) in values.iter().enumerate() {
        let [x, y, z] = [v.x, v.y, v.z].map(|e| body.name(e));
        s += &format!("    {out}[{i}] = dvec3({x}, {y}, {z});\n");
    }
    s + "}\n"
}

/// The inputs `{array}[i].x`, `.y`, `.z` as a traced vector.
fn traced_vector(array: &str, i: usize) -> V3<Expr> {
    let [x, y, z] = traced_xyz(&format!("{array}[{i}]"));
    V3::new(x, y, z)
}

/// The inputs `{name}.x`, `.y`, `.z` (a `vec3` parameter's components).
fn traced_xyz(name: &str) -> [Expr; 3] {
    ["x", "y", "z"].map(|c| Expr::input(&format!("{name}.{c}")))
}

/// PNG1's smoothed normal net traced from the net `c` and the corner normals `n`.
fn traced_png1_normals() -> (trace::Tape, [V3<Expr>; crate::basis::NORMAL_NET_LEN]) {
    use crate::scheme::png1::smoothed_normal_net_of;
    trace(|| {
        let net = std::array::from_fn(|i| traced_vector("c", i));
        smoothed_normal_net_of(&net, [0, 1, 2].map(|i| traced_vector("n", i)))
    })
}

/// GLSL 4.00 `void tessella_png1_normals(dvec3 c[21], dvec3 n[3], out dvec3 m[6])`: PNG1's
/// smoothed normal net (section 3.3) from its net `c` and corner normals `n`, in doubles,
/// traced from [`crate::scheme::png1::smoothed_normal_net_of`] as the CPU runs it in `f64`.
pub fn png1_normals_glsl() -> String {
    let (tape, m) = traced_png1_normals();
    double_function(
        &format!(
            "tessella_png1_normals(dvec3 c[{}], dvec3 n[3], out dvec3 m[{}])",
            crate::basis::png1::PNG1_LEN,
            m.len()
        ),
        "m",
        &tape,
        &m,
    )
}

/// WGSL: `fn tessella_locate(rec: u32, code: u32, side_offset: u32) -> vec3<u32>`, the
/// hardware tessellator's placement of a part's point (`tessellator::parts::locate_of`, with
/// the 16.16 ruler arithmetic of `tessellator::points::place_of`): the point's 16.16 `u`, `v`
/// and its coarse edge (`TESSELLA_NO_EDGE` off the edges). It reads the face's ruler words
/// through `tessella_ruler_word(rec: u32, r: u32, k: u32) -> u32`, which the including shader
/// defines (word `k` of ruler `r` of the record at `rec`).
pub fn locate_wgsl() -> String {
    let (tape, out) = traced_locate();
    let body = Body::new(&tape, Lang::Wgsl, &out);
    let [u, v, edge] = out.map(|e| body.name(e));
    format!(
        "fn tessella_locate(rec: u32, code: u32, side_offset: u32) -> vec3<u32> {{\n{}    return vec3<u32>({u}, {v}, {edge});\n}}\n",
        body.statements
    )
}

/// GLSL (ES 3.00): `uvec3 tessella_locate(uint rec, uint code, uint side_offset)`, the same
/// trace as [`locate_wgsl`] (the hardware tessellator's placement, 16.16 `u`, `v` and the
/// coarse edge) for WebGL2; the including shader defines
/// `uint tessella_ruler_word(uint rec, uint r, uint k)`.
pub fn locate_glsl() -> String {
    let (tape, out) = traced_locate();
    let body = Body::new(&tape, Lang::Glsl, &out);
    let [u, v, edge] = out.map(|e| body.name(e));
    format!(
        "uvec3 tessella_locate(uint rec, uint code, uint side_offset) {{\n{}    return uvec3({u}, {v}, {edge});\n}}\n",
        body.statements
    )
}

/// The reads of a packed record ([`crate::refine::packed`]), traced from
/// `refine::packed::ruler_word_of` and `forward_bits_of`, the functions that give the
/// CPU its words back: `tessella_ruler_word(rec, r, k)`, word `k` of ruler `r` as
/// [`locate_wgsl`] / [`locate_glsl`] read it (`rec` unused: the host holds one record), and
/// `tessella_forward_bits()`, the face's canonical edge bits. They read the packed words
/// through `tessella_packed(i)` (`u32` in and out), which the host defines over its texture.
pub fn packed_record(lang: Lang) -> String {
    let [(ruler_tape, word), (bits_tape, bits)] = traced_packed_record();
    let function = |head: &str, tape: &trace::Tape, out: UExpr| {
        let body = Body::new(tape, lang, &[out]);
        format!(
            "{head} {{\n{}    return {};\n}}\n",
            body.statements,
            body.name(out)
        )
    };
    let (ruler_head, bits_head) = match lang {
        Lang::Wgsl => (
            "fn tessella_ruler_word(rec: u32, r: u32, k: u32) -> u32",
            "fn tessella_forward_bits() -> u32",
        ),
        Lang::Glsl => (
            "uint tessella_ruler_word(uint rec, uint r, uint k)",
            "uint tessella_forward_bits()",
        ),
    };
    function(ruler_head, &ruler_tape, word) + &function(bits_head, &bits_tape, bits)
}

/// [`packed_record`]'s two functions traced: word `k` of ruler `r`, and the canonical bits,
/// each read through `tessella_packed(i)`.
fn traced_packed_record() -> [(trace::Tape, UExpr); 2] {
    use crate::refine::packed::{forward_bits_of, ruler_word_of};
    let packed = |i: UExpr| UExpr::call("tessella_packed", &[i]);
    [
        trace(|| {
            let r = UExpr::input("r");
            let at = |j: u32| packed(UExpr::lit(3).wmul(r).wadd(UExpr::lit(j)));
            ruler_word_of(at(0), at(1), at(2), UExpr::input("k"))
        }),
        trace(|| forward_bits_of(packed(UExpr::lit(2)))),
    ]
}

/// A canonical edge point traced from [`crate::refine::canonical::edge_sum_of`] and
/// [`crate::basis::surface_normal::unit_or_zero_of`] (the CPU's `canonical::position` and
/// `canonical::net_normal`): the point and the unit normal (zero where it vanishes).
fn traced_canonical_edge() -> (trace::Tape, ([Expr; 3], [Expr; 3])) {
    use crate::basis::surface_normal::unit_or_zero_of;
    use crate::refine::canonical::edge_sum_of;
    trace(|| {
        let value = ["x", "y", "z", "w"].map(|a| Expr::input(&format!("value.{a}")));
        let normal = traced_xyz("normal");
        let c = std::array::from_fn(|i| traced_xyz(&format!("c[{i}]")));
        let m = std::array::from_fn(|i| traced_xyz(&format!("m[{i}]")));
        (
            edge_sum_of(value, c),
            unit_or_zero_of(edge_sum_of(normal, m)),
        )
    })
}

/// A point of a coarse edge from the edge's own data, as every backend evaluates it after
/// reading the edge's four boundary control points `c` and three normal-net entries `m` in
/// canonical order: `p = Σ value_i c_i` and `n`, the unit normal of `Σ normal_i m_i` (zero
/// where it vanishes, and the caller keeps its own normal), each sum in index order, the same
/// operations on both faces of the edge. `value`, `normal` are the canonical weights
/// ([`edge_weights_wgsl`], blended where a grid point geomorphs). Traced from the CPU's
/// [`crate::refine::canonical::edge_sum_of`].
///
/// - WGSL: `fn tessella_canonical_edge(value: vec4<f32>, normal: vec3<f32>,
///   c: array<vec3<f32>, 4>, m: array<vec3<f32>, 3>) -> TessellaCanonicalEdge` (and the
///   struct, fields `p`, `n`);
/// - GLSL (ES 3.00): `void tessella_canonical_edge(vec4 value, vec3 normal, vec3 c[4],
///   vec3 m[3], out vec3 p, out vec3 n)`.
pub fn canonical_edge(lang: Lang) -> String {
    let (tape, (p, n)) = traced_canonical_edge();
    let outputs: Vec<Expr> = p.iter().chain(&n).copied().collect();
    let body = Body::new(&tape, lang, &outputs);
    let [p, n] = [p, n].map(|v| v.map(|e| body.name(e)).join(", "));
    match lang {
        Lang::Wgsl => format!(
            "struct TessellaCanonicalEdge {{\n    p: vec3<f32>,\n    n: vec3<f32>,\n}}\n\n\
             fn tessella_canonical_edge(value: vec4<f32>, normal: vec3<f32>, c: array<vec3<f32>, 4>, m: array<vec3<f32>, 3>) -> TessellaCanonicalEdge {{\n{}    \
             return TessellaCanonicalEdge(vec3<f32>({p}), vec3<f32>({n}));\n}}\n",
            body.statements
        ),
        Lang::Glsl => format!(
            "void tessella_canonical_edge(vec4 value, vec3 normal, vec3 c[4], vec3 m[3], out vec3 p, out vec3 n) {{\n{}    \
             p = vec3({p});\n    n = vec3({n});\n}}\n",
            body.statements
        ),
    }
}

/// A tessellator point read back in an adaptive shader, traced from the CPU's
/// [`crate::refine::canonical::fixed_point_of`]: from `p`, what [`locate_wgsl`] returns (16.16
/// `u`, `v`, the coarse edge), and the face's canonical edge bits `forward` (bit `k` set where
/// edge `k` runs canonically), the barycentric point `l` and, on an edge, the canonical
/// parameter `ab` that [`edge_weights_wgsl`] takes (meaningless off the edges).
///
/// - WGSL: `fn tessella_tessellator_point(p: vec3<u32>, forward: u32) ->
///   TessellaTessellatorPoint` (and the struct, fields `l: vec3<f32>`, `ab: vec2<f32>`);
/// - GLSL (ES 3.00): `void tessella_tessellator_point(uvec3 p, uint forward, out vec3 l,
///   out vec2 ab)`.
pub fn tessellator_point(lang: Lang) -> String {
    let (tape, (l, ab)) = trace(|| {
        let u = UExpr::input;
        crate::refine::canonical::fixed_point_of::<Expr>(u("p.x"), u("p.y"), u("p.z"), u("forward"))
    });
    let outputs: Vec<Expr> = l.iter().chain(&ab).copied().collect();
    let body = Body::new(&tape, lang, &outputs);
    let l = l.map(|e| body.name(e)).join(", ");
    let ab = ab.map(|e| body.name(e)).join(", ");
    match lang {
        Lang::Wgsl => format!(
            "struct TessellaTessellatorPoint {{\n    l: vec3<f32>,\n    ab: vec2<f32>,\n}}\n\n\
             fn tessella_tessellator_point(p: vec3<u32>, forward: u32) -> TessellaTessellatorPoint {{\n{}    \
             return TessellaTessellatorPoint(vec3<f32>({l}), vec2<f32>({ab}));\n}}\n",
            body.statements
        ),
        Lang::Glsl => format!(
            "void tessella_tessellator_point(uvec3 p, uint forward, out vec3 l, out vec2 ab) {{\n{}    \
             l = vec3({l});\n    ab = vec2({ab});\n}}\n",
            body.statements
        ),
    }
}

/// What a host's canonical edge point reads, for [`canonical_edge_point`].
#[derive(Clone, Copy, Debug)]
pub struct EdgeSources<'a> {
    /// Parameters the host's net reads take before `face`, declared and passed on: WGSL for
    /// three.js passes its textures (`("nets: texture_2d<f32>, ", "nets, ")`); empty where the
    /// reads use the host's globals.
    pub context: (&'a str, &'a str),
    /// A shader condition: whether the pipeline's normal mode takes the normal net's normal
    /// (every mode but `Real`, whose normal looks across the edge and stays the face's own).
    pub net_normals: &'a str,
}

/// A coarse edge's point as every backend evaluates it: the edge's four boundary control
/// points and three normal-net entries read in canonical order (the CPU's
/// [`crate::refine::canonical::canonical_points`] and
/// [`crate::refine::canonical::canonical_normals`]), summed by [`canonical_edge`]'s
/// `tessella_canonical_edge`, and the normal chosen as the CPU chooses it: the edge's net
/// normal where the mode takes the net and it does not vanish, else the face's own. Two
/// functions:
///
/// - `tessella_edge_forward(bits, edge)`: whether `edge` runs canonically (bit `edge` of the
///   face's `bits`);
/// - `tessella_canonical_edge_point(face, edge, forward, value, normal, face_normal)`: the
///   point (`p`) and its unit normal (`n`) at the canonical weights `value`, `normal`.
///
/// The host defines the reads: `tessella_net_point` and `tessella_net_normal` (see the module
/// docs, after [`EdgeSources::context`]), and `tessella_edge_control(edge, i)` and
/// `tessella_edge_normal_control(edge, i)`, the `i`th entry of
/// [`crate::refine::canonical::edge_controls`] and
/// [`crate::refine::canonical::edge_normal_controls`] of `edge` (`u32` in and out).
/// WGSL returns [`canonical_edge`]'s `TessellaCanonicalEdge`; GLSL (ES 3.00) writes `out vec3
/// p, out vec3 n` after the same arguments.
///
/// ```
/// use tessella_core::shader::{self, EdgeSources, Lang};
/// let wgsl = shader::canonical_edge_point(Lang::Wgsl, &EdgeSources {
///     context: ("", ""),
///     net_normals: "TESSELLA_NORMAL_MODE != TESSELLA_MODE_REAL",
/// });
/// assert!(wgsl.contains("tessella_net_point(face, tessella_edge_control(edge, select(3u - i, i, forward)))"));
/// ```
pub fn canonical_edge_point(lang: Lang, sources: &EdgeSources) -> String {
    let (param, arg) = sources.context;
    let net_normals = sources.net_normals;
    // A loop over the edge's entries in the face's direction, reversed where the edge runs
    // against it, as `canonical_points` reverses.
    let read = |n: usize, name: &str, reader: &str, control: &str| {
        let last = n - 1;
        let order = match lang {
            Lang::Wgsl => format!("select({last}u - i, i, forward)"),
            Lang::Glsl => format!("(forward ? i : {last}u - i)"),
        };
        let call = format!("{reader}({arg}face, {control}(edge, {order}))");
        match lang {
            Lang::Wgsl => format!(
                "    var {name}: array<vec3<f32>, {n}>;\n    for (var i = 0u; i < {n}u; i++) {{\n        \
                 {name}[i] = {call};\n    }}\n"
            ),
            Lang::Glsl => format!(
                "    vec3 {name}[{n}];\n    for (uint i = 0u; i < {n}u; i++) {{\n        {name}[i] = {call};\n    }}\n"
            ),
        }
    };
    let reads = read(4, "c", "tessella_net_point", "tessella_edge_control")
        + &read(
            3,
            "m",
            "tessella_net_normal",
            "tessella_edge_normal_control",
        );
    match lang {
        Lang::Wgsl => format!(
            "fn tessella_edge_forward(bits: u32, edge: u32) -> bool {{\n    \
             return ((bits >> edge) & 1u) != 0u;\n}}\n\n\
             fn tessella_canonical_edge_point({param}face: u32, edge: u32, forward: bool, value: vec4<f32>, normal: vec3<f32>, face_normal: vec3<f32>) -> TessellaCanonicalEdge {{\n\
             {reads}    var e = tessella_canonical_edge(value, normal, c, m);\n    \
             if (!({net_normals}) || all(e.n == vec3<f32>(0.0))) {{\n        e.n = face_normal;\n    }}\n    \
             return e;\n}}\n"
        ),
        Lang::Glsl => format!(
            "bool tessella_edge_forward(uint bits, uint edge) {{\n    \
             return ((bits >> edge) & 1u) != 0u;\n}}\n\n\
             void tessella_canonical_edge_point({param}uint face, uint edge, bool forward, vec4 value, vec3 normal, vec3 face_normal, out vec3 p, out vec3 n) {{\n\
             {reads}    tessella_canonical_edge(value, normal, c, m, p, n);\n    \
             if (!({net_normals}) || n == vec3(0.0)) {{\n        n = face_normal;\n    }}\n}}\n"
        ),
    }
}

/// What a host's adaptive point reads and how it evaluates its patch, for [`adaptive_point`].
#[derive(Clone, Copy, Debug)]
pub struct PointSources<'a> {
    /// The face, as the host's canonical edge point takes it (an expression).
    pub face: &'a str,
    /// The arguments the host's net reads take before `face` ([`EdgeSources::context`]'s).
    pub context: &'a str,
    /// The face's record for [`locate_wgsl`]'s `tessella_locate` (the first word of its record,
    /// or `0u` where the host reads its record words from elsewhere).
    pub record: &'a str,
    /// The point's code in its part and its side offset (expressions, `u32`).
    pub code: &'a str,
    pub side: &'a str,
    /// The face's canonical edge bits (an expression, evaluated once).
    pub forward_bits: &'a str,
    /// Statements that evaluate the face's patch at the barycentric point `l` (declared by
    /// these steps) into the host's `position` and `normal` (declared by the host).
    pub evaluate: &'a str,
}

/// The statements of an adaptive point on the tessellator's spacings, in the order the CPU's
/// adaptive evaluation takes them (`refine::cpu::adaptive`): the point's placement in its
/// face's record ([`locate_wgsl`] / [`locate_glsl`]'s `tessella_locate`), read back as a
/// barycentric point `l` and canonical parameter ([`tessellator_point`]), the patch evaluated
/// there (the host's [`PointSources::evaluate`]), and on a coarse edge the edge's own point in
/// canonical order with its weights ([`edge_weights_wgsl`] / [`edge_weights_glsl`],
/// [`canonical_edge_point`]) in place of the patch's, the same floats from both faces. They
/// declare `p`, `bits`, `l` (and WGSL's `t`, GLSL's `ab`), and leave the point in the host's
/// `position` and `normal`. Every adaptive host prints its point here: the adaptive renderer
/// (tessella-gpu) and the wasm GLSL and WGSL for three.js. Indented for a function body.
///
/// ```
/// use tessella_core::shader::{self, Lang, PointSources};
/// let glsl = shader::adaptive_point(Lang::Glsl, &PointSources {
///     face: "uint(face)",
///     context: "",
///     record: "0u",
///     code: "code",
///     side: "inst >> 30u",
///     forward_bits: "tessella_forward_bits()",
///     evaluate: "tessella_evaluate(face, l, position, normal);",
/// });
/// assert!(glsl.starts_with("    uvec3 p = tessella_locate(0u, code, inst >> 30u);\n"));
/// assert!(glsl.contains("    tessella_evaluate(face, l, position, normal);\n"));
/// ```
pub fn adaptive_point(lang: Lang, sources: &PointSources) -> String {
    let PointSources {
        face,
        context,
        record,
        code,
        side,
        forward_bits,
        evaluate,
    } = *sources;
    let evaluate: String = evaluate.lines().map(|l| format!("    {l}\n")).collect();
    let canonical = format!("{context}{face}, p.z, tessella_edge_forward(bits, p.z)");
    match lang {
        Lang::Wgsl => format!(
            "    let p = tessella_locate({record}, {code}, {side});\n    \
             let bits = {forward_bits};\n    \
             let t = tessella_tessellator_point(p, bits);\n    \
             let l = t.l;\n\
             {evaluate}    \
             if (p.z != TESSELLA_NO_EDGE) {{\n        \
             let w = tessella_edge_weights(t.ab.x, t.ab.y);\n        \
             let e = tessella_canonical_edge_point({canonical}, w.value, w.normal, normal);\n        \
             position = e.p;\n        \
             normal = e.n;\n    \
             }}\n"
        ),
        Lang::Glsl => format!(
            "    uvec3 p = tessella_locate({record}, {code}, {side});\n    \
             uint bits = {forward_bits};\n    \
             vec3 l;\n    \
             vec2 ab;\n    \
             tessella_tessellator_point(p, bits, l, ab);\n\
             {evaluate}    \
             if (p.z != TESSELLA_NO_EDGE) {{\n        \
             vec4 ew;\n        \
             vec3 en;\n        \
             tessella_edge_weights(ab.x, ab.y, ew, en);\n        \
             tessella_canonical_edge_point({canonical}, ew, en, normal, position, normal);\n    \
             }}\n"
        ),
    }
}

/// GLSL (ES 3.00): `void tessella_edge_weights(float a, float b, out vec4 value, out vec3
/// normal)`, [`edge_weights_wgsl`]'s weights of a point of a canonical edge for WebGL2.
pub fn edge_weights_glsl() -> String {
    let (tape, (value, normal)) = trace(|| EdgeWeights::new_of(Expr::input("a"), Expr::input("b")));
    let outputs: Vec<Expr> = value.iter().chain(&normal).copied().collect();
    let body = Body::new(&tape, Lang::Glsl, &outputs);
    let v = value.map(|e| body.name(e)).join(", ");
    let n = normal.map(|e| body.name(e)).join(", ");
    format!(
        "void tessella_edge_weights(float a, float b, out vec4 value, out vec3 normal) {{\n{}    \
         value = vec4({v});\n    normal = vec3({n});\n}}\n",
        body.statements
    )
}

/// The displacement offsets of [`crate::displace`] as WGSL: `tessella_perlin(p: vec3<f32>)`
/// ([`crate::displace::perlin_of`]), `tessella_height_map(uv: vec2<f32>, size: vec2<f32>)`
/// ([`crate::displace::height_map_of`]) and `tessella_sine(a: f32, f: f32, p: vec3<f32>)`
/// ([`crate::displace::sine_of`]), all `-> f32`. The including shader defines the reads:
/// `tessella_perm(i: u32) -> u32` (Perlin's permutation, `i < 512`) and
/// `tessella_height_texel(x: u32, y: u32) -> f32` (signed texel coordinates as `u32` bits; it
/// wraps them). And the direction a point moves along, `tessella_direction(mask: u32,
/// m1: vec3<f32>, m2: vec3<f32>, m3: vec3<f32>, l: vec3<f32>, n: vec3<f32>) -> vec3<f32>`
/// ([`crate::displace::direction_of`]), from the face record the including shader reads.
pub fn displace_wgsl() -> String {
    use crate::displace::{direction_of, height_map_of, perlin_of, sine_of};
    let v3 = traced_xyz;
    let (tape, out) = trace(|| {
        direction_of(
            UExpr::input("mask"),
            [v3("m1"), v3("m2"), v3("m3")],
            v3("l"),
            v3("n"),
        )
    });
    let body = Body::new(&tape, Lang::Wgsl, &out);
    let [x, y, z] = out.map(|e| body.name(e));
    let direction = format!(
        "fn tessella_direction(mask: u32, m1: vec3<f32>, m2: vec3<f32>, m3: vec3<f32>, l: vec3<f32>, n: vec3<f32>) -> vec3<f32> {{\n{}    return vec3<f32>({x}, {y}, {z});\n}}\n",
        body.statements
    );
    let p = || [Expr::input("p.x"), Expr::input("p.y"), Expr::input("p.z")];
    let function = |head: &str, (tape, out): (trace::Tape, Expr)| {
        let body = Body::new(&tape, Lang::Wgsl, &[out]);
        format!(
            "{head} -> f32 {{\n{}    return {};\n}}\n",
            body.statements,
            body.name(out)
        )
    };
    [
        function(
            "fn tessella_perlin(p: vec3<f32>)",
            trace(|| perlin_of(|i| UExpr::call("tessella_perm", &[i]), p())),
        ),
        function(
            "fn tessella_height_map(uv: vec2<f32>, size: vec2<f32>)",
            trace(|| {
                height_map_of(
                    |x, y| Expr::call("tessella_height_texel", &[x, y]),
                    [Expr::input("size.x"), Expr::input("size.y")],
                    [Expr::input("uv.x"), Expr::input("uv.y")],
                )
            }),
        ),
        function(
            "fn tessella_sine(a: f32, f: f32, p: vec3<f32>)",
            trace(|| sine_of(Expr::input("a"), Expr::input("f"), p())),
        ),
        direction,
    ]
    .concat()
}

/// `tessellator::parts::locate_of` traced with the inputs `rec`, `code`, `side_offset` and the
/// ruler words read through `tessella_ruler_word(rec, r, k)`.
fn traced_locate() -> (trace::Tape, [UExpr; 3]) {
    use crate::tessellator::parts::locate_of;
    trace(|| {
        let rec = UExpr::input("rec");
        locate_of(
            |r, k| UExpr::call("tessella_ruler_word", &[rec, r, UExpr::lit(k as u32)]),
            UExpr::input("code"),
            UExpr::input("side_offset"),
        )
    })
}

/// The grid point traced in its three pieces ([`grid_plan_wgsl`]'s functions), with the
/// inputs they name: the edge, the plan inside an edge, the plan elsewhere.
type GridPlanTrace = crate::refine::grid_point::GridPointOf<UExpr, Expr>;

fn traced_grid_edge() -> (trace::Tape, UExpr) {
    let u = UExpr::input;
    trace(|| crate::refine::grid_point::grid_edge_of(u("big"), u("i"), u("j")))
}

fn traced_grid_edge_plan() -> (trace::Tape, GridPlanTrace) {
    let u = UExpr::input;
    trace(|| {
        crate::refine::grid_point::edge_plan_of::<Expr>(
            u("edge"),
            u("big"),
            u("i"),
            u("j"),
            ["segments.x", "segments.y", "segments.z"].map(u),
            ["alpha.x", "alpha.y", "alpha.z"].map(Expr::input),
            u("forward"),
        )
    })
}

fn traced_grid_inner_plan() -> (trace::Tape, GridPlanTrace) {
    let u = UExpr::input;
    trace(|| {
        crate::refine::grid_point::inner_plan_of::<Expr>(
            u("big"),
            u("i"),
            u("j"),
            Expr::input("alpha_inner"),
        )
    })
}

/// WGSL: a grid point's plan, traced from `refine::grid_point` (whose functions the CPU's
/// snapped grid patterns and geomorphed stencils run), in three functions so a vertex computes
/// only its own case:
///
/// - `fn tessella_grid_edge(big: u32, i: u32, j: u32) -> u32`: the coarse edge point `(i, j)`
///   of the level-`big` grid lies inside, else `TESSELLA_NO_EDGE`;
/// - `fn tessella_grid_edge_plan(edge: u32, big: u32, i: u32, j: u32, segments: vec3<u32>,
///   alpha: vec3<f32>, forward: u32) -> TessellaGridPlan`: the plan of a point inside `edge`,
///   on a face whose edges have `segments` segments and geomorph factors `alpha` and whose edge
///   `k` runs canonically where bit `k` of `forward` is set;
/// - `fn tessella_grid_inner_plan(big: u32, i: u32, j: u32, alpha_inner: f32) ->
///   TessellaGridPlan`: the plan of an interior point or a corner.
///
/// `TessellaGridPlan` holds the point `l`, its coarse `edge` (`TESSELLA_NO_EDGE` off the
/// edges), four `points` (`xyz` a barycentric point, `w` its weight: the point, then its
/// geomorph sources) whose surfaces the caller sums, and three `edge_points` (`x`, `y` the
/// canonical `a`, `b`, `z` the weight) whose canonical edge weights it sums; a zero weight is
/// no term.
pub fn grid_plan_wgsl() -> String {
    let (tape, edge) = traced_grid_edge();
    let body = Body::new(&tape, Lang::Wgsl, &[edge]);
    let edge_fn = format!(
        "fn tessella_grid_edge(big: u32, i: u32, j: u32) -> u32 {{\n{}    return {};\n}}\n",
        body.statements,
        body.name(edge)
    );
    [
        "struct TessellaGridPlan {\n    l: vec3<f32>,\n    edge: u32,\n    points: array<vec4<f32>, 4>,\n    edge_points: array<vec3<f32>, 3>,\n}\n".to_string(),
        edge_fn,
        plan_function(
            "fn tessella_grid_edge_plan(edge: u32, big: u32, i: u32, j: u32, segments: vec3<u32>, alpha: vec3<f32>, forward: u32)",
            traced_grid_edge_plan(),
        ),
        plan_function(
            "fn tessella_grid_inner_plan(big: u32, i: u32, j: u32, alpha_inner: f32)",
            traced_grid_inner_plan(),
        ),
    ]
    .join("\n")
}

/// A WGSL function `head -> TessellaGridPlan` returning a traced plan.
fn plan_function(head: &str, (tape, plan): (trace::Tape, GridPlanTrace)) -> String {
    let mut floats: Vec<Expr> = plan.l.to_vec();
    for (l, w) in plan.points {
        floats.extend(l);
        floats.push(w);
    }
    for ([a, b], w) in plan.edge_points {
        floats.extend([a, b, w]);
    }
    let body = Body::mixed(&tape, Lang::Wgsl, &floats, &[plan.edge]);
    let vec = |items: &[Expr]| {
        items
            .iter()
            .map(|&e| body.name(e))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let points: Vec<String> = plan
        .points
        .iter()
        .map(|(l, w)| format!("vec4<f32>({}, {})", vec(l), body.name(*w)))
        .collect();
    let edge_points: Vec<String> = plan
        .edge_points
        .iter()
        .map(|([a, b], w)| format!("vec3<f32>({})", vec(&[*a, *b, *w])))
        .collect();
    format!(
        "{head} -> TessellaGridPlan {{\n{}    \
         return TessellaGridPlan(vec3<f32>({}), {}, array<vec4<f32>, 4>({}), array<vec3<f32>, 3>({}));\n}}\n",
        body.statements,
        vec(&plan.l),
        body.name(plan.edge),
        points.join(", "),
        edge_points.join(", ")
    )
}

/// `tessella_skin_normal(m, n)`, a skinned vertex's posed normal from the upper 3×3 of its
/// blended matrix and its morphed rest normal ([`crate::animation::skin_normal_of`]: the
/// cofactor matrix with the determinant's sign, normalised, falling back to `n` normalised,
/// else `+Z`): WGSL `fn tessella_skin_normal(m: mat3x3<f32>, n: vec3<f32>) -> vec3<f32>` or
/// GLSL (ES 3.00) `vec3 tessella_skin_normal(mat3 m, vec3 n)`.
pub fn skin_normal(lang: Lang) -> String {
    let (tape, out) = trace(|| {
        let m = [0, 1, 2].map(|c| ["x", "y", "z"].map(|x| Expr::input(&format!("m[{c}].{x}"))));
        let n = ["n.x", "n.y", "n.z"].map(Expr::input);
        crate::animation::skin_normal_of(m, n)
    });
    let body = Body::new(&tape, lang, &out);
    let [x, y, z] = out.map(|e| body.name(e));
    let (head, vec3) = match lang {
        Lang::Wgsl => (
            "fn tessella_skin_normal(m: mat3x3<f32>, n: vec3<f32>) -> vec3<f32>",
            "vec3<f32>",
        ),
        Lang::Glsl => ("vec3 tessella_skin_normal(mat3 m, vec3 n)", "vec3"),
    };
    format!(
        "{head} {{\n{}    return {vec3}({x}, {y}, {z});\n}}\n",
        body.statements
    )
}

/// The evaluation's normal glue, the functions the CPU kernels run
/// ([`crate::basis::surface_normal::real_normal_of`], [`crate::basis::surface_normal::unit_or_zero_of`],
/// [`crate::basis::surface_normal::corner_normal_of`]), as three shader functions every backend's evaluation
/// calls after its sums:
///
/// - `tessella_real_normal(du, dv)`: `Du × Dv`, or zero where the derivatives are (nearly)
///   parallel (the caller then sums its normal net);
/// - `tessella_unit_or_zero(n)`: `n` normalised, or zero where it has no finite unit length;
/// - `tessella_corner_normal(a, b, c)`: the unit normal of the corner triangle `a b c` (the
///   patch's first three control points), else `+Z`, for a point whose normal vanished (a
///   function of its own so the callers compute it only then).
///
/// WGSL `fn tessella_real_normal(du: vec3<f32>, dv: vec3<f32>) -> vec3<f32>`, GLSL (ES 3.00
/// and 4.x alike) `vec3 tessella_real_normal(vec3 du, vec3 dv)`; the others alike, with one
/// and three `vec3` arguments.
pub fn surface_normal(lang: Lang) -> String {
    use crate::basis::surface_normal::{corner_normal_of, real_normal_of, unit_or_zero_of};
    let v3 = traced_xyz;
    let vec3 = match lang {
        Lang::Wgsl => "vec3<f32>",
        Lang::Glsl => "vec3",
    };
    let head = |name: &str, args: &[&str]| {
        let args: Vec<String> = match lang {
            Lang::Wgsl => args.iter().map(|a| format!("{a}: vec3<f32>")).collect(),
            Lang::Glsl => args.iter().map(|a| format!("vec3 {a}")).collect(),
        };
        match lang {
            Lang::Wgsl => format!("fn {name}({}) -> vec3<f32>", args.join(", ")),
            Lang::Glsl => format!("vec3 {name}({})", args.join(", ")),
        }
    };
    let function = |head: String, (tape, out): (trace::Tape, [Expr; 3])| {
        let body = Body::new(&tape, lang, &out);
        let [x, y, z] = out.map(|e| body.name(e));
        format!(
            "{head} {{\n{}    return {vec3}({x}, {y}, {z});\n}}\n",
            body.statements
        )
    };
    [
        function(
            head("tessella_real_normal", &["du", "dv"]),
            trace(|| real_normal_of(v3("du"), v3("dv"))),
        ),
        function(
            head("tessella_unit_or_zero", &["n"]),
            trace(|| unit_or_zero_of(v3("n"))),
        ),
        function(
            head("tessella_corner_normal", &["a", "b", "c"]),
            trace(|| corner_normal_of([v3("a"), v3("b"), v3("c")])),
        ),
    ]
    .concat()
}

/// Where a host's evaluation finds what the normal's steps need, for [`normal_glue`]: shader
/// expressions and statements in the host's language, over its own names.
#[derive(Clone, Copy, Debug)]
pub struct NormalSources<'a> {
    /// The real normal's derivatives, where the host may take it: `None` for a host built for
    /// a mode that never does.
    pub real: Option<RealNormalSource<'a>>,
    /// Statements that set `n` to the normal net's sum (`n` is zero when they run).
    pub net: &'a str,
    /// The corner triangle's three points (the patch's first three control points).
    pub corners: [&'a str; 3],
}

/// The real normal's derivatives for [`NormalSources`], and when to take it.
#[derive(Clone, Copy, Debug)]
pub struct RealNormalSource<'a> {
    /// A condition the shader tests (its normal mode as a constant or a uniform), or `None`
    /// where the host is built for `Real` alone.
    pub when: Option<&'a str>,
    /// `Du` and `Dv`.
    pub du: &'a str,
    pub dv: &'a str,
}

/// The statements that take a patch point's normal through the core's
/// [`NORMAL_STEPS`](crate::basis::surface_normal::NORMAL_STEPS), in the order the CPU's
/// [`normal_of`](crate::basis::surface_normal::normal_of) takes them, calling the functions
/// [`surface_normal`] prints. They declare `n` and leave the unit normal in it; each source is
/// evaluated only where its step needs it. Indented for a function body.
///
/// ```
/// use tessella_core::shader::{self, Lang, NormalSources};
/// let glue = shader::normal_glue(Lang::Glsl, &NormalSources {
///     real: None,
///     net: "n = tessella_net_sum(face);",
///     corners: ["c0", "c1", "c2"],
/// });
/// assert!(glue.starts_with("    vec3 n = vec3(0.0);\n    n = tessella_net_sum(face);\n"));
/// assert!(glue.contains("n = tessella_corner_normal(c0, c1, c2);"));
/// ```
pub fn normal_glue(lang: Lang, sources: &NormalSources) -> String {
    use crate::basis::surface_normal::{NormalStep, NORMAL_STEPS};
    let (declare, zero) = match lang {
        Lang::Wgsl => ("var n = vec3<f32>(0.0);", "all(n == vec3<f32>(0.0))"),
        Lang::Glsl => ("vec3 n = vec3(0.0);", "n == vec3(0.0)"),
    };
    let block = |condition: Option<&str>, body: &str| -> String {
        match condition {
            Some(c) => {
                let inner: String = body.lines().map(|l| format!("        {l}\n")).collect();
                format!("    if ({c}) {{\n{inner}    }}\n")
            }
            None => body.lines().map(|l| format!("    {l}\n")).collect(),
        }
    };
    let mut s = format!("    {declare}\n");
    for step in NORMAL_STEPS {
        s += &match step {
            NormalStep::Real => sources.real.map_or(String::new(), |r| {
                block(
                    r.when,
                    &format!("n = tessella_real_normal({}, {});", r.du, r.dv),
                )
            }),
            // Without a real normal, `n` is still zero here: no test.
            NormalStep::NetWhereZero => block(sources.real.map(|_| zero), sources.net),
            NormalStep::Unit => "    n = tessella_unit_or_zero(n);\n".to_string(),
            NormalStep::CornerWhereZero => {
                let [a, b, c] = sources.corners;
                block(
                    Some(zero),
                    &format!("n = tessella_corner_normal({a}, {b}, {c});"),
                )
            }
        };
    }
    s
}

/// When a host's evaluation takes the real normal (`Du × Dv`), for [`evaluate`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum RealNormal<'a> {
    /// Never: the host is built for a mode without it.
    Never,
    /// Always: the host is built for `Real`.
    Always,
    /// Where this condition of the host's holds (its mode as a uniform).
    When(&'a str),
}

/// Where a host's evaluation of a whole patch point reads and what it sets, for [`evaluate`].
pub struct EvalSources<'a> {
    /// Control point `k` as an expression of the host's (a read of its nets, a local).
    pub point: &'a dyn Fn(usize) -> String,
    /// Normal-net entry `k` (of six) as an expression of the host's.
    pub net_normal: &'a dyn Fn(usize) -> String,
    /// When the real normal is taken.
    pub real: RealNormal<'a>,
    /// The variables (declared by the host) that get the point and the unit normal: `None`
    /// for one the host does not need here.
    pub into: [Option<&'a str>; 2],
}

/// The statements of a patch's point and unit normal at the barycentric point `l` (named so
/// by the host), as the CPU's [`eval_point`](crate::refine::eval_point) computes them: the
/// point `Σ w_k(l) C_k` ([`patch_sum`]), and the normal through the core's normal steps
/// ([`normal_glue`]) over `Du × Dv` where [`EvalSources::real`] says, the normal net's sum
/// ([`normal_net_sum`]) and the corner triangle `C_0 C_1 C_2`. Every backend that evaluates a
/// whole point at once prints it here, one call per function: the GL evaluation shader and the
/// wasm GLSL and WGSL. (The adaptive renderer blends two points' sums before their normal,
/// for its geomorph, so it prints the parts; the pattern renderer's weights come from its
/// stencil rows.) Besides [`patch_sum`]'s and [`normal_net_sum`]'s names it declares `du`,
/// `dv` (for a real normal) and `n`. Indented for a function body.
///
/// ```
/// use tessella_core::shader::{self, EvalSources, Lang, RealNormal};
/// use tessella_core::Basis;
/// let point = |k: usize| format!("ctrl(f, {k})");
/// let net_normal = |k: usize| format!("nctrl(f, {k})");
/// let glsl = shader::evaluate(Lang::Glsl, Basis::Cubic, &EvalSources {
///     point: &point,
///     net_normal: &net_normal,
///     real: RealNormal::When("u_real != 0"),
///     into: [Some("position"), Some("normal")],
/// });
/// assert!(glsl.contains("    position = ") && glsl.contains("    du = "));
/// assert!(glsl.contains("tessella_real_normal(du, dv)"));
/// assert!(glsl.ends_with("    normal = n;\n"));
/// ```
pub fn evaluate(lang: Lang, basis: Basis, sources: &EvalSources) -> String {
    let [position, normal] = sources.into;
    let real = normal.is_some() && sources.real != RealNormal::Never;
    let mut s = String::new();
    if real {
        s += match lang {
            Lang::Wgsl => "    var du: vec3<f32>;\n    var dv: vec3<f32>;\n",
            Lang::Glsl => "    vec3 du;\n    vec3 dv;\n",
        };
    }
    s += &patch_sum(
        lang,
        basis,
        &SumSources {
            point: sources.point,
            into: [position, real.then_some("du"), real.then_some("dv")],
        },
    );
    let Some(normal) = normal else { return s };
    let net = normal_net_sum(lang, sources.net_normal, "n");
    let when = match sources.real {
        RealNormal::When(condition) => Some(condition),
        RealNormal::Never | RealNormal::Always => None,
    };
    s += &normal_glue(
        lang,
        &NormalSources {
            real: real.then_some(RealNormalSource {
                when,
                du: "du",
                dv: "dv",
            }),
            net: &net,
            corners: ["c0", "c1", "c2"],
        },
    );
    s + &format!("    {normal} = n;\n")
}

/// The layout of the adaptive renderer's per-face records and the tessellator's 16.16 fixed
/// point, as `TESSELLA_`-prefixed `u32` constants (see [`constants`]): the words a shader
/// reads are the words [`crate::refine::instanced`] writes.
pub fn record_layout(lang: Lang) -> String {
    use crate::refine::instanced as rec;
    use crate::tessellator::{fixed, points};
    let word = |x: usize| x as u32;
    constants(
        lang,
        &[
            ("TESSELLA_RECORD_WORDS", word(rec::RECORD_WORDS)),
            ("TESSELLA_FORWARD_WORD", word(rec::FORWARD_WORD)),
            ("TESSELLA_RULER_WORDS", word(points::RULER_WORDS)),
            (
                "TESSELLA_RULER_PACKED_WORD",
                word(points::RULER_PACKED_WORD),
            ),
            ("TESSELLA_RULER_ODD_SHIFT", points::RULER_ODD_SHIFT),
            ("TESSELLA_RULER_POINTS_SHIFT", points::RULER_POINTS_SHIFT),
            ("TESSELLA_GRID_SEGMENTS_WORD", word(rec::GRID_SEGMENTS_WORD)),
            ("TESSELLA_GRID_LEVEL_WORD", word(rec::GRID_LEVEL_WORD)),
            ("TESSELLA_GRID_MORPH_WORD", word(rec::GRID_MORPH_WORD)),
            (
                "TESSELLA_GRID_INNER_MORPH_WORD",
                word(rec::GRID_INNER_MORPH_WORD),
            ),
            ("TESSELLA_FIXED_ONE", fixed::ONE),
            ("TESSELLA_FIXED_ONE_HALF", fixed::ONE_HALF),
            ("TESSELLA_FIXED_ONE_THIRD", fixed::ONE_THIRD),
            ("TESSELLA_FIXED_TWO_THIRDS", fixed::TWO_THIRDS),
            ("TESSELLA_FIXED_FRACTION_BITS", fixed::FRACTION_BITS),
            ("TESSELLA_NO_EDGE", crate::tessellator::parts::NO_EDGE),
        ],
    )
}

/// The codes [`normal_mode_code`] gives: what a shader (or an engine's pipeline key) reads.
pub const NORMALS_LINEAR: u32 = 0;
/// Quadratic normals' code.
pub const NORMALS_QUADRATIC: u32 = 1;
/// Real normals' code.
pub const NORMALS_REAL: u32 = 2;

/// The number a shader reads for a normal mode (a WGSL constant, a GLSL uniform):
/// [`NORMALS_LINEAR`], [`NORMALS_QUADRATIC`] or [`NORMALS_REAL`]. Every backend maps the modes
/// through this one function (and [`normal_mode_name`]), so none matches on the mode itself.
pub fn normal_mode_code(mode: NormalMode) -> u32 {
    match mode {
        NormalMode::Linear => NORMALS_LINEAR,
        NormalMode::Quadratic => NORMALS_QUADRATIC,
        NormalMode::Real => NORMALS_REAL,
    }
}

/// A normal mode's name in module and shader-def names: `linear`, `quadratic`, `real`.
pub fn normal_mode_name(mode: NormalMode) -> &'static str {
    match mode {
        NormalMode::Linear => "linear",
        NormalMode::Quadratic => "quadratic",
        NormalMode::Real => "real",
    }
}

/// `u32` constants as WGSL (`const NAME: u32 = 7u;`) or GLSL (`const uint NAME = 7u;`), one a
/// line: layout numbers the Rust side defines and a shader reads.
pub fn constants(lang: Lang, items: &[(&str, u32)]) -> String {
    items
        .iter()
        .map(|(name, value)| match lang {
            Lang::Wgsl => format!("const {name}: u32 = {value}u;\n"),
            Lang::Glsl => format!("const uint {name} = {value}u;\n"),
        })
        .collect()
}

#[cfg(test)]
mod tests;
