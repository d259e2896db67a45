//! Offsets and coordinate systems: G54…G59.3 selection, G10 L1/L2/L10/L20, G28/G30 and their
//! stored homes, G52/G92 and tool length offsets (G43, G43.1, G49). Each change goes through
//! [`Interpreter::set_frame`] so the machine stays where it is and the program position moves.

use super::frame::Frame;
use super::words::{g_group as G, Decoded};
use super::{param, tool_table, words, Interpreter, Sink, AXES};
use crate::diag::Diagnostic;
use crate::params::Params;
use oficina_canon::{CanonOp, Pos};

impl Interpreter {
    /// The active work offset and rotation; `with_g92` as rs274 does on G54…G59.3 (it
    /// restates the G92 offset between the two).
    pub(super) fn emit_coord_system(&self, sink: Sink, with_g92: bool) {
        self.emit(
            sink,
            CanonOp::SetG5xOffset {
                index: self.modal.coord_system,
                offset: Pos::from_array(self.frame.g5x),
            },
        );
        if with_g92 {
            self.emit(sink, CanonOp::SetG92Offset(Pos::from_array(self.frame.g92)));
        }
        self.emit(sink, CanonOp::SetXyRotation(self.frame.rotation));
    }

    /// Take the offset of system `index` from the parameters (LinuxCNC keeps them there, in
    /// program units).
    pub(super) fn load_coord_system(&mut self, params: &Params, index: u8) {
        let base = param::G5X_BASE + 20 * (index as i64 - 1);
        let k = self.mk();
        let mut f = self.frame;
        for i in 0..6 {
            let v = params.get(base + i as i64).unwrap_or(0.0);
            f.g5x[i] = if i < 3 { v * k } else { v };
        }
        f.rotation = params.get(base + 9).unwrap_or(0.0);
        self.set_frame(f);
    }

    pub(super) fn tool_length(
        &mut self,
        d: &Decoded,
        t: u16,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let mut f = self.frame;
        match t {
            430 => {
                let n = match d.values[words::slot('H')] {
                    Some(h) => self.tool_number(h.v, h.span, "H")?,
                    None => self.modal.tool_in_spindle,
                };
                f.tool = match self.tools.get(n) {
                    Some(tool) => tool.offset,
                    None if n == 0 || self.tools.is_empty() => [0.0; 6],
                    None => {
                        return Err(self.fail(
                            d.span_of('H'),
                            format!("Requested tool {n} not found in the tool table"),
                            0,
                        ))
                    }
                };
            }
            431 => {
                f.tool = [0.0; 6];
                for (i, &l) in AXES.iter().enumerate() {
                    if let Some(v) = d.get(l) {
                        f.tool[i] = if i < 3 { v * self.k() } else { v };
                    }
                }
            }
            _ => f.tool = [0.0; 6],
        }
        self.modal.tool_length_on = t != 490;
        self.set_frame(f);
        self.emit(sink, CanonOp::UseToolLengthOffset(Pos::from_array(f.tool)));
        Ok(())
    }

    /// G4 (done earlier), G10, G28, G30, G52, G53 (only a flag), G92…: returns whether the
    /// block's axis words were used up (no motion follows).
    pub(super) fn non_modal(
        &mut self,
        d: &Decoded,
        t: u16,
        params: &mut Params,
        sink: Sink,
    ) -> Result<bool, Diagnostic> {
        let k = self.k();
        let scale = |i: usize| if i < 3 { k } else { 1.0 };
        match t {
            100 => {
                self.g10(d, params, sink)?;
                Ok(true)
            }
            280 | 300 => {
                if self.modal.comp.is_some() {
                    return Err(self.fail(
                        d.g_span(G::NON_MODAL),
                        "Cannot use G28 or G30 with cutter radius compensation",
                        0,
                    ));
                }
                // Through the intermediate point (axis words), then home on those axes
                // (all axes when none is named).
                let mid = self.axis_target(d);
                let base = if t == 280 {
                    param::G28_HOME
                } else {
                    param::G30_HOME
                };
                // rs274 makes the intermediate move even when it goes nowhere.
                self.emit_straight(sink, false, mid);
                self.pos = mid;
                let mut home_m = self.frame.to_machine(self.pos);
                let mk = self.machine_units.mm();
                for i in 0..6 {
                    if !d.any_axis() || d.has(AXES[i]) {
                        let s = if i < 3 { mk } else { 1.0 };
                        home_m[i] = params.get(base + i as i64).unwrap_or(0.0) * s;
                    }
                }
                let home = self.frame.to_program(home_m);
                self.emit_straight(sink, false, home);
                self.pos = home;
                Ok(true)
            }
            281 | 301 => {
                let base = if t == 281 {
                    param::G28_HOME
                } else {
                    param::G30_HOME
                };
                let m = self.frame.to_machine(self.pos);
                let mk = self.machine_units.mm();
                for i in 0..6 {
                    let s = if i < 3 { mk } else { 1.0 };
                    let _ = params.set(base + i as i64, m[i] / s);
                }
                Ok(true)
            }
            520 | 920 => {
                if !d.any_axis() {
                    return Err(self.fail(
                        d.g_span(G::NON_MODAL),
                        "All axes missing with g52 or g92",
                        26,
                    ));
                }
                let mut f = self.frame;
                for i in 0..6 {
                    if let Some(v) = d.get(AXES[i]) {
                        f.g92[i] = if t == 920 {
                            self.pos[i] + self.frame.g92[i] - v * scale(i)
                        } else {
                            v * scale(i)
                        };
                    }
                }
                self.set_g92(f, params, sink);
                Ok(true)
            }
            921 | 922 => {
                let mut f = self.frame;
                f.g92 = [0.0; 6];
                if t == 921 {
                    for i in 0..6 {
                        let _ = params.set(param::G92_OFFSET + i as i64, 0.0);
                    }
                }
                self.set_frame(f);
                let _ = params.set(param::G92_ENABLED, 0.0);
                self.emit(sink, CanonOp::SetG92Offset(Pos::from_array(f.g92)));
                Ok(false)
            }
            923 => {
                let mut f = self.frame;
                for i in 0..6 {
                    let s = if i < 3 { self.mk() } else { 1.0 };
                    f.g92[i] = params.get(param::G92_OFFSET + i as i64).unwrap_or(0.0) * s;
                }
                self.set_g92(f, params, sink);
                Ok(false)
            }
            _ => Ok(false),
        }
    }

    pub(super) fn set_g92(&mut self, f: Frame, params: &mut Params, sink: Sink) {
        let k = self.mk();
        for i in 0..6 {
            let s = if i < 3 { k } else { 1.0 };
            let _ = params.set(param::G92_OFFSET + i as i64, f.g92[i] / s);
        }
        let _ = params.set(param::G92_ENABLED, 1.0);
        self.set_frame(f);
        self.emit(sink, CanonOp::SetG92Offset(Pos::from_array(f.g92)));
    }

    pub(super) fn g10(
        &mut self,
        d: &Decoded,
        params: &mut Params,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::NON_MODAL);
        let l = d.values[words::slot('L')].ok_or_else(|| {
            self.fail(
                span,
                "Line with G10 does not have L0, L1, L10, L11, L2, or L20",
                28,
            )
        })?;
        let p = d.get('P');
        let k = self.k();
        match l.v as i64 {
            2 | 20 if l.v.fract() == 0.0 => {
                let pv = p.unwrap_or(-1.0);
                if !(0.0..=9.0).contains(&pv) || pv.fract() != 0.0 {
                    return Err(self.fail(
                        d.span_of('P'),
                        format!("P value out of range (0-9) with G10 L{}", l.v),
                        28,
                    ));
                }
                let index = if pv == 0.0 {
                    self.modal.coord_system
                } else {
                    pv as u8
                };
                let base = param::G5X_BASE + 20 * (index as i64 - 1);
                let mut off = [0.0; 6];
                for (i, o) in off.iter_mut().enumerate() {
                    *o = params.get(base + i as i64).unwrap_or(0.0);
                }
                let mut rot = params.get(base + 9).unwrap_or(0.0);
                if let Some(r) = d.get('R') {
                    rot = r;
                }
                let mk = self.mk();
                if l.v == 2.0 {
                    for (i, o) in off.iter_mut().enumerate() {
                        if let Some(v) = d.get(AXES[i]) {
                            *o = if i < 3 { v * k / mk } else { v };
                        }
                    }
                } else {
                    // L20: choose the offset that makes the current point read as the values.
                    let mut f = self.frame;
                    f.rotation = rot;
                    let m = self.frame.to_machine(self.pos);
                    let mut want = self.pos;
                    for (i, w) in want.iter_mut().enumerate() {
                        if let Some(v) = d.get(AXES[i]) {
                            *w = if i < 3 { v * k } else { v };
                        }
                    }
                    f.g5x = [0.0; 6];
                    let through = f.to_machine(want);
                    for i in 0..6 {
                        // X and Y are one rotated pair: rs274 keeps the reading of the
                        // one not named, which moves both offsets.
                        let xy = d.has('X') || d.has('Y') || d.has('R');
                        if d.has(AXES[i]) || (i < 2 && xy) {
                            let s = if i < 3 { mk } else { 1.0 };
                            off[i] = (m[i] - through[i]) / s;
                        }
                    }
                }
                for (i, o) in off.iter().enumerate() {
                    let _ = params.set(base + i as i64, *o);
                }
                let _ = params.set(base + 9, rot);
                if index == self.modal.coord_system {
                    self.load_coord_system(params, index);
                    self.emit_coord_system(sink, false);
                }
                Ok(())
            }
            1 | 10 | 11 if l.v.fract() == 0.0 => {
                let pv = p.unwrap_or(-1.0);
                if pv < 1.0 || pv.fract() != 0.0 || pv > u32::MAX as f64 {
                    return Err(self.fail(
                        d.span_of('P'),
                        format!("P value out of range with G10 L{}", l.v),
                        28,
                    ));
                }
                // Like T and H, a number missing from a loaded table is an error.
                let n = self.tool_number(pv, d.span_of('P'), "P")?;
                let mut tool = self.tools.get(n).cloned().unwrap_or(tool_table::Tool {
                    number: n,
                    pocket: n,
                    ..Default::default()
                });
                // L10 and L11: the offset that makes the current point read as the value,
                // L10 through the active offsets, L11 through G59.3's alone (no G92).
                let reading = if l.v == 11.0 {
                    self.g59_3_frame(params)
                } else {
                    Frame {
                        tool: [0.0; 6],
                        ..self.frame
                    }
                };
                // The machine point itself: read through a frame without the tool offset it
                // is rs274's "current position in the system without TLO".
                let m = self.frame.to_machine(self.pos);
                let old_xy = [tool.offset[0], tool.offset[1]];
                for (i, &axis) in AXES.iter().enumerate() {
                    if let Some(v) = d.get(axis) {
                        let s = if i < 3 { k } else { 1.0 };
                        tool.offset[i] = if l.v == 1.0 {
                            v * s
                        } else {
                            let mut want = reading.to_program(m);
                            want[i] = v * s;
                            m[i] - reading.to_machine(want)[i]
                        };
                    }
                }
                if l.v != 1.0 && reading.rotation != 0.0 {
                    let here = reading.to_program(m);
                    let [x, y] = [d.get('X').map(|v| v * k), d.get('Y').map(|v| v * k)];
                    if let Some(o) = rotated_tool_xy(old_xy, here, x, y, reading.rotation) {
                        [tool.offset[0], tool.offset[1]] = o;
                    }
                }
                if let Some(r) = d.get('R') {
                    tool.diameter = 2.0 * r * k;
                }
                self.tools.insert(tool);
                self.set_tool_params(params);
                Ok(())
            }
            _ => Err(self.fail(
                l.span,
                "Line with G10 does not have L0, L1, L10, L11, L2, or L20",
                28,
            )),
        }
    }

    /// The offsets of G59.3 alone (work offset and rotation, no G92, no tool): what G10 L11
    /// reads the current point through.
    fn g59_3_frame(&self, params: &Params) -> Frame {
        let base = param::G5X_BASE + 20 * 8;
        let k = self.mk();
        let mut f = Frame::default();
        for i in 0..6 {
            let v = params.get(base + i as i64).unwrap_or(0.0);
            f.g5x[i] = if i < 3 { v * k } else { v };
        }
        f.rotation = params.get(base + 9).unwrap_or(0.0);
        f
    }
}

/// G10 L10/L11 X and Y under a rotated coordinate system, as rs274 2.9 sets them
/// (convert_setup_tool): the offset is the current point's distance from the value asked,
/// turned by the rotation; with one of X and Y, the old offset keeps its component along
/// the other (rotated) axis. `here`: the current point read in the system, mm.
fn rotated_tool_xy(
    old: [f64; 2],
    here: [f64; 6],
    x: Option<f64>,
    y: Option<f64>,
    degrees: f64,
) -> Option<[f64; 2]> {
    let (s, c) = degrees.to_radians().sin_cos();
    let turn = |v: [f64; 2], s: f64| [v[0] * c - v[1] * s, v[0] * s + v[1] * c];
    let (t, keep) = match (x, y) {
        (Some(x), Some(y)) => return Some(turn([here[0] - x, here[1] - y], s)),
        (Some(x), None) => ([here[0] - x, 0.0], 1),
        (None, Some(y)) => ([0.0, here[1] - y], 0),
        (None, None) => return None,
    };
    let mut o = turn(old, -s);
    o[1 - keep] = 0.0;
    let o = turn(o, s);
    let t = turn(t, s);
    Some([t[0] + o[0], t[1] + o[1]])
}
