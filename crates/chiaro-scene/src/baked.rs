//! Baked lighting attached to a scene: lightmap atlases for static instances and a light
//! probe grid for dynamic ones. The baker (chiaro-bake) makes these; `apply` gives each
//! lightmapped instance a mesh of its own whose vertices carry atlas coordinates, so the
//! renderer needs nothing but the scene.

use crate::types::{Mesh, Primitive, Scene};
use chiaro_math::sh::ShRgb;
use glam::{UVec3, Vec2, Vec3};

/// One atlas of baked irradiance.
#[derive(Clone, Debug, PartialEq)]
pub struct Lightmap {
    /// Texels per row.
    pub width: u32,
    /// Rows of texels.
    pub height: u32,
    /// Row-major from the top-left: RGB irradiance in lux, and in A the fraction of the
    /// texel a surface covers (0 for gutter texels, which dilation fills).
    pub texels: Vec<[f32; 4]>,
}

/// A shadow mask atlas: per texel, for each of four channels, the fraction of the texel
/// that sees the mixed light assigned to that channel (1 where no light is assigned).
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowMask {
    /// Texels per row.
    pub width: u32,
    /// Rows of texels.
    pub height: u32,
    /// Row-major from the top-left: each channel's visibility, 0 shadowed to 1 lit.
    pub texels: Vec<[f32; 4]>,
}

/// Irradiance probes on a regular grid, x varying fastest, then y, then z.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeGrid {
    /// Position of probe (0, 0, 0).
    pub origin: Vec3,
    /// Metres between neighbours along each axis (positive).
    pub spacing: Vec3,
    /// Probes along x, y and z (each at least 1).
    pub counts: UVec3,
    /// Incoming radiance per probe.
    pub probes: Vec<ShRgb>,
    /// Per probe, how much of each shadow mask channel's light reaches it (empty without
    /// shadow masks): the shadow mask of dynamic objects.
    pub occlusion: Vec<[f32; 4]>,
}

impl ProbeGrid {
    /// Index in `probes` of the probe at grid coordinates (`x`, `y`, `z`).
    pub fn index(&self, x: u32, y: u32, z: u32) -> usize {
        ((z * self.counts.y + y) * self.counts.x + x) as usize
    }

    /// World position, metres, of the probe at grid coordinates (`x`, `y`, `z`).
    pub fn position(&self, x: u32, y: u32, z: u32) -> Vec3 {
        self.origin + self.spacing * Vec3::new(x as f32, y as f32, z as f32)
    }

    /// The eight probes around `p` (clamped to the grid) with their trilinear weights, as
    /// the shader blends them.
    fn corners(&self, p: Vec3) -> [(usize, f32); 8] {
        let max = (self.counts.as_vec3() - 1.0).max(Vec3::ZERO);
        let cell = ((p - self.origin) / self.spacing).clamp(Vec3::ZERO, max);
        let base = cell.floor().min((max - 1.0).max(Vec3::ZERO));
        let t = cell - base;
        let b = base.as_uvec3();
        std::array::from_fn(|corner| {
            let corner = corner as u32;
            let offset = UVec3::new(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
            let f = Vec3::select(offset.cmpeq(UVec3::ONE), t, Vec3::ONE - t);
            let c = (b + offset).min(self.counts - 1);
            (self.index(c.x, c.y, c.z), f.x * f.y * f.z)
        })
    }

    /// The trilinear blend of the eight probes around `p` (clamped to the grid), as the
    /// shader samples it.
    pub fn sample(&self, p: Vec3) -> ShRgb {
        let mut out = ShRgb::default();
        for (index, weight) in self.corners(p) {
            for (o, c) in out.coefficients.iter_mut().zip(self.probes[index].coefficients) {
                *o += c * weight;
            }
        }
        out
    }

    /// The trilinear blend of probe occlusion at `p`, as the shader samples it; all ones
    /// without occlusion data.
    pub fn sample_occlusion(&self, p: Vec3) -> [f32; 4] {
        if self.occlusion.len() != self.probes.len() {
            return [1.0; 4];
        }
        let mut out = [0.0; 4];
        for (index, weight) in self.corners(p) {
            for (o, v) in out.iter_mut().zip(self.occlusion[index]) {
                *o += v * weight;
            }
        }
        out
    }
}

/// What a bake gives the renderer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BakedLighting {
    /// All the same size, one texture-array layer each.
    pub lightmaps: Vec<Lightmap>,
    /// The light probe grid, when the scene had bounds to place one in.
    pub probes: Option<ProbeGrid>,
    /// One per lightmap, same size and layout, when mixed lights have shadow masks.
    pub shadow_masks: Vec<ShadowMask>,
    /// Per scene light, its shadow mask channel (0 to 3), if it has one.
    pub light_channels: Vec<Option<u8>>,
    /// Scene lights the bake turned from mixed to baked (no channel was free).
    pub demoted: Vec<usize>,
}

impl BakedLighting {
    /// The shadow mask channel of scene light `light`.
    pub fn channel(&self, light: usize) -> Option<u8> {
        self.light_channels.get(light).copied().flatten()
    }
}

/// An instance's place in the lightmaps: its atlas layer, and per primitive one atlas
/// coordinate (0 to 1) per triangle corner, in index order.
#[derive(Clone, Debug, PartialEq)]
pub struct InstanceLightmap {
    /// Index in `Scene::instances`.
    pub instance: usize,
    /// The lightmap atlas (texture array layer) it is in.
    pub layer: u32,
    /// Per primitive, one atlas coordinate per index.
    pub corner_uvs: Vec<Vec<Vec2>>,
}

/// Attaches baked lighting to `scene`: each lightmapped instance gets its own copy of its
/// mesh, one vertex per triangle corner (charts split vertices at their seams), with
/// `lightmap_uv` set. Returns an error naming the instance when the placements do not fit
/// the scene's geometry.
pub fn apply(scene: &mut Scene, lighting: BakedLighting, placements: &[InstanceLightmap]) -> Result<(), String> {
    for placement in placements {
        let instance = scene
            .instances
            .get(placement.instance)
            .ok_or_else(|| format!("instance {} is not in the scene", placement.instance))?;
        if placement.layer as usize >= lighting.lightmaps.len() {
            return Err(format!(
                "instance {} ({}): lightmap layer {} does not exist",
                placement.instance, instance.name, placement.layer
            ));
        }
        let mesh = &scene.meshes[instance.mesh];
        if mesh.primitives.len() != placement.corner_uvs.len() {
            return Err(format!(
                "instance {} ({}): {} primitives in the bake, {} in the scene",
                placement.instance,
                instance.name,
                placement.corner_uvs.len(),
                mesh.primitives.len()
            ));
        }
        let mut primitives = Vec::with_capacity(mesh.primitives.len());
        for (primitive, uvs) in mesh.primitives.iter().zip(&placement.corner_uvs) {
            if primitive.indices.len() != uvs.len() {
                return Err(format!(
                    "instance {} ({}): {} lightmap corners in the bake, {} in the scene",
                    placement.instance,
                    instance.name,
                    uvs.len(),
                    primitive.indices.len()
                ));
            }
            primitives.push(per_corner(primitive, uvs));
        }
        let name = format!("{} (lightmapped {})", mesh.name, instance.name);
        scene.meshes.push(Mesh { name, primitives, points_and_lines: mesh.points_and_lines.clone() });
        let instance = &mut scene.instances[placement.instance];
        instance.mesh = scene.meshes.len() - 1;
        instance.lightmap = Some(placement.layer);
    }
    for &light in &lighting.demoted {
        let light = scene.lights.get_mut(light).ok_or_else(|| format!("demoted light {light} is not in the scene"))?;
        light.mode = crate::types::LightMode::Baked;
    }
    scene.baked = Some(lighting);
    Ok(())
}

/// The primitive with one vertex per index, carrying `uvs` as lightmap coordinates.
fn per_corner(p: &Primitive, uvs: &[Vec2]) -> Primitive {
    fn gather<T: Copy + Default>(values: &[T], indices: &[u32]) -> Vec<T> {
        if values.is_empty() {
            return Vec::new();
        }
        indices.iter().map(|&i| values.get(i as usize).copied().unwrap_or_default()).collect()
    }
    Primitive {
        positions: gather(&p.positions, &p.indices),
        normals: gather(&p.normals, &p.indices),
        tangents: gather(&p.tangents, &p.indices),
        uv0: gather(&p.uv0, &p.indices),
        uv1: gather(&p.uv1, &p.indices),
        colors: gather(&p.colors, &p.indices),
        indices: (0..p.indices.len() as u32).collect(),
        material: p.material,
        bounds: p.bounds,
        lightmap_uv: uvs.to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use crate::types::{CastShadows, MeshInstance};
    use glam::Mat4;

    fn scene() -> Scene {
        let mut scene = Scene {
            meshes: vec![Mesh::of_triangles("box".into(), vec![shapes::cuboid(Vec3::ONE)])],
            ..Scene::default()
        };
        for node in 0..2 {
            scene.instances.push(MeshInstance {
                mesh: 0,
                node,
                name: format!("box {node}"),
                world_from_local: Mat4::from_translation(Vec3::X * node as f32 * 2.0),
                cast_shadows: CastShadows::On,
                receive_shadows: true,
                is_static: true,
                lightmap: None,
                gpu_instance: None,
                label: 0,
            });
        }
        scene
    }

    fn lighting() -> BakedLighting {
        BakedLighting {
            lightmaps: vec![Lightmap { width: 1, height: 1, texels: vec![[1.0; 4]] }],
            ..BakedLighting::default()
        }
    }

    #[test]
    fn apply_gives_each_instance_its_own_split_mesh() {
        let mut scene = scene();
        let corners = scene.meshes[0].primitives[0].indices.len();
        let uvs: Vec<Vec2> = (0..corners).map(|k| Vec2::splat(k as f32 / corners as f32)).collect();
        apply(&mut scene, lighting(), &[InstanceLightmap { instance: 1, layer: 0, corner_uvs: vec![uvs.clone()] }])
            .unwrap();
        assert_eq!(scene.meshes.len(), 2);
        assert_eq!(scene.instances[0].mesh, 0);
        assert_eq!(scene.instances[0].lightmap, None);
        assert_eq!((scene.instances[1].mesh, scene.instances[1].lightmap), (1, Some(0)));
        let (old, new) = (&scene.meshes[0].primitives[0], &scene.meshes[1].primitives[0]);
        assert_eq!(new.lightmap_uv, uvs);
        assert_eq!(new.positions.len(), corners);
        for (k, &i) in old.indices.iter().enumerate() {
            assert_eq!(new.positions[k], old.positions[i as usize]);
            assert_eq!(new.normals[k], old.normals[i as usize]);
        }
        assert!(scene.baked.is_some());
    }

    #[test]
    fn placements_that_do_not_fit_are_refused() {
        let mut scene = scene();
        let e = apply(
            &mut scene,
            lighting(),
            &[InstanceLightmap { instance: 0, layer: 0, corner_uvs: vec![vec![Vec2::ZERO; 3]] }],
        );
        assert!(e.unwrap_err().contains("lightmap corners"));
        let e = apply(&mut scene, lighting(), &[InstanceLightmap { instance: 5, layer: 0, corner_uvs: vec![] }]);
        assert!(e.unwrap_err().contains("instance 5"));
        let e = apply(&mut scene, lighting(), &[InstanceLightmap { instance: 0, layer: 3, corner_uvs: vec![] }]);
        assert!(e.unwrap_err().contains("layer 3"));
    }

    #[test]
    fn probe_grid_sampling_is_trilinear_and_clamped() {
        let mut probes = Vec::new();
        for z in 0..2 {
            for y in 0..2 {
                for x in 0..3 {
                    let mut sh = ShRgb::default();
                    sh.coefficients[0] = Vec3::new(x as f32, y as f32, z as f32);
                    probes.push(sh);
                }
            }
        }
        let occlusion = (0..probes.len()).map(|k| [k as f32, 1.0, 0.5, 0.0]).collect();
        let grid =
            ProbeGrid { origin: Vec3::ZERO, spacing: Vec3::splat(2.0), counts: UVec3::new(3, 2, 2), probes, occlusion };
        let c = |p: Vec3| grid.sample(p).coefficients[0];
        assert!((c(Vec3::new(1.0, 1.0, 1.0)) - Vec3::new(0.5, 0.5, 0.5)).length() < 1e-6);
        assert!((c(Vec3::new(3.0, 0.0, 2.0)) - Vec3::new(1.5, 0.0, 1.0)).length() < 1e-6);
        assert!((c(Vec3::new(10.0, -5.0, 9.0)) - Vec3::new(2.0, 0.0, 1.0)).length() < 1e-6);
        // Occlusion blends the same way: probe k holds k in channel 0.
        let o = grid.sample_occlusion(Vec3::new(1.0, 0.0, 0.0));
        assert!((o[0] - 0.5).abs() < 1e-6 && o[1] == 1.0 && o[2] == 0.5);
        let o = grid.sample_occlusion(Vec3::new(0.0, 2.0, 2.0));
        assert!((o[0] - 9.0).abs() < 1e-6, "{o:?}");
    }
}
