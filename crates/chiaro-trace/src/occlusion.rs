//! The ambient occlusion reference: how much of its hemisphere each surface the camera
//! sees keeps open, traced per pixel.
//!
//! A `Scene`, a `PixelCamera`, a radius and a ray count flow in; `OcclusionReference`
//! flows out: per pixel the surface seen and the cosine-weighted share of rays from it
//! that leave without meeting geometry within the radius. The rays are multi-jittered
//! (`sampling::multi_jittered`) over the unit square that `cosine_direction` maps to the
//! hemisphere, jittered by a hash of the pixel, so the reference is the same on every run.
//! chiaro-compare's `occlusion` judges a rendered (screen-space) AO against it.

use crate::area::unit_float;
use crate::bvh::SceneBvh;
use crate::reference::{PixelCamera, seen_surface, shadow_ray_origin};
use chiaro_math::sampling::{cosine_direction, multi_jittered};
use chiaro_scene::Scene;
use glam::{Mat4, Vec3};
use rayon::prelude::*;

/// Rays per pixel of the reference (stratified): its own noise stays below 0.01.
pub const REFERENCE_AO_RAYS: u32 = 256;

/// Per-pixel traced ambient occlusion, row-major from the top-left.
#[derive(Clone, Debug)]
pub struct OcclusionReference {
    pub width: u32,
    pub height: u32,
    /// Metres: geometry farther than this along a ray does not occlude.
    pub radius: f32,
    /// Rays traced per pixel: the count asked for, rounded up to a square (the side of the
    /// multi-jittered grid).
    pub rays: u32,
    /// Per pixel, row-major from the top-left: the cosine-weighted fraction of rays from
    /// the surface seen that leave it without hitting anything within `radius` (1 open,
    /// 0 enclosed); NaN for sky.
    pub ao: Vec<f32>,
    /// The surface seen (`None` for sky), as `ShadowReference::position`, so a comparison
    /// can match pixels.
    pub position: Vec<Option<Vec3>>,
}

/// Traces the ambient occlusion of every pixel `camera` sees of `scene`, with `rays` rays
/// a pixel (rounded up to a square) reaching `radius` metres.
pub fn trace_ambient_occlusion(scene: &Scene, camera: &PixelCamera, radius: f32, rays: u32) -> OcclusionReference {
    let _span = tracing::info_span!("occlusion_reference", width = camera.width, height = camera.height, radius, rays)
        .entered();
    let bvh = SceneBvh::build(scene);
    let world_from_clip = camera.clip_from_world.inverse();
    let rows: Vec<Vec<(f32, Option<Vec3>)>> = (0..camera.height)
        .into_par_iter()
        .map(|y| occlusion_row(&bvh, &world_from_clip, camera, radius, rays, y))
        .collect();
    let (ao, position): (Vec<f32>, Vec<Option<Vec3>>) = rows.into_iter().flatten().unzip();
    OcclusionReference { width: camera.width, height: camera.height, radius, rays: traced_rays(rays), ao, position }
}

/// One row's `(ao, position)` per pixel: NaN and `None` where the camera sees sky.
fn occlusion_row(
    bvh: &SceneBvh,
    world_from_clip: &Mat4,
    camera: &PixelCamera,
    radius: f32,
    rays: u32,
    y: u32,
) -> Vec<(f32, Option<Vec3>)> {
    (0..camera.width)
        .map(|x| {
            let Some((hit, facing_normal)) = seen_surface(bvh, world_from_clip, camera, x, y) else {
                return (f32::NAN, None);
            };
            let seed = y as u64 * camera.width as u64 + x as u64;
            (surface_occlusion(bvh, hit.position, facing_normal, radius, rays, seed), Some(hit.position))
        })
        .collect()
}

/// The open share of the hemisphere about unit `facing_normal` at `position`: the mean
/// transmittance of `rays` (rounded up to a square) cosine-weighted rays from just off the
/// surface, each stopping at `radius` metres. Drawn with the cosine's density, their plain
/// mean is the cosine-weighted share. The rays are shadow rays (`SceneBvh::transmittance`):
/// alpha-tested holes let them through, dithered casters part of them, and instances that
/// cast no shadows do not occlude. A `radius` of zero or less (or NaN) reaches nothing, so
/// the surface is open (1). `seed` chooses the jitter (one per pixel).
pub fn surface_occlusion(
    bvh: &SceneBvh,
    position: Vec3,
    facing_normal: Vec3,
    radius: f32,
    rays: u32,
    seed: u64,
) -> f32 {
    let origin = shadow_ray_origin(position, facing_normal);
    let mut state = seed;
    let points = multi_jittered(strata_side(rays), &mut || unit_float(&mut state));
    let open: f32 =
        points.iter().map(|u| bvh.transmittance(origin, cosine_direction(facing_normal, u.x, u.y), radius)).sum();
    open / points.len() as f32
}

/// Strata per side of the multi-jittered grid for `rays` rays: the square root rounded up,
/// at least 1 (255 rays give 16 x 16 = 256, 257 give 17 x 17).
fn strata_side(rays: u32) -> usize {
    let side = rays.max(1).isqrt();
    (if side * side < rays { side + 1 } else { side }) as usize
}

/// The rays `surface_occlusion` traces when asked for `rays`.
fn traced_rays(rays: u32) -> u32 {
    let side = strata_side(rays);
    u32::try_from(side * side).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_math::camera::perspective_reverse_z;
    use chiaro_scene::{Mesh, MeshInstance, Primitive, shapes};
    use glam::Quat;

    fn mesh(primitive: Primitive) -> Mesh {
        Mesh::of_triangles(String::new(), vec![primitive])
    }

    fn instance(mesh: usize, world_from_local: Mat4) -> MeshInstance {
        MeshInstance::new(mesh, world_from_local)
    }

    /// A unit box scaled to `size` and centred at `centre`.
    fn placed(size: Vec3, centre: Vec3) -> Mat4 {
        Mat4::from_scale_rotation_translation(size, Quat::IDENTITY, centre)
    }

    /// A 200 m floor at y = 0 facing up, and unit boxes placed by `boxes`.
    fn floor_and_boxes(boxes: &[Mat4]) -> Scene {
        let mut instances = vec![instance(0, Mat4::IDENTITY)];
        instances.extend(boxes.iter().map(|&world_from_local| instance(1, world_from_local)));
        Scene {
            meshes: vec![mesh(shapes::plane(200.0, 1)), mesh(shapes::cuboid(Vec3::ONE))],
            instances,
            ..Scene::default()
        }
    }

    /// A square camera with a 60 degree field of view.
    fn camera(eye: Vec3, target: Vec3, up: Vec3, size: u32) -> PixelCamera {
        let clip_from_view = perspective_reverse_z(60f32.to_radians(), 1.0, 0.1, None);
        PixelCamera { clip_from_world: clip_from_view * Mat4::look_at_rh(eye, target, up), width: size, height: size }
    }

    /// A wall 1 m thick, 100 m high and 200 m long (far larger than the radii used), its
    /// face towards the origin at `x = face_x`, reaching below the floor.
    fn wall_at(face_x: f32) -> Mat4 {
        placed(Vec3::new(1.0, 100.0, 200.0), Vec3::new(face_x + 0.5, 49.0, 0.0))
    }

    #[test]
    fn an_open_floor_seen_from_above_is_unoccluded() {
        let scene = floor_and_boxes(&[]);
        let camera = camera(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, Vec3::NEG_Z, 8);
        let reference = trace_ambient_occlusion(&scene, &camera, 2.0, REFERENCE_AO_RAYS);
        assert_eq!((reference.width, reference.height, reference.rays), (8, 8, REFERENCE_AO_RAYS));
        assert_eq!(reference.ao.len(), 64);
        assert_eq!(reference.position.len(), 64);
        for (ao, position) in reference.ao.iter().zip(&reference.position) {
            let p = position.expect("every pixel sees the floor");
            assert!(p.y.abs() < 1e-4, "{p}");
            assert!((ao - 1.0).abs() < 0.01, "floor at {p}: {ao}");
        }
    }

    #[test]
    fn a_floor_at_the_foot_of_a_wall_keeps_half_its_hemisphere() {
        // The wall's face 0.5 mm from the point: every ray with a component towards it hits
        // it well within the radius, every other leaves, and the cosine-weighted
        // hemisphere is symmetric about the wall's plane.
        let bvh = SceneBvh::build(&floor_and_boxes(&[wall_at(0.0005)]));
        for seed in [0, 1, 99] {
            let ao = surface_occlusion(&bvh, Vec3::ZERO, Vec3::Y, 20.0, REFERENCE_AO_RAYS, seed);
            assert!((ao - 0.5).abs() < 0.02, "seed {seed}: {ao}");
        }
    }

    #[test]
    fn a_floor_inside_a_closed_box_is_enclosed() {
        let bvh = SceneBvh::build(&floor_and_boxes(&[placed(Vec3::splat(2.0), Vec3::new(0.0, 0.5, 0.0))]));
        let ao = surface_occlusion(&bvh, Vec3::ZERO, Vec3::Y, 10.0, REFERENCE_AO_RAYS, 3);
        assert!(ao.abs() < 0.01, "{ao}");
    }

    #[test]
    fn geometry_beyond_the_radius_does_not_occlude() {
        let bvh = SceneBvh::build(&floor_and_boxes(&[wall_at(2.0)]));
        let near = surface_occlusion(&bvh, Vec3::ZERO, Vec3::Y, 1.0, REFERENCE_AO_RAYS, 5);
        assert!((near - 1.0).abs() < 0.01, "the wall 2 m away, radius 1 m: {near}");
        // With a 10 m radius, rays whose horizontal component towards the wall exceeds
        // 2 / 10 reach it. A cosine-weighted direction's horizontal part is uniform on the
        // unit disc, whose segment beyond x = 0.2 holds (acos 0.2 - 0.2 sqrt(0.96)) / pi
        // = 0.3735 of it: 0.6265 stays open.
        let far = surface_occlusion(&bvh, Vec3::ZERO, Vec3::Y, 10.0, REFERENCE_AO_RAYS, 5);
        assert!((far - 0.6265).abs() < 0.02, "the wall 2 m away, radius 10 m: {far}");
    }

    #[test]
    fn the_reference_is_the_same_on_every_run() {
        // Looking at a unit box on the floor from the front, slightly above: sky in the top
        // rows, the box's front face (within 1 m of the floor, so partly occluded) and the
        // floor in front of it below.
        let scene = floor_and_boxes(&[placed(Vec3::ONE, Vec3::new(0.0, 0.5, 0.0))]);
        let camera = camera(Vec3::new(0.0, 1.5, 5.0), Vec3::new(0.0, 0.5, 0.0), Vec3::Y, 16);
        let first = trace_ambient_occlusion(&scene, &camera, 1.0, REFERENCE_AO_RAYS);
        let second = trace_ambient_occlusion(&scene, &camera, 1.0, REFERENCE_AO_RAYS);
        let bits = |ao: &[f32]| ao.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&first.ao[..]), bits(&second.ao[..]));
        assert_eq!(first.position, second.position);
        assert!(first.ao.iter().zip(&first.position).all(|(ao, p)| ao.is_nan() == p.is_none()), "NaN for sky only");
        assert!(first.position.iter().any(Option::is_none), "the sky is seen");
        assert!(first.ao.iter().any(|&ao| ao < 0.95), "something is occluded: {:?}", first.ao);
    }

    #[test]
    fn ray_counts_round_up_to_a_square() {
        assert_eq!([0, 1, 2, 4, 255, 256, 257].map(strata_side), [1, 1, 2, 2, 16, 16, 17]);
        assert_eq!(traced_rays(10), 16);
        assert_eq!(traced_rays(REFERENCE_AO_RAYS), REFERENCE_AO_RAYS);
    }
}
