//! Per-vertex material parameters and force evaluation over the flat element arrays
//! (MODEL.md §2-§3).
//!
//! Each force family is one sweep: springs (elastic and damping fused), bending elements (elastic
//! and damping fused), then the per-vertex external forces (gravity and drag fused). The switches
//! are resolved once per call into a monomorphised kernel, so a disabled force is never evaluated
//! and the inner loops carry no per-element switch test. Evaluation allocates nothing.

use super::chunks::{Chunk, Chunks, Parts, Phase, Window};
use super::elements::{Bends, Springs};
use super::integrator::Dynamics;
use super::kernels::{bend_forces, spring_forces, BendConstants};
use super::params::{Forces, Material, SpringMode};
use crate::math::{Real, Vec3};
use crate::mesh::{Mesh, VertexId};
use std::ops::Range;

/// A bending element is skipped (no force) when a triangle's doubled area `|N|` falls below this
/// fraction of `|e|²`: the triangle is degenerate (a sliver or collapsed) and its normal undefined.
pub(super) const DEGENERATE_RATIO: Real = 1e-12;

/// Below this ratio `min(|N1|, |N2|) / |e|²` (about a fifth of a right triangle's rest value,
/// 0.5 or 1), a bending element's forces are scaled down by `(ratio / SLIVER_RATIO)³`: the modes
/// grow as `1/|N|`, so the bending stiffness of a triangle squashed to a sliver grows as `1/|N|³`
/// and an explicit step cannot follow it (the extreme-compression case diverged, then, once the
/// step followed, stalled at 4e-12 s). Scaling the whole element keeps the modes, so the forces
/// still sum to zero with zero torque; the references never come near it (smallest ratio 0.37).
/// See docs/model-notes.md, "Sliver bending".
pub(crate) const SLIVER_RATIO: Real = 0.05;

/// A spring sweep over a range of springs, for one combination of the force switches.
type SpringKernel = fn(&Springs, Range<usize>, &[Vec3], &[Vec3], Window);
/// A bending sweep over a range of elements, for one combination of the force switches.
type BendKernel = fn(&Bends, Range<usize>, BendConstants, &[Vec3], &[Vec3], Window);

/// Per-vertex parameters and flat element arrays, plus force evaluation.
///
/// Per-vertex arrays are indexed by vertex slot (length `mesh.vertex_slots()`); free slots have
/// mass 0 and `inv_mass` 0; pinned vertices keep their mass but have `inv_mass` 0. Built empty by
/// [`ForceModel::new`]; call [`ForceModel::rebuild`] for a mesh before evaluating forces.
#[derive(Clone, Debug)]
pub struct ForceModel {
    material: Material,
    switches: Forces,
    g: Vec3,
    mass: Vec<Real>,
    inv_mass: Vec<Real>,
    drag: Vec<Real>,
    springs: Springs,
    bends: Bends,
    /// The elements by vertex windows, for a sweep on several threads.
    chunks: Chunks,
    total_mass: Real,
    min_mass: Real,
    max_stiffness: Real,
}

impl ForceModel {
    /// A model for this material and these force switches, empty until [`ForceModel::rebuild`].
    pub fn new(material: &Material, forces: &Forces) -> Self {
        ForceModel {
            material: material.clone(),
            switches: forces.clone(),
            g: forces.g,
            mass: Vec::new(),
            inv_mass: Vec::new(),
            drag: Vec::new(),
            springs: Springs::default(),
            bends: Bends::default(),
            chunks: Chunks::default(),
            total_mass: 0.0,
            min_mass: 0.0,
            max_stiffness: 0.0,
        }
    }

    /// The material the model was built for.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The force switches and gravity the model evaluates.
    pub fn switches(&self) -> &Forces {
        &self.switches
    }

    /// Rebuilds every vertex parameter and every element for `mesh`, reusing the allocations.
    pub fn rebuild(&mut self, mesh: &Mesh) {
        let slots = mesh.vertex_slots();
        for arr in [&mut self.mass, &mut self.inv_mass, &mut self.drag] {
            arr.clear();
            arr.resize(slots, 0.0);
        }
        for v in mesh.vertices() {
            self.set_vertex(mesh, v);
        }
        self.rebuild_elements(mesh);
    }

    /// Rebuilds the springs and bending elements and the mass statistics (after a topology
    /// change whose vertex parameters were updated with [`ForceModel::update_vertices`]).
    pub fn rebuild_elements(&mut self, mesh: &Mesh) {
        self.refresh_mass_stats();
        self.springs.rebuild(mesh, &self.material);
        self.bends.rebuild(mesh);
        self.refresh_elements();
    }

    /// This model with only the springs and bending elements having a vertex among `slots`
    /// (sorted vertex slots); masses kept. The others' energy and forces do not depend on those
    /// vertices, so while only they move, its elastic energy (J) changes exactly as the whole
    /// model's does and its elastic forces on them (N) are the whole model's.
    pub(crate) fn around(&self, slots: &[usize]) -> ForceModel {
        let mut m = self.clone();
        let keep = |i: u32| slots.binary_search(&(i as usize)).is_ok();
        m.springs.retain_touching(keep);
        m.bends.retain_touching(keep);
        m.refresh_elements();
        m
    }

    /// Recomputes mass, inverse mass and drag coefficient of the listed vertex slots (a slot that
    /// is no longer live gets zeros). The per-vertex arrays are first resized to
    /// `mesh.vertex_slots()` (new slots start at zero). Costs the listed slots only: the mass
    /// statistics ([`ForceModel::total_mass`], [`ForceModel::min_mass`]) follow at the next
    /// [`ForceModel::rebuild_elements`], once per adaptation pass, not once per edit.
    pub fn update_vertices(&mut self, mesh: &Mesh, vertices: &[VertexId]) {
        let slots = mesh.vertex_slots();
        for arr in [&mut self.mass, &mut self.inv_mass, &mut self.drag] {
            arr.resize(slots, 0.0);
        }
        for &v in vertices {
            let i = v.0 as usize;
            if i >= slots {
                continue;
            }
            if mesh.is_vertex(v) {
                self.set_vertex(mesh, v);
            } else {
                self.mass[i] = 0.0;
                self.inv_mass[i] = 0.0;
                self.drag[i] = 0.0;
            }
        }
    }

    /// A model over explicit particles and springs, without a mesh (single-spring tests and the
    /// convergence-order study of `crate::study::integrators`).
    pub(crate) fn from_parts(
        material: &Material,
        forces: &Forces,
        mass: Vec<Real>,
        pinned: &[bool],
        springs: Springs,
    ) -> Self {
        let mut model = ForceModel::new(material, forces);
        model.inv_mass = mass
            .iter()
            .zip(pinned)
            .map(|(&m, &p)| if p || m <= 0.0 { 0.0 } else { 1.0 / m })
            .collect();
        model.drag = vec![0.0; mass.len()];
        model.mass = mass;
        model.springs = springs;
        model.refresh_elements();
        model.refresh_mass_stats();
        model
    }

    fn set_vertex(&mut self, mesh: &Mesh, v: VertexId) {
        let i = v.0 as usize;
        let area = mesh.vertex_rest_area(v);
        let m = area * self.material.thickness * self.material.rho;
        self.mass[i] = m;
        self.inv_mass[i] = if mesh.is_pinned(v) || m <= 0.0 {
            0.0
        } else {
            1.0 / m
        };
        self.drag[i] = area * self.material.kappa;
    }

    /// What follows from the element arrays: the stiffest spring and the chunks.
    fn refresh_elements(&mut self) {
        self.max_stiffness = self.springs.max_stiffness();
        self.chunks = Chunks::build(&self.springs, &self.bends, self.mass.len());
    }

    fn refresh_mass_stats(&mut self) {
        self.total_mass = self.mass.iter().sum();
        self.min_mass = self
            .mass
            .iter()
            .copied()
            .filter(|&m| m > 0.0)
            .fold(Real::INFINITY, Real::min);
        if !self.min_mass.is_finite() {
            self.min_mass = 0.0;
        }
    }

    /// Mass `m_i = A_i T rho` of every vertex slot (kg).
    pub fn mass(&self) -> &[Real] {
        &self.mass
    }

    /// Inverse mass of every slot (1/kg); 0 for pinned vertices and free slots.
    pub fn inv_mass(&self) -> &[Real] {
        &self.inv_mass
    }

    /// Drag coefficient `C_i = A_i kappa` of every slot (N s/m).
    pub fn drag(&self) -> &[Real] {
        &self.drag
    }

    /// The spring arrays.
    pub fn springs(&self) -> &Springs {
        &self.springs
    }

    /// The bending elements.
    pub fn bends(&self) -> &Bends {
        &self.bends
    }

    /// Runs `work` on phase `phase` of the elements' chunks with their parts of `parts` (arrays
    /// over every slot, spring or bending element), on the threads of the pool; a mesh without
    /// chunks is one chunk of every element, swept in the even phase. A sweep runs both phases
    /// ([`Phase::BOTH`]).
    pub(super) fn sweep_phase<P: Parts>(
        &self,
        phase: Phase,
        parts: P,
        work: &(impl Fn(&Chunk, P) + Sync),
    ) {
        if !self.chunks.is_empty() {
            self.chunks.sweep_phase(phase, parts, work);
        } else if phase == Phase::Even {
            let whole = Chunk {
                springs: 0..self.springs.len(),
                bends: 0..self.bends.len(),
                window: 0..self.mass.len(),
            };
            work(&whole, parts);
        }
    }

    /// True when the elements are split in chunks (so sweeps share the pool's threads).
    pub(super) fn is_chunked(&self) -> bool {
        !self.chunks.is_empty()
    }

    /// Sum of all vertex masses, pinned included (kg): `rho T` x the mesh rest area.
    pub fn total_mass(&self) -> Real {
        self.total_mass
    }

    /// Smallest non-zero vertex mass (kg), pinned vertices included; 0 when there is none.
    pub fn min_mass(&self) -> Real {
        self.min_mass
    }

    /// Largest spring stiffness (N/m), whether or not the spring force is switched on; 0 when
    /// there is no spring.
    pub fn max_stiffness(&self) -> Real {
        self.max_stiffness
    }

    /// The stable explicit step `beta pi sqrt(m_min / k_max)` (s), MODEL.md (4.5-4.6).
    /// Infinite when there is no spring; 0 when there is no mass.
    pub fn stable_step(&self, beta: Real) -> Real {
        if self.max_stiffness <= 0.0 {
            return Real::INFINITY;
        }
        beta * std::f64::consts::PI * (self.min_mass / self.max_stiffness).sqrt()
    }

    /// Total force (N) on every slot from all switched-on forces, for positions `x` (m) and
    /// velocities `v` (m/s); `f` is overwritten. Disabled forces are not evaluated. All three
    /// slices have one entry per vertex slot.
    pub fn forces(&self, x: &[Vec3], v: &[Vec3], f: &mut [Vec3]) {
        self.internal_forces(x, v, f);
        let s = &self.switches;
        match (s.gravity, s.drag) {
            (true, true) => self.external::<true, true>(v, f),
            (true, false) => self.external::<true, false>(v, f),
            (false, true) => self.external::<false, true>(v, f),
            (false, false) => {}
        }
    }

    /// Only the internal forces (N): springs, spring damping, bending, bending damping, as
    /// switched on; `f` is overwritten. They sum to zero force and zero torque.
    pub fn internal_forces(&self, x: &[Vec3], v: &[Vec3], f: &mut [Vec3]) {
        debug_assert_eq!(x.len(), self.mass.len());
        debug_assert_eq!(v.len(), self.mass.len());
        debug_assert_eq!(f.len(), self.mass.len());
        f.fill(Vec3::zeros());
        let s = &self.switches;
        let both = self.material.springs == SpringMode::Both;
        let springs: Option<SpringKernel> = match (s.springs, s.spring_damping, both) {
            (true, true, false) => Some(spring_forces::<true, true, false>),
            (true, true, true) => Some(spring_forces::<true, true, true>),
            (true, false, false) => Some(spring_forces::<true, false, false>),
            (true, false, true) => Some(spring_forces::<true, false, true>),
            (false, true, _) => Some(spring_forces::<false, true, false>),
            (false, false, _) => None,
        };
        let bends: Option<BendKernel> = match (s.bending, s.bending_damping) {
            (true, true) => Some(bend_forces::<true, true>),
            (true, false) => Some(bend_forces::<true, false>),
            (false, true) => Some(bend_forces::<false, true>),
            (false, false) => None,
        };
        let k = BendConstants {
            elastic: self.material.k_b,
            damping: self.material.k_bd,
        };
        let sweep = |spring_range, bend_range, mut window: Window| {
            if let Some(kernel) = springs {
                kernel(&self.springs, spring_range, x, v, window.reborrow());
            }
            if let Some(kernel) = bends {
                kernel(&self.bends, bend_range, k, x, v, window);
            }
        };
        for phase in Phase::BOTH {
            self.sweep_phase(phase, Window::whole(f), &|chunk: &Chunk, window| {
                sweep(chunk.springs.clone(), chunk.bends.clone(), window)
            });
        }
    }

    /// Gravity `m g` (4.14) and drag `-C v` (4.15) on every slot.
    fn external<const GRAVITY: bool, const DRAG: bool>(&self, v: &[Vec3], f: &mut [Vec3]) {
        let n = f.len();
        let (m, c, v) = (&self.mass[..n], &self.drag[..n], &v[..n]);
        for i in 0..n {
            if GRAVITY {
                f[i] += self.g * m[i];
            }
            if DRAG {
                f[i] -= v[i] * c[i];
            }
        }
    }
}

/// The Bridson bending modes of one element and the scalars the forces need.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BendModes {
    /// `u1..u4` (m⁻¹ up to the `|e|` factors of (4.11)).
    pub u: [Vec3; 4],
    /// The damping coefficient's length: `|e|` (m), times the sliver factor.
    pub damping_scale: Real,
    /// `|e|² / (|N1| + |N2|)` (dimensionless), times the sliver factor.
    pub elastic_scale: Real,
    /// Signed `sin(theta/2)`.
    pub sin_half: Real,
}

/// Modes (4.11) of the element with opposite vertices `x1`, `x2` and shared edge `x3 -> x4`;
/// `None` when the edge or a triangle is degenerate.
///
/// `sin(theta/2) = ±sqrt((1 - n1.n2)/2)` is computed as `|n1 - n2| / 2`, the same value for unit
/// normals but without the cancellation of `1 - n1.n2` near flat (which would turn round-off of
/// `1e-16` into a spurious `1e-8`); its sign is that of `(n1 x n2) . e`.
#[inline(always)]
pub(crate) fn bend_modes(x1: Vec3, x2: Vec3, x3: Vec3, x4: Vec3) -> Option<BendModes> {
    let e = x4 - x3;
    let e2 = e.norm_squared();
    let n1 = (x1 - x3).cross(&(x1 - x4));
    let n2 = (x2 - x4).cross(&(x2 - x3));
    let n1_sq = n1.norm_squared();
    let n2_sq = n2.norm_squared();
    let tiny = DEGENERATE_RATIO * DEGENERATE_RATIO * e2 * e2;
    // `!(a > b)` also rejects NaN inputs.
    if !(e2 > 0.0 && n1_sq > tiny && n2_sq > tiny) {
        return None;
    }
    let e_len = e2.sqrt();
    let inv_e = 1.0 / e_len;
    let (n1_len, n2_len) = (n1_sq.sqrt(), n2_sq.sqrt());
    // Reciprocals once; every later division is a multiplication.
    let (inv1_sq, inv2_sq) = (1.0 / n1_sq, 1.0 / n2_sq);
    let (w1, w2) = (n1 * inv1_sq, n2 * inv2_sq);
    let (s1, s2) = (e_len * inv1_sq, e_len * inv2_sq);
    let u = [
        n1 * s1,
        n2 * s2,
        w1 * ((x1 - x4).dot(&e) * inv_e) + w2 * ((x2 - x4).dot(&e) * inv_e),
        -(w1 * ((x1 - x3).dot(&e) * inv_e) + w2 * ((x2 - x3).dot(&e) * inv_e)),
    ];
    // |n1/|n1| - n2/|n2|| / 2 with a single division; exactly 0 for parallel normals along an axis.
    let mut sin_half = 0.5 * (n1 * n2_len - n2 * n1_len).norm() / (n1_len * n2_len);
    // (n1 x n2) . e has the sign of (hat1 x hat2) . e: no need to normalise.
    if n1.cross(&n2).dot(&e) < 0.0 {
        sin_half = -sin_half;
    }
    // The sliver factor (see SLIVER_RATIO); a comparison first, so sound elements pay no division.
    let thinnest = n1_len.min(n2_len);
    let sliver = if thinnest < SLIVER_RATIO * e2 {
        (thinnest / (SLIVER_RATIO * e2)).powi(3)
    } else {
        1.0
    };
    Some(BendModes {
        u,
        damping_scale: e_len * sliver,
        elastic_scale: e2 / (n1_len + n2_len) * sliver,
        sin_half,
    })
}

impl Dynamics for ForceModel {
    /// `a_i = f_i / m_i` (m/s²) from [`ForceModel::forces`]; 0 where `inv_mass` is 0. The model
    /// is time-independent, so `t` is unused.
    fn accelerations(&self, _t: Real, x: &[Vec3], v: &[Vec3], a: &mut [Vec3]) {
        self.forces(x, v, a);
        for (ai, &w) in a.iter_mut().zip(&self.inv_mass) {
            *ai = if w == 0.0 { Vec3::zeros() } else { *ai * w };
        }
    }

    /// Zeroes the velocity of every pinned vertex and free slot.
    fn constrain_velocities(&self, v: &mut [Vec3]) {
        for (vi, &w) in v.iter_mut().zip(&self.inv_mass) {
            if w == 0.0 {
                *vi = Vec3::zeros();
            }
        }
    }

    /// True when spring damping, bending damping or drag is switched on.
    fn velocity_dependent(&self) -> bool {
        let s = &self.switches;
        s.spring_damping || s.bending_damping || s.drag
    }

    fn force_model(&self) -> Option<&ForceModel> {
        Some(self)
    }
}

/// The mechanical energy of a state (J), every term over all vertex slots.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Kinetic energy `sum 1/2 m |v|²` (J).
    pub kinetic: Real,
    /// Gravitational potential `-sum m g . x` (J; zero at the world origin).
    pub gravity: Real,
    /// Stretch potential of the springs (J), see [`ForceModel::stretch_energy`].
    pub stretch: Real,
    /// Bending potential (J), see [`ForceModel::bending_energy`].
    pub bending: Real,
    /// Potential of the contact penalties (J, [`crate::physics::penalty`]); 0 from
    /// [`ForceModel::energies`], which sees no obstacle.
    pub contact: Real,
}

impl Energies {
    /// Kinetic plus every potential (J).
    pub fn total(&self) -> Real {
        self.kinetic + self.gravity + self.stretch + self.bending + self.contact
    }
}

impl ForceModel {
    /// Kinetic and potential energies (J) of the state `(x, v)`; a potential whose force is
    /// switched off counts 0.
    pub fn energies(&self, x: &[Vec3], v: &[Vec3]) -> Energies {
        let kinetic = self
            .mass
            .iter()
            .zip(v)
            .map(|(&m, vi)| 0.5 * m * vi.norm_squared())
            .sum();
        Energies {
            kinetic,
            gravity: self.gravity_energy(x),
            stretch: self.stretch_energy(x),
            bending: self.bending_energy(x),
            contact: 0.0,
        }
    }

    /// Gravitational potential `-sum_i m_i g . x_i` (J), 0 when gravity is off.
    pub fn gravity_energy(&self, x: &[Vec3]) -> Real {
        if !self.switches.gravity {
            return 0.0;
        }
        -self
            .mass
            .iter()
            .zip(x)
            .map(|(&m, xi)| m * self.g.dot(xi))
            .sum::<Real>()
    }

    /// Stretch potential `sum_j 1/2 k_j (L_j - L0_j)²` (J) over the springs that resist: stretched
    /// ones, and compressed ones too with `springs = "both"`. Its negative gradient is the elastic
    /// spring force (4.8) exactly. 0 when springs are off.
    pub fn stretch_energy(&self, x: &[Vec3]) -> Real {
        if !self.switches.springs {
            return 0.0;
        }
        let both = self.material.springs == SpringMode::Both;
        let sp = &self.springs;
        (0..sp.len())
            .map(|j| {
                let len = (x[sp.b[j] as usize] - x[sp.a[j] as usize]).norm();
                let s = len - sp.rest_length[j];
                if both || s > 0.0 {
                    0.5 * sp.k[j] * s * s
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// Bending potential (J): `sum 2 c (1 - cos(theta/2))` over the bending elements, with
    /// `c = k_b |e|² / (|N1| + |N2|)` the coefficient of the Bridson force (4.10). With `c` frozen,
    /// its gradient is `c sin(theta/2) dtheta/dx`, the Bridson elastic force (whose modes `u_i` are
    /// `dtheta/dx_i`); since the force lets `c` vary with the shape, the energy is consistent with
    /// it to first order in the change of `c` (small strain, any angle). For small angles it is
    /// `c theta² / 4`. 0 when bending is off.
    pub fn bending_energy(&self, x: &[Vec3]) -> Real {
        if !self.switches.bending {
            return 0.0;
        }
        let kb = self.material.k_b;
        self.bends
            .v
            .iter()
            .filter_map(|&[i1, i2, i3, i4]| {
                let u = bend_modes(
                    x[i1 as usize],
                    x[i2 as usize],
                    x[i3 as usize],
                    x[i4 as usize],
                )?;
                let s2 = u.sin_half * u.sin_half;
                // 1 - cos(theta/2) = s² / (1 + cos(theta/2)), without cancellation.
                let one_minus_cos = s2 / (1.0 + (1.0 - s2).max(0.0).sqrt());
                Some(2.0 * kb * u.elastic_scale * one_minus_cos)
            })
            .sum()
    }
}

#[cfg(test)]
mod sliver_tests {
    use super::{bend_modes, SLIVER_RATIO};
    use crate::math::{Real, Vec3};

    /// An element with edge x3 = (0,0,0) -> x4 = (1,0,0), x2 below the edge and bent out of
    /// plane, and x1 above it at height `h` (so `|N1| / |e|² = h`), slightly off plane.
    fn element(h: Real) -> [Vec3; 4] {
        [
            Vec3::new(0.3, h, 0.2 * h),
            Vec3::new(0.6, -0.5, 0.1),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
        ]
    }

    /// The elastic forces `elastic_scale sin_half u_i` on the element.
    fn forces(x: [Vec3; 4]) -> [Vec3; 4] {
        let m = bend_modes(x[0], x[1], x[2], x[3]).expect("not degenerate");
        m.u.map(|u| u * (m.elastic_scale * m.sin_half))
    }

    #[test]
    fn a_sliver_keeps_zero_net_force_and_torque() {
        for h in [0.5, 0.04, 0.004] {
            let x = element(h).map(|p| p + Vec3::new(2.0, -1.0, 3.0));
            let f = forces(x);
            let total: Vec3 = f.iter().sum();
            let torque: Vec3 = x.iter().zip(&f).map(|(xi, fi)| xi.cross(fi)).sum();
            let scale: Real = x.iter().zip(&f).map(|(xi, fi)| xi.norm() * fi.norm()).sum();
            assert!(scale > 0.0);
            assert!(total.norm() <= 1e-12 * scale, "h {h}: net force {total}");
            assert!(torque.norm() <= 1e-12 * scale, "h {h}: net torque {torque}");
        }
    }

    #[test]
    fn the_sliver_factor_is_continuous_and_bounds_the_force() {
        let norm = |h: Real| forces(element(h))[0].norm();
        let (above, below) = (norm(SLIVER_RATIO * 1.0001), norm(SLIVER_RATIO * 0.9999));
        assert!((above - below).abs() <= 1e-3 * above, "{above} vs {below}");
        // Without the factor the force on x1 grows as 1/h² as the sliver thins; with it, it falls.
        assert!(norm(SLIVER_RATIO / 10.0) < norm(SLIVER_RATIO));
        assert!(norm(SLIVER_RATIO / 100.0) < norm(SLIVER_RATIO / 10.0));
    }
}
