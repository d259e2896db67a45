//! `StitchPlan`: what the machine sews, in colour blocks. Coordinates are absolute, in mm,
//! y up, with the hoop centre at the origin (the files' origin).

/// What one entry of a block does at its point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The needle goes down here: a sewn stitch from the previous point.
    Stitch,
    /// The hoop moves here with the needle stopped up (a long point of the seed).
    Jump,
    /// The thread is cut at the current point (the point repeats the previous one).
    Trim,
    /// The machine stops for the operator (appliqué, a manual thread change) at this point.
    Stop,
}

/// One entry of a plan: a point and what happens there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stitch {
    /// X, mm.
    pub x: f64,
    /// Y, mm (y up).
    pub y: f64,
    /// Stitch, jump, trim or stop.
    pub kind: Kind,
}

impl Stitch {
    /// An entry of `kind` at (`x`, `y`) mm.
    pub fn new(x: f64, y: f64, kind: Kind) -> Stitch {
        Stitch { x, y, kind }
    }
}

/// A thread: its colour and, where a file or design names it, a name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Thread {
    /// Red, green, blue.
    pub rgb: [u8; 3],
    /// The thread's name; empty when none is known.
    pub name: String,
}

impl Thread {
    /// An unnamed thread of this colour.
    pub fn rgb(r: u8, g: u8, b: u8) -> Thread {
        Thread {
            rgb: [r, g, b],
            name: String::new(),
        }
    }

    /// `#rrggbb`.
    pub fn hex(&self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.rgb[0], self.rgb[1], self.rgb[2])
    }
}

/// The stitches sewn with one thread; a colour change separates consecutive blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorBlock {
    /// The thread sewn.
    pub thread: Thread,
    /// Its entries in sewing order.
    pub stitches: Vec<Stitch>,
}

/// A whole design: colour blocks in sewing order; the end is implicit after the last block.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StitchPlan {
    /// The design's name.
    pub name: String,
    /// Colour blocks in sewing order.
    pub blocks: Vec<ColorBlock>,
}

/// Counts and lengths of a plan (the independent figures of the production sheet).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Counts {
    /// Sewn stitches.
    pub stitches: usize,
    /// Jumps.
    pub jumps: usize,
    /// Trims.
    pub trims: usize,
    /// Stops.
    pub stops: usize,
    /// Colour changes (one fewer than the blocks).
    pub color_changes: usize,
    /// Per block: (sewn stitches, thread length in mm along the sewn stitches).
    pub per_block: Vec<(usize, f64)>,
    /// Length of the jumps (hoop travel with the needle up), mm.
    pub jump_length: f64,
}

impl StitchPlan {
    /// Every entry in sewing order with the index of its block.
    pub fn entries(&self) -> impl Iterator<Item = (usize, &Stitch)> {
        self.blocks
            .iter()
            .enumerate()
            .flat_map(|(b, block)| block.stitches.iter().map(move |s| (b, s)))
    }

    /// No stitch in any block.
    pub fn is_empty(&self) -> bool {
        self.blocks.iter().all(|b| b.stitches.is_empty())
    }

    /// Stitch, jump, trim, stop and colour-change counts and the thread length per block. A
    /// stitch's thread is the distance from the previous point (the origin before the first).
    pub fn counts(&self) -> Counts {
        let mut c = Counts {
            color_changes: self.blocks.len().saturating_sub(1),
            per_block: vec![(0, 0.0); self.blocks.len()],
            ..Counts::default()
        };
        let (mut px, mut py) = (0.0, 0.0);
        for (b, s) in self.entries() {
            let d = (s.x - px).hypot(s.y - py);
            match s.kind {
                Kind::Stitch => {
                    c.stitches += 1;
                    c.per_block[b].0 += 1;
                    c.per_block[b].1 += d;
                }
                Kind::Jump => {
                    c.jumps += 1;
                    c.jump_length += d;
                }
                Kind::Trim => c.trims += 1,
                Kind::Stop => c.stops += 1,
            }
            (px, py) = (s.x, s.y);
        }
        c
    }

    /// [min x, min y, max x, max y] over every point (jumps included, as the hoop goes
    /// there), or None for an empty plan.
    pub fn bounds(&self) -> Option<[f64; 4]> {
        self.entries().fold(None, |acc, (_, s)| {
            Some(match acc {
                None => [s.x, s.y, s.x, s.y],
                Some([a, b, c, d]) => [a.min(s.x), b.min(s.y), c.max(s.x), d.max(s.y)],
            })
        })
    }

    /// Moved by (dx, dy) mm (the seed's shift of the Zero-Peça).
    pub fn translated(&self, dx: f64, dy: f64) -> StitchPlan {
        let mut p = self.clone();
        for b in &mut p.blocks {
            for s in &mut b.stitches {
                s.x += dx;
                s.y += dy;
            }
        }
        p
    }
}
