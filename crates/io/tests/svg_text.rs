//! SVG `<text>` drawn with the single-stroke font: placed where SVG places text (x, y, dx,
//! dy, tspans, text-anchor, font-size with units and inheritance, transforms, `<use>`), its
//! capitals as tall as DejaVu Sans's at the same font-size within 5 % and its advances within
//! reach of DejaVu Sans's (read from the font file by fontTools, when python3, fontTools and
//! the font are there), and bad text noted, never fatal.

use oficina_geom::{Color, Path, Rect};
use oficina_io::{read_svg, svg_from_bytes, Imported, SvgOptions};
use std::process::Command;

/// A 200 × 100 mm page with a viewBox in mm, y down; our drawing has y up (y' = 100 − y).
fn page(body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
            xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
            width="200mm" height="100mm" viewBox="0 0 200 100">{body}</svg>"#
    )
}

fn read(body: &str) -> Imported {
    svg_from_bytes(page(body).as_bytes(), "t.svg").unwrap()
}

fn bbox<'a>(paths: impl Iterator<Item = &'a Path>) -> Rect {
    paths
        .filter_map(|p| p.bounding_box())
        .reduce(|a, b| a.union(b))
        .expect("something drawn")
}

fn extents(i: &Imported) -> Rect {
    bbox(i.drawing.paths())
}

/// DejaVu Sans: capital height per em (the top of its H) and the advance of each string in ems (fontTools).
fn dejavu(strings: &[&str]) -> Option<(f64, Vec<f64>)> {
    let font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    if !std::path::Path::new(font).exists() {
        eprintln!("note: {font} is absent: not compared");
        return None;
    }
    let script = "import sys, json\nfrom fontTools.ttLib import TTFont\n\
        f = TTFont(sys.argv[1]); upm = f['head'].unitsPerEm; cmap = f.getBestCmap()\n\
        hm = f['hmtx']\n\
        w = [sum(hm[cmap[ord(c)]][0] for c in s) / upm for s in json.loads(sys.argv[2])]\n\
        print(json.dumps([f['glyf'][cmap[ord('H')]].yMax / upm, w]))\n";
    let out = Command::new("python3")
        .args(["-c", script, font, &serde_json::to_string(strings).unwrap()])
        .output()
        .map_err(|e| eprintln!("note: python3 cannot be run: {e}"))
        .ok()?;
    if !out.status.success() {
        eprintln!(
            "note: fontTools is not usable: {}",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        );
        return None;
    }
    let v: (f64, Vec<f64>) = serde_json::from_slice(&out.stdout).unwrap();
    Some(v)
}

#[test]
fn baseline_start_cap_height_and_advances() {
    let words = ["HELLO", "Oficina 21", "mill & plot"];
    let mut ours = Vec::new();
    for w in words {
        let xml = w.replace('&', "&amp;");
        // The same string anchored at its start and at its end: the shift between the two is
        // the advance width the layout used.
        let start = read(&format!(
            r#"<text x="20" y="40" font-size="10" fill="red">{xml}</text>"#
        ));
        let end = read(&format!(
            r#"<text x="20" y="40" font-size="10" text-anchor="end">{xml}</text>"#
        ));
        let middle = read(&format!(
            r#"<text x="20" y="40" font-size="10" text-anchor="middle">{xml}</text>"#
        ));
        let (s, e, m) = (extents(&start), extents(&end), extents(&middle));
        let advance = s.x0 - e.x0;
        assert!(
            (s.x0 - m.x0 - advance / 2.0).abs() < 1e-3,
            "{w}: {s:?} {m:?}"
        );
        assert!(advance > 0.0 && (s.width() - e.width()).abs() < 1e-3);
        // The first glyph's cell starts at x = 20: its strokes a side bearing to the right.
        assert!(s.x0 >= 20.0 - 1e-3 && s.x0 < 20.0 + 2.5, "{w}: {s:?}");
        ours.push(advance / 10.0);
        // Single strokes in the text's fill colour, not filled.
        assert!(start
            .drawing
            .paths()
            .all(|p| p.style.stroke == Some(Color::rgb(255, 0, 0)) && p.style.fill.is_none()));
        assert!(start.unsupported.is_empty(), "{}", start.unsupported);
    }
    // Capitals only, no descenders: from the baseline (y = 100 − 40) up one cap height.
    let caps = extents(&read(r#"<text x="20" y="40" font-size="10">HELLO</text>"#));
    assert!((caps.y0 - 60.0).abs() < 1e-3, "{caps:?}");
    let cap_per_em = (caps.y1 - caps.y0) / 10.0;
    assert!((cap_per_em - oficina_geom::text::CAP_HEIGHT_PER_EM).abs() < 1e-3);
    let Some((their_cap, their_advances)) = dejavu(&words) else {
        return;
    };
    assert!(
        (cap_per_em / their_cap - 1.0).abs() < 0.05,
        "cap height {cap_per_em} em, DejaVu Sans {their_cap} em"
    );
    for ((w, a), b) in words.iter().zip(&ours).zip(&their_advances) {
        eprintln!("{w:?}: {a:.3} em, DejaVu Sans {b:.3} em");
        assert!(
            (0.85..1.3).contains(&(a / b)),
            "{w:?}: {a} em, DejaVu Sans {b} em"
        );
    }
}

#[test]
fn tspans_dx_dy_units_inheritance_transforms_and_use() {
    // A tspan starts a new line at x = 20, 10 below; dx moves one character.
    let i = read(r#"<text x="20" y="30" font-size="10">HI<tspan x="20" dy="10">HI</tspan></text>"#);
    let paths: Vec<&Path> = i.drawing.paths().collect();
    assert_eq!(paths.len(), 8, "H three strokes, I one, twice");
    let (first, second) = (
        bbox(paths[..4].iter().copied()),
        bbox(paths[4..].iter().copied()),
    );
    assert!((first.x0 - second.x0).abs() < 1e-3);
    assert!((first.y0 - 70.0).abs() < 1e-3 && (second.y0 - 60.0).abs() < 1e-3);
    let moved = extents(&read(
        r#"<text x="20" y="30" dx="5" font-size="10">H</text>"#,
    ));
    let plain = extents(&read(r#"<text x="20" y="30" font-size="10">H</text>"#));
    assert!((moved.x0 - plain.x0 - 5.0).abs() < 1e-3);
    // x as a list: each character placed on its own.
    let spread = read(r#"<text x="20 60" y="30" font-size="10">HH</text>"#);
    let s: Vec<&Path> = spread.drawing.paths().collect();
    assert!(
        (bbox(s[3..].iter().copied()).x0 - bbox(s[..3].iter().copied()).x0 - 40.0).abs() < 1e-3
    );
    // font-size inherited from a group's style, in pt (12 pt = 16 px; here 1 px = 1 mm of
    // the viewBox): capitals 16 × 0.7 tall; in em of the parent.
    let pt = extents(&read(
        r#"<g style="font-size:12pt"><text x="0" y="50">H</text></g>"#,
    ));
    assert!((pt.height() - 16.0 * 0.7).abs() < 1e-3, "{pt:?}");
    let em = extents(&read(
        r#"<g font-size="20"><text x="0" y="50" style="font-size:0.5em">H</text></g>"#,
    ));
    assert!((em.height() - 7.0).abs() < 1e-3, "{em:?}");
    // The `font` shorthand.
    let short = extents(&read(
        r#"<text x="0" y="50" style="font:bold 20px/1.25 sans-serif">H</text>"#,
    ));
    assert!((short.height() - 14.0).abs() < 1e-3, "{short:?}");
    // No font-size anywhere: CSS's medium, 16.
    let medium = extents(&read(r#"<text x="0" y="50">H</text>"#));
    assert!((medium.height() - 16.0 * 0.7).abs() < 1e-3);
    // The text's transform and its group's: turned a quarter turn about its start, the
    // capitals stand to the right of x = 30 and run down the page from y = 40 (y up: 60 and
    // below).
    let turned = extents(&read(
        r#"<g transform="translate(10,0)"><text x="20" y="40" font-size="10" transform="rotate(90 20 40)">HH</text></g>"#,
    ));
    assert!(
        (turned.x0 - 30.0).abs() < 1e-3 && (turned.width() - 7.0).abs() < 1e-3,
        "{turned:?}"
    );
    assert!(
        turned.y1 <= 60.0 + 1e-3 && turned.height() > 10.0,
        "{turned:?}"
    );
    // Reused by <use>, on an Inkscape layer, sourced by its id.
    let used = read(
        r##"<g inkscape:groupmode="layer" id="l1" inkscape:label="Engrave">
             <text id="t" x="20" y="40" font-size="10">I</text></g>
           <use xlink:href="#t" x="100"/>"##,
    );
    let p: Vec<&Path> = used.drawing.paths().collect();
    assert_eq!(p.len(), 2);
    assert!(
        (p[1].bounding_box().unwrap().x0 - p[0].bounding_box().unwrap().x0 - 100.0).abs() < 1e-3
    );
    assert_eq!(used.drawing.layers[0].name, "Engrave");
    assert_eq!(p[0].source.element, "#t");
    // Per-glyph rotate: turned 90° clockwise on the page about its start, the I's stem lies
    // along +x from x = 20, its cell down the page from y = 40 (the stem 4/21 of a cap in).
    let r = extents(&read(
        r#"<text x="20" y="40" font-size="10" rotate="90">I</text>"#,
    ));
    assert!(r.height() < 1e-3 && (r.width() - 7.0).abs() < 1e-3, "{r:?}");
    assert!((r.x0 - 20.0).abs() < 1e-3 && (r.y0 - (60.0 - 7.0 * 4.0 / 21.0)).abs() < 1e-3);
}

#[test]
fn white_space_collapses_unless_preserved() {
    let w = |s: &str| {
        extents(&read(&format!(
            r#"<text x="0" y="50" font-size="10">{s}</text>"#
        )))
        .width()
    };
    assert!((w("A  \n\t B") - w("A B")).abs() < 1e-3);
    assert!((w("  A B  ") - w("A B")).abs() < 1e-3);
    let kept = extents(&read(
        r#"<text x="0" y="50" font-size="10" xml:space="preserve">A   B</text>"#,
    ));
    assert!(kept.width() > w("A B") + 5.0);
}

#[test]
fn bad_text_is_noted_not_fatal() {
    // Empty and blank: nothing drawn, nothing to note, the rest of the drawing read.
    for body in [
        r#"<text x="1" y="1"></text><rect x="0" y="0" width="5" height="5"/>"#,
        r#"<text x="1" y="1">   </text><rect x="0" y="0" width="5" height="5"/>"#,
        r#"<text/><rect x="0" y="0" width="5" height="5"/>"#,
    ] {
        let i = read(body);
        assert_eq!(i.drawing.path_count(), 1, "{body}");
        assert!(i.unsupported.is_empty(), "{}", i.unsupported);
    }
    // Unknown characters: drawn as '?', named with the element.
    let i = read(r#"<text id="u" x="10" y="50" font-size="10">A→B</text>"#);
    let q = read(r#"<text id="u" x="10" y="50" font-size="10">A?B</text>"#);
    assert_eq!(extents(&i), extents(&q));
    let k = "<text> (characters without a glyph, drawn as '?')";
    assert_eq!(i.unsupported.counts[k], 1, "{}", i.unsupported);
    assert!(
        i.unsupported.examples[k][0].starts_with("#u (line 3)"),
        "{:?}",
        i.unsupported
    );
    // Huge, zero, negative, nonsense font sizes: noted or defaulted, never a panic.
    for size in ["1e30", "1e400", "0", "-5", "NaN", "big"] {
        let body = format!(r#"<text id="h" x="10" y="50" font-size="{size}">AB</text>"#);
        let i = svg_from_bytes(page(&body).as_bytes(), "t.svg");
        let i = i.unwrap_or_else(|e| panic!("{size}: {e}"));
        let drawn = i.drawing.path_count() > 0;
        let noted = i.unsupported.total() > 0;
        assert!(
            drawn != noted,
            "{size}: {} {}",
            i.drawing.path_count(),
            i.unsupported
        );
    }
    // Inkscape 0.92's flowed text is not SVG: noted, not dropped in silence.
    let i = read(
        r#"<flowRoot id="f"><flowRegion><rect width="9" height="9"/></flowRegion><flowPara>hi</flowPara></flowRoot>"#,
    );
    assert_eq!(i.unsupported.counts["<flowRoot>"], 1, "{}", i.unsupported);
    // Too many characters for one document: noted, not drawn, the rest read.
    let long = "A".repeat(100_001);
    let i = read(&format!(
        r#"<text x="0" y="50">{long}</text><rect width="5" height="5"/>"#
    ));
    assert_eq!(i.drawing.path_count(), 1);
    assert!(
        i.unsupported.to_string().contains("100,000 characters"),
        "{}",
        i.unsupported
    );
    // Markup inside the text is escaped, not injected.
    let i = read(r#"<text id="a&amp;&quot;b" class="x&lt;y" x="10" y="50">&lt;/&amp;&gt;</text>"#);
    assert!(i.drawing.path_count() > 0);
    assert_eq!(i.drawing.paths().next().unwrap().source.element, "#a&\"b");
    // Line numbers of what follows a text of several lines are kept.
    let e = svg_from_bytes(
        page("<text x='1' y='1'>a\nb\nc</text>\n<rect width='1' height='1' transform='bogus'/>")
            .as_bytes(),
        "t.svg",
    );
    assert!(e.is_ok() || e.unwrap_err().to_string().contains("t.svg"));
}

#[test]
fn text_can_be_left_out_as_before() {
    let off = SvgOptions { draw_text: false };
    let i = read_svg(
        page(r#"<text x="10" y="50">AB</text>"#).as_bytes(),
        "t.svg",
        &off,
    )
    .unwrap();
    assert_eq!(i.drawing.path_count(), 0);
    assert_eq!(i.unsupported.counts["<text>"], 1);
}

mod fuzz {
    use super::*;
    use proptest::prelude::*;

    fn value() -> impl Strategy<Value = String> {
        prop_oneof![
            Just(String::new()),
            Just("1e308".to_string()),
            Just("-1e308 1e308".to_string()),
            Just("NaN".to_string()),
            Just("inf".to_string()),
            Just("0".to_string()),
            Just("1em".to_string()),
            Just("150%".to_string()),
            "[-0-9. ,a-z%]{0,16}",
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// Any positions, sizes, anchors, rotations, nesting and characters: a drawing or an
        /// error, never a panic, and nothing drawn outside finite coordinates.
        #[test]
        fn any_text_is_read_or_refused(
            x in value(), dx in value(), size in value(), rot in value(), inner in value(),
            anchor in prop_oneof![Just("start"), Just("middle"), Just("end"), Just("x")],
            s in "[a-zA-Z0-9 →€\u{20}-\u{7e}]{0,12}",
            preserve in any::<bool>(),
        ) {
            let esc = |v: &str| v.replace('&', "&amp;").replace('<', "&lt;").replace('"', "&quot;");
            let body = format!(
                r#"<g font-size="{}"><text x="{}" dx="{}" rotate="{}" text-anchor="{anchor}" {}>{}<tspan x="{}" style="font-size:{}">{}</tspan></text></g>"#,
                esc(&size), esc(&x), esc(&dx), esc(&rot),
                if preserve { r#"xml:space="preserve""# } else { "" },
                esc(&s), esc(&inner), esc(&size), esc(&s),
            );
            if let Ok(i) = svg_from_bytes(page(&body).as_bytes(), "f.svg") {
                for p in i.drawing.paths() {
                    if let Some(b) = p.bounding_box() {
                        prop_assert!(b.x0.is_finite() && b.y1.is_finite(), "{body}");
                    }
                }
            }
        }
    }
}

#[test]
fn inkscape_multiline_text() {
    // As Inkscape 1.x writes two lines: xml:space preserve, a tspan per line with its own
    // x and y, the size in the text's style, namespaced attributes.
    let i = read(
        r#"<g inkscape:groupmode="layer" id="layer1" inkscape:label="Labels" xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd">
        <text xml:space="preserve" style="font-size:10.5833px;line-height:1.25;font-family:sans-serif;fill:#ff0000;stroke-width:0.264583" x="20" y="30" id="text1"><tspan sodipodi:role="line" id="tspan1" style="stroke-width:0.264583" x="20" y="30">HI</tspan><tspan sodipodi:role="line" style="stroke-width:0.264583" x="20" y="43.229" id="tspan2">HI</tspan></text></g>"#,
    );
    let p: Vec<&Path> = i.drawing.paths().collect();
    // H three strokes, I one, twice: each a path of the drawing, sourced to the element.
    assert_eq!(p.len(), 8);
    assert!(p.iter().all(|p| p.source.element == "#text1"));
    assert_eq!(i.drawing.layers[0].name, "Labels");
    assert_eq!(p[0].style.stroke, Some(Color::rgb(255, 0, 0)));
    let b = extents(&i);
    let cap = 10.5833 * 0.7;
    // From the second baseline (100 − 43.229) to the first line's capitals (100 − 30 + cap).
    assert!(
        (b.y0 - (100.0 - 43.229)).abs() < 1e-3 && (b.y1 - (70.0 + cap)).abs() < 1e-3,
        "{b:?}"
    );
    assert!(b.x0 > 20.0 && b.x0 < 20.0 + 0.35 * cap, "{b:?}");
}
