//! `oficina carve` end to end: the real binary on a generated picture, its files and
//! figures checked against independent readings of the program; bad pictures refused with
//! clear errors and no panic.

mod common;

use common::oficina;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const W: u32 = 60;
const H: u32 = 40;
const PIXEL: f64 = 0.5;
const DEPTH: f64 = 3.0;

/// Gray level of the test picture: a dark dome off-centre on white.
fn gray(x: u32, y: u32) -> u8 {
    let (dx, dy) = (x as f64 - 22.0, y as f64 - 18.0);
    let d = (dx * dx + dy * dy).sqrt() / 16.0;
    (255.0 * d.min(1.0)).round() as u8
}

/// The design as the importer must map it: black = −DEPTH, image row 0 at the largest Y.
fn design_z(ix: u32, iy: u32) -> f64 {
    -(255.0 - gray(ix, H - 1 - iy) as f64) / 255.0 * DEPTH
}

/// `oficina carve PICTURE --pixel-size 0.5 -o OUT` with `extra` options.
fn carve(picture: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "carve",
        picture.to_str().unwrap(),
        "--pixel-size",
        "0.5",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    oficina(&args)
}

fn profile() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../profiles/grbl-router.toml")
        .display()
        .to_string()
}

fn write_picture(dir: &Path) -> PathBuf {
    let path = dir.join("dome.png");
    image::ImageBuffer::from_fn(W, H, |x, y| image::Luma([gray(x, y)]))
        .save(&path)
        .unwrap();
    path
}

/// Tool-tip positions every 0.1 mm along the program's straight moves, and the feed-only
/// seconds: an independent reading of the words the post writes.
fn positions(program: &str) -> (Vec<[f64; 3]>, f64) {
    let (mut pos, mut feed, mut modal) = ([0.0f64; 3], 0.0f64, 0);
    let (mut out, mut seconds) = (Vec::new(), 0.0);
    for line in program.lines().filter(|l| !l.starts_with('(')) {
        let mut to = pos;
        let mut moved = false;
        for word in line.split_whitespace() {
            let (letter, value) = word.split_at(1);
            match letter {
                "G" => modal = value.parse().unwrap_or(modal),
                "F" => feed = value.parse().unwrap(),
                "X" | "Y" | "Z" => {
                    to["XYZ".find(letter).unwrap()] = value.parse().unwrap();
                    moved = true;
                }
                _ => {}
            }
        }
        if !moved {
            continue;
        }
        assert!(modal <= 1, "only G0/G1 expected: {line}");
        let len = (0..3).map(|k| (to[k] - pos[k]).powi(2)).sum::<f64>().sqrt();
        // The estimate's convention: feeds as programmed, rapids at 6000 mm/min.
        seconds += len / if modal == 1 { feed } else { 6000.0 } * 60.0;
        let n = (len / 0.1).ceil().max(1.0) as usize;
        for s in 0..=n {
            let t = s as f64 / n as f64;
            out.push([0, 1, 2].map(|k| pos[k] + (to[k] - pos[k]) * t));
        }
        pos = to;
    }
    (out, seconds)
}

fn hms_seconds(text: &str) -> f64 {
    let p: Vec<f64> = text.split(':').map(|v| v.parse().unwrap()).collect();
    p[0] * 3600.0 + p[1] * 60.0 + p[2]
}

#[test]
fn carves_a_picture_into_program_preview_and_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let picture = write_picture(dir.path());
    let out = dir.path().join("dome.nc");
    let run = carve(
        &picture,
        &out,
        &[
            "--depth",
            "3",
            "--tool",
            "ball:3",
            "--rough-tool",
            "flat:6",
            "--profile",
            &profile(),
        ],
    );
    let stdout = oficina_testkit::assert_success(&run);

    let program = std::fs::read_to_string(&out).unwrap();
    assert!(
        program.contains("(grid = 60 x 40 samples, 0.5 mm per pixel)"),
        "{program:.600}"
    );
    assert!(program.contains("(command = "), "{program:.600}");
    // Readable settings, one per line, never a Rust value dumped.
    assert!(program.contains("(rough tool = flat:6)"), "{program:.900}");
    assert!(program.contains("(tool = ball:3)"), "{program:.900}");
    assert!(
        program.contains("(depth = 3 mm at black)"),
        "{program:.900}"
    );
    assert!(
        !program.contains("Args {") && !program.contains("Some("),
        "{program:.900}"
    );
    assert!(program.contains("T1\n") && program.contains("T2\nM0"));
    assert!(program.trim_end().ends_with("M30"));

    // Beside the program, never over the design (here dome.png, the same stem as dome.nc).
    let preview = out.with_extension("preview.png");
    let shaded = image::open(&preview).expect("the preview decodes");
    let design_after = image::open(&picture).expect("the design is untouched");
    assert_ne!(
        shaded.to_rgb8().into_raw(),
        design_after.to_rgb8().into_raw()
    );
    assert_eq!((shaded.width(), shaded.height()), (W, H));

    // Printed figures: zero gouge, and the feed-only time equals the one read here.
    assert!(stdout.contains("max gouge: 0.0000"), "{stdout}");
    assert!(stdout.contains("time: planner "), "{stdout}");
    let feed_only = stdout
        .split("feed-only ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .expect("feed-only time printed");
    let (points, seconds) = positions(&program);
    assert!(
        (hms_seconds(feed_only) - seconds).abs() <= 1.0,
        "printed {feed_only}, read {seconds:.1} s"
    );

    // Independent gouge check with the 3 mm ball's profile at every position (for the 6 mm
    // flat's positions a weaker but still necessary condition): never more than 1 µm below
    // a design sample.
    let r = 1.5;
    let mut deepest = 0.0f64;
    for p in &points {
        let (cx, cy) = (p[0] / PIXEL, p[1] / PIXEL);
        let reach = (r / PIXEL).ceil() as i64;
        for iy in (cy.round() as i64 - reach)..=(cy.round() as i64 + reach) {
            for ix in (cx.round() as i64 - reach)..=(cx.round() as i64 + reach) {
                if ix < 0 || iy < 0 || ix >= W as i64 || iy >= H as i64 {
                    continue;
                }
                let d = ((ix as f64 * PIXEL - p[0]).powi(2) + (iy as f64 * PIXEL - p[1]).powi(2))
                    .sqrt();
                if d <= r {
                    let bottom = p[2] + r - (r * r - d * d).sqrt();
                    deepest = deepest.max(design_z(ix as u32, iy as u32) - bottom);
                }
            }
        }
    }
    assert!(
        deepest < 1e-3,
        "a tool position cuts {deepest} mm below the design"
    );
}

fn refused(bytes: &[u8], name: &str, expect: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let out = dir.path().join("x.nc");
    let run = carve(&path, &out, &[]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{name}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains(name),
        "{name}: message names the file: {stderr}"
    );
    assert!(
        stderr.contains(expect),
        "{name}: want '{expect}' in: {stderr}"
    );
    assert!(!out.exists(), "{name}: no program for a refused picture");
}

/// CRC-32 (IEEE) of a PNG chunk's type and data, computed here bit by bit.
fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[test]
fn bad_pictures_get_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(write_picture(dir.path())).unwrap();
    refused(&[], "empty.png", "empty (0 bytes)");
    refused(
        &good[..good.len() * 2 / 3],
        "truncated.png",
        "cannot decode",
    );
    refused(
        b"P5 this is not a picture at all",
        "notes.png",
        "not a readable PNG",
    );

    // A valid signature and IHDR (with its CRC) claiming 100000 x 100000, then nothing:
    // the memory budget must refuse it before any decoding is tried.
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(100_000u32.to_be_bytes());
    ihdr.extend(100_000u32.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]);
    let mut huge = b"\x89PNG\r\n\x1a\n".to_vec();
    huge.extend(13u32.to_be_bytes());
    huge.extend(&ihdr);
    huge.extend(crc32(&ihdr).to_be_bytes());
    assert_eq!(
        crc32(&good[12..29]),
        u32::from_be_bytes(good[29..33].try_into().unwrap())
    );
    refused(&huge, "huge.png", "100000 × 100000 pixels");
}

#[test]
fn missing_arguments_are_usage_errors() {
    let run = oficina(&["carve", "nothing.png", "-o", "/tmp/never.nc"]);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("--pixel-size"));
    let run = oficina(&["carve", "--tool", "cone:3"]);
    assert_ne!(run.status.code(), Some(0));
}

#[test]
fn an_output_that_would_replace_the_design_image_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let picture = write_picture(dir.path());
    let before = std::fs::read(&picture).unwrap();
    let run = carve(
        &picture,
        &dir.path().join("out.nc"),
        &[
            "--depth",
            "3",
            "--tool",
            "ball:3",
            "--profile",
            &profile(),
            "--preview",
            picture.to_str().unwrap(),
        ],
    );
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(err.contains("is the input image"), "{err}");
    assert_eq!(
        std::fs::read(&picture).unwrap(),
        before,
        "the design must not change"
    );
}

/// A gray picture of `w` × `h` pixels with a dark spot, as PNG.
fn small_picture(dir: &Path, w: u32, h: u32) -> PathBuf {
    let path = dir.join(format!("p{w}x{h}.png"));
    image::ImageBuffer::from_fn(w, h, |x, y| image::Luma([((x * 37 + y * 91) % 256) as u8]))
        .save(&path)
        .unwrap();
    path
}

/// Runs `oficina` with its address space capped at `limit` bytes: a command that tried to
/// grow past its memory budget would die here instead of thrashing the machine.
fn oficina_capped(args: &[&str], cwd: &Path, limit: u64) -> Output {
    use std::os::unix::process::CommandExt;
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_oficina"));
    cmd.args(args).current_dir(cwd);
    // SAFETY: setrlimit is async-signal-safe; nothing else runs between fork and exec.
    unsafe {
        cmd.pre_exec(move || {
            nix::sys::resource::setrlimit(nix::sys::resource::Resource::RLIMIT_AS, limit, limit)
                .map_err(std::io::Error::from)
        });
    }
    cmd.output().expect("the binary runs")
}

#[test]
fn degenerate_pictures_tools_and_steps_carve_without_panic() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.nc");
    for (w, h) in [(1, 1), (1, 5), (5, 1), (2, 2), (1, 40), (40, 1)] {
        let picture = small_picture(dir.path(), w, h);
        for extra in [
            &["--tool", "ball:3"][..],
            &["--tool", "flat:100", "--rough-tool", "flat:150"],
            &[
                "--tool",
                "v:30:60",
                "--stepover",
                "1000",
                "--stepdown",
                "1000",
            ],
            &[
                "--tool",
                "ball:3",
                "--rough-tool",
                "flat:6",
                "--direction",
                "both",
            ],
        ] {
            let mut opts = vec!["--depth", "5"];
            opts.extend_from_slice(extra);
            let run = carve(&picture, &out, &opts);
            let err = String::from_utf8_lossy(&run.stderr);
            assert!(
                run.status.success() && !err.contains("panicked"),
                "{w} x {h} {extra:?}: {err}"
            );
            let program = std::fs::read_to_string(&out).unwrap();
            assert!(program.trim_end().ends_with("M30"), "{w} x {h} {extra:?}");
        }
    }
}

#[test]
fn absurd_sizes_are_refused_with_the_option_that_changes_them() {
    let dir = tempfile::tempdir().unwrap();
    let dome = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/relief/dome.png");
    let out = dir.path().join("x.nc");
    let cases: [(&[&str], &[&str]); 4] = [
        (&["--pixel-size", "1000000"], &["wide", "--pixel-size"]),
        (
            &["--pixel-size", "0.5", "--depth", "1000000"],
            &["deep", "--depth"],
        ),
        // 18000 levels of 5 mm: within the machine's size, not within 256 MB of moves.
        (
            &[
                "--pixel-size",
                "0.5",
                "--depth",
                "90000",
                "--memory-mb",
                "256",
            ],
            &[
                "MB",
                "over the memory budget of 256 MB",
                "--stepdown",
                "--memory-mb",
            ],
        ),
        // A grid too large for the simulation and preview within 1 MB.
        (
            &["--pixel-size", "0.5", "--memory-mb", "1"],
            &["over the memory budget of 1.0 MB", "--memory-mb"],
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec!["carve", dome.to_str().unwrap(), "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let run = oficina_capped(&args, dir.path(), 1 << 31);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{extra:?}: {err}");
        for w in want {
            assert!(err.contains(w), "{extra:?}: want '{w}' in {err}");
        }
        assert!(!out.exists(), "{extra:?}: no program");
    }
}

#[test]
fn profiles_are_found_by_name_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    let picture = small_picture(dir.path(), 12, 10);
    let out = dir.path().join("x.nc");
    // The default profile, and a bundled name, from a folder that holds no profiles/.
    for extra in [&[][..], &["--profile", "grbl-router"]] {
        let mut args = vec![
            "carve",
            picture.to_str().unwrap(),
            "--pixel-size",
            "0.5",
            "--depth",
            "2",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let run = oficina_capped(&args, dir.path(), 1 << 32);
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert!(
            run.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert!(stdout.contains("time: planner "), "{extra:?}: {stdout}");
    }
    let run = carve(&picture, &out, &["--profile", "no-such-router"]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(
        err.contains("no-such-router") && err.contains("grbl-router"),
        "{err}"
    );

    let run = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args([
            "emulate",
            "grbl",
            "--tcp",
            "127.0.0.1:0",
            "--profile",
            "grbl-router",
            "--for-seconds",
            "0.2",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    oficina_testkit::assert_success(&run);
}

/// The bundled sample is a dome: where the carved program's tool tip goes lowest, cell by
/// cell (2 mm), the centre stands highest and the corners are at full depth.
#[test]
fn the_bundled_dome_sample_carves_a_dome() {
    let dir = tempfile::tempdir().unwrap();
    let dome = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/relief/dome.png");
    let out = dir.path().join("dome.nc");
    let run = carve(
        &dome,
        &out,
        &["--depth", "6", "--tool", "ball:3", "--rough-tool", "flat:6"],
    );
    oficina_testkit::assert_success(&run);
    let (points, _) = positions(&std::fs::read_to_string(&out).unwrap());
    let picture = image::open(&dome).unwrap();
    let (w, h) = (
        (picture.width() - 1) as f64 * 0.5,
        (picture.height() - 1) as f64 * 0.5,
    );
    let cell = 2.0;
    let (nx, ny) = ((w / cell).ceil() as usize, (h / cell).ceil() as usize);
    // Untouched cells stand at the stock top.
    let mut lowest = vec![0.0f64; nx * ny];
    for p in &points {
        let (ix, iy) = ((p[0] / cell) as usize, (p[1] / cell) as usize);
        if ix < nx && iy < ny {
            let c = &mut lowest[iy * nx + ix];
            *c = c.min(p[2]);
        }
    }
    let centre = lowest[(ny / 2) * nx + nx / 2];
    let highest = lowest.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    assert!(
        centre >= highest - 0.05,
        "the centre ({centre}) must be the highest point ({highest})"
    );
    assert!(
        centre > -1.0,
        "the dome's top is near the stock top: {centre}"
    );
    for corner in [0, nx - 1, (ny - 1) * nx, ny * nx - 1] {
        assert!(lowest[corner] < -5.5, "corner at {}", lowest[corner]);
    }
}
