//! `texel_geom` holds the plain data the scene and the renderer both speak, so the renderer
//! needs neither hecs, RON nor glTF: the triangle mesh every geometry source produces
//! ([`TriMesh`]) and the engine's limits and conventions ([`limits`]).

pub mod limits;
pub mod mesh;

pub use mesh::TriMesh;
