//! Range checks of a parsed scene, reported with the file, the line of the key and what was
//! expected.

use super::adaptivity::{sizing_options, strategy_options};
use super::key_lines::subject;
use super::{ClothShape, ObstacleShape, Scene, SceneError};
use crate::math::{Real, Vec3, MAX_COORDINATE};
use std::path::Path;

/// The range a scalar must lie in.
#[derive(Clone, Copy)]
enum Range {
    /// Finite and > 0.
    Positive,
    /// Finite and >= 0.
    NonNegative,
}

/// Shortest and longest cloth side accepted (m): beyond them rest areas and masses under- or
/// overflow (a 1e-200 m or 1e308 m cloth passed the old check and panicked later).
const MIN_LENGTH: Real = 1e-6;
const MAX_LENGTH: Real = 1e6;
/// Largest cloth thickness for self-collision (m): every pair closer than it is tested each step.
const MAX_THICKNESS: Real = 0.05;

/// Largest rotation-vector component accepted (rad): far beyond any turn a keyframe needs, far
/// below where the angle's square overflows.
const MAX_ROTATION: Real = 1e6;

/// Largest gravity accepted (m/s², about 1000 g): a cloth under more passes `time.max_speed`'s
/// default of 100 m/s within 10 ms, and at 1e300 m/s² the first step overflowed.
const MAX_GRAVITY: Real = 1e4;

/// Most output frames a run may ask for (`duration x frame_rate`).
const MAX_FRAMES: Real = 1e5;
/// Most metrics rows a run may ask for (`duration x metrics_rate`).
const MAX_METRIC_ROWS: Real = 1e7;
/// Most steps a run may ask for (`duration / dt`): about 20 minutes for the smallest cloth on
/// this project's machines. Checked here for a fixed step; the dynamic step depends on the built
/// cloth and is estimated by the simulation (`sim::Simulation::check_step_estimate`).
pub const MAX_STEPS: Real = 1e8;

/// Most conjugate-gradient iterations per step (`integrator.cg_max_iterations`; default 200).
const MAX_CG_ITERATIONS: usize = 10_000;
/// Most relaxation passes per step (`integrator.relaxation_passes`; default 4).
const MAX_RELAXATION_PASSES: usize = 1_000;

/// Collects the first out-of-range value of a scene.
pub(super) struct Checker<'a> {
    pub(super) text: &'a str,
    pub(super) source: &'a str,
    /// Keys set by overrides, with the place of the setting that set each: their errors name the
    /// setting, not a line of the scene file.
    pub(super) options: &'a [(String, String)],
}

impl Checker<'_> {
    /// An error for `key` (`section.key`, or `obstacles.N.key`) holding `value`: named by the
    /// setting that set it, else by the file and the key's line ([`subject`]).
    pub(super) fn fail(
        &self,
        key: &str,
        value: impl std::fmt::Display,
        expected: &str,
    ) -> SceneError {
        SceneError::Invalid {
            subject: subject(
                self.text,
                self.source,
                self.options,
                key,
                &value.to_string(),
            ),
            expected: expected.to_string(),
        }
    }

    fn positive(&self, key: &str, v: Real) -> Result<(), SceneError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.fail(key, v, "expected a finite value > 0"))
        }
    }

    /// An obstacle's size (m): positive and at most `MAX_LENGTH`, as the cloth's sides (a box
    /// of half extent 1e308 passed `positive` and panicked in the contact query).
    fn length(&self, key: &str, v: Real) -> Result<(), SceneError> {
        self.length_up_to(key, v, MAX_LENGTH)
    }

    /// A length (m) in `(0, max]`.
    fn length_up_to(&self, key: &str, v: Real, max: Real) -> Result<(), SceneError> {
        if v > 0.0 && v <= max {
            Ok(())
        } else {
            Err(self.fail(key, v, &format!("expected a length in (0, {max:e}] m")))
        }
    }

    fn non_negative(&self, key: &str, v: Real) -> Result<(), SceneError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(self.fail(key, v, "expected a finite value >= 0"))
        }
    }

    /// Checks each `(key, value, range)` in order; the first value out of its range fails.
    fn ranges(&self, checks: &[(&str, Real, Range)]) -> Result<(), SceneError> {
        for &(key, v, range) in checks {
            match range {
                Range::Positive => self.positive(key, v)?,
                Range::NonNegative => self.non_negative(key, v)?,
            }
        }
        Ok(())
    }

    fn open_unit(&self, key: &str, v: Real) -> Result<(), SceneError> {
        if v > 0.0 && v < 1.0 {
            Ok(())
        } else {
            Err(self.fail(key, v, "expected a value in the open interval (0, 1)"))
        }
    }

    /// A position (m): three finite coordinates within [`MAX_COORDINATE`] of the origin.
    pub(super) fn position3(&self, key: &str, v: [Real; 3]) -> Result<(), SceneError> {
        self.within3(key, v, MAX_COORDINATE, "coordinates", "m")
    }

    /// A rotation vector (rad): three finite components within [`MAX_ROTATION`] (a keyframe
    /// rotation of 1e160 rad overflowed its angle and the obstacle vanished).
    pub(super) fn rotation3(&self, key: &str, v: [Real; 3]) -> Result<(), SceneError> {
        self.within3(key, v, MAX_ROTATION, "components", "rad")
    }

    /// Three finite `what` of `v` within `±max` (`unit`).
    fn within3(
        &self,
        key: &str,
        v: [Real; 3],
        max: Real,
        what: &str,
        unit: &str,
    ) -> Result<(), SceneError> {
        if v.iter().all(|c| c.abs() <= max) {
            Ok(())
        } else {
            Err(self.fail(
                key,
                format!("{v:?}"),
                &format!("expected three finite {what} within ±{max:e} {unit}"),
            ))
        }
    }

    /// A velocity (m/s): finite and slower than `time.max_speed`, at which a run counts as
    /// diverged (a cloth started faster ended its run as diverged at its first step).
    fn speed3(&self, key: &str, v: [Real; 3], max_speed: Real) -> Result<(), SceneError> {
        self.finite3(key, v)?;
        let speed = magnitude(v);
        if speed < max_speed {
            Ok(())
        } else {
            Err(self.fail(
                key,
                format!("{v:?}"),
                &format!(
                    "expected a speed below time.max_speed = {max_speed:e} m/s (a run \
                     faster than it counts as diverged); this one is {speed:e} m/s"
                ),
            ))
        }
    }

    pub(super) fn finite3(&self, key: &str, v: [Real; 3]) -> Result<(), SceneError> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(())
        } else {
            Err(self.fail(key, format!("{v:?}"), "expected three finite numbers"))
        }
    }

    fn one_of(&self, key: &str, v: &str, valid: &[&str]) -> Result<(), SceneError> {
        if valid.contains(&v) {
            Ok(())
        } else {
            Err(self.fail(key, v, &format!("expected one of: {}", valid.join(", "))))
        }
    }
}

/// Checks every range of MODEL.md and the scene format; mesh files must exist.
pub(super) fn validate(
    scene: &Scene,
    text: &str,
    source: &str,
    base_dir: &Path,
    options: &[(String, String)],
) -> Result<(), SceneError> {
    let c = Checker {
        text,
        source,
        options,
    };
    let cloth = &scene.cloth;
    for side in cloth.size {
        if !(MIN_LENGTH..=MAX_LENGTH).contains(&side) {
            return Err(c.fail(
                "cloth.size",
                format!("{:?}", cloth.size),
                &format!("expected two sides in [{MIN_LENGTH:e}, {MAX_LENGTH:e}] m"),
            ));
        }
    }
    c.position3("cloth.center", cloth.center)?;
    c.finite3("cloth.rotation_deg", cloth.rotation_deg)?;
    c.finite3("cloth.velocity", cloth.velocity)?;
    // The vertex count the cloth starts with (an OBJ cloth's is checked when it is read).
    let start = match cloth.shape {
        ClothShape::Grid => {
            if cloth.resolution < 2 {
                return Err(c.fail(
                    "cloth.resolution",
                    cloth.resolution,
                    "expected at least 2 vertices per side",
                ));
            }
            if cloth.resolution_v == 1 {
                return Err(c.fail(
                    "cloth.resolution_v",
                    1,
                    "expected 0 (same as resolution) or at least 2",
                ));
            }
            let ny = match cloth.resolution_v {
                0 => cloth.resolution,
                n => n,
            };
            let key = if ny > cloth.resolution {
                "cloth.resolution_v"
            } else {
                "cloth.resolution"
            };
            let what = format!("a {} x {ny} grid", cloth.resolution);
            let value = if key == "cloth.resolution_v" {
                ny
            } else {
                cloth.resolution
            };
            Some(vertex_count(
                &c,
                (key, value),
                cloth.resolution.checked_mul(ny),
                &what,
            )?)
        }
        ClothShape::Disk => {
            if cloth.resolution < 1 {
                return Err(c.fail("cloth.resolution", 0, "expected at least 1 ring"));
            }
            // Ring k has 6k vertices: 1 + 3 r (r + 1) in all.
            let r = cloth.resolution;
            let count = r
                .checked_add(1)
                .and_then(|r1| r1.checked_mul(r))
                .and_then(|n| n.checked_mul(3))
                .and_then(|n| n.checked_add(1));
            let what = format!("a disk of {r} rings");
            Some(vertex_count(&c, ("cloth.resolution", r), count, &what)?)
        }
        ClothShape::Obj => {
            if cloth.mesh.is_empty() {
                return Err(c.fail(
                    "cloth.mesh",
                    "\"\"",
                    "expected an OBJ file for shape = \"obj\"",
                ));
            }
            if let Some(why) = not_a_file(&super::mesh_path(base_dir, &cloth.mesh)) {
                return Err(c.fail(
                    "cloth.mesh",
                    &cloth.mesh,
                    &format!("expected an existing OBJ file ({why})"),
                ));
            }
            None
        }
    };
    for (i, p) in cloth.pinned.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(c.fail(
                &format!("cloth.pinned[{i}]"),
                format!("{p:?}"),
                "expected finite [u, v]",
            ));
        }
    }

    c.finite3("forces.g", scene.forces.g)?;
    let g = magnitude(scene.forces.g);
    if g > MAX_GRAVITY {
        return Err(c.fail(
            "forces.g",
            format!("{:?}", scene.forces.g),
            &format!("expected an acceleration of at most {MAX_GRAVITY:e} m/s² (about 1000 g)"),
        ));
    }
    let (m, t) = (&scene.material, &scene.time);
    use Range::{NonNegative, Positive};
    c.ranges(&[
        ("material.rho", m.rho, Positive),
        ("material.T", m.thickness, Positive),
        ("material.kappa", m.kappa, NonNegative),
        ("material.E", m.young, Positive),
        ("material.alpha", m.alpha, NonNegative),
        ("material.k_b", m.k_b, NonNegative),
        ("material.k_bd", m.k_bd, NonNegative),
        ("material.mu", m.mu, NonNegative),
        ("material.A0", m.cross_section, Positive),
        ("time.duration", t.duration, Positive),
        ("time.dt", t.dt, Positive),
        ("time.beta", t.beta, Positive),
        ("time.dt_initial", t.dt_initial, NonNegative),
        ("time.dt_min", t.dt_min, NonNegative),
        ("time.dt_max", t.dt_max, NonNegative),
        ("time.frame_rate", t.frame_rate, Positive),
        ("time.metrics_rate", t.metrics_rate, Positive),
        ("time.max_speed", t.max_speed, Positive),
    ])?;
    if t.dt_max > 0.0 && t.dt_min > t.dt_max {
        return Err(c.fail("time.dt_min", t.dt_min, "expected dt_min <= dt_max"));
    }
    // Counts a run could never finish (a frame rate of 1e9, a fixed step of 1e-300 s).
    let mut counts = vec![
        (
            "time.frame_rate",
            t.frame_rate,
            t.duration * t.frame_rate,
            MAX_FRAMES,
            "frames",
        ),
        (
            "time.metrics_rate",
            t.metrics_rate,
            t.duration * t.metrics_rate,
            MAX_METRIC_ROWS,
            "metrics rows",
        ),
    ];
    if t.mode == super::TimeMode::Fixed {
        counts.push(("time.dt", t.dt, t.duration / t.dt, MAX_STEPS, "steps"));
    }
    let defaults = super::TimeSpec::default();
    for (key, value, count, max, what) in counts {
        if count > max {
            // A duration too long at the default rate or step is the duration's fault.
            let default_rate = match key {
                "time.frame_rate" => defaults.frame_rate,
                "time.metrics_rate" => defaults.metrics_rate,
                _ => 1.0 / defaults.dt,
            };
            let (key, value) = match t.duration * default_rate > max {
                true => ("time.duration", t.duration),
                false => (key, value),
            };
            return Err(c.fail(
                key,
                format!("{value:e}"),
                &format!(
                    "this run would take {count:.3e} {what} over time.duration = {} s; at most \
                     {max:e} are accepted",
                    crate::console::num(t.duration)
                ),
            ));
        }
    }

    c.one_of(
        "integrator.name",
        &scene.integrator.name,
        crate::physics::INTEGRATORS,
    )?;
    if scene.cloth.pinned_velocity.len() > scene.cloth.pinned.len() {
        return Err(c.fail(
            "cloth.pinned_velocity",
            scene.cloth.pinned_velocity.len(),
            "expected at most one velocity per pinned point",
        ));
    }
    // After time.max_speed's own check.
    c.speed3("cloth.velocity", scene.cloth.velocity, scene.time.max_speed)?;
    for (k, &v) in scene.cloth.pinned_velocity.iter().enumerate() {
        c.speed3(
            &format!("cloth.pinned_velocity.{k}"),
            v,
            scene.time.max_speed,
        )?;
    }
    c.positive("integrator.cg_tolerance", scene.integrator.cg_tolerance)?;
    // Loops inside one step are bounded, so a step (and Ctrl-C between steps) never waits on
    // billions of passes.
    let i = &scene.integrator;
    if !(1..=MAX_CG_ITERATIONS).contains(&i.cg_max_iterations) {
        return Err(c.fail(
            "integrator.cg_max_iterations",
            i.cg_max_iterations,
            &format!("expected 1 to {MAX_CG_ITERATIONS} iterations per step"),
        ));
    }
    if i.relaxation_passes > MAX_RELAXATION_PASSES {
        return Err(c.fail(
            "integrator.relaxation_passes",
            i.relaxation_passes,
            &format!("expected at most {MAX_RELAXATION_PASSES} passes per step"),
        ));
    }
    c.non_negative("collision.margin", scene.collision.margin)?;
    c.open_unit("collision.restitution", scene.collision.restitution)?;
    c.non_negative("collision.penalty", scene.collision.penalty)?;
    c.length_up_to(
        "collision.thickness",
        scene.collision.thickness,
        MAX_THICKNESS,
    )?;

    for (i, o) in scene.obstacles.iter().enumerate() {
        let key = |k: &str| format!("obstacles.{i}.{k}");
        c.non_negative(&key("friction"), o.friction)?;
        if o.restitution != 0.0 {
            c.open_unit(&key("restitution"), o.restitution)?;
        }
        match &o.shape {
            ObstacleShape::Ground { height } => {
                if !height.is_finite() {
                    return Err(c.fail(&key("height"), height, "expected a finite height"));
                }
            }
            ObstacleShape::Sphere { center, radius } => {
                c.position3(&key("center"), *center)?;
                c.length(&key("radius"), *radius)?;
            }
            ObstacleShape::Cylinder {
                center,
                radius,
                height,
            } => {
                c.position3(&key("center"), *center)?;
                c.length(&key("radius"), *radius)?;
                c.length(&key("height"), *height)?;
            }
            ObstacleShape::Box {
                center,
                half_extents,
            } => {
                c.position3(&key("center"), *center)?;
                for h in half_extents {
                    c.length(&key("half_extents"), *h)?;
                }
            }
            ObstacleShape::Mesh {
                file,
                scale,
                translation,
            } => {
                c.positive(&key("scale"), *scale)?;
                c.position3(&key("translation"), *translation)?;
                let why = match file.is_empty() {
                    true => Some("empty path".to_string()),
                    false => not_a_file(&super::mesh_path(base_dir, file)),
                };
                if let Some(why) = why {
                    let shown = if file.is_empty() { "\"\"" } else { file };
                    return Err(c.fail(
                        &key("file"),
                        shown,
                        &format!("expected an existing OBJ file ({why})"),
                    ));
                }
            }
        }
        if let Some(m) = &o.motion {
            if matches!(o.shape, ObstacleShape::Ground { .. }) {
                return Err(c.fail(
                    &key("motion.kind"),
                    super::motion::kind(m),
                    "expected no [obstacles.motion] on the ground: the ground cannot move (a \
                     moving floor is a thin box)",
                ));
            }
            super::motion::check(&c, &key("motion"), m)?;
        }
    }

    let a = &scene.adaptivity;
    c.one_of(
        "adaptivity.strategy",
        &a.strategy,
        crate::strategies::strategy_names(),
    )?;
    strategy_options(&c, a)?;
    sizing_options(&c, a)?;
    c.open_unit("adaptivity.compression_c", a.compression_c)?;
    for (k, v) in [
        ("cos_refine", a.cos_refine),
        ("cos_simplify", a.cos_simplify),
    ] {
        if !(-1.0..=1.0).contains(&v) {
            return Err(c.fail(
                &format!("adaptivity.{k}"),
                v,
                "expected a cosine in [-1, 1]",
            ));
        }
    }
    c.positive("adaptivity.l_min", a.l_min)?;
    c.positive("adaptivity.l_max", a.l_max)?;
    if a.l_min >= a.l_max {
        return Err(c.fail("adaptivity.l_min", a.l_min, "expected l_min < l_max"));
    }
    c.non_negative("adaptivity.h_min", a.h_min)?;
    c.positive("adaptivity.size_angle", a.size_angle)?;
    c.positive("adaptivity.size_velocity", a.size_velocity)?;
    c.positive("adaptivity.size_compression", a.size_compression)?;
    c.non_negative("adaptivity.size_proximity", a.size_proximity)?;
    c.positive("adaptivity.c2", a.c2)?;
    c.non_negative("adaptivity.t_simplify", a.t_simplify)?;
    c.positive("adaptivity.density_refine", a.density_refine)?;
    c.positive("adaptivity.density_simplify", a.density_simplify)?;
    c.positive("adaptivity.depth_factor", a.depth_factor)?;
    if !(0.0..=1.0).contains(&a.flat_contact_cos) {
        return Err(c.fail(
            "adaptivity.flat_contact_cos",
            a.flat_contact_cos,
            "expected a cosine in [0, 1]",
        ));
    }
    c.non_negative("adaptivity.curvature_exponent", a.curvature_exponent)?;
    c.non_negative("adaptivity.interval", a.interval)?;
    if !(1..=16).contains(&a.rounds) {
        return Err(c.fail(
            "adaptivity.rounds",
            a.rounds,
            "expected a number of rounds per pass in 1..=16",
        ));
    }
    if !(1..=crate::mesh::MAX_VERTICES).contains(&a.max_vertices) {
        return Err(c.fail(
            "adaptivity.max_vertices",
            a.max_vertices,
            &format!(
                "expected a vertex count in [1, {}] (the most a run may allocate)",
                crate::mesh::MAX_VERTICES
            ),
        ));
    }
    if let Some(n) = start {
        super::adaptivity::room_for_cloth(&c, a.max_vertices, n)?;
    }
    if !(a.remesh_min_angle > 0.0 && a.remesh_min_angle <= 33.0) {
        return Err(c.fail(
            "adaptivity.remesh_min_angle",
            a.remesh_min_angle,
            "expected an angle in (0, 33] degrees (Delaunay refinement terminates below ~33)",
        ));
    }

    for (i, p) in scene.tracked.iter().enumerate() {
        if !p.rest.iter().all(|x| x.is_finite()) {
            return Err(c.fail(
                &format!("tracked.{i}.rest"),
                format!("{:?}", p.rest),
                "expected finite [u, v]",
            ));
        }
    }
    Ok(())
}

/// Why `path` cannot be read as a file, `None` when it is a regular file or a built-in one: not
/// found (or not readable, or not built in), a folder, or a device, pipe or socket (reading one
/// could block or never end).
pub(crate) fn not_a_file(path: &Path) -> Option<String> {
    let shown = path.display();
    if crate::io::is_embedded_path(path) {
        let built_in = crate::io::embedded_text(path).is_some();
        return (!built_in).then(|| format!("{shown} is not built into the binary"));
    }
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Some(format!("{shown} not found")),
        Err(e) => Some(format!("{shown}: {e}")),
        Ok(m) if m.is_dir() => Some(format!("{shown} is a folder")),
        Ok(m) if !m.is_file() => Some(format!(
            "{shown} is not a regular file: a device, pipe or socket"
        )),
        Ok(_) => None,
    }
}

/// The cloth's vertex count `count`; fails when it is `None` (past `usize`) or more than a run may
/// allocate ([`crate::mesh::MAX_VERTICES`], about [`crate::mesh::BYTES_PER_VERTEX`] bytes each);
/// `what` describes the cloth, `key` is the key to blame with its value.
fn vertex_count(
    c: &Checker,
    (key, value): (&str, usize),
    count: Option<usize>,
    what: &str,
) -> Result<usize, SceneError> {
    use crate::mesh::{BYTES_PER_VERTEX, MAX_VERTICES};
    if let Some(n) = count.filter(|&n| n <= MAX_VERTICES) {
        return Ok(n);
    }
    let need = match count {
        Some(n) => format!(
            "{n} vertices, about {:.3e} GB of memory",
            n as Real * BYTES_PER_VERTEX as Real / 1e9
        ),
        None => "more vertices than this machine can count".to_string(),
    };
    Err(c.fail(
        key,
        value,
        &format!(
            "{what} has {need}; at most {MAX_VERTICES} vertices (about {} GB) are accepted",
            MAX_VERTICES * BYTES_PER_VERTEX / 1_000_000_000
        ),
    ))
}

/// The length of `v` without overflow (a plain norm of `[0, 0, 1e300]` is infinite).
fn magnitude(v: [Real; 3]) -> Real {
    let largest = crate::math::largest_abs(&v);
    if largest > 0.0 {
        largest * (Vec3::from(v) / largest).norm()
    } else {
        0.0
    }
}
