//! `texel_geom` holds the plain data the scene and the renderer both speak, so the renderer
//! needs neither hecs, RON nor glTF: the triangle mesh every geometry source produces
//! ([`TriMesh`]), the images its surfaces sample ([`texture`]) and the engine's limits and conventions ([`limits`]), and the
//! ray–triangle test the renderer and the evaluator share ([`ray`]).

pub mod colour;
pub mod limits;
pub mod mesh;
pub mod ray;
pub mod texture;

pub use mesh::{LodPiece, MeshPart, TriMesh};
pub use texture::{Filter, Image, Sampler, SurfaceMaps, TextureRef, Wrap};
