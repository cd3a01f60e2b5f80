//! Refusing a list where the scene expects a section (a table of keys).
//!
//! serde reads a list into a section field by field, in the order the fields are declared
//! (`material = [1, 2]` would set `rho` and `T`, `cloth = []` leave every default), which gets
//! round the named keys every other check relies on. Every table of the scene as read (the
//! [`Scene`] serialized back: the sections, their sub-tables, each `[[obstacles]]` and
//! `[[tracked]]` entry) must have been given as a table.

use super::validate::Checker;
use super::{Scene, SceneError};
use toml::Value;

/// Fails for the first key of `given` (the scene as written, or after settings) that holds a list
/// where `scene` (the scene read from it) has a table, naming the key (`material`,
/// `tracked.0`, `obstacles.1.motion`) and where it was given.
pub(super) fn check(given: &toml::Table, scene: &Scene, c: &Checker) -> Result<(), SceneError> {
    let Ok(read) = toml::Table::try_from(scene) else {
        return Ok(());
    };
    match in_table(given, &read, "") {
        Some((key, value)) => Err(c.fail(
            &key,
            value,
            "expected a section (a table of keys), not a list",
        )),
        None => Ok(()),
    }
}

/// The first key under `prefix` given as a list where `read` has a table, with its value.
fn in_table<'a>(
    given: &'a toml::Table,
    read: &toml::Table,
    prefix: &str,
) -> Option<(String, &'a Value)> {
    given.iter().find_map(|(k, g)| {
        let key = match prefix {
            "" => k.clone(),
            p => format!("{p}.{k}"),
        };
        in_value(g, read.get(k)?, key)
    })
}

/// [`in_table`] for one value `given` at `key`, read as `read`; list entries are `key.N`.
fn in_value<'a>(given: &'a Value, read: &Value, key: String) -> Option<(String, &'a Value)> {
    match (given, read) {
        (Value::Array(_), Value::Table(_)) => Some((key, given)),
        (Value::Table(g), Value::Table(r)) => in_table(g, r, &key),
        (Value::Array(g), Value::Array(r)) => g
            .iter()
            .zip(r)
            .enumerate()
            .find_map(|(i, (g, r))| in_value(g, r, format!("{key}.{i}"))),
        _ => None,
    }
}
