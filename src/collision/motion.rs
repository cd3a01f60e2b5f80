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
    /// Poses at keyframe times (s): translation offsets (m) linearly interpolated, rotations
    /// about `pivot` spherically (a constant angular velocity between keyframes); held at the
    /// first and last poses outside `[times[0], times[last]]`. The motion at `t` is
    /// `M(t) p = R(t) (p - pivot) + pivot + d(t)`.
    Keyframes {
        /// Keyframe times (s), strictly increasing, at least one.
        times: Vec<Real>,
        /// Offset from the obstacle as built at each time (m), as many as `times`.
        positions: Vec<[Real; 3]>,
        /// Rotation at each time as a rotation vector (axis times angle, rad), as many as
        /// `times`, or none (translations only).
        rotations: Vec<[Real; 3]>,
        /// The point the rotations turn about, as built (m).
        pivot: [Real; 3],
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
    /// keyframe times not strictly increasing, or as many positions (and rotations, when there
    /// are any) as times missing.
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
            ObstacleMotion::Keyframes {
                times,
                positions,
                rotations,
                pivot,
            } => {
                if times.is_empty()
                    || times.len() != positions.len()
                    || !(rotations.is_empty() || rotations.len() == times.len())
                {
                    Some(format!(
                        "expected as many positions (and rotations, if any) as times, at least \
                         one (got {} times, {} positions, {} rotations)",
                        times.len(),
                        positions.len(),
                        rotations.len()
                    ))
                } else if !(finite(times)
                    && finite(pivot)
                    && positions.iter().chain(rotations).all(|p| finite(p)))
                {
                    Some("times, positions, rotations and pivot must be finite".into())
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
            ObstacleMotion::Keyframes { .. } => self.keyframe_pose(t).0,
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
            ObstacleMotion::Keyframes { .. } => v = self.keyframe_pose(t).1,
        }
        v
    }

    /// A keyframed motion's pose at `t` (s) and its velocity field there (the segment's constant
    /// rates, zero outside the keyframes); identity and zero for other motions.
    fn keyframe_pose(&self, t: Real) -> (Pose, RigidVelocity) {
        let ObstacleMotion::Keyframes {
            times,
            positions,
            rotations,
            pivot,
        } = self
        else {
            return (Pose::identity(), RigidVelocity::default());
        };
        let (offset, linear) = keyframe(times, positions, t);
        let turn = |k: usize| {
            rotations.get(k).map_or(Rotation::IDENTITY, |r| {
                Rotation::from_scaled_axis(vector(*r))
            })
        };
        let (rotation, angular) = match segment(times, t) {
            Segment::Before => (turn(0), Vector::ZERO),
            Segment::After => (turn(times.len() - 1), Vector::ZERO),
            Segment::Inside(k, s) => {
                // The shortest turn from keyframe k to k + 1, at a constant rate.
                let step = turn(k + 1) * turn(k).inverse();
                let step = if step.w < 0.0 { -step } else { step };
                let rate = step.to_scaled_axis() / (times[k + 1] - times[k]);
                (
                    Rotation::from_scaled_axis(step.to_scaled_axis() * s) * turn(k),
                    rate,
                )
            }
        };
        let c = vector(*pivot);
        let pose = Pose::from_parts(c + offset - rotation * c, rotation);
        let velocity = RigidVelocity {
            linear,
            angular,
            center: c + offset,
        };
        (pose, velocity)
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

/// Where `t` (s) falls among keyframe times.
enum Segment {
    /// Before the first time (or no times).
    Before,
    /// At or after the last time.
    After,
    /// `times[k] <= t < times[k + 1]`, at fraction `s` of the segment.
    Inside(usize, Real),
}

fn segment(times: &[Real], t: Real) -> Segment {
    match (times.first(), times.last()) {
        (Some(&first), Some(_)) if t >= first => {}
        _ => return Segment::Before,
    }
    if t >= times[times.len() - 1] {
        return Segment::After;
    }
    let k = times.partition_point(|&s| s <= t) - 1;
    Segment::Inside(k, (t - times[k]) / (times[k + 1] - times[k]))
}

/// The interpolated keyframe offset at `t` (m) and the velocity of its segment (m/s).
fn keyframe(times: &[Real], positions: &[[Real; 3]], t: Real) -> (Vector, Vector) {
    let at = |k: usize| positions.get(k).copied().map_or(Vector::ZERO, vector);
    match segment(times, t) {
        Segment::Before => (at(0), Vector::ZERO),
        Segment::After => (at(times.len().saturating_sub(1)), Vector::ZERO),
        Segment::Inside(k, s) => {
            let slope = (at(k + 1) - at(k)) / (times[k + 1] - times[k]);
            (at(k) + (at(k + 1) - at(k)) * s, slope)
        }
    }
}
