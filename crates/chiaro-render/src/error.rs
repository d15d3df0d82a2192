//! Errors at the GPU boundary: no adapter, missing features or limits, device failures.

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(
        "no GPU adapter found ({0}); install a Vulkan driver, e.g. on Debian/Ubuntu: \
         `apt-get install mesa-vulkan-drivers libvulkan1` for the software rasterizer lavapipe"
    )]
    NoAdapter(String),
    #[error("could not open the GPU device: {0}")]
    Device(String),
    #[error("output size {width}x{height} is invalid: {reason}")]
    OutputSize { width: u32, height: u32, reason: String },
    #[error("GPU error: {0}")]
    Gpu(String),
    #[error("frame graph: {0}")]
    FrameGraph(String),
    #[error("{0}")]
    Unsupported(String),
}
