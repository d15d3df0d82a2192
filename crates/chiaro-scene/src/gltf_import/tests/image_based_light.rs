//! EXT_lights_image_based: the scene's light becomes `Scene::environment`, read from the
//! first mip's RGBD faces as Babylon.js reads them; bad lights are errors naming the path.

use super::*;
use chiaro_testkit::image_based_light_gltf;
use glam::{Quat, Vec2, Vec3};

/// A distinct radiance per face, up to 200 nits (beyond what 8 bits hold without RGBD).
const FACES: [Vec3; 6] = [
    Vec3::new(200.0, 0.5, 0.5),
    Vec3::new(0.5, 60.0, 0.5),
    Vec3::new(0.5, 0.5, 20.0),
    Vec3::new(3.0, 3.0, 0.5),
    Vec3::new(0.5, 8.0, 8.0),
    Vec3::new(1.0, 1.0, 1.0),
];

/// `FACES`, with the top-left quarter of the +Z face (index 4) ten times brighter.
fn face(index: usize, uv: Vec2) -> Vec3 {
    if index == 4 && uv.x < 0.5 && uv.y < 0.5 { FACES[4] * 10.0 } else { FACES[index] }
}

fn load_doc(doc: &Value) -> Result<Scene, SceneError> {
    let dir = TempDir::new("ibl");
    load_gltf(&dir.write("ibl.gltf", doc.to_string().as_bytes()))
}

fn close(got: Vec3, want: Vec3) -> bool {
    ((got - want).abs() / want).max_element() < 0.03
}

#[test]
fn the_scenes_image_based_light_is_its_environment_as_babylon_reads_it() {
    let scene = load_doc(&image_based_light_gltf(8, face, json!({ "intensity": 2.0 }))).unwrap();
    let own = scene.environment.as_ref().expect("the scene's environment");
    assert_eq!(own.label, "EXT_lights_image_based light 0 (test studio)");
    assert_eq!((own.map.width, own.map.height), (32, 16));
    // Babylon.js reads the face it calls -X towards glTF's +X (the cube is left-handed),
    // the others as named; RGBD decodes to the radiance, times the intensity.
    let seen = [(Vec3::X, 1), (Vec3::NEG_X, 0), (Vec3::Y, 2), (Vec3::NEG_Y, 3), (Vec3::NEG_Z, 5)];
    for (d, index) in seen {
        let got = own.map.radiance(d);
        assert!(close(got, FACES[index] * 2.0), "{d}: {got}, face {index} is {}", FACES[index] * 2.0);
    }
    // The +Z face's top-left quarter is up and towards +X, seen from the centre.
    let bright = own.map.radiance(Vec3::new(0.4, 0.4, 1.0).normalize());
    assert!(close(bright, FACES[4] * 20.0), "{bright}");
    for dim in [Vec3::new(-0.4, 0.4, 1.0), Vec3::new(0.4, -0.4, 1.0)] {
        let got = own.map.radiance(dim.normalize());
        assert!(close(got, FACES[4] * 2.0), "{dim}: {got}");
    }
    assert!(scene.ignored.iter().any(|note| note.contains("irradianceCoefficients")), "{:?}", scene.ignored);
}

#[test]
fn the_lights_rotation_turns_world_directions_into_the_cube() {
    // A quarter turn about +Y: world -X reads the cube's +Z direction, world +Z its +X
    // (which the mirror makes the face named -X).
    let q = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    let doc = image_based_light_gltf(8, |i, _| FACES[i], json!({ "rotation": q.to_array() }));
    let own = load_doc(&doc).unwrap().environment.unwrap();
    assert!(close(own.map.radiance(Vec3::NEG_X), FACES[4]), "{}", own.map.radiance(Vec3::NEG_X));
    assert!(close(own.map.radiance(Vec3::Z), FACES[1]), "{}", own.map.radiance(Vec3::Z));
    assert!(close(own.map.radiance(Vec3::Y), FACES[2]));
    // A quarter turn about +X, written at twice unit length (it is normalised): world +Y
    // reads the cube's -Z face, as Babylon.js reads it.
    let q = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2) * 2.0;
    let doc = image_based_light_gltf(8, |i, _| FACES[i], json!({ "rotation": q.to_array() }));
    let own = load_doc(&doc).unwrap().environment.unwrap();
    assert!(close(own.map.radiance(Vec3::Y), FACES[5]), "{}", own.map.radiance(Vec3::Y));
    assert!(close(own.map.radiance(Vec3::X), FACES[1]), "{}", own.map.radiance(Vec3::X));
}

#[test]
fn faces_without_alpha_are_low_dynamic_range() {
    let mut doc = image_based_light_gltf(4, |i, _| FACES[i], json!({}));
    let grey = image::DynamicImage::ImageRgb8(image::RgbImage::from_pixel(4, 4, image::Rgb([128, 128, 128])));
    doc["images"][5] = json!({ "uri": data_uri(&png_bytes(grey)) });
    let own = load_doc(&doc).unwrap().environment.unwrap();
    let got = own.map.radiance(Vec3::NEG_Z);
    assert!(close(got, Vec3::splat((128.0f32 / 255.0).powf(2.2))), "{got}");
}

#[test]
fn a_scene_that_names_no_light_has_no_environment_and_says_so() {
    let mut doc = image_based_light_gltf(4, |i, _| FACES[i], json!({}));
    doc["scenes"][0].as_object_mut().unwrap().remove("extensions");
    let scene = load_doc(&doc).unwrap();
    assert!(scene.environment.is_none());
    assert!(scene.ignored.iter().any(|n| n.contains("names none of its lights")), "{:?}", scene.ignored);
    // A file that requires the extension is read.
    let mut doc = image_based_light_gltf(4, |i, _| FACES[i], json!({}));
    doc["extensionsRequired"] = json!(["EXT_lights_image_based"]);
    assert!(load_doc(&doc).unwrap().environment.is_some());
    // Without the extension, nothing changes.
    assert!(load_doc(&triangle_doc()).unwrap().environment.is_none());
}

/// The signature and header of an RGBA PNG of `width` x `height`, then an empty data
/// chunk: no pixels.
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(width.to_be_bytes());
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([8, 6, 0, 0, 0]);
    let crc = crc32(&ihdr);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(13u32.to_be_bytes());
    png.extend(ihdr);
    png.extend(crc.to_be_bytes());
    png.extend(0u32.to_be_bytes());
    png.extend(b"IDAT");
    png.extend(crc32(b"IDAT").to_be_bytes());
    png
}

/// The CRC-32 PNG chunks carry.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

/// A change to a good document that breaks it.
type Edit = dyn Fn(&mut Value);

#[test]
fn bad_image_based_lights_name_the_file_and_the_path() {
    let base = || image_based_light_gltf(4, |i, _| FACES[i], json!({}));
    let small = image::DynamicImage::ImageRgba8(image::RgbaImage::new(2, 2));
    let oblong = image::DynamicImage::ImageRgba8(image::RgbaImage::new(4, 2));
    let uri = |image| json!({ "uri": data_uri(&png_bytes(image)) });
    let light = "extensions.EXT_lights_image_based.lights[0]";
    let cases: Vec<(Box<Edit>, String)> = vec![
        (
            Box::new(|d| d["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"] = json!(3)),
            "scenes[0].extensions.EXT_lights_image_based.light: 3 is not one of the 1 lights".into(),
        ),
        (
            Box::new(|d| d["extensions"]["EXT_lights_image_based"]["lights"][0]["intensity"] = json!(-1.0)),
            format!("{light}.intensity: -1 is not a number from 0 to 1000000"),
        ),
        (
            Box::new(|d| d["extensions"]["EXT_lights_image_based"]["lights"][0]["intensity"] = json!(1e39)),
            format!("{light}.intensity: 1e+39 is not a number from 0 to 1000000"),
        ),
        (
            Box::new(|d| d["extensions"]["EXT_lights_image_based"]["lights"][0]["rotation"] = json!([0, 0, 0])),
            format!("{light}.rotation: [0,0,0] is not a quaternion"),
        ),
        (
            Box::new(|d| {
                d["extensions"]["EXT_lights_image_based"]["lights"][0]["specularImages"] = json!([[0, 1, 2, 3, 4]])
            }),
            format!("{light}.specularImages: its first mip is not a list of six images"),
        ),
        (
            Box::new(|d| d["extensions"]["EXT_lights_image_based"]["lights"][0]["specularImages"][0][2] = json!(9)),
            format!("{light}.specularImages[0][2]: 9 is not an image of the file"),
        ),
        (
            Box::new(move |d| d["images"][3] = uri(small.clone())),
            format!(
                "{light}.specularImages[0][3]: image 3 is 2 x 2; each face must be square and as large as the first (4)"
            ),
        ),
        (
            Box::new(move |d| d["images"][0] = uri(oblong.clone())),
            format!("{light}.specularImages[0][0]: image 0 is 4 x 2"),
        ),
        (
            // A face over the limit is refused from its PNG header: this one's pixels are
            // not even there to decode.
            Box::new(|d| d["images"][2] = json!({ "uri": data_uri(&png_header(20000, 20000)) })),
            format!("{light}.specularImages[0][2]: image 2 is 20000 x 20000, larger than the 2048 x 2048 allowed here"),
        ),
        (
            Box::new(|d| d["images"][1] = json!({ "uri": "missing-face.png" })),
            format!("{light}.specularImages[0][1]: image 1 (missing-face.png): cannot read"),
        ),
        (
            Box::new(|d| d["extensions"]["EXT_lights_image_based"]["lights"][0]["specularImageSize"] = json!(256)),
            format!("{light}.specularImageSize: 256, but its first mip's faces are 4 x 4"),
        ),
    ];
    for (edit, expected) in cases {
        let mut doc = base();
        edit(&mut doc);
        let error = load_doc(&doc).expect_err(&expected).to_string();
        assert!(error.contains("ibl.gltf") && error.contains(&expected), "expected {expected:?}, got {error}");
    }
}
