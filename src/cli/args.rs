//! The command line's arguments (clap): one struct per command. `src/main.rs` parses them and
//! [`super::execute`] runs the command.

use crate::eval::reference::{MAX_GRID_SIDE, MAX_SAMPLES};
use crate::report::render::MAX_SIDE;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// `adaptcloth`: the commands.
#[derive(Parser)]
#[command(
    name = "adaptcloth",
    version,
    about = "Cloth simulation on an adaptive triangle mesh"
)]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
    /// Threads of each run's force sweeps (default: RAYON_NUM_THREADS if set, else the cores
    /// shared among the command's parallel runs, cores / --jobs). The results do not depend on
    /// it, only the wall times.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub threads: Option<u16>,
}

impl Command {
    /// How many runs the command makes at once (its `--jobs`; 1 for the others).
    pub fn parallel_runs(&self) -> usize {
        match self {
            Command::Study(a) => a.execution.jobs,
            Command::Compare(a) => a.execution.jobs,
            Command::Reference(a) => a.jobs,
            _ => 1,
        }
    }
}

/// One command of the binary.
#[derive(Subcommand)]
pub enum Command {
    /// Run a scene and write frames, metrics.csv and summary.json.
    Run(RunArgs),
    /// List the scenes embedded in the binary.
    Scenes,
    /// Compute (or load from the cache) a scene's reference solution and report its error floor.
    Reference(ReferenceArgs),
    /// Run a list of configurations of a scene against the reference; write the comparison
    /// table, plots and reports.
    Compare(CompareArgs),
    /// Run a study file (scenes, reference, runs and sweeps in TOML; see docs/studies.md): one
    /// comparison and report per scene.
    Study(StudyArgs),
    /// Combine the folders of `compare --shard i/n` runs into one comparison and report.
    Merge(MergeArgs),
    /// Rewrite the plots and reports of existing comparison folders (no run), optionally
    /// docs/results.md over them.
    Report(ReportArgs),
    /// Seed 004's single-particle integrator experiments (Tables 2-5) beside the source's numbers,
    /// and the observed convergence orders on a damped spring.
    Integrators {
        /// Also write the tables into docs/integrators.md (between its generated-table markers).
        #[arg(long)]
        write_docs: bool,
        /// The document to update with --write-docs.
        #[arg(long, default_value = "docs/integrators.md", requires = "write_docs")]
        docs: PathBuf,
    },
    /// Run the stability suite (bisection of the largest stable step, hard cases for every built
    /// strategy) and write its report.
    Stability {
        /// Report file. Default: docs/stability.md, or out/stability-quick.md with --quick.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Small sizes (the test sizes): a quick look, not the report (never written to docs/
        /// unless --out says so).
        #[arg(long)]
        quick: bool,
        /// Only this strategy (the step bisection and the hard cases on it); the report then
        /// goes to out/stability[-quick]-STRATEGY.md unless --out says so.
        #[arg(long)]
        strategy: Option<String>,
    },
    /// Render one OBJ frame (cloth, edges visible) to a PNG, with a scene's obstacles if given.
    Render(RenderArgs),
    /// RMS and largest distance between the vertices of two frames of the same mesh (m). The
    /// frames must have the same vertices, faces and rest coordinates (`vt`), else exit 2 saying
    /// what differs.
    FrameDiff {
        /// First frame (OBJ).
        a: PathBuf,
        /// Second frame (OBJ).
        b: PathBuf,
    },
}

/// `adaptcloth report`.
#[derive(clap::Args)]
pub struct ReportArgs {
    /// Comparison folders (written by `compare` or `merge`).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// results.md over these comparisons.
    #[command(flatten)]
    pub docs: DocsArgs,
    /// The command to name in results.md as the one that regenerates it (with --write-docs).
    #[arg(
        long,
        requires = "write_docs",
        default_value = "adaptcloth study studies/results.toml --jobs 2 --write-docs docs --docs-notes studies/results-notes.md"
    )]
    pub docs_command: String,
}

/// Options of the reference shared by `reference` and `compare`.
#[derive(clap::Args, Clone)]
pub struct RefOpts {
    /// Reference grid (vertices per side, 2 to 2000).
    #[arg(long = "ref-resolution", default_value_t = 65, value_parser = count_in(MAX_GRID_SIDE))]
    pub ref_resolution: usize,
    /// Grid of the floor run compared against the reference (2 to 2000, below the reference's).
    #[arg(long = "floor-resolution", default_value_t = 33, value_parser = count_in(MAX_GRID_SIDE))]
    pub floor_resolution: usize,
    /// Dynamic step factor of the reference and floor runs ("scene" keeps the scene's).
    #[arg(long = "ref-beta", default_value = "0.01")]
    pub ref_beta: String,
    /// Integrator of the reference and floor runs (default: the scene's).
    #[arg(long = "ref-integrator")]
    pub ref_integrator: Option<String>,
    /// Step until the first contact of the reference and floor runs, s ("scene" keeps the
    /// scene's; 0 = dynamic step from the start).
    #[arg(long = "ref-dt-initial", default_value = "0")]
    pub ref_dt_initial: String,
    /// A fixed step of the reference and floor runs, s, instead of the dynamic one (then
    /// --ref-beta and --ref-dt-initial go unused).
    #[arg(long = "ref-dt")]
    pub ref_dt: Option<String>,
    /// Material-point sample grid (points per side, 2 to 1000).
    #[arg(long, default_value_t = 64, value_parser = count_in(MAX_SAMPLES))]
    pub samples: usize,
    /// Reference cache folder.
    #[arg(long, default_value = "out/reference-cache")]
    pub cache: PathBuf,
    /// Recompute the reference even when it is cached.
    #[arg(long)]
    pub force_reference: bool,
}

/// `adaptcloth reference`.
#[derive(clap::Args)]
pub struct ReferenceArgs {
    /// Scene file (TOML) or embedded scene name. Default: sphere.
    pub scene: Option<String>,
    /// The reference's options.
    #[command(flatten)]
    pub reference: RefOpts,
    /// Simulated duration in seconds (overrides the scene).
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Override any scene key: --set section.key=value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// 1: the reference and its floor run one after the other; 2 or more (up to 1024, like
    /// compare's): side by side, two runs at most. The cores are shared among --jobs runs for
    /// their threads (see --threads).
    #[arg(long, default_value_t = 2, value_parser = jobs_parser())]
    pub jobs: usize,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
}

/// `adaptcloth compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// Scene files or embedded scene names (default: sphere).
    pub scenes: Vec<String>,
    /// Compare the three source scenes: sphere, round_table, bunny.
    #[arg(long)]
    pub all_source_scenes: bool,
    /// Configurations: strategy[@resolution],... (default: static@5,static@9,static@17,static@33,
    /// remesh,simnett,bisect48; adaptive ones start at the scene's resolution).
    #[arg(long)]
    pub runs: Option<String>,
    /// Integrators, comma-separated; every configuration runs with each (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    pub integrators: Vec<String>,
    /// The reference's options.
    #[command(flatten)]
    pub reference: RefOpts,
    /// How the runs are executed.
    #[command(flatten)]
    pub execution: ExecutionArgs,
    /// Output folder (one scene), or parent folder (several: one subfolder per scene).
    /// Default: out/compare-<scene>, or out/compare/<scene>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Simulated duration in seconds (overrides the scene).
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Override any scene key for every run and the reference: --set section.key=value.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// results.md over the compared scenes.
    #[command(flatten)]
    pub docs: DocsArgs,
}

/// How the runs of a study are executed (`compare`, `study`).
#[derive(clap::Args)]
pub struct ExecutionArgs {
    /// Parallel runs (1 to 1024).
    #[arg(long, default_value_t = 1, value_parser = jobs_parser())]
    pub jobs: usize,
    /// Run only slice i of n (1-based) of the configurations; combine with `adaptcloth merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
    /// Run every run even when it is estimated at more than 1e8 steps (its dynamic step at the
    /// start against the duration); without it the study exits 2 with the estimate before
    /// anything runs. The reference and floor runs are always checked.
    #[arg(long)]
    pub force: bool,
}

/// `--write-docs` and `--docs-notes`.
#[derive(clap::Args)]
pub struct DocsArgs {
    /// Also write DIR/results.md (and its plots under DIR/results/) over the comparisons.
    #[arg(long, value_name = "DIR")]
    pub write_docs: Option<PathBuf>,
    /// Extra markdown file included in results.md after the introduction (settings, costs);
    /// only with --write-docs.
    #[arg(long, value_name = "FILE", requires = "write_docs")]
    pub docs_notes: Option<PathBuf>,
}

/// `adaptcloth study`.
#[derive(clap::Args)]
pub struct StudyArgs {
    /// The study file (TOML; format in docs/studies.md). Without it, the embedded quick study
    /// (studies/quick.toml): the four strategies head to head on the sphere, with --jobs 2 on 2
    /// cores in about 40 s the first time (it computes its reference) and about 4 s after.
    pub file: Option<PathBuf>,
    /// How the runs are executed.
    #[command(flatten)]
    pub execution: ExecutionArgs,
    /// Output folder; each scene's comparison goes to a subfolder named after the scene.
    /// Default: out/study-<name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Reference cache folder.
    #[arg(long, default_value = "out/reference-cache")]
    pub cache: PathBuf,
    /// Recompute the references even when they are cached.
    #[arg(long)]
    pub force_reference: bool,
    /// Only compute (or check) each scene's reference in the cache, then stop: run this once
    /// before the shards of a study so they do not all compute it.
    #[arg(long)]
    pub references_only: bool,
    /// results.md over the study's scenes.
    #[command(flatten)]
    pub docs: DocsArgs,
}

/// `adaptcloth merge`.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Folders written by `compare --shard i/n` (same scene, reference and configurations).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output folder of the merged comparison: not one of the input folders, nor inside one.
    #[arg(long)]
    pub out: PathBuf,
}

/// `adaptcloth run`.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Scene file (TOML), or the name of an embedded scene (see `adaptcloth scenes`).
    /// Default: the embedded sphere scene.
    pub scene: Option<String>,
    /// Adaptivity strategy: static, remesh, simnett or bisect48 (overrides the scene).
    #[arg(long)]
    pub strategy: Option<String>,
    /// Integrator (overrides the scene): explicit_euler, symplectic_euler, velocity_verlet, verlet,
    /// time_corrected_verlet, verlet_relaxation, rk4, implicit_euler, bdf2.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Simulated duration in seconds (overrides the scene).
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Output folder. Default: out/<scene>-<strategy>.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override any scene key: --set section.key=value (repeatable), e.g. --set cloth.resolution=17.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Run even when the run is estimated at more than 1e8 steps (the dynamic step at the start
    /// against the duration); without it such a run exits 2 with the estimate.
    #[arg(long)]
    pub force: bool,
}

/// `adaptcloth render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// The frame (OBJ, e.g. out/sphere-remesh/frames/frame_00018.obj).
    pub frame: PathBuf,
    /// The PNG to write (its name must end in .png: no other format is written).
    #[arg(long)]
    pub out: PathBuf,
    /// Scene file or embedded scene name whose obstacles are drawn too. Default: the
    /// `scene.resolved.toml` the run wrote beside the frame's `frames/` folder, if any.
    #[arg(long)]
    pub scene: Option<String>,
    /// Picture width in pixels (1 to 16384; at most 4096x4096 pixels in all).
    #[arg(long, default_value_t = 640, value_parser = picture_side())]
    pub width: u32,
    /// Picture height in pixels (1 to 16384; at most 4096x4096 pixels in all).
    #[arg(long, default_value_t = 480, value_parser = picture_side())]
    pub height: u32,
}

/// A grid side or sample count: 2 to `max`.
fn count_in(max: usize) -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::<usize>::new().range(2..=max as u64)
}

/// `--width` and `--height`: 1 to [`MAX_SIDE`] pixels, the sizes a picture can be drawn at.
fn picture_side() -> clap::builder::RangedU64ValueParser<u32> {
    clap::builder::RangedU64ValueParser::<u32>::new().range(1..=u64::from(MAX_SIDE))
}

/// `--jobs`: 1 to 1024 runs at once (0 is refused, not read as 1).
fn jobs_parser() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::<usize>::new().range(1..=1024)
}
