//! Debug views the viewers (native and browser) compute on the CPU from a frame read back:
//! the AOVs, the clusters' light counts and the shadow atlases, as RGBA8 images; and which
//! views show the 3D view itself rather than such images.

use crate::plan::clusters::{ClusterGrid, CulledLightLists};
use crate::{AovView, DebugView, FrameOutput};
use chiaro_math::bounds::Aabb;
use chiaro_scene::Scene;

/// Side of each shadow atlas as the atlas debug view shows it.
const ATLAS_VIEW_SIZE: usize = 512;

/// An image to show: its size (width, height) and RGBA8 pixels.
pub type DebugImage = ([usize; 2], Vec<[u8; 4]>);

/// Whether the 3D view itself is shown (else a debug image is, or nothing yet).
pub fn shows_view(debug: Option<DebugView>, has_disagreement: bool) -> bool {
    match debug {
        None
        | Some(DebugView::Cascades | DebugView::GbufferAlbedo | DebugView::GbufferNormal | DebugView::LightOverdraw) => {
            true
        }
        Some(DebugView::Reference) => !has_disagreement,
        Some(DebugView::Aov(_) | DebugView::Clusters | DebugView::ShadowAtlases | DebugView::VirtualPages) => false,
    }
}

/// What a frame shows in place of the lit 3D view, as images egui draws.
pub fn frame_images(debug: Option<DebugView>, frame: &FrameOutput, scene: &Scene) -> Vec<DebugImage> {
    let size = [frame.width as usize, frame.height as usize];
    let aovs = frame.aovs.as_ref();
    let image = |pixels: Vec<[u8; 4]>| vec![(size, pixels)];
    match debug {
        Some(DebugView::ShadowAtlases) => frame
            .shadow_atlases
            .iter()
            .map(|atlas| {
                let grey = atlas_grey(&atlas.depths);
                let (side, pixels) = atlas_image(&grey, atlas.size as usize, ATLAS_VIEW_SIZE);
                ([side, side], pixels)
            })
            .collect(),
        Some(DebugView::Aov(aov)) => {
            let Some(a) = aovs else { return Vec::new() };
            match aov {
                AovView::Position => image(position_image(&a.position_ws, &scene.bounds())),
                AovView::Normal => image(normal_image(&a.normal_ws, &a.depth)),
                AovView::Depth => image(depth_image(&a.depth)),
                AovView::Lightmap => image(lightmap_image(&a.baked_irradiance, &a.depth)),
                AovView::Shadow(i) => match frame.shadow_aovs.get(i) {
                    Some(shadow) => image(shadow_image(shadow, &a.depth)),
                    None => Vec::new(),
                },
            }
        }
        Some(DebugView::VirtualPages) => match frame.plan.shadows.virtual_maps.page_table_image() {
            Some((width, height, pixels)) => vec![([width, height], pixels)],
            None => Vec::new(),
        },
        Some(DebugView::Clusters) => match (aovs, &frame.plan.culled.grid) {
            (Some(a), Some(grid)) => {
                let most = (frame.plan.lights.len() as u32).clamp(1, 32);
                image(cluster_image(grid, &frame.plan.culled.lists, &a.depth, most))
            }
            _ => Vec::new(),
        },
        _ => Vec::new(),
    }
}

/// Background pixels (no surface) in the AOV views.
const NO_SURFACE: [u8; 4] = [24, 24, 32, 255];

fn unit_to_byte(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn rgb(v: [f32; 3]) -> [u8; 4] {
    [unit_to_byte(v[0]), unit_to_byte(v[1]), unit_to_byte(v[2]), 255]
}

/// Position AOV with each axis mapped across `bounds`.
pub fn position_image(positions: &[[f32; 3]], bounds: &Aabb) -> Vec<[u8; 4]> {
    let extent = (bounds.max - bounds.min).max(glam::Vec3::splat(1e-6));
    positions
        .iter()
        .map(|p| {
            if !p[0].is_finite() {
                return NO_SURFACE;
            }
            let t = (glam::Vec3::from(*p) - bounds.min) / extent;
            rgb(t.to_array())
        })
        .collect()
}

/// Normals as `n * 0.5 + 0.5`, background where there is no surface.
pub fn normal_image(normals: &[[f32; 3]], depth: &[f32]) -> Vec<[u8; 4]> {
    normals
        .iter()
        .zip(depth)
        .map(|(n, d)| if d.is_finite() { rgb(n.map(|c| c * 0.5 + 0.5)) } else { NO_SURFACE })
        .collect()
}

/// Depth as grey, near white and far black, logarithmic so that near and far detail both
/// show.
pub fn depth_image(depth: &[f32]) -> Vec<[u8; 4]> {
    let finite = || depth.iter().copied().filter(|d| d.is_finite() && *d > 0.0);
    let near = finite().fold(f32::INFINITY, f32::min);
    let far = finite().fold(0.0f32, f32::max);
    let span = (far / near).ln().max(1e-6);
    depth
        .iter()
        .map(|&d| {
            if !(d.is_finite() && d > 0.0) {
                return NO_SURFACE;
            }
            let v = unit_to_byte(1.0 - (d / near).ln() / span);
            [v, v, v, 255]
        })
        .collect()
}

/// Irradiance scaled so that the brightest texel is white.
pub fn lightmap_image(irradiance: &[[f32; 3]], depth: &[f32]) -> Vec<[u8; 4]> {
    let brightest = irradiance.iter().flatten().copied().filter(|v| v.is_finite()).fold(1e-6f32, f32::max);
    irradiance
        .iter()
        .zip(depth)
        .map(|(e, d)| if d.is_finite() { rgb(e.map(|c| c / brightest)) } else { NO_SURFACE })
        .collect()
}

/// A light's shadow (1 lit, 0 shadowed) as grey, background where there is no surface.
pub fn shadow_image(shadow: &[f32], depth: &[f32]) -> Vec<[u8; 4]> {
    shadow
        .iter()
        .zip(depth)
        .map(|(&s, d)| {
            if !d.is_finite() {
                return NO_SURFACE;
            }
            let v = unit_to_byte(s);
            [v, v, v, 255]
        })
        .collect()
}

/// A heat colour for `count` of `most`: blue for none, through green and yellow, to red.
pub fn heat(count: u32, most: u32) -> [u8; 4] {
    if count == 0 {
        return [0, 0, 96, 255];
    }
    let t = (count as f32 / most.max(1) as f32).clamp(0.0, 1.0);
    let (r, g) = if t < 0.5 { (2.0 * t, 1.0) } else { (1.0, 2.0 * (1.0 - t)) };
    [unit_to_byte(r), unit_to_byte(g), 0, 255]
}

/// Each pixel coloured by how many lights its cluster lists, as the forward pass finds
/// the cluster (pixel and view depth); `most` is the count shown red.
pub fn cluster_image(grid: &ClusterGrid, lists: &CulledLightLists, depth: &[f32], most: u32) -> Vec<[u8; 4]> {
    let width = grid.width as usize;
    depth
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            if !d.is_finite() {
                return NO_SURFACE;
            }
            let (x, y) = ((i % width) as f32 + 0.5, (i / width) as f32 + 0.5);
            let cluster = grid.cluster_at(x, y, d);
            heat(if cluster < lists.len() { lists.count(cluster) as u32 } else { 0 }, most)
        })
        .collect()
}

/// An atlas's grey RGBA8 image (`size` texels a side), sampled down to at most
/// `max_side` texels a side.
pub fn atlas_image(grey: &[u8], size: usize, max_side: usize) -> (usize, Vec<[u8; 4]>) {
    let side = size.min(max_side);
    let step = size / side;
    let pixels = (0..side * side)
        .map(|k| {
            let (x, y) = ((k % side) * step, (k / side) * step);
            let v = grey[(y * size + x) * 4];
            [v, v, v, 255]
        })
        .collect();
    (side, pixels)
}

/// An atlas's depths as grey RGBA8, stretched over the range the casters wrote (from the
/// nearest depth to 1, the cleared far plane): perspective depth crowds towards 1 with a
/// near plane of a centimetre, and would otherwise print all white.
pub fn atlas_grey(depths: &[f32]) -> Vec<u8> {
    let nearest = depths.iter().copied().filter(|d| d.is_finite() && *d < 1.0).fold(1.0f32, f32::min);
    let span = (1.0 - nearest).max(1e-6);
    depths
        .iter()
        .flat_map(|d| {
            let v = (((d.clamp(0.0, 1.0) - nearest) / span).clamp(0.0, 1.0) * 255.0).round() as u8;
            [v, v, v, 255]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atlas_images_are_sampled_down() {
        // A 1024-texel atlas, dark in its left half.
        let size = 1024;
        let grey: Vec<u8> =
            (0..size * size).flat_map(|k| if k % size < size / 2 { [0u8; 4] } else { [255; 4] }).collect();
        let (side, image) = atlas_image(&grey, size, 512);
        assert_eq!((side, image.len()), (512, 512 * 512));
        assert_eq!(image[0], [0, 0, 0, 255]);
        assert_eq!(image[511], [255, 255, 255, 255]);
        assert_eq!(atlas_image(&[9; 4 * 16], 4, 512).0, 4, "a small atlas is shown as it is");
    }

    #[test]
    fn clusters_show_their_light_counts_where_the_shader_looks_them_up() {
        let grid = ClusterGrid::new(64, 32, 0.1, 100.0);
        let clusters = grid.cluster_count();
        // Cluster k lists k % 5 lights.
        let mut lists = CulledLightLists { starts: vec![0], indices: Vec::new() };
        for k in 0..clusters {
            lists.indices.extend(std::iter::repeat_n(7, k % 5));
            lists.starts.push(lists.indices.len() as u32);
        }
        let depth: Vec<f32> = (0..64 * 32).map(|i| if i == 0 { f32::INFINITY } else { 1.0 + (i % 7) as f32 }).collect();
        let image = cluster_image(&grid, &lists, &depth, 4);
        assert_eq!(image[0], NO_SURFACE);
        for i in 1..depth.len() {
            let k = grid.cluster_at((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5, depth[i]);
            assert_eq!(image[i], heat((k % 5) as u32, 4), "pixel {i}");
        }
        assert_eq!(heat(4, 4), [255, 0, 0, 255]);
        assert_eq!(heat(0, 4), [0, 0, 96, 255]);
    }

    #[test]
    fn depth_runs_from_white_near_to_black_far() {
        let image = depth_image(&[1.0, 10.0, 100.0, f32::INFINITY]);
        assert_eq!(image[0], [255, 255, 255, 255]);
        assert_eq!(image[1], [128, 128, 128, 255]);
        assert_eq!(image[2], [0, 0, 0, 255]);
        assert_eq!(image[3], NO_SURFACE);
    }
}
