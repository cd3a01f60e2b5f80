//! The elementary operation: plan the re-meshing of one region as a single [`Edit`] (MODEL.md
//! §8.2 steps 3-6). Nothing here changes the mesh; [`super::remesh_region`] applies the
//! plan through the checked edit.

use super::hole::{min_angle, HoleMesh, HoleMesher, HoleParams};
use super::region::{hole_border, interior_vertices, BorderEdge};
use super::{Direction, RemeshError, RemeshParams, RemeshStats};
use crate::math::{signed_area, Real, Vec2};
use crate::mesh::{EdgeKey, Edit, FaceId, Mesh, NewVertex, Origin, VertexId, VertexRef};
use std::collections::{BTreeMap, BTreeSet};

/// Smallest relative change of the region's mean edge length that counts as refining or
/// simplifying (dimensionless).
const MIN_CHANGE: Real = 1e-6;

/// Spacings within this relative difference are the same attempt (a retry factor's division
/// undone by its multiplication, up to rounding; dimensionless).
const SAME_SPACING: Real = 1e-9;

/// An edit ready to apply and what it will do.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The one edit replacing the region.
    pub edit: Edit,
    /// Counts and measures of the re-meshing.
    pub stats: RemeshStats,
}

/// A point of the hole mesher's input.
#[derive(Clone, Copy, Debug)]
enum Fixed {
    /// An existing vertex kept.
    Old(VertexId),
    /// The rest midpoint of a cloth-border edge split before meshing.
    Midpoint(VertexId, VertexId),
}

/// Why an attempt was rejected (drives the retries).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    Accept,
    /// Refining made no new vertex, or did not shorten the region's edges: retry denser.
    Denser(&'static str),
    /// A new edge fell below the floor, or simplifying did not lengthen the edges: retry coarser.
    Coarser(&'static str),
    /// No retry can do better: simplifying with no interior point left did not lengthen the
    /// edges (a coarser spacing only drops interior points, and the border is already all
    /// there is; measured on the sphere: none of 423 such regions was accepted by a later
    /// attempt).
    Refuse(&'static str),
}

/// Plans the re-meshing of the region `faces` (live faces of `mesh`) in `mode`.
pub fn plan_region(
    mesh: &Mesh,
    faces: &BTreeSet<FaceId>,
    mode: Direction,
    params: &RemeshParams,
) -> Result<Plan, RemeshError> {
    if faces.is_empty() {
        return Err(RemeshError::EmptyRegion);
    }
    if let Some(&f) = faces.iter().find(|&&f| !mesh.is_face(f)) {
        return Err(RemeshError::StaleFace(f));
    }
    let border = hole_border(mesh, faces);
    let interior = interior_vertices(mesh, faces, &border);
    let pinned: Vec<VertexId> = interior
        .iter()
        .copied()
        .filter(|&v| mesh.is_pinned(v))
        .collect();
    let before = mean_edge_length(mesh, faces);
    // Density factor (4.20-4.22): f_j = L_j² / (2 A_j) over the border edges.
    let (mut sum_l, mut sum_f) = (0.0, 0.0);
    for e in &border {
        let l = mesh.rest_length(e.from, e.to);
        sum_l += l;
        sum_f += l * l / (2.0 * mesh.face_rest_area(e.face));
    }
    let n = border.len() as Real;
    let scale = match mode {
        Direction::Refine => params.density_refine,
        Direction::Simplify => params.density_simplify,
    };
    let density = scale * sum_f / n;
    let mut spacing = (sum_l / n) / density;
    if mode == Direction::Simplify {
        spacing = spacing.min(params.l_max);
    }
    let floor = params.floor_factor * params.l_min;
    // Refinement seeds every removed face's centroid where the lattice left room.
    let hints: Vec<Vec2> = match mode {
        Direction::Refine => faces
            .iter()
            .map(|&f| mesh.face(f).map(|v| mesh.rest(v)).iter().sum::<Vec2>() / 3.0)
            .collect(),
        Direction::Simplify => Vec::new(),
    };
    let mut last = "no attempt";
    let mut mesher = HoleMesher::default();
    let mut tried: Vec<Real> = Vec::with_capacity(params.max_attempts);
    for attempt in 1..=params.max_attempts {
        tried.push(spacing);
        let (fixed, constraints) = hole_input(mesh, &border, &pinned, mode, spacing, params);
        let points: Vec<Vec2> = fixed.iter().map(|p| position(mesh, *p)).collect();
        let hole = mesher.mesh(
            &points,
            &constraints,
            &hints,
            &HoleParams {
                spacing,
                angle_limit_deg: params.angle_limit_deg,
                area_slack: params.area_slack,
                seed_clearance: params.seed_clearance,
                smoothing_passes: params.smoothing_passes,
                max_refinement_vertices: params.max_new_vertices,
            },
        )?;
        let after = mean_length(&hole);
        let mut border_set: Vec<(usize, usize)> = constraints
            .iter()
            .map(|&[a, b]| (a.min(b), a.max(b)))
            .collect();
        border_set.sort_unstable();
        let shortest_border = constraints
            .iter()
            .map(|&[a, b]| (points[b] - points[a]).norm())
            .fold(Real::INFINITY, Real::min);
        let floor_here = floor.min(0.99 * shortest_border);
        let too_short = hole.triangles.iter().any(|t| {
            (0..3).any(|k| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                border_set.binary_search(&(a.min(b), a.max(b))).is_err()
                    && (hole.points[a] - hole.points[b]).norm() < floor_here
            })
        });
        let new_vertices = hole.points.len() - fixed.len()
            + fixed
                .iter()
                .filter(|p| matches!(p, Fixed::Midpoint(..)))
                .count();
        let (small, small_interior) = angle_counts(&hole, fixed.len(), params.angle_limit_deg);
        let verdict = match mode {
            Direction::Refine if new_vertices == 0 => Verdict::Denser("no new vertex"),
            Direction::Refine if after >= before * (1.0 - MIN_CHANGE) => {
                Verdict::Denser("edges not shorter")
            }
            _ if too_short => Verdict::Coarser("a new edge is below the floor"),
            _ if small_interior > 0 || small > constraints.len() => {
                Verdict::Coarser("too many triangles below the angle limit")
            }
            Direction::Simplify if after <= before * (1.0 + MIN_CHANGE) => {
                if hole.points.len() == fixed.len() {
                    Verdict::Refuse("edges not longer")
                } else {
                    Verdict::Coarser("edges not longer")
                }
            }
            _ => Verdict::Accept,
        };
        match verdict {
            Verdict::Accept => {
                let edit = build_edit(mesh, faces, &fixed, &hole)?;
                let stats = stats(mode, &edit, &fixed, &constraints, attempt);
                return Ok(Plan {
                    edit,
                    stats: RemeshStats {
                        small_angle: small,
                        small_angle_interior: small_interior,
                        mean_length_before: before,
                        mean_length_after: after,
                        target_length: spacing,
                        ..stats
                    },
                });
            }
            Verdict::Denser(why) => {
                last = why;
                if spacing <= params.l_min {
                    break;
                }
                spacing = (spacing / params.retry_factor).max(params.l_min);
            }
            Verdict::Coarser(why) => {
                last = why;
                if mode == Direction::Simplify && spacing >= params.l_max {
                    break;
                }
                spacing *= params.retry_factor;
                if mode == Direction::Simplify {
                    spacing = spacing.min(params.l_max);
                }
            }
            Verdict::Refuse(why) => {
                last = why;
                break;
            }
        }
        // The mesher is deterministic: a spacing tried before (a retry denser after one
        // coarser, or the reverse) would be refused again.
        if tried
            .iter()
            .any(|&s| (s - spacing).abs() <= SAME_SPACING * s)
        {
            break;
        }
    }
    Err(RemeshError::NoAcceptableMesh(last.to_string()))
}

/// The mesher's input for one attempt: fixed points (border vertices, pinned interior vertices,
/// cloth-border midpoints) and the directed border as index pairs, after splitting (refine) or
/// merging (simplify) cloth-border edges.
fn hole_input(
    mesh: &Mesh,
    border: &[BorderEdge],
    pinned: &[VertexId],
    mode: Direction,
    spacing: Real,
    params: &RemeshParams,
) -> (Vec<Fixed>, Vec<[usize; 2]>) {
    // Border as a successor map (one outgoing edge per vertex except at pinch vertices).
    let mut chain: Vec<(VertexId, VertexId, bool)> = border
        .iter()
        .map(|e| (e.from, e.to, e.cloth_border))
        .collect();
    if mode == Direction::Simplify {
        merge_collinear(mesh, &mut chain, params.l_max);
    }
    let mut fixed: Vec<Fixed> = Vec::new();
    let mut index: BTreeMap<VertexId, usize> = BTreeMap::new();
    let mut id = |v: VertexId, fixed: &mut Vec<Fixed>| {
        *index.entry(v).or_insert_with(|| {
            fixed.push(Fixed::Old(v));
            fixed.len() - 1
        })
    };
    let mut constraints = Vec::with_capacity(chain.len() + 4);
    for &(a, b, cloth) in &chain {
        let (ia, ib) = (id(a, &mut fixed), id(b, &mut fixed));
        let l = mesh.rest_length(a, b);
        let split = mode == Direction::Refine
            && cloth
            && l > spacing
            && 0.5 * l >= params.floor_factor * params.l_min;
        if split {
            fixed.push(Fixed::Midpoint(a, b));
            let m = fixed.len() - 1;
            constraints.push([ia, m]);
            constraints.push([m, ib]);
        } else {
            constraints.push([ia, ib]);
        }
    }
    for &v in pinned {
        id(v, &mut fixed);
    }
    (fixed, constraints)
}

/// Merges consecutive collinear cloth-border edges `u -> v -> w` (v not pinned, used by no other
/// border edge, merged length at most `l_max`), repeatedly.
fn merge_collinear(mesh: &Mesh, chain: &mut Vec<(VertexId, VertexId, bool)>, l_max: Real) {
    loop {
        let mut out_deg: BTreeMap<VertexId, usize> = BTreeMap::new();
        let mut in_deg: BTreeMap<VertexId, usize> = BTreeMap::new();
        for &(a, b, _) in chain.iter() {
            *out_deg.entry(a).or_default() += 1;
            *in_deg.entry(b).or_default() += 1;
        }
        let found = chain.iter().enumerate().find_map(|(i, &(u, v, c1))| {
            let j = chain.iter().position(|&(a, _, _)| a == v)?;
            let (_, w, c2) = chain[j];
            let ok = c1
                && c2
                && u != w
                && out_deg[&v] == 1
                && in_deg[&v] == 1
                && !mesh.is_pinned(v)
                && mesh.rest_length(u, w) <= l_max
                && collinear(mesh.rest(u), mesh.rest(v), mesh.rest(w));
            ok.then_some((i, j, u, w))
        });
        let Some((i, j, u, w)) = found else { return };
        chain[i] = (u, w, true);
        chain.remove(j);
    }
}

/// True when `v` lies on the segment `u w` (relative tolerance 1e-9) strictly between its ends.
fn collinear(u: Vec2, v: Vec2, w: Vec2) -> bool {
    let d = w - u;
    let t = (v - u).dot(&d) / d.norm_squared();
    d.perp(&(v - u)).abs() <= 1e-9 * d.norm_squared() && t > 0.0 && t < 1.0
}

fn position(mesh: &Mesh, p: Fixed) -> Vec2 {
    match p {
        Fixed::Old(v) => mesh.rest(v),
        Fixed::Midpoint(a, b) => (mesh.rest(a) + mesh.rest(b)) * 0.5,
    }
}

/// Mean rest length of the distinct edges of `faces` (m).
pub(super) fn mean_edge_length(mesh: &Mesh, faces: &BTreeSet<FaceId>) -> Real {
    let edges: BTreeSet<EdgeKey> = faces
        .iter()
        .flat_map(|&f| {
            let vs = mesh.face(f);
            (0..3).map(move |k| EdgeKey::new(vs[k], vs[(k + 1) % 3]))
        })
        .collect();
    edges
        .iter()
        .map(|e| mesh.rest_length(e.0, e.1))
        .sum::<Real>()
        / edges.len() as Real
}

/// Mean rest length of the distinct edges of a meshed hole (m).
fn mean_length(hole: &HoleMesh) -> Real {
    let mut edges: Vec<(usize, usize)> = hole
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
        .iter()
        .map(|&(a, b)| (hole.points[a] - hole.points[b]).norm())
        .sum::<Real>()
        / edges.len() as Real
}

/// The edit: remove the region, add the midpoints and the new interior points (barycentric in
/// the removed face whose rest triangle contains them), add the hole's triangles.
fn build_edit(
    mesh: &Mesh,
    faces: &BTreeSet<FaceId>,
    fixed: &[Fixed],
    hole: &HoleMesh,
) -> Result<Edit, RemeshError> {
    let mut refs = Vec::with_capacity(hole.points.len());
    let mut new_vertices = Vec::new();
    for (i, &p) in hole.points.iter().enumerate() {
        let r = match fixed.get(i) {
            Some(Fixed::Old(v)) => VertexRef::Old(*v),
            Some(&Fixed::Midpoint(a, b)) => {
                new_vertices.push(NewVertex {
                    rest: p,
                    origin: Origin::Midpoint(a, b),
                });
                VertexRef::New(new_vertices.len() - 1)
            }
            None => {
                new_vertices.push(NewVertex {
                    rest: p,
                    origin: locate(mesh, faces, p)?,
                });
                VertexRef::New(new_vertices.len() - 1)
            }
        };
        refs.push(r);
    }
    Ok(Edit {
        remove: faces.iter().copied().collect(),
        new_vertices,
        add: hole.triangles.iter().map(|t| t.map(|i| refs[i])).collect(),
    })
}

/// Barycentric origin of a rest point in the removed face containing it (the face where its
/// smallest weight is largest; tiny negative rounding is clamped).
fn locate(mesh: &Mesh, faces: &BTreeSet<FaceId>, p: Vec2) -> Result<Origin, RemeshError> {
    let mut best: Option<([VertexId; 3], [Real; 3])> = None;
    for &f in faces {
        let vs = mesh.face(f);
        let [a, b, c] = vs.map(|v| mesh.rest(v));
        let area = signed_area(a, b, c);
        let w = [
            signed_area(p, b, c) / area,
            signed_area(a, p, c) / area,
            signed_area(a, b, p) / area,
        ];
        let score = w[0].min(w[1]).min(w[2]);
        if best.is_none_or(|(_, bw)| score > bw[0].min(bw[1]).min(bw[2])) {
            best = Some((vs, w));
        }
    }
    let (corners, w) = best.ok_or(RemeshError::EmptyRegion)?;
    if w.iter().any(|&x| x < -1e-9) {
        return Err(RemeshError::Mesher(format!(
            "new point ({}, {}) is outside the region",
            p.x, p.y
        )));
    }
    let w = w.map(|x| x.max(0.0));
    let s: Real = w.iter().sum();
    Ok(Origin::InTriangle {
        corners,
        weights: w.map(|x| x / s),
    })
}

/// New triangles with a rest angle below `limit_deg`, and those of them with no vertex on the
/// hole border (points `< n_fixed`), where the border cannot be blamed.
fn angle_counts(hole: &HoleMesh, n_fixed: usize, limit_deg: Real) -> (usize, usize) {
    let limit = limit_deg.to_radians() * (1.0 - 1e-9);
    let mut small = 0;
    let mut interior = 0;
    for t in &hole.triangles {
        let [a, b, c] = t.map(|i| hole.points[i]);
        if min_angle(a, b, c) < limit {
            small += 1;
            if t.iter().all(|&i| i >= n_fixed) {
                interior += 1;
            }
        }
    }
    (small, interior)
}

/// Counts of the planned edit (the angle counts and lengths are the caller's).
fn stats(
    mode: Direction,
    edit: &Edit,
    fixed: &[Fixed],
    constraints: &[[usize; 2]],
    attempts: usize,
) -> RemeshStats {
    RemeshStats {
        mode,
        removed_faces: edit.remove.len(),
        added_faces: edit.add.len(),
        new_vertices: edit.new_vertices.len(),
        border_splits: fixed
            .iter()
            .filter(|p| matches!(p, Fixed::Midpoint(..)))
            .count(),
        border_edges: constraints.len(),
        attempts,
        ..RemeshStats::default()
    }
}
