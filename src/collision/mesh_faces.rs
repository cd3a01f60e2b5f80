//! A cloth triangle against a mesh obstacle: the tip test and the sunk-face samples of
//! [`super::faces`]'s mesh case, and the obstacle's per-vertex data they read.
//!
//! The tip test follows each obstacle vertex near the triangle along its unit pseudo-normal to
//! the triangle's plane. Its candidates are the vertices of the mesh triangles whose bounding box
//! meets the query box (the triangle's, grown by its longest edge). Two ways find them, with the
//! same set: parry's tree over the triangles, each vertex looked at once however many of the
//! returned triangles share it (a vertex of a closed mesh belongs to about six), for a box over
//! a small part of the mesh; and a scan of the vertices by the box of their triangles
//! ([`MeshObstacle::new`] takes those boxes once, with the unit normals) for a box over much of
//! it, as a coarse cloth's is. The answer does not depend on the order the vertices are looked
//! at in: the smallest distance wins, and between equal distances the smaller vertex index.

use super::faces::{bounds, TriangleContact, DEGENERATE_LENGTH};
use super::shape::Solid;
use crate::math::Real;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector;
use parry3d_f64::shape::TriMesh;
use std::cell::RefCell;

/// A query box over more than this share of the mesh's bounding box (by volume) scans the
/// vertices instead of walking the tree.
const SCAN_SHARE: Real = 0.125;

/// A mesh obstacle: parry's triangle mesh and, per vertex, what the tip test reads.
#[derive(Clone)]
pub(crate) struct MeshObstacle {
    /// The mesh, vertices in the obstacle's own frame (m).
    pub shape: TriMesh,
    /// Per vertex, its pseudo-normal normalised (`None` where it has no direction); `None` when
    /// the mesh has no pseudo-normals (the tip test then finds nothing).
    unit_normals: Option<Vec<Option<Vector>>>,
    /// Per triangle, its bounding box (m): the tree's leaf boxes, computed the same way.
    triangle_boxes: Vec<Aabb>,
    /// Per vertex, the union of its triangles' boxes (m).
    star_boxes: Vec<Aabb>,
    /// The triangles of vertex `v` are `star[star_start[v]..star_start[v + 1]]`.
    star_start: Vec<usize>,
    star: Vec<u32>,
}

impl MeshObstacle {
    /// The obstacle of `shape`, its unit pseudo-normals and the boxes of its triangles taken
    /// once.
    pub fn new(shape: TriMesh) -> Self {
        let unit_normals = shape.pseudo_normals().map(|normals| {
            normals
                .vertices_pseudo_normal
                .iter()
                .map(|n| n.try_normalize())
                .collect()
        });
        let vertices = shape.vertices();
        let triangle_boxes: Vec<Aabb> = shape
            .indices()
            .iter()
            .map(|t| {
                let (lo, hi) = bounds(t.map(|i| vertices[i as usize]));
                Aabb::new(lo, hi)
            })
            .collect();
        let mut star_start = vec![0; vertices.len() + 1];
        for t in shape.indices() {
            for &i in t {
                star_start[i as usize + 1] += 1;
            }
        }
        for v in 0..vertices.len() {
            star_start[v + 1] += star_start[v];
        }
        let mut next = star_start.clone();
        let mut star = vec![0; star_start[vertices.len()]];
        for (k, t) in shape.indices().iter().enumerate() {
            for &i in t {
                star[next[i as usize]] = k as u32;
                next[i as usize] += 1;
            }
        }
        let star_boxes = (0..vertices.len())
            .map(|v| {
                star[star_start[v]..star_start[v + 1]]
                    .iter()
                    .map(|&k| triangle_boxes[k as usize])
                    .reduce(|a, b| Aabb::new(a.mins.min(b.mins), a.maxs.max(b.maxs)))
                    .unwrap_or_else(|| Aabb::new(vertices[v], vertices[v]))
            })
            .collect();
        MeshObstacle {
            shape,
            unit_normals,
            triangle_boxes,
            star_boxes,
            star_start,
            star,
        }
    }

    /// Whether vertex `v` belongs to a triangle whose box meets `query` (boxes closed, as the
    /// tree's test).
    fn candidate(&self, v: usize, query: &Aabb) -> bool {
        overlap(&self.star_boxes[v], query)
            && self.star[self.star_start[v]..self.star_start[v + 1]]
                .iter()
                .any(|&k| overlap(&self.triangle_boxes[k as usize], query))
    }

    /// Calls `visit` with every vertex of the triangles whose box meets `query`, each once.
    fn for_each_candidate(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        let whole = self.shape.local_aabb();
        let share = whole.intersection(query).map_or(0.0, |inside| {
            inside.volume() / whole.volume().max(Real::MIN_POSITIVE)
        });
        if share > SCAN_SHARE {
            (0..self.star_boxes.len())
                .filter(|&v| self.candidate(v, query))
                .for_each(visit);
            return;
        }
        SEEN.with_borrow_mut(|seen| {
            seen.start(self.star_boxes.len());
            for part in self.shape.bvh().intersect_aabb(query) {
                for &v in &self.shape.indices()[part as usize] {
                    if seen.first(v as usize) {
                        visit(v as usize);
                    }
                }
            }
        });
    }
}

/// Whether the closed boxes `a` and `b` overlap (parry's tree test).
fn overlap(a: &Aabb, b: &Aabb) -> bool {
    a.mins.cmple(b.maxs).all() && a.maxs.cmpge(b.mins).all()
}

/// Marks of the mesh vertices one query has looked at: vertex `i` was seen when `mark[i]` is
/// the current `stamp` (a new stamp per query, so nothing is cleared between queries).
#[derive(Default)]
struct Seen {
    mark: Vec<u32>,
    stamp: u32,
}

impl Seen {
    /// Starts a query over `vertices` mesh vertices: none seen yet.
    fn start(&mut self, vertices: usize) {
        if self.mark.len() < vertices {
            self.mark.resize(vertices, 0);
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
    }

    /// True the first time `i` is asked about in this query.
    fn first(&mut self, i: usize) -> bool {
        let fresh = self.mark[i] != self.stamp;
        self.mark[i] = self.stamp;
        fresh
    }
}

thread_local! {
    /// Each thread's marks (queries run on any thread of the pool, one at a time per thread).
    static SEEN: RefCell<Seen> = RefCell::default();
}

/// The deepest mesh vertex under the triangle, followed along its outward pseudo-normal; vertices
/// more than the triangle's longest edge below it are not looked at, and a vertex counts as
/// through the triangle only when the triangle's point on its normal line is inside the solid (a
/// vertex on the far side of the mesh meets the triangle from behind, through the solid, with
/// the triangle's point outside). Of equally deep vertices, the smallest index. Worked in the
/// mesh's own frame (a moving mesh's triangle is brought there, the contact taken back).
pub(super) fn mesh_contact(
    solid: &Solid,
    mesh: &MeshObstacle,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    let normals = mesh.unit_normals.as_ref()?;
    let tip = Tip::new(solid, tri, band)?;
    let vertices = mesh.shape.vertices();
    let mut best = None;
    mesh.for_each_candidate(&tip.query_box(), |vi| {
        if let Some(np) = normals[vi] {
            tip.consider(solid, vi, vertices[vi], np, &mut best);
        }
    });
    tip.contact(solid, best)
}

/// One triangle's tip test, in the mesh's own frame.
struct Tip {
    tri: [Vector; 3],
    /// The triangle's normal, unnormalised, and normalised.
    n: Vector,
    unit: Vector,
    /// The triangle's longest edge (m): how far below it a vertex is looked at.
    reach: Real,
    band: Real,
}

/// The deepest vertex found so far and its index.
type Deepest = Option<(TriangleContact, usize)>;

impl Tip {
    /// The test of the world triangle `tri`; `None` when it is degenerate.
    fn new(solid: &Solid, tri: [Vector; 3], band: Real) -> Option<Tip> {
        let tri = tri.map(|p| solid.mesh_point(p));
        let [a, b, c] = tri;
        let n = (b - a).cross(c - a);
        let area2 = n.length();
        if area2 <= DEGENERATE_LENGTH * DEGENERATE_LENGTH {
            return None;
        }
        Some(Tip {
            tri,
            n,
            unit: n / area2,
            reach: (b - a).length().max((c - b).length()).max((a - c).length()),
            band,
        })
    }

    /// The triangle's box grown by its reach (or the band, if larger).
    fn query_box(&self) -> Aabb {
        let pad = Vector::splat(self.reach.max(self.band));
        let (lo, hi) = bounds(self.tri);
        Aabb::new(lo - pad, hi + pad)
    }

    /// Makes vertex `vi` at `p` (unit pseudo-normal `np`) the deepest when it goes through the
    /// triangle deeper than `best` (or as deep with a smaller index) and nearer than the band.
    fn consider(&self, solid: &Solid, vi: usize, p: Vector, np: Vector, best: &mut Deepest) {
        let facing = np.dot(self.unit);
        if facing.abs() <= 1e-9 {
            return;
        }
        // Along the normal line to the plane, then measured across the plane: how far the
        // triangle lies above (positive) or below the vertex.
        let s = (self.tri[0] - p).dot(self.unit) / facing;
        let distance = s * facing.abs();
        let deeper = best.is_none_or(|(best, bi)| {
            distance < best.distance || (distance == best.distance && vi < bi)
        });
        if distance >= self.band || s < -self.reach || !deeper {
            return;
        }
        let r = p + np * s;
        if inside_triangle(r, self.tri, self.n)
            && (s >= 0.0 || solid.depth(solid.world_point(r)) > 0.0)
        {
            let contact = TriangleContact {
                point: r,
                normal: self.unit * facing.signum(),
                distance,
            };
            *best = Some((contact, vi));
        }
    }

    /// The deepest vertex's contact, taken back to the world.
    fn contact(&self, solid: &Solid, best: Deepest) -> Option<TriangleContact> {
        best.map(|(c, _)| TriangleContact {
            point: solid.world_point(c.point),
            normal: solid.world_vector(c.normal),
            ..c
        })
    }
}

/// The deepest of the triangle's ten points at barycentric thirds (world, m) whose signed
/// distance to the mesh is below `band` (m), with its projection's outward normal; `None` when
/// none is.
pub(super) fn mesh_sample_contact(
    solid: &Solid,
    tri: [Vector; 3],
    band: Real,
) -> Option<TriangleContact> {
    const THIRDS: usize = 3;
    let mut best: Option<TriangleContact> = None;
    for i in 0..=THIRDS {
        for j in 0..=THIRDS - i {
            let k = THIRDS - i - j;
            let p = (tri[0] * i as Real + tri[1] * j as Real + tri[2] * k as Real) / THIRDS as Real;
            let Some(proj) = solid.project_near(p, band) else {
                continue;
            };
            if best.is_none_or(|best| proj.distance < best.distance) {
                best = Some(TriangleContact {
                    point: p,
                    normal: proj.normal,
                    distance: proj.distance,
                });
            }
        }
    }
    best
}

/// Whether `r`, in the plane of `tri` (normal `n`, unnormalised), lies in the closed triangle.
fn inside_triangle(r: Vector, tri: [Vector; 3], n: Vector) -> bool {
    (0..3).all(|k| {
        let (p, q) = (tri[k], tri[(k + 1) % 3]);
        (q - p).cross(r - p).dot(n) >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::shape::Geometry;
    use crate::collision::{Obstacle, ObstacleShape, Obstacles};
    use proptest::prelude::*;
    use std::sync::OnceLock;

    /// The bunny as the scenes load it.
    fn bunny() -> &'static Obstacles {
        static BUNNY: OnceLock<Obstacles> = OnceLock::new();
        BUNNY.get_or_init(|| {
            crate::testing::obstacles(&[Obstacle::new(ObstacleShape::Mesh {
                file: std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                    .join("scenes/meshes/bunny.obj"),
                scale: 1.0,
                translation: [0.0; 3],
            })])
        })
    }

    /// The corners of the mesh's bounding box (m).
    fn extent(mesh: &MeshObstacle) -> (Vector, Vector) {
        let v = mesh.shape.vertices();
        let lo = v
            .iter()
            .fold(Vector::splat(Real::INFINITY), |m, &p| m.min(p));
        let hi = v
            .iter()
            .fold(Vector::splat(Real::NEG_INFINITY), |m, &p| m.max(p));
        (lo, hi)
    }

    /// The tip test's candidates as they were found first: every vertex of every triangle the
    /// tree returns, its pseudo-normal normalised at each visit.
    fn every_visit(solid: &Solid, tri: [Vector; 3], band: Real) -> Option<TriangleContact> {
        let Geometry::Mesh(mesh) = solid.geometry() else {
            panic!("a mesh obstacle")
        };
        let mesh = &mesh.shape;
        let normals = mesh.pseudo_normals()?;
        let tip = Tip::new(solid, tri, band)?;
        let mut best = None;
        for part in mesh.bvh().intersect_aabb(&tip.query_box()) {
            for &vi in &mesh.indices()[part as usize] {
                let vi = vi as usize;
                if let Some(np) = normals.vertices_pseudo_normal[vi].try_normalize() {
                    tip.consider(solid, vi, mesh.vertices()[vi], np, &mut best);
                }
            }
        }
        tip.contact(solid, best)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Each vertex looked at once (by the tree for small triangles, by the scan for large
        /// ones), its normal taken once: the same contact, bit for bit, as every visit with the
        /// normal normalised each time, over triangles of 1 mm to 30 cm in and around the bunny,
        /// queried one after the other (the marks of one query must not hide a vertex from the
        /// next).
        #[test]
        fn looking_at_each_vertex_once_finds_the_same_contact(
            queries in prop::collection::vec(
                (prop::array::uniform3(prop::array::uniform3(-0.15..0.15f64)),
                 prop::array::uniform3(-1.0..1.0f64), 0.001..0.3f64, 0.0..0.05f64),
                1..6,
            )
        ) {
            let solid = &bunny().obstacles[0];
            let Geometry::Mesh(mesh) = solid.geometry() else { panic!("a mesh obstacle") };
            let (lo, hi) = extent(mesh);
            for (corners, centre, size, band) in queries {
                let middle = (lo + hi) * 0.5 + (hi - lo) * 0.6 * Vector::from(centre);
                let tri = corners.map(|c| middle + Vector::from(c) * (size / 0.15));
                let once = mesh_contact(solid, mesh, tri, band);
                prop_assert_eq!(once, every_visit(solid, tri, band));
            }
        }
    }

    #[test]
    fn a_triangle_through_the_bunny_finds_a_contact() {
        let solid = &bunny().obstacles[0];
        let Geometry::Mesh(mesh) = solid.geometry() else {
            panic!("a mesh obstacle")
        };
        let (lo, hi) = extent(mesh);
        let middle = (lo + hi) * 0.5;
        let tri = [
            middle + Vector::new(-0.3, -0.3, 0.0),
            middle + Vector::new(0.3, -0.3, 0.0),
            middle + Vector::new(0.0, 0.3, 0.0),
        ];
        let contact = mesh_contact(solid, mesh, tri, 0.01).expect("the bunny pokes through");
        assert!(contact.distance < 0.0, "{contact:?}");
        assert_eq!(Some(contact), every_visit(solid, tri, 0.01));
    }
}
