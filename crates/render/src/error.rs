//! Why a frame or a scene could not be rendered: one error type for the renderer and the
//! checks that run before it ([`crate::validate`]), in a module of its own so that neither
//! imports the other.

use crate::context::GpuError;
use crate::shader::ShaderError;

/// Why a frame could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A shader failed to assemble.
    #[error(transparent)]
    Shader(#[from] ShaderError),
    /// The GPU failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// `render` was called before `set_scene`.
    #[error("no scene uploaded: call Renderer::set_scene first")]
    NoScene,
    /// The device rejected a shader or pipeline (a bug, or a device lacking a feature).
    #[error("the GPU rejected a render pipeline: {0}")]
    Pipeline(String),
    /// The frame asks for something the renderer cannot do.
    #[error("invalid frame: {0}")]
    InvalidFrame(String),
    /// The scene needs more than the device allows.
    #[error("{0}")]
    SceneTooLarge(String),
}
