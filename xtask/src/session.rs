//! Steps and their environment: the cargo invocations of `run` and `test`, the shared
//! environment (XDG_RUNTIME_DIR, WGPU_BACKEND), a virtual X server, and the test tally.

#[allow(unused_imports)]
use super::*;

/// One cargo invocation of `run` or `test`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Step {
    /// Arguments after `cargo`.
    pub(crate) args: Vec<String>,
    /// Variables set for this step only.
    pub(crate) env: Vec<(String, String)>,
    /// Whether the step may open windows (an X display is provided if possible).
    pub(crate) needs_display: bool,
    /// A check, or a test pass on one driver.
    pub(crate) role: Role,
}

impl Step {
    /// A step running `cargo ARGS` with no extra environment and no display.
    pub(crate) fn cargo(args: &[&str]) -> Step {
        Step {
            args: strings(args),
            env: Vec::new(),
            needs_display: false,
            role: Role::Check,
        }
    }

    /// The step as a shell-like line, with its extra variables first (a filter of many
    /// tests is shown by its length).
    pub(crate) fn describe(&self) -> String {
        let mut words: Vec<String> = self
            .env
            .iter()
            .map(|(key, value)| format!("{key}={value}"))
            .collect();
        words.push("cargo".to_owned());
        words.extend(self.args.iter().map(|arg| {
            if arg.len() > 100 {
                format!("'<a filter of {} characters>'", arg.len())
            } else if arg.contains([' ', '*']) {
                format!("'{arg}'")
            } else {
                arg.clone()
            }
        }));
        words.join(" ")
    }

    /// The step's command without its environment, for the summary.
    pub(crate) fn short(&self) -> String {
        Step {
            env: Vec::new(),
            ..self.clone()
        }
        .describe()
    }
}

/// The environment shared by all steps, and the resources behind it.
///
/// Dropping it stops the virtual X server and removes the temporary runtime
/// directory, so both are cleaned up on success, on failure and on early return.
pub(crate) struct Session {
    /// Variables set on every step.
    pub(crate) env: Vec<(String, OsString)>,
    /// The runtime directory created for `XDG_RUNTIME_DIR`, if one was.
    pub(crate) runtime_dir: Option<TempDir>,
    /// The virtual X server, once started.
    pub(crate) xvfb: Option<Xvfb>,
    /// Whether starting Xvfb was already attempted.
    pub(crate) xvfb_tried: bool,
    /// Tests counted so far from libtest's `test result:` lines.
    pub(crate) tally: Tally,
}

/// Passed and failed test counts, summed over every test binary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Tally {
    pub(crate) passed: u64,
    pub(crate) failed: u64,
}

impl Tally {
    /// Adds the counts of one libtest summary line
    /// (`test result: ok. 9 passed; 0 failed; 0 ignored; ...`); other lines are ignored.
    /// (nextest's counts come from its JUnit report: `plan::junit_counts`.)
    pub(crate) fn add_line(&mut self, line: &str) {
        let line = line.trim_start();
        let Some(rest) = line.strip_prefix("test result: ") else {
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
    pub(crate) fn new() -> Result<Session, Failure> {
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
    pub(crate) fn display(&mut self) -> Option<String> {
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

    /// The variables `step` runs with: the session's, the step's, and `DISPLAY` when it
    /// needs one.
    pub(crate) fn step_env(&mut self, step: &Step) -> Vec<(String, OsString)> {
        let mut env = self.env.clone();
        env.extend((step.env.iter()).map(|(k, v)| (k.clone(), OsString::from(v))));
        if step.needs_display
            && let Some(display) = self.display()
        {
            env.push(("DISPLAY".to_owned(), display.into()));
        }
        env
    }

    /// `cargo` with `step`'s arguments and variables, in the workspace.
    fn command(&mut self, step: &Step) -> Command {
        let mut command = Command::new(cargo_program());
        command.args(&step.args).current_dir(workspace_root());
        command.envs(self.step_env(step));
        // CI's tests never skip: the opt-outs a developer may have exported do not reach them.
        command
            .env_remove("TEXEL_ALLOW_NO_GPU")
            .env_remove("TEXEL_ALLOW_NO_DISPLAY");
        command
    }

    /// Runs `step` and returns its standard output (standard error is shown as it comes).
    pub(crate) fn output(&mut self, step: &Step) -> Result<String, Failure> {
        let out = (self.command(step))
            .stderr(std::process::Stdio::inherit())
            .output()
            .map_err(|error| Failure::new(format!("could not start cargo: {error}")))?;
        if !out.status.success() {
            return Err(Failure::new(format!(
                "`{}` failed ({})",
                step.describe(),
                out.status
            )));
        }
        String::from_utf8(out.stdout)
            .map_err(|e| Failure::new(format!("`{}` wrote no text: {e}", step.describe())))
    }

    /// Runs `step` with inherited stdio; returns its exit code on failure.
    pub(crate) fn run(&mut self, step: &Step) -> Result<(), Failure> {
        let mut command = self.command(step);
        let status = if step
            .args
            .first()
            .is_some_and(|a| a == "test" || a == "nextest")
        {
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
    pub(crate) fn run_counting(
        &mut self,
        mut command: Command,
    ) -> io::Result<std::process::ExitStatus> {
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
pub(crate) struct TempDir {
    /// The directory.
    pub(crate) path: PathBuf,
}

impl TempDir {
    /// Creates a fresh directory, private to the user (mode 0700), under the
    /// system temporary directory.
    pub(crate) fn new(prefix: &str) -> io::Result<TempDir> {
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
pub(crate) struct Xvfb {
    /// The server process.
    pub(crate) child: Child,
    /// The display name, e.g. `:99`.
    pub(crate) display: String,
    /// The display number.
    pub(crate) number: u32,
}

impl Xvfb {
    /// Starts Xvfb on the first free display from `:99` and waits until it
    /// accepts connections.
    pub(crate) fn start() -> Result<Xvfb, String> {
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
pub(crate) fn display_is_free(number: u32) -> bool {
    match fs::read_to_string(format!("/tmp/.X{number}-lock")) {
        Err(_) => true,
        Ok(contents) => match contents.trim().parse::<u32>() {
            Ok(pid) => !Path::new(&format!("/proc/{pid}")).exists(),
            Err(_) => false,
        },
    }
}
