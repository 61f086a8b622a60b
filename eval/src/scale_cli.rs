//! `texel-eval scale`: generates towns of each size, measures each in a process of its own
//! (`texel-eval scale-one`, hidden), and writes the report ([`texel_eval::scale`]).

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use clap::Args;
use texel_eval::scale::{ScaleReport, ScaleRow, Walk, measure, street_walk, write};
use texel_runtime::generate::{GenOptions, generate};
use texel_runtime::path::CameraPath;

/// Default vertical field of view, degrees (as `texel-run render`'s).
const FOV_DEGREES: f32 = 60.0;

#[derive(Args, Debug)]
pub(crate) struct ScaleArgs {
    /// Comma-separated entity counts of the generated towns (8 to 100000 each).
    #[arg(long, default_value = "100,1000,10000,100000")]
    counts: String,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720")]
    size: String,
    /// Cube-face resolution (texels per face edge).
    #[arg(long, default_value_t = 128)]
    face_res: u32,
    /// Frames of each town's walk down its street (at 30 a second).
    #[arg(long, default_value_t = 30)]
    frames: u32,
    /// Walking speed down the street, m/s (the stone circle's walk_cells walks at 2.5; a
    /// faster walk crosses more probe cells, so it captures and lights more a frame).
    #[arg(long, default_value_t = 2.5)]
    speed: f32,
    /// glTF meshes the towns repeat (default: crate.glb and arch.glb of --assets).
    #[arg(long = "mesh")]
    meshes: Vec<PathBuf>,
    /// The assets folder (default meshes, the reference level and its path).
    #[arg(long, default_value = "assets")]
    assets: PathBuf,
    /// Reference level walked along --reference-path in the same run, whose frame the
    /// towns' are divided by (default: the stone circle along walk_cells); `none` for none.
    #[arg(long)]
    reference: Option<String>,
    /// Camera path of the reference level (default: --assets/paths/walk_cells.ron).
    #[arg(long)]
    reference_path: Option<PathBuf>,
    /// Most point lights a town has (its lamp posts carry them; fewer lamp posts light).
    #[arg(long, default_value_t = 64)]
    max_lights: usize,
    /// Seed of the generated towns.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output directory: scale.json, scale.md, scale.png, scale.svg.
    #[arg(long)]
    out: PathBuf,
    /// Keep the generated levels and their walks in this folder (by default they are
    /// written to a temporary folder and removed: a town of 100,000 is a 37 MB file).
    #[arg(long)]
    levels: Option<PathBuf>,
}

/// One measurement, in this process (what `scale` starts for each level).
#[derive(Args, Debug)]
pub(crate) struct ScaleOneArgs {
    #[arg(long)]
    level: PathBuf,
    #[arg(long)]
    path: PathBuf,
    #[arg(long)]
    size: String,
    #[arg(long)]
    face_res: u32,
    #[arg(long)]
    label: String,
}

pub(crate) fn scale_one(args: &ScaleOneArgs) -> Result<()> {
    let path = CameraPath::load(&args.path).with_context(|| args.path.display().to_string())?;
    let walk = Walk {
        size: crate::cli::parse_size(&args.size)?,
        face_res: args.face_res,
        fov_y: path.fov_y(FOV_DEGREES.to_radians()),
    };
    let row = measure(&args.level, &path, walk, &args.label)?;
    println!("{}", serde_json::to_string(&row)?);
    Ok(())
}

pub(crate) fn scale(args: &ScaleArgs) -> Result<()> {
    crate::cli::parse_size(&args.size)?;
    if !(args.speed.is_finite() && args.speed > 0.0 && args.speed <= 100.0) {
        bail!("--speed: {} is not within 0..=100 m/s", args.speed);
    }
    let counts = parse_counts(&args.counts)?;
    let temporary = std::env::temp_dir().join(format!("texel-scale-{}", std::process::id()));
    let levels = args.levels.clone().unwrap_or_else(|| temporary.clone());
    std::fs::create_dir_all(&levels).with_context(|| format!("creating {}", levels.display()))?;
    let result = measure_all(args, &counts, &levels);
    if args.levels.is_none() {
        let _ = std::fs::remove_dir_all(&temporary);
    }
    let (reference, towns) = result?;
    let size = crate::cli::parse_size(&args.size)?;
    let adapter = (reference.iter().chain(&towns))
        .map(|r| r.adapter.clone())
        .next()
        .unwrap_or_default();
    let args_line: Vec<String> = std::env::args().skip(1).collect();
    let report = ScaleReport {
        command: format!("texel-eval {}", args_line.join(" ")),
        stamp: texel_eval::stamp::Stamp::now().line(),
        adapter,
        size: size.to_array(),
        face_res: args.face_res,
        frames: args.frames,
        speed: args.speed,
        reference,
        towns,
    };
    write(&report, &args.out)?;
    println!("{}", report.table());
    println!("wrote {}", args.out.join("scale.md").display());
    Ok(())
}

/// The reference's row (if any) and each town's, generated into `levels`.
fn measure_all(
    args: &ScaleArgs,
    counts: &[usize],
    levels: &Path,
) -> Result<(Option<ScaleRow>, Vec<ScaleRow>)> {
    let meshes = match args.meshes.is_empty() {
        true => ["crate.glb", "arch.glb"]
            .map(|m| args.assets.join("meshes").join(m))
            .to_vec(),
        false => args.meshes.clone(),
    };
    let reference = match args.reference.as_deref() {
        Some("none") => None,
        Some(level) => Some(PathBuf::from(level)),
        None => Some(args.assets.join("levels/stone_circle.ron")),
    };
    let reference = match reference {
        None => None,
        Some(level) => {
            let path = (args.reference_path.clone())
                .unwrap_or_else(|| args.assets.join("paths/walk_cells.ron"));
            eprintln!("reference {}: measuring", level.display());
            let label = level
                .file_stem()
                .map_or("reference".into(), |s| s.to_string_lossy().into_owned());
            Some(run_child(args, &level, &path, &label)?)
        }
    };
    let mut towns = Vec::new();
    for &n in counts {
        let level = levels.join(format!("town_{n}.ron"));
        eprintln!("town of {n}: generating {}", level.display());
        let options = GenOptions {
            count: n,
            seed: args.seed,
            max_lights: args.max_lights,
            meshes: (meshes.iter())
                .map(|m| texel_scene::assets::relative_path(&level, m))
                .collect(),
            ..GenOptions::default()
        };
        for m in &meshes {
            if !m.is_file() {
                bail!("--mesh: no file {}", m.display());
            }
        }
        generate(&options)?.save(&level)?;
        let walk = levels.join(format!("town_{n}_street.ron"));
        std::fs::write(
            &walk,
            street_walk(n, options.density, args.frames, args.speed),
        )
        .with_context(|| format!("writing {}", walk.display()))?;
        eprintln!("town of {n}: measuring");
        let row = run_child(args, &level, &walk, "town")?;
        match (&row.frame_ms, &row.error) {
            (Some(ms), _) => eprintln!("town of {n}: median frame {ms:.0} ms"),
            (None, e) => eprintln!("town of {n}: refused: {}", e.as_deref().unwrap_or("?")),
        }
        towns.push(row);
    }
    Ok((reference, towns))
}

/// Measures `level` along `path` in a new process of this program; its one line of JSON.
fn run_child(args: &ScaleArgs, level: &Path, path: &Path, label: &str) -> Result<ScaleRow> {
    let exe = std::env::current_exe().context("finding texel-eval itself")?;
    let out = Command::new(exe)
        .arg("scale-one")
        .arg("--level")
        .arg(level)
        .arg("--path")
        .arg(path)
        .args(["--size", &args.size, "--label", label])
        .args(["--face-res", &args.face_res.to_string()])
        .stderr(std::process::Stdio::inherit())
        .output()
        .context("starting a measurement")?;
    if !out.status.success() {
        bail!("measuring {} failed ({})", level.display(), out.status);
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().last().unwrap_or_default();
    serde_json::from_str(line).with_context(|| format!("the measurement of {}", level.display()))
}

/// `100,1000` → [100, 1000], each within the generator's bounds.
fn parse_counts(s: &str) -> Result<Vec<usize>> {
    let mut counts = Vec::new();
    for part in s.split(',') {
        let n: usize =
            (part.trim().parse()).with_context(|| format!("--counts: `{part}` is not a number"))?;
        let (lo, hi) = (
            texel_runtime::generate::MIN_COUNT,
            texel_runtime::generate::MAX_COUNT,
        );
        if !(lo..=hi).contains(&n) {
            bail!("--counts: {n} is outside {lo}..={hi}");
        }
        counts.push(n);
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    #[test]
    fn counts_are_checked() {
        assert_eq!(
            super::parse_counts("100, 1000").expect("valid"),
            [100, 1000]
        );
        assert!(super::parse_counts("3").is_err() && super::parse_counts("x").is_err());
        assert!(super::parse_counts("1000000").is_err());
    }
}
