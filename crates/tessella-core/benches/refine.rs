//! Refinement throughput on the bundled 5120-triangle icosphere, against a naive baseline
//! measured in the same run.
//!
//! - `tessella/*`: [`Refiner`] reused (nets and stencil prepared once, output buffers reused),
//!   as an engine refines every frame; `tessella-cold/*` includes preparation and fresh output.
//! - `naive/*`: single-threaded, evaluating PN's formulas per output vertex straight from the
//!   corners (as the GMR paper's vertex shader does) and welding shared vertices by a position
//!   hash map afterwards: what a straightforward implementation does. `tessella-1thread/*` is
//!   tessella on one thread, so each ratio compares one thing: naive vs tessella-1thread is
//!   the algorithm, tessella-1thread vs tessella the threads.
//! - `frame-*/*`: a mesh twisting frame after frame (the 5120-triangle icosphere and the
//!   320-triangle creature): `update+evaluate` moves a plan's frame and writes vertices into
//!   reused buffers (indices are not rewritten), `rebuild` makes mesh, topology, nets, stencil
//!   and a fresh output every frame, and `fill` writes the same number of bytes with `fill`
//!   (the memory's write rate, measured in the same run; throughputs are in bytes).
//!
//! Also prints the peak heap growth of one cold refine against the output's own size.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rayon::prelude::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::collections::HashMap;
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};
use tessella_core::refine::{Plan, VertexOutput};
use tessella_core::{samples, Mesh, Pattern, RefineOptions, RefinedMesh, Refiner, Scheme};

/// Counts live and peak heap bytes.
struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
        PEAK.fetch_max(live, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
        PEAK.fetch_max(live, Ordering::Relaxed);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > layout.size() {
            let live = LIVE.fetch_add(new_size - layout.size(), Ordering::Relaxed) + new_size
                - layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        } else {
            LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

type V3 = [f32; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn axpy(s: f32, a: V3, acc: &mut V3) {
    for k in 0..3 {
        acc[k] += s * a[k];
    }
}

/// PN position and quadratic normal at `l`, computed from scratch (GMR Appendix A).
fn naive_pn(p: [V3; 3], n: [V3; 3], l: [f32; 3]) -> (V3, V3) {
    let edge = |i: usize, j: usize| {
        let w = dot(sub(p[j], p[i]), n[i]);
        let mut b = [0.0; 3];
        axpy(2.0 / 3.0, p[i], &mut b);
        axpy(1.0 / 3.0, p[j], &mut b);
        axpy(-w / 3.0, n[i], &mut b);
        b
    };
    let e = [
        edge(0, 1),
        edge(1, 0),
        edge(1, 2),
        edge(2, 1),
        edge(2, 0),
        edge(0, 2),
    ];
    let mut centre = [0.0; 3];
    for x in &e {
        axpy(1.0 / 4.0, *x, &mut centre);
    }
    for x in &p {
        axpy(-1.0 / 6.0, *x, &mut centre);
    }
    let [a, b, c] = l;
    let mut pos = [0.0; 3];
    axpy(a * a * a, p[0], &mut pos);
    axpy(b * b * b, p[1], &mut pos);
    axpy(c * c * c, p[2], &mut pos);
    axpy(3.0 * a * a * b, e[0], &mut pos);
    axpy(3.0 * a * b * b, e[1], &mut pos);
    axpy(3.0 * b * b * c, e[2], &mut pos);
    axpy(3.0 * b * c * c, e[3], &mut pos);
    axpy(3.0 * a * c * c, e[4], &mut pos);
    axpy(3.0 * a * a * c, e[5], &mut pos);
    axpy(6.0 * a * b * c, centre, &mut pos);
    let mid = |i: usize, j: usize| {
        let d = sub(p[j], p[i]);
        let s = [n[i][0] + n[j][0], n[i][1] + n[j][1], n[i][2] + n[j][2]];
        let v = 2.0 * dot(d, s) / dot(d, d);
        let m = sub(s, [v * d[0], v * d[1], v * d[2]]);
        let len = dot(m, m).sqrt();
        [m[0] / len, m[1] / len, m[2] / len]
    };
    let mut nrm = [0.0; 3];
    axpy(a * a, n[0], &mut nrm);
    axpy(b * b, n[1], &mut nrm);
    axpy(c * c, n[2], &mut nrm);
    axpy(a * b, mid(0, 1), &mut nrm);
    axpy(b * c, mid(1, 2), &mut nrm);
    axpy(c * a, mid(2, 0), &mut nrm);
    let len = dot(nrm, nrm).sqrt();
    (pos, [nrm[0] / len, nrm[1] / len, nrm[2] / len])
}

/// Naive single-threaded PN refinement, welded by a position hash map.
fn naive_refine(mesh: &Mesh, pattern: &Pattern) -> RefinedMesh {
    let mut out = RefinedMesh::default();
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    for f in 0..mesh.face_count() {
        let p = mesh.corner_positions(f).map(|v| v.to_array());
        let n = mesh.corner_normals(f).map(|v| v.to_array());
        let local: Vec<u32> = pattern
            .points
            .iter()
            .map(|l| {
                let (pos, nrm) = naive_pn(p, n, l.map(|x| x as f32));
                *index.entry(pos.map(f32::to_bits)).or_insert_with(|| {
                    out.positions.push(pos);
                    out.normals.push(nrm);
                    out.positions.len() as u32 - 1
                })
            })
            .collect();
        out.triangles.extend(
            pattern
                .triangles
                .iter()
                .map(|t| t.map(|i| local[i as usize])),
        );
    }
    out
}

fn print_memory(mesh: &Mesh, level: u32) {
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let out = Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, level))
        .unwrap()
        .refine();
    let peak = PEAK.load(Ordering::Relaxed) - before;
    let size = out.byte_size() as usize;
    println!(
        "memory: PN level {level}: output {:.1} MiB, peak heap growth {:.1} MiB, ratio {:.3}",
        size as f64 / 1048576.0,
        peak as f64 / 1048576.0,
        peak as f64 / size as f64
    );
}

fn bench_refine(c: &mut Criterion) {
    let mesh = samples::icosphere_4k();
    for level in [4, 16, 32] {
        print_memory(&mesh, level);
    }
    let mut group = c.benchmark_group("refine-pn-welded");
    group.sample_size(20);
    for level in [4u32, 8, 16, 32] {
        let options = RefineOptions::new(Scheme::Pn, level);
        let refiner = Refiner::new(&mesh, &options).unwrap();
        let vertices = refiner.layout().vertex_count;
        group.throughput(Throughput::Elements(vertices));
        let mut out = RefinedMesh::default();
        group.bench_with_input(BenchmarkId::new("tessella", level), &level, |b, _| {
            b.iter(|| refiner.refine_into(black_box(&mut out), &|_| {}))
        });
        group.bench_with_input(BenchmarkId::new("tessella-cold", level), &level, |b, _| {
            b.iter(|| black_box(Refiner::new(&mesh, &options).unwrap().refine()))
        });
        let single = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        group.bench_with_input(
            BenchmarkId::new("tessella-1thread", level),
            &level,
            |b, _| b.iter(|| single.install(|| refiner.refine_into(black_box(&mut out), &|_| {}))),
        );
        if level <= 16 {
            let pattern = Pattern::uniform(level);
            group.bench_with_input(BenchmarkId::new("naive", level), &level, |b, _| {
                b.iter(|| black_box(naive_refine(&mesh, &pattern)))
            });
        }
    }
    group.finish();

    let mut group = c.benchmark_group("refine-level16-schemes");
    group.sample_size(20);
    // PNG1, PN-AEN and ST relative to PN, measured in the same run.
    for scheme in [
        Scheme::Pn,
        Scheme::Flat,
        Scheme::PHONG,
        Scheme::PnAen,
        Scheme::ScalarTagged,
        Scheme::Png1,
    ] {
        let name = scheme.name();
        let refiner = Refiner::new(&mesh, &RefineOptions::new(scheme, 16)).unwrap();
        group.throughput(Throughput::Elements(refiner.layout().vertex_count));
        let mut out = RefinedMesh::default();
        group.bench_function(name, |b| {
            b.iter(|| refiner.refine_into(black_box(&mut out), &|_| {}))
        });
    }
    group.finish();
}

fn bench_frames(c: &mut Criterion) {
    for (name, mesh) in [
        ("icosphere-4k", samples::icosphere_4k()),
        ("creature", samples::creature()),
    ] {
        let frames: Vec<_> = (0..8)
            .map(|i| samples::twist(&mesh, 10.0 * i as f32))
            .collect();
        let mut group = c.benchmark_group(format!("frame-{name}"));
        group.sample_size(15);
        for level in [8u32, 16, 32] {
            let options = RefineOptions::new(Scheme::Pn, level);
            let plan = Plan::new(&mesh, &options).unwrap();
            let mut frame = plan.frame(&mesh).unwrap();
            let n = plan.vertex_count();
            let (mut p, mut nr) = (vec![[0.0f32; 3]; n], vec![[0.0f32; 3]; n]);
            group.throughput(Throughput::Bytes(n as u64 * 24));
            let mut at = 0;
            group.bench_with_input(
                BenchmarkId::new("update+evaluate", level),
                &level,
                |b, _| {
                    b.iter(|| {
                        let (fp, fnr) = &frames[at % frames.len()];
                        at += 1;
                        plan.update(&mut frame, fp, Some(fnr)).unwrap();
                        plan.evaluate(
                            &frame,
                            VertexOutput::Separate {
                                positions: black_box(&mut p),
                                normals: Some(black_box(&mut nr)),
                                uvs: None,
                            },
                        )
                        .unwrap();
                    })
                },
            );
            group.bench_with_input(BenchmarkId::new("rebuild", level), &level, |b, _| {
                b.iter(|| {
                    let (fp, fnr) = &frames[at % frames.len()];
                    at += 1;
                    let m = Mesh::new(
                        fp.clone(),
                        Some(fnr.clone()),
                        None,
                        mesh.triangles().to_vec(),
                    )
                    .unwrap();
                    black_box(Refiner::new(&m, &options).unwrap().refine())
                })
            });
            let mut bytes = vec![0.0f32; n * 6];
            let chunk = bytes.len().div_ceil(rayon::current_num_threads());
            group.bench_with_input(BenchmarkId::new("fill", level), &level, |b, _| {
                b.iter(|| {
                    black_box(&mut bytes)
                        .par_chunks_mut(chunk)
                        .for_each(|c| c.fill(black_box(1.0)))
                })
            });
        }
        group.finish();
    }
}

/// Topology of an 81,920-triangle icosphere (the one-shot benchmark's mesh): edges by index and
/// by position, owners, neighbours.
fn bench_topology(c: &mut Criterion) {
    let mesh = samples::icosphere(6);
    let mut group = c.benchmark_group("topology");
    group.sample_size(20);
    group.throughput(Throughput::Elements(mesh.face_count() as u64));
    group.bench_function("icosphere-82k", |b| {
        b.iter(|| tessella_core::Topology::new(&mesh))
    });
    group.finish();
}

/// The cost of texture coordinates: PN at level 32 on the 5120-triangle icosphere with UVs
/// (spherical coordinates) against the same mesh without.
fn bench_uvs(c: &mut Criterion) {
    let plain = samples::icosphere(4);
    let uvs = plain
        .positions()
        .iter()
        .map(|p| [p[0].atan2(p[2]), p[1].clamp(-1.0, 1.0).asin()])
        .collect();
    let textured = Mesh::new(
        plain.positions().to_vec(),
        Some(plain.normals().to_vec()),
        Some(uvs),
        plain.triangles().to_vec(),
    )
    .expect("the icosphere with UVs");
    let mut group = c.benchmark_group("uvs-pn-32");
    group.sample_size(15);
    for (name, mesh) in [("without", &plain), ("with", &textured)] {
        let refiner = Refiner::new(mesh, &RefineOptions::new(Scheme::Pn, 32)).expect("refiner");
        group.throughput(Throughput::Elements(refiner.layout().vertex_count));
        group.bench_function(name, |b| b.iter(|| black_box(refiner.refine())));
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_refine,
    bench_frames,
    bench_topology,
    bench_uvs
);
criterion_main!(benches);
