//! Group 0 of every scene pass: the frame uniform, the light buffer and its light lists,
//! the objects, the shadow uniform, the two atlases with their comparison sampler, and
//! the cookie arrays with their samplers, the lightmap array (sampled with the clamping
//! cookie sampler: one mip, bilinear), the light probes and the shadow mask array, and
//! the culled light lists: past the uniform's 512, every light in a texel table
//! (`texel_table`), and the list records and the lists' light indices in storage buffers;
//! then the environment's uniform, prefiltered cube, BRDF table and image (`environment`),
//! the shadow tints, and each pixel's scene depth for contact shadows.
//! A frame plan flows in and is uploaded; a bind group over this frame's buffers and
//! atlases flows out.

use crate::environment::GpuEnvironmentMaps;
use crate::error::RenderError;
use crate::frame_bindings::{FRAME_BINDINGS, FrameBinding, Resource};
use crate::gpu::{GpuFrame, GpuLight, GpuLightListEntry, GpuShadows};
use crate::graph::Targets;
use crate::passes::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS, SHADOW_TINTS};
use crate::plan::FramePlan;
use crate::scene::GpuScene;
use crate::shader_constants::{MAX_FRAME_LIGHTS, MAX_UNIFORM_LIGHTS};
use crate::texel_table::TexelTable;
use chiaro_scene::{Scene, Settings};

/// The frame's bind group 0: its layout and the buffers and samplers behind it, written
/// once per frame from the plan.
pub struct FrameData {
    /// Group 0's layout, which every scene pass's pipeline layout starts with.
    pub layout: wgpu::BindGroupLayout,
    frame: wgpu::Buffer,
    /// `MAX_UNIFORM_LIGHTS` lights, and `MAX_FRAME_LIGHTS` list entries.
    lights: wgpu::Buffer,
    light_list: wgpu::Buffer,
    shadows: wgpu::Buffer,
    /// Every light of the frame (seven records each, as `GpuLight` lays them out), where
    /// there are too many for the uniform, and the culled lists; grown when a frame needs
    /// more.
    all_lights: TexelTable,
    list_starts: GrowingBuffer,
    list_indices: GrowingBuffer,
    /// Each pixel's scene depth for contact shadows (`passes::contact_depth` writes it);
    /// one float where the frame has none.
    view_depths: GrowingBuffer,
    /// Each pixel's ambient occlusion as the shading reads it (`passes::ambient_occlusion`
    /// writes it, denoised), and the pass's noisy estimate before the denoise; one float
    /// where the frame has none.
    occlusion: GrowingBuffer,
    occlusion_raw: GrowingBuffer,
    occlusion_half: GrowingBuffer,
    /// The virtual shadow maps' page table (`plan::virtual_shadows`); one placeholder
    /// entry without them.
    page_table: GrowingBuffer,
    /// The marking pass's request bits, one per page-table entry (read back by the
    /// renderer; not bound in group 0).
    page_requests: GrowingBuffer,
    /// The frame's lights as uploaded, kept from frame to frame: thousands of lights
    /// written into fresh memory each frame cost more in page faults than in writing.
    gpu_lights: Vec<GpuLight>,
    shadow_sampler: wgpu::Sampler,
    /// Directional cookies tile; spot cookies stop at the cone's edge.
    cookie_repeat: wgpu::Sampler,
    cookie_clamp: wgpu::Sampler,
    /// The last frame bind group, with what it binds.
    last_bind_group: Option<(BoundResources, wgpu::BindGroup)>,
}

/// The resources a frame bind group binds that can change from frame to frame (the
/// uniform buffers and samplers are the frame data's own for good). The group is made
/// from these, and while they stay the same the last group is used again: making one
/// costs CPU time every frame (docs/performance.md).
#[derive(PartialEq)]
struct BoundResources {
    objects: wgpu::Buffer,
    directional_atlas: wgpu::TextureView,
    local_atlas: wgpu::TextureView,
    cookies_flat: wgpu::TextureView,
    cookies_cube: wgpu::TextureView,
    lightmaps: wgpu::TextureView,
    probes: wgpu::Buffer,
    shadow_masks: wgpu::TextureView,
    all_lights: wgpu::TextureView,
    list_starts: wgpu::Buffer,
    list_indices: wgpu::Buffer,
    environment_uniform: wgpu::Buffer,
    environment_specular: wgpu::TextureView,
    environment_brdf_table: wgpu::TextureView,
    shadow_tints: wgpu::TextureView,
    view_depths: wgpu::Buffer,
    occlusion: wgpu::Buffer,
    page_table: wgpu::Buffer,
}

/// The buffers of group 0 (and the request bits) that the virtual page marking pass
/// binds in a group of its own; the maps are in the shadow uniform.
#[derive(Clone, Copy)]
pub struct MarkingBuffers<'a> {
    /// The frame uniform.
    pub frame: &'a wgpu::Buffer,
    /// The shadow uniform.
    pub shadows: &'a wgpu::Buffer,
    /// One bit per page-table entry.
    pub page_requests: &'a wgpu::Buffer,
}

/// The ambient occlusion pass's buffers, one float per pixel, row by row.
#[derive(Clone, Copy)]
pub struct OcclusionBuffers<'a> {
    /// The half-resolution estimate, with each texel's point and normal (not bound in
    /// group 0).
    pub raw: &'a wgpu::Buffer,
    /// The half-resolution estimate denoised, with its slope: four floats a texel (not
    /// bound in group 0).
    pub half: &'a wgpu::Buffer,
    /// The AO per pixel, upsampled from `half`: group 0's `AMBIENT_OCCLUSION`.
    pub denoised: &'a wgpu::Buffer,
}

/// A storage buffer that is made again, twice as large, when a frame needs more.
struct GrowingBuffer {
    label: &'static str,
    buffer: wgpu::Buffer,
}

impl GrowingBuffer {
    fn new(device: &wgpu::Device, label: &'static str, size: u64) -> GrowingBuffer {
        GrowingBuffer { label, buffer: Self::make(device, label, size) }
    }

    fn make(device: &wgpu::Device, label: &'static str, size: u64) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    }

    /// Makes the buffer again, twice as large as `needed` rounded up (at most the largest
    /// binding), where it is smaller.
    fn reserve(&mut self, device: &wgpu::Device, needed: u64) {
        if needed > self.buffer.size() {
            // Doubling stops at the largest binding, so a size that fits stays bindable.
            let largest = device.limits().max_storage_buffer_binding_size.max(needed);
            self.buffer = Self::make(device, self.label, needed.next_power_of_two().min(largest));
        }
    }

    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        self.reserve(device, bytes.len() as u64);
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// A binding of `FRAME_BINDINGS` as the layout's entry.
fn layout_entry(binding: u32, b: &FrameBinding) -> wgpu::BindGroupLayoutEntry {
    use crate::frame_bindings::{Dimension, Kind, Stages};
    let texture =
        |sample_type, view_dimension| wgpu::BindingType::Texture { sample_type, view_dimension, multisampled: false };
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    let ty = match b.kind {
        Kind::Uniform => buffer(wgpu::BufferBindingType::Uniform),
        Kind::Storage => buffer(wgpu::BufferBindingType::Storage { read_only: true }),
        Kind::DepthTexture => texture(wgpu::TextureSampleType::Depth, wgpu::TextureViewDimension::D2),
        Kind::ComparisonSampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
        Kind::FilteringSampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        Kind::UintTexture => texture(wgpu::TextureSampleType::Uint, wgpu::TextureViewDimension::D2),
        Kind::FloatTexture(dimension) => texture(
            wgpu::TextureSampleType::Float { filterable: true },
            match dimension {
                Dimension::D2 => wgpu::TextureViewDimension::D2,
                Dimension::D2Array => wgpu::TextureViewDimension::D2Array,
                Dimension::Cube => wgpu::TextureViewDimension::Cube,
                Dimension::CubeArray => wgpu::TextureViewDimension::CubeArray,
            },
        ),
    };
    let visibility = match b.stages {
        Stages::Fragment => wgpu::ShaderStages::FRAGMENT,
        Stages::VertexFragment => wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
    };
    wgpu::BindGroupLayoutEntry { binding, visibility, ty, count: None }
}

/// Trilinear: the mip comes from the explicit gradients the shaders pass.
fn cookie_sampler(device: &wgpu::Device, address_mode: wgpu::AddressMode) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("cookie sampler"),
        address_mode_u: address_mode,
        address_mode_v: address_mode,
        address_mode_w: address_mode,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

impl FrameData {
    /// Makes the layout, the fixed-size buffers and the samplers (no upload yet).
    pub fn new(device: &wgpu::Device) -> FrameData {
        let entries: Vec<wgpu::BindGroupLayoutEntry> =
            FRAME_BINDINGS.iter().enumerate().map(|(i, b)| layout_entry(i as u32, b)).collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame layout"),
            entries: &entries,
        });
        let uniform_buffer = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        FrameData {
            layout,
            frame: uniform_buffer("frame uniform", size_of::<GpuFrame>() as u64),
            lights: uniform_buffer("frame lights", (size_of::<GpuLight>() * MAX_UNIFORM_LIGHTS as usize) as u64),
            light_list: uniform_buffer(
                "frame light lists",
                (size_of::<GpuLightListEntry>() * MAX_FRAME_LIGHTS as usize) as u64,
            ),
            shadows: uniform_buffer("shadows uniform", size_of::<GpuShadows>() as u64),
            all_lights: TexelTable::new(device, "frame lights"),
            list_starts: GrowingBuffer::new(device, "light list starts", 4 * 64),
            list_indices: GrowingBuffer::new(device, "light list indices", 4 * 1024),
            view_depths: GrowingBuffer::new(device, "view depths", 4),
            occlusion: GrowingBuffer::new(device, "ambient occlusion", 4),
            occlusion_raw: GrowingBuffer::new(device, "ambient occlusion before denoising", 4),
            occlusion_half: GrowingBuffer::new(device, "ambient occlusion at half resolution", 4),
            page_table: GrowingBuffer::new(device, "virtual page table", 4),
            page_requests: GrowingBuffer::new(device, "virtual page requests", 4),
            gpu_lights: Vec::new(),
            shadow_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison sampler"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            cookie_repeat: cookie_sampler(device, wgpu::AddressMode::Repeat),
            cookie_clamp: cookie_sampler(device, wgpu::AddressMode::ClampToEdge),
            last_bind_group: None,
        }
    }

    /// Writes the plan's frame uniform, lights, light lists, culled lists and shadow uniform
    /// to the GPU; the light table and the culled-list buffers grow when a frame needs more.
    /// Errors where the lights outgrow the device's largest texture.
    pub fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        plan: &FramePlan,
        scene: &Scene,
        settings: &Settings,
    ) -> Result<(), RenderError> {
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&plan.gpu_frame(settings)));
        let culled = &plan.culled.lists;
        // Every light only where culled lists read them from their table; else the
        // uniform's.
        let in_table = !culled.is_empty() && plan.lights_in_table();
        let count = if in_table { plan.lights.len() } else { MAX_UNIFORM_LIGHTS as usize };
        plan.write_gpu_lights(scene, count, &mut self.gpu_lights);
        if !culled.is_empty() {
            if in_table {
                self.all_lights.write(device, queue, bytemuck::cast_slice(&self.gpu_lights))?;
            }
            self.list_starts.write(device, queue, bytemuck::cast_slice(&culled.starts));
            self.list_indices.write(device, queue, bytemuck::cast_slice(&culled.indices));
        }
        let lights = &self.gpu_lights[..self.gpu_lights.len().min(MAX_UNIFORM_LIGHTS as usize)];
        let list: Vec<GpuLightListEntry> =
            plan.lists.concatenated().into_iter().map(|light| GpuLightListEntry { light, _pad: [0; 3] }).collect();
        debug_assert!(list.len() <= MAX_FRAME_LIGHTS as usize, "the plan keeps to the light limits");
        if !lights.is_empty() {
            queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(lights));
            queue.write_buffer(&self.light_list, 0, bytemuck::cast_slice(&list));
        }
        queue.write_buffer(&self.shadows, 0, bytemuck::bytes_of(&plan.shadows.gpu));
        if plan.copies_scene_depth() {
            let (width, height) = (plan.view.width, plan.view.height);
            let bytes = width as u64 * height as u64 * size_of::<f32>() as u64;
            // The AO estimate keeps two vec4s per 2x2 pixels: 8 bytes a pixel.
            let texels = width.div_ceil(2) as u64 * height.div_ceil(2) as u64;
            let largest_needed = if plan.features.ambient_occlusion { bytes.max(texels * 32) } else { bytes };
            let largest = device.limits().max_storage_buffer_binding_size;
            if largest_needed > largest {
                let reason = format!(
                    "contact shadows ([shadows] contact), ambient occlusion and virtual shadow maps' marking \
                     keep each pixel's depth (and AO's estimate) in one storage buffer of {largest_needed} \
                     bytes, more than the device binds ({largest}); render smaller or turn them off"
                );
                return Err(RenderError::OutputSize { width, height, reason });
            }
            self.view_depths.reserve(device, bytes);
            if plan.features.ambient_occlusion {
                self.occlusion.reserve(device, bytes);
                // Two vec4s per texel of the half-resolution estimate.
                self.occlusion_raw.reserve(device, texels * 2 * 16);
                self.occlusion_half.reserve(device, texels * 16);
            }
        }
        let virtual_maps = &plan.shadows.virtual_maps;
        if virtual_maps.is_active() {
            self.page_table.write(device, queue, bytemuck::cast_slice(&virtual_maps.page_table));
            if plan.marks_pages {
                self.page_requests.reserve(device, virtual_maps.request_bytes());
            }
        }
        Ok(())
    }

    /// The buffers the virtual page marking pass binds: the frame and shadow uniforms,
    /// the maps, and the request bits it sets.
    pub fn marking_buffers(&self) -> MarkingBuffers<'_> {
        MarkingBuffers { frame: &self.frame, shadows: &self.shadows, page_requests: &self.page_requests.buffer }
    }

    /// The buffer the contact depth pass writes each pixel's scene depth into.
    pub fn view_depths(&self) -> &wgpu::Buffer {
        &self.view_depths.buffer
    }

    /// The buffers the ambient occlusion pass writes: the noisy estimate, then the
    /// denoised AO that group 0 binds.
    pub fn occlusion_buffers(&self) -> OcclusionBuffers<'_> {
        OcclusionBuffers {
            raw: &self.occlusion_raw.buffer,
            half: &self.occlusion_half.buffer,
            denoised: &self.occlusion.buffer,
        }
    }

    /// The bind group over this frame's buffers, the scene's objects, cookies and bakes, and
    /// the shadow atlases in `targets`.
    pub fn bind_group(
        &mut self,
        device: &wgpu::Device,
        scene: &GpuScene,
        environment: &GpuEnvironmentMaps,
        targets: &Targets,
    ) -> wgpu::BindGroup {
        let bound = BoundResources {
            objects: scene.objects.clone(),
            directional_atlas: targets.view(DIRECTIONAL_ATLAS).clone(),
            local_atlas: targets.view(LOCAL_ATLAS).clone(),
            cookies_flat: scene.cookies.flat.clone(),
            cookies_cube: scene.cookies.cube.clone(),
            lightmaps: scene.baked.lightmaps.clone(),
            probes: scene.baked.probes.clone(),
            shadow_masks: scene.baked.shadow_masks.clone(),
            all_lights: self.all_lights.view().clone(),
            list_starts: self.list_starts.buffer.clone(),
            list_indices: self.list_indices.buffer.clone(),
            environment_uniform: environment.uniform.clone(),
            environment_specular: environment.specular.clone(),
            environment_brdf_table: environment.brdf_table.clone(),
            shadow_tints: targets.view(SHADOW_TINTS).clone(),
            view_depths: self.view_depths.buffer.clone(),
            occlusion: self.occlusion.buffer.clone(),
            page_table: self.page_table.buffer.clone(),
        };
        if let Some((last, group)) = &self.last_bind_group
            && *last == bound
        {
            return group.clone();
        }
        let group = self.make_bind_group(device, &bound);
        self.last_bind_group = Some((bound, group.clone()));
        group
    }

    /// The frame bind group: the frame data's own buffers and samplers, and `bound`.
    fn make_bind_group(&self, device: &wgpu::Device, bound: &BoundResources) -> wgpu::BindGroup {
        let view = |view| wgpu::BindingResource::TextureView(view);
        let sampler = |sampler| wgpu::BindingResource::Sampler(sampler);
        let entries: Vec<wgpu::BindGroupEntry> = FRAME_BINDINGS
            .iter()
            .enumerate()
            .map(|(binding, b)| {
                let resource = match b.resource {
                    Resource::Frame => self.frame.as_entire_binding(),
                    Resource::Lights => self.lights.as_entire_binding(),
                    Resource::LightList => self.light_list.as_entire_binding(),
                    Resource::Objects => bound.objects.as_entire_binding(),
                    Resource::Shadows => self.shadows.as_entire_binding(),
                    Resource::DirectionalShadowAtlas => view(&bound.directional_atlas),
                    Resource::ShadowSampler => sampler(&self.shadow_sampler),
                    Resource::LocalShadowAtlas => view(&bound.local_atlas),
                    Resource::Cookies2d => view(&bound.cookies_flat),
                    Resource::CookiesCube => view(&bound.cookies_cube),
                    Resource::CookieRepeat => sampler(&self.cookie_repeat),
                    Resource::CookieClamp => sampler(&self.cookie_clamp),
                    Resource::Lightmaps => view(&bound.lightmaps),
                    Resource::ProbeGrid => bound.probes.as_entire_binding(),
                    Resource::ShadowMasks => view(&bound.shadow_masks),
                    Resource::LightTable => view(&bound.all_lights),
                    Resource::ListStarts => bound.list_starts.as_entire_binding(),
                    Resource::ListIndices => bound.list_indices.as_entire_binding(),
                    Resource::Environment => bound.environment_uniform.as_entire_binding(),
                    Resource::EnvironmentSpecular => view(&bound.environment_specular),
                    Resource::EnvironmentBrdf => view(&bound.environment_brdf_table),
                    Resource::ShadowTints => view(&bound.shadow_tints),
                    Resource::ViewDepths => bound.view_depths.as_entire_binding(),
                    Resource::AmbientOcclusion => bound.occlusion.as_entire_binding(),
                    Resource::VirtualPageTable => bound.page_table.as_entire_binding(),
                };
                wgpu::BindGroupEntry { binding: binding as u32, resource }
            })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame bind group"),
            layout: &self.layout,
            entries: &entries,
        })
    }
}
