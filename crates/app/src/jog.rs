//! Continuous jog: a button held down moves the machine until it is released (or its page
//! is lost). It is one jog towards the end of travel, cancelled on release, the way CNCjs
//! and grbl's own jog cancel (0x85) work: no stream of small steps that could run on.

use crate::{Error, Session};
use oficina_machine::Command;

/// How far a held button may move when the travel is not known (real firmware checks its
/// own soft limits), mm.
const UNKNOWN_TRAVEL: f64 = 1000.0;

/// The jog from `pos` along the unit axis direction `dir` (each -1, 0 or 1) to the edge of
/// `travel` (a little inside it, so the soft-limit check passes), or `UNKNOWN_TRAVEL` when
/// there is no profile.
pub(crate) fn continuous_delta(
    pos: [f64; 3],
    dir: [f64; 3],
    travel: Option<[[f64; 2]; 3]>,
) -> Result<[f64; 3], Error> {
    if dir.iter().any(|d| ![-1.0, 0.0, 1.0].contains(d)) || dir.iter().all(|d| *d == 0.0) {
        return Err(Error(format!(
            "jog direction {dir:?}: each axis -1, 0 or 1, at least one moving"
        )));
    }
    const MARGIN: f64 = 1e-3;
    Ok(std::array::from_fn(|i| {
        let d = dir[i];
        match travel {
            _ if d == 0.0 => 0.0,
            Some(t) if d > 0.0 => (t[i][1] - MARGIN - pos[i]).max(0.0),
            Some(t) => -(pos[i] - t[i][0] - MARGIN).max(0.0),
            None => d * UNKNOWN_TRAVEL,
        }
    }))
}

impl Session {
    /// Start moving along `dir` at `feed` mm/min until [`Session::jog_stop`].
    pub fn jog_start(&mut self, dir: [f64; 3], feed: f64) -> Result<(), Error> {
        let pos = self.snapshot().machine_pos;
        let delta = continuous_delta(pos, dir, self.profile().map(|p| p.travel))?;
        if delta.iter().all(|d| d.abs() < 1e-6) {
            return Err(Error("at the end of travel in that direction".into()));
        }
        self.jog(delta, feed)
    }

    /// End a jog now (nothing when none moves).
    pub fn jog_stop(&mut self) -> Result<(), Error> {
        self.command(Command::JogCancel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRAVEL: [[f64; 2]; 3] = [[0.0, 300.0], [0.0, 200.0], [-50.0, 0.0]];

    #[test]
    fn a_held_button_goes_to_the_end_of_travel_and_no_further() {
        let d = continuous_delta([10.0, 20.0, -5.0], [1.0, 0.0, -1.0], Some(TRAVEL)).unwrap();
        assert!((d[0] - (290.0 - 1e-3)).abs() < 1e-9, "{d:?}");
        assert_eq!(d[1], 0.0);
        assert!((d[2] - (-45.0 + 1e-3)).abs() < 1e-9, "{d:?}");
        // Already at the end: no motion.
        let d = continuous_delta([300.0, 0.0, 0.0], [1.0, 0.0, 0.0], Some(TRAVEL)).unwrap();
        assert_eq!(d, [0.0; 3]);
        assert_eq!(
            continuous_delta([0.0; 3], [0.0, -1.0, 0.0], None).unwrap(),
            [0.0, -UNKNOWN_TRAVEL, 0.0]
        );
    }

    #[test]
    fn bad_directions_are_refused() {
        for dir in [
            [0.0; 3],
            [2.0, 0.0, 0.0],
            [f64::NAN, 0.0, 0.0],
            [0.5, 0.0, 0.0],
        ] {
            assert!(
                continuous_delta([0.0; 3], dir, Some(TRAVEL)).is_err(),
                "{dir:?}"
            );
        }
    }

    #[test]
    fn a_continuous_jog_moves_until_cancelled_on_the_virtual_machine() {
        let mut s = Session::open("virtual").unwrap();
        let start = s.snapshot().machine_pos;
        s.jog_start([1.0, 0.0, 0.0], 600.0).unwrap();
        // Wait until it moves, then cancel.
        let t0 = std::time::Instant::now();
        while s.snapshot().machine_pos[0] <= start[0] + 0.5 {
            assert!(t0.elapsed().as_secs() < 30, "the jog never moved");
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        s.jog_stop().unwrap();
        while s.snapshot().state != "idle" {
            assert!(t0.elapsed().as_secs() < 30, "the jog never stopped");
            s.poll(std::time::Duration::from_millis(10));
        }
        let stopped = s.snapshot().machine_pos[0];
        std::thread::sleep(std::time::Duration::from_millis(200));
        assert_eq!(s.snapshot().machine_pos[0], stopped, "it stays stopped");
        let end = s.profile().unwrap().travel[0][1];
        assert!(
            stopped < end - 1.0,
            "stopped at {stopped}, well before the end {end}"
        );
        // A cancel with nothing moving is harmless.
        s.jog_stop().unwrap();
    }
}
