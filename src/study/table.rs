//! The comparison table: one [`Row`] per run with named columns declared once ([`COLUMNS`] and the
//! struct come from the same list, so writing and reading cannot disagree), `comparison.csv`
//! (columns read by name), and `comparison.json` (the [`Manifest`]: everything but the rows).

use super::shard::Shard;
use super::StudyError;
use crate::eval::reference::Floor;
use crate::scene::{CollisionSpec, ObstacleSpec};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// How a column is written in `comparison.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// As is (text and integers).
    Plain,
    /// Fixed point with this many decimals.
    Fixed(usize),
    /// Scientific notation with this many decimals.
    Sci(usize),
}

/// A value of one cell.
trait Cell: Sized {
    fn write(&self, format: Format) -> String;
    fn read(text: &str) -> Result<Self, String>;
}

impl Cell for String {
    fn write(&self, _: Format) -> String {
        self.clone()
    }
    fn read(text: &str) -> Result<Self, String> {
        Ok(text.to_string())
    }
}

/// A number not measured (NaN: a `hausdorff` of a run that stopped early, a column an older
/// table lacks) is an empty cell, the usual CSV form of a missing value; `NaN` is read as well
/// (tables written before).
impl Cell for f64 {
    fn write(&self, format: Format) -> String {
        match format {
            _ if self.is_nan() => String::new(),
            Format::Plain => format!("{self}"),
            Format::Fixed(d) => format!("{self:.d$}"),
            Format::Sci(d) => format!("{self:.d$e}"),
        }
    }
    fn read(text: &str) -> Result<Self, String> {
        if text.is_empty() {
            return Ok(f64::NAN);
        }
        text.parse()
            .map_err(|_| format!("`{text}` is not a number"))
    }
}

macro_rules! integer_cell {
    ($($t:ty),*) => {$(
        impl Cell for $t {
            fn write(&self, _: Format) -> String {
                self.to_string()
            }
            fn read(text: &str) -> Result<Self, String> {
                text.parse().map_err(|_| format!("`{text}` is not a whole number"))
            }
        }
    )*};
}
integer_cell!(u64, usize);

/// Declares [`Row`] and [`COLUMNS`] from one list: `field: type => format`, in column order.
macro_rules! comparison_row {
    ($($(#[doc = $doc:literal])* $field:ident: $ty:ty => $format:expr,)*) => {
        /// One row of `comparison.csv`: one run of a study.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        pub struct Row {
            $($(#[doc = $doc])* pub $field: $ty,)*
        }

        /// The columns of `comparison.csv` in order: name and how it is written.
        pub const COLUMNS: &[(&str, Format)] = &[$((stringify!($field), $format),)*];

        impl Row {
            /// The row's cells, in [`COLUMNS`] order.
            fn cells(&self) -> Vec<String> {
                vec![$(Cell::write(&self.$field, $format),)*]
            }

            /// A row from its cells looked up by column name.
            fn from_cells<'a>(
                cell: impl Fn(&str) -> Result<&'a str, String>,
            ) -> Result<Row, String> {
                Ok(Row {
                    $($field: Cell::read(cell(stringify!($field))?)
                        .map_err(|e| format!("{}: {e}", stringify!($field)))?,)*
                })
            }
        }
    };
}

comparison_row! {
    /// Scene name.
    scene: String => Format::Plain,
    /// Strategy.
    strategy: String => Format::Plain,
    /// Integrator.
    integrator: String => Format::Plain,
    /// Configuration label (also the run's folder name).
    label: String => Format::Plain,
    /// The curve the run belongs to: its strategy, or its study run's `label`.
    series: String => Format::Plain,
    /// Wall time of the run (s), recording included.
    wall_s: f64 => Format::Fixed(4),
    /// Steps taken.
    steps: u64 => Format::Plain,
    /// Time-weighted mean live vertex count.
    mean_vertices: f64 => Format::Fixed(2),
    /// Largest live vertex count.
    max_vertices: usize => Format::Plain,
    /// RMS over frames of `e(t)` (m).
    e_rms: f64 => Format::Sci(6),
    /// `e` at the last frame (m).
    e_final: f64 => Format::Sci(6),
    /// Tracked-point trajectory error (m).
    tracked_err: f64 => Format::Sci(6),
    /// Hausdorff distance between the final surfaces (m).
    hausdorff: f64 => Format::Sci(6),
    /// Largest depth of a vertex inside an obstacle (m).
    max_penetration: f64 => Format::Sci(6),
    /// Largest depth of an obstacle through the cloth surface, faces included (m).
    max_surface_penetration: f64 => Format::Sci(6),
    /// Largest count of the cloth's crossings with itself over the metrics rows; NaN when not
    /// measured (a table written before the measure existed).
    max_self_intersections: f64 => Format::Plain,
    /// `completed`, `diverged`, `interrupted`, `failed`, or `error` (could not start).
    status: String => Format::Plain,
    /// Starting grid (vertices per side).
    resolution: usize => Format::Plain,
    /// Simulated time reached (s).
    sim_time: f64 => Format::Fixed(6),
    /// Adaptation operations.
    adapt_events: u64 => Format::Plain,
    /// Largest momentum change of one adaptation event (kg m/s).
    max_momentum_jump: f64 => Format::Sci(6),
    /// Largest absolute kinetic-energy change of one step's adaptation (J).
    max_energy_jump: f64 => Format::Sci(6),
    /// Sum of adaptation kinetic-energy changes (J).
    total_energy_jump: f64 => Format::Sci(6),
    /// Wall time integrating (s).
    integrate_s: f64 => Format::Fixed(4),
    /// Wall time in collisions (s).
    collide_s: f64 => Format::Fixed(4),
    /// Wall time adapting (s).
    adapt_s: f64 => Format::Fixed(4),
    /// Wall time rebuilding elements (s).
    rebuild_s: f64 => Format::Fixed(4),
    /// Wall time recording outputs (s).
    record_s: f64 => Format::Fixed(4),
}

impl Row {
    /// True when the run completed (only those enter the Pareto front and the speed-ups).
    pub fn completed(&self) -> bool {
        self.status == "completed"
    }
}

/// Columns added after tables were first written: an older table without one reads it as an
/// empty cell, NaN (not measured).
const LATER_COLUMNS: &[&str] = &["max_self_intersections"];

/// The column names of `comparison.csv`, in order.
pub fn column_names() -> impl Iterator<Item = &'static str> {
    COLUMNS.iter().map(|(name, _)| *name)
}

/// Writes `comparison.csv`.
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<(), StudyError> {
    let mut s = column_names().collect::<Vec<_>>().join(",");
    s.push('\n');
    for r in rows {
        s.push_str(&r.cells().join(","));
        s.push('\n');
    }
    crate::io::write_atomic(path, s.as_bytes()).map_err(super::io_err(path))
}

/// Reads `comparison.csv`; columns are found by name, so their order in the file is free. A
/// file that is missing, unreadable or malformed is bad input ([`StudyError::Config`]).
pub fn read_csv(path: &Path) -> Result<Vec<Row>, StudyError> {
    let bad = |why: String| StudyError::Config(format!("{}: {why}", path.display()));
    let text = crate::io::read_text(path).map_err(|e| {
        bad(format!(
            "cannot be read: {e}; expected the comparison table written beside comparison.json"
        ))
    })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| bad("empty".into()))?
        .split(',')
        .collect();
    for name in column_names() {
        if !header.contains(&name) && !LATER_COLUMNS.contains(&name) {
            return Err(bad(format!("no column {name}")));
        }
    }
    let mut rows = Vec::new();
    for (n, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cells: Vec<&str> = line.split(',').collect();
        let cell = |name: &str| match header.iter().position(|h| *h == name) {
            None if LATER_COLUMNS.contains(&name) => Ok(""),
            position => position
                .and_then(|k| cells.get(k).copied())
                .ok_or_else(|| "short row".to_string()),
        };
        let row = Row::from_cells(cell).map_err(|e| bad(format!("line {}: {e}", n + 2)))?;
        // The label names the run's folder, which merge and report read and write.
        if crate::io::folder_label(&row.label) != row.label {
            return Err(bad(format!(
                "line {}: label `{}` is not a plain folder name",
                n + 2,
                row.label
            )));
        }
        rows.push(row);
    }
    Ok(rows)
}

/// A configuration left out of a comparison, and why (e.g. no shard ran it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    /// Its label.
    pub label: String,
    /// Why.
    pub reason: String,
}

/// What the comparison measured against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReferenceInfo {
    /// Reference grid.
    pub resolution: usize,
    /// Its step factor.
    pub beta: f64,
    /// Its integrator.
    pub integrator: String,
    /// Its step until the first contact (s; 0 = dynamic from the start; `None`: the scene's).
    #[serde(default)]
    pub dt_initial: Option<f64>,
    /// Its fixed step (s), if it used one instead of the dynamic step.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Cache key.
    pub key: String,
    /// Its steps.
    pub steps: u64,
    /// Its wall time (s).
    pub wall_s: f64,
    /// Sample grid (per side).
    pub samples: usize,
    /// The floor.
    pub floor: Floor,
    /// The cache entry folder.
    pub dir: PathBuf,
    /// The reference's first tracked point: `[t, x, y, z]` per frame (s, m).
    pub tracked: Vec<[f64; 4]>,
}

/// `comparison.json`: everything about a comparison but the rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Scene name.
    pub scene: String,
    /// Scene file or `<embedded NAME>`.
    pub source: String,
    /// Folder of the scene's relative files.
    pub base_dir: PathBuf,
    /// Simulated duration (s).
    pub duration: f64,
    /// The scene's step factor (runs use it).
    pub beta: f64,
    /// Every configuration of the sweep (all shards), by label, in order.
    pub configs: Vec<String>,
    /// Each configuration's settings fingerprint, in `configs`' order
    /// ([`super::config::fingerprint`]): `merge` refuses shards whose runs of one label differ.
    /// Empty in a comparison written before they were kept.
    #[serde(default)]
    pub settings: Vec<String>,
    /// The command that ran this comparison's runs (a merge keeps its first shard's), and the
    /// program's version: how to make it again. Empty in a comparison written before they were
    /// kept.
    #[serde(default)]
    pub command: String,
    /// The version of the program that ran the runs (`CARGO_PKG_VERSION`).
    #[serde(default)]
    pub version: String,
    /// Configurations left out (by a merge: no shard ran them).
    pub skipped: Vec<Skipped>,
    /// The shard this folder holds (`None`: all, or merged).
    pub shard: Option<Shard>,
    /// Parallel jobs used.
    pub jobs: usize,
    /// The reference.
    pub reference: ReferenceInfo,
    /// The scene's obstacles (for rendering).
    pub obstacles: Vec<ObstacleSpec>,
    /// The scene's `[collision]` (its runs and reference share it); none in a comparison written
    /// before it was kept.
    #[serde(default)]
    pub collision: Option<CollisionSpec>,
}

/// A comparison: its manifest and its rows (in configuration order).
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The manifest.
    pub manifest: Manifest,
    /// One row per run.
    pub rows: Vec<Row>,
}

/// Writes `comparison.csv` and `comparison.json` into `out`.
pub fn write_tables(out: &Path, c: &Comparison) -> Result<(), StudyError> {
    write_csv(&out.join("comparison.csv"), &c.rows)?;
    let path = out.join("comparison.json");
    let json = serde_json::to_string_pretty(&c.manifest)
        .map_err(|e| super::io_err(&path)(std::io::Error::other(e)))?;
    crate::io::write_atomic(&path, json.as_bytes()).map_err(super::io_err(&path))
}

/// Writes `c`'s tables into `out` ([`write_tables`]) and returns the comparison read back from
/// them, its numbers rounded as written: pages made from it are the ones `adaptcloth report`
/// makes from the folder later.
pub fn as_written(out: &Path, c: &Comparison) -> Result<Comparison, StudyError> {
    write_tables(out, c)?;
    read_comparison(out)
}

/// Reads a comparison folder (`comparison.json` and `comparison.csv`); a path that is not a
/// folder holding both, readable and well formed, is bad input ([`StudyError::Config`]), not a
/// failed read. The messages name the file, not the command.
pub fn read_comparison(dir: &Path) -> Result<Comparison, StudyError> {
    let path = dir.join("comparison.json");
    if !path.is_file() {
        let what = if dir.is_dir() {
            "a folder without comparison.json"
        } else if dir.exists() {
            "not a folder"
        } else {
            "no such folder"
        };
        return Err(StudyError::Config(format!(
            "{}: {what}: expected a comparison folder written by `study` or `compare` (one per \
             scene, e.g. out/study-quick/sphere)",
            dir.display()
        )));
    }
    let bad = |why: String| StudyError::Config(format!("{}: {why}", path.display()));
    let text = crate::io::read_text(&path).map_err(|e| bad(format!("cannot be read: {e}")))?;
    let manifest: Manifest = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    // The scene names the folder of its plots under `--write-docs DIR/results/`.
    if crate::io::folder_label(&manifest.scene) != manifest.scene {
        return Err(bad(format!(
            "scene `{}` is not a plain folder name",
            manifest.scene
        )));
    }
    let rows = read_csv(&dir.join("comparison.csv"))?;
    Ok(Comparison { manifest, rows })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A completed row with every column set.
    pub(crate) fn row(label: &str) -> Row {
        Row {
            scene: "sphere".into(),
            strategy: "static".into(),
            integrator: "rk4".into(),
            label: label.into(),
            series: "static".into(),
            wall_s: 1.25,
            steps: 100,
            mean_vertices: 25.0,
            max_vertices: 25,
            e_rms: 0.0125,
            e_final: 0.02,
            tracked_err: f64::NAN,
            hausdorff: 0.03,
            max_penetration: 0.0,
            max_surface_penetration: 0.0,
            max_self_intersections: 0.0,
            status: "completed".into(),
            resolution: 5,
            sim_time: 0.6,
            adapt_events: 0,
            max_momentum_jump: 0.0,
            max_energy_jump: 0.0,
            total_energy_jump: 0.0,
            integrate_s: 1.0,
            collide_s: 0.1,
            adapt_s: 0.0,
            rebuild_s: 0.0,
            record_s: 0.15,
        }
    }

    /// A manifest with a tiny floor.
    pub(crate) fn manifest() -> Manifest {
        Manifest {
            scene: "sphere".into(),
            source: "<embedded sphere>".into(),
            base_dir: PathBuf::new(),
            duration: 0.6,
            beta: 1e-3,
            configs: Vec::new(),
            settings: Vec::new(),
            command: String::new(),
            version: String::new(),
            skipped: Vec::new(),
            shard: None,
            jobs: 1,
            collision: None,
            reference: ReferenceInfo {
                resolution: 65,
                beta: 0.01,
                integrator: "rk4".into(),
                dt_initial: Some(0.0),
                dt: None,
                key: "k".into(),
                steps: 1,
                wall_s: 1.0,
                samples: 64,
                floor: Floor {
                    resolution: 33,
                    e_rms: 1e-4,
                    e_final: 1e-4,
                    tracked_err: 1e-4,
                    hausdorff: 1e-4,
                    wall_s: 1.0,
                    steps: 1,
                },
                dir: PathBuf::new(),
                tracked: Vec::new(),
            },
            obstacles: Vec::new(),
        }
    }

    #[test]
    fn csv_round_trip_by_column_name() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.csv");
        let (a, b) = (row("static-5-rk4"), row("static-9-rk4"));
        write_csv(&p, &[a.clone(), b]).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert_eq!(
            text.lines().next().unwrap(),
            column_names().collect::<Vec<_>>().join(",")
        );
        let back = read_csv(&p).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[0].label, a.label);
        assert_eq!(back[0].e_rms, a.e_rms);
        assert!(back[0].tracked_err.is_nan());
        assert_eq!(back[0].steps, 100);
        // Columns are read by name: reversing their order reads the same rows.
        let reversed: String = text
            .lines()
            .map(|l| l.split(',').rev().collect::<Vec<_>>().join(",") + "\n")
            .collect();
        std::fs::write(&p, reversed).unwrap();
        assert_eq!(read_csv(&p).unwrap()[1].label, "static-9-rk4");
    }

    /// Regression (trial report C3): a `hausdorff` not measured (a run that stopped before the
    /// reference's end) was written `NaN`; it is an empty cell, read back as not measured, and
    /// a `NaN` cell of an older table still reads.
    #[test]
    fn a_value_not_measured_is_an_empty_cell() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.csv");
        let mut r = row("static-5-rk4");
        (r.tracked_err, r.hausdorff) = (0.01, f64::NAN);
        write_csv(&p, &[r]).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        let k = column_names().position(|c| c == "hausdorff").unwrap();
        let cells = |t: &str| -> Vec<String> {
            t.lines()
                .nth(1)
                .unwrap()
                .split(',')
                .map(String::from)
                .collect()
        };
        assert_eq!(cells(&text)[k], "");
        assert!(!text.contains("NaN"), "{text}");
        assert!(read_csv(&p).unwrap()[0].hausdorff.is_nan());
        let older = text.replace(",,", ",NaN,");
        std::fs::write(&p, &older).unwrap();
        assert_eq!(cells(&older)[k], "NaN");
        assert!(read_csv(&p).unwrap()[0].hausdorff.is_nan());
    }

    /// A table written before `max_self_intersections` existed reads it as not measured (NaN);
    /// a table with the column reads its value.
    #[test]
    fn an_older_table_without_the_self_intersections_reads_them_as_not_measured() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.csv");
        let mut r = row("static-5-rk4");
        r.max_self_intersections = 3.0;
        write_csv(&p, &[r]).unwrap();
        assert_eq!(read_csv(&p).unwrap()[0].max_self_intersections, 3.0);
        let text = std::fs::read_to_string(&p).unwrap();
        let k = column_names()
            .position(|c| c == "max_self_intersections")
            .unwrap();
        let older: String = text
            .lines()
            .map(|l| {
                let mut cells: Vec<&str> = l.split(',').collect();
                cells.remove(k);
                cells.join(",") + "\n"
            })
            .collect();
        std::fs::write(&p, older).unwrap();
        let back = read_csv(&p).unwrap();
        assert!(back[0].max_self_intersections.is_nan());
        assert_eq!(back[0].label, "static-5-rk4");
    }

    #[test]
    fn bad_cells_name_the_line_and_the_column() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.csv");
        write_csv(&p, &[row("a")]).unwrap();
        let text = std::fs::read_to_string(&p)
            .unwrap()
            .replace(",100,", ",many,");
        std::fs::write(&p, text).unwrap();
        let e = read_csv(&p).unwrap_err().to_string();
        assert!(e.contains("line 2: steps: `many`"), "{e}");
        std::fs::write(&p, "scene,label\nx,y\n").unwrap();
        assert!(read_csv(&p).unwrap_err().to_string().contains("no column"));
    }

    /// A label read back names a folder that merge copies into and report reads: one that leaves
    /// `runs/` is refused (the hostile sweep: a comparison table written by hand).
    #[test]
    fn a_label_that_leaves_the_runs_folder_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.csv");
        for label in ["../../escaped", "/tmp/x", ".."] {
            write_csv(&p, &[row("a"), row(label)]).unwrap();
            let e = read_csv(&p).unwrap_err().to_string();
            assert!(
                e.contains("line 3: label") && e.contains("not a plain folder name"),
                "{e}"
            );
        }
        write_csv(&p, &[row("bisect48-5-rk4-criteria=\"sizing\"")]).unwrap();
        assert_eq!(read_csv(&p).unwrap().len(), 1);
    }

    /// A pipe in place of the table is refused, not read (it would wait for a writer for ever).
    #[test]
    fn a_pipe_in_place_of_the_table_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("comparison.csv");
        let made = std::process::Command::new("mkfifo").arg(&p).status();
        if made.is_ok_and(|s| s.success()) {
            let q = p.clone();
            let e = crate::testing::error_within_seconds(
                move || read_csv(&q).map(|_| ()),
                || drop(std::fs::write(&p, "")),
            );
            assert!(e.contains("not a regular file"), "{e}");
        }
    }
}
