//! KTX2 images (KHR_texture_basisu's Basis Universal textures, and KTX2 files holding
//! plain 8-bit RGB or RGBA): the file's bytes in, RGBA8 texels for every mip level the
//! file stores out. The `basisu` crate (a pure-Rust port of Binomial's transcoder)
//! transcodes ETC1S and UASTC; the `ktx2` crate reads the container of plain formats and
//! `ruzstd` inflates their Zstandard supercompression. Sizes the header claims are
//! checked against limits and against what the file's bytes can hold before anything is
//! allocated for them.

use basisu::{DecodeFlags, TargetFormat, Transcoder};
use ktx2::{Format, SupercompressionScheme};

pub(super) const EXTENSION: &str = "KHR_texture_basisu";

/// The widest and tallest image read: 16384 texels, as wide as a GPU texture goes.
const MAX_SIDE: u32 = 16384;
/// The densest Basis Universal file: no ETC1S or UASTC stream decodes to more RGBA8 bytes
/// than this many times its own size (UASTC is 8 bits a texel before supercompression,
/// ETC1S with a flat image about 0.05), plus a header's worth.
const MAX_EXPANSION: u64 = 4096;
const OVERHEAD: u64 = 1 << 20;

/// The identifier every KTX2 file starts with.
const MAGIC: [u8; 12] = [0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n'];

pub(super) fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

/// A decoded KTX2 image: its size and RGBA8 texels per mip level, the largest first,
/// each level half the size of the one before (rounded down, at least 1).
pub(super) struct Levels {
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) rgba8: Vec<Vec<u8>>,
    /// ETC1S or UASTC: a device with BC textures may transcode it to BC7 instead.
    pub(super) basis: bool,
}

/// Decodes a KTX2 file; the message says what is wrong with it.
pub(super) fn decode(bytes: &[u8]) -> Result<Levels, String> {
    let reader = ktx2::Reader::new(bytes).map_err(|e| format!("not a readable KTX2 file: {e}"))?;
    let header = reader.header();
    let (width, height) = (header.pixel_width, header.pixel_height);
    if height == 0 || header.pixel_depth > 1 || header.layer_count > 1 || header.face_count != 1 {
        return Err(format!(
            "a KTX2 {width} x {height} x {} texture with {} layers and {} faces is not a 2D image",
            header.pixel_depth, header.layer_count, header.face_count
        ));
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(format!("a {width} x {height} KTX2 image is larger than {MAX_SIDE} x {MAX_SIDE}"));
    }
    let largest = u64::from(width) * u64::from(height) * 4;
    if largest > (bytes.len() as u64).saturating_mul(MAX_EXPANSION) + OVERHEAD {
        return Err(format!("{} bytes cannot hold a {width} x {height} image", bytes.len()));
    }
    // The transcoder allocates what a level's index says it inflates to: no level of an
    // ETC1S, UASTC or 8-bit image holds more than four bytes a texel of its size padded
    // to whole 4x4 blocks (UASTC spends 16 bytes on a block, a 1x1 level's too).
    for (level, index) in reader.levels().enumerate() {
        let (w, h) = level_size(width, height, level);
        let most = u64::from(w.next_multiple_of(4)) * u64::from(h.next_multiple_of(4)) * 4;
        if index.uncompressed_byte_length > most {
            return Err(format!(
                "level {level} says it inflates to {} bytes, more than {w} x {h} texels take",
                index.uncompressed_byte_length
            ));
        }
    }
    let rgba8 = match header.format {
        None => basis_levels(bytes, TargetFormat::Rgba32, 4)?,
        Some(format) => plain_levels(&reader, format, header.supercompression_scheme)?,
    };
    Ok(Levels { width, height, rgba8, basis: header.format.is_none() })
}

/// The size of mip level `level` of a `width` x `height` image.
fn level_size(width: u32, height: u32, level: usize) -> (u32, u32) {
    let shift = level.min(31) as u32;
    ((width >> shift).max(1), (height >> shift).max(1))
}

/// ETC1S or UASTC (vkFormat UNDEFINED), transcoded level by level to `target`: RGBA8
/// (`Rgba32`, 4 bytes a texel) or a block format (`Bc7Rgba`, 16 bytes a 4x4 block, passed
/// as 16 bytes a "texel" of a level counted in blocks).
fn basis_levels(bytes: &[u8], target: TargetFormat, bytes_per_unit: usize) -> Result<Vec<Vec<u8>>, String> {
    let transcoder = Transcoder::new(bytes).map_err(|e| format!("not a Basis Universal texture: {e:?}"))?;
    let blocks = target != TargetFormat::Rgba32;
    (0..transcoder.level_count())
        .map(|level| {
            let info = transcoder.image_level_info(level).map_err(|e| format!("level {level}: {e:?}"))?;
            let texels = transcoder
                .transcode(level, target, DecodeFlags::NONE)
                .map_err(|e| format!("level {level} does not transcode: {e:?}"))?;
            let (w, h) = (info.width as usize, info.height as usize);
            let units = if blocks { w.div_ceil(4) * h.div_ceil(4) } else { w * h };
            let expected = units * bytes_per_unit;
            if texels.len() != expected {
                return Err(format!("level {level} transcodes to {} bytes, not {expected}", texels.len()));
            }
            Ok(texels)
        })
        .collect()
}

impl crate::types::Image {
    /// The image as BC7 blocks, each level of the file (the largest first, rows of 4x4
    /// blocks of 16 bytes), for a device that samples BC7; `None` for an image that is not
    /// ETC1S or UASTC. Transcoded on the first call, kept for the next. The message says
    /// why a level does not transcode or is not the size of its place in the chain.
    pub fn bc7_levels(&self) -> Option<&Result<Vec<Vec<u8>>, String>> {
        let source = self.basis_source.as_ref()?;
        Some(source.bc7.get_or_init(|| {
            let levels = basis_levels(&source.ktx2, TargetFormat::Bc7Rgba, 16)?;
            for (level, blocks) in levels.iter().enumerate() {
                let (w, h) = level_size(self.width, self.height, level);
                let expected = w.div_ceil(4) as usize * h.div_ceil(4) as usize * 16;
                if blocks.len() != expected {
                    return Err(format!(
                        "level {level} is {} bytes of BC7, not the {expected} of {w} x {h}",
                        blocks.len()
                    ));
                }
            }
            Ok(levels)
        }))
    }
}

/// 8-bit RGBA or RGB (UNORM or SRGB), stored plain or Zstandard-supercompressed.
fn plain_levels(
    reader: &ktx2::Reader<&[u8]>,
    format: Format,
    supercompression: Option<SupercompressionScheme>,
) -> Result<Vec<Vec<u8>>, String> {
    let channels = match format {
        Format::R8G8B8A8_UNORM | Format::R8G8B8A8_SRGB => 4,
        Format::R8G8B8_UNORM | Format::R8G8B8_SRGB => 3,
        other => {
            return Err(format!(
                "KTX2 format {other:?} is not read; Chiaro reads Basis Universal (ETC1S, UASTC) and 8-bit RGB or RGBA"
            ));
        }
    };
    let header = reader.header();
    reader
        .levels()
        .enumerate()
        .map(|(level, data)| {
            let (w, h) = level_size(header.pixel_width, header.pixel_height, level);
            let expected = w as usize * h as usize * channels;
            let texels = match supercompression {
                None => data.data.to_vec(),
                Some(SupercompressionScheme::Zstandard) => inflate(data.data, expected).ok_or_else(|| {
                    format!("level {level}: the Zstandard stream does not inflate to {expected} bytes")
                })?,
                Some(other) => return Err(format!("KTX2 supercompression {other:?} is not read")),
            };
            if texels.len() != expected {
                return Err(format!(
                    "level {level} holds {} bytes, not the {expected} of {w} x {h} texels",
                    texels.len()
                ));
            }
            Ok(match channels {
                4 => texels,
                _ => texels.chunks_exact(3).flat_map(|t| [t[0], t[1], t[2], 255]).collect(),
            })
        })
        .collect()
}

/// Exactly `want` bytes out of a Zstandard stream, or `None`.
fn inflate(stream: &[u8], want: usize) -> Option<Vec<u8>> {
    use ruzstd::io::Read;
    let mut decoder = ruzstd::StreamingDecoder::new(stream).ok()?;
    let mut out = vec![0u8; want];
    decoder.read_exact(&mut out).ok()?;
    let mut extra = [0u8; 1];
    (decoder.read(&mut extra).ok()? == 0).then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plain KTX2 file: one RGBA8 level of `w` x `h` texels, no supercompression.
    fn plain_rgba8(w: u32, h: u32, texels: &[u8]) -> Vec<u8> {
        let mut header = ktx2::Header {
            format: Some(Format::R8G8B8A8_SRGB),
            type_size: 1,
            pixel_width: w,
            pixel_height: h,
            pixel_depth: 0,
            layer_count: 0,
            face_count: 1,
            level_count: 1,
            supercompression_scheme: None,
            // A data format descriptor holding only its own size, before the level.
            index: ktx2::Index {
                dfd_byte_offset: (ktx2::Header::LENGTH + ktx2::LevelIndex::LENGTH) as u32,
                dfd_byte_length: 4,
                kvd_byte_offset: 0,
                kvd_byte_length: 0,
                sgd_byte_offset: 0,
                sgd_byte_length: 0,
            },
        };
        let level_offset = ktx2::Header::LENGTH as u64 + ktx2::LevelIndex::LENGTH as u64;
        header.level_count = 1;
        let mut out = header.as_bytes().to_vec();
        out.extend(
            ktx2::LevelIndex {
                byte_offset: level_offset,
                byte_length: texels.len() as u64,
                uncompressed_byte_length: texels.len() as u64,
            }
            .as_bytes(),
        );
        out.extend(texels);
        out
    }

    #[test]
    fn a_plain_rgba8_file_decodes_and_a_truncated_one_is_an_error() {
        let texels: Vec<u8> = (0..2 * 2 * 4).map(|i| i as u8 * 10).collect();
        let file = plain_rgba8(2, 2, &texels);
        assert!(is_ktx2(&file));
        let levels = decode(&file).unwrap();
        assert_eq!((levels.width, levels.height), (2, 2));
        assert_eq!(levels.rgba8, vec![texels]);
        for cut in [8, 40, file.len() - 1] {
            assert!(decode(&file[..cut]).is_err(), "cut at {cut}");
        }
    }

    /// The encoder's files with bytes flipped, cut or repeated: every mutant decodes or is
    /// refused, none panics (a panic fails the test).
    #[test]
    fn mutated_basis_files_are_refused_or_decoded_never_a_panic() {
        let root = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/assets/TexturedKtx2"));
        let mut next = crate::gltf_import::tests::xorshift(0x2545_f491_4f6c_dd1d);
        let (mut decoded, mut refused) = (0, 0);
        for file in ["tiles-etc1s.ktx2", "tiles-uastc.ktx2"] {
            let original = std::fs::read(root.join(file)).unwrap();
            for _ in 0..5000 {
                let mut mutant = original.clone();
                match next() % 4 {
                    0 => mutant.truncate((next() as usize) % original.len()),
                    1 => {
                        let at = (next() as usize) % mutant.len();
                        let len = 1 + (next() as usize) % 64;
                        let copy: Vec<u8> = mutant[at..(at + len).min(mutant.len())].to_vec();
                        let to = (next() as usize) % mutant.len();
                        mutant.splice(to..to, copy);
                    }
                    _ => {
                        for _ in 0..1 + next() % 8 {
                            let at = (next() as usize) % mutant.len();
                            mutant[at] ^= 1 << (next() % 8);
                        }
                    }
                }
                match decode(&mutant) {
                    Ok(_) => decoded += 1,
                    Err(_) => refused += 1,
                }
            }
        }
        println!("{decoded} mutants decoded, {refused} refused");
        assert!(refused > 100 && decoded > 100, "{decoded} decoded, {refused} refused");
    }

    #[test]
    fn sizes_the_bytes_cannot_hold_are_refused_before_decoding() {
        let mut file = plain_rgba8(2, 2, &[0; 16]);
        // pixelWidth and pixelHeight, little-endian at bytes 20 and 24.
        file[20..24].copy_from_slice(&16000u32.to_le_bytes());
        file[24..28].copy_from_slice(&16000u32.to_le_bytes());
        let message = decode(&file).err().unwrap();
        assert!(message.contains("cannot hold"), "{message}");
        file[20..24].copy_from_slice(&40000u32.to_le_bytes());
        assert!(decode(&file).err().unwrap().contains("larger than"));
    }
}
