//! Rigid frames: where a light or camera is and how it is turned, without scale. A node's
//! transform flows in; a matrix with unit, perpendicular axes flows out, whose -Z is the
//! way the object looks or shines (glTF's convention for cameras and lights).

use glam::{Mat4, Vec3};

/// The rigid part of `m`: -Z keeps its direction exactly, +Y is made perpendicular to it,
/// +X completes a right-handed frame, the translation is kept. `None` when -Z or +Y
/// collapses (a zero scale) or is not finite.
pub fn rigid_part(m: Mat4) -> Option<Mat4> {
    let z = m.z_axis.truncate().try_normalize()?;
    let y_in = m.y_axis.truncate();
    let y = (y_in - z * z.dot(y_in)).try_normalize()?;
    let x = y.cross(z);
    Some(Mat4::from_cols(x.extend(0.0), y.extend(0.0), z.extend(0.0), m.w_axis))
}

/// A frame at `position` whose -Z points along `forward` (any length; -Z of the world when
/// it is zero), rolled so that +Y leans towards world +Y, or towards world -Z when
/// `forward` is nearly vertical. Lights made in code get this roll.
pub fn looking_along(position: Vec3, forward: Vec3) -> Mat4 {
    let z = -forward.normalize_or(Vec3::NEG_Z);
    let up = if z.y.abs() > 0.99 { Vec3::NEG_Z } else { Vec3::Y };
    let x = up.cross(z).normalize();
    let y = z.cross(x);
    Mat4::from_cols(x.extend(0.0), y.extend(0.0), z.extend(0.0), position.extend(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn assert_orthonormal(m: Mat4) {
        let (x, y, z) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
        for (a, b) in [(x, y), (y, z), (z, x)] {
            assert!(a.dot(b).abs() < 1e-5, "{m}");
        }
        for a in [x, y, z] {
            assert!((a.length() - 1.0).abs() < 1e-5, "{m}");
        }
        assert!((x.cross(y) - z).length() < 1e-5, "right-handed: {m}");
    }

    #[test]
    fn rigid_part_drops_scale_and_keeps_direction_roll_and_position() {
        let rotation = Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.4, 0.3);
        let position = Vec3::new(1.0, 2.0, -3.0);
        let scaled = Mat4::from_scale_rotation_translation(Vec3::new(2.0, 0.5, 3.0), rotation, position);
        let rigid = rigid_part(scaled).unwrap();
        assert_orthonormal(rigid);
        let expected = Mat4::from_rotation_translation(rotation, position);
        assert!(rigid.abs_diff_eq(expected, 1e-5), "{rigid} vs {expected}");
    }

    #[test]
    fn rigid_part_refuses_collapsed_axes() {
        assert!(rigid_part(Mat4::from_scale(Vec3::new(1.0, 1.0, 0.0))).is_none());
        assert!(rigid_part(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
    }

    #[test]
    fn looking_along_points_minus_z_forward_with_y_up() {
        for forward in [Vec3::new(0.3, -1.0, 0.2), Vec3::X, Vec3::NEG_Y, Vec3::Y * 5.0, Vec3::ZERO] {
            let m = looking_along(Vec3::ONE, forward);
            assert_orthonormal(m);
            let expected = forward.normalize_or(Vec3::NEG_Z);
            assert!((-m.z_axis.truncate() - expected).length() < 1e-6, "{forward}");
            assert_eq!(m.w_axis.truncate(), Vec3::ONE);
        }
        let m = looking_along(Vec3::ZERO, Vec3::X);
        assert!(m.y_axis.truncate().abs_diff_eq(Vec3::Y, 1e-6), "level lights keep +Y up");
    }
}
