//! meta.json, the record a finished job leaves in its folder: the job as given, the files
//! it read with their blake3 hashes, the effective settings, the device, the Chiaro
//! version, its wall time and the files it wrote. A rerun compares it with the job: the
//! same job object, the same effective settings and version, every file still there and
//! every input's hash unchanged mean the job is current and is skipped.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The version that wrote a record; another version renders the job again.
pub const CHIARO_VERSION: &str = env!("CARGO_PKG_VERSION");
/// The hash every `hash` field holds, hex.
pub const HASH: &str = "blake3";

/// One file a job read, and its hash.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputRecord {
    pub path: String,
    pub hash: String,
}

/// The device that rendered a job.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DeviceRecord {
    pub name: String,
    pub backend: String,
    /// "discrete_gpu", "integrated_gpu", "virtual_gpu", "cpu" or "other".
    pub device_type: String,
    pub driver: String,
}

impl DeviceRecord {
    /// What `info` says of its adapter.
    pub fn of(info: &chiaro_render::wgpu::AdapterInfo) -> DeviceRecord {
        DeviceRecord {
            name: info.name.clone(),
            backend: info.backend.to_str().to_string(),
            device_type: device_type_name(info.device_type).to_string(),
            driver: info.driver.clone(),
        }
    }
}

/// wgpu's device type as a lower-case name.
pub fn device_type_name(t: chiaro_render::wgpu::DeviceType) -> &'static str {
    use chiaro_render::wgpu::DeviceType;
    match t {
        DeviceType::DiscreteGpu => "discrete_gpu",
        DeviceType::IntegratedGpu => "integrated_gpu",
        DeviceType::VirtualGpu => "virtual_gpu",
        DeviceType::Cpu => "cpu",
        DeviceType::Other => "other",
    }
}

/// A job folder's meta.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Meta {
    /// The job object as given.
    pub job: Map<String, Value>,
    /// The hash of the scene's files (the document, then its buffers and images), each as
    /// its length (u64, little-endian) then its bytes: a bake's `scene_hash` without its
    /// `blake3:` prefix.
    pub scene_hash: String,
    /// `blake3`: what every hash here is.
    pub hash: String,
    /// Every file the job read: the scene's, and the bake's manifest when a bake lit it.
    pub inputs: Vec<InputRecord>,
    /// The effective settings, as settings.toml text.
    pub settings: String,
    pub device: DeviceRecord,
    pub chiaro_version: String,
    /// The job's seed (0 when it gives none); no pixel depends on it.
    pub seed: u64,
    /// Image size, pixels.
    pub width: u32,
    pub height: u32,
    /// Wall time of the job, seconds: scene load (when not cached), render and writes.
    pub seconds: f64,
    /// The files written beside meta.json.
    pub files: Vec<String>,
}

/// File hashes, each file read once per process (a job list may name one scene thousands
/// of times; its files are assumed not to change while the batch runs).
#[derive(Default)]
pub struct Hashes {
    known: HashMap<PathBuf, String>,
}

impl Hashes {
    /// The blake3 hash of the file at `path`, hex.
    pub fn file(&mut self, path: &Path) -> std::io::Result<String> {
        if let Some(hash) = self.known.get(path) {
            return Ok(hash.clone());
        }
        let mut hasher = blake3::Hasher::new();
        hasher.update_reader(std::fs::File::open(path)?)?;
        let hash = hasher.finalize().to_hex().to_string();
        self.known.insert(path.to_path_buf(), hash.clone());
        Ok(hash)
    }

    /// Forgets every hash (files may have changed since).
    pub fn clear(&mut self) {
        self.known.clear();
    }
}

/// The scene hash of `files`, as a bake computes it (see `Meta::scene_hash`).
pub fn scene_hash(files: &[PathBuf]) -> std::io::Result<String> {
    let mut hasher = blake3::Hasher::new();
    for path in files {
        let length = std::fs::metadata(path)?.len();
        hasher.update(&length.to_le_bytes());
        hasher.update_reader(std::fs::File::open(path)?)?;
    }
    Ok(hasher.finalize().to_hex().to_string())
}

/// Whether the record at `meta_path` says its job is current: written by this version
/// for the same job object and effective settings, its files all there, its inputs
/// unchanged. Anything unreadable is not current (the job runs again).
pub fn is_current(meta_path: &Path, job: &Map<String, Value>, settings_toml: &str, hashes: &mut Hashes) -> bool {
    let Ok(bytes) = std::fs::read(meta_path) else { return false };
    let Ok(meta) = serde_json::from_slice::<Meta>(&bytes) else { return false };
    if meta.chiaro_version != CHIARO_VERSION || &meta.job != job || meta.settings != settings_toml || meta.hash != HASH
    {
        return false;
    }
    let folder = meta_path.parent().expect("meta.json is in a folder");
    let files_there = meta.files.iter().all(|name| {
        !name.contains(['/', '\\']) && std::fs::symlink_metadata(folder.join(name)).is_ok_and(|m| m.is_file())
    });
    files_there && meta.inputs.iter().all(|input| hashes.file(Path::new(&input.path)).is_ok_and(|h| h == input.hash))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// Writes job `a`'s record (reading `input`) and its rgb.png into `dir`.
    fn record(dir: &Path, input: &Path) -> Meta {
        let meta = Meta {
            job: json!({"id": "a", "scene": input}).as_object().unwrap().clone(),
            scene_hash: scene_hash(&[input.to_path_buf()]).unwrap(),
            hash: HASH.into(),
            inputs: vec![InputRecord {
                path: input.to_string_lossy().into(),
                hash: Hashes::default().file(input).unwrap(),
            }],
            settings: "[render]\n".into(),
            device: DeviceRecord {
                name: "llvmpipe".into(),
                backend: "vulkan".into(),
                device_type: "cpu".into(),
                driver: "llvmpipe".into(),
            },
            chiaro_version: CHIARO_VERSION.into(),
            seed: 0,
            width: 8,
            height: 8,
            seconds: 0.1,
            files: vec!["rgb.png".into()],
        };
        std::fs::write(dir.join("meta.json"), serde_json::to_vec(&meta).unwrap()).unwrap();
        std::fs::write(dir.join("rgb.png"), b"png").unwrap();
        meta
    }

    #[test]
    fn a_record_is_current_until_its_job_settings_files_or_inputs_change() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("scene.gltf");
        std::fs::write(&input, b"{}").unwrap();
        let folder = dir.path().join("a");
        std::fs::create_dir(&folder).unwrap();
        let meta = record(&folder, &input);
        let path = folder.join("meta.json");
        let current =
            |job: &Map<String, Value>, settings: &str| is_current(&path, job, settings, &mut Hashes::default());
        assert!(current(&meta.job, "[render]\n"));
        let mut other = meta.job.clone();
        other.insert("seed".into(), json!(1));
        assert!(!current(&other, "[render]\n"), "another job object");
        assert!(!current(&meta.job, "[render]\nmsaa = 1\n"), "other settings");
        std::fs::write(&input, b"{ }").unwrap();
        assert!(!current(&meta.job, "[render]\n"), "a changed input");
        std::fs::write(&input, b"{}").unwrap();
        std::fs::remove_file(folder.join("rgb.png")).unwrap();
        assert!(!current(&meta.job, "[render]\n"), "a missing output");
        std::fs::write(folder.join("rgb.png"), b"png").unwrap();
        assert!(current(&meta.job, "[render]\n"));
        std::fs::write(&path, b"{\"job\": ").unwrap();
        assert!(!current(&meta.job, "[render]\n"), "an unreadable record");
    }

    #[test]
    fn the_scene_hash_is_a_bakes() {
        // chiaro-bake's scene_hash: each file's length (u64 LE) then its bytes.
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::fs::write(&a, b"gltf").unwrap();
        std::fs::write(&b, b"bin!").unwrap();
        let mut expected = blake3::Hasher::new();
        for bytes in [b"gltf", b"bin!"] {
            expected.update(&4u64.to_le_bytes());
            expected.update(bytes);
        }
        assert_eq!(scene_hash(&[a, b]).unwrap(), expected.finalize().to_hex().to_string());
    }
}
