//! The outputs a frame can give, by the names jobs and the Python package use: names in,
//! the frame options that render those outputs and no more out, and for a job's folder
//! the file each output is encoded to (as `chiaro render` encodes it).

use chiaro_io::output::Encoded;
use chiaro_render::{FrameOptions, FrameOutput};

/// One output of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Output {
    /// Tone-mapped sRGB: `rgb.png` (RGBA8), `(H, W, 3)` uint8 in Python.
    Rgb,
    /// Linear radiance: `hdr.exr` (RGB float32).
    Hdr,
    /// Linear view depth in metres, infinite on the sky: `depth.exr` (one float32 channel).
    Depth,
    /// World-space shading normal, NaN on the sky: `normal.exr` (RGB float32).
    Normal,
    /// World-space position in metres, NaN on the sky: `position.exr` (RGB float32).
    Position,
    /// The glTF node index of the mesh seen, 0xFFFFFFFF on the sky: `instance.exr` (uint32).
    Instance,
    /// The node's `extras.label`, 0 where none: `label.exr` (uint32).
    Label,
    /// Per light, the realtime shadow attenuation the shading used: `shadow.<node>.exr`.
    Shadow,
    /// The ambient occlusion the shading used, 1 open (everywhere without
    /// `[ambient_occlusion] enabled`): `ao.exr` (one float32 channel).
    Ao,
}

impl Output {
    /// Every output's name, in the order of the enum.
    pub const NAMES: [&'static str; 9] =
        ["rgb", "hdr", "depth", "normal", "position", "instance", "label", "shadow", "ao"];
    /// Every output, in the order of `NAMES`.
    pub const ALL: [Output; 9] = [
        Output::Rgb,
        Output::Hdr,
        Output::Depth,
        Output::Normal,
        Output::Position,
        Output::Instance,
        Output::Label,
        Output::Shadow,
        Output::Ao,
    ];

    /// The output called `name`, if any.
    pub fn parse(name: &str) -> Option<Output> {
        Output::NAMES.iter().position(|n| *n == name).map(|i| Output::ALL[i])
    }

    /// The output's name.
    pub fn name(self) -> &'static str {
        Output::NAMES[Output::ALL.iter().position(|o| *o == self).expect("every output is listed")]
    }
}

/// The outputs asked for, each once, in the order first asked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outputs(pub Vec<Output>);

impl Default for Outputs {
    /// The tone-mapped image alone.
    fn default() -> Outputs {
        Outputs(vec![Output::Rgb])
    }
}

impl Outputs {
    /// The outputs `names` name (repeats count once); the message starts with `outputs:`.
    pub fn from_names<S: AsRef<str>>(names: &[S]) -> Result<Outputs, String> {
        let mut outputs = Vec::new();
        for name in names {
            let name = name.as_ref();
            let output = Output::parse(name)
                .ok_or_else(|| format!("outputs: '{name}' is not one of {}", Output::NAMES.join(", ")))?;
            if !outputs.contains(&output) {
                outputs.push(output);
            }
        }
        if outputs.is_empty() {
            return Err("outputs: name at least one output".into());
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
            ambient_occlusion: self.wants(Output::Ao),
            readback: any(&[Output::Rgb, Output::Hdr, Output::Depth, Output::Normal, Output::Position]),
            skip_hdr: !self.wants(Output::Hdr),
            read_shadow_atlas: false,
            debug: None,
        }
    }

    /// The files of a job's folder for these outputs of `frame`, by name, encoded as
    /// `chiaro render` encodes the same images. `hdr_rgb` is the frame's radiance without
    /// alpha (the caller owns it: an EXR holds RGB); `light_nodes` are the scene lights'
    /// glTF nodes, which name the shadow files.
    pub fn files<'a>(
        &self,
        frame: &'a FrameOutput,
        hdr_rgb: &'a [[f32; 3]],
        light_nodes: &[usize],
    ) -> Vec<(String, Encoded<'a>)> {
        let (width, height) = (frame.width, frame.height);
        let mut files = Vec::new();
        for output in &self.0 {
            match output {
                Output::Rgb => files.push(("rgb.png".into(), Encoded::Png { width, height, rgba8: &frame.ldr })),
                Output::Hdr => files.push(("hdr.exr".into(), Encoded::ExrRgb { width, height, rgb: hdr_rgb })),
                Output::Depth | Output::Normal | Output::Position => {
                    let aovs = frame.aovs.as_ref().expect("the frame options ask for the AOVs");
                    let image = match output {
                        Output::Depth => Encoded::ExrSingle { width, height, values: &aovs.depth },
                        Output::Normal => Encoded::ExrRgb { width, height, rgb: &aovs.normal_ws },
                        _ => Encoded::ExrRgb { width, height, rgb: &aovs.position_ws },
                    };
                    files.push((format!("{}.exr", output.name()), image));
                }
                Output::Instance | Output::Label => {
                    let ids = frame.ids.as_ref().expect("the frame options ask for the ids");
                    let values = if *output == Output::Instance { &ids.instance } else { &ids.label };
                    files.push((format!("{}.exr", output.name()), Encoded::ExrU32 { width, height, values }));
                }
                Output::Shadow => {
                    for (node, values) in light_nodes.iter().zip(&frame.shadow_aovs) {
                        files.push((format!("shadow.{node}.exr"), Encoded::ExrSingle { width, height, values }));
                    }
                }
                Output::Ao => {
                    let values = frame.ambient_occlusion.as_ref().expect("the frame options ask for the AO");
                    files.push(("ao.exr".into(), Encoded::ExrSingle { width, height, values }));
                }
            }
        }
        files
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_to_their_outputs_once_each() {
        for (name, output) in Output::NAMES.iter().zip(Output::ALL) {
            assert_eq!(Output::parse(name), Some(output));
            assert_eq!(output.name(), *name);
        }
        let outputs = Outputs::from_names(&["depth", "rgb", "depth"]).unwrap();
        assert_eq!(outputs.0, vec![Output::Depth, Output::Rgb]);
        assert_eq!(
            Outputs::from_names(&["rgb", "colour"]).unwrap_err(),
            "outputs: 'colour' is not one of rgb, hdr, depth, normal, position, instance, label, shadow, ao"
        );
        assert_eq!(Outputs::from_names::<&str>(&[]).unwrap_err(), "outputs: name at least one output");
    }

    #[test]
    fn frame_options_render_what_is_asked_and_no_more() {
        let options = Outputs::from_names(&["rgb"]).unwrap().frame_options();
        assert!(options.readback && !options.aovs && !options.ids && !options.shadow_aovs);
        let depth = Outputs::from_names(&["depth"]).unwrap().frame_options();
        assert!(depth.aovs && depth.depth_only, "depth alone is the depth-only AOV pass");
        let full = Outputs::from_names(&["depth", "normal"]).unwrap().frame_options();
        assert!(full.aovs && !full.depth_only);
        let ids = Outputs::from_names(&["label", "shadow"]).unwrap().frame_options();
        assert!(ids.ids && ids.shadow_aovs && !ids.readback && !ids.aovs);
    }
}
