//! Reading untrusted files with bounds: every loader (levels, glTF files and their buffers,
//! camera paths, evaluation reports) reads through [`read_bounded`], so a FIFO, a device
//! (`/dev/zero`), a directory or a huge (or sparse) file is an error instead of a hang or an
//! allocation failure.
//!
//! * Only regular files are read. The type is checked from the path's metadata *before* the
//!   file is opened (opening a FIFO for reading would block until a writer comes), and again
//!   on the opened handle.
//! * Each [`FileKind`] has a size cap, checked against the metadata first and enforced while
//!   reading (at most cap + 1 bytes are ever read), so a file that grows, or reports a size
//!   of 0 like those in `/proc`, is still bounded.
//! * A cap can be raised (or lowered) with the kind's environment variable, e.g.
//!   `TEXEL_MAX_LEVEL_BYTES=200000000`; see [`FileKind::env_var`].

use std::io::Read;
use std::path::{Path, PathBuf};

/// What a file is, which decides its size cap and how errors name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A level (`.ron`).
    Level,
    /// A glTF mesh file (`.gltf` or `.glb`).
    Mesh,
    /// An external glTF buffer (`.bin`) a mesh file refers to.
    MeshBuffer,
    /// A camera path (`.ron`).
    CameraPath,
    /// An evaluation report (`report.json`).
    Report,
    /// A texture image (`.png` or `.jpg`).
    Texture,
    /// A palette (`.gpl`, `.hex` or `.pal`).
    Palette,
}

const MIB: u64 = 1 << 20;

impl FileKind {
    /// Every kind, for documentation and tests.
    pub const ALL: [FileKind; 7] = [
        FileKind::Level,
        FileKind::Mesh,
        FileKind::MeshBuffer,
        FileKind::CameraPath,
        FileKind::Report,
        FileKind::Texture,
        FileKind::Palette,
    ];

    /// What messages call the file.
    pub fn label(self) -> &'static str {
        match self {
            FileKind::Level => "level",
            FileKind::Mesh => "glTF file",
            FileKind::MeshBuffer => "glTF buffer",
            FileKind::CameraPath => "camera path",
            FileKind::Report => "report",
            FileKind::Texture => "texture",
            FileKind::Palette => "palette",
        }
    }

    /// The built-in cap in bytes: levels 64 MiB (a 10,000-entity level is about 3 MiB),
    /// glTF files and buffers 512 MiB each, camera paths 16 MiB, reports 64 MiB, textures
    /// 64 MiB (a 2048² RGBA PNG is at most 16 MiB), palettes 1 MiB (256 colours take a few
    /// KiB).
    pub fn default_cap(self) -> u64 {
        match self {
            FileKind::Level => 64 * MIB,
            FileKind::Mesh | FileKind::MeshBuffer => 512 * MIB,
            FileKind::CameraPath => 16 * MIB,
            FileKind::Report | FileKind::Texture => 64 * MIB,
            FileKind::Palette => MIB,
        }
    }

    /// The environment variable overriding the cap (a number of bytes).
    pub fn env_var(self) -> &'static str {
        match self {
            FileKind::Level => "TEXEL_MAX_LEVEL_BYTES",
            FileKind::Mesh => "TEXEL_MAX_MESH_BYTES",
            FileKind::MeshBuffer => "TEXEL_MAX_MESH_BUFFER_BYTES",
            FileKind::CameraPath => "TEXEL_MAX_PATH_BYTES",
            FileKind::Report => "TEXEL_MAX_REPORT_BYTES",
            FileKind::Texture => "TEXEL_MAX_TEXTURE_BYTES",
            FileKind::Palette => "TEXEL_MAX_PALETTE_BYTES",
        }
    }

    /// The cap in effect: the environment variable's value if it is set to a positive
    /// number of bytes, else [`FileKind::default_cap`].
    pub fn cap(self) -> u64 {
        env_u64(self.env_var()).unwrap_or_else(|| self.default_cap())
    }
}

/// A positive integer from the environment variable `name`, if it holds one.
pub fn env_u64(name: &str) -> Option<u64> {
    std::env::var(name)
        .ok()
        .and_then(|v| v.trim().replace('_', "").parse::<u64>().ok())
        .filter(|&v| v > 0)
}

/// Why a file was not read. Every message starts with the file's path.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadError {
    /// The path is not a regular file (a directory, FIFO, device or socket).
    #[error("{}: cannot read {what} as a {kind}: only regular files are read", path.display())]
    NotRegular {
        /// The file.
        path: PathBuf,
        /// What the file is ("a directory", "a FIFO", "a character device", ...).
        what: &'static str,
        /// What it was read as.
        kind: &'static str,
    },
    /// The file is larger than the cap for its kind.
    #[error(
        "{}: {kind} is too large: {size} bytes, the limit is {cap} (set {env} to raise it)",
        path.display()
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// What it was read as.
        kind: &'static str,
        /// Its size (from metadata, or the bytes read before stopping: cap + 1).
        size: u64,
        /// The cap.
        cap: u64,
        /// The environment variable that raises the cap.
        env: &'static str,
    },
    /// The file could not be inspected, opened or read.
    #[error("{}: cannot read {kind}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What it was read as.
        kind: &'static str,
        /// Why.
        source: std::io::Error,
    },
}

impl ReadError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::NotRegular { path, .. } | Self::TooLarge { path, .. } | Self::Io { path, .. } => {
                path
            }
        }
    }
}

/// Reads `path` whole as a `kind` with the cap in effect ([`FileKind::cap`]).
pub fn read_bounded(path: &Path, kind: FileKind) -> Result<Vec<u8>, ReadError> {
    read_bounded_with_cap(path, kind, kind.cap())
}

/// Reads `path` whole as UTF-8 text; invalid UTF-8 is an [`ReadError::Io`] of kind
/// `InvalidData`.
pub fn read_bounded_string(path: &Path, kind: FileKind) -> Result<String, ReadError> {
    let bytes = read_bounded(path, kind)?;
    String::from_utf8(bytes).map_err(|e| ReadError::Io {
        path: path.to_owned(),
        kind: kind.label(),
        source: std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not a text file (invalid UTF-8 after byte {})",
                e.utf8_error().valid_up_to()
            ),
        ),
    })
}

/// Reads `path` whole as a `kind`, refusing anything but a regular file of at most `cap`
/// bytes (checked before opening and again while reading).
pub fn read_bounded_with_cap(path: &Path, kind: FileKind, cap: u64) -> Result<Vec<u8>, ReadError> {
    let io = |source| ReadError::Io {
        path: path.to_owned(),
        kind: kind.label(),
        source,
    };
    let too_large = |size| ReadError::TooLarge {
        path: path.to_owned(),
        kind: kind.label(),
        size,
        cap,
        env: kind.env_var(),
    };
    let check = |meta: &std::fs::Metadata| {
        if let Some(what) = not_regular(&meta.file_type()) {
            return Err(ReadError::NotRegular {
                path: path.to_owned(),
                what,
                kind: kind.label(),
            });
        }
        if meta.len() > cap {
            return Err(too_large(meta.len()));
        }
        Ok(())
    };
    // Before opening: a FIFO must not be opened at all (the open would block).
    check(&std::fs::metadata(path).map_err(io)?)?;
    let file = open_nonblocking(path).map_err(io)?;
    // Again on the handle, in case the path was replaced in between.
    let meta = file.metadata().map_err(io)?;
    check(&meta)?;
    let mut bytes = Vec::with_capacity(meta.len().min(cap) as usize);
    file.take(cap.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > cap {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Opens for reading; on Linux with `O_NONBLOCK`, so that even a FIFO swapped in after the
/// metadata check cannot block the open (it is then refused by the second check).
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(all(
        target_os = "linux",
        any(
            target_arch = "x86_64",
            target_arch = "x86",
            target_arch = "aarch64",
            target_arch = "arm",
            target_arch = "riscv64"
        )
    ))]
    {
        use std::os::unix::fs::OpenOptionsExt;
        const O_NONBLOCK: i32 = 0o4000;
        options.custom_flags(O_NONBLOCK);
    }
    options.open(path)
}

/// What a non-regular file is, for messages; `None` for a regular file.
fn not_regular(t: &std::fs::FileType) -> Option<&'static str> {
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("a special file")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_small_regular_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.ron");
        std::fs::write(&p, "hello").unwrap();
        assert_eq!(read_bounded(&p, FileKind::Level).unwrap(), b"hello");
        assert_eq!(read_bounded_string(&p, FileKind::Level).unwrap(), "hello");
    }

    #[test]
    fn size_cap_from_metadata_and_while_reading() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("big.ron");
        std::fs::write(&p, [b'x'; 100]).unwrap();
        let e = read_bounded_with_cap(&p, FileKind::Level, 99).unwrap_err();
        assert!(matches!(e, ReadError::TooLarge { size: 100, .. }), "{e}");
        assert!(e.to_string().contains("TEXEL_MAX_LEVEL_BYTES"), "{e}");
        assert_eq!(
            read_bounded_with_cap(&p, FileKind::Level, 100)
                .unwrap()
                .len(),
            100
        );
        // /proc files report a length of 0: only the read itself can stop them.
        let maps = Path::new("/proc/self/maps");
        if maps.exists() {
            let e = read_bounded_with_cap(maps, FileKind::Level, 16).unwrap_err();
            assert!(matches!(e, ReadError::TooLarge { size: 17, .. }), "{e}");
        }
    }

    #[test]
    fn only_regular_files() {
        let dir = tempfile::tempdir().unwrap();
        let e = read_bounded(dir.path(), FileKind::Mesh).unwrap_err();
        assert!(e.to_string().contains("a directory"), "{e}");
        #[cfg(unix)]
        {
            let e = read_bounded(Path::new("/dev/zero"), FileKind::Level).unwrap_err();
            assert!(e.to_string().contains("a character device"), "{e}");
        }
        let e = read_bounded(&dir.path().join("missing"), FileKind::CameraPath).unwrap_err();
        assert!(matches!(e, ReadError::Io { .. }), "{e}");
        assert!(e.path().ends_with("missing"));
    }

    #[test]
    fn every_kind_has_a_cap_and_a_variable() {
        for k in FileKind::ALL {
            assert!(k.default_cap() >= MIB, "{k:?}");
            assert!(k.env_var().starts_with("TEXEL_MAX_"), "{k:?}");
        }
    }
}
