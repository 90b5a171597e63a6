//! The WGSL with which three.js's WebGPURenderer builds an [`InstancedSurface`]'s control nets
//! by compute (js/src/three-gpu-nets-nodes.js, `netsComputeWgsl`), so a skinned or morphing
//! `TessellatedMesh` uploads only its joint matrices and morph weights each frame; the face
//! indices are the WebGL pass's (`netsPassTopology`, gpu_nets.rs).
//!
//! The net builders are the core's own Rust traced into WGSL
//! ([`tessella_core::shader::net_builder`]); the packing writes a face's texels in exactly the
//! layout the CPU's [`tessella_core::PatchNets::pack_texels`] fills and the draw's WGSL
//! ([`crate::instanced::wgsl`]) reads: the `K` control points then the 6 normal-net entries,
//! 3 floats each, one after the other, zero padded to `texels_per_face(K)` texels, the row
//! width being the texture's width over that. The coarse vertices are posed by TSL (a vertex
//! per thread); the posed normal's formula is the core's too ([`shader::skin_normal`]). Each
//! texel's expression comes from the same layout constants as the CPU's packing
//! ([`texels_per_face`], [`NORMAL_NET_LEN`]); the tests check it against `pack_texels`.
//!
//! Flat, Phong, PN and PN-AEN are built ([`NetBuilder::points_for`], as tessella-gpu's
//! `GpuNetBuilder` and the WebGL pass choose); PNG1, the scalar-tagged and the quadratic schemes, and tagged
//! surfaces, read more than a face's corners and its neighbours' normals and stay on the CPU.

use crate::errors;
use crate::instanced::{texels_per_face, InstancedSurface};
use tessella_core::basis::NORMAL_NET_LEN;
use tessella_core::refine::SurfaceOptions;
use tessella_core::shader::{self, Lang, NetBuilder};
use tessella_core::Scheme;
use wasm_bindgen::prelude::*;

/// The head of the function TSL calls (one thread a texel).
pub const TEXEL: &str = "fn tessella_net_texel(";

#[wasm_bindgen]
impl InstancedSurface {
    /// WGSL ending with `fn tessella_net_texel(j: u32, p0, p1, p2, n0, n1, n2[, m0 .. m5]:
    /// vec3<f32>) -> vec4<f32>`: texel `j` (of `TESSELLA_TEXELS_PER_FACE`) of the net of a
    /// face with posed corners `p`, their normals `n` (normalised here) and, for PN-AEN, the
    /// other sides' normals `m` (the across vertices' of `netsPassTopology`). The helpers
    /// (constants, builders) come before it. A texel a thread, as the WebGL pass: WGSL (naga)
    /// passes no storage texture to a function, so TSL stores what this returns. Throws for
    /// nets the GPU does not build ([`missing`]).
    #[wasm_bindgen(js_name = netsComputeWgsl)]
    pub fn nets_compute_wgsl(&self) -> Result<String, JsError> {
        wgsl(self.surface_options()).map_err(errors::text)
    }

    /// `fn tessella_skin_normal(m: mat3x3<f32>, n: vec3<f32>) -> vec3<f32>`: a posed vertex's
    /// unit normal from its matrix's upper 3×3 and its morphed rest normal, as the CPU's
    /// `Deformer` poses it ([`shader::skin_normal`]).
    #[wasm_bindgen(js_name = skinNormalWgsl)]
    pub fn skin_normal_wgsl(&self) -> String {
        shader::skin_normal(Lang::Wgsl)
    }
}

/// Why the GPU does not build nets of these options, or `None`.
pub fn missing(options: &SurfaceOptions) -> Option<String> {
    if options.tags.is_some() {
        return Some("tagged surfaces build their nets on the CPU".into());
    }
    if NetBuilder::points_for(&options.scheme).is_none() {
        return Some(format!(
            "the GPU builds the nets of the flat, phong, pn and pn-aen schemes; '{}' nets are \
             built on the CPU",
            options.scheme.name()
        ));
    }
    None
}

/// [`InstancedSurface::nets_compute_wgsl`] for `options` (refused as [`missing`] says).
pub fn wgsl(options: &SurfaceOptions) -> Result<String, String> {
    if let Some(why) = missing(options) {
        return Err(why);
    }
    let points = NetBuilder::points_for(&options.scheme).expect("checked by missing");
    let normals = NetBuilder::normals_for(options.normal_mode());
    let k = options.scheme.basis().len();
    let texels = texels_per_face(k);
    let across = points == NetBuilder::PnAenPoints;
    let mut s = shader::constants(Lang::Wgsl, &[("TESSELLA_TEXELS_PER_FACE", texels as u32)]);
    s += &shader::net_builder(Lang::Wgsl, points);
    s += &shader::net_builder(Lang::Wgsl, normals);
    // Normalised in f32, as tessella-gpu's builder (the CPU's Mesh normalises given normals).
    s += "fn tessella_unit(v: vec3<f32>) -> vec3<f32> {\n    return v / sqrt(dot(v, v));\n}\n";
    let vectors = |names: &[&str]| {
        names
            .iter()
            .map(|n| format!("{n}: vec3<f32>"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let ms = ["m0", "m1", "m2", "m3", "m4", "m5"];
    s += &format!(
        "{TEXEL}j: u32, {}{}) -> vec4<f32> {{\n",
        vectors(&["p0", "p1", "p2", "n0", "n1", "n2"]),
        if across {
            format!(", {}", vectors(&ms))
        } else {
            String::new()
        }
    );
    s += "    let p = array<vec3<f32>, 3>(p0, p1, p2);\n    \
          let n = array<vec3<f32>, 3>(tessella_unit(n0), tessella_unit(n1), tessella_unit(n2));\n";
    let extra = match options.scheme {
        Scheme::Phong { alpha } => format!(", {}", float(alpha)),
        Scheme::PnAen => {
            let m: Vec<String> = ms.iter().map(|m| format!("tessella_unit({m})")).collect();
            s += &format!("    let m = array<vec3<f32>, 6>({});\n", m.join(", "));
            ", m".into()
        }
        _ => String::new(),
    };
    s += &format!("    let c = {}(p, n{extra});\n", points.function_name());
    s += &format!("    let e = {}(p, n);\n", normals.function_name());
    for (j, texel) in packing(k).iter().enumerate() {
        s += &format!(
            "    if (j == {j}u) {{ return vec4<f32>({}); }}\n",
            texel.join(", ")
        );
    }
    s += "    return vec4<f32>(0.0);\n}\n";
    Ok(s)
}

/// Each texel's four components: float `x` of a face's net is component `x % 3` of entry
/// `x / 3`, a control point `c[i]` for the first `k` entries, then a normal-net entry `e[i]`;
/// zeros pad the last texel.
fn packing(k: usize) -> Vec<[String; 4]> {
    let floats = 3 * (k + NORMAL_NET_LEN);
    (0..texels_per_face(k))
        .map(|j| {
            std::array::from_fn(|c| {
                let x = 4 * j + c;
                let part = ["x", "y", "z"][x % 3];
                match x / 3 {
                    _ if x >= floats => "0.0".to_string(),
                    i if i < k => format!("c[{i}].{part}"),
                    i => format!("e[{}].{part}", i - k),
                }
            })
        })
        .collect()
}

/// An `f32` as a WGSL literal that reads back as the same value.
fn float(x: f32) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'n', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arrays;
    use crate::test_meshes::sample;

    const GPU: [&str; 6] = [
        r#"{"scheme":"pn","level":4}"#,
        r#"{"scheme":"pn","level":4,"normals":"linear"}"#,
        r#"{"scheme":"flat","level":4}"#,
        r#"{"scheme":"phong","level":4,"alpha":0.6}"#,
        r#"{"scheme":"pn-aen","level":4}"#,
        r#"{"scheme":"pn-aen","level":4,"normals":"real"}"#,
    ];

    fn built(json: &str) -> InstancedSurface {
        let (m, indices) = sample();
        let mut s = InstancedSurface::with(&indices, json).unwrap();
        let (moved, _) = tessella_core::samples::twist(&m, 30.0);
        let mut posed = m.clone();
        posed.update(&moved, None).unwrap();
        s.step_with(
            arrays::flat(posed.positions()),
            Some(arrays::flat(posed.normals())),
        )
        .unwrap();
        s
    }

    #[test]
    fn the_wgsl_is_valid_for_every_scheme_the_gpu_builds() {
        for json in GPU {
            let s = built(json);
            let w = wgsl(s.surface_options()).unwrap();
            let across = s.surface_options().scheme == Scheme::PnAen;
            // TSL takes the function from its head to the end; the helpers come before.
            let at = w.find(TEXEL).unwrap();
            assert!(!w[at + 3..].contains("\nfn "), "{json}");
            let m = if across { ", v, v, v, v, v, v" } else { "" };
            let module = format!(
                "{w}{}@group(0) @binding(0) var nets: texture_storage_2d<rgba32float, write>;\n\
                 @compute @workgroup_size(64) fn main(@builtin(global_invocation_id) g: vec3<u32>) {{\n    \
                 let v = vec3<f32>(f32(g.x), 1.0, 2.0);\n    \
                 let n = tessella_skin_normal(mat3x3<f32>(v, v, v), v);\n    \
                 textureStore(nets, g.xy, tessella_net_texel(g.x % TESSELLA_TEXELS_PER_FACE, v, v, v, n, n, n{m}));\n}}\n",
                s.skin_normal_wgsl()
            );
            // Every float literal is an f32 (Tint refuses one past f32's range; naga rounds it).
            for word in module.split(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-'))
            {
                if let Ok(x) = word.parse::<f64>() {
                    assert!(
                        x.abs() <= f64::from(f32::MAX),
                        "{json}: the literal {word} is no f32"
                    );
                }
            }
            crate::naga_check::validate_wgsl(&module, json);
        }
    }

    /// The texels the WGSL stores for face `f`, its `c[i]` and `e[i]` read from the CPU's nets.
    fn stored(w: &str, nets: &tessella_core::PatchNets, f: usize) -> Vec<f32> {
        let value = |s: &str| -> f32 {
            if s == "0.0" {
                return 0.0;
            }
            let (array, rest) = s.split_at(2);
            let (i, part) = rest.split_once("].").unwrap();
            let i: usize = i.parse().unwrap();
            let entry = match array {
                "c[" => nets.patch_points(f)[i],
                "e[" => nets.patch_normals(f)[i],
                _ => panic!("{s}"),
            };
            entry[["x", "y", "z"].iter().position(|p| *p == part).unwrap()]
        };
        let mut out = Vec::new();
        for (j, line) in w.lines().filter(|l| l.contains("if (j == ")).enumerate() {
            assert!(
                line.starts_with(&format!("    if (j == {j}u) {{ return vec4<f32>(")),
                "{line}"
            );
            let inner = line.split("vec4<f32>(").nth(1).unwrap();
            let inner = inner.trim_end_matches("); }");
            out.extend(inner.split(", ").map(value));
        }
        out
    }

    #[test]
    fn the_packing_writes_the_cpus_texels_and_the_builders_are_the_schemes() {
        for json in GPU {
            let s = built(json);
            let w = wgsl(s.surface_options()).unwrap();
            let options = s.surface_options();
            let builder = NetBuilder::points_for(&options.scheme).unwrap();
            assert!(
                w.contains(&shader::net_builder(Lang::Wgsl, builder)),
                "{json}"
            );
            let normals = NetBuilder::normals_for(options.normal_mode());
            assert!(
                w.contains(&shader::net_builder(Lang::Wgsl, normals)),
                "{json}"
            );
            let (_, frame) = s.built().unwrap();
            let cpu = frame.nets();
            assert_eq!(cpu.normal_mode, options.normal_mode());
            let l = crate::instanced::Layout::new(cpu.len(), texels_per_face(cpu.basis.len()));
            let mut packed = vec![f32::NAN; l.width * l.height * 4];
            cpu.pack_texels(l.faces_per_row, l.texels, &mut packed);
            for f in 0..cpu.len() {
                let start =
                    ((f / l.faces_per_row) * l.width + (f % l.faces_per_row) * l.texels) * 4;
                let got = stored(&w, cpu, f);
                let want = &packed[start..start + 4 * l.texels];
                // pack_texels leaves the padding as it was.
                let used = 3 * (cpu.basis.len() + NORMAL_NET_LEN);
                assert_eq!(&got[..used], &want[..used], "{json}: face {f}");
                assert!(got[used..].iter().all(|&x| x == 0.0));
                assert_eq!(got.len(), 4 * l.texels);
            }
        }
    }

    #[test]
    fn schemes_the_gpu_does_not_build_are_refused_by_name() {
        let (_, indices) = sample();
        let s = InstancedSurface::with(&indices, r#"{"scheme":"png1","level":4}"#).unwrap();
        let why = missing(s.surface_options()).unwrap();
        assert!(why.contains("'png1' nets are built on the CPU"), "{why}");
        assert!(wgsl(s.surface_options()).unwrap_err().contains("'png1'"));
        let mut options = s.surface_options().clone();
        for (scheme, name) in [
            (Scheme::ScalarTagged, "'st'"),
            (Scheme::Quadratic, "'quadratic'"),
        ] {
            options.scheme = scheme;
            assert!(missing(&options).unwrap().contains(name));
        }
        options.scheme = Scheme::Pn;
        assert_eq!(missing(&options), None);
        options.tags = Some(Default::default());
        assert!(missing(&options).unwrap().contains("tagged"));
    }

    #[test]
    fn floats_read_back_as_the_same_value() {
        for x in [0.6f32, 1.0, 0.75, 1e-7, -16.0, 3.4028235e38] {
            let s = float(x);
            assert!(s.contains('.') || s.contains('e'), "{s}");
            assert_eq!(s.parse::<f32>().unwrap(), x);
        }
    }
}
