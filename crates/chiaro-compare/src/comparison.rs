//! One view compared: renders a frame with its shadow AOVs (chiaro-render), traces the
//! same camera and resolution on the CPU (chiaro-trace), and judges each light's pixels
//! (`crate::verdict`) and, with ambient occlusion on, the AO (`crate::occlusion`). A scene, a view and settings flow in; a `ShadowComparison` (one
//! `LightReport` per scene light, the reference and the rendered AOVs) flows out.

use crate::environment::{EnvironmentPixels, EnvironmentReport, compare_environment};
use crate::occlusion::{OcclusionReport, compare_occlusion};
use crate::verdict::{
    EDGE_BAND_PX, JudgedLight, LightComparison, PixelVerdict, VisibilityError, classify_pixels, soft_shadow_report,
};
use chiaro_render::{FrameOptions, PreparedScene, RenderError, Renderer, ShadowStatus, View};
use chiaro_scene::{Scene, Settings, ShadowMode};
use chiaro_trace::{PixelCamera, REFERENCE_AO_RAYS, ShadowReference, trace_ambient_occlusion, trace_shadow_reference};
use glam::Vec3;

/// One light's verdict.
#[derive(Clone, Debug)]
pub struct LightReport {
    /// Index in `Scene::lights`.
    pub light: usize,
    pub comparison: LightComparison,
    /// For a light with contact-hardening (`pcss`) shadows: how far its rendered
    /// visibility is from the share of its disc the reference sees.
    pub visibility: Option<VisibilityError>,
    /// RGBA8 difference image: the verdicts' colours (`PixelVerdict::color`), or for a
    /// `pcss` light the signed difference (`verdict::signed_difference_color`).
    pub difference: Vec<[u8; 4]>,
}

/// How a comparison judges, beyond the scene, view and settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CompareOptions {
    /// Pixels within this Chebyshev distance of a reference shadow edge are left out of
    /// the disagreement counts (`compare --edge-band`); 0 judges every pixel. The soft
    /// visibility errors never leave edges out: a penumbra is all edge.
    pub edge_band_px: usize,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions { edge_band_px: EDGE_BAND_PX }
    }
}

pub struct ShadowComparison {
    pub reports: Vec<LightReport>,
    pub reference: ShadowReference,
    /// The rendered shadow AOVs, per scene light.
    pub rendered: Vec<Vec<f32>>,
    /// Per scene light: whether a shadow map was sampled.
    pub status: Vec<ShadowStatus>,
    /// The environment's baked light against the traced environment, where the settings
    /// name an environment.
    pub environment: Option<EnvironmentReport>,
    /// The rendered ambient occlusion against the traced one, where `[ambient_occlusion]
    /// enabled`.
    pub occlusion: Option<OcclusionReport>,
}

/// Why a light with `status` is not judged against the reference; `None` when it is.
pub fn not_compared_because(status: ShadowStatus) -> Option<&'static str> {
    match status {
        ShadowStatus::Mapped | ShadowStatus::MaskOnly => None,
        ShadowStatus::Off => Some("casts no shadows"),
        ShadowStatus::NotShaded => Some("not shaded this frame"),
        ShadowStatus::NoTile => Some("no free atlas tiles: no realtime shadow"),
        ShadowStatus::Baked => Some("baked: its shadows are in the lightmaps, summed with other light; not compared"),
    }
}

/// The GPU half of a comparison: what the renderer drew for one view, read back.
/// `compare_rendered` finishes it on the CPU, on any thread.
pub struct RenderedShadows {
    /// World position of each pixel's surface; `None` where no surface is.
    pub positions: Vec<Option<Vec3>>,
    /// Per scene light, each pixel's shadow term.
    pub shadow_aovs: Vec<Vec<f32>>,
    pub status: Vec<ShadowStatus>,
    /// The frame itself, tone-mapped RGBA8, for showing the verdicts over it.
    pub ldr: Vec<u8>,
    /// Each pixel's shading normal, and the baked irradiance it read (the environment's
    /// comparison).
    pub normals: Vec<Vec3>,
    pub baked_irradiance: Vec<[f32; 3]>,
    /// The ambient occlusion the shading used, where `[ambient_occlusion] enabled`.
    pub ambient_occlusion: Option<Vec<f32>>,
}

/// Renders `view` with the shadow AOVs a comparison needs, waiting for the frame.
pub fn render_shadows(
    renderer: &mut Renderer,
    scene: &Scene,
    prepared: &PreparedScene,
    view: &View,
    settings: &Settings,
) -> Result<RenderedShadows, RenderError> {
    let frame = renderer.render(
        scene,
        prepared,
        view,
        settings,
        FrameOptions {
            aovs: true,
            shadow_aovs: true,
            readback: true,
            ambient_occlusion: settings.ambient_occlusion.enabled,
            ..Default::default()
        },
    )?;
    let status = frame.shadow_status(scene);
    let aovs = frame.aovs.expect("aovs were asked for");
    let positions = aovs.position_ws.iter().map(|p| p[0].is_finite().then(|| Vec3::from(*p))).collect();
    let normals = aovs.normal_ws.iter().map(|n| Vec3::from(*n)).collect();
    let ambient_occlusion = if settings.ambient_occlusion.enabled { frame.ambient_occlusion } else { None };
    Ok(RenderedShadows {
        ambient_occlusion,
        positions,
        shadow_aovs: frame.shadow_aovs,
        status,
        ldr: frame.ldr,
        normals,
        baked_irradiance: aovs.baked_irradiance,
    })
}

/// Traces the reference for `view` and judges each light's rendered shadows against it,
/// with the default options.
pub fn compare_rendered(
    scene: &Scene,
    view: &View,
    settings: &Settings,
    rendered: RenderedShadows,
) -> ShadowComparison {
    compare_rendered_with(scene, view, settings, rendered, CompareOptions::default())
}

/// `compare_rendered` with `options`.
pub fn compare_rendered_with(
    scene: &Scene,
    view: &View,
    settings: &Settings,
    rendered: RenderedShadows,
    options: CompareOptions,
) -> ShadowComparison {
    let ranges: Vec<f32> = scene.lights.iter().map(|l| l.shaded_range(settings.lights.range_threshold_lux)).collect();
    let camera = PixelCamera { clip_from_world: view.clip_from_world(), width: view.width, height: view.height };
    let reference = {
        let _span = tracing::info_span!("trace reference").entered();
        trace_shadow_reference(scene, &camera, &ranges)
    };
    let reports = scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| {
            let (shadow, positions) = (&rendered.shadow_aovs[i], &rendered.positions);
            // Classified once; the counts and the picture both come from the verdicts.
            let judged = JudgedLight {
                rendered_shadow: shadow,
                rendered_position: positions,
                reference: &reference,
                light_index: i,
                light,
                range: ranges[i],
                edge_band_px: options.edge_band_px,
            };
            let verdicts = classify_pixels(&judged);
            let comparison = LightComparison::from_verdicts(&verdicts);
            // Area lights are judged by visibility whatever their mode: the reference sees
            // the share of their shape.
            if light.shadow.mode == ShadowMode::Pcss || light.is_area() {
                let (visibility, difference) = soft_shadow_report(&judged);
                return LightReport { light: i, comparison, visibility: Some(visibility), difference };
            }
            LightReport {
                light: i,
                comparison,
                visibility: None,
                difference: verdicts.into_iter().map(PixelVerdict::color).collect(),
            }
        })
        .collect();
    let environment = compare_environment(
        scene,
        settings,
        &EnvironmentPixels {
            positions: &rendered.positions,
            normals: &rendered.normals,
            baked_irradiance: &rendered.baked_irradiance,
        },
    );
    let occlusion = rendered.ambient_occlusion.as_ref().map(|ao| {
        let _span = tracing::info_span!("trace ambient occlusion").entered();
        let traced = trace_ambient_occlusion(scene, &camera, settings.ambient_occlusion.radius, REFERENCE_AO_RAYS);
        compare_occlusion(ao, &rendered.positions, &traced)
    });
    ShadowComparison {
        reports,
        reference,
        rendered: rendered.shadow_aovs,
        status: rendered.status,
        environment,
        occlusion,
    }
}

/// Renders `view` and judges it against the traced reference, with the default options.
pub fn compare_shadows(
    renderer: &mut Renderer,
    scene: &Scene,
    prepared: &PreparedScene,
    view: &View,
    settings: &Settings,
) -> Result<ShadowComparison, RenderError> {
    compare_shadows_with(renderer, scene, prepared, view, settings, CompareOptions::default())
}

/// `compare_shadows` with `options`.
pub fn compare_shadows_with(
    renderer: &mut Renderer,
    scene: &Scene,
    prepared: &PreparedScene,
    view: &View,
    settings: &Settings,
    options: CompareOptions,
) -> Result<ShadowComparison, RenderError> {
    let rendered = render_shadows(renderer, scene, prepared, view, settings)?;
    Ok(compare_rendered_with(scene, view, settings, rendered, options))
}
