//! The draws a scene makes: one per primitive of each mesh instance, where its indices sit
//! in the shared vertex and index buffers, and the order the camera draws them in. Pure
//! data: the GPU scene fills its buffers by `GeometryLayout`, and frame plans refer to
//! draws by their index in `scene_draws`.

use chiaro_math::Aabb;
use chiaro_scene::{AlphaMode, CastShadows, Primitive, Scene, ShadowCasting, Topology};
use glam::Vec3;
use std::hash::{Hash, Hasher};

/// Where one primitive's indices and vertices start in the shared buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PrimitiveRange {
    /// The primitive's first index in the shared index buffer.
    pub first_index: u32,
    /// Its index count.
    pub index_count: u32,
    /// Its first vertex in the shared vertex buffer, added to each index.
    pub base_vertex: i32,
}

/// Every mesh primitive once, in scene order; instances refer to them.
#[derive(Clone, Debug, Default)]
pub struct GeometryLayout {
    /// Per mesh, per part it draws (`Mesh::drawn_parts`: triangles, then points and lines).
    pub ranges: Vec<Vec<PrimitiveRange>>,
    /// Vertices of all primitives together.
    pub vertex_count: usize,
    /// Indices of all primitives together.
    pub index_count: usize,
}

impl GeometryLayout {
    /// Lays out every drawn part of `scene`'s meshes one after the other.
    pub fn of(scene: &Scene) -> GeometryLayout {
        let mut layout = GeometryLayout::default();
        for mesh in &scene.meshes {
            let mut ranges = Vec::with_capacity(mesh.primitives.len() + mesh.points_and_lines.len());
            for (_, p) in mesh.drawn_parts() {
                ranges.push(PrimitiveRange {
                    first_index: layout.index_count as u32,
                    index_count: p.indices.len() as u32,
                    base_vertex: layout.vertex_count as i32,
                });
                layout.vertex_count += p.positions.len();
                layout.index_count += p.indices.len();
            }
            layout.ranges.push(ranges);
        }
        layout
    }
}

/// One primitive of one mesh instance.
#[derive(Clone, Debug)]
pub struct Draw {
    /// The primitive's first index in the shared index buffer.
    pub first_index: u32,
    /// Its index count.
    pub index_count: u32,
    /// Its first vertex in the shared vertex buffer, added to each index.
    pub base_vertex: i32,
    /// Index into the object buffer (the instance's index), passed as the draw's first
    /// instance.
    pub object: u32,
    /// Index of the material; `Scene::materials.len()` is the glTF default material.
    pub material: usize,
    /// Triangles, or points and lines (which no shadow map draws).
    pub topology: Topology,
    /// The material's alpha mode: opaque, masked or blended.
    pub alpha_mode: AlphaMode,
    /// Whether the material has any texture (else its shading samples none).
    pub textured: bool,
    /// Whether the material has KHR_materials_* extensions (the layered BRDF shades it,
    /// and the deferred path draws it forward too).
    pub layered: bool,
    /// Whether light passes through the (opaque or masked) material
    /// (KHR_materials_transmission): it is drawn after the other solids, refracting them.
    pub transmissive: bool,
    /// Whether it casts a coloured shadow: a solid caster whose material lets light
    /// through (`Material::shadow_transmittance`). The shadow pass draws it into the
    /// shadow tints rather than the depth atlases.
    pub tints_shadows: bool,
    /// Whether back faces are drawn too (glTF `doubleSided`).
    pub double_sided: bool,
    /// The instance's transform mirrors (negative determinant), which flips the winding.
    pub mirrored: bool,
    /// World-space centre, for sorting transparent draws back to front.
    pub center_ws: Vec3,
    /// World-space bounds, for culling casters per shadow tile.
    pub bounds_ws: Aabb,
    /// Whether and how the instance casts (two-sided, with the material's faces, off, only).
    pub cast_shadows: CastShadows,
    /// How its material casts: solid, alpha-tested, dithered or not at all.
    pub shadow_casting: ShadowCasting,
    /// A hash of everything that decides what it writes into a shadow map: its geometry,
    /// transform, casting modes and, for alpha-tested and dithered casters, its material.
    /// Equal keys draw equal depths, so a cached tile whose casters' keys are unchanged
    /// need not be drawn again.
    pub caster_key: u64,
}

impl Draw {
    /// Drawn by the camera (shadows-only casters are not).
    pub fn visible(&self) -> bool {
        self.cast_shadows != CastShadows::ShadowsOnly
    }

    /// The instance and its material both cast (the reference treats them alike).
    pub fn casts_shadows(&self) -> bool {
        self.cast_shadows != CastShadows::Off && self.shadow_casting != ShadowCasting::Off
    }
}

/// The scene's draws in instance order, skipping empty primitives.
/// A hash of a primitive's positions, indices and texture coordinates.
fn geometry_hash(p: &Primitive) -> u64 {
    let mut h = std::hash::DefaultHasher::new();
    for v in &p.positions {
        v.to_array().map(f32::to_bits).hash(&mut h);
    }
    p.indices.hash(&mut h);
    for uv in p.uv0.iter().chain(&p.uv1) {
        uv.to_array().map(f32::to_bits).hash(&mut h);
    }
    // Alpha-tested casters read the vertex colours' alpha.
    for c in &p.colors {
        c.w.to_bits().hash(&mut h);
    }
    h.finish()
}

/// Every primitive of every mesh instance, in scene order, placed by `layout`.
pub fn scene_draws(scene: &Scene, layout: &GeometryLayout) -> Vec<Draw> {
    let default_material = scene.materials.len();
    let geometry: Vec<Vec<u64>> =
        scene.meshes.iter().map(|m| m.drawn_parts().map(|(_, p)| geometry_hash(p)).collect()).collect();
    // Images alpha-tested casters read, hashed once each.
    let mut image_hashes: Vec<Option<u64>> = vec![None; scene.images.len()];
    let mut image_hash = |index: usize| -> Option<u64> {
        let image = scene.images.get(index)?;
        Some(*image_hashes[index].get_or_insert_with(|| {
            let mut h = std::hash::DefaultHasher::new();
            (image.width, image.height, &image.rgba8).hash(&mut h);
            h.finish()
        }))
    };
    let mut draws = Vec::new();
    for (object, inst) in scene.instances.iter().enumerate() {
        for (k, ((topology, p), range)) in
            scene.meshes[inst.mesh].drawn_parts().zip(&layout.ranges[inst.mesh]).enumerate()
        {
            if range.index_count == 0 {
                continue;
            }
            let material = p.material.filter(|&m| m < scene.materials.len()).unwrap_or(default_material);
            let m = scene.materials.get(material).cloned().unwrap_or_default();
            let mut h = std::hash::DefaultHasher::new();
            geometry[inst.mesh][k].hash(&mut h);
            inst.world_from_local.to_cols_array().map(f32::to_bits).hash(&mut h);
            let tints_shadows = m.shadow_casting == ShadowCasting::On && m.shadow_transmittance().is_some();
            (inst.cast_shadows, m.shadow_casting, m.double_sided, tints_shadows).hash(&mut h);
            if m.shadow_casting == ShadowCasting::Clip || m.shadow_casting == ShadowCasting::Dither {
                // What the alpha test reads.
                let texture = m.base_color_texture.map(|t| (image_hash(t.image), t.tex_coord, format!("{t:?}")));
                (m.base_color.w.to_bits(), m.alpha_cutoff.to_bits(), texture).hash(&mut h);
            }
            draws.push(Draw {
                first_index: range.first_index,
                index_count: range.index_count,
                base_vertex: range.base_vertex,
                object: object as u32,
                material,
                topology,
                alpha_mode: m.alpha_mode,
                textured: m.has_texture(),
                layered: m.layers.is_layered() && !m.unlit,
                transmissive: m.layers.transmits() && !m.unlit && m.alpha_mode != AlphaMode::Blend,
                tints_shadows,
                double_sided: m.double_sided,
                mirrored: inst.world_from_local.determinant() < 0.0,
                center_ws: inst.world_from_local.transform_point3(p.bounds.center()),
                bounds_ws: p.bounds.transformed(&inst.world_from_local),
                // Points and lines have no surface to cast with; a shadows-only instance's
                // draw nothing at all.
                cast_shadows: match (topology, inst.cast_shadows) {
                    (Topology::Triangles, cast) => cast,
                    (_, CastShadows::ShadowsOnly) => CastShadows::ShadowsOnly,
                    _ => CastShadows::Off,
                },
                shadow_casting: if topology == Topology::Triangles { m.shadow_casting } else { ShadowCasting::Off },
                caster_key: h.finish(),
            });
        }
    }
    draws
}

/// The draws of `order` as instanced draws: each run of draws of the same primitive
/// with the same material and state whose objects follow one another (the copies of an
/// EXT_mesh_gpu_instancing node, or nodes placing one mesh in a row) comes out as its
/// first draw and the number of objects it covers, drawn as instances `object..object + n`.
pub fn instanced_runs<'a>(draws: &'a [Draw], order: &'a [u32]) -> impl Iterator<Item = (&'a Draw, u32)> + 'a {
    let mut rest = order;
    std::iter::from_fn(move || {
        let (&first, tail) = rest.split_first()?;
        let first = &draws[first as usize];
        let joins = |(k, &i): (usize, &u32)| {
            let d = &draws[i as usize];
            d.object == first.object + 1 + k as u32 && draws_alike(first, d)
        };
        let run = 1 + tail.iter().enumerate().take_while(|&entry| joins(entry)).count();
        rest = &rest[run..];
        Some((first, run as u32))
    })
}

/// Whether two draws draw the same primitive with the same material in the same state,
/// so that one instanced draw can issue both.
fn draws_alike(a: &Draw, b: &Draw) -> bool {
    (a.first_index, a.index_count, a.base_vertex, a.material, a.topology)
        == (b.first_index, b.index_count, b.base_vertex, b.material, b.topology)
        && (a.alpha_mode, a.textured, a.double_sided, a.mirrored)
            == (b.alpha_mode, b.textured, b.double_sided, b.mirrored)
        && (a.cast_shadows, a.shadow_casting) == (b.cast_shadows, b.shadow_casting)
}

/// The camera's draw order, as indices into `draws`: opaque and masked draws first,
/// grouped by pipeline state, material and primitive (which keeps the copies of an
/// instanced mesh together, in object order, for `instanced_runs`); then transparent
/// draws from far to near, so that blending composes correctly. `far_key` says how far a
/// world point is: its distance from a perspective eye, its depth for parallel rays.
pub fn camera_draw_order(draws: &[Draw], far_key: impl Fn(Vec3) -> f32) -> Vec<u32> {
    let (mut blended, mut solid): (Vec<u32>, Vec<u32>) = (0..draws.len() as u32)
        .filter(|&i| draws[i as usize].visible())
        .partition(|&i| draws[i as usize].alpha_mode == AlphaMode::Blend);
    solid.sort_by_key(|&i| {
        let d = &draws[i as usize];
        (d.double_sided, d.mirrored, d.material, d.first_index)
    });
    let distance = |i: u32| far_key(draws[i as usize].center_ws);
    // Transmissive solids refract the image of the others, so they come after them; near
    // to far, since each replaces what is behind it (the copy they refract holds only
    // the other solids) and the depth test then spares the farther ones' hidden pixels.
    let (mut transmissive, mut order): (Vec<u32>, Vec<u32>) =
        solid.into_iter().partition(|&i| draws[i as usize].transmissive);
    transmissive.sort_by(|&a, &b| distance(a).total_cmp(&distance(b)));
    blended.sort_by(|&a, &b| distance(b).total_cmp(&distance(a)));
    order.extend(transmissive);
    order.extend(blended);
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::{Material, Mesh, MeshInstance, shapes};
    use glam::Mat4;

    fn scene() -> Scene {
        let mut scene = Scene::default();
        let mut cube = shapes::cuboid(Vec3::ONE);
        cube.material = Some(0);
        let mut glass = shapes::cuboid(Vec3::ONE);
        glass.material = Some(1);
        scene.meshes.push(Mesh::of_triangles("cube".into(), vec![cube, glass]));
        scene.materials.push(Material::default());
        scene.materials.push(Material { alpha_mode: AlphaMode::Blend, ..Material::default() });
        for (i, (x, cast)) in
            [(0.0, CastShadows::On), (5.0, CastShadows::ShadowsOnly), (-8.0, CastShadows::On)].into_iter().enumerate()
        {
            scene.instances.push(MeshInstance {
                mesh: 0,
                node: i,
                name: format!("cube {i}"),
                world_from_local: Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
                cast_shadows: cast,
                receive_shadows: true,
                is_static: true,
                lightmap: None,
                gpu_instance: None,
                label: 0,
            });
        }
        scene
    }

    #[test]
    fn draws_point_at_their_primitives_ranges() {
        let scene = scene();
        let layout = GeometryLayout::of(&scene);
        let p = &scene.meshes[0].primitives;
        assert_eq!(layout.vertex_count, 2 * p[0].positions.len());
        assert_eq!(layout.ranges[0][1].first_index as usize, p[0].indices.len());
        assert_eq!(layout.ranges[0][1].base_vertex as usize, p[0].positions.len());
        let draws = scene_draws(&scene, &layout);
        assert_eq!(draws.len(), 6);
        assert_eq!(draws[3].object, 1);
        assert_eq!(draws[3].first_index, layout.ranges[0][1].first_index);
        assert!(draws[1].bounds_ws.center().abs_diff_eq(Vec3::ZERO, 1e-6));
        assert!(draws[4].bounds_ws.center().abs_diff_eq(Vec3::new(-8.0, 0.0, 0.0), 1e-6));
    }

    #[test]
    fn runs_of_alike_draws_of_consecutive_objects_draw_as_one() {
        let mut scene = scene();
        let draws = scene_draws(&scene, &GeometryLayout::of(&scene));
        let runs = |draws: &[Draw], order: &[u32]| -> Vec<(u32, u32)> {
            instanced_runs(draws, order).map(|(d, n)| (d.object, n)).collect()
        };
        // The middle cube casts shadows only: its draw cannot join the others'.
        assert_eq!(runs(&draws, &[0, 2, 4]), vec![(0, 1), (1, 1), (2, 1)]);
        scene.instances[1].cast_shadows = CastShadows::On;
        let draws = scene_draws(&scene, &GeometryLayout::of(&scene));
        assert_eq!(runs(&draws, &[0, 2, 4]), vec![(0, 3)]);
        // A gap in the objects, or another primitive, starts a new run.
        assert_eq!(runs(&draws, &[0, 4]), vec![(0, 1), (2, 1)]);
        assert_eq!(runs(&draws, &[0, 2, 3, 5]), vec![(0, 2), (1, 2)]);
    }

    #[test]
    fn the_camera_draws_solids_first_then_glass_far_to_near_and_skips_shadow_only_casters() {
        let scene = scene();
        let draws = scene_draws(&scene, &GeometryLayout::of(&scene));
        // Glass draws are 1 (x = 0), 3 (shadows only) and 5 (x = -8); the eye is at x = 10.
        let order = camera_draw_order(&draws, |p| p.distance(Vec3::new(10.0, 0.0, 0.0)));
        assert_eq!(order, vec![0, 4, 5, 1]);
        // Parallel rays along +X from x = -30: depth alone orders them.
        let (eye, forward) = (Vec3::new(-30.0, 0.0, 5.0), Vec3::X);
        assert_eq!(camera_draw_order(&draws, |p| (p - eye).dot(forward)), vec![0, 4, 1, 5]);
    }
}
