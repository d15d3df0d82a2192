//! The path tracer behind lightmaps and probes. Light arrives at a surface point from:
//! baked lights directly (next event estimation with the reference's shadow rays), and
//! along cosine-weighted paths: the sky (the ambient setting, or the environment where
//! `[environment] mode = "baked"`), emissive surfaces, and the
//! light of baked and mixed lights reflected by up to `bounces` surfaces, each reflecting
//! its material's whole directional albedo (diffuse and specular lobes) along a
//! cosine-weighted direction. The
//! falloff is the runtime's: inverse square times the range window, times the spot cone.
//! At every vertex a path also aims at one point of an emissive surface; that and a bounce
//! that hits one are weighed by multiple importance sampling (the power heuristic). Past
//! `ROULETTE_AFTER` reflections a path goes on with the probability of its throughput.

use crate::emitters::{Emitters, power_heuristic};
use crate::rng::Rng;
use crate::surface::Surfaces;
use chiaro_math::area_light::vector_irradiance;
use chiaro_math::light::{distance_attenuation, range_attenuation, spot_angle_params, spot_attenuation};
use chiaro_math::sampling::cosine_direction;
use chiaro_scene::environment::{EnvironmentError, EnvironmentLight};
use chiaro_scene::settings::EnvironmentMode;
use chiaro_scene::{Light, LightKind, LightMode, MeshInstance, Scene};
use chiaro_trace::area::{AREA_LIGHT_SAMPLES, area_shape_visibility};
use chiaro_trace::{SceneBvh, light_visibility};
use glam::Vec3;
use std::f32::consts::PI;

/// Rays start this far (relative to the position's largest coordinate, at least 1 m) off
/// their surface, like the reference's shadow rays.
const RAY_OFFSET_SCALE: f32 = chiaro_trace::reference::SHADOW_RAY_OFFSET_SCALE;

/// A light as the baker evaluates it.
struct BakeLight {
    /// Index in `Scene::lights`.
    index: usize,
    light: Light,
    color: Vec3,
    range: f32,
    spot: Option<(f32, f32)>,
    direct: bool,
    indirect: bool,
}

/// What a path that leaves the scene sees.
#[derive(Clone, Debug)]
pub enum Sky {
    /// `render.ambient` from every direction.
    Constant(Vec3),
    /// The environment (`[environment] mode = "baked"`).
    Environment(EnvironmentLight),
}

impl Sky {
    /// The sky for `settings`: the environment where it is baked, else the ambient term.
    pub fn for_bake(settings: &chiaro_scene::Settings, scene: &Scene) -> Result<Sky, EnvironmentError> {
        let env = &settings.environment;
        if env.mode == EnvironmentMode::Baked
            && let Some(light) = EnvironmentLight::from_settings(env, scene)?
        {
            return Ok(Sky::Environment(light));
        }
        Ok(Sky::Constant(Vec3::from(settings.render.ambient)))
    }

    /// Radiance arriving from unit direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            Sky::Constant(radiance) => *radiance,
            Sky::Environment(light) => light.radiance(d),
        }
    }
}

pub struct Tracer<'a> {
    pub bvh: &'a SceneBvh,
    surfaces: Surfaces<'a>,
    lights: Vec<BakeLight>,
    sky: Sky,
    bounces: u32,
    emitters: Emitters,
}

/// Reflections after which Russian roulette may end a path: the first ones carry most of
/// the light, and are always traced.
pub const ROULETTE_AFTER: u32 = 3;

/// How the direction of a path's last segment was chosen, which decides how much of an
/// emitter it hits counts (the rest was counted when the emitter was aimed at).
#[derive(Clone, Copy, Debug)]
pub enum Came {
    /// By a strategy the emitter table does not compete with (a probe's uniform sphere):
    /// an emitter hit counts in full.
    Unweighted,
    /// Cosine-weighted about this normal, at a vertex that also aimed at an emitter.
    Cosine(Vec3),
}

/// Rays traced, counted per work item and summed.
pub type RayCount = u64;

fn offset_of(p: Vec3) -> f32 {
    RAY_OFFSET_SCALE * p.abs().max_element().max(1.0)
}

impl<'a> Tracer<'a> {
    /// `modes` gives each scene light's mode for this bake (the file's, with mixed lights
    /// that found no shadow mask channel demoted to baked).
    pub fn new(
        scene: &'a Scene,
        modes: &[LightMode],
        bvh: &'a SceneBvh,
        sky: Sky,
        bounces: u32,
        range_threshold_lux: f32,
    ) -> Tracer<'a> {
        let lights = scene
            .lights
            .iter()
            .zip(modes)
            .enumerate()
            .filter(|(_, (_, mode))| mode.bakes_indirect())
            .map(|(index, (l, mode))| BakeLight {
                index,
                light: l.clone(),
                color: l.color * l.intensity,
                range: l.shaded_range(range_threshold_lux),
                spot: match l.kind {
                    LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
                        Some(spot_angle_params(inner_cone_rad, outer_cone_rad))
                    }
                    _ => None,
                },
                direct: mode.bakes_direct(),
                indirect: mode.bakes_indirect(),
            })
            .collect();
        // The same instances as the BVH's: an emitter the rays cannot hit is not aimed at.
        let emitters = Emitters::new(scene, bakes_instance);
        Tracer { bvh, surfaces: Surfaces::new(scene), lights, sky, bounces, emitters }
    }

    pub fn bounces(&self) -> u32 {
        self.bounces
    }

    /// Illuminance at normal incidence from light `l` at `p` (before the cosine), and the
    /// unit direction towards it; `None` out of range or cone.
    /// An area light here is its vector irradiance: what a surface facing the way the
    /// light arrives from on average would get, and that direction (exact for such a
    /// surface; probes take it so, the lightmaps' direct light is exact for every
    /// surface: `area_irradiance`).
    fn arriving(&self, l: &BakeLight, p: Vec3) -> Option<(Vec3, Vec3)> {
        match l.light.kind {
            LightKind::Directional => Some((l.color, -l.light.direction())),
            LightKind::Rect { .. } | LightKind::Disk { .. } => {
                let to_light = l.light.position() - p;
                // It lights only the side it faces.
                if to_light.dot(l.light.direction()) >= 0.0 {
                    return None;
                }
                let relative: Vec<Vec3> = l.light.area_outline_ws()?.iter().map(|&q| q - p).collect();
                let mut vector = vector_irradiance(&relative);
                if vector.dot(to_light) < 0.0 {
                    vector = -vector;
                }
                let e = l.color * (vector.length() * range_attenuation(to_light.length_squared(), l.range));
                (e.max_element() > 0.0).then(|| (e, vector.normalize()))
            }
            _ => {
                let to_light = l.light.position() - p;
                let d2 = to_light.length_squared();
                let dir = to_light.try_normalize()?;
                let mut e = l.color * distance_attenuation(d2, l.range);
                if let Some(params) = l.spot {
                    e *= spot_attenuation(l.light.direction().dot(-dir), params);
                }
                (e.max_element() > 0.0).then_some((e, dir))
            }
        }
    }

    /// How much of the light passes the shadow ray, after the light's shadow mode and
    /// strength (a light with shadows off bakes none either).
    fn visibility(&self, l: &BakeLight, p: Vec3, side: Vec3, rays: &mut RayCount) -> f32 {
        if !l.light.shadow.casts() {
            return 1.0;
        }
        1.0 - l.light.shadow.strength * (1.0 - self.seen(l, p, side, rays))
    }

    /// The share of the light that reaches `p` unblocked: one shadow ray, or for an area
    /// light its stratified rays over its shape, jittered by the position.
    fn seen(&self, l: &BakeLight, p: Vec3, side: Vec3, rays: &mut RayCount) -> f32 {
        if l.light.is_area() {
            *rays += AREA_LIGHT_SAMPLES as u64;
            let seed = p.to_array().iter().fold(l.index as u64, |h, v| h.rotate_left(21) ^ v.to_bits() as u64);
            return area_shape_visibility(self.bvh, &l.light, p, side, seed);
        }
        *rays += 1;
        light_visibility(self.bvh, &l.light, p, side)
    }

    /// Irradiance from an area light at `p` with normal `n` before shadows: exact (its
    /// projected solid angle), inside the range window about its centre.
    fn area_irradiance(&self, l: &BakeLight, p: Vec3, n: Vec3) -> Vec3 {
        let window = range_attenuation((l.light.position() - p).length_squared(), l.range);
        l.color * (l.light.area_projected_solid_angle(p, n) * window)
    }

    /// Irradiance on the surface at `p` (normal `n`, on the side of `side`) from the lights
    /// `which` selects.
    fn light_irradiance(
        &self,
        p: Vec3,
        n: Vec3,
        side: Vec3,
        which: impl Fn(&BakeLight) -> bool,
        rays: &mut RayCount,
    ) -> Vec3 {
        let mut e = Vec3::ZERO;
        for l in self.lights.iter().filter(|l| which(l)) {
            if l.light.is_area() {
                let unshadowed = self.area_irradiance(l, p, n);
                if unshadowed.max_element() > 0.0 {
                    e += unshadowed * self.visibility(l, p, side, rays);
                }
                continue;
            }
            let Some((arriving, dir)) = self.arriving(l, p) else { continue };
            let cos = n.dot(dir);
            if cos <= 0.0 || side.dot(dir) <= 0.0 {
                continue;
            }
            e += arriving * cos * self.visibility(l, p, side, rays);
        }
        e
    }

    /// Where scene light `index` sits among the tracer's lights (those baked or mixed),
    /// for `mask_visibility`: found once, not per sample.
    pub fn light_slot(&self, index: usize) -> Option<usize> {
        self.lights.iter().position(|l| l.index == index)
    }

    /// How much of the light in `slot` (from `light_slot`) reaches `p` unblocked, from the
    /// side `side` faces: the raw visibility a shadow mask stores (1 out of its range or
    /// cone, where the mask does not matter).
    pub fn mask_visibility(&self, slot: usize, p: Vec3, side: Vec3, rays: &mut RayCount) -> f32 {
        let l = &self.lights[slot];
        if self.arriving(l, p).is_none() {
            return 1.0;
        }
        self.seen(l, p, side, rays)
    }

    /// Direct irradiance from baked lights on a lightmap texel's sample point.
    pub fn direct(&self, p: Vec3, n: Vec3, side: Vec3, rays: &mut RayCount) -> Vec3 {
        self.light_irradiance(p, n, side, |l| l.direct, rays)
    }

    /// Each baked light's arriving illuminance at a probe position (after visibility), with
    /// the direction it arrives from.
    pub fn probe_deltas(&self, p: Vec3, rays: &mut RayCount) -> Vec<(Vec3, Vec3)> {
        let mut out = Vec::new();
        for l in self.lights.iter().filter(|l| l.direct) {
            let Some((arriving, dir)) = self.arriving(l, p) else { continue };
            // No surface here: the shadow ray leaves from the probe itself.
            let v = self.visibility(l, p, dir, rays);
            out.push((dir, arriving * v));
        }
        out
    }

    /// Irradiance at `p` (normal `n`, on the side of `side`) from one point aimed at on
    /// an emissive surface, weighed against the cosine-weighted bounce that could have hit
    /// it instead.
    fn emitter_irradiance(&self, p: Vec3, n: Vec3, side: Vec3, rng: &mut Rng, rays: &mut RayCount) -> Vec3 {
        let Some(s) = self.emitters.sample(rng.next_f32(), rng.next_f32(), rng.next_f32()) else {
            return Vec3::ZERO;
        };
        let to_emitter = s.position - p;
        let d2 = to_emitter.length_squared();
        let Some(dir) = to_emitter.try_normalize() else { return Vec3::ZERO };
        let cos = n.dot(dir);
        let facing = -s.normal.dot(dir);
        if cos <= 0.0 || side.dot(dir) <= 0.0 || (facing <= 0.0 && !s.double_sided) || facing.abs() < 1e-6 {
            return Vec3::ZERO;
        }
        let emitted = self.surfaces.at(s.instance, s.primitive, s.triangle, s.barycentrics).emissive;
        if emitted.max_element() <= 0.0 {
            return Vec3::ZERO;
        }
        *rays += 1;
        let visible = self.bvh.transmittance(p, dir, d2.sqrt() * (1.0 - EMITTER_END_MARGIN));
        if visible <= 0.0 {
            return Vec3::ZERO;
        }
        let pdf = s.pdf_area * d2 / facing.abs();
        emitted * (cos / pdf * power_heuristic(pdf, cos / PI) * visible)
    }

    /// How much of the emission of the surface `hit` counts, for a path that `came` to it.
    fn emission_weight(&self, came: Came, direction: Vec3, hit: &chiaro_trace::Hit) -> f32 {
        match came {
            Came::Unweighted => 1.0,
            Came::Cosine(n) => {
                let pdf_bounce = n.dot(direction).max(0.0) / PI;
                let facing = hit.geometric_normal.dot(direction).abs().max(1e-6);
                let pdf_aimed =
                    self.emitters.pdf_area(hit.instance, hit.primitive, hit.triangle) * hit.t * hit.t / facing;
                power_heuristic(pdf_bounce, pdf_aimed)
            }
        }
    }

    /// Radiance arriving at `origin` from `direction` (unit, chosen as `came` says): sky
    /// where the path escapes, emission, and light reflected by up to `reflections`
    /// surfaces along a cosine path; and the distance to the first surface the path met
    /// (`None` where it escaped at once).
    pub fn incoming(
        &self,
        origin: Vec3,
        direction: Vec3,
        came: Came,
        reflections: u32,
        rng: &mut Rng,
        rays: &mut RayCount,
    ) -> (Vec3, Option<f32>) {
        let (mut origin, mut direction, mut came) = (origin, direction, came);
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        let mut reflected = 0;
        let mut first_hit = None;
        loop {
            *rays += 1;
            let Some(hit) = self.bvh.closest_hit(origin, direction, f32::INFINITY) else {
                radiance += throughput * self.sky.radiance(direction);
                break;
            };
            first_hit = first_hit.or(Some(hit.t));
            let surface = self.surfaces.at(hit.instance, hit.primitive, hit.triangle, hit.barycentrics);
            let front = hit.geometric_normal.dot(direction) < 0.0;
            if !front && !surface.double_sided {
                // The back of a one-sided surface: nothing leaves it towards us.
                break;
            }
            let side = if front { hit.geometric_normal } else { -hit.geometric_normal };
            let mut n = if front { surface.shading_normal } else { -surface.shading_normal };
            if n.dot(side) <= 0.0 {
                n = side;
            }
            if surface.emissive.max_element() > 0.0 {
                radiance += throughput * surface.emissive * self.emission_weight(came, direction, &hit);
            }
            // What the surface reflects back along the path: its whole directional albedo
            // towards where the path came from.
            let albedo = surface.reflectance(n.dot(-direction).max(0.0));
            if reflected == reflections || albedo.max_element() <= 0.0 {
                break;
            }
            let p = hit.position + side * offset_of(hit.position);
            let e = self.light_irradiance(p, n, side, |l| l.indirect, rays)
                + self.emitter_irradiance(p, n, side, rng, rays);
            radiance += throughput * albedo / PI * e;
            throughput *= albedo;
            reflected += 1;
            if reflected >= ROULETTE_AFTER && reflected < reflections {
                let survive = throughput.max_element().min(0.95);
                if rng.next_f32() >= survive {
                    break;
                }
                throughput /= survive;
            }
            origin = p;
            direction = cosine_direction(n, rng.next_f32(), rng.next_f32());
            came = Came::Cosine(n);
            if direction.dot(side) <= 0.0 {
                break;
            }
        }
        (radiance, first_hit)
    }

    /// One sample of the irradiance at a texel's surface point, in two parts: direct light
    /// from baked lights (exact but for the point's place in the texel), and what the
    /// path brings (emitters aimed at, plus pi times the radiance along a
    /// cosine-weighted direction from `(u, v)`), which is the noisy part.
    pub fn texel_sample(
        &self,
        p: Vec3,
        n: Vec3,
        side: Vec3,
        (u, v): (f32, f32),
        rng: &mut Rng,
        rays: &mut RayCount,
    ) -> TexelSample {
        let origin = p + side * offset_of(p);
        let direct = self.direct(origin, n, side, rays);
        let mut path = self.emitter_irradiance(origin, n, side, rng, rays);
        let direction = cosine_direction(n, u, v);
        let mut first_hit = None;
        if direction.dot(side) > 0.0 {
            let (radiance, hit) = self.incoming(origin, direction, Came::Cosine(n), self.bounces, rng, rays);
            path += PI * radiance;
            first_hit = hit;
        }
        TexelSample { direct, path, first_hit }
    }
}

/// One sample of a texel's irradiance (see `Tracer::texel_sample`).
pub struct TexelSample {
    /// From baked lights, exact but for the point's place in the texel.
    pub direct: Vec3,
    /// Brought by the path (emitters, sky, bounced light): the noisy part.
    pub path: Vec3,
    /// How far the path's first segment went before meeting a surface; `None` where it
    /// escaped. How near the surroundings are says how fast bounced light can change.
    pub first_hit: Option<f32>,
}

/// Fraction of the distance to an aimed-at emitter point left out of its shadow ray, so
/// the emitter itself does not block it.
const EMITTER_END_MARGIN: f32 = 1e-3;

/// Whether the bake sees an instance at all: static ones alone. Dynamic objects move, so
/// they take their light from the probes and their shadows from the realtime maps; the
/// BVH and the emitter table both hold what this accepts.
pub fn bakes_instance(instance: &MeshInstance) -> bool {
    instance.is_static
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{Light, LightKind};

    /// A baked 1 x 1 m panel of 100 nits 2 m up, shining down, alone.
    fn panel_tracer_parts() -> (Scene, Light) {
        let mut light = Light::new(LightKind::Rect { width: 1.0, height: 1.0 }, Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y);
        light.intensity = 100.0;
        light.mode = LightMode::Baked;
        (Scene { lights: vec![light.clone()], ..Scene::default() }, light)
    }

    #[test]
    fn a_probe_takes_an_area_light_as_the_irradiance_facing_it_gets() {
        let (scene, light) = panel_tracer_parts();
        let bvh = SceneBvh::build(&scene);
        let tracer = Tracer::new(&scene, &[LightMode::Baked], &bvh, Sky::Constant(Vec3::ZERO), 0, 1e-6);
        let mut rays = 0;
        // Close under it: bounded by pi L, where a point of L A would give L A / d^2.
        let near = Vec3::new(0.0, 1.8, 0.0);
        let deltas = tracer.probe_deltas(near, &mut rays);
        let (dir, e) = deltas[0];
        let exact = 100.0 * light.area_projected_solid_angle(near, Vec3::Y);
        assert!((e.x / exact - 1.0).abs() < 1e-3, "{} vs {exact}", e.x);
        assert!(e.x < std::f32::consts::PI * 100.0 && dir.distance(Vec3::Y) < 1e-4, "{e} from {dir}");
        // Far off its axis it is nearly a point of L A candela times the cosine at the light.
        let far = Vec3::new(6.0, -6.0, 0.0);
        let (dir, e) = tracer.probe_deltas(far, &mut rays)[0];
        let to_light = light.position() - far;
        let point = 100.0 * light.direction().dot(-to_light.normalize()) / to_light.length_squared();
        assert!((e.x / point - 1.0).abs() < 0.01, "{} vs {point}", e.x);
        assert!(dir.distance(to_light.normalize()) < 0.01);
        // Behind it, nothing.
        assert!(tracer.probe_deltas(Vec3::new(0.0, 3.0, 0.0), &mut rays).is_empty());
    }
}
