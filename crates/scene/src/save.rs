//! Atomic file writes: a save either replaces the whole file or leaves the old one alone.
//!
//! Saving over a symbolic link writes the file it points to (the link stays a link, as an
//! editor's "save" should). A save interrupted by a crash leaves a hidden temporary file
//! (`.name.tmp-<pid>-<n>`) that nothing reads; the next save of the same file removes those
//! whose process is gone.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes `bytes` to `path` atomically; see [`write_atomic_with`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |f| f.write_all(bytes))
}

/// Writes a file atomically: `write` fills a temporary file beside `path`, which is flushed
/// to disk and then renamed over `path`. If anything fails, the temporary file is removed
/// and `path` keeps its old contents.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut File) -> io::Result<()>,
) -> io::Result<()> {
    let path = &link_target(path)?;
    let tmp = temp_path(path)?;
    let result = (|| {
        let mut file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        write(&mut file)?;
        file.flush()?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, path)
    })();
    match result {
        Ok(()) => {
            sync_parent(path);
            remove_stale_temps(path);
            Ok(())
        }
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Most symbolic links followed from a save path (as the kernel's limit).
const MAX_LINKS: usize = 40;

/// The file a save of `path` writes: `path` itself, or the file its chain of symbolic links
/// ends at (which need not exist yet).
fn link_target(path: &Path) -> io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "{}: more than {MAX_LINKS} symbolic links (a loop?)",
            path.display()
        ),
    ))
}

/// Removes the temporary files earlier saves of `path` left behind when their process died
/// (best effort). A temporary file of a live process, or of this one, is in use and kept;
/// without `/proc` to tell, only those a day old go.
fn remove_stale_temps(path: &Path) {
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let proc = Path::new("/proc/self").exists();
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let Some(pid) = file_name
            .strip_prefix(&prefix)
            .and_then(|rest| rest.split('-').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let stale = if pid == std::process::id() {
            false
        } else if proc {
            !Path::new("/proc").join(pid.to_string()).exists()
        } else {
            entry
                .metadata()
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| t.elapsed().ok())
                .is_some_and(|age| age.as_secs() > 24 * 3600)
        };
        if stale {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// A unique hidden name beside `path`: `.name.tmp-<pid>-<n>`.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "save path has no file name"))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp_name = format!(".{}.tmp-{}-{n}", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp_name))
}

/// Makes the rename itself durable where the platform allows it (best effort).
fn sync_parent(path: &Path) {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && let Ok(d) = File::open(dir)
    {
        let _ = d.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leftovers(dir: &Path) -> Vec<String> {
        fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains(".tmp-"))
            .collect()
    }

    #[test]
    fn replaces_the_whole_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("level.ron");
        fs::write(&p, "old contents that are longer").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "new");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn failed_write_leaves_old_file_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("level.ron");
        fs::write(&p, "precious").unwrap();
        let err = write_atomic_with(&p, |f| {
            f.write_all(b"half a lev")?;
            Err(io::Error::other("disk full"))
        })
        .unwrap_err();
        assert_eq!(err.to_string(), "disk full");
        assert_eq!(fs::read_to_string(&p).unwrap(), "precious");
        assert!(leftovers(dir.path()).is_empty(), "temp file left behind");
    }

    #[test]
    fn saving_over_a_symbolic_link_writes_through_it() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.ron");
        let link = dir.path().join("link.ron");
        fs::write(&real, "old").unwrap();
        std::os::unix::fs::symlink("real.ron", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read_to_string(&real).unwrap(), "new");
        // A dangling link creates its target; a loop is an error naming the path.
        let dangling = dir.path().join("dangling.ron");
        std::os::unix::fs::symlink("later.ron", &dangling).unwrap();
        write_atomic(&dangling, b"x").unwrap();
        assert_eq!(
            fs::read_to_string(dir.path().join("later.ron")).unwrap(),
            "x"
        );
        let (a, b) = (dir.path().join("a.ron"), dir.path().join("b.ron"));
        std::os::unix::fs::symlink("b.ron", &a).unwrap();
        std::os::unix::fs::symlink("a.ron", &b).unwrap();
        let e = write_atomic(&a, b"x").unwrap_err();
        assert!(e.to_string().contains("a.ron"), "{e}");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_crashed_saves_temporary_file_is_removed_by_the_next_save() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("level.ron");
        // A process id no process has (above the kernel's pid_max), and one of a live
        // process (this one's parent) whose save may still be running.
        let dead = dir.path().join(".level.ron.tmp-4294967-0");
        let live = dir.path().join(format!(
            ".level.ron.tmp-{}-0",
            std::os::unix::process::parent_id()
        ));
        let other = dir.path().join(".other.ron.tmp-4294967-0");
        for f in [&dead, &live, &other] {
            fs::write(f, "half a lev").unwrap();
        }
        write_atomic(&p, b"whole").unwrap();
        assert!(!dead.exists(), "the dead process's temporary file is gone");
        assert!(live.exists() && other.exists());
    }

    #[test]
    fn missing_directory_is_an_error_and_creates_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no_such_dir").join("level.ron");
        assert!(write_atomic(&p, b"x").is_err());
        assert!(!p.exists());
    }
}
