//! Probing on a machine through [`Machine::raw_line`]: for each point a rapid to the
//! clearance, across to X Y, `G38.2` down to the deepest allowed Z, and back up. grbl
//! reports the contact as `[PRB:x,y,z:1]` in machine coordinates before its `ok`; the work
//! Z is that minus the work offset, read once from `$G` (which system) and `$#` (its
//! offset, G92 and the tool length offset).

use super::grid::SurfaceProbe;
use crate::response::Response;
use oficina_machine::Machine;

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

/// A machine (grbl firmware) as a [`SurfaceProbe`].
pub struct MachineProbe<'m> {
    machine: &'m mut dyn Machine,
    motion: ProbeMotion,
    /// Work offset of Z (machine Z of work zero), mm.
    wco_z: f64,
    /// Millimetres per unit the firmware reports positions in ($13).
    report_mm: f64,
    /// The work coordinate system in force (`G54` …).
    pub wcs: String,
}

/// Longest a single probe may take, seconds: the sender waits 30 s for a reply.
const MAX_PROBE_SECONDS: f64 = 25.0;

impl<'m> MachineProbe<'m> {
    /// Reads the work offset from the idle machine and checks the motion can complete.
    pub fn new(
        machine: &'m mut dyn Machine,
        motion: ProbeMotion,
    ) -> Result<MachineProbe<'m>, String> {
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
        let seconds = (motion.clearance - motion.max_depth) / motion.feed * 60.0;
        if seconds > MAX_PROBE_SECONDS {
            return Err(format!(
                "a probe from Z{} to Z{} at F{} takes {seconds:.0} s, more than the {MAX_PROBE_SECONDS:.0} s a reply may take: raise the feed or lower the clearance",
                motion.clearance, motion.max_depth, motion.feed
            ));
        }
        // $13=1: grbl reports positions in inches.
        let report_mm = match machine.firmware_settings() {
            Ok(s) if s.iter().any(|&(n, v)| n == 13 && v == 1.0) => 25.4,
            _ => 1.0,
        };
        let mut p = MachineProbe {
            machine,
            motion,
            wco_z: 0.0,
            report_mm,
            wcs: String::new(),
        };
        let state = p.send("$G")?;
        p.wcs = parser_wcs(&state).ok_or("`$G` did not say which coordinate system is in force")?;
        let offsets = p.send("$#")?;
        p.wco_z = work_offset_z(&offsets, &p.wcs).ok_or("`$#` did not report the work offsets")?
            * report_mm;
        Ok(p)
    }

    /// One line to the firmware; an error reply is an error naming the line.
    fn send(&mut self, line: &str) -> Result<Vec<String>, String> {
        let reply = self
            .machine
            .raw_line(line)
            .map_err(|e| format!("`{line}`: {e}"))?;
        match reply.error {
            Some(e) => Err(format!("`{line}`: {e}")),
            None => Ok(reply.lines),
        }
    }
}

impl SurfaceProbe for MachineProbe<'_> {
    fn probe_at(&mut self, x: f64, y: f64) -> Result<f64, String> {
        let m = self.motion;
        // G38.2 moves in the modal units and distance mode: say them.
        self.send(&format!("G21G90G0Z{:.4}", m.clearance))?;
        self.send(&format!("G0X{x:.4}Y{y:.4}"))?;
        let reply = self.send(&format!("G38.2Z{:.4}F{:.1}", m.max_depth, m.feed))?;
        let contact = probe_contact(&reply).ok_or_else(|| {
            format!(
                "no contact down to Z{} (grbl said: {}); clear the alarm with $X, check the probe and the depth",
                m.max_depth,
                reply.join(" ")
            )
        })?;
        self.send(&format!("G0Z{:.4}", m.clearance))?;
        Ok(contact * self.report_mm - self.wco_z)
    }
}

/// The machine Z of a successful probe in `[PRB:x,y,z:1]`.
fn probe_contact(lines: &[String]) -> Option<f64> {
    lines.iter().rev().find_map(|l| match Response::parse(l) {
        Response::Feedback { tag, value } if tag == "PRB" => {
            let (pos, ok) = value.rsplit_once(':')?;
            if ok.trim() != "1" {
                return None;
            }
            pos.split(',').nth(2)?.trim().parse().ok()
        }
        _ => None,
    })
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
            let z = || {
                value
                    .split(',')
                    .nth(2)
                    .and_then(|v| v.trim().parse::<f64>().ok())
            };
            match tag.as_str() {
                t if t == wcs => sys = z(),
                "G92" => g92 = z().unwrap_or(0.0),
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
        assert_eq!(
            probe_contact(&lines(&["[PRB:1.000,2.000,-3.250:1]"])),
            Some(-3.25)
        );
        assert_eq!(
            probe_contact(&lines(&["ALARM:5", "[PRB:1.000,2.000,-3.250:0]"])),
            None
        );
        assert_eq!(probe_contact(&[]), None);
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
}
