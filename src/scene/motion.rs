//! Range checks of an `[obstacles.motion]` table (the rest of the scene: `validate`).

use super::validate::Checker;
use super::{MotionSpec, SceneError};
use crate::math::Real;

/// The `kind` of a motion as written in the scene.
pub(super) fn kind(m: &MotionSpec) -> &'static str {
    match m {
        MotionSpec::Linear { .. } => "\"linear\"",
        MotionSpec::Spin { .. } => "\"spin\"",
        MotionSpec::Keyframes { .. } => "\"keyframes\"",
    }
}

/// Checks an `[obstacles.motion]` table (`prefix` is `obstacles.N.motion`): finite numbers, a
/// non-zero spin axis, as many keyframe positions as times (at least one) and as many rotations
/// when there are any, times strictly increasing.
pub(super) fn check(c: &Checker, prefix: &str, m: &MotionSpec) -> Result<(), SceneError> {
    let key = |k: &str| format!("{prefix}.{k}");
    match m {
        MotionSpec::Linear { velocity } => c.finite3(&key("velocity"), *velocity),
        MotionSpec::Spin {
            axis_point,
            axis,
            angular_velocity,
        } => {
            c.finite3(&key("axis_point"), *axis_point)?;
            c.finite3(&key("axis"), *axis)?;
            // Normalisable, as the motion needs it: [1e308; 3] (length overflows) and [1e-320,
            // 0, 0] (squares underflow) were refused later as "axis must not be zero".
            let length = axis.iter().map(|a| a * a).sum::<Real>().sqrt();
            if !(length > 0.0 && length.is_finite() && (1.0 / length).is_finite()) {
                return Err(c.fail(
                    &key("axis"),
                    format!("{axis:?}"),
                    "expected a non-zero direction of finite length, e.g. [0, 0, 1]",
                ));
            }
            if !angular_velocity.is_finite() {
                return Err(c.fail(
                    &key("angular_velocity"),
                    angular_velocity,
                    "expected a finite angular velocity (rad/s)",
                ));
            }
            Ok(())
        }
        MotionSpec::Keyframes {
            times,
            positions,
            rotations,
            pivot,
        } => {
            if times.is_empty() || times.len() != positions.len() {
                return Err(c.fail(
                    &key("positions"),
                    format!("{} positions", positions.len()),
                    &format!(
                        "expected one position per time, at least one ({} times)",
                        times.len()
                    ),
                ));
            }
            for (k, t) in times.iter().enumerate() {
                if !t.is_finite() {
                    return Err(c.fail(
                        &format!("{}[{k}]", key("times")),
                        t,
                        "expected a finite time (s)",
                    ));
                }
                if k > 0 && *t <= times[k - 1] {
                    return Err(c.fail(
                        &format!("{}[{k}]", key("times")),
                        t,
                        &format!(
                            "expected times strictly increasing (after {})",
                            times[k - 1]
                        ),
                    ));
                }
            }
            for (k, p) in positions.iter().enumerate() {
                c.position3(&format!("{}[{k}]", key("positions")), *p)?;
            }
            if !rotations.is_empty() && rotations.len() != times.len() {
                return Err(c.fail(
                    &key("rotations"),
                    format!("{} rotations", rotations.len()),
                    &format!(
                        "expected one rotation per time, or none ({} times)",
                        times.len()
                    ),
                ));
            }
            for (k, r) in rotations.iter().enumerate() {
                c.rotation3(&format!("{}[{k}]", key("rotations")), *r)?;
            }
            c.position3(&key("pivot"), *pivot)
        }
    }
}
