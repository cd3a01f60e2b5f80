//! Outputs of a run: OBJ frames, the metrics table, the summary. Every file is written so that a
//! partially written file never looks complete: whole files go through a temporary name and a
//! rename ([`write_atomic`]); the streamed metrics table is `metrics.csv.partial` until the run
//! ends (whatever its status), then renamed to `metrics.csv`.

mod frame_diff;
mod frames;
mod metrics;

pub use frame_diff::{frame_distance, read_frame_positions, FrameDiffError};
pub use frames::{frame_path, write_frame};
pub use metrics::{MetricsRow, MetricsWriter};

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
