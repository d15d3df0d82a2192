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
/// Its material is single-sided: where it lets light through, it tints a shadow only where
/// its front faces the light, as the renderer draws tints (one wall of a closed object,
/// as the camera sees one; the instance's two-sided casting does not change it).
const ONE_SIDED: u8 = 4;
/// The instance's transform mirrors, so its triangles' winding is turned.
const MIRRORED: u8 = 8;

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
    /// Its corners' vertex colour alpha (COLOR_0), 1 without vertex colours.
    vertex_alpha: [f32; 3],
}

/// One triangle gathered from the scene: its world corners, instance, mask bits, and
/// alpha data where its material needs it.
struct Gathered {
    triangle: Triangle,
    instance: u32,
    source: (u32, u32),
    mask: u8,
    /// The material, the corners' texture coordinates and vertex colour alpha.
    alpha: Option<(u32, [Vec2; 3], [f32; 3])>,
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
                Some((material, uv, vertex_alpha)) => {
                    alpha_triangles.push(AlphaTriangle { original: i, material, uv, vertex_alpha });
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
        let rays = Rays::new(origin, direction, max_t)?;
        let mut ray_hit = RayHit::none();
        let found = bvh.ray_traverse(rays.traversal, &mut ray_hit, |_, id| {
            if self.triangle_mask[id] & VISIBLE == 0 {
                return f32::INFINITY;
            }
            let t = self.triangles[id].intersect(&rays.caller);
            match self.alpha_at(id, &rays.caller, t) {
                Some((material, alpha)) if material.alpha_mode == AlphaMode::Mask && alpha < material.cutoff => {
                    f32::INFINITY
                }
                _ => Rays::traversal_t(t),
            }
        });
        if !found {
            return None;
        }
        let id = ray_hit.primitive_id as usize;
        let tri = &self.triangles[id];
        let t = tri.intersect(&rays.caller);
        let [a, b, c] = [tri.v0, tri.v1, tri.v2].map(|v| Vec3::from_array(v.into()));
        let position = origin + direction * t;
        let (primitive, triangle) = self.triangle_source[id];
        Some(Hit {
            t,
            position,
            geometric_normal: (b - a).cross(c - a).normalize_or_zero(),
            instance: self.triangle_instance[id] as usize,
            primitive: primitive as usize,
            triangle: triangle as usize,
            barycentrics: barycentrics(a, b, c, position),
        })
    }

    /// How much light gets along the ray with `0 <= t < max_t`, the mean of its three
    /// channels (`transmittance_rgb`): what the shadow reference and the baker compare.
    pub fn transmittance(&self, origin: Vec3, direction: Vec3, max_t: f32) -> f32 {
        let through = self.transmittance_rgb(origin, direction, max_t);
        (through.x + through.y + through.z) / 3.0
    }

    /// How much light gets along the ray with `0 <= t < max_t`, per channel: 0 where a
    /// solid caster (or an alpha-tested one where its alpha passes) lies on it, else the
    /// product of `1 - alpha` over the dithered casters it crosses and of the shadow
    /// transmittance over the surfaces that let light through (a coloured shadow), each
    /// surface once. Instances that cast no shadows let everything through; non-finite or
    /// zero rays too.
    pub fn transmittance_rgb(&self, origin: Vec3, direction: Vec3, max_t: f32) -> Vec3 {
        let (Some(bvh), Some(rays)) = (self.bvh.as_ref(), Rays::new(origin, direction, max_t)) else {
            return Vec3::ONE;
        };
        let mut crossed: Vec<u32> = Vec::new();
        let mut through = Vec3::ONE;
        let blocked = !bvh.ray_traverse_miss(rays.traversal, |_, id| {
            if self.triangle_mask[id] & CASTER == 0 {
                return f32::INFINITY;
            }
            let t = self.triangles[id].intersect(&rays.caller);
            let Some((material, alpha)) = self.alpha_at(id, &rays.caller, t) else {
                return Rays::traversal_t(t);
            };
            // Each triangle once, however many leaves reference it.
            let mut cross = |by: Vec3| {
                let original = self.alpha_triangles[self.triangle_alpha[id] as usize].original;
                if !crossed.contains(&original) {
                    crossed.push(original);
                    through *= by;
                }
                f32::INFINITY
            };
            match (material.casting, material.transmittance) {
                (ShadowCasting::Clip, _) if alpha < material.cutoff => f32::INFINITY,
                (ShadowCasting::Dither, _) => cross(Vec3::splat(1.0 - alpha.clamp(0.0, 1.0))),
                (ShadowCasting::On, Some(_)) if !self.tints_towards(id, direction) => f32::INFINITY,
                (ShadowCasting::On, Some(transmittance)) => cross(transmittance),
                _ => Rays::traversal_t(t),
            }
        });
        if blocked { Vec3::ZERO } else { through }
    }

    /// Whether triangle reference `id` tints light travelling against `direction` (a
    /// shadow ray's, from the surface to the light): always where its material is
    /// double-sided, else where its front (counter-clockwise, mirrored instances turned)
    /// faces the light.
    fn tints_towards(&self, id: usize, direction: Vec3) -> bool {
        let mask = self.triangle_mask[id];
        if mask & ONE_SIDED == 0 {
            return true;
        }
        let tri = &self.triangles[id];
        let [a, b, c] = [tri.v0, tri.v1, tri.v2].map(|v| Vec3::from_array(v.into()));
        let facing = (b - a).cross(c - a).dot(direction) > 0.0;
        facing != (mask & MIRRORED != 0)
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
        let [aa, ab, ac] = alpha_triangle.vertex_alpha;
        let vertex_alpha = aa * u + ab * v + ac * w;
        Some((material, vertex_alpha * material.alpha(&self.alpha_images, ua * u + ub * v + uc * w)))
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

/// How far obvhs's compressed nodes clamp a ray's entry: their test takes
/// `max(entry, 1e-4)` in ray lengths instead of the ray's `tmin` (obvhs 0.4,
/// `cwbvh::node::EPSILON`), so a node the ray leaves sooner is skipped, and with it a
/// surface that close to the origin.
const NODE_T_MIN: f32 = 1e-4;

/// The caller's ray, and the one the nodes are traversed with: the same line started
/// `NODE_T_MIN` ray lengths behind the origin, so that nothing in front of the origin is
/// skipped. Hits are measured on the caller's ray and handed to obvhs in the traversal
/// ray's lengths (`traversal_t`); hits behind the origin do not count.
struct Rays {
    caller: Ray,
    traversal: Ray,
}

impl Rays {
    /// `None` where obvhs's finiteness assumptions would not hold.
    fn new(origin: Vec3, direction: Vec3, max_t: f32) -> Option<Rays> {
        let valid = origin.is_finite() && direction.is_finite() && direction != Vec3::ZERO && max_t > 0.0;
        // obvhs inverts a -0.0 component to -1/EPSILON but picks the node slab order from
        // `direction < 0.0`, which is false for -0.0: the two disagree and the ray misses
        // every node. Adding +0.0 turns -0.0 into +0.0 and leaves every other value as it is.
        let direction = direction + Vec3::ZERO;
        let behind = origin - direction * NODE_T_MIN;
        valid.then(|| Rays {
            caller: Ray::new(origin.to_array().into(), direction.to_array().into(), 0.0, max_t),
            traversal: Ray::new(behind.to_array().into(), direction.to_array().into(), 0.0, max_t + NODE_T_MIN),
        })
    }

    /// A hit at `t` on the caller's ray, in the traversal ray's lengths (a miss stays one).
    fn traversal_t(t: f32) -> f32 {
        if t.is_finite() { t + NODE_T_MIN } else { f32::INFINITY }
    }
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
        let mut mask = if casts { instance_bits } else { instance_bits & !CASTER };
        if material.is_none_or(|(_, m)| !m.double_sided) {
            mask |= ONE_SIDED;
        }
        if world_from_local.determinant() < 0.0 {
            mask |= MIRRORED;
        }
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
            let alpha = alpha.map(|(m, uvs)| {
                let corner = |k: usize| corners[k] as usize;
                let uv = [0, 1, 2].map(|k| uvs.get(corner(k)).copied().unwrap_or(Vec2::ZERO));
                let vertex_alpha = [0, 1, 2].map(|k| primitive.colors.get(corner(k)).map_or(1.0, |c| c.w));
                (m, uv, vertex_alpha)
            });
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
mod alpha_tests;
#[cfg(test)]
mod tests;
