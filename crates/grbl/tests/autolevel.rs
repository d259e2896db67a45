//! Levelling a program against height maps whose surface the tests evaluate themselves:
//! pieces, arcs, depth below a tilted plane, units, line numbers and refusals.

use oficina_grbl::{
    level_stream, line_words, Area, GridSpec, HeightMap, LevelOptions, ProbeGrid, StreamLine,
};

/// A map probed from `surface` over (0, 0)–(40, 30) on a 5 × 5 grid, clearance 3.
fn map_of(surface: impl Fn(f64, f64) -> f64) -> HeightMap {
    let grid = ProbeGrid::over(
        Area {
            min: [0.0, 0.0],
            max: [40.0, 30.0],
        },
        0.0,
        GridSpec::Count(5, 5),
    )
    .unwrap();
    let mut probe = |x: f64, y: f64| Ok(surface(x, y));
    grid.probe(&mut probe, 3.0, &mut |_, _, _, _, _| {})
        .unwrap()
}

fn flat() -> HeightMap {
    map_of(|_, _| 0.0)
}

/// Every output line's position (program units) after it, with its source line; lines
/// that do not move are left out.
fn points(lines: &[StreamLine]) -> Vec<(usize, [f64; 3])> {
    let mut at = [f64::NAN; 3];
    let mut out = Vec::new();
    for l in lines {
        let words = line_words(&l.text).unwrap();
        let mut moved = false;
        for (letter, v) in words {
            if let Some(a) = "XYZ".find(letter) {
                at[a] = v;
                moved = true;
            }
        }
        if moved {
            out.push((l.file_line, at));
        }
    }
    out
}

fn level(text: &str, map: &HeightMap, opts: &LevelOptions) -> Vec<StreamLine> {
    level_stream("t.nc", text, map, opts).unwrap().0.lines
}

fn err(text: &str, map: &HeightMap) -> String {
    level_stream("t.nc", text, map, &LevelOptions::default()).unwrap_err()
}

fn xy(p: [f64; 3]) -> [f64; 2] {
    [p[0], p[1]]
}

#[test]
fn splitting_keeps_every_endpoint_and_no_piece_is_longer_than_asked() {
    let text = "G21 G90\nG0 Z5\nG0 X1 Y1\nG1 Z-0.2 F300\nG1 X31.7 Y1\nG1 X20 Y27.3\nG1 X1.5 Y2\nG1 X1.5 Y2.3\nG0 Z5\n";
    let opts = LevelOptions {
        max_segment: 0.75,
        ..LevelOptions::default()
    };
    let pts = points(&level(text, &flat(), &opts));
    let ends = [
        [1.0, 1.0, -0.2],
        [31.7, 1.0, -0.2],
        [20.0, 27.3, -0.2],
        [1.5, 2.0, -0.2],
        [1.5, 2.3, -0.2],
    ];
    for e in ends {
        assert!(
            pts.iter()
                .any(|(_, p)| p.iter().zip(&e).all(|(a, b)| (a - b).abs() < 1e-9)),
            "{e:?} missing"
        );
    }
    let mut longest: f64 = 0.0;
    for w in pts.windows(2) {
        let (a, b) = (w[0].1, w[1].1);
        if a[2] < 3.0 && b[2] < 3.0 {
            longest = longest.max((b[0] - a[0]).hypot(b[1] - a[1]));
        }
    }
    assert!(
        longest <= 0.75 + 1e-9 && longest > 0.7,
        "longest piece {longest}"
    );
    // The X31.7 line alone: ⌈30.7 / 0.75⌉ = 41 pieces, all tagged with source line 5.
    assert_eq!(pts.iter().filter(|(l, _)| *l == 5).count(), 41);
}

#[test]
fn arcs_follow_their_circle_within_the_tolerance() {
    // A full circle (G2 from its east point), then a G3 half circle over the top.
    let text = "G21 G90 G17\nG0 Z5\nG0 X30 Y15 Z1\nG1 Z-0.1 F200\nG2 X30 Y15 I-10 J0\nG3 X10 Y15 I-10 J0\nG0 Z5\n";
    let tol = 0.01;
    let opts = LevelOptions {
        arc_tolerance: tol,
        max_segment: 5.0,
        ..LevelOptions::default()
    };
    let pts = points(&level(text, &flat(), &opts));
    let circle: Vec<_> = pts.iter().filter(|(l, _)| *l == 5 || *l == 6).collect();
    assert!(circle.len() > 40, "{} points", circle.len());
    let mut prev = [30.0, 15.0];
    for (_, p) in &circle {
        let p = xy(*p);
        let centre = [20.0, 15.0];
        let r = |q: [f64; 2]| (q[0] - centre[0]).hypot(q[1] - centre[1]);
        // Chord ends on the circle (to the output's 4 decimals), chord middles within tol.
        assert!((r(p) - 10.0).abs() < 1e-4, "{p:?}");
        let mid = [(p[0] + prev[0]) / 2.0, (p[1] + prev[1]) / 2.0];
        assert!(
            10.0 - r(mid) <= tol + 1e-4,
            "chord middle {mid:?} is {} inside",
            10.0 - r(mid)
        );
        prev = p;
    }
    // The G3 half circle runs counter-clockwise from (30, 15) to (10, 15) through y = 25.
    assert!(circle
        .iter()
        .any(|(l, p)| *l == 6 && (p[1] - 25.0).abs() < 1e-3));
}

#[test]
fn cuts_land_at_programmed_depth_below_a_tilted_plane() {
    let plane = |x: f64, y: f64| 0.3 + 0.012 * x - 0.021 * y;
    let map = map_of(plane);
    let text = "G21 G90\nG0 Z5\nG0 X2 Y3\nG0 Z1\nG1 Z-0.15 F150\nG1 X38 Y4 F400\nG2 X30 Y20 R12\nG1 X5 Y28\nG2 X2 Y3 I-1.5 J-12.5\nG0 Z1\nG0 X20 Y10\nG1 Z-0.15\nG1 X21 Y10.5\nG0 Z5\nM2\n";
    let pts = points(&level(text, &map, &LevelOptions::default()));
    let (mut cuts, mut travels) = (0, 0);
    for (line, p) in &pts {
        if p[2] >= 3.0 {
            continue;
        }
        // Independent of the map: the plane itself under the point.
        let depth = p[2] - plane(p[0], p[1]);
        if (depth - 1.0).abs() < 1e-4 {
            travels += 1;
        } else {
            assert!(
                (depth + 0.15).abs() < 1e-4,
                "line {line}: {p:?} is {depth} from the plane"
            );
            cuts += 1;
        }
    }
    assert!(cuts > 100 && travels >= 2, "{cuts} cuts, {travels} travels");
}

#[test]
fn rapids_above_the_clearance_are_left_alone_and_first_moves_send_only_named_axes() {
    let map = map_of(|x, _| 0.01 * x);
    let lines = level(
        "G0 X0 Y0\nG0 Z5\nG0 X40 Y30\nG0 Z5.5\nG1 X0 Y0 Z6 F100\n",
        &map,
        &LevelOptions::default(),
    );
    let text: Vec<_> = lines
        .iter()
        .map(|l| (l.file_line, l.text.as_str()))
        .collect();
    assert_eq!(
        text,
        [
            (1, "G21"),
            (1, "G90"),
            // Z unknown: not sent, not guessed.
            (1, "G0X0Y0"),
            (2, "X0Y0Z5"),
            (3, "X40Y30Z5"),
            (4, "X40Y30Z5.5"),
            (5, "G1X0Y0Z6F100"),
        ]
    );
}

#[test]
fn inch_programs_come_out_in_inches() {
    let map = map_of(|_, _| 0.254);
    let lines = level(
        "G20 G90\nG0 X0.1 Y0.1 Z0.2\nG1 Z-0.004 F10\nG1 X1.1\n",
        &map,
        &LevelOptions::default(),
    );
    let pts = points(&lines);
    assert!(lines.iter().any(|l| l.text == "G20"));
    let last = pts.last().unwrap().1;
    // 0.254 mm is 0.01 in above the programmed −0.004 in.
    assert!(
        (last[0] - 1.1).abs() < 1e-9 && (last[2] - 0.006).abs() < 1e-9,
        "{last:?}"
    );
    // 25.4 mm in pieces of at most 1 mm: 26, and F stays in inches per minute.
    assert_eq!(pts.iter().filter(|(l, _)| *l == 4).count(), 26);
    assert!(lines.iter().any(|l| l.text.ends_with("F10")), "{lines:?}");
}

#[test]
fn incremental_moves_after_a_known_position_are_levelled_in_absolute_coordinates() {
    let map = map_of(|_, y| 0.05 * y);
    let lines = level(
        "G90 G0 X5 Y5 Z1\nG91 G1 Z-1.2 F100\nG1 X2\nG90 G0 Z5\n",
        &map,
        &LevelOptions::default(),
    );
    let pts = points(&lines);
    assert!(lines.iter().all(|l| !l.text.contains("G91")));
    let end = pts.iter().rev().find(|(l, _)| *l == 3).unwrap().1;
    assert!(
        (end[0] - 7.0).abs() < 1e-9 && (end[2] - (-0.2 + 0.25)).abs() < 1e-9,
        "{end:?}"
    );
}

#[test]
fn unsafe_programs_are_refused_naming_the_line() {
    let map = flat();
    for (text, line, says) in [
        ("G0 X1 Y1 Z1\nG92 X0 Y0\n", "line 2", "G92"),
        ("G91\nG0 X1 Y1 Z1\n", "line 2", "G91"),
        (
            "G0 X1 Y1 Z1\nG1 X80 F100\n",
            "line 2",
            "outside the height map",
        ),
        ("G0 X1 Y1 Z1\nM6 T2\n", "line 2", "M6"),
        ("G0 Z-0.1\n", "line 1", "before X and Y are known"),
        ("G0 X1 Y1 Z1\nG55\n", "", ""),
        ("G0 X1 Y1 Z1\nG1 X2 Y2 Z-1\n", "", ""),
    ] {
        match level_stream("t.nc", text, &map, &LevelOptions::default()) {
            Err(e) => assert!(e.starts_with(line) && e.contains(says), "{text:?}: {e}"),
            Ok(_) => assert!(line.is_empty(), "{text:?} was levelled"),
        }
    }
    // A map that names its coordinate system refuses programs in another.
    let mut g54 = flat();
    g54.wcs = Some("G54".into());
    let e = err("G55\nG0 X1 Y1 Z1\n", &g54);
    assert!(
        e.starts_with("line 1") && e.contains("probed in G54"),
        "{e}"
    );
    // A little outside takes the edge height, with one warning.
    let (_, report) = level_stream(
        "t.nc",
        "G0 X-1 Y-1 Z1\nG1 X-2 F100\n",
        &map,
        &LevelOptions::default(),
    )
    .unwrap();
    assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
    assert!(
        report.warnings[0].starts_with("line 1"),
        "{:?}",
        report.warnings
    );
    // A clearance under the surface is refused before anything is written.
    let low = LevelOptions {
        clearance: Some(-2.0),
        ..LevelOptions::default()
    };
    let e = level_stream("t.nc", "G0 X1 Y1 Z1\n", &map, &low).unwrap_err();
    assert!(e.contains("clearance"), "{e}");
}

#[test]
fn modal_words_pass_as_grbl_lines_with_their_source_lines() {
    let text = "G21 G90\nS12000 M3\nM8\nM7\nM9 (both off)\nG4 P0.5\nT2\nG0 G53 Z-1\nG0 X1 Y1 Z5\nM5\nM30\n";
    let lines = level(text, &flat(), &LevelOptions::default());
    let got: Vec<_> = lines
        .iter()
        .map(|l| format!("{}:{}", l.file_line, l.text))
        .collect();
    assert_eq!(
        got,
        [
            "1:G21",
            "1:G90",
            "2:S12000",
            "2:M3",
            "3:M8",
            "4:M7",
            "5:M9",
            "6:G4P0.5",
            "7:T2",
            "8:G0G53Z-1",
            "9:G0X1Y1Z5",
            "10:M5",
            "11:M2"
        ]
    );
}

#[test]
fn resume_from_a_source_line_starts_at_its_first_levelled_piece() {
    let text = "G21 G90\nG0 Z5\nG0 X1 Y1\nG1 Z-0.1 F300\nG1 X11 Y1\nG1 X11 Y6\nG0 Z5\n";
    let (program, _) = level_stream("t.nc", text, &flat(), &LevelOptions::default()).unwrap();
    let at = program.index_of_file_line(6).unwrap();
    // Line 5's ten pieces end at X11; line 6 starts with its first piece.
    assert_eq!(program.lines[at - 1].text, "X11Y1Z-0.1");
    assert_eq!(program.lines[at].text, "X11Y2Z-0.1");
    assert_eq!(program.lines[at].file_line, 6);
    // Lines that make no line of output (none here) resume at the next that does.
    assert_eq!(program.index_of_file_line(7), Some(program.len() - 1));
}

#[test]
fn maps_and_grids_built_field_by_field_are_checked_before_use() {
    let mut bad = flat();
    bad.nx = 0;
    let e = level_stream("t.nc", "G0 X1 Y1 Z1\n", &bad, &LevelOptions::default()).unwrap_err();
    assert!(e.contains("2 to 100"), "{e}");
    let huge = ProbeGrid {
        origin: [0.0; 2],
        spacing: [1.0; 2],
        nx: 1_000_000_000,
        ny: 1_000_000_000,
    };
    let mut probe = |_: f64, _: f64| Ok(0.0);
    let e = huge
        .probe(&mut probe, 3.0, &mut |_, _, _, _, _| {})
        .unwrap_err();
    assert!(e.contains("2 to 100"), "{e}");
}

/// Two tools, each cutting 0.1 mm deep across the map; the second one's M6 sits on a line
/// with its T word, and its tool is described in a CAM comment.
const TWO_TOOLS: &str = "(T2 D=1 - engraver)\nG21 G90\nT1 M6\nG0 Z5\nG0 X2 Y5\nG1 Z-0.1 F300\nG1 X38\nG0 Z5\nT2 M6\nG0 X2 Y20\nG1 Z-0.1 F300\nG1 X38 Y25\nG0 Z5\nM2\n";

fn with_policy(policy: oficina_grbl::ToolPolicy) -> LevelOptions {
    LevelOptions {
        tool_change: Some(oficina_grbl::ToolChange {
            policy,
            setter: Some(oficina_grbl::setter_at(0.0, 0.0, -5.0)),
            park: Some([0.0, 0.0, -1.0]),
            ..oficina_grbl::ToolChange::default()
        }),
        ..LevelOptions::default()
    }
}

#[test]
fn a_levelled_two_tool_program_stops_at_each_m6_and_both_tools_follow_the_surface() {
    use oficina_grbl::ToolPolicy;
    let surface = |x: f64, y: f64| 0.01 * x - 0.02 * y + 0.05 * (x / 7.0).sin();
    let map = map_of(surface);
    let (job, report) =
        level_stream("t.nc", TWO_TOOLS, &map, &with_policy(ToolPolicy::Remeasure)).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert_eq!(job.tool_change.policy, ToolPolicy::Remeasure);
    let stops: Vec<_> = job
        .tool_stops
        .iter()
        .map(|s| (s.tool, s.file_line, s.description.clone()))
        .collect();
    assert_eq!(
        stops,
        [(1, 3, None), (2, 9, Some("T2 D=1 - engraver".to_string()))]
    );
    // No M6 goes to grbl: the sender stops before the line it stood on.
    assert!(job.lines.iter().all(|l| !l.text.contains("M6")));
    for s in &job.tool_stops {
        assert!(job.lines[s.index].file_line >= s.file_line, "{s:?}");
    }
    // Every cut point of each tool 0.1 mm under the surface (within the map's own error).
    let mut cuts = [0, 0];
    for (line, p) in points(&job.lines) {
        if p[2] < 1.0 {
            let depth = p[2] - surface(p[0], p[1]);
            assert!(
                (depth + 0.1).abs() < 0.02,
                "line {line}: {p:?} depth {depth}"
            );
            cuts[usize::from(line > 9)] += 1;
        }
    }
    assert!(cuts[0] > 30 && cuts[1] > 30, "{cuts:?}");

    // Pause and park: allowed, with the re-zeroing they need said.
    for policy in [ToolPolicy::Pause, ToolPolicy::ParkPause] {
        let (job, report) = level_stream("t.nc", TWO_TOOLS, &map, &with_policy(policy)).unwrap();
        assert_eq!(job.tool_stops.len(), 2);
        assert_eq!(report.warnings.len(), 2, "{:?}", report.warnings);
        assert!(
            report.warnings[1].starts_with("line 9: M6 T2 with --tool-change")
                && report.warnings[1].contains("zero Z again where it was zeroed before probing"),
            "{:?}",
            report.warnings
        );
    }
    // Ignore: the tool is never changed, so the map holds; the note says so.
    let (job, report) =
        level_stream("t.nc", TWO_TOOLS, &map, &with_policy(ToolPolicy::Ignore)).unwrap();
    assert!(job.tool_stop_at(job.tool_stops[1].index).is_none());
    assert!(
        report.warnings[1].contains("dropped (--tool-change ignore)"),
        "{:?}",
        report.warnings
    );
    assert!(job
        .lines
        .iter()
        .all(|l| !l.text.contains("M6") && !l.text.contains('T')));

    // The area a map must cover is read past the M6s.
    let area = oficina_grbl::feed_area(TWO_TOOLS, oficina_gcode::Dialect::Grbl).unwrap();
    assert_eq!((area.min, area.max), ([2.0, 5.0], [38.0, 25.0]));

    // The firmware's own change, or a file for another sender: refused, naming the line.
    let e = level_stream("t.nc", TWO_TOOLS, &map, &with_policy(ToolPolicy::Firmware)).unwrap_err();
    assert!(
        e.starts_with("line 3: M6: with --tool-change firmware"),
        "{e}"
    );
    let e = err(TWO_TOOLS, &map);
    assert!(
        e.starts_with("line 3: M6: a levelled file for another sender cannot carry a tool change"),
        "{e}"
    );
}
