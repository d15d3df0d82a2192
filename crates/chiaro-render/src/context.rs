//! Instance, adapter, device and queue, headless. Prefers a real GPU, takes a software
//! one (lavapipe) when that is all there is, and enables timestamp queries where offered.

use crate::error::RenderError;
use std::sync::{Arc, Mutex};

/// The device and queue every renderer draws with, and what the adapter offers (timestamps,
/// depth format, MSAA counts, surface formats).
pub struct GpuContext {
    /// The wgpu device all GPU objects are made on.
    pub device: wgpu::Device,
    /// The queue uploads and command buffers go to.
    pub queue: wgpu::Queue,
    /// The adapter's name, driver and backend, as reports and errors print them.
    pub adapter_info: wgpu::AdapterInfo,
    /// Whether timestamp queries were enabled, so that passes report GPU times.
    pub has_timestamps: bool,
    /// The scene depth target's format: depth with stencil.
    pub depth_format: wgpu::TextureFormat,
    /// Samples per pixel the forward path's HDR and depth targets can have (MSAA).
    pub msaa_sample_counts: Vec<u32>,
    /// Formats the surface it was opened for can take (none without one).
    pub surface_formats: Vec<wgpu::TextureFormat>,
    /// What the surface's textures can be used for (empty without one).
    pub surface_usages: wgpu::TextureUsages,
    /// Validation errors the device reported outside an error scope, oldest first.
    errors: Arc<Mutex<Vec<String>>>,
}

impl GpuContext {
    /// Opens the best adapter of the primary backends (Vulkan, Metal, DX12). `WGPU_BACKEND`
    /// and `WGPU_ADAPTER_NAME` choose otherwise, as wgpu documents.
    pub fn new() -> Result<GpuContext, RenderError> {
        Ok(Self::open(None)?.0)
    }

    /// Opens an adapter that can present to `target` (a window), with the surface for it.
    pub fn for_surface(
        target: impl Into<wgpu::SurfaceTarget<'static>>,
    ) -> Result<(GpuContext, wgpu::Surface<'static>), RenderError> {
        let (ctx, surface) = Self::open(Some(target.into()))?;
        Ok((ctx, surface.expect("made for the target")))
    }

    /// Every adapter of the primary backends (or those `WGPU_BACKEND` names), in wgpu's
    /// order, for a caller that chooses one itself (`with_adapter`).
    pub fn adapters() -> Vec<wgpu::Adapter> {
        let instance = Self::instance();
        let backends = instance_backends();
        pollster::block_on(instance.enumerate_adapters(backends))
    }

    /// Opens `adapter` (one of `adapters()`) as `new` opens the best one.
    pub fn with_adapter(adapter: &wgpu::Adapter) -> Result<GpuContext, RenderError> {
        Self::open_adapter(adapter)
    }

    fn instance() -> wgpu::Instance {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = instance_backends();
        wgpu::Instance::new(desc)
    }

    /// Opens an adapter that can present to `target` (a canvas), with the surface for it,
    /// without blocking: the browser build's way, where nothing may block the page.
    pub async fn for_surface_async(
        target: impl Into<wgpu::SurfaceTarget<'static>>,
    ) -> Result<(GpuContext, wgpu::Surface<'static>), RenderError> {
        let (ctx, surface) = Self::open_async(Some(target.into())).await?;
        Ok((ctx, surface.expect("made for the target")))
    }

    fn open(
        target: Option<wgpu::SurfaceTarget<'static>>,
    ) -> Result<(GpuContext, Option<wgpu::Surface<'static>>), RenderError> {
        pollster::block_on(Self::open_async(target))
    }

    async fn open_async(
        target: Option<wgpu::SurfaceTarget<'static>>,
    ) -> Result<(GpuContext, Option<wgpu::Surface<'static>>), RenderError> {
        let instance = Self::instance();
        let surface = match target {
            Some(t) => Some(instance.create_surface(t).map_err(|e| RenderError::Device(format!("no surface: {e}")))?),
            None => None,
        };
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: surface.as_ref(),
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let mut ctx = Self::open_adapter_async(&adapter).await?;
        if let Some(s) = &surface {
            let capabilities = s.get_capabilities(&adapter);
            ctx.surface_formats = capabilities.formats;
            ctx.surface_usages = capabilities.usages;
        }
        Ok((ctx, surface))
    }

    fn open_adapter(adapter: &wgpu::Adapter) -> Result<GpuContext, RenderError> {
        pollster::block_on(Self::open_adapter_async(adapter))
    }

    async fn open_adapter_async(adapter: &wgpu::Adapter) -> Result<GpuContext, RenderError> {
        let has_timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = wgpu::Features::empty();
        if has_timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        // Depth clamping for shadow casters in front of the near plane; without it the
        // caster shader clamps depth itself.
        if adapter.features().contains(wgpu::Features::DEPTH_CLIP_CONTROL) {
            required_features |= wgpu::Features::DEPTH_CLIP_CONTROL;
        }
        // A 32-bit float depth keeps reverse-Z precise; the stencil beside it is for the
        // deferred light volumes. Where the pair is missing, 24-bit depth carries stencil.
        // 2 and 8 MSAA samples need the adapter's format features.
        // BC7 textures: KTX2 (Basis Universal) images transcode to them where the adapter
        // samples them, a quarter of RGBA8's memory.
        // Shadow casters draw each tile's batches with multi-draw indirect, whose draws
        // start at their object's instance.
        for optional in [
            wgpu::Features::INDIRECT_FIRST_INSTANCE,
            wgpu::Features::DEPTH32FLOAT_STENCIL8,
            wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES,
            wgpu::Features::TEXTURE_COMPRESSION_BC,
        ] {
            if adapter.features().contains(optional) {
                required_features |= optional;
            }
        }
        let adapter_limits = adapter.limits();
        let required_limits = wgpu::Limits {
            max_texture_dimension_2d: adapter_limits.max_texture_dimension_2d,
            max_buffer_size: adapter_limits.max_buffer_size,
            max_storage_buffer_binding_size: adapter_limits.max_storage_buffer_binding_size,
            // The shadow AOVs take one array layer per light.
            max_texture_array_layers: adapter_limits.max_texture_array_layers,
            // Transmissive materials' shader binds 17 (the opaque image beside the
            // frame's and the material's); without them it draws them unrefracted.
            max_sampled_textures_per_shader_stage: adapter_limits.max_sampled_textures_per_shader_stage.min(24),
            ..wgpu::Limits::default()
        };
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("chiaro device"),
                required_features,
                required_limits,
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(GpuContext::from_device(adapter, device, queue))
    }

    /// Renders with a device the caller made (an engine's own), on `adapter`. What the
    /// renderer uses follows the features the device was made with: timestamps with
    /// `TIMESTAMP_QUERY`, 32-bit depth with `DEPTH32FLOAT_STENCIL8` (else 24-bit), depth
    /// clamping for casters with `DEPTH_CLIP_CONTROL` (else in the shader), 2 and 8 MSAA
    /// samples with `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES` (else 1 and 4).
    pub fn from_device(adapter: &wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> GpuContext {
        let features = device.features();
        let depth_format = if features.contains(wgpu::Features::DEPTH32FLOAT_STENCIL8) {
            wgpu::TextureFormat::Depth32FloatStencil8
        } else {
            wgpu::TextureFormat::Depth24PlusStencil8
        };
        // WebGPU guarantees 1 and 4 samples; 2 and 8 need the adapter's format features.
        let msaa_sample_counts: Vec<u32> =
            if features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
                let hdr = adapter.get_texture_format_features(crate::passes::targets::HDR_FORMAT).flags;
                let depth = adapter.get_texture_format_features(depth_format).flags;
                [1, 2, 4, 8]
                    .into_iter()
                    .filter(|&n| n == 1 || (hdr.sample_count_supported(n) && depth.sample_count_supported(n)))
                    .collect()
            } else {
                vec![1, 4]
            };
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            tracing::error!("wgpu: {e}");
            sink.lock().expect("error sink").push(e.to_string());
        }));
        let adapter_info = adapter.get_info();
        tracing::info!(
            adapter = %adapter_info.name,
            backend = ?adapter_info.backend,
            device_type = ?adapter_info.device_type,
            "GPU ready"
        );
        GpuContext {
            has_timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            device,
            queue,
            adapter_info,
            depth_format,
            msaa_sample_counts,
            surface_formats: Vec::new(),
            surface_usages: wgpu::TextureUsages::empty(),
            errors,
        }
    }

    /// Whether the forward path's targets can have `samples` samples per pixel here;
    /// the error says what the device offers.
    pub fn check_msaa(&self, samples: u32) -> Result<(), String> {
        if self.msaa_sample_counts.contains(&samples) {
            return Ok(());
        }
        let counts: Vec<String> = self.msaa_sample_counts.iter().map(u32::to_string).collect();
        Err(format!("this device ({}) renders {} samples per pixel", self.adapter_info.name, counts.join(" or ")))
    }

    /// Returns the first GPU error reported since the last call, if any.
    pub fn take_error(&self) -> Result<(), RenderError> {
        let mut errors = self.errors.lock().expect("error sink");
        if errors.is_empty() {
            Ok(())
        } else {
            let first = errors.remove(0);
            errors.clear();
            Err(RenderError::Gpu(first))
        }
    }

    /// The largest 2D texture side the device takes, in texels: the output size's bound.
    pub fn max_texture_size(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| RenderError::Gpu(e.to_string()))?;
        Ok(())
    }
}

/// The backends to look on: `WGPU_BACKEND`'s when set, else the primary ones (Vulkan,
/// Metal, DX12).
fn instance_backends() -> wgpu::Backends {
    match std::env::var_os("WGPU_BACKEND") {
        Some(_) => wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY),
        None => wgpu::Backends::PRIMARY,
    }
}
