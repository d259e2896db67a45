//! The CADTEC public file `.PUB` (seed 000, §5.1 of the digest; Appendix II of the thesis):
//! the ASCII drawing CAMbor read. Units mm, one decimal.
//!
//! - `$ …` header lines: ignored (CAMbor ignored them too).
//! - `P TIPO COR ESTILO ESPESSURA NIVEL NPTO`, then NPTO points as `X Y` pairs, five to a
//!   line (any wrapping is accepted: numbers are read until NPTO pairs are in).
//! - `A TIPO COR ESTILO ESPESSURA NIVEL CX CY RAIO ANGI ANGF`: an arc about (CX, CY), from
//!   ANGI to ANGF degrees, counter-clockwise (the seed does not say; CCW is the CAD habit).
//! - Any other entity letter (and the numeric lines after it) is counted as unsupported.
//!
//! ESTILO 3 (dotted in CADTEC) is running stitch: a hairline stroke. Any other style is satin:
//! a stroke [`PUB_SATIN_WIDTH`] mm wide (the seed's LARGURA is an operator parameter, not in
//! the file). COR indexes [`PUB_COLOURS`] (the 16 DOS colours). Levels above 20 are ignored
//! (where CADTEC users kept hoop outlines); level 20 itself is kept ("above 20", L1643).
//! Each entity is its own layer-less path, in file order, its source the entity's line.

use crate::import::{ImportError, Imported};
use oficina_geom::{Arc, Color, Drawing, Path, Point, Segment, SourceRef, Style};

/// Stroke width given to satin (ESTILO ≠ 3) entities, mm.
pub const PUB_SATIN_WIDTH: f64 = 3.0;

/// Highest CADTEC level CAMbor sews.
pub const PUB_MAX_LEVEL: i64 = 20;

/// The 16 colours of a DOS palette, by CADTEC colour index (modulo 16).
pub const PUB_COLOURS: [[u8; 3]; 16] = [
    [0, 0, 0],
    [0, 0, 170],
    [0, 170, 0],
    [0, 170, 170],
    [170, 0, 0],
    [170, 0, 170],
    [170, 85, 0],
    [170, 170, 170],
    [85, 85, 85],
    [85, 85, 255],
    [85, 255, 85],
    [85, 255, 255],
    [255, 85, 85],
    [255, 85, 255],
    [255, 255, 85],
    [255, 255, 255],
];

struct Entity {
    line: usize,
    cor: i64,
    estilo: i64,
    nivel: i64,
}

/// Reads a `.PUB` text; `name` is the file for messages and sources.
pub fn pub_from_str(text: &str, name: &str) -> Result<Imported, ImportError> {
    let mut drawing = Drawing::new();
    let mut imported = Imported::default();
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    let err = |line: usize, m: String| ImportError::new(name, format!("line {line}"), m);
    let num = |tok: &str, line: usize, what: &str| -> Result<f64, ImportError> {
        tok.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| err(line, format!("{what} '{tok}' is not a number")))
    };
    while i < lines.len() {
        let lno = i + 1;
        let line = lines[i].trim();
        i += 1;
        if line.is_empty() || line.starts_with('$') || line.starts_with('\u{1a}') {
            continue;
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        let head = toks[0];
        if !head.starts_with(|c: char| c.is_ascii_alphabetic()) {
            return Err(err(
                lno,
                format!("'{head}': expected an entity record (P, A) or a $ header line"),
            ));
        }
        let ent = |n: usize| -> Result<Entity, ImportError> {
            if toks.len() < n {
                return Err(err(
                    lno,
                    format!(
                        "{head} record has {} fields, expected {n} (TIPO COR ESTILO ESPESSURA NIVEL …)",
                        toks.len() - 1
                    ),
                ));
            }
            let int = |k: usize, what: &str| -> Result<i64, ImportError> {
                toks[k]
                    .parse::<i64>()
                    .map_err(|_| err(lno, format!("{what} '{}' is not an integer", toks[k])))
            };
            Ok(Entity {
                line: lno,
                cor: int(2, "COR")?,
                estilo: int(3, "ESTILO")?,
                nivel: int(5, "NIVEL")?,
            })
        };
        let path = match head {
            "P" => {
                let e = ent(7)?;
                let n = toks[6]
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n <= 1_000_000)
                    .ok_or_else(|| err(lno, format!("NPTO '{}' is not a point count", toks[6])))?;
                let mut vals: Vec<f64> = Vec::with_capacity(2 * n);
                for t in &toks[7..] {
                    vals.push(num(t, lno, "coordinate")?);
                }
                while vals.len() < 2 * n {
                    let Some(l) = lines.get(i) else {
                        return Err(err(
                            lno,
                            format!(
                                "polyline of {n} points ends after {} numbers: the file is truncated",
                                vals.len()
                            ),
                        ));
                    };
                    let l = l.trim();
                    if l.starts_with(|c: char| c.is_ascii_alphabetic() || c == '$') {
                        return Err(err(
                            i + 1,
                            format!(
                                "polyline of line {lno} needs {n} points, has {} before this record",
                                vals.len() / 2
                            ),
                        ));
                    }
                    i += 1;
                    for t in l.split_whitespace() {
                        vals.push(num(t, i, "coordinate")?);
                    }
                }
                if vals.len() != 2 * n {
                    return Err(err(
                        i,
                        format!(
                            "polyline of line {lno}: {} numbers for {n} points",
                            vals.len()
                        ),
                    ));
                }
                let pts: Vec<Point> = vals.chunks(2).map(|c| Point::new(c[0], c[1])).collect();
                if pts.len() < 2 {
                    imported
                        .unsupported
                        .add("polyline of one point", format!("line {lno}"));
                    continue;
                }
                (e, Path::polyline(&pts, false))
            }
            "A" => {
                let e = ent(11)?;
                let v: Vec<f64> = toks[6..11]
                    .iter()
                    .zip(["CX", "CY", "RAIO", "ANGI", "ANGF"])
                    .map(|(t, w)| num(t, lno, w))
                    .collect::<Result<_, _>>()?;
                if v[2] <= 0.0 {
                    return Err(err(lno, format!("arc radius {} must be positive", v[2])));
                }
                let mut sweep = (v[4] - v[3]).rem_euclid(360.0);
                if sweep == 0.0 {
                    sweep = 360.0;
                }
                let arc = Arc::new(
                    Point::new(v[0], v[1]),
                    v[2],
                    v[3].to_radians(),
                    sweep.to_radians(),
                );
                (e, Path::new(vec![Segment::Arc(arc)], false))
            }
            other => {
                imported
                    .unsupported
                    .add(&format!("PUB entity {other}"), format!("line {lno}"));
                while lines.get(i).is_some_and(|l| {
                    let l = l.trim();
                    !l.is_empty() && !l.starts_with(|c: char| c.is_ascii_alphabetic() || c == '$')
                }) {
                    i += 1;
                }
                continue;
            }
        };
        let (e, path) = path;
        if e.nivel > PUB_MAX_LEVEL {
            continue;
        }
        let [r, g, b] = PUB_COLOURS[e.cor.rem_euclid(16) as usize];
        let style = Style {
            stroke: Some(Color::rgb(r, g, b)),
            stroke_width: if e.estilo == 3 { 0.0 } else { PUB_SATIN_WIDTH },
            fill: None,
        };
        let mut src = SourceRef::new(name, format!("{head} level {}", e.nivel));
        src.line = Some(e.line);
        drawing.push("0", path.with_style(style).with_source(src));
    }
    imported.drawing = drawing;
    Ok(imported)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EMC: &str = "$ EMPRESA ITAUTEC INFORMATICA\n$ TIPOARQ ARQUIVO PUBLICO\n$ UNI 1.0 MM\n\
P 1 2 3 1 0 6\n0.0 0.0 10.0 0.0 10.0 10.0 0.0 10.0 0.0 0.0\n5.0 5.0\n\
A 1 4 1 1 0 0.0 0.0 20.0 0.0 90.0\n\
P 1 1 1 1 23 2\n-80.0 0.0 80.0 0.0\n";

    #[test]
    fn polylines_arcs_styles_levels() {
        let imp = pub_from_str(EMC, "emc.pub").unwrap();
        let paths: Vec<_> = imp.drawing.paths().collect();
        assert_eq!(paths.len(), 2, "level 23 is ignored");
        // The polyline: 6 points, 5 segments, running (hairline), colour 2.
        assert_eq!(paths[0].segments.len(), 5);
        assert_eq!(paths[0].style.stroke_width, 0.0);
        assert_eq!(paths[0].style.stroke, Some(Color::rgb(0, 170, 0)));
        assert_eq!(paths[0].source.line, Some(4));
        // The arc: a quarter of radius 20, satin, its length π·20/2.
        assert_eq!(paths[1].style.stroke_width, PUB_SATIN_WIDTH);
        let len = paths[1].length();
        assert!((len - std::f64::consts::PI * 10.0).abs() < 1e-9, "{len}");
    }

    #[test]
    fn bad_records_name_their_line() {
        let e = pub_from_str("$ X\nP 1 2 3 1 0 3\n1 2 3 4\n", "t.pub").unwrap_err();
        assert_eq!(e.location, "line 2");
        assert!(e.message.contains("truncated"), "{e}");
        let e = pub_from_str("P 1 2 3 1 0 2\n1 2 x 4\n", "t.pub").unwrap_err();
        assert_eq!(e.location, "line 2");
        let e = pub_from_str("A 1 2 3 1 0 0 0 -5 0 90\n", "t.pub").unwrap_err();
        assert_eq!(e.location, "line 1");
        let e = pub_from_str("P 1 2\n", "t.pub").unwrap_err();
        assert!(e.message.contains("fields"), "{e}");
        let e = pub_from_str("P 1 2 3 1 0 2\n1 2\nA 1 2 3 1 0 0 0 5 0 90\n", "t.pub").unwrap_err();
        assert_eq!(e.location, "line 3");
        let e = pub_from_str("12 13\n", "t.pub").unwrap_err();
        assert_eq!(e.location, "line 1");
    }

    #[test]
    fn other_entities_are_counted_and_skipped() {
        let imp = pub_from_str("T 1 1 1 1 0 2\n3 4\nP 1 0 3 1 0 2\n0 0 1 1\n", "t.pub").unwrap();
        assert_eq!(imp.drawing.path_count(), 1);
        assert_eq!(imp.unsupported.total(), 1);
    }
}
