//! The linear system of one `implicit_euler` step, `A_f dv = S b`, kept in element form.
//!
//! `A = M + dt C + sum_j P_j^T B_j P_j + sum_e w_e U_e U_e^T` (kg): the per-vertex mass and drag,
//! one symmetric 3x3 block `B_j = dt D_j + dt² K_j` per spring (acting on `dv_a - dv_b`), and one
//! rank-one Gauss-Newton term per bending element (`U_e` stacks its four modes). The filtered
//! matrix `A_f = S A S + (I - S)` is Baraff-Witkin's filter `S` (0 on fixed slots: pinned
//! vertices and free slots) made invertible: the rows and columns of fixed slots are those of
//! the identity and their right-hand side is 0, so `dv = 0` there. A held contact
//! ([`crate::physics::Hold`]) is the same filter along one direction: `S = I - n nᵀ` on its
//! slot, so `dv . n = 0` there and the rest of its row is solved. The module-level
//! doc of `implicit_euler` gives the Jacobians; both solvers read this one system, CG through
//! [`System::apply`] and the direct solver through its blocks.

// Index loops over parallel per-slot arrays read clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::math::{Mat3, Real, Vec3};
use crate::physics::chunks::{Chunk, Indexed, Part, Phase, Window};
use crate::physics::forces::bend_modes;
use crate::physics::{ForceModel, Hold, PressedFace, SpringMode};

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
    /// Per slot: the right-hand side `dt (f + dt K v)` (N s); 0 at a fixed slot, without its
    /// part along `n` at a held slot.
    pub(super) b: Vec<Vec3>,
    /// The contacts held in this step's system, each slot once.
    held: Vec<Held>,
    /// Per slot: the normal of its held contact, `None` where none is held.
    pub(super) held_at: Vec<Option<Vec3>>,
    /// The faces pressed in this step's system ([`System::press`]), each with the weight
    /// `dt² k` (kg) of its term `dt² k c cᵀ`, `c` the 3n-vector holding `w_k n` at its slot `k`.
    pub(super) pressed: Vec<(PressedFace, Real)>,
}

/// One contact held in the system.
#[derive(Clone, Copy, Debug)]
struct Held {
    /// Its index in the caller's list of holds.
    hold: usize,
    slot: usize,
    /// The outward unit normal `n`.
    normal: Vec3,
    /// `n . b` of the unfiltered right-hand side (N s).
    b_normal: Real,
}

impl System {
    /// Builds the system of the step of size `dt` (s) from positions `x` (m), velocities `v`
    /// (m/s) and the total forces `f` (N) at that state, the elements' terms by chunks on the
    /// threads of the pool (the same sums in the same order on any number of threads).
    /// Allocation-free once the buffers have grown to the mesh. No contact is held until
    /// [`System::hold`].
    pub(super) fn build(
        &mut self,
        model: &ForceModel,
        dt: Real,
        x: &[Vec3],
        v: &[Vec3],
        f: &[Vec3],
    ) {
        let n = x.len();
        for h in &self.held {
            self.held_at[h.slot] = None;
        }
        self.held.clear();
        self.held_at.resize(n, None);
        self.pressed.clear();
        let sw = model.switches();
        let terms = Terms::of(model, dt);
        let bending = sw.bending || sw.bending_damping;
        let bends = if bending { model.bends().len() } else { 0 };
        self.spring_blocks
            .resize(model.springs().len(), Mat3::zeros());
        self.bend_u.resize(bends, [Vec3::zeros(); 4]);
        self.bend_w.resize(bends, 0.0);
        self.diag_blocks.resize(n, Mat3::zeros());
        self.diag.resize(n, 0.0);
        self.b.resize(n, Vec3::zeros());
        let (mass, drag) = (model.mass(), model.drag());
        for i in 0..n {
            self.diag[i] = mass[i] + if sw.drag { dt * drag[i] } else { 0.0 };
            self.diag_blocks[i] = Mat3::identity() * self.diag[i];
            self.b[i] = f[i];
        }
        for phase in Phase::BOTH {
            let slots = (
                Window::whole(&mut self.diag_blocks),
                Window::whole(&mut self.b),
            );
            let elements = (
                Part::whole(&mut self.spring_blocks, Indexed::Springs),
                bending.then(|| {
                    (
                        Part::whole(&mut self.bend_u, Indexed::Bends),
                        Part::whole(&mut self.bend_w, Indexed::Bends),
                    )
                }),
            );
            model.sweep_phase(phase, (slots, elements), &|chunk: &Chunk, parts| {
                terms.add(model, chunk, x, v, parts)
            });
        }
        let w = model.inv_mass();
        for i in 0..n {
            self.b[i] *= dt;
            if w[i] == 0.0 {
                self.b[i] = Vec3::zeros();
                self.diag_blocks[i] = Mat3::identity();
            }
        }
    }

    /// `q = A_f p` (N s for `p` in m/s) for a `p` that is 0 at every fixed slot (as CG's
    /// iterates are), swept over the elements like the force kernel, by the same chunks on the
    /// threads of the pool (the same sums in the same order on any number of threads); `q` is 0
    /// at fixed slots. `model` must be the one the system was built from.
    pub(super) fn apply(&self, model: &ForceModel, p: &[Vec3], q: &mut [Vec3]) {
        self.product(model, p, q);
        for (qi, &wi) in q.iter_mut().zip(model.inv_mass()) {
            if wi == 0.0 {
                *qi = Vec3::zeros();
            }
        }
        self.project(q);
    }

    /// `q = A p` (N s for `p` in m/s), unfiltered.
    fn product(&self, model: &ForceModel, p: &[Vec3], q: &mut [Vec3]) {
        for i in 0..p.len() {
            q[i] = p[i] * self.diag[i];
        }
        for (face, weight) in &self.pressed {
            let s = weight * face.height_of(p);
            for k in 0..3 {
                q[face.slots[k]] += face.normal * (s * face.weights[k]);
            }
        }
        for phase in Phase::BOTH {
            model.sweep_phase(phase, Window::whole(q), &|chunk: &Chunk, window| {
                self.apply_elements(model, chunk, p, window)
            });
        }
    }

    /// Adds the stiffness of each face of `faces` the penalty presses at positions `x` (m) to
    /// the system of a step `dt` (s) linearised at velocities `w` (m/s): `dt² k c cᵀ` to the
    /// matrix (its diagonal blocks here, the rest in the product and the direct solver's
    /// assembly) and `-dt² k c (cᵀ w)` to the right-hand side, at free slots; the penalty's
    /// force must already be in the `f` given to [`System::build`]. Call after it, before
    /// [`System::hold`].
    pub(super) fn press(
        &mut self,
        faces: &[PressedFace],
        dt: Real,
        x: &[Vec3],
        w: &[Vec3],
        inv_mass: &[Real],
    ) {
        for face in faces.iter().filter(|face| face.depth(x) > 0.0) {
            let weight = dt * dt * face.stiffness;
            let normal_speed = face.height_of(w);
            let nn = face.normal * face.normal.transpose();
            for k in 0..3 {
                let (i, wk) = (face.slots[k], face.weights[k]);
                if inv_mass[i] == 0.0 {
                    continue;
                }
                self.b[i] -= face.normal * (weight * wk * normal_speed);
                self.diag_blocks[i] += nn * (weight * wk * wk);
            }
            self.pressed.push((*face, weight));
        }
    }

    /// Holds the contacts of `holds` whose vertex the forces `f` (N, at the step's start)
    /// press into the obstacle (`f . n < 0`) on a free slot, each slot once (the first hold
    /// listed): filters their slot's right-hand side and diagonal block with `S = I - n nᵀ`
    /// (the block becomes `S D S + n nᵀ`) and marks them held; the others' `held` is false.
    /// Every hold's impulse is reset to 0. Call after the
    /// right-hand side is complete, before any solve.
    pub(super) fn hold(&mut self, holds: &mut [Hold], f: &[Vec3], inv_mass: &[Real]) {
        let n = self.b.len();
        for (k, h) in holds.iter_mut().enumerate() {
            h.impulse = 0.0;
            h.held = false;
            let (i, normal) = (h.slot, h.normal);
            let free = i < n && inv_mass[i] != 0.0 && self.held_at[i].is_none();
            if !free || f[i].dot(&normal) >= 0.0 {
                continue;
            }
            let nn = normal * normal.transpose();
            let s = Mat3::identity() - nn;
            let b_normal = normal.dot(&self.b[i]);
            self.b[i] -= normal * b_normal;
            self.diag_blocks[i] = s * self.diag_blocks[i] * s + nn;
            self.held_at[i] = Some(normal);
            h.held = true;
            self.held.push(Held {
                hold: k,
                slot: i,
                normal,
                b_normal,
            });
        }
    }

    /// Removes from `z` (per slot) its part along the normal of every held slot.
    pub(super) fn project(&self, z: &mut [Vec3]) {
        for h in &self.held {
            let zi = &mut z[h.slot];
            *zi -= h.normal * h.normal.dot(zi);
        }
    }

    /// Sets each held contact's impulse (N s) in `holds` (the list given to [`System::hold`])
    /// from the solution `dv` (m/s): `n . (A dv - b)` of the unfiltered system at its slot.
    /// `scratch` holds the product.
    pub(super) fn impulses(
        &self,
        model: &ForceModel,
        dv: &[Vec3],
        scratch: &mut Vec<Vec3>,
        holds: &mut [Hold],
    ) {
        if self.held.is_empty() {
            return;
        }
        scratch.resize(dv.len(), Vec3::zeros());
        self.product(model, dv, scratch);
        for h in &self.held {
            holds[h.hold].impulse = h.normal.dot(&scratch[h.slot]) - h.b_normal;
        }
    }

    /// Adds the products of `chunk`'s springs and bending elements with `p` to the window of
    /// its slots.
    fn apply_elements(&self, model: &ForceModel, chunk: &Chunk, p: &[Vec3], window: Window) {
        let Window { values: q, first } = window;
        let sp = model.springs();
        for j in chunk.springs.clone() {
            let (a, b) = (sp.a[j] as usize, sp.b[j] as usize);
            let t = self.spring_blocks[j] * (p[a] - p[b]);
            q[a - first] += t;
            q[b - first] -= t;
        }
        if self.bend_u.is_empty() {
            return;
        }
        for e in chunk.bends.clone() {
            let (ids, u, wgt) = (model.bends().v[e], &self.bend_u[e], self.bend_w[e]);
            let s: Real = (0..4).map(|k| u[k].dot(&p[ids[k] as usize])).sum();
            for k in 0..4 {
                q[ids[k] as usize - first] += u[k] * (s * wgt);
            }
        }
    }
}

/// The parts of the system's arrays a chunk of elements adds to: the diagonal blocks and the
/// right-hand side by slot (two windows of the same slots); the springs' blocks; the bending
/// elements' modes and weights (`None` when bending and its damping are off).
type BuildParts<'a> = (
    (Window<'a, Mat3>, Window<'a, Vec3>),
    (
        Part<'a, Mat3>,
        Option<(Part<'a, [Vec3; 4]>, Part<'a, Real>)>,
    ),
);

/// What the elements' terms of one step's system need besides the state.
struct Terms {
    /// The step `dt` (s).
    dt: Real,
    /// `dt²` (s²).
    dt2: Real,
    /// Springs act in compression too (`SpringMode::Both`).
    both: bool,
    /// The springs' elastic force is on.
    springs: bool,
    /// The springs' damping is on.
    spring_damping: bool,
    /// The bending stiffness `k_b` (N m) and damping `k_bd` (N m s), 0 where switched off.
    kb: Real,
    kbd: Real,
}

impl Terms {
    fn of(model: &ForceModel, dt: Real) -> Terms {
        let sw = model.switches();
        let material = model.material();
        Terms {
            dt,
            dt2: dt * dt,
            both: material.springs == SpringMode::Both,
            springs: sw.springs,
            spring_damping: sw.spring_damping,
            kb: if sw.bending { material.k_b } else { 0.0 },
            kbd: if sw.bending_damping {
                material.k_bd
            } else {
                0.0
            },
        }
    }

    /// Adds the terms of `chunk`'s springs and bending elements to its parts: per spring
    /// `B_j = dt D_j + dt² K_j` and `dt K_j (v_b - v_a)` on the right-hand side; per bending
    /// element (Gauss-Newton) `B = w u uᵀ` with `w = dt² (k_b/2) |e|²/(|N1|+|N2|) + dt k_bd
    /// |e|` and its part of the right-hand side (before the final factor `dt`).
    fn add(&self, model: &ForceModel, chunk: &Chunk, x: &[Vec3], v: &[Vec3], parts: BuildParts) {
        let ((diag, b), (blocks, bends)) = parts;
        debug_assert_eq!(diag.first, b.first, "two windows of the same slots");
        let (first, diag, b) = (diag.first, diag.values, b.values);
        let sp = model.springs();
        for j in chunk.springs.clone() {
            let (ia, ib) = (sp.a[j] as usize, sp.b[j] as usize);
            let d = x[ib] - x[ia];
            let len2 = d.norm_squared();
            let (mut kj, mut dj) = (Mat3::zeros(), Mat3::zeros());
            if len2 > 0.0 {
                let len = len2.sqrt();
                let u = d / len;
                let uu = u * u.transpose();
                if self.springs && (self.both || len > sp.rest_length[j]) {
                    let geo = (1.0 - sp.rest_length[j] / len).max(0.0);
                    kj = (uu + (Mat3::identity() - uu) * geo) * sp.k[j];
                }
                if self.spring_damping {
                    dj = uu * sp.kd[j];
                }
            }
            let bj = dj * self.dt + kj * self.dt2;
            blocks.values[j - blocks.first] = bj;
            diag[ia - first] += bj;
            diag[ib - first] += bj;
            // f + dt K v: (K v)_a = K_j (v_b - v_a), (K v)_b = -K_j (v_b - v_a).
            let kv = kj * (v[ib] - v[ia]) * self.dt;
            b[ia - first] += kv;
            b[ib - first] -= kv;
        }
        let Some((bend_u, bend_w)) = bends else {
            return;
        };
        for e in chunk.bends.clone() {
            let ids = model.bends().v[e].map(|i| i as usize);
            let (u_at, w_at) = (e - bend_u.first, e - bend_w.first);
            let Some(m) = bend_modes(x[ids[0]], x[ids[1]], x[ids[2]], x[ids[3]]) else {
                bend_u.values[u_at] = [Vec3::zeros(); 4];
                bend_w.values[w_at] = 0.0;
                continue;
            };
            let stiff = 0.5 * self.kb * m.elastic_scale;
            let wgt = self.dt2 * stiff + self.dt * self.kbd * m.damping_scale;
            let uv: Real = (0..4).map(|k| m.u[k].dot(&v[ids[k]])).sum();
            for k in 0..4 {
                diag[ids[k] - first] += m.u[k] * m.u[k].transpose() * wgt;
                // dt K v with K = -stiff u uᵀ.
                b[ids[k] - first] -= m.u[k] * (self.dt * stiff * uv);
            }
            bend_u.values[u_at] = m.u;
            bend_w.values[w_at] = wgt;
        }
    }
}
