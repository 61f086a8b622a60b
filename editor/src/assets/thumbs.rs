//! Thumbnails for the asset panel, made off the UI thread: a loader thread reads each image
//! with the scene's bounded texture reader and shrinks it to at most [`THUMB_SIZE`] pixels,
//! draws a glTF mesh (read with the scene's bounded importer) in a three-quarter view
//! ([`super::mesh_thumb`]), or reads a palette's colours, and hands the result back. The panel asks for a thumbnail
//! when its tile is on screen, shows a placeholder until it is there, and keeps it by path
//! and modification time (a changed file is read again). A file that cannot be read shows
//! as broken, with the reason.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::SystemTime;

use texel_scene::palette::Palette;
use texel_scene::texture::{Image, load_texture};

use super::scan::AssetKind;

/// The longest side of a thumbnail, pixels.
pub const THUMB_SIZE: u32 = 48;

/// What the loader made of a file.
#[derive(Debug, Clone, PartialEq)]
pub enum Made {
    /// An image, shrunk: width, height, RGBA8 pixels.
    Image(u32, u32, Vec<u8>),
    /// A palette's colours (sRGB).
    Swatches(Vec<[u8; 3]>),
    /// The file could not be read; why.
    Broken(String),
}

/// A thumbnail as the panel sees it.
#[derive(Clone)]
pub enum Thumb {
    /// Asked for, not made yet.
    Pending,
    /// An image, uploaded to egui.
    Image(egui::TextureHandle),
    /// A palette's colours.
    Swatches(Vec<[u8; 3]>),
    /// The file could not be read.
    Broken(String),
}

struct Request {
    path: PathBuf,
    kind: AssetKind,
    modified: Option<SystemTime>,
}

type Reply = (PathBuf, Option<SystemTime>, Made);

/// The thumbnail cache and its loader thread (started on the first request).
#[derive(Default)]
pub struct Thumbnails {
    cache: HashMap<PathBuf, (Option<SystemTime>, Thumb)>,
    loader: Option<(Sender<Request>, Receiver<Reply>)>,
    /// While set, the loader waits before each file (tests hold it to see the frames go on).
    held: Arc<AtomicBool>,
}

impl Thumbnails {
    /// The thumbnail of `path` (a `kind` file): made, or asked of the loader now and
    /// [`Thumb::Pending`] until it answers (a mesh's is drawn from its triangles:
    /// [`super::mesh_thumb`]).
    pub fn get(&mut self, ctx: &egui::Context, path: &Path, kind: AssetKind) -> Option<Thumb> {
        let modified = std::fs::metadata(path).and_then(|m| m.modified()).ok();
        if let Some((when, thumb)) = self.cache.get(path)
            && *when == modified
        {
            return Some(thumb.clone());
        }
        let held = self.held.clone();
        let (tx, _) = (self.loader).get_or_insert_with(|| start_loader(ctx.clone(), held));
        let request = Request {
            path: path.to_path_buf(),
            kind,
            modified,
        };
        if tx.send(request).is_err() {
            // The loader is gone (it panicked): start another next time.
            self.loader = None;
        }
        self.cache
            .insert(path.to_path_buf(), (modified, Thumb::Pending));
        Some(Thumb::Pending)
    }

    /// Takes what the loader made since the last call (without waiting), uploading images to
    /// `ctx`.
    pub fn collect(&mut self, ctx: &egui::Context) {
        let Some((_, rx)) = &self.loader else {
            return;
        };
        let replies: Vec<Reply> = rx.try_iter().collect();
        for (path, modified, made) in replies {
            let thumb = match made {
                Made::Image(w, h, pixels) => {
                    let size = [w as usize, h as usize];
                    let colour = egui::ColorImage::from_rgba_unmultiplied(size, &pixels);
                    let name = format!("asset thumbnail {}", path.display());
                    Thumb::Image(ctx.load_texture(name, colour, egui::TextureOptions::NEAREST))
                }
                Made::Swatches(c) => Thumb::Swatches(c),
                Made::Broken(e) => Thumb::Broken(e),
            };
            // An answer for a file changed since it was asked is dropped (asked again).
            if let Some(entry) = self.cache.get_mut(&path)
                && entry.0 == modified
            {
                entry.1 = thumb;
            }
        }
    }

    /// Holds the loader (it makes nothing while held) or lets it go on.
    pub fn hold(&self, held: bool) {
        self.held.store(held, Ordering::SeqCst);
    }

    /// The thumbnail of `path` as it stands (`None`: never asked for), without asking.
    pub fn peek(&self, path: &Path) -> Option<&Thumb> {
        self.cache.get(path).map(|(_, t)| t)
    }

    /// How many thumbnails are still being made.
    pub fn pending(&self) -> usize {
        (self.cache.values())
            .filter(|(_, t)| matches!(t, Thumb::Pending))
            .count()
    }
}

fn start_loader(ctx: egui::Context, held: Arc<AtomicBool>) -> (Sender<Request>, Receiver<Reply>) {
    let (tx, requests) = channel::<Request>();
    let (replies, rx) = channel::<Reply>();
    let spawned = std::thread::Builder::new()
        .name("asset thumbnails".into())
        .spawn(move || {
            for r in requests {
                while held.load(Ordering::SeqCst) {
                    std::thread::sleep(std::time::Duration::from_millis(5));
                }
                let made = make(&r.path, r.kind);
                if replies.send((r.path, r.modified, made)).is_err() {
                    return;
                }
                ctx.request_repaint();
            }
        });
    if let Err(e) = spawned {
        eprintln!("texel-editor: no thumbnail thread: {e}");
    }
    (tx, rx)
}

/// Reads `path` as a `kind` thumbnail (on the loader thread).
pub fn make(path: &Path, kind: AssetKind) -> Made {
    match kind {
        AssetKind::Palette => match Palette::load(path) {
            Ok(p) => Made::Swatches(p.colours),
            Err(e) => Made::Broken(e.to_string()),
        },
        AssetKind::Mesh => match texel_scene::gltf_import::load_gltf(path) {
            Ok(mesh) => match super::mesh_thumb::draw(&mesh, THUMB_SIZE) {
                Some(pixels) => Made::Image(THUMB_SIZE, THUMB_SIZE, pixels),
                None => Made::Broken("no triangles to show".into()),
            },
            Err(e) => Made::Broken(e.to_string()),
        },
        _ => match load_texture(path) {
            Ok(image) => {
                let (w, h, pixels) = shrink(&image, THUMB_SIZE);
                Made::Image(w, h, pixels)
            }
            Err(e) => Made::Broken(e.to_string()),
        },
    }
}

/// `image` shrunk (nearest pixel, as pixel art wants) so its longer side is at most `max`;
/// a smaller image is kept as it is.
pub fn shrink(image: &Image, max: u32) -> (u32, u32, Vec<u8>) {
    let (w, h) = (image.width.max(1), image.height.max(1));
    let scale = (max as f32 / w.max(h) as f32).min(1.0);
    let tw = ((w as f32 * scale).round() as u32).clamp(1, max);
    let th = ((h as f32 * scale).round() as u32).clamp(1, max);
    let mut out = Vec::with_capacity((tw * th * 4) as usize);
    for y in 0..th {
        let sy = ((y as f32 + 0.5) * h as f32 / th as f32) as u32;
        for x in 0..tw {
            let sx = ((x as f32 + 0.5) * w as f32 / tw as f32) as u32;
            let i = ((sy.min(h - 1) * w + sx.min(w - 1)) * 4) as usize;
            out.extend_from_slice(image.pixels.get(i..i + 4).unwrap_or(&[0, 0, 0, 0]));
        }
    }
    (tw, th, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32) -> Image {
        let pixels = (0..w * h)
            .flat_map(|i| [(i % w) as u8, (i / w) as u8, 0, 255])
            .collect();
        Image {
            name: "t".into(),
            width: w,
            height: h,
            pixels,
        }
    }

    #[test]
    fn thumbnails_keep_proportions_and_small_images() {
        let (w, h, px) = shrink(&image(256, 128), 48);
        assert_eq!((w, h, px.len()), (48, 24, 48 * 24 * 4));
        // Nearest: the last column samples near the source's last.
        assert!(px[(47 * 4) as usize] > 240);
        let (w, h, px) = shrink(&image(16, 8), 48);
        assert_eq!((w, h), (16, 8));
        assert_eq!(px, image(16, 8).pixels);
    }

    #[test]
    fn a_broken_file_is_broken_not_a_panic() {
        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.png");
        std::fs::write(&bad, b"not a png").unwrap();
        assert!(matches!(make(&bad, AssetKind::Texture), Made::Broken(_)));
        let mesh = dir.path().join("bad.glb");
        std::fs::write(&mesh, b"glTF not really").unwrap();
        assert!(matches!(make(&mesh, AssetKind::Mesh), Made::Broken(_)));
        let crate_glb = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/meshes/crate.glb");
        match make(Path::new(crate_glb), AssetKind::Mesh) {
            Made::Image(w, h, px) => {
                assert_eq!((w, h), (THUMB_SIZE, THUMB_SIZE));
                assert!(px.chunks(4).any(|p| p[3] == 255), "the crate shows");
            }
            other => panic!("a picture of the crate, not {other:?}"),
        }
        let pal = dir.path().join("p.hex");
        std::fs::write(&pal, "ff0000\n00ff00\n").unwrap();
        assert_eq!(
            make(&pal, AssetKind::Palette),
            Made::Swatches(vec![[255, 0, 0], [0, 255, 0]])
        );
    }
}
