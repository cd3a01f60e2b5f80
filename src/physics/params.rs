//! The physics' own parameters (MODEL.md §2-§4): the cloth material, the force switches and the
//! integrator options. Plain structs with documented defaults (the scene's defaults); the scene
//! converts its TOML sections into them.

use crate::math::{Real, Vec3};

/// Spring stiffness model (MODEL.md §2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum StiffnessModel {
    /// `k = E T S / L²`: mesh-independent sheet stiffness. The default.
    #[default]
    AreaWeighted,
    /// `k = E A0 / L` (seed equation 4.3).
    Seed,
}

/// Which spring deformations resist (MODEL.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpringMode {
    /// Springs resist stretching only; compression is free so the cloth buckles. The default.
    #[default]
    Tension,
    /// Springs resist stretching and compression.
    Both,
}

/// The cloth material (MODEL.md §2), SI units.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Density `rho` (kg/m³). Default 6000.
    pub rho: Real,
    /// Thickness `T` (m). Default 1e-4.
    pub thickness: Real,
    /// Permeability `kappa`: drag coefficient per rest area (N s/m³). Default 3.
    pub kappa: Real,
    /// Young's modulus `E` (N/m²). Default 1e7.
    pub young: Real,
    /// Spring damping ratio `alpha`: `kd = alpha k` (s). Default 0.01.
    pub alpha: Real,
    /// Bending stiffness `k_b` (N m). Default 1e-3.
    pub k_b: Real,
    /// Bending damping `k_bd` (N s). Default 1e-4.
    pub k_bd: Real,
    /// Cloth friction coefficient `mu` (dimensionless, averaged with the obstacle's). Default 0.05.
    pub mu: Real,
    /// Stiffness model. Default [`StiffnessModel::AreaWeighted`].
    pub stiffness: StiffnessModel,
    /// Spring cross-section `A0` (m²) for [`StiffnessModel::Seed`]. Default 1e-4.
    pub cross_section: Real,
    /// Whether springs resist compression. Default [`SpringMode::Tension`].
    pub springs: SpringMode,
}

impl Default for Material {
    fn default() -> Self {
        Material {
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

/// Which forces are evaluated (a force switched off is never evaluated), and gravity.
#[derive(Clone, Debug, PartialEq)]
pub struct Forces {
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
    /// Gravity acceleration (m/s²). Default `(0, 0, -9.81)`.
    pub g: Vec3,
}

impl Default for Forces {
    fn default() -> Self {
        Forces {
            springs: true,
            spring_damping: true,
            bending: true,
            bending_damping: true,
            gravity: true,
            drag: true,
            g: Vec3::new(0.0, 0.0, -9.81),
        }
    }
}

/// How `implicit_euler` solves its linear system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// Block-Jacobi preconditioned conjugate gradients, matrix-free.
    Cg,
    /// Sparse Cholesky of the assembled matrix, its symbolic analysis kept while the topology is
    /// unchanged; conjugate gradients for a step whose factorisation fails.
    Cholesky,
    /// Conjugate gradients, and Cholesky for a step whose CG ends above its tolerance and for a
    /// window of steps after it (doubling with each such step).
    Auto,
    /// Conjugate gradients preconditioned by a sparse Cholesky factorisation, in single
    /// precision, of the matrix with the bending couplings no spring shares (a bending
    /// element's two wings) moved to the diagonal: the springs' pattern, a sparser factor than
    /// the whole matrix's, and those couplings left to a few iterations (3 to 6 a step on
    /// average on the results' runs, 10 at most). Cholesky of the whole matrix for a step whose
    /// CG ends above its tolerance, or whose preconditioner's factorisation fails.
    /// The default.
    #[default]
    PcgSprings,
}

/// Options of the integrators that have any; each integrator reads only its own.
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorParams {
    /// `implicit_euler`: relative residual at which conjugate gradients stop,
    /// `|r| <= cg_tolerance |b|` (dimensionless). Default 1e-6.
    pub cg_tolerance: Real,
    /// `implicit_euler`: iteration cap of conjugate gradients per step. Default 200.
    pub cg_max_iterations: usize,
    /// `implicit_euler`: the linear solver. Default [`LinearSolver::PcgSprings`].
    pub solver: LinearSolver,
    /// `verlet_relaxation`: Gauss-Seidel passes over the edges after each Verlet step.
    /// Default 4.
    pub relaxation_passes: usize,
}

impl Default for IntegratorParams {
    fn default() -> Self {
        IntegratorParams {
            cg_tolerance: 1e-6,
            cg_max_iterations: 200,
            solver: LinearSolver::PcgSprings,
            relaxation_passes: 4,
        }
    }
}
