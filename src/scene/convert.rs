//! Conversions from the scene's serde types to the core's own parameter types: the scene
//! depends on the core, never the reverse. Every conversion copies values as they are (the
//! scene's defaults equal the core's documented defaults); mesh files are resolved against the
//! scene's folder ([`mesh_path`]).

use super::spec::{
    AdaptivitySpec, CollisionMode, CollisionSpec, CriteriaSpec, ForcesSpec, IntegratorSpec,
    LinearSolver, MaterialSpec, MotionSpec, ObstacleShape, ObstacleSpec, SpringMode,
    StiffnessModel,
};
use super::LoadedScene;
use crate::adapt::{self, AdaptParams};
use crate::collision::{self, ContactParams};
use crate::math::Vec3;
use crate::physics::{self, Forces, IntegratorParams, Material};
use std::path::{Path, PathBuf};

/// The file a scene's mesh key (`cloth.mesh`, `obstacles.N.file`) names: `file` under the scene's
/// folder `base_dir`. A path under `<embedded>/` names a mesh built into the binary wherever the
/// scene is; an embedded scene (`base_dir` is `<embedded>`) reads its relative names from the
/// built-in meshes, or from the current folder when none has that name.
pub fn mesh_path(base_dir: &Path, file: &str) -> PathBuf {
    let file = Path::new(file);
    if crate::io::is_embedded_path(file) {
        return file.to_path_buf();
    }
    let path = base_dir.join(file);
    if crate::io::is_embedded_path(base_dir) && crate::io::embedded_text(&path).is_none() {
        return file.to_path_buf();
    }
    path
}

impl From<StiffnessModel> for physics::StiffnessModel {
    fn from(s: StiffnessModel) -> Self {
        match s {
            StiffnessModel::AreaWeighted => physics::StiffnessModel::AreaWeighted,
            StiffnessModel::Seed => physics::StiffnessModel::Seed,
        }
    }
}

impl From<SpringMode> for physics::SpringMode {
    fn from(s: SpringMode) -> Self {
        match s {
            SpringMode::Tension => physics::SpringMode::Tension,
            SpringMode::Both => physics::SpringMode::Both,
        }
    }
}

impl From<LinearSolver> for physics::LinearSolver {
    fn from(s: LinearSolver) -> Self {
        match s {
            LinearSolver::Cg => physics::LinearSolver::Cg,
            LinearSolver::Cholesky => physics::LinearSolver::Cholesky,
            LinearSolver::Auto => physics::LinearSolver::Auto,
            LinearSolver::PcgSprings => physics::LinearSolver::PcgSprings,
        }
    }
}

impl From<&MaterialSpec> for Material {
    fn from(m: &MaterialSpec) -> Self {
        Material {
            rho: m.rho,
            thickness: m.thickness,
            kappa: m.kappa,
            young: m.young,
            alpha: m.alpha,
            k_b: m.k_b,
            k_bd: m.k_bd,
            mu: m.mu,
            stiffness: m.stiffness.into(),
            cross_section: m.cross_section,
            springs: m.springs.into(),
        }
    }
}

impl From<&ForcesSpec> for Forces {
    fn from(f: &ForcesSpec) -> Self {
        Forces {
            springs: f.springs,
            spring_damping: f.spring_damping,
            bending: f.bending,
            bending_damping: f.bending_damping,
            gravity: f.gravity,
            drag: f.drag,
            g: Vec3::from(f.g),
        }
    }
}

impl From<&IntegratorSpec> for IntegratorParams {
    fn from(i: &IntegratorSpec) -> Self {
        IntegratorParams {
            cg_tolerance: i.cg_tolerance,
            cg_max_iterations: i.cg_max_iterations,
            solver: i.solver.into(),
            relaxation_passes: i.relaxation_passes,
        }
    }
}

impl From<&CollisionSpec> for ContactParams {
    fn from(c: &CollisionSpec) -> Self {
        ContactParams {
            margin: c.margin,
            restitution: c.restitution,
            faces: c.mode == CollisionMode::Face,
        }
    }
}

impl ObstacleSpec {
    /// The core description of this obstacle, its mesh file (if any) resolved against
    /// `base_dir` (the scene's folder).
    pub fn to_core(&self, base_dir: &Path) -> collision::Obstacle {
        let shape = match &self.shape {
            ObstacleShape::Ground { height } => {
                collision::ObstacleShape::Ground { height: *height }
            }
            ObstacleShape::Sphere { center, radius } => collision::ObstacleShape::Sphere {
                center: *center,
                radius: *radius,
            },
            ObstacleShape::Cylinder {
                center,
                radius,
                height,
            } => collision::ObstacleShape::Cylinder {
                center: *center,
                radius: *radius,
                height: *height,
            },
            ObstacleShape::Box {
                center,
                half_extents,
            } => collision::ObstacleShape::Box {
                center: *center,
                half_extents: *half_extents,
            },
            ObstacleShape::Mesh {
                file,
                scale,
                translation,
            } => collision::ObstacleShape::Mesh {
                file: mesh_path(base_dir, file),
                scale: *scale,
                translation: *translation,
            },
        };
        collision::Obstacle {
            shape,
            friction: self.friction,
            restitution: self.restitution,
            motion: self
                .motion
                .as_ref()
                .map_or(collision::ObstacleMotion::Still, Into::into),
        }
    }
}

impl From<&MotionSpec> for collision::ObstacleMotion {
    fn from(m: &MotionSpec) -> Self {
        match m {
            MotionSpec::Linear { velocity } => collision::ObstacleMotion::Linear {
                velocity: *velocity,
            },
            MotionSpec::Spin {
                axis_point,
                axis,
                angular_velocity,
            } => collision::ObstacleMotion::Spin {
                axis_point: *axis_point,
                axis: *axis,
                angular_velocity: *angular_velocity,
            },
            MotionSpec::Keyframes {
                times,
                positions,
                rotations,
                pivot,
            } => collision::ObstacleMotion::Keyframes {
                times: times.clone(),
                positions: positions.clone(),
                rotations: rotations.clone(),
                pivot: *pivot,
            },
        }
    }
}

impl From<&AdaptivitySpec> for AdaptParams {
    fn from(a: &AdaptivitySpec) -> Self {
        AdaptParams {
            refuse_crossings: false,
            restore_momentum: a.restore_momentum,
            restore_energy: a.restore_energy,
            criteria: match a.criteria {
                CriteriaSpec::Source => adapt::Criteria::Source,
                CriteriaSpec::Sizing => adapt::Criteria::Sizing,
            },
            size_angle: a.size_angle,
            size_velocity: a.size_velocity,
            size_compression: a.size_compression,
            size_proximity: a.size_proximity,
            compression_c: a.compression_c,
            cos_refine: a.cos_refine,
            cos_simplify: a.cos_simplify,
            l_min: a.l_min,
            h_min: a.h_min,
            l_max: a.l_max,
            c2: a.c2,
            t_simplify: a.t_simplify,
            flat_contact_cos: a.flat_contact_cos,
            interval: a.interval,
            rounds: a.rounds,
            curvature_exponent: a.curvature_exponent,
            density_refine: a.density_refine,
            density_simplify: a.density_simplify,
            remesh_min_angle: a.remesh_min_angle,
            max_depth: a.max_depth,
            depth_factor: a.depth_factor,
            force_completion: a.force_completion,
        }
    }
}

impl LoadedScene {
    /// The scene's obstacles as the collision module describes them, mesh files resolved
    /// against [`LoadedScene::base_dir`].
    pub fn obstacles(&self) -> Vec<collision::Obstacle> {
        self.scene
            .obstacles
            .iter()
            .map(|o| o.to_core(&self.base_dir))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scene's defaults are the core's documented defaults.
    #[test]
    fn scene_defaults_convert_to_core_defaults() {
        assert_eq!(
            Material::from(&MaterialSpec::default()),
            Material::default()
        );
        assert_eq!(Forces::from(&ForcesSpec::default()), Forces::default());
        assert_eq!(
            IntegratorParams::from(&IntegratorSpec::default()),
            IntegratorParams::default()
        );
        assert_eq!(
            ContactParams::from(&CollisionSpec::default()),
            ContactParams::default()
        );
        assert_eq!(
            AdaptParams::from(&AdaptivitySpec::default()),
            AdaptParams::default()
        );
    }

    #[test]
    fn mesh_files_resolve_against_the_scene_folder() {
        let spec = ObstacleSpec {
            shape: ObstacleShape::Mesh {
                file: "meshes/bunny.obj".into(),
                scale: 2.0,
                translation: [0.0, 0.0, 0.1],
            },
            friction: 0.3,
            restitution: 0.0,
            motion: None,
        };
        let core = spec.to_core(Path::new("scenes"));
        assert_eq!(
            core.shape,
            collision::ObstacleShape::Mesh {
                file: Path::new("scenes").join("meshes/bunny.obj"),
                scale: 2.0,
                translation: [0.0, 0.0, 0.1],
            }
        );
        assert_eq!(core.friction, 0.3);
    }
}
