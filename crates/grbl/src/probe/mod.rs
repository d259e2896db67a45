//! Probing routines as UGS and CNCjs run them: each is a short sequence of firmware lines
//! (G38.2 touches, retracts, `G10 L20` / `G43.1` to set what was measured) over a
//! [`ProbeLink`], which the console's raw [`Sender`] and any [`Machine`] (through
//! [`Machine::raw_line`]) both are.
//!
//! - [`run_z_plate`]: a touch plate on the stock; the stock's top becomes Z0.
//! - [`run_corner`]: the top, then the left (−X) and front (−Y) sides of the stock (or of a
//!   corner plate); the corner becomes X0 Y0 Z0.
//! - [`run_tool_setter`]: the tool length setter; with a reference measurement the
//!   difference becomes the tool length offset (`G43.1 Z…`).
//!
//! Every position is taken from grbl's `[PRB:x,y,z:1]` (the contact, machine coordinates),
//! never from where the machine braked to a stop after it; offsets are then set with
//! `G10 L20` after an exact `G53` move to a known height above the contact, so G92 and a
//! tool length offset in force are accounted for by the firmware itself. The touches run in
//! `G21 G91`; the units and distance mode `$G` reported before are restored at the end.
//! Positions are read in mm: a board with `$13=1` (report inches) is not supported.

mod checks;
mod session;

use crate::messages;
use crate::sender::{Sender, SenderOptions};
use checks::{check_positive, check_range, check_thickness, check_wcs, fits, MAX_TRAVEL};
use oficina_machine::{Machine, RawReply};
use session::{num, Session};
use std::fmt;
use std::time::Duration;

/// A link a probe routine runs over: one line at a time, each waited for.
pub trait ProbeLink {
    /// Sends `line` and waits for its `ok` / `error:N`, at least `patience` when the link
    /// lets the caller choose (a probing move answers only once it has stopped). The lines
    /// that came before the acknowledgement (`[PRB:…]`, `ALARM:N`, `[G54:…]`) are in the
    /// reply, an error explained in words.
    fn line(&mut self, line: &str, patience: Duration) -> Result<RawReply, String>;

    /// The longest this link waits for a reply, if the caller cannot choose: a probing
    /// move that may take longer is refused before it is sent (the firmware would still
    /// be moving when the link gave up).
    fn longest_wait(&self) -> Option<Duration> {
        None
    }
}

impl ProbeLink for Sender {
    fn line(&mut self, line: &str, patience: Duration) -> Result<RawReply, String> {
        let keep = self.options.reply_timeout;
        self.options.reply_timeout = keep.max(patience);
        let reply = self.command(line);
        self.options.reply_timeout = keep;
        let reply = reply.map_err(|e| e.to_string())?;
        Ok(RawReply {
            lines: reply.lines,
            error: reply.error.map(messages::describe_error),
        })
    }
}

/// Any machine, through [`Machine::raw_line`] (the virtual machine refuses, having no
/// firmware language).
impl<M: Machine + ?Sized> ProbeLink for M {
    fn line(&mut self, line: &str, _patience: Duration) -> Result<RawReply, String> {
        self.raw_line(line).map_err(|e| e.to_string())
    }

    /// A [`crate::GrblDevice`] waits for each reply as long as its
    /// `SenderOptions::reply_timeout`, which the trait does not show: its default.
    fn longest_wait(&self) -> Option<Duration> {
        Some(SenderOptions::default().reply_timeout)
    }
}

/// How a surface is found: a fast search, a back-off, a slow touch (the one measured).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approach {
    /// Longest search, mm.
    pub travel: f64,
    /// Feed of the search, mm/min.
    pub feed: f64,
    /// Feed of the measured touch, mm/min.
    pub slow_feed: f64,
    /// Back-off after the search and after the touch, mm (the touch searches twice this).
    pub retract: f64,
}

impl Default for Approach {
    fn default() -> Self {
        Approach {
            travel: 30.0,
            feed: 100.0,
            slow_feed: 25.0,
            retract: 2.0,
        }
    }
}

/// [`run_z_plate`]'s parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZPlate {
    /// Plate thickness, mm (0: touch the stock itself).
    pub thickness: f64,
    /// Which coordinate system to set: 1 = G54 … 6 = G59.
    pub wcs: u8,
    /// How the plate is found.
    pub approach: Approach,
}

/// [`run_corner`]'s parameters: the front-left (−X, −Y) corner of the stock, the tool
/// starting above the top (or the plate) within `reach` of both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Thickness of the plate the top is touched on, mm (0: the stock's top itself).
    pub thickness: f64,
    /// From the X and Y faces touched to the corner, mm: 0 when they are the stock's own
    /// sides, a corner plate's lip thickness when they are its outer faces.
    pub side_offset: [f64; 2],
    /// Diameter of the tool (or probe tip) whose side touches, mm.
    pub tool_diameter: f64,
    /// How far the tool moves out (−X, then −Y) from where it starts before going down
    /// beside the side, mm: more than the distance to the side plus the tool's radius.
    pub reach: f64,
    /// How far below the touched top the sides are touched, mm.
    pub depth: f64,
    /// Which coordinate system to set: 1 = G54 … 6 = G59.
    pub wcs: u8,
    /// How each surface is found (`travel` is the top's search; the sides are searched
    /// over `reach`).
    pub approach: Approach,
}

/// [`run_tool_setter`]'s parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolSetter {
    /// Machine X, Y of the setter: the tool goes there at `safe_z` first; `None`: probe
    /// where the tool is.
    pub at: Option<[f64; 2]>,
    /// Machine Z to travel at when going to the setter.
    pub safe_z: f64,
    /// Machine Z the reference tool touched the setter at: given, the difference becomes
    /// the tool length offset (`G43.1 Z…`).
    pub reference: Option<f64>,
    /// How the setter is found.
    pub approach: Approach,
}

/// What a routine measured and set.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeResult {
    /// Machine positions of the measured touches, in order: the top; then the X and Y
    /// sides for a corner.
    pub contacts: Vec<[f64; 3]>,
    /// The coordinate system set (1 = G54 … 6 = G59).
    pub wcs: u8,
    /// Its offset as the firmware holds it afterwards (read back with `$#`), machine mm.
    pub offset: [f64; 3],
}

/// What [`run_tool_setter`] measured and set.
#[derive(Clone, Debug, PartialEq)]
pub struct SetterResult {
    /// Machine position of the measured touch.
    pub contact: [f64; 3],
    /// Its machine Z: the reference for later tools when this is the reference tool.
    pub measured_z: f64,
    /// The tool length offset applied (measured − reference), with a reference.
    pub tool_offset: Option<f64>,
}

/// Why a routine stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum ProbeError {
    /// A parameter is refused; nothing was sent.
    Input(String),
    /// The probe was already closed when a touch began (ALARM:4); the machine is in alarm.
    AlreadyTriggered(String),
    /// A touch reached its end without contact (ALARM:5); the machine is in alarm.
    NoContact(String),
    /// The firmware refused a line, or the link failed.
    Firmware(String),
}

impl fmt::Display for ProbeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ProbeError::Input(m)
            | ProbeError::AlreadyTriggered(m)
            | ProbeError::NoContact(m)
            | ProbeError::Firmware(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ProbeError {}

/// Touches the plate lying on the stock and sets the chosen coordinate system's Z so the
/// stock's top is Z0. Starts where the tool is, above the plate.
pub fn run_z_plate<L: ProbeLink + ?Sized>(
    link: &mut L,
    p: &ZPlate,
) -> Result<ProbeResult, ProbeError> {
    check_thickness(p.thickness)?;
    check_wcs(p.wcs)?;
    p.approach.check()?;
    p.approach.fits(link)?;
    Session::begin(link)?.run(|s| {
        let top = s.touch('Z', -1.0, &p.approach)?;
        let r = p.approach.retract;
        s.send(&format!("G90 G53 G0 Z{}", num(top[2] + r)))?;
        s.send(&format!("G10 L20 P{} Z{}", p.wcs, num(p.thickness + r)))?;
        let offset = s.finish(p.wcs)?;
        Ok(ProbeResult {
            contacts: vec![top],
            wcs: p.wcs,
            offset,
        })
    })
}

/// Touches the top, then the −X and −Y sides, and sets the chosen coordinate system so the
/// stock's front-left top corner is X0 Y0 Z0 (the tool's radius and the side offsets
/// accounted for). Nothing is set unless all three touches succeed.
pub fn run_corner<L: ProbeLink + ?Sized>(
    link: &mut L,
    p: &Corner,
) -> Result<ProbeResult, ProbeError> {
    check_thickness(p.thickness)?;
    check_wcs(p.wcs)?;
    p.approach.check()?;
    let radius = p.tool_diameter / 2.0;
    check_range("tool diameter", p.tool_diameter, 0.0, 100.0)?;
    for (what, v) in [
        ("X side offset", p.side_offset[0]),
        ("Y side offset", p.side_offset[1]),
    ] {
        check_range(what, v, -MAX_TRAVEL, MAX_TRAVEL)?;
    }
    check_positive("depth", p.depth)?;
    check_positive("reach", p.reach)?;
    if p.reach <= radius + p.approach.retract {
        return Err(ProbeError::Input(format!(
            "reach {} mm must exceed the tool's radius plus the retract ({} mm) to clear the side",
            p.reach,
            radius + p.approach.retract
        )));
    }
    let side = Approach {
        travel: p.reach,
        ..p.approach
    };
    let down = p.approach.retract + p.depth;
    p.approach.fits(link)?;
    side.fits(link)?;
    fits(link, down, p.approach.feed)?;
    Session::begin(link)?.run(|s| corner(s, p, &side, down))
}

/// [`run_corner`]'s lines, once checked.
fn corner<L: ProbeLink + ?Sized>(
    s: &mut Session<'_, L>,
    p: &Corner,
    side: &Approach,
    down: f64,
) -> Result<ProbeResult, ProbeError> {
    let radius = p.tool_diameter / 2.0;
    let top = s.touch('Z', -1.0, &p.approach)?;
    let r = p.approach.retract;
    let above = top[2] + r;
    s.send(&format!("G90 G53 G0 Z{}", num(above)))?;
    let mut sides = [[0.0; 3]; 2];
    for (i, axis) in ['X', 'Y'].into_iter().enumerate() {
        s.send(&format!("G91 G0 {axis}-{}", num(p.reach)))?;
        // Down beside the side as a probing move: if the tool is still above the work it
        // touches instead of plunging into it.
        let (at, touched) = s.probe(
            &format!("G38.3 Z-{} F{}", num(down), num(p.approach.feed)),
            down,
            p.approach.feed,
        )?;
        if touched {
            return Err(ProbeError::Input(format!(
                "after moving {} mm in −{axis} the tool still touched the work at machine Z {:.3} going down: start nearer the corner or give a longer reach",
                p.reach, at[2]
            )));
        }
        sides[i] = s.touch(axis, 1.0, side)?;
        s.send(&format!("G91 G0 {axis}-{}", num(r)))?;
        s.send(&format!("G0 Z{}", num(down)))?;
        s.send(&format!("G90 G53 G0 X{} Y{}", num(top[0]), num(top[1])))?;
    }
    // Back where the top was touched, `r` above it: that point's work coordinates.
    let corner = [
        sides[0][0] + radius + p.side_offset[0],
        sides[1][1] + radius + p.side_offset[1],
    ];
    s.send(&format!(
        "G10 L20 P{} X{} Y{} Z{}",
        p.wcs,
        num(top[0] - corner[0]),
        num(top[1] - corner[1]),
        num(p.thickness + r)
    ))?;
    let offset = s.finish(p.wcs)?;
    Ok(ProbeResult {
        contacts: vec![top, sides[0], sides[1]],
        wcs: p.wcs,
        offset,
    })
}

/// Touches the tool length setter (going there first at a safe height when its position
/// is given) and gives the machine Z of the touch; with a reference, applies the tool
/// length offset `measured − reference` with `G43.1`.
pub fn run_tool_setter<L: ProbeLink + ?Sized>(
    link: &mut L,
    p: &ToolSetter,
) -> Result<SetterResult, ProbeError> {
    p.approach.check()?;
    check_range("safe Z", p.safe_z, -10_000.0, 10_000.0)?;
    if let Some([x, y]) = p.at {
        check_range("setter X", x, -10_000.0, 10_000.0)?;
        check_range("setter Y", y, -10_000.0, 10_000.0)?;
    }
    if let Some(z) = p.reference {
        check_range("reference Z", z, -10_000.0, 10_000.0)?;
    }
    p.approach.fits(link)?;
    Session::begin(link)?.run(|s| {
        if let Some([x, y]) = p.at {
            s.send(&format!("G90 G53 G0 Z{}", num(p.safe_z)))?;
            s.send(&format!("G53 G0 X{} Y{}", num(x), num(y)))?;
        }
        let contact = s.touch('Z', -1.0, &p.approach)?;
        s.send(&format!(
            "G90 G53 G0 Z{}",
            num(contact[2] + p.approach.retract)
        ))?;
        let tool_offset = p.reference.map(|r| contact[2] - r);
        if let Some(tlo) = tool_offset {
            s.send(&format!("G43.1 Z{}", num(tlo)))?;
        }
        s.finish(1)?;
        Ok(SetterResult {
            contact,
            measured_z: contact[2],
            tool_offset,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::session::parse_prb;
    use super::*;

    /// A firmware that answers from a script: each line gets the next reply whose prefix
    /// matches, else a plain `ok`.
    struct Scripted {
        sent: Vec<String>,
        replies: Vec<(&'static str, Vec<&'static str>)>,
    }

    impl ProbeLink for Scripted {
        fn line(&mut self, line: &str, _: Duration) -> Result<RawReply, String> {
            self.sent.push(line.to_string());
            let at = self.replies.iter().position(|(p, _)| line.starts_with(p));
            let lines = match at {
                Some(i) => self.replies.remove(i).1,
                None => Vec::new(),
            };
            Ok(RawReply {
                lines: lines.into_iter().map(String::from).collect(),
                error: None,
            })
        }
    }

    fn firmware(replies: Vec<(&'static str, Vec<&'static str>)>) -> Scripted {
        let mut all = vec![("$G", vec!["[GC:G0 G54 G17 G20 G90 G94 M5 M9 T0 F0 S0]"])];
        all.extend(replies);
        all.push((
            "$#",
            vec!["[G54:1.000,2.000,-30.000]", "[G55:0.000,0.000,0.000]"],
        ));
        Scripted {
            sent: Vec::new(),
            replies: all,
        }
    }

    fn plate() -> ZPlate {
        ZPlate {
            thickness: 10.0,
            wcs: 1,
            approach: Approach::default(),
        }
    }

    #[test]
    fn z_plate_sends_the_sequence_and_sets_from_the_slow_touch() {
        let mut fw = firmware(vec![
            ("G91 G38.2 Z-30", vec!["[PRB:5.000,6.000,-20.100:1]"]),
            ("G38.2 Z-4", vec!["[PRB:5.000,6.000,-20.000:1]"]),
        ]);
        let r = run_z_plate(&mut fw, &plate()).unwrap();
        assert_eq!(
            fw.sent,
            [
                "$G",
                "G21 G91",
                "G91 G38.2 Z-30 F100",
                "G0 Z2",
                "G38.2 Z-4 F25",
                "G90 G53 G0 Z-18",
                "G10 L20 P1 Z12",
                "G20 G90",
                "G4 P0",
                "$#"
            ]
        );
        assert_eq!(r.contacts, vec![[5.0, 6.0, -20.0]]);
        assert_eq!(r.offset, [1.0, 2.0, -30.0]);
    }

    #[test]
    fn alarms_and_refusals_are_explained() {
        let mut fw = firmware(vec![(
            "G91 G38.2",
            vec!["ALARM:5", "[PRB:0.000,0.000,0.000:0]"],
        )]);
        let e = run_z_plate(&mut fw, &plate()).unwrap_err();
        assert!(matches!(e, ProbeError::NoContact(_)), "{e}");
        assert!(
            e.to_string().contains("no contact") && e.to_string().contains("$X"),
            "{e}"
        );
        // Nothing is set after a failed touch.
        assert!(
            !fw.sent.iter().any(|l| l.starts_with("G10")),
            "{:?}",
            fw.sent
        );
        let mut fw = firmware(vec![("G91 G38.2", vec!["ALARM:4"])]);
        let e = run_z_plate(&mut fw, &plate()).unwrap_err();
        assert!(matches!(e, ProbeError::AlreadyTriggered(_)), "{e}");
        assert!(e.to_string().contains("already closed"), "{e}");
        for bad in [
            ZPlate {
                thickness: -1.0,
                ..plate()
            },
            ZPlate {
                thickness: f64::NAN,
                ..plate()
            },
            ZPlate { wcs: 7, ..plate() },
            ZPlate {
                approach: Approach {
                    travel: 1500.0,
                    ..Approach::default()
                },
                ..plate()
            },
            ZPlate {
                approach: Approach {
                    feed: 0.0,
                    ..Approach::default()
                },
                ..plate()
            },
            ZPlate {
                approach: Approach {
                    retract: f64::INFINITY,
                    ..Approach::default()
                },
                ..plate()
            },
        ] {
            let mut fw = firmware(vec![]);
            let e = run_z_plate(&mut fw, &bad).unwrap_err();
            assert!(matches!(e, ProbeError::Input(_)), "{bad:?}: {e}");
            assert!(fw.sent.is_empty(), "nothing sent for {bad:?}");
        }
        assert!(run_z_plate(
            &mut firmware(vec![]),
            &ZPlate {
                thickness: -1.0,
                ..plate()
            }
        )
        .unwrap_err()
        .to_string()
        .contains("negative"));
    }

    #[test]
    fn corner_refuses_a_start_still_over_the_work() {
        let mut fw = firmware(vec![
            ("G91 G38.2 Z", vec!["[PRB:5.000,6.000,-20.100:1]"]),
            ("G38.2 Z", vec!["[PRB:5.000,6.000,-20.000:1]"]),
            ("G38.3", vec!["[PRB:-5.000,6.000,-19.000:1]"]),
        ]);
        let p = Corner {
            thickness: 0.0,
            side_offset: [0.0; 2],
            tool_diameter: 6.0,
            reach: 10.0,
            depth: 3.0,
            wcs: 1,
            approach: Approach::default(),
        };
        let e = run_corner(&mut fw, &p).unwrap_err();
        assert!(e.to_string().contains("still touched"), "{e}");
        // The units and distance mode are given back; nothing was set.
        assert_eq!(fw.sent.last().unwrap(), "G20 G90");
        assert!(
            !fw.sent.iter().any(|l| l.starts_with("G10")),
            "{:?}",
            fw.sent
        );
        let e = run_corner(&mut firmware(vec![]), &Corner { reach: 4.0, ..p }).unwrap_err();
        assert!(e.to_string().contains("reach"), "{e}");
    }

    /// A link that waits at most 30 s, as a `GrblDevice` behind the `Machine` trait.
    struct Impatient(Scripted);

    impl ProbeLink for Impatient {
        fn line(&mut self, line: &str, p: Duration) -> Result<RawReply, String> {
            self.0.line(line, p)
        }
        fn longest_wait(&self) -> Option<Duration> {
            Some(Duration::from_secs(30))
        }
    }

    #[test]
    fn a_search_longer_than_the_link_waits_is_refused_before_it_moves() {
        let slow = ZPlate {
            approach: Approach {
                travel: 60.0,
                ..Approach::default()
            },
            ..plate()
        };
        let mut link = Impatient(firmware(vec![]));
        let e = run_z_plate(&mut link, &slow).unwrap_err();
        assert!(e.to_string().contains("may take 36 s"), "{e}");
        assert!(link.0.sent.is_empty(), "{:?}", link.0.sent);
        assert!(
            !link.0.sent.iter().any(|l| l.contains("G38")),
            "{:?}",
            link.0.sent
        );
        // The default search (30 mm at 100 mm/min, 18 s) fits.
        let mut link = Impatient(firmware(vec![
            ("G91 G38.2 Z-30", vec!["[PRB:5.000,6.000,-20.100:1]"]),
            ("G38.2 Z-4", vec!["[PRB:5.000,6.000,-20.000:1]"]),
        ]));
        assert!(run_z_plate(&mut link, &plate()).is_ok());
    }

    #[test]
    fn numbers_and_reports() {
        assert_eq!(num(2.0), "2");
        assert_eq!(num(-18.00004), "-18");
        assert_eq!(num(-0.00001), "0");
        assert_eq!(num(12.34567), "12.3457");
        assert_eq!(
            parse_prb("[PRB:1.000,-2.500,3.000:1]"),
            Some(([1.0, -2.5, 3.0], true))
        );
        assert_eq!(
            parse_prb("[PRB:1,2,3,45:0]"),
            Some(([1.0, 2.0, 3.0], false))
        );
        assert_eq!(parse_prb("[PRB:1,2:1]"), None);
        assert_eq!(parse_prb("[G54:1,2,3]"), None);
    }
}
