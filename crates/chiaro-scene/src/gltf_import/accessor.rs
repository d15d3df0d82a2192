//! Buffers in (the GLB BIN chunk or URIs), typed elements out: buffer views and accessors
//! are read with every offset, stride and count checked before a byte is touched, sparse
//! substitution applied, integer components converted to floats as KHR_mesh_quantization
//! and glTF's normalized-integer rules say, and indices widened to `u32`.

use super::{Loader, json_label, meshopt, uri};
use crate::error::SceneError;
use gltf::json;
use json::accessor::ComponentType;
use json::validation::Checked;
use std::borrow::Cow;

/// Accessors with more elements than this are rejected before anything is allocated:
/// 67 million vertices in one primitive is far past what a real-time scene draws.
pub(super) const MAX_ACCESSOR_COUNT: usize = 1 << 26;

impl<'a> Loader<'a> {
    /// Buffer `index`'s bytes, read on first use: the GLB's BIN chunk or its URI, checked
    /// to hold the length the file declares, and cut to that length: a buffer view that
    /// runs past the declared length is broken even where the data behind it goes on (a
    /// GLB's chunk padding, a longer .bin).
    fn buffer(&self, index: usize) -> Result<&[u8], SceneError> {
        let declared = self.root.buffers[index].byte_length.0;
        if let Some(bytes) = self.buffers[index].get() {
            return Ok(&bytes[..declared as usize]);
        }
        let buffer = &self.root.buffers[index];
        let label = json_label("buffers", index, buffer.uri.as_deref(), None);
        let data: Cow<'a, [u8]> = match &buffer.uri {
            None if meshopt::is_fallback(self.raw, index) => {
                return Err(self.invalid(format!(
                    "{label}: an EXT_meshopt_compression fallback buffer has no data, yet a buffer view that is \
                     not compressed reads it"
                )));
            }
            None => Cow::Borrowed(
                self.bin.ok_or_else(|| self.invalid(format!("{label} has no uri and the file has no binary chunk")))?,
            ),
            Some(uri) => {
                let data = uri::read_uri(self.base_dir, self.given_files, uri)
                    .map_err(|e| self.invalid(format!("{label}: {e}")))?;
                self.inputs.borrow_mut().extend(data.file);
                Cow::Owned(data.bytes)
            }
        };
        if (data.len() as u64) < declared {
            return Err(self.invalid(format!("{label} is {} bytes but the file says {declared}", data.len())));
        }
        Ok(&self.buffers[index].get_or_init(|| data)[..declared as usize])
    }

    /// The bytes of a buffer view and its stride, checked to lie inside its buffer; an
    /// EXT_meshopt_compression view is decoded from its compressed bytes first.
    pub(super) fn view_bytes(&self, view_index: usize) -> Result<(&[u8], Option<usize>), SceneError> {
        let view = &self.root.buffer_views[view_index];
        let stride = view.byte_stride.map(|s| s.0);
        if let Some(compressed) = meshopt::view_extension(self.raw, view_index) {
            let path = format!("bufferViews[{view_index}].extensions.EXT_meshopt_compression");
            let compressed = compressed.map_err(|e| self.invalid(format!("{path}: {e}")))?;
            if let Some(bytes) = self.decoded_views[view_index].get() {
                return Ok((bytes, stride));
            }
            let source = self.byte_range(compressed.buffer, compressed.byte_offset, compressed.byte_length, &path)?;
            let decoded = meshopt::decode(&compressed, source, view.byte_length.0)
                .map_err(|e| self.invalid(format!("{path}: {e}")))?;
            return Ok((self.decoded_views[view_index].get_or_init(|| decoded), stride));
        }
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let bytes =
            self.byte_range(view.buffer.value(), offset, view.byte_length.0, &format!("bufferViews[{view_index}]"))?;
        Ok((bytes, stride))
    }

    /// Bytes `offset..offset + length` of buffer `buffer`, checked to lie inside it.
    fn byte_range(&self, buffer_index: usize, offset: u64, length: u64, path: &str) -> Result<&[u8], SceneError> {
        let buffer = self
            .root
            .buffers
            .get(buffer_index)
            .map(|_| self.buffer(buffer_index))
            .ok_or_else(|| self.invalid(format!("{path}.buffer: buffer {buffer_index} is out of range")))??;
        match offset.checked_add(length) {
            Some(end) if end <= buffer.len() as u64 => Ok(&buffer[offset as usize..end as usize]),
            _ => Err(self.invalid(format!(
                "{path} (bytes {offset}..{}) runs past the end of buffers[{buffer_index}] ({} bytes)",
                offset.saturating_add(length),
                buffer.len()
            ))),
        }
    }

    /// Gathers an accessor's elements into tightly packed bytes, sparse substitution
    /// applied. Every offset is checked against its buffer view before any byte is read.
    fn read_packed(&self, index: usize, dims: usize, what: &str) -> Result<Packed, SceneError> {
        use json::accessor::Type;
        debug_assert!((1..=4).contains(&dims) || dims == 16);
        let accessor = &self.root.accessors[index];
        let label = format!("accessors[{index}] ({what})");
        let sparse_label = format!("accessors[{index}].sparse.indices ({what})");
        let (Checked::Valid(component), Checked::Valid(ty)) = (accessor.component_type, accessor.type_) else {
            return Err(self.invalid(format!("{label} has an invalid type")));
        };
        let component = component.0;
        // 16 components are a MAT4 (inverse bind matrices); its float columns need no padding.
        let expected =
            if dims == 16 { Type::Mat4 } else { [Type::Scalar, Type::Vec2, Type::Vec3, Type::Vec4][dims - 1] };
        if ty != expected {
            return Err(self.invalid(format!("{label} is {}, expected {}", type_name(ty), type_name(expected))));
        }
        let count = usize::try_from(accessor.count.0).ok().filter(|&c| c <= MAX_ACCESSOR_COUNT).ok_or_else(|| {
            self.invalid(format!(
                "{label} has {} elements, more than Chiaro reads ({MAX_ACCESSOR_COUNT})",
                accessor.count.0
            ))
        })?;
        if let Some(decompressed) = self.decompressed.get(&index) {
            // KHR_draco_mesh_compression: the decoded values, as many as the stream holds.
            let bytes = decompressed.bytes.clone();
            return Ok(Packed { component: decompressed.component, normalized: accessor.normalized, dims, bytes });
        }
        let element_size = dims * component.size();
        let mut bytes = Vec::new();

        if let Some(view_index) = accessor.buffer_view {
            let (view, stride) = self.view_bytes(view_index.value())?;
            let stride = stride.unwrap_or(element_size);
            let offset = accessor.byte_offset.map_or(0, |o| o.0);
            let end = if count == 0 {
                Some(offset)
            } else {
                ((count - 1) as u64)
                    .checked_mul(stride as u64)
                    .and_then(|x| x.checked_add(offset))
                    .and_then(|x| x.checked_add(element_size as u64))
            };
            match end {
                Some(end) if end <= view.len() as u64 => {}
                _ => {
                    return Err(self.invalid(format!(
                        "{label} reads {count} elements of {element_size} bytes every {stride} \
                         from byte {offset}, past the end of bufferViews[{}] ({} bytes)",
                        view_index.value(),
                        view.len()
                    )));
                }
            }
            let offset = offset as usize;
            bytes.reserve_exact(count * element_size);
            for i in 0..count {
                let start = offset + i * stride;
                bytes.extend_from_slice(&view[start..start + element_size]);
            }
        } else {
            bytes.resize(count * element_size, 0);
        }

        if let Some(sparse) = &accessor.sparse {
            self.apply_sparse(sparse, (count, element_size), (&label, &sparse_label), &mut bytes)?;
        }

        Ok(Packed { component, normalized: accessor.normalized, dims, bytes })
    }

    /// Substitutes a sparse accessor's values into its packed `bytes`, checking that the
    /// indices are in range and strictly increase.
    fn apply_sparse(
        &self,
        sparse: &json::accessor::sparse::Sparse,
        (count, element_size): (usize, usize),
        (label, sparse_label): (&str, &str),
        bytes: &mut [u8],
    ) -> Result<(), SceneError> {
        let n = sparse.count.0;
        if n > count as u64 {
            return Err(self.invalid(format!("{label} replaces {n} sparse elements but has only {count}")));
        }
        let n = n as usize;
        let Checked::Valid(index_type) = sparse.indices.component_type else {
            return Err(self.invalid(format!("{label} has invalid sparse indices")));
        };
        let index_type = index_type.0;
        let indices = self.sparse_slice(
            sparse.indices.buffer_view.value(),
            sparse.indices.byte_offset.0,
            n * index_type.size(),
            label,
        )?;
        let values =
            self.sparse_slice(sparse.values.buffer_view.value(), sparse.values.byte_offset.0, n * element_size, label)?;
        let mut previous = None;
        for k in 0..n {
            let target = read_index(index_type, &indices[k * index_type.size()..])
                .filter(|&t| (t as usize) < count)
                .ok_or_else(|| self.invalid(format!("{sparse_label}: an index is out of range")))?
                as usize;
            // glTF 2.0 §3.6.2.3: sparse indices strictly increase.
            if previous.is_some_and(|p| p >= target) {
                return Err(self.invalid(format!(
                    "{sparse_label}: {target} follows {}; sparse indices must strictly increase",
                    previous.unwrap_or_default()
                )));
            }
            previous = Some(target);
            bytes[target * element_size..(target + 1) * element_size]
                .copy_from_slice(&values[k * element_size..(k + 1) * element_size]);
        }
        Ok(())
    }

    fn sparse_slice(&self, view_index: usize, offset: u64, length: usize, label: &str) -> Result<&[u8], SceneError> {
        let (view, _) = self.view_bytes(view_index)?;
        offset
            .checked_add(length as u64)
            .filter(|&end| end <= view.len() as u64)
            .map(|end| &view[offset as usize..end as usize])
            .ok_or_else(|| self.invalid(format!("{label}: sparse data runs past the end of bufferViews[{view_index}]")))
    }

    /// Float elements of `N` components, integer formats converted as
    /// KHR_mesh_quantization and glTF's normalized-integer rules say.
    pub(super) fn read_floats<const N: usize>(&self, index: usize, what: &str) -> Result<Vec<[f32; N]>, SceneError> {
        let packed = self.read_packed(index, N, what)?;
        let size = packed.component.size();
        Ok(packed
            .bytes
            .chunks_exact(packed.dims * size)
            .map(|element| {
                std::array::from_fn(|c| component_to_f32(packed.component, packed.normalized, &element[c * size..]))
            })
            .collect())
    }

    /// Index accessor `index`'s elements widened to `u32`, with its component type's
    /// largest value: the primitive restart value, which glTF 2.0 §3.7.2.1 forbids in
    /// indices.
    pub(super) fn read_indices(&self, index: usize, what: &str) -> Result<(Vec<u32>, u32), SceneError> {
        let packed = self.read_packed(index, 1, what)?;
        if !matches!(packed.component, ComponentType::U8 | ComponentType::U16 | ComponentType::U32) {
            return Err(self.invalid(format!(
                "accessor {index} ({what}) has component type {:?}; indices must be unsigned \
                 integers",
                packed.component
            )));
        }
        let size = packed.component.size();
        let restart = match packed.component {
            ComponentType::U8 => u32::from(u8::MAX),
            ComponentType::U16 => u32::from(u16::MAX),
            _ => u32::MAX,
        };
        Ok((packed.bytes.chunks_exact(size).filter_map(|b| read_index(packed.component, b)).collect(), restart))
    }

    /// Checks that accessor `index` (`what` says whose) lies inside its buffer view and the
    /// view inside its buffer, without converting its elements: for the accessors of a
    /// drawn primitive that Chiaro reads past (vertex colours, further UV sets, JOINTS
    /// without WEIGHTS, custom attributes), so that they are as sound as the rest.
    pub(super) fn check_accessor(&self, index: usize, what: &str) -> Result<(), SceneError> {
        let accessor = &self.root.accessors[index];
        let (Checked::Valid(_), Checked::Valid(ty)) = (accessor.component_type, accessor.type_) else {
            return Err(self.invalid(format!("accessors[{index}] ({what}) has an invalid type")));
        };
        let dims = match ty.multiplicity() {
            16 => 16,
            d if d <= 4 => d,
            // MAT2 and MAT3 are read by nothing Chiaro draws: their views are checked as
            // every view is, by reading them whole.
            _ => {
                return accessor.buffer_view.map_or(Ok(()), |view| self.view_bytes(view.value()).map(|_| ()));
            }
        };
        self.read_packed(index, dims, what).map(|_| ())
    }
}

struct Packed {
    component: ComponentType,
    normalized: bool,
    dims: usize,
    bytes: Vec<u8>,
}

/// One component as a float. Normalized integers map to [0, 1] or [-1, 1] (glTF 2.0
/// §3.11: signed values use `max(c / 127, -1)`, so -128 and -127 both give -1).
fn component_to_f32(component: ComponentType, normalized: bool, b: &[u8]) -> f32 {
    match component {
        ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        ComponentType::U8 => {
            let v = f32::from(b[0]);
            if normalized { v / 255.0 } else { v }
        }
        ComponentType::I8 => {
            let v = f32::from(b[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        ComponentType::U16 => {
            let v = f32::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        ComponentType::I16 => {
            let v = f32::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized { (v / 32767.0).max(-1.0) } else { v }
        }
        ComponentType::U32 => {
            let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            if normalized { (f64::from(v) / f64::from(u32::MAX)) as f32 } else { v as f32 }
        }
    }
}

fn type_name(ty: json::accessor::Type) -> &'static str {
    use json::accessor::Type;
    match ty {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn read_index(component: ComponentType, b: &[u8]) -> Option<u32> {
    match component {
        ComponentType::U8 => b.first().map(|&v| u32::from(v)),
        ComponentType::U16 => b.get(..2).map(|b| u32::from(u16::from_le_bytes([b[0], b[1]]))),
        ComponentType::U32 => b.get(..4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}
