//! Rigid motion of an obstacle (`[obstacles.motion]`): the pose of the world's rigid motion at a
//! time, and the velocity of the obstacle's material at a point.
//!
//! A motion `M(t)` is a rigid map of world space; an obstacle built at pose `P` (its shape's local
//! frame to the world) stands at `M(t) P` at time `t`. Still obstacles have no motion at all (the
//! collision queries skip every transform for them).

use crate::math::Real;
use parry3d_f64::math::{Pose, Rotation, Vector};

/// How an obstacle moves: a rigid motion of the world applied to the obstacle as built.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ObstacleMotion {
    /// It does not move (the default).
    #[default]
    Still,
    /// Translation at a constant velocity (m/s): offset `velocity t` at time `t` (s).
    Linear {
        /// Velocity (m/s).
        velocity: [Real; 3],
    },
    /// Rotation at a constant rate about a fixed axis: angle `angular_velocity t` at time `t`.
    Spin {
        /// A point of the axis (m).
        axis_point: [Real; 3],
        /// Direction of the axis (any length but zero); the rotation is right-handed about it.
        axis: [Real; 3],
        /// Angular velocity (rad/s).
        angular_velocity: Real,
    },
    /// Translation offsets (m) at keyframe times (s), linearly interpolated in between and held
    /// at the first and last offsets outside `[times[0], times[last]]`.
    Keyframes {
        /// Keyframe times (s), strictly increasing, at least one.
        times: Vec<Real>,
        /// Offset from the obstacle as built at each time (m), as many as `times`.
        positions: Vec<[Real; 3]>,
    },
}

/// The velocity field of a rigid motion at one time: `linear + angular x (p - center)` (m/s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RigidVelocity {
    /// Velocity of the material at `center` (m/s).
    pub linear: Vector,
    /// Angular velocity (rad/s, right-handed).
    pub angular: Vector,
    /// The point whose velocity is `linear` (m).
    pub center: Vector,
}

impl RigidVelocity {
    /// Velocity (m/s) of the obstacle's material at the world point `p` (m).
    #[inline]
    pub fn at(&self, p: Vector) -> Vector {
        self.linear + self.angular.cross(p - self.center)
    }
}

fn vector(a: [Real; 3]) -> Vector {
    Vector::new(a[0], a[1], a[2])
}

impl ObstacleMotion {
    /// Whether the obstacle stays where it was built.
    pub fn is_still(&self) -> bool {
        matches!(self, ObstacleMotion::Still)
    }

    /// Why this motion is not usable, `None` when it is: non-finite numbers, a zero axis,
    /// keyframe times not strictly increasing, or as many positions as times missing.
    pub fn problem(&self) -> Option<String> {
        let finite = |a: &[Real]| a.iter().all(|c| c.is_finite());
        match self {
            ObstacleMotion::Still => None,
            ObstacleMotion::Linear { velocity } => {
                (!finite(velocity)).then(|| format!("velocity must be finite, got {velocity:?}"))
            }
            ObstacleMotion::Spin {
                axis_point,
                axis,
                angular_velocity,
            } => {
                if !(finite(axis_point) && finite(axis) && angular_velocity.is_finite()) {
                    Some("axis_point, axis and angular_velocity must be finite".into())
                } else if vector(*axis).try_normalize().is_none() {
                    Some(format!("axis must not be zero, got {axis:?}"))
                } else {
                    None
                }
            }
            ObstacleMotion::Keyframes { times, positions } => {
                if times.is_empty() || times.len() != positions.len() {
                    Some(format!(
                        "expected as many positions as times, at least one (got {} times, {} \
                         positions)",
                        times.len(),
                        positions.len()
                    ))
                } else if !(finite(times) && positions.iter().all(|p| finite(p))) {
                    Some("times and positions must be finite".into())
                } else if times.windows(2).any(|w| w[1] <= w[0]) {
                    Some(format!("times must be strictly increasing, got {times:?}"))
                } else {
                    None
                }
            }
        }
    }

    /// The rigid motion `M(t)` at time `t` (s): identity when still, and for a motion with a
    /// [`ObstacleMotion::problem`] (the queries never see one: building refuses it).
    pub(crate) fn pose(&self, t: Real) -> Pose {
        if self.problem().is_some() {
            return Pose::identity();
        }
        match self {
            ObstacleMotion::Still => Pose::identity(),
            ObstacleMotion::Linear { velocity } => Pose::from_translation(vector(*velocity) * t),
            ObstacleMotion::Spin {
                axis_point,
                axis,
                angular_velocity,
            } => {
                let c = vector(*axis_point);
                let r = Rotation::from_axis_angle(vector(*axis).normalize(), angular_velocity * t);
                Pose::from_parts(c - r * c, r)
            }
            ObstacleMotion::Keyframes { times, positions } => {
                Pose::from_translation(keyframe(times, positions, t).0)
            }
        }
    }

    /// The velocity field of the obstacle at time `t` (s) (for keyframes, the slope of the
    /// segment `[times[k], times[k + 1])` holding `t`, zero outside the keyframes).
    pub(crate) fn velocity(&self, t: Real) -> RigidVelocity {
        let mut v = RigidVelocity::default();
        if self.problem().is_some() {
            return v;
        }
        match self {
            ObstacleMotion::Still => {}
            ObstacleMotion::Linear { velocity } => v.linear = vector(*velocity),
            ObstacleMotion::Spin {
                axis_point,
                axis,
                angular_velocity,
            } => {
                v.angular = vector(*axis).normalize() * *angular_velocity;
                v.center = vector(*axis_point);
            }
            ObstacleMotion::Keyframes { times, positions } => {
                v.linear = keyframe(times, positions, t).1;
            }
        }
        v
    }

    /// The rigid motion at time `t` (s) as a row-major 3 x 3 rotation followed by the
    /// translation (m): `M(t) p = R p + d`.
    pub fn matrix(&self, t: Real) -> [Real; 12] {
        let pose = self.pose(t);
        let r = parry3d_f64::math::Matrix::from_quat(pose.rotation);
        let d = pose.translation;
        let row = |i: usize| r.row(i);
        let (a, b, c) = (row(0), row(1), row(2));
        [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, d.x, d.y, d.z]
    }
}

/// The interpolated keyframe offset at `t` (m) and the velocity of its segment (m/s).
fn keyframe(times: &[Real], positions: &[[Real; 3]], t: Real) -> (Vector, Vector) {
    let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
        return (Vector::ZERO, Vector::ZERO);
    };
    let at = |k: usize| positions.get(k).copied().map_or(Vector::ZERO, vector);
    if t < first {
        return (at(0), Vector::ZERO);
    }
    if t >= last {
        return (at(times.len() - 1), Vector::ZERO);
    }
    // times[k] <= t < times[k + 1]
    let k = times.partition_point(|&s| s <= t) - 1;
    let span = times[k + 1] - times[k];
    let slope = (at(k + 1) - at(k)) / span;
    (at(k) + slope * (t - times[k]), slope)
}
