//! Errors at the GPU boundary: no adapter, missing features or limits, device failures.

/// What can go wrong at the GPU boundary; each message says what failed and why.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter (not even lavapipe) was found; carries wgpu's reason.
    #[error(
        "no GPU adapter found ({0}); install a Vulkan driver, e.g. on Debian/Ubuntu: \
         `apt-get install mesa-vulkan-drivers libvulkan1` for the software rasterizer lavapipe"
    )]
    NoAdapter(String),
    /// The adapter would not open a device with the features and limits asked for.
    #[error("could not open the GPU device: {0}")]
    Device(String),
    /// The requested output is zero-sized or larger than the device's textures.
    #[error("output size {width}x{height} is invalid: {reason}")]
    OutputSize {
        /// The width asked for, in pixels.
        width: u32,
        /// The height asked for, in pixels.
        height: u32,
        /// Why the device cannot render it.
        reason: String,
    },
    /// A validation or out-of-memory error the device reported.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// A frame graph that cannot be compiled: a read before any write, a target created
    /// twice or written but never created.
    #[error("frame graph: {0}")]
    FrameGraph(String),
    /// The environment could not be made; the message names the image file.
    #[error("{0}")]
    Environment(String),
    /// A request this device cannot serve, such as an MSAA sample count it lacks.
    #[error("{0}")]
    Unsupported(String),
}
