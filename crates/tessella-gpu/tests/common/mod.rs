//! Shared test setup: one software (lavapipe) device per test binary.
#![allow(dead_code)]

use std::sync::OnceLock;
use tessella_core::{Mesh, RefinedMesh};
use tessella_gpu::{AdapterChoice, GpuContext, GpuError, TargetFormats};

/// The software adapter every test runs on (CI installs mesa-vulkan-drivers). A missing
/// adapter fails the tests with the install hint rather than skipping them.
pub fn ctx() -> &'static GpuContext {
    static CTX: OnceLock<Result<GpuContext, GpuError>> = OnceLock::new();
    match CTX.get_or_init(|| GpuContext::new(AdapterChoice::Software)) {
        Ok(ctx) => ctx,
        Err(e) => panic!("no software GPU adapter for the tests: {e}"),
    }
}

/// Asserts GPU output equals CPU output: positions within `1e-5 × diagonal` (plus `extra`),
/// unit normals within 1e-4, UVs within 1e-6, identical indices.
pub fn assert_same(cpu: &RefinedMesh, gpu: &RefinedMesh, mesh: &Mesh, extra: f32, what: &str) {
    assert_eq!(cpu.triangles, gpu.triangles, "{what}: indices differ");
    assert_eq!(
        cpu.positions.len(),
        gpu.positions.len(),
        "{what}: vertex count"
    );
    let tol = 1e-5 * mesh.diagonal() + extra;
    for (i, (a, b)) in cpu.positions.iter().zip(&gpu.positions).enumerate() {
        let d = dist(*a, *b);
        assert!(
            d <= tol,
            "{what}: vertex {i} position {a:?} (cpu) vs {b:?} (gpu), |d| = {d} > {tol}"
        );
    }
    for (i, (a, b)) in cpu.normals.iter().zip(&gpu.normals).enumerate() {
        let d = dist(*a, *b);
        assert!(
            d <= 1e-4,
            "{what}: vertex {i} normal {a:?} (cpu) vs {b:?} (gpu), |d| = {d}"
        );
    }
    match (&cpu.uvs, &gpu.uvs) {
        (None, None) => {}
        (Some(a), Some(b)) => {
            for (i, (a, b)) in a.iter().zip(b).enumerate() {
                let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
                assert!(d <= 1e-6, "{what}: vertex {i} uv {a:?} vs {b:?}");
            }
        }
        _ => panic!("{what}: one side has UVs, the other not"),
    }
}

pub fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The torus sample with texture coordinates (the sample itself has none).
pub fn torus_with_uvs() -> Mesh {
    let m = tessella_core::samples::torus(1.0, 0.35, 12, 8);
    // Angle-based UVs from the positions: u around the axis, v around the tube.
    let uvs = m
        .positions()
        .iter()
        .map(|p| {
            let u = (p[1].atan2(p[0]) / std::f32::consts::TAU).rem_euclid(1.0);
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt() - 1.0;
            let v = (p[2].atan2(r) / std::f32::consts::TAU).rem_euclid(1.0);
            [u, v]
        })
        .collect();
    Mesh::new(
        m.positions().to_vec(),
        Some(m.normals().to_vec()),
        Some(uvs),
        m.triangles().to_vec(),
    )
    .expect("torus with uvs is valid")
}

/// Refined edges without a twin, by position: vertices closer than `tol` are one point (found
/// through a grid of `tol`-sized cells), and on a closed surface every undirected edge between
/// two points is used by exactly two triangles. (tessella-core's tests/displace.rs counts the
/// same way on the CPU.)
pub fn open_edges(positions: &[[f32; 3]], triangles: &[[u32; 3]], tol: f32) -> usize {
    use std::collections::HashMap;
    let cell = |p: [f32; 3]| p.map(|x| (x / tol).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut point = vec![0u32; positions.len()];
    for (i, &p) in positions.iter().enumerate() {
        let c = cell(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid
                        .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                        .into_iter()
                        .flatten()
                    {
                        if dist(p, positions[j as usize]) <= tol {
                            found = Some(point[j as usize]);
                            break 'search;
                        }
                    }
                }
            }
        }
        point[i] = found.unwrap_or(i as u32);
        if found.is_none() {
            grid.entry(c).or_default().push(i as u32);
        }
    }
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (point[t[k] as usize], point[t[(k + 1) % 3] as usize]);
            assert_ne!(a, b, "a refined edge collapsed to one point");
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    uses.values().filter(|&&n| n != 2).count()
}

/// The smallest shading the renderers take: the normal as colour, the point's x and y as clip
/// coordinates, and an empty bind group 1. The renderers' own tests check geometry, not looks
/// (tessella-view's pictures test a whole shading).
pub struct PlainShading {
    pub layout: wgpu::BindGroupLayout,
    pub group: wgpu::BindGroup,
    pub formats: tessella_gpu::TargetFormats,
}

pub const PLAIN_WGSL: &str = "
struct VsOut { @builtin(position) clip: vec4<f32>, @location(0) n: vec3<f32> }
fn shade_vertex(v: TessellaVertex) -> VsOut {
    return VsOut(vec4<f32>(0.5 * v.position.xy, 0.5, 1.0), v.normal);
}
@fragment fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return vec4<f32>(0.5 + 0.5 * normalize(in.n), 1.0);
}";

impl PlainShading {
    pub fn new(ctx: &GpuContext, formats: tessella_gpu::TargetFormats) -> PlainShading {
        let layout = ctx.buffer_layout("plain", &[]);
        let group = ctx.buffer_group("plain", &layout, &[]);
        PlainShading {
            layout,
            group,
            formats,
        }
    }

    pub fn shading(&self) -> tessella_gpu::Shading<'_> {
        tessella_gpu::Shading {
            wgsl: PLAIN_WGSL,
            layout: &self.layout,
            formats: self.formats,
        }
    }
}

/// The side of the pictures [`pixels`] draws.
pub const SIZE: u32 = 64;
pub const FORMATS: TargetFormats = TargetFormats {
    color: wgpu::TextureFormat::Rgba8Unorm,
    depth: None,
    samples: 1,
};

/// The RGBA pixels of one pass drawn by `draw` on a transparent black [`SIZE`]² target of
/// [`FORMATS`] (64 pixels of 4 bytes: rows already 256-byte aligned).
pub fn pixels(ctx: &GpuContext, draw: impl FnOnce(&mut wgpu::RenderPass<'_>)) -> Vec<[u8; 4]> {
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("picture"),
        size: wgpu::Extent3d {
            width: SIZE,
            height: SIZE,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMATS.color,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("picture readback"),
        size: (SIZE * SIZE * 4) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        draw(&mut pass);
    }
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(SIZE * 4),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    ctx.submit_and_wait(encoder).unwrap();
    let bytes = ctx.read_buffer(&buffer, 0, buffer.size()).unwrap();
    bytemuck::cast_slice::<u8, [u8; 4]>(&bytes).to_vec()
}

/// A buffer of `[f32; 3]` read back.
pub fn read_vec3s(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Vec<[f32; 3]> {
    let bytes = ctx.read_buffer(buffer, 0, buffer.size()).unwrap();
    bytemuck::cast_slice::<u8, [f32; 3]>(&bytes).to_vec()
}

/// The largest `|gpu - cpu| / max(1, |cpu|)` over every component; panics on a length
/// mismatch.
pub fn worst_relative(gpu: &[[f32; 3]], cpu: &[[f32; 3]]) -> f64 {
    assert_eq!(gpu.len(), cpu.len(), "net lengths");
    gpu.iter()
        .flatten()
        .zip(cpu.iter().flatten())
        .map(|(&g, &c)| (f64::from(g) - f64::from(c)).abs() / f64::from(c.abs()).max(1.0))
        .fold(0.0, f64::max)
}
