//! Bake directories: `manifest.json`, one `lightmap-N.exr` per atlas (RGB irradiance in
//! lux, A the texel's coverage), with shadow masks one `shadowmask-N.exr` per atlas (four
//! channels' visibility), `lightmap-uvs.bin` (each lightmapped instance's corner
//! coordinates, little-endian f32 pairs), `probes.bin` (nine RGB coefficients per probe,
//! little-endian f32) and with shadow masks `probe-occlusion.bin` (four f32 per probe). Written into a temporary directory beside the target and
//! renamed into place, so a failure or an interrupt leaves nothing half-written.

use crate::bake::{BakeError, BakeResult, BakeStats, MAX_PROBES};
use crate::layout::MAX_ATLAS_SIZE;
use chiaro_math::sh::{SH_COEFFICIENTS, ShRgb};
use chiaro_scene::baked::{BakedLighting, InstanceLightmap, Lightmap, ProbeGrid, ShadowMask};
use chiaro_scene::settings::BakeSettings;
use chiaro_scene::{Scene, Settings};
use glam::{UVec3, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Bumped whenever the files or their meaning change; other versions are not read.
pub const FORMAT_VERSION: u32 = 1;
pub const MANIFEST: &str = "manifest.json";
const UVS: &str = "lightmap-uvs.bin";
const PROBES: &str = "probes.bin";
const PROBE_OCCLUSION: &str = "probe-occlusion.bin";
/// Most lightmap atlases a bake may have: the texture array layers every device offers.
pub const MAX_ATLASES: usize = 256;

/// A file's bytes, refusing one longer than `limit` before reading it (a bake directory
/// is input: a broken or hostile one must not make the reader allocate without bound).
fn read_at_most(path: &Path, limit: usize) -> Result<Vec<u8>, String> {
    let len = std::fs::metadata(path).map_err(|e| format!("{}: {e}", path.display()))?.len();
    if len > limit as u64 {
        return Err(format!("{}: {len} bytes, more than the manifest accounts for ({limit})", path.display()));
    }
    std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format_version: u32,
    /// The scene's file name, for people reading the manifest.
    pub scene: String,
    /// `blake3:` and the hash of the scene's files (`scene_hash`).
    pub scene_hash: String,
    pub settings: BakeSettings,
    /// The other settings the bake depends on.
    pub ambient: [f32; 3],
    pub range_threshold_lux: f32,
    /// Side of every atlas in texels.
    pub lightmap_size: u32,
    pub lightmaps: Vec<String>,
    pub instances: Vec<ManifestInstance>,
    pub probes: Option<ManifestProbes>,
    /// How mixed lights' shadows were baked.
    #[serde(default)]
    pub mixed_mode: chiaro_scene::MixedMode,
    /// Shadow masks, one file per lightmap atlas; empty without shadowed mixed lights.
    #[serde(default)]
    pub shadow_masks: Vec<String>,
    /// Which mixed light has which shadow mask channel.
    #[serde(default)]
    pub channels: Vec<ManifestChannel>,
    /// Mixed lights that found no channel and were baked instead.
    #[serde(default)]
    pub demoted: Vec<ManifestLight>,
    pub stats: BakeStats,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestChannel {
    /// Index in the scene's lights, with its node and name to check against.
    pub light: usize,
    pub node: usize,
    pub name: String,
    pub channel: u8,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestLight {
    pub light: usize,
    pub node: usize,
    pub name: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestInstance {
    /// Index in the scene's mesh instances, with its node and name to check against.
    pub instance: usize,
    pub node: usize,
    pub name: String,
    pub layer: u32,
    /// "texcoord1" or "generated".
    pub uv_source: String,
    pub texels_per_metre: f32,
    /// Per primitive, its corners (index count); their coordinates follow each other in
    /// `lightmap-uvs.bin`, instance after instance.
    pub corners: Vec<usize>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestProbes {
    pub origin: [f32; 3],
    pub spacing: [f32; 3],
    pub counts: [u32; 3],
}

/// The hash of the files a scene was read from (document, buffers, images), in order.
pub fn scene_hash(scene: &Scene) -> Result<String, BakeError> {
    let mut hasher = blake3::Hasher::new();
    for path in &scene.inputs {
        let bytes = std::fs::read(path).map_err(|e| BakeError::Io { path: path.clone(), message: e.to_string() })?;
        hasher.update(&(bytes.len() as u64).to_le_bytes());
        hasher.update(&bytes);
    }
    Ok(format!("blake3:{}", hasher.finalize().to_hex()))
}

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

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> BakeError + '_ {
    move |e| BakeError::Io { path: path.to_path_buf(), message: e.to_string() }
}

/// Writes `result` as the bake directory `dir`, replacing one that is there. Nothing is
/// left at `dir` or beside it if this fails or `cancel` is set before the final rename.
pub fn write_bake_dir(
    dir: &Path,
    scene: &Scene,
    settings: &Settings,
    result: &BakeResult,
    cancel: &AtomicBool,
) -> Result<(), BakeError> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = dir.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "bake".into());
    let temp = tempfile::Builder::new().prefix(&format!(".{name}.")).tempdir_in(parent).map_err(io_error(parent))?;
    let manifest = manifest_of(scene, settings, result)?;

    let mut lightmap_files = Vec::new();
    for (layer, lightmap) in result.lighting.lightmaps.iter().enumerate() {
        let file = format!("lightmap-{layer}.exr");
        write_exr(&temp.path().join(&file), lightmap.width, lightmap.height, &lightmap.texels)?;
        lightmap_files.push(file);
    }
    let mut mask_files = Vec::new();
    for (layer, mask) in result.lighting.shadow_masks.iter().enumerate() {
        let file = format!("shadowmask-{layer}.exr");
        write_exr(&temp.path().join(&file), mask.width, mask.height, &mask.texels)?;
        mask_files.push(file);
    }
    let mut uvs: Vec<u8> = Vec::new();
    for placement in result.layout.placements(scene) {
        for uv in placement.corner_uvs.iter().flatten() {
            uvs.extend_from_slice(&uv.x.to_le_bytes());
            uvs.extend_from_slice(&uv.y.to_le_bytes());
        }
    }
    let path = temp.path().join(UVS);
    std::fs::write(&path, uvs).map_err(io_error(&path))?;
    if let Some(grid) = &result.lighting.probes {
        let mut bytes = Vec::with_capacity(grid.probes.len() * SH_COEFFICIENTS * 12);
        for c in grid.probes.iter().flat_map(|p| p.coefficients) {
            for v in c.to_array() {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        let path = temp.path().join(PROBES);
        std::fs::write(&path, bytes).map_err(io_error(&path))?;
        if !grid.occlusion.is_empty() {
            let bytes: Vec<u8> = grid.occlusion.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
            let path = temp.path().join(PROBE_OCCLUSION);
            std::fs::write(&path, bytes).map_err(io_error(&path))?;
        }
    }
    let manifest = Manifest { lightmaps: lightmap_files, shadow_masks: mask_files, ..manifest };
    let path = temp.path().join(MANIFEST);
    let text = serde_json::to_string_pretty(&manifest).map_err(|e| BakeError::Invalid(e.to_string()))?;
    std::fs::write(&path, text).map_err(io_error(&path))?;

    if cancel.load(Ordering::Relaxed) {
        return Err(BakeError::Cancelled);
    }
    // Swap in: the old bake moves aside first, and is removed only once the new one is in.
    let old = parent.join(format!(".{name}.old-{}", std::process::id()));
    let had_old = dir.exists();
    if had_old {
        std::fs::rename(dir, &old).map_err(io_error(dir))?;
    }
    // On disk before the rename, so that a crash cannot leave a complete-looking bake of
    // empty files.
    for entry in std::fs::read_dir(temp.path()).map_err(io_error(temp.path()))? {
        let path = entry.map_err(io_error(temp.path()))?.path();
        std::fs::File::open(&path).and_then(|f| f.sync_all()).map_err(io_error(&path))?;
    }
    let kept = temp.keep();
    if let Err(e) = std::fs::rename(&kept, dir) {
        let _ = std::fs::remove_dir_all(&kept);
        if had_old {
            let _ = std::fs::rename(&old, dir);
        }
        return Err(io_error(dir)(e));
    }
    if had_old {
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(())
}

fn manifest_of(scene: &Scene, settings: &Settings, result: &BakeResult) -> Result<Manifest, BakeError> {
    let source = scene.source.as_deref().or(scene.inputs.first().map(PathBuf::as_path));
    let instances = result
        .layout
        .instances
        .iter()
        .map(|layout| {
            let instance = &scene.instances[layout.instance];
            ManifestInstance {
                instance: layout.instance,
                node: instance.node,
                name: instance.name.clone(),
                layer: layout.layer,
                uv_source: layout.uv_source.name().into(),
                texels_per_metre: layout.texels_per_metre,
                corners: scene.meshes[instance.mesh].primitives.iter().map(|p| p.indices.len()).collect(),
            }
        })
        .collect();
    Ok(Manifest {
        format_version: FORMAT_VERSION,
        scene: source.and_then(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
        scene_hash: scene_hash(scene)?,
        settings: settings.bake.clone(),
        ambient: settings.render.ambient,
        range_threshold_lux: settings.lights.range_threshold_lux,
        lightmap_size: result.layout.size,
        lightmaps: Vec::new(),
        instances,
        probes: result.lighting.probes.as_ref().map(|g| ManifestProbes {
            origin: g.origin.to_array(),
            spacing: g.spacing.to_array(),
            counts: g.counts.to_array(),
        }),
        mixed_mode: settings.lighting.mixed_mode,
        shadow_masks: Vec::new(),
        channels: result
            .lighting
            .light_channels
            .iter()
            .enumerate()
            .filter_map(|(light, channel)| {
                let l = &scene.lights[light];
                channel.map(|channel| ManifestChannel { light, node: l.node, name: l.name.clone(), channel })
            })
            .collect(),
        demoted: result
            .lighting
            .demoted
            .iter()
            .map(|&light| ManifestLight {
                light,
                node: scene.lights[light].node,
                name: scene.lights[light].name.clone(),
            })
            .collect(),
        stats: result.stats,
    })
}

/// An atlas of four float channels (a lightmap or a shadow mask) as RGBA float32 EXR.
fn write_exr(path: &Path, width: u32, height: u32, texels: &[[f32; 4]]) -> Result<(), BakeError> {
    use exr::prelude::*;
    let w = width as usize;
    let pixels = SpecificChannels::rgba(|p: Vec2<usize>| {
        let t = texels[p.1 * w + p.0];
        (t[0], t[1], t[2], t[3])
    });
    Image::from_channels((w, height as usize), pixels)
        .write()
        .to_file(path)
        .map_err(|e| BakeError::Io { path: path.to_path_buf(), message: e.to_string() })
}

/// Reads an atlas of `size` x `size` texels; the header is checked first, so a file
/// cannot make the reader allocate more than that.
fn read_exr(path: &Path, size: u32) -> Result<Lightmap, String> {
    use exr::prelude::*;
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| format!("{}: {e}", path.display()))?;
    let declared = meta.headers.first().map(|h| h.layer_size);
    if declared.is_none_or(|s| s.width() != size as usize || s.height() != size as usize) {
        return Err(format!("{}: not {size}x{size} texels, as the manifest says", path.display()));
    }
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| (resolution.width(), vec![[0.0f32; 4]; resolution.width() * resolution.height()]),
        |(width, texels), position, (r, g, b, a): (f32, f32, f32, f32)| {
            texels[position.y() * *width + position.x()] = [r, g, b, a];
        },
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    let size = image.layer_data.size;
    let (_, texels) = image.layer_data.channel_data.pixels;
    Ok(Lightmap { width: size.width() as u32, height: size.height() as u32, texels })
}

/// A bake read back and checked against its scene.
pub struct LoadedBake {
    pub manifest: Manifest,
    pub lighting: BakedLighting,
    pub placements: Vec<InstanceLightmap>,
}

/// Reads the bake at `dir` for `scene`. The error says why it does not fit (another
/// scene, another format, missing or broken files), for a warning.
pub fn read_bake_dir(dir: &Path, scene: &Scene) -> Result<LoadedBake, String> {
    let manifest_path = dir.join(MANIFEST);
    let text = std::fs::read_to_string(&manifest_path).map_err(|e| format!("{}: {e}", manifest_path.display()))?;
    let manifest: Manifest =
        serde_json::from_str(&text).map_err(|e| format!("{}: not a bake manifest: {e}", manifest_path.display()))?;
    if manifest.format_version != FORMAT_VERSION {
        return Err(format!(
            "{}: format version {} (this Chiaro reads {FORMAT_VERSION}); bake again",
            manifest_path.display(),
            manifest.format_version
        ));
    }
    let hash = scene_hash(scene).map_err(|e| e.to_string())?;
    if manifest.scene_hash != hash {
        return Err(format!(
            "{}: made for another version of the scene (its files' hash differs); bake again",
            manifest_path.display()
        ));
    }
    for m in &manifest.instances {
        let fits = scene.instances.get(m.instance).is_some_and(|i| {
            i.node == m.node
                && i.name == m.name
                && scene.meshes[i.mesh].primitives.iter().map(|p| p.indices.len()).eq(m.corners.iter().copied())
        });
        if !fits {
            return Err(format!(
                "{}: instance {} ({}) does not match the scene",
                manifest_path.display(),
                m.instance,
                m.name
            ));
        }
    }
    for (light, node, name) in manifest
        .channels
        .iter()
        .map(|c| (c.light, c.node, &c.name))
        .chain(manifest.demoted.iter().map(|d| (d.light, d.node, &d.name)))
    {
        if !scene.lights.get(light).is_some_and(|l| l.node == node && &l.name == name) {
            return Err(format!("{}: light {light} ({name}) does not match the scene", manifest_path.display()));
        }
    }
    if !(1..=MAX_ATLAS_SIZE).contains(&manifest.lightmap_size) || manifest.lightmaps.len() > MAX_ATLASES {
        return Err(format!(
            "{}: {} atlases of {} texels (at most {MAX_ATLASES} of {MAX_ATLAS_SIZE})",
            manifest_path.display(),
            manifest.lightmaps.len(),
            manifest.lightmap_size
        ));
    }
    let shadow_masks = manifest
        .shadow_masks
        .iter()
        .map(|file| {
            let map = read_exr(&dir.join(file), manifest.lightmap_size)?;
            Ok(ShadowMask { width: map.width, height: map.height, texels: map.texels })
        })
        .collect::<Result<Vec<_>, String>>()?;
    if !shadow_masks.is_empty() && shadow_masks.len() != manifest.lightmaps.len() {
        return Err(format!(
            "{}: {} shadow masks for {} lightmaps",
            manifest_path.display(),
            shadow_masks.len(),
            manifest.lightmaps.len()
        ));
    }
    let lightmaps = manifest
        .lightmaps
        .iter()
        .map(|file| read_exr(&dir.join(file), manifest.lightmap_size))
        .collect::<Result<Vec<_>, String>>()?;
    let uv_path = dir.join(UVS);
    // The corner counts were checked against the scene above, so this bound is the scene's.
    let wanted: usize = manifest.instances.iter().flat_map(|m| &m.corners).sum::<usize>() * 2;
    let bytes = read_at_most(&uv_path, wanted * 4)?;
    let floats: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    if floats.len() != wanted || bytes.len() % 4 != 0 {
        return Err(format!("{}: {} values, the manifest needs {wanted}", uv_path.display(), floats.len()));
    }
    let mut cursor = floats.chunks_exact(2).map(|p| Vec2::new(p[0], p[1]));
    let placements = manifest
        .instances
        .iter()
        .map(|m| InstanceLightmap {
            instance: m.instance,
            layer: m.layer,
            corner_uvs: m.corners.iter().map(|&n| cursor.by_ref().take(n).collect()).collect(),
        })
        .collect();
    let probes = match &manifest.probes {
        Some(p) => {
            let counts = UVec3::from_array(p.counts);
            // u128: three u32 counts cannot overflow it.
            let n = counts.x as u128 * counts.y as u128 * counts.z as u128;
            let spacing = Vec3::from_array(p.spacing);
            if counts.min_element() == 0
                || n > MAX_PROBES as u128
                || !(spacing.is_finite() && spacing.min_element() > 0.0)
            {
                return Err(format!(
                    "{}: a probe grid of {:?} probes {:?} m apart (1 to {MAX_PROBES} probes, positive spacing)",
                    manifest_path.display(),
                    p.counts,
                    p.spacing
                ));
            }
            let n = n as usize;
            let path = dir.join(PROBES);
            let bytes = read_at_most(&path, n * SH_COEFFICIENTS * 12)?;
            if bytes.len() != n * SH_COEFFICIENTS * 12 {
                return Err(format!(
                    "{}: {} bytes, {n} probes need {}",
                    path.display(),
                    bytes.len(),
                    n * SH_COEFFICIENTS * 12
                ));
            }
            let values: Vec<f32> =
                bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
            let probes = values
                .chunks_exact(SH_COEFFICIENTS * 3)
                .map(|c| ShRgb {
                    coefficients: std::array::from_fn(|k| Vec3::new(c[3 * k], c[3 * k + 1], c[3 * k + 2])),
                })
                .collect();
            let occlusion_path = dir.join(PROBE_OCCLUSION);
            let occlusion = if manifest.channels.is_empty() {
                Vec::new()
            } else {
                let bytes = read_at_most(&occlusion_path, n * 16)?;
                if bytes.len() != n * 16 {
                    return Err(format!(
                        "{}: {} bytes, {n} probes need {}",
                        occlusion_path.display(),
                        bytes.len(),
                        n * 16
                    ));
                }
                bytes
                    .chunks_exact(16)
                    .map(|c| {
                        std::array::from_fn(|k| {
                            f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
                        })
                    })
                    .collect()
            };
            Some(ProbeGrid { origin: Vec3::from_array(p.origin), spacing, counts, probes, occlusion })
        }
        None => None,
    };
    let mut light_channels = vec![None; scene.lights.len()];
    for c in &manifest.channels {
        if c.channel as usize >= crate::channels::SHADOW_MASK_CHANNELS {
            return Err(format!("{}: light {} has channel {}", manifest_path.display(), c.name, c.channel));
        }
        light_channels[c.light] = Some(c.channel);
    }
    let demoted = manifest.demoted.iter().map(|d| d.light).collect();
    let lighting = BakedLighting { lightmaps, probes, shadow_masks, light_channels, demoted };
    Ok(LoadedBake { manifest, lighting, placements })
}

/// Reads the bake at `dir` and applies it to `scene`; on any mismatch the scene is left
/// as it was and the reason comes back.
pub fn apply_bake_dir(dir: &Path, scene: &mut Scene) -> Result<Manifest, String> {
    let loaded = read_bake_dir(dir, scene)?;
    let mut baked = scene.clone();
    chiaro_scene::baked::apply(&mut baked, loaded.lighting, &loaded.placements)
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    *scene = baked;
    Ok(loaded.manifest)
}
