//! Four elements at a time: `LANES` values of one quantity side by side, so the force kernels'
//! arithmetic compiles to vector instructions (one `ymm` register per quantity with AVX2).
//!
//! Every operation is the IEEE operation of one lane, in the same order as the scalar code it
//! mirrors (nalgebra's `dot` is `(x + y) + z`, its `cross` the usual `a_y b_z - a_z b_y`, ...), so a
//! lane kernel gives bit for bit the scalar result: no fused multiply-add, no reassociation.

use crate::math::{Real, Vec3};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Elements per block.
pub(super) const LANES: usize = 4;

/// One scalar per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Lanes(pub [Real; LANES]);

impl Lanes {
    /// The same value in every lane.
    #[inline(always)]
    pub fn splat(value: Real) -> Self {
        Lanes([value; LANES])
    }

    #[inline(always)]
    fn map(self, op: impl Fn(Real) -> Real) -> Self {
        let mut out = self.0;
        for o in &mut out {
            *o = op(*o);
        }
        Lanes(out)
    }

    #[inline(always)]
    fn zip(self, other: Self, op: impl Fn(Real, Real) -> Real) -> Self {
        let mut out = self.0;
        for (o, b) in out.iter_mut().zip(other.0) {
            *o = op(*o, b);
        }
        Lanes(out)
    }

    /// Square root of each lane.
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        self.map(Real::sqrt)
    }

    /// Larger of the two values, lane by lane (`Real::max`: a NaN lane gives `other`).
    #[inline(always)]
    pub fn max(self, other: Self) -> Self {
        self.zip(other, Real::max)
    }

    /// Smaller of the two values, lane by lane (`Real::min`).
    #[inline(always)]
    pub fn min(self, other: Self) -> Self {
        self.zip(other, Real::min)
    }

    /// `if self < other { then } else { otherwise }`, lane by lane.
    #[inline(always)]
    pub fn select_less(self, other: Self, then: Self, otherwise: Self) -> Self {
        Lanes(std::array::from_fn(|l| {
            if self.0[l] < other.0[l] {
                then.0[l]
            } else {
                otherwise.0[l]
            }
        }))
    }

    /// True where the lane is strictly greater than `other` (false for NaN).
    #[inline(always)]
    pub fn greater(self, other: Self) -> [bool; LANES] {
        std::array::from_fn(|l| self.0[l] > other.0[l])
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $method(self, rhs: Lanes) -> Lanes {
                self.zip(rhs, |a, b| a $op b)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(self) -> Lanes {
        self.map(|a| -a)
    }
}

/// One 3-vector per lane, stored as three [`Lanes`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Vec3Lanes {
    pub x: Lanes,
    pub y: Lanes,
    pub z: Lanes,
}

impl Vec3Lanes {
    /// `points[ids[l]]` in lane `l`, without bounds checks.
    ///
    /// # Safety
    /// Every `ids[l]` is below `points.len()`.
    #[inline(always)]
    pub unsafe fn gather_unchecked(points: &[Vec3], ids: [usize; LANES]) -> Self {
        let (mut x, mut y, mut z) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
        for l in 0..LANES {
            // SAFETY: the caller guarantees `ids[l] < points.len()`.
            let p = unsafe { points.get_unchecked(ids[l]) };
            (x[l], y[l], z[l]) = (p.x, p.y, p.z);
        }
        Vec3Lanes {
            x: Lanes(x),
            y: Lanes(y),
            z: Lanes(z),
        }
    }

    /// Lane `l` as a vector.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> Vec3 {
        Vec3::new(self.x.0[l], self.y.0[l], self.z.0[l])
    }

    /// `(x a_x + y a_y) + z a_z`, nalgebra's order.
    #[inline(always)]
    pub fn dot(&self, other: &Self) -> Lanes {
        self.x * other.x + self.y * other.y + self.z * other.z
    }

    /// The squared norm, `self.dot(self)`.
    #[inline(always)]
    pub fn norm_squared(&self) -> Lanes {
        self.dot(self)
    }

    /// The cross product, nalgebra's formula.
    #[inline(always)]
    pub fn cross(&self, b: &Self) -> Self {
        Vec3Lanes {
            x: self.y * b.z - self.z * b.y,
            y: self.z * b.x - self.x * b.z,
            z: self.x * b.y - self.y * b.x,
        }
    }

    /// Each component times the lane's scalar.
    #[inline(always)]
    pub fn scale(&self, s: Lanes) -> Self {
        Vec3Lanes {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl Add for Vec3Lanes {
    type Output = Vec3Lanes;
    #[inline(always)]
    fn add(self, b: Vec3Lanes) -> Vec3Lanes {
        Vec3Lanes {
            x: self.x + b.x,
            y: self.y + b.y,
            z: self.z + b.z,
        }
    }
}

impl Sub for Vec3Lanes {
    type Output = Vec3Lanes;
    #[inline(always)]
    fn sub(self, b: Vec3Lanes) -> Vec3Lanes {
        Vec3Lanes {
            x: self.x - b.x,
            y: self.y - b.y,
            z: self.z - b.z,
        }
    }
}

impl Neg for Vec3Lanes {
    type Output = Vec3Lanes;
    #[inline(always)]
    fn neg(self) -> Vec3Lanes {
        Vec3Lanes {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// The vertex slots of the block of elements starting at `start`: `ends[k][l]` is end `k` of
/// element `start + l`, from `id(j)`. Lanes past the last element (`l >= live`) repeat the block's
/// first element: they are computed and never scattered.
#[inline(always)]
pub(super) fn block_ends<const K: usize>(
    start: usize,
    live: usize,
    id: impl Fn(usize) -> [u32; K],
) -> [[usize; LANES]; K] {
    let elements: [[u32; K]; LANES] =
        std::array::from_fn(|l| id(start + if l < live { l } else { 0 }));
    std::array::from_fn(|k| std::array::from_fn(|l| elements[l][k] as usize))
}

/// `values[start + l]` in lane `l`, lane 0's value in the padding lanes (`l >= live`).
#[inline(always)]
pub(super) fn block_values(values: &[Real], start: usize, live: usize) -> Lanes {
    let mut out = [0.0; LANES];
    for (l, o) in out.iter_mut().enumerate() {
        *o = values[start + if l < live { l } else { 0 }];
    }
    Lanes(out)
}

/// The smallest and the largest slot of a block's ends.
#[inline(always)]
pub(super) fn slot_bounds<const K: usize>(ends: &[[usize; LANES]; K]) -> (usize, usize) {
    let (mut lo, mut hi) = (usize::MAX, 0);
    for slots in ends {
        for &s in slots {
            lo = lo.min(s);
            hi = hi.max(s);
        }
    }
    (lo, hi)
}
