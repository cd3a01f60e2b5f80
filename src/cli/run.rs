//! `run`, `scenes`, `render` and `frame-diff`: one scene, one frame.

use super::args::{RenderArgs, RunArgs};
use super::{interrupt_flag, output_folder, show_progress, CliError};
use crate::console::clip;
use crate::report::render::{obstacle_meshes, render_png, FrameMesh};
use crate::scene::{self, Overrides, Setting, EMBEDDED_SCENES};
use crate::sim::{self, RunOptions, RunStatus, SetupError, Simulation};
use std::path::{Path, PathBuf};

/// `adaptcloth run`: one scene to its duration, outputs in `--out`.
pub fn run(args: RunArgs) -> Result<(), CliError> {
    let overrides = Overrides {
        set: Setting::options(&args.set),
        strategy: args.strategy,
        integrator: args.integrator,
        duration: args.duration,
    };
    let loaded = scene::resolve(args.scene.as_deref(), &overrides)?;
    loaded.check_run()?;
    let setup = |e| match e {
        SetupError::OffPattern { .. } | SetupError::Scene(_) => CliError::Input(e.to_string()),
        e => CliError::Input(format!("{}: {e}", loaded.source)),
    };
    let mut simulation = Simulation::new(&loaded).map_err(setup)?;
    if !args.force {
        simulation
            .check_step_estimate()
            .map_err(|e| CliError::Input(format!("{}: {e}; {}", loaded.source, sim::FORCE_HINT)))?;
    }
    let out_dir = match args.out {
        Some(dir) => dir,
        None => {
            let name = format!("{}-{}", loaded.scene.name, simulation.strategy_name());
            let remedy = ", or give --out to name the folder yourself";
            loaded.check_folder_name(&name, remedy)?;
            PathBuf::from("out").join(name)
        }
    };
    output_folder(&out_dir)?;
    let command = sim::this_command();
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        progress: show_progress(args.quiet),
        interrupt: Some(interrupt_flag()),
        source: loaded.source.clone(),
        resolved_scene: Some(scene::resolved_toml(&loaded, &command)),
        command,
        ..RunOptions::default()
    };
    crate::note!(
        "adaptcloth: {} ({}), strategy {}, integrator {}, {} vertices, {} s -> {}",
        clip(&loaded.scene.name),
        clip(&loaded.source),
        simulation.strategy_name(),
        simulation.integrator_name(),
        simulation.cloth.mesh.vertex_count(),
        loaded.scene.time.duration,
        clip(&out_dir.to_string_lossy())
    );
    for note in [loaded.run_alone_note(), simulation.dynamic_step_note()]
        .into_iter()
        .flatten()
    {
        crate::note!("{note}");
    }
    let s = sim::run(&mut simulation, &opts)
        .map_err(|e| CliError::Failed(format!("writing outputs to {}: {e}", out_dir.display())))?;
    crate::note!(
        "{:?}: {} steps, t = {:.4} s, {} frame{}, {} vertices (max {}), max penetration {:.2e} m (surface {:.2e} m), {} self-intersections, wall {:.2} s",
        s.status, s.steps, s.sim_time, s.frames, if s.frames == 1 { "" } else { "s" },
        s.final_vertices, s.max_vertices,
        s.max_penetration, s.max_surface_penetration, s.max_self_intersections, s.wall_time_s
    );
    match s.status {
        RunStatus::Completed => Ok(()),
        RunStatus::Interrupted => Err(CliError::Interrupted(s.message)),
        RunStatus::Diverged | RunStatus::Failed => Err(CliError::Failed(s.message)),
    }
}

/// `adaptcloth scenes`: the embedded scenes with their descriptions.
pub fn scenes() -> Result<(), CliError> {
    let width = EMBEDDED_SCENES.iter().map(|(name, _)| name.len()).max();
    for (name, text) in EMBEDDED_SCENES {
        let description = text
            .lines()
            .find_map(|l| l.strip_prefix("description = "))
            .unwrap_or("")
            .trim_matches('"');
        crate::say!("{name:width$}  {description}", width = width.unwrap_or(0));
    }
    Ok(())
}

/// `adaptcloth render`: one frame (and the scene's obstacles) to a PNG.
pub fn render(args: RenderArgs) -> Result<(), CliError> {
    let input = |e: &dyn std::fmt::Display| CliError::Input(e.to_string());
    if !args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(CliError::Input(format!(
            "--out {}: expected a file name ending in .png (render writes PNG pictures only)",
            args.out.display()
        )));
    }
    let mesh = FrameMesh::read(&args.frame).map_err(|e| input(&e))?;
    super::check_report_path(&args.out)?;
    // Without --scene, the scene the run recorded beside its frames folder.
    let recorded = args
        .frame
        .parent()
        .and_then(Path::parent)
        .map(|run| run.join("scene.resolved.toml"))
        .filter(|p| p.is_file())
        .map(|p| p.display().to_string());
    let obstacles = match args.scene.as_ref().or(recorded.as_ref()) {
        Some(s) => {
            let loaded = scene::resolve(Some(s), &Overrides::default())?;
            obstacle_meshes(&loaded.scene.obstacles, &loaded.base_dir).map_err(|e| input(&e))?
        }
        None => Default::default(),
    };
    // Moving obstacles where they stand at the frame's time (its header; 0 without one).
    let t = crate::io::read_frame_time(&args.frame)
        .ok()
        .flatten()
        .unwrap_or(0.0);
    let obstacles = obstacles.at(t);
    render_png(&mesh, &obstacles, args.width, args.height, &args.out).map_err(|e| input(&e))
}

/// `adaptcloth frame-diff`: RMS and largest distance between the vertices of two frames.
pub fn frame_diff(a: &Path, b: &Path) -> Result<(), CliError> {
    let (rms, max) =
        crate::eval::frame_distance(a, b).map_err(|e| CliError::Input(e.to_string()))?;
    crate::say!("rms {rms:.6e} m, max {max:.6e} m");
    Ok(())
}
