//! The second driver's pass: each test binary's GPU tests in one process.
//!
//! On SwiftShader most of a GPU test's time was compiling its pipelines (about 4–7 s a test,
//! the same pipelines in every test of a binary), paid again in every process because
//! nextest runs each test in a process of its own and SwiftShader keeps nothing between
//! processes. Here each binary runs once, under libtest, with exactly its GPU tests
//! (`--exact NAME...`) one after another (`--test-threads=1`): `test_context()` hands every
//! test the process's one device, whose pipelines are compiled once
//! (`texel_render::pipeline_cache`). As many binaries run at once as the machine has cores,
//! the slowest first.
//!
//! What nextest gave the first pass, this pass keeps: libtest names each test as it starts
//! and ends (one at a time, it prints `test NAME ... ` before running it), so each test's
//! wall time is measured here; a test past [`BUDGET`] is killed with its process and fails
//! by name; and the device log is written per test: every test that asks for a context, or
//! starts a program that opens a device, appends a line to its process's log while it runs,
//! and the lines that appeared while a test ran are that test's.

use std::collections::BTreeMap;
use std::io::Read as _;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::plan::{self, TestId, Timing};
use crate::session::{Session, Step};
use crate::{Driver, Failure, read_device_log, test_plan_dir};
use std::fs;
use std::thread;

/// A test still running after this long is killed and fails (the first pass's budget is
/// nextest's `slow-timeout` in `.config/nextest.toml`; SwiftShader takes about 4× lavapipe's
/// time). No test is allowed longer today.
pub(crate) const BUDGET: Duration = Duration::from_secs(300);

/// One test binary and the tests of it to run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Suite {
    /// nextest's binary id.
    pub(crate) binary: String,
    /// The executable.
    pub(crate) path: PathBuf,
    /// Where it runs (its package's directory, as under cargo and nextest).
    pub(crate) cwd: PathBuf,
    /// Test names, in the binary's order.
    pub(crate) tests: Vec<String>,
}

/// The suites holding `tests`, from `cargo nextest list --message-format json`'s output.
pub(crate) fn suites(list_json: &str, tests: &[TestId]) -> Result<Vec<Suite>, String> {
    let list: serde_json::Value = serde_json::from_str(list_json)
        .map_err(|e| format!("cannot read nextest's test list: {e}"))?;
    let mut wanted: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for t in tests {
        wanted.entry(&t.binary).or_default().push(&t.name);
    }
    let mut out = Vec::new();
    for (binary, names) in wanted {
        let suite = &list["rust-suites"][binary];
        let field = |key: &str| {
            suite[key]
                .as_str()
                .map(PathBuf::from)
                .ok_or_else(|| format!("nextest lists no {key} for the test binary `{binary}`"))
        };
        let (path, cwd) = (field("binary-path")?, field("cwd")?);
        let listed = suite["testcases"].as_object();
        let mut tests = Vec::new();
        for name in names {
            if !listed.is_some_and(|cases| cases.contains_key(name)) {
                return Err(format!("nextest lists no test `{name}` in `{binary}`"));
            }
            tests.push(name.to_owned());
        }
        out.push(Suite {
            binary: binary.to_owned(),
            path,
            cwd,
            tests,
        });
    }
    Ok(out)
}

/// `suites` ordered for running: the most expensive first (`weight`: seconds the binary's
/// tests took on the first driver), so the last to start are short.
pub(crate) fn by_weight(mut suites: Vec<Suite>, weight: &BTreeMap<String, f64>) -> Vec<Suite> {
    let w = |s: &Suite| weight.get(&s.binary).copied().unwrap_or(0.0);
    suites.sort_by(|a, b| w(b).total_cmp(&w(a)).then_with(|| a.binary.cmp(&b.binary)));
    suites
}

/// `suites` with each binary heavier than a lane's fair share (the total `weight` over
/// `lanes`; `weight` holds each test's seconds on the first driver, by binary and name) cut
/// into that many processes, its tests dealt heaviest first to the lightest part, so the pass
/// is not as long as its heaviest binary alone. Each part pays for its own device.
pub(crate) fn balanced(
    suites: Vec<Suite>,
    weight: &BTreeMap<(String, String), f64>,
    lanes: usize,
) -> Vec<Suite> {
    let w = |s: &Suite, t: &String| weight.get(&(s.binary.clone(), t.clone())).copied();
    let total: f64 = (suites.iter())
        .flat_map(|s| s.tests.iter().map(move |t| w(s, t).unwrap_or(0.0)))
        .sum();
    let share = total / lanes.max(1) as f64;
    let mut out = Vec::new();
    for suite in suites {
        let own: f64 = suite
            .tests
            .iter()
            .map(|t| w(&suite, t).unwrap_or(0.0))
            .sum();
        let parts = if share > 0.0 {
            ((own / share).ceil() as usize).clamp(1, suite.tests.len().max(1))
        } else {
            1
        };
        if parts <= 1 {
            out.push(suite);
            continue;
        }
        let mut tests = suite.tests.clone();
        tests.sort_by(|a, b| {
            let (wa, wb) = (w(&suite, a).unwrap_or(0.0), w(&suite, b).unwrap_or(0.0));
            wb.total_cmp(&wa).then_with(|| a.cmp(b))
        });
        let mut bins: Vec<(f64, Vec<String>)> = vec![(0.0, Vec::new()); parts];
        for t in tests {
            let lightest = (0..parts)
                .min_by(|&i, &j| bins[i].0.total_cmp(&bins[j].0))
                .unwrap_or(0);
            bins[lightest].0 += w(&suite, &t).unwrap_or(0.0);
            bins[lightest].1.push(t);
        }
        for (_, mut part) in bins.into_iter().filter(|b| !b.1.is_empty()) {
            // In the binary's own order within a part.
            part.sort_by_key(|t| suite.tests.iter().position(|x| x == t));
            out.push(Suite {
                tests: part,
                ..suite.clone()
            });
        }
    }
    out
}

/// What libtest says about one test.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Event {
    /// `test NAME ... ` (printed before the test runs when tests run one at a time).
    Started(String),
    /// `test NAME ... ok` (or `FAILED`, `ignored`): whether it passed.
    Finished(String, bool),
    /// Any other whole line.
    Line(String),
}

/// Reads libtest's output as it comes, in pieces of any size.
#[derive(Default)]
pub(crate) struct Events {
    pending: String,
    started: bool,
}

impl Events {
    /// The events `chunk` completes.
    pub(crate) fn feed(&mut self, chunk: &str) -> Vec<Event> {
        self.pending.push_str(chunk);
        let mut events = Vec::new();
        loop {
            if !self.started
                && let Some(name) = started_name(&self.pending)
            {
                self.started = true;
                events.push(Event::Started(name));
            }
            let Some(end) = self.pending.find('\n') else {
                break;
            };
            let line: String = self.pending.drain(..=end).collect();
            let line = line.trim_end_matches(['\n', '\r']);
            let was_started = std::mem::take(&mut self.started);
            match finished(line) {
                Some((name, ok)) => {
                    if !was_started {
                        events.push(Event::Started(name.clone()));
                    }
                    events.push(Event::Finished(name, ok));
                }
                None => events.push(Event::Line(line.to_owned())),
            }
        }
        events
    }
}

/// The name in a line begun as `test NAME ... `.
fn started_name(pending: &str) -> Option<String> {
    let line = pending.split('\n').next()?;
    let rest = line.strip_prefix("test ")?;
    let (name, _) = rest.split_once(" ... ")?;
    Some(name.to_owned())
}

/// `(NAME, passed)` of a line `test NAME ... ok|FAILED|ignored`.
fn finished(line: &str) -> Option<(String, bool)> {
    let rest = line.strip_prefix("test ")?;
    let (name, verdict) = rest.split_once(" ... ")?;
    let ok = match verdict.trim() {
        "ok" | "ignored" => true,
        "FAILED" => false,
        _ => return None,
    };
    Some((name.to_owned(), ok))
}

/// One test's outcome on the second driver.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Outcome {
    /// The test and its wall time.
    pub(crate) timing: Timing,
    /// Passed (`false`: failed, or killed past the budget).
    pub(crate) passed: bool,
    /// Whether it asked for a device (its process's log grew while it ran).
    pub(crate) used_gpu: bool,
    /// Killed past [`BUDGET`].
    pub(crate) timed_out: bool,
}

/// What the pass did: every test's outcome, and the binaries that failed outside a test
/// (crashed, or exited non-zero with every test passed).
#[derive(Default)]
pub(crate) struct PassResult {
    pub(crate) outcomes: Vec<Outcome>,
    pub(crate) broken: Vec<String>,
}

/// Runs `suites` on `lanes` processes at once with `env` (the driver's), each process
/// logging its devices to a file of its own in `log_dir`.
pub(crate) fn run(
    suites: Vec<Suite>,
    lanes: usize,
    env: &[(String, std::ffi::OsString)],
    log_dir: &std::path::Path,
) -> PassResult {
    let queue = Arc::new(Mutex::new(
        suites.into_iter().enumerate().collect::<Vec<_>>(),
    ));
    queue.lock().unwrap_or_else(|e| e.into_inner()).reverse();
    let result = Arc::new(Mutex::new(PassResult::default()));
    std::thread::scope(|scope| {
        for _ in 0..lanes.max(1) {
            let (queue, result) = (queue.clone(), result.clone());
            scope.spawn(move || {
                loop {
                    let next = queue.lock().unwrap_or_else(|e| e.into_inner()).pop();
                    let Some((i, suite)) = next else { break };
                    let log = log_dir.join(format!("second-pass-{i}.txt"));
                    let (outcomes, broken) = run_suite(&suite, env, &log);
                    let mut r = result.lock().unwrap_or_else(|e| e.into_inner());
                    r.outcomes.extend(outcomes);
                    r.broken.extend(broken);
                }
            });
        }
    });
    let mut result = std::mem::take(&mut *result.lock().unwrap_or_else(|e| e.into_inner()));
    result
        .outcomes
        .sort_by(|a, b| a.timing.test.cmp(&b.timing.test));
    result
}

/// The test running in a process, and since when.
type Running = Arc<Mutex<Option<(String, Instant)>>>;

/// Runs one suite's tests in one process; its outcomes, and why the process failed
/// outside its tests, if it did.
fn run_suite(
    suite: &Suite,
    env: &[(String, std::ffi::OsString)],
    log: &std::path::Path,
) -> (Vec<Outcome>, Option<String>) {
    let _ = std::fs::write(log, "");
    let mut command = Command::new(&suite.path);
    command
        .arg("--exact")
        .args(&suite.tests)
        .arg("--test-threads=1")
        .current_dir(&suite.cwd)
        .envs(env.iter().map(|(k, v)| (k, v)))
        .env(crate::plan::DEVICE_LOG_VAR, log)
        .env(
            crate::plan::SHORT_TESTS_VAR,
            crate::plan::short_tests_value(),
        )
        .env("CARGO_MANIFEST_DIR", &suite.cwd)
        .env_remove("TEXEL_ALLOW_NO_GPU")
        .stdout(Stdio::piped());
    let mut child = match command.spawn() {
        Ok(child) => child,
        Err(e) => {
            return (
                Vec::new(),
                Some(format!("{}: cannot start: {e}", suite.binary)),
            );
        }
    };
    let Some(mut stdout) = child.stdout.take() else {
        return (Vec::new(), Some(format!("{}: no output", suite.binary)));
    };
    let child = Arc::new(Mutex::new(child));
    let running: Running = Arc::default();
    let killed: Arc<Mutex<Option<String>>> = Arc::default();
    let done = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let watchdog = {
        let (child, running, killed, done) =
            (child.clone(), running.clone(), killed.clone(), done.clone());
        std::thread::spawn(move || {
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(250));
                let over = (running.lock().unwrap_or_else(|e| e.into_inner()).as_ref())
                    .filter(|(_, since)| since.elapsed() > BUDGET)
                    .map(|(name, _)| name.clone());
                if let Some(name) = over {
                    let _ = child.lock().unwrap_or_else(|e| e.into_inner()).kill();
                    *killed.lock().unwrap_or_else(|e| e.into_inner()) = Some(name);
                    break;
                }
            }
        })
    };
    let mut outcomes = Vec::new();
    let mut events = Events::default();
    let mut log_len = 0;
    let mut buf = [0u8; 4096];
    let echo = |line: &str| println!("    {line}");
    loop {
        let n = match stdout.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => n,
        };
        for event in events.feed(&String::from_utf8_lossy(&buf[..n])) {
            match event {
                Event::Started(name) => {
                    log_len = file_len(log);
                    *running.lock().unwrap_or_else(|e| e.into_inner()) =
                        Some((name, Instant::now()));
                }
                Event::Finished(name, passed) => {
                    let since = running.lock().unwrap_or_else(|e| e.into_inner()).take();
                    let seconds = since.map_or(0.0, |(_, t)| t.elapsed().as_secs_f64());
                    let used_gpu = file_len(log) > log_len;
                    let verdict = if passed { "PASS" } else { "FAIL" };
                    echo(&format!(
                        "{verdict} [{seconds:>7.1}s] {} {name}",
                        suite.binary
                    ));
                    outcomes.push(outcome(suite, name, seconds, passed, used_gpu, false));
                }
                Event::Line(line) if !line.is_empty() => echo(&line),
                Event::Line(_) => {}
            }
        }
    }
    let status = child.lock().unwrap_or_else(|e| e.into_inner()).wait();
    done.store(true, std::sync::atomic::Ordering::Relaxed);
    let _ = watchdog.join();
    if let Some(name) = killed.lock().unwrap_or_else(|e| e.into_inner()).take() {
        let seconds = BUDGET.as_secs_f64();
        echo(&format!(
            "TIMEOUT [{seconds:>7.1}s] {} {name} (past the budget)",
            suite.binary
        ));
        let used_gpu = file_len(log) > log_len;
        outcomes.push(outcome(suite, name, seconds, false, used_gpu, true));
        return (outcomes, None);
    }
    // A test that took the shared device names itself in the log (libtest's thread name):
    // its own lines count even when they were written before its start line was read.
    let log_text = fs::read_to_string(log).unwrap_or_default();
    for o in &mut outcomes {
        let named = (log_text.lines())
            .any(|line| line.split('\t').nth(1) == Some(o.timing.test.name.as_str()));
        o.used_gpu |= named;
    }
    let broken = match status {
        Ok(s) if s.success() => None,
        // A failed test makes libtest exit non-zero: that failure is the test's.
        Ok(_) if outcomes.iter().any(|o| !o.passed) => None,
        Ok(s) => Some(format!("{}: exited with {s}, no test failed", suite.binary)),
        Err(e) => Some(format!("{}: {e}", suite.binary)),
    };
    (outcomes, broken)
}

fn outcome(
    suite: &Suite,
    name: String,
    seconds: f64,
    passed: bool,
    used_gpu: bool,
    timed_out: bool,
) -> Outcome {
    Outcome {
        timing: Timing {
            test: TestId {
                binary: suite.binary.clone(),
                name,
            },
            seconds,
        },
        passed,
        used_gpu,
        timed_out,
    }
}

fn file_len(path: &std::path::Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}

/// Where the second pass keeps its tests' times (`binary<TAB>test<TAB>seconds` lines).
pub(crate) fn timings_file() -> PathBuf {
    test_plan_dir().join("swiftshader-times.txt")
}

/// The SwiftShader pass: `step` builds and lists the tests, then every GPU test of the
/// lavapipe pass (less the exceptions) runs, each binary's in one process
/// ([`second_pass`]). Writes the pass's device log and timings; fails naming each test
/// that failed, timed out or did not run.
pub(crate) fn run_pass(session: &mut Session, step: &Step) -> Result<(), Failure> {
    let gpu = read_device_log(Driver::Lavapipe)?;
    let second = plan::second_driver_tests(&gpu.tests);
    println!(
        "==> {} tests opened a GPU device on lavapipe; {} run on SwiftShader",
        gpu.tests.len(),
        second.len()
    );
    if second.is_empty() {
        return Err(Failure::new(
            "no test opened a GPU device on lavapipe, so the plan has no GPU tests for \
             SwiftShader: the device log is not being written",
        ));
    }
    let list = session.output(step)?;
    let suites = suites(&list, &second).map_err(Failure::new)?;
    let mut weight = std::collections::BTreeMap::new();
    let mut per_test = std::collections::BTreeMap::new();
    if let Ok(xml) = fs::read_to_string(Driver::Lavapipe.junit()) {
        for t in plan::parse_junit(&xml) {
            *weight.entry(t.test.binary.clone()).or_insert(0.0) += t.seconds;
            per_test.insert((t.test.binary, t.test.name), t.seconds);
        }
    }
    let lanes = thread::available_parallelism().map_or(1, |n| n.get());
    let binaries = suites.len();
    let suites = balanced(suites, &per_test, lanes);
    let mut parts = std::collections::BTreeMap::new();
    for s in &suites {
        *parts.entry(s.binary.clone()).or_insert(0.0) += 1.0;
    }
    // A part weighs its binary's weight over the parts (for the heaviest-first order).
    let weight: BTreeMap<String, f64> = (weight.into_iter())
        .map(|(b, w)| {
            let n = parts.get(&b).copied().unwrap_or(1.0);
            (b, w / n)
        })
        .collect();
    let suites = by_weight(suites, &weight);
    println!(
        "==> {binaries} binaries in {} processes (the heaviest cut to a lane's share), {lanes} \
         at a time (a test's budget: {} s)",
        suites.len(),
        BUDGET.as_secs()
    );
    let env = session.step_env(step);
    let result = run(suites, lanes, &env, &test_plan_dir());
    let mut log = String::new();
    let mut times = String::new();
    let mut failed = Vec::new();
    for o in &result.outcomes {
        let t = &o.timing.test;
        if o.used_gpu {
            log.push_str(&format!("{}\t{}\n", t.binary, t.name));
        }
        times.push_str(&format!(
            "{}\t{}\t{:.3}\n",
            t.binary, t.name, o.timing.seconds
        ));
        if o.timed_out {
            failed.push(format!("  {t} (TIMEOUT: past {} s)", BUDGET.as_secs()));
        } else if !o.passed {
            failed.push(format!("  {t}"));
        }
    }
    let passed = result.outcomes.iter().filter(|o| o.passed).count() as u64;
    session.tally.passed += passed;
    session.tally.failed += result.outcomes.len() as u64 - passed;
    fs::write(Driver::SwiftShader.device_log(), log)
        .and_then(|()| fs::write(timings_file(), times))
        .map_err(|e| Failure::new(format!("cannot write the second pass's records: {e}")))?;
    failed.extend(result.broken.iter().map(|b| format!("  {b}")));
    if failed.is_empty() {
        return Ok(());
    }
    Err(Failure::new(format!(
        "on SwiftShader:\n{}",
        failed.join("\n")
    )))
}

/// After the SwiftShader pass: every GPU test of the lavapipe pass (but the exceptions)
/// opened a device on SwiftShader too.
pub(crate) fn check_second_driver() -> Result<(), Failure> {
    let first = read_device_log(Driver::Lavapipe)?.tests;
    let second = read_device_log(Driver::SwiftShader)?.tests;
    let missing = plan::missing_from_second(&first, &second);
    println!(
        "==> GPU tests: {} on lavapipe, {} on SwiftShader ({} excepted by name)",
        first.len(),
        second.len(),
        first.len() - plan::second_driver_tests(&first).len()
    );
    if missing.is_empty() {
        return Ok(());
    }
    let names: Vec<String> = missing.iter().map(|t| format!("  {t}")).collect();
    Err(Failure::new(format!(
        "these GPU tests opened a device on lavapipe but not on SwiftShader:\n{}",
        names.join("\n")
    )))
}
