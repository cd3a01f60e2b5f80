//! Integrator experiments: seed 004's single-particle comparison (§6.1, Tables 2-5) and the
//! convergence-order study on a damped spring. Used by `adaptcloth integrators`, which writes
//! [`report`] into `docs/integrators.md`, and by the tests.
//!
//! **Seed 004's experiments** (a particle on a line, every integrator through the same
//! [`Dynamics`] interface as the cloth):
//! 1. constant acceleration `-9.81 m/s²` from `x = 0`, `v0 = 61.29 m/s`, 25 steps of `0.25 s`
//!    (Table 2), then 25 random steps (Table 3);
//! 2. the polynomial trajectory `x = 2t³ - 7t² + 5t` (`a = 12t - 14`, `v0 = 5 m/s`), random steps
//!    (Table 4);
//! 3. the sine trajectory `x = -sin t` (`a = sin t`, `v0 = -1 m/s`), random steps (Table 5).
//!
//! The source gives neither its random steps nor its exact statistic. Here: random steps are
//! `dt_base x U(0.5, 1.5)` from a fixed-seed SplitMix64 generator ([`random_steps`]); the
//! statistic is the population standard deviation of the position error `x_num - x_exact` over
//! the `n + 1` recorded points (start included), which reproduces Table 2's Euler entry to 1 %.

use crate::math::{Real, Vec3};
use crate::physics::{
    integrator_named, Dynamics, ForceModel, Forces, Material, SpringMode, Springs, INTEGRATORS,
};

/// A particle on the x axis with a prescribed acceleration `a(t)` (no velocity dependence).
struct Prescribed {
    accel: fn(Real) -> Real,
}

impl Dynamics for Prescribed {
    fn accelerations(&self, t: Real, _x: &[Vec3], _v: &[Vec3], a: &mut [Vec3]) {
        a.fill(Vec3::new((self.accel)(t), 0.0, 0.0));
    }

    fn velocity_dependent(&self) -> bool {
        false
    }
}

/// One of seed 004's experiments.
#[derive(Clone, Copy, Debug)]
pub struct Experiment {
    /// Short name.
    pub name: &'static str,
    /// The source's table.
    pub table: &'static str,
    /// Prescribed acceleration `a(t)` (m/s²).
    pub accel: fn(Real) -> Real,
    /// Exact position `x(t)` (m).
    pub exact: fn(Real) -> Real,
    /// Initial velocity (m/s); the particle starts at `x = 0`.
    pub v0: Real,
    /// Base step (s).
    pub dt: Real,
    /// Number of steps.
    pub steps: usize,
    /// Random steps (`dt x U(0.5, 1.5)`) instead of constant ones.
    pub random: bool,
    /// The source's standard deviations (m): positional Verlet, time-corrected Verlet, Euler,
    /// velocity Verlet.
    pub source: [Real; 4],
}

/// The integrators the source compares, in its table order, with our names.
pub const SOURCE_METHODS: [(&str, &str); 4] = [
    ("Positional Verlet", "verlet"),
    ("Verlet com Correção de Tempo", "time_corrected_verlet"),
    ("Euler", "symplectic_euler"),
    ("Velocity Verlet", "velocity_verlet"),
];

/// The integrators run on a single particle: every registered one except `implicit_euler`,
/// `bdf2` and `verlet_relaxation`, which on a free particle without springs (no force model) are
/// symplectic Euler, symplectic Euler and time-corrected Verlet exactly.
pub fn particle_methods() -> Vec<&'static str> {
    INTEGRATORS
        .iter()
        .copied()
        .filter(|n| !matches!(*n, "implicit_euler" | "bdf2" | "verlet_relaxation"))
        .collect()
}

/// Seed 004's experiment 1 (Tables 2 and 3): constant acceleration `-9.81 m/s²` from
/// `v0 = 61.29 m/s`, 25 steps of 0.25 s, constant or `random`; `source` as in [`Experiment`].
fn free_fall(random: bool, source: [Real; 4]) -> Experiment {
    const G: Real = -9.81;
    const V0: Real = 61.29;
    Experiment {
        name: if random {
            "1: constant acceleration, random steps"
        } else {
            "1: constant acceleration, constant steps"
        },
        table: if random { "Tabela 3" } else { "Tabela 2" },
        accel: |_| G,
        exact: |t| V0 * t + 0.5 * G * t * t,
        v0: V0,
        dt: 0.25,
        steps: 25,
        random,
        source,
    }
}

/// Seed 004's four tables.
pub fn seed_experiments() -> [Experiment; 4] {
    [
        free_fall(false, [0.0, 0.0, 2.32, 0.0]),
        free_fall(true, [53.74, 0.58, 2.51, 0.0]),
        Experiment {
            name: "2: x = 2t³ - 7t² + 5t, random steps",
            table: "Tabela 4",
            accel: |t| 12.0 * t - 14.0,
            exact: |t| 2.0 * t * t * t - 7.0 * t * t + 5.0 * t,
            v0: 5.0,
            dt: 0.1,
            steps: 25,
            random: true,
            source: [7.09, 1.65, 3.13, 0.53],
        },
        Experiment {
            name: "3: x = -sin t, random steps",
            table: "Tabela 5",
            accel: |t| t.sin(),
            exact: |t| -t.sin(),
            v0: -1.0,
            dt: 0.5,
            steps: 25,
            random: true,
            source: [1.74, 1.11, 0.25, 0.13],
        },
    ]
}

/// `n` steps `dt x U(0.5, 1.5)` from a SplitMix64 generator with a fixed seed (reproducible).
pub fn random_steps(dt: Real, n: usize, seed: u64) -> Vec<Real> {
    let mut state = seed;
    (0..n)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            let u = (z >> 11) as Real / (1u64 << 53) as Real;
            dt * (0.5 + u)
        })
        .collect()
}

/// The fixed seed of the random steps.
pub const STEP_SEED: u64 = 4;

/// The position errors `x_num - x_exact` (m) of `method` on `exp` at the start and after each
/// step.
pub fn trajectory_errors(exp: &Experiment, method: &str) -> Vec<Real> {
    let steps = if exp.random {
        random_steps(exp.dt, exp.steps, STEP_SEED)
    } else {
        vec![exp.dt; exp.steps]
    };
    let dynamics = Prescribed { accel: exp.accel };
    let mut integ = integrator_named(method).expect("registered integrator");
    let mut x = [Vec3::zeros()];
    let mut v = [Vec3::new(exp.v0, 0.0, 0.0)];
    let mut t = 0.0;
    let mut errors = vec![0.0];
    for dt in steps {
        integ.step(&dynamics, t, dt, &mut x, &mut v);
        t += dt;
        errors.push(x[0].x - (exp.exact)(t));
    }
    errors
}

/// Population standard deviation (m) of a set of errors.
pub fn std_dev(e: &[Real]) -> Real {
    let n = e.len() as Real;
    let mean = e.iter().sum::<Real>() / n;
    (e.iter().map(|x| (x - mean).powi(2)).sum::<Real>() / n).sqrt()
}

/// Root mean square (m) of a set of errors.
pub fn rms(e: &[Real]) -> Real {
    (e.iter().map(|x| x * x).sum::<Real>() / e.len() as Real).sqrt()
}

/// One cell of the comparison table.
#[derive(Clone, Debug)]
pub struct ParticleResult {
    /// Integrator name.
    pub method: &'static str,
    /// Standard deviation of the position error (m).
    pub std_dev: Real,
    /// RMS position error (m).
    pub rms: Real,
    /// Largest absolute position error (m).
    pub max_abs: Real,
}

/// Runs every particle method on `exp`.
pub fn run_experiment(exp: &Experiment) -> Vec<ParticleResult> {
    particle_methods()
        .into_iter()
        .map(|method| {
            let e = trajectory_errors(exp, method);
            ParticleResult {
                method,
                std_dev: std_dev(&e),
                rms: rms(&e),
                max_abs: e.iter().fold(0.0, |m: Real, x| m.max(x.abs())),
            }
        })
        .collect()
}

/// The damped spring of the order study: a 1 kg particle on a spring (k = 100 N/m, kd = 1 N s/m,
/// rest length 1 m) to a pinned anchor, released 0.1 m stretched; no gravity, drag or bending.
fn damped_spring() -> (ForceModel, Vec<Vec3>, Vec<Vec3>) {
    let material = Material {
        springs: SpringMode::Both,
        ..Material::default()
    };
    let forces = Forces {
        springs: true,
        spring_damping: true,
        bending: false,
        bending_damping: false,
        gravity: false,
        drag: false,
        g: Vec3::zeros(),
    };
    let springs = Springs {
        a: vec![0],
        b: vec![1],
        rest_length: vec![1.0],
        k: vec![SPRING_K],
        kd: vec![SPRING_KD],
    };
    let model = ForceModel::from_parts(&material, &forces, vec![1.0, 1.0], &[true, false], springs);
    let x = vec![Vec3::zeros(), Vec3::new(1.0 + SPRING_S0, 0.0, 0.0)];
    (model, x, vec![Vec3::zeros(); 2])
}

const SPRING_K: Real = 100.0;
const SPRING_KD: Real = 1.0;
const SPRING_S0: Real = 0.1;

/// Exact extension (m) of the damped spring at time `t` (s).
fn damped_exact(t: Real) -> Real {
    let gamma = 0.5 * SPRING_KD; // kd / (2 m), m = 1
    let wd = (SPRING_K - gamma * gamma).sqrt();
    (-gamma * t).exp() * SPRING_S0 * ((wd * t).cos() + gamma / wd * (wd * t).sin())
}

/// Position error (m) of `method` at `t = 1 s` on the damped spring with `n` equal steps.
pub fn damped_spring_error(method: &str, n: usize) -> Real {
    let (model, mut x, mut v) = damped_spring();
    let mut integ = integrator_named(method).expect("registered integrator");
    let dt = 1.0 / n as Real;
    for k in 0..n {
        integ.step(&model, k as Real * dt, dt, &mut x, &mut v);
    }
    (x[1].x - 1.0 - damped_exact(1.0)).abs()
}

/// Observed convergence order of `method` on the damped spring: `log2(e(n) / e(2n))` at
/// `t = 1 s`, for `n` steps.
pub fn observed_order(method: &str, n: usize) -> Real {
    (damped_spring_error(method, n) / damped_spring_error(method, 2 * n)).log2()
}

/// The comparison of seed 004 as a markdown table: ours beside the source's, per experiment.
pub fn markdown_table() -> String {
    let mut out = String::new();
    for exp in seed_experiments() {
        let results = run_experiment(&exp);
        out += &format!(
            "\n**Experiment {}** ({} of seed 004; {} steps of {} s{}).\n\n",
            exp.name,
            exp.table,
            exp.steps,
            exp.dt,
            if exp.random { " x U(0.5, 1.5)" } else { "" }
        );
        out += "| integrator | source std dev (m) | our std dev (m) | our RMS error (m) | our max error (m) |\n|---|---|---|---|---|\n";
        for r in &results {
            let source = SOURCE_METHODS
                .iter()
                .position(|(_, ours)| *ours == r.method)
                .map(|k| format!("{} ({})", exp.source[k], SOURCE_METHODS[k].0))
                .unwrap_or_else(|| "-".into());
            out += &format!(
                "| `{}` | {} | {:.3e} | {:.3e} | {:.3e} |\n",
                r.method, source, r.std_dev, r.rms, r.max_abs
            );
        }
    }
    out
}

/// Opening marker of the generated tables in `docs/integrators.md`.
pub const TABLE_BEGIN: &str =
    "<!-- BEGIN integrators table (adaptcloth integrators --write-docs) -->";
/// Closing marker of the generated tables.
pub const TABLE_END: &str = "<!-- END integrators table -->";

/// Seed 004's tables beside ours ([`markdown_table`]) and the observed convergence orders.
pub fn report() -> String {
    let mut table = markdown_table();
    table += "
**Observed convergence order** on the damped spring (`log2(e(n)/e(2n))` at t = 1 s, n = 400):

| integrator | order |\n|---|---|\n";
    for name in INTEGRATORS {
        if *name == "verlet_relaxation" {
            table += "| `verlet_relaxation` | - (rigid bars: converges to another problem) |\n";
            continue;
        }
        table += &format!("| `{name}` | {:.3} |\n", observed_order(name, 400));
    }
    table
}

/// `document` with the text between [`TABLE_BEGIN`] and [`TABLE_END`] replaced by `table`;
/// `None` when the markers are missing.
pub fn replace_generated(document: &str, table: &str) -> Option<String> {
    let (a, b) = (document.find(TABLE_BEGIN)?, document.find(TABLE_END)?);
    (a < b).then(|| {
        format!(
            "{}{TABLE_BEGIN}\n{table}\n{}",
            &document[..a],
            &document[b..]
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_tables_replace_only_the_text_between_the_markers() {
        let doc = format!("intro\n{TABLE_BEGIN}\nold\n{TABLE_END}\noutro\n");
        let new = replace_generated(&doc, "new").unwrap();
        assert_eq!(
            new,
            format!("intro\n{TABLE_BEGIN}\nnew\n{TABLE_END}\noutro\n")
        );
        assert!(replace_generated("no markers", "x").is_none());
    }

    #[test]
    fn verlet_family_and_velocity_verlet_are_exact_under_constant_acceleration() {
        let exp = seed_experiments()[0];
        assert!(!exp.random);
        for name in [
            "velocity_verlet",
            "verlet",
            "time_corrected_verlet",
            "verlet_relaxation",
            "rk4",
        ] {
            let e = trajectory_errors(&exp, name);
            let worst = e.iter().fold(0.0, |m: Real, x| m.max(x.abs()));
            // Positions reach ~190 m: round-off is ~1e-13 m.
            assert!(worst <= 1e-10, "{name}: error {worst:e} m");
        }
        // The Euler schemes are not exact: their error grows linearly, dt² a n / 2 at step n.
        for name in ["explicit_euler", "symplectic_euler"] {
            let e = trajectory_errors(&exp, name);
            let want = 0.25 * 0.25 * 9.81 * 25.0 / 2.0;
            assert!((e[25].abs() - want).abs() <= 1e-9, "{name}: {}", e[25]);
        }
    }

    #[test]
    fn time_corrected_and_velocity_verlet_stay_exact_under_random_steps_but_position_verlet_does_not(
    ) {
        let exp = seed_experiments()[1];
        assert!(exp.random);
        for name in ["velocity_verlet", "rk4"] {
            let e = trajectory_errors(&exp, name);
            let worst = e.iter().fold(0.0, |m: Real, x| m.max(x.abs()));
            assert!(worst <= 1e-10, "{name}: error {worst:e} m");
        }
        // Seed 004's (4.4d) assumes dt_prev = dt in its acceleration term: off by a dt (dt - dt_prev)/2
        // per step, far less than position Verlet, which ignores the step change altogether.
        let sd = |name| std_dev(&trajectory_errors(&exp, name));
        let (tcv, verlet) = (sd("time_corrected_verlet"), sd("verlet"));
        assert!(
            tcv > 1e-3 && verlet > 10.0 * tcv,
            "tcv {tcv}, verlet {verlet}"
        );
    }

    #[test]
    fn verlet_relaxation_keeps_the_bar_at_its_rest_length() {
        // The damped spring released 10 % stretched: relaxation makes it a rigid bar at once.
        for n in [50, 100] {
            let e = damped_spring_error("verlet_relaxation", n);
            // The error is the whole elastic motion (<= the 0.1 m release stretch), not a step error.
            assert!(e > 1e-3 && e <= 0.1, "{e}");
            assert!((e - damped_spring_error("verlet_relaxation", 2 * n)).abs() < 1e-9);
        }
    }

    #[test]
    fn observed_convergence_orders_on_a_damped_spring() {
        let expected = [
            ("explicit_euler", 1.0),
            ("symplectic_euler", 1.0),
            ("implicit_euler", 1.0),
            ("bdf2", 2.0),
            ("velocity_verlet", 2.0),
            ("verlet", 2.0),
            ("time_corrected_verlet", 2.0),
            ("rk4", 4.0),
        ];
        // verlet_relaxation replaces each spring by a rigid bar: it converges to another problem.
        assert_eq!(expected.len() + 1, INTEGRATORS.len());
        for (name, order) in expected {
            let p = observed_order(name, 400);
            assert!(
                (p - order).abs() <= 0.25,
                "{name}: observed order {p:.3}, expected {order}"
            );
        }
    }
}
