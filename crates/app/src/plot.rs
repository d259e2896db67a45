//! A pen-plotting job: a drawing (SVG, DXF, HPGL, an image to hatch, or text) → an
//! optimised program for a plotter profile, its SVG preview, the optimiser's report and the
//! planned time. `oficina plot` and the workbench both run it.

use crate::{Error, Feedback};
use oficina_geom::Point;
use oficina_motion::estimate_with;
use oficina_motion::{PlanOptions, Profile};
use oficina_plot::{
    prepare, shade, text_strokes, Crop, FillStyle, Filled, Format, Gray, Hatching, Occult,
    Optimise, PenBy, PenLift, PenMachine, Plot, Prepared, Settings, Shading,
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
    /// Image hatching: layers, 1…4 (with `fill`: darkness bands, 1…8).
    pub hatch_layers: usize,
    /// Image hatching: the pens of the layers (bands), lightest first, comma-separated; the
    /// darker layers share the last (default: one pen, `#000000`).
    pub image_pens: Option<String>,
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
    /// Hatch the filled shapes (an image: its darkness bands, filled alike).
    pub fill: bool,
    /// Hatch direction, degrees from +X.
    pub fill_angle: f64,
    /// Distance between hatch lines on paper, mm.
    pub fill_spacing: f64,
    /// A second hatch at right angles.
    pub fill_cross: bool,
    /// Concentric rings instead of parallel lines.
    pub fill_concentric: bool,
    /// What counts as filled: `svg` (a fill colour), `closed` (every closed outline) or
    /// `loops` (every closed subpath on its own).
    pub filled: FilledBy,
    /// Hidden-line removal: filled shapes hide what their pen drew before them.
    pub occult: bool,
    /// … and what every pen drew before them.
    pub occult_across: bool,
    /// Closed strokes start at the vertex nearest the pen.
    pub reloop: bool,
    /// Draw every stroke this many times.
    pub passes: usize,
    /// Crop to `paper` or to a box `X0,Y0,X1,Y1` (work coordinates, mm).
    pub crop: Option<String>,
    /// The profile is a default nobody chose: a drawing larger than its travel is written
    /// at its size, as vpype writes it, with a note (a named machine refuses it).
    pub default_machine: bool,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
/// What counts as a filled shape for `fill` and `occult`.
pub enum FilledBy {
    /// A fill colour in the design.
    Svg,
    /// Every closed outline (as AxiDraw's Hatch Fill takes them), an element's subpaths one
    /// shape with holes.
    Closed,
    /// Every closed subpath a shape of its own (vpype-occult's rule).
    Loops,
}

/// `paper` or `X0,Y0,X1,Y1`.
fn parse_crop(s: &str) -> Result<Crop, Error> {
    if s.trim().eq_ignore_ascii_case("paper") {
        return Ok(Crop::Paper);
    }
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| Error(format!("--crop '{s}': use paper or X0,Y0,X1,Y1 in mm")))?;
    match v.as_slice() {
        [x0, y0, x1, y1] if v.iter().all(|v| v.is_finite()) && x1 > x0 && y1 > y0 => {
            Ok(Crop::Box([*x0, *y0, *x1, *y1]))
        }
        _ => Err(Error(format!(
            "--crop '{s}': use paper or X0,Y0,X1,Y1 in mm with X0 < X1, Y0 < Y1"
        ))),
    }
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
            image_pens: None,
            merge_tol: 0.05,
            simplify_tol: 0.01,
            no_optimise: false,
            min_ramp_steps: 100.0,
            tolerance: 0.02,
            join_tol: oficina_io::JOIN_TOL,
            fill: false,
            fill_angle: 45.0,
            fill_spacing: 1.0,
            fill_cross: false,
            fill_concentric: false,
            filled: FilledBy::Svg,
            occult: false,
            occult_across: false,
            reloop: false,
            passes: 1,
            crop: None,
            default_machine: false,
        }
    }
}

/// The default profile's travel grown to hold the drawing where it will be drawn (its own
/// coordinates × scale, or from `--at`), when it does not fit; Cartesian machines only (a
/// polar arm's reach is its geometry). `None` when it fits.
fn travel_for_drawing(
    plot: &Plot,
    s: &Settings,
    profile: &Profile,
    notes: &mut Vec<String>,
) -> Option<Profile> {
    use oficina_motion::KinematicsKind::{Cartesian, CoreXy};
    if !matches!(profile.kinematics, Cartesian | CoreXy) {
        return None;
    }
    let b = plot.bounds()?;
    let (w, h) = ((b[2] - b[0]) * s.scale, (b[3] - b[1]) * s.scale);
    let lo =
        s.at.map_or(Point::new(b[0] * s.scale, b[1] * s.scale), |a| a);
    let (span, off) = ([[lo.x, lo.x + w], [lo.y, lo.y + h]], profile.work_offset);
    let mut grown = profile.clone();
    for i in 0..2 {
        let t = &mut grown.travel[i];
        t[0] = t[0].min(span[i][0] + off[i]);
        t[1] = t[1].max(span[i][1] + off[i]);
    }
    if grown.travel == profile.travel {
        return None;
    }
    let [tx, ty] = [profile.travel[0], profile.travel[1]];
    notes.push(format!(
        "no --machine named: the drawing (X {:.1} … {:.1}, Y {:.1} … {:.1} mm on the machine) lies beyond the default {}'s travel (X {} … {}, Y {} … {}) and is written where it is; name your plotter with --machine to check that it fits, or place it on a page with --layout",
        span[0][0] + off[0],
        span[0][1] + off[0],
        span[1][0] + off[1],
        span[1][1] + off[1],
        profile.name,
        tx[0],
        tx[1],
        ty[0],
        ty[1]
    ));
    Some(grown)
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

/// Paper mm per drawing unit: the scale `layout` will fit a drawing of `bounds` to, else
/// `p.scale`.
fn paper_scale(
    p: &PlotParams,
    layout: Option<&oficina_plot::Layout>,
    bounds: Option<[f64; 4]>,
) -> f64 {
    let (Some(l), Some(b)) = (layout.filter(|l| l.fit), bounds) else {
        return p.scale;
    };
    let (pw, ph) = l.oriented();
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    let fit = |page: f64, size: f64| {
        if size > 0.0 {
            (page - 2.0 * l.margin) / size
        } else {
            f64::INFINITY
        }
    };
    let f = fit(pw, w).min(fit(ph, h));
    if f.is_finite() && f > 0.0 {
        f
    } else {
        p.scale
    }
}

/// The drawing's strokes, its filled shapes hatched and hiding what lies under them when
/// asked. The hatch spacing is on paper: divided by the scale the layout will give.
fn draw(
    d: &oficina_geom::Drawing,
    by: PenBy,
    p: &PlotParams,
    layout: Option<&oficina_plot::Layout>,
    even_odd: &std::collections::HashSet<String>,
) -> Result<Plot, Error> {
    let outline = Plot::from_drawing(d, by, p.tolerance);
    if !p.fill && !p.occult && !p.occult_across {
        return Ok(outline);
    }
    let k = paper_scale(p, layout, outline.bounds());
    let shading = Shading {
        fill: p.fill.then_some(FillStyle {
            angle: p.fill_angle,
            spacing: p.fill_spacing,
            cross: p.fill_cross,
            concentric: p.fill_concentric,
        }),
        filled: match p.filled {
            FilledBy::Svg => Filled::Svg,
            FilledBy::Closed => Filled::Closed,
            FilledBy::Loops => Filled::Loops,
        },
        occult: if p.occult_across {
            Occult::Across
        } else if p.occult {
            Occult::PerPen
        } else {
            Occult::Off
        },
        units_per_mm: 1.0 / k,
    };
    shade(d, by, p.tolerance, &shading, &|path| {
        even_odd.contains(&path.source.element)
    })
    .map_err(|e| {
        if e.contains("spacing") {
            Error(format!("--fill-spacing {}: {e}", p.fill_spacing))
        } else {
            Error(format!("fill/occult: {e}"))
        }
    })
}

/// The fill and passes settings, refused with the flag they came from.
fn check_shading(p: &PlotParams) -> Result<(), Error> {
    if p.fill && !(p.fill_spacing.is_finite() && p.fill_spacing >= oficina_plot::MIN_FILL_SPACING) {
        return Err(Error(format!(
            "--fill-spacing {}: must be at least {} mm (no pen draws lines closer)",
            p.fill_spacing,
            oficina_plot::MIN_FILL_SPACING
        )));
    }
    if p.fill && !p.fill_angle.is_finite() {
        return Err(Error(format!(
            "--fill-angle {}: must be a number of degrees",
            p.fill_angle
        )));
    }
    if !(1..=oficina_plot::MAX_PASSES).contains(&p.passes) {
        return Err(Error(format!(
            "--passes {}: use 1 to {}",
            p.passes,
            oficina_plot::MAX_PASSES
        )));
    }
    Ok(())
}

/// `--image-pens`: the pen names, lightest layer first, at most one a layer.
fn image_pens(p: &PlotParams) -> Result<Vec<String>, Error> {
    let Some(list) = &p.image_pens else {
        return Ok(vec!["#000000".into()]);
    };
    let pens: Vec<String> = list.split(',').map(|s| s.trim().to_string()).collect();
    if pens.iter().any(String::is_empty) {
        return Err(Error(format!(
            "--image-pens '{list}': name every pen (e.g. #999999,#000000), none empty"
        )));
    }
    if pens.len() > p.hatch_layers {
        return Err(Error(format!(
            "--image-pens '{list}': {} pens for {} layers (--hatch-layers): at most one pen a layer",
            pens.len(),
            p.hatch_layers
        )));
    }
    Ok(pens)
}

/// A picture hatched: layers of lines at 0/90/45/135° (`--pitch`), or with `fill` its
/// darkness bands filled as shapes are (spacing on paper, as for shapes). Layer k goes to
/// the k-th of `--image-pens`, the darker layers to the last.
fn hatch_image(
    path: &Path,
    p: &PlotParams,
    layout: Option<&oficina_plot::Layout>,
) -> Result<Plot, Error> {
    let pens = image_pens(p)?;
    let (w, h, px) = oficina_plot::load_gray(path).map_err(|e| Error::chain(&e))?;
    let img = Gray {
        width: w,
        height: h,
        pixels: &px,
    };
    let layers = if p.fill {
        let finest = p.fill_spacing / p.hatch_layers.max(1) as f64;
        // The spacing is on paper: the scale is the one the layout will give the picture's
        // dark part (the lightest band's regions).
        let bands = oficina_plot::band_regions(&img, p.pixel, p.hatch_layers, finest / p.scale)
            .map_err(|e| Error(format!("--hatch-layers/--pixel: {e}")))?;
        let bounds = oficina_geom::bounds(
            bands
                .first()
                .into_iter()
                .flatten()
                .flat_map(|r| r.outer.iter().copied()),
        )
        .map(|r| [r.x0, r.y0, r.x1, r.y1]);
        let k = paper_scale(p, layout, bounds);
        let style = FillStyle {
            angle: p.fill_angle,
            spacing: p.fill_spacing / k,
            cross: p.fill_cross,
            concentric: p.fill_concentric,
        };
        oficina_plot::fill_bands(&bands, &style, p.tolerance / k)
            .map_err(|e| Error(format!("--fill-spacing {}: {e}", p.fill_spacing)))?
    } else {
        oficina_plot::hatch(
            &img,
            &Hatching {
                pixel: p.pixel,
                pitch: p.pitch,
                layers: p.hatch_layers,
                angle: 0.0,
            },
        )
        .map_err(|e| Error::chain(&e))?
    };
    let mut plot = Plot::default();
    for (i, strokes) in layers.into_iter().enumerate() {
        let pen = &pens[i.min(pens.len() - 1)];
        plot.pen_mut(pen).strokes.extend(strokes);
    }
    Ok(plot)
}

/// Reads the design into pens of strokes; notes what was left out.
fn load(
    path: &Path,
    p: &PlotParams,
    layout: Option<&oficina_plot::Layout>,
    notes: &mut Vec<String>,
) -> Result<Plot, Error> {
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
            let mut plot = draw(
                &h.imported.drawing,
                PenBy::Layer,
                p,
                layout,
                &h.imported.even_odd,
            )?;
            for l in &h.labels {
                let strokes = text_strokes(&l.text, l.at, l.height, l.angle);
                plot.pen_mut(&l.layer).strokes.extend(strokes);
            }
            Ok(plot)
        }
        "png" | "jpg" | "jpeg" => hatch_image(path, p, layout),
        _ => {
            let imported =
                oficina_io::load_drawing_with(path, p.join_tol).map_err(|e| Error::chain(&e))?;
            notes.extend(imported.summary());
            if !imported.unsupported.is_empty() {
                notes.push(imported.unsupported.to_string());
            }
            draw(&imported.drawing, by, p, layout, &imported.even_odd)
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
    let mut notes = Vec::new();
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
    check_shading(p)?;
    fb.stage("reading the design")?;
    let mut plot = match input {
        Some(path) => load(path, p, layout.as_ref(), &mut notes)?,
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
        crop: p.crop.as_deref().map(parse_crop).transpose()?,
        reloop: p.reloop,
        passes: p.passes,
    };
    fb.stage("placing, optimising, writing the program")?;
    let stretched = if p.default_machine && settings.layout.is_none() {
        travel_for_drawing(&plot, &settings, profile, &mut notes)
    } else {
        None
    };
    let profile = stretched.as_ref().unwrap_or(profile);
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
