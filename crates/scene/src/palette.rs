//! Colour palettes: the colours a level's frames are mapped to (`Level::palette`). Three text
//! formats, told apart by the file's extension:
//!
//! - GIMP `.gpl`: a `GIMP Palette` line, optional `Name:` and `Columns:` lines, `#` comments,
//!   then one `R G B [name]` line a colour (decimal 0–255).
//! - `.hex`: one `rrggbb` a line (a leading `#` allowed), as Lospec exports them.
//! - JASC `.pal`: `JASC-PAL`, `0100`, the number of colours, then one `R G B` line each.
//!
//! Files are read bounded ([`FileKind::Palette`]); a palette holds 1 to [`MAX_COLOURS`]
//! colours; every error names the file and the line.

use std::fmt;
use std::path::{Path, PathBuf};

use glam::Vec3;
use texel_geom::colour::linear_from_srgb8;

use crate::read::{FileKind, read_bounded_string};

/// The most colours a palette may hold (what an indexed image can; the frame's mapping
/// searches them all per pixel).
pub const MAX_COLOURS: usize = 256;

/// A palette: sRGB colours in file order, at least one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Palette {
    /// The colours, sRGB bytes.
    pub colours: Vec<[u8; 3]>,
}

impl Palette {
    /// Reads the palette at `path`, its format from its extension.
    pub fn load(path: &Path) -> Result<Palette, PaletteError> {
        let error = |line, message: String| PaletteError {
            path: path.to_owned(),
            line,
            message,
        };
        let format = PaletteFormat::of(path).ok_or_else(|| {
            error(
                None,
                "not a palette file: the name must end in .gpl, .hex or .pal".into(),
            )
        })?;
        let text =
            read_bounded_string(path, FileKind::Palette).map_err(|e| error(None, e.to_string()))?;
        Palette::parse(&text, format).map_err(|(line, message)| error(Some(line), message))
    }

    /// Parses `text` as `format`; an error is its line (1-based) and what is wrong there.
    pub fn parse(text: &str, format: PaletteFormat) -> Result<Palette, (usize, String)> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut colours = Vec::new();
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
        let mut expected = None;
        match format {
            PaletteFormat::Gpl => header(&mut lines, "GIMP Palette", "a GIMP palette")?,
            PaletteFormat::Pal => {
                header(&mut lines, "JASC-PAL", "a JASC palette")?;
                header(&mut lines, "0100", "a JASC palette of version 0100")?;
                expected = Some(pal_count(&mut lines)?);
            }
            PaletteFormat::Hex => {}
        }
        let mut last = 0;
        for (n, line) in lines {
            last = n;
            let colour = match format {
                PaletteFormat::Gpl => gpl_line(line),
                PaletteFormat::Hex => hex_line(line),
                PaletteFormat::Pal => {
                    if colours.len() == expected.unwrap_or(0) && line.is_empty() {
                        continue;
                    }
                    rgb_line(line).map(Some)
                }
            }
            .map_err(|e| (n, e))?;
            if let Some(c) = colour {
                if colours.len() == MAX_COLOURS {
                    return Err((n, format!("more than {MAX_COLOURS} colours")));
                }
                if expected.is_some_and(|e| colours.len() == e) {
                    return Err((
                        n,
                        format!("more colours than the {} the header names", colours.len()),
                    ));
                }
                colours.push(c);
            }
        }
        if let Some(e) = expected
            && colours.len() != e
        {
            return Err((
                last.max(3),
                format!("{} colours where the header names {e}", colours.len()),
            ));
        }
        if colours.is_empty() {
            return Err((last.max(1), "no colours".into()));
        }
        Ok(Palette { colours })
    }

    /// The palette as the text of a `format` file, which [`Palette::parse`] reads back as
    /// the same colours: a `.gpl` with `Name: name`, a `.hex` of `rrggbb` lines, a JASC
    /// `.pal` with its count. Colour names and comments a file had are not kept.
    pub fn to_text(&self, format: PaletteFormat, name: &str) -> String {
        let mut out = String::new();
        match format {
            PaletteFormat::Gpl => {
                // A name on one line, without what would end it.
                let name: String = name.chars().filter(|c| !c.is_control()).collect();
                out.push_str(&format!("GIMP Palette\nName: {name}\nColumns: 8\n#\n"));
                for [r, g, b] in &self.colours {
                    out.push_str(&format!("{r:3} {g:3} {b:3}\n"));
                }
            }
            PaletteFormat::Hex => {
                for [r, g, b] in &self.colours {
                    out.push_str(&format!("{r:02x}{g:02x}{b:02x}\n"));
                }
            }
            PaletteFormat::Pal => {
                out.push_str(&format!("JASC-PAL\r\n0100\r\n{}\r\n", self.colours.len()));
                for [r, g, b] in &self.colours {
                    out.push_str(&format!("{r} {g} {b}\r\n"));
                }
            }
        }
        out
    }

    /// Writes the palette to `path` atomically (a temporary file beside it, renamed over
    /// it), in the format its extension names; a `.gpl` is named after the file.
    pub fn save(&self, path: &Path) -> Result<(), PaletteError> {
        let error = |message: String| PaletteError {
            path: path.to_owned(),
            line: None,
            message,
        };
        let format = PaletteFormat::of(path).ok_or_else(|| {
            error("not a palette file: the name must end in .gpl, .hex or .pal".into())
        })?;
        let name = path.file_stem().map(|s| s.to_string_lossy().into_owned());
        let text = self.to_text(format, name.as_deref().unwrap_or("palette"));
        crate::save::write_atomic(path, text.as_bytes()).map_err(|e| error(e.to_string()))
    }

    /// The colours as linear RGB (0–1).
    pub fn linear(&self) -> Vec<Vec3> {
        (self.colours.iter())
            .map(|c| Vec3::from_array(c.map(linear_from_srgb8)))
            .collect()
    }
}

/// The three file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PaletteFormat {
    /// GIMP `.gpl`.
    Gpl,
    /// One `rrggbb` a line.
    Hex,
    /// JASC `.pal`.
    Pal,
}

impl PaletteFormat {
    /// The format a file's extension names (case-insensitive), if any.
    pub fn of(path: &Path) -> Option<PaletteFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "gpl" => Some(PaletteFormat::Gpl),
            "hex" => Some(PaletteFormat::Hex),
            "pal" => Some(PaletteFormat::Pal),
            _ => None,
        }
    }
}

/// A palette file that cannot be used: the file, the line when one is to blame, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PaletteError {
    /// The file.
    pub path: PathBuf,
    /// The line (1-based), when the error is on one.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for PaletteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(
                f,
                "palette {}:{line}: {}",
                self.path.display(),
                self.message
            ),
            None => write!(f, "palette {}: {}", self.path.display(), self.message),
        }
    }
}

impl std::error::Error for PaletteError {}

type Lines<'a> = dyn Iterator<Item = (usize, &'a str)> + 'a;

/// Takes the first line, which must be `want`.
fn header<'a>(lines: &mut Lines<'a>, want: &str, what: &str) -> Result<(), (usize, String)> {
    match lines.next() {
        Some((_, l)) if l.eq_ignore_ascii_case(want) => Ok(()),
        Some((n, l)) => Err((
            n,
            format!("not {what}: expected `{want}`, found `{}`", clip(l)),
        )),
        None => Err((1, format!("not {what}: the file is empty"))),
    }
}

/// A JASC palette's colour count line.
fn pal_count<'a>(lines: &mut Lines<'a>) -> Result<usize, (usize, String)> {
    let Some((n, l)) = lines.next() else {
        return Err((3, "the number of colours is missing".into()));
    };
    match l.parse::<usize>() {
        Ok(c) if (1..=MAX_COLOURS).contains(&c) => Ok(c),
        Ok(c) => Err((
            n,
            format!("{c} colours: a palette holds 1 to {MAX_COLOURS}"),
        )),
        Err(_) => Err((
            n,
            format!("expected the number of colours, found `{}`", clip(l)),
        )),
    }
}

/// A GIMP palette line: a colour, or nothing (blank, comment, `Name:`, `Columns:`).
fn gpl_line(line: &str) -> Result<Option<[u8; 3]>, String> {
    if line.is_empty() || line.starts_with('#') {
        return Ok(None);
    }
    let key = line.split(':').next().unwrap_or("");
    if line.contains(':') && key.chars().all(|c| c.is_ascii_alphabetic() || c == ' ') {
        return Ok(None);
    }
    let mut words = line.split_whitespace();
    let mut next = |which| channel(words.next(), which);
    Ok(Some([next("red")?, next("green")?, next("blue")?]))
}

/// A JASC palette line: exactly `R G B`.
fn rgb_line(line: &str) -> Result<[u8; 3], String> {
    let mut words = line.split_whitespace();
    let c = [
        channel(words.next(), "red")?,
        channel(words.next(), "green")?,
        channel(words.next(), "blue")?,
    ];
    match words.next() {
        None => Ok(c),
        Some(w) => Err(format!("unexpected `{}` after the colour", clip(w))),
    }
}

/// One decimal channel, 0–255.
fn channel(word: Option<&str>, which: &str) -> Result<u8, String> {
    let word = word.ok_or_else(|| format!("the {which} value is missing (expected `R G B`)"))?;
    word.parse::<u8>().map_err(|_| {
        format!(
            "{which} `{}` is not a whole number from 0 to 255",
            clip(word)
        )
    })
}

/// A `.hex` line: `rrggbb` or `#rrggbb`; blank lines and `;` comments are nothing.
fn hex_line(line: &str) -> Result<Option<[u8; 3]>, String> {
    if line.is_empty() || line.starts_with(';') {
        return Ok(None);
    }
    let digits = line.strip_prefix('#').unwrap_or(line);
    let bad = || {
        format!(
            "`{}` is not a colour (expected six hex digits, rrggbb)",
            clip(line)
        )
    };
    if digits.len() != 6 || !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(bad());
    }
    let byte = |i: usize| u8::from_str_radix(&digits[i..i + 2], 16).map_err(|_| bad());
    Ok(Some([byte(0)?, byte(2)?, byte(4)?]))
}

/// `text` cut to 40 characters for a message.
fn clip(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, format: PaletteFormat) -> Result<Vec<[u8; 3]>, (usize, String)> {
        Palette::parse(text, format).map(|p| p.colours)
    }

    #[test]
    fn the_three_formats_read_the_same_colours() {
        let want = vec![[0, 0, 0], [255, 128, 7]];
        let gpl = "GIMP Palette\nName: Two\nColumns: 2\n# a comment\n  0   0   0\tBlack\n255 128   7 Orange\n";
        assert_eq!(parse(gpl, PaletteFormat::Gpl), Ok(want.clone()));
        assert_eq!(
            parse("000000\n\n#FF8007\n", PaletteFormat::Hex),
            Ok(want.clone())
        );
        let pal = "JASC-PAL\r\n0100\r\n2\r\n0 0 0\r\n255 128 7\r\n";
        assert_eq!(parse(pal, PaletteFormat::Pal), Ok(want));
    }

    #[test]
    fn bad_files_name_their_line() {
        let cases: [(&str, PaletteFormat, usize, &str); 10] = [
            ("", PaletteFormat::Hex, 1, "no colours"),
            ("\n\n", PaletteFormat::Hex, 2, "no colours"),
            ("00ff00\nzz0000\n", PaletteFormat::Hex, 2, "not a colour"),
            ("00ff0\n", PaletteFormat::Hex, 1, "six hex digits"),
            ("GIMP\n0 0 0\n", PaletteFormat::Gpl, 1, "not a GIMP palette"),
            (
                "GIMP Palette\n0 0 256\n",
                PaletteFormat::Gpl,
                2,
                "blue `256`",
            ),
            (
                "GIMP Palette\n0 0\n",
                PaletteFormat::Gpl,
                2,
                "blue value is missing",
            ),
            (
                "JASC-PAL\n0100\n3\n0 0 0\n1 1 1\n",
                PaletteFormat::Pal,
                5,
                "2 colours where the header names 3",
            ),
            (
                "JASC-PAL\n0100\n1\n0 0 0\n1 1 1\n",
                PaletteFormat::Pal,
                5,
                "more colours",
            ),
            ("JASC-PAL\n0100\n0\n", PaletteFormat::Pal, 3, "0 colours"),
        ];
        for (text, format, line, part) in cases {
            let (l, message) = parse(text, format).expect_err(text);
            assert_eq!(l, line, "{text:?}: {message}");
            assert!(message.contains(part), "{text:?}: {message}");
        }
    }

    #[test]
    fn a_hundred_thousand_colours_stop_at_the_first_too_many() {
        let text: String = (0..100_000)
            .map(|i| format!("{:06x}\n", i % 0x100_0000))
            .collect();
        let (line, message) = parse(&text, PaletteFormat::Hex).expect_err("too many");
        assert_eq!(line, MAX_COLOURS + 1);
        assert!(message.contains("more than 256"), "{message}");
    }

    #[test]
    fn files_name_themselves_in_errors() {
        let dir = tempfile::tempdir().expect("tempdir");
        let missing = dir.path().join("none.gpl");
        let e = Palette::load(&missing).expect_err("missing");
        assert!(e.to_string().contains("none.gpl"), "{e}");
        let binary = dir.path().join("noise.pal");
        std::fs::write(&binary, [0xff, 0xfe, 0x00, 0x81, 0x12]).expect("write");
        let e = Palette::load(&binary).expect_err("binary");
        assert!(e.to_string().contains("not a text file"), "{e}");
        let other = dir.path().join("colours.txt");
        std::fs::write(&other, "000000\n").expect("write");
        let e = Palette::load(&other).expect_err("extension");
        assert!(e.to_string().contains(".gpl, .hex or .pal"), "{e}");
        let bad = dir.path().join("bad.hex");
        std::fs::write(&bad, "000000\nnothex\n").expect("write");
        let e = Palette::load(&bad).expect_err("bad hex");
        assert_eq!(e.line, Some(2));
        assert!(
            e.to_string()
                .starts_with(&format!("palette {}:2:", bad.display())),
            "{e}"
        );
    }

    #[test]
    fn the_shipped_palettes_load() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/palettes");
        for (name, n) in [
            ("texel-meadow.hex", 16),
            ("texel-night.gpl", 12),
            ("texel-ember.pal", 8),
        ] {
            let p = Palette::load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(p.colours.len(), n, "{name}");
        }
    }

    /// Each format written reads back as the same colours, and a saved file loads again
    /// (written atomically: no temporary file is left beside it).
    #[test]
    fn palettes_round_trip_through_each_format() {
        let p = Palette {
            colours: vec![[0, 0, 0], [255, 128, 7], [12, 200, 99], [255, 255, 255]],
        };
        for format in [PaletteFormat::Gpl, PaletteFormat::Hex, PaletteFormat::Pal] {
            let text = p.to_text(format, "Round\ntrip");
            assert_eq!(Palette::parse(&text, format), Ok(p.clone()), "{text}");
        }
        let dir = tempfile::tempdir().expect("tempdir");
        for name in ["a.gpl", "b.hex", "c.PAL"] {
            let path = dir.path().join(name);
            p.save(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(Palette::load(&path), Ok(p.clone()), "{name}");
        }
        let gpl = std::fs::read_to_string(dir.path().join("a.gpl")).expect("read");
        assert!(gpl.starts_with("GIMP Palette\nName: a\n"), "{gpl}");
        let left: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").collect();
        assert_eq!(left.len(), 3, "only the three palettes");
        let e = p.save(&dir.path().join("d.txt")).expect_err("extension");
        assert!(e.to_string().contains(".gpl, .hex or .pal"), "{e}");
    }

    #[test]
    fn linear_colours_decode_srgb() {
        let p = Palette {
            colours: vec![[0, 0, 0], [255, 255, 255], [188, 188, 188]],
        };
        let l = p.linear();
        assert_eq!(l[0], Vec3::ZERO);
        assert_eq!(l[1], Vec3::ONE);
        assert!((l[2].x - 0.5029).abs() < 1e-3, "{}", l[2].x);
    }
}
