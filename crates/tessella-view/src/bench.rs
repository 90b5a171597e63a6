//! Benchmarks for `tessella bench`: CPU vs GPU refinement throughput, and the GMR Figure 7
//! experiment (a static fully refined vertex buffer vs the instanced pattern). Rows carry the
//! adapter's label; software adapters are marked as such, their numbers say nothing about GPUs.

use crate::compute::gpu_refine;
use crate::context::GpuContext;
use crate::displace::Displacement;
use crate::error::GpuError;
use crate::render::{render_group, scene_uniforms, PatternScene, RenderOptions, Target};
use std::time::Instant;
use tessella_core::{samples, Mesh, RefineOptions, Refiner, Scheme};

/// One row of [`refine_throughput`].
#[derive(Debug, Clone, PartialEq)]
pub struct RefineRow {
    pub adapter: String,
    pub faces: usize,
    pub level: u32,
    pub vertices: u64,
    pub triangles: u64,
    /// Median wall time of the CPU refinement (all threads).
    pub cpu_ms: f64,
    /// Median wall time of the GPU refinement including upload and readback.
    pub gpu_ms: f64,
}

/// Times CPU and GPU refinement of `mesh` with `scheme` at each level (median of `repeats`).
pub fn refine_throughput(
    ctx: &GpuContext,
    mesh: &Mesh,
    scheme: Scheme,
    levels: &[u32],
    repeats: u32,
) -> Result<Vec<RefineRow>, GpuError> {
    let mut rows = Vec::new();
    for &level in levels {
        let refiner = Refiner::new(mesh, &RefineOptions::new(scheme, level))?;
        let mut cpu = Vec::new();
        let mut gpu = Vec::new();
        for _ in 0..repeats.max(1) {
            let t = Instant::now();
            std::hint::black_box(refiner.refine());
            cpu.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            std::hint::black_box(gpu_refine(ctx, &refiner)?);
            gpu.push(t.elapsed().as_secs_f64() * 1e3);
        }
        rows.push(RefineRow {
            adapter: ctx.adapter_label(),
            faces: mesh.face_count(),
            level,
            vertices: refiner.layout().vertex_count,
            triangles: refiner.layout().triangle_count,
            cpu_ms: median(&mut cpu),
            gpu_ms: median(&mut gpu),
        });
    }
    Ok(rows)
}

/// Markdown table of [`refine_throughput`] rows.
pub fn refine_table(rows: &[RefineRow]) -> String {
    let mut s = String::from(
        "| adapter | faces | level | vertices | triangles | CPU ms | GPU ms | CPU Mvert/s | GPU Mvert/s |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let rate = |ms: f64| r.vertices as f64 / ms / 1e3;
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1} | {:.1} |\n",
            r.adapter,
            r.faces,
            r.level,
            r.vertices,
            r.triangles,
            r.cpu_ms,
            r.gpu_ms,
            rate(r.cpu_ms),
            rate(r.gpu_ms)
        );
    }
    s
}

/// Settings of the Figure 7 experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure7Config {
    /// Coarse triangle counts (GMR: 10, 100, 1000).
    pub faces: Vec<usize>,
    /// Pattern levels (GMR: 64 and 128).
    pub levels: Vec<u32>,
    /// Frames timed per configuration (median).
    pub frames: u32,
    /// Render target size.
    pub size: (u32, u32),
    pub scheme: Scheme,
}

impl Default for Figure7Config {
    fn default() -> Self {
        Figure7Config {
            faces: vec![10, 100, 1000],
            levels: vec![64, 128],
            frames: 10,
            size: (512, 512),
            scheme: Scheme::Pn,
        }
    }
}

/// One row of [`figure7`].
#[derive(Debug, Clone, PartialEq)]
pub struct Figure7Row {
    pub adapter: String,
    pub faces: usize,
    pub level: u32,
    /// (a) static vertex buffer of the fully refined, welded mesh.
    pub static_ms: f64,
    pub static_vertices: u64,
    pub static_bytes: u64,
    /// (b) the instanced pattern plus per-triangle nets.
    pub pattern_ms: f64,
    pub pattern_vertices: u64,
    pub pattern_bytes: u64,
}

/// The first `faces` triangles of a subdivided icosphere, vertices compacted: a closed-ish
/// surface with exactly the wanted number of coarse triangles.
pub fn mesh_with_faces(faces: usize) -> Result<Mesh, GpuError> {
    let mut sub = 0;
    while 20 * 4usize.pow(sub) < faces {
        sub += 1;
    }
    let source = samples::icosphere(sub);
    let mut map = vec![u32::MAX; source.vertex_count()];
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for t in source.triangles().iter().take(faces.max(1)) {
        triangles.push(t.map(|v| {
            if map[v as usize] == u32::MAX {
                map[v as usize] = positions.len() as u32;
                positions.push(source.positions()[v as usize]);
                normals.push(source.normals()[v as usize]);
            }
            map[v as usize]
        }));
    }
    Mesh::new(positions, Some(normals), None, triangles).map_err(|e| GpuError::Refine(e.into()))
}

/// GMR Figure 7 redone: frame time and GPU footprint of (a) a static refined vertex buffer and
/// (b) the instanced pattern, for each coarse triangle count and level.
pub fn figure7(ctx: &GpuContext, config: &Figure7Config) -> Result<Vec<Figure7Row>, GpuError> {
    let mut rows = Vec::new();
    let options = RenderOptions {
        size: config.size,
        ..Default::default()
    };
    let target = Target::new(ctx, config.size);
    for &faces in &config.faces {
        let mesh = mesh_with_faces(faces)?;
        for &level in &config.levels {
            let refine = RefineOptions::new(config.scheme, level);
            let uniforms = scene_uniforms(&mesh, &options, level, &0.0);
            // (b) pattern.
            let scene = PatternScene::new(ctx, &mesh, &refine, &Displacement::None)?;
            let pattern_ms = time_frames(config.frames, || {
                scene.draw(ctx, &target, &uniforms, options.background);
                ctx.check()
            })?;
            // (a) static buffer of the refined mesh.
            let refined = Refiner::new(&mesh, &refine)?.refine();
            let fixed = StaticScene::new(ctx, &refined);
            let static_ms = time_frames(config.frames, || {
                fixed.draw(ctx, &target, &uniforms, options.background);
                ctx.check()
            })?;
            rows.push(Figure7Row {
                adapter: ctx.adapter_label(),
                faces: mesh.face_count(),
                level,
                static_ms,
                static_vertices: refined.positions.len() as u64,
                static_bytes: fixed.byte_size(),
                pattern_ms,
                pattern_vertices: scene.pattern_vertex_count(),
                pattern_bytes: scene.byte_size(),
            });
        }
    }
    Ok(rows)
}

/// Markdown table of [`figure7`] rows.
pub fn figure7_table(rows: &[Figure7Row]) -> String {
    let mut s = String::from(
        "| adapter | coarse triangles | level | static VBO ms | static VBO vertices | static VBO bytes | pattern ms | pattern vertices | pattern bytes |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {} | {} | {:.2} | {} | {} |\n",
            r.adapter,
            r.faces,
            r.level,
            r.static_ms,
            r.static_vertices,
            r.static_bytes,
            r.pattern_ms,
            r.pattern_vertices,
            r.pattern_bytes
        );
    }
    s
}

/// One row of [`scheme_frame_times`].
#[derive(Debug, Clone, PartialEq)]
pub struct SchemeRow {
    pub adapter: String,
    pub scheme: String,
    pub faces: usize,
    pub level: u32,
    /// Basis size: control points per coarse triangle.
    pub k: usize,
    pub frame_ms: f64,
}

/// Frame time of the instanced pattern per scheme (e.g. PN vs PNG1: 10 vs 21 control points).
pub fn scheme_frame_times(
    ctx: &GpuContext,
    mesh: &Mesh,
    schemes: &[Scheme],
    level: u32,
    frames: u32,
    size: (u32, u32),
) -> Result<Vec<SchemeRow>, GpuError> {
    let options = RenderOptions {
        size,
        ..Default::default()
    };
    let target = Target::new(ctx, size);
    let uniforms = scene_uniforms(mesh, &options, level, &0.0);
    let mut rows = Vec::new();
    for &scheme in schemes {
        let scene = PatternScene::new(
            ctx,
            mesh,
            &RefineOptions::new(scheme, level),
            &Displacement::None,
        )?;
        let frame_ms = time_frames(frames, || {
            scene.draw(ctx, &target, &uniforms, options.background);
            ctx.check()
        })?;
        rows.push(SchemeRow {
            adapter: ctx.adapter_label(),
            scheme: scheme.name().to_string(),
            faces: mesh.face_count(),
            level,
            k: scheme.basis().len(),
            frame_ms,
        });
    }
    Ok(rows)
}

/// Markdown table of [`scheme_frame_times`] rows.
pub fn scheme_table(rows: &[SchemeRow]) -> String {
    let mut s = String::from("| adapter | scheme | K | coarse triangles | level | frame ms |\n|---|---|---:|---:|---:|---:|\n");
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.2} |\n",
            r.adapter, r.scheme, r.k, r.faces, r.level, r.frame_ms
        );
    }
    s
}

/// Median milliseconds of `frames` calls, after one warm-up call.
fn time_frames(
    frames: u32,
    mut frame: impl FnMut() -> Result<(), GpuError>,
) -> Result<f64, GpuError> {
    frame()?;
    let mut times = Vec::new();
    for _ in 0..frames.max(1) {
        let t = Instant::now();
        frame()?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    Ok(median(&mut times))
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The baseline of Figure 7: the refined mesh stored whole in GPU memory.
struct StaticScene {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    uniforms: wgpu::Buffer,
    group: wgpu::BindGroup,
}

impl StaticScene {
    fn new(ctx: &GpuContext, refined: &tessella_core::RefinedMesh) -> StaticScene {
        let interleaved: Vec<[f32; 6]> = refined
            .positions
            .iter()
            .zip(&refined.normals)
            .map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]])
            .collect();
        let init = |label, contents: &[u8], usage| ctx.buffer_init(label, contents, usage);
        let vertices = init(
            "static vertices",
            bytemuck::cast_slice(&interleaved),
            wgpu::BufferUsages::VERTEX,
        );
        let indices = init(
            "static indices",
            bytemuck::cast_slice(&refined.triangles),
            wgpu::BufferUsages::INDEX,
        );
        let uniforms = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("static uniforms"),
            size: std::mem::size_of::<crate::gpu_types::RenderUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let dummy = ctx.storage_buffer("no uvs", &[0; 4], wgpu::BufferUsages::empty());
        let group = render_group(
            ctx,
            &ctx.render_pipelines().render_layout,
            &uniforms,
            &dummy,
        );
        StaticScene {
            vertices,
            indices,
            index_count: refined.triangles.len() as u32 * 3,
            uniforms,
            group,
        }
    }

    fn byte_size(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }

    fn draw(
        &self,
        ctx: &GpuContext,
        target: &Target,
        uniforms: &crate::gpu_types::RenderUniforms,
        background: [u8; 4],
    ) {
        ctx.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = target.begin(&mut encoder, background);
            pass.set_pipeline(&ctx.render_pipelines().fixed);
            pass.set_bind_group(1, &self.group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        let _ = ctx.submit_and_wait(encoder);
    }
}
