//! `adaptcloth`: the command-line front end, a thin layer over the library.
//!
//! Exit codes: 0 the command completed; 1 the run diverged, failed or could not write its outputs;
//! 2 bad input (scene file, option, value); 130 interrupted.

use adaptcloth::eval::{self, ReferenceSettings};
use adaptcloth::scene::{self, LoadedScene, SceneError, EMBEDDED_SCENES};
use adaptcloth::sim::{self, RunOptions, RunStatus, Simulation};
use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(Parser)]
#[command(
    name = "adaptcloth",
    version,
    about = "Cloth simulation on an adaptive triangle mesh"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write frames, metrics.csv and summary.json.
    Run(RunArgs),
    /// List the scenes embedded in the binary.
    Scenes,
    /// Compute (or load from the cache) a scene's reference solution and report its error floor.
    Reference(ReferenceArgs),
    /// Run a list of configurations of a scene against the reference; write the comparison
    /// table, plots and reports.
    Compare(CompareArgs),
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
        #[arg(long, default_value = "docs/integrators.md")]
        docs: PathBuf,
    },
    /// Run the stability suite (bisection of the largest stable step, hard cases for every built
    /// strategy) and write its report.
    Stability {
        /// Report file.
        #[arg(long, default_value = "docs/stability.md")]
        out: PathBuf,
        /// Small sizes (the test sizes): a quick look, not the report.
        #[arg(long)]
        quick: bool,
    },
    /// Render one OBJ frame (cloth, edges visible) to a PNG, with a scene's obstacles if given.
    Render {
        /// The frame (OBJ, e.g. out/sphere-remesh/frames/frame_00018.obj).
        frame: PathBuf,
        /// The PNG to write.
        #[arg(long)]
        out: PathBuf,
        /// Scene file or embedded scene name whose obstacles are drawn too.
        #[arg(long)]
        scene: Option<String>,
        /// Picture size in pixels.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Picture size in pixels.
        #[arg(long, default_value_t = 480)]
        height: u32,
    },
    /// RMS and largest distance between the vertices of two frames of the same mesh (m).
    FrameDiff {
        /// First frame (OBJ).
        a: PathBuf,
        /// Second frame (OBJ).
        b: PathBuf,
    },
}

#[derive(clap::Args)]
struct ReportArgs {
    /// Comparison folders (written by `compare` or `merge`).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Also write DIR/results.md (and its plots under DIR/results/) over these comparisons.
    #[arg(long, value_name = "DIR")]
    write_docs: Option<PathBuf>,
    /// Extra markdown file included in results.md after the introduction (settings, costs).
    #[arg(long, value_name = "FILE")]
    docs_notes: Option<PathBuf>,
    /// The command to name in results.md as the one that regenerates it.
    #[arg(long, default_value = "scripts/results.sh")]
    docs_command: String,
}

/// Options of the reference shared by `reference` and `compare`.
#[derive(clap::Args, Clone)]
struct RefOpts {
    /// Reference grid (vertices per side).
    #[arg(long = "ref-resolution", default_value_t = 65)]
    ref_resolution: usize,
    /// Grid of the floor run compared against the reference.
    #[arg(long = "floor-resolution", default_value_t = 33)]
    floor_resolution: usize,
    /// Dynamic step factor of the reference and floor runs ("scene" keeps the scene's).
    #[arg(long = "ref-beta", default_value = "0.01")]
    ref_beta: String,
    /// Integrator of the reference and floor runs (default: the scene's).
    #[arg(long = "ref-integrator")]
    ref_integrator: Option<String>,
    /// Step until the first contact of the reference and floor runs, s ("scene" keeps the
    /// scene's; 0 = dynamic step from the start).
    #[arg(long = "ref-dt-initial", default_value = "0")]
    ref_dt_initial: String,
    /// Material-point sample grid (per side).
    #[arg(long, default_value_t = 64)]
    samples: usize,
    /// Reference cache folder.
    #[arg(long, default_value = "out/reference-cache")]
    cache: PathBuf,
    /// Recompute the reference even when it is cached.
    #[arg(long)]
    force_reference: bool,
}

#[derive(clap::Args)]
struct ReferenceArgs {
    /// Scene file (TOML) or embedded scene name. Default: sphere.
    scene: Option<String>,
    #[command(flatten)]
    reference: RefOpts,
    /// Simulated duration in seconds (overrides the scene).
    #[arg(long)]
    duration: Option<f64>,
    /// Override any scene key: --set section.key=value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Run the reference and the floor run in parallel (2) or one after the other (1).
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// No progress bars.
    #[arg(long)]
    quiet: bool,
}

#[derive(clap::Args)]
struct CompareArgs {
    /// Scene files or embedded scene names (default: sphere).
    scenes: Vec<String>,
    /// Compare the three source scenes: sphere, round_table, bunny.
    #[arg(long)]
    all_source_scenes: bool,
    /// Configurations: strategy[@resolution],... (default: static@5,static@9,static@17,static@33,
    /// remesh,simnett,bisect48; adaptive ones start at the scene's resolution). Strategies that are
    /// not built are skipped and listed in the report.
    #[arg(long)]
    runs: Option<String>,
    /// Integrators, comma-separated; every configuration runs with each (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    integrators: Vec<String>,
    #[command(flatten)]
    reference: RefOpts,
    /// Parallel runs.
    #[arg(long, default_value_t = 1)]
    jobs: usize,
    /// Run only slice i of n (1-based) of the configurations; combine with `adaptcloth merge`.
    #[arg(long)]
    shard: Option<String>,
    /// Output folder (one scene), or parent folder (several: one subfolder per scene).
    /// Default: out/compare-<scene>, or out/compare/<scene>.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Simulated duration in seconds (overrides the scene).
    #[arg(long)]
    duration: Option<f64>,
    /// Override any scene key for every run and the reference: --set section.key=value.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Also write DIR/results.md (and its plots under DIR/results/) over the compared scenes.
    #[arg(long, value_name = "DIR")]
    write_docs: Option<PathBuf>,
    /// Extra markdown file included in results.md after the introduction (settings, costs).
    #[arg(long, value_name = "FILE")]
    docs_notes: Option<PathBuf>,
    /// No progress bars.
    #[arg(long)]
    quiet: bool,
}

#[derive(clap::Args)]
struct MergeArgs {
    /// Folders written by `compare --shard i/n` (same scene, reference and configurations).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Output folder of the merged comparison.
    #[arg(long)]
    out: PathBuf,
}

#[derive(clap::Args)]
struct RunArgs {
    /// Scene file (TOML), or the name of an embedded scene (see `adaptcloth scenes`).
    /// Default: the embedded sphere scene.
    scene: Option<String>,
    /// Adaptivity strategy: static, remesh, simnett or bisect48 (overrides the scene).
    #[arg(long)]
    strategy: Option<String>,
    /// Integrator (overrides the scene): explicit_euler, symplectic_euler, velocity_verlet, verlet,
    /// time_corrected_verlet, verlet_relaxation, rk4, implicit_euler.
    #[arg(long)]
    integrator: Option<String>,
    /// Simulated duration in seconds (overrides the scene).
    #[arg(long)]
    duration: Option<f64>,
    /// Output folder. Default: out/<scene>-<strategy>.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Override any scene key: --set section.key=value (repeatable), e.g. --set cloth.resolution=17.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run(args) => run(args),
        Command::Reference(args) => reference(args),
        Command::Compare(args) => compare(args),
        Command::Merge(args) => merge(args),
        Command::Report(args) => report(args),
        Command::Scenes => {
            for (name, text) in EMBEDDED_SCENES {
                let description = text
                    .lines()
                    .find_map(|l| l.strip_prefix("description = "))
                    .unwrap_or("")
                    .trim_matches('"');
                println!("{name:12} {description}");
            }
            ExitCode::SUCCESS
        }
        Command::Integrators { write_docs, docs } => integrators(write_docs, &docs),
        Command::Stability { out, quick } => stability(&out, quick),
        Command::Render {
            frame,
            out,
            scene,
            width,
            height,
        } => match render_frame(&frame, &out, scene.as_deref(), width, height) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Command::FrameDiff { a, b } => match adaptcloth::output::frame_distance(&a, &b) {
            Ok((rms, max)) => {
                println!("rms {rms:.6e} m, max {max:.6e} m");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
    }
}

const TABLE_BEGIN: &str = "<!-- BEGIN integrators table (adaptcloth integrators --write-docs) -->";
const TABLE_END: &str = "<!-- END integrators table -->";

fn integrators(write_docs: bool, docs: &std::path::Path) -> ExitCode {
    use adaptcloth::physics::experiments;
    let mut table = experiments::markdown_table();
    table += "
**Observed convergence order** on the damped spring (`log2(e(n)/e(2n))` at t = 1 s, n = 400):

| integrator | order |\n|---|---|\n";
    for name in adaptcloth::physics::INTEGRATORS {
        if *name == "verlet_relaxation" {
            table += "| `verlet_relaxation` | - (rigid bars: converges to another problem) |\n";
            continue;
        }
        table += &format!(
            "| `{name}` | {:.3} |\n",
            experiments::observed_order(name, 400)
        );
    }
    print!("{table}");
    if !write_docs {
        return ExitCode::SUCCESS;
    }
    let text = match std::fs::read_to_string(docs) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: {e}", docs.display());
            return ExitCode::from(2);
        }
    };
    let (Some(a), Some(b)) = (text.find(TABLE_BEGIN), text.find(TABLE_END)) else {
        eprintln!(
            "error: {} lacks the markers {TABLE_BEGIN} ... {TABLE_END}",
            docs.display()
        );
        return ExitCode::from(2);
    };
    let new = format!("{}{TABLE_BEGIN}\n{table}\n{}", &text[..a], &text[b..]);
    write_report_file(docs, &new)
}

/// Writes a generated report atomically and says so; exit status 1 when it cannot be written.
fn write_report_file(path: &std::path::Path, text: &str) -> ExitCode {
    match adaptcloth::output::write_atomic(path, text.as_bytes()) {
        Ok(()) => {
            eprintln!("wrote {}", path.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: writing {}: {e}", path.display());
            ExitCode::from(1)
        }
    }
}

fn stability(out: &std::path::Path, quick: bool) -> ExitCode {
    use adaptcloth::study::stability::{self, CaseSizes, Search, REPORT_SEARCH};
    let (search, sizes) = if quick {
        (
            Search {
                resolution: 5,
                duration: 0.1,
                iterations: 4,
                ..REPORT_SEARCH
            },
            CaseSizes::QUICK,
        )
    } else {
        (REPORT_SEARCH, CaseSizes::REPORT)
    };
    let md = stability::report(&search, &sizes, |s| eprintln!("adaptcloth stability: {s}"));
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        let _ = std::fs::create_dir_all(dir);
    }
    write_report_file(out, &md)
}

fn run(args: RunArgs) -> ExitCode {
    let mut overrides = args.set.clone();
    if let Some(s) = &args.strategy {
        overrides.push(format!("adaptivity.strategy=\"{s}\""));
    }
    if let Some(i) = &args.integrator {
        overrides.push(format!("integrator.name=\"{i}\""));
    }
    if let Some(d) = args.duration {
        overrides.push(format!("time.duration={d:e}"));
    }
    let loaded = match load_scene(args.scene.as_deref(), &overrides) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut simulation = match Simulation::new(&loaded) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {}: {e}", loaded.source);
            return ExitCode::from(2);
        }
    };
    let out_dir = args.out.unwrap_or_else(|| {
        PathBuf::from("out").join(format!(
            "{}-{}",
            loaded.scene.name,
            simulation.strategy_name()
        ))
    });
    let interrupt = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupt.clone();
        // A second Ctrl-C while the first is being handled ends the process at once.
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    }
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        progress: !args.quiet && std::io::stderr().is_terminal(),
        interrupt: Some(interrupt),
        source: loaded.source.clone(),
        ..RunOptions::default()
    };
    eprintln!(
        "adaptcloth: {} ({}), strategy {}, integrator {}, {} vertices, {} s -> {}",
        loaded.scene.name,
        loaded.source,
        simulation.strategy_name(),
        simulation.integrator_name(),
        simulation.cloth.mesh.vertex_count(),
        loaded.scene.time.duration,
        out_dir.display()
    );
    match sim::run(&mut simulation, &opts) {
        Ok(summary) => {
            eprintln!(
                "{:?}: {} steps, t = {:.4} s, {} frames, {} vertices (max {}), max penetration {:.2e} m, wall {:.2} s",
                summary.status,
                summary.steps,
                summary.sim_time,
                summary.frames,
                summary.final_vertices,
                summary.max_vertices,
                summary.max_penetration,
                summary.wall_time_s
            );
            if !summary.message.is_empty() {
                eprintln!("{}", summary.message);
            }
            match summary.status {
                RunStatus::Completed => ExitCode::SUCCESS,
                RunStatus::Interrupted => ExitCode::from(130),
                RunStatus::Diverged | RunStatus::Failed => ExitCode::from(1),
            }
        }
        Err(e) => {
            eprintln!("error: writing outputs to {}: {e}", out_dir.display());
            ExitCode::from(1)
        }
    }
}

/// A scene file, else an embedded scene of that name, else the default scene.
/// `adaptcloth render`: one frame (and the scene's obstacles) to a PNG.
fn render_frame(
    frame: &std::path::Path,
    out: &std::path::Path,
    scene: Option<&str>,
    width: u32,
    height: u32,
) -> Result<(), String> {
    use adaptcloth::render;
    let mesh = render::read_obj_frame(frame).map_err(|e| e.to_string())?;
    let obstacles = match scene {
        Some(s) => {
            let loaded = load_scene(Some(s), &[]).map_err(|e| e.to_string())?;
            render::obstacle_meshes(&loaded.scene.obstacles, &loaded.base_dir)
                .map_err(|e| e.to_string())?
        }
        None => Vec::new(),
    };
    render::render_png(&mesh, &obstacles, width, height, out).map_err(|e| e.to_string())
}

fn load_scene(scene: Option<&str>, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    match scene {
        None => scene::load_default(overrides),
        Some(s) => {
            let path = PathBuf::from(s);
            if path.exists() {
                return scene::load(&path, overrides);
            }
            scene::load_embedded(s, overrides).unwrap_or_else(|| {
                Err(SceneError::Io {
                    path: s.to_string(),
                    source: std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        format!(
                            "no such file, and no embedded scene of that name (embedded: {})",
                            EMBEDDED_SCENES
                                .iter()
                                .map(|(n, _)| *n)
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ),
                })
            })
        }
    }
}

/// A Ctrl-C flag: the first press stops runs cleanly, a second ends the process.
fn interrupt_flag() -> Arc<AtomicBool> {
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = interrupt.clone();
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
    interrupt
}

fn scene_overrides(set: &[String], duration: Option<f64>) -> Vec<String> {
    let mut overrides = set.to_vec();
    if let Some(d) = duration {
        overrides.push(format!("time.duration={d:e}"));
    }
    overrides
}

fn reference_settings(o: &RefOpts) -> Result<ReferenceSettings, String> {
    let beta = match o.ref_beta.as_str() {
        "scene" => None,
        b => Some(
            b.parse::<f64>()
                .ok()
                .filter(|b| *b > 0.0 && b.is_finite())
                .ok_or_else(|| format!("--ref-beta {b}: expected a positive number or `scene`"))?,
        ),
    };
    let dt_initial = match o.ref_dt_initial.as_str() {
        "scene" => None,
        d => Some(
            d.parse::<f64>()
                .ok()
                .filter(|d| *d >= 0.0 && d.is_finite())
                .ok_or_else(|| {
                    format!("--ref-dt-initial {d}: expected a non-negative number or `scene`")
                })?,
        ),
    };
    if let Some(i) = &o.ref_integrator {
        adaptcloth::physics::integrator_named(i).map_err(|e| format!("--ref-integrator: {e}"))?;
    }
    for (name, v) in [
        ("--ref-resolution", o.ref_resolution),
        ("--floor-resolution", o.floor_resolution),
        ("--samples", o.samples),
    ] {
        if v < 2 {
            return Err(format!("{name} {v}: must be at least 2"));
        }
    }
    Ok(ReferenceSettings {
        resolution: o.ref_resolution,
        floor_resolution: o.floor_resolution,
        beta,
        integrator: o.ref_integrator.clone(),
        dt_initial,
        samples: o.samples,
    })
}

fn progress_target(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

fn reference(args: ReferenceArgs) -> ExitCode {
    let overrides = scene_overrides(&args.set, args.duration);
    let loaded = match load_scene(args.scene.as_deref(), &overrides) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let settings = match reference_settings(&args.reference) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let multi = indicatif::MultiProgress::with_draw_target(if progress_target(args.quiet) {
        indicatif::ProgressDrawTarget::stderr()
    } else {
        indicatif::ProgressDrawTarget::hidden()
    });
    let clock = std::time::Instant::now();
    match eval::ensure_reference(
        &loaded,
        &settings,
        &args.reference.cache,
        args.jobs,
        args.reference.force_reference,
        Some(&multi),
        Some(interrupt_flag()),
    ) {
        Ok(r) => {
            println!("{}", eval::reference::describe(&r));
            eprintln!("done in {:.1} s", clock.elapsed().as_secs_f64());
            ExitCode::SUCCESS
        }
        Err(e @ eval::reference::ReferenceError::Settings(_)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn compare(args: CompareArgs) -> ExitCode {
    let mut scenes = args.scenes.clone();
    if args.all_source_scenes {
        scenes.extend(["sphere", "round_table", "bunny"].map(String::from));
    }
    if scenes.is_empty() {
        scenes.push("sphere".into());
    }
    let settings = match reference_settings(&args.reference) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let shard = match args.shard.as_deref().map(str::parse::<eval::Shard>) {
        None => None,
        Some(Ok(s)) => Some(s),
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let notes = match &args.docs_notes {
        None => String::new(),
        Some(p) => match std::fs::read_to_string(p) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("error: {}: {e}", p.display());
                return ExitCode::from(2);
            }
        },
    };
    let overrides = scene_overrides(&args.set, args.duration);
    // Load and check everything before running anything.
    let mut plans = Vec::new();
    for name in &scenes {
        let loaded = match load_scene(Some(name), &overrides) {
            Ok(l) => l,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
        let configs = match &args.runs {
            None => match eval::parse_configs(
                "static@5,static@9,static@17,static@33,remesh,simnett,bisect48",
                &loaded.scene,
                &args.integrators,
            ) {
                Ok(c) => c,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(2);
                }
            },
            Some(spec) => match eval::parse_configs(spec, &loaded.scene, &args.integrators) {
                Ok(c) => c,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(2);
                }
            },
        };
        let out = match (&args.out, scenes.len()) {
            (Some(o), 1) => o.clone(),
            (Some(o), _) => o.join(&loaded.scene.name),
            (None, 1) => PathBuf::from("out").join(format!("compare-{}", loaded.scene.name)),
            (None, _) => PathBuf::from("out")
                .join("compare")
                .join(&loaded.scene.name),
        };
        plans.push((loaded, configs, out));
    }
    let interrupt = interrupt_flag();
    let mut done = Vec::new();
    for (loaded, configs, out) in plans {
        let clock = std::time::Instant::now();
        eprintln!(
            "adaptcloth compare: {} ({}), {} configuration(s){} -> {}",
            loaded.scene.name,
            loaded.source,
            configs.len(),
            shard.map(|s| format!(", shard {s}")).unwrap_or_default(),
            out.display()
        );
        let opts = eval::CompareOptions {
            configs,
            jobs: args.jobs.max(1),
            shard,
            out_dir: out.clone(),
            reference: settings.clone(),
            cache_dir: args.reference.cache.clone(),
            force_reference: args.reference.force_reference,
            progress: progress_target(args.quiet),
            interrupt: Some(interrupt.clone()),
        };
        let comparison = match eval::compare(&loaded, &opts) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(match e {
                    eval::CompareError::Config(_) => 2,
                    _ => 1,
                });
            }
        };
        if let Err(e) = eval::write_report(&out, &comparison) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
        eprintln!(
            "{}: {} run(s) in {:.1} s; report: {}",
            loaded.scene.name,
            comparison.rows.len(),
            clock.elapsed().as_secs_f64(),
            out.join("report.md").display()
        );
        if interrupt.load(Ordering::SeqCst) {
            return ExitCode::from(130);
        }
        done.push((out, comparison));
    }
    if let Some(dir) = &args.write_docs {
        let command = std::env::args().skip(1).collect::<Vec<_>>().join(" ");
        match eval::write_docs(dir, &done, &format!("adaptcloth {command}"), &notes) {
            Ok(p) => eprintln!("wrote {}", p.display()),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(1);
            }
        }
    }
    ExitCode::SUCCESS
}

fn merge(args: MergeArgs) -> ExitCode {
    let comparison = match eval::merge(&args.dirs, &args.out) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(match e {
                eval::CompareError::Merge(_) | eval::CompareError::Config(_) => 2,
                _ => 1,
            });
        }
    };
    match eval::write_report(&args.out, &comparison) {
        Ok(_) => {
            eprintln!(
                "merged {} run(s) from {} folder(s); report: {}",
                comparison.rows.len(),
                args.dirs.len(),
                args.out.join("report.md").display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn report(args: ReportArgs) -> ExitCode {
    let mut done = Vec::new();
    for dir in &args.dirs {
        let comparison = match eval::compare::read_comparison(dir) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
        if let Err(e) = eval::write_report(dir, &comparison) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
        eprintln!("{}", dir.join("report.md").display());
        done.push((dir.clone(), comparison));
    }
    if let Some(docs) = &args.write_docs {
        let notes = match &args.docs_notes {
            None => String::new(),
            Some(p) => match std::fs::read_to_string(p) {
                Ok(t) => t,
                Err(e) => {
                    eprintln!("error: {}: {e}", p.display());
                    return ExitCode::from(2);
                }
            },
        };
        match eval::write_docs(docs, &done, &args.docs_command, &notes) {
            Ok(p) => eprintln!("wrote {}", p.display()),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(1);
            }
        }
    }
    ExitCode::SUCCESS
}
