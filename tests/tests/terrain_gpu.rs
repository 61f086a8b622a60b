//! Terrain through the texel-splat renderer: one colour per world pixel cell on a flat
//! terrain, probe texels that do not depend on the camera, and the bundled island.

use std::collections::HashMap;

use glam::{UVec2, Vec3};
use texel_render::input::Camera;
use texel_tests::{Harness, KeptAndFresh, check_golden};

const DT: f32 = 1.0 / 30.0;

fn cam(x: f32, y: f32, z: f32, yaw: f32, pitch: f32) -> Camera {
    Camera::from_yaw_pitch(Vec3::new(x, y, z), yaw, pitch)
}

/// A flat terrain at height 0 (a constant 16-bit heightmap), lit straight from above, no
/// outlines, with a displacement texture so neighbouring cells differ: `band_distance` far
/// beyond the view keeps every cell in the finest band.
fn flat_terrain_level(dir: &std::path::Path, density: f32) -> std::path::PathBuf {
    terrain_level(dir, density, 4, &[0; 16], 1.0)
}

/// [`flat_terrain_level`] over a heightmap of `side` × `side` samples, `max_height` high.
fn terrain_level(
    dir: &std::path::Path,
    density: f32,
    side: u32,
    heights: &[u16],
    max_height: f32,
) -> std::path::PathBuf {
    let png = texel_scene::texture::encode_heightmap(side, side, heights);
    std::fs::write(dir.join("flat.png"), png).unwrap();
    let disp = texel_tests::repo_root().join("assets/textures/displacement.png");
    let text = format!(
        "(version: 3, settings: (sky: (0.5, 0.6, 0.8), ambient: (0.0, 0.0, 0.0), bands: 256, \
         pixel_scale: FaceResolution(64), cell_size: 1.0),\n entities: [(name: \"T\", \
         terrain: (size: (200.0, 200.0), heightmap: File(path: \"flat.png\"), max_height: {max_height:?}, \
         gradient: [(at: 0.0, colour: (0.1, 0.1, 0.1)), (at: 1.0, colour: (1.0, 1.0, 1.0))], \
         displacement: (path: {disp:?}, strength: 1.0, tile_size: 3.0), \
         pixel_density: {density:?}, band_distance: 1000.0, band_transition: 0.0, \
         outlined: false)),\n (directional_light: (direction: (0.0, -1.0, 0.0), \
         colour: (1.0, 1.0, 1.0), intensity: 1.0))])\n"
    );
    let path = dir.join("flat.ron");
    std::fs::write(&path, text).unwrap();
    path
}

/// [`flat_terrain_level`] (2 pixels a unit) with a shadow-casting box of `size` at `at`
/// (and `extra` after its material: an animator), under a low sun toward +Z, so that its
/// shadow falls toward a camera south of it.
fn flat_terrain_with_box(
    dir: &std::path::Path,
    at: Vec3,
    size: Vec3,
    extra: &str,
) -> std::path::PathBuf {
    let level = flat_terrain_level(dir, 2.0);
    let text = std::fs::read_to_string(&level).unwrap();
    let text = text.replace(
        "(directional_light: (direction: (0.0, -1.0, 0.0)",
        &format!(
            "(name: \"Box\", transform: (translation: ({:?}, {:?}, {:?}), rotation: (0.0, 0.0, \
             0.0), scale: (1.0, 1.0, 1.0)), geometry: Box(size: ({:?}, {:?}, {:?})), material: \
             (albedo: (0.5, 0.5, 0.5), emissive: (0.0, 0.0, 0.0), casts_shadows: true, \
             outlined: false){extra}),\n (directional_light: (direction: (0.0, -0.55, 0.83)",
            at.x, at.y, at.z, size.x, size.y, size.z
        ),
    );
    assert!(text.contains("\"Box\""), "the box was added to the level");
    std::fs::write(&level, text).unwrap();
    level
}

/// Every texel of the face below the probe whose centre ray meets the same world cell holds
/// the same colour, and the cells differ (the displacement shows).
#[test]
fn a_flat_terrain_face_holds_one_colour_per_world_cell() {
    let dir = tempfile::tempdir().unwrap();
    let density = 2.0;
    let level = flat_terrain_level(dir.path(), density);
    let size = UVec2::new(128, 72);
    let Some(mut h) = Harness::new(level.to_str().unwrap(), size, 64) else {
        return;
    };
    let c = cam(0.3, 1.6, 0.2, 0.0, -30.0);
    let (input, n, faces) = h.grid_lit_faces(c);
    let origin = input.grid.origin;
    // Face −Y (index 3); the cube convention of texel_probes::cube gives each texel's ray.
    let face = texel_probes::cube::Face::ALL[3];
    let mut cells: HashMap<(i64, i64), [u8; 3]> = HashMap::new();
    let mut texels = 0;
    for y in 0..n {
        for x in 0..n {
            let texel = texel_probes::cube::Texel { face, x, y };
            let d = texel_probes::cube::texel_center_direction(texel, n);
            let t = origin.y / -d.y;
            let p = origin + d * t;
            // Cells are anchored at the terrain's corner (−100, −100).
            let q = (p.x + 100.0, p.z + 100.0);
            let fx = q.0 * density;
            let fz = q.1 * density;
            // Skip texels whose hit is within a hair of a cell edge (rounding).
            if (fx - fx.round()).abs() < 1e-3 || (fz - fz.round()).abs() < 1e-3 {
                continue;
            }
            let key = (fx.floor() as i64, fz.floor() as i64);
            let i = ((y * n + x) * 4) as usize;
            let colour = [faces[3][i], faces[3][i + 1], faces[3][i + 2]];
            texels += 1;
            let first = *cells.entry(key).or_insert(colour);
            assert_eq!(first, colour, "cell {key:?} holds two colours");
        }
    }
    let distinct: std::collections::HashSet<_> = cells.values().collect();
    assert!(
        texels > 3000 && cells.len() > 20,
        "{texels} texels in {} cells",
        cells.len()
    );
    assert!(distinct.len() > 5, "only {} colours", distinct.len());
}

/// Under an orthographic camera a terrain's pixels are the finest no smaller than the grid
/// probe's texel, wherever they lie (`Terrain::ortho_band`): the probe's one face holds one
/// colour per world cell of that size, and side by side those cells mostly differ (the
/// displacement shows: 5364 of 5520 on lavapipe and SwiftShader). Bands had been measured
/// from the orthographic probe's origin, behind the view, as a cube probe's are: the pixels
/// came out coarser and 419 of the 5520 differed.
#[test]
fn an_orthographic_probe_holds_the_finest_pixels_its_texels_allow() {
    let dir = tempfile::tempdir().unwrap();
    let density = 2.0;
    // Flat at half its height, where the displacement spans the whole gradient, with bands
    // every 4 units (as a cube probe would have them).
    let level = terrain_level(dir.path(), density, 4, &[32768; 16], 2.0);
    let text = std::fs::read_to_string(&level).unwrap();
    std::fs::write(
        &level,
        text.replace("band_distance: 1000.0", "band_distance: 4.0"),
    )
    .unwrap();
    let ground = 2.0 * 32768.0 / 65535.0;
    let Some(mut h) = Harness::new(level.to_str().unwrap(), UVec2::new(160, 90), 64) else {
        return;
    };
    let c = Camera {
        ortho_height: Some(10.0),
        ..cam(0.3, 8.0, 0.2, 0.0, -60.0)
    };
    let (input, n, faces) = h.grid_lit_faces(c);
    let frame = input.grid.ortho.expect("an orthographic probe");
    let origin = input.grid.origin;
    let texel = frame.texel(n);
    let mut size = 1.0 / density;
    while size < texel {
        size *= 2.0;
    }
    let mut cells: HashMap<(i64, i64), [u8; 3]> = HashMap::new();
    for y in 0..n {
        for x in 0..n {
            let u = (x as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            let v = (y as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            let start = frame.point(origin, u, v, 0.0);
            let p = start + frame.forward * ((ground - start.y) / frame.forward.y);
            // Cells are anchored at the terrain's corner (−100, −100).
            let (fx, fz) = ((p.x + 100.0) / size, (p.z + 100.0) / size);
            if (fx - fx.round()).abs() < 0.02 || (fz - fz.round()).abs() < 0.02 {
                continue;
            }
            let key = (fx.floor() as i64, fz.floor() as i64);
            let i = ((y * n + x) * 4) as usize;
            let colour = [faces[0][i], faces[0][i + 1], faces[0][i + 2]];
            let first = *cells.entry(key).or_insert(colour);
            assert_eq!(first, colour, "cell {key:?} of {size} holds two colours");
        }
    }
    let (mut pairs, mut differ) = (0, 0);
    for (&(i, j), colour) in &cells {
        if let Some(next) = cells.get(&(i + 1, j)) {
            pairs += 1;
            differ += usize::from(next != colour);
        }
    }
    assert!(
        pairs > 100,
        "{pairs} neighbouring cells of {size} (texel {texel})"
    );
    assert!(
        differ * 3 > pairs * 2,
        "{differ} of {pairs} neighbouring cells of {size} differ (texel {texel})"
    );
}

/// How two views of one camera differ, drawn through the grid probes of two levels.
struct TwoProbeViews {
    /// Pixels compared.
    pixels: usize,
    /// Of those, pixels whose colour differs by more than 2 in some channel.
    differ: usize,
    /// Of those, pixels black in the first view (unlit: shadowed under no ambient).
    black: usize,
}

impl TwoProbeViews {
    /// Fewer than one pixel in `one_in` differs.
    fn assert_agree(&self, one_in: usize) {
        let Self { pixels, differ, .. } = self;
        assert!(
            differ * one_in < *pixels,
            "{differ} of {pixels} pixels differ between the two probes' views"
        );
    }
}

/// Camera `c` drawn at 160 × 90 (faces of 64) through `level` (probe cells of 1) and through
/// a copy of it beside it with probe cells of 1.37, compared on the rows below `num/den` of
/// the height; the probes must sit apart and the compared part show at least 5 colours.
/// `None` without a GPU.
fn two_probe_views(
    level: &std::path::Path,
    c: Camera,
    num: u32,
    den: u32,
) -> Option<TwoProbeViews> {
    let text = std::fs::read_to_string(level).unwrap();
    assert!(text.contains("cell_size: 1.0"), "{}", level.display());
    let other = level.with_file_name("other_cells.ron");
    std::fs::write(&other, text.replace("cell_size: 1.0", "cell_size: 1.37")).unwrap();
    let size = UVec2::new(160, 90);
    let (mut images, mut origins) = (Vec::new(), Vec::new());
    for l in [level, other.as_path()] {
        let mut h = Harness::new(l.to_str().unwrap(), size, 64)?;
        h.settle(c);
        let (input, _, px) = h.frame(c, DT);
        origins.push(input.grid.origin);
        images.push(px);
    }
    assert_ne!(origins[0], origins[1], "the two probes sit apart");
    let start = (size.x * 4 * (size.y * num / den)) as usize;
    let (a, b) = (&images[0][start..], &images[1][start..]);
    let differ = (a.chunks_exact(4).zip(b.chunks_exact(4)))
        .filter(|(p, q)| {
            p.iter()
                .zip(q.iter())
                .take(3)
                .any(|(x, y)| x.abs_diff(*y) > 2)
        })
        .count();
    let colours: std::collections::HashSet<_> =
        a.chunks_exact(4).map(|c| [c[0], c[1], c[2]]).collect();
    assert!(colours.len() >= 5, "only {} colours", colours.len());
    Some(TwoProbeViews {
        pixels: a.len() / 4,
        differ,
        black: a.chunks_exact(4).filter(|c| c[..3] == [0, 0, 0]).count(),
    })
}

/// The terrain pixel a screen pixel shows does not depend on the probe that drew it
/// (`shaders/terrain_splat.wgsl`): one view of a flat terrain, drawn through grid probes at
/// two origins (the level's probe cells 1 and 1.37 units), shows the same colour on nearly
/// every pixel. Drawn texel by texel, each probe drew the terrain pixels' edges on its own
/// texel grid, and the two views differed along every edge.
#[test]
fn terrain_pixels_on_screen_do_not_depend_on_the_probe() {
    let dir = tempfile::tempdir().unwrap();
    let level = flat_terrain_level(dir.path(), 2.0);
    // The lower half of the view: ground near both probes, in their finest band (farther,
    // each probe coarsens the pixels where its own texels outgrow them, as it should).
    let Some(views) = two_probe_views(&level, cam(0.3, 1.6, 0.2, 0.0, -30.0), 1, 2) else {
        return;
    };
    views.assert_agree(200);
}

/// As [`terrain_pixels_on_screen_do_not_depend_on_the_probe`] on rolling ground (a 201 ×
/// 201 heightmap, a sample a unit apart, 2.5 high): where the ground bends, each texel's own
/// tangent plane met the view rays a little apart from the other probe's, and pixels near a
/// terrain pixel's edge took the cell beside it: of the nearest third of the view, 98 of 4800
/// pixels differed on lavapipe, 119 on SwiftShader. The view rays are now tested against the
/// ground along the edges between the pixels (splat.wgsl `terrain_sides`), which no texel
/// owns: 50 and 74 differ (the rest lie where the two probes' texels, lights and outlines
/// still differ).
#[test]
fn terrain_pixels_on_rolling_ground_do_not_depend_on_the_probe() {
    let dir = tempfile::tempdir().unwrap();
    let side = 201u32;
    let heights: Vec<u16> = (0..side * side)
        .map(|i| {
            let (x, z) = ((i % side) as f32, (i / side) as f32);
            let h =
                0.5 + 0.3 * (0.9 * x).sin() * (0.7 * z).cos() + 0.15 * (1.7 * z + 0.3 * x).sin();
            (h.clamp(0.0, 1.0) * 65535.0) as u16
        })
        .collect();
    let level = terrain_level(dir.path(), 2.0, side, &heights, 2.5);
    // The nearest third of the view, in the finest band from both probes.
    let Some(views) = two_probe_views(&level, cam(0.3, 4.5, 0.2, 0.0, -30.0), 2, 3) else {
        return;
    };
    views.assert_agree(55);
}

/// A terrain pixel's shadow does not depend on the probe that drew it (`shaders/
/// terrain_splat.wgsl` `shadows`: rays from each pixel's centre): a tall box's shadow on a
/// flat terrain, under a low sun, drawn through grid probes at two origins, falls on the same
/// pixels. Lit by each texel's own shadow rays, the two probes' texels along the shadow's
/// edges lit their pixels differently.
#[test]
fn terrain_shadows_on_screen_do_not_depend_on_the_probe() {
    let dir = tempfile::tempdir().unwrap();
    // Its shadow falls 6 units toward the camera, onto the lower half of the view; the box
    // stands in the upper half, which is not compared.
    let box_at = Vec3::new(0.1, 2.0, -8.0);
    let level = flat_terrain_with_box(dir.path(), box_at, Vec3::new(1.5, 4.0, 1.0), "");
    let Some(views) = two_probe_views(&level, cam(0.3, 1.6, 0.2, 0.0, -30.0), 1, 2) else {
        return;
    };
    // The shadow is in the compared part: a tenth of it at least (measured: 790 of 7,200).
    assert!(views.black * 10 > views.pixels, "{} black", views.black);
    views.assert_agree(200);
}

/// A grid probe captured again from elsewhere in its cell, after both stable slots held
/// other probes, lights every terrain texel exactly as before: bands are measured from the
/// probe origin, never the camera.
#[test]
fn terrain_probe_texels_do_not_depend_on_the_camera() {
    let size = UVec2::new(160, 90);
    let Some(mut h) = Harness::new("assets/levels/terrain_hills.ron", size, 48) else {
        return;
    };
    let home = cam(0.2, 12.0, 30.3, 0.0, -20.0);
    let away = [
        cam(3.2, 12.0, 27.1, 0.0, -20.0),
        cam(-3.1, 12.0, 25.9, 0.0, -20.0),
    ];
    let back = cam(-0.3, 12.2, 29.8, 0.0, -20.0);
    // The faces this view needs (−Y below, −Z ahead); the others hold whatever the slot
    // last held.
    let colours = h.assert_recaptured_identically(home, &away, back, &[3, 5]);
    assert!(colours > 50, "{colours} colours");
}

#[test]
fn terrain_hills_golden_images() {
    let size = UVec2::new(256, 144);
    let Some(mut h) = Harness::new("assets/levels/terrain_hills.ron", size, 64) else {
        return;
    };
    let (px, _) = h.settle(cam(0.3, 16.0, 44.0, 0.0, -22.0));
    check_golden("terrain_hills_overview", &px, size, 0.002);
}

/// A terrain edit through `Session::update_level_region` marks only the probe faces that may
/// see the changed area (or its shadow) for capture, and once they are captured again the
/// frame is exactly what a session started on the edited level draws.
#[test]
fn a_terrain_dab_recaptures_only_the_faces_that_see_it() {
    use std::sync::Arc;
    use texel_runtime::load::load_level;
    use texel_runtime::session::{Session, set_face_resolution};
    use texel_scene::terrain::Terrain;

    let size = UVec2::new(160, 90);
    let n = 48;
    let Some(mut h) = Harness::new("assets/levels/terrain_hills.ron", size, n) else {
        return;
    };
    let c = cam(2.0, 7.0, 34.0, 0.0, -15.0);
    let (before, _) = h.settle(c);
    // Raise a disc of radius 3 around (-4, 24) by up to 2 units.
    let path = texel_tests::repo_root().join("assets/levels/terrain_hills.ron");
    let mut edited = load_level(&path).expect("level loads");
    set_face_resolution(&mut edited, n).expect("face resolution");
    let terrain = {
        let world = edited.scene.world();
        edited
            .scene
            .entities()
            .find_map(|e| world.get::<&Terrain>(e).ok().map(|t| (*t).clone()))
            .expect("a terrain")
    };
    let mut field = (**edited.assets.heightfield(&terrain).expect("heights")).clone();
    let step = terrain.size.x / (field.width - 1) as f32;
    for z in 0..field.depth {
        for x in 0..field.width {
            let p = glam::Vec2::new(-48.0 + x as f32 * step, -48.0 + z as f32 * step);
            let r = p.distance(glam::Vec2::new(-4.0, 24.0));
            if r < 3.0 {
                let i = (z * field.width + x) as usize;
                field.heights[i] += 2.0 * (1.0 - r / 3.0);
            }
        }
    }
    edited.assets.insert_heightfield(&terrain, Arc::new(field));
    let (min, max) = (Vec3::new(-7.0, 0.0, 21.0), Vec3::new(-1.0, 12.0, 27.0));
    let marked = h
        .session
        .update_level_region(&h.ctx, &edited, min, max)
        .expect("update");
    // Faces cached: the eye's six and the grid probe's visible ones at least.
    assert!(marked > 0, "the dab is in view");
    let mut captured_stable = 0;
    let mut px = Vec::new();
    for _ in 0..8 {
        let (input, _, p) = h.frame(c, DT);
        captured_stable += input
            .captures
            .iter()
            .filter(|w| w.slot != texel_probes::probe_set::Slot::Eye)
            .count();
        px = p;
    }
    assert!(
        captured_stable < 6,
        "only the faces that see the dab are captured again: {captured_stable}"
    );
    // A session started on the edited level draws the same frame.
    let mut fresh = Session::headless(&h.ctx, &edited, size, 60f32.to_radians()).expect("session");
    let request = texel_runtime::session::FrameRequest {
        camera: c,
        dt: DT,
        schedule: texel_render::input::Schedule::Ours,
        size,
    };
    let mut expect = Vec::new();
    for _ in 0..8 {
        expect = fresh.draw_offscreen(&h.ctx, &request).expect("frame").1;
    }
    let count = |a: &[u8], b: &[u8]| {
        a.chunks_exact(4)
            .zip(b.chunks_exact(4))
            .filter(|(x, y)| x != y)
            .count()
    };
    let changed = count(&before, &px);
    eprintln!("marked {marked}, stable faces captured {captured_stable}, pixels changed {changed}");
    assert!(changed > 100, "the dab shows: {changed} pixels changed");
    let differ = count(&px, &expect);
    assert_eq!(
        differ, 0,
        "{differ} pixels differ from a fresh session's frame"
    );
}

/// A flat terrain 200 units across with one grey gradient stop and a 2 × 2 paint layer:
/// toward −Z the −X half is red, toward +Z the −X half is red at half cover; the +X half is
/// unpainted. Every cell in the finest band, no outlines.
fn painted_terrain_level(dir: &std::path::Path) -> std::path::PathBuf {
    use texel_scene::texture::{Image, encode_heightmap, encode_png};
    std::fs::write(dir.join("flat.png"), encode_heightmap(4, 4, &[0; 16])).unwrap();
    let mut paint = Image::solid("paint", 2, 2, [0; 4]);
    paint.pixels[0..4].copy_from_slice(&[255, 0, 0, 255]);
    paint.pixels[8..12].copy_from_slice(&[255, 0, 0, 128]);
    std::fs::write(dir.join("paint.png"), encode_png(&paint)).unwrap();
    let text = "(version: 3, settings: (sky: (0.5, 0.6, 0.8), ambient: (0.0, 0.0, 0.0), \
                bands: 256, pixel_scale: FaceResolution(64), cell_size: 1.0),\n entities: \
                [(name: \"T\", terrain: (size: (200.0, 200.0), heightmap: File(path: \
                \"flat.png\"), max_height: 1.0, gradient: [(at: 0.0, colour: (0.5, 0.5, \
                0.5))], paint: (path: \"paint.png\"), pixel_density: 2.0, band_distance: \
                1000.0, band_transition: 0.0, outlined: false)),\n (directional_light: \
                (direction: (0.0, -1.0, 0.0), colour: (1.0, 1.0, 1.0), intensity: 1.0))])\n";
    let path = dir.join("painted.ron");
    std::fs::write(&path, text).unwrap();
    path
}

/// The paint layer colours whole terrain cells: the grid probe's captured albedo below it is
/// red exactly on the cells whose centres lie in the painted pixels, the gradient's grey on
/// the others, and half-covered red blends with the grey in linear light.
#[test]
fn a_painted_half_of_a_flat_terrain_captures_red_albedo_on_exactly_its_cells() {
    use texel_render::target::read_texture_layer;
    let dir = tempfile::tempdir().unwrap();
    let level = painted_terrain_level(dir.path());
    let size = UVec2::new(128, 72);
    let Some(mut h) = Harness::new(level.to_str().unwrap(), size, 64) else {
        return;
    };
    let c = cam(0.3, 1.6, 0.2, 0.0, -30.0);
    let (input, n, _) = h.grid_lit_faces(c);
    let origin = input.grid.origin;
    let face = texel_probes::cube::Face::ALL[3];
    let slot = h.renderer().probes().slot(input.grid.slot);
    let albedo = read_texture_layer(&h.ctx, &slot.albedo.texture, 3, 4).unwrap();
    let density = 2.0;
    // Linear 0.5 grey; red over it at cover 128/255.
    let grey = 128u8;
    let half = |v: f32| (v * 255.0).round() as u8;
    let a = 128.0 / 255.0;
    let blend = [
        half(0.5 + 0.5 * a),
        half(0.5 * (1.0 - a)),
        half(0.5 * (1.0 - a)),
    ];
    let mut seen = [0usize; 3];
    for y in 0..n {
        for x in 0..n {
            let texel = texel_probes::cube::Texel { face, x, y };
            let d = texel_probes::cube::texel_center_direction(texel, n);
            let p = origin + d * (origin.y / -d.y);
            let (fx, fz) = ((p.x + 100.0) * density, (p.z + 100.0) * density);
            if (fx - fx.round()).abs() < 1e-3 || (fz - fz.round()).abs() < 1e-3 {
                continue;
            }
            // The cell's centre, relative to the terrain's corner: the paint pixel holding
            // it is painted when it lies in the −X half.
            let centre = ((fx.floor() + 0.5) / density, (fz.floor() + 0.5) / density);
            let i = ((y * n + x) * 4) as usize;
            let got = [albedo[i], albedo[i + 1], albedo[i + 2]];
            let (want, kind) = match (centre.0 < 100.0, centre.1 < 100.0) {
                (false, _) => ([grey; 3], 0),
                (true, true) => ([255, 0, 0], 1),
                (true, false) => (blend, 2),
            };
            let close = got.iter().zip(want).all(|(g, w)| g.abs_diff(w) <= 1);
            assert!(
                close,
                "texel ({x}, {y}) over cell centre {centre:?}: albedo {got:?}, want {want:?}"
            );
            seen[kind] += 1;
        }
    }
    assert!(
        seen.iter().all(|&k| k > 300),
        "texels unpainted, painted, half painted: {seen:?}"
    );
}

/// The G-buffer methods colour terrain through the same function as the captures: the raster
/// baseline of the painted terrain, seen from above, shows one colour on the unpainted
/// cells, another on the painted ones (red), a third on the half-covered ones (a paler red),
/// each exactly on the cells whose centres the paint layer's pixels hold.
#[test]
fn the_raster_baseline_shows_the_same_paint_on_the_same_cells() {
    use texel_render::baselines::{Baseline, BaselineRenderer, BaselineView};
    let dir = tempfile::tempdir().unwrap();
    let level = painted_terrain_level(dir.path());
    let size = UVec2::new(160, 90);
    let Some(h) = Harness::new(level.to_str().unwrap(), size, 64) else {
        return;
    };
    let loaded = texel_runtime::load::load_level(&level).expect("level loads");
    let look = texel_runtime::frame_plan::level_look(&loaded.scene);
    let mut r = BaselineRenderer::new(&h.ctx).expect("baseline pipelines");
    r.set_scene(&h.ctx, h.session.scene()).expect("scene");
    let camera = cam(0.3, 5.0, 0.2, 0.0, -80.0);
    let view = BaselineView {
        camera,
        size,
        face_res: 64,
        look,
    };
    let frame = r.render(&h.ctx, Baseline::Raster, &view).expect("raster");
    let g = r
        .reference_gbuffer(&h.ctx, &camera, size, (camera.position, 64))
        .expect("G-buffer");
    let density = 2.0;
    let mut colours: [std::collections::BTreeSet<[u8; 3]>; 3] = Default::default();
    for (i, (&id, w)) in g.id.iter().zip(&g.world).enumerate() {
        if id == 0 {
            continue;
        }
        let (fx, fz) = ((w[0] + 100.0) * density, (w[2] + 100.0) * density);
        if (fx - fx.round()).abs() < 0.05 || (fz - fz.round()).abs() < 0.05 {
            continue;
        }
        let centre = ((fx.floor() + 0.5) / density, (fz.floor() + 0.5) / density);
        let kind = match (centre.0 < 100.0, centre.1 < 100.0) {
            (false, _) => 0,
            (true, true) => 1,
            (true, false) => 2,
        };
        let p = &frame.pixels[4 * i..4 * i + 3];
        colours[kind].insert([p[0], p[1], p[2]]);
    }
    let [grey, red, pale] = colours.map(|c| {
        assert_eq!(c.len(), 1, "one colour per region: {c:?}");
        c.into_iter().next().unwrap_or_default()
    });
    assert!(
        grey[0] == grey[1] && grey[1] == grey[2],
        "unpainted {grey:?}"
    );
    assert!(red[0] > 3 * red[1].max(red[2]), "painted {red:?}");
    assert!(
        pale[0] > pale[1] && pale[1] > red[1] && pale != grey,
        "half covered {pale:?}"
    );
}

/// Height of the full-detail mesh at world (x, z), split as `Heightfield::lod_mesh` splits
/// each quad (along its (1,0)-(0,1) diagonal); `None` off the terrain.
fn level0_height(t: &texel_render::input::TerrainInput, x: f32, z: f32) -> Option<f32> {
    let cells = (t.samples - UVec2::ONE).as_vec2();
    let step = t.size / cells;
    let g = glam::Vec2::new(x - t.corner.x, z - t.corner.z) / step;
    if g.min_element() < 0.0 || g.x > cells.x || g.y > cells.y {
        return None;
    }
    let i = g.floor().min(cells - 1.0);
    let f = g - i;
    let at = |dx: f32, dz: f32| {
        let (x, z) = ((i.x + dx) as usize, (i.y + dz) as usize);
        t.heights[z * t.samples.x as usize + x]
    };
    let h = if f.x + f.y <= 1.0 {
        at(0.0, 0.0) + f.x * (at(1.0, 0.0) - at(0.0, 0.0)) + f.y * (at(0.0, 1.0) - at(0.0, 0.0))
    } else {
        let h11 = at(1.0, 1.0);
        h11 + (1.0 - f.x) * (at(0.0, 1.0) - h11) + (1.0 - f.y) * (at(1.0, 0.0) - h11)
    };
    Some(t.corner.y + h)
}

/// Far chunks are drawn at coarser levels (`gpu_scene::chunk_lod`), yet every terrain texel
/// the grid probe splats holds a point of the full-detail surface, the one shadow rays and
/// the reference G-buffer see: a coarse level changes which texels a ridge covers, never where
/// a texel's point is (nor, so, its shadow or colour). Without the capture's refinement,
/// points on a coarse chunk's chords lie off that surface.
#[test]
fn coarse_terrain_levels_store_points_on_the_full_detail_surface() {
    let n = 32;
    let Some(mut h) = Harness::new("assets/levels/terrain_hills.ron", UVec2::new(160, 90), n)
    else {
        return;
    };
    let c = cam(0.3, 16.0, 44.0, 0.0, -22.0);
    h.settle(c);
    let (input, _, _) = h.frame(c, DT);
    let terrain = h.session.scene().terrains[0].clone();
    let origin = input.grid.origin;
    let spacing = (terrain.size / (terrain.samples - UVec2::ONE).as_vec2()).max_element();
    // A chunk is coarse once its nearest point is this far (ratio 2 in `chunk_lod`); a texel
    // this much farther than that lies in a coarse chunk whatever its chunk's extent.
    let coarse_from = spacing * n as f32 / texel_render::gpu_scene::LOD_SAMPLE_TEXELS
        + 32.0 * spacing * std::f32::consts::SQRT_2;
    let records = h.renderer().read_splats(&h.ctx).expect("splats");
    let (mut on, mut checked, mut far, mut worst) = (0, 0, 0, 0.0f32);
    // Whole quads and outlined quads' bodies: a strip is pulled toward the probe.
    for r in records
        .iter()
        .filter(|r| r.role == 1 && r.texels == 1 && r.part == 0)
    {
        let (x, y) = (r.key % n, (r.key / n) % n);
        let face = texel_probes::cube::Face::ALL[((r.key / (n * n)) % 6) as usize];
        let dir =
            texel_probes::cube::texel_center_direction(texel_probes::cube::Texel { face, x, y }, n);
        let depth = texel_probes::cube::chebyshev_norm(Vec3::from(r.corners[0]) - origin);
        let p = origin + dir * depth;
        let Some(ground) = level0_height(&terrain, p.x, p.z) else {
            continue;
        };
        // Terrain texels only: stones and the sea stand well off the ground's surface.
        let off = (p.y - ground).abs();
        if off > 0.5 {
            continue;
        }
        checked += 1;
        if depth > coarse_from {
            far += 1;
        }
        worst = worst.max(off / depth);
        if off <= 2e-4 * depth.max(1.0) {
            on += 1;
        }
    }
    assert!(
        checked > 500 && far > 20,
        "{checked} terrain texels, {far} on coarse chunks"
    );
    // Measured (faces of 32): 816 of 821 terrain texels on the surface, 43 of them on
    // coarse chunks; with the capture's refinement taken out, 578 of 821.
    assert!(
        on as f32 >= 0.99 * checked as f32,
        "{on} of {checked} terrain texels on the full-detail surface (worst {worst} of depth)"
    );
}

/// The terrain splats' record cache where keys share slots by hash, as at faces of 496 and
/// more (a 1280×720 view's): here faces of 64 in 4096 slots, 54 keys a slot. A run over the
/// hills, crossing cells (both stable probes' and the eye's records fill the slots and
/// overwrite one another), draws every frame exactly as the same run through a cache of one
/// slot per key. A record served to a key it was not made for would show.
#[test]
fn a_cache_whose_keys_share_slots_draws_what_one_slot_per_key_draws() {
    let size = UVec2::new(160, 90);
    let level = "assets/levels/terrain_hills.ron";
    let (Some(mut shared), Some(mut own)) =
        (Harness::new(level, size, 64), Harness::new(level, size, 64))
    else {
        return;
    };
    shared.session.renderer_mut().set_terrain_cache_slots(4096);
    let keys = 3 * 3 * 6 * 64 * 64;
    let mut colours = std::collections::HashSet::new();
    for i in 0..24 {
        // 6 units/s, a one-unit cell every five frames, turning a little.
        let t = i as f32 * DT;
        let c = cam(-8.0 + 0.5 * t, 7.2, 40.0 - 6.0 * t, -15.0 + 10.0 * t, -8.0);
        let (_, _, a) = shared.frame(c, DT);
        let (_, _, b) = own.frame(c, DT);
        assert_eq!(shared.renderer().terrain_cache_slots(), 4096);
        assert_eq!(own.renderer().terrain_cache_slots(), keys);
        let differ = (a.chunks_exact(4).zip(b.chunks_exact(4)))
            .filter(|(p, q)| p != q)
            .count();
        assert_eq!(differ, 0, "frame {i}: {differ} pixels differ");
        colours.extend(a.chunks_exact(4).map(|p| [p[0], p[1], p[2]]));
    }
    assert!(colours.len() > 50, "{} colours", colours.len());
}

/// The terrain splats pass does a frame's work once (its counters, read back with each
/// frame): settled, a still camera makes (nearly) no record and casts no ray; and a camera
/// moved a hundredth of a unit keeps its eye quads' records, which are stamped with the
/// block their texel lies toward, not with the texel's point.
#[test]
fn terrain_records_and_rays_are_made_once() {
    let Some(mut h) = Harness::new("assets/levels/terrain_hills.ron", UVec2::new(160, 90), 64)
    else {
        return;
    };
    let c = cam(-8.0, 7.2, 40.0, -15.0, -8.0);
    let (_, first, _) = h.frame(c, DT);
    let made = first.counters.terrain_records_made;
    let cast = first.counters.terrain_pixels_cast;
    // Measured (lavapipe): 2,011 records, 1,945 pixels' rays cast (of the 8,044 pixels their
    // blocks show: the rest shared). Without the table's claims (terrain_splat.wgsl
    // `shadows`), every miss that showed a pixel cast for it: 8,044.
    assert!(made > 1000, "{made} records made on the first frame");
    assert!(
        cast > 0 && cast < 2 * made,
        "{cast} pixels cast for {made} records"
    );
    h.settle(c);
    let (_, still, _) = h.frame(c, DT);
    let quads = still.counters.quads_splatted;
    // Measured: none of 2,318 quads. Two strips of one texel in one shade share a slot,
    // each made from its own middle: their 7 records are found on their blocks
    // (`terrain_records_shared`; 7 made before the records were also kept by block).
    assert!(
        still.counters.terrain_records_made * 100 <= quads,
        "a still camera made {} records of {quads} quads",
        still.counters.terrain_records_made
    );
    assert_eq!(
        still.counters.terrain_pixels_cast, 0,
        "a still camera cast rays"
    );
    let moved = cam(-7.99, 7.2, 40.0, -15.0, -8.0);
    let (input, m, _) = h.frame(moved, DT);
    assert!(input.previous.is_none(), "no crossing");
    // Measured: 13 records, 9 found on their blocks (26 made when records were kept by
    // texel only, 272 when an eye quad's stamp held its texel's point).
    assert!(
        m.counters.terrain_records_made < 100,
        "a camera moved 0.01 made {} records of {} quads",
        m.counters.terrain_records_made,
        m.counters.quads_splatted
    );
}

/// The eye's texels move with the camera, so an eye quad's record is kept by the block it
/// shows, not by its texel: walking back over ground the eye has shown finds the records it
/// made there, and every frame draws what a renderer that makes every record afresh draws.
#[test]
fn the_eyes_records_are_kept_by_the_ground_they_show() {
    let level = "assets/levels/terrain_hills.ron";
    let size = UVec2::new(160, 90);
    let Some(mut pair) = KeptAndFresh::new(level, size, 64) else {
        return;
    };
    // Along X inside one cell (0.2 units) and back: each position of the way back was
    // passed on the way out.
    let xs = [
        -8.0, -7.96, -7.92, -7.88, -7.84, -7.8, -7.84, -7.88, -7.92, -7.96, -8.0,
    ];
    let c = |x: f32| cam(x, 7.2, 40.0, -15.0, -8.0);
    pair.settle(c(xs[0]));
    let (mut made_out, mut made_back, mut quads_back) = (0, 0, 0);
    for (i, &x) in xs.iter().enumerate() {
        let (input, a, b, _) = pair.frame(c(x), DT, &format!("x = {x}"));
        assert!(input.previous.is_none(), "x = {x}: no crossing");
        assert!(
            b.counters.terrain_records_made > 1000,
            "the fresh cache makes every record"
        );
        if (1..=5).contains(&i) {
            made_out += a.counters.terrain_records_made;
        } else if i > 5 {
            made_back += a.counters.terrain_records_made;
            quads_back += a.counters.quads_splatted;
        }
    }
    // Measured (lavapipe): out 156 records, back 0 of 11,411 quads (out 226 and back 35
    // before records were also kept by block). When the eye's records were kept by texel,
    // out 383 and back 254: each frame's eye texels took the slots of the frame before's.
    assert!(made_out > 0, "walking out shows new ground");
    assert!(
        made_back * 2 < made_out,
        "walking back made {made_back} records, out {made_out}"
    );
    assert!(
        made_back * 100 < quads_back,
        "walking back made {made_back} records of {quads_back} quads"
    );
}

/// A record is made from its block and pixels, whichever probe's texel shows it: across a
/// crossing the new probe's quads find most of their records on the blocks the old probe's
/// made, and every frame draws what a renderer that makes every record afresh draws.
#[test]
fn a_crossings_new_probe_finds_its_records_on_the_old_probes_blocks() {
    let level = "assets/levels/terrain_hills.ron";
    let size = UVec2::new(160, 90);
    let Some(mut pair) = KeptAndFresh::new(level, size, 64) else {
        return;
    };
    let c = |z: f32| cam(-8.0, 7.2, z, -15.0, -8.0);
    pair.settle(c(40.0));
    let (mut made, mut found, mut fading) = (0, 0, 0);
    for i in 1..=12 {
        let z = 40.0 - 0.15 * i as f32;
        let (input, a, _, _) = pair.frame(c(z), DT, &format!("z = {z}"));
        if input.previous.is_some() {
            fading += 1;
            made += a.counters.terrain_records_made;
            found += a.counters.terrain_records_shared;
        }
    }
    assert!(
        fading >= 2,
        "the walk crosses into the next cell ({fading} fading frames)"
    );
    // Measured (lavapipe): 3,491 found and 2,354 made over 6 fading frames (at a crossing's
    // first, 846 and 909); without the blocks' slots every one of them was made.
    assert!(
        found > made && found > 1000,
        "fading frames found {found} records on their blocks and made {made}"
    );
}

/// A shadow caster moving over a terrain has only the terrain pixels and records where its
/// shadow may have come or gone made again (`texel_render::shadow_region::ShadowTiles`), and
/// every frame draws exactly what a renderer that makes every record and casts every ray
/// afresh draws: a record or pixel kept where the shadow moved would show.
#[test]
fn a_moving_casters_shadow_on_the_terrain_remakes_only_what_it_may_touch() {
    let dir = tempfile::tempdir().unwrap();
    // A tall box sliding 2 units along X in a second and back, its shadow falling toward
    // the camera under a low sun.
    let level = flat_terrain_with_box(
        dir.path(),
        Vec3::new(-1.0, 2.0, -8.0),
        Vec3::new(1.0, 4.0, 1.0),
        ", animator: (motion: PingPong(to: (translation: (1.0, 2.0, -8.0), rotation: (0.0, \
         0.0, 0.0), scale: (1.0, 1.0, 1.0)), period: 2.0, easing: Linear))",
    );
    assert!(
        std::fs::read_to_string(&level)
            .unwrap()
            .contains("PingPong"),
        "the box moves"
    );
    let level = level.to_str().unwrap();
    let size = UVec2::new(160, 90);
    let Some(mut pair) = KeptAndFresh::new(level, size, 64) else {
        return;
    };
    // From above and behind the shadow: it and the box in the middle, ground it never
    // reaches all around.
    let c = cam(0.3, 9.0, 6.0, 0.0, -35.0);
    let (mut made_kept, mut made_fresh, mut cast_kept, mut cast_fresh) = (0, 0, 0, 0);
    let mut black = 0;
    let mut images = std::collections::HashSet::new();
    for i in 0..16 {
        let (_, a, b, pa) = pair.frame(c, DT, &format!("frame {i}"));
        if i >= 8 {
            made_kept += a.counters.terrain_records_made;
            made_fresh += b.counters.terrain_records_made;
            cast_kept += a.counters.terrain_pixels_cast;
            cast_fresh += b.counters.terrain_pixels_cast;
        }
        black = black.max(
            pa.chunks_exact(4)
                .filter(|p| p[..3].iter().all(|&c| c < 8))
                .count(),
        );
        images.insert(pa);
    }
    // The box and its shadow (black: no ambient light) are in view, and moved: every frame
    // differs from the others.
    assert!(black > 100, "{black} black pixels");
    assert!(images.len() >= 12, "{} distinct frames of 16", images.len());
    // Measured (lavapipe, frames 8-15): 11,704 records made against 31,320, and 1,358
    // pixels' rays cast against 24,724 (before the tiles, a moving caster cleared the cache:
    // every record and ray made again each frame).
    assert!(
        made_kept * 2 < made_fresh,
        "{made_kept} records made against {made_fresh} made afresh"
    );
    assert!(
        cast_kept * 10 < cast_fresh,
        "{cast_kept} pixels' rays cast against {cast_fresh} cast afresh"
    );
}
