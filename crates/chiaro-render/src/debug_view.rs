//! Debug views: what an image shows instead of the lit frame. One vocabulary serves
//! `chiaro render --debug`, the viewer's panel and `--debug`, and the frame plan: a view
//! flows in, and out come its names and the frame it needs (`DebugView::frame_options`).
//! Cascades and the deferred views are drawn by passes; the AOV, cluster, atlas and
//! reference views are read back and coloured by the caller.

use crate::output::FrameOptions;

/// One of the frame's AOVs, shown as an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AovView {
    /// World position, each axis across the scene's bounds.
    Position,
    /// World normal as `n * 0.5 + 0.5`.
    Normal,
    /// View depth, logarithmic between the nearest and farthest surface.
    Depth,
    /// Baked irradiance from the lightmaps and probes.
    Lightmap,
    /// One light's shadow term (index in the scene's lights): white lit, black shadowed.
    Shadow(usize),
}

/// What an image shows instead of the lit frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DebugView {
    /// The lit image tinted by directional shadow cascade (the forward path's shader).
    Cascades,
    /// The deferred path's G-buffer base colour.
    GbufferAlbedo,
    /// The deferred path's G-buffer shading normal as `n * 0.5 + 0.5`.
    GbufferNormal,
    /// How many light volumes shaded each pixel, as a heat map.
    LightOverdraw,
    /// Both shadow atlases, read back.
    ShadowAtlases,
    /// An AOV, read back.
    Aov(AovView),
    /// Lights per cluster of the clustered forward path, as a heat map.
    Clusters,
    /// False and missed shadows against the ray-traced reference.
    Reference,
    /// The virtual shadow maps' page table (`VirtualShadowPlan::page_table_image`).
    VirtualPages,
}

impl DebugView {
    /// Every view, with one shadow AOV per light (`lights` of them).
    pub fn all(lights: usize) -> Vec<DebugView> {
        let mut views = vec![
            DebugView::Cascades,
            DebugView::GbufferAlbedo,
            DebugView::GbufferNormal,
            DebugView::LightOverdraw,
            DebugView::Aov(AovView::Position),
            DebugView::Aov(AovView::Normal),
            DebugView::Aov(AovView::Depth),
            DebugView::Aov(AovView::Lightmap),
        ];
        views.extend((0..lights).map(|i| DebugView::Aov(AovView::Shadow(i))));
        views.extend([DebugView::Clusters, DebugView::ShadowAtlases, DebugView::Reference, DebugView::VirtualPages]);
        views
    }

    /// The name people read, in the viewer's panel.
    pub fn label(self) -> String {
        match self {
            DebugView::Aov(AovView::Shadow(i)) => format!("aov shadow of light {i}"),
            DebugView::Aov(_) => self.cli_name().expect("named").replace('-', " "),
            DebugView::ShadowAtlases => "shadow atlases".into(),
            DebugView::Reference => "disagreement with the reference".into(),
            DebugView::VirtualPages => "virtual shadow pages".into(),
            _ => self.cli_name().expect("named").into(),
        }
    }

    /// The name `--debug` takes (none for the per-light shadow AOVs).
    pub fn cli_name(self) -> Option<&'static str> {
        Some(match self {
            DebugView::Cascades => "cascades",
            DebugView::GbufferAlbedo => "gbuffer-albedo",
            DebugView::GbufferNormal => "gbuffer-normal",
            DebugView::LightOverdraw => "light-overdraw",
            DebugView::Aov(AovView::Position) => "aov-position",
            DebugView::Aov(AovView::Normal) => "aov-normal",
            DebugView::Aov(AovView::Depth) => "aov-depth",
            DebugView::Aov(AovView::Lightmap) => "aov-lightmap",
            DebugView::Aov(AovView::Shadow(_)) => return None,
            DebugView::Clusters => "clusters",
            DebugView::ShadowAtlases => "shadow-atlases",
            DebugView::Reference => "reference",
            DebugView::VirtualPages => "virtual-pages",
        })
    }

    /// Parses a `--debug` value: a `cli_name`, or `shadow-atlas` (as `chiaro render`
    /// has always called the atlases).
    pub fn parse(text: &str) -> Result<DebugView, String> {
        if text == "shadow-atlas" {
            return Ok(DebugView::ShadowAtlases);
        }
        let views = DebugView::all(0);
        views.iter().copied().find(|d| d.cli_name() == Some(text)).ok_or_else(|| {
            let names: Vec<&str> = views.iter().filter_map(|d| d.cli_name()).collect();
            format!("'{text}' is not a debug view (one of: {})", names.join(", "))
        })
    }

    /// Shown by the deferred path's debug view pass in place of the image.
    pub fn is_deferred(self) -> bool {
        matches!(self, DebugView::GbufferAlbedo | DebugView::GbufferNormal | DebugView::LightOverdraw)
    }

    /// What a frame must render and read back to show this view. The views drawn by
    /// passes go to the output without a wait; the others are read back.
    pub fn frame_options(self) -> FrameOptions {
        let debug = Some(self);
        match self {
            DebugView::Cascades | DebugView::GbufferAlbedo | DebugView::GbufferNormal | DebugView::LightOverdraw => {
                FrameOptions { debug, ..Default::default() }
            }
            // The reference is traced apart from the frame, which renders as usual; the page
            // table is the frame's plan.
            DebugView::Reference | DebugView::VirtualPages => FrameOptions::default(),
            DebugView::ShadowAtlases => FrameOptions { readback: true, read_shadow_atlas: true, ..Default::default() },
            DebugView::Aov(aov) => FrameOptions {
                aovs: true,
                shadow_aovs: matches!(aov, AovView::Shadow(_)),
                readback: true,
                ..Default::default()
            },
            DebugView::Clusters => FrameOptions { aovs: true, readback: true, ..Default::default() },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn debug_views_parse_from_their_names() {
        for d in DebugView::all(0) {
            let name = d.cli_name().expect("named");
            assert_eq!(DebugView::parse(name), Ok(d));
        }
        assert_eq!(DebugView::parse("shadow-atlas"), Ok(DebugView::ShadowAtlases));
        let error = DebugView::parse("wireframe").unwrap_err();
        assert!(error.contains("'wireframe'") && error.contains("cascades, "), "{error}");
    }

    #[test]
    fn only_the_views_drawn_by_passes_go_to_the_output_without_a_read_back() {
        for d in DebugView::all(2) {
            let drawn =
                matches!(d, DebugView::Cascades | DebugView::Reference | DebugView::VirtualPages) || d.is_deferred();
            assert_eq!(!d.frame_options().reads_back(), drawn, "{d:?}");
        }
    }
}
