//! Checks of the `[adaptivity]` keys against what reads them: a strategy-specific key needs a
//! strategy that reads it, a sizing-field key the sizing criteria, the sizing criteria an adaptive
//! strategy, and `max_vertices` room for the cloth it starts from.

use super::validate::Checker;
use super::{AdaptivitySpec, CriteriaSpec, SceneError};

/// Fails when a strategy-specific `[adaptivity]` key holds a non-default value while the scene's
/// strategy ignores it (the strategy registry says which strategies read which key), `static`
/// included. `density_refine` and `density_simplify` (remesh only) are not checked: the source
/// scenes tune them for remesh and are run with every strategy.
pub(super) fn strategy_options(c: &Checker, a: &AdaptivitySpec) -> Result<(), SceneError> {
    let Ok(strategy) = crate::strategies::strategy_named(&a.strategy) else {
        return Ok(());
    };
    let d = AdaptivitySpec::default();
    macro_rules! key {
        ($field:ident) => {
            (
                stringify!($field),
                a.$field.to_string(),
                d.$field.to_string(),
            )
        };
    }
    let keys = [
        key!(curvature_exponent),
        key!(max_depth),
        key!(depth_factor),
        key!(force_completion),
        key!(remesh_min_angle),
    ];
    for (key, value, default) in keys {
        if value == default || strategy.options.contains(&key) {
            continue;
        }
        let users: Vec<&str> = crate::strategies::STRATEGIES
            .iter()
            .filter(|s| s.options.contains(&key))
            .map(|s| s.name)
            .collect();
        return Err(c.fail(
            &format!("adaptivity.{key}"),
            value,
            &format!(
                "strategy `{}` ignores this key; it applies to {} only (remove it or set it to \
                 its default, {default})",
                strategy.name,
                users.join(", ")
            ),
        ));
    }
    Ok(())
}

/// Fails when the criteria are the sizing field's while the strategy never edits the mesh
/// (`static` reads no criteria).
pub(super) fn criteria_need_adaptivity(c: &Checker, a: &AdaptivitySpec) -> Result<(), SceneError> {
    let adapts = crate::strategies::edits_mesh(&a.strategy);
    if a.criteria != CriteriaSpec::Sizing || adapts {
        return Ok(());
    }
    Err(c.fail(
        "adaptivity.criteria",
        "\"sizing\"",
        &format!(
            "strategy `{}` never adapts the mesh and reads no criteria; the sizing field needs \
             an adaptive strategy ({})",
            a.strategy,
            adaptive_names().join(", ")
        ),
    ))
}

/// A note when `h_min` (the shortest edge an adaptive strategy may create) is set while the
/// strategy never edits the mesh, which ignores it: for a run on its own, where a forgotten
/// `--strategy` would otherwise run the static grid silently. Not an error: a study's `set` of
/// `h_min` reaches its static runs, whose `scene.resolved.toml` keeps it and must run again.
pub(super) fn ignored_floor(a: &AdaptivitySpec) -> Option<String> {
    let adapts = crate::strategies::edits_mesh(&a.strategy);
    if adapts || a.h_min == AdaptivitySpec::default().h_min {
        return None;
    }
    Some(format!(
        "note: adaptivity.h_min = {} is ignored: strategy `{}` never adapts the mesh (its grid is \
         cloth.resolution); an adaptive strategy reads it: --strategy {}",
        a.h_min,
        a.strategy,
        adaptive_names().join(" | --strategy ")
    ))
}

/// The strategies that edit the mesh, in registry order.
fn adaptive_names() -> Vec<&'static str> {
    crate::strategies::STRATEGIES
        .iter()
        .filter(|s| s.edits_mesh)
        .map(|s| s.name)
        .collect()
}

/// Fails when a sizing-field key (`size_*`) holds a non-default value while the scene's criteria
/// are the source's, which never read it.
pub(super) fn sizing_options(c: &Checker, a: &AdaptivitySpec) -> Result<(), SceneError> {
    if a.criteria == CriteriaSpec::Sizing {
        return Ok(());
    }
    let d = AdaptivitySpec::default();
    let keys = [
        ("size_angle", a.size_angle, d.size_angle),
        ("size_velocity", a.size_velocity, d.size_velocity),
        ("size_compression", a.size_compression, d.size_compression),
        ("size_proximity", a.size_proximity, d.size_proximity),
    ];
    for (key, value, default) in keys {
        if value != default {
            return Err(c.fail(
                &format!("adaptivity.{key}"),
                value,
                &format!(
                    "a sizing-field key, read only with adaptivity.criteria = \"sizing\" \
                     (remove it or set it to its default, {default})"
                ),
            ));
        }
    }
    Ok(())
}

/// Fails when `max_vertices` (`adaptivity.max_vertices`) is below `start`, the vertex count of
/// the cloth the run starts from: the run could only fail at its first adaptation pass.
pub(super) fn room_for_cloth(
    c: &Checker,
    max_vertices: usize,
    start: usize,
) -> Result<(), SceneError> {
    if max_vertices >= start {
        return Ok(());
    }
    Err(c.fail(
        "adaptivity.max_vertices",
        max_vertices,
        &format!("expected at least the {start} vertices the cloth starts with"),
    ))
}
