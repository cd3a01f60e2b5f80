//! Physics laws and known solutions for the force model and the integrators.

use super::forces::bend_modes;
use super::*;
use crate::math::{Real, Vec2, Vec3};
use crate::mesh::{union_jack, Mesh, VertexId};
use crate::physics::{Forces, Material, SpringMode, StiffnessModel};
use crate::testing::{built, lifted, no_forces, random_state};

/// Every registered integrator by name with its default options (`implicit_euler` with the
/// `pcg_springs` solver), then `implicit_euler` with each other solver named
/// (`implicit_euler/cg`, `implicit_euler/cholesky`, `implicit_euler/auto`): laws of the integrators hold whatever solves the implicit step.
fn every_integrator() -> Vec<(String, Box<dyn Integrator>)> {
    let with = |solver| {
        let params = IntegratorParams {
            solver,
            ..IntegratorParams::default()
        };
        make_integrator("implicit_euler", &params).expect("registered")
    };
    INTEGRATORS
        .iter()
        .map(|n| (n.to_string(), integrator_named(n).expect("registered")))
        .chain([
            ("implicit_euler/cg".to_string(), with(LinearSolver::Cg)),
            (
                "implicit_euler/cholesky".to_string(),
                with(LinearSolver::Cholesky),
            ),
            ("implicit_euler/auto".to_string(), with(LinearSolver::Auto)),
        ])
        .collect()
}

fn forces_of(model: &ForceModel, x: &[Vec3], v: &[Vec3]) -> Vec<Vec3> {
    let mut f = vec![Vec3::new(7.0, 7.0, 7.0); x.len()]; // overwritten
    model.forces(x, v, &mut f);
    f
}

fn scale(f: &[Vec3]) -> Real {
    f.iter().map(|fi| fi.norm()).sum()
}

#[test]
fn internal_forces_and_torques_sum_to_zero() {
    let mesh = union_jack(6, 6, 1.0, 1.0);
    for springs in [SpringMode::Tension, SpringMode::Both] {
        let material = Material {
            springs,
            ..Material::default()
        };
        let model = built(&mesh, &material, &Forces::default());
        for seed in 0..5 {
            let (mut x, v) = random_state(&mesh, seed, 0.06);
            // Away from the origin, so torques about it are not trivially small.
            for xi in &mut x {
                *xi += Vec3::new(3.0, -2.0, 5.0);
            }
            let mut f = vec![Vec3::zeros(); x.len()];
            model.internal_forces(&x, &v, &mut f);
            let total: Vec3 = f.iter().sum();
            let torque: Vec3 = x.iter().zip(&f).map(|(xi, fi)| xi.cross(fi)).sum();
            let fs = scale(&f);
            let ts: Real = x.iter().zip(&f).map(|(xi, fi)| xi.norm() * fi.norm()).sum();
            assert!(fs > 0.0);
            assert!(total.norm() <= 1e-10 * fs, "net force {total} vs {fs}");
            assert!(torque.norm() <= 1e-10 * ts, "net torque {torque} vs {ts}");
        }
    }
}

#[test]
fn bending_alone_conserves_momentum() {
    // Bending forces are far smaller than spring forces: check them on their own scale.
    let mesh = union_jack(6, 6, 1.0, 1.0);
    let forces = Forces {
        bending: true,
        bending_damping: true,
        ..no_forces()
    };
    let model = built(&mesh, &Material::default(), &forces);
    let (x, v) = random_state(&mesh, 11, 0.08);
    let f = forces_of(&model, &x, &v);
    let total: Vec3 = f.iter().sum();
    let torque: Vec3 = x.iter().zip(&f).map(|(xi, fi)| xi.cross(fi)).sum();
    let fs = scale(&f);
    assert!(fs > 0.0);
    assert!(total.norm() <= 1e-10 * fs);
    assert!(torque.norm() <= 1e-10 * fs);
}

#[test]
fn mesh_at_rest_feels_no_spring_or_bending_force() {
    let mesh = union_jack(6, 6, 1.0, 1.0);
    let forces = Forces {
        gravity: false,
        drag: false,
        ..Forces::default()
    };
    for springs in [SpringMode::Tension, SpringMode::Both] {
        let material = Material {
            springs,
            ..Material::default()
        };
        let model = built(&mesh, &material, &forces);
        let x = lifted(&mesh);
        let v = vec![Vec3::zeros(); x.len()];
        let f = forces_of(&model, &x, &v);
        assert!(f.iter().all(|fi| *fi == Vec3::zeros()), "flat rest state");

        // Rigidly moved: zero to round-off (relative to k_max x 1 m).
        let rot = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1);
        let moved: Vec<Vec3> = x
            .iter()
            .map(|xi| rot * xi + Vec3::new(0.5, 2.0, -1.0))
            .collect();
        let f = forces_of(&model, &moved, &v);
        let bound = 1e-12 * model.max_stiffness();
        assert!(
            f.iter().all(|fi| fi.norm() <= bound),
            "rigidly moved rest state"
        );
    }
}

/// Two triangles sharing the edge 0-1, folded about it: vertex 2 lifted by `phi` (rad).
fn diamond(phi: Real) -> (Mesh, Vec<Vec3>) {
    let rest = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.5, 1.0),
        Vec2::new(0.5, -1.0),
    ];
    let mesh = Mesh::from_faces(rest, &[[0, 1, 2], [1, 0, 3]]).expect("valid diamond");
    let x = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.5, phi.cos(), phi.sin()),
        Vec3::new(0.5, -1.0, 0.0),
    ];
    (mesh, x)
}

/// The angle (rad) between the normals of the two diamond faces, oriented as in the mesh.
fn fold_angle(x: &[Vec3]) -> Real {
    let n1 = (x[1] - x[0]).cross(&(x[2] - x[0])).normalize();
    let n2 = (x[0] - x[1]).cross(&(x[3] - x[1])).normalize();
    n1.dot(&n2).clamp(-1.0, 1.0).acos()
}

#[test]
fn bends_take_their_orientation_from_the_faces() {
    let (mesh, _) = diamond(0.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    assert_eq!(model.bends().v, vec![[2, 3, 0, 1]]);
    assert_eq!(model.springs().len(), 5);
}

#[test]
fn bending_pushes_a_fold_back_towards_flat() {
    let forces = Forces {
        bending: true,
        ..no_forces()
    };
    for phi in [0.4, -0.4, 0.05, -1.5, 2.5] {
        let (mesh, x) = diamond(phi);
        let model = built(&mesh, &Material::default(), &forces);
        let v = vec![Vec3::zeros(); 4];
        let f = forces_of(&model, &x, &v);
        assert!(scale(&f) > 0.0);
        let h = 1e-4 / f.iter().map(|fi| fi.norm()).fold(0.0, Real::max);
        let stepped: Vec<Vec3> = x.iter().zip(&f).map(|(xi, fi)| xi + fi * h).collect();
        let (before, after) = (fold_angle(&x), fold_angle(&stepped));
        assert!(after < before, "phi {phi}: fold {before} -> {after}");
    }
}

#[test]
fn bending_force_matches_bridson_formula() {
    // Fold angle phi: sin(theta/2) = -sin(phi/2) for this orientation, |e| = 1,
    // |N1| = |N2| = 1, so f1 = k_b (1/2) sin(theta/2) N1.
    let phi: Real = 0.6;
    let (mesh, x) = diamond(phi);
    let material = Material::default();
    let forces = Forces {
        bending: true,
        ..no_forces()
    };
    let model = built(&mesh, &material, &forces);
    let f = forces_of(&model, &x, &[Vec3::zeros(); 4]);
    let n1 = (x[2] - x[0]).cross(&(x[2] - x[1]));
    let expected = n1 * (material.k_b * 0.5 * -(phi / 2.0).sin());
    assert!(
        (f[2] - expected).norm() <= 1e-14,
        "{} vs {}",
        f[2],
        expected
    );
}

#[test]
fn bending_damping_opposes_folding_velocity() {
    let forces = Forces {
        bending_damping: true,
        ..no_forces()
    };
    for phi in [0.0, 0.3, -0.8] {
        let (mesh, x) = diamond(phi);
        let model = built(&mesh, &Material::default(), &forces);
        for omega in [1.0, -2.0] {
            // Folding velocity of vertex 2 about the shared edge.
            let mut v = vec![Vec3::zeros(); 4];
            v[2] = Vec3::new(0.0, -phi.sin(), phi.cos()) * omega;
            let f = forces_of(&model, &x, &v);
            let power: Real = f.iter().zip(&v).map(|(fi, vi)| fi.dot(vi)).sum();
            assert!(power < 0.0, "phi {phi} omega {omega}: power {power}");
        }
        // A rigid translation is not damped.
        let v = vec![Vec3::new(0.3, -1.0, 2.0); 4];
        let f = forces_of(&model, &x, &v);
        assert!(scale(&f) <= 1e-14);
    }
}

#[test]
fn bending_sign_is_consistent_over_a_curved_sheet() {
    // Grid rolled onto a cylinder curving towards +z: every element bends the same way.
    let mesh = union_jack(9, 9, 1.0, 1.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let r = 0.8;
    let x: Vec<Vec3> = lifted(&mesh)
        .iter()
        .map(|p| Vec3::new(r * (p.x / r).sin(), p.y, r * (1.0 - (p.x / r).cos())))
        .collect();
    let sines: Vec<Real> = model
        .bends()
        .v
        .iter()
        .map(|&[a, b, c, d]| {
            let m = bend_modes(x[a as usize], x[b as usize], x[c as usize], x[d as usize]);
            m.expect("no degenerate triangle").sin_half
        })
        .collect();
    assert!(sines.iter().any(|&s| s.abs() > 1e-3));
    let positive = sines.iter().any(|&s| s > 1e-12);
    let negative = sines.iter().any(|&s| s < -1e-12);
    assert!(positive != negative, "mixed signs: {sines:?}");
}

#[test]
fn degenerate_triangles_give_no_nan() {
    let (mesh, mut x) = diamond(0.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let v = vec![Vec3::new(0.0, 0.0, 1.0); 4];
    x[2] = Vec3::new(0.5, 0.0, 0.0); // triangle 0-1-2 collapsed onto the shared edge
    let f = forces_of(&model, &x, &v);
    assert!(f.iter().all(|fi| fi.iter().all(|c| c.is_finite())));
    x[1] = x[0]; // shared edge of zero length, coincident spring ends
    let f = forces_of(&model, &x, &v);
    assert!(f.iter().all(|fi| fi.iter().all(|c| c.is_finite())));
}

#[test]
fn total_mass_is_rho_t_times_pattern_area() {
    let material = Material::default();
    let expected = |mesh: &Mesh| material.rho * material.thickness * mesh.pattern_area();
    let big = union_jack(9, 7, 1.3, 0.7);
    let model = built(&big, &material, &Forces::default());
    let want = expected(&big);
    assert!((model.total_mass() - want).abs() <= 1e-12 * want);
    let area_sum: Real = model.drag().iter().sum::<Real>() / material.kappa;
    assert!((area_sum - big.pattern_area()).abs() <= 1e-12 * big.pattern_area());

    // Vertex parameters updated slot by slot after the mesh grew match a full rebuild.
    let small = union_jack(3, 3, 1.3, 0.7);
    let mut updated = built(&small, &material, &Forces::default());
    let all: Vec<VertexId> = big.vertices().collect();
    updated.update_vertices(&big, &all);
    updated.rebuild_elements(&big);
    assert!((updated.total_mass() - want).abs() <= 1e-12 * want);
    assert_eq!(updated.mass(), model.mass());
    assert_eq!(updated.inv_mass(), model.inv_mass());
    assert_eq!(updated.drag(), model.drag());
    assert_eq!(updated.min_mass(), model.min_mass());
}

#[test]
fn pinned_vertices_keep_mass_and_never_move() {
    let mut mesh = union_jack(4, 4, 1.0, 1.0);
    mesh.set_pinned(VertexId(0), true);
    mesh.set_pinned(VertexId(3), true);
    let model = built(&mesh, &Material::default(), &Forces::default());
    assert!(model.mass()[0] > 0.0);
    assert_eq!(model.inv_mass()[0], 0.0);
    assert_eq!(model.inv_mass()[3], 0.0);
    for (name, mut integ) in every_integrator() {
        let (mut x, mut v) = random_state(&mesh, 3, 0.02);
        let (x0, x3) = (x[0], x[3]);
        for k in 0..5 {
            integ.step(&model, k as Real * 1e-5, 1e-5, &mut x, &mut v);
        }
        assert_eq!((x[0], x[3]), (x0, x3), "{name}");
        assert_eq!((v[0], v[3]), (Vec3::zeros(), Vec3::zeros()), "{name}");
    }
}

/// Under gravity alone (no internal force, so the implicit matrix is the mass matrix), implicit
/// Euler with either solver takes the symplectic Euler steps.
#[test]
fn free_fall_is_exact_with_rk4_and_known_with_symplectic_and_implicit_euler() {
    let mesh = union_jack(5, 5, 1.0, 1.0);
    let forces = Forces {
        gravity: true,
        ..no_forces()
    };
    let model = built(&mesh, &Material::default(), &forces);
    let g = forces.g;
    let v0 = Vec3::new(0.2, -0.1, 0.5);
    let (dt, n) = (1e-3, 100);
    let cases = [
        "rk4",
        "symplectic_euler",
        "implicit_euler",
        "implicit_euler/cg",
        "implicit_euler/cholesky",
    ];
    // The default solver (`pcg_springs`, single-precision preconditioner) stops at a residual
    // `|M dv - b| <= cg_tolerance |b|` with `b = dt M g` (N s), so each step's `dv` (m/s) is off
    // by at most `cg_tolerance dt |g| sqrt(sum m²) / min m` at any vertex. Block-Jacobi CG and
    // Cholesky solve `M dv = b` exactly.
    let mass = model.mass();
    let (sum_sq, min_mass) = mass
        .iter()
        .filter(|&&m| m > 0.0)
        .fold((0.0, Real::INFINITY), |(s, lo), &m| (s + m * m, lo.min(m)));
    let cg_tolerance = IntegratorParams::default().cg_tolerance;
    let dv_bound = cg_tolerance * dt * g.norm() * sum_sq.sqrt() / min_mass;
    for (name, mut integ) in every_integrator() {
        if !cases.contains(&name.as_str()) {
            continue;
        }
        let x0: Vec<Vec3> = lifted(&mesh)
            .iter()
            .map(|p| p + Vec3::new(0.0, 0.0, 1.0))
            .collect();
        let mut x = x0.clone();
        let mut v = vec![v0; x.len()];
        for k in 0..n {
            integ.step(&model, k as Real * dt, dt, &mut x, &mut v);
        }
        let t = n as Real * dt;
        let nf = n as Real;
        let iterative = name == "implicit_euler";
        // After step k the velocity is off by at most k dv_bound, the position by dt times the
        // sum of those, dt n (n + 1) / 2 dv_bound.
        let (x_slack, v_slack) = if iterative {
            (dt * nf * (nf + 1.0) / 2.0 * dv_bound, nf * dv_bound)
        } else {
            (0.0, 0.0)
        };
        for (xi, x0i) in x.iter().zip(&x0) {
            let want = match name.as_str() {
                "rk4" => x0i + v0 * t + g * (0.5 * t * t),
                _ => x0i + v0 * t + g * (dt * dt * nf * (nf + 1.0) / 2.0),
            };
            assert!(
                (xi - want).norm() <= 1e-12 * want.norm() + x_slack,
                "{name}: {xi} vs {want}"
            );
        }
        for vi in &v {
            let want = v0 + g * t;
            assert!(
                (vi - want).norm() <= 1e-12 * want.norm() + v_slack,
                "{name}"
            );
        }
    }
}

/// One spring of stiffness `k` (N/m) and damping `kd` (N s/m), rest length 1 m, along x: particle
/// 0 pinned at the origin, particle 1 of mass `m` (kg) free.
fn single_spring(k: Real, kd: Real, m: Real, springs: SpringMode) -> ForceModel {
    let material = Material {
        springs,
        ..Material::default()
    };
    let forces = Forces {
        springs: true,
        spring_damping: kd > 0.0,
        ..no_forces()
    };
    let springs = Springs {
        a: vec![0],
        b: vec![1],
        rest_length: vec![1.0],
        k: vec![k],
        kd: vec![kd],
    };
    ForceModel::from_parts(&material, &forces, vec![m, m], &[true, false], springs)
}

#[test]
fn single_spring_oscillates_with_the_analytic_period() {
    let (k, m) = (100.0, 0.01);
    let model = single_spring(k, 0.0, m, SpringMode::Both);
    let period = 2.0 * std::f64::consts::PI * (m / k).sqrt();
    let dt = period / 500.0;
    let mut integ = integrator_named("rk4").expect("registered");
    let mut x = vec![Vec3::zeros(), Vec3::new(1.1, 0.0, 0.0)];
    let mut v = vec![Vec3::zeros(); 2];
    let mut crossings = Vec::new();
    let mut t = 0.0;
    for _ in 0..2000 {
        let before = x[1].x - 1.0;
        integ.step(&model, t, dt, &mut x, &mut v);
        let after = x[1].x - 1.0;
        if before < 0.0 && after >= 0.0 {
            crossings.push(t + dt * before / (before - after));
        }
        t += dt;
    }
    assert!(crossings.len() >= 3);
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as Real;
    assert!(
        (measured - period).abs() <= 0.01 * period,
        "{measured} vs {period}"
    );
}

#[test]
fn spring_damping_dissipates_energy_monotonically() {
    let (k, m, kd) = (100.0, 0.01, 0.05);
    let model = single_spring(k, kd, m, SpringMode::Both);
    let energy = |x: &[Vec3], v: &[Vec3]| {
        let s = x[1].norm() - 1.0;
        0.5 * m * v[1].norm_squared() + 0.5 * k * s * s
    };
    let dt = 2.0 * std::f64::consts::PI * (m / k).sqrt() / 200.0;
    let mut integ = integrator_named("rk4").expect("registered");
    let mut x = vec![Vec3::zeros(), Vec3::new(1.1, 0.0, 0.0)];
    let mut v = vec![Vec3::zeros(), Vec3::new(0.0, 0.0, 0.0)];
    let e0 = energy(&x, &v);
    let mut last = e0;
    for step in 0..1000 {
        integ.step(&model, step as Real * dt, dt, &mut x, &mut v);
        let e = energy(&x, &v);
        assert!(e <= last, "step {step}: energy {last} -> {e}");
        last = e;
    }
    assert!(last < 0.5 * e0);
}

#[test]
fn tension_only_spring_is_free_in_compression() {
    let model = single_spring(100.0, 0.0, 0.01, SpringMode::Tension);
    let v = vec![Vec3::zeros(); 2];
    let f = forces_of(&model, &[Vec3::zeros(), Vec3::new(0.9, 0.0, 0.0)], &v);
    assert_eq!(f, vec![Vec3::zeros(); 2]);
    let f = forces_of(&model, &[Vec3::zeros(), Vec3::new(1.1, 0.0, 0.0)], &v);
    assert!((f[0] - Vec3::new(10.0, 0.0, 0.0)).norm() <= 1e-12);
    assert!((f[1] + f[0]).norm() == 0.0);
}

#[test]
fn stiffness_models_match_their_formulas() {
    let mesh = union_jack(5, 4, 1.2, 0.9);
    let seed = Material {
        stiffness: StiffnessModel::Seed,
        cross_section: 2.5e-5,
        alpha: 0.02,
        ..Material::default()
    };
    let model = built(&mesh, &seed, &Forces::default());
    let sp = model.springs();
    assert_eq!(sp.len(), mesh.edge_count());
    for j in 0..sp.len() {
        let l = mesh.rest_length(VertexId(sp.a[j]), VertexId(sp.b[j]));
        assert_eq!(sp.rest_length[j], l);
        let k = seed.young * seed.cross_section / l;
        assert!((sp.k[j] - k).abs() <= 1e-12 * k);
        assert!((sp.kd[j] - seed.alpha * k).abs() <= 1e-12 * k);
    }

    let area = Material::default();
    let model = built(&mesh, &area, &Forces::default());
    let sp = model.springs();
    for (j, (key, faces)) in mesh.edges().enumerate() {
        assert_eq!((sp.a[j], sp.b[j]), (key.0 .0, key.1 .0));
        let s: Real = faces.iter().map(|f| mesh.face_rest_area(f)).sum();
        let l = sp.rest_length[j];
        let k = area.young * area.thickness * s / (l * l);
        assert!((sp.k[j] - k).abs() <= 1e-12 * k);
    }
    let kmax = sp.k.iter().copied().fold(0.0, Real::max);
    assert_eq!(model.max_stiffness(), kmax);
}

#[test]
fn stable_step_follows_its_formula() {
    let mesh = union_jack(5, 5, 1.0, 1.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let m_min = model
        .mass()
        .iter()
        .copied()
        .filter(|&m| m > 0.0)
        .fold(Real::INFINITY, Real::min);
    assert_eq!(model.min_mass(), m_min);
    let beta = 0.3;
    let want = beta * std::f64::consts::PI * (m_min / model.max_stiffness()).sqrt();
    assert!((model.stable_step(beta) - want).abs() <= 1e-15 * want);
    let empty = ForceModel::new(&Material::default(), &Forces::default());
    assert_eq!(empty.stable_step(beta), Real::INFINITY);
}

#[test]
fn a_force_switched_off_equals_all_minus_that_force() {
    let mesh = union_jack(6, 6, 1.0, 1.0);
    let material = Material::default();
    let (x, v) = random_state(&mesh, 42, 0.05);
    let all = forces_of(&built(&mesh, &material, &Forces::default()), &x, &v);
    let tol = 1e-12 * scale(&all);
    type Switch = fn(&mut Forces) -> &mut bool;
    let switches: [(&str, Switch); 6] = [
        ("springs", |s| &mut s.springs),
        ("spring_damping", |s| &mut s.spring_damping),
        ("bending", |s| &mut s.bending),
        ("bending_damping", |s| &mut s.bending_damping),
        ("gravity", |s| &mut s.gravity),
        ("drag", |s| &mut s.drag),
    ];
    let mut sum_of_each = vec![Vec3::zeros(); x.len()];
    for (name, switch) in switches {
        let mut without = Forces::default();
        *switch(&mut without) = false;
        let mut only = no_forces();
        *switch(&mut only) = true;
        let f_without = forces_of(&built(&mesh, &material, &without), &x, &v);
        let f_only = forces_of(&built(&mesh, &material, &only), &x, &v);
        assert!(scale(&f_only) > 0.0, "{name} contributes");
        for i in 0..x.len() {
            assert!((all[i] - f_only[i] - f_without[i]).norm() <= tol, "{name}");
            sum_of_each[i] += f_only[i];
        }
    }
    for i in 0..x.len() {
        assert!((all[i] - sum_of_each[i]).norm() <= tol);
    }
    let none = forces_of(&built(&mesh, &material, &no_forces()), &x, &v);
    assert!(none.iter().all(|fi| *fi == Vec3::zeros()));
}

#[test]
fn accelerations_are_force_over_mass_and_zero_when_fixed() {
    let mut mesh = union_jack(4, 4, 1.0, 1.0);
    mesh.set_pinned(VertexId(5), true);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let (x, v) = random_state(&mesh, 8, 0.03);
    let f = forces_of(&model, &x, &v);
    let mut a = vec![Vec3::zeros(); x.len()];
    model.accelerations(0.0, &x, &v, &mut a);
    for i in 0..x.len() {
        if i == 5 {
            assert_eq!(a[i], Vec3::zeros());
        } else {
            assert!((a[i] * model.mass()[i] - f[i]).norm() <= 1e-12 * f[i].norm());
        }
    }
}

#[test]
fn integrators_are_found_by_name() {
    for name in INTEGRATORS {
        let integ = integrator_named(name).expect("every listed name is registered");
        assert_eq!(integ.name(), *name);
    }
    let err = integrator_named("leapfrog").err().expect("unknown name");
    assert_eq!(err.name, "leapfrog");
    let msg = err.to_string();
    assert!(msg.contains("`leapfrog`"));
    assert!(INTEGRATORS.iter().all(|n| msg.contains(n)), "{msg}");
}

/// A perturbed 4x4 sheet whose springs resist both ways, with only conservative forces.
fn conservative_sheet() -> (ForceModel, Vec<Vec3>, Vec<Vec3>) {
    let mesh = union_jack(4, 4, 1.0, 1.0);
    let material = Material {
        springs: SpringMode::Both,
        young: 1e5,
        ..Material::default()
    };
    let forces = Forces {
        springs: true,
        gravity: true,
        ..no_forces()
    };
    let model = built(&mesh, &material, &forces);
    let (x, v) = random_state(&mesh, 11, 0.03);
    (model, x, v)
}

#[test]
fn rk4_conserves_total_energy_to_fourth_order() {
    let (model, x0, v0) = conservative_sheet();
    let e0 = model.energies(&x0, &v0).total();
    let drift = |n: usize| {
        let (mut x, mut v) = (x0.clone(), v0.clone());
        let mut integ = integrator_named("rk4").expect("registered");
        let dt = 0.05 / n as Real;
        for k in 0..n {
            integ.step(&model, k as Real * dt, dt, &mut x, &mut v);
        }
        (model.energies(&x, &v).total() - e0).abs()
    };
    let (d1, d2) = (drift(200), drift(400));
    assert!(
        d1 > 0.0 && d1 <= 1e-6 * e0.abs().max(1e-3),
        "drift {d1:e} J"
    );
    let order = (d1 / d2).log2();
    assert!(
        order > 3.5,
        "energy drift order {order:.2} ({d1:e} -> {d2:e})"
    );
}

#[test]
fn spring_force_is_minus_the_gradient_of_the_stretch_energy() {
    for mode in [SpringMode::Tension, SpringMode::Both] {
        let mesh = union_jack(3, 3, 1.0, 1.0);
        let material = Material {
            springs: mode,
            ..Material::default()
        };
        let forces = Forces {
            springs: true,
            ..no_forces()
        };
        let model = built(&mesh, &material, &forces);
        let (x, v) = random_state(&mesh, 5, 0.05);
        let f = forces_of(&model, &x, &v);
        let h = 1e-7;
        for i in 0..x.len() {
            for c in 0..3 {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[i][c] += h;
                xm[i][c] -= h;
                let grad = (model.stretch_energy(&xp) - model.stretch_energy(&xm)) / (2.0 * h);
                assert!(
                    (f[i][c] + grad).abs() <= 1e-5 * scale(&f),
                    "{mode:?} vertex {i} axis {c}: f {} vs -dE/dx {}",
                    f[i][c],
                    -grad
                );
            }
        }
    }
}

#[test]
fn bending_energy_is_zero_flat_and_grows_with_the_fold() {
    let forces = Forces {
        bending: true,
        ..no_forces()
    };
    let mut last = -1.0;
    for phi in [0.0, 0.1, 0.4, 1.0] {
        let (mesh, x) = diamond(phi);
        let model = built(&mesh, &Material::default(), &forces);
        let e = model.bending_energy(&x);
        assert!(e > last || (phi == 0.0 && e == 0.0), "phi {phi}: {e}");
        last = e;
    }
}

#[test]
fn a_model_around_some_vertices_sees_their_moves_and_forces_as_the_whole_model_does() {
    let mesh = union_jack(6, 6, 1.0, 1.0);
    let model = built(&mesh, &Material::default(), &Forces::default());
    let slots = [14, 15, 21];
    let local = model.around(&slots);
    assert!(local.springs().len() < model.springs().len());
    let (x, v) = random_state(&mesh, 3, 0.06);
    let mut moved = x.clone();
    for &i in &slots {
        moved[i] += Vec3::new(0.01, -0.02, 0.015);
    }
    let elastic = |m: &ForceModel, x: &[Vec3]| {
        let e = m.energies(x, &v);
        e.stretch + e.bending
    };
    let whole = elastic(&model, &moved) - elastic(&model, &x);
    let part = elastic(&local, &moved) - elastic(&local, &x);
    assert!(whole.abs() > 0.0);
    assert!(
        (whole - part).abs() <= 1e-12 * elastic(&model, &x),
        "{whole} vs {part}"
    );
    let (mut f, mut g) = (vec![Vec3::zeros(); x.len()], vec![Vec3::zeros(); x.len()]);
    model.internal_forces(&moved, &v, &mut f);
    local.internal_forces(&moved, &v, &mut g);
    for &i in &slots {
        assert!((f[i] - g[i]).norm() <= 1e-12 * f[i].norm(), "{i}");
    }
}
