//! The inspector's animator section: add or remove the selected entity's animator and edit
//! its motion. It edits the inspector's copy of the row, so each gesture is one undo step
//! like any other component's.
//!
//! The editor shows an animated entity at its transform (the animation's rest pose); play
//! mode moves it.

use egui::Ui;
use glam::Vec3;
use texel_scene::animator::{Animator, Easing, MAX_PATH_KEYS, Motion, PathKey};
use texel_scene::level::check_animator_row;
use texel_scene::{EntityRow, Transform, Validate};

use crate::ui::widgets::{BIG, MIN_SIZE, scalar, vec3};

/// The least time between two path keys (and between the last key and the period) the
/// inspector makes; files may hold less.
const MIN_STEP: f32 = 0.01;

/// The animator of `row`, or a button adding one (disabled, saying why, on an entity without
/// a transform or with a terrain). Removing the transform or adding a terrain removes the
/// animator in the same step: a level cannot hold it then.
pub fn section(ui: &mut Ui, row: &mut EntityRow) {
    if row.animator.is_some() && check_animator_row(row).is_err() {
        row.animator = None;
    }
    let base = row.transform.unwrap_or_default();
    let Some(animator) = &mut row.animator else {
        let why = if row.transform.is_none() {
            Some("An animator moves the entity's transform: add a transform first")
        } else if row.terrain.is_some() {
            Some("Terrains do not move")
        } else {
            None
        };
        let button = ui.add_enabled(why.is_none(), egui::Button::new("Add Animator").small());
        let button = match why {
            Some(why) => button.on_disabled_hover_text(why),
            None => button,
        };
        if button.clicked() {
            row.animator = Some(default_animator());
        }
        return;
    };
    let mut remove = false;
    egui::CollapsingHeader::new("Animator")
        .default_open(true)
        .show(ui, |ui| {
            let before = animator.clone();
            edit(ui, animator, &base);
            // A value the level would refuse (a speed dragged through zero, …) is not taken.
            if animator.validate().is_err() {
                *animator = before;
            }
            remove = ui.small_button("Remove Animator").clicked();
        });
    if remove {
        row.animator = None;
    }
}

/// What "Add Animator" makes: a turn about Y at 45° per second.
pub fn default_animator() -> Animator {
    Animator {
        motion: motion_of_kind(0, &Transform::default()),
        phase: 0.0,
    }
}

const KINDS: [&str; 3] = ["Rotate", "Ping-pong", "Path"];

fn kind_of(m: &Motion) -> usize {
    match m {
        Motion::Rotate { .. } => 0,
        Motion::PingPong { .. } => 1,
        Motion::Path { .. } => 2,
    }
}

/// A default motion of kind `k` (an index into [`KINDS`]) for an entity at `base`: a turn,
/// or there and back 2 units along X, or up 1 unit and back.
pub fn motion_of_kind(k: usize, base: &Transform) -> Motion {
    let key = |time, lift: f32| PathKey {
        time,
        translation: base.translation + Vec3::Y * lift,
        rotation: base.rotation,
    };
    match k {
        1 => Motion::PingPong {
            to: Transform {
                translation: base.translation + Vec3::X * 2.0,
                ..*base
            },
            period: 4.0,
            easing: Easing::Smooth,
        },
        2 => Motion::Path {
            keys: vec![key(0.0, 0.0), key(2.0, 1.0)],
            period: 4.0,
        },
        _ => Motion::Rotate {
            axis: Vec3::Y,
            speed: 45.0,
        },
    }
}

fn edit(ui: &mut Ui, a: &mut Animator, base: &Transform) {
    let mut k = kind_of(&a.motion);
    ui.horizontal(|ui| {
        ui.label("Motion");
        for (i, name) in KINDS.iter().enumerate() {
            ui.radio_value(&mut k, i, *name)
                .accessible_name(format!("Motion {name}"));
        }
    });
    if k != kind_of(&a.motion) {
        a.motion = motion_of_kind(k, base);
    }
    match &mut a.motion {
        Motion::Rotate { axis, speed } => {
            vec3(ui, "Axis", axis, 0.01, -BIG);
            scalar(ui, "Speed", speed, 1.0, -BIG, BIG);
            ui.weak("Degrees per second about the axis (world space), through the translation");
        }
        Motion::PingPong { to, period, easing } => {
            ui.label("To (the other end; the transform is the first)");
            vec3(ui, "To translation", &mut to.translation, 0.05, -BIG);
            vec3(ui, "To rotation", &mut to.rotation, 1.0, -BIG);
            vec3(ui, "To scale", &mut to.scale, 0.01, MIN_SIZE);
            if ui
                .small_button("Use the transform")
                .on_hover_text("Set the other end to the entity's transform")
                .clicked()
            {
                *to = *base;
            }
            scalar(ui, "Period", period, 0.05, MIN_STEP, BIG);
            ui.horizontal(|ui| {
                ui.label("Easing");
                ui.radio_value(easing, Easing::Linear, "Linear");
                ui.radio_value(easing, Easing::Smooth, "Smooth");
            });
        }
        Motion::Path { keys, period } => path(ui, keys, period, base),
    }
    scalar(ui, "Phase", &mut a.phase, 0.05, -BIG, BIG);
}

/// The keys of a path (each key's time kept between its neighbours', the first at 0), one
/// removed (two are always left) or one added after another, and the period (past the last
/// key).
fn path(ui: &mut Ui, keys: &mut Vec<PathKey>, period: &mut f32, base: &Transform) {
    let n = keys.len();
    let (mut remove, mut insert) = (None, None);
    for i in 0..n {
        let k = i + 1;
        let lo = if i > 0 {
            keys[i - 1].time + MIN_STEP
        } else {
            0.0
        };
        let hi = keys.get(i + 1).map_or(*period, |next| next.time) - MIN_STEP;
        let key = &mut keys[i];
        ui.horizontal(|ui| {
            ui.label(format!("Key {k} at"));
            if i == 0 || lo > hi {
                ui.label(format!("{} s", key.time));
            } else {
                ui.add(
                    egui::DragValue::new(&mut key.time)
                        .speed(0.05)
                        .range(lo..=hi)
                        .suffix(" s"),
                )
                .accessible_name(format!("Key {k} time"));
            }
            let minus = egui::Button::new("−").small();
            if ui
                .add_enabled(i > 0 && n > 2, minus)
                .on_hover_text("Remove this key")
                .accessible_name(format!("Remove key {k}"))
                .clicked()
            {
                remove = Some(i);
            }
            let plus = egui::Button::new("+").small();
            if ui
                .add_enabled(n < MAX_PATH_KEYS, plus)
                .on_hover_text("Add a key after this one")
                .accessible_name(format!("Add key after {k}"))
                .clicked()
            {
                insert = Some(i);
            }
            if ui
                .small_button("Use transform")
                .on_hover_text("Set this key to the entity's transform")
                .accessible_name(format!("Key {k} from transform"))
                .clicked()
            {
                key.translation = base.translation;
                key.rotation = base.rotation;
            }
        });
        vec3(
            ui,
            &format!("Key {k} translation"),
            &mut key.translation,
            0.05,
            -BIG,
        );
        vec3(
            ui,
            &format!("Key {k} rotation"),
            &mut key.rotation,
            1.0,
            -BIG,
        );
    }
    let last = keys.last().map_or(0.0, |k| k.time);
    scalar(ui, "Period", period, 0.05, last + MIN_STEP, BIG);
    if let Some(i) = remove.filter(|&i| i > 0 && n > 2) {
        keys.remove(i);
    } else if let Some(i) = insert.filter(|_| n < MAX_PATH_KEYS) {
        let end = keys.get(i + 1).map_or(*period, |next| next.time);
        let new = PathKey {
            time: 0.5 * (keys[i].time + end),
            ..keys[i]
        };
        keys.insert(i + 1, new);
    }
}
