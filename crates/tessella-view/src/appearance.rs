//! How the pictures and the viewer shade a surface: the [`Shading`] half of tessella-gpu's
//! renderers (`shaders/shade.wgsl`). tessella-gpu places the points; this module colours them.

use bytemuck::{Pod, Zeroable};
use std::mem::{offset_of, size_of};
use std::sync::atomic::{AtomicBool, Ordering};
use tessella_gpu::{
    AdaptiveRenderer, GpuContext, GpuError, PatternRenderer, Shading, TargetFormats, READ, UNIFORM,
};

/// The camera, light and colours of an [`Appearance`]: `RenderUniforms` in
/// `shaders/shade.wgsl`. Colours are linear RGB(A).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct RenderUniforms {
    pub view_proj: [[f32; 4]; 4],
    /// xyz: camera position.
    pub eye: [f32; 4],
    /// xyz: unit direction towards the light.
    pub light_dir: [f32; 4],
    pub base_color: [f32; 4],
    /// rgb: colour of the coarse edges in the wireframe, a: their largest half-width in pixels
    /// (thinner on small triangles; the pattern's own edges are thin shades of the surface).
    pub wire_color: [f32; 4],
    /// x: wireframe on, y: unused, z: facet normals from screen derivatives (for displaced
    /// surfaces), w: `1 << 24 | r | g << 8 | b << 16` paints back faces in that sRGB colour
    /// (the inside of a closed surface seen through a crack), 0 shades them like front faces.
    pub flags: [u32; 4],
}
const _: () = assert!(size_of::<RenderUniforms>() == 144);
const _: () = assert!(offset_of!(RenderUniforms, eye) == 64);
const _: () = assert!(offset_of!(RenderUniforms, wire_color) == 112);
const _: () = assert!(offset_of!(RenderUniforms, flags) == 128);

/// Entries of the colormap uniform: a header and up to 256 samples.
const COLORMAP_ENTRIES: usize = 257;

/// A scalar field for [`Appearance::set_field`]: six net values per coarse face
/// (`tessella_core::fields::face_nets`: the corners', then the mid-edge values of edges 0-1,
/// 1-2, 2-0), the colormap's sRGB samples (0..=1) and the range `[low, high]` they span.
#[derive(Debug, Clone, Copy)]
pub struct FieldNets<'a> {
    pub nets: &'a [f32],
    pub colormap: &'a [[f32; 3]],
    pub range: [f32; 2],
}

/// The WGSL of the shading: its constants, the generated P2 weights, `shaders/shade.wgsl`.
fn shade_wgsl() -> &'static str {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        [
            format!("const COLORMAP_ENTRIES: u32 = {COLORMAP_ENTRIES}u;\n"),
            tessella_core::shader::p2_weights_wgsl(),
            include_str!("shaders/shade.wgsl").to_string(),
        ]
        .join("\n")
    })
}

/// A renderer of tessella-gpu that an [`Appearance`] shades: drawn indexed, or with its
/// triangles unrolled for the wireframe.
pub trait Shaded {
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup);
    fn draw_unrolled(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup);
}

impl Shaded for PatternRenderer {
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        PatternRenderer::draw(self, pass, shading)
    }
    fn draw_unrolled(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        PatternRenderer::draw_unrolled(self, pass, shading)
    }
}

impl Shaded for AdaptiveRenderer {
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        AdaptiveRenderer::draw(self, pass, shading)
    }
    fn draw_unrolled(&self, pass: &mut wgpu::RenderPass<'_>, shading: &wgpu::BindGroup) {
        AdaptiveRenderer::draw_unrolled(self, pass, shading)
    }
}

/// Blinn-Phong shading under one light, a scalar field through a colormap (interpolated per
/// vertex from its P2 net, so only coarse data crosses the bus), a wireframe of the pattern
/// (coarse edges bold, the pattern's own thin, fading out where they would be denser than a
/// few pixels) and back faces in a colour of their own: its uniforms, field and bind group.
///
/// ```no_run
/// # fn demo(ctx: &tessella_gpu::GpuContext, pass: &mut wgpu::RenderPass<'_>,
/// #         uniforms: &tessella_view::RenderUniforms) -> Result<(), tessella_gpu::GpuError> {
/// use tessella_core::refine::Plan;
/// use tessella_core::{samples, RefineOptions, Scheme};
/// use tessella_gpu::{Displacement, PatternRenderer};
/// use tessella_view::{Appearance, Target};
/// let mesh = samples::icosphere(1);
/// let (plan, frame) = Plan::with_frame(&mesh, &RefineOptions::new(Scheme::Pn, 16))?;
/// let look = Appearance::new(ctx, Target::FORMATS);
/// let renderer = PatternRenderer::new(ctx, &plan, &frame, &look.shading(), &Displacement::None)?;
/// look.set_uniforms(uniforms);
/// look.draw(pass, &renderer);
/// # Ok(()) }
/// ```
pub struct Appearance {
    ctx: GpuContext,
    formats: TargetFormats,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// Per coarse face the six values of a scalar field's P2 net; one 0 without a field.
    face_field: wgpu::Buffer,
    /// `[low, high, samples, 0]` then the colormap's sRGB samples; `samples` 0: no field.
    colormap: wgpu::Buffer,
    group: wgpu::BindGroup,
    /// Set by [`Appearance::set_uniforms`]: draw the unrolled triangles.
    wireframe: AtomicBool,
}

impl std::fmt::Debug for Appearance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Appearance")
            .field("formats", &self.formats)
            .finish()
    }
}

impl Appearance {
    /// The shading's buffers for a pass with `formats`: no field, uniforms zero until
    /// [`Appearance::set_uniforms`].
    pub fn new(ctx: &GpuContext, formats: TargetFormats) -> Appearance {
        let both = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let vertex = wgpu::ShaderStages::VERTEX;
        let layout = ctx.buffer_layout(
            "appearance",
            &[(both, UNIFORM), (vertex, READ), (both, UNIFORM)],
        );
        let uniforms = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render uniforms"),
            size: size_of::<RenderUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let face_field = field_buffer(ctx, &[0.0]);
        let colormap = colormap_buffer(ctx, &[0.0; 4]);
        let group = ctx.buffer_group("appearance", &layout, &[&uniforms, &face_field, &colormap]);
        Appearance {
            ctx: ctx.clone(),
            formats,
            layout,
            uniforms,
            face_field,
            colormap,
            group,
            wireframe: AtomicBool::new(false),
        }
    }

    /// What tessella-gpu's renderers compile their pipelines with.
    pub fn shading(&self) -> Shading<'_> {
        Shading {
            wgsl: shade_wgsl(),
            layout: &self.layout,
            formats: self.formats,
        }
    }

    /// Bind group 1 of the renderers' draws.
    pub fn group(&self) -> &wgpu::BindGroup {
        &self.group
    }

    /// Sets the camera, light and colours for the next draws; with `flags.x` (wireframe) set,
    /// [`Appearance::draw`] draws the triangles unrolled, so the fragment shader knows its
    /// distance to every pattern edge whatever the pattern.
    pub fn set_uniforms(&self, uniforms: &RenderUniforms) {
        self.wireframe
            .store(uniforms.flags[0] != 0, Ordering::Relaxed);
        self.ctx
            .queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
    }

    /// Records `renderer`'s draw with this shading: indexed, or unrolled for the wireframe.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, renderer: &impl Shaded) {
        if self.wireframe.load(Ordering::Relaxed) {
            renderer.draw_unrolled(pass, &self.group);
        } else {
            renderer.draw(pass, &self.group);
        }
    }

    /// Colours the surface of `faces` coarse triangles by a scalar field instead of the base
    /// colour: its values are interpolated in the vertex shader at each point's barycentric
    /// `l` with the P2 shape functions; the colormap's 2 to 256 samples are spread evenly over
    /// the range, linearly interpolated, values outside clamped to the ends. Field colours are
    /// lit diffusely, without the white highlight. `None` goes back to the base colour. Points
    /// of an already refined vertex buffer (`PatternRenderer::draw_refined`) keep the base
    /// colour.
    pub fn set_field(
        &mut self,
        faces: usize,
        field: Option<FieldNets<'_>>,
    ) -> Result<(), GpuError> {
        let (nets, header): (&[f32], Vec<f32>) = match field {
            None => (&[0.0], vec![0.0; 8]),
            Some(FieldNets {
                nets,
                colormap,
                range: [low, high],
            }) => {
                if nets.len() != faces * 6 {
                    return Err(GpuError::BadOption(format!(
                        "a field net of {} values; {faces} faces need 6 each",
                        nets.len()
                    )));
                }
                if !(2..=256).contains(&colormap.len()) {
                    return Err(GpuError::BadOption(format!(
                        "a colormap of {} samples; give 2 to 256",
                        colormap.len()
                    )));
                }
                if !(low.is_finite() && high.is_finite() && low <= high) {
                    return Err(GpuError::BadOption(format!(
                        "field range {low}..{high} must be finite and increasing"
                    )));
                }
                let mut header = vec![low, high, colormap.len() as f32, 0.0];
                header.extend(colormap.iter().flat_map(|c| [c[0], c[1], c[2], 1.0]));
                (nets, header)
            }
        };
        let ctx = self.ctx.clone();
        ctx.scoped(|| {
            self.face_field = field_buffer(&ctx, nets);
            self.colormap = colormap_buffer(&ctx, &header);
            self.group = ctx.buffer_group(
                "appearance",
                &self.layout,
                &[&self.uniforms, &self.face_field, &self.colormap],
            );
        })
    }

    /// Bytes kept on the GPU: uniforms, field nets and colormap.
    pub fn byte_size(&self) -> u64 {
        self.uniforms.size() + self.face_field.size() + self.colormap.size()
    }
}

fn field_buffer(ctx: &GpuContext, nets: &[f32]) -> wgpu::Buffer {
    ctx.storage_buffer(
        "face field",
        bytemuck::cast_slice(nets),
        wgpu::BufferUsages::empty(),
    )
}

/// The colormap uniform holding `header` (floats, at most `COLORMAP_ENTRIES` vec4s),
/// zero-padded.
fn colormap_buffer(ctx: &GpuContext, header: &[f32]) -> wgpu::Buffer {
    let mut bytes = vec![0u8; COLORMAP_ENTRIES * 16];
    let data: &[u8] = bytemuck::cast_slice(header);
    bytes[..data.len()].copy_from_slice(data);
    ctx.buffer_init("colormap", &bytes, wgpu::BufferUsages::UNIFORM)
}
