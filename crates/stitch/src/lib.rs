//! Embroidery (seed 000): a `Drawing` becomes a [`StitchPlan`] of running, satin and tatami
//! fill stitches; the plan is checked against the hoops, summed up in a production sheet,
//! sewn on the needle-synchronised table, and written and read as the machines' files (Tajima
//! DST, Melco EXP, Brother PES/PEC, Janome JEF, Pfaff VP3, Singer XXX, Barudan U01).
//! Designs made in Ink/Stitch keep their authors' parameters (`inkstitch:` attributes, read by
//! [`read_inkstitch`], sewn by [`generate_inkstitch`]).

mod alter;
mod format;
mod generate;
mod hoop;
mod inkstitch;
mod lettering;
mod plan;
mod preview;
mod seedlink;
mod sheet;
mod speed;
mod table;

pub use alter::{alter, link, Alteration, MirrorAxis};
pub use format::seed_ram::{SeedHeader, STEP as SEED_STEP};
pub use format::{read_bor, write_bor, Format, FormatError, Op, Rec};
pub use generate::{
    generate, generate_inkstitch, running, GenerateError, Generated, Params, ShapeKind,
    MAX_STITCHES, TIE,
};
pub use hoop::{smallest_hoop, Hoop, HoopError, HoopShape, CLEARANCE, HOOPS};
pub use inkstitch::{
    read_inkstitch, ElementParams, FillMethod, Inkstitch, InkstitchError, Placement, ReverseRails,
    RippleParams, StrokeMethod, Ties, FILL_STITCH_LENGTH, NAMESPACE as INKSTITCH_NAMESPACE,
};
pub use lettering::{
    append, letter, Align, Font, Glyph, GlyphElement, Layout, Lettered, LetteringError, Placed,
    Text, Trim, DEFAULT_FONT, FONTS, PX_PER_MM,
};
pub use plan::{ColorBlock, Counts, Kind, Stitch, StitchPlan, Thread};
pub use preview::{preview_svg, render, render_png, Render, RenderError, RenderOptions};
pub use seedlink::{
    open_seed_port, send, transmission, Received, SeedMachine, Stored, SEED_BAUD, SEED_RAM_BYTES,
};
pub use sheet::{duration, sheet, Sheet, ThreadLine};
pub use speed::{sections, sew_at_speed, speed_code, Section, SpeedCode, MAX_SEWN, SPEED_CODES};
pub use table::{run, Fault, HeadSpeed, Pauses, RunReport, Table};
