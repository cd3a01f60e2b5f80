//! The commands of the `adaptcloth` binary. `src/main.rs` parses the arguments ([`args`]) and
//! calls [`execute`]; every command returns `Result<(), CliError>`, and [`CliError::exit_code`] is
//! the one place errors become exit codes: 0 done; 1 a run diverged or failed, or outputs could
//! not be written; 2 bad input (scene file, option, value, input file); 130 interrupted.
//!
//! Files: `args` (clap), `run` (run, scenes, render, frame-diff), `compare` (reference, compare,
//! merge, report), `suites` (integrators, stability).

pub mod args;
mod compare;
mod run;
mod suites;

use crate::eval::reference::ReferenceError;
use crate::report::ReportError;
use crate::scene::SceneError;
use crate::sim::RunStatus;
use crate::study::StudyError;
use args::Command;
use std::io::IsTerminal;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

/// Why a command did not complete; the variant decides the exit code.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad input: a scene, an option, a value or an input file (exit 2).
    #[error("{0}")]
    Input(String),
    /// A run diverged or failed, or outputs could not be written (exit 1).
    #[error("{0}")]
    Failed(String),
    /// Stopped by Ctrl-C (exit 130); the message may be empty.
    #[error("{0}")]
    Interrupted(String),
}

impl CliError {
    /// The process exit code of this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failed(_) => 1,
            CliError::Interrupted(_) => 130,
        }
    }
}

impl From<SceneError> for CliError {
    fn from(e: SceneError) -> Self {
        CliError::Input(e.to_string())
    }
}

impl From<StudyError> for CliError {
    fn from(e: StudyError) -> Self {
        match e {
            StudyError::Config(_) | StudyError::Merge(_) | StudyError::Scene(_) => {
                CliError::Input(e.to_string())
            }
            StudyError::Reference(r) => r.into(),
            StudyError::Io { .. } => CliError::Failed(e.to_string()),
            StudyError::Interrupted(_) => CliError::Interrupted(e.to_string()),
        }
    }
}

impl From<ReferenceError> for CliError {
    fn from(e: ReferenceError) -> Self {
        match e {
            ReferenceError::Settings(_) => CliError::Input(e.to_string()),
            // Stopped by a signal: the command was interrupted, nothing failed.
            ReferenceError::RunFailed {
                status: RunStatus::Interrupted,
                ..
            } => CliError::Interrupted(e.to_string()),
            _ => CliError::Failed(e.to_string()),
        }
    }
}

impl From<ReportError> for CliError {
    fn from(e: ReportError) -> Self {
        CliError::Failed(e.to_string())
    }
}

/// Runs one command.
pub fn execute(command: Command) -> Result<(), CliError> {
    match command {
        Command::Run(a) => run::run(a),
        Command::Scenes => run::scenes(),
        Command::Render(a) => run::render(a),
        Command::FrameDiff { a, b } => run::frame_diff(&a, &b),
        Command::Reference(a) => compare::reference(a),
        Command::Compare(a) => compare::compare(a),
        Command::Study(a) => compare::study(a),
        Command::Merge(a) => compare::merge(a),
        Command::Report(a) => compare::report(a),
        Command::Integrators { write_docs, docs } => suites::integrators(write_docs, &docs),
        Command::Stability {
            out,
            quick,
            strategy,
        } => suites::stability(out.as_deref(), quick, strategy.as_deref()),
    }
}

/// Sizes the process's thread pool, which runs the force sweeps of large meshes: `threads` if
/// given, else `RAYON_NUM_THREADS` if set, else the cores divided among `parallel_runs` runs (at
/// least one thread). Call once, before any run.
pub fn configure_threads(threads: Option<u16>, parallel_runs: usize) {
    let count = match threads {
        Some(n) => usize::from(n),
        None if std::env::var_os("RAYON_NUM_THREADS").is_some() => return,
        None => {
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            (cores / parallel_runs.max(1)).max(1)
        }
    };
    if let Err(e) = rayon::ThreadPoolBuilder::new()
        .num_threads(count)
        .build_global()
    {
        crate::note!("warning: the thread pool was not resized to {count} threads: {e}");
    }
}

/// Signals this soon after the first count as the same interrupt: `timeout -s INT` sends its
/// signal to the command and again to its process group, and a terminal may do the like.
const REPEATED_SIGNAL: Duration = Duration::from_secs(1);

/// The process's one interrupt flag, set by Ctrl-C (SIGINT), SIGTERM and SIGHUP alike (the
/// `ctrlc` crate's `termination` feature): the first signal asks runs to stop cleanly (status
/// `interrupted`, summary written, exit 130 whichever signal it was); another one at least a
/// second later ends the process at once (exit 130, saying so), one sooner is the same interrupt.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let handler_flag = flag.clone();
        let first = OnceLock::new();
        let _ = ctrlc::set_handler(move || {
            let at = *first.get_or_init(Instant::now);
            if handler_flag.swap(true, Ordering::SeqCst) && at.elapsed() >= REPEATED_SIGNAL {
                crate::note!("interrupted again: exiting at once; this run's output is incomplete");
                std::process::exit(130);
            }
        });
        flag
    })
    .clone()
}

/// Whether to draw progress bars: not `--quiet`, and stderr is a terminal.
fn show_progress(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

/// Writes a generated report atomically and says so.
fn write_report_file(path: &Path, text: &str) -> Result<(), CliError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::Failed(format!("creating {}: {e}", dir.display())))?;
    }
    crate::io::write_atomic(path, text.as_bytes())
        .map_err(|e| CliError::Failed(format!("writing {}: {e}", path.display())))?;
    crate::note!("wrote {}", path.display());
    Ok(())
}

/// Checks, before a long suite runs or a picture is drawn, that its file can be written at
/// `path` (exit 2 naming `--out` otherwise: a folder or device in the way, a missing permission): creates the parent
/// folder and writes and removes the temporary file the final write will use.
fn check_report_path(path: &Path) -> Result<(), CliError> {
    let refuse = |why: String| CliError::Input(format!("--out {}: {why}", path.display()));
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            let why = in_the_way(dir).unwrap_or_else(|| e.to_string());
            refuse(format!("cannot create its folder: {why}"))
        })?;
    }
    if let Ok(meta) = std::fs::metadata(path) {
        if !meta.is_file() {
            return Err(refuse("is not a regular file".into()));
        }
    }
    let tmp = crate::io::temp_path(path);
    std::fs::write(&tmp, b"").map_err(|e| refuse(format!("cannot be written: {e}")))?;
    let _ = std::fs::remove_file(&tmp);
    Ok(())
}

/// Creates the output folder `dir` of `--out` and checks that files can be written in it
/// ([`writable_folder`]).
fn output_folder(dir: &Path) -> Result<(), CliError> {
    writable_folder("--out", "output folder", dir)
}

/// Creates the reference cache folder `dir` of `--cache` and checks that files can be written
/// in it ([`writable_folder`]).
fn cache_folder(dir: &Path) -> Result<(), CliError> {
    writable_folder("--cache", "cache folder", dir)
}

/// Creates the folder `dir` that `option` names (`what` it is for) and writes and removes a file
/// in it, so that a command refuses an unusable folder (exit 2 naming the option) before it runs
/// anything: a file or device in the way (`dir` or one of its parents), no permission, a
/// read-only or pseudo file system (`/proc`).
fn writable_folder(option: &str, what: &str, dir: &Path) -> Result<(), CliError> {
    let refuse = |why: String| CliError::Input(format!("{option} {}: {why}", dir.display()));
    std::fs::create_dir_all(dir).map_err(|e| {
        let why = in_the_way(dir).unwrap_or_else(|| e.to_string());
        refuse(format!("cannot create the {what}: {why}"))
    })?;
    let probe = dir.join(format!(".adaptcloth-probe-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(&probe)
        .map_err(|e| refuse(format!("cannot write in the {what}: {e}")))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// What keeps `dir` from being a folder: `dir` itself or one of its parents that exists and is
/// not a folder (a file, device, pipe or socket), said in words; `None` when nothing is.
fn in_the_way(dir: &Path) -> Option<String> {
    let f = dir.ancestors().find(|a| a.exists() && !a.is_dir())?;
    let kind = if f.is_file() {
        "a file"
    } else {
        "a device, pipe or socket"
    };
    Some(if f == dir {
        format!("it is {kind}, not a folder")
    } else {
        format!("{} is {kind}, not a folder", f.display())
    })
}

/// Refuses an output folder `dir` of `option` that cannot be one ([`in_the_way`]) without
/// creating anything (a command that checks its inputs first creates it later).
fn not_in_the_way(option: &str, dir: &Path) -> Result<(), CliError> {
    match in_the_way(dir) {
        Some(why) => Err(CliError::Input(format!(
            "{option} {}: {why}",
            dir.display()
        ))),
        None => Ok(()),
    }
}

/// The text of an input file (exit 2 when it cannot be read).
fn read_input(path: &Path) -> Result<String, CliError> {
    crate::io::read_text(path).map_err(|e| CliError::Input(format!("{}: {e}", path.display())))
}
