//! The GPU mirror of a `Scene`: one vertex and one index buffer for all geometry, an
//! object buffer of transforms, a bind group per material, and the draw list.

use crate::gpu_types::{GpuMaterial, GpuObject, GpuTextureTransform, GpuVertex};
use crate::textures::{SamplerCache, solid, upload_image};
use chiaro_math::Aabb;
use chiaro_scene::{AlphaMode, CastShadows, Material, Scene, TextureRef};
use glam::{Vec3, Vec4};
use wgpu::util::DeviceExt;

/// One primitive of one mesh instance.
#[derive(Clone, Debug)]
pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    pub base_vertex: i32,
    /// Index into the object buffer, passed as the draw's first instance.
    pub object: u32,
    /// Index into `GpuScene::materials` (the last one is the glTF default material).
    pub material: usize,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
    /// The instance's transform mirrors (negative determinant), which flips the winding.
    pub mirrored: bool,
    /// World-space centre, for sorting transparent draws back to front.
    pub center_ws: Vec3,
    /// World-space bounds, for culling casters per shadow tile.
    pub bounds_ws: Aabb,
    pub cast_shadows: CastShadows,
}

impl Draw {
    /// Drawn by the camera (shadows-only casters are not).
    pub fn visible(&self) -> bool {
        self.cast_shadows != CastShadows::ShadowsOnly
    }

    /// Alpha-blended surfaces cast no shadows (the reference skips them too).
    pub fn casts_shadows(&self) -> bool {
        self.cast_shadows != CastShadows::Off && self.alpha_mode != AlphaMode::Blend
    }
}

pub struct GpuScene {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub objects: wgpu::Buffer,
    pub materials: Vec<wgpu::BindGroup>,
    pub draws: Vec<Draw>,
}

pub fn material_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let mut entries = vec![wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }];
    for texture in 0..5u32 {
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: 1 + texture * 2,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        });
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: 2 + texture * 2,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        });
    }
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("material layout"),
        entries: &entries,
    })
}

fn texture_transform(t: Option<&TextureRef>) -> GpuTextureTransform {
    let (m, set) = match t {
        Some(t) => (t.transform.matrix(), t.tex_coord.min(1) as f32),
        None => (chiaro_scene::UvTransform::default().matrix(), 0.0),
    };
    GpuTextureTransform {
        linear: Vec4::new(m[0].x, m[0].y, m[1].x, m[1].y),
        offset_uv_set: Vec4::new(m[2].x, m[2].y, set, 0.0),
    }
}

pub fn gpu_material(m: &Material) -> GpuMaterial {
    GpuMaterial {
        base_color: m.base_color,
        emissive: m.emissive,
        metallic: m.metallic,
        roughness: m.roughness,
        normal_scale: m.normal_scale,
        occlusion_strength: m.occlusion_strength,
        alpha_cutoff: m.alpha_cutoff,
        alpha_mode: match m.alpha_mode {
            AlphaMode::Opaque => 0,
            AlphaMode::Mask => 1,
            AlphaMode::Blend => 2,
        },
        double_sided: m.double_sided as u32,
        flags: m.normal_texture.is_some() as u32,
        _pad: 0,
        base_color_uv: texture_transform(m.base_color_texture.as_ref()),
        metallic_roughness_uv: texture_transform(m.metallic_roughness_texture.as_ref()),
        normal_uv: texture_transform(m.normal_texture.as_ref()),
        occlusion_uv: texture_transform(m.occlusion_texture.as_ref()),
        emissive_uv: texture_transform(m.emissive_texture.as_ref()),
    }
}

impl GpuScene {
    pub fn upload(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layout: &wgpu::BindGroupLayout,
        scene: &Scene,
    ) -> GpuScene {
        let _span = tracing::info_span!("upload scene").entered();
        // Geometry: every mesh primitive once, instances refer to it.
        let mut vertices: Vec<GpuVertex> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut ranges: Vec<Vec<(u32, u32, i32)>> = Vec::new();
        for mesh in &scene.meshes {
            let mut mesh_ranges = Vec::new();
            for p in &mesh.primitives {
                let base_vertex = vertices.len() as i32;
                let first_index = indices.len() as u32;
                for i in 0..p.positions.len() {
                    vertices.push(GpuVertex {
                        position: p.positions[i].to_array(),
                        normal: p.normals.get(i).copied().unwrap_or(Vec3::Y).to_array(),
                        tangent: p.tangents.get(i).copied().unwrap_or(Vec4::new(1.0, 0.0, 0.0, 1.0)).to_array(),
                        uv0: p.uv0.get(i).copied().unwrap_or_default().to_array(),
                        uv1: p.uv1.get(i).copied().unwrap_or_default().to_array(),
                    });
                }
                indices.extend_from_slice(&p.indices);
                mesh_ranges.push((first_index, p.indices.len() as u32, base_vertex));
            }
            ranges.push(mesh_ranges);
        }
        // wgpu refuses empty buffers' bindings; keep at least one element.
        if vertices.is_empty() {
            vertices.push(GpuVertex::zeroed());
        }
        if indices.is_empty() {
            indices.push(0);
        }

        let default_material = scene.materials.len();
        let mut objects = Vec::new();
        let mut draws = Vec::new();
        for inst in &scene.instances {
            let object = objects.len() as u32;
            objects.push(GpuObject::new(inst.world_from_local, inst.receive_shadows));
            for (p, &(first_index, index_count, base_vertex)) in
                scene.meshes[inst.mesh].primitives.iter().zip(&ranges[inst.mesh])
            {
                if index_count == 0 {
                    continue;
                }
                let material = p.material.filter(|&m| m < scene.materials.len()).unwrap_or(default_material);
                let m = scene.materials.get(material).cloned().unwrap_or_default();
                draws.push(Draw {
                    first_index,
                    index_count,
                    base_vertex,
                    object,
                    material,
                    alpha_mode: m.alpha_mode,
                    double_sided: m.double_sided,
                    mirrored: inst.world_from_local.determinant() < 0.0,
                    center_ws: inst.world_from_local.transform_point3(p.bounds.center()),
                    bounds_ws: p.bounds.transformed(&inst.world_from_local),
                    cast_shadows: inst.cast_shadows,
                });
            }
        }
        if objects.is_empty() {
            objects.push(GpuObject::new(glam::Mat4::IDENTITY, true));
        }

        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let objects = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene objects"),
            contents: bytemuck::cast_slice(&objects),
            usage: wgpu::BufferUsages::STORAGE,
        });

        // Textures: each image once; white, flat-normal and black stand-ins.
        let images: Vec<wgpu::TextureView> = scene.images.iter().map(|i| upload_image(device, queue, i)).collect();
        let white = solid(device, queue, "white", [255, 255, 255, 255]);
        let flat_normal = solid(device, queue, "flat normal", [128, 128, 255, 255]);
        let mut samplers = SamplerCache::default();
        let default = Material::default();
        let materials = scene
            .materials
            .iter()
            .chain(std::iter::once(&default))
            .map(|m| {
                let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&m.name),
                    contents: bytemuck::bytes_of(&gpu_material(m)),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let slots = [
                    (m.base_color_texture, &white),
                    (m.metallic_roughness_texture, &white),
                    (m.normal_texture, &flat_normal),
                    (m.occlusion_texture, &white),
                    (m.emissive_texture, &white),
                ];
                let resolved: Vec<(&wgpu::TextureView, wgpu::Sampler)> = slots
                    .iter()
                    .map(|(t, fallback)| match t.filter(|t| t.image < images.len()) {
                        Some(t) => (&images[t.image], samplers.get(device, &t.sampler)),
                        None => (*fallback, samplers.get(device, &Default::default())),
                    })
                    .collect();
                let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() }];
                for (k, (view, sampler)) in resolved.iter().enumerate() {
                    entries.push(wgpu::BindGroupEntry {
                        binding: 1 + 2 * k as u32,
                        resource: wgpu::BindingResource::TextureView(view),
                    });
                    entries.push(wgpu::BindGroupEntry {
                        binding: 2 + 2 * k as u32,
                        resource: wgpu::BindingResource::Sampler(sampler),
                    });
                }
                device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(&m.name), layout, entries: &entries })
            })
            .collect();
        GpuScene { vertices, indices, objects, materials, draws }
    }
}

use bytemuck::Zeroable;
