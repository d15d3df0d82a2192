//! Bind group 0 of every scene pass, as one table: each binding's place, its name, the
//! stages that read it and its type. The table builds the group's layout and the order of
//! its entries (`frame_data`), and build.rs hands each binding's place to WESL as
//! `BINDING_<NAME>`, so a shader writes `@group(0) @binding(BINDING_FRAME)` and a binding
//! is numbered in one place. No wgpu here: build.rs includes this file.

/// The shader stages that read a binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stages {
    /// The fragment stage alone.
    Fragment,
    /// The vertex and fragment stages.
    VertexFragment,
}

/// A texture's view dimension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// `texture_2d`.
    D2,
    /// `texture_2d_array`.
    D2Array,
    /// `texture_cube`.
    Cube,
    /// `texture_cube_array`.
    CubeArray,
}

/// What a binding holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A uniform buffer.
    Uniform,
    /// A read-only storage buffer.
    Storage,
    /// A depth texture read through a comparison sampler.
    DepthTexture,
    /// A comparison sampler (for the shadow atlases).
    ComparisonSampler,
    /// A filtering sampler.
    FilteringSampler,
    /// A filterable float texture.
    FloatTexture(Dimension),
    /// An unfiltered unsigned-integer 2D texture (the light texel table).
    UintTexture,
}

/// Which resource a binding holds, for the code that fills the group's entries; each
/// variant is the binding of the same name in `FRAME_BINDINGS`.
#[allow(missing_docs)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resource {
    Frame,
    Lights,
    LightList,
    Objects,
    Shadows,
    DirectionalShadowAtlas,
    ShadowSampler,
    LocalShadowAtlas,
    Cookies2d,
    CookiesCube,
    CookieRepeat,
    CookieClamp,
    Lightmaps,
    ProbeGrid,
    ShadowMasks,
    LightTable,
    ListStarts,
    ListIndices,
    Environment,
    EnvironmentSpecular,
    EnvironmentBrdf,
    ShadowTints,
    ViewDepths,
    VirtualPageTable,
    AmbientOcclusion,
}

/// One binding of group 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameBinding {
    /// What the binding holds.
    pub resource: Resource,
    /// Upper snake case: the WESL constant is `BINDING_<name>`.
    pub name: &'static str,
    /// The stages that read it.
    pub stages: Stages,
    /// Its type.
    pub kind: Kind,
}

const fn fragment(resource: Resource, name: &'static str, kind: Kind) -> FrameBinding {
    FrameBinding { resource, name, stages: Stages::Fragment, kind }
}

/// Group 0's bindings; a binding's number is its place here.
pub const FRAME_BINDINGS: [FrameBinding; 25] = [
    // The frame uniform (common/frame.wesl): the camera, exposure, light counts.
    FrameBinding { resource: Resource::Frame, name: "FRAME", stages: Stages::VertexFragment, kind: Kind::Uniform },
    // The first MAX_UNIFORM_LIGHTS lights and the light lists (lighting/light.wesl).
    fragment(Resource::Lights, "LIGHTS", Kind::Uniform),
    fragment(Resource::LightList, "LIGHT_LIST", Kind::Uniform),
    // The objects; the id pass reads their node and label in the fragment stage.
    FrameBinding { resource: Resource::Objects, name: "OBJECTS", stages: Stages::VertexFragment, kind: Kind::Storage },
    // The shadow uniform, the directional atlas, their comparison sampler and the local
    // lights' atlas (shadows/data.wesl).
    fragment(Resource::Shadows, "SHADOWS", Kind::Uniform),
    fragment(Resource::DirectionalShadowAtlas, "DIRECTIONAL_SHADOW_ATLAS", Kind::DepthTexture),
    fragment(Resource::ShadowSampler, "SHADOW_SAMPLER", Kind::ComparisonSampler),
    fragment(Resource::LocalShadowAtlas, "LOCAL_SHADOW_ATLAS", Kind::DepthTexture),
    // Cookies and their samplers (lighting/light.wesl).
    fragment(Resource::Cookies2d, "COOKIES_2D", Kind::FloatTexture(Dimension::D2Array)),
    fragment(Resource::CookiesCube, "COOKIES_CUBE", Kind::FloatTexture(Dimension::CubeArray)),
    fragment(Resource::CookieRepeat, "COOKIE_REPEAT", Kind::FilteringSampler),
    fragment(Resource::CookieClamp, "COOKIE_CLAMP", Kind::FilteringSampler),
    // Baked light (lighting/baked.wesl).
    fragment(Resource::Lightmaps, "LIGHTMAPS", Kind::FloatTexture(Dimension::D2Array)),
    fragment(Resource::ProbeGrid, "PROBE_GRID", Kind::Storage),
    fragment(Resource::ShadowMasks, "SHADOW_MASKS", Kind::FloatTexture(Dimension::D2Array)),
    // Culled light lists (lighting/culled.wesl): every light in a texel table, the lists'
    // starts and their entries.
    fragment(Resource::LightTable, "LIGHT_TABLE", Kind::UintTexture),
    fragment(Resource::ListStarts, "LIST_STARTS", Kind::Storage),
    fragment(Resource::ListIndices, "LIST_INDICES", Kind::Storage),
    // The environment (lighting/environment.wesl).
    fragment(Resource::Environment, "ENVIRONMENT", Kind::Uniform),
    fragment(Resource::EnvironmentSpecular, "ENVIRONMENT_SPECULAR", Kind::FloatTexture(Dimension::Cube)),
    fragment(Resource::EnvironmentBrdf, "ENVIRONMENT_BRDF", Kind::FloatTexture(Dimension::D2Array)),
    // What casters that let light through leave of it, per shadow texel: a layer per
    // atlas (shadows/tint.wesl). The environment's image, which only the background
    // reads, is bound by the background pipeline instead, so that a forward shader and
    // its material stay within the 16 sampled textures a stage is sure to have.
    fragment(Resource::ShadowTints, "SHADOW_TINTS", Kind::FloatTexture(Dimension::D2Array)),
    // The scene depth of each pixel, row by row, for contact shadows' march
    // (shadows/contact.wesl): a storage buffer the contact depth pass fills, so that the
    // passes that read it may keep the depth target attached and stay within 16 sampled
    // textures.
    fragment(Resource::ViewDepths, "VIEW_DEPTHS", Kind::Storage),
    // The virtual shadow maps' page table (shadows/virtual_map.wesl): which pool slot
    // holds each page, 0 for none.
    fragment(Resource::VirtualPageTable, "VIRTUAL_PAGE_TABLE", Kind::Storage),
    // Each pixel's ambient occlusion (lighting/occlusion.wesl), which the ambient occlusion
    // pass writes: a buffer like the view depths, for the same 16 sampled textures.
    fragment(Resource::AmbientOcclusion, "AMBIENT_OCCLUSION", Kind::Storage),
];

/// The binding number of the binding named `name`.
pub fn binding_of(name: &str) -> u32 {
    FRAME_BINDINGS.iter().position(|b| b.name == name).unwrap_or_else(|| panic!("no frame binding {name}")) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_resources_are_unique() {
        for (i, b) in FRAME_BINDINGS.iter().enumerate() {
            assert_eq!(binding_of(b.name), i as u32, "{} is named twice", b.name);
            assert_eq!(FRAME_BINDINGS.iter().filter(|o| o.resource == b.resource).count(), 1, "{:?}", b.resource);
        }
    }
}
