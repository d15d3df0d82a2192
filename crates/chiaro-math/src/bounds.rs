//! Axis-aligned boxes and spheres: scene bounds in, framing and culling volumes out.

use glam::{Mat4, Vec3};

/// An axis-aligned box. `Aabb::EMPTY` grows from nothing; an empty box has `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        let mut aabb = Aabb::EMPTY;
        for p in points {
            aabb.grow(p);
        }
        aabb
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }

    /// The box around this box's corners after `transform`; empty stays empty.
    pub fn transformed(&self, transform: &Mat4) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        Aabb::from_points(self.corners().map(|c| transform.transform_point3(c)))
    }

    /// The smallest sphere centred on the box that holds it.
    pub fn bounding_sphere(&self) -> Sphere {
        Sphere { center: self.center(), radius: self.size().length() * 0.5 }
    }
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

/// A sphere, used for light ranges and framing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

/// The smallest sphere around what a spot light can reach: the spherical sector with
/// apex `position`, axis `direction` (unit), radius `range` and half-angle `outer_rad`.
/// Up to 45 degrees it passes through the apex and the cap's rim; from 45 to 90 degrees
/// it is the rim's own sphere (centred on the axis at the rim's height), which holds the
/// apex and the cap; wider cones get the range sphere.
pub fn spot_bounding_sphere(position: Vec3, direction: Vec3, range: f32, outer_rad: f32) -> Sphere {
    let (sin, cos) = outer_rad.sin_cos();
    if cos <= 0.0 {
        return Sphere { center: position, radius: range };
    }
    if cos <= std::f32::consts::FRAC_1_SQRT_2 {
        return Sphere { center: position + direction * (range * cos), radius: range * sin };
    }
    // Equidistant from the apex and the rim: c^2 = (R cos - c)^2 + (R sin)^2.
    let radius = range / (2.0 * cos);
    Sphere { center: position + direction * radius, radius }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spot_spheres_hold_their_cone() {
        let apex = Vec3::new(1.0, 2.0, 3.0);
        let dir = Vec3::new(0.0, -1.0, 0.0);
        for outer_deg in [5.0f32, 20.0, 35.0, 44.0, 45.0, 46.0, 59.0, 60.0, 80.0, 89.0] {
            let outer = outer_deg.to_radians();
            let s = spot_bounding_sphere(apex, dir, 10.0, outer);
            assert!(s.radius <= 10.0 + 1e-4, "never larger than the range sphere");
            // Points of the sector: the apex, along the axis, and over the cap and sides.
            for i in 0..=20 {
                for j in 0..16 {
                    let angle = outer * i as f32 / 20.0;
                    let around = std::f32::consts::TAU * j as f32 / 16.0;
                    let off_axis = Vec3::new(around.cos(), 0.0, around.sin());
                    for r in [0.0, 2.5, 5.0, 7.5, 10.0] {
                        let p = apex + (dir * angle.cos() + off_axis * angle.sin()) * r;
                        assert!(p.distance(s.center) <= s.radius * (1.0 + 1e-4), "{outer_deg} deg: {p} outside");
                    }
                }
            }
        }
        let narrow = spot_bounding_sphere(apex, dir, 25.0, 35f32.to_radians());
        assert!(narrow.radius < 16.0, "a 35 degree cone needs far less than its range: {}", narrow.radius);
        let wide = spot_bounding_sphere(apex, dir, 10.0, 60f32.to_radians());
        assert!(wide.radius < 8.7, "a 60 degree cone needs less than its range: {}", wide.radius);
    }

    #[test]
    fn empty_box_grows_to_its_points() {
        let mut b = Aabb::EMPTY;
        assert!(b.is_empty());
        b.grow(Vec3::new(1.0, -2.0, 3.0));
        b.grow(Vec3::new(-1.0, 2.0, 0.0));
        assert!(!b.is_empty());
        assert_eq!(b.min, Vec3::new(-1.0, -2.0, 0.0));
        assert_eq!(b.max, Vec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn bounding_sphere_holds_every_corner() {
        let b = Aabb::from_points([Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 5.0, 4.0)]);
        let s = b.bounding_sphere();
        for c in b.corners() {
            assert!(c.distance(s.center) <= s.radius + 1e-5);
        }
    }
}
