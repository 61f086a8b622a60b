//! `texel_runtime` joins the scene, the probe system and the renderer into something that
//! plays a level: it loads levels and their assets, turns the hecs world into the plain data
//! the renderer consumes, and drives the frame loop. The `texel-run` binary is a thin
//! wrapper over [`cli`], so tests and the editor reuse the same code.

pub mod cli;
pub mod density_check;
pub mod extract;
pub mod first_person;
pub mod frame_plan;
pub mod generate;
pub mod headless;
pub mod level_sprites;
pub mod load;
pub mod occluders;
pub mod path;
pub mod play;
pub mod play_sculpt;
pub mod reload;
pub mod session;
pub mod soak;
pub mod stamp;
pub mod walk;
