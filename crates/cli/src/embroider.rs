//! `oficina embroider DESIGN.svg -o out.pes`: an SVG/DXF design (or an embroidery file, to
//! convert it) becomes an embroidery file in the format of the output's extension, with the
//! production sheet, a preview and a run on the needle-synchronised table.
//! `oficina embroider --info FILE.jef` prints the sheet of any embroidery file.

use anyhow::Context;
use oficina_app::embroider::{
    embroider_text, output_format, preview_document, read_stitch_file, sheet_document_with_render,
    sheet_of, EmbroiderParams,
};
use oficina_app::Feedback;
use oficina_stitch::{
    duration, open_seed_port, send, Align, Alteration, Format, MirrorAxis, Params, RunReport,
    SeedHeader, Sheet, StitchPlan, Text, Trim,
};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// The design: .svg or .dxf (fills → tatami, strokes ≥ --satin-min-width → satin, thinner
    /// strokes → running stitch), or an embroidery file (.dst .exp .pes .pec .jef .vp3 .xxx
    /// .u01 .ram .bor) to check and convert; .pub: the seed's CADTEC public file (style 3
    /// running, others satin).
    input: Option<PathBuf>,
    /// Where to write the embroidery file; its extension names the format (.dst .exp .pes
    /// .pec .jef .vp3 .xxx .u01, or .ram / .bor: the seed's program, binary / ASCII).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// File format: dst exp pes pes-v1 pec jef vp3 xxx u01 seed-ram (default: the output's
    /// extension; must agree with it).
    #[arg(long, value_parser = format_arg)]
    format: Option<Format>,
    /// Running stitch length, mm (the seed's PASSO, 0.1–12.7).
    #[arg(long, default_value_t = 2.5)]
    stitch_length: f64,
    /// Fill row angle, degrees from X.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    fill_angle: f64,
    /// Fill row spacing, mm.
    #[arg(long, default_value_t = 0.4)]
    fill_spacing: f64,
    /// Fill stitch length, mm.
    #[arg(long, default_value_t = 3.0)]
    fill_stitch_length: f64,
    /// Satin zig spacing on the outer edge, mm.
    #[arg(long, default_value_t = 0.4)]
    satin_spacing: f64,
    /// Strokes at least this wide (mm) sew as satin columns.
    #[arg(long, default_value_t = 1.0)]
    satin_min_width: f64,
    /// Pull compensation: mm added to satin widths and fill rows.
    #[arg(long, default_value_t = 0.2)]
    pull_compensation: f64,
    /// No underlay under satins and fills.
    #[arg(long)]
    no_underlay: bool,
    /// Fill closed paths that have no fill colour (DXF outlines) instead of outlining them.
    #[arg(long)]
    fill_closed: bool,
    /// No lock stitches (tie-in / tie-off) where the thread is cut.
    #[arg(long)]
    no_ties: bool,
    /// Trim before jumps longer than this, mm.
    #[arg(long, default_value_t = 3.0)]
    trim_length: f64,
    /// Hoop by name (round-100 … round-325, oval-110x160 … oval-220x360) or seed code (C01,
    /// O05); default: the smallest that fits.
    #[arg(long)]
    hoop: Option<String>,
    /// Write the production sheet (.html for HTML, else text).
    #[arg(long)]
    sheet: Option<PathBuf>,
    /// Write a preview: .png draws the design as thread (0.4 mm wide, shaded, jumps not
    /// drawn) at --preview-dpi; else an SVG in the thread colours (jumps dashed, hoop drawn).
    #[arg(long)]
    preview: Option<PathBuf>,
    /// The PNG preview's resolution, pixels per inch (a large design is drawn at less).
    #[arg(long, default_value_t = 254.0)]
    preview_dpi: f64,
    /// Print the sheet of an existing embroidery file instead.
    #[arg(long, conflicts_with = "input")]
    info: Option<PathBuf>,
    /// Sew it on the virtual needle-synchronised table: report the time and every stitch the
    /// table cannot finish while the needle is up (exit 1 if any).
    #[arg(long)]
    run: bool,
    /// The table: embroidery-table (the seed's, limits from its head-speed table) or a motion
    /// profile whose X/Y joints give speed and acceleration (e.g. embroidery-xy).
    #[arg(long, default_value = "embroidery-table")]
    machine: String,
    /// Sew at this fixed head speed (stitches/min) instead of the seed's speed codes.
    #[arg(long)]
    ppm: Option<f64>,
    /// Pieces for the sheet's batch time.
    #[arg(long, default_value_t = 1)]
    pieces: u32,
    /// Letter this text in an embroidery font (`|` or a newline starts a line); alone, or
    /// added to the design.
    #[arg(long)]
    text: Option<String>,
    /// The embroidery font of --text (bundled: masego, Ink/Stitch's OFL satin font).
    #[arg(long, default_value = oficina_stitch::DEFAULT_FONT)]
    font: String,
    /// Cap height of --text, mm: within the sizes the font is made for (its font.json's
    /// scales; Masego 13.9 to 20.9).
    #[arg(long, default_value_t = 15.0)]
    text_size: f64,
    /// Alignment of the text's lines: left, center, right.
    #[arg(long, default_value = "center")]
    text_align: String,
    /// Where the text's first baseline is anchored, X,Y mm (y up; the design's coordinates).
    /// Default: under the design, centred on it (or at its left or right edge as aligned);
    /// text alone is centred in the hoop.
    #[arg(long, value_parser = point_arg, allow_hyphen_values = true)]
    text_at: Option<(f64, f64)>,
    /// Cut the thread after each line, word or letter of --text (Ink/Stitch's "Add trims");
    /// never: only where the font's own jumps are long.
    #[arg(long, default_value = "never", value_parser = ["never", "line", "word", "letter"])]
    text_trim: String,
    /// Shift the Zero-Peça by X,Y mm (the seed's ALTER), e.g. --shift 30,-30.
    #[arg(long, value_parser = shift_arg, allow_hyphen_values = true)]
    shift: Option<[f64; 2]>,
    /// Rotate by this many degrees, counter-clockwise (a design before stitching).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    rotate: f64,
    /// Mirror about the x axis (y → −y) or the y axis (x → −x).
    #[arg(long, value_parser = ["x", "y"])]
    mirror: Option<String>,
    /// Scale by this factor (a design is scaled before stitching: stitch lengths are kept).
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// Stitch files to join after the input, as the seed's LINKA: one point from each
    /// program's last stitch to the next one's start (a .bor's Zero-Peça). Repeatable.
    #[arg(long)]
    link: Vec<PathBuf>,
    /// Where the origin of each --link file goes, X,Y mm from the input's origin, in the
    /// order of the --link files (the page's stitch editor places designs so); repeatable.
    #[arg(long, value_parser = shift_arg, allow_hyphen_values = true, requires = "link")]
    link_at: Vec<[f64; 2]>,
    /// Sew the section (consecutive stitches of one colour) holding entry ENTRY (counted from
    /// 0 over the altered, linked design) at the faster speed code CODE (4–12): its stitches
    /// longer than the code allows are split. Repeatable.
    #[arg(long, value_name = "ENTRY:CODE", value_parser = section_speed_arg)]
    section_speed: Vec<(usize, u8)>,
    /// Send the program one way to the seed machine on this serial port (9600 baud, 7 data
    /// bits, even parity, 2 stop bits: the .BOR text), e.g. the pty `oficina emulate seed
    /// --pty` prints.
    #[arg(long, value_name = "PORT")]
    send: Option<String>,
    /// The program number the machine stores it under (with --send).
    #[arg(long, default_value_t = 1, requires = "send")]
    program: u16,
}

fn point_arg(s: &str) -> Result<(f64, f64), String> {
    let (x, y) = s.split_once(',').ok_or("use X,Y")?;
    let f = |v: &str| v.trim().parse::<f64>().map_err(|e| format!("{v}: {e}"));
    Ok((f(x)?, f(y)?))
}

fn text_of(a: &Args) -> anyhow::Result<Option<Text>> {
    let Some(text) = &a.text else {
        return Ok(None);
    };
    let align = Align::from_id(&a.text_align).ok_or_else(|| {
        anyhow::anyhow!("--text-align {}: use left, center or right", a.text_align)
    })?;
    let (x, y) = a.text_at.unwrap_or((0.0, 0.0));
    Ok(Some(Text {
        text: text.clone(),
        font: a.font.clone(),
        size: a.text_size,
        align,
        at: oficina_geom::Point::new(x, y),
        under_design: a.text_at.is_none(),
        trim: Trim::from_id(&a.text_trim).unwrap_or_default(),
        ..Text::default()
    }))
}

fn shift_arg(s: &str) -> Result<[f64; 2], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| "give X,Y in mm, e.g. 30,-30".to_string())?;
    match v.as_slice() {
        [x, y] => Ok([*x, *y]),
        _ => Err("give X,Y in mm, e.g. 30,-30".into()),
    }
}

fn section_speed_arg(s: &str) -> Result<(usize, u8), String> {
    let usage = || "give ENTRY:CODE, e.g. 120:12".to_string();
    let (e, c) = s.split_once(':').ok_or_else(usage)?;
    Ok((
        e.trim().parse().map_err(|_| usage())?,
        c.trim().parse().map_err(|_| usage())?,
    ))
}

fn format_arg(s: &str) -> Result<Format, String> {
    Format::from_id(s).ok_or_else(|| {
        let ids: Vec<&str> = Format::EVERY.iter().map(|f| f.id()).collect();
        format!("use one of {}", ids.join(", "))
    })
}

fn params(a: &Args, format: Format) -> EmbroiderParams {
    EmbroiderParams {
        stitch: Params {
            stitch_length: a.stitch_length,
            fill_angle_deg: a.fill_angle,
            fill_spacing: a.fill_spacing,
            fill_stitch_length: a.fill_stitch_length,
            satin_spacing: a.satin_spacing,
            satin_min_width: a.satin_min_width,
            pull_compensation: a.pull_compensation,
            underlay: !a.no_underlay,
            trim_length: a.trim_length,
            ties: !a.no_ties,
            fill_closed: a.fill_closed,
            ..Params::default()
        },
        format,
        hoop: a.hoop.clone(),
        table: a.machine.clone(),
        ppm: a.ppm,
        pieces: a.pieces,
        alteration: Alteration {
            shift: a.shift.unwrap_or([0.0, 0.0]),
            rotate_deg: a.rotate,
            mirror: match a.mirror.as_deref() {
                Some("x") => Some(MirrorAxis::X),
                Some("y") => Some(MirrorAxis::Y),
                _ => None,
            },
            scale: a.scale,
        },
        link: a.link.clone(),
        link_at: a.link_at.clone(),
        section_speed: a.section_speed.clone(),
    }
}

fn write_sheet(path: &Path, s: &Sheet, plan: &StitchPlan) -> anyhow::Result<()> {
    std::fs::write(path, sheet_document_with_render(path, s, plan))
        .with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn print_run(r: &RunReport, machine: &str) -> ExitCode {
    println!(
        "run on {machine}: sewing {}, jumps {}, pauses {}, total {}",
        duration(r.sewing_seconds),
        duration(r.jump_seconds),
        duration(r.pause_seconds),
        duration(r.total_seconds)
    );
    for (i, x, y) in r.out_of_travel.iter().take(5) {
        println!("  entry {i}: ({x:.1}, {y:.1}) mm is beyond the table's travel");
    }
    for f in r.faults.iter().take(10) {
        println!(
            "  stitch {} (colour {}): {:.2} mm at {} ppm needs {:.1} ms, the needle is up {:.1} ms",
            f.index + 1,
            f.block + 1,
            f.length,
            f.ppm,
            f.move_seconds * 1000.0,
            f.window_seconds * 1000.0
        );
    }
    if r.faults.len() > 10 {
        println!("  … {} more", r.faults.len() - 10);
    }
    if r.faults.is_empty() && r.out_of_travel.is_empty() {
        println!("every stitch completed within its needle-up window");
        ExitCode::SUCCESS
    } else {
        println!(
            "the run would stop: {} stitch(es) too long for their window (\"ponto longo demais\"), {} point(s) beyond travel",
            r.faults.len(),
            r.out_of_travel.len()
        );
        ExitCode::FAILURE
    }
}

pub(crate) fn run(a: Args) -> anyhow::Result<ExitCode> {
    // The output's format first: an extension Oficina cannot write is refused before any work.
    let format = output_format(a.output.as_deref(), a.format)?;
    let p = params(&a, format);
    if let Some(file) = &a.info {
        let plan = read_stitch_file(file)?;
        let s = sheet_of(&plan, &p)?;
        print!("{}", s.text());
        if let Some(path) = &a.sheet {
            write_sheet(path, &s, &plan)?;
        }
        if let Some(path) = &a.preview {
            let doc = preview_document(path, &plan, s.hoop.as_ref().ok(), a.preview_dpi)?;
            std::fs::write(path, doc).with_context(|| format!("writing {}", path.display()))?;
            println!("wrote {}", path.display());
        }
        if a.run {
            return Ok(print_run(&s.run, &a.machine));
        }
        return Ok(ExitCode::SUCCESS);
    }
    let text = text_of(&a)?;
    if a.input.is_none() && text.is_none() {
        anyhow::bail!(
            "give a design (SVG/DXF) or an embroidery file to embroider, a --text, or --info FILE.dst"
        );
    }
    let input = a.input.as_deref();
    let shown = input.map_or("lettering".into(), |i| i.display().to_string());
    // One line per stage, its percentage updated in place.
    let last = std::sync::Mutex::new(String::new());
    let progress = |stage: &str, f: f64| {
        let mut e = std::io::stderr();
        let mut last = last.lock().unwrap_or_else(|p| p.into_inner());
        if *last != stage && !last.is_empty() {
            let _ = writeln!(e);
        }
        *last = stage.to_string();
        let _ = write!(e, "\r{stage} {:>3.0}%", f * 100.0);
    };
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let r = embroider_text(
        input,
        text.as_ref(),
        &p,
        Feedback {
            progress: &progress,
            cancel: &cancel,
        },
    )?;
    eprintln!();
    for n in &r.notes {
        eprintln!("note: {n}");
    }
    let g = &r.generated;
    match r.source {
        Some(f) => println!("read {shown} ({f})"),
        None => println!(
            "shapes: {} fill, {} satin, {} running",
            g.fills, g.satins, g.runnings
        ),
    }
    print!("{}", r.sheet.text());
    if let Err(e) = &r.sheet.hoop {
        anyhow::bail!("{e}; nothing written (choose a larger --hoop or scale the design)");
    }
    match &a.output {
        Some(out) => {
            std::fs::write(out, &r.file).with_context(|| format!("writing {}", out.display()))?;
            println!(
                "wrote {} ({}, {} bytes)",
                out.display(),
                p.format,
                r.file.len()
            );
        }
        None if !a.run && a.send.is_none() => eprintln!("note: no -o given, no file written"),
        None => {}
    }
    if let Some(port) = &a.send {
        let plan = p.format.read(&r.file, "program")?;
        let header = SeedHeader {
            program: a.program,
            start: [0.0, 0.0],
            hoop: r.sheet.hoop.as_ref().ok().copied(),
        };
        let mut sp = open_seed_port(port)?;
        let n = send(&mut *sp, &plan, &header).map_err(anyhow::Error::msg)?;
        println!(
            "sent program {} to {port} ({n} bytes, 9600 baud 7E2)",
            a.program
        );
    }
    if let Some(path) = &a.sheet {
        write_sheet(path, &r.sheet, &r.generated.plan)?;
    }
    if let Some(path) = &a.preview {
        let doc = preview_document(
            path,
            &r.generated.plan,
            r.sheet.hoop.as_ref().ok(),
            a.preview_dpi,
        )?;
        std::fs::write(path, doc).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    if a.run {
        // The sheet's run is the file's plan sewn on the table.
        return Ok(print_run(&r.sheet.run, &a.machine));
    }
    Ok(ExitCode::SUCCESS)
}
