//! Clicking in the 3D view selects the mesh instance under the pointer: a ray through the
//! pixel's centre against the scene's triangles (chiaro-trace's BVH, built on the first
//! click after a scene is opened).

use chiaro_math::bounds::Aabb;
use chiaro_render::View;
use chiaro_scene::Scene;
use chiaro_trace::{Hit, SceneBvh};
use glam::{Vec3, Vec4};

/// The world-space ray through the centre of pixel `(x, y)` (pixels from the top-left
/// corner): origin and unit direction. A perspective ray starts at the eye; an
/// orthographic one on the near plane, along the view axis.
pub fn pixel_ray(view: &View, x: f32, y: f32) -> (Vec3, Vec3) {
    let ndc_x = (x + 0.5) / view.width as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y + 0.5) / view.height as f32 * 2.0;
    // Reverse-Z: clip depth 1 is the near plane, which every projection here keeps finite.
    let on_near = view.clip_from_view.inverse() * Vec4::new(ndc_x, ndc_y, 1.0, 1.0);
    let on_near = on_near.truncate() / on_near.w;
    if view.is_orthographic() {
        return (view.world_from_view.transform_point3(on_near), view.forward());
    }
    (view.eye(), view.world_from_view.transform_vector3(on_near.normalize()).normalize())
}

/// World-space bounds of instance `i`.
pub fn instance_bounds(scene: &Scene, i: usize) -> Aabb {
    let instance = &scene.instances[i];
    let local = scene.meshes[instance.mesh].primitives.iter().fold(Aabb::EMPTY, |b, p| b.union(&p.bounds));
    local.transformed(&instance.world_from_local)
}

#[derive(Default)]
pub struct Picker {
    bvh: Option<SceneBvh>,
}

impl Picker {
    /// Forgets the scene (a new one was opened).
    pub fn reset(&mut self) {
        self.bvh = None;
    }

    /// The instance seen at pixel `(x, y)` of `view`, if any.
    pub fn pick(&mut self, scene: &Scene, view: &View, x: f32, y: f32) -> Option<usize> {
        self.hit(scene, view, x, y).map(|hit| hit.instance)
    }

    fn hit(&mut self, scene: &Scene, view: &View, x: f32, y: f32) -> Option<Hit> {
        let bvh = self.bvh.get_or_insert_with(|| SceneBvh::build(scene));
        let (origin, direction) = pixel_ray(view, x, y);
        bvh.closest_hit(origin, direction, f32::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_picks_the_instance_drawn_there() {
        let scene = chiaro_scene::demo::demo_scene(0);
        let perspective = View::from_camera(&scene, 0, 96, 64);
        let projection = chiaro_math::camera::Projection::Orthographic { ymag: 8.0 };
        let orthographic = View::projected(perspective.world_from_view, projection, 0.05, Some(200.0), 96, 64);
        for view in [perspective, orthographic] {
            assert_picks_what_it_draws(&scene, &view);
        }
    }

    fn assert_picks_what_it_draws(scene: &Scene, view: &View) {
        let (scene, view) = (scene.clone(), *view);
        // Project each instance's centre and pick at that pixel: the ray must hit the
        // instance itself or one in front of it (never one behind).
        let mut picker = Picker::default();
        let mut hits_itself = 0;
        for i in 0..scene.instances.len() {
            let center = instance_bounds(&scene, i).center();
            let clip = view.clip_from_world() * center.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            if clip.w <= 0.0 || ndc.x.abs() >= 1.0 || ndc.y.abs() >= 1.0 {
                continue;
            }
            let x = (ndc.x + 1.0) * 0.5 * view.width as f32 - 0.5;
            let y = (1.0 - ndc.y) * 0.5 * view.height as f32 - 0.5;
            let hit = picker.hit(&scene, &view, x, y).expect("something is under an object's centre");
            let (origin, direction) = pixel_ray(&view, x, y);
            // Another instance is picked only when it stands in front of this one's centre.
            let center_t = (center - origin).dot(direction);
            assert!(hit.instance == i || hit.t < center_t, "instance {i}: picked {} at {}", hit.instance, hit.t);
            hits_itself += usize::from(hit.instance == i);
        }
        assert!(hits_itself >= 3, "most visible objects pick themselves: {hits_itself}");
        // A ray through the top-left corner of the demo's view looks at the sky.
        assert_eq!(picker.pick(&scene, &view, 0.0, 0.0), None, "{:?}", view.projection);
    }

    #[test]
    fn the_centre_pixel_ray_is_the_view_direction() {
        let scene = chiaro_scene::demo::demo_scene(0);
        let view = View::from_camera(&scene, 0, 65, 33);
        let (origin, direction) = pixel_ray(&view, 32.0, 16.0);
        let forward = -view.world_from_view.z_axis.truncate().normalize();
        assert!(origin.distance(view.eye()) < 1e-5);
        assert!(direction.dot(forward) > 0.99999, "{direction} against {forward}");
    }
}
