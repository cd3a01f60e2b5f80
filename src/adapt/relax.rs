//! Relaxation of new vertices: after a re-meshing, the vertices it created are moved from their
//! interpolated positions towards the minimum of the elastic energy, the other vertices held, so
//! the new elements do not start out stretched by where interpolation put them. Gravity is left
//! out: the cloth moves, and a held neighbourhood is no equilibrium to sag into.

use crate::cloth::Cloth;
use crate::math::{Mat3, Real, Vec3};
use crate::mesh::VertexId;
use crate::physics::SpringMode;

/// Most descent iterations of one relaxation.
const MAX_ITERATIONS: usize = 50;

/// The relaxation stops when an iteration lowers the potential by less than this fraction of its
/// magnitude (dimensionless).
const MIN_DECREASE: Real = 1e-12;

/// Smallest step fraction tried before an iteration gives up (dimensionless).
const MIN_STEP: Real = 1e-4;

/// Regularisation of a vertex's stiffness block, as a fraction of its springs' summed stiffness
/// (dimensionless): keeps the block invertible when every spring at the vertex is slack.
const REGULARISATION: Real = 1e-3;

/// Lowers the elastic energy of `cloth` (stretch and bending, J) over the positions of the movable
/// `vertices`, every other vertex held; velocities are untouched. Each iteration moves every such
/// vertex by a Newton step of its own springs, `dx_i = s H_i^-1 f_i`, with `f_i` the elastic force
/// and `H_i` the Gauss-Newton stiffness block of its stretched springs (N/m), `s` halved until the
/// energy falls. Never raises the elastic energy. Returns its decrease (J).
pub fn relax(cloth: &mut Cloth, vertices: &[VertexId]) -> Real {
    let inv = cloth.model.inv_mass();
    let mut movable: Vec<usize> = vertices
        .iter()
        .map(|v| v.0 as usize)
        .filter(|&i| inv.get(i).is_some_and(|&w| w > 0.0))
        .collect();
    movable.sort_unstable();
    movable.dedup();
    if movable.is_empty() {
        return 0.0;
    }
    let n = cloth.x.len();
    let still = vec![Vec3::zeros(); n];
    let model = &cloth.model;
    let potential = |x: &[Vec3]| {
        let e = model.energies(x, &still);
        e.stretch + e.bending
    };
    let start = potential(&cloth.x);
    let mut u = start;
    let mut force = vec![Vec3::zeros(); n];
    let mut x = cloth.x.clone();
    let mut trial = x.clone();
    let mut dx = vec![Vec3::zeros(); movable.len()];
    let mut step: Real = 1.0;
    for _ in 0..MAX_ITERATIONS {
        model.internal_forces(&x, &still, &mut force);
        let blocks = stiffness_blocks(cloth, &x, &movable);
        for (k, &i) in movable.iter().enumerate() {
            dx[k] = blocks[k]
                .try_inverse()
                .map_or(Vec3::zeros(), |h| h * force[i]);
        }
        let lowered = loop {
            for (k, &i) in movable.iter().enumerate() {
                trial[i] = x[i] + dx[k] * step;
            }
            let ut = potential(&trial);
            if ut < u {
                break Some(ut);
            }
            step *= 0.5;
            if step < MIN_STEP {
                break None;
            }
        };
        let Some(ut) = lowered else { break };
        let decrease = u - ut;
        u = ut;
        for &i in &movable {
            x[i] = trial[i];
        }
        step = (2.0 * step).min(1.0);
        if decrease <= MIN_DECREASE * u.abs().max(Real::MIN_POSITIVE) {
            break;
        }
    }
    for &i in &movable {
        cloth.x[i] = x[i];
    }
    start - u
}

/// The Gauss-Newton stiffness block (N/m) of every vertex in `movable` (sorted slots): over its
/// springs, `k ((1 - L0/l)+ I + (L0/l) d d^T)` for a stretched spring (and a compressed one with
/// `springs = "both"`), plus the regularisation.
fn stiffness_blocks(cloth: &Cloth, x: &[Vec3], movable: &[usize]) -> Vec<Mat3> {
    let springs = cloth.model.springs();
    let both = cloth.model.material().springs == SpringMode::Both;
    let mut blocks = vec![Mat3::zeros(); movable.len()];
    let mut total = vec![0.0; movable.len()];
    for j in 0..springs.len() {
        let (a, b) = (springs.a[j] as usize, springs.b[j] as usize);
        let ka = movable.binary_search(&a).ok();
        let kb = movable.binary_search(&b).ok();
        if ka.is_none() && kb.is_none() {
            continue;
        }
        let k = springs.k[j];
        let d = x[b] - x[a];
        let l = d.norm();
        let l0 = springs.rest_length[j];
        let block = if l > 0.0 && (both || l > l0) {
            let dir = d / l;
            (Mat3::identity() * (1.0 - l0 / l).max(0.0) + dir * dir.transpose() * (l0 / l)) * k
        } else {
            Mat3::zeros()
        };
        for end in [ka, kb].into_iter().flatten() {
            blocks[end] += block;
            total[end] += k;
        }
    }
    for (block, t) in blocks.iter_mut().zip(total) {
        *block += Mat3::identity() * (REGULARISATION * t);
    }
    blocks
}
