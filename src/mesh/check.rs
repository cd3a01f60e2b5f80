//! The conformity checker: every rule of MODEL.md §1, reporting which rule broke and where.
//!
//! [`Mesh::check`] runs after every frame of a run and after every operation of the property
//! tests, so it is near-linear: the structural rules use the incremental edge map and the
//! per-vertex face lists, the only geometric search (T-junctions) uses a k-d tree over rest
//! space. Cheap structural rules run first; the first broken rule is reported.
use super::point_tree::PointTree;
use super::{FaceId, Mesh, VertexId};
use crate::math::{Real, Vec2};
use petgraph::unionfind::UnionFind;

/// Smallest accepted ratio of a face's rest area to the square of its longest rest edge: a face at
/// or below it counts as degenerate or clockwise (dimensionless; an equilateral face has 0.43).
pub(crate) const MIN_AREA_RATIO: Real = 1e-12;

/// Relative tolerance of the pattern-area rule (dimensionless).
pub(crate) const AREA_REL_TOL: Real = 1e-9;

/// Relative distance (fraction of the edge's rest length) within which a vertex counts as lying
/// on an edge for the T-junction rule (dimensionless).
pub(crate) const ON_EDGE_REL_TOL: Real = 1e-9;

/// A conformity rule of MODEL.md §1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// Each edge has one or two adjacent triangles.
    EdgeFaceCount,
    /// A face names the same vertex twice.
    DegenerateFace,
    /// Two faces have the same vertex set.
    DuplicateFace,
    /// The two faces of an interior edge traverse it in the same direction.
    Orientation,
    /// A face is not counter-clockwise in rest space (rest area not clearly positive).
    PositiveArea,
    /// A live vertex lies in the interior of an edge in rest space (hanging node).
    TJunction,
    /// The faces around a vertex do not form one fan (one cycle inside, one open chain on the
    /// border).
    NonManifoldVertex,
    /// The mesh has more than one connected component.
    Disconnected,
    /// The faces' total rest area differs from [`Mesh::pattern_area`].
    AreaMismatch,
    /// A live vertex has no face.
    IsolatedVertex,
}

/// A broken conformity rule and where it broke.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("rule {rule:?} broken: {at}")]
pub struct ConformityError {
    /// The rule.
    pub rule: Rule,
    /// Where (vertex, edge or face ids and values), human readable.
    pub at: String,
}

fn broken(rule: Rule, at: String) -> Result<(), ConformityError> {
    Err(ConformityError { rule, at })
}

/// True when the face `vs` traverses `a -> b` (in its counter-clockwise order).
pub(crate) fn has_directed(vs: [VertexId; 3], a: VertexId, b: VertexId) -> bool {
    (0..3).any(|k| vs[k] == a && vs[(k + 1) % 3] == b)
}

/// True when the rest triangle `(a, b, c)` is counter-clockwise with a clearly positive area:
/// `area > MIN_AREA_RATIO * longest_edge²`. Also false for non-finite coordinates.
pub(crate) fn is_positive_triangle(a: Vec2, b: Vec2, c: Vec2) -> bool {
    let area = crate::math::signed_area(a, b, c);
    let l2 = (b - a)
        .norm_squared()
        .max((c - b).norm_squared())
        .max((a - c).norm_squared());
    area.is_finite() && l2.is_finite() && area > MIN_AREA_RATIO * l2
}

/// Fans up to this many wedges are checked by scanning them (no allocation); larger ones through
/// sorted copies.
const SMALL_FAN: usize = 16;

/// Checks that the wedges `x -> y` of the faces around one vertex (each face rotated so the vertex
/// comes first) form a single fan: one cycle (interior vertex) or one open chain (border vertex).
/// Assumes at most two faces per edge and consistent orientation; says why not otherwise.
/// O(n log n) in the number of wedges (a vertex of a 100000-face fan is checked at once).
pub(crate) fn single_fan<K: Copy + Ord>(wedges: &[(K, K)]) -> Result<(), String> {
    let n = wedges.len();
    if n == 0 {
        return Err("no faces".into());
    }
    if n <= SMALL_FAN {
        scanned_fan(wedges)
    } else {
        sorted_fan(wedges)
    }
}

/// [`single_fan`] by scanning the wedges: O(n²), no allocation.
fn scanned_fan<K: Copy + Ord>(wedges: &[(K, K)]) -> Result<(), String> {
    walk_fan(
        wedges,
        |k| wedges.iter().position(|w| w.0 == k),
        |k| wedges.iter().any(|w| w.1 == k),
    )
}

/// [`single_fan`] through sorted copies of the wedges: O(n log n).
fn sorted_fan<K: Copy + Ord>(wedges: &[(K, K)]) -> Result<(), String> {
    let n = wedges.len();
    // Wedge indices sorted by their first neighbour, and the sorted second neighbours.
    let mut by_first: Vec<usize> = (0..n).collect();
    by_first.sort_by_key(|&i| (wedges[i].0, i));
    let mut ends: Vec<K> = wedges.iter().map(|w| w.1).collect();
    ends.sort_unstable();
    walk_fan(
        wedges,
        |k| {
            let p = by_first.partition_point(|&i| wedges[i].0 < k);
            by_first.get(p).copied().filter(|&i| wedges[i].0 == k)
        },
        |k| ends.binary_search(&k).is_ok(),
    )
}

/// The walk of [`single_fan`], given `starting_at(k)`, the first wedge (smallest index) whose
/// first neighbour is `k`, and `is_end(k)`, whether `k` is some wedge's second neighbour.
fn walk_fan<K: Copy + Ord>(
    wedges: &[(K, K)],
    starting_at: impl Fn(K) -> Option<usize>,
    is_end: impl Fn(K) -> bool,
) -> Result<(), String> {
    let n = wedges.len();
    // A chain start: a wedge whose first neighbour ends no wedge.
    let mut starts = (0..n).filter(|&i| !is_end(wedges[i].0));
    let first = starts.next();
    let more = starts.count();
    if more > 0 {
        return Err(format!("{} separate fans of faces", more + 1));
    }
    let first = first.unwrap_or(0);
    let mut visited = 1;
    let mut cur = wedges[first].1;
    while visited < n {
        match starting_at(cur) {
            Some(i) if i != first => {
                visited += 1;
                cur = wedges[i].1;
            }
            _ => break,
        }
    }
    if visited != n {
        return Err(format!(
            "its {n} faces do not form one fan (one fan has {visited})"
        ));
    }
    Ok(())
}

impl Mesh {
    /// Checks every conformity rule of MODEL.md §1 and returns the first broken one, with the ids
    /// and values where it broke. Near-linear in the mesh size; never panics.
    ///
    /// Order (cheap structural rules first): [`Rule::DegenerateFace`], [`Rule::IsolatedVertex`],
    /// [`Rule::DuplicateFace`], [`Rule::EdgeFaceCount`], [`Rule::PositiveArea`],
    /// [`Rule::Orientation`], [`Rule::NonManifoldVertex`], [`Rule::Disconnected`],
    /// [`Rule::AreaMismatch`], [`Rule::TJunction`].
    pub fn check(&self) -> Result<(), ConformityError> {
        self.check_faces_structure()?;
        self.check_edges()?;
        self.check_fans()?;
        self.check_connected()?;
        self.check_area()?;
        self.check_t_junctions()
    }

    fn check_faces_structure(&self) -> Result<(), ConformityError> {
        for f in self.faces() {
            let [a, b, c] = self.face(f);
            if a == b || b == c || c == a {
                return broken(
                    Rule::DegenerateFace,
                    format!("face {} has vertices {:?}", f.0, [a.0, b.0, c.0]),
                );
            }
        }
        for v in self.vertices() {
            if self.vertex_faces(v).is_empty() {
                return broken(
                    Rule::IsolatedVertex,
                    format!(
                        "vertex {} at rest {:?} has no face",
                        v.0,
                        self.rest(v).as_slice()
                    ),
                );
            }
        }
        // Duplicate faces: the sorted vertex triples, sorted, side by side (O(F log F)).
        let mut sorted: Vec<([VertexId; 3], FaceId)> = self
            .faces()
            .map(|f| {
                let mut s = self.face(f);
                s.sort_unstable();
                (s, f)
            })
            .collect();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0].0 == w[1].0) {
            let ((s, g), (_, f)) = (w[0], w[1]);
            return broken(
                Rule::DuplicateFace,
                format!(
                    "faces {} and {} both have vertices {:?}",
                    g.0,
                    f.0,
                    [s[0].0, s[1].0, s[2].0]
                ),
            );
        }
        Ok(())
    }

    fn check_edges(&self) -> Result<(), ConformityError> {
        for (key, ef) in self.edges() {
            if ef.extra > 0 {
                return broken(
                    Rule::EdgeFaceCount,
                    format!(
                        "edge {}-{} has {} faces (faces {}, {:?}, ...)",
                        key.0 .0,
                        key.1 .0,
                        2 + ef.extra,
                        ef.first.0,
                        ef.second.map(|g| g.0)
                    ),
                );
            }
        }
        for f in self.faces() {
            let [a, b, c] = self.face(f);
            let (pa, pb, pc) = (self.rest(a), self.rest(b), self.rest(c));
            if !is_positive_triangle(pa, pb, pc) {
                return broken(
                    Rule::PositiveArea,
                    format!(
                        "face {} ({}, {}, {}) has rest area {:e} m² (clockwise or degenerate)",
                        f.0,
                        a.0,
                        b.0,
                        c.0,
                        crate::math::signed_area(pa, pb, pc)
                    ),
                );
            }
        }
        for (key, ef) in self.edges() {
            if let Some(g) = ef.second {
                let f = ef.first;
                if has_directed(self.face(f), key.0, key.1)
                    == has_directed(self.face(g), key.0, key.1)
                {
                    return broken(
                        Rule::Orientation,
                        format!(
                            "faces {} and {} traverse edge {}-{} in the same direction",
                            f.0, g.0, key.0 .0, key.1 .0
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    /// Each vertex's faces must form a single fan. Each face `(v, x, y)` (rotated so `v` comes
    /// first) is a wedge `x -> y`; with consistent orientation and at most two faces per edge, every
    /// neighbour starts and ends at most one wedge, so the wedges form chains and cycles.
    fn check_fans(&self) -> Result<(), ConformityError> {
        let mut wedges: Vec<(VertexId, VertexId)> = Vec::new();
        for v in self.vertices() {
            wedges.clear();
            for &f in self.vertex_faces(v) {
                let vs = self.face(f);
                let k = (0..3).find(|&k| vs[k] == v).unwrap_or(0);
                wedges.push((vs[(k + 1) % 3], vs[(k + 2) % 3]));
            }
            if let Err(why) = single_fan(&wedges) {
                return broken(Rule::NonManifoldVertex, format!("vertex {}: {why}", v.0));
            }
        }
        Ok(())
    }

    fn check_connected(&self) -> Result<(), ConformityError> {
        let mut uf = UnionFind::<u32>::new(self.vertex_slots());
        for f in self.faces() {
            let [a, b, c] = self.face(f);
            uf.union(a.0, b.0);
            uf.union(b.0, c.0);
        }
        let mut root = None;
        for v in self.vertices() {
            let r = uf.find_mut(v.0);
            match root {
                None => root = Some((v, r)),
                Some((v0, r0)) if r0 != r => {
                    return broken(
                        Rule::Disconnected,
                        format!("vertices {} and {} are in different components", v0.0, v.0),
                    );
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn check_area(&self) -> Result<(), ConformityError> {
        let total: Real = self.faces().map(|f| self.face_rest_area(f)).sum();
        let pattern = self.pattern_area();
        let error = (total - pattern).abs();
        if error.is_nan() || error > AREA_REL_TOL * pattern.abs() {
            return broken(
                Rule::AreaMismatch,
                format!("faces cover {total:e} m², the pattern area is {pattern:e} m²"),
            );
        }
        Ok(())
    }

    /// No live vertex strictly inside an edge: the live vertices go in a k-d tree
    /// ([`PointTree`]) and each edge visits only the vertices near its segment, so the rule costs
    /// about O(E log V) whatever the shape of the triangles.
    fn check_t_junctions(&self) -> Result<(), ConformityError> {
        let tree = PointTree::new(self.vertices().map(|v| (self.rest(v), v)).collect());
        let mut stack = Vec::new();
        for (key, _) in self.edges() {
            let (a, b) = (self.rest(key.0), self.rest(key.1));
            let d = b - a;
            let l2 = d.norm_squared();
            let tol = ON_EDGE_REL_TOL * l2.sqrt();
            let mut hit: Option<(VertexId, Real)> = None;
            tree.for_each_near_segment((a, b), tol, &mut stack, |p, w| {
                if w == key.0 || w == key.1 || hit.is_some_and(|h| h.0 < w) {
                    return;
                }
                let t = (p - a).dot(&d) / l2;
                if t <= ON_EDGE_REL_TOL || t >= 1.0 - ON_EDGE_REL_TOL {
                    return;
                }
                if (p - a - d * t).norm() <= tol {
                    hit = Some((w, t));
                }
            });
            if let Some((w, t)) = hit {
                return broken(
                    Rule::TJunction,
                    format!(
                        "vertex {} at rest {:?} lies inside edge {}-{} (at parameter {t:.6})",
                        w.0,
                        self.rest(w).as_slice(),
                        key.0 .0,
                        key.1 .0
                    ),
                );
            }
        }
        Ok(())
    }
}

/// Used by the tests of the mesh module to build broken meshes.
#[cfg(test)]
pub(crate) fn broken_mesh(rest: &[[Real; 2]], faces: &[[u32; 3]]) -> Mesh {
    let mut m = Mesh::default();
    for p in rest {
        m.push_vertex(Vec2::new(p[0], p[1]));
    }
    for f in faces {
        m.push_face([VertexId(f[0]), VertexId(f[1]), VertexId(f[2])]);
    }
    m.pattern_area = m.faces().map(|f: super::FaceId| m.face_rest_area(f)).sum();
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{disk, union_jack};

    proptest::proptest! {
        /// Both ways of checking a fan give the same answer, word for word, on any wedges (fans,
        /// chains, several fans, repeated neighbours).
        #[test]
        fn scanning_and_sorting_check_fans_alike(
            wedges in proptest::collection::vec((0u8..8, 0u8..8), 1..=SMALL_FAN),
        ) {
            proptest::prop_assert_eq!(scanned_fan(&wedges), sorted_fan(&wedges));
        }
    }

    fn rule_of(m: &Mesh) -> Rule {
        m.check().expect_err("mesh should be rejected").rule
    }

    #[test]
    fn accepts_union_jack_grids() {
        for (nx, ny) in [(2, 2), (3, 7), (17, 17), (65, 65)] {
            let m = union_jack(nx, ny, 1.0, 0.7);
            assert_eq!(m.check(), Ok(()), "{nx}x{ny}");
        }
    }

    #[test]
    fn accepts_disks() {
        for rings in [1, 2, 5, 12] {
            assert_eq!(disk(0.5, rings).check(), Ok(()), "{rings} rings");
        }
    }

    #[test]
    fn rejects_t_junction() {
        // A crack 0-1 whose lower side is split at 2: vertex 2 hangs on edge 0-1.
        let m = broken_mesh(
            &[
                [0., 0.],
                [2., 0.],
                [1., 0.],
                [1., 1.],
                [1., -1.],
                [-1., 0.],
                [3., 0.],
            ],
            &[
                [0, 1, 3],
                [0, 4, 2],
                [2, 4, 1],
                [0, 3, 5],
                [0, 5, 4],
                [1, 6, 3],
                [1, 4, 6],
            ],
        );
        let e = m.check().unwrap_err();
        assert_eq!(e.rule, Rule::TJunction, "{e}");
        assert!(e.at.contains("vertex 2"), "{}", e.at);
    }

    #[test]
    fn rejects_clockwise_triangle() {
        let m = broken_mesh(&[[0., 0.], [1., 0.], [0., 1.]], &[[0, 2, 1]]);
        assert_eq!(rule_of(&m), Rule::PositiveArea);
    }

    #[test]
    fn rejects_flipped_triangle_in_grid() {
        let mut m = union_jack(3, 3, 1.0, 1.0);
        let f = FaceId(3);
        let [a, b, c] = m.face(f);
        m.free_face(f);
        m.push_face([a, c, b]);
        assert_eq!(rule_of(&m), Rule::PositiveArea);
    }

    #[test]
    fn rejects_inconsistent_orientation() {
        // Both faces counter-clockwise, both traverse 0 -> 1 (they overlap).
        let m = broken_mesh(
            &[[0., 0.], [1., 0.], [0.5, 1.], [0.2, 0.5]],
            &[[0, 1, 2], [0, 1, 3]],
        );
        assert_eq!(rule_of(&m), Rule::Orientation);
    }

    #[test]
    fn rejects_degenerate_face() {
        let m = broken_mesh(&[[0., 0.], [1., 0.], [0., 1.]], &[[0, 1, 1], [0, 1, 2]]);
        assert_eq!(rule_of(&m), Rule::DegenerateFace);
    }

    #[test]
    fn rejects_duplicate_face() {
        let mut m = union_jack(3, 3, 1.0, 1.0);
        let vs = m.face(FaceId(4));
        m.push_face([vs[1], vs[2], vs[0]]);
        let e = m.check().unwrap_err();
        assert_eq!(e.rule, Rule::DuplicateFace, "{e}");
    }

    #[test]
    fn rejects_edge_with_three_faces() {
        let m = broken_mesh(
            &[[0., 0.], [1., 0.], [0.5, 1.], [0.5, -1.], [0.5, 2.]],
            &[[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        );
        assert_eq!(rule_of(&m), Rule::EdgeFaceCount);
    }

    #[test]
    fn rejects_bowtie() {
        let m = broken_mesh(
            &[[0., 0.], [1., 0.], [1., 1.], [-1., 0.], [-1., -1.]],
            &[[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(rule_of(&m), Rule::NonManifoldVertex);
    }

    #[test]
    fn rejects_disconnected_pieces() {
        let m = broken_mesh(
            &[[0., 0.], [1., 0.], [0., 1.], [3., 0.], [4., 0.], [3., 1.]],
            &[[0, 1, 2], [3, 4, 5]],
        );
        assert_eq!(rule_of(&m), Rule::Disconnected);
    }

    #[test]
    fn rejects_isolated_vertex() {
        let m = broken_mesh(&[[0., 0.], [1., 0.], [0., 1.], [5., 5.]], &[[0, 1, 2]]);
        assert_eq!(rule_of(&m), Rule::IsolatedVertex);
    }

    #[test]
    fn rejects_area_mismatch() {
        let mut m = union_jack(4, 4, 1.0, 1.0);
        m.pattern_area *= 1.0 + 1e-6;
        assert_eq!(rule_of(&m), Rule::AreaMismatch);
    }

    #[test]
    fn large_grid_checks_quickly() {
        let m = union_jack(65, 65, 1.0, 1.0);
        let t = std::time::Instant::now();
        for _ in 0..5 {
            m.check().unwrap();
        }
        // Generous bound for unoptimised test builds; release is a few ms per check.
        assert!(t.elapsed().as_secs_f64() < 5.0);
    }

    /// A long thin grid (5 x 100000 vertices: edges 0.25 m across, 1e-5 m along) was checked in
    /// minutes by the old uniform-grid search (issue 15): every edge visited a whole column.
    #[test]
    fn anisotropic_grid_checks_quickly() {
        let m = union_jack(5, 100_000, 1.0, 1.0);
        let t = std::time::Instant::now();
        m.check().unwrap();
        // Generous bound for unoptimised test builds; release takes well under a second.
        assert!(t.elapsed().as_secs_f64() < 20.0, "{:?}", t.elapsed());
    }

    /// A vertex shared by many faces (a fan of 20000 triangles) is checked without the quadratic
    /// scans of its wedges and faces.
    #[test]
    fn a_vertex_of_high_valence_checks_quickly() {
        let n = 20_000;
        let mut rest = vec![Vec2::new(0.0, 0.0)];
        for k in 0..=n {
            let a = std::f64::consts::PI * k as Real / n as Real;
            rest.push(Vec2::new(a.cos(), a.sin()));
        }
        let faces: Vec<[usize; 3]> = (0..n).map(|k| [0, k + 1, k + 2]).collect();
        let t = std::time::Instant::now();
        let m = Mesh::from_faces(rest, &faces).unwrap();
        assert_eq!(m.face_count(), n);
        assert!(t.elapsed().as_secs_f64() < 20.0, "{:?}", t.elapsed());
    }
}
