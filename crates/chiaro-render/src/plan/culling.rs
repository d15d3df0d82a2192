//! The frame's culled light lists for the forward pass: per cluster of the view's froxel
//! grid, or per object, the point and spot lights (indices into `FramePlan::lights`) that
//! can reach it. The grid and the lists' format are `clusters`; this gathers its input.

use super::clusters::{ClusterGrid, CullLight, CulledLightLists, lights_per_object};
use super::draws::Draw;
use super::lights::FrameLight;
use crate::view::View;
use chiaro_math::bounds::spot_bounding_sphere;
use chiaro_math::{Aabb, Sphere};
use chiaro_scene::{LightCulling, LightKind, Scene};

/// The forward pass's culled light lists: the cluster grid (if clustered) and the lists.
#[derive(Clone, Debug, Default)]
pub struct CulledLights {
    /// The froxel grid, under clustered culling.
    pub grid: Option<ClusterGrid>,
    /// One list per cluster (clustered) or per object (per-object); empty without culling.
    pub lists: CulledLightLists,
}

/// Builds the lists `culling` asks for, for the forward pass's draws (`order`, indices
/// into `draws`). `lights[first_local..]` are the point and spot lights; `shadowed[k]`
/// says whether light `k` needs a shadow lookup.
#[allow(clippy::too_many_arguments)]
pub fn cull_lights(
    culling: LightCulling,
    scene: &Scene,
    draws: &[Draw],
    order: &[u32],
    view: &View,
    lights: &[FrameLight],
    first_local: usize,
    shadowed: &[bool],
) -> CulledLights {
    // Culling sees the point and spot lights alone; list indices are moved back into
    // `lights` (by `first_local`).
    let others = &lights[first_local..];
    // Spots are bounded by the sphere around their cone, in world space.
    let cull_light = |(k, l): (usize, &FrameLight)| {
        let light = &scene.lights[l.id.index()];
        let sphere = match light.kind {
            LightKind::Spot { outer_cone_rad, .. } => {
                spot_bounding_sphere(light.position(), light.direction(), l.range, outer_cone_rad)
            }
            _ => Sphere { center: light.position(), radius: l.range },
        };
        CullLight { sphere, shadowed: shadowed[first_local + k], peak_intensity: light.peak_intensity_cd() }
    };
    match culling {
        LightCulling::None => CulledLights::default(),
        LightCulling::Clustered => {
            let view_from_world = view.view_from_world();
            let cull: Vec<CullLight> = others
                .iter()
                .enumerate()
                .map(|kl| {
                    let mut c = cull_light(kl);
                    c.sphere.center = view_from_world.transform_point3(c.sphere.center);
                    c
                })
                .collect();
            // The slices span the depths of the pass's surfaces, as far as a light reaches.
            let light_far = cull.iter().map(|c| -c.sphere.center.z + c.sphere.radius).fold(view.znear, f32::max);
            let (near, far) = surface_depths(draws, order, &view_from_world, view.znear);
            let grid = ClusterGrid::new(view.width, view.height, near, far.min(light_far));
            // List indices are moved back into `lights` as they are written.
            let lists = grid.assign_numbered(&view.clip_from_view, &cull, first_local as u32);
            CulledLights { grid: Some(grid), lists }
        }
        LightCulling::PerObject => {
            // Records are indexed by object; objects the pass does not draw get none.
            let objects = draws.iter().map(|d| d.object as usize + 1).max().unwrap_or(0);
            let mut bounds = vec![Aabb::default(); objects];
            for &i in order {
                let d = &draws[i as usize];
                bounds[d.object as usize] = bounds[d.object as usize].union(&d.bounds_ws);
            }
            let cull: Vec<CullLight> = others.iter().enumerate().map(cull_light).collect();
            let mut lists = lights_per_object(&bounds, &cull);
            for i in &mut lists.indices {
                *i += first_local as u32;
            }
            CulledLights { grid: None, lists }
        }
    }
}

/// The view depths (nearest and farthest, no nearer than `znear`) of the bounds of the
/// draws `order` names: no pixel of the pass lies outside them.
fn surface_depths(draws: &[Draw], order: &[u32], view_from_world: &glam::Mat4, znear: f32) -> (f32, f32) {
    let (mut near, mut far) = (f32::INFINITY, znear);
    for bounds in order.iter().map(|&i| &draws[i as usize].bounds_ws).filter(|b| !b.is_empty()) {
        for corner in bounds.corners() {
            let depth = -view_from_world.transform_point3(corner).z;
            near = near.min(depth);
            far = far.max(depth);
        }
    }
    (near.max(znear).min(far), far)
}
