//! Material points: locating a rest point in the mesh (barycentric coordinates).
//!
//! A [`RestLocator`] buckets the faces' rest bounding boxes in a uniform grid (built in O(F)); it is
//! valid for one mesh version ([`RestLocator::is_current`]) and must be rebuilt after an edit.
//! Used by the material-point metrics (MODEL.md §1) and by the state transfer of re-meshed regions.
use super::grid::BucketGrid;
use super::{FaceId, Mesh};
use crate::math::{signed_area, Real, Vec2};

/// Distance (fraction of the pattern's bounding-box diagonal) within which a point outside every
/// face still snaps to the nearest face (dimensionless).
pub const SNAP_REL_TOL: Real = 1e-9;

/// Smallest barycentric weight still counted as inside a face (rounding on edges and vertices).
const INSIDE_WEIGHT_TOL: Real = -1e-12;

/// A rest point located in a face: the face and its barycentric weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Barycentric {
    /// The face containing the point.
    pub face: FaceId,
    /// Weights of the face's three vertices, in the order of [`Mesh::face`]; each in `[0, 1]`,
    /// summing to 1.
    pub weights: [f64; 3],
}

/// An acceleration structure over the faces' rest triangles, valid for one mesh version.
#[derive(Clone, Debug)]
pub struct RestLocator {
    version: u64,
    grid: BucketGrid<FaceId>,
    lo: Vec2,
    hi: Vec2,
    snap: Real,
}

impl RestLocator {
    /// Builds the locator for the current mesh in O(faces): a grid of cells the size of the mean
    /// face box (about one face per cell, long thin faces included), each face listed in the cells its rest bounding box (widened by the snapping
    /// distance) overlaps.
    pub fn new(mesh: &Mesh) -> Self {
        let mut lo = Vec2::repeat(Real::INFINITY);
        let mut hi = Vec2::repeat(Real::NEG_INFINITY);
        for f in mesh.faces() {
            for v in mesh.face(f) {
                lo = lo.inf(&mesh.rest(v));
                hi = hi.sup(&mesh.rest(v));
            }
        }
        if mesh.face_count() == 0 {
            lo = Vec2::zeros();
            hi = Vec2::zeros();
        }
        let snap = SNAP_REL_TOL * (hi - lo).norm();
        let entries: Vec<(Vec2, Vec2, FaceId)> = mesh
            .faces()
            .map(|f| {
                let [a, b, c] = mesh.face(f).map(|v| mesh.rest(v));
                let w = Vec2::repeat(snap);
                (a.inf(&b).inf(&c) - w, a.sup(&b).sup(&c) + w, f)
            })
            .collect();
        // Cells of the mean face box: about one face per cell, however thin the faces.
        let mean_box =
            entries.iter().map(|(a, b, _)| b - a).sum::<Vec2>() / entries.len().max(1) as Real;
        RestLocator {
            version: mesh.version(),
            grid: BucketGrid::new(lo, hi, mean_box, &entries),
            lo,
            hi,
            snap,
        }
    }

    /// True when the locator was built for the mesh's current version (no edit since).
    pub fn is_current(&self, mesh: &Mesh) -> bool {
        self.version == mesh.version()
    }

    /// The face containing rest point `p` (m) with its barycentric weights, or `None` outside the
    /// pattern. Points on edges and vertices are found (in the face of smallest id among the
    /// best-containing ones); a point outside every face by less than [`SNAP_REL_TOL`] times the
    /// pattern's bounding-box diagonal snaps to the nearest point of the nearest face. `mesh`
    /// must be the mesh the locator was built for ([`RestLocator::is_current`]).
    pub fn locate(&self, mesh: &Mesh, p: Vec2) -> Option<Barycentric> {
        debug_assert!(self.is_current(mesh), "RestLocator used on a changed mesh");
        let s = Vec2::repeat(self.snap);
        if !(p.x.is_finite() && p.y.is_finite())
            || p.x < self.lo.x - s.x
            || p.y < self.lo.y - s.y
            || p.x > self.hi.x + s.x
            || p.y > self.hi.y + s.y
        {
            return None;
        }
        let candidates = self.grid.at(p);
        let mut best: Option<(Real, Barycentric)> = None;
        for &f in candidates {
            if !mesh.is_face(f) {
                continue;
            }
            let w = weights(mesh, f, p);
            let min = w[0].min(w[1]).min(w[2]);
            if best.is_none_or(|(m, _)| min > m) {
                best = Some((
                    min,
                    Barycentric {
                        face: f,
                        weights: w,
                    },
                ));
            }
        }
        if let Some((min, mut b)) = best {
            if min >= INSIDE_WEIGHT_TOL {
                if min < 0.0 {
                    b.weights = normalised(b.weights.map(|x| x.max(0.0)));
                }
                return Some(b);
            }
        }
        // Snap: the nearest face within the snapping distance.
        let mut nearest: Option<(Real, FaceId, Vec2)> = None;
        for &f in candidates {
            if !mesh.is_face(f) {
                continue;
            }
            let [a, b, c] = mesh.face(f).map(|v| mesh.rest(v));
            let q = closest_on_triangle(p, a, b, c);
            let d = (q - p).norm();
            if d <= self.snap && nearest.is_none_or(|(m, _, _)| d < m) {
                nearest = Some((d, f, q));
            }
        }
        nearest.map(|(_, f, q)| Barycentric {
            face: f,
            weights: normalised(weights(mesh, f, q).map(|x| x.max(0.0))),
        })
    }
}

/// Barycentric weights of `p` in face `f` (may be negative outside).
fn weights(mesh: &Mesh, f: FaceId, p: Vec2) -> [Real; 3] {
    let [a, b, c] = mesh.face(f).map(|v| mesh.rest(v));
    let area = signed_area(a, b, c);
    [
        signed_area(p, b, c) / area,
        signed_area(a, p, c) / area,
        signed_area(a, b, p) / area,
    ]
}

fn normalised(w: [Real; 3]) -> [Real; 3] {
    let s = w[0] + w[1] + w[2];
    if s > 0.0 {
        w.map(|x| x / s)
    } else {
        [1.0 / 3.0; 3]
    }
}

fn closest_on_segment(p: Vec2, a: Vec2, b: Vec2) -> Vec2 {
    let d = b - a;
    let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    if t.is_finite() {
        a + d * t
    } else {
        a
    }
}

/// The closest point to `p` on the closed triangle `(a, b, c)` (counter-clockwise).
fn closest_on_triangle(p: Vec2, a: Vec2, b: Vec2, c: Vec2) -> Vec2 {
    if signed_area(a, b, p) >= 0.0 && signed_area(b, c, p) >= 0.0 && signed_area(c, a, p) >= 0.0 {
        return p;
    }
    [
        closest_on_segment(p, a, b),
        closest_on_segment(p, b, c),
        closest_on_segment(p, c, a),
    ]
    .into_iter()
    .min_by(|x, y| (x - p).norm_squared().total_cmp(&(y - p).norm_squared()))
    .unwrap_or(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{disk, union_jack};

    fn interpolate(mesh: &Mesh, b: &Barycentric) -> Vec2 {
        let vs = mesh.face(b.face);
        (0..3).map(|k| mesh.rest(vs[k]) * b.weights[k]).sum()
    }

    fn assert_weights_ok(b: &Barycentric) {
        assert!(b.weights.iter().all(|&w| (0.0..=1.0).contains(&w)), "{b:?}");
        assert!((b.weights.iter().sum::<Real>() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn finds_vertices_with_unit_weight() {
        let m = union_jack(5, 4, 1.0, 0.6);
        let loc = RestLocator::new(&m);
        for v in m.vertices() {
            let b = loc.locate(&m, m.rest(v)).expect("vertex found");
            assert_weights_ok(&b);
            let k = m
                .face(b.face)
                .iter()
                .position(|&w| w == v)
                .expect("face has the vertex");
            assert!((b.weights[k] - 1.0).abs() < 1e-12, "{v:?}: {b:?}");
        }
    }

    #[test]
    fn finds_edge_midpoints_and_centroids() {
        let m = disk(0.3, 4);
        let loc = RestLocator::new(&m);
        for (key, _) in m.edges() {
            let p = (m.rest(key.0) + m.rest(key.1)) / 2.0;
            let b = loc.locate(&m, p).expect("midpoint found");
            assert_weights_ok(&b);
            let vs = m.face(b.face);
            for (k, v) in vs.iter().enumerate() {
                let want = if *v == key.0 || *v == key.1 { 0.5 } else { 0.0 };
                assert!((b.weights[k] - want).abs() < 1e-9, "{key:?}: {b:?}");
            }
        }
        for f in m.faces() {
            let [a, b, c] = m.face(f).map(|v| m.rest(v));
            let found = loc.locate(&m, (a + b + c) / 3.0).expect("centroid found");
            assert_eq!(found.face, f);
            for w in found.weights {
                assert!((w - 1.0 / 3.0).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn interpolation_reproduces_random_points() {
        let m = union_jack(9, 9, 2.0, 1.0);
        let loc = RestLocator::new(&m);
        for i in 0..200 {
            let p = Vec2::new(
                (i as Real * 0.618).fract() * 2.0,
                (i as Real * 0.381).fract(),
            );
            let b = loc.locate(&m, p).expect("inside");
            assert_weights_ok(&b);
            assert!((interpolate(&m, &b) - p).norm() < 1e-12);
        }
    }

    #[test]
    fn outside_is_none_and_tiny_overshoot_snaps() {
        let m = union_jack(3, 3, 1.0, 1.0);
        let loc = RestLocator::new(&m);
        assert!(loc.locate(&m, Vec2::new(-0.1, 0.5)).is_none());
        assert!(loc.locate(&m, Vec2::new(0.5, 1.001)).is_none());
        assert!(loc.locate(&m, Vec2::new(Real::NAN, 0.5)).is_none());
        let b = loc
            .locate(&m, Vec2::new(0.3, 1.0 + 1e-11))
            .expect("snapped");
        assert_weights_ok(&b);
        assert!((interpolate(&m, &b) - Vec2::new(0.3, 1.0)).norm() < 1e-12);
        // Outside a disk's polygon, but inside its bounding box.
        let d = disk(1.0, 3);
        let loc = RestLocator::new(&d);
        assert!(loc.locate(&d, Vec2::new(0.02, 0.02)).is_none());
    }

    #[test]
    fn is_current_tracks_the_mesh_version() {
        let mut m = union_jack(3, 3, 1.0, 1.0);
        let loc = RestLocator::new(&m);
        assert!(loc.is_current(&m));
        m.push_vertex(Vec2::new(0.5, 0.5));
        assert!(!loc.is_current(&m));
    }
}
