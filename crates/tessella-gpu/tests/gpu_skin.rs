//! GPU skinning ([`GpuSkinner`]) against the CPU pose ([`Poser::pose_into`]): the skinned
//! positions within 1e-6 of the bounding box diagonal, the normals within 1e-5, and the bytes a
//! frame uploads.

mod common;

#[allow(clippy::all)]
#[path = "../../tessella-core/tests/animation_scene/mod.rs"]
mod animation_scene;

use animation_scene::{scene, MESH_NODE, PROP_NODE};
use common::ctx;
use tessella_core::animation::{AnimatedMesh, Interpolation, Poser, Property};
use tessella_gpu::{GpuError, GpuSkinner, SKINNED_VERTEX_BYTES};

/// The skinner's output after `update` and `record`: per vertex position, normal, padding.
fn skin(skinner: &mut GpuSkinner, poser: &Poser, clip: Option<usize>, time: f32) -> Vec<[f32; 8]> {
    skinner.update(poser, clip, time).expect("update");
    read(skinner)
}

fn read(skinner: &GpuSkinner) -> Vec<[f32; 8]> {
    let ctx = ctx();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    skinner.record(&mut encoder).expect("record");
    ctx.submit(encoder).expect("submit");
    let bytes = ctx
        .read_buffer(
            skinner.output_buffer(),
            0,
            skinner.vertex_count() as u64 * u64::from(SKINNED_VERTEX_BYTES),
        )
        .expect("read back");
    bytemuck::pod_collect_to_vec(&bytes)
}

fn diagonal(points: &[[f32; 3]]) -> f32 {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f32>().sqrt()
}

/// GPU-skinned equals CPU-posed at this moment; returns the CPU positions.
fn assert_same(
    skinner: &mut GpuSkinner,
    poser: &Poser,
    clip: Option<usize>,
    time: f32,
    what: &str,
) -> Vec<[f32; 3]> {
    let gpu = skin(skinner, poser, clip, time);
    let (positions, normals) = poser.pose(clip, time).expect("CPU pose");
    let normals = normals.expect("normals");
    assert_eq!(gpu.len(), positions.len());
    let tolerance = 1e-6 * diagonal(&positions);
    for (v, g) in gpu.iter().enumerate() {
        let d = common::dist([g[0], g[1], g[2]], positions[v]);
        assert!(
            d <= tolerance,
            "{what} clip {clip:?} t={time} vertex {v}: GPU {:?} vs CPU {:?} ({d:e} > {tolerance:e})",
            &g[..3],
            positions[v]
        );
        let d = common::dist([g[4], g[5], g[6]], normals[v]);
        assert!(
            d <= 1e-5,
            "{what} clip {clip:?} t={time} normal {v}: GPU {:?} vs CPU {:?} ({d:e})",
            &g[4..7],
            normals[v]
        );
        assert_eq!((g[3], g[7]), (0.0, 0.0), "{what}: padding of vertex {v}");
    }
    positions
}

/// Every clip at several moments (and the rest pose), each pose different from the rest.
fn assert_all_clips(poser: &Poser, what: &str) {
    let mut skinner = GpuSkinner::new(ctx(), poser).expect("skinner");
    let rest = assert_same(&mut skinner, poser, None, 0.0, what);
    for clip in 0..poser.clip_count() {
        let end = poser.duration(clip).unwrap();
        let mut moved = false;
        for s in [0.0, 0.23, 0.5, 0.81, 1.0] {
            let posed = assert_same(&mut skinner, poser, Some(clip), s * end, what);
            moved |= posed != rest;
        }
        assert!(moved, "{what}: clip {clip} never moves the mesh");
    }
}

/// The animated sample: skinned and morphing, every clip; a frame uploads the joint matrices
/// and morph weights alone.
#[test]
fn creature_skins_on_the_gpu_as_on_the_cpu() {
    let poser = Poser::new(tessella_core::samples::animated_creature(1)).unwrap();
    assert!(poser.morph_weight_count() > 0, "the creature morphs");
    let model = poser.model();
    let joints: usize = model.skins.iter().map(|s| s.joints.len()).sum();
    let unskinned = model.instances.iter().filter(|i| i.skin.is_none()).count();
    assert_eq!(poser.deform_matrix_count(), joints + unskinned);
    assert_all_clips(&poser, "creature");
    let mut skinner = GpuSkinner::new(ctx(), &poser).unwrap();
    let bytes = skinner.update(&poser, Some(0), 0.3).unwrap();
    assert_eq!(
        bytes,
        64 * (joints + unskinned) as u64 + 4 * poser.morph_weight_count() as u64
    );
}

/// The three.js fixture, as tessella-io reads it.
#[test]
fn three_js_fixture_skins_on_the_gpu_as_on_the_cpu() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tessella-io/tests/fixtures/three/skinned.gltf");
    let model = tessella_io::read_animated(&path).expect("the fixture");
    let poser = Poser::new(model).unwrap();
    assert!(poser.clip_count() > 0);
    assert_all_clips(&poser, "three.js fixture");
}

/// The hand-made scene: two influence sets (eight joints a vertex), weights not summing to
/// one, zero weights, a morph target without normals, an unskinned instance under a matrix
/// node whose parent is animated; each interpolation.
#[test]
fn hand_made_scene_skins_on_the_gpu_as_on_the_cpu() {
    for kind in [
        Interpolation::Linear,
        Interpolation::Step,
        Interpolation::CubicSpline,
    ] {
        let model = scene(kind);
        let skinned = &model.instances[0];
        assert_eq!(skinned.influences.len(), 2);
        assert!(skinned.targets.iter().any(|t| t.normals.is_none()));
        assert!(skinned.influences[0]
            .weights
            .iter()
            .any(|w| w.contains(&0.0)));
        let sums: Vec<f32> = (0..skinned.positions.len())
            .map(|v| {
                skinned
                    .influences
                    .iter()
                    .map(|s| s.weights[v].iter().sum::<f32>())
                    .sum()
            })
            .collect();
        assert!(sums.iter().any(|s| (s - 1.0).abs() > 0.1), "{sums:?}");
        assert!(model.instances[1].skin.is_none());
        let poser = Poser::new(model).unwrap();
        assert!(poser.deform_table().slots > 4, "both sets in use");
        assert_all_clips(&poser, &format!("scene {kind:?}"));
    }
}

/// A skinned-only model: the scene's skinned grid without morph targets or the unskinned
/// prop.
fn skin_only() -> AnimatedMesh {
    let mut model = scene(Interpolation::Linear);
    model.instances.truncate(1);
    let count = model.instances[0].positions.len() as u32;
    model.triangles.retain(|t| t.iter().all(|&i| i < count));
    model.instances[0].targets.clear();
    model.instances[0].default_weights.clear();
    model.nodes[PROP_NODE as usize].weights = None;
    for clip in &mut model.clips {
        clip.channels.retain(|c| {
            c.property != Property::Weights && c.node != PROP_NODE && c.node != MESH_NODE
        });
    }
    model
}

/// A skin-only frame uploads exactly the joint matrices: 64 bytes a joint.
#[test]
fn skin_only_frame_uploads_the_joint_matrices_alone() {
    let poser = Poser::new(skin_only()).unwrap();
    assert_eq!(poser.morph_weight_count(), 0);
    let joints = poser.model().skins[0].joints.len();
    let mut skinner = GpuSkinner::new(ctx(), &poser).unwrap();
    assert_eq!(
        skinner.update(&poser, Some(0), 0.4).unwrap(),
        joints as u64 * 64
    );
    assert_same(&mut skinner, &poser, Some(0), 0.4, "skin only");
    // An engine's own matrices: the same bytes, and the counts checked.
    let (mut m, mut w) = (Vec::new(), Vec::new());
    poser.deform_into(Some(0), 0.9, &mut m, &mut w).unwrap();
    assert_eq!(skinner.update_matrices(&m, &w).unwrap(), joints as u64 * 64);
    assert!(matches!(
        skinner.update_matrices(&m[1..], &w),
        Err(GpuError::BadOption(_))
    ));
    // A poser of another model is refused.
    let other = Poser::new(scene(Interpolation::Linear)).unwrap();
    assert!(matches!(
        skinner.update(&other, Some(0), 0.0),
        Err(GpuError::BadOption(_))
    ));
    // Bad clip and time: the core's errors.
    assert!(matches!(
        skinner.update(&poser, Some(9), 0.0),
        Err(GpuError::Animation(_))
    ));
    assert!(matches!(
        skinner.update(&poser, Some(0), f32::INFINITY),
        Err(GpuError::Animation(_))
    ));
}

/// Singular blended matrices (every joint scaled to zero): every point at the origin, and
/// the normals fall back to the (morphed) rest normals, normalised, as on the CPU.
#[test]
fn singular_matrices_fall_back_to_the_rest_normals() {
    let model = scene(Interpolation::Linear);
    let poser = Poser::new(model.clone()).unwrap();
    let skinner = GpuSkinner::new(ctx(), &poser).unwrap();
    let matrices = vec![[0.0f32; 16]; poser.deform_matrix_count()];
    let weights = vec![0.0f32; poser.morph_weight_count()];
    skinner.update_matrices(&matrices, &weights).unwrap();
    let out = read(&skinner);
    let rest: Vec<[f32; 3]> = model
        .instances
        .iter()
        .flat_map(|i| i.normals.clone().unwrap())
        .collect();
    for (v, g) in out.iter().enumerate() {
        assert_eq!(&g[..3], &[0.0; 3], "vertex {v}");
        let n = rest[v];
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let want = n.map(|c| c / l);
        assert!(
            common::dist([g[4], g[5], g[6]], want) < 1e-6,
            "normal {v}: {g:?} vs {want:?}"
        );
    }
    // The CPU agrees: the scene with every joint scaled to zero.
    let mut flat = model;
    for j in 1..=8 {
        if let tessella_core::animation::Transform::Trs { scale, .. } = &mut flat.nodes[j].transform
        {
            *scale = [0.0; 3];
        }
    }
    flat.clips[0]
        .channels
        .retain(|c| c.property != Property::Scale);
    let poser = Poser::new(flat).unwrap();
    let mut skinner = GpuSkinner::new(ctx(), &poser).unwrap();
    assert_same(&mut skinner, &poser, Some(0), 0.5, "joints scaled to zero");
}

/// The output as a coarse input: 32-byte stride, positions at 0, normals at 16.
#[test]
fn output_is_a_coarse_input() {
    let poser = Poser::new(skin_only()).unwrap();
    let skinner = GpuSkinner::new(ctx(), &poser).unwrap();
    let input = skinner.output();
    assert_eq!((input.positions.stride, input.positions.first), (32, 0));
    assert_eq!((input.normals.stride, input.normals.first), (32, 16));
    assert_eq!(input.positions.offset, 0);
    let usage = skinner.output_buffer().usage();
    assert!(usage.contains(
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC
    ));
    assert_eq!(
        skinner.output_buffer().size(),
        poser.vertex_count() as u64 * 32
    );
}

/// A model without normals is refused, with the way out.
#[test]
fn model_without_normals_is_refused() {
    let mut model = scene(Interpolation::Linear);
    model.instances[1].normals = None;
    for t in &mut model.instances[1].targets {
        t.normals = None;
    }
    let poser = Poser::new(model).unwrap();
    let err = GpuSkinner::new(ctx(), &poser).unwrap_err();
    assert_eq!(err, GpuError::SkinNeedsNormals);
    assert!(err.to_string().contains("on the CPU"), "{err}");
}
