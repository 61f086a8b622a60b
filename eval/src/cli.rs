//! The command line: `texel-eval run`, `texel-eval suite`, `texel-eval survey`,
//! `texel-eval compare`, `texel-eval chart` and `texel-eval scale` (`crate::scale_cli`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand};
use glam::UVec2;
use indicatif::{ProgressBar, ProgressStyle};
use texel_eval::chart::write_charts;
use texel_eval::report::Report;
use texel_eval::runner::Method;
use texel_eval::suite::{ReferenceKind, RunPlan, run_plan, suite_plans, total_frames};
use texel_render::context::GpuContext;

/// Measures Texel's render methods along camera paths: shimmer, coverage error, hole rate
/// and frame time, written to DIR/report.json with charts (DIR/chart.png, DIR/chart.svg).
#[derive(Parser, Debug)]
#[command(name = "texel-eval", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The paths `texel-eval suite` flies.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum PathSet {
    /// The bundled paths (`SUITE_PATHS`).
    Bundled,
    /// The paths of the weak classes of views (`CLASS_PATHS`).
    Classes,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Runs methods along one camera path on one level.
    Run {
        /// Level file (RON).
        #[arg(long)]
        level: PathBuf,
        /// Camera-path file (RON).
        #[arg(long)]
        path: PathBuf,
        /// Take the level's animators off first: what moves stands still as ordinary
        /// geometry (the still-world baseline of a path with motion in view).
        #[arg(long)]
        freeze: bool,
        #[command(flatten)]
        common: Common,
    },
    /// Runs every bundled path on its level (stone_circle, colonnade, textured, terrain_hills,
    /// moving_parts, sprites), or the weak classes' paths (`--set classes`), with every method.
    Suite {
        /// The assets folder holding levels/ and paths/.
        #[arg(long, default_value = "assets")]
        assets: PathBuf,
        /// Which paths: `bundled` (the suite's 22) or `classes` (the ten written for the weak
        /// classes of views, `paths/classes/`; fly them with splat-paper too for the
        /// `crossings` table).
        #[arg(long, value_enum, default_value = "bundled")]
        set: PathSet,
        /// Random walks per level flown besides the bundled paths (naive and splat, seed 1,
        /// written to DIR/paths/LEVEL_survey_NN.ron); table.md lists the worst. 0: none.
        #[arg(long, default_value_t = 3)]
        survey: u32,
        #[command(flatten)]
        common: Common,
    },
    /// Flies random walks through one level (made from a seed, clear of its surfaces,
    /// toward its content) with the methods, so a change is judged on views the bundled
    /// paths do not fly: writes the walks (DIR/paths/survey_NN.ron, for `run` and
    /// `compare`), report.json and charts, and DIR/survey.md (each walk's shimmer per
    /// method, and naive's over splat's).
    Survey(SurveyArgs),
    /// Writes the methods side by side along one path as an animated GIF (DIR/NAME.gif),
    /// each frame's shimmer under each method (the values `run` reports), and the per-frame
    /// numbers as DIR/NAME.json.
    Compare(CompareArgs),
    /// Rewrites the results tables in Markdown files from the reports they name: each block
    /// between `<!-- texel-eval table=shimmer|colour|speed|crossings report=FILE [rows=level:path,...]
    /// [methods=...] [passes=...] -->` and `<!-- /texel-eval -->` (FILE relative to the
    /// Markdown file's folder). Files are replaced atomically.
    Tables {
        /// Markdown files to rewrite (README.md, docs/guide/*.md, ...).
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Change nothing: list the files whose tables differ from their reports, and fail
        /// if any does.
        #[arg(long)]
        check: bool,
    },
    /// Measures frame cost and memory against level size: generated towns of each count
    /// (`texel-run gen`'s generator) walked down their street, each in a process of its
    /// own, and a bundled level as the reference; writes scale.json, scale.md and a chart
    /// (scale.png, scale.svg) into --out.
    Scale(crate::scale_cli::ScaleArgs),
    /// One measurement of `scale` (run by it in a process of its own).
    #[command(hide = true)]
    ScaleOne(crate::scale_cli::ScaleOneArgs),
    /// Redraws the charts (and table.md) of an existing report.
    Chart {
        /// The report.json to read.
        #[arg(long)]
        report: PathBuf,
        /// Directory to write chart.png, chart.svg and table.md into.
        #[arg(long)]
        out: PathBuf,
    },
}

#[derive(Args, Debug)]
struct Common {
    /// Comma-separated methods: raster, naive, snap, cubemap, splat-paper, splat, march;
    /// also splat-facing (splat with sprites turned toward the camera, to compare).
    #[arg(
        long,
        default_value = "raster,naive,snap,cubemap,splat-paper,splat,march"
    )]
    methods: String,
    /// Comma-separated cube-face resolutions (texels per face edge).
    #[arg(long, default_value = "64,128")]
    face_res: String,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "320x180")]
    size: String,
    /// Reference G-buffer: gpu (plain raster) or cpu (ray cast).
    #[arg(long, default_value = "gpu")]
    reference: String,
    /// Output directory (report.json, chart.png, chart.svg, table.md).
    #[arg(long)]
    out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

/// Parses the arguments and runs the command.
pub fn main() -> Result<()> {
    let cli = Cli::parse();
    let command_line = std::env::args().collect::<Vec<_>>().join(" ");
    match cli.command {
        Command::Run {
            level,
            path,
            freeze,
            common,
        } => {
            let plan = RunPlan {
                level,
                path,
                methods: parse_methods(&common.methods)?,
                face_res: parse_list(&common.face_res, "--face-res")?,
                size: parse_size(&common.size)?,
                freeze,
                first_frames: None,
            };
            execute(&[plan], &common, command_line).map(drop)
        }
        Command::Suite {
            assets,
            set,
            survey,
            common,
        } => {
            let methods = parse_methods(&common.methods)?;
            let face_res = parse_list(&common.face_res, "--face-res")?;
            let size = parse_size(&common.size)?;
            let set = match set {
                PathSet::Bundled => texel_eval::suite::SUITE_PATHS.as_slice(),
                PathSet::Classes => texel_eval::suite::CLASS_PATHS.as_slice(),
            };
            let plans = suite_plans(&assets, set, &methods, (&face_res, size));
            let walks = suite_walks(&assets, survey, &common.out, (&methods, &face_res, size))?;
            execute_with_survey(&plans, &walks, &common, command_line).map(drop)
        }
        Command::Compare(args) => compare(&args),
        Command::Survey(args) => survey(&args, command_line),
        Command::Tables { files, check } => tables(&files, check),
        Command::Scale(args) => crate::scale_cli::scale(&args),
        Command::ScaleOne(args) => crate::scale_cli::scale_one(&args),
        Command::Chart { report, out } => {
            let r = Report::load(&report)?;
            write_outputs(&r, &out, false)
        }
    }
}

/// The suite's surveyed walks: `count` per level of the bundled paths, flown by the naive
/// and splat of `methods`.
fn suite_walks(
    assets: &Path,
    count: u32,
    out: &Path,
    (methods, face_res, size): (&[Method], &[u32], UVec2),
) -> Result<Vec<RunPlan>> {
    if count > 50 {
        bail!("--survey must be 0..=50 walks a level, got {count}");
    }
    let flown: Vec<Method> = (methods.iter().copied())
        .filter(|m| matches!(m, Method::Naive | Method::Splat))
        .collect();
    if count == 0 || flown.is_empty() {
        return Ok(Vec::new());
    }
    let mut levels: Vec<&str> = Vec::new();
    for (level, _) in texel_eval::suite::SUITE_PATHS {
        if !levels.contains(&level) {
            levels.push(level);
        }
    }
    let mut plans = Vec::new();
    for name in levels {
        let file = assets.join("levels").join(format!("{name}.ron"));
        let level = texel_runtime::load::load_level(&file)?;
        let spec = texel_eval::survey::SurveySpec {
            count,
            ..texel_eval::survey::SurveySpec::new(level.scene.settings.cell_size)
        };
        let (walks, _) = texel_eval::survey::walk_plans(
            (&file, &level),
            &spec,
            (&out.join("paths"), &format!("{name}_survey_")),
            (&flown, face_res, size),
        )?;
        plans.extend(walks);
    }
    Ok(plans)
}

fn execute(plans: &[RunPlan], common: &Common, command: String) -> Result<Report> {
    execute_with_survey(plans, &[], common, command)
}

/// Runs `plans` and `walks` (surveyed walks, kept apart in the report's `survey`) and writes
/// the outputs.
fn execute_with_survey(
    plans: &[RunPlan],
    walks: &[RunPlan],
    common: &Common,
    command: String,
) -> Result<Report> {
    let reference = match common.reference.as_str() {
        "gpu" => ReferenceKind::Gpu,
        "cpu" => ReferenceKind::Cpu,
        other => bail!("--reference must be gpu or cpu, got `{other}`"),
    };
    std::fs::create_dir_all(&common.out)
        .with_context(|| format!("creating {}", common.out.display()))?;
    let started = Instant::now();
    let total = total_frames(plans)? + total_frames(walks)?;
    let ctx = GpuContext::headless()?;
    let bar = if common.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} frames (eta {eta}) {msg}",
        )
        .context("progress style")?
        .progress_chars("=> "),
    );
    let mut report = Report {
        adapter: ctx.describe(),
        command,
        stamp: texel_eval::stamp::Stamp::now(),
        ..Default::default()
    };
    for plan in plans {
        let records = run_plan(&ctx, plan, reference, &mut |label: &str| {
            bar.set_message(label.to_owned());
            bar.inc(1);
        })
        .with_context(|| format!("{} along {}", plan.level.display(), plan.path.display()))?;
        report.runs.extend(records);
    }
    for plan in walks {
        let records = run_plan(&ctx, plan, reference, &mut |label: &str| {
            bar.set_message(label.to_owned());
            bar.inc(1);
        })
        .with_context(|| format!("{} along {}", plan.level.display(), plan.path.display()))?;
        report.survey.extend(records);
    }
    bar.finish_and_clear();
    report.duration_s = started.elapsed().as_secs_f64();
    write_outputs(&report, &common.out, true)?;
    eprintln!(
        "{} runs in {:.0} s on {} → {}",
        report.runs.len(),
        report.duration_s,
        report.adapter,
        common.out.join("report.json").display()
    );
    Ok(report)
}

/// `survey`'s arguments: `run`'s (`Common`), but flying naive and splat at faces of 128 by
/// default.
#[derive(Args, Debug)]
#[command(
    mut_arg("methods", |a| a.default_value("naive,splat")),
    mut_arg("face_res", |a| a.default_value("128"))
)]
struct SurveyArgs {
    /// Level file (RON).
    #[arg(long)]
    level: PathBuf,
    /// How many walks.
    #[arg(long, default_value_t = 8)]
    count: u32,
    /// Seed of the walks (the same seed makes the same walks).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Frames of each walk (at 30 per second).
    #[arg(long, default_value_t = 40)]
    frames: u32,
    /// Slowest and fastest speed in probe cells per second, MIN,MAX.
    #[arg(long, default_value = "1.5,8")]
    speed: String,
    #[command(flatten)]
    common: Common,
}

/// The survey's walk spec from its arguments and the level's cell size.
fn survey_spec(args: &SurveyArgs, cell_size: f32) -> Result<texel_eval::survey::SurveySpec> {
    let (lo, hi) = args
        .speed
        .split_once(',')
        .with_context(|| format!("--speed must be MIN,MAX, got `{}`", args.speed))?;
    let num = |v: &str| -> Result<f32> {
        v.trim()
            .parse::<f32>()
            .ok()
            .filter(|x| x.is_finite() && *x > 0.0)
            .with_context(|| format!("--speed: `{v}` is not a positive number"))
    };
    let (lo, hi) = (num(lo)?, num(hi)?);
    if lo > hi {
        bail!("--speed: {lo} is above {hi}");
    }
    if args.count == 0 || args.count > 1000 {
        bail!("--count must be 1..=1000, got {}", args.count);
    }
    if !(2..=texel_runtime::path::MAX_FRAMES).contains(&args.frames) {
        bail!(
            "--frames must be 2..={}, got {}",
            texel_runtime::path::MAX_FRAMES,
            args.frames
        );
    }
    Ok(texel_eval::survey::SurveySpec {
        count: args.count,
        seed: args.seed,
        frames: args.frames,
        speed: (lo, hi),
        ..texel_eval::survey::SurveySpec::new(cell_size)
    })
}

fn survey(args: &SurveyArgs, command_line: String) -> Result<()> {
    let common = &args.common;
    let methods = parse_methods(&common.methods)?;
    let face_res = parse_list(&common.face_res, "--face-res")?;
    let size = parse_size(&common.size)?;
    let level = texel_runtime::load::load_level(&args.level)?;
    let spec = survey_spec(args, level.scene.settings.cell_size)?;
    let (plans, walks) = texel_eval::survey::walk_plans(
        (&args.level, &level),
        &spec,
        (&common.out.join("paths"), "survey_"),
        (&methods, &face_res, size),
    )?;
    let report = execute(&plans, common, command_line)?;
    let text = texel_eval::survey::survey_table(&report, &walks);
    let file = common.out.join("survey.md");
    std::fs::write(&file, &text).with_context(|| format!("writing {}", file.display()))?;
    println!("{text}");
    Ok(())
}

#[derive(Args, Debug)]
struct CompareArgs {
    /// Level file (RON).
    #[arg(long)]
    level: PathBuf,
    /// Camera-path file (RON).
    #[arg(long)]
    path: PathBuf,
    /// Comma-separated methods, left to right: raster, naive, snap, cubemap, splat-paper,
    /// splat, march, splat-facing.
    #[arg(long, default_value = "naive,snap,splat")]
    methods: String,
    /// Cube-face resolution of every method (texels per face edge).
    #[arg(long, default_value_t = 128)]
    face_res: u32,
    /// Size of each method's frames, WIDTHxHEIGHT.
    #[arg(long, default_value = "320x180")]
    size: String,
    /// Nearest-neighbour upscale of each panel in the GIF.
    #[arg(long, default_value_t = 2)]
    scale: u32,
    /// Frames per second of the GIF (default: the path's, 1/dt).
    #[arg(long)]
    fps: Option<f32>,
    /// Reference G-buffer: gpu (plain raster) or cpu (ray cast).
    #[arg(long, default_value = "gpu")]
    reference: String,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// File stem of the GIF and JSON.
    #[arg(long, default_value = "compare")]
    name: String,
    /// Show where each method flickers: the frame in grey, changed pixels red (magenta:
    /// from the eye probe), as the shimmer metric counts them.
    #[arg(long, conflicts_with_all = ["coverage", "colour"])]
    flicker: bool,
    /// Show where each method's colours differ from the raster's frame, as the colour
    /// error counts them: the frame in grey, each art pixel red by its error (full red at
    /// ΔE 0.1). Needs raster among --methods.
    #[arg(long, conflicts_with = "coverage")]
    colour: bool,
    /// Show where each method's silhouettes differ from the reference, as the coverage
    /// error counts them: the frame in grey, blue where it shows an object over the
    /// reference's sky, yellow sky over an object, red another object.
    #[arg(long)]
    coverage: bool,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

/// Checks the arguments of `compare` (before any GPU work) and makes its plan.
fn compare_plan(args: &CompareArgs) -> Result<texel_eval::compare::ComparePlan> {
    let reference = match args.reference.as_str() {
        "gpu" => ReferenceKind::Gpu,
        "cpu" => ReferenceKind::Cpu,
        other => bail!("--reference must be gpu or cpu, got `{other}`"),
    };
    let face_res = parse_list(&args.face_res.to_string(), "--face-res")?[0];
    if args.name.is_empty() || args.name.contains(['/', '\\']) {
        bail!(
            "--name must be a file stem (no directory), got `{}`",
            args.name
        );
    }
    if !(1..=16).contains(&args.scale) {
        bail!("--scale must be 1..=16, got {}", args.scale);
    }
    if let Some(fps) = args.fps
        && !(fps.is_finite() && (1.0..=100.0).contains(&fps))
    {
        bail!("--fps must be 1..=100, got {fps}");
    }
    Ok(texel_eval::compare::ComparePlan {
        level: args.level.clone(),
        path: args.path.clone(),
        methods: parse_methods(&args.methods)?,
        face_res,
        size: parse_size(&args.size)?,
        reference,
        overlay: if args.flicker {
            texel_eval::compare::Overlay::Flicker
        } else if args.coverage {
            texel_eval::compare::Overlay::Coverage
        } else if args.colour {
            texel_eval::compare::Overlay::Colour
        } else {
            texel_eval::compare::Overlay::Frames
        },
    })
}

fn compare(args: &CompareArgs) -> Result<()> {
    use texel_eval::compare::{compare_frames, run_compare, write_compare};
    let plan = compare_plan(args)?;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(compare_frames(&plan)?)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} frames (eta {eta}) {msg}",
        )
        .context("progress style")?
        .progress_chars("=> "),
    );
    let ctx = GpuContext::headless()?;
    let run = run_compare(&ctx, &plan, &mut |label: &str| {
        bar.set_message(label.to_owned());
        bar.inc(1);
    })
    .with_context(|| format!("{} along {}", plan.level.display(), plan.path.display()))?;
    bar.set_message("writing the GIF");
    let files = write_compare(&run, &args.out, &args.name, args.scale, args.fps)?;
    bar.finish_and_clear();
    for m in &run.methods {
        eprintln!(
            "{:>12}: mean shimmer {:.4}",
            m.method.name(),
            m.shimmer.mean
        );
    }
    eprintln!(
        "{} frames of {}×{} on {} → {} ({})",
        files.frames,
        files.size.x,
        files.size.y,
        ctx.describe(),
        files.gif.display(),
        files.json.display()
    );
    Ok(())
}

fn write_outputs(report: &Report, out: &Path, with_json: bool) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    if with_json {
        let file = out.join("report.json");
        std::fs::write(&file, serde_json::to_string_pretty(report)?)
            .with_context(|| format!("writing {}", file.display()))?;
    }
    let table = out.join("table.md");
    let text = format!(
        "{}\n{}{}",
        report.summary_table(),
        report.markdown_table(),
        texel_eval::survey::worst_walks_table(&report.survey, 5)
    );
    std::fs::write(&table, text).with_context(|| format!("writing {}", table.display()))?;
    write_charts(report, out, "chart")?;
    Ok(())
}

/// `texel-eval tables`: every file's blocks from their reports; with `check`, only which
/// files differ.
fn tables(files: &[PathBuf], check: bool) -> Result<()> {
    let mut stale = Vec::new();
    for file in files {
        let text =
            texel_scene::read::read_bounded_string(file, texel_scene::read::FileKind::Report)?;
        let new = texel_eval::tables::refresh(&text, file)?;
        if new == text {
            continue;
        }
        if check {
            stale.push(file.display().to_string());
        } else {
            let tmp = file.with_extension("md.tmp");
            std::fs::write(&tmp, &new).with_context(|| format!("writing {}", tmp.display()))?;
            std::fs::rename(&tmp, file).with_context(|| format!("replacing {}", file.display()))?;
            eprintln!("{}: tables rewritten", file.display());
        }
    }
    if !stale.is_empty() {
        bail!(
            "tables differ from their reports in {} (run `texel-eval tables` on them)",
            stale.join(", ")
        );
    }
    Ok(())
}

fn parse_methods(s: &str) -> Result<Vec<Method>> {
    let methods = s
        .split(',')
        .filter(|m| !m.trim().is_empty())
        .map(Method::parse)
        .collect::<Result<Vec<_>, _>>()?;
    if methods.is_empty() {
        bail!("--methods lists no method");
    }
    Ok(methods)
}

fn parse_list(s: &str, flag: &str) -> Result<Vec<u32>> {
    let v = s
        .split(',')
        .map(|x| {
            let n: u32 = x
                .trim()
                .parse()
                .with_context(|| format!("{flag}: `{x}` is not a whole number"))?;
            if !texel_scene::FACE_RESOLUTIONS.contains(&n) {
                bail!("{}", texel_scene::limits::face_resolution_error(flag, n));
            }
            Ok(n)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(v)
}

pub(crate) fn parse_size(s: &str) -> Result<UVec2> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .with_context(|| format!("--size must be WIDTHxHEIGHT, got `{s}`"))?;
    let parse = |v: &str| -> Result<u32> {
        let n: u32 = v
            .trim()
            .parse()
            .with_context(|| format!("--size: `{v}` is not a number"))?;
        if !(8..=4096).contains(&n) {
            bail!("--size: {n} is outside 8..=4096");
        }
        Ok(n)
    };
    Ok(UVec2::new(parse(w)?, parse(h)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_are_checked() {
        assert_eq!(parse_size("320x180").expect("valid"), UVec2::new(320, 180));
        assert!(parse_size("320").is_err() && parse_size("0x9").is_err());
        assert_eq!(
            parse_list("32, 64", "--face-res").expect("valid"),
            vec![32, 64]
        );
        assert!(parse_list("32,abc", "--face-res").is_err());
        assert_eq!(parse_methods("splat,naive").expect("valid").len(), 2);
        assert!(parse_methods("splat,bogus").is_err());
        Cli::try_parse_from(["texel-eval", "suite", "--out", "x"]).expect("suite parses");
        assert!(Cli::try_parse_from(["texel-eval", "run", "--out", "x"]).is_err());
    }

    #[test]
    fn the_suite_surveys_three_walks_a_level_unless_told() {
        let parse = |extra: &[&str]| {
            let mut v = vec!["texel-eval", "suite", "--out", "d"];
            v.extend_from_slice(extra);
            match Cli::try_parse_from(v).expect("suite parses").command {
                Command::Suite { survey, .. } => survey,
                other => panic!("not suite: {other:?}"),
            }
        };
        assert_eq!(parse(&[]), 3);
        assert_eq!(parse(&["--survey", "0"]), 0);
        let dir = tempfile::tempdir().expect("a temporary folder");
        let methods = [Method::Naive, Method::Splat];
        let too_many = suite_walks(
            Path::new("assets"),
            51,
            dir.path(),
            (&methods, &[64], UVec2::ONE),
        );
        assert!(too_many.unwrap_err().to_string().contains("--survey"));
        // No walk without naive or splat among the methods, or with none asked for.
        let none = suite_walks(
            Path::new("x"),
            3,
            dir.path(),
            (&[Method::Raster], &[64], UVec2::ONE),
        );
        assert!(none.expect("nothing to do").is_empty());
    }

    #[test]
    fn compare_arguments_parse_with_their_defaults() {
        let cli = Cli::try_parse_from([
            "texel-eval",
            "compare",
            "--level",
            "l.ron",
            "--path",
            "p.ron",
            "--out",
            "d",
        ])
        .expect("compare parses");
        let Command::Compare(a) = cli.command else {
            panic!("not compare: {:?}", cli.command);
        };
        assert_eq!(
            (a.methods.as_str(), a.face_res, a.scale),
            ("naive,snap,splat", 128, 2)
        );
        assert_eq!(
            (a.size.as_str(), a.fps, a.name.as_str()),
            ("320x180", None, "compare")
        );
        assert!(Cli::try_parse_from(["texel-eval", "compare", "--out", "d"]).is_err());
        let plan = compare_plan(&a).expect("defaults are valid");
        assert_eq!((plan.methods.len(), plan.face_res), (3, 128));
        let bad = [
            ("--scale", "0"),
            ("--fps", "0"),
            ("--face-res", "100000"),
            ("--name", "a/b"),
            ("--methods", "splat,bogus"),
            ("--size", "9"),
            ("--reference", "x"),
        ];
        for (flag, value) in bad {
            let cli = Cli::try_parse_from([
                "texel-eval",
                "compare",
                "--level",
                "l.ron",
                "--path",
                "p.ron",
                "--out",
                "d",
                flag,
                value,
            ])
            .expect("parses");
            let Command::Compare(a) = cli.command else {
                panic!("not compare");
            };
            assert!(compare_plan(&a).is_err(), "{flag} {value} accepted");
        }
    }

    #[test]
    fn survey_arguments_parse_with_their_defaults_and_bad_ones_are_refused() {
        let parse = |extra: &[&str]| {
            let mut v = vec!["texel-eval", "survey", "--level", "l.ron", "--out", "d"];
            v.extend_from_slice(extra);
            let cli = Cli::try_parse_from(v).expect("survey parses");
            let Command::Survey(a) = cli.command else {
                panic!("not survey");
            };
            a
        };
        let a = parse(&[]);
        assert_eq!(
            (
                a.count,
                a.seed,
                a.frames,
                a.common.methods.as_str(),
                a.common.face_res.as_str()
            ),
            (8, 1, 40, "naive,splat", "128")
        );
        let spec = survey_spec(&a, 2.0).expect("defaults are valid");
        assert_eq!(
            (spec.speed, spec.cell_size, spec.count),
            ((1.5, 8.0), 2.0, 8)
        );
        for bad in [
            &["--speed", "3"][..],
            &["--speed", "3,1"],
            &["--speed", "0,2"],
            &["--speed", "nan,2"],
            &["--count", "0"],
            &["--frames", "1"],
        ] {
            assert!(survey_spec(&parse(bad), 1.0).is_err(), "{bad:?} accepted");
        }
        assert!(Cli::try_parse_from(["texel-eval", "survey", "--out", "d"]).is_err());
    }
}
