//! A job's `camera`: absent (the scene's first glTF camera, else one framing the scene, as
//! `chiaro render` chooses), a camera's name or index, or an object placing a camera by
//! eye and target (perspective, or orthographic with `ymag`). JSON flows in; the frame's view flows out once the scene is loaded.

use crate::error_line;
use chiaro_math::camera::LookAt;
use chiaro_render::View;
use chiaro_scene::{Scene, Settings};
use glam::Vec3;
use serde_json::{Map, Value};

/// The near plane of a placed camera without `znear`, metres (as `chiaro.Camera.look_at`).
pub const DEFAULT_ZNEAR_M: f32 = 0.05;
/// The keys of the object form.
const KEYS: [&str; 7] = ["eye", "target", "up", "yfov_deg", "ymag", "znear", "zfar"];

/// The camera a job asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraSpec {
    /// The scene's first camera, or one that frames its bounds.
    Default,
    /// A glTF camera by name, or by index when the text is digits (as `--camera` reads it).
    Key(String),
    /// A glTF camera by index into the scene's cameras.
    Index(usize),
    /// A camera placed by eye and target.
    Placed(LookAt),
}

impl CameraSpec {
    /// Reads the `camera` value; `auto_yfov_deg` is the placed camera's default field of
    /// view (the settings' `camera.auto_yfov_deg`). The message starts with `camera`.
    pub fn parse(value: Option<&Value>, auto_yfov_deg: f32) -> Result<CameraSpec, String> {
        match value {
            None | Some(Value::Null) => Ok(CameraSpec::Default),
            Some(Value::String(key)) => Ok(CameraSpec::Key(key.clone())),
            Some(Value::Number(n)) => match (n.as_u64(), n.as_i64()) {
                (Some(index), _) => Ok(CameraSpec::Index(usize::try_from(index).unwrap_or(usize::MAX))),
                (None, Some(negative)) => Err(format!("camera: index {negative} is negative")),
                _ => Err(format!("camera: {n} is not a camera index (a whole number)")),
            },
            Some(Value::Object(fields)) => placed(fields, auto_yfov_deg).map(CameraSpec::Placed),
            Some(other) => Err(format!(
                "camera: expected a camera name, an index or {{\"eye\": [x, y, z], \"target\": [x, y, z]}}, not {}",
                kind(other)
            )),
        }
    }

    /// The frame's view of `scene` at `width` x `height`; an unknown camera names the
    /// scene's cameras.
    pub fn view(&self, scene: &Scene, settings: &Settings, width: u32, height: u32) -> Result<View, String> {
        let choose = |key: Option<&str>| {
            chiaro_io::scenes::choose_view(scene, key, settings, width, height)
                .map_err(|e| format!("camera: {}", error_line(&e)))
        };
        match self {
            CameraSpec::Default => choose(None),
            CameraSpec::Key(key) => choose(Some(key)),
            CameraSpec::Index(index) => choose(Some(&index.to_string())),
            CameraSpec::Placed(placed) => {
                let world_from_view = placed.world_from_view().map_err(|e| format!("camera: {e}"))?;
                Ok(View::projected(world_from_view, placed.projection(), placed.znear, placed.zfar, width, height))
            }
        }
    }
}

/// The object form, checked whole (eye on target, up along the view) before any scene loads.
fn placed(fields: &Map<String, Value>, auto_yfov_deg: f32) -> Result<LookAt, String> {
    if let Some(key) = fields.keys().find(|k| !KEYS.contains(&k.as_str())) {
        return Err(format!("camera: unknown key '{key}' (a placed camera's keys: {})", KEYS.join(", ")));
    }
    let vector = |key: &str, default: Option<Vec3>| -> Result<Vec3, String> {
        match (fields.get(key), default) {
            (None | Some(Value::Null), Some(d)) => Ok(d),
            (None | Some(Value::Null), None) => Err(format!("camera: '{key}' is missing ([x, y, z] in metres)")),
            (Some(value), _) => {
                let numbers: Option<Vec<f32>> =
                    value.as_array().filter(|a| a.len() == 3).map(|a| a.iter().filter_map(number).collect());
                match numbers {
                    Some(v) if v.len() == 3 => Ok(Vec3::new(v[0], v[1], v[2])),
                    _ => Err(format!("camera.{key}: expected [x, y, z], three numbers, not {value}")),
                }
            }
        }
    };
    let scalar = |key: &str| -> Result<Option<f32>, String> {
        match fields.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(value) => {
                number(value).map(Some).ok_or_else(|| format!("camera.{key}: expected a number, not {value}"))
            }
        }
    };
    let ymag = scalar("ymag")?;
    if ymag.is_some() && fields.get("yfov_deg").is_some_and(|v| !v.is_null()) {
        return Err("camera: 'yfov_deg' and 'ymag' both given (a camera is perspective or orthographic)".into());
    }
    let placed = LookAt {
        eye: vector("eye", None)?,
        target: vector("target", None)?,
        up: vector("up", Some(Vec3::Y))?,
        yfov_deg: scalar("yfov_deg")?.unwrap_or(auto_yfov_deg),
        ymag,
        znear: scalar("znear")?.unwrap_or(DEFAULT_ZNEAR_M),
        zfar: scalar("zfar")?,
    };
    placed.world_from_view().map_err(|e| format!("camera: {e}"))?;
    Ok(placed)
}

fn number(value: &Value) -> Option<f32> {
    value.as_f64().map(|v| v as f32)
}

/// A JSON value's kind, for messages.
pub(crate) fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn parse(value: Value) -> Result<CameraSpec, String> {
        CameraSpec::parse(Some(&value), 45.0)
    }

    #[test]
    fn names_indices_and_absence_choose_as_render_does() {
        assert_eq!(CameraSpec::parse(None, 45.0).unwrap(), CameraSpec::Default);
        assert_eq!(parse(Value::Null).unwrap(), CameraSpec::Default);
        assert_eq!(parse(json!("Camera")).unwrap(), CameraSpec::Key("Camera".into()));
        assert_eq!(parse(json!(2)).unwrap(), CameraSpec::Index(2));
        assert_eq!(parse(json!(-1)).unwrap_err(), "camera: index -1 is negative");
        assert!(parse(json!(1.5)).unwrap_err().contains("not a camera index"));
        assert!(parse(json!(true)).unwrap_err().ends_with("not a boolean"));
        let scene = Scene::default();
        let e = parse(json!("front")).unwrap().view(&scene, &Settings::default(), 8, 8).unwrap_err();
        assert_eq!(e, "camera: no camera 'front' in the scene (cameras: none)");
    }

    #[test]
    fn a_placed_camera_takes_defaults_and_refuses_bad_values() {
        let CameraSpec::Placed(p) = parse(json!({"eye": [0, 1, 5], "target": [0, 1, 0]})).unwrap() else {
            panic!("placed")
        };
        assert_eq!((p.up, p.yfov_deg, p.znear, p.zfar), (Vec3::Y, 45.0, DEFAULT_ZNEAR_M, None));
        let view = CameraSpec::Placed(p).view(&Scene::default(), &Settings::default(), 64, 32).unwrap();
        assert_eq!((view.width, view.height), (64, 32));
        assert!((view.eye() - Vec3::new(0.0, 1.0, 5.0)).length() < 1e-5);
        let e = parse(json!({"eye": [0, 1, 5], "target": [0, 1, 0], "fov": 30})).unwrap_err();
        assert!(e.starts_with("camera: unknown key 'fov'"), "{e}");
        assert_eq!(parse(json!({"target": [0, 0, 0]})).unwrap_err(), "camera: 'eye' is missing ([x, y, z] in metres)");
        let e = parse(json!({"eye": [0, 1], "target": [0, 0, 0]})).unwrap_err();
        assert_eq!(e, "camera.eye: expected [x, y, z], three numbers, not [0,1]");
        let e = parse(json!({"eye": [1, 1, 1], "target": [1, 1, 1]})).unwrap_err();
        assert_eq!(e, "camera: look_at: eye and target are the same point");
        let e = parse(json!({"eye": [0, 5, 0], "target": [0, 0, 0]})).unwrap_err();
        assert_eq!(e, "camera: look_at: up is zero or parallel to the viewing direction");
        let e = parse(json!({"eye": [0, 1, 5], "target": [0, 0, 0], "yfov_deg": 0})).unwrap_err();
        assert_eq!(e, "camera: yfov_deg: 0 is not between 0 and 180 degrees");
    }

    #[test]
    fn a_placed_camera_with_ymag_is_orthographic_and_needs_a_far_plane() {
        let spec = parse(json!({"eye": [0, 1, 5], "target": [0, 1, 0], "ymag": 2.0, "zfar": 20})).unwrap();
        let view = spec.view(&Scene::default(), &Settings::default(), 64, 32).unwrap();
        assert!(view.is_orthographic());
        // Half height 2 m, half width 4 m at a 2:1 image: x = 4 m right of the axis is the edge.
        let edge = view.clip_from_world().project_point3(Vec3::new(4.0, 3.0, -3.0));
        assert!((edge.x - 1.0).abs() < 1e-5 && (edge.y - 1.0).abs() < 1e-5, "{edge}");
        let e = parse(json!({"eye": [0, 1, 5], "target": [0, 1, 0], "ymag": 2.0})).unwrap_err();
        assert_eq!(e, "camera: zfar: an orthographic camera (ymag) needs a far plane");
        let e = parse(json!({"eye": [0, 1, 5], "target": [0, 1, 0], "ymag": 2.0, "zfar": 9, "yfov_deg": 30}));
        assert_eq!(
            e.unwrap_err(),
            "camera: 'yfov_deg' and 'ymag' both given (a camera is perspective or orthographic)"
        );
        let e = parse(json!({"eye": [0, 1, 5], "target": [0, 1, 0], "ymag": -1, "zfar": 9})).unwrap_err();
        assert_eq!(e, "camera: ymag: -1 is not a positive distance");
    }
}
