//! The stability suite (issue 3): the largest stable step of every integrator on `hanging`, and
//! the hard cases, each with its pass criterion and its measured figure, for every built strategy.
//!
//! **Stable** (bisection): the run reaches its duration without divergence (non-finite state or a
//! vertex above `time.max_speed`) and its total energy never exceeds the initial total energy by
//! more than [`ENERGY_TOL`] x `M |g| 1 m` (an explicit scheme that gains energy is unstable even if
//! it has not yet blown up). Steps are given as the multiple `beta` of `pi sqrt(m_min/k_max)`.

use crate::cloth::Cloth;
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{Mesh, VertexId};
use crate::physics::INTEGRATORS;
use crate::scene::{self, LoadedScene, TimeMode};
use crate::sim::{Simulation, StepError};
use crate::strategies::strategy_names;
use std::time::Instant;

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
    /// Total conjugate-gradient iterations.
    pub cg_iterations: usize,
    /// All positions and velocities finite at the end.
    pub finite: bool,
}

/// Steps `sim` to its duration, measuring energy after every step (and penetration when
/// `penetration` is set).
pub fn run(mut sim: Simulation, t_settle: Real, penetration: bool) -> (Outcome, Simulation) {
    let clock = Instant::now();
    let g = Vec3::from(sim.scene.forces.g).norm();
    let energy = |s: &Simulation| s.cloth.model.energies(&s.cloth.x, &s.cloth.v).total();
    let mut o = Outcome {
        e0: energy(&sim),
        energy_scale: sim.cloth.model.total_mass() * g.max(1.0),
        ..Outcome::default()
    };
    let mut min_e = Real::INFINITY;
    while !sim.finished() {
        match sim.step() {
            Ok(r) => o.cg_iterations += r.integrator.cg_iterations,
            Err(e) => {
                o.diverged = matches!(e, StepError::Diverged { .. });
                o.message = e.to_string();
                break;
            }
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
/// sqrt(m_min/k_max)` (fixed, computed once on the initial mesh, so a step never shrinks).
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
    s.time.mode = TimeMode::Dynamic;
    s.time.beta = beta;
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

/// One hard case's result.
#[derive(Clone, Debug)]
pub struct CaseResult {
    /// Case name.
    pub case: &'static str,
    /// Strategy.
    pub strategy: String,
    /// Integrator.
    pub integrator: String,
    /// The pass criterion, in words.
    pub criterion: String,
    /// The measured figures, in words.
    pub measured: String,
    /// Whether the criterion held.
    pub passed: bool,
}

/// Sizes of the hard cases (the report uses [`CaseSizes::REPORT`], the tests smaller ones).
#[derive(Clone, Copy, Debug)]
pub struct CaseSizes {
    /// Cloth resolution of the grid cases.
    pub resolution: usize,
    /// Duration of the short cases (s).
    pub duration: Real,
    /// Duration of the long run (s).
    pub long_duration: Real,
    /// Height of the drop above the sphere's top (m).
    pub drop_height: Real,
    /// Duration of the tiny-elements case (s): its explicit step is tiny.
    pub tiny_duration: Real,
}

impl CaseSizes {
    /// The sizes of `docs/stability.md`.
    pub const REPORT: CaseSizes = CaseSizes {
        resolution: 17,
        duration: 0.5,
        long_duration: 10.0,
        drop_height: 3.0,
        tiny_duration: 0.1,
    };
    /// Quick sizes for the tests.
    pub const QUICK: CaseSizes = CaseSizes {
        resolution: 9,
        duration: 0.2,
        long_duration: 2.0,
        drop_height: 3.0,
        tiny_duration: 0.04,
    };
}

/// The integrators the hard cases run with: `rk4` at `beta = 0.02` (below its measured limit on
/// 17x17 at E = 1e7, 0.044; the stiff case uses a tenth, below the limit at E = 1e9, 0.004) and `implicit_euler` at a
/// fixed 1/240 s (beta 0).
pub const CASE_INTEGRATORS: [(&str, Real); 2] = [("rk4", 0.02), ("implicit_euler", 0.0)];

/// Sets the step of a hard case: dynamic `beta` for explicit schemes, fixed 1/240 s for
/// `implicit_euler` (beta 0).
fn set_step(loaded: &mut LoadedScene, beta: Real) {
    let t = &mut loaded.scene.time;
    t.dt_initial = 0.0;
    if beta > 0.0 {
        t.mode = TimeMode::Dynamic;
        t.beta = beta;
    } else {
        t.mode = TimeMode::Fixed;
        t.dt = 1.0 / 240.0;
    }
}

fn energy_words(o: &Outcome) -> String {
    format!(
        "{} after {} steps ({:.2} s wall); energy rise after 0.1 s {:.2e} J (tolerance {:.2e} J)",
        if o.completed { "completed" } else { "stopped" },
        o.steps,
        o.wall_s,
        o.max_rise_after_settle,
        ENERGY_TOL * o.energy_scale
    )
}

/// Stiff material: `hanging` at E = 1e9.
pub fn case_stiff(strategy: &str, integrator: &str, beta: Real, sizes: &CaseSizes) -> CaseResult {
    let n = sizes.resolution;
    let mut loaded = sized("hanging", integrator, strategy, n, sizes.duration.min(0.2));
    loaded.scene.material.young = 1e9;
    // Spring damping (kd = alpha k) bounds the explicit step by about m/kd, which falls faster
    // than the unit with stiffness and resolution: rk4 runs at beta / 10 = 0.002 (the bisection
    // finds 0.016 on 5x5 at E = 1e9 and 0.004 on 17x17).
    set_step(&mut loaded, beta * 0.1);
    let (o, _) = run(Simulation::new(&loaded).expect("builds"), 0.1, false);
    CaseResult {
        case: "stiff material (E = 1e9)",
        strategy: strategy.into(),
        integrator: integrator.into(),
        criterion: "completes, finite, total energy never rises above its running minimum by more than the tolerance after 0.1 s".into(),
        passed: o.completed && o.finite && o.max_rise_after_settle <= ENERGY_TOL * o.energy_scale,
        measured: energy_words(&o),
    }
}

/// A fixed step of `factor` times the explicit limit on `hanging` (E = 1e7).
pub fn case_beyond_limit(
    strategy: &str,
    integrator: &str,
    factor: Real,
    sizes: &CaseSizes,
) -> CaseResult {
    let n = sizes.resolution;
    let mut loaded = sized("hanging", integrator, strategy, n, sizes.duration);
    let unit = Simulation::new(&loaded)
        .expect("builds")
        .cloth
        .model
        .stable_step(1.0);
    loaded.scene.time.mode = TimeMode::Fixed;
    loaded.scene.time.dt = factor * unit;
    loaded.scene.time.duration = sizes.duration.max(MIN_STEPS as Real * factor * unit);
    let (o, _) = run(Simulation::new(&loaded).expect("builds"), 0.1, false);
    let implicit = integrator == "implicit_euler";
    let relaxation = integrator == "verlet_relaxation";
    let bounded = o.completed && o.finite && o.max_rise_from_start <= ENERGY_TOL * o.energy_scale;
    let diverged_clearly = o.diverged && o.message.contains("diverged");
    let (criterion, passed) = if implicit {
        (
            "runs stably: completes, finite, and after 0.1 s the total energy never rises above its running minimum by more than the tolerance (the first steps may overshoot: one linearised Newton step per time step)",
            o.completed && o.finite && o.max_rise_after_settle <= ENERGY_TOL * o.energy_scale,
        )
    } else if relaxation {
        (
            "either ends `diverged` with a message or stays bounded (relaxation projects lengths)",
            diverged_clearly || bounded,
        )
    } else {
        (
            "ends with status `diverged` and a message (never a silent garbage result)",
            diverged_clearly,
        )
    };
    CaseResult {
        case: "step far beyond the explicit limit",
        strategy: strategy.into(),
        integrator: integrator.into(),
        criterion: format!(
            "dt = {factor} x pi sqrt(m_min/k_max) = {:.3e} s: {criterion}",
            factor * unit
        ),
        measured: if o.completed {
            format!(
                "completed {} steps; largest energy above the start {:.2e} J; rise after 0.1 s {:.2e} J",
                o.steps, o.max_rise_from_start, o.max_rise_after_settle
            )
        } else {
            o.message.clone()
        },
        passed,
    }
}

/// A tensor grid 1 m x 1 m whose first `fine` cells in u and v are `tiny` wide and the rest
/// share the remaining length: tiny elements next to large ones.
pub fn graded_mesh(fine: usize, tiny: Real, coarse: usize) -> (Mesh, Vec<Vec3>) {
    let mut ticks = vec![0.0];
    for k in 1..=fine {
        ticks.push(k as Real * tiny);
    }
    let start = fine as Real * tiny;
    for k in 1..=coarse {
        ticks.push(start + (1.0 - start) * k as Real / coarse as Real);
    }
    let n = ticks.len();
    let mut rest = Vec::new();
    for &v in &ticks {
        for &u in &ticks {
            rest.push(Vec2::new(u, v));
        }
    }
    let mut faces = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (
                j * n + i,
                j * n + i + 1,
                (j + 1) * n + i + 1,
                (j + 1) * n + i,
            );
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    let x = rest
        .iter()
        .map(|p| Vec3::new(p.x - 0.5, p.y - 0.5, 1.0))
        .collect();
    (
        Mesh::from_faces(rest, &faces).expect("valid graded grid"),
        x,
    )
}

/// Tiny elements next to large ones (vertex mass ratio about 1e-3), pinned at the two far corners.
pub fn case_tiny_elements(
    strategy: &str,
    integrator: &str,
    beta: Real,
    sizes: &CaseSizes,
) -> CaseResult {
    let mut loaded = embedded("hanging", integrator, strategy);
    loaded.scene.cloth.pinned.clear();
    loaded.scene.time.duration = sizes.tiny_duration;
    // The spring damping of the tiny elements (kd/m large) bounds the explicit step below the
    // hanging limit: rk4 runs at 0.4 beta = 0.008 (measured: diverges at 0.05, stable at 0.02).
    set_step(&mut loaded, beta * 0.4);
    let mut sim = Simulation::new(&loaded).expect("builds");
    // 3x3 cells of 1 cm beside 4 cells of about 24 cm per side: vertex mass ratio about 6e-4.
    let (mut mesh, x) = graded_mesh(3, 0.01, 4);
    let corners: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| (mesh.rest(v).y - 1.0).abs() < 1e-12 && (mesh.rest(v).x - 0.5).abs() > 0.49)
        .collect();
    for v in corners {
        mesh.set_pinned(v, true);
    }
    let model = &sim.cloth.model;
    sim.cloth = Cloth::new(mesh, x, Vec3::zeros(), model.material(), model.switches());
    let m = sim.cloth.model.mass();
    let max_m = m.iter().copied().fold(0.0, Real::max);
    let ratio = sim.cloth.model.min_mass() / max_m;
    let settle = 0.5 * sizes.tiny_duration;
    let (o, _) = run(sim, settle, false);
    CaseResult {
        case: "tiny elements next to large ones",
        strategy: strategy.into(),
        integrator: integrator.into(),
        criterion: format!("{} s with 3x3 cells of 1 cm beside cells of about 24 cm: completes, finite, total energy never rises above its running minimum by more than the tolerance after {settle} s", sizes.tiny_duration),
        measured: format!(
            "mass ratio m_min/m_max = {ratio:.1e}; {}{}",
            energy_words(&o),
            if o.message.is_empty() { String::new() } else { format!(" ({})", o.message) }
        ),
        passed: o.completed && o.finite && o.max_rise_after_settle <= ENERGY_TOL * o.energy_scale,
    }
}

/// The cloth dropped from `drop_height` above the sphere's top (impact at about
/// `sqrt(2 g h)`): no tunnelling.
pub fn case_impact(strategy: &str, integrator: &str, beta: Real, sizes: &CaseSizes) -> CaseResult {
    let mut loaded = embedded("sphere", integrator, strategy);
    let s = &mut loaded.scene;
    s.cloth.resolution = sizes.resolution;
    s.cloth.center = [0.0, 0.0, 0.25 + sizes.drop_height];
    // Without drag (its terminal speed, g rho T / kappa = 2 m/s, would soften the impact).
    s.forces.drag = false;
    let fall = (2.0 * sizes.drop_height / 9.81).sqrt();
    s.time.duration = fall + 0.2;
    set_step(&mut loaded, beta);
    let sim = Simulation::new(&loaded).expect("builds");
    let centre = sim
        .cloth
        .mesh
        .vertices()
        .min_by(|a, b| {
            let d = |v: VertexId| (sim.cloth.mesh.rest(v) - Vec2::new(0.5, 0.5)).norm();
            d(*a).total_cmp(&d(*b))
        })
        .expect("a vertex")
        .0 as usize;
    let (o, sim) = run(sim, Real::INFINITY, true);
    let z = sim.cloth.x[centre].z;
    let margin = loaded.scene.collision.margin;
    CaseResult {
        case: "high-speed impact on the sphere",
        strategy: strategy.into(),
        integrator: integrator.into(),
        criterion: format!(
            "dropped from {} m (about {:.1} m/s at impact): completes, largest penetration <= margin ({margin} m) over every step, the centre ends resting on top of the sphere (0.2 m < z < 0.35 m; no drag)",
            sizes.drop_height,
            (2.0 * 9.81 * sizes.drop_height).sqrt()
        ),
        measured: format!(
            "{} after {} steps; max penetration {:.2e} m; centre z = {z:.3} m",
            if o.completed { "completed" } else { o.message.as_str() },
            o.steps,
            o.max_penetration
        ),
        passed: o.completed && o.finite && o.max_penetration <= margin && z > 0.2 && z < 0.35,
    }
}

/// A long run of `hanging` with damping: total energy never rises beyond the tolerance after the
/// first 0.1 s.
pub fn case_long_run(
    strategy: &str,
    integrator: &str,
    beta: Real,
    sizes: &CaseSizes,
) -> CaseResult {
    let n = sizes.resolution;
    let mut loaded = sized("hanging", integrator, strategy, n, sizes.long_duration);
    set_step(&mut loaded, beta);
    let (o, _) = run(Simulation::new(&loaded).expect("builds"), 0.1, false);
    CaseResult {
        case: "long run",
        strategy: strategy.into(),
        integrator: integrator.into(),
        criterion: format!(
            "{} s of `hanging` with damping: completes; total energy never rises above its running minimum by more than the tolerance after 0.1 s",
            sizes.long_duration
        ),
        measured: energy_words(&o),
        passed: o.completed && o.finite && o.max_rise_after_settle <= ENERGY_TOL * o.energy_scale,
    }
}

/// Two opposite borders (u = 0 and u = 1, every vertex pinned and driven at 0.4 m/s towards the
/// other) close the cloth to 20 % of its width in 1 s: it must buckle with no non-finite value.
pub fn case_compression(
    strategy: &str,
    integrator: &str,
    beta: Real,
    sizes: &CaseSizes,
) -> CaseResult {
    let mut loaded = embedded("hanging", integrator, strategy);
    let s = &mut loaded.scene;
    let n = sizes.resolution;
    s.cloth.resolution = n;
    s.cloth.pinned.clear();
    s.cloth.pinned_velocity.clear();
    for k in 0..n {
        let v = k as Real / (n - 1) as Real;
        s.cloth.pinned.push([0.0, v]);
        s.cloth.pinned_velocity.push([0.4, 0.0, 0.0]);
        s.cloth.pinned.push([1.0, v]);
        s.cloth.pinned_velocity.push([-0.4, 0.0, 0.0]);
    }
    s.time.duration = 1.0;
    set_step(&mut loaded, beta);
    let (o, sim) = run(
        Simulation::new(&loaded).expect("builds"),
        Real::INFINITY,
        false,
    );
    let zs = sim
        .cloth
        .mesh
        .vertices()
        .map(|v| sim.cloth.x[v.0 as usize].z);
    let (lo, hi) = zs.fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), z| {
        (a.min(z), b.max(z))
    });
    CaseResult {
        case: "extreme compression",
        strategy: strategy.into(),
        integrator: integrator.into(),
        criterion: "borders driven together to 20 % of the width in 1 s: completes, every value finite, the cloth buckles out of plane (height range >= 0.1 m)".into(),
        measured: format!(
            "{} after {} steps; out-of-plane range {:.3} m",
            if o.completed { "completed" } else { o.message.as_str() },
            o.steps,
            hi - lo
        ),
        passed: o.completed && o.finite && hi - lo >= 0.1,
    }
}

/// Every hard case for one strategy with the [`CASE_INTEGRATORS`], plus the beyond-the-limit
/// case for every integrator.
pub fn hard_cases(strategy: &str, sizes: &CaseSizes) -> Vec<CaseResult> {
    let mut out = Vec::new();
    for (integrator, beta) in CASE_INTEGRATORS {
        out.push(case_stiff(strategy, integrator, beta, sizes));
    }
    for integrator in INTEGRATORS {
        out.push(case_beyond_limit(strategy, integrator, 10.0, sizes));
    }
    for (integrator, beta) in CASE_INTEGRATORS {
        out.push(case_tiny_elements(strategy, integrator, beta, sizes));
        out.push(case_impact(strategy, integrator, beta, sizes));
        out.push(case_long_run(strategy, integrator, beta, sizes));
        out.push(case_compression(strategy, integrator, beta, sizes));
    }
    out
}

/// The search of `docs/stability.md`.
pub const REPORT_SEARCH: Search = Search {
    resolution: 9,
    duration: 0.1,
    range: (2e-3, 64.0),
    iterations: 6,
};

/// Runs the whole suite and returns `docs/stability.md`; `progress` hears about each piece.
pub fn report(search: &Search, sizes: &CaseSizes, mut progress: impl FnMut(&str)) -> String {
    let started = Instant::now();
    let strategies = built_strategies();
    let mut md = String::from(
        "# Stability of the integrators\n\n\
         Generated by `adaptcloth stability` (do not edit by hand; rerun the command). The \
         criteria and the code are in `src/study/stability.rs`; `tests/stability.rs` runs the \
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
    for strategy in &strategies {
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
    md
}
