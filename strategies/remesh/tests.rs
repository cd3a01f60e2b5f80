//! Tests of the local-remeshing strategy: the elementary operation on hand-built meshes, the
//! strategy's bookkeeping, and property tests over random grids and random operation sequences.

use super::*;
use crate::adapt::{Adaptivity, ClothTarget, TransferOptions};
use crate::cloth::Cloth;
use crate::math::{Vec2, Vec3};
use crate::mesh::{union_jack, Mesh, Origin, VertexId, VertexKey};
use proptest::prelude::*;
use std::collections::BTreeSet;

fn params(cells: usize) -> RemeshParams {
    let h = 1.0 / cells as Real;
    RemeshParams {
        l_min: 0.2 * h,
        l_max: 2.5 * h,
        ..RemeshParams::default()
    }
}

fn e(a: u32, b: u32) -> EdgeKey {
    EdgeKey::new(VertexId(a), VertexId(b))
}

fn rest_area(mesh: &Mesh) -> Real {
    mesh.faces().map(|f| mesh.face_rest_area(f)).sum()
}

/// Mean rest length of the distinct edges of `faces`.
fn mean_length(mesh: &Mesh, faces: impl IntoIterator<Item = FaceId>) -> Real {
    let mut edges = BTreeSet::new();
    for f in faces {
        let vs = mesh.face(f);
        for k in 0..3 {
            edges.insert(EdgeKey::new(vs[k], vs[(k + 1) % 3]));
        }
    }
    edges
        .iter()
        .map(|e| mesh.rest_length(e.0, e.1))
        .sum::<Real>()
        / edges.len() as Real
}

/// The edges of every face around vertex `v`.
fn star_edges(mesh: &Mesh, v: VertexId) -> Vec<EdgeKey> {
    let mut out: Vec<EdgeKey> = mesh
        .vertex_faces(v)
        .iter()
        .flat_map(|&f| {
            let vs = mesh.face(f);
            (0..3).map(move |k| EdgeKey::new(vs[k], vs[(k + 1) % 3]))
        })
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

#[test]
fn refining_an_interior_edge_makes_a_finer_conforming_region() {
    let mut mesh = union_jack(5, 5, 1.0, 1.0);
    let area = rest_area(&mesh);
    // (1,1)-(2,2) = 6-12, a diagonal of the 5x5 grid.
    let before = mean_length(&mesh, region_faces(&mesh, &[e(6, 12)]).unwrap());
    let (record, stats) =
        remesh_region(&mut mesh, &[e(6, 12)], Direction::Refine, &params(4)).unwrap();
    mesh.check().unwrap();
    assert!((rest_area(&mesh) - area).abs() <= 1e-12 * area);
    assert!(!record.added_vertices.is_empty());
    let after = mean_length(&mesh, record.added_faces.iter().copied());
    assert!(after < before, "{before} -> {after}");
    assert_eq!(stats.small_angle_interior, 0, "{stats:?}");
}

#[test]
fn refining_at_the_cloth_border_bisects_border_edges() {
    let mut mesh = union_jack(3, 3, 1.0, 1.0);
    // Edge 0-1 lies on the cloth border v = 0.
    let (record, stats) =
        remesh_region(&mut mesh, &[e(0, 1)], Direction::Refine, &params(2)).unwrap();
    mesh.check().unwrap();
    assert!(stats.border_splits >= 1, "{stats:?}");
    let mid = record
        .added_vertices
        .iter()
        .find(|(_, o)| matches!(o, Origin::Midpoint(..)))
        .expect("a midpoint");
    assert!((mesh.rest(mid.0) - Vec2::new(0.25, 0.0)).norm() < 1e-15);
    assert!(mesh.is_border_vertex(mid.0));
}

#[test]
fn simplifying_a_refined_patch_coarsens_it_and_keeps_corners_and_pins() {
    let mut mesh = union_jack(9, 9, 1.0, 1.0);
    mesh.set_pinned(VertexId(4), true); // (4, 0), middle of the bottom border
    let keep: Vec<VertexKey> = [0, 4, 8, 72, 80].map(|i| mesh.key(VertexId(i))).to_vec();
    let p = RemeshParams {
        l_max: 0.5,
        ..params(8)
    };
    // Everything: the whole cloth is one region, the border loop the cloth border.
    let all: Vec<EdgeKey> = mesh.edges().map(|(k, _)| k).collect();
    let vertices = mesh.vertex_count();
    let before = mean_length(&mesh, mesh.faces().collect::<Vec<_>>());
    let (record, stats) = remesh_region(&mut mesh, &all, Direction::Simplify, &p).unwrap();
    mesh.check().unwrap();
    assert!(mesh.vertex_count() < vertices, "{stats:?}");
    assert!(!record.removed_vertices.is_empty());
    let after = mean_length(&mesh, mesh.faces().collect::<Vec<_>>());
    assert!(after > before, "{before} -> {after}");
    for k in keep {
        assert!(mesh.resolve(k).is_some(), "{k:?} removed");
    }
    assert!(mesh.is_pinned(VertexId(4)));
    // Collinear border edges were merged, up to l_max.
    let border_edges = mesh.edges().filter(|(_, f)| f.is_border()).count();
    assert!(border_edges < 32, "{border_edges}");
}

#[test]
fn region_around_a_kept_island_is_remeshed_as_an_annulus() {
    // On a 7x7 grid, select the ring of edges around the centre cell's star but not the star's
    // own edges: the faces adjacent to the ring surround kept faces.
    let mut mesh = union_jack(7, 7, 1.0, 1.0);
    let centre = VertexId(24); // (3, 3), valence 8
    let island: BTreeSet<FaceId> = mesh.vertex_faces(centre).iter().copied().collect();
    let ring: Vec<EdgeKey> = mesh
        .edges()
        .map(|(k, _)| k)
        .filter(|k| {
            let (a, b) = (mesh.rest(k.0), mesh.rest(k.1));
            let far = |p: Vec2| (p - Vec2::new(0.5, 0.5)).abs().max();
            (far(a) - 2.0 / 6.0).abs() < 1e-9 && (far(b) - 2.0 / 6.0).abs() < 1e-9
        })
        .collect();
    assert_eq!(ring.len(), 16);
    let faces = region_faces(&mesh, &ring).unwrap();
    assert!(faces.is_disjoint(&island));
    let area = rest_area(&mesh);
    remesh_region(&mut mesh, &ring, Direction::Refine, &params(6)).unwrap();
    mesh.check().unwrap();
    assert!((rest_area(&mesh) - area).abs() <= 1e-12 * area);
    for f in island {
        assert!(mesh.is_face(f), "island face {f:?} removed");
    }
}

#[test]
fn refusals_leave_the_mesh_untouched() {
    let mut mesh = union_jack(4, 4, 1.0, 1.0);
    let copy = mesh.clone();
    assert_eq!(
        remesh_region(&mut mesh, &[e(0, 15)], Direction::Refine, &params(3)).unwrap_err(),
        RemeshError::NoSuchEdge(e(0, 15))
    );
    // A floor above every possible new edge: refining can never be accepted.
    let p = RemeshParams {
        l_min: 10.0,
        ..params(3)
    };
    let err = remesh_region(&mut mesh, &[e(5, 10)], Direction::Refine, &p).unwrap_err();
    assert!(matches!(err, RemeshError::NoAcceptableMesh(_)), "{err}");
    assert_eq!(mesh, copy);
}

#[test]
fn components_join_edges_sharing_a_face_only() {
    let mesh = union_jack(5, 5, 1.0, 1.0);
    // 0-1 and 1-6 share face (0,1,6); 18-19 is far away.
    let groups = components(&mesh, &[e(18, 19), e(1, 6), e(0, 1)]);
    assert_eq!(groups, vec![vec![e(0, 1), e(1, 6)], vec![e(18, 19)]]);
}

/// A flat 5 x 5 cloth of 1 m with edge 6-7 compressed to 50 % (refinement by compression), no
/// obstacle, and a remesh run of `spec` adapting it at t = 1 s.
fn adapt_compressed(
    spec: &crate::adapt::AdaptParams,
    velocity: impl Fn(Vec3) -> Vec3,
) -> (Remesh, Cloth, crate::adapt::AdaptReport) {
    use crate::adapt::AdaptContext;
    let mesh = union_jack(5, 5, 1.0, 1.0);
    let mut x: Vec<Vec3> = mesh
        .vertices()
        .map(|v| Vec3::new(mesh.rest(v).x, mesh.rest(v).y, 0.0))
        .collect();
    x[7] = x[6] + (x[7] - x[6]) * 0.5;
    let mut cloth = crate::testing::cloth(mesh, x);
    for i in 0..cloth.x.len() {
        cloth.v[i] = velocity(cloth.x[i]);
    }
    let obstacles = crate::testing::obstacles(&[]);
    let mut s = Remesh::new();
    let ctx = AdaptContext {
        obstacles: &obstacles,
        time: 1.0,
        params: spec,
        interrupt: None,
    };
    let report = s.adapt(&mut cloth, &ctx).unwrap();
    cloth.refresh();
    cloth.mesh.check().unwrap();
    (s, cloth, report)
}

#[test]
fn refined_edges_age_and_are_forgotten_after_t_simplify() {
    let spec = crate::adapt::AdaptParams::default();
    let (mut s, cloth, report) = adapt_compressed(&spec, |_| Vec3::zeros());
    assert!(s.counters.refined >= 1, "{:?}", s.counters);
    assert!(report.vertices_added > 0);
    let new = cloth.mesh.vertices().last().unwrap();
    let edge = star_edges(&cloth.mesh, new)[0];
    let age = s
        .age(&cloth.mesh, edge, 1.05)
        .expect("a refined edge has an age");
    assert!((age - 0.05).abs() < 1e-12, "{age}");
    s.prune(&cloth.mesh, 1.0 + spec.t_simplify, spec.t_simplify);
    assert_eq!(s.age(&cloth.mesh, edge, 1.2), None);
}

/// A region the planner refused is answered from memory when the next pass selects it again,
/// with the same refusal, and is planned afresh once the parameters change; edges the mesher
/// could not coarsen are not selected again within `t_simplify`.
#[test]
fn a_refused_region_is_remembered_until_the_parameters_change() {
    use crate::adapt::AdaptContext;
    // No edge shorter than 0.34 m may be made: edges are selected (compression, simplification)
    // but no hole mesh is acceptable.
    let spec = crate::adapt::AdaptParams {
        h_min: 0.17,
        ..crate::adapt::AdaptParams::default()
    };
    let (mut s, mut cloth, report) = adapt_compressed(&spec, |_| Vec3::zeros());
    let first = s.counters.clone();
    assert!(first.refused >= 1 && first.remembered == 0, "{first:?}");
    assert_eq!(report.vertices_added, 0, "{:?}", s.counters);
    let mesh = cloth.mesh.clone();
    let obstacles = crate::testing::obstacles(&[]);
    let mut ctx = AdaptContext {
        obstacles: &obstacles,
        time: 1.0 + 0.5 * spec.t_simplify,
        params: &spec,
        interrupt: None,
    };
    s.adapt(&mut cloth, &ctx).unwrap();
    assert_eq!(s.counters.refused, first.refused, "the coarsenings wait");
    ctx.time = 1.0 + 1.01 * spec.t_simplify;
    s.adapt(&mut cloth, &ctx).unwrap();
    assert_eq!(s.counters.refused, 2 * first.refused, "{:?}", s.counters);
    assert_eq!(s.counters.remembered, first.refused);
    assert_eq!(s.counters.last_refusal, first.last_refusal);
    assert_eq!(cloth.mesh, mesh);
    let changed = crate::adapt::AdaptParams {
        remesh_min_angle: 24.0,
        ..spec
    };
    ctx.params = &changed;
    ctx.time += 2.01 * spec.t_simplify;
    s.adapt(&mut cloth, &ctx).unwrap();
    assert_eq!(s.counters.refused, 3 * first.refused, "{:?}", s.counters);
    assert_eq!(s.counters.remembered, first.refused, "planned afresh");
}

/// `restore_energy` means for remesh what it means for every strategy: the shared transfer
/// gives the re-meshed region back the kinetic energy that averaging velocities lost.
#[test]
fn restore_energy_keeps_the_kinetic_energy_of_a_remeshed_region() {
    let swirl = |x: Vec3| Vec3::new((7.0 * x.y).sin(), (5.0 * x.x).cos(), x.x * x.y);
    let mut spec = crate::adapt::AdaptParams::default();
    let (_, cloth, lost) = adapt_compressed(&spec, swirl);
    let energy = cloth.kinetic_energy();
    assert!(lost.events > 0);
    assert!(lost.kinetic_energy_change < -1e-6 * energy, "{lost:?}");
    spec.restore_energy = true;
    let (_, _, kept) = adapt_compressed(&spec, swirl);
    assert_eq!(kept.events, lost.events);
    assert!(
        kept.kinetic_energy_change.abs() <= 1e-12 * energy,
        "{kept:?}"
    );
}

// ----- property tests -----

/// A random cloth: `cells` x `cells` union-jack grid of 1 m, smoothly deformed, random velocities,
/// some pinned vertices.
fn random_cloth(cells: usize, seed: u64, pins: usize) -> Cloth {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut mesh = union_jack(cells + 1, cells + 1, 1.0, 1.0);
    let n = mesh.vertex_count() as u32;
    for _ in 0..pins {
        mesh.set_pinned(VertexId(rng.random_range(0..n)), true);
    }
    let (a, b, c) = (
        rng.random_range(-0.3..0.3),
        rng.random_range(-0.3..0.3),
        rng.random_range(0.5..3.0),
    );
    let x: Vec<Vec3> = mesh
        .vertices()
        .map(|v| {
            let p = mesh.rest(v);
            Vec3::new(
                p.x + a * (c * p.y).sin(),
                p.y + b * (c * p.x).cos(),
                0.3 * (c * (p.x + p.y)).sin(),
            )
        })
        .collect();
    let mut cloth = crate::testing::cloth(mesh, x);
    for v in cloth.mesh.vertices().collect::<Vec<_>>() {
        if !cloth.mesh.is_pinned(v) {
            cloth.v[v.0 as usize] = Vec3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            );
        }
    }
    cloth
}

/// A connected set of up to `size` edges grown from the `pick`-th edge through shared faces.
fn connected_edges(mesh: &Mesh, pick: usize, size: usize) -> Vec<EdgeKey> {
    let all: Vec<EdgeKey> = mesh.edges().map(|(k, _)| k).collect();
    let mut set = vec![all[pick % all.len()]];
    let mut i = 0;
    while set.len() < size && i < set.len() {
        let ek = set[i];
        for f in mesh.edge(ek.0, ek.1).into_iter().flat_map(|ef| ef.iter()) {
            let vs = mesh.face(f);
            for k in 0..3 {
                let n = EdgeKey::new(vs[k], vs[(k + 1) % 3]);
                if set.len() < size && !set.contains(&n) {
                    set.push(n);
                }
            }
        }
        i += 1;
    }
    set
}

fn corners(mesh: &Mesh) -> Vec<VertexKey> {
    mesh.vertices()
        .filter(|&v| {
            let p = mesh.rest(v);
            (p.x == 0.0 || p.x == 1.0) && (p.y == 0.0 || p.y == 1.0)
        })
        .map(|v| mesh.key(v))
        .collect()
}

/// Independent count of the new faces with a rest angle below `limit_deg`: all of them, those
/// with no vertex on the hole border (neither an old vertex nor a cloth-border midpoint), and the
/// number of edges of the new region's border.
fn angle_census(
    before: &Mesh,
    after: &Mesh,
    record: &EditRecord,
    limit_deg: Real,
) -> (usize, usize, usize) {
    let on_border = |v: VertexId| {
        (before.is_vertex(v) && before.key(v) == after.key(v))
            || record
                .added_vertices
                .iter()
                .any(|(w, o)| *w == v && matches!(o, Origin::Midpoint(..)))
    };
    let mut directed = BTreeSet::new();
    let (mut small, mut interior) = (0, 0);
    for &f in &record.added_faces {
        let vs = after.face(f);
        for k in 0..3 {
            directed.insert((vs[k], vs[(k + 1) % 3]));
        }
        let [a, b, c] = vs.map(|v| after.rest(v));
        let angle = |p: Vec2, q: Vec2, r: Vec2| {
            let (u, w) = (q - p, r - p);
            (u.dot(&w) / (u.norm() * w.norm())).clamp(-1.0, 1.0).acos()
        };
        let min = angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b));
        if min.to_degrees() < limit_deg * (1.0 - 1e-6) {
            small += 1;
            if !vs.iter().any(|&v| on_border(v)) {
                interior += 1;
            }
        }
    }
    let border = directed
        .iter()
        .filter(|(a, b)| !directed.contains(&(*b, *a)))
        .count();
    (small, interior, border)
}

fn momentum_scale(cloth: &Cloth) -> Real {
    let m = cloth.model.mass();
    cloth
        .mesh
        .vertices()
        .map(|v| m[v.0 as usize] * cloth.v[v.0 as usize].norm())
        .sum()
}

fn cases() -> ProptestConfig {
    let n = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(64);
    ProptestConfig::with_cases(n)
}

proptest! {
    #![proptest_config(cases())]

    /// Random refine/simplify sequences keep every invariant after every operation.
    #[test]
    fn random_remesh_sequences_keep_conformity_mass_momentum_and_shape(
        cells in 2usize..=12,
        seed in any::<u64>(),
        pins in 0usize..4,
        ops in prop::collection::vec((any::<bool>(), any::<usize>(), 1usize..8), 50..60),
    ) {
        let mut cloth = random_cloth(cells, seed, pins);
        let p = params(cells);
        let area0 = rest_area(&cloth.mesh);
        let mass0 = cloth.model.total_mass();
        let momentum0 = cloth.linear_momentum();
        let scale = momentum_scale(&cloth).max(1e-30);
        let pinned: Vec<VertexKey> = cloth
            .mesh
            .vertices()
            .filter(|&v| cloth.mesh.is_pinned(v))
            .map(|v| cloth.mesh.key(v))
            .collect();
        let corner_keys = corners(&cloth.mesh);
        prop_assert_eq!(corner_keys.len(), 4);
        let mut applied = 0;
        for (refine, pick, size) in ops {
            let mode = if refine { Direction::Refine } else { Direction::Simplify };
            let edges = connected_edges(&cloth.mesh, pick, size);
            let region = region_faces(&cloth.mesh, &edges).unwrap();
            let before = mean_length(&cloth.mesh, region.iter().copied());
            let mesh_before = cloth.mesh.clone();
            let x_before = cloth.x.clone();
            let options = TransferOptions { restore_momentum: true, ..TransferOptions::default() };
            let result = remesh_region(&mut ClothTarget::new(&mut cloth, options), &edges, mode, &p);
            match result {
                Ok((record, stats)) => {
                    applied += 1;
                    cloth.refresh();
                    prop_assert!(cloth.mesh.check().is_ok(), "{:?}", cloth.mesh.check());
                    let after = mean_length(&cloth.mesh, record.added_faces.iter().copied());
                    match mode {
                        Direction::Refine => prop_assert!(after < before, "refine {} -> {}", before, after),
                        Direction::Simplify => prop_assert!(after > before, "simplify {} -> {}", before, after),
                    }
                    let (small, interior, border) =
                        angle_census(&mesh_before, &cloth.mesh, &record, p.angle_limit_deg);
                    prop_assert_eq!(interior, 0, "{:?}", stats);
                    prop_assert!(small <= border, "{} small-angle triangles, {} border edges {:?}",
                        small, border, stats);
                    prop_assert_eq!((small, interior), (stats.small_angle, stats.small_angle_interior));
                }
                Err(_) => {
                    prop_assert!(cloth.mesh == mesh_before, "refusal changed the mesh");
                    prop_assert!(cloth.x == x_before);
                }
            }
            let area = rest_area(&cloth.mesh);
            prop_assert!((area - area0).abs() <= 1e-12 * area0, "area {} -> {}", area0, area);
            let mass = cloth.model.total_mass();
            prop_assert!((mass - mass0).abs() <= 1e-12 * mass0, "mass {} -> {}", mass0, mass);
            let momentum = cloth.linear_momentum();
            prop_assert!((momentum - momentum0).norm() <= 1e-9 * scale,
                "momentum {} -> {}", momentum0, momentum);
            for k in pinned.iter().chain(&corner_keys) {
                prop_assert!(cloth.mesh.resolve(*k).is_some(), "{:?} removed", k);
            }
        }
        prop_assert!(applied > 0, "no operation was accepted");
    }
}

#[test]
fn region_with_two_border_loops_keeps_its_island() {
    // 9x9 grid, Chebyshev levels 0..4 around the centre (4, 4) = 40. Selecting every edge with
    // both ends at levels 2 or 3 removes a band: the hole's border has an outer loop and an inner
    // loop around the kept centre.
    let mesh = union_jack(9, 9, 1.0, 1.0);
    let level = |mesh: &Mesh, v: VertexId| {
        let p = mesh.rest(v) * 8.0 - Vec2::new(4.0, 4.0);
        p.abs().max().round() as i32
    };
    let band: Vec<EdgeKey> = mesh
        .edges()
        .map(|(k, _)| k)
        .filter(|k| (2..=3).contains(&level(&mesh, k.0)) && (2..=3).contains(&level(&mesh, k.1)))
        .collect();
    let faces = region_faces(&mesh, &band).unwrap();
    let border = super::region::hole_border(&mesh, &faces);
    // Two loops: union the border's vertices along its edges.
    let mut uf = petgraph::unionfind::UnionFind::<usize>::new(mesh.vertex_slots());
    for b in &border {
        uf.union(b.from.0 as usize, b.to.0 as usize);
    }
    let loops: BTreeSet<usize> = border.iter().map(|b| uf.find(b.from.0 as usize)).collect();
    assert_eq!(loops.len(), 2, "{border:?}");
    let kept: Vec<FaceId> = mesh.faces().filter(|f| !faces.contains(f)).collect();
    let centre = VertexId(40);
    assert!(mesh.vertex_faces(centre).iter().all(|f| !faces.contains(f)));
    let area = rest_area(&mesh);
    for mode in [Direction::Refine, Direction::Simplify] {
        let mut m = mesh.clone();
        let result = remesh_region(&mut m, &band, mode, &params(8));
        if mode == Direction::Refine {
            result.as_ref().expect("refining the band");
        }
        m.check().unwrap();
        assert!((rest_area(&m) - area).abs() <= 1e-12 * area);
        for &f in &kept {
            assert!(m.is_face(f), "kept face {f:?} removed ({mode:?})");
        }
    }
}
