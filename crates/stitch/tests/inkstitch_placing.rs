//! Ink/Stitch's commands that place a start or an end (`fill_start`, `fill_end`,
//! `satin_start`, `satin_end`, `run_start`, `run_end`) and `ripple_target`, written as
//! Ink/Stitch writes them (a `<use>` of the command's symbol, a connector path from it to the
//! object), read through `oficina embroider`'s own path: the text stripped of the symbols,
//! imported, sewn. The points expected are worked out from the SVG by hand (a 100 mm page,
//! one user unit a millimetre, y up in the drawing: y = 100 − SVG y).

mod common;

use common::sewn;
use oficina_stitch::{Kind, Params, StitchPlan};

/// The symbols Ink/Stitch puts in `<defs>` (their drawing does not matter here).
const DEFS: &str = r#"<defs>
  <symbol id="inkstitch_fill_start"><path id="fs1" d="M-5 -5L5 5" style="stroke:#000;fill:none"/></symbol>
  <symbol id="inkstitch_fill_end"><path id="fe1" d="M-5 5L5 -5" style="stroke:#000;fill:none"/></symbol>
  <symbol id="inkstitch_satin_start"><path id="ss1" d="M0 -5L0 5" style="stroke:#000;fill:none"/></symbol>
  <symbol id="inkstitch_satin_end"><path id="se1" d="M-5 0L5 0" style="stroke:#000;fill:none"/></symbol>
  <symbol id="inkstitch_run_start"><circle id="rs1" r="4" style="stroke:#000;fill:none"/></symbol>
  <symbol id="inkstitch_run_end"><circle id="re1" r="3" style="stroke:#000;fill:none"/></symbol>
  <symbol id="inkstitch_ripple_target"><circle id="rt1" r="2" style="stroke:#000;fill:none"/></symbol>
</defs>"#;

fn doc(body: &str) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
        xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
        xmlns:inkstitch="http://inkstitch.org/namespace" width="100mm" height="100mm" viewBox="0 0 100 100">
        {DEFS}<g id="layer1" inkscape:groupmode="layer">{body}</g></svg>"##
    )
}

/// A command as Ink/Stitch adds it: a group holding the connector (from the symbol at
/// `(sx, sy)` to `(tx, ty)` on the object) and the symbol's `<use>`.
fn command(
    n: usize,
    cmd: &str,
    target: &str,
    (sx, sy): (f64, f64),
    (tx, ty): (f64, f64),
) -> String {
    format!(
        r##"<g id="command_group{n}">
          <path id="command_connector{n}" d="M {sx},{sy} {tx},{ty}" style="stroke:#000000;stroke-width:1px;stroke-opacity:0.5;fill:none;"
                inkscape:connection-start="#command_use{n}" inkscape:connection-end="#{target}" inkscape:connector-type="polyline"/>
          <use id="command_use{n}" xlink:href="#inkstitch_{cmd}" x="{sx}" y="{sy}" width="100%" height="100%"/>
        </g>"##
    )
}

fn sew(svg: &str) -> StitchPlan {
    let p = Params {
        center: false,
        ..Params::default()
    };
    common::sew_inkstitch(svg, &p)
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// A 40 × 20 mm filled rectangle, SVG x 10..50, y 20..40 (drawing y 60..80).
fn rect(extra: &str) -> String {
    format!(
        r#"<path id="shape" d="M10,20 H50 V40 H10 Z" style="fill:#ff0000;stroke:none" inkstitch:row_spacing_mm="0.25" {extra}/>"#
    )
}

#[test]
fn a_fill_starts_and_ends_at_its_commands() {
    let no_underlay = r#"inkstitch:fill_underlay="false""#;
    let plain = sewn(&sew(&doc(&rect(no_underlay))));
    for (start_y, end) in [(30.0, (10.0, 22.0)), (35.0, (30.0, 40.0))] {
        let body = format!(
            "{}{}{}",
            rect(no_underlay),
            command(1, "fill_start", "shape", (70.0, start_y), (50.0, start_y)),
            command(2, "fill_end", "shape", (5.0, 10.0), end)
        );
        let pts = sewn(&sew(&doc(&body)));
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        let (want0, want1) = ((50.0, 100.0 - start_y), (end.0, 100.0 - end.1));
        // Within a row spacing of the command's point on the outline.
        assert!(
            dist(first, want0) <= 0.25,
            "first {first:?}, command {want0:?}"
        );
        assert!(
            dist(last, want1) <= 0.25,
            "last {last:?}, command {want1:?}"
        );
        // The same rows, a few travel stitches more.
        let ratio = pts.len() as f64 / plain.len() as f64;
        assert!(
            (0.97..1.10).contains(&ratio),
            "{} vs {}",
            pts.len(),
            plain.len()
        );
    }
    // Without commands it starts at a corner of the rectangle, not at the right edge's middle.
    assert!(dist(plain[0], (50.0, 70.0)) > 5.0, "{:?}", plain[0]);
}

#[test]
fn with_an_underlay_the_underlay_starts_at_the_fill_start() {
    let body = format!(
        r#"<g transform="translate(5,-3)">{}{}</g>"#,
        rect(""),
        command(1, "fill_start", "shape", (70.0, 30.0), (50.0, 30.0))
    );
    let pts = sewn(&sew(&doc(&body)));
    // The group's translation moves the object and its command alike: (55, 100 − 27).
    let want = (55.0, 73.0);
    // The underlay's rows are 3 × 0.25 mm apart.
    assert!(dist(pts[0], want) <= 0.75, "{:?}", pts[0]);
}

/// Two rails 50 mm long, SVG y 28 and 32 (a 4 mm column), x 10..60.
fn column(extra: &str) -> String {
    format!(
        r#"<path id="col" d="M10,28 H60 M10,32 H60" style="fill:none;stroke:#0000ff;stroke-width:0.3" inkstitch:satin_column="true" {extra}/>"#
    )
}

#[test]
fn a_satin_starts_at_the_end_nearest_satin_start_and_ends_at_satin_end() {
    let plain = sewn(&sew(&doc(&column(""))));
    assert!(plain[0].0 < 11.0, "drawn from the left: {:?}", plain[0]);
    let start_right = format!(
        "{}{}",
        column(""),
        command(1, "satin_start", "col", (80.0, 30.0), (60.0, 30.0))
    );
    let pts = sewn(&sew(&doc(&start_right)));
    assert!(pts[0].0 > 59.0, "{:?}", pts[0]);
    let end_right = format!(
        "{}{}",
        column(""),
        command(1, "satin_end", "col", (80.0, 30.0), (60.0, 30.0))
    );
    let pts = sewn(&sew(&doc(&end_right)));
    assert!(pts[pts.len() - 1].0 > 59.0, "{:?}", pts[pts.len() - 1]);
    let end_left = format!(
        "{}{}",
        column(""),
        command(1, "satin_end", "col", (0.0, 30.0), (10.0, 30.0))
    );
    let pts = sewn(&sew(&doc(&end_left)));
    assert!(pts[pts.len() - 1].0 < 11.0, "{:?}", pts[pts.len() - 1]);
}

#[test]
fn a_running_line_starts_at_run_start_and_a_loop_at_its_point_nearest() {
    let line = r#"<path id="l" d="M10,50 H60" style="fill:none;stroke:#000;stroke-width:0.1"/>"#;
    let at = |body: String| {
        let pts = sewn(&sew(&doc(&body)));
        (pts[0], pts[pts.len() - 1])
    };
    let (first, _) = at(line.to_string());
    assert!(dist(first, (10.0, 50.0)) < 1e-4);
    let (first, _) = at(format!(
        "{line}{}",
        command(1, "run_start", "l", (70.0, 40.0), (60.0, 50.0))
    ));
    assert!(dist(first, (60.0, 50.0)) < 1e-4, "{first:?}");
    let (_, last) = at(format!(
        "{line}{}",
        command(1, "run_end", "l", (0.0, 40.0), (10.0, 50.0))
    ));
    assert!(dist(last, (10.0, 50.0)) < 1e-4, "{last:?}");
    // A circle of radius 10 about (50, 50): the start moves round with the command.
    let circle =
        r#"<circle id="c" cx="50" cy="50" r="10" style="fill:none;stroke:#000;stroke-width:0.1"/>"#;
    for deg in [0.0f64, 70.0, 200.0] {
        let (c, s) = (deg.to_radians().cos(), deg.to_radians().sin());
        let on = (50.0 + 10.0 * c, 50.0 + 10.0 * s);
        let (first, _) = at(format!(
            "{circle}{}",
            command(1, "run_start", "c", (50.0 + 20.0 * c, 50.0 + 20.0 * s), on)
        ));
        // Within a stitch (2.5 mm) of the command's point, y up.
        assert!(dist(first, (on.0, 100.0 - on.1)) <= 2.5, "{deg}: {first:?}");
    }
}

#[test]
fn a_ripple_shrinks_to_its_ripple_target() {
    let circle = r#"<circle id="c" cx="50" cy="50" r="20" style="fill:none;stroke:#000;stroke-width:0.1" inkstitch:stroke_method="ripple_stitch" inkstitch:line_count="5"/>"#;
    // The target is where the symbol stands (its x, y), not the connector's end.
    let body = format!(
        "{circle}{}",
        command(1, "ripple_target", "c", (58.0, 45.0), (50.0, 50.0))
    );
    let pts = sewn(&sew(&doc(&body)));
    let last = pts[pts.len() - 1];
    assert!(dist(last, (58.0, 55.0)) < 0.1, "{last:?}");
    // Without it, the centre of the circle.
    let pts = sewn(&sew(&doc(circle)));
    let last = pts[pts.len() - 1];
    assert!(dist(last, (50.0, 50.0)) < 0.2, "{last:?}");
}

#[test]
fn placing_symbols_and_connectors_are_not_sewn() {
    let body = format!(
        "{}{}",
        rect(r#"inkstitch:fill_underlay="false""#),
        command(1, "fill_start", "shape", (90.0, 90.0), (50.0, 30.0))
    );
    let plan = sew(&doc(&body));
    let b = plan.bounds().unwrap();
    // The rectangle only (the symbol stands at x 90, SVG y 90).
    assert!(
        b[0] > 9.9 && b[2] < 50.1 && b[1] > 59.9 && b[3] < 80.1,
        "{b:?}"
    );
}

#[test]
fn without_a_start_command_a_fill_starts_where_the_needle_is() {
    // A blue line ending on the red rectangle's right edge, then the fill: it starts there
    // (as Ink/Stitch starts a fill at the last stitch), not at a corner.
    let line = r#"<path id="l" d="M90,30 H50" style="fill:none;stroke:#0000ff;stroke-width:0.1"/>"#;
    let body = format!("{line}{}", rect(r#"inkstitch:fill_underlay="false""#));
    let plan = sew(&doc(&body));
    assert_eq!(plan.blocks.len(), 2);
    let first = plan.blocks[1]
        .stitches
        .iter()
        .find(|s| s.kind == Kind::Stitch)
        .unwrap();
    assert!(dist((first.x, first.y), (50.0, 70.0)) <= 0.25, "{first:?}");
    // Alone, it starts at a corner.
    let alone = sewn(&sew(&doc(&rect(r#"inkstitch:fill_underlay="false""#))));
    assert!(dist(alone[0], (50.0, 70.0)) > 5.0);
}

/// `swap_satin_rails` (Ink/Stitch's "swap rails"): the first zig lands on the other rail.
#[test]
fn swapped_rails_start_the_satin_on_the_other_rail() {
    // Rails at SVG y 40 (drawing y 60, the first subpath) and y 50 (drawing y 50); no underlay.
    let column = |extra: &str| {
        format!(
            r#"<path id="col" d="M 10,40 L 60,40 M 10,50 L 60,50" style="fill:none;stroke:#0000ff;stroke-width:0.5" inkstitch:satin_column="True" {extra}/>"#
        )
    };
    let first = |extra: &str| sewn(&sew(&doc(&column(extra))))[0];
    let (plain, swapped) = (first(""), first(r#"inkstitch:swap_satin_rails="True""#));
    let rail = |p: (f64, f64)| {
        [60.0, 50.0]
            .into_iter()
            .find(|y| (p.1 - y).abs() < 0.3)
            .unwrap_or_else(|| panic!("{p:?} on neither rail"))
    };
    assert_ne!(rail(plain), rail(swapped), "{plain:?} / {swapped:?}");
    // The same end of the column: only the rail changes.
    assert!((plain.0 - swapped.0).abs() < 0.5, "{plain:?} / {swapped:?}");
}

/// `force_lock_stitches`: a running line is tied off at its end although the next one, 2 mm on,
/// is reached without cutting the thread (no tie there otherwise).
#[test]
fn forced_lock_stitches_tie_off_where_no_trim_follows() {
    let lines = |extra: &str| {
        format!(
            r#"<path id="a" d="M 10,50 L 40,50" style="fill:none;stroke:#000000;stroke-width:0.1" {extra}/>
               <path id="b" d="M 42,50 L 70,50" style="fill:none;stroke:#000000;stroke-width:0.1"/>"#
        )
    };
    // Stitches where the needle goes back (towards smaller x) between the lines' ends.
    let back = |extra: &str| {
        let plan = sew(&doc(&lines(extra)));
        assert_eq!(plan.counts().trims, 0, "{extra}");
        let pts = sewn(&plan);
        let end = pts
            .iter()
            .position(|p| dist(*p, (40.0, 50.0)) < 1e-4)
            .unwrap_or_else(|| panic!("{pts:?}"));
        pts.windows(2)
            .skip(end)
            .take_while(|w| w[0].0 <= 40.0 + 1e-4)
            .filter(|w| w[1].0 < w[0].0 - 1e-6)
            .count()
    };
    assert_eq!(back(""), 0);
    assert_eq!(back(r#"inkstitch:force_lock_stitches="True""#), 1);
    // Lock stitches not allowed (`ties` 3): none, forced or not.
    assert_eq!(
        back(r#"inkstitch:force_lock_stitches="True" inkstitch:ties="3""#),
        0
    );
}
