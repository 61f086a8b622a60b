//! The test plan: which tests run on which driver, and what each one cost.
//!
//! Every test runs once on lavapipe under cargo-nextest, one process per test. Each process
//! that opens a wgpu device (`texel_render::context::GpuContext`, also inside a `texel-run`
//! or `texel-eval` the test starts) appends its test's name to the file named by
//! [`DEVICE_LOG_VAR`]. Those tests, and only those, run again on SwiftShader, less the
//! [`SECOND_DRIVER_EXCEPTIONS`] (each binary's in one process: `second_pass`). So a new GPU
//! test joins the two-driver set by opening a device, and a CPU-only test never runs twice.
//! After the second pass the two records are compared ([`missing_from_second`]): a GPU test
//! that did not use a device on SwiftShader fails the run by name.
//!
//! The time each test took comes from nextest's JUnit report on lavapipe ([`parse_junit`])
//! and from the second pass's own record ([`parse_timings`]); the run prints the slowest per
//! driver. The per-test budget is nextest's `slow-timeout` in `.config/nextest.toml` (where
//! the tests allowed longer are listed with their reasons) and `second_pass::BUDGET`.

use std::collections::{BTreeMap, BTreeSet};

/// The variable naming the file each device-opening test process appends its name to.
pub(crate) const DEVICE_LOG_VAR: &str = "TEXEL_GPU_TEST_LOG";

/// GPU tests the second driver does not run: a part of the test's name, and why.
pub(crate) const SECOND_DRIVER_EXCEPTIONS: &[(&str, &str)] = &[
    (
        "golden_images",
        "compares against lavapipe's own pixels (tests/golden); SwiftShader rasterizes with \
         4-bit sub-pixel precision and rounds depth its own way, so it differs by design",
    ),
    (
        "a_killed_editor_offers_its_last_autosave_and_leaves_the_level_alone",
        "starts the real texel-editor, whose window presents through the window system; the \
         SwiftShader Chromium ships has no window-system surfaces",
    ),
    (
        "plays_five_frames_of_the_stone_circle_and_exits",
        "presents to a window; the SwiftShader Chromium ships has no window-system surfaces \
         (`texel-run play` says so, which its other tests check)",
    ),
];

/// The variable naming the tests that run in their short form (a comma-separated list of
/// parts of test names; `texel_render::context::short_form` reads it).
pub(crate) const SHORT_TESTS_VAR: &str = "TEXEL_SHORT_TESTS";

/// GPU tests the second driver runs in a short form: a part of the test's name, and why.
/// Such a test flies the first half of its camera path's frames (`CameraPath::first`, the
/// same cameras to the bit) with the same level, methods, size and face resolution, and
/// checks the same bounds; its full form runs on lavapipe. Only measurement-heavy tests
/// whose bound is a ratio or a mean over the path belong here: the second driver is there to
/// catch a driver-dependent result, which shows on half a path as on all of it.
/// Each was run in its short form on SwiftShader before it was listed; two that failed
/// their bound on the first half (the dither pattern across cells, the diagonal run between
/// the pillars) run whole.
pub(crate) const SECOND_DRIVER_SHORT: &[(&str, &str)] = &[
    (
        "junctions_and_edges_against_farther_walls_are_as_tight_as_low_resolution_rendering",
        "splat's coverage error against naive's (a ratio) along the colonnade's occluder pass \
         at 320x180, faces of 128: 40 s on SwiftShader in full",
    ),
    (
        "sprites_stay_locked_to_the_world_inside_a_cell",
        "sprite shimmer against the image's and camera-facing sprites' (ratios) on two paths \
         at 320x180: 40 s on SwiftShader in full",
    ),
    (
        "moving_objects_stay_locked_and_leave_the_world_as_stable",
        "moving against still pixels, moving and frozen, against naive's (ratios), three \
         runs of the moving parts' walk: 36 s on SwiftShader in full",
    ),
    (
        "terrain_walk_stays_well_below_naive",
        "splat's shimmer against naive's (a ratio) and the hole rate over the hills' walk: \
         35 s on SwiftShader in full",
    ),
    (
        "along_the_wall_at_faces_of_64_silhouettes_are_as_tight_as_naive",
        "splat's coverage error against naive's (a ratio) along the colonnade's wall: 19 s \
         on SwiftShader in full",
    ),
    (
        "a_dithered_palette_and_a_bloom_keep_splat_far_below_naive",
        "splat's shimmer against naive's (ratios) with a dithered palette and a bloom on \
         three walks: 28 s on SwiftShader in full",
    ),
    (
        "a_highlight_adds_no_more_shimmer_to_splat_than_to_naive",
        "the shimmer a highlight adds to splat against what it adds to naive (a ratio) on \
         two walks: 24 s on SwiftShader in full",
    ),
    (
        "walking_toward_moving_parts_stays_ten_times_below_the_baselines",
        "a weak class of views (issue 60): splat's shimmer, its ratio to the better baseline \
         and its worst frame, walking toward the moving parts: 28 s on SwiftShader in full",
    ),
    (
        "a_low_camera_outside_the_ring_stays_below_the_baselines",
        "a weak class of views (issue 60): splat's shimmer, its ratio to the better baseline \
         and its worst frame, a low camera outside the stone ring: 20 s on SwiftShader in full",
    ),
    (
        "a_camera_orbiting_near_a_sprite_stays_well_below_the_baselines",
        "a weak class of views (issue 60): splat's shimmer, its ratio to the better baseline \
         and its worst frame, orbiting near a sprite: 20 s on SwiftShader in full",
    ),
    (
        "brushing_past_stones_stays_below_the_baselines",
        "a weak class of views (issue 60): splat's shimmer, its ratio to the better baseline \
         and its worst frame, brushing past standing stones: 13 s on SwiftShader in full",
    ),
];

/// [`SECOND_DRIVER_SHORT`]'s parts as [`SHORT_TESTS_VAR`]'s value.
pub(crate) fn short_tests_value() -> String {
    let parts: Vec<&str> = SECOND_DRIVER_SHORT.iter().map(|(part, _)| *part).collect();
    parts.join(",")
}

/// How many of the slowest tests are printed per driver.
pub(crate) const SLOWEST_SHOWN: usize = 15;

/// One test, as nextest names it.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct TestId {
    /// nextest's binary id (`texel_eval::stability`, `texel_render`, ...).
    pub(crate) binary: String,
    /// The test's path inside its binary.
    pub(crate) name: String,
}

impl std::fmt::Display for TestId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.binary, self.name)
    }
}

/// What a device log holds: the tests that opened a device, and how many lines named no
/// test (a device opened outside nextest, which the plan cannot place).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct DeviceLog {
    /// Tests that opened at least one device.
    pub(crate) tests: BTreeSet<TestId>,
    /// Lines without a binary id and test name.
    pub(crate) unnamed: usize,
}

/// Reads a device log: one `binary<TAB>test` line per device opened.
pub(crate) fn parse_device_log(text: &str) -> DeviceLog {
    let mut log = DeviceLog::default();
    for line in text.lines().filter(|line| !line.trim().is_empty()) {
        match line.split_once('\t') {
            Some((binary, name))
                if !binary.is_empty() && !name.is_empty() && binary != "?" && name != "?" =>
            {
                log.tests.insert(TestId {
                    binary: binary.to_owned(),
                    name: name.to_owned(),
                });
            }
            _ => log.unnamed += 1,
        }
    }
    log
}

/// The exception that keeps `test` off the second driver, if one does.
pub(crate) fn second_driver_exception(test: &TestId) -> Option<&'static str> {
    SECOND_DRIVER_EXCEPTIONS
        .iter()
        .find(|(part, _)| test.name.contains(part))
        .map(|(_, reason)| *reason)
}

/// The GPU tests the second driver runs: every test of `gpu` but the exceptions.
pub(crate) fn second_driver_tests(gpu: &BTreeSet<TestId>) -> Vec<TestId> {
    gpu.iter()
        .filter(|test| second_driver_exception(test).is_none())
        .cloned()
        .collect()
}

/// A nextest filterset matching exactly `tests` (grouped by binary); `None` when empty.
pub(crate) fn filterset(tests: &[TestId]) -> Option<String> {
    let mut by_binary: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for test in tests {
        by_binary.entry(&test.binary).or_default().push(&test.name);
    }
    let groups: Vec<String> = by_binary
        .iter()
        .map(|(binary, names)| {
            let names: Vec<String> = names.iter().map(|name| format!("test(={name})")).collect();
            format!("(binary_id(={binary}) & ({}))", names.join(" | "))
        })
        .collect();
    (!groups.is_empty()).then(|| groups.join(" | "))
}

/// GPU tests of the first driver that did not open a device on the second one and are not
/// excepted: the plan failed to run them there.
pub(crate) fn missing_from_second(
    first: &BTreeSet<TestId>,
    second: &BTreeSet<TestId>,
) -> Vec<TestId> {
    first
        .iter()
        .filter(|test| second_driver_exception(test).is_none() && !second.contains(test))
        .cloned()
        .collect()
}

/// One test's outcome in a JUnit report.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Timing {
    /// The test.
    pub(crate) test: TestId,
    /// Wall time in seconds.
    pub(crate) seconds: f64,
}

/// The test cases of a JUnit report as nextest writes it (`<testcase name=.. classname=..
/// time=..>`, classname being the binary id). Cases without a time are left out.
pub(crate) fn parse_junit(xml: &str) -> Vec<Timing> {
    let mut timings = Vec::new();
    for chunk in xml.split("<testcase ").skip(1) {
        let Some(tag) = chunk.split('>').next() else {
            continue;
        };
        let (Some(name), Some(binary), Some(time)) = (
            attribute(tag, "name"),
            attribute(tag, "classname"),
            attribute(tag, "time"),
        ) else {
            continue;
        };
        let Ok(seconds) = time.parse::<f64>() else {
            continue;
        };
        timings.push(Timing {
            test: TestId {
                binary: unescape(&binary),
                name: unescape(&name),
            },
            seconds,
        });
    }
    timings
}

/// The run's counts from a JUnit report's `<testsuites tests=.. failures=.. errors=..>`:
/// `(tests, failed)`, failures and errors together; `None` without that element.
pub(crate) fn junit_counts(xml: &str) -> Option<(u64, u64)> {
    let tag = xml.split("<testsuites ").nth(1)?.split('>').next()?;
    let count = |key| attribute(tag, key).and_then(|v| v.parse::<u64>().ok());
    Some((
        count("tests")?,
        count("failures")? + count("errors").unwrap_or(0),
    ))
}

/// The value of attribute `key` in an XML start tag's text.
fn attribute(tag: &str, key: &str) -> Option<String> {
    let mut rest = tag;
    loop {
        let at = rest.find(&format!("{key}=\""))?;
        // A whole attribute name: `name=` must not match inside `classname=`.
        let whole = at == 0 || rest.as_bytes()[at - 1].is_ascii_whitespace();
        let value_start = at + key.len() + 2;
        if whole {
            let value = &rest[value_start..];
            return value.find('"').map(|end| value[..end].to_owned());
        }
        rest = &rest[value_start..];
    }
}

/// XML's five escapes undone.
fn unescape(text: &str) -> String {
    text.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

/// Timings written as `binary<TAB>test<TAB>seconds` lines (the second pass's); other lines
/// are left out.
pub(crate) fn parse_timings(text: &str) -> Vec<Timing> {
    (text.lines())
        .filter_map(|line| {
            let mut parts = line.split('\t');
            let (binary, name, seconds) = (parts.next()?, parts.next()?, parts.next()?);
            Some(Timing {
                test: TestId {
                    binary: binary.to_owned(),
                    name: name.to_owned(),
                },
                seconds: seconds.parse().ok()?,
            })
        })
        .collect()
}

/// The `n` slowest timings, slowest first.
pub(crate) fn slowest(timings: &[Timing], n: usize) -> Vec<Timing> {
    let mut sorted = timings.to_vec();
    sorted.sort_by(|a, b| b.seconds.total_cmp(&a.seconds));
    sorted.truncate(n);
    sorted
}

/// The slowest tests of one driver's pass as lines for people.
pub(crate) fn slowest_report(driver: &str, timings: &[Timing]) -> String {
    let total: f64 = timings.iter().map(|t| t.seconds).sum();
    let mut text = format!(
        "==> the {} slowest of {} tests on {driver} ({total:.0} s of test time in all)\n",
        SLOWEST_SHOWN.min(timings.len()),
        timings.len()
    );
    for timing in slowest(timings, SLOWEST_SHOWN) {
        text.push_str(&format!("  {:>7.1} s  {}\n", timing.seconds, timing.test));
    }
    text
}
