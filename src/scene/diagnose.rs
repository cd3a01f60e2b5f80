//! Naming the key of an `[[obstacles]]` table that does not parse.
//!
//! An obstacle's keys sit in a flattened, `kind`-tagged enum, so the TOML parser reports any
//! mistake in it (a wrong type, an unknown key, a missing field, an unknown kind) at the
//! `[[obstacles]]` header with no key name. This re-reads the obstacles one key at a time against
//! a valid obstacle of the same kind, so the error names the key, its own line (or the option
//! that set it) and what was expected; a mistake in its `[obstacles.motion]` table likewise.

use super::validate::Checker;
use super::{MotionSpec, ObstacleShape, ObstacleSpec, SceneError};
use serde::Deserialize;

/// A parser message with Rust's type names in plain words (`expected f64` becomes `expected a
/// number`), for people who write TOML, not Rust; each of its lines clipped as echoed text is
/// ([`crate::console::clip`]: a 100,000-character key made a 300 KB message).
pub fn plain_types(message: &str) -> String {
    let clipped: Vec<_> = message.lines().map(crate::console::clip).collect();
    plain_words(&clipped.join("\n"))
}

fn plain_words(message: &str) -> String {
    const PLAIN: [(&str, &str); 9] = [
        ("expected a sequence", "expected a list [...]"),
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
        ("expected usize", "expected a whole number, 0 or more"),
        ("expected u64", "expected a whole number, 0 or more"),
        (
            "expected u32",
            "expected a whole number from 0 to 4294967295",
        ),
        ("expected i64", "expected a whole number"),
        ("expected i32", "expected a whole number"),
        ("expected a boolean", "expected true or false"),
    ];
    let plain = PLAIN.iter().fold(message.to_string(), |m, (rust, plain)| {
        m.replace(rust, plain)
    });
    // `expected struct ClothSpec`: a section (a table of keys) was expected.
    match plain.find("expected struct ") {
        Some(at) => {
            let rest = &plain[at + "expected struct ".len()..];
            let name_end = rest
                .find(|c: char| !c.is_alphanumeric() && c != '_')
                .unwrap_or(rest.len());
            format!(
                "{}expected a section (a table of keys){}",
                &plain[..at],
                &rest[name_end..]
            )
        }
        None => plain,
    }
}

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

/// Why obstacle `i` (`table`) failed with `error`: its `[obstacles.motion]` table if that is
/// what fails ([`motion_error`]), else an unknown kind, an unknown key or a key of the wrong type
/// (each on its own line), else the parser's message on the `kind` line.
fn explain(i: usize, table: &toml::Table, error: &toml::de::Error, c: &Checker) -> SceneError {
    if let Some(e) = table.get("motion").and_then(|m| motion_error(i, m, c)) {
        return e;
    }
    let valid: Vec<toml::Table> = templates()
        .into_iter()
        .filter_map(|shape| {
            toml::Table::try_from(ObstacleSpec {
                shape,
                friction: 0.0,
                restitution: 0.0,
                motion: Some(MotionSpec::Linear { velocity: [0.0; 3] }),
            })
            .ok()
        })
        .collect();
    let parse = |t| ObstacleSpec::deserialize(t).map(drop);
    explain_table(&format!("obstacles.{i}"), table, &valid, parse, error, c)
}

/// Why the `motion` value of obstacle `i` does not read, as [`explain`] says it for an
/// obstacle; `None` when it reads.
fn motion_error(i: usize, motion: &toml::Value, c: &Checker) -> Option<SceneError> {
    let prefix = format!("obstacles.{i}.motion");
    let error = MotionSpec::deserialize(motion.clone()).err()?;
    let Some(table) = motion.as_table() else {
        return Some(c.fail(&prefix, motion, "expected a table"));
    };
    let valid: Vec<toml::Table> = [
        MotionSpec::Linear { velocity: [0.0; 3] },
        MotionSpec::Spin {
            axis_point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            angular_velocity: 0.0,
        },
        MotionSpec::Keyframes {
            times: vec![0.0],
            positions: vec![[0.0; 3]],
            rotations: vec![[0.0; 3]],
            pivot: [0.0, 0.0, 1.0],
        },
    ]
    .iter()
    .filter_map(|m| toml::Table::try_from(m).ok())
    .collect();
    let parse = |t| MotionSpec::deserialize(t).map(drop);
    Some(explain_table(&prefix, table, &valid, parse, &error, c))
}

/// Why `table` (the keys under `prefix`) failed with `error`, given a valid table of each kind
/// (`valid`, tagged by `kind`) and its parser: an unknown kind, an unknown key or a key of the
/// wrong type, else the parser's message on the `kind` line.
fn explain_table(
    prefix: &str,
    table: &toml::Table,
    valid: &[toml::Table],
    parse: impl Fn(toml::Value) -> Result<(), toml::de::Error>,
    error: &toml::de::Error,
    c: &Checker,
) -> SceneError {
    let key = |k: &str| format!("{prefix}.{k}");
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
        if let Err(e) = parse(toml::Value::Table(probe)) {
            return c.fail(&key(k), v, &plain_types(e.message().trim()));
        }
    }
    let kind = kind.map_or(String::new(), |k| k.to_string());
    c.fail(&key("kind"), kind, &plain_types(error.message().trim()))
}
