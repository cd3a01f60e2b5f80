//! Material-point sampling for the error metrics (MODEL.md §1): an optional recorder the run
//! driver calls at every output frame. It stores the world positions of a fixed set of rest points
//! compactly (f32, frame-major), the final vertex positions (for the surface Hausdorff distance),
//! and the momentum and kinetic-energy jumps of the adaptation events seen in between.
//!
//! In the step: after `record` in [`super::run`]; never touches the simulation state. The
//! barycentric locations of the points are recomputed only when the mesh version changes.

use crate::cloth::Cloth;
use crate::math::{Real, Vec2};
use crate::mesh::{Barycentric, Mesh, RestLocator};
use serde::{Deserialize, Serialize};

/// The rest points to sample: a regular grid over the pattern, then the tracked points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SamplePoints {
    /// Rest points (m): the first `grid` are the grid samples, the rest the tracked points.
    pub rest: Vec<[Real; 2]>,
    /// How many of `rest` are grid samples.
    pub grid: usize,
    /// Points per side when the grid samples form a complete `side x side` grid in row-major
    /// order (u fastest), which lets the metrics triangulate them; 0 when some were off the
    /// pattern.
    #[serde(default)]
    pub side: usize,
}

impl SamplePoints {
    /// An `n x n` grid of rest points spanning the pattern's rest bounding box (corners included),
    /// keeping only the points on the pattern, followed by the `tracked` rest points.
    pub fn grid_over(mesh: &Mesh, n: usize, tracked: &[[Real; 2]]) -> SamplePoints {
        let locator = RestLocator::new(mesh);
        let mut lo = Vec2::repeat(Real::INFINITY);
        let mut hi = Vec2::repeat(Real::NEG_INFINITY);
        for v in mesh.vertices() {
            lo = lo.inf(&mesh.rest(v));
            hi = hi.sup(&mesh.rest(v));
        }
        let n = n.max(2);
        let mut rest = Vec::with_capacity(n * n + tracked.len());
        for j in 0..n {
            for i in 0..n {
                let s = i as Real / (n - 1) as Real;
                let t = j as Real / (n - 1) as Real;
                let p = Vec2::new(lo.x + s * (hi.x - lo.x), lo.y + t * (hi.y - lo.y));
                if locator.locate(mesh, p).is_some() {
                    rest.push([p.x, p.y]);
                }
            }
        }
        let grid = rest.len();
        rest.extend_from_slice(tracked);
        SamplePoints {
            rest,
            grid,
            side: if grid == n * n { n } else { 0 },
        }
    }

    /// Number of points (grid and tracked).
    pub fn len(&self) -> usize {
        self.rest.len()
    }

    /// True when there is no point.
    pub fn is_empty(&self) -> bool {
        self.rest.is_empty()
    }
}

/// Adaptation events seen during a run, with their largest jumps (MODEL.md §6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AdaptJumps {
    /// Elementary adaptation operations applied.
    pub events: u64,
    /// Steps with at least one event.
    pub steps_with_events: u64,
    /// Largest linear-momentum change of one event, after restoration (kg m/s).
    pub max_momentum_change: Real,
    /// Largest absolute kinetic-energy change of one step's events (J).
    pub max_energy_change: Real,
    /// Sum of the kinetic-energy changes of all events (J; negative = lost).
    pub total_energy_change: Real,
}

/// The sampled trajectories of a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory {
    /// Number of points per frame.
    pub points: usize,
    /// How many of the points are grid samples (the others are tracked points).
    pub grid: usize,
    /// Grid samples per side when they form a complete grid (see [`SamplePoints::side`]), else 0.
    pub side: usize,
    /// Simulated time of each recorded frame (s).
    pub times: Vec<Real>,
    /// World positions (m), frame-major: `positions[frame * points + point]`.
    pub positions: Vec<[f32; 3]>,
    /// World positions of the live vertices at the last recorded frame (m).
    pub final_vertices: Vec<[f32; 3]>,
    /// Adaptation events and their jumps.
    pub adapt: AdaptJumps,
}

impl Trajectory {
    /// Number of recorded frames.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    /// The positions of frame `k`.
    pub fn frame(&self, k: usize) -> &[[f32; 3]] {
        &self.positions[k * self.points..(k + 1) * self.points]
    }
}

fn to_f32(p: crate::math::Vec3) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

/// Records a [`Trajectory`] for a set of [`SamplePoints`].
#[derive(Clone, Debug)]
pub struct Sampler {
    rest: Vec<Vec2>,
    locations: Vec<Barycentric>,
    version: Option<u64>,
    out: Trajectory,
}

impl Sampler {
    /// A sampler of `points`.
    pub fn new(points: &SamplePoints) -> Sampler {
        Sampler {
            rest: points.rest.iter().map(|p| Vec2::new(p[0], p[1])).collect(),
            locations: Vec::new(),
            version: None,
            out: Trajectory {
                points: points.len(),
                grid: points.grid,
                side: points.side,
                ..Trajectory::default()
            },
        }
    }

    /// Records the world positions of every point at time `t` (s). A point that cannot be located
    /// (off the pattern) records NaN.
    pub fn record(&mut self, cloth: &Cloth, t: Real) {
        let mesh = &cloth.mesh;
        if self.version != Some(mesh.version()) {
            let locator = RestLocator::new(mesh);
            self.locations = self
                .rest
                .iter()
                .map(|&p| {
                    locator.locate(mesh, p).unwrap_or(Barycentric {
                        face: mesh.faces().next().expect("a cloth has faces"),
                        weights: [Real::NAN; 3],
                    })
                })
                .collect();
            self.version = Some(mesh.version());
        }
        self.out.times.push(t);
        self.out.positions.extend(
            self.locations
                .iter()
                .map(|b| to_f32(cloth.world_position(b))),
        );
        self.out.final_vertices.clear();
        self.out
            .final_vertices
            .extend(mesh.vertices().map(|v| to_f32(cloth.x[v.0 as usize])));
    }

    /// Counts one step's adaptation events and their jumps.
    pub fn observe_adaptation(&mut self, report: &crate::adapt::AdaptReport) {
        if report.events == 0 {
            return;
        }
        let a = &mut self.out.adapt;
        a.events += report.events as u64;
        a.steps_with_events += 1;
        a.max_momentum_change = a.max_momentum_change.max(report.momentum_change);
        a.max_energy_change = a.max_energy_change.max(report.kinetic_energy_change.abs());
        a.total_energy_change += report.kinetic_energy_change;
    }

    /// The recorded trajectory.
    pub fn finish(self) -> Trajectory {
        self.out
    }
}
