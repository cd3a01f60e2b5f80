//! `adaptcloth`: the command-line front end, a thin layer over the library.
//!
//! Exit codes: 0 the command completed; 1 the run diverged, failed or could not write its outputs;
//! 2 bad input (scene file, option, value); 130 interrupted.

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
    /// RMS and largest distance between the vertices of two frames of the same mesh (m).
    FrameDiff {
        /// First frame (OBJ).
        a: PathBuf,
        /// Second frame (OBJ).
        b: PathBuf,
    },
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
    match adaptcloth::output::write_atomic(docs, new.as_bytes()) {
        Ok(()) => {
            eprintln!("wrote {}", docs.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: writing {}: {e}", docs.display());
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
    match adaptcloth::output::write_atomic(out, md.as_bytes()) {
        Ok(()) => {
            eprintln!("wrote {}", out.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: writing {}: {e}", out.display());
            ExitCode::from(1)
        }
    }
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
