//! What Chiaro's tests share, in one dev-only crate (no release build links it): scenes
//! made in code (`scenes`: a floor, boxes, lights, spheres, glTF documents with an
//! image-based light), a renderer on whatever adapter is present, and the sRGB transfer
//! function tests predict pixels with. No adapter is a failure, never a skip.

pub mod scenes;

pub use scenes::*;

use chiaro_render::{GpuContext, Renderer};

/// A renderer on the best adapter (the software Vulkan device in CI); panics without one,
/// so a machine with no adapter fails the GPU tests instead of skipping them.
pub fn renderer() -> Renderer {
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    Renderer::new(ctx).expect("renderer")
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1]: what an
/// sRGB target stores for it.
pub fn srgb_encode(linear: f32) -> f32 {
    let c = linear.clamp(0.0, 1.0);
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

#[cfg(test)]
mod tests {
    use super::srgb_encode;

    #[test]
    fn srgb_encodes_the_ends_and_the_knee() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.003_130_8) - 0.040_45).abs() < 1e-5);
        assert!((srgb_encode(0.214_041) - 0.5).abs() < 1e-4);
    }
}
