//! tessella-gpu embedded in an engine (the walk-through of `docs/engine.md`): the engine owns
//! the device (opened with WebGPU's default limits), its error handler, its encoder, its
//! interleaved vertex buffer and its pipelines; tessella records its work into the engine's
//! encoder and provides WGSL the engine's own shader calls.
//!
//! - The engine's vertex format is position, one float of padding, normal: 8 floats, 32 bytes
//!   ([`ENGINE_FORMAT`]); [`tessella_gpu::GpuEvaluator::record`] fills it in the engine's
//!   encoder, leaving the padding alone.
//! - The engine draws the surface twice, into two pictures: from that vertex buffer with its
//!   own shader, and with no vertex buffer at all, its vertex shader calling the exported
//!   `tessella_point(instance, vertex)` ([`tessella_gpu::PatchBindings`]).
//! - The engine's uncaptured-error handler stays the engine's.
//!
//! `cargo run -p tessella-gpu --example engine -- OUT_DIR` writes `buffer.png` and
//! `module.png`; `tests/engine.rs` runs the same code and checks it against the CPU.

use std::error::Error;
use std::sync::{Arc, Mutex};
use tessella_core::refine::{Frame, Plan, VertexFormat};
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::{
    GpuContext, GpuEvaluator, GpuOutput, GpuRefineOptions, IndexWidth, PatchBindings,
};

mod common;

/// The engine's vertex: position (floats 0..3), padding (3), normal (4..7), padding (7).
pub const ENGINE_FORMAT: VertexFormat = VertexFormat {
    stride: 8,
    position: 0,
    normal: Some(4),
    uv: None,
};

/// What the engine fills its vertex buffer with first: tessella must leave the padding so.
pub const PADDING: f32 = -7.5;

pub const SIZE: u32 = 96;
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The engine's shading, shared by both draws; `vs_buffer` reads the engine's vertex buffer,
/// `vs_module` calls tessella's exported function (the module is put before this source,
/// its group at index 1; the engine's own uniforms are group 0).
const SHADER: &str = r#"
struct View { transform: mat4x4<f32>, light: vec4<f32> }
@group(0) @binding(0) var<uniform> view: View;
struct Out { @builtin(position) clip: vec4<f32>, @location(0) normal: vec3<f32> }

fn engine_vertex(p: vec3<f32>, n: vec3<f32>) -> Out {
    var out: Out;
    out.clip = view.transform * vec4<f32>(p, 1.0);
    out.normal = (view.transform * vec4<f32>(n, 0.0)).xyz;
    return out;
}

@vertex fn vs_buffer(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> Out {
    return engine_vertex(p, n);
}

// instance = coarse triangle, vertex_index = pattern vertex (the index buffer holds the
// pattern's triangles).
@vertex fn vs_module(@builtin(instance_index) face: u32, @builtin(vertex_index) v: u32) -> Out {
    let point = tessella_point(face, v);
    return engine_vertex(point.position, point.normal);
}

@fragment fn fs(in: Out) -> @location(0) vec4<f32> {
    let d = max(dot(normalize(in.normal), normalize(view.light.xyz)), 0.0);
    return vec4<f32>(vec3<f32>(0.45, 0.6, 0.85) * (0.15 + 0.85 * d), 1.0);
}
"#;

/// The messages the engine's uncaptured-error handler received.
pub type EngineErrors = Arc<Mutex<Vec<String>>>;

/// The engine's device: WebGPU's default limits, and its own uncaptured-error handler, which
/// collects messages into the returned list.
pub fn open_engine_device() -> Result<(wgpu::Device, wgpu::Queue, EngineErrors), Box<dyn Error>> {
    let adapter = common::request_adapter()?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("engine"),
        required_limits: wgpu::Limits::default(),
        ..Default::default()
    }))?;
    let errors = Arc::new(Mutex::new(Vec::new()));
    let sink = errors.clone();
    device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
        sink.lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(e.to_string());
    }));
    Ok((device, queue, errors))
}

/// The mesh and plan the walk-through draws: a PN icosphere at level 6.
pub fn scene() -> Result<(Mesh, Plan), Box<dyn Error>> {
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 6))?;
    Ok((mesh, plan))
}

/// What one engine frame leaves behind.
pub struct EngineFrame {
    /// The engine's vertex buffer as tessella filled it: [`ENGINE_FORMAT`].
    pub vertices: Vec<f32>,
    /// RGBA pictures of the draw from the vertex buffer and of the draw through the module.
    pub buffer_picture: Vec<u8>,
    pub module_picture: Vec<u8>,
    /// Per coarse triangle and pattern vertex, `tessella_point`'s position and normal, from
    /// the engine's compute shader calling the module (6 floats each).
    pub module_points: Vec<f32>,
}

/// One frame as an engine runs it: tessella's dispatches, the engine's two draws, a compute
/// pass of the engine calling the module, and the copies back, all in one encoder the engine
/// submits.
pub fn run_frame(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    plan: &Plan,
    frame: &Frame,
) -> Result<EngineFrame, Box<dyn Error>> {
    let ctx = GpuContext::from_device(device.clone(), queue.clone());
    let mut evaluator = GpuEvaluator::with_options(
        &ctx,
        plan,
        &GpuRefineOptions {
            vertex_format: Some(ENGINE_FORMAT),
            ..Default::default()
        },
    )?;
    let patch = PatchBindings::new(
        &ctx,
        plan,
        frame,
        1,
        wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::COMPUTE,
    )?;
    let init = |label, contents: &[u8], usage| {
        wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            },
        )
    };
    use wgpu::BufferUsages as U;
    let vertex_bytes = (plan.vertex_count() * ENGINE_FORMAT.stride * 4) as u64;
    let filled = vec![PADDING; plan.vertex_count() * ENGINE_FORMAT.stride];
    let vertices = init(
        "engine vertices",
        bytemuck::cast_slice(&filled),
        U::VERTEX | U::STORAGE | U::COPY_SRC,
    );
    let width = IndexWidth::for_plan(plan);
    let indices = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("engine indices"),
        size: width.buffer_bytes(plan),
        usage: U::INDEX | U::COPY_DST,
        mapped_at_creation: false,
    });
    evaluator.write_indices(plan, &indices, 0, width)?;
    let pattern = plan.pattern();
    let pattern_indices: Vec<u32> = pattern.triangles.iter().flatten().copied().collect();
    let pattern_buffer = init("pattern", bytemuck::cast_slice(&pattern_indices), U::INDEX);

    let mut view = [0.0f32; 20];
    let s = 0.6;
    let m = [
        [s, 0.0, 0.0, 0.0],
        [0.0, s, 0.0, 0.0],
        [0.0, 0.0, -0.25, 0.0],
        [0.0, 0.0, 0.5, 1.0],
    ];
    for (i, v) in m.iter().flatten().enumerate() {
        view[i] = *v;
    }
    view[16..19].copy_from_slice(&[0.4, 0.6, -0.7]);
    let uniforms = init("engine view", bytemuck::cast_slice(&view), U::UNIFORM);

    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("engine shader"),
        source: wgpu::ShaderSource::Wgsl(format!("{}\n{SHADER}", patch.wgsl()).into()),
    });
    let (view_layout, view_group) = common::view_group(device, Some("engine view"), &uniforms);
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("engine"),
        bind_group_layouts: &[Some(&view_layout), Some(patch.layout())],
        immediate_size: 0,
    });
    let attributes = common::position_normal(
        ENGINE_FORMAT.position,
        ENGINE_FORMAT.normal.ok_or("the format has normals")?,
    );
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: (ENGINE_FORMAT.stride * 4) as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &attributes,
    })];
    let pipeline = |entry, buffers: &[Option<wgpu::VertexBufferLayout>]| {
        common::render_pipeline(
            device,
            entry,
            &layout,
            &module,
            entry,
            buffers,
            (COLOR, DEPTH),
        )
    };
    let from_buffer = pipeline("vs_buffer", &buffers);
    let from_module = pipeline("vs_module", &[]);

    // The engine's compute pass calling the module for every (face, pattern vertex).
    let points_per_face = pattern.points.len();
    let faces = plan.face_count();
    let probe_count = faces * points_per_face;
    let probe_source = format!(
        "{}\n@group(0) @binding(0) var<storage, read_write> probed: array<f32>;\n\
         @compute @workgroup_size(64) fn probe(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
           let i = id.x;\n\
           if (i >= {probe_count}u) {{ return; }}\n\
           let point = tessella_point(i / {points_per_face}u, i % {points_per_face}u);\n\
           probed[i * 6u] = point.position.x; probed[i * 6u + 1u] = point.position.y;\n\
           probed[i * 6u + 2u] = point.position.z; probed[i * 6u + 3u] = point.normal.x;\n\
           probed[i * 6u + 4u] = point.normal.y; probed[i * 6u + 5u] = point.normal.z;\n\
         }}\n",
        patch.wgsl()
    );
    let probe_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("engine probe"),
        source: wgpu::ShaderSource::Wgsl(probe_source.into()),
    });
    let probe_bytes = (probe_count * 6 * 4) as u64;
    let probed = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probed"),
        size: probe_bytes,
        usage: U::STORAGE | U::COPY_SRC,
        mapped_at_creation: false,
    });
    let probe_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("probe"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let probe_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &probe_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: probed.as_entire_binding(),
        }],
    });
    let probe_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("probe"),
        bind_group_layouts: &[Some(&probe_layout), Some(patch.layout())],
        immediate_size: 0,
    });
    let probe = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("probe"),
        layout: Some(&probe_pipeline_layout),
        module: &probe_module,
        entry_point: Some("probe"),
        compilation_options: Default::default(),
        cache: None,
    });

    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let row = common::padded_row(SIZE);
    let staging = |label, size| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: U::MAP_READ | U::COPY_DST,
            mapped_at_creation: false,
        })
    };
    let vertices_back = staging("vertices back", vertex_bytes);
    let probed_back = staging("probed back", probe_bytes);
    let pictures_back = [
        staging("picture", row * SIZE as u64),
        staging("picture", row * SIZE as u64),
    ];

    // One encoder, the engine's: tessella's dispatches first, then the engine's passes.
    let mut encoder = device.create_command_encoder(&Default::default());
    evaluator.record(
        &mut encoder,
        plan,
        frame,
        GpuOutput::Buffer {
            buffer: &vertices,
            offset: 0,
        },
    )?;
    for (k, back) in pictures_back.iter().enumerate() {
        let color = common::texture(device, SIZE, COLOR, attach | wgpu::TextureUsages::COPY_SRC);
        let depth = common::texture(device, SIZE, DEPTH, attach);
        let (color_view, depth_view) = (
            color.create_view(&Default::default()),
            depth.create_view(&Default::default()),
        );
        {
            let mut pass =
                common::begin_pass(&mut encoder, "engine pass", &color_view, &depth_view);
            pass.set_bind_group(0, &view_group, &[]);
            pass.set_bind_group(1, patch.bind_group(), &[]);
            if k == 0 {
                pass.set_pipeline(&from_buffer);
                pass.set_vertex_buffer(0, vertices.slice(..));
                pass.set_index_buffer(indices.slice(..), width.format());
                pass.draw_indexed(0..plan.triangle_count() as u32 * 3, 0, 0..1);
            } else {
                pass.set_pipeline(&from_module);
                pass.set_index_buffer(pattern_buffer.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..pattern_indices.len() as u32, 0, 0..faces as u32);
            }
        }
        common::copy_picture(&mut encoder, &color, back, SIZE);
    }
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&probe);
        pass.set_bind_group(0, &probe_group, &[]);
        pass.set_bind_group(1, patch.bind_group(), &[]);
        pass.dispatch_workgroups((probe_count as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&vertices, 0, &vertices_back, 0, vertex_bytes);
    encoder.copy_buffer_to_buffer(&probed, 0, &probed_back, 0, probe_bytes);
    queue.submit([encoder.finish()]);

    let read = |b: &wgpu::Buffer| ctx.map_and_copy(b);
    let vertices = bytemuck::pod_collect_to_vec(&read(&vertices_back)?);
    let module_points = bytemuck::pod_collect_to_vec(&read(&probed_back)?);
    let mut pictures = Vec::new();
    for back in &pictures_back {
        pictures.push(common::unpad_rows(&read(back)?, SIZE));
    }
    let module_picture = pictures.pop().ok_or("two pictures")?;
    let buffer_picture = pictures.pop().ok_or("two pictures")?;
    Ok(EngineFrame {
        vertices,
        buffer_picture,
        module_picture,
        module_points,
    })
}

#[allow(dead_code)] // the test includes this file for `run_frame`
fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args().nth(1).ok_or("usage: engine OUT_DIR")?;
    let out = std::path::PathBuf::from(out);
    std::fs::create_dir_all(&out)?;
    let (device, queue, errors) = open_engine_device()?;
    let (mesh, plan) = scene()?;
    let frame = plan.frame(&mesh)?;
    let result = run_frame(&device, &queue, &plan, &frame)?;
    for (name, pixels) in [
        ("buffer.png", result.buffer_picture),
        ("module.png", result.module_picture),
    ] {
        let picture =
            image::RgbaImage::from_raw(SIZE, SIZE, pixels).ok_or("picture size mismatch")?;
        let path = out.join(name);
        picture.save(&path)?;
        println!("{}", path.display());
    }
    let errors = errors.lock().unwrap_or_else(|p| p.into_inner());
    if !errors.is_empty() {
        return Err(format!("the engine's handler got errors: {errors:?}").into());
    }
    Ok(())
}
