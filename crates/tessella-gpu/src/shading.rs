//! The caller's half of a render pipeline. tessella-gpu's renderers place the surface's points
//! (bind group 0, the vertex entry points); what the points look like is the caller's: its
//! WGSL, its bind group 1 and its attachments. tessella-view's pictures are one such caller, an
//! engine's material another.

/// How a caller shades what [`crate::PatternRenderer`] and [`crate::AdaptiveRenderer`] draw.
///
/// `wgsl` is appended to the renderer's vertex stage, whose entry point builds a
/// `TessellaVertex` per vertex (`position`, unit `normal`, `l` the barycentric point in the
/// coarse triangle, `corner` the vertex's one-hot corner of its pattern triangle, `face` the coarse
/// triangle or `TESSELLA_NO_FACE`; see [`VERTEX_WGSL`]) and returns `shade_vertex(v)`. So
/// `wgsl` defines:
/// - `fn shade_vertex(v: TessellaVertex) -> VsOut`, with a `struct VsOut` of its own that has a
///   `@builtin(position)`;
/// - `@fragment fn fs_main(...)`, writing the one colour attachment of `formats`;
/// - its bindings, all in `@group(1)`, laid out as `layout`.
///
/// Names beginning `tessella_`, `Tessella` or `TESSELLA_` are the renderer's. The pipelines
/// are cached per device by `wgsl` and `formats` (a layout equal in its entries is
/// interchangeable, as WebGPU's rules for bind groups say).
///
/// ```
/// // A shading that paints the normal, with no bindings of its own.
/// const NORMALS: &str = "
/// struct VsOut { @builtin(position) clip: vec4<f32>, @location(0) n: vec3<f32> }
/// fn shade_vertex(v: TessellaVertex) -> VsOut {
///     return VsOut(vec4<f32>(v.position.xy, 0.5, 1.0), v.normal);
/// }
/// @fragment fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
///     return vec4<f32>(0.5 + 0.5 * normalize(in.n), 1.0);
/// }";
/// # let _ = NORMALS;
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Shading<'a> {
    pub wgsl: &'a str,
    /// The layout of bind group 1, which the caller sets on each draw.
    pub layout: &'a wgpu::BindGroupLayout,
    /// The attachments of the caller's render pass.
    pub formats: TargetFormats,
}

/// What the renderers' vertex stage declares for the shading: `struct TessellaVertex`,
/// `TESSELLA_NO_FACE` and `tessella_corner`.
pub const VERTEX_WGSL: &str = include_str!("shaders/vertex.wgsl");

/// The attachments the caller's render pass has: what the renderers compile their pipelines
/// for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TargetFormats {
    pub color: wgpu::TextureFormat,
    /// `None`: no depth attachment (then nothing is depth-tested).
    pub depth: Option<wgpu::TextureFormat>,
    /// Samples per pixel of the attachments (1, or 4 for multisampling).
    pub samples: u32,
}

impl Shading<'_> {
    /// The part of a pipeline cache key that names this shading: its formats and a hash of its
    /// WGSL.
    pub(crate) fn cache_key(&self) -> String {
        use std::hash::{Hash, Hasher};
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        self.wgsl.hash(&mut hasher);
        format!("{:?}|{:016x}", self.formats, hasher.finish())
    }

    /// The vertex stage's WGSL followed by the shading's: what `own` (the renderer's entry
    /// points, prefixed by the caller with its evaluation modules) is completed with.
    pub(crate) fn append_to(&self, own: &str) -> String {
        [VERTEX_WGSL, own, self.wgsl].join("\n")
    }

    /// A triangle-list pipeline of `module`'s vertex `entry` and the shading's `fs_main`.
    pub(crate) fn pipeline(
        &self,
        ctx: &crate::GpuContext,
        module: &wgpu::ShaderModule,
        layout: &wgpu::PipelineLayout,
        entry: &str,
        buffer: wgpu::VertexBufferLayout,
    ) -> wgpu::RenderPipeline {
        let targets = &self.formats;
        ctx.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    buffers: &[Some(buffer)],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: targets.depth.map(|format| wgpu::DepthStencilState {
                    format,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: targets.samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(targets.color.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
    }
}

/// The depth attachment the pipelines' depth test (`Less`) expects of a pass that draws a
/// picture from scratch: `view` cleared to 1 (the far plane) and discarded after the pass.
pub fn cleared_depth(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
            store: wgpu::StoreOp::Discard,
        }),
        stencil_ops: None,
    }
}
