//! What the test files share: the examples' binaries and running a command whose log must be
//! clean.

use std::path::{Path, PathBuf};
use std::process::Command;

/// An example's binary: `cargo test` builds the examples into `<target>/<profile>/examples`
/// (`CARGO_TARGET_TMPDIR` is `<target>/tmp`).
pub fn example(name: &str) -> PathBuf {
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("..");
    let profile = if cfg!(debug_assertions) {
        "debug"
    } else {
        "release"
    };
    let bin = target.join(profile).join("examples").join(name);
    assert!(
        bin.exists(),
        "{} is missing (cargo test builds it)",
        bin.display()
    );
    bin
}

/// Runs `cmd`, which must succeed without an `ERROR` line in its log (Bevy logs wgpu
/// validation errors and shader errors and draws on: a picture is not enough, the log must be
/// clean too); returns its stdout and stderr.
pub fn run(mut cmd: Command) -> (String, String) {
    let out = cmd.output().expect("the command starts");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{cmd:?} failed:\n{stdout}\n{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("ERROR")).collect();
    assert!(
        errors.is_empty(),
        "{cmd:?} logged errors:\n{}",
        errors.join("\n")
    );
    (stdout, stderr)
}

/// Writes `mesh` as `<dir>/<name>.gltf` with its buffer beside it (`<name>.bin`): positions,
/// triangles, normals only if `normals`, and with `jpeg` (a JPEG file's bytes, stored in the
/// buffer) a material whose base colour is that image, every vertex at its centre (uv 0.5,
/// 0.5). Written here, not by tessella's writer, so that Bevy's loader gets what the test says.
#[allow(dead_code)]
pub fn write_gltf(
    dir: &Path,
    name: &str,
    mesh: &tessella_core::Mesh,
    normals: bool,
    jpeg: Option<&[u8]>,
) -> PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut attributes = Vec::new();
    let n = mesh.vertex_count();
    let (lo, hi) = mesh.bounds();
    let mut add = |bin: &mut Vec<u8>, bytes: &[u8], accessor: String| {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            bytes.len()
        ));
        bin.extend_from_slice(bytes);
        accessors.push(accessor.replace("VIEW", &(views.len() - 1).to_string()));
        accessors.len() - 1
    };
    let floats = |v: &[[f32; 3]]| {
        v.iter()
            .flatten()
            .flat_map(|f| f.to_le_bytes())
            .collect::<Vec<u8>>()
    };
    let p = add(
        &mut bin,
        &floats(mesh.positions()),
        format!(
            r#"{{"bufferView":VIEW,"componentType":5126,"count":{n},"type":"VEC3","min":{lo:?},"max":{hi:?}}}"#
        ),
    );
    attributes.push(format!(r#""POSITION":{p}"#));
    if normals {
        let a = add(
            &mut bin,
            &floats(mesh.normals()),
            format!(r#"{{"bufferView":VIEW,"componentType":5126,"count":{n},"type":"VEC3"}}"#),
        );
        attributes.push(format!(r#""NORMAL":{a}"#));
    }
    if jpeg.is_some() {
        let uvs: Vec<u8> = (0..2 * n).flat_map(|_| 0.5f32.to_le_bytes()).collect();
        let a = add(
            &mut bin,
            &uvs,
            format!(r#"{{"bufferView":VIEW,"componentType":5126,"count":{n},"type":"VEC2"}}"#),
        );
        attributes.push(format!(r#""TEXCOORD_0":{a}"#));
    }
    let indices: Vec<u8> = mesh
        .triangles()
        .iter()
        .flatten()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let count = mesh.face_count() * 3;
    let i = add(
        &mut bin,
        &indices,
        format!(r#"{{"bufferView":VIEW,"componentType":5125,"count":{count},"type":"SCALAR"}}"#),
    );
    let material = match jpeg {
        Some(bytes) => {
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
                bin.len(),
                bytes.len()
            ));
            bin.extend_from_slice(bytes);
            bin.resize(bin.len().next_multiple_of(4), 0);
            format!(
                r#","material":0}}]}}],"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"metallicFactor":0}}}}],"textures":[{{"source":0}}],"images":[{{"bufferView":{},"mimeType":"image/jpeg"}}]"#,
                views.len() - 1
            )
        }
        None => "}]}]".to_string(),
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"buffers":[{{"uri":"{name}.bin","byteLength":{}}}],"bufferViews":[{}],"accessors":[{}],"meshes":[{{"primitives":[{{"attributes":{{{}}},"indices":{i}{material}}}"#,
        bin.len(),
        views.join(","),
        accessors.join(","),
        attributes.join(","),
    );
    std::fs::write(dir.join(format!("{name}.bin")), &bin).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}
