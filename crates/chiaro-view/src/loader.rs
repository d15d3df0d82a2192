//! Opening scenes while the window stays live: a dropped or changed file is read (and
//! its bake applied) on a thread of its own; the window keeps showing the old scene until
//! the new one is ready, and a file that fails to load leaves it in place. How a file is
//! read (and which bake it gets) is the caller's `LoadScene`.

use crate::LoadScene;
use anyhow::{Result, bail};
use chiaro_scene::{Scene, Settings};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant, SystemTime};

/// How often the scene's files are checked for changes.
const WATCH_INTERVAL: Duration = Duration::from_millis(500);

/// A scene read on another thread.
#[derive(Debug)]
pub struct Loaded {
    pub path: PathBuf,
    /// A reload of the scene on screen (the camera stays), not a new file.
    pub reload: bool,
    pub scene: Result<Scene>,
}

pub struct Loader {
    load_scene: LoadScene,
    pending: Option<(PathBuf, mpsc::Receiver<Loaded>)>,
    /// The scene's files and the newest modification time among them at load.
    watched: Vec<PathBuf>,
    watched_time: Option<SystemTime>,
    last_check: Instant,
}

/// A `LoadScene` that reads a glTF file and attaches no bake (tests, and callers
/// without flags to honour).
pub fn plain_loader() -> LoadScene {
    std::sync::Arc::new(|path, _settings| Ok(chiaro_scene::load_gltf(path)?))
}

/// Whether `path` names a file the viewer opens.
pub fn check_scene_file(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("gltf" | "glb")) {
        bail!("{}: not a .gltf or .glb file", path.display());
    }
    Ok(())
}

/// The newest modification time among `files` (None if none can be read).
fn newest_time(files: &[PathBuf]) -> Option<SystemTime> {
    files.iter().filter_map(|f| std::fs::metadata(f).and_then(|m| m.modified()).ok()).max()
}

impl Loader {
    pub fn new(load_scene: LoadScene) -> Loader {
        Loader { load_scene, pending: None, watched: Vec::new(), watched_time: None, last_check: Instant::now() }
    }

    /// The file being read, if any.
    pub fn loading(&self) -> Option<&Path> {
        self.pending.as_ref().map(|(p, _)| p.as_path())
    }

    /// Watches the files `scene` was read from (none for the demo scene).
    pub fn watch(&mut self, scene: &Scene) {
        self.watched = scene.inputs.clone();
        self.watched_time = newest_time(&self.watched);
    }

    /// Starts reading `path` (replacing any read under way).
    pub fn open(&mut self, path: PathBuf, settings: &Settings, reload: bool) {
        let (tx, rx) = mpsc::channel();
        let (load_scene, settings, job_path) = (self.load_scene.clone(), settings.clone(), path.clone());
        std::thread::spawn(move || {
            let scene = check_scene_file(&job_path).and_then(|()| load_scene(&job_path, &settings));
            // The window may have closed meanwhile; then nobody listens.
            let _ = tx.send(Loaded { path: job_path, reload, scene });
        });
        self.pending = Some((path, rx));
    }

    /// A scene that finished reading since the last call.
    pub fn poll(&mut self) -> Option<Loaded> {
        let (_, rx) = self.pending.as_ref()?;
        match rx.try_recv() {
            Ok(loaded) => {
                self.pending = None;
                Some(loaded)
            }
            Err(mpsc::TryRecvError::Empty) => None,
            Err(mpsc::TryRecvError::Disconnected) => {
                let (path, _) = self.pending.take()?;
                Some(Loaded { path, reload: false, scene: Err(anyhow::anyhow!("the loading thread stopped")) })
            }
        }
    }

    /// Whether a watched file changed since the scene was read (checked at most twice a
    /// second; a change is reported once).
    pub fn changed(&mut self) -> bool {
        if self.watched.is_empty() || self.pending.is_some() || self.last_check.elapsed() < WATCH_INTERVAL {
            return false;
        }
        self.last_check = Instant::now();
        let now = newest_time(&self.watched);
        if now.is_some() && now != self.watched_time {
            self.watched_time = now;
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait(loader: &mut Loader) -> Loaded {
        let start = Instant::now();
        loop {
            if let Some(l) = loader.poll() {
                return l;
            }
            assert!(start.elapsed() < Duration::from_secs(60), "the load never finished");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn loader() -> Loader {
        Loader::new(plain_loader())
    }

    #[test]
    fn a_broken_file_is_an_error_that_names_it_and_a_good_one_loads() {
        let dir = tempfile::tempdir().unwrap();
        let broken = dir.path().join("broken.gltf");
        std::fs::write(&broken, "{ not json").unwrap();
        let mut loader = loader();
        loader.open(broken.clone(), &Settings::default(), false);
        assert_eq!(loader.loading(), Some(broken.as_path()));
        let error = format!("{:#}", wait(&mut loader).scene.expect_err("broken"));
        assert!(error.contains("broken.gltf"), "{error}");

        let not_gltf = dir.path().join("notes.txt");
        std::fs::write(&not_gltf, "hello").unwrap();
        loader.open(not_gltf, &Settings::default(), false);
        let error = format!("{:#}", wait(&mut loader).scene.expect_err("not a scene"));
        assert!(error.contains("notes.txt: not a .gltf or .glb"), "{error}");

        let good = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets"))
            .join("ShadowsSpot/glTF/shadows-spot.gltf");
        loader.open(good, &Settings::default(), true);
        let loaded = wait(&mut loader);
        assert!(loaded.reload);
        assert!(!loaded.scene.expect("loads").lights.is_empty());
    }

    #[test]
    fn a_changed_file_is_noticed_once() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("scene.gltf");
        std::fs::write(&file, "a").unwrap();
        let mut loader = loader();
        let scene = Scene { inputs: vec![file.clone()], ..Default::default() };
        loader.watch(&scene);
        loader.last_check -= WATCH_INTERVAL;
        assert!(!loader.changed(), "unchanged");
        let later = SystemTime::now() + Duration::from_secs(5);
        std::fs::File::options().write(true).open(&file).unwrap().set_modified(later).unwrap();
        loader.last_check -= WATCH_INTERVAL;
        assert!(loader.changed(), "the new time is seen");
        loader.last_check -= WATCH_INTERVAL;
        assert!(!loader.changed(), "and reported once");
    }
}
