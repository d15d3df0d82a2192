//! The command line as a user meets it: good renders write what they promise, and every
//! kind of bad input gets a one-line error naming the file and the problem, a non-zero
//! exit, no panic, and no half-written output.

mod common;

use common::*;

#[test]
fn missing_file() {
    expect_failure(&[], &["render", "nowhere.gltf", "-o", "out.png"], &[], &["nowhere.gltf", "cannot read"]);
}

#[test]
fn not_gltf() {
    expect_failure(
        &[("notes.gltf", b"these are not the droids")],
        &["render", "notes.gltf", "-o", "out.png"],
        &[],
        &["notes.gltf", "not a valid glTF"],
    );
}

#[test]
fn broken_json() {
    expect_failure(
        &[("broken.gltf", br#"{"asset": {"version": "2.0"}, "nodes": [ "#)],
        &["render", "broken.gltf", "-o", "out.png"],
        &[],
        &["broken.gltf"],
    );
}

#[test]
fn missing_buffer() {
    let gltf = triangle_gltf(r#"[{"mesh": 0}]"#, "missing.bin", 36, 0);
    expect_failure(
        &[("scene.gltf", gltf.as_bytes())],
        &["render", "scene.gltf", "-o", "out.png"],
        &[],
        &["scene.gltf", "missing.bin"],
    );
}

#[test]
fn short_buffer() {
    let gltf = triangle_gltf(r#"[{"mesh": 0}]"#, TRIANGLE_BUFFER, 400, 0);
    expect_failure(
        &[("short.gltf", gltf.as_bytes())],
        &["render", "short.gltf", "-o", "out.png"],
        &[],
        &["short.gltf", "buffer"],
    );
}

#[test]
fn accessor_index_out_of_range() {
    let gltf = triangle_gltf(r#"[{"mesh": 0}]"#, TRIANGLE_BUFFER, 36, 7);
    expect_failure(
        &[("accessor.gltf", gltf.as_bytes())],
        &["render", "accessor.gltf", "-o", "out.png"],
        &[],
        &["accessor.gltf"],
    );
}

#[test]
fn unsupported_image_format() {
    let scene = textured_scene("texture.gif");
    expect_failure(
        &[("scene.gltf", &scene[0].1), ("texture.gif", b"GIF89a\x01\x00\x01\x00\x00\x00\x00;")],
        &["render", "scene.gltf", "-o", "out.png"],
        &[],
        &["scene.gltf", "image 0 (texture.gif): unsupported image format"],
    );
}

#[test]
fn non_finite_transform() {
    let nodes = r#"[{"children": [1], "scale": [1e38, 1e38, 1e38]}, {"mesh": 0, "scale": [1e38, 1e38, 1e38]}]"#;
    let gltf = triangle_gltf(nodes, TRIANGLE_BUFFER, 36, 0);
    expect_failure(
        &[("huge.gltf", gltf.as_bytes())],
        &["render", "huge.gltf", "-o", "out.png"],
        &[],
        &["huge.gltf", "finite"],
    );
}

#[test]
fn unsupported_required_extension() {
    let gltf = good_triangle().replacen(
        '{',
        r#"{"extensionsRequired": ["EXT_lights_ies"], "extensionsUsed": ["EXT_lights_ies"],"#,
        1,
    );
    expect_failure(
        &[("ies.gltf", gltf.as_bytes())],
        &["render", "ies.gltf", "-o", "out.png"],
        &[],
        &["ies.gltf", "EXT_lights_ies"],
    );
}

#[test]
fn zero_size_output() {
    expect_failure(&[], &["render", "--width", "0", "-o", "out.png"], &[], &["0x720", "at least 1"]);
}

#[test]
fn absurd_output_size() {
    expect_failure(&[], &["render", "--width", "4000000", "--height", "4", "-o", "out.png"], &[], &["4000000x4"]);
}

#[test]
fn unsupported_output_format() {
    expect_failure(&[], &["render", "-o", "out.jpg"], &[], &["out.jpg", ".jpg"]);
}

#[test]
fn unknown_settings_key() {
    expect_failure(
        &[("settings.toml", b"[render]\nexposure = 3\n")],
        &["render", "--settings", "settings.toml", "-o", "out.png"],
        &[],
        &["settings.toml", "exposure"],
    );
}

#[test]
fn out_of_range_setting() {
    expect_failure(
        &[("settings.toml", b"[lights]\nmax_other_lights = 5000\n")],
        &["render", "--settings", "settings.toml", "-o", "out.png"],
        &[],
        &["settings.toml", "lights.max_other_lights"],
    );
}

#[test]
fn bad_environments_name_the_file_or_flag_and_write_nothing() {
    let missing = expect_failure(
        &[],
        &["render", "--width", "32", "--height", "32", "--environment", "missing.hdr", "-o", "out.png"],
        &[],
        &["missing.hdr", "cannot read environment image"],
    );
    assert_eq!(missing, 1);
    // Twice as tall as wide: not equirectangular (a 2 x 4 Radiance file, flat RGBE).
    let mut tall = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 2\n".to_vec();
    tall.extend([128u8, 128, 128, 129].repeat(8));
    let code = expect_failure(
        &[("tall.hdr", &tall)],
        &["render", "--width", "32", "--height", "32", "--environment", "tall.hdr", "-o", "out.png"],
        &[],
        &["tall.hdr", "2 x 4 texels is not equirectangular"],
    );
    assert_eq!(code, 1);
    let code = expect_failure(
        &[],
        &["render", "--environment", "studio.png", "-o", "out.png"],
        &[],
        &["--environment", "\"studio.png\" is not none, ambient, neutral, sky"],
    );
    assert_eq!(code, 1);
    let code = expect_failure(
        &[("settings.toml", b"[environment]\nsource = \"neutral\"\nintensity = -2\n")],
        &["render", "--settings", "settings.toml", "-o", "out.png"],
        &[],
        &["settings.toml", "environment.intensity (line 3): -2 is out of range"],
    );
    assert_eq!(code, 1);
}

#[test]
fn unknown_camera() {
    expect_failure(&[], &["render", "--camera", "nosuch", "-o", "out.png"], &[], &["nosuch", "demo camera"]);
}

#[test]
fn no_gpu_adapter() {
    expect_failure(
        &[],
        &["render", "-o", "out.png"],
        &[("VK_ICD_FILENAMES", "/nonexistent/icd.json"), ("VK_DRIVER_FILES", "/nonexistent/icd.json")],
        &["no GPU adapter", "mesa-vulkan-drivers"],
    );
}

#[test]
fn demo_render_writes_png_and_aovs() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(
        &[
            "render", "--width", "96", "--height", "64", "-o", "demo.png", "--aov", "position", "--aov", "normal",
            "--aov", "depth",
        ],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(dir.path().join("demo.png")).unwrap().permissions().mode();
        assert_eq!(mode & 0o044, 0o044, "outputs are readable by others, not private temp files: {mode:o}");
    }
    let png = image::open(dir.path().join("demo.png")).unwrap();
    assert_eq!((png.width(), png.height()), (96, 64));
    let position = read_exr_channels(&dir.path().join("demo.position.exr"));
    let normal = read_exr_channels(&dir.path().join("demo.normal.exr"));
    let depth = read_exr_channels(&dir.path().join("demo.depth.exr"));
    assert_eq!(position.len(), 3);
    assert_eq!(normal.len(), 3);
    assert_eq!(depth.len(), 1, "depth has one channel");
    let z = &depth[0].1;
    assert_eq!(z.len(), 96 * 64);
    // The demo camera sees sky at the top and the floor at the bottom.
    assert!(!z[0].is_finite(), "top-left is sky");
    assert!(z[z.len() - 1].is_finite() && z[z.len() - 1] > 0.0, "bottom row is floor");
    let sky = position[0].1.iter().filter(|v| !v.is_finite()).count();
    assert!(sky > 0 && sky < 96 * 64);
    // Normals of covered pixels are unit length.
    for (i, depth) in z.iter().enumerate() {
        if depth.is_finite() {
            let n = [normal[0].1[i], normal[1].1[i], normal[2].1[i]];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-3, "normal length {len}");
        }
    }
}

#[test]
fn the_same_render_twice_is_the_same_bytes() {
    // Outputs are content-hashed by job runners (meta.json, datasets): two renders of the
    // same scene and settings must write identical files, image and AOVs, PNG and EXR.
    let render = |dir: &std::path::Path, output: &str| {
        let mut args = vec!["render", "--width", "64", "--height", "48", "-o", output];
        for aov in ["position", "normal", "depth", "shadow", "instance", "label"] {
            args.extend(["--aov", aov]);
        }
        let run = chiaro(&args, &[], dir);
        assert_eq!(run.code, 0, "{}", run.stderr);
    };
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    for output in ["demo.png", "demo.exr"] {
        render(a.path(), output);
        render(b.path(), output);
    }
    let mut names: Vec<String> =
        std::fs::read_dir(a.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert!(names.len() >= 8 && names.iter().any(|n| n.ends_with(".png")), "{names:?}");
    for name in &names {
        let (first, second) =
            (std::fs::read(a.path().join(name)).unwrap(), std::fs::read(b.path().join(name)).unwrap());
        assert!(first == second, "{name}: {} and {} bytes differ", first.len(), second.len());
    }
}

#[test]
fn exr_output_is_linear_radiance() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(&["render", "--width", "64", "--height", "48", "-o", "demo.exr"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let channels = read_exr_channels(&dir.path().join("demo.exr"));
    assert_eq!(channels.len(), 3);
    assert!(channels.iter().all(|(_, v)| v.iter().all(|x| x.is_finite() && *x >= 0.0)));
    assert!(channels[0].1.iter().any(|&x| x > 0.05), "some pixels are lit");
}

#[test]
fn info_lists_lights_and_cameras() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.gltf"), good_triangle()).unwrap();
    let run = chiaro(&["info", "tri.gltf"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("1 triangles drawn"), "{}", run.stdout);
    assert!(run.stdout.contains("lights: 0"), "{}", run.stdout);
    assert!(run.stdout.contains("bounds: min"), "{}", run.stdout);
}

#[test]
fn info_lists_compression_and_instancing() {
    let assets = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets"));
    for (file, line) in [
        ("ShadowsSpot/encoded/shadows-spot-draco-edgebreaker.glb", "KHR_draco_mesh_compression: 5 primitives decoded"),
        ("ShadowsSpot/encoded/shadows-spot-meshopt.glb", "EXT_meshopt_compression: 19 buffer views decoded"),
        ("InstancedBoxes/boxes-instanced.glb", "EXT_mesh_gpu_instancing: node 4 '': 64 copies, instance ids 5..=68"),
    ] {
        let run = chiaro(&["info", &assets.join(file).to_string_lossy()], &[], assets);
        assert_eq!(run.code, 0, "{}", run.stderr);
        assert!(run.stdout.contains(&format!("extensions read:\n  {line}\n")), "{file}: {}", run.stdout);
    }
}

#[test]
fn triangle_without_camera_is_framed_and_rendered() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tri.gltf"), good_triangle()).unwrap();
    let run = chiaro(
        &["render", "tri.gltf", "--width", "32", "--height", "32", "-o", "tri.png", "--aov", "depth"],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let png = image::open(dir.path().join("tri.png")).unwrap();
    assert_eq!((png.width(), png.height()), (32, 32));
    // The framing camera puts the triangle in the middle of the picture, neither lost in
    // a corner nor filling it.
    let depth = &read_exr_channels(&dir.path().join("tri.depth.exr"))[0].1;
    let covered = depth.iter().filter(|d| d.is_finite()).count();
    assert!(depth[16 * 32 + 16].is_finite() || depth[15 * 32 + 15].is_finite(), "centre covered");
    assert!(covered > 32 * 32 / 10 && covered < 32 * 32, "triangle covers {covered} pixels");
}

#[test]
fn bench_prints_a_table() {
    let dir = tempfile::tempdir().unwrap();
    // Without the shadow cache every frame draws its tiles, so the shadow pass has a row.
    std::fs::write(dir.path().join("uncached.toml"), "[shadows]\ncache = false\n").unwrap();
    let run = chiaro(
        &[
            "bench",
            "--width",
            "64",
            "--height",
            "64",
            "--frames",
            "3",
            "--warmup",
            "1",
            "--demo-lights",
            "4",
            "--settings",
            "uncached.toml",
        ],
        &[],
        dir.path(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("4 point/spot lights shaded"), "{}", run.stdout);
    // Each row's median is a positive time.
    for row in [
        "frame (back to back)",
        "gpu frame (timestamps)",
        "gpu shadows pass",
        "gpu depth prepass pass",
        "gpu forward pass",
        "gpu tonemap pass",
    ] {
        let line = run
            .stdout
            .lines()
            .find(|l| l.trim_start().starts_with(row))
            .unwrap_or_else(|| panic!("no '{row}': {}", run.stdout));
        let median: f64 = line[row.len() + 2..].split_whitespace().next().unwrap().parse().unwrap();
        assert!(median > 0.0, "{line}");
    }
    assert!(run.stdout.contains("cpu prepare"), "{}", run.stdout);
}

#[test]
fn bench_json_is_one_object_with_the_named_keys() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["bench", "--width", "64", "--height", "48", "--frames", "3", "--warmup", "1", "--demo-lights", "6"];
    let run = chiaro(&[&args[..], &["--json", "--msaa", "4"]].concat(), &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: serde_json::Value =
        serde_json::from_str(run.stdout.trim()).unwrap_or_else(|e| panic!("{e}: {}", run.stdout));
    assert_eq!((report["width"].as_u64(), report["height"].as_u64()), (Some(64), Some(48)));
    assert_eq!(report["msaa"].as_u64(), Some(4));
    // The demo's sun and its six point and spot lights.
    assert_eq!(report["lights_shaded"].as_u64(), Some(7));
    for key in ["frame_ms", "gpu_ms"] {
        assert!(report[key].as_f64().is_some_and(|ms| ms > 0.0), "{key}: {report}");
    }
    let passes = report["passes"].as_object().expect("passes");
    for pass in ["depth prepass", "forward", "tonemap"] {
        assert!(passes[pass].as_f64().is_some_and(|ms| ms > 0.0), "{pass}: {report}");
    }
    // A still scene keeps its shadow tiles: after the warm-up frame no tile is drawn, and
    // the frame graph runs no shadow pass.
    let tiles = report["shadow_tiles_rendered"].as_array().expect("tiles per frame");
    assert!(tiles.iter().all(|t| t.as_u64() == Some(0)), "{report}");
    assert!(!passes.contains_key("shadows"), "{report}");
    // Shadow texels per pixel over the shaded pixels: a 64x48 view of the demo samples
    // its maps several texels a pixel, in order.
    let ratios: Vec<f64> = ["shadow_texel_ratio_p10", "shadow_texel_ratio_p50", "shadow_texel_ratio_p90"]
        .iter()
        .map(|key| report[key].as_f64().unwrap_or_else(|| panic!("{key}: {report}")))
        .collect();
    assert!(ratios[0] > 0.0 && ratios[0] <= ratios[1] && ratios[1] <= ratios[2], "{ratios:?}");
    // The atlases' memory stands in for a pool; the atlas technique has no pages.
    assert_eq!(report["shadow_technique"].as_str(), Some("atlas"));
    assert_eq!(report["shadow_pages_drawn"].as_u64(), Some(0), "{report}");
    assert!(report["shadow_pages_resident"].is_null(), "{report}");
    assert!(report["shadow_pool_mb"].as_f64().is_some_and(|mb| mb > 0.0), "{report}");
    // Virtual maps: the warm-up frame drew the pages; the still timed frames draw none
    // and keep them resident in the pool.
    std::fs::write(dir.path().join("virtual.toml"), "[shadows]\ntechnique = \"virtual\"\nvirtual_pool_mb = 32\n")
        .unwrap();
    let run = chiaro(&[&args[..], &["--json", "--settings", "virtual.toml"]].concat(), &[], dir.path());
    let report: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(report["shadow_technique"].as_str(), Some("virtual"), "{report}");
    assert_eq!(report["shadow_pages_drawn"].as_u64(), Some(0), "{report}");
    assert!(report["shadow_pages_resident"].as_u64().is_some_and(|n| n > 0), "{report}");
    assert!(report["shadow_pool_mb"].as_f64().is_some_and(|mb| mb > 28.0 && mb <= 32.0), "{report}");
    std::fs::write(dir.path().join("uncached.toml"), "[shadows]\ncache = false\n").unwrap();
    let run = chiaro(&[&args[..], &["--json", "--settings", "uncached.toml"]].concat(), &[], dir.path());
    let report: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert!(report["passes"]["shadows"].as_f64().is_some_and(|ms| ms > 0.0), "uncached: {report}");
    // The deferred path has one sample per pixel, and says so.
    let run = chiaro(&[&args[..], &["--json", "--path", "deferred"]].concat(), &[], dir.path());
    let report: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(report["msaa"].as_u64(), Some(1));
    assert!(report["passes"]["gbuffer"].as_f64().is_some(), "{report}");
}

#[test]
fn an_msaa_count_the_device_lacks_names_its_source() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("eight.toml"), "[render]\nmsaa = 8\n").unwrap();
    let run = chiaro(
        &["render", "--settings", "eight.toml", "--width", "32", "--height", "32", "-o", "out.png"],
        &[],
        dir.path(),
    );
    if run.code == 0 {
        // A device with 8 samples renders them.
        assert!(dir.path().join("out.png").exists());
    } else {
        // lavapipe offers 1 and 4: the error names the file, the key and what the device has.
        for w in ["eight.toml", "render.msaa = 8", "4"] {
            assert!(run.stderr.contains(w), "no '{w}' in: {}", run.stderr);
        }
        assert!(!dir.path().join("out.png").exists());
    }
}

#[test]
fn msaa_and_culling_flags_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    for (args, words) in [
        (&["render", "--msaa", "3", "-o", "out.png"][..], &["--msaa", "render.msaa", "3"][..]),
        (&["render", "--culling", "none", "--demo-lights", "100", "-o", "out.png"][..], &[][..]),
    ] {
        let run = chiaro(args, &[], dir.path());
        if words.is_empty() {
            // 100 lights without culling: the 64 most important are shaded, with a warning.
            assert_eq!(run.code, 0, "{}", run.stderr);
            assert!(run.stderr.contains("over the limit of 64"), "{}", run.stderr);
        } else {
            assert_ne!(run.code, 0);
            for w in words {
                assert!(run.stderr.contains(w), "no '{w}' in: {}", run.stderr);
            }
            assert!(!dir.path().join("out.png").exists());
        }
    }
}

/// Share of vertical pixel triples (all three surfaces) whose view depth is affine: the
/// middle one halfway between its neighbours within `tolerance` metres.
fn affine_depth_share(depth: &[f32], width: usize, tolerance: f32) -> f64 {
    let (mut triples, mut affine) = (0usize, 0usize);
    for y in 1..depth.len() / width - 1 {
        for x in 0..width {
            let [a, b, c] = [y - 1, y, y + 1].map(|row| depth[row * width + x]);
            if a.is_finite() && b.is_finite() && c.is_finite() {
                triples += 1;
                affine += ((a + c - 2.0 * b).abs() <= tolerance) as usize;
            }
        }
    }
    affine as f64 / triples.max(1) as f64
}

#[test]
fn orthographic_cameras_render_compare_and_bench() {
    let assets = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets"));
    let file = assets.join("ShadowsDirectional/orthographic/shadows-directional-orthographic.gltf");
    let file = file.to_string_lossy();
    let dir = tempfile::tempdir().unwrap();
    let info = chiaro(&["info", &file], &[], dir.path());
    assert!(
        info.stdout.contains("camera 0 'Plan' (node 3): orthographic, ymag 5.625 m, near 0.1, far 100"),
        "{}",
        info.stdout
    );
    let mut shares = Vec::new();
    for camera in ["Plan", "Perspective"] {
        let out = format!("{camera}.png");
        let args =
            ["render", &file, "--camera", camera, "--width", "160", "--height", "90", "-o", &out, "--aov", "depth"];
        let run = chiaro(&args, &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
        let depth = &read_exr_channels(&dir.path().join(format!("{camera}.depth.exr")))[0].1;
        shares.push(affine_depth_share(depth, 160, 1e-3));
    }
    println!("affine depth triples: orthographic {:.3}, perspective {:.3}", shares[0], shares[1]);
    // Parallel rays see a plane's depth change evenly down the image; a pinhole does not.
    // Measured: 0.82 orthographic (the sphere, the cone and the edges make the rest), 0.06
    // perspective.
    assert!(shares[0] > 0.7 && shares[1] < 0.3, "{shares:?}");
    let compare = chiaro(&["compare", &file, "--width", "128", "--height", "72"], &[], dir.path());
    assert_eq!(compare.code, 0, "{}", compare.stderr);
    assert!(compare.stdout.contains("Sun.001") && compare.stdout.contains("directional"), "{}", compare.stdout);
    let bench = chiaro(&["bench", &file, "--width", "64", "--height", "36", "--frames", "2"], &[], dir.path());
    assert_eq!(bench.code, 0, "{}", bench.stderr);
}

#[test]
fn tone_mapping_flag_and_setting_pick_the_display_curve() {
    let dir = tempfile::tempdir().unwrap();
    let render = |extra: &[&str], out: &str| {
        let mut args = vec!["render", "--width", "48", "--height", "32", "--exposure", "-2", "-o", out];
        args.extend_from_slice(extra);
        let run = chiaro(&args, &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
        image::open(dir.path().join(out)).unwrap().to_rgb8().into_raw()
    };
    let neutral = render(&[], "neutral.png");
    let aces = render(&["--tone-mapping", "aces"], "aces.png");
    std::fs::write(dir.path().join("agx.toml"), "[render]\ntone_mapping = \"agx\"\n").unwrap();
    let agx = render(&["--settings", "agx.toml"], "agx.png");
    let linear = render(&["--settings", "agx.toml", "--tone-mapping", "linear"], "linear.png");
    let differ = |a: &[u8], b: &[u8]| a.iter().zip(b).filter(|(x, y)| x.abs_diff(**y) > 2).count();
    for (name, image) in [("aces", &aces), ("agx", &agx), ("linear", &linear)] {
        assert!(differ(&neutral, image) > 300, "{name} looks like pbr-neutral");
    }
    assert!(differ(&agx, &linear) > 300, "the flag overrides the settings file");
    expect_usage_error(&["render", "--tone-mapping", "filmic"], &["--tone-mapping", "filmic"]);
    let run = chiaro(&["render", "--tone-mapping", "filmic"], &[], dir.path());
    assert!(run.stderr.contains("[possible values: pbr-neutral, aces, agx, linear]"), "{}", run.stderr);
    std::fs::write(dir.path().join("bad.toml"), "[render]\ntone_mapping = \"filmic\"\n").unwrap();
    let run = chiaro(&["render", "--settings", "bad.toml", "-o", "bad.png"], &[], dir.path());
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("tone_mapping") && run.stderr.contains("filmic"), "{}", run.stderr);
}

#[test]
fn compare_edge_band_narrows_the_pixels_left_out_beside_traced_edges() {
    let dir = tempfile::tempdir().unwrap();
    // The sun's row: `node light type compared ...`.
    let sun_compared = |band: &str| {
        let args = ["compare", "--width", "96", "--height", "64", "--demo-lights", "0", "--edge-band", band];
        let run = chiaro(&args, &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
        assert!(run.stdout.contains(&format!("edge band {band} px")), "{}", run.stdout);
        let row = run.stdout.lines().find(|l| l.contains("directional")).expect("the sun's row").to_string();
        row.split_whitespace().nth(3).and_then(|n| n.parse::<usize>().ok()).expect("a pixel count")
    };
    let (default, one, none) = (sun_compared("3"), sun_compared("1"), sun_compared("0"));
    println!("sun pixels compared at edge bands 3, 1, 0: {default}, {one}, {none}");
    assert!(default < one && one < none, "{default}, {one}, {none}");
}
