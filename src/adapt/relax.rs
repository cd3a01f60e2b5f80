//! Relaxation of new vertices: after a re-meshing, the vertices it created are moved from their
//! interpolated positions towards the minimum of the elastic energy, the other vertices held, so
//! the new elements do not start out stretched by where interpolation put them. Gravity is left
//! out: the cloth moves, and a held neighbourhood is no equilibrium to sag into.

use crate::cloth::Cloth;
use crate::math::{Mat3, Real, Vec3};
use crate::mesh::VertexId;
use crate::physics::{ForceModel, SpringMode};
use nalgebra::{DMatrix, DVector};

/// Most descent iterations of one relaxation.
const MAX_ITERATIONS: usize = 50;

/// The relaxation stops when an iteration lowers the potential by less than this fraction of its
/// magnitude, or by less than the caller's resolution (dimensionless).
const MIN_DECREASE: Real = 1e-12;

/// Smallest step fraction tried before an iteration gives up (dimensionless).
const MIN_STEP: Real = 1e-4;

/// Regularisation of a vertex's stiffness block, as a fraction of its springs' summed stiffness
/// (dimensionless): keeps the block invertible when every spring at the vertex is slack.
const REGULARISATION: Real = 1e-3;

/// Lowers the elastic energy of `cloth` (stretch and bending, J) over the positions of the movable
/// `vertices`, every other vertex held; velocities are untouched. Each iteration moves them all by
/// one coupled Gauss-Newton step of their springs, `dx = s H^-1 f`, with `f` the elastic forces
/// and `H` the Gauss-Newton stiffness of the stretched springs over the moved vertices (N/m, dense:
/// they are few), `s` halved until the energy falls. Stops when an iteration lowers the energy by
/// at most `resolution` (J; 0 for the tightest stop) or a `1e-12` fraction of it, or as soon as
/// `enough(x, decrease)` holds for the positions `x` an iteration reached and the decrease of the
/// elastic energy so far (J). Never raises the elastic energy. Returns its decrease (J).
pub fn relax(
    cloth: &mut Cloth,
    vertices: &[VertexId],
    resolution: Real,
    enough: impl Fn(&[Vec3], Real) -> bool,
) -> Real {
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
    // Only the elements at the moved vertices change: relax over them alone.
    let model = &cloth.model.around(&movable);
    let potential = |x: &[Vec3]| model.stretch_energy(x) + model.bending_energy(x);
    let start = potential(&cloth.x);
    let mut u = start;
    let mut force = vec![Vec3::zeros(); n];
    let mut x = cloth.x.clone();
    let mut trial = x.clone();
    let mut dx = vec![Vec3::zeros(); movable.len()];
    let mut step: Real = 1.0;
    for _ in 0..MAX_ITERATIONS {
        model.internal_forces(&x, &still, &mut force);
        let h = stiffness(model, &x, &movable);
        let f = DVector::from_iterator(
            3 * movable.len(),
            movable.iter().flat_map(|&i| force[i].iter().copied()),
        );
        let solved = h.cholesky().map(|c| c.solve(&f));
        for (k, d) in dx.iter_mut().enumerate() {
            *d = solved.as_ref().map_or(Vec3::zeros(), |s| {
                Vec3::new(s[3 * k], s[3 * k + 1], s[3 * k + 2])
            });
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
        if decrease <= resolution.max(MIN_DECREASE * u.abs().max(Real::MIN_POSITIVE))
            || enough(&x, start - u)
        {
            break;
        }
    }
    for &i in &movable {
        cloth.x[i] = x[i];
    }
    start - u
}

/// The Gauss-Newton stiffness (N/m) over the vertices in `movable` (sorted slots), `3n x 3n`:
/// each spring adds `K = k ((1 - L0/l)+ I + (L0/l) d d^T)` when stretched (and compressed with
/// `springs = "both"`) to its moved ends' diagonal blocks and `-K` between two moved ends; each
/// diagonal block is regularised. Symmetric positive definite.
fn stiffness(model: &ForceModel, x: &[Vec3], movable: &[usize]) -> DMatrix<Real> {
    let springs = model.springs();
    let both = model.material().springs == SpringMode::Both;
    let mut h = DMatrix::zeros(3 * movable.len(), 3 * movable.len());
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
            let mut diagonal = h.fixed_view_mut::<3, 3>(3 * end, 3 * end);
            diagonal += block;
            total[end] += k;
        }
        if let (Some(p), Some(q)) = (ka, kb) {
            let mut off = h.fixed_view_mut::<3, 3>(3 * p, 3 * q);
            off -= block;
            let mut off = h.fixed_view_mut::<3, 3>(3 * q, 3 * p);
            off -= block;
        }
    }
    for (k, t) in total.into_iter().enumerate() {
        let mut diagonal = h.fixed_view_mut::<3, 3>(3 * k, 3 * k);
        diagonal += Mat3::identity() * (REGULARISATION * t);
    }
    h
}
