//! `cargo xtask`: the one entry point for setting up, running and testing Texel.
//!
//! Texel renders through wgpu, and its tests and tools need things Cargo cannot
//! provide: a Vulkan loader, a Vulkan driver that works without a GPU (Mesa's
//! lavapipe), and an X server for window tests (Xvfb). They also need a
//! particular environment (one device per test process, the Vulkan backend, GPU
//! tests that fail rather than skip). Rather than spreading that knowledge over
//! shell scripts and CI files, this crate holds it in plain Rust with no
//! dependencies, so it compiles in seconds on any machine with a toolchain:
//!
//! * `cargo xtask setup` checks the system packages and installs the missing
//!   ones with `apt-get` when it can (root or passwordless sudo), or says exactly
//!   what to install when it cannot;
//! * `cargo xtask run [-- ARGS]` does the setup, then runs the project's main job;
//! * `cargo xtask test` does the setup, then runs formatting, clippy, every test on
//!   lavapipe (benches once, in test mode) and the GPU tests again on SwiftShader,
//!   stopping at the first failure (`--quick`: a shorter everyday loop; [`plan`]).
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
    "xdotool",
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

/// Arguments given to Xvfb after the display name. `-noreset`: by default an X server
/// resets when its last client leaves and refuses connections meanwhile, so a window test
/// that kills its only client and starts another (the editor's SIGKILL test) could fail to
/// connect on a loaded machine (2 of 100 quick reconnects under load, 0 with `-noreset`).
const XVFB_ARGS: &[&str] = &[
    "-screen",
    "0",
    "1280x800x24",
    "-nolisten",
    "tcp",
    "-noreset",
];

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
            role: Role::Check,
        }
    }
}

/// What a step of `cargo xtask test` is, beyond the command it runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// A check (fmt, clippy) or the benches in test mode.
    Check,
    /// A nextest pass on one driver: its device log is kept and its slowest tests shown.
    Tests(Driver),
}

/// A Vulkan driver the tests run on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Driver {
    /// Mesa's lavapipe: every test runs here.
    Lavapipe,
    /// SwiftShader: the GPU tests recorded on lavapipe run again here (less the exceptions).
    SwiftShader,
}

impl Driver {
    /// The driver's name, which is also its nextest profile (`.config/nextest.toml`).
    fn name(self) -> &'static str {
        match self {
            Driver::Lavapipe => "lavapipe",
            Driver::SwiftShader => "swiftshader",
        }
    }

    /// The file this driver's pass records its device-opening tests in.
    fn device_log(self) -> PathBuf {
        test_plan_dir().join(format!("{}-devices.txt", self.name()))
    }

    /// nextest's JUnit report of this driver's pass.
    fn junit(self) -> PathBuf {
        workspace_root()
            .join("target/nextest")
            .join(self.name())
            .join("junit.xml")
    }
}

/// Where the test plan's records are kept between steps (and for `--quick`).
fn test_plan_dir() -> PathBuf {
    workspace_root().join("target/test-plan")
}

/// Which tests `cargo xtask test` runs.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Scope {
    /// Everything CI runs: both drivers, the benches in test mode.
    Full,
    /// The everyday loop: fmt, clippy, the CPU tests, and on lavapipe the GPU tests of one
    /// package (or of none).
    Quick {
        /// The package whose GPU tests run too.
        package: Option<String>,
    },
    /// Only the second driver's pass, over the GPU tests the last full run recorded.
    SecondDriver,
}

/// The steps of `cargo xtask test`, in order.
///
/// On lavapipe tests run under cargo-nextest, one process per test, one per core
/// (`.config/nextest.toml`). GPU and window tests fail when no adapter or display exists
/// (`TEXEL_ALLOW_NO_GPU` / `TEXEL_ALLOW_NO_DISPLAY` would skip them; the steps never see
/// them). The SwiftShader pass runs the tests that opened a device on lavapipe, each
/// binary's in one process ([`plan`], [`second_pass`]). Criterion benches run once in
/// test mode through `cargo test` (nextest does not run them), on lavapipe;
/// `RUST_TEST_THREADS=1` because criterion rejects `--test-threads`.
fn test_steps(scope: &Scope) -> Vec<Step> {
    let lavapipe = Step {
        args: strings(&["nextest", "run", "--workspace", "--profile", "lavapipe"]),
        env: Vec::new(),
        needs_display: true,
        role: Role::Tests(Driver::Lavapipe),
    };
    let mut steps = vec![
        Step::cargo(&["fmt", "--all", "--", "--check"]),
        Step::cargo(&[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ]),
    ];
    let swiftshader = Step {
        // Builds and lists the tests; then each binary's GPU tests run in one process
        // (`second_pass`).
        args: strings(&["nextest", "list", "--workspace", "--message-format", "json"]),
        env: vec![
            ("VK_ICD_FILENAMES".to_owned(), SWIFTSHADER_ICD.to_owned()),
            (
                "TEXEL_EXPECT_ADAPTER".to_owned(),
                SWIFTSHADER_ADAPTER.to_owned(),
            ),
        ],
        needs_display: true,
        role: Role::Tests(Driver::SwiftShader),
    };
    match scope {
        Scope::Quick { .. } => steps.push(lavapipe),
        Scope::SecondDriver => return vec![swiftshader],
        Scope::Full => {
            steps.push(Step {
                env: vec![(
                    plan::DEVICE_LOG_VAR.to_owned(),
                    Driver::Lavapipe.device_log().display().to_string(),
                )],
                ..lavapipe
            });
            steps.push(Step {
                // `--bench '*'`: the bench targets only (`--benches` also takes every lib,
                // whose unit tests nextest has run).
                args: strings(&["test", "--workspace", "--bench", "*", "--no-fail-fast"]),
                env: vec![("RUST_TEST_THREADS".to_owned(), "1".to_owned())],
                needs_display: false,
                role: Role::Check,
            });
            steps.push(swiftshader);
        }
    }
    steps
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
        Cli::Test(scope) => run_tests(&scope),
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
    /// Ensure system packages, then run the checks and the tests in `Scope`.
    Test(Scope),
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
    if sub == Sub::Test {
        return parse_test_options(options).map(Cli::Test);
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
        Sub::Test => unreachable!("`test` returned above"),
        Sub::Setup => Cli::Setup,
    })
}

/// `test`'s options: none (the full run), or `--quick` with an optional `-p PACKAGE`.
fn parse_test_options(options: &[String]) -> Result<Scope, UsageError> {
    let error = |message: String| UsageError {
        message,
        topic: Some(Sub::Test),
    };
    let mut quick = false;
    let mut package = None;
    let mut rest = options.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--second-driver" if options.len() == 1 => return Ok(Scope::SecondDriver),
            "--quick" => quick = true,
            "-p" | "--package" => match rest.next() {
                Some(name) if !name.starts_with('-') => package = Some(name.clone()),
                _ => return Err(error(format!("`{arg}` needs a package name"))),
            },
            other => return Err(error(format!("unexpected argument `{other}` for `test`"))),
        }
    }
    match (quick, package) {
        (false, Some(_)) => Err(error("`-p` is for `--quick` runs".to_owned())),
        (false, None) => Ok(Scope::Full),
        (true, package) => Ok(Scope::Quick { package }),
    }
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
             \x20                  SwiftShader, Xvfb, xauth, xdotool) and install the missing ones\n\
             \x20                  with apt-get\n\
             \x20 run [-- ARGS]    Set up, then run the main job:\n\
             \x20                    {default_run}\n\
             \x20 test             Set up, then fmt check, clippy, every test on lavapipe (and\n\
             \x20                  the benches in test mode), the GPU tests on SwiftShader;\n\
             \x20                  stops after the first failing step (--quick: a short loop)\n\
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
             (lvp_icd*.json), SwiftShader ({SWIFTSHADER_ICD}), Xvfb, xauth and xdotool.\n\
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
            let steps: Vec<String> = test_steps(&Scope::Full)
                .iter()
                .map(|step| format!("  {}", step.describe()))
                .collect();
            let exceptions: Vec<String> = plan::SECOND_DRIVER_EXCEPTIONS
                .iter()
                .map(|(part, reason)| format!("  *{part}*: {reason}"))
                .collect();
            let short: Vec<String> = plan::SECOND_DRIVER_SHORT
                .iter()
                .map(|(part, reason)| format!("  *{part}*: {reason}"))
                .collect();
            format!(
                "cargo xtask test: set up, then run every check CI runs\n\
                 \n\
                 Usage: cargo xtask test [--quick [-p PACKAGE] | --second-driver]\n\
                 \n\
                 Steps, in order (stops after the first failing step; a test step runs every\n\
                 test, failing or not):\n\
                 {}\n\
                 \n\
                 On lavapipe, tests run under cargo-nextest, one process per test, one per\n\
                 core at a time (.config/nextest.toml: the per-test time budget, and the tests\n\
                 allowed longer with their reasons). Each test that opens a GPU device there\n\
                 is recorded ({}) and runs again on SwiftShader, each test binary's GPU tests\n\
                 in one process sharing one device (its pipelines compiled once), one binary\n\
                 per core at a time, {} s a test at most; except:\n\
                 {}\n\
                 and these run there in a short form, the first half of their path's\n\
                 frames against the same bounds ({}):\n\
                 {}\n\
                 A GPU test that did not run on both fails the run by name. Each pass ends\n\
                 with its {} slowest tests. GPU and window tests fail without an adapter or\n\
                 a display.\n\
                 \n\
                 --quick        the everyday loop: fmt, clippy, and on lavapipe the CPU tests\n\
                 \x20              and no GPU test (which tests open a device comes from the\n\
                 \x20              last full run's record; without one, every test runs)\n\
                 -p PACKAGE     with --quick: also PACKAGE's GPU tests\n\
                 --second-driver  only the SwiftShader pass, over the last full run's record\n\
                 \n\
                 Environment: WGPU_BACKEND=vulkan unless set; XDG_RUNTIME_DIR set to a fresh\n\
                 private directory unless set; when DISPLAY is unset and Xvfb exists,\n\
                 \x20 Xvfb :99 {}\n\
                 is started for the test steps and stopped at the end (also on failure).",
                steps.join("\n"),
                plan::DEVICE_LOG_VAR,
                second_pass::BUDGET.as_secs(),
                exceptions.join("\n"),
                plan::SHORT_TESTS_VAR,
                short.join("\n"),
                plan::SLOWEST_SHOWN,
                XVFB_ARGS.join(" ")
            )
        }
    }
}

mod plan;
mod second_pass;
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
fn run_tests(scope: &Scope) -> Result<(), Failure> {
    ensure_system()?;
    check_test_components()?;
    let mut session = Session::new()?;
    let steps = test_steps(scope);
    let total = Instant::now();
    let mut results = Vec::new();
    let mut reports = Vec::new();
    let tree = tree::untracked();
    if tree.is_none() {
        println!("(not a git checkout: what the tests leave in the tree is not checked)");
    }
    for (index, step) in steps.iter().enumerate() {
        let step = prepare_step(step, scope)?;
        let title = step.describe();
        println!("\n==> [{}/{}] {title}", index + 1, steps.len());
        let started = Instant::now();
        let mut result = match step.role {
            Role::Tests(Driver::SwiftShader) => second_pass::run_pass(&mut session, &step),
            _ => session.run(&step),
        };
        if let Role::Tests(driver @ Driver::Lavapipe) = step.role {
            // nextest prints its summary on stderr: the counts come from its report.
            if let Some((tests, failed)) =
                (fs::read_to_string(driver.junit()).ok()).and_then(|xml| plan::junit_counts(&xml))
            {
                session.tally.passed += tests - failed.min(tests);
                session.tally.failed += failed;
            }
            let report = driver_report(driver);
            println!("{report}");
            reports.push(report);
        }
        if step.role == Role::Tests(Driver::SwiftShader) {
            let report = (fs::read_to_string(second_pass::timings_file()).ok())
                .map(|text| plan::slowest_report("swiftshader", &plan::parse_timings(&text)))
                .unwrap_or_default();
            println!("{report}");
            reports.push(report);
            if result.is_ok() {
                result = second_pass::check_second_driver();
            }
        }
        if result.is_ok() {
            result = tree::check(tree.as_ref(), &step.short());
        }
        let elapsed = format_duration(started.elapsed());
        let verdict = if result.is_ok() { "ok" } else { "FAILED" };
        println!("==> [{}/{}] {verdict} in {elapsed}", index + 1, steps.len());
        results.push(format!("  {verdict:<6} {elapsed:>8}  {}", step.short()));
        if result.is_err() {
            print_summary(&results, &reports, total.elapsed());
            return result;
        }
    }
    print_summary(&results, &reports, total.elapsed());
    // One closing line over every test binary, so CI reads the whole run's count.
    println!(
        "tests: {} passed, {} failed",
        session.tally.passed, session.tally.failed
    );
    Ok(())
}

/// `step` ready to run: a device log emptied before the pass that writes it, and the
/// filter the pass needs (the GPU tests for SwiftShader; no GPU tests for `--quick`).
fn prepare_step(step: &Step, scope: &Scope) -> Result<Step, Failure> {
    let mut step = step.clone();
    let Role::Tests(driver) = step.role else {
        return Ok(step);
    };
    if let Some((_, log)) = step.env.iter().find(|(k, _)| k == plan::DEVICE_LOG_VAR) {
        fs::create_dir_all(test_plan_dir())
            .and_then(|()| fs::write(log, ""))
            .map_err(|e| Failure::new(format!("could not reset the device log {log}: {e}")))?;
    }
    let filter = match (scope, driver) {
        (Scope::Full, Driver::Lavapipe) => None,
        // The second driver's tests are chosen from the listing (`run_second_driver`).
        (Scope::Full | Scope::SecondDriver, Driver::SwiftShader) => None,
        (Scope::SecondDriver, Driver::Lavapipe) => None,
        (Scope::Quick { package }, _) => quick_filter(package.as_deref()),
    };
    if let Some(filter) = filter {
        step.args.extend(["-E".to_owned(), filter]);
    }
    Ok(step)
}

/// `--quick`'s filter: every test but the GPU tests the last full run recorded, plus
/// `package`'s. Without a record, `None` (every test), which it says.
fn quick_filter(package: Option<&str>) -> Option<String> {
    let gpu = read_device_log(Driver::Lavapipe)
        .ok()
        .filter(|log| !log.tests.is_empty());
    let Some(gpu) = gpu else {
        println!(
            "==> no record of which tests open a GPU device yet ({}; the full \
             `cargo xtask test` writes it): running every test",
            Driver::Lavapipe.device_log().display()
        );
        return None;
    };
    let gpu: Vec<plan::TestId> = gpu.tests.into_iter().collect();
    let not_gpu = format!("not ({})", plan::filterset(&gpu)?);
    Some(match package {
        Some(package) => format!("{not_gpu} | package({package})"),
        None => not_gpu,
    })
}

/// The tests that opened a device in `driver`'s last pass.
fn read_device_log(driver: Driver) -> Result<plan::DeviceLog, Failure> {
    let path = driver.device_log();
    let text = fs::read_to_string(&path)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", path.display())))?;
    let log = plan::parse_device_log(&text);
    if log.unnamed > 0 {
        println!(
            "==> warning: {} devices in {} were opened outside a named test",
            log.unnamed,
            path.display()
        );
    }
    Ok(log)
}

/// The slowest tests of `driver`'s last pass, from nextest's JUnit report.
fn driver_report(driver: Driver) -> String {
    match fs::read_to_string(driver.junit()) {
        Ok(xml) => plan::slowest_report(driver.name(), &plan::parse_junit(&xml)),
        Err(e) => format!(
            "==> no timings for {} ({}: {e})",
            driver.name(),
            driver.junit().display()
        ),
    }
}

/// Prints each pass's slowest tests, the per-step results and the total time.
fn print_summary(results: &[String], reports: &[String], total: Duration) {
    for report in reports {
        println!("\n{report}");
    }
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
mod tree;
