//! A read-back frame as numpy arrays. The pixels are put into their final layout once,
//! without the GIL; numpy then takes ownership of those vectors in their final shape
//! (`IntoPyArray`), so no further copy is made.

use crate::outputs::{Output, Outputs};
use chiaro_render::FrameOutput;
use numpy::ndarray::{self, IxDyn};
use numpy::{Element, IntoPyArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One array's data and its shape.
pub struct Array<T> {
    data: Vec<T>,
    shape: Vec<usize>,
}

impl<T: Element> Array<T> {
    fn into_py<'py>(self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let array = ndarray::ArrayD::from_shape_vec(IxDyn(&self.shape), self.data)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("array layout: {e}")))?;
        Ok(array.into_pyarray(py).into_any())
    }
}

/// A frame's outputs, laid out for numpy, made without the GIL.
pub struct FrameArrays {
    u8s: Vec<(Output, Array<u8>)>,
    f32s: Vec<(Output, Array<f32>)>,
    u32s: Vec<(Output, Array<u32>)>,
    /// The glTF node of each shadow layer, in order.
    shadow_lights: Option<Vec<usize>>,
}

/// Flattens pixels of N channels kept as arrays into one vector.
fn flatten<const N: usize>(pixels: Vec<[f32; N]>) -> Vec<f32> {
    pixels.into_iter().flatten().collect()
}

impl FrameArrays {
    /// Takes what `outputs` asked for out of `frame`; `shadow_nodes` are the scene's
    /// lights' nodes, one per shadow layer.
    pub fn new(frame: FrameOutput, outputs: &Outputs, shadow_nodes: Vec<usize>) -> FrameArrays {
        let (h, w) = (frame.height as usize, frame.width as usize);
        let mut arrays = FrameArrays { u8s: Vec::new(), f32s: Vec::new(), u32s: Vec::new(), shadow_lights: None };
        let FrameOutput { ldr, hdr, aovs, ids, shadow_aovs, ambient_occlusion, .. } = frame;
        let mut ambient_occlusion = ambient_occlusion;
        let mut aovs = aovs;
        let mut ids = ids;
        for &output in &outputs.0 {
            match output {
                Output::Rgb => {
                    let rgb: Vec<u8> = ldr.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
                    arrays.u8s.push((output, Array { data: rgb, shape: vec![h, w, 3] }));
                }
                Output::Hdr => {
                    let rgb: Vec<f32> = hdr.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
                    arrays.f32s.push((output, Array { data: rgb, shape: vec![h, w, 3] }));
                }
                Output::Depth | Output::Normal | Output::Position => {
                    let a = aovs.as_mut().expect("the frame rendered its AOVs");
                    let (data, shape) = match output {
                        Output::Depth => (std::mem::take(&mut a.depth), vec![h, w]),
                        Output::Normal => (flatten(std::mem::take(&mut a.normal_ws)), vec![h, w, 3]),
                        _ => (flatten(std::mem::take(&mut a.position_ws)), vec![h, w, 3]),
                    };
                    arrays.f32s.push((output, Array { data, shape }));
                }
                Output::Instance | Output::Label => {
                    let i = ids.as_mut().expect("the frame rendered its ids");
                    let data = match output {
                        Output::Instance => std::mem::take(&mut i.instance),
                        _ => std::mem::take(&mut i.label),
                    };
                    arrays.u32s.push((output, Array { data, shape: vec![h, w] }));
                }
                Output::Shadow => {
                    let layers = shadow_aovs.len();
                    let data: Vec<f32> = shadow_aovs.iter().flatten().copied().collect();
                    arrays.f32s.push((output, Array { data, shape: vec![layers, h, w] }));
                    arrays.shadow_lights = Some(shadow_nodes.iter().copied().take(layers).collect());
                }
                Output::Ao => {
                    let data = ambient_occlusion.take().expect("the frame read back its AO");
                    arrays.f32s.push((output, Array { data, shape: vec![h, w] }));
                }
            }
        }
        arrays
    }

    /// The outputs as a dict of numpy arrays keyed by output name (and `shadow_lights`,
    /// a list of node indices, beside `shadow`).
    pub fn into_dict<'py>(self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        let name = |o: Output| Output::NAMES[o as usize];
        for (output, array) in self.u8s {
            dict.set_item(name(output), array.into_py(py)?)?;
        }
        for (output, array) in self.f32s {
            dict.set_item(name(output), array.into_py(py)?)?;
        }
        for (output, array) in self.u32s {
            dict.set_item(name(output), array.into_py(py)?)?;
        }
        if let Some(nodes) = self.shadow_lights {
            dict.set_item("shadow_lights", nodes)?;
        }
        Ok(dict)
    }
}
