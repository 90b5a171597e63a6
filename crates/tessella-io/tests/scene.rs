//! glTF scenes in and out (`tessella_io::gltf::scene`): what a refined scene keeps, what its
//! attributes hold (checked against f64 evaluations written here), which files are refused.
//! The inputs are the bundled samples (`tessella samples`), edited where a test needs a
//! broken or extended file.

use serde_json::{json, Value};
use std::path::Path;
use tessella_core::{RefineOptions, Scheme};
use tessella_io::gltf::scene::{RefinedScene, Scene, SceneLevels, SceneOptions, Tangents};
use tessella_io::gltf::Buffers;

fn sample(name: &str) -> Vec<u8> {
    std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../samples")
            .join(name),
    )
    .unwrap()
}

fn read(name: &str, bytes: &[u8]) -> Result<Scene, tessella_io::IoError> {
    Scene::from_bytes(name, bytes, Buffers::Given(&[]))
}

fn refine(bytes: &[u8], scheme: Scheme, level: u32) -> RefinedScene {
    read("in.glb", bytes)
        .unwrap()
        .refine(&SceneOptions::new(
            RefineOptions::new(scheme, 1),
            SceneLevels::Uniform(level),
        ))
        .unwrap()
}

/// A GLB's JSON and binary chunk, split by the `gltf` crate.
fn split(glb: &[u8]) -> (Value, Vec<u8>) {
    let glb = gltf::Glb::from_slice(glb).unwrap();
    (
        serde_json::from_slice(&glb.json).unwrap(),
        glb.bin.map(|b| b.into_owned()).unwrap_or_default(),
    )
}

/// A GLB from edited JSON and the same binary chunk.
fn join(json: &Value, bin: &[u8]) -> Vec<u8> {
    tessella_io::gltf::scene::glb(json, bin).unwrap()
}

/// The floats of an accessor of a file this crate wrote (plain f32, tightly packed or strided),
/// read by hand from the JSON.
fn floats(json: &Value, bin: &[u8], accessor: u64) -> (Vec<f64>, usize) {
    let a = &json["accessors"][accessor as usize];
    let width = match a["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        _ => 4,
    };
    let component = a["componentType"].as_u64().unwrap();
    let size = match component {
        5126 => 4,
        5121 => 1,
        5123 => 2,
        _ => panic!("component type {component}"),
    };
    assert!(
        component == 5126 || a["normalized"] == true,
        "floats or normalised integers"
    );
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let stride = view["byteStride"]
        .as_u64()
        .map_or(width * size, |s| s as usize);
    let count = a["count"].as_u64().unwrap() as usize;
    let mut out = Vec::with_capacity(count * width);
    for e in 0..count {
        for c in 0..width {
            let at = start + e * stride + c * size;
            out.push(match component {
                5126 => f32::from_le_bytes(bin[at..at + 4].try_into().unwrap()) as f64,
                5121 => bin[at] as f64 / 255.0,
                _ => u16::from_le_bytes(bin[at..at + 2].try_into().unwrap()) as f64 / 65535.0,
            });
        }
    }
    (out, width)
}

/// The floats of a MAT4 accessor (inverse bind matrices), tightly packed.
fn floats16(json: &Value, bin: &[u8], accessor: u64) -> Vec<f32> {
    let a = &json["accessors"][accessor as usize];
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let count = a["count"].as_u64().unwrap() as usize * 16;
    (0..count)
        .map(|i| f32::from_le_bytes(bin[start + 4 * i..start + 4 * i + 4].try_into().unwrap()))
        .collect()
}

/// Indices of an accessor of u8/u16/u32 (tightly packed).
fn indices(json: &Value, bin: &[u8], accessor: u64) -> Vec<u32> {
    let a = &json["accessors"][accessor as usize];
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let count = a["count"].as_u64().unwrap() as usize;
    (0..count)
        .map(|i| match a["componentType"].as_u64().unwrap() {
            5121 => bin[start + i] as u32,
            5123 => {
                u16::from_le_bytes(bin[start + 2 * i..start + 2 * i + 2].try_into().unwrap()) as u32
            }
            _ => u32::from_le_bytes(bin[start + 4 * i..start + 4 * i + 4].try_into().unwrap()),
        })
        .collect()
}

fn triangle_count(json: &Value, primitive: &Value) -> usize {
    match primitive.get("indices") {
        Some(i) => {
            json["accessors"][i.as_u64().unwrap() as usize]["count"]
                .as_u64()
                .unwrap() as usize
                / 3
        }
        None => {
            json["accessors"][primitive["attributes"]["POSITION"].as_u64().unwrap() as usize]
                ["count"]
                .as_u64()
                .unwrap() as usize
                / 3
        }
    }
}

const SAMPLES: [&str; 3] = ["scene.glb", "scene-quantized.glb", "animated-creature.glb"];

#[test]
fn every_part_of_the_scene_is_kept() {
    for name in SAMPLES {
        let input = sample(name);
        let refined = refine(&input, Scheme::Pn, 3);
        let output = refined.to_glb().unwrap();
        let (mut a, b) = (
            read("in.glb", &input).unwrap().counts(),
            read("out.glb", &output).unwrap().counts(),
        );
        // Quantised attributes are refined into floats: the output needs no quantisation.
        a.extensions_used.retain(|e| e != "KHR_mesh_quantization");
        assert_eq!(a, b, "{name}: the counts of what the scene holds");
        let (inj, _) = split(&input);
        let (outj, _) = split(&output);
        for key in [
            "nodes",
            "materials",
            "textures",
            "samplers",
            "cameras",
            "scenes",
        ] {
            assert_eq!(
                inj.get(key),
                outj.get(key),
                "{name}: {key} are copied as they were"
            );
        }
        // Skins keep their joints; their inverse bind matrices keep their values under a new
        // accessor index.
        let (inb, outb) = (split(&input).1, split(&output).1);
        for (x, y) in inj["skins"]
            .as_array()
            .into_iter()
            .flatten()
            .zip(outj["skins"].as_array().into_iter().flatten())
        {
            let (mut x, mut y) = (x.clone(), y.clone());
            let ibm = |j: &Value, b: &[u8], i: &Value| floats16(j, b, i.as_u64().unwrap());
            assert_eq!(
                ibm(&inj, &inb, &x["inverseBindMatrices"]),
                ibm(&outj, &outb, &y["inverseBindMatrices"])
            );
            x.as_object_mut().unwrap().remove("inverseBindMatrices");
            y.as_object_mut().unwrap().remove("inverseBindMatrices");
            assert_eq!(x, y, "{name}: skins");
        }
        assert_eq!(
            inj.get("extensions"),
            outj.get("extensions"),
            "{name}: root extensions (lights)"
        );
        // Animations keep their channels; their samplers' accessors are renumbered.
        for (x, y) in inj["animations"]
            .as_array()
            .unwrap()
            .iter()
            .zip(outj["animations"].as_array().unwrap())
        {
            assert_eq!(x["channels"], y["channels"]);
            assert_eq!(x["name"], y["name"]);
        }
        for (m, (mi, mo)) in inj["meshes"]
            .as_array()
            .unwrap()
            .iter()
            .zip(outj["meshes"].as_array().unwrap())
            .enumerate()
        {
            assert_eq!(mi.get("weights"), mo.get("weights"));
            assert_eq!(mi.get("extras"), mo.get("extras"));
            for (p, (pi, po)) in mi["primitives"]
                .as_array()
                .unwrap()
                .iter()
                .zip(mo["primitives"].as_array().unwrap())
                .enumerate()
            {
                assert_eq!(
                    pi.get("material"),
                    po.get("material"),
                    "{name} mesh {m} primitive {p}: material"
                );
                let names = |p: &Value| {
                    p["attributes"]
                        .as_object()
                        .unwrap()
                        .keys()
                        .cloned()
                        .collect::<std::collections::BTreeSet<_>>()
                };
                let mut expected = names(pi);
                let mode = pi.get("mode").and_then(Value::as_u64).unwrap_or(4);
                if mode >= 4 {
                    expected.insert("NORMAL".into());
                }
                assert_eq!(
                    names(po),
                    expected,
                    "{name} mesh {m} primitive {p}: attribute sets"
                );
                let targets = |p: &Value| {
                    p.get("targets")
                        .and_then(Value::as_array)
                        .map_or(0, Vec::len)
                };
                assert_eq!(
                    targets(pi),
                    targets(po),
                    "{name} mesh {m} primitive {p}: morph targets"
                );
                let (ti, to) = (triangle_count(&inj, pi), triangle_count(&outj, po));
                if mode >= 4 {
                    assert_eq!(
                        to,
                        9 * ti,
                        "{name} mesh {m} primitive {p}: level² times the triangles"
                    );
                } else {
                    assert_eq!(
                        pi.get("mode"),
                        po.get("mode"),
                        "points and lines stay what they are"
                    );
                }
            }
        }
    }
}

#[test]
fn points_lines_and_images_keep_their_bytes() {
    let input = sample("scene.glb");
    let (inj, inb) = split(&input);
    let (outj, outb) = split(&refine(&input, Scheme::Pn, 2).to_glb().unwrap());
    for p in 0..2 {
        let a = floats(
            &inj,
            &inb,
            inj["meshes"][2]["primitives"][p]["attributes"]["POSITION"]
                .as_u64()
                .unwrap(),
        );
        let b = floats(
            &outj,
            &outb,
            outj["meshes"][2]["primitives"][p]["attributes"]["POSITION"]
                .as_u64()
                .unwrap(),
        );
        assert_eq!(a, b);
    }
    let image = |json: &Value, bin: &[u8]| {
        let view = &json["bufferViews"][json["images"][0]["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        bin[start..start + view["byteLength"].as_u64().unwrap() as usize].to_vec()
    };
    assert_eq!(image(&inj, &inb), image(&outj, &outb), "the embedded PNG");
}

/// Barycentric coordinates of `p` in triangle `t` (f64, by least squares in the plane), or
/// `None` when it lies outside.
fn barycentric(p: [f64; 3], t: [[f64; 3]; 3]) -> Option<[f64; 3]> {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e1, e2, d) = (sub(t[1], t[0]), sub(t[2], t[0]), sub(p, t[0]));
    let (a, b, c) = (dot(e1, e1), dot(e1, e2), dot(e2, e2));
    let det = a * c - b * b;
    if det.abs() < 1e-20 {
        return None;
    }
    let (r, s) = (dot(d, e1), dot(d, e2));
    let l1 = (c * r - b * s) / det;
    let l2 = (a * s - b * r) / det;
    let l = [1.0 - l1 - l2, l1, l2];
    let off = sub(
        p,
        [0, 1, 2].map(|k| t[0][k] * l[0] + t[1][k] * l[1] + t[2][k] * l[2]),
    );
    (l.iter().all(|&x| x > -1e-5) && dot(off, off) < 1e-12).then_some(l)
}

/// With flat refinement a refined vertex lies where its barycentric weights put it on its
/// coarse triangle, so those weights can be found from the position alone: every other
/// attribute must then be the corners' values blended with them (f64 here).
#[test]
fn attributes_at_refined_vertices_are_the_corners_blended() {
    let input = sample("scene.glb");
    let (inj, inb) = split(&input);
    let (outj, outb) = split(&refine(&input, Scheme::Flat, 4).to_glb().unwrap());
    let mut checked = 0;
    for p in 0..2 {
        let pi = &inj["meshes"][0]["primitives"][p];
        let po = &outj["meshes"][0]["primitives"][p];
        let (pos, _) = floats(&inj, &inb, pi["attributes"]["POSITION"].as_u64().unwrap());
        let tris = indices(&inj, &inb, pi["indices"].as_u64().unwrap());
        let (out_pos, _) = floats(&outj, &outb, po["attributes"]["POSITION"].as_u64().unwrap());
        for name in ["TEXCOORD_0", "TEXCOORD_1", "COLOR_0"] {
            let (coarse, w) = floats(
                &inj,
                &inb,
                pi["attributes"][name]
                    .as_u64()
                    .unwrap_or_else(|| panic!("{name}")),
            );
            let (refined, w2) = floats(&outj, &outb, po["attributes"][name].as_u64().unwrap());
            assert_eq!(w, w2);
            for v in 0..out_pos.len() / 3 {
                let at = [out_pos[v * 3], out_pos[v * 3 + 1], out_pos[v * 3 + 2]];
                let corner = |i: u32| {
                    [
                        pos[i as usize * 3],
                        pos[i as usize * 3 + 1],
                        pos[i as usize * 3 + 2],
                    ]
                };
                // Any coarse triangle that holds the vertex and whose blend matches it: texture
                // seams give one position two texture coordinates.
                let matches = tris.chunks_exact(3).any(|t| {
                    let Some(l) = barycentric(at, [corner(t[0]), corner(t[1]), corner(t[2])])
                    else {
                        return false;
                    };
                    (0..w).all(|c| {
                        let want: f64 = (0..3).map(|k| l[k] * coarse[t[k] as usize * w + c]).sum();
                        (refined[v * w + c] - want).abs() < 2e-6
                    })
                });
                assert!(
                    matches,
                    "mesh 0 primitive {p} {name}: vertex {v} is no blend of its corners"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

#[test]
fn degenerate_triangles_are_refined_flat_without_nan() {
    let input = sample("scene.glb");
    let refined = refine(&input, Scheme::Pn, 4);
    let lower = refined.which.iter().position(|&w| w == (0, 1)).unwrap();
    assert_eq!(
        refined.primitives[lower].degenerate, 2,
        "a repeated corner and a collinear triangle"
    );
    let (outj, outb) = split(&refined.to_glb().unwrap());
    let po = &outj["meshes"][0]["primitives"][1];
    let (pos, _) = floats(&outj, &outb, po["attributes"]["POSITION"].as_u64().unwrap());
    let (nor, _) = floats(&outj, &outb, po["attributes"]["NORMAL"].as_u64().unwrap());
    assert!(pos.iter().chain(&nor).all(|x| x.is_finite()));
    // The last two flat patterns (15 points each at level 4) lie on a segment: every point is
    // collinear with the patch's first and last points.
    let n = pos.len() / 3;
    for patch in 0..2 {
        let first = n - (2 - patch) * 15;
        let p = |i: usize| [pos[i * 3], pos[i * 3 + 1], pos[i * 3 + 2]];
        let (a, b) = (p(first), p(first + 4));
        for i in first..first + 15 {
            let (u, v) = (
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [p(i)[0] - a[0], p(i)[1] - a[1], p(i)[2] - a[2]],
            );
            let cross = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            assert!(
                cross.iter().all(|c| c.abs() < 1e-6),
                "patch {patch} point {i} leaves its segment"
            );
        }
    }
}

#[test]
fn quantized_attributes_read_as_the_floats_they_stand_for() {
    let (fj, fb) = split(
        &refine(&sample("scene.glb"), Scheme::Pn, 2)
            .to_glb()
            .unwrap(),
    );
    let (qj, qb) = split(
        &refine(&sample("scene-quantized.glb"), Scheme::Pn, 2)
            .to_glb()
            .unwrap(),
    );
    for (m, p) in [(0, 0), (0, 1), (1, 0)] {
        for (name, tolerance) in [("POSITION", 1e-3), ("TEXCOORD_0", 1e-4)] {
            let f = floats(
                &fj,
                &fb,
                fj["meshes"][m]["primitives"][p]["attributes"][name]
                    .as_u64()
                    .unwrap(),
            )
            .0;
            let q = floats(
                &qj,
                &qb,
                qj["meshes"][m]["primitives"][p]["attributes"][name]
                    .as_u64()
                    .unwrap(),
            )
            .0;
            assert_eq!(f.len(), q.len());
            let worst = f
                .iter()
                .zip(&q)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst < tolerance, "mesh {m} primitive {p} {name}: {worst}");
        }
    }
    assert!(
        !qj.to_string().contains("KHR_mesh_quantization"),
        "every quantised primitive was refined into floats"
    );
}

#[test]
fn morph_targets_refine_the_targets_shape() {
    let input = sample("scene.glb");
    let (inj, inb) = split(&input);
    // Flat: the refined delta is the corners' deltas blended (the target's shape is flat too).
    let (outj, outb) = split(&refine(&input, Scheme::Flat, 3).to_glb().unwrap());
    let pi = &inj["meshes"][0]["primitives"][0];
    let po = &outj["meshes"][0]["primitives"][0];
    let (delta, _) = floats(&inj, &inb, pi["targets"][0]["POSITION"].as_u64().unwrap());
    let (pos, _) = floats(&inj, &inb, pi["attributes"]["POSITION"].as_u64().unwrap());
    let tris = indices(&inj, &inb, pi["indices"].as_u64().unwrap());
    let (out_pos, _) = floats(&outj, &outb, po["attributes"]["POSITION"].as_u64().unwrap());
    let (out_delta, _) = floats(&outj, &outb, po["targets"][0]["POSITION"].as_u64().unwrap());
    for v in 0..out_pos.len() / 3 {
        let at = [out_pos[v * 3], out_pos[v * 3 + 1], out_pos[v * 3 + 2]];
        let corner = |i: u32| {
            [
                pos[i as usize * 3],
                pos[i as usize * 3 + 1],
                pos[i as usize * 3 + 2],
            ]
        };
        let ok = tris.chunks_exact(3).any(|t| {
            barycentric(at, [corner(t[0]), corner(t[1]), corner(t[2])]).is_some_and(|l| {
                (0..3).all(|c| {
                    let want: f64 = (0..3).map(|k| l[k] * delta[t[k] as usize * 3 + c]).sum();
                    (out_delta[v * 3 + c] - want).abs() < 1e-6
                })
            })
        });
        assert!(
            ok,
            "vertex {v}: the flat target's delta is not the corners' blend"
        );
    }
    // PN: base + delta is the PN refinement of the target's coarse shape, evaluated here
    // with the core's one-shot `refine` of that shape.
    let (outj, outb) = split(&refine(&input, Scheme::Pn, 3).to_glb().unwrap());
    let po = &outj["meshes"][0]["primitives"][0];
    let (out_pos, _) = floats(&outj, &outb, po["attributes"]["POSITION"].as_u64().unwrap());
    let (out_delta, _) = floats(&outj, &outb, po["targets"][0]["POSITION"].as_u64().unwrap());
    let (normals, _) = floats(&inj, &inb, pi["attributes"]["NORMAL"].as_u64().unwrap());
    let v3 = |a: &[f64]| {
        a.chunks_exact(3)
            .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
            .collect::<Vec<_>>()
    };
    let moved: Vec<f64> = pos
        .iter()
        .zip(&delta)
        .map(|(p, d)| (*p as f32 + *d as f32) as f64)
        .collect();
    let triangles: Vec<[u32; 3]> = tris.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let shape = tessella_core::Mesh::new(v3(&moved), Some(v3(&normals)), None, triangles).unwrap();
    let expected = tessella_core::refine(&shape, &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let worst = expected
        .positions
        .iter()
        .enumerate()
        .map(|(v, e)| {
            (0..3)
                .map(|c| (out_pos[v * 3 + c] + out_delta[v * 3 + c] - e[c] as f64).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-6,
        "base + refined delta is {worst} from the refined target"
    );
}

#[test]
fn skin_influences_are_blended_and_pose_near_pose_then_refine() {
    let input = sample("animated-creature.glb");
    let level = 4;
    let refined = refine(&input, Scheme::Pn, level);
    let output = refined.to_glb().unwrap();
    let (outj, outb) = split(&output);
    let po = &outj["meshes"][0]["primitives"][0];
    let (w0, _) = floats(
        &outj,
        &outb,
        po["attributes"]["WEIGHTS_0"].as_u64().unwrap(),
    );
    let (w1, _) = floats(
        &outj,
        &outb,
        po["attributes"]["WEIGHTS_1"].as_u64().unwrap(),
    );
    for v in 0..w0.len() / 4 {
        let sum: f64 = w0[v * 4..v * 4 + 4]
            .iter()
            .chain(&w1[v * 4..v * 4 + 4])
            .sum();
        assert!((sum - 1.0).abs() < 1e-5, "vertex {v}: weights sum to {sum}");
        let sorted = w0[v * 4..v * 4 + 4]
            .iter()
            .chain(&w1[v * 4..v * 4 + 4])
            .collect::<Vec<_>>();
        assert!(sorted.windows(2).all(|p| p[0] >= p[1]), "strongest first");
    }
    // Posed by the skin (refined weights), against posed then refined (what `refine --clip`
    // does), both with the core's glTF poser.
    use tessella_core::animation::Poser;
    let diagonal = {
        let mesh = Poser::new(tessella_io::read_animated_bytes("in.glb", &input, &[]).unwrap())
            .unwrap()
            .mesh(None, 0.0)
            .unwrap();
        let (lo, hi) = tessella_core::mesh::bounds(mesh.positions());
        ((0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>() as f64).sqrt()
    };
    let ours =
        Poser::new(tessella_io::read_animated_bytes("out.glb", &output, &[]).unwrap()).unwrap();
    let theirs =
        Poser::new(tessella_io::read_animated_bytes("in.glb", &input, &[]).unwrap()).unwrap();
    for (clip, time) in [("wave", 0.5), ("hop", 0.3), ("breathe", 1.2)] {
        let (c1, c2) = (
            ours.clip_index(clip).unwrap(),
            theirs.clip_index(clip).unwrap(),
        );
        let posed = ours.mesh(Some(c1), time).unwrap();
        let coarse = theirs.mesh(Some(c2), time).unwrap();
        let reference =
            tessella_core::refine(&coarse, &RefineOptions::new(Scheme::Pn, level)).unwrap();
        assert_eq!(posed.vertex_count(), reference.positions.len());
        let worst = posed
            .positions()
            .iter()
            .zip(&reference.positions)
            .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f32>().sqrt() as f64)
            .fold(0.0, f64::max);
        eprintln!("{clip} at {time}s: refined-then-skinned is {:.4}% of the diagonal from posed-then-refined", 100.0 * worst / diagonal);
        assert!(worst / diagonal < 0.03, "{clip}: {worst} of {diagonal}");
    }
}

#[test]
fn max_edge_gives_each_mesh_the_level_its_world_size_needs() {
    let scene = read("in.glb", &sample("scene.glb")).unwrap();
    let coarse = scene.levels(&SceneLevels::MaxEdge(0.1)).unwrap();
    let fine = scene.levels(&SceneLevels::MaxEdge(0.025)).unwrap();
    for ((k, a), (_, b)) in coarse.iter().zip(&fine) {
        assert!(*b >= 3 * a && *b <= 4 * a + 1, "{k:?}: {a} then {b}");
    }
    // The ball (radius 1) and the ring (tube 0.26) have different edge lengths: their levels differ.
    let ball = coarse.iter().find(|(k, _)| *k == (0, 0)).unwrap().1;
    let ring = coarse.iter().find(|(k, _)| *k == (1, 0)).unwrap().1;
    assert_ne!(ball, ring);
    // A mesh shown only scaled down gets a lower level.
    let (mut json, bin) = split(&sample("scene.glb"));
    json["nodes"][2]["scale"] = json!([0.25, 0.25, 0.25]);
    let small = read("in.glb", &join(&json, &bin))
        .unwrap()
        .levels(&SceneLevels::MaxEdge(0.1))
        .unwrap();
    let small_ring = small.iter().find(|(k, _)| *k == (1, 0)).unwrap().1;
    assert!(small_ring < ring, "{small_ring} < {ring}");
    assert!(scene.levels(&SceneLevels::MaxEdge(0.0)).is_err());
    assert!(scene.levels(&SceneLevels::MaxEdge(f32::NAN)).is_err());
}

fn refused(json: &Value, bin: &[u8]) -> String {
    match read("in.glb", &join(json, bin)) {
        Ok(scene) => match scene.refine(&SceneOptions::new(
            RefineOptions::new(Scheme::Pn, 1),
            SceneLevels::Uniform(2),
        )) {
            Ok(_) => "accepted".into(),
            Err(e) => e.to_string(),
        },
        Err(e) => e.to_string(),
    }
}

#[test]
fn required_extensions_are_accepted_or_refused_by_name() {
    let (json, bin) = split(&sample("scene.glb"));
    for accepted in [
        "KHR_lights_punctual",
        "KHR_materials_clearcoat",
        "EXT_texture_webp",
        "KHR_texture_basisu",
        "EXT_mesh_gpu_instancing",
    ] {
        let mut edited = json.clone();
        edited["extensionsRequired"]
            .as_array_mut()
            .unwrap()
            .push(accepted.into());
        let scene =
            read("in.glb", &join(&edited, &bin)).unwrap_or_else(|e| panic!("{accepted}: {e}"));
        let out = scene
            .refine(&SceneOptions::new(
                RefineOptions::new(Scheme::Pn, 1),
                SceneLevels::Uniform(2),
            ))
            .unwrap();
        let (outj, _) = split(&out.to_glb().unwrap());
        assert!(
            outj["extensionsRequired"]
                .as_array()
                .unwrap()
                .contains(&accepted.into()),
            "{accepted} kept"
        );
    }
    let mut unknown = json.clone();
    unknown["extensionsRequired"]
        .as_array_mut()
        .unwrap()
        .push("VENDOR_secret_sauce".into());
    let message = refused(&unknown, &bin);
    assert!(message.contains("VENDOR_secret_sauce"), "{message}");
    let mut draco = json.clone();
    draco["extensionsRequired"]
        .as_array_mut()
        .unwrap()
        .push("KHR_draco_mesh_compression".into());
    let message = refused(&draco, &bin);
    assert!(
        message.contains("KHR_draco_mesh_compression") && message.contains("gltf-transform"),
        "{message}"
    );
}

/// A change that breaks a file.
type Edit = Box<dyn Fn(&mut Value)>;

#[test]
fn broken_files_are_refused_with_the_part_named() {
    let (json, bin) = split(&sample("scene.glb"));
    let index = json["meshes"][0]["primitives"][0]["indices"]
        .as_u64()
        .unwrap() as usize;
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "an accessor overrunning its view",
            Box::new(move |j: &mut Value| j["accessors"][index]["count"] = json!(1_000_000)),
            "past the end",
        ),
        (
            "an index past the vertices",
            Box::new(|j: &mut Value| {
                let a = j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
                    .as_u64()
                    .unwrap() as usize;
                j["accessors"][a]["count"] = json!(3);
            }),
            "vertex",
        ),
        (
            "an attribute naming a missing accessor",
            Box::new(|j: &mut Value| {
                j["meshes"][1]["primitives"][0]["attributes"]["NORMAL"] = json!(9999)
            }),
            "accessor 9999",
        ),
        (
            "a view past its buffer",
            Box::new(|j: &mut Value| j["bufferViews"][0]["byteLength"] = json!(100_000_000)),
            "bufferView",
        ),
        (
            "a skin with a missing joint",
            Box::new(|j: &mut Value| j["skins"] = json!([{ "joints": [42] }])),
            "skins",
        ),
        (
            "an animation of a missing node",
            Box::new(|j: &mut Value| {
                j["animations"][0]["channels"][0]["target"]["node"] = json!(77)
            }),
            "targets node 77",
        ),
    ];
    let more: Vec<(&str, Edit, &str)> = vec![
        (
            "unequal morph targets",
            Box::new(|j: &mut Value| {
                j["meshes"][0]["primitives"][1]
                    .as_object_mut()
                    .unwrap()
                    .remove("targets");
            }),
            "primitive 1 has 0 morph targets but primitive 0 has 1",
        ),
        (
            "too many weights",
            Box::new(|j: &mut Value| j["meshes"][0]["weights"] = json!([0.0, 0.0])),
            "2 weights for 1 morph targets",
        ),
        (
            "a stride not a multiple of 4",
            Box::new(|j: &mut Value| j["bufferViews"][0]["byteStride"] = json!(6)),
            "byteStride is 6",
        ),
        (
            "normalised floats",
            Box::new(|j: &mut Value| j["accessors"][0]["normalized"] = json!(true)),
            "normalized with component type 5126",
        ),
        (
            "a skin without joints",
            Box::new(|j: &mut Value| j["skins"] = json!([{ "joints": [] }])),
            "no joints",
        ),
        (
            "too few inverse bind matrices",
            Box::new(|j: &mut Value| {
                j["skins"] = json!([{ "joints": [0, 1], "inverseBindMatrices": 0 }])
            }),
            "inverseBindMatrices",
        ),
    ];
    for (what, edit, expected) in cases.into_iter().chain(more) {
        let mut broken = json.clone();
        edit(&mut broken);
        let message = refused(&broken, &bin);
        assert!(
            message.contains(expected) && message != "accepted",
            "{what}: {message}"
        );
    }
    for cut in [0, 11, 20, 200, 2000] {
        let bytes = sample("scene.glb");
        assert!(read("in.glb", &bytes[..cut]).is_err(), "cut at {cut}");
    }
}

#[test]
fn gltf_output_writes_its_bin_and_copies_external_images() {
    let dir = tempfile::tempdir().unwrap();
    let (mut json, bin) = split(&sample("scene.glb"));
    // The texture as a file beside the input, named by a relative URI with a space.
    let view = &json["bufferViews"][json["images"][0]["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap() as usize;
    let png = bin[start..start + view["byteLength"].as_u64().unwrap() as usize].to_vec();
    std::fs::create_dir_all(dir.path().join("in/tex")).unwrap();
    std::fs::write(dir.path().join("in/tex/check er.png"), &png).unwrap();
    json["images"][0] = json!({ "uri": "tex/check%20er.png" });
    json["images"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "uri": "missing.png" }));
    std::fs::write(dir.path().join("in/scene.glb"), join(&json, &bin)).unwrap();
    let scene = Scene::read(&dir.path().join("in/scene.glb")).unwrap();
    let refined = scene
        .refine(&SceneOptions::new(
            RefineOptions::new(Scheme::Pn, 1),
            SceneLevels::Uniform(2),
        ))
        .unwrap();
    std::fs::create_dir_all(dir.path().join("out")).unwrap();
    let out = dir.path().join("out/refined scene.gltf");
    let warnings = refined
        .write(&out, tessella_io::Durability::Synced)
        .unwrap();
    assert!(
        warnings.len() == 1 && warnings[0].contains("missing.png"),
        "{warnings:?}"
    );
    assert_eq!(
        std::fs::read(dir.path().join("out/tex/check er.png")).unwrap(),
        png
    );
    assert!(dir.path().join("out/refined scene.bin").is_file());
    let text: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(text["buffers"][0]["uri"], "refined%20scene.bin");
    let back = Scene::read(&out).unwrap();
    assert_eq!(back.counts(), scene.counts());
}

/// Both tangent modes give unit tangents orthogonal to the refined normals with a ±1
/// handedness, and agree closely on the smooth sample away from its texture seam (the angles
/// between them are printed).
#[test]
fn tangents_recomputed_and_carried_are_frames_of_the_refined_normals() {
    let input = sample("scene.glb");
    let scene = read("in.glb", &input).unwrap();
    let options = SceneOptions::new(RefineOptions::new(Scheme::Pn, 1), SceneLevels::Uniform(4));
    let get = |tangents: Tangents| {
        let refined = scene
            .refine(&options.clone().with_tangents(tangents))
            .unwrap();
        let (j, b) = split(&refined.to_glb().unwrap());
        let p = &j["meshes"][1]["primitives"][0];
        let t = floats(&j, &b, p["attributes"]["TANGENT"].as_u64().unwrap()).0;
        let n = floats(&j, &b, p["attributes"]["NORMAL"].as_u64().unwrap()).0;
        (t, n)
    };
    let (recomputed, normals) = get(Tangents::Recomputed);
    let (carried, normals2) = get(Tangents::Carried);
    assert_eq!(
        normals, normals2,
        "the surface does not depend on the tangent mode"
    );
    let mut angles = Vec::new();
    for v in 0..normals.len() / 3 {
        let n = &normals[v * 3..v * 3 + 3];
        for t in [&recomputed[v * 4..v * 4 + 4], &carried[v * 4..v * 4 + 4]] {
            let len = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-4, "vertex {v}: tangent length {len}");
            let dot = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
            assert!(dot.abs() < 1e-4, "vertex {v}: tangent . normal = {dot}");
            assert!(t[3] == 1.0 || t[3] == -1.0);
        }
        let (a, b) = (&recomputed[v * 4..v * 4 + 3], &carried[v * 4..v * 4 + 3]);
        let cos = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).clamp(-1.0, 1.0);
        angles.push(cos.acos().to_degrees());
    }
    angles.sort_by(f64::total_cmp);
    let mean = angles.iter().sum::<f64>() / angles.len() as f64;
    let p95 = angles[angles.len() * 95 / 100];
    eprintln!("ring, PN level 4: recomputed against carried tangents: mean {mean:.2}°, 95th percentile {p95:.2}°, max {:.2}°", angles.last().unwrap());
    // The ring's texture coordinates wrap at one seam (u jumps from 1 to 0), where MikkTSpace
    // turns the tangent around; elsewhere the two agree within a few degrees.
    assert!(p95 < 5.0, "95th percentile {p95}");
}

/// A VEC4 integer accessor (joints: u8 or u16, tightly packed or strided).
fn ints4(json: &Value, bin: &[u8], accessor: u64) -> Vec<u32> {
    let a = &json["accessors"][accessor as usize];
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let size = if a["componentType"] == 5121 { 1 } else { 2 };
    let stride = view["byteStride"].as_u64().map_or(4 * size, |s| s as usize);
    let count = a["count"].as_u64().unwrap() as usize;
    (0..count * 4)
        .map(|i| {
            let at = start + (i / 4) * stride + (i % 4) * size;
            if size == 1 {
                bin[at] as u32
            } else {
                u16::from_le_bytes([bin[at], bin[at + 1]]) as u32
            }
        })
        .collect()
}

/// Every skin influence of a primitive, per vertex: joint to weight, summed over all sets.
fn influences(
    json: &Value,
    bin: &[u8],
    primitive: &Value,
) -> Vec<std::collections::BTreeMap<u32, f64>> {
    let a = &primitive["attributes"];
    let mut out: Vec<std::collections::BTreeMap<u32, f64>> = Vec::new();
    for set in 0.. {
        let (Some(j), Some(w)) = (
            a[format!("JOINTS_{set}")].as_u64(),
            a[format!("WEIGHTS_{set}")].as_u64(),
        ) else {
            break;
        };
        let (joints, weights) = (ints4(json, bin, j), floats(json, bin, w).0);
        out.resize(joints.len() / 4, Default::default());
        for (i, (&j, &w)) in joints.iter().zip(&weights).enumerate() {
            if w > 0.0 {
                *out[i / 4].entry(j).or_default() += w;
            }
        }
    }
    out
}

/// With more sets allowed (`JointSets::UpTo`), a refined vertex keeps every influence of its
/// corners: flat refinement puts a vertex where its barycentric weights say, and its weight for
/// each joint is then the corners' weights for that joint blended with them (f64 here). With the
/// input's one set, the weakest are dropped; the weight lost is printed. The input is the
/// creature with one set of four influences per vertex, joints `i..i + 4` (mod its 7) at
/// vertex `i`, so neighbours' blends need more than four.
#[test]
fn more_joint_sets_keep_every_blended_influence() {
    use tessella_io::gltf::scene::JointSets;
    let (mut inj, mut inb) = split(&sample("animated-creature.glb"));
    let attributes = inj["meshes"][0]["primitives"][0]["attributes"]
        .as_object_mut()
        .unwrap();
    attributes.remove("JOINTS_1");
    attributes.remove("WEIGHTS_1");
    let at = |name: &str| {
        let a = &inj["accessors"][inj["meshes"][0]["primitives"][0]["attributes"][name]
            .as_u64()
            .unwrap() as usize];
        assert!(a["byteOffset"].is_null() && (name != "JOINTS_0" || a["componentType"] == 5123));
        inj["bufferViews"][a["bufferView"].as_u64().unwrap() as usize]["byteOffset"]
            .as_u64()
            .unwrap() as usize
    };
    let (joints_at, weights_at) = (at("JOINTS_0"), at("WEIGHTS_0"));
    for v in 0..162 {
        for c in 0..4 {
            let j = ((v + c) % 7) as u16;
            let w = [0.4f32, 0.3, 0.2, 0.1][c];
            inb[joints_at + (v * 4 + c) * 2..][..2].copy_from_slice(&j.to_le_bytes());
            inb[weights_at + (v * 4 + c) * 4..][..4].copy_from_slice(&w.to_le_bytes());
        }
    }
    let input = join(&inj, &inb);
    let pi = &inj["meshes"][0]["primitives"][0];
    let (pos, _) = floats(&inj, &inb, pi["attributes"]["POSITION"].as_u64().unwrap());
    let tris = indices(&inj, &inb, pi["indices"].as_u64().unwrap());
    let coarse = influences(&inj, &inb, pi);
    let scene = read("in.glb", &input).unwrap();
    let options = SceneOptions::new(RefineOptions::new(Scheme::Flat, 1), SceneLevels::Uniform(3));
    let run = |sets: JointSets| {
        let (j, b) = split(
            &scene
                .refine(&options.clone().with_joint_sets(sets))
                .unwrap()
                .to_glb()
                .unwrap(),
        );
        let p = j["meshes"][0]["primitives"][0].clone();
        let (out_pos, _) = floats(&j, &b, p["attributes"]["POSITION"].as_u64().unwrap());
        let count = (0..)
            .take_while(|s| p["attributes"][format!("JOINTS_{s}")].is_u64())
            .count();
        (influences(&j, &b, &p), out_pos, count)
    };
    let (wide, out_pos, wide_sets) = run(JointSets::UpTo(8));
    let (kept, _, kept_sets) = run(JointSets::AsInput);
    assert_eq!(kept_sets, 1, "the input has one set");
    assert!(
        wide_sets > 1,
        "some refined vertex has more than four influences ({wide_sets} sets)"
    );
    let corner = |i: u32| [0, 1, 2].map(|k| pos[i as usize * 3 + k]);
    let mut lost: f64 = 0.0;
    for v in 0..out_pos.len() / 3 {
        let at = [0, 1, 2].map(|k| out_pos[v * 3 + k]);
        let blends = tris.chunks_exact(3).any(|t| {
            let Some(l) = barycentric(at, [corner(t[0]), corner(t[1]), corner(t[2])]) else {
                return false;
            };
            let mut want = std::collections::BTreeMap::<u32, f64>::new();
            for k in 0..3 {
                for (&j, &w) in &coarse[t[k] as usize] {
                    *want.entry(j).or_default() += l[k] * w;
                }
            }
            let total: f64 = want.values().sum();
            want.retain(|_, w| *w / total > 1e-7);
            want.len() == wide[v].len()
                && want
                    .iter()
                    .all(|(j, w)| wide[v].get(j).is_some_and(|g| (g - w / total).abs() < 2e-6))
        });
        assert!(
            blends,
            "vertex {v}: {:?} is not its corners' influences blended",
            wide[v]
        );
        lost = lost.max(
            wide[v]
                .iter()
                .filter(|(j, _)| !kept[v].contains_key(j))
                .map(|(_, w)| w)
                .sum(),
        );
    }
    eprintln!("creature, flat level 3: {wide_sets} sets hold every influence; one set drops at most {:.2}% of a vertex's weight", 100.0 * lost);
    assert!(
        lost > 0.0,
        "one set drops something, or the test shows nothing"
    );
}

/// Where accessor `a`'s first element starts in the binary chunk.
fn data_at(json: &Value, a: u64) -> usize {
    let a = &json["accessors"][a as usize];
    let view = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    (view["byteOffset"].as_u64().unwrap_or(0) + a["byteOffset"].as_u64().unwrap_or(0)) as usize
}

/// Broken data that the structure does not show is refused with a message naming the part,
/// before anything is refined: the failures the Khronos validator's corpus holds for joints,
/// weights, indices, floats, animation times, views and GLB chunks.
#[test]
fn broken_values_and_containers_are_refused_naming_the_part() {
    let creature = sample("animated-creature.glb");
    let (cj, cb) = split(&creature);
    let attribute = |name: &str| {
        cj["meshes"][0]["primitives"][0]["attributes"][name]
            .as_u64()
            .unwrap()
    };
    let edit = |at: usize, bytes: &[u8]| {
        let mut b = cb.clone();
        b[at..at + bytes.len()].copy_from_slice(bytes);
        refused(&cj, &b)
    };
    let m = edit(data_at(&cj, attribute("JOINTS_0")), &9u16.to_le_bytes());
    assert!(
        m.contains("mesh 0 primitive 0: JOINTS_0 names joint 9, but skin 0"),
        "{m}"
    );
    let m = edit(
        data_at(&cj, attribute("WEIGHTS_0")),
        &(-0.5f32).to_le_bytes(),
    );
    assert!(
        m.contains("mesh 0 primitive 0: WEIGHTS_0 holds the negative weight -0.5"),
        "{m}"
    );
    let input = cj["animations"][0]["samplers"][0]["input"]
        .as_u64()
        .unwrap();
    let first = f32::from_le_bytes(cb[data_at(&cj, input)..][..4].try_into().unwrap());
    let m = edit(data_at(&cj, input) + 4, &first.to_le_bytes());
    assert!(m.contains("animation 0 sampler 0: its times"), "{m}");
    assert!(m.contains("strictly increase"), "{m}");

    let (sj, sb) = split(&sample("scene.glb"));
    let p = &sj["meshes"][0]["primitives"][0];
    let mut b = sb.clone();
    let uv = data_at(&sj, p["attributes"]["TEXCOORD_0"].as_u64().unwrap());
    b[uv..uv + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let m = refused(&sj, &b);
    assert!(
        m.contains("holds NaN") && m.contains("glTF floats are finite"),
        "{m}"
    );
    let indices = p["indices"].as_u64().unwrap();
    let restart: &[u8] = match sj["accessors"][indices as usize]["componentType"].as_u64() {
        Some(5123) => &[0xff, 0xff],
        Some(5121) => &[0xff],
        _ => &[0xff; 4],
    };
    let mut b = sb.clone();
    let at = data_at(&sj, indices);
    b[at..at + restart.len()].copy_from_slice(restart);
    let m = refused(&sj, &b);
    assert!(
        m.contains("mesh 0 primitive 0: index") && m.contains("primitive-restart"),
        "{m}"
    );

    let view = sj["accessors"][indices as usize]["bufferView"]
        .as_u64()
        .unwrap() as usize;
    let mut j = sj.clone();
    j["bufferViews"][view]["byteLength"] = json!(sb.len() * 2);
    let m = refused(&j, &sb);
    assert!(
        m.contains(&format!(
            "bufferView {view} reaches past the end of buffer 0"
        )),
        "{m}"
    );
    let mut j = sj.clone();
    j["bufferViews"][view]["target"] = json!(34963);
    j["bufferViews"][view]["byteStride"] = json!(4);
    let m = refused(&j, &sb);
    assert!(m.contains("index views are tightly packed"), "{m}");

    // A GLB with a second BIN chunk, and one whose chunk length is not a multiple of 4.
    let glb = sample("scene.glb");
    let refused_with_chunk = |kind: &[u8; 4], data: &[u8]| {
        let mut bytes = glb.clone();
        bytes.extend_from_slice(&(data.len() as u32).to_le_bytes());
        bytes.extend_from_slice(kind);
        bytes.extend_from_slice(data);
        let total = bytes.len() as u32;
        bytes[8..12].copy_from_slice(&total.to_le_bytes());
        read("in.glb", &bytes).map(|_| ()).unwrap_err().to_string()
    };
    let m = refused_with_chunk(b"BIN\0", &[0; 4]);
    assert!(m.contains("a second BIN chunk"), "{m}");
    let m = refused_with_chunk(b"XTRA", &[0; 3]);
    assert!(m.contains("not a multiple of 4"), "{m}");
}
