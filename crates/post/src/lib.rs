//! Post-processors: a [`Toolpath`] becomes G-code text for a named control.
//!
//! ```
//! use oficina_cam::{Move, Operation, Toolpath};
//! use oficina_canon::{CanonOp, Pos};
//! use oficina_post::{program_text, read_back, PostDialect, PostOptions};
//!
//! let moves = vec![
//!     Move::Rapid { to: [10.0, 2.0, 5.0] },
//!     Move::Line { to: [10.0, 2.0, -1.0], feed: 5.0 },
//!     Move::Arc { to: [12.0, 4.0, -1.0], center: [10.0, 4.0], ccw: true, feed: 20.0 },
//! ];
//! let tool = "flat:6".parse().unwrap();
//! let op = Operation { name: "arc".into(), tool_number: 1, tool, spindle_rpm: 12e3, moves };
//! let path = Toolpath { safe_z: 5.0, operations: vec![op] };
//! let title = "demo".into();
//! let opts = PostOptions { dialect: PostDialect::LinuxCnc, allow_m6: true, title, settings: vec![] };
//! let text = program_text(&path, &opts).unwrap();
//! assert!(text.lines().any(|l| l == "T1 M6"), "{text}");
//! assert!(text.contains("G3 X12 Y4 I0 J2 F1200"), "{text}");
//! // Read back as the interpreter reads it: the arc ends where the toolpath says.
//! let ops = read_back(&text, &opts).unwrap();
//! let arc_end = ops.iter().find_map(|c| match c.op {
//!     CanonOp::ArcFeed { end, .. } => Some(end),
//!     _ => None,
//! });
//! assert_eq!(arc_end, Some(Pos::xyz(12.0, 4.0, -1.0)));
//! ```
//!
//! One [`Post`] per dialect, each in its own file (`linuxcnc`, `grbl`, `sinumerik`,
//! `legacy`); they share the text writer ([`Emitter`]) and the number format ([`Format`]).
//! Every setting that shaped the program is written into the header as comments, so the
//! file says how to regenerate it. [`read_back`] reads a program as Oficina's interpreter
//! does, so callers judge the text a machine would get, never the CAM's own idea of it.

mod emit;
mod format;
mod grbl;
mod legacy;
mod linuxcnc;
mod readback;
mod rs274;
mod sinumerik;

pub use emit::{Emitter, MotionWords};
pub use format::{Format, LineNumbers, Numbers, Units};
pub use readback::{read_back, read_back_with_tools};
pub use sinumerik::sinumerik_to_ngc;

use oficina_cam::{CompSide, Drill, Move, Operation, PathMode, Toolpath};
use std::io::{self, Write};

/// The control a program is written for (the interpreter's own reading dialect is
/// `oficina_gcode::Dialect`; Sinumerik is written but read back through a translation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PostDialect {
    /// grbl 1.1: no M6 unless the machine allows it; tool changes are an M0 pause.
    Grbl,
    /// LinuxCNC: `T n M6`.
    LinuxCnc,
    /// A Sinumerik-7M-style control as in seed 001: integer words in 0.001 mm.
    Sinumerik,
    /// The seed 002 controller (2006): G90 is the feed move, I J absolute, no F.
    Legacy2006,
}

impl std::str::FromStr for PostDialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "grbl" => Ok(PostDialect::Grbl),
            "linuxcnc" | "rs274" => Ok(PostDialect::LinuxCnc),
            "sinumerik" | "sinumerik-7m" => Ok(PostDialect::Sinumerik),
            "legacy-2006" | "legacy" | "legacy2006" => Ok(PostDialect::Legacy2006),
            other => Err(format!(
                "unknown post-processor '{other}': use grbl, linuxcnc, sinumerik or legacy-2006"
            )),
        }
    }
}

/// Who the program is for and what the header says about it.
#[derive(Clone, Debug, PartialEq)]
pub struct PostOptions {
    /// The control the program is written for.
    pub dialect: PostDialect,
    /// The machine has a tool changer (or a sender that handles M6).
    pub allow_m6: bool,
    /// The first header comment: what the program is.
    pub title: String,
    /// (name, value) pairs written as header comments.
    pub settings: Vec<(String, String)>,
}

/// What a tool change knows.
pub struct ToolChange<'a> {
    /// The whole toolpath (its safe Z).
    pub tp: &'a Toolpath,
    /// The caller's options (whether the machine takes M6).
    pub opts: &'a PostOptions,
    /// The operation whose tool is loaded.
    pub op: &'a Operation,
    /// The tool in the spindle; `None` at the program's first change.
    pub previous: Option<u32>,
}

/// One control's way of writing a toolpath. The driver ([`write_program_with`]) walks the
/// operations; the post writes what differs between controls.
pub trait Post {
    /// The motion words and centre convention of this control.
    fn words(&self) -> MotionWords {
        rs274::RS274_WORDS
    }
    /// The number format used when the caller asks for none.
    fn default_format(&self) -> Format {
        Format::DEFAULT
    }
    /// Refuses format options this control cannot express.
    fn check_format(&self, format: &Format) -> Result<(), String> {
        format.validate()
    }
    /// Header comments and the modal set-up before the first tool.
    fn prologue(&self, e: &mut Emitter, _tp: &Toolpath, opts: &PostOptions) -> io::Result<()> {
        let format = e.format;
        header_comments(e, opts, &format)?;
        rs274::modal_setup(e)
    }
    /// Loads `c.op`'s tool: the skeleton every control follows. With a tool in, up to safe
    /// Z first; then the control's change words ([`Post::load_tool`]); after the program's
    /// first change, [`Post::first_tool_ready`].
    fn tool_change(&self, e: &mut Emitter, c: &ToolChange) -> io::Result<()> {
        if c.previous.is_some() {
            e.rapid_z(c.tp.safe_z)?;
        }
        self.load_tool(e, c)?;
        if c.previous.is_none() {
            self.first_tool_ready(e, c)?;
        }
        Ok(())
    }
    /// The words that change the tool, once clear of the work: `T n M6` by default.
    fn load_tool(&self, e: &mut Emitter, c: &ToolChange) -> io::Result<()> {
        rs274::m6(e, c.op)
    }
    /// After the first tool is in: up to safe Z, now that the tool length is known.
    fn first_tool_ready(&self, e: &mut Emitter, c: &ToolChange) -> io::Result<()> {
        e.rapid_z(c.tp.safe_z)
    }
    /// Spindle on at the operation's speed (`new_tool`: right after a tool change).
    fn spindle(
        &self,
        e: &mut Emitter,
        _tp: &Toolpath,
        op: &Operation,
        _new_tool: bool,
    ) -> io::Result<()> {
        rs274::spindle_on(e, op)
    }
    /// A drilled hole; by default the plain moves of the cycle.
    fn drill(&self, e: &mut Emitter, d: &Drill) -> io::Result<()> {
        for m in d.moves(e.pos) {
            self.write_move(e, &m)?;
        }
        Ok(())
    }
    /// A pause of `seconds` (s): `G4 P` by default.
    fn dwell(&self, e: &mut Emitter, seconds: f64) -> io::Result<()> {
        let mut s = String::from("G4 P");
        format::push_decimal(&mut s, seconds, 4);
        e.block(&s)
    }
    /// G61 exact stop or G64 continuous path, as the control can say it.
    fn path_mode(&self, e: &mut Emitter, mode: PathMode) -> io::Result<()>;
    /// G41/G42 with the D register, or G40; controls without it refuse the program.
    fn comp(&self, _e: &mut Emitter, _comp: Option<(CompSide, u32)>) -> io::Result<()> {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "this control has no cutter radius compensation: post without --comp",
        ))
    }
    /// Up to safe Z, then the control's end of program ([`Post::end_program`]).
    fn epilogue(&self, e: &mut Emitter, tp: &Toolpath, _opts: &PostOptions) -> io::Result<()> {
        e.rapid_z(tp.safe_z)?;
        self.end_program(e)
    }
    /// The words that end the program, at safe Z: `M5 M30` by default.
    fn end_program(&self, e: &mut Emitter) -> io::Result<()> {
        rs274::end(e)
    }

    /// One move of any kind.
    fn write_move(&self, e: &mut Emitter, m: &Move) -> io::Result<()> {
        match m {
            Move::Drill(d) => self.drill(e, d),
            Move::Dwell(s) => self.dwell(e, *s),
            Move::PathMode(p) => self.path_mode(e, *p),
            Move::Comp(c) => self.comp(e, *c),
            m => e.motion(m),
        }
    }
}

/// The post for a dialect with its default set-up.
pub fn post_for(dialect: PostDialect) -> Box<dyn Post> {
    match dialect {
        PostDialect::Grbl => Box::new(grbl::Grbl),
        PostDialect::LinuxCnc => Box::new(linuxcnc::LinuxCnc),
        PostDialect::Sinumerik => Box::new(sinumerik::Sinumerik::default()),
        PostDialect::Legacy2006 => Box::new(legacy::Legacy),
    }
}

/// The format a dialect writes with when nothing else is asked for.
pub fn default_format(dialect: PostDialect) -> Format {
    post_for(dialect).default_format()
}

/// Writes the whole program in the dialect's default format.
pub fn write_program(tp: &Toolpath, opts: &PostOptions, out: &mut dyn Write) -> io::Result<()> {
    let post = post_for(opts.dialect);
    write_program_with(tp, opts, &post.default_format(), post.as_ref(), out)
}

/// Writes the whole program with `post` in `format`.
pub fn write_program_with(
    tp: &Toolpath,
    opts: &PostOptions,
    format: &Format,
    post: &dyn Post,
    out: &mut dyn Write,
) -> io::Result<()> {
    post.check_format(format)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))?;
    let mut e = Emitter::new(out, *format, post.words());
    post.prologue(&mut e, tp, opts)?;
    let mut current: Option<u32> = None;
    for op in &tp.operations {
        let new_tool = current != Some(op.tool_number);
        if new_tool {
            e.comment(&format!(
                "operation: {} with T{} {}",
                op.name, op.tool_number, op.tool
            ))?;
            let change = ToolChange {
                tp,
                opts,
                op,
                previous: current,
            };
            post.tool_change(&mut e, &change)?;
            current = Some(op.tool_number);
        } else {
            e.comment(&format!("operation: {}", op.name))?;
        }
        post.spindle(&mut e, tp, op, new_tool)?;
        for m in &op.moves {
            post.write_move(&mut e, m)?;
        }
    }
    post.epilogue(&mut e, tp, opts)
}

/// The program as a string, in the dialect's default format. Writing to memory cannot fail,
/// so an error is the post refusing the toolpath (e.g. cutter compensation on grbl).
pub fn program_text(tp: &Toolpath, opts: &PostOptions) -> io::Result<String> {
    let mut buf = Vec::new();
    write_program(tp, opts, &mut buf)?;
    // The writers emit only ASCII; a lossy conversion keeps that promise without a panic.
    Ok(String::from_utf8_lossy(&buf).into_owned())
}

/// The program as a string in `format`; an error names the format option the dialect
/// cannot express.
pub fn program_text_with(
    tp: &Toolpath,
    opts: &PostOptions,
    format: &Format,
) -> Result<String, String> {
    let post = post_for(opts.dialect);
    let mut buf = Vec::new();
    write_program_with(tp, opts, format, post.as_ref(), &mut buf).map_err(|e| e.to_string())?;
    String::from_utf8(buf).map_err(|e| e.to_string())
}

/// The header every rs274-family dialect (LinuxCNC, grbl) writes.
/// The title and every setting as comments: how the program was made.
pub(crate) fn title_and_settings(e: &mut Emitter, opts: &PostOptions) -> io::Result<()> {
    e.comment(&opts.title)?;
    for (k, v) in &opts.settings {
        e.comment(&format!("{k} = {v}"))?;
    }
    Ok(())
}

pub(crate) fn header_comments(
    e: &mut Emitter,
    opts: &PostOptions,
    format: &Format,
) -> io::Result<()> {
    title_and_settings(e, opts)?;
    e.comment(&format!(
        "post = {:?}, M6 allowed = {}",
        opts.dialect, opts.allow_m6
    ))?;
    if *format != Format::DEFAULT {
        e.comment(&format!("format = {format:?}"))?;
    }
    Ok(())
}
