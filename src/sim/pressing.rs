//! Face contact as a penalty (`collision.penalty` > 0, [`crate::physics::penalty`]): before a
//! step, the faces an obstacle presses, handed to every integrator through
//! [`crate::physics::Pressed`]; after it, their friction.

use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::Real;
use crate::physics::PressedFace;

/// The faces pressed in the current step, with their obstacles (buffers reused across steps).
#[derive(Debug, Default)]
pub(super) struct Pressing {
    /// This step's pressed faces (slots of the cloth's current mesh).
    pub(super) faces: Vec<PressedFace>,
    obstacle: Vec<usize>,
}

impl Pressing {
    /// Lists every face of `faces` (vertex slots of `cloth`) that one of `obstacles` presses at
    /// the cloth's positions ([`Obstacles::pressed_faces`]), with a penalty of `stiffness`
    /// (N/m) reaching to [`Obstacles::resting_band`]. Call at the step's start.
    pub(super) fn prepare(
        &mut self,
        obstacles: &Obstacles,
        cloth: &Cloth,
        faces: &[[usize; 3]],
        stiffness: Real,
    ) {
        self.faces.clear();
        self.obstacle.clear();
        find(obstacles, cloth, faces, stiffness, |face, ob| {
            self.faces.push(face);
            self.obstacle.push(ob);
        });
    }

    /// Forgets the pressed faces (the mesh changed: their slots are stale).
    pub(super) fn clear(&mut self) {
        self.faces.clear();
        self.obstacle.clear();
    }

    /// After the step of `dt` (s): gives each vertex of a pressed face the friction
    /// ([`Obstacles::held_friction`], cloth friction `mu`) of its share `dt F w_k` of the
    /// penalty's normal impulse, `F` the penalty's force at the step's end (the force an
    /// implicit step solved for). Velocities only: moving the positions by the velocity
    /// change times `dt`, as a vertex hold's friction does, pumped a fine cloth draped over a
    /// sharp edge (docs/model-notes.md, "Face contact as a penalty"). Returns the number of
    /// faces the penalty pressed at the step's end.
    pub(super) fn finish(
        &self,
        obstacles: &Obstacles,
        cloth: &mut Cloth,
        mu: Real,
        dt: Real,
    ) -> usize {
        let mut pressed = 0;
        for (face, &ob) in self.faces.iter().zip(&self.obstacle) {
            let force = face.force(&cloth.x);
            if force <= 0.0 {
                continue;
            }
            pressed += 1;
            for k in 0..3 {
                let i = face.slots[k];
                let inv = cloth.model.inv_mass()[i];
                if inv == 0.0 {
                    continue;
                }
                let dv_n = dt * force * face.weights[k] * inv;
                let v = obstacles.held_friction(ob, cloth.x[i], face.normal, cloth.v[i], dv_n, mu);
                cloth.v[i] = v;
            }
        }
        pressed
    }
}

/// The penalty's energy (J) at the cloth's current state: over the faces `obstacles` press now,
/// as the next step will find them.
pub(super) fn pressed_energy(
    obstacles: &Obstacles,
    cloth: &Cloth,
    faces: &[[usize; 3]],
    stiffness: Real,
) -> Real {
    let mut energy = 0.0;
    find(obstacles, cloth, faces, stiffness, |face, _| {
        energy += face.energy(&cloth.x)
    });
    energy
}

/// Calls `found(face, obstacle)` for each face of `faces` that `obstacles` press at the cloth's
/// positions: its contact plane at the penalty's reach, `level = n . sum w_k x_k + reach - d`
/// for a contact at signed distance `d` (m).
fn find(
    obstacles: &Obstacles,
    cloth: &Cloth,
    faces: &[[usize; 3]],
    stiffness: Real,
    mut found: impl FnMut(PressedFace, usize),
) {
    let reach = obstacles.resting_band();
    let inv_mass = cloth.model.inv_mass();
    obstacles.pressed_faces(
        &cloth.x,
        inv_mass,
        faces,
        |slots, weights, normal, d, ob| {
            let mut face = PressedFace {
                slots,
                weights,
                normal,
                level: 0.0,
                stiffness,
            };
            face.level = face.height_of(&cloth.x) + reach - d;
            found(face, ob);
        },
    );
}
