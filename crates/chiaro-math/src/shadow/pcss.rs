//! Contact-hardening soft shadows (percentage-closer soft shadows, PCSS) from a light's
//! size: how a shadow tile maps its depths and texture offsets back to metres (the
//! "lens" the shaders in `shaders/shadows/pcss.wesl` read), the penumbra's width by
//! similar triangles, and the visibility of a disc light across a straight shadow edge,
//! which is what a disc-shaped filter over the hard shadow gives and what the tests and
//! the reference measure against.

use glam::Mat4;

/// Blocker searches reach at most the tile's width over this from the receiver: the
/// cone to a sphere light's near plane (or a sun's pulled-back one) would otherwise
/// cover most of the tile. Blockers whose penumbra would need more are found only in
/// part, and their shadows come out harder than they are. A reach fixed in texels is too
/// little in a near cascade, whose texels are a millimetre across (docs/performance.md).
pub const SEARCH_TILE_DIVISOR: u32 = 8;

/// A cascade's near plane is pulled this many culling-sphere radii towards a `pcss`
/// light (at least; the light's own `shadowNearPlane` if that is more). Casters nearer
/// the light than the near plane are flattened onto it, which makes them look closer to
/// their receivers and their penumbrae narrower (docs/performance.md). Depth is linear in
/// an orthographic tile, so the pull costs no precision worth having.
pub const DIRECTIONAL_NEAR_PLANE_PULL: f32 = 2.0;

/// A tile's lens: `[near, far, metres_per_uv]`. Perspective tiles (spot, point faces):
/// the projection's near and far planes (wgpu depth 0 at near, 1 at far) and the metres
/// one unit of atlas texture coordinates spans at 1 m from the light. Orthographic tiles
/// (cascades): near 0, `far` the metres from depth 0 to 1, and the metres one unit of
/// texture coordinates spans at any depth.
pub type TileLens = [f32; 3];

/// The lens of a cascade tile from its atlas-from-world projection (orthographic:
/// texture coordinates and depth are affine in world position).
pub fn orthographic_lens(atlas_from_world: &Mat4) -> TileLens {
    let per_metre = |row: usize| atlas_from_world.row(row).truncate().length();
    [0.0, 1.0 / per_metre(2), 1.0 / per_metre(0)]
}

/// The lens of a perspective tile from its `clip_from_view` (glam's `perspective_rh`) and
/// the width of the tile in atlas texture coordinates.
pub fn perspective_lens(clip_from_view: &Mat4, tile_uv_width: f32) -> TileLens {
    // perspective_rh: z_axis.z = f / (n - f), w_axis.z = n f / (n - f).
    let (a, b) = (clip_from_view.z_axis.z, clip_from_view.w_axis.z);
    let (near, far) = (b / a, b / (1.0 + a));
    // NDC x = x_axis.x * x / z, and the tile spans 2 NDC units.
    [near, far, 2.0 / (clip_from_view.x_axis.x * tile_uv_width)]
}

/// Metres from the light (perspective) or from depth 0 (orthographic) of a shadow-map
/// depth.
pub fn linear_depth(lens: TileLens, depth: f32) -> f32 {
    let [near, far, _] = lens;
    if near > 0.0 { near * far / (far - depth * (far - near)) } else { depth * far }
}

/// The full width of the penumbra on a receiver `receiver_m` from the light (or the
/// sun's depth 0) behind a blocker edge at `blocker_m`: for a sphere light of radius
/// `size` seen in perspective, `2 size (receiver - blocker) / blocker`; for a sun,
/// `size` = tan of half its angular diameter, `2 size (receiver - blocker)`.
pub fn penumbra_width(perspective: bool, size: f32, receiver_m: f32, blocker_m: f32) -> f32 {
    let gap = (receiver_m - blocker_m).max(0.0);
    if perspective { 2.0 * size * gap / blocker_m.max(1e-6) } else { 2.0 * size * gap }
}

/// Share of a uniform disc left uncovered when a straight edge covers it up to `x` (in
/// units of its radius, from -1: all covered, to 1: none): the visibility of a disc
/// light across the shadow of a straight edge, with `x` the receiver's place across the
/// penumbra scaled to [-1, 1].
pub fn disc_edge_visibility(x: f32) -> f32 {
    let x = x.clamp(-1.0, 1.0);
    // The area of the disc's part beyond the chord at x, over pi.
    let covered = (x.acos() - x * (1.0 - x * x).sqrt()) / std::f32::consts::PI;
    1.0 - covered
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn perspective_lens_recovers_near_far_and_texel_scale() {
        let clip = Mat4::perspective_rh(90f32.to_radians(), 1.0, 0.05, 8.0);
        let [near, far, metres_per_uv] = perspective_lens(&clip, 0.25);
        assert!((near - 0.05).abs() < 1e-5 && (far - 8.0).abs() < 1e-3, "{near} {far}");
        // A 90 degree tile is 2 m wide at 1 m; it spans 0.25 of the atlas.
        assert!((metres_per_uv - 8.0).abs() < 1e-4, "{metres_per_uv}");
        for d in [0.1f32, 1.0, 4.0, 7.5] {
            let depth = clip.project_point3(Vec3::new(0.0, 0.0, -d)).z;
            assert!((linear_depth([near, far, metres_per_uv], depth) - d).abs() < 1e-3 * d, "{d}");
        }
    }

    #[test]
    fn orthographic_lens_reads_the_projection() {
        let atlas_from_world = Mat4::from_scale(Vec3::new(0.5, 0.5, 1.0))
            * Mat4::orthographic_rh(-10.0, 10.0, -10.0, 10.0, 0.0, 40.0)
            * Mat4::look_to_rh(Vec3::new(3.0, 20.0, 1.0), Vec3::new(0.3, -1.0, 0.2).normalize(), Vec3::Z);
        let [near, far, metres_per_uv] = orthographic_lens(&atlas_from_world);
        assert_eq!(near, 0.0);
        // 20 m across x, halved into texture coordinates: 20 m per unit.
        assert!((far - 40.0).abs() < 1e-3 && (metres_per_uv - 20.0).abs() < 1e-3, "{far} {metres_per_uv}");
        assert!((linear_depth([near, far, metres_per_uv], 0.25) - 10.0).abs() < 1e-4);
    }

    #[test]
    fn penumbra_follows_similar_triangles() {
        // A plank 1 m above the floor, a 0.2 m light 3 m above it: 2 * 0.2 * 1 / 2.
        assert!((penumbra_width(true, 0.2, 3.0, 2.0) - 0.2).abs() < 1e-6);
        // The sun (0.53 degrees) behind a caster 10 m up.
        let sun = penumbra_width(false, (0.53f32.to_radians() * 0.5).tan(), 30.0, 20.0);
        assert!((sun - 0.0925).abs() < 1e-3, "{sun}");
        assert_eq!(penumbra_width(true, 0.2, 2.0, 2.0), 0.0);
    }

    #[test]
    fn disc_edge_visibility_runs_from_dark_to_lit() {
        assert_eq!(disc_edge_visibility(-1.0), 0.0);
        assert!((disc_edge_visibility(0.0) - 0.5).abs() < 1e-6);
        assert!((disc_edge_visibility(1.0) - 1.0).abs() < 1e-6);
        assert!(disc_edge_visibility(-0.3) + disc_edge_visibility(0.3) - 1.0 < 1e-6);
        assert!(disc_edge_visibility(0.2) < disc_edge_visibility(0.4));
    }
}
