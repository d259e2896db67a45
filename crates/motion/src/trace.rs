//! The planned motion sampled at a fixed period of machine time (docs/trace-format.md).

use crate::planner::Segment;
use std::io::{self, Write};

/// Writes `t,x,y,z,joint_<j0>,joint_<j1>,joint_<j2>,speed,line` rows every `period` seconds of
/// machine time: the joint columns carry a prefix, so a Cartesian machine's joints (`x,y,z`)
/// do not repeat the names of the machine position columns.
pub struct TraceWriter<W: Write> {
    out: W,
    period: f64,
    /// Machine time at the start of the next segment.
    t_seg: f64,
    /// Time of the next sample.
    t_next: f64,
    /// Rows written so far.
    pub rows: u64,
}

impl<W: Write> TraceWriter<W> {
    /// Writes the header to `out`; rows follow every `period` seconds of machine time.
    pub fn new(mut out: W, period: f64, joint_names: [&str; 3]) -> io::Result<Self> {
        writeln!(
            out,
            "t,x,y,z,joint_{},joint_{},joint_{},speed,line",
            joint_names[0], joint_names[1], joint_names[2]
        )?;
        Ok(TraceWriter {
            out,
            period,
            t_seg: 0.0,
            t_next: 0.0,
            rows: 0,
        })
    }

    /// Samples one segment; joint angles are written as they are inside (radians).
    pub fn segment(&mut self, seg: &Segment) -> io::Result<()> {
        let end = self.t_seg + seg.duration();
        while self.t_next <= end {
            let (p, q, v) = seg.sample(self.t_next - self.t_seg);
            writeln!(
                self.out,
                "{:.3},{:.5},{:.5},{:.5},{:.6},{:.6},{:.6},{:.3},{}",
                self.t_next,
                p[0],
                p[1],
                p[2],
                q[0],
                q[1],
                q[2],
                v * 60.0,
                seg.line
            )?;
            self.rows += 1;
            self.t_next = self.rows as f64 * self.period;
        }
        self.t_seg = end;
        Ok(())
    }

    /// Bytes of one row on a machine of ordinary size (an estimate of the file before it is
    /// written): t (12), x y z (3 × 14), the joints (3 × 15), speed (12), line (10), the
    /// commas and the newline.
    pub const ROW_BYTES: u64 = 12 + 3 * 14 + 3 * 15 + 12 + 10 + 9;

    /// Flushes the output; returns the machine time traced, seconds.
    pub fn finish(mut self) -> io::Result<f64> {
        self.out.flush()?;
        Ok(self.t_seg)
    }
}
