//! System packages: what Texel needs on the machine (the Vulkan loader, Mesa lavapipe,
//! Chromium's SwiftShader, Xvfb, xauth, xdotool), how to tell whether it is there, and how to install
//! it or say how.

#[allow(unused_imports)]
use super::*;

/// Something Texel needs from the operating system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Requirement {
    /// The Vulkan loader, `libvulkan.so.1`.
    VulkanLoader,
    /// Mesa's lavapipe: a Vulkan driver running on the CPU.
    Lavapipe,
    /// The virtual X server, for window tests without a screen.
    Xvfb,
    /// `xauth`, used to authorise clients of the virtual X server.
    Xauth,
    /// SwiftShader (from Chromium), a second Vulkan driver running on the CPU.
    SwiftShader,
    /// `xdotool`, with which a test types into the editor's window (the kill-and-recover
    /// test).
    Xdotool,
}

impl Requirement {
    /// Every requirement, in the order they are reported.
    pub(crate) const ALL: [Requirement; 6] = [
        Requirement::VulkanLoader,
        Requirement::Lavapipe,
        Requirement::Xvfb,
        Requirement::Xauth,
        Requirement::SwiftShader,
        Requirement::Xdotool,
    ];

    /// A short human description.
    pub(crate) fn describe(self) -> &'static str {
        match self {
            Requirement::VulkanLoader => "Vulkan loader (libvulkan.so.1)",
            Requirement::Lavapipe => "Mesa lavapipe Vulkan driver (lvp_icd*.json)",
            Requirement::Xvfb => "Xvfb (virtual X server)",
            Requirement::Xauth => "xauth",
            Requirement::SwiftShader => "SwiftShader Vulkan driver (vk_swiftshader_icd.json)",
            Requirement::Xdotool => "xdotool (types into a window in a test)",
        }
    }

    /// Whether the requirement is met on this machine.
    pub(crate) fn is_present(self) -> bool {
        match self {
            Requirement::VulkanLoader => has_shared_library("libvulkan.so.1"),
            Requirement::Lavapipe => has_lavapipe_icd(),
            Requirement::Xvfb => find_in_path("Xvfb").is_some(),
            Requirement::Xauth => find_in_path("xauth").is_some(),
            Requirement::SwiftShader => Path::new(SWIFTSHADER_ICD).is_file(),
            Requirement::Xdotool => find_in_path("xdotool").is_some(),
        }
    }
}

/// The requirements not met on this machine.
pub(crate) fn missing_requirements() -> Vec<Requirement> {
    Requirement::ALL
        .into_iter()
        .filter(|requirement| !requirement.is_present())
        .collect()
}

/// What this machine allows for installing packages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct HostAccess {
    /// Running as root (uid 0).
    pub(crate) is_root: bool,
    /// `sudo -n true` succeeds (passwordless sudo).
    pub(crate) has_sudo: bool,
    /// `apt-get` is on `PATH`.
    pub(crate) has_apt: bool,
}

/// Why the packages cannot be installed automatically.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ManualReason {
    /// No `apt-get`: probably not Debian or Ubuntu.
    NoApt,
    /// Not root and no passwordless sudo.
    CannotElevate,
}

/// What the set-up step should do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SetupAction {
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
pub(crate) fn decide_setup(missing: &[Requirement], access: HostAccess) -> SetupAction {
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
pub(crate) fn install_commands(use_sudo: bool) -> Vec<Vec<String>> {
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
pub(crate) fn manual_instructions(missing: &[Requirement], reason: ManualReason) -> String {
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
         \x20   xorg-server-xvfb xorg-xauth; and Chromium's SwiftShader Vulkan driver with its\n\
         \x20   manifest at {SWIFTSHADER_ICD} (the tests' second Vulkan); and xdotool",
        list.join("\n"),
        APT_PACKAGES.join(" ")
    )
}

/// Makes sure the toolchain and the system packages are there, installing the
/// packages when possible.
pub(crate) fn ensure_system() -> Result<(), Failure> {
    check_toolchain()?;
    let missing = missing_requirements();
    if missing.is_empty() {
        println!(
            "==> system packages: all present (Vulkan loader, lavapipe, SwiftShader, Xvfb, xauth, xdotool)"
        );
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
pub(crate) fn run_install_command(command: &[String]) -> Result<(), Failure> {
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
pub(crate) fn check_toolchain() -> Result<(), Failure> {
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

/// Checks that the cargo subcommands used by `test` are installed, and installs
/// cargo-nextest when it is not.
pub(crate) fn check_test_components() -> Result<(), Failure> {
    for (component, subcommand) in [("rustfmt", "fmt"), ("clippy", "clippy")] {
        if command_output(&cargo_program(), &[subcommand, "--version"]).is_none() {
            return Err(Failure::new(format!(
                "`cargo {subcommand}` is not available: install it with \
                 `rustup component add {component}`"
            )));
        }
    }
    if command_output(&cargo_program(), &["nextest", "--version"]).is_none() {
        // nextest runs the tests (one process per test, per-test budgets, JUnit timings).
        // Only crates.io may be reachable, so it is built from source (a few minutes, once).
        let install = ["install", "--locked", "cargo-nextest"];
        println!("==> cargo-nextest is missing: cargo {}", install.join(" "));
        let status = Command::new(cargo_program())
            .args(install)
            .status()
            .map_err(|e| Failure::new(format!("could not start cargo install: {e}")))?;
        if !status.success() {
            return Err(Failure::new(format!(
                "`cargo {}` failed ({status}); install cargo-nextest \
                 (https://nexte.st) and run this again",
                install.join(" ")
            )));
        }
    }
    Ok(())
}

/// Whether the dynamic linker knows `library` (from `ldconfig -p`, or common
/// library directories when ldconfig cannot be run).
pub(crate) fn has_shared_library(library: &str) -> bool {
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
pub(crate) fn ldconfig_lists(listing: &str, library: &str) -> bool {
    listing
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .any(|name| name == library)
}

/// Whether a lavapipe ICD manifest is installed.
pub(crate) fn has_lavapipe_icd() -> bool {
    ICD_DIRS.iter().any(|dir| {
        fs::read_dir(dir).is_ok_and(|entries| {
            entries
                .flatten()
                .any(|entry| is_lavapipe_icd(&entry.file_name().to_string_lossy()))
        })
    })
}

/// Whether `file_name` is a lavapipe ICD manifest (`lvp_icd*.json`).
pub(crate) fn is_lavapipe_icd(file_name: &str) -> bool {
    file_name.starts_with("lvp_icd") && file_name.ends_with(".json")
}

/// Whether this process runs as root.
pub(crate) fn is_root() -> bool {
    if let Ok(metadata) = fs::metadata("/proc/self") {
        return metadata.uid() == 0;
    }
    command_output(Path::new("id"), &["-u"]).is_some_and(|uid| uid.trim() == "0")
}

/// Whether `sudo -n true` succeeds, i.e. sudo works without a password.
pub(crate) fn sudo_works() -> bool {
    Command::new("sudo")
        .args(["-n", "true"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|status| status.success())
}
