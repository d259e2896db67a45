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
