//! The linear system of one `implicit_euler` step, `A_f dv = S b`, kept in element form.
//!
//! `A = M + dt C + sum_j P_j^T B_j P_j + sum_e w_e U_e U_e^T` (kg): the per-vertex mass and drag,
//! one symmetric 3x3 block `B_j = dt D_j + dt² K_j` per spring (acting on `dv_a - dv_b`), and one
//! rank-one Gauss-Newton term per bending element (`U_e` stacks its four modes). The filtered
//! matrix `A_f = S A S + (I - S)` is Baraff-Witkin's filter `S` (0 on fixed slots: pinned
//! vertices and free slots) made invertible: the rows and columns of fixed slots are those of
//! the identity and their right-hand side is 0, so `dv = 0` there. The module-level
//! doc of `implicit_euler` gives the Jacobians; both solvers read this one system, CG through
//! [`System::apply`] and the direct solver through its blocks.

// Index loops over parallel per-slot arrays read clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::math::{Mat3, Real, Vec3};
use crate::physics::forces::bend_modes;
use crate::physics::{ForceModel, SpringMode};

/// The assembled pieces of `S A S` and `S b` for one step; buffers are reused across steps.
#[derive(Clone, Debug, Default)]
pub(super) struct System {
    /// Per spring (in `model.springs()` order): `B_j = dt D_j + dt² K_j` (kg).
    pub(super) spring_blocks: Vec<Mat3>,
    /// Per bending element (in `model.bends()` order): its modes `u1..u4` (1/m up to the `|e|`
    /// factors of MODEL.md (4.11)). Empty when bending and its damping are both off.
    pub(super) bend_u: Vec<[Vec3; 4]>,
    /// Per bending element: the weight `w = dt² (k_b/2) |e|²/(|N1|+|N2|) + dt k_bd |e|` of its
    /// term `w u uᵀ` (kg m²); 0 for a degenerate element (no force, no term).
    pub(super) bend_w: Vec<Real>,
    /// Per slot: `m_i + dt C_i` (kg).
    pub(super) diag: Vec<Real>,
    /// Per slot: the 3x3 diagonal block of `A_f` (kg); the identity at a fixed slot.
    pub(super) diag_blocks: Vec<Mat3>,
    /// Per slot: the right-hand side `dt (f + dt K v)` (N s); 0 at a fixed slot.
    pub(super) b: Vec<Vec3>,
}

impl System {
    /// Builds the system of the step of size `dt` (s) from positions `x` (m), velocities `v`
    /// (m/s) and the total forces `f` (N) at that state. Allocation-free once the buffers have
    /// grown to the mesh.
    pub(super) fn build(
        &mut self,
        model: &ForceModel,
        dt: Real,
        x: &[Vec3],
        v: &[Vec3],
        f: &[Vec3],
    ) {
        let n = x.len();
        let sp = model.springs();
        let ns = sp.len();
        let sw = model.switches();
        let both = model.material().springs == SpringMode::Both;
        self.spring_blocks.resize(ns, Mat3::zeros());
        self.diag_blocks.resize(n, Mat3::zeros());
        self.diag.resize(n, 0.0);
        self.b.resize(n, Vec3::zeros());
        let (mass, drag) = (model.mass(), model.drag());
        for i in 0..n {
            self.diag[i] = mass[i] + if sw.drag { dt * drag[i] } else { 0.0 };
            self.diag_blocks[i] = Mat3::identity() * self.diag[i];
            self.b[i] = f[i];
        }
        let dt2 = dt * dt;
        for j in 0..ns {
            let (a, b) = (sp.a[j] as usize, sp.b[j] as usize);
            let d = x[b] - x[a];
            let len2 = d.norm_squared();
            let (mut kj, mut dj) = (Mat3::zeros(), Mat3::zeros());
            if len2 > 0.0 {
                let len = len2.sqrt();
                let u = d / len;
                let uu = u * u.transpose();
                if sw.springs && (both || len > sp.rest_length[j]) {
                    let geo = (1.0 - sp.rest_length[j] / len).max(0.0);
                    kj = (uu + (Mat3::identity() - uu) * geo) * sp.k[j];
                }
                if sw.spring_damping {
                    dj = uu * sp.kd[j];
                }
            }
            let bj = dj * dt + kj * dt2;
            self.spring_blocks[j] = bj;
            self.diag_blocks[a] += bj;
            self.diag_blocks[b] += bj;
            // f + dt K v: (K v)_a = K_j (v_b - v_a), (K v)_b = -K_j (v_b - v_a).
            let kv = kj * (v[b] - v[a]) * dt;
            self.b[a] += kv;
            self.b[b] -= kv;
        }
        self.build_bending(model, dt, x, v);
        let w = model.inv_mass();
        for i in 0..n {
            self.b[i] *= dt;
            if w[i] == 0.0 {
                self.b[i] = Vec3::zeros();
                self.diag_blocks[i] = Mat3::identity();
            }
        }
    }

    /// Bending, Gauss-Newton: `B = w u uᵀ` with `w = dt² (c/2) + dt k_bd |e|`, and its part of
    /// the right-hand side (before the final factor `dt`).
    fn build_bending(&mut self, model: &ForceModel, dt: Real, x: &[Vec3], v: &[Vec3]) {
        self.bend_u.clear();
        self.bend_w.clear();
        let sw = model.switches();
        if !(sw.bending || sw.bending_damping) {
            return;
        }
        let kb = if sw.bending {
            model.material().k_b
        } else {
            0.0
        };
        let kbd = if sw.bending_damping {
            model.material().k_bd
        } else {
            0.0
        };
        for &ids in &model.bends().v {
            let ids = ids.map(|i| i as usize);
            let Some(m) = bend_modes(x[ids[0]], x[ids[1]], x[ids[2]], x[ids[3]]) else {
                self.bend_u.push([Vec3::zeros(); 4]);
                self.bend_w.push(0.0);
                continue;
            };
            let stiff = 0.5 * kb * m.elastic_scale;
            let wgt = dt * dt * stiff + dt * kbd * m.damping_scale;
            let uv: Real = (0..4).map(|k| m.u[k].dot(&v[ids[k]])).sum();
            for k in 0..4 {
                self.diag_blocks[ids[k]] += m.u[k] * m.u[k].transpose() * wgt;
                // dt K v with K = -stiff u uᵀ.
                self.b[ids[k]] -= m.u[k] * (dt * stiff * uv);
            }
            self.bend_u.push(m.u);
            self.bend_w.push(wgt);
        }
    }

    /// `q = A_f p` (N s for `p` in m/s) for a `p` that is 0 at every fixed slot (as CG's
    /// iterates are), swept over the elements like the force kernel; `q` is 0 at fixed slots.
    /// `model` must be the one the system was built from.
    pub(super) fn apply(&self, model: &ForceModel, p: &[Vec3], q: &mut [Vec3]) {
        let sp = model.springs();
        let w = model.inv_mass();
        for i in 0..p.len() {
            q[i] = p[i] * self.diag[i];
        }
        for j in 0..sp.len() {
            let (a, b) = (sp.a[j] as usize, sp.b[j] as usize);
            let t = self.spring_blocks[j] * (p[a] - p[b]);
            q[a] += t;
            q[b] -= t;
        }
        let bends = model.bends().v.iter().zip(&self.bend_u).zip(&self.bend_w);
        for ((ids, u), &wgt) in bends {
            let s: Real = (0..4).map(|k| u[k].dot(&p[ids[k] as usize])).sum();
            for k in 0..4 {
                q[ids[k] as usize] += u[k] * (s * wgt);
            }
        }
        for (qi, &wi) in q.iter_mut().zip(w) {
            if wi == 0.0 {
                *qi = Vec3::zeros();
            }
        }
    }
}
