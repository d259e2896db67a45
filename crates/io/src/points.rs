//! Digitised point lists: one point a line, x and y separated by commas, semicolons, tabs or
//! spaces, with or without a header line naming the columns (`x`, `y` found by name, else the
//! first two columns). `#` starts a comment. With `;` as separator a decimal comma is read
//! (`40,9;0,0`), as Brazilian spreadsheets write it.

use crate::import::ImportError;
use oficina_geom::Point;

/// Most points one list may hold.
pub(crate) const MAX_POINTS: usize = 10_000_000;

/// Coordinates beyond this (mm) are taken as a mistake.
const ABSURD: f64 = 1e9;

/// Parses a point list; `file` names it in errors.
pub fn parse_points(text: &str, file: &str) -> Result<Vec<Point>, ImportError> {
    let mut out = Vec::new();
    let mut cols: Option<(usize, usize)> = None;
    let mut seen_data = false;
    for (no, raw) in text.lines().enumerate() {
        let line_no = no + 1;
        let at = || format!("line {line_no}");
        let line = raw
            .split('#')
            .next()
            .unwrap_or("")
            .trim()
            .trim_start_matches('\u{feff}');
        if line.is_empty() {
            continue;
        }
        let semicolon = line.contains(';');
        let fields: Vec<String> = line
            .split(|c: char| c == ';' || c == '\t' || c == ' ' || (!semicolon && c == ','))
            .filter(|s| !s.is_empty())
            .map(|s| {
                if semicolon {
                    s.replace(',', ".")
                } else {
                    s.to_string()
                }
            })
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if !seen_data && cols.is_none() && numbers.iter().any(|n| n.is_none()) {
            // A header: find x and y by name.
            let find = |name: &str| {
                fields
                    .iter()
                    .position(|f| f.trim_matches('"').eq_ignore_ascii_case(name))
            };
            cols = Some(match (find("x"), find("y")) {
                (Some(x), Some(y)) => (x, y),
                _ => (0, 1),
            });
            continue;
        }
        seen_data = true;
        let (cx, cy) = cols.unwrap_or((0, 1));
        let get = |i: usize| -> Result<f64, ImportError> {
            let f = fields.get(i).ok_or_else(|| {
                ImportError::new(
                    file,
                    at(),
                    format!(
                        "expected x and y, found {} value(s) in '{raw}'",
                        fields.len()
                    ),
                )
            })?;
            let v = numbers[i]
                .ok_or_else(|| ImportError::new(file, at(), format!("'{f}' is not a number")))?;
            if !v.is_finite() || v.abs() > ABSURD {
                return Err(ImportError::new(
                    file,
                    at(),
                    format!("{v} is not a usable coordinate (mm)"),
                ));
            }
            Ok(v)
        };
        let p = Point::new(get(cx)?, get(cy)?);
        if out.len() >= MAX_POINTS {
            return Err(ImportError::new(
                file,
                at(),
                format!("more than {MAX_POINTS} points"),
            ));
        }
        out.push(p);
    }
    if out.is_empty() {
        return Err(ImportError::new(file, "file", "no points found"));
    }
    Ok(out)
}

/// Reads a point list file (size-capped).
pub fn load_points(path: &std::path::Path) -> Result<Vec<Point>, ImportError> {
    let name = path.display().to_string();
    let bytes = crate::import::read_capped(path)?;
    parse_points(crate::import::utf8(&bytes, &name)?, &name)
}

/// Writes points as CSV with an `x,y` header.
pub fn write_points_csv(points: &[Point]) -> String {
    let mut s = String::from("x,y\n");
    for p in points {
        s.push_str(&format!("{},{}\n", p.x, p.y));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_or_not_any_separator_decimal_comma() {
        let a = parse_points("x,y\n1,2\n3.5,4\n", "a").unwrap();
        assert_eq!(a, vec![Point::new(1.0, 2.0), Point::new(3.5, 4.0)]);
        let b = parse_points("# digitised\n1 2\n3.5\t4\n", "b").unwrap();
        assert_eq!(a, b);
        let c = parse_points("id;y;x\n7;2,0;1,0\n8;4;3,5\n", "c").unwrap();
        assert_eq!(a, c, "columns by name, decimal comma");
    }

    #[test]
    fn bad_lines_are_named() {
        let e = parse_points("1,2\n3,abc\n", "f.csv").unwrap_err();
        assert_eq!(e.location, "line 2");
        assert!(e.to_string().contains("'abc' is not a number"), "{e}");
        let e = parse_points("1,2\n3\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("line 2") && e.to_string().contains("expected x and y"));
        assert!(parse_points("1,inf\n", "f").is_err());
        assert!(parse_points("", "f").is_err());
    }

    #[test]
    fn round_trip_through_csv() {
        let p = vec![Point::new(0.1, -2.5), Point::new(1e3, 7.0)];
        assert_eq!(parse_points(&write_points_csv(&p), "w").unwrap(), p);
    }
}
