//! One line from the firmware, classified. grbl answers every line it receives with exactly
//! one `ok` or `error:N`; everything else (status, feedback, alarms, the welcome banner) is
//! unsolicited or a reply to a `$` query and must never be counted as an acknowledgement.

use crate::status::StatusReport;

/// One line from the firmware, classified.
#[derive(Clone, Debug, PartialEq)]
pub enum Response {
    /// `ok`.
    Ok,
    /// `error:N`.
    Error(u8),
    /// `ALARM:N`.
    Alarm(u8),
    /// `<Idle|MPos:…>`.
    Status(StatusReport),
    /// The firmware (re)started; everything in flight is gone. grbl: `Grbl 1.1h ['$' for
    /// help]`; grblHAL: `GrblHAL 1.1f ['$' or '$HELP' for help]`; FluidNC: `Grbl 3.7.12
    /// [FluidNC v3.7.12 (wifi) '$' for help]`.
    Welcome {
        /// `Grbl`, `GrblHAL` or `FluidNC`.
        firmware: String,
        /// The version, e.g. `1.1h`.
        version: String,
    },
    /// `[MSG:…]`
    Message(String),
    /// `[GC:G0 G54 G17 …]`, reply to `$G`.
    ParserState(String),
    /// `[VER:1.1h.20190825:]`
    Version(String),
    /// `[OPT:V,15,128]`: option letters, planner blocks, RX buffer bytes.
    Options {
        /// Option letters.
        codes: String,
        /// Planner blocks.
        blocks: Option<u32>,
        /// RX buffer bytes.
        rx_bytes: Option<u32>,
    },
    /// `[G54:0.000,0.000,0.000]`, `[PRB:…:1]`, `[TLO:…]`, `[HLP:…]`, `[echo:…]` and others.
    Feedback {
        /// The tag before the colon.
        tag: String,
        /// The rest.
        value: String,
    },
    /// `$110=500.000`
    Setting {
        /// Setting number.
        number: u16,
        /// Its value as sent.
        value: String,
    },
    /// `$N0=G20`
    StartupLine {
        /// Startup line number.
        index: u8,
        /// Its text.
        line: String,
    },
    /// `>G54G20:ok`: a startup line ran.
    StartupResult(String),
    /// A line that matches nothing above: kept verbatim so the user sees it.
    Unknown(String),
}

/// `x,y,z[,a…]`, the value of a `[G54:…]`, `[G92:…]` or `[PRB:…]` report → its first three
/// numbers (grblHAL lists its other axes after them).
pub fn report_xyz(value: &str) -> Option<[f64; 3]> {
    let v: Vec<f64> = value
        .split(',')
        .map(|x| x.trim().parse().ok())
        .collect::<Option<_>>()?;
    (v.len() >= 3 && v.iter().all(|x| x.is_finite())).then(|| [v[0], v[1], v[2]])
}

/// The value of a `[PRB:x,y,z:flag]` report → where the probe stopped (machine mm) and
/// whether it touched (`flag` 1).
pub fn probe_report(value: &str) -> Option<([f64; 3], bool)> {
    let (xyz, flag) = value.rsplit_once(':')?;
    Some((report_xyz(xyz)?, flag.trim() == "1"))
}

impl Response {
    /// Classifies one line (without its line ending). Never panics on any input.
    pub fn parse(raw: &str) -> Response {
        let line = raw.trim_matches(|c: char| c.is_whitespace() || c == '\0');
        if line == "ok" {
            return Response::Ok;
        }
        if let Some(n) = line.strip_prefix("error:") {
            if let Ok(code) = n.trim().parse() {
                return Response::Error(code);
            }
        }
        if let Some(n) = line.strip_prefix("ALARM:") {
            if let Ok(code) = n.trim().parse() {
                return Response::Alarm(code);
            }
        }
        if line.starts_with('<') && line.ends_with('>') {
            return match StatusReport::parse(line) {
                Ok(s) => Response::Status(s),
                Err(_) => Response::Unknown(line.to_string()),
            };
        }
        if let Some(w) = welcome(line) {
            return w;
        }
        if let Some(inner) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            let (tag, value) = inner.split_once(':').unwrap_or((inner, ""));
            return match tag {
                "MSG" => Response::Message(value.to_string()),
                "GC" => Response::ParserState(value.to_string()),
                "VER" => Response::Version(value.to_string()),
                "OPT" => {
                    let mut parts = value.split(',');
                    let codes = parts.next().unwrap_or("").to_string();
                    let blocks = parts.next().and_then(|b| b.trim().parse().ok());
                    let rx_bytes = parts.next().and_then(|b| b.trim().parse().ok());
                    Response::Options {
                        codes,
                        blocks,
                        rx_bytes,
                    }
                }
                _ => Response::Feedback {
                    tag: tag.to_string(),
                    value: value.to_string(),
                },
            };
        }
        if let Some(rest) = line.strip_prefix("$N") {
            if let Some((i, l)) = rest.split_once('=') {
                if let Ok(index) = i.parse() {
                    return Response::StartupLine {
                        index,
                        line: l.to_string(),
                    };
                }
            }
        }
        if let Some(rest) = line.strip_prefix('$') {
            if let Some((n, v)) = rest.split_once('=') {
                if let Ok(number) = n.parse() {
                    return Response::Setting {
                        number,
                        value: v.to_string(),
                    };
                }
            }
        }
        if let Some(rest) = line.strip_prefix('>') {
            return Response::StartupResult(rest.to_string());
        }
        Response::Unknown(line.to_string())
    }

    /// `ok` and `error:N` are the only answers that free RX buffer space.
    pub fn is_ack(&self) -> bool {
        matches!(self, Response::Ok | Response::Error(_))
    }
}

/// A reset banner: a firmware name, a version that starts with a digit, then `[…help]`.
/// The version rule keeps a message such as `Grbl is busy` from passing for a reset.
fn welcome(line: &str) -> Option<Response> {
    let (name, rest) = line.split_once(' ')?;
    if !matches!(name, "Grbl" | "GrblHAL") {
        return None;
    }
    let (version, tail) = rest.split_once(' ').unwrap_or((rest, ""));
    if !version.starts_with(|c: char| c.is_ascii_digit()) || !tail.starts_with('[') {
        return None;
    }
    let firmware = if tail.starts_with("[FluidNC") {
        "FluidNC"
    } else {
        name
    };
    Some(Response::Welcome {
        firmware: firmware.to_string(),
        version: version.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classifies_lines() {
        assert_eq!(Response::parse("ok\r"), Response::Ok);
        assert_eq!(Response::parse("error:22"), Response::Error(22));
        assert_eq!(Response::parse("ALARM:3"), Response::Alarm(3));
        assert_eq!(
            Response::parse("Grbl 1.1h ['$' for help]"),
            Response::Welcome {
                firmware: "Grbl".into(),
                version: "1.1h".into()
            }
        );
        assert_eq!(
            Response::parse("[OPT:V,15,128]"),
            Response::Options {
                codes: "V".into(),
                blocks: Some(15),
                rx_bytes: Some(128)
            }
        );
        assert_eq!(
            Response::parse("$110=500.000"),
            Response::Setting {
                number: 110,
                value: "500.000".into()
            }
        );
        assert_eq!(
            Response::parse("$N0=G20"),
            Response::StartupLine {
                index: 0,
                line: "G20".into()
            }
        );
        assert_eq!(
            Response::parse("[G54:1.000,2.000,0.000]"),
            Response::Feedback {
                tag: "G54".into(),
                value: "1.000,2.000,0.000".into()
            }
        );
        assert!(matches!(
            Response::parse("<Idle|MPos:0,0,0>"),
            Response::Status(_)
        ));
    }

    #[test]
    fn every_family_banner_is_a_reset() {
        // grblHAL's and FluidNC's banners as their firmware prints them (grblHAL's from
        // its Simulator, FluidNC's from its serial log).
        for (line, firmware, version) in [
            ("GrblHAL 1.1f ['$' or '$HELP' for help]", "GrblHAL", "1.1f"),
            (
                "Grbl 3.7.12 [FluidNC v3.7.12 (wifi) '$' for help]",
                "FluidNC",
                "3.7.12",
            ),
            ("Grbl 1.1f ['$' for help]", "Grbl", "1.1f"),
        ] {
            assert_eq!(
                Response::parse(line),
                Response::Welcome {
                    firmware: firmware.into(),
                    version: version.into()
                },
                "{line}"
            );
        }
        for not in [
            "Grbl is busy",
            "GrblHAL",
            "Grbl ",
            "GrblHALx 1.1 [x]",
            "Grbl 1.1h",
        ] {
            assert!(
                !matches!(Response::parse(not), Response::Welcome { .. }),
                "{not}"
            );
        }
    }

    #[test]
    fn garbage_never_counts_as_ack() {
        for g in [
            "okk",
            "ok ok",
            "error:",
            "error:x",
            "\u{fffd}ok",
            "<Idle|MPos:a>",
            "",
            "ALARM:",
        ] {
            assert!(!Response::parse(g).is_ack(), "{g:?}");
        }
    }
}
