//! One model written four ways: plain floats and a PNG texture, KHR_mesh_quantization
//! (integer positions, normals and UVs), EXT_meshopt_compression (every view compressed,
//! behind a fallback buffer with no data) and EXT_texture_webp (the texture as WebP only).
//! Each variant, loaded by the importer and rendered, must give the plain image: mean FLIP
//! below 0.01. A model with its texture changed must not, so the measure can see a
//! difference of that size.

mod common;

use base64::Engine as _;
use chiaro_scene::{Scene, Settings, load_gltf};
use common::{render, renderer};
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

/// Vertex data of one primitive.
struct Geometry {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    indices: Vec<u32>,
}

/// A unit sphere, latitude by longitude.
fn sphere(rings: u32, segments: u32) -> Geometry {
    let mut g = Geometry { positions: Vec::new(), normals: Vec::new(), uvs: Vec::new(), indices: Vec::new() };
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = v * std::f32::consts::PI;
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let phi = u * std::f32::consts::TAU;
            let p = [theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin()];
            g.positions.push(p);
            g.normals.push(p);
            g.uvs.push([u, v]);
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let b = a + row;
            g.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    g
}

/// A 6 m square floor at y = -1, facing up, with whole-metre corners (exact as integers).
fn floor() -> Geometry {
    Geometry {
        positions: vec![[-3.0, -1.0, -3.0], [-3.0, -1.0, 3.0], [3.0, -1.0, 3.0], [3.0, -1.0, -3.0]],
        normals: vec![[0.0, 1.0, 0.0]; 4],
        uvs: vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
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
    fn view(
        &mut self,
        plain: &[u8],
        stride: Option<usize>,
        compressed: impl FnOnce() -> (Vec<u8>, usize, &'static str),
    ) -> usize {
        let mut view = json!({ "buffer": 0, "byteLength": plain.len() });
        if let Some(stride) = stride {
            view["byteStride"] = json!(stride);
        }
        if self.variant == Variant::Meshopt {
            let (bytes, count, mode) = compressed();
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

    fn accessor(&mut self, view: usize, component: u32, normalized: bool, count: usize, ty: &str) -> usize {
        self.accessors.push(json!({
            "bufferView": view, "componentType": component, "normalized": normalized, "count": count, "type": ty
        }));
        self.accessors.len() - 1
    }

    /// Float attributes, or with quantization the integer formats KHR_mesh_quantization allows.
    fn primitive(&mut self, g: &Geometry, material: usize) -> Value {
        let n = g.positions.len();
        let attributes = if self.variant == Variant::Quantized {
            // Positions lie in [-3, 3]: SHORT with 1/8192 m steps, undone by the node's scale.
            let positions: Vec<[i16; 4]> =
                g.positions.iter().map(|p| [p[0], p[1], p[2], 0.0].map(|c| (c * 8192.0).round() as i16)).collect();
            let normals: Vec<[i8; 4]> =
                g.normals.iter().map(|v| [v[0], v[1], v[2], 0.0].map(|c| (c * 127.0).round() as i8)).collect();
            let uvs: Vec<[u16; 2]> = g.uvs.iter().map(|uv| uv.map(|c| (c * 65535.0).round() as u16)).collect();
            let p = self.view(bytemuck::cast_slice(&positions), Some(8), || unreachable!());
            let nv = self.view(bytemuck::cast_slice(&normals), Some(4), || unreachable!());
            let t = self.view(bytemuck::cast_slice(&uvs), None, || unreachable!());
            let position = self.accessor(p, 5122, false, n, "VEC3");
            let normal = self.accessor(nv, 5120, true, n, "VEC3");
            let uv = self.accessor(t, 5123, true, n, "VEC2");
            json!({ "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv })
        } else {
            let p = self.view(bytemuck::cast_slice(&g.positions), Some(12), || {
                (meshopt::encoding::encode_vertex_buffer(&g.positions).unwrap(), n, "ATTRIBUTES")
            });
            let nv = self.view(bytemuck::cast_slice(&g.normals), Some(12), || {
                (meshopt::encoding::encode_vertex_buffer(&g.normals).unwrap(), n, "ATTRIBUTES")
            });
            let t = self.view(bytemuck::cast_slice(&g.uvs), Some(8), || {
                (meshopt::encoding::encode_vertex_buffer(&g.uvs).unwrap(), n, "ATTRIBUTES")
            });
            let position = self.accessor(p, 5126, false, n, "VEC3");
            let normal = self.accessor(nv, 5126, false, n, "VEC3");
            let uv = self.accessor(t, 5126, false, n, "VEC2");
            json!({ "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv })
        };
        let mut attributes = attributes;
        let (min, max) = bounds(&g.positions, if self.variant == Variant::Quantized { 8192.0 } else { 1.0 });
        let position = attributes["POSITION"].as_u64().unwrap() as usize;
        self.accessors[position]["min"] = json!(min);
        self.accessors[position]["max"] = json!(max);
        let i = self.view(bytemuck::cast_slice(&g.indices), None, || {
            (meshopt::encoding::encode_index_buffer(&g.indices, n).unwrap(), g.indices.len(), "TRIANGLES")
        });
        let indices = self.accessor(i, 5125, false, g.indices.len(), "SCALAR");
        attributes = json!({ "attributes": attributes, "indices": indices, "material": material });
        attributes
    }
}

/// Per-axis bounds of `points` in the accessor's units (`scale` times metres, rounded
/// where the values are stored as integers).
fn bounds(points: &[[f32; 3]], scale: f32) -> ([f32; 3], [f32; 3]) {
    let stored = |c: f32| if scale == 1.0 { c } else { (c * scale).round() };
    let mut min = [f32::MAX; 3];
    let mut max = [f32::MIN; 3];
    for p in points {
        for k in 0..3 {
            min[k] = min[k].min(stored(p[k]));
            max[k] = max[k].max(stored(p[k]));
        }
    }
    (min, max)
}

/// The model as a glTF document: a textured sphere over a floor, a directional light that
/// casts the sphere's shadow, and a camera.
fn model(variant: Variant, texture: &image::DynamicImage) -> Value {
    let mut doc = Document { variant, plain_length: 0, bytes: Vec::new(), views: Vec::new(), accessors: Vec::new() };
    let sphere = doc.primitive(&sphere(24, 48), 0);
    let floor = doc.primitive(&floor(), 1);
    let node_scale = if variant == Variant::Quantized { 1.0 / 8192.0 } else { 1.0 };
    let world_from_camera = Mat4::look_at_rh(Vec3::new(0.0, 1.5, 4.5), Vec3::new(0.0, -0.3, 0.0), Vec3::Y).inverse();
    let world_from_light = Mat4::look_at_rh(Vec3::ZERO, Vec3::new(-0.4, -1.0, -0.5), Vec3::Y).inverse();
    let (image, extensions) = match variant {
        Variant::Webp => (
            json!({ "uri": data_uri("image/webp", &encoded(texture, image::ImageFormat::WebP)) }),
            vec!["EXT_texture_webp"],
        ),
        Variant::Quantized => (
            json!({ "uri": data_uri("image/png", &encoded(texture, image::ImageFormat::Png)) }),
            vec!["KHR_mesh_quantization"],
        ),
        Variant::Meshopt => (
            json!({ "uri": data_uri("image/png", &encoded(texture, image::ImageFormat::Png)) }),
            vec!["EXT_meshopt_compression"],
        ),
        Variant::Plain => (json!({ "uri": data_uri("image/png", &encoded(texture, image::ImageFormat::Png)) }), vec![]),
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
    let frame = render(&mut renderer(), scene, &settings, SIZE);
    frame.ldr.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

fn mean_flip(reference: &[u8], test: &[u8]) -> f32 {
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(SIZE, SIZE, reference),
        nv_flip::FlipImageRgb8::with_data(SIZE, SIZE, test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&error).mean()
}

#[test]
fn quantized_meshopt_and_webp_variants_render_as_the_plain_model() {
    let texture = checker([[200, 40, 30, 255], [240, 240, 230, 255]]);
    let plain_scene = load(&model(Variant::Plain, &texture), "plain.gltf");
    assert_eq!(plain_scene.triangle_count(), 24 * 48 * 2 + 2);
    let plain = rendered(&plain_scene);
    for variant in [Variant::Quantized, Variant::Meshopt, Variant::Webp] {
        let scene = load(&model(variant, &texture), &format!("{variant:?}.gltf"));
        assert_eq!(scene.triangle_count(), plain_scene.triangle_count(), "{variant:?}");
        let flip = mean_flip(&plain, &rendered(&scene));
        eprintln!("{variant:?} against the plain model: mean FLIP {flip}");
        assert!(flip < MAX_MEAN_FLIP, "{variant:?}: mean FLIP {flip}");
    }

    // The same model with its checker's red turned blue scores well above the limit.
    let changed = checker([[30, 40, 200, 255], [240, 240, 230, 255]]);
    let flip = mean_flip(&plain, &rendered(&load(&model(Variant::Plain, &changed), "changed.gltf")));
    eprintln!("a changed texture against the plain model: mean FLIP {flip}");
    assert!(flip > 2.0 * MAX_MEAN_FLIP, "a changed texture scored only {flip}");
}
