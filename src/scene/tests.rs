//! Scene loading: the shipped scenes parse, overrides work, bad input gets a clear error.
use super::*;

fn text_of(name: &str) -> &'static str {
    EMBEDDED_SCENES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .expect("embedded scene")
}

fn load_text(text: &str, overrides: &[&str]) -> Result<LoadedScene, SceneError> {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let base = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    from_text(text, "test.toml", "test", base, &overrides)
}

#[test]
fn every_embedded_scene_loads() {
    for (name, _) in EMBEDDED_SCENES {
        let loaded = load_embedded(name, &[]).expect("embedded").expect("valid");
        assert_eq!(&loaded.scene.name, name);
    }
}

#[test]
fn source_parameters_are_read_under_their_names() {
    let s = load_embedded("bunny", &[]).unwrap().unwrap().scene;
    assert_eq!(s.material.rho, 8000.0);
    assert_eq!(s.material.thickness, 1e-4);
    assert_eq!(s.material.kappa, 3.0);
    assert_eq!(s.material.young, 1e7);
    assert_eq!(s.material.mu, 0.4);
    assert_eq!(s.adaptivity.l_min, 0.13);
    assert_eq!(s.adaptivity.l_max, 0.40);
    assert_eq!(s.adaptivity.density_simplify, 0.75);
    assert_eq!(s.obstacles.len(), 2);
    assert_eq!(s.obstacles[0].friction, 0.01);
    let t = load_embedded("round_table", &[]).unwrap().unwrap().scene;
    assert_eq!(t.material.kappa, 3.5);
    assert_eq!(t.adaptivity.t_simplify, 0.02);
    assert_eq!(t.adaptivity.c2, 0.65);
    match t.obstacles[0].shape {
        ObstacleShape::Cylinder { radius, .. } => assert_eq!(radius, 0.35),
        ref other => panic!("round table is {other:?}"),
    }
}

#[test]
fn set_overrides_any_key_and_converts_integers_for_floats() {
    let s = load_text(
        text_of("sphere"),
        &[
            "cloth.resolution=17",
            "material.E=1e9",
            "time.duration=1",
            "obstacles.0.radius=0.3",
            "forces.drag=false",
            "integrator.name=symplectic_euler",
        ],
    )
    .unwrap()
    .scene;
    assert_eq!(s.cloth.resolution, 17);
    assert_eq!(s.material.young, 1e9);
    assert_eq!(s.time.duration, 1.0);
    assert!(!s.forces.drag);
    assert_eq!(s.integrator.name, "symplectic_euler");
    match s.obstacles[0].shape {
        ObstacleShape::Sphere { radius, .. } => assert_eq!(radius, 0.3),
        ref other => panic!("{other:?}"),
    }
}

#[test]
fn set_of_a_key_absent_from_the_file_but_in_the_schema_works() {
    let s = load_text("[time]\nduration = 0.1\n", &["time.dt_max=1e-3"]).unwrap();
    assert_eq!(s.scene.time.dt_max, 1e-3);
}

#[test]
fn unknown_key_in_file_is_named_with_its_line() {
    let text = "[cloth]\nresolution = 5\n\n[material]\nrho = 1000.0\nstiffnes = 3\n";
    let e = load_text(text, &[]).unwrap_err().to_string();
    assert!(e.contains("stiffnes"), "{e}");
    assert!(e.contains("line 6"), "{e}");
}

#[test]
fn wrong_type_is_reported_with_its_line() {
    let e = load_text("[cloth]\nresolution = \"five\"\n", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 2"), "{e}");
}

#[test]
fn out_of_range_values_are_rejected_with_key_line_and_expectation() {
    let cases = [
        ("[material]\nrho = -1.0\n", "material.rho", ":2"),
        ("[time]\ndt = 0.0\n", "time.dt", ":2"),
        ("[time]\nduration = -2\n", "time.duration", ":2"),
        (
            "[collision]\nrestitution = 1.5\n",
            "collision.restitution",
            ":2",
        ),
        (
            "[collision]\nrestitution = 0.0\n",
            "collision.restitution",
            ":2",
        ),
        ("[cloth]\nresolution = 1\n", "cloth.resolution", ":2"),
        ("[collision]\npenalty = -1e3\n", "collision.penalty", ":2"),
        // A thickness of a metre would test every pair of the cloth each step.
        (
            "[collision]\nthickness = 1.0\n",
            "collision.thickness",
            ":2",
        ),
        (
            "[collision]\nthickness = 0.0\n",
            "collision.thickness",
            ":2",
        ),
        (
            "[[obstacles]]\nkind = \"sphere\"\ncenter = [0,0,0]\nradius = -1\n",
            "obstacles.0.radius",
            ":4",
        ),
    ];
    for (text, key, line) in cases {
        let e = load_text(text, &[]).unwrap_err();
        assert!(matches!(e, SceneError::Invalid { .. }), "{text}: {e}");
        let msg = e.to_string();
        assert!(msg.contains(key), "{msg}");
        assert!(msg.contains(&format!("test.toml{line}")), "{msg}");
    }
}

#[test]
fn missing_mesh_file_is_rejected() {
    let text = "[[obstacles]]\nkind = \"mesh\"\nfile = \"meshes/nothere.obj\"\n";
    let e = load_text(text, &[]).unwrap_err().to_string();
    assert!(e.contains("nothere.obj") && e.contains("not found"), "{e}");
}

#[test]
fn unknown_strategy_and_integrator_list_the_valid_ones() {
    let e = load_text("", &["adaptivity.strategy=foo"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("static") && e.contains("bisect48"), "{e}");
    let e = load_text("", &["integrator.name=leapfrog"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("rk4") && e.contains("symplectic_euler"), "{e}");
}

#[test]
fn set_of_an_unknown_key_is_an_error() {
    for bad in ["cloth.resolutin=3", "nosection.x=1", "obstacles.5.radius=1"] {
        let e = load_text(text_of("sphere"), &[bad]).unwrap_err();
        assert!(matches!(e, SceneError::UnknownKey { .. }), "{bad}: {e}");
    }
    let e = load_text("", &["cloth.resolution"]).unwrap_err();
    assert!(matches!(e, SceneError::BadOverride { .. }));
    // A list index out of range says which indices exist, in words.
    let e = load_text(text_of("sphere"), &["obstacles.5.radius=1"]).unwrap_err();
    assert!(e.to_string().contains("0 (the list has one entry)"), "{e}");
}

#[test]
fn a_number_beyond_a_doubles_range_says_so() {
    for raw in ["1e400", "-1e400"] {
        let setting = format!("material.rho={raw}");
        let e = load_text("", &[setting.as_str()]).unwrap_err().to_string();
        assert!(e.contains("beyond the range of a number"), "{e}");
        assert!(e.contains(&setting), "{e}");
    }
    // `inf` spelled out is TOML's infinity, a number (refused later by the range checks).
    let e = load_text("", &["material.rho=inf"])
        .unwrap_err()
        .to_string();
    assert!(!e.contains("beyond the range"), "{e}");
}

#[test]
fn a_value_where_a_section_belongs_says_a_section_was_expected() {
    let e = load_text("", &["cloth=3"]).unwrap_err().to_string();
    assert!(
        e.contains("expected a section (a table of keys) in `cloth`"),
        "{e}"
    );
    assert!(!e.contains("struct"), "{e}");
}

#[test]
fn set_with_wrong_type_is_an_error_not_a_panic() {
    let e = load_text("", &["cloth.resolution=abc"]).unwrap_err();
    assert!(matches!(e, SceneError::Parse { .. }), "{e}");
}

#[test]
fn a_strategy_specific_key_set_for_a_strategy_that_ignores_it_is_rejected() {
    let text = "[adaptivity]\nstrategy = \"remesh\"\nmax_depth = 5\n";
    let e = load_text(text, &[]).unwrap_err().to_string();
    assert!(e.contains("test.toml:3: adaptivity.max_depth = 5"), "{e}");
    assert!(e.contains("`remesh` ignores"), "{e}");
    assert!(e.contains("simnett, bisect48 only"), "{e}");
    for (key, strategy) in [
        ("force_completion=true", "bisect48"),
        ("remesh_min_angle=20", "simnett"),
        ("depth_factor=0.9", "bisect48"),
        ("curvature_exponent=1", "simnett"),
    ] {
        let strategy = format!("adaptivity.strategy={strategy}");
        let key = format!("adaptivity.{key}");
        let e = load_text("", &[&strategy, &key]).unwrap_err();
        assert!(matches!(e, SceneError::Invalid { .. }), "{key}: {e}");
    }
    // The static baseline reads none of them (trial report C1: it was exempt).
    for key in [
        "max_depth=5",
        "remesh_min_angle=10",
        "force_completion=true",
    ] {
        let key = format!("adaptivity.{key}");
        let e = load_text("", &["adaptivity.strategy=static", &key])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("strategy `static` ignores this key"),
            "{key}: {e}"
        );
    }
    // The strategies that read a key accept it; the default value is accepted everywhere.
    load_text(
        "",
        &[
            "adaptivity.strategy=simnett",
            "adaptivity.force_completion=true",
        ],
    )
    .unwrap();
    load_text(
        "",
        &["adaptivity.strategy=bisect48", "adaptivity.max_depth=4"],
    )
    .unwrap();
    load_text(
        "",
        &["adaptivity.strategy=static", "adaptivity.max_depth=3"],
    )
    .unwrap();
    load_text(
        "",
        &["adaptivity.strategy=remesh", "adaptivity.max_depth=3"],
    )
    .unwrap();
}

#[test]
fn every_source_scene_loads_with_every_strategy() {
    for (name, _) in EMBEDDED_SCENES {
        for strategy in crate::strategies::strategy_names() {
            let set = format!("adaptivity.strategy={strategy}");
            load_text(text_of(name), &[&set]).unwrap_or_else(|e| panic!("{name}/{strategy}: {e}"));
        }
    }
}

#[test]
fn the_resolved_scene_loads_back_to_the_same_scene_from_another_folder() {
    let overrides = [
        "cloth.resolution=9".to_string(),
        "time.duration=0.2".to_string(),
    ];
    for name in ["bunny", "sphere"] {
        let loaded = load_embedded(name, &overrides).unwrap().unwrap();
        let text = resolved_toml(&loaded, "adaptcloth run bunny --set cloth.resolution=9");
        assert!(text.starts_with("# The scene this run ran"), "{text}");
        assert!(text.contains("# Command: adaptcloth run bunny"), "{text}");
        assert!(text.contains(env!("CARGO_PKG_VERSION")));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene.resolved.toml");
        std::fs::write(&path, &text).unwrap();
        let back = load(&path, &[]).unwrap();
        // Mesh files are absolute or built in, so only their spelling may differ: the embedded
        // bunny's is the built-in copy (trial report A7).
        let mut want = loaded.scene.clone();
        for (o, b) in want.obstacles.iter_mut().zip(&back.scene.obstacles) {
            if let (ObstacleShape::Mesh { file, .. }, ObstacleShape::Mesh { file: f2, .. }) =
                (&mut o.shape, &b.shape)
            {
                assert_eq!(f2, &format!("<embedded>/{file}"));
                file.clone_from(f2);
            }
        }
        let mesh = back.obstacles().into_iter().find_map(|o| match o.shape {
            crate::collision::ObstacleShape::Mesh { file, .. } => Some(file),
            _ => None,
        });
        if name == "bunny" {
            let obj = crate::io::read_obj(&mesh.unwrap()).unwrap();
            assert_eq!((obj.positions.len(), obj.faces.len()), (2002, 4000));
        }
        assert_eq!(back.scene, want, "{name}");
    }
}

/// A sub-table of an obstacle written after another section (`[obstacles.motion]` after
/// `[adaptivity]`) is still found at its line.
#[test]
fn a_motion_table_after_another_section_is_found_at_its_line() {
    let text = "[[obstacles]]\nkind = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.2\n\
                [adaptivity]\nl_min = 0.1\n\
                [obstacles.motion]\nkind = \"keyframes\"\ntimes = [0.0, 1.0]\n\
                positions = [[0,0,0],[0,1e308,0]]\n";
    let e = load_text(text, &[]).unwrap_err().to_string();
    assert!(e.contains(":10: obstacles.0.motion.positions[1]"), "{e}");
}

/// A parser message echoes a huge key clipped (a 100,000-character key made a 300 KB message).
#[test]
fn a_huge_key_is_echoed_clipped() {
    let text = format!("[cloth]\n{} = 1\n", "k".repeat(100_000));
    let e = load_text(&text, &[]).unwrap_err().to_string();
    assert!(
        e.contains("unknown field") && e.contains("... (100008 characters)"),
        "{e}"
    );
    assert!(e.len() < 2_000, "{} bytes", e.len());
}

/// A duration too long for any frame rate is blamed on the duration, with its line, and echoed
/// short (it named `time.frame_rate = 6e1` without a line and printed 1e300 as 301 digits).
#[test]
fn a_duration_too_long_is_named_and_echoed_short() {
    let e = load_text("[time]\nduration = 1e300\n", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains(":2: time.duration = 1e300"), "{e}");
    assert!(e.contains("over time.duration = 1e300 s"), "{e}");
    assert!(e.len() < 200, "{e}");
    // A frame rate too high for the duration is the rate's fault.
    let e = load_text("[time]\nduration = 1.0\nframe_rate = 1e9\n", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains(":3: time.frame_rate = 1e9"), "{e}");
}

/// A newline in the command (an argument of `--set`) stays inside the comment: it made the rest
/// of the argument a line of the resolved scene, which then failed to load (`[bogus]`).
#[test]
fn a_newline_in_the_command_stays_in_its_comment() {
    let loaded = load_embedded("sphere", &[]).unwrap().unwrap();
    let text = resolved_toml(
        &loaded,
        "adaptcloth run --set 'description=x\n[bogus]\ny=1'\r",
    );
    assert!(
        text.contains("# Command: adaptcloth run --set 'description=x\\n[bogus]\\ny=1'\\r\n"),
        "{text}"
    );
    let back = load_text(&text, &[]).unwrap();
    assert_eq!(back.scene, loaded.scene);
}

#[test]
fn sizing_keys_need_the_sizing_criteria_and_rounds_are_bounded() {
    let e = load_text("", &["adaptivity.size_angle=0.1"]).unwrap_err();
    assert!(e.to_string().contains("criteria = \"sizing\""), "{e}");
    load_text(
        "",
        &[
            "adaptivity.criteria=\"sizing\"",
            "adaptivity.size_angle=0.1",
        ],
    )
    .unwrap();
    let e = load_text("", &["adaptivity.criteria=\"narain\""]).unwrap_err();
    assert!(e.to_string().contains("adaptivity.criteria"), "{e}");
    for bad in ["adaptivity.rounds=0", "adaptivity.rounds=17"] {
        let e = load_text("", &[bad]).unwrap_err();
        assert!(e.to_string().contains("1..=16"), "{bad}: {e}");
    }
    for bad in [
        "adaptivity.size_velocity=0",
        "adaptivity.size_compression=-1",
        "adaptivity.size_proximity=nan",
    ] {
        let sizing = "adaptivity.criteria=\"sizing\"";
        assert!(load_text("", &[sizing, bad]).is_err(), "{bad}");
    }
}

#[test]
fn the_sizing_criteria_on_a_static_run_are_rejected_after_every_override() {
    let text = "[adaptivity]\nstrategy = \"static\"\ncriteria = \"sizing\"\n";
    let e = load_text(text, &[]).unwrap().check_run().unwrap_err();
    let e = e.to_string();
    assert!(
        e.starts_with("test.toml:3: adaptivity.criteria = \"sizing\": strategy `static` never"),
        "{e}"
    );
    assert!(e.contains("bisect48"), "{e}");
    let e = load_text("", &["adaptivity.criteria=\"sizing\""])
        .unwrap()
        .check_run()
        .unwrap_err();
    assert!(
        e.to_string().starts_with("--set adaptivity.criteria"),
        "{e}"
    );
    // `run --strategy bisect48` on a file that says static: the final scene adapts.
    let overrides = Overrides {
        strategy: Some("bisect48".into()),
        ..Overrides::default()
    };
    let base = PathBuf::from(".");
    let loaded = from_text_with(text, "test.toml", "test", base, &overrides).unwrap();
    loaded.check_run().unwrap();
}

#[test]
fn an_error_from_a_setting_names_its_key_and_value_once() {
    let e = load_text("", &["adaptivity.size_angle=0.1"]).unwrap_err();
    let e = e.to_string();
    assert!(
        e.starts_with("--set adaptivity.size_angle=0.1: a sizing-field key"),
        "{e}"
    );
    assert_eq!(e.matches("size_angle").count(), 1, "{e}");
}

/// `[obstacles.motion]` reads into the core's motion and takes `--set`; a scene without it
/// serializes without a `motion` key (so its reference cache key is unchanged:
/// `eval::reference_tests` pins them).
#[test]
fn obstacle_motion_reads_takes_settings_and_is_absent_from_still_scenes() {
    use crate::collision::ObstacleMotion;
    let loaded = load_embedded("turntable", &[]).unwrap().unwrap();
    let core = loaded.obstacles();
    assert_eq!(
        core[0].motion,
        ObstacleMotion::Spin {
            axis_point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            angular_velocity: 3.0
        }
    );
    assert_eq!(core[1].motion, ObstacleMotion::Still);
    let set = ["obstacles.0.motion.velocity=[0.0, 2.0, 0.0]"].map(String::from);
    let loaded = load_embedded("moving_sphere", &set).unwrap().unwrap();
    assert_eq!(
        loaded.obstacles()[0].motion,
        ObstacleMotion::Linear {
            velocity: [0.0, 2.0, 0.0]
        }
    );
    let still = load_embedded("round_table", &[]).unwrap().unwrap();
    let text = toml::to_string(&still.scene).unwrap();
    assert!(!text.contains("motion"), "{text}");
    // Keyframes with their defaults-free keys round-trip through the resolved scene.
    let keyframes = "[[obstacles]]\nkind = \"box\"\ncenter = [0,0,0]\nhalf_extents = [1,1,1]\n\
                     [obstacles.motion]\nkind = \"keyframes\"\ntimes = [0, 0.5]\n\
                     positions = [[0,0,0], [0.1,0,0]]\n";
    // And with rotations about a pivot.
    let turning = format!("{keyframes}rotations = [[0,0,0], [0,0,1.5]]\npivot = [0.5,0,0]\n");
    for text in [keyframes, turning.as_str()] {
        let loaded = load_text(text, &[]).unwrap();
        let resolved = resolved_toml(&loaded, "test");
        assert_eq!(resolved.contains("rotations"), text.contains("rotations"));
        let back = from_text(&resolved, "back.toml", "back", loaded.base_dir.clone(), &[]).unwrap();
        assert_eq!(back.scene.obstacles, loaded.scene.obstacles);
    }
}

/// A bad `[obstacles.motion]` is named by its key, its line and what was expected, as any other
/// key: values out of range, unknown keys and kinds, wrong types, a moving ground.
#[test]
fn bad_motions_are_rejected_with_key_line_and_expectation() {
    let sphere = "[[obstacles]]\nkind = \"sphere\"\ncenter = [0,0,0]\nradius = 1\n\
                  [obstacles.motion]\n";
    let cases = [
        (
            "kind = \"spin\"\naxis = [0,0,0]\nangular_velocity = 1\n",
            "obstacles.0.motion.axis",
            ":7",
            "non-zero",
        ),
        // The hostile sweep: lengths that overflow or underflow were called "zero" later,
        // without the key's line.
        (
            "kind = \"spin\"\naxis = [1e308,1e308,1e308]\nangular_velocity = 1\n",
            "obstacles.0.motion.axis",
            ":7",
            "non-zero direction of finite length",
        ),
        (
            "kind = \"spin\"\naxis = [1e-320,0,0]\nangular_velocity = 1\n",
            "obstacles.0.motion.axis",
            ":7",
            "non-zero direction of finite length",
        ),
        (
            "kind = \"keyframes\"\ntimes = [0, 1, 1]\npositions = [[0,0,0],[0,0,0],[0,0,0]]\n",
            "obstacles.0.motion.times[2]",
            ":7",
            "strictly increasing",
        ),
        (
            "kind = \"keyframes\"\ntimes = [0, 1]\npositions = [[0,0,0]]\n",
            "obstacles.0.motion.positions",
            ":8",
            "one position per time",
        ),
        (
            "kind = \"keyframes\"\ntimes = [0, 1]\npositions = [[0,0,0],[0,0,0]]\n\
             rotations = [[0,0,1]]\n",
            "obstacles.0.motion.rotations",
            ":9",
            "one rotation per time",
        ),
        (
            "kind = \"keyframes\"\ntimes = [0]\npositions = [[0,0,0]]\npivot = [0, inf, 0]\n",
            "obstacles.0.motion.pivot",
            ":9",
            "finite",
        ),
        // Finite but overflowing: the rotation's angle, the obstacle's place.
        (
            "kind = \"keyframes\"\ntimes = [0]\npositions = [[0,0,0]]\nrotations = [[0,0,1e160]]\n",
            "obstacles.0.motion.rotations[0]",
            ":9",
            "within ±1e6 rad",
        ),
        (
            "kind = \"keyframes\"\ntimes = [0]\npositions = [[1e300,0,0]]\n",
            "obstacles.0.motion.positions[0]",
            ":8",
            "within ±1e6 m",
        ),
        (
            "kind = \"linear\"\nvelocity = [nan, 0, 0]\n",
            "obstacles.0.motion.velocity",
            ":7",
            "finite",
        ),
        (
            "kind = \"linear\"\nvelocity = [1,0,0]\nspeed = 2\n",
            "obstacles.0.motion.speed",
            ":8",
            "no such key",
        ),
        (
            "kind = \"orbit\"\n",
            "obstacles.0.motion.kind",
            ":6",
            "\"keyframes\"",
        ),
        (
            "kind = \"spin\"\nangular_velocity = \"fast\"\n",
            "obstacles.0.motion.angular_velocity",
            ":7",
            "expected a number",
        ),
        (
            "kind = \"linear\"\n",
            "obstacles.0.motion.kind",
            ":6",
            "velocity",
        ),
    ];
    let ground = "[[obstacles]]\nkind = \"ground\"\n[obstacles.motion]\nkind = \"linear\"\n\
                  velocity = [0,0,1]\n";
    let texts = cases
        .iter()
        .map(|(motion, key, line, expected)| (format!("{sphere}{motion}"), *key, *line, *expected))
        .chain([(
            ground.to_string(),
            "obstacles.0.motion.kind",
            ":4",
            "the ground cannot move",
        )]);
    for (text, key, line, expected) in texts {
        let msg = load_text(&text, &[]).unwrap_err().to_string();
        assert!(msg.contains(key), "{text}\n{msg}");
        assert!(msg.contains(&format!("test.toml{line}")), "{text}\n{msg}");
        assert!(msg.contains(expected), "{text}\n{msg}");
    }
}

/// Regression (trial report A3): a list where a section belongs was read positionally
/// (`material = [1, 2]` set `rho` and `T`); refused like any other non-table value, with the key
/// and its line or setting, for the sections and every nested table.
#[test]
fn a_list_where_a_section_belongs_is_refused() {
    let expected = "expected a section (a table of keys), not a list";
    for (text, place) in [
        (
            "material = [1.0, 2.0]\n",
            "test.toml:1: material = [1.0, 2.0]",
        ),
        (
            "name = \"x\"\ntime = [0.05]\n",
            "test.toml:2: time = [0.05]",
        ),
        ("cloth = []\n", "test.toml:1: cloth = []"),
        (
            "tracked = [[\"P\", [0.1, 0.2]]]\n",
            "tracked.0 = [\"P\", [0.1, 0.2]]",
        ),
        (
            "[[obstacles]]\nkind = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.2\n\
             motion = [\"linear\", [1.0, 0.0, 0.0]]\n",
            "test.toml:5: obstacles.0.motion = [\"linear\", [1.0, 0.0, 0.0]]",
        ),
    ] {
        let e = load_text(text, &[]).unwrap_err().to_string();
        assert!(e.contains(place) && e.contains(expected), "{text}: {e}");
    }
    for (set, place) in [
        ("material=[1,2]", "--set material=[1,2]: "),
        ("cloth=[]", "--set cloth=[]: "),
        (
            "tracked=[[\"P\", [0.1, 0.2]]]",
            "--set tracked=[[\"P\", [0.1, 0.2]]]: tracked.0 = ",
        ),
    ] {
        let e = load_text(text_of("sphere"), &[set])
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(place) && e.contains(expected), "{set}: {e}");
    }
    // Lists where lists belong still read.
    load_text(text_of("sphere"), &["cloth.pinned=[[0.0, 0.0]]"]).unwrap();
}

/// Regression (trial report B7): a cap below the cloth's starting vertex count could only fail
/// the run at its first pass; refused with the count.
#[test]
fn max_vertices_below_the_starting_cloth_is_refused() {
    let e = load_text("", &["adaptivity.max_vertices=24"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--set adaptivity.max_vertices=24: expected at least the 25 vertices"),
        "{e}"
    );
    let disk = [
        "cloth.shape=\"disk\"",
        "cloth.resolution=2",
        "adaptivity.max_vertices=18",
    ];
    let e = load_text("", &disk).unwrap_err().to_string();
    assert!(e.contains("at least the 19 vertices"), "{e}");
    load_text("", &["adaptivity.max_vertices=25"]).unwrap();
}

/// Regression (trial report B8): a garbage file named like an embedded scene hid it behind a
/// bare read error; the error now says which was read and how to run the embedded one.
#[test]
fn a_file_named_like_an_embedded_scene_says_it_hides_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sphere");
    std::fs::write(&path, [0xff, 0xfe, 0x00]).unwrap();
    let e = shadowing("sphere", load(&path, &[]).unwrap_err()).to_string();
    assert!(e.contains("cannot read scene file"), "{e}");
    assert!(e.contains("instead of the embedded scene `sphere`"), "{e}");
    std::fs::write(&path, "[cloth\n").unwrap();
    let e = shadowing("sphere", load(&path, &[]).unwrap_err()).to_string();
    assert!(e.contains("instead of the embedded scene `sphere`"), "{e}");
    let e = shadowing("mine", load(&path, &[]).unwrap_err()).to_string();
    assert!(!e.contains("embedded scene"), "{e}");
}

/// Regression (trial report B6): `file = ""` said "( not found)".
#[test]
fn an_empty_obstacle_mesh_path_says_so() {
    let text = "[[obstacles]]\nkind = \"mesh\"\nfile = \"\"\n";
    let e = load_text(text, &[]).unwrap_err().to_string();
    assert!(
        e.contains(
            "test.toml:3: obstacles.0.file = \"\": expected an existing OBJ file (empty path)"
        ),
        "{e}"
    );
}

/// Regression (trial report B1): a value the overrides replace was never checked, so a file with
/// `duration = nan` ran under `--duration`. The file is validated as written, named by its line.
#[test]
fn the_file_is_valid_as_written_under_overrides() {
    for o in ["time.duration=0.5", "time.dt=0.001"] {
        let e = load_text("[time]\nduration = nan\n", &[o])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(":2: time.duration = NaN: expected a finite value > 0"),
            "{o}: {e}"
        );
    }
    assert!(load_text("[time]\nduration = 0.1\n", &["time.duration=0.5"]).is_ok());
}

#[test]
fn a_study_file_given_as_a_scene_is_named_as_such() {
    let study = "scenes = [\"sphere\"]\n[[runs]]\nstrategy = \"static\"\n";
    let e = load_text(study, &[]).unwrap_err().to_string();
    assert!(e.contains("this looks like a study file"), "{e}");
    assert!(e.contains("adaptcloth study FILE"), "{e}");
    // A scene with a mistake is not sent to `study`.
    let e = load_text("[cloth]\nresolutoin = 9\n", &[])
        .unwrap_err()
        .to_string();
    assert!(!e.contains("study file"), "{e}");
}
