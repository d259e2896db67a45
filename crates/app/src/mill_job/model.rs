//! The job file as written: stock, tool library, extra shapes and operations (TOML).
//! Every table refuses keys it does not know, so a typo is an error naming its line.

use crate::mill::{EntryKind, PocketStrategy};
use crate::Error;
use serde::Deserialize;
use toml::Spanned;

/// A milling job: one drawing, one stock, operations in order.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Job {
    /// The drawing (SVG, DXF, …), relative to the job file.
    pub drawing: String,
    /// A tool library (TOML `[[tool]]` tables), relative to the job file.
    pub library: Option<String>,
    /// Material name: the library's chip load for it sets the feeds.
    pub material: Option<String>,
    /// Join tolerance of the drawing's path ends, mm.
    pub join_tol: Option<f64>,
    /// Retraction plane above the stock top, mm.
    pub clear_z: Option<f64>,
    /// Safe Z for tool changes and the end, mm.
    pub safe_z: Option<f64>,
    /// Grid of the stock simulation, mm.
    pub check_pixel: Option<f64>,
    /// How operations are ordered.
    #[serde(default)]
    pub order: Order,
    /// The stock.
    pub stock: Stock,
    /// Shapes the job adds to the drawing.
    #[serde(default)]
    pub shape: Vec<Spanned<JobShape>>,
    /// The operations, in the order written.
    #[serde(default)]
    pub op: Vec<Spanned<JobOp>>,
}

/// Operation order.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Order {
    /// Grouped by tool to save changes, never across a cut-out.
    #[default]
    ByTool,
    /// As written.
    AsWritten,
}

/// The stock: its top is Z 0, the drawing's coordinates are the program's.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Stock {
    /// Thickness, mm: a profile-out this deep cuts the part out.
    pub thickness: f64,
    /// Width and height, mm (optional: only checked against the cuts).
    pub size: Option<[f64; 2]>,
    /// Lower-left corner in drawing coordinates, mm.
    #[serde(default)]
    pub corner: [f64; 2],
    /// Where the program's X0 Y0 is.
    #[serde(default)]
    pub origin: Origin,
}

/// The program's XY zero.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum Origin {
    /// The drawing's zero.
    #[default]
    Drawing,
    /// The stock's lower-left corner (the drawing moves by −corner).
    StockCorner,
}

/// A shape the job adds: a rectangle, rounded if asked (a plate around a drawing of
/// holes).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JobShape {
    /// Layer it goes on (selectable by it).
    pub layer: String,
    /// [x0, y0, x1, y1], mm.
    pub rect: [f64; 4],
    /// Corner radius, mm.
    #[serde(default)]
    pub corner_radius: f64,
}

/// Which operation.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum OpKind {
    /// Inside closed shapes.
    ProfileIn,
    /// Outside closed shapes, holes inside, islands outside again.
    ProfileOut,
    /// On the line.
    ProfileOn,
    /// On the line (a groove, letters).
    Engrave,
    /// Clear the inside.
    Pocket,
    /// Clear the inside at a bounded engagement (`max_engagement`, `stock_to_leave`).
    Adaptive,
    /// Canned cycles at circle centres.
    Drill,
    /// V-carve.
    Vcarve,
    /// V bit along the top edge.
    Chamfer,
}

/// Which side a chamfer runs on, when the nesting should not decide.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum ChamferSide {
    /// Inside the shapes (holes).
    In,
    /// Outside the shapes (parts).
    Out,
}

/// `dogbone = true | false | "t-bone"`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub(crate) enum Dogbone {
    /// On the bisector, or none.
    On(bool),
    /// A named style.
    Style(String),
}

/// A tool by library number or by spec (`flat:3`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub(crate) enum ToolRef {
    /// The library's tool with this number.
    Number(u32),
    /// A spec, `shape:diameter…`.
    Spec(String),
}

/// Shapes to cut: every key given must match (all shapes when none is).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub(crate) struct Select {
    /// Layer name, or one of several.
    pub layer: Option<OneOrMany>,
    /// Stroke colour: `#rrggbb` or a name (red, green, blue, …).
    pub color: Option<String>,
    /// Ids as the import report numbers the shapes.
    pub ids: Option<Vec<usize>>,
    /// Size (a circle's diameter, else the larger side of the box) below this, mm.
    pub diameter_under: Option<f64>,
    /// Size above this, mm.
    pub diameter_over: Option<f64>,
    /// Closed (true) or open (false) shapes only.
    pub closed: Option<bool>,
    /// Circles only (true) or no circles (false).
    pub circle: Option<bool>,
}

/// A string or a list of them.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub(crate) enum OneOrMany {
    /// One.
    One(String),
    /// Several.
    Many(Vec<String>),
}

impl OneOrMany {
    /// The names.
    pub(crate) fn names(&self) -> Vec<&str> {
        match self {
            OneOrMany::One(s) => vec![s],
            OneOrMany::Many(v) => v.iter().map(String::as_str).collect(),
        }
    }
}

/// Tabs left on a cut-out.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub(crate) struct JobTabs {
    /// Per contour.
    pub count: usize,
    /// Width, mm.
    #[serde(default = "default_tab_width")]
    pub width: f64,
    /// Height above the cut's bottom, mm.
    #[serde(default = "default_tab_height")]
    pub height: f64,
}

fn default_tab_width() -> f64 {
    5.0
}

fn default_tab_height() -> f64 {
    1.0
}

/// One operation of the job; lengths mm, feeds mm/min, angles degrees.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JobOp {
    /// A name for the report and the program's comments.
    pub name: Option<String>,
    /// The operation.
    pub kind: OpKind,
    /// Its shapes.
    #[serde(default)]
    pub select: Select,
    /// Its tool.
    pub tool: ToolRef,
    /// T number for a tool given by spec (default: the next free number).
    pub tool_number: Option<u32>,
    /// Depth below the stock top (a chamfer's comes from its width).
    pub depth: Option<f64>,
    /// Largest depth per pass.
    pub stepdown: Option<f64>,
    /// Pocket step-over.
    pub stepover: Option<f64>,
    /// Pocket strategy.
    pub strategy: Option<PocketStrategy>,
    /// Stock left for a finishing pass.
    pub allowance: Option<f64>,
    /// Adaptive: largest engagement angle, degrees (90).
    pub max_engagement: Option<f64>,
    /// Adaptive: stock left on the walls (0).
    pub stock_to_leave: Option<f64>,
    /// Cutting feed.
    pub feed: Option<f64>,
    /// Plunge and ramp feed.
    pub plunge_feed: Option<f64>,
    /// Spindle speed.
    pub rpm: Option<f64>,
    /// How the tool enters.
    pub entry: Option<EntryKind>,
    /// Ramp and helix angle.
    pub ramp_angle: Option<f64>,
    /// Tabs on profiles.
    pub tabs: Option<JobTabs>,
    /// Lead-in arc radius onto profiles.
    pub lead_in: Option<f64>,
    /// Lead-out arc radius.
    pub lead_out: Option<f64>,
    /// Drill peck depth.
    pub peck: Option<f64>,
    /// Drill dwell, s.
    pub dwell: Option<f64>,
    /// V-carving leftover.
    pub leftover: Option<f64>,
    /// Chamfer width on the top face.
    pub width: Option<f64>,
    /// Chamfer tip offset into the waste.
    pub tip_offset: Option<f64>,
    /// Chamfer side, instead of the nesting's.
    pub side: Option<ChamferSide>,
    /// Pocket and profile-in: a notch of the tool's radius in every inside corner
    /// (`true`: on the bisector; `"t-bone"`: along the longer side).
    pub dogbone: Option<Dogbone>,
}

/// Line (from 1) of byte offset `at` in `text`.
pub(crate) fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

/// Reads the job `text` of file `name`; a syntax error or unknown key names the line.
pub(crate) fn parse_job(name: &str, text: &str) -> Result<Job, Error> {
    let job = parse_job_shapes(name, text)?;
    if job.op.is_empty() {
        return Err(Error(format!(
            "{name}: no [[op]]: a job needs at least one operation"
        )));
    }
    Ok(job)
}

/// Reads the job `text` as [`parse_job`] does, with no operation needed yet (the page asks
/// for a drawing's shapes before it has any).
pub(crate) fn parse_job_shapes(name: &str, text: &str) -> Result<Job, Error> {
    let job: Job = toml::from_str(text).map_err(|e| Error(format!("{name}: {e}")))?;
    if !(job.stock.thickness.is_finite() && job.stock.thickness > 0.0) {
        return Err(Error(format!(
            "{name}: [stock] thickness = {}: must be above 0 mm",
            job.stock.thickness
        )));
    }
    Ok(job)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_keys_name_their_line() {
        let text = "drawing = \"a.svg\"\n[stock]\nthickness = 6\n[[op]]\nkind = \"pocket\"\ntool = 2\ndepht = 3\n";
        let e = parse_job("job.toml", text).unwrap_err().0;
        assert!(e.starts_with("job.toml: "), "{e}");
        assert!(e.contains("line 7") && e.contains("depht"), "{e}");
    }

    #[test]
    fn tools_by_number_or_spec_and_selections() {
        let text = "drawing = \"a.svg\"\n[stock]\nthickness = 6\n[[op]]\nkind = \"drill\"\ntool = \"flat:3\"\nselect = { layer = [\"A\", \"B\"], diameter_under = 10 }\n[[op]]\nkind = \"chamfer\"\ntool = 2\n";
        let job = parse_job("job.toml", text).unwrap();
        assert_eq!(job.op[0].get_ref().tool, ToolRef::Spec("flat:3".into()));
        assert_eq!(job.op[1].get_ref().tool, ToolRef::Number(2));
        let sel = &job.op[0].get_ref().select;
        assert_eq!(sel.layer.as_ref().unwrap().names(), ["A", "B"]);
        assert_eq!(sel.diameter_under, Some(10.0));
        assert_eq!(line_of(text, job.op[1].span().start), 8);
    }
}
