//! Copies a texture back to the CPU, removing wgpu's 256-byte row padding.

use crate::context::GpuContext;
use crate::error::RenderError;

/// Reads a whole 2D texture of `bytes_per_pixel`; returns tightly packed rows.
pub fn read_texture(ctx: &GpuContext, texture: &wgpu::Texture, bytes_per_pixel: u32) -> Result<Vec<u8>, RenderError> {
    let (width, height) = (texture.width(), texture.height());
    let unpadded = width * bytes_per_pixel;
    let padded = unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    ctx.queue.submit([encoder.finish()]);
    read_buffer(ctx, &buffer).map(|bytes| {
        let mut out = Vec::with_capacity((unpadded * height) as usize);
        for row in bytes.chunks_exact(padded as usize) {
            out.extend_from_slice(&row[..unpadded as usize]);
        }
        out
    })
}

/// Maps a MAP_READ buffer after the queue's work and returns its bytes.
pub fn read_buffer(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, RenderError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = sender.send(r);
    });
    ctx.wait_idle()?;
    receiver.recv().map_err(|e| RenderError::Gpu(e.to_string()))?.map_err(|e| RenderError::Gpu(e.to_string()))?;
    let bytes = buffer.get_mapped_range(..).map_err(|e| RenderError::Gpu(e.to_string()))?.to_vec();
    buffer.unmap();
    Ok(bytes)
}
