//! Face contact as a penalty (`collision.penalty` > 0, [`crate::physics::penalty`]): before a
//! step, the faces an obstacle presses, handed to every integrator through
//! [`crate::physics::Pressed`]; after it, their friction.

use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::{Real, Vec3};
use crate::physics::PressedFace;

/// The faces pressed in the current step, with their obstacles (buffers reused across steps).
/// The list is kept with the state it was found at, so the search is not repeated at the same
/// state: a step lists the faces pressed at the state it ends at, which the energy audit of
/// that state and the next step's start then read.
#[derive(Debug, Default)]
pub(super) struct Pressing {
    /// This step's pressed faces (slots of the cloth's current mesh).
    pub(super) faces: Vec<PressedFace>,
    obstacle: Vec<usize>,
    /// The mesh version, time (s) and penalty stiffness (N/m) the list was found at; `None`
    /// when there is no list.
    found_at: Option<(u64, Real, Real)>,
    /// The positions (m) the list was found at.
    x_found: Vec<Vec3>,
}

impl Pressing {
    /// Lists every face of `faces` (vertex slots of `cloth`) that one of `obstacles` presses at
    /// the cloth's positions ([`Obstacles::pressed_faces`]), with a penalty of `stiffness`
    /// (N/m) reaching to [`Obstacles::resting_band`], the obstacles placed for time `t` (s).
    /// Does nothing when the list is already that of this state.
    pub(super) fn prepare(
        &mut self,
        obstacles: &Obstacles,
        cloth: &Cloth,
        faces: &[[usize; 3]],
        stiffness: Real,
        t: Real,
    ) {
        if self.is_current(cloth, stiffness, t) {
            return;
        }
        self.faces.clear();
        self.obstacle.clear();
        find(obstacles, cloth, faces, stiffness, |face, ob| {
            self.faces.push(face);
            self.obstacle.push(ob);
        });
        self.found_at = Some((cloth.mesh.version(), t, stiffness));
        self.x_found.clear();
        self.x_found.extend_from_slice(&cloth.x);
    }

    /// Whether the list was found at `cloth`'s mesh and positions, at time `t` (s) with
    /// `stiffness` (N/m).
    fn is_current(&self, cloth: &Cloth, stiffness: Real, t: Real) -> bool {
        self.found_at == Some((cloth.mesh.version(), t, stiffness)) && self.x_found == cloth.x
    }

    /// Forgets the pressed faces (the mesh changed: their slots are stale).
    pub(super) fn clear(&mut self) {
        self.faces.clear();
        self.obstacle.clear();
        self.found_at = None;
    }

    /// The penalty's energy (J) at `cloth`'s current state at time `t` (s), over the faces of
    /// `faces` that `obstacles` press now: this list's when it is that state's, else a new
    /// search.
    pub(super) fn energy(
        &self,
        obstacles: &Obstacles,
        cloth: &Cloth,
        faces: &[[usize; 3]],
        stiffness: Real,
        t: Real,
    ) -> Real {
        if self.is_current(cloth, stiffness, t) {
            return self.faces.iter().map(|f| f.energy(&cloth.x)).sum();
        }
        let mut energy = 0.0;
        find(obstacles, cloth, faces, stiffness, |face, _| {
            energy += face.energy(&cloth.x)
        });
        energy
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

#[cfg(test)]
mod tests {
    use super::Pressing;
    use crate::scene::load_embedded;
    use crate::sim::Simulation;

    /// The round table at 17x17 under implicit Euler at 2 ms, run to 0.4 s: the cloth lies over
    /// the table's rim, whose faces the penalty presses.
    fn draped() -> Simulation {
        let set = [
            "cloth.resolution=17",
            "integrator.name=\"implicit_euler\"",
            "time.mode=\"fixed\"",
            "time.dt=0.002",
        ]
        .map(String::from);
        let loaded = load_embedded("round_table", &set).unwrap().unwrap();
        let mut sim = Simulation::new(&loaded).unwrap();
        while sim.t < 0.4 {
            sim.step().unwrap();
        }
        sim
    }

    /// The penalty energy by a search of its own.
    fn searched_energy(sim: &Simulation) -> f64 {
        let penalty = sim.scene.collision.penalty;
        Pressing::default().energy(&sim.obstacles, &sim.cloth, &sim.faces.1, penalty, sim.t)
    }

    #[test]
    fn the_list_kept_from_the_step_is_the_one_a_new_search_finds() {
        let mut sim = draped();
        assert!(!sim.pressing.faces.is_empty(), "the rim presses no face");
        let kept = sim.energies().contact;
        assert!(kept > 0.0);
        assert_eq!(kept, searched_energy(&sim));

        // Positions changed outside a step: the list is found again.
        for x in &mut sim.cloth.x {
            x.z -= 0.002;
        }
        assert_eq!(sim.energies().contact, searched_energy(&sim));
        for x in &mut sim.cloth.x {
            x.z += 1.0;
        }
        let penalty = sim.scene.collision.penalty;
        let (cloth, t) = (&sim.cloth, sim.t);
        sim.pressing
            .prepare(&sim.obstacles, cloth, &sim.faces.1, penalty, t);
        assert!(sim.pressing.faces.is_empty());
    }
}
