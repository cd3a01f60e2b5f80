//! Helpers shared by the unit tests of the core and the strategies (test builds only).

use crate::cloth::Cloth;
use crate::collision::{ContactParams, Obstacle, Obstacles};
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{union_jack, Mesh};
use crate::physics::{ForceModel, Forces, Material};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A cloth of the default material and forces over `mesh` at world positions `x` (m), at rest.
pub fn cloth(mesh: Mesh, x: Vec<Vec3>) -> Cloth {
    Cloth::new(
        mesh,
        x,
        Vec3::zeros(),
        &Material::default(),
        &Forces::default(),
    )
}

/// The `n` x `n` union-jack grid of 1 m x 1 m lying flat: the vertex at rest point `(u, v)` is at
/// `(u + offset.x, v + offset.y, offset.z)` (m).
pub fn flat_cloth(n: usize, offset: Vec3) -> Cloth {
    let mesh = union_jack(n, n, 1.0, 1.0);
    let x = mesh
        .vertices()
        .map(|v| {
            let p = mesh.rest(v);
            Vec3::new(p.x + offset.x, p.y + offset.y, offset.z)
        })
        .collect();
    cloth(mesh, x)
}

/// The flat `n` x `n` grid of [`flat_cloth`] folded by 90 degrees along `u = 0.5`: the half
/// `u > 0.5` stands up along +z.
pub fn folded_cloth(n: usize) -> Cloth {
    let mut cloth = flat_cloth(n, Vec3::zeros());
    for v in cloth.mesh.vertices().collect::<Vec<_>>() {
        let p = cloth.mesh.rest(v);
        if p.x > 0.5 {
            cloth.x[v.0 as usize] = Vec3::new(0.5, p.y, p.x - 0.5);
        }
    }
    cloth
}

/// These obstacles with the default contact parameters.
pub fn obstacles(list: &[Obstacle]) -> Obstacles {
    Obstacles::build(list, &ContactParams::default()).expect("valid test obstacles")
}

/// The face pass over one face `[0, 1, 2]` of the three positions `x` (m) and velocities `v`
/// (m/s) with inverse masses `inv_mass`, no friction, swept from `x_start` when given.
pub fn respond_one_face(
    obs: &Obstacles,
    x_start: Option<&[Vec3]>,
    x: &mut [Vec3],
    v: &mut [Vec3],
    inv_mass: [Real; 3],
) -> crate::collision::FaceContactStats {
    let scratch = &mut crate::collision::FaceScratch::default();
    obs.respond_faces(&[[0, 1, 2]], x_start, x, v, &inv_mass, 0.0, scratch)
}

/// Every force switched off; a test switches on what it checks (`Forces { bending: true,
/// ..no_forces() }`).
pub fn no_forces() -> Forces {
    Forces {
        springs: false,
        spring_damping: false,
        bending: false,
        bending_damping: false,
        gravity: false,
        drag: false,
        ..Forces::default()
    }
}

/// The force model of `material` and `forces` built over `mesh`.
pub fn built(mesh: &Mesh, material: &Material, forces: &Forces) -> ForceModel {
    let mut m = ForceModel::new(material, forces);
    m.rebuild(mesh);
    m
}

/// Rest coordinates lifted to the plane z = 0, one entry per slot.
pub fn lifted(mesh: &Mesh) -> Vec<Vec3> {
    let mut x = vec![Vec3::zeros(); mesh.vertex_slots()];
    for v in mesh.vertices() {
        let r = mesh.rest(v);
        x[v.0 as usize] = Vec3::new(r.x, r.y, 0.0);
    }
    x
}

/// A reproducible sequence of numbers uniform in [0, 1) from `seed` (a 64-bit linear
/// congruential generator, top 53 bits): cheap random input for geometry tests.
pub fn uniform(seed: u64) -> impl FnMut() -> Real {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as Real / (1u64 << 53) as Real
    }
}

/// A randomly deformed state of `mesh`: rest positions plus noise of size `amp` (m), random
/// velocities in [-1, 1] m/s.
pub fn random_state(mesh: &Mesh, seed: u64, amp: Real) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = lifted(mesh);
    let mut v = vec![Vec3::zeros(); x.len()];
    for (xi, vi) in x.iter_mut().zip(v.iter_mut()) {
        for k in 0..3 {
            xi[k] += rng.random_range(-amp..amp);
            vi[k] = rng.random_range(-1.0..1.0);
        }
    }
    (x, v)
}

/// Runs `work` (which touches a pipe) in a thread and returns its error message, failing the test
/// when it has not returned within 5 s; `release` (opening the pipe's other end) then frees the
/// waiting thread.
pub fn error_within_seconds<E: std::fmt::Display>(
    work: impl FnOnce() -> Result<(), E> + Send + 'static,
    release: impl FnOnce(),
) -> String {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(work().map_err(|e| e.to_string())));
    match receive.recv_timeout(std::time::Duration::from_secs(5)) {
        Ok(result) => result.expect_err("the pipe was used as a file"),
        Err(_) => {
            release();
            panic!("waited on a pipe for 5 s");
        }
    }
}

/// Runs `work` on a fresh rayon pool of `threads` threads and returns its value.
pub fn in_pool<R: Send>(threads: usize, work: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
        .install(work)
}

/// A rest pattern (m, by slot) for loose `faces` at world positions `x` (m): each piece of faces
/// joined by shared vertices keeps its world `(x, y)`, moved 100 m along `x` per piece, so
/// vertices of different pieces are far apart in the pattern (two layers, not one piece).
pub fn pieces_pattern(x: &[Vec3], faces: &[[usize; 3]]) -> Vec<Vec2> {
    let mut pieces = petgraph::unionfind::UnionFind::<usize>::new(x.len());
    for f in faces {
        pieces.union(f[0], f[1]);
        pieces.union(f[0], f[2]);
    }
    let labels = pieces.into_labeling();
    let mut roots = labels.clone();
    roots.sort_unstable();
    roots.dedup();
    x.iter()
        .zip(&labels)
        .map(|(p, r)| {
            let piece = roots.binary_search(r).unwrap_or(0);
            Vec2::new(p.x + 100.0 * piece as Real, p.y)
        })
        .collect()
}

/// A refusal memory in which every edge of `mesh` was refused by the energy law at time 0 with a
/// gain no motion pays (1e9 J): each waits `t_simplify` (s).
pub fn every_edge_refused(mesh: &Mesh, t_simplify: Real) -> crate::adapt::RefusalMemory {
    use crate::adapt::{Cause, RefusalMemory};
    let edges: Vec<crate::mesh::EdgeKey> = mesh.edges().map(|(e, _)| e).collect();
    let mut refusals = RefusalMemory::default();
    refusals.remember(mesh, &edges, 0.0, Cause::Energy { gain: 1e9 }, t_simplify);
    refusals
}
