//! The frame plan: everything a frame will do, decided on the CPU before anything is
//! recorded. A scene, its draws, a view and the settings flow in; the lights the frame
//! shades (with stable ids), their light lists and shadow slots, the shadow tiles with
//! their casters, the camera's draw order and the passes to run flow out. Passes only
//! record what the plan says, and tests inspect plans without a GPU.

pub mod draws;
pub mod lights;
pub mod shadows;

use crate::gpu::{GpuFrame, GpuLight};
use crate::shader_constants::{DEBUG_VIEW_CASCADES, DEBUG_VIEW_NONE};
use crate::view::View;
use chiaro_math::tonemap::exposure_scale;
use chiaro_scene::{Scene, Settings};
use draws::{Draw, camera_draw_order};
use glam::Vec3;
use lights::{FrameLight, LightId, choose_lights, gpu_light};
use shadows::{ShadowAtlasTiles, ShadowPlan, ShadowSlot, plan_shadows};
use std::fmt;

/// The passes a frame can run, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PassId {
    /// Casters into both shadow atlases.
    Shadows,
    /// Every light over every visible draw into the HDR target.
    Forward,
    /// World position, normal and view depth.
    Aov,
    /// The HDR target to the display-referred output.
    Tonemap,
    /// One light's shadow term (run once per light, after the frame).
    ShadowAov,
}

impl PassId {
    pub fn name(self) -> &'static str {
        match self {
            PassId::Shadows => "shadows",
            PassId::Forward => "forward",
            PassId::Aov => "aov",
            PassId::Tonemap => "tonemap",
            PassId::ShadowAov => "shadow aov",
        }
    }
}

/// What the caller wants from the frame besides the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanRequest {
    /// World position, normal and depth AOVs.
    pub aovs: bool,
    /// Tint by cascade.
    pub debug_cascades: bool,
}

/// The frame's lights as index lists into `FramePlan::lights`; the shaders loop over
/// them in this order (directional, shadowed point and spot, the other point and spot).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LightLists {
    pub directional: Vec<u32>,
    pub shadowed_other: Vec<u32>,
    pub unshadowed_other: Vec<u32>,
}

impl LightLists {
    /// The lists one after the other, as the light index buffer holds them.
    pub fn concatenated(&self) -> Vec<u32> {
        [&self.directional[..], &self.shadowed_other, &self.unshadowed_other].concat()
    }
}

#[derive(Clone, Debug)]
pub struct FramePlan {
    pub view: View,
    pub request: PlanRequest,
    /// Every light the frame shades: the directional ones in scene order, then the point
    /// and spot lights most important first.
    pub lights: Vec<FrameLight>,
    pub lists: LightLists,
    pub shadows: ShadowPlan,
    /// Indices into the scene's draws, in the order the camera passes draw them.
    pub camera_draws: Vec<u32>,
    pub passes: Vec<PassId>,
    /// Per scene light (by `LightId`), its index in `lights`, if the frame shades it.
    frame_index: Vec<Option<u32>>,
    /// Directional lights over the limit, and visible point and spot lights over
    /// `max_other_lights`, not shaded.
    pub dropped_directional: usize,
    pub dropped_other: usize,
}

impl FramePlan {
    /// Plans a frame of `scene` (whose draws are `draws`, see `draws::scene_draws`).
    /// `atlases` carries the shadow tiles over from the previous frame.
    pub fn new(
        scene: &Scene,
        draws: &[Draw],
        view: &View,
        settings: &Settings,
        atlases: &mut ShadowAtlasTiles,
        request: PlanRequest,
    ) -> FramePlan {
        let choice = choose_lights(scene, view, settings);
        let (shadows, slots) = plan_shadows(scene, draws, view, settings, &choice.directional, &choice.other, atlases);
        let mut lights = Vec::with_capacity(choice.directional.len() + choice.other.len());
        let mut lists = LightLists::default();
        for (&id, &shadow) in choice.directional.iter().zip(&slots.directional) {
            lists.directional.push(lights.len() as u32);
            lights.push(FrameLight { id, range: f32::INFINITY, shadow });
        }
        for (&(id, range), &shadow) in choice.other.iter().zip(&slots.other) {
            let list = match shadow {
                ShadowSlot::Realtime { .. } => &mut lists.shadowed_other,
                _ => &mut lists.unshadowed_other,
            };
            list.push(lights.len() as u32);
            lights.push(FrameLight { id, range, shadow });
        }
        let mut frame_index = vec![None; scene.lights.len()];
        for (k, light) in lights.iter().enumerate() {
            frame_index[light.id.index()] = Some(k as u32);
        }
        let mut passes = Vec::new();
        if !shadows.tiles.is_empty() {
            passes.push(PassId::Shadows);
        }
        passes.push(PassId::Forward);
        if request.aovs {
            passes.push(PassId::Aov);
        }
        passes.push(PassId::Tonemap);
        FramePlan {
            view: *view,
            request,
            lights,
            lists,
            shadows,
            camera_draws: camera_draw_order(draws, view.eye()),
            passes,
            frame_index,
            dropped_directional: choice.dropped_directional,
            dropped_other: choice.selection.dropped,
        }
    }

    /// Where the light with `id` sits in `lights`, if the frame shades it.
    pub fn light_index(&self, id: LightId) -> Option<usize> {
        self.frame_index.get(id.index()).copied().flatten().map(|k| k as usize)
    }

    /// Where each of `lights` sits in the concatenated lists, the order the shaders see.
    pub fn list_positions(&self) -> Vec<u32> {
        let mut positions = vec![0; self.lights.len()];
        for (position, &light) in self.lists.concatenated().iter().enumerate() {
            positions[light as usize] = position as u32;
        }
        positions
    }

    /// The point and spot lights the frame shades.
    pub fn other_light_count(&self) -> usize {
        self.lists.shadowed_other.len() + self.lists.unshadowed_other.len()
    }

    /// The light buffer, in the order of `lights`.
    pub fn gpu_lights(&self, scene: &Scene) -> Vec<GpuLight> {
        self.lights.iter().map(|l| gpu_light(&scene.lights[l.id.index()], l)).collect()
    }

    pub fn gpu_frame(&self, settings: &Settings) -> GpuFrame {
        let view = &self.view;
        GpuFrame {
            clip_from_world: view.clip_from_world(),
            view_from_world: view.view_from_world(),
            camera_position_ws: view.eye(),
            exposure_scale: exposure_scale(settings.render.exposure_ev100),
            ambient: Vec3::from(settings.render.ambient),
            debug_view: if self.request.debug_cascades { DEBUG_VIEW_CASCADES } else { DEBUG_VIEW_NONE },
            directional_light_count: self.lists.directional.len() as u32,
            shadowed_other_light_count: self.lists.shadowed_other.len() as u32,
            other_light_count: self.other_light_count() as u32,
            _pad: 0,
        }
    }
}

impl fmt::Display for FramePlan {
    /// One line per light, then the shadow tiles and the passes.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "frame plan: {}x{}, {} lights ({} directional, {} shadowed point/spot, {} other), {} draws",
            self.view.width,
            self.view.height,
            self.lights.len(),
            self.lists.directional.len(),
            self.lists.shadowed_other.len(),
            self.lists.unshadowed_other.len(),
            self.camera_draws.len()
        )?;
        for (i, light) in self.lights.iter().enumerate() {
            writeln!(f, "  light {i}: scene light {} range {:.2} shadow {:?}", light.id.0, light.range, light.shadow)?;
        }
        let s = &self.shadows;
        writeln!(
            f,
            "  shadow tiles: {} (atlases {} and {} texels{})",
            s.tiles.len(),
            s.directional_atlas_size,
            s.other_atlas_size,
            if s.tiles_kept { ", tiles kept from the last frame" } else { "" }
        )?;
        for t in &s.tiles {
            writeln!(
                f,
                "    {:?} tile {} light {} viewport {:?}, {} casters",
                t.atlas,
                t.tile,
                t.light.0,
                t.viewport,
                t.casters.len()
            )?;
        }
        let passes: Vec<&str> = self.passes.iter().map(|p| p.name()).collect();
        write!(f, "  passes: {}", passes.join(", "))
    }
}
