//! The plain data the renderer consumes: what the scene is ([`SceneInput`], uploaded when it
//! changes) and what to draw this frame ([`FrameInput`]). Built by the runtime from the hecs
//! world and the probe system, or by hand in tests.

use std::sync::Arc;

use glam::{Mat4, UVec2, Vec2, Vec3, Vec4};
pub use texel_geom::TextureRef;
pub use texel_geom::texture::Image;
use texel_geom::{SurfaceMaps, TriMesh};
use texel_probes::cube::{Face, FaceMask};
use texel_probes::probe_set::{Role, Slot};

/// Near and far planes of a capture, world units. Beyond `CAPTURE_FAR` is sky. Here rather
/// than in the capture pass that uses them, so the input (a camera's default far plane)
/// does not reach up into a pass.
pub const CAPTURE_NEAR: f32 = 0.02;
/// See [`CAPTURE_NEAR`].
pub const CAPTURE_FAR: f32 = 500.0;

/// How a surface is shaded.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialInput {
    /// Linear RGB base colour.
    pub albedo: Vec3,
    /// Linear RGB emitted light (drawn unlit).
    pub emissive: Vec3,
    /// Whether it blocks shadow rays.
    pub casts_shadows: bool,
    /// Whether outlines are drawn on it.
    pub outlined: bool,
    /// Textures, sampled at the mesh's UVs × `maps.uv_scale`; a mesh part's own textures
    /// (glTF) are used where these have none.
    pub maps: SurfaceMaps,
    /// Index into [`SceneInput::terrains`]: the surface is coloured as that terrain (its
    /// world pixel grid, bands, gradient and displacement) instead of by albedo and texture.
    pub terrain: Option<usize>,
    /// A highlight: strength (0: none) and shininess (the Blinn-Phong exponent), seen from
    /// the probe that captures the texel (texel splatting) or the camera (the baselines).
    pub specular: Vec2,
}

impl Default for MaterialInput {
    fn default() -> Self {
        MaterialInput {
            albedo: Vec3::splat(0.7),
            emissive: Vec3::ZERO,
            casts_shadows: true,
            outlined: true,
            maps: SurfaceMaps::default(),
            terrain: None,
            specular: Vec2::ZERO,
        }
    }
}

/// A heightmap terrain's colouring (the mesh itself is an ordinary object).
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainInput {
    /// World position of height sample (0, 0) at height 0: the terrain's −X −Z corner.
    pub corner: Vec3,
    /// World extent along X and Z.
    pub size: glam::Vec2,
    /// Samples along X and Z.
    pub samples: glam::UVec2,
    /// Heights (world units above `corner`), rows along X, one row per Z sample.
    pub heights: Arc<Vec<f32>>,
    /// Height that normalised elevation 1 stands for.
    pub max_height: f32,
    /// `(normalised elevation, linear RGB)` stops, ascending.
    pub gradient: Vec<(f32, Vec3)>,
    /// Displacement texture (red channel), with its strength and world tile size.
    pub displacement: Option<(texel_geom::TextureRef, f32, f32)>,
    /// Paint layer (RGBA8, sRGB colour, alpha = cover) over the extent, blended over the
    /// gradient colour of each terrain pixel at the pixel's centre.
    pub paint: Option<Arc<texel_geom::texture::Image>>,
    /// Terrain pixels per world unit in the nearest band.
    pub pixel_density: f32,
    /// Distance within which the nearest band applies.
    pub band_distance: f32,
    /// Share of a band over which cells are promoted to the next band (Bayer pattern).
    pub band_transition: f32,
}

/// One drawable object: a mesh placed in the world. Its `id` is unique per entity.
#[derive(Debug, Clone)]
pub struct ObjectInput {
    /// Object-space mesh.
    pub mesh: Arc<TriMesh>,
    /// Object → world.
    pub transform: Mat4,
    /// Surface.
    pub material: MaterialInput,
    /// Entity id, unique, non-zero (0 means sky).
    pub id: u32,
}

/// A directional light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunInput {
    /// Direction the light travels (normalised by the renderer).
    pub direction: Vec3,
    /// Linear RGB colour × intensity.
    pub colour: Vec3,
}

/// A point light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLightInput {
    /// World position.
    pub position: Vec3,
    /// Linear RGB colour × intensity.
    pub colour: Vec3,
    /// Distance at which it fades to zero.
    pub radius: f32,
}

/// Everything static about the scene; upload again when it changes.
#[derive(Debug, Clone, Default)]
pub struct SceneInput {
    /// Drawable objects.
    pub objects: Vec<ObjectInput>,
    /// Directional lights.
    pub suns: Vec<SunInput>,
    /// Point lights.
    pub points: Vec<PointLightInput>,
    /// Terrains the objects' materials refer to.
    pub terrains: Vec<TerrainInput>,
    /// Indices into `objects` of the objects that move (an animator drives them). They are
    /// never captured into the probes nor cast shadows from the static BVH; the moving pass
    /// draws them each frame at [`FrameInput::poses`], their pixels cut on a grid fixed to
    /// the object. Their `transform` is the base pose the poses start from.
    pub animated: Vec<usize>,
    /// Sprites: pictures drawn one instance each after the splats (`passes::sprites`),
    /// never captured into the probes.
    pub sprites: Vec<SpriteInput>,
}

/// How a sprite's quad turns toward its viewer (the grid probe's origin, or the camera in
/// [`SpriteFacing::Camera`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpriteBillboard {
    /// Faces the viewer fully.
    Spherical,
    /// Turns about the world's Y axis only.
    #[default]
    Upright,
    /// Does not turn: the rotation's XY plane, facing its +Z.
    Fixed,
}

/// What sprites turn toward.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpriteFacing {
    /// The grid probe's origin (the previous probe's during a crossfade, with the splats'
    /// Bayer pattern), their anchors snapped to its texels: world-locked inside a cell.
    #[default]
    Probe,
    /// The camera, as screen-space sprite renderers do (kept to compare against): the quad
    /// lies in the view plane and turns with every camera move.
    Camera,
}

/// One sprite: a sheet cut into frames, placed at a point, turned toward the viewer.
#[derive(Debug, Clone)]
pub struct SpriteInput {
    /// Entity id (picking, the evaluator's ids).
    pub id: u32,
    /// World point of the pivot.
    pub position: Vec3,
    /// The fixed quad's orientation, and the front 8 directions are measured from.
    pub rotation: glam::Quat,
    /// World size of the quad; `None`: matched, one sprite pixel per probe texel at the
    /// sprite's distance from the probe.
    pub size: Option<glam::Vec2>,
    /// The point the position places, in fractions of the frame (x right, y down).
    pub pivot: glam::Vec2,
    /// How the quad turns.
    pub billboard: SpriteBillboard,
    /// The sheet (RGBA8, alpha below one half is empty).
    pub sheet: Arc<texel_geom::texture::Image>,
    /// Frame size in pixels (divides the sheet).
    pub frame_size: UVec2,
    /// 8 directions: a frame's direction `d` version is `d` frame rows further down.
    pub eight_directions: bool,
    /// Tangent-space normal map, the sheet's size.
    pub normal_map: Option<Arc<texel_geom::texture::Image>>,
    /// Relief: depth map (red: 0 at the quad, 255 at the depth) and its depth in world units.
    pub relief: Option<(Arc<texel_geom::texture::Image>, f32)>,
    /// Refraction through the relief: back depth map and index ratio (outside / inside).
    pub refraction: Option<(Arc<texel_geom::texture::Image>, f32)>,
    /// Whether outlines are drawn at its alpha edges.
    pub outlined: bool,
    /// Whether it blocks shadow rays toward the world.
    pub casts_shadows: bool,
    /// The frame shown until a [`SpriteState`] says otherwise (direction 0's).
    pub frame: u32,
}

/// A sprite's state this frame, for a sprite that moves or animates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpriteState {
    /// Index into [`SceneInput::sprites`].
    pub sprite: usize,
    /// World point of its pivot.
    pub position: Vec3,
    /// Frame (direction 0's; the renderer adds the direction its viewer sees).
    pub frame: u32,
}

/// A perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Near plane distance.
    pub near: f32,
    /// Far plane distance. By default the probes' capture range
    /// ([`CAPTURE_FAR`]): past it they hold only the sky, so a farther
    /// plane would show nothing more, and a nearer one would cut off what they hold.
    pub far: f32,
    /// `Some(h)`: an orthographic camera whose view is `h` world units tall (`fov_y` unused).
    pub ortho_height: Option<f32>,
}

impl Camera {
    /// A camera at `position` looking along `forward` with a 60° vertical field of view.
    pub fn looking(position: Vec3, forward: Vec3) -> Self {
        Camera {
            position,
            forward: forward.normalize(),
            fov_y: 60f32.to_radians(),
            near: 0.05,
            far: CAPTURE_FAR,
            ortho_height: None,
        }
    }

    /// A camera from yaw and pitch in degrees (yaw 0 looks along −Z, positive yaw turns
    /// toward −X; positive pitch looks up), as the level's player start stores them.
    pub fn from_yaw_pitch(position: Vec3, yaw_deg: f32, pitch_deg: f32) -> Self {
        let (y, p) = (yaw_deg.to_radians(), pitch_deg.to_radians());
        let forward = Vec3::new(-y.sin() * p.cos(), p.sin(), -y.cos() * p.cos());
        Self::looking(position, forward)
    }

    /// The up vector of the view ([`view_up`] of its direction).
    pub fn up(&self) -> Vec3 {
        view_up(self.forward)
    }

    /// World → view matrix (right-handed, [`Camera::up`] up).
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_to_mat4(self.position, self.forward, self.up())
    }

    /// View → clip matrix (depth 0 at the near plane, 1 at the far one).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        self.projection_between(aspect, self.near, self.far)
    }

    /// View → clip matrix with reversed depth: 1 at the near plane, 0 at the far one. A float
    /// depth buffer then keeps about the same relative precision at every distance (the
    /// forward mapping spends it all near the camera), which the splat's per-texel tie-break
    /// between overlapping coplanar quads needs far away.
    pub fn projection_reverse_z(&self, aspect: f32) -> Mat4 {
        self.projection_between(aspect, self.far, self.near)
    }

    /// The projection mapping view depth `z0` to NDC depth 0 and `z1` to 1.
    fn projection_between(&self, aspect: f32, z0: f32, z1: f32) -> Mat4 {
        // wgpu's NDC: depth 0..1, Y up (the DirectX convention).
        use glam::camera::rh::proj::directx;
        match self.ortho_height {
            Some(h) => {
                let (hw, hh) = (h * 0.5 * aspect, h * 0.5);
                directx::orthographic(-hw, hw, -hh, hh, z0, z1)
            }
            None => directx::perspective(self.fov_y, aspect, z0, z1),
        }
    }
}

/// The up vector of a view along the unit `forward`: world +Y, or +Z when looking (nearly)
/// straight up or down.
pub fn view_up(forward: Vec3) -> Vec3 {
    if forward.y.abs() > 0.999 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// How the probe texels are scheduled and drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Schedule {
    /// Ours: cached shading, per-texel culling, eye texels the grid probe covers skipped.
    #[default]
    Ours,
    /// The paper's reference schedule: every texel of every drawn face splatted.
    Paper,
}

/// How probe texels reach the pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Display {
    /// Texel splatting: every visible texel drawn as a world-space quad.
    #[default]
    Splat,
    /// Texel marching: per pixel, the view ray marched through the stable probes' faces.
    March,
}

/// A probe as drawn this frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeView {
    /// The part it plays.
    pub role: Role,
    /// Where its data lives.
    pub slot: Slot,
    /// Its origin.
    pub origin: Vec3,
    /// Texels per face edge.
    pub face_resolution: u32,
    /// Faces to splat.
    pub draw: FaceMask,
    /// Faces holding data captured from this origin once this frame's captures are done
    /// (shading looks across seams only into these).
    pub valid: FaceMask,
    /// `Some` for an orthographic probe: one face (+X) along the frame, not a cube.
    pub ortho: Option<texel_probes::ortho::OrthoFrame>,
    /// Planes `(normal, d)` (`dot(normal, p) + d = 0`) of the big flat faces that pass near
    /// this stable probe (`texel_probes::placement::near_faces`): its texels on them are
    /// laid flat (`shaders/cull.wgsl`). Unused entries are zero.
    pub near_faces: [Vec4; MAX_NEAR_FACES],
}

/// Most near faces a probe hands the cull pass ([`ProbeView::near_faces`]).
pub const MAX_NEAR_FACES: usize = 4;

/// One face to capture and shade before drawing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaptureInput {
    /// Destination slot.
    pub slot: Slot,
    /// The face.
    pub face: Face,
    /// Probe origin to capture from.
    pub origin: Vec3,
    /// Texels per face edge.
    pub face_resolution: u32,
    /// `Some` for an orthographic probe's face (see [`ProbeView::ortho`]).
    pub ortho: Option<texel_probes::ortho::OrthoFrame>,
}

/// The look of the level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// Linear RGB sky colour.
    pub sky: Vec3,
    /// Linear RGB ambient light.
    pub ambient: Vec3,
    /// OKLab lightness bands.
    pub bands: u32,
    /// Haze density per world unit (0 = none).
    pub haze: f32,
}

/// What to draw this frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameInput {
    /// The camera.
    pub camera: Camera,
    /// Output size in pixels.
    pub size: UVec2,
    /// Size the splats are drawn at before a nearest upscale to `size` (at most `size`,
    /// same aspect). Art pixels span several screen pixels, so drawing them at a lower
    /// internal resolution loses nothing of the look, and saves per-pixel work.
    pub internal_size: UVec2,
    /// Level look.
    pub look: Look,
    /// The eye probe.
    pub eye: ProbeView,
    /// The grid probe: the probe a crossfade runs toward, which is the camera cell's probe
    /// except while `filling_ahead`.
    pub grid: ProbeView,
    /// The previous probe, during a crossfade.
    pub previous: Option<ProbeView>,
    /// Crossfade progress: 0 = previous draws everything, 1 = grid does.
    pub fade_t: f32,
    /// Whether the frame comes before a crossing and is drawn as the crossing's first frame
    /// will be: `grid` is then the next cell's probe, filling behind the camera cell's probe,
    /// which draws as `previous` and owns every pixel (`fade_t` 0). See
    /// [`FrameInput::cell_probe`].
    pub filling_ahead: bool,
    /// The grid probe of the cell the camera is heading into, whose faces are being
    /// captured ahead of the crossing (in the free stable slot); not drawn.
    pub prefetch: Option<ProbeView>,
    /// Faces to capture and shade first.
    pub captures: Vec<CaptureInput>,
    /// Scheduling and culling method.
    pub schedule: Schedule,
    /// Whether the grid probe has every face it needs; while it does not, the previous
    /// probe keeps the pixels whose grid face is missing during a crossfade.
    pub grid_complete: bool,
    /// Where the animated objects ([`SceneInput::animated`]) are this frame: object index
    /// and object → world transform. An animated object without a pose stays at its base
    /// transform.
    pub poses: Vec<Pose>,
    /// Stable-probe faces to light again without capturing them (a moving object's shadow
    /// may have come or gone there); faces captured this frame are lit anyway, and eye faces
    /// are lit as the view needs them.
    pub relight: Vec<Relight>,
    /// Stable-probe faces captured this frame after a scene edit that can have changed
    /// only part of them ([`PartialFace`]): the rest keeps what its last capture at the same
    /// origin held and its light, which it equals. Faces not captured are ignored.
    pub partial: Vec<PartialFace>,
    /// Sprites that moved or changed frame since the last frame (the others keep theirs).
    pub sprites: Vec<SpriteState>,
    /// The eye probe's far field (`crate::far_field`): `None` draws everything into the eye
    /// every frame.
    pub far_field: Option<crate::far_field::FarFieldInput>,
}

impl FrameInput {
    /// The grid probe of the camera's cell: `previous` while the next cell's probe fills
    /// ahead of a crossing ([`FrameInput::filling_ahead`]), else `grid`. The eye probe's
    /// terrain bands are measured from its origin.
    pub fn cell_probe(&self) -> &ProbeView {
        match (&self.previous, self.filling_ahead) {
            (Some(p), true) => p,
            _ => &self.grid,
        }
    }
}

/// Texels of a stable probe's face to light again (see [`FrameInput::relight`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Relight {
    /// The probe's slot.
    pub slot: Slot,
    /// The face.
    pub face: Face,
    /// The texels.
    pub rect: texel_probes::visibility::TexelRect,
    /// Of those, only the texels whose light this says may have changed (`None`: all).
    pub filter: Option<LightFilter>,
}

/// A stable face an edit changed in part ([`FrameInput::partial`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PartialFace {
    /// The probe's slot.
    pub slot: Slot,
    /// The face.
    pub face: Face,
    /// The texels captured again and lit whole: where the edit's old or new geometry may be
    /// seen, with a margin for the neighbours a texel reads (empty when none).
    pub rect: texel_probes::visibility::TexelRect,
    /// The texels that may be lit again: `rect` and where the edit's shadows and a changed
    /// light's reach project to.
    pub light: texel_probes::visibility::TexelRect,
    /// Which texels of `light` outside `rect` are lit again.
    pub filter: LightFilter,
    /// The objects (by index in the scene) the edits since the face was last captured
    /// rewrote in place: where the face showed none of them, what it holds bounds what the
    /// rest can show, and the capture leaves out what lies behind it
    /// ([`crate::passes::occlusion`]). `None`: not known (objects added or removed), every
    /// object that may cover `rect` is drawn.
    pub edited: Option<Vec<u32>>,
}

/// Where an edit can have changed the light on surfaces it did not move: a texel whose
/// surface stayed is lit again when a ray from it toward a light that reaches it meets one
/// of `casters` (the edited objects' old and new bounds: a shadow came or went), or when it
/// lies in one of `lit` (a changed light's reach). At most [`LightFilter::MAX_BOXES`] boxes
/// in all; more are joined.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LightFilter {
    /// Boxes (min, max) whose shadows changed.
    pub casters: Vec<(Vec3, Vec3)>,
    /// Boxes (min, max) where the light itself changed.
    pub lit: Vec<(Vec3, Vec3)>,
}

impl LightFilter {
    /// The most boxes a shade job carries (its record's room).
    pub const MAX_BOXES: usize = 4;

    /// The filter of both `self` and `other`: their boxes, the nearest joined while there
    /// are more than [`LightFilter::MAX_BOXES`].
    pub fn union(&self, other: &LightFilter) -> LightFilter {
        let mut out = LightFilter {
            casters: [self.casters.clone(), other.casters.clone()].concat(),
            lit: [self.lit.clone(), other.lit.clone()].concat(),
        };
        while out.casters.len() + out.lit.len() > Self::MAX_BOXES {
            let list = if out.casters.len() >= out.lit.len() {
                &mut out.casters
            } else {
                &mut out.lit
            };
            join_nearest(list);
        }
        out
    }
}

/// Joins the two boxes of `list` whose joined box is the smallest.
fn join_nearest(list: &mut Vec<(Vec3, Vec3)>) {
    let volume = |a: (Vec3, Vec3), b: (Vec3, Vec3)| {
        let (lo, hi) = (a.0.min(b.0), a.1.max(b.1));
        (hi - lo).max(Vec3::ZERO).element_product()
    };
    let mut best = (0, 1, f32::INFINITY);
    for i in 0..list.len() {
        for j in i + 1..list.len() {
            let v = volume(list[i], list[j]);
            if v < best.2 {
                best = (i, j, v);
            }
        }
    }
    let (i, j, _) = best;
    if j < list.len() {
        let b = list.swap_remove(j);
        list[i] = (list[i].0.min(b.0), list[i].1.max(b.1));
    }
}

/// An animated object's transform this frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Index into [`SceneInput::objects`].
    pub object: usize,
    /// Object → world.
    pub transform: Mat4,
}

/// Internal pixels per texel at the view centre that the splat pass draws at (the reference's
/// 2.5): enough to keep quad edges crisp after the nearest upscale.
pub const INTERNAL_PIXELS_PER_TEXEL: f32 = 5.0;

/// The internal render size for an output of `size`, faces of `face_resolution` texels and a
/// vertical field of view `fov_y`: tall enough for [`INTERNAL_PIXELS_PER_TEXEL`] pixels per
/// texel at the view centre (the pixel-perfect relation), never larger than `size`, same
/// aspect.
pub fn internal_size(size: UVec2, face_resolution: u32, fov_y: f32) -> UVec2 {
    let want = texel_probes::resolution::screen_height_for(
        face_resolution,
        fov_y,
        INTERNAL_PIXELS_PER_TEXEL,
    )
    .unwrap_or(size.y);
    if want >= size.y || size.y == 0 {
        return size;
    }
    let h = want.max(1);
    let w = ((u64::from(size.x) * u64::from(h)).div_ceil(u64::from(size.y)) as u32).max(1);
    UVec2::new(w, h)
}
