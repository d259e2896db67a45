//! Work coordinate systems as the page shows them: G54…G59, which one is active, G92, the
//! tool length offset and the last probe. Real firmware's are read from its `$#` and `$G`
//! replies (classified by grbl's own [`oficina_grbl::Response`] parser); the virtual
//! machine's are kept by the session.

use oficina_grbl::Response;
use serde::Serialize;

/// The six work coordinate systems' names, in grbl's order (`G10 L20 P1` is G54).
pub const SYSTEMS: [&str; 6] = ["G54", "G55", "G56", "G57", "G58", "G59"];

/// The last probe cycle's result (`[PRB:x,y,z:1]`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Probe {
    /// Where the probe stopped, machine mm.
    pub pos: [f64; 3],
    /// True when it touched (`:1`); false after a probe that found nothing.
    pub touched: bool,
}

/// A machine's work offsets.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct WorkOffsets {
    /// G54…G59 origins, machine mm.
    pub systems: [[f64; 3]; 6],
    /// The active system: 0 = G54 … 5 = G59.
    pub active: usize,
    /// The G92 offset, mm.
    pub g92: [f64; 3],
    /// The tool length offset, mm.
    pub tlo: f64,
    /// The last probe, when the machine reported one.
    pub probe: Option<Probe>,
    /// The table was read from the machine (false until a `$#` reply was seen on firmware).
    pub known: bool,
}

/// The index (0 = G54) of a system named `G54`…`G59` (any case).
pub fn system_index(name: &str) -> Option<usize> {
    SYSTEMS
        .iter()
        .position(|s| s.eq_ignore_ascii_case(name.trim()))
}

fn numbers(value: &str) -> Vec<f64> {
    value
        .split(',')
        .map_while(|v| v.trim().parse::<f64>().ok())
        .collect()
}

use oficina_grbl::report_xyz as xyz;

impl WorkOffsets {
    /// Reads the lines of a `$#` or `$G` reply (any other line is left alone); true when
    /// one of them said something about the offsets.
    pub fn read_reply(&mut self, lines: &[String]) -> bool {
        let mut seen = false;
        for line in lines {
            match Response::parse(line) {
                Response::ParserState(state) => {
                    if let Some(i) = state.split_whitespace().find_map(system_index) {
                        self.active = i;
                        seen = true;
                    }
                }
                Response::Feedback { tag, value } => seen |= self.read_feedback(&tag, &value),
                _ => {}
            }
        }
        seen
    }

    fn read_feedback(&mut self, tag: &str, value: &str) -> bool {
        if let Some(i) = system_index(tag) {
            if let Some(p) = xyz(value) {
                self.systems[i] = p;
                self.known = true;
                return true;
            }
        }
        match tag {
            "G92" => xyz(value).map(|p| self.g92 = p).is_some(),
            // grbl: `[TLO:z]`; grblHAL may list one value per axis: Z's is the last.
            "TLO" => numbers(value).last().map(|z| self.tlo = *z).is_some(),
            "PRB" => oficina_grbl::probe_report(value)
                .map(|(pos, touched)| self.probe = Some(Probe { pos, touched }))
                .is_some(),
            _ => false,
        }
    }

    /// The work position of `machine_pos` in the active system (G92 included).
    pub fn work_position(&self, machine_pos: [f64; 3]) -> [f64; 3] {
        let o = self.systems[self.active];
        std::array::from_fn(|i| machine_pos[i] - o[i] - self.g92[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &str) -> Vec<String> {
        text.lines().map(String::from).collect()
    }

    #[test]
    fn a_grbl_offsets_reply_fills_the_table() {
        let mut o = WorkOffsets::default();
        let reply = lines(
            "[G54:1.000,2.000,-3.500]\n[G55:10.000,0.000,0.000]\n[G56:0.000,0.000,0.000]\n\
             [G57:0.000,0.000,0.000]\n[G58:0.000,0.000,0.000]\n[G59:0.000,0.000,-7.000]\n\
             [G28:0.000,0.000,0.000]\n[G30:0.000,0.000,0.000]\n[G92:0.000,0.500,0.000]\n\
             [TLO:1.250]\n[PRB:5.000,6.000,-2.000:1]",
        );
        assert!(o.read_reply(&reply));
        assert!(o.known);
        assert_eq!(o.systems[0], [1.0, 2.0, -3.5]);
        assert_eq!(o.systems[1], [10.0, 0.0, 0.0]);
        assert_eq!(o.systems[5], [0.0, 0.0, -7.0]);
        assert_eq!(o.g92, [0.0, 0.5, 0.0]);
        assert_eq!(o.tlo, 1.25);
        assert_eq!(
            o.probe,
            Some(Probe {
                pos: [5.0, 6.0, -2.0],
                touched: true
            })
        );
        assert_eq!(o.work_position([11.0, 2.5, -3.5]), [10.0, 0.0, 0.0]);
    }

    #[test]
    fn the_parser_state_names_the_active_system_and_odd_lines_are_ignored() {
        let mut o = WorkOffsets::default();
        assert!(o.read_reply(&lines("[GC:G0 G56 G17 G21 G90 G94 M5 M9 T0 F0 S0]\nok")));
        assert_eq!(o.active, 2);
        assert!(!o.known, "no offsets were listed");
        // grblHAL's multi-axis TLO and extra systems; broken lines change nothing.
        assert!(o.read_reply(&lines("[TLO:0.000,0.000,2.500]\n[G59.1:1,2,3]")));
        assert_eq!(o.tlo, 2.5);
        assert!(!o.read_reply(&lines("[G54:x,y]\n[PRB:1,2]\n[MSG:hello]\n$#\n")));
        assert_eq!(o.systems, [[0.0; 3]; 6]);
        assert_eq!(system_index("g59"), Some(5));
        assert_eq!(system_index("G53"), None);
    }
}
