//! Camera paths: keyframes a headless run or an evaluation flies through, as RON.
//!
//! ```ron
//! (
//!     frames: 60,
//!     dt: 0.0333,
//!     keyframes: [
//!         (position: (0.0, 1.6, 10.0), yaw: 0.0, pitch: 0.0),
//!         (position: (0.0, 1.6, 4.0), yaw: 30.0, pitch: -5.0),
//!     ],
//! )
//! ```
//!
//! Keyframes are spread evenly over the frames and interpolated (position, yaw and pitch in
//! degrees, as a level's player start stores them): linearly by default, or through a
//! Catmull–Rom spline with `interpolation: Smooth`. `projection: Perspective(60.0)` (vertical
//! field of view in degrees) or `projection: Orthographic(12.0)` (view height in world units)
//! overrides the field of view the caller passes to [`CameraPath::camera`].

use std::path::Path;

use glam::Vec3;
use serde::Deserialize;
use texel_render::input::Camera;

/// One keyframe.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// Eye position.
    pub position: (f32, f32, f32),
    /// Heading in degrees (0 looks along −Z, positive turns toward −X).
    #[serde(default)]
    pub yaw: f32,
    /// Pitch in degrees (positive looks up).
    #[serde(default)]
    pub pitch: f32,
}

/// How the camera moves between keyframes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
pub enum Interpolation {
    /// Straight lines at constant speed between keyframes.
    #[default]
    Linear,
    /// A Catmull–Rom spline through the keyframes (smooth turns, no velocity jumps).
    Smooth,
}

/// The camera's projection along a path.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub enum Projection {
    /// Perspective with this vertical field of view in degrees.
    Perspective(f32),
    /// Orthographic with a view this many world units tall.
    Orthographic(f32),
}

fn some_projection<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Projection>, D::Error> {
    Projection::deserialize(d).map(Some)
}

/// A camera path.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPath {
    /// Frames to render.
    pub frames: u32,
    /// Seconds between frames.
    #[serde(default = "default_dt")]
    pub dt: f32,
    /// At least one keyframe.
    pub keyframes: Vec<Keyframe>,
    /// How to move between keyframes.
    #[serde(default)]
    pub interpolation: Interpolation,
    /// Projection overriding the caller's field of view (None: the caller's perspective).
    #[serde(default, deserialize_with = "some_projection")]
    pub projection: Option<Projection>,
}

fn default_dt() -> f32 {
    1.0 / 30.0
}

/// Most frames a path (or `texel-run render --frames`) may ask for.
pub const MAX_FRAMES: u32 = 100_000;

/// A path that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum PathError {
    /// Unreadable file.
    #[error("{0}: {1}")]
    Io(String, std::io::Error),
    /// Not a regular file, or larger than a camera path may be (`TEXEL_MAX_PATH_BYTES`).
    #[error(transparent)]
    Read(texel_scene::read::ReadError),
    /// Bad RON.
    #[error("{0}:{1}")]
    Parse(String, ron::error::SpannedError),
    /// Bad values.
    #[error("{0}: {1}")]
    Invalid(String, String),
}

impl CameraPath {
    /// Reads and checks a path file.
    pub fn load(path: &Path) -> Result<Self, PathError> {
        let name = path.display().to_string();
        use texel_scene::read::{FileKind, ReadError, read_bounded_string};
        let text = read_bounded_string(path, FileKind::CameraPath).map_err(|e| match e {
            ReadError::Io { source, .. } => PathError::Io(name.clone(), source),
            other => PathError::Read(other),
        })?;
        Self::from_ron_str(&text, &name)
    }

    /// Parses and checks the text of a path file; `name` is what errors call it.
    pub fn from_ron_str(text: &str, name: &str) -> Result<Self, PathError> {
        let p: CameraPath =
            ron::from_str(text).map_err(|e| PathError::Parse(name.to_owned(), e))?;
        p.check()
            .map_err(|m| PathError::Invalid(name.to_owned(), m))?;
        Ok(p)
    }

    /// A one-keyframe path of `frames` frames.
    pub fn still(k: Keyframe, frames: u32) -> Self {
        CameraPath {
            frames,
            dt: default_dt(),
            keyframes: vec![k],
            interpolation: Interpolation::Linear,
            projection: None,
        }
    }

    fn check(&self) -> Result<(), String> {
        if self.keyframes.is_empty() {
            return Err("a path needs at least one keyframe".into());
        }
        if self.frames == 0 || self.frames > MAX_FRAMES {
            return Err(format!(
                "frames must be 1..={MAX_FRAMES}, got {}",
                self.frames
            ));
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(format!("dt must be in (0, 1] seconds, got {}", self.dt));
        }
        for (i, k) in self.keyframes.iter().enumerate() {
            let v = [k.position.0, k.position.1, k.position.2, k.yaw, k.pitch];
            if v.iter().any(|x| !x.is_finite() || x.abs() > 1.0e6) {
                return Err(format!("keyframe {i}: NaN, infinite or huge number"));
            }
            if k.pitch.abs() > 89.0 {
                return Err(format!("keyframe {i}: pitch must be within ±89"));
            }
        }
        match self.projection {
            Some(Projection::Perspective(f)) if !(f.is_finite() && f > 1.0 && f < 170.0) => Err(
                format!("perspective field of view must be in (1, 170) degrees, got {f}"),
            ),
            Some(Projection::Orthographic(h)) if !(h.is_finite() && h > 0.0 && h < 1.0e5) => {
                Err(format!("orthographic height must be positive, got {h}"))
            }
            _ => Ok(()),
        }
    }

    /// The vertical field of view (radians) of the path's perspective projection, or
    /// `fallback` when the path does not set one.
    pub fn fov_y(&self, fallback: f32) -> f32 {
        match self.projection {
            Some(Projection::Perspective(deg)) => deg.to_radians(),
            _ => fallback,
        }
    }

    /// The path's first `frames` frames (all of them when it has fewer): a path of one
    /// keyframe a frame, each the camera this path has at that frame, so the cameras are the
    /// same to the bit. The second driver's pass flies some measurement-heavy tests this way
    /// (`texel_render::context::short_form`).
    pub fn first(&self, frames: u32) -> CameraPath {
        let frames = frames.clamp(1, self.frames);
        CameraPath {
            frames,
            dt: self.dt,
            keyframes: (0..frames).map(|i| self.keyframe(i)).collect(),
            interpolation: Interpolation::Linear,
            projection: self.projection,
        }
    }

    /// The keyframe the path interpolates at frame `i`.
    fn keyframe(&self, i: u32) -> Keyframe {
        let v = self.pose(i);
        Keyframe {
            position: (v[0], v[1], v[2]),
            yaw: v[3],
            pitch: v[4],
        }
    }

    /// The camera at frame `i` with vertical field of view `fov_y` (radians) unless the path
    /// sets its own projection.
    pub fn camera(&self, i: u32, fov_y: f32) -> Camera {
        let v = self.pose(i);
        let mut cam = Camera::from_yaw_pitch(Vec3::new(v[0], v[1], v[2]), v[3], v[4]);
        cam.fov_y = self.fov_y(fov_y);
        if let Some(Projection::Orthographic(h)) = self.projection {
            cam.ortho_height = Some(h);
        }
        cam
    }

    /// Position, yaw and pitch at frame `i`, interpolated between the keyframes.
    fn pose(&self, i: u32) -> [f32; 5] {
        let k = &self.keyframes;
        let t = if self.frames <= 1 || k.len() == 1 {
            0.0
        } else if k.len() as u32 == self.frames {
            // A keyframe a frame (what `first` writes): frame `i` is keyframe `i`, exactly.
            i.min(self.frames - 1) as f32
        } else {
            i.min(self.frames - 1) as f32 / (self.frames - 1) as f32 * (k.len() - 1) as f32
        };
        let a = (t.floor() as usize).min(k.len() - 1);
        let b = (a + 1).min(k.len() - 1);
        let f = t - a as f32;
        let key = |j: usize| {
            let k = &k[j];
            [k.position.0, k.position.1, k.position.2, k.yaw, k.pitch]
        };
        match self.interpolation {
            Interpolation::Linear => {
                let (ka, kb) = (key(a), key(b));
                std::array::from_fn(|c| ka[c] + (kb[c] - ka[c]) * f)
            }
            Interpolation::Smooth => {
                let p0 = key(a.saturating_sub(1));
                let p3 = key((b + 1).min(k.len() - 1));
                catmull_rom(p0, key(a), key(b), p3, f)
            }
        }
    }
}

/// Uniform Catmull–Rom between `p1` and `p2`, per component.
fn catmull_rom(p0: [f32; 5], p1: [f32; 5], p2: [f32; 5], p3: [f32; 5], t: f32) -> [f32; 5] {
    let (t2, t3) = (t * t, t * t * t);
    std::array::from_fn(|c| {
        let (a, b, d, e) = (p0[c], p1[c], p2[c], p3[c]);
        0.5 * (2.0 * b
            + (d - a) * t
            + (2.0 * a - 5.0 * b + 4.0 * d - e) * t2
            + (3.0 * b - a - 3.0 * d + e) * t3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_frames_of_a_path_are_its_cameras_to_the_bit() {
        let key = |x: f32, yaw: f32, pitch: f32| Keyframe {
            position: (x, 1.0 + x * 0.1, -x),
            yaw,
            pitch,
        };
        for interpolation in [Interpolation::Linear, Interpolation::Smooth] {
            let p = CameraPath {
                frames: 37,
                dt: 0.05,
                keyframes: vec![
                    key(0.0, 0.0, 0.0),
                    key(3.3, 47.0, -9.0),
                    key(5.1, 12.5, 4.0),
                ],
                interpolation,
                projection: Some(Projection::Orthographic(6.0)),
            };
            let first = p.first(18);
            assert_eq!((first.frames, first.dt), (18, p.dt));
            assert_eq!(first.projection, p.projection);
            for i in 0..18 {
                let (a, b) = (p.camera(i, 1.0), first.camera(i, 1.0));
                assert_eq!(a.position, b.position, "{interpolation:?} frame {i}");
                assert_eq!(a.forward, b.forward, "{interpolation:?} frame {i}");
                assert_eq!(a.ortho_height, b.ortho_height);
            }
            // More frames than the path has: all of them.
            assert_eq!(p.first(100).frames, 37);
        }
    }

    #[test]
    fn interpolates_evenly_between_keyframes() {
        let p = CameraPath {
            frames: 5,
            dt: 0.1,
            keyframes: vec![
                Keyframe {
                    position: (0.0, 1.0, 0.0),
                    yaw: 0.0,
                    pitch: 0.0,
                },
                Keyframe {
                    position: (4.0, 1.0, 0.0),
                    yaw: 40.0,
                    pitch: 0.0,
                },
            ],
            interpolation: Interpolation::Linear,
            projection: None,
        };
        assert_eq!(p.camera(0, 1.0).position, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(p.camera(2, 1.0).position, Vec3::new(2.0, 1.0, 0.0));
        assert_eq!(p.camera(4, 1.0).position, Vec3::new(4.0, 1.0, 0.0));
        let mid = Camera::from_yaw_pitch(Vec3::ZERO, 20.0, 0.0).forward;
        assert!((p.camera(2, 1.0).forward - mid).length() < 1e-6);
    }

    #[test]
    fn smooth_paths_pass_through_keyframes_and_projection_applies() {
        let text = "(frames: 5, keyframes: [(position: (0.0, 1.0, 0.0)), \
                    (position: (2.0, 1.0, 0.0)), (position: (2.0, 1.0, 4.0))], \
                    interpolation: Smooth, projection: Orthographic(8.0))";
        let p: CameraPath = ron::from_str(text).expect("parses");
        p.check().expect("valid");
        assert!((p.camera(2, 1.0).position - Vec3::new(2.0, 1.0, 0.0)).length() < 1e-5);
        assert!((p.camera(4, 1.0).position - Vec3::new(2.0, 1.0, 4.0)).length() < 1e-5);
        // Between keyframes the spline leaves the straight line (it rounds the corner).
        let mid = p.camera(1, 1.0).position;
        assert!(mid.z.abs() > 1e-3, "{mid}");
        assert_eq!(p.camera(1, 1.0).ortho_height, Some(8.0));
        let q: CameraPath = ron::from_str(
            "(frames: 2, keyframes: [(position: (0.0, 1.0, 0.0))], projection: Perspective(90.0))",
        )
        .expect("parses");
        assert!((q.camera(0, 1.0).fov_y - 90f32.to_radians()).abs() < 1e-6);
        assert_eq!(q.camera(0, 1.0).ortho_height, None);
    }

    #[test]
    fn bad_paths_are_refused() {
        let mut p = CameraPath::still(
            Keyframe {
                position: (0.0, 0.0, 0.0),
                yaw: 0.0,
                pitch: 95.0,
            },
            3,
        );
        assert!(p.check().unwrap_err().contains("pitch"));
        p.keyframes.clear();
        assert!(p.check().is_err());
    }
}
