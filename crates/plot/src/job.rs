//! The plot job: place the drawing, check it, optimise it and write the program and preview.

use oficina_geom::Point;
use oficina_motion::Profile;
use oficina_motion::{for_profile, Kinematics};

use crate::layout::{layout, Layout, Placed};
use crate::machine::{
    check_paper, check_ramps, check_reach, snap_to_travel, PenMachine, PlotError, Ramp,
};
use crate::optimise::{optimise, Optimise, Report};
use crate::passes::{multipass, reloop, reorder};
use crate::strokes::Plot;

/// Crops `plot` to the box or the sheet; an empty result is an error that says why.
fn crop_to(plot: &mut Plot, c: Option<Crop>, sheet: Option<[f64; 4]>) -> Result<(), PlotError> {
    let b = match c {
        None => return Ok(()),
        Some(Crop::Box(b)) => b,
        Some(Crop::Paper) => sheet.ok_or_else(|| {
            PlotError::Settings("--crop paper needs a sheet: give --paper or --layout".into())
        })?,
    };
    crate::crop::crop(plot, b).map_err(PlotError::Settings)?;
    if plot.bounds().is_none() {
        return Err(PlotError::Settings(format!(
            "nothing of the drawing lies inside the crop box {b:?}"
        )));
    }
    Ok(())
}

/// Which program to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// G-code in Cartesian work coordinates for grbl-family firmware (or our virtual machine).
    Gcode,
    /// G-code whose X and Y are the two joints, timed in inverse time (polar, hanging).
    Joint,
    /// HPGL for vintage plotters.
    Hpgl,
    /// G-code for Marlin 2.x plotters (servo pen lift, `M280`).
    Marlin,
}

/// Everything a plot job is made with besides the drawing and the machine.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Uniform scale applied first.
    pub scale: f64,
    /// Where the lower-left corner of the drawing goes (work coordinates, mm); `None` keeps
    /// the drawing where it is.
    pub at: Option<Point>,
    /// The sheet (width, height) in mm, its lower-left corner where the drawing's is put.
    pub paper: Option<(f64, f64)>,
    /// Lay the drawing out on a page (centred, fitted or not), the page's lower-left corner at
    /// `at` or else at the lower-left corner of the machine's travel. Replaces `paper`.
    pub layout: Option<Layout>,
    /// Stroke optimisation; `None` keeps the strokes as drawn.
    pub optimise: Option<Optimise>,
    /// Joint ramps shorter than this many steps are refused (the seed arm's oscillation).
    pub min_ramp_steps: f64,
    /// The program's language.
    pub format: Format,
    /// Sub-segment length for joint-space programs, mm.
    pub joint_piece: f64,
    /// Crop the placed strokes to the paper or a box; `None` keeps them all.
    pub crop: Option<Crop>,
    /// After ordering, start each closed stroke at its vertex nearest the pen.
    pub reloop: bool,
    /// Draw every stroke this many times (1: once).
    pub passes: usize,
}

/// What the strokes are cropped to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Crop {
    /// The sheet of `paper` or of the `layout`.
    Paper,
    /// This box in work coordinates: min x, min y, max x, max y, mm.
    Box([f64; 4]),
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            scale: 1.0,
            at: None,
            paper: None,
            layout: None,
            optimise: Some(Optimise::default()),
            min_ramp_steps: 100.0,
            format: Format::Gcode,
            joint_piece: 1.0,
            crop: None,
            reloop: false,
            passes: 1,
        }
    }
}

/// A plot ready to send: the program, its checks and its preview.
#[derive(Clone, Debug, PartialEq)]
pub struct Prepared {
    /// The placed, optimised strokes.
    pub plot: Plot,
    /// The program text.
    pub program: String,
    /// What the optimisation changed, if it ran.
    pub report: Option<Report>,
    /// Each joint's acceleration ramp.
    pub ramps: Vec<Ramp>,
    /// SVG preview of the strokes.
    pub preview: String,
    /// Bounding box of the placed drawing (min x, min y, max x, max y), mm.
    pub bounds: [f64; 4],
    /// The page and scale of the layout, if one was asked for.
    pub placed: Option<Placed>,
}

/// Scales and places `plot` (or lays it out on a page), checks paper, ramps and reach,
/// optimises, and writes the program for `profile`.
pub fn prepare(
    mut plot: Plot,
    profile: &Profile,
    m: &PenMachine,
    s: &Settings,
) -> Result<Prepared, PlotError> {
    let b = plot.bounds().ok_or(PlotError::Empty)?;
    let scale = s.scale;
    let mut placed = None;
    // The sheet in work coordinates, for cropping to it.
    let mut sheet: Option<[f64; 4]> = None;
    if let Some(l) = &s.layout {
        plot.map_points(|p| Point::new(p.x * scale, p.y * scale));
        let corner = s.at.unwrap_or(Point::new(
            profile.travel[0][0] - profile.work_offset[0],
            profile.travel[1][0] - profile.work_offset[1],
        ));
        let pl = layout(&mut plot, l, corner)?;
        sheet = Some([
            corner.x,
            corner.y,
            corner.x + pl.page.0,
            corner.y + pl.page.1,
        ]);
        placed = Some(pl);
        crop_to(&mut plot, s.crop, sheet)?;
    } else {
        let origin = s.at.unwrap_or(Point::new(b[0] * scale, b[1] * scale));
        let shift = origin - Point::new(b[0] * scale, b[1] * scale);
        plot.map_points(|p| Point::new(p.x * scale, p.y * scale) + shift);
        if let Some((w, h)) = s.paper {
            sheet = Some([origin.x, origin.y, origin.x + w, origin.y + h]);
        }
        crop_to(&mut plot, s.crop, sheet)?;
        if let Some((w, h)) = s.paper {
            let mut on_paper = plot.clone();
            on_paper.map_points(|p| p - origin.to_vec2());
            check_paper(&on_paper, w, h)?;
        }
    }
    snap_to_travel(&mut plot, profile);
    let ramps = check_ramps(profile, s.min_ramp_steps)?;
    let mut report = s.optimise.as_ref().map(|o| optimise(&mut plot, o, m.home));
    multipass(&mut plot, s.passes).map_err(PlotError::Settings)?;
    if s.passes.is_multiple_of(2) {
        // Open strokes now end where they begin: order them for that.
        if let Some(o) = s.optimise.as_ref().filter(|o| o.reorder) {
            reorder(&mut plot, o, m.home);
        }
    }
    // After ordering: each closed stroke (all of them, after even passes) begins nearest
    // the pen.
    if s.reloop {
        reloop(&mut plot, m.home);
    }
    if let Some(r) = report.as_mut() {
        // What is drawn: with the passes and the reloop's seams.
        r.after = plot.lengths();
    }
    // Straight lines stay straight in joint space on linear machines: their ends suffice.
    let step = if for_profile(profile).is_linear() {
        f64::INFINITY
    } else {
        2.0
    };
    check_reach(&plot, profile, step)?;
    let program = match s.format {
        Format::Gcode => crate::emit::gcode(&plot, m, profile),
        Format::Joint => crate::emit::joint_gcode(&plot, m, profile, s.joint_piece)?,
        Format::Hpgl => crate::emit::hpgl(&plot),
        Format::Marlin => crate::emit::marlin(&plot, m, profile),
    };
    let preview = crate::preview::svg(&plot, m.home);
    let bounds = plot.bounds().ok_or(PlotError::Empty)?;
    Ok(Prepared {
        plot,
        program,
        report,
        ramps,
        preview,
        bounds,
        placed,
    })
}
