//! The step loop. One step reads in one function, [`Simulation::step`]: choose `dt`, integrate,
//! collide, adapt (every `adaptivity.interval` of simulated time); each stage is timed. Recording
//! and the run driver are in [`run`].

mod frames;
mod holds;
mod pressing;
mod run;
mod sample;
mod self_pass;
mod setup;
mod step_size;

pub use run::{
    labelled_bar, rerun_line, run, this_command, write_mesh_frame, RunOptions, RunStatus,
    RunSummary,
};
pub use sample::{AdaptJumps, SamplePoints, Sampler, Trajectory};
pub use setup::{build_cloth, SetupError};

use crate::adapt::{AdaptContext, AdaptParams, AdaptReport, Adaptivity};
use crate::cloth::Cloth;
use crate::collision::{ContactStats, FaceScratch, Obstacles, SelfContactTotals};
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{Barycentric, RestLocator};
use crate::physics::{make_integrator, Energies, Integrator, Pressed, StabilityLimit, StepStats};
use crate::scene::{CollisionMode, LoadedScene, OnUnconverged, Scene};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// What `--force` does, said (by the commands that have it) after a refused step estimate
/// ([`Simulation::check_step_estimate`]).
pub const FORCE_HINT: &str = "--force runs it anyway";
use crate::strategies::make_strategy;
use holds::Holding;
use pressing::Pressing;
use self_pass::SelfPass;
use std::time::{Duration, Instant};

/// Wall time spent in each stage of the step, summed over the run.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct StageTimes {
    /// Integration (force evaluations included), s.
    pub integrate_s: f64,
    /// Collision pass (obstacles and self-collision), s.
    pub collide_s: f64,
    /// The self-collision part of `collide_s`, s.
    pub self_collide_s: f64,
    /// Adaptivity (criteria and edits), s.
    pub adapt_s: f64,
    /// Rebuilding element arrays after a mesh change, s.
    pub rebuild_s: f64,
    /// Recording metrics and frames, s.
    pub record_s: f64,
}

/// What one step did.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepReport {
    /// The step taken (s).
    pub dt: Real,
    /// Collision statistics of the step.
    pub contacts: ContactStats,
    /// Vertices resting on an obstacle that the integrator held in its solve ([`Holding`]; 0
    /// for an integrator that holds none), plus the faces a penalty pressed at the step's end
    /// ([`Pressing`]).
    pub held_contacts: usize,
    /// What adaptation changed.
    pub adapt: AdaptReport,
    /// The cloth's total energy (kinetic, gravity, stretch, bending) after the step's
    /// adaptation minus before it (J): its edits, the elements rebuilt and the contact passes
    /// that follow them. 0 without an adaptation event. The adaptation's own report counts only
    /// the kinetic energy its state transfer changed.
    pub adapt_total_energy_change: Real,
    /// What the integrator reported (conjugate-gradient iterations).
    pub integrator: StepStats,
}

/// Why the simulation cannot go on.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// A non-finite value or a velocity above the scene's bound.
    #[error("diverged at step {step}, t = {t:.6} s: {reason}")]
    Diverged {
        /// Step number.
        step: u64,
        /// Simulated time (s).
        t: Real,
        /// What was seen.
        reason: String,
    },
    /// A linear solve ended above its tolerance with `integrator.on_unconverged = "fail"`.
    #[error("the implicit solve did not converge at step {step}, t = {t:.6} s: {reason}")]
    Unconverged {
        /// Step number.
        step: u64,
        /// Simulated time (s).
        t: Real,
        /// What the solver reported.
        reason: String,
    },
    /// Adaptation failed.
    #[error("adaptation failed at step {step}, t = {t:.6} s: {reason}")]
    Adapt {
        /// Step number.
        step: u64,
        /// Simulated time (s).
        t: Real,
        /// The error.
        reason: String,
    },
}

/// Steps whose linear solve did not go as asked, counted over a run (`implicit_euler`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveCounts {
    /// Steps whose solve ended above its tolerance ([`StepStats::unconverged`]).
    pub unconverged: u64,
    /// Step number and simulated time (s) at the end of the first of them.
    pub first_unconverged: Option<(u64, Real)>,
    /// Steps whose direct solve failed and fell back to conjugate gradients
    /// ([`StepStats::solver_fallback`]).
    pub fallbacks: u64,
    /// Steps whose CG ended above its tolerance and that Cholesky solved again
    /// ([`StepStats::direct_rescue`]).
    pub rescues: u64,
    /// Steps after which `auto` went to Cholesky because CG had been slow
    /// ([`StepStats::slow_switch`]).
    pub switches: u64,
}

/// A material point tracked through the run.
#[derive(Clone, Debug)]
pub struct Tracked {
    /// Its name.
    pub name: String,
    /// Rest point (m).
    pub rest: Vec2,
    location: Barycentric,
}

/// A running simulation: the scene, the cloth, obstacles, integrator and strategy.
pub struct Simulation {
    /// The scene (validated).
    pub scene: Scene,
    /// The cloth.
    pub cloth: Cloth,
    /// The obstacles.
    pub obstacles: Obstacles,
    integrator: Box<dyn Integrator>,
    strategy: Box<dyn Adaptivity>,
    adapt_params: AdaptParams,
    /// Simulated time (s).
    pub t: Real,
    /// Steps taken.
    pub steps: u64,
    /// Tracked material points.
    pub tracked: Vec<Tracked>,
    locator: RestLocator,
    contact_seen: bool,
    x_start: Vec<Vec3>,
    /// The live faces as vertex slots and the mesh version they were listed at (face contact).
    faces: (u64, Vec<[usize; 3]>, FaceScratch),
    /// The faces holding a vertex the self pass moved (scratch).
    faces_moved: Vec<[usize; 3]>,
    /// The stability limit the dynamic step formula does not see (damping, bending) and the mesh
    /// version it was last updated on (dynamic steps of explicit integrators only).
    stability: (u64, StabilityLimit),
    /// Simulated time (s) of the last adaptation pass, for `adaptivity.interval`.
    last_adapt: Option<Real>,
    /// Driven pinned vertices (slot, prescribed velocity in m/s), from `cloth.pinned_velocity`.
    drivers: Vec<(usize, Vec3)>,
    /// Wall time per stage.
    pub stage_times: StageTimes,
    /// Set when the run is interrupted: the adaptation pass stops at its next edit or round.
    interrupt: Option<Arc<AtomicBool>>,
    /// Linear solves that ended above their tolerance so far.
    pub solves: SolveCounts,
    /// Self-collision (`collision.self = true`).
    self_contact: Option<SelfPass>,
    /// What self-collision did so far.
    pub self_contact_totals: SelfContactTotals,
    /// The contacts handed to the integrator to hold in its solve, with their obstacles.
    holding: Holding,
    /// The faces pressed by an obstacle in the step, with a penalty (`collision.penalty` > 0).
    pressing: Pressing,
}

impl Simulation {
    /// Builds everything a scene describes.
    pub fn new(loaded: &LoadedScene) -> Result<Simulation, SetupError> {
        let scene = loaded.scene.clone();
        let cloth = build_cloth(loaded)?;
        let obstacles = Obstacles::build(&loaded.obstacles(), &(&scene.collision).into())
            .map_err(|e| setup::obstacle_error(loaded, e))?;
        let integrator = make_integrator(&scene.integrator.name, &(&scene.integrator).into())?;
        let drivers = setup::drivers(loaded, &cloth)?;
        let strategy = make_strategy(&scene.adaptivity.strategy)?;
        let locator = RestLocator::new(&cloth.mesh);
        let mut tracked = Vec::new();
        for (i, p) in scene.tracked.iter().enumerate() {
            let rest = Vec2::new(p.rest[0], p.rest[1]);
            let location = locator
                .locate(&cloth.mesh, rest)
                .ok_or_else(|| setup::off_pattern(loaded, &format!("tracked.{i}.rest"), p.rest))?;
            let name = if p.name.is_empty() {
                format!("p{i}")
            } else {
                p.name.clone()
            };
            tracked.push(Tracked {
                name,
                rest,
                location,
            });
        }
        Ok(Simulation {
            scene,
            cloth,
            obstacles,
            integrator,
            strategy,
            adapt_params: AdaptParams {
                refuse_crossings: loaded.scene.collision.self_collision,
                ..(&loaded.scene.adaptivity).into()
            },
            t: 0.0,
            steps: 0,
            tracked,
            locator,
            contact_seen: false,
            x_start: Vec::new(),
            faces: (u64::MAX, Vec::new(), FaceScratch::default()),
            faces_moved: Vec::new(),
            stability: (u64::MAX, StabilityLimit::default()),
            last_adapt: None,
            drivers,
            stage_times: StageTimes::default(),
            interrupt: None,
            solves: SolveCounts::default(),
            self_contact: loaded
                .scene
                .collision
                .self_collision
                .then(|| SelfPass::new(loaded.scene.collision.thickness)),
            self_contact_totals: SelfContactTotals::default(),
            holding: Holding::default(),
            pressing: Pressing::default(),
        })
    }

    /// Lets a long step end early once `flag` is set (the run driver passes its interrupt flag,
    /// so Ctrl-C or SIGTERM is answered within a step's inner loop, not after it: the
    /// integrator's iterations, the adaptation pass's rounds and edits).
    pub fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.integrator.set_interrupt(flag.clone());
        self.interrupt = Some(flag);
    }

    /// The strategy's name.
    pub fn strategy_name(&self) -> &'static str {
        self.strategy.name()
    }

    /// The integrator's name.
    pub fn integrator_name(&self) -> &'static str {
        self.integrator.name()
    }

    /// One step: integrate, collide, adapt. The step is cut so the run ends exactly at
    /// `duration`. Allocation-free in steady state (no mesh change).
    pub fn step(&mut self) -> Result<StepReport, StepError> {
        self.update_stability_limit();
        let dt = self
            .next_dt()
            .min(self.scene.time.duration - self.t)
            .max(Real::MIN_POSITIVE);

        let penalty = self.scene.collision.penalty;
        if self.integrator.holds().is_some() || penalty > 0.0 {
            let clock = Instant::now();
            let face_contact = self.list_faces();
            let pressing = self.press_faces();
            // Pressed faces replace the face holds.
            let faces = (face_contact && !pressing).then_some(&self.faces.1[..]);
            let integrator = &mut *self.integrator;
            self.holding
                .prepare(integrator, &self.obstacles, &self.cloth, faces);
            self.stage_times.collide_s += secs(clock.elapsed());
        }
        let clock = Instant::now();
        self.x_start.clear();
        self.x_start.extend_from_slice(&self.cloth.x);
        let cloth = &mut self.cloth;
        let dynamics = Pressed {
            model: &cloth.model,
            faces: &self.pressing.faces,
        };
        let integrator = self
            .integrator
            .step(&dynamics, self.t, dt, &mut cloth.x, &mut cloth.v);
        // Driven pinned vertices move with their prescribed velocity (their inverse mass is 0, so
        // the integrator left them in place); their velocity stays 0 for the force model.
        for &(i, vel) in &self.drivers {
            cloth.x[i] += vel * dt;
        }
        self.stage_times.integrate_s += secs(clock.elapsed());

        let clock = Instant::now();
        self.before_obstacles();
        // Moving obstacles go to where they are at the end of the step.
        self.obstacles.set_step(self.t, self.t + dt);
        let held_contacts =
            self.holding.finish(
                &mut *self.integrator,
                &self.obstacles,
                &mut self.cloth,
                self.scene.material.mu,
                dt,
            ) + self
                .pressing
                .finish(&self.obstacles, &mut self.cloth, self.scene.material.mu, dt);
        let cloth = &mut self.cloth;
        let contacts = if self.obstacles.is_empty() {
            ContactStats::default()
        } else {
            let mut stats = self.obstacles.respond(
                &self.x_start,
                &mut cloth.x,
                &mut cloth.v,
                cloth.model.inv_mass(),
                self.scene.material.mu,
                dt,
            );
            stats.contacts += self.face_pass(true);
            stats
        };
        self.contact_seen |= contacts.contacts + held_contacts > 0;
        self.self_collide(dt, true);
        self.stage_times.collide_s += secs(clock.elapsed());
        self.t += dt;
        self.steps += 1;
        self.check_finite()?;
        self.count_solve(&integrator)?;

        let due = self.adapt_due();
        let energy = |c: &Cloth| c.model.energies(&c.x, &c.v).total();
        let energy_before = if due { energy(&self.cloth) } else { 0.0 };
        let clock = Instant::now();
        let adapt = if due {
            self.last_adapt = Some(self.t);
            let ctx = AdaptContext {
                obstacles: &self.obstacles,
                time: self.t,
                params: &self.adapt_params,
                interrupt: self.interrupt.as_deref(),
            };
            let mut total = AdaptReport::default();
            for _ in 0..self.adapt_params.rounds.max(1) {
                if ctx.interrupted() {
                    break;
                }
                let round =
                    self.strategy
                        .adapt(&mut self.cloth, &ctx)
                        .map_err(|e| StepError::Adapt {
                            step: self.steps,
                            t: self.t,
                            reason: e.to_string(),
                        })?;
                total.merge(&round);
                let over_cap = self.cloth.mesh.vertex_count() > self.scene.adaptivity.max_vertices;
                if round.vertices_added == 0 || over_cap {
                    break;
                }
            }
            total
        } else {
            AdaptReport::default()
        };
        self.stage_times.adapt_s += secs(clock.elapsed());
        let max_vertices = self.scene.adaptivity.max_vertices;
        if adapt.vertices_added > 0 && self.cloth.mesh.vertex_count() > max_vertices {
            return Err(StepError::Adapt {
                step: self.steps,
                t: self.t,
                reason: format!(
                    "the mesh has {} vertices, above adaptivity.max_vertices = {max_vertices}",
                    self.cloth.mesh.vertex_count()
                ),
            });
        }
        if adapt.events > 0 {
            self.integrator.forget_history();
            self.pressing.clear();
            let clock = Instant::now();
            self.cloth.refresh();
            self.relocate_tracked();
            self.stage_times.rebuild_s += secs(clock.elapsed());
            // New faces (a coarsened region over an obstacle) start outside, as new vertices do;
            // with self-collision, that push is kept free of crossings (positions only).
            let clock = Instant::now();
            self.x_start.clear();
            self.x_start.extend_from_slice(&self.cloth.x);
            self.before_obstacles();
            self.face_pass(false);
            self.self_collide(dt, false);
            self.stage_times.collide_s += secs(clock.elapsed());
        }
        let adapt_total_energy_change = if adapt.events > 0 {
            energy(&self.cloth) - energy_before
        } else {
            0.0
        };
        // The faces pressed at the state the step ends at: the next step's start and the
        // energy audit of this state read them.
        let clock = Instant::now();
        self.press_faces();
        self.stage_times.collide_s += secs(clock.elapsed());
        Ok(StepReport {
            dt,
            contacts,
            held_contacts,
            adapt,
            adapt_total_energy_change,
            integrator,
        })
    }

    /// The cloth's energies (J) at its current state, the penalties' potential included
    /// (`collision.penalty` > 0: over the faces the obstacles press now).
    pub fn energies(&self) -> Energies {
        let cloth = &self.cloth;
        let mut energies = cloth.model.energies(&cloth.x, &cloth.v);
        let penalty = self.scene.collision.penalty;
        if penalty > 0.0 && self.scene.collision.mode == CollisionMode::Face {
            // The step's face list when it is current (no allocation in a per-step audit).
            let fresh: Vec<[usize; 3]>;
            let faces = if self.faces.0 == cloth.mesh.version() {
                &self.faces.1[..]
            } else {
                fresh = cloth.mesh.face_vertex_slots().collect();
                &fresh[..]
            };
            energies.contact = self
                .pressing
                .energy(&self.obstacles, cloth, faces, penalty, self.t);
        }
        energies
    }

    /// The face contact pass ([`crate::collision::Obstacles::respond_faces`]) when
    /// `collision.mode = "face"`, over the live faces (listed again after a mesh change), with
    /// the swept test from the step's start positions when `swept` (after the integration; not
    /// after an adaptation event, which moves nothing); returns the face contacts resolved (0 in
    /// vertex mode).
    fn face_pass(&mut self, swept: bool) -> usize {
        if !self.list_faces() {
            return 0;
        }
        let cloth = &mut self.cloth;
        self.obstacles
            .respond_faces(
                &self.faces.1,
                swept.then_some(&self.x_start[..]),
                &mut cloth.x,
                &mut cloth.v,
                cloth.model.inv_mass(),
                self.scene.material.mu,
                &mut self.faces.2,
            )
            .contacts
    }

    /// With face contact and obstacles, lists the live faces (vertex slots) in `self.faces` if
    /// the mesh changed since they were listed, and returns true; false otherwise.
    fn list_faces(&mut self) -> bool {
        if self.scene.collision.mode != CollisionMode::Face || self.obstacles.is_empty() {
            return false;
        }
        let mesh = &self.cloth.mesh;
        if self.faces.0 != mesh.version() {
            self.faces.1.clear();
            self.faces.1.extend(mesh.face_vertex_slots());
            self.faces.0 = mesh.version();
        }
        true
    }

    /// With face contact and `collision.penalty` > 0, lists the faces the obstacles press at the
    /// cloth's current state ([`Pressing::prepare`]: no search when the list is already this
    /// state's); returns whether the penalty is on.
    fn press_faces(&mut self) -> bool {
        let penalty = self.scene.collision.penalty;
        if penalty <= 0.0 || !self.list_faces() {
            return false;
        }
        self.pressing
            .prepare(&self.obstacles, &self.cloth, &self.faces.1, penalty, self.t);
        true
    }

    /// Keeps the cloth's positions before the obstacles' response, for the self pass.
    fn before_obstacles(&mut self) {
        if let Some(pass) = &mut self.self_contact {
            pass.before_obstacles(&self.cloth.x);
        }
    }

    /// The self-collision pass when `collision.self = true` ([`SelfPass::respond`]) on the
    /// motion from `x_start` to the cloth's positions: a step of `dt` (s) after the obstacles'
    /// response, velocities included when `velocities`, else a correction of positions only.
    fn self_collide(&mut self, dt: Real, velocities: bool) {
        let Some(pass) = &mut self.self_contact else {
            return;
        };
        let clock = Instant::now();
        let cloth = &mut self.cloth;
        let (obstacles, x_start, mu) = (&self.obstacles, &self.x_start, self.scene.material.mu);
        let face_mode = self.scene.collision.mode == CollisionMode::Face;
        let (_, faces, scratch) = &mut self.faces;
        let (near, all_inv_mass) = (&mut self.faces_moved, cloth.model.inv_mass());
        // The obstacles again over the vertices the self pass moved (positive `inv_mass`), and
        // the faces holding one (`face_pass` listed this mesh version's faces before the first
        // self pass when there are obstacles). A face's push goes to all its vertices: given to
        // one vertex of small weight, it would be divided by that weight.
        let again = |x: &mut [Vec3], v: &mut [Vec3], inv_mass: &[Real]| {
            if obstacles.is_empty() {
                return 0;
            }
            let mut moved = obstacles.respond(x_start, x, v, inv_mass, mu, dt).contacts;
            if face_mode {
                near.clear();
                near.extend(
                    faces
                        .iter()
                        .filter(|f| f.iter().any(|&i| inv_mass[i] > 0.0)),
                );
                let swept = Some(&x_start[..]);
                moved += obstacles
                    .respond_faces(near, swept, x, v, all_inv_mass, mu, scratch)
                    .contacts;
            }
            moved
        };
        let stats = pass.respond(
            cloth.mesh.version(),
            cloth.mesh.face_vertex_slots(),
            cloth.mesh.rest_slots(),
            x_start,
            &mut cloth.x,
            velocities.then_some(&mut cloth.v[..]),
            all_inv_mass,
            mu,
            dt,
            again,
        );
        self.self_contact_totals.add(&stats);
        self.stage_times.self_collide_s += secs(clock.elapsed());
    }

    /// Whether the adapt stage runs this step: always for the first pass, then once at least
    /// `adaptivity.interval` (s, with a relative slack of 1e-9) has passed since the last one.
    fn adapt_due(&self) -> bool {
        let interval = self.adapt_params.interval;
        self.last_adapt
            .is_none_or(|t0| self.t - t0 >= interval * (1.0 - 1e-9))
    }

    /// True when the run reached its duration.
    pub fn finished(&self) -> bool {
        self.t >= self.scene.time.duration * (1.0 - 1e-12)
    }

    /// World positions (m) of the tracked points.
    pub fn tracked_positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.tracked
            .iter()
            .map(|p| self.cloth.world_position(&p.location))
    }

    /// Largest depth of a cloth vertex inside an obstacle's raw surface (m).
    pub fn max_penetration(&self) -> Real {
        self.cloth
            .mesh
            .vertices()
            .map(|v| self.obstacles.penetration(self.cloth.x[v.0 as usize]))
            .fold(0.0, Real::max)
    }

    /// Largest depth of an obstacle through the cloth surface, faces included (m):
    /// [`crate::collision::Obstacles::surface_penetration`] over the live faces.
    pub fn max_surface_penetration(&self) -> Real {
        self.obstacles
            .surface_penetration(&self.cloth.x, self.cloth.mesh.face_vertex_slots())
    }

    /// The cloth's crossings with itself: edge-face pairs sharing no vertex where the edge passes
    /// through the face ([`crate::collision::self_intersections`]).
    pub fn self_intersections(&self) -> usize {
        let mesh = &self.cloth.mesh;
        let faces: Vec<[usize; 3]> = mesh.face_vertex_slots().collect();
        let edges: Vec<[usize; 2]> = mesh
            .edges()
            .map(|(e, _)| [e.0 .0 as usize, e.1 .0 as usize])
            .collect();
        crate::collision::self_intersections(&self.cloth.x, &faces, &edges)
    }

    /// Locates the tracked material points again after a mesh change.
    /// Call after editing `cloth.mesh` from outside the step (experiments, tests): rebuilds the
    /// spring and bending arrays and relocates the tracked points, as the step does after an
    /// adaptation pass.
    pub fn after_mesh_edit(&mut self) {
        self.cloth.refresh();
        self.relocate_tracked();
    }

    fn relocate_tracked(&mut self) {
        self.locator = RestLocator::new(&self.cloth.mesh);
        for p in &mut self.tracked {
            if let Some(loc) = self.locator.locate(&self.cloth.mesh, p.rest) {
                p.location = loc;
            }
        }
    }

    /// Counts the step just taken in [`Simulation::solves`] when its direct solve fell back to
    /// CG or its solve ended above tolerance, and then fails under
    /// `integrator.on_unconverged = "fail"`.
    fn count_solve(&mut self, stats: &StepStats) -> Result<(), StepError> {
        self.solves.fallbacks += u64::from(stats.solver_fallback);
        self.solves.rescues += u64::from(stats.direct_rescue);
        self.solves.switches += u64::from(stats.slow_switch);
        if !stats.unconverged {
            return Ok(());
        }
        self.solves.unconverged += 1;
        self.solves
            .first_unconverged
            .get_or_insert((self.steps, self.t));
        let i = &self.scene.integrator;
        if i.on_unconverged == OnUnconverged::Fail {
            return Err(StepError::Unconverged {
                step: self.steps,
                t: self.t,
                reason: format!(
                    "{}; integrator.on_unconverged = \"fail\" ends the run",
                    self.unconverged_reason(stats)
                ),
            });
        }
        Ok(())
    }

    /// What an unconverged solve did, for messages: its iterations against the scene's limits.
    fn unconverged_reason(&self, stats: &StepStats) -> String {
        let i = &self.scene.integrator;
        format!(
            "conjugate gradients stopped after {} iterations above the relative tolerance \
             integrator.cg_tolerance = {:e} (integrator.cg_max_iterations = {})",
            stats.cg_iterations, i.cg_tolerance, i.cg_max_iterations
        )
    }

    /// Fails when a live vertex has a non-finite position or velocity, or moves faster than the
    /// scene's `max_speed`.
    fn check_finite(&self) -> Result<(), StepError> {
        let max_speed2 = self.scene.time.max_speed.powi(2);
        for v in self.cloth.mesh.vertices() {
            let i = v.0 as usize;
            let (x, vel) = (self.cloth.x[i], self.cloth.v[i]);
            let reason = if !(x.iter().all(|c| c.is_finite()) && vel.iter().all(|c| c.is_finite()))
            {
                format!("vertex {i} has a non-finite position or velocity")
            } else if vel.norm_squared() > max_speed2 {
                format!(
                    "vertex {i} moves at {:.3e} m/s, above time.max_speed = {} m/s",
                    vel.norm(),
                    self.scene.time.max_speed
                )
            } else {
                continue;
            };
            return Err(StepError::Diverged {
                step: self.steps,
                t: self.t,
                reason,
            });
        }
        Ok(())
    }
}

fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}
