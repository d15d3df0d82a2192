//! The parsed document in (raw JSON and typed `Root`), `Ok(())` or a [`SceneError`] out:
//! required extensions checked against [`SUPPORTED_EXTENSIONS`], indices and enums
//! validated, and each problem described in words with the offending value looked up in
//! the raw JSON (`meshes[0].primitives[0].indices: accessor 7 is out of range`).

use super::SUPPORTED_EXTENSIONS;
use crate::error::SceneError;
use gltf::json;
use json::validation::{Checked, Validate};
use serde_json::Value;
use std::path::Path;

/// `extensionsRequired` naming anything Chiaro cannot read is an error of its own kind,
/// checked on the raw JSON so that it wins over any other complaint about the file.
pub(super) fn check_required_extensions(path: &Path, raw: &Value) -> Result<(), SceneError> {
    let Some(required) = raw.get("extensionsRequired") else {
        return Ok(());
    };
    let not_strings = || SceneError::Parse {
        path: path.to_path_buf(),
        message: "extensionsRequired is not an array of strings".into(),
    };
    for name in required.as_array().ok_or_else(not_strings)? {
        let name = name.as_str().ok_or_else(not_strings)?;
        if !SUPPORTED_EXTENSIONS.contains(&name) {
            return Err(SceneError::UnsupportedExtension { path: path.to_path_buf(), extension: name.to_owned() });
        }
    }
    Ok(())
}

/// Runs the `gltf` crate's index and enum validation, after checking the one thing its
/// validation would otherwise panic on, and tolerating what Chiaro handles itself: required
/// extensions already vetted, primitives without POSITION (skipped), and POSITION accessors
/// without `min`/`max` (bounds are computed from the data).
pub(super) fn validate(path: &Path, raw: &Value, root: &json::Root) -> Result<(), SceneError> {
    let invalid = |message: String| SceneError::Invalid { path: path.to_path_buf(), message };
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    return Err(invalid(format!(
                        "meshes[{m}].primitives[{p}].attributes[\"{}\"]: accessor {} is out \
                         of range (the file has {})",
                        semantic_name(semantic),
                        accessor.value(),
                        root.accessors.len()
                    )));
                }
            }
        }
    }

    let mut problems: Vec<(json::Path, json::validation::Error)> = Vec::new();
    root.validate(root, json::Path::new, &mut |path, error| {
        let path = path();
        let p = path.as_str();
        let tolerated = p.starts_with("extensionsRequired")
            || (p.ends_with("attributes[\"POSITION\"]") && error == json::validation::Error::Missing)
            || p.ends_with("attributes[\"POSITION\"].min")
            || p.ends_with("attributes[\"POSITION\"].max")
            || optional_in_the_spec(p, error)
            || unknown_accessor_type(p, error);
        if !tolerated {
            problems.push((path, error));
        }
    });
    if problems.is_empty() {
        return Ok(());
    }
    let mut message = problems
        .iter()
        .take(3)
        .map(|(path, error)| describe_problem(raw, path.as_str(), *error))
        .collect::<Vec<_>>()
        .join("; ");
    if problems.len() > 3 {
        message += &format!("; and {} more", problems.len() - 3);
    }
    Err(invalid(message))
}

/// An accessor `type` or `componentType` glTF does not define: the validator warns
/// (VALUE_NOT_IN_LIST), and the accessor is refused where something drawn reads it
/// (`Loader::read_packed`), else read past with a note.
fn unknown_accessor_type(path: &str, error: json::validation::Error) -> bool {
    error == json::validation::Error::Invalid
        && path.strip_prefix("accessors[").is_some_and(|rest| {
            rest.split_once(']').is_some_and(|(index, field)| {
                index.parse::<usize>().is_ok() && (field == ".type" || field == ".componentType")
            })
        })
}

/// What the `gltf` crate requires and glTF 2.0 does not: an accessor without a buffer view
/// (its elements are zeros), a texture without a source (an extension may give the image,
/// or nothing uses it).
fn optional_in_the_spec(path: &str, error: json::validation::Error) -> bool {
    let missing = error == json::validation::Error::Missing;
    let under = |kind: &str, field: &str| {
        path.strip_prefix(kind).and_then(|rest| rest.strip_suffix(field)).is_some_and(|index| {
            index.strip_prefix('[').and_then(|i| i.strip_suffix(']')).is_some_and(|i| i.parse::<usize>().is_ok())
        })
    };
    missing && (under("accessors", ".bufferView") || under("textures", ".source"))
}

fn semantic_name(semantic: &Checked<json::mesh::Semantic>) -> String {
    match semantic {
        Checked::Valid(s) => s.to_string(),
        Checked::Invalid => "?".into(),
    }
}

/// One validation problem in words: `meshes[0].primitives[0].indices: accessor 7 is out of
/// range`. Validation paths use camelCased Rust field names, so the light extension's key
/// is mapped back before looking the value up.
fn describe_problem(raw: &Value, path: &str, error: json::validation::Error) -> String {
    use json::validation::Error as E;
    let path = path.replace("khrLightsPunctual", "KHR_lights_punctual");
    match error {
        E::IndexOutOfBounds => {
            let kind = index_kind(&path);
            match json_at(raw, &path).and_then(Value::as_u64) {
                Some(index) => format!("{path}: {kind} {index} is out of range"),
                None => format!("{path}: {kind} index is out of range"),
            }
        }
        E::Invalid => format!("{path}: invalid value"),
        E::Missing => format!("{path}: missing"),
        E::Oversize => format!("{path}: too large"),
        E::Unsupported => format!("{path}: not supported"),
    }
}

/// What an index at `path` points to, from the last field name on the path.
fn index_kind(path: &str) -> &'static str {
    let field = path.rsplit('.').next().unwrap_or(path).split('[').next().unwrap_or("");
    match field {
        "indices" | "attributes" | "input" | "output" | "inverseBindMatrices" | "POSITION" | "NORMAL" | "TANGENT" => {
            "accessor"
        }
        "children" | "nodes" | "node" | "joints" | "skeleton" => "node",
        "bufferView" => "buffer view",
        "buffer" => "buffer",
        "source" => "image",
        "index" => "texture",
        "material" => "material",
        "mesh" => "mesh",
        "camera" => "camera",
        "skin" => "skin",
        "sampler" => "sampler",
        "scene" => "scene",
        "light" => "light",
        _ => "index",
    }
}

/// The value at a validation path such as `meshes[0].primitives[1].attributes["NORMAL"]`.
fn json_at<'v>(mut value: &'v Value, path: &str) -> Option<&'v Value> {
    let mut rest = path;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("[\"") {
            let end = r.find("\"]")?;
            value = value.get(&r[..end])?;
            rest = &r[end + 2..];
        } else if let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']')?;
            value = value.get(r[..end].parse::<usize>().ok()?)?;
            rest = &r[end + 1..];
        } else {
            let r = rest.strip_prefix('.').unwrap_or(rest);
            let end = r.find(['.', '[']).unwrap_or(r.len());
            value = value.get(&r[..end])?;
            rest = &r[end..];
        }
    }
    Some(value)
}
