//! `texel_scene` is the document every other part of Texel works on: the components a level
//! is made of, stored in a [`hecs`] world ([`Scene`]); levels as versioned, canonical RON text
//! ([`Level`]) with errors that name the file, line and column; atomic saves; CPU meshes for
//! the primitives; and glTF import. It knows nothing of the GPU, so the renderer, the
//! runtime, the editor and the tests all share one definition of a level.

pub mod animator;
pub mod assets;
pub mod components;
pub mod density;
pub mod gltf_import;
pub mod hierarchy;
pub mod level;
pub mod level_read;
pub mod migrate;
pub mod num;
pub mod palette;
pub mod primitives;
pub mod read;
pub mod save;
pub mod scene;
pub mod sculpt;
pub mod sprite;
pub mod terrain;
pub mod texture;

pub use components::*;
pub use level::{CURRENT_VERSION, EntityRow, ErrorKind, Level, LevelError};
pub use scene::{KindCounts, Scene};
pub use texel_geom::{TriMesh, limits, mesh};
