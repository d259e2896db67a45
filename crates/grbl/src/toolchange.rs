//! Tool changes at `M6` for firmware without a tool changer. grbl 1.1 answers `M6` with
//! error:20 (unsupported command), so the sender handles it, with the policies CNCjs names:
//! - `firmware`: the line goes as written (grblHAL and FluidNC may change tools themselves);
//! - `ignore`: `M6` and the `T` word are taken out of the line, and the console says so;
//! - `pause`: streaming stops before the `M6` line; once the machine has executed every line
//!   before it (idle), spindle and coolant go off and the operator is asked to change to
//!   tool T; after Resume the state before the change is restored (the resume preamble:
//!   spindle, coolant, a safe approach, the program's modes) and streaming goes on;
//! - `park`: as `pause`, after a move to the park position (`G53 G0 Z`, then `X Y`);
//! - `remeasure`: as `pause` (parking first when a park position is given); after Resume
//!   the new tool is measured on a tool length setter ([`setter_at`], the probe routines' [`ToolSetter`]) and
//!   `G43.1 Z<delta>` puts its tip where the first tool's was (delta = this tool's touch Z
//!   − the first tool's, both in machine coordinates).
//!
//! `M6` itself never reaches the firmware under the last four; `T` alone is harmless to grbl
//! (it reads and keeps the tool number, 0…255).

use crate::gline;
use crate::job::{StreamLine, StreamProgram};
use crate::probe::{Approach, ToolSetter};
use std::str::FromStr;

mod run;
pub(crate) use run::{apply_offset, change_tool, remeasure, ToolError, ToolLengths};

/// What the sender does at an `M6`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolPolicy {
    /// Send the line as written: the firmware changes tools itself.
    Firmware,
    /// Drop `M6` and the `T` word from the line; note it in the console.
    Ignore,
    /// Stop streaming at the `M6` line and wait for the operator to change the tool.
    Pause,
    /// Move to the park position first, then pause.
    ParkPause,
    /// Pause, then measure the new tool on the tool setter and apply its length offset.
    Remeasure,
}

impl ToolPolicy {
    /// The name the command line takes (`--tool-change NAME`).
    pub fn name(self) -> &'static str {
        match self {
            ToolPolicy::Firmware => "firmware",
            ToolPolicy::Ignore => "ignore",
            ToolPolicy::Pause => "pause",
            ToolPolicy::ParkPause => "park",
            ToolPolicy::Remeasure => "remeasure",
        }
    }

    /// The sender stops streaming at each `M6`.
    pub fn pauses(self) -> bool {
        matches!(
            self,
            ToolPolicy::Pause | ToolPolicy::ParkPause | ToolPolicy::Remeasure
        )
    }
}

impl FromStr for ToolPolicy {
    type Err = String;
    fn from_str(s: &str) -> Result<ToolPolicy, String> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "firmware" | "none" => ToolPolicy::Firmware,
            "ignore" => ToolPolicy::Ignore,
            "pause" | "manual" => ToolPolicy::Pause,
            "park" | "park-pause" => ToolPolicy::ParkPause,
            "remeasure" | "pause-remeasure" => ToolPolicy::Remeasure,
            other => {
                return Err(format!(
                    "tool-change policy '{other}': one of pause, ignore, remeasure, park, firmware"
                ))
            }
        })
    }
}

/// The tool setter of a tool change: machine `x`, `y` (mm) over it, reached at machine
/// `z_start` (the height the move travels at and the search starts from); a search of at
/// most 50 mm at 200 mm/min, a lift of 2 mm and the measured touch at 25 mm/min.
pub fn setter_at(x: f64, y: f64, z_start: f64) -> ToolSetter {
    ToolSetter {
        at: Some([x, y]),
        safe_z: z_start,
        reference: None,
        approach: Approach {
            travel: 50.0,
            feed: 200.0,
            slow_feed: 25.0,
            retract: 2.0,
        },
    }
}

/// How tool changes are handled (the sender's run settings carry one).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolChange {
    /// What happens at an `M6`.
    pub policy: ToolPolicy,
    /// Park position, machine X, Y, Z (mm): `G53 G0 Z`, then `G53 G0 X Y`. Needed by `park`;
    /// `remeasure` parks there too when it is given.
    pub park: Option<[f64; 3]>,
    /// The tool setter `remeasure` probes ([`setter_at`]; its `reference`, when given, is
    /// the first tool's touch, so the first tool need not be measured).
    pub setter: Option<ToolSetter>,
    /// `remeasure`: measure the tool in the spindle when the job starts (the first tool's
    /// reference), not at the first `M6`.
    pub measure_at_start: bool,
}

impl Default for ToolChange {
    /// Pause for a manual change: never cut on with the wrong tool.
    fn default() -> Self {
        ToolChange {
            policy: ToolPolicy::Pause,
            park: None,
            setter: None,
            measure_at_start: false,
        }
    }
}

impl ToolChange {
    /// `M6` goes to the firmware as written.
    pub fn as_written() -> ToolChange {
        ToolChange {
            policy: ToolPolicy::Firmware,
            ..ToolChange::default()
        }
    }

    /// Says what is missing or out of range: `park` needs a park position, `remeasure` a
    /// setter, a park position has finite coordinates (the setter's numbers are checked by
    /// the probe routine before it moves).
    pub fn validate(&self) -> Result<(), String> {
        if self.policy == ToolPolicy::ParkPause && self.park.is_none() {
            return Err(
                "--tool-change park needs a park position (--park X,Y,Z, machine mm)".into(),
            );
        }
        if self.policy == ToolPolicy::Remeasure && self.setter.is_none() {
            return Err("--tool-change remeasure needs a tool setter (--tool-setter X,Y,ZSTART, machine mm)".into());
        }
        if let Some(p) = self.park {
            if !p.iter().all(|v| v.is_finite()) {
                return Err(format!(
                    "park position {p:?}: every coordinate a finite number"
                ));
            }
        }
        Ok(())
    }

    /// What `check --dialect grbl` says of an `M6` the sender handles: the policy and what
    /// happens (`None` under `firmware`: the line goes to grbl, which refuses it).
    pub fn note(&self, tool: Option<u32>) -> Option<String> {
        let t = tool.map(|t| format!(" T{t}")).unwrap_or_default();
        let what = match self.policy {
            ToolPolicy::Firmware => return None,
            ToolPolicy::Ignore => "the sender drops M6 and the T word",
            ToolPolicy::Pause => "the sender pauses for a manual change",
            ToolPolicy::ParkPause => {
                "the sender parks the machine and pauses for a manual change"
            }
            ToolPolicy::Remeasure => {
                "the sender pauses for a manual change, then measures the new tool on the tool setter (G43.1)"
            }
        };
        Some(format!(
            "M6{t}: grbl has no tool changer; {what} (--tool-change {})",
            self.policy.name()
        ))
    }
}

/// Where the sender stops for a tool change (or, under `ignore`, where one was dropped).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolStop {
    /// The job line the stop comes before (what remains of the `M6` line, or the next line).
    pub index: usize,
    /// The file line of the `M6`.
    pub file_line: usize,
    /// The tool: the line's `T` word, else the last one before it (0 when none).
    pub tool: u32,
    /// The program's own words for the tool: a `(T2 D=6 …)` comment, as CAM posts write.
    pub description: Option<String>,
}

impl ToolStop {
    /// What the operator is asked.
    pub fn prompt(&self, policy: ToolPolicy) -> String {
        let about = match &self.description {
            Some(d) => format!("{d}; "),
            None => String::new(),
        };
        let then = if policy == ToolPolicy::Remeasure {
            ", then resume: the sender measures it on the tool setter"
        } else {
            ", then resume"
        };
        format!(
            "change to tool T{} ({about}M6 at line {}){then}",
            self.tool, self.file_line
        )
    }
}

/// The words of a cleaned line and, when it has an `M6`, that line without the words the
/// policy takes out (`M6`; `T` too under `ignore`), as byte ranges of the line to drop.
pub(crate) fn m6_words(
    clean: &[u8],
    policy: ToolPolicy,
) -> Option<(Option<u32>, Vec<std::ops::Range<usize>>)> {
    let words = gline::word_spans(clean).ok()?;
    if !words.iter().any(|(l, v, _)| *l == 'M' && *v == 6.0) {
        return None;
    }
    let tool = tool_word(&words);
    let drop = words
        .into_iter()
        .filter(|(l, v, _)| (*l == 'M' && *v == 6.0) || (*l == 'T' && policy == ToolPolicy::Ignore))
        .map(|(_, _, r)| r)
        .collect();
    Some((tool, drop))
}

fn tool_word(words: &[(char, f64, std::ops::Range<usize>)]) -> Option<u32> {
    words
        .iter()
        .find(|(l, _, _)| *l == 'T')
        .map(|(_, v, _)| v.clamp(0.0, u32::MAX as f64) as u32)
}

/// `(T2 D=6 CR=0 - flat end mill)` → (2, "T2 D=6 CR=0 - flat end mill"): the tool list CAM
/// posts write in comments. Control characters are dropped, the text is kept short.
fn tool_comment(raw: &str) -> Option<(u32, String)> {
    let start = raw.find('(')?;
    let inner = &raw[start + 1..];
    let inner = inner[..inner.find(')').unwrap_or(inner.len())].trim();
    let rest = inner.strip_prefix(['T', 't'])?;
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let after = &rest[digits..];
    if digits == 0 || !(after.is_empty() || after.starts_with([' ', '\t'])) {
        return None;
    }
    let n = rest[..digits].parse().ok()?;
    let text: String = inner
        .chars()
        .filter(|c| !c.is_control())
        .take(100)
        .collect();
    Some((n, text))
}

impl StreamProgram {
    /// The program as the sender streams it under `tc`: [`StreamProgram::from_text`], then
    /// each `M6` line rewritten as the policy says and its stop recorded.
    pub fn with_tool_change(
        name: &str,
        text: &str,
        tc: &ToolChange,
    ) -> Result<StreamProgram, String> {
        tc.validate()?;
        let mut job = StreamProgram::from_text(name, text)?;
        if tc.policy == ToolPolicy::Firmware {
            return Ok(job);
        }
        job.take_tool_changes(text, tc);
        Ok(job)
    }

    /// Each `M6` line of the job rewritten as `tc`'s policy says and its stop recorded;
    /// `source` is the program as written (its `(T2 …)` comments describe the tools).
    pub(crate) fn take_tool_changes(&mut self, source: &str, tc: &ToolChange) {
        let job = self;
        let text = source;
        let mut described = std::collections::BTreeMap::new();
        for raw in text.lines() {
            if let Some((n, d)) = tool_comment(raw) {
                described.entry(n).or_insert(d);
            }
        }
        let mut lines = Vec::with_capacity(job.lines.len());
        let mut stops: Vec<ToolStop> = Vec::new();
        let mut tool = None;
        for line in std::mem::take(&mut job.lines) {
            let bytes = line.text.as_bytes();
            if let Ok(w) = gline::word_spans(bytes) {
                tool = tool_word(&w).or(tool);
            }
            let Some((_, drop)) = m6_words(bytes, tc.policy) else {
                lines.push(line);
                continue;
            };
            let kept: String = line
                .text
                .char_indices()
                .filter(|(i, _)| !drop.iter().any(|r| r.contains(i)))
                .map(|(_, c)| c)
                .collect();
            let t = tool.unwrap_or(0);
            let stop = ToolStop {
                index: lines.len(),
                file_line: line.file_line,
                tool: t,
                description: described.get(&t).cloned(),
            };
            // Two changes with nothing between them: the last one is the tool wanted.
            if stops.last().is_some_and(|s| s.index == stop.index) {
                stops.pop();
            }
            stops.push(stop);
            if !kept.is_empty() {
                lines.push(StreamLine {
                    file_line: line.file_line,
                    text: kept,
                });
            }
        }
        job.lines = lines;
        job.tool_stops = stops;
        job.tool_change = tc.clone();
    }

    /// The tool stop before job line `index`, when the policy stops there.
    pub fn tool_stop_at(&self, index: usize) -> Option<&ToolStop> {
        if !self.tool_change.policy.pauses() {
            return None;
        }
        self.tool_stops.iter().find(|s| s.index == index)
    }

    /// Where streaming from `from` must stop next: the first tool stop after `from`, else the end.
    pub(crate) fn next_stop_after(&self, from: usize) -> usize {
        if !self.tool_change.policy.pauses() {
            return self.len();
        }
        self.tool_stops
            .iter()
            .map(|s| s.index)
            .find(|&i| i > from)
            .unwrap_or(self.len())
            .min(self.len())
    }
}

/// What the sender does to a line of a program checked for grbl (`check --dialect grbl`).
#[derive(Clone, Debug, PartialEq)]
pub struct SenderNote {
    /// 1-based line.
    pub line: u32,
    /// 1-based column (characters) of the first word taken out.
    pub col: u32,
    /// Columns from `col` to the end of the last word taken out.
    pub len: u32,
    /// What the sender does there.
    pub message: String,
}

/// The program as grbl receives it from the sender under `tc`, for a check in grbl's own
/// terms: `M6` (and the `T` word under `ignore`) and the `%` tape marks on the first and
/// last lines (which the sender never sends) are overwritten with spaces, so the result
/// has the same bytes everywhere else and every column of a diagnostic still points into
/// the file; a note says what happens on each such line. Under `firmware` `M6` stays (grbl
/// refuses it).
pub fn sender_view(text: &[u8], tc: &ToolChange) -> (Vec<u8>, Vec<SenderNote>) {
    let mut out = text.to_vec();
    let mut notes = Vec::new();
    let mut starts = vec![0];
    starts.extend(
        text.iter()
            .enumerate()
            .filter(|(_, b)| **b == b'\n')
            .map(|(i, _)| i + 1),
    );
    let line_of = |k: usize| {
        let s = starts[k];
        let e = starts.get(k + 1).map_or(text.len(), |n| n - 1);
        s..e
    };
    let col = |s: usize, at: usize| {
        // Characters, not bytes: count the UTF-8 lead bytes before `at`.
        1 + text[s..at].iter().filter(|b| (**b & 0xC0) != 0x80).count() as u32
    };
    let blank = |r: &std::ops::Range<usize>| r.clone().all(|i| text[i].is_ascii_whitespace());
    let is_mark = |r: &std::ops::Range<usize>| text[r.clone()].trim_ascii() == b"%";
    let first = (0..starts.len()).find(|&k| !blank(&line_of(k)));
    let last = (0..starts.len()).rev().find(|&k| !blank(&line_of(k)));
    let mut tool = None;
    for k in 0..starts.len() {
        let r = line_of(k);
        let number = k as u32 + 1;
        if (Some(k) == first || Some(k) == last) && is_mark(&r) {
            let at = r.start + text[r.clone()].iter().position(|b| *b == b'%').unwrap_or(0);
            out[at] = b' ';
            notes.push(SenderNote {
                line: number,
                col: col(r.start, at),
                len: 1,
                message: "'%' tape mark: the sender does not send it".into(),
            });
            continue;
        }
        let (clean, at) = gline::clean_mapped(&text[r.clone()]);
        if let Ok(w) = gline::word_spans(&clean) {
            tool = tool_word(&w).or(tool);
        }
        if tc.policy == ToolPolicy::Firmware {
            continue;
        }
        let Some((_, drop)) = m6_words(&clean, tc.policy) else {
            continue;
        };
        // Every source byte of the words taken out (spaces inside a word included).
        let mut span: Option<(usize, usize)> = None;
        for w in &drop {
            let (a, b) = (at[w.start], at[w.end - 1]);
            for i in w.clone() {
                out[r.start + at[i]] = b' ';
            }
            span = Some(span.map_or((a, b), |(s, e)| (s.min(a), e.max(b))));
        }
        let (a, b) = span.unwrap_or((0, 0));
        let c0 = col(r.start, r.start + a);
        notes.push(SenderNote {
            line: number,
            col: c0,
            len: col(r.start, r.start + b + 1) - c0,
            message: tc.note(tool).unwrap_or_default(),
        });
    }
    (out, notes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prepared(text: &str, policy: ToolPolicy) -> StreamProgram {
        let tc = ToolChange {
            policy,
            park: Some([0.0, 0.0, -1.0]),
            setter: Some(setter_at(0.0, 0.0, -5.0)),
            measure_at_start: false,
        };
        StreamProgram::with_tool_change("t.nc", text, &tc).unwrap()
    }

    const TWO_TOOLS: &str = "%\n(T1 D=3.175 CR=0 - flat end mill)\n(T2 D=6 - ball)\nT1 M6\nS10000 M3\nG0 X1\nM5\nT2\nm06 (change)\nG0 X2\nM30\n%\n";

    #[test]
    fn pause_keeps_t_and_stops_before_the_line() {
        let j = prepared(TWO_TOOLS, ToolPolicy::Pause);
        let texts: Vec<&str> = j.lines.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(texts, ["T1", "S10000M3", "G0X1", "M5", "T2", "G0X2", "M30"]);
        assert_eq!(j.tool_stops.len(), 2);
        assert_eq!(
            (
                j.tool_stops[0].index,
                j.tool_stops[0].tool,
                j.tool_stops[0].file_line
            ),
            (0, 1, 4)
        );
        assert_eq!(
            (
                j.tool_stops[1].index,
                j.tool_stops[1].tool,
                j.tool_stops[1].file_line
            ),
            (5, 2, 9)
        );
        assert_eq!(
            j.tool_stops[1].description.as_deref(),
            Some("T2 D=6 - ball")
        );
        assert!(j.tool_stops[1]
            .prompt(ToolPolicy::Pause)
            .starts_with("change to tool T2 (T2 D=6 - ball; M6 at line 9)"));
        assert_eq!(j.next_stop_after(0), 5);
        assert_eq!(j.next_stop_after(5), j.len());
        assert!(j.tool_stop_at(5).is_some() && j.tool_stop_at(4).is_none());
    }

    #[test]
    fn ignore_drops_m6_and_t() {
        let j = prepared(TWO_TOOLS, ToolPolicy::Ignore);
        let texts: Vec<&str> = j.lines.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(texts, ["S10000M3", "G0X1", "M5", "T2", "G0X2", "M30"]);
        assert_eq!(j.tool_stops.len(), 2, "recorded for the notes");
        assert!(
            j.tool_stop_at(j.tool_stops[1].index).is_none(),
            "never stops"
        );
        assert_eq!(j.next_stop_after(0), j.len());
        assert!(!j.lines.iter().any(|l| l.text.contains("M6")));
    }

    #[test]
    fn firmware_leaves_m6_and_settings_are_validated() {
        let j = prepared(TWO_TOOLS, ToolPolicy::Firmware);
        assert!(j.lines.iter().any(|l| l.text == "T1M6"));
        assert!(j.tool_stops.is_empty());
        let bad = ToolChange {
            policy: ToolPolicy::Remeasure,
            ..ToolChange::default()
        };
        assert!(bad.validate().unwrap_err().contains("--tool-setter"));
        let bad = ToolChange {
            policy: ToolPolicy::ParkPause,
            ..ToolChange::default()
        };
        assert!(bad.validate().unwrap_err().contains("--park"));
        let bad = ToolChange {
            park: Some([0.0, f64::NAN, 0.0]),
            ..ToolChange::default()
        };
        assert!(bad.validate().is_err());
        assert_eq!(
            "pause-remeasure".parse::<ToolPolicy>(),
            Ok(ToolPolicy::Remeasure)
        );
        assert!("swap".parse::<ToolPolicy>().is_err());
    }

    #[test]
    fn sender_view_blanks_in_place_with_notes() {
        let text = b"%\n(T1 D=3)\nT1 m 6 (first)\nG0 X1\nT2\nM06\nM30\n%\n";
        let pause = ToolChange::default();
        let (out, notes) = sender_view(text, &pause);
        assert_eq!(out.len(), text.len());
        assert_eq!(
            std::str::from_utf8(&out).unwrap(),
            " \n(T1 D=3)\nT1     (first)\nG0 X1\nT2\n   \nM30\n \n"
        );
        let at: Vec<(u32, u32, u32)> = notes.iter().map(|n| (n.line, n.col, n.len)).collect();
        assert_eq!(at, [(1, 1, 1), (3, 4, 3), (6, 1, 3), (8, 1, 1)]);
        assert!(notes[1]
            .message
            .starts_with("M6 T1: grbl has no tool changer; the sender pauses"));
        assert!(
            notes[2].message.contains("M6 T2") && notes[2].message.contains("--tool-change pause")
        );
        let ignore = ToolChange {
            policy: ToolPolicy::Ignore,
            ..ToolChange::default()
        };
        let (out, notes) = sender_view(text, &ignore);
        assert!(std::str::from_utf8(&out)
            .unwrap()
            .contains("\n       (first)\n"));
        assert!(notes[1].message.contains("drops M6 and the T word"));
        // `%` in the middle stays (grbl refuses it), and so does M6 under `firmware`.
        let (out, notes) = sender_view(b"G0\n%\nM6\nG0\n", &ToolChange::as_written());
        assert_eq!(out, b"G0\n%\nM6\nG0\n");
        assert!(notes.is_empty());
    }
}
