//! Shadow mask channels for mixed lights, as Unity assigns them: four channels; a
//! directional light overlaps every other light; point and spot lights share a channel
//! when their influence volumes do not overlap. Lights take channels most important
//! first, each the lowest channel no overlapping light holds; a light that finds none
//! (a fifth overlapping light) is demoted to baked.

use glam::Vec3;

pub const SHADOW_MASK_CHANNELS: usize = 4;

/// A shadowed mixed light as the assignment sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelCandidate {
    /// Index in `Scene::lights`.
    pub light: usize,
    /// Brightest channel times intensity (candela; lux for directional lights).
    pub importance: f32,
    /// A sphere around the light's influence, `None` for directional lights (everywhere).
    pub bounds: Option<(Vec3, f32)>,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChannelAssignment {
    /// `(light, channel)` for every light that got one, in assignment order.
    pub channels: Vec<(usize, u8)>,
    /// Lights that found no free channel, least important last.
    pub demoted: Vec<usize>,
}

/// A sphere around a spot light's influence (its range sphere cut by the cone): for
/// cones narrower than 90 degrees the sphere through the apex with its centre on the
/// axis at `range / (2 cos(outer))` holds the whole sector.
pub fn spot_bounds(position: Vec3, direction: Vec3, range: f32, outer_rad: f32) -> (Vec3, f32) {
    let cos = outer_rad.cos();
    if cos > std::f32::consts::FRAC_1_SQRT_2 {
        let radius = range / (2.0 * cos);
        (position + direction * radius, radius)
    } else {
        (position, range)
    }
}

fn overlap(a: &ChannelCandidate, b: &ChannelCandidate) -> bool {
    match (a.bounds, b.bounds) {
        (Some((ca, ra)), Some((cb, rb))) => ca.distance(cb) < ra + rb,
        _ => true,
    }
}

pub fn assign_channels(candidates: &[ChannelCandidate]) -> ChannelAssignment {
    let mut order: Vec<&ChannelCandidate> = candidates.iter().collect();
    // Directional lights first (they overlap everything), then by importance, then by
    // index so that the assignment is stable.
    order.sort_by(|a, b| {
        b.bounds
            .is_none()
            .cmp(&a.bounds.is_none())
            .then(b.importance.total_cmp(&a.importance))
            .then(a.light.cmp(&b.light))
    });
    let mut assigned: Vec<(&ChannelCandidate, u8)> = Vec::new();
    let mut out = ChannelAssignment::default();
    for candidate in order {
        let mut taken = [false; SHADOW_MASK_CHANNELS];
        for (other, channel) in &assigned {
            if overlap(candidate, other) {
                taken[*channel as usize] = true;
            }
        }
        match taken.iter().position(|t| !t) {
            Some(channel) => {
                assigned.push((candidate, channel as u8));
                out.channels.push((candidate.light, channel as u8));
            }
            None => out.demoted.push(candidate.light),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(light: usize, x: f32, importance: f32) -> ChannelCandidate {
        ChannelCandidate { light, importance, bounds: Some((Vec3::new(x, 0.0, 0.0), 1.0)) }
    }

    fn channel_of(a: &ChannelAssignment, light: usize) -> Option<u8> {
        a.channels.iter().find(|(l, _)| *l == light).map(|(_, c)| *c)
    }

    #[test]
    fn lights_that_do_not_overlap_share_a_channel() {
        // Three points in a row, 3 m apart with 1 m ranges: none overlap.
        let a = assign_channels(&[point(0, 0.0, 1.0), point(1, 3.0, 1.0), point(2, 6.0, 1.0)]);
        assert_eq!(a.channels, vec![(0, 0), (1, 0), (2, 0)]);
        assert!(a.demoted.is_empty());
    }

    #[test]
    fn the_overlap_graph_decides_the_channels() {
        // 0 overlaps 1, 1 overlaps 2, 0 and 2 do not: 0 and 2 share, 1 takes another.
        let a = assign_channels(&[point(0, 0.0, 3.0), point(1, 1.5, 2.0), point(2, 3.0, 1.0)]);
        assert_eq!(channel_of(&a, 0), Some(0));
        assert_eq!(channel_of(&a, 1), Some(1));
        assert_eq!(channel_of(&a, 2), Some(0));
    }

    #[test]
    fn a_fifth_overlapping_light_is_demoted_least_important_first() {
        let lights: Vec<ChannelCandidate> = (0..6).map(|i| point(i, i as f32 * 0.1, 10.0 - i as f32)).collect();
        let a = assign_channels(&lights);
        assert_eq!(a.channels.len(), 4);
        assert_eq!(a.demoted, vec![4, 5]);
        // Importance, not file order, decides: reverse the importances.
        let lights: Vec<ChannelCandidate> = (0..6).map(|i| point(i, i as f32 * 0.1, 1.0 + i as f32)).collect();
        assert_eq!(assign_channels(&lights).demoted, vec![1, 0]);
    }

    #[test]
    fn directional_lights_overlap_everything_and_come_first() {
        let sun = ChannelCandidate { light: 9, importance: 0.001, bounds: None };
        let a = assign_channels(&[point(0, 0.0, 100.0), point(1, 50.0, 100.0), sun]);
        assert_eq!(a.channels[0], (9, 0));
        assert_eq!(channel_of(&a, 0), Some(1));
        assert_eq!(channel_of(&a, 1), Some(1));
        let suns: Vec<ChannelCandidate> =
            (0..5).map(|i| ChannelCandidate { light: i, importance: 1.0, bounds: None }).collect();
        assert_eq!(assign_channels(&suns).demoted, vec![4]);
    }

    #[test]
    fn spot_bounds_hold_the_whole_sector() {
        let (position, direction, range) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, -0.6, 0.8), 5.0);
        for outer in [0.2f32, 0.6, 0.78, 1.2] {
            let (centre, radius) = spot_bounds(position, direction, range, outer);
            let (t, b) = chiaro_math::sampling::basis(direction);
            for i in 0..=8 {
                for j in 0..16 {
                    let angle = outer * i as f32 / 8.0;
                    let phi = j as f32 / 16.0 * std::f32::consts::TAU;
                    let d = direction * angle.cos() + (t * phi.cos() + b * phi.sin()) * angle.sin();
                    for distance in [0.0, range * 0.5, range] {
                        let p = position + d * distance;
                        assert!(p.distance(centre) <= radius * 1.0001, "outer {outer}: {p} outside");
                    }
                }
            }
        }
    }
}
