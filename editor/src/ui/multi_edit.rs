//! The inspector on several entities: the active entity's fields are shown and edited, and
//! what an edit changed (each changed field, found by comparing the rows as JSON values) is
//! given to every other selected entity that has that field; the fields whose values differ
//! across the selection are "mixed", shown as "—".

use std::collections::BTreeSet;

use serde_json::Value;
use texel_scene::EntityRow;

/// The fields whose values differ across some rows, as paths (`transform/translation/0`:
/// components, then fields, then indices).
/// A component only some rows have is named alone; its fields differ or not across the rows
/// that have it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Mixed {
    paths: BTreeSet<String>,
    on_some: BTreeSet<String>,
}

impl Mixed {
    /// The fields that differ across `rows` (none for fewer than two).
    pub fn of(rows: &[EntityRow]) -> Mixed {
        let values: Vec<Value> = (rows.iter())
            .filter_map(|r| serde_json::to_value(r).ok())
            .collect();
        let components: BTreeSet<&String> = (values.iter())
            .filter_map(Value::as_object)
            .flat_map(|m| m.keys())
            .collect();
        let mut mixed = Mixed::default();
        for c in components {
            let having: Vec<&Value> = values.iter().filter_map(|v| v.get(c)).collect();
            if having.len() < values.len() {
                mixed.on_some.insert(c.clone());
            }
            let Some((first, rest)) = having.split_first() else {
                continue;
            };
            for v in rest {
                let mut out = Vec::new();
                diff(&mut vec![c.clone()], first, v, &mut out);
                mixed
                    .paths
                    .extend(out.into_iter().map(|(p, _)| p.join("/")));
            }
        }
        mixed
    }

    /// Whether the field at `path` (or something under it) differs.
    pub fn has(&self, path: &str) -> bool {
        let under = format!("{path}/");
        self.paths
            .iter()
            .any(|p| p == path || p.starts_with(&under))
    }

    /// Whether anything differs.
    pub fn is_empty(&self) -> bool {
        self.paths.is_empty() && self.on_some.is_empty()
    }

    /// What a section title adds for `component`: "on some" when only some rows have it,
    /// "mixed: a, b" naming the fields that differ (where they have it), or nothing.
    pub fn note(&self, component: &str) -> String {
        let some = self.on_some.contains(component);
        if self.paths.contains(component) {
            // One value as a whole (an enum's variant, a bare value).
            return if some {
                " (on some, mixed)"
            } else {
                " (mixed)"
            }
            .to_owned();
        }
        let prefix = format!("{component}/");
        let fields: BTreeSet<&str> = (self.paths.iter())
            .filter_map(|p| p.strip_prefix(&prefix))
            // An enum's variant ("Box") names no field: the field under it does.
            .map(|rest| {
                let mut segs = rest.split('/');
                let first = segs.next().unwrap_or(rest);
                match segs.next() {
                    Some(f) if first.starts_with(char::is_uppercase) => f,
                    _ => first,
                }
            })
            .collect();
        let list: Vec<&str> = fields.into_iter().collect();
        match (some, list.is_empty()) {
            (false, true) => String::new(),
            (true, true) => " (on some)".to_owned(),
            (false, false) => format!(" (mixed: {})", list.join(", ")),
            (true, false) => format!(" (on some; mixed: {})", list.join(", ")),
        }
    }
}

/// `others` with the fields that changed from `before` to `after` set as in `after`. A row
/// without such a field (an edit inside a component it lacks), or that the change would make
/// invalid, keeps its value there.
pub fn spread(
    before: &EntityRow,
    after: &EntityRow,
    others: Vec<(usize, EntityRow)>,
) -> Vec<(usize, EntityRow)> {
    let (Ok(b), Ok(a)) = (serde_json::to_value(before), serde_json::to_value(after)) else {
        return others;
    };
    let mut changes = Vec::new();
    diff(&mut Vec::new(), &b, &a, &mut changes);
    others
        .into_iter()
        .map(|(i, row)| {
            let Ok(mut v) = serde_json::to_value(&row) else {
                return (i, row);
            };
            let mut took = false;
            for (path, value) in &changes {
                let mut trial = v.clone();
                if set(&mut trial, path, value.clone())
                    && serde_json::from_value::<EntityRow>(trial.clone()).is_ok()
                {
                    v = trial;
                    took = true;
                }
            }
            match serde_json::from_value(v) {
                Ok(r) if took => (i, r),
                _ => (i, row),
            }
        })
        .collect()
}

/// The paths where `a` and `b` differ and `b`'s values there. An enum's variant change (an
/// object with one key becoming one with another) is one change of the whole.
fn diff(path: &mut Vec<String>, a: &Value, b: &Value, out: &mut Vec<(Vec<String>, Value)>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y))
            if !(x.len() == 1 && y.len() == 1 && x.keys().ne(y.keys())) =>
        {
            let keys: BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                path.push(k.clone());
                let (va, vb) = (x.get(k), y.get(k));
                diff(
                    path,
                    va.unwrap_or(&Value::Null),
                    vb.unwrap_or(&Value::Null),
                    out,
                );
                path.pop();
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (k, (va, vb)) in x.iter().zip(y).enumerate() {
                path.push(k.to_string());
                diff(path, va, vb, out);
                path.pop();
            }
        }
        _ if a != b => out.push((path.clone(), b.clone())),
        _ => {}
    }
}

/// Sets the value at `path` in `v` (null removes an object's key); false when `v` has no
/// such place.
fn set(v: &mut Value, path: &[String], value: Value) -> bool {
    let Some((last, parents)) = path.split_last() else {
        *v = value;
        return true;
    };
    let mut at = v;
    for seg in parents {
        let next = match at {
            Value::Object(m) => m.get_mut(seg),
            Value::Array(a) => seg.parse::<usize>().ok().and_then(|k| a.get_mut(k)),
            _ => None,
        };
        match next {
            Some(n) => at = n,
            None => return false,
        }
    }
    match at {
        Value::Object(m) if value.is_null() => {
            m.remove(last);
            true
        }
        Value::Object(m) => {
            m.insert(last.clone(), value);
            true
        }
        Value::Array(a) => match last.parse::<usize>().ok().and_then(|k| a.get_mut(k)) {
            Some(slot) => {
                *slot = value;
                true
            }
            None => false,
        },
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use texel_scene::{Geometry, Level, Material, PointLight, Transform};

    fn sphere_of(row: &EntityRow, radius: f32) -> EntityRow {
        let mut r = row.clone();
        r.geometry = Some(Geometry::Sphere {
            radius,
            segments: 16,
        });
        r
    }

    fn rows_of(level: &str) -> Vec<EntityRow> {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../assets/levels")
            .join(level);
        Level::load(&p).expect("level").entities
    }

    #[test]
    fn rows_survive_the_json_round_trip() {
        for level in [
            "stone_circle.ron",
            "moving_parts.ron",
            "sprites.ron",
            "terrain_hills.ron",
            "textured.ron",
        ] {
            for row in rows_of(level) {
                let v = serde_json::to_value(&row).expect("to json");
                let back: EntityRow = serde_json::from_value(v).expect("from json");
                assert_eq!(back, row, "{level}");
            }
        }
    }

    #[test]
    fn an_edit_reaches_the_others_that_have_the_field() {
        let boxed = |x: f32, c: f32| EntityRow {
            transform: Some(Transform::from_translation(Vec3::new(x, 1.0, 0.0))),
            geometry: Some(Geometry::Box { size: Vec3::ONE }),
            material: Some(Material {
                albedo: Vec3::splat(c),
                ..Material::default()
            }),
            ..EntityRow::default()
        };
        let light = EntityRow {
            transform: Some(Transform::from_translation(Vec3::new(5.0, 1.0, 0.0))),
            point_light: Some(PointLight::default()),
            ..EntityRow::default()
        };
        let rows = [boxed(0.0, 0.5), boxed(2.0, 0.2), light.clone()];
        let mixed = Mixed::of(&rows);
        assert!(mixed.has("transform/translation/0"));
        assert!(!mixed.has("transform/translation/1"));
        assert_eq!(mixed.note("material"), " (on some; mixed: albedo)");
        assert_eq!(mixed.note("point_light"), " (on some)");
        assert_eq!(
            Mixed::of(&rows[..2]).note("transform"),
            " (mixed: translation)"
        );
        assert_eq!(Mixed::of(&rows[..2]).note("material"), " (mixed: albedo)");
        // Y of the first: every Y; X stays each one's own.
        let mut after = rows[0].clone();
        after.transform.as_mut().expect("t").translation.y = 3.0;
        after.material.as_mut().expect("m").albedo.x = 0.9;
        let out = spread(&rows[0], &after, vec![(1, rows[1].clone()), (2, light)]);
        let t = |r: &EntityRow| r.transform.expect("t").translation;
        assert_eq!(t(&out[0].1), Vec3::new(2.0, 3.0, 0.0));
        assert_eq!(t(&out[1].1), Vec3::new(5.0, 3.0, 0.0));
        assert_eq!(
            out[0].1.material.as_ref().expect("m").albedo,
            Vec3::new(0.9, 0.2, 0.2)
        );
        assert_eq!(out[1].1.material, None, "the light gets no material");
        // A change of kind is taken whole.
        assert_eq!(
            Mixed::of(&[rows[0].clone(), sphere_of(&rows[0], 2.0)]).note("geometry"),
            " (mixed)"
        );
        let mut wide = rows[1].clone();
        wide.geometry = Some(Geometry::Box {
            size: Vec3::splat(2.0),
        });
        assert_eq!(
            Mixed::of(&[rows[0].clone(), wide]).note("geometry"),
            " (mixed: size)"
        );
        let mut sphere = rows[0].clone();
        sphere.geometry = Some(Geometry::Sphere {
            radius: 0.5,
            segments: 16,
        });
        let out = spread(&rows[0], &sphere, vec![(1, rows[1].clone())]);
        assert_eq!(out[0].1.geometry, sphere.geometry);
    }
}
