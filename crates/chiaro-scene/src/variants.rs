//! KHR_materials_variants: the variants a file names and, per primitive, the material
//! each gives it. Selecting a variant (or the default) sets the primitives' materials;
//! a name the file lacks is an error listing the ones it has.

use crate::types::Scene;

/// A file's material variants and which is selected.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialVariants {
    /// The variants' names, in the file's order.
    pub names: Vec<String>,
    /// Every primitive some variant gives another material.
    pub mappings: Vec<VariantMapping>,
    /// The selected variant (an index into `names`); `None`: the file's default materials.
    pub selected: Option<usize>,
}

/// The materials variants give one primitive.
#[derive(Clone, Debug, PartialEq)]
pub struct VariantMapping {
    /// Index into `Scene::meshes`.
    pub mesh: usize,
    /// Index into that mesh's primitives.
    pub primitive: usize,
    /// The primitive's own material, which variants without a mapping for it keep.
    pub default_material: Option<usize>,
    /// (variant, material) pairs.
    pub materials: Vec<(usize, usize)>,
}

/// Why a variant cannot be selected.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{0}")]
pub struct VariantError(String);

impl MaterialVariants {
    /// The material primitive `mapping` has under variant `selected`.
    fn material(mapping: &VariantMapping, selected: Option<usize>) -> Option<usize> {
        selected
            .and_then(|v| mapping.materials.iter().find(|(variant, _)| *variant == v).map(|(_, m)| *m))
            .or(mapping.default_material)
    }

    /// Every material some variant uses, the defaults aside.
    pub fn variant_materials(&self) -> impl Iterator<Item = usize> + '_ {
        self.mappings.iter().flat_map(|m| m.materials.iter().map(|(_, material)| *material))
    }
}

impl Scene {
    /// Gives every primitive the material of the variant named `name`, or its default
    /// material for `None`.
    pub fn select_variant(&mut self, name: Option<&str>) -> Result<(), VariantError> {
        let selected = match name {
            None => None,
            Some(name) => Some(self.variants.names.iter().position(|n| n == name).ok_or_else(|| {
                VariantError(match self.variants.names.len() {
                    0 => format!("no material variant '{name}': the scene has no KHR_materials_variants variants"),
                    _ => format!("no material variant '{name}'; the scene has: {}", self.variants.names.join(", ")),
                })
            })?),
        };
        for mapping in &self.variants.mappings {
            let material = MaterialVariants::material(mapping, selected);
            if let Some(primitive) =
                self.meshes.get_mut(mapping.mesh).and_then(|m| m.primitives.get_mut(mapping.primitive))
            {
                primitive.material = material;
            }
        }
        self.variants.selected = selected;
        Ok(())
    }

    /// The selected variant's name, if one is selected.
    pub fn selected_variant(&self) -> Option<&str> {
        self.variants.selected.and_then(|v| self.variants.names.get(v)).map(String::as_str)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use crate::types::Mesh;

    fn scene() -> Scene {
        let mut scene = Scene::default();
        let mut a = shapes::cuboid(glam::Vec3::ONE);
        a.material = Some(0);
        let b = a.clone();
        scene.meshes.push(Mesh::of_triangles("shoe".into(), vec![a, b]));
        scene.variants = MaterialVariants {
            names: vec!["red".into(), "blue".into()],
            mappings: vec![
                VariantMapping { mesh: 0, primitive: 0, default_material: Some(0), materials: vec![(0, 1), (1, 2)] },
                VariantMapping { mesh: 0, primitive: 1, default_material: Some(0), materials: vec![(1, 3)] },
            ],
            selected: None,
        };
        scene
    }

    fn materials(scene: &Scene) -> Vec<Option<usize>> {
        scene.meshes[0].primitives.iter().map(|p| p.material).collect()
    }

    #[test]
    fn selecting_a_variant_sets_its_materials_and_none_restores_the_defaults() {
        let mut scene = scene();
        scene.select_variant(Some("red")).unwrap();
        assert_eq!(materials(&scene), vec![Some(1), Some(0)]);
        assert_eq!(scene.selected_variant(), Some("red"));
        scene.select_variant(Some("blue")).unwrap();
        assert_eq!(materials(&scene), vec![Some(2), Some(3)]);
        scene.select_variant(None).unwrap();
        assert_eq!(materials(&scene), vec![Some(0), Some(0)]);
        assert_eq!(scene.selected_variant(), None);
    }

    #[test]
    fn an_unknown_name_is_an_error_listing_the_variants() {
        let mut scene = scene();
        let error = scene.select_variant(Some("green")).unwrap_err();
        assert_eq!(error.to_string(), "no material variant 'green'; the scene has: red, blue");
        assert_eq!(materials(&scene), vec![Some(0), Some(0)]);
        let error = Scene::default().select_variant(Some("red")).unwrap_err();
        assert!(error.to_string().contains("has no KHR_materials_variants variants"), "{error}");
    }
}
