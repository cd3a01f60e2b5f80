//! Static obstacles and collision response through parry3d (the only module that imports it).
//!
//! Where it sits in the step (MODEL.md §5): after each integration step the simulator calls
//! [`Obstacles::respond`], which tests every free vertex's path `x_start -> x` against the
//! obstacles, applies the restitution and friction response (4.16)-(4.18) and keeps every vertex
//! at least the collision margin off every surface. The adaptivity stage uses
//! [`Obstacles::edge_hit`] (edge criterion), [`Obstacles::push_out`] (new vertices) and
//! [`Obstacles::closest_surface`].
//!
//! Obstacles: ground (parry `HalfSpace`, normal +z), sphere (`Ball`), vertical cylinder
//! (`Cylinder` turned so its axis is z), axis-aligned box (`Cuboid`) and closed triangle meshes
//! (`TriMesh` with `ORIENTED | MERGE_DUPLICATE_VERTICES`, read from OBJ files). Each obstacle keeps
//! its world AABB as a broad phase, so vertices far from an obstacle cost a few comparisons.
//!
//! Any obstacle but the ground may move rigidly ([`ObstacleMotion`]): the step loop calls
//! [`Obstacles::set_step`] before the response, every query then sees the obstacles where they
//! are at the end of the step, the swept test follows a vertex's path relative to the obstacle
//! and the response acts on the velocity relative to the obstacle's surface.
//!
//! Files: `shape` (one obstacle and its parry queries, nalgebra <-> glam conversions), `motion`
//! (rigid motions: pose and velocity at a time), `faces`
//! (obstacles against the cloth's triangles: the surface penetration), `segment_query` (the
//! criteria's edge query, in closed form where it can be),
//! `cylinder_ray` (closed-form ray entry into a cylinder, in place of parry's GJK), `grid` (mesh
//! signed-distance bounds), `crossings` (the cloth's crossings with itself:
//! [`self_intersections`]), `face_grid` (a uniform grid of triangles' boxes, for the measure and
//! adaptation's crossing check), `resting` (the vertices resting on an obstacle, for an
//! integrator that holds them in its solve, and their friction), `error` ([`CollisionError`]).
//!
//! Depths and distances are measured from the raw surface (margin not included): the promise
//! "no penetration beyond the collision margin" reads `max_penetration <= margin`.

mod crossings;
mod cylinder_ray;
mod error;
mod face_grid;
mod faces;
mod grid;
mod mesh_faces;
mod motion;
#[cfg(test)]
mod motion_tests;
mod params;
mod resting;
#[cfg(test)]
mod resting_tests;
mod segment_query;
mod self_contact;
mod shape;
#[cfg(test)]
mod tests;

pub use crossings::{segment_crosses_triangle, self_intersections};
pub use error::CollisionError;
pub(crate) use face_grid::{bounds, FaceGrid};
pub use faces::{FaceContactStats, FaceScratch};
pub use motion::ObstacleMotion;
pub use params::{ContactParams, Obstacle, ObstacleShape};
pub use resting::LEAVING_SPEED;
pub use self_contact::{SelfContact, SelfContactStats, SelfContactTotals};

use crate::math::{Real, Vec3};
use parry3d_f64::math::Vector;
use shape::{to_glam, to_na, Solid};

/// How many push-out sweeps over the obstacles a point gets (a point wedged between two
/// obstacles may be pushed back and forth; after this many sweeps the last position stands).
const PUSH_OUT_SWEEPS: usize = 4;

/// With face contact, an edge closer than this many collision margins to an obstacle meets it
/// (for the adaptivity criteria: faces held at the margin never cross a surface).
pub const TOUCH_MARGINS: Real = 1.5;

/// Slack (m) below the margin before a point counts as too close: a point just pushed to the
/// margin sits there up to rounding and must not be pushed again.
const MARGIN_SLACK: Real = 1e-9;

/// All obstacles of a scene, the collision margin and the default restitution.
pub struct Obstacles {
    obstacles: Vec<Solid>,
    margin: Real,
    restitution: Real,
    faces: bool,
}

/// What one collision pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStats {
    /// Number of vertices that touched an obstacle (crossed a surface or ended within the margin).
    pub contacts: usize,
    /// Largest depth of a vertex inside a raw obstacle surface after the response (m); 0 when
    /// every vertex is outside.
    pub max_penetration: Real,
}

/// Where a segment first meets an obstacle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeHit {
    /// Index of the obstacle in the scene's list.
    pub obstacle: usize,
    /// First point of the segment on or inside the obstacle (m).
    pub point: Vec3,
    /// Outward unit normal of the obstacle there.
    pub normal: Vec3,
}

/// The closest obstacle surface point to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Index of the obstacle in the scene's list.
    pub obstacle: usize,
    /// Closest point on that obstacle's surface (m).
    pub point: Vec3,
    /// Outward unit normal there.
    pub normal: Vec3,
    /// Signed distance from the surface to the query point (m), negative inside.
    pub distance: Real,
}

/// Friction on the tangential velocity (4.17): `v_T' = max(1 - mu dv_N / |v_T|, 0) v_T`.
#[inline]
fn apply_friction(v_t: Vector, mu: Real, dv_n: Real) -> Vector {
    let speed = v_t.length();
    if speed <= 0.0 {
        return v_t;
    }
    v_t * (1.0 - mu * dv_n / speed).max(0.0)
}

/// Response (4.16)-(4.18) of velocity `v` (m/s) on a surface of outward unit normal `n` with
/// restitution `gamma` and friction `mu`. Only an inward normal velocity is reflected.
#[inline]
fn collide_velocity(v: Vector, n: Vector, gamma: Real, mu: Real) -> Vector {
    let v_n = v.dot(n);
    if v_n >= 0.0 {
        return v;
    }
    let v_t = v - n * v_n;
    // v_R = v - (1 + gamma) v_N, so v_R . n = -gamma v_n and dv_N = (v_R - v) . n.
    let dv_n = -(1.0 + gamma) * v_n;
    n * (-gamma * v_n) + apply_friction(v_t, mu, dv_n)
}

impl Obstacles {
    /// Builds the obstacles with these contact parameters.
    ///
    /// Errors: a non-positive or non-finite radius, height, half extent or scale, a non-finite
    /// position, a negative margin, or a mesh file that is missing, unreadable, malformed or
    /// has no faces.
    pub fn build(
        obstacles: &[Obstacle],
        contact: &ContactParams,
    ) -> Result<Obstacles, CollisionError> {
        if !(contact.margin.is_finite() && contact.margin >= 0.0) {
            return Err(CollisionError::BadParameter {
                message: format!("margin must be >= 0, got {}", contact.margin),
            });
        }
        let obstacles = obstacles
            .iter()
            .enumerate()
            .map(|(index, o)| Solid::build(index, o, 2.0 * contact.margin))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Obstacles {
            obstacles,
            margin: contact.margin,
            restitution: contact.restitution,
            faces: contact.faces,
        })
    }

    /// Whether there is no obstacle at all.
    pub fn is_empty(&self) -> bool {
        self.obstacles.is_empty()
    }

    /// Number of obstacles.
    pub fn len(&self) -> usize {
        self.obstacles.len()
    }

    /// Whether any obstacle moves.
    pub fn any_moving(&self) -> bool {
        self.obstacles.iter().any(Solid::is_moving)
    }

    /// Moves every moving obstacle to its pose at `t1` (s) for the step `t0 -> t1` (s): the
    /// queries that follow see it there, [`Obstacles::respond`] follows each vertex's path
    /// relative to it over the step and uses its velocity at `t1`. Still obstacles are untouched.
    /// Built obstacles stand at their pose at `t = 0`.
    pub fn set_step(&mut self, t0: Real, t1: Real) {
        for ob in &mut self.obstacles {
            ob.set_step(t0, t1);
        }
    }

    /// Whether faces collide too (`ContactParams::faces`).
    pub fn face_contact(&self) -> bool {
        self.faces
    }

    /// Outward unit normal of obstacle `index` at its surface point closest to `p` (m).
    pub fn normal_of(&self, index: usize, p: Vec3) -> Vec3 {
        to_na(self.obstacles[index].project(to_glam(p)).normal)
    }

    /// Collision margin (m): vertices are kept this far off every surface.
    pub fn margin(&self) -> Real {
        self.margin
    }

    /// Restitution of obstacle `ob`: its own if positive, else the default.
    #[inline]
    fn gamma(&self, ob: &Solid) -> Real {
        if ob.restitution > 0.0 {
            ob.restitution
        } else {
            self.restitution
        }
    }

    /// Collision pass after an integration step (MODEL.md §5).
    ///
    /// For each vertex `i` with `inv_mass[i] > 0` (others are never touched): the path
    /// `x_start[i] -> x[i]` (m) is tested against every obstacle whose AABB, grown by the margin,
    /// meets the path's AABB. On the first surface crossing, with outward normal `n`, the velocity
    /// `v[i]` (m/s) gets the response (4.16)-(4.18), restitution `gamma` (the obstacle's own if
    /// positive, else the default) and friction `mu = (cloth_mu + obstacle friction) / 2`, and
    /// `x[i] = x_start[i] + v' dt` (`dt` in s). Then, against every obstacle, a vertex inside or
    /// closer than the margin loses its inward normal velocity (with the same friction law,
    /// `dv_N` being the removed normal speed) and is moved along the projection direction to the
    /// margin. Vertices that did neither are left unchanged.
    ///
    /// A moving obstacle (after [`Obstacles::set_step`] for the step `t1 - dt -> t1`) is tested
    /// against the path relative to it ([`shape::Solid::path_start`]), and both responses act on
    /// the velocity relative to its surface's velocity at the contact point, which is then added
    /// back: restitution reflects the relative normal velocity and friction drags the cloth along.
    ///
    /// Returns the number of vertices with a contact and the largest depth (m) of a vertex inside
    /// a raw obstacle surface afterwards (non-zero only when obstacles fight over a vertex).
    /// Allocation-free.
    pub fn respond(
        &self,
        x_start: &[Vec3],
        x: &mut [Vec3],
        v: &mut [Vec3],
        inv_mass: &[Real],
        cloth_mu: Real,
        dt: Real,
    ) -> ContactStats {
        debug_assert_eq!(x_start.len(), x.len());
        debug_assert_eq!(v.len(), x.len());
        debug_assert_eq!(inv_mass.len(), x.len());
        let mut stats = ContactStats::default();
        if self.obstacles.is_empty() {
            return stats;
        }
        let margin = self.margin;
        for i in 0..x.len() {
            if inv_mass[i] <= 0.0 {
                continue;
            }
            let p0 = to_glam(x_start[i]);
            let p1 = to_glam(x[i]);
            // The path relative to each obstacle (start and bounding box): the path itself for
            // a still one.
            let (lo, hi) = (p0.min(p1), p0.max(p1));
            let path = |ob: &Solid| {
                if !ob.is_moving() {
                    return (p0, lo, hi);
                }
                let s = ob.path_start(p0);
                (s, s.min(p1), s.max(p1))
            };
            if !self.obstacles.iter().any(|ob| {
                let (_, lo, hi) = path(ob);
                ob.overlaps(lo, hi, margin)
            }) {
                continue;
            }
            let mut vel = to_glam(v[i]);
            let mut p = p1;
            let mut contact = false;

            // Swept test: the earliest surface crossing of the path.
            // A path shorter than the distance from its end to a surface cannot cross it.
            let length = (p1 - p0).length();
            let mut first: Option<(Real, Vector, usize, Vector)> = None;
            for (k, ob) in self.obstacles.iter().enumerate() {
                let (s, lo, hi) = path(ob);
                let length = if ob.is_moving() {
                    (p1 - s).length()
                } else {
                    length
                };
                if !ob.overlaps(lo, hi, margin) || ob.surely_clear(p1, length) {
                    continue;
                }
                if let Some((t, n)) = ob.cast_entry(s, p1 - s) {
                    if first.is_none_or(|(best, ..)| t < best) {
                        first = Some((t, n, k, s + (p1 - s) * t));
                    }
                }
            }
            if let Some((_, n, k, hit)) = first {
                let ob = &self.obstacles[k];
                let mu = 0.5 * (cloth_mu + ob.friction);
                vel = ob.collide(vel, hit, n, self.gamma(ob), mu);
                p = p0 + vel * dt;
                contact = true;
            }

            // Margin: push out of every obstacle, removing the inward normal velocity.
            let (q, pushed, settled) = self.push_out_glam(p, |ob, point, normal| {
                let mu = 0.5 * (cloth_mu + ob.friction);
                vel = ob.collide(vel, point, normal, 0.0, mu);
            });
            p = q;
            contact |= pushed;
            if !contact {
                continue;
            }
            stats.contacts += 1;
            if !settled {
                stats.max_penetration = stats.max_penetration.max(self.penetration_glam(p));
            }
            x[i] = to_na(p);
            v[i] = to_na(vel);
        }
        stats
    }

    fn penetration_glam(&self, p: Vector) -> Real {
        self.obstacles
            .iter()
            .map(|ob| ob.depth(p))
            .fold(0.0, Real::max)
    }

    /// Depth (m) of `p` inside the raw obstacle surface (margin not included), 0 when outside;
    /// the maximum over obstacles.
    pub fn penetration(&self, p: Vec3) -> Real {
        self.penetration_glam(to_glam(p))
    }

    /// Moves a point (m) found inside an obstacle or within the margin of its surface out to the
    /// margin, along the projection direction; returns the new point (unchanged if clear). For
    /// vertices created by adaptation.
    pub fn push_out(&self, p: Vec3) -> Vec3 {
        to_na(self.push_out_glam(to_glam(p), |_, _, _| {}).0)
    }

    /// Moves `p` out to the margin of every obstacle it is inside or closer than the margin to,
    /// along the projection direction, sweeping over the obstacles up to [`PUSH_OUT_SWEEPS`]
    /// times; `on_push` hears each push before it happens (the obstacle, its surface point and
    /// its outward normal there).
    /// Returns the final point, whether any push happened, and whether a sweep found nothing left
    /// to push (settled).
    fn push_out_glam(
        &self,
        mut p: Vector,
        mut on_push: impl FnMut(&Solid, Vector, Vector),
    ) -> (Vector, bool, bool) {
        let margin = self.margin;
        let mut pushed = false;
        for _ in 0..PUSH_OUT_SWEEPS {
            let mut moved = false;
            for ob in &self.obstacles {
                if !ob.overlaps(p, p, margin) {
                    continue;
                }
                if let Some(proj) = ob.project_near(p, margin - MARGIN_SLACK) {
                    on_push(ob, proj.point, proj.normal);
                    p = proj.point + proj.normal * margin;
                    moved = true;
                }
            }
            pushed |= moved;
            if !moved {
                return (p, pushed, true);
            }
        }
        (p, pushed, false)
    }

    /// Edge query for the adaptivity criteria: does the segment `a -> b` (m) meet an obstacle?
    /// It does when it enters one or lies inside one: the first such point along `a -> b` (`a`
    /// itself when `a` is inside) with the obstacle's outward unit normal there, ties to the lower
    /// obstacle index. With face contact on, no edge ever crosses a surface (faces are held at
    /// the margin), so an edge also meets an obstacle when it comes within
    /// [`TOUCH_MARGINS`] margins of it: the closest obstacle's point and normal.
    pub fn edge_hit(&self, a: Vec3, b: Vec3) -> Option<EdgeHit> {
        self.edge_crossing(a, b).or_else(|| {
            self.faces
                .then(|| self.edge_touch(a, b, TOUCH_MARGINS * self.margin))
                .flatten()
        })
    }

    /// The first point where the segment `a -> b` enters an obstacle or lies inside one.
    fn edge_crossing(&self, a: Vec3, b: Vec3) -> Option<EdgeHit> {
        let (a, b) = (to_glam(a), to_glam(b));
        let (lo, hi) = (a.min(b), a.max(b));
        let mut best: Option<(Real, EdgeHit)> = None;
        for (k, ob) in self.obstacles.iter().enumerate() {
            if !ob.overlaps(lo, hi, 0.0) {
                continue;
            }
            let hit = if let Some(start) = ob.project_near(a, Real::MIN_POSITIVE) {
                Some((0.0, a, start.normal))
            } else {
                ob.cast_entry(a, b - a)
                    .map(|(t, n)| (t, a + (b - a) * t, n))
            };
            if let Some((t, point, normal)) = hit {
                if best.as_ref().is_none_or(|(bt, _)| t < *bt) {
                    best = Some((
                        t,
                        EdgeHit {
                            obstacle: k,
                            point: to_na(point),
                            normal: to_na(normal),
                        },
                    ));
                }
            }
        }
        best.map(|(_, hit)| hit)
    }

    /// The closest obstacle surface point to `p` (m) among the obstacles whose surface is nearer
    /// than `band` (m; inside counts as nearer), as [`Obstacles::closest_surface`] reports it;
    /// `None` when every obstacle is at least `band` away. Obstacles whose bounding box, grown by
    /// `band`, does not hold `p` are skipped without a query.
    pub fn surface_near(&self, p: Vec3, band: Real) -> Option<SurfacePoint> {
        self.nearest(p, |ob, q| {
            if ob.overlaps(q, q, band) {
                ob.project_near(q, band)
            } else {
                None
            }
        })
    }

    /// The obstacle surface point closest to `p` (m), with the outward normal and the signed
    /// distance; among several obstacles, the one with the smallest signed distance (so a point
    /// inside an obstacle reports that obstacle). `None` only when there is no obstacle.
    pub fn closest_surface(&self, p: Vec3) -> Option<SurfacePoint> {
        self.nearest(p, |ob, q| Some(ob.project(q)))
    }

    /// The projection with the smallest signed distance among those `project` gives, per
    /// obstacle (ties to the lower index).
    fn nearest(
        &self,
        p: Vec3,
        project: impl Fn(&Solid, Vector) -> Option<shape::Projection>,
    ) -> Option<SurfacePoint> {
        let q = to_glam(p);
        let mut best: Option<SurfacePoint> = None;
        for (k, ob) in self.obstacles.iter().enumerate() {
            let Some(proj) = project(ob, q) else {
                continue;
            };
            if best.is_none_or(|b| proj.distance < b.distance) {
                best = Some(SurfacePoint {
                    obstacle: k,
                    point: to_na(proj.point),
                    normal: to_na(proj.normal),
                    distance: proj.distance,
                });
            }
        }
        best
    }
}
