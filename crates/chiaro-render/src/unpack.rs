//! Read-back bytes to a frame's images: the read-back targets and their tightly packed
//! texels flow in; the HDR image (exposure undone), the tone-mapped image, the AOVs, the
//! per-light shadow AOVs and the shadow atlases flow out into `FrameOutput`, and any other
//! exported target stays as bytes in `FrameOutput::images`.

use crate::graph::{OUTPUT, Target};
use crate::output::{Aovs, AtlasImage, FrameOutput, Ids, f16_to_f32};
use crate::passes::forward::HDR;
use crate::passes::shadows::{DIRECTIONAL_ATLAS, OTHER_ATLAS};
use crate::passes::{aov, id, shadow_aov};

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
            id::IDS => out.ids = Some(ids(&bytes)),
            shadow_aov::SHADOW => out.shadow_aovs = shadow_layers(&bytes, out.width, out.height),
            DIRECTIONAL_ATLAS => {
                let size = out.plan.shadows.directional_atlas_size;
                out.shadow_atlases.push(AtlasImage { name: "directional", size, depths: depths(&bytes) });
            }
            OTHER_ATLAS => {
                let size = out.plan.shadows.other_atlas_size;
                out.shadow_atlases.push(AtlasImage { name: "other", size, depths: depths(&bytes) });
            }
            _ => {
                out.images.insert(target, bytes);
            }
        }
    }
    if let (Some(position), Some(normal), Some(baked)) = (position, normal, baked) {
        out.aovs = Some(aovs(&position, &normal, &baked));
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
    let halves: &[u16] = bytemuck::cast_slice(bytes);
    halves
        .chunks_exact(4)
        .map(|p| {
            let c = [p[0], p[1], p[2], p[3]].map(f16_to_f32);
            [c[0] / exposure, c[1] / exposure, c[2] / exposure, c[3]]
        })
        .collect()
}

/// Each light's layer of (shadow term, coverage) pairs: the term where a surface is, NaN
/// elsewhere.
fn shadow_layers(bytes: &[u8], width: u32, height: u32) -> Vec<Vec<f32>> {
    let pairs: &[[f32; 2]] = bytemuck::cast_slice(bytes);
    pairs
        .chunks_exact((width * height) as usize)
        .map(|layer| layer.iter().map(|p| if p[1] > 0.5 { p[0] } else { f32::NAN }).collect())
        .collect()
}

fn depths(bytes: &[u8]) -> Vec<f32> {
    bytemuck::cast_slice(bytes).to_vec()
}

/// Position, normal-and-depth and baked AOVs to world-space values, NaN (infinite depth,
/// no irradiance) where no surface is.
fn aovs(position: &[u8], normal: &[u8], baked: &[u8]) -> Aovs {
    let position: &[[f32; 4]] = bytemuck::cast_slice(position);
    let normal: &[[f32; 4]] = bytemuck::cast_slice(normal);
    let baked: &[[f32; 4]] = bytemuck::cast_slice(baked);
    let mut a = Aovs::default();
    for ((p, n), e) in position.iter().zip(normal).zip(baked) {
        if p[3] > 0.5 {
            a.position_ws.push([p[0], p[1], p[2]]);
            a.normal_ws.push([n[0], n[1], n[2]]);
            a.depth.push(n[3]);
            a.baked_irradiance.push([e[0], e[1], e[2]]);
        } else {
            a.position_ws.push([f32::NAN; 3]);
            a.normal_ws.push([f32::NAN; 3]);
            a.depth.push(f32::INFINITY);
            a.baked_irradiance.push([0.0; 3]);
        }
    }
    a
}
