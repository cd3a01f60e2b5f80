//! The adaptivity criteria's edge query against the obstacles ([`Obstacles::edge_touch`]): how
//! near a cloth edge comes to each obstacle and with what normal, in closed form where the
//! geometry gives one ([`Solid::segment_closest`]), else by parry's contact (GJK).

use super::faces::{cylinder_side_contact, DEGENERATE_LENGTH};
use super::shape::{to_glam, to_na, Geometry, Solid};
use super::Obstacles;
use crate::math::{Real, Vec3};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::Segment;

impl Solid {
    /// Distance (m) from a point in the flat region `region` ([`Solid::flat_region`]; `local` in
    /// the solid's frame) to the solid: its height over that face's plane.
    fn flat_region_distance(&self, local: Vector, region: u8) -> Real {
        let axis = usize::from(region / 2);
        match self.geometry() {
            Geometry::Cuboid(s) => local[axis].abs() - s.half_extents[axis],
            Geometry::Cylinder(s) => local.y.abs() - s.half_height,
            _ => Real::INFINITY,
        }
    }

    /// The closest point of the segment `p -> q` (world, m) to the solid and its distance (m),
    /// in closed form where the geometry gives one: both ends in one flat region of a box or a
    /// cylinder (the distance is the height over the face's plane, linear along the segment, so
    /// least at an end: `p` on a tie), a cylinder's side ([`cylinder_side_contact`]), or a
    /// sphere the segment stays outside of. `None` elsewhere (left to parry's contact).
    pub(super) fn segment_closest(&self, p: Vector, q: Vector) -> Option<(Real, Vector)> {
        if let Some(region) = self.flat_region(p) {
            if self.flat_region(q) == Some(region) {
                let to = |x: Vector| {
                    let local = self.pose().inverse_transform_point(x);
                    self.flat_region_distance(local, region)
                };
                let (dp, dq) = (to(p), to(q));
                return Some(if dq < dp { (dq, q) } else { (dp, p) });
            }
        }
        match self.geometry() {
            Geometry::Cylinder(s) => {
                cylinder_side_contact(self.pose(), s.radius, s.half_height, [p, q, q])
                    .map(|c| (c.distance, c.point))
            }
            Geometry::Ball(ball) => {
                // The segment's closest point to the centre, when outside the ball.
                let (centre, pq) = (self.pose().translation, q - p);
                let length2 = pq.length_squared();
                let t = if length2 > 0.0 {
                    ((centre - p).dot(pq) / length2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let closest = p + pq * t;
                let distance = (closest - centre).length() - ball.radius;
                (distance > DEGENERATE_LENGTH).then_some((distance, closest))
            }
            _ => None,
        }
    }
}

impl Obstacles {
    /// The obstacle closest to the segment `a -> b` (m) among those nearer than `band` (m), by
    /// [`Solid::segment_closest`] where it has a closed form, else parry's contact between the
    /// segment and the obstacle (skipped where the obstacle's box or [`Solid::hull_clear`] says
    /// the segment is clear); the point and outward normal are the obstacle's projection of the
    /// segment's closest point.
    pub(super) fn edge_touch(&self, a: Vec3, b: Vec3, band: Real) -> Option<super::EdgeHit> {
        let (p, q) = (to_glam(a), to_glam(b));
        let segment = Segment::new(p, q);
        let (lo, hi) = (p.min(q), p.max(q));
        let mut best: Option<(Real, super::EdgeHit)> = None;
        for (k, ob) in self.obstacles.iter().enumerate() {
            if !ob.overlaps(lo, hi, band) || ob.hull_clear([p, q, q], band) {
                continue;
            }
            let (dist, point) = match ob.segment_closest(p, q) {
                Some((dist, point)) if dist <= band => (dist, point),
                Some(_) => continue,
                None => match parry3d_f64::query::contact(
                    &Pose::identity(),
                    &segment,
                    ob.pose(),
                    ob.shape(),
                    band,
                ) {
                    Ok(Some(c)) => (c.dist, c.point1),
                    _ => continue,
                },
            };
            if best.as_ref().is_none_or(|(d, _)| dist < *d) {
                let proj = ob.project(point);
                let hit = super::EdgeHit {
                    obstacle: k,
                    point: to_na(proj.point),
                    normal: to_na(proj.normal),
                };
                best = Some((dist, hit));
            }
        }
        best.map(|(_, hit)| hit)
    }
}
