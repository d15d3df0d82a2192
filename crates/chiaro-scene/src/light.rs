//! KHR_lights_punctual lights as the scene holds them: their kind and units, placement,
//! shadow settings from `extras`, cookie and bake mode.

use chiaro_math::area_light::AreaShape;
use chiaro_math::rigid::looking_along;
use glam::{Mat4, Vec2, Vec3};

/// KHR_lights_punctual's light types and EXT_lights_area's, with the units of their
/// intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Illuminance in lux on a surface facing the light.
    Directional,
    /// Intensity in candela.
    Point,
    /// Intensity in candela; glTF half-angles of the cone.
    Spot {
        /// Half-angle from the axis inside which the spot is at full intensity, radians.
        inner_cone_rad: f32,
        /// Half-angle from the axis beyond which the spot gives no light, radians.
        outer_cone_rad: f32,
    },
    /// EXT_lights_area's rect: luminance in nits over `width` (local X) by `height`
    /// (local Y) metres, emitting towards local -Z.
    Rect {
        /// Metres along the light's local X.
        width: f32,
        /// Metres along the light's local Y.
        height: f32,
    },
    /// EXT_lights_area's disk: luminance in nits over a disk of `diameter` metres in the
    /// local X/Y plane, emitting towards local -Z.
    Disk {
        /// Metres.
        diameter: f32,
    },
}

impl LightKind {
    /// KHR_lights_punctual's name for the type.
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Directional => "directional",
            LightKind::Point => "point",
            LightKind::Spot { .. } => "spot",
            LightKind::Rect { .. } => "rect",
            LightKind::Disk { .. } => "disk",
        }
    }

    /// The emitting shape of an area light; `None` for punctual lights.
    pub fn area_shape(self) -> Option<AreaShape> {
        match self {
            LightKind::Rect { width, height } => Some(AreaShape::Rect { width, height }),
            LightKind::Disk { diameter } => Some(AreaShape::Disk { diameter }),
            _ => None,
        }
    }
}

/// Realtime shadows of a light: `none`, `hard` (the 2x2 filter whatever the settings say),
/// `soft` (the settings' filter) or `pcss` (contact-hardening: a penumbra as wide as the
/// light's size and the blocker's distance make it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowMode {
    /// No realtime shadows.
    None,
    /// The 2x2 filter, whatever the settings say.
    Hard,
    /// The settings' filter.
    #[default]
    Soft,
    /// Percentage-closer soft shadows from the light's size (`LightShadow::light_radius`,
    /// `angular_diameter_deg`).
    Pcss,
}

impl ShadowMode {
    /// The light's `extras.shadows` value.
    pub fn name(self) -> &'static str {
        match self {
            ShadowMode::None => "none",
            ShadowMode::Hard => "hard",
            ShadowMode::Soft => "soft",
            ShadowMode::Pcss => "pcss",
        }
    }
}

/// A light's shadow settings, from its KHR_lights_punctual `extras`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightShadow {
    /// Whether and how softly it casts realtime shadows (`extras.shadows`).
    pub mode: ShadowMode,
    /// 0 to 1: how dark the shadow is.
    pub strength: f32,
    /// Slope-scale depth bias. Too little gives shadow acne on lit surfaces; too much
    /// detaches shadows from their casters (peter-panning).
    pub depth_bias: f32,
    /// Normal bias in shadow-map texels along the surface normal. Too little gives acne
    /// at grazing angles; too much shrinks shadows and leaks light at contact.
    pub normal_bias: f32,
    /// Metres the shadow projection's near plane is pulled towards the light. Too little
    /// clips (or, with depth clamping, flattens) casters close to the light; too much wastes
    /// depth precision.
    pub near_plane: f32,
    /// Radius in metres of the sphere a point or spot light emits from
    /// (`extras.lightRadius`): how wide `pcss` shadows grow with distance from their caster.
    pub light_radius: f32,
    /// Angle in degrees the disc of a directional light spans (`extras.angularDiameter`;
    /// the sun's is about 0.53), for its `pcss` shadows.
    pub angular_diameter_deg: f32,
}

/// `LightShadow::light_radius` where a light's extras give none, metres.
pub const DEFAULT_LIGHT_RADIUS: f32 = 0.05;
/// `LightShadow::angular_diameter_deg` where a light's extras give none: the sun's.
pub const DEFAULT_ANGULAR_DIAMETER_DEG: f32 = 0.53;

impl Default for LightShadow {
    fn default() -> Self {
        LightShadow {
            mode: ShadowMode::Soft,
            strength: 1.0,
            depth_bias: 1.0,
            normal_bias: 0.5,
            near_plane: 0.0,
            light_radius: DEFAULT_LIGHT_RADIUS,
            angular_diameter_deg: DEFAULT_ANGULAR_DIAMETER_DEG,
        }
    }
}

impl LightShadow {
    /// Whether the light casts shadows at all: a mode other than none, and some strength.
    pub fn casts(&self) -> bool {
        self.mode != ShadowMode::None && self.strength > 0.0
    }
}

/// A light cookie (light `extras.cookie`): an image, read as linear values, that
/// multiplies the light's colour channel by channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cookie {
    /// Index into `Scene::images`.
    pub image: usize,
    /// Directional cookies: metres one repeat of the image spans along the light's local
    /// X and Y (unused by spot and point cookies).
    pub size_m: Vec2,
}

/// How a light is evaluated (light `extras.mode`). Without a bake every light is realtime,
/// so that nothing goes dark.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightMode {
    /// Realtime direct light, not baked at all.
    #[default]
    Realtime,
    /// Realtime direct light; its indirect light is baked.
    Mixed,
    /// Direct and indirect light baked; not evaluated at runtime when a bake is applied.
    Baked,
}

impl LightMode {
    /// The light's `extras.mode` value.
    pub fn name(self) -> &'static str {
        match self {
            LightMode::Realtime => "realtime",
            LightMode::Mixed => "mixed",
            LightMode::Baked => "baked",
        }
    }

    /// Whether the baker writes the light's direct light.
    pub fn bakes_direct(self) -> bool {
        self == LightMode::Baked
    }

    /// Whether the baker carries the light's bounced light.
    pub fn bakes_indirect(self) -> bool {
        self != LightMode::Realtime
    }
}

/// A KHR_lights_punctual light placed in the world.
#[derive(Clone, Debug)]
pub struct Light {
    /// The light's name, else its node's, else `light N` (empty for lights made in code).
    pub name: String,
    /// Index of the glTF node that carries the light.
    pub node: usize,
    /// Directional, point or spot, with the spot's cone.
    pub kind: LightKind,
    /// Linear RGB.
    pub color: Vec3,
    /// Lux for directional lights, candela for point and spot lights, nits (luminance)
    /// for rect and disk lights.
    pub intensity: f32,
    /// Range from the file; `None` means infinite (a range is derived at render time).
    pub range: Option<f32>,
    /// The light's node without scale: unit axes, -Z the way it shines, +X and +Y its
    /// roll (which orients cookies and shadow tiles), the translation its position.
    pub world_from_light: Mat4,
    /// Its shadow settings, from `extras`.
    pub shadow: LightShadow,
    /// The image that tints its light, if any (`extras.cookie`).
    pub cookie: Option<Cookie>,
    /// Realtime, mixed or baked (`extras.mode`).
    pub mode: LightMode,
}

impl Light {
    /// A white light of intensity 1, with no range, default shadows and no name, carried
    /// by node 0, at `position` shining along `direction` (rolled as
    /// chiaro_math::rigid::looking_along rolls it): the starting point for lights made in code.
    pub fn new(kind: LightKind, position: Vec3, direction: Vec3) -> Light {
        Light {
            name: String::new(),
            node: 0,
            kind,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
            world_from_light: looking_along(position, direction),
            shadow: LightShadow::default(),
            cookie: None,
            mode: LightMode::Realtime,
        }
    }

    /// World position, metres (the origin of its node); unused by directional lights.
    pub fn position(&self) -> Vec3 {
        self.world_from_light.w_axis.truncate()
    }

    /// The range a point or spot light is shaded, baked and judged with, metres:
    /// `chiaro_math::light::shaded_range` of its own range and peak intensity.
    /// An area light's range also reaches past its own extent.
    pub fn shaded_range(&self, range_threshold_lux: f32) -> f32 {
        let range = chiaro_math::light::shaded_range(self.range, self.peak_intensity_cd(), range_threshold_lux);
        match (self.kind.area_shape(), self.range) {
            (Some(shape), None) => range + shape.bounding_radius(),
            _ => range,
        }
    }

    /// The brightest channel's intensity in candela in the light's brightest direction:
    /// a point or spot light's intensity, an area light's luminance times its area (what
    /// it gives far away, along its axis). Lux for directional lights.
    pub fn peak_intensity_cd(&self) -> f32 {
        let area = self.kind.area_shape().map_or(1.0, AreaShape::area);
        self.intensity * area * self.color.max_element()
    }

    /// Whether it is a rect or disk light.
    pub fn is_area(&self) -> bool {
        self.kind.area_shape().is_some()
    }

    /// A rect or disk light's outline in world space (`AreaShape::outline`); `None` for
    /// punctual lights.
    pub fn area_outline_ws(&self) -> Option<Vec<Vec3>> {
        let shape = self.kind.area_shape()?;
        Some(shape.outline().iter().map(|p| self.world_from_light.transform_point3(p.extend(0.0))).collect())
    }

    /// The projected solid angle a surface at `position` with unit `normal` sees a rect
    /// or disk light under, exactly (clipped to its horizon), and zero behind the light,
    /// which emits towards its -Z only: its unshadowed irradiance over its luminance. 0
    /// for punctual lights.
    pub fn area_projected_solid_angle(&self, position: Vec3, normal: Vec3) -> f32 {
        let Some(outline) = self.area_outline_ws() else {
            return 0.0;
        };
        if (position - self.position()).dot(self.direction()) <= 0.0 {
            return 0.0;
        }
        let relative: Vec<Vec3> = outline.iter().map(|&p| p - position).collect();
        chiaro_math::area_light::projected_solid_angle(&relative, normal)
    }

    /// Unit direction the light shines in (-Z of its node); unused by point lights.
    pub fn direction(&self) -> Vec3 {
        -self.world_from_light.z_axis.truncate()
    }
}
