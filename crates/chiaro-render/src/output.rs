//! What a caller asks of a frame and what it gets back: the images read back, the AOVs,
//! each light's shadow status, and the frame's timings.

use crate::debug_view::DebugView;
use crate::graph::{FrameGraph, PassStats, Target};
use crate::plan::FramePlan;
use crate::plan::lights::LightId;
use crate::plan::shadows::ShadowSlot;
use crate::plan::virtual_shadows::VirtualPageStats;
use chiaro_scene::{LightMode, Scene};

/// What a caller asks of a frame beyond the image: AOVs, read-back, atlases, a debug view.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameOptions {
    /// Also render world position, normal and view depth.
    pub aovs: bool,
    /// With `aovs`, render the view depth alone: `Aovs::depth` is filled and the other
    /// AOVs come back empty. One float a pixel instead of three four-float targets, for
    /// callers (datasets) that want depth and no more.
    pub depth_only: bool,
    /// Also render each light's shadow attenuation (needs `readback`).
    pub shadow_aovs: bool,
    /// Also render each pixel's glTF node and label (`FrameOutput::ids`).
    pub ids: bool,
    /// Also read back the ambient occlusion the shading used
    /// (`FrameOutput::ambient_occlusion`).
    pub ambient_occlusion: bool,
    /// Copy the images back to the CPU, waiting for the frame (off for benchmarking and
    /// for frames that go to a window).
    pub readback: bool,
    /// With `readback`, leave the linear radiance on the GPU: `FrameOutput::hdr` comes
    /// back empty and only the tone-mapped image is copied, for callers that want no more.
    pub skip_hdr: bool,
    /// Copy the shadow atlases back to the CPU.
    pub read_shadow_atlas: bool,
    /// A debug view the frame's passes draw (cascades, the deferred views); the others
    /// are read back and coloured by the caller (see `DebugView::frame_options`).
    pub debug: Option<DebugView>,
}

impl FrameOptions {
    /// Whether the frame must be waited for.
    pub fn reads_back(&self) -> bool {
        self.readback || self.shadow_aovs || self.ids || self.read_shadow_atlas || self.ambient_occlusion
    }
}

/// How long a frame took: CPU preparation, and GPU time per pass when waited for.
#[derive(Clone, Debug, Default)]
pub struct FrameTimings {
    /// The frame's number, counting from 0 for each renderer.
    pub frame: u64,
    /// Time to plan the frame, upload its data and record its commands (wall clock).
    pub cpu_prepare_ms: f64,
    /// The same, on the preparing thread's own CPU clock (`thread_clock`): its work alone,
    /// without the time other threads (a software rasteriser's) took from it. `None`
    /// where the platform has no thread clock.
    pub cpu_prepare_thread_ms: Option<f64>,
    /// GPU time of each pass that ran, from timestamp queries, when the frame was waited
    /// for (see `Renderer::gpu_times` otherwise).
    pub gpu_pass_ms: Vec<(&'static str, f64)>,
    /// Wall time from the start of planning until the GPU finished, when waited for.
    pub wall_ms: Option<f64>,
}

impl FrameTimings {
    /// The sum of the passes' GPU times in milliseconds, if they were measured.
    pub fn gpu_total_ms(&self) -> Option<f64> {
        (!self.gpu_pass_ms.is_empty()).then(|| self.gpu_pass_ms.iter().map(|(_, t)| t).sum())
    }
}

/// Pass times of a frame that finished on the GPU.
#[derive(Clone, Debug, Default)]
pub struct GpuFrameTimes {
    /// The frame's number, counting from 0 for each renderer.
    pub frame: u64,
    /// Each pass that ran, by name, with its GPU time in milliseconds.
    pub passes: Vec<(&'static str, f64)>,
}

impl GpuFrameTimes {
    /// The frame's GPU time in milliseconds: its passes' sum.
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|(_, t)| t).sum()
    }
}

/// World-space AOVs; `NaN` where no surface covers the pixel. A depth-only frame
/// (`FrameOptions::depth_only`) fills `depth` alone.
#[derive(Clone, Debug, Default)]
pub struct Aovs {
    /// World-space position, metres, per pixel.
    pub position_ws: Vec<[f32; 3]>,
    /// World-space unit shading normal, per pixel.
    pub normal_ws: Vec<[f32; 3]>,
    /// Linear depth along the view axis, metres; infinity where no surface is.
    pub depth: Vec<f32>,
    /// The baked irradiance (lux) each pixel used, from its lightmap or the probes; zero
    /// where no bake lights it.
    pub baked_irradiance: Vec<[f32; 3]>,
}

/// Which surface each pixel shows, exactly (one sample a pixel, never blended).
#[derive(Clone, Debug, Default)]
pub struct Ids {
    /// The glTF node (demo object) whose mesh the pixel shows, or for a copy made by
    /// EXT_mesh_gpu_instancing its own id (`MeshInstance::aov_id`); `NO_NODE` (u32::MAX)
    /// on the sky.
    pub instance: Vec<u32>,
    /// That node's `extras.label`; 0 where it has none and on the sky.
    pub label: Vec<u32>,
}

/// A shadow atlas as read back: its side and depths, row-major.
#[derive(Clone, Debug)]
pub struct AtlasImage {
    /// "directional" or "other".
    pub name: &'static str,
    /// The atlas side in texels.
    pub size: u32,
    /// The depths as the atlas stores them, `size` x `size`, row-major.
    pub depths: Vec<f32>,
}

/// What a frame returns: the images read back, AOVs, shadow data, timings and its plan.
#[derive(Clone, Debug)]
pub struct FrameOutput {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Linear radiance (not exposed), RGBA, row-major from the top-left; empty unless read
    /// back.
    pub hdr: Vec<[f32; 4]>,
    /// Tone-mapped sRGB, RGBA8; empty unless read back to a texture of the renderer's.
    pub ldr: Vec<u8>,
    /// World position, normal, depth and baked light per pixel, if asked for.
    pub aovs: Option<Aovs>,
    /// The glTF node and label per pixel, if asked for.
    pub ids: Option<Ids>,
    /// With `FrameOptions::ambient_occlusion`: the AO the shading used per pixel (1 open,
    /// 0 hidden; 1 where no surface is, and everywhere without `[ambient_occlusion]
    /// enabled`).
    pub ambient_occlusion: Option<Vec<f32>>,
    /// CPU and GPU times of the frame.
    pub timings: FrameTimings,
    /// Per scene light (by index in `Scene::lights`): the shadow attenuation the shading
    /// used, 1 where no shadow map covers the pixel, NaN where no surface is.
    pub shadow_aovs: Vec<Vec<f32>>,
    /// Per scene light, with `shadow_aovs`: how many shadow-map texels a step of one
    /// pixel crosses where that light's map was sampled (the larger of the two screen
    /// axes; 1 is a texel a pixel), NaN where no map was or no surface is.
    pub shadow_texels_per_pixel: Vec<Vec<f32>>,
    /// The shadow atlases in use, if asked for.
    pub shadow_atlases: Vec<AtlasImage>,
    /// Shadow tiles rendered and caster draws issued into them.
    pub shadow_tiles: usize,
    /// See `shadow_tiles`.
    pub shadow_caster_draws: usize,
    /// Exported targets read back that have no field above (a new pass's output), as
    /// tightly packed texels, layer after layer.
    pub images: std::collections::BTreeMap<Target, Vec<u8>>,
    /// What the frame did.
    pub plan: FramePlan,
    /// The passes that ran, in order, and the targets they used.
    pub graph: FrameGraph,
}

impl FrameOutput {
    /// A submitted frame's output before anything is read back: its size, the passes'
    /// counts, the CPU timings, the plan and the graph.
    pub(crate) fn before_read_back(
        (width, height): (u32, u32),
        timings: FrameTimings,
        stats: PassStats,
        plan: FramePlan,
        graph: FrameGraph,
    ) -> FrameOutput {
        FrameOutput {
            width,
            height,
            hdr: Vec::new(),
            ldr: Vec::new(),
            aovs: None,
            ids: None,
            ambient_occlusion: None,
            timings,
            shadow_aovs: Vec::new(),
            shadow_texels_per_pixel: Vec::new(),
            shadow_atlases: Vec::new(),
            shadow_tiles: stats.shadow_tiles_rendered,
            shadow_caster_draws: stats.shadow_caster_draws,
            images: Default::default(),
            plan,
            graph,
        }
    }

    /// The 10th, 50th and 90th percentiles of shadow texels per pixel over every pixel
    /// and light a realtime map was sampled for (`shadow_texels_per_pixel`); `None` where
    /// none was (or the shadow AOVs were not asked for).
    pub fn shadow_texel_ratio_percentiles(&self) -> Option<[f32; 3]> {
        let mut ratios: Vec<f32> =
            self.shadow_texels_per_pixel.iter().flatten().copied().filter(|r| r.is_finite()).collect();
        if ratios.is_empty() {
            return None;
        }
        ratios.sort_by(f32::total_cmp);
        Some([0.1, 0.5, 0.9].map(|q| ratios[((ratios.len() - 1) as f32 * q).round() as usize]))
    }

    /// The virtual shadow technique's page counts this frame (pages asked for, those the
    /// pool could not hold, pages resident, the pool's megabytes); `None` with the atlas
    /// technique or no virtual-shadowed light.
    pub fn virtual_pages(&self) -> Option<VirtualPageStats> {
        let maps = &self.plan.shadows.virtual_maps;
        maps.is_active().then_some(maps.stats)
    }

    /// Point and spot lights shaded.
    pub fn local_lights_shaded(&self) -> usize {
        self.plan.shaded_local_lights()
    }

    /// Visible point and spot lights left out by `max_other_lights`.
    pub fn local_lights_dropped(&self) -> usize {
        self.plan.dropped_local
    }

    /// Per scene light: whether it had a realtime shadow map this frame, and if not why.
    pub fn shadow_status(&self, scene: &Scene) -> Vec<ShadowStatus> {
        (0..scene.lights.len())
            .map(|i| match self.plan.light_index(LightId(i as u32)).map(|k| self.plan.lights[k].shadow) {
                _ if !scene.lights[i].shadow.casts() => ShadowStatus::Off,
                None if scene.skips_baked_lights() && scene.lights[i].mode == LightMode::Baked => ShadowStatus::Baked,
                None => ShadowStatus::NotShaded,
                Some(ShadowSlot::Realtime { .. }) => ShadowStatus::Mapped,
                Some(ShadowSlot::BakedOnly) if self.plan.mask_channel(LightId(i as u32)).is_some() => {
                    ShadowStatus::MaskOnly
                }
                Some(ShadowSlot::BakedOnly) => ShadowStatus::NoTile,
                Some(ShadowSlot::None) => ShadowStatus::Off,
            })
            .collect()
    }
}

/// Whether a light's shadows came from a shadow map this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowStatus {
    /// Sampled from its atlas tiles.
    Mapped,
    /// The light casts no shadows (extras `shadows: none` or strength 0).
    Off,
    /// The light was not shaded this frame (culled, or over the light limits).
    NotShaded,
    /// It casts shadows but found no free atlas tiles.
    NoTile,
    /// A baked light with a bake applied: its light and shadows are in the lightmaps.
    Baked,
    /// No free atlas tiles, but a shadow mask channel: its baked shadows are used.
    MaskOnly,
}
