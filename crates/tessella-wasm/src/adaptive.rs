//! `AdaptiveSurface`: what `TessellatedMesh`'s `lod` option (js/src/three-lod.js) draws from in
//! WebGL2, the counterpart of tessella-gpu's `AdaptiveRenderer` (whose storage buffers WebGL2
//! lacks).
//!
//! Built once: the spacing's parts (strips and interiors of the hardware tessellator's patterns,
//! `tessella_core::refine::instanced::PartTable`) as one vertex array of point codes and one
//! index array, with each part's index range; the GLSL. Built per frame, O(coarse triangles):
//! the nets ([`InstancedSurface`]'s packing and texture layout), and from per-edge levels (given,
//! or from a LOD function and the camera, `tessella_core::refine::lod`, one level per unique
//! edge so both faces of an edge agree) one record per face and one instance per face and part
//! (`refine::instanced::frame_instances`), grouped into one draw per part used.
//!
//! A record is the core's 24 words ([`RECORD_WORDS`]) of which the tessellator reads 21 (four
//! rulers of five words and the canonical edge bits); they are packed into 12 words (three
//! `RGBA32UI` texels per face, the core's `refine::packed`) so that a frame uploads 48 bytes of records
//! and at most 16 of instances per coarse triangle.

use crate::instanced::{
    glsl as nets_glsl, wgsl as nets_wgsl, InstancedSurface, Layout, MAX_TEXTURE_WIDTH,
};
use crate::{errors, options::Options};
use tessella_core::refine::instanced::{FrameInstances, PartTable, RECORD_WORDS};
use tessella_core::refine::packed::{pack_record, PACKED_WORDS};
use tessella_core::refine::{canonical, Camera, InstancedDriver, Lod, SurfaceOptions};
use tessella_core::shader::{self, Lang};
use tessella_core::{Named, NormalMode};
use wasm_bindgen::prelude::*;

/// Texels (RGBA32UI) of a packed record.
pub const RECORD_TEXELS: usize = PACKED_WORDS / 4;
/// Words of one ruler in the core's record (`tessellator::points::RULER_WORDS`; the GLSL's
/// `TESSELLA_RULER_WORDS`, which a test compares).
#[cfg(test)]
const RULER_WORDS: usize = 5;

/// What the LOD function needs each frame, parsed once.
#[derive(Debug, Clone, Copy)]
enum LodKind {
    /// Levels from the nets alone.
    Tolerance(f32),
    /// Pixels per segment; needs the camera and the image size.
    Screen(f32),
    /// Near, far, max; needs the eye.
    Distance(f32, f32, f32),
}

#[wasm_bindgen]
pub struct AdaptiveSurface {
    nets: InstancedSurface,
    lod: Option<LodKind>,
    driver: InstancedDriver,
    /// Every part's distinct point codes, one part after the other.
    codes: Vec<u32>,
    /// Every part's triangles as indices into `codes`.
    indices: Vec<u32>,
    /// Per part id: first index and index count.
    ranges: Vec<u32>,
    records_layout: Layout,
    /// `records_layout.width * height * 4` words.
    records: Vec<u32>,
    /// `face | side << 30`, grouped by part; room for four per face.
    instances: Vec<u32>,
}

crate::arrays::frame_input_exports!(AdaptiveSurface, via nets);

#[wasm_bindgen]
impl AdaptiveSurface {
    /// `options`: `scheme`, `normals`, `alpha`, `spacing` (a tessellator spacing); `lod`: the
    /// LOD function's text (`tolerance:D`, `screen:PX`, `distance:NEAR,FAR,MAX`) or empty, for
    /// levels given by [`AdaptiveSurface::set_levels`].
    #[wasm_bindgen(constructor)]
    pub fn new(indices: &[u32], options: &str, lod: &str) -> Result<AdaptiveSurface, JsError> {
        AdaptiveSurface::with(indices, options, lod).map_err(errors::text)
    }

    #[wasm_bindgen(js_name = basisLength)]
    pub fn basis_length(&self) -> usize {
        self.nets.basis_length()
    }
    #[wasm_bindgen(js_name = normalMode)]
    pub fn normal_mode(&self) -> String {
        self.nets.normal_mode()
    }
    /// The spacing's name.
    pub fn spacing(&self) -> String {
        self.driver.spacing().name().to_string()
    }
    #[wasm_bindgen(js_name = faceCount)]
    pub fn face_count(&self) -> usize {
        self.nets.face_count()
    }
    #[wasm_bindgen(js_name = texelsPerFace)]
    pub fn texels_per_face(&self) -> usize {
        self.nets.texels_per_face()
    }
    #[wasm_bindgen(js_name = facesPerRow)]
    pub fn faces_per_row(&self) -> usize {
        self.nets.faces_per_row()
    }
    #[wasm_bindgen(js_name = textureWidth)]
    pub fn texture_width(&self) -> usize {
        self.nets.texture_width()
    }
    #[wasm_bindgen(js_name = textureHeight)]
    pub fn texture_height(&self) -> usize {
        self.nets.texture_height()
    }
    /// Records texture (RGBA32UI, three texels a face): faces per row, width, height.
    #[wasm_bindgen(js_name = recordsPerRow)]
    pub fn records_per_row(&self) -> usize {
        self.records_layout.faces_per_row
    }
    #[wasm_bindgen(js_name = recordsWidth)]
    pub fn records_width(&self) -> usize {
        self.records_layout.width
    }
    #[wasm_bindgen(js_name = recordsHeight)]
    pub fn records_height(&self) -> usize {
        self.records_layout.height
    }
    /// Unique edges of the mesh (once a frame was built): the length of `setLevels`' array.
    #[wasm_bindgen(js_name = edgeCount)]
    pub fn edge_count(&self) -> usize {
        self.nets
            .built()
            .map_or(0, |(s, _)| s.topology().edges.len())
    }

    /// The parts' point codes (one vertex each), built once.
    #[wasm_bindgen(js_name = partCodes)]
    pub fn part_codes(&self) -> Vec<u32> {
        self.codes.clone()
    }
    /// The parts' triangles, indices into `partCodes`.
    #[wasm_bindgen(js_name = partIndices)]
    pub fn part_indices(&self) -> Vec<u32> {
        self.indices.clone()
    }
    /// Per part id its first index and index count.
    #[wasm_bindgen(js_name = partRanges)]
    pub fn part_ranges(&self) -> Vec<u32> {
        self.ranges.clone()
    }

    /// The vertex shader's GLSL (ES 3.00): see [`glsl`].
    pub fn glsl(&self) -> String {
        let o = self.nets.surface_options();
        glsl(o.scheme.basis(), o.normal_mode())
    }

    /// The same in WGSL, for three.js's WebGPURenderer (TSL `wgslFn`): see [`wgsl`].
    pub fn wgsl(&self) -> String {
        let o = self.nets.surface_options();
        wgsl(o.scheme.basis(), o.normal_mode())
    }

    #[wasm_bindgen(js_name = netsOutput)]
    pub fn nets_output(&self) -> *const f32 {
        self.nets.nets_output()
    }
    #[wasm_bindgen(js_name = netsLength)]
    pub fn nets_length(&self) -> usize {
        self.nets.nets_length()
    }
    #[wasm_bindgen(js_name = boundsOutput)]
    pub fn bounds_output(&self) -> *const f32 {
        self.nets.bounds_output()
    }

    /// Levels of the LOD function on the last frame, seen by a camera at `eye` looking at
    /// `target` with vertical field of view `fov` degrees on an image `width × height`
    /// (the mesh's own coordinates; `tolerance` reads none of them).
    #[allow(clippy::too_many_arguments)]
    #[wasm_bindgen(js_name = setLod)]
    pub fn set_lod(
        &mut self,
        ex: f32,
        ey: f32,
        ez: f32,
        tx: f32,
        ty: f32,
        tz: f32,
        fov: f32,
        width: u32,
        height: u32,
    ) -> Result<(), JsError> {
        let camera = Camera {
            eye: [ex, ey, ez],
            target: [tx, ty, tz],
            fov_y_deg: fov,
        };
        self.lod_with(camera, [width, height]).map_err(errors::text)
    }

    /// Per-edge levels given by the caller: one per unique edge (the core's `Topology::edges`
    /// order, `edgeCount` of them).
    #[wasm_bindgen(js_name = setLevels)]
    pub fn set_levels(&mut self, levels: &[f32]) -> Result<(), JsError> {
        self.levels_with(levels, None).map_err(errors::text)
    }

    /// The last levels, one per unique edge.
    #[wasm_bindgen(js_name = edgeLevels)]
    pub fn edge_levels(&self) -> Vec<f32> {
        self.driver.edge_levels().to_vec()
    }
    /// The packed records (`recordsWidth * recordsHeight * 4` words) in wasm memory.
    #[wasm_bindgen(js_name = recordsOutput)]
    pub fn records_output(&self) -> *const u32 {
        self.records.as_ptr()
    }
    #[wasm_bindgen(js_name = recordsLength)]
    pub fn records_length(&self) -> usize {
        self.records.len()
    }
    /// The instances (`face | side << 30`, grouped by part) in wasm memory: `instanceCount`
    /// of them, in an array of room for `4 * faceCount`.
    #[wasm_bindgen(js_name = instancesOutput)]
    pub fn instances_output(&self) -> *const u32 {
        self.instances.as_ptr()
    }
    #[wasm_bindgen(js_name = instanceCount)]
    pub fn instance_count(&self) -> usize {
        self.driver.frame().instances.len()
    }
    /// One draw per part used: part id, first instance, instance count.
    pub fn draws(&self) -> Vec<u32> {
        self.driver
            .frame()
            .draws
            .iter()
            .flat_map(|d| [d.part, d.instances.start, d.instances.len() as u32])
            .collect()
    }
    /// Triangles the last levels draw.
    #[wasm_bindgen(js_name = triangleCount)]
    pub fn triangle_count(&self) -> f64 {
        self.driver.frame().triangles as f64
    }
}

impl AdaptiveSurface {
    /// [`AdaptiveSurface::new`] with a `String` error.
    pub fn with(indices: &[u32], options: &str, lod: &str) -> Result<AdaptiveSurface, String> {
        let given: serde_json::Value =
            serde_json::from_str(options).map_err(|e| format!("bad options: {e}"))?;
        if given.get("level").is_some_and(|v| !v.is_null()) {
            return Err("level: with lod the levels come from the LOD function".into());
        }
        let Options {
            refine: options,
            origin,
        } = Options::from_json(options)?;
        if origin {
            return Err("origin: not an option of an adaptive surface".into());
        }
        if !options.weld {
            return Err("soup: not an option of an adaptive surface".into());
        }
        let spacing = options.spacing;
        if spacing.tessellator().is_none() {
            return Err(format!(
                "spacing: lod draws the GPU tessellator's patterns: give spacing \
                 'equal', 'fractional-odd' or 'fractional-even' (not '{}')",
                spacing.name()
            ));
        }
        let lod = parse_lod(lod)?;
        let surface = SurfaceOptions {
            scheme: options.scheme,
            normals: options.normals,
            tags: options.tags.clone(),
        };
        let nets = InstancedSurface::for_adaptive(indices, surface)?;
        let faces = nets.face_count();
        let records_layout = Layout::new(faces, RECORD_TEXELS);
        if records_layout.height > MAX_TEXTURE_WIDTH {
            return Err(format!(
                "{faces} triangles need a records texture of {} rows, over {MAX_TEXTURE_WIDTH}",
                records_layout.height
            ));
        }
        let table = PartTable::new(spacing);
        let (codes, indices, ranges) = part_arrays(&table);
        Ok(AdaptiveSurface {
            nets,
            lod,
            driver: InstancedDriver::with_table(std::sync::Arc::new(table)),
            codes,
            indices,
            ranges,
            records: vec![0; records_layout.width * records_layout.height * 4],
            records_layout,
            instances: vec![0; 4 * faces],
        })
    }

    /// The LOD function's levels for `camera` and `size` on the last frame.
    pub fn lod_with(&mut self, camera: Camera, size: [u32; 2]) -> Result<(), String> {
        let kind = self
            .lod
            .ok_or("no lod: this surface takes its levels from setLevels")?;
        let lod = match kind {
            LodKind::Tolerance(d) => Lod::Tolerance { max_deviation: d },
            LodKind::Screen(pixels) => Lod::Screen {
                pixels,
                camera,
                size,
            },
            LodKind::Distance(near, far, max) => Lod::Distance {
                near,
                far,
                max,
                eye: camera.eye,
            },
        };
        let (surface, frame) = self.nets.built().ok_or("no frame yet: update() first")?;
        self.driver
            .update(surface, frame, &lod)
            .map_err(|e| errors::message(&e))?;
        self.write_frame();
        Ok(())
    }

    /// Records and instances of per-edge levels (and per-face minimum inner levels).
    pub fn levels_with(&mut self, edges: &[f32], faces: Option<&[f32]>) -> Result<(), String> {
        let (surface, _) = self.nets.built().ok_or("no frame yet: update() first")?;
        self.driver
            .set_levels(surface, edges, faces)
            .map_err(|e| errors::message(&e))?;
        self.write_frame();
        Ok(())
    }

    /// The driver's records, packed into the records texture's words, and its instances.
    fn write_frame(&mut self) {
        let frame = self.driver.frame();
        let Layout {
            faces_per_row,
            width,
            ..
        } = self.records_layout;
        for (f, record) in frame.records.chunks_exact(RECORD_WORDS).enumerate() {
            let start = ((f / faces_per_row) * width + (f % faces_per_row) * RECORD_TEXELS) * 4;
            self.records[start..start + PACKED_WORDS].copy_from_slice(&pack_record(record));
        }
        self.instances[..frame.instances.len()].copy_from_slice(&frame.instances);
    }

    /// The frame's draws (for the tests).
    pub fn frame_instances(&self) -> &FrameInstances {
        self.driver.frame()
    }

    /// The packed record of face `f`, `None` past the last face (for the tests).
    #[cfg(test)]
    fn packed_record(&self, f: usize) -> Option<[u32; PACKED_WORDS]> {
        let l = self.records_layout;
        let start = ((f / l.faces_per_row) * l.width + (f % l.faces_per_row) * RECORD_TEXELS) * 4;
        self.records
            .get(start..start + PACKED_WORDS)?
            .try_into()
            .ok()
    }

    /// The nets half (frames, packing).
    pub fn nets_mut(&mut self) -> &mut InstancedSurface {
        &mut self.nets
    }
}

fn parse_lod(text: &str) -> Result<Option<LodKind>, String> {
    if text.is_empty() {
        return Ok(None);
    }
    // The camera and size come every frame; a stand-in one validates the rest now.
    let stand_in = Camera {
        eye: [0.0, 0.0, 1.0],
        target: [0.0; 3],
        fov_y_deg: 45.0,
    };
    let lod = Lod::parse(text, Some(stand_in), Some([1, 1]))
        .map_err(|e| format!("lod: {}", errors::message(&e)))?;
    Ok(Some(match lod {
        Lod::Tolerance { max_deviation } => LodKind::Tolerance(max_deviation),
        Lod::Screen { pixels, .. } => LodKind::Screen(pixels),
        Lod::Distance { near, far, max, .. } => LodKind::Distance(near, far, max),
        other => {
            return Err(format!(
                "lod: {other:?} is not drawn by an adaptive surface"
            ))
        }
    }))
}

/// The part table as arrays: per part its distinct codes and its triangles as absolute indices
/// into them (WebGL2 has no base vertex), and per part id `[first index, index count]`.
fn part_arrays(table: &PartTable) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    let mut codes = Vec::new();
    let mut indices = Vec::new();
    let mut ranges = Vec::with_capacity(2 * table.ranges.len());
    for part in 0..table.ranges.len() as u32 {
        let (own, local) = table.part_vertices(part);
        let (base, first) = (codes.len() as u32, indices.len() as u32);
        codes.extend(own);
        indices.extend(local.iter().map(|i| base + i));
        ranges.extend([first, indices.len() as u32 - first]);
    }
    (codes, indices, ranges)
}

/// GLSL (ES 3.00) for a vertex shader that draws one part instance: [`nets_glsl`]'s nets
/// reader and `tessella_evaluate` (the basis' and normal net's weights generated from the core's
/// formulas), the record layout constants, the packed record's and the edge tables' reads, and
/// the adaptive point's steps generated from the core's Rust: the tessellator's placement
/// `tessella_locate`, its barycentric point and canonical parameter
/// `tessella_tessellator_point`, the canonical edge weights and point
/// (`shader::locate_glsl`, `shader::tessellator_point`, `shader::edge_weights_glsl`,
/// `shader::canonical_edge`, `shader::canonical_edge_point`); last, from the core's adaptive
/// point (`shader::adaptive_point`, over `tessella_evaluate`),
/// `void tessella_adaptive_evaluate(uint code, uint inst, out vec3 position, out vec3 normal,
/// out vec3 bary)`:
/// the point the part's `code` names on instance `inst` (`face | side << 30`), placed with the
/// face's record and evaluated there; a point on a coarse edge from the edge's four boundary
/// control points in canonical order with weights from the edge's own 16.16 position, the same
/// floats from both faces (as `adaptive.wgsl` does); `bary` is the point's barycentric
/// coordinates in the coarse triangle. It declares, beside the nets' uniforms,
/// `uniform highp usampler2D tessellaRecords` and `uniform int tessellaRecordsPerRow`.
pub fn glsl(basis: tessella_core::Basis, mode: NormalMode) -> String {
    let mut s = nets_glsl(basis, mode);
    s += "uniform highp usampler2D tessellaRecords;\nuniform int tessellaRecordsPerRow;\n";
    s += &shader::record_layout(Lang::Glsl);
    s += &shader::constants(
        Lang::Glsl,
        &[
            ("TESSELLA_BASIS_K", basis.len() as u32),
            ("TESSELLA_RECORD_TEXELS", RECORD_TEXELS as u32),
        ],
    );
    let [controls, normals] = edge_tables(basis);
    s += &format!(
        "const uint TESSELLA_EDGE_CONTROLS[12] = uint[12]({controls});\n\
         const uint TESSELLA_EDGE_NORMALS[9] = uint[9]({normals});\n"
    );
    s += &format!(
        "const bool TESSELLA_REAL_NORMALS = {};\n",
        mode == NormalMode::Real
    );
    s += ADAPTIVE_GLSL_READERS;
    s += &shader::packed_record(Lang::Glsl);
    s += &shader::locate_glsl();
    s += &shader::tessellator_point(Lang::Glsl);
    s += &shader::edge_weights_glsl();
    s += &shader::canonical_edge(Lang::Glsl);
    s += &shader::canonical_edge_point(Lang::Glsl, &edge_sources(Lang::Glsl));
    let steps = shader::adaptive_point(Lang::Glsl, &point_sources(Lang::Glsl));
    s += &format!(
        "void tessella_adaptive_evaluate(uint code, uint inst, out vec3 position, out vec3 normal, \
         out vec3 bary) {{\n    int face = int(inst & 0x3fffffffu);\n    tessella_read_record(face);\n\
         {steps}    bary = l;\n}}\n"
    );
    s
}

/// The adaptive point's sources in either language: the record read into locals (`0u`), its
/// bits from the packed record, the point evaluated by [`nets_glsl`]'s `tessella_evaluate` or
/// [`nets_wgsl`]'s `tessella_position` and `tessella_normal` (whose reads take the nets
/// texture first).
fn point_sources(lang: Lang) -> shader::PointSources<'static> {
    let wgsl = matches!(lang, Lang::Wgsl);
    shader::PointSources {
        face: if wgsl { "face" } else { "uint(face)" },
        context: if wgsl { "nets, " } else { "" },
        record: "0u",
        code: "code & 0x3fffffffu",
        side: "inst >> 30u",
        forward_bits: "tessella_forward_bits()",
        evaluate: if wgsl {
            "position = tessella_position(nets, face, l);\nnormal = tessella_normal(nets, face, l);"
        } else {
            "tessella_evaluate(face, l, position, normal);"
        },
    }
}

/// The canonical edge point's sources in either language: the WGSL's net reads take the nets
/// texture first (TSL passes it), and the mode is the `TESSELLA_REAL_NORMALS` constant.
fn edge_sources(lang: Lang) -> shader::EdgeSources<'static> {
    shader::EdgeSources {
        context: if matches!(lang, Lang::Wgsl) {
            ("nets: texture_2d<f32>, ", "nets, ")
        } else {
            ("", "")
        },
        net_normals: "!TESSELLA_REAL_NORMALS",
    }
}

/// The edge tables both languages declare: per coarse edge its four boundary control points
/// (`canonical::edge_controls`) and its three normal-net entries
/// (`canonical::edge_normal_controls`), in canonical order, as `u32` literals.
fn edge_tables(basis: tessella_core::Basis) -> [String; 2] {
    let controls: Vec<String> = (0..3)
        .flat_map(|k| canonical::edge_controls(basis, k))
        .map(|i| format!("{i}u"))
        .collect();
    let normals: Vec<String> = (0..3)
        .flat_map(canonical::edge_normal_controls)
        .map(|i| format!("{i}u"))
        .collect();
    [controls.join(", "), normals.join(", ")]
}

/// WGSL for three.js's WebGPURenderer (TSL `wgslFn`), the twin of [`glsl`]: [`nets_wgsl`]'s
/// nets reader, `tessella_position` and `tessella_normal`, the record layout constants, the
/// edge tables, the packed record's reader, the same generated steps (`tessella_locate`,
/// `tessella_tessellator_point`, `tessella_edge_weights`, `tessella_canonical_edge`,
/// `tessella_canonical_edge_point`, whose net reads take the nets texture first), and last
/// `fn tessella_adaptive_point(nets: texture_2d<f32>, records: texture_2d<u32>,
/// instances: texture_2d<u32>, code: u32, instance: u32) -> mat3x3<f32>`:
/// [`glsl`]'s `tessella_adaptive_evaluate` for the instance word (`face | side << 30`) at
/// `instance` of the `instances` texture (R32UI, row-major; three.js cannot give a WebGPU
/// draw a first instance, so a part reads its words at its first plus the instance index),
/// returning the columns point, unit normal, barycentric coordinates. The textures' rows are
/// their widths over the texels per record / face. Its steps are the core's adaptive point
/// (`shader::adaptive_point`, over `tessella_position` and `tessella_normal`), as the GLSL's;
/// the readers are written next to the GLSL's (`ADAPTIVE_WGSL_READERS`), validated by naga in
/// the tests.
pub fn wgsl(basis: tessella_core::Basis, mode: NormalMode) -> String {
    let mut s = nets_wgsl(basis, mode);
    s += &shader::record_layout(Lang::Wgsl);
    s += &shader::constants(
        Lang::Wgsl,
        &[
            ("TESSELLA_BASIS_K", basis.len() as u32),
            ("TESSELLA_RECORD_TEXELS", RECORD_TEXELS as u32),
        ],
    );
    let [controls, normals] = edge_tables(basis);
    // Private arrays: indexed by a runtime value (a const array may not be, everywhere).
    s += &format!(
        "var<private> TESSELLA_EDGE_CONTROLS: array<u32, 12> = array<u32, 12>({controls});\n\
         var<private> TESSELLA_EDGE_NORMALS: array<u32, 9> = array<u32, 9>({normals});\n"
    );
    s += &format!(
        "const TESSELLA_REAL_NORMALS: bool = {};\n",
        mode == NormalMode::Real
    );
    s += ADAPTIVE_WGSL_READERS;
    s += &shader::packed_record(Lang::Wgsl);
    s += &shader::locate_wgsl();
    s += &shader::tessellator_point(Lang::Wgsl);
    s += &shader::edge_weights_wgsl();
    s += &shader::canonical_edge(Lang::Wgsl);
    s += &shader::canonical_edge_point(Lang::Wgsl, &edge_sources(Lang::Wgsl));
    let steps = shader::adaptive_point(Lang::Wgsl, &point_sources(Lang::Wgsl));
    s += &format!(
        "fn tessella_adaptive_point(nets: texture_2d<f32>, records: texture_2d<u32>, \
         instances: texture_2d<u32>, code: u32, instance: u32) -> mat3x3<f32> {{\n    \
         let inst = tessella_instance_word(instances, instance);\n    \
         let face = inst & 0x3fffffffu;\n    \
         tessella_read_record(records, face);\n    \
         var position: vec3<f32>;\n    \
         var normal: vec3<f32>;\n\
         {steps}    return mat3x3<f32>(position, normal, l);\n}}\n"
    );
    s
}

/// [`ADAPTIVE_GLSL_READERS`] in WGSL, and the instance word's reader.
const ADAPTIVE_WGSL_READERS: &str = r#"var<private> tessella_rec: array<vec4<u32>, 3>;
fn tessella_read_record(records: texture_2d<u32>, face: u32) {
    let per_row = textureDimensions(records).x / TESSELLA_RECORD_TEXELS;
    let row = face / per_row;
    let column = (face - row * per_row) * TESSELLA_RECORD_TEXELS;
    for (var j = 0u; j < 3u; j++) {
        tessella_rec[j] = textureLoad(records, vec2<u32>(column + j, row), 0);
    }
}
fn tessella_packed(i: u32) -> u32 {
    return tessella_rec[i >> 2u][i & 3u];
}
fn tessella_net_float(nets: texture_2d<f32>, face: u32, x: u32) -> f32 {
    return tessella_texel(nets, face, x >> 2u)[x & 3u];
}
fn tessella_net_point(nets: texture_2d<f32>, face: u32, k: u32) -> vec3<f32> {
    let x = 3u * k;
    return vec3<f32>(tessella_net_float(nets, face, x), tessella_net_float(nets, face, x + 1u), tessella_net_float(nets, face, x + 2u));
}
fn tessella_net_normal(nets: texture_2d<f32>, face: u32, k: u32) -> vec3<f32> {
    return tessella_net_point(nets, face, TESSELLA_BASIS_K + k);
}
fn tessella_edge_control(edge: u32, i: u32) -> u32 {
    return TESSELLA_EDGE_CONTROLS[4u * edge + i];
}
fn tessella_edge_normal_control(edge: u32, i: u32) -> u32 {
    return TESSELLA_EDGE_NORMALS[3u * edge + i];
}
fn tessella_instance_word(instances: texture_2d<u32>, i: u32) -> u32 {
    let width = textureDimensions(instances).x;
    let row = i / width;
    return textureLoad(instances, vec2<u32>(i - row * width, row), 0).x;
}
"#;

/// The packed record's texel reads (`tessella_packed`, under the generated
/// `shader::packed_record`), and the reads the generated canonical edge point takes: the nets' entries and the edge tables.
const ADAPTIVE_GLSL_READERS: &str = r#"uvec4 tessella_rec[3];
void tessella_read_record(int face) {
    int row = face / tessellaRecordsPerRow;
    int column = (face - row * tessellaRecordsPerRow) * int(TESSELLA_RECORD_TEXELS);
    for (int j = 0; j < 3; j++) tessella_rec[j] = texelFetch(tessellaRecords, ivec2(column + j, row), 0);
}
uint tessella_packed(uint i) { return tessella_rec[i >> 2u][i & 3u]; }
float tessella_net_float(int face, int x) {
    vec4 t = tessella_texel(face, x >> 2);
    return t[x & 3];
}
vec3 tessella_net_point(uint face, uint k) {
    int x = 3 * int(k);
    return vec3(tessella_net_float(int(face), x), tessella_net_float(int(face), x + 1), tessella_net_float(int(face), x + 2));
}
vec3 tessella_net_normal(uint face, uint k) { return tessella_net_point(face, TESSELLA_BASIS_K + k); }
uint tessella_edge_control(uint edge, uint i) { return TESSELLA_EDGE_CONTROLS[4u * edge + i]; }
uint tessella_edge_normal_control(uint edge, uint i) { return TESSELLA_EDGE_NORMALS[3u * edge + i]; }
"#;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_meshes::sample;
    use tessella_core::refine::instanced::FORWARD_WORD;
    use tessella_core::refine::{packed, Levels, Plan};

    fn flat(p: &[[f32; 3]]) -> Vec<f32> {
        p.iter().flatten().copied().collect()
    }

    #[test]
    fn packed_records_give_back_every_word_and_the_cpus_triangle_count() {
        let (m, indices) = sample();
        for spacing in ["equal", "fractional-odd", "fractional-even"] {
            let json = format!(r#"{{"scheme":"pn","spacing":"{spacing}"}}"#);
            let mut s = AdaptiveSurface::with(&indices, &json, "screen:4").unwrap();
            s.nets_mut()
                .step_with(&flat(m.positions()), Some(&flat(m.normals())))
                .unwrap();
            for (eye, size) in [
                ([0.0, 0.0, 3.0], [640, 480]),
                ([0.3, 0.2, 1.3], [1920, 1080]),
            ] {
                let camera = Camera {
                    eye,
                    target: [0.0; 3],
                    fov_y_deg: 50.0,
                };
                s.lod_with(camera, size).unwrap();
                let frame = s.frame_instances().clone();
                for (f, record) in frame.records.chunks_exact(RECORD_WORDS).enumerate() {
                    let packed = s.packed_record(f).expect("a face's record");
                    for r in 0..4 {
                        for k in 0..RULER_WORDS {
                            assert_eq!(
                                packed::ruler_word(&packed, r, k),
                                record[RULER_WORDS * r + k],
                                "{spacing} face {f} ruler {r} word {k}"
                            );
                        }
                    }
                    assert_eq!(packed::forward_bits(&packed), record[FORWARD_WORD]);
                }
                // The CPU's adaptive refinement with the same LOD makes as many triangles.
                let options = Options::from_json(&json)
                    .unwrap()
                    .refine
                    .with_levels(Levels::Lod(Lod::Screen {
                        pixels: 4.0,
                        camera,
                        size,
                    }));
                let plan = Plan::new(&m, &options).unwrap();
                assert_eq!(frame.triangles, plan.triangle_count() as u64, "{spacing}");
            }
        }
    }

    #[test]
    fn the_glsl_holds_the_generated_placement_edge_point_and_the_record_layout() {
        let g = glsl(tessella_core::Basis::Cubic, NormalMode::Quadratic);
        assert!(g.contains(&shader::locate_glsl()));
        // The packed record's reader: the generated one, the only one.
        assert!(g.contains(&shader::packed_record(Lang::Glsl)));
        assert_eq!(g.matches("uint tessella_ruler_word(").count(), 1);
        assert_eq!(g.matches("uint tessella_forward_bits(").count(), 1);
        assert!(g.contains(&shader::edge_weights_glsl()));
        assert!(g.contains(&shader::canonical_edge(Lang::Glsl)));
        // The adaptive point's steps: generated, and called by the entry.
        assert!(g.contains(&shader::tessellator_point(Lang::Glsl)));
        assert!(g.contains(&shader::canonical_edge_point(
            Lang::Glsl,
            &edge_sources(Lang::Glsl)
        )));
        // The entry: the core's adaptive point over tessella_evaluate, its point's barycentric
        // coordinates given back.
        let steps = shader::adaptive_point(Lang::Glsl, &point_sources(Lang::Glsl));
        let entry = g.find("void tessella_adaptive_evaluate(uint code, uint inst, out vec3 position, out vec3 normal, out vec3 bary) {").unwrap();
        assert_eq!(g[entry..].matches(&steps).count(), 1);
        assert!(g.ends_with("    bary = l;\n}\n"));
        assert!(g.contains(&format!(
            "const uint TESSELLA_RULER_WORDS = {RULER_WORDS}u;"
        )));
        assert!(g.contains("void tessella_evaluate(int face"));
        assert!(g.contains("const bool TESSELLA_REAL_NORMALS = false;"));
    }

    #[test]
    fn the_wgsl_is_valid_and_holds_the_generated_placement_and_the_glsls_tables() {
        use tessella_core::Basis;
        for (basis, mode) in [
            (Basis::Cubic, NormalMode::Quadratic),
            (Basis::Cubic, NormalMode::Linear),
            (Basis::Png1, NormalMode::Real),
        ] {
            let w = wgsl(basis, mode);
            let g = glsl(basis, mode);
            assert!(w.contains(&shader::locate_wgsl()));
            assert!(w.contains(&shader::packed_record(Lang::Wgsl)));
            assert_eq!(w.matches("fn tessella_ruler_word(").count(), 1);
            assert_eq!(w.matches("fn tessella_forward_bits(").count(), 1);
            assert!(w.contains(&shader::edge_weights_wgsl()));
            assert!(w.contains(&shader::canonical_edge(Lang::Wgsl)));
            assert!(w.contains(&shader::tessellator_point(Lang::Wgsl)));
            assert!(w.contains(&shader::canonical_edge_point(
                Lang::Wgsl,
                &edge_sources(Lang::Wgsl)
            )));
            assert!(w.contains(&shader::record_layout(Lang::Wgsl)));
            assert!(w.starts_with(&nets_wgsl(basis, mode)));
            // The same edge tables as the GLSL's.
            let [controls, normals] = edge_tables(basis);
            assert!(w.contains(&format!("array<u32, 12>({controls});")));
            assert!(g.contains(&format!("uint[12]({controls});")));
            assert!(w.contains(&format!("array<u32, 9>({normals});")));
            assert!(g.contains(&format!("uint[9]({normals});")));
            assert_eq!(
                w.contains("const TESSELLA_REAL_NORMALS: bool = true;"),
                mode == NormalMode::Real
            );
            // The entry TSL calls: the core's adaptive point over tessella_position and
            // tessella_normal, last.
            let steps = shader::adaptive_point(Lang::Wgsl, &point_sources(Lang::Wgsl));
            assert_eq!(w.matches(&steps).count(), 1);
            let at = w.find("fn tessella_adaptive_point(nets: texture_2d<f32>, records: texture_2d<u32>, instances: texture_2d<u32>, code: u32, instance: u32) -> mat3x3<f32> {").unwrap();
            assert!(!w[at + 3..].contains("\nfn "));
            // A vertex shader as three's would include it: valid WGSL.
            let module = format!(
                "{w}@group(0) @binding(0) var nets: texture_2d<f32>;\n\
                 @group(0) @binding(1) var records: texture_2d<u32>;\n\
                 @group(0) @binding(2) var instances: texture_2d<u32>;\n\
                 @vertex fn main(@builtin(instance_index) i: u32, @location(0) code: u32) -> @builtin(position) vec4<f32> {{\n    \
                 let m = tessella_adaptive_point(nets, records, instances, code, 3u + i);\n    \
                 return vec4<f32>(m[0] + m[1] + m[2], 1.0);\n}}\n"
            );
            crate::naga_check::validate_wgsl(&module, "the adaptive module");
        }
    }

    #[test]
    fn options_outside_the_adaptive_path_are_refused_by_name() {
        let (_, indices) = sample();
        for (json, lod, expected) in [
            (r#"{}"#, "screen:4", "spacing: lod draws"),
            (r#"{"spacing":"grid"}"#, "screen:4", "spacing: lod draws"),
            (
                r#"{"spacing":"equal","level":3}"#,
                "screen:4",
                "level: with lod",
            ),
            (r#"{"spacing":"equal"}"#, "screen:0", "lod: "),
            (r#"{"spacing":"equal"}"#, "fast", "lod: "),
            (r#"{"spacing":"equal","soup":true}"#, "screen:4", "soup"),
        ] {
            let err = AdaptiveSurface::with(&indices, json, lod).err().unwrap();
            assert!(err.contains(expected), "{json} {lod}: {err}");
        }
        let mut s =
            AdaptiveSurface::with(&indices, r#"{"spacing":"equal"}"#, "tolerance:0.01").unwrap();
        let camera = Camera {
            eye: [0.0, 0.0, 3.0],
            target: [0.0; 3],
            fov_y_deg: 50.0,
        };
        assert!(s
            .lod_with(camera, [4, 4])
            .unwrap_err()
            .contains("no frame yet"));
    }
}
