//! Where a cube map keeps each direction, in the layout OpenGL, Direct3D and Vulkan share
//! (faces +X, -X, +Y, -Y, +Z, -Z; each face's image seen from outside the cube in a
//! left-handed frame), and the inverse: the direction at a face's texture coordinate.

use glam::{Vec2, Vec3};

/// The face (0 to 5: +X, -X, +Y, -Y, +Z, -Z) and the texture coordinate on it (u to the
/// right, v down, both 0 to 1) where the cube keeps direction `d` (need not be unit).
pub fn cube_map_uv(d: Vec3) -> (usize, Vec2) {
    let a = d.abs();
    // (face, major axis magnitude, sc, tc) as the shared cube-map tables give them.
    let (face, major, sc, tc) = if a.x >= a.y && a.x >= a.z {
        if d.x >= 0.0 { (0, a.x, -d.z, -d.y) } else { (1, a.x, d.z, -d.y) }
    } else if a.y >= a.z {
        if d.y >= 0.0 { (2, a.y, d.x, d.z) } else { (3, a.y, d.x, -d.z) }
    } else if d.z >= 0.0 {
        (4, a.z, d.x, -d.y)
    } else {
        (5, a.z, -d.x, -d.y)
    };
    let major = major.max(f32::MIN_POSITIVE);
    (face, Vec2::new(0.5 * (sc / major + 1.0), 0.5 * (tc / major + 1.0)))
}

/// The unit direction at texture coordinate `uv` of `face`; inverse of `cube_map_uv`.
pub fn cube_map_direction(face: usize, uv: Vec2) -> Vec3 {
    let (sc, tc) = (2.0 * uv.x - 1.0, 2.0 * uv.y - 1.0);
    let d = match face {
        0 => Vec3::new(1.0, -tc, -sc),
        1 => Vec3::new(-1.0, -tc, sc),
        2 => Vec3::new(sc, 1.0, tc),
        3 => Vec3::new(sc, -1.0, -tc),
        4 => Vec3::new(sc, -tc, 1.0),
        _ => Vec3::new(-sc, -tc, -1.0),
    };
    d.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_follow_the_shared_layout() {
        // The +X face: u runs towards -Z, v towards -Y (its top row looks up).
        let (face, uv) = cube_map_uv(Vec3::new(1.0, 0.5, -0.25));
        assert_eq!(face, 0);
        assert!(uv.abs_diff_eq(Vec2::new(0.625, 0.25), 1e-6), "{uv}");
        // The +Y face: u towards +X, v towards +Z (its top row borders the -Z face).
        let (face, uv) = cube_map_uv(Vec3::new(0.5, 1.0, -1.0 + 1e-3));
        assert_eq!(face, 2);
        assert!(uv.abs_diff_eq(Vec2::new(0.75, 0.0), 1e-3), "{uv}");
        // The -Z face: u towards -X.
        let (face, uv) = cube_map_uv(Vec3::new(-0.5, 0.0, -1.0));
        assert_eq!(face, 5);
        assert!(uv.abs_diff_eq(Vec2::new(0.75, 0.5), 1e-6), "{uv}");
        assert_eq!(cube_map_uv(Vec3::NEG_Y).0, 3);
        assert_eq!(cube_map_uv(Vec3::Z).0, 4);
        assert_eq!(cube_map_uv(Vec3::NEG_X).0, 1);
    }

    #[test]
    fn directions_round_trip_on_every_face() {
        for face in 0..6 {
            for uv in [Vec2::new(0.5, 0.5), Vec2::new(0.1, 0.8), Vec2::new(0.93, 0.07)] {
                let (back, back_uv) = cube_map_uv(cube_map_direction(face, uv));
                assert_eq!(back, face, "{uv}");
                assert!(back_uv.abs_diff_eq(uv, 1e-5), "face {face}: {uv} -> {back_uv}");
            }
        }
    }
}
