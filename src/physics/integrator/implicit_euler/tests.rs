//! `implicit_euler` with its solvers: convergence, agreement of CG and Cholesky, CG preconditioned
//! by the springs' factorisation, the kept symbolic analysis, the fallback to CG, `auto`'s
//! rescues, switches and windows, the interrupt.

use super::cg::{Cg, Preconditioner};
use super::cholesky::{Cholesky, Factored};
use super::supernodal_solve::{BALANCE, PARALLEL_ENTRIES};
use super::system::System;
use super::{ImplicitEuler, AUTO_FIRST_WINDOW, AUTO_SLOW_ITERATIONS, AUTO_SLOW_STEPS};
use crate::math::{Real, Vec3};
use crate::mesh::{union_jack, VertexId};
use crate::physics::{
    ForceModel, Forces, Integrator, IntegratorParams, LinearSolver, Material, SpringMode, Springs,
};
use crate::testing::{built, in_pool, random_state};

pub(super) const SOLVERS: [LinearSolver; 3] = [
    LinearSolver::Cg,
    LinearSolver::Cholesky,
    LinearSolver::PcgSprings,
];

pub(super) fn implicit(solver: LinearSolver) -> ImplicitEuler {
    ImplicitEuler::new(&IntegratorParams {
        solver,
        ..IntegratorParams::default()
    })
}

/// A 6x6 sheet 1000 times stiffer than the default material, pinned at one corner, randomly
/// deformed (stretched and bent), and a step 100 times its explicit limit.
fn stiff_sheet(springs: SpringMode) -> (ForceModel, Vec<Vec3>, Vec<Vec3>, Real) {
    stiff_sheet_of(6, springs, 2, 0.05)
}

/// The sheet of [`stiff_sheet`] with `n` x `n` vertices, its state drawn from `seed` with
/// amplitude `amplitude` (m).
fn stiff_sheet_of(
    n: usize,
    springs: SpringMode,
    seed: u64,
    amplitude: Real,
) -> (ForceModel, Vec<Vec3>, Vec<Vec3>, Real) {
    let mut mesh = union_jack(n, n, 1.0, 1.0);
    mesh.set_pinned(VertexId(0), true);
    let material = Material {
        young: 1e9,
        springs,
        ..Material::default()
    };
    let model = built(&mesh, &material, &Forces::default());
    let (x, v) = random_state(&mesh, seed, amplitude);
    let dt = 100.0 * model.stable_step(1.0);
    (model, x, v, dt)
}

/// The system of one step of size `dt` from state `(x, v)`.
fn system_at(model: &ForceModel, dt: Real, x: &[Vec3], v: &[Vec3]) -> System {
    let mut f = vec![Vec3::zeros(); x.len()];
    model.forces(x, v, &mut f);
    let mut system = System::default();
    system.build(model, dt, x, v, &f);
    system
}

/// `|A dv - b| / |b|` of `system` (built from `model`).
fn relative_residual(model: &ForceModel, system: &System, dv: &[Vec3]) -> Real {
    let mut q = vec![Vec3::zeros(); dv.len()];
    system.apply(model, dv, &mut q);
    let residual: Vec<Vec3> = q.iter().zip(&system.b).map(|(q, b)| q - b).collect();
    norm(&residual) / norm(&system.b)
}

/// Two particles joined by a spring of negative stiffness, stretched: a matrix no Cholesky
/// factorisation accepts.
fn negative_spring() -> (ForceModel, Vec<Vec3>, Vec<Vec3>) {
    let material = Material {
        springs: SpringMode::Both,
        ..Material::default()
    };
    let forces = Forces {
        springs: true,
        ..Forces::default()
    };
    let springs = Springs {
        a: vec![0],
        b: vec![1],
        rest_length: vec![1.0],
        k: vec![-1e6],
        kd: vec![0.0],
    };
    let model = ForceModel::from_parts(&material, &forces, vec![1.0, 1.0], &[false; 2], springs);
    let x = vec![Vec3::zeros(), Vec3::new(1.5, 0.0, 0.0)];
    (model, x, vec![Vec3::zeros(); 2])
}

/// The system of one step of [`stiff_sheet`] and its solution by the whole Cholesky.
fn solved_stiff_sheet(springs: SpringMode) -> (ForceModel, System, Vec<Vec3>) {
    let (model, x, v, dt) = stiff_sheet(springs);
    let system = system_at(&model, dt, &x, &v);
    let mut direct = vec![Vec3::zeros(); x.len()];
    Cholesky::new(Factored::Whole)
        .solve(&system, &model, &mut direct)
        .expect("positive definite");
    (model, system, direct)
}

pub(super) fn norm(a: &[Vec3]) -> Real {
    a.iter().map(|p| p.norm_squared()).sum::<Real>().sqrt()
}

#[test]
fn implicit_euler_converges_and_reports_its_iterations() {
    for solver in SOLVERS {
        let (model, mut x, mut v, dt) = stiff_sheet(SpringMode::Tension);
        let mut integ = implicit(solver);
        for k in 0..20 {
            let stats = integ.step(&model, k as Real * dt, dt, &mut x, &mut v);
            assert!(!stats.unconverged && !stats.solver_fallback, "{stats:?}");
            // CG iterates; the direct solve does not.
            assert_eq!(
                stats.cg_iterations > 0,
                solver != LinearSolver::Cholesky,
                "{stats:?}"
            );
        }
        assert!(x.iter().chain(&v).all(|p| p.iter().all(|c| c.is_finite())));
        assert!(
            v.iter().all(|vi| vi.norm() < 10.0),
            "{solver:?}: bounded velocities"
        );
    }
}

/// On a stretched and bent state (every force on, springs resisting both ways or tension only),
/// the sparse Cholesky solve satisfies the system to round-off and agrees with CG run to a
/// tight tolerance; pinned vertices get no velocity change.
#[test]
fn cholesky_and_cg_give_the_same_velocity_change() {
    for springs in [SpringMode::Both, SpringMode::Tension] {
        let (model, system, direct) = solved_stiff_sheet(springs);
        let mut q = vec![Vec3::zeros(); direct.len()];
        system.apply(&model, &direct, &mut q);
        let residual: Vec<Vec3> = q.iter().zip(&system.b).map(|(q, b)| q - b).collect();
        assert!(
            norm(&residual) <= 1e-12 * norm(&system.b),
            "{springs:?}: |A dv - b| = {:e}, |b| = {:e}",
            norm(&residual),
            norm(&system.b)
        );
        let tolerance = 1e-10;
        let mut iterative = vec![Vec3::zeros(); direct.len()];
        let stats = Cg::new(tolerance, 10_000).solve(
            &system,
            &model,
            None,
            Preconditioner::BlockJacobi,
            &mut iterative,
        );
        assert!(!stats.unconverged, "{stats:?}");
        let diff: Vec<Vec3> = direct.iter().zip(&iterative).map(|(a, b)| a - b).collect();
        assert!(
            norm(&diff) <= 1e3 * tolerance * norm(&direct),
            "{springs:?}: |dv_cholesky - dv_cg| = {:e}, |dv| = {:e}",
            norm(&diff),
            norm(&direct)
        );
        assert_eq!(direct[0], Vec3::zeros(), "the pinned vertex");
    }
}

/// CG preconditioned by the factorisation of the matrix without its bending couplings (moved
/// to the diagonal) solves the same system as Cholesky, to its tolerance, in fewer iterations
/// than block-Jacobi CG; the preconditioner alone is not the system's inverse (bending is
/// bent here, so its couplings matter).
#[test]
fn cg_preconditioned_by_the_springs_factor_solves_the_whole_system() {
    for springs in [SpringMode::Both, SpringMode::Tension] {
        let (model, system, direct) = solved_stiff_sheet(springs);
        let tolerance = 1e-10;
        let mut factor = Cholesky::new(Factored::SpringsSingle);
        factor
            .factorize(&system, &model)
            .expect("positive definite");
        let mut alone = vec![Vec3::zeros(); direct.len()];
        factor.solve_factored(&system.b, &mut alone);
        let off = |dv: &[Vec3]| -> Real {
            let diff: Vec<Vec3> = direct.iter().zip(dv).map(|(a, b)| a - b).collect();
            norm(&diff) / norm(&direct)
        };
        assert!(off(&alone) > 1e-6, "{springs:?}: bending couples the wings");
        let mut pcg = vec![Vec3::zeros(); direct.len()];
        let preconditioned = Cg::new(tolerance, 10_000).solve(
            &system,
            &model,
            None,
            Preconditioner::Factor(&mut factor),
            &mut pcg,
        );
        let mut jacobi = vec![Vec3::zeros(); direct.len()];
        let block_jacobi = Cg::new(tolerance, 10_000).solve(
            &system,
            &model,
            None,
            Preconditioner::BlockJacobi,
            &mut jacobi,
        );
        assert!(!preconditioned.unconverged, "{preconditioned:?}");
        assert!(off(&pcg) <= 1e3 * tolerance, "{springs:?}: {:e}", off(&pcg));
        assert!(
            preconditioned.cg_iterations < block_jacobi.cg_iterations,
            "{springs:?}: {} against {} iterations",
            preconditioned.cg_iterations,
            block_jacobi.cg_iterations
        );
        assert_eq!(pcg[0], Vec3::zeros(), "the pinned vertex");
    }
}

/// The symbolic analysis is done once per topology: kept over steps on one mesh, redone on
/// another mesh (whose steps then match CG's) and again when the first comes back.
#[test]
fn cholesky_keeps_its_symbolic_analysis_until_the_topology_changes() {
    let mut integ = implicit(LinearSolver::Cholesky);
    let (first, mut x, mut v, dt) = stiff_sheet(SpringMode::Tension);
    for k in 0..3 {
        integ.step(&first, k as Real * dt, dt, &mut x, &mut v);
    }
    assert_eq!(integ.cholesky.analyses, 1);
    let mesh = union_jack(5, 7, 1.0, 1.2);
    let other = built(&mesh, &Material::default(), &Forces::default());
    let (x0, v0) = random_state(&mesh, 9, 0.02);
    let mut cg = ImplicitEuler::new(&IntegratorParams {
        solver: LinearSolver::Cg,
        cg_tolerance: 1e-12,
        cg_max_iterations: 10_000,
        ..IntegratorParams::default()
    });
    let (mut xc, mut vc) = (x0.clone(), v0.clone());
    let (mut xd, mut vd) = (x0, v0);
    for k in 0..3 {
        cg.step(&other, k as Real * dt, dt, &mut xc, &mut vc);
        integ.step(&other, k as Real * dt, dt, &mut xd, &mut vd);
    }
    assert_eq!(integ.cholesky.analyses, 2);
    let diff: Vec<Vec3> = xc.iter().zip(&xd).map(|(a, b)| a - b).collect();
    assert!(norm(&diff) <= 1e-9, "{:e} m", norm(&diff));
    integ.step(&first, 0.0, dt, &mut x, &mut v);
    assert_eq!(integ.cholesky.analyses, 3);
}

/// A matrix that is not positive definite (a spring of negative stiffness, far beyond the mass
/// at this step) fails the factorisation: the step is solved by CG and flagged, under
/// `cholesky` and under `auto` alike.
#[test]
fn a_failed_factorisation_falls_back_to_cg() {
    let (model, mut x, mut v) = negative_spring();
    let (x0, v0) = (x.clone(), v.clone());
    let stats = implicit(LinearSolver::Cholesky).step(&model, 0.0, 0.1, &mut x, &mut v);
    assert!(
        stats.solver_fallback && stats.cg_iterations > 0,
        "{stats:?}"
    );
    // `auto` whose CG ends above tolerance on this matrix tries Cholesky, which fails: the step
    // is CG's, unconverged, a fallback and not a rescue.
    let (mut x, mut v) = (x0, v0);
    let stats = implicit(LinearSolver::Auto).step(&model, 0.0, 0.1, &mut x, &mut v);
    assert!(
        stats.unconverged && stats.solver_fallback && !stats.direct_rescue,
        "{stats:?}"
    );
}

/// An interrupt ends the CG loop of a long `implicit_euler` step within 16 iterations, whichever
/// preconditioner; an interrupted solve is neither unconverged nor rescued.
#[test]
fn implicit_euler_stops_its_cg_loop_when_interrupted() {
    for solver in [LinearSolver::Auto, LinearSolver::PcgSprings] {
        let (model, mut x, mut v, dt) = stiff_sheet(SpringMode::Tension);
        let params = IntegratorParams {
            solver,
            cg_tolerance: 1e-300,
            cg_max_iterations: 10_000,
            ..Default::default()
        };
        let mut integ = ImplicitEuler::new(&params);
        integ.set_interrupt(std::sync::Arc::new(true.into()));
        let stats = integ.step(&model, 0.0, dt, &mut x, &mut v);
        assert!(
            stats.cg_iterations < 16 && !stats.unconverged && !stats.direct_rescue,
            "{solver:?}: {stats:?}"
        );
    }
}

/// `pcg_springs` whose CG stops at its cap (one iteration to 1e-14 on the stiff sheet) has the step solved
/// again by Cholesky: converged, counted as a rescue with CG's iterations, and where Cholesky's
/// own step lands; where its preconditioner cannot be factorised (a spring of negative
/// stiffness), the whole Cholesky is tried at once, and CG after it when that fails too.
#[test]
fn pcg_springs_is_rescued_by_cholesky_and_falls_back_to_it() {
    let (model, x0, v0, dt) = stiff_sheet(SpringMode::Tension);
    let capped = |solver| {
        ImplicitEuler::new(&IntegratorParams {
            solver,
            cg_tolerance: 1e-14,
            cg_max_iterations: 1,
            ..IntegratorParams::default()
        })
    };
    let (mut xp, mut vp) = (x0.clone(), v0.clone());
    let (mut xd, mut vd) = (x0, v0);
    let (mut pcg, mut direct) = (
        capped(LinearSolver::PcgSprings),
        capped(LinearSolver::Cholesky),
    );
    for k in 0..3 {
        let t = k as Real * dt;
        let stats = pcg.step(&model, t, dt, &mut xp, &mut vp);
        assert!(
            stats.direct_rescue
                && stats.cg_iterations == 1
                && !stats.unconverged
                && !stats.solver_fallback,
            "{stats:?}"
        );
        direct.step(&model, t, dt, &mut xd, &mut vd);
    }
    assert_eq!(xp, xd, "the rescued steps are Cholesky's");

    let (model, mut x, mut v) = negative_spring();
    let stats = implicit(LinearSolver::PcgSprings).step(&model, 0.0, 0.1, &mut x, &mut v);
    assert!(
        stats.solver_fallback && stats.cg_iterations > 0 && !stats.direct_rescue,
        "{stats:?}"
    );
}

/// `auto` where CG converges is CG, bit for bit; where CG stops at its cap (a cap of 3
/// iterations on the stiff sheet), the step is solved again by Cholesky and lands where
/// Cholesky's does, converged; the next `AUTO_FIRST_WINDOW` steps go straight to Cholesky (no CG
/// iteration), then CG is tried again and the window doubles.
#[test]
fn auto_is_cg_where_cg_converges_and_rescues_capped_solves_with_cholesky() {
    let with = |solver, cap| {
        ImplicitEuler::new(&IntegratorParams {
            solver,
            cg_max_iterations: cap,
            ..IntegratorParams::default()
        })
    };
    let (model, x0, v0, dt) = stiff_sheet(SpringMode::Tension);
    let run = |integ: &mut ImplicitEuler, steps: usize| {
        let (mut x, mut v) = (x0.clone(), v0.clone());
        let stats: Vec<_> = (0..steps)
            .map(|k| integ.step(&model, k as Real * dt, dt, &mut x, &mut v))
            .collect();
        (x, v, stats)
    };
    let (xa, va, auto_stats) = run(&mut with(LinearSolver::Auto, 200), 5);
    let (xc, vc, _) = run(&mut with(LinearSolver::Cg, 200), 5);
    assert!(auto_stats
        .iter()
        .all(|s| !s.direct_rescue && !s.unconverged));
    assert_eq!((xa, va), (xc, vc), "auto is CG where CG converges");

    let window = AUTO_FIRST_WINDOW as usize;
    let steps = 2 * window + 3;
    let (xa, _, stats) = run(&mut with(LinearSolver::Auto, 3), steps);
    let (xd, _, _) = run(&mut with(LinearSolver::Cholesky, 3), steps);
    let rescued: Vec<usize> = (0..steps).filter(|&k| stats[k].direct_rescue).collect();
    assert_eq!(rescued, [0, window + 1], "{stats:?}");
    for (k, s) in stats.iter().enumerate() {
        assert!(!s.unconverged && !s.solver_fallback, "step {k}: {s:?}");
        let tried_cg = rescued.contains(&k);
        assert_eq!(s.cg_iterations > 0, tried_cg, "step {k}: {s:?}");
    }
    let diff: Vec<Vec3> = xa.iter().zip(&xd).map(|(a, b)| a - b).collect();
    assert!(
        norm(&diff) <= 1e-9 * norm(&xd),
        "auto's rescued run lands where Cholesky's does: {:e} m",
        norm(&diff)
    );
}

/// `auto` where CG converges, but slowly (the stiff sheet needs more than
/// `AUTO_SLOW_ITERATIONS sqrt(slots)` iterations at every step): the first `AUTO_SLOW_STEPS`
/// steps are CG's, bit for bit; the last of them opens a window of `AUTO_FIRST_WINDOW` steps
/// solved by Cholesky (no CG iteration), after which one slow CG solve opens the next window. A
/// topology met between two slow solves (the same sheet with one cell's diagonal flipped) starts
/// the count again, so alternating topologies never switch.
#[test]
fn auto_goes_to_cholesky_after_a_streak_of_slow_cg_solves_on_one_topology() {
    let (model, x0, v0, dt) = stiff_sheet(SpringMode::Tension);
    let slow = AUTO_SLOW_ITERATIONS * (model.mass().len() as Real).sqrt();
    let (streak, window) = (AUTO_SLOW_STEPS as usize, AUTO_FIRST_WINDOW as usize);
    let steps = streak + window + 1;
    let run = |solver| {
        let mut integ = implicit(solver);
        let (mut x, mut v) = (x0.clone(), v0.clone());
        let stats: Vec<_> = (0..steps)
            .map(|k| integ.step(&model, k as Real * dt, dt, &mut x, &mut v))
            .collect();
        (x, stats)
    };
    let (x_cg, cg) = run(LinearSolver::Cg);
    assert!(
        cg.iter()
            .all(|s| !s.unconverged && s.cg_iterations as Real > slow),
        "every CG solve converges above {slow} iterations: {cg:?}"
    );
    let (x_auto, auto) = run(LinearSolver::Auto);
    let switched: Vec<usize> = (0..steps).filter(|&k| auto[k].slow_switch).collect();
    let second = streak + window;
    assert_eq!(switched, [streak - 1, second], "{auto:?}");
    for (k, s) in auto.iter().enumerate() {
        let by_cg = k < streak || k == second;
        assert_eq!(s.cg_iterations > 0, by_cg, "step {k}: {s:?}");
        assert!(!s.unconverged && !s.direct_rescue, "step {k}: {s:?}");
    }
    let iterations = |s: &[crate::physics::StepStats]| -> Vec<usize> {
        s[..streak].iter().map(|s| s.cg_iterations).collect()
    };
    assert_eq!(iterations(&auto), iterations(&cg), "CG's solves first");
    // The Cholesky steps solve the systems CG solves to its tolerance: auto ends no farther from
    // CG's run than Cholesky's own run does.
    let (x_direct, _) = run(LinearSolver::Cholesky);
    let distance = |x: &[Vec3]| -> Real {
        let d: Vec<Vec3> = x.iter().zip(&x_cg).map(|(a, b)| a - b).collect();
        norm(&d)
    };
    let (from_auto, from_direct) = (distance(&x_auto), distance(&x_direct));
    assert!(
        from_auto <= from_direct,
        "auto ends {from_auto:e} m from CG's run, Cholesky's {from_direct:e} m"
    );

    // Alternating topologies (the sheet with one cell's diagonal flipped): never a switch.
    let flipped = {
        let mut mesh = union_jack(6, 6, 1.0, 1.0);
        mesh.set_pinned(VertexId(0), true);
        let (e, f1, f2) = mesh
            .edges()
            .find_map(|(e, ef)| {
                let long = (mesh.rest(e.0) - mesh.rest(e.1)).norm() > 0.25;
                Some((e, ef.first, ef.second?)).filter(|_| long)
            })
            .expect("a cell diagonal");
        let t1 = mesh.face(f1);
        let forward = (0..3).any(|k| t1[k] == e.0 && t1[(k + 1) % 3] == e.1);
        let (a, b) = if forward { (e.0, e.1) } else { (e.1, e.0) };
        let third = |f| {
            mesh.face(f)
                .into_iter()
                .find(|&w| w != a && w != b)
                .unwrap()
        };
        let (c, d) = (third(f1), third(f2));
        let old = crate::mesh::VertexRef::Old;
        let edit = crate::mesh::Edit {
            remove: vec![f1, f2],
            new_vertices: Vec::new(),
            add: vec![[old(a), old(d), old(c)], [old(d), old(b), old(c)]],
        };
        mesh.replace(&edit).expect("the flip is a valid edit");
        let material = Material {
            young: 1e9,
            ..Material::default()
        };
        built(&mesh, &material, &Forces::default())
    };
    let mut integ = implicit(LinearSolver::Auto);
    let (mut x, mut v) = (x0.clone(), v0.clone());
    let mut slow_solves = 0;
    for k in 0..2 * streak {
        let m = if k % 2 == 0 { &model } else { &flipped };
        let s = integ.step(m, k as Real * dt, dt, &mut x, &mut v);
        assert!(!s.slow_switch, "step {k}: {s:?}");
        slow_solves += usize::from(!s.unconverged && s.cg_iterations as Real > slow);
    }
    assert!(
        slow_solves >= streak,
        "{slow_solves} slow solves, enough for a switch on one mesh"
    );
}

/// The triangular solves split over two threads: a sheet large enough for it (41 x 41 vertices)
/// gives the same direct solution bit for bit on one thread and on two, within rounding of the
/// system; every supernode has one place in the split, whose two groups are balanced.
#[test]
fn the_split_solve_is_the_same_on_one_thread_and_two() {
    let (model, x, v, dt) = stiff_sheet_of(41, Material::default().springs, 3, 0.02);
    let system = system_at(&model, dt, &x, &v);
    let solve_on = |threads: usize| {
        in_pool(threads, || {
            let mut cholesky = Cholesky::new(Factored::Whole);
            let mut dv = vec![Vec3::zeros(); x.len()];
            cholesky
                .solve(&system, &model, &mut dv)
                .expect("positive definite");
            let entries = cholesky.check_split().expect("analysed").unwrap();
            (dv, entries, cholesky.shares_solves())
        })
    };
    let (one, [g0, g1, top], shared_on_one) = solve_on(1);
    let (two, _, shared_on_two) = solve_on(2);
    assert!(!shared_on_one && shared_on_two);
    assert!(one == two, "one thread and two differ");
    assert!(g0 > 0 && g1 > 0 && g0.max(g1) as Real <= BALANCE * (g0 + g1) as Real);
    let entries = g0 + g1 + top;
    assert!(
        entries >= PARALLEL_ENTRIES,
        "large enough for two threads: {entries}"
    );
    let residual = relative_residual(&model, &system, &one);
    assert!(residual <= 1e-9, "{residual}");
}

/// The system's build and its product with a vector are swept by chunks on the pool's threads:
/// on a sheet large enough for chunks (49 x 49 vertices), with bending and its damping on, off,
/// and its damping alone, one thread and two give every array and product bit for bit, and the
/// direct solution (its matrix's diagonal blocks the build's sums, its couplings the elements'
/// own blocks) leaves a residual of rounding under the chunked product.
#[test]
fn the_chunked_system_is_the_same_on_one_thread_and_two() {
    let mut mesh = union_jack(49, 49, 1.0, 1.0);
    mesh.set_pinned(VertexId(0), true);
    let (x, v) = random_state(&mesh, 5, 0.02);
    let (p, _) = random_state(&mesh, 6, 0.1);
    let bending = [(true, true), (false, false), (false, true)];
    for (bending, bending_damping) in bending {
        let forces = Forces {
            bending,
            bending_damping,
            ..Forces::default()
        };
        let model = built(&mesh, &Material::default(), &forces);
        assert!(model.is_chunked(), "a 49x49 sheet is swept in chunks");
        let dt = 100.0 * model.stable_step(1.0);
        let on = |threads: usize| {
            in_pool(threads, || {
                let system = system_at(&model, dt, &x, &v);
                let mut q = vec![Vec3::zeros(); p.len()];
                system.apply(&model, &p, &mut q);
                (system, q)
            })
        };
        let (one, q_one) = on(1);
        let (two, q_two) = on(2);
        let case = format!("bending {bending}, its damping {bending_damping}");
        assert_eq!(
            one.bend_u.is_empty(),
            !(bending || bending_damping),
            "{case}"
        );
        assert!(one.spring_blocks == two.spring_blocks && one.bend_u == two.bend_u);
        assert!(one.bend_w == two.bend_w && one.diag_blocks == two.diag_blocks);
        assert!(
            one.b == two.b && q_one == q_two,
            "{case}: one thread and two differ"
        );
        let mut dv = vec![Vec3::zeros(); x.len()];
        let mut cholesky = Cholesky::new(Factored::Whole);
        cholesky
            .solve(&one, &model, &mut dv)
            .expect("positive definite");
        let residual = relative_residual(&model, &one, &dv);
        assert!(residual <= 1e-9, "{case}: {residual}");
    }
}
