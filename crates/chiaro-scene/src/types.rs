//! The plain-data scene every later stage reads: meshes with world transforms, materials,
//! decoded images, punctual lights and cameras, all in world space and glTF units.

use crate::layers::{LayerTexture, MaterialLayers};
use chiaro_math::Aabb;
use glam::{Mat4, Vec2, Vec3, Vec4};
use std::path::PathBuf;

pub use crate::light::*;

/// One drawable piece of a mesh, with one material. Vertex attributes are complete:
/// normals and tangents are generated at import when the file has none.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    /// Object-space vertex positions, metres.
    pub positions: Vec<Vec3>,
    /// Object-space unit vertex normals.
    pub normals: Vec<Vec3>,
    /// xyz tangent, w the bitangent sign (glTF convention).
    pub tangents: Vec<Vec4>,
    /// First texture coordinate set (TEXCOORD_0); zeros where the file has none.
    pub uv0: Vec<Vec2>,
    /// Second texture coordinate set (TEXCOORD_1); zeros where the file has none.
    pub uv1: Vec<Vec2>,
    /// Linear RGBA vertex colours (COLOR_0), each channel in 0..1, multiplying the base
    /// colour and its alpha; empty where the file has none (white).
    pub colors: Vec<Vec4>,
    /// Triangle list indices.
    pub indices: Vec<u32>,
    /// Index into `Scene::materials`; `None` uses the glTF default material.
    pub material: Option<usize>,
    /// Object-space bounds of `positions`.
    pub bounds: Aabb,
    /// Coordinates in the instance's lightmap atlas, one per vertex; empty until a bake is
    /// applied (`baked::apply`), which gives each lightmapped instance its own mesh.
    pub lightmap_uv: Vec<Vec2>,
}

impl Primitive {
    /// Triangles in `indices`.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// How a primitive's indices join its vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Topology {
    /// Three indices a triangle.
    #[default]
    Triangles,
    /// Two indices a line segment, drawn one pixel wide.
    Lines,
    /// One index a point, drawn as one pixel.
    Points,
}

/// A glTF POINTS, LINES, LINE_LOOP or LINE_STRIP primitive: drawn by the camera, one
/// pixel wide, but no surface, so it casts no shadow, is not traced and is not baked.
#[derive(Clone, Debug)]
pub struct PointsOrLines {
    /// `Lines` (loops and strips become segment lists) or `Points`.
    pub topology: Topology,
    /// Its vertices; `indices` lists segments or points. Without normals in the file it
    /// has none here and its material is an unlit copy of the file's.
    pub primitive: Primitive,
}

/// A glTF mesh: primitives drawn with the same transform.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// The file's name, or `mesh N`.
    pub name: String,
    /// Its drawable triangle primitives; those Chiaro cannot draw are left out.
    pub primitives: Vec<Primitive>,
    /// Its points and lines, drawn by the camera after the triangles.
    pub points_and_lines: Vec<PointsOrLines>,
}

impl Mesh {
    /// A mesh of triangle primitives only.
    pub fn of_triangles(name: String, primitives: Vec<Primitive>) -> Mesh {
        Mesh { name, primitives, points_and_lines: Vec::new() }
    }

    /// Every part the camera draws with its topology: the triangle primitives, then the
    /// points and lines.
    pub fn drawn_parts(&self) -> impl Iterator<Item = (Topology, &Primitive)> {
        let triangles = self.primitives.iter().map(|p| (Topology::Triangles, p));
        triangles.chain(self.points_and_lines.iter().map(|p| (p.topology, &p.primitive)))
    }
}

/// Whether and how an object casts shadows (node `extras.castShadows`; glTF nodes
/// without it cast two-sided, as the reference does).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CastShadows {
    /// Casts no shadows.
    Off,
    /// Casts with the faces its material draws, as the ShadowCaster pass of Catlike
    /// Coding's Custom SRP tutorials does.
    #[default]
    On,
    /// Casts with both faces, whatever its material says: what glTF nodes do by default.
    TwoSided,
    /// Casts shadows but is not drawn.
    ShadowsOnly,
}

/// A mesh placed in the world by a node.
#[derive(Clone, Debug)]
pub struct MeshInstance {
    /// Index into `Scene::meshes`.
    pub mesh: usize,
    /// Index of the glTF node (or demo object) that places it.
    pub node: usize,
    /// The node's name, else its mesh's, else `node N`, for messages and the viewer.
    pub name: String,
    /// The node's world transform (scale included).
    pub world_from_local: Mat4,
    /// Node `extras.castShadows`; glTF nodes default to two-sided.
    pub cast_shadows: CastShadows,
    /// Node `extras.receiveShadows`; true by default.
    pub receive_shadows: bool,
    /// Static instances receive lightmaps; dynamic ones (node `extras.static: false`, or
    /// moved by a glTF animation) are lit by light probes.
    pub is_static: bool,
    /// The atlas layer of its lightmap, once a bake is applied.
    pub lightmap: Option<u32>,
    /// Node `extras.label`: an integer class id for datasets, 0 if none.
    pub label: u32,
    /// Where it is one of the copies EXT_mesh_gpu_instancing makes of its node's mesh.
    pub gpu_instance: Option<GpuInstance>,
}

impl MeshInstance {
    /// An instance of mesh `mesh` placed by `world_from_local`, as a plain glTF node gives
    /// it: node 0, no name, casting and receiving shadows, static, no lightmap, no GPU
    /// instance, label 0. Callers set what differs with struct update syntax.
    pub fn new(mesh: usize, world_from_local: Mat4) -> MeshInstance {
        MeshInstance {
            mesh,
            node: 0,
            name: String::new(),
            world_from_local,
            cast_shadows: CastShadows::On,
            receive_shadows: true,
            is_static: true,
            lightmap: None,
            label: 0,
            gpu_instance: None,
        }
    }

    /// Its id in the instance AOV: the glTF node index, or a GPU instance's own id.
    pub fn aov_id(&self) -> usize {
        self.gpu_instance.map_or(self.node, |g| g.id as usize)
    }

    /// One copy of this node instance per GPU instance, each placed within the node and
    /// named after it with its position among the copies.
    pub fn gpu_instances<'a>(&'a self, copies: &'a [GpuInstance]) -> impl Iterator<Item = MeshInstance> + 'a {
        copies.iter().enumerate().map(move |(k, copy)| MeshInstance {
            name: format!("{} [{k}]", self.name),
            world_from_local: self.world_from_local * copy.node_from_instance,
            gpu_instance: Some(*copy),
            ..self.clone()
        })
    }
}

/// One copy of a node's mesh made by EXT_mesh_gpu_instancing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuInstance {
    /// Its id in the instance AOV. glTF node indices come first, so instance ids start at
    /// the file's node count: the instances of the node with the lowest index that has
    /// the extension take the next ids, in the order of its accessors, then the next such
    /// node's, and so on (docs/gltf.md).
    pub id: u32,
    /// Its transform within the node: the extension's TRANSLATION, ROTATION and SCALE.
    pub node_from_instance: Mat4,
}

/// glTF's alpha mode: how base colour alpha is used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlphaMode {
    /// Alpha ignored: fully opaque.
    Opaque,
    /// Alpha tested against `alpha_cutoff`: holes where it is below.
    Mask,
    /// Alpha blended over what is behind.
    Blend,
}

/// How a material's surfaces cast shadows (material `extras.shadowCasting`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowCasting {
    /// Solid casters, whatever their alpha.
    #[default]
    On,
    /// Alpha-tested: no shadow where base colour alpha is below the material's cutoff,
    /// as the camera sees the holes of MASK materials.
    Clip,
    /// Stippled by a stable dither pattern against alpha, so that filtered shadows darken
    /// in proportion to opacity (for transparent surfaces).
    Dither,
    /// No shadows.
    Off,
}

impl ShadowCasting {
    /// The glTF alpha mode's natural choice: clip for MASK, dither for BLEND, on for OPAQUE.
    pub fn default_for(alpha: AlphaMode) -> ShadowCasting {
        match alpha {
            AlphaMode::Opaque => ShadowCasting::On,
            AlphaMode::Mask => ShadowCasting::Clip,
            AlphaMode::Blend => ShadowCasting::Dither,
        }
    }
}

/// How texture coordinates outside 0 to 1 wrap (glTF sampler wrap modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WrapMode {
    /// The image tiles.
    Repeat,
    /// The image tiles, every other copy mirrored.
    MirroredRepeat,
    /// Coordinates clamp to the edge texels.
    ClampToEdge,
}

/// A glTF sampler: wrapping and filtering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplerDesc {
    /// Wrapping along U.
    pub wrap_u: WrapMode,
    /// Wrapping along V.
    pub wrap_v: WrapMode,
    /// Linear (true) or nearest (false) magnification.
    pub mag_linear: bool,
    /// Linear (true) or nearest (false) minification.
    pub min_linear: bool,
    /// Whether minification samples mipmaps.
    pub mipmaps: bool,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        SamplerDesc {
            wrap_u: WrapMode::Repeat,
            wrap_v: WrapMode::Repeat,
            mag_linear: true,
            min_linear: true,
            mipmaps: true,
        }
    }
}

/// KHR_texture_transform: `uv' = T(offset) * R(rotation) * S(scale) * uv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Translation in UV units, applied last.
    pub offset: Vec2,
    /// Counter-clockwise rotation, radians.
    pub rotation_rad: f32,
    /// Scale along U and V, applied first.
    pub scale: Vec2,
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform { offset: Vec2::ZERO, rotation_rad: 0.0, scale: Vec2::ONE }
    }
}

impl UvTransform {
    /// The 3x2 matrix (column-major: three columns of two rows) the shader applies.
    pub fn matrix(&self) -> [Vec2; 3] {
        let (s, c) = self.rotation_rad.sin_cos();
        [Vec2::new(c * self.scale.x, -s * self.scale.x), Vec2::new(s * self.scale.y, c * self.scale.y), self.offset]
    }
}

/// A material's use of an image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into `Scene::images`.
    pub image: usize,
    /// How the image is sampled.
    pub sampler: SamplerDesc,
    /// Which UV set: 0 or 1.
    pub tex_coord: u32,
    /// KHR_texture_transform on the coordinates.
    pub transform: UvTransform,
}

/// glTF metallic-roughness material, with emissive strength folded into `emissive`.
#[derive(Clone, Debug)]
pub struct Material {
    /// The file's name, or `material N`.
    pub name: String,
    /// Linear RGBA factor; alpha is coverage or opacity by `alpha_mode`.
    pub base_color: Vec4,
    /// sRGB base colour and alpha, times `base_color`.
    pub base_color_texture: Option<TextureRef>,
    /// Metalness factor, 0 dielectric to 1 metal.
    pub metallic: f32,
    /// Perceptual roughness factor, 0 mirror to 1 fully rough.
    pub roughness: f32,
    /// Roughness in G and metalness in B, times the factors.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map.
    pub normal_texture: Option<TextureRef>,
    /// Scale of the normal map's X and Y.
    pub normal_scale: f32,
    /// Ambient occlusion in R.
    pub occlusion_texture: Option<TextureRef>,
    /// How much of the occlusion texture applies, 0 to 1.
    pub occlusion_strength: f32,
    /// Linear emissive radiance factor (already times KHR_materials_emissive_strength).
    pub emissive: Vec3,
    /// sRGB emissive colour, times `emissive`.
    pub emissive_texture: Option<TextureRef>,
    /// How base colour alpha is used.
    pub alpha_mode: AlphaMode,
    /// MASK threshold: alpha below it is a hole.
    pub alpha_cutoff: f32,
    /// glTF `doubleSided`: whether back faces are drawn too.
    pub double_sided: bool,
    /// How its surfaces cast shadows (`extras.shadowCasting`, or by alpha mode).
    pub shadow_casting: ShadowCasting,
    /// KHR_materials_unlit: the surface shows its base colour (factor times texture, alpha
    /// by `alpha_mode`) as emitted radiance, lit by no light, shadow, ambient or bake. It
    /// still casts shadows by `shadow_casting`.
    pub unlit: bool,
    /// The KHR_materials_* extensions beyond metallic-roughness.
    pub layers: MaterialLayers,
}

impl Material {
    /// What one crossing of the surface lets through for shadows, per channel, or `None`
    /// where it casts an ordinary shadow (see `MaterialLayers::shadow_transmittance`).
    pub fn shadow_transmittance(&self) -> Option<Vec3> {
        self.layers.shadow_transmittance(self.base_color.truncate(), self.metallic, self.double_sided)
    }

    /// Every texture reference the material holds: the five core slots, then the
    /// extensions' in `LayerTexture::ALL` order.
    pub fn textures_mut(&mut self) -> Vec<&mut Option<TextureRef>> {
        let mut textures = vec![
            &mut self.base_color_texture,
            &mut self.metallic_roughness_texture,
            &mut self.normal_texture,
            &mut self.occlusion_texture,
            &mut self.emissive_texture,
        ];
        textures.extend(self.layers.textures.iter_mut());
        textures
    }

    /// Every texture the material has, with the colour space it is sampled in.
    pub fn textures_in_color_spaces(&self) -> Vec<(TextureRef, ColorSpace)> {
        let core = [
            (self.base_color_texture, ColorSpace::Srgb),
            (self.metallic_roughness_texture, ColorSpace::Linear),
            (self.normal_texture, ColorSpace::Linear),
            (self.occlusion_texture, ColorSpace::Linear),
            (self.emissive_texture, ColorSpace::Srgb),
        ];
        let layered = LayerTexture::ALL.iter().map(|&slot| (self.layers.textures[slot.index()], slot.color_space()));
        core.into_iter().chain(layered).filter_map(|(t, space)| t.map(|t| (t, space))).collect()
    }
}

impl Default for Material {
    /// The glTF default material: white, fully rough dielectric... per spec metallic 1,
    /// roughness 1.
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            alpha_cutoff: 0.5,
            double_sided: false,
            shadow_casting: ShadowCasting::On,
            unlit: false,
            layers: MaterialLayers::default(),
        }
    }
}

impl Material {
    /// Whether any of its five textures is set.
    pub fn has_texture(&self) -> bool {
        [
            &self.base_color_texture,
            &self.metallic_roughness_texture,
            &self.normal_texture,
            &self.occlusion_texture,
            &self.emissive_texture,
        ]
        .iter()
        .any(|t| t.is_some())
    }
}

/// Whether an image holds colour (sRGB-encoded) or data (linear), decided by its use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSpace {
    /// Colour, sRGB-encoded: decoded to linear when sampled.
    Srgb,
    /// Data (normals, roughness, occlusion, cookies): sampled as stored.
    Linear,
}

/// A decoded image, always 8-bit RGBA.
#[derive(Clone, Debug)]
pub struct Image {
    /// The image's name, else its URI, else `image N`, for messages.
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major RGBA8 texels from the top-left, `width * height * 4` bytes.
    pub rgba8: Vec<u8>,
    /// The smaller mip levels the file stores (KTX2), each half the size of the one
    /// before; empty where the renderer makes them.
    pub file_mips: Vec<Vec<u8>>,
    /// Whether the texels are colour or data.
    pub color_space: ColorSpace,
    /// The KTX2 file of an ETC1S or UASTC (Basis Universal) image, kept so that a device
    /// that samples BC7 can have it transcoded to that (`Image::bc7_levels`) rather than
    /// take `rgba8`; `None` for every other image.
    pub basis_source: Option<std::sync::Arc<BasisSource>>,
}

/// A Basis Universal KTX2 file and, once a device has asked for it, its BC7 transcode
/// (kept: a scene is prepared again at every pose of an animation).
#[derive(Debug)]
pub struct BasisSource {
    /// The KTX2 file's bytes.
    pub ktx2: Vec<u8>,
    pub(crate) bc7: std::sync::OnceLock<Result<Vec<Vec<u8>>, String>>,
}

impl BasisSource {
    /// The file, not transcoded yet.
    pub fn new(ktx2: Vec<u8>) -> BasisSource {
        BasisSource { ktx2, bc7: std::sync::OnceLock::new() }
    }
}

/// A glTF camera, perspective or orthographic, placed in the world.
#[derive(Clone, Debug)]
pub struct Camera {
    /// The camera's name, else its node's, else `camera N`.
    pub name: String,
    /// Index of the glTF node that carries the camera.
    pub node: usize,
    /// Perspective (vertical field of view) or orthographic (half height, `ymag`); the
    /// output's aspect ratio gives the width, for `xmag` as for a perspective's.
    pub projection: chiaro_math::camera::Projection,
    /// Distance to the near plane, metres.
    pub znear: f32,
    /// `None` for an infinite projection (perspective cameras only).
    pub zfar: Option<f32>,
    /// The file's aspect ratio, if any (`xmag / ymag` for an orthographic camera); the
    /// output size decides the rendered aspect.
    pub aspect_ratio: Option<f32>,
    /// The camera's node without scale: it looks down its -Z, +Y up.
    pub world_from_view: Mat4,
}

/// A loaded scene. `ignored` lists what the file had that Chiaro does not use, and why.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The file the scene was loaded from; `None` for scenes made in code.
    pub source: Option<PathBuf>,
    /// Meshes, indexed by `MeshInstance::mesh`.
    pub meshes: Vec<Mesh>,
    /// Every mesh placed in the world, one per node that carries a mesh.
    pub instances: Vec<MeshInstance>,
    /// Materials, indexed by `Primitive::material`.
    pub materials: Vec<Material>,
    /// Decoded images, indexed by `TextureRef::image` and `Cookie::image`.
    pub images: Vec<Image>,
    /// Punctual lights in the file's order.
    pub lights: Vec<Light>,
    /// Cameras in the file's order.
    pub cameras: Vec<Camera>,
    /// What the file had that Chiaro does not use, one line each, saying why.
    pub ignored: Vec<String>,
    /// What the file's extensions that Chiaro reads gave, one line each (compression,
    /// instancing, material variants), for `chiaro info`.
    pub extensions_read: Vec<String>,
    /// Files the scene was read from: the document, then its external buffers and images.
    pub inputs: Vec<PathBuf>,
    /// Lightmaps and light probes, once a bake is applied (`baked::apply`).
    pub baked: Option<crate::baked::BakedLighting>,
    /// Every node at its glTF index (objects' `node` fields index it); empty for scenes
    /// made in code until `ensure_nodes`.
    pub nodes: Vec<crate::nodes::SceneNode>,
    /// glTF animations, skins and morph targets, for `Scene::pose`; `None` when the file
    /// has none (and for scenes made in code).
    pub animation: Option<Box<crate::animation::SceneAnimation>>,
    /// The environment the file carries (EXT_lights_image_based), used when the settings
    /// name none of their own.
    pub environment: Option<crate::environment::SceneEnvironment>,
    /// KHR_materials_variants: the file's variants, the materials they give, and which is
    /// selected (`Scene::select_variant`).
    pub variants: crate::variants::MaterialVariants,
}

impl Scene {
    /// World-space bounds of every mesh instance.
    pub fn bounds(&self) -> Aabb {
        self.instances.iter().fold(Aabb::EMPTY, |acc, inst| {
            let local = self.meshes[inst.mesh].drawn_parts().fold(Aabb::EMPTY, |b, (_, p)| b.union(&p.bounds));
            acc.union(&local.transformed(&inst.world_from_local))
        })
    }

    /// Triangles drawn: every instance's primitives.
    pub fn triangle_count(&self) -> usize {
        self.instances.iter().flat_map(|inst| &self.meshes[inst.mesh].primitives).map(Primitive::triangle_count).sum()
    }

    /// Whether baked lights are left out of the realtime lights: only when a bake is
    /// applied, so that without one they fall back to realtime.
    pub fn skips_baked_lights(&self) -> bool {
        self.baked.is_some()
    }

    /// Finds a camera by name (camera or node name) or by index in `cameras`.
    pub fn find_camera(&self, key: &str) -> Option<usize> {
        if let Ok(index) = key.parse::<usize>() {
            return (index < self.cameras.len()).then_some(index);
        }
        self.cameras.iter().position(|c| c.name == key)
    }
}
