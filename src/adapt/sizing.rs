//! The sizing field (MODEL.md §10.1; Narain, Samii & O'Brien 2012 in isotropic, per-edge form):
//! every edge gets a target rest length `h*`, the shortest of four terms, each the length at
//! which one measure of the solution's variation across the edge would equal its tolerance:
//!
//! - curvature: `h = size_angle L0 / theta`, `theta` the angle (rad) between the end vertices'
//!   normals and `L0` the edge's rest length (so `theta / L0` is the curvature in material space);
//! - velocity: `h = size_velocity L0 / |v_b - v_a|` (the velocity gradient along the edge);
//! - compression (anticipated buckling): an edge squeezed to `s = L / L0 < 1` holds `L0 - L` of
//!   excess length that a finer mesh would fold; `h = L0 sqrt(size_compression / (1 - s))`, so an
//!   edge at the tolerated strain keeps its length and 4x the strain halves it;
//! - obstacle: when both ends are within `size_proximity` (grown by the distance the fastest
//!   vertex travels in one `interval`) of an obstacle, `h = size_angle L0 / phi`, `phi` the angle
//!   between the obstacle normals at the ends' closest surface points: the cloth must resolve the
//!   obstacle's curvature before it wraps it, and a flat contact (a table top) asks for nothing.
//!
//! `h*` is the shortest term clamped to `[h_min, l_max]` (`h_min` is half the refinement floor
//! `refine_min_length`, so `l_min / 2` without `h_min`). An edge is selected for refinement when
//! `L0 > h* (1 + SIZE_HYSTERESIS)` and `L0 >= refine_min_length` (its halves stay at least
//! `h_min`), and for simplification when twice its rest length still fits,
//! `2 L0 (1 + SIZE_HYSTERESIS) <= h*` (a merge doubles edges), `L0 <= l_max` and it is old
//! enough (`t_simplify`). The smoothing rule (4.19) of the source criteria then applies unchanged.

use super::criteria::{old_enough, smooth, vertex_normals, EdgeInfo, RefineReason, Selection};
use super::AdaptParams;
use crate::cloth::Cloth;
use crate::collision::Obstacles;
use crate::math::{Real, Vec3};
use crate::mesh::VertexId;

/// Relative slack `eta` between the refine and simplify thresholds of the sizing field.
pub const SIZE_HYSTERESIS: Real = 0.2;

/// The curvature term (m): `tol L0 / theta` for a normal change `theta` (rad) across an edge of
/// rest length `rest` (m) and tolerance `tol` (rad); infinite for a flat edge.
pub fn curvature_size(rest: Real, theta: Real, tol: Real) -> Real {
    if theta > 0.0 {
        tol * rest / theta
    } else {
        Real::INFINITY
    }
}

/// The velocity term (m): `tol L0 / |dv|` for a velocity difference `dv` (m/s) across an edge of
/// rest length `rest` (m) and tolerance `tol` (m/s); infinite for a rigidly translating edge.
pub fn velocity_size(rest: Real, dv: Real, tol: Real) -> Real {
    if dv > 0.0 {
        tol * rest / dv
    } else {
        Real::INFINITY
    }
}

/// The compression term (m): `L0 sqrt(tol / (1 - L / L0))` for an edge of rest length `rest` and
/// world length `length` (m) shorter than its rest, strain tolerance `tol`; infinite otherwise.
pub fn compression_size(rest: Real, length: Real, tol: Real) -> Real {
    let squeeze = 1.0 - length / rest;
    if squeeze > 0.0 {
        rest * (tol / squeeze).sqrt()
    } else {
        Real::INFINITY
    }
}

/// The target rest length `h*` (m) of one edge and the term that set it
/// ([`RefineReason::Size`] when no term is below the ceiling `l_max`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeSize {
    /// Target rest length (m), clamped to `[h_min, l_max]` (`l_min / 2` without `h_min`).
    pub target: Real,
    /// The term that set it.
    pub reason: RefineReason,
}

/// Per-vertex data the terms share, computed once per pass.
struct Fields {
    normals: Vec<Vec3>,
    /// Outward normal of the nearest obstacle surface within the band, per vertex slot.
    obstacle_normals: Vec<Option<Vec3>>,
}

impl Fields {
    fn new(cloth: &Cloth, obstacles: &Obstacles, spec: &AdaptParams) -> Fields {
        let mesh = &cloth.mesh;
        let mut obstacle_normals = vec![None; mesh.vertex_slots()];
        if !obstacles.is_empty() {
            let fastest = mesh
                .vertices()
                .map(|v| cloth.v[v.0 as usize].norm())
                .fold(0.0, Real::max);
            let band = spec.size_proximity + fastest * spec.interval;
            for v in mesh.vertices() {
                let i = v.0 as usize;
                obstacle_normals[i] = obstacles.surface_near(cloth.x[i], band).map(|s| s.normal);
            }
        }
        Fields {
            normals: vertex_normals(cloth),
            obstacle_normals,
        }
    }
}

/// The sizing field's value on the edge `(a, b)` (vertex slots).
fn edge_size(cloth: &Cloth, fields: &Fields, spec: &AdaptParams, a: usize, b: usize) -> EdgeSize {
    let rest = cloth
        .mesh
        .rest_length(VertexId(a as u32), VertexId(b as u32));
    let angle = |p: Vec3, q: Vec3| p.dot(&q).clamp(-1.0, 1.0).acos();
    let obstacle = match (fields.obstacle_normals[a], fields.obstacle_normals[b]) {
        (Some(na), Some(nb)) => curvature_size(rest, angle(na, nb), spec.size_angle),
        _ => Real::INFINITY,
    };
    let terms = [
        (
            curvature_size(
                rest,
                angle(fields.normals[a], fields.normals[b]),
                spec.size_angle,
            ),
            RefineReason::Curvature,
        ),
        (
            velocity_size(rest, (cloth.v[b] - cloth.v[a]).norm(), spec.size_velocity),
            RefineReason::Velocity,
        ),
        (
            compression_size(
                rest,
                (cloth.x[b] - cloth.x[a]).norm(),
                spec.size_compression,
            ),
            RefineReason::Compression,
        ),
        (obstacle, RefineReason::Proximity),
    ];
    let (size, reason) =
        terms
            .into_iter()
            .fold((Real::INFINITY, RefineReason::Size), |(h, r), (t, why)| {
                if t < h {
                    (t, why)
                } else {
                    (h, r)
                }
            });
    let floor = 0.5 * spec.refine_min_length();
    if size >= spec.l_max {
        EdgeSize {
            target: spec.l_max,
            reason: RefineReason::Size,
        }
    } else {
        EdgeSize {
            target: size.max(floor),
            reason,
        }
    }
}

/// The sizing field's verdict on every edge: refine edges longer than their target, simplify
/// edges that would still fit when doubled, then the smoothing rule (4.19).
pub fn select_by_size(
    cloth: &Cloth,
    obstacles: &Obstacles,
    spec: &AdaptParams,
    info: &dyn EdgeInfo,
) -> Selection {
    let mesh = &cloth.mesh;
    let fields = Fields::new(cloth, obstacles, spec);
    let mut refine = Vec::new();
    let mut simplify = Vec::new();
    for (e, _) in mesh.edges() {
        let rest = mesh.rest_length(e.0, e.1);
        let size = edge_size(cloth, &fields, spec, e.0 .0 as usize, e.1 .0 as usize);
        if rest > size.target * (1.0 + SIZE_HYSTERESIS) && rest >= spec.refine_min_length() {
            refine.push((e, size.reason));
        } else if 2.0 * rest * (1.0 + SIZE_HYSTERESIS) <= size.target
            && rest <= spec.l_max
            && old_enough(info.age(e), spec.t_simplify)
        {
            simplify.push(e);
        }
    }
    smooth(mesh, spec, info, &mut refine, &mut simplify);
    Selection { refine, simplify }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adapt::criteria::NoHistory;
    use crate::adapt::Criteria;
    use crate::collision::{Obstacle, ObstacleShape};
    use crate::mesh::EdgeKey;
    use crate::testing;

    /// Sizing parameters over a 1 m cloth: refinement floor 0.05 m (h_min 0.025 m), ceiling 0.6 m.
    fn spec() -> AdaptParams {
        AdaptParams {
            criteria: Criteria::Sizing,
            h_min: 0.025,
            l_max: 0.6,
            ..AdaptParams::default()
        }
    }

    fn no_obstacles() -> Obstacles {
        testing::obstacles(&[])
    }

    fn reasons(sel: &Selection) -> Vec<RefineReason> {
        let mut r: Vec<_> = sel.refine.iter().map(|(_, r)| *r).collect();
        r.sort();
        r.dedup();
        r
    }

    /// The edge on the border `v = 0` whose rest midpoint is at `u = mid_u`.
    fn edge_on_v0(cloth: &Cloth, mid_u: Real) -> EdgeKey {
        let mesh = &cloth.mesh;
        mesh.edges()
            .map(|(e, _)| e)
            .find(|e| {
                let (a, b) = (mesh.rest(e.0), mesh.rest(e.1));
                a.y == 0.0 && b.y == 0.0 && (a.x + b.x - 2.0 * mid_u).abs() < 1e-9
            })
            .expect("a border edge there")
    }

    /// The size of edge `e` in `cloth` under `spec` without obstacles.
    fn size_of(cloth: &Cloth, spec: &AdaptParams, e: EdgeKey) -> EdgeSize {
        let fields = Fields::new(cloth, &no_obstacles(), spec);
        edge_size(cloth, &fields, spec, e.0 .0 as usize, e.1 .0 as usize)
    }

    #[test]
    fn the_terms_are_the_lengths_at_which_the_variation_meets_its_tolerance() {
        // 0.5 rad across 0.2 m with a 0.25 rad tolerance: half the edge.
        assert!((curvature_size(0.2, 0.5, 0.25) - 0.1).abs() < 1e-12);
        assert_eq!(curvature_size(0.2, 0.0, 0.25), Real::INFINITY);
        // 2 m/s across 0.1 m with 0.5 m/s tolerated: a quarter of the edge.
        assert!((velocity_size(0.1, 2.0, 0.5) - 0.025).abs() < 1e-12);
        assert_eq!(velocity_size(0.1, 0.0, 0.5), Real::INFINITY);
        // Squeezed by 8 % with 2 % tolerated: half the edge; at the tolerance: the edge itself;
        // stretched: no term.
        assert!((compression_size(0.1, 0.092, 0.02) - 0.05).abs() < 1e-12);
        assert!((compression_size(0.1, 0.098, 0.02) - 0.1).abs() < 1e-9);
        assert_eq!(compression_size(0.1, 0.11, 0.02), Real::INFINITY);
    }

    #[test]
    fn a_flat_still_cloth_is_coarsened_and_never_refined() {
        let cloth = testing::flat_cloth(5, Vec3::zeros());
        let sel = select_by_size(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
        // Every axis edge (0.25 m) doubled still fits 0.6 m / 1.2 = 0.5 m; the diagonals
        // (0.35 m) do not, and come only through the smoothing rule (4.19).
        let mesh = &cloth.mesh;
        for (e, _) in mesh.edges() {
            let (a, b) = (mesh.rest(e.0), mesh.rest(e.1));
            if a.x == b.x || a.y == b.y {
                assert!(sel.simplify.contains(&e), "{e:?}");
            }
        }
        // Longer than the ceiling: refined for size alone.
        let s = AdaptParams {
            l_max: 0.2,
            ..spec()
        };
        let sel = select_by_size(&cloth, &no_obstacles(), &s, &NoHistory);
        assert!(sel
            .refine
            .contains(&(cloth.mesh.edges().next().unwrap().0, RefineReason::Size)));
        assert!(reasons(&sel)
            .iter()
            .all(|r| matches!(r, RefineReason::Size | RefineReason::Smoothing)));
    }

    #[test]
    fn a_fold_is_refined_for_curvature_along_the_fold_only() {
        // Fold a 5x5 grid by 90 degrees along u = 0.5.
        let cloth = testing::folded_cloth(5);
        let sel = select_by_size(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert!(sel
            .refine
            .iter()
            .any(|(_, r)| *r == RefineReason::Curvature));
        for (e, r) in &sel.refine {
            if *r == RefineReason::Curvature {
                let (a, b) = (cloth.mesh.rest(e.0), cloth.mesh.rest(e.1));
                assert!((a.x - 0.5).abs() < 0.3 || (b.x - 0.5).abs() < 0.3, "{e:?}");
            }
        }
        // The size across the fold: an edge from u = 0.25 to 0.5 at v = 0 sees the normals
        // turn by less than 90 degrees (vertex normals average the faces), more than 0.25 rad.
        let e = edge_on_v0(&cloth, 0.375);
        let size = size_of(&cloth, &spec(), e);
        assert_eq!(size.reason, RefineReason::Curvature);
        assert!(size.target < 0.25 && size.target >= 0.025, "{size:?}");
    }

    #[test]
    fn shear_velocity_refines_along_the_gradient_and_rigid_motion_does_not() {
        let mut cloth = testing::flat_cloth(5, Vec3::zeros());
        // Rigid translation at 5 m/s: nothing to refine.
        for v in &mut cloth.v {
            *v = Vec3::new(0.0, 0.0, -5.0);
        }
        let sel = select_by_size(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
        // v_z = 10 u (1/s): an edge along u of 0.25 m sees 2.5 m/s, size 0.5 * 0.25 / 2.5 = 0.05 m.
        for v in cloth.mesh.vertices().collect::<Vec<_>>() {
            let u = cloth.mesh.rest(v).x;
            cloth.v[v.0 as usize] = Vec3::new(0.0, 0.0, 10.0 * u);
        }
        let mesh = &cloth.mesh;
        let (along_u, along_v): (Vec<EdgeKey>, Vec<EdgeKey>) = mesh
            .edges()
            .map(|(e, _)| e)
            .filter(|e| {
                let (a, b) = (mesh.rest(e.0), mesh.rest(e.1));
                a.x == b.x || a.y == b.y
            })
            .partition(|e| mesh.rest(e.0).y == mesh.rest(e.1).y);
        for e in along_u {
            let size = size_of(&cloth, &spec(), e);
            assert_eq!(size.reason, RefineReason::Velocity, "{e:?}");
            assert!((size.target - 0.05).abs() < 1e-9, "{size:?}");
        }
        for e in along_v {
            assert_eq!(size_of(&cloth, &spec(), e).reason, RefineReason::Size);
        }
    }

    #[test]
    fn a_squeezed_edge_is_refined_to_anticipate_buckling() {
        let mut cloth = testing::flat_cloth(5, Vec3::zeros());
        // The edge from (0, 0) to (0.25, 0): squeeze it by 8 % (move its end, not its neighbours').
        let e = edge_on_v0(&cloth, 0.125);
        let (a, b) = (e.0 .0 as usize, e.1 .0 as usize);
        let (ra, rb) = (cloth.mesh.rest(e.0), cloth.mesh.rest(e.1));
        let towards = if ra.x < rb.x { b } else { a };
        let from = if towards == b { a } else { b };
        cloth.x[towards] = cloth.x[from] + (cloth.x[towards] - cloth.x[from]) * 0.92;
        let size = size_of(&cloth, &spec(), e);
        assert_eq!(size.reason, RefineReason::Compression);
        // 0.25 sqrt(0.02 / 0.08) = 0.125 m.
        assert!((size.target - 0.125).abs() < 1e-9, "{size:?}");
        let sel = select_by_size(&cloth, &no_obstacles(), &spec(), &NoHistory);
        assert!(
            sel.refine.contains(&(e, RefineReason::Compression)),
            "{sel:?}"
        );
    }

    #[test]
    fn an_obstacle_sizes_the_cloth_by_its_curvature_within_the_travel_grown_band() {
        let sphere = Obstacle::new(ObstacleShape::Sphere {
            center: [0.5, 0.5, -0.3],
            radius: 0.28,
        });
        let ground = Obstacle::new(ObstacleShape::Ground { height: 0.0 });
        // A band of 0.2 m: the vertices round the sphere's top are within it.
        let spec = || AdaptParams {
            size_proximity: 0.2,
            ..spec()
        };
        // Flat cloth 1 cm above the sphere's top: the sphere turns its normal under the edges
        // round the top (0.7 rad between the top and 0.25 m aside).
        let cloth = testing::flat_cloth(5, Vec3::new(0.0, 0.0, -0.01));
        let near = testing::obstacles(std::slice::from_ref(&sphere));
        let sel = select_by_size(&cloth, &near, &spec(), &NoHistory);
        assert!(reasons(&sel).contains(&RefineReason::Proximity), "{sel:?}");
        // Lying on flat ground: the normals agree, nothing to refine.
        let cloth_on_ground = testing::flat_cloth(5, Vec3::new(0.0, 0.0, 0.001));
        let flat = testing::obstacles(&[ground]);
        let sel = select_by_size(&cloth_on_ground, &flat, &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
        // 0.5 m above the sphere, still: outside the band, no query answers.
        let mut high = testing::flat_cloth(5, Vec3::new(0.0, 0.0, 0.5));
        let sel = select_by_size(&high, &near, &spec(), &NoHistory);
        assert!(sel.refine.is_empty(), "{sel:?}");
        // Falling at 60 m/s: in one interval (0.01 s) it travels 0.6 m, the band grows to reach
        // the sphere, and the edges are refined before contact.
        for v in &mut high.v {
            *v = Vec3::new(0.0, 0.0, -60.0);
        }
        let sel = select_by_size(&high, &near, &spec(), &NoHistory);
        assert!(reasons(&sel).contains(&RefineReason::Proximity), "{sel:?}");
    }

    #[test]
    fn no_edge_is_refined_below_the_floor() {
        // Strong fold, but h_min = 0.2: a 5x5 grid's 0.25 m edges have halves below 0.2 m.
        let cloth = testing::folded_cloth(5);
        let s = AdaptParams {
            h_min: 0.2,
            ..spec()
        };
        let sel = select_by_size(&cloth, &no_obstacles(), &s, &NoHistory);
        for (e, _) in &sel.refine {
            assert!(cloth.mesh.rest_length(e.0, e.1) >= 0.4, "{e:?}");
        }
        // Every target respects the floor.
        let e = cloth.mesh.edges().next().unwrap().0;
        assert!(size_of(&cloth, &s, e).target >= 0.2);
    }
}
