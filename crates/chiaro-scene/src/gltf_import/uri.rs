//! A glTF `uri` string in, its bytes out: `data:` URIs decoded (base64 or
//! percent-encoded), `file:` URIs and relative paths read from disk beside the glTF file.
//! Failures are messages that the caller prefixes with the buffer or image they belong to.

use base64::Engine as _;
use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
use std::path::{Path, PathBuf};

pub(super) struct UriData {
    pub(super) bytes: Vec<u8>,
    /// The media type of a `data:` URI.
    pub(super) mime: Option<String>,
    /// The file it was read from, for anything but a `data:` URI.
    pub(super) file: Option<PathBuf>,
}

/// Files given in memory instead of read from disk, by the path a document's relative URI
/// resolves to ([`resolve`]): for a caller with no filesystem (the browser build), which
/// fetched them itself.
pub type GivenFiles = std::collections::HashMap<PathBuf, Vec<u8>>;

/// Reads a `data:` URI, a `file:` URI or a path relative to `base_dir`, the glTF file's
/// folder; from `given` instead of the disk when the caller gave the files.
pub(super) fn read_uri(base_dir: &Path, given: Option<&GivenFiles>, uri: &str) -> Result<UriData, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, payload) = rest.split_once(',').ok_or("data URI has no comma before its payload")?;
        let (mime, base64) = match header.strip_suffix(";base64") {
            Some(mime) => (mime, true),
            None => (header, false),
        };
        let bytes = if base64 { decode_base64(payload)? } else { percent_decode(payload)? };
        let mime = mime.split(';').next().unwrap_or("");
        return Ok(UriData { bytes, mime: (!mime.is_empty()).then(|| mime.to_ascii_lowercase()), file: None });
    }
    let path = resolve(base_dir, uri)?;
    let bytes = match given {
        Some(files) => files.get(&path).cloned().ok_or_else(|| {
            format!("cannot read {}: it is not among the files given with the document", path.display())
        })?,
        None => crate::files::read_regular_file(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?,
    };
    Ok(UriData { bytes, mime: None, file: Some(path) })
}

/// The file a URI other than `data:` names: a `file:` URI's path, or a path relative to
/// `base_dir`; other schemes are errors.
pub(super) fn resolve(base_dir: &Path, uri: &str) -> Result<PathBuf, String> {
    match uri.find(':') {
        Some(colon) if !uri[..colon].contains('/') => {
            let scheme = &uri[..colon];
            if !scheme.eq_ignore_ascii_case("file") {
                return Err(format!("URI scheme {scheme}: is not supported"));
            }
            let rest = &uri[colon + 1..];
            let rest = rest.strip_prefix("//").unwrap_or(rest);
            Ok(PathBuf::from(bytes_to_path(percent_decode(rest)?)?))
        }
        _ => Ok(base_dir.join(bytes_to_path(percent_decode(uri)?)?)),
    }
}

/// Standard or URL-safe base64 (RFC 4648 §4 and §5), as exporters write it in data URIs:
/// padding optional, whitespace skipped, anything after the first `=` ignored, and stray
/// bits in the last symbol dropped. The URL-safe symbols are mapped onto the standard ones
/// so that a payload mixing the two still decodes. A symbol count that leaves a lone
/// 6-bit symbol at the end cannot hold a byte and is an error (a truncated payload).
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    const FORGIVING: GeneralPurpose = GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        GeneralPurposeConfig::new()
            .with_decode_padding_mode(DecodePaddingMode::Indifferent)
            .with_decode_allow_trailing_bits(true),
    );
    let is_space = |c: &u8| matches!(c, b' ' | b'\t' | b'\r' | b'\n');
    let payload = text.split_once('=').map_or(text, |(payload, _)| payload);
    let symbols: Vec<u8> = payload
        .bytes()
        .filter(|c| !is_space(c))
        .map(|c| match c {
            b'-' => b'+',
            b'_' => b'/',
            c => c,
        })
        .collect();
    FORGIVING.decode(&symbols).map_err(|e| match e {
        base64::DecodeError::InvalidByte(offset, _) => {
            // `offset` counts symbols; the message counts characters of the payload.
            let at = text.bytes().enumerate().filter(|(_, c)| !is_space(c)).nth(offset).map_or(offset, |(i, _)| i);
            format!("invalid base64 character at {at}")
        }
        other => format!("invalid base64: {other}"),
    })
}

/// `%XX` escapes decoded (RFC 3986 §2.1). The `percent-encoding` crate passes a malformed
/// escape through unchanged; here it is an error, since it means a broken URI.
fn percent_decode(text: &str) -> Result<Vec<u8>, String> {
    let bytes = text.as_bytes();
    let well_formed = bytes
        .iter()
        .enumerate()
        .filter(|&(_, &c)| c == b'%')
        .all(|(i, _)| bytes.get(i + 1..i + 3).is_some_and(|hex| hex.iter().all(u8::is_ascii_hexdigit)));
    if !well_formed {
        return Err(format!("invalid percent escape in URI {text}"));
    }
    Ok(percent_encoding::percent_decode(bytes).collect())
}

fn bytes_to_path(bytes: Vec<u8>) -> Result<String, String> {
    String::from_utf8(bytes).map_err(|_| "URI is not UTF-8 after percent-decoding".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_accepts_both_alphabets_with_or_without_padding() {
        // 0xFB 0xFF encodes as "+/8=" (standard) or "-_8" (URL-safe, unpadded).
        for text in ["+/8=", "+/8", "-_8=", "-_8", "+_8", "+/8=ignored"] {
            assert_eq!(decode_base64(text).unwrap(), vec![0xFB, 0xFF], "{text}");
        }
        assert_eq!(decode_base64("").unwrap(), Vec::<u8>::new());
        assert_eq!(decode_base64("SGVs\r\nbG8 ").unwrap(), b"Hello");
        // "QR" carries 12 bits for one byte; the 4 stray bits are dropped.
        assert_eq!(decode_base64("QR==").unwrap(), b"A");
    }

    #[test]
    fn base64_errors_name_the_character_position() {
        assert_eq!(decode_base64("SGVs*G8=").unwrap_err(), "invalid base64 character at 4");
        // Positions count the payload's characters, whitespace included.
        assert_eq!(decode_base64("SG\nVs*G8=").unwrap_err(), "invalid base64 character at 5");
        assert!(decode_base64("SGVsb").unwrap_err().starts_with("invalid base64"));
    }

    #[test]
    fn percent_escapes_decode_and_malformed_ones_are_errors() {
        assert_eq!(percent_decode("a%20b%2Fc%e2%82%ac").unwrap(), "a b/c€".as_bytes());
        assert_eq!(percent_decode("plain").unwrap(), b"plain");
        for text in ["50%", "%2", "%zz", "%+1", "a%%41"] {
            assert_eq!(percent_decode(text).unwrap_err(), format!("invalid percent escape in URI {text}"));
        }
        assert!(bytes_to_path(percent_decode("%ff").unwrap()).is_err());
    }

    #[test]
    fn data_uris_keep_their_media_type_and_paths_resolve_beside_the_file() {
        let data = read_uri(Path::new("."), None, "data:IMAGE/PNG;charset=x;base64,AAE=").unwrap();
        assert_eq!(data.bytes, vec![0, 1]);
        assert_eq!(data.mime.as_deref(), Some("image/png"));
        let data = read_uri(Path::new("."), None, "data:,a%20b").unwrap();
        assert_eq!(data.bytes, b"a b");
        assert_eq!(data.mime, None);
        assert_eq!(
            read_uri(Path::new("."), None, "https://example.com/a.bin").err().unwrap(),
            "URI scheme https: is not supported"
        );
        let missing = read_uri(Path::new("/no-such-dir"), None, "a%20b.bin").err().unwrap();
        assert!(missing.starts_with("cannot read /no-such-dir/a b.bin"), "{missing}");
    }
}
