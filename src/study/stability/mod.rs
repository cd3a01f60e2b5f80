//! The stability suite (issue 3): the largest stable step of every integrator on `hanging`, and
//! the hard cases, each with its pass criterion and its measured figure, for every built strategy.
//!
//! **Stable** (bisection): the run reaches its duration without divergence (non-finite state or a
//! vertex above `time.max_speed`) and its total energy never exceeds the initial total energy by
//! more than [`ENERGY_TOL`] x `M |g| 1 m` (an explicit scheme that gains energy is unstable even if
//! it has not yet blown up). Steps are given as the multiple `beta` of `pi sqrt(m_min/k_max)`.

use crate::cloth::Cloth;
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{Mesh, RestLocator, VertexId};
use crate::physics::INTEGRATORS;
use crate::scene::{self, LoadedScene, TimeMode};
use crate::sim::{Simulation, StepError};
use crate::strategies::strategy_names;
use std::time::Instant;

mod cases;

pub use cases::*;

/// Fewest steps of a bisection trial and of the beyond-the-limit case.
pub const MIN_STEPS: usize = 40;

/// Energy tolerance of the stability criteria, as a fraction of `M |g| x 1 m`.
pub const ENERGY_TOL: Real = 1e-3;

/// Every registered strategy (the suite runs for each).
pub fn built_strategies() -> Vec<&'static str> {
    strategy_names().to_vec()
}

/// An embedded scene with the given integrator and strategy (panics only on a broken embedded
/// scene, which the scene tests rule out).
pub fn embedded(name: &str, integrator: &str, strategy: &str) -> LoadedScene {
    let mut loaded = scene::load_embedded(name, &[])
        .expect("embedded scene exists")
        .expect("embedded scene is valid");
    loaded.scene.integrator.name = integrator.to_string();
    loaded.scene.adaptivity.strategy = strategy.to_string();
    loaded.scene.tracked.clear();
    loaded
}

/// How a study run ended and what it measured.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// Reached the duration.
    pub completed: bool,
    /// Why it stopped early (the simulation's message), empty when completed.
    pub message: String,
    /// True when it stopped as diverged.
    pub diverged: bool,
    /// Steps taken.
    pub steps: u64,
    /// Wall time (s).
    pub wall_s: f64,
    /// Total energy at the start (J).
    pub e0: Real,
    /// Largest total energy above the start (J).
    pub max_rise_from_start: Real,
    /// Largest rise of the total energy above its running minimum after `t_settle` (J).
    pub max_rise_after_settle: Real,
    /// `M |g| 1 m` (J), the energy scale of the tolerances.
    pub energy_scale: Real,
    /// Largest penetration into an obstacle over the run (m).
    pub max_penetration: Real,
    /// All positions and velocities finite at the end.
    pub finite: bool,
}

/// World position (m) of the material point at rest coordinates `rest` (m): interpolated in the
/// face holding it (the nearest vertex's when no face does).
pub fn material_point(cloth: &Cloth, rest: Vec2) -> Vec3 {
    let mesh = &cloth.mesh;
    match RestLocator::new(mesh).locate(mesh, rest) {
        Some(b) => cloth.world_position(&b),
        None => {
            let nearest = mesh
                .vertices()
                .min_by(|a, b| {
                    let d = |v: VertexId| (mesh.rest(v) - rest).norm();
                    d(*a).total_cmp(&d(*b))
                })
                .expect("a vertex");
            cloth.x[nearest.0 as usize]
        }
    }
}

/// Steps `sim` to its duration, measuring energy after every step (and penetration when
/// `penetration` is set).
pub fn run(mut sim: Simulation, t_settle: Real, penetration: bool) -> (Outcome, Simulation) {
    let clock = Instant::now();
    let g = Vec3::from(sim.scene.forces.g).norm();
    let energy = |s: &Simulation| s.energies().total();
    let mut o = Outcome {
        e0: energy(&sim),
        energy_scale: sim.cloth.model.total_mass() * g.max(1.0),
        ..Outcome::default()
    };
    let mut min_e = Real::INFINITY;
    while !sim.finished() {
        if let Err(e) = sim.step() {
            o.diverged = matches!(e, StepError::Diverged { .. });
            o.message = e.to_string();
            break;
        }
        let e = energy(&sim);
        o.max_rise_from_start = o.max_rise_from_start.max(e - o.e0);
        if sim.t >= t_settle {
            min_e = min_e.min(e);
            o.max_rise_after_settle = o.max_rise_after_settle.max(e - min_e);
        }
        if penetration {
            o.max_penetration = o.max_penetration.max(sim.max_penetration());
        }
    }
    o.completed = sim.finished() && o.message.is_empty();
    o.steps = sim.steps;
    o.wall_s = clock.elapsed().as_secs_f64();
    o.finite = sim
        .cloth
        .x
        .iter()
        .chain(&sim.cloth.v)
        .all(|p| p.iter().all(|c| c.is_finite()));
    (o, sim)
}

/// `hanging` with Young's modulus `e`, `resolution`, `duration`, and the step `beta pi
/// sqrt(m_min/k_max)` (fixed, computed once on the initial mesh, so a step never shrinks and the
/// dynamic step's stability cap, which would hide the limit being measured, does not apply).
pub fn hanging(
    integrator: &str,
    strategy: &str,
    e: Real,
    resolution: usize,
    duration: Real,
    beta: Real,
) -> Simulation {
    let mut loaded = sized("hanging", integrator, strategy, resolution, duration);
    let s = &mut loaded.scene;
    s.material.young = e;
    let unit = Simulation::new(&loaded)
        .expect("hanging builds")
        .cloth
        .model
        .stable_step(1.0);
    let s = &mut loaded.scene;
    s.time.mode = TimeMode::Fixed;
    s.time.dt = beta * unit;
    Simulation::new(&loaded).expect("hanging builds")
}

/// An embedded scene at `resolution` (vertices per side) for `duration` (s).
fn sized(
    name: &str,
    integrator: &str,
    strategy: &str,
    resolution: usize,
    duration: Real,
) -> LoadedScene {
    let mut loaded = embedded(name, integrator, strategy);
    loaded.scene.cloth.resolution = resolution;
    loaded.scene.time.duration = duration;
    loaded
}

/// True when `o` meets the bisection's stability criterion.
pub fn is_stable(o: &Outcome) -> bool {
    o.completed && o.finite && o.max_rise_from_start <= ENERGY_TOL * o.energy_scale
}

/// The largest stable step of one integrator, found by bisection.
#[derive(Clone, Debug)]
pub struct StableStep {
    /// Integrator.
    pub integrator: &'static str,
    /// Young's modulus (N/m²).
    pub young: Real,
    /// Largest stable multiple of `pi sqrt(m_min/k_max)` (the bracket's stable end).
    pub multiple: Real,
    /// The bracket's unstable end (`INFINITY` when the top of the search range was stable).
    pub unstable_at: Real,
    /// The explicit limit `pi sqrt(m_min/k_max)` (s).
    pub unit_s: Real,
}

/// Bisection settings.
#[derive(Clone, Copy, Debug)]
pub struct Search {
    /// Cloth resolution of `hanging`.
    pub resolution: usize,
    /// Simulated duration of each trial (s).
    pub duration: Real,
    /// Search range of the multiple.
    pub range: (Real, Real),
    /// Geometric bisection iterations.
    pub iterations: usize,
}

/// Largest stable multiple of `integrator` on `hanging` at Young's modulus `e` (geometric
/// bisection over `search.range`; stability is assumed monotonic in the step).
pub fn largest_stable(
    integrator: &'static str,
    strategy: &str,
    e: Real,
    search: &Search,
) -> StableStep {
    // At least MIN_STEPS steps per trial, so a huge step cannot pass by taking a single step.
    let trial = |beta: Real| {
        let unit = hanging(integrator, strategy, e, search.resolution, 1.0, 1.0)
            .cloth
            .model
            .stable_step(1.0);
        // A whole number of equal steps (no cut last step, which position Verlet mishandles).
        let dt = beta * unit;
        let steps = ((search.duration / dt).ceil() as usize).max(MIN_STEPS);
        let duration = steps as Real * dt * (1.0 - 1e-10);
        let sim = hanging(integrator, strategy, e, search.resolution, duration, beta);
        is_stable(&run(sim, 0.0, false).0)
    };
    let unit_s = hanging(
        integrator,
        strategy,
        e,
        search.resolution,
        search.duration,
        1.0,
    )
    .cloth
    .model
    .stable_step(1.0);
    let (mut lo, mut hi) = search.range;
    let mut result = StableStep {
        integrator,
        young: e,
        multiple: hi,
        unstable_at: Real::INFINITY,
        unit_s,
    };
    if trial(hi) {
        return result;
    }
    if !trial(lo) {
        result.multiple = 0.0;
        result.unstable_at = lo;
        return result;
    }
    for _ in 0..search.iterations {
        let mid = (lo * hi).sqrt();
        if trial(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    result.multiple = lo;
    result.unstable_at = hi;
    result
}

/// The search of `docs/stability.md`.
pub const REPORT_SEARCH: Search = Search {
    resolution: 9,
    duration: 0.1,
    range: (2e-3, 64.0),
    iterations: 6,
};

/// The suite's report: `docs/stability.md`'s text and how many hard cases failed.
#[derive(Clone, Debug)]
pub struct SuiteReport {
    /// The report (markdown).
    pub markdown: String,
    /// Hard cases that failed their criterion.
    pub failed: usize,
}

/// Runs the suite for `strategies` (the step bisection on the first, the hard cases for each)
/// and returns its report; `progress` hears about each piece.
pub fn report(
    search: &Search,
    sizes: &CaseSizes,
    strategies: &[&str],
    mut progress: impl FnMut(&str),
) -> SuiteReport {
    let started = Instant::now();
    let mut md = String::from(
        "# Stability of the integrators\n\n\
         Generated by `adaptcloth stability` (do not edit by hand; rerun the command). The \
         criteria and the code are in `src/study/stability/`; `tests/stability.rs` runs the \
         same cases at small sizes with assertions.\n\n",
    );
    md += &format!(
        "## Largest stable step on `hanging`\n\n\
         Geometric bisection ({} iterations) of the step multiple `beta` in [{}, {}], the step \
         being `beta pi sqrt(m_min/k_max)` on the initial mesh (resolution {}x{}, {} s per trial, \
         strategy `{}`). Stable = reaches the duration without divergence and the total energy \
         never exceeds its initial value by more than {} x M|g| x 1 m. Stability is assumed \
         monotonic in the step. `>= {}` means the top of the range was stable.\n\n\
         | integrator | E = 1e7: largest stable multiple | first unstable | E = 1e9: largest stable multiple | first unstable |\n|---|---|---|---|---|\n",
        search.iterations,
        search.range.0,
        search.range.1,
        search.resolution,
        search.resolution,
        search.duration,
        strategies.first().copied().unwrap_or("static"),
        ENERGY_TOL,
        search.range.1
    );
    let strategy = strategies.first().copied().unwrap_or("static");
    let mut units = Vec::new();
    for integrator in INTEGRATORS {
        let mut cells = Vec::new();
        for e in [1e7, 1e9] {
            progress(&format!("bisection: {integrator} at E = {e:e}"));
            let r = largest_stable(integrator, strategy, e, search);
            if units.len() < 2 {
                units.push((e, r.unit_s));
            }
            let stable = if r.unstable_at.is_infinite() {
                format!(">= {}", r.multiple)
            } else if r.multiple == 0.0 {
                format!("< {}", r.unstable_at)
            } else {
                format!("{:.3}", r.multiple)
            };
            let unstable = if r.unstable_at.is_infinite() {
                "-".to_string()
            } else {
                format!("{:.3}", r.unstable_at)
            };
            cells.push(format!("{stable} | {unstable}"));
        }
        md += &format!("| `{integrator}` | {} |\n", cells.join(" | "));
    }
    md += "\nThe unit `pi sqrt(m_min/k_max)`: ";
    md += &units
        .iter()
        .map(|(e, u)| format!("{u:.3e} s at E = {e:e}"))
        .collect::<Vec<_>>()
        .join(", ");
    md += ".\n\n## Hard cases\n\n";
    md += &format!(
        "Sizes: grid resolution {r}x{r}, short cases {d} s, long run {l} s, drop from {h} m. \
         Explicit reference: `rk4` at beta = 0.02 (0.002 for E = 1e9 over 0.2 s, 0.008 for the tiny elements; dynamic step); large steps: `implicit_euler` at \
         a fixed 1/240 s. The step-beyond-the-limit case runs every integrator. Energy tolerance: \
         {tol} x M|g| x 1 m. Strategies: {s}.\n\n\
         | case | strategy | integrator | pass criterion | measured | result |\n|---|---|---|---|---|---|\n",
        r = sizes.resolution,
        d = sizes.duration,
        l = sizes.long_duration,
        h = sizes.drop_height,
        tol = ENERGY_TOL,
        s = strategies.join(", ")
    );
    let mut failed = 0;
    for strategy in strategies {
        progress(&format!("hard cases: strategy {strategy}"));
        for c in hard_cases(strategy, sizes) {
            failed += usize::from(!c.passed);
            md += &format!(
                "| {} | `{}` | `{}` | {} | {} | {} |\n",
                c.case,
                c.strategy,
                c.integrator,
                c.criterion,
                c.measured.replace('|', "/"),
                if c.passed { "pass" } else { "**FAIL**" }
            );
        }
    }
    md += &format!(
        "\n{failed} case(s) failed. Suite wall time {:.0} s.\n",
        started.elapsed().as_secs_f64()
    );
    SuiteReport {
        markdown: md,
        failed,
    }
}
