//! Physics consistency across element sizes (issue 11, item 4): a cloth refined once on its left
//! half only, with no criteria, must sit between the uniform grids' errors. If the spring or
//! bending constants of refined elements made the refined patch stiffer or softer than its
//! surroundings, the patch would carry an error no criterion can remove, and the half-refined
//! cloth would do worse than the coarse grid it was refined from.
//!
//! Every run: the hanging scene (pinned at two corners, swinging), implicit Euler at a fixed 2 ms
//! step for 0.6 s; the reference is the static 65x65 grid under the same integrator and step, so
//! the errors measure the space discretisation alone.
use crate::common::scene;
use adaptcloth::adapt::{ClothTarget, TransferOptions};
use adaptcloth::eval::metrics::positions_at;
use adaptcloth::mesh::EdgeKey;
use adaptcloth::sim::{self, RunOptions, SamplePoints, Simulation, Trajectory};
use adaptcloth::strategies::simnett::Hierarchy;
use std::path::Path;
use std::sync::Arc;

/// RMS over frames and sample points of the material-point error (m): all points, those with
/// rest `u < 0.5` (the refined half) and the others.
#[derive(Debug)]
struct Errors {
    all: f64,
    left: f64,
    right: f64,
}

fn hanging(resolution: usize) -> adaptcloth::scene::LoadedScene {
    let res = format!("cloth.resolution={resolution}");
    scene(
        "hanging",
        &[
            &res,
            "integrator.name=\"implicit_euler\"",
            "time.mode=\"fixed\"",
            "time.dt=0.002",
            "time.duration=0.6",
            "time.frame_rate=20",
        ],
    )
}

/// Splits every edge of every face whose rest centroid has `u < 0.5`, once, through the
/// Simnett hierarchy (1-to-4 inside, temporary children on the border: conforming throughout).
fn refine_left_half(sim: &mut Simulation) {
    let mut hierarchy = Hierarchy::new(&sim.cloth.mesh);
    let mesh = &sim.cloth.mesh;
    let mut edges: Vec<EdgeKey> = Vec::new();
    for f in mesh.faces() {
        let vs = mesh.face(f);
        let centroid_u = vs.iter().map(|&v| mesh.rest(v).x).sum::<f64>() / 3.0;
        if centroid_u < 0.5 {
            for k in 0..3 {
                edges.push(EdgeKey::new(vs[k], vs[(k + 1) % 3]));
            }
        }
    }
    edges.sort();
    edges.dedup();
    let mut target = ClothTarget::new(
        &mut sim.cloth,
        TransferOptions {
            obstacles: None,
            restore_momentum: true,
            ..TransferOptions::default()
        },
    );
    for e in edges {
        hierarchy
            .split_edge(&mut target, e, 1, 0.0)
            .expect("a leaf edge of the start mesh splits");
    }
    sim.after_mesh_edit();
}

fn run(resolution: usize, refine: bool, samples: &Arc<SamplePoints>, out: &Path) -> Trajectory {
    let loaded = hanging(resolution);
    let mut simulation = Simulation::new(&loaded).expect("scene builds");
    if refine {
        refine_left_half(&mut simulation);
    }
    let opts = RunOptions {
        out_dir: out.to_path_buf(),
        samples: Some(samples.clone()),
        source: loaded.source.clone(),
        ..RunOptions::default()
    };
    let summary = sim::run(&mut simulation, &opts).expect("outputs written");
    assert_eq!(
        summary.status,
        sim::RunStatus::Completed,
        "{}",
        summary.message
    );
    summary.trajectory.expect("sampled")
}

fn errors(run: &Trajectory, reference: &Trajectory, samples: &SamplePoints) -> Errors {
    let (mut all, mut left, mut right) = ((0.0, 0), (0.0, 0), (0.0, 0));
    for (k, &t) in run.times.iter().enumerate() {
        let r = positions_at(reference, t);
        for (i, p) in run.frame(k)[..samples.grid].iter().enumerate() {
            let d2: f64 = (0..3).map(|c| (p[c] as f64 - r[i][c]).powi(2)).sum();
            let side = if samples.rest[i][0] < 0.5 - 1e-9 {
                &mut left
            } else {
                &mut right
            };
            side.0 += d2;
            side.1 += 1;
            all.0 += d2;
            all.1 += 1;
        }
    }
    let rms = |(s, n): (f64, usize)| (s / n as f64).sqrt();
    Errors {
        all: rms(all),
        left: rms(left),
        right: rms(right),
    }
}

#[test]
fn a_cloth_refined_on_its_left_half_lies_between_the_uniform_grids() {
    let dir = tempfile::tempdir().unwrap();
    let base = sim::build_cloth(&hanging(9)).unwrap();
    let samples = Arc::new(SamplePoints::grid_over(&base.mesh, 33, &[]));
    let reference = run(65, false, &samples, &dir.path().join("65"));
    let coarse = errors(
        &run(9, false, &samples, &dir.path().join("9")),
        &reference,
        &samples,
    );
    let fine = errors(
        &run(17, false, &samples, &dir.path().join("17")),
        &reference,
        &samples,
    );
    let half = errors(
        &run(9, true, &samples, &dir.path().join("9-half")),
        &reference,
        &samples,
    );
    eprintln!("consistency: 9x9 {coarse:?}\n  17x17 {fine:?}\n  9x9 left half refined {half:?}");
    // The uniform grids converge.
    assert!(fine.all < coarse.all, "17x17 {fine:?} vs 9x9 {coarse:?}");
    // The refined half does better than the coarse grid there, and the whole cloth too: a patch
    // whose constants disagreed with its surroundings would add error instead.
    assert!(half.left < coarse.left, "{half:?} vs 9x9 {coarse:?}");
    assert!(half.all < coarse.all, "{half:?} vs 9x9 {coarse:?}");
    assert!(half.right < coarse.right, "{half:?} vs 9x9 {coarse:?}");
    // On the refined half, closer to the fine grid's error than to the coarse grid's.
    assert!(
        half.left - fine.left < coarse.left - half.left,
        "{half:?} vs 9x9 {coarse:?} and 17x17 {fine:?}"
    );
    // And no better than the grid that is fine everywhere.
    assert!(half.all > fine.all, "{half:?} vs 17x17 {fine:?}");
}
