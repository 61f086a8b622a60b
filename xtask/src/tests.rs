//! Unit tests of the pure parts of xtask: argument parsing, set-up decisions, steps.
use super::*;

#[test]
fn tally_sums_libtest_summaries() {
    let mut t = Tally::default();
    t.add_line("test result: ok. 9 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.02s");
    t.add_line("test result: FAILED. 3 passed; 2 failed; 0 ignored; 0 measured; 0 filtered out");
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
            "chromium-common",
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
            "RUST_TEST_THREADS=1 cargo test --workspace --all-targets --no-fail-fast",
            "RUST_TEST_THREADS=1 cargo test --workspace --doc --no-fail-fast",
            "RUST_TEST_THREADS=1 \
             VK_ICD_FILENAMES=/usr/lib/chromium/vk_swiftshader_icd.json \
             TEXEL_EXPECT_ADAPTER=SwiftShader cargo test --workspace --tests --no-fail-fast -- --skip golden_images \
             --skip plays_five_frames_of_the_stone_circle_and_exits",
        ]
    );
    let display: Vec<bool> = steps.iter().map(|step| step.needs_display).collect();
    assert_eq!(display, [false, false, true, false, true]);
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
