//! `oficina plot PICTURE --fill …`: pictures hatched as shapes are filled, measured from the
//! G-code's pen-down moves, not from our hatcher: the ink laid per area of paper against the
//! picture's darkness there (read with the `image` crate), concentric rings of a drawn disc
//! and ring (their radii from the known centre), and the pens of the darkness bands.

mod common;
use common::{oficina, pen_down_path, text, word};
use std::path::{Path, PathBuf};

/// Paper mm per pixel in every run here.
const PIXEL: f64 = 0.5;

/// The pen-down polylines of a Z-lift program (Z ≤ 0 is down).
fn ink(program: &str) -> Vec<Vec<[f64; 2]>> {
    pen_down_path(program, |l| word(l, 'Z').map(|z| z <= 0.0))
}

/// `oficina plot PICTURE args… -o F` (scale 1, so the G-code is in the picture's mm, its
/// lower-left corner at the origin): the program, or the failure's stderr.
fn plot(picture: &Path, args: &[&str]) -> Result<String, String> {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("p.nc");
    let px = PIXEL.to_string();
    let mut all = vec![
        "plot",
        picture.to_str().unwrap(),
        "--pixel",
        &px,
        "-o",
        nc.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let o = oficina(&all);
    if !o.status.success() {
        return Err(text(&o).1);
    }
    Ok(std::fs::read_to_string(nc).unwrap())
}

/// Darkness 0 (white) … 1 (black) of each pixel, row 0 at the top.
struct Picture {
    w: usize,
    h: usize,
    dark: Vec<f64>,
}

fn read(path: &Path) -> Picture {
    let g = image::open(path).unwrap().to_luma8();
    Picture {
        w: g.width() as usize,
        h: g.height() as usize,
        dark: g.pixels().map(|p| 1.0 - p.0[0] as f64 / 255.0).collect(),
    }
}

/// A picture made here, `dark(x, y)` in mm from its lower-left corner, saved as PNG.
fn synthetic(name: &str, w: u32, h: u32, dark: impl Fn(f64, f64) -> f64) -> PathBuf {
    let img = image::GrayImage::from_fn(w, h, |c, r| {
        // Four samples a pixel: an anti-aliased edge, as a scanned or rendered picture has.
        let mut d = 0.0;
        for (sx, sy) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
            let x = (c as f64 + sx) * PIXEL;
            let y = (h as f64 - r as f64 - sy) * PIXEL;
            d += dark(x, y).clamp(0.0, 1.0) / 4.0;
        }
        image::Luma([(255.0 * (1.0 - d)).round() as u8])
    });
    let path = oficina_testkit::scratch_dir("plot_image_hatch").join(name);
    img.save(&path).unwrap();
    path
}

/// Every pen-down segment cut into pieces of at most 0.02 mm: (midpoint, length).
fn pieces(strokes: &[Vec<[f64; 2]>]) -> Vec<([f64; 2], f64)> {
    let mut out = Vec::new();
    for s in strokes {
        for w in s.windows(2) {
            let (a, b) = (w[0], w[1]);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            let n = (len / 0.02).ceil().max(1.0) as usize;
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64;
                let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                out.push((p, len / n as f64));
            }
        }
    }
    out
}

/// Ink (mm of line per mm² of paper) over the cells of `cell` mm whose mean darkness falls in
/// each of `bins` equal bins, with the number of cells: the paper rasterised at `cell`.
fn density_by_darkness(
    pic: &Picture,
    strokes: &[Vec<[f64; 2]>],
    cell: usize,
    bins: usize,
) -> Vec<(f64, usize)> {
    let (cw, ch) = (pic.w / cell, pic.h / cell);
    let size = cell as f64 * PIXEL;
    let hmm = pic.h as f64 * PIXEL;
    let mut ink = vec![0.0; cw * ch];
    for (p, len) in pieces(strokes) {
        let (c, r) = ((p[0] / size).floor(), ((hmm - p[1]) / size).floor());
        if c >= 0.0 && r >= 0.0 && (c as usize) < cw && (r as usize) < ch {
            ink[r as usize * cw + c as usize] += len;
        }
    }
    let mut sum = vec![(0.0, 0usize); bins];
    for r in 0..ch {
        for c in 0..cw {
            let mut d = 0.0;
            for y in r * cell..(r + 1) * cell {
                for x in c * cell..(c + 1) * cell {
                    d += pic.dark[y * pic.w + x];
                }
            }
            d /= (cell * cell) as f64;
            let b = ((d * bins as f64) as usize).min(bins - 1);
            sum[b].0 += ink[r * cw + c];
            sum[b].1 += 1;
        }
    }
    sum.into_iter()
        .map(|(l, n)| (l / (n.max(1) as f64 * size * size), n))
        .collect()
}

fn pictures() -> Vec<PathBuf> {
    // A ramp, white at the left to black at the right, 100 × 20 mm.
    let mut v = vec![synthetic("ramp.png", 200, 40, |x, _| x / 100.0)];
    if let Some(dir) = oficina_testkit::realworld("relief-images") {
        v.push(dir.join("osc_smiley.png"));
        v.push(dir.join("lcnc_torus.png"));
    }
    v
}

#[test]
fn ink_per_area_rises_with_darkness_parallel_and_concentric() {
    // Three bands (darkness over 1/4, 1/2, 3/4) at 1 mm: 0, 1, 2, 3 mm of line per mm² (twice
    // that cross-hatched). Cells of 2 mm (4 × 4 pixels) binned by their darkness in quarters:
    // each quarter's ink must exceed the lighter one's, the white quarter nearly none; the
    // parallel lines lay k mm/mm² within 10 % in quarter k (a cell astride a band's edge
    // averages two bands). Concentric rings stand a spacing in from every edge of a band, so
    // thin bands (the anti-aliased rims of a drawing's strokes) get fewer: only the order holds.
    for pic in pictures() {
        let p = read(&pic);
        for mode in [&[][..], &["--fill-concentric"][..], &["--fill-cross"][..]] {
            let mut args = vec!["--fill", "--fill-spacing", "1", "--hatch-layers", "3"];
            args.extend_from_slice(mode);
            let program = plot(&pic, &args).unwrap();
            let d = density_by_darkness(&p, &ink(&program), 4, 4);
            eprintln!("{} {mode:?}: {d:?}", pic.display());
            let per = if mode == ["--fill-cross"] { 2.0 } else { 1.0 };
            let filled: Vec<&(f64, usize)> = d.iter().filter(|(_, n)| *n >= 10).collect();
            assert!(filled.len() >= 2, "{}: {d:?}", pic.display());
            for w in filled.windows(2) {
                assert!(w[1].0 > w[0].0 * 1.2, "{} {mode:?}: {d:?}", pic.display());
            }
            assert!(d[0].0 < 0.1 * per, "{} {mode:?}: {d:?}", pic.display());
            if mode != ["--fill-concentric"] {
                for (k, &(ink, n)) in d.iter().enumerate().skip(1) {
                    let want = k as f64 * per;
                    assert!(
                        n < 100 || (ink / want - 1.0).abs() < 0.1,
                        "{} {mode:?} quarter {k}: {ink} mm/mm², want {want}: {d:?}",
                        pic.display()
                    );
                }
            }
        }
    }
}

/// Radii of the strokes' points about `c`: per stroke (min, max, mean).
fn radii(strokes: &[Vec<[f64; 2]>], c: [f64; 2]) -> Vec<(f64, f64, f64)> {
    strokes
        .iter()
        .map(|s| {
            let r: Vec<f64> = s.iter().map(|p| (p[0] - c[0]).hypot(p[1] - c[1])).collect();
            let (lo, hi) = r
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
            (lo, hi, r.iter().sum::<f64>() / r.len() as f64)
        })
        .collect()
}

#[test]
fn concentric_rings_of_a_disc_and_a_ring_are_circles_inside_them_holes_empty() {
    // A black disc of radius 15 mm centred in 50 × 50 mm, and a black ring 6…15 mm.
    let c = [25.0, 25.0];
    let r = |x: f64, y: f64| (x - c[0]).hypot(y - c[1]);
    let disc = synthetic("disc.png", 100, 100, |x, y| (15.0 - r(x, y)) * 2.0 + 0.5);
    let ring = synthetic("ring.png", 100, 100, |x, y| {
        ((15.0 - r(x, y)).min(r(x, y) - 6.0)) * 2.0 + 0.5
    });
    let args = [
        "--fill",
        "--fill-concentric",
        "--fill-spacing",
        "1",
        "--hatch-layers",
        "1",
    ];
    // The disc: rings inset 1, 2, … 14 mm, each a circle (radius spread under 0.1 mm).
    let rs = radii(&ink(&plot(&disc, &args).unwrap()), c);
    let mut means: Vec<f64> = rs.iter().map(|r| r.2).collect();
    means.sort_by(f64::total_cmp);
    assert_eq!(means.len(), 14, "{rs:?}");
    for (i, &(lo, hi, mean)) in rs.iter().enumerate() {
        assert!(hi - lo < 0.1, "ring {i}: radii {lo}…{hi}");
        assert!(
            hi < 15.0 - 1.0 + 0.05,
            "ring {i} past the first inset: {hi}"
        );
        let k = (15.0 - mean).round();
        assert!(
            (15.0 - k - mean).abs() < 0.05,
            "ring {i}: mean radius {mean}"
        );
    }
    // The ring: circles about the centre between 6 and 15 mm, none in the hole; parallel
    // lines too stay in the ring.
    let rs = radii(&ink(&plot(&ring, &args).unwrap()), c);
    assert!(rs.len() >= 8, "{rs:?}");
    for &(lo, hi, _) in &rs {
        assert!(
            hi - lo < 0.1 && lo > 6.0 + 1.0 - 0.05 && hi < 15.0 - 1.0 + 0.05,
            "{rs:?}"
        );
    }
    let lines = ink(&plot(
        &ring,
        &["--fill", "--fill-spacing", "0.5", "--hatch-layers", "1"],
    )
    .unwrap());
    let pts = pieces(&lines);
    assert!(pts.len() > 1000);
    for (p, _) in pts {
        let d = r(p[0], p[1]);
        assert!(
            d > 6.0 - 0.1 && d < 15.0 + 0.1,
            "a hatch line at {p:?}, {d} mm from the centre"
        );
    }
}

#[test]
fn darkness_bands_go_to_their_pens_and_bad_pens_are_refused() {
    // The ramp in two bands (darkness over 1/3 and over 2/3): the light pen draws between 1/3
    // and 2/3 of the width, the dark pen beyond, and the program changes pens between them.
    let ramp = synthetic("ramp2.png", 200, 40, |x, _| x / 100.0);
    let program = plot(
        &ramp,
        &[
            "--fill",
            "--hatch-layers",
            "2",
            "--image-pens",
            "#999999,#000000",
        ],
    )
    .unwrap();
    let (light, dark) = program
        .split_once("M0 (MSG, pen 2: #000000)")
        .expect("a pen change to the second pen");
    assert!(light.contains("(pen 1: #999999)"), "{program}");
    let xs = |p: &str| -> Vec<f64> { pieces(&ink(p)).iter().map(|(p, _)| p[0]).collect() };
    let (l, d) = (xs(light), xs(dark));
    assert!(!l.is_empty() && !d.is_empty());
    assert!(
        l.iter()
            .all(|&x| x > 100.0 / 3.0 - 0.5 && x < 200.0 / 3.0 + 0.5),
        "{l:?}"
    );
    assert!(d.iter().all(|&x| x > 200.0 / 3.0 - 0.5), "{d:?}");
    // More pens than bands, an empty name, too many bands: refused, naming the flag.
    for (args, flag) in [
        (
            &["--fill", "--hatch-layers", "2", "--image-pens", "a,b,c"][..],
            "--image-pens",
        ),
        (
            &["--hatch-layers", "2", "--image-pens", "a,,b"][..],
            "--image-pens",
        ),
        (&["--fill", "--hatch-layers", "9"][..], "--hatch-layers"),
        (&["--fill", "--fill-spacing", "0.001"][..], "--fill-spacing"),
    ] {
        let e = plot(&ramp, args).unwrap_err();
        assert!(e.contains(flag), "{args:?}: {e}");
    }
}

#[test]
fn a_noisy_picture_is_drawn_or_refused_by_its_flag() {
    // White noise: every band a maze of specks and holes. Detail under a
    // spacing square is dropped, so it is drawn (or refused by the spacing), never a panic.
    let mut rng = oficina_testkit::random::Xorshift::new(7);
    let img =
        image::GrayImage::from_fn(200, 200, |_, _| image::Luma([(rng.next_u64() % 256) as u8]));
    let path = oficina_testkit::scratch_dir("plot_image_noise").join("noise.png");
    img.save(&path).unwrap();
    for mode in [&[][..], &["--fill-concentric"][..]] {
        let mut args = vec!["--fill", "--fill-spacing", "0.3"];
        args.extend_from_slice(mode);
        match plot(&path, &args) {
            Ok(program) => assert!(!ink(&program).is_empty()),
            Err(e) => assert!(e.contains("--fill-spacing"), "{mode:?}: {e}"),
        }
    }
}
