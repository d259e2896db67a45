//! HPGL (HP-GL/1, the language of HP's and Roland's pen plotters) → `Drawing`.
//!
//! Supported: IN, DF, SP, PU, PD, PA, PR, CI, AA, AR, LB, DT, SI, DI. Coordinates are plotter
//! units, 40 per mm (HP's 0.025 mm). Each pen is a layer `pen N`; pen-down runs become
//! polylines, circles and arcs stay circular arcs. Labels are returned as [`Label`]s (the
//! caller draws them with a single-stroke font). Instructions that change only speed, line
//! type or scaling (VS, LT, SC, IP, …) are counted as unsupported, never dropped in silence.
//! Errors name the line and the instruction.

use crate::import::{ImportError, Imported};
use oficina_geom::{Arc, Path, Point, Segment, SourceRef, Vec2};

/// Plotter units per millimetre.
pub(crate) const UNITS_PER_MM: f64 = 40.0;
/// Coordinates beyond this (plotter units, ≈ 25 km) are refused as absurd.
const MAX_COORD: f64 = 1e9;

/// A label (`LB`): text at a place, in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub at: Point,
    pub text: String,
    /// Cap height and character width, mm (`SI`, default 3.75 × 2.85 as on A4 plotters).
    pub height: f64,
    pub width: f64,
    /// Direction of the text baseline, radians (`DI`).
    pub angle: f64,
    pub layer: String,
}

/// An imported HPGL file: the drawing and its labels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hpgl {
    /// The drawing, pens as layers.
    pub imported: Imported,
    /// The `LB` labels, placed.
    pub labels: Vec<Label>,
}

struct State {
    at: Point,
    down: bool,
    relative: bool,
    pen: u32,
    terminator: u8,
    size: (f64, f64),
    angle: f64,
    /// The pen-down run being drawn.
    run: Vec<Point>,
    run_line: usize,
}

/// Parses HPGL text; `file` names it in errors.
pub fn hpgl_from_bytes(bytes: &[u8], file: &str) -> Result<Hpgl, ImportError> {
    let mut out = Hpgl::default();
    let mut st = State {
        at: Point::ORIGIN,
        down: false,
        relative: false,
        pen: 1,
        terminator: 3,
        size: (2.85, 3.75),
        angle: 0.0,
        run: Vec::new(),
        run_line: 1,
    };
    let mut i = 0;
    let mut line = 1;
    let n = bytes.len();
    while i < n {
        let c = bytes[i];
        match c {
            b'\n' => {
                line += 1;
                i += 1;
                continue;
            }
            b' ' | b'\t' | b'\r' | b';' | b',' | 0 => {
                i += 1;
                continue;
            }
            // Device-control escapes (ESC . x … :) from plotter drivers: skipped.
            0x1b => {
                while i < n && bytes[i] != b':' && bytes[i] != b'\n' {
                    i += 1;
                }
                i += 1;
                continue;
            }
            _ => {}
        }
        if !(c.is_ascii_alphabetic() && i + 1 < n && bytes[i + 1].is_ascii_alphabetic()) {
            return Err(ImportError::new(
                file,
                format!("line {line}"),
                format!(
                    "expected a two-letter instruction, found '{}'",
                    String::from_utf8_lossy(&bytes[i..(i + 8).min(n)]).escape_debug()
                ),
            ));
        }
        let mn = [c.to_ascii_uppercase(), bytes[i + 1].to_ascii_uppercase()];
        let name = std::str::from_utf8(&mn).unwrap_or("??").to_string();
        i += 2;
        let here =
            |line: usize, msg: String| ImportError::new(file, format!("line {line}, {name}"), msg);
        match &mn {
            b"LB" => {
                let start = i;
                while i < n && bytes[i] != st.terminator {
                    i += 1;
                }
                let text = String::from_utf8_lossy(&bytes[start..i]).into_owned();
                line += text.matches('\n').count();
                i += 1;
                let (w, h) = st.size;
                out.labels.push(Label {
                    at: mm(st.at),
                    text,
                    height: h,
                    width: w,
                    angle: st.angle,
                    layer: layer(st.pen),
                });
                continue;
            }
            b"DT" => {
                st.terminator = *bytes.get(i).unwrap_or(&3);
                i += 1;
                continue;
            }
            _ => {}
        }
        // Parameters: numbers separated by commas or spaces, up to the next instruction.
        let mut params = Vec::new();
        loop {
            while i < n && matches!(bytes[i], b' ' | b',' | b'\t' | b'\r' | b'\n') {
                if bytes[i] == b'\n' {
                    line += 1;
                }
                i += 1;
            }
            if i >= n
                || !(bytes[i] == b'-'
                    || bytes[i] == b'+'
                    || bytes[i] == b'.'
                    || bytes[i].is_ascii_digit())
            {
                break;
            }
            let start = i;
            i += 1;
            while i < n && (bytes[i].is_ascii_digit() || matches!(bytes[i], b'.' | b'e' | b'E')) {
                i += 1;
            }
            let t = std::str::from_utf8(&bytes[start..i]).unwrap_or("");
            let v: f64 = t
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && v.abs() <= MAX_COORD)
                .ok_or_else(|| here(line, format!("'{t}' is not a number within ±{MAX_COORD}")))?;
            params.push(v);
            if params.len() > 1_000_000 {
                return Err(here(line, "more than a million parameters".into()));
            }
        }
        match &mn {
            b"IN" | b"DF" => {
                flush(&mut st, &mut out.imported, file);
                st.down = false;
                st.relative = false;
                st.terminator = 3;
                st.size = (2.85, 3.75);
                st.angle = 0.0;
                if mn == *b"IN" {
                    st.at = Point::ORIGIN;
                }
            }
            b"SP" => {
                flush(&mut st, &mut out.imported, file);
                st.pen = match params.first() {
                    None => 0,
                    Some(&p) if (0.0..=255.0).contains(&p) => p as u32,
                    Some(p) => return Err(here(line, format!("pen {p} is not 0…255"))),
                };
            }
            b"PU" | b"PD" | b"PA" | b"PR" => {
                match &mn {
                    b"PU" => {
                        flush(&mut st, &mut out.imported, file);
                        st.down = false;
                    }
                    b"PD" => st.down = true,
                    b"PA" => st.relative = false,
                    _ => st.relative = true,
                }
                if params.len() % 2 == 1 {
                    return Err(here(
                        line,
                        format!("{} parameters: coordinates come in X,Y pairs", params.len()),
                    ));
                }
                for xy in params.chunks(2) {
                    let p = if st.relative {
                        Point::new(st.at.x + xy[0], st.at.y + xy[1])
                    } else {
                        Point::new(xy[0], xy[1])
                    };
                    move_to(&mut st, p, line, &mut out.imported, file);
                }
            }
            b"CI" => {
                let r = *params
                    .first()
                    .ok_or_else(|| here(line, "needs a radius (CI r[,chord angle])".into()))?;
                if r == 0.0 {
                    continue;
                }
                let arc = Arc::new(
                    mm(st.at),
                    r.abs() / UNITS_PER_MM,
                    0.0,
                    std::f64::consts::TAU,
                );
                let path =
                    Path::new(vec![Segment::Arc(arc)], true).with_source(source(file, line, "CI"));
                out.imported.drawing.push(&layer(st.pen), path);
            }
            b"AA" | b"AR" => {
                if params.len() < 3 {
                    return Err(here(
                        line,
                        format!(
                        "needs X,Y,sweep (centre and sweep angle in degrees), got {} parameters",
                        params.len()
                    ),
                    ));
                }
                let c = if mn == *b"AR" {
                    Point::new(st.at.x + params[0], st.at.y + params[1])
                } else {
                    Point::new(params[0], params[1])
                };
                let sweep = params[2].to_radians();
                if sweep.abs() > 360f64.to_radians() * 1000.0 {
                    return Err(here(line, format!("sweep {}° is absurd", params[2])));
                }
                let r = c.distance(st.at);
                let start = (st.at - c).atan2();
                let end = c + Vec2::from_angle(start + sweep) * r;
                if st.down && r > 0.0 {
                    flush(&mut st, &mut out.imported, file);
                    let arc = Arc::new(mm(c), r / UNITS_PER_MM, start, sweep);
                    let path = Path::new(vec![Segment::Arc(arc)], false)
                        .with_source(source(file, line, &name));
                    out.imported.drawing.push(&layer(st.pen), path);
                }
                st.at = end;
            }
            b"SI" => {
                if params.len() >= 2 {
                    // SI is in centimetres.
                    st.size = (params[0] * 10.0, params[1] * 10.0);
                } else {
                    st.size = (2.85, 3.75);
                }
            }
            b"DI" => {
                st.angle = match params.as_slice() {
                    [run, rise, ..] if *run != 0.0 || *rise != 0.0 => rise.atan2(*run),
                    _ => 0.0,
                };
            }
            _ => {
                if !mn.iter().all(u8::is_ascii_uppercase) {
                    return Err(here(line, "not an instruction".into()));
                }
                out.imported.unsupported.add(&name, format!("line {line}"));
            }
        }
    }
    flush(&mut st, &mut out.imported, file);
    Ok(out)
}

fn mm(p: Point) -> Point {
    Point::new(p.x / UNITS_PER_MM, p.y / UNITS_PER_MM)
}

fn layer(pen: u32) -> String {
    format!("pen {pen}")
}

fn source(file: &str, line: usize, element: &str) -> SourceRef {
    SourceRef {
        file: file.to_string(),
        element: element.to_string(),
        line: Some(line),
    }
}

fn move_to(st: &mut State, p: Point, line: usize, out: &mut Imported, file: &str) {
    if st.down {
        if st.run.is_empty() {
            st.run.push(mm(st.at));
            st.run_line = line;
        }
        st.run.push(mm(p));
    } else {
        flush(st, out, file);
    }
    st.at = p;
}

/// Ends the pen-down run as a polyline path (a lone PD with no move draws a dot).
fn flush(st: &mut State, out: &mut Imported, file: &str) {
    if st.run.len() >= 2 {
        let pts = std::mem::take(&mut st.run);
        let path = Path::polyline(&pts, false).with_source(source(file, st.run_line, "PD"));
        out.drawing.push(&layer(st.pen), path);
    }
    st.run.clear();
}

/// Loads `.hpgl`/`.plt` files with the same size cap as the other importers.
pub fn load_hpgl(path: &std::path::Path) -> Result<Hpgl, ImportError> {
    let bytes = crate::import::read_capped(path)?;
    hpgl_from_bytes(&bytes, &path.display().to_string())
}
