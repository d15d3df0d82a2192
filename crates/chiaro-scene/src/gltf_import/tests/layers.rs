//! The KHR_materials_* extensions beyond metallic-roughness: every factor and texture
//! read into `MaterialLayers`, defaults where a key is absent, and an error naming the
//! material, extension and key for each out-of-range value.

use super::materials::painted_quad;
use super::{TempDir, invalid_message, load_doc};
use crate::layers::{LayerTexture, MaterialLayers};
use crate::types::ColorSpace;
use glam::{Vec2, Vec3};
use serde_json::{Value, json};

/// The painted quad with `extensions` on its material (keeping its emissive strength).
fn with_extensions(dir: &TempDir, extensions: Value) -> Value {
    let mut doc = painted_quad(dir);
    let material = &mut doc["materials"][0]["extensions"];
    for (name, value) in extensions.as_object().unwrap() {
        material[name] = value.clone();
    }
    doc
}

fn every_extension() -> Value {
    json!({
        "KHR_materials_ior": { "ior": 1.33 },
        "KHR_materials_specular": { "specularFactor": 0.5, "specularColorFactor": [1.0, 0.5, 2.0],
            "specularTexture": { "index": 1 }, "specularColorTexture": { "index": 0 } },
        "KHR_materials_clearcoat": { "clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.2,
            "clearcoatTexture": { "index": 1 }, "clearcoatRoughnessTexture": { "index": 1 },
            "clearcoatNormalTexture": { "index": 1, "scale": 0.5,
                "extensions": { "KHR_texture_transform": { "scale": [4.0, 4.0] } } } },
        "KHR_materials_sheen": { "sheenColorFactor": [0.9, 0.1, 0.2], "sheenRoughnessFactor": 0.6,
            "sheenColorTexture": { "index": 0, "texCoord": 1 }, "sheenRoughnessTexture": { "index": 1 } },
        "KHR_materials_transmission": { "transmissionFactor": 0.8, "transmissionTexture": { "index": 1 } },
        "KHR_materials_volume": { "thicknessFactor": 0.25, "attenuationDistance": 2.0,
            "attenuationColor": [0.9, 0.5, 0.1], "thicknessTexture": { "index": 1 } },
        "KHR_materials_iridescence": { "iridescenceFactor": 1.0, "iridescenceIor": 1.8,
            "iridescenceThicknessMinimum": 200.0, "iridescenceThicknessMaximum": 800.0,
            "iridescenceTexture": { "index": 1 }, "iridescenceThicknessTexture": { "index": 1 } },
        "KHR_materials_anisotropy": { "anisotropyStrength": 0.7, "anisotropyRotation": 1.5,
            "anisotropyTexture": { "index": 1 } },
        "KHR_materials_dispersion": { "dispersion": 0.3 },
        "KHR_materials_diffuse_transmission": { "diffuseTransmissionFactor": 0.4,
            "diffuseTransmissionColorFactor": [0.2, 0.9, 0.3],
            "diffuseTransmissionTexture": { "index": 1 }, "diffuseTransmissionColorTexture": { "index": 0 } }
    })
}

#[test]
fn every_extension_factor_and_texture_is_read() {
    let dir = TempDir::new("layers");
    let scene = load_doc(&dir, &with_extensions(&dir, every_extension())).unwrap();
    assert!(scene.ignored.iter().all(|n| !n.contains("KHR_materials")), "{:?}", scene.ignored);
    let l = &scene.materials[0].layers;
    assert!(l.is_layered() && l.transmits());
    assert_eq!(l.extensions(), super::super::layers::EXTENSIONS.to_vec());
    assert_eq!((l.ior, l.specular, l.specular_color), (1.33, 0.5, Vec3::new(1.0, 0.5, 2.0)));
    assert_eq!((l.clearcoat, l.clearcoat_roughness, l.clearcoat_normal_scale), (1.0, 0.2, 0.5));
    assert_eq!((l.sheen_color, l.sheen_roughness), (Vec3::new(0.9, 0.1, 0.2), 0.6));
    assert_eq!((l.transmission, l.thickness, l.attenuation_distance), (0.8, 0.25, 2.0));
    assert_eq!(l.attenuation_color, Vec3::new(0.9, 0.5, 0.1));
    assert_eq!(
        (l.iridescence, l.iridescence_ior, l.iridescence_thickness_min, l.iridescence_thickness_max),
        (1.0, 1.8, 200.0, 800.0)
    );
    assert_eq!((l.anisotropy_strength, l.anisotropy_rotation, l.dispersion), (0.7, 1.5, 0.3));
    assert_eq!((l.diffuse_transmission, l.diffuse_transmission_color), (0.4, Vec3::new(0.2, 0.9, 0.3)));
    // Every slot the file fills holds its image (0: colour, 1: data), UV set and transform.
    let filled: Vec<LayerTexture> = LayerTexture::ALL.into_iter().filter(|&s| l.texture(s).is_some()).collect();
    assert_eq!(filled, LayerTexture::ALL.to_vec());
    assert_eq!(l.texture(LayerTexture::SheenColor).unwrap().tex_coord, 1);
    assert_eq!(l.texture(LayerTexture::ClearcoatNormal).unwrap().transform.scale, Vec2::splat(4.0));
    assert_eq!(l.texture(LayerTexture::SpecularColor).unwrap().image, 0);
    assert_eq!(l.texture(LayerTexture::Anisotropy).unwrap().image, 1);
    // Colour slots make their image sRGB; data slots leave theirs linear.
    assert_eq!(scene.images[0].color_space, ColorSpace::Srgb);
    assert_eq!(scene.images[1].color_space, ColorSpace::Linear);
}

#[test]
fn absent_keys_take_the_specs_defaults_and_a_plain_material_is_not_layered() {
    let dir = TempDir::new("layer-defaults");
    let names = [
        "KHR_materials_ior",
        "KHR_materials_specular",
        "KHR_materials_volume",
        "KHR_materials_iridescence",
        "KHR_materials_diffuse_transmission",
    ];
    let empty: serde_json::Map<String, Value> = names.iter().map(|n| (n.to_string(), json!({}))).collect();
    let scene = load_doc(&dir, &with_extensions(&dir, Value::Object(empty))).unwrap();
    let defaults = MaterialLayers::default();
    assert_eq!(scene.materials[0].layers, defaults);
    assert!(!defaults.is_layered());
    assert!(defaults.extensions().is_empty());
    assert_eq!((defaults.ior, defaults.iridescence_ior), (1.5, 1.3));
    assert_eq!((defaults.iridescence_thickness_min, defaults.iridescence_thickness_max), (100.0, 400.0));
    assert!(defaults.attenuation_distance.is_infinite());
    // ior 0 is the spec's infinite index: kept, so F0 comes out 1.
    let scene = load_doc(&dir, &with_extensions(&dir, json!({ "KHR_materials_ior": { "ior": 0.0 } }))).unwrap();
    assert_eq!(scene.materials[0].layers.ior, 0.0);
}

#[test]
fn out_of_range_values_name_the_material_extension_and_key() {
    let dir = TempDir::new("layer-errors");
    let cases = [
        (json!({ "KHR_materials_ior": { "ior": 0.5 } }), "KHR_materials_ior.ior is 0.5, but must be at least 1"),
        (
            json!({ "KHR_materials_volume": { "thicknessFactor": -1.0 } }),
            "KHR_materials_volume.thicknessFactor is -1, but must be at least 0",
        ),
        (
            json!({ "KHR_materials_volume": { "attenuationDistance": 0.0 } }),
            "KHR_materials_volume.attenuationDistance is 0, but must be above 0",
        ),
        (
            json!({ "KHR_materials_clearcoat": { "clearcoatFactor": 1.5 } }),
            "KHR_materials_clearcoat.clearcoatFactor is 1.5, but must be within [0, 1]",
        ),
        (
            json!({ "KHR_materials_sheen": { "sheenColorFactor": [0.5, 2.0, 0.5] } }),
            "KHR_materials_sheen.sheenColorFactor is [0.5,2,0.5]: every channel must be within [0, 1]",
        ),
        (
            json!({ "KHR_materials_specular": { "specularColorFactor": [1.0, 1.0] } }),
            "KHR_materials_specular.specularColorFactor is [1,1], not three finite numbers",
        ),
        (
            json!({ "KHR_materials_transmission": { "transmissionFactor": "all" } }),
            "KHR_materials_transmission.transmissionFactor is \"all\", not a finite number",
        ),
        (
            json!({ "KHR_materials_dispersion": { "dispersion": -0.1 } }),
            "KHR_materials_dispersion.dispersion is -0.1, but must be at least 0",
        ),
        (
            json!({ "KHR_materials_anisotropy": { "anisotropyTexture": { "index": 9 } } }),
            "KHR_materials_anisotropy.anisotropyTexture: index 9 names no texture (the file has 3)",
        ),
    ];
    for (extensions, expected) in cases {
        let message = invalid_message(load_doc(&dir, &with_extensions(&dir, extensions)));
        assert_eq!(message, format!("material 0 (painted): {expected}"));
    }
}
