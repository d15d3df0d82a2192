//! Emissive triangles as lights the path tracer can aim at: a table of the static
//! emissive triangles, picked in proportion to their power (area times the luminance of
//! their emissive factor) and sampled uniformly over their area. With it the tracer
//! weighs the two ways a path finds an emitter (aimed at, or hit by a bounce) by multiple
//! importance sampling, so small bright emitters no longer make fireflies.

use chiaro_math::tonemap::luminance;
use chiaro_scene::{Material, MeshInstance, Scene};
use glam::Vec3;
use std::collections::HashMap;

/// One emissive triangle in world space.
struct EmitterTriangle {
    instance: usize,
    primitive: usize,
    triangle: usize,
    corners: [Vec3; 3],
    /// Unit geometric normal (the front face's).
    normal: Vec3,
    area: f32,
    double_sided: bool,
}

/// A point picked on an emitter, with what the tracer needs to weigh it.
pub struct EmitterPoint {
    pub instance: usize,
    pub primitive: usize,
    pub triangle: usize,
    pub barycentrics: [f32; 3],
    pub position: Vec3,
    pub normal: Vec3,
    pub double_sided: bool,
    /// Probability density of this point per unit area.
    pub pdf_area: f32,
}

/// The static emissive triangles of a scene.
#[derive(Default)]
pub struct Emitters {
    triangles: Vec<EmitterTriangle>,
    /// Cumulative picking probability, ending at 1.
    cdf: Vec<f32>,
    /// (instance, primitive, triangle) to its index in `triangles`.
    index: HashMap<(usize, usize, usize), usize>,
}

impl Emitters {
    /// The emissive triangles of the instances `include` accepts (the baker's static ones:
    /// the only ones its rays can hit).
    pub fn new(scene: &Scene, include: impl Fn(&MeshInstance) -> bool) -> Emitters {
        let default_material = Material::default();
        let mut triangles = Vec::new();
        let mut power = Vec::new();
        for (i, instance) in scene.instances.iter().enumerate().filter(|(_, instance)| include(instance)) {
            let Some(mesh) = scene.meshes.get(instance.mesh) else { continue };
            for (pi, p) in mesh.primitives.iter().enumerate() {
                let material = p.material.and_then(|m| scene.materials.get(m)).unwrap_or(&default_material);
                let brightness = luminance(material.emissive);
                if !(brightness > 0.0 && brightness.is_finite()) {
                    continue;
                }
                for t in 0..p.triangle_count() {
                    let corners = [0, 1, 2].map(|k| {
                        let v = p.indices[3 * t + k] as usize;
                        instance.world_from_local.transform_point3(p.positions[v])
                    });
                    let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
                    let area = 0.5 * cross.length();
                    if !(area > 0.0 && area.is_finite()) {
                        continue;
                    }
                    triangles.push(EmitterTriangle {
                        instance: i,
                        primitive: pi,
                        triangle: t,
                        corners,
                        normal: cross.normalize(),
                        area,
                        double_sided: material.double_sided,
                    });
                    power.push(area as f64 * brightness as f64);
                }
            }
        }
        let total: f64 = power.iter().sum();
        let mut running = 0.0;
        let cdf = power
            .iter()
            .map(|p| {
                running += p;
                (running / total) as f32
            })
            .collect();
        let index = triangles.iter().enumerate().map(|(k, t)| ((t.instance, t.primitive, t.triangle), k)).collect();
        Emitters { triangles, cdf, index }
    }

    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    fn pick_probability(&self, k: usize) -> f32 {
        self.cdf[k] - if k == 0 { 0.0 } else { self.cdf[k - 1] }
    }

    /// A point on an emitter from three uniform numbers; `None` without emitters.
    pub fn sample(&self, pick: f32, u: f32, v: f32) -> Option<EmitterPoint> {
        if self.triangles.is_empty() {
            return None;
        }
        let k = self.cdf.partition_point(|&c| c <= pick).min(self.triangles.len() - 1);
        let t = &self.triangles[k];
        // Uniform over the triangle.
        let r = u.sqrt();
        let barycentrics = [1.0 - r, r * (1.0 - v), r * v];
        let position = t.corners[0] * barycentrics[0] + t.corners[1] * barycentrics[1] + t.corners[2] * barycentrics[2];
        Some(EmitterPoint {
            instance: t.instance,
            primitive: t.primitive,
            triangle: t.triangle,
            barycentrics,
            position,
            normal: t.normal,
            double_sided: t.double_sided,
            pdf_area: self.pick_probability(k) / t.area,
        })
    }

    /// The density per unit area with which `sample` picks a point of this triangle; 0 for
    /// a triangle that is not an emitter.
    pub fn pdf_area(&self, instance: usize, primitive: usize, triangle: usize) -> f32 {
        match self.index.get(&(instance, primitive, triangle)) {
            Some(&k) => self.pick_probability(k) / self.triangles[k].area,
            None => 0.0,
        }
    }
}

/// The power heuristic's weight for the strategy of density `pdf` against `other`.
pub fn power_heuristic(pdf: f32, other: f32) -> f32 {
    let (a, b) = (pdf * pdf, other * other);
    if a + b > 0.0 { a / (a + b) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{CastShadows, Material};
    use chiaro_testkit::{add_box, floor_scene};
    use glam::Vec4;

    fn scene_with_a_glowing_box() -> Scene {
        let mut scene = floor_scene(4.0, Vec3::new(0.0, 4.0, 3.0), vec![]);
        add_box(&mut scene, Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.5, 2.0), 0.0, CastShadows::On);
        // The box gets its own glowing material.
        let mesh = scene.instances[1].mesh;
        scene.meshes[mesh].primitives[0].material = Some(1);
        scene.materials.push(Material {
            name: "glow".into(),
            base_color: Vec4::ONE,
            emissive: Vec3::new(2.0, 1.0, 0.5),
            ..Material::default()
        });
        scene
    }

    #[test]
    fn picks_emitters_by_area_and_its_density_integrates_to_one() {
        let scene = scene_with_a_glowing_box();
        let emitters = Emitters::new(&scene, |_: &MeshInstance| true);
        // The floor does not glow; the box's 12 triangles do.
        assert_eq!(emitters.triangles.len(), 12);
        assert_eq!(emitters.pdf_area(0, 0, 0), 0.0);
        // Equal brightness: the density is one over the total area everywhere.
        let area = 2.0 * (1.0 * 0.5 + 1.0 * 2.0 + 0.5 * 2.0);
        for t in 0..12 {
            assert!((emitters.pdf_area(1, 0, t) * area - 1.0).abs() < 1e-4);
        }
        let mut hits = [0u32; 12];
        let n = 60_000;
        let mut rng = crate::rng::Rng::new(0, 5, 0);
        for _ in 0..n {
            let p = emitters.sample(rng.next_f32(), rng.next_f32(), rng.next_f32()).unwrap();
            assert!((p.pdf_area * area - 1.0).abs() < 1e-4);
            assert!(p.barycentrics.iter().all(|&w| (0.0..=1.0).contains(&w)));
            hits[p.triangle] += 1;
        }
        for (t, &h) in hits.iter().enumerate() {
            let expected = emitters.triangles[t].area / area * n as f32;
            assert!((h as f32 - expected).abs() < 0.1 * expected, "triangle {t}: {h} of {expected}");
        }
    }

    #[test]
    fn no_emitters_no_samples() {
        let scene = floor_scene(4.0, Vec3::new(0.0, 4.0, 3.0), vec![]);
        let emitters = Emitters::new(&scene, |_: &MeshInstance| true);
        assert!(emitters.is_empty());
        assert!(emitters.sample(0.5, 0.5, 0.5).is_none());
    }

    #[test]
    fn the_power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 3.0), (0.2, 0.0), (5.0, 5.0)] {
            assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
