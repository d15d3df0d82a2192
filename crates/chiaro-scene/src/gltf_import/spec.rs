//! The glTF 2.0 rules the `gltf` crate's validation leaves out, checked on the typed model
//! (with the raw JSON for extension data): material factors within their ranges, vertex
//! attributes and indices of the component types the spec allows (more with
//! KHR_mesh_quantization), buffer-view strides that hold their elements, the UV sets that
//! materials ask for, and nodes with either a matrix or TRS. The first broken rule is returned in words, starting with its JSON path.

use gltf::json;
use json::accessor::{ComponentType, Type};
use json::mesh::Semantic;
use json::validation::Checked;
use serde_json::Value;

pub(super) fn check_spec(raw: &Value, root: &json::Root) -> Result<(), String> {
    let quantized = raw
        .get("extensionsUsed")
        .and_then(Value::as_array)
        .is_some_and(|used| used.iter().any(|e| e.as_str() == Some("KHR_mesh_quantization")));
    check_materials(raw, root)?;
    check_strides(root)?;
    check_primitives(raw, root, quantized)?;
    check_nodes(raw)
}

fn in_unit_range(path: &str, value: f32) -> Result<(), String> {
    if (0.0..=1.0).contains(&value) { Ok(()) } else { Err(format!("{path}: {value} is outside [0, 1]")) }
}

fn check_materials(raw: &Value, root: &json::Root) -> Result<(), String> {
    for (i, m) in root.materials.iter().enumerate() {
        let pbr = &m.pbr_metallic_roughness;
        for (k, &c) in pbr.base_color_factor.0.iter().enumerate() {
            in_unit_range(&format!("materials[{i}].pbrMetallicRoughness.baseColorFactor[{k}]"), c)?;
        }
        in_unit_range(&format!("materials[{i}].pbrMetallicRoughness.metallicFactor"), pbr.metallic_factor.0)?;
        in_unit_range(&format!("materials[{i}].pbrMetallicRoughness.roughnessFactor"), pbr.roughness_factor.0)?;
        for (k, &c) in m.emissive_factor.0.iter().enumerate() {
            in_unit_range(&format!("materials[{i}].emissiveFactor[{k}]"), c)?;
        }
        if let Some(occlusion) = &m.occlusion_texture {
            in_unit_range(&format!("materials[{i}].occlusionTexture.strength"), occlusion.strength.0)?;
        }
        if let Some(cutoff) = m.alpha_cutoff
            && cutoff.0 < 0.0
        {
            return Err(format!("materials[{i}].alphaCutoff: {} is negative", cutoff.0));
        }
        let strength = raw
            .pointer(&format!("/materials/{i}/extensions/KHR_materials_emissive_strength/emissiveStrength"))
            .and_then(Value::as_f64);
        if let Some(s) = strength.filter(|s| *s < 0.0) {
            return Err(format!(
                "materials[{i}].extensions.KHR_materials_emissive_strength.emissiveStrength: {s} is negative"
            ));
        }
    }
    Ok(())
}

/// Bytes of one element of an accessor.
fn element_size(accessor: &json::Accessor) -> Option<usize> {
    let (Checked::Valid(component), Checked::Valid(ty)) = (accessor.component_type, accessor.type_) else {
        return None;
    };
    Some(component.0.size() * ty.multiplicity())
}

fn check_strides(root: &json::Root) -> Result<(), String> {
    for (v, view) in root.buffer_views.iter().enumerate() {
        if let Some(stride) = view.byte_stride
            && stride.0 % 4 != 0
        {
            return Err(format!("bufferViews[{v}].byteStride: {} is not a multiple of 4", stride.0));
        }
    }
    for (a, accessor) in root.accessors.iter().enumerate() {
        let (Some(view), Some(size)) = (accessor.buffer_view, element_size(accessor)) else {
            continue;
        };
        if let Some(stride) = root.buffer_views[view.value()].byte_stride
            && stride.0 < size
        {
            return Err(format!(
                "accessors[{a}]: its elements are {size} bytes, more than bufferViews[{}].byteStride ({}), so \
                 they would overlap",
                view.value(),
                stride.0
            ));
        }
    }
    Ok(())
}

fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}

/// Whether an attribute may use `component` (normalized or not): glTF 2.0 §3.7.2.1, and
/// KHR_mesh_quantization's additions where the file uses it.
fn attribute_component_allowed(
    semantic: &Semantic,
    component: ComponentType,
    normalized: bool,
    quantized: bool,
) -> bool {
    use ComponentType::*;
    let core = match semantic {
        Semantic::Positions | Semantic::Normals | Semantic::Tangents => component == F32,
        Semantic::TexCoords(_) | Semantic::Colors(_) => {
            component == F32 || (normalized && matches!(component, U8 | U16))
        }
        _ => true,
    };
    let quantization = quantized
        && match semantic {
            Semantic::Positions | Semantic::TexCoords(_) => matches!(component, I8 | U8 | I16 | U16),
            Semantic::Normals | Semantic::Tangents => normalized && matches!(component, I8 | I16),
            _ => false,
        };
    core || quantization
}

fn expected_types(semantic: &Semantic) -> &'static [Type] {
    match semantic {
        Semantic::Positions | Semantic::Normals => &[Type::Vec3],
        Semantic::Tangents => &[Type::Vec4],
        Semantic::TexCoords(_) => &[Type::Vec2],
        Semantic::Colors(_) => &[Type::Vec3, Type::Vec4],
        _ => &[],
    }
}

fn check_primitives(raw: &Value, root: &json::Root, quantized: bool) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let here = format!("meshes[{m}].primitives[{p}]");
            for (semantic, accessor_index) in &primitive.attributes {
                let Checked::Valid(semantic) = semantic else { continue };
                let accessor = &root.accessors[accessor_index.value()];
                let (Checked::Valid(component), Checked::Valid(ty)) = (accessor.component_type, accessor.type_) else {
                    continue;
                };
                let name = semantic.to_string();
                let path = format!("{here}.attributes[\"{name}\"]");
                let types = expected_types(semantic);
                if !types.is_empty() && !types.contains(&ty) {
                    return Err(format!(
                        "{path}: accessor {} is {ty:?}, which {name} cannot be",
                        accessor_index.value()
                    ));
                }
                if !attribute_component_allowed(semantic, component.0, accessor.normalized, quantized) {
                    let normalized = if accessor.normalized { "normalized " } else { "" };
                    let hint = if quantized { "" } else { " (without KHR_mesh_quantization)" };
                    return Err(format!(
                        "{path}: accessor {} holds {normalized}{}, which {name} cannot be{hint}",
                        accessor_index.value(),
                        component_name(component.0)
                    ));
                }
            }
            if let Some(indices) = primitive.indices {
                let accessor = &root.accessors[indices.value()];
                let path = format!("{here}.indices");
                let component = match accessor.component_type {
                    Checked::Valid(c) => c.0,
                    Checked::Invalid => continue,
                };
                let integer = matches!(component, ComponentType::U8 | ComponentType::U16 | ComponentType::U32);
                if !integer || accessor.normalized || accessor.type_ != Checked::Valid(Type::Scalar) {
                    return Err(format!(
                        "{path}: accessor {} is not a SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                        indices.value()
                    ));
                }
                if let Some(view) = accessor.buffer_view
                    && root.buffer_views[view.value()].byte_stride.is_some()
                {
                    return Err(format!("{path}: bufferViews[{}] of indices has a byteStride", view.value()));
                }
            }
            if let Some(material) = primitive.material {
                check_uv_sets(raw, material.value(), primitive, &here)?;
            }
        }
    }
    Ok(())
}

/// Every texture of the primitive's material reads a UV set the primitive has.
fn check_uv_sets(raw: &Value, material: usize, primitive: &json::mesh::Primitive, here: &str) -> Result<(), String> {
    let Some(m) = raw.get("materials").and_then(|ms| ms.get(material)) else {
        return Ok(());
    };
    let slots = [
        ("pbrMetallicRoughness.baseColorTexture", m.pointer("/pbrMetallicRoughness/baseColorTexture")),
        ("pbrMetallicRoughness.metallicRoughnessTexture", m.pointer("/pbrMetallicRoughness/metallicRoughnessTexture")),
        ("normalTexture", m.get("normalTexture")),
        ("occlusionTexture", m.get("occlusionTexture")),
        ("emissiveTexture", m.get("emissiveTexture")),
    ];
    for (slot, info) in slots {
        let Some(info) = info else { continue };
        let transform_set = info.pointer("/extensions/KHR_texture_transform/texCoord").and_then(Value::as_u64);
        let (set, key) = match transform_set {
            Some(set) => (set, "extensions.KHR_texture_transform.texCoord"),
            None => (info.get("texCoord").and_then(Value::as_u64).unwrap_or(0), "texCoord"),
        };
        let has = u32::try_from(set)
            .is_ok_and(|set| primitive.attributes.contains_key(&Checked::Valid(Semantic::TexCoords(set))));
        if !has {
            return Err(format!(
                "{here}: materials[{material}].{slot}.{key} is {set}, but the primitive has no TEXCOORD_{set}"
            ));
        }
    }
    Ok(())
}

fn check_nodes(raw: &Value) -> Result<(), String> {
    let nodes = raw.get("nodes").and_then(Value::as_array).map(Vec::as_slice).unwrap_or_default();
    for (n, node) in nodes.iter().enumerate() {
        if node.get("matrix").is_some() {
            let trs: Vec<&str> =
                ["translation", "rotation", "scale"].into_iter().filter(|k| node.get(*k).is_some()).collect();
            if !trs.is_empty() {
                return Err(format!(
                    "nodes[{n}]: has both matrix and {}; glTF allows one or the other",
                    trs.join(", ")
                ));
            }
        }
    }
    Ok(())
}
