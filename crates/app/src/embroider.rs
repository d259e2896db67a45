//! Embroidery jobs: a design (SVG/DXF) → stitches → hoop check → sheet → DST/EXP file and
//! preview → a run on the needle-synchronised table; and the sheet of any stitch file.

use crate::{Error, Feedback};
use oficina_stitch::{
    generate, preview_svg, sheet, Format, Generated, HeadSpeed, Hoop, Params, Pauses, Sheet,
    StitchPlan, Table,
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

/// The whole pipeline for a design file.
pub fn embroider(input: &Path, p: &EmbroiderParams, fb: Feedback) -> Result<Embroidered, Error> {
    p.check()?;
    fb.stage("reading the design")?;
    let imported = oficina_io::load_drawing(input).map_err(|e| Error(e.to_string()))?;
    let mut notes = Vec::new();
    if !imported.unsupported.is_empty() {
        notes.push(format!(
            "{}: {} element(s) not sewn (text, images: convert them to paths)",
            input.display(),
            imported.unsupported.total()
        ));
    }
    let name = input
        .file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().to_string());
    fb.stage("generating stitches")?;
    let mut tick = |done: usize, total: usize| {
        (fb.progress)("generating stitches", done as f64 / total.max(1) as f64)
    };
    let generated =
        generate(&imported.drawing, &name, &p.stitch, &mut tick).map_err(|e| Error(e.0))?;
    fb.stage("writing the file")?;
    let file = p
        .format
        .write(&generated.plan)
        .map_err(|e| Error(e.to_string()))?;
    let mut back = p
        .format
        .read(&file, &name)
        .map_err(|e| Error(e.to_string()))?;
    // The file carries no colours: the design's threads, block for block.
    for (b, g) in back.blocks.iter_mut().zip(&generated.plan.blocks) {
        b.thread = g.thread.clone();
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
    })
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

/// Reads a DST/EXP/seed RAM file (by extension), refusing what is too large to be one.
pub fn read_stitch_file(path: &Path) -> Result<StitchPlan, Error> {
    let format = Format::from_path(path).ok_or_else(|| {
        Error(format!(
            "{}: unknown stitch file extension (read: .dst, .exp, .ram)",
            path.display()
        ))
    })?;
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
    let name = path
        .file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().to_string());
    format
        .read(&bytes, &name)
        .map_err(|e| Error(format!("{}: {e}", path.display())))
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
}
