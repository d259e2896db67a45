//! grbl 1.1 status reports: `<Run|MPos:1.000,2.000,0.000|Bf:15,128|FS:500,0|Ov:100,100,100>`.
//! Every field of interface.md is parsed; unknown fields are kept, not rejected, because
//! grbl forks (grblHAL, FluidNC) add their own.

/// The machine state of a status report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GrblState {
    /// At rest.
    Idle,
    /// Running a program.
    Run,
    /// `Hold:0` hold complete, `Hold:1` still decelerating.
    Hold(u8),
    /// Jogging.
    Jog,
    /// In alarm: unlock or reset.
    Alarm,
    /// `Door:0` closed and ready, `Door:1` stopped and ajar, `Door:2` opened while moving
    /// (retracting), `Door:3` closed and restoring.
    Door(u8),
    /// `$C` check mode: lines parsed, nothing moves.
    Check,
    /// Homing.
    Home,
    /// Asleep (`$SLP`).
    Sleep,
    /// A state name this version does not know (forks add e.g. `Tool`).
    Other(String),
}

impl GrblState {
    /// Reads a state name, with its `:n` sub-state.
    pub fn parse(s: &str) -> GrblState {
        let (name, sub) = match s.split_once(':') {
            Some((n, x)) => (n, x.parse::<u8>().ok()),
            None => (s, None),
        };
        match name {
            "Idle" => GrblState::Idle,
            "Run" => GrblState::Run,
            "Hold" => GrblState::Hold(sub.unwrap_or(0)),
            "Jog" => GrblState::Jog,
            "Alarm" => GrblState::Alarm,
            "Door" => GrblState::Door(sub.unwrap_or(0)),
            "Check" => GrblState::Check,
            "Home" => GrblState::Home,
            "Sleep" => GrblState::Sleep,
            _ => GrblState::Other(s.to_string()),
        }
    }

    /// The state as grbl writes it (`Hold:0`).
    pub fn name(&self) -> String {
        match self {
            GrblState::Hold(n) => format!("Hold:{n}"),
            GrblState::Door(n) => format!("Door:{n}"),
            GrblState::Other(s) => s.clone(),
            other => format!("{other:?}"),
        }
    }

    /// Motion may still be happening (the machine is not at rest).
    pub fn is_moving(&self) -> bool {
        matches!(
            self,
            GrblState::Run
                | GrblState::Jog
                | GrblState::Home
                | GrblState::Hold(1)
                | GrblState::Door(2)
                | GrblState::Door(3)
        )
    }
}

/// One parsed status report. Positions are in the report units (mm unless `$13=1`).
#[derive(Clone, Debug, PartialEq)]
pub struct StatusReport {
    /// The machine state.
    pub state: GrblState,
    /// Machine position (`MPos`).
    pub mpos: Option<Vec<f64>>,
    /// Work position (`WPos`).
    pub wpos: Option<Vec<f64>>,
    /// Work coordinate offset (`WCO`), sent every few reports.
    pub wco: Option<Vec<f64>>,
    /// (free planner blocks, free RX bytes)
    pub buffer: Option<(u32, u32)>,
    /// Source line number (`Ln`).
    pub line: Option<u32>,
    /// Current feed (`F` or `FS`).
    pub feed: Option<f64>,
    /// Current spindle speed (`FS`).
    pub spindle: Option<f64>,
    /// Input pins that are triggered, e.g. "XYZPDHRS".
    pub pins: Option<String>,
    /// (feed %, rapid %, spindle %)
    pub overrides: Option<(u32, u32, u32)>,
    /// Accessory state, e.g. "SFM" (spindle CW, flood, mist) or "C" (spindle CCW).
    pub accessories: Option<String>,
    /// Fields this parser does not know, as found.
    pub extra: Vec<String>,
}

impl StatusReport {
    /// Parses the text between (and including) `<` and `>`.
    pub fn parse(line: &str) -> Result<StatusReport, String> {
        let inner = line
            .trim()
            .strip_prefix('<')
            .and_then(|l| l.strip_suffix('>'))
            .ok_or_else(|| format!("status report not enclosed in <>: {line:?}"))?;
        let mut fields = inner.split('|');
        let state = GrblState::parse(fields.next().unwrap_or(""));
        let mut st = StatusReport {
            state,
            mpos: None,
            wpos: None,
            wco: None,
            buffer: None,
            line: None,
            feed: None,
            spindle: None,
            pins: None,
            overrides: None,
            accessories: None,
            extra: Vec::new(),
        };
        for field in fields {
            let (key, value) = field.split_once(':').unwrap_or((field, ""));
            let bad = || format!("status field {key} has a bad value {value:?}");
            match key {
                "MPos" => st.mpos = Some(numbers(value).ok_or_else(bad)?),
                "WPos" => st.wpos = Some(numbers(value).ok_or_else(bad)?),
                "WCO" => st.wco = Some(numbers(value).ok_or_else(bad)?),
                "Bf" => {
                    let v = numbers(value).filter(|v| v.len() == 2).ok_or_else(bad)?;
                    st.buffer = Some((v[0] as u32, v[1] as u32));
                }
                "Ln" => st.line = Some(value.parse().map_err(|_| bad())?),
                "F" => st.feed = Some(value.parse().map_err(|_| bad())?),
                "FS" => {
                    let v = numbers(value).filter(|v| v.len() == 2).ok_or_else(bad)?;
                    st.feed = Some(v[0]);
                    st.spindle = Some(v[1]);
                }
                "Pn" => st.pins = Some(value.to_string()),
                "Ov" => {
                    let v = numbers(value).filter(|v| v.len() == 3).ok_or_else(bad)?;
                    st.overrides = Some((v[0] as u32, v[1] as u32, v[2] as u32));
                }
                "A" => st.accessories = Some(value.to_string()),
                _ => st.extra.push(field.to_string()),
            }
        }
        Ok(st)
    }

    /// Work position: reported directly, or machine position less the work offset.
    pub fn work_position(&self, last_wco: Option<&[f64]>) -> Option<Vec<f64>> {
        if let Some(w) = &self.wpos {
            return Some(w.clone());
        }
        let m = self.mpos.as_ref()?;
        let wco = self.wco.as_deref().or(last_wco)?;
        Some(m.iter().zip(wco).map(|(m, o)| m - o).collect())
    }

    /// Machine position: reported directly, or work position plus the work offset.
    pub fn machine_position(&self, last_wco: Option<&[f64]>) -> Option<Vec<f64>> {
        if let Some(m) = &self.mpos {
            return Some(m.clone());
        }
        let w = self.wpos.as_ref()?;
        let wco = self.wco.as_deref().or(last_wco)?;
        Some(w.iter().zip(wco).map(|(w, o)| w + o).collect())
    }
}

fn numbers(s: &str) -> Option<Vec<f64>> {
    s.split(',')
        .map(|x| x.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_four_axis_reports_as_grblhal_prints_them() {
        // grblHAL built with N_AXIS = 4 prints X, Y, Z, A in MPos/WPos and WCO.
        let s = StatusReport::parse(
            "<Run|MPos:10.000,0.000,19.500,370.000|FS:600,12000|WCO:10.000,225.000,-80.000,0.000>",
        )
        .unwrap();
        assert_eq!(s.mpos, Some(vec![10.0, 0.0, 19.5, 370.0]));
        assert_eq!(s.work_position(None), Some(vec![0.0, -225.0, 99.5, 370.0]));
        let w = StatusReport::parse("<Idle|WPos:1.000,2.000,3.000,-45.500|FS:0,0>").unwrap();
        assert_eq!(
            w.machine_position(Some(&[1.0, 1.0, 1.0, 0.0])),
            Some(vec![2.0, 3.0, 4.0, -45.5])
        );
    }

    #[test]
    fn parses_every_field() {
        let s = StatusReport::parse(
            "<Hold:1|MPos:1.000,-2.500,3.250|Bf:12,77|Ln:99|FS:500,12000|WCO:1.000,1.000,0.000|Pn:XZP|Ov:120,50,100|A:SFM|Foo:1>",
        )
        .unwrap();
        assert_eq!(s.state, GrblState::Hold(1));
        assert_eq!(s.mpos, Some(vec![1.0, -2.5, 3.25]));
        assert_eq!(s.buffer, Some((12, 77)));
        assert_eq!(s.line, Some(99));
        assert_eq!(s.feed, Some(500.0));
        assert_eq!(s.spindle, Some(12000.0));
        assert_eq!(s.pins.as_deref(), Some("XZP"));
        assert_eq!(s.overrides, Some((120, 50, 100)));
        assert_eq!(s.accessories.as_deref(), Some("SFM"));
        assert_eq!(s.extra, vec!["Foo:1".to_string()]);
        assert_eq!(s.work_position(None), Some(vec![0.0, -3.5, 3.25]));
    }

    #[test]
    fn substates_and_wpos() {
        let s = StatusReport::parse("<Door:2|WPos:0.000,0.000,1.000|F:300>").unwrap();
        assert_eq!(s.state, GrblState::Door(2));
        assert_eq!(s.feed, Some(300.0));
        assert_eq!(
            s.machine_position(Some(&[1.0, 2.0, 3.0])),
            Some(vec![1.0, 2.0, 4.0])
        );
        assert_eq!(
            StatusReport::parse("<Tool|MPos:0,0,0>").unwrap().state,
            GrblState::Other("Tool".into())
        );
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert!(StatusReport::parse("<Idle|MPos:1,x,3>").is_err());
        assert!(StatusReport::parse("Idle|MPos:1,2,3").is_err());
        assert!(StatusReport::parse("<Idle|Bf:15>").is_err());
        assert!(StatusReport::parse("<Idle|MPos:nan,1,2>").is_err());
    }
}
