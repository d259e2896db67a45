//! Text alone, from the CLI: `oficina embroider --text "Ana|Maria" -o ana.pes` sews the
//! lettering as the library sews it (letter + its Ink/Stitch document), and pyembroidery reads
//! the PES with those stitches: the count the CLI prints, and every needle point in the same
//! place relative to the first (0.1 mm). Skipped with a note when python3 lacks pyembroidery.

mod common;

use common::{oficina, text};
use oficina_stitch::{letter, Kind, Params, Text};
use std::process::Command;

const DUMP: &str = r#"
import sys, pyembroidery as P
p = P.read(sys.argv[1])
for x, y, c in p.stitches:
    if c & P.COMMAND_MASK == P.STITCH:
        print(x, y)
"#;

#[test]
fn text_alone_goes_to_pes_as_the_library_sews_it_and_pyembroidery_reads_it() {
    let dir = oficina_testkit::scratch_dir("lettering-alone");
    let out = dir.join("ana.pes");
    let o = oficina(&[
        "embroider",
        "--text",
        "Ana|Maria",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    let printed: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("Stitches"))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| panic!("no Stitches in {stdout}"));

    // The library, at the CLI's defaults (15 mm, centred).
    let l = letter(&Text {
        text: "Ana|Maria".into(),
        ..Text::default()
    })
    .unwrap();
    let plan = l.sew(&Params::default(), &mut |_, _| {}).unwrap().plan;
    let ours: Vec<(f64, f64)> = plan
        .entries()
        .filter(|(_, s)| s.kind == Kind::Stitch)
        .map(|(_, s)| (s.x, s.y))
        .collect();
    assert_eq!(
        ours.len(),
        printed,
        "the library's stitches vs the CLI's sheet"
    );

    let py = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let has = Command::new(&py)
        .args(["-c", "import pyembroidery"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has {
        eprintln!(
            "note: skipped, {py} lacks pyembroidery (python3 -m pip install --user pyembroidery)"
        );
        return;
    }
    let o = Command::new(&py)
        .args(["-c", DUMP, out.to_str().unwrap()])
        .output()
        .unwrap();
    oficina_testkit::assert_success(&o);
    let peer: Vec<(f64, f64)> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            // pyembroidery: 0.1 mm, y down.
            (v[0] / 10.0, -v[1] / 10.0)
        })
        .collect();
    assert_eq!(
        peer.len(),
        printed,
        "pyembroidery's stitches vs the CLI's sheet"
    );
    // Where the file puts its origin is the writer's; the design's shape is not.
    let (o0, p0) = (ours[0], peer[0]);
    for (i, (a, b)) in ours.iter().zip(&peer).enumerate() {
        let d = ((a.0 - o0.0) - (b.0 - p0.0)).hypot((a.1 - o0.1) - (b.1 - p0.1));
        assert!(
            d < 0.15,
            "stitch {i}: {a:?} for us, {b:?} for pyembroidery ({d:.2} mm apart)"
        );
    }
}
