//! The cluster grid and per-object lists against brute force.

use super::*;
use crate::shader_constants::{CLUSTER_SLICES, SHADOWED_ENTRY};
use chiaro_math::camera::perspective_reverse_z;
use glam::Vec3;

fn light(center: Vec3, radius: f32, shadowed: bool) -> CullLight {
    CullLight { sphere: Sphere { center, radius }, shadowed, peak_intensity: 1.0 }
}

/// View-space bounds of every cluster, in `index` order: the boxes culling tested
/// against before it projected each slice of a sphere. `view_from_clip` inverts a
/// projection with clip-space depth 1 at the near plane (reverse-Z) or 0 (standard);
/// either works, as only rays through pixel corners are taken from it.
fn cluster_bounds(grid: &ClusterGrid, view_from_clip: &Mat4) -> Vec<Aabb> {
    // The ray through each tile corner, as (origin, direction) in view space.
    let corner_ray = |tx: u32, ty: u32| {
        let px = (tx * grid.tile_width).min(grid.width) as f32;
        let py = (ty * grid.tile_height).min(grid.height) as f32;
        let ndc_x = px / grid.width as f32 * 2.0 - 1.0;
        let ndc_y = 1.0 - py / grid.height as f32 * 2.0;
        let a = view_from_clip.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
        let b = view_from_clip.project_point3(Vec3::new(ndc_x, ndc_y, 0.5));
        (a, b - a)
    };
    let at_depth = |(origin, dir): (Vec3, Vec3), depth: f32| {
        // Where the ray meets the plane z = -depth (the camera looks along -Z).
        if dir.z.abs() < 1e-12 { origin } else { origin + dir * ((-depth - origin.z) / dir.z) }
    };
    let mut rays = Vec::with_capacity(((grid.tiles_x + 1) * (grid.tiles_y + 1)) as usize);
    for ty in 0..=grid.tiles_y {
        for tx in 0..=grid.tiles_x {
            rays.push(corner_ray(tx, ty));
        }
    }
    let ray = |tx: u32, ty: u32| rays[(ty * (grid.tiles_x + 1) + tx) as usize];
    let mut bounds = Vec::with_capacity(grid.cluster_count());
    for s in 0..CLUSTER_SLICES {
        let (z0, z1) = (grid.slice_start(s), grid.slice_start(s + 1));
        for ty in 0..grid.tiles_y {
            for tx in 0..grid.tiles_x {
                let corners = [ray(tx, ty), ray(tx + 1, ty), ray(tx, ty + 1), ray(tx + 1, ty + 1)];
                bounds.push(Aabb::from_points(corners.iter().flat_map(|&r| [at_depth(r, z0), at_depth(r, z1)])));
            }
        }
    }
    bounds
}

fn projection() -> Mat4 {
    perspective_reverse_z(1.0, 16.0 / 9.0, 0.1, None)
}

/// A view-space point seen at pixel (x, y), depth `depth`.
fn point_at(grid: &ClusterGrid, proj: &Mat4, x: f32, y: f32, depth: f32) -> Vec3 {
    let ndc = Vec3::new(x / grid.width as f32 * 2.0 - 1.0, 1.0 - y / grid.height as f32 * 2.0, 0.5);
    let p = proj.inverse().project_point3(ndc);
    p * (depth / -p.z)
}

#[test]
fn slices_cover_near_to_far_exponentially() {
    let grid = ClusterGrid::new(1280, 720, 0.1, 100.0);
    assert_eq!(grid.slice_of(0.05), 0);
    assert_eq!(grid.slice_of(0.1001), 0);
    assert_eq!(grid.slice_of(99.9), CLUSTER_SLICES - 1);
    assert_eq!(grid.slice_of(1e6), CLUSTER_SLICES - 1);
    for s in 0..CLUSTER_SLICES {
        let mid = (grid.slice_start(s) * grid.slice_start(s + 1)).sqrt();
        assert_eq!(grid.slice_of(mid), s);
    }
    assert!((grid.slice_start(CLUSTER_SLICES) - 100.0).abs() < 1e-3);
}

#[test]
fn every_pixel_a_light_reaches_lists_it() {
    // Brute force: sample pixels and depths; wherever a point lies inside a light's
    // sphere, that pixel's cluster must list the light.
    let proj = projection();
    let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
    let lights = vec![
        light(Vec3::new(0.0, 0.0, -5.0), 1.0, false),
        light(Vec3::new(3.0, -1.0, -12.0), 4.0, true),
        light(Vec3::new(-0.2, 0.1, -0.3), 0.5, false),
        light(Vec3::new(-20.0, 5.0, -30.0), 6.0, true),
        light(Vec3::new(0.0, 0.0, 2.0), 3.0, false),
    ];
    let lists = grid.assign(&proj, &lights);
    let mut checked = 0;
    for y in (0..180).step_by(7) {
        for x in (0..320).step_by(7) {
            for k in 0..60 {
                let depth = 0.1 * 1.12f32.powi(k);
                let p = point_at(&grid, &proj, x as f32 + 0.5, y as f32 + 0.5, depth);
                let listed = lists.list(grid.cluster_at(x as f32 + 0.5, y as f32 + 0.5, depth));
                for (i, l) in lights.iter().enumerate() {
                    if p.distance(l.sphere.center) < l.sphere.radius {
                        assert!(listed.contains(&(i as u32)), "light {i} missing at ({x}, {y}, {depth})");
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 1000, "the lights must cover many samples ({checked})");
}

#[test]
fn an_orthographic_view_lists_every_light_where_it_reaches_and_only_near_there() {
    let proj = chiaro_math::camera::orthographic_reverse_z(8.0, 4.5, 0.1, 40.0);
    let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
    let lights = vec![
        light(Vec3::new(0.0, 0.0, -5.0), 1.0, false),
        light(Vec3::new(3.0, -1.0, -12.0), 2.0, true),
        light(Vec3::new(-6.0, 3.0, -30.0), 1.5, false),
    ];
    let lists = grid.assign(&proj, &lights);
    let (mut inside, mut outside_listed, mut outside) = (0, 0, 0);
    for y in (0..180).step_by(5) {
        for x in (0..320).step_by(5) {
            for k in 0..60 {
                let depth = 0.1 * 1.12f32.powi(k);
                let ndc = Vec3::new((x as f32 + 0.5) / 160.0 - 1.0, 1.0 - (y as f32 + 0.5) / 90.0, 0.5);
                // Parallel rays: a pixel's x and y are the same at every depth.
                let p = proj.inverse().project_point3(ndc).truncate().extend(-depth);
                let listed = lists.list(grid.cluster_at(x as f32 + 0.5, y as f32 + 0.5, depth));
                for (i, l) in lights.iter().enumerate() {
                    let distance = p.distance(l.sphere.center);
                    if distance < l.sphere.radius {
                        assert!(listed.contains(&(i as u32)), "light {i} missing at ({x}, {y}, {depth})");
                        inside += 1;
                    } else if distance > 3.0 * l.sphere.radius + 2.0 {
                        outside += 1;
                        outside_listed += listed.contains(&(i as u32)) as usize;
                    }
                }
            }
        }
    }
    assert!(inside > 500, "the lights must cover many samples ({inside})");
    // Far from a light its clusters do not list it: the projection is culled by, not
    // every tile.
    assert_eq!(outside_listed, 0, "of {outside} samples far from the lights");
}

#[test]
fn lights_small_for_their_depth_are_listed_wherever_they_reach() {
    let proj = projection();
    let fine = ClusterGrid::new(320, 180, 0.5, 60.0);
    // Lights a hundredth of their depth wide: far thinner than a slice.
    let small: Vec<CullLight> = (0..400)
        .map(|k| {
            let depth = 2.0 + (k % 40) as f32 * 1.4;
            let x = ((k * 37) % 41) as f32 / 41.0 - 0.5;
            light(Vec3::new(x * depth, -0.3 * depth * 0.56, -depth), 0.01 * depth, k % 9 == 0)
        })
        .collect();
    // Brute force: every sampled point inside a light lies in a cluster that lists it;
    // shadowed lights lead each list.
    let lists = fine.assign(&proj, &small);
    assert_eq!(lists.len(), fine.cluster_count());
    let mut checked = 0;
    for y in (0..180).step_by(3) {
        for x in (0..320).step_by(3) {
            for k in 0..200 {
                let depth = 2.0 * 1.02f32.powi(k);
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let p = point_at(&fine, &proj, px, py, depth);
                let cluster = fine.cluster_at(px, py, depth);
                for (i, l) in small.iter().enumerate() {
                    if p.distance(l.sphere.center) < l.sphere.radius {
                        assert!(lists.list(cluster).contains(&(i as u32)), "light {i} missing at ({x}, {y}, {depth})");
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 200, "the lights must cover many samples ({checked})");
    for k in 0..lists.len() {
        let list = lists.list(k);
        let (lead, rest) = list.split_at(lists.shadowed(k));
        assert!(lead.iter().all(|&i| small[i as usize].shadowed));
        assert!(rest.iter().all(|&i| !small[i as usize].shadowed));
    }
}

#[test]
fn numbered_lists_are_the_lists_moved_along() {
    let proj = projection();
    let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
    let lights: Vec<CullLight> =
        (0..50).map(|k| light(Vec3::new(k as f32 * 0.3 - 7.0, -1.0, -3.0 - k as f32 * 0.5), 1.5, k % 4 == 0)).collect();
    let plain = grid.assign(&proj, &lights);
    let numbered = grid.assign_numbered(&proj, &lights, 3);
    assert_eq!(numbered.starts, plain.starts);
    assert!(plain.indices.iter().any(|&e| e & SHADOWED_ENTRY != 0), "some entries are marked");
    // The marks stay; the indices move by 3.
    assert!(numbered.indices.iter().zip(&plain.indices).all(|(&n, &p)| n == p + 3));
    for k in 0..plain.len() {
        assert_eq!(numbered.shadowed(k), plain.shadowed(k));
    }
}

#[test]
fn clusters_far_from_a_light_do_not_list_it() {
    let proj = projection();
    let grid = ClusterGrid::new(320, 180, 0.1, 40.0);
    let lists = grid.assign(&proj, &[light(Vec3::new(0.0, 0.0, -5.0), 0.5, false)]);
    let listed = (0..lists.len()).filter(|&k| lists.count(k) > 0).count();
    assert!(listed > 0 && listed < 40, "a small light touches a few clusters, not {listed}");
    // A light behind the camera touches none.
    let behind = grid.assign(&proj, &[light(Vec3::new(0.0, 0.0, 5.0), 1.0, false)]);
    assert!(behind.indices.is_empty());
}

#[test]
fn lists_are_no_longer_than_the_cluster_boxes_give() {
    // Many small lights over a floor below the camera: each slice's projected
    // cross-section lists at most the lights whose sphere touches the cluster's
    // view-space box (the old test), and far fewer than the lights in the frame.
    let proj = projection();
    let grid = ClusterGrid::new(640, 360, 2.0, 120.0);
    let view_from_world = Mat4::look_at_rh(Vec3::new(0.0, 10.0, 0.0), Vec3::new(0.0, 0.0, -40.0), Vec3::Y);
    let mut lights = Vec::new();
    for i in 0..64 {
        for j in 0..64 {
            let p = Vec3::new(-60.0 + i as f32 * 1.875, 0.5, -j as f32 * 1.875);
            lights.push(light(view_from_world.transform_point3(p), 1.8, (i + j) % 7 == 0));
        }
    }
    let lists = grid.assign(&proj, &lights);
    let bounds = cluster_bounds(&grid, &proj.inverse());
    let boxed: usize = bounds
        .iter()
        .map(|b| {
            lights
                .iter()
                .filter(|l| l.sphere.center.clamp(b.min, b.max).distance(l.sphere.center) <= l.sphere.radius)
                .count()
        })
        .sum();
    let longest = (0..lists.len()).map(|k| lists.count(k)).max().unwrap();
    println!("{} light-cluster pairs, {boxed} by the boxes; longest list {longest}", lists.indices.len());
    assert!(lists.indices.len() <= boxed, "{} > {boxed}", lists.indices.len());
    assert!(longest < 64, "a cluster lists {longest} of {} lights", lights.len());
    // Every list is in order: the shadowed lights, marked, first.
    for k in 0..lists.len() {
        let list = lists.list(k);
        assert!(list[..lists.shadowed(k)].iter().all(|&i| lights[i as usize].shadowed));
        assert!(list[lists.shadowed(k)..].iter().all(|&i| !lights[i as usize].shadowed));
    }
}

#[test]
fn shadowed_lights_lead_each_list() {
    let proj = projection();
    let grid = ClusterGrid::new(64, 64, 0.1, 20.0);
    let lights = [
        light(Vec3::new(0.0, 0.0, -5.0), 3.0, false),
        light(Vec3::new(0.0, 0.0, -5.0), 3.0, true),
        light(Vec3::new(0.0, 0.0, -5.0), 3.0, false),
    ];
    let lists = grid.assign(&proj, &lights);
    let k = grid.cluster_at(32.0, 32.0, 5.0);
    assert_eq!(lists.list(k), &[1, 0, 2]);
    assert_eq!(lists.shadowed(k), 1);
}

#[test]
fn objects_get_their_brightest_lights_first() {
    let object = Aabb { min: Vec3::splat(-1.0), max: Vec3::splat(1.0) };
    let far_object = Aabb { min: Vec3::splat(50.0), max: Vec3::splat(51.0) };
    let mut lights: Vec<CullLight> =
        (0..12).map(|i| light(Vec3::new(2.0 + i as f32, 0.0, 0.0), 20.0, i == 5)).collect();
    lights[7].peak_intensity = 1000.0;
    let lists = lights_per_object(&[object, far_object], &lights);
    // Light 7 is brightest at the object; 5 is shadowed, so it leads; then by distance.
    assert_eq!(lists.list(0), &[5, 7, 0, 1, 2, 3, 4, 6]);
    assert_eq!(lists.shadowed(0), 1);
    assert!(lists.list(1).is_empty(), "no light reaches the far object");
}
