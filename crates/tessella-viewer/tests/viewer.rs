//! The viewer drawn offscreen on lavapipe, checked against `tessella_view::render` (the CLI's
//! `tessella render`), against the CPU and against its own earlier state.

use serde_json::{json, Value};
use std::sync::OnceLock;
use tessella_core::refine::Plan;
use tessella_core::{samples, RefineOptions, Scheme};
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::{read_texture, render, RenderOptions, RgbaImage};
use tessella_viewer::{Viewer, ViewerError};

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

fn ctx() -> GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| GpuContext::new(AdapterChoice::Software).expect("a software adapter"))
        .clone()
}

fn viewer(size: (u32, u32)) -> Viewer {
    let mut v = Viewer::new(ctx(), FORMAT).expect("a viewer");
    v.resize(size.0, size.1).unwrap();
    v
}

fn set(v: &mut Viewer, changes: Value) -> Result<(), ViewerError> {
    v.set(changes.as_object().expect("an object"))
}

/// One frame at `time_ms` drawn into a fresh texture, read back.
fn frame(v: &mut Viewer, time_ms: f64) -> RgbaImage {
    let ctx = v.context().clone();
    let (w, h) = v.size();
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test frame"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    v.draw(&texture.create_view(&Default::default()), time_ms)
        .expect("a frame");
    read_texture(&ctx, &texture).expect("read back")
}

/// Pixels whose colours differ by more than `tolerance` in some channel.
fn differing(a: &RgbaImage, b: &RgbaImage, tolerance: u8) -> usize {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > tolerance))
        .count()
}

/// Pixels that are not the white background.
fn covered(a: &RgbaImage) -> usize {
    a.pixels().filter(|p| p.0[..3] != [255, 255, 255]).count()
}

/// `tessella render`'s picture of the first sample (icosphere(1)), PN level 8, with `view`.
fn pn8_reference(view: RenderOptions) -> RgbaImage {
    render(
        &ctx(),
        &samples::icosphere(1),
        &RefineOptions::new(Scheme::Pn, 8),
        &view,
    )
    .unwrap()
}

#[test]
fn the_viewer_draws_what_tessella_render_draws() {
    let size = (192, 160);
    let mut v = viewer(size);
    set(
        &mut v,
        json!({"scheme": "pn", "level": 8, "yaw": 40, "pitch": 10, "zoom": 1.2}),
    )
    .unwrap();
    let picture = frame(&mut v, 0.0);
    let reference = pn8_reference(RenderOptions {
        size,
        yaw: 40.0,
        pitch: 10.0,
        zoom: 1.2,
        ..RenderOptions::default()
    });
    let total = (size.0 * size.1) as usize;
    assert!(covered(&picture) > total / 5, "the picture is nearly blank");
    // Same camera, pipeline and target formats: at most a few pixels differ (rounding).
    let diff = differing(&picture, &reference, 2);
    assert!(diff <= total / 1000, "{diff} of {total} pixels differ");
    // Wireframe too, and the silhouette of another camera.
    set(&mut v, json!({"wireframe": true, "yaw": -70, "zoom": 0.8})).unwrap();
    let wire = frame(&mut v, 0.0);
    let reference = pn8_reference(RenderOptions {
        size,
        yaw: -70.0,
        pitch: 10.0,
        zoom: 0.8,
        wireframe: true,
        ..RenderOptions::default()
    });
    let diff = differing(&wire, &reference, 2);
    assert!(
        diff <= total / 1000,
        "wireframe: {diff} of {total} pixels differ"
    );
}

#[test]
fn scheme_level_and_panels_change_the_picture() {
    let mut v = viewer((160, 160));
    set(&mut v, json!({"scheme": "flat", "level": 4})).unwrap();
    let flat = frame(&mut v, 0.0);
    // The first sample is samples::icosphere(1): 80 coarse triangles.
    assert_eq!(v.stats().refined_triangles, 80 * 16);
    set(&mut v, json!({"scheme": "png1"})).unwrap();
    let png1 = frame(&mut v, 0.0);
    // The curved silhouette covers more than the flat icosahedron's.
    assert!(covered(&png1) > covered(&flat) + 100);
    set(&mut v, json!({"level": 1})).unwrap();
    let coarse = frame(&mut v, 0.0);
    assert!(differing(&coarse, &png1, 8) > 200);
    assert_eq!(v.stats().refined_triangles, 80);
    set(&mut v, json!({"panels": ["flat", "pn"], "level": 3})).unwrap();
    frame(&mut v, 0.0);
    let s = v.stats();
    assert_eq!(s.refined_triangles, 2 * 80 * 9);
    assert_eq!(v.panels().len(), 2);
    // The static buffer is the welded layout of each panel (24-byte vertices, 4-byte indices).
    let plan = Plan::new(&samples::icosphere(1), &RefineOptions::new(Scheme::Pn, 3)).unwrap();
    let welded = plan.vertex_count() as u64 * 24 + plan.triangle_count() as u64 * 12;
    assert_eq!(s.static_bytes, 2 * welded);
    assert!(s.pattern_bytes > 0);
}

#[test]
fn bad_input_keeps_the_previous_mesh_and_parameters() {
    let mut v = viewer((128, 128));
    set(&mut v, json!({"scheme": "pn", "level": 6})).unwrap();
    let before = frame(&mut v, 0.0);
    let params = v.params().clone();
    for (change, name) in [
        (json!({"level": "NaN"}), "level"),
        (json!({"level": 100000}), "level"),
        (json!({"level": 3, "yaw": "east"}), "yaw"),
        (
            json!({"displace": "sine:0.1,5", "lod": "screen:4"}),
            "displace",
        ),
    ] {
        let err = set(&mut v, change.clone()).unwrap_err();
        assert!(
            err.to_string().starts_with(&format!("{name}: ")),
            "{change}: {err}"
        );
        assert_eq!(v.params(), &params, "{change}");
    }
    let faces = v.mesh().face_count();
    for (name, bytes) in [
        ("broken.obj", &b"v 0 0 0\nf 1 2 3\n"[..]),
        ("broken.ply", &b"ply\nformat nonsense\n"[..]),
        ("broken.glb", &b"glTF\x02\x00"[..]),
        ("mesh.xyz", &b"1 2 3"[..]),
    ] {
        assert!(v.load(name, bytes).is_err(), "{name}");
        assert_eq!(v.mesh().face_count(), faces);
    }
    assert!(v.load_sample("teapot").is_err());
    assert!(v.move_vertex(9999, [0.0; 3]).is_err());
    assert!(v.move_vertex(0, [f32::NAN, 0.0, 0.0]).is_err());
    assert!(v.set_edge_sharpness(0, 0, 1.0).is_err());
    assert!(v.set_edge_sharpness(0, 1, 2.0).is_err());
    let after = frame(&mut v, 0.0);
    assert_eq!(differing(&before, &after, 0), 0, "the picture changed");
    // A good file after all that.
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    v.load("tet.obj", obj).unwrap();
    assert_eq!(v.mesh().face_count(), 4);
    frame(&mut v, 0.0);
    assert_eq!(v.stats().refined_triangles, 4 * 36);
}

#[test]
fn screen_lod_uploads_coarse_data_only_while_the_levels_move() {
    let mut v = viewer((200, 200));
    set(
        &mut v,
        json!({"scheme": "pn", "spacing": "fractional-odd", "lod": "screen:6"}),
    )
    .unwrap();
    let faces = v.mesh().face_count() as u64;
    let mut levels = Vec::new();
    for k in 0..6 {
        let zoom = 0.7 * 1.5f32.powi(k);
        set(&mut v, json!({ "zoom": zoom })).unwrap();
        let picture = frame(&mut v, 0.0);
        let s = v.stats().clone();
        assert!(s.uploaded_bytes > 0);
        assert!(
            s.uploaded_bytes < 128 * faces,
            "zoom {zoom}: {} bytes for {faces} coarse triangles",
            s.uploaded_bytes
        );
        assert!(covered(&picture) > 1000);
        levels.push(s.level);
    }
    // Flying in, the levels grow.
    assert!(levels.windows(2).all(|w| w[1] >= w[0]), "{levels:?}");
    assert!(levels[5] > levels[0] * 2.0, "{levels:?}");
    // The twist re-uploads the nets every frame: coarse too.
    set(&mut v, json!({"animate": "twist"})).unwrap();
    let a = frame(&mut v, 0.0);
    let b = frame(&mut v, 1000.0);
    assert!(differing(&a, &b, 8) > 100);
    assert!(v.stats().uploaded_bytes < 1024 * faces);
}

#[test]
fn pick_finds_the_vertex_drawn_at_a_pixel() {
    let size = (200, 160);
    let mut v = viewer(size);
    set(&mut v, json!({"yaw": 25, "pitch": 15, "level": 4})).unwrap();
    frame(&mut v, 0.0);
    let mesh = samples::icosphere(1);
    let options = RenderOptions {
        size,
        yaw: 25.0,
        pitch: 15.0,
        ..RenderOptions::default()
    };
    let u = tessella_view::scene_uniforms(&mesh, &options, 0.0);
    let view_proj = glam::Mat4::from_cols_array_2d(&u.view_proj);
    let eye = glam::Vec3::from_slice(&u.eye[..3]);
    let mut checked = 0;
    for (i, &p) in mesh.positions().iter().enumerate() {
        let p = glam::Vec3::from(p);
        // Vertices facing the camera (the unit sphere's normal is the position).
        if p.dot((eye - p).normalize()) < 0.3 {
            continue;
        }
        let clip = view_proj * p.extend(1.0);
        let (x, y) = (clip.x / clip.w, clip.y / clip.w);
        let px = (x + 1.0) * 0.5 * size.0 as f32;
        let py = (1.0 - y) * 0.5 * size.1 as f32;
        let picked = v.pick(px, py).expect("a hit");
        assert_eq!(picked.vertex, i as u32, "vertex {i} at ({px}, {py})");
        assert!(picked.edge.contains(&(i as u32)));
        checked += 1;
    }
    assert!(checked >= 5, "{checked}");
    // Off the mesh: nothing.
    assert_eq!(v.pick(1.0, 1.0), None);
}

/// The bundled animated sample's bytes.
fn animated_glb() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../samples/animated-creature.glb"
    ))
    .unwrap()
}

/// A glTF file with clips plays them: paused at a given time the panels hold the pose
/// `Poser::pose_into` gives, a frame uploads the control nets alone (nothing while paused),
/// playing moves the time and the picture, and bad clips are refused by name.
#[test]
fn a_files_clip_plays_posed_as_the_poser_poses_it() {
    use tessella_core::animation::Poser;
    let size = (160, 160);
    let mut v = viewer(size);
    v.load("animated-creature.glb", &animated_glb()).unwrap();
    let poser =
        Poser::new(tessella_io::read_animated_bytes("a.glb", &animated_glb(), &[]).unwrap())
            .unwrap();
    let wave = poser.clip_index("wave").unwrap();
    set(
        &mut v,
        json!({"clip": "wave", "time": "0.5", "playing": false}),
    )
    .unwrap();
    let paused = frame(&mut v, 1000.0);
    let (expected, _) = poser.pose(Some(wave), 0.5).unwrap();
    let shown = v.panels()[0].mesh().positions().to_vec();
    let gap = shown
        .iter()
        .zip(&expected)
        .flat_map(|(a, b)| (0..3).map(move |k| (a[k] - b[k]).abs()))
        .fold(0.0f32, f32::max);
    assert!(
        gap <= 1e-6 * v.mesh().diagonal(),
        "the panel's mesh is {gap} off the pose"
    );
    let faces = poser.model().triangles.len() as u64;
    assert_eq!(v.stats().uploaded_bytes, faces * 16 * 12, "PN's nets alone");
    assert_eq!(v.stats().clips, ["wave", "hop", "breathe"]);
    assert!(v.stats().duration > 0.5);
    let rest = poser.mesh(None, 0.0).unwrap();
    // Paused: the same frame again uploads nothing.
    frame(&mut v, 1500.0);
    assert_eq!(v.stats().uploaded_bytes, 0);
    assert_eq!(v.params().time, 0.5);
    // Playing from 0.5: 250 ms later the clip is at 0.75 and the picture moved.
    set(&mut v, json!({"playing": true})).unwrap();
    frame(&mut v, 2000.0);
    let later = frame(&mut v, 2250.0);
    assert!((v.params().time - 0.75).abs() < 1e-4, "{}", v.params().time);
    assert_eq!(v.stats().uploaded_bytes, faces * 16 * 12);
    assert!(differing(&paused, &later, 8) > 20);
    // Bad clips name the parameter; the clip playing stays.
    for bad in [
        json!({"clip": "dance"}),
        json!({"time": -1}),
        json!({"time": "soon"}),
    ] {
        let e = set(&mut v, bad.clone()).unwrap_err().to_string();
        assert!(
            e.starts_with("clip:") || e.starts_with("time:"),
            "{bad}: {e}"
        );
    }
    assert_eq!(v.params().clip.as_deref(), Some("wave"));
    // No clip: the rest pose again.
    set(&mut v, json!({"clip": "none"})).unwrap();
    frame(&mut v, 3000.0);
    assert_eq!(v.panels()[0].mesh().positions(), rest.positions());
    // A mesh without clips refuses one.
    v.load_sample("icosphere").unwrap();
    let e = set(&mut v, json!({"clip": "wave"}))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("clip:"), "{e}");
}
