//! Self-collision (`[collision] self = true`, issue 16): a cloth dropped folded onto the ground, a
//! cloth falling over a thin bar so its two halves meet, and the bunny scene end every metrics
//! row with no crossing of the cloth with itself, for every strategy; with self-collision off the
//! folded cloth's upper layer falls through the lower one.
use crate::common::{metrics_column, run_into, scene};
use adaptcloth::scene::{self, LoadedScene};
use adaptcloth::sim::{RunStatus, Simulation};
use std::fmt::Write as _;
use std::path::Path;

const STRATEGIES: [&str; 4] = ["static", "remesh", "simnett", "bisect48"];
const THICKNESS: f64 = 2e-3;

/// Implicit Euler at a fixed 2 ms, a metrics row every step.
const SETTINGS: [&str; 4] = [
    "integrator.name=\"implicit_euler\"",
    "time.mode=\"fixed\"",
    "time.dt=0.002",
    "time.metrics_rate=500",
];

/// Folded cloth: rest pattern `1.0 x 0.25` m, `33 x 9` vertices, folded at about `u = 0.5` by a
/// half circle of radius 1 cm so the upper layer lies 2 cm over the lower one, 10 cm above the
/// ground. Returns the OBJ text and the rest `u` where the lower layer ends and the upper begins.
fn folded_obj() -> (String, f64, f64) {
    let (nu, nv) = (33usize, 9usize);
    let (width, depth, r, z0) = (1.0, 0.25, 0.01, 0.1);
    let fold = std::f64::consts::PI * r;
    let a = (width - fold) / 2.0;
    let mut obj = String::new();
    for j in 0..nv {
        for i in 0..nu {
            let u = width * i as f64 / (nu - 1) as f64;
            let v = depth * j as f64 / (nv - 1) as f64;
            let (x, z) = if u <= a {
                (u, z0)
            } else if u <= a + fold {
                let theta = (u - a) / r;
                (a + r * theta.sin(), z0 + r * (1.0 - theta.cos()))
            } else {
                (a - (u - a - fold), z0 + 2.0 * r)
            };
            writeln!(obj, "v {x} {v} {z}\nvt {u} {v}").unwrap();
        }
    }
    let id = |i: usize, j: usize| j * nu + i + 1;
    for j in 0..nv - 1 {
        for i in 0..nu - 1 {
            let (p, q, s, t) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            let (f1, f2) = if (i + j) % 2 == 0 {
                ([p, q, s], [p, s, t])
            } else {
                ([p, q, t], [q, s, t])
            };
            for f in [f1, f2] {
                writeln!(obj, "f {0}/{0} {1}/{1} {2}/{2}", f[0], f[1], f[2]).unwrap();
            }
        }
    }
    (obj, a, a + fold)
}

/// The folded cloth's scene, written with its OBJ into `dir`, with self-collision `on`.
fn folded_scene(dir: &Path, strategy: &str, on: bool) -> LoadedScene {
    let (obj, _, _) = folded_obj();
    std::fs::write(dir.join("folded.obj"), obj).unwrap();
    let text = "name = \"folded\"\n[cloth]\nshape = \"obj\"\nmesh = \"folded.obj\"\n\
                [time]\nduration = 0.5\n[[obstacles]]\nkind = \"ground\"\n";
    let mut set: Vec<String> = SETTINGS.iter().map(|s| s.to_string()).collect();
    set.push(format!("collision.self={on}"));
    set.push(format!("adaptivity.strategy=\"{strategy}\""));
    // Below the start grid's 3.1 cm edges, so the adaptive strategies refine.
    set.push("adaptivity.h_min=0.008".into());
    scene::from_text(text, "folded.toml", "folded", dir.to_path_buf(), &set).expect("valid")
}

/// Runs `loaded` into `out`, checks it completed, and returns the simulation and the largest
/// `self_intersections` over its metrics rows (checked against the summary's figure; the count is
/// taken on the frames' rows and the last one, the other rows leave it empty).
fn run_counting_crossings(loaded: &LoadedScene, out: &Path) -> (Simulation, usize) {
    let (sim, summary) = run_into(loaded, out);
    assert_eq!(summary.status, RunStatus::Completed, "{}", summary.message);
    let all = metrics_column(out, "self_intersections");
    let rows: Vec<f64> = all.iter().copied().filter(|c| !c.is_nan()).collect();
    assert!(
        rows.len() > all.len() / 20 && rows.len() >= summary.frames && rows.len() < all.len(),
        "{} of {} rows",
        rows.len(),
        all.len()
    );
    let worst = rows.iter().copied().fold(0.0, f64::max) as usize;
    assert_eq!(worst, summary.max_self_intersections);
    (sim, worst)
}

/// Mean height (m) of the live vertices whose rest `u` satisfies `pick`.
fn mean_height(sim: &Simulation, pick: impl Fn(f64) -> bool) -> f64 {
    let mesh = &sim.cloth.mesh;
    let z: Vec<f64> = mesh
        .vertices()
        .filter(|&v| pick(mesh.rest(v).x))
        .map(|v| sim.cloth.x[v.0 as usize].z)
        .collect();
    z.iter().sum::<f64>() / z.len() as f64
}

#[test]
fn a_cloth_dropped_folded_on_the_ground_never_crosses_itself() {
    let dir = tempfile::tempdir().unwrap();
    let (_, lower_end, upper_start) = folded_obj();
    let layer_gap = |sim: &Simulation| {
        // Away from the fold, where the layers lie flat over each other.
        mean_height(sim, |u| u > upper_start + 0.1) - mean_height(sim, |u| u < lower_end - 0.1)
    };
    for strategy in STRATEGIES {
        let loaded = folded_scene(dir.path(), strategy, true);
        let (sim, worst) = run_counting_crossings(&loaded, &dir.path().join(strategy));
        assert_eq!(worst, 0, "{strategy}: {worst} crossings at a metrics row");
        assert!(
            sim.self_contact_totals.proximities > 0,
            "{strategy}: no contact"
        );
        let gap = layer_gap(&sim);
        assert!(
            gap > 0.5 * THICKNESS,
            "{strategy}: the layers are {gap} m apart"
        );
    }
    // Without self-collision the upper layer falls through the lower one onto the ground.
    let loaded = folded_scene(dir.path(), "static", false);
    let (sim, _) = run_into(&loaded, &dir.path().join("off"));
    let gap = layer_gap(&sim);
    assert!(gap < 0.5 * THICKNESS, "self-collision off: {gap} m apart");
}

#[test]
fn a_cloth_over_a_thin_bar_folds_both_halves_without_crossing() {
    let dir = tempfile::tempdir().unwrap();
    let text = "name = \"bar\"\n[cloth]\nsize = [1.0, 1.0]\ncenter = [0.0, 0.0, 0.75]\n\
                resolution = 17\n[time]\nduration = 1.0\n[collision]\nself = true\n\
                [[obstacles]]\nkind = \"box\"\ncenter = [0.0, 0.0, 0.7]\n\
                half_extents = [0.7, 0.004, 0.004]\nfriction = 0.3\n";
    for strategy in STRATEGIES {
        let mut set: Vec<String> = SETTINGS.iter().map(|s| s.to_string()).collect();
        set.push(format!("adaptivity.strategy=\"{strategy}\""));
        let loaded = scene::from_text(text, "bar.toml", "bar", dir.path().to_path_buf(), &set)
            .expect("valid");
        let (sim, worst) = run_counting_crossings(&loaded, &dir.path().join(strategy));
        assert_eq!(worst, 0, "{strategy}: {worst} crossings at a metrics row");
        assert!(
            sim.self_contact_totals.proximities > 0,
            "{strategy}: the halves never met"
        );
    }
}

#[test]
fn the_bunny_scene_never_crosses_itself_with_any_strategy() {
    let dir = tempfile::tempdir().unwrap();
    for strategy in STRATEGIES {
        let resolution = if strategy == "static" { 33 } else { 5 };
        let mut set: Vec<String> = SETTINGS.iter().map(|s| s.to_string()).collect();
        set.push(format!("adaptivity.strategy=\"{strategy}\""));
        set.push(format!("cloth.resolution={resolution}"));
        set.push("adaptivity.h_min=0.015".into());
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        let loaded = scene("bunny", &set);
        assert!(
            loaded.scene.collision.self_collision,
            "the bunny scene has it on"
        );
        let (_, worst) = run_counting_crossings(&loaded, &dir.path().join(strategy));
        assert_eq!(worst, 0, "{strategy}: {worst} crossings at a metrics row");
    }
}
