//! `chiaro batch` as a scheduler meets it: shards that split a list once, reruns that
//! touch nothing, a failed job that leaves a report while the rest finish, a killed batch
//! that leaves only whole jobs and resumes, shards from Slurm's and Kubernetes'
//! environment, and images equal to `chiaro render`'s.

mod common;

use common::*;
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

/// The scheduler variables a test must not inherit (the suite may itself run under one).
const SCHEDULER_VARS: [&str; 4] =
    ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_COUNT", "JOB_COMPLETION_INDEX"];
const SCENE: &str = "shadows-spot.gltf";

/// ShadowsSpot (a spot light, a camera named "Camera", animations) copied into `dir`.
fn spot_scene(dir: &Path) {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/ShadowsSpot/glTF");
    for file in [SCENE, "shadows-spot.bin"] {
        std::fs::copy(source.join(file), dir.join(file)).unwrap();
    }
}

fn write_jobs(dir: &Path, jobs: &[Value]) {
    let text: String = jobs.iter().map(|j| format!("{j}\n")).collect();
    std::fs::write(dir.join("jobs.jsonl"), text).unwrap();
}

/// `chiaro batch` in `dir` with `set` in its environment and no scheduler's variables.
fn batch(args: &[&str], set: &[(&str, &str)], dir: &Path) -> Run {
    let mut all = vec!["batch"];
    all.extend(args);
    let removed: Vec<&str> = SCHEDULER_VARS.iter().copied().filter(|v| !set.iter().any(|(k, _)| k == v)).collect();
    chiaro_env(&all, set, &removed, dir)
}

/// Twelve jobs with a mix of cameras, outputs and times.
fn twelve_jobs() -> Vec<Value> {
    (0..12)
        .map(|i| {
            let mut job = json!({"id": format!("job-{i:02}"), "scene": SCENE, "width": 64, "height": 64});
            match i % 4 {
                0 => {}
                1 => job["camera"] = json!("Camera"),
                2 => job["camera"] = json!({"eye": [6, 4, 6], "target": [0, 0, 0]}),
                _ => job["camera"] = json!(0),
            }
            job["outputs"] = match i % 3 {
                0 => json!(["rgb"]),
                1 => json!(["rgb", "depth", "instance"]),
                _ => json!(["shadow", "label", "normal"]),
            };
            if i % 5 == 4 {
                job["time"] = json!(0.5);
            }
            job
        })
        .collect()
}

/// The files a job's outputs name (the spot light is node 0's child: its node comes from
/// the scene, so the shadow file is matched by prefix).
fn expected_files(job: &Value) -> Vec<String> {
    let outputs: Vec<&str> =
        job["outputs"].as_array().map_or(vec!["rgb"], |a| a.iter().map(|v| v.as_str().unwrap()).collect());
    outputs
        .iter()
        .map(|o| match *o {
            "rgb" => "rgb.png".to_string(),
            "shadow" => "shadow.".to_string(),
            other => format!("{other}.exr"),
        })
        .collect()
}

/// Checks that `DIR/<id>` is whole: meta.json lists exactly the files beside it, and they
/// are the ones the job asked for.
fn check_whole(dir: &Path, job: &Value) {
    let id = job["id"].as_str().unwrap();
    let folder = dir.join(id);
    let meta: Value = serde_json::from_slice(&std::fs::read(folder.join("meta.json")).unwrap()).unwrap();
    assert_eq!(meta["job"], *job, "{id}: the job as given");
    let mut listed: Vec<String> =
        meta["files"].as_array().unwrap().iter().map(|f| f.as_str().unwrap().into()).collect();
    listed.sort();
    let mut present: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "meta.json")
        .collect();
    present.sort();
    assert_eq!(listed, present, "{id}: meta.json lists the folder's files");
    for wanted in expected_files(job) {
        assert!(present.iter().any(|p| p.starts_with(&wanted)), "{id}: no {wanted}* in {present:?}");
    }
    assert_eq!(present.len(), expected_files(job).len(), "{id}: one file per output (one light)");
}

/// Every file under `dir` with its modification time and bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, (SystemTime, Vec<u8>)> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let modified = std::fs::metadata(&path).unwrap().modified().unwrap();
                files.insert(path.clone(), (modified, std::fs::read(&path).unwrap()));
            }
        }
    }
    files
}

/// The names in `dir` that are not hidden: finished job folders and error reports.
fn visible(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect()
}

/// The ids a run's progress lines say it rendered.
fn done_ids(run: &Run) -> Vec<String> {
    run.stderr
        .lines()
        .filter(|l| l.starts_with("chiaro: [") && l.contains(" done in "))
        .map(|l| l.split_once("] ").unwrap().1.split_once(" done in").unwrap().0.to_string())
        .collect()
}

#[test]
fn three_shards_render_every_job_once_and_a_rerun_touches_nothing() {
    let dir = tempfile::tempdir().unwrap();
    spot_scene(dir.path());
    let jobs = twelve_jobs();
    write_jobs(dir.path(), &jobs);
    // Three processes at once, as a job array runs them.
    let children: Vec<_> = (0..3)
        .map(|i| {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_chiaro"));
            cmd.args(["batch", "jobs.jsonl", "--output", "out", "--shard", &format!("{i}/3")])
                .current_dir(dir.path())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped());
            for var in SCHEDULER_VARS {
                cmd.env_remove(var);
            }
            cmd.spawn().unwrap()
        })
        .collect();
    let mut rendered = Vec::new();
    for child in children {
        let output = child.wait_with_output().unwrap();
        let run = Run {
            code: output.status.code().unwrap_or(-1),
            stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
            stdout: String::new(),
        };
        assert_eq!(run.code, 0, "{}", run.stderr);
        assert_eq!(done_ids(&run).len(), 4, "{}", run.stderr);
        assert!(run.stderr.contains("chiaro: batch: 4 done, 0 skipped, 0 failed of 4 jobs (shard"), "{}", run.stderr);
        rendered.extend(done_ids(&run));
    }
    rendered.sort();
    let ids: Vec<String> = jobs.iter().map(|j| j["id"].as_str().unwrap().to_string()).collect();
    assert_eq!(rendered, ids, "every job rendered by exactly one shard");
    let out = dir.path().join("out");
    assert_eq!(visible(&out), ids.iter().cloned().collect::<BTreeSet<_>>());
    assert!(std::fs::read_dir(&out).unwrap().count() == 12, "no temporary folders stay behind");
    for job in &jobs {
        check_whole(&out, job);
    }
    let meta: Value = serde_json::from_slice(&std::fs::read(out.join("job-01/meta.json")).unwrap()).unwrap();
    let hash = meta["scene_hash"].as_str().unwrap();
    assert!(hash.len() == 64 && hash.bytes().all(|b| b.is_ascii_hexdigit()), "{hash}");
    let inputs: Vec<&str> = meta["inputs"].as_array().unwrap().iter().map(|i| i["path"].as_str().unwrap()).collect();
    assert!(inputs[0].ends_with(SCENE) && inputs[1].ends_with("shadows-spot.bin"), "{inputs:?}");
    assert!(Path::new(inputs[0]).is_absolute());
    assert_eq!(meta["chiaro_version"], env!("CARGO_PKG_VERSION"));
    assert!(!meta["device"]["name"].as_str().unwrap().is_empty());
    assert_eq!((meta["width"].clone(), meta["height"].clone(), meta["seed"].clone()), (json!(64), json!(64), json!(0)));
    assert!(meta["settings"].as_str().unwrap().contains("[render]"));
    let depth = read_exr_channels(&out.join("job-01/depth.exr"));
    assert_eq!((depth.len(), depth[0].1.len()), (1, 64 * 64), "depth is one channel of 64x64");
    assert!(depth[0].1.iter().any(|d| d.is_finite() && *d > 0.0));
    let png = image::open(out.join("job-00/rgb.png")).unwrap();
    assert_eq!((png.width(), png.height()), (64, 64));

    let before = snapshot(&out);
    let run = batch(&["jobs.jsonl", "--output", "out"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stderr.matches(" skipped\n").count(), 12, "{}", run.stderr);
    assert!(run.stderr.contains("chiaro: batch: 0 done, 12 skipped, 0 failed of 12 jobs"), "{}", run.stderr);
    assert!(before == snapshot(&out), "a rerun changes no file, not even its time");
}

#[test]
fn a_failed_job_leaves_its_report_and_the_others_finish() {
    let dir = tempfile::tempdir().unwrap();
    spot_scene(dir.path());
    let jobs = [
        json!({"id": "a", "scene": SCENE, "width": 32, "height": 32}),
        json!({"id": "lost", "scene": "missing.gltf", "width": 32, "height": 32}),
        json!({"id": "b", "scene": SCENE, "width": 32, "height": 32, "outputs": ["depth"]}),
    ];
    write_jobs(dir.path(), &jobs);
    let run = batch(&["jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 1, "one job failed: {}", run.stderr);
    assert!(run.stderr.contains("chiaro: [2/3] lost FAILED: jobs.jsonl:2: scene: "), "{}", run.stderr);
    let out = dir.path().join("out");
    assert_eq!(visible(&out), ["a", "b", "lost.error.json"].map(String::from).into_iter().collect());
    let report: Value = serde_json::from_slice(&std::fs::read(out.join("lost.error.json")).unwrap()).unwrap();
    assert_eq!(
        (report["id"].clone(), report["line"].clone(), report["job"].clone()),
        (json!("lost"), json!(2), jobs[1].clone())
    );
    let error = report["error"].as_str().unwrap();
    assert!(error.starts_with("jobs.jsonl:2: scene: ") && error.contains("missing.gltf"), "{error}");
    assert_eq!(report["chiaro_version"], env!("CARGO_PKG_VERSION"));

    // The scene appears: the rerun renders the job and removes its report.
    std::fs::copy(dir.path().join(SCENE), dir.path().join("missing.gltf")).unwrap();
    let run = batch(&["jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("0 failed"), "{}", run.stderr);
    assert_eq!(visible(&out), ["a", "b", "lost"].map(String::from).into_iter().collect());

    // A changed input renders its jobs again, replacing the stale folders.
    let mut text = std::fs::read_to_string(dir.path().join(SCENE)).unwrap();
    text.push(' ');
    std::fs::write(dir.path().join(SCENE), text).unwrap();
    let run = batch(&["jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(done_ids(&run), ["a", "b"], "{}", run.stderr);
    assert_eq!(visible(&out), ["a", "b", "lost"].map(String::from).into_iter().collect());
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 3, "stale folders are removed");
}

#[test]
fn mistakes_in_a_job_fail_it_and_mistakes_in_the_list_stop_the_batch() {
    let dir = tempfile::tempdir().unwrap();
    spot_scene(dir.path());
    write_jobs(
        dir.path(),
        &[
            json!({"id": "typo", "scene": SCENE, "cmera": "Camera"}),
            json!({"id": "camera", "scene": SCENE, "camera": "Nope", "width": 16, "height": 16}),
            json!({"id": "msaa", "scene": SCENE, "settings": {"render": {"msaa": 3}}}),
        ],
    );
    let run = batch(&["jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 3, "{}", run.stderr);
    let error = |id: &str| -> String {
        let report: Value =
            serde_json::from_slice(&std::fs::read(dir.path().join(format!("out/{id}.error.json"))).unwrap()).unwrap();
        report["error"].as_str().unwrap().to_string()
    };
    assert!(
        error("typo").starts_with("jobs.jsonl:1: unknown key 'cmera' (a job's keys: id, scene,"),
        "{}",
        error("typo")
    );
    assert!(error("camera").starts_with("jobs.jsonl:2: camera: no camera 'Nope' in the scene (cameras: 0: "));
    assert!(error("msaa").starts_with("jobs.jsonl:3: settings: render.msaa: "), "{}", error("msaa"));

    let fatal = |lines: &str, args: &[&str], env: &[(&str, &str)], needle: &str| {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("jobs.jsonl"), lines).unwrap();
        let mut all = vec!["jobs.jsonl", "-o", "out"];
        all.extend(args);
        let run = batch(&all, env, dir.path());
        assert_eq!(run.code, 101, "{}", run.stderr);
        let lines = error_lines(&run);
        assert_eq!(lines.len(), 1, "{}", run.stderr);
        assert!(lines[0].contains(needle), "'{}' lacks '{needle}'", lines[0]);
        assert!(!dir.path().join("out").join("a").exists(), "nothing rendered");
    };
    let a = r#"{"id": "a", "scene": "s.gltf"}"#;
    fatal(&format!("{a}\n\n{{\"id\": \"b\", \"scene\": }}\n"), &[], &[], "jobs.jsonl:3: not JSON");
    fatal(&format!("{a}\n{a}\n"), &[], &[], "jobs.jsonl:2: id 'a' is already the id of line 1");
    fatal(r#"{"id": "../up", "scene": "s.gltf"}"#, &[], &[], "jobs.jsonl:1: id \"../up\": holds '/'");
    fatal(a, &["--shard", "2/2"], &[], "--shard 2/2: shard 2 of 2 does not exist");
    fatal(a, &[], &[("JOB_COMPLETION_INDEX", "0")], "JOB_COMPLETION_INDEX is set: give the number of shards");
    fatal(a, &["--settings", "absent.toml"], &[], "absent.toml");
}

#[test]
fn the_scheduler_environment_picks_the_jobs_the_flag_picks() {
    let dir = tempfile::tempdir().unwrap();
    spot_scene(dir.path());
    let jobs: Vec<Value> =
        (0..7).map(|i| json!({"id": format!("j{i}"), "scene": SCENE, "width": 16, "height": 16})).collect();
    write_jobs(dir.path(), &jobs);
    let shard_of = |out: &str, args: &[&str], env: &[(&str, &str)]| -> BTreeSet<String> {
        let mut all = vec!["jobs.jsonl", "-o", out];
        all.extend(args);
        let run = batch(&all, env, dir.path());
        assert_eq!(run.code, 0, "{env:?}: {}", run.stderr);
        visible(&dir.path().join(out))
    };
    let flag = shard_of("flag", &["--shard", "1/3"], &[]);
    assert_eq!(flag, ["j1", "j4"].map(String::from).into_iter().collect());
    let slurm = shard_of("slurm", &[], &[("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_COUNT", "3")]);
    let from_one = shard_of(
        "slurm1",
        &[],
        &[("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_MIN", "1"), ("SLURM_ARRAY_TASK_COUNT", "3")],
    );
    let k8s = shard_of("k8s", &["--shards", "3"], &[("JOB_COMPLETION_INDEX", "1")]);
    assert_eq!((&slurm, &from_one, &k8s), (&flag, &flag, &flag));
}

#[test]
fn a_killed_batch_leaves_whole_jobs_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    spot_scene(dir.path());
    let jobs: Vec<Value> = (0..40)
        .map(|i| {
            json!({"id": format!("k{i:02}"), "scene": SCENE, "width": 128, "height": 128,
                   "camera": {"eye": [6.0 + i as f64 * 0.1, 4, 6], "target": [0, 0, 0]},
                   "outputs": ["rgb", "hdr", "depth", "normal", "shadow"]})
        })
        .collect();
    write_jobs(dir.path(), &jobs);
    let out = dir.path().join("out");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_chiaro"));
    cmd.args(["batch", "jobs.jsonl", "-o", "out"]).current_dir(dir.path()).stdout(Stdio::null()).stderr(Stdio::null());
    for var in SCHEDULER_VARS {
        cmd.env_remove(var);
    }
    let mut child = cmd.spawn().unwrap();
    let deadline = Instant::now() + Duration::from_secs(300);
    while !out.is_dir() || visible(&out).is_empty() {
        assert!(child.try_wait().unwrap().is_none(), "the batch ended before any job folder was seen");
        assert!(Instant::now() < deadline, "no job finished in 300 s");
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(child.try_wait().unwrap().is_none(), "the batch finished before it could be killed");
    child.kill().unwrap(); // SIGKILL: no chance to clean up
    child.wait().unwrap();

    let finished = visible(&out);
    assert!(!finished.is_empty() && finished.len() < jobs.len(), "killed midway: {} jobs done", finished.len());
    for job in jobs.iter().filter(|j| finished.contains(j["id"].as_str().unwrap())) {
        check_whole(&out, job);
    }
    let done_before = snapshot(&out);
    let run = batch(&["jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stderr.matches(" skipped\n").count(), finished.len(), "{}", run.stderr);
    assert_eq!(done_ids(&run).len(), jobs.len() - finished.len(), "{}", run.stderr);
    for job in &jobs {
        check_whole(&out, job);
    }
    let after = snapshot(&out);
    for (path, before) in &done_before {
        let inside = path.strip_prefix(&out).unwrap();
        if !inside.components().any(|c| c.as_os_str().to_string_lossy().starts_with('.')) {
            assert!(after.get(path) == Some(before), "{}: a finished job was touched", path.display());
        }
    }
    let hidden: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(hidden.is_empty(), "the killed run's temporary folders are removed: {hidden:?}");
}

#[test]
fn a_batch_image_equals_chiaro_render_pixel_for_pixel() {
    let dir = tempfile::tempdir().unwrap();
    spot_scene(dir.path());
    // The second job renders on a renderer that drew the first: its scene stays uploaded
    // and the shadow cache is on, as in a long batch.
    write_jobs(
        dir.path(),
        &[
            json!({"id": "first", "scene": SCENE, "width": 96, "height": 64, "outputs": ["depth"]}),
            json!({"id": "second", "scene": SCENE, "camera": "Camera", "width": 96, "height": 64}),
            json!({"id": "posed", "scene": SCENE, "camera": "Camera", "width": 96, "height": 64, "time": 1.25}),
        ],
    );
    let run = batch(&["jobs.jsonl", "-o", "out"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let rgba = |path: &str| image::open(dir.path().join(path)).unwrap().to_rgba8();
    for (id, time) in [("second", None), ("posed", Some("1.25"))] {
        let mut args = vec!["render", SCENE, "--camera", "Camera", "--width", "96", "--height", "64", "-o", "r.png"];
        args.extend(time.map(|t| ["--time", t]).into_iter().flatten());
        let run = chiaro(&args, &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
        let (batch_png, render_png) = (rgba(&format!("out/{id}/rgb.png")), rgba("r.png"));
        assert_eq!(batch_png.dimensions(), (96, 64));
        let differing = batch_png.pixels().zip(render_png.pixels()).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "{id}: pixels that differ from chiaro render's");
    }
    // The animation moves something the camera sees.
    assert_ne!(rgba("out/second/rgb.png"), rgba("out/posed/rgb.png"), "the time poses the scene");
}

#[test]
fn help_names_the_exit_statuses() {
    let dir = tempfile::tempdir().unwrap();
    let run = chiaro(&["batch", "--help"], &[], dir.path());
    assert_eq!(run.code, 0, "{}", run.stderr);
    for needle in ["Exit status:", "1-100", "101", "--shard <I/N>", "SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"] {
        assert!(run.stdout.contains(needle), "--help lacks {needle}: {}", run.stdout);
    }
}

#[test]
fn a_usage_error_of_batch_is_not_read_as_two_failed_jobs() {
    let dir = tempfile::tempdir().unwrap();
    for args in [&["batch", "jobs.jsonl", "--output", "out", "--bogus"][..], &["batch", "jobs.jsonl"][..]] {
        let run = chiaro(args, &[], dir.path());
        assert_eq!(run.code, 101, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("error:"), "{args:?}: clap's message is printed: {}", run.stderr);
    }
    // Other commands keep clap's usage status.
    assert_eq!(chiaro(&["render", "--bogus"], &[], dir.path()).code, 2);
    assert_eq!(chiaro(&["--version"], &[], dir.path()).code, 0);
}

/// Jobs on the benchmark scene, each camera near one of its shadowed lights, so that the
/// lights' importance (which orders their shadow tiles) and their coverage (which sizes
/// them) change from job to job; every file a light's shadow shows in.
fn history_jobs(scene: &Path) -> Vec<Value> {
    let near = [[0.8, -3.7], [-14.4, -16.6], [-17.8, -1.7], [-1.0, 0.3], [-5.9, -0.7], [-12.4, -11.7]];
    (0..10)
        .map(|i| {
            let [x, z] = near[i % near.len()];
            let eye = [x + 3.0 + 0.3 * i as f64, 8.0 + (i % 3) as f64, z + 4.0];
            json!({
                "id": format!("near-{i:02}"), "scene": scene, "width": 80, "height": 60,
                "camera": {"eye": eye, "target": [x, 0.0, z]},
                "outputs": ["rgb", "hdr", "shadow"],
            })
        })
        .collect()
}

/// Every file of every job folder under `out` but meta.json (which holds the wall time).
fn job_files(out: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    for job in std::fs::read_dir(out).unwrap() {
        let job = job.unwrap().path();
        for file in std::fs::read_dir(&job).unwrap() {
            let file = file.unwrap().path();
            if file.file_name().unwrap() != "meta.json" {
                files.insert(file.strip_prefix(out).unwrap().to_path_buf(), std::fs::read(&file).unwrap());
            }
        }
    }
    files
}

#[test]
fn a_job_renders_the_same_bytes_whatever_ran_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/chiaro-bench/shadow-bench.gltf");
    let jobs = history_jobs(&scene);
    let mut reversed = jobs.clone();
    reversed.reverse();
    let mut outputs = Vec::new();
    for (name, list) in [("listed", &jobs), ("reversed", &reversed)] {
        write_jobs(dir.path(), list);
        let run = batch(&["jobs.jsonl", "--output", name], &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
        outputs.push(job_files(&dir.path().join(name)));
    }
    // Each job alone, in a process of its own: nothing ran before it.
    for job in &jobs {
        write_jobs(dir.path(), std::slice::from_ref(job));
        let run = batch(&["jobs.jsonl", "--output", "alone"], &[], dir.path());
        assert_eq!(run.code, 0, "{}", run.stderr);
    }
    outputs.push(job_files(&dir.path().join("alone")));
    assert!(outputs[0].len() >= jobs.len() * 3, "{:?}", outputs[0].keys());
    for (name, other) in ["reversed", "alone"].iter().zip(&outputs[1..]) {
        assert_eq!(other.keys().collect::<Vec<_>>(), outputs[0].keys().collect::<Vec<_>>());
        let differing: Vec<&PathBuf> =
            outputs[0].iter().filter(|(file, bytes)| other[*file] != **bytes).map(|(f, _)| f).collect();
        assert!(
            differing.is_empty(),
            "{name}: {} files differ from the listed order's: {differing:?}",
            differing.len()
        );
    }
}
