//! Where a measurement comes from: the date (UTC), the commit and the machine a report was
//! written on, so a table in the docs says which code on which hardware made its numbers.

use serde::{Deserialize, Serialize};

/// When, from which commit and on what machine a report was written.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stamp {
    /// UTC date, `YYYY-MM-DD`.
    pub date: String,
    /// `git rev-parse --short HEAD` of the working directory, with ` (modified)` when tracked
    /// files differ from it; `unknown` outside a git checkout.
    pub commit: String,
    /// CPU model and logical core count, e.g. `2 × AMD EPYC 7B13`.
    pub machine: String,
    /// `debug` or `release`: how the measuring binary was built (frame times depend on it).
    #[serde(default)]
    pub build: String,
    /// The machine's one-minute load average when the measurement ended (`/proc/loadavg`;
    /// empty where unknown): above the core count, other work shared the machine and the
    /// times are slower than on a quiet one.
    #[serde(default)]
    pub load: String,
}

impl Stamp {
    /// The stamp of a report written now, in the current directory's checkout.
    pub fn now() -> Stamp {
        let secs = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Stamp {
            date: utc_date(secs),
            commit: commit(),
            machine: machine(),
            build: if cfg!(debug_assertions) {
                "debug"
            } else {
                "release"
            }
            .to_owned(),
            load: load(),
        }
    }

    /// One line for under a table: `2026-12-07, commit 869bffd (debug build), 2 × AMD EPYC
    /// 7B13`; empty when the report has no stamp.
    pub fn line(&self) -> String {
        if self.date.is_empty() {
            return String::new();
        }
        let build = if self.build.is_empty() {
            String::new()
        } else {
            format!(" ({} build)", self.build)
        };
        let load = if self.load.is_empty() {
            String::new()
        } else {
            format!(", load {}", self.load)
        };
        format!(
            "{}, commit {}{build}, {}{load}",
            self.date, self.commit, self.machine
        )
    }
}

/// `YYYY-MM-DD` of a Unix time (the proleptic Gregorian calendar, days counted from
/// 1970-01-01 and split into 400-year eras).
pub fn utc_date(unix_secs: u64) -> String {
    let days = (unix_secs / 86_400) as i64 + 719_468;
    let era = days.div_euclid(146_097);
    let day_of_era = days.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1_460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_index = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_index + 2) / 5 + 1;
    let month = if month_index < 10 {
        month_index + 3
    } else {
        month_index - 9
    };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

fn git(args: &[&str]) -> Option<String> {
    let out = std::process::Command::new("git").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

fn commit() -> String {
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(hash) if !hash.is_empty() => {
            let modified = git(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if modified {
                format!("{hash} (modified)")
            } else {
                hash
            }
        }
        _ => "unknown".to_owned(),
    }
}

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|text| text.split_whitespace().next().map(str::to_owned))
        .unwrap_or_default()
}

fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find_map(|l| l.strip_prefix("model name"))
                .and_then(|rest| rest.split_once(':'))
                .map(|(_, name)| name.split_whitespace().collect::<Vec<_>>().join(" "))
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_owned());
    format!("{cores} × {model}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_the_calendars() {
        assert_eq!(utc_date(0), "1970-01-01");
        assert_eq!(utc_date(951_782_400), "2000-02-29");
        assert_eq!(utc_date(951_868_800), "2000-03-01");
        assert_eq!(utc_date(1_796_601_599), "2026-12-06");
        assert_eq!(utc_date(1_796_601_600), "2026-12-07");
    }

    #[test]
    fn a_stamp_reads_as_one_line() {
        let s = Stamp {
            date: "2026-12-07".into(),
            commit: "abc1234".into(),
            machine: "2 × CPU".into(),
            build: "debug".into(),
            load: String::new(),
        };
        assert_eq!(
            s.line(),
            "2026-12-07, commit abc1234 (debug build), 2 × CPU"
        );
        assert_eq!(Stamp::default().line(), "");
        let busy = Stamp {
            load: "3.10".into(),
            ..s
        };
        assert!(
            busy.line().ends_with("2 × CPU, load 3.10"),
            "{}",
            busy.line()
        );
    }
}
