//! Draws whose material has no texture run pipelines that sample none (the
//! `MATERIAL_TEXTURED` override): the same surface as white textures would give, in both
//! paths.

mod common;

use chiaro_render::plan::draws::{GeometryLayout, scene_draws};
use chiaro_scene::{ColorSpace, Image, RenderPath, Scene, Settings, TextureRef};
use common::*;
use glam::{Vec3, Vec4};

/// The turned floor, coloured, rough and glowing a little, lit by its sun and a point.
fn coloured_floor() -> Scene {
    let mut scene = turned_floor_scene();
    let m = &mut scene.materials[0];
    m.base_color = Vec4::new(0.7, 0.5, 0.3, 1.0);
    m.metallic = 0.2;
    m.roughness = 0.6;
    m.emissive = Vec3::new(0.05, 0.02, 0.0);
    scene
}

/// The same floor with white 1x1 base colour, metallic-roughness, occlusion and emissive
/// textures: a texture multiplies its factor, so white changes nothing.
fn with_white_textures(mut scene: Scene) -> Scene {
    let image = |color_space| Image {
        name: "white".into(),
        width: 1,
        height: 1,
        rgba8: vec![255; 4],
        file_mips: Vec::new(),
        basis_source: None,
        color_space,
    };
    scene.images = vec![image(ColorSpace::Srgb), image(ColorSpace::Linear)];
    let texture =
        |image| Some(TextureRef { image, sampler: Default::default(), tex_coord: 0, transform: Default::default() });
    let m = &mut scene.materials[0];
    m.base_color_texture = texture(0);
    m.emissive_texture = texture(0);
    m.metallic_roughness_texture = texture(1);
    m.occlusion_texture = texture(1);
    scene
}

#[test]
fn an_untextured_material_shades_as_white_textures_do_without_sampling_them() {
    let plain = coloured_floor();
    let textured = with_white_textures(coloured_floor());
    let flags = |scene: &Scene| -> Vec<bool> {
        scene_draws(scene, &GeometryLayout::of(scene)).iter().map(|d| d.textured).collect()
    };
    assert_eq!(flags(&plain), vec![false], "the plain floor's draw samples no texture");
    assert_eq!(flags(&textured), vec![true]);

    let mut r = renderer();
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let mut settings = Settings::default();
        settings.render.path = path;
        let a = render(&mut r, &plain, &settings, 96);
        let b = render(&mut r, &textured, &settings, 96);
        let lit = a.hdr.iter().filter(|p| p[0] > 1e-3).count();
        assert!(lit > 1000, "{path:?}: the floor fills the view ({lit} lit pixels)");
        let worst = a
            .hdr
            .iter()
            .zip(&b.hdr)
            .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() / p[c].abs().max(q[c].abs()).max(1e-3)))
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-5, "{path:?}: untextured and white-textured floors differ by {worst}");
    }
}
