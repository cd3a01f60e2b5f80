//! Contacts held in the solve ([`Hold`]): a held slot keeps its velocity along its normal, the
//! rest of the system is solved with the constraint in it by every solver alike, the reported
//! impulses are the momentum the obstacle gave, and a vertex pulled off is released; pressed
//! faces' penalties are solved alike by every solver too.

use super::tests::{norm, SOLVERS};
use super::ImplicitEuler;
use crate::math::{Real, Vec3};
use crate::mesh::union_jack;
use crate::physics::{
    Forces, Hold, Integrator, IntegratorParams, LinearSolver, Material, Pressed, PressedFace,
};
use crate::testing::{built, random_state};

/// A free 7x7 sheet (no pinned vertex), stiff, randomly deformed, and a step 100 times its
/// explicit limit: (model, x, v, dt).
fn free_sheet() -> (crate::physics::ForceModel, Vec<Vec3>, Vec<Vec3>, Real) {
    let mesh = union_jack(7, 7, 1.0, 1.0);
    let material = Material {
        young: 1e8,
        ..Material::default()
    };
    let model = built(&mesh, &material, &Forces::default());
    let (x, v) = random_state(&mesh, 5, 0.02);
    let dt = 100.0 * model.stable_step(1.0);
    (model, x, v, dt)
}

/// Holds on every fourth slot, each with a normal the forces at `x`, `v` press into
/// (`f . n < 0`: the force's direction turned by a fixed amount), plus one slot whose forces
/// pull it off (`f . n > 0`), listed last.
fn holds_for(model: &crate::physics::ForceModel, x: &[Vec3], v: &[Vec3]) -> Vec<Hold> {
    let mut f = vec![Vec3::zeros(); x.len()];
    model.forces(x, v, &mut f);
    let hold = |slot: usize, normal: Vec3| Hold {
        slot,
        normal: normal.normalize(),
        held: false,
        impulse: 0.0,
    };
    let mut holds: Vec<Hold> = (0..x.len())
        .step_by(4)
        .map(|i| hold(i, -f[i].normalize() + Vec3::new(0.3, -0.2, 0.1)))
        .collect();
    let pulled = holds.pop().expect("some holds").slot;
    holds.push(hold(pulled, f[pulled]));
    holds
}

/// An integrator with `solver`, its CG run to a tight tolerance (so every solver gives the
/// same solution to about 1e-8).
fn tight(solver: LinearSolver) -> ImplicitEuler {
    ImplicitEuler::new(&IntegratorParams {
        solver,
        cg_tolerance: 1e-10,
        cg_max_iterations: 10_000,
        ..IntegratorParams::default()
    })
}

#[test]
fn held_slots_keep_their_normal_velocity_and_every_solver_solves_the_rest_alike() {
    let (model, x0, v0, dt) = free_sheet();
    let mut results = Vec::new();
    for solver in SOLVERS {
        let (mut x, mut v) = (x0.clone(), v0.clone());
        let mut integ = tight(solver);
        *integ.holds().expect("implicit Euler holds contacts") = holds_for(&model, &x, &v);
        let stats = integ.step(&model, 0.0, dt, &mut x, &mut v);
        assert!(!stats.unconverged && !stats.solver_fallback, "{stats:?}");
        let holds = integ.holds().unwrap().clone();
        let (last, pressed) = holds.split_last().unwrap();
        assert!(!last.held && last.impulse == 0.0, "pulled off: released");
        for h in pressed {
            assert!(h.held, "{h:?}");
            let change = (v[h.slot] - v0[h.slot]).dot(&h.normal);
            assert!(change.abs() < 1e-12, "{solver:?}: slot {} {change}", h.slot);
        }
        // The filtered residual: what the solver was asked to make small.
        let (system, dv) = (&integ.system, &integ.dv);
        let mut q = vec![Vec3::zeros(); dv.len()];
        system.apply(&model, dv, &mut q);
        let residual: Vec<Vec3> = q.iter().zip(&system.b).map(|(q, b)| q - b).collect();
        let (residual, scale) = (norm(&residual), norm(&system.b));
        assert!(residual < 1e-9 * scale, "{solver:?}: {residual} of {scale}");
        results.push((v, holds));
    }
    let (v_ref, holds_ref) = &results[1]; // the direct solve
    for (v, holds) in &results {
        let diff: Vec<Vec3> = v.iter().zip(v_ref).map(|(a, b)| a - b).collect();
        let diff = norm(&diff);
        assert!(diff <= 1e-7 * norm(v_ref), "{diff}");
        for (a, b) in holds.iter().zip(holds_ref) {
            assert!((a.impulse - b.impulse).abs() <= 1e-6 * b.impulse.abs() + 1e-15);
        }
    }
}

/// Momentum: the elements' terms cancel in the sum over the slots, so the solve's momentum
/// change is the external forces' impulse (gravity, drag) plus the holds' `sum impulse n`.
#[test]
fn the_holds_impulses_are_the_momentum_the_obstacle_gave() {
    let (model, x0, v0, dt) = free_sheet();
    let (mut x, mut v) = (x0.clone(), v0.clone());
    let mut f = vec![Vec3::zeros(); x.len()];
    model.forces(&x, &v, &mut f);
    let mut integ = tight(LinearSolver::Cholesky);
    *integ.holds().unwrap() = holds_for(&model, &x, &v);
    integ.step(&model, 0.0, dt, &mut x, &mut v);
    let system = &integ.system;
    // sum (m + dt C) dv, against dt sum f + sum impulse n.
    let change: Vec3 = (0..x.len()).map(|i| (v[i] - v0[i]) * system.diag[i]).sum();
    let external: Vec3 = f.iter().sum::<Vec3>() * dt;
    let holds = integ.holds().unwrap();
    let from_holds: Vec3 = holds.iter().map(|h| h.normal * h.impulse).sum();
    assert!(from_holds.norm() > 1e-3 * change.norm(), "{from_holds}");
    let error = (change - external - from_holds).norm();
    assert!(error < 1e-9 * change.norm(), "{error} of {}", change.norm());
}

/// Every fourth face of the sheet's mesh pressed 5 mm deep at `x` along a tilted normal, with
/// uneven weights and a stiff penalty (it moves the step's solution by far more than the
/// solvers' tolerance).
fn pressed_for(x: &[Vec3]) -> Vec<PressedFace> {
    let mesh = union_jack(7, 7, 1.0, 1.0);
    mesh.face_vertex_slots()
        .step_by(4)
        .map(|slots| {
            let mut face = PressedFace {
                slots,
                weights: [0.5, 0.3, 0.2],
                normal: Vec3::new(0.1, 0.2, 1.0).normalize(),
                level: 0.0,
                stiffness: 1e5,
            };
            face.level = face.height_of(x) + 5e-3;
            face
        })
        .collect()
}

/// Pressed faces: every solver solves the system with their stiffness alike (the direct one
/// from its assembled matrix, CG from its product), and the direct solve's momentum change is the
/// external forces' impulse plus `dt k depth n` per face at the step's end positions (the
/// penalty linear within the step, unclipped), the force the friction after the step uses.
#[test]
fn pressed_faces_are_solved_alike_by_every_solver_with_their_force_at_the_steps_end() {
    let (model, x0, v0, dt) = free_sheet();
    let faces = pressed_for(&x0);
    let dynamics = Pressed {
        model: &model,
        faces: &faces,
    };
    let mut bare = vec![Vec3::zeros(); x0.len()];
    model.forces(&x0, &v0, &mut bare);
    let mut results = Vec::new();
    for solver in SOLVERS {
        let (mut x, mut v) = (x0.clone(), v0.clone());
        let mut integ = tight(solver);
        let stats = integ.step(&dynamics, 0.0, dt, &mut x, &mut v);
        assert!(!stats.unconverged && !stats.solver_fallback, "{stats:?}");
        let system = &integ.system;
        assert_eq!(system.pressed.len(), faces.len());
        let change: Vec3 = (0..x.len()).map(|i| (v[i] - v0[i]) * system.diag[i]).sum();
        let external: Vec3 = bare.iter().sum::<Vec3>() * dt;
        // Linear within the step: a face that overshoots its level ends with a small pull.
        let penalty: Vec3 = faces
            .iter()
            .map(|p| p.normal * (p.stiffness * p.depth(&x) * dt))
            .sum();
        assert!(penalty.norm() > 0.1 * change.norm(), "{penalty} {change}");
        let error = (change - external - penalty).norm();
        // Exact for the direct solve; CG's iterates carry their tolerance's error.
        if solver == LinearSolver::Cholesky {
            assert!(error < 1e-9 * change.norm(), "{error} of {}", change.norm());
        }
        results.push(v);
    }
    let v_ref = &results[1]; // the direct solve
    for v in &results {
        let diff: Vec<Vec3> = v.iter().zip(v_ref).map(|(a, b)| a - b).collect();
        assert!(norm(&diff) <= 1e-7 * norm(v_ref), "{}", norm(&diff));
    }
}
