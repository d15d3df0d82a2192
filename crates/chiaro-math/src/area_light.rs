//! Rect and disk lights (EXT_lights_area): their shapes, points on them for shadow rays,
//! and the light they give a surface without shadows. `projected_solid_angle` of a shape
//! is exact (Lambert's polygon formula, clipped to the surface's horizon); the renderer's
//! LTC shading (`crate::ltc`) is judged against it, and the reference tracer and the
//! baker multiply it by the visible share of the light.
//!
//! Shapes lie in the light's local X/Y plane, centred on its origin, and emit towards its
//! local -Z. Irradiance from a light of uniform luminance L is L times the projected
//! solid angle the receiver sees it under (the integral of cos over the light's solid
//! angle above the horizon).

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

/// The edges of the polygon a disk is integrated as: exact to 1e-4 of its light with the
/// area kept (`AreaShape::outline`).
pub const DISK_OUTLINE_EDGES: usize = 128;

/// The emitting surface of an area light, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AreaShape {
    /// `width` along the light's local X, `height` along its local Y.
    Rect { width: f32, height: f32 },
    /// A disk of `diameter`.
    Disk { diameter: f32 },
}

impl AreaShape {
    /// Emitting area, square metres.
    pub fn area(self) -> f32 {
        match self {
            AreaShape::Rect { width, height } => width * height,
            AreaShape::Disk { diameter } => PI * diameter * diameter * 0.25,
        }
    }

    /// Half the extent along local X and Y (a disk's radius twice).
    pub fn half_extents(self) -> Vec2 {
        match self {
            AreaShape::Rect { width, height } => Vec2::new(width, height) * 0.5,
            AreaShape::Disk { diameter } => Vec2::splat(diameter * 0.5),
        }
    }

    /// Distance from the centre to the farthest point of the shape.
    pub fn bounding_radius(self) -> f32 {
        match self {
            AreaShape::Rect { .. } => self.half_extents().length(),
            AreaShape::Disk { diameter } => diameter * 0.5,
        }
    }

    /// The shape's outline in its local X/Y plane, counter-clockwise seen from +Z: a
    /// rect's four corners, or a disk as a regular `DISK_OUTLINE_EDGES`-gon of the disk's
    /// area (its radius grown so), which integrates like the disk.
    pub fn outline(self) -> Vec<Vec2> {
        match self {
            AreaShape::Rect { .. } => {
                let h = self.half_extents();
                vec![Vec2::new(-h.x, -h.y), Vec2::new(h.x, -h.y), Vec2::new(h.x, h.y), Vec2::new(-h.x, h.y)]
            }
            AreaShape::Disk { diameter } => regular_polygon(diameter * 0.5, DISK_OUTLINE_EDGES),
        }
    }

    /// A point of the shape (local X/Y) from a point of the unit square, keeping areas:
    /// stratified squares give stratified points.
    pub fn point(self, u: Vec2) -> Vec2 {
        match self {
            AreaShape::Rect { width, height } => (u - Vec2::splat(0.5)) * Vec2::new(width, height),
            AreaShape::Disk { diameter } => concentric_disk(u) * (diameter * 0.5),
        }
    }
}

/// A regular `edges`-gon with the area of the circle of `radius`, counter-clockwise.
pub fn regular_polygon(radius: f32, edges: usize) -> Vec<Vec2> {
    let n = edges as f32;
    // Area of the polygon of circumradius R: n/2 R^2 sin(2 pi / n).
    let circumradius = radius * (TAU / (n * (TAU / n).sin())).sqrt();
    (0..edges)
        .map(|k| {
            let (s, c) = (TAU * k as f32 / n).sin_cos();
            Vec2::new(c, s) * circumradius
        })
        .collect()
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disk: keeps areas
/// and strata's shapes (less stretched than the polar map).
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let p = u * 2.0 - Vec2::ONE;
    if p.x == 0.0 && p.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if p.x.abs() > p.y.abs() {
        (p.x, FRAC_PI_2 * 0.5 * (p.y / p.x))
    } else {
        (p.y, FRAC_PI_2 - FRAC_PI_2 * 0.5 * (p.x / p.y))
    };
    Vec2::new(theta.cos(), theta.sin()) * r
}

/// Lambert's vector irradiance of a polygon seen from the origin (its vertices relative
/// to the receiver, any length), for unit luminance: half the sum over its edges of the
/// angle each subtends times its plane's unit normal. Its component along a unit normal
/// is the projected solid angle of the polygon above (or, negative, below) that plane,
/// up to the winding's sign.
pub fn vector_irradiance(points: &[Vec3]) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for (k, &a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        let (a, b) = (a.normalize(), b.normalize());
        let cross = a.cross(b);
        let sin = cross.length();
        if sin > 0.0 {
            let angle = sin.atan2(a.dot(b));
            sum += cross * (angle / sin);
        }
    }
    sum * 0.5
}

/// The part of a polygon (relative to the receiver) on the positive side of the plane
/// through the origin with unit `normal` (Sutherland-Hodgman).
pub fn clip_to_horizon(points: &[Vec3], normal: Vec3) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(points.len() + 1);
    for (k, &a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        let (da, db) = (a.dot(normal), b.dot(normal));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}

/// The exact projected solid angle (steradians weighted by cos) of a polygon seen from
/// the origin by a surface of unit `normal`: the polygon clipped to the horizon, then
/// Lambert's formula. Irradiance is the luminance times this.
pub fn projected_solid_angle(points: &[Vec3], normal: Vec3) -> f32 {
    let clipped = clip_to_horizon(points, normal);
    if clipped.len() < 3 {
        return 0.0;
    }
    vector_irradiance(&clipped).dot(normal).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect_points(centre: Vec3, width: f32, height: f32) -> Vec<Vec3> {
        AreaShape::Rect { width, height }.outline().iter().map(|p| centre + p.extend(0.0)).collect()
    }

    /// Irradiance (unit luminance) under a corner of a w x h rect parallel to the
    /// receiver at height d: the textbook form factor times pi.
    fn corner_rect(w: f32, h: f32, d: f32) -> f32 {
        let (a, b) = (w / d, h / d);
        let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
        0.5 * (a / sa * (b / sa).atan() + b / sb * (a / sb).atan())
    }

    #[test]
    fn a_parallel_rect_matches_the_corner_formula_by_superposition() {
        // Receiver at the origin facing +Z; a 2 x 1 rect 1.5 m up, offset so that the
        // receiver is under the point (0.5, 0.3) of the rect measured from its corner.
        let (w, h, d) = (2.0, 1.0, 1.5);
        let (ox, oy) = (0.5, 0.3);
        let centre = Vec3::new(w * 0.5 - ox, h * 0.5 - oy, d);
        let exact = projected_solid_angle(&rect_points(centre, w, h), Vec3::Z);
        let parts = corner_rect(ox, oy, d)
            + corner_rect(w - ox, oy, d)
            + corner_rect(ox, h - oy, d)
            + corner_rect(w - ox, h - oy, d);
        assert!((exact - parts).abs() < 1e-5, "{exact} vs {parts}");
    }

    #[test]
    fn an_on_axis_disk_matches_the_closed_form() {
        for (r, d) in [(0.5f32, 1.0f32), (1.0, 0.3), (0.05, 2.0)] {
            let points: Vec<Vec3> =
                AreaShape::Disk { diameter: 2.0 * r }.outline().iter().map(|p| p.extend(d)).collect();
            let exact = PI * r * r / (r * r + d * d);
            let got = projected_solid_angle(&points, Vec3::Z);
            assert!((got / exact - 1.0).abs() < 1e-4, "r {r} d {d}: {got} vs {exact}");
        }
    }

    #[test]
    fn a_rect_across_the_horizon_matches_quadrature() {
        // A vertical 1 x 1 rect standing on the receiver's plane, half below it.
        let points = vec![
            Vec3::new(-0.5, 1.0, -0.5),
            Vec3::new(0.5, 1.0, -0.5),
            Vec3::new(0.5, 1.0, 0.5),
            Vec3::new(-0.5, 1.0, 0.5),
        ];
        let got = projected_solid_angle(&points, Vec3::Z);
        // Midpoint quadrature over the upper half: cos * dA * cos_l / d^2.
        let n = 400;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let p = Vec3::new(-0.5 + (i as f32 + 0.5) / n as f32, 1.0, 0.5 * (j as f32 + 0.5) / n as f32);
                let d2 = p.length_squared();
                let l = p / d2.sqrt();
                sum += (l.z * l.y / d2) as f64 * (0.5 / (n * n) as f64);
            }
        }
        assert!((got as f64 - sum).abs() < 2e-4 * sum, "{got} vs {sum}");
    }

    #[test]
    fn a_light_behind_the_receiver_gives_nothing() {
        assert_eq!(projected_solid_angle(&rect_points(Vec3::new(0.0, 0.0, -1.0), 1.0, 1.0), Vec3::Z), 0.0);
    }

    #[test]
    fn points_stay_inside_and_polygons_keep_the_area() {
        let rect = AreaShape::Rect { width: 1.0, height: 0.1 };
        assert_eq!(rect.point(Vec2::ZERO), Vec2::new(-0.5, -0.05));
        assert_eq!(rect.point(Vec2::ONE), Vec2::new(0.5, 0.05));
        let disk = AreaShape::Disk { diameter: 2.0 };
        for k in 0..200 {
            let u = Vec2::new((k % 17) as f32 / 16.0, (k % 13) as f32 / 12.0);
            assert!(disk.point(u).length() <= 1.0 + 1e-5);
        }
        // A regular polygon keeps the circle's area (shoelace formula).
        let octagon = regular_polygon(1.0, 8);
        let area: f32 = (0..8).map(|k| octagon[k].perp_dot(octagon[(k + 1) % 8])).sum::<f32>() * 0.5;
        assert!((area - PI).abs() < 1e-5, "{area}");
        assert!((AreaShape::Disk { diameter: 1.0 }.bounding_radius() - 0.5).abs() < 1e-6);
        assert!((AreaShape::Rect { width: 3.0, height: 4.0 }.bounding_radius() - 2.5).abs() < 1e-6);
    }
}
