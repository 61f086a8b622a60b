//! The document's terrains as things to edit: a terrain entity with its loaded heights
//! ([`TerrainTarget`]), the selected one, and the edits made on a terrain through the editor
//! state, each one undo step: its heights or paint becoming files of its own, heightmap
//! import and export, a paint stroke's starting layer, clearing the paint. What they change
//! ([`HeightChange`], [`PaintChange`]) and the files they write are [`crate::terrain`]'s and
//! [`crate::paint`]'s, which know nothing of the editor state.

use std::path::Path;
use std::sync::Arc;

use texel_scene::EntityRow;
use texel_scene::terrain::{HeightSource, Heightfield, PaintLayer, Terrain};
use texel_scene::texture::Image;

use crate::command::{Command, CommandError};
use crate::paint::{PaintChange, blank_layer, layer_size, paint_file_name};
use crate::state::EditorState;
use crate::terrain::{
    HeightChange, Placement, heightmap_file_name, read_heightmap, write_heightmap,
};

/// A terrain entity of the document and its heights.
#[derive(Debug, Clone)]
pub struct TerrainTarget {
    /// Position in the level order.
    pub index: usize,
    /// Its components.
    pub row: EntityRow,
    /// Its terrain.
    pub terrain: Terrain,
    /// Its heights.
    pub field: Arc<Heightfield>,
    /// Where its heights lie in the world.
    pub place: Placement,
}

/// The terrain of the entity at `index`, when it has one with loaded heights.
pub fn terrain_at(state: &EditorState, index: usize) -> Option<TerrainTarget> {
    let row = state.row_at(index)?;
    let terrain = row.terrain.clone()?;
    let field = state.document.level.assets.heightfield(&terrain)?.clone();
    let origin = row.transform.unwrap_or_default().translation;
    let place = Placement::new(&terrain, origin, &field);
    Some(TerrainTarget {
        index,
        row,
        terrain,
        field,
        place,
    })
}

/// The selected entity's terrain ([`terrain_at`]).
pub fn selected_terrain(state: &EditorState) -> Option<TerrainTarget> {
    terrain_at(state, state.selection?)
}

/// `row` (the entity at `index`) once its terrain's heights are its own: a noise source
/// becomes the heightmap file beside the level they will be saved to
/// ([`heightmap_file_name`]), and so does a file another entity's terrain also names (a
/// duplicate); a file source of its own is kept.
pub fn file_backed(state: &EditorState, index: usize, row: &EntityRow) -> EntityRow {
    let mut row = row.clone();
    let shared = |path: &str| {
        let scene = state.scene();
        scene.entities().enumerate().any(|(i, e)| {
            i != index
                && scene.world().get::<&Terrain>(e).is_ok_and(
                    |t| matches!(&t.heightmap, HeightSource::File { path: p } if p == path),
                )
        })
    };
    let fresh = row.terrain.as_ref().is_some_and(|t| match &t.heightmap {
        HeightSource::Noise { .. } => true,
        HeightSource::File { path } => shared(path),
    });
    if fresh {
        let name = heightmap_file_name(
            &state.document.level.path,
            row.name.as_ref().map(|n| n.0.as_str()),
            index,
            |n| state.document.heightmap_taken(n),
        );
        if let Some(t) = &mut row.terrain {
            t.heightmap = HeightSource::File { path: name };
        }
    }
    row
}

/// Replaces the heights of the terrain at `index` with the 16-bit heightmap `file`, as one
/// undo step (the grid takes the file's size; a noise source becomes a file beside the
/// level). A file that is not a 16-bit greyscale PNG of 2..=4097 samples per edge is
/// refused with the reason, and nothing changes.
pub fn import_heightmap(state: &mut EditorState, index: usize, file: &Path) -> Result<(), String> {
    let target = terrain_at(state, index)
        .ok_or_else(|| format!("entity {index} has no terrain with loaded heights"))?;
    let field = read_heightmap(file, target.terrain.max_height)?;
    let after = file_backed(state, index, &target.row);
    let change = HeightChange::Field {
        before: target.field.clone(),
        after: Arc::new(field),
    };
    let cmd = Command::SetHeights {
        index,
        before: Box::new(target.row),
        after: Box::new(after),
        change: Arc::new(change),
    };
    state.apply(cmd, None).map_err(|e| e.to_string())?;
    state.history.seal();
    Ok(())
}

/// Writes the heights of the terrain at `index` to `file` as a 16-bit greyscale PNG
/// (0..=65535 for 0..=max height).
pub fn export_heightmap(state: &EditorState, index: usize, file: &Path) -> Result<(), String> {
    let target = terrain_at(state, index)
        .ok_or_else(|| format!("entity {index} has no terrain with loaded heights"))?;
    write_heightmap(file, &target.field, target.terrain.max_height)
}

/// `row` (the entity at `index`, a terrain) once it has a paint layer of its own: a terrain
/// without one, or naming a file another terrain also names (a duplicate), gets a new file
/// beside the level ([`paint_file_name`]); its own file is kept.
pub fn paint_backed(state: &EditorState, index: usize, row: &EntityRow) -> EntityRow {
    let mut row = row.clone();
    let shared = |path: &str| {
        let scene = state.scene();
        scene.entities().enumerate().any(|(i, e)| {
            i != index
                && scene
                    .world()
                    .get::<&Terrain>(e)
                    .is_ok_and(|t| t.paint.as_ref().is_some_and(|p| p.path == path))
        })
    };
    let Some(t) = &mut row.terrain else {
        return row;
    };
    if t.paint.as_ref().is_none_or(|p| shared(&p.path)) {
        let path = paint_file_name(
            &state.document.level.path,
            row.name.as_ref().map(|n| n.0.as_str()),
            index,
            |n| state.document.heightmap_taken(n),
        );
        t.paint = Some(PaintLayer { path });
    }
    row
}

/// The paint layer `terrain` starts a stroke from: its own (loaded), or a blank one the size
/// [`layer_size`] gives for `field`. `None` when it names a layer that is not loaded.
pub fn stroke_start(
    state: &EditorState,
    terrain: &Terrain,
    field: &Heightfield,
) -> Option<Arc<Image>> {
    match &terrain.paint {
        Some(_) => state.document.level.assets.paint(terrain).cloned(),
        None => {
            let (w, h) = layer_size(field);
            Some(Arc::new(blank_layer("paint", w, h)))
        }
    }
}

/// Removes the paint layer of the terrain at `index` as one undo step (undo brings the
/// layer back as it was); `after` is the entity's row without it. Nothing happens when the
/// terrain has no layer.
pub fn clear_paint(
    state: &mut EditorState,
    index: usize,
    after: EntityRow,
) -> Result<(), CommandError> {
    let before = state
        .row_at(index)
        .ok_or_else(|| CommandError(format!("no entity at position {index}")))?;
    let Some(t) = &before.terrain else {
        return Ok(());
    };
    let Some(image) = state.document.level.assets.paint(t).cloned() else {
        return Ok(());
    };
    let cmd = Command::SetPaint {
        index,
        before: Box::new(before),
        after: Box::new(after),
        change: Arc::new(PaintChange::Layer {
            before: Some(image),
            after: None,
        }),
    };
    state.apply(cmd, None)?;
    state.history.seal();
    Ok(())
}
