//! The bake directory's binary files: little-endian f32 values, encoded and decoded here
//! alone. `lightmap-uvs.bin` holds each lightmapped instance's corner coordinates (pairs),
//! `probes.bin` nine RGB coefficients per probe, `probe-occlusion.bin` four channels'
//! visibility per probe. Values flow in and bytes out, and back; a file longer than the
//! manifest accounts for is refused before it is read.

use super::BakeDirError;
use chiaro_math::sh::{SH_COEFFICIENTS, ShRgb};
use chiaro_scene::baked::InstanceLightmap;
use glam::{Vec2, Vec3};
use std::path::Path;

/// Bytes of one f32.
const F32_BYTES: usize = 4;
/// Bytes of one probe's coefficients in `probes.bin`.
pub const PROBE_BYTES: usize = SH_COEFFICIENTS * 3 * F32_BYTES;
/// Bytes of one probe's occlusion in `probe-occlusion.bin`.
pub const OCCLUSION_BYTES: usize = 4 * F32_BYTES;

/// `values` as little-endian bytes.
pub fn encode(values: impl IntoIterator<Item = f32>) -> Vec<u8> {
    values.into_iter().flat_map(f32::to_le_bytes).collect()
}

/// Little-endian bytes as values; a trailing partial value is dropped (callers check the
/// length first).
pub fn decode(bytes: &[u8]) -> Vec<f32> {
    bytes.chunks_exact(F32_BYTES).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect()
}

/// Writes `bytes` to `path`.
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), BakeDirError> {
    std::fs::write(path, bytes).map_err(BakeDirError::io(path))
}

/// A file's bytes, refusing one longer than `limit` before reading it (a bake directory
/// is input: a broken or hostile one must not make the reader allocate without bound).
pub fn read_at_most(path: &Path, limit: usize) -> Result<Vec<u8>, BakeDirError> {
    let len = std::fs::metadata(path).map_err(BakeDirError::io(path))?.len();
    if len > limit as u64 {
        return Err(BakeDirError::TooLong { path: path.to_path_buf(), len, limit });
    }
    std::fs::read(path).map_err(BakeDirError::io(path))
}

/// Exactly `probes` records of `record_bytes` each from `path`, as values.
fn read_probe_records(path: &Path, probes: usize, record_bytes: usize) -> Result<Vec<f32>, BakeDirError> {
    let wanted = probes * record_bytes;
    let bytes = read_at_most(path, wanted)?;
    if bytes.len() != wanted {
        return Err(BakeDirError::ProbeBytes { path: path.to_path_buf(), found: bytes.len(), probes, wanted });
    }
    Ok(decode(&bytes))
}

/// The corner coordinates of every placement, instance after instance.
pub fn encode_uvs(placements: &[InstanceLightmap]) -> Vec<u8> {
    encode(placements.iter().flat_map(|p| p.corner_uvs.iter().flatten()).flat_map(|uv| [uv.x, uv.y]))
}

/// Reads `lightmap-uvs.bin` back into placements: `layers[i]` and `corners[i]` (corners
/// per primitive) of instance `instances[i]`, as the manifest lists them.
pub fn read_uvs(path: &Path, instances: &[(usize, u32, &[usize])]) -> Result<Vec<InstanceLightmap>, BakeDirError> {
    let wanted: usize = instances.iter().flat_map(|(_, _, corners)| corners.iter()).sum::<usize>() * 2;
    let bytes = read_at_most(path, wanted * F32_BYTES)?;
    let floats = decode(&bytes);
    if floats.len() != wanted || bytes.len() % F32_BYTES != 0 {
        return Err(BakeDirError::UvCount { path: path.to_path_buf(), found: floats.len(), wanted });
    }
    let mut cursor = floats.chunks_exact(2).map(|p| Vec2::new(p[0], p[1]));
    Ok(instances
        .iter()
        .map(|&(instance, layer, corners)| InstanceLightmap {
            instance,
            layer,
            corner_uvs: corners.iter().map(|&n| cursor.by_ref().take(n).collect()).collect(),
        })
        .collect())
}

/// Every probe's coefficients, probe after probe, RGB after RGB.
pub fn encode_probes(probes: &[ShRgb]) -> Vec<u8> {
    encode(probes.iter().flat_map(|p| p.coefficients).flat_map(|c| c.to_array()))
}

/// Reads `probes` probes' coefficients from `path`.
pub fn read_probes(path: &Path, probes: usize) -> Result<Vec<ShRgb>, BakeDirError> {
    let values = read_probe_records(path, probes, PROBE_BYTES)?;
    Ok(values
        .chunks_exact(SH_COEFFICIENTS * 3)
        .map(|c| ShRgb { coefficients: std::array::from_fn(|k| Vec3::new(c[3 * k], c[3 * k + 1], c[3 * k + 2])) })
        .collect())
}

/// Every probe's four channels of occlusion.
pub fn encode_occlusion(occlusion: &[[f32; 4]]) -> Vec<u8> {
    encode(occlusion.iter().flatten().copied())
}

/// Reads `probes` probes' occlusion from `path`.
pub fn read_occlusion(path: &Path, probes: usize) -> Result<Vec<[f32; 4]>, BakeDirError> {
    let values = read_probe_records(path, probes, OCCLUSION_BYTES)?;
    Ok(values.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_round_trip_bit_for_bit_in_little_endian() {
        let values = [0.0, -0.0, 1.5, f32::MIN_POSITIVE, f32::MAX, f32::NEG_INFINITY];
        let bytes = encode(values);
        assert_eq!(&bytes[8..12], &[0, 0, 0xc0, 0x3f], "1.5 little-endian");
        let back = decode(&bytes);
        assert!(back.iter().zip(values).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(decode(&bytes[..5]).len(), 1, "a partial value is dropped");
    }
}
