//! An environment stored as six cube faces (as EXT_lights_image_based stores one) turned
//! into the equirectangular map everything else reads. The faces' linear radiance and the
//! turn from world directions to the cube's flow in; an `EnvironmentMap` flows out.
//! Also the pixel encodings the extension uses: RGBD (HDR in an 8-bit PNG) and LDR.

use super::EnvironmentMap;
use chiaro_math::cube_map::cube_map_uv;
use glam::{Quat, Vec2, Vec3, Vec4};

/// The widest map made from a cube: what the renderer keeps on the device (a 2048-texel
/// cube would make a 400 MB map only to be averaged down).
pub const MAX_EQUIRECT_WIDTH: u32 = 4096;

/// Six square faces of linear radiance in the order +X, -X, +Y, -Y, +Z, -Z, each row by
/// row from the top, laid out as `chiaro_math::cube_map` says.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeFaces {
    /// Texels along each face's side.
    pub size: u32,
    /// `size` x `size` texels per face.
    pub faces: [Vec<Vec3>; 6],
}

impl CubeFaces {
    /// The radiance at `uv` of `face`, bilinear between texel centres and clamped at the
    /// face's edges.
    pub fn bilinear(&self, face: usize, uv: Vec2) -> Vec3 {
        let last = (self.size - 1) as f32;
        let x = (uv.x * self.size as f32 - 0.5).clamp(0.0, last);
        let y = (uv.y * self.size as f32 - 0.5).clamp(0.0, last);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texels = &self.faces[face];
        let at = |x: f32, y: f32| texels[(y.min(last) as u32 * self.size + x.min(last) as u32) as usize];
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }

    /// The radiance the cube keeps for direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (face, uv) = cube_map_uv(d);
        self.bilinear(face, uv)
    }

    /// The equirectangular map of the cube read at `to_cube(d)` for each world direction
    /// `d`: four texels across per face texel (as fine as the cube at the equator), at
    /// most `MAX_EQUIRECT_WIDTH`.
    pub fn to_equirect(&self, to_cube: impl Fn(Vec3) -> Vec3) -> EnvironmentMap {
        let width = (4 * self.size).clamp(8, MAX_EQUIRECT_WIDTH);
        EnvironmentMap::from_fn(width, |d| self.radiance(to_cube(d)))
    }
}

/// Where an EXT_lights_image_based cube keeps world direction `d`, for a light with
/// `rotation`: as Babylon.js (the extension's reference loader) reads it in its default
/// left-handed scene, the direction is mirrored in x (glTF's right-handed frame into the
/// scene's) and then turned by the inverse of the rotation's components as written.
pub fn image_based_light_direction(d: Vec3, rotation: Quat) -> Vec3 {
    rotation.inverse() * Vec3::new(-d.x, d.y, d.z)
}

/// The gamma the extension's PNG and JPEG faces are encoded with (Babylon.js's).
const ENCODING_GAMMA: f32 = 2.2;

/// Linear radiance of an RGBD pixel (components 0 to 1): gamma-encoded colour divided by
/// the alpha channel, which holds 1 / the scale (so values above 1 fit in 8 bits).
pub fn rgbd_radiance(rgbd: Vec4) -> Vec3 {
    if rgbd.w <= 0.0 {
        return Vec3::ZERO;
    }
    ldr_radiance(rgbd.truncate()) / rgbd.w
}

/// Linear radiance of a gamma-encoded low-dynamic-range pixel (components 0 to 1).
pub fn ldr_radiance(rgb: Vec3) -> Vec3 {
    rgb.max(Vec3::ZERO).powf(ENCODING_GAMMA)
}

/// The RGBD pixel that stores `radiance` (the encoder of the extension's writers): the
/// largest scale up to 255 that keeps every channel at most 1. For tests and tools.
pub fn rgbd_encode(radiance: Vec3) -> Vec4 {
    let brightest = radiance.max_element().max(1e-6);
    let scale = (255.0 / brightest).clamp(1.0, 255.0).floor() / 255.0;
    (radiance * scale).max(Vec3::ZERO).powf(1.0 / ENCODING_GAMMA).min(Vec3::ONE).extend(scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgbd_round_trips_bright_and_dim_radiance() {
        for radiance in [Vec3::new(200.0, 20.0, 0.5), Vec3::new(0.3, 0.2, 0.1), Vec3::splat(1.0)] {
            // Through 8 bits per channel, as a PNG keeps it.
            let stored = (rgbd_encode(radiance) * 255.0).round() / 255.0;
            let back = rgbd_radiance(stored);
            let error = ((back - radiance).abs() / radiance.max(Vec3::splat(0.05))).max_element();
            assert!(error < 0.03, "{radiance} -> {back}");
        }
        assert_eq!(rgbd_radiance(Vec4::new(1.0, 1.0, 1.0, 0.0)), Vec3::ZERO);
        assert!(ldr_radiance(Vec3::splat(0.5)).abs_diff_eq(Vec3::splat(0.2176), 1e-4));
    }

    #[test]
    fn the_extension_reads_the_cube_mirrored_in_x_after_its_rotation() {
        // Babylon.js reads the face it calls -X for glTF's +X, and +Z for +Z.
        assert_eq!(cube_map_uv(image_based_light_direction(Vec3::X, Quat::IDENTITY)).0, 1);
        assert_eq!(cube_map_uv(image_based_light_direction(Vec3::Z, Quat::IDENTITY)).0, 4);
        assert_eq!(cube_map_uv(image_based_light_direction(Vec3::Y, Quat::IDENTITY)).0, 2);
        // A quarter turn about +Y: world +Z reads the cube towards -X.
        let quarter = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        assert_eq!(cube_map_uv(image_based_light_direction(Vec3::Z, quarter)).0, 1);
        // About +X the mirror does not commute with the turn: world +Y reads towards -Z,
        // as in Babylon.js (turning first and mirroring after would read +Z).
        let quarter = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
        assert_eq!(cube_map_uv(image_based_light_direction(Vec3::Y, quarter)).0, 5);
    }

    #[test]
    fn an_equirect_of_the_cube_keeps_each_faces_radiance() {
        let colours = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE, Vec3::splat(2.0), Vec3::splat(3.0)];
        let cube = CubeFaces { size: 4, faces: colours.map(|c| vec![c; 16]) };
        let map = cube.to_equirect(|d| d);
        assert_eq!((map.width, map.height), (16, 8));
        for (face, d) in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z].into_iter().enumerate() {
            assert_eq!(map.radiance(d), colours[face], "{d}");
        }
    }

    #[test]
    fn bilinear_reads_texel_centres_and_clamps_at_edges() {
        let mut faces: [Vec<Vec3>; 6] = Default::default();
        for face in &mut faces {
            *face = (0..4).map(|i| Vec3::splat(i as f32)).collect();
        }
        let cube = CubeFaces { size: 2, faces };
        assert_eq!(cube.bilinear(0, Vec2::new(0.25, 0.25)), Vec3::ZERO);
        assert_eq!(cube.bilinear(0, Vec2::new(0.5, 0.25)), Vec3::splat(0.5));
        assert_eq!(cube.bilinear(0, Vec2::new(1.0, 1.0)), Vec3::splat(3.0));
    }
}
