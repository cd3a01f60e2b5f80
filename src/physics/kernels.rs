//! The spring and bending force sweeps, [`LANES`] elements at a time.
//!
//! Each block gathers its elements' vertices into [`Vec3Lanes`], computes the forces of all lanes
//! at once (vector instructions: compiled for AVX2 when the CPU has it, checked once per sweep),
//! then adds them to the vertices element by element, in element order. The per-element
//! arithmetic is the scalar formulas' own, operation for operation, so the forces are bit for bit
//! those of [`bend_modes`] and the spring formula, on every CPU (tested).

use super::chunks::Window;
use super::elements::{Bends, Springs};
#[cfg(doc)]
use super::forces::bend_modes;
use super::forces::{DEGENERATE_RATIO, SLIVER_RATIO};
use super::lanes::{block_ends, block_values, slot_bounds, Lanes, Vec3Lanes, LANES};
use crate::math::{Real, Vec3};
use std::ops::Range;

/// The bending stiffness `k_b` (N m) and damping `k_bd` (N m s) of the material.
#[derive(Clone, Copy, Debug)]
pub(super) struct BendConstants {
    pub elastic: Real,
    pub damping: Real,
}

/// Springs `range` (4.8-4.9), added to `f`: `f_a = [k s / L + kd ((v_b - v_a) . d) / L²] d`,
/// `d = x_b - x_a`, `s = L - L_rest` (clamped at 0 unless `BOTH`); `f_b = -f_a`. A spring with
/// coincident ends has no direction and no force.
pub(super) fn spring_forces<const ELASTIC: bool, const DAMP: bool, const BOTH: bool>(
    springs: &Springs,
    range: Range<usize>,
    x: &[Vec3],
    v: &[Vec3],
    f: Window,
) {
    dispatch!(
        springs_avx2,
        spring_blocks::<ELASTIC, DAMP, BOTH>(springs, range, x, v, f)
    )
}

/// Bridson bending (4.10-4.13) of the elements `range`, added to `f`, elastic and damping parts
/// fused; degenerate elements (see [`bend_modes`]) have no force.
pub(super) fn bend_forces<const ELASTIC: bool, const DAMP: bool>(
    bends: &Bends,
    range: Range<usize>,
    k: BendConstants,
    x: &[Vec3],
    v: &[Vec3],
    f: Window,
) {
    dispatch!(
        bends_avx2,
        bend_blocks::<ELASTIC, DAMP>(bends, range, k, x, v, f)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn springs_avx2<const ELASTIC: bool, const DAMP: bool, const BOTH: bool>(
    springs: &Springs,
    range: Range<usize>,
    x: &[Vec3],
    v: &[Vec3],
    f: Window,
) {
    spring_blocks::<ELASTIC, DAMP, BOTH>(springs, range, x, v, f)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn bends_avx2<const ELASTIC: bool, const DAMP: bool>(
    bends: &Bends,
    range: Range<usize>,
    k: BendConstants,
    x: &[Vec3],
    v: &[Vec3],
    f: Window,
) {
    bend_blocks::<ELASTIC, DAMP>(bends, range, k, x, v, f)
}

#[inline(always)]
fn spring_blocks<const ELASTIC: bool, const DAMP: bool, const BOTH: bool>(
    sp: &Springs,
    range: Range<usize>,
    x: &[Vec3],
    v: &[Vec3],
    f: Window,
) {
    let Window { values: f, first } = f;
    let mut sum = RunningSum::default();
    for start in range.clone().step_by(LANES) {
        let live = (range.end - start).min(LANES);
        spring_block::<ELASTIC, DAMP, BOTH>(sp, start, live, x, v, f, first, &mut sum);
    }
    sum.flush(f);
}

/// The force of one window slot kept in registers while consecutive springs add to it (springs
/// are sorted by their first end, so each first end's additions come in one run), written back
/// when the run ends. Every slot receives the same additions in the same order as when each is
/// made in memory, so the sums are bit for bit the same.
struct RunningSum {
    /// The window slot (`usize::MAX`: none).
    slot: usize,
    /// Its force so far (N).
    sum: Vec3,
}

impl Default for RunningSum {
    fn default() -> Self {
        RunningSum {
            slot: usize::MAX,
            sum: Vec3::zeros(),
        }
    }
}

impl RunningSum {
    /// Adds `force` to window slot `slot` (below `f.len()`), starting a new run from `f`'s value
    /// when the slot changes.
    #[inline(always)]
    fn add(&mut self, f: &mut [Vec3], slot: usize, force: Vec3) {
        if slot != self.slot {
            self.flush(f);
            self.slot = slot;
            self.sum = f[slot];
        }
        self.sum += force;
    }

    /// Writes the running sum back to its slot.
    #[inline(always)]
    fn flush(&mut self, f: &mut [Vec3]) {
        if let Some(out) = f.get_mut(self.slot) {
            *out = self.sum;
        }
        self.slot = usize::MAX;
    }
}

/// The springs `start..start + live` (`live <= LANES`), added to `f` (slots from `first`).
/// Panics when an end is outside `x`, `v` or the window: the gathers and the scatter are
/// unchecked once that is checked, block by block.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn spring_block<const ELASTIC: bool, const DAMP: bool, const BOTH: bool>(
    sp: &Springs,
    start: usize,
    live: usize,
    x: &[Vec3],
    v: &[Vec3],
    f: &mut [Vec3],
    first: usize,
    sum: &mut RunningSum,
) {
    let ends = block_ends(start, live, |j| [sp.a[j], sp.b[j]]);
    let (lo, hi) = slot_bounds(&ends);
    assert!(
        hi < x.len() && hi < v.len() && lo >= first && hi - first < f.len(),
        "spring slots {lo}..={hi} outside the state or the window"
    );
    let [ia, ib] = ends;
    // SAFETY: every slot of `ia` and `ib` is below `x.len()` (checked above).
    let d = unsafe { Vec3Lanes::gather_unchecked(x, ib) - Vec3Lanes::gather_unchecked(x, ia) };
    let len2 = d.norm_squared();
    let mut c = Lanes::splat(0.0);
    if ELASTIC {
        let len = len2.sqrt();
        let stretch = len - block_values(&sp.rest_length, start, live);
        let stretch = if BOTH {
            stretch
        } else {
            stretch.max(Lanes::splat(0.0))
        };
        c = c + block_values(&sp.k, start, live) * stretch / len;
    }
    if DAMP {
        // SAFETY: every slot of `ia` and `ib` is below `v.len()` (checked above).
        let dv = unsafe { Vec3Lanes::gather_unchecked(v, ib) - Vec3Lanes::gather_unchecked(v, ia) };
        c = c + block_values(&sp.kd, start, live) * dv.dot(&d) / len2;
    }
    let fa = d.scale(c);
    for l in 0..live {
        // `!(len2 <= 0)`: a NaN length goes on and shows in the forces.
        if len2.0[l] <= 0.0 {
            continue;
        }
        let fl = fa.lane(l);
        sum.add(f, ia[l] - first, fl);
        // `ib[l]` is not the running sum's slot: a spring with both ends on one slot (no mesh
        // edge is one) has `d = 0` and stopped above, unless its position is not finite, and
        // then its forces are NaN whichever the order.
        // SAFETY: `first <= ib[l] < first + f.len()` (checked above).
        unsafe { *f.get_unchecked_mut(ib[l] - first) -= fl };
    }
}

#[inline(always)]
fn bend_blocks<const ELASTIC: bool, const DAMP: bool>(
    bends: &Bends,
    range: Range<usize>,
    k: BendConstants,
    x: &[Vec3],
    v: &[Vec3],
    f: Window,
) {
    let Window { values: f, first } = f;
    for start in range.clone().step_by(LANES) {
        let live = (range.end - start).min(LANES);
        bend_block::<ELASTIC, DAMP>(bends, start, live, k, x, v, f, first);
    }
}

/// The bending elements `start..start + live` (`live <= LANES`), added to `f` (slots from
/// `first`). Panics when a vertex is outside `x`, `v` or the window: the gathers and the scatter
/// are unchecked once that is checked, block by block.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn bend_block<const ELASTIC: bool, const DAMP: bool>(
    bends: &Bends,
    start: usize,
    live: usize,
    k: BendConstants,
    x: &[Vec3],
    v: &[Vec3],
    f: &mut [Vec3],
    first: usize,
) {
    let ids = block_ends(start, live, |j| bends.v[j]);
    let (lo, hi) = slot_bounds(&ids);
    assert!(
        hi < x.len() && hi < v.len() && lo >= first && hi - first < f.len(),
        "bending element slots {lo}..={hi} outside the state or the window"
    );
    // SAFETY: every slot of `ids` is below `x.len()` and `v.len()` (checked above).
    let p = unsafe { gather4(x, &ids) };
    let m = BendLanes::new(&p);
    let mut c = Lanes::splat(0.0);
    if ELASTIC {
        c = c + Lanes::splat(k.elastic) * m.elastic_scale * m.sin_half;
    }
    if DAMP {
        // SAFETY: as for `p`.
        let w = unsafe { gather4(v, &ids) };
        let uv = m.u[0].dot(&w[0]) + m.u[1].dot(&w[1]) + m.u[2].dot(&w[2]) + m.u[3].dot(&w[3]);
        c = c - Lanes::splat(k.damping) * m.damping_scale * uv;
    }
    let [u1, u2, u3, u4] = &m.u;
    let forces = [u1.scale(c), u2.scale(c), u3.scale(c), u4.scale(c)];
    for l in 0..live {
        if !m.sound[l] {
            continue;
        }
        for (slots, force) in ids.iter().zip(&forces) {
            // SAFETY: `first <= slots[l] < first + f.len()` (checked above).
            unsafe { *f.get_unchecked_mut(slots[l] - first) += force.lane(l) };
        }
    }
}

/// The four vertices of a block of bending elements (`array::map` is not always inlined).
///
/// # Safety
/// Every slot of `ids` is below `points.len()`.
#[inline(always)]
unsafe fn gather4(points: &[Vec3], ids: &[[usize; LANES]; 4]) -> [Vec3Lanes; 4] {
    // SAFETY: the caller's contract.
    unsafe {
        [
            Vec3Lanes::gather_unchecked(points, ids[0]),
            Vec3Lanes::gather_unchecked(points, ids[1]),
            Vec3Lanes::gather_unchecked(points, ids[2]),
            Vec3Lanes::gather_unchecked(points, ids[3]),
        ]
    }
}

/// [`bend_modes`] for a block of elements; lanes whose `sound` is false are degenerate and their
/// other fields meaningless.
struct BendLanes {
    u: [Vec3Lanes; 4],
    damping_scale: Lanes,
    elastic_scale: Lanes,
    sin_half: Lanes,
    sound: [bool; LANES],
}

impl BendLanes {
    /// The modes of elements `[x1, x2, x3, x4]`, lane by lane; the operations of [`bend_modes`]
    /// in its order (see there for the formulas).
    #[inline(always)]
    fn new([x1, x2, x3, x4]: &[Vec3Lanes; 4]) -> Self {
        let (x1, x2, x3, x4) = (*x1, *x2, *x3, *x4);
        let e = x4 - x3;
        let e2 = e.norm_squared();
        let n1 = (x1 - x3).cross(&(x1 - x4));
        let n2 = (x2 - x4).cross(&(x2 - x3));
        let n1_sq = n1.norm_squared();
        let n2_sq = n2.norm_squared();
        let tiny = Lanes::splat(DEGENERATE_RATIO * DEGENERATE_RATIO) * e2 * e2;
        let (positive, n1_ok, n2_ok) = (
            e2.greater(Lanes::splat(0.0)),
            n1_sq.greater(tiny),
            n2_sq.greater(tiny),
        );
        let sound = std::array::from_fn(|l| positive[l] && n1_ok[l] && n2_ok[l]);
        let one = Lanes::splat(1.0);
        let e_len = e2.sqrt();
        let inv_e = one / e_len;
        let (n1_len, n2_len) = (n1_sq.sqrt(), n2_sq.sqrt());
        let (inv1_sq, inv2_sq) = (one / n1_sq, one / n2_sq);
        let (w1, w2) = (n1.scale(inv1_sq), n2.scale(inv2_sq));
        let (s1, s2) = (e_len * inv1_sq, e_len * inv2_sq);
        let u = [
            n1.scale(s1),
            n2.scale(s2),
            w1.scale((x1 - x4).dot(&e) * inv_e) + w2.scale((x2 - x4).dot(&e) * inv_e),
            -(w1.scale((x1 - x3).dot(&e) * inv_e) + w2.scale((x2 - x3).dot(&e) * inv_e)),
        ];
        let gap = n1.scale(n2_len) - n2.scale(n1_len);
        let sin_half = Lanes::splat(0.5) * gap.norm_squared().sqrt() / (n1_len * n2_len);
        let sin_half = n1
            .cross(&n2)
            .dot(&e)
            .select_less(Lanes::splat(0.0), -sin_half, sin_half);
        let thinnest = n1_len.min(n2_len);
        let limit = Lanes::splat(SLIVER_RATIO) * e2;
        let ratio = thinnest / limit;
        let sliver = thinnest.select_less(limit, ratio * ratio * ratio, one);
        BendLanes {
            u,
            damping_scale: e_len * sliver,
            elastic_scale: e2 / (n1_len + n2_len) * sliver,
            sin_half,
            sound,
        }
    }
}

#[cfg(test)]
#[path = "kernels_tests.rs"]
mod tests;
