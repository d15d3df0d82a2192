//! KHR_draco_mesh_compression: a primitive's extension object and the compressed bytes of
//! its buffer view in, the plain bytes of each accessor it names out, laid out as the
//! accessor says (its component type, normalisation and element type), so the accessor
//! reader treats them as it treats bytes read from a buffer view.
//!
//! The `draco-core` crate decodes the stream: a pure-Rust port of Google's decoder that
//! returns an error, never panics, on corrupt input, bounds every allocation by what the
//! stream can back, and takes ceilings on the decoded size (`DecodeLimits`), which are
//! set here to what the accessor reader accepts anyway.

use super::Loader;
use super::accessor::MAX_ACCESSOR_COUNT;
use crate::error::SceneError;
use draco_core::decode_limits::DecodeLimits;
use draco_core::decoder_buffer::DecoderBuffer;
use draco_core::draco_types::DataType;
use draco_core::geometry_attribute::PointAttribute;
use draco_core::geometry_indices::PointIndex;
use draco_core::mesh::Mesh;
use draco_core::mesh_decoder::MeshDecoder;
use gltf::json;
use json::accessor::ComponentType;
use json::validation::Checked;
use serde::Deserialize;
use serde_json::Value;
use std::collections::BTreeMap;

pub(super) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// The extension object on a primitive.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct DracoPrimitive {
    pub(super) buffer_view: usize,
    /// glTF attribute semantic to the Draco attribute's unique id.
    pub(super) attributes: BTreeMap<String, u32>,
}

/// The extension on primitive `primitive` of mesh `mesh`, if it has one: parsed, or a
/// message saying what is wrong.
pub(super) fn primitive_extension(
    raw: &Value,
    mesh: usize,
    primitive: usize,
) -> Option<Result<DracoPrimitive, String>> {
    let value = raw.pointer(&format!("/meshes/{mesh}/primitives/{primitive}/extensions/{EXTENSION}"))?;
    Some(DracoPrimitive::deserialize(value).map_err(|e| e.to_string()))
}

/// How an accessor lays out its elements: what the decoded values are written as.
#[derive(Clone, Copy, Debug)]
pub(super) struct Layout {
    pub(super) component: ComponentType,
    pub(super) normalized: bool,
    pub(super) dims: usize,
}

/// A decoded Draco triangle mesh.
pub(super) struct Decoded {
    mesh: Mesh,
}

/// Decodes a Draco stream holding a triangle mesh of at most `max_points` points.
pub(super) fn decode(stream: &[u8], max_points: usize) -> Result<Decoded, String> {
    let limits = DecodeLimits::default()
        .with_max_points(max_points as u64)
        .with_max_faces(max_points as u64)
        .with_max_decoded_bytes(max_points as u64 * 64);
    let mut buffer = DecoderBuffer::new(stream).with_limits(limits);
    let mut mesh = Mesh::new();
    MeshDecoder::new().decode(&mut buffer, &mut mesh).map_err(|e| format!("the Draco stream does not decode: {e}"))?;
    if mesh.num_faces() == 0 {
        return Err("the Draco stream holds no triangles (Draco point clouds are not read)".into());
    }
    if mesh.num_points() > max_points {
        return Err(format!("the Draco stream decodes {} points, more than Chiaro reads", mesh.num_points()));
    }
    Ok(Decoded { mesh })
}

impl Decoded {
    pub(super) fn point_count(&self) -> usize {
        self.mesh.num_points()
    }

    /// The triangles' corners as little-endian `u32`s, checked to name decoded points.
    pub(super) fn index_bytes(&self) -> Result<Vec<u8>, String> {
        let points = self.mesh.num_points() as u32;
        let mut bytes = Vec::with_capacity(self.mesh.num_faces() * 12);
        for face in self.mesh.faces() {
            for PointIndex(corner) in face {
                if *corner >= points {
                    return Err(format!("a triangle names point {corner} of {points}"));
                }
                bytes.extend_from_slice(&corner.to_le_bytes());
            }
        }
        Ok(bytes)
    }

    /// The values of the attribute with `unique_id`, one per decoded point, written as
    /// `layout` says: integers converted to floats (normalised where the Draco attribute
    /// is) and floats to normalised integers where the accessor asks for them.
    pub(super) fn attribute_bytes(&self, unique_id: u32, layout: Layout) -> Result<Vec<u8>, String> {
        let attribute = self
            .mesh
            .attribute_by_unique_id(unique_id)
            .ok_or_else(|| format!("the Draco stream has no attribute with id {unique_id}"))?;
        let source = Source::of(attribute)?;
        if source.dims < layout.dims {
            return Err(format!(
                "Draco attribute {unique_id} has {} components; its accessor reads {}",
                source.dims, layout.dims
            ));
        }
        let points = self.mesh.num_points();
        let mut bytes = Vec::with_capacity(points * layout.dims * layout.component.size());
        for point in 0..points {
            let value = attribute.mapped_index(PointIndex(point as u32)).0 as usize;
            for component in 0..layout.dims {
                let scalar = source
                    .scalar(value, component)
                    .ok_or_else(|| format!("Draco attribute {unique_id}: point {point} has no value"))?;
                write_scalar(scalar, layout, &mut bytes);
            }
        }
        Ok(bytes)
    }
}

/// A decoded attribute's values, read with every offset checked.
struct Source<'a> {
    data: &'a [u8],
    data_type: DataType,
    normalized: bool,
    dims: usize,
    stride: usize,
    values: usize,
}

/// A decoded scalar: an integer (with whether it is normalised) or a float.
#[derive(Clone, Copy)]
enum Scalar {
    Float(f64),
    Integer { value: i64, max: f64, normalized: bool },
}

impl<'a> Source<'a> {
    fn of(attribute: &'a PointAttribute) -> Result<Source<'a>, String> {
        let data_type = attribute.data_type();
        let width = data_type.byte_length();
        let dims = usize::from(attribute.num_components());
        let stride = usize::try_from(attribute.byte_stride()).unwrap_or(0);
        if width == 0 || matches!(data_type, DataType::Bool) || stride < width * dims {
            return Err(format!(
                "a Draco attribute has data type {data_type:?} and stride {stride}, which glTF has no use for"
            ));
        }
        Ok(Source {
            data: attribute.buffer().data(),
            data_type,
            normalized: attribute.normalized(),
            dims,
            stride,
            values: attribute.size(),
        })
    }

    fn scalar(&self, value: usize, component: usize) -> Option<Scalar> {
        if value >= self.values {
            return None;
        }
        let width = self.data_type.byte_length();
        let start = value.checked_mul(self.stride)?.checked_add(component * width)?;
        let b = self.data.get(start..start + width)?;
        let integer = |value: i64, max: f64| Scalar::Integer { value, max, normalized: self.normalized };
        Some(match self.data_type {
            DataType::Float32 => Scalar::Float(f64::from(f32::from_le_bytes(b.try_into().ok()?))),
            DataType::Float64 => Scalar::Float(f64::from_le_bytes(b.try_into().ok()?)),
            DataType::Int8 => integer(i64::from(b[0] as i8), 127.0),
            DataType::Uint8 => integer(i64::from(b[0]), 255.0),
            DataType::Int16 => integer(i64::from(i16::from_le_bytes(b.try_into().ok()?)), 32767.0),
            DataType::Uint16 => integer(i64::from(u16::from_le_bytes(b.try_into().ok()?)), 65535.0),
            DataType::Int32 => integer(i64::from(i32::from_le_bytes(b.try_into().ok()?)), f64::from(i32::MAX)),
            DataType::Uint32 => integer(i64::from(u32::from_le_bytes(b.try_into().ok()?)), f64::from(u32::MAX)),
            DataType::Int64 | DataType::Uint64 => integer(i64::from_le_bytes(b.try_into().ok()?), i64::MAX as f64),
            DataType::Invalid | DataType::Bool => return None,
        })
    }
}

impl Scalar {
    /// The value as a float: a normalised integer in [-1, 1], else as it is.
    fn as_f64(self) -> f64 {
        match self {
            Scalar::Float(v) => v,
            Scalar::Integer { value, max, normalized: true } => (value as f64 / max).max(-1.0),
            Scalar::Integer { value, .. } => value as f64,
        }
    }
}

/// Appends `scalar` as one component of `layout`. An integer into an integer keeps its
/// value; a float into a normalised integer scales by the type's largest value, as the
/// glTF specification's normalisation rule says, rounding to nearest.
fn write_scalar(scalar: Scalar, layout: Layout, out: &mut Vec<u8>) {
    let integer = |max: f64| -> f64 {
        match (scalar, layout.normalized) {
            (Scalar::Integer { value, normalized: false, .. }, _) => value as f64,
            (_, true) => (scalar.as_f64() * max).round(),
            (_, false) => scalar.as_f64().round(),
        }
    };
    match layout.component {
        ComponentType::F32 => out.extend_from_slice(&(scalar.as_f64() as f32).to_le_bytes()),
        ComponentType::U8 => out.push(integer(255.0).clamp(0.0, 255.0) as u8),
        ComponentType::I8 => out.push((integer(127.0).clamp(-128.0, 127.0) as i8) as u8),
        ComponentType::U16 => out.extend_from_slice(&(integer(65535.0).clamp(0.0, 65535.0) as u16).to_le_bytes()),
        ComponentType::I16 => {
            out.extend_from_slice(&(integer(32767.0).clamp(-32768.0, 32767.0) as i16).to_le_bytes());
        }
        ComponentType::U32 => {
            out.extend_from_slice(&(integer(f64::from(u32::MAX)).clamp(0.0, f64::from(u32::MAX)) as u32).to_le_bytes());
        }
    }
}

/// An accessor's values decoded from a Draco stream, laid out as the accessor says
/// (indices widened to `u32`): what the accessor reader reads instead of a buffer view.
pub(super) struct Decompressed {
    pub(super) component: ComponentType,
    pub(super) bytes: Vec<u8>,
}

impl Loader<'_> {
    /// Decodes the Draco stream of primitive `p` of mesh `mesh`, if it has one, into the
    /// accessors it names (`label` names the primitive in errors).
    pub(super) fn decode_draco(&mut self, mesh: usize, p: usize, label: &str) -> Result<(), SceneError> {
        let Some(extension) = primitive_extension(self.raw, mesh, p) else { return Ok(()) };
        let path = format!("{label}: {EXTENSION}");
        let fail = |message: String| self.invalid(format!("{path}: {message}"));
        let extension = extension.map_err(&fail)?;
        let primitive = &self.root.meshes[mesh].primitives[p];
        if primitive.mode != Checked::Valid(json::mesh::Mode::Triangles) {
            return Err(fail("a Draco-compressed primitive must be TRIANGLES".into()));
        }
        let Some(indices) = primitive.indices else {
            return Err(fail("a Draco-compressed primitive must name an indices accessor".into()));
        };
        if extension.buffer_view >= self.root.buffer_views.len() {
            return Err(fail(format!("bufferView {} is out of range", extension.buffer_view)));
        }
        let (stream, _) = self.view_bytes(extension.buffer_view)?;
        let decoded = decode(stream, MAX_ACCESSOR_COUNT).map_err(&fail)?;
        let mut accessors = vec![(
            indices.value(),
            Decompressed { component: ComponentType::U32, bytes: decoded.index_bytes().map_err(&fail)? },
        )];
        for (semantic, &id) in &extension.attributes {
            let accessor = self
                .raw
                .pointer(&format!("/meshes/{mesh}/primitives/{p}/attributes/{semantic}"))
                .and_then(Value::as_u64)
                .and_then(|a| usize::try_from(a).ok())
                .filter(|&a| a < self.root.accessors.len())
                .ok_or_else(|| fail(format!("{semantic} is not an attribute of the primitive")))?;
            let json_accessor = &self.root.accessors[accessor];
            let (Checked::Valid(component), Checked::Valid(ty)) = (json_accessor.component_type, json_accessor.type_)
            else {
                return Err(fail(format!("accessors[{accessor}] ({semantic}) has an invalid type")));
            };
            let dims = ty.multiplicity();
            if dims > 4 {
                return Err(fail(format!("accessors[{accessor}] ({semantic}) is a matrix, which Draco does not hold")));
            }
            let layout = Layout { component: component.0, normalized: json_accessor.normalized, dims };
            let bytes = decoded.attribute_bytes(id, layout).map_err(|e| fail(format!("{semantic}: {e}")))?;
            accessors.push((accessor, Decompressed { component: component.0, bytes }));
        }
        tracing::trace!(label, points = decoded.point_count(), "decoded Draco primitive");
        self.decompressed.extend(accessors);
        self.decompressed_primitives += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written(scalar: Scalar, component: ComponentType, normalized: bool) -> Vec<u8> {
        let mut out = Vec::new();
        write_scalar(scalar, Layout { component, normalized, dims: 1 }, &mut out);
        out
    }

    #[test]
    fn values_convert_to_the_accessors_layout() {
        let byte = |value| Scalar::Integer { value, max: 255.0, normalized: true };
        // A normalised byte colour read as float, and kept as a byte.
        assert_eq!(written(byte(255), ComponentType::F32, false), 1.0f32.to_le_bytes());
        assert_eq!(written(byte(51), ComponentType::U8, true), [51]);
        // A float written into a normalised short, and a signed one into a signed byte.
        assert_eq!(written(Scalar::Float(0.5), ComponentType::U16, true), 32768u16.to_le_bytes());
        assert_eq!(written(Scalar::Float(-1.0), ComponentType::I8, true), [(-127i8) as u8]);
        // Plain integers keep their values whatever the accessor's normalisation.
        let plain = Scalar::Integer { value: 300, max: 65535.0, normalized: false };
        assert_eq!(written(plain, ComponentType::U16, false), 300u16.to_le_bytes());
        assert_eq!(written(plain, ComponentType::F32, false), 300.0f32.to_le_bytes());
    }

    #[test]
    fn corrupt_streams_are_errors() {
        assert!(decode(&[], 1000).is_err());
        assert!(decode(b"DRACO\x02\x02\x01\x01\x00\x00\xff\xff\xff\xff", 1000).is_err());
        let garbage: Vec<u8> = (0..4096u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8).collect();
        assert!(decode(&garbage, 1000).is_err());
    }
}
