//! `chiaro.Light`: a view of one light of a scene; reading or setting an attribute reads or
//! changes the scene itself, with the checks the glTF importer makes.

use crate::scene::{SharedScene, reading, writing};
use chiaro_math::light::MAX_LIGHT_INTENSITY;
use chiaro_scene::{LightKind, LightMode, ShadowMode};
use glam::Vec3;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A punctual light of a scene (KHR_lights_punctual), in physical units: directional
/// lights in lux, point and spot lights in candela. Setting an attribute changes the
/// scene; the next frame uses it.
#[pyclass(module = "chiaro", frozen)]
pub struct Light {
    pub state: SharedScene,
    pub index: usize,
}

impl Light {
    fn with<T: Send>(&self, f: impl FnOnce(&chiaro_scene::Light) -> T + Send) -> T {
        reading(&self.state, |s| f(&s.scene.lights[self.index]))
    }

    fn edit<T: Send>(&self, f: impl FnOnce(&mut chiaro_scene::Light) -> PyResult<T> + Send) -> PyResult<T> {
        writing(&self.state, |s| f(&mut s.scene.lights[self.index]))
    }
}

fn check_brightness(intensity: f32, color: Vec3) -> PyResult<()> {
    let peak = intensity * color.max_element();
    if peak > MAX_LIGHT_INTENSITY {
        return Err(PyValueError::new_err(format!(
            "intensity {intensity:e} times colour {color} is beyond {MAX_LIGHT_INTENSITY:e}, the brightest light \
             Chiaro shades"
        )));
    }
    Ok(())
}

#[pymethods]
impl Light {
    /// The light's name (the glTF light's, else its node's).
    #[getter]
    fn name(&self) -> String {
        self.with(|l| l.name.clone())
    }

    /// The glTF node index that carries the light (the `shadow.<node>` AOV's number).
    #[getter]
    fn node(&self) -> usize {
        self.with(|l| l.node)
    }

    /// "directional", "point", "spot", "rect" or "disk".
    #[getter]
    fn kind(&self) -> &'static str {
        self.with(|l| l.kind.name())
    }

    /// The light's type as glTF names it: "directional", "point" or "spot"
    /// (KHR_lights_punctual), "rect" or "disk" (EXT_lights_area). The same as `kind`.
    #[getter]
    #[pyo3(name = "type")]
    fn light_type(&self) -> &'static str {
        self.with(|l| l.kind.name())
    }

    /// A rect light's height (along its local Y) or a disk light's diameter, metres, as
    /// EXT_lights_area's `size` (times the node's scale); None for punctual lights.
    #[getter]
    fn size(&self) -> Option<f32> {
        self.with(|l| match l.kind {
            LightKind::Rect { height, .. } => Some(height),
            LightKind::Disk { diameter } => Some(diameter),
            _ => None,
        })
    }

    /// Sets a rect's height (keeping its aspect) or a disk's diameter; positive metres.
    #[setter]
    fn set_size(&self, metres: f32) -> PyResult<()> {
        if !(metres.is_finite() && metres > 0.0) {
            return Err(PyValueError::new_err(format!("size: {metres} must be a positive number of metres")));
        }
        self.edit(|l| {
            let kind = match l.kind {
                LightKind::Rect { width, height } => LightKind::Rect { width: width / height * metres, height: metres },
                LightKind::Disk { .. } => LightKind::Disk { diameter: metres },
                other => {
                    return Err(PyValueError::new_err(format!("size: a {} light is not a rect or disk", other.name())));
                }
            };
            // Luminance times area is the light's peak intensity.
            check_brightness(l.intensity * kind.area_shape().map_or(1.0, |s| s.area().max(1.0)), l.color)?;
            l.kind = kind;
            Ok(())
        })
    }

    /// A rect light's width over its height (EXT_lights_area's `rect.aspect`); None for
    /// other lights.
    #[getter]
    fn aspect(&self) -> Option<f32> {
        self.with(|l| match l.kind {
            LightKind::Rect { width, height } => Some(width / height),
            _ => None,
        })
    }

    /// Sets a rect's width to `aspect` times its height.
    #[setter]
    fn set_aspect(&self, aspect: f32) -> PyResult<()> {
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(PyValueError::new_err(format!("aspect: {aspect} must be a positive number")));
        }
        self.edit(|l| match l.kind {
            LightKind::Rect { height, .. } => {
                l.kind = LightKind::Rect { width: aspect * height, height };
                Ok(())
            }
            other => Err(PyValueError::new_err(format!("aspect: a {} light is not a rect", other.name()))),
        })
    }

    /// Linear RGB colour, each channel 0 or more.
    #[getter]
    fn color(&self) -> [f32; 3] {
        self.with(|l| l.color.to_array())
    }

    #[setter]
    fn set_color(&self, color: [f32; 3]) -> PyResult<()> {
        let c = Vec3::from_array(color);
        if !c.is_finite() || c.min_element() < 0.0 {
            return Err(PyValueError::new_err(format!("color: {color:?} is not a linear RGB colour")));
        }
        self.edit(|l| {
            check_brightness(l.intensity, c)?;
            l.color = c;
            Ok(())
        })
    }

    /// Lux for directional lights, candela for point and spot lights.
    #[getter]
    fn intensity(&self) -> f32 {
        self.with(|l| l.intensity)
    }

    #[setter]
    fn set_intensity(&self, intensity: f32) -> PyResult<()> {
        if !intensity.is_finite() || intensity < 0.0 {
            return Err(PyValueError::new_err(format!("intensity: {intensity} is negative or not finite")));
        }
        self.edit(|l| {
            // An area light's peak is its luminance times its area.
            check_brightness(intensity * l.kind.area_shape().map_or(1.0, |s| s.area().max(1.0)), l.color)?;
            l.intensity = intensity;
            Ok(())
        })
    }

    /// Range in metres beyond which the light gives nothing; None for the range the
    /// renderer derives from the intensity (`[lights] range_threshold_lux`).
    #[getter]
    fn range(&self) -> Option<f32> {
        self.with(|l| l.range)
    }

    #[setter]
    fn set_range(&self, range: Option<f32>) -> PyResult<()> {
        if let Some(r) = range
            && !(r.is_finite() && r > 0.0)
        {
            return Err(PyValueError::new_err(format!("range: {r} is not positive")));
        }
        self.edit(|l| {
            l.range = range;
            Ok(())
        })
    }

    /// A spot's inner cone half-angle in degrees (full intensity inside); None for other
    /// lights.
    #[getter]
    fn inner_cone_deg(&self) -> Option<f32> {
        self.cone_deg().map(|[inner, _]| inner)
    }

    #[setter]
    fn set_inner_cone_deg(&self, degrees: f32) -> PyResult<()> {
        self.set_cone(Some(degrees), None)
    }

    /// A spot's outer cone half-angle in degrees (no light beyond); None for other lights.
    #[getter]
    fn outer_cone_deg(&self) -> Option<f32> {
        self.cone_deg().map(|[_, outer]| outer)
    }

    #[setter]
    fn set_outer_cone_deg(&self, degrees: f32) -> PyResult<()> {
        self.set_cone(None, Some(degrees))
    }

    /// Whether the light casts realtime shadows. Set True (the settings' filter), False,
    /// or a mode name: "none", "hard" (2x2 filter), "soft" or "pcss" (contact-hardening).
    #[getter]
    fn shadows(&self) -> bool {
        self.with(|l| l.shadow.casts())
    }

    #[setter]
    fn set_shadows(&self, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let mode = if let Ok(on) = value.extract::<bool>() {
            if on { ShadowMode::Soft } else { ShadowMode::None }
        } else if let Ok(name) = value.extract::<String>() {
            match name.as_str() {
                "none" => ShadowMode::None,
                "hard" => ShadowMode::Hard,
                "soft" => ShadowMode::Soft,
                "pcss" => ShadowMode::Pcss,
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "shadows: '{name}' is not one of True, False, 'none', 'hard', 'soft', 'pcss'"
                    )));
                }
            }
        } else {
            return Err(PyTypeError::new_err("shadows: expected a bool or 'none', 'hard', 'soft' or 'pcss'"));
        };
        self.edit(|l| {
            l.shadow.mode = mode;
            Ok(())
        })
    }

    /// The shadow mode by name: "none", "hard", "soft" or "pcss" (the light's
    /// `extras.shadows`).
    #[getter]
    fn shadow_mode(&self) -> &'static str {
        self.with(|l| l.shadow.mode.name())
    }

    /// How dark the shadow is, 0 to 1.
    #[getter]
    fn shadow_strength(&self) -> f32 {
        self.with(|l| l.shadow.strength)
    }

    #[setter]
    fn set_shadow_strength(&self, strength: f32) -> PyResult<()> {
        if !(0.0..=1.0).contains(&strength) {
            return Err(PyValueError::new_err(format!("shadow_strength: {strength} is not between 0 and 1")));
        }
        self.edit(|l| {
            l.shadow.strength = strength;
            Ok(())
        })
    }

    /// Radius in metres of the sphere a point or spot light emits from, for "pcss" shadows
    /// (the light's `extras.lightRadius`).
    #[getter]
    fn light_radius(&self) -> f32 {
        self.with(|l| l.shadow.light_radius)
    }

    #[setter]
    fn set_light_radius(&self, radius: f32) -> PyResult<()> {
        self.edit(|l| {
            if !(radius.is_finite() && radius >= 0.0 && l.range.is_none_or(|range| radius <= range)) {
                return Err(PyValueError::new_err(format!(
                    "light_radius: {radius} m is negative, not finite or larger than the light's range"
                )));
            }
            l.shadow.light_radius = radius;
            Ok(())
        })
    }

    /// Degrees a directional light's disc spans, for "pcss" shadows (the light's
    /// `extras.angularDiameter`; the sun's is about 0.53).
    #[getter]
    fn angular_diameter(&self) -> f32 {
        self.with(|l| l.shadow.angular_diameter_deg)
    }

    #[setter]
    fn set_angular_diameter(&self, degrees: f32) -> PyResult<()> {
        if !(degrees.is_finite() && (0.0..180.0).contains(&degrees)) {
            return Err(PyValueError::new_err(format!(
                "angular_diameter: {degrees} is not from 0 to below 180 degrees"
            )));
        }
        self.edit(|l| {
            l.shadow.angular_diameter_deg = degrees;
            Ok(())
        })
    }

    /// "realtime", "mixed" or "baked" (the light's `extras.mode`).
    #[getter]
    fn mode(&self) -> &'static str {
        self.with(|l| l.mode.name())
    }

    #[setter]
    fn set_mode(&self, mode: &str) -> PyResult<()> {
        let mode = match mode {
            "realtime" => LightMode::Realtime,
            "mixed" => LightMode::Mixed,
            "baked" => LightMode::Baked,
            other => {
                return Err(PyValueError::new_err(format!(
                    "mode: '{other}' is not one of 'realtime', 'mixed', 'baked'"
                )));
            }
        };
        self.edit(|l| {
            l.mode = mode;
            Ok(())
        })
    }

    /// World-space position in metres (a directional light's node position).
    #[getter]
    fn position(&self) -> [f32; 3] {
        self.with(|l| l.position().to_array())
    }

    /// World-space unit direction the light points along (its node's -Z).
    #[getter]
    fn direction(&self) -> [f32; 3] {
        self.with(|l| l.direction().to_array())
    }

    fn __repr__(&self) -> String {
        self.with(|l| {
            format!(
                "<chiaro.Light {:?} node {}: {} {:.4} {}, shadows {}>",
                l.name,
                l.node,
                l.kind.name(),
                l.intensity,
                match l.kind {
                    LightKind::Directional => "lx",
                    LightKind::Rect { .. } | LightKind::Disk { .. } => "nits",
                    _ => "cd",
                },
                l.shadow.mode.name()
            )
        })
    }
}

impl Light {
    /// A spot's inner and outer cone half-angles in degrees; None for other lights.
    fn cone_deg(&self) -> Option<[f32; 2]> {
        self.with(|l| match l.kind {
            LightKind::Spot { inner_cone_rad, outer_cone_rad } => {
                Some([inner_cone_rad.to_degrees(), outer_cone_rad.to_degrees()])
            }
            _ => None,
        })
    }

    /// Sets a spot's cone angles (either or both), keeping 0 <= inner < outer <= 90 degrees.
    fn set_cone(&self, inner_deg: Option<f32>, outer_deg: Option<f32>) -> PyResult<()> {
        self.edit(|l| {
            let LightKind::Spot { inner_cone_rad, outer_cone_rad } = l.kind else {
                return Err(PyValueError::new_err(format!(
                    "cone angles: light '{}' is a {} light, not a spot",
                    l.name,
                    l.kind.name()
                )));
            };
            let inner = inner_deg.map_or(inner_cone_rad, f32::to_radians);
            let outer = outer_deg.map_or(outer_cone_rad, f32::to_radians);
            if !(inner.is_finite() && outer.is_finite() && 0.0 <= inner && inner < outer && outer <= 90f32.to_radians())
            {
                return Err(PyValueError::new_err(format!(
                    "cone angles must satisfy 0 <= inner ({:.3}) < outer ({:.3}) <= 90 degrees",
                    inner.to_degrees(),
                    outer.to_degrees()
                )));
            }
            l.kind = LightKind::Spot { inner_cone_rad: inner, outer_cone_rad: outer };
            Ok(())
        })
    }
}
