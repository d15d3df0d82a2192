//! The command line's outputs beyond the image, checked for what they hold: per-light
//! shadow AOVs and atlases, compare's report, exact instance and label ids, a file's own
//! image-based light.

mod common;

use common::*;

#[test]
fn shadow_aovs_and_atlas_are_written_per_light() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(
        &[
            "render",
            "--width",
            "64",
            "--height",
            "48",
            "--demo-lights",
            "2",
            "-o",
            "demo.png",
            "--aov",
            "shadow",
            "--debug",
            "shadow-atlas",
            "--debug",
            "cascades",
            "--shadow-atlas-size",
            "512",
        ],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    // Demo lights: the sun and two others, on nodes after the 9 objects.
    for node in [9, 10, 11] {
        let channels = read_exr_channels(&dir.path().join(format!("demo.shadow.{node}.exr")));
        assert_eq!(channels.len(), 1);
        let values = &channels[0].1;
        assert!(values.iter().filter(|v| v.is_finite()).all(|v| (0.0..=1.0).contains(v)));
        // The sun, the spot and the point all cast shadows in the demo's view.
        assert!(values.iter().any(|&v| v < 0.5), "light on node {node} casts no shadow");
    }
    let atlas = image::open(dir.path().join("demo.shadow-atlas.png")).unwrap();
    assert_eq!((atlas.width(), atlas.height()), (512, 512));
    // The spot and the point cast into the second atlas (default 2048).
    let other = image::open(dir.path().join("demo.other-shadow-atlas.png")).unwrap().to_luma8();
    assert_eq!(other.width(), 2048);
    assert!(other.pixels().any(|p| p.0[0] < 250), "casters drawn into the point/spot atlas");
}

#[test]
fn bad_shadow_options_name_the_setting() {
    expect_failure(&[], &["render", "--shadow-filter", "gauss", "-o", "out.png"], &[], &["shadows.directional.filter"]);
    expect_failure(&[], &["render", "--cascades", "9", "-o", "out.png"], &[], &["shadows.directional.cascade_count"]);
    expect_failure(&[], &["render", "--shadow-distance", "-4", "-o", "out.png"], &[], &["shadows.max_distance"]);
}

#[test]
fn compare_reports_every_light() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(
        &["compare", "--width", "96", "--height", "96", "--demo-lights", "2", "--diff", "diff.png"],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    for name in ["sun", "spot 0", "point 1"] {
        assert!(run.stdout.contains(name), "missing {name}: {}", run.stdout);
    }
    let sun_line = run.stdout.lines().find(|l| l.contains("sun")).unwrap();
    let disagree: f64 = sun_line.split_whitespace().nth(4).unwrap().parse().unwrap();
    assert!(disagree < 100.0 * chiaro_compare::MAX_DISAGREEMENT, "{sun_line}");
    // The sun's difference picture: a grey pixel for each compared pixel that agrees,
    // black where not compared.
    let compared: usize = sun_line.split_whitespace().nth(3).unwrap().parse().unwrap();
    let diff = image::open(dir.path().join("diff.9.png")).unwrap().to_rgb8();
    assert_eq!(diff.dimensions(), (96, 96));
    let agree = diff.pixels().filter(|p| p.0 == [128, 128, 128] || p.0 == [48, 48, 48]).count();
    let disagree = diff.pixels().filter(|p| p.0 == [255, 0, 0] || p.0 == [0, 0, 255]).count();
    assert!(compared > 96 * 96 / 4, "{sun_line}");
    assert_eq!(agree + disagree, compared, "{sun_line}");
    // Shadows cut off half a metre from the camera miss most of the reference's: the
    // limit catches it.
    let run = chiaro(
        &[
            "compare",
            "--width",
            "64",
            "--height",
            "64",
            "--demo-lights",
            "2",
            "--shadow-distance",
            "0.5",
            "--fail-above",
            "0.5",
        ],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 1, "{}", run.stdout);
    assert!(error_lines(&run)[0].contains("limit 0.5%"), "{}", run.stderr);
}

/// Two triangles, node 0 labelled 5 by its extras, node 1 without a label.
fn labelled_triangles(label: &str) -> String {
    let nodes = format!(
        r#"[{{"mesh": 0, "translation": [-1.2, 0, 0], "extras": {{"label": {label}}}}}, {{"mesh": 0, "translation": [0.2, 0, 0]}}]"#
    );
    triangle_gltf(&nodes, TRIANGLE_BUFFER, 36, 0).replace(r#""nodes": [0]"#, r#""nodes": [0, 1]"#)
}

#[test]
fn instance_and_label_aovs_are_exact_uint32_ids() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.gltf"), labelled_triangles("5")).unwrap();
    let run = chiaro(
        &[
            "render", "tri.gltf", "--width", "64", "--height", "64", "-o", "tri.png", "--aov", "instance", "--aov",
            "label",
        ],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let read = |name: &str| {
        use exr::prelude::*;
        let image = read_all_flat_layers_from_file(dir.path().join(name)).unwrap();
        let channels = &image.layer_data[0].channel_data.list;
        assert_eq!(channels.len(), 1, "{name}: one channel");
        match &channels[0].sample_data {
            FlatSamples::U32(values) => values.clone(),
            other => panic!("{name}: uint32 samples expected, got {other:?}"),
        }
    };
    let (instance, label) = (read("tri.instance.exr"), read("tri.label.exr"));
    assert_eq!(instance.len(), 64 * 64);
    let count = |node: u32| instance.iter().filter(|&&n| n == node).count();
    println!("node 0: {} pixels, node 1: {}, sky: {}", count(0), count(1), count(u32::MAX));
    assert!(count(0) > 20 && count(1) > 20 && count(u32::MAX) > 20);
    assert_eq!(count(0) + count(1) + count(u32::MAX), instance.len(), "only the two nodes and the sky");
    for (node, label) in instance.iter().zip(&label) {
        assert_eq!(*label, if *node == 0 { 5 } else { 0 }, "node {node}");
    }
}

#[test]
fn a_label_that_is_no_class_id_names_the_node_and_the_key() {
    expect_failure(
        &[("tri.gltf", labelled_triangles("\"car\"").as_bytes())],
        &["render", "tri.gltf", "-o", "tri.png", "--aov", "label"],
        &[],
        &["tri.gltf", "node 0", "extras.label"],
    );
}

#[test]
fn a_file_with_an_image_based_light_renders_under_it() {
    // Every cube face a different colour; the file's camera looks down -Z, so the middle
    // of the picture is the -Z face (radiance in the linear .exr).
    let faces = [[4.0, 1.0, 1.0], [1.0, 4.0, 1.0], [1.0, 1.0, 4.0], [3.0, 3.0, 1.0], [1.0, 3.0, 3.0], [0.5, 2.0, 6.0]];
    let doc =
        chiaro_testkit::image_based_light_gltf(8, |face, _| glam::Vec3::from_array(faces[face]), serde_json::json!({}));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("studio.gltf"), doc.to_string()).unwrap();
    let middle = |args: &[&str]| {
        let run =
            chiaro(&[&["render", "studio.gltf", "--width", "33", "--height", "33"], args].concat(), &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
        let channels = read_exr_channels(&dir.path().join("out.exr"));
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        let at = |name: &str| channels[names.iter().position(|n| *n == name).unwrap()].1[16 * 33 + 16];
        [at("R"), at("G"), at("B")]
    };
    let own = middle(&["-o", "out.exr"]);
    for (got, want) in own.iter().zip(faces[5]) {
        assert!((got / want - 1.0).abs() < 0.03, "{own:?} is not the -Z face {:?}", faces[5]);
    }
    let info = chiaro(&["info", "studio.gltf"], &[], dir.path());
    assert!(
        info.stdout.contains("environment: EXT_lights_image_based light 0 (test studio), 32 x 16"),
        "{}",
        info.stdout
    );
    // `--environment ambient` keeps the plain background.
    let plain = middle(&["--environment", "ambient", "-o", "out.exr"]);
    assert!(plain.iter().all(|c| *c < 0.5), "{plain:?}");
    // A scene naming a light the file does not have is refused, naming file and path.
    let mut bad = doc.clone();
    bad["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"] = serde_json::json!(2);
    let code = expect_failure(
        &[("bad.gltf", bad.to_string().as_bytes())],
        &["render", "bad.gltf", "-o", "out.png"],
        &[],
        &["bad.gltf", "scenes[0].extensions.EXT_lights_image_based.light: 2 is not one of the 1 lights"],
    );
    assert_eq!(code, 1);
}

#[test]
fn ambient_occlusion_aov_and_compare_columns() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ao.toml"), "[ambient_occlusion]\nenabled = true\n").unwrap();
    let run = chiaro(
        &["render", "--width", "128", "--height", "96", "--settings", "ao.toml", "-o", "demo.png", "--aov", "ao"],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let channels = read_exr_channels(&dir.path().join("demo.ao.exr"));
    assert_eq!(channels.len(), 1, "one channel");
    let values = &channels[0].1;
    assert_eq!(values.len(), 128 * 96);
    assert!(values.iter().all(|v| (0.0..=1.0).contains(v)), "AO within 0 to 1");
    // The demo's objects stand on a floor: their feet are occluded, the open floor is not.
    assert!(values.iter().filter(|&&v| v < 0.9).count() > 50, "no pixel occluded");
    assert!(values.iter().filter(|&&v| v > 0.99).count() > values.len() / 4, "open surfaces occluded");

    let run = chiaro(
        &["compare", "--width", "64", "--height", "64", "--settings", "ao.toml", "--diff", "diff.png"],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let line = run.stdout.lines().find(|l| l.starts_with("ambient occlusion")).expect(&run.stdout);
    let mean: f32 = line.split("mean |dAO| ").nth(1).unwrap().split_whitespace().next().unwrap().parse().unwrap();
    assert!(mean < 0.05, "{line}");
    let diff = image::open(dir.path().join("diff.ao.png")).unwrap();
    assert_eq!((diff.width(), diff.height()), (64, 64));
}
