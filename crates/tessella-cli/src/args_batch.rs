//! `tessella batch` arguments: every `refine` option (the same parser, so the two cannot
//! drift apart), with the input taking many paths and `-o` naming a folder.

use crate::args::RefineArgs;
use clap::{Arg, ArgAction, ArgMatches, Args, Command, FromArgMatches};
use std::path::PathBuf;

#[derive(Debug)]
pub struct BatchArgs {
    /// Files, folders (their mesh files, recursively) and glob patterns.
    pub inputs: Vec<PathBuf>,
    /// Refine even when the output exists.
    pub force: bool,
    /// Files refined at once (default: one per core).
    pub jobs: Option<usize>,
    /// Output extension: ply, obj, glb, gltf or stl.
    pub format: String,
    /// `fsync` each output before it gets its name, instead of flushing them all at the end.
    pub sync_each: bool,
    /// The refine options; `output` is the output folder, `input` the first input.
    pub refine: RefineArgs,
}

impl FromArgMatches for BatchArgs {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        Ok(BatchArgs {
            inputs: matches
                .get_many::<PathBuf>("input")
                .map(|v| v.cloned().collect())
                .unwrap_or_default(),
            force: matches.get_flag("force"),
            jobs: matches.get_one::<usize>("jobs").copied(),
            format: matches
                .get_one::<String>("format")
                .cloned()
                .unwrap_or_else(|| "ply".into()),
            sync_each: matches.get_flag("sync-each"),
            refine: RefineArgs::from_arg_matches(matches)?,
        })
    }
    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for BatchArgs {
    fn augment_args(cmd: Command) -> Command {
        RefineArgs::augment_args(cmd)
            .mut_arg("input", |a| {
                a.num_args(1..)
                    .value_name("INPUTS")
                    .help("Mesh files, folders (searched recursively) and glob patterns")
            })
            .mut_arg("output", |a| a.value_name("DIR").help("Output folder"))
            .arg(
                Arg::new("force")
                    .long("force")
                    .action(ArgAction::SetTrue)
                    .help("Refine files whose output exists too (default: skip them)"),
            )
            .arg(
                Arg::new("jobs")
                    .long("jobs")
                    .short('j')
                    .value_parser(clap::value_parser!(usize))
                    .help("Files refined at once (default: one per core)"),
            )
            .arg(
                Arg::new("format")
                    .long("format")
                    .default_value("ply")
                    .help("Output format: ply, obj, glb, gltf or stl"),
            )
            .arg(
                Arg::new("sync-each")
                    .long("sync-each")
                    .action(ArgAction::SetTrue)
                    .help(
                        "Flush each output to the disk before it gets its name (default: all \
                         at once when the batch ends; a killed batch leaves whole files either \
                         way, a power cut before the end may not)",
                    ),
            )
    }
    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}
