//! The compute passes that make an environment's maps on the device, once per change:
//! the equirectangular image into a radiance cube and its mips, the GGX-prefiltered
//! cube, and (once per renderer) the split-sum BRDF table. Entry points in
//! `shaders/environment_bake.wesl`.

use super::{GpuEnvironmentMaps, device_sized, half_texels, map_summary, uniform_buffer};
use crate::gpu::GpuEnvironmentBake;
use crate::shaders;
use chiaro_scene::environment::EnvironmentMap;
use wgpu::util::DeviceExt;

/// The maps' texel format: filterable and writable from compute shaders everywhere.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The radiance cube's largest face side (its mips feed the prefilter's wide lobes).
const MAX_RADIANCE_SIZE: u32 = 256;
/// The prefiltered cube's first face side, and its mip count: roughness 0, 0.2, .. 1
/// on faces of 128 down to 4 texels.
const SPECULAR_SIZE: u32 = 128;
const SPECULAR_MIPS: u32 = 6;
/// GGX samples per prefiltered texel (each reads the mip its share of the lobe covers).
const PREFILTER_SAMPLES: u32 = 128;
/// The BRDF table's side and samples per entry.
const TABLE_SIZE: u32 = 64;
// The LTC layer shares the split-sum table's grid, so one lookup serves both.
const _: () = assert!(TABLE_SIZE as usize == chiaro_math::ltc::LTC_TABLE_SIZE);
const TABLE_SAMPLES: u32 = 512;
const WORKGROUP: u32 = 8;

/// The environment's compute pipelines, its sampler and the BRDF table they made.
pub struct EnvironmentBaker {
    cube_from_equirect: wgpu::ComputePipeline,
    downsample: wgpu::ComputePipeline,
    prefilter: wgpu::ComputePipeline,
    sampler: wgpu::Sampler,
    table: wgpu::Texture,
}

pub fn cube_texture(
    device: &wgpu::Device,
    label: &str,
    size: u32,
    mips: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 6 },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage,
        view_formats: &[],
    })
}

pub fn cube_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    })
}

/// One mip of a cube as the 2D array of its six faces.
fn faces_view(texture: &wgpu::Texture, mip: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_mip_level: mip,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

/// The BRDF table's layers: the split-sum terms and sheen albedo, then the LTC matrices.
const TABLE_LAYERS: u32 = 2;
use crate::shader_constants::LTC_LAYER;

fn table_texture(device: &wgpu::Device, size: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("environment brdf table"),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: TABLE_LAYERS },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// The BRDF table as the shaders sample it: both layers.
pub fn table_view(table: &wgpu::Texture) -> wgpu::TextureView {
    table.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// The LTC layer's texels: the four entries of each cell's inverse matrix, as half floats.
fn ltc_texels() -> Vec<u16> {
    chiaro_math::ltc::table().iter().flat_map(|cell| cell.inverse.map(|v| half::f16::from_f32(v).to_bits())).collect()
}

/// The equirectangular image as a half-float texture, radiance divided by `scale`.
pub fn upload_equirect(device: &wgpu::Device, queue: &wgpu::Queue, map: &EnvironmentMap, scale: f32) -> wgpu::Texture {
    device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("environment image"),
            size: wgpu::Extent3d { width: map.width, height: map.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&half_texels(map, scale)),
    )
}

/// The largest power of two no larger than `n` (n >= 1).
fn power_of_two_at_most(n: u32) -> u32 {
    1 << (31 - n.max(1).leading_zeros())
}

/// Makes the BRDF table (submitted at once): the split-sum terms in x and y, the Charlie
/// sheen albedo in z. Every renderer has it, environment or not: punctual lights' energy
/// compensation and sheen read it too.
pub fn bake_brdf_table(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::Texture {
    let module = shaders::module(device, "brdf table", crate::wgsl!("environment_bake"));
    let table_pipeline = crate::shaders::compute_pipeline(device, &module, "brdf_table");
    let table = table_texture(device, TABLE_SIZE);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("brdf table") });
    let params = GpuEnvironmentBake { size: TABLE_SIZE, source_size: 0, roughness: 0.0, samples: TABLE_SAMPLES };
    let view = table.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: 0,
        array_layer_count: Some(1),
        ..Default::default()
    });
    dispatch(device, &mut encoder, &table_pipeline, params, 1, &[(6, wgpu::BindingResource::TextureView(&view))]);
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &table,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z: LTC_LAYER },
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(&ltc_texels()),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(TABLE_SIZE * 8),
            rows_per_image: Some(TABLE_SIZE),
        },
        wgpu::Extent3d { width: TABLE_SIZE, height: TABLE_SIZE, depth_or_array_layers: 1 },
    );
    queue.submit([encoder.finish()]);
    table
}

/// Records one dispatch of `pipeline` over `params.size`² texels x `layers`, with the
/// parameters at binding 0 and `resources` at their bindings.
fn dispatch(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    params: GpuEnvironmentBake,
    layers: u32,
    resources: &[(u32, wgpu::BindingResource<'_>)],
) {
    let params_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("environment bake parameters"),
        contents: bytemuck::bytes_of(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: params_buffer.as_entire_binding() }];
    entries.extend(
        resources
            .iter()
            .map(|(binding, resource)| wgpu::BindGroupEntry { binding: *binding, resource: resource.clone() }),
    );
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("environment bake"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &bind_group, &[]);
    let groups = params.size.div_ceil(WORKGROUP);
    pass.dispatch_workgroups(groups, groups, layers);
}

impl EnvironmentBaker {
    /// Makes the pipelines; the maps it makes carry `table` (`bake_brdf_table`).
    pub fn new(device: &wgpu::Device, table: wgpu::Texture) -> EnvironmentBaker {
        let module = shaders::module(device, "environment bake", crate::wgsl!("environment_bake"));
        EnvironmentBaker {
            cube_from_equirect: crate::shaders::compute_pipeline(device, &module, "cube_from_equirect"),
            downsample: crate::shaders::compute_pipeline(device, &module, "downsample"),
            prefilter: crate::shaders::compute_pipeline(device, &module, "prefilter"),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("environment bake sampler"),
                address_mode_u: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
            table,
        }
    }

    /// Uploads `map` and records and submits the passes that make its cube maps.
    pub fn make(&self, device: &wgpu::Device, queue: &wgpu::Queue, map: &EnvironmentMap) -> GpuEnvironmentMaps {
        let (radiance_sh, scale) = map_summary(map);
        let image_texture = upload_equirect(device, queue, &device_sized(map), scale);
        let image = image_texture.create_view(&Default::default());
        let radiance_size = power_of_two_at_most(map.width / 4).clamp(SPECULAR_SIZE, MAX_RADIANCE_SIZE);
        let radiance_mips = radiance_size.trailing_zeros() + 1;
        let storage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING;
        let radiance = cube_texture(device, "environment radiance cube", radiance_size, radiance_mips, storage);
        let specular = cube_texture(device, "environment specular cube", SPECULAR_SIZE, SPECULAR_MIPS, storage);

        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("environment") });
        let sampler = wgpu::BindingResource::Sampler(&self.sampler);
        let params =
            |size, roughness, samples| GpuEnvironmentBake { size, source_size: radiance_size, roughness, samples };
        let out = faces_view(&radiance, 0);
        dispatch(
            device,
            &mut encoder,
            &self.cube_from_equirect,
            params(radiance_size, 0.0, 0),
            6,
            &[(1, wgpu::BindingResource::TextureView(&image)), (2, sampler.clone()), (5, view_resource(&out))],
        );
        for mip in 1..radiance_mips {
            let (finer, out) = (faces_view(&radiance, mip - 1), faces_view(&radiance, mip));
            dispatch(
                device,
                &mut encoder,
                &self.downsample,
                params(radiance_size >> mip, 0.0, 0),
                6,
                &[(3, view_resource(&finer)), (5, view_resource(&out))],
            );
        }
        let radiance_cube = cube_view(&radiance);
        for mip in 0..SPECULAR_MIPS {
            let roughness = mip as f32 / (SPECULAR_MIPS - 1) as f32;
            let out = faces_view(&specular, mip);
            dispatch(
                device,
                &mut encoder,
                &self.prefilter,
                params(SPECULAR_SIZE >> mip, roughness, PREFILTER_SAMPLES),
                6,
                &[(2, sampler.clone()), (4, view_resource(&radiance_cube)), (5, view_resource(&out))],
            );
        }
        queue.submit([encoder.finish()]);
        GpuEnvironmentMaps {
            uniform: uniform_buffer(device),
            specular: cube_view(&specular),
            brdf_table: table_view(&self.table),
            image,
            radiance_sh,
            specular_last_mip: (SPECULAR_MIPS - 1) as f32,
            storage_scale: scale,
        }
    }
}

fn view_resource(view: &wgpu::TextureView) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::TextureView(view)
}
