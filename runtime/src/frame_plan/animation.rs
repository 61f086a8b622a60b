//! Animation, one clock for everything that moves: animated objects' poses and sprites'
//! frames are pure functions of the frame's time (f64 seconds, the sum of the frames' `dt`),
//! so every frame source poses frame `i` alike; and where a moved object's shadow may have
//! come or gone, the stable faces that see it are lit again.

use glam::Vec3;
use texel_probes::visibility::{TexelRect, face_box_rect};
use texel_render::input::{FrameInput, LightFilter, SceneInput};
use texel_render::shadow_region::{bounds_under, point_shadow_bounds, sun_shadow_bounds};
use texel_scene::Transform;

use crate::load::LoadedLevel;

/// The level's animated objects and what drives them: poses as a function of time, the same
/// wherever a frame is drawn (play, `texel-run render`, the evaluator's methods and its
/// reference).
#[derive(Debug, Clone, Default)]
pub struct Animation {
    objects: Vec<Animated>,
    /// Sprites whose frames play or whose entity an animator moves.
    sprites: Vec<crate::level_sprites::SpriteClock>,
}

impl Animation {
    /// The animated objects of `scene` (extracted from `level` by
    /// [`scene_input`](super::scene_input)).
    pub fn new(level: &LoadedLevel, scene: &SceneInput) -> Self {
        Animation {
            objects: animated_objects(level, scene),
            sprites: sprite_clocks(level, scene),
        }
    }

    /// Whether nothing moves or plays.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty() && self.sprites.is_empty()
    }

    /// The state of every sprite that moves or plays, at `t` seconds.
    pub fn sprite_states(&self, t: f64) -> Vec<texel_render::input::SpriteState> {
        self.sprites.iter().map(|s| s.state(t)).collect()
    }

    /// Every animated object's pose at `t` seconds.
    pub fn poses(&self, t: f64) -> Vec<texel_render::input::Pose> {
        (self.objects.iter())
            .map(|a| texel_render::input::Pose {
                object: a.object,
                transform: a.carried.pose_at(t).matrix(),
            })
            .collect()
    }

    /// The time of the frame after one at `t`, `dt` seconds later: how every frame source
    /// advances, so they all pose frame `i` alike (a `dt` that is not a positive number does
    /// not advance; one above a second counts as a second).
    pub fn next_time(t: f64, dt: f32) -> f64 {
        if dt.is_finite() && dt > 0.0 {
            t + f64::from(dt.min(1.0))
        } else {
            t
        }
    }

    /// World bounds of the animated object `k` (in [`Animation::poses`] order) under
    /// `transform`.
    fn bounds(&self, k: usize, transform: glam::Mat4) -> (Vec3, Vec3) {
        let a = &self.objects[k];
        bounds_under(transform, a.local_min, a.local_max)
    }
}

/// An animated object: what moves it (its animator, or an animated ancestor's), and its
/// mesh's bounds.
#[derive(Debug, Clone)]
struct Animated {
    object: usize,
    carried: texel_scene::hierarchy::Carried,
    local_min: Vec3,
    local_max: Vec3,
}

/// The animated objects of `scene` (extracted from `level` by
/// [`scene_input`](super::scene_input)): entities with geometry that an animator moves (their
/// own or an ancestor's), matched to their objects by entity id.
fn animated_objects(level: &LoadedLevel, scene: &SceneInput) -> Vec<Animated> {
    let entities: Vec<hecs::Entity> = level.scene.entities().collect();
    scene
        .animated
        .iter()
        .filter_map(|&object| {
            let o = &scene.objects[object];
            let e = *entities.get(o.id.checked_sub(1)? as usize)?;
            let carried = level.scene.carried(e)?;
            let (local_min, local_max) = o.mesh.bounds()?;
            Some(Animated {
                object,
                carried,
                local_min,
                local_max,
            })
        })
        .collect()
}

fn sprite_clocks(
    level: &LoadedLevel,
    scene: &SceneInput,
) -> Vec<crate::level_sprites::SpriteClock> {
    let w = level.scene.world();
    let entities: Vec<hecs::Entity> = level.scene.entities().collect();
    (scene.sprites.iter().enumerate())
        .filter_map(|(index, input)| {
            let e = *entities.get(input.id.checked_sub(1)? as usize)?;
            let sprite = w.get::<&texel_scene::sprite::Sprite>(e).ok()?;
            let base = w.get::<&Transform>(e).map(|t| *t).ok()?;
            let carried = level.scene.carried(e);
            crate::level_sprites::SpriteClock::new(index, &sprite, input, base, carried)
        })
        .collect()
}

/// A frame driver's animation clock: the time the next frame is posed at, whether it
/// stands still, and the poses the last frame drew.
#[derive(Debug, Clone, Default)]
pub(super) struct Clock {
    /// Animation time, seconds: the sum of the frames' `dt` (so a replayed path poses
    /// every frame as it did).
    pub(super) time: f64,
    /// Each animated object's transform last frame, for the faces its shadow left.
    last_poses: Vec<glam::Mat4>,
    /// Whether the animation time stands still (the editor outside Play).
    pub(super) paused: bool,
}

impl Clock {
    /// Poses the animated objects at this frame's time (then advances it by `dt`), and lists
    /// the stable faces to light again where a moved object's shadow may have come or gone:
    /// those that may see its old or new bounds, pushed along each sun to the ground, or the
    /// reach of a point light the object is within.
    /// `scene` is the level's, with its lowest point at `floor` ([`scene_floor`](texel_render::shadow_region::scene_floor)), and
    /// `animation` its animated objects.
    pub(super) fn animate(
        &mut self,
        animation: &Animation,
        scene: &SceneInput,
        floor: f32,
        input: &mut FrameInput,
        dt: f32,
    ) {
        if animation.is_empty() {
            return;
        }
        let poses = animation.poses(self.time);
        input.sprites = animation.sprite_states(self.time);
        if !self.paused {
            self.time = Animation::next_time(self.time, dt);
        }
        // Where each moved object's shadows may have come or gone: its old and new bounds
        // and their shadows, along each sun to the ground and away from each point light
        // whose reach it is in, out to that reach.
        let mut regions: Vec<(Vec3, Vec3)> = Vec::new();
        // Of what those regions project to, only the texels whose rays toward a light meet
        // a moved object's old or new bounds are lit again.
        let mut filter = LightFilter::default();
        for (k, pose) in poses.iter().enumerate() {
            let now = pose.transform;
            let before = self.last_poses.get(k).copied().unwrap_or(now);
            if before == now && !self.last_poses.is_empty() {
                continue;
            }
            let (a, b) = (animation.bounds(k, before), animation.bounds(k, now));
            let (lo, hi) = (a.0.min(b.0), a.1.max(b.1));
            filter = filter.union(&LightFilter {
                casters: vec![a, b],
                lit: Vec::new(),
            });
            let (mut lo2, mut hi2) = sun_shadow_bounds(&scene.suns, floor, lo, hi);
            for p in &scene.points {
                if let Some((plo, phi)) = point_shadow_bounds(p.position, p.radius, lo, hi) {
                    lo2 = lo2.min(plo);
                    hi2 = hi2.max(phi);
                }
            }
            regions.push((lo2, hi2));
        }
        self.last_poses = poses.iter().map(|p| p.transform).collect();
        input.poses = poses;
        // The texels of each stable face that may see a region: one rectangle per face.
        let stable = [
            Some(&input.grid),
            input.previous.as_ref(),
            input.prefetch.as_ref(),
        ];
        for p in stable.into_iter().flatten() {
            let n = p.face_resolution;
            for face in p.valid.iter() {
                let rect = (regions.iter())
                    .filter_map(|&r| face_box_rect(face, p.origin, r, n, 1))
                    .reduce(|a, b| TexelRect {
                        x0: a.x0.min(b.x0),
                        y0: a.y0.min(b.y0),
                        x1: a.x1.max(b.x1),
                        y1: a.y1.max(b.y1),
                    });
                if let Some(rect) = rect.filter(|r| r.area() > 0) {
                    let slot = p.slot;
                    (input.relight).push(texel_render::input::Relight {
                        slot,
                        face,
                        rect,
                        filter: Some(filter.clone()),
                    });
                }
            }
        }
    }
}
