//! The raw JSON in, the same document rewritten into the form the `gltf` crate's typed model
//! reads out, with notes on what was set aside. The typed model is stricter than the glTF 2.0
//! specification in a few places; each rewrite here follows a rule of the specification:
//! - JSON has one number type, so an integer property written `1.0` is an integer (§3.6);
//! - `scenes[i].nodes` is optional, and a scene without it is empty;
//! - `animations[i].channels[j].target.node` is optional (an extension targets something
//!   else), so such channels are set aside: KHR_animation_pointer's are kept for the
//!   loader, with their pointer, the rest noted;
//! - a KHR_lights_punctual light of a type the extension does not define is skipped;
//! - a texture with EXT_texture_webp or KHR_texture_basisu takes its image from the
//!   extension.

use serde_json::{Map, Value};

/// The rewritten document and what the loader must know about the rewrites.
pub(super) struct Normalized {
    pub(super) json: Value,
    /// Per KHR_lights_punctual light, whether its type is one Chiaro skips.
    pub(super) skipped_lights: Vec<bool>,
    /// What was set aside, in words for `Scene::ignored`.
    pub(super) notes: Vec<String>,
    /// KHR_animation_pointer channels, taken out of their animations.
    pub(super) pointer_channels: Vec<PointerChannel>,
}

/// A KHR_animation_pointer channel: where it was, the sampler it names (checked by the
/// loader) and the JSON pointer it animates.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct PointerChannel {
    pub(super) animation: usize,
    pub(super) channel: usize,
    pub(super) sampler: Option<usize>,
    pub(super) pointer: String,
}

/// The light types KHR_lights_punctual defines.
const LIGHT_TYPES: [&str; 3] = ["directional", "point", "spot"];

pub(super) fn normalize(mut json: Value) -> Normalized {
    integral_floats_to_integers(&mut json);
    let mut notes = Vec::new();
    default_scene_nodes(&mut json);
    let pointer_channels = set_aside_channels_without_node(&mut json, &mut notes);
    let skipped_lights = skip_unknown_light_types(&mut json, &mut notes);
    take_extension_sources(&mut json);
    Normalized { json, skipped_lights, notes, pointer_channels }
}

/// Floats holding an integer value become integers, so that `"count": 3.0` reads as 3.
/// Float-typed properties accept integers, so the rewrite is safe everywhere; a value
/// with a fraction stays a float and is refused where an integer is expected.
fn integral_floats_to_integers(value: &mut Value) {
    // Integers of f64 magnitude below 2^53 are exact; larger ones are no glTF index or count.
    const EXACT: f64 = 9_007_199_254_740_992.0;
    match value {
        Value::Number(n) if n.is_f64() => {
            let f = n.as_f64().unwrap_or(f64::NAN);
            if f.fract() == 0.0 && f.abs() < EXACT {
                *value = if f >= 0.0 { Value::from(f as u64) } else { Value::from(f as i64) };
            }
        }
        Value::Array(items) => items.iter_mut().for_each(integral_floats_to_integers),
        Value::Object(map) => map.values_mut().for_each(integral_floats_to_integers),
        _ => {}
    }
}

fn array_mut<'v>(json: &'v mut Value, key: &str) -> impl Iterator<Item = &'v mut Map<String, Value>> {
    json.get_mut(key).and_then(Value::as_array_mut).into_iter().flatten().filter_map(Value::as_object_mut)
}

fn default_scene_nodes(json: &mut Value) {
    for scene in array_mut(json, "scenes") {
        scene.entry("nodes").or_insert_with(|| Value::Array(Vec::new()));
    }
}

/// The KHR_animation_pointer pointer a channel's target names, if it is one.
fn animation_pointer(channel: &Value) -> Option<String> {
    let target = channel.get("target")?;
    let pointer = target.pointer("/extensions/KHR_animation_pointer/pointer")?.as_str()?;
    (target.get("path").and_then(Value::as_str) == Some("pointer")).then(|| pointer.to_owned())
}

fn set_aside_channels_without_node(json: &mut Value, notes: &mut Vec<String>) -> Vec<PointerChannel> {
    let mut pointer_channels = Vec::new();
    for (a, animation) in array_mut(json, "animations").enumerate() {
        let Some(channels) = animation.get_mut("channels").and_then(Value::as_array_mut) else { continue };
        let without_node = |c: &Value| c.get("target").is_some_and(|t| t.is_object() && t.get("node").is_none());
        for (c, channel) in channels.iter().enumerate().filter(|(_, c)| without_node(c)) {
            if let Some(pointer) = animation_pointer(channel) {
                let sampler = channel.get("sampler").and_then(Value::as_u64).map(|s| s as usize);
                pointer_channels.push(PointerChannel { animation: a, channel: c, sampler, pointer });
            }
        }
        let before = channels.len();
        channels.retain(|c| !without_node(c));
        let dropped = before - channels.len() - pointer_channels.iter().filter(|p| p.animation == a).count();
        if dropped > 0 {
            let what = if dropped == 1 { "channel targets" } else { "channels target" };
            notes.push(format!("animations[{a}]: {dropped} {what} no node (an extension's target), ignored"));
        }
    }
    pointer_channels
}

/// Lights of an unknown type are marked skipped and given the point type, so that the
/// typed model reads the file; nothing places them.
fn skip_unknown_light_types(json: &mut Value, notes: &mut Vec<String>) -> Vec<bool> {
    let lights = json.pointer_mut("/extensions/KHR_lights_punctual/lights").and_then(Value::as_array_mut);
    let mut skipped = Vec::new();
    for (i, light) in lights.into_iter().flatten().enumerate() {
        let Some(light) = light.as_object_mut() else {
            skipped.push(false);
            continue;
        };
        let known = match light.get("type") {
            Some(Value::String(ty)) => LIGHT_TYPES.contains(&ty.as_str()),
            // A missing or non-string type is the typed model's to refuse.
            _ => true,
        };
        if !known {
            let ty = light.get("type").and_then(Value::as_str).unwrap_or_default();
            notes.push(format!(
                "extensions.KHR_lights_punctual.lights[{i}]: type \"{ty}\" is not one KHR_lights_punctual defines, \
                 light skipped"
            ));
            light.insert("type".into(), Value::from("point"));
        }
        skipped.push(!known);
    }
    skipped
}

/// EXT_texture_webp and KHR_texture_basisu name the WebP or KTX2 image; `source`, when
/// present, is a fallback for viewers without them, and Chiaro reads both.
fn take_extension_sources(json: &mut Value) {
    for texture in array_mut(json, "textures") {
        let extensions = texture.get("extensions");
        let source = ["EXT_texture_webp", "KHR_texture_basisu"]
            .iter()
            .find_map(|name| extensions.and_then(|e| e.get(*name)).and_then(|w| w.get("source")));
        if let Some(source) = source.cloned() {
            texture.insert("source".into(), source);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn integral_floats_become_integers_and_fractions_stay() {
        let mut value = json!({ "count": 3.0, "offset": -2.0, "scale": 0.5, "list": [1.0, 2.5], "big": 1e300 });
        integral_floats_to_integers(&mut value);
        assert_eq!(value, json!({ "count": 3, "offset": -2, "scale": 0.5, "list": [1, 2.5], "big": 1e300 }));
    }

    #[test]
    fn pointer_channels_are_kept_aside_and_other_nodeless_channels_noted() {
        let pointer =
            |p: &str| json!({ "path": "pointer", "extensions": { "KHR_animation_pointer": { "pointer": p } } });
        let doc = json!({ "animations": [{ "channels": [
            { "sampler": 0, "target": { "node": 0, "path": "rotation" } },
            { "sampler": 1, "target": pointer("/materials/0/emissiveFactor") },
            { "sampler": 0, "target": { "path": "weights" } },
        ], "samplers": [] }] });
        let normalized = normalize(doc);
        let channel = PointerChannel {
            animation: 0,
            channel: 1,
            sampler: Some(1),
            pointer: "/materials/0/emissiveFactor".into(),
        };
        assert_eq!(normalized.pointer_channels, vec![channel]);
        assert_eq!(normalized.json.pointer("/animations/0/channels").unwrap().as_array().unwrap().len(), 1);
        assert_eq!(normalized.notes, vec!["animations[0]: 1 channel targets no node (an extension's target), ignored"]);
    }

    #[test]
    fn unknown_light_types_are_skipped_and_known_kept() {
        let doc = json!({ "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "area" }, { "type": "spot", "spot": {} }
        ] } } });
        let normalized = normalize(doc);
        assert_eq!(normalized.skipped_lights, vec![true, false]);
        assert_eq!(normalized.json.pointer("/extensions/KHR_lights_punctual/lights/0/type"), Some(&json!("point")));
        assert_eq!(normalized.notes.len(), 1);
        assert!(normalized.notes[0].contains("\"area\""), "{:?}", normalized.notes);
    }
}
