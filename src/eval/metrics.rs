//! Error metrics between a run and the reference, mesh-independent (MODEL.md §1: material points).
//!
//! - `e(t)`: RMS over the grid samples of the distance between the run's and the reference's
//!   world positions of the same material point at the same time. The run is sampled at its output
//!   frames (the first step at or after each frame time); the reference is interpolated linearly in
//!   time to the run's sample time (its own frames bracket it).
//! - `e_rms`: RMS of `e(t)` over the run's frames; `e_final`: `e` at the last frame.
//! - tracked error: RMS over frames and tracked points of the tracked points' distance.
//! - Hausdorff: two-sided Hausdorff distance between the final surfaces, approximated on point
//!   sets: each surface is represented by its dense material-point samples plus its mesh vertices.
//!   Since both sets lie on their surfaces, the point-set value differs from the exact surface
//!   distance by at most the covering radius of the sample sets (about half a sample spacing
//!   times the local stretch: 1/126 of the pattern side for the default 64x64 grid), which is
//!   below the error floor of the reference; folds that end up in a different place but cover the
//!   same shape score low, unlike `e`.

use crate::sim::Trajectory;

/// Why two trajectories cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// The runs did not sample the same points.
    #[error("sample sets differ: run has {run} points ({run_grid} grid), reference {reference} ({reference_grid} grid)")]
    PointsDiffer {
        /// Points of the run.
        run: usize,
        /// Grid points of the run.
        run_grid: usize,
        /// Points of the reference.
        reference: usize,
        /// Grid points of the reference.
        reference_grid: usize,
    },
    /// One of the trajectories has no frame.
    #[error("a trajectory has no recorded frame")]
    Empty,
}

/// Errors of one run against the reference (all in m).
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorReport {
    /// `(t, e(t))` at each frame of the run (s, m).
    pub e_t: Vec<(f64, f64)>,
    /// RMS of `e(t)` over the frames.
    pub e_rms: f64,
    /// `e` at the run's last frame.
    pub e_final: f64,
    /// RMS over frames and tracked points of the tracked points' distance (NaN without tracked
    /// points).
    pub tracked_err: f64,
    /// Two-sided Hausdorff distance between the final surfaces (point-sampled).
    pub hausdorff: f64,
}

fn dist(a: [f32; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] as f64 - b[0], a[1] as f64 - b[1], a[2] as f64 - b[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The reference's positions at time `t`, linearly interpolated between its bracketing frames
/// (clamped to its first and last frames).
pub fn positions_at(reference: &Trajectory, t: f64) -> Vec<[f64; 3]> {
    let times = &reference.times;
    let k = times.partition_point(|&s| s <= t);
    let (a, b, w) = if k == 0 {
        (0, 0, 0.0)
    } else if k >= times.len() {
        (times.len() - 1, times.len() - 1, 0.0)
    } else {
        let (t0, t1) = (times[k - 1], times[k]);
        let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        (k - 1, k, w)
    };
    reference
        .frame(a)
        .iter()
        .zip(reference.frame(b))
        .map(|(p, q)| [0, 1, 2].map(|c| (1.0 - w) * p[c] as f64 + w * q[c] as f64))
        .collect()
}

/// Compares a run's sampled trajectory with the reference's.
pub fn compare(run: &Trajectory, reference: &Trajectory) -> Result<ErrorReport, EvalError> {
    if run.points != reference.points || run.grid != reference.grid {
        return Err(EvalError::PointsDiffer {
            run: run.points,
            run_grid: run.grid,
            reference: reference.points,
            reference_grid: reference.grid,
        });
    }
    if run.frames() == 0 || reference.frames() == 0 {
        return Err(EvalError::Empty);
    }
    let grid = run.grid;
    let tracked = run.points - grid;
    let mut e_t = Vec::with_capacity(run.frames());
    let mut tracked_sq = 0.0;
    for (k, &t) in run.times.iter().enumerate() {
        let r = positions_at(reference, t);
        let p = run.frame(k);
        // Points that could not be located (NaN) in either run are left out.
        let d: Vec<f64> = (0..grid)
            .map(|i| dist(p[i], r[i]))
            .filter(|d| d.is_finite())
            .collect();
        e_t.push((t, rms(d.into_iter())));
        tracked_sq += (grid..run.points)
            .map(|i| dist(p[i], r[i]).powi(2))
            .sum::<f64>();
    }
    let e_rms = rms(e_t.iter().map(|&(_, e)| e));
    let e_final = e_t.last().map_or(f64::NAN, |&(_, e)| e);
    let tracked_err = if tracked == 0 {
        f64::NAN
    } else {
        (tracked_sq / (tracked * run.frames()) as f64).sqrt()
    };
    let hausdorff = hausdorff(&final_surface_points(run), &final_surface_points(reference));
    Ok(ErrorReport {
        e_t,
        e_rms,
        e_final,
        tracked_err,
        hausdorff,
    })
}

/// Root mean square of the values (NaN when empty).
pub fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for v in values {
        s += v * v;
        n += 1;
    }
    if n == 0 {
        f64::NAN
    } else {
        (s / n as f64).sqrt()
    }
}

/// The final surface as points: the last frame's grid samples and the final mesh vertices.
fn final_surface_points(t: &Trajectory) -> Vec<[f64; 3]> {
    let last = t.frame(t.frames() - 1);
    last[..t.grid]
        .iter()
        .chain(&t.final_vertices)
        .filter(|p| p.iter().all(|c| c.is_finite()))
        .map(|p| p.map(|c| c as f64))
        .collect()
}

/// Two-sided Hausdorff distance between two point sets (m): the largest distance from a point of
/// either set to the nearest point of the other. Infinite when exactly one set is empty, 0 when
/// both are. Uses a uniform bucket grid, so it is fast on the dense sample sets.
pub fn hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    match (a.is_empty(), b.is_empty()) {
        (true, true) => return 0.0,
        (true, false) | (false, true) => return f64::INFINITY,
        _ => {}
    }
    directed_hausdorff(a, b).max(directed_hausdorff(b, a))
}

/// `max over p in a of min over q in b of |p - q|`, with `b` bucketed in a uniform grid and the
/// search growing shell by shell until no closer point can exist.
pub fn directed_hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    if b.is_empty() {
        return f64::INFINITY;
    }
    let grid = PointGrid::new(b);
    a.iter()
        .map(|p| grid.nearest_distance(p))
        .fold(0.0, f64::max)
}

struct PointGrid<'a> {
    points: &'a [[f64; 3]],
    lo: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    start: Vec<usize>,
    order: Vec<usize>,
}

impl<'a> PointGrid<'a> {
    fn new(points: &'a [[f64; 3]]) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let ext: Vec<f64> = (0..3).map(|c| (hi[c] - lo[c]).max(0.0)).collect();
        // Cloth surfaces are two-dimensional: size cells for about one point per cell over the
        // two largest extents.
        let mut sorted = ext.clone();
        sorted.sort_by(|a, b| b.total_cmp(a));
        let diag = (ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]).sqrt();
        let cell = (sorted[0] * sorted[1] / points.len() as f64)
            .sqrt()
            .max(diag / points.len() as f64)
            .max(1e-9);
        let dims = [0, 1, 2].map(|c| ((ext[c] / cell) as usize + 1).min(1024));
        let index = |p: &[f64; 3]| -> usize {
            let i = [0, 1, 2].map(|c| (((p[c] - lo[c]) / cell) as usize).min(dims[c] - 1));
            (i[2] * dims[1] + i[1]) * dims[0] + i[0]
        };
        let ncells = dims[0] * dims[1] * dims[2];
        let mut count = vec![0usize; ncells + 1];
        for p in points {
            count[index(p) + 1] += 1;
        }
        for k in 0..ncells {
            count[k + 1] += count[k];
        }
        let start = count.clone();
        let mut fill = count;
        let mut order = vec![0; points.len()];
        for (j, p) in points.iter().enumerate() {
            let c = index(p);
            order[fill[c]] = j;
            fill[c] += 1;
        }
        PointGrid {
            points,
            lo,
            cell,
            dims,
            start,
            order,
        }
    }

    fn nearest_distance(&self, p: &[f64; 3]) -> f64 {
        let centre = [0, 1, 2].map(|c| {
            let x = ((p[c] - self.lo[c]) / self.cell).floor();
            x.clamp(-1.0, self.dims[c] as f64) as i64
        });
        let mut best = f64::INFINITY;
        let max_r = *self.dims.iter().max().expect("3 dims") as i64 + 2;
        for r in 0..=max_r {
            // Every point in shell r is at least (r - 1) cells away.
            if r >= 1 && ((r - 1) as f64 * self.cell) > best {
                break;
            }
            let range = |c: usize| {
                let lo = (centre[c] - r).max(0);
                let hi = (centre[c] + r).min(self.dims[c] as i64 - 1);
                lo..=hi
            };
            for iz in range(2) {
                for iy in range(1) {
                    let on_shell = (iz - centre[2]).abs() == r || (iy - centre[1]).abs() == r;
                    let xs: Vec<i64> = if on_shell {
                        range(0).collect()
                    } else {
                        [centre[0] - r, centre[0] + r]
                            .into_iter()
                            .filter(|&x| x >= 0 && x < self.dims[0] as i64)
                            .collect()
                    };
                    for ix in xs {
                        let k =
                            (iz as usize * self.dims[1] + iy as usize) * self.dims[0] + ix as usize;
                        for &j in &self.order[self.start[k]..self.start[k + 1]] {
                            let q = self.points[j];
                            let d = ((p[0] - q[0]).powi(2)
                                + (p[1] - q[1]).powi(2)
                                + (p[2] - q[2]).powi(2))
                            .sqrt();
                            best = best.min(d);
                        }
                    }
                }
            }
        }
        best
    }
}

/// Indices of the Pareto-optimal points among `(time, error)` pairs: no other point is at least
/// as fast and at least as accurate and strictly better in one. Non-finite points are excluded.
/// Sorted by increasing time.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    idx.sort_by(|&i, &j| {
        points[i]
            .0
            .total_cmp(&points[j].0)
            .then(points[i].1.total_cmp(&points[j].1))
            .then(i.cmp(&j))
    });
    let mut front = Vec::new();
    let mut best_error = f64::INFINITY;
    for i in idx {
        if points[i].1 < best_error {
            front.push(i);
            best_error = points[i].1;
        }
    }
    front
}

/// The wall time the static-mesh curve would need to reach `error`, interpolated linearly in
/// log-log between the two static points (on the static Pareto front) that bracket it. `None`
/// when `error` is outside the static points' error range (no extrapolation).
pub fn static_time_at_error(static_points: &[(f64, f64)], error: f64) -> Option<f64> {
    let front: Vec<(f64, f64)> = pareto_front(static_points)
        .into_iter()
        .map(|i| static_points[i])
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .collect();
    if !(error > 0.0) {
        return None;
    }
    // Along the front, time increases and error decreases.
    for w in front.windows(2) {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        if error <= e0 && error >= e1 {
            let s = if e0 == e1 {
                0.0
            } else {
                (error.ln() - e0.ln()) / (e1.ln() - e0.ln())
            };
            return Some((t0.ln() + s * (t1.ln() - t0.ln())).exp());
        }
    }
    front.iter().find(|p| p.1 == error).map(|p| p.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::AdaptJumps;

    /// A trajectory of `frames` frames of a `n x n` grid in the plane z = 0, plus one tracked point
    /// (the grid's first point), moved by `offset` and with positions scaled by `stretch`.
    fn traj(n: usize, frames: usize, offset: [f64; 3], stretch: f64) -> Trajectory {
        let mut grid_pts = Vec::new();
        for j in 0..n {
            for i in 0..n {
                grid_pts.push([i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64, 0.0]);
            }
        }
        let tracked = grid_pts[0];
        let mut t = Trajectory {
            points: n * n + 1,
            grid: n * n,
            adapt: AdaptJumps::default(),
            ..Trajectory::default()
        };
        for k in 0..frames {
            t.times.push(k as f64 * 0.1);
            for p in grid_pts.iter().chain([&tracked]) {
                t.positions
                    .push([0, 1, 2].map(|c| (p[c] * stretch + offset[c] + 0.01 * k as f64) as f32));
            }
        }
        t.final_vertices = t.frame(frames - 1)[..n * n].to_vec();
        t
    }

    #[test]
    fn identical_runs_have_zero_error() {
        let a = traj(8, 5, [0.0; 3], 1.0);
        let r = compare(&a, &a).unwrap();
        assert_eq!(r.e_rms, 0.0);
        assert_eq!(r.e_final, 0.0);
        assert_eq!(r.tracked_err, 0.0);
        assert_eq!(r.hausdorff, 0.0);
        assert_eq!(r.e_t.len(), 5);
    }

    #[test]
    fn rigid_translation_by_d_gives_error_d() {
        let d = [0.03, -0.04, 0.12]; // |d| = 0.13
        let a = traj(8, 5, [0.0; 3], 1.0);
        let b = traj(8, 5, d, 1.0);
        let r = compare(&b, &a).unwrap();
        for &(_, e) in &r.e_t {
            assert!((e - 0.13).abs() < 1e-6, "{e}");
        }
        assert!((r.e_rms - 0.13).abs() < 1e-6);
        assert!((r.e_final - 0.13).abs() < 1e-6);
        assert!((r.tracked_err - 0.13).abs() < 1e-6);
        // A normal translation of a flat sheet: the Hausdorff distance is at least the normal
        // part and at most |d|.
        assert!(
            r.hausdorff >= 0.12 - 1e-6 && r.hausdorff <= 0.13 + 1e-6,
            "{}",
            r.hausdorff
        );
    }

    #[test]
    fn reference_is_interpolated_in_time() {
        // The reference moves 0.01 m per 0.1 s along each axis; a run sampled halfway between two
        // reference frames with the same motion has zero error.
        let reference = traj(4, 5, [0.0; 3], 1.0);
        let mut run = traj(4, 4, [0.005; 3], 1.0);
        for t in &mut run.times {
            *t += 0.05;
        }
        let r = compare(&run, &reference).unwrap();
        assert!(r.e_rms < 1e-6, "{}", r.e_rms);
        // Without the shift in time, the same run is off by |(0.005, 0.005, 0.005)|.
        let mut unshifted = run.clone();
        for t in &mut unshifted.times {
            *t -= 0.05;
        }
        let r = compare(&unshifted, &reference).unwrap();
        assert!((r.e_rms - 0.005 * 3f64.sqrt()).abs() < 1e-6, "{}", r.e_rms);
    }

    #[test]
    fn mismatched_samples_are_an_error() {
        let a = traj(4, 3, [0.0; 3], 1.0);
        let b = traj(5, 3, [0.0; 3], 1.0);
        assert!(matches!(
            compare(&a, &b),
            Err(EvalError::PointsDiffer { .. })
        ));
    }

    #[test]
    fn hausdorff_of_known_sets() {
        let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let b = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [5.0, 0.0, 0.0]];
        // a -> b: 0; b -> a: 4.
        assert_eq!(directed_hausdorff(&a, &b), 0.0);
        assert_eq!(directed_hausdorff(&b, &a), 4.0);
        assert_eq!(hausdorff(&a, &b), 4.0);
        assert_eq!(hausdorff(&b, &a), 4.0);
        // Two parallel unit squares of points 0.2 apart.
        let sq = |z: f64| -> Vec<[f64; 3]> {
            (0..400)
                .map(|k| [(k % 20) as f64 / 19.0, (k / 20) as f64 / 19.0, z])
                .collect()
        };
        assert!((hausdorff(&sq(0.0), &sq(0.2)) - 0.2).abs() < 1e-12);
        assert_eq!(hausdorff(&[], &[]), 0.0);
        assert!(hausdorff(&a, &[]).is_infinite());
    }

    #[test]
    fn hausdorff_grid_matches_brute_force() {
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let a: Vec<[f64; 3]> = (0..300).map(|_| [rnd(), rnd(), 0.1 * rnd()]).collect();
        let b: Vec<[f64; 3]> = (0..200).map(|_| [rnd() * 2.0, rnd(), rnd()]).collect();
        let brute = |x: &[[f64; 3]], y: &[[f64; 3]]| {
            x.iter()
                .map(|p| {
                    y.iter()
                        .map(|q| {
                            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2))
                                .sqrt()
                        })
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max)
        };
        assert_eq!(directed_hausdorff(&a, &b), brute(&a, &b));
        assert_eq!(directed_hausdorff(&b, &a), brute(&b, &a));
    }

    #[test]
    fn pareto_front_selection() {
        let pts = [
            (1.0, 0.5),      // 0: fastest
            (2.0, 0.6),      // 1: dominated by 0
            (3.0, 0.1),      // 2
            (3.0, 0.2),      // 3: dominated by 2
            (10.0, 0.01),    // 4
            (20.0, 0.01),    // 5: dominated by 4
            (f64::NAN, 0.0), // 6: excluded
            (0.5, f64::INFINITY),
        ];
        assert_eq!(pareto_front(&pts), vec![0, 2, 4]);
        assert!(pareto_front(&[]).is_empty());
    }

    #[test]
    fn static_curve_interpolates_in_log_log() {
        // e = 1 / t: log-log straight line, so interpolation is exact.
        let pts = [(1.0, 1.0), (10.0, 0.1), (100.0, 0.01)];
        let t = static_time_at_error(&pts, 0.05).unwrap();
        assert!((t - 20.0).abs() < 1e-9, "{t}");
        assert!((static_time_at_error(&pts, 0.1).unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(static_time_at_error(&pts, 0.001), None);
        assert_eq!(static_time_at_error(&pts, 2.0), None);
    }
}
