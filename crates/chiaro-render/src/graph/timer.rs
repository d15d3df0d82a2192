//! GPU time per pass from timestamp queries, read back without waiting: each frame's
//! passes get two queries each, resolved into a buffer that is mapped when the GPU is
//! done with it; `collect` hands over the frames that have finished.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Most passes timed in one frame.
const MAX_TIMED_PASSES: u32 = 16;
const QUERY_BYTES: u64 = 8;

/// The two queries of one pass.
#[derive(Clone, Copy)]
pub struct PassTimestamps<'a> {
    query_set: &'a wgpu::QuerySet,
    begin: u32,
}

impl<'a> PassTimestamps<'a> {
    /// Writes for a render pass that is the pass's `first` and/or `last` (a pass recorded
    /// as several wgpu passes marks its start in the first and its end in the last; the
    /// ones between get none).
    pub fn writes(&self, first: bool, last: bool) -> Option<wgpu::RenderPassTimestampWrites<'a>> {
        (first || last).then_some(wgpu::RenderPassTimestampWrites {
            query_set: self.query_set,
            beginning_of_pass_write_index: first.then_some(self.begin),
            end_of_pass_write_index: last.then_some(self.begin + 1),
        })
    }

    /// Writes for a pass recorded as one compute pass.
    pub fn compute_writes(&self) -> wgpu::ComputePassTimestampWrites<'a> {
        wgpu::ComputePassTimestampWrites {
            query_set: self.query_set,
            beginning_of_pass_write_index: Some(self.begin),
            end_of_pass_write_index: Some(self.begin + 1),
        }
    }
}

struct Pending {
    frame: u64,
    passes: Vec<&'static str>,
    buffer: wgpu::Buffer,
    mapped: Arc<AtomicBool>,
    map_requested: bool,
}

/// Per-pass GPU times from timestamp queries, collected frames later without waiting.
pub struct GpuTimer {
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    period_ns: f64,
    /// Passes given queries this frame, in order.
    current: Vec<&'static str>,
    pending: Vec<Pending>,
    free: Vec<wgpu::Buffer>,
}

impl GpuTimer {
    /// A query set for `MAX_TIMED_PASSES` passes and the buffers to resolve it into;
    /// `queue` gives the timestamp period.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> GpuTimer {
        let bytes = 2 * MAX_TIMED_PASSES as u64 * QUERY_BYTES;
        GpuTimer {
            query_set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_TIMED_PASSES,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            period_ns: queue.get_timestamp_period() as f64,
            current: Vec::new(),
            pending: Vec::new(),
            free: Vec::new(),
        }
    }

    /// Queries for `pass` in this frame; `None` once the frame has used them all.
    pub fn pass(&mut self, pass: &'static str) -> Option<PassTimestamps<'_>> {
        let slot = self.current.len() as u32;
        if slot >= MAX_TIMED_PASSES {
            return None;
        }
        self.current.push(pass);
        Some(PassTimestamps { query_set: &self.query_set, begin: 2 * slot })
    }

    /// Resolves this frame's queries into a buffer of its own, to be mapped once the
    /// frame is submitted.
    pub fn end_frame(&mut self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, frame: u64) {
        let passes = std::mem::take(&mut self.current);
        if passes.is_empty() {
            return;
        }
        let bytes = 2 * passes.len() as u64 * QUERY_BYTES;
        encoder.resolve_query_set(&self.query_set, 0..2 * passes.len() as u32, &self.resolve, 0);
        let buffer = self.free.pop().unwrap_or_else(|| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size: 2 * MAX_TIMED_PASSES as u64 * QUERY_BYTES,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            })
        });
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &buffer, 0, bytes);
        self.pending.push(Pending {
            frame,
            passes,
            buffer,
            mapped: Arc::new(AtomicBool::new(false)),
            map_requested: false,
        });
    }

    /// Asks for the submitted frames' buffers to be mapped when the GPU is done.
    pub fn submitted(&mut self) {
        for p in self.pending.iter_mut().filter(|p| !p.map_requested) {
            let mapped = p.mapped.clone();
            p.buffer.map_async(wgpu::MapMode::Read, .., move |result| {
                mapped.store(result.is_ok(), Ordering::Release);
            });
            p.map_requested = true;
        }
    }

    /// Pass times (ms) of every frame whose queries have been read back, oldest first.
    /// Callers poll the device first; this never waits.
    pub fn collect(&mut self) -> Vec<(u64, Vec<(&'static str, f64)>)> {
        let mut done = Vec::new();
        let mut still_pending = Vec::new();
        for p in self.pending.drain(..) {
            if !p.mapped.load(Ordering::Acquire) {
                still_pending.push(p);
                continue;
            }
            let times = match p.buffer.get_mapped_range(..) {
                Ok(range) => {
                    let stamps: &[u64] = bytemuck::cast_slice(&range);
                    p.passes
                        .iter()
                        .enumerate()
                        .map(|(i, &pass)| {
                            let ticks = stamps[2 * i + 1].saturating_sub(stamps[2 * i]);
                            (pass, ticks as f64 * self.period_ns * 1e-6)
                        })
                        .collect()
                }
                Err(e) => {
                    tracing::warn!("timestamps of frame {} unreadable: {e}", p.frame);
                    Vec::new()
                }
            };
            p.buffer.unmap();
            self.free.push(p.buffer);
            done.push((p.frame, times));
        }
        self.pending = still_pending;
        done
    }
}
