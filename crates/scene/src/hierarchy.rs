//! Parent–child transforms: groups.
//!
//! In a level file an entity row may name its `parent` by the parent's `name`, which must be
//! unique in the level; the row's `transform` is then relative to the parent's (local). A
//! group is simply an entity with a name, a transform and children. Loading refuses a
//! parent that names no entity or a name two entities share, a cycle, a chain deeper than
//! [`MAX_DEPTH`], and an animator or a terrain inside a moving (animated) entity; every
//! error names the file, the entity and the `parent` field ([`check_rows`]). Children follow
//! a moving parent: an animated entity carries its descendants ([`Carried`]).
//!
//! The [`crate::Scene`] resolves the hierarchy once, when the level becomes the hecs
//! world: every entity's [`Transform`] component there is its *world* transform, so the
//! renderer, physics, picking and the editor read placements without knowing of parents.
//! The link is a [`Parent`] component; the scene keeps each child's local transform as
//! read, so a level saves back to the same bytes, and works it out again from the world
//! transforms when either has moved ([`relative`]).
//!
//! Transforms compose as matrices (`world = parent · local`), read back as translation,
//! Euler rotation and scale: a non-uniformly scaled parent with a rotated child would need
//! a shear, which a transform cannot hold, so such a child keeps its axes' lengths and loses
//! the shear.

use std::collections::HashMap;

use glam::{EulerRot, Mat4, Vec3};

use crate::components::Transform;
use crate::level::EntityRow;

/// The deepest parent chain a level may hold (a child of a child … 32 times).
pub const MAX_DEPTH: usize = 32;

/// The entity's parent in the scene (a hecs handle; in a file, the parent's name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parent(pub hecs::Entity);

/// A child's transform relative to its parent, as last read or set, with the world
/// transforms it was true for: used again while neither has moved, so values read from a
/// file are written back exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Local {
    pub local: Transform,
    pub world: Transform,
    pub parent_world: Transform,
}

/// What moves an entity: its own animator, or the animator of its nearest animated
/// ancestor, which carries it along (the entity keeps its place relative to the ancestor).
#[derive(Debug, Clone, PartialEq)]
pub struct Carried {
    /// The animator that moves it.
    pub animator: crate::animator::Animator,
    /// The animated entity's world transform at rest (its own, or its ancestor's).
    pub base: Transform,
    /// The entity relative to the animated ancestor at rest; `None` when it is the
    /// animated entity itself.
    pub offset: Option<Transform>,
}

impl Carried {
    /// The entity's world pose `t` seconds in.
    pub fn pose_at(&self, t: f64) -> Transform {
        let pose = self.animator.pose_at(&self.base, t);
        match &self.offset {
            Some(o) => compose(&pose, o),
            None => pose,
        }
    }
}

/// `local` placed in `parent`'s frame: the world transform of a child.
pub fn compose(parent: &Transform, local: &Transform) -> Transform {
    if *parent == Transform::default() {
        return *local;
    }
    from_matrix(parent.matrix() * local.matrix())
}

/// `world` seen from `parent`'s frame: the local transform a child at `world` has.
pub fn relative(parent: &Transform, world: &Transform) -> Transform {
    if *parent == Transform::default() {
        return *world;
    }
    from_matrix(parent.matrix().inverse() * world.matrix())
}

/// The transform of an affine matrix without shear, values within float noise of a
/// thousandth rounded to it (so a parent's 90° turn gives a child `90`, not `89.99999`).
pub fn from_matrix(m: Mat4) -> Transform {
    let (scale, rotation, translation) = m.to_scale_rotation_translation();
    let (yaw, pitch, roll) = rotation.normalize().to_euler(EulerRot::YXZ);
    let degrees = Vec3::new(pitch, yaw, roll) * (180.0 / std::f32::consts::PI);
    Transform {
        translation: tidy3(translation),
        rotation: tidy3(degrees),
        scale: tidy3(scale).max(Vec3::splat(f32::MIN_POSITIVE)),
    }
}

fn tidy3(v: Vec3) -> Vec3 {
    Vec3::new(tidy(v.x), tidy(v.y), tidy(v.z))
}

fn tidy(v: f32) -> f32 {
    let r = (v * 1000.0).round() / 1000.0;
    let r = if r == 0.0 { 0.0 } else { r };
    if (v - r).abs() <= 1e-5 * v.abs().max(1.0) {
        r
    } else {
        v
    }
}

/// What is wrong with a row's `parent`: the row's index and the message.
pub type HierarchyError = (usize, String);

/// Each row's parent (by index) as the file names it; `Err` for the first name that is
/// missing or shared.
fn parent_indices(rows: &[EntityRow]) -> Result<Vec<Option<usize>>, HierarchyError> {
    if rows.iter().all(|r| r.parent.is_none()) {
        return Ok(vec![None; rows.len()]);
    }
    let mut by_name: HashMap<&str, (usize, usize)> = HashMap::new();
    for (i, r) in rows.iter().enumerate() {
        if let Some(n) = &r.name {
            by_name.entry(n.0.as_str()).or_insert((i, 0)).1 += 1;
        }
    }
    let mut out = Vec::with_capacity(rows.len());
    for (i, r) in rows.iter().enumerate() {
        let Some(p) = &r.parent else {
            out.push(None);
            continue;
        };
        match by_name.get(p.0.as_str()) {
            None => return Err((i, format!("no entity is named \"{}\"", p.0))),
            Some(&(_, n)) if n > 1 => {
                return Err((
                    i,
                    format!(
                        "{n} entities are named \"{}\": a parent is named by a name no other entity has",
                        p.0
                    ),
                ));
            }
            Some(&(j, _)) => out.push(Some(j)),
        }
    }
    Ok(out)
}

/// Checks the rows' parents: each names exactly one entity; no chain loops or is deeper
/// than [`MAX_DEPTH`]; no row inside a moving (animated) entity has an animator or a
/// terrain of its own.
pub fn check_rows(rows: &[EntityRow]) -> Result<(), HierarchyError> {
    let parents = parent_indices(rows)?;
    for (i, p) in parents.iter().enumerate() {
        let Some(p) = *p else { continue };
        let mut chain = vec![i];
        let mut at = Some(p);
        while let Some(a) = at {
            if let Some(start) = chain.iter().position(|&c| c == a) {
                let names: Vec<&str> = chain[start..].iter().map(|&c| name_of(&rows[c])).collect();
                return Err((
                    i,
                    format!(
                        "a cycle: {} → \"{}\" (an entity cannot be its own ancestor)",
                        names
                            .iter()
                            .map(|n| format!("\"{n}\""))
                            .collect::<Vec<_>>()
                            .join(" → "),
                        name_of(&rows[a])
                    ),
                ));
            }
            if chain.len() > MAX_DEPTH {
                return Err((
                    i,
                    format!("the chain of parents is deeper than {MAX_DEPTH}"),
                ));
            }
            chain.push(a);
            at = parents[a];
        }
        // An animated ancestor carries the row: the row cannot move by itself too.
        if let Some(&a) = chain[1..].iter().find(|&&a| rows[a].animator.is_some()) {
            let what = if rows[i].animator.is_some() {
                "an animator (an entity moves with one animator: its own or its group's)"
            } else if rows[i].terrain.is_some() {
                "a terrain (terrains do not move)"
            } else {
                continue;
            };
            return Err((
                i,
                format!(
                    "it is inside \"{}\", which moves (has an animator), and has {what}",
                    name_of(&rows[a])
                ),
            ));
        }
    }
    Ok(())
}

fn name_of(row: &EntityRow) -> &str {
    row.name.as_ref().map_or("unnamed", |n| n.0.as_str())
}

/// Each row's parent (by index) and world transform, for building a scene. Rows that fail
/// [`check_rows`] (a level built in code) still resolve: a missing parent, or the link that
/// closes a cycle or passes [`MAX_DEPTH`], is left out (the row is a root).
pub(crate) fn resolve(rows: &[EntityRow]) -> (Vec<Option<usize>>, Vec<Option<Transform>>) {
    if rows.iter().all(|r| r.parent.is_none()) {
        return (
            vec![None; rows.len()],
            rows.iter().map(|r| r.transform).collect(),
        );
    }
    let mut parents = match parent_indices(rows) {
        Ok(p) => p,
        Err(_) => lenient_parents(rows),
    };
    // Cut cycles and over-deep chains.
    for i in 0..rows.len() {
        let mut at = parents[i];
        let mut depth = 0;
        while let Some(a) = at {
            depth += 1;
            if a == i || depth > MAX_DEPTH {
                parents[i] = None;
                break;
            }
            at = parents[a];
        }
    }
    let mut world: Vec<Option<Option<Transform>>> = vec![None; rows.len()];
    for i in 0..rows.len() {
        let mut chain = vec![i];
        while let Some(p) = parents[*chain.last().unwrap_or(&i)] {
            if world[p].is_some() {
                break;
            }
            chain.push(p);
        }
        for &c in chain.iter().rev() {
            let local = rows[c].transform;
            let parent = parents[c].and_then(|p| world[p].flatten());
            world[c] = Some(match (parent, local) {
                (Some(p), Some(l)) => Some(compose(&p, &l)),
                (_, l) => l,
            });
        }
    }
    (parents, world.into_iter().map(Option::flatten).collect())
}

/// Each row's world transform (its parents' composed with its own), resolved as
/// [`crate::Scene::from_level`] does.
pub fn world_transforms(rows: &[EntityRow]) -> Vec<Option<Transform>> {
    resolve(rows).1
}

/// Parents by the first row of each name (for rows that name missing or shared parents).
fn lenient_parents(rows: &[EntityRow]) -> Vec<Option<usize>> {
    let mut by_name: HashMap<&str, usize> = HashMap::new();
    for (i, r) in rows.iter().enumerate() {
        if let Some(n) = &r.name {
            by_name.entry(n.0.as_str()).or_insert(i);
        }
    }
    rows.iter()
        .map(|r| {
            r.parent
                .as_ref()
                .and_then(|p| by_name.get(p.0.as_str()).copied())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::Name;

    fn row(name: &str, parent: Option<&str>, t: Transform) -> EntityRow {
        EntityRow {
            name: Some(Name(name.into())),
            parent: parent.map(|p| Name(p.into())),
            transform: Some(t),
            ..EntityRow::default()
        }
    }

    /// A parent turned 90° about Y and scaled 2: a child one unit along its X sits two units
    /// along the world's −Z, turned 90°, twice as big; and back.
    #[test]
    fn a_rotated_scaled_parent_composes() {
        let parent = Transform {
            translation: Vec3::new(10.0, 0.0, 0.0),
            rotation: Vec3::new(0.0, 90.0, 0.0),
            scale: Vec3::splat(2.0),
        };
        let local = Transform {
            translation: Vec3::new(1.0, 0.0, 0.0),
            rotation: Vec3::new(0.0, 0.0, 0.0),
            scale: Vec3::new(1.0, 0.5, 1.0),
        };
        let w = compose(&parent, &local);
        assert_eq!(w.translation, Vec3::new(10.0, 0.0, -2.0));
        assert_eq!(w.rotation, Vec3::new(0.0, 90.0, 0.0));
        assert_eq!(w.scale, Vec3::new(2.0, 1.0, 2.0));
        assert_eq!(relative(&parent, &w), local);
        // A point of the child lands where the two matrices take it.
        let p = Vec3::new(0.3, -0.7, 1.1);
        let by_matrices = parent.matrix() * local.matrix();
        let d = w.matrix().transform_point3(p) - by_matrices.transform_point3(p);
        assert!(d.length() < 1e-4, "{d}");
    }

    #[test]
    fn missing_shared_cycle_deep_and_animated_parents_are_refused() {
        let t = Transform::default();
        let missing = [row("a", Some("nobody"), t)];
        let (i, m) = check_rows(&missing).unwrap_err();
        assert_eq!(i, 0);
        assert!(m.contains("no entity is named \"nobody\""), "{m}");
        let shared = [row("a", None, t), row("a", None, t), row("c", Some("a"), t)];
        assert!(check_rows(&shared).unwrap_err().1.contains("2 entities"));
        let cycle = [row("a", Some("b"), t), row("b", Some("a"), t)];
        let (i, m) = check_rows(&cycle).unwrap_err();
        assert_eq!(i, 0);
        assert!(m.contains("cycle") && m.contains("\"b\""), "{m}");
        assert!(check_rows(&[row("a", Some("a"), t)]).is_err(), "self");
        let deep: Vec<EntityRow> = (0..=MAX_DEPTH + 1)
            .map(|i| {
                let parent = (i > 0).then(|| format!("n{}", i - 1));
                row(&format!("n{i}"), parent.as_deref(), t)
            })
            .collect();
        assert!(check_rows(&deep).unwrap_err().1.contains("deeper"));
        assert!(check_rows(&deep[..MAX_DEPTH]).is_ok());
        let mut animated = [row("a", None, t), row("b", Some("a"), t)];
        animated[0].animator = Some(crate::animator::Animator {
            motion: crate::animator::Motion::Rotate {
                axis: Vec3::Y,
                speed: 10.0,
            },
            phase: 0.0,
        });
        assert!(
            check_rows(&animated).is_ok(),
            "a moving parent carries its children"
        );
        animated[1].animator = animated[0].animator.clone();
        let (i, m) = check_rows(&animated).unwrap_err();
        assert_eq!(i, 1);
        assert!(m.contains("inside \"a\", which moves"), "{m}");
        // Built in code anyway, they still resolve, as roots.
        let (p, w) = resolve(&cycle);
        assert!(p.iter().any(Option::is_none));
        assert!(w.iter().all(Option::is_some));
    }
}
