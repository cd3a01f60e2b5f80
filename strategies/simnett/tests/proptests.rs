//! Property tests: random grids (2x2 to 9x9 cells, random aspect), random deformation and
//! velocities, random sequences of 200-300 split/merge operations (valid and invalid), through
//! the cloth ([`ClothTarget`], mass and momentum) and the bare mesh in lockstep. After every
//! operation: conformity, hierarchy consistency (states match the split status of the edges,
//! depth at most `max_depth`), total mass, rest area and linear momentum unchanged (relative
//! 1e-12; velocities are perturbed randomly before every operation, as the dynamics would), an
//! error leaves everything untouched. A split immediately merged restores the mesh
//! exactly; merging everything at the end returns the initial mesh.
//!
//! Cases: `PROPTEST_CASES` (default 64).

use super::*;
use crate::adapt::{ClothTarget, EditTarget, TransferOptions};
use crate::mesh::{Edit, EditError, EditRecord};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(64);
    ProptestConfig::with_cases(cases)
}

/// One random operation: `kind` 0 split then merge back, 1-4 split, 5-7 merge, 8-9 forced split;
/// `pick` chooses the edge.
type Op = (u8, u32);

const REL: Real = 1e-12;

/// The edge an operation targets: mostly mesh edges (leaves or temporary edges) for splits and
/// split edges for merges, sometimes any hierarchy edge or a vertex pair that is no edge.
fn choose(kind: u8, pick: u32, h: &Hierarchy, mesh: &Mesh) -> EdgeKey {
    let p = pick as usize;
    if p % 41 == 0 {
        let vs: Vec<VertexId> = mesh.vertices().collect();
        return EdgeKey::new(vs[p / 41 % vs.len()], vs[(p / 7 + 3) % vs.len()]);
    }
    let split: Vec<EdgeKey> = h
        .edges()
        .filter(|(_, n)| n.mid.is_some())
        .map(|(e, _)| e)
        .collect();
    let list: Vec<EdgeKey> = if (5..=7).contains(&kind) && !split.is_empty() && p % 5 != 0 {
        split
    } else if p % 9 == 0 {
        h.edges().map(|(e, _)| e).collect()
    } else {
        mesh.edges().map(|(e, _)| e).collect()
    };
    list[(p / 3) % list.len()]
}

/// Rest coordinates of the live vertices.
fn rest_points(mesh: &Mesh) -> Vec<(VertexId, [u64; 2])> {
    mesh.vertices()
        .map(|w| {
            let p = mesh.rest(w);
            (w, [p.x.to_bits(), p.y.to_bits()])
        })
        .collect()
}

struct Reference {
    mass: Real,
    area: Real,
    momentum: Vec3,
}

fn check_all(
    cloth: &Cloth,
    h: &Hierarchy,
    max_depth: u32,
    r: &Reference,
    what: &str,
) -> Result<(), TestCaseError> {
    let mesh = &cloth.mesh;
    if let Err(e) = mesh.check() {
        return Err(TestCaseError::fail(format!("{what}: not conforming: {e}")));
    }
    if let Err(e) = h.check(mesh, max_depth) {
        return Err(TestCaseError::fail(format!("{what}: hierarchy: {e}")));
    }
    prop_assert!(
        h.max_depth() <= max_depth,
        "{}: depth {}",
        what,
        h.max_depth()
    );
    let mass = cloth.model.total_mass();
    prop_assert!(
        (mass - r.mass).abs() <= REL * r.mass,
        "{}: mass {} -> {}",
        what,
        r.mass,
        mass
    );
    let area: Real = mesh.faces().map(|f| mesh.face_rest_area(f)).sum();
    prop_assert!(
        (area - r.area).abs() <= REL * r.area,
        "{}: area {} -> {}",
        what,
        r.area,
        area
    );
    let p = cloth.linear_momentum();
    prop_assert!(
        (p - r.momentum).norm() <= REL * r.momentum.norm(),
        "{}: momentum {:?} -> {:?}",
        what,
        r.momentum,
        p
    );
    Ok(())
}

fn run(
    cells: usize,
    aspect: Real,
    seed: u64,
    max_depth: u32,
    ops: &[Op],
) -> Result<(), TestCaseError> {
    let mesh = union_jack(cells + 1, cells + 1, 1.0, aspect);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut noise = |s: Real| rng.random_range(-s..s);
    let x: Vec<Vec3> = (0..mesh.vertex_slots())
        .map(|i| {
            let p = mesh.rest(VertexId(i as u32));
            Vec3::new(p.x + noise(0.05), p.y + noise(0.05), noise(0.3))
        })
        .collect();
    let mut cloth = crate::testing::cloth(mesh.clone(), x);
    for i in 0..cloth.v.len() {
        cloth.v[i] = Vec3::new(0.5 + noise(1.0), -0.3 + noise(1.0), 0.2 + noise(1.0));
    }
    let mut reference = Reference {
        mass: cloth.model.total_mass(),
        area: mesh.pattern_area(),
        momentum: cloth.linear_momentum(),
    };
    let mut bare = mesh.clone();
    let mut h = Hierarchy::new(&cloth.mesh);
    let mut hb = h.clone();
    let initial = (triples(&mesh), rest_points(&mesh));
    let mut applied = 0;
    for (i, &(kind, pick)) in ops.iter().enumerate() {
        let e = choose(kind, pick, &h, &cloth.mesh);
        // The dynamics between operations: velocities drift from the interpolated ones (without
        // it, every vertex velocity stays the linear interpolant of the initial corners and any
        // retiling conserves momentum trivially).
        for w in cloth.mesh.vertices().collect::<Vec<_>>() {
            cloth.v[w.0 as usize] += Vec3::new(noise(0.2), noise(0.2), noise(0.2));
        }
        reference.momentum = cloth.linear_momentum();
        let before = (
            cloth.mesh.clone(),
            h.clone(),
            cloth.x.clone(),
            cloth.v.clone(),
        );
        let topology = (triples(&cloth.mesh), rest_points(&cloth.mesh));
        let what = format!("op {i} kind {kind} on {e:?}");
        let mut target = AsItComes(ClothTarget::new(
            &mut cloth,
            TransferOptions {
                restore_momentum: true,
                ..TransferOptions::default()
            },
        ));
        let (result, result_bare) = match kind {
            0..=4 => (
                h.split_edge(&mut target, e, max_depth, i as Real)
                    .map(|r| vec![r]),
                hb.split_edge(&mut bare, e, max_depth, i as Real)
                    .map(|r| vec![r]),
            ),
            5..=7 => (
                h.merge_edge(&mut target, e, i as Real).map(|r| vec![r]),
                hb.merge_edge(&mut bare, e, i as Real).map(|r| vec![r]),
            ),
            _ => (
                h.split_edge_forced(&mut target, e, max_depth, i as Real),
                hb.split_edge_forced(&mut bare, e, max_depth, i as Real),
            ),
        };
        cloth.refresh();
        prop_assert_eq!(
            &result,
            &result_bare,
            "{}: cloth and bare mesh disagree",
            what
        );
        prop_assert!(cloth.mesh == bare, "{}: meshes differ", what);
        prop_assert!(h == hb, "{}: hierarchies differ", what);
        if let Err(err) = &result {
            prop_assert!(
                !matches!(err, OpError::Edit(_)),
                "{}: the mesh refused the hierarchy's edit: {}",
                what,
                err
            );
            prop_assert!(
                (&cloth.mesh, &h, &cloth.x, &cloth.v)
                    == (&before.0, &before.1, &before.2, &before.3),
                "{}: refused ({}) but something changed",
                what,
                err
            );
        } else {
            applied += 1;
        }
        check_all(&cloth, &h, max_depth, &reference, &what)?;
        if kind == 0 && result.is_ok() {
            let mut target = AsItComes(ClothTarget::new(
                &mut cloth,
                TransferOptions {
                    restore_momentum: true,
                    ..TransferOptions::default()
                },
            ));
            let undo = h.merge_edge(&mut target, e, i as Real);
            let undo_bare = hb.merge_edge(&mut bare, e, i as Real);
            cloth.refresh();
            prop_assert!(
                undo.is_ok(),
                "{}: merge after split refused: {:?}",
                what,
                undo
            );
            prop_assert_eq!(&undo, &undo_bare);
            check_all(&cloth, &h, max_depth, &reference, &what)?;
            prop_assert_eq!(
                (triples(&cloth.mesh), rest_points(&cloth.mesh)),
                topology,
                "{}: split + merge did not restore the mesh",
                what
            );
        }
    }
    prop_assert!(applied > 0);
    // Merge everything, deepest first: always possible, and gives the initial mesh back.
    loop {
        let mut split: Vec<(std::cmp::Reverse<u32>, EdgeKey)> = h
            .edges()
            .filter(|(_, n)| n.mid.is_some())
            .map(|(e, n)| (std::cmp::Reverse(n.depth), e))
            .collect();
        if split.is_empty() {
            break;
        }
        split.sort();
        let (_, e) = split[0];
        let mut target = AsItComes(ClothTarget::new(
            &mut cloth,
            TransferOptions {
                restore_momentum: true,
                ..TransferOptions::default()
            },
        ));
        let r = h.merge_edge(&mut target, e, 0.0);
        cloth.refresh();
        prop_assert!(r.is_ok(), "merge-all: {:?} refused: {:?}", e, r);
        check_all(&cloth, &h, max_depth, &reference, "merge-all")?;
    }
    prop_assert_eq!((triples(&cloth.mesh), rest_points(&cloth.mesh)), initial);
    prop_assert_eq!(h.triangles().count(), mesh.face_count());
    prop_assert_eq!(h.edges().count(), mesh.edge_count());
    Ok(())
}

/// The cloth edited with every edit applied as it comes, also those the operations ask under the
/// energy law: the cloth and the bare mesh then see the same operations succeed, edit for edit
/// (the law's refusals are the strategy's concern, tested with the strategies).
struct AsItComes<'a, 'o>(ClothTarget<'a, 'o>);

impl EditTarget for AsItComes<'_, '_> {
    fn mesh(&self) -> &Mesh {
        self.0.mesh()
    }

    fn apply(&mut self, edit: &Edit) -> Result<EditRecord, EditError> {
        self.0.apply(edit)
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_split_merge_sequences_keep_every_invariant(
        cells in 2usize..=9,
        aspect in 0.5f64..2.0,
        seed in any::<u64>(),
        max_depth in 1u32..=4,
        ops in prop::collection::vec((0u8..10, any::<u32>()), 200..=300),
    ) {
        run(cells, aspect, seed, max_depth, &ops)?;
    }
}
