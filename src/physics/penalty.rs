//! Face contact as a penalty force (`collision.penalty`): a face an obstacle presses between its
//! vertices is pushed back by a spring on its contact point, inside every integrator's step.
//!
//! The collision code lists the pressed faces at a step's start ([`PressedFace`]); each one is a
//! plane through its contact point, fixed for the step. With `w_k` the contact point's
//! barycentric weights and `n` the obstacle's outward normal, the contact point's height is
//! `s(x) = n . sum w_k x_k`, its depth `level - s(x)`, and the penalty's energy
//! `1/2 k max(depth, 0)²`; its force on vertex `k` is `k max(depth, 0) w_k n` and its stiffness
//! matrix `-k w_k w_j n nᵀ` (while pressed). [`Pressed`] adds the force to a model's
//! accelerations, so explicit integrators feel it at every stage; `implicit_euler` and `bdf2`
//! also put its stiffness in their linear system.

use super::{Dynamics, ForceModel};
use crate::math::{Real, Vec3};

/// A face of the cloth that an obstacle presses, pushed back through one step by a penalty
/// spring on its contact point (see the module's documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressedFace {
    /// The face's vertex slots.
    pub slots: [usize; 3],
    /// The contact point's barycentric weights (non-negative, summing to 1).
    pub weights: [Real; 3],
    /// The obstacle's outward unit normal at the contact, fixed for the step.
    pub normal: Vec3,
    /// The height `n . sum w_k x_k` (m) below which the penalty pushes.
    pub level: Real,
    /// The penalty's stiffness `k` (N/m).
    pub stiffness: Real,
}

impl PressedFace {
    /// How far (m) the contact point lies below [`PressedFace::level`] at positions `x` (m);
    /// negative when it is above (the penalty then pushes nothing).
    pub fn depth(&self, x: &[Vec3]) -> Real {
        self.level - self.height_of(x)
    }

    /// `n . sum w_k z_k` for any per-slot vector `z` (positions in m: the contact point's
    /// height; velocities in m/s: its normal speed).
    pub fn height_of(&self, z: &[Vec3]) -> Real {
        (0..3)
            .map(|k| self.weights[k] * self.normal.dot(&z[self.slots[k]]))
            .sum()
    }

    /// The penalty's normal force (N) on the contact point at positions `x` (m), >= 0.
    pub fn force(&self, x: &[Vec3]) -> Real {
        self.stiffness * self.depth(x).max(0.0)
    }

    /// The penalty's energy `1/2 k max(depth, 0)²` (J) at positions `x` (m).
    pub fn energy(&self, x: &[Vec3]) -> Real {
        let d = self.depth(x).max(0.0);
        0.5 * self.stiffness * d * d
    }

    /// Adds the penalty's force (N) at positions `x` (m) to `f`, at every vertex of the face
    /// (fixed slots included: their callers ignore their forces).
    pub fn add_forces(&self, x: &[Vec3], f: &mut [Vec3]) {
        let push = self.force(x);
        if push > 0.0 {
            for k in 0..3 {
                f[self.slots[k]] += self.normal * (push * self.weights[k]);
            }
        }
    }
}

/// A model's dynamics with the penalties of the faces pressed in this step added
/// (see the module's documentation).
pub struct Pressed<'a> {
    /// The cloth's forces.
    pub model: &'a ForceModel,
    /// This step's pressed faces (their slots are the model's).
    pub faces: &'a [PressedFace],
}

impl Dynamics for Pressed<'_> {
    /// The model's accelerations plus each pressed face's penalty over the mass; 0 at fixed
    /// slots.
    fn accelerations(&self, t: Real, x: &[Vec3], v: &[Vec3], a: &mut [Vec3]) {
        self.model.accelerations(t, x, v, a);
        let inv = self.model.inv_mass();
        for face in self.faces {
            let push = face.force(x);
            if push <= 0.0 {
                continue;
            }
            for k in 0..3 {
                let i = face.slots[k];
                a[i] += face.normal * (push * face.weights[k] * inv[i]);
            }
        }
    }

    fn constrain_velocities(&self, v: &mut [Vec3]) {
        self.model.constrain_velocities(v);
    }

    fn velocity_dependent(&self) -> bool {
        self.model.velocity_dependent()
    }

    fn force_model(&self) -> Option<&ForceModel> {
        Some(self.model)
    }

    fn pressed_faces(&self) -> &[PressedFace] {
        self.faces
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::union_jack;
    use crate::physics::{Forces, Material};
    use crate::testing::{built, random_state};

    /// A face of slots 0, 1, 2 pressed along a tilted normal, 2 mm deep at `x`.
    fn face_at(x: &[Vec3]) -> PressedFace {
        let mut face = PressedFace {
            slots: [0, 1, 2],
            weights: [0.2, 0.3, 0.5],
            normal: Vec3::new(0.3, -0.2, 1.0).normalize(),
            level: 0.0,
            stiffness: 1e3,
        };
        face.level = face.height_of(x) + 2e-3;
        face
    }

    #[test]
    fn the_force_is_minus_the_energys_gradient_and_pushes_along_the_normal_only() {
        let x = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(0.2, 1.0, 0.1),
        ];
        let face = face_at(&x);
        let mut f = vec![Vec3::zeros(); 3];
        face.add_forces(&x, &mut f);
        let h = 1e-7;
        for i in 0..3 {
            for axis in 0..3 {
                let mut plus = x.clone();
                plus[i][axis] += h;
                let mut minus = x.clone();
                minus[i][axis] -= h;
                let gradient = (face.energy(&plus) - face.energy(&minus)) / (2.0 * h);
                assert!((f[i][axis] + gradient).abs() < 1e-6, "{i} {axis}");
            }
        }
        let total: Vec3 = f.iter().sum();
        assert!(
            (total - face.normal * (1e3 * 2e-3)).norm() < 1e-12,
            "{total}"
        );
        // Lifted above its level, the face feels nothing and stores nothing.
        let lifted: Vec<Vec3> = x.iter().map(|p| p + face.normal * 3e-3).collect();
        let mut f = vec![Vec3::zeros(); 3];
        face.add_forces(&lifted, &mut f);
        assert_eq!((f, face.energy(&lifted)), (vec![Vec3::zeros(); 3], 0.0));
    }

    #[test]
    fn pressed_dynamics_add_the_penalty_over_the_mass_to_the_models_accelerations() {
        let mesh = union_jack(5, 5, 1.0, 1.0);
        let model = built(&mesh, &Material::default(), &Forces::default());
        let (x, v) = random_state(&mesh, 3, 0.01);
        let face = face_at(&x);
        let (mut bare, mut pressed) = (vec![Vec3::zeros(); x.len()], vec![Vec3::zeros(); x.len()]);
        model.accelerations(0.0, &x, &v, &mut bare);
        let faces = [face];
        let dynamics = Pressed {
            model: &model,
            faces: &faces,
        };
        dynamics.accelerations(0.0, &x, &v, &mut pressed);
        assert_eq!(dynamics.pressed_faces(), &faces);
        for i in 0..x.len() {
            let k = face.slots.iter().position(|&s| s == i);
            let expected = k.map_or(Vec3::zeros(), |k| {
                face.normal * (face.force(&x) * face.weights[k] * model.inv_mass()[i])
            });
            assert!((pressed[i] - bare[i] - expected).norm() < 1e-9, "slot {i}");
        }
    }
}
