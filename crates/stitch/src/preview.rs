//! An SVG picture of a plan: each thread in its colour, jumps dashed grey, the hoop's field.

use crate::hoop::{Hoop, HoopShape, CLEARANCE};
use crate::plan::{Kind, StitchPlan};
use std::fmt::Write;

/// An SVG picture of the plan's stitches, the hoop's ring drawn when given.
pub fn preview_svg(plan: &StitchPlan, hoop: Option<&Hoop>) -> String {
    let mut b = plan.bounds().unwrap_or([0.0, 0.0, 1.0, 1.0]);
    if let Some(h) = hoop {
        let (rx, ry) = match h.shape {
            HoopShape::Round { diameter } => (diameter / 2.0, diameter / 2.0),
            HoopShape::Oval { width, height } => (width / 2.0, height / 2.0),
        };
        b = [b[0].min(-rx), b[1].min(-ry), b[2].max(rx), b[3].max(ry)];
    }
    let m = 2.0;
    let (w, h) = (b[2] - b[0] + 2.0 * m, b[3] - b[1] + 2.0 * m);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.1}mm\" height=\"{h:.1}mm\" viewBox=\"{:.2} {:.2} {w:.2} {h:.2}\">",
        b[0] - m,
        -b[3] - m
    );
    if let Some(hp) = hoop {
        let (rx, ry) = match hp.shape {
            HoopShape::Round { diameter } => (diameter / 2.0, diameter / 2.0),
            HoopShape::Oval { width, height } => (width / 2.0, height / 2.0),
        };
        let _ = writeln!(s, "<ellipse cx=\"0\" cy=\"0\" rx=\"{rx}\" ry=\"{ry}\" fill=\"none\" stroke=\"#999\" stroke-width=\"1\"/>");
        let _ = writeln!(
            s,
            "<ellipse cx=\"0\" cy=\"0\" rx=\"{}\" ry=\"{}\" fill=\"none\" stroke=\"#ccc\" stroke-width=\"0.3\" stroke-dasharray=\"2 2\"/>",
            rx - CLEARANCE,
            ry - CLEARANCE
        );
    }
    let (mut px, mut py) = (0.0f64, 0.0f64);
    for block in &plan.blocks {
        let mut d = String::new();
        let mut jumps = String::new();
        let mut pen = false;
        for st in &block.stitches {
            match st.kind {
                Kind::Stitch => {
                    if !pen {
                        let _ = write!(d, "M{:.2} {:.2}", px, -py);
                        pen = true;
                    }
                    let _ = write!(d, "L{:.2} {:.2}", st.x, -st.y);
                }
                Kind::Jump => {
                    let _ = write!(jumps, "M{:.2} {:.2}L{:.2} {:.2}", px, -py, st.x, -st.y);
                    pen = false;
                }
                Kind::Trim | Kind::Stop => pen = false,
            }
            (px, py) = (st.x, st.y);
        }
        let _ = writeln!(
            s,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"0.25\" stroke-linejoin=\"round\"/>",
            block.thread.hex()
        );
        if !jumps.is_empty() {
            let _ = writeln!(s, "<path d=\"{jumps}\" fill=\"none\" stroke=\"#888\" stroke-width=\"0.15\" stroke-dasharray=\"0.6 0.6\"/>");
        }
    }
    s += "</svg>\n";
    s
}

/// How a plan is rendered as thread ([`render`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Pixels per inch of the design (25.4 mm).
    pub dpi: f64,
    /// The thread's width, mm (a 40-weight thread lies about 0.4 mm wide).
    pub thread_width: f64,
    /// Fabric around the design, mm.
    pub margin: f64,
    /// The fabric's colour.
    pub background: [u8; 3],
    /// The longest side the image may have, pixels: a larger design is drawn at a lower dpi
    /// (the [`Render`] says which).
    pub max_side: u32,
}

impl Default for RenderOptions {
    fn default() -> RenderOptions {
        RenderOptions {
            dpi: 254.0,
            thread_width: 0.4,
            margin: 1.0,
            background: [238, 235, 228],
            max_side: 6000,
        }
    }
}

/// Why a plan could not be rendered.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RenderError {
    /// Nothing is sewn.
    #[error("the design has no stitches to draw")]
    Empty,
    /// A coordinate or option is not a finite, positive figure.
    #[error("render: {0}")]
    Invalid(String),
    /// So large that even at the lowest resolution drawn the thread would vanish.
    #[error("the design is {0:.0} x {1:.0} mm: too large to render (at most {2:.0} mm a side)")]
    TooLarge(f64, f64, f64),
}

/// An RGB image of a plan sewn on fabric.
#[derive(Clone, Debug, PartialEq)]
pub struct Render {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Row-major RGB, top row first.
    pub rgb: Vec<u8>,
    /// The resolution drawn at, pixels per inch (lower than asked when the design is large).
    pub dpi: f64,
    /// The design point (mm, y up) at the image's top-left corner.
    pub origin: [f64; 2],
}

impl Render {
    /// The pixel (column, row) where the design point (`x`, `y`) mm lies.
    pub fn pixel_of(&self, x: f64, y: f64) -> (i64, i64) {
        let s = self.dpi / 25.4;
        (
            ((x - self.origin[0]) * s).floor() as i64,
            ((self.origin[1] - y) * s).floor() as i64,
        )
    }

    /// The colour at pixel (`col`, `row`).
    pub fn at(&self, col: u32, row: u32) -> [u8; 3] {
        let i = (row as usize * self.width as usize + col as usize) * 3;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// The image as a PNG file.
    pub fn png(&self) -> Vec<u8> {
        use image::ImageEncoder;
        let mut out = Vec::new();
        // Encoding a well-formed RGB buffer into memory does not fail.
        let _ = image::codecs::png::PngEncoder::new(&mut out).write_image(
            &self.rgb,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
        );
        out
    }
}

/// The smallest resolution a large design is drawn at, pixels per mm.
const MIN_PX_PER_MM: f64 = 0.5;

/// The plan drawn as sewn thread: each stitch a round-ended band `thread_width` wide in its
/// thread's colour, lit like a twisted cylinder (a highlight along its centre, darker edges,
/// a little darker still where the needle pierced the fabric at its ends), later stitches over
/// earlier ones; jumps, trims and stops are not drawn. The image spans the sewn stitches'
/// extents plus the margin at `dpi`; a design whose image would be more than `max_side`
/// pixels a side is drawn at the dpi that fits.
pub fn render(plan: &StitchPlan, o: &RenderOptions) -> Result<Render, RenderError> {
    if !(o.dpi.is_finite() && o.dpi > 0.0) {
        return Err(RenderError::Invalid(format!(
            "dpi {} must be above 0",
            o.dpi
        )));
    }
    if !(o.thread_width.is_finite() && o.thread_width > 0.0 && o.thread_width < 10.0) {
        return Err(RenderError::Invalid(format!(
            "thread width {} mm: use more than 0 and less than 10",
            o.thread_width
        )));
    }
    if !(o.margin.is_finite() && o.margin >= 0.0) || o.max_side < 16 {
        return Err(RenderError::Invalid(
            "margin must be 0 or more and max side at least 16 px".into(),
        ));
    }
    // The segments drawn: (from, to, block).
    let mut segs: Vec<([f64; 2], [f64; 2], usize)> = Vec::new();
    let mut prev: Option<[f64; 2]> = None;
    for (b, s) in plan.entries() {
        if !(s.x.is_finite() && s.y.is_finite()) {
            return Err(RenderError::Invalid(format!(
                "a point ({}, {}) is not finite",
                s.x, s.y
            )));
        }
        let p = [s.x, s.y];
        if s.kind == Kind::Stitch {
            segs.push((prev.unwrap_or(p), p, b));
        }
        prev = Some(p);
    }
    if segs.is_empty() {
        return Err(RenderError::Empty);
    }
    let mut bb = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for (a, c, _) in &segs {
        for p in [a, c] {
            bb = [
                bb[0].min(p[0]),
                bb[1].min(p[1]),
                bb[2].max(p[0]),
                bb[3].max(p[1]),
            ];
        }
    }
    let m = o.margin + o.thread_width / 2.0;
    let (wmm, hmm) = (bb[2] - bb[0] + 2.0 * m, bb[3] - bb[1] + 2.0 * m);
    let mut s = o.dpi / 25.4;
    let side = wmm.max(hmm);
    if side * s > o.max_side as f64 {
        s = (o.max_side as f64 - 1.0) / side;
        if s < MIN_PX_PER_MM {
            let most = (o.max_side as f64 - 1.0) / MIN_PX_PER_MM;
            return Err(RenderError::TooLarge(wmm, hmm, most));
        }
    }
    let (w, h) = (
        ((wmm * s).ceil() as u32).max(1),
        ((hmm * s).ceil() as u32).max(1),
    );
    let origin = [bb[0] - m, bb[3] + m];
    let mut rgb = Vec::with_capacity(w as usize * h as usize * 3);
    for _ in 0..w as usize * h as usize {
        rgb.extend_from_slice(&o.background);
    }
    // A thread under 1 px is drawn 1 px wide (fainter detail, but the colours stay visible).
    let r = (o.thread_width * s / 2.0).max(0.5);
    for (a, c, b) in segs {
        let col = plan.blocks[b].thread.rgb;
        let pa = [(a[0] - origin[0]) * s, (origin[1] - a[1]) * s];
        let pc = [(c[0] - origin[0]) * s, (origin[1] - c[1]) * s];
        draw_thread(&mut rgb, w, h, pa, pc, r, col);
    }
    Ok(Render {
        width: w,
        height: h,
        rgb,
        dpi: s * 25.4,
        origin,
    })
}

/// The plan rendered ([`render`]) as a PNG file.
pub fn render_png(plan: &StitchPlan, o: &RenderOptions) -> Result<Vec<u8>, RenderError> {
    render(plan, o).map(|r| r.png())
}

/// One stitch from `a` to `c` (pixels, y down) as a lit thread of radius `r` px.
fn draw_thread(rgb: &mut [u8], w: u32, h: u32, a: [f64; 2], c: [f64; 2], r: f64, col: [u8; 3]) {
    let (dx, dy) = (c[0] - a[0], c[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let len = len2.sqrt();
    let reach = r + 1.0;
    let x0 = (a[0].min(c[0]) - reach).floor().max(0.0) as u32;
    let y0 = (a[1].min(c[1]) - reach).floor().max(0.0) as u32;
    let x1 = ((a[0].max(c[0]) + reach).ceil().max(0.0) as u32).min(w);
    let y1 = ((a[1].max(c[1]) + reach).ceil().max(0.0) as u32).min(h);
    let col = col.map(f64::from);
    for y in y0..y1 {
        let py = y as f64 + 0.5;
        for x in x0..x1 {
            let px = x as f64 + 0.5;
            // Distance to the segment and the position along it.
            let t = if len2 > 0.0 {
                (((px - a[0]) * dx + (py - a[1]) * dy) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (qx, qy) = (a[0] + t * dx - px, a[1] + t * dy - py);
            let d = (qx * qx + qy * qy).sqrt();
            let cover = (r + 0.5 - d).clamp(0.0, 1.0);
            if cover <= 0.0 {
                continue;
            }
            // The thread's surface: a cylinder lit from above the viewer.
            let u = (d / r).min(1.0);
            let n = (1.0 - u * u).sqrt();
            let mut shade = 0.45 + 0.6 * n;
            // Where the needle pierced, the thread dips into the fabric.
            let along = (t * len).min((1.0 - t) * len);
            if along < r {
                shade *= 0.85 + 0.15 * (along / r);
            }
            let spec = 0.35 * n.powi(6);
            let i = (y as usize * w as usize + x as usize) * 3;
            for k in 0..3 {
                let lit = (col[k] * shade).min(255.0);
                let v = lit + (255.0 - lit) * spec;
                let old = rgb[i + k] as f64;
                rgb[i + k] = (old + (v - old) * cover).round().clamp(0.0, 255.0) as u8;
            }
        }
    }
}
