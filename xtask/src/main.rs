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
    package: "texel_runtime",
    bin: "texel-run",
    default_args: &[
        "render",
        "assets/levels/stone_circle.ron",
        "--size",
        "1280x720",
        "--out",
        "target/stone_circle",
    ],
    needs_display: false,
};

/// The Debian/Ubuntu packages that provide everything in [`Requirement::ALL`].
const APT_PACKAGES: &[&str] = &["mesa-vulkan-drivers", "libvulkan1", "xvfb", "xauth"];

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
/// variable correctly. `TEXEL_REQUIRE_GPU=1` makes GPU tests fail instead of
/// skipping when no adapter exists.
fn test_steps() -> Vec<Step> {
    let test_env = vec![
        ("RUST_TEST_THREADS".to_owned(), "1".to_owned()),
        ("TEXEL_REQUIRE_GPU".to_owned(), "1".to_owned()),
        // Window tests fail instead of skipping when no display could be provided.
        ("TEXEL_REQUIRE_DISPLAY".to_owned(), "1".to_owned()),
    ];
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
            args: strings(&["test", "--workspace", "--all-targets"]),
            env: test_env.clone(),
            needs_display: true,
        },
        Step {
            args: strings(&["test", "--workspace", "--doc"]),
            env: test_env,
            needs_display: false,
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
             \x20 setup            Check the system packages (Vulkan loader, lavapipe, Xvfb,\n\
             \x20                  xauth) and install the missing ones with apt-get\n\
             \x20 run [-- ARGS]    Set up, then run the main job:\n\
             \x20                    {default_run}\n\
             \x20 test             Set up, then fmt check, clippy, tests (and benches in test\n\
             \x20                  mode) and doc tests; stops at the first failure\n\
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
             (lvp_icd*.json), Xvfb and xauth. If any is missing and this runs as root or\n\
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
                 Steps, in order (stops at the first failure):\n\
                 {}\n\
                 \n\
                 GPU tests run one at a time (RUST_TEST_THREADS=1; criterion benches reject\n\
                 `-- --test-threads=1`) and fail without an adapter (TEXEL_REQUIRE_GPU=1).\n\
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

// ---------------------------------------------------------------------------
// System packages
// ---------------------------------------------------------------------------

/// Something Texel needs from the operating system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Requirement {
    /// The Vulkan loader, `libvulkan.so.1`.
    VulkanLoader,
    /// Mesa's lavapipe: a Vulkan driver running on the CPU.
    Lavapipe,
    /// The virtual X server, for window tests without a screen.
    Xvfb,
    /// `xauth`, used to authorise clients of the virtual X server.
    Xauth,
}

impl Requirement {
    /// Every requirement, in the order they are reported.
    const ALL: [Requirement; 4] = [
        Requirement::VulkanLoader,
        Requirement::Lavapipe,
        Requirement::Xvfb,
        Requirement::Xauth,
    ];

    /// A short human description.
    fn describe(self) -> &'static str {
        match self {
            Requirement::VulkanLoader => "Vulkan loader (libvulkan.so.1)",
            Requirement::Lavapipe => "Mesa lavapipe Vulkan driver (lvp_icd*.json)",
            Requirement::Xvfb => "Xvfb (virtual X server)",
            Requirement::Xauth => "xauth",
        }
    }

    /// Whether the requirement is met on this machine.
    fn is_present(self) -> bool {
        match self {
            Requirement::VulkanLoader => has_shared_library("libvulkan.so.1"),
            Requirement::Lavapipe => has_lavapipe_icd(),
            Requirement::Xvfb => find_in_path("Xvfb").is_some(),
            Requirement::Xauth => find_in_path("xauth").is_some(),
        }
    }
}

/// The requirements not met on this machine.
fn missing_requirements() -> Vec<Requirement> {
    Requirement::ALL
        .into_iter()
        .filter(|requirement| !requirement.is_present())
        .collect()
}

/// What this machine allows for installing packages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct HostAccess {
    /// Running as root (uid 0).
    is_root: bool,
    /// `sudo -n true` succeeds (passwordless sudo).
    has_sudo: bool,
    /// `apt-get` is on `PATH`.
    has_apt: bool,
}

/// Why the packages cannot be installed automatically.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ManualReason {
    /// No `apt-get`: probably not Debian or Ubuntu.
    NoApt,
    /// Not root and no passwordless sudo.
    CannotElevate,
}

/// What the set-up step should do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SetupAction {
    /// Everything is there.
    NothingToDo,
    /// Install with apt-get, through `sudo -n` when `use_sudo`.
    Install {
        /// Whether to run apt-get through `sudo -n`.
        use_sudo: bool,
    },
    /// Tell the user what to install, then fail.
    Manual(ManualReason),
}

/// Decides how to get the `missing` requirements onto a machine with `access`.
fn decide_setup(missing: &[Requirement], access: HostAccess) -> SetupAction {
    if missing.is_empty() {
        SetupAction::NothingToDo
    } else if !access.has_apt {
        SetupAction::Manual(ManualReason::NoApt)
    } else if access.is_root {
        SetupAction::Install { use_sudo: false }
    } else if access.has_sudo {
        SetupAction::Install { use_sudo: true }
    } else {
        SetupAction::Manual(ManualReason::CannotElevate)
    }
}

/// The commands (program first) that install the packages with apt-get.
///
/// `DEBIAN_FRONTEND=noninteractive` is also set on the process; through sudo,
/// which resets the environment, it is passed with `env`.
fn install_commands(use_sudo: bool) -> Vec<Vec<String>> {
    let prefix: Vec<String> = if use_sudo {
        strings(&["sudo", "-n", "env", "DEBIAN_FRONTEND=noninteractive"])
    } else {
        Vec::new()
    };
    let mut update = prefix.clone();
    update.extend(strings(&["apt-get", "update"]));
    let mut install = prefix;
    install.extend(strings(&[
        "apt-get",
        "install",
        "-y",
        "--no-install-recommends",
    ]));
    install.extend(strings(APT_PACKAGES));
    vec![update, install]
}

/// The message shown when the packages must be installed by hand.
fn manual_instructions(missing: &[Requirement], reason: ManualReason) -> String {
    let why = match reason {
        ManualReason::NoApt => "apt-get was not found (this does not look like Debian or Ubuntu)",
        ManualReason::CannotElevate => {
            "this is not root and passwordless sudo (`sudo -n true`) is not available"
        }
    };
    let list: Vec<String> = missing
        .iter()
        .map(|requirement| format!("  - {}", requirement.describe()))
        .collect();
    format!(
        "missing system packages:\n\
         {}\n\
         xtask installs them itself with apt-get, as root or with passwordless sudo, but\n\
         {why}.\n\
         Install them, then run this again:\n\
         \x20 Debian/Ubuntu: sudo apt-get install -y --no-install-recommends {}\n\
         \x20 Other distros: install the Vulkan loader, Mesa's lavapipe (llvmpipe) Vulkan\n\
         \x20   driver and Xvfb (with xauth); e.g. Fedora: vulkan-loader mesa-vulkan-drivers\n\
         \x20   xorg-x11-server-Xvfb xorg-x11-xauth; Arch: vulkan-icd-loader vulkan-swrast\n\
         \x20   xorg-server-xvfb xorg-xauth",
        list.join("\n"),
        APT_PACKAGES.join(" ")
    )
}

/// Makes sure the toolchain and the system packages are there, installing the
/// packages when possible.
fn ensure_system() -> Result<(), Failure> {
    check_toolchain()?;
    let missing = missing_requirements();
    if missing.is_empty() {
        println!("==> system packages: all present (Vulkan loader, lavapipe, Xvfb, xauth)");
        return Ok(());
    }
    let names: Vec<&str> = missing.iter().map(|r| r.describe()).collect();
    println!("==> system packages missing: {}", names.join(", "));
    let is_root = is_root();
    let access = HostAccess {
        is_root,
        // Only ask sudo when it matters: `sudo -n` may log a failed attempt.
        has_sudo: !is_root && find_in_path("sudo").is_some() && sudo_works(),
        has_apt: find_in_path("apt-get").is_some(),
    };
    match decide_setup(&missing, access) {
        SetupAction::NothingToDo => Ok(()),
        SetupAction::Manual(reason) => Err(Failure::new(manual_instructions(&missing, reason))),
        SetupAction::Install { use_sudo } => {
            for command in install_commands(use_sudo) {
                run_install_command(&command)?;
            }
            let still_missing = missing_requirements();
            if still_missing.is_empty() {
                println!("==> system packages: all present after installing");
                Ok(())
            } else {
                let names: Vec<&str> = still_missing.iter().map(|r| r.describe()).collect();
                Err(Failure::new(format!(
                    "apt-get finished, but these are still missing: {}",
                    names.join(", ")
                )))
            }
        }
    }
}

/// Runs one apt-get command (program first) with inherited output.
fn run_install_command(command: &[String]) -> Result<(), Failure> {
    let line = command.join(" ");
    println!("==> {line}");
    let status = Command::new(&command[0])
        .args(&command[1..])
        .env("DEBIAN_FRONTEND", "noninteractive")
        .stdin(Stdio::null())
        .status()
        .map_err(|error| Failure::new(format!("could not start `{line}`: {error}")))?;
    if status.success() {
        Ok(())
    } else {
        Err(Failure::new(format!("`{line}` failed ({status})")))
    }
}

/// Checks that cargo and rustc work, with a rustup hint when they do not.
fn check_toolchain() -> Result<(), Failure> {
    let hint = "install the Rust toolchain with rustup (https://rustup.rs), then run this again";
    if command_output(&cargo_program(), &["--version"]).is_none() {
        return Err(Failure::new(format!("`cargo --version` failed: {hint}")));
    }
    if command_output(Path::new("rustc"), &["--version"]).is_none() {
        return Err(Failure::new(format!(
            "`rustc --version` failed (rustc is missing or broken): {hint}"
        )));
    }
    Ok(())
}

/// Checks that the cargo subcommands used by `test` are installed.
fn check_test_components() -> Result<(), Failure> {
    for (component, subcommand) in [("rustfmt", "fmt"), ("clippy", "clippy")] {
        if command_output(&cargo_program(), &[subcommand, "--version"]).is_none() {
            return Err(Failure::new(format!(
                "`cargo {subcommand}` is not available: install it with \
                 `rustup component add {component}`"
            )));
        }
    }
    Ok(())
}

/// Whether the dynamic linker knows `library` (from `ldconfig -p`, or common
/// library directories when ldconfig cannot be run).
fn has_shared_library(library: &str) -> bool {
    for ldconfig in ["ldconfig", "/sbin/ldconfig", "/usr/sbin/ldconfig"] {
        if let Some(listing) = command_output(Path::new(ldconfig), &["-p"]) {
            return ldconfig_lists(&listing, library);
        }
    }
    let mut dirs: Vec<PathBuf> = ["/usr/lib64", "/usr/lib", "/lib64", "/lib"]
        .iter()
        .map(PathBuf::from)
        .collect();
    for parent in ["/usr/lib", "/lib"] {
        if let Ok(entries) = fs::read_dir(parent) {
            dirs.extend(
                entries
                    .flatten()
                    .map(|entry| entry.path())
                    .filter(|path| path.to_string_lossy().ends_with("-linux-gnu")),
            );
        }
    }
    dirs.iter().any(|dir| dir.join(library).exists())
}

/// Whether an `ldconfig -p` listing contains `library`.
fn ldconfig_lists(listing: &str, library: &str) -> bool {
    listing
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .any(|name| name == library)
}

/// Whether a lavapipe ICD manifest is installed.
fn has_lavapipe_icd() -> bool {
    ICD_DIRS.iter().any(|dir| {
        fs::read_dir(dir).is_ok_and(|entries| {
            entries
                .flatten()
                .any(|entry| is_lavapipe_icd(&entry.file_name().to_string_lossy()))
        })
    })
}

/// Whether `file_name` is a lavapipe ICD manifest (`lvp_icd*.json`).
fn is_lavapipe_icd(file_name: &str) -> bool {
    file_name.starts_with("lvp_icd") && file_name.ends_with(".json")
}

/// Whether this process runs as root.
fn is_root() -> bool {
    if let Ok(metadata) = fs::metadata("/proc/self") {
        return metadata.uid() == 0;
    }
    command_output(Path::new("id"), &["-u"]).is_some_and(|uid| uid.trim() == "0")
}

/// Whether `sudo -n true` succeeds, i.e. sudo works without a password.
fn sudo_works() -> bool {
    Command::new("sudo")
        .args(["-n", "true"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|status| status.success())
}

// ---------------------------------------------------------------------------
// Steps and their environment
// ---------------------------------------------------------------------------

/// One cargo invocation of `run` or `test`.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Step {
    /// Arguments after `cargo`.
    args: Vec<String>,
    /// Variables set for this step only.
    env: Vec<(String, String)>,
    /// Whether the step may open windows (an X display is provided if possible).
    needs_display: bool,
}

impl Step {
    /// A step running `cargo ARGS` with no extra environment and no display.
    fn cargo(args: &[&str]) -> Step {
        Step {
            args: strings(args),
            env: Vec::new(),
            needs_display: false,
        }
    }

    /// The step as a shell-like line, with its extra variables first.
    fn describe(&self) -> String {
        let mut words: Vec<String> = self
            .env
            .iter()
            .map(|(key, value)| format!("{key}={value}"))
            .collect();
        words.push("cargo".to_owned());
        words.extend(self.args.iter().cloned());
        words.join(" ")
    }
}

/// The environment shared by all steps, and the resources behind it.
///
/// Dropping it stops the virtual X server and removes the temporary runtime
/// directory, so both are cleaned up on success, on failure and on early return.
struct Session {
    /// Variables set on every step.
    env: Vec<(String, OsString)>,
    /// The runtime directory created for `XDG_RUNTIME_DIR`, if one was.
    runtime_dir: Option<TempDir>,
    /// The virtual X server, once started.
    xvfb: Option<Xvfb>,
    /// Whether starting Xvfb was already attempted.
    xvfb_tried: bool,
    /// Tests counted so far from libtest's `test result:` lines.
    tally: Tally,
}

/// Passed and failed test counts, summed over every test binary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Tally {
    passed: u64,
    failed: u64,
}

impl Tally {
    /// Adds the counts of one libtest summary line
    /// (`test result: ok. 9 passed; 0 failed; 0 ignored; ...`); other lines are ignored.
    fn add_line(&mut self, line: &str) {
        let Some(rest) = line.trim_start().strip_prefix("test result: ") else {
            return;
        };
        let count = |word: &str| {
            rest.split(';')
                .find_map(|part| {
                    part.trim()
                        .strip_suffix(word)?
                        .trim()
                        .rsplit(' ')
                        .next()?
                        .parse::<u64>()
                        .ok()
                })
                .unwrap_or(0)
        };
        self.passed += count("passed");
        self.failed += count("failed");
    }
}

impl Session {
    /// Prepares the shared environment: `WGPU_BACKEND` and `XDG_RUNTIME_DIR`.
    fn new() -> Result<Session, Failure> {
        let mut env = Vec::new();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            env.push(("WGPU_BACKEND".to_owned(), OsString::from("vulkan")));
        }
        let mut runtime_dir = None;
        if std::env::var_os("XDG_RUNTIME_DIR").is_none_or(|dir| dir.is_empty()) {
            let dir = TempDir::new("texel-xdg-runtime").map_err(|error| {
                Failure::new(format!("could not create XDG_RUNTIME_DIR: {error}"))
            })?;
            env.push((
                "XDG_RUNTIME_DIR".to_owned(),
                dir.path.clone().into_os_string(),
            ));
            runtime_dir = Some(dir);
        }
        for (key, value) in &env {
            println!("==> env: {key}={}", value.to_string_lossy());
        }
        Ok(Session {
            env,
            runtime_dir,
            xvfb: None,
            xvfb_tried: false,
            tally: Tally::default(),
        })
    }

    /// Starts Xvfb if no display is set, once; returns the `DISPLAY` to use.
    fn display(&mut self) -> Option<String> {
        if std::env::var_os("DISPLAY").is_some_and(|display| !display.is_empty()) {
            return None;
        }
        if !self.xvfb_tried {
            self.xvfb_tried = true;
            match Xvfb::start() {
                Ok(xvfb) => {
                    println!(
                        "==> started Xvfb on {} (pid {})",
                        xvfb.display,
                        xvfb.child.id()
                    );
                    self.xvfb = Some(xvfb);
                }
                Err(error) => {
                    eprintln!("xtask: warning: no X display for window tests: {error}");
                }
            }
        }
        self.xvfb.as_ref().map(|xvfb| xvfb.display.clone())
    }

    /// Runs `step` with inherited stdio; returns its exit code on failure.
    fn run(&mut self, step: &Step) -> Result<(), Failure> {
        let mut command = Command::new(cargo_program());
        command.args(&step.args).current_dir(workspace_root());
        command.envs(self.env.iter().map(|(key, value)| (key, value)));
        command.envs(step.env.iter().map(|(key, value)| (key, value)));
        if step.needs_display
            && let Some(display) = self.display()
        {
            command.env("DISPLAY", display);
        }
        let status = if step.args.first().is_some_and(|a| a == "test") {
            self.run_counting(command)
        } else {
            command.status()
        }
        .map_err(|error| Failure::new(format!("could not start cargo: {error}")))?;
        if status.success() {
            return Ok(());
        }
        let exit_code = status
            .code()
            .and_then(|code| u8::try_from(code).ok())
            .filter(|&code| code != 0)
            .unwrap_or(1);
        Err(Failure {
            message: format!("`{}` failed ({status})", step.describe()),
            exit_code,
        })
    }
}

impl Session {
    /// Runs a `cargo test`, echoing its standard output line by line and counting tests.
    fn run_counting(&mut self, mut command: Command) -> io::Result<std::process::ExitStatus> {
        use io::BufRead as _;
        let mut child = command.stdout(std::process::Stdio::piped()).spawn()?;
        if let Some(out) = child.stdout.take() {
            let stdout = io::stdout();
            for line in io::BufReader::new(out).lines() {
                let line = line?;
                self.tally.add_line(&line);
                let mut lock = stdout.lock();
                writeln!(lock, "{line}")?;
                lock.flush()?;
            }
        }
        child.wait()
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        if let Some(xvfb) = self.xvfb.take() {
            let display = xvfb.display.clone();
            drop(xvfb);
            println!("==> stopped Xvfb on {display}");
        }
        drop(self.runtime_dir.take());
    }
}

/// A directory removed when dropped.
struct TempDir {
    /// The directory.
    path: PathBuf,
}

impl TempDir {
    /// Creates a fresh directory, private to the user (mode 0700), under the
    /// system temporary directory.
    fn new(prefix: &str) -> io::Result<TempDir> {
        let base = std::env::temp_dir();
        let pid = std::process::id();
        let mut last_error = None;
        for attempt in 0..100 {
            let path = base.join(format!("{prefix}-{pid}-{attempt}"));
            match fs::DirBuilder::new().mode(0o700).create(&path) {
                Ok(()) => {
                    // The mode passed to mkdir is filtered by the umask; make sure.
                    fs::set_permissions(&path, fs::Permissions::from_mode(0o700))?;
                    return Ok(TempDir { path });
                }
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists => {
                    last_error = Some(error);
                }
                Err(error) => return Err(error),
            }
        }
        Err(last_error.unwrap_or_else(|| io::Error::other("no free directory name")))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.path);
    }
}

/// A virtual X server started by xtask, stopped when dropped.
struct Xvfb {
    /// The server process.
    child: Child,
    /// The display name, e.g. `:99`.
    display: String,
    /// The display number.
    number: u32,
}

impl Xvfb {
    /// Starts Xvfb on the first free display from `:99` and waits until it
    /// accepts connections.
    fn start() -> Result<Xvfb, String> {
        let program = find_in_path("Xvfb").ok_or("Xvfb is not on PATH")?;
        let number = (FIRST_XVFB_DISPLAY..FIRST_XVFB_DISPLAY + XVFB_DISPLAY_TRIES)
            .find(|&number| display_is_free(number))
            .ok_or("no free X display number")?;
        let display = format!(":{number}");
        let child = Command::new(program)
            .arg(&display)
            .args(XVFB_ARGS)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|error| format!("could not start Xvfb: {error}"))?;
        let mut xvfb = Xvfb {
            child,
            display,
            number,
        };
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{number}"));
        let deadline = Instant::now() + XVFB_START_TIMEOUT;
        loop {
            if let Ok(Some(status)) = xvfb.child.try_wait() {
                return Err(format!(
                    "Xvfb {} exited at start ({status}); try `Xvfb {} {}` by hand",
                    xvfb.display,
                    xvfb.display,
                    XVFB_ARGS.join(" ")
                ));
            }
            if socket.exists() {
                return Ok(xvfb);
            }
            if Instant::now() >= deadline {
                // Still running: it may listen on an abstract socket only.
                eprintln!(
                    "xtask: warning: {} not seen; using Xvfb anyway",
                    socket.display()
                );
                return Ok(xvfb);
            }
            thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM first, so that Xvfb removes its lock file and socket.
        let pid = self.child.id().to_string();
        let terminated = Command::new("kill")
            .args(["-TERM", &pid])
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|status| status.success());
        if terminated {
            let deadline = Instant::now() + Duration::from_secs(3);
            while Instant::now() < deadline {
                if let Ok(Some(_)) = self.child.try_wait() {
                    return;
                }
                thread::sleep(Duration::from_millis(20));
            }
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = fs::remove_file(format!("/tmp/.X{}-lock", self.number));
        let _ = fs::remove_file(format!("/tmp/.X11-unix/X{}", self.number));
    }
}

/// Whether X display `number` looks unused: no lock file, or a lock file left
/// by a process that no longer exists.
fn display_is_free(number: u32) -> bool {
    match fs::read_to_string(format!("/tmp/.X{number}-lock")) {
        Err(_) => true,
        Ok(contents) => match contents.trim().parse::<u32>() {
            Ok(pid) => !Path::new(&format!("/proc/{pid}")).exists(),
            Err(_) => false,
        },
    }
}

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
mod tests {
    use super::*;

    #[test]
    fn tally_sums_libtest_summaries() {
        let mut t = Tally::default();
        t.add_line("test result: ok. 9 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.02s");
        t.add_line(
            "test result: FAILED. 3 passed; 2 failed; 0 ignored; 0 measured; 0 filtered out",
        );
        t.add_line("running 5 tests");
        t.add_line("test foo ... ok");
        assert_eq!(
            t,
            Tally {
                passed: 12,
                failed: 2
            }
        );
    }

    fn parse(args: &[&str]) -> Result<Cli, UsageError> {
        parse_args(&strings(args))
    }

    const ALL_MISSING: &[Requirement] = &Requirement::ALL;

    fn access(is_root: bool, has_sudo: bool, has_apt: bool) -> HostAccess {
        HostAccess {
            is_root,
            has_sudo,
            has_apt,
        }
    }

    #[test]
    fn parses_subcommands() {
        assert_eq!(parse(&["test"]), Ok(Cli::Test));
        assert_eq!(parse(&["setup"]), Ok(Cli::Setup));
        assert_eq!(parse(&["run"]), Ok(Cli::Run { args: None }));
    }

    #[test]
    fn run_arguments_after_double_dash_replace_the_defaults() {
        assert_eq!(
            parse(&["run", "--", "check", "assets/levels/sandbox.ron"]),
            Ok(Cli::Run {
                args: Some(strings(&["check", "assets/levels/sandbox.ron"]))
            })
        );
        // Everything after `--` belongs to the program, even help flags.
        assert_eq!(
            parse(&["run", "--", "--help"]),
            Ok(Cli::Run {
                args: Some(strings(&["--help"]))
            })
        );
        assert_eq!(parse(&["run", "--"]), Ok(Cli::Run { args: Some(vec![]) }));
    }

    #[test]
    fn run_rejects_arguments_before_double_dash() {
        let error = parse(&["run", "check"]).unwrap_err();
        assert!(error.message.contains("`check`"));
        assert!(error.message.contains("after `--`"));
        assert_eq!(error.topic, Some(Sub::Run));
    }

    #[test]
    fn help_flags_and_help_command() {
        for args in [&["-h"][..], &["--help"], &["help"]] {
            assert_eq!(parse(args), Ok(Cli::Help(None)));
        }
        assert_eq!(parse(&["run", "--help"]), Ok(Cli::Help(Some(Sub::Run))));
        assert_eq!(parse(&["test", "-h"]), Ok(Cli::Help(Some(Sub::Test))));
        assert_eq!(parse(&["help", "setup"]), Ok(Cli::Help(Some(Sub::Setup))));
        assert!(parse(&["help", "deploy"]).is_err());
    }

    #[test]
    fn unknown_input_is_a_usage_error() {
        assert!(parse(&[]).is_err());
        let error = parse(&["deploy"]).unwrap_err();
        assert_eq!(error.message, "unknown command `deploy`");
        assert_eq!(error.topic, None);
        assert_eq!(
            parse(&["--verbose"]).unwrap_err().message,
            "unknown option `--verbose`"
        );
        let error = parse(&["test", "--release"]).unwrap_err();
        assert_eq!(error.topic, Some(Sub::Test));
        assert!(parse(&["setup", "--", "x"]).is_err());
    }

    #[test]
    fn usage_mentions_every_command() {
        let text = usage(None);
        for name in ["setup", "run", "test", "help"] {
            assert!(text.contains(name), "{name} missing from usage");
        }
        for sub in [Sub::Run, Sub::Test, Sub::Setup] {
            assert!(usage(Some(sub)).contains(&format!("cargo xtask {}", sub.name())));
        }
    }

    #[test]
    fn nothing_to_do_when_nothing_is_missing() {
        for is_root in [false, true] {
            for has_sudo in [false, true] {
                for has_apt in [false, true] {
                    let host = access(is_root, has_sudo, has_apt);
                    assert_eq!(decide_setup(&[], host), SetupAction::NothingToDo);
                }
            }
        }
    }

    #[test]
    fn root_installs_directly() {
        assert_eq!(
            decide_setup(ALL_MISSING, access(true, false, true)),
            SetupAction::Install { use_sudo: false }
        );
        assert_eq!(
            decide_setup(&[Requirement::Xvfb], access(true, true, true)),
            SetupAction::Install { use_sudo: false }
        );
    }

    #[test]
    fn passwordless_sudo_installs_through_sudo() {
        assert_eq!(
            decide_setup(ALL_MISSING, access(false, true, true)),
            SetupAction::Install { use_sudo: true }
        );
    }

    #[test]
    fn without_privileges_or_apt_the_user_is_told() {
        assert_eq!(
            decide_setup(ALL_MISSING, access(false, false, true)),
            SetupAction::Manual(ManualReason::CannotElevate)
        );
        for is_root in [false, true] {
            assert_eq!(
                decide_setup(&[Requirement::Lavapipe], access(is_root, true, false)),
                SetupAction::Manual(ManualReason::NoApt)
            );
        }
    }

    #[test]
    fn manual_instructions_name_the_packages_and_the_reason() {
        let text = manual_instructions(
            &[Requirement::Lavapipe, Requirement::Xvfb],
            ManualReason::CannotElevate,
        );
        assert!(text.contains(
            "sudo apt-get install -y --no-install-recommends \
             mesa-vulkan-drivers libvulkan1 xvfb xauth"
        ));
        assert!(text.contains("lavapipe"));
        assert!(text.contains("Xvfb (virtual X server)"));
        assert!(!text.contains("libvulkan.so.1"));
        assert!(text.contains("passwordless sudo"));
        assert!(text.contains("Other distros"));
        let text = manual_instructions(&[Requirement::VulkanLoader], ManualReason::NoApt);
        assert!(text.contains("apt-get was not found"));
    }

    #[test]
    fn install_commands_update_then_install() {
        let direct = install_commands(false);
        assert_eq!(direct[0], strings(&["apt-get", "update"]));
        assert_eq!(
            direct[1],
            strings(&[
                "apt-get",
                "install",
                "-y",
                "--no-install-recommends",
                "mesa-vulkan-drivers",
                "libvulkan1",
                "xvfb",
                "xauth",
            ])
        );
        let sudo = install_commands(true);
        for (with_sudo, without) in sudo.iter().zip(&direct) {
            assert_eq!(
                &with_sudo[..4],
                strings(&["sudo", "-n", "env", "DEBIAN_FRONTEND=noninteractive"])
            );
            assert_eq!(&with_sudo[4..], &without[..]);
        }
    }

    #[test]
    fn recognises_lavapipe_and_the_loader() {
        assert!(is_lavapipe_icd("lvp_icd.x86_64.json"));
        assert!(is_lavapipe_icd("lvp_icd.json"));
        assert!(!is_lavapipe_icd("radeon_icd.x86_64.json"));
        assert!(!is_lavapipe_icd("lvp_icd.x86_64.json.bak"));
        let listing = "1234 libs found in cache `/etc/ld.so.cache'\n\
             \tlibvulkan.so.1 (libc6,x86-64) => /lib/x86_64-linux-gnu/libvulkan.so.1\n\
             \tlibz.so.1 (libc6,x86-64) => /lib/x86_64-linux-gnu/libz.so.1\n";
        assert!(ldconfig_lists(listing, "libvulkan.so.1"));
        assert!(!ldconfig_lists(listing, "libvulkan.so"));
        assert!(!ldconfig_lists(
            "\tlibvulkan.so (libc6) => /x\n",
            "libvulkan.so.1"
        ));
    }

    #[test]
    fn test_steps_are_in_order_with_their_environment() {
        let steps = test_steps();
        let lines: Vec<String> = steps.iter().map(Step::describe).collect();
        assert_eq!(
            lines,
            [
                "cargo fmt --all -- --check",
                "cargo clippy --workspace --all-targets -- -D warnings",
                "RUST_TEST_THREADS=1 TEXEL_REQUIRE_GPU=1 TEXEL_REQUIRE_DISPLAY=1 cargo test --workspace --all-targets",
                "RUST_TEST_THREADS=1 TEXEL_REQUIRE_GPU=1 TEXEL_REQUIRE_DISPLAY=1 cargo test --workspace --doc",
            ]
        );
        let display: Vec<bool> = steps.iter().map(|step| step.needs_display).collect();
        assert_eq!(display, [false, false, true, false]);
    }

    #[test]
    fn main_job_uses_defaults_or_replacements() {
        let job = MainJob {
            package: "texel_runtime",
            bin: "texel-run",
            default_args: &["check", "a.ron"],
            needs_display: false,
        };
        assert_eq!(
            job.step(None).describe(),
            "cargo run -p texel_runtime --bin texel-run -- check a.ron"
        );
        assert_eq!(
            job.step(Some(&strings(&["check", "b.ron"]))).describe(),
            "cargo run -p texel_runtime --bin texel-run -- check b.ron"
        );
        assert_eq!(
            job.step(Some(&[])).describe(),
            "cargo run -p texel_runtime --bin texel-run --"
        );
    }

    #[test]
    fn formats_durations() {
        assert_eq!(format_duration(Duration::from_millis(420)), "0.4 s");
        assert_eq!(format_duration(Duration::from_millis(59_940)), "59.9 s");
        assert_eq!(format_duration(Duration::from_secs(245)), "4 min 05 s");
    }

    #[test]
    fn workspace_root_holds_the_workspace_manifest() {
        assert!(workspace_root().join("Cargo.toml").is_file());
        assert!(workspace_root().join("xtask").is_dir());
    }
}
