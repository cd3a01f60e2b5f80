//! The scene's data types: one struct per TOML section, every default in one place.
//!
//! Field names follow MODEL.md §9 and the seed's tables (`rho`, `T`, `kappa`, `E`, `alpha`, `k_b`,
//! `k_bd`, `mu`, `beta`, ...). Every struct denies unknown keys so a typo is an error, not a silent
//! default.

use crate::math::Real;
use serde::{Deserialize, Serialize};

/// A whole scene: the cloth, its material, the forces, time stepping, integrator, collision,
/// obstacles, adaptivity parameters and tracked material points.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name used in outputs (defaults to the file stem); made a safe file name on load
    /// (`io::file_safe`: no path separators, no leading dot), since output folders are named
    /// after it.
    #[serde(default)]
    pub name: String,
    /// One-line description.
    #[serde(default)]
    pub description: String,
    /// `[cloth]`: shape, size, resolution, placement, pinned vertices.
    #[serde(default)]
    pub cloth: ClothSpec,
    /// `[material]`: density, thickness, stiffness, damping, friction.
    #[serde(default)]
    pub material: MaterialSpec,
    /// `[forces]`: each force on or off, gravity vector.
    #[serde(default)]
    pub forces: ForcesSpec,
    /// `[time]`: duration and time-step control.
    #[serde(default)]
    pub time: TimeSpec,
    /// `[integrator]`: the time integrator and its options.
    #[serde(default)]
    pub integrator: IntegratorSpec,
    /// `[collision]`: margin and default restitution.
    #[serde(default)]
    pub collision: CollisionSpec,
    /// `[[obstacles]]`: obstacles, still or moving rigidly.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
    /// `[adaptivity]`: strategy choice and the criteria parameters.
    #[serde(default)]
    pub adaptivity: AdaptivitySpec,
    /// `[[tracked]]`: material points whose world position is recorded.
    #[serde(default)]
    pub tracked: Vec<TrackedSpec>,
}

/// How the cloth pattern is made.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ClothShape {
    /// Union-jack grid of `resolution` x `resolution_v` vertices over `size`.
    #[default]
    Grid,
    /// Disk of diameter `size[0]` with `resolution` rings.
    Disk,
    /// Triangle mesh from the OBJ file `mesh` (`vt` = rest coordinates in m, `v` = world positions).
    Obj,
}

/// `[cloth]`: the pattern and where it starts in the world.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ClothSpec {
    /// Pattern shape. Default `grid`.
    pub shape: ClothShape,
    /// Pattern size `[width, height]` (m). Default `[1, 1]`.
    pub size: [Real; 2],
    /// Vertices per side along u (grid, at least 2) or rings (disk). Default 5.
    pub resolution: usize,
    /// Vertices along v for an N x M grid; 0 means equal to `resolution`. Default 0.
    pub resolution_v: usize,
    /// OBJ file for `shape = "obj"`, relative to the scene file.
    pub mesh: String,
    /// World position of the pattern's centre (m). Default `[0, 0, 0.3]`.
    pub center: [Real; 3],
    /// Rotation of the pattern about x, then y, then z (degrees). Default none: the pattern lies
    /// in the horizontal plane, u along x, v along y.
    pub rotation_deg: [Real; 3],
    /// Pinned vertices, given as rest points `[u, v]` (m): the vertex nearest to each is pinned.
    pub pinned: Vec<[Real; 2]>,
    /// Initial velocity of every vertex (m/s). Default zero.
    pub velocity: [Real; 3],
    /// Prescribed velocity (m/s) of each pinned vertex, in the order of `pinned`: a pinned vertex
    /// with a non-zero entry is driven (it moves by `velocity dt` every step, whatever the forces).
    /// Empty (the default) or shorter than `pinned`: the others stay still.
    pub pinned_velocity: Vec<[Real; 3]>,
}

impl Default for ClothSpec {
    fn default() -> Self {
        ClothSpec {
            shape: ClothShape::Grid,
            size: [1.0, 1.0],
            resolution: 5,
            resolution_v: 0,
            mesh: String::new(),
            center: [0.0, 0.0, 0.3],
            rotation_deg: [0.0; 3],
            pinned: Vec::new(),
            velocity: [0.0; 3],
            pinned_velocity: Vec::new(),
        }
    }
}

/// Spring stiffness model (MODEL.md §2).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum StiffnessModel {
    /// `k = E T S / L²`: mesh-independent sheet stiffness.
    #[default]
    AreaWeighted,
    /// `k = E A0 / L` (seed equation 4.3).
    Seed,
}

/// Which spring deformations resist (MODEL.md §3).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum SpringMode {
    /// Springs resist stretching only; compression is free so the cloth buckles.
    #[default]
    Tension,
    /// Springs resist stretching and compression.
    Both,
}

/// `[material]`: cloth material (MODEL.md §2), SI units.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct MaterialSpec {
    /// Density (kg/m³). Default 6000.
    pub rho: Real,
    /// Thickness `T` (m). Default 1e-4.
    #[serde(rename = "T")]
    pub thickness: Real,
    /// Permeability `kappa`: drag coefficient per rest area (N s/m³). Default 3.
    pub kappa: Real,
    /// Young's modulus `E` (N/m²). Default 1e7.
    #[serde(rename = "E")]
    pub young: Real,
    /// Spring damping ratio `alpha`: `kd = alpha k` (s). Default 0.01.
    pub alpha: Real,
    /// Bending stiffness `k_b` (N m). Default 1e-3.
    pub k_b: Real,
    /// Bending damping `k_bd` (N s). Default 1e-4.
    pub k_bd: Real,
    /// Cloth friction coefficient `mu` (averaged with the obstacle's). Default 0.05.
    pub mu: Real,
    /// Stiffness model. Default `area_weighted`.
    pub stiffness: StiffnessModel,
    /// Spring cross-section `A0` (m²) for `stiffness = "seed"`. Default 1e-4.
    #[serde(rename = "A0")]
    pub cross_section: Real,
    /// Whether springs resist compression. Default `tension`.
    pub springs: SpringMode,
}

impl Default for MaterialSpec {
    fn default() -> Self {
        MaterialSpec {
            rho: 6000.0,
            thickness: 1e-4,
            kappa: 3.0,
            young: 1e7,
            alpha: 0.01,
            k_b: 1e-3,
            k_bd: 1e-4,
            mu: 0.05,
            stiffness: StiffnessModel::AreaWeighted,
            cross_section: 1e-4,
            springs: SpringMode::Tension,
        }
    }
}

/// `[forces]`: each force on or off (a force switched off is never evaluated).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ForcesSpec {
    /// Elastic spring force (4.8). Default on.
    pub springs: bool,
    /// Spring damping (4.9). Default on.
    pub spring_damping: bool,
    /// Bridson bending (4.10-4.11). Default on.
    pub bending: bool,
    /// Bending damping (4.12-4.13). Default on.
    pub bending_damping: bool,
    /// Gravity (4.14). Default on.
    pub gravity: bool,
    /// Air drag (4.15). Default on.
    pub drag: bool,
    /// Gravity acceleration (m/s²). Default `[0, 0, -9.81]`.
    pub g: [Real; 3],
}

impl Default for ForcesSpec {
    fn default() -> Self {
        ForcesSpec {
            springs: true,
            spring_damping: true,
            bending: true,
            bending_damping: true,
            gravity: true,
            drag: true,
            g: [0.0, 0.0, -9.81],
        }
    }
}

/// Time-step mode (MODEL.md §4).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum TimeMode {
    /// `dt = beta pi sqrt(m_min / k_max)` before every step.
    #[default]
    Dynamic,
    /// Constant `dt`.
    Fixed,
}

/// `[time]`: duration and step control.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct TimeSpec {
    /// Simulated duration (s). Default 0.6.
    pub duration: Real,
    /// Step mode. Default `dynamic`.
    pub mode: TimeMode,
    /// Step for `mode = "fixed"` (s). Default 1e-4.
    pub dt: Real,
    /// Safety factor of the dynamic step. Default 1e-3.
    pub beta: Real,
    /// Step used until the first contact (s); 0 starts dynamic at once. Default 0.
    pub dt_initial: Real,
    /// Lower clamp of the dynamic step (s); 0 means none. Default 0.
    pub dt_min: Real,
    /// Upper clamp of the dynamic step (s); 0 means none. Default 0.
    pub dt_max: Real,
    /// Output frames per simulated second. Default 60.
    pub frame_rate: Real,
    /// Metrics rows per simulated second (every adaptation event is recorded too). Default 1000.
    pub metrics_rate: Real,
    /// Divergence bound: a vertex faster than this (m/s) ends the run as diverged. Default 100.
    pub max_speed: Real,
}

impl Default for TimeSpec {
    fn default() -> Self {
        TimeSpec {
            duration: 0.6,
            mode: TimeMode::Dynamic,
            dt: 1e-4,
            beta: 1e-3,
            dt_initial: 0.0,
            dt_min: 0.0,
            dt_max: 0.0,
            frame_rate: 60.0,
            metrics_rate: 1000.0,
            max_speed: 100.0,
        }
    }
}

/// How `implicit_euler` solves its linear system.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum LinearSolver {
    /// Block-Jacobi preconditioned conjugate gradients, matrix-free.
    Cg,
    /// Sparse Cholesky of the assembled matrix (conjugate gradients for a step whose
    /// factorisation fails, counted in `solver_fallbacks` of summary.json).
    Cholesky,
    /// Conjugate gradients; a step whose CG ends above `cg_tolerance` (at `cg_max_iterations`,
    /// or broken down) is solved again by Cholesky (counted in `cholesky_rescues` of
    /// summary.json), and the next 8 steps go straight to Cholesky, a window that doubles with
    /// each rescue (up to 1024 steps). 24 consecutive CG solves of one mesh above 3.5
    /// `sqrt(slots)` iterations open such a window too (`cholesky_switches`).
    Auto,
    /// Conjugate gradients preconditioned by a sparse Cholesky factorisation, in single
    /// precision, of the matrix with the bending couplings no spring shares moved to the
    /// diagonal (the springs' pattern, a sparser factor), iterated to `cg_tolerance`; a step
    /// whose CG ends above it is solved again by Cholesky (`cholesky_rescues`), and one whose
    /// preconditioner cannot be factorised by Cholesky at once (`solver_fallbacks`). The
    /// default.
    #[default]
    PcgSprings,
}

/// What a run does when a step's linear solve ends above its tolerance (`implicit_euler`).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum OnUnconverged {
    /// Go on with the last iterate; the first such step is warned about on stderr and every one
    /// is counted (`cg_unconverged` in metrics.csv and summary.json).
    #[default]
    Warn,
    /// End the run with status `failed` at the first such step, keeping what was written.
    Fail,
}

/// `[integrator]`: the integrator's name and options.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct IntegratorSpec {
    /// Integrator name (see `adaptcloth run --help`). Default `rk4`.
    pub name: String,
    /// `implicit_euler`: relative residual at which conjugate gradients stop,
    /// `|r| <= cg_tolerance |b|` (dimensionless). Default 1e-6.
    pub cg_tolerance: Real,
    /// `implicit_euler`: iteration cap of conjugate gradients per step. Default 200.
    pub cg_max_iterations: usize,
    /// `implicit_euler`: the linear solver, `pcg_springs`, `auto`, `cg` or `cholesky`. Default
    /// `pcg_springs`.
    pub solver: LinearSolver,
    /// `implicit_euler`: what a step whose solve ends above `cg_tolerance` does to the run:
    /// `warn` or `fail`. Default `warn`.
    pub on_unconverged: OnUnconverged,
    /// `verlet_relaxation`: Gauss-Seidel passes over the edges after each Verlet step (seed 002's
    /// bar relaxation). Default 4.
    pub relaxation_passes: usize,
}

impl Default for IntegratorSpec {
    fn default() -> Self {
        IntegratorSpec {
            name: "rk4".into(),
            cg_tolerance: 1e-6,
            cg_max_iterations: 200,
            solver: LinearSolver::PcgSprings,
            on_unconverged: OnUnconverged::Warn,
            relaxation_passes: 4,
        }
    }
}

/// `[collision]`: collision response parameters shared by all obstacles.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct CollisionSpec {
    /// Collision margin (m): the cloth is kept this far off every obstacle surface. Default 2e-3.
    pub margin: Real,
    /// Restitution `gamma` in (0, 1) (4.16), unless an obstacle sets its own. Default 0.5.
    #[serde(alias = "gamma")]
    pub restitution: Real,
    /// What of the cloth meets the obstacles. Default `face`.
    pub mode: CollisionMode,
    /// `self`: whether the cloth collides with itself (proximity impulses, the swept test and
    /// impact zones, docs/model-notes.md). Default false: a scene pays for it only when on.
    #[serde(rename = "self")]
    pub self_collision: bool,
    /// Cloth thickness for self-collision (m): pairs of the cloth closer than this are pushed
    /// apart. Default 2e-3.
    pub thickness: Real,
    /// Stiffness (N/m) of the penalty on each face an obstacle presses between its vertices
    /// (`mode = "face"`; docs/model-notes.md, "Face contact as a penalty"), felt by every
    /// integrator. Default [`DEFAULT_PENALTY`]; 0 holds those faces' vertices in implicit
    /// solves instead (the model before 2026-11-30, which pumps energy into a fine cloth over
    /// a sharp edge).
    pub penalty: Real,
}

/// The default face-contact penalty (N/m): measured on the draped plate, 1e2 N/m pumps and
/// 1e4 to 1e5 N/m are no better and take 2 to 5 times the CG iterations.
pub const DEFAULT_PENALTY: Real = 1e3;

/// The default cloth thickness (m).
pub const DEFAULT_THICKNESS: Real = 2e-3;

impl Default for CollisionSpec {
    fn default() -> Self {
        CollisionSpec {
            margin: 2e-3,
            restitution: 0.5,
            mode: CollisionMode::Face,
            self_collision: false,
            thickness: DEFAULT_THICKNESS,
            penalty: DEFAULT_PENALTY,
        }
    }
}

/// What of the cloth meets the obstacles (`[collision] mode`).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum CollisionMode {
    /// Vertices only, as in the source: an obstacle may poke through a face between vertices.
    Vertex,
    /// Vertices, then every face (the default): an obstacle within the margin of a face pushes
    /// it out by impulses spread over the face's vertices.
    #[default]
    Face,
}

/// The geometry of a static obstacle.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum ObstacleShape {
    /// Ground half-space `z <= height`.
    Ground {
        /// Height of the ground plane (m).
        #[serde(default)]
        height: Real,
    },
    /// Sphere.
    Sphere {
        /// Centre (m).
        center: [Real; 3],
        /// Radius (m).
        radius: Real,
    },
    /// Cylinder with a vertical axis (the round table).
    Cylinder {
        /// Centre of the cylinder (m): halfway between its bottom and top faces.
        center: [Real; 3],
        /// Radius (m).
        radius: Real,
        /// Height (m).
        height: Real,
    },
    /// Axis-aligned box.
    Box {
        /// Centre (m).
        center: [Real; 3],
        /// Half extents along x, y, z (m).
        half_extents: [Real; 3],
    },
    /// Closed triangle mesh read from an OBJ file (relative to the scene file).
    Mesh {
        /// The OBJ file.
        file: String,
        /// Uniform scale applied first.
        #[serde(default = "one")]
        scale: Real,
        /// Translation applied after scaling (m).
        #[serde(default)]
        translation: [Real; 3],
    },
}

fn one() -> Real {
    1.0
}

/// `[[obstacles]]`: one obstacle, its geometry, its contact parameters and how it moves.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ObstacleSpec {
    /// The geometry (`kind = "ground" | "sphere" | "cylinder" | "box" | "mesh"` and its fields).
    #[serde(flatten)]
    pub shape: ObstacleShape,
    /// Friction coefficient of the obstacle surface (averaged with the cloth's `mu`). Default 0.
    #[serde(default)]
    pub friction: Real,
    /// Restitution in (0, 1) for this obstacle; 0 (the default) uses `[collision] restitution`.
    #[serde(default)]
    pub restitution: Real,
    /// `[obstacles.motion]`: how the obstacle moves. Default none: it stays where it is. Not
    /// written when absent, so the scenes without it serialize (and key their cached
    /// references) as before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<MotionSpec>,
}

/// `[obstacles.motion]`: a rigid motion of the obstacle from where the scene puts it, at time
/// `t` (s) from the start of the run. The ground cannot move.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionSpec {
    /// Constant velocity: moved by `velocity t`.
    Linear {
        /// Velocity (m/s).
        velocity: [Real; 3],
    },
    /// Constant rotation about a fixed axis: turned by `angular_velocity t` (right-handed about
    /// `axis`).
    Spin {
        /// A point of the axis (m). Default the origin.
        #[serde(default)]
        axis_point: [Real; 3],
        /// Direction of the axis, not zero. Default `[0, 0, 1]` (vertical).
        #[serde(default = "vertical")]
        axis: [Real; 3],
        /// Angular velocity (rad/s).
        angular_velocity: Real,
    },
    /// Keyframed poses: translations linearly interpolated, rotations spherically (at a constant
    /// rate between keyframes); held at the first and last outside the keyframe times.
    Keyframes {
        /// Keyframe times (s), strictly increasing.
        times: Vec<Real>,
        /// Offset from where the scene puts the obstacle at each time (m), one per time.
        positions: Vec<[Real; 3]>,
        /// Rotation at each time as a rotation vector (axis times angle, rad, right-handed), one
        /// per time, about `pivot`; none (the default) for translations only. Not written when
        /// empty.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        rotations: Vec<[Real; 3]>,
        /// The point the rotations turn about, where the scene puts it (m); it moves with the
        /// offsets. Default the origin; not written when it is.
        #[serde(default, skip_serializing_if = "is_origin")]
        pivot: [Real; 3],
    },
}

fn is_origin(p: &[Real; 3]) -> bool {
    *p == [0.0; 3]
}

fn vertical() -> [Real; 3] {
    [0.0, 0.0, 1.0]
}

/// Which criteria select edges (`adaptivity.criteria`).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum CriteriaSpec {
    /// The source's criteria (MODEL.md §7).
    #[default]
    Source,
    /// The sizing field (MODEL.md §10.1).
    Sizing,
}

/// `[adaptivity]`: the strategy and the criteria of MODEL.md §7 (names of the seed's tables).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct AdaptivitySpec {
    /// Strategy: `static`, `remesh`, `simnett` or `bisect48`. Default `static`.
    pub strategy: String,
    /// Restore the linear momentum of a re-meshed region by a uniform velocity correction.
    /// Default on.
    pub restore_momentum: bool,
    /// Restore the kinetic energy an edit loses by averaging velocities with the momentum-neutral
    /// correction of MODEL.md §8.4 rule 6 (velocities of the touched vertices relative to their
    /// mean scaled; `adapt::restore_kinetic_energy`), in every strategy that edits the mesh.
    /// Default off.
    pub restore_energy: bool,
    /// Which criteria select edges: `source` (MODEL.md §7, the default) or `sizing` (a target
    /// rest length per edge, MODEL.md §10.1).
    pub criteria: CriteriaSpec,
    /// Sizing field: tolerated normal change across an edge (rad), for the curvature and obstacle
    /// terms. Default 0.25.
    pub size_angle: Real,
    /// Sizing field: tolerated velocity difference across an edge (m/s). Default 0.5.
    pub size_velocity: Real,
    /// Sizing field: tolerated compressive strain before buckling is anticipated. Default 0.02.
    pub size_compression: Real,
    /// Sizing field: distance (m) within which an obstacle's curvature sizes the cloth (grown by
    /// the distance the fastest vertex travels in one `interval`). Default 0.05.
    pub size_proximity: Real,
    /// Compression criterion `c`: refine when `L / L_rest < c`. Default 0.70.
    pub compression_c: Real,
    /// Curvature: refine when the cosine between end normals is below this. Default 0.97.
    pub cos_refine: Real,
    /// Curvature: simplify when the cosine is above this. Default 0.999995.
    pub cos_simplify: Real,
    /// No refinement of an edge shorter than this at rest (m). Default 0.08.
    pub l_min: Real,
    /// No simplification above this rest length (m). Default 0.25.
    pub l_max: Real,
    /// The resolution knob of every adaptive strategy: the shortest rest edge a strategy may
    /// create (m). 0 (the default) leaves `l_min` and `max_depth` in charge; set, it overrides
    /// both (whatever the scene gives them): an edge is refined only when its halves are at
    /// least `h_min`, and `simnett` and `bisect48` may go as many levels deep as halving the
    /// longest initial edge down to `h_min` takes.
    pub h_min: Real,
    /// Smoothing (4.19): refine a neighbour j of a selected edge i when `L_i / L_j < c2`.
    /// Default 0.75.
    pub c2: Real,
    /// Hysteresis: no simplification until this long after refinement (s). Default 0.1.
    pub t_simplify: Real,
    /// Density factor scale when refining. Default 1.01.
    pub density_refine: Real,
    /// Density factor scale when simplifying. Default 0.35.
    pub density_simplify: Real,
    /// Collision criterion: an edge meeting an obstacle is not refined when the mean normal of its
    /// faces and the obstacle normal have an absolute cosine at least this (flat contact).
    /// Default 0.97 (about 14 degrees).
    pub flat_contact_cos: Real,
    /// Curvature criterion: exponent of `theta_refine = theta_max (A_max / A_e)^exponent`.
    /// Default 0.5.
    pub curvature_exponent: Real,
    /// Maximum subdivision depth (1-to-4). Default 3.
    pub max_depth: u32,
    /// Cosine-limit factor per depth level (1-to-4). Default 0.95.
    pub depth_factor: Real,
    /// 1-to-4 (`simnett`): when an edge selected for refinement is blocked by a temporary
    /// (state -1) neighbour, first split the remaining edges of the blocking parent triangle so
    /// the edge can split (the project's improvement). Default false: the source's faithful rule
    /// (the edge waits until its parent triangle reaches state 7).
    pub force_completion: bool,
    /// Simulated time between adaptation passes (s), for every strategy (the step loop skips the
    /// adapt stage in between); 0 adapts after every step, as the source did. Default 0.01:
    /// measured (`studies/interval.toml`, docs/model-notes.md) to change the error little while
    /// cutting adaptation's share of a run several-fold.
    pub interval: Real,
    /// Rounds per adaptation pass (1 to 16): the strategy is called again while its last round
    /// added vertices, so one pass can refine several levels. Default 1 (the source's one round).
    pub rounds: u32,
    /// Local remeshing: minimum angle the hole mesher keeps away from the hole border (degrees).
    /// Default 25.
    pub remesh_min_angle: Real,
    /// Most live vertices adaptation may grow the mesh to, for every strategy: a run whose
    /// adaptation pass adds vertices past it (`l_min = 1e-9` with `max_depth = 40`) stops with
    /// status `failed`. At least 1, at most `mesh::MAX_VERTICES`. Default 200000.
    pub max_vertices: usize,
}

impl Default for AdaptivitySpec {
    fn default() -> Self {
        AdaptivitySpec {
            strategy: "static".into(),
            restore_momentum: true,
            restore_energy: false,
            criteria: CriteriaSpec::Source,
            size_angle: 0.25,
            size_velocity: 0.5,
            size_compression: 0.02,
            size_proximity: 0.05,
            compression_c: 0.70,
            cos_refine: 0.97,
            cos_simplify: 0.999995,
            l_min: 0.08,
            l_max: 0.25,
            h_min: 0.0,
            c2: 0.75,
            t_simplify: 0.1,
            density_refine: 1.01,
            density_simplify: 0.35,
            flat_contact_cos: 0.97,
            curvature_exponent: 0.5,
            max_depth: 3,
            depth_factor: 0.95,
            force_completion: false,
            interval: 0.01,
            rounds: 1,
            remesh_min_angle: 25.0,
            max_vertices: 200_000,
        }
    }
}

/// `[[tracked]]`: a material point (the seed's particle P) whose world position is recorded.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TrackedSpec {
    /// Name used in messages.
    #[serde(default)]
    pub name: String,
    /// Rest point `[u, v]` (m) in the pattern.
    pub rest: [Real; 2],
}
