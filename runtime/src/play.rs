//! The windowed "play" shell: a winit window, a wgpu surface, the first-person camera and an
//! egui overlay with frame times and work counters, on top of whatever draws the frame.
//!
//! The frame is drawn by a [`Session`], the overlay by `overlay`; the player walks through
//! the level's colliders ([`Walker`]), moving objects posed at the session's animation time.
//! Controls: click to capture the mouse, WASD to walk, Shift to run, Space/E to jump, F to
//! toggle flying (through everything; Space/E and Ctrl/Q rise and sink), Tab to switch the
//! schedule, F3 to hide the overlay, R and G to raise and lower the terrain under the
//! crosshair (`crate::play_sculpt`), Esc to release the mouse and Esc again (or closing the window)
//! to quit. The level file is watched: saved again (by hand or by the editor), the rows that
//! changed are taken in as edits, at the cost of what changed (`crate::reload`).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, anyhow, bail};
use glam::{UVec2, Vec2};
use texel_render::context::{GpuContext, new_instance};
use texel_render::input::Schedule;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::error::EventLoopError;
use winit::event::{DeviceEvent, DeviceId, ElementState, KeyEvent, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{CursorGrabMode, Window, WindowId};

use crate::first_person::{InputState, WalkCamera};
use crate::load::{LoadedLevel, load_level};
use crate::play_sculpt::{SculptKeys, dab_at_centre};
use crate::reload::LevelWatch;
use crate::session::{FrameRequest, Session};
use crate::walk::Walker;

mod overlay;
use overlay::{FpsMeter, Overlay, dab_line, overlay_lines};

/// Vertical field of view of the play camera, degrees.
pub const FOV_Y_DEG: f32 = 60.0;
pub use overlay::{FPS_WINDOW, KEY_HELP};

/// How to run [`play`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlayOptions {
    /// Requested inner size of the window in physical pixels (the window system may differ).
    pub size: (u32, u32),
    /// Quit by itself after presenting this many frames (for tests); `None` runs until the
    /// window is closed.
    pub exit_after_frames: Option<u32>,
}

impl Default for PlayOptions {
    fn default() -> Self {
        PlayOptions {
            size: (1280, 720),
            exit_after_frames: None,
        }
    }
}

/// Parses a size written `WIDTHxHEIGHT` (e.g. `1280x720`); both sides within
/// 1..=[`texel_render::validate::MAX_OUTPUT_SIDE`] (the device may allow less: see
/// `texel_render::validate::device_output`).
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    use texel_render::validate::MAX_OUTPUT_SIDE;
    let bad = || format!("invalid size `{text}`: expected WIDTHxHEIGHT, e.g. 1280x720");
    let (w, h) = text.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |s: &str| s.trim().parse::<u64>().map_err(|_| bad());
    let (w, h) = (side(w)?, side(h)?);
    let range = 1..=u64::from(MAX_OUTPUT_SIDE);
    if !range.contains(&w) || !range.contains(&h) {
        return Err(format!(
            "size {w}x{h} is out of range: each side must be 1..={MAX_OUTPUT_SIDE} (the \
             renderer's limit)"
        ));
    }
    Ok((w as u32, h as u32))
}

/// Opens a window on `level_path` and plays it until the window closes (or, with
/// [`PlayOptions::exit_after_frames`], until that many frames are shown).
///
/// A level that cannot be loaded returns its [`crate::load::LoadError`] (downcast it to tell
/// it apart); no display, no GPU or a GPU that cannot present returns an error too, never a
/// panic. May be called from any thread on X11 and Wayland, but only once per process
/// (winit allows one event loop).
pub fn play(level_path: &Path, options: PlayOptions) -> anyhow::Result<()> {
    let level = load_level(level_path)?;
    let event_loop = new_event_loop()?;
    let mut app = App::new(level, options);
    event_loop
        .run_app(&mut app)
        .context("the window's event loop failed")?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

fn new_event_loop() -> anyhow::Result<EventLoop<()>> {
    let mut builder = EventLoop::builder();
    #[cfg(all(
        unix,
        not(any(target_os = "macos", target_os = "ios", target_os = "android"))
    ))]
    {
        // Tests and tools run the loop off the main thread; X11 and Wayland allow it.
        winit::platform::x11::EventLoopBuilderExtX11::with_any_thread(&mut builder, true);
    }
    builder.build().map_err(|e| match e {
        EventLoopError::RecreationAttempt => {
            anyhow!("cannot open a window: play runs once per process (winit's one event loop)")
        }
        e => anyhow!(
            "cannot open a window: {e} (play needs a display: run it in a desktop session, \
             or under Xvfb with DISPLAY set)"
        ),
    })
}

/// A movement key, held or not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MoveKey {
    Forward,
    Back,
    Left,
    Right,
    Up,
    Down,
    Run,
}

impl MoveKey {
    fn flag(self, input: &mut InputState) -> &mut bool {
        match self {
            MoveKey::Forward => &mut input.forward,
            MoveKey::Back => &mut input.back,
            MoveKey::Left => &mut input.left,
            MoveKey::Right => &mut input.right,
            MoveKey::Up => &mut input.up,
            MoveKey::Down => &mut input.down,
            MoveKey::Run => &mut input.run,
        }
    }
}

/// What a key does in the play shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KeyAction {
    /// Sets one movement flag while held.
    Move(MoveKey),
    /// Raises (`true`) or lowers the terrain under the crosshair while held.
    Sculpt(bool),
    ToggleFly,
    ToggleSchedule,
    ToggleOverlay,
    /// The level's palette or its alternate (day and night).
    SwapPalette,
    Escape,
}

fn key_action(code: KeyCode) -> Option<KeyAction> {
    use KeyAction::*;
    Some(match code {
        KeyCode::KeyW | KeyCode::ArrowUp => Move(MoveKey::Forward),
        KeyCode::KeyS | KeyCode::ArrowDown => Move(MoveKey::Back),
        KeyCode::KeyA | KeyCode::ArrowLeft => Move(MoveKey::Left),
        KeyCode::KeyD | KeyCode::ArrowRight => Move(MoveKey::Right),
        KeyCode::Space | KeyCode::KeyE => Move(MoveKey::Up),
        KeyCode::ControlLeft | KeyCode::ControlRight | KeyCode::KeyQ => Move(MoveKey::Down),
        KeyCode::ShiftLeft | KeyCode::ShiftRight => Move(MoveKey::Run),
        KeyCode::KeyF => ToggleFly,
        KeyCode::KeyR => Sculpt(true),
        KeyCode::KeyG => Sculpt(false),
        KeyCode::Tab => ToggleSchedule,
        KeyCode::F3 => ToggleOverlay,
        KeyCode::KeyN => SwapPalette,
        KeyCode::Escape => Escape,
        _ => return None,
    })
}

/// Everything that exists once the window is open.
struct Running {
    overlay: Overlay,
    session: Session,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    ctx: GpuContext,
    window: Arc<Window>,
}

impl Running {
    fn reconfigure(&mut self, size: PhysicalSize<u32>) {
        if size.width == 0 || size.height == 0 {
            return; // minimised: keep the old configuration and draw nothing
        }
        self.config.width = size.width;
        self.config.height = size.height;
        self.surface.configure(&self.ctx.device, &self.config);
    }
}

struct App {
    /// The level played (sculpting changes its heights in memory only).
    level: LoadedLevel,
    options: PlayOptions,
    running: Option<Running>,
    error: Option<anyhow::Error>,
    camera: WalkCamera,
    /// The level's colliders and the player; `None` when they could not be built (the
    /// camera then only flies).
    walker: Option<Walker>,
    input: InputState,
    mouse_delta: Vec2,
    schedule: Schedule,
    overlay: bool,
    grabbed: bool,
    /// Factor on raw mouse motion (see [`confined_motion_doubles`]).
    motion_scale: f32,
    frames: u32,
    last_frame: Option<Instant>,
    fps: FpsMeter,
    sculpt: SculptKeys,
    /// Probe faces the last dab marked for capture.
    dab_marked: Option<u32>,
    /// The level file, taken in again when it changes on disk (`crate::reload`).
    watch: LevelWatch,
}

impl App {
    fn new(level: LoadedLevel, options: PlayOptions) -> Self {
        let level_path = level.path.clone();
        let mut camera = WalkCamera::from_scene(&level.scene);
        let walker = match Walker::new(&level.scene, &level.assets) {
            Ok(w) => {
                for warning in w.warnings() {
                    eprintln!("warning: {}: {warning}", level.path.display());
                }
                Some(w)
            }
            Err(e) => {
                eprintln!(
                    "warning: {}: no collision, flying only: {e}",
                    level.path.display()
                );
                camera.toggle_fly();
                None
            }
        };
        App {
            camera,
            walker,
            level,
            options,
            running: None,
            error: None,
            input: InputState::default(),
            mouse_delta: Vec2::ZERO,
            schedule: Schedule::Ours,
            overlay: true,
            grabbed: false,
            motion_scale: 1.0,
            frames: 0,
            last_frame: None,
            fps: FpsMeter::default(),
            sculpt: SculptKeys::default(),
            dab_marked: None,
            watch: LevelWatch::new(&level_path),
        }
    }

    /// Takes in the level file when it changed on disk: the rows that changed as edits
    /// ([`Session::reload`]), the colliders built again around the player where it stands.
    /// A file that does not load is reported and the level played goes on.
    fn reload_if_changed(&mut self) {
        if !self.watch.changed() {
            return;
        }
        let Some(r) = &mut self.running else {
            return;
        };
        let path = self.level.path.clone();
        let new = match load_level(&path) {
            Ok(new) => new,
            Err(e) => {
                eprintln!("play: {} changed but does not load: {e}", path.display());
                return;
            }
        };
        match r.session.reload(&r.ctx, &self.level, &new) {
            Ok(how) => eprintln!("play: {} changed on disk: {how:?}", path.display()),
            Err(e) => {
                eprintln!("play: {} changed but cannot be drawn: {e}", path.display());
                return;
            }
        }
        if let Some(w) = &mut self.walker
            && let Err(e) = w.rebuild(&new.scene, &new.assets)
        {
            eprintln!("play: the collision keeps the old level: {e}");
        }
        self.level = new;
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    fn title(&self) -> String {
        let name = self
            .level
            .path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| self.level.path.display().to_string());
        format!("Texel — {name}")
    }

    fn open(&self, event_loop: &ActiveEventLoop) -> anyhow::Result<Running> {
        let (w, h) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(self.title())
            .with_inner_size(PhysicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot create the window")?,
        );
        let instance = new_instance();
        let surface = instance
            .create_surface(window.clone())
            .context("cannot create a wgpu surface for the window")?;
        let ctx = pollster::block_on(GpuContext::with_instance(instance, Some(&surface)))?;
        let config = surface_config(&surface, &ctx, window.inner_size())?;
        surface.configure(&ctx.device, &config);
        let size = UVec2::new(config.width, config.height);
        let fov_y = FOV_Y_DEG.to_radians();
        let session = Session::new(&ctx, &self.level, config.format, size, fov_y)?;
        let overlay = Overlay::new(&ctx, &window, overlay_format(&config));
        eprintln!("play: {} on {}", self.title(), ctx.describe());
        Ok(Running {
            overlay,
            session,
            surface,
            config,
            ctx,
            window,
        })
    }

    /// Captures the mouse for looking around (hidden, locked or else confined), or lets go.
    fn set_grab(&mut self, event_loop: &ActiveEventLoop, grab: bool) {
        let Some(r) = &self.running else { return };
        self.motion_scale = 1.0;
        if grab {
            let mode = match r.window.set_cursor_grab(CursorGrabMode::Locked) {
                Ok(()) => Ok(CursorGrabMode::Locked),
                Err(_) => r
                    .window
                    .set_cursor_grab(CursorGrabMode::Confined)
                    .map(|()| CursorGrabMode::Confined),
            };
            match mode {
                Ok(CursorGrabMode::Confined) if confined_motion_doubles(event_loop) => {
                    self.motion_scale = 0.5;
                }
                Ok(_) => {}
                // Raw mouse motion still turns the view; the cursor may just leave the window.
                Err(e) => eprintln!("play: cannot grab the cursor: {e}"),
            }
        } else if let Err(e) = r.window.set_cursor_grab(CursorGrabMode::None) {
            eprintln!("play: cannot release the cursor: {e}");
        }
        r.window.set_cursor_visible(!grab);
        self.grabbed = grab;
        self.mouse_delta = Vec2::ZERO;
    }

    fn on_key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) {
        let PhysicalKey::Code(code) = event.physical_key else {
            return;
        };
        let pressed = event.state == ElementState::Pressed;
        let Some(action) = key_action(code) else {
            return;
        };
        match action {
            KeyAction::Move(key) => {
                *key.flag(&mut self.input) = pressed;
                return;
            }
            KeyAction::Sculpt(raise) => {
                self.sculpt.set(raise, pressed);
                return;
            }
            _ => {}
        }
        if !pressed || event.repeat {
            return;
        }
        match action {
            KeyAction::ToggleFly => self.toggle_fly(),
            KeyAction::ToggleSchedule => {
                self.schedule = match self.schedule {
                    Schedule::Ours => Schedule::Paper,
                    Schedule::Paper => Schedule::Ours,
                }
            }
            KeyAction::ToggleOverlay => self.overlay = !self.overlay,
            KeyAction::SwapPalette => {
                let swapped = (self.running.as_mut()).and_then(|r| r.session.swap_palette());
                if swapped.is_none() {
                    eprintln!("N: the level names no alternate palette");
                }
            }
            KeyAction::Escape if self.grabbed => self.set_grab(event_loop, false),
            KeyAction::Escape => event_loop.exit(),
            KeyAction::Move(_) | KeyAction::Sculpt(_) => {}
        }
    }

    /// F: flying on or off (landing puts the player under the camera); without colliders
    /// the camera keeps flying.
    fn toggle_fly(&mut self) {
        if let Some(w) = &mut self.walker {
            w.toggle_fly(&mut self.camera);
        }
    }

    /// Moves the camera for a frame `dt` seconds long whose moving objects stand at animation
    /// time `t`: the mouse turns it; walking, the player steps through the level and the
    /// camera takes its eye; flying, the camera moves itself.
    fn advance(&mut self, dt: f32, t: f64) {
        let mouse = std::mem::take(&mut self.mouse_delta);
        match &mut self.walker {
            Some(w) => {
                w.frame(
                    &self.level.scene,
                    t,
                    &mut self.camera,
                    &self.input,
                    mouse,
                    dt,
                );
            }
            None => self.camera.update(&self.input, mouse, dt),
        }
    }

    /// Draws and presents one frame; returns whether one was presented.
    fn redraw(&mut self) -> anyhow::Result<bool> {
        let now = Instant::now();
        let dt = self
            .last_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f32());
        self.last_frame = Some(now);
        self.reload_if_changed();
        // The time the session will pose the moving objects at in this frame's draw.
        let t = (self.running.as_ref()).map_or(0.0, |r| r.session.animation_time());
        self.advance(dt, t);
        let fps = self.fps.tick(dt);

        let Some(r) = &mut self.running else {
            return Ok(false);
        };
        let inner = r.window.inner_size();
        if inner.width == 0 || inner.height == 0 {
            return Ok(false);
        }
        let camera = self.camera.camera(FOV_Y_DEG.to_radians());
        if let Some((raise, n)) = self.sculpt.due(dt) {
            let done = dab_at_centre(&r.ctx, &mut r.session, &mut self.level, &camera, raise, n)?;
            if let (Some(d), Some(w)) = (done, &mut self.walker)
                && let Err(e) = w.update_heights(&self.level.scene, &self.level.assets, d.entity)
            {
                eprintln!("play: the ground's collision keeps its old heights: {e}");
            }
            self.dab_marked = done.map(|d| d.faces_marked).or(self.dab_marked);
        }
        let (frame, suboptimal) = match r.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => (f, false),
            // Drawn anyway; the surface is configured afresh after presenting.
            wgpu::CurrentSurfaceTexture::Suboptimal(f) => (f, true),
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                r.reconfigure(inner);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                bail!("the window surface reported a validation error")
            }
        };
        let target = frame.texture.create_view(&Default::default());
        let overlay = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(overlay_format(&r.config)),
            ..Default::default()
        });
        let size = UVec2::new(frame.texture.width(), frame.texture.height());
        let request = FrameRequest {
            camera,
            dt,
            schedule: self.schedule,
            size,
        };
        let stats = r.session.draw(&r.ctx, &request, &target)?.stats;
        let lines = self.overlay.then(|| {
            let mut lines = overlay_lines(&stats, fps, self.schedule, &self.camera);
            lines.extend(dab_line(self.dab_marked));
            lines
        });
        (r.overlay).paint(&r.ctx, &r.window, lines.as_deref(), &overlay, size);
        r.window.pre_present_notify();
        r.ctx.queue.present(frame);
        if suboptimal || (r.config.width, r.config.height) != (inner.width, inner.height) {
            r.reconfigure(inner);
        }
        Ok(true)
    }
}

/// Whether raw mouse motion arrives twice while the cursor is confined: winit 0.30's X11
/// backend grabs the pointer with `owner_events`, so the X server sends each raw motion both
/// to the root window's selection and to the grab (winit issues #2846 and #3773; measured
/// under Xvfb: a 2-pixel move gave two 2-pixel `MouseMotion` events).
fn confined_motion_doubles(event_loop: &ActiveEventLoop) -> bool {
    #[cfg(all(
        unix,
        not(any(target_os = "macos", target_os = "ios", target_os = "android"))
    ))]
    {
        winit::platform::x11::ActiveEventLoopExtX11::is_x11(event_loop)
    }
    #[cfg(not(all(
        unix,
        not(any(target_os = "macos", target_os = "ios", target_os = "android"))
    )))]
    {
        let _ = event_loop;
        false
    }
}

/// The format the overlay is drawn in: the surface's, as sRGB (egui writes linear colour and
/// lets the view encode it).
fn overlay_format(config: &wgpu::SurfaceConfiguration) -> wgpu::TextureFormat {
    config.format.add_srgb_suffix()
}

/// A FIFO configuration for `surface`. The renderer draws into the surface's own format,
/// which is plain where the adapter can also view it as sRGB (for the overlay): the renderer
/// writes sRGB-encoded bytes itself, and an sRGB target would encode every pixel again.
fn surface_config(
    surface: &wgpu::Surface<'_>,
    ctx: &GpuContext,
    size: PhysicalSize<u32>,
) -> anyhow::Result<wgpu::SurfaceConfiguration> {
    let (w, h) = (size.width.max(1), size.height.max(1));
    let mut config = surface
        .get_default_config(&ctx.adapter, w, h)
        .ok_or_else(|| anyhow!("the GPU `{}` cannot present to this window", ctx.describe()))?;
    let caps = surface.get_capabilities(&ctx.adapter);
    let views = (ctx.adapter.get_downlevel_capabilities().flags)
        .contains(wgpu::DownlevelFlags::SURFACE_VIEW_FORMATS);
    // A plain format with an sRGB twin, when the overlay can view it as that twin.
    let plain = (caps.formats.iter()).find(|f| !f.is_srgb() && f.add_srgb_suffix() != **f);
    let srgb = caps.formats.iter().find(|f| f.is_srgb());
    if let Some(format) = plain.filter(|_| views).or(srgb) {
        config.format = *format;
    }
    // FIFO is the one mode every surface supports, and it paces the loop to the display.
    config.present_mode = wgpu::PresentMode::Fifo;
    config.usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let srgb = config.format.add_srgb_suffix();
    if srgb != config.format {
        config.view_formats.push(srgb);
    }
    Ok(config)
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(r) => {
                r.window.request_redraw();
                self.running = Some(r);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if let Some(r) = &mut self.running {
            r.overlay.on_window_event(&r.window, &event);
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(r) = &mut self.running {
                    r.reconfigure(size);
                }
            }
            WindowEvent::Focused(false) => {
                self.input = InputState::default();
                self.sculpt.release();
                if self.grabbed {
                    self.set_grab(event_loop, false);
                }
            }
            WindowEvent::MouseInput {
                state: ElementState::Pressed,
                button: MouseButton::Left,
                ..
            } if !self.grabbed => self.set_grab(event_loop, true),
            WindowEvent::KeyboardInput { event, .. } => self.on_key(event_loop, &event),
            WindowEvent::RedrawRequested => match self.redraw() {
                Ok(true) => {
                    self.frames += 1;
                    if self
                        .options
                        .exit_after_frames
                        .is_some_and(|n| self.frames >= n)
                    {
                        event_loop.exit();
                    }
                }
                Ok(false) => {}
                Err(e) => self.fail(event_loop, e),
            },
            _ => {}
        }
    }

    fn device_event(&mut self, _: &ActiveEventLoop, _: DeviceId, event: DeviceEvent) {
        if let DeviceEvent::MouseMotion { delta: (x, y) } = event
            && self.grabbed
        {
            self.mouse_delta += Vec2::new(x as f32, y as f32) * self.motion_scale;
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }
}

#[cfg(test)]
mod tests;
