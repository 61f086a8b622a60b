//! The scene hierarchy: every entity with its kind icon and name, as a tree of parents and
//! children ([`crate::groups`]) whose parents fold (`-`, `+`); select (Ctrl-click toggles,
//! Shift-click selects a range), rename, duplicate, delete; drag a row onto another to make
//! it its child, onto the space below the rows to take it out of its parent; a filter by
//! name and by component (a child that passes shows with its ancestors); each row's hide
//! (H) and lock (L) toggles ([`crate::visibility`]).

use egui::Ui;
use texel_scene::{EntityRow, Name};

use crate::command::CommandError;
use crate::selection::Pick;
use crate::state::EditorState;
use crate::ui::widgets::{display_name, kind_icon};

/// Which rows the outliner shows: those whose name holds `text` (any case) and that have
/// the component `kind` names.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OutlinerFilter {
    /// Part of the name, any case (empty: every name).
    pub text: String,
    /// The component asked for.
    pub kind: KindFilter,
    /// The parents folded (their children not shown), by entity (`hecs::Entity::to_bits`).
    pub folded: std::collections::BTreeSet<u64>,
}

/// The component filter of the outliner.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum KindFilter {
    /// Every entity.
    #[default]
    Any,
    /// A shape (geometry).
    Geometry,
    /// A sun or a point light.
    Light,
    /// A sprite.
    Sprite,
    /// A terrain.
    Terrain,
    /// A probe-grid override.
    ProbeOverride,
    /// An animator.
    Animated,
}

impl KindFilter {
    /// Every choice, in the combo's order.
    pub const ALL: [KindFilter; 7] = [
        KindFilter::Any,
        KindFilter::Geometry,
        KindFilter::Light,
        KindFilter::Sprite,
        KindFilter::Terrain,
        KindFilter::ProbeOverride,
        KindFilter::Animated,
    ];

    /// Its name in the combo.
    pub fn label(self) -> &'static str {
        match self {
            KindFilter::Any => "any",
            KindFilter::Geometry => "geometry",
            KindFilter::Light => "light",
            KindFilter::Sprite => "sprite",
            KindFilter::Terrain => "terrain",
            KindFilter::ProbeOverride => "probe override",
            KindFilter::Animated => "animated",
        }
    }

    /// Whether `row` has the component.
    pub fn matches(self, row: &EntityRow) -> bool {
        match self {
            KindFilter::Any => true,
            KindFilter::Geometry => row.geometry.is_some(),
            KindFilter::Light => row.directional_light.is_some() || row.point_light.is_some(),
            KindFilter::Sprite => row.sprite.is_some(),
            KindFilter::Terrain => row.terrain.is_some(),
            KindFilter::ProbeOverride => row.probe_grid_override.is_some(),
            KindFilter::Animated => row.animator.is_some(),
        }
    }
}

impl OutlinerFilter {
    /// Whether the row shown as `name` passes.
    pub fn passes(&self, name: &str, row: &EntityRow) -> bool {
        let text = self.text.trim().to_lowercase();
        self.kind.matches(row) && (text.is_empty() || name.to_lowercase().contains(&text))
    }

    /// The search box and the component combo.
    fn ui(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.text)
                    .hint_text("filter by name")
                    .desired_width(120.0),
            )
            .accessible_name("Filter by name");
            egui::ComboBox::from_id_salt("outliner kind")
                .selected_text(self.kind.label())
                .show_ui(ui, |ui| {
                    for k in KindFilter::ALL {
                        ui.selectable_value(&mut self.kind, k, k.label());
                    }
                })
                .response
                .accessible_name("Component filter");
        });
    }
}

/// The hide toggle's label (the default fonts have no eye nor padlock): highlighted while
/// the entity is hidden.
pub const HIDE: &str = "H";
/// The lock toggle's label, highlighted while the entity is locked.
pub const LOCK: &str = "L";

/// What a row dragged in the outliner carries: its position.
#[derive(Debug, Clone, Copy)]
struct DragRow(usize);

/// One line of the outliner: an entity, how deep in the tree, whether it has children.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Line {
    /// Position in the level order.
    pub index: usize,
    /// How many ancestors it has.
    pub depth: usize,
    /// Whether it has children (it gets a fold toggle).
    pub parent: bool,
}

/// The lines the outliner shows, in tree order (each parent followed by its children, in
/// level order): with a filter, the rows that pass and their ancestors, unfolded; without,
/// every row but those inside a folded parent.
pub fn lines(state: &EditorState, filter: &OutlinerFilter, rows: &[EntityRow]) -> Vec<Line> {
    let scene = state.scene();
    let ents: Vec<hecs::Entity> = scene.entities().collect();
    let at: std::collections::HashMap<hecs::Entity, usize> =
        ents.iter().enumerate().map(|(i, e)| (*e, i)).collect();
    let parent: Vec<Option<usize>> = ents
        .iter()
        .map(|&e| scene.parent(e).and_then(|p| at.get(&p).copied()))
        .collect();
    let mut kids: Vec<Vec<usize>> = vec![Vec::new(); rows.len()];
    for (i, p) in parent.iter().enumerate() {
        if let Some(p) = *p {
            kids[p].push(i);
        }
    }
    let filtering = !filter.text.trim().is_empty() || filter.kind != KindFilter::Any;
    let mut shown = vec![!filtering; rows.len()];
    if filtering {
        for (i, row) in rows.iter().enumerate() {
            if filter.passes(&display_name(row, i), row) {
                let mut at = Some(i);
                while let Some(a) = at.filter(|&a| !shown[a]) {
                    shown[a] = true;
                    at = parent[a];
                }
            }
        }
    }
    let mut out = Vec::new();
    let mut stack: Vec<(usize, usize)> = (0..rows.len())
        .rev()
        .filter(|&i| parent[i].is_none())
        .map(|i| (i, 0))
        .collect();
    while let Some((i, depth)) = stack.pop() {
        if !shown[i] {
            continue;
        }
        out.push(Line {
            index: i,
            depth,
            parent: !kids[i].is_empty(),
        });
        let folded = !filtering && filter.folded.contains(&ents[i].to_bits().get());
        if !folded {
            stack.extend(kids[i].iter().rev().map(|&k| (k, depth + 1)));
        }
    }
    out
}

/// Draws the tree. `rename` holds the entity being renamed and its edited name; `filter`
/// which rows show and which parents are folded. A row dragged onto another becomes its
/// child, onto the space below the rows a root ([`EditorState::reparent`]). A command that
/// fails is returned, for the caller to show.
pub fn show(
    ui: &mut Ui,
    state: &mut EditorState,
    rename: &mut Option<(usize, String)>,
    filter: &mut OutlinerFilter,
) -> Result<(), CommandError> {
    ui.heading("Scene");
    filter.ui(ui);
    let rows: Vec<_> = {
        let scene = state.scene();
        scene.entities().filter_map(|e| scene.row(e)).collect()
    };
    let flags = state.hidden_and_locked();
    let lines = lines(state, filter, &rows);
    let mut action: Option<Action> = None;
    egui::ScrollArea::vertical().show(ui, |ui| {
        for line in &lines {
            let i = line.index;
            let row = &rows[i];
            let name = display_name(row, i);
            let (hidden, locked) = flags.get(i).copied().unwrap_or_default();
            if let Some((ri, text)) = rename.as_mut()
                && *ri == i
            {
                let r = ui.text_edit_singleline(text).accessible_name("Rename");
                r.request_focus();
                if r.lost_focus() {
                    action = Some(Action::Rename(i, text.clone()));
                }
                continue;
            }
            let selected = state.is_selected(i);
            let mut text = egui::RichText::new(format!("{} {}", kind_icon(row), name));
            if state.selection == Some(i) && !state.also_selected.is_empty() {
                // The active one of several: the inspector shows its components.
                text = text.strong().underline();
            }
            if hidden {
                text = text.weak().italics();
            }
            let r = ui
                .horizontal(|ui| {
                    let eye = ui
                        .selectable_label(hidden, HIDE)
                        .accessible_name(format!("Hide {name}"))
                        .on_hover_text("Hide: not drawn in the viewport (still saved)");
                    if eye.clicked() {
                        action = Some(Action::Hide(i, !hidden));
                    }
                    let lock = ui
                        .selectable_label(locked, LOCK)
                        .accessible_name(format!("Lock {name}"))
                        .on_hover_text("Lock: not picked nor moved in the viewport");
                    if lock.clicked() {
                        action = Some(Action::Lock(i, !locked));
                    }
                    ui.add_space(line.depth as f32 * 12.0);
                    if line.parent {
                        let folded = filter.folded.contains(&entity_bits(state, i));
                        let (mark, verb) = if folded {
                            ("+", "Unfold")
                        } else {
                            ("-", "Fold")
                        };
                        if ui
                            .small_button(mark)
                            .accessible_name(format!("{verb} {name}"))
                            .clicked()
                        {
                            action = Some(Action::Fold(i, !folded));
                        }
                    } else {
                        ui.add_space(18.0);
                    }
                    ui.selectable_label(selected, text)
                        .interact(egui::Sense::drag())
                })
                .inner;
            r.dnd_set_drag_payload(DragRow(i));
            if let Some(dragged) = r.dnd_hover_payload::<DragRow>()
                && dragged.0 != i
            {
                let stroke = ui.visuals().selection.stroke;
                ui.painter()
                    .rect_stroke(r.rect, 2.0, stroke, egui::StrokeKind::Outside);
            }
            if let Some(dragged) = r.dnd_release_payload::<DragRow>()
                && dragged.0 != i
            {
                action = Some(Action::Reparent(dragged.0, Some(i)));
            }
            if r.clicked() {
                let how = Pick::from_modifiers(ui.input(|inp| inp.modifiers), Pick::Range);
                action = Some(Action::Select(i, how));
            }
            if r.double_clicked() {
                *rename = Some((i, name.clone()));
            }
            r.context_menu(|ui| {
                if ui.button("Rename").clicked() {
                    *rename = Some((i, name.clone()));
                }
                if ui.button("Duplicate").clicked() {
                    action = Some(Action::Duplicate(i));
                }
                if ui.button("Delete").clicked() {
                    action = Some(Action::Delete(i));
                }
            });
        }
        // Below the rows: a drop there takes the row out of its parent.
        let size = egui::vec2(ui.available_width(), ui.available_height().max(24.0));
        let rest = ui.allocate_response(size, egui::Sense::hover());
        if let Some(dragged) = rest.dnd_release_payload::<DragRow>() {
            action = Some(Action::Reparent(dragged.0, None));
        }
    });
    act(state, action, rename, filter)
}

fn entity_bits(state: &EditorState, index: usize) -> u64 {
    crate::command::entity_at(state.scene(), index).map_or(0, |e| e.to_bits().get())
}

/// Carries out what the outliner was asked this frame.
fn act(
    state: &mut EditorState,
    action: Option<Action>,
    rename: &mut Option<(usize, String)>,
    filter: &mut OutlinerFilter,
) -> Result<(), CommandError> {
    match action {
        Some(Action::Select(i, how)) => state.pick(Some(i), how),
        Some(Action::Hide(i, on)) => state.set_hidden(i, on),
        Some(Action::Lock(i, on)) => state.set_locked(i, on),
        Some(Action::Fold(i, fold)) => {
            let bits = entity_bits(state, i);
            if fold {
                filter.folded.insert(bits);
            } else {
                filter.folded.remove(&bits);
            }
        }
        // A selected row drags the whole selection along.
        Some(Action::Reparent(i, to)) if state.is_selected(i) => {
            // Onto a row of the selection: the others go into it.
            let mut moved = state.selected();
            moved.retain(|&m| Some(m) != to);
            state.reparent(&moved, to)?
        }
        Some(Action::Reparent(i, to)) => state.reparent(&[i], to)?,
        // On a selected row: the whole selection.
        Some(Action::Duplicate(i)) if state.is_selected(i) => state.duplicate_selection()?,
        Some(Action::Delete(i)) if state.is_selected(i) => state.delete_selection()?,
        Some(Action::Duplicate(i)) => state.duplicate(i)?,
        Some(Action::Delete(i)) => state.delete(i)?,
        Some(Action::Rename(i, text)) => {
            *rename = None;
            if let Some(mut row) = state.row_at(i) {
                row.name = (!text.trim().is_empty()).then(|| Name(text.trim().to_owned()));
                state.set_row(i, row, None)?;
            }
        }
        None => {}
    }
    Ok(())
}

enum Action {
    Select(usize, Pick),
    Fold(usize, bool),
    Reparent(usize, Option<usize>),
    Duplicate(usize),
    Delete(usize),
    Rename(usize, String),
    Hide(usize, bool),
    Lock(usize, bool),
}
