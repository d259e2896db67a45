//! Layout on a page, as vpype's `layout` command does it: a page size (a named size or W×H
//! with units), portrait unless landscape; the drawing centred on it, and either scaled to fit
//! inside the margins (vpype's `--fit-to-margins`) or kept at its size (vpype's default).
//!
//! With the drawing's box w × h and the page W × H, margin m:
//! fit: s = min((W − 2m)/w, (H − 2m)/h), the box scaled by s about its corner;
//! both: the box's lower-left corner goes to ((W − s·w)/2, (H − s·h)/2) on the page, which is
//! vpype's offset `m + (W − s·w − 2m)/2` written out. Centring is symmetric, so vpype's page
//! (y down) and ours (y up) put the drawing at the same place.

use crate::machine::PlotError;
use crate::strokes::Plot;
use oficina_geom::Point;

/// Named page sizes (portrait, mm): vpype's list.
pub const PAGE_SIZES: &[(&str, f64, f64)] = &[
    ("a6", 105.0, 148.0),
    ("a5", 148.0, 210.0),
    ("a4", 210.0, 297.0),
    ("a3", 297.0, 420.0),
    ("a2", 420.0, 594.0),
    ("a1", 594.0, 841.0),
    ("a0", 841.0, 1189.0),
    ("letter", 215.9, 279.4),
    ("legal", 215.9, 355.6),
    ("executive", 185.15, 266.7),
    ("tabloid", 279.4, 431.8),
];

/// Units a page size may carry, in mm.
const UNITS: &[(&str, f64)] = &[
    ("mm", 1.0),
    ("cm", 10.0),
    ("in", 25.4),
    ("pt", 25.4 / 72.0),
    ("pc", 25.4 / 6.0),
    ("px", 25.4 / 96.0),
    ("m", 1000.0),
];

/// A page size: a name (`a4`, `a3`, `letter`, …, see [`PAGE_SIZES`]) or `WxH` in mm, each
/// number with an optional unit (`8.5x11in`, `210mmx297mm`, `30cmx20cm`; a unit on the second
/// number only applies to both). Returns (width, height) in mm as written.
pub fn page_size(s: &str) -> Result<(f64, f64), String> {
    let t = s.trim().to_ascii_lowercase();
    if let Some(&(_, w, h)) = PAGE_SIZES.iter().find(|(n, _, _)| *n == t) {
        return Ok((w, h));
    }
    let names: Vec<&str> = PAGE_SIZES.iter().map(|p| p.0).collect();
    let bad = || {
        format!(
            "page '{s}': use a name ({}) or WxH in mm, e.g. 300x200 or 8.5x11in",
            names.join(", ")
        )
    };
    let (a, b) = t.split_once('x').ok_or_else(bad)?;
    let split = |v: &str| -> Result<(f64, Option<f64>), String> {
        let v = v.trim();
        let cut = v.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(v.len());
        let (num, unit) = v.split_at(cut);
        let n: f64 = num.trim().parse().map_err(|_| bad())?;
        let u = if unit.is_empty() {
            None
        } else {
            Some(
                UNITS
                    .iter()
                    .find(|(u, _)| *u == unit)
                    .map(|(_, f)| *f)
                    .ok_or_else(|| {
                        format!("page '{s}': unknown unit '{unit}' (mm, cm, in, pt, px)")
                    })?,
            )
        };
        Ok((n, u))
    };
    let (w, uw) = split(a)?;
    let (h, uh) = split(b)?;
    let (uw, uh) = (uw.or(uh).unwrap_or(1.0), uh.unwrap_or(1.0));
    let (w, h) = (w * uw, h * uh);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0 && w <= 1e5 && h <= 1e5) {
        return Err(format!(
            "page '{s}': width and height must be > 0 and at most 100 m"
        ));
    }
    Ok((w, h))
}

/// How a drawing is laid out on a page.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Page (width, height) in mm as named; `landscape` turns it.
    pub page: (f64, f64),
    /// Landscape: the longer side horizontal. Otherwise portrait (vpype's rule for both).
    pub landscape: bool,
    /// Margin on every side when fitting, mm.
    pub margin: f64,
    /// Scale to fit inside the margins (up or down); otherwise keep the size and only centre.
    pub fit: bool,
}

impl Layout {
    /// The page (width, height) in the layout's orientation.
    pub fn oriented(&self) -> (f64, f64) {
        let (a, b) = self.page;
        let (short, long) = (a.min(b), a.max(b));
        if self.landscape {
            (long, short)
        } else {
            (short, long)
        }
    }
}

/// What a layout did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    /// The page used (width, height), mm.
    pub page: (f64, f64),
    /// The scale applied (1 without fitting).
    pub scale: f64,
}

/// Lays `plot` out on the page of `l` whose lower-left corner is `corner` (work coordinates).
pub fn layout(plot: &mut Plot, l: &Layout, corner: Point) -> Result<Placed, PlotError> {
    let page = l.oriented();
    let (pw, ph) = page;
    let b = plot.bounds().ok_or(PlotError::Empty)?;
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    let m = l.margin;
    if !(m.is_finite() && m >= 0.0 && 2.0 * m < pw.min(ph)) {
        return Err(PlotError::Layout(format!(
            "margin {m} mm leaves nothing of the {pw} × {ph} mm page"
        )));
    }
    let scale = if l.fit {
        let sx = if w > 0.0 {
            (pw - 2.0 * m) / w
        } else {
            f64::INFINITY
        };
        let sy = if h > 0.0 {
            (ph - 2.0 * m) / h
        } else {
            f64::INFINITY
        };
        let s = sx.min(sy);
        if s.is_finite() {
            s
        } else {
            1.0
        }
    } else {
        if w > pw + 1e-9 || h > ph + 1e-9 {
            return Err(PlotError::Layout(format!(
                "the drawing ({w:.1} × {h:.1} mm) is larger than the {pw} × {ph} mm page: let it be scaled to fit (drop --no-fit) or use a larger page"
            )));
        }
        1.0
    };
    let to = Point::new(
        corner.x + (pw - scale * w) / 2.0,
        corner.y + (ph - scale * h) / 2.0,
    );
    plot.map_points(|p| Point::new(to.x + (p.x - b[0]) * scale, to.y + (p.y - b[1]) * scale));
    Ok(Placed { page, scale })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strokes::Pen;

    fn plot(pts: &[(f64, f64)]) -> Plot {
        Plot {
            pens: vec![Pen {
                name: "p".into(),
                strokes: vec![pts.iter().map(|&(x, y)| Point::new(x, y)).collect()],
            }],
        }
    }

    #[test]
    fn page_sizes_by_name_and_with_units() {
        assert_eq!(page_size("A3"), Ok((297.0, 420.0)));
        assert_eq!(page_size("letter"), Ok((215.9, 279.4)));
        assert_eq!(page_size("300x200"), Ok((300.0, 200.0)));
        let (w, h) = page_size("8.5x11in").unwrap();
        assert!((w - 215.9).abs() < 1e-9 && (h - 279.4).abs() < 1e-9);
        assert_eq!(page_size("30cmx200mm"), Ok((300.0, 200.0)));
        for bad in ["a9", "x", "10x", "0x10", "-5x10", "10x10furlong", "1e9x1"] {
            assert!(page_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn fit_scales_into_the_margins_and_centres() {
        // 100 × 50 box on an A4 landscape page (297 × 210) with 10 mm margins: limited by
        // width, s = 277/100; height 138.5, centred vertically.
        let mut p = plot(&[(5.0, 5.0), (105.0, 55.0)]);
        let l = Layout {
            page: (210.0, 297.0),
            landscape: true,
            margin: 10.0,
            fit: true,
        };
        let r = layout(&mut p, &l, Point::new(0.0, 0.0)).unwrap();
        assert_eq!(r.page, (297.0, 210.0));
        assert!((r.scale - 2.77).abs() < 1e-12);
        let b = p.bounds().unwrap();
        let want = [10.0, (210.0 - 138.5) / 2.0, 287.0, (210.0 + 138.5) / 2.0];
        for k in 0..4 {
            assert!((b[k] - want[k]).abs() < 1e-9, "{b:?} vs {want:?}");
        }
    }

    #[test]
    fn no_fit_centres_at_size_and_refuses_what_is_larger_than_the_page() {
        let mut p = plot(&[(0.0, 0.0), (100.0, 40.0)]);
        let l = Layout {
            page: (210.0, 297.0),
            landscape: false,
            margin: 10.0,
            fit: false,
        };
        layout(&mut p, &l, Point::new(50.0, 20.0)).unwrap();
        assert_eq!(
            p.bounds().unwrap(),
            [50.0 + 55.0, 20.0 + 128.5, 50.0 + 155.0, 20.0 + 168.5]
        );
        let mut big = plot(&[(0.0, 0.0), (300.0, 10.0)]);
        let e = layout(&mut big, &l, Point::ORIGIN).unwrap_err();
        assert!(
            e.to_string().contains("larger than the 210 × 297 mm page"),
            "{e}"
        );
        let l = Layout {
            margin: 105.0,
            fit: true,
            ..l
        };
        assert!(layout(&mut p, &l, Point::ORIGIN).is_err());
    }
}
