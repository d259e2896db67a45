//! Text in drawings, end to end: an SVG `<text>` plotted and a DXF TEXT engraved on its line
//! (`--op profile-on`), both drawn with the single-stroke font at the size the file gives.

mod common;

use common::{oficina, text};
use oficina_testkit::assert_success;

#[test]
fn svg_text_plots_at_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("label.svg");
    // Capitals only: the drawing is one cap height tall, 0.7 of the font-size.
    std::fs::write(
        &svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="30mm" viewBox="0 0 100 30">
             <text x="10" y="20" font-size="12" fill="#0000ff">OFICINA</text></svg>"##,
    )
    .unwrap();
    let nc = dir.path().join("label.nc");
    let out = assert_success(&oficina(&[
        "plot",
        svg.to_str().unwrap(),
        "-o",
        nc.to_str().unwrap(),
    ]));
    assert!(out.contains("#0000ff"), "{out}");
    // "drawing: W x H mm at (X, Y)"
    let line = out.lines().find(|l| l.starts_with("drawing:")).unwrap();
    let words: Vec<&str> = line.split_whitespace().collect();
    let (w, h): (f64, f64) = (words[1].parse().unwrap(), words[3].parse().unwrap());
    assert!((h - 8.4).abs() < 0.05 && w > 40.0 && w < 70.0, "{out}");
    assert!(std::fs::read_to_string(&nc).unwrap().lines().count() > 20);
}

#[test]
fn dxf_text_engraves_on_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let dxf = dir.path().join("label.dxf");
    let pairs = [
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "TEXT"),
        ("5", "A1"),
        ("8", "engrave"),
        ("10", "10"),
        ("20", "5"),
        ("40", "6"),
        ("1", "HELLO"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ];
    let body: String = pairs.iter().map(|(c, v)| format!("{c}\n{v}\n")).collect();
    std::fs::write(&dxf, body).unwrap();
    let nc = dir.path().join("label.nc");
    let preview = dir.path().join("label-preview.svg");
    let o = oficina(&[
        "mill",
        dxf.to_str().unwrap(),
        "--op",
        "profile-on",
        "--depth",
        "0.3",
        "-o",
        nc.to_str().unwrap(),
        "--preview",
        preview.to_str().unwrap(),
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    // Where the cutter is below the surface: on the letters' strokes, from the baseline
    // (y = 5) up one cap height (6 mm), starting at x = 10.
    let (mut x, mut y, mut z) = (0.0f64, 0.0f64, 10.0f64);
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for line in std::fs::read_to_string(&nc).unwrap().lines() {
        if line.starts_with('(') {
            continue;
        }
        for w in line.split_whitespace() {
            let v = w[1..].parse::<f64>();
            match (w.as_bytes()[0], v) {
                (b'X', Ok(v)) => x = v,
                (b'Y', Ok(v)) => y = v,
                (b'Z', Ok(v)) => z = v,
                _ => {}
            }
        }
        if z < -0.29 {
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
    }
    assert!(
        (b[1] - 5.0).abs() < 0.01 && (b[3] - 11.0).abs() < 0.01,
        "{b:?}"
    );
    assert!(b[0] >= 10.0 && b[0] < 12.0 && b[2] > 30.0, "{b:?}");
}
