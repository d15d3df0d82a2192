//! The shadow reference: what a perfect shadow map would say, traced per pixel.
//!
//! A `Scene`, a `PixelCamera` and one range per light flow in; `ShadowReference` flows out:
//! for every pixel the surface the camera sees (position, camera-facing geometric normal,
//! whether it receives shadows) and, per light, how much of it a shadow ray from that
//! surface carries (through alpha-tested holes, dimmed by dithered casters); for a light
//! with contact-hardening (`pcss`) shadows, the share of its disc the surface sees
//! (`area`).
//! chiaro-compare's `verdict` judges a rendered shadow against it.

use crate::area::{area_light_visibility, area_shape_visibility};
use crate::bvh::{Hit, SceneBvh};
use chiaro_scene::{Light, LightKind, Scene, ShadowMode};
use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;

/// Shadow rays start this far (relative to the position's largest coordinate, at least
/// 1 m) off the surface, along its camera-facing normal: 0.1 mm near the origin, 1 cm at
/// 100 m where one float step is 7.6 µm. Too little and the ray can hit its own triangle,
/// shadowing lit surfaces (acne in the reference); too much and it starts past casters that
/// touch the surface, leaking light at contact (peter-panning in the reference).
pub const SHADOW_RAY_OFFSET_SCALE: f32 = 1.0e-4;

/// Point and spot shadow rays stop this fraction short of the light, so geometry at the
/// light itself (a bulb mesh around it) does not count.
const LIGHT_END_MARGIN: f32 = 1.0e-4;

/// A camera as the renderer sees it: the full projection and the image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelCamera {
    /// Reverse-Z perspective (clip z = 1 at the near plane, 0 at the far plane or
    /// infinity) times view-from-world; wgpu NDC, x right and y up.
    pub clip_from_world: Mat4,
    pub width: u32,
    pub height: u32,
}

impl PixelCamera {
    /// The ray through the centre of pixel `(x, y)`, counted from the top-left:
    /// `(origin on the near plane, unit direction)`, or `None` for a singular matrix.
    pub fn primary_ray(&self, x: u32, y: u32) -> Option<(Vec3, Vec3)> {
        primary_ray(&self.clip_from_world.inverse(), self.width, self.height, x, y)
    }
}

fn primary_ray(world_from_clip: &Mat4, width: u32, height: u32, x: u32, y: u32) -> Option<(Vec3, Vec3)> {
    let uv = (Vec2::new(x as f32, y as f32) + 0.5) / Vec2::new(width as f32, height as f32);
    let ndc = Vec2::new(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
    // Reverse-Z: depth 1 is the near plane; 0.5 is a finite point beyond it even for an
    // infinite projection (twice the near distance).
    let near = world_from_clip.project_point3(ndc.extend(1.0));
    let farther = world_from_clip.project_point3(ndc.extend(0.5));
    let direction = (farther - near).try_normalize()?;
    near.is_finite().then_some((near, direction))
}

/// The surface pixel `(x, y)` sees: the closest hit of its primary ray and the hit's
/// geometric normal turned to face the camera; `None` for sky (or a singular matrix).
pub(crate) fn seen_surface(
    bvh: &SceneBvh,
    world_from_clip: &Mat4,
    camera: &PixelCamera,
    x: u32,
    y: u32,
) -> Option<(Hit, Vec3)> {
    let (origin, direction) = primary_ray(world_from_clip, camera.width, camera.height, x, y)?;
    let hit = bvh.closest_hit(origin, direction, f32::INFINITY)?;
    let facing_normal =
        if hit.geometric_normal.dot(direction) > 0.0 { -hit.geometric_normal } else { hit.geometric_normal };
    Some((hit, facing_normal))
}

/// Per-pixel surfaces and per-light visibility, row-major from the top-left.
#[derive(Clone, Debug)]
pub struct ShadowReference {
    pub width: u32,
    pub height: u32,
    /// World-space position of the surface seen, `None` for sky.
    pub position: Vec<Option<Vec3>>,
    /// Unit geometric normal turned to face the camera; zero for sky.
    pub normal: Vec<Vec3>,
    /// The seen instance's `receive_shadows`; false for sky.
    pub receives: Vec<bool>,
    /// `visibility[light][pixel]`: 1 where a shadow ray reaches `scene.lights[light]`
    /// unoccluded, 0 where a caster blocks it, `1 - alpha` products through dithered
    /// casters (for a `pcss` light, the mean over rays to its disc), NaN for sky. Computed for every surface,
    /// whether or not it receives shadows, faces the light, or lies in its range or cone.
    pub visibility: Vec<Vec<f32>>,
    /// The range each light was traced with (`ranges` as given, the light's own or
    /// infinity where missing; infinity for directional lights), for the comparison.
    pub ranges: Vec<f32>,
}

impl ShadowReference {
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// Traces the reference for every light of `scene` as seen by `camera`. `ranges[i]` is
/// the range the renderer uses for `scene.lights[i]`; it does not change visibility, which
/// is traced for every surface, and is kept in `ShadowReference::ranges`.
pub fn trace_shadow_reference(scene: &Scene, camera: &PixelCamera, ranges: &[f32]) -> ShadowReference {
    let _span = tracing::info_span!(
        "shadow_reference",
        width = camera.width,
        height = camera.height,
        lights = scene.lights.len()
    )
    .entered();
    let bvh = SceneBvh::build(scene);
    let ranges: Vec<f32> = scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| match light.kind {
            LightKind::Directional => f32::INFINITY,
            _ => ranges.get(i).copied().or(light.range).unwrap_or(f32::INFINITY),
        })
        .collect();

    let world_from_clip = camera.clip_from_world.inverse();
    let rows: Vec<Row> =
        (0..camera.height).into_par_iter().map(|y| trace_row(scene, &bvh, &world_from_clip, camera, y)).collect();

    let pixels = camera.width as usize * camera.height as usize;
    let mut reference = ShadowReference {
        width: camera.width,
        height: camera.height,
        position: Vec::with_capacity(pixels),
        normal: Vec::with_capacity(pixels),
        receives: Vec::with_capacity(pixels),
        visibility: vec![Vec::with_capacity(pixels); scene.lights.len()],
        ranges,
    };
    let width = camera.width as usize;
    for row in rows {
        reference.position.extend(row.position);
        reference.normal.extend(row.normal);
        reference.receives.extend(row.receives);
        for (light, visibility) in reference.visibility.iter_mut().enumerate() {
            visibility.extend_from_slice(&row.visibility[light * width..(light + 1) * width]);
        }
    }
    reference
}

/// One traced row; `visibility` is light-major: `[light * width + x]`.
struct Row {
    position: Vec<Option<Vec3>>,
    normal: Vec<Vec3>,
    receives: Vec<bool>,
    visibility: Vec<f32>,
}

fn trace_row(scene: &Scene, bvh: &SceneBvh, world_from_clip: &Mat4, camera: &PixelCamera, y: u32) -> Row {
    let width = camera.width as usize;
    let mut row = Row {
        position: vec![None; width],
        normal: vec![Vec3::ZERO; width],
        receives: vec![false; width],
        visibility: vec![f32::NAN; width * scene.lights.len()],
    };
    for x in 0..width {
        let Some((hit, facing_normal)) = seen_surface(bvh, world_from_clip, camera, x as u32, y) else {
            continue;
        };
        row.position[x] = Some(hit.position);
        row.normal[x] = facing_normal;
        row.receives[x] = scene.instances[hit.instance].receive_shadows;
        for (light_index, light) in scene.lights.iter().enumerate() {
            let seed = ((y as u64 * camera.width as u64 + x as u64) << 8) ^ light_index as u64;
            row.visibility[light_index * width + x] = if light.is_area() {
                // Rect and disk lights are their shape, whatever their shadow mode.
                area_shape_visibility(bvh, light, hit.position, facing_normal, seed)
            } else if light.shadow.mode == ShadowMode::Pcss {
                // The light's disc, jittered per pixel and light.
                area_light_visibility(bvh, light, hit.position, facing_normal, seed)
            } else {
                light_visibility(bvh, light, hit.position, facing_normal)
            };
        }
    }
    row
}

/// Where shadow rays from a surface at `position` start: off it along `facing_normal`.
pub(crate) fn shadow_ray_origin(position: Vec3, facing_normal: Vec3) -> Vec3 {
    position + facing_normal * (SHADOW_RAY_OFFSET_SCALE * position.abs().max_element().max(1.0))
}

/// How much of `light` a shadow ray from just off the surface (on the side `facing_normal`
/// points to) carries: 1 unoccluded, 0 behind a caster, between for dithered
/// (transparent) casters. The baker's shadows use it too, so they agree with the reference.
pub fn light_visibility(bvh: &SceneBvh, light: &Light, position: Vec3, facing_normal: Vec3) -> f32 {
    let origin = shadow_ray_origin(position, facing_normal);
    let (direction, max_t) = match light.kind {
        LightKind::Directional => (-light.direction(), f32::INFINITY),
        // An area light's centre: one ray stands for it where a single ray must.
        LightKind::Point | LightKind::Spot { .. } | LightKind::Rect { .. } | LightKind::Disk { .. } => {
            let to_light = light.position() - origin;
            let distance = to_light.length();
            (to_light / distance, distance * (1.0 - LIGHT_END_MARGIN))
        }
    };
    // A ray the BVH rejects (the light at the origin, a zero direction) is not occluded.
    bvh.transmittance(origin, direction, max_t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_math::camera::perspective_reverse_z;
    use chiaro_scene::{Mesh, MeshInstance, Primitive, shapes};

    fn mesh(primitive: Primitive) -> Mesh {
        Mesh::of_triangles(String::new(), vec![primitive])
    }

    fn instance(mesh: usize, world_from_local: Mat4) -> MeshInstance {
        MeshInstance::new(mesh, world_from_local)
    }

    /// A 6 m floor and a unit box floating with its bottom 1 m above it, so the floor under
    /// it is visible from the side; one sun shining straight down and one point light
    /// 2 m above the box's top.
    fn box_scene() -> Scene {
        Scene {
            meshes: vec![mesh(shapes::plane(6.0, 3)), mesh(shapes::cuboid(Vec3::ONE))],
            instances: vec![instance(0, Mat4::IDENTITY), instance(1, Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0)))],
            lights: vec![
                Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y),
                Light::new(LightKind::Point, Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y),
            ],
            ..Scene::default()
        }
    }

    /// Looking down at the origin from above and in front.
    fn camera(width: u32, height: u32) -> PixelCamera {
        let eye = Vec3::new(0.0, 6.0, 5.0);
        let view_from_world = Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y);
        let clip_from_view = perspective_reverse_z(60f32.to_radians(), width as f32 / height as f32, 0.1, None);
        PixelCamera { clip_from_world: clip_from_view * view_from_world, width, height }
    }

    #[test]
    fn a_rect_light_is_seen_whole_beside_a_plank_hidden_under_it_and_partly_between() {
        // A 1 x 1 m rect 3 m up shining down, a 2 m wide plank 1 m above the floor.
        let light = Light::new(LightKind::Rect { width: 1.0, height: 1.0 }, Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y);
        let scene = Scene {
            meshes: vec![mesh(shapes::plane(20.0, 3)), mesh(shapes::cuboid(Vec3::ONE))],
            instances: vec![
                instance(0, Mat4::IDENTITY),
                instance(
                    1,
                    Mat4::from_scale_rotation_translation(Vec3::new(2.0, 0.05, 8.0), glam::Quat::IDENTITY, Vec3::Y),
                ),
            ],
            lights: vec![light.clone()],
            ..Scene::default()
        };
        let bvh = SceneBvh::build(&scene);
        let at = |x: f32| crate::area::area_shape_visibility(&bvh, &light, Vec3::new(x, 0.0, 0.0), Vec3::Y, 7);
        assert_eq!(at(0.0), 0.0, "under the plank's middle");
        assert_eq!(at(4.0), 1.0, "far beside it");
        // The plank's edge (x = 1) seen from the light's points x_l in [-0.5, 0.5] falls
        // at x = 1.5 - 0.5 x_l on the floor: penumbra from 1.25 to 1.75, half lit at 1.5.
        let profile: Vec<f32> = [1.3, 1.4, 1.5, 1.6, 1.7].iter().map(|&x| at(x)).collect();
        assert!(profile.windows(2).all(|w| w[0] < w[1]), "{profile:?}");
        assert!((profile[2] - 0.5).abs() < 0.1, "half the light mid-penumbra: {profile:?}");
        assert_eq!(at(1.8), 1.0);
        assert_eq!(at(1.2), 0.0);
    }

    #[test]
    fn a_strips_penumbra_is_traced_with_little_noise_whichever_side_makes_it() {
        // A 1 x 0.1 m strip 3 m up, a plank's edge at x = 1, 1 m above the floor: the
        // strip's long side across the edge makes a 0.5 m penumbra, its short side (turned
        // along the edge) a 5 cm one. Mid-penumbra, the visibility over many seeds varies
        // by under 0.01 either way (stratified over one side only, the narrow one's
        // varied by about 0.05).
        let plank = Mat4::from_scale_rotation_translation(Vec3::new(2.0, 0.05, 8.0), glam::Quat::IDENTITY, Vec3::Y);
        let scene = Scene {
            meshes: vec![mesh(shapes::plane(20.0, 3)), mesh(shapes::cuboid(Vec3::ONE))],
            instances: vec![instance(0, Mat4::IDENTITY), instance(1, plank)],
            ..Scene::default()
        };
        let bvh = SceneBvh::build(&scene);
        for (width, height) in [(1.0, 0.1), (0.1, 1.0)] {
            let light = Light::new(LightKind::Rect { width, height }, Vec3::new(0.0, 3.0, 0.0), Vec3::NEG_Y);
            // The plank's top edge (x = 1, y = 1.025) seen from the light's centre.
            let mid_penumbra = Vec3::new(3.0 / (3.0 - 1.025), 0.0, 0.0);
            let values: Vec<f32> = (0..200)
                .map(|seed| crate::area::area_shape_visibility(&bvh, &light, mid_penumbra, Vec3::Y, seed))
                .collect();
            let mean = values.iter().sum::<f32>() / values.len() as f32;
            let deviation = (values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / values.len() as f32).sqrt();
            assert!((mean - 0.5).abs() < 0.1, "{width} x {height}: mean {mean}");
            println!("{width} x {height} strip: mid-penumbra visibility {mean:.3} +- {deviation:.4}");
            assert!(deviation < 0.01, "{width} x {height}: standard deviation {deviation}");
        }
    }

    #[test]
    fn primary_rays_go_through_pixel_centres() {
        let camera = camera(64, 48);
        let eye = Vec3::new(0.0, 6.0, 5.0);
        for (x, y) in [(0, 0), (63, 0), (31, 20), (63, 47)] {
            let (origin, direction) = camera.primary_ray(x, y).unwrap();
            assert!((origin - eye).length() < 0.2, "origin on the near plane");
            assert!((direction.length() - 1.0).abs() < 1e-5);
            let clip = camera.clip_from_world * (origin + direction * 3.0).extend(1.0);
            let ndc = clip.truncate() / clip.w;
            let expected_x = (x as f32 + 0.5) / 64.0 * 2.0 - 1.0;
            let expected_y = 1.0 - (y as f32 + 0.5) / 48.0 * 2.0;
            assert!((ndc.x - expected_x).abs() < 1e-4, "{ndc} at ({x}, {y})");
            assert!((ndc.y - expected_y).abs() < 1e-4, "{ndc} at ({x}, {y})");
        }
    }

    #[test]
    fn box_shadows_its_footprint_under_a_straight_down_sun() {
        let scene = box_scene();
        let camera = camera(160, 120);
        let reference = trace_shadow_reference(&scene, &camera, &[0.0, 20.0]);
        assert_eq!(reference.visibility.len(), 2);
        assert_eq!(reference.ranges, vec![f32::INFINITY, 20.0]);
        let sun = &reference.visibility[0];
        let (mut shadowed, mut lit) = (0, 0);
        for (i, position) in reference.position.iter().enumerate() {
            let Some(p) = position else {
                assert!(sun[i].is_nan());
                assert_eq!(reference.normal[i], Vec3::ZERO);
                continue;
            };
            let to_camera = Vec3::new(0.0, 6.0, 5.0) - *p;
            assert!(reference.normal[i].dot(to_camera) > 0.0, "normal faces the camera");
            if p.y.abs() > 1e-4 {
                continue;
            }
            let footprint_distance = (p.x.abs() - 0.5).max(p.z.abs() - 0.5);
            if footprint_distance < -0.02 {
                assert_eq!(sun[i], 0.0, "floor at {p} is under the box");
                shadowed += 1;
            } else if footprint_distance > 0.02 {
                assert_eq!(sun[i], 1.0, "floor at {p} is in the open");
                lit += 1;
            }
        }
        assert!(shadowed > 50, "{shadowed} shadowed floor pixels seen");
        assert!(lit > 1000, "{lit} lit floor pixels seen");
        assert!(reference.position.iter().any(Option::is_none), "the sky is seen");
    }

    #[test]
    fn point_light_shadow_widens_with_distance() {
        let scene = box_scene();
        let reference = trace_shadow_reference(&scene, &camera(160, 120), &[]);
        // The light at height 4 and the box's top edge at height 2 put the shadow's edge on
        // the floor at 0.5 * 4 / 2 = 1 m from the centre along each axis.
        assert_eq!(reference.ranges[1], f32::INFINITY);
        let point = &reference.visibility[1];
        let mut shadowed = 0;
        for (i, position) in reference.position.iter().enumerate() {
            let Some(p) = position.filter(|p| p.y.abs() < 1e-4) else {
                continue;
            };
            let square_distance = p.x.abs().max(p.z.abs());
            if square_distance < 0.97 {
                assert_eq!(point[i], 0.0, "floor at {p} is in the point light's shadow");
                shadowed += 1;
            } else if square_distance > 1.03 {
                assert_eq!(point[i], 1.0, "floor at {p} is lit by the point light");
            }
        }
        assert!(shadowed > 200, "{shadowed}");
    }

    #[test]
    fn empty_scene_and_camera_give_empty_reference() {
        let reference = trace_shadow_reference(&Scene::default(), &camera(0, 0), &[]);
        assert_eq!(reference.pixel_count(), 0);
        let reference = trace_shadow_reference(&box_scene(), &camera(8, 0), &[1.0]);
        assert!(reference.position.is_empty());
        assert!(reference.visibility.iter().all(Vec::is_empty));
        let singular = PixelCamera { clip_from_world: Mat4::ZERO, width: 4, height: 4 };
        let reference = trace_shadow_reference(&box_scene(), &singular, &[]);
        assert!(reference.position.iter().all(Option::is_none));
        assert!(reference.visibility[0].iter().all(|v| v.is_nan()));
    }
}
