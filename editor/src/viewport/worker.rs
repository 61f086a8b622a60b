//! The render worker: a thread that owns the viewport's renderer ([`GpuView`]) and draws
//! the newest [`Request`], so the UI never waits for a frame.
//!
//! - The UI hands over a request whenever what it wants drawn changes (camera, size,
//!   document revision, method, debug views; every UI frame in Play). Requests coalesce:
//!   one waits at most, and a newer one replaces it (the level snapshot it carries, if
//!   any, is kept; the frame times add up).
//! - The document goes over as a [`LevelSnapshot`] (its rows and shared assets) at most
//!   once per frame the worker takes: a new snapshot is taken only when none is waiting.
//! - It draws on a device of its own ([`GpuView::beside`], on eframe's adapter; eframe's
//!   own when the driver will not open a second): its errors stay its own, and the window's
//!   paint queues apart from its frames. A finished frame is read back into an image the UI
//!   uploads whole ([`super::picture`]) at its next frame.
//! - A finished [`Frame`] or an error is published and a repaint asked of egui; after a
//!   new request the worker draws [`SETTLE_FRAMES`] frames (one in Play), so probes finish
//!   updating, then sleeps until the next.
//! - Picking is a request too ([`RenderWorker::pick`]), answered from the last frame drawn.
//! - Errors (the renderer's, a panic in it) become the viewport's message; dropping the
//!   worker stops its thread and joins it.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;

use egui::ColorImage;
use glam::{UVec2, Vec2, Vec3};
use texel_render::input::{Camera, ProbeView, Schedule};
use texel_render::readback::FrameIds;
use texel_runtime::frame_plan::RowEdit;
use texel_runtime::load::LoadedLevel;
use texel_scene::assets::AssetLibrary;
use texel_scene::{Level, Scene};

use super::debug::{FacesKey, FrameData, probe_key};
use super::gpu::{GpuView, LastProbes, RenderReport};
use super::overlay;

/// Frames drawn after a new request, so that probes finish updating.
pub const SETTLE_FRAMES: u32 = 6;

/// How long a test helper waits for the worker before calling it stuck.
const WAIT_LIMIT: Duration = Duration::from_secs(600);

/// The document as the worker draws it: rows and assets taken at one revision.
pub struct LevelSnapshot {
    /// The snapshot's number, one more for each snapshot sent (the renderer's revision).
    pub number: u64,
    /// The document (its id and revision) the snapshot was taken from.
    pub document: (u64, u64),
    /// The number of the snapshot before it and a box every change since then fell in (a
    /// terrain stroke), so only the probe faces that see it are updated.
    pub since: Option<(u64, (Vec3, Vec3))>,
    /// The number of the snapshot before it and the changes of entities (by position) every
    /// change since then was (gizmo drags, inspector changes, entities added or deleted), so
    /// only they are taken in ([`GpuView::use_rows`]).
    pub entities: Option<(u64, Vec<RowEdit>)>,
    /// The number of the snapshot before it, when every change since then was the palette's
    /// alone: the session then maps colours again ([`GpuView::use_palette`]) and nothing
    /// is uploaded or shaded again.
    pub palette: Option<u64>,
    /// Where the level resolves its files from.
    pub path: PathBuf,
    /// The rows and settings.
    pub rows: Level,
    /// Meshes, textures and heights (shared, not copied).
    pub assets: AssetLibrary,
}

impl LevelSnapshot {
    fn loaded(self) -> (LoadedLevel, u64, (u64, u64)) {
        let level = LoadedLevel {
            path: self.path,
            scene: Scene::from_level(&self.rows),
            assets: self.assets,
        };
        (level, self.number, self.document)
    }
}

/// What a frame shows, apart from the level: a new one is a new request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The eye.
    pub camera: Camera,
    /// Internal size, pixels.
    pub size: UVec2,
    /// Render method.
    pub schedule: Schedule,
    /// The ground grid drawn.
    pub grid: bool,
    /// The texel-density view.
    pub density: bool,
    /// The eye-sourced pixels debug view (its ids are read back after each frame).
    pub eye_pixels: bool,
    /// The cube-faces debug view (the grid probe's faces are read back).
    pub cube_faces: bool,
    /// Play: the animation clock follows [`Request::time`].
    pub playing: bool,
    /// Frames map to the level's alternate palette (night).
    pub night: bool,
    /// The viewport height the level's pixel scale is measured on (the still view's, so a
    /// moving frame, drawn smaller, keeps its probes); `None` (Play): the frame's own.
    pub face_height: Option<u32>,
}

/// One request of the UI.
pub struct Request {
    /// What to draw.
    pub view: View,
    /// Seconds since the previous request the worker took (the UI's frame times, summed
    /// while requests coalesce).
    pub dt: f32,
    /// In Play, the animation time to pose moving objects at (the physics' clock).
    pub time: f64,
    /// The document, when it changed since the last snapshot.
    pub level: Option<LevelSnapshot>,
}

/// A finished frame.
pub struct Frame {
    /// Frames finished since the worker started; the first is 1.
    pub number: u64,
    /// The request it drew (see [`RenderWorker::submit`]).
    pub request: u64,
    /// Its pixels, as the game presents them.
    pub image: Arc<ColorImage>,
    /// What it shows.
    pub view: View,
    /// The document (id, revision) it shows.
    pub document: (u64, u64),
    /// The animation time it posed moving objects at.
    pub time: f64,
    /// What it cost, and the renderer's totals.
    pub report: RenderReport,
    /// The probes it drew.
    pub probes: Option<LastProbes>,
    /// Whether it was the last of a settle run.
    pub settled: bool,
    ids: Option<FrameIds>,
    faces: Option<Arc<Faces>>,
}

/// The grid probe's faces as read back: whose they are, `n`, six `n × n` RGBA images.
type Faces = (FacesKey, u32, Vec<Vec<u8>>);

impl std::fmt::Debug for Frame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Frame")
            .field("number", &self.number)
            .field("request", &self.request)
            .field("size", &self.image.size)
            .field("view", &self.view)
            .field("document", &self.document)
            .field("time", &self.time)
            .field("settled", &self.settled)
            .finish_non_exhaustive()
    }
}

impl FrameData for Frame {
    fn probes(&self) -> Option<LastProbes> {
        self.probes
    }

    fn frame_ids(&self) -> Result<FrameIds, String> {
        self.ids.clone().ok_or_else(|| "not read back".into())
    }

    fn probe_faces(&self, view: &ProbeView) -> Result<(u32, Vec<Vec<u8>>), String> {
        match self.faces.as_deref() {
            Some((key, n, faces)) if *key == probe_key(view) => Ok((*n, faces.clone())),
            _ => Err("not read back".into()),
        }
    }
}

/// What the UI and the worker share.
struct Shared {
    state: Mutex<State>,
    /// Wakes the worker: a request, a pick, a hold released, stop.
    wake: Condvar,
    /// Wakes waiters on the worker (tests): a frame, an error, the worker at a hold.
    news: Condvar,
}

#[derive(Default)]
struct State {
    pending: Option<Request>,
    /// Requests submitted so far (the newest's number).
    submitted: u64,
    frame: Option<Arc<Frame>>,
    /// The last error and the request it came with; a finished frame clears it.
    error: Option<(u64, String)>,
    /// A pick asked (number, position in the frame 0..1) and the last answer.
    pick: Option<(u64, Vec2)>,
    picked: Option<(u64, Result<Option<u32>, String>)>,
    picks: u64,
    /// The number of the last pick answered (its answer may have been taken since).
    answered: u64,
    held: bool,
    at_hold: bool,
    stop: bool,
    /// Set by the thread as it ends.
    ended: bool,
}

fn lock(shared: &Shared) -> MutexGuard<'_, State> {
    // A panic while the lock was held leaves plain data behind: carry on with it.
    shared
        .state
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The render thread and what it shares with the UI; dropping it stops the thread and
/// joins it.
pub struct RenderWorker {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl RenderWorker {
    /// Starts the thread drawing with `gpu`; `ctx` is asked to repaint when a frame is done.
    pub fn start(gpu: GpuView, ctx: egui::Context) -> Result<RenderWorker, String> {
        let shared = Arc::new(Shared {
            state: Mutex::new(State::default()),
            wake: Condvar::new(),
            news: Condvar::new(),
        });
        let theirs = shared.clone();
        let thread = std::thread::Builder::new()
            .name("texel-editor render".into())
            .spawn(move || {
                Worker::new(gpu).run(&theirs, &ctx);
                lock(&theirs).ended = true;
                theirs.news.notify_all();
            })
            .map_err(|e| format!("cannot start the render thread: {e}"))?;
        Ok(RenderWorker {
            shared,
            thread: Some(thread),
        })
    }

    /// Hands `request` over, replacing a request still waiting (whose level snapshot it
    /// keeps when it has none, and whose frame time it adds); returns its number.
    pub fn submit(&self, mut request: Request) -> u64 {
        let mut st = lock(&self.shared);
        if let Some(old) = st.pending.take() {
            request.dt += old.dt;
            if request.level.is_none() {
                request.level = old.level;
            }
        }
        st.pending = Some(request);
        st.submitted += 1;
        self.shared.wake.notify_all();
        st.submitted
    }

    /// Whether a level snapshot waits to be taken (then the UI sends no newer one yet).
    pub fn snapshot_waiting(&self) -> bool {
        lock(&self.shared)
            .pending
            .as_ref()
            .is_some_and(|r| r.level.is_some())
    }

    /// The newest finished frame, and the last error.
    pub fn newest(&self) -> (Option<Arc<Frame>>, Option<String>) {
        let st = lock(&self.shared);
        let error = st.error.as_ref().map(|e| e.1.clone());
        (st.frame.clone(), error)
    }

    /// Asks for the entity under `at` (0..1 across the last frame); the answer comes with a
    /// later [`RenderWorker::picked`]. Returns the pick's number.
    pub fn pick(&self, at: Vec2) -> u64 {
        let mut st = lock(&self.shared);
        st.picks += 1;
        st.pick = Some((st.picks, at));
        self.shared.wake.notify_all();
        st.picks
    }

    /// The answer to the last pick, once: its number and the entity id (`None`: nothing).
    pub fn picked(&self) -> Option<(u64, Result<Option<u32>, String>)> {
        lock(&self.shared).picked.take()
    }

    /// Test hook: the worker draws nothing more until the returned hold is dropped (a frame
    /// in progress finishes).
    pub fn hold(&self) -> Hold {
        lock(&self.shared).held = true;
        Hold(self.shared.clone())
    }

    /// Test helper: blocks until the newest request submitted was drawn (or failed), and
    /// returns the newest frame.
    pub fn wait_drawn(&self) -> Result<Arc<Frame>, String> {
        let mut st = lock(&self.shared);
        let want = st.submitted;
        loop {
            if let Some((r, e)) = &st.error
                && *r >= want
            {
                return Err(e.clone());
            }
            if let Some(f) = &st.frame
                && f.request >= want
            {
                return Ok(f.clone());
            }
            if st.stop || self.thread.as_ref().is_none_or(JoinHandle::is_finished) {
                return Err("the render thread stopped".into());
            }
            let (next, timeout) = (self.shared.news)
                .wait_timeout(st, WAIT_LIMIT)
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            st = next;
            if timeout.timed_out() {
                return Err("the render thread is stuck".into());
            }
        }
    }

    /// Test helper: blocks until the last pick asked is answered (its answer stays for
    /// [`RenderWorker::picked`] unless the UI took it already); an error at once when no
    /// pick was asked (a click that never reached the viewport would otherwise wait on).
    pub fn wait_picked(&self) -> Result<(), String> {
        let mut st = lock(&self.shared);
        if st.picks == 0 {
            return Err("no pick was asked".into());
        }
        while st.answered < st.picks {
            if st.stop || st.ended {
                return Err("the render thread stopped".into());
            }
            let (next, timeout) = (self.shared.news)
                .wait_timeout(st, WAIT_LIMIT)
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            st = next;
            if timeout.timed_out() {
                return Err("the render thread is stuck".into());
            }
        }
        Ok(())
    }

    /// Whether the thread still runs (it stops only when the worker is dropped).
    pub fn running(&self) -> bool {
        self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }

    /// A handle that tells whether the thread has ended (tests).
    pub fn watch(&self) -> WorkerWatch {
        WorkerWatch(self.shared.clone())
    }
}

impl Drop for RenderWorker {
    fn drop(&mut self) {
        {
            let mut st = lock(&self.shared);
            st.stop = true;
            st.held = false;
        }
        self.shared.wake.notify_all();
        if let Some(t) = self.thread.take() {
            // A panic escaping the thread was already reported by the panic hook.
            let _ = t.join();
        }
    }
}

/// See [`RenderWorker::watch`].
pub struct WorkerWatch(Arc<Shared>);

impl WorkerWatch {
    /// Whether the thread has ended.
    pub fn ended(&self) -> bool {
        lock(&self.0).ended
    }
}

/// See [`RenderWorker::hold`].
pub struct Hold(Arc<Shared>);

impl Hold {
    /// Blocks until the worker waits at the hold (no frame in progress).
    pub fn wait_held(&self) -> Result<(), String> {
        let shared = &self.0;
        let mut st = lock(shared);
        while !st.at_hold {
            if st.stop || st.ended {
                return Err("the render thread stopped".into());
            }
            let (next, timeout) = (shared.news)
                .wait_timeout(st, WAIT_LIMIT)
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            st = next;
            if timeout.timed_out() {
                return Err("the render thread is stuck".into());
            }
        }
        Ok(())
    }
}

impl Drop for Hold {
    fn drop(&mut self) {
        lock(&self.0).held = false;
        self.0.wake.notify_all();
    }
}

/// What the worker does next.
enum Job {
    Pick(u64, Vec2),
    Draw {
        request: Option<Box<Request>>,
        number: u64,
    },
}

/// The thread's own state.
struct Worker {
    gpu: GpuView,
    /// The newest snapshot, loaded, with its number and document revision.
    level: Option<(LoadedLevel, u64, (u64, u64))>,
    /// The request being settled: view, frame time, animation time, number.
    current: Option<(View, f32, f64, u64)>,
    settle: u32,
    playing: bool,
    grid: Option<bool>,
    /// The grid probe's faces last read, handed on with every frame while they are its
    /// probe's (a UI frame may skip the frame that read them).
    faces: Option<Arc<Faces>>,
    frames: u64,
}

impl Worker {
    fn new(gpu: GpuView) -> Worker {
        Worker {
            gpu,
            level: None,
            current: None,
            settle: 0,
            playing: false,
            grid: None,
            faces: None,
            frames: 0,
        }
    }

    fn run(mut self, shared: &Shared, ctx: &egui::Context) {
        while let Some(job) = self.next_job(shared) {
            match job {
                Job::Pick(n, at) => {
                    let size = self.gpu.report.size;
                    let pixel = UVec2::new(
                        ((at.x * size.x as f32) as u32).min(size.x.saturating_sub(1)),
                        ((at.y * size.y as f32) as u32).min(size.y.saturating_sub(1)),
                    );
                    let answer = catch(|| self.gpu.pick(pixel)).map_err(|e| e.0);
                    let mut st = lock(shared);
                    st.picked = Some((n, answer));
                    st.answered = n;
                }
                Job::Draw { request, number } => {
                    let drawn = catch(|| self.draw(request, number));
                    if let Err((_, true)) = drawn {
                        // The session may be half-updated: the next request starts afresh.
                        self.gpu.reset();
                    }
                    let mut st = lock(shared);
                    match drawn {
                        Ok(mut frame) => {
                            self.frames += 1;
                            frame.number = self.frames;
                            st.frame = Some(Arc::new(frame));
                            st.error = None;
                        }
                        Err((e, _)) => {
                            // Not drawn again until the next request.
                            self.settle = 0;
                            st.error = Some((number, e));
                        }
                    }
                }
            }
            shared.news.notify_all();
            ctx.request_repaint();
        }
    }

    /// Waits for something to do: a pick, a new request, a frame left to settle; `None`
    /// when told to stop.
    fn next_job(&mut self, shared: &Shared) -> Option<Job> {
        let mut st = lock(shared);
        loop {
            if st.stop {
                return None;
            }
            if st.held {
                st.at_hold = true;
                shared.news.notify_all();
            } else {
                st.at_hold = false;
                if let Some((n, at)) = st.pick.take() {
                    return Some(Job::Pick(n, at));
                }
                let request = st.pending.take().map(Box::new);
                if request.is_some() || (self.settle > 0 && self.current.is_some()) {
                    let number = match &request {
                        Some(_) => st.submitted,
                        None => self.current.map_or(0, |c| c.3),
                    };
                    return Some(Job::Draw { request, number });
                }
            }
            st = shared
                .wake
                .wait(st)
                .unwrap_or_else(std::sync::PoisonError::into_inner);
        }
    }

    /// Takes `request` (if a new one came) and draws the current one, with what the debug
    /// views want read back.
    fn draw(&mut self, request: Option<Box<Request>>, number: u64) -> Result<Frame, String> {
        if let Some(r) = request {
            self.take(*r, number)?;
        }
        let (view, dt, time, number) = self.current.ok_or("nothing asked yet")?;
        if view.playing {
            self.gpu.set_animation_time(time);
        }
        // The clock the frame is drawn at (a session made by this frame starts at 0).
        let time = self.gpu.animation_time().unwrap_or(0.0);
        let (level, revision, document) = self.level.as_ref().ok_or("no level yet")?;
        let document = *document;
        self.gpu.set_face_height(view.face_height);
        let (size, mut pixels) =
            self.gpu
                .render_pixels(level, *revision, view.camera, view.size, view.schedule, dt)?;
        // Opaque, as the window shows it.
        for p in pixels.chunks_exact_mut(4) {
            p[3] = 255;
        }
        let image =
            ColorImage::from_rgba_premultiplied([size.x as usize, size.y as usize], &pixels);
        self.settle = self.settle.saturating_sub(1);
        let settled = self.settle == 0;
        let ids = (view.eye_pixels)
            .then(|| self.gpu.frame_ids().ok())
            .flatten();
        let faces = self.read_faces(view.cube_faces, settled);
        Ok(Frame {
            number: 0,
            request: number,
            image: Arc::new(image),
            view,
            document,
            time,
            report: self.gpu.report.clone(),
            probes: self.gpu.probes,
            settled,
            ids,
            faces,
        })
    }

    /// Makes `r` the current request: its level snapshot, the grid, the density view and
    /// Play's clock applied.
    fn take(&mut self, r: Request, number: u64) -> Result<(), String> {
        if let Some(snapshot) = r.level {
            let (since, entities) = (snapshot.since, snapshot.entities.clone());
            let palette = snapshot.palette;
            let (level, number, document) = snapshot.loaded();
            let shown = self.gpu.session_revision();
            let region = (since.filter(|(base, _)| shown == Some(*base))).map(|(_, r)| r);
            self.gpu.use_region(region);
            let entities = (entities.filter(|(base, _)| shown == Some(*base))).map(|(_, e)| e);
            self.gpu.use_rows(entities);
            self.gpu.use_palette(palette.is_some() && palette == shown);
            self.level = Some((level, number, document));
        }
        let v = r.view;
        if self.grid != Some(v.grid) {
            let lines = if v.grid {
                overlay::grid_lines()
            } else {
                Vec::new()
            };
            self.gpu.set_lines(&lines);
            self.grid = Some(v.grid);
        }
        if self.gpu.texture_density_view() != v.density {
            self.gpu.set_texture_density_view(v.density)?;
        }
        self.gpu.set_night(v.night);
        if self.playing != v.playing {
            self.gpu.set_animating(v.playing);
            self.playing = v.playing;
        }
        // In Play every UI frame asks for a frame of its own time.
        self.settle = if v.playing { 1 } else { SETTLE_FRAMES };
        self.current = Some((v, r.dt, r.time, number));
        Ok(())
    }

    /// The grid probe's faces while the cube-faces view is on: read back when the probe
    /// changed or the frame settled, else those read last.
    fn read_faces(&mut self, on: bool, settled: bool) -> Option<Arc<Faces>> {
        let grid = self.gpu.probes.map(|p| p.grid).filter(|_| on);
        let Some(grid) = grid else {
            self.faces = None;
            return None;
        };
        let key = probe_key(&grid);
        let same = self.faces.as_ref().is_some_and(|f| f.0 == key);
        if !same || settled {
            self.faces = (self.gpu.probe_faces(&grid).ok()).map(|(n, f)| Arc::new((key, n, f)));
        }
        self.faces.clone()
    }
}

/// Runs `f`, turning a panic into an error (`true`: it was a panic).
fn catch<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, (String, bool)> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r.map_err(|e| (e, false)),
        Err(panic) => {
            let what = (panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown cause".into());
            Err((format!("the renderer panicked: {what}"), true))
        }
    }
}
