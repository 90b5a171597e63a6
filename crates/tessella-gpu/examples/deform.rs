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
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::PRIMARY,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
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
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: uniforms.as_entire_binding(),
        }],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    // tessella's default format without UVs: position, normal (`examples/engine.rs` passes a
    // format of its own).
    let format = evaluator.vertex_format();
    let normal = format.normal.ok_or("the default format has normals")?;
    let attributes = [
        wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Float32x3,
            offset: format.position as u64 * 4,
            shader_location: 0,
        },
        wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Float32x3,
            offset: normal as u64 * 4,
            shader_location: 1,
        },
    ];
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("app pipeline"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: format.stride as u64 * 4,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            })],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(COLOR.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let extent = wgpu::Extent3d {
        width: args.size,
        height: args.size,
        depth_or_array_layers: 1,
    };
    let texture = |format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let color = texture(COLOR, attach | wgpu::TextureUsages::COPY_SRC);
    let depth = texture(DEPTH, attach);
    let (color_view, depth_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let row = (args.size as u64 * 4).next_multiple_of(256);
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("app readback"),
        size: row * args.size as u64,
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
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("app pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.set_vertex_buffer(0, vertices.slice(..));
            pass.set_index_buffer(indices.slice(..), width.format());
            pass.draw_indexed(0..index_count, 0, 0..1);
        }
        encoder.copy_texture_to_buffer(
            color.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row as u32),
                    rows_per_image: Some(args.size),
                },
            },
            extent,
        );
        ctx.submit_and_wait(encoder)?;
        let bytes = ctx.map_and_copy(&readback)?;
        let mut pixels = Vec::with_capacity((args.size * args.size * 4) as usize);
        for y in 0..args.size as usize {
            let start = y * row as usize;
            pixels.extend_from_slice(&bytes[start..start + args.size as usize * 4]);
        }
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
