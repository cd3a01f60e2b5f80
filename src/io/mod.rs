//! Files: the one OBJ reader and writer ([`obj`]), the files built into the binary (under
//! `<embedded>/`: the embedded scenes' meshes), the metrics table a run streams
//! ([`MetricsWriter`]), numeric CSV reading, and whole-file atomic writes. Every file is written
//! so that a partially written file never looks complete: whole files go through a temporary name
//! and a rename ([`write_atomic`]); the streamed metrics table is `metrics.csv.partial` until the
//! run ends (whatever its status), then renamed to `metrics.csv`.
//!
//! Where it sits: at the bottom, beside `math`: it knows file formats, not meshes or physics.

mod decimal;
mod embedded;
mod metrics;
pub mod obj;

pub use embedded::{embedded_text, is_embedded_path, EMBEDDED_DIR};
pub use metrics::{MetricsRow, MetricsWriter};
pub use obj::{
    frame_path, is_frame_name, read_frame_time, read_obj, write_frame, ObjError, ObjFile,
};

use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` through a temporary file in the same folder ([`temp_path`]), synced
/// to the disk, and a rename. On failure (a full disk, a folder in the way) the temporary file is
/// removed and `path` is left as it was: never a partly written file under the final name.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_through_temp(path, bytes, true)
}

/// [`write_atomic`] without the sync: the rename still never shows a torn file to this or any
/// other process (a Ctrl-C, a signal, a divergence or a full disk at the write), but a power cut
/// may lose the last files. For the frames a run writes by the dozen, where a sync costs more
/// than the step that made them (about 2.5 ms a frame on this machine's disk).
pub fn write_atomic_unsynced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_through_temp(path, bytes, false)
}

fn write_through_temp(path: &Path, bytes: &[u8], sync: bool) -> std::io::Result<()> {
    refuse_special(path)?;
    let tmp = temp_path(path);
    let written = create_for_writing(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        if sync {
            f.sync_all()
        } else {
            f.flush()
        }
    });
    let result = written.and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Refuses an existing `path` (symbolic links followed) that is not a regular file: the rename
/// of an atomic write would replace a device such as `/dev/full` (as root, for every program) or
/// a pipe with a plain file.
fn refuse_special(path: &Path) -> std::io::Result<()> {
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{} is {}, not a file to write",
                path.display(),
                if meta.is_dir() {
                    "a folder"
                } else {
                    "a device, pipe or socket"
                }
            ),
        )),
        _ => Ok(()),
    }
}

/// Creates (or truncates) `path` for writing. An existing pipe or socket there (symbolic links
/// followed) is refused before it is opened: opening a pipe with no reader waits for one for
/// ever, and no signal ends that wait. A device is opened as asked (a link to `/dev/full` is how
/// the tests fill the disk).
pub(crate) fn create_for_writing(path: &Path) -> std::io::Result<std::fs::File> {
    #[cfg(unix)]
    if let Ok(meta) = std::fs::metadata(path) {
        use std::os::unix::fs::FileTypeExt;
        let kind = meta.file_type();
        if kind.is_fifo() || kind.is_socket() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!(
                    "{} is a pipe or socket, not a file to write",
                    path.display()
                ),
            ));
        }
    }
    std::fs::File::create(path)
}

/// The text of the regular file `path`, or of the built-in file a path under `<embedded>/` names
/// ([`embedded_text`]). A folder, a device, a pipe or a socket is refused with an `InvalidInput`
/// error saying so, before reading: `/dev/zero` would never end.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    if is_embedded_path(path) {
        return embedded_text(path)
            .map(str::to_string)
            .ok_or_else(|| embedded::not_built_in(path));
    }
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a folder"
        } else {
            "not a regular file (a device, pipe or socket)"
        };
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} is {what}", path.display()),
        ));
    }
    std::fs::read_to_string(path)
}

/// The temporary name [`write_atomic`] writes `path` under: `path` with `.tmp` appended. A
/// process killed in the middle of a write leaves it behind; runs remove their own.
pub fn temp_path(path: &Path) -> PathBuf {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    PathBuf::from(tmp)
}

/// `label` as one folder name that keeps its meaning: a path separator (`/`, `\\`), a comma (the
/// comparison table is comma-separated) and control characters become `_`; a label that would
/// still name the folder itself or its parent (`.`, `..`, empty) becomes `_`. A run's label is
/// its folder under `runs/`: a study `label = "/tmp/x"` wrote `/tmp/x-5-rk4`.
pub fn folder_label(label: &str) -> String {
    let mapped: String = label
        .chars()
        .map(|c| {
            if matches!(c, '/' | '\\' | ',') || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    if matches!(mapped.as_str(), "" | "." | "..") {
        "_".into()
    } else {
        mapped
    }
}

/// `name` made safe as one file-name component: characters other than ASCII letters, digits,
/// `-`, `_` and `.` become `_`, and leading dots are dropped, so it can never name a parent
/// folder, an absolute path or a hidden file. Empty when nothing is left.
pub fn file_safe(name: &str) -> String {
    let mapped: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    mapped.trim_start_matches('.').to_string()
}

/// Reads a CSV file of numbers: its header and rows (cells that do not parse become NaN).
pub fn read_numeric_csv(path: &Path) -> std::io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let text = read_text(path)?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|x| x.parse::<f64>().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    Ok((header, rows))
}

/// Why the numeric CSV at `path` cannot be plotted: unreadable, a column of `columns` missing
/// from its header, a line with another number of cells than the header, or a cell that is
/// neither empty nor a number; `None` when it can.
pub fn numeric_csv_problem(path: &Path, columns: &[&str]) -> Option<String> {
    let text = match read_text(path) {
        Ok(text) => text,
        Err(e) => return Some(e.to_string()),
    };
    let mut lines = text.lines().enumerate();
    let header: Vec<&str> = lines
        .next()
        .map_or(Vec::new(), |(_, l)| l.split(',').collect());
    if let Some(c) = columns.iter().find(|c| !header.contains(c)) {
        return Some(format!("line 1: no column `{c}` in its header"));
    }
    for (k, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != header.len() {
            return Some(format!(
                "line {}: {} cells, expected {} as in its header",
                k + 1,
                cells.len(),
                header.len()
            ));
        }
        if let Some(bad) = cells
            .iter()
            .find(|c| !c.is_empty() && c.parse::<f64>().is_err())
        {
            return Some(format!("line {}: `{bad}` is not a number", k + 1));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::{file_safe, numeric_csv_problem, temp_path, write_atomic, MetricsWriter};
    use crate::testing::error_within_seconds;
    use std::path::Path;

    /// The error of `write` over `pipe`, opening a reader to free it if it waits.
    fn write_error(
        pipe: &Path,
        write: impl FnOnce() -> std::io::Result<()> + Send + 'static,
    ) -> String {
        error_within_seconds(write, || drop(std::fs::File::open(pipe)))
    }

    /// A pipe left where a run writes (the metrics table, an atomic write's temporary file) is
    /// refused with a message; opening it waited for a reader for ever, through Ctrl-C (the
    /// hostile sweep's `o/metrics.csv.partial` FIFO case, killed after ignoring SIGINT).
    #[test]
    fn numeric_csv_problems_name_the_line() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("e.csv");
        for (text, problem) in [
            ("t,e\n0.1,2e-3\n0.2,\n", None),
            ("garbage\n", Some("line 1: no column `t` in its header")),
            ("t,e\n0.1,2e-3\n0.2\n", Some("line 3: 1 cells, expected 2")),
            ("t,e\n0.1,x\n", Some("line 2: `x` is not a number")),
        ] {
            std::fs::write(&p, text).unwrap();
            let got = numeric_csv_problem(&p, &["t", "e"]);
            match problem {
                None => assert_eq!(got, None, "{text}"),
                Some(want) => assert!(got.as_deref().unwrap_or("").starts_with(want), "{got:?}"),
            }
        }
        assert!(numeric_csv_problem(&d.path().join("none.csv"), &["t"]).is_some());
    }

    #[test]
    fn a_pipe_where_a_run_writes_is_refused_not_waited_on() {
        let dir = tempfile::tempdir().unwrap();
        let partial = dir.path().join("metrics.csv.partial");
        let summary = dir.path().join("summary.json");
        for pipe in [&partial, &temp_path(&summary)] {
            let made = std::process::Command::new("mkfifo").arg(pipe).status();
            if !made.is_ok_and(|s| s.success()) {
                return; // no mkfifo: nothing to test
            }
        }
        let out = dir.path().to_path_buf();
        let err = write_error(&partial, move || {
            MetricsWriter::create(&out, &[]).map(|_| ())
        });
        assert!(err.contains("is a pipe or socket"), "{err}");
        let err = write_error(&temp_path(&summary), move || write_atomic(&summary, b"{}"));
        assert!(err.contains("is a pipe or socket"), "{err}");
    }

    /// An atomic write never replaces a device or a pipe (a rename over `/dev/full` as root once
    /// turned it into a plain file for every program on the machine); a pipe stands in for the
    /// device here, so a failure of this test cannot harm the machine.
    #[test]
    fn an_atomic_write_refuses_to_replace_a_pipe_or_a_folder() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let err = write_atomic(&fifo, b"x").unwrap_err();
            assert!(
                err.to_string().contains("a device, pipe or socket"),
                "{err}"
            );
            let meta = std::fs::symlink_metadata(&fifo).unwrap();
            assert!(!meta.is_file(), "the pipe was replaced");
        }
        let err = write_atomic(dir.path(), b"x").unwrap_err();
        assert!(err.to_string().contains("a folder"), "{err}");
        let file = dir.path().join("f.txt");
        write_atomic(&file, b"one").unwrap();
        write_atomic(&file, b"two").unwrap();
        assert_eq!(std::fs::read(&file).unwrap(), b"two");
    }

    #[test]
    fn names_cannot_escape_the_output_folder() {
        assert_eq!(file_safe("round_table"), "round_table");
        assert_eq!(file_safe("../../escaped"), "_.._escaped");
        assert_eq!(file_safe("/tmp/x"), "_tmp_x");
        assert_eq!(file_safe(".."), "");
        assert_eq!(file_safe("a b\\c:d"), "a_b_c_d");
        for n in ["../../escaped", "/tmp/x", "..", "a/../../b"] {
            let s = file_safe(n);
            assert!(!s.contains('/') && !s.starts_with('.'), "{n} -> {s}");
        }
    }
}
