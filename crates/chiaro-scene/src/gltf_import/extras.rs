//! glTF `extras` Chiaro reads, since glTF has no place for shadow settings or cookies: a
//! light's `{"shadows": "none"|"hard"|"soft"|"pcss", "shadowStrength", "shadowDepthBias",
//! "shadowNormalBias", "shadowNearPlane", "lightRadius", "angularDiameter", "cookie": {"image": N, "size": [W, H]}, "mode":
//! "realtime"|"mixed"|"baked"}`, a mesh node's `{"castShadows":
//! "on"|"off"|"two-sided"|"shadows-only", "receiveShadows": bool, "static": bool, "label": class id}`, and a material's `{"shadowCasting": "on"|"clip"|"dither"|"off"}`. Other keys
//! are left alone; a known key with a wrong value is an error naming it.

use crate::types::{AlphaMode, CastShadows, LightMode, LightShadow, ShadowCasting, ShadowMode};
use gltf::json;
use serde::Deserialize;
use serde_json::value::RawValue;

/// A light's `extras.cookie`: a glTF image index and, for directional lights, the size in
/// metres one repeat spans.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub(super) struct CookieExtras {
    pub(super) image: usize,
    pub(super) size: Option<[f32; 2]>,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct LightExtras {
    /// Parsed on its own, so that its errors name it.
    cookie: Option<serde_json::Value>,
    shadows: Option<String>,
    shadow_strength: Option<f32>,
    shadow_depth_bias: Option<f32>,
    shadow_normal_bias: Option<f32>,
    shadow_near_plane: Option<f32>,
    light_radius: Option<f32>,
    angular_diameter: Option<f32>,
    mode: Option<serde_json::Value>,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct NodeExtras {
    cast_shadows: Option<serde_json::Value>,
    receive_shadows: Option<bool>,
    #[serde(rename = "static")]
    is_static: Option<serde_json::Value>,
    label: Option<serde_json::Value>,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct MaterialExtras {
    shadow_casting: Option<serde_json::Value>,
}

fn parse<'a, T: Deserialize<'a> + Default>(extras: Option<&'a RawValue>) -> Result<T, String> {
    match extras {
        // Extras that are not an object (a string, a number) hold nothing of ours.
        Some(raw) if raw.get().trim_start().starts_with('{') => {
            serde_json::from_str(raw.get()).map_err(|e| format!("extras: {e}"))
        }
        _ => Ok(T::default()),
    }
}

/// A directional light's disc spans less than a half sphere (tan of half of it is finite).
/// Wider is no sun: 180 degrees or more is refused.
const MAX_ANGULAR_DIAMETER_DEG: f32 = 180.0;

fn non_negative(key: &str, value: Option<f32>, default: f32) -> Result<f32, String> {
    match value {
        None => Ok(default),
        Some(v) if v.is_finite() && v >= 0.0 => Ok(v),
        Some(v) => Err(format!("extras.{key}: {v} must be a finite number >= 0")),
    }
}

/// A light's shadow settings; defaults where its extras say nothing.
pub(super) fn light_shadow(extras: Option<&RawValue>) -> Result<LightShadow, String> {
    let e: LightExtras = parse(extras)?;
    let d = LightShadow::default();
    let mode = match e.shadows.as_deref() {
        None => d.mode,
        Some("none") => ShadowMode::None,
        Some("hard") => ShadowMode::Hard,
        Some("soft") => ShadowMode::Soft,
        Some("pcss") => ShadowMode::Pcss,
        Some(other) => {
            return Err(format!("extras.shadows: '{other}' is not none, hard, soft or pcss"));
        }
    };
    let strength = non_negative("shadowStrength", e.shadow_strength, d.strength)?;
    if strength > 1.0 {
        return Err(format!("extras.shadowStrength: {strength} must be between 0 and 1"));
    }
    let angular_diameter_deg = non_negative("angularDiameter", e.angular_diameter, d.angular_diameter_deg)?;
    if angular_diameter_deg >= MAX_ANGULAR_DIAMETER_DEG {
        return Err(format!(
            "extras.angularDiameter: {angular_diameter_deg} degrees must be below {MAX_ANGULAR_DIAMETER_DEG}"
        ));
    }
    Ok(LightShadow {
        mode,
        strength,
        depth_bias: non_negative("shadowDepthBias", e.shadow_depth_bias, d.depth_bias)?,
        normal_bias: non_negative("shadowNormalBias", e.shadow_normal_bias, d.normal_bias)?,
        near_plane: non_negative("shadowNearPlane", e.shadow_near_plane, d.near_plane)?,
        light_radius: non_negative("lightRadius", e.light_radius, d.light_radius)?,
        angular_diameter_deg,
    })
}

/// A light's cookie, if its extras name one.
pub(super) fn light_cookie(extras: Option<&RawValue>) -> Result<Option<CookieExtras>, String> {
    let e: LightExtras = parse(extras)?;
    e.cookie.map(|c| serde_json::from_value(c).map_err(|e| format!("extras.cookie: {e}"))).transpose()
}

/// A light's mode: realtime unless its extras say mixed or baked.
pub(super) fn light_mode(extras: Option<&RawValue>) -> Result<LightMode, String> {
    let e: LightExtras = parse(extras)?;
    match e.mode {
        None => Ok(LightMode::Realtime),
        Some(serde_json::Value::String(s)) => match s.as_str() {
            "realtime" => Ok(LightMode::Realtime),
            "mixed" => Ok(LightMode::Mixed),
            "baked" => Ok(LightMode::Baked),
            other => Err(format!("extras.mode: '{other}' is not realtime, mixed or baked")),
        },
        Some(other) => Err(format!("extras.mode: {other} is not a string")),
    }
}

/// A mesh node's `extras.static`, if it gives one.
pub(super) fn node_static(node: &json::scene::Node) -> Result<Option<bool>, String> {
    let e: NodeExtras = parse(node.extras.as_deref())?;
    match e.is_static {
        None => Ok(None),
        Some(serde_json::Value::Bool(b)) => Ok(Some(b)),
        Some(other) => Err(format!("extras.static: {other} is not true or false")),
    }
}

/// A mesh node's `extras.label`, a class id from 0 to 2^32 - 1; 0 if it gives none.
pub(super) fn node_label(node: &json::scene::Node) -> Result<u32, String> {
    let e: NodeExtras = parse(node.extras.as_deref())?;
    match e.label {
        None => Ok(0),
        Some(value) => value
            .as_u64()
            // JSON has one number type: 3.0 is the integer 3.
            .or_else(|| value.as_f64().filter(|f| f.fract() == 0.0 && *f >= 0.0).map(|f| f as u64))
            .and_then(|n| u32::try_from(n).ok())
            .ok_or_else(|| format!("extras.label: {value} is not an integer from 0 to 4294967295")),
    }
}

/// A mesh node's (cast, receive) shadow flags.
pub(super) fn node_shadows(node: &json::scene::Node) -> Result<(CastShadows, bool), String> {
    let e: NodeExtras = parse(node.extras.as_deref())?;
    // By default casters block light with both faces, as the ray-traced reference (and
    // physics) does: a light inside a single-sided box must not light the room around
    // it. "on" keeps the casting of Catlike Coding's Custom SRP tutorials, whose
    // ShadowCaster pass draws the material's faces.
    let cast = match e.cast_shadows {
        None => CastShadows::TwoSided,
        Some(serde_json::Value::Bool(true)) => CastShadows::TwoSided,
        Some(serde_json::Value::Bool(false)) => CastShadows::Off,
        Some(serde_json::Value::String(s)) => match s.as_str() {
            "on" => CastShadows::On,
            "off" => CastShadows::Off,
            "two-sided" => CastShadows::TwoSided,
            "shadows-only" => CastShadows::ShadowsOnly,
            other => {
                return Err(format!("extras.castShadows: '{other}' is not on, off, two-sided or shadows-only"));
            }
        },
        Some(other) => return Err(format!("extras.castShadows: {other} is not a string")),
    };
    Ok((cast, e.receive_shadows.unwrap_or(true)))
}

/// How a material's surfaces cast shadows: its extras' `shadowCasting`, else what its
/// alpha mode implies.
pub(super) fn material_shadow_casting(extras: Option<&RawValue>, alpha: AlphaMode) -> Result<ShadowCasting, String> {
    let e: MaterialExtras = parse(extras)?;
    match e.shadow_casting {
        None => Ok(ShadowCasting::default_for(alpha)),
        Some(serde_json::Value::String(s)) => match s.as_str() {
            "on" => Ok(ShadowCasting::On),
            "clip" => Ok(ShadowCasting::Clip),
            "dither" => Ok(ShadowCasting::Dither),
            "off" => Ok(ShadowCasting::Off),
            other => Err(format!("extras.shadowCasting: '{other}' is not on, clip, dither or off")),
        },
        Some(other) => Err(format!("extras.shadowCasting: {other} is not a string")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raw(text: &str) -> Box<RawValue> {
        RawValue::from_string(text.to_string()).unwrap()
    }

    #[test]
    fn light_extras_override_defaults() {
        let s = light_shadow(Some(&raw(
            r#"{"shadows": "hard", "shadowStrength": 0.5, "shadowNormalBias": 2, "other": 1}"#,
        )))
        .unwrap();
        assert_eq!(s.mode, ShadowMode::Hard);
        assert_eq!(s.strength, 0.5);
        assert_eq!(s.normal_bias, 2.0);
        assert_eq!(s.depth_bias, LightShadow::default().depth_bias);
        assert_eq!(light_shadow(None).unwrap(), LightShadow::default());
        assert_eq!(light_shadow(Some(&raw(r#""a note""#))).unwrap(), LightShadow::default());
    }

    #[test]
    fn pcss_extras_set_the_light_size() {
        let s = light_shadow(Some(&raw(r#"{"shadows": "pcss", "lightRadius": 0.2, "angularDiameter": 2}"#))).unwrap();
        assert_eq!((s.mode, s.light_radius, s.angular_diameter_deg), (ShadowMode::Pcss, 0.2, 2.0));
        let d = light_shadow(Some(&raw(r#"{"shadows": "pcss"}"#))).unwrap();
        assert_eq!((d.light_radius, d.angular_diameter_deg), (0.05, 0.53));
    }

    #[test]
    fn bad_light_extras_name_the_key() {
        for (text, key) in [
            (r#"{"shadows": "fuzzy"}"#, "extras.shadows"),
            (r#"{"shadowStrength": 2}"#, "extras.shadowStrength"),
            (r#"{"shadowDepthBias": -1}"#, "extras.shadowDepthBias"),
            (r#"{"shadowNearPlane": "far"}"#, "extras"),
            (r#"{"lightRadius": -0.1}"#, "extras.lightRadius"),
            (r#"{"angularDiameter": 180}"#, "extras.angularDiameter"),
            (r#"{"angularDiameter": -1}"#, "extras.angularDiameter"),
        ] {
            let e = light_shadow(Some(&raw(text))).unwrap_err();
            assert!(e.starts_with(key), "{e}");
        }
    }

    #[test]
    fn node_extras_choose_casting() {
        let node =
            |extras: &str| json::scene::Node { extras: Some(raw(extras)), ..serde_json::from_str("{}").unwrap() };
        assert_eq!(
            node_shadows(&node(r#"{"castShadows": "shadows-only"}"#)).unwrap(),
            (CastShadows::ShadowsOnly, true)
        );
        assert_eq!(
            node_shadows(&node(r#"{"castShadows": false, "receiveShadows": false}"#)).unwrap(),
            (CastShadows::Off, false)
        );
        assert_eq!(node_shadows(&node(r#"{}"#)).unwrap().0, CastShadows::TwoSided, "both faces by default");
        assert_eq!(node_shadows(&node(r#"{"castShadows": "on"}"#)).unwrap().0, CastShadows::On);
        assert_eq!(node_shadows(&node(r#"{"castShadows": "two-sided"}"#)).unwrap().0, CastShadows::TwoSided);
        assert!(node_shadows(&node(r#"{"castShadows": "sometimes"}"#)).unwrap_err().contains("castShadows"));
    }

    #[test]
    fn light_modes_and_static_flags_parse_and_name_bad_values() {
        assert_eq!(light_mode(None).unwrap(), LightMode::Realtime);
        assert_eq!(light_mode(Some(&raw(r#"{"mode": "baked"}"#))).unwrap(), LightMode::Baked);
        assert_eq!(light_mode(Some(&raw(r#"{"mode": "mixed"}"#))).unwrap(), LightMode::Mixed);
        assert_eq!(
            light_mode(Some(&raw(r#"{"mode": "sometimes"}"#))).unwrap_err(),
            "extras.mode: 'sometimes' is not realtime, mixed or baked"
        );
        assert!(light_mode(Some(&raw(r#"{"mode": 2}"#))).unwrap_err().starts_with("extras.mode"));
        let node =
            |extras: &str| json::scene::Node { extras: Some(raw(extras)), ..serde_json::from_str("{}").unwrap() };
        assert_eq!(node_static(&node(r#"{"static": false}"#)).unwrap(), Some(false));
        assert_eq!(node_static(&node(r#"{"castShadows": "on"}"#)).unwrap(), None);
        assert!(node_static(&node(r#"{"static": "yes"}"#)).unwrap_err().starts_with("extras.static"));
        assert_eq!(node_label(&node(r#"{"label": 7}"#)).unwrap(), 7);
        assert_eq!(node_label(&node(r#"{"label": 4294967295.0}"#)).unwrap(), u32::MAX);
        assert_eq!(node_label(&node(r#"{"static": true}"#)).unwrap(), 0);
        for bad in [r#"{"label": -1}"#, r#"{"label": 1.5}"#, r#"{"label": 4294967296}"#, r#"{"label": "car"}"#] {
            assert!(node_label(&node(bad)).unwrap_err().starts_with("extras.label"), "{bad}");
        }
    }

    #[test]
    fn material_extras_choose_shadow_casting_and_alpha_modes_set_the_default() {
        assert_eq!(material_shadow_casting(None, AlphaMode::Opaque).unwrap(), ShadowCasting::On);
        assert_eq!(material_shadow_casting(None, AlphaMode::Mask).unwrap(), ShadowCasting::Clip);
        assert_eq!(material_shadow_casting(None, AlphaMode::Blend).unwrap(), ShadowCasting::Dither);
        let extras = raw(r#"{"shadowCasting": "off"}"#);
        assert_eq!(material_shadow_casting(Some(&extras), AlphaMode::Mask).unwrap(), ShadowCasting::Off);
        let extras = raw(r#"{"shadowCasting": "dither"}"#);
        assert_eq!(material_shadow_casting(Some(&extras), AlphaMode::Opaque).unwrap(), ShadowCasting::Dither);
        let e = material_shadow_casting(Some(&raw(r#"{"shadowCasting": "sometimes"}"#)), AlphaMode::Opaque);
        assert_eq!(e.unwrap_err(), "extras.shadowCasting: 'sometimes' is not on, clip, dither or off");
    }
}
