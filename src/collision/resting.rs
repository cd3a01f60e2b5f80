//! Resting contact for an integrator that holds contacts in its solve
//! ([`crate::physics::Hold`]): which vertices rest on an obstacle at a step's start, and the
//! friction a held vertex gets after the step.

use super::faces::{barycentric, bounds, TriangleContact};
use super::shape::{Geometry, Solid};
use super::{apply_friction, to_glam, to_na, Obstacles, MARGIN_SLACK, TOUCH_MARGINS};
use crate::math::{Real, Vec3};
use parry3d_f64::math::Vector;

/// Speed (m/s) away from a surface, relative to it, above which a vertex near an obstacle is
/// leaving it and is not held: the response leaves a resting vertex's normal speed at zero up
/// to round-off.
pub const LEAVING_SPEED: Real = 1e-6;

/// A face contact holds its vertices only where the obstacle comes closer to the face than the
/// vertices' own distances, interpolated at the contact point, by more than this many collision
/// margins: an edge or a corner poking the face between its vertices, which no vertex contact
/// sees. Where the surface is smooth at the face's scale the vertices' own contacts hold the
/// cloth; holding every vertex of such a face along one normal over-constrains it (the sphere's
/// finest implicit grid moved away from the reference: docs/model-notes.md, "Contact in the
/// implicit solve").
pub const FACE_HOLD_EXCESS: Real = 1.0;

/// A face is pressed ([`Obstacles::pressed_faces`]) where the obstacle comes closer to it than
/// its vertices' interpolated distances by more than this many collision margins. Lower than
/// [`FACE_HOLD_EXCESS`]: measured on the plate (docs/model-notes.md, "Face contact as a
/// penalty"), a whole margin left the 65x65 grid pumping.
pub const PRESS_EXCESS: Real = 0.25;

impl Obstacles {
    /// Calls `found(slot, obstacle, normal)` for every free vertex (`inv_mass > 0`) resting on
    /// an obstacle at positions `x` (m) and velocities `v` (m/s), not leaving it faster than
    /// [`LEAVING_SPEED`] relative to its surface: first each vertex within [`TOUCH_MARGINS`]
    /// collision margins of a surface (inside included), with the nearest obstacle's index and
    /// its outward unit normal at the closest point; then, with `faces` (vertex slots; face
    /// contact), each vertex of positive barycentric weight at the contact point of a face
    /// that close to an obstacle but the ground, with that contact's normal, when the contact is
    /// closer than the vertices' interpolated distances by more than [`FACE_HOLD_EXCESS`]
    /// margins (a slot may be found more than once). Obstacles stand where the last [`Obstacles::set_step`] put them
    /// (the step's start).
    pub fn resting(
        &self,
        x: &[Vec3],
        v: &[Vec3],
        inv_mass: &[Real],
        faces: Option<&[[usize; 3]]>,
        mut found: impl FnMut(usize, usize, Vec3),
    ) {
        let band = TOUCH_MARGINS * self.margin + MARGIN_SLACK;
        let resting = |ob: &Solid, i: usize, point: Vector, normal: Vector| {
            let relative = to_glam(v[i]) - ob.surface_velocity(point);
            inv_mass[i] > 0.0 && relative.dot(normal) <= LEAVING_SPEED
        };
        for (i, &p) in x.iter().enumerate() {
            if inv_mass[i] <= 0.0 {
                continue;
            }
            let Some(surface) = self.surface_near(p, band) else {
                continue;
            };
            let ob = &self.obstacles[surface.obstacle];
            if resting(ob, i, to_glam(surface.point), to_glam(surface.normal)) {
                found(i, surface.obstacle, surface.normal);
            }
        }
        let faces = faces.unwrap_or_default();
        self.poked_faces(x, inv_mass, faces, FACE_HOLD_EXCESS, |f, w, c, k| {
            let ob = &self.obstacles[k];
            for j in 0..3 {
                if w[j] > 0.0 && resting(ob, f[j], c.point, c.normal) {
                    found(f[j], k, to_na(c.normal));
                }
            }
        });
    }

    /// Calls `found(face, weights, normal, distance, obstacle)` for every face of `faces`
    /// (vertex slots into `x`, m) with a free vertex that an obstacle but the ground presses
    /// within [`TOUCH_MARGINS`] collision margins, closer than its vertices' interpolated
    /// distances by more than [`PRESS_EXCESS`] margins: the contact point's barycentric
    /// weights, the obstacle's outward unit normal there, the contact's signed distance (m)
    /// and the obstacle's index. Obstacles stand where the last [`Obstacles::set_step`] put
    /// them.
    pub fn pressed_faces(
        &self,
        x: &[Vec3],
        inv_mass: &[Real],
        faces: &[[usize; 3]],
        mut found: impl FnMut([usize; 3], [Real; 3], Vec3, Real, usize),
    ) {
        self.poked_faces(x, inv_mass, faces, PRESS_EXCESS, |f, w, c, k| {
            found(f, w, to_na(c.normal), c.distance, k)
        });
    }

    /// Calls `found(face, weights, contact, obstacle)` for every face of `faces` (vertex slots
    /// into `x`, m) with a free vertex that an obstacle but the ground comes within
    /// [`TOUCH_MARGINS`] collision margins of, closer than the face's vertices' own distances
    /// interpolated at the contact point by more than `excess` margins (an edge or a corner
    /// poking the face): the contact point's barycentric weights, the contact and the
    /// obstacle's index.
    fn poked_faces(
        &self,
        x: &[Vec3],
        inv_mass: &[Real],
        faces: &[[usize; 3]],
        excess: Real,
        mut found: impl FnMut([usize; 3], [Real; 3], &TriangleContact, usize),
    ) {
        let band = TOUCH_MARGINS * self.margin + MARGIN_SLACK;
        for &f in faces {
            if f.iter().all(|&i| inv_mass[i] <= 0.0) {
                continue;
            }
            let tri = f.map(|i| to_glam(x[i]));
            let (lo, hi) = bounds(tri);
            for (k, ob) in self.obstacles.iter().enumerate() {
                if matches!(ob.geometry(), Geometry::Ground(_)) || !ob.overlaps(lo, hi, band) {
                    continue;
                }
                let Some(c) = ob.triangle_contact(tri, band) else {
                    continue;
                };
                let w = barycentric(c.point, tri);
                let poked = c.distance + excess * self.margin;
                if interpolated_distance(ob, tri, w, poked) >= poked {
                    found(f, w, &c, k);
                }
            }
        }
    }

    /// The distance (m) from an obstacle within which a face rests on it: the penalty's reach.
    pub fn resting_band(&self) -> Real {
        TOUCH_MARGINS * self.margin
    }

    /// The velocity (m/s) of a vertex held on obstacle `obstacle` at `p` (m), of velocity `v`
    /// (m/s), after the friction (4.17) of a normal impulse per unit mass `dv_n` (m/s): its
    /// velocity relative to the surface keeps its part along `normal` and its tangential part
    /// `v_T` becomes `max(1 - mu dv_n / |v_T|, 0) v_T`, `mu` the mean of `cloth_mu` and the
    /// obstacle's friction. `v` itself for `dv_n <= 0` (the obstacle pressed nothing).
    pub fn held_friction(
        &self,
        obstacle: usize,
        p: Vec3,
        normal: Vec3,
        v: Vec3,
        dv_n: Real,
        cloth_mu: Real,
    ) -> Vec3 {
        if dv_n <= 0.0 {
            return v;
        }
        let ob: &Solid = &self.obstacles[obstacle];
        let n = to_glam(normal);
        let carried = ob.surface_velocity(to_glam(p));
        let relative = to_glam(v) - carried;
        let along = n * relative.dot(n);
        let mu = 0.5 * (cloth_mu + ob.friction);
        to_na(carried + along + apply_friction(relative - along, mu, dv_n))
    }
}

/// `sum w_k d_k` over the triangle `tri`'s vertices, `d_k` their signed distances (m) to `ob`,
/// exact when it is below `limit` (m); otherwise some value at least `limit`. A vertex whose
/// term alone would reach `limit` is not measured further (a bounded query: cheap on a mesh),
/// the other vertices being taken as outside.
fn interpolated_distance(ob: &Solid, tri: [Vector; 3], w: [Real; 3], limit: Real) -> Real {
    let mut sum = 0.0;
    for k in 0..3 {
        if w[k] <= 0.0 {
            continue;
        }
        let reach = limit.max(0.0) / w[k];
        match ob.project_near(tri[k], reach) {
            Some(p) => sum += w[k] * p.distance,
            None => return limit,
        }
    }
    sum
}
