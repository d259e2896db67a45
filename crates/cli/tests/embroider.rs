//! `oficina embroider`: the sample design end to end (file, sheet, preview, table run), the
//! sheet of a file read back, and the refusals (bad files, hoops too small, bad parameters).

mod common;

use common::{oficina, root, text};

use std::path::{Path, PathBuf};
use std::process::Output;

fn scratch(name: &str) -> PathBuf {
    let dir = oficina_testkit::scratch_dir("embroider");
    dir.join(name)
}

/// `embroider SAMPLE --run --machine embroidery-xy args…`.
fn run_on_embroidery_xy(sample: &Path, args: &[&str]) -> Output {
    let mut all = vec![
        "embroider",
        sample.to_str().unwrap(),
        "--run",
        "--machine",
        "embroidery-xy",
    ];
    all.extend_from_slice(args);
    oficina(&all)
}

fn field(out: &str, key: &str) -> String {
    out.lines()
        .find(|l| l.starts_with(key))
        .map(|l| l[key.len()..].trim().to_string())
        .unwrap_or_else(|| panic!("no {key} in {out}"))
}

#[test]
fn the_sample_sews_end_to_end_and_reads_back() {
    let sample = root().join("samples/embroidery/sunflower.svg");
    for ext in ["dst", "exp", "pes", "pec", "jef", "vp3", "xxx", "u01"] {
        let out = scratch(&format!("sunflower.{ext}"));
        let sheet = scratch(&format!("sheet-{ext}.html"));
        let preview = scratch(&format!("preview-{ext}.svg"));
        let o = oficina(&[
            "embroider",
            sample.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--sheet",
            sheet.to_str().unwrap(),
            "--preview",
            preview.to_str().unwrap(),
            "--run",
        ]);
        let (stdout, stderr) = text(&o);
        assert!(o.status.success(), "{stdout}\n{stderr}");
        assert!(
            stdout.contains("shapes: 1 fill, 2 satin, 2 running"),
            "{stdout}"
        );
        assert!(
            stdout.contains("every stitch completed within its needle-up window"),
            "{stdout}"
        );
        assert!(stderr.contains("generating stitches 100%"), "{stderr}");
        let stitches = field(&stdout, "Stitches");
        assert!(
            stdout.contains(&format!("({}, ", ext.to_uppercase())),
            "the output's extension names the format: {stdout}"
        );
        let svg = std::fs::read_to_string(&preview).unwrap();
        for c in ["#2e8b3a", "#f2c014", "#6b3e1e"] {
            assert!(svg.contains(c), "{c} missing from the preview");
            // PEC and JEF keep a thread chart's nearest colour, not the design's.
            if !matches!(ext, "pec" | "jef") {
                assert!(stdout.contains(c), "{ext}: {c} missing from the sheet");
            }
        }
        assert!(std::fs::read_to_string(&sheet)
            .unwrap()
            .contains("<h1>Production sheet"));
        // The file read back: same stitch count, same hoop, same sewing time.
        let info = oficina(&["embroider", "--info", out.to_str().unwrap()]);
        let (info_out, info_err) = text(&info);
        assert!(info.status.success(), "{info_err}");
        assert_eq!(field(&info_out, "Stitches"), stitches);
        assert_eq!(field(&info_out, "Hoop"), field(&stdout, "Hoop"));
        assert_eq!(
            field(&info_out, "Sewing time"),
            field(&stdout, "Sewing time")
        );
    }
}

#[test]
fn a_slow_table_reports_the_stitches_it_cannot_finish() {
    let sample = root().join("samples/embroidery/sunflower.svg");
    // The bundled embroidery-xy profile (140 mm/s, 5000 mm/s²) cannot move 3 mm fill stitches
    // in code 11's 47.6 ms window: 2·√(3/5000) = 49 ms.
    let o = run_on_embroidery_xy(&sample, &[]);
    let (stdout, _) = text(&o);
    assert!(!o.status.success());
    assert!(
        stdout.contains("the needle is up 47.6 ms") && stdout.contains("ponto longo demais"),
        "{stdout}"
    );
    // A fixed 350 ppm (the seed's EMC and PATO runs) gives every stitch 85.7 ms: all finish.
    let o = run_on_embroidery_xy(&sample, &["--ppm", "350"]);
    let (stdout, _) = text(&o);
    assert!(o.status.success(), "{stdout}");
    assert!(stdout.contains("fixed 350 stitches/min"), "{stdout}");
}

#[test]
fn bad_files_and_parameters_get_clear_errors() {
    let empty = scratch("empty.dst");
    std::fs::write(&empty, b"").unwrap();
    let o = oficina(&["embroider", "--info", empty.to_str().unwrap()]);
    let (_, err) = text(&o);
    assert!(
        !o.status.success() && err.contains("empty.dst") && err.contains("the file is empty"),
        "{err}"
    );

    let trunc = scratch("trunc.dst");
    std::fs::write(&trunc, b"LA:x").unwrap();
    let (_, err) = text(&oficina(&["embroider", "--info", trunc.to_str().unwrap()]));
    assert!(err.contains("shorter than the 512-byte header"), "{err}");

    let odd = scratch("odd.exp");
    std::fs::write(&odd, [10u8, 10, 0x80, 0x04, 1]).unwrap();
    let (_, err) = text(&oficina(&["embroider", "--info", odd.to_str().unwrap()]));
    assert!(err.contains("byte 2") && err.contains("truncated"), "{err}");

    let txt = scratch("design.pes");
    std::fs::write(&txt, b"#PES0001").unwrap();
    let (_, err) = text(&oficina(&["embroider", "--info", txt.to_str().unwrap()]));
    assert!(
        err.contains("design.pes") && err.contains("PES file: byte 8") && err.contains("truncated"),
        "{err}"
    );
    let txt = scratch("notes.txt");
    std::fs::write(&txt, b"hello").unwrap();
    let (_, err) = text(&oficina(&["embroider", "--info", txt.to_str().unwrap()]));
    assert!(
        err.contains("not an embroidery file Oficina reads"),
        "{err}"
    );

    let sample = root().join("samples/embroidery/sunflower.svg");
    let (_, err) = text(&oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "--stitch-length",
        "0",
    ]));
    assert!(
        err.contains("stitch length (mm) 0 is outside 0.1..12.7"),
        "{err}"
    );
    let (_, err) = text(&oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "--hoop",
        "round-999",
    ]));
    assert!(err.contains("--hoop round-999: no such hoop"), "{err}");

    // A design larger than the hoop asked for: refused, nothing written.
    let big = scratch("big.svg");
    std::fs::write(
        &big,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="120mm" height="40mm" viewBox="0 0 120 40">
        <path d="M 0 20 L 120 20" stroke="#000" stroke-width="0.3" fill="none"/></svg>"##,
    )
    .unwrap();
    let out = scratch("big.dst");
    let o = oficina(&[
        "embroider",
        big.to_str().unwrap(),
        "--hoop",
        "round-100",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (_, err) = text(&o);
    assert!(
        !o.status.success()
            && err.contains("leaves hoop round-100")
            && err.contains("15.0 mm beyond"),
        "{err}"
    );
    assert!(!out.exists());
}

/// The output's extension decides the format: one Oficina cannot write is refused before
/// any work, naming those it can; `--format` must agree with it.
#[test]
fn the_output_format_follows_the_extension() {
    let sample = root().join("samples/embroidery/sunflower.svg");
    let out = scratch("design.xyz");
    let o = oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let (_, err) = text(&o);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.contains("design.xyz") && err.contains(".pes, .pec, .jef, .vp3, .xxx, .u01"),
        "{err}"
    );
    assert!(
        !err.contains("generating"),
        "refused before any work: {err}"
    );
    assert!(!out.exists());
    let out = scratch("design.dst");
    let (_, err) = text(&oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--format",
        "jef",
    ]));
    assert!(
        err.contains("--format jef") && err.contains("names DST"),
        "{err}"
    );
    assert!(!out.exists());
    // PES version 1 is a .pes too.
    let out = scratch("v1.pes");
    let o = oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--format",
        "pes-v1",
    ]);
    assert!(o.status.success(), "{}", text(&o).1);
    assert!(std::fs::read(&out).unwrap().starts_with(b"#PES0001"));
}

/// An embroidery file as input is read as its stitch plan, checked and converted.
#[test]
fn an_embroidery_file_converts_to_another_format() {
    let sample = root().join("samples/embroidery/sunflower.svg");
    let jef = scratch("sunflower.jef");
    let o = oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        jef.to_str().unwrap(),
    ]);
    let (made, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let pes = scratch("converted.pes");
    let o = oficina(&[
        "embroider",
        jef.to_str().unwrap(),
        "-o",
        pes.to_str().unwrap(),
    ]);
    let (stdout, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        stdout.contains("(JEF)") && stdout.contains("(PES, "),
        "{stdout}"
    );
    assert!(std::fs::read(&pes).unwrap().starts_with(b"#PES0060"));
    assert_eq!(field(&stdout, "Stitches"), field(&made, "Stitches"));
    assert_eq!(field(&stdout, "Trims"), field(&made, "Trims"));
    assert_eq!(field(&stdout, "Colours"), field(&made, "Colours"));
    assert_eq!(field(&stdout, "Design size"), field(&made, "Design size"));
    let info = oficina(&["embroider", "--info", pes.to_str().unwrap()]);
    let (info_out, _) = text(&info);
    assert_eq!(field(&info_out, "Stitches"), field(&made, "Stitches"));
}

#[test]
fn the_seeds_machine_program_is_written_and_read() {
    let sample = root().join("samples/embroidery/sunflower.svg");
    let out = scratch("sunflower.ram");
    let o = oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stderr}");
    let bytes = std::fs::read(&out).unwrap();
    // Start code, program 1, start (0, 0) in excess 0x8000, hoop C01; ends FF FF.
    assert_eq!(&bytes[..9], &[0, 0, 1, 0, 0, 0x80, 0, 0x80, 1]);
    assert_eq!(&bytes[bytes.len() - 2..], &[0xFF, 0xFF]);
    let info = oficina(&["embroider", "--info", out.to_str().unwrap()]);
    let (info_out, _) = text(&info);
    assert_eq!(field(&info_out, "Stitches"), field(&stdout, "Stitches"));
    assert_eq!(field(&info_out, "Trims"), "0"); // the seed's machine has no trimmer
}

#[test]
fn a_png_preview_draws_thread_and_the_html_sheet_embeds_it() {
    let real = oficina_testkit::realworld("embroidery-files").map(|d| d.join("emm_Star.pes"));
    let sample = root().join("samples/embroidery/sunflower.svg");
    let (png, html) = (scratch("sunflower.png"), scratch("sunflower-sheet.html"));
    let o = oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        scratch("sunflower-r.dst").to_str().unwrap(),
        "--preview",
        png.to_str().unwrap(),
        "--preview-dpi",
        "100",
        "--sheet",
        html.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("@page{size:A4") && page.contains("data:image/png;base64,iVBOR"));
    assert!(page.contains("Colour sequence"));
    // An embroidery file's sheet (--info) too, where the real file is at hand.
    if let Some(real) = real.filter(|p| p.exists()) {
        let p2 = scratch("star.png");
        let o = oficina(&[
            "embroider",
            "--info",
            real.to_str().unwrap(),
            "--preview",
            p2.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{:?}", text(&o));
        assert_eq!(&std::fs::read(&p2).unwrap()[1..4], b"PNG");
    }
}

#[test]
fn text_is_lettered_alone_or_on_a_design() {
    let out = scratch("ana.pes");
    let o = oficina(&[
        "embroider",
        "--text",
        "Ana|Maria",
        "--text-size",
        "14",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains(" satin, "), "{stdout}");
    // Two lines 14 mm high, `leading` (100 units over a 52.6-unit cap height) apart.
    let size = field(&stdout, "Design size");
    let h: f64 = size
        .split(" x ")
        .nth(1)
        .unwrap()
        .trim_end_matches(" mm")
        .parse()
        .unwrap();
    assert!((h - (14.0 + 14.0 * 100.0 / 52.6)).abs() < 1.5, "{size}");
    // Masego is made for 14 to 21 mm capitals (its font.json's scales): 10 mm is refused.
    let o = oficina(&[
        "embroider",
        "--text",
        "Ana",
        "--text-size",
        "10",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (_, stderr) = text(&o);
    assert!(!o.status.success());
    assert!(
        stderr.contains("--text-size 10") && stderr.contains("13.9 to 20.9"),
        "{stderr}"
    );
    assert!(std::fs::metadata(&out).unwrap().len() > 1000);

    let sample = root().join("samples/embroidery/sunflower.svg");
    let out = scratch("sunflower-named.dst");
    let o = oficina(&[
        "embroider",
        sample.to_str().unwrap(),
        "--text",
        "Zoë",
        "--text-at",
        "0,-60",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("no glyph for \"ë\""), "{stderr}");

    let o = oficina(&["embroider", "--text", " | ", "-o", out.to_str().unwrap()]);
    let (_, stderr) = text(&o);
    assert!(!o.status.success());
    assert!(stderr.contains("the text is empty"), "{stderr}");
}
