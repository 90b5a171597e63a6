//! An engine's use of tessella-gpu: the application owns the wgpu device, its vertex and index
//! buffers and its render pipeline; tessella only writes refined vertices into its buffer.
//!
//! A coarse icosphere wobbles over the frames. The plan (topology, stencil, indices) is built
//! once; per frame the coarse mesh moves (`Plan::update`, O(coarse)), the GPU evaluator writes
//! the refined vertices straight into the application's vertex buffer, and the application
//! draws it with its own shader into an offscreen texture, written as a PNG.
//!
//! `cargo run -p tessella-gpu --example deform -- OUT_DIR [--frames N] [--size PIXELS]`

use std::error::Error;
use std::path::PathBuf;
use tessella_core::refine::Plan;
use tessella_core::{samples, RefineOptions, Scheme};
use tessella_gpu::{GpuContext, GpuEvaluator, GpuOutput, IndexWidth};

mod common;

const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The application's own shader: a fixed orthographic view, Lambert shading.
const SHADER: &str = r#"
struct View { transform: mat4x4<f32>, light: vec4<f32> }
@group(0) @binding(0) var<uniform> view: View;
struct Out { @builtin(position) clip: vec4<f32>, @location(0) normal: vec3<f32> }
@vertex fn vs(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> Out {
    var out: Out;
    out.clip = view.transform * vec4<f32>(p, 1.0);
    out.normal = (view.transform * vec4<f32>(n, 0.0)).xyz;
    return out;
}
@fragment fn fs(in: Out) -> @location(0) vec4<f32> {
    let d = max(dot(normalize(in.normal), normalize(view.light.xyz)), 0.0);
    return vec4<f32>(vec3<f32>(0.45, 0.6, 0.85) * (0.15 + 0.85 * d), 1.0);
}
"#;

struct Args {
    out: PathBuf,
    frames: u32,
    size: u32,
}

fn parse_args() -> Result<Args, Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let mut out = None;
    let (mut frames, mut size) = (8, 256);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--frames" => frames = args.next().ok_or("--frames needs a number")?.parse()?,
            "--size" => size = args.next().ok_or("--size needs a number")?.parse()?,
            _ if out.is_none() => out = Some(PathBuf::from(a)),
            _ => return Err(format!("unexpected argument '{a}'").into()),
        }
    }
    let out = out.ok_or("usage: deform OUT_DIR [--frames N] [--size PIXELS]")?;
    if frames == 0 || size == 0 || size > 4096 {
        return Err("--frames must be 1 or more, --size within 1..=4096".into());
    }
    Ok(Args { out, frames, size })
}

/// The application opens its own device; any adapter will do (software included).
fn open_device() -> Result<(wgpu::Device, wgpu::Queue), Box<dyn Error>> {
    let adapter = common::request_adapter()?;
    // tessella works within WebGPU's default limits.
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default()))?;
    Ok((device, queue))
}

/// Column-major: turn about Y by `yaw`, about X by `pitch`, scale by `s`, depth into [0, 1].
fn transform(yaw: f32, pitch: f32, s: f32) -> [[f32; 4]; 4] {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    // rows of R = Rx(pitch) · Ry(yaw)
    let r = [
        [cy, 0.0, sy],
        [sp * sy, cp, -sp * cy],
        [-cp * sy, sp, cp * cy],
    ];
    let mut m = [[0.0f32; 4]; 4];
    for col in 0..3 {
        m[col][0] = s * r[0][col];
        m[col][1] = s * r[1][col];
        m[col][2] = -0.25 * r[2][col]; // nearer (larger z) = smaller depth
    }
    m[3] = [0.0, 0.0, 0.5, 1.0];
    m
}

fn main() -> Result<(), Box<dyn Error>> {
    let args = parse_args()?;
    std::fs::create_dir_all(&args.out)?;
    let (device, queue) = open_device()?;
    let ctx = GpuContext::from_device(device.clone(), queue.clone());
    println!("adapter: {}", ctx.adapter_label());

    // Once per topology: the plan, the evaluator, the index buffer.
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 8))?;
    let mut frame = plan.frame(&mesh)?;
    let mut evaluator = GpuEvaluator::new(&ctx, &plan)?;
    let vertices = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app vertices"),
        size: evaluator.vertex_bytes(),
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let width = IndexWidth::for_plan(&plan);
    let index_count = plan.triangle_count() as u32 * 3;
    let indices = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app indices"),
        size: width.buffer_bytes(&plan),
        usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    evaluator.write_indices(&plan, &indices, 0, width)?;

    // The application's pipeline and targets.
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("app shader"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app view"),
        size: 80,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let (layout, group) = common::view_group(&device, None, &uniforms);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    // tessella's default format without UVs: position, normal (`examples/engine.rs` passes a
    // format of its own).
    let format = evaluator.vertex_format();
    let normal = format.normal.ok_or("the default format has normals")?;
    let attributes = common::position_normal(format.position, normal);
    let pipeline = common::render_pipeline(
        &device,
        "app pipeline",
        &pipeline_layout,
        &module,
        "vs",
        &[Some(wgpu::VertexBufferLayout {
            array_stride: format.stride as u64 * 4,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &attributes,
        })],
        (COLOR, DEPTH),
    );
    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let color = common::texture(
        &device,
        args.size,
        COLOR,
        attach | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = common::texture(&device, args.size, DEPTH, attach);
    let (color_view, depth_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app readback"),
        size: common::padded_row(args.size) * args.size as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });

    let mut view = [0.0f32; 20];
    for (i, v) in transform(0.5, 0.35, 0.6).iter().flatten().enumerate() {
        view[i] = *v;
    }
    view[16..19].copy_from_slice(&[0.4, 0.6, 0.7]);
    queue.write_buffer(&uniforms, 0, bytemuck_bytes(&view));

    for k in 0..args.frames {
        // Per frame: move the coarse mesh, rebuild the nets, refine into our buffer.
        let t = k as f32 / args.frames as f32 * std::f32::consts::TAU;
        let moved: Vec<[f32; 3]> = mesh
            .positions()
            .iter()
            .map(|p| {
                let s = 1.0 + 0.25 * (3.0 * p[1] + t).sin();
                [p[0] * s, p[1] * (1.0 + 0.15 * t.sin()), p[2] * s]
            })
            .collect();
        plan.update(&mut frame, &moved, None)?;
        // tessella's dispatches and the application's draw in one encoder of the application.
        let mut encoder = device.create_command_encoder(&Default::default());
        evaluator.record(
            &mut encoder,
            &plan,
            &frame,
            GpuOutput::Buffer {
                buffer: &vertices,
                offset: 0,
            },
        )?;
        {
            let mut pass = common::begin_pass(&mut encoder, "app pass", &color_view, &depth_view);
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.set_vertex_buffer(0, vertices.slice(..));
            pass.set_index_buffer(indices.slice(..), width.format());
            pass.draw_indexed(0..index_count, 0, 0..1);
        }
        common::copy_picture(&mut encoder, &color, &readback, args.size);
        ctx.submit_and_wait(encoder)?;
        let pixels = common::unpad_rows(&ctx.map_and_copy(&readback)?, args.size);
        let picture = image::RgbaImage::from_raw(args.size, args.size, pixels)
            .ok_or("picture size mismatch")?;
        let path = args.out.join(format!("frame_{k:03}.png"));
        picture.save(&path)?;
        println!("{}", path.display());
    }
    Ok(())
}

fn bytemuck_bytes(v: &[f32]) -> &[u8] {
    bytemuck::cast_slice(v)
}
