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
    assert_eq!(parse(&["test"]), Ok(Cli::Test(Scope::Full)));
    assert_eq!(
        parse(&["test", "--quick"]),
        Ok(Cli::Test(Scope::Quick { package: None }))
    );
    assert_eq!(
        parse(&["test", "--quick", "-p", "texel_render"]),
        Ok(Cli::Test(Scope::Quick {
            package: Some("texel_render".to_owned())
        }))
    );
    assert!(parse(&["test", "-p", "texel_render"]).is_err());
    assert!(parse(&["test", "--quick", "-p"]).is_err());
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
            "xdotool",
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
    let steps = test_steps(&Scope::Full);
    let lines: Vec<String> = steps.iter().map(Step::short).collect();
    assert_eq!(
        lines,
        [
            "cargo fmt --all -- --check",
            "cargo clippy --workspace --all-targets -- -D warnings",
            "cargo nextest run --workspace --profile lavapipe",
            "cargo test --workspace --bench '*' --no-fail-fast",
            "cargo nextest list --workspace --message-format json",
        ]
    );
    let display: Vec<bool> = steps.iter().map(|step| step.needs_display).collect();
    assert_eq!(display, [false, false, true, false, true]);
    let roles: Vec<Role> = steps.iter().map(|step| step.role).collect();
    assert_eq!(
        roles[2..],
        [
            Role::Tests(Driver::Lavapipe),
            Role::Check,
            Role::Tests(Driver::SwiftShader)
        ]
    );
    // The lavapipe pass records its devices in one file; the second pass gives each of its
    // processes a file of its own (`second_pass`) and writes its record from them.
    let env = |step: &Step, key: &str| {
        step.env
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
    };
    assert!(env(&steps[2], plan::DEVICE_LOG_VAR).is_some());
    assert_eq!(env(&steps[4], plan::DEVICE_LOG_VAR), None);
    assert_eq!(
        test_steps(&Scope::SecondDriver)
            .iter()
            .map(Step::short)
            .collect::<Vec<_>>(),
        [lines[4].clone()]
    );
    assert_eq!(
        env(&steps[4], "TEXEL_EXPECT_ADAPTER").as_deref(),
        Some("SwiftShader")
    );
    assert_eq!(
        env(&steps[4], "VK_ICD_FILENAMES").as_deref(),
        Some(SWIFTSHADER_ICD)
    );
    assert_eq!(env(&steps[2], "VK_ICD_FILENAMES"), None);
    // The quick loop runs one pass on lavapipe and records nothing.
    let quick = test_steps(&Scope::Quick { package: None });
    assert_eq!(quick.len(), 3);
    assert!(quick[2].env.is_empty());
}

fn id(binary: &str, name: &str) -> plan::TestId {
    plan::TestId {
        binary: binary.to_owned(),
        name: name.to_owned(),
    }
}

#[test]
fn the_device_log_names_tests_once_and_counts_unnamed_devices() {
    let log = plan::parse_device_log(
        "texel_eval::stability\twalk_is_stable\n\
         texel_eval::stability\twalk_is_stable\n\
         texel_render\tpasses::cull::tests::keeps\n\
         ?\t?\n\
         \n\
         broken line\n",
    );
    assert_eq!(log.tests.len(), 2);
    assert!(
        log.tests
            .contains(&id("texel_render", "passes::cull::tests::keeps"))
    );
    assert_eq!(log.unnamed, 2);
}

#[test]
fn the_second_driver_runs_every_gpu_test_but_the_named_exceptions() {
    let gpu: std::collections::BTreeSet<_> = [
        id(
            "texel_tests::splat_gpu",
            "stone_circle_golden_images_from_three_cameras",
        ),
        id("texel_tests::splat_gpu", "splats_cover_the_view"),
        id(
            "texel_runtime::play_window",
            "plays_five_frames_of_the_stone_circle_and_exits",
        ),
        id("texel_eval::stability", "walk_is_stable"),
    ]
    .into();
    let second = plan::second_driver_tests(&gpu);
    assert_eq!(
        second,
        [
            id("texel_eval::stability", "walk_is_stable"),
            id("texel_tests::splat_gpu", "splats_cover_the_view"),
        ]
    );
    // Every exception says why; so does every short form, and none is also an exception.
    for (part, reason) in plan::SECOND_DRIVER_EXCEPTIONS {
        assert!(!part.is_empty() && reason.len() > 40, "{part}: {reason}");
    }
    for (part, reason) in plan::SECOND_DRIVER_SHORT {
        assert!(
            !part.is_empty() && !part.contains(',') && reason.len() > 40,
            "{part}"
        );
        let test = id("texel_eval::stability", part);
        assert_eq!(plan::second_driver_exception(&test), None, "{part}");
    }
    assert_eq!(
        plan::short_tests_value().split(',').count(),
        plan::SECOND_DRIVER_SHORT.len()
    );
    assert_eq!(
        plan::filterset(&second).unwrap(),
        "(binary_id(=texel_eval::stability) & (test(=walk_is_stable))) | \
         (binary_id(=texel_tests::splat_gpu) & (test(=splats_cover_the_view)))"
    );
    assert_eq!(plan::filterset(&[]), None);
    // A GPU test that opened no device on the second driver is named; exceptions are not.
    let ran: std::collections::BTreeSet<_> = [id("texel_eval::stability", "walk_is_stable")].into();
    assert_eq!(
        plan::missing_from_second(&gpu, &ran),
        [id("texel_tests::splat_gpu", "splats_cover_the_view")]
    );
    assert!(plan::missing_from_second(&gpu, &second.into_iter().collect()).is_empty());
}

#[test]
fn junit_timings_and_the_slowest() {
    let xml = r#"<?xml version="1.0" encoding="UTF-8"?>
<testsuites name="nextest-run" tests="3" failures="0" errors="0" uuid="x" timestamp="t" time="9.5">
    <testsuite name="texel_scene" tests="2" disabled="0" errors="0" failures="0">
        <testcase name="level::tests::a&lt;b&gt;" classname="texel_scene" timestamp="t" time="0.250">
        </testcase>
        <testcase name="level::tests::slow" classname="texel_scene" timestamp="t" time="7.000"/>
    </testsuite>
    <testsuite name="texel_eval::stability" tests="1">
        <testcase name="walk" classname="texel_eval::stability" timestamp="t" time="2.25">
            <failure type="test failure">x</failure>
        </testcase>
    </testsuite>
</testsuites>"#;
    let timings = plan::parse_junit(xml);
    assert_eq!(timings.len(), 3);
    assert_eq!(timings[0].test, id("texel_scene", "level::tests::a<b>"));
    let slowest = plan::slowest(&timings, 2);
    assert_eq!(slowest[0].test.name, "level::tests::slow");
    assert_eq!(slowest[1].seconds, 2.25);
    assert_eq!(plan::junit_counts(xml), Some((3, 0)));
    assert_eq!(
        plan::junit_counts(r#"<testsuites name="r" tests="9" failures="2" errors="1">"#),
        Some((9, 3))
    );
    assert_eq!(plan::junit_counts("<testsuite tests=\"1\">"), None);
    let report = plan::slowest_report("lavapipe", &timings);
    assert!(report.contains("the 3 slowest of 3 tests on lavapipe"));
    assert!(report.contains("7.0 s  texel_scene level::tests::slow"));
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

#[test]
fn libtest_output_read_in_pieces_gives_each_tests_start_and_end() {
    let text = "\nrunning 3 tests\ntest a::one ... ok\ntest a::two ... FAILED\ntest b ... ignored\n\
                \ntest result: FAILED. 1 passed; 1 failed; 1 ignored\n";
    let whole = second_pass::Events::default().feed(text);
    // Fed a byte at a time, a test starts as soon as `test NAME ... ` is out.
    let mut events = second_pass::Events::default();
    let mut pieces = Vec::new();
    for (i, c) in text.char_indices() {
        let got = events.feed(&c.to_string());
        if text[..=i].ends_with("test a::one ... ") {
            assert_eq!(got, [second_pass::Event::Started("a::one".into())]);
        }
        pieces.extend(got);
    }
    assert_eq!(pieces, whole);
    use second_pass::Event::*;
    let tests: Vec<_> = (whole.iter())
        .filter(|e| !matches!(e, Line(_)))
        .cloned()
        .collect();
    assert_eq!(
        tests,
        [
            Started("a::one".into()),
            Finished("a::one".into(), true),
            Started("a::two".into()),
            Finished("a::two".into(), false),
            Started("b".into()),
            Finished("b".into(), true),
        ]
    );
    assert!(whole.contains(&Line(
        "test result: FAILED. 1 passed; 1 failed; 1 ignored".into()
    )));
}

#[test]
fn the_second_pass_finds_each_binary_and_runs_the_dearest_first() {
    let list = r#"{"rust-suites": {
        "texel_eval::stability": {"binary-path": "/t/stability-1", "cwd": "/w/eval",
            "testcases": {"walk": {}, "yaw": {}, "cpu_only": {}}},
        "texel_render": {"binary-path": "/t/texel_render-2", "cwd": "/w/crates/render",
            "testcases": {"passes::cull::tests::keeps": {}}}
    }}"#;
    let tests = [
        id("texel_render", "passes::cull::tests::keeps"),
        id("texel_eval::stability", "yaw"),
        id("texel_eval::stability", "walk"),
    ];
    let suites = second_pass::suites(list, &tests).unwrap();
    assert_eq!(suites.len(), 2);
    assert_eq!(suites[0].binary, "texel_eval::stability");
    assert_eq!(suites[0].tests, ["yaw", "walk"]);
    assert_eq!(suites[0].cwd, std::path::Path::new("/w/eval"));
    let weight = [("texel_render".to_owned(), 90.0)].into();
    let ordered = second_pass::by_weight(suites, &weight);
    assert_eq!(ordered[0].binary, "texel_render");
    // A test or binary the listing lacks is an error naming it.
    let gone = second_pass::suites(list, &[id("texel_eval::stability", "gone")]);
    assert!(gone.unwrap_err().contains("`gone`"));
    let no_binary = second_pass::suites(list, &[id("texel_tests::x", "y")]);
    assert!(no_binary.unwrap_err().contains("texel_tests::x"));
    assert!(second_pass::suites("not json", &tests).is_err());
    // Its times are kept as lines and read back.
    let times = plan::parse_timings("texel_render\ta::b\t1.500\nbroken\n");
    assert_eq!(times.len(), 1);
    assert_eq!(times[0].seconds, 1.5);
}

#[test]
fn a_binary_heavier_than_a_lanes_share_is_cut_into_parts() {
    let suite = |binary: &str, tests: &[&str]| second_pass::Suite {
        binary: binary.to_owned(),
        path: "/t/x".into(),
        cwd: "/w".into(),
        tests: tests.iter().map(|t| (*t).to_owned()).collect(),
    };
    let suites = vec![
        suite("heavy", &["a", "b", "c", "d"]),
        suite("light", &["e"]),
    ];
    let w = |b: &str, t: &str, s: f64| ((b.to_owned(), t.to_owned()), s);
    let weight = [
        w("heavy", "a", 40.0),
        w("heavy", "b", 30.0),
        w("heavy", "c", 20.0),
        w("heavy", "d", 10.0),
        w("light", "e", 10.0),
    ]
    .into();
    // 110 s over 2 lanes: a share of 55 s; the heavy binary's 100 s go in two parts.
    let parts = second_pass::balanced(suites.clone(), &weight, 2);
    assert_eq!(parts.len(), 3);
    let heavy: Vec<_> = parts.iter().filter(|s| s.binary == "heavy").collect();
    assert_eq!(heavy[0].tests, ["a", "d"], "in the binary's order");
    assert_eq!(heavy[1].tests, ["b", "c"]);
    assert_eq!(parts[2].tests, ["e"]);
    // One lane, or no times: nothing is cut.
    assert_eq!(second_pass::balanced(suites.clone(), &weight, 1), suites);
    assert_eq!(
        second_pass::balanced(suites.clone(), &Default::default(), 2),
        suites
    );
}
