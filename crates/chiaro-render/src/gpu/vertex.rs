//! One interleaved vertex, as `shaders/common/mesh.wesl` reads it through attributes.

use bytemuck::{Pod, Zeroable};

/// One interleaved vertex (locations 0 to 5 of `shaders/common/mesh.wesl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuVertex {
    // Plain arrays: glam's SIMD Vec4 is 16-aligned and would pad the vertex.
    /// Position in the mesh's local space, metres.
    pub position: [f32; 3],
    /// Unit normal in local space.
    pub normal: [f32; 3],
    /// Local-space tangent (xyz) and the bitangent's sign (w), as glTF stores them.
    pub tangent: [f32; 4],
    /// TEXCOORD_0.
    pub uv0: [f32; 2],
    /// TEXCOORD_1.
    pub uv1: [f32; 2],
    /// Coordinates in the instance's lightmap atlas layer (zero without one).
    pub lightmap_uv: [f32; 2],
    /// Linear RGBA vertex colour (COLOR_0), normalised 16-bit: white without one. Eight
    /// bytes instead of sixteen, and finer than any 8-bit colour a file can hold.
    pub color: [u16; 4],
}

impl GpuVertex {
    /// The seven attributes at shader locations 0 to 6, in field order.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 7] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32x2, 4 => Float32x2, 5 => Float32x2,
        6 => Unorm16x4
    ];

    /// A linear colour in 0..1 as the vertex stores it.
    pub fn unorm16(color: glam::Vec4) -> [u16; 4] {
        color.to_array().map(|c| (c.clamp(0.0, 1.0) * 65535.0).round() as u16)
    }

    /// The vertex buffer layout of the mesh passes: `GpuVertex` per vertex.
    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<GpuVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_sit_at_the_fields_offsets() {
        let offsets = [
            std::mem::offset_of!(GpuVertex, position),
            std::mem::offset_of!(GpuVertex, normal),
            std::mem::offset_of!(GpuVertex, tangent),
            std::mem::offset_of!(GpuVertex, uv0),
            std::mem::offset_of!(GpuVertex, uv1),
            std::mem::offset_of!(GpuVertex, lightmap_uv),
            std::mem::offset_of!(GpuVertex, color),
        ];
        for (attribute, offset) in GpuVertex::ATTRIBUTES.iter().zip(offsets) {
            assert_eq!(attribute.offset as usize, offset, "location {}", attribute.shader_location);
        }
    }
}
