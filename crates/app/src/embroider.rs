//! Embroidery jobs: a design (SVG/DXF) or an embroidery file → stitches → hoop check → sheet
//! → an embroidery file in the format the output's extension names, and preview → a run on
//! the needle-synchronised table; and the sheet of any stitch file.

use crate::{Error, Feedback};
use oficina_stitch::{
    alter, append, generate_inkstitch, letter, link, preview_svg, read_bor, read_inkstitch,
    sew_at_speed, sheet, Align, Alteration, Format, Generated, HeadSpeed, Hoop, Inkstitch, Params,
    Pauses, Sheet, StitchPlan, Table, Text,
};
use std::path::Path;

/// Stitch files larger than this are refused before reading (a DST of 5 million stitches).
pub const MAX_STITCH_FILE: u64 = 16 << 20;

#[derive(Clone, Debug)]
/// The form of an embroidery job.
pub struct EmbroiderParams {
    /// Stitch lengths, fill, satin, underlay, trims and ties.
    pub stitch: Params,
    /// The file written: DST, EXP or the seed's program.
    pub format: Format,
    /// A hoop by name or seed code; None = the smallest that fits.
    pub hoop: Option<String>,
    /// `embroidery-table`, or a motion profile (bundled name or TOML file) whose X/Y joints
    /// give the table's speed and acceleration.
    pub table: String,
    /// A fixed head speed (stitches/min) instead of the seed's table.
    pub ppm: Option<f64>,
    /// Pieces for the sheet's batch time.
    pub pieces: u32,
    /// Shift of the Zero-Peça, rotation, mirror, scale (the seed's ALTER, completed). A
    /// design is scaled, rotated and mirrored before stitching (stitch lengths kept); a stitch
    /// file's points are moved as they are.
    pub alteration: Alteration,
    /// Stitch files linked after the input, as the seed's LINKA does (the input must be a
    /// stitch file too).
    pub link: Vec<std::path::PathBuf>,
    /// Where each linked file's origin goes, mm, in the order of `link` (the stitch editor
    /// places designs so); a file without one starts at its own Zero-Peça.
    pub link_at: Vec<[f64; 2]>,
    /// Sections sewn at a faster head-speed code: (an entry of the section, counted over the
    /// altered plan in sewing order; the code), as `oficina_stitch::sew_at_speed` does.
    pub section_speed: Vec<(usize, u8)>,
}

impl Default for EmbroiderParams {
    fn default() -> EmbroiderParams {
        EmbroiderParams {
            stitch: Params::default(),
            format: Format::Dst,
            hoop: None,
            table: "embroidery-table".into(),
            ppm: None,
            pieces: 1,
            alteration: Alteration::default(),
            link: Vec::new(),
            link_at: Vec::new(),
            section_speed: Vec::new(),
        }
    }
}

/// An embroidery job's output.
pub struct Embroidered {
    /// Shapes stitched, by kind.
    pub generated: Generated,
    /// The file's bytes in `format`.
    pub file: Vec<u8>,
    /// The sheet of the plan as the file holds it (read back), so its figures are the file's.
    pub sheet: Sheet,
    /// The SVG preview.
    pub preview: String,
    /// What the design held that was left out.
    pub notes: Vec<String>,
    /// The input's format when it was an embroidery file (read, not generated).
    pub source: Option<Format>,
}

/// Every format Oficina writes, for messages: "dst, exp, pes, …".
pub fn writable() -> String {
    let mut ext: Vec<&str> = Format::EVERY.iter().map(|f| f.extension()).collect();
    ext.dedup();
    ext.iter()
        .map(|e| format!(".{e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The format an embroidery job writes: the output's extension decides, and `--format`, if
/// given, must agree with it (`pes-v1` is a `.pes`); without an output, `--format` or DST.
/// An extension Oficina cannot write is refused before any work, naming those it can.
pub fn output_format(output: Option<&Path>, format: Option<Format>) -> Result<Format, Error> {
    let Some(out) = output else {
        return Ok(format.unwrap_or(Format::Dst));
    };
    let Some(by_ext) = Format::from_path(out) else {
        return Err(Error(format!(
            "{}: Oficina cannot write embroidery files of this extension; it writes {} (--format pes-v1 for PES version 1)",
            out.display(),
            writable()
        )));
    };
    match format {
        Some(f) if f.extension() != by_ext.extension() => Err(Error(format!(
            "--format {}: the output {} names {} by its extension; give a .{} file or leave --format out",
            f.id(),
            out.display(),
            by_ext,
            f.extension()
        ))),
        Some(f) => Ok(f),
        None => Ok(by_ext),
    }
}

/// The stitch-file format of `path`: what its first bytes show, else what its extension
/// names; None for anything else (a drawing). Unreadable files are left to the reader that
/// follows, which names the error.
pub fn stitch_format(path: &Path) -> Option<Format> {
    use std::io::Read;
    let mut head = Vec::with_capacity(1024);
    if let Ok(f) = std::fs::File::open(path) {
        let _ = f.take(1024).read_to_end(&mut head);
    }
    Format::sniff(&head).or_else(|| Format::from_path(path))
}

/// The table a name stands for.
pub fn table_for(name: &str) -> Result<Table, Error> {
    if name == "embroidery-table" {
        return Ok(Table::embroidery_table());
    }
    let p = oficina_motion::resolve(name).map_err(|e| Error(format!("--machine {name}: {e}")))?;
    let joints: Vec<_> = p.joints.iter().take(2).flatten().collect();
    if joints.len() < 2 {
        return Err(Error(format!(
            "--machine {name}: an embroidery table needs X and Y joints"
        )));
    }
    Ok(Table {
        name: name.to_string(),
        max_speed: joints
            .iter()
            .map(|j| j.max_rate)
            .fold(f64::INFINITY, f64::min),
        acceleration: joints
            .iter()
            .map(|j| j.acceleration)
            .fold(f64::INFINITY, f64::min),
        needle_up: 0.5,
        travel: [
            p.travel[0][0],
            p.travel[1][0],
            p.travel[0][1],
            p.travel[1][1],
        ],
    })
}

/// The label `Params::check` starts its message with, and the flag of the field it is about.
const CHECKED: &[(&str, &str)] = &[
    ("stitch length", "stitch-length"),
    ("fill stitch length", "fill-stitch-length"),
    ("satin spacing", "satin-spacing"),
    ("fill row spacing", "fill-spacing"),
    ("satin minimum width", "satin-min-width"),
    ("fill angle", "fill-angle"),
    ("pull compensation", "pull-compensation"),
    ("trim length", "trim-length"),
];

impl EmbroiderParams {
    /// Refuse a head speed or stitch parameter out of range before the job starts; the
    /// message starts with the flag of the field it names, so a form can show it there.
    pub fn check(&self) -> Result<(), Error> {
        self.alteration.check().map_err(Error)?;
        if self.link_at.len() > self.link.len() {
            return Err(Error(format!(
                "--link-at: {} offsets for {} --link file(s); give one per file",
                self.link_at.len(),
                self.link.len()
            )));
        }
        if let Some(ppm) = self.ppm {
            if !(ppm.is_finite() && ppm > 0.0 && ppm <= 10_000.0) {
                return Err(Error(format!("--ppm {ppm}: use 1..10000 stitches/min")));
            }
        }
        self.stitch.check().map_err(|e| {
            let flag = CHECKED
                .iter()
                .find(|(label, _)| e.0.starts_with(&format!("{label} (")))
                .map_or(String::new(), |(_, f)| format!("--{f}: "));
            Error(format!("{flag}{}", e.0))
        })
    }
}

fn hoop(p: &EmbroiderParams) -> Result<Option<Hoop>, Error> {
    p.hoop
        .as_deref()
        .map(|n| {
            Hoop::by_name(n).ok_or_else(|| {
                let names: Vec<String> = oficina_stitch::HOOPS.iter().map(|h| h.name()).collect();
                Error(format!(
                    "--hoop {n}: no such hoop (hoops: {}; or the codes C01..C11, O01..O06)",
                    names.join(", ")
                ))
            })
        })
        .transpose()
}

fn speed(p: &EmbroiderParams) -> HeadSpeed {
    p.ppm.map_or(HeadSpeed::Table, HeadSpeed::Fixed)
}

/// The production sheet of `plan`: hoop, colours, times and the run on the table.
pub fn sheet_of(plan: &StitchPlan, p: &EmbroiderParams) -> Result<Sheet, Error> {
    p.check()?;
    if p.pieces == 0 || p.pieces > 1_000_000 {
        return Err(Error(format!("--pieces {}: use 1..1000000", p.pieces)));
    }
    sheet(
        plan,
        hoop(p)?,
        &table_for(&p.table)?,
        speed(p),
        Pauses::default(),
        p.pieces,
    )
    .map_err(Error)
}

/// The whole pipeline for a design file, or for an embroidery file (read as its stitch plan,
/// then checked, summed up and converted to `p.format`).
pub fn embroider(input: &Path, p: &EmbroiderParams, fb: Feedback) -> Result<Embroidered, Error> {
    embroider_text(Some(input), None, p, fb)
}

/// [`embroider`] with lettering: `text` set in an embroidery font is added to the design
/// (or sewn alone when there is no `input`). Text cannot be added to an embroidery file.
pub fn embroider_text(
    input: Option<&Path>,
    text: Option<&Text>,
    p: &EmbroiderParams,
    fb: Feedback,
) -> Result<Embroidered, Error> {
    p.check()?;
    let Some(input) = input else {
        let Some(t) = text else {
            return Err(Error("give a design or a text to embroider".into()));
        };
        fb.stage("lettering")?;
        let mut l = letter(t).map_err(|e| Error(e.0))?;
        transform(&mut l.drawing, p);
        fb.stage("generating stitches")?;
        let mut tick = |done: usize, total: usize| {
            (fb.progress)("generating stitches", done as f64 / total.max(1) as f64)
        };
        let mut generated = l.sew(&p.stitch, &mut tick).map_err(|e| Error(e.0))?;
        let [dx, dy] = p.alteration.shift;
        generated.plan = generated.plan.translated(dx, dy);
        // The design's name (a DST's label, the sheet's title) is the text itself.
        let name: String = t
            .text
            .split(['|', '\n'])
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(" ");
        let name: String = name
            .trim()
            .chars()
            .filter(|c| !c.is_control())
            .take(40)
            .collect();
        generated.plan.name = name.clone();
        let notes = l.notes;
        return finish(generated, &name, notes, None, p, fb);
    };
    let name = input
        .file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().to_string());
    let mut notes = Vec::new();
    let source = stitch_format(input);
    if let (Some(f), Some(_)) = (source, text) {
        return Err(Error(format!(
            "{}: text cannot be added to a {f} stitch file; give an SVG/DXF design or no input",
            input.display()
        )));
    }
    if !p.section_speed.is_empty() && source.is_none() {
        return Err(Error(format!(
            "{}: --section-speed changes a stitch file's stitches; stitch the design first",
            input.display()
        )));
    }
    if !p.link.is_empty() && source.is_none() {
        return Err(Error(format!(
            "{}: --link joins stitch files (.bor .dst …); stitch the design first",
            input.display()
        )));
    }
    let generated = if let Some(format) = source {
        fb.stage("reading the stitch file")?;
        let (mut plan, _, moved) = read_stitch(input)?;
        if !p.link.is_empty() {
            let mut programs = vec![(plan, zero_peca(input, format)?)];
            for (i, f) in p.link.iter().enumerate() {
                let (q, qf, _) = read_stitch(f)?;
                let at = match p.link_at.get(i) {
                    Some(at) => *at,
                    None => zero_peca(f, qf)?,
                };
                programs.push((q, at));
            }
            plan = link(&programs);
            plan.name = name.clone();
        }
        let mut plan = alter(&plan, &p.alteration);
        for &(entry, code) in &p.section_speed {
            plan = sew_at_speed(&plan, entry, code)
                .map_err(|e| Error(format!("--section-speed {entry}:{code}: {e}")))?;
        }
        if plan.is_empty() {
            return Err(Error(format!(
                "{}: the file holds no stitches",
                input.display()
            )));
        }
        if let Some((dx, dy)) = moved.filter(|(dx, dy)| dx.abs().max(dy.abs()) >= 1.0) {
            notes.push(format!(
                "{}: {format} design centred in the hoop as Brother machines sew it (moved {dx:+.1}, {dy:+.1} mm)",
                input.display()
            ));
        }
        Generated {
            plan,
            fills: 0,
            satins: 0,
            runnings: 0,
        }
    } else {
        fb.stage("reading the design")?;
        // Ink/Stitch's parameters first: its command symbols are cut from the text before
        // the drawing is imported (the importer would make anonymous paths of them).
        let (ink, svg_text) = inkstitch_of(input)?;
        // An SVG's <text> is not sewn (Ink/Stitch does not stitch text either; `--text` letters
        // in an embroidery font): it is counted as not sewn, with the note below.
        let imported = match svg_text {
            Some(t) => {
                let t = if ink.is_inkstitch { ink.strip(&t) } else { t };
                let no_text = oficina_io::SvgOptions { draw_text: false };
                oficina_io::read_svg(t.as_bytes(), &input.display().to_string(), &no_text).map(
                    |mut i| {
                        // Ink/Stitch's elements keep their own parameters: never chained.
                        if !ink.is_inkstitch {
                            i.close(oficina_io::JOIN_TOL);
                        }
                        i
                    },
                )
            }
            None => oficina_io::load_drawing(input),
        }
        .map_err(|e| Error(e.to_string()))?;
        if !imported.unsupported.is_empty() {
            notes.push(format!(
                "{}: {} element(s) not sewn (text, images: convert them to paths)",
                input.display(),
                imported.unsupported.total()
            ));
        }
        if ink.is_inkstitch {
            notes.push(format!(
                "{}: an Ink/Stitch design: {} element(s) with their own parameters, sewn in document order",
                input.display(),
                ink.len()
            ));
        }
        notes.extend(ink.notes.iter().cloned());
        let mut drawing = imported.drawing;
        // The lettering is sewn as its own Ink/Stitch document after the design.
        let lettered = match text {
            Some(t) => {
                fb.stage("lettering")?;
                let mut t = t.clone();
                if let (true, Some(b)) = (t.under_design, drawing.bounding_box()) {
                    let x = match t.align {
                        Align::Left => b.x0,
                        Align::Center => (b.x0 + b.x1) / 2.0,
                        Align::Right => b.x1,
                    };
                    t.at = oficina_geom::Point::new(x, b.y0 - 1.5 * t.size);
                }
                let mut l = letter(&t).map_err(|e| Error(e.0))?;
                notes.extend(l.notes.iter().cloned());
                transform(&mut l.drawing, p);
                Some(l)
            }
            None => None,
        };
        transform(&mut drawing, p);
        fb.stage("generating stitches")?;
        let mut tick = |done: usize, total: usize| {
            (fb.progress)("generating stitches", done as f64 / total.max(1) as f64)
        };
        let alone = Params {
            center: false,
            ..p.stitch.clone()
        };
        let mut g =
            generate_inkstitch(&drawing, &name, &alone, &ink, &mut tick).map_err(|e| Error(e.0))?;
        if let Some(l) = lettered {
            let lg = l.sew(&alone, &mut |_, _| {}).map_err(|e| Error(e.0))?;
            append(&mut g.plan, lg.plan);
            g.satins += lg.satins;
            g.fills += lg.fills;
            g.runnings += lg.runnings;
        }
        // Centred on the hoop as `generate` centres a design.
        if let Some(b) = g.plan.bounds().filter(|_| p.stitch.center) {
            g.plan = g
                .plan
                .translated(-(b[0] + b[2]) / 2.0, -(b[1] + b[3]) / 2.0);
        }
        let [dx, dy] = p.alteration.shift;
        if dx != 0.0 || dy != 0.0 {
            g.plan = g.plan.translated(dx, dy);
        }
        g
    };
    finish(generated, &name, notes, source, p, fb)
}

/// The alteration's scale, rotation and mirror applied to a design itself (the stitches keep
/// their lengths).
fn transform(drawing: &mut oficina_geom::Drawing, p: &EmbroiderParams) {
    if p.alteration.is_identity() {
        return;
    }
    let [a, b, c, d] = p.alteration.linear();
    let m = oficina_geom::kurbo::Affine::new([a, b, c, d, 0.0, 0.0]);
    for layer in &mut drawing.layers {
        for path in &mut layer.paths {
            *path = path.transform(m);
        }
    }
}

/// The file, the sheet and the preview of generated stitches.
fn finish(
    generated: Generated,
    name: &str,
    notes: Vec<String>,
    source: Option<Format>,
    p: &EmbroiderParams,
    fb: Feedback,
) -> Result<Embroidered, Error> {
    fb.stage("writing the file")?;
    let file = p
        .format
        .write(&generated.plan)
        .map_err(|e| Error(e.to_string()))?;
    let mut back = p
        .format
        .read(&file, name)
        .map_err(|e| Error(e.to_string()))?;
    if !p.format.stores_colours() {
        // The file carries no colours: the design's threads, block for block.
        for (b, g) in back.blocks.iter_mut().zip(&generated.plan.blocks) {
            b.thread = g.thread.clone();
        }
    }
    fb.stage("sheet and table run")?;
    let sheet = sheet_of(&back, p)?;
    let preview = preview_svg(&generated.plan, sheet.hoop.as_ref().ok());
    Ok(Embroidered {
        generated,
        file,
        sheet,
        preview,
        notes,
        source,
    })
}

/// Ink/Stitch's parameters of an SVG design, with its text (none for other drawings, and
/// for a file too large to be a drawing, which the importer then refuses).
pub fn inkstitch_of(input: &Path) -> Result<(Inkstitch, Option<String>), Error> {
    let svg = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    let size = std::fs::metadata(input).map_or(u64::MAX, |m| m.len());
    if !svg || size > oficina_io::MAX_DRAWING_BYTES {
        return Ok((Inkstitch::default(), None));
    }
    let text =
        std::fs::read_to_string(input).map_err(|e| Error(format!("{}: {e}", input.display())))?;
    let ink = read_inkstitch(&text, &input.display().to_string()).map_err(|e| Error(e.0))?;
    Ok((ink, Some(text)))
}

/// A program's Zero-Peça from Zero-Máquina, mm: a `.bor` file's header, else the origin.
fn zero_peca(path: &Path, format: Format) -> Result<[f64; 2], Error> {
    if format != Format::Bor {
        return Ok([0.0, 0.0]);
    }
    let bytes = std::fs::read(path).map_err(|e| Error(format!("{}: {e}", path.display())))?;
    let (_, h) = read_bor(&bytes).map_err(|e| Error(format!("{}: {e}", path.display())))?;
    Ok(h.start)
}

/// The production sheet as the file `path` wants it: HTML for `.html`/`.htm`, else text.
pub fn sheet_document(path: &Path, sheet: &Sheet) -> String {
    let html = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    if html {
        sheet.html()
    } else {
        sheet.text()
    }
}

/// The production sheet as the file `path` wants it, with the design drawn as thread: an A4
/// HTML page with the render embedded for `.html`/`.htm`, else text.
pub fn sheet_document_with_render(path: &Path, sheet: &Sheet, plan: &StitchPlan) -> String {
    let html = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    if !html {
        return sheet.text();
    }
    // A page's render: 200 dpi is plenty for print and keeps the page small.
    let o = oficina_stitch::RenderOptions {
        dpi: 200.0,
        max_side: 2400,
        ..Default::default()
    };
    let png = oficina_stitch::render_png(plan, &o).ok();
    sheet.html_page(png.as_deref())
}

/// The preview file `path` wants: a PNG of the design as thread for `.png` (at `dpi`),
/// else the SVG preview with the hoop.
pub fn preview_document(
    path: &Path,
    plan: &StitchPlan,
    hoop: Option<&Hoop>,
    dpi: f64,
) -> Result<Vec<u8>, Error> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        let o = oficina_stitch::RenderOptions {
            dpi,
            ..Default::default()
        };
        oficina_stitch::render_png(plan, &o).map_err(|e| Error(format!("{}: {e}", path.display())))
    } else {
        Ok(preview_svg(plan, hoop).into_bytes())
    }
}

/// Reads an embroidery file (its format from its content, else its extension), refusing what
/// is too large to be one. A PES or PEC design is centred on the hoop centre, where Brother
/// machines sew it (its file's origin is only where its first stitch happens to be).
pub fn read_stitch_file(path: &Path) -> Result<StitchPlan, Error> {
    read_stitch(path).map(|(plan, _, _)| plan)
}

/// The plan of an embroidery file, its format and how far a Brother design was moved to
/// centre it (mm).
fn read_stitch(path: &Path) -> Result<(StitchPlan, Format, Option<(f64, f64)>), Error> {
    let meta = std::fs::metadata(path).map_err(|e| Error(format!("{}: {e}", path.display())))?;
    if meta.len() > MAX_STITCH_FILE {
        return Err(Error(format!(
            "{}: {} bytes is more than the {} MB a stitch file may have",
            path.display(),
            meta.len(),
            MAX_STITCH_FILE >> 20
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| Error(format!("{}: {e}", path.display())))?;
    let format = Format::sniff(&bytes)
        .or_else(|| Format::from_path(path))
        .ok_or_else(|| {
            Error(format!(
                "{}: not an embroidery file Oficina reads (it reads {})",
                path.display(),
                writable()
            ))
        })?;
    let name = path
        .file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().to_string());
    let plan = format
        .read(&bytes, &name)
        .map_err(|e| Error(format!("{}: {e}", path.display())))?;
    if !matches!(format, Format::Pes | Format::PesV1 | Format::Pec) {
        return Ok((plan, format, None));
    }
    let Some([x0, y0, x1, y1]) = plan.bounds() else {
        return Ok((plan, format, None));
    };
    // The centre rounded to the files' 0.1 mm, so the stitches stay on their grid.
    let (dx, dy) = (
        -((x0 + x1) * 5.0).round() / 10.0,
        -((y0 + y1) * 5.0).round() / 10.0,
    );
    Ok((plan.translated(dx, dy), format, Some((dx, dy))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_parameters_are_refused_naming_their_flag() {
        assert_eq!(EmbroiderParams::default().check(), Ok(()));
        let mut p = EmbroiderParams {
            ppm: Some(0.0),
            ..EmbroiderParams::default()
        };
        let e = p.check().unwrap_err();
        assert_eq!(e.field().as_deref(), Some("ppm"), "{e}");
        p.ppm = Some(350.0);
        p.stitch.stitch_length = 0.0;
        let e = p.check().unwrap_err();
        assert_eq!(e.field().as_deref(), Some("stitch_length"), "{e}");
        assert!(e.0.contains("stitch length (mm) 0 is outside"), "{e}");
    }

    #[test]
    fn an_inkstitch_design_sews_with_its_parameters_and_a_bad_one_is_named() {
        let dir = std::env::temp_dir().join(format!("oficina-ink-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let svg = |spacing: &str| {
            format!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkstitch="http://inkstitch.org/namespace" width="40mm" height="20mm" viewBox="0 0 40 20">
                 <path id="col" d="M2 5 L38 5 M2 9 L38 9" fill="none" stroke="black" stroke-width="0.1"
                       inkstitch:satin_column="true" inkstitch:zigzag_spacing_mm="{spacing}"/></svg>"#
            )
        };
        let good = dir.join("col.svg");
        std::fs::write(&good, svg("0.5")).unwrap();
        let out = embroider(&good, &EmbroiderParams::default(), Feedback::none()).unwrap();
        assert_eq!(out.generated.satins, 1);
        assert!(
            out.notes.iter().any(|n| n.contains("Ink/Stitch design")),
            "{:?}",
            out.notes
        );
        // A 36 mm column at 0.5 mm peak to peak: 73 zig-zags, two needle points each.
        let n = out.generated.plan.counts().stitches;
        assert!((146..=160).contains(&n), "{n}");
        let bad = dir.join("bad.svg");
        std::fs::write(&bad, svg("dense")).unwrap();
        let e = embroider(&bad, &EmbroiderParams::default(), Feedback::none())
            .err()
            .unwrap();
        assert!(
            e.0.contains("bad.svg") && e.0.contains("#col") && e.0.contains("zigzag_spacing_mm"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn inkstitch_commands_and_ripples_reach_the_stitches() {
        let dir = std::env::temp_dir().join(format!("oficina-ink-cmd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // A column from x 2 to 38 with a satin_start command at its right end, and a ripple
        // circle: the design starts at the column's right end (centred: x = +18).
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
              xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
              xmlns:inkstitch="http://inkstitch.org/namespace" width="40mm" height="40mm" viewBox="0 0 40 40">
            <defs><symbol id="inkstitch_satin_start"><circle r="3"/></symbol></defs>
            <path id="col" d="M2 5 L38 5 M2 9 L38 9" fill="none" stroke="black" stroke-width="0.1"
                  inkstitch:satin_column="true"/>
            <circle id="rip" cx="20" cy="26" r="10" fill="none" stroke="black" stroke-width="0.1"
                  inkstitch:stroke_method="ripple_stitch" inkstitch:line_count="4"/>
            <path id="cc" d="M 45,7 38,7" inkscape:connection-start="#cu" inkscape:connection-end="#col"/>
            <use id="cu" xlink:href="#inkstitch_satin_start" x="45" y="7"/>
          </svg>"##;
        let path = dir.join("cmd.svg");
        std::fs::write(&path, svg).unwrap();
        let out = embroider(&path, &EmbroiderParams::default(), Feedback::none()).unwrap();
        let first = out
            .generated
            .plan
            .entries()
            .find(|(_, s)| s.kind == oficina_stitch::Kind::Stitch)
            .unwrap()
            .1;
        assert!(first.x > 17.0, "{first:?}");
        // The ripple is a ripple now (no note that it is sewn as a running line), and the
        // command's symbol is not sewn: the design is the column and the circle, 36 × 31 mm.
        assert!(
            !out.notes.iter().any(|n| n.contains("ripple")),
            "{:?}",
            out.notes
        );
        let b = out.generated.plan.bounds().unwrap();
        assert!(
            (b[2] - b[0] - 36.0).abs() < 1.0 && (b[3] - b[1] - 31.0).abs() < 1.0,
            "{b:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
