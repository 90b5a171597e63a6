//! Shared helpers for the format tests.
#![allow(dead_code)]

use tessella_io::{MeshView, RawMesh};

/// A small open mesh (a square pyramid without its base) with normals and uvs whose values do
/// not have short decimal forms, so text formats must print and parse exactly.
pub struct Sample {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub uvs: Vec<[f32; 2]>,
    pub triangles: Vec<[u32; 3]>,
}

impl Sample {
    pub fn new() -> Sample {
        let positions = vec![
            [0.1, -0.2, 0.3],
            [1.0 / 3.0, 1e-7, -2.5e6],
            [-7.25, 3.0e-30, 0.7],
            [0.0, 1.7, 0.2],
            [0.37, 0.41, 9.0],
        ];
        let normals = vec![
            [0.0, 0.0, 1.0],
            [0.6, 0.0, 0.8],
            [0.0, -0.6, 0.8],
            [(0.5f32).sqrt(), 0.0, (0.5f32).sqrt()],
            [0.267_261_24, 0.534_522_5, 0.801_783_7],
        ];
        // Binary fractions: exact through glTF's v flip (see tessella_io::gltf).
        let uvs = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [0.75, 1.0],
            [0.125, 0.5],
            [0.3125, 0.0625],
        ];
        // Vertices used in order of first appearance, so OBJ readers keep their numbering.
        let triangles = vec![[0, 1, 2], [1, 3, 2], [3, 4, 2], [4, 0, 2]];
        Sample {
            positions,
            normals,
            uvs,
            triangles,
        }
    }

    pub fn view(&self) -> MeshView<'_> {
        MeshView {
            positions: &self.positions,
            normals: Some(&self.normals),
            uvs: Some(&self.uvs),
            triangles: &self.triangles,
        }
    }
}

pub fn bits3(v: &[[f32; 3]]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.map(f32::to_bits)).collect()
}

pub fn bits2(v: &[[f32; 2]]) -> Vec<[u32; 2]> {
    v.iter().map(|p| p.map(f32::to_bits)).collect()
}

/// Asserts that `raw` holds exactly the sample's arrays, bit for bit.
pub fn assert_same(raw: &RawMesh, sample: &Sample, normals: bool, uvs: bool) {
    assert_eq!(bits3(&raw.positions), bits3(&sample.positions));
    assert_eq!(raw.triangles, sample.triangles);
    if normals {
        assert_eq!(
            bits3(raw.normals.as_ref().expect("normals read back")),
            bits3(&sample.normals)
        );
    } else {
        assert!(raw.normals.is_none());
    }
    if uvs {
        assert_eq!(
            bits2(raw.uvs.as_ref().expect("uvs read back")),
            bits2(&sample.uvs)
        );
    } else {
        assert!(raw.uvs.is_none());
    }
}

/// Files left in a folder (to catch stray temporary files).
pub fn entries(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
