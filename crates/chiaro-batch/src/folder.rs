//! A job's place in the output folder: `DIR/<id>/` holds its files and meta.json, whole
//! or absent; `DIR/<id>.error.json` says why it failed. A job is written into a hidden
//! temporary folder beside its own (`DIR/.<id>.tmp-<pid>-<nanos>`), its files synced and
//! meta.json last, and then renamed into place: a killed process leaves at most that
//! temporary folder, which the job's next run removes. A stale folder of the same id is
//! moved aside (`DIR/.<id>.old-<pid>-<nanos>`) for the rename and deleted after it.

use std::collections::HashMap;
use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::job::ERROR_SUFFIX;

/// The folders and files of one job id in an output folder.
#[derive(Clone, Debug)]
pub struct JobFolder {
    dir: PathBuf,
    id: String,
}

/// What a leftover of a killed run is called: `.<id>.<kind>-<pid>-<nanos>`.
const LEFTOVER_KINDS: [&str; 2] = ["tmp", "old"];

impl JobFolder {
    /// Job `id`'s places in `dir` (the id is already checked: one safe path component).
    pub fn new(dir: &Path, id: &str) -> JobFolder {
        JobFolder { dir: dir.to_path_buf(), id: id.to_string() }
    }

    /// `DIR/<id>`: the finished job.
    pub fn path(&self) -> PathBuf {
        self.dir.join(&self.id)
    }

    /// `DIR/<id>/meta.json`.
    pub fn meta_path(&self) -> PathBuf {
        self.path().join("meta.json")
    }

    /// `DIR/<id>.error.json`: why the job's last run failed.
    pub fn error_path(&self) -> PathBuf {
        self.dir.join(format!("{}{ERROR_SUFFIX}", self.id))
    }

    /// A new name `DIR/.<id>.<kind>-<pid>-<nanos>`.
    fn hidden(&self, kind: &str) -> PathBuf {
        let nanos = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        self.dir.join(format!(".{}.{kind}-{}-{nanos}", self.id, std::process::id()))
    }

    /// Removes the temporary and set-aside folders a killed run of this job left (listing
    /// the whole output folder: a runner lists it once for all its jobs instead, with
    /// `leftovers`).
    pub fn remove_leftovers(&self) -> io::Result<()> {
        for path in leftovers(&self.dir)?.remove(&self.id).unwrap_or_default() {
            remove_any(&path)?;
        }
        Ok(())
    }

    /// A fresh, empty temporary folder for the job's files.
    pub fn create_temp(&self) -> io::Result<PathBuf> {
        let tmp = self.hidden("tmp");
        std::fs::create_dir(&tmp)?;
        Ok(tmp)
    }

    /// Moves the finished temporary folder `tmp` (every file written) into place: its
    /// files and the folder are synced first, a stale folder of the id is set aside for
    /// the rename and removed after it.
    pub fn publish(&self, tmp: &Path) -> io::Result<()> {
        for entry in std::fs::read_dir(tmp)? {
            File::open(entry?.path())?.sync_all()?;
        }
        sync_folder(tmp)?;
        let target = self.path();
        let stale = match std::fs::symlink_metadata(&target) {
            Ok(_) => {
                let aside = self.hidden("old");
                std::fs::rename(&target, &aside)?;
                Some(aside)
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(e),
        };
        std::fs::rename(tmp, &target)?;
        sync_folder(&self.dir)?;
        if let Some(aside) = stale {
            remove_any(&aside)?;
        }
        Ok(())
    }

    /// Writes the job's `error.json` whole or not at all.
    pub fn write_error(&self, report: &serde_json::Value) -> Result<(), String> {
        let mut bytes = serde_json::to_vec_pretty(report).expect("JSON values serialise");
        bytes.push(b'\n');
        chiaro_io::output::write_file(&self.error_path(), &bytes).map_err(|e| crate::error_line(&e))
    }

    /// Removes an `error.json` a failed run left, now that the job is done.
    pub fn clear_error(&self) -> io::Result<()> {
        match std::fs::remove_file(self.error_path()) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => Err(e),
            _ => Ok(()),
        }
    }
}

/// The id whose leftover `name` is: exactly `.<id>.tmp-<digits>-<digits>` or
/// `.<id>.old-<digits>-<digits>`, read from the right, so that the id `a` does not claim
/// `.a.tmp-5.tmp-1-2`, the leftover of id `a.tmp-5`.
fn leftover_id(name: &str) -> Option<&str> {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let (rest, nanos) = name.rsplit_once('-')?;
    let (rest, pid) = rest.rsplit_once('-')?;
    if !(digits(pid) && digits(nanos)) {
        return None;
    }
    let id = LEFTOVER_KINDS.iter().find_map(|kind| rest.strip_suffix(kind)?.strip_suffix('.'))?;
    id.strip_prefix('.').filter(|id| !id.is_empty())
}

/// Every leftover of a killed run in `dir`, by job id.
pub fn leftovers(dir: &Path) -> io::Result<HashMap<String, Vec<PathBuf>>> {
    let mut found: HashMap<String, Vec<PathBuf>> = HashMap::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        if let Some(id) = name.to_str().and_then(leftover_id) {
            found.entry(id.to_string()).or_default().push(entry.path());
        }
    }
    Ok(found)
}

/// Removes a file or a folder with everything in it.
pub fn remove_any(path: &Path) -> io::Result<()> {
    let meta = std::fs::symlink_metadata(path)?;
    if meta.is_dir() { std::fs::remove_dir_all(path) } else { std::fs::remove_file(path) }
}

/// Syncs a folder's entries (the renames in it) to disk where the platform can.
fn sync_folder(dir: &Path) -> io::Result<()> {
    #[cfg(unix)]
    File::open(dir)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }

    #[test]
    fn a_published_job_replaces_a_stale_one_whole() {
        let dir = tempfile::tempdir().unwrap();
        let folder = JobFolder::new(dir.path(), "a");
        std::fs::create_dir(folder.path()).unwrap();
        std::fs::write(folder.path().join("old.png"), b"stale").unwrap();
        let tmp = folder.create_temp().unwrap();
        assert!(tmp.file_name().unwrap().to_str().unwrap().starts_with(".a.tmp-"));
        std::fs::write(tmp.join("rgb.png"), b"new").unwrap();
        std::fs::write(tmp.join("meta.json"), b"{}").unwrap();
        folder.publish(&tmp).unwrap();
        assert_eq!(names(dir.path()), ["a"]);
        assert_eq!(names(&folder.path()), ["meta.json", "rgb.png"]);
    }

    #[test]
    fn leftovers_of_the_id_are_removed_and_no_one_elses() {
        let dir = tempfile::tempdir().unwrap();
        for name in [".a.tmp-12-345", ".a.old-12-346", ".a.tmp-5.tmp-1-2", ".ab.tmp-1-2", ".a.tmp-x-2", "a"] {
            std::fs::create_dir(dir.path().join(name)).unwrap();
        }
        JobFolder::new(dir.path(), "a").remove_leftovers().unwrap();
        assert_eq!(names(dir.path()), [".a.tmp-5.tmp-1-2", ".a.tmp-x-2", ".ab.tmp-1-2", "a"]);
        JobFolder::new(dir.path(), "a.tmp-5").remove_leftovers().unwrap();
        assert_eq!(names(dir.path()), [".a.tmp-x-2", ".ab.tmp-1-2", "a"]);
        assert_eq!(leftover_id(".a b.old-1-2"), Some("a b"));
        for name in [".tmp-1-2", "a.tmp-1-2", ".a.new-1-2", ".a.tmp-1-", ".a.tmp1-2"] {
            assert_eq!(leftover_id(name), None, "{name}");
        }
    }

    #[test]
    fn an_error_report_is_written_and_cleared() {
        let dir = tempfile::tempdir().unwrap();
        let folder = JobFolder::new(dir.path(), "a");
        folder.write_error(&serde_json::json!({"id": "a", "error": "no"})).unwrap();
        assert_eq!(names(dir.path()), ["a.error.json"]);
        let report: serde_json::Value = serde_json::from_slice(&std::fs::read(folder.error_path()).unwrap()).unwrap();
        assert_eq!(report["error"], "no");
        folder.clear_error().unwrap();
        folder.clear_error().unwrap();
        assert!(names(dir.path()).is_empty());
    }
}
