//! Refinement on the GL tessellation stages, read back by transform feedback, and the
//! comparison with the CPU refinement of the same options.

use crate::context::GlContext;
use crate::error::GlError;
use glow::HasContext;
use tessella_core::displace::Displacement;
use tessella_core::refine::{Evaluator, Frame, Plan, PlanSizes, Spacing};
use tessella_core::scheme::png1_edge_sources;
use tessella_core::tessellator;
use tessella_core::{Mesh, NormalMode, RefineOptions, RefinedMesh, Scheme, Tags};

/// Floats per captured vertex: position, normal, tessellation coordinate, face (an `int`).
const TF_FLOATS: usize = 10;

/// How the TCS gets its levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum LevelSource {
    /// One uniform for all four levels of every patch (van Veen's setting).
    Uniform,
    /// Four levels per patch from a buffer: each edge's level from that edge alone, as the CPU
    /// plan resolved them (per-edge levels, LOD functions).
    PerFace,
}

/// What the GL tessellator wrote: an unwelded triangle soup (vertex `3t + i` is corner `i` of
/// triangle `t`), with each vertex's coarse face and tessellation coordinate.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GlRefined {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    /// `gl_TessCoord` = barycentric `(l1, l2, l3)` on the coarse face.
    pub coords: Vec<[f32; 3]>,
    /// Coarse face (`gl_PrimitiveID`) of each vertex.
    pub faces: Vec<u32>,
    /// Messages about levels changed to fit the driver (above `GL_MAX_TESS_GEN_LEVEL`).
    pub notes: Vec<String>,
    /// Seconds from the draw call to the read-back being complete (`glFinish`).
    pub draw_seconds: f64,
}

impl GlRefined {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.positions.len() / 3
    }
    /// As a [`RefinedMesh`]: unwelded, triangle `t` is `(3t, 3t+1, 3t+2)`.
    pub fn to_mesh(&self) -> RefinedMesh {
        RefinedMesh {
            positions: self.positions.clone(),
            normals: self.normals.clone(),
            uvs: None,
            triangles: (0..self.triangle_count() as u32)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect(),
        }
    }
}

/// The vertex array and the 1×1 framebuffer draws need, on one context; the tessellation
/// programs are the context's ([`GlContext`] links each once and shares it).
pub struct GlTessellator<'c> {
    ctx: &'c GlContext,
    vao: glow::VertexArray,
    /// A 1×1 framebuffer: a surfaceless context has no default one, and drawing needs one
    /// even with rasterisation discarded.
    fbo: glow::Framebuffer,
    rbo: glow::Renderbuffer,
}

/// The hardware spacing of `options`, or why the GL backend cannot run them.
pub fn hardware_spacing(options: &RefineOptions) -> Result<tessellator::Partitioning, GlError> {
    options.spacing.tessellator().ok_or_else(|| {
        GlError::Unsupported(format!(
            "the GL backend runs the hardware tessellator, whose patterns are not the {} \
             pattern: use spacing equal, fractional-odd or fractional-even",
            Spacing::Grid
        ))
    })
}

impl<'c> GlTessellator<'c> {
    /// Prepares a vertex array (patches carry no attributes: the TES reads the nets).
    pub fn new(ctx: &'c GlContext) -> Result<GlTessellator<'c>, GlError> {
        // SAFETY: GL calls on the context current on this thread.
        let gl = ctx.gl();
        let (vao, fbo, rbo) = unsafe {
            let vao = gl.create_vertex_array().map_err(GlError::Unsupported)?;
            let fbo = gl.create_framebuffer().map_err(GlError::Unsupported)?;
            let rbo = gl.create_renderbuffer().map_err(GlError::Unsupported)?;
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(rbo));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, 1, 1);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(rbo),
            );
            (vao, fbo, rbo)
        };
        ctx.check("making the vertex array and framebuffer")?;
        Ok(GlTessellator { ctx, vao, fbo, rbo })
    }

    /// The context.
    pub fn context(&self) -> &'c GlContext {
        self.ctx
    }

    /// The program for `spacing`, compiled and linked on first use (by the context, which
    /// keeps it for every tessellator and evaluator on it).
    pub fn program(
        &mut self,
        spacing: tessellator::Partitioning,
    ) -> Result<glow::Program, GlError> {
        self.ctx.program(spacing)
    }

    /// Refines `mesh` with `options` on the GL tessellator and reads the triangles back by
    /// transform feedback. The nets and levels come from the same [`Plan`] the CPU uses.
    pub fn refine(
        &mut self,
        mesh: &Mesh,
        options: &RefineOptions,
        source: Option<LevelSource>,
    ) -> Result<GlRefined, GlError> {
        let prepared = self.prepare(mesh, options, source)?;
        self.run(&prepared)
    }

    /// Everything that does not depend on the GL draw: the plan, its nets and the levels (the
    /// frame borrows `mesh`).
    pub fn prepare<'m>(
        &mut self,
        mesh: &'m Mesh,
        options: &RefineOptions,
        source: Option<LevelSource>,
    ) -> Result<Prepared<'m>, GlError> {
        hardware_spacing(options)?;
        let (plan, frame) = Plan::with_frame(mesh, &options.clone().with_weld(false))?;
        let setup = PlanSetup::new(self.ctx, mesh, &plan, source)?;
        Ok(Prepared {
            spacing: setup.spacing,
            nets: setup.nets,
            plan,
            frame,
            levels: setup.levels,
            source: setup.source,
            expected: setup.expected,
            notes: setup.notes,
        })
    }

    /// Uploads the nets and levels of `p`, draws the patches with transform feedback and reads
    /// the triangles back.
    pub fn run(&mut self, p: &Prepared) -> Result<GlRefined, GlError> {
        let program = self.program(p.spacing)?;
        let ctx = self.ctx;
        let draw = p.draw();
        let mut out = GlRefined::default();
        // SAFETY: GL calls on the current context; every buffer made here is deleted here.
        unsafe {
            let buffers = PatchBuffers::new(ctx, draw.nets, draw.levels)?;
            let result = (|| {
                buffers.upload_frame(ctx, draw.nets, draw.frame)?;
                buffers.bind(ctx, self.vao, draw.nets)?;
                let tf = transform_feedback_buffer(ctx, p.plan.face_count(), p.expected)?;
                let captured = capture(ctx, program, self.vao, self.fbo, tf, &draw, p.expected);
                ctx.gl().delete_buffer(tf);
                let (raw, seconds) = captured?;
                unpack_into(&raw, &p.notes, seconds, &mut out);
                Ok(())
            })();
            buffers.delete(ctx.gl());
            result.map(|()| out)
        }
    }
}

impl GlTessellator<'_> {
    /// Draws `p` (a `width × height` picture, coloured by normal: `0.5 n + 0.5`) seen through
    /// the column-major `view_proj`, with depth test; `wireframe` draws lines. RGBA rows from
    /// the bottom up, as GL reads them.
    pub fn render(
        &mut self,
        p: &Prepared,
        view_proj: &[f32; 16],
        width: i32,
        height: i32,
        wireframe: bool,
    ) -> Result<Vec<u8>, GlError> {
        let mode = if wireframe {
            DrawMode::Lines
        } else {
            DrawMode::Fill
        };
        self.draw(p, view_proj, width, height, mode)
    }

    /// [`GlTessellator::render`] with the choice of [`DrawMode`]: `FillAndLines` draws the
    /// surface coloured by normal, then the pattern's edges in near-black on top (the fill is
    /// pushed back by a polygon offset so the lines win the depth test).
    pub fn draw(
        &mut self,
        p: &Prepared,
        view_proj: &[f32; 16],
        width: i32,
        height: i32,
        mode: DrawMode,
    ) -> Result<Vec<u8>, GlError> {
        if width <= 0 || height <= 0 {
            return Err(GlError::Unsupported(format!(
                "picture size {width}x{height} must be at least 1x1"
            )));
        }
        let program = self.program(p.spacing)?;
        let ctx = self.ctx;
        let gl = ctx.gl();
        let d = p.draw();
        // SAFETY: GL calls on the current context; the read-back buffer has the picture's size.
        unsafe {
            let buffers = PatchBuffers::new(ctx, d.nets, d.levels)?;
            let fbo = gl.create_framebuffer().map_err(GlError::Unsupported)?;
            let colour = gl.create_renderbuffer().map_err(GlError::Unsupported)?;
            let depth = gl.create_renderbuffer().map_err(GlError::Unsupported)?;
            let result = (|| {
                gl.bind_renderbuffer(glow::RENDERBUFFER, Some(colour));
                gl.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, width, height);
                gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
                gl.renderbuffer_storage(glow::RENDERBUFFER, glow::DEPTH_COMPONENT24, width, height);
                gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
                gl.framebuffer_renderbuffer(
                    glow::FRAMEBUFFER,
                    glow::COLOR_ATTACHMENT0,
                    glow::RENDERBUFFER,
                    Some(colour),
                );
                gl.framebuffer_renderbuffer(
                    glow::FRAMEBUFFER,
                    glow::DEPTH_ATTACHMENT,
                    glow::RENDERBUFFER,
                    Some(depth),
                );
                ctx.check("making the picture's framebuffer")?;
                buffers.upload_frame(ctx, d.nets, d.frame)?;
                buffers.bind(ctx, self.vao, d.nets)?;
                gl.use_program(Some(program));
                set_uniforms(gl, program, &d);
                let loc = gl.get_uniform_location(program, "u_view_proj");
                gl.uniform_matrix_4_f32_slice(loc.as_ref(), false, view_proj);
                gl.bind_vertex_array(Some(self.vao));
                gl.viewport(0, 0, width, height);
                gl.clear_color(1.0, 1.0, 1.0, 1.0);
                gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
                gl.enable(glow::DEPTH_TEST);
                gl.depth_func(glow::LEQUAL);
                let wire = gl.get_uniform_location(program, "u_wire");
                if mode != DrawMode::Lines {
                    gl.uniform_1_i32(wire.as_ref(), 0);
                    gl.enable(glow::POLYGON_OFFSET_FILL);
                    gl.polygon_offset(1.0, 1.0);
                    draw_patches(gl, &d);
                    gl.disable(glow::POLYGON_OFFSET_FILL);
                }
                if mode != DrawMode::Fill {
                    // Lines alone keep the normal colours; over the fill they are near-black.
                    gl.uniform_1_i32(wire.as_ref(), i32::from(mode == DrawMode::FillAndLines));
                    gl.polygon_mode(glow::FRONT_AND_BACK, glow::LINE);
                    draw_patches(gl, &d);
                    gl.polygon_mode(glow::FRONT_AND_BACK, glow::FILL);
                    gl.uniform_1_i32(wire.as_ref(), 0);
                }
                gl.depth_func(glow::LESS);
                gl.disable(glow::DEPTH_TEST);
                ctx.check("drawing the picture")?;
                let mut pixels = vec![0u8; (width * height * 4) as usize];
                gl.read_pixels(
                    0,
                    0,
                    width,
                    height,
                    glow::RGBA,
                    glow::UNSIGNED_BYTE,
                    glow::PixelPackData::Slice(Some(&mut pixels)),
                );
                ctx.check("reading the picture")?;
                Ok(pixels)
            })();
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(self.fbo));
            gl.delete_framebuffer(fbo);
            gl.delete_renderbuffer(colour);
            gl.delete_renderbuffer(depth);
            buffers.delete(gl);
            result
        }
    }
}

/// A column-major `view_proj` made for a `0..=1` clip depth (wgpu, Vulkan, tessella-view's
/// camera) turned into one for GL's `-1..=1`: `z' = 2z - w`, so the same camera frames the same
/// picture.
pub fn gl_clip_from_zero_to_one(view_proj: [[f32; 4]; 4]) -> [f32; 16] {
    let mut out = [0.0; 16];
    for (c, col) in view_proj.iter().enumerate() {
        out[4 * c..4 * c + 4].copy_from_slice(&[col[0], col[1], 2.0 * col[2] - col[3], col[3]]);
    }
    out
}

/// What [`GlTessellator::draw`] draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum DrawMode {
    /// The surface, coloured by normal (`0.5 n + 0.5`).
    Fill,
    /// The pattern's edges only, coloured by normal.
    Lines,
    /// The surface with its edges drawn in near-black on top (`render --wireframe`).
    FillAndLines,
}

/// Where the tessellation control shader gets each patch's control net.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum NetSource {
    /// Built in the control shader from the coarse vertices (van Veen): flat, Phong, PN and
    /// PNG1 (whose 6-vertex patches add each edge's opposite neighbour corner). Per frame only
    /// the coarse positions and normals are uploaded.
    Shader(ShaderNets),
    /// Copied from buffers the CPU filled (`tessella_core::scheme`): the schemes whose nets need
    /// more than a triangle and its neighbours' corners (PN-AEN, scalar-tagged, quadratic).
    Buffers,
}

/// What the control shader needs to build the nets itself; see [`NetSource::Shader`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShaderNets {
    /// The shader's `u_nets`: 1 flat, 2 Phong, 3 PN, 4 PNG1.
    pub code: i32,
    /// Phong's shape factor.
    pub alpha: f32,
    /// Vertices per patch: the 3 corners, then (PNG1) each edge's opposite corner.
    pub patch_vertices: i32,
    /// Coarse vertex indices, `patch_vertices` per face (topology: built once).
    pub indices: Vec<u32>,
    /// PNG1, per face and edge: flags (1 = has a neighbour, 2 = sharp) and `κ` (topology and
    /// tags: built once).
    pub edges: Vec<f32>,
}

impl ShaderNets {
    /// The shader-built nets of `mesh` for `plan`'s scheme, or `None` when the scheme's nets
    /// come from the CPU.
    pub fn new(mesh: &Mesh, plan: &Plan) -> Option<ShaderNets> {
        let options = plan.options();
        let (code, alpha) = match options.scheme {
            Scheme::Flat => (1, 0.0),
            Scheme::Phong { alpha } => (2, alpha),
            Scheme::Pn => (3, 0.0),
            Scheme::Png1 => (4, 0.0),
            _ => return None,
        };
        let triangles = mesh.triangles();
        let (patch_vertices, indices, edges) = if code == 4 {
            let empty = Tags::new();
            let tags = options.tags.as_deref().unwrap_or(&empty);
            let mut indices = Vec::with_capacity(triangles.len() * 6);
            let mut edges = Vec::with_capacity(triangles.len() * 6);
            for (f, t) in triangles.iter().enumerate() {
                let sources = png1_edge_sources(mesh, plan.topology(), tags, f);
                indices.extend(t);
                for (k, (opposite, sharp)) in sources.iter().enumerate() {
                    indices.push(opposite.unwrap_or(t[k]));
                    let flags = u8::from(opposite.is_some()) + 2 * u8::from(sharp.is_some());
                    edges.extend([flags as f32, sharp.unwrap_or(0.0) as f32]);
                }
            }
            (6, indices, edges)
        } else {
            (3, triangles.iter().flatten().copied().collect(), Vec::new())
        };
        Some(ShaderNets {
            code,
            alpha,
            patch_vertices,
            indices,
            edges,
        })
    }
}

/// Plan, nets and levels of one GL refinement ([`GlTessellator::prepare`]); its frame borrows
/// the mesh.
pub struct Prepared<'m> {
    pub spacing: tessellator::Partitioning,
    pub plan: Plan,
    pub frame: Frame<'m>,
    /// Where the control shader gets the nets (the frame's CPU nets for [`NetSource::Buffers`]).
    pub nets: NetSource,
    /// Four levels per face, GL order: `outer[0..3]`, inner.
    pub levels: Vec<f32>,
    pub source: LevelSource,
    /// Triangles the CPU plan makes (`None` when levels were clamped for the driver).
    pub expected: Option<u64>,
    pub notes: Vec<String>,
}

impl Prepared<'_> {
    fn draw(&self) -> Draw<'_> {
        Draw {
            nets: &self.nets,
            levels: &self.levels,
            source: self.source,
            frame: &self.frame,
            faces: self.plan.face_count(),
        }
    }
}

/// What a plan fixes for the GL draw: spacing, net source, levels, the expected output.
struct PlanSetup {
    spacing: tessellator::Partitioning,
    nets: NetSource,
    levels: Vec<f32>,
    source: LevelSource,
    expected: Option<u64>,
    notes: Vec<String>,
}

impl PlanSetup {
    /// The setup of `plan` (made from `mesh`); `source: None` picks uniform levels when every
    /// face has the same ones.
    fn new(
        ctx: &GlContext,
        mesh: &Mesh,
        plan: &Plan,
        source: Option<LevelSource>,
    ) -> Result<PlanSetup, GlError> {
        let options = plan.options();
        let spacing = hardware_spacing(options)?;
        let tiling = plan
            .tiling()
            .ok_or_else(|| GlError::Unsupported("the plan has no per-face patterns".into()))?;
        let faces = plan.face_count();
        let max = ctx.info().max_tess_level as f32;
        let mut notes = Vec::new();
        let mut levels = Vec::with_capacity(faces * 4);
        let mut clamped = 0usize;
        for f in 0..faces {
            let t = tiling.tile(f);
            // GL's outer[k] is the edge opposite corner k: our edges 1, 2, 0.
            for x in [t.outer[1], t.outer[2], t.outer[0], t.inner] {
                if x > max {
                    clamped += 1;
                }
                levels.push(x.min(max));
            }
        }
        if clamped > 0 {
            notes.push(format!(
                "{clamped} tessellation levels above the driver's GL_MAX_TESS_GEN_LEVEL = {max} \
                 were clamped to it"
            ));
        }
        let uniform = levels.chunks(4).all(|c| c == [levels[0]; 4]);
        let source = match source {
            Some(LevelSource::Uniform) if !uniform => {
                return Err(GlError::Unsupported(
                    "uniform levels were asked for, but these options give each face its own \
                     levels"
                        .into(),
                ))
            }
            Some(s) => s,
            None if uniform => LevelSource::Uniform,
            None => LevelSource::PerFace,
        };
        // The CPU's triangle count, unless levels were clamped (then the hardware decides).
        let expected = if clamped == 0 {
            Some(plan.triangle_count() as u64)
        } else {
            None
        };
        let bytes = plan.triangle_count() as u64 * 3 * (TF_FLOATS as u64 * 4);
        if bytes > options.max_output_bytes {
            return Err(GlError::Unsupported(format!(
                "the GL output would need {bytes} bytes, more than the cap of {}",
                options.max_output_bytes
            )));
        }
        let nets = match ShaderNets::new(mesh, plan) {
            Some(n) => NetSource::Shader(n),
            None => NetSource::Buffers,
        };
        Ok(PlanSetup {
            spacing,
            nets,
            levels,
            source,
            expected,
            notes,
        })
    }
}

/// One draw of the patches: the plan's part and the frame.
struct Draw<'a> {
    nets: &'a NetSource,
    levels: &'a [f32],
    source: LevelSource,
    frame: &'a Frame<'a>,
    faces: usize,
}

/// The buffers the patches read. What the plan fixes is uploaded once by [`PatchBuffers::new`]:
/// the levels (storage buffer 2) and, for shader-built nets, the patch indices and PNG1's edge
/// data (storage buffer 3). What the frame changes is uploaded by
/// [`PatchBuffers::upload_frame`]: the coarse vertices (shader-built nets) or the CPU's nets
/// (storage buffers 0 and 1). Blocks a source does not use get a small empty buffer.
struct PatchBuffers {
    points: glow::Buffer,
    normals: glow::Buffer,
    levels: glow::Buffer,
    edges: glow::Buffer,
    vertices: glow::Buffer,
    indices: glow::Buffer,
}

/// `v` as bytes; 16 zero bytes for an empty `v` (GL refuses empty storage blocks).
fn float_bytes(v: impl IntoIterator<Item = f32>) -> Vec<u8> {
    let bytes: Vec<u8> = v.into_iter().flat_map(|x| x.to_ne_bytes()).collect();
    if bytes.is_empty() {
        vec![0; 16]
    } else {
        bytes
    }
}

impl PatchBuffers {
    /// Makes the buffers and uploads what the plan fixes.
    ///
    /// # Safety
    /// `ctx` is current on this thread.
    unsafe fn new(
        ctx: &GlContext,
        nets: &NetSource,
        levels: &[f32],
    ) -> Result<PatchBuffers, GlError> {
        let gl = ctx.gl();
        let mut made = Vec::with_capacity(6);
        for _ in 0..6 {
            match gl.create_buffer() {
                Ok(b) => made.push(b),
                Err(e) => {
                    for b in made {
                        gl.delete_buffer(b);
                    }
                    return Err(GlError::Unsupported(e));
                }
            }
        }
        let b = PatchBuffers {
            points: made[0],
            normals: made[1],
            levels: made[2],
            edges: made[3],
            vertices: made[4],
            indices: made[5],
        };
        let upload = |target: u32, buffer: glow::Buffer, bytes: &[u8]| {
            gl.bind_buffer(target, Some(buffer));
            gl.buffer_data_u8_slice(target, bytes, glow::STATIC_DRAW);
        };
        let ssbo = glow::SHADER_STORAGE_BUFFER;
        upload(ssbo, b.levels, &float_bytes(levels.iter().copied()));
        match nets {
            NetSource::Shader(s) => {
                upload(ssbo, b.edges, &float_bytes(s.edges.iter().copied()));
                upload(ssbo, b.points, &float_bytes([]));
                upload(ssbo, b.normals, &float_bytes([]));
                let indices: Vec<u8> = s.indices.iter().flat_map(|i| i.to_ne_bytes()).collect();
                upload(glow::ARRAY_BUFFER, b.indices, &indices);
            }
            NetSource::Buffers => upload(ssbo, b.edges, &float_bytes([])),
        }
        gl.bind_buffer(glow::ARRAY_BUFFER, None);
        if let Err(e) = ctx.check("uploading the patches' plan data") {
            b.delete(gl);
            return Err(e);
        }
        Ok(b)
    }

    /// Uploads the frame's part: the coarse positions and normals for shader-built nets, the
    /// frame's control nets otherwise. Returns the bytes uploaded.
    ///
    /// # Safety
    /// `ctx` is current on this thread and made these buffers.
    unsafe fn upload_frame(
        &self,
        ctx: &GlContext,
        nets: &NetSource,
        frame: &Frame,
    ) -> Result<u64, GlError> {
        let gl = ctx.gl();
        let mut bytes = 0u64;
        let mut upload = |target: u32, buffer: glow::Buffer, data: &[u8]| {
            gl.bind_buffer(target, Some(buffer));
            gl.buffer_data_u8_slice(target, data, glow::STREAM_DRAW);
            bytes += data.len() as u64;
        };
        match nets {
            NetSource::Shader(_) => {
                let mesh = frame.mesh();
                let vertices = mesh
                    .positions()
                    .iter()
                    .zip(mesh.normals())
                    .flat_map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]]);
                upload(glow::ARRAY_BUFFER, self.vertices, &float_bytes(vertices));
            }
            NetSource::Buffers => {
                let n = frame.nets();
                let ssbo = glow::SHADER_STORAGE_BUFFER;
                upload(
                    ssbo,
                    self.points,
                    &float_bytes(n.points.iter().flatten().copied()),
                );
                upload(
                    ssbo,
                    self.normals,
                    &float_bytes(n.normals.iter().flatten().copied()),
                );
            }
        }
        gl.bind_buffer(glow::ARRAY_BUFFER, None);
        ctx.check("uploading the frame's nets")?;
        Ok(bytes)
    }

    /// Binds the storage blocks, and the vertex attributes and indices on `vao`.
    ///
    /// # Safety
    /// `ctx` is current on this thread and made these buffers and `vao`.
    unsafe fn bind(
        &self,
        ctx: &GlContext,
        vao: glow::VertexArray,
        nets: &NetSource,
    ) -> Result<(), GlError> {
        let gl = ctx.gl();
        for (binding, b) in [self.points, self.normals, self.levels, self.edges]
            .into_iter()
            .enumerate()
        {
            gl.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, binding as u32, Some(b));
        }
        gl.bind_vertex_array(Some(vao));
        match nets {
            NetSource::Shader(_) => {
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.vertices));
                for (location, offset) in [(0u32, 0i32), (1, 12)] {
                    gl.enable_vertex_attrib_array(location);
                    gl.vertex_attrib_pointer_f32(location, 3, glow::FLOAT, false, 24, offset);
                }
                gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(self.indices));
            }
            NetSource::Buffers => {
                gl.disable_vertex_attrib_array(0);
                gl.disable_vertex_attrib_array(1);
                gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, None);
            }
        }
        ctx.check("binding the patches' inputs")
    }

    /// # Safety
    /// `gl` is the context that made these buffers, current on this thread.
    unsafe fn delete(&self, gl: &glow::Context) {
        for b in [
            self.points,
            self.normals,
            self.levels,
            self.edges,
            self.vertices,
            self.indices,
        ] {
            gl.delete_buffer(b);
        }
    }
}

/// A transform feedback buffer with room for the output of `faces` patches: `expected`
/// triangles, or (levels clamped for the driver) the most the hardware can make.
///
/// # Safety
/// `ctx` is current on this thread.
unsafe fn transform_feedback_buffer(
    ctx: &GlContext,
    faces: usize,
    expected: Option<u64>,
) -> Result<glow::Buffer, GlError> {
    let gl = ctx.gl();
    // Generous room: the hardware may write more than the CPU expects only when it is wrong,
    // which the primitive count of `capture` reports.
    let triangles = expected.unwrap_or_else(|| faces as u64 * 2 * 66 * 66);
    let bytes = triangles * 3 * TF_FLOATS as u64 * 4;
    let size = i32::try_from(bytes).map_err(|_| {
        GlError::Unsupported(format!(
            "the GL output needs {bytes} bytes, more than one GL buffer holds"
        ))
    })?;
    let tf = gl.create_buffer().map_err(GlError::Unsupported)?;
    gl.bind_buffer(glow::TRANSFORM_FEEDBACK_BUFFER, Some(tf));
    gl.buffer_data_size(glow::TRANSFORM_FEEDBACK_BUFFER, size, glow::STREAM_READ);
    gl.bind_buffer(glow::TRANSFORM_FEEDBACK_BUFFER, None);
    if let Err(e) = ctx.check("allocating the transform feedback buffer") {
        gl.delete_buffer(tf);
        return Err(e);
    }
    Ok(tf)
}

/// Draws the patches of `d` (inputs bound) with transform feedback into `tf` and reads the
/// captured vertices back: the raw bytes and the seconds from the draw call to the read-back.
/// Refuses a primitive count other than `expected` (when known).
///
/// # Safety
/// `ctx` is current on this thread and made `program`, `vao`, `fbo` and `tf`.
unsafe fn capture(
    ctx: &GlContext,
    program: glow::Program,
    vao: glow::VertexArray,
    fbo: glow::Framebuffer,
    tf: glow::Buffer,
    d: &Draw<'_>,
    expected: Option<u64>,
) -> Result<(Vec<u8>, f64), GlError> {
    let gl = ctx.gl();
    gl.use_program(Some(program));
    set_uniforms(gl, program, d);
    gl.bind_vertex_array(Some(vao));
    gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
    gl.enable(glow::RASTERIZER_DISCARD);
    let query = match gl.create_query() {
        Ok(q) => q,
        Err(e) => {
            gl.disable(glow::RASTERIZER_DISCARD);
            return Err(GlError::Unsupported(e));
        }
    };
    let start = std::time::Instant::now();
    gl.bind_buffer_base(glow::TRANSFORM_FEEDBACK_BUFFER, 0, Some(tf));
    gl.begin_query(glow::TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, query);
    gl.begin_transform_feedback(glow::TRIANGLES);
    draw_patches(gl, d);
    gl.end_transform_feedback();
    gl.end_query(glow::TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
    gl.disable(glow::RASTERIZER_DISCARD);
    let written = gl.get_query_parameter_u32(query, glow::QUERY_RESULT) as u64;
    gl.delete_query(query);
    let result = (|| {
        ctx.check("drawing the patches with transform feedback")?;
        if let Some(e) = expected {
            if written != e {
                return Err(GlError::Count {
                    got: written,
                    expected: e,
                });
            }
        }
        let mut raw = vec![0u8; (written * 3 * TF_FLOATS as u64 * 4) as usize];
        gl.bind_buffer(glow::TRANSFORM_FEEDBACK_BUFFER, Some(tf));
        gl.get_buffer_sub_data(glow::TRANSFORM_FEEDBACK_BUFFER, 0, &mut raw);
        let seconds = start.elapsed().as_secs_f64();
        ctx.check("reading the transform feedback buffer")?;
        Ok((raw, seconds))
    })();
    gl.bind_buffer_base(glow::TRANSFORM_FEEDBACK_BUFFER, 0, None);
    result
}

/// Draws every face's patch.
///
/// # Safety
/// The program, vertex array and [`PatchBuffers::bind`]'s buffers are bound.
unsafe fn draw_patches(gl: &glow::Context, d: &Draw<'_>) {
    let faces = d.faces as i32;
    match d.nets {
        NetSource::Shader(s) => {
            gl.patch_parameter_i32(glow::PATCH_VERTICES, s.patch_vertices);
            gl.draw_elements(
                glow::PATCHES,
                faces * s.patch_vertices,
                glow::UNSIGNED_INT,
                0,
            );
        }
        NetSource::Buffers => {
            gl.patch_parameter_i32(glow::PATCH_VERTICES, 1);
            gl.draw_arrays(glow::PATCHES, 0, faces);
        }
    }
}

/// # Safety
/// `program` is in use on the current context.
unsafe fn set_uniforms(gl: &glow::Context, program: glow::Program, d: &Draw<'_>) {
    let loc = |name: &str| gl.get_uniform_location(program, name);
    let nets = d.frame.nets();
    gl.uniform_1_i32(loc("u_k").as_ref(), nets.basis.len() as i32);
    gl.uniform_1_i32(
        loc("u_real").as_ref(),
        i32::from(nets.normal_mode == NormalMode::Real),
    );
    let (code, alpha) = match d.nets {
        NetSource::Shader(s) => (s.code, s.alpha),
        NetSource::Buffers => (0, 0.0),
    };
    gl.uniform_1_i32(loc("u_nets").as_ref(), code);
    gl.uniform_1_f32(loc("u_alpha").as_ref(), alpha);
    let normals = tessella_core::shader::normal_mode_code(nets.normal_mode);
    gl.uniform_1_i32(loc("u_normals").as_ref(), normals as i32);
    gl.uniform_1_i32(
        loc("u_per_face").as_ref(),
        i32::from(d.source == LevelSource::PerFace),
    );
    gl.uniform_1_f32(loc("u_level").as_ref(), d.levels[0]);
    let identity: [f32; 16] = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    gl.uniform_matrix_4_f32_slice(loc("u_view_proj").as_ref(), false, &identity);
}

/// Unpacks captured vertices into `out` (its vectors cleared and refilled: their memory is
/// reused).
fn unpack_into(raw: &[u8], notes: &[String], draw_seconds: f64, out: &mut GlRefined) {
    let n = raw.len() / (TF_FLOATS * 4);
    for v in [&mut out.positions, &mut out.normals, &mut out.coords] {
        v.clear();
        v.reserve(n);
    }
    out.faces.clear();
    out.faces.reserve(n);
    out.notes.clear();
    out.notes.extend_from_slice(notes);
    out.draw_seconds = draw_seconds;
    for v in raw.chunks_exact(TF_FLOATS * 4) {
        let word = |i: usize| [v[4 * i], v[4 * i + 1], v[4 * i + 2], v[4 * i + 3]];
        let f = |i: usize| f32::from_ne_bytes(word(i));
        out.positions.push([f(0), f(1), f(2)]);
        out.normals.push([f(3), f(4), f(5)]);
        out.coords.push([f(6), f(7), f(8)]);
        out.faces.push(i32::from_ne_bytes(word(9)) as u32);
    }
}

/// The GL implementation of [`Evaluator`]: made once per [`Plan`] (it links the program, if
/// the context has not yet, and uploads the levels, the patch indices and PNG1's edge data),
/// it draws each [`Frame`] with transform feedback, uploading only the frame's coarse data
/// (the coarse positions and normals for nets the control shader builds, the frame's control
/// nets otherwise).
///
/// Its output is the hardware tessellator's, not the plan's layout: an unwelded triangle soup
/// in the order the hardware emits it, each vertex with its coarse face (`gl_PrimitiveID`) and
/// tessellation coordinate (barycentric on that face), written into the caller's
/// [`GlRefined`] (its vectors are cleared and refilled, so their memory is reused frame to
/// frame). The plan's spacing must be a hardware one (equal, fractional-odd or
/// fractional-even): the grid pattern is not the hardware's. The GL backend does not displace
/// ([`GlEvaluator::with_displacement`] says why).
///
/// ```no_run
/// use tessella_core::refine::{Evaluator, Levels, Plan, Spacing};
/// use tessella_core::{samples, RefineOptions, Scheme};
/// use tessella_gl::{GlContext, GlEvaluator, GlRefined};
/// let ctx = GlContext::new()?;
/// let mesh = samples::icosphere(1);
/// let options = RefineOptions::new(Scheme::Pn, 1)
///     .with_spacing(Spacing::Equal)
///     .with_levels(Levels::Uniform(6.0));
/// let plan = Plan::new(&mesh, &options)?;
/// let mut frame = plan.frame(&mesh)?;
/// let mut gl = GlEvaluator::new(&ctx, &plan, &frame)?;
/// let mut out = GlRefined::default();
/// for t in 0..3 {
///     let s = 1.0 + 0.1 * t as f32;
///     let moved: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.map(|c| s * c)).collect();
///     plan.update(&mut frame, &moved, None)?;
///     gl.evaluate(&plan, &frame, &mut out)?; // uploads the coarse vertices only, then one draw
///     assert_eq!(out.triangle_count(), plan.triangle_count());
/// }
/// # Ok::<(), tessella_gl::GlError>(())
/// ```
pub struct GlEvaluator<'c> {
    tessellator: GlTessellator<'c>,
    plan_key: PlanKey,
    setup: PlanSetup,
    buffers: PatchBuffers,
    tf: glow::Buffer,
    /// Bytes the last [`Evaluator::evaluate`] uploaded.
    uploaded: u64,
}

/// Tells plans apart: their sizes (vertex, triangle and face counts, level, weld), scheme
/// (with its parameters: Phong's shape factor is a uniform made per plan), spacing, normal
/// mode. The frame check (`Plan::check_frame`) adds the plan's identity for frames.
type PlanKey = (PlanSizes, Scheme, Spacing, NormalMode);

fn plan_key(plan: &Plan) -> PlanKey {
    let options = plan.options();
    (
        plan.sizes(),
        options.scheme,
        options.spacing,
        plan.normal_mode(),
    )
}

impl std::fmt::Debug for GlEvaluator<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GlEvaluator")
            .field("faces", &self.plan_key.0.faces)
            .field("triangles", &self.plan_key.0.triangles)
            .finish()
    }
}

impl<'c> GlEvaluator<'c> {
    /// The evaluator of `plan` on `ctx`. `frame` (one of the plan's) gives the coarse mesh the
    /// per-plan data is built from: the patch indices and PNG1's edge data depend on the
    /// topology, the normals' splits and the tags only, which every frame of a plan shares.
    pub fn new(ctx: &'c GlContext, plan: &Plan, frame: &Frame) -> Result<GlEvaluator<'c>, GlError> {
        plan.check_frame(frame)?;
        let setup = PlanSetup::new(ctx, frame.mesh(), plan, None)?;
        let tessellator = GlTessellator::new(ctx)?;
        ctx.program(setup.spacing)?;
        // SAFETY: GL calls on the current context; on failure what was made is deleted.
        let (buffers, tf) = unsafe {
            let buffers = PatchBuffers::new(ctx, &setup.nets, &setup.levels)?;
            match transform_feedback_buffer(ctx, plan.face_count(), setup.expected) {
                Ok(tf) => (buffers, tf),
                Err(e) => {
                    buffers.delete(ctx.gl());
                    return Err(e);
                }
            }
        };
        Ok(GlEvaluator {
            tessellator,
            plan_key: plan_key(plan),
            setup,
            buffers,
            tf,
            uploaded: 0,
        })
    }

    /// [`GlEvaluator::new`] for a displaced surface: refused unless `displacement` is
    /// [`Displacement::None`]. The GL backend does not displace: its tessellation evaluation
    /// shader evaluates the patch and its normals and has no displacement stage (sine, Perlin
    /// noise, height maps and the shared directions along split edges that keep a displaced
    /// surface closed). Displace on the CPU (`Displacement::apply` on the refined output) or
    /// with the GPU compute evaluator (`GpuRefineOptions::displacement`), which displace alike.
    pub fn with_displacement(
        ctx: &'c GlContext,
        plan: &Plan,
        frame: &Frame,
        displacement: &Displacement,
    ) -> Result<GlEvaluator<'c>, GlError> {
        if displacement.is_some() {
            return Err(GlError::Unsupported(
                "the GL backend does not displace (its tessellation evaluation shader has no \
                 displacement stage); displace on the CPU or with the GPU compute evaluator"
                    .into(),
            ));
        }
        GlEvaluator::new(ctx, plan, frame)
    }

    /// Bytes the last [`Evaluator::evaluate`] uploaded (the frame's coarse data only).
    pub fn uploaded_bytes(&self) -> u64 {
        self.uploaded
    }

    /// Messages about levels changed to fit the driver (also in every [`GlRefined::notes`]).
    pub fn notes(&self) -> &[String] {
        &self.setup.notes
    }
}

impl Evaluator for GlEvaluator<'_> {
    type Output<'a> = &'a mut GlRefined;
    type Error = GlError;

    /// Draws `frame` and reads its triangles back into `out` (see [`GlEvaluator`] for the
    /// order). Refuses a plan other than the one the evaluator was made for, and a frame of
    /// another plan.
    fn evaluate(&mut self, plan: &Plan, frame: &Frame, out: &mut GlRefined) -> Result<(), GlError> {
        if plan_key(plan) != self.plan_key {
            return Err(GlError::Unsupported(
                "this GL evaluator was made for another plan".into(),
            ));
        }
        plan.check_frame(frame)?;
        let ctx = self.tessellator.ctx;
        let program = ctx.program(self.setup.spacing)?;
        let draw = Draw {
            nets: &self.setup.nets,
            levels: &self.setup.levels,
            source: self.setup.source,
            frame,
            faces: plan.face_count(),
        };
        // SAFETY: GL calls on the current context, with buffers this evaluator made on it.
        unsafe {
            self.uploaded = self.buffers.upload_frame(ctx, draw.nets, frame)?;
            self.buffers.bind(ctx, self.tessellator.vao, draw.nets)?;
            let (raw, seconds) = capture(
                ctx,
                program,
                self.tessellator.vao,
                self.tessellator.fbo,
                self.tf,
                &draw,
                self.setup.expected,
            )?;
            unpack_into(&raw, &self.setup.notes, seconds, out);
        }
        Ok(())
    }
}

impl Drop for GlEvaluator<'_> {
    fn drop(&mut self) {
        let gl = self.tessellator.ctx.gl();
        // SAFETY: buffers made on this context.
        unsafe {
            self.buffers.delete(gl);
            gl.delete_buffer(self.tf);
        }
    }
}

impl Drop for GlTessellator<'_> {
    fn drop(&mut self) {
        let gl = self.ctx.gl();
        // SAFETY: objects made on this context.
        unsafe {
            gl.delete_vertex_array(self.vao);
            gl.delete_framebuffer(self.fbo);
            gl.delete_renderbuffer(self.rbo);
        }
    }
}
