//! One model written four ways: plain floats and a PNG texture, KHR_mesh_quantization
//! (integer positions, normals and UVs), EXT_meshopt_compression (every view compressed,
//! behind a fallback buffer with no data) and EXT_texture_webp (the texture as WebP only).
//! Each variant, loaded by the importer and rendered, must give the plain image: mean FLIP
//! below 0.01. A model with its texture changed must not, so the measure can see a
//! difference of that size.

mod common;

use base64::Engine as _;
use chiaro_math::Aabb;
use chiaro_scene::shapes::{plane, sphere};
use chiaro_scene::types::Primitive;
use chiaro_scene::{Scene, Settings, load_gltf};
use common::{ldr_rgb, mean_flip, render, renderer};
use glam::{Mat4, Vec3};
use serde_json::{Value, json};
use std::path::PathBuf;

const SIZE: u32 = 256;
const MAX_MEAN_FLIP: f32 = 0.01;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Variant {
    Plain,
    Quantized,
    Meshopt,
    Webp,
}

/// Positions are stored as SHORT in steps of 1/QUANTUM m, undone by the node's scale; the
/// model lies within [-3, 3] m, inside SHORT's range.
const QUANTUM: f32 = 8192.0;

/// A 6 m square floor at y = -1, facing up, with whole-metre corners (exact as integers)
/// and UVs in [0, 1] (as normalized integers hold them).
fn floor() -> Primitive {
    let mut floor = plane(6.0, 1);
    floor.positions.iter_mut().for_each(|p| p.y = -1.0);
    floor.uv0.iter_mut().for_each(|uv| *uv /= 6.0);
    floor.bounds = Aabb::from_points(floor.positions.iter().copied());
    floor
}

fn checker(colors: [[u8; 4]; 2]) -> image::DynamicImage {
    image::DynamicImage::ImageRgba8(image::RgbaImage::from_fn(64, 32, |x, y| {
        image::Rgba(colors[((x / 8 + y / 8) % 2) as usize])
    }))
}

fn encoded(image: &image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write_to(&mut bytes, format).unwrap();
    bytes.into_inner()
}

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

/// Buffer views and accessors as they are added; with meshopt, each view's plain bytes sit
/// in a fallback buffer (0) that has no data and its compressed bytes in buffer 1.
struct Document {
    variant: Variant,
    plain_length: usize,
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Document {
    /// A buffer view of `plain`; with meshopt, `compressed` gives its compressed bytes, its
    /// element count and the extension's mode.
    fn view(&mut self, plain: &[u8], stride: Option<usize>, compressed: Option<(Vec<u8>, usize, &str)>) -> usize {
        let mut view = json!({ "buffer": 0, "byteLength": plain.len() });
        if let Some(stride) = stride {
            view["byteStride"] = json!(stride);
        }
        if let Some((bytes, count, mode)) = compressed {
            view["byteOffset"] = json!(self.plain_length);
            view["extensions"] = json!({ "EXT_meshopt_compression": {
                "buffer": 1, "byteOffset": self.bytes.len(), "byteLength": bytes.len(),
                "byteStride": plain.len() / count, "count": count, "mode": mode } });
            self.plain_length += plain.len().next_multiple_of(4);
            self.bytes.extend(bytes);
        } else {
            view["byteOffset"] = json!(self.bytes.len());
            self.bytes.extend(plain);
        }
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views.push(view);
        self.views.len() - 1
    }

    fn meshopt(&self) -> bool {
        self.variant == Variant::Meshopt
    }

    fn attribute_view<T: bytemuck::Pod>(&mut self, values: &[T], stride: Option<usize>) -> usize {
        let compressed = self
            .meshopt()
            .then(|| (meshopt::encoding::encode_vertex_buffer(values).unwrap(), values.len(), "ATTRIBUTES"));
        self.view(bytemuck::cast_slice(values), stride, compressed)
    }

    fn index_view(&mut self, indices: &[u32], vertex_count: usize) -> usize {
        let compressed = self.meshopt().then(|| {
            (meshopt::encoding::encode_index_buffer(indices, vertex_count).unwrap(), indices.len(), "TRIANGLES")
        });
        self.view(bytemuck::cast_slice(indices), None, compressed)
    }

    fn accessor(&mut self, view: usize, component: u32, normalized: bool, count: usize, ty: &str) -> usize {
        self.accessors.push(json!({
            "bufferView": view, "componentType": component, "normalized": normalized, "count": count, "type": ty
        }));
        self.accessors.len() - 1
    }

    /// Float attributes, or with quantization the integer formats KHR_mesh_quantization allows.
    fn primitive(&mut self, p: &Primitive, material: usize) -> Value {
        let n = p.positions.len();
        let (position, normal, uv, (min, max)) = if self.variant == Variant::Quantized {
            let positions: Vec<[i16; 4]> =
                p.positions.iter().map(|v| v.extend(0.0).to_array().map(|c| (c * QUANTUM).round() as i16)).collect();
            let normals: Vec<[i8; 4]> =
                p.normals.iter().map(|v| v.extend(0.0).to_array().map(|c| (c * 127.0).round() as i8)).collect();
            let uvs: Vec<[u16; 2]> =
                p.uv0.iter().map(|uv| uv.to_array().map(|c| (c * 65535.0).round() as u16)).collect();
            let (position, normal, uv) = (
                self.attribute_view(&positions, Some(8)),
                self.attribute_view(&normals, Some(4)),
                self.attribute_view(&uvs, None),
            );
            // Rounding keeps order, so the stored bounds are the rounded bounds.
            let bounds = ((p.bounds.min * QUANTUM).round(), (p.bounds.max * QUANTUM).round());
            (
                self.accessor(position, 5122, false, n, "VEC3"),
                self.accessor(normal, 5120, true, n, "VEC3"),
                self.accessor(uv, 5123, true, n, "VEC2"),
                bounds,
            )
        } else {
            let (position, normal, uv) = (
                self.attribute_view(&p.positions, Some(12)),
                self.attribute_view(&p.normals, Some(12)),
                self.attribute_view(&p.uv0, Some(8)),
            );
            (
                self.accessor(position, 5126, false, n, "VEC3"),
                self.accessor(normal, 5126, false, n, "VEC3"),
                self.accessor(uv, 5126, false, n, "VEC2"),
                (p.bounds.min, p.bounds.max),
            )
        };
        self.accessors[position]["min"] = json!(min.to_array());
        self.accessors[position]["max"] = json!(max.to_array());
        let indices = self.index_view(&p.indices, n);
        let indices = self.accessor(indices, 5125, false, p.indices.len(), "SCALAR");
        json!({
            "attributes": { "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv },
            "indices": indices,
            "material": material
        })
    }
}

/// The model as a glTF document: a textured sphere over a floor, a directional light that
/// casts the sphere's shadow, and a camera.
fn model(variant: Variant, texture: &image::DynamicImage) -> Value {
    let mut doc = Document { variant, plain_length: 0, bytes: Vec::new(), views: Vec::new(), accessors: Vec::new() };
    let sphere = doc.primitive(&sphere(1.0, 48, 24), 0);
    let floor = doc.primitive(&floor(), 1);
    let node_scale = if variant == Variant::Quantized { 1.0 / QUANTUM } else { 1.0 };
    let world_from_camera = Mat4::look_at_rh(Vec3::new(0.0, 1.5, 4.5), Vec3::new(0.0, -0.3, 0.0), Vec3::Y).inverse();
    let world_from_light = Mat4::look_at_rh(Vec3::ZERO, Vec3::new(-0.4, -1.0, -0.5), Vec3::Y).inverse();
    let image = match variant {
        Variant::Webp => json!({ "uri": data_uri("image/webp", &encoded(texture, image::ImageFormat::WebP)) }),
        _ => json!({ "uri": data_uri("image/png", &encoded(texture, image::ImageFormat::Png)) }),
    };
    let extensions = match variant {
        Variant::Plain => vec![],
        Variant::Quantized => vec!["KHR_mesh_quantization"],
        Variant::Meshopt => vec!["EXT_meshopt_compression"],
        Variant::Webp => vec!["EXT_texture_webp"],
    };
    let texture_json = match variant {
        Variant::Webp => json!({ "extensions": { "EXT_texture_webp": { "source": 0 } } }),
        _ => json!({ "source": 0 }),
    };
    let buffers = match variant {
        Variant::Meshopt => json!([
            { "byteLength": doc.plain_length, "extensions": { "EXT_meshopt_compression": { "fallback": true } } },
            { "byteLength": doc.bytes.len(), "uri": data_uri("application/octet-stream", &doc.bytes) }
        ]),
        _ => json!([{ "byteLength": doc.bytes.len(), "uri": data_uri("application/octet-stream", &doc.bytes) }]),
    };
    let mut used = extensions.clone();
    used.push("KHR_lights_punctual");
    json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": used,
        "extensionsRequired": extensions,
        "scene": 0,
        "scenes": [{ "nodes": [0, 1, 2, 3] }],
        "nodes": [
            { "mesh": 0, "scale": [node_scale, node_scale, node_scale] },
            { "mesh": 1, "scale": [node_scale, node_scale, node_scale] },
            { "camera": 0, "matrix": world_from_camera.to_cols_array() },
            { "matrix": world_from_light.to_cols_array(), "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.9, "znear": 0.1, "zfar": 50 } }],
        "extensions": { "KHR_lights_punctual": { "lights": [{ "type": "directional", "intensity": 3 }] } },
        "meshes": [{ "primitives": [sphere] }, { "primitives": [floor] }],
        "materials": [
            { "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 }, "metallicFactor": 0, "roughnessFactor": 0.6 } },
            { "pbrMetallicRoughness": { "baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0 } }
        ],
        "textures": [texture_json],
        "images": [image],
        "accessors": doc.accessors,
        "bufferViews": doc.views,
        "buffers": buffers
    })
}

fn load(doc: &Value, name: &str) -> Scene {
    let dir = std::env::temp_dir().join(format!("chiaro-gltf-variants-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path: PathBuf = dir.join(name);
    std::fs::write(&path, doc.to_string()).unwrap();
    let scene = load_gltf(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let _ = std::fs::remove_file(&path);
    scene
}

fn rendered(scene: &Scene) -> Vec<u8> {
    let mut settings = Settings::default();
    settings.render.msaa = 1;
    ldr_rgb(&render(&mut renderer(), scene, &settings, SIZE))
}

#[test]
fn quantized_meshopt_and_webp_variants_render_as_the_plain_model() {
    let texture = checker([[200, 40, 30, 255], [240, 240, 230, 255]]);
    let plain_scene = load(&model(Variant::Plain, &texture), "plain.gltf");
    assert_eq!(plain_scene.triangle_count(), sphere(1.0, 48, 24).triangle_count() + floor().triangle_count());
    let plain = rendered(&plain_scene);
    for variant in [Variant::Quantized, Variant::Meshopt, Variant::Webp] {
        let scene = load(&model(variant, &texture), &format!("{variant:?}.gltf"));
        assert_eq!(scene.triangle_count(), plain_scene.triangle_count(), "{variant:?}");
        let flip = mean_flip(SIZE, &plain, &rendered(&scene));
        eprintln!("{variant:?} against the plain model: mean FLIP {flip}");
        assert!(flip < MAX_MEAN_FLIP, "{variant:?}: mean FLIP {flip}");
    }

    // The same model with its checker's red turned blue scores well above the limit.
    let changed = checker([[30, 40, 200, 255], [240, 240, 230, 255]]);
    let flip = mean_flip(SIZE, &plain, &rendered(&load(&model(Variant::Plain, &changed), "changed.gltf")));
    eprintln!("a changed texture against the plain model: mean FLIP {flip}");
    assert!(flip > 2.0 * MAX_MEAN_FLIP, "a changed texture scored only {flip}");
}
