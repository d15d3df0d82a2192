//! Copies textures back to the CPU: copies are recorded into a frame's encoder, and one
//! wait after its submission maps them all; wgpu's 256-byte row padding is removed.

use crate::context::GpuContext;
use crate::error::RenderError;

/// A texture copy waiting for its submission to finish.
pub struct PendingCopy {
    buffer: wgpu::Buffer,
    unpadded_row: u32,
    padded_row: u32,
}

/// Records a copy of the first `bytes` of `source` (a multiple of 4) into `encoder`.
pub fn copy_buffer(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    source: &wgpu::Buffer,
    bytes: u32,
) -> PendingCopy {
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: bytes as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(source, 0, &buffer, 0, bytes as u64);
    PendingCopy { buffer, unpadded_row: bytes, padded_row: bytes }
}

/// Records a copy of the whole of `texture` (`bytes_per_pixel` each, every layer) into
/// `encoder`.
pub fn copy_texture(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    bytes_per_pixel: u32,
) -> PendingCopy {
    let (width, height, layers) = (texture.width(), texture.height(), texture.depth_or_array_layers());
    let unpadded_row = width * bytes_per_pixel;
    let padded_row = unpadded_row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded_row as u64 * height as u64 * layers as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    PendingCopy { buffer, unpadded_row, padded_row }
}

/// Waits once for the submitted copies and returns each one's tightly packed rows (layer
/// after layer).
pub fn finish_copies(ctx: &GpuContext, copies: Vec<PendingCopy>) -> Result<Vec<Vec<u8>>, RenderError> {
    finish_copies_of(ctx, copies, None)
}

/// As [`finish_copies`], waiting only for `submission` (the one that recorded the copies)
/// when given, so that frames submitted after it keep running.
pub fn finish_copies_of(
    ctx: &GpuContext,
    copies: Vec<PendingCopy>,
    submission: Option<wgpu::SubmissionIndex>,
) -> Result<Vec<Vec<u8>>, RenderError> {
    // A browser's main thread cannot wait for the GPU: its mapping finishes only after
    // control returns to the page, so waiting here would hang the tab. The page reads back
    // with `finish_copies_async` instead.
    if cfg!(target_arch = "wasm32") {
        return Err(RenderError::Gpu(
            "this read-back waits for the GPU, which the browser build cannot do (virtual shadow maps mark \
             their pages this way)"
                .into(),
        ));
    }
    let receivers: Vec<_> = copies
        .iter()
        .map(|copy| {
            let (sender, receiver) = std::sync::mpsc::channel();
            copy.buffer.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = sender.send(r);
            });
            receiver
        })
        .collect();
    match submission {
        Some(index) => {
            ctx.device
                .poll(wgpu::PollType::Wait { submission_index: Some(index), timeout: None })
                .map_err(|e| RenderError::Gpu(e.to_string()))?;
        }
        None => ctx.wait_idle()?,
    }
    copies
        .into_iter()
        .zip(receivers)
        .map(|(copy, receiver)| {
            receiver
                .recv()
                .map_err(|e| RenderError::Gpu(e.to_string()))?
                .map_err(|e| RenderError::Gpu(e.to_string()))?;
            read_mapped(copy)
        })
        .collect()
}

/// As [`finish_copies`], for the browser, whose main thread cannot wait: each copy's
/// mapping is awaited while the page's event loop runs.
#[cfg(target_arch = "wasm32")]
pub async fn finish_copies_async(copies: Vec<PendingCopy>) -> Result<Vec<Vec<u8>>, RenderError> {
    let receivers: Vec<_> = copies
        .iter()
        .map(|copy| {
            let (sender, receiver) = futures_channel::oneshot::channel();
            copy.buffer.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = sender.send(r);
            });
            receiver
        })
        .collect();
    let mut read = Vec::with_capacity(copies.len());
    for (copy, receiver) in copies.into_iter().zip(receivers) {
        receiver
            .await
            .map_err(|_| RenderError::Gpu("the device was lost before a read-back arrived".into()))?
            .map_err(|e| RenderError::Gpu(e.to_string()))?;
        read.push(read_mapped(copy)?);
    }
    Ok(read)
}

/// The tightly packed rows of a mapped copy; unmaps it.
fn read_mapped(copy: PendingCopy) -> Result<Vec<u8>, RenderError> {
    let bytes = {
        let mapped = copy.buffer.get_mapped_range(..).map_err(|e| RenderError::Gpu(e.to_string()))?;
        let mut out = Vec::with_capacity(mapped.len());
        for row in mapped.chunks_exact(copy.padded_row as usize) {
            out.extend_from_slice(&row[..copy.unpadded_row as usize]);
        }
        out
    };
    copy.buffer.unmap();
    Ok(bytes)
}
