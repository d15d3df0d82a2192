//! The GPU mirror of a `Scene`: one vertex and one index buffer for all geometry (laid
//! out by `plan::draws::GeometryLayout`), an object buffer of transforms, a bind group per
//! material, and the draw list the frame plans index.

pub mod baked;
pub mod cookies;
pub mod layer_textures;
mod textures;

use crate::gpu::{GpuLayerTextureSlot, GpuMaterial, GpuMaterialLayers, GpuObject, GpuTextureTransform, GpuVertex};
use crate::plan::draws::{Draw, GeometryLayout, scene_draws};
use crate::shader_constants::{
    MATERIAL_ALPHA_BLEND, MATERIAL_ALPHA_MASK, MATERIAL_ALPHA_OPAQUE, MATERIAL_FLAG_NORMAL_TEXTURE, MATERIAL_FLAG_UNLIT,
};
use baked::BakedTextures;
use bytemuck::Zeroable;
use chiaro_scene::{AlphaMode, LayerTexture, Material, MaterialLayers, Scene, TextureRef};
use cookies::CookieTextures;
use glam::{Vec2, Vec3, Vec4};
use layer_textures::{LayerPlan, layer_plan, upload_layers};
use textures::{SamplerCache, solid, upload_scene_image};
use wgpu::util::DeviceExt;

/// A scene on the GPU: geometry, objects, materials, draws, cookies and bakes.
pub struct GpuScene {
    /// Every primitive's vertices, as `GeometryLayout` places them.
    pub vertices: wgpu::Buffer,
    /// Every primitive's indices (u32).
    pub indices: wgpu::Buffer,
    /// One `GpuObject` per mesh instance.
    pub objects: wgpu::Buffer,
    /// One bind group (group 1) per material, then the glTF default material.
    pub materials: Vec<wgpu::BindGroup>,
    /// Every primitive of every instance, as the plans index them.
    pub draws: Vec<Draw>,
    /// The lights' cookies, bound in group 0.
    pub cookies: CookieTextures,
    /// Lightmaps and light probes, bound in group 0.
    pub baked: BakedTextures,
    /// How many of the scene's images went to the GPU as BC7 (KTX2 images transcoded to
    /// it on a device with BC textures); the rest are RGBA8.
    pub bc7_images: usize,
}

/// Group 1 of the mesh passes: one material's uniform, its textures and their samplers.
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
    // The KHR_materials_* textures: one array (scene/layer_textures.rs) and its sampler.
    entries.push(wgpu::BindGroupLayoutEntry {
        binding: 11,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    });
    entries.push(wgpu::BindGroupLayoutEntry {
        binding: 12,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    });
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("material layout"),
        entries: &entries,
    })
}

fn texture_transform(t: Option<&TextureRef>) -> GpuTextureTransform {
    let (m, set) = match t {
        Some(t) => (t.transform.matrix(), t.tex_coord.min(1)),
        None => (chiaro_scene::UvTransform::default().matrix(), 0),
    };
    GpuTextureTransform {
        linear: Vec4::new(m[0].x, m[0].y, m[1].x, m[1].y),
        offset: Vec2::new(m[2].x, m[2].y),
        uv_set: set,
        _pad: 0,
    }
}

/// A material's KHR_materials_* factors and its extension texture slots (their layers in
/// `plan`'s array) as the shaders read them, with what it lets through for shadows.
pub fn gpu_material_layers(l: &MaterialLayers, shadow_transmittance: Vec3, plan: &LayerPlan) -> GpuMaterialLayers {
    let textures = LayerTexture::ALL.map(|slot| {
        let t = texture_transform(l.texture(slot));
        GpuLayerTextureSlot { linear: t.linear, offset: t.offset, uv_set: t.uv_set, layer: plan.slots[slot.index()] }
    });
    GpuMaterialLayers {
        specular_color: l.specular_color,
        specular: l.specular,
        sheen_color: l.sheen_color,
        sheen_roughness: l.sheen_roughness,
        attenuation_color: l.attenuation_color,
        attenuation_distance: l.attenuation_distance.min(f32::MAX),
        diffuse_transmission_color: l.diffuse_transmission_color,
        diffuse_transmission: l.diffuse_transmission,
        ior: l.ior,
        clearcoat: l.clearcoat,
        clearcoat_roughness: l.clearcoat_roughness,
        clearcoat_normal_scale: l.clearcoat_normal_scale,
        transmission: l.transmission,
        thickness: l.thickness,
        iridescence: l.iridescence,
        iridescence_ior: l.iridescence_ior,
        iridescence_thickness_min: l.iridescence_thickness_min,
        iridescence_thickness_max: l.iridescence_thickness_max,
        anisotropy_strength: l.anisotropy_strength,
        anisotropy_rotation: l.anisotropy_rotation,
        dispersion: l.dispersion,
        shadow_transmittance_r: shadow_transmittance.x,
        shadow_transmittance_g: shadow_transmittance.y,
        shadow_transmittance_b: shadow_transmittance.z,
        textures,
    }
}

/// A material's factors, alpha mode and texture transforms as the shaders read them, its
/// extension textures in `plan`'s layers.
pub fn gpu_material(m: &Material, plan: &LayerPlan) -> GpuMaterial {
    GpuMaterial {
        base_color: m.base_color,
        emissive: m.emissive,
        metallic: m.metallic,
        roughness: m.roughness,
        normal_scale: m.normal_scale,
        occlusion_strength: m.occlusion_strength,
        alpha_cutoff: m.alpha_cutoff,
        alpha_mode: match m.alpha_mode {
            AlphaMode::Opaque => MATERIAL_ALPHA_OPAQUE,
            AlphaMode::Mask => MATERIAL_ALPHA_MASK,
            AlphaMode::Blend => MATERIAL_ALPHA_BLEND,
        },
        double_sided: m.double_sided as u32,
        flags: if m.normal_texture.is_some() { MATERIAL_FLAG_NORMAL_TEXTURE } else { 0 }
            | if m.unlit { MATERIAL_FLAG_UNLIT } else { 0 },
        _pad: 0,
        base_color_uv: texture_transform(m.base_color_texture.as_ref()),
        metallic_roughness_uv: texture_transform(m.metallic_roughness_texture.as_ref()),
        normal_uv: texture_transform(m.normal_texture.as_ref()),
        occlusion_uv: texture_transform(m.occlusion_texture.as_ref()),
        emissive_uv: texture_transform(m.emissive_texture.as_ref()),
        layers: gpu_material_layers(&m.layers, m.shadow_transmittance().unwrap_or(Vec3::ONE), plan),
    }
}

impl GpuScene {
    /// Uploads `scene`'s geometry, objects, materials, cookies and bake into buffers and
    /// textures, with bind groups made in `layout`.
    pub fn upload(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layout: &wgpu::BindGroupLayout,
        scene: &Scene,
    ) -> GpuScene {
        let _span = tracing::info_span!("upload scene").entered();
        let geometry = GeometryLayout::of(scene);
        let (vertices, indices) = vertices_and_indices(scene, &geometry);
        let draws = scene_draws(scene, &geometry);
        let objects = gpu_objects(scene);
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

        let (materials, bc7_images) = material_bind_groups(device, queue, layout, scene);
        let cookies = CookieTextures::upload(device, queue, scene);
        let baked = BakedTextures::upload(device, queue, scene.baked.as_ref());
        GpuScene { vertices, indices, objects, materials, draws, cookies, baked, bc7_images }
    }
}

/// Every mesh primitive's vertices and indices once, in the layout the draws point into.
fn vertices_and_indices(scene: &Scene, geometry: &GeometryLayout) -> (Vec<GpuVertex>, Vec<u32>) {
    let mut vertices: Vec<GpuVertex> = Vec::with_capacity(geometry.vertex_count);
    let mut indices: Vec<u32> = Vec::with_capacity(geometry.index_count);
    for (_, p) in scene.meshes.iter().flat_map(|m| m.drawn_parts()) {
        for i in 0..p.positions.len() {
            vertices.push(GpuVertex {
                position: p.positions[i].to_array(),
                normal: p.normals.get(i).copied().unwrap_or(Vec3::Y).to_array(),
                tangent: p.tangents.get(i).copied().unwrap_or(Vec4::new(1.0, 0.0, 0.0, 1.0)).to_array(),
                uv0: p.uv0.get(i).copied().unwrap_or_default().to_array(),
                uv1: p.uv1.get(i).copied().unwrap_or_default().to_array(),
                lightmap_uv: p.lightmap_uv.get(i).copied().unwrap_or_default().to_array(),
                color: GpuVertex::unorm16(p.colors.get(i).copied().unwrap_or(Vec4::ONE)),
            });
        }
        indices.extend_from_slice(&p.indices);
    }
    // wgpu refuses empty buffers' bindings; keep at least one element.
    if vertices.is_empty() {
        vertices.push(GpuVertex::zeroed());
    }
    if indices.is_empty() {
        indices.push(0);
    }
    (vertices, indices)
}

/// One object record per instance, lit by its lightmap layer, the probes or neither.
fn gpu_objects(scene: &Scene) -> Vec<GpuObject> {
    let has_probes = scene.baked.as_ref().is_some_and(|b| b.probes.is_some());
    let mut objects: Vec<GpuObject> = scene
        .instances
        .iter()
        .map(|inst| {
            let object =
                GpuObject::new(inst.world_from_local, inst.receive_shadows).identified(inst.aov_id(), inst.label);
            match inst.lightmap {
                Some(layer) if scene.baked.is_some() => object.lightmapped(layer),
                _ if has_probes => object.probe_lit(),
                _ => object,
            }
        })
        .collect();
    if objects.is_empty() {
        objects.push(GpuObject::new(glam::Mat4::IDENTITY, true));
    }
    objects
}

/// One bind group per material (and one for the default material, last): its uniform and
/// its five textures, each image uploaded once, white and flat-normal stand-ins for the
/// textures a material lacks.
fn material_bind_groups(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layout: &wgpu::BindGroupLayout,
    scene: &Scene,
) -> (Vec<wgpu::BindGroup>, usize) {
    let uploaded: Vec<(wgpu::TextureView, bool)> =
        scene.images.iter().map(|i| upload_scene_image(device, queue, i)).collect();
    let bc7_images = uploaded.iter().filter(|(_, bc7)| *bc7).count();
    let images: Vec<wgpu::TextureView> = uploaded.into_iter().map(|(view, _)| view).collect();
    let white = solid(device, queue, "white", [255, 255, 255, 255]);
    let flat_normal = solid(device, queue, "flat normal", [128, 128, 255, 255]);
    let no_layers = upload_layers(device, queue, "no extension textures", &layer_plan(&Material::default(), 0), &[]);
    let mut samplers = SamplerCache::default();
    let default = Material::default();
    let groups = scene
        .materials
        .iter()
        .chain(std::iter::once(&default))
        .map(|m| {
            let plan = layer_plan(m, scene.images.len());
            let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&m.name),
                contents: bytemuck::bytes_of(&gpu_material(m, &plan)),
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
            let layers = match plan.images.is_empty() {
                true => no_layers.clone(),
                false => upload_layers(device, queue, &m.name, &plan, &scene.images),
            };
            entries.push(wgpu::BindGroupEntry { binding: 11, resource: wgpu::BindingResource::TextureView(&layers) });
            let layer_sampler = samplers.get(device, &plan.sampler);
            entries
                .push(wgpu::BindGroupEntry { binding: 12, resource: wgpu::BindingResource::Sampler(&layer_sampler) });
            device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(&m.name), layout, entries: &entries })
        })
        .collect();
    (groups, bc7_images)
}
