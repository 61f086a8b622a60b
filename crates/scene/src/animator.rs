//! Moving parts: an [`Animator`] moves its entity's transform as a pure function of time, so
//! any frame of any session can be evaluated on its own (a replay, a test, a renderer that
//! jumps) and every run of a level moves the same way.
//!
//! Three motions: [`Motion::Rotate`] (a turning speed about an axis through the entity's
//! translation), [`Motion::PingPong`] (there and back between the entity's transform and
//! another, eased) and [`Motion::Path`] (key poses at times, looping). Time is an `f64` of
//! seconds reduced modulo the motion's period before anything becomes `f32`, so the pose
//! after an hour is as exact as in the first second. The entity's transform in the level is
//! the animation's base (the rest pose the editor shows); `Scene::animated_poses` evaluates
//! every animated entity of a scene without changing it, with the descendants an animated
//! entity carries (`Scene::carried`, [`crate::hierarchy::Carried`]).

use glam::{EulerRot, Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::components::{Transform, Validate};
use crate::num;

/// Most keys a path may hold.
pub const MAX_PATH_KEYS: usize = 1024;

/// Moves its entity's transform over time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Animator {
    /// How it moves.
    #[serde(deserialize_with = "de_motion")]
    pub motion: Motion,
    /// Seconds added to the time (to set alike animators apart); left out of the file when 0.
    #[serde(default, skip_serializing_if = "is_plus_zero", with = "num::finite")]
    pub phase: f32,
}

/// How an animator moves its entity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Motion {
    /// Turns about `axis` (world space, through the entity's translation) at `speed`.
    Rotate {
        /// The axis of rotation in world space; not zero, normalised on use.
        #[serde(with = "num::axis")]
        axis: Vec3,
        /// Degrees per second (right-handed about `axis`); not zero.
        #[serde(with = "num::speed")]
        speed: f32,
    },
    /// There and back: from the entity's transform to `to` in half the period, and back in
    /// the other half. Translation and scale are interpolated linearly, rotation by slerp.
    PingPong {
        /// The other end (the entity's transform is the first).
        to: Transform,
        /// Seconds for there and back, > 0.
        #[serde(with = "num::period")]
        period: f32,
        /// The pace along the way; left out of the file when linear.
        #[serde(default, skip_serializing_if = "is_linear")]
        easing: Easing,
    },
    /// Through key poses (world translation and rotation; the scale stays the entity's) at
    /// their times, linearly in translation and by slerp in rotation; after the last key it
    /// returns to the first, which it reaches at `period`, and loops.
    Path {
        /// At least 2 keys, the first at time 0, times strictly increasing.
        #[serde(deserialize_with = "de_keys")]
        keys: Vec<PathKey>,
        /// Seconds per loop, longer than the last key's time.
        #[serde(with = "num::period")]
        period: f32,
    },
}

/// The pace of a [`Motion::PingPong`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Easing {
    /// Constant speed.
    #[default]
    Linear,
    /// Smoothstep (`3s² − 2s³`): starts and stops gently.
    Smooth,
}

impl Easing {
    /// The eased fraction of the way for `s` in 0..=1.
    pub fn apply(self, s: f32) -> f32 {
        match self {
            Easing::Linear => s,
            Easing::Smooth => s * s * (3.0 - 2.0 * s),
        }
    }
}

/// One pose of a [`Motion::Path`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathKey {
    /// Seconds since the loop's start.
    #[serde(with = "num::finite")]
    pub time: f32,
    /// Position in world units.
    #[serde(with = "num::vec3")]
    pub translation: Vec3,
    /// Euler angles in degrees, as a [`Transform`]'s; left out of the file when zero.
    #[serde(default, skip_serializing_if = "is_plus_zero3", with = "num::vec3")]
    pub rotation: Vec3,
}

impl PathKey {
    /// This key's pose with `scale`.
    pub fn transform(&self, scale: Vec3) -> Transform {
        Transform {
            translation: self.translation,
            rotation: self.rotation,
            scale,
        }
    }
}

fn is_plus_zero(v: &f32) -> bool {
    v.to_bits() == 0
}
fn is_plus_zero3(v: &Vec3) -> bool {
    v.to_array().iter().all(is_plus_zero)
}
fn is_linear(e: &Easing) -> bool {
    *e == Easing::Linear
}

impl Animator {
    /// The entity's pose at `t` seconds (plus the phase), its transform in the level being
    /// `base`. A pure function: the same inputs give the same bits. A velocity or the
    /// previous frame's pose is `pose_at(base, t - dt)`. A time that is not finite counts as
    /// 0.
    pub fn pose_at(&self, base: &Transform, t: f64) -> Transform {
        let t = if t.is_finite() { t } else { 0.0 } + f64::from(self.phase);
        match &self.motion {
            Motion::Rotate { axis, speed } => {
                let Some(axis) = axis.try_normalize() else {
                    return *base;
                };
                let degrees = wrap(f64::from(*speed) * t, 360.0) as f32;
                let turn = Quat::from_axis_angle(axis, degrees.to_radians());
                Transform {
                    rotation: euler_degrees(turn * base.quat()),
                    ..*base
                }
            }
            Motion::PingPong { to, period, easing } => {
                let p = f64::from(*period);
                let u = (wrap(t, p) / p) as f32;
                let s = if u < 0.5 { 2.0 * u } else { 2.0 - 2.0 * u };
                blend(base, to, easing.apply(s.clamp(0.0, 1.0)))
            }
            Motion::Path { keys, period } => path_pose(keys, *period, base.scale, t),
        }
    }
}

impl Motion {
    /// Seconds after which the motion repeats (a full turn, for a rotation).
    pub fn period(&self) -> f64 {
        match self {
            Motion::Rotate { speed, .. } => 360.0 / f64::from(speed.abs()),
            Motion::PingPong { period, .. } | Motion::Path { period, .. } => f64::from(*period),
        }
    }
}

/// `t` modulo `period` in `[0, period)` (`period` > 0), in f64.
fn wrap(t: f64, period: f64) -> f64 {
    let r = t.rem_euclid(period);
    // rem_euclid may round a tiny negative remainder up to the period itself.
    if r.is_finite() && r < period { r } else { 0.0 }
}

/// Euler degrees (X, Y, Z) of `q`, in [`Transform`]'s order (yaw, then pitch, then roll).
fn euler_degrees(q: Quat) -> Vec3 {
    let (yaw, pitch, roll) = q.normalize().to_euler(EulerRot::YXZ);
    Vec3::new(pitch, yaw, roll) * (180.0 / std::f32::consts::PI)
}

/// The pose a fraction `s` of the way from `a` to `b`: exactly `a` at 0 and `b` at 1.
fn blend(a: &Transform, b: &Transform, s: f32) -> Transform {
    if s <= 0.0 {
        return *a;
    }
    if s >= 1.0 {
        return *b;
    }
    Transform {
        translation: a.translation.lerp(b.translation, s),
        rotation: euler_degrees(a.quat().slerp(b.quat(), s)),
        scale: a.scale.lerp(b.scale, s),
    }
}

fn path_pose(keys: &[PathKey], period: f32, scale: Vec3, t: f64) -> Transform {
    let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
        return Transform {
            scale,
            ..Transform::default()
        };
    };
    let local = wrap(t, f64::from(period)) as f32;
    // The last key at or before `local`; the segment after the last key runs back to the
    // first, reached at `period`.
    let i = keys.partition_point(|k| k.time <= local).saturating_sub(1);
    let (a, b, end) = match keys.get(i + 1) {
        Some(next) => (&keys[i], next, next.time),
        None => (last, first, period),
    };
    let s = (local - a.time) / (end - a.time);
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.0
    };
    blend(&a.transform(scale), &b.transform(scale), s)
}

fn de_motion<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Motion, D::Error> {
    let motion = Motion::deserialize(d)?;
    if let Motion::Path { keys, period } = &motion {
        check_path_period(keys, *period).map_err(serde::de::Error::custom)?;
    }
    Ok(motion)
}

fn de_keys<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<PathKey>, D::Error> {
    let keys = Vec::<PathKey>::deserialize(d)?;
    check_keys(&keys).map_err(serde::de::Error::custom)?;
    Ok(keys)
}

/// A path has 2..=[`MAX_PATH_KEYS`] keys, the first at time 0, times strictly increasing.
pub fn check_keys(keys: &[PathKey]) -> Result<(), String> {
    if keys.len() < 2 {
        return Err(format!("a path needs at least 2 keys, got {}", keys.len()));
    }
    if keys.len() > MAX_PATH_KEYS {
        return Err(format!(
            "a path has {} keys, at most {MAX_PATH_KEYS} are allowed",
            keys.len()
        ));
    }
    if keys[0].time != 0.0 {
        return Err(format!(
            "the first path key must be at time 0, got {:?}",
            keys[0].time
        ));
    }
    for (i, w) in keys.windows(2).enumerate() {
        if w[1].time.partial_cmp(&w[0].time) != Some(std::cmp::Ordering::Greater) {
            return Err(format!(
                "path key times must increase: key {} at {:?} s does not come after key {} at {:?} s",
                i + 1,
                w[1].time,
                i,
                w[0].time
            ));
        }
    }
    Ok(())
}

/// A path's period is longer than its last key's time (the way back to the first key takes
/// the rest).
pub fn check_path_period(keys: &[PathKey], period: f32) -> Result<(), String> {
    match keys.last() {
        Some(last) if period <= last.time => Err(format!(
            "the path's period ({period:?} s) must be longer than its last key's time ({:?} s)",
            last.time
        )),
        _ => Ok(()),
    }
}

impl Validate for Animator {
    fn validate(&self) -> Result<(), (&'static str, String)> {
        let field = |name, r: Result<(), String>| r.map_err(|m| (name, m));
        field("phase", num::check_coord(self.phase).map(drop))?;
        match &self.motion {
            Motion::Rotate { axis, speed } => {
                field("axis", num::check_axis(*axis).map(drop))?;
                field("speed", num::check_speed(*speed).map(drop))
            }
            Motion::PingPong { to, period, .. } => {
                to.validate()
                    .map_err(|(f, m)| ("to", format!("{f}: {m}")))?;
                field("period", num::check_period(*period).map(drop))
            }
            Motion::Path { keys, period } => {
                field("keys", check_keys(keys))?;
                for k in keys {
                    field("keys", num::check_coord(k.time).map(drop))?;
                    field("keys", num::check_vec3(k.translation).map(drop))?;
                    field("keys", num::check_vec3(k.rotation).map(drop))?;
                }
                field("period", num::check_period(*period).map(drop))?;
                field("period", check_path_period(keys, *period))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    /// Whether two poses place every point alike.
    fn same_pose(a: &Transform, b: &Transform) -> bool {
        [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z].iter().all(|&p| {
            close(
                a.matrix().transform_point3(p),
                b.matrix().transform_point3(p),
            )
        })
    }

    fn at(x: f32, y: f32, z: f32) -> Transform {
        Transform::from_translation(Vec3::new(x, y, z))
    }

    fn animator(motion: Motion) -> Animator {
        Animator { motion, phase: 0.0 }
    }

    #[test]
    fn rotation_turns_quarter_turns_about_the_entitys_translation() {
        let a = animator(Motion::Rotate {
            axis: Vec3::new(0.0, 0.0, 2.0),
            speed: 90.0,
        });
        let base = at(1.0, 2.0, 3.0);
        for (t, x_goes_to) in [
            (0.0, Vec3::X),
            (1.0, Vec3::Y),
            (2.0, -Vec3::X),
            (3.0, -Vec3::Y),
            (4.0, Vec3::X),
        ] {
            let p = a.pose_at(&base, t);
            assert_eq!(p.translation, base.translation, "turns in place");
            let moved = p.matrix().transform_point3(Vec3::X) - base.translation;
            assert!(close(moved, x_goes_to), "t {t}: {moved}");
        }
        // About a tilted entity: the turn is about the world axis, after its own rotation.
        let tilted = Transform {
            rotation: Vec3::new(0.0, 90.0, 0.0),
            ..base
        };
        let p = a.pose_at(&tilted, 1.0);
        let moved = p.matrix().transform_point3(Vec3::Z) - base.translation;
        // Yaw 90 takes +Z to +X, the quarter turn about Z takes +X to +Y.
        assert!(close(moved, Vec3::Y), "{moved}");
        // Negative speeds turn the other way; the phase shifts time.
        let back = animator(Motion::Rotate {
            axis: Vec3::Z,
            speed: -90.0,
        });
        let moved = back.pose_at(&base, 1.0).matrix().transform_point3(Vec3::X) - base.translation;
        assert!(close(moved, -Vec3::Y), "{moved}");
        let phased = Animator {
            phase: 1.0,
            ..a.clone()
        };
        assert_eq!(phased.pose_at(&base, 0.0), a.pose_at(&base, 1.0));
    }

    #[test]
    fn ping_pong_reaches_both_ends_and_the_middle_with_both_easings() {
        let base = at(0.0, 1.0, 0.0);
        let to = Transform {
            translation: Vec3::new(2.0, 1.0, 0.0),
            rotation: Vec3::new(0.0, 90.0, 0.0),
            scale: Vec3::splat(3.0),
        };
        for easing in [Easing::Linear, Easing::Smooth] {
            let a = animator(Motion::PingPong {
                to,
                period: 4.0,
                easing,
            });
            assert_eq!(a.pose_at(&base, 0.0), base, "{easing:?} starts at the base");
            assert_eq!(a.pose_at(&base, 2.0), to, "{easing:?} is at `to` half way");
            assert_eq!(a.pose_at(&base, 4.0), base, "{easing:?} is back");
            let mid = a.pose_at(&base, 1.0);
            assert!(close(mid.translation, Vec3::new(1.0, 1.0, 0.0)), "{mid:?}");
            assert!(close(mid.rotation, Vec3::new(0.0, 45.0, 0.0)), "{mid:?}");
            assert!(close(mid.scale, Vec3::splat(2.0)), "{mid:?}");
            assert_eq!(
                a.pose_at(&base, 3.0),
                mid,
                "the way back mirrors the way there"
            );
        }
        // A quarter of the way there in time: linear is a quarter of the way in space,
        // smoothstep 0.15625 (3/16 − 2/64).
        let quarter = |easing| {
            animator(Motion::PingPong {
                to,
                period: 4.0,
                easing,
            })
            .pose_at(&base, 0.5)
            .translation
            .x
        };
        assert!((quarter(Easing::Linear) - 0.5).abs() < 1e-6);
        assert!((quarter(Easing::Smooth) - 2.0 * 0.15625).abs() < 1e-6);
    }

    fn platform() -> Motion {
        let key = |time, y, yaw| PathKey {
            time,
            translation: Vec3::new(0.0, y, 0.0),
            rotation: Vec3::new(0.0, yaw, 0.0),
        };
        Motion::Path {
            keys: vec![key(0.0, 0.0, 0.0), key(2.0, 1.0, 90.0), key(3.0, 1.0, 90.0)],
            period: 4.0,
        }
    }

    #[test]
    fn paths_pass_their_keys_and_midpoints_and_loop_back_to_the_first() {
        let a = animator(platform());
        let base = Transform {
            scale: Vec3::splat(2.0),
            ..at(9.0, 9.0, 9.0)
        };
        let Motion::Path { keys, .. } = &a.motion else {
            unreachable!()
        };
        for k in keys {
            assert_eq!(
                a.pose_at(&base, f64::from(k.time)),
                k.transform(base.scale),
                "at key {}",
                k.time
            );
        }
        let mid = a.pose_at(&base, 1.0);
        assert!(close(mid.translation, Vec3::new(0.0, 0.5, 0.0)), "{mid:?}");
        assert!(close(mid.rotation, Vec3::new(0.0, 45.0, 0.0)), "{mid:?}");
        assert_eq!(mid.scale, base.scale, "the scale is the entity's");
        // Between keys 2 and 3 it holds still; after the last key it heads back to the first.
        assert!(same_pose(
            &a.pose_at(&base, 2.5),
            &keys[1].transform(base.scale)
        ));
        let back = a.pose_at(&base, 3.5);
        assert!(
            close(back.translation, Vec3::new(0.0, 0.5, 0.0)),
            "{back:?}"
        );
        assert!(close(back.rotation, Vec3::new(0.0, 45.0, 0.0)), "{back:?}");
        // Loop wrap: the period is the first key again, and time wraps.
        assert_eq!(a.pose_at(&base, 4.0), keys[0].transform(base.scale));
        assert_eq!(a.pose_at(&base, 5.0), mid);
        assert_eq!(a.pose_at(&base, -3.0), mid, "negative times wrap too");
        assert_eq!(a.pose_at(&base, f64::NAN), a.pose_at(&base, 0.0));
    }

    #[test]
    fn an_hour_in_is_the_same_pose_as_the_first_second() {
        let base = at(1.0, 0.5, -2.0);
        let motions = [
            // 40°/s turns once every 9 s, 400 times an hour.
            Motion::Rotate {
                axis: Vec3::new(0.3, 0.0, 1.0),
                speed: 40.0,
            },
            Motion::PingPong {
                to: at(3.0, 0.5, -2.0),
                period: 4.0,
                easing: Easing::Smooth,
            },
            Motion::Path {
                keys: vec![
                    PathKey {
                        time: 0.0,
                        translation: Vec3::ZERO,
                        rotation: Vec3::ZERO,
                    },
                    PathKey {
                        time: 3.0,
                        translation: Vec3::ONE,
                        rotation: Vec3::new(10.0, 20.0, 30.0),
                    },
                ],
                period: 8.0,
            },
        ];
        for motion in motions {
            for phase in [0.0, 0.25] {
                let a = Animator {
                    motion: motion.clone(),
                    phase,
                };
                assert_eq!(a.pose_at(&base, 3600.5), a.pose_at(&base, 0.5), "{a:?}");
                assert_eq!(
                    a.pose_at(&base, 36000.0 + 1.25),
                    a.pose_at(&base, 1.25),
                    "{a:?}"
                );
            }
        }
        assert_eq!(
            Motion::Rotate {
                axis: Vec3::Z,
                speed: -40.0
            }
            .period(),
            9.0
        );
    }

    #[test]
    fn bad_values_are_named_by_validation() {
        let bad = |motion| animator(motion).validate().unwrap_err();
        let e = bad(Motion::Rotate {
            axis: Vec3::ZERO,
            speed: 1.0,
        });
        assert_eq!(e.0, "axis");
        assert!(e.1.contains("axis must not be zero"), "{e:?}");
        for speed in [0.0, f32::NAN, f32::INFINITY] {
            let e = bad(Motion::Rotate {
                axis: Vec3::Y,
                speed,
            });
            assert_eq!(e.0, "speed", "{speed}");
        }
        for period in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let e = bad(Motion::PingPong {
                to: Transform::default(),
                period,
                easing: Easing::Linear,
            });
            assert_eq!(e.0, "period", "{period}");
        }
        let Motion::Path { keys, .. } = platform() else {
            unreachable!()
        };
        let path = |keys: &[PathKey], period| Motion::Path {
            keys: keys.to_vec(),
            period,
        };
        assert!(bad(path(&keys[..1], 4.0)).1.contains("at least 2 keys"));
        let mut late = keys.clone();
        late[0].time = 0.5;
        assert!(
            bad(path(&late, 4.0))
                .1
                .contains("first path key must be at time 0")
        );
        let mut tied = keys.clone();
        tied[2].time = 2.0;
        assert!(bad(path(&tied, 4.0)).1.contains("must increase"));
        let e = bad(path(&keys, 3.0));
        assert_eq!(e.0, "period");
        assert!(e.1.contains("longer than its last key's time"), "{e:?}");
        let e = animator(Motion::PingPong {
            to: Transform {
                scale: Vec3::ZERO,
                ..Transform::default()
            },
            period: 1.0,
            easing: Easing::Linear,
        })
        .validate()
        .unwrap_err();
        assert_eq!(e.0, "to");
        assert!(e.1.starts_with("scale: "), "{e:?}");
        assert!(animator(platform()).validate().is_ok());
    }
}
