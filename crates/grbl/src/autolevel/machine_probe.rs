//! Probing a height map over a [`ProbeLink`] (any `Machine` through its `raw_line`, or the
//! console's `Sender`): for each point a rapid to the clearance, across to X Y, `G38.2`
//! down to the deepest allowed Z, and back up. grbl reports the contact as `[PRB:x,y,z:1]`
//! in machine coordinates before its `ok`; the work Z is that minus the work offset, read
//! once from `$G` (which system) and `$#` (its offset, G92 and the tool length offset).

use super::grid::SurfaceProbe;
use crate::messages::describe_alarm;
use crate::probe::{fits, parse_prb, parse_xyz, ProbeLink};
use crate::response::Response;
use std::time::Duration;

/// How each point is probed, in work coordinates (mm, mm/min).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeMotion {
    /// Work Z each probe starts from and retracts to: above the stock everywhere.
    pub clearance: f64,
    /// Lowest work Z a probe may reach before it counts as no contact.
    pub max_depth: f64,
    /// Probing feed, mm/min.
    pub feed: f64,
}

impl Default for ProbeMotion {
    fn default() -> Self {
        ProbeMotion {
            clearance: 3.0,
            max_depth: -3.0,
            feed: 60.0,
        }
    }
}

/// A grbl link as a [`SurfaceProbe`].
pub struct MachineProbe<'m, L: ProbeLink + ?Sized> {
    link: &'m mut L,
    motion: ProbeMotion,
    /// Work offset of Z (machine Z of work zero), mm.
    wco_z: f64,
    /// The work coordinate system in force (`G54` …).
    pub wcs: String,
}

impl<'m, L: ProbeLink + ?Sized> MachineProbe<'m, L> {
    /// Reads the work offset from the idle firmware and checks the motion can complete.
    pub fn new(link: &'m mut L, motion: ProbeMotion) -> Result<MachineProbe<'m, L>, String> {
        if !(motion.clearance.is_finite()
            && motion.max_depth.is_finite()
            && motion.clearance > motion.max_depth)
        {
            return Err(format!(
                "probe clearance Z{} must be above the deepest probe Z{}",
                motion.clearance, motion.max_depth
            ));
        }
        if !(motion.feed.is_finite() && motion.feed > 0.0) {
            return Err(format!(
                "probe feed {}: must be more than 0 mm/min",
                motion.feed
            ));
        }
        // Each probe must end within the link's reply wait.
        fits(&*link, motion.clearance - motion.max_depth, motion.feed)
            .map_err(|e| e.to_string())?;
        let mut p = MachineProbe {
            link,
            motion,
            wco_z: 0.0,
            wcs: String::new(),
        };
        // Positions are read in mm: $13=1 (report inches) would scale every one.
        let settings = p.send("$$")?;
        if settings.iter().any(|l| {
            matches!(Response::parse(l), Response::Setting { number: 13, value } if value.trim() == "1")
        }) {
            return Err("the firmware reports inches ($13=1): set $13=0 to probe a height map".into());
        }
        let state = p.send("$G")?;
        p.wcs = parser_wcs(&state).ok_or("`$G` did not say which coordinate system is in force")?;
        let offsets = p.send("$#")?;
        p.wco_z = work_offset_z(&offsets, &p.wcs).ok_or("`$#` did not report the work offsets")?;
        Ok(p)
    }

    /// One line to the firmware; an alarm or an error reply is an error naming the line.
    fn send(&mut self, line: &str) -> Result<Vec<String>, String> {
        let seconds = (self.motion.clearance - self.motion.max_depth) / self.motion.feed * 60.0;
        let reply = self
            .link
            .line(line, Duration::from_secs_f64(seconds * 1.5 + 10.0))
            .map_err(|e| format!("`{line}`: {e}"))?;
        for l in &reply.lines {
            if let Response::Alarm(code) = Response::parse(l) {
                return Err(format!(
                    "alarm during `{line}`: {}; unlock with $X once the cause is fixed",
                    describe_alarm(code)
                ));
            }
        }
        match reply.error {
            Some(e) => Err(format!("`{line}`: {e}")),
            None => Ok(reply.lines),
        }
    }
}

impl<L: ProbeLink + ?Sized> SurfaceProbe for MachineProbe<'_, L> {
    fn probe_at(&mut self, x: f64, y: f64) -> Result<f64, String> {
        let m = self.motion;
        // G38.2 moves in the modal units and distance mode: say them.
        self.send(&format!("G21G90G0Z{:.4}", m.clearance))?;
        self.send(&format!("G0X{x:.4}Y{y:.4}"))?;
        let probe = format!("G38.2Z{:.4}F{:.1}", m.max_depth, m.feed);
        let reply = self.send(&probe)?;
        let contact = match reply.iter().find_map(|l| parse_prb(l)) {
            Some((at, true)) => at[2],
            _ => {
                return Err(format!(
                    "`{probe}`: no contact down to Z{} ({}): check the probe and the depth",
                    m.max_depth,
                    reply.join(" ")
                ))
            }
        };
        self.send(&format!("G0Z{:.4}", m.clearance))?;
        Ok(contact - self.wco_z)
    }
}

/// `G54` … `G59` from `$G`'s `[GC:G0 G54 G17 …]`.
fn parser_wcs(lines: &[String]) -> Option<String> {
    lines.iter().find_map(|l| match Response::parse(l) {
        Response::ParserState(s) => s
            .split_whitespace()
            .find(|w| w.starts_with("G5") && w.len() == 3 && *w != "G53")
            .map(str::to_string),
        _ => None,
    })
}

/// Work offset of Z from `$#`: the active system's Z + G92's Z + the tool length offset.
fn work_offset_z(lines: &[String], wcs: &str) -> Option<f64> {
    let (mut sys, mut g92, mut tlo) = (None, 0.0, 0.0);
    for l in lines {
        if let Response::Feedback { tag, value } = Response::parse(l) {
            match tag.as_str() {
                t if t == wcs => sys = parse_xyz(&value).map(|p| p[2]),
                "G92" => g92 = parse_xyz(&value).map_or(0.0, |p| p[2]),
                "TLO" => tlo = value.trim().parse().unwrap_or(0.0),
                _ => {}
            }
        }
    }
    Some(sys? + g92 + tlo)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn replies_are_read() {
        let gc = lines(&["[GC:G0 G55 G17 G21 G90 G94 M5 M9 T0 F0 S0]"]);
        assert_eq!(parser_wcs(&gc).as_deref(), Some("G55"));
        let offsets = lines(&[
            "[G54:0.000,0.000,0.000]",
            "[G55:10.000,20.000,-30.500]",
            "[G92:0.000,0.000,1.000]",
            "[TLO:0.250]",
            "[PRB:0.000,0.000,0.000:0]",
        ]);
        assert_eq!(work_offset_z(&offsets, "G55"), Some(-29.25));
        assert_eq!(work_offset_z(&offsets, "G57"), None);
    }

    /// A firmware answering from a script: each line the reply of the first entry its
    /// start matches, else a plain `ok`.
    struct Scripted {
        sent: Vec<String>,
        replies: Vec<(&'static str, Vec<&'static str>)>,
    }

    impl ProbeLink for Scripted {
        fn line(&mut self, line: &str, _: Duration) -> Result<oficina_machine::RawReply, String> {
            self.sent.push(line.to_string());
            let lines = self
                .replies
                .iter()
                .find(|(p, _)| line.starts_with(p))
                .map(|(_, r)| r.iter().map(|s| s.to_string()).collect())
                .unwrap_or_default();
            Ok(oficina_machine::RawReply { lines, error: None })
        }

        fn longest_wait(&self) -> Option<Duration> {
            Some(Duration::from_secs(30))
        }
    }

    fn board(settings: &'static str, prb: &'static str) -> Scripted {
        Scripted {
            sent: Vec::new(),
            replies: vec![
                ("$$", vec![settings]),
                ("$G", vec!["[GC:G0 G55 G17 G21 G90 G94 M5 M9 T0 F0 S0]"]),
                ("$#", vec!["[G55:10.000,20.000,-30.000]", "[TLO:0.500]"]),
                ("G38.2", vec![prb]),
            ],
        }
    }

    #[test]
    fn a_point_is_probed_from_the_clearance_in_work_coordinates() {
        let mut fw = board("$13=0", "[PRB:15.000,27.000,-29.300:1]");
        let mut p = MachineProbe::new(&mut fw, ProbeMotion::default()).unwrap();
        assert_eq!(p.wcs, "G55");
        // Machine −29.3 less the work offset −30 + 0.5 (TLO): 0.2.
        let z = p.probe_at(5.0, 7.0).unwrap();
        assert!((z - 0.2).abs() < 1e-12, "{z}");
        assert_eq!(
            fw.sent[3..],
            [
                "G21G90G0Z3.0000",
                "G0X5.0000Y7.0000",
                "G38.2Z-3.0000F60.0",
                "G0Z3.0000"
            ]
        );
        let mut miss = board("$13=0", "[PRB:15.000,27.000,-33.000:0]");
        let e = MachineProbe::new(&mut miss, ProbeMotion::default())
            .unwrap()
            .probe_at(5.0, 7.0)
            .unwrap_err();
        assert!(e.contains("no contact down to Z-3"), "{e}");
        let mut inches = board("$13=1", "");
        let e = MachineProbe::new(&mut inches, ProbeMotion::default())
            .err()
            .unwrap();
        assert!(e.contains("$13=0"), "{e}");
        let slow = ProbeMotion {
            feed: 5.0,
            ..ProbeMotion::default()
        };
        let e = MachineProbe::new(&mut board("$13=0", ""), slow)
            .err()
            .unwrap();
        assert!(e.contains("raise the feed"), "{e}");
    }
}
