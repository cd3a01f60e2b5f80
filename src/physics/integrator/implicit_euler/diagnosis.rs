//! Why CG needs more iterations on a graded mesh than on a uniform grid: the measurement behind
//! docs/performance.md ("Implicit solve: CG against sparse Cholesky"). Not a test: run with
//! `cargo test --release --lib implicit_euler::diagnosis -- --ignored --nocapture` (about two
//! minutes, most of it the dense eigenvalues of the 33x33 grid). The states come from whole runs
//! of the round-table scene, so this test-only code names the scene and simulation layers.

use super::assembly::Pattern;
use super::cg::{Cg, Preconditioner};
use super::system::System;
use crate::math::{Real, Vec3};
use crate::physics::{ForceModel, Forces};
use crate::scene::load_embedded;
use crate::sim::Simulation;
use nalgebra::DMatrix;

/// The round table at a fixed 2 ms step with `implicit_euler`, `settings` added, run to `t` (s).
fn round_table_at(settings: &[&str], t: Real) -> Simulation {
    let mut all = vec![
        "integrator.name=\"implicit_euler\"",
        "time.mode=\"fixed\"",
        "time.dt=0.002",
    ];
    all.extend_from_slice(settings);
    let all: Vec<String> = all.iter().map(|s| s.to_string()).collect();
    let loaded = load_embedded("round_table", &all)
        .expect("embedded")
        .expect("valid");
    let mut sim = Simulation::new(&loaded).expect("builds");
    while sim.t < t - 1e-9 {
        sim.step().expect("runs");
    }
    sim
}

/// The system of the next step from `sim`'s state, with `model` (the cloth's, or a variant).
fn system_of(sim: &Simulation, model: &ForceModel) -> System {
    let (x, v) = (&sim.cloth.x, &sim.cloth.v);
    let mut f = vec![Vec3::zeros(); x.len()];
    model.forces(x, v, &mut f);
    let mut system = System::default();
    system.build(model, sim.scene.time.dt, x, v, &f);
    system
}

/// CG iterations to the default relative tolerance 1e-6 (no cap in practice).
fn iterations(system: &System, model: &ForceModel) -> usize {
    let mut dv = vec![Vec3::zeros(); system.b.len()];
    Cg::new(1e-6, 10_000)
        .solve(system, model, None, Preconditioner::BlockJacobi, &mut dv)
        .cg_iterations
}

/// Smallest and largest eigenvalue of the block-Jacobi preconditioned matrix `D^-1/2 A D^-1/2`
/// over the free slots (`D`: the 3x3 diagonal blocks), from the assembled lower triangle.
fn preconditioned_spectrum(system: &System, model: &ForceModel) -> (Real, Real) {
    let pattern = Pattern::new(model, true).expect("memory for the ordering");
    let (mut blocks, mut diagonal, mut values) = (Vec::new(), Vec::new(), Vec::new());
    pattern.fill(system, model, &mut blocks, &mut diagonal, &mut values);
    let free: Vec<usize> = (0..model.mass().len())
        .filter(|&i| model.inv_mass()[i] != 0.0)
        .collect();
    let mut index = vec![usize::MAX; 3 * model.mass().len()];
    for (k, &i) in free.iter().enumerate() {
        for c in 0..3 {
            index[3 * pattern.position(i) + c] = 3 * k + c;
        }
    }
    let m = 3 * free.len();
    let mut a = DMatrix::<Real>::zeros(m, m);
    for col in 0..pattern.dim() {
        for e in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            let (r, c) = (index[pattern.row_idx[e]], index[col]);
            if r != usize::MAX && c != usize::MAX {
                a[(r, c)] = values[e];
                a[(c, r)] = values[e];
            }
        }
    }
    let mut scale = DMatrix::<Real>::zeros(m, m);
    for (k, &i) in free.iter().enumerate() {
        let l = system.diag_blocks[i].cholesky().expect("SPD block").l();
        let inv = l.try_inverse().expect("invertible");
        scale.view_mut((3 * k, 3 * k), (3, 3)).copy_from(&inv);
    }
    let s = &scale * a * scale.transpose();
    let eig = ((&s + s.transpose()) * 0.5).symmetric_eigenvalues();
    (eig.min(), eig.max())
}

/// Bending elements whose Gauss-Newton diagonal exceeds the spring diagonal at one of their
/// vertices; the largest such ratio; and, for that element, its smaller triangle's deformed
/// over rest area.
fn bending_outliers(sim: &Simulation, system: &System) -> (usize, Real, Real) {
    let model = &sim.cloth.model;
    let dt2 = sim.scene.time.dt.powi(2);
    let sp = model.springs();
    let mut spring_diag = vec![0.0; model.mass().len()];
    for j in 0..sp.len() {
        spring_diag[sp.a[j] as usize] += dt2 * sp.k[j];
        spring_diag[sp.b[j] as usize] += dt2 * sp.k[j];
    }
    let (x, mesh) = (&sim.cloth.x, &sim.cloth.mesh);
    let rest = |i: u32| {
        let p = mesh.rest(crate::mesh::VertexId(i));
        Vec3::new(p.x, p.y, 0.0)
    };
    let (mut count, mut worst, mut crushed) = (0, 0.0, 1.0);
    let bends = model
        .bends()
        .v
        .iter()
        .zip(&system.bend_u)
        .zip(&system.bend_w);
    for ((ids, u), &w) in bends {
        let ratio = (0..4)
            .map(|k| w * u[k].norm_squared() / spring_diag[ids[k] as usize])
            .fold(0.0, Real::max);
        count += usize::from(ratio > 1.0);
        if ratio > worst {
            worst = ratio;
            let area = |p: [Vec3; 3]| (p[0] - p[2]).cross(&(p[0] - p[1])).norm();
            let tri = |o: usize| [ids[o], ids[2], ids[3]];
            crushed = (0..2)
                .map(|o| {
                    let t = tri(o);
                    area(t.map(|i| x[i as usize])) / area(t.map(rest))
                })
                .fold(Real::INFINITY, Real::min);
        }
    }
    (count, worst, crushed)
}

/// One line per state: vertices, |b| over the gravity impulse, CG iterations with the full
/// matrix and with bending left out of it (same right-hand side), the bending outliers, and on
/// request the preconditioned condition number with and without bending.
fn report(label: &str, sim: &Simulation, spectrum: bool) {
    let model = &sim.cloth.model;
    let system = system_of(sim, model);
    let flat = ForceModel::new(
        model.material(),
        &Forces {
            bending: false,
            bending_damping: false,
            ..model.switches().clone()
        },
    );
    let mut flat = flat;
    flat.rebuild(&sim.cloth.mesh);
    let mut without = system_of(sim, &flat);
    without.b.clone_from(&system.b);
    let dt = sim.scene.time.dt;
    let impulse: Real = model.mass().iter().map(|m| (m * 9.81 * dt).powi(2)).sum();
    let b: Real = system.b.iter().map(|b| b.norm_squared()).sum();
    let (count, worst, crushed) = bending_outliers(sim, &system);
    let mut line = format!(
        "{label} t={:.2}: {} vertices, |b|/|dt m g| {:.0}, CG {} iterations ({} without \
         bending in the matrix), {count} bending elements above the spring diagonal, largest \
         ratio {worst:.3}, its triangle at {crushed:.4} of its rest area",
        sim.t,
        sim.cloth.mesh.vertex_count(),
        (b / impulse).sqrt(),
        iterations(&system, model),
        iterations(&without, &flat),
    );
    if spectrum {
        let (lo, hi) = preconditioned_spectrum(&system, model);
        let (lo_f, hi_f) = preconditioned_spectrum(&without, &flat);
        line += &format!(
            "; block-Jacobi spectrum [{lo:.2e}, {hi:.2}], kappa {:.0} ({:.0} without bending)",
            hi / lo,
            hi_f / lo_f
        );
    }
    println!("{line}");
}

#[test]
#[ignore]
fn cg_on_the_graded_round_table() {
    let graded = |h: &'static str| ["adaptivity.strategy=\"bisect48\"", "cloth.resolution=5", h];
    for t in [0.3, 0.45, 0.6, 0.75, 0.95] {
        let sim = round_table_at(&graded("adaptivity.h_min=0.02"), t);
        report("bisect48 h_min 0.02", &sim, t == 0.6);
    }
    let sim = round_table_at(&graded("adaptivity.h_min=0.03"), 0.6);
    report("bisect48 h_min 0.03", &sim, true);
    let sim = round_table_at(&["cloth.resolution=33"], 0.6);
    report("static 33x33", &sim, true);
}
