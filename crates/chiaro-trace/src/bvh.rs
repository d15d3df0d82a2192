//! A bounding volume hierarchy over every triangle of a scene, in world space.
//!
//! A `Scene` flows in; `SceneBvh` answers ray queries: `closest_hit` (what the camera
//! sees: instances that are drawn, through the holes MASK materials cut) and
//! `transmittance` (how much of a light reaches along a ray: casters block it, both faces;
//! alpha-tested casters only where their alpha passes the cutoff; dithered casters let
//! `1 - alpha` through). Queries are single rays taking `&self`, so callers parallelise
//! over rays.
//!
//! The hierarchy is obvhs's compressed wide BVH8 (PLOC build, SIMD node tests). obvhs
//! speaks glam 0.34 while Chiaro uses 0.30, so vectors cross the boundary as `[f32; 3]`
//! arrays; no glam 0.34 type is named here, `.into()` infers them from obvhs's signatures.

use crate::alpha::{AlphaImage, AlphaMaterial, alpha_images};
use chiaro_scene::{AlphaMode, CastShadows, MeshInstance, Scene, ShadowCasting};
use glam::{Vec2, Vec3};
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
    /// The primitive of the instance's mesh, and the triangle in it (indices
    /// `3 * triangle ..`), for looking up materials and vertex attributes.
    pub primitive: usize,
    pub triangle: usize,
    /// Weights of the triangle's corners at `position`.
    pub barycentrics: [f32; 3],
}

/// Every valid world-space triangle of a scene in one hierarchy.
pub struct SceneBvh {
    /// `None` when the scene has no valid triangle (obvhs does not build empty trees).
    bvh: Option<CwBvh>,
    /// Triangles in the hierarchy's primitive order, so a leaf's primitive id indexes them.
    triangles: Vec<Triangle>,
    /// The instance of each entry of `triangles`.
    triangle_instance: Vec<u32>,
    /// The (primitive, triangle) of each entry of `triangles` within its instance's mesh.
    triangle_source: Vec<(u32, u32)>,
    /// `VISIBLE | CASTER` bits of each entry of `triangles`: its instance's casting mode,
    /// less CASTER where its material casts no shadows (as in the renderer).
    triangle_mask: Vec<u8>,
    /// Per entry of `triangles`, its index in `alpha_triangles`, or `NO_ALPHA`.
    triangle_alpha: Vec<u32>,
    /// Triangles whose material tests its alpha.
    alpha_triangles: Vec<AlphaTriangle>,
    alpha_materials: Vec<AlphaMaterial>,
    alpha_images: Vec<AlphaImage>,
}

const NO_ALPHA: u32 = u32::MAX;

/// A triangle whose surface has holes or lets light through.
#[derive(Clone, Copy, Debug)]
struct AlphaTriangle {
    /// Its index among the scene's triangles, the same for every reference a pre-split
    /// build makes to it.
    original: u32,
    material: u32,
    /// Texture coordinates of its corners, in the UV set its material's texture reads.
    uv: [Vec2; 3],
}

/// One triangle gathered from the scene: its world corners, instance, mask bits, and
/// alpha data where its material needs it.
struct Gathered {
    triangle: Triangle,
    instance: u32,
    source: (u32, u32),
    mask: u8,
    alpha: Option<(u32, [Vec2; 3])>,
}

impl SceneBvh {
    /// Builds the hierarchy from every instance's primitives, transformed to world space.
    /// Triangles with a non-finite position, an index past the vertex list, or zero area
    /// are skipped; user data never panics here.
    pub fn build(scene: &Scene) -> SceneBvh {
        SceneBvh::build_with(scene, |_| true)
    }

    /// Builds the hierarchy from the instances `include` accepts (the baker leaves dynamic
    /// objects out); hits still name instances by their index in `scene`.
    pub fn build_with(scene: &Scene, include: impl Fn(&MeshInstance) -> bool + Sync) -> SceneBvh {
        let _span = tracing::info_span!("bvh_build").entered();
        let start = Instant::now();
        let gathered: Vec<Gathered> = scene
            .instances
            .par_iter()
            .enumerate()
            .filter(|(_, instance)| include(instance))
            .flat_map_iter(|(index, instance)| world_triangles(scene, index as u32, instance))
            .collect();
        // Not `Scene::triangle_count`, which trusts every instance's mesh index.
        let submitted: usize = scene
            .instances
            .iter()
            .filter(|instance| include(instance))
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
        let alpha_materials = scene.materials.iter().map(AlphaMaterial::new).collect();
        let alpha_images = alpha_images(scene);
        if gathered.is_empty() {
            return SceneBvh {
                bvh: None,
                triangles: Vec::new(),
                triangle_instance: Vec::new(),
                triangle_source: Vec::new(),
                triangle_mask: Vec::new(),
                triangle_alpha: Vec::new(),
                alpha_triangles: Vec::new(),
                alpha_materials,
                alpha_images,
            };
        }

        let source: Vec<Triangle> = gathered.iter().map(|g| g.triangle).collect();
        let bvh = build_cwbvh_from_tris(&source, BvhBuildParams::medium_build(), &mut Duration::default());
        // With pre-splits a triangle may be referenced from several leaves; copying per
        // reference keeps every lookup direct.
        let mut alpha_triangles = Vec::new();
        let mut triangle_alpha = Vec::with_capacity(bvh.primitive_indices.len());
        let mut triangles = Vec::with_capacity(bvh.primitive_indices.len());
        let mut triangle_instance = Vec::with_capacity(bvh.primitive_indices.len());
        let mut triangle_source = Vec::with_capacity(bvh.primitive_indices.len());
        let mut triangle_mask = Vec::with_capacity(bvh.primitive_indices.len());
        for &i in &bvh.primitive_indices {
            let g = &gathered[i as usize];
            triangles.push(g.triangle);
            triangle_instance.push(g.instance);
            triangle_source.push(g.source);
            triangle_mask.push(g.mask);
            triangle_alpha.push(match g.alpha {
                Some((material, uv)) => {
                    alpha_triangles.push(AlphaTriangle { original: i, material, uv });
                    (alpha_triangles.len() - 1) as u32
                }
                None => NO_ALPHA,
            });
        }
        tracing::debug!(
            triangles = source.len(),
            alpha_tested = alpha_triangles.len(),
            nodes = bvh.nodes.len(),
            ms = start.elapsed().as_secs_f64() * 1e3,
            "built scene BVH"
        );
        SceneBvh {
            bvh: Some(bvh),
            triangles,
            triangle_instance,
            triangle_source,
            triangle_mask,
            triangle_alpha,
            alpha_triangles,
            alpha_materials,
            alpha_images,
        }
    }

    /// Number of triangle references in the hierarchy (the valid triangles, unless a
    /// build with spatial pre-splits referenced some twice).
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The nearest drawn surface (any instance but `ShadowsOnly`) with `0 <= t < max_t`,
    /// either face, where a MASK material's alpha passes its cutoff. `direction` need not
    /// be unit; `t` and `max_t` are in its units. Non-finite or zero rays hit nothing.
    pub fn closest_hit(&self, origin: Vec3, direction: Vec3, max_t: f32) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let ray = make_ray(origin, direction, max_t)?;
        let mut ray_hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut ray_hit, |ray, id| {
            if self.triangle_mask[id] & VISIBLE == 0 {
                return f32::INFINITY;
            }
            let t = self.triangles[id].intersect(ray);
            match self.alpha_at(id, ray, t) {
                Some((material, alpha)) if material.alpha_mode == AlphaMode::Mask && alpha < material.cutoff => {
                    f32::INFINITY
                }
                _ => t,
            }
        });
        if !found {
            return None;
        }
        let id = ray_hit.primitive_id as usize;
        let tri = &self.triangles[id];
        let [a, b, c] = [tri.v0, tri.v1, tri.v2].map(|v| Vec3::from_array(v.into()));
        let position = origin + direction * ray_hit.t;
        let (primitive, triangle) = self.triangle_source[id];
        Some(Hit {
            t: ray_hit.t,
            position,
            geometric_normal: (b - a).cross(c - a).normalize_or_zero(),
            instance: self.triangle_instance[id] as usize,
            primitive: primitive as usize,
            triangle: triangle as usize,
            barycentrics: barycentrics(a, b, c, position),
        })
    }

    /// How much light gets along the ray with `0 <= t < max_t`: 0 where a solid caster
    /// (or an alpha-tested one where its alpha passes) lies on it, else the product of
    /// `1 - alpha` over the dithered casters it crosses. Instances that cast no shadows
    /// let everything through; non-finite or zero rays too.
    pub fn transmittance(&self, origin: Vec3, direction: Vec3, max_t: f32) -> f32 {
        let (Some(bvh), Some(ray)) = (self.bvh.as_ref(), make_ray(origin, direction, max_t)) else {
            return 1.0;
        };
        let mut crossed: Vec<u32> = Vec::new();
        let mut through = 1.0;
        let blocked = !bvh.ray_traverse_miss(ray, |ray, id| {
            if self.triangle_mask[id] & CASTER == 0 {
                return f32::INFINITY;
            }
            let t = self.triangles[id].intersect(ray);
            let Some((material, alpha)) = self.alpha_at(id, ray, t) else {
                return t;
            };
            match material.casting {
                ShadowCasting::Clip if alpha < material.cutoff => f32::INFINITY,
                ShadowCasting::Dither => {
                    // Each triangle once, however many leaves reference it.
                    let original = self.alpha_triangles[self.triangle_alpha[id] as usize].original;
                    if !crossed.contains(&original) {
                        crossed.push(original);
                        through *= 1.0 - alpha.clamp(0.0, 1.0);
                    }
                    f32::INFINITY
                }
                _ => t,
            }
        });
        if blocked { 0.0 } else { through }
    }

    /// Whether a caster blocks the ray entirely (see `transmittance`).
    pub fn occluded(&self, origin: Vec3, direction: Vec3, max_t: f32) -> bool {
        self.transmittance(origin, direction, max_t) == 0.0
    }

    /// The material and alpha of triangle reference `id` where `ray` meets it at `t`, for
    /// triangles whose material tests alpha; `None` for the others and for misses.
    fn alpha_at(&self, id: usize, ray: &Ray, t: f32) -> Option<(&AlphaMaterial, f32)> {
        let index = *self.triangle_alpha.get(id)?;
        if index == NO_ALPHA || !t.is_finite() {
            return None;
        }
        let alpha_triangle = &self.alpha_triangles[index as usize];
        let material = &self.alpha_materials[alpha_triangle.material as usize];
        let tri = &self.triangles[id];
        let [a, b, c] = [tri.v0, tri.v1, tri.v2].map(|v| Vec3::from_array(v.into()));
        let origin = Vec3::from_array(ray.origin.into());
        let direction = Vec3::from_array(ray.direction.into());
        let [u, v, w] = barycentrics(a, b, c, origin + direction * t);
        let [ua, ub, uc] = alpha_triangle.uv;
        Some((material, material.alpha(&self.alpha_images, ua * u + ub * v + uc * w)))
    }
}

/// Barycentric weights of `p` (in the triangle's plane) for corners `a`, `b`, `c`.
fn barycentrics(a: Vec3, b: Vec3, c: Vec3, p: Vec3) -> [f32; 3] {
    let (e0, e1, e2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let (d20, d21) = (e2.dot(e0), e2.dot(e1));
    let denominator = d00 * d11 - d01 * d01;
    if denominator == 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / denominator;
    let w = (d00 * d21 - d01 * d20) / denominator;
    [1.0 - v - w, v, w]
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

/// The valid world-space triangles of one instance, with its mask bits (less CASTER where
/// the material casts no shadows) and, where the material tests alpha, its index and the
/// corners' texture coordinates.
fn world_triangles<'a>(
    scene: &'a Scene,
    index: u32,
    instance: &'a MeshInstance,
) -> impl Iterator<Item = Gathered> + 'a {
    let primitives = scene.meshes.get(instance.mesh).map(|mesh| mesh.primitives.as_slice()).unwrap_or_default();
    let world_from_local = instance.world_from_local;
    let instance_bits = instance_mask(instance.cast_shadows);
    primitives.iter().enumerate().flat_map(move |(primitive_index, primitive)| {
        let material = primitive.material.and_then(|m| scene.materials.get(m).map(|material| (m, material)));
        let casts = material.is_none_or(|(_, m)| m.shadow_casting != ShadowCasting::Off);
        let mask = if casts { instance_bits } else { instance_bits & !CASTER };
        let alpha = material.filter(|(_, m)| AlphaMaterial::needed(m)).map(|(m, material)| {
            let uvs = if AlphaMaterial::new(material).uv_set() == 1 { &primitive.uv1 } else { &primitive.uv0 };
            (m as u32, uvs)
        });
        primitive.indices.chunks_exact(3).enumerate().filter_map(move |(triangle_index, corners)| {
            let mut world = [Vec3::ZERO; 3];
            for (w, &index) in world.iter_mut().zip(corners) {
                *w = world_from_local.transform_point3(*primitive.positions.get(index as usize)?);
            }
            let [a, b, c] = world;
            // Catches non-finite corners too: their cross product does not normalise.
            (b - a).cross(c - a).try_normalize()?;
            let alpha = alpha
                .map(|(m, uvs)| (m, [0, 1, 2].map(|k| uvs.get(corners[k] as usize).copied().unwrap_or(Vec2::ZERO))));
            Some(Gathered {
                triangle: Triangle { v0: a.to_array().into(), v1: b.to_array().into(), v2: c.to_array().into() },
                instance: index,
                source: (primitive_index as u32, triangle_index as u32),
                mask,
                alpha,
            })
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
        MeshInstance {
            mesh,
            node: 0,
            name: String::new(),
            world_from_local,
            cast_shadows,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
        }
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
}

#[cfg(test)]
mod alpha_tests {
    use super::*;
    use chiaro_scene::{ColorSpace, Image, Material, Mesh, SamplerDesc, TextureRef, shapes};
    use glam::Mat4;

    /// A 2 m plane at y = 0 (UVs 0..1 across it) with one material, seen from above.
    fn plane_scene(material: Material, images: Vec<Image>) -> Scene {
        let mut plane = shapes::plane(2.0, 1);
        plane.material = Some(0);
        Scene {
            meshes: vec![Mesh { name: "plane".into(), primitives: vec![plane] }],
            materials: vec![material],
            images,
            instances: vec![MeshInstance {
                mesh: 0,
                node: 0,
                name: "plane".into(),
                world_from_local: Mat4::IDENTITY,
                cast_shadows: CastShadows::On,
                receive_shadows: true,
                is_static: true,
                lightmap: None,
            }],
            ..Scene::default()
        }
    }

    /// 2x2 alpha: opaque where x == y (nearest sampling).
    fn checker_material(alpha_mode: AlphaMode, casting: ShadowCasting) -> (Material, Vec<Image>) {
        let texel = |a: u8| [255u8, 255, 255, a];
        let image = Image {
            name: "checker".into(),
            width: 2,
            height: 2,
            rgba8: [texel(255), texel(0), texel(0), texel(255)].concat(),
            color_space: ColorSpace::Srgb,
        };
        let material = Material {
            alpha_mode,
            shadow_casting: casting,
            base_color_texture: Some(TextureRef {
                image: 0,
                sampler: SamplerDesc { mag_linear: false, ..SamplerDesc::default() },
                tex_coord: 0,
                transform: Default::default(),
            }),
            ..Material::default()
        };
        (material, vec![image])
    }

    /// Where (x, z) on the plane falls in the checker: the plane's UVs are (x + 1, z + 1),
    /// so the 2x2 texture repeats every metre.
    fn opaque_at(x: f32, z: f32) -> bool {
        let (u, v) = ((x + 1.0).fract(), (z + 1.0).fract());
        (u < 0.5) == (v < 0.5)
    }

    #[test]
    fn clipped_casters_block_only_where_alpha_passes() {
        let (material, images) = checker_material(AlphaMode::Mask, ShadowCasting::Clip);
        let bvh = SceneBvh::build(&plane_scene(material, images));
        let mut checked = 0;
        for (x, z) in [(-0.75, -0.75), (-0.25, -0.75), (0.25, 0.25), (0.75, 0.25), (-0.8, 0.3), (0.2, 0.9)] {
            let origin = Vec3::new(x, 1.0, z);
            let blocked = bvh.occluded(origin, Vec3::NEG_Y, f32::INFINITY);
            assert_eq!(blocked, opaque_at(x, z), "({x}, {z})");
            // The camera sees the same holes.
            assert_eq!(bvh.closest_hit(origin, Vec3::NEG_Y, f32::INFINITY).is_some(), opaque_at(x, z));
            checked += 1;
        }
        assert_eq!(checked, 6);
    }

    #[test]
    fn dithered_casters_let_one_minus_alpha_through_each_time() {
        let material = Material {
            alpha_mode: AlphaMode::Blend,
            base_color: glam::Vec4::new(1.0, 1.0, 1.0, 0.3),
            shadow_casting: ShadowCasting::Dither,
            ..Material::default()
        };
        let mut scene = plane_scene(material, Vec::new());
        // A second pane 0.5 m above the first.
        let mut second = scene.instances[0].clone();
        second.world_from_local = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
        scene.instances.push(second);
        let bvh = SceneBvh::build(&scene);
        let through = bvh.transmittance(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY);
        assert!((through - 0.7 * 0.7).abs() < 1e-6, "{through}");
        // Blended glass is still seen by the camera.
        assert!(bvh.closest_hit(Vec3::new(0.1, 2.0, 0.2), Vec3::NEG_Y, f32::INFINITY).is_some());
        // Between the panes, one is crossed.
        let through = bvh.transmittance(Vec3::new(0.1, 0.25, 0.2), Vec3::Y, f32::INFINITY);
        assert!((through - 0.7).abs() < 1e-6, "{through}");
    }

    #[test]
    fn materials_that_cast_off_are_seen_but_block_nothing() {
        let material = Material { shadow_casting: ShadowCasting::Off, ..Material::default() };
        let bvh = SceneBvh::build(&plane_scene(material, Vec::new()));
        let origin = Vec3::new(0.1, 1.0, 0.2);
        assert!(bvh.closest_hit(origin, Vec3::NEG_Y, f32::INFINITY).is_some());
        assert_eq!(bvh.transmittance(origin, Vec3::NEG_Y, f32::INFINITY), 1.0);
    }

    #[test]
    fn barycentrics_rebuild_the_point() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::new(0.0, 0.0, 2.0));
        let p = a * 0.2 + b * 0.3 + c * 0.5;
        let w = barycentrics(a, b, c, p);
        assert!((w[0] - 0.2).abs() < 1e-6 && (w[1] - 0.3).abs() < 1e-6 && (w[2] - 0.5).abs() < 1e-6, "{w:?}");
    }
}
