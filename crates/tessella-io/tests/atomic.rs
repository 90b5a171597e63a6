mod common;

use common::{entries, Sample};
use std::fs;
use std::io::Error;
use tessella_io::{write_atomic, write_mesh, IoError, MeshView, WriteOptions};

#[test]
fn a_failing_writer_leaves_no_file_and_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.ply");
    let err = write_atomic(&path, |w| {
        w.write_all(b"half a file")?;
        Err(Error::other("disk on fire"))
    })
    .unwrap_err();
    assert!(matches!(err, IoError::Write { .. }), "{err}");
    assert!(err.to_string().contains("disk on fire"), "{err}");
    assert!(err.to_string().contains("out.ply"), "{err}");
    assert!(entries(dir.path()).is_empty(), "{:?}", entries(dir.path()));
}

#[test]
fn a_failing_writer_leaves_the_old_file_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    fs::write(&path, "old contents").unwrap();
    let result = write_atomic(&path, |w| {
        w.write_all(&[b'x'; 100_000])?;
        Err(Error::other("interrupted"))
    });
    assert!(result.is_err());
    assert_eq!(fs::read_to_string(&path).unwrap(), "old contents");
    assert_eq!(entries(dir.path()), ["out.obj"]);
}

#[test]
fn a_failing_rename_leaves_the_target_untouched() {
    let dir = tempfile::tempdir().unwrap();
    // The target is a non-empty folder: the data is written, but renaming over it fails.
    let target = dir.path().join("taken.ply");
    fs::create_dir(&target).unwrap();
    fs::write(target.join("keep.txt"), "keep").unwrap();
    let err = write_atomic(&target, |w| w.write_all(b"new")).unwrap_err();
    assert!(matches!(err, IoError::Write { .. }), "{err}");
    assert!(target.is_dir());
    assert_eq!(fs::read_to_string(target.join("keep.txt")).unwrap(), "keep");
    assert_eq!(entries(dir.path()), ["taken.ply"]);
}

#[test]
fn success_replaces_the_old_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.txt");
    fs::write(&path, "old").unwrap();
    write_atomic(&path, |w| w.write_all(b"new")).unwrap();
    assert_eq!(fs::read_to_string(&path).unwrap(), "new");
    assert_eq!(entries(dir.path()), ["out.txt"]);
}

#[test]
fn a_missing_folder_is_a_write_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no/such/folder/out.glb");
    let err = write_mesh(&path, Sample::new().view(), &WriteOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::Write { .. }), "{err}");
}

#[test]
fn inconsistent_views_are_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let sample = Sample::new();
    let path = dir.path().join("bad.gltf");
    let cases = [
        MeshView {
            normals: Some(&sample.normals[..2]),
            ..sample.view()
        },
        MeshView {
            uvs: Some(&sample.uvs[..1]),
            ..sample.view()
        },
        MeshView {
            triangles: &[],
            ..sample.view()
        },
        MeshView {
            triangles: &[[0, 1, 5]],
            ..sample.view()
        },
    ];
    for view in cases {
        let err = write_mesh(&path, view, &WriteOptions::default()).unwrap_err();
        assert!(
            matches!(
                err,
                IoError::BadMesh { .. } | IoError::IndexOutOfRange { .. }
            ),
            "{err}"
        );
    }
    let nan = [[f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let view = MeshView {
        positions: &nan,
        normals: None,
        uvs: None,
        triangles: &[[0, 1, 2]],
    };
    assert!(write_mesh(&path, view, &WriteOptions::default()).is_err());
    assert!(entries(dir.path()).is_empty());
}

/// The temporary file is created 0600; the result must get a plain file's permissions.
#[cfg(unix)]
#[test]
fn written_files_get_the_permissions_of_a_plain_create() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.txt");
    fs::write(&plain, "x").unwrap();
    let atomic = dir.path().join("atomic.txt");
    write_atomic(&atomic, |w| w.write_all(b"x")).unwrap();
    let mode = |p: &std::path::Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&atomic), mode(&plain));
}

/// On Linux the file has no name while it is written (O_TMPFILE), so a process killed at that
/// point, even by SIGKILL, leaves nothing in the folder; the name appears with the whole file.
#[cfg(target_os = "linux")]
#[test]
fn while_it_is_written_the_file_has_no_name() {
    let dir = tempfile::tempdir().unwrap();
    for (path, old) in [
        (dir.path().join("new.ply"), None),
        (dir.path().join("old.ply"), Some("old")),
    ] {
        if let Some(old) = old {
            fs::write(&path, old).unwrap();
        }
        let before = entries(dir.path());
        write_atomic(&path, |w| {
            w.write_all(&[7u8; 200_000])?;
            w.flush()?;
            // Written and flushed, not yet finished: the folder is as it was.
            assert_eq!(entries(dir.path()), before);
            Ok(())
        })
        .unwrap();
        assert_eq!(fs::read(&path).unwrap(), vec![7u8; 200_000]);
    }
    assert_eq!(entries(dir.path()), ["new.ply", "old.ply"]);
}

/// Cached writes (a batch's) land whole as well, and `sync_folder` flushes them.
#[test]
fn cached_writes_land_whole_and_sync_folder_flushes_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.bin");
    tessella_io::write_atomic_with(&path, tessella_io::Durability::Cached, |w| {
        w.write_all(b"cached")
    })
    .unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"cached");
    tessella_io::sync_folder(dir.path()).unwrap();
    let err = tessella_io::sync_folder(&dir.path().join("missing")).unwrap_err();
    assert!(err.to_string().contains("missing"), "{err}");
}
