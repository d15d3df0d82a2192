//! glTF points and lines on both paths: a segment and a strip drawn one pixel wide,
//! points one pixel each, unlit where they have no normals (their material's base colour
//! times the vertex colour, as an unlit surface shows it), lit where they have normals,
//! and casting no shadow on the floor below them.

mod common;

use chiaro_math::Aabb;
use chiaro_math::tonemap::{exposure_scale, pbr_neutral};
use chiaro_render::{FrameOptions, FrameOutput, View};
use chiaro_scene::{
    Light, LightKind, Material, Mesh, MeshInstance, PointsOrLines, Primitive, RenderPath, Scene, Settings, Topology,
};
use common::*;
use glam::{Mat4, Vec2, Vec3, Vec4};

const SIZE: u32 = 96;

/// A node number for the wires' instance, to find their pixels in the instance AOV.
const WIRES_NODE: usize = 40;

fn wire(
    topology: Topology,
    positions: Vec<Vec3>,
    colors: Vec<Vec4>,
    normals: Vec<Vec3>,
    material: usize,
) -> PointsOrLines {
    let n = positions.len();
    let tangents = normals.iter().map(|n| n.any_orthonormal_vector().extend(1.0)).collect();
    PointsOrLines {
        topology,
        primitive: Primitive {
            bounds: Aabb::from_points(positions.iter().copied()),
            positions,
            normals,
            tangents,
            uv0: vec![Vec2::ZERO; n],
            uv1: vec![Vec2::ZERO; n],
            colors,
            indices: (0..n as u32).collect(),
            material: Some(material),
            lightmap_uv: Vec::new(),
        },
    }
}

/// A sunlit floor seen straight down from 6 m, with a mesh of wires 1 m above it: an unlit
/// red segment across the view (material 1), an unlit strip whose vertex colours turn it
/// blue, five unlit yellow points, and (with normals) a lit grey segment (material 2).
fn wired_floor(with_wires: bool) -> Scene {
    let sun = Light { intensity: 3.0, ..Light::new(LightKind::Directional, Vec3::ZERO, Vec3::new(0.3, -1.0, 0.2)) };
    let mut scene = floor_scene(12.0, Vec3::new(0.0, 6.0, 0.0), vec![sun]);
    scene.cameras[0].world_from_view = Mat4::look_at_rh(Vec3::new(0.0, 6.0, 0.0), Vec3::ZERO, Vec3::NEG_Z).inverse();
    let unlit =
        |name: &str, color: Vec4| Material { name: name.into(), base_color: color, unlit: true, ..Material::default() };
    scene.materials.push(unlit("red", Vec4::new(1.0, 0.1, 0.05, 1.0)));
    scene.materials.push(Material { base_color: Vec4::new(0.5, 0.5, 0.5, 1.0), ..scene.materials[0].clone() });
    scene.materials.push(unlit("white", Vec4::ONE));
    if !with_wires {
        return scene;
    }
    let y = 1.0;
    let blue = Vec4::new(0.1, 0.2, 1.0, 1.0);
    let yellow = Vec4::new(1.0, 0.9, 0.1, 1.0);
    let points: Vec<Vec3> = (0..5).map(|k| Vec3::new(-2.0 + k as f32, y, 1.5)).collect();
    let mesh = Mesh {
        name: "wires".into(),
        primitives: Vec::new(),
        points_and_lines: vec![
            wire(Topology::Lines, vec![Vec3::new(-6.0, y, -0.93), Vec3::new(6.0, y, -0.93)], vec![], vec![], 1),
            wire(
                Topology::Lines,
                vec![
                    Vec3::new(-6.0, y, 0.51),
                    Vec3::new(0.0, y, 0.51),
                    Vec3::new(0.0, y, 0.51),
                    Vec3::new(6.0, y, 0.51),
                ],
                vec![blue; 4],
                vec![],
                3,
            ),
            wire(Topology::Points, points, vec![yellow; 5], vec![], 3),
            wire(
                Topology::Lines,
                vec![Vec3::new(-6.0, y, -2.02), Vec3::new(6.0, y, -2.02)],
                vec![],
                vec![Vec3::Y; 2],
                2,
            ),
        ],
    };
    scene.meshes.push(mesh);
    scene.instances.push(MeshInstance {
        mesh: scene.meshes.len() - 1,
        node: WIRES_NODE,
        name: "wires".into(),
        ..scene.instances[0].clone()
    });
    scene
}

fn render(scene: &Scene, path: RenderPath) -> FrameOutput {
    let mut settings = Settings::default();
    settings.render.path = path;
    settings.render.msaa = 1;
    let mut r = renderer();
    let prepared = r.prepare(scene).expect("prepare");
    let view = View::from_camera(scene, 0, SIZE, SIZE);
    let options = FrameOptions { ids: true, readback: true, ..Default::default() };
    r.render(scene, &prepared, &view, &settings, options).expect("render")
}

/// What an unlit surface of linear colour `color` shows in the LDR image.
fn unlit_ldr(color: Vec3) -> [u8; 3] {
    let shown = pbr_neutral(color * exposure_scale(Settings::default().render.exposure_ev100));
    let encode = |c: f32| (srgb_encode(c) * 255.0).round() as u8;
    [encode(shown.x), encode(shown.y), encode(shown.z)]
}

/// The pixels (row, column) of the LDR image within 2 levels of `rgb`.
fn pixels_of(frame: &FrameOutput, rgb: [u8; 3]) -> Vec<(u32, u32)> {
    (0..SIZE * SIZE)
        .filter(|&i| {
            let p = &frame.ldr[i as usize * 4..i as usize * 4 + 3];
            p.iter().zip(rgb).all(|(&a, b)| a.abs_diff(b) <= 2)
        })
        .map(|i| (i / SIZE, i % SIZE))
        .collect()
}

#[test]
fn points_and_lines_draw_one_pixel_wide_unlit_without_normals_in_both_paths() {
    let scene = wired_floor(true);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let frame = render(&scene, path);
        // The red segment runs across the whole view: one pixel in every column.
        let red = pixels_of(&frame, unlit_ldr(Vec3::new(1.0, 0.1, 0.05)));
        let mut columns: Vec<u32> = red.iter().map(|&(_, x)| x).collect();
        columns.sort_unstable();
        assert_eq!(columns, (0..SIZE).collect::<Vec<_>>(), "{path:?}: red pixels {red:?}");
        assert!(red.iter().all(|&(row, _)| row == red[0].0), "{path:?}: one row");
        // The strip, white times its blue vertex colours: one pixel a column too.
        let blue = pixels_of(&frame, unlit_ldr(Vec3::new(0.1, 0.2, 1.0)));
        assert_eq!(blue.len(), SIZE as usize, "{path:?}: blue pixels {blue:?}");
        // Five points, one pixel each.
        let yellow = pixels_of(&frame, unlit_ldr(Vec3::new(1.0, 0.9, 0.1)));
        assert_eq!(yellow.len(), 5, "{path:?}: yellow pixels {yellow:?}");
        // Every one of those pixels shows the wires' node in the instance AOV.
        let ids = frame.ids.as_ref().expect("ids");
        let wire_pixels = ids.instance.iter().filter(|&&n| n == WIRES_NODE as u32).count();
        assert_eq!(wire_pixels, red.len() + blue.len() + yellow.len() + SIZE as usize, "{path:?}");
    }
}

#[test]
fn lit_lines_are_shaded_and_no_wire_shadows_the_floor() {
    let bare = render(&wired_floor(false), RenderPath::Forward);
    let mut grey = wired_floor(false);
    grey.materials[0] = grey.materials[2].clone();
    let grey_floor = render(&grey, RenderPath::Forward);
    for path in [RenderPath::Forward, RenderPath::Deferred] {
        let frame = render(&wired_floor(true), path);
        let ids = frame.ids.as_ref().expect("ids");
        // Off the wires, the floor is what it is without them: no shadow of theirs.
        let mut floor = 0;
        for (i, &node) in ids.instance.iter().enumerate() {
            if node != WIRES_NODE as u32 {
                let (a, b) = (frame.hdr[i], bare.hdr[i]);
                let close = (0..3).all(|c| (a[c] - b[c]).abs() <= 2e-3 * b[c].abs().max(1e-3));
                assert!(close, "{path:?}: pixel {i} changed by the wires: {a:?} vs {b:?}");
                floor += 1;
            }
        }
        assert!(floor > (SIZE * SIZE) as usize * 9 / 10);
        // The lit grey segment (the row of wire pixels that is neither red nor blue nor
        // yellow) is lit as a grey floor of its material would be there.
        let grey_row: Vec<usize> = (0..(SIZE * SIZE) as usize)
            .filter(|&i| {
                let [r, g, b, _] = frame.hdr[i];
                ids.instance[i] == WIRES_NODE as u32 && (r - b).abs() < 0.05 * r && (r - g).abs() < 0.05 * r
            })
            .collect();
        assert_eq!(grey_row.len(), SIZE as usize, "{path:?}: one lit grey pixel a column");
        // Its normal is the floor's and the light directional: the same radiance, but for
        // the view direction from 1 m nearer the camera (within 2% at roughness 1).
        for &i in &grey_row {
            let (line, floor) = (frame.hdr[i][0], grey_floor.hdr[i][0]);
            assert!((line / floor - 1.0).abs() < 0.02, "{path:?}: pixel {i}: lit line {line}, grey floor {floor}");
        }
    }
}
