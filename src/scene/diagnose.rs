//! Naming the key of an `[[obstacles]]` table that does not parse.
//!
//! An obstacle's keys sit in a flattened, `kind`-tagged enum, so the TOML parser reports any
//! mistake in it (a wrong type, an unknown key, a missing field, an unknown kind) at the
//! `[[obstacles]]` header with no key name. This re-reads the obstacles one key at a time against
//! a valid obstacle of the same kind, so the error names the key, its own line (or the option
//! that set it) and what was expected.

use super::validate::Checker;
use super::{ObstacleShape, ObstacleSpec, SceneError};
use serde::Deserialize;

/// A valid obstacle of each kind: their serialized keys are the keys each kind accepts.
fn templates() -> [ObstacleShape; 5] {
    [
        ObstacleShape::Ground { height: 0.0 },
        ObstacleShape::Sphere {
            center: [0.0; 3],
            radius: 1.0,
        },
        ObstacleShape::Cylinder {
            center: [0.0; 3],
            radius: 1.0,
            height: 1.0,
        },
        ObstacleShape::Box {
            center: [0.0; 3],
            half_extents: [1.0; 3],
        },
        ObstacleShape::Mesh {
            file: String::new(),
            scale: 1.0,
            translation: [0.0; 3],
        },
    ]
}

/// The first `[[obstacles]]` table of the serialized scene `scene` that does not deserialize,
/// explained key by key; `None` when every obstacle reads (the error is elsewhere).
pub(super) fn obstacle_error(scene: &toml::Table, c: &Checker) -> Option<SceneError> {
    let list = scene.get("obstacles")?.as_array()?;
    for (i, o) in list.iter().enumerate() {
        let Some(table) = o.as_table() else {
            return Some(c.fail(&format!("obstacles.{i}"), o, "expected a table"));
        };
        if let Err(e) = ObstacleSpec::deserialize(o.clone()) {
            return Some(explain(i, table, &e, c));
        }
    }
    None
}

/// Why obstacle `i` (`table`) failed with `error`: an unknown kind, an unknown key or a key of
/// the wrong type (each on its own line), else the parser's message on the `kind` line.
fn explain(i: usize, table: &toml::Table, error: &toml::de::Error, c: &Checker) -> SceneError {
    let key = |k: &str| format!("obstacles.{i}.{k}");
    let valid: Vec<toml::Table> = templates()
        .into_iter()
        .filter_map(|shape| {
            toml::Table::try_from(ObstacleSpec {
                shape,
                friction: 0.0,
                restitution: 0.0,
            })
            .ok()
        })
        .collect();
    let kind = table.get("kind");
    let Some(template) = valid
        .iter()
        .find(|t| kind.is_some_and(|k| t.get("kind") == Some(k)))
    else {
        let kinds: Vec<String> = valid
            .iter()
            .filter_map(|t| t.get("kind").map(|k| k.to_string()))
            .collect();
        let value = kind.map_or("(missing)".to_string(), |k| k.to_string());
        return c.fail(
            &key("kind"),
            value,
            &format!("expected one of: {}", kinds.join(", ")),
        );
    };
    for (k, v) in table {
        if !template.contains_key(k) {
            let keys: Vec<&str> = template.keys().map(String::as_str).collect();
            return c.fail(
                &key(k),
                v,
                &format!("no such key for this kind; valid keys: {}", keys.join(", ")),
            );
        }
        let mut probe = template.clone();
        probe.insert(k.clone(), v.clone());
        if let Err(e) = ObstacleSpec::deserialize(toml::Value::Table(probe)) {
            return c.fail(&key(k), v, e.message().trim());
        }
    }
    let kind = kind.map_or(String::new(), |k| k.to_string());
    c.fail(&key("kind"), kind, error.message().trim())
}
