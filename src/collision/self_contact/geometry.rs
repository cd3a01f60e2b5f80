//! Geometry of self-contact: closest points of a point and a triangle and of two segments, and the
//! times at which four moving points become coplanar (the continuous test).
//!
//! A contact is a [`Stencil`] of four cloth vertices with weights summing to zero: the point and
//! the face's barycentric weights negated (vertex-face), or the two edges' weights with the
//! second negated (edge-edge). `sum w_i x_i` is then the vector from the face or second edge's
//! closest point to the point or first edge's (Bridson, Fedkiw & Anderson 2002, §7.1).

use crate::math::{Real, Vec3};

/// Four vertices (slots) and their weights: `sum w_i x_i` is the gap vector between the two
/// closest points, from the second element to the first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stencil {
    /// Vertex slots: the point and the face's three, or the first edge's two and the second's.
    pub v: [usize; 4],
    /// Weights, summing to 0.
    pub w: [Real; 4],
}

impl Stencil {
    /// Vertex-face stencil: point `p` and face `f` with barycentric weights `b` of the closest
    /// point.
    pub fn vertex_face(p: usize, f: [usize; 3], b: [Real; 3]) -> Stencil {
        Stencil {
            v: [p, f[0], f[1], f[2]],
            w: [1.0, -b[0], -b[1], -b[2]],
        }
    }

    /// Edge-edge stencil: edges `e1`, `e2` with closest points at parameters `s` on `e1` and
    /// `t` on `e2` (0 at the first vertex, 1 at the second).
    pub fn edge_edge(e1: [usize; 2], e2: [usize; 2], s: Real, t: Real) -> Stencil {
        Stencil {
            v: [e1[0], e1[1], e2[0], e2[1]],
            w: [1.0 - s, s, t - 1.0, -t],
        }
    }

    /// `sum w_i y_i` over the stencil's vertices of a per-vertex field `y` (positions: the gap
    /// vector in m; velocities: the relative velocity in m/s).
    pub fn combine(&self, y: &[Vec3]) -> Vec3 {
        (0..4).map(|k| self.w[k] * y[self.v[k]]).sum()
    }
}

/// Barycentric weights `(u, v, w)` of the point of triangle `(a, b, c)` closest to `p`
/// (Ericson, Real-Time Collision Detection, §5.1.5). A degenerate triangle gives one of its
/// edges' or vertices' closest points.
pub fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> [Real; 3] {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - w, w];
    }
    let sum = va + vb + vc;
    if sum.abs() <= Real::MIN_POSITIVE || !sum.is_finite() {
        // Degenerate (zero-area) triangle: the best of its three edges.
        let edges = [(a, b, 0, 1), (b, c, 1, 2), (c, a, 2, 0)];
        let mut best = (Real::INFINITY, [1.0, 0.0, 0.0]);
        for (q0, q1, i, j) in edges {
            let s = closest_on_segment(p, q0, q1);
            let d = (p - (q0 + (q1 - q0) * s)).norm_squared();
            if d < best.0 {
                let mut weights = [0.0; 3];
                weights[i] = 1.0 - s;
                weights[j] = s;
                best = (d, weights);
            }
        }
        return best.1;
    }
    let (v, w) = (vb / sum, vc / sum);
    [1.0 - v - w, v, w]
}

/// Parameter in `[0, 1]` of the point of segment `a -> b` closest to `p`.
fn closest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Real {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 <= Real::MIN_POSITIVE {
        return 0.0;
    }
    ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
}

/// Parameters `(s, t)` in `[0, 1]` of the closest points of segments `p1 -> q1` and `p2 -> q2`
/// (Ericson, §5.1.9); parallel segments give one of the closest pairs.
pub fn closest_between_segments(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> (Real, Real) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let tiny = Real::MIN_POSITIVE;
    if a <= tiny && e <= tiny {
        return (0.0, 0.0);
    }
    if a <= tiny {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(&r);
    if e <= tiny {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(&d2);
    let denom = a * e - b * b;
    let mut s = if denom > 1e-14 * a * e {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (s, t)
}

/// Bisection steps on a bracketed root: the interval `[0, 1]` shrinks below `2^-52`.
const BISECTIONS: usize = 52;

/// The times `t` in `[0, 1]` (ascending, at most three) at which the four points `x0[k] + t
/// dx[k]` are coplanar: the roots of the cubic `(x1 - x0) . ((x2 - x0) x (x3 - x0))`. Each root
/// is bracketed between the cubic's turning points and found by bisection, so no root with a
/// sign change is missed; a double root (touching without crossing) is found when the cubic
/// reaches exactly 0 at a bracket's end, else the proximity test covers it.
pub fn coplanar_times(x0: [Vec3; 4], dx: [Vec3; 4]) -> ([Real; 3], usize) {
    let (a0, b0, c0) = (x0[1] - x0[0], x0[2] - x0[0], x0[3] - x0[0]);
    let (a1, b1, c1) = (dx[1] - dx[0], dx[2] - dx[0], dx[3] - dx[0]);
    let coef = [
        a0.dot(&b0.cross(&c0)),
        a1.dot(&b0.cross(&c0)) + a0.dot(&b1.cross(&c0)) + a0.dot(&b0.cross(&c1)),
        a0.dot(&b1.cross(&c1)) + a1.dot(&b1.cross(&c0)) + a1.dot(&b0.cross(&c1)),
        a1.dot(&b1.cross(&c1)),
    ];
    // The cubic lies in the convex hull of its Bernstein coefficients on [0, 1]: all of one
    // strict sign, no root (most pairs).
    let bernstein = [
        coef[0],
        coef[0] + coef[1] / 3.0,
        coef[0] + (2.0 * coef[1] + coef[2]) / 3.0,
        coef[0] + coef[1] + coef[2] + coef[3],
    ];
    if bernstein.iter().all(|&b| b > 0.0) || bernstein.iter().all(|&b| b < 0.0) {
        return ([0.0; 3], 0);
    }
    let f = |t: Real| ((coef[3] * t + coef[2]) * t + coef[1]) * t + coef[0];
    // Split [0, 1] at the turning points (roots of 3 c3 t^2 + 2 c2 t + c1) inside it.
    let mut cuts = [0.0, 1.0, 1.0, 1.0];
    let mut n_cuts = 1;
    for t in quadratic_roots(3.0 * coef[3], 2.0 * coef[2], coef[1]) {
        if t > 0.0 && t < 1.0 {
            cuts[n_cuts] = t;
            n_cuts += 1;
        }
    }
    cuts[n_cuts] = 1.0;
    cuts[..=n_cuts].sort_by(Real::total_cmp);
    let mut roots = [0.0; 3];
    let mut count = 0;
    for k in 0..n_cuts {
        let (mut lo, mut hi) = (cuts[k], cuts[k + 1]);
        let (flo, fhi) = (f(lo), f(hi));
        if flo == 0.0 {
            push_root(&mut roots, &mut count, lo);
            continue;
        }
        if fhi == 0.0 {
            push_root(&mut roots, &mut count, hi);
            continue;
        }
        if (flo > 0.0) == (fhi > 0.0) {
            continue;
        }
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if (f(mid) > 0.0) == (flo > 0.0) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        push_root(&mut roots, &mut count, 0.5 * (lo + hi));
    }
    (roots, count)
}

/// Appends `t` unless it repeats the last root.
fn push_root(roots: &mut [Real; 3], count: &mut usize, t: Real) {
    if (*count == 0 || roots[*count - 1] != t) && *count < 3 {
        roots[*count] = t;
        *count += 1;
    }
}

/// Real roots of `a t^2 + b t + c` (none, one or two; a linear equation when `a = 0`).
fn quadratic_roots(a: Real, b: Real, c: Real) -> impl Iterator<Item = Real> {
    let mut out = [Real::NAN; 2];
    if a == 0.0 {
        if b != 0.0 {
            out[0] = -c / b;
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            // The stable form: no cancellation between -b and the root of the discriminant.
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            out[0] = q / a;
            if q != 0.0 {
                out[1] = c / q;
            }
        }
    }
    out.into_iter().filter(|t| t.is_finite())
}
