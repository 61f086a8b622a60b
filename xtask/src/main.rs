//! `cargo xtask`: the one entry point for setting up, running and testing Texel.
//!
//! Texel renders through wgpu, and its tests and tools need things Cargo cannot
//! provide: a Vulkan loader, a Vulkan driver that works without a GPU (Mesa's
//! lavapipe), and an X server for window tests (Xvfb). They also need a
//! particular environment (single-threaded GPU tests, the Vulkan backend, GPU
//! tests that fail rather than skip). Rather than spreading that knowledge over
//! shell scripts and CI files, this crate holds it in plain Rust with no
//! dependencies, so it compiles in seconds on any machine with a toolchain:
//!
//! * `cargo xtask setup` checks the system packages and installs the missing
//!   ones with `apt-get` when it can (root or passwordless sudo), or says exactly
//!   what to install when it cannot;
//! * `cargo xtask run [-- ARGS]` does the setup, then runs the project's main job;
//! * `cargo xtask test` does the setup, then runs formatting, clippy, all tests
//!   (benches once, in test mode) and doc tests, stopping at the first failure.
//!
//! The decisions (argument parsing, what to install and how, which steps to run)
//! are pure functions with unit tests; the rest is thin glue around processes.

use std::ffi::OsString;
use std::fmt;
use std::fs;
use std::io::{self, Write};
use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::thread;
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------

/// The project's main job, run by `cargo xtask run`.
///
/// This is the one place to change when the main job changes (it will become
/// the `texel-editor` binary). It is built in the debug profile, like the tests,
/// so running it after `cargo xtask test` builds nothing twice.
const MAIN_JOB: MainJob = MainJob {
    package: "texel_editor",
    bin: "texel-editor",
    default_args: &["assets/levels/stone_circle.ron"],
    // The editor is a window on the user's display; without one it says so and exits
    // (rather than running invisibly on a virtual display).
    needs_display: false,
};

/// The Debian/Ubuntu packages that provide everything in [`Requirement::ALL`].
const APT_PACKAGES: &[&str] = &[
    "mesa-vulkan-drivers",
    "libvulkan1",
    "xvfb",
    "xauth",
    "chromium-common",
];

/// SwiftShader's Vulkan ICD manifest as Debian's `chromium-common` installs it: the second,
/// independent Vulkan driver the GPU tests also run on.
const SWIFTSHADER_ICD: &str = "/usr/lib/chromium/vk_swiftshader_icd.json";

/// What the SwiftShader run's adapter name must contain (`texel_render::context::test_context`
/// checks it), so the second run cannot silently fall back to lavapipe.
const SWIFTSHADER_ADAPTER: &str = "SwiftShader";

/// Directories where Vulkan ICD manifests (driver descriptions) live.
const ICD_DIRS: &[&str] = &["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"];

/// The first X display number tried for the virtual X server.
const FIRST_XVFB_DISPLAY: u32 = 99;

/// How many display numbers (from [`FIRST_XVFB_DISPLAY`]) are tried before giving up.
const XVFB_DISPLAY_TRIES: u32 = 20;

/// Arguments given to Xvfb after the display name.
const XVFB_ARGS: &[&str] = &["-screen", "0", "1280x800x24", "-nolisten", "tcp"];

/// How long to wait for Xvfb to create its socket.
const XVFB_START_TIMEOUT: Duration = Duration::from_secs(10);

/// A binary of the workspace that `cargo xtask run` builds and runs.
#[derive(Clone, Copy, Debug)]
struct MainJob {
    /// The Cargo package holding the binary.
    package: &'static str,
    /// The binary target's name.
    bin: &'static str,
    /// Arguments used when the user gives none after `--`.
    default_args: &'static [&'static str],
    /// Whether the job opens a window (an Xvfb display is started if none exists).
    needs_display: bool,
}

impl MainJob {
    /// The Cargo step that runs this job with `args` (or the defaults when `None`).
    fn step(&self, args: Option<&[String]>) -> Step {
        let mut cargo_args = strings(&["run", "-p", self.package, "--bin", self.bin, "--"]);
        match args {
            Some(args) => cargo_args.extend(args.iter().cloned()),
            None => cargo_args.extend(strings(self.default_args)),
        }
        Step {
            args: cargo_args,
            env: Vec::new(),
            needs_display: self.needs_display,
        }
    }
}

/// The steps of `cargo xtask test`, in order.
///
/// GPU tests must run one at a time on lavapipe. That is asked of libtest with
/// `RUST_TEST_THREADS=1` rather than `-- --test-threads=1`: `--all-targets`
/// also runs criterion benches (once, in test mode), and criterion rejects
/// `--test-threads` as an unknown argument, while both ignore or honour the
/// variable correctly. GPU and window tests fail when no adapter or display exists
/// (`TEXEL_ALLOW_NO_GPU` / `TEXEL_ALLOW_NO_DISPLAY` would skip them; CI never sets
/// them). `--no-fail-fast`: a failing test binary does
/// not hide the others' results (a SwiftShader failure in one crate's tests had
/// left the later crates untested in that step).
fn test_steps() -> Vec<Step> {
    let test_env = vec![("RUST_TEST_THREADS".to_owned(), "1".to_owned())];
    vec![
        Step::cargo(&["fmt", "--all", "--", "--check"]),
        Step::cargo(&[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ]),
        Step {
            args: strings(&["test", "--workspace", "--all-targets", "--no-fail-fast"]),
            env: test_env.clone(),
            needs_display: true,
        },
        Step {
            args: strings(&["test", "--workspace", "--doc", "--no-fail-fast"]),
            env: test_env.clone(),
            needs_display: false,
        },
        // Every test again on SwiftShader, a second conformant Vulkan (4-bit sub-pixel
        // precision, its own shader compiler and depth rounding), except the golden images,
        // which are lavapipe's pixels, and the one test that presents to a window: the
        // SwiftShader Chromium ships has no window-system surfaces (play says so, no panic).
        Step {
            args: strings(&[
                "test",
                "--workspace",
                "--tests",
                "--no-fail-fast",
                "--",
                "--skip",
                "golden_images",
                "--skip",
                "plays_five_frames_of_the_stone_circle_and_exits",
            ]),
            env: [
                test_env,
                vec![
                    ("VK_ICD_FILENAMES".to_owned(), SWIFTSHADER_ICD.to_owned()),
                    (
                        "TEXEL_EXPECT_ADAPTER".to_owned(),
                        SWIFTSHADER_ADAPTER.to_owned(),
                    ),
                ],
            ]
            .concat(),
            needs_display: true,
        },
    ]
}

// ---------------------------------------------------------------------------
// Entry point and errors
// ---------------------------------------------------------------------------

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let command = match parse_args(&args) {
        Ok(command) => command,
        Err(error) => {
            eprintln!("error: {error}\n");
            eprintln!("{}", usage(error.topic));
            return ExitCode::from(2);
        }
    };
    let result = match command {
        Cli::Help(topic) => {
            // A closed pipe (`cargo xtask --help | head`) is not an error.
            let _ = writeln!(io::stdout(), "{}", usage(topic));
            Ok(())
        }
        Cli::Setup => ensure_system(),
        Cli::Run { args } => run_main_job(args.as_deref()),
        Cli::Test => run_tests(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("\nxtask: error: {}", error.message);
            ExitCode::from(error.exit_code)
        }
    }
}

/// A failure that ends xtask with a message and an exit code.
#[derive(Debug)]
struct Failure {
    /// What went wrong and, where possible, what to do about it.
    message: String,
    /// The process exit code (never 0).
    exit_code: u8,
}

impl Failure {
    /// A failure with exit code 1.
    fn new(message: impl Into<String>) -> Self {
        Failure {
            message: message.into(),
            exit_code: 1,
        }
    }
}

// ---------------------------------------------------------------------------
// Argument parsing
// ---------------------------------------------------------------------------

/// A subcommand, used to pick which help text to show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sub {
    /// `cargo xtask run`.
    Run,
    /// `cargo xtask test`.
    Test,
    /// `cargo xtask setup`.
    Setup,
}

impl Sub {
    /// The subcommand named `name`, if there is one.
    fn from_name(name: &str) -> Option<Sub> {
        match name {
            "run" => Some(Sub::Run),
            "test" => Some(Sub::Test),
            "setup" => Some(Sub::Setup),
            _ => None,
        }
    }

    /// The subcommand's name on the command line.
    fn name(self) -> &'static str {
        match self {
            Sub::Run => "run",
            Sub::Test => "test",
            Sub::Setup => "setup",
        }
    }
}

/// What the command line asks for.
#[derive(Debug, PartialEq, Eq)]
enum Cli {
    /// Print help for the tool (`None`) or for one subcommand.
    Help(Option<Sub>),
    /// Ensure system packages, then run the main job. `args` replaces the
    /// job's default arguments when given (everything after `--`).
    Run {
        /// The arguments after `--`, if `--` was given.
        args: Option<Vec<String>>,
    },
    /// Ensure system packages, then run the checks and tests.
    Test,
    /// Only ensure system packages.
    Setup,
}

/// A command line that could not be understood.
#[derive(Debug, PartialEq, Eq)]
struct UsageError {
    /// What was wrong.
    message: String,
    /// The help text to show with it.
    topic: Option<Sub>,
}

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// Whether `arg` asks for help.
fn is_help_flag(arg: &str) -> bool {
    arg == "-h" || arg == "--help"
}

/// Parses the arguments after the program name.
fn parse_args(args: &[String]) -> Result<Cli, UsageError> {
    let error = |message: String, topic| Err(UsageError { message, topic });
    let Some((first, rest)) = args.split_first() else {
        return error("no command given".to_owned(), None);
    };
    if is_help_flag(first) {
        return Ok(Cli::Help(None));
    }
    if first == "help" {
        return match rest {
            [] => Ok(Cli::Help(None)),
            [name] => match Sub::from_name(name) {
                Some(sub) => Ok(Cli::Help(Some(sub))),
                None => error(format!("no help for unknown command `{name}`"), None),
            },
            _ => error("`help` takes at most one command name".to_owned(), None),
        };
    }
    let Some(sub) = Sub::from_name(first) else {
        let what = if first.starts_with('-') {
            "option"
        } else {
            "command"
        };
        return error(format!("unknown {what} `{first}`"), None);
    };
    // Only `run` takes `--`; what follows it belongs to the program.
    let (options, program_args) = match rest.iter().position(|arg| arg == "--") {
        Some(index) if sub == Sub::Run => (&rest[..index], Some(rest[index + 1..].to_vec())),
        _ => (rest, None),
    };
    if options.iter().any(|arg| is_help_flag(arg)) {
        return Ok(Cli::Help(Some(sub)));
    }
    if let Some(arg) = options.first() {
        let hint = if sub == Sub::Run {
            "; give the program's arguments after `--`"
        } else {
            ""
        };
        return error(
            format!("unexpected argument `{arg}` for `{}`{hint}", sub.name()),
            Some(sub),
        );
    }
    Ok(match sub {
        Sub::Run => Cli::Run { args: program_args },
        Sub::Test => Cli::Test,
        Sub::Setup => Cli::Setup,
    })
}

/// The help text for the tool or one subcommand.
fn usage(topic: Option<Sub>) -> String {
    let job = MAIN_JOB;
    let default_run = format!(
        "cargo run -p {} --bin {} -- {}",
        job.package,
        job.bin,
        job.default_args.join(" ")
    );
    match topic {
        None => format!(
            "cargo xtask: set up, run and test Texel\n\
             \n\
             Usage: cargo xtask <COMMAND>\n\
             \n\
             Commands:\n\
             \x20 setup            Check the system packages (Vulkan loader, lavapipe,\n\
             \x20                  SwiftShader, Xvfb, xauth) and install the missing ones\n\
             \x20                  with apt-get\n\
             \x20 run [-- ARGS]    Set up, then run the main job:\n\
             \x20                    {default_run}\n\
             \x20 test             Set up, then fmt check, clippy, tests (and benches in test\n\
             \x20                  mode) and doc tests; stops after the first failing step\n\
             \x20 help [COMMAND]   Print this help or a command's help\n\
             \n\
             Options:\n\
             \x20 -h, --help       Print help (also after a command: `cargo xtask test --help`)"
        ),
        Some(Sub::Setup) => format!(
            "cargo xtask setup: check and install the system packages Texel needs\n\
             \n\
             Usage: cargo xtask setup\n\
             \n\
             Checks for the Vulkan loader (libvulkan.so.1), Mesa's lavapipe Vulkan driver\n\
             (lvp_icd*.json), SwiftShader ({SWIFTSHADER_ICD}), Xvfb and xauth.\n\
             If any is missing and this runs as root or\n\
             with passwordless sudo, runs `apt-get update` and\n\
             \x20 apt-get install -y --no-install-recommends {}\n\
             otherwise prints what to install and exits with an error.",
            APT_PACKAGES.join(" ")
        ),
        Some(Sub::Run) => format!(
            "cargo xtask run: set up, then run Texel's main job\n\
             \n\
             Usage: cargo xtask run [-- ARGS...]\n\
             \n\
             Runs `{default_run}`\n\
             from the workspace root (so relative paths are relative to it), in the debug\n\
             profile the tests use. Arguments after `--` replace the default arguments, e.g.\n\
             \x20 cargo xtask run -- check assets/levels/sandbox.ron\n\
             `cargo xtask run --` with nothing after it runs the program with no arguments."
        ),
        Some(Sub::Test) => {
            let steps: Vec<String> = test_steps()
                .iter()
                .map(|step| format!("  {}", step.describe()))
                .collect();
            format!(
                "cargo xtask test: set up, then run every check CI runs\n\
                 \n\
                 Usage: cargo xtask test\n\
                 \n\
                 Steps, in order (stops after the first failing step; a test step runs every\n\
                 test binary, failing or not):\n\
                 {}\n\
                 \n\
                 GPU tests run one at a time (RUST_TEST_THREADS=1; criterion benches reject\n\
                 `-- --test-threads=1`) and fail without an adapter or a display.\n\
                 Environment: WGPU_BACKEND=vulkan unless set; XDG_RUNTIME_DIR set to a fresh\n\
                 private directory unless set; when DISPLAY is unset and Xvfb exists,\n\
                 \x20 Xvfb :99 {}\n\
                 is started for the test step and stopped at the end (also on failure).",
                steps.join("\n"),
                XVFB_ARGS.join(" ")
            )
        }
    }
}

mod session;
mod setup;
use session::*;
use setup::*;

// ---------------------------------------------------------------------------
// Subcommands
// ---------------------------------------------------------------------------

/// `cargo xtask run`: set up, then run the main job with `args` or its defaults.
fn run_main_job(args: Option<&[String]>) -> Result<(), Failure> {
    ensure_system()?;
    let mut session = Session::new()?;
    let step = MAIN_JOB.step(args);
    println!("==> {}", step.describe());
    session.run(&step)
}

/// `cargo xtask test`: set up, then run [`test_steps`] in order, stopping at the
/// first failure, with a header and the elapsed time for each step.
fn run_tests() -> Result<(), Failure> {
    ensure_system()?;
    check_test_components()?;
    let mut session = Session::new()?;
    let steps = test_steps();
    let total = Instant::now();
    let mut results = Vec::new();
    for (index, step) in steps.iter().enumerate() {
        let title = step.describe();
        println!("\n==> [{}/{}] {title}", index + 1, steps.len());
        let started = Instant::now();
        let result = session.run(step);
        let elapsed = format_duration(started.elapsed());
        let verdict = if result.is_ok() { "ok" } else { "FAILED" };
        println!("==> [{}/{}] {verdict} in {elapsed}", index + 1, steps.len());
        results.push(format!("  {verdict:<6} {elapsed:>8}  {title}"));
        if result.is_err() {
            print_summary(&results, total.elapsed());
            return result;
        }
    }
    print_summary(&results, total.elapsed());
    // One closing line over every test binary, so CI reads the whole run's count.
    println!(
        "tests: {} passed, {} failed",
        session.tally.passed, session.tally.failed
    );
    Ok(())
}

/// Prints the per-step results and the total time.
fn print_summary(results: &[String], total: Duration) {
    println!("\n==> summary ({})", format_duration(total));
    for line in results {
        println!("{line}");
    }
}

// ---------------------------------------------------------------------------
// Small helpers
// ---------------------------------------------------------------------------

/// The cargo running us (`$CARGO`), or `cargo` from `PATH`.
fn cargo_program() -> PathBuf {
    std::env::var_os("CARGO")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("cargo"))
}

/// The workspace root: the parent of this crate's directory.
fn workspace_root() -> &'static Path {
    let manifest_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest_dir.parent().unwrap_or(manifest_dir)
}

/// Runs `program ARGS` quietly; returns its stdout if it succeeded.
fn command_output(program: &Path, args: &[&str]) -> Option<String> {
    let output = Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .ok()?;
    output
        .status
        .success()
        .then(|| String::from_utf8_lossy(&output.stdout).into_owned())
}

/// The path of executable `name` found on `PATH`, if any.
fn find_in_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|candidate| {
            fs::metadata(candidate)
                .is_ok_and(|meta| meta.is_file() && meta.permissions().mode() & 0o111 != 0)
        })
}

/// Owned copies of `words`.
fn strings(words: &[&str]) -> Vec<String> {
    words.iter().map(|word| (*word).to_owned()).collect()
}

/// A duration for humans: `0.4 s`, `12.3 s`, `4 min 05 s`.
fn format_duration(duration: Duration) -> String {
    let seconds = duration.as_secs_f64();
    if seconds < 60.0 {
        format!("{seconds:.1} s")
    } else {
        let whole = duration.as_secs();
        format!("{} min {:02} s", whole / 60, whole % 60)
    }
}

#[cfg(test)]
mod tests;
