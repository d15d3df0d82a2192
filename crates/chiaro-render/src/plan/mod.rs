//! The frame plan: everything a frame will do, decided on the CPU before anything is
//! recorded. A scene, its draws, a view and the settings flow in; the lights the frame
//! shades (with stable ids), their light lists and shadow slots, the shadow tiles with
//! their casters and which of them are drawn again, the camera's draw order, the light
//! volumes and the shader features flow out. Passes declare and record only what the plan
//! says (the frame graph decides from their declarations which run), and tests inspect
//! plans without a GPU.

pub mod clusters;
pub mod cookies;
pub mod culling;
pub mod draws;
pub mod features;
pub mod lights;
pub mod shadow_cache;
pub mod shadows;
pub mod virtual_shadows;
pub mod volumes;

use crate::debug_view::DebugView;
use crate::gpu::{GpuFrame, GpuLight, GpuVolumeLight};
use crate::shader_constants::{
    DEBUG_VIEW_CASCADES, DEBUG_VIEW_NONE, MAX_FRAME_LIGHTS, MAX_UNIFORM_LIGHTS, MIXED_MODE_BAKED_INDIRECT,
    MIXED_MODE_DISTANCE_SHADOWMASK, MIXED_MODE_SHADOWMASK,
};
use crate::view::View;
use chiaro_math::light::MAX_LOCAL_LIGHTS;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{
    AlphaMode, DeferredAntialiasing, Light, LightBuffer, LightCulling, MixedMode, RenderPath, Scene, Settings,
};
use cookies::cookie_slots;
use culling::{CulledLights, cull_lights};
use draws::{Draw, camera_draw_order};
use glam::Vec3;
use lights::{FrameLight, LightChoice, LightId, choose_lights, gpu_light};
use shadows::{ShadowAtlasTiles, ShadowPlan, ShadowSlot, ShadowSlots, plan_shadows};
use std::fmt;
use volumes::{VolumeDraw, light_volume};

/// What the caller wants from the frame besides the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanRequest {
    /// World position, normal and depth AOVs.
    pub aovs: bool,
    /// With `aovs`, the view depth alone (one float a pixel, a lighter pass).
    pub depth_only: bool,
    /// A debug view drawn by the frame's passes: cascades tint the forward path's image,
    /// the deferred views imply the deferred path.
    pub debug: Option<DebugView>,
    /// Per-light shadow AOVs, which (like `aovs`) test against single-sampled depth.
    pub shadow_aovs: bool,
    /// The node and label of each pixel's surface, single-sampled like the AOVs.
    pub ids: bool,
}

impl PlanRequest {
    /// The deferred path's debug view asked for, if any.
    pub fn deferred_view(&self) -> Option<DebugView> {
        self.debug.filter(|d| d.is_deferred())
    }
}

/// The frame's lights as index lists into `FramePlan::lights`; the shaders loop over
/// them in this order (directional, shadowed local, unshadowed local).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ShadedLights {
    /// Indices of the directional lights.
    pub directional: Vec<u32>,
    /// Indices of the point and spot lights with a realtime shadow.
    pub shadowed_local: Vec<u32>,
    /// Indices of the point and spot lights without a realtime shadow.
    pub unshadowed_local: Vec<u32>,
}

impl ShadedLights {
    /// The lists one after the other, as the light index buffer holds them.
    pub fn concatenated(&self) -> Vec<u32> {
        [&self.directional[..], &self.shadowed_local, &self.unshadowed_local].concat()
    }
}

/// Everything a frame will do, decided on the CPU from the scene, view and settings:
/// its lights, shadows, draws and passes. Printable and testable without a device.
#[derive(Clone, Debug)]
pub struct FramePlan {
    /// The camera of the frame.
    pub view: View,
    /// What the caller asked for (AOVs, debug view, read-back).
    pub request: PlanRequest,
    /// Forward or deferred (a debug view of the G-buffer implies deferred).
    pub path: RenderPath,
    /// How the deferred path accumulates light: HDR or the LDR exp2 buffer.
    pub light_buffer: LightBuffer,
    /// The display curve of the tone mapping pass (`[render] tone_mapping`).
    pub tone_mapping: chiaro_scene::ToneMapping,
    /// `[ambient_occlusion]`, for the ambient occlusion pass (`features.ambient_occlusion`
    /// says whether it runs).
    pub ambient_occlusion: chiaro_scene::AmbientOcclusionSettings,
    /// Every light the frame shades: the directional ones in scene order, then the point
    /// and spot lights most important first.
    pub lights: Vec<FrameLight>,
    /// The index lists the shaders loop over.
    pub lists: ShadedLights,
    /// Shadow tiles, their casters and the shadow uniform.
    pub shadows: ShadowPlan,
    /// Indices into the scene's draws, in the order the camera passes draw them: opaque
    /// and masked ones, then from `transparent_from` the alpha-blended ones.
    pub camera_draws: Vec<u32>,
    /// Where the transmissive (KHR_materials_transmission) solids start in
    /// `camera_draws`; they end where the transparent draws start.
    pub transmissive_from: usize,
    /// Where the transparent draws start in `camera_draws`.
    pub transparent_from: usize,
    /// The forward pass's solid draws before the transmissive ones: every other solid on
    /// the forward path; on the deferred path the layered (KHR_materials_*) ones, shaded
    /// again over the G-buffer's light. The pass then draws the transmissive solids and
    /// the transparent draws.
    pub forward_draws: Vec<u32>,
    /// The forward path's opaque (not alpha-tested) draws, which a depth prepass draws
    /// first; empty on the deferred path.
    pub prepass_draws: Vec<u32>,
    /// The deferred path's light volumes: one full-screen draw for every directional
    /// light, then one volume per point and spot light.
    pub volumes: Vec<VolumeDraw>,
    /// Per scene light, its cookie's layer.
    cookie_layers: Vec<Option<u32>>,
    /// Per scene light, the shadow mask channel it reads: the bake's, unless the mixed
    /// mode (baked-indirect) uses no masks.
    mask_channels: Vec<Option<u8>>,
    /// Per scene light (by `LightId`), its index in `lights`, if the frame shades it.
    frame_index: Vec<Option<u32>>,
    /// Directional lights over the limit, and visible point and spot lights over
    /// `max_other_lights`, not shaded.
    pub dropped_directional: usize,
    /// See `dropped_directional`.
    pub dropped_local: usize,
    /// `shadows.cache`: tiles whose content is unchanged keep last frame's depths.
    pub shadow_cache: bool,
    /// How the forward pass finds its point and spot lights, and the lists it reads.
    pub culling: LightCulling,
    /// The culled lists of `culling` (empty when it is `none`).
    pub culled: CulledLights,
    /// Samples per pixel of the forward path's colour and depth (1 on the deferred path
    /// and with AOVs).
    pub msaa: u32,
    /// Whether the deferred path smooths the lit image's edges with FXAA: where the
    /// forward path would have MSAA (so both paths at their defaults antialias), with no
    /// G-buffer debug view.
    pub fxaa: bool,
    /// What the forward pass's shader needs compiled in.
    pub features: features::ShaderFeatures,
    /// The environment is drawn behind the scene (`[environment] background`).
    pub environment_background: bool,
    /// A frame that only marks the virtual pages its pixels want (the depth prepass, the
    /// contact depth pass and the marking pass run; `Renderer` makes it from the frame's
    /// plan with `marking_plan`).
    pub marks_pages: bool,
    /// What the shadow atlases hold once this frame is drawn (tile placement, tiers and
    /// the tile cache): the plan only reads the renderer's, and the renderer keeps this
    /// one (`take_atlas_update`) once the frame is submitted, so that a frame that fails
    /// before it is submitted leaves the cache as it was.
    atlas_update: ShadowAtlasTiles,
}

/// Per scene light, the shadow mask channel it reads: the bake's, unless the mixed mode
/// (baked-indirect) uses no masks.
fn mask_channels(scene: &Scene, settings: &Settings) -> Vec<Option<u8>> {
    let used = settings.lighting.mixed_mode.uses_shadow_mask();
    (0..scene.lights.len()).map(|i| scene.baked.as_ref().and_then(|b| b.channel(i)).filter(|_| used)).collect()
}

/// The frame's lights in shading order, the lists by kind, and per light whether its loop
/// needs a shadow lookup.
struct ShadedList {
    lights: Vec<FrameLight>,
    lists: ShadedLights,
    shadowed: Vec<bool>,
}

/// Directional lights first, then the chosen point and spot lights; the forward lists (all
/// of the forward path's lights, the deferred path's transparent surfaces) take the most
/// important `MAX_LOCAL_LIGHTS` of those.
fn shaded_lights(
    choice: &LightChoice,
    slots: &ShadowSlots,
    mask_channels: &[Option<u8>],
    is_area: &[bool],
) -> ShadedList {
    let mut out = ShadedList {
        lights: Vec::with_capacity(choice.directional.len() + choice.local.len()),
        lists: ShadedLights::default(),
        shadowed: Vec::new(),
    };
    for (&id, &shadow) in choice.directional.iter().zip(&slots.directional) {
        out.lists.directional.push(out.lights.len() as u32);
        out.lights.push(FrameLight { id, range: f32::INFINITY, shadow });
        out.shadowed.push(true);
    }
    for (k, (&(id, range), &shadow)) in choice.local.iter().zip(&slots.local).enumerate() {
        // A light with a shadow mask channel has a shadow even without tiles. Area
        // lights are shaded in the loop that reads whole lights, shadowed or not (the
        // other reads only what a point or spot light needs).
        let masked = mask_channels[id.index()].is_some();
        let has_shadow = matches!(shadow, ShadowSlot::Realtime { .. }) || masked || is_area[id.index()];
        if k < MAX_LOCAL_LIGHTS {
            let list = if has_shadow { &mut out.lists.shadowed_local } else { &mut out.lists.unshadowed_local };
            list.push(out.lights.len() as u32);
        }
        out.lights.push(FrameLight { id, range, shadow });
        out.shadowed.push(has_shadow);
    }
    out
}

/// The deferred path's light draws: the directional lights share one full-screen draw,
/// each point and spot light has its volume.
fn light_volumes(scene: &Scene, view: &View, lights: &[FrameLight], lists: &ShadedLights) -> Vec<VolumeDraw> {
    let directional = lists.directional.first().map(|&k| VolumeDraw::screen(k));
    let locals = lights
        .iter()
        .enumerate()
        .skip(lists.directional.len())
        .map(|(k, l)| light_volume(&scene.lights[l.id.index()], l.range, view, k as u32));
    directional.into_iter().chain(locals).collect()
}

/// The forward path's MSAA samples and whether the deferred path runs FXAA. AOVs and ids
/// test against single-sampled depth, and the G-buffer has one sample; the deferred path
/// smooths its edges where the forward path would multisample.
fn antialiasing(request: &PlanRequest, path: RenderPath, settings: &Settings) -> (u32, bool) {
    let pixel_exact = request.aovs || request.shadow_aovs || request.ids;
    let msaa = if pixel_exact || path == RenderPath::Deferred { 1 } else { settings.render.msaa };
    let fxaa = path == RenderPath::Deferred
        && !pixel_exact
        && settings.render.msaa > 1
        && request.debug.is_none()
        && settings.render.deferred_antialiasing == DeferredAntialiasing::Fxaa;
    (msaa, fxaa)
}

impl FramePlan {
    /// Plans a frame of `scene` (whose draws are `draws`, see `draws::scene_draws`).
    /// `atlases` is what the shadow atlases hold from earlier frames; it is only read: the
    /// plan carries what they will hold after this frame (`take_atlas_update`).
    pub fn new(
        scene: &Scene,
        draws: &[Draw],
        view: &View,
        settings: &Settings,
        atlases: &ShadowAtlasTiles,
        request: PlanRequest,
    ) -> FramePlan {
        let mut atlases = atlases.clone();
        let choice = choose_lights(scene, view, settings);
        let mask_channels = mask_channels(scene, settings);
        let (mut shadows, slots) =
            plan_shadows(scene, draws, view, settings, &choice.directional, &choice.local, &mut atlases);
        let is_area: Vec<bool> = scene.lights.iter().map(Light::is_area).collect();
        let ShadedList { lights, lists, shadowed } = shaded_lights(&choice, &slots, &mask_channels, &is_area);
        let path = if request.deferred_view().is_some() { RenderPath::Deferred } else { settings.render.path };
        let light_buffer = settings.render.light_buffer;
        let mut frame_index = vec![None; scene.lights.len()];
        for (k, light) in lights.iter().enumerate() {
            frame_index[light.id.index()] = Some(k as u32);
        }
        let (eye, forward) = (view.eye(), view.forward());
        let camera_draws = if view.is_orthographic() {
            camera_draw_order(draws, |p| (p - eye).dot(forward))
        } else {
            camera_draw_order(draws, |p| p.distance_squared(eye))
        };
        let transparent_from =
            camera_draws.iter().take_while(|&&d| draws[d as usize].alpha_mode != AlphaMode::Blend).count();
        let transmissive_from =
            camera_draws[..transparent_from].iter().take_while(|&&d| !draws[d as usize].transmissive).count();
        let volumes = match path {
            RenderPath::Forward => Vec::new(),
            RenderPath::Deferred => light_volumes(scene, view, &lights, &lists),
        };
        // The deferred path draws a depth prepass only where the depth is copied before its
        // G-buffer pass (`has_depth_prepass`): for ambient occlusion, which that pass's
        // indirect light reads, and contact shadows.
        let prepass_draws =
            if path == RenderPath::Forward || settings.ambient_occlusion.enabled || settings.shadows.contact {
                camera_draws[..transmissive_from]
                    .iter()
                    .copied()
                    .filter(|&d| draws[d as usize].alpha_mode == AlphaMode::Opaque)
                    .collect()
            } else {
                Vec::new()
            };
        let culling = settings.lights.culling;
        let forward_draws: Vec<u32> = match path {
            RenderPath::Forward => camera_draws[..transmissive_from].to_vec(),
            RenderPath::Deferred => {
                camera_draws[..transmissive_from].iter().copied().filter(|&d| draws[d as usize].layered).collect()
            }
        };
        let shaded_forward: Vec<u32> =
            forward_draws.iter().chain(&camera_draws[transmissive_from..]).copied().collect();
        let culled = if shaded_forward.is_empty() {
            CulledLights::default()
        } else {
            let first_local = lists.directional.len();
            cull_lights(culling, scene, draws, &shaded_forward, view, &lights, first_local, &shadowed)
        };
        let (msaa, fxaa) = antialiasing(&request, path, settings);
        // A debug view of the G-buffer shades nothing, so it draws no shadow tiles (and
        // the cache keeps what the atlases hold for the next lit frame).
        shadows.redraw = if request.deferred_view().is_some() {
            vec![false; shadows.tiles.len()]
        } else {
            atlases.cache.redraws(&shadows, draws, settings.shadows.cache)
        };
        let mut features = features::ShaderFeatures::of(scene, settings, &lights, &shadowed[lists.directional.len()..]);
        features.tinted_shadows = shadows.tiles.iter().any(|tile| !tile.tint_casters.is_empty());
        // Without the contact depth pass no shader may march (the shadow AOV's and the
        // light volumes' are specialised to the features too; this guards any that is not).
        if !features.contact_shadows {
            shadows.gpu.contact.steps = 0;
        }
        FramePlan {
            view: *view,
            request,
            path,
            light_buffer,
            tone_mapping: settings.render.tone_mapping,
            ambient_occlusion: settings.ambient_occlusion.clone(),
            lights,
            lists,
            shadows,
            camera_draws,
            transmissive_from,
            transparent_from,
            forward_draws,
            prepass_draws,
            volumes,
            cookie_layers: cookie_slots(scene).into_iter().map(|slot| slot.map(|(_, layer)| layer)).collect(),
            mask_channels,
            frame_index,
            dropped_directional: choice.dropped_directional,
            dropped_local: choice.selection.dropped,
            shadow_cache: settings.shadows.cache,
            culling,
            culled,
            msaa,
            environment_background: settings.environment.enabled_for(scene) && settings.environment.background,
            fxaa,
            features,
            marks_pages: false,
            atlas_update: atlases,
        }
    }

    /// Whether the scene depth is copied to the view depth buffer (contact shadows, the
    /// virtual pages' marking) and so must be sampled; the marking frame and the frame
    /// it marks for make their depth targets alike, so that neither makes them anew.
    pub fn samples_scene_depth(&self) -> bool {
        self.features.contact_shadows || self.shadows.virtual_maps.is_active() || self.features.ambient_occlusion
    }

    /// Whether the contact depth pass copies the scene depth into group 0's view depth
    /// buffer: for contact shadows, the virtual pages' marking and ambient occlusion.
    pub fn copies_scene_depth(&self) -> bool {
        self.features.contact_shadows || self.marks_pages || self.features.ambient_occlusion
    }

    /// Whether the scene depth is drawn before anything is shaded: always on the forward
    /// path, on the deferred path where the depth is copied for the passes that run
    /// before the G-buffer pass (the contact depth copy, ambient occlusion, which the
    /// G-buffer pass's indirect light reads; passes run in list order).
    pub fn has_depth_prepass(&self) -> bool {
        self.path == RenderPath::Forward || self.copies_scene_depth()
    }

    /// Whether the frame has virtual pages to place before it is drawn: it shades (a
    /// G-buffer view does not) from virtual maps.
    pub fn wants_pages(&self) -> bool {
        self.shadows.virtual_maps.is_active() && self.request.deferred_view().is_none() && !self.marks_pages
    }

    /// The frame that marks this one's virtual pages: the same view and draws, its
    /// opaque surfaces' depth (single-sampled, the forward path's prepass on either path).
    pub fn marking_plan(&self, draws: &[Draw]) -> FramePlan {
        let mut plan = self.clone();
        plan.path = RenderPath::Forward;
        plan.msaa = 1;
        plan.marks_pages = true;
        // Marking reads the depth alone.
        plan.features.ambient_occlusion = false;
        plan.prepass_draws = (0..self.camera_draws.len())
            .filter(|&k| self.marked_by_prepass(draws, k))
            .map(|k| self.camera_draws[k])
            .collect();
        plan.shadows.redraw = vec![false; plan.shadows.tiles.len()];
        plan
    }

    /// What the marking frame's requests depend on: the view, the virtual maps, the shadow
    /// distance and the opaque surfaces the camera sees. Equal keys, equal requests: a
    /// still frame need not mark its pages again.
    pub fn marking_key(&self, draws: &[Draw]) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::hash::DefaultHasher::new();
        let view = &self.view;
        (view.width, view.height).hash(&mut h);
        view.world_from_view.to_cols_array().map(f32::to_bits).hash(&mut h);
        view.clip_from_view.to_cols_array().map(f32::to_bits).hash(&mut h);
        bytemuck::cast_slice::<_, u8>(&self.shadows.virtual_maps.maps).hash(&mut h);
        self.shadows.gpu.fade.inverse_max_distance.to_bits().hash(&mut h);
        for (k, &d) in self.camera_draws[..self.transmissive_from].iter().enumerate() {
            (self.marked_by_prepass(draws, k), draws[d as usize].caster_key).hash(&mut h);
        }
        h.finish()
    }

    /// Whether the marking frame's opaque prepass draws `camera_draws[k]`: an opaque
    /// solid before the transmissive ones. The pixels of the others mark no page.
    fn marked_by_prepass(&self, draws: &[Draw], k: usize) -> bool {
        k < self.transmissive_from && draws[self.camera_draws[k] as usize].alpha_mode == AlphaMode::Opaque
    }

    /// Places the pages the marking frame asked for (`requests`, a bit per page-table
    /// entry), and decides which are drawn again (the tile cache).
    pub fn place_virtual_pages(&mut self, draws: &[Draw], requests: &[u32]) {
        // The surfaces the marking frame's opaque prepass leaves out.
        let unmarked: Vec<chiaro_math::Aabb> = (0..self.camera_draws.len())
            .filter(|&k| !self.marked_by_prepass(draws, k))
            .map(|k| draws[self.camera_draws[k] as usize].bounds_ws)
            .collect();
        let pages = &mut self.atlas_update.virtual_pages;
        virtual_shadows::place_pages(&mut self.shadows, draws, requests, &unmarked, pages);
        self.shadows.redraw = self.atlas_update.cache.redraws(&self.shadows, draws, self.shadow_cache);
    }

    /// What the shadow atlases hold once this frame is drawn, for the renderer to keep
    /// after it submits the frame (the plan then holds an empty update).
    pub fn take_atlas_update(&mut self) -> ShadowAtlasTiles {
        std::mem::take(&mut self.atlas_update)
    }

    /// The shadow mask channel the light with `id` reads this frame.
    pub fn mask_channel(&self, id: LightId) -> Option<u8> {
        self.mask_channels.get(id.index()).copied().flatten()
    }

    /// How many lights the scene has (shaded this frame or not).
    pub fn scene_light_count(&self) -> usize {
        self.frame_index.len()
    }

    /// Where the light with `id` sits in `lights`, if the frame shades it.
    pub fn light_index(&self, id: LightId) -> Option<usize> {
        self.frame_index.get(id.index()).copied().flatten().map(|k| k as usize)
    }

    /// The point and spot lights the forward lists shade (all the frame shades on the
    /// forward path; the deferred path's volumes shade every light in `lights`).
    pub fn local_light_count(&self) -> usize {
        self.lists.shadowed_local.len() + self.lists.unshadowed_local.len()
    }

    /// Every point and spot light the frame shades.
    pub fn shaded_local_lights(&self) -> usize {
        self.lights.len() - self.lists.directional.len()
    }

    /// The `k`th light as the shaders read it.
    pub fn gpu_light(&self, scene: &Scene, k: usize) -> GpuLight {
        let l = &self.lights[k];
        let channel = self.mask_channel(l.id);
        gpu_light(&scene.lights[l.id.index()], l, self.cookie_layers.get(l.id.index()).copied().flatten(), channel)
    }

    /// The forward light buffer: the lights the lists index, in the order of `lights`
    /// (the directional ones and the most important point and spot lights come first).
    pub fn gpu_lights(&self, scene: &Scene) -> Vec<GpuLight> {
        self.gpu_lights_up_to(scene, MAX_FRAME_LIGHTS as usize)
    }

    /// Culled lists read their lights from their texel table: too many for the uniform.
    pub fn lights_in_table(&self) -> bool {
        self.lights.len() > MAX_UNIFORM_LIGHTS as usize
    }

    /// The first `count` lights the frame shades (all of them, if fewer), as the shaders
    /// read them.
    pub fn gpu_lights_up_to(&self, scene: &Scene, count: usize) -> Vec<GpuLight> {
        let mut lights = Vec::new();
        self.write_gpu_lights(scene, count, &mut lights);
        lights
    }

    /// `gpu_lights_up_to` into `out` (cleared first), so that a renderer reuses one
    /// allocation from frame to frame.
    pub fn write_gpu_lights(&self, scene: &Scene, count: usize, out: &mut Vec<GpuLight>) {
        out.clear();
        out.extend((0..self.lights.len().min(count)).map(|k| self.gpu_light(scene, k)));
    }

    /// The light volumes as the deferred light pass reads them.
    pub fn gpu_volumes(&self, scene: &Scene) -> Vec<GpuVolumeLight> {
        self.volumes
            .iter()
            .map(|v| GpuVolumeLight {
                world_from_volume: v.world_from_volume,
                light: self.gpu_light(scene, v.light as usize),
            })
            .collect()
    }

    /// The frame uniform for this plan and `settings` (exposure, ambient, culling grid).
    pub fn gpu_frame(&self, settings: &Settings) -> GpuFrame {
        let view = &self.view;
        GpuFrame {
            clip_from_world: view.clip_from_world(),
            view_from_world: view.view_from_world(),
            world_from_view: view.world_from_view,
            view_from_clip: view.clip_from_view.inverse(),
            camera_position_ws: view.eye(),
            exposure_scale: exposure_scale(settings.render.exposure_ev100),
            ambient: Vec3::from(settings.render.ambient),
            debug_view: if self.request.debug == Some(DebugView::Cascades) {
                DEBUG_VIEW_CASCADES
            } else {
                DEBUG_VIEW_NONE
            },
            directional_light_count: self.lists.directional.len() as u32,
            shadowed_local_light_count: self.lists.shadowed_local.len() as u32,
            local_light_count: self.local_light_count() as u32,
            width: view.width,
            height: view.height,
            mixed_mode: match settings.lighting.mixed_mode {
                MixedMode::BakedIndirect => MIXED_MODE_BAKED_INDIRECT,
                MixedMode::Shadowmask => MIXED_MODE_SHADOWMASK,
                MixedMode::DistanceShadowmask => MIXED_MODE_DISTANCE_SHADOWMASK,
            },
            cluster_tile_width: self.culled.grid.map_or(1, |g| g.tile_width),
            cluster_tile_height: self.culled.grid.map_or(1, |g| g.tile_height),
            cluster_slice_scale: self.culled.grid.map_or(0.0, |g| g.slice_params().0),
            cluster_slice_bias: self.culled.grid.map_or(0.0, |g| g.slice_params().1),
            cluster_tiles_x: self.culled.grid.map_or(1, |g| g.tiles_x),
            cluster_tiles_y: self.culled.grid.map_or(1, |g| g.tiles_y),
            orthographic: view.is_orthographic() as u32,
            _pad: [0; 3],
        }
    }
}

impl fmt::Display for FramePlan {
    /// One line per light, then the shadow tiles (those drawn again marked) and the
    /// light culling.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "frame plan: {:?} path, {}x{}, {} lights ({} directional, {} shadowed point/spot, {} other), {} draws",
            self.path,
            self.view.width,
            self.view.height,
            self.lights.len(),
            self.lists.directional.len(),
            self.lists.shadowed_local.len(),
            self.lists.unshadowed_local.len(),
            self.camera_draws.len()
        )?;
        for (i, light) in self.lights.iter().enumerate() {
            writeln!(f, "  light {i}: scene light {} range {:.2} shadow {:?}", light.id.0, light.range, light.shadow)?;
        }
        let s = &self.shadows;
        writeln!(
            f,
            "  shadow tiles: {}, {} drawn this frame (atlases {} and {} texels{})",
            s.tiles.len(),
            s.redraw.iter().filter(|&&r| r).count(),
            s.directional_atlas_size,
            s.local_atlas_size,
            if s.tiles_kept { ", tiles kept from the last frame" } else { "" }
        )?;
        for (t, redraw) in s.tiles.iter().zip(&s.redraw) {
            writeln!(
                f,
                "    {:?} tile {} light {} viewport {:?}, {} casters{}",
                t.atlas,
                t.tile,
                t.light.0,
                t.viewport,
                t.casters.len(),
                if *redraw { ", drawn" } else { ", kept" }
            )?;
        }
        let lists = &self.culled.lists;
        if !lists.is_empty() {
            let longest = (0..lists.len()).map(|k| lists.count(k)).max().unwrap_or(0);
            let used = (0..lists.len()).filter(|&k| lists.count(k) > 0).count();
            writeln!(
                f,
                "  {:?} light culling: {} lists ({} not empty), {} entries, longest {}",
                self.culling,
                lists.len(),
                used,
                lists.indices.len(),
                longest
            )?;
        }
        Ok(())
    }
}
