//! The editor's panels. Each is a function that borrows the part of the state it shows.

pub mod animator;
pub mod dialogs;
pub mod hierarchy;
pub mod inspector;
pub mod menu;
pub mod multi_edit;
pub mod palette_section;
pub mod pixel_section;
pub mod sprite_section;
pub mod widgets;
