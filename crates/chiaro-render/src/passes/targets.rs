//! The targets several passes share, in one home: the HDR image that the forward path,
//! the G-buffer pass and the light volumes write and FXAA, the LDR decode and tone mapping
//! read; the scene depth; the deferred path's G-buffer and LDR light buffer; the two
//! shadow atlases. A target that one pass alone makes and reads stays in its module.

use crate::graph::Target;

/// The HDR targets' format: half floats, pre-exposed so that bright scenes stay in range.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Pre-exposed linear radiance, single-sampled: what tone mapping reads.
pub const HDR: Target = Target("hdr");

/// Base colour (linear) and metallic.
pub const GBUFFER_ALBEDO_METALLIC_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Normals, view depth, roughness and flags, bit-packed.
pub const GBUFFER_PACKED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
/// The legacy LDR light buffer: exp2(-light) in 8 bits.
pub const LIGHT_BUFFER_LDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The deferred path's base colour and metallic.
pub const GBUFFER_ALBEDO_METALLIC: Target = Target("gbuffer albedo metallic");
/// The deferred path's normals, view depth, roughness and flags.
pub const GBUFFER_PACKED: Target = Target("gbuffer packed");
/// The deferred path's legacy LDR light buffer, exp2(-light).
pub const LIGHT_BUFFER_LDR: Target = Target("light buffer ldr");

/// Reverse-Z scene depth with stencil, single-sampled: the deferred path's, and the
/// forward path's without MSAA.
pub const DEPTH: Target = Target("depth");

/// The shadow atlases' format: 32-bit float depth.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The directional lights' cascades.
pub const DIRECTIONAL_ATLAS: Target = Target("directional shadow atlas");
/// The point and spot lights' tiles.
pub const LOCAL_ATLAS: Target = Target("local shadow atlas");

/// The shadow tints' format: per texel, the light the casters that let it through leave
/// (RGB, multiplied together) and `1 / (1 + d)` of the nearest one's depth `d` (A, the
/// largest kept), so that a texel nothing tints (cleared to alpha 0, or never drawn)
/// tints nothing. Half floats: `d` keeps 11 significant bits.
pub const SHADOW_TINTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Two layers the size of the larger atlas: the directional atlas's tiles in layer 0,
/// the local atlas's in layer 1, each at its depth tile's texels.
pub const SHADOW_TINTS: Target = Target("shadow tints");
