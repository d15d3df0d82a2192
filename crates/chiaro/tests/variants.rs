//! KHR_materials_variants from the command line: `--variant NAME` on render, bench,
//! compare and view, the settings' `[scene] variant` (which the flag overrides), a batch job's
//! `"variant"` key, `chiaro info`'s list, and a name the file lacks refused with the list.
//! The scene: InstancedBoxes' 64 orange boxes, whose primitive variant "Blue" and "Green"
//! make blue and green.

mod common;

use common::*;
use serde_json::{Value, json};
use std::path::Path;

/// boxes-nodes.gltf with materials 2 (blue) and 3 (green) and the variants mapping them.
fn variant_scene(dir: &Path) {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/InstancedBoxes/boxes-nodes.gltf");
    let mut doc: Value = serde_json::from_slice(&std::fs::read(source).unwrap()).unwrap();
    let materials = doc["materials"].as_array_mut().unwrap();
    for (name, color) in [("blue", [0.1, 0.2, 0.9, 1.0]), ("green", [0.1, 0.8, 0.1, 1.0])] {
        materials
            .push(json!({ "name": name, "pbrMetallicRoughness": { "baseColorFactor": color, "metallicFactor": 0.0 } }));
    }
    doc["meshes"][0]["primitives"][0]["extensions"] = json!({ "KHR_materials_variants": { "mappings": [
        { "material": 2, "variants": [0] }, { "material": 3, "variants": [1] } ] } });
    doc["extensions"]["KHR_materials_variants"] = json!({ "variants": [{ "name": "Blue" }, { "name": "Green" }] });
    doc["extensionsUsed"].as_array_mut().unwrap().push(json!("KHR_materials_variants"));
    std::fs::write(dir.join("boxes.gltf"), doc.to_string()).unwrap();
}

/// The mean red, green and blue of a PNG.
fn mean_rgb(path: &Path) -> [f64; 3] {
    let image = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8();
    let n = f64::from(image.width() * image.height());
    let mut sum = [0.0; 3];
    for p in image.pixels() {
        for c in 0..3 {
            sum[c] += f64::from(p[c]) / n;
        }
    }
    sum
}

fn render(dir: &Path, out: &str, extra: &[&str]) -> Run {
    let mut args = vec!["render", "boxes.gltf", "--width", "64", "--height", "64", "-o", out];
    args.extend(extra);
    chiaro(&args, &[], dir)
}

#[test]
fn the_variant_flag_and_setting_pick_the_materials() {
    let dir = tempfile::tempdir().unwrap();
    variant_scene(dir.path());
    std::fs::write(dir.path().join("green.toml"), "[scene]\nvariant = \"Green\"\n").unwrap();
    for (out, extra) in [
        ("default.png", vec![]),
        ("blue.png", vec!["--variant", "Blue"]),
        ("green.png", vec!["--settings", "green.toml"]),
        ("blue-over-green.png", vec!["--settings", "green.toml", "--variant", "Blue"]),
    ] {
        let run = render(dir.path(), out, &extra);
        assert_eq!(run.code, 0, "{out}: {}", run.stderr);
    }
    let [r, g, b] = mean_rgb(&dir.path().join("default.png"));
    assert!(r > g && r > b, "the default boxes are orange: {r} {g} {b}");
    let [r, g, b] = mean_rgb(&dir.path().join("blue.png"));
    assert!(b > r && b > g, "--variant Blue: {r} {g} {b}");
    let [r, g, b] = mean_rgb(&dir.path().join("green.png"));
    assert!(g > r && g > b, "[scene] variant = Green: {r} {g} {b}");
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("blue-over-green.png"), read("blue.png"), "the flag overrides the setting");

    let info = chiaro(&["info", "boxes.gltf"], &[], dir.path());
    assert!(info.stdout.contains("KHR_materials_variants: 2 variants: 'Blue', 'Green'"), "{}", info.stdout);
}

#[test]
fn an_unknown_variant_is_refused_with_the_list_by_every_command() {
    let dir = tempfile::tempdir().unwrap();
    variant_scene(dir.path());
    let expected = "no material variant 'Red'; the scene has: Blue, Green";
    let run = render(dir.path(), "red.png", &["--variant", "Red"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(run.stderr.contains("boxes.gltf") && run.stderr.contains(expected), "{}", run.stderr);
    assert!(!dir.path().join("red.png").exists());
    for command in ["bench", "compare", "view"] {
        let run =
            chiaro(&[command, "boxes.gltf", "--variant", "Red", "--width", "32", "--height", "32"], &[], dir.path());
        assert_eq!(run.code, 1, "{command}: {}", run.stderr);
        assert!(run.stderr.contains(expected), "{command}: {}", run.stderr);
    }
    let run = chiaro(
        &["bench", "boxes.gltf", "--variant", "Blue", "--width", "32", "--height", "32", "--frames", "2"],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "bench --variant Blue: {}", run.stderr);
    // The demo scene has no variants at all.
    let run =
        chiaro(&["render", "--variant", "Blue", "--width", "32", "--height", "32", "-o", "demo.png"], &[], dir.path());
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("has no KHR_materials_variants variants"), "{}", run.stderr);
}

#[test]
fn a_jobs_variant_key_picks_its_materials_and_a_bad_one_fails_that_job() {
    let dir = tempfile::tempdir().unwrap();
    variant_scene(dir.path());
    let jobs = [
        json!({ "id": "plain", "scene": "boxes.gltf", "width": 64, "height": 64 }),
        json!({ "id": "blue", "scene": "boxes.gltf", "variant": "Blue", "width": 64, "height": 64 }),
        json!({ "id": "green", "scene": "boxes.gltf", "settings": { "scene": { "variant": "Green" } }, "width": 64, "height": 64 }),
        json!({ "id": "red", "scene": "boxes.gltf", "variant": "Red", "width": 64, "height": 64 }),
    ];
    let text: String = jobs.iter().map(|j| format!("{j}\n")).collect();
    std::fs::write(dir.path().join("jobs.jsonl"), text).unwrap();
    let run = chiaro(&["batch", "jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 1, "one job fails: {}", run.stderr);
    let out = dir.path().join("out");
    let [r, g, b] = mean_rgb(&out.join("plain/rgb.png"));
    assert!(r > g && r > b, "plain: {r} {g} {b}");
    let [r, g, b] = mean_rgb(&out.join("blue/rgb.png"));
    assert!(b > r && b > g, "blue: {r} {g} {b}");
    let [r, g, b] = mean_rgb(&out.join("green/rgb.png"));
    assert!(g > r && g > b, "green: {r} {g} {b}");
    let report = std::fs::read_to_string(out.join("red.error.json")).unwrap();
    assert!(report.contains("variant: no material variant 'Red'; the scene has: Blue, Green"), "{report}");
    // The job renders what `chiaro render --variant` renders.
    let run = render(dir.path(), "blue.png", &["--variant", "Blue"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(image::open(out.join("blue/rgb.png")).unwrap(), image::open(dir.path().join("blue.png")).unwrap());
}
