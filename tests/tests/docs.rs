//! The docs are checked like code, so what they show works as written:
//!
//! - every ```` ```ron ```` block in `README.md` and `docs/**/*.md` is a level the loader
//!   accepts (parsed by `Level::from_ron_str`, then its files loaded by `load_assets` as if
//!   it lay in `assets/levels/`, as the bundled levels do) or a camera path
//!   (`CameraPath::from_ron_str`); a failure names the file and the block's line;
//! - every ```` ```sh ```` line there is one command (after `NAME=value` settings) starting
//!   with `texel-run`, `texel-eval` or `cargo`, and names real subcommands and flags.
//!   `texel-run`'s main is one call of the public `texel_runtime::cli::Cli`, so the line is
//!   parsed by that very parser (the whole line must parse, and `SUBCOMMAND --help` must ask
//!   for help). `texel-eval`'s parser is private to its binary, and cargo hands a test only
//!   its own package's binaries (`CARGO_BIN_EXE_*`), so the binary built beside this test
//!   (`target/<profile>/texel-eval`) is run with `SUBCOMMAND --help`, which must succeed and
//!   list every `--flag` of the line. When that binary is missing or older than its command
//!   line's source, the test fails and says how to build it rather than pass unchecked
//!   (`cargo xtask test` builds every workspace binary before it runs a test). A `cargo run
//!   … --bin texel-run -- ARGS` line is checked the same way; `-p`, `--bin`, `--bench`,
//!   `--test` and `install --path` must name what exists;
//! - `README.md` is at most 300 lines and `ARCHITECTURE.md` at most 200;
//! - every relative link in `README.md`, `ARCHITECTURE.md` and `docs/guide/*.md` points at
//!   a file inside the repository that exists, and a `#fragment` at one of its headings;
//! - `ARCHITECTURE.md` names every workspace crate and every render pass.
//!
//! No GPU device is opened: `--help` draws nothing.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Parser as _;
use texel_runtime::cli::Cli;
use texel_runtime::path::CameraPath;
use texel_scene::Level;
use texel_scene::assets::load_assets;
use texel_tests::repo_root;

/// A fenced code block of a Markdown file.
struct Block {
    /// The info string's first word (`ron`, `sh`, …).
    lang: String,
    /// 1-based line of the opening fence.
    line: usize,
    /// The lines between the fences, with their 1-based line numbers.
    lines: Vec<(usize, String)>,
}

impl Block {
    fn text(&self) -> String {
        let mut text = String::new();
        for (_, l) in &self.lines {
            text.push_str(l);
            text.push('\n');
        }
        text
    }
}

/// The number of backticks a fence line opens with (3 or more), or 0.
fn fence_ticks(line: &str) -> usize {
    let n = line.trim_start().chars().take_while(|&c| c == '`').count();
    if n >= 3 { n } else { 0 }
}

/// The fenced blocks of `text`, and the lines outside them (1-based numbers).
fn split_markdown(text: &str) -> (Vec<Block>, Vec<(usize, &str)>) {
    let mut blocks = Vec::new();
    let mut prose = Vec::new();
    let mut open: Option<(usize, Block)> = None;
    for (i, line) in text.lines().enumerate() {
        let number = i + 1;
        let ticks = fence_ticks(line);
        match open.take() {
            Some((n, block)) if ticks >= n && line.trim().chars().all(|c| c == '`') => {
                blocks.push(block);
            }
            Some((n, mut block)) => {
                block.lines.push((number, line.to_owned()));
                open = Some((n, block));
            }
            None if ticks > 0 && !line.trim()[ticks..].contains('`') => {
                let info = line.trim()[ticks..].trim();
                let lang = info.split_whitespace().next().unwrap_or("").to_owned();
                let block = Block {
                    lang,
                    line: number,
                    lines: Vec::new(),
                };
                open = Some((ticks, block));
            }
            None => prose.push((number, line)),
        }
    }
    if let Some((_, block)) = open {
        panic!("a code block opened on line {} is never closed", block.line);
    }
    (blocks, prose)
}

fn read(rel: &str) -> String {
    let path = repo_root().join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `README.md` and every Markdown file under `docs/`, as repository-relative paths.
fn documents() -> Vec<String> {
    fn walk(dir: &Path, root: &Path, out: &mut Vec<String>) {
        let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                walk(&path, root, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                let rel = path.strip_prefix(root).expect("under the root");
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let root = repo_root();
    let mut out = vec!["README.md".to_owned()];
    walk(&root.join("docs"), &root, &mut out);
    out.sort();
    out
}

/// Every fenced block of the documents, with its file.
fn all_blocks() -> Vec<(String, Block)> {
    let mut out = Vec::new();
    for doc in documents() {
        let (blocks, _) = split_markdown(&read(&doc));
        out.extend(blocks.into_iter().map(|b| (doc.clone(), b)));
    }
    out
}

/// Why a RON block is neither a level the loader takes (with its files) nor a camera path.
fn check_ron(doc: &str, block: &Block) -> Result<(), String> {
    let text = block.text();
    let name = format!("{doc}:{}", block.line);
    let level_error = match Level::from_ron_str(&text, Path::new(&name)) {
        Ok(level) => {
            // Paths in a level are relative to its file: read them as a bundled level's.
            let at = repo_root().join("assets/levels/docs_example.ron");
            return load_assets(&level, &at, Some(&text))
                .map(drop)
                .map_err(|e| format!("{name}: a level whose files do not load: {e}"));
        }
        Err(e) => e,
    };
    CameraPath::from_ron_str(&text, &name)
        .map(drop)
        .map_err(|path_error| {
            format!(
                "{name}: neither a level ({level_error}) nor a camera path ({path_error}); \
             line numbers inside count from the block"
            )
        })
}

#[test]
fn every_ron_example_is_a_level_or_a_camera_path() {
    let mut checked = 0;
    let mut failures = Vec::new();
    for (doc, block) in all_blocks().iter().filter(|(_, b)| b.lang == "ron") {
        checked += 1;
        if let Err(e) = check_ron(doc, block) {
            failures.push(e);
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
    assert!(checked >= 5, "only {checked} RON blocks found");
}

/// Splits a command line into words as a shell would for plain words and quotes.
fn shell_words(line: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut quote: Option<char> = None;
    for c in line.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                in_word = true;
            }
            (None, c) if c.is_whitespace() => {
                if in_word {
                    words.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            (None, c) => {
                word.push(c);
                in_word = true;
            }
        }
    }
    if quote.is_some() {
        return Err("an unclosed quote".to_owned());
    }
    if in_word {
        words.push(word);
    }
    Ok(words)
}

/// The line without a trailing ` # comment` (outside quotes).
fn strip_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '\'' || c == '"' => quote = Some(c),
            None if c == '#' && previous.is_whitespace() => return &line[..i],
            None => {}
        }
        previous = c;
    }
    line
}

/// A workspace package: its name, folder, and the text of its `Cargo.toml`.
struct Package {
    dir: PathBuf,
    manifest: String,
}

/// The packages of the workspace's `members` (and `fuzz`, kept outside it), by name.
fn packages() -> BTreeMap<String, Package> {
    let root = repo_root();
    let cargo = read("Cargo.toml");
    let start = cargo
        .find("members = [")
        .expect("a members list in Cargo.toml");
    let end = start + cargo[start..].find(']').expect("the members list ends");
    let mut dirs: Vec<String> = cargo[start..end]
        .split('"')
        .skip(1)
        .step_by(2)
        .map(str::to_owned)
        .collect();
    dirs.push("fuzz".to_owned());
    let mut out = BTreeMap::new();
    for dir in dirs {
        let manifest = read(&format!("{dir}/Cargo.toml"));
        let name = manifest
            .lines()
            .find_map(|l| l.trim().strip_prefix("name = \""))
            .and_then(|rest| rest.split('"').next())
            .unwrap_or_else(|| panic!("{dir}/Cargo.toml names no package"))
            .to_owned();
        out.insert(
            name,
            Package {
                dir: root.join(&dir),
                manifest,
            },
        );
    }
    out
}

/// The binary `name` built beside this test (`target/<profile>/`), if it is there and newer
/// than `sources` (repository-relative), which define its command line.
fn built_binary(name: &str, package: &str, sources: &[&str]) -> Result<PathBuf, String> {
    let build = format!(
        "build it first: `cargo build -p {package} --bin {name}` (`cargo xtask test` builds it \
         with the workspace's tests)"
    );
    let exe = std::env::current_exe().map_err(|e| format!("this test's path: {e}"))?;
    // target/<profile>/deps/docs-<hash>
    let dir = exe
        .parent()
        .and_then(Path::parent)
        .ok_or("this test does not lie in target/<profile>/deps/")?;
    let bin = dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    let built = std::fs::metadata(&bin)
        .and_then(|m| m.modified())
        .map_err(|_| format!("{} is not built: {build}", bin.display()))?;
    for source in sources {
        let path = repo_root().join(source);
        let changed = std::fs::metadata(&path)
            .and_then(|m| m.modified())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        if changed > built {
            return Err(format!("{} is older than {source}: {build}", bin.display()));
        }
    }
    Ok(bin)
}

/// Checks commands against the programs' parsers, remembering each `--help` it ran.
#[derive(Default)]
struct Commands {
    eval_help: BTreeMap<String, Result<String, String>>,
    packages: Option<BTreeMap<String, Package>>,
}

impl Commands {
    fn packages(&mut self) -> &BTreeMap<String, Package> {
        self.packages.get_or_insert_with(packages)
    }

    /// One command line of a ```sh block.
    fn check_line(&mut self, line: &str) -> Result<(), String> {
        if line.ends_with('\\') {
            return Err("one command per line: no `\\` continuation".to_owned());
        }
        let mut words = shell_words(strip_comment(line))?;
        let settings = words
            .iter()
            .take_while(|w| {
                w.split_once('=').is_some_and(|(k, _)| {
                    !k.is_empty()
                        && k.chars()
                            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
                })
            })
            .count();
        words.drain(..settings);
        if let Some(op) = words
            .iter()
            .find(|w| ["&&", "||", "|", ";", ">", "<"].contains(&w.as_str()))
        {
            return Err(format!("one command per line: `{op}` joins two"));
        }
        match words.first().map(String::as_str) {
            Some("texel-run") => check_texel_run(&words[1..]),
            Some("texel-eval") => self.check_texel_eval(&words[1..]),
            Some("cargo") => self.check_cargo(&words[1..]),
            _ => Err("a command starts with `texel-run`, `texel-eval` or `cargo`".to_owned()),
        }
    }

    fn check_texel_eval(&mut self, args: &[String]) -> Result<(), String> {
        let sub = subcommand(args)?;
        let help = self
            .eval_help
            .entry(sub.to_owned())
            .or_insert_with(|| eval_help(sub))
            .clone()?;
        for flag in args.iter().filter(|a| a.starts_with("--")) {
            let flag = flag.split('=').next().unwrap_or(flag);
            if !lists_flag(&help, flag) {
                return Err(format!("`texel-eval {sub} --help` does not list `{flag}`"));
            }
        }
        Ok(())
    }

    fn check_cargo(&mut self, args: &[String]) -> Result<(), String> {
        let (cargo_args, program_args) = match args.iter().position(|a| a == "--") {
            Some(i) => (&args[..i], &args[i + 1..]),
            None => (args, &[][..]),
        };
        let value = |flags: &[&str]| {
            (cargo_args.windows(2))
                .find(|w| flags.contains(&w[0].as_str()))
                .map(|w| w[1].clone())
        };
        match cargo_args.first().map(String::as_str) {
            Some("xtask") => {
                let sub = cargo_args.get(1).map_or("", String::as_str);
                if !["run", "test", "setup"].contains(&sub) {
                    return Err(format!(
                        "`cargo xtask {sub}`: xtask has run, test and setup"
                    ));
                }
            }
            Some("install") => {
                if let Some(dir) = value(&["--path"])
                    && !repo_root().join(&dir).join("Cargo.toml").is_file()
                {
                    return Err(format!("`cargo install --path {dir}`: no package there"));
                }
            }
            _ => {}
        }
        let package = value(&["-p", "--package"]);
        if let Some(name) = &package {
            let Some(p) = self.packages().get(name) else {
                return Err(format!("`-p {name}`: no such workspace package"));
            };
            // A target is `kind/target.rs` or, split into modules, `kind/target/main.rs`
            // (the two places Cargo looks).
            let exists = |kind: &str, flag: &str| -> Result<(), String> {
                let found = |target: &str| {
                    let dir = p.dir.join(kind);
                    dir.join(format!("{target}.rs")).is_file()
                        || dir.join(target).join("main.rs").is_file()
                };
                match value(&[flag]) {
                    Some(target) if !found(&target) => Err(format!(
                        "`{flag} {target}`: {name} has no {kind}/{target}.rs or \
                         {kind}/{target}/main.rs"
                    )),
                    _ => Ok(()),
                }
            };
            exists("benches", "--bench")?;
            exists("tests", "--test")?;
            if let Some(bin) = value(&["--bin"])
                && !p.manifest.contains(&format!("name = \"{bin}\""))
            {
                return Err(format!("`--bin {bin}`: {name} has no such binary"));
            }
        }
        if cargo_args.first().is_some_and(|c| c == "run") {
            match value(&["--bin"]).as_deref() {
                Some("texel-run") => return check_texel_run(program_args),
                Some("texel-eval") => return self.check_texel_eval(program_args),
                _ => {}
            }
        }
        Ok(())
    }
}

/// The subcommand: the first argument, not a flag.
fn subcommand(args: &[String]) -> Result<&str, String> {
    match args.first() {
        Some(sub) if !sub.starts_with('-') => Ok(sub.as_str()),
        _ => Err("no subcommand".to_owned()),
    }
}

/// Whether `help` lists `flag` (as a whole word: `--face-res`, not `--face-resolution`).
fn lists_flag(help: &str, flag: &str) -> bool {
    help.match_indices(flag).any(|(i, _)| {
        let next = help[i + flag.len()..].chars().next();
        let before = help[..i].chars().next_back();
        !next.is_some_and(|c| c.is_alphanumeric() || c == '-' || c == '_')
            && !before.is_some_and(|c| c.is_alphanumeric() || c == '-')
    })
}

/// `texel-run ARGS`, through the binary's own parser.
fn check_texel_run(args: &[String]) -> Result<(), String> {
    let sub = subcommand(args)?;
    let line = std::iter::once("texel-run").chain(args.iter().map(String::as_str));
    Cli::try_parse_from(line).map_err(|e| format!("texel-run: {}", e.render()))?;
    match Cli::try_parse_from(["texel-run", sub, "--help"]) {
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelp => Ok(()),
        Err(e) => Err(format!("`texel-run {sub} --help`: {}", e.render())),
        Ok(_) => Err(format!("`texel-run {sub} --help` ran the command")),
    }
}

/// What `texel-eval SUB --help` prints.
fn eval_help(sub: &str) -> Result<String, String> {
    let sources = ["eval/src/cli.rs", "eval/src/main.rs"];
    let bin = built_binary("texel-eval", "texel_eval", &sources)?;
    let out = Command::new(&bin)
        .args([sub, "--help"])
        .env_remove("TEXEL_GPU_TEST_LOG")
        .output()
        .map_err(|e| format!("{}: {e}", bin.display()))?;
    if !out.status.success() {
        return Err(format!(
            "`texel-eval {sub} --help` failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

#[test]
fn every_command_line_names_real_subcommands_and_flags() {
    let mut commands = Commands::default();
    let mut checked = 0;
    let mut failures = Vec::new();
    for (doc, block) in all_blocks().iter().filter(|(_, b)| b.lang == "sh") {
        for (number, line) in &block.lines {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            checked += 1;
            if let Err(e) = commands.check_line(line) {
                failures.push(format!("{doc}:{number}: {e}\n    {line}"));
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
    assert!(checked >= 20, "only {checked} command lines found");
}

#[test]
fn the_readme_and_the_architecture_stay_short() {
    for (doc, most) in [("README.md", 300), ("ARCHITECTURE.md", 200)] {
        let lines = read(doc).lines().count();
        assert!(lines <= most, "{doc} has {lines} lines, at most {most}");
    }
}

/// The text of `line` without its inline code spans.
fn without_code_spans(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(start) = rest.find('`') {
        out.push_str(&rest[..start]);
        let ticks = rest[start..].chars().take_while(|&c| c == '`').count();
        let after = &rest[start + ticks..];
        let fence = "`".repeat(ticks);
        match after.find(&fence) {
            Some(end) => rest = &after[end + ticks..],
            None => {
                rest = after;
                break;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The link targets of a line of prose: what follows each `](`, up to its `)`.
fn link_targets(line: &str) -> Vec<String> {
    let text = without_code_spans(line);
    let mut out = Vec::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        let end = rest.find(')').unwrap_or(rest.len());
        let target = rest[..end].split_whitespace().next().unwrap_or("");
        out.push(target.to_owned());
        rest = &rest[end..];
    }
    out
}

/// The anchors GitHub gives a Markdown file's headings.
fn anchors(text: &str) -> BTreeSet<String> {
    let (_, prose) = split_markdown(text);
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let mut out = BTreeSet::new();
    for (_, line) in prose {
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let title = line[hashes..].trim().trim_end_matches('#').trim();
        let slug: String = (title.to_lowercase().chars())
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        let n = seen.entry(slug.clone()).or_insert(0);
        let key = if *n == 0 { slug } else { format!("{slug}-{n}") };
        out.insert(key);
        *n += 1;
    }
    out
}

#[test]
fn every_relative_link_points_at_something_that_exists() {
    let root = repo_root().canonicalize().expect("the repository root");
    let mut docs = vec!["README.md".to_owned(), "ARCHITECTURE.md".to_owned()];
    let guide = root.join("docs/guide");
    for entry in std::fs::read_dir(&guide).expect("docs/guide/") {
        let path = entry.expect("a directory entry").path();
        if path.extension().is_some_and(|e| e == "md") {
            let name = path.file_name().expect("a file name").to_string_lossy();
            docs.push(format!("docs/guide/{name}"));
        }
    }
    let mut checked = 0;
    let mut failures = Vec::new();
    for doc in &docs {
        let text = read(doc);
        let dir = root.join(doc).parent().expect("a folder").to_owned();
        let (_, prose) = split_markdown(&text);
        for (number, line) in prose {
            for target in link_targets(line) {
                if target.is_empty()
                    || ["http://", "https://", "mailto:"]
                        .iter()
                        .any(|s| target.starts_with(s))
                {
                    continue;
                }
                checked += 1;
                let (file, fragment) = target.split_once('#').unwrap_or((target.as_str(), ""));
                let path = if file.is_empty() {
                    root.join(doc)
                } else {
                    dir.join(file)
                };
                let Ok(path) = path.canonicalize() else {
                    failures.push(format!("{doc}:{number}: `{target}`: no such file"));
                    continue;
                };
                if !path.starts_with(&root) {
                    failures.push(format!(
                        "{doc}:{number}: `{target}` lies outside the repository"
                    ));
                    continue;
                }
                if !fragment.is_empty() && path.extension().is_some_and(|e| e == "md") {
                    let text = std::fs::read_to_string(&path).expect("a Markdown file");
                    if !anchors(&text).contains(fragment) {
                        failures.push(format!("{doc}:{number}: `{target}`: no such heading"));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
    assert!(checked >= 30, "only {checked} relative links found");
}

#[test]
fn the_architecture_names_every_crate_and_every_pass() {
    let text = read("ARCHITECTURE.md");
    let mut missing = Vec::new();
    for name in packages().keys() {
        if !text.contains(&format!("| `{name}` |")) {
            missing.push(format!("crate {name}"));
        }
    }
    let passes = repo_root().join("crates/render/src/passes");
    for entry in std::fs::read_dir(&passes).expect("crates/render/src/passes/") {
        let path = entry.expect("a directory entry").path();
        let stem = path.file_stem().expect("a file name").to_string_lossy();
        if path.extension().is_some_and(|e| e == "rs")
            && stem != "mod"
            && !text.contains(&format!("| `{stem}` |"))
        {
            missing.push(format!("pass {stem}"));
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md has no row for: {missing:?}"
    );
}

#[test]
fn markdown_blocks_and_links_are_found() {
    let (blocks, prose) = split_markdown(
        "a [b](c.md#d) `[x](y)`\n```ron\n(frames: 1)\n```\n   ```sh\n   cargo xtask run # c\n   ```\n",
    );
    assert_eq!(blocks.len(), 2);
    assert_eq!((blocks[0].lang.as_str(), blocks[0].line), ("ron", 2));
    assert_eq!(
        blocks[1].lines,
        vec![(6, "   cargo xtask run # c".to_owned())]
    );
    assert_eq!(prose.len(), 1);
    assert_eq!(link_targets(prose[0].1), vec!["c.md#d".to_owned()]);
    assert_eq!(
        shell_words(strip_comment("A=1 cargo bench -- \"jog|hills\" # x")),
        Ok(["A=1", "cargo", "bench", "--", "jog|hills"]
            .map(String::from)
            .to_vec())
    );
    let heads = anchors("# Texel\n## Two commands\n### `texel-run render`\n## Two commands\n");
    for a in [
        "texel",
        "two-commands",
        "texel-run-render",
        "two-commands-1",
    ] {
        assert!(heads.contains(a), "{a}: {heads:?}");
    }
}

/// The results tables are written by `texel-eval tables` from the reports they name, so a
/// number in them always comes from a command: a block that differs from what its report
/// gives (typed by hand, or left behind by a newer report) fails here. The README's
/// stability and speed tables are such blocks.
#[test]
fn results_tables_are_what_their_reports_give() {
    let mut blocks = 0;
    for doc in documents() {
        let text = read(&doc);
        let path = repo_root().join(&doc);
        let fresh = texel_eval::tables::refresh(&text, &path).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            fresh == text,
            "{doc}: a results table differs from its report; run `texel-eval tables {doc}`"
        );
        blocks += text.matches(texel_eval::tables::CLOSE).count();
    }
    let readme = read("README.md");
    for table in ["table=shimmer", "table=speed"] {
        assert!(
            readme.contains(&format!("{}{table} ", texel_eval::tables::OPEN)),
            "README.md has no {table} block"
        );
    }
    assert!(blocks >= 4, "{blocks} results blocks in the docs");
}
