//! What the baker needs to know about a point on a surface: its material as the renderer
//! shades it (base colour, metallic and roughness, textures and vertex colours included), from which it
//! reflects bounced light, its emission, whether its back face reflects, and its shading
//! normal.

use chiaro_math::environment::{SplitSumTable, directional_albedo};
use chiaro_scene::{ColorSpace, Image, Material, Scene, TextureRef, WrapMode};
use glam::{Mat3, Vec2, Vec3, Vec4};

pub struct SurfacePoint {
    /// Linear base colour, clamped to 0..1.
    pub base_color: Vec3,
    pub metallic: f32,
    /// Perceptual roughness, clamped as the shader clamps it.
    pub roughness: f32,
    pub emissive: Vec3,
    pub double_sided: bool,
    /// Interpolated vertex normal in world space (unit; zero where the mesh has none).
    pub shading_normal: Vec3,
}

/// The shader's least roughness (`common/material.wesl`).
const MIN_ROUGHNESS: f32 = 0.03;

impl SurfacePoint {
    /// The share of the light arriving at this point that it reflects towards a direction
    /// `n_dot_out` from its normal: the material's directional albedo, both lobes
    /// (`chiaro_math::environment::directional_albedo`). A bounce carries all of it, as
    /// energy balance asks; it leaves in a cosine-weighted direction (the diffuse lobe's
    /// shape), which is where lightmaps, storing irradiance, forget direction anyway.
    pub fn reflectance(&self, n_dot_out: f32) -> Vec3 {
        let terms = SplitSumTable::shared().terms(n_dot_out, self.roughness);
        directional_albedo(self.base_color, self.metallic, terms)
    }
}

/// Surface lookups over a scene.
pub struct Surfaces<'a> {
    scene: &'a Scene,
    default_material: Material,
    /// Per instance, the normal matrix.
    normal_from_local: Vec<Mat3>,
    srgb_to_linear: [f32; 256],
}

impl<'a> Surfaces<'a> {
    pub fn new(scene: &'a Scene) -> Surfaces<'a> {
        let normal_from_local =
            scene.instances.iter().map(|i| Mat3::from_mat4(i.world_from_local).inverse().transpose()).collect();
        let mut srgb_to_linear = [0.0; 256];
        for (k, v) in srgb_to_linear.iter_mut().enumerate() {
            let c = k as f32 / 255.0;
            *v = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
        }
        Surfaces { scene, default_material: Material::default(), normal_from_local, srgb_to_linear }
    }

    /// The surface of `instance` at weights `w` of triangle `triangle` of its mesh's
    /// primitive `primitive`.
    pub fn at(&self, instance: usize, primitive: usize, triangle: usize, w: [f32; 3]) -> SurfacePoint {
        let inst = &self.scene.instances[instance];
        let p = &self.scene.meshes[inst.mesh].primitives[primitive];
        let corners = [0, 1, 2].map(|k| p.indices.get(3 * triangle + k).copied().unwrap_or(0) as usize);
        let lerp2 = |values: &[Vec2]| -> Vec2 {
            corners.iter().zip(w).map(|(&i, wk)| values.get(i).copied().unwrap_or_default() * wk).sum()
        };
        let normal_ls: Vec3 =
            corners.iter().zip(w).map(|(&i, wk)| p.normals.get(i).copied().unwrap_or_default() * wk).sum();
        let shading_normal = (self.normal_from_local[instance] * normal_ls).normalize_or_zero();
        let material = p.material.and_then(|m| self.scene.materials.get(m)).unwrap_or(&self.default_material);
        let (uv0, uv1) = (lerp2(&p.uv0), lerp2(&p.uv1));
        let texture = |t: &Option<TextureRef>| -> Vec4 {
            match t.as_ref().and_then(|t| self.scene.images.get(t.image).map(|image| (t, image))) {
                Some((t, image)) => {
                    let uv = if t.tex_coord == 1 { uv1 } else { uv0 };
                    let m = t.transform.matrix();
                    self.sample(image, t, m[0] * uv.x + m[1] * uv.y + m[2])
                }
                None => Vec4::ONE,
            }
        };
        let vertex_color: Vec4 = match p.colors.is_empty() {
            true => Vec4::ONE,
            false => corners.iter().zip(w).map(|(&i, wk)| p.colors.get(i).copied().unwrap_or(Vec4::ONE) * wk).sum(),
        };
        let base = material.base_color * vertex_color * texture(&material.base_color_texture);
        let metallic_roughness = texture(&material.metallic_roughness_texture);
        let metallic = (material.metallic * metallic_roughness.z).clamp(0.0, 1.0);
        let roughness = (material.roughness * metallic_roughness.y).clamp(MIN_ROUGHNESS, 1.0);
        let emissive = material.emissive * texture(&material.emissive_texture).truncate();
        SurfacePoint {
            base_color: (base.truncate() * layered_albedo_scale(&material.layers, metallic))
                .clamp(Vec3::ZERO, Vec3::ONE),
            metallic,
            roughness,
            emissive,
            double_sided: material.double_sided,
            shading_normal,
        }
    }

    /// Nearest-texel lookup (bounced light is diffuse and averaged over many paths), colour
    /// images decoded to linear.
    fn sample(&self, image: &Image, t: &TextureRef, uv: Vec2) -> Vec4 {
        if image.width == 0 || image.height == 0 || !uv.is_finite() {
            return Vec4::ONE;
        }
        let wrap = |c: f32, mode: WrapMode, n: u32| -> u32 {
            let n_f = n as f32;
            let x = match mode {
                WrapMode::Repeat => c.rem_euclid(1.0) * n_f,
                WrapMode::MirroredRepeat => {
                    let m = c.rem_euclid(2.0);
                    (if m > 1.0 { 2.0 - m } else { m }) * n_f
                }
                WrapMode::ClampToEdge => c.clamp(0.0, 1.0) * n_f,
            };
            (x as u32).min(n - 1)
        };
        let x = wrap(uv.x, t.sampler.wrap_u, image.width);
        let y = wrap(uv.y, t.sampler.wrap_v, image.height);
        let i = ((y * image.width + x) * 4) as usize;
        let Some(px) = image.rgba8.get(i..i + 4) else { return Vec4::ONE };
        let channel = |k: usize| match image.color_space {
            ColorSpace::Srgb if k < 3 => self.srgb_to_linear[px[k] as usize],
            _ => px[k] as f32 / 255.0,
        };
        Vec4::new(channel(0), channel(1), channel(2), channel(3))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_colours_multiply_the_base_colour_bounces_reflect() {
        let mut scene = chiaro_testkit::floor_scene(2.0, Vec3::Y, Vec::new());
        scene.materials[0].base_color = Vec4::new(0.5, 0.5, 0.5, 1.0);
        // Blue at x = -1 turning red at x = +1: a triangle's corners differ.
        let floor = &mut scene.meshes[0].primitives[0];
        floor.colors =
            floor.positions.iter().map(|p| Vec4::new(0.5 * (p.x + 1.0), 0.0, 0.5 * (1.0 - p.x), 1.0)).collect();
        let surfaces = Surfaces::new(&scene);
        let p = &scene.meshes[0].primitives[0];
        // Every corner of the first triangle, and its centre.
        for k in 0..3 {
            let mut w = [0.0; 3];
            w[k] = 1.0;
            let corner = p.indices[k] as usize;
            let expected = 0.5 * p.colors[corner].truncate();
            assert_eq!(surfaces.at(0, 0, 0, w).base_color, expected, "corner {k}");
        }
        let centre = surfaces.at(0, 0, 0, [1.0 / 3.0; 3]).base_color;
        let expected: Vec3 = (0..3).map(|k| p.colors[p.indices[k] as usize].truncate() * 0.5 / 3.0).sum();
        assert!(centre.distance(expected) < 1e-6, "{centre} vs {expected}");
    }
}

/// How much of a bounce the KHR_materials_* layers leave the base's albedo, by their
/// factors (their textures are not read here): light that transmission or diffuse
/// transmission passes through the dielectric does not bounce back off it, and a coat
/// takes its Fresnel share (4% head-on, the mean over angles about 10%).
fn layered_albedo_scale(layers: &chiaro_scene::MaterialLayers, metallic: f32) -> f32 {
    const COAT_MEAN_FRESNEL: f32 = 0.1;
    let kept_by_dielectric = (1.0 - layers.transmission) * (1.0 - layers.diffuse_transmission);
    let base = metallic + (1.0 - metallic) * kept_by_dielectric;
    base * (1.0 - layers.clearcoat * COAT_MEAN_FRESNEL)
}

#[cfg(test)]
mod layer_tests {
    use super::layered_albedo_scale;
    use chiaro_scene::MaterialLayers;

    #[test]
    fn transmission_and_coats_bounce_less_light() {
        assert_eq!(layered_albedo_scale(&MaterialLayers::default(), 0.0), 1.0);
        let glass = MaterialLayers { transmission: 1.0, ..Default::default() };
        assert_eq!(layered_albedo_scale(&glass, 0.0), 0.0);
        // A metal transmits nothing.
        assert_eq!(layered_albedo_scale(&glass, 1.0), 1.0);
        let leaf = MaterialLayers { diffuse_transmission: 0.5, ..Default::default() };
        assert_eq!(layered_albedo_scale(&leaf, 0.0), 0.5);
        let coated = MaterialLayers { clearcoat: 1.0, ..Default::default() };
        assert!((layered_albedo_scale(&coated, 0.0) - 0.9).abs() < 1e-6);
    }
}
