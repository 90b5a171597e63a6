//! The GLSL and index data of WebGL2's net pass: `TessellatedMesh` (js/src/three.js) posing a
//! skinned or morphing source on the GPU (js/src/three-gpu-nets.js) builds its control nets in
//! a fragment shader, one fragment per texel of the nets texture, in the layout the vertex
//! shader reads ([`crate::instanced`]'s header, [`PatchNets::pack_texels`]).
//!
//! Everything that decides a net's numbers is generated here from the core's Rust: the
//! scheme's builders (chosen by [`NetBuilder::points_for`] and [`NetBuilder::normals_for`], as
//! tessella-gpu's compute builder chooses them) traced into one function of a texel
//! ([`shader::net_texel_glsl`]: each texel's branch computes only the operations its four
//! floats need), for the layout the CPU packs with, and the skinned normal
//! ([`shader::skin_normal`]). The JS pass only poses the corners (three's skinning and morph
//! targets) and calls these.
//!
//! [`PatchNets::pack_texels`]: tessella_core::PatchNets::pack_texels

use crate::errors;
use crate::instanced::InstancedSurface;
use tessella_core::scheme::pn_aen;
use tessella_core::shader::{self, Lang, NetBuilder};
use tessella_core::{NormalMode, Scheme};
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl InstancedSurface {
    /// Why the GPU cannot build this surface's nets (the scheme, tags), or `undefined`.
    #[wasm_bindgen(js_name = netsPassMissing)]
    pub fn nets_pass_missing(&self) -> Option<String> {
        builders(
            &self.surface_options().scheme,
            self.surface_options().tags.is_some(),
        )
        .err()
    }

    /// The net pass's GLSL (ES 3.00), see [`nets_pass_glsl`]. Throws for a surface whose nets
    /// the GPU does not build ([`InstancedSurface::nets_pass_missing`]).
    #[wasm_bindgen(js_name = netsPassGlsl)]
    pub fn nets_pass_glsl(&self) -> Result<String, JsError> {
        let o = self.surface_options();
        nets_pass_glsl(
            &o.scheme,
            o.normal_mode(),
            o.tags.is_some(),
            self.basis_length(),
        )
        .map_err(errors::text)
    }

    /// The pass's per-face vertex indices: each face's 3 corners, then for PN-AEN the 6
    /// vertices whose normals the other sides use ([`pn_aen::across_table`]); `stride` (3 or 9)
    /// words a face, in face order. Fixed by the topology, read once the first frame is built.
    #[wasm_bindgen(js_name = netsPassTopology)]
    pub fn nets_pass_topology(&self) -> Result<Vec<u32>, JsError> {
        self.topology_words().map_err(errors::text)
    }
}

impl InstancedSurface {
    /// [`InstancedSurface::nets_pass_topology`] with a `String` error.
    pub fn topology_words(&self) -> Result<Vec<u32>, String> {
        let Some((surface, _)) = self.built() else {
            return Err("the net pass's topology is known once a frame was built".into());
        };
        let triangles = surface.triangles();
        let across = matches!(surface.options().scheme, Scheme::PnAen)
            .then(|| pn_aen::across_table(triangles, surface.topology()));
        let mut words = Vec::with_capacity(triangles.len() * if across.is_some() { 9 } else { 3 });
        for (f, t) in triangles.iter().enumerate() {
            words.extend_from_slice(t);
            if let Some(a) = &across {
                words.extend_from_slice(&a[f]);
            }
        }
        Ok(words)
    }
}

/// The builder of `scheme`'s points, or why the GPU does not build its nets.
fn builders(scheme: &Scheme, tagged: bool) -> Result<NetBuilder, String> {
    if tagged {
        return Err("tags: the GPU builds untagged nets (the CPU builds tagged ones)".into());
    }
    NetBuilder::points_for(scheme).ok_or_else(|| {
        format!(
            "the GPU builds the control nets of the flat, phong, pn and pn-aen schemes; '{}' nets \
             are built on the CPU",
            scheme.name()
        )
    })
}

/// GLSL (ES 3.00) for the net pass of a surface of `scheme` with `mode`'s normal net and `k`
/// control points:
///
/// - `const int TESSELLA_NETS_STRIDE` (topology words a face: 3, or 9 with PN-AEN's across
///   vertices) and `const bool TESSELLA_NETS_ACROSS`;
/// - `vec3 tessella_skin_normal(mat3 m, vec3 n)`;
/// - the generated `tessella_net_texel` ([`shader::net_texel_glsl`]: each texel computes only
///   the part of the net it holds) and `vec4 tessella_nets_texel_of(vec3 p[3], vec3 n[3], vec3
///   across[6], int j)`, texel `j` of the face's net as [`tessella_core::PatchNets::pack_texels`]
///   packs it (the points then the normal net, 3 floats an entry one after the other, zeros
///   past the last entry), from the posed corners (`across`: the posed unit normals of the
///   across vertices, read by PN-AEN only).
pub fn nets_pass_glsl(
    scheme: &Scheme,
    mode: NormalMode,
    tagged: bool,
    k: usize,
) -> Result<String, String> {
    let points = builders(scheme, tagged)?;
    let normals = NetBuilder::normals_for(mode);
    let across = points == NetBuilder::PnAenPoints;
    let mut s = format!(
        "const int TESSELLA_NETS_STRIDE = {};\nconst bool TESSELLA_NETS_ACROSS = {across};\n",
        if across { 9 } else { 3 }
    );
    s += &shader::skin_normal(Lang::Glsl);
    s += &shader::net_texel_glsl(points, normals, crate::instanced::texels_per_face(k));
    // The shape factor as the f32 the CPU builds with (a round-tripping literal).
    let alpha = match scheme {
        Scheme::Phong { alpha } => format!("{alpha:e}"),
        _ => "0.0".to_string(),
    };
    s += &format!(
        "vec4 tessella_nets_texel_of(vec3 p[3], vec3 n[3], vec3 across[6], int j) {{\n    \
         return tessella_net_texel(p, n, {alpha}, across, j);\n}}\n"
    );
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessella_core::basis::NORMAL_NET_LEN;
    use tessella_core::{Basis, PatchNets};

    /// The layout `shader::net_texel_glsl` writes is the CPU's: `pack_texels` puts a net's
    /// points then its normal net, three floats an entry, four a texel, zeros after.
    #[test]
    fn the_cpu_packs_points_then_normals_four_floats_a_texel() {
        for basis in [Basis::Cubic, Basis::Png1] {
            let k = basis.len();
            // Every float its own value, so a misplaced one shows.
            let nets = PatchNets {
                basis,
                normal_mode: NormalMode::Quadratic,
                points: (0..k)
                    .map(|i| [0, 1, 2].map(|a| (10 * i + a) as f32 + 1.0))
                    .collect(),
                normals: (0..NORMAL_NET_LEN)
                    .map(|i| [0, 1, 2].map(|a| -((10 * i + a) as f32) - 1.0))
                    .collect(),
            };
            let texels = crate::instanced::texels_per_face(k);
            let mut packed = vec![0.0; 4 * texels];
            nets.pack_texels(1, texels, &mut packed);
            let mut want: Vec<f32> = nets
                .points
                .iter()
                .chain(&nets.normals)
                .flatten()
                .copied()
                .collect();
            want.resize(4 * texels, 0.0);
            assert_eq!(packed, want, "{basis:?}");
        }
    }

    #[test]
    fn the_pass_calls_the_scheme_s_generated_builders_and_refuses_the_others() {
        let cases = [
            (Scheme::Flat, NormalMode::Linear, "0.0"),
            (Scheme::Phong { alpha: 0.6 }, NormalMode::Linear, "6e-1"),
            (Scheme::Pn, NormalMode::Quadratic, "0.0"),
            (Scheme::PnAen, NormalMode::Quadratic, "0.0"),
        ];
        for (scheme, mode, alpha) in cases {
            let g = nets_pass_glsl(&scheme, mode, false, 10).unwrap();
            let points = NetBuilder::points_for(&scheme).unwrap();
            let texels = crate::instanced::texels_per_face(10);
            assert!(g.contains(&shader::net_texel_glsl(
                points,
                NetBuilder::normals_for(mode),
                texels
            )));
            let call = format!("tessella_net_texel(p, n, {alpha}, across, j)");
            assert!(g.contains(&shader::skin_normal(Lang::Glsl)));
            assert!(g.contains(&call), "{scheme:?}: {g}");
            let across = scheme == Scheme::PnAen;
            assert!(g.contains(&format!("TESSELLA_NETS_ACROSS = {across};")));
        }
        let e = nets_pass_glsl(&Scheme::Png1, NormalMode::Quadratic, false, 21).unwrap_err();
        assert!(e.contains("'png1' nets are built on the CPU"), "{e}");
        let e = nets_pass_glsl(&Scheme::Pn, NormalMode::Quadratic, true, 10).unwrap_err();
        assert!(e.contains("tags"), "{e}");
    }

    #[test]
    fn the_topology_is_each_face_s_corners_then_pn_aen_s_across_vertices() {
        // Two triangles sharing an edge.
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.2];
        let indices = [0, 1, 2, 2, 1, 3];
        let mut pn = InstancedSurface::with(&indices, r#"{"scheme":"pn","level":2}"#).unwrap();
        assert!(pn.topology_words().is_err());
        pn.step_with(&positions, None).unwrap();
        assert_eq!(pn.topology_words().unwrap(), indices);
        let mut aen = InstancedSurface::with(&indices, r#"{"scheme":"pn-aen","level":2}"#).unwrap();
        aen.step_with(&positions, None).unwrap();
        let words = aen.topology_words().unwrap();
        assert_eq!(words.len(), 18);
        assert_eq!(&words[..3], &indices[..3]);
        assert_eq!(&words[9..12], &indices[3..]);
        // Face 0's edge 1 (corners 1 -> 2) is face 1's: its across vertices are 1 and 2.
        assert_eq!(&words[5..7], &[1, 2]);
    }
}
