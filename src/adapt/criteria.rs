//! The adaptivity criteria, shared by every adaptive strategy: the source's (MODEL.md §7) or the
//! sizing field (`super::sizing`), chosen by `adaptivity.criteria`.
//!
//! [`select_source`] evaluates every edge, in key order, against compression, collision and curvature
//! (an edge selected by one criterion is not tested by the next), applies the size limits and the
//! simplification hysteresis, then the smoothing rule (4.19). Strategies decide what to do with
//! the selection; what they know per edge (age since refinement, a depth-dependent curvature
//! limit) reaches the criteria through [`EdgeInfo`].

use super::{AdaptParams, Criteria};
use crate::cloth::Cloth;
use crate::collision::{Obstacles, TOUCH_MARGINS};
use crate::math::{Real, Vec3};
use crate::mesh::{EdgeFaces, EdgeKey, FaceId, Mesh};

/// Why an edge was selected for refinement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum RefineReason {
    /// `L / L_rest < compression_c`: buckling needs detail.
    Compression,
    /// The edge segment meets an obstacle away from a flat contact.
    Collision,
    /// The angle between the end vertex normals exceeds the (area-scaled) limit.
    Curvature,
    /// Neighbour of a refined edge much shorter than it (4.19).
    Smoothing,
    /// Sizing field: the velocity difference across the edge.
    Velocity,
    /// Sizing field: the obstacle's curvature under the edge's ends.
    Proximity,
    /// Sizing field: longer than `l_max`, the field's ceiling.
    Size,
}

/// The criteria's verdict on every edge.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Selection {
    /// Edges to refine, in key order, with the criterion that selected them.
    pub refine: Vec<(EdgeKey, RefineReason)>,
    /// Edges to simplify, in key order.
    pub simplify: Vec<EdgeKey>,
}

/// What a strategy knows about an edge that the criteria need.
pub trait EdgeInfo {
    /// Seconds since this edge (or the region it belongs to) was last refined; `None` when it
    /// never was (an edge of the initial mesh), which counts as old enough to simplify.
    fn age(&self, edge: EdgeKey) -> Option<Real>;

    /// The curvature refinement limit (rad) of an edge, given the area-scaled default of MODEL.md
    /// §7. Strategies with their own rule (1-to-4's depth factor) override it.
    fn refine_angle_limit(&self, edge: EdgeKey, area_scaled: Real) -> Real {
        let _ = edge;
        area_scaled
    }
}

/// An [`EdgeInfo`] for strategies that keep no per-edge history: every edge is old.
pub struct NoHistory;

impl EdgeInfo for NoHistory {
    fn age(&self, _edge: EdgeKey) -> Option<Real> {
        None
    }
}

/// Unit world normals of every vertex slot: the normalised sum of the unit normals of its faces
/// (zero for free slots and fully degenerate fans).
pub fn vertex_normals(cloth: &Cloth) -> Vec<Vec3> {
    let mesh = &cloth.mesh;
    let mut n = vec![Vec3::zeros(); mesh.vertex_slots()];
    for f in mesh.faces() {
        let fnormal = face_normal(cloth, f);
        for v in mesh.face(f) {
            n[v.0 as usize] += fnormal;
        }
    }
    for x in &mut n {
        let len = x.norm();
        if len > 0.0 {
            *x /= len;
        }
    }
    n
}

/// Unit world normal of a face (zero when degenerate).
pub fn face_normal(cloth: &Cloth, f: FaceId) -> Vec3 {
    let [a, b, c] = cloth.mesh.face(f).map(|v| cloth.x[v.0 as usize]);
    let n = (b - a).cross(&(c - a));
    let len = n.norm();
    if len > 0.0 {
        n / len
    } else {
        Vec3::zeros()
    }
}

/// Rest area (m²) of an equilateral triangle of side `l_max`: `A_max` of MODEL.md §7.
pub fn max_area(spec: &AdaptParams) -> Real {
    Real::sqrt(3.0) / 4.0 * spec.l_max * spec.l_max
}

/// The area-scaled curvature refinement limit (rad) of MODEL.md §7,
/// `theta_max (A_max / A_e)^exponent` with `theta_max = acos(cos_refine)`, capped at pi; its
/// constants taken once per pass.
pub struct AreaScaledAngle {
    theta_max: Real,
    max_area: Real,
    exponent: Real,
}

impl AreaScaledAngle {
    /// The limit under `spec`.
    pub fn new(spec: &AdaptParams) -> Self {
        AreaScaledAngle {
            theta_max: spec.cos_refine.clamp(-1.0, 1.0).acos(),
            max_area: max_area(spec),
            exponent: spec.curvature_exponent,
        }
    }

    /// The limit (rad) for faces of mean rest area `mean_face_area` (m²); pi for no area.
    pub fn at(&self, mean_face_area: Real) -> Real {
        if mean_face_area <= 0.0 {
            return std::f64::consts::PI;
        }
        (self.theta_max * (self.max_area / mean_face_area).powf(self.exponent))
            .min(std::f64::consts::PI)
    }
}

/// Mean rest area (m²) of the faces adjacent to an edge.
fn mean_adjacent_area(mesh: &Mesh, faces: &EdgeFaces) -> Real {
    let (sum, n) = faces.iter().fold((0.0, 0.0), |(s, n), f| {
        (s + mesh.face_rest_area(f), n + 1.0)
    });
    sum / n
}

/// Evaluates the scene's criteria on every edge: the source's (MODEL.md §7, [`select_source`])
/// or the sizing field ([`super::sizing::select_by_size`]), as `spec.criteria` says.
pub fn select(
    cloth: &Cloth,
    obstacles: &Obstacles,
    spec: &AdaptParams,
    info: &dyn EdgeInfo,
) -> Selection {
    match spec.criteria {
        Criteria::Source => select_source(cloth, obstacles, spec, info),
        Criteria::Sizing => super::sizing::select_by_size(cloth, obstacles, spec, info),
    }
}

/// Evaluates the source's criteria on every edge (MODEL.md §7).
pub fn select_source(
    cloth: &Cloth,
    obstacles: &Obstacles,
    spec: &AdaptParams,
    info: &dyn EdgeInfo,
) -> Selection {
    let mesh = &cloth.mesh;
    let normals = vertex_normals(cloth);
    let mut curved = CurvedContact::new(cloth, obstacles, spec);
    let area_scaled = AreaScaledAngle::new(spec);
    let mut refine = Vec::new();
    let mut simplify = Vec::new();
    for (e, faces) in mesh.edges() {
        let rest = mesh.rest_length(e.0, e.1);
        let (xa, xb) = (cloth.x[e.0 .0 as usize], cloth.x[e.1 .0 as usize]);
        let (na, nb) = (normals[e.0 .0 as usize], normals[e.1 .0 as usize]);
        let can_refine = rest >= spec.refine_min_length();
        // An edge too short to refine can only be simplified, which every criterion below must
        // allow: the cheap conditions first, the obstacle queries last (the same verdict).
        let may_simplify = || {
            rest <= spec.l_max
                && na.dot(&nb) > spec.cos_simplify
                && old_enough(info.age(e), spec.t_simplify)
        };
        // Known up front for an edge too short to refine, asked at the end otherwise.
        let simplifiable = (!can_refine).then(may_simplify);
        if simplifiable == Some(false) {
            continue;
        }
        // 1. Compression.
        if (xb - xa).norm() < spec.compression_c * rest {
            if can_refine {
                refine.push((e, RefineReason::Compression));
            }
            continue;
        }
        // 2. Collision, unless the contact is flat.
        if faces.iter().any(|f| curved.at(f)) {
            if can_refine {
                refine.push((e, RefineReason::Collision));
            }
            continue;
        }
        if let Some(hit) = obstacles.edge_hit(xa, xb) {
            let mean: Vec3 = faces.iter().map(|f| face_normal(cloth, f)).sum();
            // With face contact an edge rests on a curved obstacle as a tangent (it never crosses
            // it), so the contact is flat only where the obstacle is flat under the whole edge.
            let flat = mean.norm() > 0.0
                && (mean.normalize().dot(&hit.normal)).abs() >= spec.flat_contact_cos
                && (!obstacles.face_contact()
                    || [xa, xb].iter().all(|&p| {
                        obstacles.normal_of(hit.obstacle, p).dot(&hit.normal)
                            >= spec.flat_contact_cos
                    }));
            if !flat {
                if can_refine {
                    refine.push((e, RefineReason::Collision));
                }
                continue;
            }
        }
        // 3. Curvature.
        let angle = na.dot(&nb).clamp(-1.0, 1.0).acos();
        let limit = info.refine_angle_limit(e, area_scaled.at(mean_adjacent_area(mesh, faces)));
        if angle > limit {
            if can_refine {
                refine.push((e, RefineReason::Curvature));
            }
        } else if simplifiable.unwrap_or_else(may_simplify) {
            simplify.push(e);
        }
    }
    smooth(mesh, spec, info, &mut refine, &mut simplify);
    Selection { refine, simplify }
}

/// Per face slot, with face contact on: whether an obstacle comes within
/// [`TOUCH_MARGINS`] margins of the face where it is not flat under the face (its normal at the
/// contact differs from the face's, or from its normals at the face's vertices, by more than
/// `flat_contact_cos`). An obstacle tip under a large face (a bunny's ear) touches no edge; the
/// face's edges are then refined for collision. Always false in vertex mode. Each face is
/// queried when first asked about, once.
struct CurvedContact<'a> {
    cloth: &'a Cloth,
    obstacles: &'a Obstacles,
    spec: &'a AdaptParams,
    /// Per face slot: `None` until asked.
    known: Vec<Option<bool>>,
}

impl<'a> CurvedContact<'a> {
    fn new(cloth: &'a Cloth, obstacles: &'a Obstacles, spec: &'a AdaptParams) -> Self {
        CurvedContact {
            cloth,
            obstacles,
            spec,
            known: vec![None; cloth.mesh.face_slots()],
        }
    }

    /// Whether live face `f` is in curved contact.
    fn at(&mut self, f: FaceId) -> bool {
        let slot = &mut self.known[f.0 as usize];
        if let Some(curved) = *slot {
            return curved;
        }
        let curved = face_in_curved_contact(self.cloth, self.obstacles, self.spec, f);
        *slot = Some(curved);
        curved
    }
}

/// Whether live face `f` is in curved contact ([`CurvedContact`]).
fn face_in_curved_contact(
    cloth: &Cloth,
    obstacles: &Obstacles,
    spec: &AdaptParams,
    f: FaceId,
) -> bool {
    if !obstacles.face_contact() || obstacles.is_empty() {
        return false;
    }
    let band = TOUCH_MARGINS * obstacles.margin();
    let tri = cloth.mesh.face(f).map(|v| cloth.x[v.0 as usize]);
    let Some(hit) = obstacles.face_touch(tri, band) else {
        return false;
    };
    let agrees = |n: Vec3| n.dot(&hit.normal).abs() >= spec.flat_contact_cos;
    let flat = agrees(face_normal(cloth, f))
        && tri.iter().all(|&p| {
            obstacles.normal_of(hit.obstacle, p).dot(&hit.normal) >= spec.flat_contact_cos
        });
    !flat
}

/// True when an edge of the given age may be simplified under the hysteresis `t_simplify`.
pub(super) fn old_enough(age: Option<Real>, threshold: Real) -> bool {
    age.is_none_or(|a| a >= threshold)
}

/// The smoothing rule (4.19): a neighbour j (sharing a face) of a refine-selected edge i is
/// selected when `L_i / L_j < c2` (rest lengths, `L_j >= refine_min_length`); a neighbour of a
/// simplify-selected edge is selected for simplification when its age reached 10 % of
/// `t_simplify` and it is not selected for refinement. One pass; results stay in key order.
pub(super) fn smooth(
    mesh: &Mesh,
    spec: &AdaptParams,
    info: &dyn EdgeInfo,
    refine: &mut Vec<(EdgeKey, RefineReason)>,
    simplify: &mut Vec<EdgeKey>,
) {
    let neighbours = |e: EdgeKey| -> Vec<EdgeKey> {
        let mut out = Vec::new();
        if let Some(faces) = mesh.edge(e.0, e.1) {
            for f in faces.iter() {
                let vs = mesh.face(f);
                for k in 0..3 {
                    let n = EdgeKey::new(vs[k], vs[(k + 1) % 3]);
                    if n != e {
                        out.push(n);
                    }
                }
            }
        }
        out
    };
    let mut extra_refine = Vec::new();
    for &(e, _) in refine.iter() {
        let li = mesh.rest_length(e.0, e.1);
        for n in neighbours(e) {
            let lj = mesh.rest_length(n.0, n.1);
            if li / lj < spec.c2 && lj >= spec.refine_min_length() {
                extra_refine.push((n, RefineReason::Smoothing));
            }
        }
    }
    refine.extend(extra_refine);
    refine.sort();
    refine.dedup_by_key(|(e, _)| *e);
    let refined = |e: &EdgeKey| refine.binary_search_by_key(e, |(k, _)| *k).is_ok();
    let mut extra_simplify = Vec::new();
    for &e in simplify.iter() {
        for n in neighbours(e) {
            if !refined(&n)
                && mesh.rest_length(n.0, n.1) <= spec.l_max
                && old_enough(info.age(n), 0.1 * spec.t_simplify)
            {
                extra_simplify.push(n);
            }
        }
    }
    simplify.extend(extra_simplify);
    simplify.sort();
    simplify.dedup();
    simplify.retain(|e| !refined(e));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::{ContactParams, Obstacle, ObstacleShape};
    use crate::mesh::VertexId;
    use crate::testing;

    /// A flat `n` x `n` grid of 1 m x 1 m at height z (world = rest lifted).
    fn flat_cloth(n: usize, z: Real) -> Cloth {
        testing::flat_cloth(n, Vec3::new(0.0, 0.0, z))
    }

    fn spec() -> AdaptParams {
        AdaptParams {
            l_min: 0.05,
            l_max: 0.6,
            ..AdaptParams::default()
        }
    }

    fn no_obstacles() -> Obstacles {
        testing::obstacles(&[])
    }

    fn reason(sel: &Selection, e: EdgeKey) -> Option<RefineReason> {
        sel.refine.iter().find(|(k, _)| *k == e).map(|(_, r)| *r)
    }

    /// An age for every edge: `fixed` seconds.
    struct Aged(Real);
    impl EdgeInfo for Aged {
        fn age(&self, _: EdgeKey) -> Option<Real> {
            Some(self.0)
        }
    }

    #[test]
    fn flat_old_mesh_is_all_simplify_and_no_refine() {
        let cloth = flat_cloth(4, 0.0);
        let sel = select(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert!(sel.refine.is_empty());
        assert_eq!(sel.simplify.len(), cloth.mesh.edge_count());
    }

    #[test]
    fn compressed_edge_is_refined_for_compression() {
        let mut cloth = flat_cloth(4, 0.0);
        // Vertices 0 and 1 (rest distance 1/3): bring 1 towards 0 to 60 % of the rest length.
        cloth.x[1] = cloth.x[0] + (cloth.x[1] - cloth.x[0]) * 0.6;
        let e = EdgeKey::new(VertexId(0), VertexId(1));
        let sel = select(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert_eq!(reason(&sel, e), Some(RefineReason::Compression));
        // Below the compression threshold only: at 80 % it is not compressed enough.
        let mut cloth = flat_cloth(4, 0.0);
        cloth.x[1] = cloth.x[0] + (cloth.x[1] - cloth.x[0]) * 0.8;
        let sel = select(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert_ne!(reason(&sel, e), Some(RefineReason::Compression));
    }

    #[test]
    fn size_limit_blocks_refinement_of_short_edges() {
        let mut cloth = flat_cloth(4, 0.0);
        cloth.x[1] = cloth.x[0] + (cloth.x[1] - cloth.x[0]) * 0.5;
        let s = AdaptParams {
            l_min: 0.4, // above every rest length of a 4x4 grid's axis edges (1/3 m)
            ..spec()
        };
        let sel = select(&cloth, &no_obstacles(), &s, &NoHistory);
        let e = EdgeKey::new(VertexId(0), VertexId(1));
        assert_eq!(reason(&sel, e), None);
    }

    #[test]
    fn edge_crossing_an_obstacle_steeply_is_refined_but_flat_contact_is_not() {
        let sphere = Obstacle::new(ObstacleShape::Sphere {
            center: [0.5, 0.5, -0.25],
            radius: 0.3,
        });
        let obstacles = testing::obstacles(&[sphere]);
        // A flat cloth at z = 0 cuts the sphere's cap: edges near (0.5, 0.5) cross it where the
        // sphere's normal is tilted from the cloth's by more than the flat-contact angle at the
        // cap's rim.
        let cloth = flat_cloth(5, 0.0);
        let sel = select(&cloth, &obstacles, &spec(), &NoHistory);
        assert!(
            sel.refine
                .iter()
                .any(|(_, r)| *r == RefineReason::Collision),
            "{sel:?}"
        );
        // Lying on the ground (contact normal = face normal): flat contact, no collision refinement.
        let ground = Obstacle::new(ObstacleShape::Ground { height: 0.0 });
        let obstacles = testing::obstacles(&[ground]);
        let cloth = flat_cloth(5, -1e-4);
        let sel = select(&cloth, &obstacles, &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
    }

    #[test]
    fn a_face_over_an_obstacle_tip_is_refined_in_face_mode_only() {
        // A small sphere under the middle of a face of a 2x2 cloth (1 m square), its top 2 mm
        // below the cloth: 0.12 m and more from every edge, so no edge comes near it; only the
        // face does, and the sphere is curved under it.
        let tip = || {
            Obstacle::new(ObstacleShape::Sphere {
                center: [0.75, 0.5, -0.052],
                radius: 0.05,
            })
        };
        let cloth = flat_cloth(2, 0.0);
        let mode = |faces| ContactParams {
            faces,
            ..ContactParams::default()
        };
        let face_mode = mode(true);
        let obstacles = Obstacles::build(&[tip()], &face_mode).unwrap();
        let sel = select(&cloth, &obstacles, &spec(), &NoHistory);
        let touched = cloth
            .mesh
            .faces()
            .find(|&f| {
                let c: Vec3 = cloth
                    .mesh
                    .face(f)
                    .map(|v| cloth.x[v.0 as usize])
                    .iter()
                    .sum();
                (c / 3.0 - Vec3::new(0.75, 0.5, 0.0)).norm() < 0.3
            })
            .unwrap();
        let vs = cloth.mesh.face(touched);
        for k in 0..3 {
            let e = EdgeKey::new(vs[k], vs[(k + 1) % 3]);
            assert_eq!(reason(&sel, e), Some(RefineReason::Collision), "{sel:?}");
        }
        // Vertex mode: the source's edge criterion sees nothing.
        let vertex_only = Obstacles::build(&[tip()], &mode(false)).unwrap();
        let sel = select(&cloth, &vertex_only, &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
        // Face mode over a plane-like obstacle (a wide box top under the whole cloth): flat.
        let slab = Obstacle::new(ObstacleShape::Box {
            center: [0.5, 0.5, -1.002],
            half_extents: [2.0, 2.0, 1.0],
        });
        let obstacles = Obstacles::build(&[slab], &face_mode).unwrap();
        let sel = select(&cloth, &obstacles, &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
    }

    #[test]
    fn fold_is_refined_for_curvature_and_the_limit_grows_as_faces_shrink() {
        // Fold a 5x5 grid by 90 degrees along the line u = 0.5.
        let cloth = testing::folded_cloth(5);
        let sel = select(&cloth, &no_obstacles(), &spec(), &NoHistory);
        let fold: Vec<_> = sel
            .refine
            .iter()
            .filter(|(_, r)| *r == RefineReason::Curvature)
            .collect();
        assert!(!fold.is_empty(), "{sel:?}");
        // Every curvature-selected edge touches the fold line u = 0.5.
        for (e, _) in &fold {
            let (a, b) = (cloth.mesh.rest(e.0), cloth.mesh.rest(e.1));
            assert!(
                (a.x - 0.5).abs() < 0.3 || (b.x - 0.5).abs() < 0.3,
                "{e:?} far from the fold"
            );
        }
        // Smaller faces get a larger angle limit (harder to refine).
        let s = spec();
        let limit = AreaScaledAngle::new(&s);
        assert!(limit.at(0.001) > limit.at(0.01));
        assert!(limit.at(max_area(&s)) - s.cos_refine.acos() < 1e-12);
    }

    #[test]
    fn hysteresis_blocks_simplification_of_young_edges() {
        let cloth = flat_cloth(3, 0.0);
        let s = spec();
        let young = select(&cloth, &no_obstacles(), &s, &Aged(0.5 * s.t_simplify));
        assert!(young.simplify.is_empty());
        let old = select(&cloth, &no_obstacles(), &s, &Aged(s.t_simplify));
        assert!(!old.simplify.is_empty());
        // Longer than l_max: never simplified.
        let s = AdaptParams {
            l_max: 0.1,
            l_min: 0.05,
            ..spec()
        };
        let sel = select(&cloth, &no_obstacles(), &s, &NoHistory);
        assert!(sel.simplify.is_empty());
    }

    #[test]
    fn smoothing_selects_much_longer_neighbours() {
        // Refine-select a short edge by compression next to long ones: with c2 = 0.75 the
        // diagonal neighbours (ratio 1/sqrt(2) = 0.707 < 0.75) are selected, not with c2 = 0.7.
        let mut cloth = flat_cloth(4, 0.0);
        cloth.x[1] = cloth.x[0] + (cloth.x[1] - cloth.x[0]) * 0.6;
        let e = EdgeKey::new(VertexId(0), VertexId(1));
        let with = select(
            &cloth,
            &no_obstacles(),
            &AdaptParams { c2: 0.75, ..spec() },
            &NoHistory,
        );
        let smoothing: Vec<_> = with
            .refine
            .iter()
            .filter(|(_, r)| *r == RefineReason::Smoothing)
            .collect();
        assert!(!smoothing.is_empty(), "{with:?}");
        assert_eq!(reason(&with, e), Some(RefineReason::Compression));
        let without = select(
            &cloth,
            &no_obstacles(),
            &AdaptParams { c2: 0.70, ..spec() },
            &NoHistory,
        );
        assert!(without
            .refine
            .iter()
            .all(|(_, r)| *r != RefineReason::Smoothing));
        // Refined edges are never also simplified.
        for (k, _) in &with.refine {
            assert!(!with.simplify.contains(k));
        }
    }
}
