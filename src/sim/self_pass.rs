//! The self-collision pass of a step with the obstacles behind it (MODEL.md §10.2 runs the self
//! pass after the obstacles' response; docs/model-notes.md "Self-collision"):
//!
//! - a vertex whose motion an obstacle's response set in this step (it rests on or hit an
//!   obstacle) is *held*: it weighs `1 / OBSTACLE_BACKED_INV_MASS` times its mass in the self
//!   pass, so a pair between a layer held by an obstacle and a free layer moves the free one,
//!   not the held one into the obstacle;
//! - the obstacles' response then runs again on the vertices the self pass moved, and the self
//!   pass again with the vertices it moved held, up to [`OBSTACLE_ROUNDS`] self passes, until
//!   the obstacles move nothing. The last pass is always the self pass: a crossing left would
//!   stay, a vertex left inside an obstacle's margin is pushed out by the next step.

use crate::collision::{SelfContact, SelfContactStats};
use crate::math::{Real, Vec2, Vec3};

/// Factor on the inverse mass of a held vertex in the self pass: it takes a thousandth of the
/// share of a correction a free vertex of the same mass takes (finite, so a pair held on both
/// sides still splits its correction).
pub const OBSTACLE_BACKED_INV_MASS: Real = 1e-3;

/// Most self passes in one step, with the obstacles' response between them.
pub const OBSTACLE_ROUNDS: usize = 3;

/// Self-collision with the obstacles' response behind it: [`SelfContact`], the positions before
/// that response, and scratch.
pub struct SelfPass {
    contact: SelfContact,
    /// Positions (m) before the latest obstacles' response, by slot.
    before_obstacles: Vec<Vec3>,
    /// Positions (m) before the latest self pass, by slot.
    before_self: Vec<Vec3>,
    /// Vertices an obstacles' response moved in this step, by slot.
    held: Vec<bool>,
    /// The inverse masses (1/kg) of the self pass, or of the obstacles' second response (only
    /// the vertices the self pass moved; 0 for the others).
    inv_mass: Vec<Real>,
}

impl SelfPass {
    /// Self-collision with cloth thickness `thickness` (m, positive).
    pub fn new(thickness: Real) -> SelfPass {
        SelfPass {
            contact: SelfContact::new(thickness),
            before_obstacles: Vec::new(),
            before_self: Vec::new(),
            held: Vec::new(),
            inv_mass: Vec::new(),
        }
    }

    /// Keeps the positions `x` (m) before the step's obstacles' response.
    pub fn before_obstacles(&mut self, x: &[Vec3]) {
        self.before_obstacles.clear();
        self.before_obstacles.extend_from_slice(x);
        self.held.clear();
        self.held.resize(x.len(), false);
    }

    /// Marks held the vertices whose positions `x` differ from the ones kept before the latest
    /// obstacles' response.
    fn mark_held(&mut self, x: &[Vec3]) {
        debug_assert_eq!(self.before_obstacles.len(), x.len());
        for ((held, p), q) in self.held.iter_mut().zip(x).zip(&self.before_obstacles) {
            *held |= p != q;
        }
    }

    /// [`SelfContact::respond`] on the motion `x_start -> x` after the step's obstacles'
    /// response (positions kept by [`SelfPass::before_obstacles`] before it), held vertices'
    /// inverse masses `inv_mass` (1/kg) scaled by [`OBSTACLE_BACKED_INV_MASS`]. With velocities
    /// `v`, `obstacles(x, v, inv_mass)` is then the obstacles' response over the vertices of
    /// positive `inv_mass` (those the self pass moved), returning how many it moved; while it
    /// moves some, the self pass runs again (at most [`OBSTACLE_ROUNDS`] self passes). Without
    /// `v` (a correction of positions only), one self pass. Returns the self passes' counts
    /// summed.
    #[allow(clippy::too_many_arguments)]
    pub fn respond(
        &mut self,
        version: u64,
        faces: impl Iterator<Item = [usize; 3]>,
        rest: &[Vec2],
        x_start: &[Vec3],
        x: &mut [Vec3],
        mut v: Option<&mut [Vec3]>,
        inv_mass: &[Real],
        mu: Real,
        dt: Real,
        mut obstacles: impl FnMut(&mut [Vec3], &mut [Vec3], &[Real]) -> usize,
    ) -> SelfContactStats {
        self.mark_held(x);
        // The faces are read only when the mesh version changed: by the first pass at most.
        let mut faces = Some(faces);
        let mut total = SelfContactStats::default();
        for round in 1..=OBSTACLE_ROUNDS {
            self.inv_mass.clear();
            self.inv_mass
                .extend(inv_mass.iter().zip(&self.held).map(|(&w, &held)| {
                    if held {
                        w * OBSTACLE_BACKED_INV_MASS
                    } else {
                        w
                    }
                }));
            self.before_self.clear();
            self.before_self.extend_from_slice(x);
            let faces = faces.take().into_iter().flatten();
            let stats = self.contact.respond(
                version,
                faces,
                rest,
                x_start,
                x,
                v.as_deref_mut(),
                &self.inv_mass,
                mu,
                dt,
            );
            total.merge(&stats);
            let Some(v) = v.as_deref_mut().filter(|_| round < OBSTACLE_ROUNDS) else {
                break;
            };
            // The obstacles again, over the vertices this pass moved.
            self.inv_mass.clear();
            self.inv_mass.extend(
                inv_mass
                    .iter()
                    .zip(x.iter().zip(&self.before_self))
                    .map(|(&w, (p, q))| if p == q { 0.0 } else { w }),
            );
            if self.inv_mass.iter().all(|&w| w == 0.0) {
                break;
            }
            self.before_obstacles.clear();
            self.before_obstacles.extend_from_slice(x);
            if obstacles(x, v, &self.inv_mass) == 0 {
                break;
            }
            self.mark_held(x);
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::pieces_pattern;

    /// A small triangle (slots 0-2) falling from height `from` to `to` (m) over a large one
    /// (slots 3-5) at height `below`: the faces, start and end positions.
    fn falling_over(from: Real, to: Real, below: Real) -> ([[usize; 3]; 2], Vec<Vec3>, Vec<Vec3>) {
        let small = |z: Real| {
            [
                Vec3::new(0.2, 0.2, z),
                Vec3::new(0.25, 0.2, z),
                Vec3::new(0.2, 0.25, z),
            ]
        };
        let large = [
            Vec3::new(-1.0, -1.0, below),
            Vec3::new(2.0, -1.0, below),
            Vec3::new(-1.0, 2.0, below),
        ];
        let at = |z: Real| small(z).into_iter().chain(large).collect();
        ([[0, 1, 2], [3, 4, 5]], at(from), at(to))
    }

    /// A small triangle falling through a large one the obstacles' response moved (held) in
    /// this step: the momentum the correction keeps is the one of the held masses, so the large
    /// triangle moves a thousand times less than when free.
    #[test]
    fn a_held_layer_gives_way_a_thousand_times_less() {
        let (faces, x_start, x_end) = falling_over(0.01, -0.01, 0.0);
        let inv_mass = [1.0; 6];
        // The vertical shifts of the falling triangle and of the one below, summed.
        let run = |held: bool| {
            let mut pass = SelfPass::new(0.002);
            let mut before = x_end.clone();
            if held {
                for p in &mut before[3..] {
                    p.z -= 0.001;
                }
            }
            pass.before_obstacles(&before);
            let mut x = x_end.clone();
            let mut v = [Vec3::new(0.0, 0.0, -2.0); 6];
            for u in &mut v[3..] {
                *u = Vec3::zeros();
            }
            let stats = pass.respond(
                0,
                faces.iter().copied(),
                &pieces_pattern(&x_start, &faces),
                &x_start,
                &mut x,
                Some(&mut v),
                &inv_mass,
                0.0,
                0.01,
                |_: &mut [Vec3], _: &mut [Vec3], _: &[Real]| 0,
            );
            assert!(stats.crossings > 0);
            let shift = |r: std::ops::Range<usize>| r.map(|i| x[i].z - x_end[i].z).sum::<Real>();
            (shift(0..3), shift(3..6))
        };
        let (falling_free, below_free) = run(false);
        let (falling_held, below_held) = run(true);
        assert!(falling_free > 0.0 && below_free < 0.0);
        assert!(
            (falling_free + below_free).abs() < 1e-9,
            "{falling_free} {below_free}"
        );
        assert!(falling_held > 0.0 && below_held < 0.0);
        let held_momentum = falling_held + below_held / OBSTACLE_BACKED_INV_MASS;
        assert!(held_momentum.abs() < 1e-9, "{falling_held} {below_held}");
        assert!(
            -below_held < 3e-3 * -below_free,
            "{below_held} {below_free}"
        );
    }

    /// A small triangle falling through a lighter large one resting just above an obstacle's
    /// margin (the plane z = 0, margin 1 mm): the self pass pushes the large one into the
    /// margin, the obstacles push it back out, and no crossing comes back.
    #[test]
    fn obstacles_and_self_passes_alternate() {
        const MARGIN: Real = 0.001;
        let (faces, x_start, mut x) = falling_over(0.0065, 0.00105, 0.0013);
        let mut v = vec![Vec3::zeros(); 6];
        for u in &mut v[..3] {
            u.z = -0.545;
        }
        let mut pass = SelfPass::new(0.002);
        pass.before_obstacles(&x);
        let mut calls = 0;
        let ground = |x: &mut [Vec3], v: &mut [Vec3], inv_mass: &[Real]| {
            calls += 1;
            let mut moved = 0;
            for i in 0..x.len() {
                if inv_mass[i] > 0.0 && x[i].z < MARGIN {
                    x[i].z = MARGIN;
                    v[i].z = v[i].z.max(0.0);
                    moved += 1;
                }
            }
            moved
        };
        let inv_mass = [1.0, 1.0, 1.0, 10.0, 10.0, 10.0];
        let stats = pass.respond(
            0,
            faces.iter().copied(),
            &pieces_pattern(&x_start, &faces),
            &x_start,
            &mut x,
            Some(&mut v),
            &inv_mass,
            0.0,
            0.01,
            ground,
        );
        assert!(stats.crossings > 0);
        assert!(calls >= 1);
        for p in &x[3..] {
            assert!(p.z >= MARGIN - 1e-5, "the held layer ends at {} m", p.z);
        }
        // The large triangle's height under each vertex of the small one.
        let n = (x[4] - x[3]).cross(&(x[5] - x[3]));
        let under = |p: &Vec3| x[3].z - (n.x * (p.x - x[3].x) + n.y * (p.y - x[3].y)) / n.z;
        for p in &x[..3] {
            assert!(
                p.z > under(p),
                "the falling layer ends at {} m below {} m",
                p.z,
                under(p)
            );
        }
    }
}
