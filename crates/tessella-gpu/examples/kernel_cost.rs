//! The cost of evaluating every refined vertex once in a compute pass with the exported patch
//! module (`tessella_point`), what an engine's per-frame evaluation runs (tessella-bevy's
//! `TessellaDraw::PerFrame`): the creature's PN surface at a level, one thread per welded
//! refined vertex (the plan's order: corners, edges, then the faces' insides), each writing
//! its position and normal.
//!
//! `cargo run --release -p tessella-gpu --example kernel_cost -- [LEVEL] [DISPATCHES]
//! [--normals linear|quadratic|real] [--dump FILE]` prints the vertices and the mean
//! milliseconds a dispatch (each submitted and waited for); `--dump` writes the evaluated
//! floats' bytes, to compare two builds bit for bit.

use std::error::Error;
use std::time::Instant;
use tessella_core::refine::Plan;
use tessella_core::{samples, NormalMode, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext, PatchBindings};

const WORKGROUP: u32 = 64;

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| {
        let at = args.iter().position(|a| a == name)?;
        args.get(at + 1).cloned()
    };
    let numbers: Vec<&String> = args.iter().take_while(|a| !a.starts_with("--")).collect();
    let level: u32 = numbers.first().map_or(Ok(32), |s| s.parse())?;
    let dispatches: u32 = numbers.get(1).map_or(Ok(10), |s| s.parse())?;
    let ctx = GpuContext::new(AdapterChoice::Auto)?;
    let mesh = samples::creature();
    let mut options = RefineOptions::new(Scheme::Pn, level);
    options.normals = Some(match flag("--normals").as_deref() {
        Some("real") => NormalMode::Real,
        Some("linear") => NormalMode::Linear,
        None | Some("quadratic") => NormalMode::Quadratic,
        Some(other) => return Err(format!("--normals {other}: linear, quadratic or real").into()),
    });
    let plan = Plan::new(&mesh, &options)?;
    let frame = plan.frame(&mesh)?;
    let patch = PatchBindings::new(&ctx, &plan, &frame, 0, wgpu::ShaderStages::COMPUTE)?;
    // The plan's welded vertices, each at its owning face's pattern vertex.
    let key = |l: [f32; 3]| (l[1].to_bits(), l[2].to_bits());
    let points: std::collections::HashMap<(u32, u32), u32> = (plan.pattern().points.iter())
        .enumerate()
        .map(|(v, l)| (key(l.map(|x| x as f32)), v as u32))
        .collect();
    let (owners, bary) = plan.origin();
    let origins: Vec<[u32; 2]> = owners
        .iter()
        .zip(&bary)
        .map(|(&f, &l)| points.get(&key(l)).map(|&v| [f, v]))
        .collect::<Option<_>>()
        .ok_or("a welded vertex off the pattern")?;
    let vertices = origins.len() as u32;
    // The entry tessella-bevy's per-frame pass runs, its bindings in group 1; the vertices
    // packed six floats apart.
    let source = format!(
        "{}\n{}",
        patch.wgsl(),
        tessella_gpu::wgsl::evaluation_entry(1, [0, 1, 2], WORKGROUP)
    );
    let device = &ctx.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("kernel_cost"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let own = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[
            storage(0, true),
            storage(1, false),
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(patch.layout()), Some(&own)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("kernel_cost"),
        layout: Some(&layout),
        module: &module,
        entry_point: Some("tessella_evaluate"),
        compilation_options: Default::default(),
        cache: None,
    });
    use wgpu::util::DeviceExt;
    let origins_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&origins),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let placement = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&[0u32, 6, vertices, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 24 * u64::from(vertices),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &own,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: origins_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: out.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: placement.as_entire_binding(),
            },
        ],
    });
    let run = || -> Result<(), Box<dyn Error>> {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, patch.bind_group(), &[]);
            pass.set_bind_group(1, &group, &[]);
            pass.dispatch_workgroups(vertices.div_ceil(WORKGROUP), 1, 1);
        }
        ctx.submit_and_wait(encoder)?;
        Ok(())
    };
    // The first dispatch compiles (lavapipe JITs on first use).
    run()?;
    let start = Instant::now();
    for _ in 0..dispatches {
        run()?;
    }
    let ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(dispatches);
    println!("{{\"level\":{level},\"vertices\":{vertices},\"ms_per_dispatch\":{ms:.3}}}");
    if let Some(path) = flag("--dump") {
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: out.size(),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&out, 0, &read, 0, out.size());
        ctx.submit_and_wait(encoder)?;
        let slice = read.slice(..);
        slice.map_async(wgpu::MapMode::Read, |r| r.expect("map"));
        device.poll(wgpu::PollType::wait_indefinitely())?;
        std::fs::write(path, &*slice.get_mapped_range()?)?;
    }
    Ok(())
}
