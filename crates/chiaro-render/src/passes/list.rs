// The frame's passes, one line each: its module, its type, and the shader artifacts
// (top-level files of `shaders/`) it uses. Where two passes write the same target, the
// one listed first runs first; otherwise the graph orders and culls them. build.rs reads
// this list too, to compose each artifact. A new pass is a new module and one line here.
macro_rules! frame_passes {
    ($then:ident) => {
        $then! {
            shadows: ShadowPass ["shadow_caster"],
            depth_prepass: DepthPrepassPass ["forward"],
            contact_depth: ContactDepthPass ["contact_depth"],
            ambient_occlusion: AmbientOcclusionPass ["ambient_occlusion"],
            virtual_marking: VirtualMarkingPass ["virtual_marking"],
            gbuffer: GBufferPass ["gbuffer", "background"],
            deferred_lights: DeferredLightsPass ["deferred_light"],
            ldr_decode: LdrDecodePass ["ldr_decode"],
            forward: ForwardPass ["forward", "background", "opaque_copy"],
            fxaa: FxaaPass ["fxaa"],
            aov: AovPass ["aov"],
            id: IdPass ["id"],
            shadow_aov: ShadowAovPass ["shadow_aov"],
            tonemap: TonemapPass ["tonemap"],
            debug_view: DebugViewPass ["debug_view"],
        }
    };
}

// Shader artifacts no frame pass draws with: the compute passes that make an environment's
// maps when it is loaded (src/environment/).
const SETUP_ARTIFACTS: &[&str] = &["environment_bake"];
