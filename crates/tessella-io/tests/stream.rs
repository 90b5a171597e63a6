//! Streamed writes against the in-memory writers: the same bytes for every format, with and
//! without texture coordinates, however small the pieces; refusals leave nothing behind.

use tessella_core::refine::Plan;
use tessella_core::{refine, samples, Mesh, RefineOptions, Scheme};
use tessella_io::stream::{check_free_space, expected_bytes, Corners, MeshSource, Wanted};
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

#[test]
fn streamed_files_equal_the_in_memory_files() {
    let dir = tempfile::tempdir().unwrap();
    let plain = samples::icosphere(2);
    let meshes = [plain.clone(), with_uvs(&plain)];
    for (m, mesh) in meshes.iter().enumerate() {
        for (scheme, level, weld) in [
            (Scheme::Pn, 1, true),
            (Scheme::Pn, 7, true),
            (Scheme::Png1, 4, true),
            (Scheme::Pn, 7, false),
            (Scheme::Png1, 1, false),
        ] {
            let options = RefineOptions::new(scheme, level).with_weld(weld);
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
                let source = RefinedSource::new(&plan, &frame, budget).unwrap();
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
                        .unwrap()
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
        .unwrap()
        .displaced(&needs_uvs)
        .is_err());
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
    let source = RefinedSource::new(&plan, &frame, 1 << 20).unwrap();
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
        each: &mut dyn FnMut(MeshView<'_>) -> std::io::Result<()>,
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
