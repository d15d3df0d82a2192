//! Materials and their textures: PBR factors, texture transforms, samplers and images
//! (PNG in two bit depths, formats it cannot read) in; `Material`, decoded `Image`s and
//! generated tangents, or an error naming the image, out.

use super::{TempDir, data_uri, f32_bytes, invalid_message, load_doc, png_bytes, textured_doc, triangle_doc};
use crate::types::{AlphaMode, ColorSpace, SamplerDesc, UvTransform, WrapMode};
use glam::{Vec2, Vec3, Vec4};
use serde_json::json;

#[test]
fn unsupported_image_formats_name_the_image() {
    let dir = TempDir::new("gif");
    dir.write("tex.gif", b"GIF89a\x01\0\x01\0\0\0\0;");
    let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "uri": "tex.gif" }))));
    assert!(message.starts_with("image 0 (tex.gif): unsupported image format"), "{message}");

    dir.write("tex.png", b"definitely not a png");
    let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "uri": "tex.png" }))));
    assert!(message.starts_with("image 0 (tex.png): unsupported image format"), "{message}");

    // Said to be KTX2 (KHR_texture_basisu), and not one.
    let doc = textured_doc(json!({ "uri": "tex.png", "mimeType": "image/ktx2" }));
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.starts_with("image 0 (tex.png): not a readable KTX2 file"), "{message}");

    // An image with a bufferView and no mimeType: the gltf crate's wrapper would panic.
    let message = invalid_message(load_doc(&dir, &textured_doc(json!({ "bufferView": 0 }))));
    assert!(message.starts_with("image 0: unsupported image format"), "{message}");
}

/// A quad facing +Z with upright glTF UVs (v = 0 at the top, y = 1) and a material that
/// sets every factor and texture slot, two images written into `dir`.
pub(super) fn painted_quad(dir: &TempDir) -> serde_json::Value {
    let mut rgba = image::RgbaImage::new(2, 1);
    rgba.put_pixel(1, 0, image::Rgba([10, 20, 30, 255]));
    dir.write("color.png", &png_bytes(rgba.into()));
    let grey16 = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(1, 1, vec![65535u16]).unwrap();
    dir.write("orm.png", &png_bytes(image::DynamicImage::ImageLuma16(grey16)));

    let mut bytes = f32_bytes(&[
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, // POSITION
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // NORMAL
        0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, // TEXCOORD_0
    ]);
    bytes.extend([0u8, 1, 2, 0, 2, 3]);
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0] = json!({
        "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 2 },
        "indices": 3, "material": 0
    });
    doc["accessors"] = json!([
        { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
        { "bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3" },
        { "bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2" },
        { "bufferView": 0, "byteOffset": 128, "componentType": 5121, "count": 6, "type": "SCALAR" }
    ]);
    doc["bufferViews"] = json!([{ "buffer": 0, "byteLength": bytes.len() }]);
    doc["buffers"] = json!([{ "byteLength": bytes.len(), "uri": data_uri(&bytes) }]);
    doc["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_materials_emissive_strength"]);
    doc["materials"] = json!([{
        "name": "painted",
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.5, 0.5, 1.0],
            "baseColorTexture": { "index": 0, "extensions": { "KHR_texture_transform": {
                "offset": [0.5, 0.0], "rotation": 0.25, "scale": [2.0, 2.0], "texCoord": 1 } } },
            "metallicFactor": 0.25, "roughnessFactor": 0.75,
            "metallicRoughnessTexture": { "index": 1 }
        },
        "normalTexture": { "index": 0, "scale": 0.5,
            "extensions": { "KHR_texture_transform": { "scale": [3.0, 3.0] } } },
        "occlusionTexture": { "index": 1, "strength": 0.25 },
        "emissiveFactor": [1.0, 0.5, 0.0],
        "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 } },
        "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true
    }, { "name": "unused image", "emissiveTexture": { "index": 2 } }]);
    doc["samplers"] = json!([{ "magFilter": 9728, "minFilter": 9729, "wrapS": 33071, "wrapT": 33648 }]);
    doc["textures"] = json!([{ "source": 0, "sampler": 0 }, { "source": 1 }, { "source": 0 }]);
    doc["images"] = json!([{ "uri": "color.png" }, { "uri": "orm.png" }, { "uri": "never-read.png" }]);
    doc
}

#[test]
fn materials_textures_and_generated_tangents() {
    let dir = TempDir::new("material");
    let scene = load_doc(&dir, &painted_quad(&dir)).unwrap();

    // Image 0 is both colour and normal map: decoded once, as sRGB.
    assert_eq!(scene.images.len(), 2);
    let color = &scene.images[0];
    assert_eq!((color.width, color.height), (2, 1));
    assert_eq!(color.color_space, ColorSpace::Srgb);
    assert_eq!(&color.rgba8[4..], &[10, 20, 30, 255]);
    assert_eq!(color.name, "color.png");
    let orm = &scene.images[1];
    assert_eq!(orm.color_space, ColorSpace::Linear);
    assert_eq!(orm.rgba8, vec![255, 255, 255, 255]);

    let m = &scene.materials[0];
    assert_eq!(m.name, "painted");
    assert_eq!(m.base_color, Vec4::new(0.5, 0.5, 0.5, 1.0));
    assert_eq!((m.metallic, m.roughness), (0.25, 0.75));
    assert_eq!(m.emissive, Vec3::new(4.0, 2.0, 0.0));
    assert_eq!(m.alpha_mode, AlphaMode::Mask);
    assert_eq!(m.alpha_cutoff, 0.3);
    assert!(m.double_sided);
    assert_eq!((m.normal_scale, m.occlusion_strength), (0.5, 0.25));
    let base = m.base_color_texture.unwrap();
    assert_eq!(base.image, 0);
    assert_eq!(base.tex_coord, 1);
    assert_eq!(
        base.transform,
        UvTransform { offset: Vec2::new(0.5, 0.0), rotation_rad: 0.25, scale: Vec2::splat(2.0) }
    );
    assert_eq!(
        base.sampler,
        SamplerDesc {
            wrap_u: WrapMode::ClampToEdge,
            wrap_v: WrapMode::MirroredRepeat,
            mag_linear: false,
            min_linear: true,
            mipmaps: false,
        }
    );
    let normal = m.normal_texture.unwrap();
    assert_eq!(normal.image, 0);
    assert_eq!(normal.transform.scale, Vec2::splat(3.0));
    assert_eq!(m.metallic_roughness_texture.unwrap().image, 1);
    assert_eq!(m.occlusion_texture.unwrap().sampler, SamplerDesc::default());
    // The second material's image was never decoded (its file does not exist) but
    // materials still refer into `Scene::images`.
    assert_eq!(scene.materials[1].emissive_texture.unwrap().image, 0);

    let p = &scene.meshes[0].primitives[0];
    assert_eq!(p.triangle_count(), 2);
    for t in &p.tangents {
        assert!(t.truncate().distance(Vec3::X) < 1e-5, "{t}");
        assert_eq!(t.w, 1.0);
    }
}

#[test]
fn khr_materials_unlit_marks_its_materials_unlit() {
    let dir = TempDir::new("unlit");
    let mut doc = triangle_doc();
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    // Required, as files that cannot be shown lit ask: the importer must accept it.
    doc["extensionsUsed"] = json!(["KHR_materials_unlit"]);
    doc["extensionsRequired"] = json!(["KHR_materials_unlit"]);
    doc["materials"] = json!([
        { "name": "flat", "extensions": { "KHR_materials_unlit": {} },
          "pbrMetallicRoughness": { "baseColorFactor": [0.2, 0.4, 0.6, 1.0] } },
        { "name": "lit" }
    ]);
    let scene = load_doc(&dir, &doc).unwrap();
    assert!(scene.materials[0].unlit, "the extension's presence makes the material unlit");
    assert_eq!(scene.materials[0].base_color, Vec4::new(0.2, 0.4, 0.6, 1.0));
    assert!(!scene.materials[1].unlit, "a material without the extension is lit");
    assert!(!scene.ignored.iter().any(|note| note.contains("KHR_materials_unlit")), "{:?}", scene.ignored);
}

/// A material that names TEXCOORD_2 (and TEXCOORD_3) gets those sets in the vertex's UV
/// slots, its textures pointed at the slots.
#[test]
fn any_texcoord_set_a_material_names_is_read() {
    let dir = TempDir::new("texcoord-n");
    let mut doc = textured_doc(json!({ "uri": data_uri(&png_bytes(image::DynamicImage::new_rgba8(1, 1))) }));
    // TEXCOORD_1, _2 and _3 after TEXCOORD_0 (accessor 1) in a second buffer.
    let sets: [[f32; 6]; 3] =
        [[0.1, 0.1, 0.1, 0.1, 0.1, 0.1], [0.2, 0.0, 0.4, 0.0, 0.2, 0.6], [0.9, 0.8, 0.7, 0.6, 0.5, 0.4]];
    let bytes = f32_bytes(&sets.concat());
    doc["buffers"].as_array_mut().unwrap().push(json!({ "byteLength": bytes.len(), "uri": data_uri(&bytes) }));
    doc["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": bytes.len() }));
    for (k, name) in ["TEXCOORD_1", "TEXCOORD_2", "TEXCOORD_3"].iter().enumerate() {
        let accessor = doc["accessors"].as_array().unwrap().len();
        doc["accessors"]
            .as_array_mut()
            .unwrap()
            .push(json!({ "bufferView": 1, "byteOffset": 24 * k, "componentType": 5126, "count": 3, "type": "VEC2" }));
        doc["meshes"][0]["primitives"][0]["attributes"][*name] = json!(accessor);
    }
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = json!(2);
    let scene = load_doc(&dir, &doc).unwrap();
    let primitive = &scene.meshes[0].primitives[0];
    assert_eq!(primitive.uv0, sets[1].chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect::<Vec<_>>());
    assert_eq!(primitive.uv1, sets[0].chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect::<Vec<_>>());
    assert_eq!(scene.materials[0].base_color_texture.unwrap().tex_coord, 0);
    assert!(scene.ignored.iter().all(|n| !n.contains("a third set")), "{:?}", scene.ignored);

    // Sets 0 and 3: TEXCOORD_3 in the second slot.
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = json!(3);
    doc["materials"][0]["emissiveTexture"] = json!({ "index": 0, "texCoord": 0 });
    let scene = load_doc(&dir, &doc).unwrap();
    let primitive = &scene.meshes[0].primitives[0];
    assert_eq!(primitive.uv1, sets[2].chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect::<Vec<_>>());
    let material = &scene.materials[0];
    assert_eq!((material.base_color_texture.unwrap().tex_coord, material.emissive_texture.unwrap().tex_coord), (1, 0));
    // TEXCOORD_2 is read by no material now: noted.
    assert!(
        scene.ignored.iter().any(|n| n.contains("TEXCOORD_2 or above that its material does not read")),
        "{:?}",
        scene.ignored
    );
}
