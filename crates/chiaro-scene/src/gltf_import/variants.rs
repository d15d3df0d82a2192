//! KHR_materials_variants in the file: the root's variant names and each primitive's
//! mappings in, `VariantMapping`s out, every variant and material index checked.

use super::Loader;
use crate::error::SceneError;
use crate::variants::VariantMapping;
use serde_json::Value;

pub(super) const EXTENSION: &str = "KHR_materials_variants";

impl Loader<'_> {
    /// The variants' names, in the file's order; a variant without one is named by index.
    pub(super) fn variant_names(&self) -> Result<Vec<String>, SceneError> {
        let Some(variants) = self.raw.pointer(&format!("/extensions/{EXTENSION}/variants")) else {
            return Ok(Vec::new());
        };
        let variants = variants
            .as_array()
            .ok_or_else(|| self.invalid(format!("extensions.{EXTENSION}.variants is not an array")))?;
        Ok(variants
            .iter()
            .enumerate()
            .map(|(i, v)| v.get("name").and_then(Value::as_str).map_or_else(|| format!("variant {i}"), str::to_owned))
            .collect())
    }

    /// Primitive `p` of mesh `mesh` as Chiaro's primitive `primitive` of that mesh: the
    /// materials its mappings give it, if it has any.
    pub(super) fn variant_mapping(
        &self,
        (mesh, p): (usize, usize),
        primitive: usize,
        label: &str,
    ) -> Result<Option<VariantMapping>, SceneError> {
        let Some(mappings) =
            self.raw.pointer(&format!("/meshes/{mesh}/primitives/{p}/extensions/{EXTENSION}/mappings"))
        else {
            return Ok(None);
        };
        let path = format!("{label}: {EXTENSION}.mappings");
        let mappings = mappings.as_array().ok_or_else(|| self.invalid(format!("{path} is not an array")))?;
        let index = |value: Option<&Value>, count: usize, what: &str| -> Result<usize, SceneError> {
            value.and_then(Value::as_u64).and_then(|i| usize::try_from(i).ok()).filter(|&i| i < count).ok_or_else(
                || {
                    self.invalid(format!(
                        "{path}: {what} {} is out of range (the file has {count})",
                        value.unwrap_or(&Value::Null)
                    ))
                },
            )
        };
        let mut materials = Vec::new();
        for mapping in mappings {
            let material = index(mapping.get("material"), self.root.materials.len(), "material")?;
            let variants = mapping
                .get("variants")
                .and_then(Value::as_array)
                .ok_or_else(|| self.invalid(format!("{path}: a mapping has no variants array")))?;
            for variant in variants {
                let variant = index(Some(variant), self.variant_names.len(), "variant")?;
                if materials.iter().any(|(v, _)| *v == variant) {
                    return Err(self.invalid(format!("{path}: variant {variant} is mapped twice")));
                }
                materials.push((variant, material));
            }
        }
        let default_material = self.root.meshes[mesh].primitives[p].material.map(|m| m.value());
        Ok(Some(VariantMapping { mesh, primitive, default_material, materials }))
    }
}
