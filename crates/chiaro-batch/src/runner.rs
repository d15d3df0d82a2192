//! Runs jobs on a renderer the caller lends (the CLI opens one; the Python package lends
//! its `Renderer`'s). Per job: read its keys over the base settings, skip it when its
//! folder is current, else load its scene (once per process, kept while jobs still to run
//! use it), pose it at the job's time, upload it when the scene or the time differs from
//! what the device holds, render the outputs asked for, and write the job's folder whole.
//! A failure is written as the job's error.json and the batch goes on. Progress goes to a
//! callback, so the CLI's bar and lines and Python's counts share one loop.

use crate::error_line;
use crate::folder::{JobFolder, remove_any};
use crate::job::Job;
use crate::meta::{self, CHIARO_VERSION, DeviceRecord, Hashes, InputRecord, Meta};
use crate::outputs::Output;
use chiaro_render::{PreparedScene, Renderer};
use chiaro_scene::{RenderPath, Scene, Settings};
use serde_json::json;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How a job ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum JobOutcome {
    /// Rendered, and its folder written.
    Done,
    /// Its folder was current: nothing was loaded or written.
    Skipped,
    /// It failed; the message (also in its error.json) names the list's line, the key or
    /// file, and the problem.
    Failed(String),
}

/// What the runner reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum Event<'a> {
    /// Job `position` (from 1) of `total` starts.
    Started { position: usize, total: usize, job: &'a Job },
    /// It ended after `seconds` of wall time.
    Finished { position: usize, total: usize, job: &'a Job, outcome: &'a JobOutcome, seconds: f64 },
}

/// How the jobs of a run ended.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    pub done: usize,
    pub skipped: usize,
    /// Each failed job's id and message, in the list's order.
    pub failed: Vec<(String, String)>,
}

/// A scene loaded for the jobs that use it.
struct LoadedScene {
    scene: Scene,
    /// Which load this is, so that an upload knows its scene.
    load: u64,
    /// The time the scene is posed at (`Some(None)`: the rest pose); `None` after a pose
    /// failed halfway.
    posed_at: Option<Option<u32>>,
    scene_hash: String,
    inputs: Vec<InputRecord>,
}

/// The scene on the device: which load of it, at which time, in which material variant.
struct Uploaded {
    load: u64,
    time: Option<u32>,
    variant: Option<usize>,
    gpu: PreparedScene,
}

/// Runs jobs on a borrowed renderer; see the module's comment.
pub struct BatchRunner<'r> {
    renderer: &'r mut Renderer,
    base: Settings,
    device: DeviceRecord,
    /// Loaded scenes (or why they failed to load) by absolute path.
    scenes: HashMap<PathBuf, Result<LoadedScene, String>>,
    /// Jobs still to run per scene path; a scene is dropped when its count ends.
    uses: HashMap<PathBuf, usize>,
    uploaded: Option<Uploaded>,
    hashes: Hashes,
    loads: u64,
    /// What killed runs left in the output folder, by job id, listed once by `run_all`
    /// (without it, each job lists the folder).
    leftovers: Option<HashMap<String, Vec<PathBuf>>>,
}

impl<'r> BatchRunner<'r> {
    /// A runner rendering on `renderer` with `base` settings (each job's are merged over
    /// them). The renderer's own upload is not used: the first job uploads its scene.
    pub fn new(renderer: &'r mut Renderer, base: Settings) -> BatchRunner<'r> {
        let device = DeviceRecord::of(&renderer.ctx.adapter_info);
        BatchRunner {
            renderer,
            base,
            device,
            scenes: HashMap::new(),
            uses: HashMap::new(),
            uploaded: None,
            hashes: Hashes::default(),
            loads: 0,
            leftovers: None,
        }
    }

    /// Runs `jobs` in order into `dir` (which exists), reporting to `progress`.
    pub fn run_all(&mut self, jobs: &[Job], dir: &Path, mut progress: impl FnMut(Event<'_>)) -> Summary {
        for path in jobs.iter().filter_map(Job::scene_path) {
            *self.uses.entry(path).or_default() += 1;
        }
        self.leftovers = crate::folder::leftovers(dir).ok();
        let mut summary = Summary::default();
        let total = jobs.len();
        for (i, job) in jobs.iter().enumerate() {
            let position = i + 1;
            progress(Event::Started { position, total, job });
            let start = Instant::now();
            let outcome = self.run_job(job, dir);
            let seconds = start.elapsed().as_secs_f64();
            progress(Event::Finished { position, total, job, outcome: &outcome, seconds });
            match outcome {
                JobOutcome::Done => summary.done += 1,
                JobOutcome::Skipped => summary.skipped += 1,
                JobOutcome::Failed(message) => summary.failed.push((job.id.clone(), message)),
            }
        }
        self.uploaded = None;
        self.scenes.clear();
        self.uses.clear();
        self.leftovers = None;
        summary
    }

    /// Runs one job into `dir`: skipped when its folder is current, else rendered and
    /// written whole; a failure is written as `<id>.error.json`.
    pub fn run_job(&mut self, job: &Job, dir: &Path) -> JobOutcome {
        let _span = tracing::info_span!("job", id = %job.id).entered();
        let start = Instant::now();
        let folder = JobFolder::new(dir, &job.id);
        let outcome = match self.attempt(job, &folder, start) {
            Ok(true) => JobOutcome::Done,
            Ok(false) => JobOutcome::Skipped,
            Err(problem) => {
                let message = job.failure(&problem);
                let report = json!({
                    "id": job.id,
                    "line": job.line,
                    "job": job.object,
                    "error": message,
                    "chiaro_version": CHIARO_VERSION,
                });
                match folder.write_error(&report) {
                    Ok(()) => JobOutcome::Failed(message),
                    Err(e) => JobOutcome::Failed(format!("{message} (and its error report was not written: {e})")),
                }
            }
        };
        if let Some(path) = job.scene_path() {
            self.release(&path);
        }
        outcome
    }

    /// One use of the scene at `path` is over; the last drops it (and its upload).
    fn release(&mut self, path: &Path) {
        match self.uses.get_mut(path) {
            Some(left) if *left > 1 => *left -= 1,
            _ => {
                self.uses.remove(path);
                if let Some(Ok(loaded)) = self.scenes.remove(path)
                    && self.uploaded.as_ref().is_some_and(|u| u.load == loaded.load)
                {
                    self.uploaded = None;
                }
            }
        }
    }

    /// The job rendered and written (true), or found current (false).
    fn attempt(&mut self, job: &Job, folder: &JobFolder, start: Instant) -> Result<bool, String> {
        let spec = job.spec(&self.base)?;
        let settings_toml = spec.settings.to_toml();
        let removed = match self.leftovers.as_mut() {
            Some(all) => all.remove(&job.id).unwrap_or_default().iter().try_for_each(|p| remove_any(p)),
            None => folder.remove_leftovers(),
        };
        removed.map_err(|e| format!("cannot remove what a killed run of the job left: {e}"))?;
        if meta::is_current(&folder.meta_path(), &job.object, &settings_toml, &mut self.hashes) {
            folder.clear_error().map_err(|e| format!("{}: cannot remove it: {e}", folder.error_path().display()))?;
            return Ok(false);
        }
        if spec.settings.render.path == RenderPath::Forward {
            let msaa = spec.settings.render.msaa;
            self.renderer.ctx.check_msaa(msaa).map_err(|e| format!("settings: render.msaa = {msaa}: {e}"))?;
        }
        let loads = &mut self.loads;
        let hashes = &mut self.hashes;
        let loaded = self
            .scenes
            .entry(spec.scene.clone())
            .or_insert_with(|| {
                *loads += 1;
                load(&spec.scene, &spec.settings, *loads, hashes)
            })
            .as_mut()
            .map_err(|e| e.clone())?;
        // A scene without animation poses the same at every time: one upload serves all.
        let time = spec.time.filter(|_| loaded.scene.animation.is_some()).map(f32::to_bits);
        if loaded.posed_at != Some(time) {
            loaded.posed_at = None;
            loaded.scene.pose(time.map(f32::from_bits)).map_err(|e| format!("time: {e}"))?;
            loaded.posed_at = Some(time);
        }
        if loaded.scene.selected_variant() != spec.variant.as_deref() {
            loaded.scene.select_variant(spec.variant.as_deref()).map_err(|e| format!("variant: {e}"))?;
        }
        let variant = loaded.scene.variants.selected;
        let scene = &loaded.scene;
        let view = spec.camera.view(scene, &spec.settings, spec.width, spec.height)?;
        let layers = self.renderer.ctx.device.limits().max_texture_array_layers as usize;
        if spec.outputs.wants(Output::Shadow) && scene.lights.len() > layers {
            return Err(format!(
                "outputs: 'shadow' takes one layer per light, and this device holds at most {layers} (the scene has {} \
                 lights)",
                scene.lights.len()
            ));
        }
        let fresh =
            !self.uploaded.as_ref().is_some_and(|u| u.load == loaded.load && u.time == time && u.variant == variant);
        if fresh {
            self.uploaded = None;
            let gpu = self.renderer.prepare(scene).map_err(|e| e.to_string())?;
            self.uploaded = Some(Uploaded { load: loaded.load, time, variant, gpu });
        }
        let gpu = &self.uploaded.as_ref().expect("uploaded above").gpu;
        // Every tile drawn afresh, placed as on a new renderer: the job renders the same
        // bytes whatever ran before it, in any order and any front end.
        self.renderer.forget_history();
        let frame = self
            .renderer
            .render(scene, gpu, &view, &spec.settings, spec.outputs.frame_options())
            .map_err(|e| e.to_string())?;
        let hdr_rgb: Vec<[f32; 3]> = if spec.outputs.wants(Output::Hdr) {
            frame.hdr.iter().map(|p| [p[0], p[1], p[2]]).collect()
        } else {
            Vec::new()
        };
        let light_nodes: Vec<usize> = scene.lights.iter().map(|l| l.node).collect();
        let files = spec.outputs.files(&frame, &hdr_rgb, &light_nodes);
        let record = |names: Vec<String>| Meta {
            job: job.object.clone(),
            scene_hash: loaded.scene_hash.clone(),
            hash: meta::HASH.into(),
            inputs: loaded.inputs.clone(),
            settings: settings_toml.clone(),
            device: self.device.clone(),
            chiaro_version: CHIARO_VERSION.into(),
            seed: spec.seed,
            width: spec.width,
            height: spec.height,
            seconds: start.elapsed().as_secs_f64(),
            files: names,
        };
        write_folder(folder, files, record)?;
        folder.clear_error().map_err(|e| format!("{}: cannot remove it: {e}", folder.error_path().display()))?;
        Ok(true)
    }
}

/// Loads the scene at `path` with the bake `chiaro render` would use, and hashes what it
/// read; the message names the file.
fn load(path: &Path, settings: &Settings, load: u64, hashes: &mut Hashes) -> Result<LoadedScene, String> {
    let mut scene = chiaro_io::scenes::load_scene(Some(path), &Default::default())
        .map_err(|e| format!("scene: {}", error_line(&e)))?;
    let bake = chiaro_io::bake::BakeChoice::default()
        .apply(&mut scene, Some(path), settings)
        .map_err(|e| format!("scene: {}", error_line(&e)))?;
    let mut read = scene.inputs.clone();
    read.extend(bake.map(|dir| dir.join(chiaro_bake::bake_dir::MANIFEST)));
    let unreadable = |file: &Path, e: std::io::Error| format!("scene: {}: cannot hash it: {e}", file.display());
    let inputs = read
        .iter()
        .map(|file| {
            let hash = hashes.file(file).map_err(|e| unreadable(file, e))?;
            Ok(InputRecord { path: file.to_string_lossy().into_owned(), hash })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let scene_hash = meta::scene_hash(&scene.inputs).map_err(|e| format!("scene: {}: {e}", path.display()))?;
    Ok(LoadedScene { scene, load, posed_at: Some(None), scene_hash, inputs })
}

/// Writes the job's files and then its meta.json (made by `record` from the files'
/// names) into a temporary folder, and moves it into place; nothing is left on failure.
fn write_folder(
    folder: &JobFolder,
    files: Vec<(String, chiaro_io::output::Encoded<'_>)>,
    record: impl FnOnce(Vec<String>) -> Meta,
) -> Result<(), String> {
    let tmp =
        folder.create_temp().map_err(|e| format!("{}: cannot make a folder there: {e}", folder.path().display()))?;
    let written = (|| {
        let mut names = Vec::with_capacity(files.len());
        for (name, image) in files {
            image
                .write(&tmp.join(&name))
                .map_err(|e| format!("{}: cannot write {name}: {}", folder.path().display(), error_line(&e)))?;
            names.push(name);
        }
        let mut bytes = serde_json::to_vec_pretty(&record(names)).expect("a record serialises");
        bytes.push(b'\n');
        std::fs::write(tmp.join("meta.json"), bytes)
            .map_err(|e| format!("{}: cannot write meta.json: {e}", folder.path().display()))?;
        folder
            .publish(&tmp)
            .map_err(|e| format!("{}: cannot move the finished job into place: {e}", folder.path().display()))
    })();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    written
}
