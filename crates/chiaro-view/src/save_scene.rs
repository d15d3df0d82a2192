//! "Save settings": the settings as TOML, so that `chiaro render --settings` renders what
//! the viewer showed.
//!
//! "Save scene": the glTF as the viewer shows it. Light edits belong to the glTF (its
//! KHR_lights_punctual and EXT_lights_area lights and their extras), not to settings.toml, and the camera is
//! the viewer's own; so the file is written again beside the original (its buffers and
//! images stay where its URIs point) with the edited lights and a camera named
//! "chiaro view", and `chiaro render SAVED --camera "chiaro view" --settings SAVED.toml`
//! renders what the window showed.

use anyhow::{Context, Result, anyhow, bail};
use chiaro_math::camera::Projection;
use chiaro_render::View;
use chiaro_scene::{Light, LightKind, Scene, Settings};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// Writes `settings` as TOML to `path`, whole or not at all (a temporary file renamed
/// over it), so that `chiaro render --settings path` renders what the viewer showed.
pub fn save_settings(path: &Path, settings: &Settings) -> Result<()> {
    chiaro_io::output::write_file(path, settings.to_toml().as_bytes())
}

/// The name of the camera the saved file gains.
pub const VIEW_CAMERA: &str = "chiaro view";

/// Where the scene read from `source` is saved: `<stem>.chiaro.gltf` (or `.glb`) beside it.
pub fn saved_path(source: &Path) -> PathBuf {
    let stem = source.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
    let stem = stem.strip_suffix(".chiaro").unwrap_or(stem);
    let ext = source.extension().and_then(|e| e.to_str()).unwrap_or("gltf");
    source.with_file_name(format!("{stem}.chiaro.{ext}"))
}

/// Writes `scene`'s lights and `view` into a copy of the glTF at `source`, to `target`
/// (whole or not at all).
pub fn save_scene(source: &Path, scene: &Scene, view: &View, target: &Path) -> Result<()> {
    let bytes = std::fs::read(source).with_context(|| format!("{}", source.display()))?;
    let is_glb = bytes.starts_with(b"glTF");
    let (json_bytes, bin) = if is_glb {
        let (json, bin) =
            chiaro_scene::gltf_import::glb::split_glb(&bytes).map_err(|e| anyhow!("{}: {e}", source.display()))?;
        (json, bin)
    } else {
        (&bytes[..], None)
    };
    let mut root: Value =
        serde_json::from_slice(json_bytes).with_context(|| format!("{}: not glTF JSON", source.display()))?;
    write_lights(&mut root, &scene.lights).with_context(|| format!("{}", source.display()))?;
    add_camera(&mut root, view).with_context(|| format!("{}", source.display()))?;
    let text = serde_json::to_vec_pretty(&root)?;
    let out = if is_glb { glb(&text, bin) } else { text };
    chiaro_io::output::write_file(target, &out)
}

/// A GLB container of `json` and the original `bin` chunk (glTF 2.0, section 4.4).
fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |len: usize| (4 - len % 4) % 4;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.map_or(0, |b| b.len() + pad(b.len()));
    let total = 12 + 8 + json_len + bin.map_or(0, |_| 8 + bin_len);
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    if let Some(bin) = bin {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
        out.extend(std::iter::repeat_n(0u8, pad(bin.len())));
    }
    out
}

fn object<'a>(value: &'a mut Value, what: &str) -> Result<&'a mut serde_json::Map<String, Value>> {
    if value.is_null() {
        *value = json!({});
    }
    value.as_object_mut().ok_or_else(|| anyhow!("{what} is not a JSON object"))
}

/// Each scene light's values, written into the glTF light its node carries (a
/// KHR_lights_punctual light, or an EXT_lights_area one).
fn write_lights(root: &mut Value, lights: &[Light]) -> Result<()> {
    let scale_of = world_scales(root);
    for light in lights {
        let extension = if light.is_area() { "EXT_lights_area" } else { "KHR_lights_punctual" };
        let index = root["nodes"][light.node]["extensions"][extension]["light"]
            .as_u64()
            .ok_or_else(|| anyhow!("node {} carries no {extension} light", light.node))? as usize;
        let entry = &mut root["extensions"][extension]["lights"][index];
        let gltf = object(entry, &format!("light {index}"))?;
        gltf.insert("color".into(), json!(light.color.to_array()));
        gltf.insert("intensity".into(), json!(light.intensity));
        match light.range {
            Some(range) => gltf.insert("range".into(), json!(range)),
            None => gltf.remove("range"),
        };
        if let LightKind::Spot { inner_cone_rad, outer_cone_rad } = light.kind {
            gltf.insert("spot".into(), json!({ "innerConeAngle": inner_cone_rad, "outerConeAngle": outer_cone_rad }));
        }
        // EXT_lights_area sizes are the file's times the node's largest world scale.
        let size = match light.kind {
            LightKind::Rect { width, height } => {
                gltf.insert("rect".into(), json!({ "aspect": width / height }));
                Some(height)
            }
            LightKind::Disk { diameter } => Some(diameter),
            _ => None,
        };
        if let Some(size) = size {
            gltf.insert("size".into(), json!(size / scale_of[light.node]));
        }
        let extras = object(gltf.entry("extras").or_insert(Value::Null), &format!("light {index} extras"))?;
        extras.insert("shadows".into(), json!(light.shadow.mode.name()));
        extras.insert("shadowStrength".into(), json!(light.shadow.strength));
        extras.insert("shadowDepthBias".into(), json!(light.shadow.depth_bias));
        extras.insert("shadowNormalBias".into(), json!(light.shadow.normal_bias));
        extras.insert("shadowNearPlane".into(), json!(light.shadow.near_plane));
        match light.kind {
            LightKind::Directional => {
                extras.insert("angularDiameter".into(), json!(light.shadow.angular_diameter_deg));
            }
            // An area light's size is its shape's.
            LightKind::Rect { .. } | LightKind::Disk { .. } => {}
            _ => {
                extras.insert("lightRadius".into(), json!(light.shadow.light_radius));
            }
        };
        extras.insert("mode".into(), json!(light.mode.name()));
    }
    Ok(())
}

/// Each node's largest world scale (the length of its longest world axis), from the
/// file's hierarchy: what an EXT_lights_area light's size is multiplied by.
fn world_scales(root: &Value) -> Vec<f32> {
    let nodes = root["nodes"].as_array().cloned().unwrap_or_default();
    let mut parent = vec![None; nodes.len()];
    for (i, node) in nodes.iter().enumerate() {
        for child in node["children"].as_array().into_iter().flatten().filter_map(Value::as_u64) {
            if let Some(slot) = parent.get_mut(child as usize) {
                *slot = Some(i);
            }
        }
    }
    let floats = |v: &Value, n: usize, default: &[f32]| -> Vec<f32> {
        v.as_array()
            .filter(|a| a.len() == n)
            .map(|a| a.iter().map(|x| x.as_f64().unwrap_or(0.0) as f32).collect())
            .unwrap_or_else(|| default.to_vec())
    };
    let local = |node: &Value| -> glam::Mat4 {
        if node.get("matrix").is_some() {
            return glam::Mat4::from_cols_slice(&floats(&node["matrix"], 16, &glam::Mat4::IDENTITY.to_cols_array()));
        }
        let t = floats(&node["translation"], 3, &[0.0; 3]);
        let r = floats(&node["rotation"], 4, &[0.0, 0.0, 0.0, 1.0]);
        let s = floats(&node["scale"], 3, &[1.0; 3]);
        glam::Mat4::from_scale_rotation_translation(
            glam::Vec3::from_slice(&s),
            glam::Quat::from_slice(&r).normalize(),
            glam::Vec3::from_slice(&t),
        )
    };
    (0..nodes.len())
        .map(|i| {
            let (mut world, mut at, mut steps) = (local(&nodes[i]), parent[i], 0);
            // A cycle is an invalid file the importer refused; stop rather than spin.
            while let (Some(p), true) = (at, steps < nodes.len()) {
                world = local(&nodes[p]) * world;
                at = parent[p];
                steps += 1;
            }
            let scale =
                [world.x_axis, world.y_axis, world.z_axis].iter().map(|a| a.truncate().length()).fold(0.0, f32::max);
            if scale.is_finite() && scale > 0.0 { scale } else { 1.0 }
        })
        .collect()
}

/// A camera named VIEW_CAMERA at `view` (perspective or orthographic as it is), on a new
/// root node of every scene.
fn add_camera(root: &mut Value, view: &View) -> Result<()> {
    let (_, rotation, translation) = view.world_from_view.to_scale_rotation_translation();
    let camera = match view.projection {
        Projection::Perspective { yfov_rad } => {
            let mut perspective = json!({ "yfov": yfov_rad, "znear": view.znear });
            if let Some(zfar) = view.zfar {
                perspective["zfar"] = json!(zfar);
            }
            json!({ "name": VIEW_CAMERA, "type": "perspective", "perspective": perspective })
        }
        Projection::Orthographic { ymag } => {
            let zfar = view.zfar.unwrap_or(view.znear * 1.0e6);
            let orthographic = json!({ "xmag": ymag * view.aspect(), "ymag": ymag, "znear": view.znear, "zfar": zfar });
            json!({ "name": VIEW_CAMERA, "type": "orthographic", "orthographic": orthographic })
        }
    };
    let node = json!({ "name": VIEW_CAMERA, "rotation": rotation.normalize().to_array(), "translation": translation.to_array() });
    let push = |root: &mut Value, key: &str, item: Value| -> Result<usize> {
        let list = root
            .as_object_mut()
            .ok_or_else(|| anyhow!("the glTF is not a JSON object"))?
            .entry(key)
            .or_insert(json!([]))
            .as_array_mut()
            .ok_or_else(|| anyhow!("{key} is not a list"))?;
        list.push(item);
        Ok(list.len() - 1)
    };
    let camera_index = push(root, "cameras", camera)?;
    let mut node = node;
    node["camera"] = json!(camera_index);
    let node_index = push(root, "nodes", node)?;
    let scenes = root["scenes"].as_array_mut().filter(|s| !s.is_empty());
    let Some(scenes) = scenes else { bail!("the glTF has no scene to put the camera in") };
    for scene in scenes {
        let nodes = object(scene, "a scene")?.entry("nodes").or_insert(json!([]));
        nodes.as_array_mut().ok_or_else(|| anyhow!("a scene's nodes are not a list"))?.push(json!(node_index));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_render::{FrameOptions, GpuContext, Renderer};
    use chiaro_scene::ShadowMode;
    use glam::{Mat4, Vec3};

    fn asset(name: &str) -> PathBuf {
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets")).join(name)
    }

    fn ldr(scene: &Scene, view: &View) -> Vec<u8> {
        let mut renderer = Renderer::new(GpuContext::new().expect("a device")).unwrap();
        let prepared = renderer.prepare(scene).unwrap();
        let options = FrameOptions { readback: true, ..Default::default() };
        renderer.render(scene, &prepared, view, &Default::default(), options).unwrap().ldr
    }

    #[test]
    fn a_saved_scene_renders_what_the_viewer_showed() {
        let dir = tempfile::tempdir().unwrap();
        // Copied so that the saved file lands beside its buffers in a scratch folder.
        let source_dir = asset("ShadowsSpot/glTF");
        for entry in std::fs::read_dir(&source_dir).unwrap() {
            let entry = entry.unwrap();
            std::fs::copy(entry.path(), dir.path().join(entry.file_name())).unwrap();
        }
        let source = dir.path().join("shadows-spot.gltf");
        let mut scene = chiaro_scene::load_gltf(&source).unwrap();
        let spot = scene.lights.iter().position(|l| matches!(l.kind, LightKind::Spot { .. })).unwrap();
        let light = &mut scene.lights[spot];
        light.intensity *= 3.0;
        light.color = Vec3::new(1.0, 0.6, 0.3);
        light.kind = LightKind::Spot { inner_cone_rad: 0.2, outer_cone_rad: 0.45 };
        light.shadow.mode = ShadowMode::Hard;
        light.shadow.normal_bias = 1.5;
        light.shadow.near_plane = 0.3;
        let start = View::from_camera(&scene, 0, 96, 64);
        let eye = start.eye() + Vec3::new(1.0, 0.5, 0.0);
        let view = View { world_from_view: Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y).inverse(), ..start };

        let target = saved_path(&source);
        assert_eq!(target, dir.path().join("shadows-spot.chiaro.gltf"));
        save_scene(&source, &scene, &view, &target).unwrap();
        let saved = chiaro_scene::load_gltf(&target).unwrap();
        let saved_light = &saved.lights[spot];
        assert_eq!(saved_light.intensity, scene.lights[spot].intensity);
        assert_eq!(saved_light.color, scene.lights[spot].color);
        assert_eq!(saved_light.kind, scene.lights[spot].kind);
        assert_eq!(saved_light.shadow, scene.lights[spot].shadow);
        let camera = saved.find_camera(VIEW_CAMERA).expect("the view's camera");
        let saved_view = View::from_camera(&saved, camera, 96, 64);
        assert!(saved_view.world_from_view.abs_diff_eq(view.world_from_view, 1e-4));
        let (shown, rendered) = (ldr(&scene, &view), ldr(&saved, &saved_view));
        let differing = shown.iter().zip(&rendered).filter(|(a, b)| a.abs_diff(**b) > 2).count();
        assert!(differing * 1000 < shown.len(), "{differing} channels differ");
        // Saving again from the saved file writes the same name, not .chiaro.chiaro.
        assert_eq!(saved_path(&target), target);
    }

    #[test]
    fn a_saved_area_light_keeps_its_edited_size_under_a_scaled_node() {
        let dir = tempfile::tempdir().unwrap();
        let doc = json!({
            "asset": { "version": "2.0" },
            "extensionsUsed": ["EXT_lights_area"],
            "extensions": { "EXT_lights_area": { "lights": [
                { "type": "rect", "intensity": 300.0, "size": 0.5, "rect": { "aspect": 2.0 } },
                { "type": "disk", "size": 0.2 }
            ] } },
            "scene": 0,
            "scenes": [{ "nodes": [0] }],
            "nodes": [
                { "scale": [2.0, 2.0, 2.0], "children": [1, 2] },
                { "translation": [0.0, 3.0, 0.0], "extensions": { "EXT_lights_area": { "light": 0 } } },
                { "extensions": { "EXT_lights_area": { "light": 1 } } }
            ]
        });
        let source = dir.path().join("area.gltf");
        std::fs::write(&source, serde_json::to_vec(&doc).unwrap()).unwrap();
        let mut scene = chiaro_scene::load_gltf(&source).unwrap();
        assert_eq!(scene.lights[0].kind, LightKind::Rect { width: 2.0, height: 1.0 });
        scene.lights[0].kind = LightKind::Rect { width: 3.0, height: 0.5 };
        scene.lights[0].intensity = 450.0;
        scene.lights[1].kind = LightKind::Disk { diameter: 0.8 };
        let view = View::framing(&scene, 1.0, 64, 64);
        let target = saved_path(&source);
        save_scene(&source, &scene, &view, &target).unwrap();
        let saved = chiaro_scene::load_gltf(&target).unwrap();
        assert_eq!(saved.lights[0].kind, LightKind::Rect { width: 3.0, height: 0.5 });
        assert_eq!(saved.lights[0].intensity, 450.0);
        assert_eq!(saved.lights[1].kind, LightKind::Disk { diameter: 0.8 });
    }

    #[test]
    fn saved_settings_read_back_equal() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("viewer.toml");
        let mut settings = Settings::default();
        settings.shadows.max_distance = 42.0;
        settings.lights.culling = chiaro_scene::LightCulling::PerObject;
        save_settings(&path, &settings).unwrap();
        assert_eq!(chiaro_io::scenes::load_settings(Some(&path)).unwrap(), settings);
    }

    #[test]
    fn glb_containers_keep_their_binary_chunk() {
        let json = br#"{"asset":{"version":"2.0"}}"#;
        let bin = [1u8, 2, 3, 4, 5];
        let bytes = glb(json, Some(&bin));
        assert_eq!(bytes.len() % 4, 0);
        let (json_back, bin_back) = chiaro_scene::gltf_import::glb::split_glb(&bytes).unwrap();
        assert_eq!(std::str::from_utf8(json_back).unwrap().trim_end(), std::str::from_utf8(json).unwrap());
        assert_eq!(&bin_back.unwrap()[..5], &bin);
    }
}
