//! Files: the one OBJ reader and writer ([`obj`]), the metrics table a run streams
//! ([`MetricsWriter`]), numeric CSV reading, and whole-file atomic writes. Every file is written
//! so that a partially written file never looks complete: whole files go through a temporary name
//! and a rename ([`write_atomic`]); the streamed metrics table is `metrics.csv.partial` until the
//! run ends (whatever its status), then renamed to `metrics.csv`.
//!
//! Where it sits: at the bottom, beside `math`: it knows file formats, not meshes or physics.

mod metrics;
pub mod obj;

pub use metrics::{MetricsRow, MetricsWriter};
pub use obj::{frame_path, read_frame_time, read_obj, write_frame, ObjError, ObjFile};

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

/// Reads a CSV file of numbers: its header and rows (cells that do not parse become NaN).
pub fn read_numeric_csv(path: &Path) -> std::io::Result<(Vec<String>, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path)?;
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
