//! The `texel-run` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use texel_scene::Level;
use texel_scene::read::{FileKind, read_bounded_string};

use crate::load::load_level;

/// Plays, renders and checks Texel levels.
#[derive(Debug, Parser)]
#[command(name = "texel-run", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Load a level and every asset it refers to; print a summary. Exits 2 on a bad level.
    Check {
        /// The level file (.ron).
        level: PathBuf,
        /// Also list the textured entities whose texture pixels are far from one per art
        /// pixel (probe texel) at the level's reference distance.
        #[arg(long)]
        density: bool,
        /// The output size the density is judged for, WIDTHxHEIGHT (it sets the face
        /// resolution of a level whose pixel scale is a pixel size).
        #[arg(long, default_value = "640x360", requires = "density")]
        size: String,
        /// Vertical field of view in degrees, for the density.
        #[arg(long, default_value_t = 60.0, requires = "density")]
        fov: f32,
    },
    /// Rewrite a level in canonical form (atomically), as the editor would save it.
    Fmt {
        /// The level files (.ron).
        #[arg(required = true)]
        levels: Vec<PathBuf>,
        /// Only report files that are not canonical; change nothing (exit 1 if any).
        #[arg(long)]
        check: bool,
    },
    /// Render a level offscreen to PNGs plus stats.json (pass times and counters per frame).
    Render(RenderArgs),
    /// Render many frames headless along a looping camera path and watch resident memory;
    /// exits 1 when it grew by more than --max-growth-mib after the first frames.
    Soak(SoakArgs),
    /// Generate a town or forest level of N entities at a constant density, deterministic
    /// from a seed (for benchmarks and tests of large levels).
    Gen(GenArgs),
    /// Open a window and walk through a level (exit status 1 without a display or GPU).
    Play {
        /// The level file (.ron).
        level: PathBuf,
        /// Window size, WIDTHxHEIGHT.
        #[arg(long, default_value = "1280x720")]
        size: String,
    },
}

/// Options of `texel-run render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The level file (.ron).
    pub level: PathBuf,
    /// One camera: x,y,z,yaw,pitch (degrees). Default: the level's player start.
    #[arg(long, conflicts_with = "path", allow_hyphen_values = true)]
    pub camera: Option<String>,
    /// A camera path file (.ron) to fly along.
    #[arg(long)]
    pub path: Option<PathBuf>,
    /// Frames to render (default: the path's, or 1).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360")]
    pub size: String,
    /// Cube-face resolution (default: the level's).
    #[arg(long)]
    pub face_res: Option<u32>,
    /// Scheduling: ours or paper.
    #[arg(long, default_value = "ours")]
    pub schedule: String,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 60.0)]
    pub fov: f32,
    /// Write a PNG of every frame (default: only the last).
    #[arg(long)]
    pub all_frames: bool,
    /// Output folder for PNGs and stats.json.
    #[arg(long)]
    pub out: PathBuf,
}

/// Options of `texel-run gen`.
#[derive(Debug, clap::Args)]
pub struct GenArgs {
    /// The kind of place.
    #[arg(long, value_enum, default_value = "town")]
    pub kind: crate::generate::Kind,
    /// Entities in all (ground, sun, lights and player start included).
    #[arg(long, default_value_t = 1000)]
    pub count: usize,
    /// Seed of every random choice: the same options write the same file.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Entities per 100 m² (the level's side grows with the square root of the count).
    #[arg(long, default_value_t = 4.0)]
    pub density: f32,
    /// Stand everything on a noise terrain instead of a flat plane.
    #[arg(long)]
    pub terrain: bool,
    /// Most point lights.
    #[arg(long, default_value_t = 64)]
    pub max_lights: usize,
    /// A glTF mesh to place copies of (repeat for several); written relative to the level.
    #[arg(long = "mesh")]
    pub meshes: Vec<PathBuf>,
    /// The level file to write (atomically).
    #[arg(long)]
    pub out: PathBuf,
}

/// Options of `texel-run soak`.
#[derive(Debug, clap::Args)]
pub struct SoakArgs {
    /// The level file (.ron).
    pub level: PathBuf,
    /// The camera path file (.ron) to fly along, looped.
    #[arg(long)]
    pub path: PathBuf,
    /// Frames to render in all.
    #[arg(long, default_value_t = 10_000)]
    pub frames: u32,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "160x90")]
    pub size: String,
    /// Cube-face resolution (default: the level's).
    #[arg(long)]
    pub face_res: Option<u32>,
    /// Frames between two memory samples.
    #[arg(long, default_value_t = 1000)]
    pub sample_every: u32,
    /// Largest growth of resident memory allowed from the settled baseline to the end, MiB.
    #[arg(long, default_value_t = 16.0)]
    pub max_growth_mib: f64,
}

/// Exit status for a bad level or asset.
pub const EXIT_BAD_INPUT: u8 = 2;

/// Runs a parsed command line; errors are printed to stderr as `path:line:column: message`.
pub fn run(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Check {
            level,
            density,
            size,
            fov,
        } => check(&level, density.then_some((size.as_str(), fov))),
        Command::Fmt { levels, check } => fmt(&levels, check),
        Command::Play { level, size } => play(&level, &size),
        Command::Render(args) => render(&args),
        Command::Soak(args) => soak(&args),
        Command::Gen(args) => gen_level(&args),
    }
}

fn gen_level(args: &GenArgs) -> ExitCode {
    match try_gen_level(args) {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("texel-run gen: {e:#}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

fn try_gen_level(args: &GenArgs) -> anyhow::Result<String> {
    use anyhow::Context as _;
    let out = std::path::absolute(&args.out).context("--out")?;
    let folder = out.parent().context("--out names no file")?;
    anyhow::ensure!(folder.is_dir(), "--out: no folder {}", folder.display());
    let mut meshes = Vec::new();
    for mesh in &args.meshes {
        anyhow::ensure!(mesh.is_file(), "--mesh: no file {}", mesh.display());
        meshes.push(texel_scene::assets::relative_path(&out, mesh));
    }
    let options = crate::generate::GenOptions {
        kind: args.kind,
        count: args.count,
        seed: args.seed,
        density: args.density,
        terrain: args.terrain,
        max_lights: args.max_lights,
        meshes,
    };
    let level = crate::generate::generate(&options)?;
    level.save(&out)?;
    let side = crate::generate::side(options.count, options.density);
    let lights = (level.entities.iter())
        .filter(|e| e.point_light.is_some())
        .count();
    Ok(format!(
        "{}: {} entities over {side:.0} × {side:.0} m, {lights} point lights (seed {})",
        out.display(),
        level.entities.len(),
        options.seed
    ))
}

fn soak(args: &SoakArgs) -> ExitCode {
    match soak_inner(args) {
        Ok(report) => {
            let growth = report.growth_mib();
            println!(
                "{}: {} frames on {}: resident {:.1} MiB at the start, {:.1} after {} frames, \
                 {:.1} at the end (peak {:.1}): {growth:+.1} MiB",
                args.level.display(),
                report.frames,
                report.adapter,
                report.start.rss_mib,
                report.settled.rss_mib,
                report.settled.frame,
                report.samples.last().map_or(0.0, |s| s.rss_mib),
                report.peak_mib
            );
            if growth > args.max_growth_mib {
                eprintln!(
                    "texel-run soak: resident memory grew {growth:.1} MiB (allowed {:.1})",
                    args.max_growth_mib
                );
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
        Err(e) if e.is::<crate::load::LoadError>() => {
            eprintln!("{e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
        Err(e) => {
            eprintln!("texel-run soak: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn soak_inner(args: &SoakArgs) -> anyhow::Result<crate::soak::SoakReport> {
    let (w, h) = crate::play::parse_size(&args.size).map_err(|e| anyhow::anyhow!("--size: {e}"))?;
    // Up to a million frames: a soak is meant to run long, but not for ever.
    if !(1..=1_000_000).contains(&args.frames) {
        anyhow::bail!("--frames must be 1..=1000000, got {}", args.frames);
    }
    if args.sample_every == 0 {
        anyhow::bail!("--sample-every must be at least 1");
    }
    if !(args.max_growth_mib.is_finite() && args.max_growth_mib >= 0.0) {
        anyhow::bail!("--max-growth-mib must be a finite number of MiB, at least 0");
    }
    if let Some(n) = args.face_res {
        check_face_res(n)?;
    }
    let path = crate::path::CameraPath::load(&args.path)?;
    let opts = crate::soak::SoakOptions {
        size: glam::UVec2::new(w, h),
        fov_y: path.fov_y(60f32.to_radians()),
        face_res: args.face_res,
        frames: args.frames,
        sample_every: args.sample_every,
    };
    crate::soak::soak(&args.level, &path, &opts, &mut |s| {
        eprintln!("frame {:>7}: resident {:.1} MiB", s.frame, s.rss_mib);
    })
}

fn play(path: &std::path::Path, size: &str) -> ExitCode {
    let size = match crate::play::parse_size(size) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("texel-run play: {e}");
            return ExitCode::FAILURE;
        }
    };
    let options = crate::play::PlayOptions {
        size,
        ..Default::default()
    };
    match crate::play::play(path, options) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<crate::load::LoadError>() => {
            eprintln!("{e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
        Err(e) => {
            eprintln!("texel-run play: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn check(path: &std::path::Path, density: Option<(&str, f32)>) -> ExitCode {
    // The numbers first, before anything is loaded.
    let viewport = match density.map(|(size, fov)| -> anyhow::Result<_> {
        let (w, h) = crate::play::parse_size(size).map_err(|e| anyhow::anyhow!("--size: {e}"))?;
        let fov = check_fov(fov)?;
        Ok((
            (w, h),
            crate::extract::Viewport {
                height: h,
                fov_y: fov.to_radians(),
            },
        ))
    }) {
        Some(Err(e)) => {
            eprintln!("texel-run check: {e:#}");
            return ExitCode::FAILURE;
        }
        Some(Ok(v)) => Some(v),
        None => None,
    };
    match load_level(path) {
        Ok(loaded) => {
            println!(
                "{}: ok: {}; {} mesh files ({} triangles), {} textures",
                path.display(),
                loaded.scene.kind_counts(),
                loaded.assets.len(),
                loaded.assets.triangle_count(),
                loaded.assets.texture_count()
            );
            if let Some((size, viewport)) = viewport {
                println!(
                    "{}",
                    crate::density_check::format_report(&loaded, viewport, size)
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

fn fmt(paths: &[PathBuf], check_only: bool) -> ExitCode {
    let mut status = ExitCode::SUCCESS;
    for path in paths {
        let result = (|| {
            let level = Level::load(path)?;
            let canonical = level.to_ron_string(path)?;
            let current = read_bounded_string(path, FileKind::Level).unwrap_or_default();
            if canonical == current {
                return Ok(false);
            }
            if !check_only {
                level.save(path)?;
            }
            Ok::<bool, texel_scene::LevelError>(true)
        })();
        match result {
            Ok(true) if check_only => {
                println!("{}: not canonical", path.display());
                status = ExitCode::FAILURE;
            }
            Ok(true) => println!("{}: rewritten", path.display()),
            Ok(false) => {}
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(EXIT_BAD_INPUT);
            }
        }
    }
    status
}

fn render(args: &RenderArgs) -> ExitCode {
    match render_inner(args) {
        Ok(record) => {
            let median = record.median_frame_ms;
            let sum = |f: fn(&texel_render::stats::Counters) -> u64| -> u64 {
                record.frames.iter().map(|r| f(&r.stats.counters)).sum()
            };
            let faces = sum(|c| u64::from(c.faces_captured)).max(1) as f64;
            let mb = |b: u64| b as f64 / 1e6;
            println!(
                "{}: {} frames on {}, median {median:.1} ms; {} faces captured, {:.0} objects \
                 and {:.0} triangles a face; stats in {}",
                args.level.display(),
                record.frames.len(),
                record.adapter,
                sum(|c| u64::from(c.faces_captured)),
                sum(|c| c.objects_captured) as f64 / faces,
                sum(|c| c.triangles_captured) as f64 / faces,
                args.out.join("stats.json").display()
            );
            if let Some(c) = record.frames.last().map(|f| f.stats.counters) {
                let peak = (record.peak_resident_bytes).map_or(String::new(), |b| {
                    format!("; peak resident {:.0} MB", mb(b))
                });
                println!(
                    "GPU memory: scene {:.1} MB, shadow trees {:.1} MB, textures {:.1} MB, \
                     probes {:.1} MB{peak}",
                    mb(c.gpu_scene_bytes),
                    mb(c.gpu_bvh_bytes),
                    mb(c.texture_bytes),
                    mb(c.gpu_probe_bytes),
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) if e.is::<crate::load::LoadError>() => {
            eprintln!("{e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
        Err(e) => {
            eprintln!("texel-run render: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn render_inner(args: &RenderArgs) -> anyhow::Result<crate::headless::RunRecord> {
    use crate::path::CameraPath;
    use texel_render::input::Schedule;
    // Every number is checked here, before the level is loaded or anything is created on the
    // GPU (the device's own limits are checked by `headless::render` once it has one).
    let (w, h) = crate::play::parse_size(&args.size).map_err(|e| anyhow::anyhow!("--size: {e}"))?;
    let schedule = match args.schedule.as_str() {
        "ours" => Schedule::Ours,
        "paper" => Schedule::Paper,
        other => anyhow::bail!("--schedule must be `ours` or `paper`, got `{other}`"),
    };
    let frames = args.frames.map(check_frames).transpose()?;
    let fov = check_fov(args.fov)?;
    if let Some(n) = args.face_res {
        check_face_res(n)?;
    }
    let mut path = match (&args.camera, &args.path) {
        (Some(c), _) => Some(CameraPath::still(parse_camera(c)?, 1)),
        (None, Some(p)) => Some(CameraPath::load(p)?),
        (None, None) => None,
    };
    if let (Some(n), Some(p)) = (frames, path.as_mut()) {
        p.frames = n;
    }
    let opts = crate::headless::RenderOptions {
        size: glam::UVec2::new(w, h),
        fov_y: fov.to_radians(),
        face_res: args.face_res,
        schedule,
        out: args.out.clone(),
        all_frames: args.all_frames,
        frames,
    };
    crate::headless::render(&args.level, path.as_ref(), &opts)
}

/// `--frames`: 1..=[`crate::path::MAX_FRAMES`], the range a camera path's `frames` has.
pub fn check_frames(n: u32) -> anyhow::Result<u32> {
    use crate::path::MAX_FRAMES;
    if (1..=MAX_FRAMES).contains(&n) {
        Ok(n)
    } else {
        anyhow::bail!("--frames must be 1..={MAX_FRAMES}, got {n}")
    }
}

/// `--fov`: finite and strictly between 1 and 170 degrees, as a camera path's perspective.
pub fn check_fov(deg: f32) -> anyhow::Result<f32> {
    if deg.is_finite() && deg > 1.0 && deg < 170.0 {
        Ok(deg)
    } else {
        anyhow::bail!("--fov must be a field of view in (1, 170) degrees, got {deg}")
    }
}

/// `--face-res`: within the engine's face resolutions.
pub fn check_face_res(n: u32) -> anyhow::Result<u32> {
    use texel_scene::limits::{FACE_RESOLUTIONS, face_resolution_error};
    if FACE_RESOLUTIONS.contains(&n) {
        Ok(n)
    } else {
        anyhow::bail!(
            "--face-res: {}",
            face_resolution_error("face resolution", n)
        )
    }
}

/// `--camera x,y,z,yaw,pitch`: five numbers checked as a level's (finite coordinates within
/// the level limit, pitch within ±89 degrees).
pub fn parse_camera(text: &str) -> anyhow::Result<crate::path::Keyframe> {
    use texel_scene::num::{check_coord, check_pitch};
    let v: Vec<f32> = text
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("--camera x,y,z,yaw,pitch: {e}"))?;
    let [x, y, z, yaw, pitch] = v[..] else {
        anyhow::bail!("--camera takes five numbers: x,y,z,yaw,pitch");
    };
    let named =
        |what: &str, r: Result<f32, String>| r.map_err(|e| anyhow::anyhow!("--camera {what}: {e}"));
    Ok(crate::path::Keyframe {
        position: (
            named("x", check_coord(x))?,
            named("y", check_coord(y))?,
            named("z", check_coord(z))?,
        ),
        yaw: named("yaw", check_coord(yaw))?,
        pitch: named("pitch", check_pitch(pitch))?,
    })
}
