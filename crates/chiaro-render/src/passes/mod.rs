//! One module per pass, each owning its pipelines and bind group layouts and declaring,
//! in its `setup`, the targets it makes, reads and writes: the shadow atlases, the depth
//! prepass, the contact shadows' depth copy, forward lighting, the deferred path's
//! G-buffer, light volumes, LDR decoding and debug views, the deferred path's FXAA, the
//! AOVs, the per-light shadow AOV and tone mapping. `list.rs` names them all;
//! `fullscreen` and `mesh` are helpers they share.

use crate::graph::{FramePass, PassDeclaration, PassInit, PassType};

pub mod background;
pub mod fullscreen;
pub mod mesh;
pub mod opaque_copy;
pub mod targets;

include!("list.rs");

macro_rules! declare_passes {
    ($($module:ident: $ty:ident [$($artifact:literal),*],)*) => {
        $(pub mod $module;)*

        /// Every pass's name and setup, in list order: enough to compile a frame's graph
        /// without a device.
        pub const DECLARATIONS: &[PassDeclaration] = &[$(PassDeclaration {
            name: <$module::$ty as PassType>::NAME,
            setup: <$module::$ty as PassType>::setup,
        }),*];

        /// Makes every pass, in list order.
        pub fn make_all(init: &PassInit<'_>) -> Vec<Box<dyn FramePass>> {
            vec![$(Box::new(<$module::$ty as PassType>::new(init))),*]
        }

        /// The composed WGSL of every shader artifact the passes use, by name.
        pub fn shader_sources() -> Vec<(&'static str, &'static str)> {
            let mut sources: Vec<(&'static str, &'static str)> =
                vec![$($(($artifact, crate::wgsl!($artifact))),*),*];
            sources.push(("environment_bake", crate::wgsl!("environment_bake")));
            debug_assert_eq!(SETUP_ARTIFACTS, ["environment_bake"], "each setup artifact is listed here");
            sources.sort();
            sources.dedup();
            sources
        }
    };
}

frame_passes!(declare_passes);

/// The passes of a frame that marks virtual pages (`FramePlan::marks_pages`): the shadow
/// pass (whose persistent atlases group 0 binds; it draws nothing), the depth prepass,
/// the contact depth copy and the marking. Every other pass declares nothing.
pub fn marking_declarations() -> Vec<PassDeclaration> {
    const KEPT: [&str; 4] = [
        shadows::ShadowPass::NAME,
        depth_prepass::DepthPrepassPass::NAME,
        contact_depth::ContactDepthPass::NAME,
        virtual_marking::VirtualMarkingPass::NAME,
    ];
    fn nothing(_: &crate::plan::FramePlan, _: &mut crate::graph::PassSetup) {}
    DECLARATIONS
        .iter()
        .map(|d| if KEPT.contains(&d.name) { *d } else { PassDeclaration { name: d.name, setup: nothing } })
        .collect()
}
