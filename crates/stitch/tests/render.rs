//! The thread render's pixels: a stitch's centre in its thread's colour (lit), fabric
//! elsewhere, jumps not drawn, the size the extents at the dpi, and bounded images.

use oficina_stitch::{
    render, ColorBlock, Kind, RenderError, RenderOptions, Stitch, StitchPlan, Thread,
};

fn plan(blocks: Vec<(Thread, Vec<Stitch>)>) -> StitchPlan {
    StitchPlan {
        name: "t".into(),
        blocks: blocks
            .into_iter()
            .map(|(thread, stitches)| ColorBlock { thread, stitches })
            .collect(),
    }
}

fn s(x: f64, y: f64) -> Stitch {
    Stitch::new(x, y, Kind::Stitch)
}

fn j(x: f64, y: f64) -> Stitch {
    Stitch::new(x, y, Kind::Jump)
}

const RED: [u8; 3] = [200, 30, 40];

/// Two horizontal red stitches at y = 0 from x 0..10, a jump to x 30 and a stitch at y 5.
fn sample() -> StitchPlan {
    plan(vec![(
        Thread::rgb(RED[0], RED[1], RED[2]),
        vec![
            j(0.0, 0.0),
            s(5.0, 0.0),
            s(10.0, 0.0),
            j(30.0, 5.0),
            s(30.0, 10.0),
        ],
    )])
}

#[test]
fn a_stitch_centre_is_its_thread_lit_and_its_edges_darker() {
    let r = render(&sample(), &RenderOptions::default()).unwrap();
    let (cx, cy) = r.pixel_of(2.5, 0.0);
    let centre = r.at(cx as u32, cy as u32);
    // Red dominates and is brighter than the thread (the highlight), never another hue.
    assert!(centre[0] >= RED[0], "{centre:?}");
    assert!(
        centre[0] > centre[1] + 100 && centre[0] > centre[2] + 100,
        "{centre:?}"
    );
    // Near the edge (0.15 mm off the 0.2 mm half-width) the thread is darker than its centre.
    let (ex, ey) = r.pixel_of(2.5, 0.15);
    let edge = r.at(ex as u32, ey as u32);
    assert!(edge[0] < centre[0], "edge {edge:?} centre {centre:?}");
    assert!(edge[0] > edge[1] + 60, "{edge:?}");
}

#[test]
fn fabric_elsewhere_and_jumps_not_drawn() {
    let o = RenderOptions::default();
    let r = render(&sample(), &o).unwrap();
    // Off the thread: 1 mm away from the stitch.
    let (x, y) = r.pixel_of(2.5, 1.0);
    assert_eq!(r.at(x as u32, y as u32), o.background);
    // Midway along the jump (10,0) → (30,5): fabric.
    let (x, y) = r.pixel_of(20.0, 2.5);
    assert_eq!(r.at(x as u32, y as u32), o.background);
    // The stitch after the jump is drawn from the jump's end.
    let (x, y) = r.pixel_of(30.0, 7.5);
    assert_ne!(r.at(x as u32, y as u32), o.background);
}

#[test]
fn the_size_is_the_extents_at_the_dpi() {
    let o = RenderOptions {
        dpi: 254.0,
        margin: 0.0,
        thread_width: 0.4,
        ..RenderOptions::default()
    };
    let r = render(&sample(), &o).unwrap();
    // Sewn extents 30 x 10 mm plus half a thread each side, at 10 px/mm.
    assert_eq!((r.width, r.height), (304, 104));
    assert!((r.dpi - 254.0).abs() < 1e-9);
    assert_eq!(r.rgb.len(), 304 * 104 * 3);
    let png = r.png();
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn later_colours_cover_earlier_ones() {
    let p = plan(vec![
        (Thread::rgb(0, 0, 200), vec![j(0.0, 0.0), s(10.0, 0.0)]),
        (Thread::rgb(0, 200, 0), vec![j(5.0, -3.0), s(5.0, 3.0)]),
    ]);
    let r = render(&p, &RenderOptions::default()).unwrap();
    let (x, y) = r.pixel_of(5.0, 0.0);
    let c = r.at(x as u32, y as u32);
    assert!(c[1] > c[2] && c[1] > c[0], "{c:?}");
}

#[test]
fn bad_input_is_refused_or_bounded() {
    let o = RenderOptions::default();
    assert_eq!(render(&StitchPlan::default(), &o), Err(RenderError::Empty));
    // Only jumps: nothing sewn.
    let jumps = plan(vec![(Thread::rgb(1, 2, 3), vec![j(0.0, 0.0), j(5.0, 5.0)])]);
    assert_eq!(render(&jumps, &o), Err(RenderError::Empty));
    // A 2 m design is drawn at a lower dpi within max_side.
    let big = plan(vec![(
        Thread::rgb(1, 2, 3),
        vec![s(0.0, 0.0), s(2000.0, 10.0)],
    )]);
    let r = render(&big, &o).unwrap();
    assert!(r.width <= o.max_side && r.height <= o.max_side);
    assert!(r.dpi < o.dpi);
    // A kilometre is refused with a message naming the size.
    let huge = plan(vec![(
        Thread::rgb(1, 2, 3),
        vec![s(0.0, 0.0), s(1e6, 10.0)],
    )]);
    let e = render(&huge, &o).unwrap_err();
    assert!(matches!(e, RenderError::TooLarge(..)), "{e}");
    assert!(e.to_string().contains("too large"));
    let nan = plan(vec![(Thread::rgb(1, 2, 3), vec![s(0.0, f64::NAN)])]);
    assert!(matches!(render(&nan, &o), Err(RenderError::Invalid(_))));
    let bad = RenderOptions {
        dpi: 0.0,
        ..RenderOptions::default()
    };
    assert!(matches!(
        render(&sample(), &bad),
        Err(RenderError::Invalid(_))
    ));
}

#[test]
fn the_sheet_page_prints_on_a4_with_the_render_and_thread_names() {
    use oficina_stitch::{sheet, HeadSpeed, Pauses, Table};
    let mut p = sample();
    p.blocks[0].thread.name = "Madeira 1147 <Red>".into();
    let s = sheet(
        &p,
        None,
        &Table::embroidery_table(),
        HeadSpeed::Table,
        Pauses::default(),
        1,
    )
    .unwrap();
    let png = render(&p, &RenderOptions::default()).unwrap().png();
    let page = s.html_page(Some(&png));
    assert!(page.contains("@page{size:A4"), "{page}");
    assert!(
        page.contains("src=\"data:image/png;base64,iVBORw0KGgo"),
        "{page}"
    );
    assert!(page.contains("Madeira 1147 &lt;Red&gt;"));
    assert!(page.contains("Colour sequence"));
    assert!(
        page.contains("Design size") && page.contains("Hoop") && page.contains("Total per piece")
    );
    assert!(s.text().contains("Madeira 1147 <Red>"));
}
