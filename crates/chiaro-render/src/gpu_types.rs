//! `#[repr(C)]` mirrors of the WGSL structs in `shaders/common/`. The WGSL names drop the
//! `Gpu` prefix; a test checks every size against naga's layout of the shaders.

use bytemuck::{Pod, Zeroable};
use chiaro_math::light::{MAX_DIRECTIONAL_LIGHTS, MAX_OTHER_LIGHTS};
use glam::{Mat4, Vec2, Vec3, Vec4};

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuFrame {
    pub clip_from_world: Mat4,
    pub view_from_world: Mat4,
    pub camera_position_ws: Vec3,
    pub exposure_scale: f32,
    pub ambient: Vec3,
    pub directional_light_count: u32,
    pub background: Vec3,
    pub other_light_count: u32,
    /// 0: shaded image; 1: cascade colours over it.
    pub debug_view: u32,
    /// Other lights [0, this) have shadow maps; the shader loops over them apart.
    pub shadowed_other_light_count: u32,
    pub _pad: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuDirectionalLight {
    pub color: Vec3,
    pub _pad0: f32,
    pub direction_to_light_ws: Vec3,
    pub _pad1: f32,
    /// (strength, first atlas tile, normal bias, filter); strength 0 casts no shadow.
    pub shadow: Vec4,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuOtherLight {
    pub position_ws: Vec3,
    pub range: f32,
    pub color: Vec3,
    pub _pad0: f32,
    pub spot_direction_ws: Vec3,
    pub _pad1: f32,
    pub spot_angles: Vec2,
    pub _pad2: Vec2,
    /// (strength, first atlas tile, 1 for points, filter); strength <= 0 samples none.
    pub shadow: Vec4,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuLights {
    pub directional: [GpuDirectionalLight; MAX_DIRECTIONAL_LIGHTS],
    pub other: [GpuOtherLight; MAX_OTHER_LIGHTS],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuObject {
    pub world_from_local: Mat4,
    pub normal_from_local: Mat4,
    /// x: `OBJECT_*` flag bits.
    pub flags: [u32; 4],
}

/// The object receives shadows.
pub const OBJECT_RECEIVES_SHADOWS: u32 = 1;

impl GpuObject {
    pub fn new(world_from_local: Mat4, receives_shadows: bool) -> GpuObject {
        GpuObject {
            world_from_local,
            normal_from_local: world_from_local.inverse().transpose(),
            flags: [if receives_shadows { OBJECT_RECEIVES_SHADOWS } else { 0 }, 0, 0, 0],
        }
    }
}

/// Shadowed directional lights x cascades.
pub const MAX_DIRECTIONAL_SHADOW_TILES: usize = 16;
pub use chiaro_math::shadow::other::MAX_OTHER_SHADOW_TILES;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuShadows {
    pub directional_atlas_from_world: [Mat4; MAX_DIRECTIONAL_SHADOW_TILES],
    /// xyz centre, w radius squared.
    pub culling_spheres: [Vec4; 4],
    /// x: 1 / radius squared; y: texel size x sqrt(2).
    pub cascade_data: [Vec4; 4],
    pub distance_fade: Vec4,
    /// (atlas size, 1 / atlas size, tiles per side, unused).
    pub directional_atlas: Vec4,
    pub other_atlas_from_world: [Mat4; MAX_OTHER_SHADOW_TILES],
    /// xy: tile origin (half a texel in), z: extent less a texel, w: normal bias per metre.
    pub other_tiles: [Vec4; MAX_OTHER_SHADOW_TILES],
    /// (atlas size, 1 / atlas size, unused, unused).
    pub other_atlas: Vec4,
    pub cascade_count: u32,
    pub cascade_blend: u32,
    pub _pad: [u32; 2],
}

/// One shadow-caster view, at a 256-byte dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuCasterView {
    pub clip_from_world: Mat4,
    /// x: clamp depth in the vertex shader (no unclipped-depth support).
    pub flags: [u32; 4],
    pub _pad: [Vec4; 11],
}

/// The light the shadow AOV pass reports, at a 256-byte dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuAovLight {
    pub directional_index: u32,
    pub other_index: u32,
    pub _pad: [u32; 62],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTextureTransform {
    pub linear: Vec4,
    pub offset_uv_set: Vec4,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_color: Vec4,
    pub emissive: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub normal_scale: f32,
    pub occlusion_strength: f32,
    pub alpha_cutoff: f32,
    pub alpha_mode: u32,
    pub double_sided: u32,
    /// Bit 0: the material has a normal texture.
    pub flags: u32,
    pub _pad: u32,
    pub base_color_uv: GpuTextureTransform,
    pub metallic_roughness_uv: GpuTextureTransform,
    pub normal_uv: GpuTextureTransform,
    pub occlusion_uv: GpuTextureTransform,
    pub emissive_uv: GpuTextureTransform,
}

/// One interleaved vertex, as `shaders/common/mesh.wesl` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuVertex {
    // Plain arrays: glam's SIMD Vec4 is 16-aligned and would pad the vertex.
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub tangent: [f32; 4],
    pub uv0: [f32; 2],
    pub uv1: [f32; 2],
}

impl GpuVertex {
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32x2, 4 => Float32x2
    ];

    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<GpuVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}
