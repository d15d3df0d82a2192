//! Writing a bake directory atomically: every file goes into a temporary directory beside
//! the target, is synced to disk, and the directory is renamed into place (the old bake
//! moved aside first, and removed only once the new one is in). A `BakeResult` flows in;
//! on failure or interrupt nothing is left at the target or beside it.

use super::binary::{self, encode_occlusion, encode_probes, encode_uvs};
use super::manifest::manifest_of;
use super::{BakeDirError, MANIFEST, PROBE_OCCLUSION, PROBES, UVS, atlas};
use crate::bake::BakeResult;
use chiaro_scene::{Scene, Settings};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Writes `result` as the bake directory `dir`, replacing one that is there. Nothing is
/// left at `dir` or beside it if this fails or `cancel` is set before the final rename.
pub fn write_bake_dir(
    dir: &Path,
    scene: &Scene,
    settings: &Settings,
    result: &BakeResult,
    cancel: &AtomicBool,
) -> Result<(), BakeDirError> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = dir.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "bake".into());
    let temp =
        tempfile::Builder::new().prefix(&format!(".{name}.")).tempdir_in(parent).map_err(BakeDirError::io(parent))?;
    write_files(temp.path(), scene, settings, result)?;
    if cancel.load(Ordering::Relaxed) {
        return Err(BakeDirError::Cancelled);
    }
    swap_in(temp, parent, &name, dir)
}

/// Every file of the bake into `into`, the manifest last.
fn write_files(into: &Path, scene: &Scene, settings: &Settings, result: &BakeResult) -> Result<(), BakeDirError> {
    let lighting = &result.lighting;
    // The manifest first: it hashes the scene, which may fail, and names the atlas files.
    let manifest = manifest_of(scene, settings, result)?;
    for (file, lightmap) in manifest.lightmaps.iter().zip(&lighting.lightmaps) {
        atlas::write_exr(&into.join(file), lightmap.width, lightmap.height, &lightmap.texels)?;
    }
    for (file, mask) in manifest.shadow_masks.iter().zip(&lighting.shadow_masks) {
        atlas::write_exr(&into.join(file), mask.width, mask.height, &mask.texels)?;
    }
    binary::write(&into.join(UVS), &encode_uvs(&result.layout.placements(scene)))?;
    if let Some(grid) = &lighting.probes {
        binary::write(&into.join(PROBES), &encode_probes(&grid.probes))?;
        if !grid.occlusion.is_empty() {
            binary::write(&into.join(PROBE_OCCLUSION), &encode_occlusion(&grid.occlusion))?;
        }
    }
    let text = serde_json::to_string_pretty(&manifest).map_err(BakeDirError::Encode)?;
    binary::write(&into.join(MANIFEST), text.as_bytes())
}

/// Renames the finished temporary directory to `dir`, keeping the old bake until the new
/// one is in.
fn swap_in(temp: tempfile::TempDir, parent: &Path, name: &str, dir: &Path) -> Result<(), BakeDirError> {
    let old = parent.join(format!(".{name}.old-{}", std::process::id()));
    let had_old = dir.exists();
    if had_old {
        std::fs::rename(dir, &old).map_err(BakeDirError::io(dir))?;
    }
    // On disk before the rename, so that a crash cannot leave a complete-looking bake of
    // empty files.
    for entry in std::fs::read_dir(temp.path()).map_err(BakeDirError::io(temp.path()))? {
        let path = entry.map_err(BakeDirError::io(temp.path()))?.path();
        std::fs::File::open(&path).and_then(|f| f.sync_all()).map_err(BakeDirError::io(&path))?;
    }
    let kept = temp.keep();
    if let Err(e) = std::fs::rename(&kept, dir) {
        let _ = std::fs::remove_dir_all(&kept);
        if had_old {
            let _ = std::fs::rename(&old, dir);
        }
        return Err(BakeDirError::io(dir)(e));
    }
    if had_old {
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(())
}
