//! What the KHR_materials_* extensions add to a metallic-roughness material: index of
//! refraction, specular, clearcoat, sheen, transmission, volume, iridescence, anisotropy,
//! dispersion and diffuse transmission. Each field holds the extension's factor, or the
//! value that leaves the base material as it is where the file has no such extension,
//! so a material without any equals `MaterialLayers::default()`.

use crate::types::{ColorSpace, TextureRef};
use glam::Vec3;

/// The textures the extensions name, one slot each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LayerTexture {
    /// KHR_materials_specular `specularTexture` (A).
    Specular,
    /// KHR_materials_specular `specularColorTexture` (RGB, sRGB).
    SpecularColor,
    /// KHR_materials_clearcoat `clearcoatTexture` (R).
    Clearcoat,
    /// KHR_materials_clearcoat `clearcoatRoughnessTexture` (G).
    ClearcoatRoughness,
    /// KHR_materials_clearcoat `clearcoatNormalTexture` (tangent-space normal).
    ClearcoatNormal,
    /// KHR_materials_sheen `sheenColorTexture` (RGB, sRGB).
    SheenColor,
    /// KHR_materials_sheen `sheenRoughnessTexture` (A).
    SheenRoughness,
    /// KHR_materials_transmission `transmissionTexture` (R).
    Transmission,
    /// KHR_materials_volume `thicknessTexture` (G).
    Thickness,
    /// KHR_materials_iridescence `iridescenceTexture` (R).
    Iridescence,
    /// KHR_materials_iridescence `iridescenceThicknessTexture` (G).
    IridescenceThickness,
    /// KHR_materials_anisotropy `anisotropyTexture` (RG direction, B strength).
    Anisotropy,
    /// KHR_materials_diffuse_transmission `diffuseTransmissionTexture` (A).
    DiffuseTransmission,
    /// KHR_materials_diffuse_transmission `diffuseTransmissionColorTexture` (RGB, sRGB).
    DiffuseTransmissionColor,
}

impl LayerTexture {
    /// Every slot, in the order of `MaterialLayers::textures` (and of the GPU material's).
    pub const ALL: [LayerTexture; 14] = [
        LayerTexture::Specular,
        LayerTexture::SpecularColor,
        LayerTexture::Clearcoat,
        LayerTexture::ClearcoatRoughness,
        LayerTexture::ClearcoatNormal,
        LayerTexture::SheenColor,
        LayerTexture::SheenRoughness,
        LayerTexture::Transmission,
        LayerTexture::Thickness,
        LayerTexture::Iridescence,
        LayerTexture::IridescenceThickness,
        LayerTexture::Anisotropy,
        LayerTexture::DiffuseTransmission,
        LayerTexture::DiffuseTransmissionColor,
    ];

    /// The slot's place in `ALL`.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The extension that names the texture and its key there.
    pub fn json_key(self) -> (&'static str, &'static str) {
        match self {
            LayerTexture::Specular => ("KHR_materials_specular", "specularTexture"),
            LayerTexture::SpecularColor => ("KHR_materials_specular", "specularColorTexture"),
            LayerTexture::Clearcoat => ("KHR_materials_clearcoat", "clearcoatTexture"),
            LayerTexture::ClearcoatRoughness => ("KHR_materials_clearcoat", "clearcoatRoughnessTexture"),
            LayerTexture::ClearcoatNormal => ("KHR_materials_clearcoat", "clearcoatNormalTexture"),
            LayerTexture::SheenColor => ("KHR_materials_sheen", "sheenColorTexture"),
            LayerTexture::SheenRoughness => ("KHR_materials_sheen", "sheenRoughnessTexture"),
            LayerTexture::Transmission => ("KHR_materials_transmission", "transmissionTexture"),
            LayerTexture::Thickness => ("KHR_materials_volume", "thicknessTexture"),
            LayerTexture::Iridescence => ("KHR_materials_iridescence", "iridescenceTexture"),
            LayerTexture::IridescenceThickness => ("KHR_materials_iridescence", "iridescenceThicknessTexture"),
            LayerTexture::Anisotropy => ("KHR_materials_anisotropy", "anisotropyTexture"),
            LayerTexture::DiffuseTransmission => ("KHR_materials_diffuse_transmission", "diffuseTransmissionTexture"),
            LayerTexture::DiffuseTransmissionColor => {
                ("KHR_materials_diffuse_transmission", "diffuseTransmissionColorTexture")
            }
        }
    }

    /// Colour textures hold sRGB-encoded values; the rest hold data.
    pub fn color_space(self) -> ColorSpace {
        match self {
            LayerTexture::SpecularColor | LayerTexture::SheenColor | LayerTexture::DiffuseTransmissionColor => {
                ColorSpace::Srgb
            }
            _ => ColorSpace::Linear,
        }
    }
}

/// The KHR_materials_* extensions of one material (see the module comment).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialLayers {
    /// KHR_materials_ior: the dielectric's index of refraction (1.5: F0 of 4%).
    pub ior: f32,
    /// KHR_materials_specular: strength of the dielectric's specular reflection (and of
    /// its F90), times the texture's alpha.
    pub specular: f32,
    /// KHR_materials_specular: the dielectric's F0 colour, times the texture's RGB.
    pub specular_color: Vec3,
    /// KHR_materials_clearcoat: the coat's strength, times the texture's red.
    pub clearcoat: f32,
    /// The coat's perceptual roughness, times the texture's green.
    pub clearcoat_roughness: f32,
    /// Scale of the coat's normal map's X and Y.
    pub clearcoat_normal_scale: f32,
    /// KHR_materials_sheen: the sheen's colour (black: none), times the texture's RGB.
    pub sheen_color: Vec3,
    /// The sheen's roughness, times the texture's alpha.
    pub sheen_roughness: f32,
    /// KHR_materials_transmission: the share of light that passes through the
    /// dielectric's surface, times the texture's red.
    pub transmission: f32,
    /// KHR_materials_volume: the thickness of the volume under the surface in the
    /// mesh's units (0: thin-walled), times the texture's green.
    pub thickness: f32,
    /// The distance light travels in the volume before its colour is
    /// `attenuation_color` (infinite: no absorption).
    pub attenuation_distance: f32,
    /// The colour white light turns after `attenuation_distance`.
    pub attenuation_color: Vec3,
    /// KHR_materials_iridescence: the thin film's strength, times the texture's red.
    pub iridescence: f32,
    /// The film's index of refraction.
    pub iridescence_ior: f32,
    /// The film's thickness in nanometres where the thickness texture's green is 0...
    pub iridescence_thickness_min: f32,
    /// ...and where it is 1 (or everywhere, without the texture).
    pub iridescence_thickness_max: f32,
    /// KHR_materials_anisotropy: how much the highlight stretches, times the texture's
    /// blue.
    pub anisotropy_strength: f32,
    /// The stretch direction's angle from the tangent, counter-clockwise, radians.
    pub anisotropy_rotation: f32,
    /// KHR_materials_dispersion: Abbe-number spread of the ior with wavelength, as
    /// 20 / Abbe number (0: none).
    pub dispersion: f32,
    /// KHR_materials_diffuse_transmission: the share of diffuse light that passes to the
    /// other side, times the texture's alpha.
    pub diffuse_transmission: f32,
    /// The colour diffuse light takes through, times the texture's RGB.
    pub diffuse_transmission_color: Vec3,
    /// The extensions' textures, by `LayerTexture::index`.
    pub textures: [Option<TextureRef>; 14],
}

impl Default for MaterialLayers {
    fn default() -> Self {
        MaterialLayers {
            ior: 1.5,
            specular: 1.0,
            specular_color: Vec3::ONE,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            clearcoat_normal_scale: 1.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            transmission: 0.0,
            thickness: 0.0,
            attenuation_distance: f32::INFINITY,
            attenuation_color: Vec3::ONE,
            iridescence: 0.0,
            iridescence_ior: 1.3,
            iridescence_thickness_min: 100.0,
            iridescence_thickness_max: 400.0,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            dispersion: 0.0,
            diffuse_transmission: 0.0,
            diffuse_transmission_color: Vec3::ONE,
            textures: [None; 14],
        }
    }
}

impl MaterialLayers {
    /// The texture in `slot`, if the material has one.
    pub fn texture(&self, slot: LayerTexture) -> Option<&TextureRef> {
        self.textures[slot.index()].as_ref()
    }

    /// Whether any extension changes the base material's look (the shaders then take the
    /// layered path).
    pub fn is_layered(&self) -> bool {
        self != &MaterialLayers::default()
    }

    /// The extensions that change this material (a value or a texture other than the
    /// default), by name, in `gltf_import::layers::EXTENSIONS` order.
    pub fn extensions(&self) -> Vec<&'static str> {
        use LayerTexture as T;
        let d = MaterialLayers::default();
        let textured = |slots: &[LayerTexture]| slots.iter().any(|&s| self.texture(s).is_some());
        let used = [
            ("KHR_materials_ior", self.ior != d.ior),
            (
                "KHR_materials_specular",
                self.specular != d.specular
                    || self.specular_color != d.specular_color
                    || textured(&[T::Specular, T::SpecularColor]),
            ),
            ("KHR_materials_clearcoat", self.clearcoat != d.clearcoat || textured(&[T::Clearcoat])),
            ("KHR_materials_sheen", self.sheen_color != d.sheen_color || textured(&[T::SheenColor])),
            ("KHR_materials_transmission", self.transmission != d.transmission || textured(&[T::Transmission])),
            (
                "KHR_materials_volume",
                self.thickness != d.thickness
                    || self.attenuation_distance != d.attenuation_distance
                    || textured(&[T::Thickness]),
            ),
            ("KHR_materials_iridescence", self.iridescence != d.iridescence || textured(&[T::Iridescence])),
            (
                "KHR_materials_anisotropy",
                self.anisotropy_strength != d.anisotropy_strength || textured(&[T::Anisotropy]),
            ),
            ("KHR_materials_dispersion", self.dispersion != d.dispersion),
            (
                "KHR_materials_diffuse_transmission",
                self.diffuse_transmission != d.diffuse_transmission || textured(&[T::DiffuseTransmission]),
            ),
        ];
        used.into_iter().filter(|(_, used)| *used).map(|(name, _)| name).collect()
    }

    /// Whether light passes through the surface (transmission), which the renderer
    /// draws after the opaque scene, refracting it.
    pub fn transmits(&self) -> bool {
        self.transmission > 0.0
    }

    /// What one crossing of the surface lets through of a light behind it, per channel,
    /// for shadows: `None` for a surface that lets nothing through (no transmission and no
    /// diffuse transmission), which casts an ordinary shadow. From the factors alone (no
    /// textures, no vertex colours, no angle): the dielectric share `1 - metallic`, less
    /// its Fresnel reflectance at normal incidence, split as the spec mixes its lobes,
    /// `transmission` of it tinted by the base colour and the rest's diffuse transmission
    /// tinted by its colour; a volume's Beer-Lambert attenuation over its thickness, split
    /// between the walls the light crosses. The renderer's coloured shadows and the
    /// reference tracer both apply it once per surface crossed whose material shows the
    /// face the light meets: a single-sided closed object (the camera sees its front wall
    /// alone) tints once, with the whole thickness; a `double_sided` one twice, with half
    /// of it each time.
    pub fn shadow_transmittance(&self, base_color: Vec3, metallic: f32, double_sided: bool) -> Option<Vec3> {
        if self.transmission <= 0.0 && self.diffuse_transmission <= 0.0 {
            return None;
        }
        let dielectric = (1.0 - metallic).clamp(0.0, 1.0);
        let f0 = ((self.ior - 1.0) / (self.ior + 1.0)).powi(2) * self.specular;
        let specular = self.transmission * base_color;
        let diffuse = (1.0 - self.transmission) * self.diffuse_transmission * self.diffuse_transmission_color;
        let mut through = (specular + diffuse) * dielectric * (1.0 - f0.clamp(0.0, 1.0));
        if self.thickness > 0.0 && self.attenuation_distance.is_finite() && self.attenuation_distance > 0.0 {
            let walls = if double_sided { 2.0 } else { 1.0 };
            let exponent = self.thickness / (walls * self.attenuation_distance);
            through *= self.attenuation_color.max(Vec3::ZERO).powf(exponent);
        }
        Some(through.clamp(Vec3::ZERO, Vec3::ONE))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn opaque_surfaces_cast_ordinary_shadows() {
        assert_eq!(MaterialLayers::default().shadow_transmittance(Vec3::ONE, 0.0, false), None);
    }

    #[test]
    fn transmission_is_tinted_by_base_colour_less_fresnel_and_metal() {
        let glass = MaterialLayers { transmission: 1.0, ..MaterialLayers::default() };
        // ior 1.5: F0 = 0.04.
        let red = Vec3::new(1.0, 0.2, 0.1);
        assert!(close(glass.shadow_transmittance(red, 0.0, false).unwrap(), red * 0.96));
        assert!(close(glass.shadow_transmittance(red, 0.5, false).unwrap(), red * 0.48));
        let half = MaterialLayers { transmission: 0.5, ..glass.clone() };
        assert!(close(half.shadow_transmittance(Vec3::ONE, 0.0, false).unwrap(), Vec3::splat(0.48)));
    }

    #[test]
    fn diffuse_transmission_takes_its_own_colour() {
        let leaf = MaterialLayers {
            diffuse_transmission: 0.5,
            diffuse_transmission_color: Vec3::new(0.2, 1.0, 0.2),
            ..MaterialLayers::default()
        };
        let through = leaf.shadow_transmittance(Vec3::new(1.0, 0.0, 0.0), 0.0, false).unwrap();
        assert!(close(through, Vec3::new(0.1, 0.5, 0.1) * 0.96), "{through}");
    }

    #[test]
    fn a_volume_attenuates_over_its_thickness_split_between_the_walls_crossed() {
        let volume = MaterialLayers {
            transmission: 1.0,
            thickness: 2.0,
            attenuation_distance: 1.0,
            attenuation_color: Vec3::new(0.5, 1.0, 0.25),
            ..MaterialLayers::default()
        };
        let beer_lambert = Vec3::new(0.25, 1.0, 0.0625);
        // Single-sided: one wall crossed, the whole thickness.
        let one = volume.shadow_transmittance(Vec3::ONE, 0.0, false).unwrap();
        assert!(close(one / 0.96, beer_lambert), "{one}");
        // Double-sided: two crossings make the same colour^(thickness / distance).
        let half = volume.shadow_transmittance(Vec3::ONE, 0.0, true).unwrap();
        let two = half * half / (0.96 * 0.96);
        assert!(close(two, beer_lambert), "{two}");
    }
}
