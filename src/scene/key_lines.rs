//! Where a scene key's value came from, for error messages: the setting that set it, or the
//! scene file and the key's line.

use crate::console::clip;

/// Where `key`'s value came from and what it is: the setting that set it (its place names the key
/// and the value: `--set key=value`); for a list element `key[i]` or a key `key.sub` set as a
/// whole, that setting then `key[i] = value`; else the file, the key's line and `key = value`;
/// both clipped ([`clip`]).
pub(super) fn subject(
    text: &str,
    source: &str,
    options: &[(String, String)],
    key: &str,
    value: &str,
) -> String {
    // Set whole: `key` is `k[i]` or `k.sub`.
    let within = |k: &str| {
        key.strip_prefix(k)
            .is_some_and(|r| r.starts_with(['[', '.']))
    };
    let value = clip(value);
    match options.iter().rev().find(|(k, _)| k == key || within(k)) {
        Some((k, place)) if k == key => clip(place).into_owned(),
        Some((_, place)) => format!("{}: {key} = {value}", clip(place)),
        None => {
            let line = find_line(text, key)
                .map(|l| format!(":{l}"))
                .unwrap_or_default();
            format!("{source}{line}: {key} = {value}")
        }
    }
}

/// The 1-based line of `key` in the scene text: `section.key` under `[section]`, `obstacles.N.key`
/// under the N-th `[[obstacles]]`, `obstacles.N.sub.key` under the `[obstacles.sub]` that follows
/// it, `section.key[..]` for list elements. `None` when the key is not written in the file (a
/// default, or set by `--set`).
pub(super) fn find_line(text: &str, key: &str) -> Option<usize> {
    let key = key.split('[').next()?;
    let parts: Vec<&str> = key.split('.').collect();
    let (section, index, name) = match parts.as_slice() {
        [name] => (String::new(), None, *name),
        [section, name] => (section.to_string(), None, *name),
        [section, index, name] => (section.to_string(), index.parse::<usize>().ok(), *name),
        [section, index, sub, name] => (
            format!("{section}.{sub}"),
            index.parse::<usize>().ok(),
            *name,
        ),
        _ => return None,
    };
    let array = parts[0];
    let mut current = String::new();
    let mut seen_array = 0usize;
    let mut current_index = None;
    for (n, line) in text.lines().enumerate() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
            current = h.trim().to_string();
            current_index = None;
            if current == array {
                current_index = Some(seen_array);
                seen_array += 1;
            }
            continue;
        }
        if let Some(h) = l.strip_prefix('[').and_then(|r| r.split(']').next()) {
            current = h.trim().to_string();
            // A sub-table of the array belongs to its last element so far, wherever it stands
            // (an `[obstacles.motion]` after `[adaptivity]` is still the last obstacle's).
            current_index = match current.starts_with(&format!("{array}.")) {
                true => seen_array.checked_sub(1),
                false => None,
            };
            continue;
        }
        let Some((k, _)) = l.split_once('=') else {
            continue;
        };
        if current == section && k.trim() == name && (index.is_none() || index == current_index) {
            return Some(n + 1);
        }
    }
    None
}
