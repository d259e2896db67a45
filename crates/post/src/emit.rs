//! The text writer every dialect prints through: block numbers, comments, modal motion
//! words, axes that changed, feeds. It tracks where the tool is so arcs can write their
//! centres relative to the start and unchanged axes can be left out.

use crate::format::Format;
use oficina_cam::Move;
use std::io::{self, Write};

/// The words a dialect uses for the four motions and how it gives arc centres.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MotionWords {
    /// Rapid move word (G0).
    pub rapid: &'static str,
    /// Straight feed move word (G1).
    pub line: &'static str,
    /// Clockwise arc word (G2).
    pub cw: &'static str,
    /// Counter-clockwise arc word (G3).
    pub ccw: &'static str,
    /// I J are the centre itself (seed 002) rather than centre − start.
    pub absolute_centres: bool,
    /// The control takes F words (the legacy one runs at its configured feed).
    pub feed_words: bool,
    /// Feeds are written as whole mm/min (or inch/min) numbers.
    pub integer_feed: bool,
}

/// Writes blocks to the output and remembers the modal state and tool position.
pub struct Emitter<'a> {
    out: &'a mut dyn Write,
    /// How numbers and lines look.
    pub format: Format,
    /// The dialect's motion words.
    pub words: MotionWords,
    line: String,
    /// The motion word in force, "" when unknown (after a block that could change it).
    last_motion: &'static str,
    /// Where the tool is, mm (NaN = unknown).
    pub pos: [f64; 3],
    /// Feed in force, program units per minute.
    feed: f64,
    next_n: Option<u32>,
}

impl<'a> Emitter<'a> {
    /// A writer to `out` with nothing yet in force.
    pub fn new(out: &'a mut dyn Write, format: Format, words: MotionWords) -> Emitter<'a> {
        Emitter {
            out,
            format,
            words,
            line: String::new(),
            last_motion: "",
            pos: [f64::NAN; 3],
            feed: f64::NAN,
            next_n: format.line_numbers.map(|n| n.start),
        }
    }

    /// One block as written, with its number when the format numbers blocks. A block that
    /// holds a motion word of its own leaves the modal motion unknown.
    pub fn block(&mut self, s: &str) -> io::Result<()> {
        let motion = [self.words.rapid, self.words.line];
        if !motion.iter().any(|w| s.starts_with(&format!("{w} "))) {
            self.last_motion = "";
        }
        self.write_block(s)
    }

    fn write_block(&mut self, s: &str) -> io::Result<()> {
        let s = s.trim_start();
        match self.next_n.as_mut() {
            Some(n) => {
                let step = self.format.line_numbers.map_or(1, |l| l.step);
                let this = *n;
                *n = n.saturating_add(step);
                writeln!(self.out, "N{this} {s}")
            }
            None => writeln!(self.out, "{s}"),
        }
    }

    /// A line written as is, without a block number (`%` tape marks).
    pub fn raw(&mut self, s: &str) -> io::Result<()> {
        writeln!(self.out, "{s}")
    }

    /// A comment line; parentheses inside would end it early.
    pub fn comment(&mut self, s: &str) -> io::Result<()> {
        let clean: String = s
            .chars()
            .map(|c| match c {
                '(' => '[',
                ')' => ']',
                c => c,
            })
            .filter(|c| c.is_ascii() && *c != '\n' && *c != '\r')
            .collect();
        writeln!(self.out, "({clean})")
    }

    /// A number in this format, for blocks a dialect writes itself.
    pub fn len_word(&self, letter: char, mm: f64) -> String {
        let mut s = String::new();
        self.format
            .push_word(&mut s, letter, self.format.length(mm));
        s
    }

    /// Forget the modal motion (after a block of the dialect's own that may have set it).
    pub fn forget_motion(&mut self) {
        self.last_motion = "";
    }

    /// A rapid to `z` (mm) at the current X Y.
    pub fn rapid_z(&mut self, z: f64) -> io::Result<()> {
        let to = [self.pos[0], self.pos[1], z];
        self.motion(&Move::Rapid { to })
    }

    /// Rapid, line or arc. (Drills, dwells and path modes are the dialect's.)
    pub fn motion(&mut self, m: &Move) -> io::Result<()> {
        self.line.clear();
        let before = self.last_motion;
        match *m {
            Move::Rapid { to } => {
                self.word_motion(self.words.rapid);
                self.axes(to, false);
            }
            Move::Line { to, feed } => {
                self.word_motion(self.words.line);
                self.axes(to, false);
                self.feed_word(feed);
            }
            Move::Arc {
                to,
                center,
                ccw,
                feed,
            } => {
                let (i, j) = if self.words.absolute_centres {
                    (center[0], center[1])
                } else {
                    (center[0] - self.pos[0], center[1] - self.pos[1])
                };
                // An arc always writes its word and its end in the plane: a full circle has
                // no other sign, and a reader sees the arc's direction on its own line.
                self.last_motion = "";
                self.word_motion(if ccw { self.words.ccw } else { self.words.cw });
                self.axes(to, true);
                let f = self.format;
                f.push_word(&mut self.line, 'I', f.length(i));
                f.push_word(&mut self.line, 'J', f.length(j));
                self.feed_word(feed);
            }
            Move::Dwell(_) | Move::Drill(_) | Move::PathMode(_) | Move::Comp(_) => {
                return Err(io::Error::other(
                    "internal: the dialect writes dwells, drills and path modes",
                ))
            }
        }
        let bare = [self.words.rapid, self.words.line];
        if self.line.is_empty() || bare.contains(&self.line.trim()) {
            // Nothing moved: the G word was not written, so it is not modal yet.
            self.last_motion = before;
            return Ok(());
        }
        let line = std::mem::take(&mut self.line);
        let r = self.write_block(&line);
        self.line = line;
        r
    }

    fn word_motion(&mut self, g: &'static str) {
        if self.last_motion != g || !self.format.modal {
            self.line.push_str(g);
            self.last_motion = g;
        }
    }

    /// The axes that print differently from where the tool is (all of them when modal
    /// suppression is off; X and Y always for arcs).
    fn axes(&mut self, to: [f64; 3], arc: bool) {
        let f = self.format;
        for (k, axis) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if to[k].is_nan() {
                continue;
            }
            let changed = !f.same_printed(f.length(to[k]), f.length(self.pos[k]));
            if changed || !f.modal || (arc && k < 2) {
                f.push_word(&mut self.line, axis, f.length(to[k]));
                self.pos[k] = to[k];
            }
        }
    }

    fn feed_word(&mut self, feed_mm_s: f64) {
        if !self.words.feed_words {
            return;
        }
        let mut f = self.format.length(feed_mm_s * 60.0);
        if self.words.integer_feed {
            f = f.round().max(1.0);
        }
        if !crate::format::Format::DEFAULT.same_printed(f, self.feed) || !self.format.modal {
            self.line.push_str(" F");
            crate::format::push_decimal(&mut self.line, f, 4);
            self.feed = f;
        }
    }

    /// Records the feed in force, program units per minute (after a block that set it outside
    /// [`Emitter::motion`]).
    pub fn set_feed_written(&mut self, f: f64) {
        self.feed = f;
    }
}
