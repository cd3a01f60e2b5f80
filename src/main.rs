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
}

#[derive(clap::Args)]
struct RunArgs {
    /// Scene file (TOML), or the name of an embedded scene (see `adaptcloth scenes`).
    /// Default: the embedded sphere scene.
    scene: Option<String>,
    /// Adaptivity strategy: static, remesh, simnett or bisect48 (overrides the scene).
    #[arg(long)]
    strategy: Option<String>,
    /// Integrator (overrides the scene), e.g. rk4 or symplectic_euler.
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
