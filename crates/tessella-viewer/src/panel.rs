//! One panel: one scheme's surface and the tessella-gpu renderer that draws it. A whole level on
//! the grid with fixed levels is drawn by the [`PatternRenderer`] (one pattern, uploaded once);
//! anything else (fractional levels, a tessellator spacing, a LOD) by the
//! [`AdaptiveRenderer`], whose levels are per edge and may change every frame, crack-free.

use crate::error::ViewerError;
use crate::params::Params;
use tessella_core::refine::{Camera, Frame, Lod, Plan, Spacing, Surface};
use tessella_core::{Mesh, RefineOptions, Scheme, Tags};
use tessella_gpu::{AdaptiveRenderer, GpuContext, PatternRenderer, TargetFormats};
use tessella_view::{Appearance, RenderUniforms};

/// The most refined triangles a panel may draw: software rasterisers (SwiftShader, lavapipe)
/// take seconds per frame well before this, and a frame that never ends looks like a hang.
pub const MAX_REFINED_TRIANGLES: u64 = 1 << 27;

/// How a panel's levels are set.
#[derive(Debug, Clone, PartialEq)]
enum Levels {
    /// One level on every edge, set once (rounded up when not geomorphing a grid).
    Fixed(f32),
    /// A LOD spec evaluated every frame with the view's camera.
    Lod(String),
}

// A panel holds one drawer and there are a few panels: the size difference costs nothing.
#[allow(clippy::large_enum_variant)]
enum Drawer {
    Pattern {
        plan: Plan,
        frame: Frame<'static>,
        renderer: PatternRenderer,
    },
    Adaptive {
        surface: Surface,
        frame: Frame<'static>,
        renderer: AdaptiveRenderer,
        levels: Levels,
        /// Grid spacing without geomorphing: levels rounded up.
        round_up: bool,
        /// The largest edge level of the last levels set.
        max_level: f32,
    },
}

/// One scheme drawn in one viewport.
pub struct Panel {
    pub scheme: Scheme,
    /// The options a CPU refinement of this panel uses (export), levels included.
    pub options: RefineOptions,
    drawer: Drawer,
    /// The panel's shading (its own camera uniforms).
    look: Appearance,
    /// Bytes a static, welded and indexed refined mesh of this panel would need.
    static_bytes: u64,
}

impl std::fmt::Debug for Panel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Panel")
            .field("scheme", &self.scheme.name())
            .field("pattern", &matches!(self.drawer, Drawer::Pattern { .. }))
            .finish()
    }
}

/// The refine options of `scheme` under `params` (levels, spacing, normals, tags), parsed
/// from the core's text form as every front end's are ([`Params::refine_pairs`]).
pub fn refine_options(
    params: &Params,
    scheme: Scheme,
    tags: Option<&Tags>,
) -> Result<RefineOptions, ViewerError> {
    let options = RefineOptions::from_pairs(params.refine_pairs(scheme))?;
    Ok(match tags {
        Some(tags) => options.with_tags(tags.clone()),
        None => options,
    })
}

/// Refuses a uniform grid level the device cannot draw: its pattern buffers (indices and the
/// wireframe's unrolled triangles, 12 bytes per pattern triangle; the stencil, `K` weights and
/// two derivative weights per point plus 6 normal weights) over the device's buffer limits, or
/// more than [`MAX_REFINED_TRIANGLES`] refined triangles.
pub fn check_level(
    ctx: &GpuContext,
    level: u32,
    faces: usize,
    scheme: Scheme,
) -> Result<(), ViewerError> {
    let n = level as u64;
    let triangles = n * n;
    let points = (n + 1) * (n + 2) / 2;
    let k = scheme.basis().len() as u64;
    let stencil = points * (3 * k + 6) * 4;
    let pattern = triangles * 12;
    let limit = ctx.max_binding();
    let refined = triangles.saturating_mul(faces as u64);
    let too_big = |what: String| ViewerError::Param {
        name: "level",
        message: format!("level {level} is more than this device can draw: {what}"),
    };
    if pattern > ctx.limits.max_buffer_size || stencil > limit {
        return Err(too_big(format!(
            "the pattern needs {} bytes in one buffer, the device allows {}",
            pattern.max(stencil),
            limit.min(ctx.limits.max_buffer_size)
        )));
    }
    if refined > MAX_REFINED_TRIANGLES {
        return Err(too_big(format!(
            "{refined} refined triangles, over the viewer's cap of {MAX_REFINED_TRIANGLES}"
        )));
    }
    Ok(())
}

impl Panel {
    /// Builds the surface of `scheme` on `mesh` and its renderer for `formats`.
    pub fn new(
        ctx: &GpuContext,
        mesh: &Mesh,
        params: &Params,
        scheme: Scheme,
        tags: Option<&Tags>,
        formats: &TargetFormats,
    ) -> Result<Panel, ViewerError> {
        let options = refine_options(params, scheme, tags)?;
        if let (None, Some(level)) = (&params.lod, options.uniform_grid_level()) {
            check_level(ctx, level, mesh.face_count(), scheme)?;
            let plan = Plan::new(mesh, &options)?;
            // The panel's frame outlives `mesh`'s borrow: it owns a copy, which it moves.
            let frame = plan.frame(mesh.clone())?;
            let look = Appearance::new(ctx, *formats);
            let renderer =
                PatternRenderer::new(ctx, &plan, &frame, &look.shading(), &params.displacement)?;
            let static_bytes = plan.layout().output_bytes(false);
            return Ok(Panel {
                scheme,
                options,
                drawer: Drawer::Pattern {
                    plan,
                    frame,
                    renderer,
                },
                look,
                static_bytes,
            });
        }
        let surface = Surface::new(mesh, &options.surface_options())?;
        let frame = surface.frame(mesh.clone())?;
        let look = Appearance::new(ctx, *formats);
        let mut renderer =
            AdaptiveRenderer::new(ctx, &surface, &frame, &look.shading(), params.spacing)?;
        let levels = match &params.lod {
            Some(spec) => Levels::Lod(spec.clone()),
            None => Levels::Fixed(params.level as f32),
        };
        let round_up = params.spacing == Spacing::Grid && !params.geomorph;
        let mut max_level = 0.0;
        if let Levels::Fixed(level) = levels {
            let level = if round_up { level.ceil() } else { level };
            let edges = vec![level; surface.topology().edges.len()];
            renderer.set_levels(&edges, None)?;
            max_level = level;
        }
        Ok(Panel {
            scheme,
            options,
            drawer: Drawer::Adaptive {
                surface,
                frame,
                renderer,
                levels,
                round_up,
                max_level,
            },
            look,
            static_bytes: 0,
        })
    }

    /// Moves the panel's coarse mesh to `positions` and `normals` and uploads the new control
    /// nets; returns the bytes written.
    pub fn deform(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<u64, ViewerError> {
        Ok(match &mut self.drawer {
            Drawer::Pattern {
                plan,
                frame,
                renderer,
            } => {
                plan.update(frame, positions, normals)?;
                renderer.update(frame)?
            }
            Drawer::Adaptive {
                surface,
                frame,
                renderer,
                ..
            } => {
                surface.update(frame, positions, normals)?;
                renderer.update(frame)?
            }
        })
    }

    /// With a LOD: the levels `camera` on a `size` view gives the current mesh, uploaded;
    /// returns the bytes written (0 without a LOD).
    pub fn follow_camera(&mut self, camera: Camera, size: [u32; 2]) -> Result<u64, ViewerError> {
        let Drawer::Adaptive {
            frame,
            renderer,
            levels: Levels::Lod(spec),
            round_up,
            max_level,
            ..
        } = &mut self.drawer
        else {
            return Ok(0);
        };
        let lod = Lod::parse(spec, Some(camera), Some(size)).map_err(|e| ViewerError::Param {
            name: "lod",
            message: e.to_string(),
        })?;
        let (mut edges, mut faces) = renderer.levels(frame, &lod)?;
        if *round_up {
            edges.iter_mut().for_each(|l| *l = l.ceil());
            if let Some(f) = faces.as_mut() {
                f.iter_mut().for_each(|l| *l = l.ceil());
            }
        }
        *max_level = edges.iter().copied().fold(1.0, f32::max);
        Ok(renderer.set_levels(&edges, faces.as_deref())?)
    }

    /// Whether the levels follow the camera.
    pub fn has_lod(&self) -> bool {
        matches!(
            self.drawer,
            Drawer::Adaptive {
                levels: Levels::Lod(_),
                ..
            }
        )
    }

    pub fn set_uniforms(&self, uniforms: &RenderUniforms) {
        self.look.set_uniforms(uniforms);
    }

    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        match &self.drawer {
            Drawer::Pattern { renderer, .. } => self.look.draw(pass, renderer),
            Drawer::Adaptive { renderer, .. } => self.look.draw(pass, renderer),
        }
    }

    /// How far displacement moves a point (for framing the camera).
    pub fn reach(&self) -> f32 {
        match &self.drawer {
            Drawer::Pattern { renderer, .. } => renderer.displacement_reach(),
            Drawer::Adaptive { .. } => 0.0,
        }
    }

    /// Triangles drawn per frame.
    pub fn triangles(&self) -> u64 {
        match &self.drawer {
            Drawer::Pattern { plan, .. } => plan.triangle_count() as u64,
            Drawer::Adaptive { renderer, .. } => renderer.triangle_count(),
        }
    }

    /// The uniform level, or the largest edge level last set.
    pub fn level(&self) -> f32 {
        match &self.drawer {
            Drawer::Pattern { plan, .. } => plan.layout().level as f32,
            Drawer::Adaptive { max_level, .. } => *max_level,
        }
    }

    /// GPU bytes the renderer keeps (pattern or parts, stencil, nets, per-face buffers).
    pub fn gpu_bytes(&self) -> u64 {
        match &self.drawer {
            Drawer::Pattern { renderer, .. } => renderer.byte_size(),
            Drawer::Adaptive { renderer, .. } => renderer.byte_size(),
        }
    }

    /// Bytes of a static refined mesh (24-byte vertices, 4-byte indices) of what this panel
    /// draws: the welded layout's for a uniform level; with adaptive levels the drawn
    /// triangles' indices and `T / 2 + 2` vertices (a closed mesh's welded count, by Euler's
    /// formula).
    pub fn static_bytes(&self) -> u64 {
        match &self.drawer {
            Drawer::Pattern { .. } => self.static_bytes,
            Drawer::Adaptive { renderer, .. } => {
                let t = renderer.triangle_count();
                t * 12 + (t / 2 + 2) * 24
            }
        }
    }

    /// The coarse mesh as drawn now (deformed, moved).
    pub fn mesh(&self) -> &Mesh {
        match &self.drawer {
            Drawer::Pattern { frame, .. } | Drawer::Adaptive { frame, .. } => frame.mesh(),
        }
    }
}
