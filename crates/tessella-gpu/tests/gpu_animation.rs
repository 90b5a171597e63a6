//! A frame of an animated mesh done wholly on the GPU: [`GpuSkinner`] poses the coarse mesh
//! from the frame's deform matrices, [`GpuNetBuilder`] builds the control nets from its output.
//! The nets must equal the CPU's frame (`Poser::pose_into`, `Mesh::update`, the scheme's net
//! builder) within 1e-6 relative, for every scheme the GPU builds and both normal nets.
mod common;

use common::{ctx, read_vec3s, worst_relative};
use tessella_core::animation::Poser;
use tessella_core::refine::{Surface, SurfaceOptions};
use tessella_core::{samples, NormalMode, Scheme};
use tessella_gpu::{GpuNetBuilder, GpuSkinner, NetsTarget};

#[test]
fn gpu_skinned_nets_equal_the_cpu_frames_nets() {
    let ctx = ctx();
    let poser = Poser::new(samples::animated_creature(1)).unwrap();
    let rest = poser.mesh(None, 0.0).unwrap();
    let mut skinner = GpuSkinner::new(ctx, &poser).unwrap();
    let faces = rest.face_count();
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let sentinel = |label, floats: usize| {
        ctx.buffer_init(
            label,
            bytemuck::cast_slice(&vec![-7777.0f32; floats]),
            usage,
        )
    };
    let (points, normals) = (
        sentinel("points", faces * 30),
        sentinel("normals", faces * 18),
    );
    let schemes = [
        (Scheme::Flat, NormalMode::Linear),
        (Scheme::Phong { alpha: 0.75 }, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Linear),
        (Scheme::Pn, NormalMode::Quadratic),
        (Scheme::Pn, NormalMode::Real),
        (Scheme::PnAen, NormalMode::Quadratic),
    ];
    for (scheme, mode) in schemes {
        let options = SurfaceOptions::new(scheme).with_normals(mode);
        let surface = Surface::new(&rest, &options).unwrap();
        let builder = GpuNetBuilder::new(ctx, &surface).unwrap();
        let still = surface.frame(&rest).unwrap().nets().clone();
        for clip in 0..poser.clip_count() {
            let mut moved = 0.0f64;
            for time in [0.0, 0.37, 0.61, 1.1] {
                skinner.update(&poser, Some(clip), time).unwrap();
                let mut encoder = ctx.device.create_command_encoder(&Default::default());
                skinner.record(&mut encoder).unwrap();
                let target = NetsTarget::new(&points, &normals, faces, mode);
                builder
                    .record(&mut encoder, skinner.output(), target)
                    .unwrap();
                ctx.submit_and_wait(encoder).unwrap();
                let posed = poser.mesh(Some(clip), time).unwrap();
                let cpu = surface.frame(&posed).unwrap().nets().clone();
                let what = format!("{} {mode:?}, clip {clip} at {time}", scheme.name());
                let worst_points = worst_relative(&read_vec3s(ctx, &points), &cpu.points);
                let worst_normals = worst_relative(&read_vec3s(ctx, &normals), &cpu.normals);
                assert!(
                    worst_points <= 1e-6,
                    "{what}: points off by {worst_points:e}"
                );
                assert!(
                    worst_normals <= 1e-6,
                    "{what}: normals off by {worst_normals:e}"
                );
                moved = moved.max(worst_relative(&cpu.points, &still.points));
            }
            // The clip moved the nets away from the rest pose's (else this proves little).
            assert!(moved > 1e-3, "{} clip {clip} does not move", scheme.name());
        }
    }
}

/// A crowd's frame in two passes, as an engine records it: each character's skinning
/// dispatched into one pass ([`GpuSkinner::dispatch`]), then each one's net build into a second
/// ([`GpuNetBuilder::bind`], [`tessella_gpu::NetsDispatch::dispatch`]). Three characters at
/// their own clip and time each get the CPU frame's nets of their own pose within 1e-6, and the
/// poses differ (a character built from another's skinning would not match).
#[test]
fn a_crowd_skinned_in_one_pass_and_built_in_another_equals_each_cpu_frame() {
    let ctx = ctx();
    let poser = Poser::new(samples::animated_creature(1)).unwrap();
    let rest = poser.mesh(None, 0.0).unwrap();
    let faces = rest.face_count();
    let mode = NormalMode::Quadratic;
    let surface = Surface::new(&rest, &SurfaceOptions::new(Scheme::Pn).with_normals(mode)).unwrap();
    let builder = GpuNetBuilder::new(ctx, &surface).unwrap();
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let poses = [(0, 0.2f32), (1, 0.5), (0, 0.9)];
    let crowd: Vec<_> = poses
        .iter()
        .map(|&(clip, time)| {
            let mut skinner = GpuSkinner::new(ctx, &poser).unwrap();
            skinner.update(&poser, Some(clip), time).unwrap();
            let points = ctx.buffer_init("points", &vec![0u8; faces * 30 * 4], usage);
            let normals = ctx.buffer_init("normals", &vec![0u8; faces * 18 * 4], usage);
            (skinner, points, normals)
        })
        .collect();
    let builds: Vec<_> = crowd
        .iter()
        .map(|(skinner, points, normals)| {
            let target = NetsTarget::new(points, normals, faces, mode);
            builder.bind(skinner.output(), target).unwrap().unwrap()
        })
        .collect();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        for (skinner, _, _) in &crowd {
            skinner.dispatch(&mut pass);
        }
    }
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        for build in &builds {
            build.dispatch(&mut pass);
        }
    }
    ctx.submit_and_wait(encoder).unwrap();
    let mut frames = Vec::new();
    for (&(clip, time), (_, points, normals)) in poses.iter().zip(&crowd) {
        let posed = poser.mesh(Some(clip), time).unwrap();
        let cpu = surface.frame(&posed).unwrap().nets().clone();
        let worst_points = worst_relative(&read_vec3s(ctx, points), &cpu.points);
        let worst_normals = worst_relative(&read_vec3s(ctx, normals), &cpu.normals);
        assert!(
            worst_points <= 1e-6 && worst_normals <= 1e-6,
            "clip {clip} at {time}: points off by {worst_points:e}, normals by {worst_normals:e}"
        );
        frames.push(cpu.points);
    }
    assert!(worst_relative(&frames[0], &frames[2]) > 1e-3);
    assert!(worst_relative(&frames[0], &frames[1]) > 1e-3);
}
