//! Read-back bytes to a frame's images: the read-back targets and their tightly packed
//! texels flow in; the HDR image (exposure undone), the tone-mapped image, the AOVs, the
//! per-light shadow AOVs and the shadow atlases flow out into `FrameOutput`, and any other
//! exported target stays as bytes in `FrameOutput::images`.

use crate::graph::{OUTPUT, Target};
use crate::output::{Aovs, AtlasImage, FrameOutput, Ids};
use crate::passes::targets::HDR;
use crate::passes::targets::{DIRECTIONAL_ATLAS, LOCAL_ATLAS};
use crate::passes::{ambient_occlusion, aov, id, shadow_aov};

/// Fills `out` from the read-back bytes of each target.
pub fn unpack_images(out: &mut FrameOutput, read: Vec<(Target, Vec<u8>)>, exposure: f32) {
    let mut position = None;
    let mut normal = None;
    let mut baked = None;
    for (target, bytes) in read {
        match target {
            HDR => out.hdr = hdr_image(&bytes, exposure),
            OUTPUT => out.ldr = bytes,
            aov::POSITION => position = Some(bytes),
            aov::NORMAL_DEPTH => normal = Some(bytes),
            aov::BAKED => baked = Some(bytes),
            aov::VIEW_DEPTH => out.aovs = Some(view_depth(&bytes)),
            id::IDS => out.ids = Some(ids(&bytes)),
            ambient_occlusion::AMBIENT_OCCLUSION => out.ambient_occlusion = Some(bytemuck::pod_collect_to_vec(&bytes)),
            shadow_aov::SHADOW => {
                (out.shadow_aovs, out.shadow_texels_per_pixel) = shadow_layers(&bytes, out.width, out.height);
            }
            DIRECTIONAL_ATLAS => {
                let size = out.plan.shadows.directional_atlas_size;
                out.shadow_atlases.push(AtlasImage { name: "directional", size, depths: depths(&bytes) });
            }
            LOCAL_ATLAS => {
                let size = out.plan.shadows.local_atlas_size;
                out.shadow_atlases.push(AtlasImage { name: "other", size, depths: depths(&bytes) });
            }
            _ => {
                out.images.insert(target, bytes);
            }
        }
    }
    // Without a bake the AOV pass writes no baked target: the irradiance is zero.
    if let (Some(position), Some(normal)) = (position, normal) {
        out.aovs = Some(aovs(&position, &normal, baked.as_deref()));
    }
}

/// Rg32Uint (node, label) texels to the two id images.
fn ids(bytes: &[u8]) -> Ids {
    let (instance, label) = bytes
        .chunks_exact(8)
        .map(|t| (u32::from_le_bytes([t[0], t[1], t[2], t[3]]), u32::from_le_bytes([t[4], t[5], t[6], t[7]])))
        .unzip();
    Ids { instance, label }
}

/// Rgba16Float pre-exposed radiance to linear radiance.
fn hdr_image(bytes: &[u8], exposure: f32) -> Vec<[f32; 4]> {
    use half::slice::{HalfBitsSliceExt, HalfFloatSliceExt};
    let bits: &[u16] = bytemuck::cast_slice(bytes);
    // half converts whole slices with the CPU's F16C instructions where it has them.
    let mut linear = vec![0.0f32; bits.len()];
    bits.reinterpret_cast::<half::f16>().convert_to_f32_slice(&mut linear);
    linear.chunks_exact(4).map(|c| [c[0] / exposure, c[1] / exposure, c[2] / exposure, c[3]]).collect()
}

/// Per light layer: the shadow term and the texels per pixel, NaN where no surface is
/// (and, for the texels, where no map was sampled). The second channel is 0 where no
/// surface is, else 1 + texels per pixel.
fn shadow_layers(bytes: &[u8], width: u32, height: u32) -> (Vec<Vec<f32>>, Vec<Vec<f32>>) {
    let texels: &[[f32; 2]] = bytemuck::cast_slice(bytes);
    texels
        .chunks_exact((width * height) as usize)
        .map(|layer| {
            let covered = |p: &[f32; 2]| p[1] > 0.5;
            let shadow = layer.iter().map(|p| if covered(p) { p[0] } else { f32::NAN }).collect();
            let ratio = layer.iter().map(|p| if p[1] > 1.0 { p[1] - 1.0 } else { f32::NAN }).collect();
            (shadow, ratio)
        })
        .unzip()
}

fn depths(bytes: &[u8]) -> Vec<f32> {
    bytemuck::cast_slice(bytes).to_vec()
}

/// Position, normal-and-depth and baked AOVs to world-space values, NaN (infinite depth,
/// no irradiance) where no surface is.
/// A depth-only request's AOVs: the view depth, infinite where no surface is (0 there in
/// the target); position, normal and irradiance stay empty.
fn view_depth(bytes: &[u8]) -> Aovs {
    let depth: &[f32] = bytemuck::cast_slice(bytes);
    Aovs { depth: depth.iter().map(|&d| if d > 0.0 { d } else { f32::INFINITY }).collect(), ..Aovs::default() }
}

fn aovs(position: &[u8], normal: &[u8], baked: Option<&[u8]>) -> Aovs {
    let position: &[[f32; 4]] = bytemuck::cast_slice(position);
    let normal: &[[f32; 4]] = bytemuck::cast_slice(normal);
    // Alpha 1 marks a surface; the sky holds NaN (position, normal) or infinity (depth).
    let covered = |p: &[f32; 4]| p[3] > 0.5;
    let baked_irradiance = match baked {
        Some(bytes) => {
            let baked: &[[f32; 4]] = bytemuck::cast_slice(bytes);
            position.iter().zip(baked).map(|(p, e)| if covered(p) { [e[0], e[1], e[2]] } else { [0.0; 3] }).collect()
        }
        // No bake, no baked pass: zero everywhere.
        None => vec![[0.0; 3]; position.len()],
    };
    Aovs {
        position_ws: position.iter().map(|p| if covered(p) { [p[0], p[1], p[2]] } else { [f32::NAN; 3] }).collect(),
        normal_ws: position
            .iter()
            .zip(normal)
            .map(|(p, n)| if covered(p) { [n[0], n[1], n[2]] } else { [f32::NAN; 3] })
            .collect(),
        depth: position.iter().zip(normal).map(|(p, n)| if covered(p) { n[3] } else { f32::INFINITY }).collect(),
        baked_irradiance,
    }
}

#[cfg(test)]
mod tests {
    use super::{aovs, hdr_image};

    #[test]
    fn half_floats_convert_exactly_and_lose_the_exposure() {
        // 1, -2, the largest half, infinity; then a subnormal, a small normal, 1/3 rounded.
        let halves: [u16; 8] = [0x3c00, 0xc000, 0x7bff, 0x7c00, 0x0001, 0x0200, 0x3555, 0x3c00];
        let image = hdr_image(bytemuck::cast_slice(&halves), 2.0);
        assert_eq!(image[0][..3], [0.5, -1.0, 32752.0]);
        assert!(image[0][3].is_infinite(), "alpha keeps no exposure");
        assert_eq!(image[1][0], 5.960_464_5e-8 / 2.0);
        assert_eq!(image[1][1], 3.051_757_8e-5 / 2.0);
        assert_eq!(image[1][2], 0.333_251_95 / 2.0);
        assert_eq!(image[1][3], 1.0);
    }

    #[test]
    fn aovs_mark_the_sky_and_fill_zero_irradiance_without_a_bake() {
        let position: [[f32; 4]; 2] = [[1.0, 2.0, 3.0, 1.0], [0.0; 4]];
        let normal: [[f32; 4]; 2] = [[0.0, 1.0, 0.0, 7.5], [0.0; 4]];
        let a = aovs(bytemuck::cast_slice(&position), bytemuck::cast_slice(&normal), None);
        assert_eq!(a.position_ws[0], [1.0, 2.0, 3.0]);
        assert_eq!(a.normal_ws[0], [0.0, 1.0, 0.0]);
        assert_eq!(a.depth, [7.5, f32::INFINITY]);
        assert!(a.position_ws[1].iter().chain(&a.normal_ws[1]).all(|v| v.is_nan()));
        assert_eq!(a.baked_irradiance, [[0.0; 3]; 2]);
        let baked: [[f32; 4]; 2] = [[4.0, 5.0, 6.0, 1.0], [9.0; 4]];
        let a =
            aovs(bytemuck::cast_slice(&position), bytemuck::cast_slice(&normal), Some(bytemuck::cast_slice(&baked)));
        assert_eq!(a.baked_irradiance, [[4.0, 5.0, 6.0], [0.0; 3]]);
    }
}
