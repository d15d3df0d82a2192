//! A node's [`Placement`] in, the KHR_lights_punctual [`Light`] and perspective or
//! orthographic [`Camera`] it carries out, in world space. Colours, intensities, ranges,
//! cone angles and projection parameters are checked.

use super::Loader;
use super::nodes::Placement;
use super::object_label;
use crate::error::SceneError;
use crate::types::{Camera, Cookie, Light, LightKind};
use chiaro_math::camera::Projection;
use chiaro_math::light::MAX_LIGHT_INTENSITY;
use chiaro_math::rigid::{looking_along, rigid_part};
use glam::{Vec2, Vec3};
use gltf::json;
use json::validation::Checked;

impl Loader<'_> {
    pub(super) fn light(&self, placement: &Placement) -> Result<Option<Light>, SceneError> {
        use json::extensions::scene::khr_lights_punctual::Type;

        let node = &self.root.nodes[placement.node];
        let Some(light_index) =
            node.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map(|l| l.light.value())
        else {
            return Ok(None);
        };
        if self.skipped_lights.get(light_index) == Some(&true) {
            return Ok(None);
        }
        let Some(light) = self
            .root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|l| l.lights.get(light_index))
        else {
            return Err(self.invalid(format!("node {}: light {light_index} is out of range", placement.node)));
        };
        let label = object_label("light", light_index, None, light.name.as_deref());
        let color = Vec3::from_array(light.color);
        self.check_light_strength(&label, color, light.intensity, light.range)?;
        let kind = match (light.type_, &light.spot) {
            (Checked::Valid(Type::Directional), _) => LightKind::Directional,
            (Checked::Valid(Type::Point), _) => LightKind::Point,
            (Checked::Valid(Type::Spot), Some(spot)) => {
                let (inner, outer) = spot_cone(spot.inner_cone_angle, spot.outer_cone_angle).ok_or_else(|| {
                    self.invalid(format!(
                        "{label}: spot cone angles must satisfy 0 <= inner ({}) < outer \
                             ({}) <= pi/2",
                        spot.inner_cone_angle, spot.outer_cone_angle
                    ))
                })?;
                LightKind::Spot { inner_cone_rad: inner, outer_cone_rad: outer }
            }
            _ => return Err(self.invalid(format!("{label}: invalid light type"))),
        };
        let shadow =
            super::extras::light_shadow(light.extras.as_deref()).map_err(|e| self.invalid(format!("{label}: {e}")))?;
        // An emitter larger than the light's reach lights nothing the way its shadows say.
        if let Some(range) = light.range.filter(|&r| shadow.light_radius > r && kind != LightKind::Directional) {
            return Err(self.invalid(format!(
                "{label}: extras.lightRadius: {} m is larger than the light's range ({range} m)",
                shadow.light_radius
            )));
        }
        let mode =
            super::extras::light_mode(light.extras.as_deref()).map_err(|e| self.invalid(format!("{label}: {e}")))?;
        let cookie = self.light_cookie(&label, kind, light.extras.as_deref())?;
        let world_from_light = light_frame(placement.world_from_local);
        Ok(Some(Light {
            name: light.name.clone().or_else(|| node.name.clone()).unwrap_or_else(|| format!("light {light_index}")),
            node: placement.node,
            kind,
            color,
            intensity: light.intensity,
            range: light.range,
            world_from_light,
            shadow,
            cookie,
            mode,
        }))
    }

    /// Refuses colours, intensities and ranges Chiaro cannot shade.
    pub(super) fn check_light_strength(
        &self,
        label: &str,
        color: Vec3,
        intensity: f32,
        range_m: Option<f32>,
    ) -> Result<(), SceneError> {
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(self.invalid(format!("{label}: colour {color} is not a linear RGB colour")));
        }
        if !intensity.is_finite() || intensity < 0.0 {
            return Err(self.invalid(format!("{label}: intensity {} is negative or not finite", intensity)));
        }
        let peak = intensity * color.max_element();
        if peak > MAX_LIGHT_INTENSITY {
            return Err(self.invalid(format!(
                "{label}: intensity {:e} times colour {color} is beyond {MAX_LIGHT_INTENSITY:e}, the brightest \
                 light Chiaro shades",
                intensity
            )));
        }
        if let Some(range) = range_m
            && !(range.is_finite() && range > 0.0)
        {
            return Err(self.invalid(format!("{label}: range {range} is not positive")));
        }
        Ok(())
    }

    /// The light's cookie from its extras, checked against the file's images and the light's kind.
    fn light_cookie(
        &self,
        label: &str,
        kind: LightKind,
        extras: Option<&json::extras::RawValue>,
    ) -> Result<Option<Cookie>, SceneError> {
        let cookie = match super::extras::light_cookie(extras).map_err(|e| self.invalid(format!("{label}: {e}")))? {
            Some(c) => {
                if c.image >= self.root.images.len() {
                    return Err(self.invalid(format!(
                        "{label}: extras.cookie.image: {} is not an image of the file (it has {})",
                        c.image,
                        self.root.images.len()
                    )));
                }
                let size_m = match (kind, c.size) {
                    (LightKind::Directional, Some([w, h])) if w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0 => {
                        Vec2::new(w, h)
                    }
                    (LightKind::Directional, _) => {
                        return Err(self.invalid(format!(
                            "{label}: extras.cookie.size: a directional light's cookie needs [width, height] in \
                             metres, both positive"
                        )));
                    }
                    _ => Vec2::ONE,
                };
                // The glTF image index for now; `decode_images` maps it to `Scene::images`.
                Some(Cookie { image: c.image, size_m })
            }
            None => None,
        };
        Ok(cookie)
    }

    pub(super) fn camera(&mut self, placement: &Placement) -> Result<Option<Camera>, SceneError> {
        let node = &self.root.nodes[placement.node];
        let Some(camera_index) = node.camera.map(|c| c.value()) else {
            return Ok(None);
        };
        let camera = &self.root.cameras[camera_index];
        let label = object_label("camera", camera_index, None, camera.name.as_deref());
        let lens = match (camera.type_, &camera.perspective, &camera.orthographic) {
            (Checked::Valid(json::camera::Type::Perspective), Some(p), _) => self.perspective_lens(&label, p)?,
            (Checked::Valid(json::camera::Type::Orthographic), _, Some(o)) => self.orthographic_lens(&label, o)?,
            (Checked::Valid(json::camera::Type::Perspective), None, _) => {
                return Err(self.invalid(format!("{label}: type is perspective but it has no perspective parameters")));
            }
            (Checked::Valid(json::camera::Type::Orthographic), _, None) => {
                return Err(
                    self.invalid(format!("{label}: type is orthographic but it has no orthographic parameters"))
                );
            }
            (Checked::Invalid, ..) => {
                self.ignored.push(format!(
                    "{label} on node {}: its type is neither perspective nor orthographic, ignored",
                    placement.node
                ));
                return Ok(None);
            }
        };
        let world_from_view = rigid_part(placement.world_from_local).ok_or_else(|| {
            self.invalid(format!("{label} on node {}: the node's transform is degenerate", placement.node))
        })?;
        Ok(Some(Camera {
            name: camera.name.clone().or_else(|| node.name.clone()).unwrap_or_else(|| format!("camera {camera_index}")),
            node: placement.node,
            projection: lens.projection,
            znear: lens.znear,
            zfar: lens.zfar,
            aspect_ratio: lens.aspect_ratio,
            world_from_view,
        }))
    }

    /// A perspective camera's checked values; the message names the camera and the value.
    fn perspective_lens(&self, label: &str, perspective: &json::camera::Perspective) -> Result<Lens, SceneError> {
        let yfov = perspective.yfov;
        let znear = perspective.znear;
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            return Err(self.invalid(format!("{label}: yfov {yfov} is not in (0, pi)")));
        }
        if !(znear > 0.0 && znear.is_finite()) {
            return Err(self.invalid(format!("{label}: znear {znear} is not positive")));
        }
        if let Some(zfar) = perspective.zfar
            && !(zfar > znear && zfar.is_finite())
        {
            return Err(self.invalid(format!("{label}: zfar {zfar} is not beyond znear {znear}")));
        }
        if let Some(aspect) = perspective.aspect_ratio
            && !(aspect > 0.0 && aspect.is_finite())
        {
            return Err(self.invalid(format!("{label}: aspect ratio {aspect} is not positive")));
        }
        Ok(Lens {
            projection: Projection::Perspective { yfov_rad: yfov },
            znear,
            zfar: perspective.zfar,
            aspect_ratio: perspective.aspect_ratio,
        })
    }

    /// An orthographic camera's checked values. The spec allows `znear` 0, which a
    /// parallel projection can draw, but the light clusters slice depth logarithmically,
    /// so a zero near plane is moved out by a millionth of the far distance. Negative
    /// magnifications (which the spec advises against) count by their size.
    fn orthographic_lens(&mut self, label: &str, o: &json::camera::Orthographic) -> Result<Lens, SceneError> {
        let (xmag, ymag, znear, zfar) = (o.xmag, o.ymag, o.znear, o.zfar);
        for (key, mag) in [("xmag", xmag), ("ymag", ymag)] {
            if !(mag.is_finite() && mag != 0.0) {
                return Err(self.invalid(format!("{label}: {key} {mag} is not a non-zero distance")));
            }
            if mag < 0.0 {
                self.ignored.push(format!("{label}: {key} {mag} is negative; its size is used"));
            }
        }
        if !(znear >= 0.0 && znear.is_finite()) {
            return Err(self.invalid(format!("{label}: znear {znear} is negative")));
        }
        if !(zfar > znear && zfar.is_finite()) {
            return Err(self.invalid(format!("{label}: zfar {zfar} is not beyond znear {znear}")));
        }
        Ok(Lens {
            projection: Projection::Orthographic { ymag: ymag.abs() },
            znear: znear.max(zfar * 1.0e-6),
            zfar: Some(zfar),
            aspect_ratio: Some(xmag.abs() / ymag.abs()),
        })
    }
}

/// A camera's projection and clip planes, checked.
struct Lens {
    projection: Projection,
    znear: f32,
    zfar: Option<f32>,
    aspect_ratio: Option<f32>,
}

/// A light's frame on a node placed at `world`: its rigid part. A zero scale collapses the
/// node's axes; the light then keeps its position and what is left of its direction.
pub(crate) fn light_frame(world: glam::Mat4) -> glam::Mat4 {
    rigid_part(world).unwrap_or_else(|| looking_along(world.w_axis.truncate(), world.transform_vector3(Vec3::NEG_Z)))
}

/// Validated spot cone half-angles: `0 <= inner < outer <= pi/2`. `inner == outer` (a
/// hard-edged cone some exporters write) is tolerated by pulling inner in by 1e-4 rad, so
/// that the smoothstep between them never divides by zero.
fn spot_cone(inner: f32, outer: f32) -> Option<(f32, f32)> {
    const EPS: f32 = 1e-4;
    let half_pi = std::f32::consts::FRAC_PI_2;
    let ordered = inner >= 0.0 && outer > 0.0 && inner <= outer && outer <= half_pi + 1e-6;
    if !ordered {
        return None;
    }
    let outer = outer.min(half_pi);
    let inner = if inner >= outer - EPS { (outer - EPS).max(0.0) } else { inner };
    Some((inner, outer))
}
