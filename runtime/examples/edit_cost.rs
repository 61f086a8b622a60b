//! What one editor edit costs on a large level, headless: a level is opened in a session at
//! the editor's reduced viewport size (a quarter of a 1280×720 viewport by default), drawn
//! until its probes settle, then one entity near the camera is moved a little (a gizmo drag
//! step) or recoloured (an inspector change), and the wall time from the edit to the next
//! finished frame is printed, with its parts. Reported, never asserted.
//!
//! ```sh
//! cargo run -p texel_runtime --bin texel-run -- gen --count 10000 --mesh assets/meshes/crate.glb --mesh assets/meshes/arch.glb --out /tmp/scale_town10000.ron
//! cargo run -p texel_runtime --example edit_cost -- /tmp/scale_town10000.ron
//! ```
//!
//! Options: `--size WxH` (default 320x180), `--steps N` (edits measured, default 5),
//! `--lit` (the entity edited may stand in a point light's reach, where its shadow may
//! fall anywhere; by default it stands outside every light's reach),
//! `--region` (the edit goes through `Session::update_level_region`: the level prepared
//! and uploaded again, the faces that may see it marked; the editor's path before
//! `Session::update_entities`), `--full` (through `Session::set_level`), `--add-delete`
//! (the entity deleted on even steps and put back on odd ones, as an editor's delete and
//! its undo: `Session::edit_rows`, or `Session::set_level` with `--full`), `--occlusion`
//! (stable faces captured in part leave out what lies behind what they hold, instead of
//! drawing everything that may cover their rectangle: `Renderer::set_capture_occlusion`),
//! `--occlusion-ab` (occlusion on for steps 0 and 1, off for 2 and 3, and so on: medians of
//! each printed apart), `--far-ab` (likewise, an edit keeping the eye's far faces it does not
//! reach, or forgetting them all: `Renderer::set_edit_keeps_far_faces`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use glam::{UVec2, Vec3};
use texel_render::context::GpuContext;
use texel_render::input::Schedule;
use texel_runtime::frame_plan::RowEdit;
use texel_runtime::load::{LoadedLevel, load_level};
use texel_runtime::session::{FrameRequest, Session};
use texel_scene::{Geometry, Material, PointLight, Transform};

struct Options {
    level: PathBuf,
    size: UVec2,
    steps: u32,
    mode: Mode,
    lit: bool,
    /// Deletes and puts back the entity instead of moving and recolouring it.
    add_delete: bool,
    /// Stable faces captured in part leave out what lies behind what they hold.
    occlusion: bool,
    /// Occlusion on and off by pairs of steps.
    occlusion_ab: bool,
    /// Far faces kept through the edit and not by pairs of steps.
    far_ab: bool,
}

/// How the edit reaches the session.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// `Session::update_entities`: the entity alone, in place.
    Entity,
    /// `Session::update_level_region`: the level prepared and uploaded again, the faces
    /// that may see the entity's box (and its sun shadows) marked.
    Region,
    /// `Session::set_level`: prepared, uploaded and planned afresh.
    Full,
}

fn options() -> Result<Options> {
    let mut args = std::env::args().skip(1);
    let mut o = Options {
        level: PathBuf::new(),
        size: UVec2::new(320, 180),
        steps: 5,
        mode: Mode::Entity,
        lit: false,
        add_delete: false,
        occlusion: false,
        occlusion_ab: false,
        far_ab: false,
    };
    while let Some(a) = args.next() {
        match a.as_str() {
            "--size" => {
                let s = args.next().context("--size needs WxH")?;
                let (w, h) = s.split_once('x').context("--size needs WxH")?;
                o.size = UVec2::new(w.parse()?, h.parse()?);
            }
            "--steps" => o.steps = args.next().context("--steps needs N")?.parse()?,
            "--full" => o.mode = Mode::Full,
            "--region" => o.mode = Mode::Region,
            "--lit" => o.lit = true,
            "--add-delete" => o.add_delete = true,
            "--occlusion" => o.occlusion = true,
            "--occlusion-ab" => o.occlusion_ab = true,
            "--far-ab" => o.far_ab = true,
            _ if a.starts_with("--") => bail!("unknown option {a}"),
            _ => o.level = PathBuf::from(a),
        }
    }
    if o.level.as_os_str().is_empty() {
        bail!(
            "usage: edit_cost LEVEL [--size WxH] [--steps N] [--full | --region] [--lit] [--add-delete] [--occlusion | --occlusion-ab] [--far-ab]"
        );
    }
    Ok(o)
}

/// The level index of the entity with geometry nearest to `eye` in front of it (and, unless
/// `lit`, outside every point light's reach, by its position).
fn entity_in_view(level: &LoadedLevel, eye: Vec3, forward: Vec3, lit: bool) -> Option<usize> {
    let lights: Vec<(Vec3, f32)> = (level.scene.entities())
        .filter_map(|e| {
            let w = level.scene.world();
            let p = w.get::<&PointLight>(e).ok()?;
            let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
            Some((t.translation, p.radius))
        })
        .collect();
    let w = level.scene.world();
    let mut best: Option<(f32, usize)> = None;
    for (i, e) in level.scene.entities().enumerate() {
        let Ok(g) = w.get::<&Geometry>(e) else {
            continue;
        };
        if matches!(&*g, Geometry::Plane { .. }) {
            continue;
        }
        let t = w.get::<&Transform>(e).map(|t| *t).unwrap_or_default();
        let reach = |&(p, r): &(Vec3, f32)| p.distance(t.translation) < r + 3.0;
        if !lit && lights.iter().any(reach) {
            continue;
        }
        let d = t.translation - eye;
        if d.dot(forward) < 2.0 {
            continue;
        }
        let dist = d.length();
        if best.is_none_or(|b| dist < b.0) {
            best = Some((dist, i));
        }
    }
    best.map(|b| b.1)
}

fn main() -> Result<()> {
    let o = options()?;
    let t = Instant::now();
    let mut level = load_level(&o.level).map_err(|e| anyhow!("{e}"))?;
    println!(
        "load: {:.0} ms ({} entities)",
        ms(t),
        level.scene.entities().count()
    );
    let ctx = GpuContext::headless().map_err(|e| anyhow!("{e}"))?;
    println!("adapter: {}", ctx.adapter.get_info().name);
    let t = Instant::now();
    let mut session = Session::headless(&ctx, &level, o.size, 1.0)?;
    println!("session: {:.0} ms", ms(t));
    let camera = session.start_camera();
    let request = FrameRequest {
        camera,
        dt: 1.0 / 30.0,
        schedule: Schedule::Ours,
        size: o.size,
    };
    let t = Instant::now();
    for _ in 0..12 {
        session.draw_offscreen(&ctx, &request)?;
    }
    println!("12 settling frames: {:.0} ms", ms(t));
    let t = Instant::now();
    let (drawn, _) = session.draw_offscreen(&ctx, &request)?;
    println!(
        "a settled frame: {:.1} ms, faces captured {}",
        ms(t),
        drawn.stats.counters.faces_captured
    );
    print_passes(&drawn.stats);
    let index = entity_in_view(&level, camera.position, camera.forward, o.lit)
        .context("no entity in front of the start camera")?;
    let (lo, hi) = bounds(&session, index);
    println!(
        "editing entity {index}: bounds {lo:.2}..{hi:.2}, grid probe at {:.2}",
        drawn.input.grid.origin
    );
    let t = Instant::now();
    let prepared = texel_runtime::frame_plan::PreparedLevel::new(&level);
    println!("  PreparedLevel::new: {:.0} ms", ms(t));
    let t = Instant::now();
    texel_render::validate::scene(&ctx.device.limits(), prepared.scene())?;
    println!("  validate: {:.0} ms", ms(t));
    let t = Instant::now();
    let gpu = texel_render::gpu_scene::GpuScene::upload(&ctx, prepared.scene())?;
    println!("  GpuScene::upload: {:.0} ms", ms(t));
    drop(gpu);
    let (mut edits, mut settled) = (Vec::new(), Vec::new());
    let (mut edit_passes, mut settled_passes) = (Vec::new(), Vec::new());
    let mut removed = None;
    let mut ab: [Vec<f64>; 2] = Default::default();
    for step in 0..o.steps {
        let at = (index, step);
        let a = (step / 2).is_multiple_of(2);
        let occlusion = o.occlusion && (!o.occlusion_ab || a);
        session.renderer_mut().set_capture_occlusion(occlusion);
        session
            .renderer_mut()
            .set_edit_keeps_far_faces(!o.far_ab || a);
        let (edit, stats) = edit_step(
            &ctx,
            &mut session,
            &mut level,
            &o,
            at,
            &request,
            &mut removed,
        )?;
        edits.push(edit);
        ab[usize::from(!(step / 2).is_multiple_of(2))].push(edit);
        edit_passes.push(stats);
        // Settle again, then time a frame with nothing to catch up on.
        for _ in 0..4 {
            session.draw_offscreen(&ctx, &request)?;
        }
        let t = Instant::now();
        let (drawn, _) = session.draw_offscreen(&ctx, &request)?;
        settled.push(ms(t));
        settled_passes.push(drawn.stats);
    }
    println!(
        "median over {} edits: edit to next finished frame {:.0} ms; settled frame between them {:.0} ms",
        o.steps,
        median(&mut edits),
        median(&mut settled)
    );
    if o.occlusion_ab || o.far_ab {
        println!(
            "  A (steps 0, 1, 4, 5, ...): edit to frame {:.0} ms (median of {}); B: {:.0} ms (median of {})",
            median(&mut ab[0]),
            ab[0].len(),
            median(&mut ab[1]),
            ab[1].len()
        );
    }
    for pass in ["capture", "shade"] {
        let mut e: Vec<f64> = edit_passes.iter().map(|s| s.pass_ms(pass)).collect();
        let mut q: Vec<f64> = settled_passes.iter().map(|s| s.pass_ms(pass)).collect();
        println!(
            "  {pass}: {:.0} ms after an edit, {:.0} ms settled (medians)",
            median(&mut e),
            median(&mut q)
        );
    }
    Ok(())
}

/// Changes the entity at `index` for `step`: moved on even steps and recoloured on odd
/// ones, or (`o.add_delete`) deleted into `removed` on even steps and put back on odd ones.
fn change(
    level: &mut LoadedLevel,
    o: &Options,
    (index, step): (usize, u32),
    removed: &mut Option<texel_scene::EntityRow>,
) -> Result<RowEdit> {
    if o.add_delete {
        if let Some(row) = removed.take() {
            level.scene.spawn_at(index, row);
            return Ok(RowEdit::Insert(index));
        }
        let entity = level.scene.entities().nth(index).context("entity")?;
        *removed = Some(level.scene.despawn(entity).context("row")?);
        return Ok(RowEdit::Remove(index));
    }
    let entity = level.scene.entities().nth(index).context("entity")?;
    let mut row = level.scene.row(entity).context("row")?;
    if step.is_multiple_of(2) {
        let tr = row.transform.get_or_insert_with(Transform::default);
        tr.translation.x += 0.25;
    } else {
        let m = row.material.get_or_insert_with(Material::default);
        m.albedo = Vec3::new(0.2 + 0.1 * step as f32, 0.5, 0.3);
    }
    level
        .scene
        .set_row(entity, row)
        .map_err(|e| anyhow!("{e}"))?;
    Ok(RowEdit::Set(index))
}

/// Edit `step` of the entity at `index` ([`change`]), taken in as `o.mode` says, and the
/// frame after it; returns the wall time from the edit to the finished frame, ms, and the
/// frame's stats.
fn edit_step(
    ctx: &GpuContext,
    session: &mut Session,
    level: &mut LoadedLevel,
    o: &Options,
    (index, step): (usize, u32),
    request: &FrameRequest,
    removed: &mut Option<texel_scene::EntityRow>,
) -> Result<(f64, texel_render::stats::FrameStats)> {
    let mut before = bounds(session, index);
    let edit = change(level, o, (index, step), removed)?;
    if removed.is_none() {
        // Put back: where it now stands.
        let (lo, hi) = bounds_in(texel_runtime::frame_plan::scene_input(level), index);
        before = (before.0.min(lo), before.1.max(hi));
    }
    let t = Instant::now();
    let how = match o.mode {
        Mode::Full => {
            session.set_level(ctx, level)?;
            "set_level".to_owned()
        }
        Mode::Region => {
            let (lo, hi) = before;
            let (lo, hi) = texel_runtime::session::shadow_extended(session.scene(), lo, hi);
            let marked = session.update_level_region(ctx, level, lo, hi)?;
            format!("update_level_region, {marked} faces marked")
        }
        Mode::Entity => format!("{:?}", session.edit_rows(ctx, level, &[edit])?),
    };
    let update = ms(t);
    let t2 = Instant::now();
    let (drawn, _) = session.draw_offscreen(ctx, request)?;
    let frame = ms(t2);
    let edit_to_frame = ms(t);
    print_passes(&drawn.stats);
    let stable: Vec<String> = (drawn.input.captures.iter())
        .filter(|c| c.slot != texel_probes::probe_set::Slot::Eye)
        .map(|c| {
            let part = (drawn.input.partial.iter()).find(|r| r.slot == c.slot && r.face == c.face);
            match part {
                Some(r) => format!(
                    "{:?} {}x{} of {}",
                    c.face,
                    r.rect.x1 - r.rect.x0,
                    r.rect.y1 - r.rect.y0,
                    c.face_resolution
                ),
                None => format!("{:?} whole {}", c.face, c.face_resolution),
            }
        })
        .collect();
    println!("  stable faces captured: {}", stable.join(", "));
    println!(
        "edit {step} ({}, {how}): update {update:.1} ms, frame {frame:.1} ms, edit to frame {edit_to_frame:.1} ms, faces captured {}",
        match edit {
            RowEdit::Insert(_) => "put back",
            RowEdit::Remove(_) => "delete",
            _ if step.is_multiple_of(2) => "move",
            _ => "colour",
        },
        drawn.stats.counters.faces_captured,
    );
    Ok((edit_to_frame, drawn.stats))
}

/// The median of `v` (0 for none).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// The world bounds of object `index`'s entity as the session's scene holds it.
fn bounds(session: &Session, index: usize) -> (Vec3, Vec3) {
    bounds_in(session.scene().clone(), index)
}

/// The world bounds of the entity at `index` in `scene`.
fn bounds_in(scene: texel_render::input::SceneInput, index: usize) -> (Vec3, Vec3) {
    let id = texel_runtime::frame_plan::entity_id(index);
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for o in scene.objects.iter().filter(|o| o.id == id) {
        for p in &o.mesh.positions {
            let w = o.transform.transform_point3(*p);
            lo = lo.min(w);
            hi = hi.max(w);
        }
    }
    (lo, hi)
}

/// The passes of a frame that took a millisecond or more, and the renderer's wall time.
fn print_passes(stats: &texel_render::stats::FrameStats) {
    let passes: Vec<String> = (stats.passes.iter())
        .filter(|p| p.ms >= 1.0)
        .map(|p| format!("{} {:.0}", p.pass, p.ms))
        .collect();
    println!(
        "  passes: {} (renderer {:.0} ms, texels shaded {}, of them the eye's {}; objects drawn {}, of them the eye's {}; left out behind what stable faces held {})",
        passes.join(", "),
        stats.frame_ms,
        stats.counters.texels_shaded,
        stats.counters.eye_texels_shaded,
        stats.counters.objects_captured,
        stats.counters.eye_objects_captured,
        stats.counters.objects_occluded
    );
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
