//! The verdicts on a synthetic floor seen from above, where every answer is known.

use super::*;

const W: usize = 20;
const H: usize = 12;

fn sun() -> Light {
    Light::new(LightKind::Directional, Vec3::ZERO, Vec3::NEG_Y)
}

/// A floor seen from above: pixel (x, y) at (x, 0, y) decimetres, facing up; all lit.
fn floor_reference() -> ShadowReference {
    let position: Vec<_> = (0..W * H).map(|i| Some(Vec3::new((i % W) as f32, 0.0, (i / W) as f32) * 0.1)).collect();
    ShadowReference {
        width: W as u32,
        height: H as u32,
        position,
        normal: vec![Vec3::Y; W * H],
        receives: vec![true; W * H],
        visibility: vec![vec![1.0; W * H]],
        ranges: vec![f32::INFINITY],
    }
}

/// Light 0 of `reference` rendered as `rendered` at the reference's own positions, with
/// the default edge band.
fn judged<'a>(rendered: &'a [f32], reference: &'a ShadowReference, light: &'a Light, range: f32) -> JudgedLight<'a> {
    JudgedLight {
        rendered_shadow: rendered,
        rendered_position: &reference.position,
        reference,
        light_index: 0,
        light,
        range,
        edge_band_px: EDGE_BAND_PX,
    }
}

fn compare(rendered: &[f32], reference: &ShadowReference, light: &Light, range: f32) -> LightComparison {
    compare_light(&judged(rendered, reference, light, range))
}

#[test]
fn counts_false_and_missed_shadows() {
    let mut reference = floor_reference();
    let mut rendered = vec![1.0; W * H];
    rendered[5] = 0.0;
    rendered[6] = 0.4;
    rendered[7] = 0.6; // within the threshold
    let result = compare(&rendered, &reference, &sun(), f32::INFINITY);
    assert_eq!(result, LightComparison { compared: W * H, false_shadow: 2, missed_shadow: 0 });
    assert!((result.disagreement() - 2.0 / (W * H) as f64).abs() < 1e-12);
    assert_eq!(result.missed_share(), 0.0);

    reference.visibility[0] = vec![0.0; W * H];
    let mut rendered = vec![0.0; W * H];
    rendered[..3].fill(1.0);
    let result = compare(&rendered, &reference, &sun(), f32::INFINITY);
    assert_eq!((result.false_shadow, result.missed_shadow), (0, 3));
    assert!((result.missed_share() - 3.0 / (W * H) as f64).abs() < 1e-12);
    assert_eq!(LightComparison::default().disagreement(), 0.0);
}

#[test]
fn positions_must_agree_within_a_centimetre() {
    let reference = floor_reference();
    let rendered = vec![0.0; W * H];
    let mut positions = reference.position.clone();
    for (i, p) in positions.iter_mut().enumerate() {
        let offset = match i % 3 {
            0 => 0.009,
            1 => 0.011,
            _ => f32::NAN,
        };
        *p = if offset.is_nan() { None } else { p.map(|p| p + Vec3::Y * offset) };
    }
    let result = compare_light(&JudgedLight {
        rendered_position: &positions,
        ..judged(&rendered, &reference, &sun(), f32::INFINITY)
    });
    assert_eq!(result.compared, (0..W * H).filter(|i| i % 3 == 0).count());
    assert_eq!(result.false_shadow, result.compared);
}

#[test]
fn unlit_surfaces_and_non_receivers_are_not_compared() {
    let mut reference = floor_reference();
    let rendered = vec![1.0; W * H];
    // The sun from below lights nothing.
    let under = Light::new(LightKind::Directional, Vec3::ZERO, Vec3::Y);
    assert_eq!(compare(&rendered, &reference, &under, f32::INFINITY).compared, 0);
    reference.receives[..W].fill(false);
    assert_eq!(compare(&rendered, &reference, &sun(), f32::INFINITY).compared, W * (H - 1));
    reference.position[W] = None;
    assert_eq!(compare(&rendered, &reference, &sun(), f32::INFINITY).compared, W * (H - 1) - 1);
    // Out of range: the light index, and short rendered arrays.
    assert_eq!(
        compare_light(&JudgedLight { light_index: 1, ..judged(&rendered, &reference, &sun(), 1.0) }).compared,
        0
    );
    // Row 0 does not receive and pixel W is sky: W - 1 of the first two rows count.
    assert_eq!(compare(&rendered[..W * 2], &reference, &sun(), f32::INFINITY).compared, W - 1);
}

#[test]
fn point_lights_reach_only_within_range() {
    let reference = floor_reference();
    let rendered = vec![1.0; W * H];
    let centre = Vec3::new(1.0, 0.5, 0.5);
    let point = Light::new(LightKind::Point, centre, Vec3::NEG_Y);
    let range = 1.0;
    let expected = reference.position.iter().filter(|p| p.unwrap().distance(centre) < range).count();
    assert!(expected > 10 && expected < W * H);
    assert_eq!(compare(&rendered, &reference, &point, range).compared, expected);
    assert_eq!(compare(&rendered, &reference, &point, f32::INFINITY).compared, W * H);
}

#[test]
fn spot_lights_reach_only_inside_the_cone() {
    let reference = floor_reference();
    let rendered = vec![1.0; W * H];
    let apex = Vec3::new(1.0, 0.5, 0.5);
    let (inner, outer) = (0.3f32, 0.6f32);
    let spot = Light::new(LightKind::Spot { inner_cone_rad: inner, outer_cone_rad: outer }, apex, Vec3::NEG_Y);
    // Inside the outer cone: the angle from straight down is below `outer`.
    let expected = reference
        .position
        .iter()
        .filter(|p| {
            let to_surface = (p.unwrap() - apex).normalize();
            to_surface.dot(Vec3::NEG_Y).acos() < outer - 1e-3
        })
        .count();
    let near_rim = reference
        .position
        .iter()
        .filter(|p| {
            let angle = (p.unwrap() - apex).normalize().dot(Vec3::NEG_Y).acos();
            (angle - outer).abs() <= 1e-3
        })
        .count();
    assert_eq!(near_rim, 0, "no pixel sits on the rim");
    assert!(expected > 10 && expected < W * H);
    assert_eq!(compare(&rendered, &reference, &spot, 10.0).compared, expected);
}

#[test]
fn shadow_edges_are_banded_but_sky_edges_are_not() {
    let mut reference = floor_reference();
    // Left half (x < 10) shadowed.
    for (i, v) in reference.visibility[0].iter_mut().enumerate() {
        *v = if i % W < 10 { 0.0 } else { 1.0 };
    }
    // Sky in the top row's right half, bordering lit floor.
    for x in 10..W {
        reference.position[x] = None;
        reference.normal[x] = Vec3::ZERO;
        reference.visibility[0][x] = f32::NAN;
    }
    // Everything rendered wrong, so every compared pixel counts.
    let rendered: Vec<f32> = reference.visibility[0].iter().map(|v| 1.0 - v).collect();
    let verdicts = classify_pixels(&judged(&rendered, &reference, &sun(), f32::INFINITY));
    for y in 0..H {
        for x in 0..W {
            let verdict = verdicts[y * W + x];
            let expected = if (7..13).contains(&x) || (y == 0 && x >= 10) {
                PixelVerdict::NotCompared
            } else if x < 10 {
                PixelVerdict::MissedShadow
            } else {
                PixelVerdict::FalseShadow
            };
            assert_eq!(verdict, expected, "pixel ({x}, {y})");
        }
    }
    let result = compare(&rendered, &reference, &sun(), f32::INFINITY);
    assert_eq!(result.missed_shadow, 7 * H);
    assert_eq!(result.false_shadow, 7 * (H - 1));
}

#[test]
fn difference_image_colours() {
    let mut reference = floor_reference();
    reference.visibility[0][W * H - 1] = 0.0;
    reference.receives[0] = false;
    let mut rendered = vec![1.0; W * H];
    rendered[W * 6 + 10] = 0.0;
    rendered[W * H - 1] = 0.0;
    let image = difference_image(&judged(&rendered, &reference, &sun(), 1.0));
    assert_eq!(image.len(), W * H);
    assert_eq!(image[0], [0, 0, 0, 255]);
    assert_eq!(image[W * 6 + 10], [255, 0, 0, 255]);
    assert_eq!(image[W * 6 + 2], [128, 128, 128, 255]);
    // The lone shadowed corner pixel is inside its own edge band.
    assert_eq!(image[W * H - 1], [0, 0, 0, 255]);
    let mut dark = floor_reference();
    dark.visibility[0].fill(0.0);
    rendered.fill(0.0);
    rendered[3] = 1.0;
    let image = difference_image(&judged(&rendered, &dark, &sun(), 1.0));
    assert_eq!(image[3], [0, 0, 255, 255]);
    assert_eq!(image[4], [48, 48, 48, 255]);
}

#[test]
fn the_edge_band_leaves_out_the_pixels_that_near_a_traced_edge() {
    // The reference's shadow covers columns 10 and up; the rendered one starts a column
    // early (column 9: a false shadow right at the edge) and has a stray false shadow in
    // column 2, far from it.
    let mut reference = floor_reference();
    reference.visibility[0] = (0..W * H).map(|i| if i % W >= 10 { 0.0 } else { 1.0 }).collect();
    let rendered: Vec<f32> = (0..W * H).map(|i| if i % W >= 9 || i % W == 2 { 0.0 } else { 1.0 }).collect();
    let counted = |edge_band_px| {
        compare_light(&JudgedLight { edge_band_px, ..judged(&rendered, &reference, &sun(), f32::INFINITY) })
    };
    // Band 0: every pixel, both false shadows.
    assert_eq!(counted(0), LightComparison { compared: W * H, false_shadow: 2 * H, missed_shadow: 0 });
    // Band 1: columns 9 and 10 left out; the stray one is still judged.
    assert_eq!(counted(1), LightComparison { compared: (W - 2) * H, false_shadow: H, missed_shadow: 0 });
    // Band 3 (the default): columns 7 to 12 left out.
    assert_eq!(counted(EDGE_BAND_PX), LightComparison { compared: (W - 6) * H, false_shadow: H, missed_shadow: 0 });
}
