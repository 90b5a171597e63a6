//! The whole glTF round trip against refinement alone, in one run.
//!
//! A textured scene of about 100k triangles (the sample scene made finer: an icosphere of
//! 20,480 triangles in two materials, a ring of 76,800, texture, tangents, colours, a morph
//! target) is read, refined at level 4 and written as GLB bytes
//! (`Scene::from_bytes` → `refine` → `to_glb`), against the core's `refine` of the same
//! primitives' geometry (positions, normals, triangles: what `tessella refine` does to a mesh).
//! Runs alternate, the median of each is printed with their ratio.
//!
//! `cargo run --release -p tessella-io --example gltf_round_trip [-- RUNS]`
//! `-- --once round-trip|refine` runs one side once (for callgrind's instruction counts);
//! `--no-tangents` drops the TANGENT attributes first (MikkTSpace then does not run);
//! `-- --write DIR` writes the scene and its bare geometry (`DIR/scene.glb`,
//! `DIR/geometry.glb`) to time `tessella refine` on both.

use std::time::Instant;
use tessella_core::{Mesh, RefineOptions, Scheme};
use tessella_io::gltf::scene::{Scene, SceneLevels, SceneOptions};
use tessella_io::gltf::Buffers;

const LEVEL: u32 = 4;

/// The primitives' coarse meshes as `refine` would see them: positions, normals, triangles
/// (each mesh once, in its own space; zero-area triangles left out, as `refine` requires).
fn geometry(scene_bytes: &[u8]) -> Vec<Mesh> {
    let gltf = gltf::Gltf::from_slice_without_validation(scene_bytes).expect("the scene parses");
    let bin = gltf.blob.clone().expect("a GLB");
    let mut meshes = Vec::new();
    for mesh in gltf.document.meshes() {
        for primitive in mesh
            .primitives()
            .filter(|p| p.mode() == gltf::mesh::Mode::Triangles)
        {
            let reader = primitive.reader(|_| Some(&bin));
            let positions: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
            let normals: Vec<[f32; 3]> = reader.read_normals().expect("normals").collect();
            let corners: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
            let triangles = corners
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .filter(|t| !tessella_core::mesh::is_degenerate(&positions, *t))
                .collect();
            meshes.push(
                Mesh::new(positions, Some(normals), None, triangles).expect("valid geometry"),
            );
        }
    }
    meshes
}

fn round_trip(bytes: &[u8]) -> usize {
    let scene = Scene::from_bytes("scene.glb", bytes, Buffers::Given(&[])).expect("reads");
    let options = SceneOptions::new(
        RefineOptions::new(Scheme::Pn, 1),
        SceneLevels::Uniform(LEVEL),
    );
    scene
        .refine(&options)
        .expect("refines")
        .to_glb()
        .expect("writes")
        .len()
}

fn refine_alone(meshes: &[Mesh]) -> usize {
    meshes
        .iter()
        .map(|m| {
            tessella_core::refine(m, &RefineOptions::new(Scheme::Pn, LEVEL))
                .expect("refines")
                .triangles
                .len()
        })
        .sum()
}

/// The scene's GLB, without TANGENT attributes when `tangents` is false.
fn scene(tangents: bool) -> Vec<u8> {
    let bytes = tessella_io::sample_scene_detailed(false, 5, [240, 160]);
    if tangents {
        return bytes;
    }
    let glb = gltf::Glb::from_slice(&bytes).expect("a GLB");
    let mut json: serde_json::Value = serde_json::from_slice(&glb.json).expect("JSON");
    for mesh in json["meshes"].as_array_mut().expect("meshes") {
        for primitive in mesh["primitives"].as_array_mut().expect("primitives") {
            primitive["attributes"]
                .as_object_mut()
                .expect("attributes")
                .remove("TANGENT");
        }
    }
    tessella_io::gltf::scene::glb(&json, &glb.bin.expect("a buffer")).expect("a GLB")
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // With `--no-tangents` the scene's primitives carry no TANGENT (most textured assets have
    // none: tangents come with normal maps).
    let tangents = !args.iter().any(|a| a == "--no-tangents");
    let args: Vec<String> = args.into_iter().filter(|a| a != "--no-tangents").collect();
    let bytes = scene(tangents);
    let meshes = geometry(&bytes);
    let triangles: usize = meshes.iter().map(Mesh::face_count).sum();
    if args.first().map(String::as_str) == Some("--write") {
        // The two files `tessella refine` is timed on: the scene, and its geometry alone (each
        // mesh once, positions, normals and triangles, one primitive).
        let dir = std::path::Path::new(args.get(1).map_or(".", String::as_str));
        std::fs::write(dir.join("scene.glb"), &bytes).expect("write scene.glb");
        let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for mesh in &meshes {
            let base = positions.len() as u32;
            positions.extend_from_slice(mesh.positions());
            normals.extend_from_slice(mesh.normals());
            triangles.extend(mesh.triangles().iter().map(|t| t.map(|i| i + base)));
        }
        let merged = Mesh::new(positions, Some(normals), None, triangles).expect("valid");
        tessella_io::write_mesh(
            &dir.join("geometry.glb"),
            (&merged).into(),
            &Default::default(),
        )
        .expect("write geometry.glb");
        println!("{}: scene.glb and geometry.glb", dir.display());
        return;
    }
    if args.first().map(String::as_str) == Some("--once") {
        match args.get(1).map(String::as_str) {
            Some("round-trip") => println!("{} bytes", round_trip(&bytes)),
            _ => println!("{} triangles", refine_alone(&meshes)),
        }
        return;
    }
    let runs: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(7);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let mut size = 0;
    for _ in 0..runs {
        let t = Instant::now();
        size = round_trip(&bytes);
        a.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        std::hint::black_box(refine_alone(&meshes));
        b.push(t.elapsed().as_secs_f64());
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (ta, tb) = (median(&mut a), median(&mut b));
    println!(
        "scene: {} bytes, {triangles} coarse triangles, level {LEVEL}; output {size} bytes",
        bytes.len()
    );
    println!("| what | median of {runs} (ms) |");
    println!("|---|---:|");
    println!(
        "| glTF round trip (read, refine every primitive with its attributes, write GLB) | {:.1} |",
        ta * 1e3
    );
    println!(
        "| refine alone (positions, normals, triangles) | {:.1} |",
        tb * 1e3
    );
    println!("ratio round trip / refine alone: {:.2}", ta / tb);
}
