//! `tessella samples`: write the bundled sample meshes.

use crate::args::SamplesArgs;
use anyhow::Context;
use tessella_core::samples;
use tessella_io::{write_mesh, MeshView, WriteOptions};

pub fn run(args: &SamplesArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    for name in samples::NAMES {
        let mesh = samples::by_name(name).expect("every listed sample exists");
        let path = args.output.join(format!("{name}.obj"));
        write_mesh(&path, MeshView::from(&mesh), &WriteOptions::default())?;
        println!(
            "{}: {} vertices, {} triangles",
            path.display(),
            mesh.vertex_count(),
            mesh.face_count()
        );
    }
    Ok(())
}
