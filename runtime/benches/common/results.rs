//! Where a bench's results table goes: `docs/results/benches/NAME.md`, stamped with the
//! command, the adapter, the date, the commit, the machine and its load, so the docs include
//! it whole (`<!-- texel-eval include=../results/benches/NAME.md -->`, rewritten by
//! `texel-eval tables`) and no number in them is typed. Only a measuring run writes it
//! (`cargo bench`, never `cargo test --benches`).

use std::path::PathBuf;
use std::time::Duration;

use texel_runtime::stamp::Stamp;

/// Writes `table` (Markdown) for the bench `bench` measured on `adapter`; atomically (a
/// temporary file, then a rename), so a bench stopped halfway leaves the last table whole.
pub fn write(bench: &str, adapter: &str, table: &str) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/results/benches");
    let path = dir.join(format!("{bench}.md"));
    // A bench built with the dev profile (dependencies optimised, the workspace not) says so.
    let profile = if cfg!(debug_assertions) {
        " --profile dev"
    } else {
        ""
    };
    let text = format!(
        "{}\n\n<sub>From `cargo bench{profile} -p texel_runtime --bench {bench}`; {adapter}; \
         {}.</sub>\n",
        table.trim_end(),
        Stamp::now().line()
    );
    let tmp = dir.join(format!(".{bench}.md.tmp"));
    let written = std::fs::create_dir_all(&dir)
        .and_then(|()| std::fs::write(&tmp, &text))
        .and_then(|()| std::fs::rename(&tmp, &path));
    match written {
        Ok(()) => eprintln!("results table written to {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
}

/// Each sample's time per iteration, kept in call order: criterion calls a routine for its
/// warm-up first and then once per sample, so the last `n` are the measured samples.
#[derive(Default)]
pub struct Samples(Vec<Duration>);

impl Samples {
    /// Records one call of `iters` iterations that took `total`.
    pub fn push(&mut self, total: Duration, iters: u64) {
        self.0.push(total / iters.max(1) as u32);
    }

    /// The median of the last `n` samples, in milliseconds (NaN with none).
    pub fn median_ms(&self, n: usize) -> f64 {
        let mut last: Vec<f64> = (self.0.iter().rev().take(n))
            .map(|d| d.as_secs_f64() * 1e3)
            .collect();
        last.sort_by(f64::total_cmp);
        match last.len() {
            0 => f64::NAN,
            k if k % 2 == 1 => last[k / 2],
            k => 0.5 * (last[k / 2 - 1] + last[k / 2]),
        }
    }
}
