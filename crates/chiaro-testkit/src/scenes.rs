//! Small scenes made in code for tests and examples: a white floor with a camera, boxes
//! to stand on it, point lights, and settings with no ambient term, so that measured
//! radiance comes from the lights alone.

use chiaro_scene::settings::Settings;
use chiaro_scene::shapes;
use chiaro_scene::{Camera, CastShadows, Light, LightKind, Material, Mesh, MeshInstance, Primitive, Scene};
use glam::{Mat4, Vec3};

/// Settings with no ambient term, so only the punctual lights contribute.
pub fn unlit_settings() -> Settings {
    let mut s = Settings::default();
    s.render.ambient = [0.0; 3];
    s
}

/// A white, fully rough dielectric floor of `size` metres in the XZ plane, seen from
/// `eye` looking at the origin (+Z up in the view, so a camera straight above works).
pub fn floor_scene(size: f32, eye: Vec3, lights: Vec<Light>) -> Scene {
    let mut floor = shapes::plane(size, 4);
    floor.material = Some(0);
    Scene {
        meshes: vec![Mesh::of_triangles("floor".into(), vec![floor])],
        instances: vec![MeshInstance {
            mesh: 0,
            node: 0,
            name: "floor".into(),
            world_from_local: Mat4::IDENTITY,
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
            gpu_instance: None,
            label: 0,
        }],
        materials: vec![Material {
            name: "white".into(),
            base_color: glam::Vec4::ONE,
            metallic: 0.0,
            roughness: 1.0,
            ..Material::default()
        }],
        lights,
        cameras: vec![Camera {
            name: "test".into(),
            node: 1,
            projection: chiaro_math::camera::Projection::Perspective { yfov_rad: 70f32.to_radians() },
            znear: 0.05,
            zfar: None,
            aspect_ratio: None,
            world_from_view: Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Z).inverse(),
        }],
        ..Scene::default()
    }
}

/// A white point light named "point" on node 10.
pub fn point_light(position: Vec3, intensity: f32, range: Option<f32>) -> Light {
    Light { name: "point".into(), node: 10, intensity, range, ..Light::new(LightKind::Point, position, Vec3::NEG_Z) }
}

/// Adds a box (white, like the floor) of `size` at `position`, turned by `yaw_rad` about Y.
pub fn add_box(scene: &mut Scene, position: Vec3, size: Vec3, yaw_rad: f32, cast: CastShadows) {
    let mesh = match scene.meshes.iter().position(|m| m.name == "unit box") {
        Some(m) => m,
        None => {
            let mut cube = shapes::cuboid(Vec3::ONE);
            cube.material = Some(0);
            scene.meshes.push(Mesh::of_triangles("unit box".into(), vec![cube]));
            scene.meshes.len() - 1
        }
    };
    let node = 100 + scene.instances.len();
    scene.instances.push(MeshInstance {
        mesh,
        node,
        name: format!("box {node}"),
        world_from_local: Mat4::from_scale_rotation_translation(size, glam::Quat::from_rotation_y(yaw_rad), position),
        cast_shadows: cast,
        receive_shadows: true,
        is_static: true,
        lightmap: None,
        gpu_instance: None,
        label: 0,
    });
}

/// Adds `primitive` as a mesh of its own with a material of its own, placed by
/// `world_from_local` and casting by `cast`; returns the new instance's index.
pub fn add_mesh(
    scene: &mut Scene,
    name: &str,
    mut primitive: Primitive,
    material: Material,
    world_from_local: Mat4,
    cast: CastShadows,
) -> usize {
    primitive.material = Some(scene.materials.len());
    scene.materials.push(material);
    scene.meshes.push(Mesh::of_triangles(name.into(), vec![primitive]));
    scene.instances.push(MeshInstance {
        mesh: scene.meshes.len() - 1,
        node: 200 + scene.instances.len(),
        name: name.into(),
        world_from_local,
        cast_shadows: cast,
        receive_shadows: true,
        is_static: true,
        lightmap: None,
        gpu_instance: None,
        label: 0,
    });
    scene.instances.len() - 1
}

/// Where the plank of `plank_scene` starts, in x.
pub const PLANK_EDGE_X: f32 = 0.4;
/// How high the plank of `plank_scene` floats.
pub const PLANK_HEIGHT: f32 = 1.0;
/// How far the point or spot light of `plank_scene` stands above the floor.
pub const PLANK_LIGHT_HEIGHT: f32 = 3.0;

/// The light of `plank_scene`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlankLight {
    /// A point light PLANK_LIGHT_HEIGHT above the origin.
    Point,
    /// A spot there, shining down (outer cone 1 rad).
    Spot,
    /// A sun straight above.
    Sun,
}

/// A plank 0.8 m wide (from x = PLANK_EDGE_X), 3 m long and 4 cm thick, PLANK_HEIGHT above
/// a 6 m floor, under one light with contact-hardening shadows of `size` (radius in
/// metres, or angular diameter in degrees for the sun), the camera looking straight down
/// from `camera_height` at `look_at_x`. The plank casts shadows but the camera does not
/// see it, so the floor under it shows.
pub fn plank_scene(light: PlankLight, size: f32, camera_height: f32, look_at_x: f32) -> Scene {
    let position = Vec3::new(0.0, PLANK_LIGHT_HEIGHT, 0.0);
    let mut light = match light {
        PlankLight::Point => point_light(position, 40.0, Some(20.0)),
        PlankLight::Spot => Light {
            intensity: 40.0,
            range: Some(20.0),
            ..Light::new(LightKind::Spot { inner_cone_rad: 0.8, outer_cone_rad: 1.0 }, position, Vec3::NEG_Y)
        },
        PlankLight::Sun => Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y) },
    };
    light.shadow.mode = chiaro_scene::ShadowMode::Pcss;
    light.shadow.light_radius = size;
    light.shadow.angular_diameter_deg = size;
    let mut scene = floor_scene(6.0, Vec3::new(look_at_x, camera_height, 0.0), vec![light]);
    let (eye, target) = (Vec3::new(look_at_x, camera_height, 0.0), Vec3::new(look_at_x, 0.0, 0.0));
    scene.cameras[0].world_from_view = Mat4::look_at_rh(eye, target, Vec3::Z).inverse();
    let plank = Vec3::new(0.8, 0.04, 3.0);
    let at = Vec3::new(PLANK_EDGE_X + plank.x / 2.0, PLANK_HEIGHT, 0.0);
    add_box(&mut scene, at, plank, 0.0, CastShadows::ShadowsOnly);
    scene
}

/// A pole (8 cm thick, 1.5 m tall) standing on a 6 m floor and a plank leaning from the
/// floor up to 0.8 m, under a point light of radius 0.25 m with `mode` shadows, seen from
/// above one corner at `aspect`: contact hardening on a thin and a wide caster.
pub fn pole_and_plank_scene(mode: chiaro_scene::ShadowMode, aspect: f32) -> Scene {
    let mut light = point_light(Vec3::new(-0.8, 3.0, -0.6), 30.0, Some(15.0));
    light.shadow.mode = mode;
    light.shadow.light_radius = 0.25;
    let mut scene = floor_scene(6.0, Vec3::new(3.0, 2.5, 3.5), vec![light]);
    look_from(&mut scene, Vec3::new(2.6, 2.4, 3.2), Vec3::new(0.5, 0.0, 0.5));
    scene.cameras[0].aspect_ratio = Some(aspect);
    add_box(&mut scene, Vec3::new(-0.2, 0.75, 0.4), Vec3::new(0.08, 1.5, 0.08), 0.0, CastShadows::On);
    add_box(&mut scene, Vec3::ZERO, Vec3::ONE, 0.0, CastShadows::On);
    let plank = scene.instances.last_mut().expect("the plank");
    let rise = (0.8f32 / 1.6).asin();
    plank.world_from_local = Mat4::from_scale_rotation_translation(
        Vec3::new(1.6, 0.04, 0.5),
        glam::Quat::from_rotation_z(rise),
        Vec3::new(0.9, 0.4, -0.2),
    );
    scene
}

/// Points the scene's first camera from `eye` at `target`.
pub fn look_from(scene: &mut Scene, eye: Vec3, target: Vec3) {
    scene.cameras[0].world_from_view = Mat4::look_at_rh(eye, target, Vec3::Y).inverse();
}

/// Makes the scene's first camera orthographic: a view `2 * ymag` metres high, clip planes
/// from 0.05 m to `zfar` metres.
pub fn make_orthographic(scene: &mut Scene, ymag: f32, zfar: f32) {
    let camera = &mut scene.cameras[0];
    camera.projection = chiaro_math::camera::Projection::Orthographic { ymag };
    camera.zfar = Some(zfar);
}

/// A sphere's material in `spheres_scene`: linear base colour, metallic, roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereMaterial {
    /// Linear RGB base colour.
    pub base_color: Vec3,
    /// 0 dielectric, 1 metal.
    pub metallic: f32,
    /// Perceptual roughness.
    pub roughness: f32,
}

/// Spheres of radius 1 in a row along X (2.5 m apart, centred on the origin), one per
/// material, with no floor and no light, seen from +Z: what environment tests look at.
pub fn spheres_scene(materials: &[SphereMaterial]) -> Scene {
    let mut scene = floor_scene(1.0, Vec3::new(0.0, 0.0, 5.0), Vec::new());
    scene.materials.clear();
    scene.instances.clear();
    let count = materials.len();
    for (i, m) in materials.iter().enumerate() {
        scene.materials.push(Material {
            name: format!("sphere {i}"),
            base_color: m.base_color.extend(1.0),
            metallic: m.metallic,
            roughness: m.roughness,
            ..Material::default()
        });
        let x = (i as f32 - (count as f32 - 1.0) / 2.0) * 2.5;
        scene.instances.push(MeshInstance {
            mesh: i,
            node: 100 + i,
            name: format!("sphere {i}"),
            world_from_local: Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: false,
            lightmap: None,
            gpu_instance: None,
            label: 0,
        });
    }
    // One material per sphere: each sphere has its own mesh.
    scene.meshes = (0..count)
        .map(|i| {
            let mut sphere = shapes::sphere(1.0, 96, 48);
            sphere.material = Some(i);
            Mesh::of_triangles(format!("sphere {i}"), vec![sphere])
        })
        .collect();
    let distance = 2.0 + 1.5 * count as f32;
    look_from(&mut scene, Vec3::new(0.0, 0.0, distance), Vec3::ZERO);
    scene.cameras[0].projection = chiaro_math::camera::Projection::Perspective { yfov_rad: 50f32.to_radians() };
    scene
}

/// A glTF document whose scene carries an EXT_lights_image_based light and nothing to
/// draw but a camera at the origin looking down -Z. The light's first mip has six faces
/// of `size` texels with radiance `face(index, uv)` (uv at texel centres), stored as RGBD
/// PNGs in data URIs (images 0 to 5); `light` adds or replaces the light's properties.
pub fn image_based_light_gltf(
    size: u32,
    face: impl Fn(usize, glam::Vec2) -> Vec3,
    light: serde_json::Value,
) -> serde_json::Value {
    use base64::Engine as _;
    let images: Vec<serde_json::Value> = (0..6)
        .map(|index| {
            let pixels = image::RgbaImage::from_fn(size, size, |x, y| {
                let uv = glam::Vec2::new((x as f32 + 0.5) / size as f32, (y as f32 + 0.5) / size as f32);
                let rgbd = chiaro_scene::environment::rgbd_encode(face(index, uv));
                image::Rgba((rgbd * 255.0).round().to_array().map(|c| c as u8))
            });
            let mut png = std::io::Cursor::new(Vec::new());
            pixels.write_to(&mut png, image::ImageFormat::Png).expect("encode a face");
            let data = base64::engine::general_purpose::STANDARD.encode(png.into_inner());
            serde_json::json!({ "uri": format!("data:image/png;base64,{data}") })
        })
        .collect();
    let mut properties = serde_json::json!({
        "name": "test studio",
        "intensity": 1.0,
        "rotation": [0.0, 0.0, 0.0, 1.0],
        "irradianceCoefficients": vec![[0.0f32; 3]; 9],
        "specularImageSize": size,
        "specularImages": [[0, 1, 2, 3, 4, 5]]
    });
    if let (Some(target), serde_json::Value::Object(extra)) = (properties.as_object_mut(), light) {
        target.extend(extra);
    }
    serde_json::json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["EXT_lights_image_based"],
        "extensions": { "EXT_lights_image_based": { "lights": [properties] } },
        "scene": 0,
        "scenes": [{ "nodes": [0], "extensions": { "EXT_lights_image_based": { "light": 0 } } }],
        "nodes": [{ "camera": 0, "name": "camera" }],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "zfar": 100.0 } }],
        "images": images
    })
}
