//! Streamed writes against the in-memory writers: the same bytes for every format, with and
//! without texture coordinates, however small the pieces; refusals leave nothing behind.

use tessella_core::refine::Plan;
use tessella_core::{refine, samples, Mesh, RefineOptions, Scheme};
use tessella_io::stream::{check_free_space, expected_bytes};
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
                if !ascii && !name.ends_with(".obj") {
                    let expected = expected_bytes(dir.path().join(name).as_path(), &source, &opts);
                    let expected = expected.unwrap();
                    // Exact but for the header's few hundred bytes.
                    assert!(expected >= got.len() as u64 && expected < got.len() as u64 + 1100);
                }
            }
        }
    }
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
    // .gltf (base64 text) is refused by the streamed writer, after it opened its temp file.
    let error = write_streamed(&dir.path().join("x.gltf"), &source, &opts, &|_| {});
    assert!(error
        .unwrap_err()
        .to_string()
        .contains("write .glb instead"));
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
