//! The obstacles against the cloth's triangles: an obstacle poking through a face between
//! vertices that are all outside it, which no vertex test sees. [`Obstacles::surface_penetration`]
//! measures it (what a user sees: `max_surface_penetration`); [`Obstacles::respond_faces`]
//! resolves it (`[collision] mode = "face"`), Bridson et al. (2002) style: the face's contact
//! point is moved out to the margin and loses its inward velocity by impulses spread over the
//! face's vertices by their barycentric weights and inverse masses.
//!
//! The deepest point of an obstacle inside a triangle, per shape:
//! - ground: a plane, so the lowest vertex (exact);
//! - sphere: the triangle's closest point to the centre (exact);
//! - cylinder and box: parry's convex contact (GJK/EPA): the smallest translation that separates
//!   the triangle from the solid, so a rim or a box edge or corner through a face is found;
//! - mesh: the deeper of two tests. A tip: each obstacle vertex near the triangle is followed
//!   along its outward pseudo-normal to the triangle's plane; where that meets the triangle, the
//!   vertex's signed distance across the plane is how far the cloth lies above (positive) or
//!   below (negative) the obstacle there. A sunk face: the triangle's ten points at barycentric
//!   thirds, each projected on the mesh; the deepest, pushed out along its projection's normal.
//!   The tip test alone misses a face sunk into the mesh with no mesh vertex through it (a mesh
//!   edge across the face, a coarse face over a smooth bulge); the samples alone miss a thin tip
//!   between them (the bunny's ears). A mesh edge through a face between the samples is seen
//!   only as deep as the samples reach (at most the exact depth).

use super::mesh_faces::{mesh_contact, mesh_sample_contact};
use super::shape::{to_glam, to_na, Geometry, Solid};
use super::{Obstacles, MARGIN_SLACK};
use crate::math::{Real, Vec3};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{Shape, Triangle};

/// Below this length (m) an offset gives no direction.
pub(super) const DEGENERATE_LENGTH: Real = 1e-12;

/// Most passes of the face response over the faces (a face pushed out may push a neighbour in;
/// what a last pass leaves shows in `max_surface_penetration`). A pass visits only the faces
/// the last one moved. 4 left the bunny's ears 3.6 cm through a 65x65 cloth; 16 leave none.
const FACE_SWEEPS: usize = 16;

/// Reusable lists of the face pass (so a steady-state step allocates nothing).
#[derive(Clone, Debug, Default)]
pub struct FaceScratch {
    active: Vec<usize>,
    next: Vec<usize>,
}

/// What one face pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FaceContactStats {
    /// Face contacts resolved, over every sweep.
    pub contacts: usize,
    /// Sweeps that moved something.
    pub sweeps: usize,
}

/// Where an obstacle comes closest to (or deepest into) a cloth triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TriangleContact {
    /// The point of the cloth triangle (m).
    pub point: Vector,
    /// Outward unit normal of the obstacle there: the direction to move the triangle out along.
    pub normal: Vector,
    /// Signed distance from the obstacle's surface to the triangle along `normal` (m); negative
    /// when the obstacle pokes through the triangle by that much.
    pub distance: Real,
}

impl Solid {
    /// The flat face of a box or the cap of a cylinder whose outer region holds `p` (world, m):
    /// the points outside the solid whose closest surface point lies on that one flat face. A
    /// region is convex, so a triangle with its three vertices in one region lies in it and is
    /// closest to the solid at a vertex. `None` elsewhere and for other shapes.
    pub(super) fn flat_region(&self, p: Vector) -> Option<u8> {
        let local = self.pose().inverse_transform_point(p);
        match self.geometry() {
            Geometry::Cuboid(s) => {
                let h = s.half_extents;
                let out = [
                    local.x.abs() > h.x,
                    local.y.abs() > h.y,
                    local.z.abs() > h.z,
                ];
                let axis = match out {
                    [true, false, false] => 0,
                    [false, true, false] => 1,
                    [false, false, true] => 2,
                    _ => return None,
                };
                Some(2 * axis + u8::from(local[axis as usize] > 0.0))
            }
            Geometry::Cylinder(s) => {
                let radial = local.x * local.x + local.z * local.z;
                (local.y.abs() > s.half_height && radial <= s.radius * s.radius)
                    .then_some(u8::from(local.y > 0.0))
            }
            _ => None,
        }
    }

    /// Whether the triangle surely has no contact closer than `band` (m) other than at its
    /// vertices: its three vertices in one flat region ([`Solid::flat_region`]), or the whole
    /// triangle clear ([`Solid::hull_clear`]).
    fn triangle_clear(&self, tri: [Vector; 3], band: Real) -> bool {
        if let Some(region) = self.flat_region(tri[0]) {
            if tri[1..]
                .iter()
                .all(|&p| self.flat_region(p) == Some(region))
            {
                return true;
            }
        }
        self.hull_clear(tri, band)
    }

    /// Whether every point of the triangle `tri` (world, m; a segment when two vertices
    /// coincide) is surely farther than `band` (m) from the solid, its vertices included: for a
    /// cylinder, the triangle's distance from the axis across the plane of the caps exceeds the
    /// radius by `band` (the solid lies inside its infinite cylinder); for a mesh, one vertex is
    /// farther than `band` plus its longest edge (the signed distance is 1-Lipschitz; the grid's
    /// lower bound answers without a query). `false` when unsure.
    pub(super) fn hull_clear(&self, tri: [Vector; 3], band: Real) -> bool {
        match self.geometry() {
            Geometry::Cylinder(s) => {
                let across = tri.map(|p| {
                    let local = self.pose().inverse_transform_point(p);
                    [local.x, local.z]
                });
                distance_to_origin_2d(across).0 - s.radius >= band
            }
            Geometry::Mesh(_) => {
                let (a, b, c) = (
                    (tri[1] - tri[0]).length(),
                    (tri[2] - tri[1]).length(),
                    (tri[0] - tri[2]).length(),
                );
                let reach = [a.max(c), a.max(b), b.max(c)];
                (0..3).any(|k| self.surely_clear(tri[k], band + reach[k]))
            }
            _ => false,
        }
    }

    /// The deepest (or closest) contact of this obstacle with the triangle `tri` (world, m), when
    /// its signed distance is below `band` (m); `None` otherwise.
    pub(crate) fn triangle_contact(&self, tri: [Vector; 3], band: Real) -> Option<TriangleContact> {
        if self.triangle_clear(tri, band) {
            return None;
        }
        let contact = match self.geometry() {
            Geometry::Ground(_) => {
                let h = self.pose().translation.z;
                let low = tri
                    .into_iter()
                    .min_by(|p, q| p.z.total_cmp(&q.z))
                    .expect("three vertices");
                TriangleContact {
                    point: low,
                    normal: Vector::Z,
                    distance: low.z - h,
                }
            }
            Geometry::Ball(ball) => {
                let centre = self.pose().translation;
                let t = Triangle::new(tri[0], tri[1], tri[2]);
                let q = t.project_local_point(centre, false).point;
                let offset = q - centre;
                let length = offset.length();
                let normal = if length > DEGENERATE_LENGTH {
                    offset / length
                } else {
                    t.normal().unwrap_or(Vector::Z)
                };
                TriangleContact {
                    point: q,
                    normal,
                    distance: length - ball.radius,
                }
            }
            Geometry::Cylinder(s) => {
                match cylinder_side_contact(self.pose(), s.radius, s.half_height, tri) {
                    Some(side) => side,
                    None => convex_contact(self.pose(), s, tri, band)?,
                }
            }
            Geometry::Cuboid(s) => convex_contact(self.pose(), s, tri, band)?,
            // The deeper of the tip and the sunk face (the tip on a tie).
            Geometry::Mesh(m) => [
                mesh_contact(self, m, tri, band),
                mesh_sample_contact(self, tri, band),
            ]
            .into_iter()
            .flatten()
            .min_by(|a, b| a.distance.total_cmp(&b.distance))?,
        };
        (contact.distance < band).then_some(contact)
    }
}

/// parry's contact between the triangle and a convex solid at `pose`.
fn convex_contact(
    pose: &Pose,
    solid: &dyn Shape,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    let t = Triangle::new(tri[0], tri[1], tri[2]);
    let c = parry3d_f64::query::contact(&Pose::identity(), &t, pose, solid, band).ok()??;
    Some(TriangleContact {
        point: c.point1,
        normal: -c.normal1,
        distance: c.dist,
    })
}

/// The bounding box `(lo, hi)` of a triangle (m).
pub(super) fn bounds(tri: [Vector; 3]) -> (Vector, Vector) {
    (
        tri[0].min(tri[1]).min(tri[2]),
        tri[0].max(tri[1]).max(tri[2]),
    )
}

/// The swept test's verdict on a face through `ob` at the step's end (`end`, contact normal
/// `end_normal`): the obstacle's normal at the start (`start`) when the face was clear of it
/// then and the normal has turned by more than 45 degrees since (the face passed a feature
/// thinner than its motion); `None` otherwise (the push answers).
fn crossed(
    ob: &Solid,
    start: [Vector; 3],
    end: [Vector; 3],
    end_normal: Vector,
    margin: Real,
) -> Option<Vector> {
    let travel = (0..3)
        .map(|k| (end[k] - start[k]).length())
        .fold(0.0, Real::max);
    let c0 = ob.triangle_contact(start, travel + 2.0 * margin)?;
    (c0.distance >= 0.0 && c0.normal.dot(end_normal) < std::f64::consts::FRAC_1_SQRT_2)
        .then_some(c0.normal)
}

/// Bisection steps of the swept face test: the time of impact to 1/1024 of the step.
const IMPACT_BISECTIONS: usize = 10;

/// The latest fraction `s` of the step (in [0, 1)) at which the face moving linearly from
/// `start` (clear of `ob`) to `end` (through it) is still clear of the obstacle's surface.
fn time_of_impact(ob: &Solid, start: [Vector; 3], end: [Vector; 3], margin: Real) -> Real {
    let at = |s: Real| -> [Vector; 3] { [0, 1, 2].map(|k| start[k] + (end[k] - start[k]) * s) };
    let clear = |s: Real| {
        ob.triangle_contact(at(s), margin)
            .is_none_or(|c| c.distance >= 0.0)
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..IMPACT_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if clear(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Distance (m) from the origin to the plane triangle `tri`, 0 when it holds the origin (a
/// degenerate triangle is its edges); outside, also the closest point as `(k, t)`: at parameter
/// `t` along the edge from vertex `k` to vertex `k + 1`.
fn distance_to_origin_2d(tri: [[Real; 2]; 3]) -> (Real, Option<(usize, Real)>) {
    let cross = |a: [Real; 2], b: [Real; 2]| a[0] * b[1] - a[1] * b[0];
    let side = |k: usize| cross(tri[k], tri[(k + 1) % 3]);
    let sides = [side(0), side(1), side(2)];
    if sides.iter().all(|&c| c > 0.0) || sides.iter().all(|&c| c < 0.0) {
        return (0.0, None);
    }
    // Edges compared by squared distance; the one square root (`hypot`) for the closest.
    let mut best: Option<(Real, usize, Real, [Real; 2])> = None;
    // (A NaN distance never wins, as a NaN fails every comparison.)
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = if len2 > 0.0 {
            (-(a[0] * ab[0] + a[1] * ab[1]) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + t * ab[0], a[1] + t * ab[1]];
        let d2 = q[0] * q[0] + q[1] * q[1];
        if d2 < best.map_or(Real::INFINITY, |(b2, ..)| b2) {
            best = Some((d2, k, t, q));
        }
    }
    match best {
        Some((_, k, t, q)) => (q[0].hypot(q[1]), Some((k, t))),
        None => (Real::INFINITY, None),
    }
}

/// The contact of a triangle (local frame of the cylinder, axis y) with the cylinder's side in
/// closed form, when it is surely the side's: every vertex between the caps' planes and the
/// triangle outside the infinite cylinder. Then its closest point to the axis (on an edge) is the
/// contact and the normal is radial. `None` otherwise (left to GJK).
pub(super) fn cylinder_side_contact(
    pose: &Pose,
    radius: Real,
    half_height: Real,
    tri: [Vector; 3],
) -> Option<TriangleContact> {
    let local = tri.map(|p| pose.inverse_transform_point(p));
    if local.iter().any(|p| p.y.abs() > half_height) {
        return None;
    }
    let (d, Some((k, t))) = distance_to_origin_2d(local.map(|p| [p.x, p.z])) else {
        return None;
    };
    if d < radius || d <= DEGENERATE_LENGTH {
        return None;
    }
    let q = local[k] + (local[(k + 1) % 3] - local[k]) * t;
    let radial = Vector::new(q.x, 0.0, q.z) / d;
    Some(TriangleContact {
        point: tri[k] + (tri[(k + 1) % 3] - tri[k]) * t,
        normal: pose.rotation * radial,
        distance: d - radius,
    })
}

/// Barycentric weights of `p` (on the triangle, m) in `tri`, clamped to the triangle.
pub(super) fn barycentric(p: Vector, tri: [Vector; 3]) -> [Real; 3] {
    let (e1, e2, d) = (tri[1] - tri[0], tri[2] - tri[0], p - tri[0]);
    let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = a * c - b * b;
    if det <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let (u, w) = (e1.dot(d), e2.dot(d));
    let w1 = ((c * u - b * w) / det).clamp(0.0, 1.0);
    let w2 = ((a * w - b * u) / det).clamp(0.0, 1.0 - w1);
    [1.0 - w1 - w2, w1, w2]
}

impl Obstacles {
    /// Face query for the adaptivity criteria: the obstacle (ground excluded: a plane meets a face
    /// first at a vertex) closest to the triangle `tri` (world, m) among those nearer than `band`
    /// (m): the triangle's point of contact and the obstacle's outward unit normal there; `None`
    /// when none is that near.
    pub fn face_touch(&self, tri: [Vec3; 3], band: Real) -> Option<super::EdgeHit> {
        let tri = tri.map(to_glam);
        let (lo, hi) = bounds(tri);
        let mut best: Option<(Real, super::EdgeHit)> = None;
        for (k, ob) in self.obstacles.iter().enumerate() {
            if matches!(ob.geometry(), Geometry::Ground(_)) || !ob.overlaps(lo, hi, band) {
                continue;
            }
            let Some(c) = ob.triangle_contact(tri, band) else {
                continue;
            };
            if best.as_ref().is_none_or(|(d, _)| c.distance < *d) {
                let hit = super::EdgeHit {
                    obstacle: k,
                    point: to_na(c.point),
                    normal: to_na(c.normal),
                };
                best = Some((c.distance, hit));
            }
        }
        best.map(|(_, hit)| hit)
    }

    /// Face pass after [`Obstacles::respond`] (when the obstacles were built with
    /// `ContactParams::faces`; otherwise nothing): for each face of `faces` (vertex indices into
    /// `x`, world positions in m) with a movable vertex, and each obstacle but the ground (a
    /// plane meets a face first at a vertex), the deepest contact closer than the margin moves
    /// the face's contact point out to the margin along the obstacle's normal and removes its
    /// inward normal velocity, with Coulomb friction as for vertices (`mu` the mean of the
    /// cloth's and the obstacle's). Both changes are spread over the vertices as
    /// `w_k inv_mass_k / sum_j w_j^2 inv_mass_j` times the change at the point (`w` its
    /// barycentric weights), so the point moves exactly as asked and pinned vertices never move.
    /// Up to [`FACE_SWEEPS`] sweeps, until one moves nothing.
    ///
    /// Swept test, with `x_start` (the positions at the step's start): a face clear of an
    /// obstacle at the start that ends the step through it, with the obstacle's normal turned by
    /// more than 45 degrees from the start's (a thin feature passed between its vertices: the
    /// shortest way out is then sideways or through), is not pushed but moved back along its
    /// vertices' paths to just before the obstacle (the time of impact, by bisection), and loses
    /// its inward velocity along the start's normal.
    #[allow(clippy::too_many_arguments)]
    pub fn respond_faces(
        &self,
        faces: &[[usize; 3]],
        x_start: Option<&[Vec3]>,
        x: &mut [Vec3],
        v: &mut [Vec3],
        inv_mass: &[Real],
        cloth_mu: Real,
        scratch: &mut FaceScratch,
    ) -> FaceContactStats {
        let mut stats = FaceContactStats::default();
        if !self.faces {
            return stats;
        }
        let margin = self.margin;
        // The first sweep visits every face; later ones only the faces the previous one moved
        // (a face pushed out moves its vertices outward, seldom a neighbour inward).
        let FaceScratch { active, next } = scratch;
        active.clear();
        active.extend(0..faces.len());
        next.clear();
        next.reserve(faces.len());
        for _ in 0..FACE_SWEEPS {
            next.clear();
            for &k in active.iter() {
                let f = faces[k];
                if self.resolve_face(f, x_start, x, v, inv_mass, cloth_mu, margin) {
                    next.push(k);
                }
            }
            if next.is_empty() {
                break;
            }
            stats.contacts += next.len();
            stats.sweeps += 1;
            std::mem::swap(active, next);
        }
        stats
    }

    /// One face against every obstacle but the ground; true when a contact moved it.
    #[allow(clippy::too_many_arguments)]
    fn resolve_face(
        &self,
        f: [usize; 3],
        x_start: Option<&[Vec3]>,
        x: &mut [Vec3],
        v: &mut [Vec3],
        inv_mass: &[Real],
        cloth_mu: Real,
        margin: Real,
    ) -> bool {
        let inv = f.map(|i| inv_mass[i]);
        if inv.iter().all(|&m| m <= 0.0) {
            return false;
        }
        let mut moved = false;
        for ob in &self.obstacles {
            if matches!(ob.geometry(), Geometry::Ground(_)) {
                continue;
            }
            let tri = f.map(|i| to_glam(x[i]));
            let (lo, hi) = bounds(tri);
            if !ob.overlaps(lo, hi, margin) {
                continue;
            }
            let Some(c) = ob.triangle_contact(tri, margin - MARGIN_SLACK) else {
                continue;
            };
            let mu = 0.5 * (cloth_mu + ob.friction);
            if let Some(x0) = x_start.filter(|_| c.distance < 0.0) {
                // The path relative to the obstacle (a moving one carries the start along).
                let start = f.map(|i| ob.path_start(to_glam(x0[i])));
                if let Some(n0) = crossed(ob, start, tri, c.normal, margin) {
                    let s = time_of_impact(ob, start, tri, margin);
                    for k in (0..3).filter(|&k| inv[k] > 0.0) {
                        let p = start[k] + (tri[k] - start[k]) * s;
                        x[f[k]] = to_na(p);
                        v[f[k]] = to_na(ob.collide(to_glam(v[f[k]]), p, n0, 0.0, mu));
                    }
                    moved = true;
                    continue;
                }
            }
            let w = barycentric(c.point, tri);
            let s: Real = (0..3).map(|k| w[k] * w[k] * inv[k]).sum();
            if s <= 0.0 {
                continue;
            }
            let push = c.normal * (margin - c.distance);
            let velocity: Vector = (0..3).map(|k| to_glam(v[f[k]]) * w[k]).sum();
            let dv = ob.collide(velocity, c.point, c.normal, 0.0, mu) - velocity;
            for k in 0..3 {
                let share = w[k] * inv[k] / s;
                x[f[k]] += to_na(push * share);
                v[f[k]] += to_na(dv * share);
            }
            moved = true;
        }
        moved
    }

    /// The deepest point of any obstacle inside the cloth surface (m): over the triangles `faces`
    /// (vertex indices into `x`, world positions in m) and the obstacles whose bounding box meets
    /// a triangle's, the largest depth by which an obstacle pokes through a triangle; 0 when none
    /// does. Unlike the vertex figure, it sees obstacles through faces between outside vertices.
    pub fn surface_penetration(
        &self,
        x: &[Vec3],
        faces: impl IntoIterator<Item = [usize; 3]>,
    ) -> Real {
        let mut deepest: Real = 0.0;
        for f in faces {
            let tri = f.map(|i| to_glam(x[i]));
            let (lo, hi) = bounds(tri);
            for ob in &self.obstacles {
                if !ob.overlaps(lo, hi, 0.0) {
                    continue;
                }
                if let Some(c) = ob.triangle_contact(tri, 0.0) {
                    deepest = deepest.max(-c.distance);
                }
            }
        }
        deepest
    }
}

#[cfg(test)]
#[path = "faces_tests.rs"]
mod tests;
