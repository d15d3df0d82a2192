//! KHR_materials_variants: the file's variants load with the materials each gives its
//! primitives; the default materials show until one is selected; a variant's textures are
//! decoded though no default material uses them; broken mappings are refused naming the
//! primitive.

use super::*;

/// The textured triangle whose own material (1) is plain red; variant "textured" gives it
/// the textured material 0, variant "blue" material 2.
fn variants_doc() -> Value {
    let mut doc = textured_doc(json!({ "uri": data_uri(&png_bytes(image::DynamicImage::new_rgba8(2, 2))) }));
    doc["materials"].as_array_mut().unwrap().extend([
        json!({ "name": "red", "pbrMetallicRoughness": { "baseColorFactor": [1, 0, 0, 1] } }),
        json!({ "name": "blue", "pbrMetallicRoughness": { "baseColorFactor": [0, 0, 1, 1] } }),
    ]);
    let primitive = &mut doc["meshes"][0]["primitives"][0];
    primitive["material"] = json!(1);
    primitive["extensions"] = json!({ "KHR_materials_variants": { "mappings": [
        { "material": 0, "variants": [0] }, { "material": 2, "variants": [1] } ] } });
    doc["extensions"] =
        json!({ "KHR_materials_variants": { "variants": [{ "name": "textured" }, { "name": "blue" }] } });
    doc["extensionsUsed"] = json!(["KHR_materials_variants"]);
    doc
}

#[test]
fn variants_load_and_select_their_materials() {
    let dir = TempDir::new("variants");
    let mut scene = load_doc(&dir, &variants_doc()).unwrap();
    assert_eq!(scene.variants.names, vec!["textured", "blue"]);
    let material = |scene: &Scene| scene.meshes[0].primitives[0].material;
    assert_eq!(material(&scene), Some(1));
    // Material 0's texture is decoded though only a variant uses it.
    let texture = scene.materials[0].base_color_texture.expect("variant material keeps its texture");
    assert!(texture.image < scene.images.len());
    scene.select_variant(Some("textured")).unwrap();
    assert_eq!(material(&scene), Some(0));
    scene.select_variant(Some("blue")).unwrap();
    assert_eq!(material(&scene), Some(2));
    assert!(scene.extensions_read.iter().any(|l| l == "KHR_materials_variants: 2 variants: 'textured', 'blue'"));
}

#[test]
fn broken_mappings_are_refused_naming_the_primitive() {
    let dir = TempDir::new("variants-broken");
    let mut doc = variants_doc();
    doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][1]["variants"] = json!([2]);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(
        message.starts_with(
            "meshes[0].primitives[0] (triangle): KHR_materials_variants.mappings: variant 2 is out of range"
        ),
        "{message}"
    );

    let mut doc = variants_doc();
    doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][0]["material"] = json!(7);
    let message = invalid_message(load_doc(&dir, &doc));
    assert!(message.contains("material 7 is out of range"), "{message}");
}
