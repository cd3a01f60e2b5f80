//! Scenes: TOML files (serde) describing the cloth, material, forces, time stepping, integrator,
//! collision, obstacles, adaptivity and tracked points; `--set section.key=value` overrides; and
//! validation with errors that name the file, the line and what was expected.
//!
//! Loading is the first stage of a run: [`resolve`] (or [`load`]) → [`Scene`] → `sim`.
//! The scene depends on the core, never the reverse: `convert` turns its sections into the core's
//! own parameter types (`From<&MaterialSpec> for physics::Material`, ...,
//! [`ObstacleSpec::to_core`], [`LoadedScene::obstacles`]).

mod adaptivity;
mod convert;
mod diagnose;
mod key_lines;
mod motion;
mod sections;
mod spec;
mod validate;

pub use convert::mesh_path;
pub use diagnose::plain_types;
pub use spec::*;
pub(crate) use validate::not_a_file;
pub use validate::MAX_STEPS;

use crate::math::Real;
use std::path::{Path, PathBuf};

/// The three scenes of the source thesis (its Tests I-III), in the order studies list them.
pub const SOURCE_SCENES: [&str; 3] = ["sphere", "round_table", "bunny"];

/// The embedded scene run when no scene is named: the source's sphere test (Test III).
pub const DEFAULT_SCENE: &str = "sphere";

/// Most bytes of one folder name on common file systems (Linux's `NAME_MAX`): the longest output
/// folder name a scene's `name` may make ([`LoadedScene::check_folder_name`]).
pub const MAX_FOLDER_NAME: usize = 255;

/// Names of the scenes shipped in `scenes/` and embedded in the binary.
pub const EMBEDDED_SCENES: &[(&str, &str)] = &[
    ("sphere", include_str!("../../scenes/sphere.toml")),
    ("round_table", include_str!("../../scenes/round_table.toml")),
    ("bunny", include_str!("../../scenes/bunny.toml")),
    ("hanging", include_str!("../../scenes/hanging.toml")),
    ("sphere_peer", include_str!("../../scenes/sphere_peer.toml")),
    (
        "moving_sphere",
        include_str!("../../scenes/moving_sphere.toml"),
    ),
    ("turntable", include_str!("../../scenes/turntable.toml")),
];

/// A scene ready to run: the parsed, overridden and validated scene, where it came from, and the
/// folder its relative file names (meshes) are resolved against.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The scene.
    pub scene: Scene,
    /// The file it was read from, or `<embedded NAME>`.
    pub source: String,
    /// Folder for relative paths in the scene.
    pub base_dir: PathBuf,
    /// The scene's text (for the lines of keys in later messages).
    text: String,
    /// Keys set by overrides, with the place of the setting that set each.
    options: Vec<(String, String)>,
}

impl LoadedScene {
    /// Where `key` (holding `value`) came from and what it is, for messages about it: the setting
    /// that set it (`--set key=value`, `study.toml:12: runs[0].set."key" = value`), else
    /// `FILE:LINE: key = value` (the key's line in the scene file: `cloth.pinned[0]`,
    /// `tracked.0.rest`).
    pub fn subject(&self, key: &str, value: &str) -> String {
        key_lines::subject(&self.text, &self.source, &self.options, key, value)
    }

    /// Refuses `folder`, the name of an output folder made from the scene's `name`, when it is
    /// longer than a file system allows ([`MAX_FOLDER_NAME`] bytes), naming the `name` key (its
    /// line) rather than the folder; `remedy` ends the message (`; or give --out ...`).
    pub fn check_folder_name(&self, folder: &str, remedy: &str) -> Result<(), SceneError> {
        if folder.len() <= MAX_FOLDER_NAME {
            return Ok(());
        }
        Err(SceneError::Invalid {
            subject: self.subject("name", &self.scene.name),
            expected: format!(
                "too long for a folder name: the output folder {} is named after it, and a file \
                 system allows {MAX_FOLDER_NAME} bytes; shorten it{remedy}",
                crate::console::clip(folder),
            ),
        })
    }

    /// Checks what a scene must satisfy to be run, beyond [`validate`]'s ranges: the sizing
    /// criteria need a strategy that adapts the mesh. Called on a run's final scene (`run`, each
    /// run of a study); a study's base scene is a template whose strategy its runs replace.
    pub fn check_run(&self) -> Result<(), SceneError> {
        adaptivity::criteria_need_adaptivity(&self.checker(), &self.scene.adaptivity)
    }

    /// What a run on its own (`adaptcloth run`) should be told about its scene: `h_min` set for
    /// a strategy that never adapts ([`adaptivity::ignored_floor`]).
    pub fn run_alone_note(&self) -> Option<String> {
        adaptivity::ignored_floor(&self.scene.adaptivity)
    }

    /// Fails when `adaptivity.max_vertices` is below `start`, the vertex count of the cloth as
    /// built: for an OBJ cloth, whose count [`validate`] cannot know before the file is read.
    pub fn check_start_vertices(&self, start: usize) -> Result<(), SceneError> {
        let max = self.scene.adaptivity.max_vertices;
        adaptivity::room_for_cloth(&self.checker(), max, start)
    }

    fn checker(&self) -> validate::Checker<'_> {
        validate::Checker {
            text: &self.text,
            source: &self.source,
            options: &self.options,
        }
    }
}

/// Why a scene could not be loaded; every variant says where and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{path}: cannot read scene file: {source}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// TOML syntax error, unknown key, or wrong type (the message carries line and column).
    #[error("{path}: {message}")]
    Parse {
        /// The file (or `--set`).
        path: String,
        /// The parser's message, with line and column.
        message: String,
    },
    /// An override is not of the form `section.key=value`.
    #[error("{place}: expected section.key=value")]
    BadOverride {
        /// Where it was given ([`Setting::place`]).
        place: String,
    },
    /// An override's key names no scene parameter.
    #[error("{place}: no such scene key; valid keys here: {valid}")]
    UnknownKey {
        /// Where it was given ([`Setting::place`]).
        place: String,
        /// The valid keys at that level.
        valid: String,
    },
    /// A value out of its range.
    #[error("{subject}: {expected}")]
    Invalid {
        /// Where the value came from and what it is ([`LoadedScene::subject`]):
        /// `FILE:LINE: key = value`, or the setting that set it (`--set key=value`).
        subject: String,
        /// What was expected.
        expected: String,
    },
}

/// One `section.key=value` scene override and where it was given, which messages about its key
/// name instead of a line of the scene file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Setting {
    /// `section.key=value`, the value in TOML syntax (or a bare string).
    pub arg: String,
    /// Where it was given, with its key and value (`study.toml:12: runs[0].set."time.dt" =
    /// 0.1`); `None` for the command line (`--set ARG`).
    pub from: Option<String>,
}

impl Setting {
    /// `--set ARG` on the command line.
    pub fn option(arg: &str) -> Setting {
        Setting {
            arg: arg.to_string(),
            from: None,
        }
    }

    /// Given at `from` (a file, its line, the key and the value).
    pub fn at(arg: String, from: String) -> Setting {
        Setting {
            arg,
            from: Some(from),
        }
    }

    /// The key it sets (`section.key`, trimmed); `None` for an argument without `=`.
    pub fn key(&self) -> Option<&str> {
        self.arg.split_once('=').map(|(key, _)| key.trim())
    }

    /// Where it was given, naming the key and the value: `--set ARG` or [`Setting::from`].
    pub fn place(&self) -> String {
        self.from
            .clone()
            .unwrap_or_else(|| format!("--set {}", self.arg))
    }

    /// Command-line `--set` arguments as settings.
    pub fn options(args: &[String]) -> Vec<Setting> {
        args.iter().map(|a| Setting::option(a)).collect()
    }
}

/// Changes to a scene: `section.key=value` settings (`--set` or a study file's), then the typed
/// options (`--strategy`, `--integrator`, `--duration`), applied before validation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// `section.key=value` overrides, in order.
    pub set: Vec<Setting>,
    /// `[adaptivity] strategy`.
    pub strategy: Option<String>,
    /// `[integrator] name`.
    pub integrator: Option<String>,
    /// `[time] duration` (s).
    pub duration: Option<Real>,
}

impl Overrides {
    /// Only `--set` strings.
    pub fn set(set: &[String]) -> Overrides {
        Overrides {
            set: Setting::options(set),
            ..Overrides::default()
        }
    }

    /// Each key these overrides set, with the place of the setting or option that set it
    /// (`--set key=value`, a study file's line, `--strategy NAME`, ...), for error messages.
    fn options(&self) -> Vec<(String, String)> {
        let mut out = places(&self.set);
        let typed = [
            ("adaptivity.strategy", "--strategy", self.strategy.clone()),
            ("integrator.name", "--integrator", self.integrator.clone()),
            (
                "time.duration",
                "--duration",
                self.duration.map(|d| d.to_string()),
            ),
        ];
        for (key, option, value) in typed {
            if let Some(v) = value {
                out.push((key.to_string(), format!("{option} {v}")));
            }
        }
        out
    }

    /// The typed options applied to `scene`.
    fn apply_typed(&self, scene: &mut Scene) {
        if let Some(s) = &self.strategy {
            scene.adaptivity.strategy = s.clone();
        }
        if let Some(i) = &self.integrator {
            scene.integrator.name = i.clone();
        }
        if let Some(d) = self.duration {
            scene.time.duration = d;
        }
    }
}

/// The scene named on the command line: a TOML file if `name` is a path that exists (a file comes
/// first, even one named like an embedded scene: its read or parse error then says so; a folder
/// named like one does not hide it), else the embedded scene of that name, else (no name) the
/// default scene; with `overrides` applied and validated.
pub fn resolve(name: Option<&str>, overrides: &Overrides) -> Result<LoadedScene, SceneError> {
    let Some(name) = name else {
        return embedded_with(DEFAULT_SCENE, overrides).ok_or_else(|| not_found(DEFAULT_SCENE))?;
    };
    let path = Path::new(name);
    let embedded_folder = path.is_dir() && embedded_names().contains(&name);
    if path.exists() && !embedded_folder {
        return load_with(path, overrides).map_err(|e| shadowing(name, e));
    }
    embedded_with(name, overrides).ok_or_else(|| not_found(name))?
}

/// `e`, the error reading or parsing the file `name`, saying that the file hides the embedded
/// scene of the same name when there is one.
fn shadowing(name: &str, e: SceneError) -> SceneError {
    if !embedded_names().contains(&name) {
        return e;
    }
    let hint = format!(
        "(the file `{name}` here is read instead of the embedded scene `{name}`: a file comes \
         first; to run the embedded scene, rename or move the file, or run from another folder)"
    );
    match e {
        SceneError::Io { path, source } => SceneError::Io {
            path,
            source: std::io::Error::new(source.kind(), format!("{source} {hint}")),
        },
        SceneError::Parse { path, message } => SceneError::Parse {
            path,
            message: format!("{message} {hint}"),
        },
        e => e,
    }
}

/// The names of the embedded scenes, in [`EMBEDDED_SCENES`]' order.
pub fn embedded_names() -> Vec<&'static str> {
    EMBEDDED_SCENES.iter().map(|(n, _)| *n).collect()
}

fn not_found(name: &str) -> SceneError {
    SceneError::Io {
        path: name.to_string(),
        source: std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!(
                "no such file, and no embedded scene of that name (embedded: {})",
                embedded_names().join(", ")
            ),
        ),
    }
}

/// Reads, overrides (`--set`) and validates a scene file.
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    load_with(path, &Overrides::set(overrides))
}

/// Reads, overrides and validates a scene file.
pub fn load_with(path: &Path, overrides: &Overrides) -> Result<LoadedScene, SceneError> {
    let source = path.display().to_string();
    let text = crate::io::read_text(path).map_err(|e| SceneError::Io {
        path: source.clone(),
        source: e,
    })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let base_dir = path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    // An empty file is a mistake, not a request for the default scene.
    if toml::from_str::<toml::Table>(&text).is_ok_and(|t| t.is_empty()) {
        return Err(SceneError::Parse {
            path: source,
            message: "the scene file sets nothing (empty, or comments only); name an embedded \
                      scene instead (`adaptcloth scenes`) or give its sections"
                .into(),
        });
    }
    from_text_with(&text, &source, &stem, base_dir, overrides)
}

/// The top-level keys of a scene file that a study file never has: its sections.
const SCENE_SECTIONS: [&str; 9] = [
    "cloth",
    "material",
    "forces",
    "time",
    "integrator",
    "collision",
    "obstacles",
    "adaptivity",
    "tracked",
];

/// Whether a parsed TOML document looks like a scene file (a scene's section and no study key),
/// to point a user who gave one to `study` at `run`.
pub fn looks_like_scene(doc: &toml::Table) -> bool {
    has_scene_section(doc) && !crate::study::has_study_key(doc)
}

/// Whether a parsed TOML document has one of a scene file's sections.
pub fn has_scene_section(doc: &toml::Table) -> bool {
    SCENE_SECTIONS.iter().any(|k| doc.contains_key(*k))
}

/// Loads an embedded scene by name (see [`EMBEDDED_SCENES`]) with `--set` overrides; its relative
/// mesh paths name the meshes built into the binary (`<embedded>/meshes/bunny.obj`), else files of
/// the current folder ([`mesh_path`]).
pub fn load_embedded(name: &str, overrides: &[String]) -> Option<Result<LoadedScene, SceneError>> {
    embedded_with(name, &Overrides::set(overrides))
}

/// Loads an embedded scene by name with overrides.
fn embedded_with(name: &str, overrides: &Overrides) -> Option<Result<LoadedScene, SceneError>> {
    let (_, text) = EMBEDDED_SCENES.iter().find(|(n, _)| *n == name)?;
    let base_dir = PathBuf::from(crate::io::EMBEDDED_DIR);
    Some(from_text_with(
        text,
        &format!("<embedded {name}>"),
        name,
        base_dir,
        overrides,
    ))
}

/// Parses scene text, applies the `--set` overrides, and validates.
pub fn from_text(
    text: &str,
    source: &str,
    default_name: &str,
    base_dir: PathBuf,
    overrides: &[String],
) -> Result<LoadedScene, SceneError> {
    from_text_with(
        text,
        source,
        default_name,
        base_dir,
        &Overrides::set(overrides),
    )
}

/// Parses scene text, validates it as written, applies the overrides, and validates the result.
fn from_text_with(
    text: &str,
    source: &str,
    default_name: &str,
    base_dir: PathBuf,
    overrides: &Overrides,
) -> Result<LoadedScene, SceneError> {
    let options = overrides.options();
    let checker = validate::Checker {
        text,
        source,
        options: &options,
    };
    // First pass on the text itself, so unknown keys and wrong types are reported with their line;
    // an `[[obstacles]]` mistake by its key and line (the parser gives the header).
    let scene: Scene = toml::from_str(text).map_err(|e| {
        let table = toml::from_str::<toml::Table>(text).ok();
        let hint = match &table {
            Some(t) if crate::study::looks_like_study(t) => {
                "\nthis looks like a study file (it has `scenes` or [[runs]] and no scene \
                 section): run it with `adaptcloth study FILE`"
            }
            _ => "",
        };
        table
            .and_then(|t| diagnose::obstacle_error(&t, &checker))
            .unwrap_or_else(|| SceneError::Parse {
                path: source.to_string(),
                message: format!("{}{hint}", plain_types(e.to_string().trim_end())),
            })
    })?;
    if let Ok(given) = toml::from_str::<toml::Table>(text) {
        sections::check(&given, &scene, &checker)?;
    }
    // The file as written is valid on its own: a value an override replaces is checked too (a
    // `time.duration = nan` under `--duration 1` was never looked at), and named by its line.
    if *overrides != Overrides::default() {
        validate::validate(&scene, text, source, &base_dir, &[])?;
    }
    let mut scene = apply_settings(scene, &overrides.set, &checker)?;
    overrides.apply_typed(&mut scene);
    // The name names output folders: it must stay one safe file-name component.
    scene.name = crate::io::file_safe(&scene.name);
    if scene.name.is_empty() {
        scene.name = crate::io::file_safe(default_name);
    }
    validate::validate(&scene, text, source, &base_dir, &options)?;
    Ok(LoadedScene {
        scene,
        source: source.to_string(),
        base_dir,
        text: text.to_string(),
        options,
    })
}

/// `loaded` with more settings (a study run's own), validated again; errors name the setting
/// (its file and line) for its keys, the scene file's line for the others.
pub fn with_overrides(loaded: &LoadedScene, set: &[Setting]) -> Result<LoadedScene, SceneError> {
    let mut options = loaded.options.clone();
    options.extend(places(set));
    let checker = validate::Checker {
        text: &loaded.text,
        source: &loaded.source,
        options: &options,
    };
    let scene = apply_settings(loaded.scene.clone(), set, &checker)?;
    validate::validate(
        &scene,
        &loaded.text,
        &loaded.source,
        &loaded.base_dir,
        &options,
    )?;
    Ok(LoadedScene {
        scene,
        options,
        ..loaded.clone()
    })
}

/// Each setting's key with its place ([`Setting::place`]).
fn places(set: &[Setting]) -> Vec<(String, String)> {
    set.iter()
        .filter_map(|s| Some((s.key()?.to_string(), s.place())))
        .collect()
}

/// `scene` with `settings` applied in order. A value of the wrong type is blamed on the setting
/// that gave it (the first after which the scene no longer reads), an `[[obstacles]]` one on its
/// key.
fn apply_settings(
    scene: Scene,
    settings: &[Setting],
    checker: &validate::Checker,
) -> Result<Scene, SceneError> {
    if settings.is_empty() {
        return Ok(scene);
    }
    let mut table = toml::Table::try_from(&scene).map_err(|e| SceneError::Parse {
        path: checker.source.to_string(),
        message: e.to_string(),
    })?;
    for setting in settings {
        apply_override(&mut table, setting)?;
        match Scene::deserialize(toml::Value::Table(table.clone())) {
            Ok(scene) => sections::check(&table, &scene, checker)?,
            Err(e) => {
                return Err(
                    diagnose::obstacle_error(&table, checker).unwrap_or_else(|| {
                        SceneError::Parse {
                            path: setting.place(),
                            message: plain_types(&e.to_string().trim_end().replace('\n', " ")),
                        }
                    }),
                )
            }
        }
    }
    Scene::deserialize(toml::Value::Table(table)).map_err(|e| SceneError::Parse {
        path: checker.source.to_string(),
        message: plain_types(e.to_string().trim_end()),
    })
}

/// The scene after every override as TOML that loads back to the same scene from any folder
/// (relative mesh paths made absolute; a built-in mesh kept as `<embedded>/...`), headed by comments naming the binary's version, the
/// command that ran it and where the scene came from. Runs write it as `scene.resolved.toml`.
pub fn resolved_toml(loaded: &LoadedScene, command: &str) -> String {
    let mut scene = loaded.scene.clone();
    let absolute = |f: &str| {
        let p = mesh_path(&loaded.base_dir, f);
        match crate::io::is_embedded_path(&p) {
            true => p,
            false => std::path::absolute(&p).unwrap_or(p),
        }
        .display()
        .to_string()
    };
    if !scene.cloth.mesh.is_empty() {
        scene.cloth.mesh = absolute(&scene.cloth.mesh);
    }
    for o in &mut scene.obstacles {
        if let ObstacleShape::Mesh { file, .. } = &mut o.shape {
            *file = absolute(file);
        }
    }
    let body = toml::to_string(&scene).unwrap_or_else(|e| format!("# not serializable: {e}\n"));
    format!(
        "# The scene this run ran, after every override (adaptcloth {}).\n\
         # Command: {}\n\
         # Scene from: {}\n\
         # Run it alone again: adaptcloth run <this file>\n\n{body}",
        env!("CARGO_PKG_VERSION"),
        comment_safe(command),
        comment_safe(&loaded.source)
    )
}

/// `text` with its control characters escaped (`\n` as the two characters `\` `n`), so it stays
/// inside one TOML comment line: a newline in an argument made the rest of it a line of the
/// resolved scene.
fn comment_safe(text: &str) -> String {
    text.chars()
        .map(|c| match c.is_control() {
            true => c.escape_default().to_string(),
            false => c.to_string(),
        })
        .collect()
}

use serde::Deserialize;

/// Applies one `section.key=value` override to the serialized scene (which holds every key with
/// its default, so a key absent there does not exist). Array elements are addressed by index:
/// `obstacles.0.radius=0.3`. The value is parsed as TOML (number, boolean, array, quoted string)
/// or else taken as a bare string; an integer given for a float key becomes a float.
fn apply_override(table: &mut toml::Table, setting: &Setting) -> Result<(), SceneError> {
    let bad = || SceneError::BadOverride {
        place: setting.place(),
    };
    let (key, raw) = setting.arg.split_once('=').ok_or_else(bad)?;
    let key = key.trim();
    let parts: Vec<&str> = key.split('.').collect();
    if key.is_empty() || parts.iter().any(|p| p.is_empty()) {
        return Err(bad());
    }
    let value = parse_value(raw.trim());
    // A number beyond a double's range is not a string: TOML refuses it, so say why.
    if value.is_str() && raw.trim().parse::<f64>().is_ok_and(f64::is_infinite) {
        return Err(SceneError::Invalid {
            subject: setting.place(),
            expected: format!(
                "{} is beyond the range of a number here (at most about 1.8e308 in size)",
                raw.trim()
            ),
        });
    }
    let unknown = |valid: Vec<String>| SceneError::UnknownKey {
        place: setting.place(),
        valid: valid.join(", "),
    };
    let top_keys: Vec<String> = table.keys().cloned().collect();
    let mut node: &mut toml::Value = table.get_mut(parts[0]).ok_or_else(|| unknown(top_keys))?;
    for (depth, part) in parts.iter().enumerate().skip(1) {
        node = match node {
            toml::Value::Table(t) => {
                let valid: Vec<String> = t.keys().cloned().collect();
                t.get_mut(*part).ok_or_else(|| unknown(valid))?
            }
            toml::Value::Array(a) => {
                let indices = match a.len() {
                    0 => "none (the list is empty)".to_string(),
                    1 => "0 (the list has one entry)".to_string(),
                    n => format!("0 to {} (the list has {n} entries)", n - 1),
                };
                let index: usize = part.parse().map_err(|_| unknown(vec![indices.clone()]))?;
                a.get_mut(index).ok_or_else(|| unknown(vec![indices]))?
            }
            _ => {
                let value = parts[..depth].join(".");
                return Err(unknown(vec![format!(
                    "none ({value} is a value, not a section)"
                )]));
            }
        };
    }
    *node = match (&*node, value) {
        (toml::Value::Float(_), toml::Value::Integer(i)) => toml::Value::Float(i as f64),
        (_, v) => v,
    };
    Ok(())
}

/// Parses an override value as TOML, falling back to a bare string.
fn parse_value(raw: &str) -> toml::Value {
    let doc = format!("v = {raw}");
    toml::from_str::<toml::Table>(&doc)
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(raw.to_string()))
}

#[cfg(test)]
mod tests;
