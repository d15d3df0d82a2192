//! Frame plans, inspected without a GPU: lights keep their ids and come in lists with the
//! shadowed ones apart, shadow slots say where each light's shadow comes from, atlas
//! tiles stay with their lights from frame to frame, and casters are culled per tile.

use chiaro_render::View;
use chiaro_render::graph::FrameGraph;
use chiaro_render::plan::draws::{Draw, GeometryLayout, scene_draws};
use chiaro_render::plan::lights::LightId;
use chiaro_render::plan::shadows::{ShadowAtlasTiles, ShadowSlot};
use chiaro_render::plan::{FramePlan, PlanRequest};
use chiaro_render::shader_constants::{SHADOW_SLOT_BAKED_ONLY, SHADOW_SLOT_NONE, SHADOW_SLOT_REALTIME};
use chiaro_scene::demo::demo_scene;
use chiaro_scene::{CastShadows, LightKind, Scene, Settings, ShadowMode};
use chiaro_testkit::{add_box, floor_scene, point_light, unlit_settings};
use glam::Vec3;

fn draws(scene: &Scene) -> Vec<Draw> {
    scene_draws(scene, &GeometryLayout::of(scene))
}

/// Plans a frame and keeps its atlas update in `atlases`, as the renderer does once the
/// frame is submitted.
fn plan(scene: &Scene, view: &View, atlases: &mut ShadowAtlasTiles, request: PlanRequest) -> FramePlan {
    let mut plan = FramePlan::new(scene, &draws(scene), view, &Settings::default(), atlases, request);
    *atlases = plan.take_atlas_update();
    plan
}

/// The first frame of `scene` from its camera, with no ambient term.
fn first_plan(scene: &Scene, request: PlanRequest) -> FramePlan {
    first_plan_with(scene, &unlit_settings(), request)
}

/// The first frame of `scene` from its camera, with `settings`.
fn first_plan_with(scene: &Scene, settings: &Settings, request: PlanRequest) -> FramePlan {
    let view = View::from_camera(scene, 0, 64, 64);
    FramePlan::new(scene, &draws(scene), &view, settings, &ShadowAtlasTiles::default(), request)
}

/// The frame graph of `plan`, compiled without a device.
fn graph(plan: &FramePlan) -> FrameGraph {
    let depth = chiaro_render::wgpu::TextureFormat::Depth32FloatStencil8;
    FrameGraph::compile(chiaro_render::passes::DECLARATIONS, plan, depth).expect("a valid graph")
}

/// The passes the frame graph runs for `plan`, in order.
fn passes(plan: &FramePlan) -> Vec<&'static str> {
    graph(plan).passes
}

fn slot_of(plan: &FramePlan, light: usize) -> ShadowSlot {
    plan.lights[plan.light_index(LightId(light as u32)).expect("shaded")].shadow
}

#[test]
fn the_demo_plans_lists_with_shadowed_lights_apart() {
    let scene = demo_scene(8);
    let view = View::from_camera(&scene, 0, 320, 180);
    let plan = plan(&scene, &view, &mut ShadowAtlasTiles::default(), PlanRequest::default());
    // The sun, then the eight others.
    assert_eq!(plan.lights.len(), 9);
    assert_eq!(plan.lists.directional, vec![0]);
    assert_eq!(plan.lights[0].id, LightId(0));
    // Four spots and two points cast shadows; two points do not.
    assert_eq!(plan.lists.shadowed_local.len(), 6);
    assert_eq!(plan.lists.unshadowed_local.len(), 2);
    for &i in &plan.lists.shadowed_local {
        assert!(matches!(plan.lights[i as usize].shadow, ShadowSlot::Realtime { .. }));
    }
    for &i in &plan.lists.unshadowed_local {
        let light = &scene.lights[plan.lights[i as usize].id.index()];
        assert_eq!(light.shadow.mode, ShadowMode::None, "{}", light.name);
        assert_eq!(plan.lights[i as usize].shadow, ShadowSlot::None);
    }
    // Lists keep importance order within themselves and cover every light once.
    let mut all = plan.lists.concatenated();
    assert_eq!(all.len(), 9);
    all.sort();
    assert_eq!(all, (0..9).collect::<Vec<u32>>());
    // The GPU records follow the lights and their slots.
    let gpu = plan.gpu_lights(&scene);
    assert_eq!(gpu.len(), 9);
    for (light, record) in plan.lights.iter().zip(&gpu) {
        let expected = match light.shadow {
            ShadowSlot::None => SHADOW_SLOT_NONE,
            ShadowSlot::Realtime { first_tile, .. } => {
                assert_eq!(record.shadow_first_tile, first_tile);
                SHADOW_SLOT_REALTIME
            }
            ShadowSlot::BakedOnly => SHADOW_SLOT_BAKED_ONLY,
        };
        assert_eq!(record.shadow_slot, expected);
        assert_eq!(record.position_ws, scene.lights[light.id.index()].position());
    }
    let frame = plan.gpu_frame(&Settings::default());
    assert_eq!((frame.directional_light_count, frame.shadowed_local_light_count, frame.local_light_count), (1, 6, 8));
    // Sixteen point/spot tiles and four cascades: every tile has a light and a viewport.
    assert_eq!(plan.shadows.tiles.len(), 4 + 16);
    assert_eq!(passes(&plan), vec!["shadows", "depth prepass", "forward", "tonemap"]);
    let printed = plan.to_string();
    assert!(printed.contains("9 lights") && printed.contains("20 drawn this frame"), "{printed}");
    let printed = graph(&plan).to_string();
    assert!(printed.contains("frame graph: shadows, depth prepass, forward, tonemap"), "{printed}");
    assert!(printed.contains("hdr: Rgba16Float View, 1 sample(s), 1 layer(s), Transient"), "{printed}");
}

#[test]
fn shadowed_lights_keep_their_tiles_from_frame_to_frame() {
    let scene = demo_scene(8);
    let mut atlases = ShadowAtlasTiles::default();
    let view = View::from_camera(&scene, 0, 320, 180);
    let first = plan(&scene, &view, &mut atlases, PlanRequest::default());
    // From elsewhere the lights rank differently, but the same ones cast shadows.
    let mut moved = scene.clone();
    moved.cameras[0].world_from_view =
        glam::Mat4::look_at_rh(Vec3::new(-9.0, 6.0, -3.0), Vec3::ZERO, Vec3::Y).inverse();
    let moved_view = View::from_camera(&moved, 0, 320, 180);
    let second = plan(&moved, &moved_view, &mut atlases, PlanRequest::default());
    let order = |p: &FramePlan| p.lists.shadowed_local.iter().map(|&i| p.lights[i as usize].id).collect::<Vec<_>>();
    assert_ne!(order(&first), order(&second), "the camera move must reorder the lights for this test to mean much");
    assert!(second.shadows.tiles_kept);
    for light in 0..scene.lights.len() {
        if first.light_index(LightId(light as u32)).is_some() {
            assert_eq!(slot_of(&first, light), slot_of(&second, light), "light {light}");
        }
    }
    // A light that stops casting changes the set: tiles are dealt out again.
    let mut fewer = moved.clone();
    let spot = fewer.lights.iter().position(|l| matches!(l.kind, LightKind::Spot { .. })).unwrap();
    fewer.lights[spot].shadow.mode = ShadowMode::None;
    let third = plan(&fewer, &moved_view, &mut atlases, PlanRequest::default());
    assert!(!third.shadows.tiles_kept);
    assert_eq!(slot_of(&third, spot), ShadowSlot::None);
    assert_eq!(third.lists.shadowed_local.len(), 5);
}

#[test]
fn a_plan_only_reads_the_atlases_until_its_update_is_kept() {
    let scene = demo_scene(8);
    let view = View::from_camera(&scene, 0, 320, 180);
    let atlases = ShadowAtlasTiles::default();
    let settings = Settings::default();
    let new_plan = |atlases: &ShadowAtlasTiles| {
        FramePlan::new(&scene, &draws(&scene), &view, &settings, atlases, PlanRequest::default())
    };
    // A frame planned and never submitted (its upload failed, say) leaves nothing cached:
    // the next plan draws every tile again.
    let dropped = new_plan(&atlases);
    assert!(!dropped.shadows.tiles.is_empty());
    let mut next = new_plan(&atlases);
    assert_eq!(next.shadows.redrawn_tiles().count(), next.shadows.tiles.len());
    // Kept, its update makes a still frame draw none.
    let kept = next.take_atlas_update();
    let still = new_plan(&kept);
    assert_eq!(still.shadows.redrawn_tiles().count(), 0);
}

#[test]
fn the_plan_says_which_shadow_tiles_are_drawn_again() {
    let mut scene = demo_scene(8);
    let mut atlases = ShadowAtlasTiles::default();
    let view = View::from_camera(&scene, 0, 320, 180);
    let drawn = |p: &FramePlan| p.shadows.redrawn_tiles().map(|(_, t)| t.light).collect::<Vec<_>>();
    let first = plan(&scene, &view, &mut atlases, PlanRequest::default());
    assert_eq!(drawn(&first).len(), first.shadows.tiles.len(), "the first frame draws every tile");
    let still = plan(&scene, &view, &mut atlases, PlanRequest::default());
    assert!(drawn(&still).is_empty(), "a still frame keeps every tile");
    assert!(!passes(&still).contains(&"shadows"), "and runs no shadow pass");
    // A moved shadowed spot draws its own tile again, and nothing else.
    let spot = first
        .shadows
        .tiles
        .iter()
        .map(|t| t.light.index())
        .find(|&i| matches!(scene.lights[i].kind, LightKind::Spot { .. }))
        .expect("a shadowed spot");
    let position = scene.lights[spot].position() + Vec3::new(0.2, 0.0, 0.0);
    scene.lights[spot].world_from_light =
        chiaro_math::rigid::looking_along(position, scene.lights[spot].direction() + Vec3::new(0.05, 0.0, 0.0));
    let moved = plan(&scene, &view, &mut atlases, PlanRequest::default());
    assert_eq!(drawn(&moved), [LightId(spot as u32)]);
    assert!(moved.to_string().contains("1 drawn this frame"), "{moved}");
    // A G-buffer view shades nothing: it draws no tile and leaves the cache as it was.
    let debug = PlanRequest { debug: Some(chiaro_render::DebugView::GbufferAlbedo), ..Default::default() };
    scene.lights[spot].world_from_light = chiaro_math::rigid::looking_along(position, Vec3::NEG_Y);
    assert!(drawn(&plan(&scene, &view, &mut atlases, debug)).is_empty());
    assert_eq!(drawn(&plan(&scene, &view, &mut atlases, PlanRequest::default())), [LightId(spot as u32)]);
}

#[test]
fn lights_that_find_no_tiles_are_baked_only() {
    // Three shadowed points want 18 tiles of 16.
    let lights = (0..3).map(|i| point_light(Vec3::new(i as f32 - 1.0, 1.0, 0.0), 10.0 + i as f32, Some(4.0))).collect();
    let scene = floor_scene(10.0, Vec3::new(0.0, 6.0, 0.01), lights);
    let all_fit = first_plan(&scene, PlanRequest::default());
    assert_eq!(all_fit.lists.shadowed_local.len(), 3, "the default 64 tiles hold all three");
    assert_eq!(all_fit.shadows.tiles.len(), 18);
    let mut settings = unlit_settings();
    settings.shadows.other.max_tiles = 16;
    let plan = first_plan_with(&scene, &settings, PlanRequest::default());
    let slots: Vec<ShadowSlot> = (0..3).map(|i| slot_of(&plan, i)).collect();
    // The brightest two fit; the dimmest (light 0) does not.
    assert_eq!(slots[0], ShadowSlot::BakedOnly);
    assert!(matches!(slots[1], ShadowSlot::Realtime { tile_count: 6, .. }));
    assert!(matches!(slots[2], ShadowSlot::Realtime { tile_count: 6, .. }));
    assert_eq!(plan.lists.shadowed_local.len(), 2);
    assert_eq!(plan.lists.unshadowed_local.len(), 1);
    let gpu = plan.gpu_lights(&scene);
    assert_eq!(gpu[plan.light_index(LightId(0)).unwrap()].shadow_slot, SHADOW_SLOT_BAKED_ONLY);
}

#[test]
fn each_tile_draws_only_the_casters_that_reach_it() {
    let light = point_light(Vec3::new(0.0, 1.0, 0.0), 10.0, Some(3.0));
    let mut scene = floor_scene(30.0, Vec3::new(0.0, 8.0, 0.01), vec![light]);
    add_box(&mut scene, Vec3::new(1.0, 0.5, 0.0), Vec3::ONE, 0.0, CastShadows::On); // draw 1: in range
    add_box(&mut scene, Vec3::new(10.0, 0.5, 0.0), Vec3::ONE, 0.0, CastShadows::On); // draw 2: out of range
    add_box(&mut scene, Vec3::new(-1.0, 0.5, 0.0), Vec3::ONE, 0.0, CastShadows::Off); // draw 3: casts none
    let plan = first_plan(&scene, PlanRequest { aovs: true, ..Default::default() });
    assert_eq!(plan.shadows.tiles.len(), 6);
    // The floor reaches every cube face; the box beside the light (all of it at x > 0.5)
    // only the faces it lies in front of: +X, not -X; the others never.
    for tile in &plan.shadows.tiles {
        assert_eq!(tile.casters[0], 0, "tile {}", tile.tile);
        assert!(tile.casters.iter().all(|&c| c <= 1), "tile {}: {:?}", tile.tile, tile.casters);
    }
    assert_eq!(plan.shadows.tiles[0].casters, vec![0, 1], "+X face");
    assert_eq!(plan.shadows.tiles[1].casters, vec![0], "-X face");
    assert_eq!(passes(&plan), vec!["shadows", "depth prepass", "forward", "aov", "tonemap"]);
    // With shadows off, no tile and no shadow pass.
    let mut unshadowed = scene.clone();
    unshadowed.lights[0].shadow.mode = ShadowMode::None;
    let plan = first_plan(&unshadowed, PlanRequest::default());
    assert!(plan.shadows.tiles.is_empty());
    assert_eq!(passes(&plan), vec!["depth prepass", "forward", "tonemap"]);
}

#[test]
fn the_passes_follow_the_path_the_light_buffer_and_the_debug_view() {
    use chiaro_render::DebugView;
    use chiaro_render::plan::volumes::VolumeShape;
    use chiaro_scene::{LightBuffer, RenderPath};
    let scene = chiaro_scene::demo::demo_scene(100);
    let view = View::from_camera(&scene, 0, 64, 64);
    let plan_with = |settings: &Settings, request| {
        FramePlan::new(&scene, &draws(&scene), &view, settings, &ShadowAtlasTiles::default(), request)
    };
    let mut settings = unlit_settings();
    settings.render.path = RenderPath::Forward;
    let forward = plan_with(&settings, PlanRequest::default());
    assert_eq!(passes(&forward), vec!["shadows", "depth prepass", "forward", "tonemap"]);
    assert!(forward.volumes.is_empty());
    assert!(forward.shaded_local_lights() > 64, "clustered culling shades every visible light");
    settings.lights.culling = chiaro_scene::LightCulling::None;
    let unculled = plan_with(&settings, PlanRequest::default());
    assert_eq!(unculled.shaded_local_lights(), 64, "the limit without culling");

    settings.render.path = RenderPath::Deferred;
    let deferred = plan_with(&settings, PlanRequest::default());
    // At the defaults (4x MSAA forward) the deferred path antialiases with FXAA.
    assert_eq!(passes(&deferred), vec!["shadows", "gbuffer", "deferred lights", "fxaa", "tonemap"]);
    let visible = deferred.shaded_local_lights();
    assert!(visible > 64, "the deferred path shades every visible light: {visible}");
    // One full-screen draw for the directional lights, then a volume per point and spot.
    assert_eq!(deferred.volumes.len(), 1 + visible);
    assert_eq!(deferred.volumes[0].shape, VolumeShape::Screen);
    assert!(deferred.volumes[1..].iter().all(|v| v.shape != VolumeShape::Screen));
    // Transparent surfaces see the forward lists: the 64 most important.
    assert_eq!(deferred.local_light_count(), 64);
    assert!(deferred.gpu_lights(&scene).len() <= 68);

    settings.render.light_buffer = LightBuffer::LdrExp2;
    let ldr = plan_with(&settings, PlanRequest { aovs: true, ..Default::default() });
    assert_eq!(passes(&ldr), vec!["shadows", "gbuffer", "deferred lights", "ldr decode", "aov", "tonemap"]);
    // Debug views imply the deferred path, even when the settings say forward.
    settings.render.path = RenderPath::Forward;
    let albedo = plan_with(&settings, PlanRequest { debug: Some(DebugView::GbufferAlbedo), ..Default::default() });
    assert_eq!(albedo.path, RenderPath::Deferred);
    assert_eq!(passes(&albedo), vec!["gbuffer", "debug view"]);
    let overdraw = plan_with(&settings, PlanRequest { debug: Some(DebugView::LightOverdraw), ..Default::default() });
    assert_eq!(passes(&overdraw), vec!["gbuffer", "deferred lights", "debug view"]);
}

#[test]
fn past_sixteen_tiles_point_lights_get_tiles_by_screen_coverage() {
    use chiaro_render::plan::shadows::ShadowAtlas;
    // Four shadowed points (24 tiles): the camera stands in the first one's range; two are
    // ordinary; the last is small and far.
    let lights = vec![
        point_light(Vec3::new(0.0, 1.0, 0.0), 10.0, Some(20.0)),
        point_light(Vec3::new(3.0, 1.0, -4.0), 10.0, Some(2.5)),
        point_light(Vec3::new(-3.0, 1.0, -4.0), 10.0, Some(2.5)),
        point_light(Vec3::new(-4.0, 0.5, -4.0), 10.0, Some(0.3)),
    ];
    let scene = floor_scene(12.0, Vec3::new(0.0, 6.0, 5.0), lights);
    let plan = first_plan(&scene, PlanRequest::default());
    let size_of = |light: u32| {
        let sizes: Vec<u32> = plan
            .shadows
            .tiles
            .iter()
            .filter(|t| t.atlas == ShadowAtlas::Local && t.light == LightId(light))
            .map(|t| t.viewport.2)
            .collect();
        assert_eq!(sizes.len(), 6, "light {light} has its six faces");
        assert!(sizes.iter().all(|&s| s == sizes[0]));
        sizes[0]
    };
    assert_eq!([size_of(0), size_of(1), size_of(2), size_of(3)], [512, 256, 256, 128]);
    // No two tiles overlap.
    let other: Vec<_> = plan.shadows.tiles.iter().filter(|t| t.atlas == ShadowAtlas::Local).collect();
    for (k, a) in other.iter().enumerate() {
        for b in &other[k + 1..] {
            let (ax, ay, as_) = a.viewport;
            let (bx, by, bs) = b.viewport;
            assert!(ax + as_ <= bx || bx + bs <= ax || ay + as_ <= by || by + bs <= ay, "{a:?} and {b:?} overlap");
        }
    }
}

#[test]
fn an_atlas_too_small_for_any_light_gives_no_tiles_and_no_panic() {
    // A point light needs six tiles; with four allowed it gets none.
    let scene = floor_scene(8.0, Vec3::new(0.0, 6.0, 3.0), vec![point_light(Vec3::new(0.0, 1.0, 0.0), 5.0, Some(6.0))]);
    let mut settings = unlit_settings();
    settings.shadows.other.max_tiles = 4;
    let plan = first_plan_with(&scene, &settings, PlanRequest::default());
    assert_eq!(slot_of(&plan, 0), ShadowSlot::BakedOnly);
    assert!(plan.shadows.tiles.is_empty());
}

#[test]
fn shadow_loops_for_point_and_spot_lights_compile_in_only_where_a_light_needs_them() {
    let scene = demo_scene(8);
    let view = View::from_camera(&scene, 0, 320, 180);
    let shadowed = plan(&scene, &view, &mut ShadowAtlasTiles::default(), PlanRequest::default());
    assert!(shadowed.features.local_shadows, "the demo's spots and points cast shadows");
    // Every point and spot light unshadowed: the sun's shadow alone does not count.
    let mut unshadowed = scene.clone();
    for light in unshadowed.lights.iter_mut().filter(|l| l.kind != LightKind::Directional) {
        light.shadow.mode = ShadowMode::None;
    }
    let plan = plan(&unshadowed, &view, &mut ShadowAtlasTiles::default(), PlanRequest::default());
    assert!(!plan.features.local_shadows);
    assert!(plan.lights.iter().any(|l| matches!(l.shadow, ShadowSlot::Realtime { .. })), "the sun keeps its shadow");
}

#[test]
fn area_light_shading_compiles_in_only_where_a_rect_or_disk_is_shaded() {
    let scene = demo_scene(8);
    let view = View::from_camera(&scene, 0, 320, 180);
    let punctual = plan(&scene, &view, &mut ShadowAtlasTiles::default(), PlanRequest::default());
    assert!(!punctual.features.area_lights, "the demo has punctual lights only");
    let mut with_rect = scene.clone();
    let point = with_rect.lights.iter_mut().find(|l| l.kind == LightKind::Point).expect("the demo has a point light");
    point.kind = LightKind::Rect { width: 0.5, height: 0.25 };
    let plan = plan(&with_rect, &view, &mut ShadowAtlasTiles::default(), PlanRequest::default());
    assert!(plan.features.area_lights);
}
