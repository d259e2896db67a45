//! Lettering sewn as its font demands: the glyphs' satin columns are read back from the
//! Ink/Stitch document the lettering makes (its paths and `inkstitch:` attributes, parsed here
//! with roxmltree and svgtypes, rails told from rungs by Ink/Stitch's rule), and the sewn
//! stitches are checked against that geometry alone: each column is crossed from rail to rail
//! about twice per `zigzag_spacing_mm` of its length, every crossing near-parallel to the
//! nearest rung, and the needle stays on the glyphs. And the document itself against the font
//! file read by Oficina's SVG importer (usvg): every glyph element there, scaled to the cap
//! height asked for and moved, nothing else.

use oficina_stitch::{letter, Align, Kind, Params, Text, Trim};

type P = (f64, f64);

/// The subpaths of an SVG path `d`, y flipped (the document is y down, the stitches y up).
fn subpaths(d: &str) -> Vec<Vec<P>> {
    let mut out: Vec<Vec<P>> = Vec::new();
    for seg in svgtypes::SimplifyingPathParser::from(d).flatten() {
        match seg {
            svgtypes::SimplePathSegment::MoveTo { x, y } => out.push(vec![(x, -y)]),
            svgtypes::SimplePathSegment::LineTo { x, y } => out.last_mut().unwrap().push((x, -y)),
            svgtypes::SimplePathSegment::ClosePath => {
                let f = out.last().unwrap()[0];
                out.last_mut().unwrap().push(f);
            }
            s => panic!("the lettering writes polylines, not {s:?}"),
        }
    }
    out
}

fn dist_seg(p: P, a: P, b: P) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// The nearest point of `line` to `p`, and its distance.
fn nearest(p: P, line: &[P]) -> (f64, P) {
    let mut best = (f64::INFINITY, p);
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = (a.0 + t * dx, a.1 + t * dy);
        let d = (p.0 - q.0).hypot(p.1 - q.1);
        if d < best.0 {
            best = (d, q);
        }
    }
    best
}

fn dist(p: P, line: &[P]) -> f64 {
    line.windows(2)
        .map(|w| dist_seg(p, w[0], w[1]))
        .fold(f64::INFINITY, f64::min)
}

fn length(line: &[P]) -> f64 {
    line.windows(2)
        .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
        .sum()
}

fn cross(a: &[P], b: &[P]) -> bool {
    let side = |p: P, q: P, r: P| (q.0 - p.0) * (r.1 - p.1) - (q.1 - p.1) * (r.0 - p.0);
    a.windows(2).any(|u| {
        b.windows(2).any(|v| {
            side(v[0], v[1], u[0]) * side(v[0], v[1], u[1]) <= 0.0
                && side(u[0], u[1], v[0]) * side(u[0], u[1], v[1]) <= 0.0
        })
    })
}

/// A satin column of the document: rails, rungs, spacing (mm).
struct Column {
    id: String,
    rails: [Vec<P>; 2],
    rungs: Vec<Vec<P>>,
    spacing: f64,
    e_stitch: bool,
}

/// Ink/Stitch's rule: a rung crosses exactly two other subpaths; the rest are the rails.
fn column(id: &str, subs: Vec<Vec<P>>, spacing: f64, e_stitch: bool) -> Column {
    let n = subs.len();
    let count = |i: usize| {
        (0..n)
            .filter(|&j| j != i && cross(&subs[i], &subs[j]))
            .count()
    };
    let mut rails: Vec<usize> = (0..n).filter(|&i| n <= 2 || count(i) != 2).collect();
    if rails.len() != 2 {
        rails = (0..n).collect();
        rails.sort_by(|&i, &j| length(&subs[j]).total_cmp(&length(&subs[i])));
        rails.truncate(2);
    }
    Column {
        id: id.to_string(),
        rails: [subs[rails[0]].clone(), subs[rails[1]].clone()],
        rungs: (0..n)
            .filter(|i| !rails.contains(i))
            .map(|i| subs[i].clone())
            .collect(),
        spacing,
        e_stitch,
    }
}

struct Doc {
    columns: Vec<Column>,
    /// Every subpath of every element (the glyphs' whole geometry).
    all: Vec<Vec<P>>,
    trims: usize,
}

fn read(svg: &str) -> Doc {
    let ns = "http://inkstitch.org/namespace";
    let doc = roxmltree::Document::parse(svg).unwrap();
    let mut d = Doc {
        columns: vec![],
        all: vec![],
        trims: 0,
    };
    for p in doc.descendants().filter(|n| n.has_tag_name("path")) {
        let subs = subpaths(p.attribute("d").unwrap());
        d.all.extend(subs.iter().cloned());
        d.trims += usize::from(p.attribute((ns, "trim_after")) == Some("true"));
        if p.attribute((ns, "satin_column")) == Some("True") {
            let spacing = p
                .attribute((ns, "zigzag_spacing_mm"))
                .map_or(0.4, |v| v.parse().unwrap());
            let e = p.attribute((ns, "e_stitch")) == Some("True");
            d.columns
                .push(column(p.attribute("id").unwrap(), subs, spacing, e));
        }
    }
    d
}

fn angle(u: P, v: P) -> f64 {
    let c = (u.0 * v.0 + u.1 * v.1).abs() / (u.0.hypot(u.1) * v.0.hypot(v.1));
    c.min(1.0).acos().to_degrees()
}

fn text(s: &str) -> Text {
    Text {
        text: s.into(),
        size: 15.0,
        align: Align::Left,
        ..Text::default()
    }
}

/// How the stitches of `s` sit on its glyphs' columns.
struct Fit {
    /// The largest angle between a zig and its nearest rung or column end, and its column.
    worst: (f64, String),
    /// The farthest a zig crossing a rung lies from it (its ends' distance to the rung), mm.
    at_rung: (f64, String),
    /// Needle points off the glyphs, of all.
    off: (usize, usize),
}

fn fit(s: &str) -> Fit {
    let l = letter(&text(s)).unwrap();
    let doc = read(&l.svg);
    assert!(
        doc.columns.len() >= 15,
        "{} satin columns",
        doc.columns.len()
    );
    assert!(doc.columns.iter().any(|c| !c.rungs.is_empty()));
    let p = Params {
        center: false,
        ..Params::default()
    };
    let plan = l.sew(&p, &mut |_, _| {}).unwrap().plan;
    let entries: Vec<(P, bool)> = plan
        .entries()
        .map(|(_, s)| ((s.x, s.y), s.kind == Kind::Stitch))
        .collect();
    let pts: Vec<P> = entries.iter().filter(|e| e.1).map(|e| e.0).collect();
    // Stitches sewn one after the other (a jump between two needle points is no stitch).
    let sewn: Vec<(P, P)> = entries
        .windows(2)
        .filter(|w| w[0].1 && w[1].1)
        .map(|w| (w[0].0, w[1].0))
        .collect();
    let on = 0.02; // mm: Masego has no pull compensation, zigs end on the rails
    let mut worst = (0.0f64, String::new());
    let mut at_rung = (0.0f64, String::new());
    for c in &doc.columns {
        let [a, b] = &c.rails;
        let zigs: Vec<(P, P)> = sewn
            .iter()
            .copied()
            .filter(|&(p, q)| {
                (dist(p, a) < on && dist(q, b) < on) || (dist(p, b) < on && dist(q, a) < on)
            })
            .filter(|&(p, q)| (p.0 - q.0).hypot(p.1 - q.1) > 0.3)
            .collect();
        // About two crossings per spacing of the longer rail (an E-stitch: two per step).
        let expected = 2.0 * length(a).max(length(b)) / c.spacing;
        let n = zigs.len() as f64;
        let (lo, hi) = if c.e_stitch { (0.5, 1.5) } else { (0.6, 1.3) };
        // A column under a millimetre long: its first and last zigs count for more.
        assert!(
            n > lo * expected - 2.0 && n < hi * expected + 5.0,
            "{}: {n} rail-to-rail stitches, {expected:.0} expected from its length and spacing {}",
            c.id,
            c.spacing
        );
        // The lines zigs follow: the rungs (between the rails), and the column's two ends.
        let [a, b] = &c.rails;
        let (a0, a1) = (a[0], a[a.len() - 1]);
        let (b0, b1) = if (a0.0 - b[0].0).hypot(a0.1 - b[0].1)
            <= (a0.0 - b[b.len() - 1].0).hypot(a0.1 - b[b.len() - 1].1)
        {
            (b[0], b[b.len() - 1])
        } else {
            (b[b.len() - 1], b[0])
        };
        let mut guides: Vec<Vec<P>> = c.rungs.clone();
        guides.push(vec![a0, b0]);
        guides.push(vec![a1, b1]);
        for &(p, q) in &zigs {
            let mid = ((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0);
            let (d, k, g) = guides
                .iter()
                .enumerate()
                .map(|(k, r)| (dist(mid, r), k, r))
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .unwrap();
            let a = angle(
                (q.0 - p.0, q.1 - p.1),
                (g[g.len() - 1].0 - g[0].0, g[g.len() - 1].1 - g[0].1),
            );
            if a > worst.0 {
                worst = (a, c.id.clone());
            }
            // Where a zig crosses a rung it lies along it (the rung pairs the rails there).
            let on_rung = k < c.rungs.len() && d < 0.25;
            if on_rung {
                let off = dist(p, g).max(dist(q, g));
                if off > at_rung.0 {
                    at_rung = (off, c.id.clone());
                }
            }
        }
    }
    // The needle stays on the glyphs: near one of their paths, or between a column's rails
    // (its distances to the nearest points of the two rails add up to their distance apart).
    let inside = |p: P| {
        doc.all.iter().any(|l| dist(p, l) < 0.6)
            || doc.columns.iter().any(|c| {
                let (da, qa) = nearest(p, &c.rails[0]);
                let (db, qb) = nearest(p, &c.rails[1]);
                da + db < (qa.0 - qb.0).hypot(qa.1 - qb.1) + 0.3
            })
    };
    let off = pts.iter().filter(|&&p| !inside(p)).count();
    Fit {
        worst,
        at_rung,
        off: (off, pts.len()),
    }
}

#[test]
fn satin_zigs_cross_the_rails_along_the_rungs() {
    // A name, and every glyph of the alphabet and the digits.
    for s in [
        "Ana|Maria",
        "ABCDEFGHIJKLM|NOPQRSTUVWXYZ|abcdefghijklm|nopqrstuvwxyz|0123456789",
    ] {
        let f = fit(s);
        eprintln!(
            "{s}: worst zig {:.1}° ({}), at a rung {:.2} mm ({}), {} of {} off",
            f.worst.0, f.worst.1, f.at_rung.0, f.at_rung.1, f.off.0, f.off.1
        );
        // 24° at the x's crossing; 25.8° in a brace whose font path swaps its rails (the zig
        // from the other rail first slants the other way at the column's bends).
        assert!(
            f.worst.0 < 27.0,
            "{s}: a zig {:.1}° off its nearest rung in {}",
            f.worst.0,
            f.worst.1
        );
        // Rails paired by proportion alone (no rungs) leave zigs 0.58 to 0.83 mm off some
        // rungs of these glyphs; paired at the rungs, within 0.54 mm (half a zig's slant).
        assert!(
            f.at_rung.0 < 0.6,
            "{s}: a zig {:.2} mm off the rung it crosses in {}",
            f.at_rung.0,
            f.at_rung.1
        );
        assert!(
            f.off.0 * 100 < f.off.1,
            "{s}: {} of {} stitches off the glyphs",
            f.off.0,
            f.off.1
        );
    }
}

#[test]
fn trims_fall_after_letters_words_or_lines_as_asked() {
    // "Ana Maria|Zé": 3 lines' worth of glyphs, 3 words, 2 lines.
    let glyphs = 10; // A n a M a r i a Z é→o
    for (trim, marked) in [
        (Trim::Never, 0),
        (Trim::Line, 1),
        (Trim::Word, 2),
        (Trim::Letter, glyphs),
    ] {
        let t = Text {
            trim,
            ..text("Ana Maria|Zé")
        };
        let l = letter(&t).unwrap();
        assert_eq!(read(&l.svg).trims, marked, "{trim:?}");
        let p = Params {
            center: false,
            ..Params::default()
        };
        let plan = l.sew(&p, &mut |_, _| {}).unwrap().plan;
        let trims = plan.counts().trims;
        // Each marked glyph's thread is cut after it (the last one's by the end of the
        // design); the font's long jumps are trimmed too.
        assert!(trims >= marked.min(glyphs - 1), "{trim:?}: {trims} trims");
        if trim == Trim::Letter {
            let never = letter(&text("Ana Maria|Zé"))
                .unwrap()
                .sew(&p, &mut |_, _| {})
                .unwrap()
                .plan
                .counts()
                .trims;
            assert!(trims > never, "{trims} trims per letter, {never} without");
        }
    }
}

/// Bounding box [x0, y0, x1, y1] of points.
fn bbox<'a>(pts: impl Iterator<Item = &'a P>) -> [f64; 4] {
    pts.fold(
        [f64::MAX, f64::MAX, f64::MIN, f64::MIN],
        |[a, b, c, d], p| [a.min(p.0), b.min(p.1), c.max(p.0), d.max(p.1)],
    )
}

#[test]
fn the_document_holds_the_fonts_glyphs_scaled_and_moved_only() {
    // The font file read by Oficina's SVG importer (usvg), its hidden glyph layers shown: each
    // glyph element in mm, y up, by its id.
    let font = include_str!("../fonts/inkstitch_masego/ltr.svg").replace("display:none", "");
    let imported = oficina_io::read_svg(
        font.as_bytes(),
        "ltr.svg",
        &oficina_io::SvgOptions { draw_text: false },
    )
    .unwrap();
    let mut glyph_bbox: std::collections::HashMap<String, [f64; 4]> = Default::default();
    for path in imported.drawing.paths() {
        let pts: Vec<P> = path.flatten(0.001).iter().map(|q| (q.x, q.y)).collect();
        let b = bbox(pts.iter());
        let e = glyph_bbox.entry(path.source.element.clone()).or_insert([
            f64::MAX,
            f64::MAX,
            f64::MIN,
            f64::MIN,
        ]);
        *e = [
            e[0].min(b[0]),
            e[1].min(b[1]),
            e[2].max(b[2]),
            e[3].max(b[3]),
        ];
    }
    let l = letter(&text("Ana|Maria")).unwrap();
    let doc = roxmltree::Document::parse(&l.svg).unwrap();
    let mut scales = Vec::new();
    for g in doc.descendants().filter(|n| {
        n.has_tag_name("g") && n.attribute("id").is_some_and(|i| i.starts_with("glyph-"))
    }) {
        // Per glyph: one scale and one shift take every element's box from the font's to the
        // document's (the document is y down: its y negated).
        let mut pairs: Vec<([f64; 4], [f64; 4])> = Vec::new();
        for p in g.children().filter(|n| n.has_tag_name("path")) {
            let id = p.attribute("id").unwrap();
            let font_id = format!("#{}", id.split_once('-').unwrap().1);
            let ours: Vec<P> = subpaths(p.attribute("d").unwrap()).concat();
            let theirs = *glyph_bbox
                .get(&font_id)
                .unwrap_or_else(|| panic!("{font_id} is not in the font"));
            pairs.push((theirs, bbox(ours.iter())));
        }
        let (f0, d0) = (pairs[0].0, pairs[0].1);
        let widest = pairs
            .iter()
            .max_by(|a, b| (a.0[2] - a.0[0]).total_cmp(&(b.0[2] - b.0[0])))
            .unwrap();
        let s = (widest.1[2] - widest.1[0]) / (widest.0[2] - widest.0[0]);
        let (tx, ty) = (d0[0] - s * f0[0], d0[1] - s * f0[1]);
        for (theirs, ours) in &pairs {
            let mapped = [
                s * theirs[0] + tx,
                s * theirs[1] + ty,
                s * theirs[2] + tx,
                s * theirs[3] + ty,
            ];
            let off = mapped
                .iter()
                .zip(ours)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let label = g.attribute(("http://www.inkscape.org/namespaces/inkscape", "label"));
            assert!(
                off < 0.05,
                "{label:?}: an element {off:.3} mm from the font's, scaled by {s}"
            );
        }
        scales.push(s);
    }
    assert_eq!(scales.len(), 8, "A n a M a r i a");
    // One scale for every glyph: 15 mm capitals over the height of the font's H.
    let h = imported
        .drawing
        .layers
        .iter()
        .find(|l| l.name.ends_with("GlyphLayer-H"))
        .expect("the H layer");
    let pts: Vec<P> = h
        .paths
        .iter()
        .flat_map(|p| p.flatten(0.001))
        .map(|q| (q.x, q.y))
        .collect();
    let b = bbox(pts.iter());
    let want = 15.0 / (b[3] - b[1]);
    for s in &scales {
        assert!((s - want).abs() < 1e-3, "{scales:?}, {want} wanted");
    }
}
