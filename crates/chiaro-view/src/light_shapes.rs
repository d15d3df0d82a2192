//! Where the 3D view draws rect and disk lights: each one's outline and a short tick from
//! its centre the way it shines (it lights one side only), as line segments in clip
//! space, cut at the near plane so that a light beside or behind the camera draws only
//! what is in front of it. Pure: the scene's lights and the view in, vertices out;
//! light_overlay.rs draws them.

use chiaro_render::View;
use chiaro_scene::Light;
use glam::{Vec3, Vec4};

/// One end of a line: clip-space position and linear RGBA colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LineVertex {
    pub clip: [f32; 4],
    pub color: [f32; 4],
}

/// The tick's length as a share of the light's bounding radius.
const TICK_SHARE: f32 = 0.5;

/// The selected light's colour: white stands out from any light's own colour.
const SELECTED_COLOR: [f32; 4] = [1.0, 1.0, 1.0, 1.0];

/// Line segments (pairs of vertices) of every area light in `lights` as `view` sees it;
/// `selected`, a light index, is drawn white, the others in their own colour at full
/// brightness.
pub fn area_light_lines(lights: &[Light], view: &View, selected: Option<usize>) -> Vec<LineVertex> {
    let view_from_world = view.view_from_world();
    let mut vertices = Vec::new();
    for (index, light) in lights.iter().enumerate() {
        let (Some(outline), Some(shape)) = (light.area_outline_ws(), light.kind.area_shape()) else { continue };
        let color = if selected == Some(index) { SELECTED_COLOR } else { full_brightness(light.color) };
        let centre = light.position();
        let facing = light.direction();
        let tick = (centre, centre + facing * (TICK_SHARE * shape.bounding_radius()));
        let edges = outline.iter().zip(outline.iter().cycle().skip(1)).map(|(a, b)| (*a, *b));
        for (a, b) in edges.chain([tick]) {
            let Some((a, b)) = clip_to_near_plane(
                view_from_world.transform_point3(a),
                view_from_world.transform_point3(b),
                view.znear,
            ) else {
                continue;
            };
            for p in [a, b] {
                vertices.push(LineVertex { clip: (view.clip_from_view * p.extend(1.0)).to_array(), color });
            }
        }
    }
    vertices
}

/// A light's colour scaled so that its brightest channel is 1 (a dim or black light
/// still draws: grey).
fn full_brightness(color: Vec3) -> [f32; 4] {
    let peak = color.max_element();
    let rgb = if peak > 0.0 && peak.is_finite() { color / peak } else { Vec3::splat(0.5) };
    Vec4::from((rgb, 1.0)).to_array()
}

/// The part of the view-space segment `a`-`b` in front of the near plane (view space
/// looks down -Z), or `None` where none of it is.
fn clip_to_near_plane(a: Vec3, b: Vec3, znear: f32) -> Option<(Vec3, Vec3)> {
    let (depth_a, depth_b) = (-a.z - znear, -b.z - znear);
    match (depth_a >= 0.0, depth_b >= 0.0) {
        (true, true) => Some((a, b)),
        (false, false) => None,
        _ => {
            let crossing = a + (b - a) * (depth_a / (depth_a - depth_b));
            Some(if depth_a >= 0.0 { (a, crossing) } else { (crossing, b) })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_math::camera::Projection;
    use chiaro_scene::LightKind;
    use glam::{Mat4, Vec2};

    /// A 100 x 100 pixel view from the origin down -Z with a 90 degree field of view.
    fn view() -> View {
        let projection = Projection::Perspective { yfov_rad: std::f32::consts::FRAC_PI_2 };
        View {
            width: 100,
            height: 100,
            world_from_view: Mat4::IDENTITY,
            clip_from_view: projection.clip_from_view(1.0, 0.1, None),
            projection,
            znear: 0.1,
            zfar: None,
        }
    }

    fn rect(at: Vec3, facing: Vec3, width: f32, height: f32) -> Light {
        Light::new(LightKind::Rect { width, height }, at, facing)
    }

    /// The vertices in pixels from the view's top-left corner.
    fn pixels(vertices: &[LineVertex]) -> Vec<Vec2> {
        vertices
            .iter()
            .map(|v| {
                let ndc = Vec2::new(v.clip[0], v.clip[1]) / v.clip[3];
                Vec2::new((ndc.x + 1.0) * 50.0, (1.0 - ndc.y) * 50.0)
            })
            .collect()
    }

    #[test]
    fn a_rect_facing_the_camera_projects_to_its_size_with_a_tick_towards_the_camera() {
        // 1 x 0.5 m at 2 m: half a unit of NDC per metre, 25 pixels per metre.
        let lines = area_light_lines(&[rect(Vec3::new(0.0, 0.0, -2.0), Vec3::Z, 1.0, 0.5)], &view(), None);
        assert_eq!(lines.len(), 2 * 5, "four edges and the tick");
        let outline = pixels(&lines[..8]);
        let (min, max) = outline.iter().fold((Vec2::MAX, Vec2::MIN), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        assert!((max - min - Vec2::new(25.0, 12.5)).abs().max_element() < 1e-3, "{min} {max}");
        assert!(((min + max) / 2.0 - Vec2::splat(50.0)).abs().max_element() < 1e-3, "centred: {min} {max}");
        // The tick runs from the centre towards the camera (it shines at us): nearer, so
        // its far end has a smaller w.
        let tick = &lines[8..];
        assert!(tick[1].clip[3] < tick[0].clip[3], "{tick:?}");
    }

    #[test]
    fn a_light_behind_the_camera_draws_nothing_and_punctual_lights_are_not_drawn() {
        let behind = rect(Vec3::new(0.0, 0.0, 3.0), Vec3::Z, 1.0, 1.0);
        let point = Light::new(LightKind::Point, Vec3::new(0.0, 0.0, -2.0), Vec3::NEG_Z);
        assert!(area_light_lines(&[behind, point], &view(), None).is_empty());
    }

    #[test]
    fn a_light_across_the_near_plane_is_cut_there() {
        // A rect 4 m wide along the view axis (its local X, facing +X), from 2 m behind
        // the camera to 2 m in front, 1 m to its left.
        let across = rect(Vec3::NEG_X, Vec3::X, 4.0, 1.0);
        let lines = area_light_lines(&[across], &view(), None);
        assert!(!lines.is_empty());
        for v in &lines {
            let w = v.clip[3];
            assert!(w >= 0.1 - 1e-5, "every vertex at or past the near plane: w {w}");
        }
        // Two edges run along the axis, each cut to 2 m - 0.1 m.
        let cut = lines.chunks(2).filter(|pair| (pair[0].clip[3] - pair[1].clip[3]).abs() > 1.8).count();
        assert_eq!(cut, 2, "{lines:?}");
    }

    #[test]
    fn a_disk_draws_its_polygon_and_the_selected_light_is_white() {
        let disk = Light {
            color: Vec3::new(2.0, 1.0, 0.0),
            ..Light::new(LightKind::Disk { diameter: 1.0 }, -2.0 * Vec3::Z, Vec3::Z)
        };
        let lines = area_light_lines(std::slice::from_ref(&disk), &view(), None);
        let segments = chiaro_math::area_light::AreaShape::Disk { diameter: 1.0 }.outline().len() + 1;
        assert_eq!(lines.len(), 2 * segments);
        assert_eq!(lines[0].color, [1.0, 0.5, 0.0, 1.0], "the light's colour at full brightness");
        let selected = area_light_lines(&[disk], &view(), Some(0));
        assert!(selected.iter().all(|v| v.color == SELECTED_COLOR));
    }
}
