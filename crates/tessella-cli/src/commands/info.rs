//! `tessella info`: what a mesh file holds and what is wrong with it.

use crate::args::InfoArgs;
use serde::Serialize;
use tessella_core::mesh::is_degenerate;
use tessella_core::{quality, Mesh, QualityReport, RefineOptions, Scheme, TopologyReport};
use tessella_io::read_raw;

#[derive(Serialize)]
struct Info {
    file: String,
    vertices: usize,
    triangles: usize,
    has_normals: bool,
    has_uvs: bool,
    bounds_min: [f32; 3],
    bounds_max: [f32; 3],
    non_finite_vertices: usize,
    out_of_range_triangles: usize,
    degenerate_triangles: usize,
    /// Topology of the valid triangles (absent when none are left or the mesh cannot be built).
    topology: Option<TopologyReport>,
    /// Why `tessella refine` would refuse this file, if it would.
    problem: Option<String>,
    /// Skins, morph targets and clips of a glTF file that has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    animation: Option<AnimationInfo>,
    /// A glTF file's scene: what it holds and each triangle primitive's level.
    #[serde(skip_serializing_if = "Option::is_none")]
    scene: Option<SceneInfo>,
    /// Every scheme's surface quality (with --quality).
    #[serde(skip_serializing_if = "Option::is_none")]
    quality: Option<Vec<QualityRow>>,
}

/// What a glTF scene holds, as `refine` writes it back.
#[derive(Serialize)]
struct SceneInfo {
    nodes: usize,
    meshes: usize,
    materials: usize,
    textures: usize,
    images: usize,
    skins: usize,
    animations: usize,
    cameras: usize,
    extensions_used: Vec<String>,
    /// Per triangle primitive: mesh, primitive, triangles, degenerate triangles, level.
    primitives: Vec<(usize, usize, usize, usize, u32)>,
}

/// The scene of a glTF `path` (`None` for other formats) with the levels `--level` or
/// `--max-edge` give.
fn scene_info(args: &InfoArgs) -> anyhow::Result<Option<SceneInfo>> {
    use tessella_io::gltf::scene::{Scene, SceneLevels};
    if !matches!(
        tessella_io::Format::from_path(&args.input),
        Ok(tessella_io::Format::Gltf | tessella_io::Format::Glb)
    ) {
        if args.max_edge.is_some() {
            anyhow::bail!("--max-edge shows the levels of a glTF scene's primitives; give a .gltf or .glb file");
        }
        return Ok(None);
    }
    let scene = Scene::read(&args.input)?;
    let levels = match args.max_edge {
        Some(length) => SceneLevels::MaxEdge(length),
        None => SceneLevels::Uniform(args.level),
    };
    let c = scene.counts();
    Ok(Some(SceneInfo {
        nodes: c.nodes,
        meshes: c.meshes,
        materials: c.materials,
        textures: c.textures,
        images: c.images,
        skins: c.skins,
        animations: c.animations,
        cameras: c.cameras,
        extensions_used: c.extensions_used,
        primitives: scene
            .primitives(&levels)?
            .iter()
            .map(|p| (p.id.0, p.id.1, p.triangles, p.degenerate, p.level))
            .collect(),
    }))
}

fn print_scene(s: &SceneInfo) {
    println!(
        "  scene               {} nodes, {} meshes, {} materials, {} textures, {} images, {} skins, {} animations, {} cameras",
        s.nodes, s.meshes, s.materials, s.textures, s.images, s.skins, s.animations, s.cameras
    );
    if !s.extensions_used.is_empty() {
        println!("  extensions          {}", s.extensions_used.join(", "));
    }
    for (m, p, triangles, degenerate, level) in &s.primitives {
        println!(
            "  mesh {m} primitive {p}  {triangles} triangles ({degenerate} degenerate), level {level} -> {} triangles",
            triangles * (*level as usize).pow(2)
        );
    }
}

/// What a glTF file animates.
#[derive(Serialize)]
struct AnimationInfo {
    /// Per skin: its name and joint count.
    skins: Vec<(Option<String>, usize)>,
    /// Morph targets of each mesh instance, summed.
    morph_targets: usize,
    /// Per clip: its name and duration in seconds.
    clips: Vec<(String, f32)>,
    /// Why the animation cannot be played, if it cannot.
    problem: Option<String>,
}

/// The animation of a glTF `path`, if it has skins, morph targets or clips.
fn animation_info(path: &std::path::Path) -> anyhow::Result<Option<AnimationInfo>> {
    let is_gltf = matches!(
        tessella_io::Format::from_path(path),
        Ok(tessella_io::Format::Gltf | tessella_io::Format::Glb)
    );
    if !is_gltf {
        return Ok(None);
    }
    let model = tessella_io::read_animated(path)?;
    let morph_targets = model.instances.iter().map(|i| i.targets.len()).sum();
    if model.skins.is_empty() && model.clips.is_empty() && morph_targets == 0 {
        return Ok(None);
    }
    let skins = model
        .skins
        .iter()
        .map(|s| (s.name.clone(), s.joints.len()))
        .collect();
    let names: Vec<String> = model.clips.iter().map(|c| c.name.clone()).collect();
    let (clips, problem) = match tessella_core::animation::Poser::new(model) {
        Ok(poser) => {
            let durations = (0..names.len()).map(|i| poser.duration(i));
            let clips = names
                .into_iter()
                .zip(durations)
                .map(|(name, d)| Ok((name, d?)))
                .collect::<Result<Vec<_>, tessella_core::AnimationError>>()?;
            (clips, None)
        }
        Err(e) => (
            names.into_iter().map(|n| (n, f32::NAN)).collect(),
            Some(e.to_string()),
        ),
    };
    Ok(Some(AnimationInfo {
        skins,
        morph_targets,
        clips,
        problem,
    }))
}

pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    let scene = scene_info(args)?;
    let raw = match (read_raw(&args.input), &scene) {
        (Ok(raw), _) => raw,
        // A scene refine reads (quantised, meshopt-compressed) that the merged reader cannot.
        (Err(e), Some(scene)) if !args.json => {
            println!("{}", args.input.display());
            print_scene(scene);
            println!("  merged mesh         not read ({e})");
            println!("  ready to refine (as a scene)");
            return Ok(());
        }
        (Err(e), _) => return Err(e.into()),
    };
    let nv = raw.positions.len();
    let finite = |p: &[f32; 3]| p.iter().all(|c| c.is_finite());
    let non_finite_vertices = raw.positions.iter().filter(|p| !finite(p)).count();
    let mut out_of_range = 0;
    let mut degenerate = 0;
    let mut valid = Vec::with_capacity(raw.triangles.len());
    for t in &raw.triangles {
        if t.iter().any(|&i| i as usize >= nv) {
            out_of_range += 1;
            continue;
        }
        if is_degenerate(&raw.positions, *t) {
            degenerate += 1;
            continue;
        }
        valid.push(*t);
    }
    let (lo, hi) = tessella_core::mesh::bounds(
        &raw.positions
            .iter()
            .copied()
            .filter(finite)
            .collect::<Vec<_>>(),
    );
    let full = Mesh::new(
        raw.positions.clone(),
        raw.normals.clone(),
        raw.uvs.clone(),
        raw.triangles.clone(),
    );
    // A glTF scene is refined primitive by primitive, its degenerate triangles flat: only the
    // merged mesh of other formats is refused for them.
    let problem = match &scene {
        Some(_) => None,
        None => full.as_ref().err().map(|e| e.to_string()),
    };
    // Topology of what is usable: the whole mesh, or its valid triangles without normals.
    let topology = match full {
        Ok(mesh) => Some(mesh.topology().report),
        Err(_) if non_finite_vertices == 0 && !valid.is_empty() => {
            Mesh::new(raw.positions.clone(), None, None, valid)
                .ok()
                .map(|m| m.topology().report)
        }
        Err(_) => None,
    };
    let info = Info {
        file: args.input.display().to_string(),
        vertices: nv,
        triangles: raw.triangles.len(),
        has_normals: raw.normals.is_some(),
        has_uvs: raw.uvs.is_some(),
        bounds_min: lo,
        bounds_max: hi,
        non_finite_vertices,
        out_of_range_triangles: out_of_range,
        degenerate_triangles: degenerate,
        topology,
        problem,
        animation: animation_info(&args.input)?,
        scene,
        quality: None,
    };
    let quality = if args.quality {
        let (raw, mesh) = super::tags::read(&args.input)?;
        let mut options = RefineOptions::new(Scheme::Pn, args.level);
        if let Some(tags) = super::tags::gather(&raw, &mesh, Scheme::ScalarTagged, &args.tags)? {
            options = options.with_tags(tags);
        }
        // Each scheme on its own: one that refuses this mesh (ST allows one crease through a
        // vertex) gets its reason in the table instead of sinking the others.
        let rows: Vec<QualityRow> = super::demo::SCHEMES
            .iter()
            .map(|&scheme| {
                let mut o = options.clone();
                o.scheme = scheme;
                match quality::report(&mesh, &o) {
                    Ok(report) => QualityRow::Measured(report),
                    Err(e) => QualityRow::Refused {
                        scheme: scheme.name().into(),
                        reason: e.to_string(),
                    },
                }
            })
            .collect();
        Some(rows)
    } else {
        None
    };
    let info = Info { quality, ..info };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print_text(&info);
        if let Some(reports) = &info.quality {
            println!();
            print_quality(reports);
        }
    }
    Ok(())
}

/// One scheme's quality, or why it refused the mesh.
#[derive(Serialize)]
#[serde(untagged)]
pub enum QualityRow {
    Measured(QualityReport),
    Refused { scheme: String, reason: String },
}

/// Prints quality reports as a Markdown table.
pub fn print_quality(reports: &[QualityRow]) {
    println!("| scheme | level | normal jump across edges, max (°) | mean (°) | largest gap (% of diagonal) | largest distance from coarse (% of diagonal) |");
    println!("|---|---:|---:|---:|---:|---:|");
    for row in reports {
        let r = match row {
            QualityRow::Measured(r) => r,
            QualityRow::Refused { scheme, reason } => {
                println!("| {scheme} | | refused: {reason} | | | |");
                continue;
            }
        };
        println!(
            "| {} | {} | {:.4} | {:.4} | {:.2e} | {:.3} |",
            r.scheme,
            r.level,
            r.normal_jump_max_deg,
            r.normal_jump_mean_deg,
            100.0 * r.gap_max_relative,
            100.0 * r.distance_max_relative
        );
    }
}

fn print_text(i: &Info) {
    println!("{}", i.file);
    println!("  vertices            {}", i.vertices);
    println!("  triangles           {}", i.triangles);
    println!(
        "  normals             {}",
        if i.has_normals {
            "given"
        } else {
            "missing (computed when refining)"
        }
    );
    println!(
        "  uvs                 {}",
        if i.has_uvs { "given" } else { "none" }
    );
    println!(
        "  bounds              {:?} .. {:?}",
        i.bounds_min, i.bounds_max
    );
    println!("  non-finite vertices {}", i.non_finite_vertices);
    println!(
        "  bad indices         {} triangles",
        i.out_of_range_triangles
    );
    println!("  degenerate          {} triangles", i.degenerate_triangles);
    if let Some(t) = &i.topology {
        println!("  positions           {}", t.positions);
        println!("  edges               {}", t.edges);
        println!("  boundary edges      {}", t.boundary_edges);
        println!("  non-manifold edges  {}", t.non_manifold_edges);
        println!(
            "  inconsistent edges  {} (faces winding the same way along them)",
            t.inconsistent_edges
        );
        println!(
            "  seam edges          {} (one position, split vertices)",
            t.seam_edges
        );
        println!(
            "  split normals       {} positions",
            t.split_normal_positions
        );
        println!("  unreferenced        {} vertices", t.unreferenced_vertices);
        println!("  euler characteristic {}", t.euler_characteristic);
        println!(
            "  closed manifold     {}",
            if t.is_closed_manifold() { "yes" } else { "no" }
        );
    }
    if let Some(s) = &i.scene {
        print_scene(s);
    }
    if let Some(a) = &i.animation {
        for (k, (name, joints)) in a.skins.iter().enumerate() {
            let name = name.as_deref().unwrap_or("unnamed");
            println!("  skin {k}              {name}: {joints} joints");
        }
        println!("  morph targets       {}", a.morph_targets);
        for (k, (name, seconds)) in a.clips.iter().enumerate() {
            println!("  clip {k}              {name}: {seconds:.3} s");
        }
        if let Some(p) = &a.problem {
            println!("  cannot animate: {p}");
        }
    }
    match &i.problem {
        Some(p) => println!("  refine would refuse: {p}"),
        None => println!("  ready to refine"),
    }
}
