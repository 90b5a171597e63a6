//! Streamed writes against the in-memory writers: the same bytes for every format, with and
//! without texture coordinates, however small the pieces; refusals leave nothing behind.

use tessella_core::refine::{Levels, Plan, Spacing};
use tessella_core::{refine, samples, Mesh, RefineOptions, Scheme};
use tessella_io::stream::{
    check_free_space, expected_bytes, Corners, MeshSource, VertexRun, Wanted,
};
use tessella_io::{write_mesh, write_streamed, MeshView, RefinedSource, WriteOptions};

/// An icosphere with texture coordinates from its positions (any UVs will do).
fn with_uvs(mesh: &Mesh) -> Mesh {
    let uvs = mesh
        .positions()
        .iter()
        .map(|p| [0.5 + 0.5 * p[0], 0.25 + 0.7 * p[1]])
        .collect();
    Mesh::new(
        mesh.positions().to_vec(),
        Some(mesh.normals().to_vec()),
        Some(uvs),
        mesh.triangles().to_vec(),
    )
    .unwrap()
}

/// The number of unique edges of `mesh`.
fn plain_edges(mesh: &Mesh) -> usize {
    tessella_core::mesh::Topology::new(mesh).edges.len()
}

#[test]
fn streamed_files_equal_the_in_memory_files() {
    let dir = tempfile::tempdir().unwrap();
    let plain = samples::icosphere(2);
    let meshes = [plain.clone(), with_uvs(&plain)];
    for (m, mesh) in meshes.iter().enumerate() {
        // Uniform levels, and adaptive plans: a fractional level on a tessellator spacing
        // and the screen-size LOD (a level per edge).
        let uniform = [
            (Scheme::Pn, 1, true),
            (Scheme::Pn, 7, true),
            (Scheme::Png1, 4, true),
            (Scheme::Pn, 7, false),
            (Scheme::Png1, 1, false),
        ]
        .map(|(scheme, level, weld)| RefineOptions::new(scheme, level).with_weld(weld));
        let adaptive = [(Scheme::Pn, true), (Scheme::Png1, false)].map(|(scheme, weld)| {
            RefineOptions::new(scheme, 1)
                .with_spacing(Spacing::FractionalEven)
                .with_uniform_level(5.3)
                .with_weld(weld)
        });
        let lod = RefineOptions::new(Scheme::Pn, 1).with_levels(Levels::PerEdge {
            edges: (0..plain_edges(mesh))
                .map(|e| 1.0 + (e % 6) as f32)
                .collect(),
            faces: None,
        });
        for options in uniform.into_iter().chain(adaptive).chain([lod]) {
            let (scheme, level, weld) = (
                options.scheme,
                format!("{:?}", options.levels),
                options.weld,
            );
            // The independent path: the whole refinement in memory, the ordinary writer.
            let whole = refine(mesh, &options).unwrap();
            let plan = Plan::new(mesh, &options).unwrap();
            let frame = plan.frame(mesh).unwrap();
            // The smallest budget: pieces of 1024 vertices, many per file, evaluated on a
            // thread of their own; and one the whole output fits in, evaluated in turn.
            let files = [
                ("a.ply", false),
                ("b.ply", true),
                ("c.obj", false),
                ("d.glb", false),
                ("e.stl", false),
                ("f.gltf", false),
            ];
            for (budget, (name, ascii)) in
                [0, 1 << 30].into_iter().flat_map(|b| files.map(|f| (b, f)))
            {
                let source = RefinedSource::new(&plan, &frame, budget);
                let opts = WriteOptions {
                    ply_ascii: ascii,
                    ..Default::default()
                };
                let want = dir.path().join(format!("want-{name}"));
                let got = dir.path().join(format!("got-{name}"));
                write_mesh(&want, MeshView::from(&whole), &opts).unwrap();
                let written = std::cell::Cell::new(0u64);
                write_streamed(&got, &source, &opts, &|n| written.set(written.get() + n)).unwrap();
                let (want, got) = (std::fs::read(&want).unwrap(), std::fs::read(&got).unwrap());
                assert!(
                    want == got,
                    "mesh {m} {scheme:?} level {level} weld {weld} budget {budget} {name} \
                     (ascii {ascii}): {} bytes vs {}",
                    got.len(),
                    want.len()
                );
                assert_eq!(
                    written.get(),
                    got.len() as u64,
                    "progress counts every byte"
                );
                if !ascii && !name.ends_with(".obj") && !name.ends_with(".gltf") {
                    let expected = expected_bytes(dir.path().join(name).as_path(), &source, &opts);
                    let expected = expected.unwrap();
                    // Exact but for the header's few hundred bytes.
                    assert!(expected >= got.len() as u64 && expected < got.len() as u64 + 1100);
                }
            }
        }
    }
}

/// Per-vertex fields and origins written piece by piece equal the whole refinement's
/// (`interpolate_point_data`, `Plan::origin`) written in memory: PLY (binary and ascii, with
/// and without origins) and glTF (binary and text), welded and soup, pieces of 1024 vertices
/// and one piece for all. Formats that hold no fields write the same file as without them.
#[test]
fn streamed_fields_and_origins_equal_the_in_memory_files() {
    use tessella_core::fields::interpolate_point_data;
    let dir = tempfile::tempdir().unwrap();
    let mesh = with_uvs(&samples::icosphere(2));
    let fields: Vec<(String, Vec<f32>)> = vec![
        (
            "temperature".into(),
            mesh.positions().iter().map(|p| p[0] + 2.0 * p[1]).collect(),
        ),
        (
            "pressure".into(),
            mesh.positions().iter().map(|p| p[2] * p[2] - 0.5).collect(),
        ),
    ];
    for (scheme, level, weld) in [
        (Scheme::Pn, 7, true),
        (Scheme::Png1, 1, true),
        (Scheme::Pn, 5, false),
    ] {
        let options = RefineOptions::new(scheme, level).with_weld(weld);
        let whole = refine(&mesh, &options).unwrap();
        let plan = Plan::new(&mesh, &options).unwrap();
        let frame = plan.frame(&mesh).unwrap();
        let refined: Vec<(String, Vec<f32>)> = fields
            .iter()
            .map(|(n, v)| {
                (
                    n.clone(),
                    interpolate_point_data(&mesh, &plan, n, v, 1).unwrap(),
                )
            })
            .collect();
        let scalars: Vec<(&str, &[f32])> = refined
            .iter()
            .map(|(n, v)| (n.as_str(), v.as_slice()))
            .collect();
        let (faces, bary) = plan.origin();
        let origin = tessella_io::ply::Origin {
            faces: &faces,
            bary: &bary,
        };
        for budget in [0, 1 << 30] {
            let what = format!("{scheme:?} level {level} weld {weld} budget {budget}");
            let source = || {
                RefinedSource::new(&plan, &frame, budget)
                    .with_fields(&fields)
                    .unwrap()
            };
            for (name, ascii, with_origin) in [
                ("a.ply", false, false),
                ("b.ply", true, false),
                ("c.ply", false, true),
                ("d.ply", true, true),
                ("e.glb", false, false),
                ("f.gltf", false, false),
            ] {
                let opts = WriteOptions {
                    ply_ascii: ascii,
                    ..Default::default()
                };
                let (want, got) = (
                    dir.path().join(format!("want-{name}")),
                    dir.path().join(format!("got-{name}")),
                );
                let view = MeshView::from(&whole);
                let streamed = match with_origin {
                    true => {
                        tessella_io::ply::write_file_with(
                            &want,
                            view,
                            &scalars,
                            Some(origin),
                            ascii,
                        )
                        .unwrap();
                        source().with_origin()
                    }
                    false => {
                        tessella_io::write_mesh_with_scalars(&want, view, &scalars, &opts).unwrap();
                        source()
                    }
                };
                write_streamed(&got, &streamed, &opts, &|_| {}).unwrap();
                let (want, got) = (std::fs::read(&want).unwrap(), std::fs::read(&got).unwrap());
                assert!(
                    want == got,
                    "{what} {name} (origin {with_origin}): {} bytes vs {}",
                    got.len(),
                    want.len()
                );
            }
        }
    }
    // Formats without per-vertex fields, or without origins, refuse them as the in-memory
    // writer does, and leave nothing behind.
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let source = RefinedSource::new(&plan, &frame, 0);
    for (name, source) in [
        ("x.obj", source.with_fields(&fields).unwrap()),
        (
            "x.stl",
            RefinedSource::new(&plan, &frame, 0)
                .with_fields(&fields)
                .unwrap(),
        ),
        ("x.glb", RefinedSource::new(&plan, &frame, 0).with_origin()),
    ] {
        let path = dir.path().join(name);
        let err = write_streamed(&path, &source, &WriteOptions::default(), &|_| {}).unwrap_err();
        let message = err.to_string();
        assert!(message.contains("cannot hold"), "{name}: {message}");
        assert!(!path.exists());
    }
    // A field of the wrong length, or with a NaN, is refused, naming it.
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    for bad in [vec![1.0; 5], {
        let mut v = vec![0.0; mesh.vertex_count()];
        v[3] = f32::NAN;
        v
    }] {
        let fields = [("bad".to_string(), bad)];
        let err = RefinedSource::new(&plan, &frame, 0)
            .with_fields(&fields)
            .err()
            .expect("refused");
        assert!(err.to_string().contains("bad"), "{err}");
    }
}

/// Displaced refinements written piece by piece equal `Displacement::apply` on the whole
/// refinement, written in memory: split normals (the hard cube's shared directions on its
/// edges and corners) and smooth meshes, welded and soup, noise and a height map, every
/// format, pieces of 1024 vertices and one piece for all.
#[test]
fn streamed_displaced_files_equal_the_in_memory_files() {
    use tessella_core::{DisplaceFrame, Displacement, HeightMap};
    let dir = tempfile::tempdir().unwrap();
    let map = HeightMap::new(3, 2, vec![0.0, 0.5, 1.0, 0.25, 0.75, 0.1]).unwrap();
    let cases = [
        (
            samples::hard_cube(),
            Displacement::Perlin {
                amplitude: 0.05,
                frequency: 3.0,
                seed: 7,
            },
        ),
        (
            samples::icosphere(2),
            Displacement::Sine {
                amplitude: 0.1,
                frequency: 12.0,
            },
        ),
        (
            with_uvs(&samples::icosphere(2)),
            Displacement::HeightMap {
                amplitude: 0.2,
                map,
            },
        ),
    ];
    for (c, (mesh, displacement)) in cases.iter().enumerate() {
        for weld in [true, false] {
            let options = RefineOptions::new(Scheme::Pn, 9).with_weld(weld);
            let plan = Plan::new(mesh, &options).unwrap();
            let frame = plan.frame(mesh).unwrap();
            let mut whole = refine(mesh, &options).unwrap();
            let dframe = DisplaceFrame::new(mesh, plan.topology(), plan.layout());
            assert!(
                c != 0 || dframe.has_splits(),
                "the hard cube has split normals"
            );
            displacement.apply(&mut whole, &dframe).unwrap();
            for budget in [0, 1 << 30] {
                for name in ["a.ply", "b.obj", "c.glb", "d.stl", "e.gltf"] {
                    let source = RefinedSource::new(&plan, &frame, budget)
                        .displaced(displacement)
                        .unwrap();
                    let opts = WriteOptions::default();
                    let want = dir.path().join(format!("want-{name}"));
                    let got = dir.path().join(format!("got-{name}"));
                    write_mesh(&want, MeshView::from(&whole), &opts).unwrap();
                    write_streamed(&got, &source, &opts, &|_| {}).unwrap();
                    assert!(
                        std::fs::read(&want).unwrap() == std::fs::read(&got).unwrap(),
                        "case {c} weld {weld} budget {budget} {name}"
                    );
                }
            }
        }
    }
    // A height map needs texture coordinates: refused before anything is written.
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let needs_uvs = Displacement::HeightMap {
        amplitude: 0.1,
        map: HeightMap::new(1, 1, vec![1.0]).unwrap(),
    };
    assert!(RefinedSource::new(&plan, &frame, 0)
        .displaced(&needs_uvs)
        .is_err());
    // Displacement follows the uniform layout: an adaptive plan is refused, with why.
    let spaced = RefineOptions::new(Scheme::Pn, 1)
        .with_spacing(Spacing::FractionalOdd)
        .with_uniform_level(3.0);
    let plan = Plan::new(&mesh, &spaced).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let sine = Displacement::Sine {
        amplitude: 0.1,
        frequency: 2.0,
    };
    let err = RefinedSource::new(&plan, &frame, 0)
        .displaced(&sine)
        .err()
        .expect("refused");
    assert!(err.to_string().contains("uniform grid levels"), "{err}");
}

#[test]
fn a_disk_too_small_is_refused_with_both_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.ply");
    let error = check_free_space(&path, u64::MAX / 2)
        .unwrap_err()
        .to_string();
    assert!(error.contains("needs 9223.4 PB, the disk has"), "{error}");
    assert!(error.contains("free"), "{error}");
    assert!(check_free_space(&path, 1).is_ok());
}

#[test]
fn failed_streamed_writes_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = samples::icosphere(1);
    let plan = Plan::new(&mesh, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let frame = plan.frame(&mesh).unwrap();
    let source = RefinedSource::new(&plan, &frame, 1 << 20);
    let opts = WriteOptions::default();
    // A source that fails half-way, after the header and the vertices went out, in every
    // format: the error comes back and no file is left.
    let failing = FailsAtTriangles(&source);
    for name in ["x.ply", "x.obj", "x.glb", "x.gltf", "x.stl"] {
        let error = write_streamed(&dir.path().join(name), &failing, &opts, &|_| {});
        assert!(
            error
                .unwrap_err()
                .to_string()
                .contains("no triangles today"),
            "{name}"
        );
        assert!(!dir.path().join(name).exists(), "{name} was left");
    }
    // A read-only folder (root ignores permissions, so only check what can be checked).
    let locked = dir.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    }
    let result = write_streamed(&locked.join("x.ply"), &source, &opts, &|_| {});
    if let Err(e) = &result {
        assert!(e.to_string().contains("cannot write"), "{e}");
    }
    let left: Vec<_> = walk(dir.path())
        .into_iter()
        .filter(|p| p.to_string_lossy().contains(".tessella-"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
    assert!(!dir.path().join("x.gltf").exists());
}

/// A source whose vertices come from the one it wraps and whose triangles fail.
struct FailsAtTriangles<'a>(&'a RefinedSource<'a>);

impl MeshSource for FailsAtTriangles<'_> {
    fn vertex_count(&self) -> u64 {
        self.0.vertex_count()
    }
    fn triangle_count(&self) -> u64 {
        self.0.triangle_count()
    }
    fn has_normals(&self) -> bool {
        self.0.has_normals()
    }
    fn has_uvs(&self) -> bool {
        self.0.has_uvs()
    }
    fn vertices(
        &self,
        want: Wanted,
        each: &mut dyn FnMut(VertexRun<'_>) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        self.0.vertices(want, each)
    }
    fn triangles(
        &self,
        _each: &mut dyn FnMut(&[[u32; 3]]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        Err(std::io::Error::other("no triangles today"))
    }
    fn triangle_corners(
        &self,
        _each: &mut dyn FnMut(&[Corners]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        Err(std::io::Error::other("no triangles today"))
    }
}

fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(walk(&path));
        } else {
            out.push(path);
        }
    }
    out
}
