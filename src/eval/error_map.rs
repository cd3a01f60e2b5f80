//! Error maps: where on the cloth a run's error is. `e(u, v)` is the distance between the run's
//! and the reference's world positions of the material point at rest position `(u, v)`, on the
//! sample grid, at a few times (the run frames nearest to [`MAP_FRACTIONS`] of its duration; the
//! reference interpolated in time). Written beside the run as `error_map.csv` (`t,u,v,e`, s and m)
//! and drawn over the run's rest-space mesh by the report.

use super::metrics::positions_at;
use crate::sim::{SamplePoints, Trajectory};
use std::fmt::Write as _;
use std::path::Path;

/// Fractions of the run's duration at which the maps are taken.
pub const MAP_FRACTIONS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

/// The error over the sample grid at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorMap {
    /// Time of the run frame (s).
    pub t: f64,
    /// Per grid sample: rest position `(u, v)` (m) and error (m; NaN where a sample was lost).
    pub samples: Vec<([f64; 2], f64)>,
}

/// The maps of `run` against `reference` at the run frames nearest to each of `MAP_FRACTIONS`
/// of `duration` (s); `samples` are the rest points both sampled. Empty when the trajectories do
/// not sample the same points or have no frame.
pub fn error_maps(
    run: &Trajectory,
    reference: &Trajectory,
    samples: &SamplePoints,
    duration: f64,
) -> Vec<ErrorMap> {
    if run.points != reference.points || run.grid != samples.grid || run.frames() == 0 {
        return Vec::new();
    }
    let mut frames: Vec<usize> = MAP_FRACTIONS
        .iter()
        .filter_map(|f| {
            let target = f * duration;
            (0..run.frames()).min_by(|&a, &b| {
                (run.times[a] - target)
                    .abs()
                    .total_cmp(&(run.times[b] - target).abs())
            })
        })
        .collect();
    frames.dedup();
    frames
        .into_iter()
        .map(|k| {
            let t = run.times[k];
            let r = positions_at(reference, t);
            let p = run.frame(k);
            let samples = (0..run.grid)
                .map(|i| {
                    let d = [0, 1, 2].map(|c| p[i][c] as f64 - r[i][c]);
                    let e = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    (samples.rest[i], e)
                })
                .collect();
            ErrorMap { t, samples }
        })
        .collect()
}

/// Writes `t,u,v,e` rows (s, m, m, m) atomically.
pub fn write_error_maps(path: &Path, maps: &[ErrorMap]) -> std::io::Result<()> {
    let mut s = String::from("t,u,v,e\n");
    for m in maps {
        for ([u, v], e) in &m.samples {
            let _ = writeln!(s, "{:.6},{u:.6},{v:.6},{e:.6e}", m.t);
        }
    }
    crate::io::write_atomic(path, s.as_bytes())
}

/// Reads `error_map.csv` back into maps (rows grouped by time, in file order).
pub fn read_error_maps(path: &Path) -> std::io::Result<Vec<ErrorMap>> {
    let (_, rows) = crate::io::read_numeric_csv(path)?;
    let mut maps: Vec<ErrorMap> = Vec::new();
    for row in rows.iter().filter(|r| r.len() == 4) {
        let sample = ([row[1], row[2]], row[3]);
        match maps.last_mut() {
            Some(m) if m.t == row[0] => m.samples.push(sample),
            _ => maps.push(ErrorMap {
                t: row[0],
                samples: vec![sample],
            }),
        }
    }
    Ok(maps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::AdaptJumps;

    /// A 3x3 grid in the plane, frames at 0, 0.5, 1 s; `lift(i, k)` moves sample `i` up at frame k.
    fn trajectory(lift: impl Fn(usize, usize) -> f32) -> (Trajectory, SamplePoints) {
        let rest: Vec<[f64; 2]> = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64]).collect();
        let mut positions = Vec::new();
        for k in 0..3 {
            for (i, r) in rest.iter().enumerate() {
                positions.push([r[0] as f32, r[1] as f32, lift(i, k)]);
            }
        }
        let t = Trajectory {
            points: 9,
            grid: 9,
            side: 3,
            times: vec![0.0, 0.5, 1.0],
            positions,
            final_vertices: Vec::new(),
            adapt: AdaptJumps::default(),
        };
        let s = SamplePoints {
            rest,
            grid: 9,
            side: 3,
        };
        (t, s)
    }

    #[test]
    fn maps_locate_the_error_where_the_run_differs() {
        let (reference, samples) = trajectory(|_, _| 0.0);
        // Only sample 4 (the centre, rest (1, 1)) differs, by 0.1 m times the frame index.
        let (run, _) = trajectory(|i, k| if i == 4 { 0.1 * k as f32 } else { 0.0 });
        let maps = error_maps(&run, &reference, &samples, 1.0);
        // Frames nearest to 0.25, 0.5, 0.75, 1 s: 0 (or 0.5), 0.5, 0.5 (or 1), 1, deduplicated.
        assert!(maps.len() >= 2 && maps.len() <= 3, "{maps:?}");
        let last = maps.last().unwrap();
        assert_eq!(last.t, 1.0);
        for (rest, e) in &last.samples {
            let want = if *rest == [1.0, 1.0] { 0.2 } else { 0.0 };
            assert!((e - want).abs() < 1e-6, "{rest:?}: {e}");
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("error_map.csv");
        write_error_maps(&path, &maps).unwrap();
        let back = read_error_maps(&path).unwrap();
        assert_eq!(back.len(), maps.len());
        assert_eq!(back[0].samples.len(), 9);
        assert!((back.last().unwrap().samples[4].1 - 0.2).abs() < 1e-6);
    }
}
