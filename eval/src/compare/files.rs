//! Writing the comparison: its frames as one looping GIF with a palette shared by every
//! frame, and its numbers as JSON beside it.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::UVec2;

use super::panels::check_run;
use super::{
    Canvas, CompareError, CompareNumbers, CompareRun, Layout, MethodNumbers, compose_frame,
};

/// Maps colours to a palette of at most 256 shared by every frame.
struct Palette {
    rgb: Vec<u8>,
    exact: HashMap<[u8; 3], u8>,
    quant: Option<color_quant::NeuQuant>,
}

impl Palette {
    /// The palette of `frames`: their colours when at most 256, else NeuQuant's.
    fn of(frames: &[&Canvas]) -> Palette {
        let mut exact: HashMap<[u8; 3], u8> = HashMap::new();
        'scan: for f in frames {
            for p in f.rgb.chunks_exact(3) {
                let k = [p[0], p[1], p[2]];
                if !exact.contains_key(&k) {
                    if exact.len() == 256 {
                        exact.clear();
                        break 'scan;
                    }
                    exact.insert(k, exact.len() as u8);
                }
            }
        }
        if !exact.is_empty() {
            let mut rgb = vec![0; exact.len() * 3];
            for (k, i) in &exact {
                let i = usize::from(*i) * 3;
                rgb[i..i + 3].copy_from_slice(k);
            }
            return Palette {
                rgb,
                exact,
                quant: None,
            };
        }
        // Sample at most about a million pixels over all frames.
        let total: usize = frames.iter().map(|f| f.rgb.len() / 3).sum();
        let step = (total / 1_000_000).max(1);
        let mut samples = Vec::with_capacity(total / step * 4 + 4);
        let mut k = 0;
        for f in frames {
            for p in f.rgb.chunks_exact(3) {
                if k % step == 0 {
                    samples.extend_from_slice(&[p[0], p[1], p[2], 255]);
                }
                k += 1;
            }
        }
        let nq = color_quant::NeuQuant::new(10, 256, &samples);
        Palette {
            rgb: nq.color_map_rgb(),
            exact: HashMap::new(),
            quant: Some(nq),
        }
    }

    fn index(&mut self, frame: &Canvas) -> Vec<u8> {
        frame
            .rgb
            .chunks_exact(3)
            .map(|p| {
                let k = [p[0], p[1], p[2]];
                if let Some(i) = self.exact.get(&k) {
                    return *i;
                }
                let i = self
                    .quant
                    .as_ref()
                    .map_or(0, |q| q.index_of(&[p[0], p[1], p[2], 255]) as u8);
                self.exact.insert(k, i);
                i
            })
            .collect()
    }
}

/// What [`write_compare`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareFiles {
    /// The animated GIF.
    pub gif: PathBuf,
    /// The per-frame numbers.
    pub json: PathBuf,
    /// Frames in the GIF.
    pub frames: u32,
    /// Width and height of the GIF.
    pub size: UVec2,
}

/// The GIF frame delay, in hundredths of a second, of `fps` (at least 2: browsers slow
/// shorter delays down to 10).
pub fn gif_delay(fps: f32) -> u16 {
    (100.0 / fps.max(0.01))
        .round()
        .clamp(2.0, f32::from(u16::MAX)) as u16
}

/// Writes `dir/<name>.gif` (looping forever, `fps` frames per second, default the path's)
/// and `dir/<name>.json` of `run`, the panels upscaled `scale` times.
pub fn write_compare(
    run: &CompareRun,
    dir: &Path,
    name: &str,
    scale: u32,
    fps: Option<f32>,
) -> Result<CompareFiles, CompareError> {
    let frames = check_run(run)?;
    let layout = Layout::new(run.methods.len() as u32, run.size, scale)?;
    let fps = fps.unwrap_or(if run.dt > 0.0 { 1.0 / run.dt } else { 30.0 });
    if !(fps.is_finite() && fps > 0.0) {
        return Err(CompareError::Layout(format!(
            "frames per second must be positive, got {fps}"
        )));
    }
    let io = |file: &Path| {
        let file = file.to_path_buf();
        move |source| CompareError::Io { file, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let gif_file = dir.join(format!("{name}.gif"));
    let json_file = dir.join(format!("{name}.json"));

    let composed = (0..frames as usize)
        .map(|t| compose_frame(run, &layout, scale, t))
        .collect::<Result<Vec<_>, _>>()?;
    let mut palette = Palette::of(&composed.iter().collect::<Vec<_>>());
    let gif_err = |e: gif::EncodingError| CompareError::Gif(gif_file.clone(), e.to_string());
    let file = std::fs::File::create(&gif_file).map_err(io(&gif_file))?;
    let (w, h) = (layout.frame.x as u16, layout.frame.y as u16);
    let mut encoder =
        gif::Encoder::new(std::io::BufWriter::new(file), w, h, &palette.rgb).map_err(gif_err)?;
    encoder.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
    let delay = gif_delay(fps);
    for canvas in &composed {
        let mut frame = gif::Frame::from_indexed_pixels(w, h, palette.index(canvas), None);
        frame.delay = delay;
        encoder.write_frame(&frame).map_err(gif_err)?;
    }
    encoder.into_inner().map_err(gif_err)?;

    let numbers = CompareNumbers {
        level: run.level.clone(),
        path: run.path.clone(),
        face_res: run.face_res,
        size: run.size.to_array(),
        scale,
        frames,
        fps,
        methods: run
            .methods
            .iter()
            .map(|m| MethodNumbers {
                method: m.method.name().to_owned(),
                shimmer: m.shimmer,
                shimmer_per_frame: m.shimmer_per_frame.clone(),
            })
            .collect(),
    };
    let text = serde_json::to_string_pretty(&numbers)
        .map_err(|e| CompareError::Layout(format!("serialising the numbers: {e}")))?;
    std::fs::write(&json_file, text).map_err(io(&json_file))?;
    Ok(CompareFiles {
        gif: gif_file,
        json: json_file,
        frames,
        size: layout.frame,
    })
}
