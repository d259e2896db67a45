//! Ink/Stitch's parameters: the `inkstitch:` attributes (namespace
//! `http://inkstitch.org/namespace`) an SVG designed in Ink/Stitch carries on each element.
//!
//! As Ink/Stitch reads them: a parameter belongs to the element it is written on (Ink/Stitch
//! looks it up on the node itself, not on its groups); the element's colour and stroke width
//! come from its style, which is inherited through groups and CSS classes (usvg resolves that
//! for the drawing). A parameter left out, or empty, takes Ink/Stitch's default, given beside
//! each field below (lengths in mm, angles in degrees). Booleans are Ink/Stitch's: `yes`, `y`,
//! `true`, `t`, `1` in any case are true. A value that is not a number where one is needed is
//! refused with the file, the element and the attribute.

use oficina_geom::{Drawing, Path, Point};
use std::collections::HashMap;

/// The namespace of Ink/Stitch's attributes.
pub const NAMESPACE: &str = "http://inkstitch.org/namespace";

/// How a stroke that is not a satin column is sewn (`stroke_method`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StrokeMethod {
    /// `running_stitch` (the default).
    #[default]
    Running,
    /// `manual_stitch`: every node of the path is a needle point.
    Manual,
    /// `zigzag_stitch`: a zig-zag of the stroke's width.
    Zigzag,
    /// `ripple_stitch`: copies of the line shrinking to a target (a spiral for a closed
    /// line), between two rails, or along a guide line (`generate/ripple.rs`).
    Ripple,
}

/// How a filled shape is sewn (`fill_method`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FillMethod {
    /// `auto_fill` (the default), also `legacy_fill`: rows of tatami.
    #[default]
    Auto,
    /// `contour_fill`: rings parallel to the outline, inwards.
    Contour,
    /// `guided_fill`: rows that follow the element's guide line (`generate/guided.rs`);
    /// `parallel` is `guided_fill_strategy` 1 (parallel offsets) against 0 (shifted copies).
    Guided {
        /// Rows are parallel offsets of the guide, not shifted copies of it.
        parallel: bool,
    },
}

/// Which satin rails are reversed before they are paired (`reverse_rails`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ReverseRails {
    /// `automatic` (the default): a rail drawn the other way round is reversed.
    #[default]
    Automatic,
    /// `none`: as drawn.
    None,
    /// `first`: the first rail.
    First,
    /// `second`: the second rail.
    Second,
    /// `both`.
    Both,
}

/// Lock stitches of an element (`ties`: 0 both, 1 at the start, 2 at the end, 3 none;
/// Ink/Stitch's older files say `True` / `False`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ties {
    /// Tie in where the element starts after a cut.
    pub start: bool,
    /// Tie off where the thread is cut after it.
    pub end: bool,
}

/// One element's parameters, resolved to Ink/Stitch's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementParams {
    /// `satin_column`: the stroke is a satin column between its two rails (false).
    pub satin_column: bool,
    /// `stroke_method` (running).
    pub stroke_method: StrokeMethod,
    /// `running_stitch_length_mm` (2.5).
    pub running_stitch_length: f64,
    /// `repeats`: passes over a running line, back and forth (1).
    pub repeats: u32,
    /// `bean_stitch_repeats`: each running stitch sewn again back and forth this many times
    /// (0; 1 is a triple stitch).
    pub bean_stitch_repeats: u32,
    /// `reverse_rails` (automatic).
    pub reverse_rails: ReverseRails,
    /// `swap_satin_rails`: the zig-zag starts on the other rail (false).
    pub swap_rails: bool,
    /// `zigzag_spacing_mm`: peak to peak distance of satin zig-zags (0.4).
    pub zigzag_spacing: f64,
    /// `pull_compensation_mm`: each side of a satin moved outwards by this (0).
    pub pull_compensation: f64,
    /// `e_stitch` or `satin_method="e_stitch"`: an E-stitch instead of a satin (false).
    pub e_stitch: bool,
    /// `max_stitch_length_mm`: the longest fill stitch (3.0); satin zigs longer are split
    /// (satins: the machine's longest when not given).
    pub max_stitch_length: Option<f64>,
    /// `center_walk_underlay` (false).
    pub center_walk_underlay: bool,
    /// `center_walk_underlay_stitch_length_mm` (1.5).
    pub center_walk_length: f64,
    /// `center_walk_underlay_repeats`: passes, there and back (2).
    pub center_walk_repeats: u32,
    /// `contour_underlay` (false).
    pub contour_underlay: bool,
    /// `contour_underlay_stitch_length_mm` (1.5).
    pub contour_length: f64,
    /// `contour_underlay_inset_mm` (0.4).
    pub contour_inset: f64,
    /// `zigzag_underlay` (false).
    pub zigzag_underlay: bool,
    /// `zigzag_underlay_spacing_mm` (3.0).
    pub zigzag_underlay_spacing: f64,
    /// `zigzag_underlay_inset_mm` (half the contour inset).
    pub zigzag_underlay_inset: f64,
    /// `angle` of fill rows, degrees counter-clockwise from X (0).
    pub angle: f64,
    /// `row_spacing_mm` (0.25).
    pub row_spacing: f64,
    /// `staggers`: rows before the stitch grid repeats (4).
    pub staggers: u32,
    /// `expand_mm`: the filled shape grown (or shrunk, negative) by this before it is sewn (0).
    pub expand: f64,
    /// `fill_method` (auto).
    pub fill_method: FillMethod,
    /// `fill_underlay` (true).
    pub fill_underlay: bool,
    /// `fill_underlay_angle`: one or more angles, each an underlay layer (the fill's + 90).
    pub fill_underlay_angles: Vec<f64>,
    /// `fill_underlay_row_spacing_mm` (3 × row spacing).
    pub fill_underlay_row_spacing: f64,
    /// `fill_underlay_inset_mm` (0).
    pub fill_underlay_inset: f64,
    /// `fill_underlay_max_stitch_length_mm` (the fill's).
    pub fill_underlay_max_stitch_length: f64,
    /// `trim_after` (false).
    pub trim_after: bool,
    /// `stop_after` (false).
    pub stop_after: bool,
    /// `ties` (both).
    pub ties: Ties,
    /// `force_lock_stitches`: tied off at its end even when no trim follows (false).
    pub force_lock: bool,
    /// `min_stitch_length_mm`: shorter stitches are merged away (none).
    pub min_stitch_length: Option<f64>,
    /// `min_jump_stitch_length_mm` (older files: `collapse_len_mm`): a move to the element
    /// shorter than this is sewn, not jumped (none: Oficina's own rule, a jump).
    pub min_jump_length: Option<f64>,
    /// Ripple stitch (`stroke_method="ripple_stitch"`).
    pub ripple: RippleParams,
}

/// A ripple stitch's parameters (Ink/Stitch's names and defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct RippleParams {
    /// `line_count`: copies of the line from start to finish (10).
    pub line_count: u32,
    /// `min_line_dist_mm`: when given, the count comes from this spacing instead (none).
    pub min_line_dist: Option<f64>,
    /// `skip_start` / `skip_end`: copies left out at the start and the end (0).
    pub skip_start: u32,
    /// See `skip_start`.
    pub skip_end: u32,
    /// `exponent`: copies bunched towards one end when not 1 (1).
    pub exponent: f64,
    /// `flip_exponent`: the bunching at the other end (false).
    pub flip_exponent: bool,
    /// `reverse`: sewn from the other end (false).
    pub reverse: bool,
    /// `flip_copies`: open ripples go back and forth, every other copy reversed (true).
    pub flip_copies: bool,
    /// `scale_start` / `scale_end`: size of the first and last copy along a guide line, % (100, 0).
    pub scale_start: f64,
    /// See `scale_start`.
    pub scale_end: f64,
    /// `rotate_ripples`: copies along a guide turn as the guide turns (true).
    pub rotate: bool,
    /// `grid_size_mm`: when not 0, the line is cut every this much and the joins across the
    /// copies are sewn too, after the copies (a grid).
    pub grid_size: f64,
    /// `grid_first`: the grid first, then the copies (false).
    pub grid_first: bool,
}

impl Default for RippleParams {
    fn default() -> RippleParams {
        RippleParams {
            line_count: 10,
            min_line_dist: None,
            skip_start: 0,
            skip_end: 0,
            exponent: 1.0,
            flip_exponent: false,
            reverse: false,
            flip_copies: true,
            scale_start: 100.0,
            scale_end: 0.0,
            rotate: true,
            grid_size: 0.0,
            grid_first: false,
        }
    }
}

impl Default for ElementParams {
    fn default() -> ElementParams {
        ElementParams {
            satin_column: false,
            stroke_method: StrokeMethod::Running,
            running_stitch_length: 2.5,
            repeats: 1,
            bean_stitch_repeats: 0,
            reverse_rails: ReverseRails::Automatic,
            swap_rails: false,
            zigzag_spacing: 0.4,
            pull_compensation: 0.0,
            e_stitch: false,
            max_stitch_length: None,
            center_walk_underlay: false,
            center_walk_length: 1.5,
            center_walk_repeats: 2,
            contour_underlay: false,
            contour_length: 1.5,
            contour_inset: 0.4,
            zigzag_underlay: false,
            zigzag_underlay_spacing: 3.0,
            zigzag_underlay_inset: 0.2,
            angle: 0.0,
            row_spacing: 0.25,
            staggers: 4,
            expand: 0.0,
            fill_method: FillMethod::Auto,
            fill_underlay: true,
            fill_underlay_angles: vec![90.0],
            fill_underlay_row_spacing: 0.75,
            fill_underlay_inset: 0.0,
            fill_underlay_max_stitch_length: 3.0,
            trim_after: false,
            stop_after: false,
            ties: Ties {
                start: true,
                end: true,
            },
            force_lock: false,
            min_stitch_length: None,
            min_jump_length: None,
            ripple: RippleParams::default(),
        }
    }
}

/// Fill stitch length when `max_stitch_length_mm` is not given.
pub const FILL_STITCH_LENGTH: f64 = 3.0;

/// A value Ink/Stitch could not use either, named by file, element and attribute.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct InkstitchError(pub String);

/// Every element's `inkstitch:` attributes of one SVG, by element id as the drawing names it
/// (`#id`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Inkstitch {
    elements: HashMap<String, ElementParams>,
    /// The document declares Ink/Stitch's namespace: its elements sew as Ink/Stitch sews them
    /// (in document order, strokes as running stitch unless satin columns), with defaults
    /// where an element says nothing.
    pub is_inkstitch: bool,
    /// What was read but is sewn differently from Ink/Stitch (ripple stitch, unknown methods).
    pub notes: Vec<String>,
    /// Elements not sewn: Ink/Stitch's command symbols and their connectors, objects with an
    /// `ignore_object` command, the objects of a layer with an `ignore_layer` command.
    ignored: std::collections::HashSet<String>,
    /// Byte ranges of the source text of the elements not sewn, each with what replaces it
    /// (empty, or a marker path standing where a command points).
    cut: Vec<(std::ops::Range<usize>, String)>,
    /// Where positional commands point, found in the drawing by their marker's id.
    positions: Vec<Position>,
    /// The guide line (`#id`) of an element (`#id`).
    guides: HashMap<String, String>,
}

/// Ink/Stitch's commands that place something: where a fill, a satin or a running line
/// starts or ends, and where a ripple shrinks to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Place {
    FillStart,
    FillEnd,
    RunStart,
    RunEnd,
    SatinStart,
    SatinEnd,
    RippleTarget,
}

impl Place {
    fn of(cmd: &str) -> Option<Place> {
        Some(match cmd {
            "fill_start" => Place::FillStart,
            "fill_end" => Place::FillEnd,
            "run_start" => Place::RunStart,
            "run_end" => Place::RunEnd,
            "satin_start" => Place::SatinStart,
            "satin_end" => Place::SatinEnd,
            "ripple_target" => Place::RippleTarget,
            _ => return None,
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
struct Position {
    target: String,
    place: Place,
    /// The id (`#id`) of the path whose start (or end) is the point: the marker left by
    /// [`Inkstitch::strip`], or the connector itself in a drawing read unstripped.
    marker: String,
    at_start: bool,
}

/// What an element's commands and guide line place, in the drawing's coordinates (mm).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Placement {
    /// `fill_start`: the fill's first stitch nearest here.
    pub fill_start: Option<Point>,
    /// `fill_end`: the fill's last stitch nearest here.
    pub fill_end: Option<Point>,
    /// `run_start` / `satin_start`: the line or column starts at its end nearest here.
    pub start: Option<Point>,
    /// `run_end` / `satin_end`: the line or column ends at its end nearest here.
    pub end: Option<Point>,
    /// `ripple_target`: where a ripple shrinks to.
    pub ripple_target: Option<Point>,
    /// The guide line (a path marked `marker-start:url(#inkstitch-guide-line-marker)` in
    /// the element's group): guided fill rows and ripple copies follow it.
    pub guide: Option<Path>,
}

impl Inkstitch {
    /// The parameters of element `id` (`#id`), Ink/Stitch's defaults for an element without
    /// any.
    pub fn element(&self, id: &str) -> ElementParams {
        self.elements.get(id).cloned().unwrap_or_default()
    }

    /// Whether element `id` (`#id`) is left out, as Ink/Stitch leaves it out.
    pub fn ignored(&self, id: &str) -> bool {
        self.ignored.contains(id)
    }

    /// The SVG text `svg` (the one read) without the elements Ink/Stitch does not sew: command
    /// symbols' `<use>`, connectors, ignored objects and layers. (A drawing importer turns a
    /// `<use>` into anonymous paths, which could not be told apart afterwards.)
    pub fn strip(&self, svg: &str) -> String {
        let mut cut = self.cut.clone();
        cut.sort_by_key(|(r, _)| (r.start, std::cmp::Reverse(r.end)));
        let mut out = String::with_capacity(svg.len());
        let mut at = 0;
        for (r, with) in cut {
            if r.start < at || r.end > svg.len() {
                continue; // inside one already cut
            }
            out.push_str(&svg[at..r.start]);
            out.push_str(&with);
            at = r.end;
        }
        out.push_str(&svg[at..]);
        out
    }

    /// What commands and guide lines place, per element (`#id`), read from `drawing` (the
    /// design imported from [`Inkstitch::strip`]'s text, where each command left a marker).
    pub fn placed(&self, drawing: &Drawing) -> HashMap<String, Placement> {
        let mut first: HashMap<&str, &Path> = HashMap::new();
        for p in drawing.paths() {
            first.entry(p.source.element.as_str()).or_insert(p);
        }
        let mut out: HashMap<String, Placement> = HashMap::new();
        for pos in &self.positions {
            let Some(path) = first.get(pos.marker.as_str()) else {
                continue;
            };
            let at = if pos.at_start {
                path.start()
            } else {
                path.end()
            };
            let e = out.entry(pos.target.clone()).or_default();
            let slot = match pos.place {
                Place::FillStart => &mut e.fill_start,
                Place::FillEnd => &mut e.fill_end,
                Place::RunStart | Place::SatinStart => &mut e.start,
                Place::RunEnd | Place::SatinEnd => &mut e.end,
                Place::RippleTarget => &mut e.ripple_target,
            };
            *slot = slot.or(at);
        }
        for (target, guide) in &self.guides {
            let paths: Vec<&Path> = drawing
                .paths()
                .filter(|p| p.source.element == *guide)
                .collect();
            // The longest subpath of the guide (Ink/Stitch takes the first line).
            if let Some(g) = paths
                .iter()
                .max_by(|a, b| a.length().total_cmp(&b.length()))
            {
                out.entry(target.clone()).or_default().guide = Some((*g).clone());
            }
        }
        out
    }

    /// Elements that carry at least one `inkstitch:` parameter.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// No element carries a parameter.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }
}

/// Reads the `inkstitch:` attributes of `svg` (the text of `file`, for messages).
pub fn read_inkstitch(svg: &str, file: &str) -> Result<Inkstitch, InkstitchError> {
    let doc = roxmltree::Document::parse_with_options(
        svg,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .map_err(|e| InkstitchError(format!("{file}: {e}")))?;
    let mut out = Inkstitch {
        is_inkstitch: doc
            .root_element()
            .namespaces()
            .any(|ns| ns.uri() == NAMESPACE),
        ..Inkstitch::default()
    };
    for n in doc.descendants().filter(|n| n.is_element()) {
        let attrs: HashMap<&str, &str> = n
            .attributes()
            .filter(|a| a.namespace() == Some(NAMESPACE))
            .map(|a| (a.name(), a.value().trim()))
            .filter(|(_, v)| !v.is_empty())
            .collect();
        if attrs.is_empty() {
            continue;
        }
        out.is_inkstitch = true;
        let line = doc.text_pos_at(n.range().start).row;
        let name = n.attribute("id").map_or_else(
            || format!("<{}> at line {line}", n.tag_name().name()),
            |id| format!("#{id} (line {line})"),
        );
        let e = element_params(&attrs, &format!("{file}: {name}"), &mut out.notes)?;
        if let Some(id) = n.attribute("id") {
            // The first element of an id wins, as usvg keeps it.
            out.elements.entry(format!("#{id}")).or_insert(e);
        }
    }
    commands(&doc, file, &mut out);
    Ok(out)
}

const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";
const XLINK: &str = "http://www.w3.org/1999/xlink";

/// Ink/Stitch's commands: a `<use>` of a symbol `#inkstitch_<command>` joined to its object by
/// a connector path (`inkscape:connection-start` / `-end`, one end the `<use>`, the other the
/// object); `ignore_layer` is a `<use>` standing in its layer. Trim and stop set the object's
/// `trim_after` / `stop_after`; ignore leaves it out. The symbols and connectors are never
/// sewn. A command that places something points where its connector ends on the object (a
/// `ripple_target` where its symbol stands), as Ink/Stitch reads it: that point is left in the
/// stripped text as a tiny marker path with the connector's (or symbol's) id and transform,
/// so the importer puts it in the drawing's coordinates ([`Inkstitch::placed`]).
fn commands(doc: &roxmltree::Document, file: &str, out: &mut Inkstitch) {
    let href = |n: &roxmltree::Node| {
        n.attribute((XLINK, "href"))
            .or_else(|| n.attribute("href"))
            .map(str::to_string)
    };
    // Command uses by id, and what they command.
    let mut uses: HashMap<String, (String, roxmltree::Node)> = HashMap::new();
    for n in doc.descendants().filter(|n| n.has_tag_name("use")) {
        let Some(cmd) = href(&n).and_then(|h| h.strip_prefix("#inkstitch_").map(str::to_string))
        else {
            continue;
        };
        out.is_inkstitch = true;
        if let Some(id) = n.attribute("id") {
            out.ignored.insert(format!("#{id}"));
            uses.insert(format!("#{id}"), (cmd.clone(), n));
        }
        if cmd == "ripple_target" {
            continue; // cut below, with its connector: it becomes the marker of its point
        }
        if matches!(cmd.as_str(), "origin" | "stop_position") {
            out.notes.push(format!(
                "{file}: Ink/Stitch command \"{cmd}\" not used by Oficina (the design is centred in the hoop)"
            ));
        }
        out.cut.push((n.range(), String::new()));
        if cmd == "ignore_layer" {
            if let Some(layer) = n
                .ancestors()
                .find(|a| a.attribute((INKSCAPE, "groupmode")) == Some("layer"))
            {
                out.cut.push((layer.range(), String::new()));
                for d in layer.descendants().filter_map(|d| d.attribute("id")) {
                    out.ignored.insert(format!("#{d}"));
                }
            }
        }
    }
    // Everything inside a command symbol, and Ink/Stitch's markers (the importer would draw
    // the guide line's marker as paths of its own).
    for n in doc.descendants().filter(|n| {
        (n.has_tag_name("symbol") || n.has_tag_name("marker"))
            && n.attribute("id")
                .is_some_and(|i| i.starts_with("inkstitch_") || i.starts_with("inkstitch-"))
    }) {
        if n.has_tag_name("marker") {
            out.cut.push((n.range(), String::new()));
        }
        for d in n.descendants().filter_map(|d| d.attribute("id")) {
            out.ignored.insert(format!("#{d}"));
        }
    }
    let mut placed_uses: Vec<&str> = Vec::new();
    for c in doc.descendants().filter(|n| n.is_element()) {
        let (Some(a), Some(b)) = (
            c.attribute((INKSCAPE, "connection-start")),
            c.attribute((INKSCAPE, "connection-end")),
        ) else {
            continue;
        };
        let (cmd, use_node, target, at_start) = match (uses.get(a), uses.get(b)) {
            (Some((cmd, u)), _) => (cmd, u, b, false),
            (None, Some((cmd, u))) => (cmd, u, a, true),
            (None, None) => continue,
        };
        let id = c.attribute("id").map_or_else(
            || format!("oficina-command-{}", c.range().start),
            str::to_string,
        );
        out.ignored.insert(format!("#{id}"));
        let place = Place::of(cmd);
        let marker = match place {
            Some(Place::RippleTarget) => {
                // The symbol's own position: its x, y under its transform.
                let uid = use_node.attribute("id").unwrap_or_default();
                if !placed_uses.contains(&uid) {
                    placed_uses.push(uid);
                    let num = |k: &str| {
                        use_node
                            .attribute(k)
                            .and_then(|v| v.trim().parse::<f64>().ok())
                            .unwrap_or(0.0)
                    };
                    let m = marker_path(
                        uid,
                        use_node.attribute("transform"),
                        (num("x"), num("y")),
                        true,
                    );
                    out.cut.push((use_node.range(), m));
                }
                out.positions.push(Position {
                    target: target.to_string(),
                    place: Place::RippleTarget,
                    marker: format!("#{uid}"),
                    at_start: true,
                });
                String::new()
            }
            Some(place) => {
                out.positions.push(Position {
                    target: target.to_string(),
                    place,
                    marker: format!("#{id}"),
                    at_start,
                });
                match connector_end(c.attribute("d").unwrap_or(""), at_start) {
                    Some(q) => marker_path(&id, c.attribute("transform"), q, at_start),
                    None => {
                        out.notes.push(format!(
                            "{file}: #{id}: the connector of command \"{cmd}\" has no path; not used"
                        ));
                        String::new()
                    }
                }
            }
            None => String::new(),
        };
        out.cut.push((c.range(), marker));
        let e = out.elements.entry(target.to_string()).or_default();
        match cmd.as_str() {
            "trim" => e.trim_after = true,
            "stop" => e.stop_after = true,
            "ignore_object" => {
                out.ignored.insert(target.to_string());
                let id = target.trim_start_matches('#');
                if let Some(t) = doc.descendants().find(|t| t.attribute("id") == Some(id)) {
                    out.cut.push((t.range(), String::new()));
                }
            }
            _ if place.is_some() => {}
            other => out.notes.push(format!(
                "{file}: {target}: Ink/Stitch command \"{other}\" not used by Oficina"
            )),
        }
    }
    // A ripple target without a connector is no command of any object.
    for (id, (cmd, n)) in &uses {
        if cmd == "ripple_target" && !placed_uses.contains(&id.trim_start_matches('#')) {
            out.cut.push((n.range(), String::new()));
        }
    }
    guides(doc, file, out);
}

/// Guide lines: a path whose style starts with Ink/Stitch's guide-line marker guides the
/// other elements of its group (Ink/Stitch looks for it among the element's siblings). It is
/// not sewn; the first one counts. A pattern (the pattern marker) is not sewn either.
fn guides(doc: &roxmltree::Document, file: &str, out: &mut Inkstitch) {
    let marked = |n: &roxmltree::Node, what: &str| {
        n.attribute("style")
            .is_some_and(|s| s.contains(&format!("marker-start:url(#inkstitch-{what}-marker")))
    };
    for n in doc.descendants().filter(|n| n.is_element()) {
        // Marked objects are never sewn themselves (Ink/Stitch's marker objects).
        let Some(id) = n.attribute("id") else {
            continue;
        };
        if marked(&n, "guide-line") {
            out.ignored.insert(format!("#{id}"));
        } else if marked(&n, "pattern") {
            out.ignored.insert(format!("#{id}"));
            out.notes.push(format!(
                "{file}: #{id}: an Ink/Stitch pattern, not applied by Oficina (not sewn)"
            ));
        }
    }
    for g in doc.descendants().filter(|n| n.is_element()) {
        let Some(guide) = g
            .children()
            .find(|c| c.is_element() && marked(c, "guide-line"))
            .and_then(|c| c.attribute("id"))
        else {
            continue;
        };
        for c in g
            .children()
            .filter(|c| c.is_element() && !marked(c, "guide-line"))
        {
            if let Some(id) = c.attribute("id") {
                out.guides.insert(format!("#{id}"), format!("#{guide}"));
            }
        }
    }
}

/// A marker: a path a hair long that starts (`at_start`) or ends at (x, y) under
/// `transform`, as the connector it replaces did (it stands in the same group, so the
/// importer applies the same transforms).
fn marker_path(id: &str, transform: Option<&str>, (x, y): (f64, f64), at_start: bool) -> String {
    let t = transform
        .map(|t| format!(r#" transform="{}""#, t.replace('"', "&quot;")))
        .unwrap_or_default();
    let x0 = if at_start { x } else { x - 0.001 };
    format!(
        r#"<path id="{id}"{t} d="M {x0} {y} h 0.001" style="fill:none;stroke:#000000;stroke-width:0.01"/>"#
    )
}

/// The connector's point on its object: the first point of its path (`at_start`) or the
/// last point of its first subpath, as Ink/Stitch takes it.
fn connector_end(d: &str, at_start: bool) -> Option<(f64, f64)> {
    use svgtypes::SimplePathSegment as S;
    let mut first: Option<(f64, f64)> = None;
    let mut last: Option<(f64, f64)> = None;
    for seg in svgtypes::SimplifyingPathParser::from(d) {
        let p = match seg.ok()? {
            S::MoveTo { .. } if first.is_some() => break,
            S::MoveTo { x, y } | S::LineTo { x, y } => (x, y),
            S::Quadratic { x, y, .. } | S::CurveTo { x, y, .. } => (x, y),
            S::ClosePath => first?,
        };
        first = first.or(Some(p));
        last = Some(p);
    }
    if at_start {
        first
    } else {
        last
    }
}

fn boolean(v: &str) -> bool {
    matches!(
        v.to_ascii_lowercase().as_str(),
        "yes" | "y" | "true" | "t" | "1"
    )
}

fn element_params(
    a: &HashMap<&str, &str>,
    at: &str,
    notes: &mut Vec<String>,
) -> Result<ElementParams, InkstitchError> {
    let num = |key: &str| -> Result<Option<f64>, InkstitchError> {
        a.get(key)
            .map(|v| {
                // Ink/Stitch writes lists ("0 90", "1,0") for some; the first counts here.
                let first = v.split([' ', ',']).find(|s| !s.is_empty()).unwrap_or("");
                first.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                    InkstitchError(format!(
                        "{at}: inkstitch:{key} \"{v}\" is not a number; fix it in Ink/Stitch's Params dialog"
                    ))
                })
            })
            .transpose()
    };
    let len = |key: &str, lo: f64, hi: f64| -> Result<Option<f64>, InkstitchError> {
        match num(key)? {
            Some(x) if !(lo..=hi).contains(&x) => Err(InkstitchError(format!(
                "{at}: inkstitch:{key} {x} is outside {lo}..{hi}"
            ))),
            x => Ok(x),
        }
    };
    let count = |key: &str, hi: f64| -> Result<Option<u32>, InkstitchError> {
        match num(key)? {
            Some(x) if !(0.0..=hi).contains(&x) => Err(InkstitchError(format!(
                "{at}: inkstitch:{key} {x} is outside 0..{hi}"
            ))),
            x => Ok(x.map(|x| x.round() as u32)),
        }
    };
    let flag = |key: &str| a.get(key).map(|v| boolean(v));
    let d = ElementParams::default();
    let row_spacing = len("row_spacing_mm", 0.05, 10.0)?.unwrap_or(d.row_spacing);
    let max_stitch_length = len("max_stitch_length_mm", 0.1, 100.0)?;
    let angle = num("angle")?.unwrap_or(0.0);
    let contour_inset = len("contour_underlay_inset_mm", -10.0, 10.0)?.unwrap_or(d.contour_inset);
    let fill_underlay_angles = match a.get("fill_underlay_angle") {
        None => vec![angle + 90.0],
        Some(v) => v
            .split([' ', ','])
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        InkstitchError(format!(
                            "{at}: inkstitch:fill_underlay_angle \"{v}\" is not a list of angles"
                        ))
                    })
            })
            .collect::<Result<_, _>>()?,
    };
    let stroke_method = match a.get("stroke_method").copied() {
        None | Some("running_stitch") => StrokeMethod::Running,
        Some("manual_stitch") => StrokeMethod::Manual,
        Some("zigzag_stitch") => StrokeMethod::Zigzag,
        Some("ripple_stitch") => StrokeMethod::Ripple,
        Some(other) => {
            notes.push(format!(
                "{at}: stroke method \"{other}\" unknown to Oficina, sewn as a running stitch"
            ));
            StrokeMethod::Running
        }
    };
    let fill_method = match a.get("fill_method").copied() {
        Some("contour_fill") => FillMethod::Contour,
        Some("guided_fill") => FillMethod::Guided {
            parallel: count("guided_fill_strategy", 1.0)? == Some(1),
        },
        None | Some("auto_fill" | "legacy_fill") => FillMethod::Auto,
        Some(other) => {
            notes.push(format!(
                "{at}: fill method \"{other}\" unknown to Oficina, sewn as rows (auto fill)"
            ));
            FillMethod::Auto
        }
    };
    let ties = match a.get("ties").copied() {
        None | Some("0") => d.ties,
        Some("1") => Ties {
            start: true,
            end: false,
        },
        Some("2") => Ties {
            start: false,
            end: true,
        },
        Some("3") => Ties {
            start: false,
            end: false,
        },
        Some(v) => {
            let b = boolean(v);
            Ties { start: b, end: b }
        }
    };
    let reverse_rails = match a.get("reverse_rails").copied() {
        None | Some("automatic") => ReverseRails::Automatic,
        Some("none") => ReverseRails::None,
        Some("first") => ReverseRails::First,
        Some("second") => ReverseRails::Second,
        Some("both") => ReverseRails::Both,
        Some(other) => {
            notes.push(format!(
                "{at}: reverse_rails \"{other}\" unknown to Oficina, rails paired automatically"
            ));
            ReverseRails::Automatic
        }
    };
    let fill_len = max_stitch_length.unwrap_or(FILL_STITCH_LENGTH);
    if num("join_style")?.is_some_and(|j| j == 1.0) && stroke_method == StrokeMethod::Ripple {
        notes.push(format!(
            "{at}: ripple join style \"point\" sewn as \"flat\""
        ));
    }
    let rd = RippleParams::default();
    let ripple = RippleParams {
        line_count: count("line_count", 10_000.0)?
            .unwrap_or(rd.line_count)
            .max(1),
        min_line_dist: len("min_line_dist_mm", 0.0, 100.0)?.filter(|&d| d > 0.0),
        skip_start: count("skip_start", 10_000.0)?.unwrap_or(0),
        skip_end: count("skip_end", 10_000.0)?.unwrap_or(0),
        exponent: len("exponent", 0.1, 100.0)?.unwrap_or(rd.exponent),
        flip_exponent: flag("flip_exponent").unwrap_or(false),
        reverse: flag("reverse").unwrap_or(false),
        flip_copies: flag("flip_copies").unwrap_or(rd.flip_copies),
        scale_start: len("scale_start", 0.0, 10_000.0)?.unwrap_or(rd.scale_start),
        scale_end: len("scale_end", 0.0, 10_000.0)?.unwrap_or(rd.scale_end),
        rotate: flag("rotate_ripples").unwrap_or(rd.rotate),
        grid_size: len("grid_size_mm", -100.0, 100.0)?.map_or(0.0, f64::abs),
        grid_first: flag("grid_first").unwrap_or(false),
    };
    Ok(ElementParams {
        satin_column: flag("satin_column").unwrap_or(false),
        stroke_method,
        running_stitch_length: len("running_stitch_length_mm", 0.1, 100.0)?
            .unwrap_or(d.running_stitch_length),
        repeats: count("repeats", 100.0)?.unwrap_or(1).max(1),
        bean_stitch_repeats: count("bean_stitch_repeats", 100.0)?.unwrap_or(0),
        reverse_rails,
        swap_rails: flag("swap_satin_rails").unwrap_or(false),
        zigzag_spacing: len("zigzag_spacing_mm", 0.05, 10.0)?.unwrap_or(d.zigzag_spacing),
        pull_compensation: len("pull_compensation_mm", -10.0, 10.0)?.unwrap_or(d.pull_compensation),
        e_stitch: flag("e_stitch").unwrap_or(false) || a.get("satin_method") == Some(&"e_stitch"),
        max_stitch_length,
        center_walk_underlay: flag("center_walk_underlay").unwrap_or(false),
        center_walk_length: len("center_walk_underlay_stitch_length_mm", 0.1, 100.0)?
            .unwrap_or(d.center_walk_length),
        center_walk_repeats: count("center_walk_underlay_repeats", 100.0)?
            .unwrap_or(d.center_walk_repeats)
            .max(1),
        contour_underlay: flag("contour_underlay").unwrap_or(false),
        contour_length: len("contour_underlay_stitch_length_mm", 0.1, 100.0)?
            .unwrap_or(d.contour_length),
        contour_inset,
        zigzag_underlay: flag("zigzag_underlay").unwrap_or(false),
        zigzag_underlay_spacing: len("zigzag_underlay_spacing_mm", 0.05, 100.0)?
            .unwrap_or(d.zigzag_underlay_spacing),
        zigzag_underlay_inset: len("zigzag_underlay_inset_mm", -10.0, 10.0)?
            .unwrap_or(contour_inset / 2.0),
        angle,
        row_spacing,
        staggers: count("staggers", 100.0)?.unwrap_or(d.staggers).max(1),
        expand: len("expand_mm", -20.0, 20.0)?.unwrap_or(0.0),
        fill_method,
        fill_underlay: flag("fill_underlay").unwrap_or(d.fill_underlay),
        fill_underlay_angles,
        fill_underlay_row_spacing: len("fill_underlay_row_spacing_mm", 0.05, 100.0)?
            .unwrap_or(3.0 * row_spacing),
        fill_underlay_inset: len("fill_underlay_inset_mm", -10.0, 10.0)?.unwrap_or(0.0),
        fill_underlay_max_stitch_length: len("fill_underlay_max_stitch_length_mm", 0.1, 100.0)?
            .unwrap_or(fill_len),
        trim_after: flag("trim_after").unwrap_or(false),
        stop_after: flag("stop_after").unwrap_or(false),
        ties,
        force_lock: flag("force_lock_stitches").unwrap_or(false),
        // `min_stitch_len_mm` is the older name.
        min_stitch_length: match len("min_stitch_length_mm", 0.0, 10.0)? {
            Some(x) => Some(x),
            None => len("min_stitch_len_mm", 0.0, 10.0)?,
        },
        min_jump_length: match len("min_jump_stitch_length_mm", 0.0, 100.0)? {
            Some(x) => Some(x),
            None => len("collapse_len_mm", 0.0, 100.0)?,
        },
        ripple,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svg(body: &str) -> String {
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkstitch="{NAMESPACE}">{body}</svg>"#
        )
    }

    #[test]
    fn attributes_are_read_per_element_with_defaults() {
        let s = svg(r#"<g inkstitch:running_stitch_length_mm="4">
              <path id="a" d="M0 0L10 0" inkstitch:repeats="3" inkstitch:bean_stitch_repeats="1"/>
              <path id="b" d="M0 0L10 10Z" inkstitch:angle="45" inkstitch:row_spacing_mm=".15"
                    inkstitch:fill_underlay_angle="0 90" inkstitch:ties="3" inkstitch:trim_after="True"/>
            </g>"#);
        let ink = read_inkstitch(&s, "t.svg").unwrap();
        assert!(ink.is_inkstitch);
        let a = ink.element("#a");
        assert_eq!((a.repeats, a.bean_stitch_repeats), (3, 1));
        // Not inherited from the group, as Ink/Stitch reads the node itself.
        assert_eq!(a.running_stitch_length, 2.5);
        let b = ink.element("#b");
        assert_eq!(b.angle, 45.0);
        assert_eq!(b.fill_underlay_angles, vec![0.0, 90.0]);
        assert!((b.fill_underlay_row_spacing - 0.45).abs() < 1e-12);
        assert_eq!(
            b.ties,
            Ties {
                start: false,
                end: false
            }
        );
        assert!(b.trim_after);
        // Unknown element: the defaults, fill underlay across the rows.
        let c = ink.element("#nothing");
        assert_eq!(c, ElementParams::default());
        assert!(c.fill_underlay && c.fill_underlay_angles == vec![90.0]);
    }

    #[test]
    fn a_bad_number_names_file_element_and_attribute() {
        let s = svg(r#"<path id="p" d="M0 0L1 1" inkstitch:zigzag_spacing_mm="wide"/>"#);
        let e = read_inkstitch(&s, "x.svg").unwrap_err().0;
        assert!(
            e.contains("x.svg") && e.contains("#p") && e.contains("zigzag_spacing_mm"),
            "{e}"
        );
        let s = svg(r#"<path id="q" d="M0 0L1 1" inkstitch:row_spacing_mm="0"/>"#);
        let e = read_inkstitch(&s, "x.svg").unwrap_err().0;
        assert!(e.contains("#q") && e.contains("outside"), "{e}");
    }

    #[test]
    fn a_plain_svg_is_not_inkstitch() {
        let s = r#"<svg xmlns="http://www.w3.org/2000/svg"><path id="a" d="M0 0L1 1"/></svg>"#;
        let ink = read_inkstitch(s, "p.svg").unwrap();
        assert!(!ink.is_inkstitch && ink.is_empty());
    }
}
