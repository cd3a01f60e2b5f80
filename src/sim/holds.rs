//! Contacts held in the implicit solve ([`Hold`]): before a step, the vertices resting on an
//! obstacle, handed to an integrator that holds them; after it, their friction.

use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::Real;
use crate::physics::{Hold, Integrator};

/// Per hold handed to the integrator, the index of its obstacle (buffers reused across steps).
#[derive(Debug, Default)]
pub(super) struct Holding {
    obstacle: Vec<usize>,
}

impl Holding {
    /// Lists in `integrator`'s holds ([`Integrator::holds`]) every vertex of `cloth` resting on
    /// one of `obstacles` ([`Obstacles::resting`]), by its faces too when `faces` is given (face
    /// contact: the cloth's faces as vertex slots); nothing for an integrator that holds no
    /// contacts. Call at the step's start, before the integrator's step.
    pub(super) fn prepare(
        &mut self,
        integrator: &mut dyn Integrator,
        obstacles: &Obstacles,
        cloth: &Cloth,
        faces: Option<&[[usize; 3]]>,
    ) {
        let Some(holds) = integrator.holds() else {
            return;
        };
        holds.clear();
        self.obstacle.clear();
        if obstacles.is_empty() {
            return;
        }
        let inv_mass = cloth.model.inv_mass();
        obstacles.resting(&cloth.x, &cloth.v, inv_mass, faces, |slot, ob, n| {
            holds.push(Hold {
                slot,
                normal: n,
                held: false,
                impulse: 0.0,
            });
            self.obstacle.push(ob);
        });
    }

    /// After the integrator's step of `dt` (s): gives every held vertex the friction of its
    /// impulse ([`Obstacles::held_friction`], cloth friction `mu`), its position moved by the
    /// velocity change times `dt`, as the collision response moves a vertex it stops. Returns
    /// the number of vertices held in the step.
    pub(super) fn finish(
        &self,
        integrator: &mut dyn Integrator,
        obstacles: &Obstacles,
        cloth: &mut Cloth,
        mu: Real,
        dt: Real,
    ) -> usize {
        let Some(holds) = integrator.holds() else {
            return 0;
        };
        let mass = cloth.model.mass();
        let mut held = 0;
        for (h, &ob) in holds.iter().zip(&self.obstacle) {
            if !h.held {
                continue;
            }
            held += 1;
            let i = h.slot;
            let dv_n = h.impulse / mass[i];
            let v = obstacles.held_friction(ob, cloth.x[i], h.normal, cloth.v[i], dv_n, mu);
            cloth.x[i] += (v - cloth.v[i]) * dt;
            cloth.v[i] = v;
        }
        held
    }
}
