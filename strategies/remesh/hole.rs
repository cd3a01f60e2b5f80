//! The rest-space mesher of a hole (MODEL.md §8.2 step 6): a constrained Delaunay triangulation
//! (spade) of the hole's border, seeded with a triangular lattice at the target spacing, refined to
//! a maximum area and a minimum angle without splitting the border, then Laplacian smoothing of the
//! new interior vertices.
//!
//! The lattice seeding stands in for the source's quadtree guide: spade's refinement with
//! `keep_constraint_edges` may add no vertex next to long constraint edges (DEPENDENCIES.md), so
//! the interior is seeded first and the refinement only repairs areas and angles.

use super::RemeshError;
use crate::math::{signed_area, Real, Vec2};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};
use std::collections::{BTreeSet, HashMap};

/// How to mesh one hole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct HoleParams {
    /// Target edge length of the new elements (m).
    pub spacing: Real,
    /// Minimum angle the refinement tries to keep (degrees).
    pub angle_limit_deg: Real,
    /// Refinement area limit as a multiple of the equilateral triangle of side `spacing`.
    pub area_slack: Real,
    /// Lattice seeds closer than `seed_clearance * max(spacing, segment length)` to a border
    /// segment, or than `seed_clearance * spacing` to a fixed point, are dropped (room for a
    /// well-shaped triangle on every border edge, which the mesher may not split).
    pub seed_clearance: Real,
    /// Laplacian smoothing passes over the new interior vertices.
    pub smoothing_passes: usize,
    /// Budget of vertices the refinement may add (seeds not included).
    pub max_refinement_vertices: usize,
}

/// A meshed hole: the fixed points first (same indices as the input), then the new interior
/// points; counter-clockwise triangles.
#[derive(Clone, Debug)]
pub(super) struct HoleMesh {
    /// Rest positions (m).
    pub points: Vec<Vec2>,
    /// Triangles as indices into `points`.
    pub triangles: Vec<[usize; 3]>,
}

/// The hole mesher of one region's attempts. It remembers its last meshing when spade's
/// refinement added no vertex to it: asked again with the same fixed points, border and seeds,
/// and an area limit no triangle's area lies between (spade asks of each triangle only whether
/// its area exceeds the limit and whether it is skinny), the refinement would do what it did,
/// nothing, so the last mesh is returned without meshing (a region that cannot be simplified is
/// asked up to `max_attempts` times, each coarser, its border alone triangulated each time).
#[derive(Default)]
pub(super) struct HoleMesher {
    last: Option<Unrefined>,
}

/// A meshing to which the refinement added no vertex, and what it was made from.
struct Unrefined {
    /// The parameters but the spacing (which acts through the seeds and `max_area`).
    params: HoleParams,
    fixed: Vec<Vec2>,
    constraints: Vec<[usize; 2]>,
    seeds: Vec<Vec2>,
    max_area: Real,
    /// spade's area of every triangle the refinement weighed (the faces it did not exclude).
    areas: Vec<Real>,
    mesh: HoleMesh,
}

impl Unrefined {
    /// True when meshing this input under `max_area` would give `self.mesh` again.
    fn repeats(
        &self,
        params: &HoleParams,
        fixed: &[Vec2],
        constraints: &[[usize; 2]],
        seeds: &[Vec2],
        max_area: Real,
    ) -> bool {
        self.params == *params
            && same_points(&self.fixed, fixed)
            && self.constraints == constraints
            && same_points(&self.seeds, seeds)
            && self
                .areas
                .iter()
                .all(|&a| (a > self.max_area) == (a > max_area))
    }
}

/// `p` with its spacing set to zero, to compare the rest.
fn but_spacing(p: &HoleParams) -> HoleParams {
    HoleParams { spacing: 0.0, ..*p }
}

/// Bit-for-bit equal point lists.
fn same_points(a: &[Vec2], b: &[Vec2]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits())
}

impl HoleMesher {
    /// Meshes the region enclosed by the directed border `constraints` (indices into `fixed`,
    /// the hole on their left; several loops allowed: a point is inside when its crossing parity
    /// is odd). Every fixed point must be used; new points lie strictly inside the hole. The same
    /// input always gets the same mesh, remembered or not.
    pub(super) fn mesh(
        &mut self,
        fixed: &[Vec2],
        constraints: &[[usize; 2]],
        hints: &[Vec2],
        p: &HoleParams,
    ) -> Result<HoleMesh, RemeshError> {
        let fail = |why: String| RemeshError::Mesher(why);
        if !(p.spacing.is_finite() && p.spacing > 0.0) {
            return Err(fail(format!(
                "target spacing {} is not positive",
                p.spacing
            )));
        }
        let seeds = lattice_seeds(fixed, constraints, hints, p);
        let max_area = p.area_slack * Real::sqrt(3.0) / 4.0 * p.spacing * p.spacing;
        if let Some(last) = &self.last {
            if last.repeats(&but_spacing(p), fixed, constraints, &seeds, max_area) {
                return Ok(last.mesh.clone());
            }
        }
        self.last = None;
        let mut points: Vec<Point2<Real>> = fixed.iter().map(|q| Point2::new(q.x, q.y)).collect();
        points.extend(seeds.iter().map(|q| Point2::new(q.x, q.y)));
        let n_input = points.len();
        // A border that crosses itself (a rest pattern overlapping itself, as an OBJ cloth's
        // may) is refused: spade's panicking loader aborted the run there.
        let mut crossing = None;
        let mut cdt = ConstrainedDelaunayTriangulation::<Point2<Real>>::try_bulk_load_cdt(
            points,
            constraints.to_vec(),
            |e| {
                crossing.get_or_insert(e);
            },
        )
        .map_err(|e| fail(format!("spade could not load the hole: {e:?}")))?;
        if let Some([a, b]) = crossing {
            return Err(fail(format!(
                "the hole's border crosses itself at its edge {a}-{b} (the rest pattern overlaps \
                 itself there)"
            )));
        }
        if cdt.num_vertices() != n_input {
            return Err(fail("duplicate points in the hole border".into()));
        }
        let result = cdt.refine(
            RefinementParameters::new()
                .with_max_allowed_area(max_area)
                .with_angle_limit(AngleLimit::from_deg(p.angle_limit_deg))
                .with_max_additional_vertices(p.max_refinement_vertices)
                .keep_constraint_edges()
                .exclude_outer_faces(true),
        );
        let excluded: BTreeSet<usize> = result.excluded_faces.iter().map(|f| f.index()).collect();
        let kept = || {
            cdt.inner_faces()
                .filter(|f| !excluded.contains(&f.fix().index()))
        };
        let all: Vec<Vec2> = cdt
            .vertices()
            .map(|v| Vec2::new(v.position().x, v.position().y))
            .collect();
        let mut triangles: Vec<[usize; 3]> = kept()
            .map(|f| f.vertices().map(|v| v.fix().index()))
            .collect();
        // Compact: keep the fixed points, then the new points some triangle uses, in spade's order.
        let mut used = vec![false; all.len()];
        for t in &triangles {
            for &i in t {
                used[i] = true;
            }
        }
        if let Some(i) = (0..fixed.len()).find(|&i| !used[i]) {
            return Err(fail(format!(
                "border point {i} is outside every new triangle"
            )));
        }
        let mut map = vec![usize::MAX; all.len()];
        let mut out = Vec::with_capacity(all.len());
        for (i, q) in all.iter().enumerate() {
            if i < fixed.len() || used[i] {
                map[i] = out.len();
                out.push(if i < fixed.len() { fixed[i] } else { *q });
            }
        }
        for t in &mut triangles {
            *t = t.map(|i| map[i]);
        }
        let mut mesh = HoleMesh {
            points: out,
            triangles,
        };
        smooth(&mut mesh, fixed.len(), p.smoothing_passes);
        if cdt.num_vertices() == n_input {
            self.last = Some(Unrefined {
                params: but_spacing(p),
                fixed: fixed.to_vec(),
                constraints: constraints.to_vec(),
                seeds,
                max_area,
                areas: kept().map(|f| f.area()).collect(),
                mesh: mesh.clone(),
            });
        }
        Ok(mesh)
    }
}

/// Hint points closer than this multiple of the spacing to the border are dropped.
const HINT_CLEARANCE: Real = 0.25;

/// Points of a triangular lattice of spacing `p.spacing` inside the hole, clear of the border and
/// of the fixed points, then the hints (e.g. the removed faces' centroids) that are inside, at
/// least `HINT_CLEARANCE` spacings from the border and clear of the points already chosen.
fn lattice_seeds(
    fixed: &[Vec2],
    constraints: &[[usize; 2]],
    hints: &[Vec2],
    p: &HoleParams,
) -> Vec<Vec2> {
    let (mut lo, mut hi) = (Vec2::repeat(Real::INFINITY), Vec2::repeat(-Real::INFINITY));
    for q in fixed {
        lo = lo.inf(q);
        hi = hi.sup(q);
    }
    let h = p.spacing;
    let clearance = p.seed_clearance * h;
    let row = h * Real::sqrt(3.0) / 2.0;
    let (nx, ny) = (((hi.x - lo.x) / h).ceil(), ((hi.y - lo.y) / row).ceil());
    // Keep the lattice bounded whatever the spacing (a refusal follows from the area budget).
    if nx.is_nan() || ny.is_nan() || nx * ny > 1.0e6 {
        return Vec::new();
    }
    let segments: Vec<(Vec2, Vec2)> = constraints
        .iter()
        .map(|&[a, b]| (fixed[a], fixed[b]))
        .collect();
    let mut near = PointGrid::new(clearance);
    for &f in fixed {
        near.insert(f);
    }
    let mut seeds = Vec::new();
    for j in 0..=ny as usize {
        let y = lo.y + j as Real * row;
        let shift = if j % 2 == 1 { 0.5 * h } else { 0.0 };
        for i in 0..=nx as usize {
            let q = Vec2::new(lo.x + shift + i as Real * h, y);
            if inside(q, &segments)
                && segments.iter().all(|&(a, b)| {
                    segment_distance(q, a, b) >= p.seed_clearance * h.max((b - a).norm())
                })
                && !near.any_within(q)
            {
                seeds.push(q);
            }
        }
    }
    for &q in &seeds {
        near.insert(q);
    }
    // Hints (refinement: the removed faces' centroids) fill what the lattice left empty.
    for &q in hints {
        let clear_of_border = segments
            .iter()
            .all(|&(a, b)| segment_distance(q, a, b) >= HINT_CLEARANCE * h);
        if inside(q, &segments) && clear_of_border && !near.any_within(q) {
            seeds.push(q);
            near.insert(q);
        }
    }
    seeds
}

/// Points bucketed in square cells of side `radius`, to ask whether any lies closer than `radius`
/// to a point in constant time (the 3 x 3 cells around it) instead of over every point: the
/// seeding of a hole of tens of thousands of vertices checked each hint against every point.
struct PointGrid {
    radius: Real,
    cells: HashMap<(i64, i64), Vec<Vec2>>,
}

impl PointGrid {
    /// An empty grid for the distance `radius` (m); with `radius` not positive (or not finite) no
    /// point is ever within it.
    fn new(radius: Real) -> Self {
        PointGrid {
            radius,
            cells: HashMap::new(),
        }
    }

    fn cell(&self, q: Vec2) -> (i64, i64) {
        // `as` saturates: a point beyond i64's range shares the extreme cell.
        (
            (q.x / self.radius).floor() as i64,
            (q.y / self.radius).floor() as i64,
        )
    }

    fn insert(&mut self, q: Vec2) {
        if self.radius > 0.0 && self.radius.is_finite() {
            let cell = self.cell(q);
            self.cells.entry(cell).or_default().push(q);
        }
    }

    /// True when a point of the grid lies strictly closer than `radius` to `q`.
    fn any_within(&self, q: Vec2) -> bool {
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return false;
        }
        let (i, j) = self.cell(q);
        (-1..=1).any(|di| {
            (-1..=1).any(|dj| {
                let key = (i.saturating_add(di), j.saturating_add(dj));
                self.cells
                    .get(&key)
                    .is_some_and(|pts| pts.iter().any(|f| (f - q).norm() < self.radius))
            })
        })
    }
}

/// Crossing-parity point-in-region test against the border segments.
fn inside(q: Vec2, segments: &[(Vec2, Vec2)]) -> bool {
    let mut odd = false;
    for &(a, b) in segments {
        if (a.y > q.y) != (b.y > q.y) {
            let x = a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if x > q.x {
                odd = !odd;
            }
        }
    }
    odd
}

/// Distance from `q` to the segment `a b` (m).
fn segment_distance(q: Vec2, a: Vec2, b: Vec2) -> Real {
    let d = b - a;
    let t = ((q - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (a + d * t - q).norm()
}

/// Smallest interior angle of a triangle (rad).
pub(super) fn min_angle(a: Vec2, b: Vec2, c: Vec2) -> Real {
    let (u, v) = smallest_angle_sides(a, b, c);
    u.perp(&v).abs().atan2(u.dot(&v))
}

/// Tangent of the smallest interior angle of a triangle of positive area (dimensionless): that
/// angle is at most 60 degrees, where the tangent grows with it, so comparing tangents compares
/// angles without an arctangent.
fn min_angle_tan(a: Vec2, b: Vec2, c: Vec2) -> Real {
    let (u, v) = smallest_angle_sides(a, b, c);
    u.perp(&v).abs() / u.dot(&v)
}

/// The two sides from the corner of a triangle's smallest angle.
fn smallest_angle_sides(a: Vec2, b: Vec2, c: Vec2) -> (Vec2, Vec2) {
    // The smallest angle faces the shortest side (law of sines).
    let (ab, bc, ca) = (
        (b - a).norm_squared(),
        (c - b).norm_squared(),
        (a - c).norm_squared(),
    );
    let (p, q, r) = if bc <= ab && bc <= ca {
        (a, b, c)
    } else if ca <= ab {
        (b, c, a)
    } else {
        (c, a, b)
    };
    (q - p, r - p)
}

/// Laplacian smoothing of the new points (index `>= n_fixed`): each moves to the mean of its
/// neighbours when every incident triangle stays clearly positive and the smallest angle around it
/// does not decrease, so smoothing never folds the mesh, never leaves the hole and never worsens
/// its worst angle.
fn smooth(mesh: &mut HoleMesh, n_fixed: usize, passes: usize) {
    let n = mesh.points.len();
    if n == n_fixed {
        return;
    }
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut neighbours: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    for (k, t) in mesh.triangles.iter().enumerate() {
        for j in 0..3 {
            incident[t[j]].push(k);
            neighbours[t[j]].insert(t[(j + 1) % 3]);
            neighbours[t[j]].insert(t[(j + 2) % 3]);
        }
    }
    // The tangent of the star's smallest angle, `None` when a triangle is not clearly positive.
    let star_quality = |pts: &[Vec2], v: usize, at: Vec2| -> Option<Real> {
        let mut worst = Real::INFINITY;
        for &k in &incident[v] {
            let [a, b, c] = mesh.triangles[k].map(|i| if i == v { at } else { pts[i] });
            let scale = (b - a).norm_squared().max((c - a).norm_squared());
            if signed_area(a, b, c) <= 1e-9 * scale {
                return None;
            }
            worst = worst.min(min_angle_tan(a, b, c));
        }
        Some(worst)
    };
    for _ in 0..passes {
        for (v, nb) in neighbours.iter().enumerate().skip(n_fixed) {
            let centre = nb.iter().map(|&w| mesh.points[w]).sum::<Vec2>() / nb.len() as Real;
            let before = star_quality(&mesh.points, v, mesh.points[v]).unwrap_or(0.0);
            if let Some(after) = star_quality(&mesh.points, v, centre) {
                if after >= before {
                    mesh.points[v] = centre;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The grid answers as the scan over every point does, at any radius and spread.
        #[test]
        fn the_point_grid_answers_as_the_scan_over_every_point(
            points in prop::collection::vec((-5.0..5.0f64, -5.0..5.0f64), 0..60),
            queries in prop::collection::vec((-6.0..6.0f64, -6.0..6.0f64), 1..30),
            radius in 0.01..3.0f64,
        ) {
            let points: Vec<Vec2> = points.into_iter().map(|(x, y)| Vec2::new(x, y)).collect();
            let mut grid = PointGrid::new(radius);
            for &p in &points {
                grid.insert(p);
            }
            for (x, y) in queries {
                let q = Vec2::new(x, y);
                let scan = points.iter().any(|p| (p - q).norm() < radius);
                prop_assert_eq!(grid.any_within(q), scan);
            }
        }

        /// A mesher that meshed a hole before gives, at every spacing of the retries (coarser and
        /// denser, the area limit crossing triangles' areas or not) and whatever the smoothing,
        /// the mesh a fresh mesher gives, point for point and triangle for triangle: remembering
        /// never changes a plan.
        #[test]
        fn a_remembered_mesh_is_the_mesh_a_fresh_mesher_makes(
            radii in prop::collection::vec(0.5..1.0f64, 3..9),
            hint in prop::option::of((-0.2..0.2f64, -0.2..0.2f64)),
            spacing in 0.3..3.0f64,
            factors in prop::collection::vec(
                (prop::sample::select(vec![1.0 / 1.2, 1.0, 1.2, 1.44]), 0usize..4), 1..8),
        ) {
            // A star-shaped polygon (counter-clockwise, the hole on its left).
            let n = radii.len();
            let fixed: Vec<Vec2> = radii
                .iter()
                .enumerate()
                .map(|(k, r)| {
                    let a = 2.0 * std::f64::consts::PI * k as Real / n as Real;
                    Vec2::new(r * a.cos(), r * a.sin())
                })
                .collect();
            let c: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
            let hints: Vec<Vec2> = hint.map(|(x, y)| Vec2::new(x, y)).into_iter().collect();
            let mut remembering = HoleMesher::default();
            let mut h = spacing;
            for (f, passes) in factors {
                h *= f;
                let p = HoleParams { smoothing_passes: passes, ..params(h) };
                let again = remembering.mesh(&fixed, &c, &hints, &p);
                let fresh = HoleMesher::default().mesh(&fixed, &c, &hints, &p);
                match (again, fresh) {
                    (Ok(a), Ok(b)) => {
                        prop_assert!(same_points(&a.points, &b.points));
                        prop_assert_eq!(a.triangles, b.triangles);
                    }
                    (a, b) => prop_assert_eq!(a.is_ok(), b.is_ok()),
                }
            }
        }
    }

    /// A border that crosses itself is refused, not a panic (an OBJ cloth whose pattern
    /// overlaps itself made spade panic under remesh).
    #[test]
    fn a_border_that_crosses_itself_is_refused() {
        let fixed = [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0)].map(|(x, y)| Vec2::new(x, y));
        let bow_tie = [[0, 1], [1, 2], [2, 3], [3, 0]];
        let e = HoleMesher::default()
            .mesh(&fixed, &bow_tie, &[], &params(0.5))
            .unwrap_err();
        assert!(e.to_string().contains("crosses itself"), "{e}");
    }

    fn params(spacing: Real) -> HoleParams {
        HoleParams {
            spacing,
            angle_limit_deg: 25.0,
            area_slack: 1.5,
            seed_clearance: 0.5,
            smoothing_passes: 3,
            max_refinement_vertices: 1000,
        }
    }

    fn area(m: &HoleMesh) -> Real {
        m.triangles
            .iter()
            .map(|t| signed_area(m.points[t[0]], m.points[t[1]], m.points[t[2]]))
            .sum()
    }

    /// The smallest angle (the one facing the shortest side) equals the smallest of the three
    /// angles, for acute, right, obtuse, needle and flat triangles in either orientation.
    #[test]
    fn min_angle_is_the_smallest_of_the_three_angles() {
        let angle = |p: Vec2, q: Vec2, r: Vec2| {
            let (u, v) = (q - p, r - p);
            u.perp(&v).abs().atan2(u.dot(&v))
        };
        let triangles = [
            [(0.0, 0.0), (1.0, 0.0), (0.3, 0.8)],
            [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)],
            [(0.0, 0.0), (3.0, 0.0), (0.2, 0.1)],
            [(0.0, 0.0), (1.0, 0.0), (0.5, 1e-7)],
            [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)],
            [(0.4, 2.0), (-1.0, 0.3), (5.0, -0.2)],
        ];
        for t in triangles {
            let [a, b, c] = t.map(|(x, y)| Vec2::new(x, y));
            for (p, q, r) in [(a, b, c), (c, b, a), (b, c, a)] {
                let brute = angle(p, q, r).min(angle(q, r, p)).min(angle(r, p, q));
                assert!((min_angle(p, q, r) - brute).abs() < 1e-12, "{t:?}");
                if signed_area(p, q, r) > 0.0 {
                    let tan = min_angle_tan(p, q, r);
                    assert!((tan.atan() - brute).abs() < 1e-12, "{t:?}: tan {tan}");
                }
            }
        }
    }

    #[test]
    fn square_hole_is_tiled_with_interior_points_and_good_angles() {
        // The unit square's border in 20 edges of 0.2 m, counter-clockwise.
        let mut fixed = Vec::new();
        for side in 0..4 {
            for k in 0..5 {
                let t = k as Real / 5.0;
                fixed.push(match side {
                    0 => Vec2::new(t, 0.0),
                    1 => Vec2::new(1.0, t),
                    2 => Vec2::new(1.0 - t, 1.0),
                    _ => Vec2::new(0.0, 1.0 - t),
                });
            }
        }
        let c: Vec<[usize; 2]> = (0..20).map(|i| [i, (i + 1) % 20]).collect();
        let m = HoleMesher::default()
            .mesh(&fixed, &c, &[], &params(0.2))
            .unwrap();
        // About 1 / (0.2² sqrt(3)/4) = 58 triangles, so around 10 interior points.
        assert!(m.points.len() >= 26, "{}", m.points.len());
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.points[i]);
            assert!(min_angle(a, b, c).to_degrees() > 25.0 - 1e-9);
        }
        assert!((area(&m) - 1.0).abs() < 1e-12);
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.points[i]);
            assert!(signed_area(a, b, c) > 0.0);
        }
    }

    #[test]
    fn annulus_around_a_kept_island_excludes_the_island() {
        // Outer square 0..3 counter-clockwise, inner square 1..2 clockwise (the island kept).
        let fixed = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(3.0, 0.0),
            Vec2::new(3.0, 3.0),
            Vec2::new(0.0, 3.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 2.0),
            Vec2::new(2.0, 2.0),
            Vec2::new(2.0, 1.0),
        ];
        let c = [
            [0, 1],
            [1, 2],
            [2, 3],
            [3, 0],
            [4, 5],
            [5, 6],
            [6, 7],
            [7, 4],
        ];
        let m = HoleMesher::default()
            .mesh(&fixed, &c, &[], &params(0.5))
            .unwrap();
        assert!((area(&m) - 8.0).abs() < 1e-12, "{}", area(&m));
    }
}
