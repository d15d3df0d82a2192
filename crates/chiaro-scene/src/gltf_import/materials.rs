//! A glTF material index in, a [`Material`] out: PBR factors, alpha mode, emissive
//! strength, and texture references with their samplers, UV sets and
//! KHR_texture_transform (read from the raw JSON, as the typed model drops it on normal
//! and occlusion textures). Texture references hold glTF image indices; the images the
//! drawn materials use are decoded later, by [`super::images`].

use super::{Loader, object_label};
use crate::error::SceneError;
use crate::types::{AlphaMode, Material, SamplerDesc, TextureRef, UvTransform, WrapMode};
use glam::{Vec2, Vec3, Vec4};
use gltf::json;
use json::validation::Checked;
use serde_json::Value;

impl Loader<'_> {
    /// A material with `TextureRef::image` still holding the glTF image index;
    /// `decode_images` maps it to `Scene::images`.
    pub(super) fn material(&mut self, index: usize) -> Result<Material, SceneError> {
        let m = &self.root.materials[index];
        let label = object_label("material", index, None, m.name.as_deref());
        let raw = self.raw.get("materials").and_then(|ms| ms.get(index)).unwrap_or(&Value::Null);
        let raw_pbr = raw.get("pbrMetallicRoughness").unwrap_or(&Value::Null);
        let pbr = &m.pbr_metallic_roughness;

        let mut texture = |slot: &str, info: Option<(usize, u32)>, raw_info: Option<&Value>| match info {
            Some((texture, tex_coord)) => self.texture_ref(&format!("{label} {slot}"), texture, tex_coord, raw_info),
            None => Ok(None),
        };
        let base_color_texture = texture(
            "baseColorTexture",
            pbr.base_color_texture.as_ref().map(|t| (t.index.value(), t.tex_coord)),
            raw_pbr.get("baseColorTexture"),
        )?;
        let metallic_roughness_texture = texture(
            "metallicRoughnessTexture",
            pbr.metallic_roughness_texture.as_ref().map(|t| (t.index.value(), t.tex_coord)),
            raw_pbr.get("metallicRoughnessTexture"),
        )?;
        let normal_texture = texture(
            "normalTexture",
            m.normal_texture.as_ref().map(|t| (t.index.value(), t.tex_coord)),
            raw.get("normalTexture"),
        )?;
        let occlusion_texture = texture(
            "occlusionTexture",
            m.occlusion_texture.as_ref().map(|t| (t.index.value(), t.tex_coord)),
            raw.get("occlusionTexture"),
        )?;
        let emissive_texture = texture(
            "emissiveTexture",
            m.emissive_texture.as_ref().map(|t| (t.index.value(), t.tex_coord)),
            raw.get("emissiveTexture"),
        )?;

        let alpha_mode = match m.alpha_mode {
            Checked::Valid(json::material::AlphaMode::Mask) => AlphaMode::Mask,
            Checked::Valid(json::material::AlphaMode::Blend) => AlphaMode::Blend,
            _ => AlphaMode::Opaque,
        };
        let shadow_casting = super::extras::material_shadow_casting(m.extras.as_deref(), alpha_mode)
            .map_err(|e| self.invalid(format!("{label}: {e}")))?;
        let emissive_strength =
            m.extensions.as_ref().and_then(|e| e.emissive_strength.as_ref()).map_or(1.0, |s| s.emissive_strength.0);
        let material = Material {
            name: m.name.clone().unwrap_or_else(|| format!("material {index}")),
            base_color: Vec4::from_array(pbr.base_color_factor.0),
            base_color_texture,
            metallic: pbr.metallic_factor.0,
            roughness: pbr.roughness_factor.0,
            metallic_roughness_texture,
            normal_scale: m.normal_texture.as_ref().map_or(1.0, |t| t.scale),
            normal_texture,
            occlusion_strength: m.occlusion_texture.as_ref().map_or(1.0, |t| t.strength.0),
            occlusion_texture,
            emissive: Vec3::from_array(m.emissive_factor.0) * emissive_strength,
            emissive_texture,
            alpha_mode,
            alpha_cutoff: m.alpha_cutoff.map_or(0.5, |c| c.0),
            double_sided: m.double_sided,
            shadow_casting,
            unlit: raw.pointer("/extensions/KHR_materials_unlit").is_some(),
            layers: self.material_layers(&label, raw)?,
        };
        let factors_finite = material.base_color.is_finite()
            && material.emissive.is_finite()
            && [
                material.metallic,
                material.roughness,
                material.normal_scale,
                material.occlusion_strength,
                material.alpha_cutoff,
            ]
            .iter()
            .all(|f| f.is_finite());
        if !factors_finite {
            return Err(self.invalid(format!("{label}: a factor is not finite")));
        }
        Ok(material)
    }

    /// A texture info's image, sampler, UV set and KHR_texture_transform. The transform is
    /// read from the raw JSON because the typed model drops it on normal and occlusion
    /// textures.
    pub(super) fn texture_ref(
        &mut self,
        label: &str,
        texture: usize,
        tex_coord: u32,
        info: Option<&Value>,
    ) -> Result<Option<TextureRef>, SceneError> {
        #[derive(serde::Deserialize)]
        #[serde(rename_all = "camelCase")]
        struct TextureTransform {
            #[serde(default)]
            offset: [f32; 2],
            #[serde(default)]
            rotation: f32,
            #[serde(default = "unit_scale")]
            scale: [f32; 2],
            tex_coord: Option<u32>,
        }
        fn unit_scale() -> [f32; 2] {
            [1.0, 1.0]
        }

        let gltf_texture = &self.root.textures[texture];
        // `source` is optional: an extension Chiaro does not read may give the image.
        if gltf_texture.source.value() >= self.root.images.len() {
            self.ignored.push(format!("{label}: textures[{texture}] has no image Chiaro reads, drawn untextured"));
            return Ok(None);
        }
        let sampler = gltf_texture.sampler.map(|s| sampler_desc(&self.root.samplers[s.value()])).unwrap_or_default();
        let mut reference =
            TextureRef { image: gltf_texture.source.value(), sampler, tex_coord, transform: UvTransform::default() };
        let transform_json = info.and_then(|i| i.get("extensions")).and_then(|e| e.get("KHR_texture_transform"));
        if let Some(value) = transform_json {
            let t: TextureTransform = serde_json::from_value(value.clone())
                .map_err(|e| self.invalid(format!("{label}: invalid KHR_texture_transform: {e}")))?;
            reference.transform = UvTransform {
                offset: Vec2::from_array(t.offset),
                rotation_rad: t.rotation,
                scale: Vec2::from_array(t.scale),
            };
            if let Some(set) = t.tex_coord {
                reference.tex_coord = set;
            }
            let m = reference.transform.matrix();
            if !m.iter().all(|c| c.is_finite()) {
                return Err(self.invalid(format!("{label}: KHR_texture_transform is not finite")));
            }
        }
        Ok(Some(reference))
    }

    /// The two texture coordinate sets material `index` reads, which its primitives load
    /// into the vertex's two UV slots, with its textures' `tex_coord` rewritten from set
    /// to slot. Sets 0 and 1 stay where they are; a material that names a later set has
    /// it in a slot it leaves free (a third distinct set falls back to slot 0, noted).
    pub(super) fn assign_uv_slots(&mut self, index: usize, material: &mut Material) -> [u32; 2] {
        let textures = material.textures_mut();
        let sets: Vec<u32> = textures.iter().flat_map(|t| t.map(|t| t.tex_coord)).collect();
        let mut later: Vec<u32> = sets.iter().copied().filter(|&set| set > 1).collect();
        later.sort_unstable();
        later.dedup();
        let slots = match (sets.contains(&0), sets.contains(&1), later.as_slice()) {
            (_, _, []) => [0, 1],
            (true, _, [k, ..]) => [0, *k],
            (false, _, [k]) => [*k, 1],
            (false, true, [k, ..]) => [*k, 1],
            (false, false, [k, l, ..]) => [*k, *l],
        };
        for texture in textures.into_iter().flatten() {
            texture.tex_coord = match texture.tex_coord {
                set if set == slots[0] => 0,
                set if set == slots[1] => 1,
                set => {
                    self.ignored.push(format!(
                        "materials[{index}]: a texture reads TEXCOORD_{set}, a third set besides TEXCOORD_{} and \
                         TEXCOORD_{}; it reads TEXCOORD_{} instead",
                        slots[0], slots[1], slots[0]
                    ));
                    0
                }
            };
        }
        slots
    }
}

fn sampler_desc(sampler: &json::texture::Sampler) -> SamplerDesc {
    use json::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |mode: Checked<WrappingMode>| match mode {
        Checked::Valid(WrappingMode::ClampToEdge) => WrapMode::ClampToEdge,
        Checked::Valid(WrappingMode::MirroredRepeat) => WrapMode::MirroredRepeat,
        _ => WrapMode::Repeat,
    };
    let (min_linear, mipmaps) = match sampler.min_filter {
        Some(Checked::Valid(MinFilter::Nearest)) => (false, false),
        Some(Checked::Valid(MinFilter::Linear)) => (true, false),
        Some(Checked::Valid(MinFilter::NearestMipmapNearest | MinFilter::NearestMipmapLinear)) => (false, true),
        _ => (true, true),
    };
    SamplerDesc {
        wrap_u: wrap(sampler.wrap_s),
        wrap_v: wrap(sampler.wrap_t),
        mag_linear: !matches!(sampler.mag_filter, Some(Checked::Valid(MagFilter::Nearest))),
        min_linear,
        mipmaps,
    }
}
