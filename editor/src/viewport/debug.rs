//! Debug views of the probe renderer, switched on in the View menu: pixels drawn from the
//! eye probe tinted, the origins of the probes the last frame drew, the grid cells around
//! the camera, a window with the grid probe's six lit cube faces, and the renderer's
//! texel-density view (with its legend). Each reads GPU data back only while it is on.

use egui::{Color32, ColorImage, Painter, Stroke, TextureHandle, TextureOptions};
use glam::Vec3;
use texel_probes::grid::{GridCell, resolve_grid};
use texel_render::input::ProbeView;
use texel_render::readback::FrameIds;
use texel_runtime::extract::{Viewport as ExtractViewport, grid_settings};
use texel_scene::Scene;

use super::gpu::{GpuView, LastProbes, OtherProbe};
use crate::camera::Projector;
use crate::viewport::overlay;

/// One debug view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DebugView {
    /// Tint the pixels whose colour came from the eye probe.
    EyePixels,
    /// Markers at the eye, grid and previous probe origins.
    ProbeOrigins,
    /// The grid cells around the camera's cell.
    GridCells,
    /// A window with the grid probe's six lit faces.
    CubeFaces,
    /// Captures coloured by texture pixels per art pixel (the renderer's texel-density view):
    /// green 1:1, blue magnified, red minified, grey untextured.
    TexelDensity,
}

impl DebugView {
    /// All views in menu order.
    pub const ALL: [DebugView; 5] = [
        DebugView::EyePixels,
        DebugView::ProbeOrigins,
        DebugView::GridCells,
        DebugView::CubeFaces,
        DebugView::TexelDensity,
    ];

    /// The menu label.
    pub fn label(self) -> &'static str {
        match self {
            DebugView::EyePixels => "Eye-sourced pixels",
            DebugView::ProbeOrigins => "Probe origins",
            DebugView::GridCells => "Grid cells",
            DebugView::CubeFaces => "Cube faces of the grid probe",
            DebugView::TexelDensity => "Texel density",
        }
    }
}

/// Which debug views are on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DebugFlags {
    /// See [`DebugView::EyePixels`].
    pub eye_pixels: bool,
    /// See [`DebugView::ProbeOrigins`].
    pub probe_origins: bool,
    /// See [`DebugView::GridCells`].
    pub grid_cells: bool,
    /// See [`DebugView::CubeFaces`].
    pub cube_faces: bool,
    /// See [`DebugView::TexelDensity`].
    pub texel_density: bool,
}

impl DebugFlags {
    fn slot(&mut self, v: DebugView) -> &mut bool {
        match v {
            DebugView::EyePixels => &mut self.eye_pixels,
            DebugView::ProbeOrigins => &mut self.probe_origins,
            DebugView::GridCells => &mut self.grid_cells,
            DebugView::CubeFaces => &mut self.cube_faces,
            DebugView::TexelDensity => &mut self.texel_density,
        }
    }

    /// Whether `v` is on.
    pub fn get(mut self, v: DebugView) -> bool {
        *self.slot(v)
    }

    /// Switches `v` on or off.
    pub fn toggle(&mut self, v: DebugView) {
        let s = self.slot(v);
        *s = !*s;
    }
}

/// Tint of eye-sourced pixels.
pub const EYE_TINT: Color32 = Color32::from_rgba_premultiplied(120, 0, 120, 120);
const EYE_COLOUR: Color32 = Color32::from_rgb(255, 90, 220);
const GRID_COLOUR: Color32 = Color32::from_rgb(90, 230, 255);
const PREVIOUS_COLOUR: Color32 = Color32::from_rgb(255, 200, 60);
const NEXT_COLOUR: Color32 = Color32::from_rgb(140, 255, 120);
/// Edge pieces per cell edge, so edges passing behind the camera keep their visible part.
const EDGE_PIECES: usize = 6;

/// The last frame's GPU data the debug views read: a [`GpuView`] reads it back when asked,
/// a frame of the render worker carries what the worker read back after drawing it.
pub trait FrameData {
    /// The probes the frame drew.
    fn probes(&self) -> Option<LastProbes>;
    /// Per pixel of the frame: entity id and whether the eye probe drew it.
    fn frame_ids(&self) -> Result<FrameIds, String>;
    /// The six lit faces of `view`'s slot (sRGB8 RGBA, `n × n` texels each), with `n`.
    fn probe_faces(&self, view: &ProbeView) -> Result<(u32, Vec<Vec<u8>>), String>;
}

impl FrameData for GpuView {
    fn probes(&self) -> Option<LastProbes> {
        self.probes
    }

    fn frame_ids(&self) -> Result<FrameIds, String> {
        GpuView::frame_ids(self)
    }

    fn probe_faces(&self, view: &ProbeView) -> Result<(u32, Vec<Vec<u8>>), String> {
        GpuView::probe_faces(self, view)
    }
}

/// The grid probe's faces as last read back.
struct Faces {
    key: FacesKey,
    textures: Vec<TextureHandle>,
}

/// The debug views' switches and what they read back.
#[derive(Default)]
pub struct DebugState {
    /// Which views are on.
    pub flags: DebugFlags,
    eye_tint: Option<TextureHandle>,
    faces: Option<Faces>,
    /// How many times GPU data was read back (tests check that nothing is read while off).
    pub readbacks: u64,
}

impl DebugState {
    /// Takes what the views that are on need from the last frame's `data`: after a new
    /// frame (`rendered`), or when a view was just switched on. `settled` says the frame was
    /// the last of a settle run (the probe faces are complete then).
    pub fn update(
        &mut self,
        ctx: &egui::Context,
        data: &dyn FrameData,
        rendered: bool,
        settled: bool,
    ) {
        if !self.flags.eye_pixels {
            self.eye_tint = None;
        } else if rendered || self.eye_tint.is_none() {
            // No frame yet gives an empty image, which egui cannot hold as a texture.
            if let Ok(ids) = data.frame_ids()
                && ids.size.x > 0
                && ids.size.y > 0
                && ids.from_eye.len() == (ids.size.x * ids.size.y) as usize
            {
                self.readbacks += 1;
                let image = eye_mask(&ids);
                self.eye_tint = Some(ctx.load_texture("debug::eye", image, nearest()));
            }
        }
        if !self.flags.cube_faces {
            self.faces = None;
        } else if let Some(p) = data.probes() {
            let key = probe_key(&p.grid);
            let stale = self.faces.as_ref().is_none_or(|f| f.key != key);
            if (stale || (rendered && settled))
                && let Ok((n, faces)) = data.probe_faces(&p.grid)
            {
                self.readbacks += 1;
                let textures = faces
                    .into_iter()
                    .enumerate()
                    .map(|(i, rgba)| {
                        let size = [n as usize, n as usize];
                        let image = ColorImage::from_rgba_unmultiplied(size, &rgba);
                        ctx.load_texture(format!("debug::face{i}"), image, nearest())
                    })
                    .collect();
                self.faces = Some(Faces { key, textures });
            }
        }
    }

    /// Paints the overlays of the views that are on over the viewport.
    pub fn paint(
        &self,
        painter: &Painter,
        proj: &Projector,
        probes: Option<&LastProbes>,
        scene: &Scene,
        camera: Vec3,
        viewport: ExtractViewport,
    ) {
        let rect = proj.rect();
        if let Some(t) = &self.eye_tint {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            painter.image(t.id(), rect, uv, Color32::WHITE);
        }
        if self.flags.grid_cells {
            grid_cells(painter, proj, scene, camera, viewport);
        }
        if self.flags.probe_origins
            && let Some(p) = probes
        {
            // Name, colour, view, and whether it is the camera cell's probe, which placement
            // may have moved off its cell's vertex.
            let other = p.other.map(|(what, v)| match what {
                OtherProbe::Previous => ("previous", PREVIOUS_COLOUR, v, false),
                OtherProbe::Next => ("next", NEXT_COLOUR, v, false),
            });
            let views = [
                Some(("eye", EYE_COLOUR, p.eye, false)),
                Some(("grid", GRID_COLOUR, p.grid, true)),
                other,
            ];
            // The probes follow the camera, so their origins are often off screen: a
            // readout in the corner says where they are relative to the eye.
            // Below the Play banner and the render error line.
            let mut line = proj.rect().left_top() + egui::vec2(8.0, 30.0);
            // The grid probe's cell vertex: placement moves the probe off it when it would
            // be blind there (inside a solid, on a surface).
            let (defaults, overrides) = grid_settings(scene, viewport);
            let vertex = resolve_grid(camera, &defaults, &overrides).map(|c| c.origin());
            for (name, colour, v, cell) in views.into_iter().flatten() {
                if cell
                    && let Ok(vertex) = vertex
                    && (v.origin - vertex).length() > 1e-4
                {
                    let m = v.origin - vertex;
                    let text = format!(
                        "{name:<8} placed {:>5.2} {:>5.2} {:>5.2} from its cell centre",
                        m.x, m.y, m.z
                    );
                    backed_text(painter, line, text, colour);
                    line.y += 15.0;
                    if let (Some(a), Some(b)) = (proj.project(vertex), proj.project(v.origin)) {
                        painter.line_segment([a, b], Stroke::new(1.5, colour));
                        painter.circle_stroke(a, 3.0, Stroke::new(1.0, colour));
                    }
                }
                let d = v.origin - camera;
                backed_text(
                    painter,
                    line,
                    format!(
                        "{name:<8} origin {:>6.2} {:>6.2} {:>6.2}  Δeye {:>5.2} {:>5.2} {:>5.2}  faces {:06b}",
                        v.origin.x,
                        v.origin.y,
                        v.origin.z,
                        d.x,
                        d.y,
                        d.z,
                        v.draw.bits()
                    ),
                    colour,
                );
                line.y += 15.0;
                if let Some(at) = proj.project(v.origin) {
                    painter.circle_stroke(at, 6.0, Stroke::new(2.0, colour));
                    painter.line_segment(
                        [at - egui::vec2(9.0, 0.0), at + egui::vec2(9.0, 0.0)],
                        Stroke::new(1.0, colour),
                    );
                    painter.line_segment(
                        [at - egui::vec2(0.0, 9.0), at + egui::vec2(0.0, 9.0)],
                        Stroke::new(1.0, colour),
                    );
                    painter.text(
                        at + egui::vec2(9.0, -9.0),
                        egui::Align2::LEFT_BOTTOM,
                        format!(
                            "{name} {:.2} {:.2} {:.2}",
                            v.origin.x, v.origin.y, v.origin.z
                        ),
                        egui::FontId::monospace(11.0),
                        colour,
                    );
                }
            }
        }
    }

    /// The window with the grid probe's faces (open while the view is on), first placed in
    /// the bottom left corner of the viewport `rect`.
    pub fn faces_window(&mut self, ctx: &egui::Context, rect: egui::Rect) {
        let mut open = self.flags.cube_faces;
        egui::Window::new("Grid probe faces")
            .open(&mut open)
            .pivot(egui::Align2::LEFT_BOTTOM)
            .default_pos(rect.left_bottom() + egui::vec2(8.0, -30.0))
            .resizable(false)
            .show(ctx, |ui| match &self.faces {
                Some(f) => {
                    ui.label(format!(
                        "slot {} · origin {:?} · {}² texels",
                        f.key.0,
                        f.key.1.map(f32::from_bits),
                        f.key.2
                    ));
                    egui::Grid::new("debug::faces").show(ui, |ui| {
                        for (i, (t, name)) in f.textures.iter().zip(FACE_NAMES).enumerate() {
                            let captured = f.key.3 & (1 << i) != 0;
                            ui.vertical(|ui| {
                                ui.label(name);
                                let size = egui::vec2(FACE_PX, FACE_PX);
                                if captured {
                                    ui.image((t.id(), size));
                                } else {
                                    let (r, _) = ui.allocate_exact_size(size, egui::Sense::hover());
                                    ui.painter().rect_filled(r, 0.0, Color32::from_gray(40));
                                    ui.painter().text(
                                        r.center(),
                                        egui::Align2::CENTER_CENTER,
                                        "not captured",
                                        egui::FontId::proportional(12.0),
                                        Color32::GRAY,
                                    );
                                }
                            });
                            if i % 3 == 2 {
                                ui.end_row();
                            }
                        }
                    });
                }
                None => {
                    ui.label("no grid probe yet");
                }
            });
        self.flags.cube_faces = open;
    }

    /// The legend of the texel-density view (shown while it is on), in the bottom right
    /// corner of the viewport `rect`.
    pub fn density_legend(&self, ctx: &egui::Context, rect: egui::Rect) {
        if !self.flags.texel_density {
            return;
        }
        egui::Area::new(egui::Id::unique("debug::density_legend"))
            .pivot(egui::Align2::RIGHT_BOTTOM)
            .fixed_pos(rect.right_bottom() + egui::vec2(-8.0, -8.0))
            .interactable(false)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.label(egui::RichText::new("Texel density").strong());
                    for (colour, text) in DENSITY_LEGEND {
                        ui.horizontal(|ui| {
                            let (r, _) = ui
                                .allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
                            ui.painter().rect_filled(r, 2.0, colour);
                            ui.label(text);
                        });
                    }
                });
            });
    }

    /// Whether an eye-pixel tint is ready to paint.
    pub fn has_eye_tint(&self) -> bool {
        self.eye_tint.is_some()
    }

    /// How many face images the faces window shows.
    pub fn face_count(&self) -> usize {
        self.faces.as_ref().map_or(0, |f| f.textures.len())
    }
}

/// The texel-density view's colours (the capture shader's, in sRGB, unlit) and meanings.
pub const DENSITY_LEGEND: [(Color32, &str); 4] = [
    (
        Color32::from_rgb(89, 225, 89),
        "green: 1:1 (a texture pixel per art pixel)",
    ),
    (
        Color32::from_rgb(39, 63, 231),
        "blue: magnified (texture pixels larger)",
    ),
    (
        Color32::from_rgb(231, 39, 39),
        "red: minified (texture pixels smaller)",
    ),
    (Color32::from_gray(160), "grey: untextured"),
];

/// Shown size of one face in the faces window, points.
const FACE_PX: f32 = 88.0;
const FACE_NAMES: [&str; 6] = ["+X", "−X", "+Y", "−Y", "+Z", "−Z"];

fn nearest() -> TextureOptions {
    TextureOptions::NEAREST
}

/// Slot, origin bits, face resolution and captured faces of a probe: the faces are read
/// again when any of these changes.
/// What identifies a probe's faces: slot, origin, face resolution, captured faces.
pub type FacesKey = (usize, [u32; 3], u32, u8);

/// The [`FacesKey`] of `v`.
pub fn probe_key(v: &ProbeView) -> FacesKey {
    (
        v.slot as usize,
        v.origin.to_array().map(f32::to_bits),
        v.face_resolution,
        v.valid.bits(),
    )
}

/// An image as large as the frame: [`EYE_TINT`] where the eye probe drew, clear elsewhere.
pub fn eye_mask(ids: &FrameIds) -> ColorImage {
    let size = [ids.size.x as usize, ids.size.y as usize];
    let pixels = ids
        .from_eye
        .iter()
        .map(|&e| if e { EYE_TINT } else { Color32::TRANSPARENT })
        .collect();
    ColorImage::new(size, pixels)
}

/// The world boxes of the cell containing `camera` and its 26 neighbours (the region that
/// snaps to each probe origin), and the cell of the camera.
pub fn cells_around(cell: &GridCell) -> (Vec<(Vec3, Vec3)>, (Vec3, Vec3)) {
    let s = cell.cell_size;
    let half = Vec3::splat(s * 0.5);
    let centre = cell.origin();
    let mut out = Vec::with_capacity(27);
    for z in -1..=1 {
        for y in -1..=1 {
            for x in -1..=1 {
                let c = centre + Vec3::new(x as f32, y as f32, z as f32) * s;
                out.push((c - half, c + half));
            }
        }
    }
    (out, (centre - half, centre + half))
}

fn grid_cells(p: &Painter, proj: &Projector, scene: &Scene, camera: Vec3, v: ExtractViewport) {
    let (defaults, overrides) = grid_settings(scene, v);
    let choice = match resolve_grid(camera, &defaults, &overrides) {
        Ok(c) => c,
        Err(e) => {
            p.text(
                proj.rect().left_bottom() + egui::vec2(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                format!("grid: {e}"),
                egui::FontId::proportional(13.0),
                Color32::from_rgb(255, 120, 120),
            );
            return;
        }
    };
    let faint = Stroke::new(1.0, Color32::from_rgba_unmultiplied(90, 230, 255, 70));
    let (cells, own) = cells_around(&choice.key.cell);
    for (min, max) in cells {
        pieced_box(p, proj, min, max, faint);
    }
    pieced_box(
        p,
        proj,
        own.0,
        own.1,
        Stroke::new(2.0, Color32::from_rgb(90, 230, 255)),
    );
    if let Some(i) = choice.override_index
        && let Some(o) = overrides.get(i)
    {
        pieced_box(
            p,
            proj,
            o.min,
            o.max,
            Stroke::new(2.5, Color32::from_rgb(255, 140, 40)),
        );
    }
    if let Some(at) = proj.project(choice.origin()) {
        p.circle_filled(at, 3.0, Color32::from_rgb(90, 230, 255));
    }
    backed_text(
        p,
        proj.rect().left_bottom() + egui::vec2(8.0, -22.0),
        format!(
            "cell {:?} · size {} · {} texels{}",
            choice.key.cell.index.to_array(),
            choice.key.cell.cell_size,
            choice.key.face_resolution,
            choice
                .override_index
                .map_or(String::new(), |i| format!(" · override #{i}"))
        ),
        Color32::from_rgb(90, 230, 255),
    );
}

/// Monospace text with its top left at `at` on a dark backing, readable over the sky.
fn backed_text(p: &Painter, at: egui::Pos2, text: String, colour: Color32) {
    let galley = p.layout_no_wrap(text, egui::FontId::monospace(11.0), colour);
    let rect = egui::Rect::from_min_size(at, galley.size()).expand(2.0);
    p.rect_filled(rect, 2.0, Color32::from_black_alpha(170));
    p.galley(at, galley, colour);
}

/// A box whose edges are split into pieces, so the visible part of an edge that passes
/// behind the camera still shows.
fn pieced_box(p: &Painter, proj: &Projector, min: Vec3, max: Vec3, stroke: Stroke) {
    let c = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                let (a, b) = (c(i), c(i | bit));
                for k in 0..EDGE_PIECES {
                    let t0 = k as f32 / EDGE_PIECES as f32;
                    let t1 = (k + 1) as f32 / EDGE_PIECES as f32;
                    overlay::segment(p, proj, a.lerp(b, t0), a.lerp(b, t1), stroke);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{IVec3, UVec2};

    #[test]
    fn eye_mask_tints_only_eye_pixels() {
        let ids = FrameIds {
            size: UVec2::new(2, 1),
            entity: vec![1, 0],
            from_eye: vec![true, false],
        };
        let m = eye_mask(&ids);
        assert_eq!(m.pixels, vec![EYE_TINT, Color32::TRANSPARENT]);
    }

    #[test]
    fn cells_surround_the_camera_cell() {
        let cell = GridCell {
            index: IVec3::new(2, 0, -1),
            cell_size: 2.0,
        };
        let (cells, own) = cells_around(&cell);
        assert_eq!(cells.len(), 27);
        assert_eq!(cells[13], own);
        assert_eq!(own.0, Vec3::new(3.0, -1.0, -3.0));
        assert_eq!(own.1, Vec3::new(5.0, 1.0, -1.0));
    }

    #[test]
    fn flags_toggle() {
        let mut f = DebugFlags::default();
        for v in DebugView::ALL {
            assert!(!f.get(v));
            f.toggle(v);
            assert!(f.get(v));
        }
    }
}
