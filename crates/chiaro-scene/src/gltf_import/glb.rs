//! GLB container bytes in, the JSON chunk and the optional BIN chunk out, as slices of the
//! input. Every offset is checked, since the `gltf` crate's own GLB reader underflows on
//! short headers; a malformed container is a message for `SceneError::Parse`.

/// Splits a GLB container into its JSON chunk and its optional BIN chunk (glTF 2.0 §4.4).
/// Unknown chunk types are skipped, as the specification asks.
pub fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let u32_at = |offset: usize| -> Option<u32> {
        let b = bytes.get(offset..offset.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err("GLB header is truncated".into());
    };
    if version != 2 {
        return Err(format!("GLB container version {version}; Chiaro reads version 2"));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(format!("GLB header says {length} bytes but the file has {}", bytes.len()));
    }
    let mut offset = 12;
    let mut json_chunk = None;
    let mut bin_chunk = None;
    while offset + 8 <= length {
        let chunk_length = u32_at(offset).unwrap_or(0) as usize;
        let chunk_type = &bytes[offset + 4..offset + 8];
        let start = offset + 8;
        let end = start
            .checked_add(chunk_length)
            .filter(|&end| end <= length)
            .ok_or_else(|| format!("GLB chunk at byte {offset} runs past the end of the file"))?;
        match chunk_type {
            b"JSON" if json_chunk.is_none() && offset == 12 => {
                json_chunk = Some(&bytes[start..end]);
            }
            b"BIN\0" if bin_chunk.is_none() && json_chunk.is_some() => {
                bin_chunk = Some(&bytes[start..end]);
            }
            _ if offset == 12 => return Err("GLB file does not start with a JSON chunk".into()),
            _ => {}
        }
        offset = end;
    }
    let json_chunk = json_chunk.ok_or("GLB file has no JSON chunk")?;
    Ok((json_chunk, bin_chunk))
}
