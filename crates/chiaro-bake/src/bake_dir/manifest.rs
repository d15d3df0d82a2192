//! `manifest.json`: what a bake directory holds and what it was made from (the scene's
//! hash, the settings, the instances and lights it names, the probe grid). A scene, its
//! settings and a `BakeResult` flow in to make one; a manifest read back flows in with a
//! scene to be checked against it, and a reason flows out where it does not fit.

use super::{BakeDirError, FORMAT_VERSION, MAX_ATLASES};
use crate::bake::{BakeResult, BakeStats, MAX_PROBES};
use crate::channels::SHADOW_MASK_CHANNELS;
use crate::layout::MAX_ATLAS_SIZE;
use chiaro_scene::settings::BakeSettings;
use chiaro_scene::{Scene, Settings};
use glam::{UVec3, Vec3};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The contents of `manifest.json`.
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
    /// The environment the sky was, where `[environment] mode = "baked"` (else the
    /// ambient term was).
    #[serde(default)]
    pub environment: Option<chiaro_scene::settings::EnvironmentSettings>,
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

/// A mixed light's shadow mask channel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestChannel {
    /// Index in the scene's lights, with its node and name to check against.
    pub light: usize,
    pub node: usize,
    pub name: String,
    pub channel: u8,
}

/// A scene light named by the manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestLight {
    pub light: usize,
    pub node: usize,
    pub name: String,
}

/// A lightmapped mesh instance.
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

/// The light probe grid's placement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestProbes {
    pub origin: [f32; 3],
    pub spacing: [f32; 3],
    pub counts: [u32; 3],
}

/// The hash of the files a scene was read from (document, buffers, images), in order.
pub fn scene_hash(scene: &Scene) -> Result<String, BakeDirError> {
    let mut hasher = blake3::Hasher::new();
    for path in &scene.inputs {
        let bytes = std::fs::read(path).map_err(BakeDirError::io(path))?;
        hasher.update(&(bytes.len() as u64).to_le_bytes());
        hasher.update(&bytes);
    }
    Ok(format!("blake3:{}", hasher.finalize().to_hex()))
}

/// The manifest of `result`, baked from `scene` with `settings`: `lightmap-N.exr` and
/// `shadowmask-N.exr` name atlas N.
pub(super) fn manifest_of(scene: &Scene, settings: &Settings, result: &BakeResult) -> Result<Manifest, BakeDirError> {
    let files = |stem: &str, count: usize| (0..count).map(|layer| format!("{stem}-{layer}.exr")).collect();
    let source = scene.source.as_deref().or(scene.inputs.first().map(PathBuf::as_path));
    Ok(Manifest {
        format_version: FORMAT_VERSION,
        scene: source.and_then(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
        scene_hash: scene_hash(scene)?,
        // The counts the quality picked, written out: the manifest says what was traced.
        settings: BakeSettings {
            samples: Some(settings.bake.texel_samples()),
            probe_samples: Some(settings.bake.probe_samples()),
            ..settings.bake.clone()
        },
        ambient: settings.render.ambient,
        environment: (settings.environment.enabled_for(scene)
            && settings.environment.mode == chiaro_scene::settings::EnvironmentMode::Baked)
            .then(|| settings.environment.clone()),
        range_threshold_lux: settings.lights.range_threshold_lux,
        lightmap_size: result.layout.size,
        lightmaps: files("lightmap", result.lighting.lightmaps.len()),
        instances: manifest_instances(scene, result),
        probes: result.lighting.probes.as_ref().map(|g| ManifestProbes {
            origin: g.origin.to_array(),
            spacing: g.spacing.to_array(),
            counts: g.counts.to_array(),
        }),
        mixed_mode: settings.lighting.mixed_mode,
        shadow_masks: files("shadowmask", result.lighting.shadow_masks.len()),
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
        demoted: result.lighting.demoted.iter().map(|&light| manifest_light(scene, light)).collect(),
        stats: result.stats,
    })
}

fn manifest_instances(scene: &Scene, result: &BakeResult) -> Vec<ManifestInstance> {
    let corners = |mesh: usize| scene.meshes[mesh].primitives.iter().map(|p| p.indices.len()).collect();
    result
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
                corners: corners(instance.mesh),
            }
        })
        .collect()
}

fn manifest_light(scene: &Scene, light: usize) -> ManifestLight {
    ManifestLight { light, node: scene.lights[light].node, name: scene.lights[light].name.clone() }
}

/// Reads the manifest at `path`.
pub(super) fn read_manifest(path: &Path) -> Result<Manifest, BakeDirError> {
    let text = std::fs::read_to_string(path).map_err(BakeDirError::io(path))?;
    serde_json::from_str(&text).map_err(|source| BakeDirError::NotAManifest { path: path.to_path_buf(), source })
}

impl Manifest {
    /// Whether the manifest (read from `path`) was made by this format for this version
    /// of `scene`, names only the scene's instances and lights, and holds numbers a bake
    /// can have. The files it lists are checked as they are read.
    pub(super) fn check_fits(&self, path: &Path, scene: &Scene) -> Result<(), BakeDirError> {
        let path = path.to_path_buf();
        if self.format_version != FORMAT_VERSION {
            return Err(BakeDirError::FormatVersion { path, found: self.format_version });
        }
        if self.scene_hash != scene_hash(scene)? {
            return Err(BakeDirError::OtherScene { path });
        }
        for m in &self.instances {
            let fits = scene.instances.get(m.instance).is_some_and(|i| {
                i.node == m.node
                    && i.name == m.name
                    && scene.meshes[i.mesh].primitives.iter().map(|p| p.indices.len()).eq(m.corners.iter().copied())
            });
            if !fits {
                return Err(BakeDirError::InstanceMismatch { path, instance: m.instance, name: m.name.clone() });
            }
        }
        let named_lights = self.channels.iter().map(|c| (c.light, c.node, &c.name));
        for (light, node, name) in named_lights.chain(self.demoted.iter().map(|d| (d.light, d.node, &d.name))) {
            if !scene.lights.get(light).is_some_and(|l| l.node == node && &l.name == name) {
                return Err(BakeDirError::LightMismatch { path, light, name: name.clone() });
            }
        }
        if !(1..=MAX_ATLAS_SIZE).contains(&self.lightmap_size) || self.lightmaps.len() > MAX_ATLASES {
            return Err(BakeDirError::Atlases { path, count: self.lightmaps.len(), size: self.lightmap_size });
        }
        Ok(())
    }

    /// The probe grid's origin, spacing and counts, refusing an empty or oversized grid
    /// or a spacing that is not positive.
    pub(super) fn probe_grid(&self, path: &Path) -> Result<Option<(Vec3, Vec3, UVec3)>, BakeDirError> {
        let Some(p) = &self.probes else {
            return Ok(None);
        };
        let counts = UVec3::from_array(p.counts);
        // u128: three u32 counts cannot overflow it.
        let n = counts.x as u128 * counts.y as u128 * counts.z as u128;
        let spacing = Vec3::from_array(p.spacing);
        if counts.min_element() == 0 || n > MAX_PROBES as u128 || !(spacing.is_finite() && spacing.min_element() > 0.0)
        {
            return Err(BakeDirError::ProbeGrid { path: path.to_path_buf(), counts: p.counts, spacing: p.spacing });
        }
        Ok(Some((Vec3::from_array(p.origin), spacing, counts)))
    }

    /// Each scene light's shadow mask channel, refusing channels past the last.
    pub(super) fn light_channels(&self, path: &Path, lights: usize) -> Result<Vec<Option<u8>>, BakeDirError> {
        let mut light_channels = vec![None; lights];
        for c in &self.channels {
            if c.channel as usize >= SHADOW_MASK_CHANNELS {
                return Err(BakeDirError::Channel {
                    path: path.to_path_buf(),
                    name: c.name.clone(),
                    channel: c.channel,
                });
            }
            light_channels[c.light] = Some(c.channel);
        }
        Ok(light_channels)
    }
}
