//! Self-collision: the cloth's response to itself (Bridson, Fedkiw & Anderson 2002, MODEL.md
//! §10.2), run after the obstacle response of each step on the step's motion `x_start -> x`
//! (the step loop's `sim::self_pass` gives it the masses and alternates it with the obstacles).
//!
//! 1. **Proximity**: every vertex-face and edge-edge pair closer than the thickness `h` at the
//!    step's start gets an impulse along the line between its closest points, so its relative
//!    normal motion over the step is at least `REPULSION (h - d) / dt` (an approaching pair
//!    stops, a pair too close is eased apart over a few steps), with Coulomb friction `mu` on
//!    the tangential relative motion. A pair already closer than `h` in the rest pattern is one
//!    piece of cloth, held by its springs, not two layers: it gets no repulsion (with `h` above
//!    a triangle's height, the cloth's own neighbours were pushed apart at every step, which
//!    stretched a flat cloth and added energy to it).
//! 2. **Swept test**: over the straight motion of the step, every pair that becomes coplanar
//!    while its closest points meet (within `CCD_TOLERANCE h`), or ends that close, is a
//!    crossing; an impulse along the normal at that moment makes the pair end at least
//!    `CCD_SEPARATION h` apart along it. Repeated up to [`CCD_ROUNDS`] times while crossings are
//!    found.
//! 3. **Impact zones**: crossings left after those rounds merge their vertices into zones that
//!    move rigidly ([`zones`]); repeated until none is left, and after [`ZONE_ROUNDS`] rounds the
//!    whole cloth is one zone (a step taken rigidly, counted as a fallback).
//!
//! Impulses are spread over a pair's four vertices with weights `w_i` and inverse masses, so the
//! relative motion changes by exactly the wanted amount and the linear momentum is kept. End
//! positions take the whole correction; end velocities only the inelastic and friction change of
//! their own relative velocity ([`Motion::velocity_change`]), so a contact adds no kinetic energy.
//! The start positions are assumed free of crossings (the cloth starts flat and every step keeps
//! it so).
//!
//! Pairs come from a list ([`SelfContact::list_pairs`]): those whose boxes over the step's
//! motion, grown by the thickness and a skin, meet ([`tree`]), with their distances then; the
//! list serves the following steps while no vertex leaves the box it was listed with, and a pair
//! is tested only when its listed distance, less how far its vertices moved since, is within
//! reach.
//!
//! Files: `geometry` (closest points, coplanarity times), `tree` (the bounding-volume hierarchy
//! over faces), `zones` (rigid impact zones).

mod geometry;
#[cfg(test)]
mod tests;
mod tree;
mod zones;

use super::apply_friction;
use super::shape::{to_glam, to_na};
use crate::math::{Real, Vec2, Vec3};
use geometry::{closest_between_segments, closest_on_triangle, coplanar_times, Stencil};
use tree::{bounds_of, overlap, Bounds, FaceTree};
use zones::Zones;

/// Fraction of the missing distance `h - d` a too-close pair is pushed apart by in one step.
const REPULSION: Real = 0.1;
/// A pair whose closest points are within this fraction of the thickness when coplanar crosses.
const CCD_TOLERANCE: Real = 1e-3;
/// Distance, as a fraction of the thickness, a crossing pair is left apart at the step's end.
const CCD_SEPARATION: Real = 0.1;
/// Extra pad, as a fraction of the thickness, the pairs are listed with: the list serves the
/// following steps while no vertex leaves the box it was listed with.
const SKIN: Real = 1.0;
/// Rounds of the swept test with impulses before impact zones take over.
pub const CCD_ROUNDS: usize = 8;
/// Rounds of impact zones before the whole cloth moves as one.
pub const ZONE_ROUNDS: usize = 64;

/// What one self-contact pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SelfContactStats {
    /// Pairs closer than the thickness at the step's start that got a repulsion impulse.
    pub proximities: usize,
    /// Crossings found by the swept test and answered by an impulse.
    pub crossings: usize,
    /// Vertices moved rigidly in impact zones.
    pub zone_vertices: usize,
    /// Whether the whole cloth had to move rigidly (impact zones did not settle).
    pub fallback: bool,
}

impl SelfContactStats {
    /// Adds another pass of the same step: counts summed, the fail-safe if either used it.
    pub fn merge(&mut self, other: &SelfContactStats) {
        self.proximities += other.proximities;
        self.crossings += other.crossings;
        self.zone_vertices += other.zone_vertices;
        self.fallback |= other.fallback;
    }
}

/// Self-contact over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct SelfContactTotals {
    /// Pairs closer than the thickness that got a repulsion impulse, summed over steps.
    pub proximities: u64,
    /// Crossings found by the swept test and answered by an impulse, summed over steps.
    pub crossings: u64,
    /// Steps that needed rigid impact zones.
    pub zone_steps: u64,
    /// Steps in which the whole cloth moved rigidly (the fail-safe).
    pub fallbacks: u64,
}

impl SelfContactTotals {
    /// Adds one pass.
    pub fn add(&mut self, s: &SelfContactStats) {
        self.proximities += s.proximities as u64;
        self.crossings += s.crossings as u64;
        self.zone_steps += u64::from(s.zone_vertices > 0);
        self.fallbacks += u64::from(s.fallback);
    }
}

/// One pair of cloth elements to test: a vertex and a face, or two edges (vertex slots).
#[derive(Clone, Copy, Debug)]
enum Pair {
    VertexFace(usize, [usize; 3]),
    EdgeEdge([usize; 2], [usize; 2]),
}

/// Self-collision of one cloth: its thickness, the tree over its faces (kept between steps
/// while the mesh is unchanged) and scratch.
pub struct SelfContact {
    thickness: Real,
    /// The mesh version the tree's faces were listed at.
    version: Option<u64>,
    tree: FaceTree,
    pairs: Vec<Pair>,
    /// Each pair's distance (m) at `x_listed`.
    gaps: Vec<Real>,
    /// Each pair's side: true when its elements are at least the thickness apart in the rest
    /// pattern (only those get a proximity repulsion).
    apart: Vec<bool>,
    /// The rest pattern of mesh version `version`, by slot (m, in the plane `z = 0`).
    rest: Vec<Vec3>,
    /// The positions the pairs were listed at (m): the end of that step.
    x_listed: Vec<Vec3>,
    /// Each vertex's farthest distance from `x_listed` in this step (m), by slot.
    reach: Vec<Real>,
    /// The largest of `reach` (m).
    max_reach: Real,
    /// The listed pairs' indices by increasing gap.
    by_gap: Vec<u32>,
    /// The indices of the pairs that can come near in this step, in list order (scratch).
    near: Vec<u32>,
    /// The mesh version the pairs were listed for.
    listed: Option<u64>,
    /// Swept boxes of the vertices (by slot) and of the edges (by index in the tree's edges).
    vertex_boxes: Vec<Bounds>,
    edge_boxes: Vec<Bounds>,
    zones: Zones,
}

impl SelfContact {
    /// Self-collision with cloth thickness `thickness` (m, positive).
    pub fn new(thickness: Real) -> SelfContact {
        SelfContact {
            thickness,
            version: None,
            tree: FaceTree::default(),
            pairs: Vec::new(),
            gaps: Vec::new(),
            apart: Vec::new(),
            rest: Vec::new(),
            x_listed: Vec::new(),
            reach: Vec::new(),
            max_reach: 0.0,
            by_gap: Vec::new(),
            near: Vec::new(),
            listed: None,
            vertex_boxes: Vec::new(),
            edge_boxes: Vec::new(),
            zones: Zones::default(),
        }
    }

    /// The self-contact pass of one step of `dt` (s): `faces` are the live faces (vertex slots)
    /// of mesh version `version` and `rest` its rest pattern by slot (m; both read only when the
    /// version changed), `x_start` the positions
    /// at the step's start (m, free of crossings), `x` and `v` the positions (m) and velocities
    /// (m/s) at its end, changed in place; vertices of zero inverse mass are never moved; `mu`
    /// is the cloth's friction coefficient. Without `v`, positions only: a correction of
    /// positions (`x_start -> x`, such as the obstacles' push after an adaptation) made free of
    /// crossings, `dt` then only a scale that cancels.
    #[allow(clippy::too_many_arguments)]
    pub fn respond(
        &mut self,
        version: u64,
        faces: impl Iterator<Item = [usize; 3]>,
        rest: &[Vec2],
        x_start: &[Vec3],
        x: &mut [Vec3],
        v: Option<&mut [Vec3]>,
        inv_mass: &[Real],
        mu: Real,
        dt: Real,
    ) -> SelfContactStats {
        if self.version != Some(version) {
            self.tree.set_faces(faces);
            self.rest.clear();
            self.rest
                .extend(rest.iter().map(|r| Vec3::new(r.x, r.y, 0.0)));
            self.version = Some(version);
        }
        let mut stats = SelfContactStats::default();
        let h = self.thickness;
        let mut motion = Motion {
            x_start,
            x,
            v,
            inv_mass,
            dt,
        };
        // 1. Proximity at the step's start.
        self.list_pairs(motion.x_start, motion.x);
        self.select_near(h, true);
        for &j in &self.near {
            let (pair, gap) = (self.pairs[j as usize], self.gaps[j as usize]);
            if gap - self.reach_of(pair) < h {
                stats.proximities += usize::from(motion.repel(pair, h, mu));
            }
        }
        // 2. The swept test, answered by impulses.
        let tolerance = CCD_TOLERANCE * h;
        for _ in 0..CCD_ROUNDS {
            self.list_pairs(motion.x_start, motion.x);
            self.select_near(tolerance, false);
            let mut found = 0;
            for &j in &self.near {
                let (pair, gap) = (self.pairs[j as usize], self.gaps[j as usize]);
                if gap - self.reach_of(pair) >= tolerance {
                    continue;
                }
                if let Some(hit) = motion.first_crossing(pair, tolerance) {
                    found += usize::from(motion.separate(&hit, CCD_SEPARATION * h));
                }
            }
            stats.crossings += found;
            if found == 0 {
                return stats;
            }
        }
        // 3. Rigid impact zones until no crossing is left.
        self.zones.reset(motion.x.len());
        for _ in 0..ZONE_ROUNDS {
            self.list_pairs(motion.x_start, motion.x);
            self.select_near(tolerance, false);
            let mut found = false;
            for &j in &self.near {
                let (pair, gap) = (self.pairs[j as usize], self.gaps[j as usize]);
                if gap - self.reach_of(pair) >= tolerance {
                    continue;
                }
                if let Some(hit) = motion.first_crossing(pair, tolerance) {
                    if !self.zones.same_zone(hit.stencil.v) {
                        found = true;
                        for k in 1..4 {
                            self.zones.union(hit.stencil.v[0], hit.stencil.v[k]);
                        }
                    }
                }
            }
            if !found {
                return stats;
            }
            stats.zone_vertices = self.move_zones(&mut motion);
        }
        // The fail-safe: the whole cloth as one zone.
        let all = self.tree.vertices();
        for &i in all {
            self.zones.union(all[0], i);
        }
        stats.zone_vertices = self.move_zones(&mut motion);
        stats.fallback = true;
        stats
    }

    /// Moves the impact zones rigidly; returns the vertices they hold.
    fn move_zones(&mut self, m: &mut Motion) -> usize {
        let vertices = self.tree.vertices();
        self.zones.move_rigidly(
            vertices,
            m.x_start,
            m.x,
            m.v.as_deref_mut(),
            m.inv_mass,
            m.dt,
        )
    }

    /// Makes `self.pairs` hold every vertex-face and edge-edge pair sharing no vertex whose boxes
    /// over the motion `x_start -> x`, grown by the thickness, meet, with `self.gaps` their
    /// distances (m) where they were listed, and `self.reach` each vertex's farthest distance (m,
    /// at the step's start or end) from where it was listed ([`SelfContact::reach_of`]). The list
    /// is kept while every vertex's box lies inside the one it was listed with (found with the
    /// pad `h + SKIN h`); it is found again otherwise.
    fn list_pairs(&mut self, x_start: &[Vec3], x: &[Vec3]) {
        let h = self.thickness;
        let inside =
            |p: &Vec3, b: &Bounds| (0..3).all(|k| p[k] - h >= b[0][k] && p[k] + h <= b[1][k]);
        let kept = self.listed == self.version
            && self.tree.vertices().iter().all(|&i| {
                inside(&x_start[i], &self.vertex_boxes[i]) && inside(&x[i], &self.vertex_boxes[i])
            });
        if !kept {
            self.find_pairs(x_start, x, h + SKIN * h);
            self.x_listed.clear();
            self.x_listed.extend_from_slice(x);
            let y = &self.x_listed;
            self.gaps.clear();
            self.gaps.extend(self.pairs.iter().map(|&pair| {
                let s = stencil_at(pair, y);
                s.combine(y).norm()
            }));
            let (h, rest) = (self.thickness, &self.rest);
            self.apart.clear();
            self.apart.extend(
                self.pairs
                    .iter()
                    .map(|&pair| stencil_at(pair, rest).combine(rest).norm() >= h),
            );
            let gaps = &self.gaps;
            self.by_gap.clear();
            self.by_gap.extend(0..self.pairs.len() as u32);
            self.by_gap
                .sort_unstable_by(|&a, &b| gaps[a as usize].total_cmp(&gaps[b as usize]));
            self.listed = self.version;
        }
        let y = &self.x_listed;
        self.reach.resize(x.len(), 0.0);
        self.max_reach = 0.0;
        for &i in self.tree.vertices() {
            self.reach[i] = (x_start[i] - y[i]).norm().max((x[i] - y[i]).norm());
            self.max_reach = self.max_reach.max(self.reach[i]);
        }
    }

    /// Puts in `self.near`, in list order, the listed pairs that can come closer than `limit`
    /// (m) in this step, only those apart in the rest pattern when `only_apart`:
    /// `gap - reach_of(pair) < limit` needs `gap < limit + 2 max_reach`, so only a prefix of
    /// `by_gap` is read (a flat cloth's neighbours, listed but apart by about an edge, are never
    /// visited while the list is kept).
    fn select_near(&mut self, limit: Real, only_apart: bool) {
        let cutoff = limit + 2.0 * self.max_reach;
        let (gaps, apart) = (&self.gaps, &self.apart);
        let count = self.by_gap.partition_point(|&j| gaps[j as usize] < cutoff);
        self.near.clear();
        self.near.extend(
            self.by_gap[..count]
                .iter()
                .filter(|&&j| !only_apart || apart[j as usize]),
        );
        self.near.sort_unstable();
    }

    /// How much closer than its listed gap a pair can be during the step (m): the largest reach
    /// of the first element's vertices plus that of the second's (each element's points move no
    /// farther than its farthest vertex).
    fn reach_of(&self, pair: Pair) -> Real {
        let r = |vs: &[usize]| vs.iter().map(|&i| self.reach[i]).fold(0.0, Real::max);
        match pair {
            Pair::VertexFace(p, f) => self.reach[p] + r(&f),
            Pair::EdgeEdge(e1, e2) => r(&e1) + r(&e2),
        }
    }

    /// Lists in `self.pairs` the vertex-face and edge-edge pairs sharing no vertex whose boxes
    /// over the motion `x_start -> x`, grown by `pad` (m), meet; `self.vertex_boxes` keeps the
    /// vertices' boxes.
    fn find_pairs(&mut self, x_start: &[Vec3], x: &[Vec3], pad: Real) {
        let tree = &mut self.tree;
        tree.update(x_start, x, pad);
        tree.find_pairs();
        self.pairs.clear();
        self.vertex_boxes.resize(x.len(), [Vec3::zeros(); 2]);
        for &p in tree.vertices() {
            self.vertex_boxes[p] = bounds_of(&[x_start[p], x[p]], pad);
        }
        self.edge_boxes.clear();
        self.edge_boxes.extend(tree.edges().iter().map(|e| {
            let (a, b) = (&self.vertex_boxes[e[0]], &self.vertex_boxes[e[1]]);
            [a[0].inf(&b[0]), a[1].sup(&b[1])]
        }));
        let edges = tree.edges();
        for &(a, b) in &tree.pairs {
            for (f, g) in [(a, b), (b, a)] {
                let face = tree.faces[g];
                for &p in tree.vertices_of(f) {
                    if !face.contains(&p) && overlap(&self.vertex_boxes[p], &tree.boxes[g]) {
                        self.pairs.push(Pair::VertexFace(p, face));
                    }
                }
            }
            for i in tree.edges_of(a) {
                let e1 = edges[i];
                for j in tree.edges_of(b) {
                    let e2 = edges[j];
                    if !e2.contains(&e1[0])
                        && !e2.contains(&e1[1])
                        && overlap(&self.edge_boxes[i], &self.edge_boxes[j])
                    {
                        self.pairs.push(Pair::EdgeEdge(e1, e2));
                    }
                }
            }
        }
    }
}

/// The pair's stencil at positions `y` (m): its closest points there.
fn stencil_at(pair: Pair, y: &[Vec3]) -> Stencil {
    match pair {
        Pair::VertexFace(p, f) => {
            let b = closest_on_triangle(y[p], y[f[0]], y[f[1]], y[f[2]]);
            Stencil::vertex_face(p, f, b)
        }
        Pair::EdgeEdge(e1, e2) => {
            let (s, t) = closest_between_segments(y[e1[0]], y[e1[1]], y[e2[0]], y[e2[1]]);
            Stencil::edge_edge(e1, e2, s, t)
        }
    }
}

/// A crossing found by the swept test: the pair's stencil at the moment it is coplanar, and the
/// plane's unit normal then, turned toward the side the pair started on.
struct Crossing {
    stencil: Stencil,
    normal: Vec3,
}

/// The step's motion being corrected: start positions, end positions and velocities (none for a
/// correction of positions only).
struct Motion<'a> {
    x_start: &'a [Vec3],
    x: &'a mut [Vec3],
    v: Option<&'a mut [Vec3]>,
    inv_mass: &'a [Real],
    dt: Real,
}

impl Motion<'_> {
    /// The relative velocity of a stencil over the step (m/s).
    fn relative_velocity(&self, s: &Stencil) -> Vec3 {
        (s.combine(self.x) - s.combine(self.x_start)) / self.dt
    }

    /// Changes the stencil's relative velocity by `du` (m/s) with an impulse spread by its
    /// weights and inverse masses (end positions and velocities both); false when every vertex
    /// Changes the stencil's relative motion over the step by `du` (m/s: end positions move by
    /// `dt` times it) and its relative end velocity by `dv` (m/s), each by an impulse spread by
    /// its weights and inverse masses; false when every vertex is pinned. The two differ when
    /// the step's motion is not its velocity (an obstacle's push, a positions-only pass).
    fn apply(&mut self, s: &Stencil, du: Vec3, dv: Vec3) -> bool {
        let denominator: Real = (0..4).map(|k| s.w[k].powi(2) * self.inv_mass[s.v[k]]).sum();
        if denominator <= 0.0 {
            return false;
        }
        for k in 0..4 {
            let share = s.w[k] * self.inv_mass[s.v[k]] / denominator;
            self.x[s.v[k]] += share * du * self.dt;
            if let Some(v) = self.v.as_deref_mut() {
                v[s.v[k]] += share * dv;
            }
        }
        true
    }

    /// The change of a stencil's relative end velocity (m/s) for a contact of normal `n`: an
    /// approaching normal velocity is removed (inelastic), with friction `mu` on the tangential
    /// one; zero without velocities or when not approaching. Repulsion beyond it moves positions
    /// only, so a contact never adds kinetic energy.
    fn velocity_change(&self, s: &Stencil, n: Vec3, mu: Real) -> Vec3 {
        let Some(v) = self.v.as_deref() else {
            return Vec3::zeros();
        };
        let u = s.combine(v);
        let u_n = u.dot(&n);
        if u_n >= 0.0 {
            return Vec3::zeros();
        }
        let u_t = u - n * u_n;
        n * -u_n + to_na(apply_friction(to_glam(u_t), mu, -u_n)) - u_t
    }

    /// Proximity response of one pair closer than `h` (m) at the step's start; true when it
    /// got an impulse.
    fn repel(&mut self, pair: Pair, h: Real, mu: Real) -> bool {
        let s = stencil_at(pair, self.x_start);
        let gap = s.combine(self.x_start);
        let d = gap.norm();
        if d >= h || d <= 0.0 {
            return false;
        }
        let n = gap / d;
        let u = self.relative_velocity(&s);
        let u_n = u.dot(&n);
        let du_n = (REPULSION * (h - d) / self.dt - u_n).max(0.0);
        if du_n <= 0.0 {
            return false;
        }
        let u_t = u - n * u_n;
        let du_t = to_na(apply_friction(to_glam(u_t), mu, du_n)) - u_t;
        let dv = self.velocity_change(&s, n, mu);
        self.apply(&s, n * du_n + du_t, dv)
    }

    /// The first moment in the step at which the pair is coplanar with its closest points
    /// within `tolerance` (m), or else its end if they end within it; none otherwise.
    fn first_crossing(&self, pair: Pair, tolerance: Real) -> Option<Crossing> {
        let v = match pair {
            Pair::VertexFace(p, f) => [p, f[0], f[1], f[2]],
            Pair::EdgeEdge(e1, e2) => [e1[0], e1[1], e2[0], e2[1]],
        };
        let x0 = v.map(|i| self.x_start[i]);
        let dx = v.map(|i| self.x[i] - self.x_start[i]);
        let (times, count) = coplanar_times(x0, dx);
        // The roots, then the end of the step: a pair ending within the tolerance touches
        // (a root at the very end may be lost to rounding, the cubic's sign unchanged).
        for t in times[..count].iter().copied().chain([1.0]) {
            let y = [0, 1, 2, 3].map(|k| x0[k] + dx[k] * t);
            let (stencil, plane) = match pair {
                Pair::VertexFace(p, f) => {
                    let b = closest_on_triangle(y[0], y[1], y[2], y[3]);
                    let plane = (y[2] - y[1]).cross(&(y[3] - y[1]));
                    (Stencil::vertex_face(p, f, b), plane)
                }
                Pair::EdgeEdge(e1, e2) => {
                    let (s, t) = closest_between_segments(y[0], y[1], y[2], y[3]);
                    let plane = (y[1] - y[0]).cross(&(y[3] - y[2]));
                    (Stencil::edge_edge(e1, e2, s, t), plane)
                }
            };
            let gap: Vec3 = (0..4).map(|k| stencil.w[k] * y[k]).sum();
            if gap.norm() > tolerance {
                continue;
            }
            let gap_start = stencil.combine(self.x_start);
            let plane = if plane.norm_squared() > 0.0 {
                plane
            } else {
                gap_start
            };
            let Some(mut normal) = plane.try_normalize(0.0) else {
                continue;
            };
            let side = normal.dot(&gap_start);
            let approach = normal.dot(&(stencil.combine(self.x) - gap_start));
            if side < 0.0 || side == 0.0 && approach > 0.0 {
                normal = -normal;
            }
            return Some(Crossing { stencil, normal });
        }
        None
    }

    /// Answers a crossing: the pair's relative normal velocity becomes large enough for it to
    /// end `separation` (m) apart along the normal; false when every vertex is pinned.
    fn separate(&mut self, hit: &Crossing, separation: Real) -> bool {
        let s = &hit.stencil;
        let side = hit.normal.dot(&s.combine(self.x_start));
        let u_n = self.relative_velocity(s).dot(&hit.normal);
        let du_n = (separation - side) / self.dt - u_n;
        let dv = self.velocity_change(s, hit.normal, 0.0);
        du_n > 0.0 && self.apply(s, hit.normal * du_n, dv)
    }
}
