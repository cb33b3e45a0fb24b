//! `subsurf repose`: refine a base mesh once, then write the refined mesh of each pose
//! (the same faces, other positions) with one application of a re-posing plan per pose.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use subsurf::io::PendingFile;
use subsurf::io::{write_obj, WriteOptions};
use subsurf::mesh::Options;
use subsurf::{PoseError, Reposer, SubdivideOptions};

use crate::input::Input;
use crate::progress::Progress;
use crate::{AdjustArgs, SchemeArgs, SchemeKind};

/// Help text after the options of `subsurf repose`.
pub const REPOSE_EXAMPLES: &str = "\
The base mesh's faces, tags (creases, corners, holes, knot intervals, weights) and scheme
(Catmull-Clark; the adjustable one with --scheme adjustable --c C [--adjust-steps K]; NURSS
with --scheme nurss, the default for a base mesh with knot interval or weight tags; Loop
and bilinear with --scheme loop|bilinear; as 'subsurf subdivide' refines) hold for every pose. A rational base mesh's weights stay with
its vertices. A pose
is an OBJ file with the base mesh's vertices moved: it repeats the base mesh's faces (same
vertices, same order; its tags are not read) or has no faces at all ('v' lines only, as a
point cache). Each refined pose is written to DIR (created, with its parents, if missing)
under the pose's file name. The outputs appear all together or not at all: the first pose
that cannot be read or does not match stops the run, and nothing is written.
The positions are those 'subsurf subdivide' writes for the pose, to rounding (1e-14 of the
mesh's size); with --limit, the limit positions and normals too (the limit masks applied
as rows of weights after the plan; NURSS: the limit positions, no normals, as 'subdivide
--limit' writes them). Refining a pose costs a tenth of a full refinement or
less (Loop and bilinear: a third to a twelfth, their plans having no patch kernels);
writing the OBJ text then takes most of the time (the library's Reposer skips that).

Examples:
  subsurf repose rest.obj frames/f0001.obj frames/f0002.obj -o refined -l 3
  subsurf repose rest.obj frames/*.obj -o refined -l 2 --boundary edge-and-corner
  subsurf repose rest.obj frames/*.obj -o refined -l 3 --scheme adjustable --c 0.3
  subsurf repose knots.obj frames/*.obj -o refined -l 3 --scheme nurss
  subsurf repose scan.obj frames/*.obj -o refined -l 2 --scheme loop --limit";

/// Arguments of `subsurf repose`.
#[derive(Debug, Args)]
pub struct ReposeArgs {
    /// The base mesh (OBJ or PLY): faces, tags and scheme of every pose ('-' reads standard input).
    #[arg(value_name = "BASE")]
    pub base: PathBuf,
    /// Poses: OBJ or PLY files with the base mesh's vertices moved.
    #[arg(value_name = "POSE", required = true)]
    pub poses: Vec<PathBuf>,
    /// Directory the refined poses are written to, as OBJ, each under its pose's file name
    /// with the extension .obj.
    #[arg(short, long = "output-dir", value_name = "DIR")]
    pub output_dir: PathBuf,
    /// Number of refinement levels.
    #[arg(short, long, value_name = "N", default_value_t = 2)]
    pub levels: u32,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Subdivision scheme [default: nurss when the base mesh has knot interval or weight
    /// tags, else catmull-clark].
    #[arg(long = "scheme", id = "scheme_kind", value_name = "SCHEME", value_enum)]
    pub scheme_kind: Option<SchemeKind>,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Move the last level's vertices to the limit surface and write limit normals (as
    /// `subdivide --limit`).
    #[arg(long)]
    pub limit: bool,
    /// Keep hole faces in the output (tagged as holes) instead of leaving them out.
    #[arg(long)]
    pub keep_holes: bool,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
    /// Print no warnings and no progress bar.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `subsurf repose`.
pub fn run(args: &ReposeArgs) -> Result<()> {
    let outputs = output_paths(args)?;
    let base = Input::read_surface(&args.base, args.max_memory)?;
    let progress = Progress::counting(args.poses.len() as u64, "poses", args.quiet);
    let kind = super::subdivide::scheme_kind(args.scheme_kind, &base, &progress, args.quiet);
    let opts = SubdivideOptions {
        levels: args.levels,
        scheme: super::adjustable::for_subdivide(kind, &args.adjust),
        options: args
            .scheme
            .over(base.obj.options)
            .resolve(Options::default()),
        limit: args.limit,
        keep_holes: args.keep_holes,
        max_memory: None,
    };
    let mesh = &base.obj.mesh;
    let estimate = Reposer::estimate_memory(mesh, &opts);
    let what = format!("refining to level {} and planning re-posing", opts.levels);
    crate::memory::check(
        &base.name,
        &what,
        estimate,
        args.max_memory,
        "use a lower level",
    )?;
    crate::memory::for_refinement(estimate);
    progress.set_message(format!("refining {} and planning re-posing", base.name));
    let mut reposer = Reposer::new(mesh, &opts).with_context(|| base.name.clone())?;
    let flags = super::subdivide::scheme_flags(opts.scheme, opts.levels);
    if !args.quiet {
        for w in base.warnings() {
            progress.warn(&w);
        }
        for w in reposer
            .warnings()
            .iter()
            .filter_map(|w| base.topology_warning(w))
        {
            progress.warn(&w);
        }
    }
    // Each pose is written to a temporary file beside its output, renamed into place once
    // every pose has been written: all outputs or none.
    let mut written = Vec::with_capacity(outputs.len());
    for (pose, out) in args.poses.iter().zip(&outputs) {
        progress.set_message(format!("re-posing {}", pose.display()));
        let input = Input::read(pose, args.max_memory)?;
        reposer
            .pose_mesh(&input.obj.mesh)
            .map_err(|e| pose_error(&input, &base, &e))?;
        let comment = super::subdivide::command_line_of(
            "repose",
            &opts,
            &flags,
            &format!("{} {}", base.name, input.name),
        );
        let write_opts = WriteOptions {
            normals: reposer.normals(),
            scheme: Some(opts.options),
            comment: Some(&comment),
        };
        let refined = reposer.mesh();
        let cannot = || format!("cannot write {}", out.display());
        let mut file = PendingFile::create(out).with_context(cannot)?;
        write_obj(file.writer(), refined, &write_opts).with_context(cannot)?;
        written.push((file.finish().with_context(cannot)?, out));
        progress.step_done();
    }
    for (file, out) in written {
        file.commit()
            .with_context(|| format!("cannot write {}", out.display()))?;
    }
    Ok(())
}

/// The output file of each pose: `DIR/<its file name>`, `DIR` created if missing. Fails
/// before any work when `DIR` is not a directory, two poses have the same file name, or an
/// output would replace the base mesh or a pose.
fn output_paths(args: &ReposeArgs) -> Result<Vec<PathBuf>> {
    let dir = &args.output_dir;
    if dir.exists() && !dir.is_dir() {
        bail!("cannot write to {}: not a directory", dir.display());
    }
    let inputs: HashSet<PathBuf> = std::iter::once(&args.base)
        .chain(&args.poses)
        .filter_map(|p| p.canonicalize().ok())
        .collect();
    let mut names = HashSet::new();
    let mut outputs = Vec::with_capacity(args.poses.len());
    for pose in &args.poses {
        if pose == Path::new("-") {
            bail!("poses are read from files; standard input ('-') can be the base mesh only");
        }
        let Some(name) = pose.file_name() else {
            bail!("{}: not a file name", pose.display());
        };
        // The refined poses are OBJ files: `walk.ply` becomes `walk.obj`.
        let name = Path::new(name).with_extension("obj");
        let out = dir.join(&name);
        if !names.insert(name) {
            bail!(
                "two poses would be written to {}: their outputs would replace each other",
                out.display()
            );
        }
        if out.canonicalize().is_ok_and(|o| inputs.contains(&o)) {
            bail!(
                "{}: the output for pose {} would replace an input; write to another directory",
                out.display(),
                pose.display()
            );
        }
        outputs.push(out);
    }
    crate::output::create_dir_all(dir)?;
    Ok(outputs)
}

/// `e` in the pose file's terms: faces and vertices numbered as the files number them
/// (from 1 in OBJ, from 0 in PLY), with the line of a face where there is one.
fn pose_error(pose: &Input, base: &Input, e: &PoseError) -> anyhow::Error {
    match e {
        PoseError::Face { face } => {
            let at = |input: &Input| match input.obj.face_line(*face) {
                Some(l) => format!("{}:{l}", input.name),
                None => input.name.clone(),
            };
            anyhow::anyhow!(
                "{}: face {} is not the base mesh's face {} ({}): a pose repeats the base \
                 mesh's faces, in the same order, or has none",
                at(pose),
                *face as u64 + pose.format.first_index(),
                *face as u64 + base.format.first_index(),
                at(base)
            )
        }
        PoseError::Mesh(m) => match pose.describe_error(m) {
            (Some(l), message) => anyhow::anyhow!("{}:{l}: {message}", pose.name),
            (None, message) => anyhow::anyhow!("{}: {message}", pose.name),
        },
        e => anyhow::anyhow!("{}: {e} ({})", pose.name, base.name),
    }
}
