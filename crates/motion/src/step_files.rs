//! Steps written as they are generated: one CSV row each (`motor,time_s,dir`), and/or
//! Klipper-style compressed runs per motor (`motor,interval,count,add,dir`).

use crate::stepcompress::Compressor;
use crate::steps::{StepSink, MOTORS};
use std::io::{self, Write};

/// Klipper's MCU clock for the compressed intervals, and its step time tolerance.
const CLOCK_HZ: f64 = 16e6;
const MAX_STEP_ERROR: f64 = 25e-6;

/// A [`StepSink`] writing the step outputs; the first write error is kept and returned by
/// [`StepFiles::finish`].
pub struct StepFiles<W: Write> {
    names: [&'static str; MOTORS],
    csv: Option<W>,
    runs: Option<(W, [Compressor; MOTORS])>,
    steps: u64,
    error: Option<io::Error>,
}

impl<W: Write> StepFiles<W> {
    /// Bytes of one CSV row at most: a joint name, a time with 9 decimals, a direction
    /// (a compressed run holds at least one step, so its file is never larger).
    pub const ROW_BYTES: u64 = 24;

    /// Writes the headers; `names` are the motors' names (`motor_names`).
    pub fn new(
        names: [&'static str; MOTORS],
        csv: Option<W>,
        runs: Option<W>,
    ) -> io::Result<StepFiles<W>> {
        let csv = csv
            .map(|mut w| writeln!(w, "motor,time_s,dir").map(|()| w))
            .transpose()?;
        let runs = runs
            .map(|mut w| {
                writeln!(w, "motor,interval,count,add,dir # {CLOCK_HZ} Hz")?;
                let c = || Compressor::new(CLOCK_HZ, MAX_STEP_ERROR);
                Ok::<_, io::Error>((w, std::array::from_fn(|_| c())))
            })
            .transpose()?;
        Ok(StepFiles {
            names,
            csv,
            runs,
            steps: 0,
            error: None,
        })
    }

    fn keep(&mut self, r: io::Result<()>) {
        if let (Err(e), None) = (r, &self.error) {
            self.error = Some(e);
        }
    }

    fn drain(&mut self, motor: usize) {
        if let Some((w, c)) = self.runs.as_mut() {
            let name = self.names[motor];
            let r = c[motor].out.drain(..).try_for_each(|q| {
                writeln!(
                    w,
                    "{name},{},{},{},{}",
                    q.interval,
                    q.count,
                    q.add,
                    if q.forward { '+' } else { '-' }
                )
            });
            self.keep(r);
        }
    }

    /// Flushes every output; the number of steps written, or the first write error.
    pub fn finish(mut self) -> io::Result<u64> {
        for m in 0..MOTORS {
            if let Some((_, c)) = self.runs.as_mut() {
                c[m].flush();
            }
            self.drain(m);
        }
        if let Some(w) = self.csv.as_mut() {
            let r = w.flush();
            self.keep(r);
        }
        if let Some((w, _)) = self.runs.as_mut() {
            let r = w.flush();
            self.keep(r);
        }
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.steps),
        }
    }
}

impl<W: Write> StepSink for StepFiles<W> {
    fn step(&mut self, motor: usize, time: f64, forward: bool) {
        self.steps += 1;
        if let Some(w) = self.csv.as_mut() {
            let dir = if forward { '+' } else { '-' };
            let r = writeln!(w, "{},{time:.9},{dir}", self.names[motor]);
            self.keep(r);
        }
        if let Some((_, c)) = self.runs.as_mut() {
            c[motor].push(time, forward);
            self.drain(motor);
        }
    }
}
