//! Which casters a shadow tile needs: those whose bounds overlap the tile's projection.

use crate::bounds::Aabb;
use glam::Mat4;

/// Whether a caster with world bounds `bounds` can draw into the tile of `clip_from_world`.
/// With `pancake` (orthographic directional cascades with depth clamping), casters between
/// the light and the near plane still count: their depth is flattened onto the near plane.
pub fn caster_in_tile(clip_from_world: &Mat4, bounds: &Aabb, pancake: bool) -> bool {
    if bounds.is_empty() {
        return false;
    }
    let corners = bounds.corners().map(|c| clip_from_world * c.extend(1.0));
    let all = |f: &dyn Fn(glam::Vec4) -> bool| corners.iter().all(|&c| f(c));
    let outside = all(&|c| c.x < -c.w)
        || all(&|c| c.x > c.w)
        || all(&|c| c.y < -c.w)
        || all(&|c| c.y > c.w)
        || all(&|c| c.z > c.w)
        || (!pancake && all(&|c| c.z < 0.0));
    !outside
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn casters_beside_the_tile_are_culled_and_those_towards_the_light_are_kept() {
        // Light looks down -Z from z = 10, covering x, y in [-5, 5], depth 0..20.
        let clip = Mat4::orthographic_rh(-5.0, 5.0, -5.0, 5.0, 0.0, 20.0)
            * Mat4::look_to_rh(Vec3::new(0.0, 0.0, 10.0), Vec3::NEG_Z, Vec3::Y);
        let cube = |c: Vec3| Aabb::from_points([c - 0.5, c + 0.5]);
        assert!(caster_in_tile(&clip, &cube(Vec3::ZERO), true));
        assert!(!caster_in_tile(&clip, &cube(Vec3::new(8.0, 0.0, 0.0)), true));
        assert!(!caster_in_tile(&clip, &cube(Vec3::new(0.0, -8.0, 0.0)), true));
        assert!(!caster_in_tile(&clip, &cube(Vec3::new(0.0, 0.0, -30.0)), true), "beyond the far plane");
        // Between the light and its near plane: kept when pancaking, culled otherwise.
        assert!(caster_in_tile(&clip, &cube(Vec3::new(0.0, 0.0, 15.0)), true));
        assert!(!caster_in_tile(&clip, &cube(Vec3::new(0.0, 0.0, 15.0)), false));
        assert!(!caster_in_tile(&clip, &Aabb::EMPTY, true));
    }
}

/// Whether a caster can reach into a point or spot light's tiles: its bounds overlap the
/// sphere of the light's range.
pub fn caster_in_range(bounds: &Aabb, light: &crate::Sphere) -> bool {
    !bounds.is_empty()
        && light.center.clamp(bounds.min, bounds.max).distance_squared(light.center) <= light.radius * light.radius
}

#[cfg(test)]
mod range_tests {
    use super::*;
    use crate::Sphere;
    use glam::Vec3;

    #[test]
    fn casters_out_of_range_are_culled() {
        let light = Sphere { center: Vec3::ZERO, radius: 5.0 };
        let cube = |c: Vec3| Aabb::from_points([c - 0.5, c + 0.5]);
        assert!(caster_in_range(&cube(Vec3::new(3.0, 0.0, 0.0)), &light));
        assert!(caster_in_range(&cube(Vec3::new(5.4, 0.0, 0.0)), &light));
        assert!(!caster_in_range(&cube(Vec3::new(5.6, 0.0, 0.0)), &light));
        assert!(!caster_in_range(&cube(Vec3::new(4.2, 4.2, 0.0)), &light));
        assert!(caster_in_range(&Aabb::from_points([Vec3::splat(-9.0), Vec3::splat(9.0)]), &light), "light inside");
    }
}
