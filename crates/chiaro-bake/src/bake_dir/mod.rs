//! Bake directories: `manifest.json` (`manifest`), one `lightmap-N.exr` per atlas (RGB
//! irradiance in lux, A the texel's coverage), with shadow masks one `shadowmask-N.exr`
//! per atlas (four channels' visibility) (`atlas`), and the little-endian f32 files
//! `lightmap-uvs.bin`, `probes.bin` and with shadow masks `probe-occlusion.bin`
//! (`binary`). `write` puts them in place atomically; `read_bake_dir` reads them back and
//! checks them against their scene. Every failure is a `BakeDirError` naming the file.

mod atlas;
pub mod binary;
mod error;
pub mod manifest;
mod write;

pub use error::BakeDirError;
pub use manifest::{Manifest, ManifestChannel, ManifestInstance, ManifestLight, ManifestProbes, scene_hash};
pub use write::write_bake_dir;

use chiaro_scene::Scene;
use chiaro_scene::baked::{BakedLighting, InstanceLightmap, Lightmap, ProbeGrid, ShadowMask};
use std::path::{Path, PathBuf};

/// Bumped whenever the files or their meaning change; other versions are not read.
pub const FORMAT_VERSION: u32 = 1;
/// The manifest's file name inside a bake directory.
pub const MANIFEST: &str = "manifest.json";
const UVS: &str = "lightmap-uvs.bin";
const PROBES: &str = "probes.bin";
const PROBE_OCCLUSION: &str = "probe-occlusion.bin";
/// Most lightmap atlases a bake may have: the texture array layers every device offers.
pub const MAX_ATLASES: usize = 256;

/// Whether `dir` holds a bake this Chiaro wrote (its manifest parses as one): the only
/// kind of directory `write_bake_dir` replaces.
pub fn is_bake_dir(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join(MANIFEST)).is_ok_and(|text| serde_json::from_str::<Manifest>(&text).is_ok())
}

/// `<scene stem>.bake` beside the scene.
pub fn default_bake_dir(scene_path: &Path) -> PathBuf {
    let stem = scene_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    scene_path.with_file_name(format!("{stem}.bake"))
}

/// A bake read back and checked against its scene.
pub struct LoadedBake {
    pub manifest: Manifest,
    pub lighting: BakedLighting,
    pub placements: Vec<InstanceLightmap>,
}

/// Reads the bake at `dir` for `scene`. The error says why it does not fit (another
/// scene, another format, missing or broken files), for a warning.
pub fn read_bake_dir(dir: &Path, scene: &Scene) -> Result<LoadedBake, BakeDirError> {
    let manifest_path = dir.join(MANIFEST);
    let manifest = manifest::read_manifest(&manifest_path)?;
    manifest.check_fits(&manifest_path, scene)?;
    let read_atlases = |files: &[String]| -> Result<Vec<Lightmap>, BakeDirError> {
        files.iter().map(|file| atlas::read_exr(&dir.join(file), manifest.lightmap_size)).collect()
    };
    let shadow_masks: Vec<ShadowMask> = read_atlases(&manifest.shadow_masks)?
        .into_iter()
        .map(|map| ShadowMask { width: map.width, height: map.height, texels: map.texels })
        .collect();
    if !shadow_masks.is_empty() && shadow_masks.len() != manifest.lightmaps.len() {
        return Err(BakeDirError::MaskCount {
            path: manifest_path,
            masks: shadow_masks.len(),
            lightmaps: manifest.lightmaps.len(),
        });
    }
    let lightmaps = read_atlases(&manifest.lightmaps)?;
    // The corner counts were checked against the scene, so the file's bound is the scene's.
    let instances: Vec<(usize, u32, &[usize])> =
        manifest.instances.iter().map(|m| (m.instance, m.layer, m.corners.as_slice())).collect();
    let placements = binary::read_uvs(&dir.join(UVS), &instances)?;
    let probes = read_probe_grid(dir, &manifest_path, &manifest)?;
    let light_channels = manifest.light_channels(&manifest_path, scene.lights.len())?;
    let demoted = manifest.demoted.iter().map(|d| d.light).collect();
    let lighting = BakedLighting { lightmaps, probes, shadow_masks, light_channels, demoted };
    Ok(LoadedBake { manifest, lighting, placements })
}

/// The probe grid the manifest describes, its coefficients and (with shadow masks) its
/// occlusion read from their files.
fn read_probe_grid(dir: &Path, manifest_path: &Path, manifest: &Manifest) -> Result<Option<ProbeGrid>, BakeDirError> {
    let Some((origin, spacing, counts)) = manifest.probe_grid(manifest_path)? else {
        return Ok(None);
    };
    let n = (counts.x * counts.y * counts.z) as usize;
    let probes = binary::read_probes(&dir.join(PROBES), n)?;
    let occlusion =
        if manifest.channels.is_empty() { Vec::new() } else { binary::read_occlusion(&dir.join(PROBE_OCCLUSION), n)? };
    Ok(Some(ProbeGrid { origin, spacing, counts, probes, occlusion }))
}

/// Reads the bake at `dir` and applies it to `scene`; on any mismatch the scene is left
/// as it was and the reason comes back.
pub fn apply_bake_dir(dir: &Path, scene: &mut Scene) -> Result<Manifest, BakeDirError> {
    let loaded = read_bake_dir(dir, scene)?;
    let mut baked = scene.clone();
    chiaro_scene::baked::apply(&mut baked, loaded.lighting, &loaded.placements)
        .map_err(|message| BakeDirError::Apply { dir: dir.to_path_buf(), message })?;
    *scene = baked;
    Ok(loaded.manifest)
}
