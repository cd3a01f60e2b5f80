//! One static obstacle: its parry3d shape and pose, contact parameters and bounding box, and the
//! three geometric queries the response needs (swept entry, signed-distance projection, AABB
//! overlap). The nalgebra <-> glam conversions of the module live here.

use super::collide_velocity;
use super::cylinder_ray::cylinder_entry;
use super::error::CollisionError;
use super::grid::DistanceGrid;
use super::mesh_faces::MeshObstacle;
use super::motion::{ObstacleMotion, RigidVelocity};
use super::params::{Obstacle, ObstacleShape};
use crate::math::{Real, Vec3, MAX_COORDINATE};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayCullingMode};
use parry3d_f64::shape::{
    Ball, Cuboid, Cylinder, FeatureId, HalfSpace, Shape, TriMesh, TriMeshFlags,
};
use std::path::Path;

/// Below this length (m) a projection offset is treated as zero and the normal comes from the
/// shape's own geometry instead.
const DEGENERATE_LENGTH: Real = 1e-12;

/// nalgebra -> glam.
#[inline]
pub(crate) fn to_glam(v: Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// glam -> nalgebra.
#[inline]
pub(crate) fn to_na(v: Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// The parry3d shape of an obstacle (in its local frame).
pub(crate) enum Geometry {
    /// Ground: solid below the plane through the pose origin, normal +z.
    Ground(HalfSpace),
    /// Sphere centred at the pose origin.
    Ball(Ball),
    /// Cylinder, local axis +y (the pose turns it to +z).
    Cylinder(Cylinder),
    /// Box centred at the pose origin.
    Cuboid(Cuboid),
    /// Closed, outward-oriented triangle mesh (vertices already in world coordinates).
    Mesh(Box<MeshObstacle>),
}

/// Closest surface point of an obstacle to a query point (world frame).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Projection {
    /// Closest point on the surface (m).
    pub point: Vector,
    /// Outward unit normal there (direction to push a point out along).
    pub normal: Vector,
    /// Signed distance of the query point (m), negative inside.
    pub distance: Real,
}

/// One obstacle, built: its parry3d shape, pose, contact parameters and bounds.
pub(crate) struct Solid {
    geometry: Geometry,
    /// The pose now (for a moving obstacle, at the end of the current step).
    pose: Pose,
    /// Friction coefficient of the surface.
    pub friction: Real,
    /// Restitution of the surface; 0 means "use the default".
    pub restitution: Real,
    /// World AABB of the raw shape (m); infinite for the ground.
    lo: Vector,
    hi: Vector,
    /// Coarse signed-distance grid (meshes only), covering the AABB grown by `grid_pad`, in the
    /// mesh's own frame.
    grid: Option<DistanceGrid>,
    /// How it moves; `None` for a still obstacle (no transform on any query).
    moving: Option<Box<Moving>>,
}

/// A moving obstacle's motion and its state over the current step `t0 -> t1`.
struct Moving {
    motion: ObstacleMotion,
    /// The pose as built (before the motion).
    built: Pose,
    /// `M(t1) M(t0)^-1`: carries a point fixed to the obstacle at `t0` to where it is at `t1`.
    carry: Pose,
    /// The velocity field at `t1`.
    velocity: RigidVelocity,
}

fn positive(index: usize, what: &str, value: Real) -> Result<Real, CollisionError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(CollisionError::BadShape {
            index,
            message: format!("{what} must be positive and finite, got {value}"),
        })
    }
}

fn finite3(index: usize, what: &str, v: [Real; 3]) -> Result<Vector, CollisionError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(Vector::new(v[0], v[1], v[2]))
    } else {
        Err(CollisionError::BadShape {
            index,
            message: format!("{what} must be finite, got {v:?}"),
        })
    }
}

impl Solid {
    /// Builds obstacle number `index` of the list. For meshes, a coarse signed-distance grid covering the AABB grown by `grid_pad` (m) is
    /// sampled as a mid phase (see `grid`).
    pub fn build(index: usize, spec: &Obstacle, grid_pad: Real) -> Result<Solid, CollisionError> {
        let bad = |message: String| CollisionError::BadShape { index, message };
        if let Some(why) = spec.motion.problem() {
            return Err(bad(format!("motion: {why}")));
        }
        let moving = match spec.shape {
            ObstacleShape::Ground { .. } if !spec.motion.is_still() => {
                return Err(bad("the ground cannot move".into()));
            }
            _ if spec.motion.is_still() => None,
            _ => Some(spec.motion.clone()),
        };
        let (geometry, pose) = match &spec.shape {
            ObstacleShape::Ground { height } => {
                if !height.is_finite() {
                    return Err(bad(format!("ground height must be finite, got {height}")));
                }
                (
                    Geometry::Ground(HalfSpace::new(Vector::Z)),
                    Pose::from_translation(Vector::new(0.0, 0.0, *height)),
                )
            }
            ObstacleShape::Sphere { center, radius } => (
                Geometry::Ball(Ball::new(positive(index, "sphere radius", *radius)?)),
                Pose::from_translation(finite3(index, "sphere center", *center)?),
            ),
            ObstacleShape::Cylinder {
                center,
                radius,
                height,
            } => {
                let radius = positive(index, "cylinder radius", *radius)?;
                let height = positive(index, "cylinder height", *height)?;
                // parry's cylinder axis is local +y; a quarter turn about x takes it to +z.
                let pose = Pose::new(
                    finite3(index, "cylinder center", *center)?,
                    Vector::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0),
                );
                (
                    Geometry::Cylinder(Cylinder::new(0.5 * height, radius)),
                    pose,
                )
            }
            ObstacleShape::Box {
                center,
                half_extents,
            } => {
                let mut h = [0.0; 3];
                for (k, slot) in h.iter_mut().enumerate() {
                    *slot = positive(index, "box half extent", half_extents[k])?;
                }
                (
                    Geometry::Cuboid(Cuboid::new(Vector::new(h[0], h[1], h[2]))),
                    Pose::from_translation(finite3(index, "box center", *center)?),
                )
            }
            ObstacleShape::Mesh {
                file,
                scale,
                translation,
            } => (
                mesh_geometry(index, file, *scale, *translation)?,
                Pose::identity(),
            ),
        };
        let (lo, hi) = match &geometry {
            Geometry::Ground(_) => (
                Vector::splat(Real::NEG_INFINITY),
                Vector::new(Real::INFINITY, Real::INFINITY, pose.translation.z),
            ),
            Geometry::Ball(s) => aabb_of(s, &pose),
            Geometry::Cylinder(s) => aabb_of(s, &pose),
            Geometry::Cuboid(s) => aabb_of(s, &pose),
            Geometry::Mesh(s) => aabb_of(&s.shape, &pose),
        };
        let mut obstacle = Solid {
            geometry,
            pose,
            friction: spec.friction,
            restitution: spec.restitution,
            lo,
            hi,
            grid: None,
            moving: None,
        };
        if matches!(obstacle.geometry, Geometry::Mesh(_)) {
            let pad = Vector::splat(grid_pad.max(0.0));
            obstacle.grid = Some(DistanceGrid::build(lo - pad, hi + pad, |c| {
                obstacle.project(c).distance
            }));
        }
        if let Some(motion) = moving {
            obstacle.moving = Some(Box::new(Moving {
                motion,
                built: obstacle.pose,
                carry: Pose::identity(),
                velocity: RigidVelocity::default(),
            }));
            obstacle.set_step(0.0, 0.0);
        }
        Ok(obstacle)
    }

    /// Whether the obstacle moves.
    #[inline]
    pub fn is_moving(&self) -> bool {
        self.moving.is_some()
    }

    /// Moves the obstacle to its pose at `t1` (s), for the step `t0 -> t1`: its pose, bounding
    /// box, the carry of [`Solid::path_start`] and the velocity of [`Solid::collide`]. Nothing
    /// for a still obstacle.
    pub fn set_step(&mut self, t0: Real, t1: Real) {
        let Some(m) = self.moving.as_mut() else {
            return;
        };
        let m1 = m.motion.pose(t1);
        m.carry = m1 * m.motion.pose(t0).inverse();
        m.velocity = m.motion.velocity(t1);
        self.pose = m1 * m.built;
        (self.lo, self.hi) = aabb_of(self.shape(), &self.pose);
    }

    /// Where a path starting at `p0` (m, at the start of the step) starts relative to the
    /// obstacle as it stands now: `p0` carried by the obstacle's motion over the step, so the
    /// segment to the path's end is the path in the obstacle's frame (exact for a translation;
    /// for a rotation, the chord of the relative arc). `p0` itself for a still obstacle.
    #[inline]
    pub fn path_start(&self, p0: Vector) -> Vector {
        match &self.moving {
            None => p0,
            Some(m) => m.carry.transform_point(p0),
        }
    }

    /// The response (4.16)-(4.18) of velocity `vel` (m/s) at the contact point `p` (m) with
    /// outward unit normal `n`, restitution `gamma` and friction `mu`, on the velocity relative to
    /// the obstacle's material at `p` (for a still obstacle, `vel` itself): friction drags the
    /// cloth along with a moving surface.
    #[inline]
    pub fn collide(&self, vel: Vector, p: Vector, n: Vector, gamma: Real, mu: Real) -> Vector {
        match &self.moving {
            None => collide_velocity(vel, n, gamma, mu),
            Some(_) => {
                let carried = self.surface_velocity(p);
                collide_velocity(vel - carried, n, gamma, mu) + carried
            }
        }
    }

    /// Velocity (m/s) of the obstacle's material at the world point `p` (m), at the end of the
    /// current step; zero for a still obstacle.
    #[inline]
    pub fn surface_velocity(&self, p: Vector) -> Vector {
        match &self.moving {
            None => Vector::ZERO,
            Some(m) => m.velocity.at(p),
        }
    }

    /// For a mesh: a world point (m) in the frame of its vertices and distance grid (the world
    /// as the scene places the mesh); the point itself for a still obstacle.
    #[inline]
    pub fn mesh_point(&self, p: Vector) -> Vector {
        match &self.moving {
            None => p,
            Some(_) => self.pose.inverse_transform_point(p),
        }
    }

    /// For a mesh: a point (m) of its frame in the world, the inverse of [`Solid::mesh_point`].
    #[inline]
    pub fn world_point(&self, p: Vector) -> Vector {
        match &self.moving {
            None => p,
            Some(_) => self.pose.transform_point(p),
        }
    }

    /// For a mesh: a direction of its frame in the world.
    #[inline]
    pub fn world_vector(&self, v: Vector) -> Vector {
        match &self.moving {
            None => v,
            Some(_) => self.pose.transform_vector(v),
        }
    }

    /// The parry3d shape, in the obstacle's local frame.
    pub(crate) fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The parry3d shape as a trait object (for parry's generic queries).
    pub(crate) fn shape(&self) -> &dyn Shape {
        match &self.geometry {
            Geometry::Ground(s) => s,
            Geometry::Ball(s) => s,
            Geometry::Cylinder(s) => s,
            Geometry::Cuboid(s) => s,
            Geometry::Mesh(s) => &s.shape,
        }
    }

    /// The pose taking the local frame to the world.
    pub(crate) fn pose(&self) -> &Pose {
        &self.pose
    }

    /// The triangle mesh, for mesh obstacles.
    #[cfg(test)]
    pub fn mesh(&self) -> Option<&TriMesh> {
        match &self.geometry {
            Geometry::Mesh(m) => Some(&m.shape),
            _ => None,
        }
    }

    /// Whether the box `[lo, hi]` (m) overlaps the obstacle's AABB grown by `pad` (m).
    #[inline]
    pub fn overlaps(&self, lo: Vector, hi: Vector, pad: Real) -> bool {
        lo.x <= self.hi.x + pad
            && lo.y <= self.hi.y + pad
            && lo.z <= self.hi.z + pad
            && hi.x >= self.lo.x - pad
            && hi.y >= self.lo.y - pad
            && hi.z >= self.lo.z - pad
    }

    /// First entry of the path `origin -> origin + dir` (the fraction `t` in (0, 1]) into the
    /// solid, with the outward unit normal there. A path that starts inside or on the surface,
    /// or only leaves the solid, has no entry (the projection handles it). Cylinders use the
    /// closed form of `cylinder_ray` (parry's is a GJK iteration).
    pub fn cast_entry(&self, origin: Vector, dir: Vector) -> Option<(Real, Vector)> {
        if dir.length_squared() == 0.0 {
            return None;
        }
        let ray = Ray::new(origin, dir);
        let hit = match &self.geometry {
            Geometry::Cylinder(s) => {
                let local_origin = self.pose.inverse_transform_point(origin);
                let local_dir = self.pose.inverse_transform_vector(dir);
                return cylinder_entry(s.half_height, s.radius, local_origin, local_dir, 1.0)
                    .map(|(t, n)| (t, self.pose.rotation * n));
            }
            Geometry::Mesh(m) => m.shape.cast_ray_with_culling(
                &self.pose,
                &ray,
                1.0,
                RayCullingMode::IgnoreBackfaces,
            ),
            Geometry::Ground(s) => s.cast_ray_and_get_normal(&self.pose, &ray, 1.0, true),
            Geometry::Ball(s) => s.cast_ray_and_get_normal(&self.pose, &ray, 1.0, true),
            Geometry::Cuboid(s) => s.cast_ray_and_get_normal(&self.pose, &ray, 1.0, true),
        }?;
        let n = hit.normal.try_normalize()?;
        (hit.time_of_impact > 0.0 && n.dot(dir) < 0.0).then_some((hit.time_of_impact, n))
    }

    /// Closest surface point to `p`, signed distance (negative inside) and outward normal.
    /// Exact, but for a mesh it may visit much of the BVH (about 2.5 us on the bunny).
    pub fn project(&self, p: Vector) -> Projection {
        let proj = match &self.geometry {
            Geometry::Ground(s) => s.project_point(&self.pose, p, false),
            Geometry::Ball(s) => s.project_point(&self.pose, p, false),
            Geometry::Cylinder(s) => s.project_point(&self.pose, p, false),
            Geometry::Cuboid(s) => s.project_point(&self.pose, p, false),
            Geometry::Mesh(s) => s.shape.project_point(&self.pose, p, false),
        };
        self.finish(p, proj)
    }

    /// The projection of `p` when its signed distance (m) is below `band` (inside, or outside
    /// but closer than `band`), else `None`. For a mesh this is the fast path: a point query
    /// bounded by `band`, and when nothing is that close, a ray along +z whose first hit is a
    /// back face tells an inside point (only then is the full projection computed).
    pub fn project_near(&self, p: Vector, band: Real) -> Option<Projection> {
        let proj = match &self.geometry {
            Geometry::Mesh(m) => {
                let grid = self.grid.as_ref();
                if let Some((low, high)) = grid.and_then(|g| g.bounds(self.mesh_point(p))) {
                    if low >= band {
                        return None;
                    }
                    if high < 0.0 {
                        let proj = self.project(p);
                        return (proj.distance < band).then_some(proj);
                    }
                }
                match m
                    .shape
                    .project_point_with_max_dist(&self.pose, p, false, band.max(0.0))
                {
                    Some(proj) => self.finish(p, proj),
                    None if self.mesh_inside(&m.shape, p) => self.project(p),
                    None => return None,
                }
            }
            _ => self.project(p),
        };
        (proj.distance < band).then_some(proj)
    }

    /// Whether `p` is certainly outside and at least `distance` (m) off the surface, from the
    /// mesh grid's bound (always `false` for analytic shapes, whose exact queries are cheap).
    #[inline]
    pub fn surely_clear(&self, p: Vector, distance: Real) -> bool {
        self.grid
            .as_ref()
            .and_then(|g| g.bounds(self.mesh_point(p)))
            .is_some_and(|(low, _)| low >= distance)
    }

    /// Depth (m) of `p` inside the raw surface, 0 outside.
    pub fn depth(&self, p: Vector) -> Real {
        if !self.overlaps(p, p, 0.0) {
            return 0.0;
        }
        self.project_near(p, 0.0)
            .map_or(0.0, |proj| (-proj.distance).max(0.0))
    }

    /// Inside test for a closed, outward-oriented mesh: the first surface met going up from `p`
    /// is seen from behind. (A ray grazing a silhouette edge may answer wrongly; callers confirm
    /// with the exact projection.)
    fn mesh_inside(&self, mesh: &TriMesh, p: Vector) -> bool {
        let length = (self.hi.z - p.z).max(0.0) + 1.0;
        let ray = Ray::new(p, Vector::Z);
        mesh.cast_ray_and_get_normal(&self.pose, &ray, length, false)
            .is_some_and(|hit| hit.feature == FeatureId::Face(1))
    }

    /// Signed distance and normal from a parry projection of `p`.
    fn finish(&self, p: Vector, proj: PointProjection) -> Projection {
        let offset = p - proj.point;
        let length = offset.length();
        if length > DEGENERATE_LENGTH {
            let sign = if proj.is_inside { -1.0 } else { 1.0 };
            Projection {
                point: proj.point,
                normal: offset * (sign / length),
                distance: sign * length,
            }
        } else {
            Projection {
                point: proj.point,
                normal: self.surface_normal(proj.point, proj.subshape),
                distance: 0.0,
            }
        }
    }

    /// Outward unit normal at a surface point `q` (world frame) from the shape itself, for
    /// query points lying on the surface (no offset to take a direction from).
    fn surface_normal(&self, q: Vector, subshape: u32) -> Vector {
        let local = self.pose.inverse_transform_point(q);
        let n = match &self.geometry {
            Geometry::Ground(s) => s.normal,
            Geometry::Ball(_) => local.try_normalize().unwrap_or(Vector::Z),
            Geometry::Cuboid(s) => {
                let r = local / s.half_extents;
                let a = r.abs();
                if a.x >= a.y && a.x >= a.z {
                    Vector::new(r.x.signum(), 0.0, 0.0)
                } else if a.y >= a.z {
                    Vector::new(0.0, r.y.signum(), 0.0)
                } else {
                    Vector::new(0.0, 0.0, r.z.signum())
                }
            }
            Geometry::Cylinder(s) => {
                let planar = (local.x * local.x + local.z * local.z).sqrt();
                if local.y.abs() / s.half_height >= planar / s.radius || planar == 0.0 {
                    Vector::new(0.0, local.y.signum(), 0.0)
                } else {
                    Vector::new(local.x / planar, 0.0, local.z / planar)
                }
            }
            Geometry::Mesh(m) => m.shape.triangle_normal(subshape).unwrap_or(Vector::Z),
        };
        self.pose.rotation * n
    }
}

/// The smallest size (m) of an obstacle mesh, its bounding box's longest side once scaled.
const MIN_MESH_SIZE: Real = 1e-6;

/// The triangle mesh of obstacle `index` read from `file`, scaled then translated (m).
fn mesh_geometry(
    index: usize,
    file: &Path,
    scale: Real,
    translation: [Real; 3],
) -> Result<Geometry, CollisionError> {
    let scale = positive(index, "mesh scale", scale)?;
    let translation = finite3(index, "mesh translation", translation)?;
    let obj =
        crate::io::read_obj(file).map_err(|source| CollisionError::MeshFile { index, source })?;
    if obj.faces.is_empty() {
        return Err(CollisionError::BadShape {
            index,
            message: format!(
                "mesh `{}`: no faces: an obstacle mesh needs at least one `f` line",
                file.display()
            ),
        });
    }
    let vertices: Vec<Vector> = obj
        .positions
        .iter()
        .map(|&[x, y, z]| Vector::new(x, y, z) * scale + translation)
        .collect();
    // parry's tree over the triangles recurses without end on a mesh of subnormal size.
    let across = Aabb::from_points_ref(&vertices).extents().max_element();
    if !(across.is_finite() && across >= MIN_MESH_SIZE) {
        return Err(CollisionError::BadShape {
            index,
            message: format!(
                "mesh `{}` scaled by {scale:e} is {across:.3e} m across: expected a finite size of at \
                 least {MIN_MESH_SIZE:e} m (check `scale`)",
                file.display()
            ),
        });
    }
    let farthest = vertices
        .iter()
        .fold(0.0, |m: Real, v| m.max(v.abs().max_element()));
    if farthest > MAX_COORDINATE {
        return Err(CollisionError::BadShape {
            index,
            message: format!(
                "mesh `{}` scaled by {scale:e} and moved by {translation:?} reaches {farthest:.3e} m \
                 from the origin: expected coordinates within ±{MAX_COORDINATE:e} m (check \
                 `scale` and `translation`)",
                file.display()
            ),
        });
    }
    let triangles: Vec<[u32; 3]> = obj.triangles().map(|(_, t)| t.map(|i| i as u32)).collect();
    let area = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        (b - a).cross(c - a).length()
    };
    if !triangles.iter().any(|t| area(t) > 0.0) {
        return Err(CollisionError::BadShape {
            index,
            message: format!(
                "mesh `{}`: no face has a positive area: an obstacle mesh needs at least one \
                 triangle that is not flat",
                file.display()
            ),
        });
    }
    let mesh = TriMesh::with_flags(
        vertices,
        triangles,
        TriMeshFlags::ORIENTED | TriMeshFlags::MERGE_DUPLICATE_VERTICES,
    )
    .map_err(|e| CollisionError::BadShape {
        index,
        message: format!("mesh `{}`: {e}", file.display()),
    })?;
    Ok(Geometry::Mesh(Box::new(MeshObstacle::new(mesh))))
}

fn aabb_of(shape: &dyn Shape, pose: &Pose) -> (Vector, Vector) {
    let aabb = shape.compute_aabb(pose);
    (aabb.mins, aabb.maxs)
}
