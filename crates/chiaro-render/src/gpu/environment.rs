//! The environment's uniform (`shaders/lighting/environment.wesl`) and the parameters of
//! the compute passes that make its maps (`shaders/environment_bake.wesl`).

use bytemuck::{Pod, Zeroable};
use glam::Vec4;

/// How surfaces read the environment: its irradiance as spherical harmonics, the turn
/// from world into the image's frame, and the prefiltered cube's mips.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuEnvironment {
    /// Nine RGB coefficients of radiance (chiaro_math::sh order), times the intensity.
    pub radiance_sh: [Vec4; 9],
    /// cos and sin of minus `rotation_deg`: world directions into the image's frame.
    pub turn_cos: f32,
    /// See `turn_cos`.
    pub turn_sin: f32,
    /// `environment.intensity`, applied to the cube and the background.
    pub intensity: f32,
    /// The prefiltered cube's last mip, which holds roughness 1.
    pub specular_last_mip: f32,
    /// 1 where the bake holds the environment's diffuse light (`mode = "baked"`): baked
    /// surfaces then take only its specular light.
    pub diffuse_baked: u32,
    /// Keeps the struct a multiple of 16 bytes, as uniforms are.
    pub _pad: [u32; 3],
}

/// One dispatch of the environment's compute passes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuEnvironmentBake {
    /// The side in texels of what the dispatch writes (a cube face or the BRDF table).
    pub size: u32,
    /// The side of the radiance cube's first mip, which the prefilter reads.
    pub source_size: u32,
    /// Perceptual roughness the prefilter's mip holds.
    pub roughness: f32,
    /// Importance samples per texel.
    pub samples: u32,
}
