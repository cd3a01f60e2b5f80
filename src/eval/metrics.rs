//! Error metrics between a run and the reference, mesh-independent (MODEL.md §1: material points).
//!
//! - `e(t)`: RMS over the grid samples of the distance between the run's and the reference's
//!   world positions of the same material point at the same time. The run is sampled at its output
//!   frames (the first step at or after each frame time); the reference is interpolated linearly in
//!   time to the run's sample time (its own frames bracket it).
//! - `e_rms`: RMS of `e(t)` over the run's frames; `e_final`: `e` at the last frame.
//! - tracked error: RMS over frames and tracked points of the tracked points' distance.
//! - Hausdorff: two-sided Hausdorff distance between the final surfaces, fold-pattern-insensitive
//!   (folds that end up in a different place but cover the same shape score low, unlike `e`).
//!   Approximation: each surface is represented by the triangulation of its final material-point
//!   grid (64x64 by default; the grid samples lie on the surface, so this is the surface up to
//!   the chord error of one sample spacing, about `h^2 kappa / 8` for curvature `kappa`), and the
//!   distance is taken from the points of each side (grid samples and mesh vertices) to the other
//!   side's triangulation. Identical surfaces score 0 whatever their meshes. Without a complete
//!   sample grid (a non-rectangular pattern), it falls back to the point-set distance, which
//!   overestimates by up to the samples' covering radius.

use super::nearest::{PointGrid, TriangleGrid};
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
    /// The run stopped before its first frame after the start (interrupted or diverged at once):
    /// its only frames show the shared initial state, whose error says nothing of the run.
    #[error("the run has no frame after its start")]
    NotStarted,
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
    /// Two-sided Hausdorff distance between the final surfaces (point-sampled); NaN when the
    /// run's last frame is not at the reference's last time (an interrupted or diverged run:
    /// surfaces at two different times are not compared).
    pub hausdorff: f64,
}

/// Whether the last frames of `run` and `reference` are at the same time, to half the
/// reference's last frame interval (its whole duration when it has one frame).
fn ends_together(run: &Trajectory, reference: &Trajectory) -> bool {
    let (Some(&t_run), Some(&t_ref)) = (run.times.last(), reference.times.last()) else {
        return false;
    };
    let n = reference.times.len();
    let spacing = if n >= 2 {
        t_ref - reference.times[n - 2]
    } else {
        t_ref.abs()
    };
    (t_run - t_ref).abs() <= 0.5 * spacing.max(1e-12)
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
    if run.times.last() <= run.times.first() && reference.times.last() > run.times.last() {
        return Err(EvalError::NotStarted);
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
    let hausdorff = if ends_together(run, reference) {
        surface_hausdorff(run, reference)
    } else {
        f64::NAN
    };
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

/// Triangles of a complete `side x side` sample grid (row-major), skipping any with a NaN corner.
fn grid_triangles(points: &[[f64; 3]], side: usize) -> Vec<[[f64; 3]; 3]> {
    let mut tris = Vec::with_capacity(2 * side.saturating_sub(1).pow(2));
    let ok = |p: &[f64; 3]| p.iter().all(|c| c.is_finite());
    for j in 0..side.saturating_sub(1) {
        for i in 0..side - 1 {
            let a = points[j * side + i];
            let b = points[j * side + i + 1];
            let c = points[(j + 1) * side + i + 1];
            let d = points[(j + 1) * side + i];
            for t in [[a, b, c], [a, c, d]] {
                if t.iter().all(ok) {
                    tris.push(t);
                }
            }
        }
    }
    tris
}

/// Two-sided Hausdorff distance between the final surfaces of two trajectories (m): from the
/// points of each (grid samples and vertices) to the triangulated sample grid of the other; the
/// point-set distance when the samples are not a complete grid.
pub fn surface_hausdorff(a: &Trajectory, b: &Trajectory) -> f64 {
    let pa = final_surface_points(a);
    let pb = final_surface_points(b);
    if a.side < 2 || b.side < 2 || a.side * a.side != a.grid || b.side * b.side != b.grid {
        return hausdorff(&pa, &pb);
    }
    let last = |t: &Trajectory| -> Vec<[f64; 3]> {
        t.frame(t.frames() - 1)[..t.grid]
            .iter()
            .map(|p| p.map(|c| c as f64))
            .collect()
    };
    let ta = grid_triangles(&last(a), a.side);
    let tb = grid_triangles(&last(b), b.side);
    if ta.is_empty() || tb.is_empty() {
        return hausdorff(&pa, &pb);
    }
    directed_to_triangles(&pa, &tb).max(directed_to_triangles(&pb, &ta))
}

/// `max over p in points of the distance from p to the nearest triangle`.
pub fn directed_to_triangles(points: &[[f64; 3]], tris: &[[[f64; 3]; 3]]) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    if tris.is_empty() {
        return f64::INFINITY;
    }
    let grid = TriangleGrid::new(tris);
    points
        .iter()
        .map(|p| grid.nearest_distance(p))
        .fold(0.0, f64::max)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Distance from `p` to the closed triangle `t` (Ericson, Real-Time Collision Detection, 5.1.5).
pub fn point_triangle_distance(p: [f64; 3], t: &[[f64; 3]; 3]) -> f64 {
    let [a, b, c] = *t;
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    let lerp = |x: [f64; 3], y: [f64; 3], w: f64| {
        [
            x[0] + w * (y[0] - x[0]),
            x[1] + w * (y[1] - x[1]),
            x[2] + w * (y[2] - x[2]),
        ]
    };
    let closest = if d1 <= 0.0 && d2 <= 0.0 {
        a
    } else {
        let bp = sub(p, b);
        let d3 = dot(ab, bp);
        let d4 = dot(ac, bp);
        let cp = sub(p, c);
        let d5 = dot(ab, cp);
        let d6 = dot(ac, cp);
        let vc = d1 * d4 - d3 * d2;
        let vb = d5 * d2 - d1 * d6;
        let va = d3 * d6 - d5 * d4;
        if d3 >= 0.0 && d4 <= d3 {
            b
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            lerp(a, b, d1 / (d1 - d3))
        } else if d6 >= 0.0 && d5 <= d6 {
            c
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            lerp(a, c, d2 / (d2 - d6))
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            lerp(b, c, (d4 - d3) / ((d4 - d3) + (d5 - d6)))
        } else {
            let denom = va + vb + vc;
            if denom.abs() < f64::MIN_POSITIVE {
                // Degenerate triangle: nearest of its corners.
                return [a, b, c]
                    .iter()
                    .map(|q| dot(sub(p, *q), sub(p, *q)).sqrt())
                    .fold(f64::INFINITY, f64::min);
            }
            let v = vb / denom;
            let w = vc / denom;
            [
                a[0] + ab[0] * v + ac[0] * w,
                a[1] + ab[1] * v + ac[1] * w,
                a[2] + ab[2] * v + ac[2] * w,
            ]
        }
    };
    let d = sub(p, closest);
    dot(d, d).sqrt()
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
    if error.is_nan() || error <= 0.0 {
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
            side: n,
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
    fn a_run_ending_early_has_errors_but_no_final_surface_distance() {
        // An interrupted run: its frames are compared at their times, but its last surface is
        // not the reference's final one.
        let reference = traj(8, 5, [0.0; 3], 1.0);
        let early = traj(8, 3, [0.0; 3], 1.0);
        let r = compare(&early, &reference).unwrap();
        assert_eq!(r.e_rms, 0.0);
        assert_eq!(r.e_t.len(), 3);
        assert!(r.hausdorff.is_nan(), "{}", r.hausdorff);
    }

    #[test]
    fn a_run_stopped_before_its_first_frame_after_the_start_is_not_measured() {
        // Interrupted before it began: only the initial state, which every run shares.
        let reference = traj(8, 5, [0.0; 3], 1.0);
        let unstarted = traj(8, 1, [0.0; 3], 1.0);
        assert_eq!(compare(&unstarted, &reference), Err(EvalError::NotStarted));
        // A one-frame reference against a one-frame run still compares.
        assert!(compare(&unstarted, &unstarted).is_ok());
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
        let mut rnd = crate::testing::uniform(12345);
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
    fn point_triangle_distances() {
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let cases = [
            ([0.2, 0.2, 0.5], 0.5),           // above the interior
            ([-1.0, 0.0, 0.0], 1.0),          // beyond vertex a
            ([2.0, 0.0, 0.0], 1.0),           // beyond vertex b
            ([0.5, -2.0, 0.0], 2.0),          // beside edge ab
            ([1.0, 1.0, 0.0], 0.5f64.sqrt()), // beside edge bc
            ([-0.5, 0.5, 0.0], 0.5),          // beside edge ca
            ([0.0, 2.0, 0.0], 1.0),           // beyond vertex c
        ];
        for (p, want) in cases {
            let d = point_triangle_distance(p, &t);
            assert!((d - want).abs() < 1e-12, "{p:?}: {d} != {want}");
        }
    }

    #[test]
    fn surface_hausdorff_ignores_meshes_and_sees_offsets() {
        let b = traj(9, 2, [0.0; 3], 1.0);
        // The same flat surface sampled on another grid: the points of each lie in the other's
        // triangles, so the distance is 0 where the point-set distance is not.
        let c = traj(7, 2, [0.0; 3], 1.0);
        assert!(hausdorff(&final_surface_points(&b), &final_surface_points(&c)) > 0.01);
        assert!(surface_hausdorff(&b, &c) < 1e-6);
        // Mesh vertices count: one side's vertices 0.01 above the other's surface (the last
        // frame is the unit square shifted by 0.01 along every axis) give 0.01.
        let mut a = b.clone();
        a.final_vertices = (0..25)
            .map(|k| {
                let (i, j) = ((k % 5) as f32, (k / 5) as f32);
                [0.01 + 0.25 * i, 0.01 + 0.25 * j, 0.02]
            })
            .collect();
        let d = surface_hausdorff(&a, &b);
        assert!((d - 0.01).abs() < 1e-6, "{d}");
        // A parallel plane 0.2 away.
        let e = traj(9, 2, [0.0, 0.0, 0.2], 1.0);
        assert!((surface_hausdorff(&b, &e) - 0.2).abs() < 1e-6);
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
