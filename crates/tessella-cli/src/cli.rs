//! The command line: the subcommands and the arguments each takes (in `args` and
//! `args_batch`).

use crate::args::{
    AnimateArgs, BenchArgs, DemoArgs, InfoArgs, PatternArgs, RefineArgs, RenderArgs, SamplesArgs,
    ViewArgs,
};
use crate::args_batch::BatchArgs;
use clap::{Parser, Subcommand};

/// Turn coarse triangle meshes into smooth curved surfaces.
///
/// Each coarse triangle is replaced by a curved patch (flat, Phong tessellation, PN triangles,
/// PNG1, PN-AEN, scalar-tagged PN or second-order elements: `--scheme`) sampled with a
/// refinement pattern of LEVEL segments per edge, so LEVEL 8 turns every triangle into 64.
/// Files: OBJ, PLY, glTF/GLB and STL, read and written (STL written binary, without normals or
/// texture coordinates).
#[derive(Debug, Parser)]
#[command(name = "tessella", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Refine a mesh file into a smooth, denser mesh file.
    ///
    /// Example: tessella refine bunny.obj -o smooth.ply --scheme pn --level 8
    Refine(RefineArgs),
    /// Refine many mesh files (files, folders, glob patterns) into a folder with the options
    /// of `refine`, on all cores; existing outputs are skipped (a killed batch resumes), and
    /// `manifest.jsonl` in the folder gets a row per input. Exit code 1 when some file failed,
    /// 2 for usage errors.
    ///
    /// Example: tessella batch meshes/ 'more/*.stl' -o refined/ --level 4
    Batch(BatchArgs),
    /// Report a mesh file's counts, bounds, boundary and non-manifold edges, split normals and
    /// degenerate triangles.
    Info(InfoArgs),
    /// Print a refinement pattern (barycentric points and small triangles) as JSON, or draw it
    /// as SVG: the uniform grid, or the GPU tessellator's pattern for given levels.
    Pattern(PatternArgs),
    /// Write the bundled sample meshes (icosphere, torus, tetrahedron, hard-cube, creature) as
    /// OBJ files.
    Samples(SamplesArgs),
    /// Refine every bundled sample with every scheme and print a table of counts, time and
    /// distance to the coarse input.
    Demo(DemoArgs),
    /// Render a picture of the refined surface (GPU; a software adapter when there is none).
    ///
    /// Example: tessella render samples/creature.obj -o creature.png --compare flat,pn,png1
    Render(RenderArgs),
    /// Render frames of a coarse mesh twisting over time, re-uploading only the coarse control
    /// nets per frame, and report the bytes uploaded against a full refined vertex buffer.
    Animate(AnimateArgs),
    /// Open the interactive viewer in a window: drag to orbit (shift or right button: pan),
    /// wheel or +/- to zoom, arrows orbit (alt: pan), w wireframe, 1-7 or Tab the scheme,
    /// the bracket keys step the level, a the twist animation, s a screenshot, Esc or q quits.
    ///
    /// Example: tessella view samples/creature.obj --scheme png1 --level 6
    View(ViewArgs),
    /// Measure refinement throughput and print a Markdown table.
    Bench(BenchArgs),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::{NormalsArg, SchemeArg};
    use tessella_core::{Backend, Named, NormalMode, Scheme};

    #[test]
    fn core_names_parse_and_bad_names_list_the_valid_ones() {
        let refine = |extra: &[&str]| {
            let mut argv = vec!["tessella", "refine", "in.obj", "-o", "out.ply"];
            argv.extend_from_slice(extra);
            Cli::try_parse_from(argv)
        };
        let Command::Refine(args) = refine(&[
            "--scheme",
            "pn_aen",
            "--normals",
            "real",
            "--backend",
            "cpu",
        ])
        .unwrap()
        .command
        else {
            panic!("not a refine command")
        };
        assert_eq!(args.shape.scheme, SchemeArg(Scheme::PnAen));
        assert_eq!(args.shape.normals, Some(NormalsArg(NormalMode::Real)));
        assert_eq!(args.backend, Backend::Cpu);
        let Command::Refine(args) = refine(&["--scheme", "phong", "--alpha", "0.5"])
            .unwrap()
            .command
        else {
            panic!("not a refine command")
        };
        assert_eq!(
            args.shape.scheme.scheme(args.shape.alpha),
            Scheme::Phong { alpha: 0.5 }
        );
        assert_eq!(args.backend, Backend::Auto);

        let err = refine(&["--scheme", "loop"]).unwrap_err().to_string();
        assert!(
            err.contains(r#"unknown scheme "loop"; use one of ["flat", "phong", "pn", "png1", "pn-aen", "st", "quadratic"]"#),
            "{err}"
        );
        assert!(err.contains("--scheme"), "{err}");
        let err = refine(&["--backend", "tpu"]).unwrap_err().to_string();
        assert!(err.contains(r#"unknown backend "tpu""#), "{err}");
        let err = refine(&["--normals", "smooth"]).unwrap_err().to_string();
        assert!(err.contains(r#"unknown normal mode "smooth""#), "{err}");

        let Command::Render(args) = Cli::try_parse_from([
            "tessella",
            "render",
            "in.obj",
            "-o",
            "out.png",
            "--compare",
            "flat,png1,st",
        ])
        .unwrap()
        .command
        else {
            panic!("not a render command")
        };
        assert_eq!(
            args.compare,
            [Scheme::Flat, Scheme::Png1, Scheme::ScalarTagged].map(SchemeArg)
        );
    }

    #[test]
    fn help_lists_the_core_names() {
        use clap::CommandFactory;
        let mut cli = Cli::command();
        let help = cli
            .find_subcommand_mut("refine")
            .expect("refine")
            .render_long_help()
            .to_string();
        for value in Scheme::ALL {
            assert!(help.contains(value.name()), "{help}");
            assert!(help.contains(value.description()), "{help}");
        }
        for name in NormalMode::NAMES.iter().chain(Backend::NAMES) {
            assert!(help.contains(name), "{help}");
        }
    }

    #[test]
    fn cli_is_well_formed() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
