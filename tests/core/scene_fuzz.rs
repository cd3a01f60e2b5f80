//! Fuzzing the scene loader (issue 15): generated TOML scenes and `--set` values (keys from the
//! real key set, values of wrong types, extreme and non-finite numbers, huge integers, random
//! strings) either load as a valid scene or fail with a message; never a panic, never a long
//! wait. A scene that loads and has a small cloth also builds its cloth (no simulation).
use adaptcloth::scene::{self, ClothShape, LoadedScene};
use adaptcloth::sim::build_cloth;
use proptest::prelude::*;
use std::path::Path;
use std::time::{Duration, Instant};

/// Every key path of the sphere scene (which has obstacles and tracked points), as `--set`
/// writes them (`cloth.size`, `obstacles.0.radius`), with its value, from its serialized form.
fn real_keys() -> Vec<(String, toml::Value)> {
    let loaded = scene::load_embedded("sphere", &[]).unwrap().unwrap();
    let table = toml::Table::try_from(&loaded.scene).unwrap();
    let mut keys = Vec::new();
    collect_keys("", &toml::Value::Table(table), &mut keys);
    keys
}

/// A value of the same TOML type as `like`, picked by `r` among ordinary, extreme and
/// non-finite ones: it passes the parser and exercises validation and building.
fn same_type(like: &toml::Value, r: u64) -> String {
    const FLOATS: [&str; 13] = [
        "0.0", "-1.0", "0.5", "3.0", "1e9", "1e308", "-1e308", "5e-324", "1e-300", "nan", "inf",
        "-inf", "2e-3",
    ];
    const INTS: [&str; 11] = [
        "0",
        "1",
        "2",
        "3",
        "5",
        "9",
        "17",
        "40",
        "100000",
        "4294967296",
        "9223372036854775807",
    ];
    const STRINGS: [&str; 6] = [
        "\"\"",
        "\"x\"",
        "\"sphere\"",
        "\"remesh\"",
        "\"..\"",
        "\"/\"",
    ];
    let pick = |list: &[&str]| list[(r % list.len() as u64) as usize].to_string();
    match like {
        toml::Value::Float(_) => pick(&FLOATS),
        toml::Value::Integer(_) => pick(&INTS),
        toml::Value::Boolean(_) => pick(&["true", "false"]),
        toml::Value::String(_) => pick(&STRINGS),
        toml::Value::Array(a) => {
            let items: Vec<String> = (0..a.len().max(1 + (r % 3) as usize))
                .map(|k| {
                    let like = a.get(k).or(a.first()).unwrap_or(&toml::Value::Float(0.0));
                    same_type(like, r.rotate_right(5 * (k as u32 + 1)))
                })
                .collect();
            format!("[{}]", items.join(", "))
        }
        _ => pick(&INTS),
    }
}

fn collect_keys(prefix: &str, value: &toml::Value, out: &mut Vec<(String, toml::Value)>) {
    let join = |k: &str| {
        if prefix.is_empty() {
            k.to_string()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match value {
        toml::Value::Table(t) => {
            for (k, v) in t {
                collect_keys(&join(k), v, out);
            }
        }
        toml::Value::Array(a) if a.iter().all(toml::Value::is_table) && !a.is_empty() => {
            for (i, v) in a.iter().enumerate() {
                collect_keys(&join(&i.to_string()), v, out);
            }
        }
        _ => out.push((prefix.to_string(), value.clone())),
    }
}

/// A value as `--set` takes it (TOML syntax, or a bare string).
fn value() -> impl Strategy<Value = String> {
    let number = prop_oneof![
        Just("0".to_string()),
        Just("-0.0".to_string()),
        Just("1e308".to_string()),
        Just("-1e308".to_string()),
        Just("5e-324".to_string()),
        Just("1e-300".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("9223372036854775807".to_string()),
        Just("-9223372036854775808".to_string()),
        Just("99999999999999999999999".to_string()),
        Just("4294967296".to_string()),
        (-1e3f64..1e3).prop_map(|x| format!("{x:e}")),
        (-100i64..100_000).prop_map(|x| x.to_string()),
    ];
    let word = prop_oneof![
        Just("\"sphere\"".to_string()),
        Just("\"mesh\"".to_string()),
        Just("\"remesh\"".to_string()),
        Just("\"disk\"".to_string()),
        Just("\"obj\"".to_string()),
        Just("\"fixed\"".to_string()),
        Just("true".to_string()),
        Just("{ a = 1 }".to_string()),
        "[ -~]{0,12}".prop_map(|s| s.to_string()),
        "[ -~]{0,12}".prop_map(|s| format!("{s:?}")),
    ];
    prop_oneof![
        3 => number.clone(),
        2 => word,
        2 => prop::collection::vec(number, 0..5).prop_map(|v| format!("[{}]", v.join(", "))),
    ]
}

/// Loads `text` with `overrides`; when it loads and the cloth is small, builds the cloth. Fails
/// on a panic (proptest reports it) or a slow load.
fn check(text: &str, overrides: &[String]) -> Result<(), TestCaseError> {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let start = Instant::now();
    let result = scene::from_text(text, "fuzz.toml", "fuzz", base, overrides);
    let took = start.elapsed();
    prop_assert!(took < Duration::from_secs(2), "load took {took:?}");
    match result {
        Ok(loaded) => {
            if small(&loaded) {
                // Building may refuse the scene (a point off the cloth), never panic.
                let _ = build_cloth(&loaded);
            }
        }
        Err(e) => prop_assert!(!e.to_string().is_empty()),
    }
    Ok(())
}

/// True when the scene's cloth has at most a few thousand vertices (cheap to build).
fn small(loaded: &LoadedScene) -> bool {
    let c = &loaded.scene.cloth;
    match c.shape {
        ClothShape::Grid => {
            c.resolution
                .saturating_mul(c.resolution_v.max(c.resolution))
                <= 4096
        }
        ClothShape::Disk => c.resolution <= 30,
        ClothShape::Obj => false,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// `--set` overrides of real keys (and a few unknown ones) on a scene file.
    #[test]
    fn set_overrides_load_or_fail_cleanly(
        picks in prop::collection::vec(
            (any::<prop::sample::Index>(), value(), 0u8..10, any::<u64>()),
            1..5,
        )
    ) {
        let keys = real_keys();
        let sphere = scene::EMBEDDED_SCENES.iter().find(|(n, _)| *n == "sphere").unwrap().1;
        let overrides: Vec<String> = picks
            .iter()
            .map(|(i, v, how, r)| {
                let (key, like) = i.get(&keys);
                match how {
                    0 => format!("cloth.no_such={v}"),
                    1..=3 => format!("{key}={v}"),
                    _ => format!("{key}={}", same_type(like, *r)),
                }
            })
            .collect();
        check(sphere, &overrides)?;
    }

    /// Generated scene files: real sections and keys (obstacles and tracked points included)
    /// with generated values.
    #[test]
    fn generated_scene_files_load_or_fail_cleanly(
        picks in prop::collection::vec(
            (any::<prop::sample::Index>(), value(), any::<bool>(), any::<u64>()),
            1..8,
        ),
        obstacle in prop::option::of((
            prop::sample::select(vec!["ground", "sphere", "cylinder", "box", "mesh", "blob"]),
            prop::collection::vec(
                (prop::sample::select(vec![
                    "center", "radius", "height", "half_extents", "file", "scale", "translation",
                    "friction", "restitution", "nokey",
                ]), value()),
                0..4,
            ),
        )),
    ) {
        let keys: Vec<(String, toml::Value)> = real_keys()
            .into_iter()
            .filter(|(k, _)| k.split('.').count() == 2)
            .collect();
        let mut sections: std::collections::BTreeMap<String, Vec<String>> = Default::default();
        for (i, v, typed, r) in &picks {
            let (path, like) = i.get(&keys);
            let (section, key) = path.split_once('.').unwrap();
            let v = if *typed { same_type(like, *r) } else { v.clone() };
            sections.entry(section.to_string()).or_default().push(format!("{key} = {v}"));
        }
        let mut text = String::new();
        for (section, lines) in &sections {
            text.push_str(&format!("[{section}]\n{}\n", lines.join("\n")));
        }
        if let Some((kind, entries)) = &obstacle {
            text.push_str(&format!("[[obstacles]]\nkind = \"{kind}\"\n"));
            for (k, v) in entries {
                text.push_str(&format!("{k} = {v}\n"));
            }
        }
        check(&text, &[])?;
    }
}
