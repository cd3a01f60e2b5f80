//! Rigid impact zones, the fail-safe of self-contact (Provot 1997; Bridson, Fedkiw & Anderson
//! 2002, §7.4): vertices of contacts the impulses could not resolve are merged into zones, and
//! each zone moves rigidly over the step with the linear and angular momentum of its vertices.
//! A rigid motion keeps a zone as it was at the step's start, where it did not cross itself, so
//! merging until no crossing is left always ends (at worst with one zone).

use crate::math::{Mat3, Real, Vec3};
use nalgebra::Rotation3;

/// Union-find over vertex slots: which zone each vertex belongs to.
#[derive(Default)]
pub struct Zones {
    parent: Vec<usize>,
    /// Vertices of zones with more than one vertex, grouped by zone (scratch).
    members: Vec<(usize, usize)>,
}

impl Zones {
    /// Every vertex of `n` slots alone in its zone.
    pub fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n);
    }

    /// The zone (a representative vertex) of vertex `i`.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Merges the zones of `a` and `b`.
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }

    /// Whether the four vertices are all in one zone (their contact moves rigidly: it cannot
    /// cross).
    pub fn same_zone(&mut self, v: [usize; 4]) -> bool {
        let r = self.find(v[0]);
        v[1..].iter().all(|&i| self.find(i) == r)
    }

    /// Moves every zone of more than one of `vertices` rigidly over the step `dt` (s): from its
    /// start positions `x_start` (m), with the mass-weighted mean velocity and the angular
    /// velocity of the step's velocities `(x - x_start) / dt`; `x` becomes the end position and
    /// `v` (m/s, when given) the rigid velocity there. A zone holding a vertex of zero inverse mass (pinned)
    /// keeps those vertices' own motion and moves the others by their mean displacement.
    /// Returns the number of vertices moved.
    pub fn move_rigidly(
        &mut self,
        vertices: &[usize],
        x_start: &[Vec3],
        x: &mut [Vec3],
        mut v: Option<&mut [Vec3]>,
        inv_mass: &[Real],
        dt: Real,
    ) -> usize {
        let mut members = std::mem::take(&mut self.members);
        members.clear();
        members.extend(vertices.iter().map(|&i| (self.find(i), i)));
        members.sort_unstable();
        let mut moved = 0;
        for zone in members.chunk_by(|a, b| a.0 == b.0) {
            if zone.len() < 2 {
                continue;
            }
            moved += zone.len();
            let zone: Vec<usize> = zone.iter().map(|&(_, i)| i).collect();
            if zone.iter().any(|&i| inv_mass[i] <= 0.0) {
                translate_with_pins(&zone, x_start, x, v.as_deref_mut(), inv_mass, dt);
            } else {
                move_zone(&zone, x_start, x, v.as_deref_mut(), inv_mass, dt);
            }
        }
        self.members = members;
        moved
    }
}

/// The rigid motion of a free zone: translation of its centre of mass, rotation `exp(omega dt)`
/// about it, fitted to the step's motion `(x - x_start) / dt`; the end velocities (when given)
/// become the rigid velocity fitted to them, so a zone keeps its linear momentum and adds no
/// motion an obstacle's push put in the step.
fn move_zone(
    zone: &[usize],
    x_start: &[Vec3],
    x: &mut [Vec3],
    v: Option<&mut [Vec3]>,
    inv_mass: &[Real],
    dt: Real,
) {
    let fit = RigidFit::new(zone, x_start, inv_mass);
    let (v_centre, omega) = fit.velocity(|i| (x[i] - x_start[i]) / dt);
    let turn = Rotation3::new(omega * dt);
    let centre_end = fit.centre + v_centre * dt;
    let velocity = v.as_deref().map(|v| fit.velocity(|i| v[i]));
    for &i in zone {
        x[i] = centre_end + turn * (x_start[i] - fit.centre);
    }
    if let (Some(v), Some((v_centre, omega))) = (v, velocity) {
        for &i in zone {
            v[i] = v_centre + omega.cross(&(x[i] - centre_end));
        }
    }
}

/// Masses, centre and inertia of a zone at the start positions, to fit a rigid velocity to a
/// velocity field.
struct RigidFit<'a> {
    zone: &'a [usize],
    x_start: &'a [Vec3],
    inv_mass: &'a [Real],
    total: Real,
    centre: Vec3,
    /// Inverse inertia tensor about the centre; none when singular (collinear points: the zone
    /// does not turn).
    inv_inertia: Option<Mat3>,
}

impl<'a> RigidFit<'a> {
    fn new(zone: &'a [usize], x_start: &'a [Vec3], inv_mass: &'a [Real]) -> Self {
        let mass = |i: usize| 1.0 / inv_mass[i];
        let total: Real = zone.iter().map(|&i| mass(i)).sum();
        let centre: Vec3 = zone.iter().map(|&i| mass(i) * x_start[i]).sum::<Vec3>() / total;
        let mut inertia = Mat3::zeros();
        for &i in zone {
            let r = x_start[i] - centre;
            inertia += mass(i) * (Mat3::identity() * r.norm_squared() - r * r.transpose());
        }
        RigidFit {
            zone,
            x_start,
            inv_mass,
            total,
            centre,
            inv_inertia: inertia.try_inverse(),
        }
    }

    /// The centre's velocity (momentum over mass) and the angular velocity `I^-1 L` (m/s, 1/s)
    /// of the velocity field `u`.
    fn velocity(&self, u: impl Fn(usize) -> Vec3) -> (Vec3, Vec3) {
        let mut momentum = Vec3::zeros();
        let mut angular = Vec3::zeros();
        for &i in self.zone {
            let m = 1.0 / self.inv_mass[i];
            momentum += m * u(i);
            angular += m * (self.x_start[i] - self.centre).cross(&u(i));
        }
        let omega = self.inv_inertia.map_or(Vec3::zeros(), |inv| inv * angular);
        (momentum / self.total, omega)
    }
}

/// A zone holding pinned vertices: they keep their motion; the others move by the pinned
/// vertices' mean displacement.
fn translate_with_pins(
    zone: &[usize],
    x_start: &[Vec3],
    x: &mut [Vec3],
    mut v: Option<&mut [Vec3]>,
    inv_mass: &[Real],
    dt: Real,
) {
    let pins: Vec<usize> = zone
        .iter()
        .copied()
        .filter(|&i| inv_mass[i] <= 0.0)
        .collect();
    let shift = pins.iter().map(|&i| x[i] - x_start[i]).sum::<Vec3>() / pins.len() as Real;
    for &i in zone {
        if inv_mass[i] > 0.0 {
            x[i] = x_start[i] + shift;
            if let Some(v) = v.as_deref_mut() {
                v[i] = shift / dt;
            }
        }
    }
}
