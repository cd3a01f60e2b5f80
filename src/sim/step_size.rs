//! The size of a simulation's steps: the fixed or dynamic step (MODEL.md §4) capped by the
//! integrator's stability limit, the run's step count estimated before it starts, and the note
//! for an integrator stable at any step left on the dynamic one.

use super::{SetupError, Simulation};
use crate::math::Real;
use crate::physics::{StabilityLimit, ITERATIONS_AFTER_EDIT, STEPS_PER_ITERATION};
use crate::scene::{TimeMode, MAX_STEPS};

impl Simulation {
    /// The step the next call of [`Simulation::step`] will take (s), MODEL.md §4: fixed, or
    /// `beta pi sqrt(m_min / k_max)` clamped to `[dt_min, dt_max]`, with `dt_initial` until the
    /// first contact. For explicit integrators both are also capped by the stability limit of
    /// the damping and bending ([`StabilityLimit`], see docs/model-notes.md), which the formula
    /// does not see: it binds on light (refined) vertices, on crumpled elements and on
    /// `dt_initial = 1e-4` at 33 x 33 and finer.
    pub fn next_dt(&self) -> Real {
        self.dt_for(self.contact_seen, &self.stability.1)
    }

    /// The step (s) [`Simulation::next_dt`] gives on the current mesh, before or after the first
    /// contact, capped by the estimates of `stability` for this integrator.
    fn dt_for(&self, contact_seen: bool, stability: &StabilityLimit) -> Real {
        let time = &self.scene.time;
        if time.mode == TimeMode::Fixed {
            return time.dt;
        }
        let limit = self
            .integrator
            .stability_limit()
            .map_or(Real::INFINITY, |axis| stability.step_limit(axis));
        if time.dt_initial > 0.0 && !contact_seen {
            return time.dt_initial.min(limit);
        }
        let mut dt = self.cloth.model.stable_step(time.beta).min(limit);
        if time.dt_max > 0.0 {
            dt = dt.min(time.dt_max);
        }
        if time.dt_min > 0.0 {
            dt = dt.max(time.dt_min);
        }
        dt
    }

    /// The run's step count estimated on the cloth as built: `(duration / dt, dt, cap)` with `dt`
    /// (s) the smaller of the first step and the dynamic step after the first contact, and `cap`
    /// (s) the stability limit of the damping and bending for this integrator (infinite when it
    /// does not apply).
    pub fn step_estimate(&self) -> (Real, Real, Real) {
        let mut stability = StabilityLimit::default();
        stability.update(&self.cloth.model, &self.cloth.x, ITERATIONS_AFTER_EDIT);
        let dt = self
            .dt_for(false, &stability)
            .min(self.dt_for(true, &stability));
        let cap = self
            .integrator
            .stability_limit()
            .map_or(Real::INFINITY, |axis| stability.step_limit(axis));
        (self.scene.time.duration / dt, dt, cap)
    }

    /// For an integrator stable at any step (`implicit_euler`, `bdf2`) on the scene's dynamic
    /// step, which the explicit limit sets (`time.mode = "dynamic"`): a note saying so, with the
    /// smallest step expected (s) and how to take large steps; `None` otherwise.
    pub fn dynamic_step_note(&self) -> Option<String> {
        if self.scene.time.mode != TimeMode::Dynamic || self.integrator.stability_limit().is_some()
        {
            return None;
        }
        let (_, dt, _) = self.step_estimate();
        Some(format!(
            "note: {} takes the scene's dynamic step (time.mode = \"dynamic\", set by the \
             explicit integrators' stability: down to {dt:.2e} s here); for its large steps fix \
             the step: --set time.mode=fixed --set time.dt=0.002 (in a study: dt = 0.002)",
            self.integrator.name()
        ))
    }

    /// Refines the stability limit for this step (dynamic steps of explicit integrators only):
    /// [`ITERATIONS_AFTER_EDIT`] power iterations after a mesh change (from the warm start mixed
    /// with a fresh one), one every [`STEPS_PER_ITERATION`] steps otherwise, warm-started.
    pub(super) fn update_stability_limit(&mut self) {
        if self.scene.time.mode == TimeMode::Fixed || self.integrator.stability_limit().is_none() {
            return;
        }
        let version = self.cloth.mesh.version();
        let (model, x) = (&self.cloth.model, &self.cloth.x);
        if self.stability.0 != version {
            self.stability.0 = version;
            self.stability.1.update_after_edit(model, x);
        } else if self.steps % STEPS_PER_ITERATION == 0 {
            self.stability.1.update(model, x, 1);
        }
    }

    /// Fails when [`Simulation::step_estimate`] is above [`MAX_STEPS`] (or not a number): a run
    /// that could never finish (`material.E = 1e308`, `time.dt_initial = 1e-300`). The error
    /// gives the estimate and the quantities that set the step.
    pub fn check_step_estimate(&self) -> Result<(), SetupError> {
        let (steps, dt, cap) = self.step_estimate();
        if steps <= MAX_STEPS {
            return Ok(());
        }
        let t = &self.scene.time;
        let model = &self.cloth.model;
        let why = if t.mode == TimeMode::Fixed {
            "The step is time.dt (time.mode = \"fixed\")".to_string()
        } else {
            format!(
                "The step is time.beta = {} x pi x sqrt(smallest vertex mass {:.3e} kg / largest \
                 spring stiffness {:.3e} N/m; set by material.E, material.rho, material.T and the \
                 cloth's resolution), capped by the damping and bending stability limit \
                 ({cap:.3e} s for this integrator; material.alpha, material.k_b) and clamped by \
                 time.dt_min = {:e} s and time.dt_max = {:e} s, with time.dt_initial = {:e} s \
                 until the first contact",
                crate::console::num(t.beta),
                model.min_mass(),
                model.max_stiffness(),
                t.dt_min,
                t.dt_max,
                t.dt_initial
            )
        };
        Err(SetupError::TooManySteps(format!(
            "this run would take about {steps:.3e} steps of {dt:.3e} s over time.duration = {} s; \
             at most {MAX_STEPS:e} are accepted. {why}",
            crate::console::num(t.duration),
        )))
    }
}
