//! The BVH against brute force over every triangle, and its instance masks: what the
//! camera sees, what casts shadows, and what invalid geometry and rays do.

use super::*;
use chiaro_scene::{Mesh, Primitive, shapes};
use glam::{Mat4, Quat};
use proptest::prelude::*;
use std::sync::OnceLock;

fn instance(mesh: usize, world_from_local: Mat4, cast_shadows: CastShadows) -> MeshInstance {
    MeshInstance { cast_shadows, ..MeshInstance::new(mesh, world_from_local) }
}

fn mesh(primitive: Primitive) -> Mesh {
    Mesh::of_triangles(String::new(), vec![primitive])
}

/// A floor, two turned boxes and a squashed sphere, apart from one another, with every
/// shadow mode.
fn test_scene() -> Scene {
    Scene {
        meshes: vec![
            mesh(shapes::plane(8.0, 4)),
            mesh(shapes::cuboid(Vec3::new(1.0, 2.0, 0.5))),
            mesh(shapes::sphere(0.7, 16, 8)),
        ],
        instances: vec![
            instance(0, Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0)), CastShadows::On),
            instance(
                1,
                Mat4::from_rotation_translation(
                    Quat::from_rotation_y(0.6) * Quat::from_rotation_x(0.3),
                    Vec3::new(1.8, 0.2, 0.3),
                ),
                CastShadows::TwoSided,
            ),
            instance(
                2,
                Mat4::from_scale_rotation_translation(
                    Vec3::new(1.0, 0.6, 1.4),
                    Quat::from_rotation_z(0.4),
                    Vec3::new(-1.7, 0.4, 0.5),
                ),
                CastShadows::Off,
            ),
            instance(
                1,
                Mat4::from_scale_rotation_translation(
                    Vec3::splat(0.8),
                    Quat::from_rotation_x(1.1),
                    Vec3::new(0.0, 1.5, -2.0),
                ),
                CastShadows::ShadowsOnly,
            ),
        ],
        ..Scene::default()
    }
}

fn shared() -> &'static (Scene, SceneBvh) {
    static SHARED: OnceLock<(Scene, SceneBvh)> = OnceLock::new();
    SHARED.get_or_init(|| {
        let scene = test_scene();
        let bvh = SceneBvh::build(&scene);
        (scene, bvh)
    })
}

/// Every triangle of the accepted instances, tested one by one with the same
/// triangle intersection: `(t, instance)` of the nearest.
fn brute_force(
    scene: &Scene,
    origin: Vec3,
    direction: Vec3,
    max_t: f32,
    accept: impl Fn(CastShadows) -> bool,
) -> Option<(f32, usize)> {
    let ray = Ray::new(origin.to_array().into(), direction.to_array().into(), 0.0, max_t);
    let mut best: Option<(f32, usize)> = None;
    for (index, inst) in scene.instances.iter().enumerate() {
        if !accept(inst.cast_shadows) {
            continue;
        }
        for primitive in &scene.meshes[inst.mesh].primitives {
            for corners in primitive.indices.chunks_exact(3) {
                let [a, b, c] =
                    [0, 1, 2].map(|k| inst.world_from_local.transform_point3(primitive.positions[corners[k] as usize]));
                if (b - a).cross(c - a).try_normalize().is_none() {
                    continue;
                }
                let tri = Triangle { v0: a.to_array().into(), v1: b.to_array().into(), v2: c.to_array().into() };
                let t = tri.intersect(&ray);
                if t < max_t && best.is_none_or(|(best_t, _)| t < best_t) {
                    best = Some((t, index));
                }
            }
        }
    }
    best
}

fn arb_ray() -> impl Strategy<Value = (Vec3, Vec3, f32)> {
    let point = |r: f32| (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vec3::new(x, y, z));
    let max_t = prop_oneof![Just(f32::INFINITY), 0.1f32..8.0];
    // Aiming at a point near the objects makes most rays hit; the direction keeps
    // the aim's length, so `t` is not a distance.
    let aimed = (point(6.0), point(2.5), max_t.clone())
        .prop_filter("distinct", |(o, target, _)| o.distance(*target) > 1e-3)
        .prop_map(|(origin, target, max_t)| (origin, target - origin, max_t));
    // Axis directions as negation makes them, with -0.0 components.
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::NEG_X, Vec3::NEG_Y, Vec3::NEG_Z];
    let axial = (point(3.0), proptest::sample::select(axes.to_vec()), max_t)
        .prop_map(|(origin, axis, max_t)| (origin, -axis, max_t));
    prop_oneof![3 => aimed, 1 => axial]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn closest_hit_equals_brute_force((origin, direction, max_t) in arb_ray()) {
        let (scene, bvh) = shared();
        let expected = brute_force(scene, origin, direction, max_t, |c| {
            c != CastShadows::ShadowsOnly
        });
        let got = bvh.closest_hit(origin, direction, max_t);
        prop_assert_eq!(got.map(|h| (h.t, h.instance)), expected);
        if let Some(hit) = got {
            prop_assert!((hit.position - (origin + direction * hit.t)).length() < 1e-5);
            prop_assert!((hit.geometric_normal.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn occluded_equals_brute_force((origin, direction, max_t) in arb_ray()) {
        let (scene, bvh) = shared();
        let expected =
            brute_force(scene, origin, direction, max_t, |c| c != CastShadows::Off);
        prop_assert_eq!(bvh.occluded(origin, direction, max_t), expected.is_some());
    }
}

#[test]
fn most_aimed_rays_hit() {
    let (_, bvh) = shared();
    let mut state = 0x2545_f491_u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    let hits = (0..1000)
        .filter(|_| {
            let origin = Vec3::new(next(), next(), next()) * 6.0;
            let target = Vec3::new(next(), next(), next()) * 2.0;
            bvh.closest_hit(origin, target - origin, f32::INFINITY).is_some()
        })
        .count();
    assert!(hits > 500, "{hits} of 1000 aimed rays hit");
}

#[test]
fn hits_name_the_triangle_and_weights_that_rebuild_their_position() {
    let (scene, bvh) = shared();
    let mut checked = 0;
    for k in 0..400 {
        let angle = k as f32 * 0.37;
        let origin = Vec3::new(angle.cos() * 6.0, 3.0 + (k % 7) as f32 * 0.3, angle.sin() * 6.0);
        let target = Vec3::new((k % 5) as f32 * 0.4 - 0.8, 0.2, (k % 3) as f32 * 0.5 - 0.5);
        let Some(hit) = bvh.closest_hit(origin, target - origin, f32::INFINITY) else { continue };
        let instance = &scene.instances[hit.instance];
        let primitive = &scene.meshes[instance.mesh].primitives[hit.primitive];
        let corners = &primitive.indices[3 * hit.triangle..3 * hit.triangle + 3];
        let rebuilt: Vec3 = corners
            .iter()
            .zip(hit.barycentrics)
            .map(|(&i, w)| instance.world_from_local.transform_point3(primitive.positions[i as usize]) * w)
            .sum();
        assert!(rebuilt.distance(hit.position) < 1e-4, "{rebuilt} vs {}", hit.position);
        checked += 1;
    }
    assert!(checked > 100, "{checked} hits");
}

/// A floor at y = 0 and three quads above it facing up, at heights 1, 2 and 3, with
/// shadows off, shadows only and on.
fn stacked_scene() -> Scene {
    let at = |y: f32| Mat4::from_translation(Vec3::new(0.0, y, 0.0));
    Scene {
        meshes: vec![mesh(shapes::plane(4.0, 1)), mesh(shapes::plane(1.0, 1))],
        instances: vec![
            instance(0, at(0.0), CastShadows::On),
            instance(1, at(1.0), CastShadows::Off),
            instance(1, at(2.0), CastShadows::ShadowsOnly),
            instance(1, at(3.0), CastShadows::On),
        ],
        ..Scene::default()
    }
}

#[test]
fn closest_hit_skips_shadows_only_and_sees_shadows_off() {
    let bvh = SceneBvh::build(&stacked_scene());
    let hit = bvh.closest_hit(Vec3::new(0.1, 2.5, 0.1), Vec3::NEG_Y, f32::INFINITY);
    let hit = hit.expect("the quad with shadows off is drawn");
    assert_eq!(hit.instance, 1);
    assert!((hit.t - 1.5).abs() < 1e-6);
    assert_eq!(hit.geometric_normal, Vec3::Y);
    // Beside the small quads, down to the floor.
    let hit = bvh.closest_hit(Vec3::new(1.5, 2.5, 0.1), Vec3::NEG_Y, f32::INFINITY);
    assert_eq!(hit.map(|h| h.instance), Some(0));
    // Straight up from between the quads: the shadows-only quad is not seen.
    let hit = bvh.closest_hit(Vec3::new(0.1, 1.5, 0.1), Vec3::Y, f32::INFINITY);
    assert_eq!(hit.map(|h| h.instance), Some(3));
}

#[test]
fn occluded_counts_shadows_only_and_ignores_shadows_off() {
    let bvh = SceneBvh::build(&stacked_scene());
    let origin = Vec3::new(0.1, 0.001, 0.1);
    // Up through the back face of the quad with shadows off (ignored) to the
    // shadows-only one at t = 2 (counted, back face).
    assert!(!bvh.occluded(origin, Vec3::Y, 1.9));
    assert!(bvh.occluded(origin, Vec3::Y, 2.1));
    // Down from above, front faces.
    assert!(bvh.occluded(Vec3::new(0.1, 2.5, 0.1), Vec3::NEG_Y, 1.0));
    assert!(!bvh.occluded(Vec3::new(0.1, 1.5, 0.1), Vec3::NEG_Y, 1.0));
    // Negated axis directions carry -0.0 components.
    assert!(bvh.occluded(origin, -Vec3::NEG_Y, 2.1));
    assert!(bvh.occluded(Vec3::new(0.1, 2.5, 0.1), -Vec3::Y, 1.0));
    assert_eq!(bvh.closest_hit(Vec3::new(0.1, 2.5, 0.1), -Vec3::Y, 9.0).map(|h| h.instance), Some(1));
    // max_t is exclusive of the surface itself.
    assert!(!bvh.occluded(Vec3::new(0.1, 2.5, 0.1), Vec3::NEG_Y, 0.5));
}

#[test]
fn invalid_geometry_and_rays_are_skipped() {
    let mut primitive = Primitive {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::X * 2.0],
        ..Primitive::default()
    };
    // Valid, non-finite corner, zero area, index out of range, then a partial triangle.
    primitive.indices = vec![0, 2, 1, 0, 3, 1, 0, 1, 4, 0, 1, 9, 0, 1];
    let scene = Scene {
        meshes: vec![mesh(primitive)],
        instances: vec![instance(0, Mat4::IDENTITY, CastShadows::On), instance(7, Mat4::IDENTITY, CastShadows::On)],
        ..Scene::default()
    };
    let bvh = SceneBvh::build(&scene);
    assert_eq!(bvh.triangle_count(), 1);
    let down = Vec3::new(0.2, 1.0, 0.2);
    assert!(bvh.closest_hit(down, Vec3::NEG_Y, f32::INFINITY).is_some());
    assert!(bvh.closest_hit(down, Vec3::ZERO, f32::INFINITY).is_none());
    assert!(bvh.closest_hit(down, Vec3::NEG_Y, f32::NAN).is_none());
    assert!(!bvh.occluded(Vec3::splat(f32::NAN), Vec3::NEG_Y, 1.0));

    let empty = SceneBvh::build(&Scene::default());
    assert_eq!(empty.triangle_count(), 0);
    assert!(empty.closest_hit(down, Vec3::NEG_Y, f32::INFINITY).is_none());
    assert!(!empty.occluded(down, Vec3::NEG_Y, f32::INFINITY));
}

/// obvhs's compressed nodes skip what a ray leaves within 1e-4 ray lengths of its start;
/// the floor just in front of these origins must still be hit, and block shadow rays.
#[test]
fn surfaces_just_in_front_of_the_origin_are_hit() {
    let (scene, bvh) = shared();
    let direction = Vec3::new(-2.2201715, 2.0713806, -0.017495127);
    // x = 0 is the edge between two of the floor's quads; x = 0.5 lies inside one.
    for (x, below) in [(0.0, 1.818e-4f32), (0.0, 1e-4), (0.0, 1e-3), (0.5, 1e-5), (0.5, 1e-6)] {
        let origin = Vec3::new(x, -1.0 - below, 0.0);
        let expected = brute_force(scene, origin, direction, f32::INFINITY, |c| c != CastShadows::ShadowsOnly);
        let got = bvh.closest_hit(origin, direction, f32::INFINITY);
        assert_eq!(got.map(|h| (h.t, h.instance)), expected, "{below} m below the floor");
        assert_eq!(expected.map(|(_, instance)| instance), Some(0), "the floor is the nearest");
        assert!(bvh.occluded(origin, direction, 1.0), "{below} m below the floor: the floor blocks");
    }
}
