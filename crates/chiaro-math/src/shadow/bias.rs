//! Bias terms that keep a surface from shadowing itself.
//!
//! Slope-scale depth bias is rasterizer state; the normal bias moves the sampled position
//! along the surface normal by a distance that scales with the shadow map's world-space
//! texel size and the filter's footprint.

use super::filter::ShadowFilter;

/// World-space size of one texel of a cascade whose culling sphere has `radius`, on a tile
/// of `tile_size` texels: the tile spans the sphere's diameter.
pub fn cascade_texel_size_ws(radius: f32, tile_size: u32) -> f32 {
    2.0 * radius / tile_size as f32
}

/// The cascade's normal-bias distance for a light's normal bias of 1: the filter's
/// footprint in texels times the texel size times sqrt(2) (the texel's diagonal, the
/// worst case). A 2048 tile over a 10 m radius with the 2x2 filter: 0.0098 x 1 x 1.414 =
/// 1.4 cm; with 7x7, 5.5 cm.
pub fn normal_bias_ws(texel_size_ws: f32, filter: ShadowFilter) -> f32 {
    texel_size_ws * filter.footprint_texels() * std::f32::consts::SQRT_2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_bias_grows_with_texel_and_filter() {
        let texel = cascade_texel_size_ws(10.0, 2048);
        assert!((texel - 20.0 / 2048.0).abs() < 1e-7);
        let hard = normal_bias_ws(texel, ShadowFilter::Pcf2x2);
        assert!((hard - texel * std::f32::consts::SQRT_2).abs() < 1e-7);
        assert!(normal_bias_ws(texel, ShadowFilter::Tent7x7) > normal_bias_ws(texel, ShadowFilter::Tent5x5));
        assert!(normal_bias_ws(texel, ShadowFilter::Tent5x5) > normal_bias_ws(texel, ShadowFilter::Tent3x3));
        assert!(normal_bias_ws(texel, ShadowFilter::Tent3x3) > hard);
    }
}
