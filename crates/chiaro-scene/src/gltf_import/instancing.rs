//! EXT_mesh_gpu_instancing: a node's TRANSLATION, ROTATION and SCALE accessors in, one
//! transform per instance out (instance to node), each checked to be finite and
//! invertible. The loader places one `MeshInstance` per transform; the renderer draws the
//! consecutive instances of a primitive with one instanced draw.

use super::Loader;
use crate::error::SceneError;
use glam::{Mat4, Quat, Vec3};
use serde_json::Value;

pub(super) const EXTENSION: &str = "EXT_mesh_gpu_instancing";

impl Loader<'_> {
    /// Whether node `node` carries the extension.
    pub(super) fn is_instanced(&self, node: usize) -> bool {
        self.raw.pointer(&format!("/nodes/{node}/extensions/{EXTENSION}")).is_some()
    }

    /// Node `node`'s instance transforms, if it carries the extension.
    pub(super) fn instance_transforms(&self, node: usize) -> Result<Option<Vec<Mat4>>, SceneError> {
        let Some(extension) = self.raw.pointer(&format!("/nodes/{node}/extensions/{EXTENSION}")) else {
            return Ok(None);
        };
        let label = format!("nodes[{node}].extensions.{EXTENSION}");
        let attributes = extension
            .get("attributes")
            .and_then(Value::as_object)
            .ok_or_else(|| self.invalid(format!("{label} has no attributes object")))?;
        let accessor = |name: &str| -> Result<Option<usize>, SceneError> {
            let Some(value) = attributes.get(name) else { return Ok(None) };
            value
                .as_u64()
                .and_then(|a| usize::try_from(a).ok())
                .filter(|&a| a < self.root.accessors.len())
                .map(Some)
                .ok_or_else(|| self.invalid(format!("{label}.attributes.{name}: {value} is not an accessor")))
        };
        let what = |name: &str| format!("{name} of {label}");
        let translations =
            accessor("TRANSLATION")?.map(|a| self.read_floats::<3>(a, &what("TRANSLATION"))).transpose()?;
        let rotations = accessor("ROTATION")?.map(|a| self.read_floats::<4>(a, &what("ROTATION"))).transpose()?;
        let scales = accessor("SCALE")?.map(|a| self.read_floats::<3>(a, &what("SCALE"))).transpose()?;
        let counts =
            [translations.as_ref().map(Vec::len), rotations.as_ref().map(Vec::len), scales.as_ref().map(Vec::len)];
        let mut present = counts.iter().flatten();
        let Some(&count) = present.next() else {
            return Err(self.invalid(format!("{label} names no TRANSLATION, ROTATION or SCALE accessor")));
        };
        if present.any(|&c| c != count) {
            return Err(
                self.invalid(format!("{label}: TRANSLATION, ROTATION and SCALE have different counts ({counts:?})"))
            );
        }
        (0..count)
            .map(|i| {
                let translation = translations.as_ref().map_or(Vec3::ZERO, |t| Vec3::from_array(t[i]));
                let rotation = rotations.as_ref().map_or(Quat::IDENTITY, |r| Quat::from_array(r[i]));
                let scale = scales.as_ref().map_or(Vec3::ONE, |s| Vec3::from_array(s[i]));
                let m = Mat4::from_scale_rotation_translation(scale, rotation.normalize(), translation);
                if !m.is_finite() || m.determinant().abs() < 1e-20 || rotation.length() < 1e-6 {
                    return Err(self.invalid(format!(
                        "{label}: instance {i} has a transform that is not finite or cannot be inverted \
                         (translation {translation}, rotation {rotation}, scale {scale})"
                    )));
                }
                Ok(m)
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }
}
