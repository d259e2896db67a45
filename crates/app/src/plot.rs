//! A pen-plotting job: a drawing (SVG, DXF, HPGL, an image to hatch, or text) → an
//! optimised program for a plotter profile, its SVG preview, the optimiser's report and the
//! planned time. `oficina plot` and the workbench both run it.

use crate::{Error, Feedback};
use oficina_geom::Point;
use oficina_motion::estimate_with;
use oficina_motion::{PlanOptions, Profile};
use oficina_plot::{
    prepare, text_strokes, Format, Gray, Hatching, Optimise, PenBy, PenLift, PenMachine, Plot,
    Prepared, Settings,
};
use serde::Deserialize;
use std::path::Path;

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
/// What a plot is written as.
pub enum PlotFormat {
    /// Cartesian G-code (grbl family).
    Gcode,
    /// G-code whose X/Y are the two joints (polar and hanging plotters on a plain controller).
    Joint,
    /// HPGL (vintage plotters).
    Hpgl,
    /// Cartesian G-code for Marlin 2.x plotters: `M280 P0 S…` servo pen lift, `G28`, one
    /// command per line.
    Marlin,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
/// What makes a pen of a drawing.
pub enum PensBy {
    /// Its stroke colour.
    Color,
    /// Its layer.
    Layer,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
/// How the pen is lifted.
pub enum Lift {
    /// A Z axis.
    Z,
    /// A servo: M3 S<servo_down> / M5 (grbl), M280 P0 S<servo_down> / S<servo_up> (Marlin).
    Servo,
    /// The pen-down and pen-up command lines as given.
    Command,
}

/// The form of a plot; lengths in mm, feeds in mm/min. The defaults are the CLI's.
#[derive(Clone, Debug, Deserialize)]
#[serde(default)]
pub struct PlotParams {
    /// The output's form.
    pub format: PlotFormat,
    /// Text to draw in a single-stroke Hershey font (besides or instead of the input).
    pub text: Option<String>,
    /// Capital height of `text`.
    pub text_height: f64,
    /// What makes a pen.
    pub pens: PensBy,
    /// How the pen is lifted.
    pub pen: Lift,
    /// Servo value for pen down (S word).
    pub servo_down: f64,
    /// Servo angle for pen up (Marlin's `M280 P0 S…`), degrees.
    pub servo_up: f64,
    /// Pen-down command (with `Lift::Command`).
    pub pen_down_cmd: Option<String>,
    /// Pen-up command (with `Lift::Command`).
    pub pen_up_cmd: Option<String>,
    /// Seconds to wait after each pen move.
    pub pen_dwell: f64,
    /// Drawing feed (default: the profile's default feed).
    pub feed: Option<f64>,
    /// Scale factor of the drawing.
    pub scale: f64,
    /// Lower-left corner of the drawing, work coordinates.
    pub at: Option<[f64; 2]>,
    /// Paper W, H; the drawing must fit on it.
    pub paper: Option<[f64; 2]>,
    /// Lay the drawing out on this page (a4, a3, letter, … or WxH with units), as vpype's
    /// `layout`: centred, scaled to fit inside `margin` unless `no_fit`.
    pub layout: Option<String>,
    /// The page of `layout` in landscape (otherwise portrait; a page that fits the machine
    /// only when turned is turned, with a note).
    pub landscape: bool,
    /// Margin of `layout` when fitting, mm.
    pub margin: f64,
    /// `layout` keeps the drawing's size (only centres it).
    pub no_fit: bool,
    /// Image hatching: pixel size on paper.
    pub pixel: f64,
    /// Image hatching: distance between hatch lines.
    pub pitch: f64,
    /// Image hatching: layers, 1…4.
    pub hatch_layers: usize,
    /// Largest gap between stroke ends that are merged.
    pub merge_tol: f64,
    /// Largest deviation when simplifying strokes.
    pub simplify_tol: f64,
    /// Draw strokes as given: no merging, ordering, simplifying or de-duplicating.
    pub no_optimise: bool,
    /// Refuse a profile whose joint acceleration ramps are shorter than this many steps.
    pub min_ramp_steps: f64,
    /// Chord tolerance for curves.
    pub tolerance: f64,
    /// Ends of a drawing's paths that meet within this distance are joined (closed as
    /// drawn, open pieces chained), mm.
    pub join_tol: f64,
}

impl Default for PlotParams {
    fn default() -> Self {
        PlotParams {
            format: PlotFormat::Gcode,
            text: None,
            text_height: 10.0,
            pens: PensBy::Color,
            pen: Lift::Z,
            servo_down: 30.0,
            servo_up: 90.0,
            pen_down_cmd: None,
            pen_up_cmd: None,
            pen_dwell: 0.0,
            feed: None,
            scale: 1.0,
            at: None,
            paper: None,
            layout: None,
            landscape: false,
            margin: 10.0,
            no_fit: false,
            pixel: 0.5,
            pitch: 1.0,
            hatch_layers: 3,
            merge_tol: 0.05,
            simplify_tol: 0.01,
            no_optimise: false,
            min_ramp_steps: 100.0,
            tolerance: 0.02,
            join_tol: oficina_io::JOIN_TOL,
        }
    }
}

/// A plot's output.
pub struct PlotResult {
    /// What the input held that was left out.
    pub notes: Vec<String>,
    /// The program, its preview and the optimisation's figures.
    pub prepared: Prepared,
    /// Planned time on the profile, s.
    pub seconds: f64,
}

/// The pen machine `p` describes on `profile`.
pub fn pen_machine(p: &PlotParams, profile: &Profile) -> Result<PenMachine, Error> {
    let mut m = PenMachine::for_profile(profile);
    let need = |v: &Option<String>, flag: &str| {
        v.clone()
            .ok_or_else(|| Error(format!("--pen command needs --{flag}")))
    };
    m.lift = match p.pen {
        Lift::Z => m.lift,
        Lift::Servo => PenLift::Servo { down: p.servo_down },
        Lift::Command => PenLift::Command {
            down: need(&p.pen_down_cmd, "pen-down-cmd")?,
            up: need(&p.pen_up_cmd, "pen-up-cmd")?,
        },
    };
    if let Some(f) = p.feed {
        if !(f.is_finite() && f > 0.0) {
            return Err(Error(format!("--feed {f}: must be > 0 mm/min")));
        }
        m.draw_feed = f;
    }
    if !(p.servo_up.is_finite() && p.servo_down.is_finite()) {
        return Err(Error("--servo-up and --servo-down must be numbers".into()));
    }
    // M280 takes a hobby servo's angle, 0° to 180°.
    let angle = |a: f64| (0.0..=180.0).contains(&a);
    if p.format == PlotFormat::Marlin && !(angle(p.servo_up) && angle(p.servo_down)) {
        return Err(Error(format!(
            "--servo-up {} / --servo-down {}: Marlin's M280 takes servo angles from 0 to 180 degrees",
            p.servo_up, p.servo_down
        )));
    }
    if !(p.pen_dwell.is_finite() && p.pen_dwell >= 0.0) {
        return Err(Error(format!(
            "--pen-dwell {}: use 0 s or more",
            p.pen_dwell
        )));
    }
    m.servo_up = p.servo_up;
    m.lift_dwell = p.pen_dwell;
    Ok(m)
}

/// Reads the design into pens of strokes; notes what was left out.
fn load(path: &Path, p: &PlotParams, notes: &mut Vec<String>) -> Result<Plot, Error> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let by = match p.pens {
        PensBy::Color => PenBy::Color,
        PensBy::Layer => PenBy::Layer,
    };
    // HP-GL by its extension or its content (.plt, .hp, .000, PCL with HP-GL/2 inside, …).
    let hpgl = oficina_io::is_hpgl_file(path);
    match ext.as_str() {
        _ if hpgl => {
            let mut h = oficina_io::load_hpgl(path).map_err(|e| Error::chain(&e))?;
            h.imported.close(p.join_tol);
            notes.extend(h.imported.summary());
            if !h.imported.unsupported.is_empty() {
                notes.push(h.imported.unsupported.to_string());
            }
            // HPGL pens are layers whatever `pens` says.
            let mut plot = Plot::from_drawing(&h.imported.drawing, PenBy::Layer, p.tolerance);
            for l in &h.labels {
                let strokes = text_strokes(&l.text, l.at, l.height, l.angle);
                plot.pen_mut(&l.layer).strokes.extend(strokes);
            }
            Ok(plot)
        }
        "png" | "jpg" | "jpeg" => {
            let (w, h, px) = oficina_plot::load_gray(path).map_err(|e| Error::chain(&e))?;
            let strokes = oficina_plot::hatch(
                &Gray {
                    width: w,
                    height: h,
                    pixels: &px,
                },
                &Hatching {
                    pixel: p.pixel,
                    pitch: p.pitch,
                    layers: p.hatch_layers,
                },
            )
            .map_err(|e| Error::chain(&e))?;
            let mut plot = Plot::default();
            plot.pen_mut("#000000").strokes = strokes;
            Ok(plot)
        }
        _ => {
            let imported =
                oficina_io::load_drawing_with(path, p.join_tol).map_err(|e| Error::chain(&e))?;
            notes.extend(imported.summary());
            if !imported.unsupported.is_empty() {
                notes.push(imported.unsupported.to_string());
            }
            Ok(Plot::from_drawing(&imported.drawing, by, p.tolerance))
        }
    }
}

/// Plots `input` (and/or `p.text`) on `profile`.
pub fn plot(
    input: Option<&Path>,
    p: &PlotParams,
    profile: &Profile,
    fb: Feedback,
) -> Result<PlotResult, Error> {
    let m = pen_machine(p, profile)?;
    if !(p.scale.is_finite() && p.scale > 0.0 && p.scale <= 1e4) {
        return Err(Error(format!(
            "--scale {}: use more than 0, at most 10000",
            p.scale
        )));
    }
    if !(p.join_tol.is_finite() && (0.0..=oficina_io::MAX_JOIN_TOL).contains(&p.join_tol)) {
        return Err(Error(format!(
            "--join-tol {}: use 0 to {} mm",
            p.join_tol,
            oficina_io::MAX_JOIN_TOL
        )));
    }
    fb.stage("reading the design")?;
    let mut notes = Vec::new();
    let mut plot = match input {
        Some(path) => load(path, p, &mut notes)?,
        None => Plot::default(),
    };
    if let Some(t) = &p.text {
        let below = plot.bounds().map_or(0.0, |b| b[1] - 2.0 * p.text_height);
        let strokes = text_strokes(t, Point::new(0.0, below), p.text_height, 0.0);
        plot.pen_mut("#000000").strokes.extend(strokes);
    }
    if input.is_none() && p.text.is_none() {
        return Err(Error(
            "nothing to plot: give a design file or --text".into(),
        ));
    }
    let layout = match &p.layout {
        None => None,
        Some(name) => {
            if p.paper.is_some() {
                return Err(Error(
                    "--layout and --paper: give the page once, not both".into(),
                ));
            }
            let page = oficina_plot::page_size(name).map_err(|e| Error(format!("--layout {e}")))?;
            if !(p.margin.is_finite() && p.margin >= 0.0 && 2.0 * p.margin < page.0.min(page.1)) {
                return Err(Error(format!(
                    "--margin {} mm: use 0 or more, less than half the page's shorter side ({} mm)",
                    p.margin,
                    page.0.min(page.1)
                )));
            }
            let mut l = oficina_plot::Layout {
                page,
                landscape: p.landscape,
                margin: p.margin,
                fit: !p.no_fit,
            };
            // A page that fits the machine only when turned is turned (an A3 sheet lies
            // landscape on an A3 plotter).
            let travel = |(w, h): (f64, f64)| {
                w <= profile.travel[0][1] - profile.travel[0][0] + 1e-9
                    && h <= profile.travel[1][1] - profile.travel[1][0] + 1e-9
            };
            let turned = oficina_plot::Layout {
                landscape: !l.landscape,
                ..l.clone()
            };
            if p.at.is_none() && !travel(l.oriented()) && travel(turned.oriented()) {
                let (w, h) = turned.oriented();
                notes.push(format!(
                    "the page is laid {} ({w} × {h} mm): that way it fits the machine's travel",
                    if turned.landscape {
                        "landscape"
                    } else {
                        "portrait"
                    }
                ));
                l = turned;
            }
            Some(l)
        }
    };
    let settings = Settings {
        scale: p.scale,
        at: p.at.map(|[x, y]| Point::new(x, y)),
        paper: p.paper.map(|[w, h]| (w, h)),
        layout,
        optimise: (!p.no_optimise).then(|| Optimise {
            merge_tol: p.merge_tol,
            simplify_tol: p.simplify_tol,
            ..Optimise::default()
        }),
        min_ramp_steps: p.min_ramp_steps,
        format: match p.format {
            PlotFormat::Gcode => Format::Gcode,
            PlotFormat::Joint => Format::Joint,
            PlotFormat::Hpgl => Format::Hpgl,
            PlotFormat::Marlin => Format::Marlin,
        },
        joint_piece: 1.0,
    };
    fb.stage("placing, optimising, writing the program")?;
    let prepared = prepare(plot, profile, &m, &settings).map_err(|e| match e {
        // Nothing drawn: say what the file held instead (fills, labels of no pen, …).
        oficina_plot::PlotError::Empty if !notes.is_empty() => Error(format!(
            "{e}; the design held only what was skipped: {}",
            notes.join("; ")
        )),
        e => Error::chain(&e),
    })?;
    fb.stage("planning the time")?;
    let e = estimate_with(
        oficina_plot::to_canon(&prepared.plot, &m, profile).into_iter(),
        profile,
        PlanOptions::default(),
        false,
    )
    .map_err(Error::from_display)?;
    Ok(PlotResult {
        notes,
        prepared,
        seconds: e.seconds,
    })
}
