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
//! Keyframes are spread evenly over the frames and interpolated linearly (position, yaw and
//! pitch in degrees, as a level's player start stores them).

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
}

fn default_dt() -> f32 {
    1.0 / 30.0
}

/// A path that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum PathError {
    /// Unreadable file.
    #[error("{0}: {1}")]
    Io(String, std::io::Error),
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
        let text = std::fs::read_to_string(path).map_err(|e| PathError::Io(name.clone(), e))?;
        let p: CameraPath = ron::from_str(&text).map_err(|e| PathError::Parse(name.clone(), e))?;
        p.check().map_err(|m| PathError::Invalid(name, m))?;
        Ok(p)
    }

    /// A one-keyframe path of `frames` frames.
    pub fn still(k: Keyframe, frames: u32) -> Self {
        CameraPath {
            frames,
            dt: default_dt(),
            keyframes: vec![k],
        }
    }

    fn check(&self) -> Result<(), String> {
        if self.keyframes.is_empty() {
            return Err("a path needs at least one keyframe".into());
        }
        if self.frames == 0 || self.frames > 100_000 {
            return Err(format!("frames must be 1..=100000, got {}", self.frames));
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
        Ok(())
    }

    /// The camera at frame `i` with vertical field of view `fov_y` (radians).
    pub fn camera(&self, i: u32, fov_y: f32) -> Camera {
        let k = &self.keyframes;
        let t = if self.frames <= 1 || k.len() == 1 {
            0.0
        } else {
            i.min(self.frames - 1) as f32 / (self.frames - 1) as f32 * (k.len() - 1) as f32
        };
        let a = (t.floor() as usize).min(k.len() - 1);
        let b = (a + 1).min(k.len() - 1);
        let f = t - a as f32;
        let lerp = |x: f32, y: f32| x + (y - x) * f;
        let (pa, pb) = (Vec3::from(k[a].position), Vec3::from(k[b].position));
        let mut cam = Camera::from_yaw_pitch(
            pa.lerp(pb, f),
            lerp(k[a].yaw, k[b].yaw),
            lerp(k[a].pitch, k[b].pitch),
        );
        cam.fov_y = fov_y;
        cam
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        };
        assert_eq!(p.camera(0, 1.0).position, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(p.camera(2, 1.0).position, Vec3::new(2.0, 1.0, 0.0));
        assert_eq!(p.camera(4, 1.0).position, Vec3::new(4.0, 1.0, 0.0));
        let mid = Camera::from_yaw_pitch(Vec3::ZERO, 20.0, 0.0).forward;
        assert!((p.camera(2, 1.0).forward - mid).length() < 1e-6);
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
