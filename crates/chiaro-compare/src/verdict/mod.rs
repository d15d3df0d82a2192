//! Per-pixel verdicts of a rendered shadow against the traced reference, one light at a
//! time.
//!
//! A rendered per-pixel shadow term (1 lit, 0 shadowed), the rendered world positions and
//! a `chiaro_trace::ShadowReference` flow in; out comes one `PixelVerdict` per pixel
//! (`classify_pixels`), which `counts` turns into false shadows (acne: shadow where the
//! reference is lit) and missed shadows (peter-panning and leaks: light where the
//! reference is shadowed), and into an RGBA difference image. A light with
//! contact-hardening shadows is also judged by how far its soft visibility is from the
//! traced share of its disc (`soft`).
//!
//! Only pixels where the question is fair are compared: the reference and the renderer
//! see the same surface, the surface receives shadows and the light reaches it, and no
//! reference shadow edge is near (`edge_band`), since a shadow map's texels and filter
//! move edges by a pixel or two without being wrong.

mod counts;
mod edge_band;
mod soft;
#[cfg(test)]
mod tests;

pub use counts::{LightComparison, compare_light, difference_image};
pub use soft::{
    FAR_OFF, VisibilityError, signed_difference_color, signed_difference_image, soft_shadow_report, visibility_error,
};

use chiaro_math::light::{spot_angle_params, spot_attenuation};
use chiaro_scene::{Light, LightKind};
use chiaro_trace::ShadowReference;
use edge_band::shadow_edge_band;
use glam::Vec3;
use rayon::prelude::*;

/// Farthest the rendered position may be from the reference's for the pixel to count as
/// the same surface. Too small and depth-buffer reconstruction error drops fair pixels;
/// too large and silhouettes, where the two see different objects, are judged.
pub const POSITION_TOLERANCE_M: f32 = 0.01;

/// Whether a rendered and a reference position are the same surface: within
/// `POSITION_TOLERANCE_M`. Every comparison with a reference matches pixels by it.
pub(crate) fn same_surface(rendered_position: Vec3, reference_position: Vec3) -> bool {
    rendered_position.distance(reference_position) <= POSITION_TOLERANCE_M
}

/// Pixels within this Chebyshev distance of a change in reference visibility are not
/// compared, by default (`compare --edge-band` changes it). Too narrow and filtered or
/// texel-snapped edges count as errors; too wide and thin shadows (and the acne or leaks
/// inside them) are never judged.
pub const EDGE_BAND_PX: usize = 3;

/// The largest edge band `compare --edge-band` takes, pixels.
pub const MAX_EDGE_BAND_PX: usize = 64;

/// Rendered and reference visibility disagree when they differ by more than this.
pub const DISAGREEMENT_THRESHOLD: f32 = 0.5;

/// What one pixel says about one light's shadow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelVerdict {
    NotCompared,
    AgreeLit,
    AgreeShadowed,
    /// Rendered darker than the reference: acne, or shadow where there should be light.
    FalseShadow,
    /// Rendered brighter than the reference: peter-panning, or light leaking.
    MissedShadow,
}

impl PixelVerdict {
    /// The difference image's colour: black not compared, grey (128) agreeing and lit,
    /// dark grey (48) agreeing and shadowed, red false shadow, blue missed shadow.
    pub fn color(self) -> [u8; 4] {
        match self {
            PixelVerdict::NotCompared => [0, 0, 0, 255],
            PixelVerdict::AgreeLit => [128, 128, 128, 255],
            PixelVerdict::AgreeShadowed => [48, 48, 48, 255],
            PixelVerdict::FalseShadow => [255, 0, 0, 255],
            PixelVerdict::MissedShadow => [0, 0, 255, 255],
        }
    }
}

/// One light's rendered shadow and the reference to judge it by: what every verdict reads.
/// `rendered_shadow` is the light's visibility per pixel (1 lit, 0 shadowed) and
/// `rendered_position` the world position the renderer shaded, both row-major like the
/// reference; `light` is `scene.lights[light_index]`, with the range the renderer used
/// (infinity for none).
#[derive(Clone, Copy)]
pub struct JudgedLight<'a> {
    /// The rendered visibility per pixel.
    pub rendered_shadow: &'a [f32],
    /// The rendered surface's world position per pixel (`None` on the sky).
    pub rendered_position: &'a [Option<Vec3>],
    /// The ray-traced reference of the frame.
    pub reference: &'a ShadowReference,
    /// The light's index in the scene and in the reference.
    pub light_index: usize,
    /// The light.
    pub light: &'a Light,
    /// Its shaded range, metres.
    pub range: f32,
    /// Pixels within this Chebyshev distance of a reference shadow edge are not counted
    /// by `classify_pixels` (`EDGE_BAND_PX` by default; 0 counts every pixel).
    pub edge_band_px: usize,
}

/// Each pixel's verdict, row-major, one per reference pixel. Pixels missing from the
/// rendered arrays, or with a non-finite rendered shadow, are not compared; a reference
/// whose arrays do not match its size compares nothing.
pub fn classify_pixels(judged: &JudgedLight) -> Vec<PixelVerdict> {
    let pairs = compared_pairs(judged, true);
    pairs
        .into_par_iter()
        .map(|pair| {
            let Some((rendered, expected)) = pair else {
                return PixelVerdict::NotCompared;
            };
            verdict_of(rendered, expected)
        })
        .collect()
}

fn verdict_of(rendered: f32, expected: f32) -> PixelVerdict {
    if (rendered - expected).abs() <= DISAGREEMENT_THRESHOLD {
        if expected >= 0.5 { PixelVerdict::AgreeLit } else { PixelVerdict::AgreeShadowed }
    } else if rendered < expected {
        PixelVerdict::FalseShadow
    } else {
        PixelVerdict::MissedShadow
    }
}

/// Per pixel, `(rendered, reference)` visibility where the comparison is fair, `None`
/// elsewhere: the same surface, receiving shadows, reached by the light, and (with
/// `edge_band`) away from the reference's shadow edges. Nothing is compared where the
/// reference's arrays do not match its size.
fn compared_pairs(judged: &JudgedLight, edge_band: bool) -> Vec<Option<(f32, f32)>> {
    let JudgedLight { rendered_shadow, rendered_position, reference, light_index, light, range, edge_band_px } =
        *judged;
    let (width, height) = (reference.width as usize, reference.height as usize);
    let pixels = width * height;
    let Some(visibility) = reference.visibility.get(light_index) else {
        return vec![None; pixels];
    };
    let consistent = [visibility.len(), reference.position.len(), reference.normal.len(), reference.receives.len()]
        .iter()
        .all(|&len| len == pixels);
    if !consistent {
        return vec![None; pixels];
    }
    let near_edge = match edge_band && edge_band_px > 0 {
        true => shadow_edge_band(visibility, width, height, edge_band_px),
        false => vec![false; pixels],
    };
    (0..pixels)
        .into_par_iter()
        .map(|i| {
            let (Some(position), Some(&rendered), Some(Some(rendered_position))) =
                (reference.position[i], rendered_shadow.get(i), rendered_position.get(i))
            else {
                return None;
            };
            let compared = reference.receives[i]
                && !near_edge[i]
                && rendered.is_finite()
                && same_surface(*rendered_position, position)
                && light_reaches(light, range, position, reference.normal[i]);
            compared.then_some((rendered, visibility[i]))
        })
        .collect()
}

/// Whether `light` can light a surface at `position` facing `normal`: the surface faces
/// it, and for point and spot lights lies within `range` (and the cone); for rect and
/// disk lights, within range of the centre and seeing some of the light in front of it.
fn light_reaches(light: &Light, range: f32, position: Vec3, normal: Vec3) -> bool {
    if light.is_area() {
        return light.position().distance(position) < range && light.area_projected_solid_angle(position, normal) > 0.0;
    }
    let (to_light, in_range) = match light.kind {
        LightKind::Directional => (-light.direction(), true),
        LightKind::Point | LightKind::Spot { .. } | LightKind::Rect { .. } | LightKind::Disk { .. } => {
            let offset = light.position() - position;
            let distance = offset.length();
            // At the light itself `to_light` is NaN and every test below fails.
            (offset / distance, distance < range)
        }
    };
    let in_cone = match light.kind {
        LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
            let params = spot_angle_params(inner_cone_rad, outer_cone_rad);
            spot_attenuation(light.direction().dot(-to_light), params) > 0.0
        }
        _ => true,
    };
    in_range && in_cone && normal.dot(to_light) > 0.0
}
