//! A table of 16-byte records kept in a 2D `Rgba32Uint` texture, `TEXEL_TABLE_WIDTH`
//! (shader_constants) records a row (record `i` at texel `(i % width, i / width)`), read in shaders with
//! `textureLoad`. The culled light loops read their lights this way, past the uniform
//! buffer's 512, rather than from a storage buffer. A lavapipe choice: lavapipe loads a
//! storage buffer one lane and one word at a time behind a bounds test, where it fetches
//! texels as vectors (the figures: docs/performance.md); a GPU may read either as fast.

use crate::error::RenderError;
use crate::gpu::GpuLight;
use crate::shader_constants::{LIGHT_RECORDS, TEXEL_TABLE_WIDTH};

/// Bytes of one record (one texel).
const RECORD_BYTES: usize = 16;
const _: () = assert!(size_of::<GpuLight>() == LIGHT_RECORDS as usize * RECORD_BYTES);
const ROW_BYTES: usize = TEXEL_TABLE_WIDTH as usize * RECORD_BYTES;

/// One table: its texture is made again, with twice the rows, when a frame needs more.
pub struct TexelTable {
    label: &'static str,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl TexelTable {
    /// An empty table of one row.
    pub fn new(device: &wgpu::Device, label: &'static str) -> TexelTable {
        let (texture, view) = Self::make(device, label, 1);
        TexelTable { label, texture, view }
    }

    fn make(device: &wgpu::Device, label: &'static str, rows: u32) -> (wgpu::Texture, wgpu::TextureView) {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: TEXEL_TABLE_WIDTH, height: rows, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        (texture, view)
    }

    /// The view the frame's bind group binds.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Rows that `records` records take.
    fn rows_for(records: usize) -> u32 {
        records.div_ceil(TEXEL_TABLE_WIDTH as usize).max(1) as u32
    }

    /// Writes `bytes` (whole records, zero-padded if not) from record 0. Errors, naming the
    /// table, where they need more rows than the device's largest texture has.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) -> Result<(), RenderError> {
        let records = bytes.len().div_ceil(RECORD_BYTES);
        let rows = Self::rows_for(records);
        let max_rows = device.limits().max_texture_dimension_2d;
        if rows > max_rows {
            return Err(RenderError::Unsupported(format!(
                "the {} need {records} records, more than this device's {max_rows} rows of {TEXEL_TABLE_WIDTH} hold",
                self.label
            )));
        }
        if rows > self.texture.height() {
            (self.texture, self.view) = Self::make(device, self.label, rows.next_power_of_two().min(max_rows));
        }
        let full_rows = bytes.len() / ROW_BYTES;
        if full_rows > 0 {
            self.write_rows(queue, 0, &bytes[..full_rows * ROW_BYTES], TEXEL_TABLE_WIDTH, full_rows as u32);
        }
        let rest = &bytes[full_rows * ROW_BYTES..];
        if !rest.is_empty() {
            let mut padded = rest.to_vec();
            padded.resize(rest.len().next_multiple_of(RECORD_BYTES), 0);
            let width = (padded.len() / RECORD_BYTES) as u32;
            self.write_rows(queue, full_rows as u32, &padded, width, 1);
        }
        Ok(())
    }

    fn write_rows(&self, queue: &wgpu::Queue, first_row: u32, bytes: &[u8], width: u32, rows: u32) {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: first_row, z: 0 },
                aspect: wgpu::TextureAspect::All,
            },
            bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * RECORD_BYTES as u32),
                rows_per_image: Some(rows),
            },
            wgpu::Extent3d { width, height: rows, depth_or_array_layers: 1 },
        );
    }
}
