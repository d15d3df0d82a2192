//! A bounding volume hierarchy over every triangle of a scene, in world space.
//!
//! A `Scene` flows in; `SceneBvh` answers two ray queries: `closest_hit` (what the camera
//! sees: instances that are drawn) and `occluded` (what blocks a light: instances that cast
//! shadows, both faces). Queries are single rays taking `&self`, so callers parallelise
//! over rays.
//!
//! The hierarchy is obvhs's compressed wide BVH8 (PLOC build, SIMD node tests). obvhs
//! speaks glam 0.34 while Chiaro uses 0.30, so vectors cross the boundary as `[f32; 3]`
//! arrays; no glam 0.34 type is named here, `.into()` infers them from obvhs's signatures.

use chiaro_scene::{AlphaMode, CastShadows, MeshInstance, Scene};
use glam::Vec3;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// The instance is drawn, so primary rays see it.
const VISIBLE: u8 = 1;
/// The instance casts shadows, so shadow rays stop at it.
const CASTER: u8 = 2;

fn instance_mask(cast_shadows: CastShadows) -> u8 {
    match cast_shadows {
        CastShadows::Off => VISIBLE,
        CastShadows::On | CastShadows::TwoSided => VISIBLE | CASTER,
        CastShadows::ShadowsOnly => CASTER,
    }
}

/// The nearest surface a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray in units of the query's `direction`: `position = origin + t *
    /// direction`.
    pub t: f32,
    pub position: Vec3,
    /// Unit normal of the triangle as wound, `normalize((b - a) x (c - a))` in world space;
    /// it may face away from the ray.
    pub geometric_normal: Vec3,
    /// Index into `Scene::instances`.
    pub instance: usize,
}

/// Every valid world-space triangle of a scene in one hierarchy.
pub struct SceneBvh {
    /// `None` when the scene has no valid triangle (obvhs does not build empty trees).
    bvh: Option<CwBvh>,
    /// Triangles in the hierarchy's primitive order, so a leaf's primitive id indexes them.
    triangles: Vec<Triangle>,
    /// The instance of each entry of `triangles`.
    triangle_instance: Vec<u32>,
    /// `VISIBLE | CASTER` bits of each entry of `triangles`: its instance's casting mode,
    /// less CASTER for alpha-blended materials, which cast no shadows (as in the renderer).
    triangle_mask: Vec<u8>,
}

impl SceneBvh {
    /// Builds the hierarchy from every instance's primitives, transformed to world space.
    /// Triangles with a non-finite position, an index past the vertex list, or zero area
    /// are skipped; user data never panics here.
    pub fn build(scene: &Scene) -> SceneBvh {
        let _span = tracing::info_span!("bvh_build").entered();
        let start = Instant::now();
        let gathered: Vec<(Triangle, (u32, u8))> = scene
            .instances
            .par_iter()
            .enumerate()
            .flat_map_iter(|(index, instance)| {
                let mask = instance_mask(instance.cast_shadows);
                world_triangles(scene, instance)
                    .map(move |(tri, blended)| (tri, (index as u32, if blended { mask & !CASTER } else { mask })))
            })
            .collect();
        // Not `Scene::triangle_count`, which trusts every instance's mesh index.
        let submitted: usize = scene
            .instances
            .iter()
            .filter_map(|instance| scene.meshes.get(instance.mesh))
            .flat_map(|mesh| &mesh.primitives)
            .map(|primitive| primitive.triangle_count())
            .sum();
        if gathered.len() < submitted {
            tracing::debug!(
                skipped = submitted - gathered.len(),
                "skipped degenerate, non-finite or out-of-range triangles"
            );
        }
        if gathered.is_empty() {
            return SceneBvh {
                bvh: None,
                triangles: Vec::new(),
                triangle_instance: Vec::new(),
                triangle_mask: Vec::new(),
            };
        }

        let source: Vec<Triangle> = gathered.iter().map(|(tri, _)| *tri).collect();
        let bvh = build_cwbvh_from_tris(&source, BvhBuildParams::medium_build(), &mut Duration::default());
        // With pre-splits a triangle may be referenced from several leaves; copying per
        // reference keeps every lookup direct.
        let (triangles, tags): (Vec<Triangle>, Vec<(u32, u8)>) =
            bvh.primitive_indices.iter().map(|&i| gathered[i as usize]).unzip();
        let (triangle_instance, triangle_mask) = tags.into_iter().unzip();
        tracing::debug!(
            triangles = source.len(),
            nodes = bvh.nodes.len(),
            ms = start.elapsed().as_secs_f64() * 1e3,
            "built scene BVH"
        );
        SceneBvh { bvh: Some(bvh), triangles, triangle_instance, triangle_mask }
    }

    /// Number of triangle references in the hierarchy (the valid triangles, unless a
    /// build with spatial pre-splits referenced some twice).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The nearest drawn surface (any instance but `ShadowsOnly`) with `0 <= t < max_t`,
    /// either face. `direction` need not be unit; `t` and `max_t` are in its units.
    /// Non-finite or zero rays hit nothing.
    pub fn closest_hit(&self, origin: Vec3, direction: Vec3, max_t: f32) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let ray = make_ray(origin, direction, max_t)?;
        let mut ray_hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut ray_hit, |ray, id| self.intersect_masked(ray, id, VISIBLE));
        if !found {
            return None;
        }
        let id = ray_hit.primitive_id as usize;
        let tri = &self.triangles[id];
        let [a, b, c] = [tri.v0, tri.v1, tri.v2].map(|v| Vec3::from_array(v.into()));
        Some(Hit {
            t: ray_hit.t,
            position: origin + direction * ray_hit.t,
            geometric_normal: (b - a).cross(c - a).normalize_or_zero(),
            instance: self.triangle_instance[id] as usize,
        })
    }

    /// Whether any shadow caster (any instance but `CastShadows::Off`), either face, lies
    /// on the ray with `0 <= t < max_t`. Non-finite or zero rays are not occluded.
    pub fn occluded(&self, origin: Vec3, direction: Vec3, max_t: f32) -> bool {
        let (Some(bvh), Some(ray)) = (self.bvh.as_ref(), make_ray(origin, direction, max_t)) else {
            return false;
        };
        !bvh.ray_traverse_miss(ray, |ray, id| self.intersect_masked(ray, id, CASTER))
    }

    fn intersect_masked(&self, ray: &Ray, id: usize, mask: u8) -> f32 {
        if self.triangle_mask[id] & mask == 0 {
            return f32::INFINITY;
        }
        self.triangles[id].intersect(ray)
    }
}

/// An obvhs ray, or `None` where obvhs's finiteness assumptions would not hold.
fn make_ray(origin: Vec3, direction: Vec3, max_t: f32) -> Option<Ray> {
    let valid = origin.is_finite() && direction.is_finite() && direction != Vec3::ZERO && max_t > 0.0;
    // obvhs inverts a -0.0 component to -1/EPSILON but picks the node slab order from
    // `direction < 0.0`, which is false for -0.0: the two disagree and the ray misses every
    // node. Adding +0.0 turns -0.0 into +0.0 and leaves every other value as it is.
    let direction = direction + Vec3::ZERO;
    valid.then(|| Ray::new(origin.to_array().into(), direction.to_array().into(), 0.0, max_t))
}

/// The valid world-space triangles of one instance, as obvhs triangles, each with whether
/// its material is alpha-blended.
fn world_triangles<'a>(scene: &'a Scene, instance: &'a MeshInstance) -> impl Iterator<Item = (Triangle, bool)> + 'a {
    let primitives = scene.meshes.get(instance.mesh).map(|mesh| mesh.primitives.as_slice()).unwrap_or_default();
    let world_from_local = instance.world_from_local;
    primitives.iter().flat_map(move |primitive| {
        let blended =
            primitive.material.and_then(|m| scene.materials.get(m)).is_some_and(|m| m.alpha_mode == AlphaMode::Blend);
        primitive.indices.chunks_exact(3).filter_map(move |corners| {
            let mut world = [Vec3::ZERO; 3];
            for (w, &index) in world.iter_mut().zip(corners) {
                *w = world_from_local.transform_point3(*primitive.positions.get(index as usize)?);
            }
            let [a, b, c] = world;
            // Catches non-finite corners too: their cross product does not normalise.
            (b - a).cross(c - a).try_normalize()?;
            Some((Triangle { v0: a.to_array().into(), v1: b.to_array().into(), v2: c.to_array().into() }, blended))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{Mesh, Primitive, shapes};
    use glam::{Mat4, Quat};
    use proptest::prelude::*;
    use std::sync::OnceLock;

    fn instance(mesh: usize, world_from_local: Mat4, cast_shadows: CastShadows) -> MeshInstance {
        MeshInstance { mesh, node: 0, name: String::new(), world_from_local, cast_shadows, receive_shadows: true }
    }

    fn mesh(primitive: Primitive) -> Mesh {
        Mesh { name: String::new(), primitives: vec![primitive] }
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
                    let [a, b, c] = [0, 1, 2]
                        .map(|k| inst.world_from_local.transform_point3(primitive.positions[corners[k] as usize]));
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
}

#[cfg(test)]
mod blend_tests {
    use super::*;
    use chiaro_scene::{Material, Mesh, shapes};
    use glam::Mat4;

    #[test]
    fn blended_surfaces_are_seen_but_cast_no_shadow() {
        let mut plane = shapes::plane(2.0, 1);
        plane.material = Some(0);
        let scene = Scene {
            meshes: vec![Mesh { name: "glass".into(), primitives: vec![plane] }],
            materials: vec![Material { alpha_mode: AlphaMode::Blend, ..Material::default() }],
            instances: vec![MeshInstance {
                mesh: 0,
                node: 0,
                name: "glass".into(),
                world_from_local: Mat4::IDENTITY,
                cast_shadows: CastShadows::On,
                receive_shadows: true,
            }],
            ..Scene::default()
        };
        let bvh = SceneBvh::build(&scene);
        let origin = Vec3::new(0.1, 1.0, 0.2);
        assert!(bvh.closest_hit(origin, Vec3::NEG_Y, f32::INFINITY).is_some());
        assert!(!bvh.occluded(origin, Vec3::NEG_Y, f32::INFINITY));
    }
}
