//! The inspector: every component of the selected entity, and the level settings. Edits are
//! made on a copy of the entity's row and applied as one command per gesture.

use std::sync::Arc;

use egui::Ui;
use glam::{Vec2, Vec3};
use texel_scene::assets::AssetLibrary;
use texel_scene::terrain::{
    Displacement, GradientStop, HeightSource, MAX_GRADIENT_STOPS, MAX_HEIGHTMAP, Terrain,
};
use texel_scene::{
    BANDS, DirectionalLight, EntityRow, FACE_RESOLUTIONS, Geometry, LevelSettings, Material, Name,
    PixelScale, PlayerStart, PointLight, ProbeGridOverride, SEGMENTS, Sampling, TextureMap,
    Transform,
};

use crate::command::{Command, CommandError};
use crate::history::MergeKey;
use crate::state::EditorState;
use crate::ui::multi_edit::{self, Mixed};
use crate::ui::sprite_section::SpritePanel;
use crate::ui::widgets::{BIG, MIN_SIZE, colour, integer, scalar, vec2, vec3, vec3_mixed};

/// The selected entity's components (`sprites`: the sprite section's state between frames).
/// A command that fails is returned, for the caller to show.
pub fn entity(
    ui: &mut Ui,
    state: &mut EditorState,
    sprites: &mut SpritePanel,
) -> Result<(), CommandError> {
    let Some((index, before)) = state.selected_row() else {
        ui.label("Nothing selected");
        return Ok(());
    };
    let others: Vec<(usize, EntityRow)> = (state.selected_rows().into_iter())
        .filter(|(i, _)| *i != index)
        .collect();
    let mixed = mixed_fields(ui, state, &before, &others);
    let mut row = before.clone();
    let terrain = TerrainInfo::of(state, index, &before);
    let sprite = SpriteContext {
        index,
        assets: &state.document.level.assets,
        panel: sprites,
    };
    edit_row(ui, &mut row, &terrain, sprite, &mixed);
    crate::ui::sprite_section::keep_row_valid(ui.ctx(), &before, &mut row, sprites);
    if before.animator.is_none()
        && row.animator.is_some()
        && let Some(why) = state.why_no_animator(index)
    {
        return Err(CommandError(format!("no animator here: {why}")));
    }
    let cleared = |r: &EntityRow| r.terrain.as_ref().is_some_and(|t| t.paint.is_none());
    let painted = |r: &EntityRow| r.terrain.as_ref().is_some_and(|t| t.paint.is_some());
    if painted(&before) && cleared(&row) {
        // "Clear paint": the layer goes with the undo step, so undo brings it back.
        crate::terrain_edits::clear_paint(state, index, row)?;
    } else if row != before {
        let key = gesture_widget(ui.ctx()).map(|widget| MergeKey::Row { index, widget });
        if others.is_empty() {
            state.set_row(index, row, key)?;
        } else {
            // The same change on every selected entity that has the field, one step.
            let mut rows = multi_edit::spread(&before, &row, others);
            rows.push((index, row));
            rows.sort_by_key(|r| r.0);
            state.set_rows(rows, key)?;
        }
    }
    Ok(())
}

/// The fields that differ across the selection (none for one entity), said above the
/// fields; kept between frames for the document revision and selection they were found for.
fn mixed_fields(
    ui: &mut Ui,
    state: &EditorState,
    active: &EntityRow,
    others: &[(usize, EntityRow)],
) -> Arc<Mixed> {
    if others.is_empty() {
        return Arc::default();
    }
    let name = active
        .name
        .as_ref()
        .map_or("the active entity's", |n| n.0.as_str());
    ui.label(format!(
        "{} entities selected: an edit applies to all that have the field; \
         \u{2014} marks a value that differs. Other values shown: {name}.",
        others.len() + 1
    ));
    let key = (
        state.document.id(),
        state.document.revision,
        state.selected(),
    );
    let id = egui::Id::unique("inspector mixed fields");
    let cached = ui.data(|d| d.get_temp::<(MixedKey, Arc<Mixed>)>(id));
    if let Some((k, m)) = cached
        && k == key
    {
        return m;
    }
    let mut rows = vec![active.clone()];
    rows.extend(others.iter().map(|(_, r)| r.clone()));
    let m = Arc::new(Mixed::of(&rows));
    ui.data_mut(|d| d.insert_temp(id, (key, m.clone())));
    m
}

type MixedKey = (u64, u64, Vec<usize>);

/// What the terrain section shows beside the component: the file a noise source switched to
/// File starts with, the size of the loaded heights and of the paint layer.
struct TerrainInfo {
    file_name: String,
    samples: Option<(u32, u32)>,
    paint: Option<(u32, u32)>,
}

impl TerrainInfo {
    fn of(state: &EditorState, index: usize, row: &EntityRow) -> Self {
        let Some(t) = &row.terrain else {
            return TerrainInfo {
                file_name: String::new(),
                samples: None,
                paint: None,
            };
        };
        let file_name = match &crate::terrain_edits::file_backed(state, index, row).terrain {
            Some(Terrain {
                heightmap: HeightSource::File { path },
                ..
            }) => path.clone(),
            _ => String::new(),
        };
        let assets = &state.document.level.assets;
        let samples = assets.heightfield(t).map(|f| (f.width, f.depth));
        let paint = assets.paint(t).map(|p| (p.width, p.height));
        TerrainInfo {
            file_name,
            samples,
            paint,
        }
    }
}

/// What the sprite section needs beside the row: the entity's position, the loaded sheets
/// and its own state.
struct SpriteContext<'a> {
    index: usize,
    assets: &'a AssetLibrary,
    panel: &'a mut SpritePanel,
}

fn edit_row(
    ui: &mut Ui,
    row: &mut EntityRow,
    info: &TerrainInfo,
    sprite: SpriteContext<'_>,
    mixed: &Mixed,
) {
    // A name that differs shows empty, "—" greyed in it; typing names them all.
    let mixed_name = mixed.has("name");
    let mut name = match &row.name {
        Some(n) if !mixed_name => n.0.clone(),
        _ => String::new(),
    };
    ui.horizontal(|ui| {
        ui.label("Name");
        let edit = egui::TextEdit::singleline(&mut name).hint_text(if mixed_name {
            "\u{2014}"
        } else {
            ""
        });
        if ui.add(edit).accessible_name("Name").changed() {
            row.name = (!name.is_empty()).then(|| Name(name.clone()));
        }
    });
    // The parent is changed in the hierarchy (drag a row); here it is only shown.
    match (&row.parent, mixed.has("parent")) {
        (_, true) => drop(ui.weak("In group: \u{2014}")),
        (Some(p), false) => drop(ui.label(format!("In group: {} (transform in the world)", p.0))),
        (None, false) => {}
    }
    let title = |t: &str, key: &str| format!("{t}{}", mixed.note(key));
    section_with(
        ui,
        &title("Transform", "transform"),
        &mut row.transform,
        Transform::default,
        |ui, t| transform(ui, t, mixed),
    );
    // A terrain lies along the world's axes: say so where its rotation or scale is set.
    let unapplied = (row.terrain.as_ref().and(row.transform.as_ref()))
        .and_then(texel_scene::terrain::unapplied_transform);
    if let Some(message) = unapplied {
        ui.colored_label(ui.visuals().warn_fg_color, format!("Terrain: {message}."));
    }
    crate::ui::sprite_section::section(ui, sprite.index, row, sprite.assets, sprite.panel);
    section_with(
        ui,
        &title("Geometry", "geometry"),
        &mut row.geometry,
        || geometry_of_kind(0),
        geometry,
    );
    section(
        ui,
        &title("Material", "material"),
        &mut row.material,
        material,
    );
    let sun_title = title("Directional light", "directional_light");
    section(ui, &sun_title, &mut row.directional_light, sun);
    section(
        ui,
        &title("Point light", "point_light"),
        &mut row.point_light,
        point,
    );
    section(
        ui,
        &title("Probe-grid override", "probe_grid_override"),
        &mut row.probe_grid_override,
        probe,
    );
    section(
        ui,
        &title("Player start", "player_start"),
        &mut row.player_start,
        start,
    );
    section_with(
        ui,
        &title("Terrain", "terrain"),
        &mut row.terrain,
        crate::terrain::default_terrain,
        |ui, t| terrain(ui, t, info),
    );
    crate::ui::animator::section(ui, row);
}

/// A collapsible component with a remove button, or an add button when absent.
fn section<T: Default>(ui: &mut Ui, title: &str, c: &mut Option<T>, body: fn(&mut Ui, &mut T)) {
    section_with(ui, title, c, T::default, body);
}

fn section_with<T>(
    ui: &mut Ui,
    title: &str,
    c: &mut Option<T>,
    make: fn() -> T,
    body: impl FnOnce(&mut Ui, &mut T),
) {
    // A title may carry a note on the selection's values after " (": the header keeps its
    // place (and its open state) by the plain name.
    let name = title.split(" (").next().unwrap_or(title);
    match c {
        Some(v) => {
            let mut remove = false;
            egui::CollapsingHeader::new(title)
                .id_salt(name)
                .default_open(true)
                .show(ui, |ui| {
                    body(ui, v);
                    remove = ui.small_button(format!("Remove {name}")).clicked();
                });
            if remove {
                *c = None;
            }
        }
        None => {
            if ui.small_button(format!("Add {name}")).clicked() {
                *c = Some(make());
            }
        }
    }
}

fn transform(ui: &mut Ui, t: &mut Transform, mixed: &Mixed) {
    let axes = |field: &str| [0, 1, 2].map(|k| mixed.has(&format!("transform/{field}/{k}")));
    vec3_mixed(
        ui,
        "Translation",
        &mut t.translation,
        0.05,
        -BIG,
        axes("translation"),
    );
    vec3_mixed(ui, "Rotation", &mut t.rotation, 1.0, -BIG, axes("rotation"));
    vec3_mixed(ui, "Scale", &mut t.scale, 0.01, MIN_SIZE, axes("scale"));
}

const KINDS: [&str; 6] = ["Box", "Sphere", "Cylinder", "Plane", "Wedge", "Mesh"];

fn kind_of(g: &Geometry) -> usize {
    match g {
        Geometry::Box { .. } => 0,
        Geometry::Sphere { .. } => 1,
        Geometry::Cylinder { .. } => 2,
        Geometry::Plane { .. } => 3,
        Geometry::Wedge { .. } => 4,
        Geometry::Mesh { .. } => 5,
    }
}

/// A default geometry of kind `k` (an index into the kinds list).
pub fn geometry_of_kind(k: usize) -> Geometry {
    match k {
        1 => Geometry::Sphere {
            radius: 0.5,
            segments: 16,
        },
        2 => Geometry::Cylinder {
            radius: 0.5,
            height: 1.0,
            segments: 16,
        },
        3 => Geometry::Plane {
            size: Vec2::splat(4.0),
        },
        4 => Geometry::Wedge { size: Vec3::ONE },
        5 => Geometry::Mesh {
            path: String::new(),
        },
        _ => Geometry::Box { size: Vec3::ONE },
    }
}

fn geometry(ui: &mut Ui, g: &mut Geometry) {
    let mut k = kind_of(g);
    egui::ComboBox::from_label("Kind")
        .selected_text(KINDS[k])
        .show_ui(ui, |ui| {
            for (i, name) in KINDS.iter().enumerate() {
                ui.selectable_value(&mut k, i, *name);
            }
        });
    if k != kind_of(g) {
        *g = geometry_of_kind(k);
    }
    match g {
        Geometry::Box { size } | Geometry::Wedge { size } => {
            vec3(ui, "Size", size, 0.02, MIN_SIZE);
        }
        Geometry::Sphere { radius, segments } => {
            scalar(ui, "Radius", radius, 0.01, MIN_SIZE, BIG);
            integer(ui, "Segments", segments, SEGMENTS);
        }
        Geometry::Cylinder {
            radius,
            height,
            segments,
        } => {
            scalar(ui, "Radius", radius, 0.01, MIN_SIZE, BIG);
            scalar(ui, "Height", height, 0.02, MIN_SIZE, BIG);
            integer(ui, "Segments", segments, SEGMENTS);
        }
        Geometry::Plane { size } => {
            vec2(ui, "Size", size, 0.05, MIN_SIZE);
        }
        Geometry::Mesh { path } => {
            ui.horizontal(|ui| {
                ui.label("Path");
                ui.text_edit_singleline(path).accessible_name("Mesh path");
            });
        }
    }
}

fn material(ui: &mut Ui, m: &mut Material) {
    colour(ui, "Albedo", &mut m.albedo);
    colour(ui, "Emissive", &mut m.emissive);
    ui.checkbox(&mut m.casts_shadows, "Casts shadows");
    ui.checkbox(&mut m.outlined, "Outlined");
    let mut textured = m.texture.is_some();
    ui.checkbox(&mut textured, "Texture");
    match (textured, &m.texture) {
        (true, None) => m.texture = Some(TextureMap::new("")),
        (false, Some(_)) => m.texture = None,
        _ => {}
    }
    if let Some(t) = &mut m.texture {
        ui.indent("texture", |ui| texture(ui, t));
    }
    let mut normals = m.normal_map.is_some();
    ui.checkbox(&mut normals, "Normal map");
    match (normals, &m.normal_map) {
        (true, None) => m.normal_map = Some(String::new()),
        (false, Some(_)) => m.normal_map = None,
        _ => {}
    }
    if let Some(p) = &mut m.normal_map {
        ui.indent("normal map", |ui| path_field(ui, "Normal map path", p));
    }
}

/// A texture's file, filtering, density and UV scale.
fn texture(ui: &mut Ui, t: &mut TextureMap) {
    path_field(ui, "Texture path", &mut t.path);
    ui.horizontal(|ui| {
        ui.label("Sampling");
        ui.radio_value(&mut t.sampling, Sampling::Nearest, "Nearest");
        ui.radio_value(&mut t.sampling, Sampling::Linear, "Linear");
    });
    ui.horizontal(|ui| {
        ui.label("Density");
        ui.add(
            egui::DragValue::new(&mut t.density)
                .speed(0.1)
                .range(0.01..=BIG)
                .suffix(" px/unit"),
        )
        .on_hover_text(
            "Texture pixels per world unit on primitives (glTF meshes bring their own UVs)",
        )
        .accessible_name("Density");
    });
    ui.horizontal(|ui| {
        ui.label("UV scale");
        for (axis, c) in ["U", "V"]
            .iter()
            .zip([&mut t.uv_scale.x, &mut t.uv_scale.y])
        {
            ui.add(egui::DragValue::new(c).speed(0.01).range(MIN_SIZE..=BIG))
                .accessible_name(format!("UV scale {axis}"));
        }
    });
}

/// A file path relative to the level, typed (loaded once typing stops).
fn path_field(ui: &mut Ui, name: &str, path: &mut String) {
    ui.horizontal(|ui| {
        ui.label("Path");
        ui.add(
            egui::TextEdit::singleline(path)
                .hint_text("relative to the level, e.g. ../textures/a.png"),
        )
        .accessible_name(name);
    });
}

/// Every field of a terrain. Switching the heights to File keeps them (saved to
/// `info.file_name` beside the level); switching to Noise bakes noise.
fn terrain(ui: &mut Ui, t: &mut Terrain, info: &TerrainInfo) {
    vec2(ui, "Terrain size", &mut t.size, 0.5, MIN_SIZE);
    scalar(ui, "Max height", &mut t.max_height, 0.05, MIN_SIZE, BIG);
    let mut file = matches!(t.heightmap, HeightSource::File { .. });
    ui.horizontal(|ui| {
        ui.label("Heights");
        ui.radio_value(&mut file, false, "Noise")
            .on_hover_text("Fractal noise baked when the level loads");
        ui.radio_value(&mut file, true, "File")
            .on_hover_text("A 16-bit greyscale PNG beside the level (sculpting makes one)");
    });
    match (file, &t.heightmap) {
        (true, HeightSource::Noise { .. }) if !info.file_name.is_empty() => {
            t.heightmap = HeightSource::File {
                path: info.file_name.clone(),
            };
        }
        (false, HeightSource::File { .. }) => {
            t.heightmap = crate::terrain::default_terrain().heightmap;
        }
        _ => {}
    }
    match &mut t.heightmap {
        HeightSource::Noise {
            seed,
            resolution,
            frequency,
            octaves,
            island,
        } => {
            integer(ui, "Seed", seed, 0..=u32::MAX);
            integer(ui, "Resolution", resolution, 2..=MAX_HEIGHTMAP);
            scalar(ui, "Frequency", frequency, 0.001, 1e-4, 100.0);
            integer(ui, "Octaves", octaves, 1..=8);
            scalar(ui, "Island", island, 0.01, 0.0, 1.0);
        }
        HeightSource::File { path } => {
            path_field(ui, "Heightmap path", path);
        }
    }
    if let Some((w, d)) = info.samples {
        ui.label(format!("{w}×{d} height samples"));
    }
    gradient(ui, &mut t.gradient);
    match &t.paint {
        Some(p) => {
            let size = info
                .paint
                .map_or(String::new(), |(w, h)| format!(" ({w}×{h})"));
            ui.label(format!("Paint layer: {}{size}", p.path))
                .on_hover_text("Colour painted over the gradient (the terrain tool's Paint brush)");
            if ui.button("Clear paint").clicked() {
                t.paint = None;
            }
        }
        None => {
            ui.label("No paint layer")
                .on_hover_text("The terrain tool's Paint brush adds one");
        }
    }
    let mut displaced = t.displacement.is_some();
    ui.checkbox(&mut displaced, "Displacement");
    match (displaced, &t.displacement) {
        (true, None) => {
            t.displacement = Some(Displacement {
                path: String::new(),
                strength: 0.2,
                tile_size: 6.0,
            })
        }
        (false, Some(_)) => t.displacement = None,
        _ => {}
    }
    if let Some(d) = &mut t.displacement {
        ui.indent("displacement", |ui| {
            path_field(ui, "Displacement path", &mut d.path);
            scalar(
                ui,
                "Displacement strength",
                &mut d.strength,
                0.005,
                0.0,
                10.0,
            );
            scalar(ui, "Tile size", &mut d.tile_size, 0.05, MIN_SIZE, BIG);
        });
    }
    scalar(
        ui,
        "Pixel density",
        &mut t.pixel_density,
        0.05,
        0.01,
        1000.0,
    );
    scalar(
        ui,
        "Band distance",
        &mut t.band_distance,
        0.1,
        MIN_SIZE,
        BIG,
    );
    scalar(
        ui,
        "Band transition",
        &mut t.band_transition,
        0.01,
        0.0,
        1.0,
    );
    ui.checkbox(&mut t.casts_shadows, "Terrain casts shadows");
    ui.checkbox(&mut t.outlined, "Terrain outlined");
}

/// The elevation gradient: each stop's colour and elevation (kept between its neighbours, so
/// the stops stay in order), removed (one is always left) or followed by a new one.
fn gradient(ui: &mut Ui, stops: &mut Vec<GradientStop>) {
    ui.label("Gradient");
    let n = stops.len();
    let (mut remove, mut insert) = (None, None);
    for i in 0..n {
        let lo = if i > 0 { stops[i - 1].at } else { 0.0 };
        let hi = stops.get(i + 1).map_or(1.0, |s| s.at);
        let s = &mut stops[i];
        ui.horizontal(|ui| {
            let k = i + 1;
            let mut rgb = s.colour.to_array();
            if ui
                .color_edit_button_rgb(&mut rgb)
                .accessible_name(format!("Stop {k} colour"))
                .changed()
            {
                s.colour = Vec3::from_array(rgb).max(Vec3::ZERO);
            }
            ui.add(egui::DragValue::new(&mut s.at).speed(0.005).range(lo..=hi))
                .on_hover_text("Elevation: 0 ground level, 1 the max height")
                .accessible_name(format!("Stop {k} at"));
            let minus = egui::Button::new("−").small();
            if ui
                .add_enabled(n > 1, minus)
                .on_hover_text("Remove this stop")
                .accessible_name(format!("Remove stop {k}"))
                .clicked()
            {
                remove = Some(i);
            }
            let plus = egui::Button::new("+").small();
            if ui
                .add_enabled(n < MAX_GRADIENT_STOPS, plus)
                .on_hover_text("Add a stop after this one")
                .accessible_name(format!("Add stop after {k}"))
                .clicked()
            {
                insert = Some(i);
            }
        });
    }
    if let Some(i) = remove.filter(|_| n > 1) {
        stops.remove(i);
    } else if let Some(i) = insert.filter(|_| n < MAX_GRADIENT_STOPS) {
        let a = stops[i];
        let next = stops.get(i + 1).map_or(1.0, |s| s.at);
        stops.insert(
            i + 1,
            GradientStop {
                at: 0.5 * (a.at + next),
                colour: a.colour,
            },
        );
    }
}

fn sun(ui: &mut Ui, s: &mut DirectionalLight) {
    let mut d = s.direction;
    if vec3(ui, "Direction", &mut d, 0.01, -BIG) && d.length_squared() > 1e-6 {
        s.direction = d;
    }
    colour(ui, "Colour", &mut s.colour);
    scalar(ui, "Intensity", &mut s.intensity, 0.01, 0.0, 1000.0);
}

fn point(ui: &mut Ui, p: &mut PointLight) {
    colour(ui, "Colour", &mut p.colour);
    scalar(ui, "Intensity", &mut p.intensity, 0.01, 0.0, 1000.0);
    scalar(ui, "Radius", &mut p.radius, 0.05, MIN_SIZE, BIG);
}

fn probe(ui: &mut Ui, o: &mut ProbeGridOverride) {
    vec3(ui, "Volume", &mut o.size, 0.05, MIN_SIZE);
    scalar(ui, "Cell size", &mut o.cell_size, 0.01, 0.01, BIG);
    let mut own = o.face_resolution.is_some();
    ui.checkbox(&mut own, "Own face resolution");
    match (own, o.face_resolution) {
        (true, None) => o.face_resolution = Some(128),
        (false, Some(_)) => o.face_resolution = None,
        _ => {}
    }
    if let Some(n) = &mut o.face_resolution {
        integer(ui, "Face resolution", n, FACE_RESOLUTIONS);
    }
    ui.horizontal(|ui| {
        ui.label("Priority");
        ui.add(egui::DragValue::new(&mut o.priority))
            .accessible_name("Priority");
    });
}

fn start(ui: &mut Ui, p: &mut PlayerStart) {
    scalar(ui, "Yaw", &mut p.yaw, 1.0, -360.0, 360.0);
    scalar(ui, "Pitch", &mut p.pitch, 1.0, -89.0, 89.0);
    scalar(ui, "Eye height", &mut p.eye_height, 0.01, 0.01, 100.0);
}

/// The level settings. A command that fails is returned, for the caller to show.
pub fn settings(ui: &mut Ui, state: &mut EditorState) -> Result<(), CommandError> {
    let before: LevelSettings = state.scene().settings;
    let mut s = before;
    colour(ui, "Sky", &mut s.sky);
    colour(ui, "Ambient", &mut s.ambient);
    integer(ui, "Bands", &mut s.bands, BANDS);
    let mut fixed = matches!(s.pixel_scale, PixelScale::FaceResolution(_));
    ui.horizontal(|ui| {
        ui.radio_value(&mut fixed, false, "Pixel size");
        ui.radio_value(&mut fixed, true, "Face resolution");
    });
    s.pixel_scale = match (fixed, s.pixel_scale) {
        (true, PixelScale::PixelSize(_)) => PixelScale::FaceResolution(128),
        (false, PixelScale::FaceResolution(_)) => PixelScale::PixelSize(2.5),
        (_, p) => p,
    };
    match &mut s.pixel_scale {
        PixelScale::PixelSize(k) => {
            scalar(ui, "Pixel size", k, 0.05, 0.1, 64.0);
        }
        PixelScale::FaceResolution(n) => {
            integer(ui, "Face resolution", n, FACE_RESOLUTIONS);
        }
    }
    scalar(ui, "Default cell size", &mut s.cell_size, 0.01, 0.01, BIG);
    scalar(
        ui,
        "Reference distance",
        &mut s.reference_distance,
        0.05,
        0.01,
        BIG,
    );
    if s != before {
        let key = gesture_widget(ui.ctx()).map(|widget| MergeKey::Settings { widget });
        state.apply(Command::SetSettings { before, after: s }, key)?;
    }
    Ok(())
}

/// The widget of a continuing gesture (the one being dragged or typed into), for the merge
/// key that makes a drag or typing one undo step; `None` for one-shot changes.
pub fn gesture_widget(ctx: &egui::Context) -> Option<egui::Id> {
    ctx.dragged_id().or_else(|| ctx.memory(|m| m.focused()))
}
