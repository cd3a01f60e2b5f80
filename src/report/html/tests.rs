//! Unit tests of the HTML report.

use super::*;

fn square(z: f32) -> FrameMesh {
    FrameMesh {
        positions: vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
        faces: vec![[0, 1, 2], [0, 2, 3]],
    }
}

const SVG: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"><rect width=\"10\" height=\"10\"/></svg>";

#[test]
fn the_report_is_self_contained_and_embeds_its_images() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("error.svg");
    std::fs::write(&svg, SVG).unwrap();
    let png = dir.path().join("grid.png");
    crate::report::render::render_png(&square(0.0), &[], 8, 6, &png).unwrap();
    let sections = [HtmlSection {
        title: "Errors <vs> resolution".into(),
        markdown: "| a | b |\n|---|---|\n| 1 | 2 |\n\n![inline](grid.png) and ![remote](https://example.org/x.png)".into(),
        images: vec![svg.clone(), png.clone()],
    }];
    let mut refined = square(0.1);
    refined.positions.push([0.5, 0.5, 0.1]);
    refined.faces = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    let replays = [ReplayRun {
        label: "static </script><b>".into(),
        frame_times: vec![0.0, 0.1, 0.2],
        frames: vec![square(0.3), square(0.2), refined],
    }];
    let out = dir.path().join("report.html");
    write_report_html(
        &out,
        "Sphere & friends",
        &sections,
        &replays,
        &vec![square(0.0)].into(),
    )
    .unwrap();
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "network reference"
    );
    assert!(!html.contains("<link") && !html.contains("<script src"));
    assert!(html.contains("<title>Sphere &amp; friends</title>"));
    assert!(html.contains("<h2>Errors &lt;vs&gt; resolution</h2>"));
    assert!(html.contains("<td>1</td>"));
    assert_eq!(html.matches("src=\"data:image/svg+xml;base64,").count(), 1);
    assert_eq!(
        html.matches("src=\"data:image/png;base64,").count(),
        2,
        "inline + listed"
    );
    assert!(html.contains("<em>[remote]</em>"));
    assert!(html.contains("id=\"status\"") && html.contains("id=\"replay-canvas\""));
    // Exactly one raw "</script>" per script element: the label cannot close one early.
    assert_eq!(html.matches("</script>").count(), 3);
    // Frames: quantised positions, faces shared while the topology is unchanged.
    let start = html.find("id=\"replay-data\">").unwrap() + "id=\"replay-data\">".len();
    let end = start + html[start..].find("</script>").unwrap();
    let data: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
    let run = &data["runs"][0];
    assert_eq!(run["label"], "static </script><b>");
    assert_eq!(run["topologies"].as_array().unwrap().len(), 2);
    let ks: Vec<u64> = run["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["k"].as_u64().unwrap())
        .collect();
    assert_eq!(ks, vec![0, 0, 1]);
    assert_eq!(run["frames"][0]["p"][2], 3000, "0.3 m in 0.1 mm");
}

#[test]
fn images_other_than_png_or_svg_are_errors_and_an_empty_report_works() {
    let dir = tempfile::tempdir().unwrap();
    let txt = dir.path().join("notes.txt");
    std::fs::write(&txt, "x").unwrap();
    let sections = [HtmlSection {
        title: "t".into(),
        markdown: String::new(),
        images: vec![txt],
    }];
    let out = dir.path().join("report.html");
    let none = ObstacleMeshes::default();
    let err = write_report_html(&out, "t", &sections, &[], &none).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    write_report_html(&out, "empty", &[], &[], &none).unwrap();
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(!html.contains("id=\"replay-canvas\""));
}

/// The replay carries each frame's obstacle motions only when an obstacle moves: a linear motion
/// at 1 m/s along x gives the second frame (t = 0.5 s) a translation of 0.5 m.
#[test]
fn the_replay_carries_obstacle_motions_only_when_one_moves() {
    use crate::scene::{MotionSpec, ObstacleShape, ObstacleSpec};
    let run = [ReplayRun {
        label: "r".into(),
        frame_times: vec![0.0, 0.5],
        frames: vec![square(0.0), square(0.0)],
    }];
    let mut specs = [ObstacleSpec {
        shape: ObstacleShape::Sphere {
            center: [0.0; 3],
            radius: 0.5,
        },
        friction: 0.0,
        restitution: 0.0,
        motion: None,
    }];
    let frames = |specs: &[ObstacleSpec]| {
        let meshes = crate::report::render::obstacle_meshes(specs, Path::new(".")).unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&replay_json("t", &run, &meshes).unwrap()).unwrap();
        json["runs"][0]["frames"].as_array().unwrap().clone()
    };
    assert!(frames(&specs).iter().all(|f| f.get("o").is_none()));
    specs[0].motion = Some(MotionSpec::Linear {
        velocity: [1.0, 0.0, 0.0],
    });
    let moving = frames(&specs);
    let o = &moving[1]["o"][0];
    assert_eq!(o[9].as_f64(), Some(0.5));
    assert_eq!(o[0].as_f64(), Some(1.0));
    assert_eq!(moving[0]["o"][0][9].as_f64(), Some(0.0));
}
