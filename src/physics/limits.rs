//! The step-size limits the dynamic step formula (4.5-4.6) does not see.
//!
//! The formula `beta pi sqrt(m_min / k_max)` sees the stiffest spring and the lightest vertex.
//! Two things it misses bind explicit schemes on small or crumpled elements:
//! - **spring damping** `kd = alpha k` adds real decay rates up to the largest eigenvalue of
//!   `M^-1 C`, with `C = sum_j kd_j P_jᵀ u_j u_jᵀ P_j` (spring j along unit `u_j`) plus the
//!   bending damping; that rate grows as `1/m` while the elastic frequency grows as `1/sqrt(m)`, so
//!   it binds on light (refined) vertices;
//! - **bending of flattened triangles**: Bridson's modes grow as `1/|N|`, so the bending
//!   stiffness of a triangle squashed towards a sliver grows as `1/|N|³` (bounded below the
//!   sliver ratio by the forces' sliver factor, `forces::SLIVER_RATIO`, where it peaks at a few
//!   times the springs' stiffness).
//!
//! An explicit scheme is stable on a decay rate `r` for `dt r` below its real-axis limit, and on
//! an oscillation of frequency `w` for `dt w` below its imaginary-axis limit
//! ([`crate::physics::Integrator::stability_limit`]: 2 for the Euler and Verlet schemes, 2.785
//! for RK4). The largest eigenvalues of `M^-1 C(x)` and
//! `M^-1 K(x)` (`K`: the springs' stiffness with the geometric term of stretched springs, and the
//! bending's Gauss-Newton part, as in `implicit_euler`) are estimated by power iteration,
//! warm-started from step to step, and after a mesh change from the warm start mixed with a fixed
//! pseudo-random vector ([`StabilityLimit::update_after_edit`]). The per-vertex Gershgorin bounds
//! would be safe but 1.3-2x too tight on flat grids.

use super::forces::bend_modes;
use super::{ForceModel, SpringMode};
use crate::math::{Real, Vec3};

/// Power iterations after a mesh change (from the previous eigenvectors, extended to new slots
/// and mixed with a fixed pseudo-random start: [`StabilityLimit::update_after_edit`]).
pub const ITERATIONS_AFTER_EDIT: usize = 30;
/// Steps between two single power iterations while the mesh is unchanged: the state moves
/// little in a few explicit steps, and each iteration costs about one force evaluation.
pub const STEPS_PER_ITERATION: u64 = 4;
/// Margin for the estimates approaching the eigenvalues from below.
const MARGIN: Real = 0.95;

/// Estimates of the largest decay rate (1/s) and the largest squared frequency (1/s²) of the
/// linearised cloth, by power iteration on `M^-1/2 C M^-1/2` and `M^-1/2 K M^-1/2` over the
/// movable vertices. Each estimate is a Rayleigh quotient, approaching its eigenvalue from below;
/// [`StabilityLimit::step_limit`] keeps a margin for that. Allocation-free once sized.
#[derive(Clone, Debug, Default)]
pub struct StabilityLimit {
    damping: PowerIteration,
    stiffness: PowerIteration,
}

/// One power iteration's state: the eigenvector estimate and the last Rayleigh quotient.
#[derive(Clone, Debug, Default)]
struct PowerIteration {
    z: Vec<Vec3>,
    y: Vec<Vec3>,
    value: Real,
}

impl StabilityLimit {
    /// Refines both estimates with `iterations` power iterations at positions `x` (m). Slots added
    /// since the last call start from a fixed pseudo-random vector, so they are seen at once.
    pub fn update(&mut self, model: &ForceModel, x: &[Vec3], iterations: usize) {
        let w = model.inv_mass();
        let (c, k) = (&mut self.damping, &mut self.stiffness);
        c.value = 0.0;
        k.value = 0.0;
        c.prepare(w);
        k.prepare(w);
        for _ in 0..iterations {
            let (nc, nk) = (c.normalise(w), k.normalise(w));
            if nc == 0.0 && nk == 0.0 {
                return;
            }
            apply_scaled(model, x, [&c.z, &k.z], [&mut c.y, &mut k.y]);
            c.finish();
            k.finish();
        }
    }

    /// After a mesh change: mixes the fixed pseudo-random start into both eigenvector estimates
    /// (each normalised, then summed; the first call has no warm start to mix), then refines them with [`ITERATIONS_AFTER_EDIT`] power
    /// iterations at positions `x` (m). The warm start alone can hold almost nothing of the new
    /// mesh's fastest mode when an edit moved it elsewhere (a coarsening that leaves light
    /// vertices or squashed elements in another region): 30 iterations then stayed near the old
    /// mode and the step rose past the limit (bisect48 with the sizing field under RK4 diverged
    /// 23 steps after such a pass). The mixed start holds every mode.
    pub fn update_after_edit(&mut self, model: &ForceModel, x: &[Vec3]) {
        let w = model.inv_mass();
        for p in [&mut self.damping, &mut self.stiffness] {
            let warm = !p.z.is_empty();
            p.prepare(w);
            if warm {
                p.mix_start();
            }
        }
        self.update(model, x, ITERATIONS_AFTER_EDIT);
    }

    /// The spring and bending damping's largest decay rate (1/s); 0 without damping.
    pub fn decay_rate(&self) -> Real {
        self.damping.value
    }

    /// The largest angular frequency (1/s) of the springs and bending; 0 without stiffness.
    pub fn frequency(&self) -> Real {
        self.stiffness.value.max(0.0).sqrt()
    }

    /// The largest step (s) the estimates allow a scheme of stability limit `axis_limit`
    /// ([`crate::physics::Integrator::stability_limit`]): `0.95 axis_limit / max(rate,
    /// frequency)`; infinite when both are 0.
    pub fn step_limit(&self, axis_limit: Real) -> Real {
        let fastest = self.decay_rate().max(self.frequency());
        if fastest > 0.0 {
            MARGIN * axis_limit / fastest
        } else {
            Real::INFINITY
        }
    }
}

impl PowerIteration {
    /// Sizes the vectors to `w`'s slots, new slots from [`start_vector`].
    fn prepare(&mut self, w: &[Real]) {
        for i in self.z.len()..w.len() {
            self.z.push(start_vector(i));
        }
        self.z.truncate(w.len());
        self.y.resize(w.len(), Vec3::zeros());
    }

    /// `z` becomes `z / |z| + s / |s|`, `s` the [`start_vector`]s (non-finite entries of `z`
    /// count as 0; `z` is `s / |s|` where it is all 0).
    fn mix_start(&mut self) {
        let finite = |a: &Vec3| a.iter().all(|c| c.is_finite());
        let largest = self
            .z
            .iter()
            .filter(|a| finite(a))
            .map(|a| a.amax())
            .fold(0.0, Real::max);
        let norm_z = if largest > 0.0 {
            largest
                * self
                    .z
                    .iter()
                    .filter(|a| finite(a))
                    .map(|a| (a / largest).norm_squared())
                    .sum::<Real>()
                    .sqrt()
        } else {
            0.0
        };
        let norm_s = (0..self.z.len())
            .map(|i| start_vector(i).norm_squared())
            .sum::<Real>()
            .sqrt();
        if norm_s == 0.0 {
            return;
        }
        for (i, zi) in self.z.iter_mut().enumerate() {
            let warm = if norm_z > 0.0 && finite(zi) {
                *zi / norm_z
            } else {
                Vec3::zeros()
            };
            *zi = warm + start_vector(i) / norm_s;
        }
    }

    /// Scales `z` to unit norm over the movable slots (fixed and non-finite entries zeroed);
    /// returns 0 when nothing is left. Divides by the largest component first, so eigenvalues
    /// near the float range (`material.E = 1e308`) do not overflow the squares.
    fn normalise(&mut self, w: &[Real]) -> Real {
        for (zi, &wi) in self.z.iter_mut().zip(w) {
            if wi == 0.0 || !zi.iter().all(|c| c.is_finite()) {
                *zi = Vec3::zeros();
            }
        }
        let largest = self.z.iter().map(|a| a.amax()).fold(0.0, Real::max);
        if largest == 0.0 {
            return 0.0;
        }
        self.z.iter_mut().for_each(|a| *a /= largest);
        let norm = self.z.iter().map(|a| a.norm_squared()).sum::<Real>().sqrt();
        self.z.iter_mut().for_each(|a| *a /= norm);
        norm
    }

    /// After `y = S z`: the Rayleigh quotient `zᵀ S z`, and `y` becomes the next `z`.
    fn finish(&mut self) {
        self.value = self.z.iter().zip(&self.y).map(|(a, b)| a.dot(b)).sum();
        std::mem::swap(&mut self.z, &mut self.y);
    }
}

/// `y[0] = M^-1/2 C(x) M^-1/2 z[0]` and `y[1] = M^-1/2 K(x) M^-1/2 z[1]` in one sweep over the
/// springs and bending elements (inverse masses from the model; fixed slots give 0).
fn apply_scaled(model: &ForceModel, x: &[Vec3], z: [&[Vec3]; 2], y: [&mut Vec<Vec3>; 2]) {
    let w = model.inv_mass();
    let sw = model.switches();
    let material = model.material();
    let both = material.springs == SpringMode::Both;
    let [yc, yk] = y;
    yc.fill(Vec3::zeros());
    yk.fill(Vec3::zeros());
    let scaled = |z: &[Vec3], i: usize| z[i] * w[i].sqrt();
    let s = model.springs();
    for j in 0..s.len() {
        let (a, b) = (s.a[j] as usize, s.b[j] as usize);
        let d = x[b] - x[a];
        let len2 = d.norm_squared();
        if len2 <= 0.0 {
            continue;
        }
        let len = len2.sqrt();
        let u = d / len;
        if sw.spring_damping {
            let rel = scaled(z[0], a) - scaled(z[0], b);
            let t = u * (s.kd[j] * u.dot(&rel));
            yc[a] += t * w[a].sqrt();
            yc[b] -= t * w[b].sqrt();
        }
        if sw.springs && (both || len > s.rest_length[j]) {
            let rel = scaled(z[1], a) - scaled(z[1], b);
            let geo = (1.0 - s.rest_length[j] / len).max(0.0);
            let along = u * u.dot(&rel);
            let t = (along + (rel - along) * geo) * s.k[j];
            yk[a] += t * w[a].sqrt();
            yk[b] -= t * w[b].sqrt();
        }
    }
    let kb = if sw.bending { material.k_b } else { 0.0 };
    let kbd = if sw.bending_damping {
        material.k_bd
    } else {
        0.0
    };
    if kb == 0.0 && kbd == 0.0 {
        return;
    }
    for &[i1, i2, i3, i4] in &model.bends().v {
        let ids = [i1 as usize, i2 as usize, i3 as usize, i4 as usize];
        let Some(m) = bend_modes(x[ids[0]], x[ids[1]], x[ids[2]], x[ids[3]]) else {
            continue;
        };
        let weights = [kbd * m.damping_scale, 0.5 * kb * m.elastic_scale];
        for (which, (&wgt, y)) in weights.iter().zip([&mut *yc, &mut *yk]).enumerate() {
            let along: Real = (0..4).map(|k| m.u[k].dot(&scaled(z[which], ids[k]))).sum();
            for k in 0..4 {
                y[ids[k]] += m.u[k] * (wgt * along * w[ids[k]].sqrt());
            }
        }
    }
}

/// A fixed pseudo-random start for slot `i`, with components on every direction and sign.
fn start_vector(i: usize) -> Vec3 {
    let h = |k: usize| {
        let v = (i.wrapping_mul(2654435761).wrapping_add(k * 40503)) % 1000;
        v as Real / 500.0 - 1.0
    };
    Vec3::new(h(1), h(2), h(3))
}

#[cfg(test)]
mod tests {
    use super::{StabilityLimit, ITERATIONS_AFTER_EDIT};
    use crate::math::{Real, Vec3};
    use crate::mesh::union_jack;
    use crate::physics::{integrator_named, Dynamics, ForceModel};
    use crate::physics::{Forces, Material, SpringMode};
    use crate::testing::{built, lifted, no_forces};

    /// The flat `n x n` grid at rest (one slot per vertex) under `forces` and `springs`.
    fn grid(n: usize, forces: Forces, springs: SpringMode) -> (ForceModel, Vec<Vec3>) {
        let mesh = union_jack(n, n, 1.0, 1.0);
        let material = Material {
            springs,
            ..Material::default()
        };
        (built(&mesh, &material, &forces), lifted(&mesh))
    }

    /// Spring damping only, so the step limit is the damping one.
    fn damping_only(n: usize) -> (ForceModel, Vec<Vec3>) {
        let forces = Forces {
            spring_damping: true,
            ..no_forces()
        };
        grid(n, forces, SpringMode::Tension)
    }

    /// Springs resisting both ways, no damping: the step limit is the oscillation one.
    fn springs_only(n: usize) -> (ForceModel, Vec<Vec3>) {
        let forces = Forces {
            springs: true,
            ..no_forces()
        };
        grid(n, forces, SpringMode::Both)
    }

    fn converged(model: &ForceModel, x: &[Vec3]) -> StabilityLimit {
        let mut limit = StabilityLimit::default();
        limit.update(model, x, 3000);
        limit
    }

    /// The per-vertex Gershgorin bound on the damping rate: `max_i 2 sum_j kd_j / m_i` (1/s).
    fn gershgorin(model: &ForceModel) -> Real {
        let w = model.inv_mass();
        let mut sum = vec![0.0; w.len()];
        let s = model.springs();
        for j in 0..s.len() {
            sum[s.a[j] as usize] += s.kd[j];
            sum[s.b[j] as usize] += s.kd[j];
        }
        w.iter()
            .zip(&sum)
            .map(|(w, c)| 2.0 * w * c)
            .fold(0.0, Real::max)
    }

    /// Runs symplectic Euler from a fixed small velocity field for 400 steps of `dt`; returns the
    /// final sum of |v|².
    fn run(model: &ForceModel, x0: &[Vec3], dt: Real) -> Real {
        let mut x = x0.to_vec();
        let mut v: Vec<Vec3> = (0..x.len())
            .map(|i| Vec3::new((i as Real * 0.37).sin(), (i as Real * 1.3).cos(), 0.2) * 1e-4)
            .collect();
        model.constrain_velocities(&mut v);
        let mut integrator = integrator_named("symplectic_euler").unwrap();
        for k in 0..400 {
            integrator.step(model, k as Real * dt, dt, &mut x, &mut v);
        }
        v.iter().map(|w| w.norm_squared()).sum()
    }

    #[test]
    fn the_damping_estimate_converges_below_the_gershgorin_bound() {
        let (model, x) = damping_only(9);
        let mut quick = StabilityLimit::default();
        quick.update(&model, &x, ITERATIONS_AFTER_EDIT);
        let exact = converged(&model, &x).decay_rate();
        let bound = gershgorin(&model);
        assert!(exact <= bound * (1.0 + 1e-12), "{exact} vs {bound}");
        assert!(
            exact < 0.8 * bound,
            "no tighter than Gershgorin: {exact} vs {bound}"
        );
        let estimate = quick.decay_rate();
        assert!(estimate > 0.9 * exact && estimate <= exact * (1.0 + 1e-9));
        assert_eq!(quick.frequency(), 0.0, "no stiffness switched on");
    }

    #[test]
    fn the_damping_limit_is_tight_stable_below_and_unstable_above() {
        let (model, x) = damping_only(9);
        let exact = 2.0 / converged(&model, &x).decay_rate();
        let start = run(&model, &x, 0.0);
        assert!(
            run(&model, &x, 0.95 * exact) <= start,
            "decays below the limit"
        );
        let blown = run(&model, &x, 1.2 * exact);
        assert!(
            !blown.is_finite() || blown > 1e6 * start,
            "{blown} vs {start}"
        );
        let mut estimate = StabilityLimit::default();
        estimate.update(&model, &x, ITERATIONS_AFTER_EDIT);
        let limit = estimate.step_limit(2.0);
        assert!(limit < exact && limit > 0.8 * exact, "{limit} vs {exact}");
    }

    #[test]
    fn the_oscillation_limit_is_tight_stable_below_and_unstable_above() {
        let (model, x) = springs_only(9);
        let exact = 2.0 / converged(&model, &x).frequency();
        let start = run(&model, &x, 0.0);
        assert!(
            run(&model, &x, 0.95 * exact) < 10.0 * start,
            "bounded below the limit"
        );
        let blown = run(&model, &x, 1.2 * exact);
        assert!(
            !blown.is_finite() || blown > 1e6 * start,
            "{blown} vs {start}"
        );
    }

    #[test]
    fn a_flattened_triangle_raises_the_bending_frequency_until_the_sliver_factor_bounds_it() {
        // Bending only: a square of two triangles, one opposite vertex pushed towards the
        // midpoint of the shared edge.
        let forces = Forces {
            bending: true,
            ..no_forces()
        };
        let (model, flat) = grid(2, forces, SpringMode::Tension);
        let mut frequency = Vec::new();
        // The rest ratio |N1| / |e|² is 0.5 here; the sliver factor starts at 0.05.
        for squash in [1.0, 0.1, 0.01, 0.001] {
            let x = squashed(&model, &flat, 0, squash);
            frequency.push(converged(&model, &x).frequency());
        }
        assert!(frequency[0] > 0.0);
        assert!(frequency[1] > 5.0 * frequency[0], "{frequency:?}");
        assert!(frequency[2] < frequency[1], "{frequency:?}");
        assert!(frequency[3] < frequency[2], "{frequency:?}");
    }

    #[test]
    fn new_slots_are_seen_at_once() {
        // The slots grow from 25 to 81 with lighter vertices: the warm start sees them at once.
        let (coarse, x) = damping_only(5);
        let mut limit = StabilityLimit::default();
        limit.update(&coarse, &x, ITERATIONS_AFTER_EDIT);
        let before = limit.decay_rate();
        let (fine, xf) = damping_only(9);
        limit.update(&fine, &xf, ITERATIONS_AFTER_EDIT);
        let exact = converged(&fine, &xf).decay_rate();
        let after = limit.decay_rate();
        assert!(
            after > 3.0 * before && after > 0.9 * exact,
            "{before} {after} {exact}"
        );
    }

    /// `x` with the opposite vertex of bending element `e` pushed towards the midpoint of its
    /// shared edge, to `squash` of its distance: a squashed triangle, a stiff bending mode there.
    fn squashed(model: &ForceModel, x: &[Vec3], e: usize, squash: Real) -> Vec<Vec3> {
        let [x1, _, x3, x4] = model.bends().v[e].map(|i| i as usize);
        let mid = (x[x3] + x[x4]) * 0.5;
        let mut x = x.to_vec();
        x[x1] = mid + (x[x1] - mid) * squash;
        x
    }

    #[test]
    fn after_an_edit_moves_the_fastest_mode_elsewhere_the_estimate_finds_it() {
        // Springs and bending on a 9x9 grid: a squashed triangle at one end, then (the "edit")
        // the same squash at the other end instead. The warm start holds the first mode only.
        let forces = Forces {
            springs: true,
            bending: true,
            ..no_forces()
        };
        let (model, flat) = grid(9, forces, SpringMode::Both);
        let last = model.bends().len() - 1;
        let squash = 0.1;
        let before = squashed(&model, &flat, 0, squash);
        let after = squashed(&model, &flat, last, squash);
        let exact = converged(&model, &after).frequency();
        assert!(
            exact > 1.1 * converged(&model, &flat).frequency(),
            "the squash makes the fastest mode"
        );
        let mut warm = converged(&model, &before);
        let mut mixed = warm.clone();
        warm.update(&model, &after, ITERATIONS_AFTER_EDIT);
        mixed.update_after_edit(&model, &after);
        let (warm, mixed) = (warm.frequency(), mixed.frequency());
        assert!(
            warm < 0.9 * exact,
            "the warm start alone falls short: {warm} vs {exact}"
        );
        assert!(
            mixed > 0.97 * exact && mixed <= exact * (1.0 + 1e-9),
            "{mixed} vs {exact}"
        );
    }

    #[test]
    fn no_limit_without_damping_or_stiffness() {
        let forces = Forces {
            gravity: true,
            drag: true,
            ..no_forces()
        };
        let (model, x) = grid(3, forces, SpringMode::Tension);
        let mut limit = StabilityLimit::default();
        limit.update(&model, &x, 5);
        assert_eq!(limit.step_limit(2.0), Real::INFINITY);
    }
}
