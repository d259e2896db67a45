//! DXF text drawn with the single-stroke font. Where ezdxf placed each string (its TEXT's
//! first point and height) is compared in dxf_vs_ezdxf.rs; here the strokes drawn for each
//! TEXT of the real files are measured in the string's own frame: they start at its point,
//! their capitals are its height tall, they run along its rotation, and their length is
//! within reach of the same string set in DejaVu Sans at that cap height (ezdxf's font
//! measurement, when python3 and ezdxf are there).

use oficina_geom::{Point, Vec2};
use oficina_io::{read_dxf, DxfOptions, DxfRead, DxfText};
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

fn pairs(p: &[(&str, &str)]) -> String {
    p.iter().map(|(c, v)| format!("{c}\n{v}\n")).collect()
}

fn data(name: &str) -> Vec<u8> {
    std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/dxf")
            .join(name),
    )
    .unwrap()
}

fn no_limit() -> DxfOptions {
    DxfOptions {
        max_size_mm: f64::INFINITY,
        ..DxfOptions::default()
    }
}

/// Points drawn for `t` (paths whose source is its entity), in the string's frame: x along
/// the baseline from its start, y up from the baseline, both in text heights.
fn frame(r: &DxfRead, t: &DxfText) -> Vec<Point> {
    let (dir, up) = (
        Vec2::from_angle(t.angle),
        Vec2::from_angle(t.angle + std::f64::consts::FRAC_PI_2),
    );
    r.imported
        .drawing
        .paths()
        .filter(|p| p.source.element == t.source.element && p.source.line == t.source.line)
        .flat_map(|p| p.flatten(1e-4 * t.height))
        .map(|p| {
            let d = p - t.at;
            Point::new(d.dot(dir) / t.height, d.dot(up) / t.height)
        })
        .collect()
}

/// Widths of the strings in DejaVu Sans with capitals 1 tall, from ezdxf's font tools.
fn dejavu_widths(strings: &[String]) -> Option<Vec<f64>> {
    let script = "import sys, json\nfrom ezdxf.fonts import fonts\n\
        f = fonts.make_font('DejaVuSans.ttf', 1.0)\n\
        print(json.dumps([f.text_width(s) for s in json.load(sys.stdin)]))\n";
    let mut child = Command::new("python3")
        .args(["-c", script])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| eprintln!("note: python3 cannot be run: {e}"))
        .ok()?;
    let input = serde_json::to_string(strings).unwrap();
    child.stdin.take()?.write_all(input.as_bytes()).ok()?;
    let out = child.wait_with_output().ok()?;
    if !out.status.success() {
        eprintln!(
            "note: no DejaVu widths from ezdxf: {}",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        );
        return None;
    }
    serde_json::from_slice(&out.stdout).ok()
}

#[test]
fn text_of_real_files_is_drawn_at_its_point_height_and_rotation() {
    let (mut checked, mut turned) = (0, 0);
    let mut strings: Vec<String> = Vec::new();
    let mut ours: Vec<f64> = Vec::new();
    for name in [
        "made_by_ezdxf.dxf",
        "made_by_ezdxf_binary.dxf",
        "ezdxf_insert_bricscad_level_1.dxf",
        "ezdxf_dimension_in_nested_blocks.dxf",
    ] {
        let r = read_dxf(&data(name), name, &no_limit()).unwrap();
        assert!(!r.texts.is_empty(), "{name}");
        let not_drawn = r
            .imported
            .unsupported
            .counts
            .keys()
            .filter(|k| k.contains("text is not drawn"))
            .count();
        assert_eq!(not_drawn, 0, "{name}: {}", r.imported.unsupported);
        // A TEXT in a block inserted several times has one source for all its copies: those
        // with a source of their own are measured.
        let once = |t: &DxfText| r.texts.iter().filter(|u| u.source == t.source).count() == 1;
        for t in r
            .texts
            .iter()
            .filter(|t| t.source.element.starts_with("TEXT") && once(t))
        {
            let pts = frame(&r, t);
            if t.text.trim().is_empty() {
                assert!(pts.is_empty(), "{name}: {t:?}");
                continue;
            }
            assert!(!pts.is_empty(), "{name}: nothing drawn for {t:?}");
            let (x0, x1, y0, y1) = pts.iter().fold(
                (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
                |(a, b, c, d), p| (a.min(p.x), b.max(p.x), c.min(p.y), d.max(p.y)),
            );
            // Starts at the point (a glyph's left side bearing is under a third of a height),
            // stands on the baseline (descenders reach a third of a height below).
            assert!((-0.01..0.35).contains(&x0), "{name}: {t:?} starts at {x0}");
            assert!(y0 > -0.4 && y1 < 1.4, "{name}: {t:?} from {y0} to {y1}");
            let plain = t
                .text
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || " .,=-_:".contains(c));
            if plain
                && t.text
                    .chars()
                    .any(|c| c.is_ascii_uppercase() || c.is_ascii_digit())
            {
                // Capitals and digits are the text's height tall, within 5 % (brackets and
                // such reach higher).
                assert!((y1 - 1.0).abs() < 0.05, "{name}: {t:?} tops at {y1}");
            }
            strings.push(t.text.clone());
            ours.push(x1);
            checked += 1;
            turned += usize::from(t.angle.abs() > 1e-6);
        }
    }
    assert!(checked >= 12, "{checked} {turned}");
    let Some(theirs) = dejavu_widths(&strings) else {
        return;
    };
    // Roman Simplex is a little wider than DejaVu Sans at one cap height; a string drawn at
    // the wrong size or with lost letters falls outside this band.
    for ((s, a), b) in strings.iter().zip(&ours).zip(&theirs) {
        let ratio = a / b;
        eprintln!("{s:?}: {a:.3} heights long, DejaVu Sans {b:.3} ({ratio:.3})");
        assert!(
            (0.9..1.35).contains(&ratio),
            "{s:?}: {a:.3} heights long, DejaVu Sans {b:.3}"
        );
    }
}

#[test]
fn text_options_and_bad_text_are_reported_not_fatal() {
    let text = |h: &str, s: &str| {
        pairs(&[
            ("0", "SECTION"),
            ("2", "ENTITIES"),
            ("0", "TEXT"),
            ("5", "A1"),
            ("8", "marks"),
            ("10", "10"),
            ("20", "5"),
            ("40", h),
            ("1", s),
            ("0", "ENDSEC"),
            ("0", "EOF"),
        ])
    };
    let read = |h: &str, s: &str| read_dxf(text(h, s).as_bytes(), "t.dxf", &DxfOptions::default());
    // Turned 30° (group 50): the strokes run along the turned baseline, capitals 4 tall.
    let turned = text("4", "HE").replace("40\n4\n", "40\n4\n50\n30\n");
    let r = read_dxf(turned.as_bytes(), "t.dxf", &DxfOptions::default()).unwrap();
    let t = &r.texts[0];
    assert!((t.angle - 30f64.to_radians()).abs() < 1e-12);
    let pts = frame(&r, t);
    let (x0, y0, y1) = pts
        .iter()
        .fold((f64::MAX, f64::MAX, f64::MIN), |(a, c, d), p| {
            (a.min(p.x), c.min(p.y), d.max(p.y))
        });
    assert!((0.0..0.35).contains(&x0) && y0.abs() < 1e-9 && (y1 - 1.0).abs() < 1e-9);
    // Drawn on its layer, sourced to its entity.
    let r = read("4", "AB").unwrap();
    let paths: Vec<_> = r.imported.drawing.paths().collect();
    assert!(paths.len() >= 3, "{paths:?}");
    assert!(r.imported.drawing.layers.iter().all(|l| l.name == "marks"));
    assert!(paths.iter().all(|p| p.source.element == "TEXT #A1"));
    assert!(
        r.imported.unsupported.is_empty(),
        "{}",
        r.imported.unsupported
    );
    // Asked not to, it is skipped with the reason, and still placed.
    let off = DxfOptions {
        draw_text: false,
        ..DxfOptions::default()
    };
    let r = read_dxf(text("4", "AB").as_bytes(), "t.dxf", &off).unwrap();
    assert_eq!(r.imported.drawing.path_count(), 0);
    assert_eq!(r.imported.unsupported.counts["TEXT (text is not drawn)"], 1);
    assert_eq!(r.texts.len(), 1);
    // Characters the font lacks are drawn as '?' and listed with the entity.
    let r = read("4", "A→B").unwrap();
    let u = &r.imported.unsupported;
    let k = "TEXT (characters without a glyph, drawn as '?')";
    assert_eq!(u.counts[k], 1, "{u}");
    assert!(u.examples[k][0].contains("#A1") && u.examples[k][0].contains('→'));
    let with_q = read("4", "A?B").unwrap().imported.drawing;
    assert_eq!(
        r.imported.drawing.bounding_box(),
        with_q.bounding_box(),
        "drawn as '?'"
    );
    // Empty, blank, no height: nothing drawn, no panic; no height is named.
    for s in ["", "   "] {
        assert_eq!(read("4", s).unwrap().imported.drawing.path_count(), 0);
    }
    let r = read("0", "AB").unwrap();
    assert_eq!(r.imported.drawing.path_count(), 0);
    assert_eq!(r.imported.unsupported.counts["TEXT (text of no height)"], 1);
    // A huge height makes a drawing too large for its units: refused with the hint.
    let e = read("1e9", "AB").unwrap_err();
    assert!(e.message.contains("units"), "{e}");
}

#[test]
fn justified_text_and_mtext_attachments_sit_on_their_points() {
    // "HIH" is symmetric in its cells: centred on a point, its strokes are centred on it.
    fn ent(
        kind: &'static str,
        codes: &[(&'static str, &'static str)],
    ) -> Vec<(&'static str, &'static str)> {
        let mut v = vec![("0", kind), ("8", "0"), ("40", "6")];
        v.extend_from_slice(codes);
        v
    }
    let mut all = vec![("0", "SECTION"), ("2", "ENTITIES")];
    let cases: Vec<Vec<(&str, &str)>> = vec![
        // centre, on the baseline at (100, 0); group 10 where a wider font put its start.
        ent(
            "TEXT",
            &[
                ("5", "C"),
                ("10", "80"),
                ("20", "0"),
                ("11", "100"),
                ("21", "0"),
                ("72", "1"),
                ("1", "HIH"),
            ],
        ),
        // right, at (100, 20)
        ent(
            "TEXT",
            &[
                ("5", "R"),
                ("10", "70"),
                ("20", "20"),
                ("11", "100"),
                ("21", "20"),
                ("72", "2"),
                ("1", "HIH"),
            ],
        ),
        // middle (72 = 4) at (100, 40)
        ent(
            "TEXT",
            &[
                ("5", "M"),
                ("10", "0"),
                ("20", "0"),
                ("11", "100"),
                ("21", "40"),
                ("72", "4"),
                ("1", "HIH"),
            ],
        ),
        // top left at (0, 60), bottom left at (0, 80)
        ent(
            "TEXT",
            &[
                ("5", "T"),
                ("10", "0"),
                ("20", "0"),
                ("11", "0"),
                ("21", "60"),
                ("73", "3"),
                ("1", "HIH"),
            ],
        ),
        ent(
            "TEXT",
            &[
                ("5", "B"),
                ("10", "0"),
                ("20", "0"),
                ("11", "0"),
                ("21", "80"),
                ("73", "1"),
                ("1", "HIH"),
            ],
        ),
        // MTEXT of two lines attached middle centre (5) at (100, 120)
        ent(
            "MTEXT",
            &[
                ("5", "X"),
                ("10", "100"),
                ("20", "120"),
                ("71", "5"),
                ("1", r"HIH\PHIH"),
            ],
        ),
    ];
    for c in &cases {
        all.extend_from_slice(c);
    }
    all.extend_from_slice(&[("0", "ENDSEC"), ("0", "EOF")]);
    let r = read_dxf(pairs(&all).as_bytes(), "j.dxf", &DxfOptions::default()).unwrap();
    let b = |h: &str| {
        bbox_of(
            r.imported
                .drawing
                .paths()
                .filter(|p| p.source.element.ends_with(&format!("#{h}"))),
        )
    };
    let h = 6.0;
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    let c = b("C");
    assert!(near((c.x0 + c.x1) / 2.0, 100.0) && near(c.y0, 0.0), "{c:?}");
    let rt = b("R");
    // Ends at the point less H's right side bearing (4 of its 22 units, cap 21).
    assert!(
        near(rt.x1, 100.0 - 4.0 / 21.0 * h) && near(rt.y0, 20.0),
        "{rt:?}"
    );
    let m = b("M");
    assert!(
        near((m.x0 + m.x1) / 2.0, 100.0) && near((m.y0 + m.y1) / 2.0, 40.0),
        "{m:?}"
    );
    let t = b("T");
    assert!(near(t.y1, 60.0) && t.x0 > 0.0 && t.x0 < 0.35 * h, "{t:?}");
    let bo = b("B");
    assert!(near(bo.y0, 80.0 + h / 3.0), "{bo:?}");
    // The block: first line's capitals on top, the second baseline 5/3 h lower.
    let x = b("X");
    assert!(near(x.height(), h + 5.0 / 3.0 * h), "{x:?}");
    assert!(
        near((x.x0 + x.x1) / 2.0, 100.0) && near((x.y0 + x.y1) / 2.0, 120.0),
        "{x:?}"
    );
}

fn bbox_of<'a>(paths: impl Iterator<Item = &'a oficina_geom::Path>) -> oficina_geom::Rect {
    paths
        .filter_map(|p| p.bounding_box())
        .reduce(|a, b| a.union(b))
        .expect("drawn")
}
