//! `chiaro bake` and the bake flags of render as a user meets them: the bake lands beside
//! the scene and is used, a stale bake is ignored with a warning that says why, and bad
//! input gets a one-line error naming the file or flag.

mod common;

use common::*;
use std::path::Path;

/// ShadowsSpot copied into `dir`, its light made baked.
fn baked_spot_scene(dir: &Path) {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/ShadowsSpot/glTF");
    std::fs::copy(source.join("shadows-spot.bin"), dir.join("shadows-spot.bin")).unwrap();
    let text = std::fs::read_to_string(source.join("shadows-spot.gltf")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    for light in doc["extensions"]["KHR_lights_punctual"]["lights"].as_array_mut().unwrap() {
        light["extras"] = serde_json::json!({ "mode": "baked" });
    }
    std::fs::write(dir.join("shadows-spot.gltf"), doc.to_string()).unwrap();
}

const QUICK: [&str; 8] = ["--samples", "4", "--bounces", "1", "--texels-per-metre", "4", "--probe-spacing", "4"];

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

#[test]
fn a_bake_lands_beside_the_scene_and_lights_the_render() {
    let dir = tempfile::tempdir().unwrap();
    baked_spot_scene(dir.path());
    let mut args = vec!["bake", "shadows-spot.gltf"];
    args.extend(QUICK);
    let run = chiaro(&args, &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    // Not a terminal: plain progress lines, and a summary.
    assert!(run.stderr.contains("chiaro: bake: lightmap rows"), "{}", run.stderr);
    assert!(run.stderr.contains("M rays/s"), "{}", run.stderr);
    // The summary adds the estimated error; progress lines give whole rays per second.
    assert!(run.stderr.contains("estimated error") && run.stderr.contains("before denoising"), "{}", run.stderr);
    let rate = run.stderr.lines().find(|l| l.contains("lightmap rows") && l.ends_with(" rays/s")).unwrap();
    let figure = rate.rsplit(", ").next().unwrap().trim_end_matches(" rays/s");
    assert!(figure.parse::<u64>().is_ok(), "{rate}");
    assert_eq!(names(dir.path()), vec!["shadows-spot.bake", "shadows-spot.bin", "shadows-spot.gltf"]);
    let bake = dir.path().join("shadows-spot.bake");
    assert_eq!(names(&bake), vec!["lightmap-0.exr", "lightmap-uvs.bin", "manifest.json", "probes.bin"]);
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(bake.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["format_version"], 1);
    assert_eq!(manifest["settings"]["samples"], 4);
    assert_eq!(manifest["settings"]["texels_per_metre"], 4.0);
    assert_eq!(manifest["settings"]["denoise"], true);
    assert_eq!(manifest["settings"]["quality"], "default");
    assert_eq!(manifest["settings"]["probe_samples"], 4096, "the default quality's count, written out");
    assert!(manifest["scene_hash"].as_str().unwrap().starts_with("blake3:"));

    let render = |extra: &[&str]| {
        let mut args = vec!["render", "shadows-spot.gltf", "-o", "out.png", "--width", "48", "--height", "48"];
        args.extend(extra);
        chiaro(&args, &[], dir.path())
    };
    let run = render(&["--aov", "lightmap"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("0 point/spot lights shaded"), "the baked spot is not realtime: {}", run.stderr);
    let channels = read_exr_channels(&dir.path().join("out.lightmap.exr"));
    let red = &channels.iter().find(|(name, _)| name == "R").unwrap().1;
    assert!(red.iter().any(|&v| v > 0.0), "some pixel reads baked light");

    let run = render(&["--no-bake"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("1 point/spot lights shaded"), "{}", run.stderr);

    // The buffer changes: the bake is for another scene now.
    let bin = dir.path().join("shadows-spot.bin");
    let mut bytes = std::fs::read(&bin).unwrap();
    bytes[10] ^= 1;
    std::fs::write(&bin, &bytes).unwrap();
    let run = render(&[]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("ignoring the bake"), "{}", run.stderr);
    assert!(run.stderr.contains("another version of the scene"), "{}", run.stderr);
    assert!(run.stderr.contains("1 point/spot lights shaded"), "baked lights fall back to realtime: {}", run.stderr);

    // Baked again into a directory named on the command line, then used with --bake.
    let mut args = vec!["bake", "shadows-spot.gltf", "--output", "elsewhere.bake"];
    args.extend(QUICK);
    assert_eq!(chiaro(&args, &[], dir.path()).code, 0);
    let run = render(&["--bake", "elsewhere.bake"]);
    assert!(run.stderr.contains("0 point/spot lights shaded"), "{}", run.stderr);

    // Too many probes for the scene's bounds: refused before any work, nothing written.
    let run =
        chiaro(&["bake", "shadows-spot.gltf", "--output", "fine.bake", "--probe-spacing", "0.05"], &[], dir.path());
    assert_ne!(run.code, 0);
    let line = error_lines(&run)[0];
    assert!(line.contains("bake.probe_spacing") && line.contains("probes"), "{line}");
    assert!(!dir.path().join("fine.bake").exists());
}

#[test]
fn quality_picks_the_sample_counts_not_given_and_denoising_can_be_turned_off() {
    let dir = tempfile::tempdir().unwrap();
    baked_spot_scene(dir.path());
    let manifest_of = |bake: &str| -> serde_json::Value {
        let text = std::fs::read_to_string(dir.path().join(bake).join("manifest.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    };
    let quick = ["--bounces", "1", "--texels-per-metre", "4", "--probe-spacing", "4"];
    let mut args = vec!["bake", "shadows-spot.gltf", "-o", "draft.bake", "--quality", "draft", "--no-denoise"];
    args.extend(quick);
    let run = chiaro(&args, &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("(not denoised)"), "{}", run.stderr);
    let m = manifest_of("draft.bake");
    assert_eq!((m["settings"]["samples"].as_u64(), m["settings"]["probe_samples"].as_u64()), (Some(48), Some(1024)));
    assert_eq!(m["settings"]["denoise"], false);
    assert_eq!(m["settings"]["quality"], "draft");

    // An explicit count wins over the quality's; the quality still picks the other.
    let settings = "[bake]\nquality = \"high\"\nsamples = 8\n";
    std::fs::write(dir.path().join("high.toml"), settings).unwrap();
    let mut args = vec!["bake", "shadows-spot.gltf", "-o", "high.bake", "--settings", "high.toml"];
    args.extend(quick);
    let run = chiaro(&args, &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let m = manifest_of("high.bake");
    assert_eq!((m["settings"]["samples"].as_u64(), m["settings"]["probe_samples"].as_u64()), (Some(8), Some(16384)));
    assert_eq!(m["settings"]["denoise"], true);

    // Bad qualities are named, on the command line and in settings.
    let run = chiaro(&["bake", "shadows-spot.gltf", "--quality", "superb"], &[], dir.path());
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("superb") && run.stderr.contains("draft"), "{}", run.stderr);
    std::fs::write(dir.path().join("bad.toml"), "[bake]\nquality = \"superb\"\n").unwrap();
    let run = chiaro(&["bake", "shadows-spot.gltf", "--settings", "bad.toml"], &[], dir.path());
    assert_ne!(run.code, 0);
    let line = error_lines(&run)[0];
    assert!(line.contains("bad.toml") && line.contains("superb"), "{line}");
}

#[test]
fn bad_bake_input_gets_one_line_naming_it() {
    let triangle = good_triangle();
    let files: &[(&str, &[u8])] = &[("scene.gltf", triangle.as_bytes())];
    expect_failure(&[], &["bake", "nowhere.gltf"], &[], &["nowhere.gltf", "cannot read"]);
    expect_failure(
        files,
        &["bake", "scene.gltf", "--samples", "0"],
        &[],
        &["--samples", "bake.samples", "out of range"],
    );
    expect_failure(
        files,
        &["bake", "scene.gltf", "--texels-per-metre", "1e9"],
        &[],
        &["--texels-per-metre", "bake.texels_per_metre"],
    );
    expect_failure(files, &["bake", "scene.gltf", "--output", "scene.gltf"], &[], &["scene.gltf", "input"]);
    expect_failure(files, &["render", "scene.gltf", "--bake", "missing.bake"], &[], &["missing.bake", "not a bake"]);
    expect_usage_error(&["render", "scene.gltf", "--bake", "a", "--no-bake"], &["--no-bake"]);

    // A folder that is not a bake is never replaced, even with a manifest.json of its
    // own, nor the folder holding the scene.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.gltf"), &triangle).unwrap();
    std::fs::create_dir(dir.path().join("photos")).unwrap();
    std::fs::write(dir.path().join("photos/holiday.jpg"), b"precious").unwrap();
    std::fs::write(dir.path().join("photos/manifest.json"), br#"{"name": "a web app"}"#).unwrap();
    let run = chiaro(&["bake", "scene.gltf", "--output", "photos"], &[], dir.path());
    assert_ne!(run.code, 0);
    assert!(error_lines(&run)[0].contains("not a bake directory"), "{}", run.stderr);
    assert_eq!(std::fs::read(dir.path().join("photos/holiday.jpg")).unwrap(), b"precious");
    let run = chiaro(&["bake", "scene.gltf", "--output", "."], &[], dir.path());
    assert_ne!(run.code, 0);
    assert!(error_lines(&run)[0].contains("an input of this command"), "{}", run.stderr);
    assert!(dir.path().join("scene.gltf").exists());
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_bake_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    baked_spot_scene(dir.path());
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .args(["bake", "shadows-spot.gltf", "--samples", "65536", "--texels-per-metre", "16"])
        .current_dir(dir.path())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once the bake is under way.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("interrupted; nothing was written"), "{stderr}");
    assert_eq!(names(dir.path()), vec!["shadows-spot.bin", "shadows-spot.gltf"]);
}
