//! The catalogue of hostile inputs (issue 13): files that are not regular files, huge or
//! sparse files, glTF files that escape their folder or expand without bound, and command-line
//! numbers out of range. Every case runs `texel-run` as a process with a time limit and asserts
//! a non-zero exit that is not a panic (101), no panic message, and the expected error text.
//! The level loader's content catalogue is `crates/scene/tests/levels.rs`; reports for
//! `texel-eval chart` are in `eval/tests/hostile_reports.rs`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longer than any case needs by far (each fails before any GPU work), short enough that a
/// hang fails the test instead of stalling it.
const TIME_LIMIT: Duration = Duration::from_secs(60);

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// Runs `texel-run` with `args` and extra environment; `(exit code, stderr)`, or an error
/// when it outlives [`TIME_LIMIT`] (it is then killed).
fn texel_run(args: &[String], env: &[(&str, &str)]) -> Result<(Option<i32>, String), String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_texel-run"))
        .args(args)
        .envs(env.iter().copied())
        .env("RUST_BACKTRACE", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("texel-run does not start: {e}"))?;
    let started = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if started.elapsed() > TIME_LIMIT => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!("hung for more than {TIME_LIMIT:?}"));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(e.to_string()),
        }
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    Ok((
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    ))
}

/// One hostile input: the command line, extra environment, and a phrase the error must hold.
struct Case {
    name: String,
    args: Vec<String>,
    env: Vec<(&'static str, &'static str)>,
    expect: &'static str,
}

fn case(name: &str, args: &[&str], expect: &'static str) -> Case {
    Case {
        name: name.to_owned(),
        args: args.iter().map(|s| s.to_string()).collect(),
        env: Vec::new(),
        expect,
    }
}

fn with_env(mut c: Case, env: &[(&'static str, &'static str)]) -> Case {
    c.env.extend_from_slice(env);
    c
}

/// Runs every case; fails once, listing every case that went wrong.
fn run_catalogue(cases: &[Case]) {
    let mut failures = String::new();
    for c in cases {
        match texel_run(&c.args, &c.env) {
            Err(e) => writeln!(failures, "{}: {e}", c.name).unwrap(),
            Ok((code, err)) => {
                let ok = matches!(code, Some(n) if n != 0 && n != 101)
                    && !err.contains("panicked")
                    && err.contains(c.expect);
                if !ok {
                    writeln!(
                        failures,
                        "{}: exit {code:?}, expected {:?} in stderr:\n{err}",
                        c.name, c.expect
                    )
                    .unwrap();
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures}");
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(status.success(), "mkfifo {}", path.display());
}

/// A sparse file of `len` bytes (no disk space used).
fn sparse(path: &Path, len: u64) {
    std::fs::File::create(path)
        .and_then(|f| f.set_len(len))
        .expect("sparse file");
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// A level whose one entity is the mesh at `mesh` (written as is in the level).
fn level_with_mesh(dir: &Path, name: &str, mesh: &str) -> PathBuf {
    let path = dir.join(name);
    let text = format!(
        "(version: 2, settings: (sky: (0.5, 0.6, 0.8), ambient: (0.2, 0.2, 0.2), bands: 32, \
         pixel_scale: PixelSize(2.5), cell_size: 1.0),\n entities: [(name: \"M\", \
         geometry: Mesh(path: {mesh:?}))])\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// A level whose one entity is a terrain with the heightmap file `heightmap`.
fn level_with_terrain(dir: &Path, name: &str, heightmap: &str) -> PathBuf {
    let path = dir.join(name);
    let text = format!(
        "(version: 3, entities: [(name: \"T\",\n terrain: (size: (16.0, 16.0), \
         heightmap: File(path: {heightmap:?}), max_height: 4.0, \
         gradient: [(at: 0.0, colour: (0.2, 0.5, 0.1))], pixel_density: 4.0, \
         band_distance: 8.0, band_transition: 0.3))])\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// A blank RGBA image of `w` × `h`.
fn texel_geom_image(w: u32, h: u32) -> texel_scene::texture::Image {
    texel_scene::texture::Image::solid("blank", w, h, [0; 4])
}

/// A level whose one entity is a box textured with `texture` (written as is in the level).
fn level_with_texture(dir: &Path, name: &str, texture: &str) -> PathBuf {
    let path = dir.join(name);
    let text = format!(
        "(version: 3, settings: (sky: (0.5, 0.6, 0.8), ambient: (0.2, 0.2, 0.2), bands: 32, \
         pixel_scale: PixelSize(2.5), cell_size: 1.0),\n entities: [(name: \"T\", \
         geometry: Box(size: (1.0, 1.0, 1.0)),\n material: (albedo: (1.0, 1.0, 1.0), \
         texture: (path: {texture:?})))])\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// A glTF of one triangle (positions and `u32` indices in `bin`, written beside it unless
/// `write_bin` is false), placed by `nodes` nodes; `primitives` copies of the primitive per
/// mesh; `tri_copies` repeats the triangle's indices.
fn gltf(
    dir: &Path,
    name: &str,
    bin: &str,
    write_bin: bool,
    nodes: usize,
    primitives: usize,
    tri_copies: usize,
) -> PathBuf {
    let mut bytes = Vec::new();
    for v in [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in v {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    for _ in 0..tri_copies {
        for i in [0u32, 1, 2] {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
    }
    if write_bin {
        std::fs::write(dir.join(bin), &bytes).unwrap();
    }
    let prim = r#"{"attributes":{"POSITION":0},"indices":1}"#;
    let prims = vec![prim; primitives].join(",");
    let node_list = vec![r#"{"mesh":0}"#; nodes].join(",");
    let roots = (0..nodes)
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},
"buffers":[{{"uri":{bin:?},"byteLength":{len}}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":{ilen}}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5125,"count":{icount},"type":"SCALAR"}}],
"meshes":[{{"primitives":[{prims}]}}],
"nodes":[{node_list}],
"scenes":[{{"nodes":[{roots}]}}],"scene":0}}"#,
        len = bytes.len(),
        ilen = bytes.len() - 36,
        icount = tri_copies * 3,
    );
    let path = dir.join(name);
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn hostile_files_are_refused_fast_with_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("fifo.ron");
    mkfifo(&fifo);
    let huge = d.join("huge.ron");
    sparse(&huge, 1 << 40);
    let folder = d.join("folder.ron");
    std::fs::create_dir(&folder).unwrap();
    let link = d.join("zero_link.ron");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let stone = repo("assets/levels/stone_circle.ron");
    let sandbox = repo("assets/levels/sandbox.ron");
    let check = |name: &str, file: &Path, expect| case(name, &["check", s(file)], expect);
    let mut cases = vec![
        // Levels.
        check(
            "level /dev/zero",
            Path::new("/dev/zero"),
            "a character device",
        ),
        check(
            "level /dev/null",
            Path::new("/dev/null"),
            "a character device",
        ),
        check("level FIFO", &fifo, "a FIFO"),
        check("level directory", &folder, "a directory"),
        check("level sparse 1 TiB", &huge, "too large"),
        check("level symlink to /dev/zero", &link, "a character device"),
        check("level missing", &d.join("missing.ron"), "missing.ron"),
        with_env(
            check("level over a lowered cap", &stone, "TEXEL_MAX_LEVEL_BYTES"),
            &[("TEXEL_MAX_LEVEL_BYTES", "100")],
        ),
        // A /proc file reports 0 bytes: only the bounded read stops it.
        with_env(
            check(
                "level /proc (size 0, read bounded)",
                Path::new("/proc/self/maps"),
                "too large",
            ),
            &[("TEXEL_MAX_LEVEL_BYTES", "16")],
        ),
        case("fmt /dev/zero", &["fmt", "/dev/zero"], "a character device"),
        case("fmt FIFO", &["fmt", "--check", s(&fifo)], "a FIFO"),
        case("play FIFO", &["play", s(&fifo)], "a FIFO"),
    ];

    // Meshes a level refers to, and their buffers.
    let assets = d.join("assets");
    std::fs::create_dir_all(assets.join("sub")).unwrap();
    mkfifo(&assets.join("mesh_fifo.gltf"));
    mkfifo(&assets.join("buffer_fifo.bin"));
    sparse(&assets.join("huge.glb"), 1 << 40);
    sparse(&assets.join("huge.bin"), 1 << 40);
    std::fs::create_dir(assets.join("folder.glb")).unwrap();
    // A valid buffer outside the glTF's folder (the .gltf written beside it is unused).
    gltf(d, "outside.gltf", "outside.bin", true, 1, 1, 1);
    std::os::unix::fs::symlink(d.join("outside.bin"), assets.join("link.bin")).unwrap();
    let mesh_case = |name: &str, mesh: &str, expect| {
        let level = level_with_mesh(
            &assets,
            &format!(
                "{}.ron",
                name.replace(|c: char| !c.is_ascii_alphanumeric(), "_")
            ),
            mesh,
        );
        case(name, &["check", s(&level)], expect)
    };
    let bomb = |file: &str, nodes, prims, tris| {
        let bin = file.replace(".gltf", ".bin");
        gltf(&assets, file, &bin, true, nodes, prims, tris)
    };
    let ok = bomb("ok.gltf", 2, 1, 1);
    let tris = bomb("triangle_bomb.gltf", 2_000, 1, 10_000);
    let nodes = bomb("node_bomb.gltf", 100_001, 1, 1);
    let instances = bomb("instance_bomb.gltf", 400, 300, 1);
    let uri = |file: &str, bin: &str| gltf(&assets, file, bin, false, 1, 1, 1);
    let absolute = uri("absolute.gltf", "/etc/passwd");
    let dotdot = uri("dotdot.gltf", "../outside.bin");
    let deep = uri("deep.gltf", "sub/../../outside.bin");
    let encoded = uri("encoded.gltf", "%2e%2e/outside.bin");
    let linked = uri("linked.gltf", "link.bin");
    let buffer_fifo = uri("buffer_fifo.gltf", "buffer_fifo.bin");
    let buffer_huge = uri("buffer_huge.gltf", "huge.bin");
    let buffer_dev = gltf(&assets, "buffer_dev.gltf", "sub/dev", false, 1, 1, 1);
    std::os::unix::fs::symlink("/dev/zero", assets.join("sub/dev")).unwrap();
    let name = |p: &Path| p.file_name().unwrap().to_str().unwrap().to_owned();
    cases.extend([
        mesh_case("mesh /dev/zero", "/dev/zero", "a character device"),
        mesh_case("mesh FIFO", "mesh_fifo.gltf", "a FIFO"),
        mesh_case("mesh sparse 1 TiB", "huge.glb", "too large"),
        mesh_case("mesh directory", "folder.glb", "a directory"),
        mesh_case(
            "mesh triangle bomb",
            &name(&tris),
            "more than 4000000 triangles",
        ),
        mesh_case("mesh node bomb", &name(&nodes), "100001 nodes"),
        mesh_case(
            "mesh instance bomb",
            &name(&instances),
            "mesh primitive instances",
        ),
        mesh_case(
            "buffer absolute URI",
            &name(&absolute),
            "is an absolute path",
        ),
        mesh_case("buffer .. URI", &name(&dotdot), "leads out of the folder"),
        mesh_case(
            "buffer sub/../.. URI",
            &name(&deep),
            "leads out of the folder",
        ),
        mesh_case(
            "buffer %2e%2e URI",
            &name(&encoded),
            "leads out of the folder",
        ),
        mesh_case("buffer symlink out", &name(&linked), "symbolic link"),
        mesh_case("buffer FIFO", &name(&buffer_fifo), "a FIFO"),
        mesh_case("buffer sparse 1 TiB", &name(&buffer_huge), "too large"),
        mesh_case(
            "buffer symlink to /dev/zero",
            &name(&buffer_dev),
            "symbolic link",
        ),
        with_env(
            mesh_case(
                "buffer /dev/zero, any URI",
                &name(&buffer_dev),
                "a character device",
            ),
            &[("TEXEL_GLTF_ANY_URI", "1")],
        ),
        with_env(
            mesh_case(
                "mesh over a lowered triangle budget",
                &name(&ok),
                "TEXEL_GLTF_MAX_TRIANGLES",
            ),
            &[("TEXEL_GLTF_MAX_TRIANGLES", "1")],
        ),
        with_env(
            check(
                "bundled mesh over a lowered buffer cap",
                &sandbox,
                "TEXEL_MAX_MESH_BUFFER_BYTES",
            ),
            &[("TEXEL_MAX_MESH_BUFFER_BYTES", "10")],
        ),
    ]);

    // Camera paths (read before the level and before any GPU work).
    let bad_frames = d.join("frames0.ron");
    std::fs::write(
        &bad_frames,
        "(frames: 0, keyframes: [(position: (0.0, 1.0, 0.0))])",
    )
    .unwrap();
    let bad_pitch = d.join("pitch95.ron");
    std::fs::write(
        &bad_pitch,
        "(frames: 2, keyframes: [(position: (0.0, 1.0, 0.0), pitch: 95.0)])",
    )
    .unwrap();
    // Textures: missing, not images, not PNG, too large, not regular files.
    let textures = d.join("textures");
    std::fs::create_dir(&textures).unwrap();
    std::fs::write(textures.join("text.png"), "not an image").unwrap();
    let png = texel_scene::texture::encode_png(&texel_geom_image(4096, 1));
    std::fs::write(textures.join("wide.png"), &png).unwrap();
    let mut half = texel_scene::texture::encode_png(&texel_geom_image(64, 64));
    half.truncate(half.len() / 2);
    std::fs::write(textures.join("truncated.png"), &half).unwrap();
    // A BMP header: recognised as an image, not one this build reads.
    let mut bmp = b"BM".to_vec();
    bmp.resize(64, 0);
    std::fs::write(textures.join("bitmap.png"), &bmp).unwrap();
    sparse(&textures.join("sparse.png"), 1 << 40);
    mkfifo(&textures.join("fifo.png"));
    let textured = |name: &str, file: &str, expect| {
        let level = level_with_texture(d, &format!("{name}.ron"), file);
        check(name, &level, expect)
    };
    cases.extend([
        textured(
            "texture missing",
            "textures/missing.png",
            "textures/missing.png",
        ),
        textured("texture text", "textures/text.png", "not a PNG"),
        textured("texture 4096 wide", "textures/wide.png", "larger than 2048"),
        textured(
            "texture truncated",
            "textures/truncated.png",
            "cannot decode",
        ),
        textured("texture BMP", "textures/bitmap.png", "not supported"),
        textured("texture sparse 1 TiB", "textures/sparse.png", "too large"),
        textured("texture FIFO", "textures/fifo.png", "a FIFO"),
        textured("texture directory", "textures", "a directory"),
    ]);
    // Heightmaps: missing, 8-bit, a single row, too large.
    let heights = d.join("heights");
    std::fs::create_dir(&heights).unwrap();
    std::fs::write(
        heights.join("rgba.png"),
        texel_scene::texture::encode_png(&texel_geom_image(8, 8)),
    )
    .unwrap();
    std::fs::write(
        heights.join("row.png"),
        texel_scene::texture::encode_heightmap(8, 1, &[0; 8]),
    )
    .unwrap();
    std::fs::write(
        heights.join("huge.png"),
        texel_scene::texture::encode_heightmap(5000, 2, &vec![0; 10_000]),
    )
    .unwrap();
    let terrain = |name: &str, file: &str, expect| {
        let level = level_with_terrain(d, &format!("{name}.ron"), file);
        check(name, &level, expect)
    };
    cases.extend([
        terrain(
            "heightmap missing",
            "heights/missing.png",
            "heights/missing.png",
        ),
        terrain(
            "heightmap 8-bit RGBA",
            "heights/rgba.png",
            "16-bit greyscale",
        ),
        terrain("heightmap one row", "heights/row.png", "at least 2×2"),
        terrain(
            "heightmap 5000 wide",
            "heights/huge.png",
            "larger than 4097",
        ),
    ]);
    let out = d.join("out");
    let render_path = |name: &str, path: &Path, expect| {
        case(
            name,
            &["render", s(&stone), "--path", s(path), "--out", s(&out)],
            expect,
        )
    };
    cases.extend([
        render_path(
            "path /dev/zero",
            Path::new("/dev/zero"),
            "a character device",
        ),
        render_path("path FIFO", &fifo, "a FIFO"),
        render_path("path directory", &folder, "a directory"),
        render_path("path sparse 1 TiB", &huge, "too large"),
        render_path("path frames 0", &bad_frames, "frames must be 1..=100000"),
        render_path("path pitch 95", &bad_pitch, "pitch must be within ±89"),
    ]);
    assert!(cases.len() >= 30, "{} file cases", cases.len());
    run_catalogue(&cases);

    // The fixtures are valid within the limits, and the options that allow more allow it.
    let check_ok = |level: &Path, env: &[(&str, &str)]| {
        let (code, err) = texel_run(&["check".into(), s(level).into()], env).unwrap();
        assert_eq!(code, Some(0), "{}: {err}", level.display());
    };
    check_ok(&level_with_mesh(&assets, "ok.ron", &name(&ok)), &[]);
    let any_uri = level_with_mesh(&assets, "dotdot_allowed.ron", &name(&dotdot));
    check_ok(&any_uri, &[("TEXEL_GLTF_ANY_URI", "1")]);
    let few_nodes = level_with_mesh(&assets, "few_nodes.ron", &name(&bomb("few.gltf", 20, 1, 1)));
    check_ok(&few_nodes, &[]);
    let (code, err) = texel_run(
        &["check".into(), s(&few_nodes).into()],
        &[("TEXEL_GLTF_MAX_NODES", "10")],
    )
    .unwrap();
    assert!(
        code == Some(2) && err.contains("20 nodes, the limit is 10"),
        "{err}"
    );
}

/// The one hostile file only a GPU can refuse (its limits decide), apart from the catalogue
/// above, which never opens a device and so runs on one driver only.
#[test]
fn a_level_too_large_for_the_gpu_is_refused_before_upload() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let assets = d.join("assets");
    std::fs::create_dir_all(&assets).unwrap();
    // A valid level the GPU cannot hold: 2,000 copies of a 100,000-triangle mesh (200 million
    // triangles, 18 GiB of vertices) is refused before anything is expanded or uploaded.
    gltf(&assets, "big.gltf", "big.bin", true, 1, 1, 100_000);
    let copies = d.join("copies.ron");
    let rows: Vec<String> = (0..2000)
        .map(|i| {
            format!(
                "(name: \"C{i}\", transform: (translation: ({}.0, 0.0, {}.0), rotation: (0.0, \
                 0.0, 0.0), scale: (1.0, 1.0, 1.0)), geometry: Mesh(path: \"assets/big.gltf\"))",
                i % 50,
                i / 50
            )
        })
        .collect();
    std::fs::write(
        &copies,
        format!(
            "(version: 2, settings: (sky: (0.5, 0.6, 0.8), ambient: (0.2, 0.2, 0.2), bands: 32, \
             pixel_scale: PixelSize(2.5), cell_size: 1.0),\n entities: [{}])\n",
            rows.join(",\n")
        ),
    )
    .unwrap();
    let out_big = d.join("out_big");
    run_catalogue(&[case(
        "2,000 copies of a 100k-triangle mesh",
        &[
            "render",
            s(&copies),
            "--size",
            "64x36",
            "--out",
            s(&out_big),
        ],
        "too large for this GPU",
    )]);
}

#[test]
fn hostile_command_line_numbers_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let stone = repo("assets/levels/stone_circle.ron");
    let render = |name: &str, extra: &[&str], expect| {
        let mut args = vec!["render", s(&stone), "--out", s(&out)];
        args.extend_from_slice(extra);
        case(name, &args, expect)
    };
    let cases = [
        render(
            "frames 0",
            &["--frames", "0"],
            "--frames must be 1..=100000",
        ),
        render(
            "frames u32::MAX",
            &["--frames", "4294967295"],
            "--frames must be 1..=100000",
        ),
        render(
            "frames 100001",
            &["--frames", "100001"],
            "--frames must be 1..=100000",
        ),
        render("frames negative", &["--frames=-1"], "invalid value"),
        render("frames 2^32", &["--frames", "4294967296"], "invalid value"),
        render(
            "camera pitch 95",
            &["--camera=0,1,0,0,95"],
            "pitch must be within ±89",
        ),
        render(
            "camera pitch -90",
            &["--camera=0,1,0,0,-90"],
            "pitch must be within ±89",
        ),
        render(
            "camera pitch NaN",
            &["--camera=0,1,0,0,NaN"],
            "NaN or infinite",
        ),
        render("camera yaw inf", &["--camera=0,1,0,inf,0"], "--camera yaw"),
        render("camera x 1e9", &["--camera=1e9,1,0,0,0"], "too large"),
        render("camera y -inf", &["--camera=0,-inf,0,0,0"], "--camera y"),
        render("camera four numbers", &["--camera=0,1,0,0"], "five numbers"),
        render(
            "camera six numbers",
            &["--camera=0,1,0,0,0,0"],
            "five numbers",
        ),
        render(
            "camera not numbers",
            &["--camera=a,b,c,d,e"],
            "--camera x,y,z,yaw,pitch",
        ),
        render(
            "size 8193x8192",
            &["--size", "8193x8192"],
            "each side must be 1..=8192",
        ),
        render(
            "size 16384x16384",
            &["--size", "16384x16384"],
            "each side must be 1..=8192",
        ),
        render(
            "size 0x10",
            &["--size", "0x10"],
            "each side must be 1..=8192",
        ),
        render(
            "size 10x0",
            &["--size", "10x0"],
            "each side must be 1..=8192",
        ),
        render(
            "size 2^40",
            &["--size", "1099511627776x1"],
            "each side must be 1..=8192",
        ),
        render(
            "size words",
            &["--size", "bigxsmall"],
            "expected WIDTHxHEIGHT",
        ),
        render(
            "size one number",
            &["--size", "640"],
            "expected WIDTHxHEIGHT",
        ),
        render("fov 0", &["--fov", "0"], "--fov must be"),
        render("fov 170", &["--fov", "170"], "--fov must be"),
        render("fov NaN", &["--fov", "NaN"], "--fov must be"),
        render("fov -inf", &["--fov=-inf"], "--fov must be"),
        render(
            "face-res 0",
            &["--face-res", "0"],
            "face resolution must be within 8..=2048",
        ),
        render(
            "face-res 7",
            &["--face-res", "7"],
            "face resolution must be within 8..=2048",
        ),
        render(
            "face-res 4096",
            &["--face-res", "4096"],
            "face resolution must be within 8..=2048",
        ),
        render(
            "schedule unknown",
            &["--schedule", "fast"],
            "--schedule must be",
        ),
        case(
            "play size 16384x16384",
            &["play", s(&stone), "--size", "16384x16384"],
            "1..=8192",
        ),
        case(
            "play size 0x0",
            &["play", s(&stone), "--size", "0x0"],
            "1..=8192",
        ),
    ];
    assert!(cases.len() >= 30, "{} command-line cases", cases.len());
    run_catalogue(&cases);
    assert!(
        !out.exists(),
        "nothing may be written before the arguments are checked"
    );
}
