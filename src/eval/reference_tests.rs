//! Tests of the reference cache: keys, the compact format, the floor.
use super::*;
use crate::scene::load_embedded;

fn sphere(overrides: &[&str]) -> LoadedScene {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    load_embedded("sphere", &o).unwrap().unwrap()
}

/// Integrator keys that came after cached references existed (issue 13) stay out of the key
/// at their defaults, so the `[integrator]` part is the one those references were keyed
/// with; a non-default value changes the key.
#[test]
fn later_integrator_keys_enter_the_cache_key_only_when_set() {
    let json = physics_json(&sphere(&[]).scene);
    let mut keys: Vec<&str> = json["integrator"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "cg_max_iterations",
            "cg_tolerance",
            "name",
            "relaxation_passes"
        ]
    );
    let settings = ReferenceSettings::default();
    let base = cache_key(&sphere(&[]), &settings);
    for o in [
        "integrator.on_unconverged=\"fail\"",
        "integrator.solver=\"cholesky\"",
        "integrator.solver=\"cg\"",
    ] {
        assert_ne!(base, cache_key(&sphere(&[o]), &settings), "{o}");
    }
}

#[test]
fn cache_key_changes_with_physics_only() {
    let settings = ReferenceSettings::default();
    let base = cache_key(&sphere(&[]), &settings);
    assert_eq!(base.len(), 16);
    assert_eq!(base, cache_key(&sphere(&[]), &settings), "deterministic");
    // Physics parameters change it.
    for o in [
        "material.E=2e7",
        "material.rho=6001",
        "obstacles.0.radius=0.3",
        "time.duration=0.5",
        "forces.drag=false",
        "collision.margin=0.003",
    ] {
        assert_ne!(base, cache_key(&sphere(&[o]), &settings), "{o}");
    }
    // Reference settings change it.
    for s in [
        ReferenceSettings {
            resolution: 33,
            ..settings.clone()
        },
        ReferenceSettings {
            beta: Some(0.02),
            ..settings.clone()
        },
        ReferenceSettings {
            samples: 32,
            ..settings.clone()
        },
        ReferenceSettings {
            dt_initial: None,
            ..settings.clone()
        },
        ReferenceSettings {
            integrator: Some("symplectic_euler".into()),
            ..settings.clone()
        },
        ReferenceSettings {
            dt: Some(0.00025),
            ..settings.clone()
        },
    ] {
        assert_ne!(base, cache_key(&sphere(&[]), &s), "{s:?}");
    }
    // Output and adaptivity settings, the run's own grid, step and strategy do not (the
    // reference replaces them), nor does the output folder (not an input of the key).
    for o in [
        "name=\"other\"",
        "time.metrics_rate=50",
        "adaptivity.l_min=0.05",
        "adaptivity.strategy=\"remesh\"",
        "cloth.resolution=9",
        "time.beta=0.002",
        "time.dt_initial=0.0002",
    ] {
        assert_eq!(base, cache_key(&sphere(&[o]), &settings), "{o}");
    }
    let mut moved = sphere(&[]);
    moved.source = "/elsewhere/out".into();
    assert_eq!(base, cache_key(&moved, &settings));
}

#[test]
fn fnv1a_known_values() {
    // Test vectors of the FNV-1a 64-bit hash.
    assert_eq!(fnv1a(FNV_OFFSET, b""), 0xcbf29ce484222325);
    assert_eq!(fnv1a(FNV_OFFSET, b"a"), 0xaf63dc4c8601ec8c);
    assert_eq!(fnv1a(FNV_OFFSET, b"foobar"), 0x85944171f73967e8);
}

/// A header for the trajectory `t` over `samples` (the other fields fixed test values).
fn header_of(
    samples: SamplePoints,
    t: &Trajectory,
    settings: ReferenceSettings,
) -> ReferenceHeader {
    ReferenceHeader {
        format: CACHE_FORMAT,
        key: "0123456789abcdef".into(),
        scene: "s".into(),
        settings,
        integrator: "rk4".into(),
        beta: 0.01,
        samples,
        times: t.times.clone(),
        final_vertices: 1,
        steps: 10,
        wall_s: 1.0,
        sim_time: 0.5,
        floor: Floor {
            resolution: 3,
            e_rms: 0.1,
            e_final: 0.2,
            tracked_err: 0.3,
            hausdorff: 0.4,
            wall_s: 0.5,
            steps: 6,
        },
        physics: serde_json::json!({"a": 1}),
        data_hash: String::new(),
    }
}

/// Three sample points (two of them a grid) and their trajectory over `times` (s), `positions`
/// three per frame (m), one final vertex.
fn three_points(times: Vec<f64>, positions: Vec<[f32; 3]>) -> (SamplePoints, Trajectory) {
    let samples = SamplePoints {
        rest: vec![[0.0, 0.0], [1.0, 0.0], [0.5, 0.5]],
        grid: 2,
        side: 0,
    };
    let t = Trajectory {
        points: 3,
        grid: 2,
        side: 0,
        times,
        positions,
        final_vertices: vec![[1.0, 2.0, 3.0]],
        adapt: Default::default(),
    };
    (samples, t)
}

#[test]
fn bin_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("reference.bin");
    let (samples, t) = three_points(
        vec![0.0, 0.5],
        (0..6).map(|i| [i as f32, 0.5, -1.25 * i as f32]).collect(),
    );
    let header = header_of(samples, &t, ReferenceSettings::default());
    let written = write_bin(&path, &header, &t).unwrap();
    let (h, back) = read_bin(&path).unwrap();
    assert_eq!(h, written);
    assert_eq!(
        h,
        ReferenceHeader {
            data_hash: h.data_hash.clone(),
            ..header
        }
    );
    assert_eq!(back, t);
    // Regression (study review 2026-11-29, finding 7): positions moved by 5 cm, still finite,
    // were used as the reference. The data's checksum finds them.
    let mut bytes = std::fs::read(&path).unwrap();
    let last = bytes.len() - 4;
    let moved = f32::from_le_bytes(bytes[last..].try_into().unwrap()) + 0.05;
    bytes[last..].copy_from_slice(&moved.to_le_bytes());
    std::fs::write(&path, &bytes).unwrap();
    match read_bin(&path) {
        Err(ReferenceError::Malformed { why, .. }) => assert!(why.contains("checksum"), "{why}"),
        other => panic!("{other:?}"),
    }
    // A truncated file is reported, not misread.
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 4]).unwrap();
    assert!(matches!(
        read_bin(&path),
        Err(ReferenceError::Malformed { .. })
    ));
}

/// A floor error that is not a number (no tracked point: a scene without `[[tracked]]`) is
/// written `null` and read back as NaN: such a reference is read from the cache, not discarded
/// and computed again at every study.
#[test]
fn a_reference_whose_floor_has_no_tracked_error_is_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("reference.bin");
    let (samples, t) = three_points(vec![0.0], vec![[0.0; 3]; 3]);
    let mut header = header_of(samples, &t, ReferenceSettings::default());
    header.floor.tracked_err = f64::NAN;
    write_bin(&path, &header, &t).unwrap();
    let (back, _) = read_bin(&path).expect("read back");
    assert!(back.floor.tracked_err.is_nan());
    assert_eq!(back.floor.e_rms, header.floor.e_rms);
}

/// A valid `reference.bin` over a complete 2 x 2 sample grid at `path`, and its header.
fn write_small_entry(path: &Path) -> ReferenceHeader {
    let samples = SamplePoints {
        rest: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
        grid: 4,
        side: 2,
    };
    let t = Trajectory {
        points: 4,
        grid: 4,
        side: 2,
        times: vec![0.0, 0.5],
        positions: (0..8).map(|i| [i as f32, 0.5, -0.25 * i as f32]).collect(),
        final_vertices: vec![[1.0, 2.0, 3.0]],
        adapt: Default::default(),
    };
    let header = header_of(
        samples,
        &t,
        ReferenceSettings {
            samples: 2,
            ..ReferenceSettings::default()
        },
    );
    let header = write_bin(path, &header, &t).unwrap();
    assert!(read_bin(path).is_ok());
    header
}

/// Regression (trial report A6): a cache entry with NaN or infinite positions, or a header whose
/// counts disagree with the data, was loaded as "(cached)" and its NaN turned into plausible
/// errors. Each is refused as malformed (and so recomputed).
#[test]
fn a_corrupted_reference_cache_entry_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("reference.bin");
    let refused = |path: &Path, what: &str| match read_bin(path) {
        Err(ReferenceError::Malformed { why, .. }) => why,
        other => panic!("{what}: expected Malformed, got {other:?}"),
    };
    // A non-finite value in the data, the header intact.
    for bad in [f32::NAN, f32::INFINITY] {
        write_small_entry(&path);
        let mut bytes = std::fs::read(&path).unwrap();
        let at = bytes.len() - 8; // the last vertex's y
        bytes[at..at + 4].copy_from_slice(&bad.to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        let why = refused(&path, &format!("{bad}"));
        assert!(why.contains("expected a finite number"), "{why}");
    }
    // Header counts off by one, the data intact.
    let rewrite = |edit: &dyn Fn(&mut ReferenceHeader)| {
        let mut header = write_small_entry(&path);
        let (_, t) = read_bin(&path).unwrap();
        edit(&mut header);
        // Written byte for byte as `write_bin` would, whatever the header says.
        let json = serde_json::to_vec(&header).unwrap();
        let mut bytes = bin::MAGIC.to_vec();
        bytes.extend_from_slice(&(json.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&json);
        for c in t.positions.iter().chain(&t.final_vertices).flatten() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
        std::fs::write(&path, bytes).unwrap();
    };
    rewrite(&|h| h.settings.samples += 1);
    assert!(refused(&path, "samples + 1").contains("settings.samples = 3"));
    rewrite(&|h| h.final_vertices += 1);
    assert!(refused(&path, "final_vertices + 1").contains("floats, expected"));
    rewrite(&|h| h.samples.grid += 1);
    refused(&path, "grid + 1");
    rewrite(&|h| h.times[1] = f64::NAN);
    refused(&path, "a NaN time");
    // Edited so that the data would be misread: times reversed, a negative floor (the hostile
    // sweep of 2026-11-29 had them used without a word).
    rewrite(&|h| h.times.reverse());
    assert!(refused(&path, "reversed times").contains("increasing times"));
    rewrite(&|h| h.floor.e_rms = -1.0);
    assert!(refused(&path, "a negative floor").contains("floor error"));
    rewrite(&|h| h.floor.e_rms = f64::NAN);
    assert!(refused(&path, "no floor e_rms").contains("floor error"));
}

/// The keys of the shipped scenes without moving obstacles, as computed before obstacles could
/// move (`[obstacles.motion]`) and after face contact became the default (the mode is part of
/// the key): a scene that does not use a later key keeps its cached references. The sphere's
/// key is the one the build before the motion merge gave its reference. Self-collision
/// (`collision.self`, issue 16) is such a later key: off, the keys are the old ones; on (as the
/// sphere and the round table ship), it is physics and changes the key. So is the face penalty
/// (on by default since 2026-11-30): at 0 the keys are the old ones.
#[test]
fn scenes_without_motion_keep_their_cache_keys() {
    let settings = ReferenceSettings::default();
    let off = [
        "collision.self=false".to_string(),
        "collision.penalty=0".to_string(),
    ];
    for (name, key) in [
        ("sphere", "f0230cb2139792e0"),
        ("round_table", "d6e383108c333410"),
        ("hanging", "454b940d2ad9874f"),
        ("sphere_peer", "df5e1a1d60c3da56"),
    ] {
        let scene = load_embedded(name, &off).unwrap().unwrap();
        assert_eq!(cache_key(&scene, &settings), key, "{name}");
    }
    let shipped = load_embedded("sphere", &[]).unwrap().unwrap();
    assert!(shipped.scene.collision.self_collision);
    assert_ne!(cache_key(&shipped, &settings), "f0230cb2139792e0");
    let no_self = load_embedded("sphere", &off[..1]).unwrap().unwrap();
    assert!(no_self.scene.collision.penalty > 0.0);
    assert_ne!(cache_key(&no_self, &settings), "f0230cb2139792e0");
}

#[test]
fn a_fixed_reference_step_makes_the_reference_and_floor_runs_fixed() {
    let base = sphere(&[]);
    let dynamic = static_variant(&base, 9, &ReferenceSettings::default());
    assert_eq!(dynamic.scene.time.mode, TimeMode::Dynamic);
    let settings = ReferenceSettings {
        integrator: Some("implicit_euler".into()),
        dt: Some(0.00025),
        ..ReferenceSettings::default()
    };
    let fixed = static_variant(&base, 9, &settings);
    assert_eq!(fixed.scene.time.mode, TimeMode::Fixed);
    assert_eq!(fixed.scene.time.dt, 0.00025);
    assert_eq!(fixed.scene.integrator.name, "implicit_euler");
    assert_eq!(
        step_description(0.01, Some(0.0), settings.dt),
        "fixed step 0.00025 s"
    );
    // Cache entries written before the key existed still read.
    let mut json = serde_json::to_value(ReferenceSettings::default()).unwrap();
    json.as_object_mut().unwrap().remove("dt");
    let old: ReferenceSettings = serde_json::from_value(json).unwrap();
    assert_eq!(old.dt, None);
}
