//! Job lists: one JSON object per line, blank lines ignored. The list is checked whole
//! before anything renders (every line an object with a safe, unique string `id`), so
//! that every shard of it agrees on the jobs and their positions; a job's other keys are
//! read when it runs, and a mistake there fails that job alone. Text flows in; `Job`s
//! flow out, and from each job and the base settings, the `JobSpec` that renders it.

use crate::camera::{CameraSpec, kind};
use crate::outputs::Outputs;
use crate::settings::merged_settings;
use chiaro_scene::Settings;
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// Every key a job may have.
pub const KEYS: [&str; 10] =
    ["id", "scene", "camera", "time", "variant", "width", "height", "outputs", "settings", "seed"];
/// The longest id, bytes: a folder name every file system takes with room for suffixes.
pub const MAX_ID_BYTES: usize = 200;
/// The widest side a job may ask for, pixels (the device's own limit may be lower).
pub const MAX_SIDE: u64 = 16384;
/// What follows a job's id in its failure's file name, beside the job folders.
pub const ERROR_SUFFIX: &str = ".error.json";

/// One job of a list, as given.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// The list it came from, as messages name it (the file's path as given).
    pub source: Arc<str>,
    /// Its 1-based line in the list (blank lines counted).
    pub line: usize,
    /// Its id: the name of its folder.
    pub id: String,
    /// The whole object as given: what meta.json records and a rerun compares.
    pub object: Map<String, Value>,
}

/// Why a job list cannot run at all.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum JobListError {
    /// A line is not a job: not JSON, not an object, or without a safe string id.
    #[error("{source_name}:{line}: {message}")]
    BadLine { source_name: String, line: usize, message: String },
    /// Two jobs share an id, and so a folder.
    #[error("{source_name}:{line}: id '{id}' is already the id of line {first}; ids must be unique")]
    DuplicateId { source_name: String, line: usize, first: usize, id: String },
}

/// The jobs of a list whose lines are `lines` (the first is line 1), named `source_name`
/// in messages.
pub fn parse_jobs<'a>(lines: impl IntoIterator<Item = &'a str>, source_name: &str) -> Result<Vec<Job>, JobListError> {
    let source: Arc<str> = Arc::from(source_name);
    let mut jobs: Vec<Job> = Vec::new();
    let mut lines_of_ids: HashMap<String, usize> = HashMap::new();
    for (i, text) in lines.into_iter().enumerate() {
        let line = i + 1;
        let text = if line == 1 { text.trim_start_matches('\u{feff}') } else { text };
        if text.trim().is_empty() {
            continue;
        }
        let bad = |message: String| JobListError::BadLine { source_name: source_name.to_string(), line, message };
        let value: Value = serde_json::from_str(text).map_err(|e| bad(format!("not JSON: {e}")))?;
        let Value::Object(object) = value else {
            return Err(bad(format!("a job is a JSON object ({{\"id\": ..., \"scene\": ...}}), not {}", kind(&value))));
        };
        let id = match object.get("id") {
            Some(Value::String(id)) => id.clone(),
            Some(other) => return Err(bad(format!("\"id\" must be a string, not {}", kind(other)))),
            None => return Err(bad("no \"id\": every job needs a string id, the name of its folder".into())),
        };
        check_id(&id).map_err(|why| bad(format!("id {id:?}: {why}")))?;
        if let Some(&first) = lines_of_ids.get(&id) {
            return Err(JobListError::DuplicateId { source_name: source_name.to_string(), line, first, id });
        }
        lines_of_ids.insert(id.clone(), line);
        jobs.push(Job { source: source.clone(), line, id, object });
    }
    Ok(jobs)
}

/// Whether `id` is a safe folder name: one path component, printable, not hidden (the
/// temporary folders are), and not a job's error file.
pub fn check_id(id: &str) -> Result<(), String> {
    if id.is_empty() {
        return Err("is empty".into());
    }
    if id.len() > MAX_ID_BYTES {
        return Err(format!("is {} bytes long, more than {MAX_ID_BYTES}", id.len()));
    }
    if let Some(c) = id.chars().find(|c| matches!(c, '/' | '\\') || c.is_control()) {
        return Err(format!("holds {c:?}; an id is a folder name, without slashes or control characters"));
    }
    if id.starts_with('.') {
        return Err("starts with '.'; those names are the batch's temporary folders".into());
    }
    if id.ends_with(ERROR_SUFFIX) {
        return Err(format!("ends with '{ERROR_SUFFIX}', the name of a failed job's report"));
    }
    Ok(())
}

/// What a job renders, every default filled in.
#[derive(Clone, Debug)]
pub struct JobSpec {
    /// The scene file, absolute (a relative path is relative to the current directory).
    pub scene: PathBuf,
    pub camera: CameraSpec,
    /// Seconds into the scene's animations; `None` for the rest pose.
    pub time: Option<f32>,
    /// The KHR_materials_variants variant, by name: the job's `"variant"`, else its
    /// settings' `scene.variant`; `None`: the file's default materials.
    pub variant: Option<String>,
    /// Image size, pixels.
    pub width: u32,
    pub height: u32,
    pub outputs: Outputs,
    /// The base settings with the job's merged over them.
    pub settings: Settings,
    /// The job's label for tools that make variations; the renderer draws nothing at
    /// random, so it changes no pixel.
    pub seed: u64,
}

impl Job {
    /// The scene file the job names, absolute, if it names one; what the scene cache
    /// counts uses by.
    pub fn scene_path(&self) -> Option<PathBuf> {
        let path = self.object.get("scene")?.as_str().filter(|s| !s.is_empty())?;
        std::path::absolute(path).ok()
    }

    /// The job's keys read over `base`; the message names the key.
    pub fn spec(&self, base: &Settings) -> Result<JobSpec, String> {
        if let Some(key) = self.object.keys().find(|k| !KEYS.contains(&k.as_str())) {
            return Err(format!("unknown key '{key}' (a job's keys: {})", KEYS.join(", ")));
        }
        let get = |key: &str| self.object.get(key).filter(|v| !v.is_null());
        let scene = match get("scene") {
            Some(Value::String(path)) if !path.is_empty() => {
                std::path::absolute(path).map_err(|e| format!("scene: {path}: {e}"))?
            }
            Some(Value::String(_)) => return Err("scene: is empty; give a .gltf or .glb file".into()),
            Some(other) => return Err(format!("scene: expected a file's path, not {}", kind(other))),
            None => return Err("scene: is missing; every job needs a .gltf or .glb file".into()),
        };
        let settings = match get("settings") {
            None => base.clone(),
            Some(Value::Object(overrides)) => merged_settings(base, overrides)?,
            Some(other) => {
                return Err(format!(
                    "settings: expected an object of sections such as {{\"render\": {{\"msaa\": 1}}}}, not {}",
                    kind(other)
                ));
            }
        };
        let camera = CameraSpec::parse(get("camera"), settings.camera.auto_yfov_deg)?;
        let time = match get("time") {
            None => None,
            Some(value) => {
                let t = value.as_f64().ok_or_else(|| format!("time: expected seconds, not {}", kind(value)))? as f32;
                if !t.is_finite() {
                    return Err(format!("time: {value} is not a finite number of seconds"));
                }
                Some(t)
            }
        };
        let variant = match get("variant") {
            None => settings.scene.variant.clone(),
            Some(Value::String(name)) if !name.trim().is_empty() => Some(name.clone()),
            Some(other) => return Err(format!("variant: expected a variant's name, not {}", kind(other))),
        };
        let side = |key: &str, default: u32| -> Result<u32, String> {
            match get(key) {
                None => Ok(default),
                Some(value) => match value.as_u64() {
                    Some(v) if (1..=MAX_SIDE).contains(&v) => Ok(v as u32),
                    _ => Err(format!("{key}: {value} is not between 1 and {MAX_SIDE} pixels")),
                },
            }
        };
        let width = side("width", settings.render.width)?;
        let height = side("height", settings.render.height)?;
        let outputs = match get("outputs") {
            None => Outputs::default(),
            Some(Value::String(name)) => Outputs::from_names(&[name])?,
            Some(Value::Array(items)) => {
                let names: Vec<&str> = items
                    .iter()
                    .map(|v| v.as_str().ok_or_else(|| format!("outputs: expected names, not {}", kind(v))))
                    .collect::<Result<_, _>>()?;
                Outputs::from_names(&names)?
            }
            Some(other) => {
                return Err(format!(
                    "outputs: expected a list of names such as [\"rgb\", \"depth\"], not {}",
                    kind(other)
                ));
            }
        };
        let seed = match get("seed") {
            None => 0,
            Some(value) => value.as_u64().ok_or_else(|| format!("seed: {value} is not a whole number from 0"))?,
        };
        Ok(JobSpec { scene, camera, time, variant, width, height, outputs, settings, seed })
    }

    /// The job's failure message: the list, the line, then `problem`.
    pub fn failure(&self, problem: &str) -> String {
        format!("{}:{}: {problem}", self.source, self.line)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outputs::Output;

    fn one(line: &str) -> Job {
        parse_jobs([line], "jobs.jsonl").unwrap().remove(0)
    }

    #[test]
    fn blank_lines_are_skipped_but_counted() {
        let jobs =
            parse_jobs(["", r#"{"id": "a", "scene": "s.gltf"}"#, "   ", r#"{"id": "b", "scene": "s.gltf"}"#], "j")
                .unwrap();
        let found: Vec<(usize, &str)> = jobs.iter().map(|j| (j.line, j.id.as_str())).collect();
        assert_eq!(found, [(2, "a"), (4, "b")]);
    }

    #[test]
    fn a_line_that_is_no_job_stops_the_list_naming_its_line() {
        let error = |lines: &[&str]| parse_jobs(lines.iter().copied(), "jobs.jsonl").unwrap_err().to_string();
        let e = error(&[r#"{"id": "a"}"#, "{not json"]);
        assert!(e.starts_with("jobs.jsonl:2: not JSON: "), "{e}");
        assert!(error(&["[1, 2]"]).starts_with("jobs.jsonl:1: a job is a JSON object"));
        assert_eq!(
            error(&[r#"{"scene": "s.gltf"}"#]),
            "jobs.jsonl:1: no \"id\": every job needs a string id, the name of its folder"
        );
        assert_eq!(error(&[r#"{"id": 7}"#]), "jobs.jsonl:1: \"id\" must be a string, not a number");
    }

    #[test]
    fn ids_must_be_safe_folder_names() {
        let error = |id: &str| {
            let line = serde_json::json!({"id": id, "scene": "s.gltf"}).to_string();
            parse_jobs([line.as_str()], "j").unwrap_err().to_string()
        };
        assert_eq!(error(""), "j:1: id \"\": is empty");
        assert!(error("a/b").contains("holds '/'"), "{}", error("a/b"));
        assert!(error("a\\b").contains("holds '\\\\'"), "{}", error("a\\b"));
        assert!(error("a\u{0}b").contains("control characters"));
        assert!(error("tab\there").contains("control characters"));
        assert!(error(".hidden").contains("starts with '.'"));
        assert!(error("..").contains("starts with '.'"));
        assert!(error("x.error.json").contains("ends with '.error.json'"));
        assert!(error(&"x".repeat(201)).contains("201 bytes long, more than 200"));
        assert!(check_id(&"x".repeat(200)).is_ok());
        assert!(check_id("frame 0001 (left)").is_ok());
    }

    #[test]
    fn a_repeated_id_names_both_lines() {
        let lines = [r#"{"id": "a", "scene": "s.gltf"}"#, r#"{"id": "b", "scene": "s.gltf"}"#, r#"{"id": "a"}"#];
        let e = parse_jobs(lines, "jobs.jsonl").unwrap_err().to_string();
        assert_eq!(e, "jobs.jsonl:3: id 'a' is already the id of line 1; ids must be unique");
    }

    #[test]
    fn an_unknown_key_fails_the_job_naming_the_key() {
        let job = one(r#"{"id": "a", "scene": "s.gltf", "cmera": 0}"#);
        let e = job.spec(&Settings::default()).unwrap_err();
        assert!(e.starts_with("unknown key 'cmera' (a job's keys: id, scene, camera,"), "{e}");
        assert_eq!(job.failure(&e), format!("jobs.jsonl:1: {e}"));
    }

    #[test]
    fn defaults_fill_what_a_job_leaves_out() {
        let mut base = Settings::default();
        base.render.width = 96;
        base.render.height = 64;
        let spec = one(r#"{"id": "a", "scene": "s.gltf"}"#).spec(&base).unwrap();
        assert!(spec.scene.is_absolute() && spec.scene.ends_with("s.gltf"));
        assert_eq!(spec.camera, CameraSpec::Default);
        assert_eq!((spec.time, spec.width, spec.height, spec.seed), (None, 96, 64, 0));
        assert_eq!(spec.outputs.0, [Output::Rgb]);
        assert_eq!(spec.settings, base);
        let spec = one(r#"{"id": "a", "scene": "s.gltf", "camera": "Camera", "time": 0.5, "width": 32, "height": 16,
                "outputs": ["depth", "rgb"], "settings": {"render": {"msaa": 1}}, "seed": 42}"#)
        .spec(&base)
        .unwrap();
        assert_eq!((spec.time, spec.width, spec.height, spec.seed), (Some(0.5), 32, 16, 42));
        assert_eq!(spec.outputs.0, [Output::Depth, Output::Rgb]);
        assert_eq!((spec.settings.render.msaa, spec.settings.render.width), (1, 96));
    }

    #[test]
    fn bad_values_fail_the_job_naming_the_key() {
        let error = |rest: &str| {
            one(&format!(r#"{{"id": "a", "scene": "s.gltf", {rest}}}"#)).spec(&Settings::default()).unwrap_err()
        };
        assert_eq!(error(r#""width": 0"#), "width: 0 is not between 1 and 16384 pixels");
        assert_eq!(error(r#""height": 16385"#), "height: 16385 is not between 1 and 16384 pixels");
        assert_eq!(error(r#""width": "64""#), "width: \"64\" is not between 1 and 16384 pixels");
        assert_eq!(error(r#""time": "soon""#), "time: expected seconds, not a string");
        assert_eq!(error(r#""time": 1e300"#), "time: 1e+300 is not a finite number of seconds");
        assert_eq!(error(r#""seed": -1"#), "seed: -1 is not a whole number from 0");
        assert!(error(r#""outputs": ["rgb", "albedo"]"#).starts_with("outputs: 'albedo' is not one of rgb,"));
        assert!(error(r#""outputs": []"#).starts_with("outputs: name at least one output"));
        assert!(error(r#""settings": {"render": {"msaa": 3}}"#).starts_with("settings: render.msaa: "));
        assert!(error(r#""settings": 1"#).starts_with("settings: expected an object"));
        let missing = one(r#"{"id": "a"}"#).spec(&Settings::default()).unwrap_err();
        assert_eq!(missing, "scene: is missing; every job needs a .gltf or .glb file");
    }
}
