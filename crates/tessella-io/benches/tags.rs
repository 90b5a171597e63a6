//! Loading shape tags from a 1M-vertex PLY: a 1000 × 1000 torus (2M triangles) in binary PLY, in
//! memory, with vertex properties `tension`, `sharpness`, `bias` on every vertex and an `edge`
//! element tagging 100k edges (every tenth ring) with `sharpness` and `kappa`.
//!
//! - `parse`: the PLY reader alone (`ply::read` into a `RawMesh`);
//! - `from_ply`: tags from the parsed properties (`tags::from_ply`: position ids, faces per
//!   position, one check per tag);
//! - `load`: what `tessella refine --scheme png1` does before refining: parse, validate the mesh
//!   (`Mesh::new`) and layer the tags (`tags::gather`).
//!
//! Run with `cargo bench -p tessella-io --bench tags` (`-- --quick` for a short run).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::io::Cursor;
use std::path::Path;
use std::time::Duration;
use tessella_core::{samples, Mesh, Scheme};
use tessella_io::tags::{self, TagSources};
use tessella_io::{ply, RawMesh};

/// Torus size: `AROUND × TUBE` vertices.
const AROUND: u32 = 1000;
const TUBE: u32 = 1000;

/// The benchmark file: the torus with tag properties, binary little-endian.
fn tagged_torus_ply() -> (Vec<u8>, usize) {
    let mesh = samples::torus(3.0, 1.0, AROUND, TUBE);
    let id = |i: u32, j: u32| (i % AROUND) * TUBE + (j % TUBE);
    let edges: Vec<[u32; 2]> = (0..AROUND)
        .step_by(10)
        .flat_map(|i| (0..TUBE).map(move |j| [id(i, j), id(i + 1, j)]))
        .collect();
    let header = format!(
        "ply\nformat binary_little_endian 1.0\n\
         element vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property float tension\nproperty float sharpness\nproperty float bias\n\
         element face {}\nproperty list uchar uint vertex_indices\n\
         element edge {}\nproperty uint vertex1\nproperty uint vertex2\n\
         property float sharpness\nproperty float kappa\n\
         end_header\n",
        mesh.vertex_count(),
        mesh.face_count(),
        edges.len()
    );
    let mut out = header.into_bytes();
    let f32s = |out: &mut Vec<u8>, values: &[f32]| {
        for v in values {
            out.extend_from_slice(&v.to_le_bytes());
        }
    };
    for (v, (p, n)) in mesh.positions().iter().zip(mesh.normals()).enumerate() {
        let tension = 0.1 * (v % 3) as f32;
        let sharpness = 0.25 * (v % 5) as f32 - 0.5;
        let bias = 0.01 * (v % 7) as f32;
        f32s(&mut out, p);
        f32s(&mut out, n);
        f32s(&mut out, &[tension, sharpness, bias]);
    }
    for t in mesh.triangles() {
        out.push(3);
        for v in t {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    for [a, b] in &edges {
        out.extend_from_slice(&a.to_le_bytes());
        out.extend_from_slice(&b.to_le_bytes());
        f32s(&mut out, &[0.5, -0.05]);
    }
    (out, edges.len())
}

fn parse(bytes: &[u8]) -> RawMesh {
    ply::read(Path::new("torus.ply"), Cursor::new(bytes)).expect("the benchmark PLY is valid")
}

fn mesh_of(raw: &RawMesh) -> Mesh {
    Mesh::new(
        raw.positions.clone(),
        raw.normals.clone(),
        raw.uvs.clone(),
        raw.triangles.clone(),
    )
    .expect("the torus is valid")
}

fn bench(c: &mut Criterion) {
    let (bytes, edge_count) = tagged_torus_ply();
    let raw = parse(&bytes);
    let mesh = mesh_of(&raw);
    let tags = tags::from_ply(&mesh, &raw.vertex_scalars, &raw.edges).expect("valid tags");
    assert_eq!(tags.edge_count(), edge_count);
    assert!(tags.vertex_count() > mesh.vertex_count() * 9 / 10);

    let mut group = c.benchmark_group("tags-1M");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.bench_function("parse", |b| b.iter(|| parse(black_box(&bytes))));
    group.bench_function("from_ply", |b| {
        b.iter(|| tags::from_ply(&mesh, &raw.vertex_scalars, &raw.edges).expect("valid tags"))
    });
    group.bench_function("load", |b| {
        b.iter(|| {
            let raw = parse(black_box(&bytes));
            let mesh = mesh_of(&raw);
            let sources = TagSources {
                file: Some(&raw),
                ..TagSources::default()
            };
            tags::gather(&mesh, Scheme::Png1, &sources).expect("valid tags")
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
