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

#[cfg(test)]
mod tests {
    use super::*;

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
