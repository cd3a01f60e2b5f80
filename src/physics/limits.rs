//! Step-size limits the dynamic step formula (4.5-4.6) does not see.

use super::ForceModel;
use crate::math::Real;

impl ForceModel {
    /// Largest step (s) for which explicit integration of the spring damping alone stays stable:
    /// `min_i m_i / sum_j kd_j` over movable vertices i and their springs j. The damping rate of
    /// vertex i is at most `2 sum_j kd_j / m_i` (Gershgorin), and explicit Euler (the most
    /// restrictive of the explicit schemes on real decay rates) is stable below `2 / rate`.
    /// Infinite when spring damping is off or nothing can move. Allocates a scratch array: call it
    /// when the mesh changes, not every step.
    pub fn damping_step_limit(&self) -> Real {
        if !self.switches().spring_damping {
            return Real::INFINITY;
        }
        let inv_mass = self.inv_mass();
        let mut damping = vec![0.0; inv_mass.len()];
        let s = self.springs();
        for j in 0..s.len() {
            damping[s.a[j] as usize] += s.kd[j];
            damping[s.b[j] as usize] += s.kd[j];
        }
        inv_mass
            .iter()
            .zip(&damping)
            .filter(|(&w, &c)| w > 0.0 && c > 0.0)
            .map(|(&w, &c)| 1.0 / (w * c))
            .fold(Real::INFINITY, Real::min)
    }
}

#[cfg(test)]
mod tests {
    use crate::math::{Real, Vec3};
    use crate::mesh::union_jack;
    use crate::physics::{integrator_named, Dynamics, ForceModel};
    use crate::physics::{Forces, Material};

    /// Damping only (no elasticity, gravity or drag), so the step limit is the damping one.
    fn damping_model(n: usize) -> ForceModel {
        let mesh = union_jack(n, n, 1.0, 1.0);
        let forces = Forces {
            springs: false,
            bending: false,
            bending_damping: false,
            gravity: false,
            drag: false,
            ..Forces::default()
        };
        let mut m = ForceModel::new(&Material::default(), &forces);
        m.rebuild(&mesh);
        m
    }

    /// Runs symplectic Euler on a random velocity field for 400 steps of `dt`; returns the final
    /// kinetic-energy proxy (sum of |v|²).
    fn run(model: &ForceModel, dt: Real) -> Real {
        let n = model.mass().len();
        let mut x = vec![Vec3::zeros(); n];
        let mut v: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new((i as Real * 0.37).sin(), (i as Real * 1.3).cos(), 0.2))
            .collect();
        model.constrain_velocities(&mut v);
        let mut integrator = integrator_named("symplectic_euler").unwrap();
        for k in 0..400 {
            integrator.step(model, k as Real * dt, dt, &mut x, &mut v);
        }
        v.iter().map(|w| w.norm_squared()).sum()
    }

    #[test]
    fn steps_below_the_damping_limit_are_stable_and_far_above_it_blow_up() {
        let model = damping_model(9);
        let limit = model.damping_step_limit();
        assert!(limit.is_finite() && limit > 0.0);
        let start = run(&model, 0.0);
        assert!(run(&model, 0.9 * limit) <= start, "decays below the limit");
        let blown = run(&model, 8.0 * limit);
        assert!(
            !blown.is_finite() || blown > 1e6 * start,
            "{blown} vs {start}"
        );
    }

    #[test]
    fn limit_is_infinite_without_spring_damping() {
        let mesh = union_jack(3, 3, 1.0, 1.0);
        let forces = Forces {
            spring_damping: false,
            ..Forces::default()
        };
        let mut m = ForceModel::new(&Material::default(), &forces);
        m.rebuild(&mesh);
        assert_eq!(m.damping_step_limit(), Real::INFINITY);
    }
}
