//! The arrays a render can return, by name, and what the frame must render and read back
//! for them.

use chiaro_render::FrameOptions;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// One output of `Renderer.render`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// (H, W, 3) uint8 tone-mapped sRGB.
    Rgb,
    /// (H, W, 3) float32 linear radiance.
    Hdr,
    /// (H, W) float32 linear view depth, metres; inf on the sky.
    Depth,
    /// (H, W, 3) float32 world-space shading normal; NaN on the sky.
    Normal,
    /// (H, W, 3) float32 world-space position, metres; NaN on the sky.
    Position,
    /// (H, W) uint32 glTF node index; 0xFFFFFFFF on the sky.
    Instance,
    /// (H, W) uint32 node `extras.label`; 0 where none.
    Label,
    /// (L, H, W) float32 realtime shadow attenuation per light.
    Shadow,
}

impl Output {
    /// Every output's name, in the order of the enum.
    pub const NAMES: [&'static str; 8] = ["rgb", "hdr", "depth", "normal", "position", "instance", "label", "shadow"];
    const ALL: [Output; 8] = [
        Output::Rgb,
        Output::Hdr,
        Output::Depth,
        Output::Normal,
        Output::Position,
        Output::Instance,
        Output::Label,
        Output::Shadow,
    ];

    fn parse(name: &str) -> Option<Output> {
        Output::NAMES.iter().position(|n| *n == name).map(|i| Output::ALL[i])
    }
}

/// The outputs asked for, each once.
#[derive(Clone, Debug, Default)]
pub struct Outputs(pub Vec<Output>);

impl Outputs {
    /// Reads `outputs=`: a string or a sequence of strings naming outputs.
    pub fn extract(value: Option<&Bound<'_, PyAny>>) -> PyResult<Outputs> {
        let Some(value) = value.filter(|v| !v.is_none()) else { return Ok(Outputs(vec![Output::Rgb])) };
        let names: Vec<String> = if let Ok(one) = value.extract::<String>() {
            vec![one]
        } else {
            value.extract::<Vec<String>>().map_err(|_| {
                PyTypeError::new_err("outputs: expected a sequence of output names such as ('rgb', 'depth')")
            })?
        };
        let mut outputs = Vec::new();
        for name in &names {
            let output = Output::parse(name).ok_or_else(|| {
                PyValueError::new_err(format!("outputs: '{name}' is not one of {}", Output::NAMES.join(", ")))
            })?;
            if !outputs.contains(&output) {
                outputs.push(output);
            }
        }
        if outputs.is_empty() {
            return Err(PyValueError::new_err("outputs: name at least one output"));
        }
        Ok(Outputs(outputs))
    }

    /// Whether `output` was asked for.
    pub fn wants(&self, output: Output) -> bool {
        self.0.contains(&output)
    }

    /// What the frame renders and reads back for these outputs and no more.
    pub fn frame_options(&self) -> FrameOptions {
        let any = |list: &[Output]| list.iter().any(|o| self.wants(*o));
        FrameOptions {
            aovs: any(&[Output::Depth, Output::Normal, Output::Position]),
            // Depth without normal or position: one float a pixel instead of two float4s.
            depth_only: !any(&[Output::Normal, Output::Position]),
            shadow_aovs: self.wants(Output::Shadow),
            ids: any(&[Output::Instance, Output::Label]),
            readback: any(&[Output::Rgb, Output::Hdr, Output::Depth, Output::Normal, Output::Position]),
            read_shadow_atlas: false,
            debug: None,
        }
    }
}
