//! EXT_meshopt_compression: a buffer view's extension object and its compressed bytes in,
//! the view's plain bytes out. The `meshopt` crate decodes the streams and filters; this
//! module checks first every precondition its C decoder asserts on (a failed assertion
//! would abort the process), and bounds the decoded size by what the compressed bytes can
//! hold, so an untrusted count never sizes an allocation.

use serde::Deserialize;
use serde_json::Value;

/// The extension object on a buffer view.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
pub(super) struct CompressedView {
    pub(super) buffer: usize,
    #[serde(default)]
    pub(super) byte_offset: u64,
    pub(super) byte_length: u64,
    byte_stride: usize,
    count: usize,
    mode: Mode,
    #[serde(default)]
    filter: Filter,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "UPPERCASE")]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "UPPERCASE")]
enum Filter {
    #[default]
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

/// The densest meshopt stream: the vertex codec spends 2 bits on a lane of up to 256
/// bytes that does not change, so no valid stream decodes to more than this many times its
/// size (plus a small header and tail).
const MAX_EXPANSION: u64 = 1024;
const STREAM_OVERHEAD: u64 = 4096;

/// The view's extension, if it has one: parsed, or a message saying what is wrong.
pub(super) fn view_extension(raw: &Value, view: usize) -> Option<Result<CompressedView, String>> {
    let value = raw.get("bufferViews")?.get(view)?.get("extensions")?.get("EXT_meshopt_compression")?;
    Some(CompressedView::deserialize(value).map_err(|e| e.to_string()))
}

/// Whether buffer `index` is marked as the extension's fallback: a placeholder with no data
/// that only compressed views point at.
pub(super) fn is_fallback(raw: &Value, index: usize) -> bool {
    raw.pointer(&format!("/buffers/{index}/extensions/EXT_meshopt_compression/fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// Decodes `compressed` (the bytes the extension points at) into the view's bytes: `count`
/// elements of `byteStride`, which the view's `view_length` must hold.
pub(super) fn decode(view: &CompressedView, compressed: &[u8], view_length: u64) -> Result<Vec<u8>, String> {
    let stride = view.byte_stride;
    let decoded_length = (view.count as u64)
        .checked_mul(stride as u64)
        .ok_or_else(|| format!("count {} times byteStride {stride} overflows", view.count))?;
    if decoded_length > view_length {
        return Err(format!(
            "count {} times byteStride {stride} is {decoded_length} bytes, more than the buffer view's byteLength \
             ({view_length})",
            view.count
        ));
    }
    if decoded_length > (compressed.len() as u64).saturating_mul(MAX_EXPANSION) + STREAM_OVERHEAD {
        return Err(format!(
            "{} compressed bytes cannot hold {decoded_length} bytes of meshopt data",
            compressed.len()
        ));
    }
    decode_checked(view, compressed)
}

#[cfg(not(target_arch = "wasm32"))]
fn decode_checked(view: &CompressedView, compressed: &[u8]) -> Result<Vec<u8>, String> {
    match view.mode {
        Mode::Attributes => decode_attributes(view, compressed),
        Mode::Triangles | Mode::Indices => decode_indices(view, compressed),
    }
}

/// Builds without the C decoder (the browser's) read the extension's JSON and refuse its
/// data with a message that names what is missing, rather than drawing garbage.
#[cfg(target_arch = "wasm32")]
fn decode_checked(_view: &CompressedView, _compressed: &[u8]) -> Result<Vec<u8>, String> {
    Err("this build of Chiaro has no EXT_meshopt_compression decoder (the browser build leaves out \
         meshoptimizer, which is C); convert the file without meshopt compression"
        .to_string())
}

#[cfg(not(target_arch = "wasm32"))]
fn decode_attributes(view: &CompressedView, compressed: &[u8]) -> Result<Vec<u8>, String> {
    let stride = view.byte_stride;
    if stride == 0 || stride > 256 || !stride.is_multiple_of(4) {
        return Err(format!("byteStride {stride} is not a multiple of 4 from 4 to 256, as ATTRIBUTES needs"));
    }
    let filter_fits = match view.filter {
        Filter::None => true,
        Filter::Octahedral => stride == 4 || stride == 8,
        Filter::Quaternion => stride == 8,
        Filter::Exponential => stride.is_multiple_of(4),
    };
    if !filter_fits {
        return Err(format!("filter {:?} does not apply to byteStride {stride}", view.filter));
    }
    let mut bytes = vec![0u8; view.count * stride];
    // SAFETY: `bytes` holds `count * stride` bytes, which the decoder writes at most; the
    // asserted preconditions (stride a multiple of 4 up to 256) were checked above.
    let status = unsafe {
        meshopt::ffi::meshopt_decodeVertexBuffer(
            bytes.as_mut_ptr().cast(),
            view.count,
            stride,
            compressed.as_ptr(),
            compressed.len(),
        )
    };
    if status != 0 {
        return Err(format!("the ATTRIBUTES stream does not decode (meshopt error {status})"));
    }
    apply_filter(view.filter, stride, &mut bytes);
    Ok(bytes)
}

#[cfg(not(target_arch = "wasm32"))]
/// Filters turn the decoded integers back into the values the view holds, in place.
fn apply_filter(filter: Filter, stride: usize, bytes: &mut [u8]) {
    match (filter, stride) {
        (Filter::None, _) => {}
        (Filter::Octahedral, 4) => meshopt::decode_filter_oct::<i8>(bytemuck::cast_slice_mut(bytes)),
        (Filter::Octahedral, _) => with_aligned::<[i16; 4]>(bytes, meshopt::decode_filter_oct::<i16>),
        (Filter::Quaternion, _) => with_aligned::<[i16; 4]>(bytes, meshopt::decode_filter_quat),
        (Filter::Exponential, _) => with_aligned::<[u32; 1]>(bytes, meshopt::decode_filter_exp::<1>),
    }
}

#[cfg(not(target_arch = "wasm32"))]
/// Runs `filter` over `bytes` viewed as elements of `T`, through an aligned copy (a `Vec<u8>`
/// promises no alignment beyond 1).
fn with_aligned<T: bytemuck::Pod>(bytes: &mut [u8], filter: impl FnOnce(&mut [T])) {
    let mut elements: Vec<T> = bytemuck::pod_collect_to_vec(bytes);
    filter(&mut elements);
    bytes.copy_from_slice(bytemuck::cast_slice(&elements));
}

#[cfg(not(target_arch = "wasm32"))]
fn decode_indices(view: &CompressedView, compressed: &[u8]) -> Result<Vec<u8>, String> {
    let stride = view.byte_stride;
    if stride != 2 && stride != 4 {
        return Err(format!("byteStride {stride} is not 2 or 4, as {:?} needs", view.mode));
    }
    if view.filter != Filter::None {
        return Err(format!("filter {:?} applies to ATTRIBUTES only", view.filter));
    }
    if view.mode == Mode::Triangles && !view.count.is_multiple_of(3) {
        return Err(format!("count {} is not whole triangles", view.count));
    }
    let decoded: Result<Vec<u8>, _> = match (view.mode, stride) {
        (Mode::Triangles, 2) => meshopt::decode_index_buffer::<u16>(compressed, view.count).map(to_bytes),
        (Mode::Triangles, _) => meshopt::decode_index_buffer::<u32>(compressed, view.count).map(to_bytes),
        (_, 2) => meshopt::decode_index_sequence::<u16>(compressed, view.count).map(to_bytes),
        (_, _) => meshopt::decode_index_sequence::<u32>(compressed, view.count).map(to_bytes),
    };
    decoded.map_err(|e| format!("the {:?} stream does not decode ({e})", view.mode))
}

#[cfg(not(target_arch = "wasm32"))]
fn to_bytes<T: bytemuck::Pod>(values: Vec<T>) -> Vec<u8> {
    bytemuck::cast_slice(&values).to_vec()
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;

    fn view(mode: Mode, stride: usize, count: usize, filter: Filter) -> CompressedView {
        CompressedView { buffer: 0, byte_offset: 0, byte_length: 0, byte_stride: stride, count, mode, filter }
    }

    #[test]
    fn attributes_and_triangles_round_trip() {
        let vertices: Vec<[f32; 3]> = (0..100).map(|i| [i as f32, (i * 2) as f32, 0.5]).collect();
        let encoded = meshopt::encode_vertex_buffer(&vertices).unwrap();
        let decoded = decode(&view(Mode::Attributes, 12, 100, Filter::None), &encoded, 1200).unwrap();
        assert_eq!(decoded, bytemuck::cast_slice::<_, u8>(&vertices));

        let indices: Vec<u32> = (0..99).map(|i| (i * 7) % 100).collect();
        let encoded = meshopt::encode_index_buffer(&indices, 100).unwrap();
        let decoded = decode(&view(Mode::Triangles, 4, 99, Filter::None), &encoded, 396).unwrap();
        let decoded: Vec<u32> = bytemuck::pod_collect_to_vec(&decoded);
        // The index codec may rotate a triangle's corners; the winding stays.
        for (d, i) in decoded.chunks_exact(3).zip(indices.chunks_exact(3)) {
            let rotations = [[i[0], i[1], i[2]], [i[1], i[2], i[0]], [i[2], i[0], i[1]]];
            assert!(rotations.iter().any(|r| r == d), "{d:?} is not {i:?} rotated");
        }
    }

    #[test]
    fn octahedral_filter_gives_unit_normals() {
        let normals = [[0.0f32, 0.0, 1.0, 0.0], [0.6, 0.8, 0.0, 0.0], [0.0, -1.0, 0.0, 0.0]];
        let filtered: Vec<[i8; 4]> = meshopt::encode_filter_oct(&normals, 8);
        let encoded = meshopt::encode_vertex_buffer(&filtered).unwrap();
        let decoded = decode(&view(Mode::Attributes, 4, 3, Filter::Octahedral), &encoded, 12).unwrap();
        for (n, d) in normals.iter().zip(decoded.chunks_exact(4)) {
            let d: Vec<f32> = d[..3].iter().map(|&c| f32::from(c as i8) / 127.0).collect();
            for k in 0..3 {
                assert!((d[k] - n[k]).abs() < 0.03, "{d:?} against {n:?}");
            }
        }
    }

    #[test]
    fn what_the_decoder_would_assert_on_is_refused() {
        let cases = [
            view(Mode::Attributes, 6, 1, Filter::None),
            view(Mode::Attributes, 260, 1, Filter::None),
            view(Mode::Attributes, 12, 1, Filter::Quaternion),
            view(Mode::Triangles, 3, 3, Filter::None),
            view(Mode::Triangles, 4, 4, Filter::None),
            view(Mode::Indices, 4, 4, Filter::Octahedral),
        ];
        for case in &cases {
            let length = (case.count * case.byte_stride) as u64;
            assert!(decode(case, &[0; 64], length).is_err(), "{case:?}");
        }
        // A count far beyond what the bytes can hold is refused before anything is allocated.
        let huge = view(Mode::Attributes, 256, 1 << 40, Filter::None);
        let message = decode(&huge, &[0; 16], u64::MAX).unwrap_err();
        assert!(message.contains("cannot hold"), "{message}");
        // Garbage does not decode, and says so.
        assert!(decode(&view(Mode::Attributes, 12, 100, Filter::None), &[0xA0; 40], 1200).is_err());
    }
}
