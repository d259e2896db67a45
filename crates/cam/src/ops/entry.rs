//! Going down into material. A flat end mill cannot cut under its own centre, so by default
//! the tool descends while moving: along the path it is about to cut (ramp) or round a
//! helix. A straight plunge is only written when the user says the tool can (drills,
//! centre-cutting mills).

use super::chain::Chain;
use super::{Builder, OpError};
use crate::Move;
use std::f64::consts::TAU;

/// How a cut goes down into material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Entry {
    /// Straight down at the plunge feed.
    Plunge,
    /// Down along the path at this angle from horizontal (degrees).
    Ramp {
        /// Degrees from horizontal.
        angle: f64,
    },
    /// Round a circle of this radius (mm) at this angle, where it fits; otherwise a ramp.
    Helix {
        /// Radius of the helix, mm.
        radius: f64,
        /// Degrees from horizontal.
        angle: f64,
    },
}

impl Default for Entry {
    fn default() -> Entry {
        Entry::Ramp { angle: 3.0 }
    }
}

impl Entry {
    /// Refuses angles and radii no cut could use.
    pub fn validate(&self) -> Result<(), OpError> {
        let angle_ok = |a: f64| a.is_finite() && a > 0.1 && a <= 45.0;
        match *self {
            Entry::Plunge => Ok(()),
            Entry::Ramp { angle } | Entry::Helix { angle, .. } if !angle_ok(angle) => Err(
                OpError::Invalid(format!("entry angle {angle}°: use 0.1 to 45 degrees")),
            ),
            Entry::Helix { radius, .. } if !(radius.is_finite() && radius > 0.0) => Err(
                OpError::Invalid(format!("helix radius {radius} mm must be above 0")),
            ),
            _ => Ok(()),
        }
    }

    /// The ramp angle, radians (a plunge uses none).
    pub fn angle(&self) -> Option<f64> {
        match *self {
            Entry::Plunge => None,
            Entry::Ramp { angle } | Entry::Helix { angle, .. } => Some(angle.to_radians()),
        }
    }
}

/// From `z_from` (in air or on an already cut floor) down to `z_to`, entering a closed
/// `chain` at its start; returns the arc length where the descent ended (the caller then
/// cuts the whole loop from there).
pub(crate) fn enter_loop(
    b: &mut Builder,
    chain: &Chain,
    entry: Entry,
    z_from: f64,
    z_to: f64,
    feed: f64,
) -> f64 {
    match entry.angle() {
        None => {
            b.line([chain.start()[0], chain.start()[1], z_to], feed);
            0.0
        }
        Some(angle) => {
            let run = (z_from - z_to).max(0.0) / angle.tan();
            let mut moves = Vec::new();
            chain.walk(&[(0.0, z_from), (run, z_to)], feed, &mut moves);
            b.extend(moves);
            run
        }
    }
}

/// Down to `z_to` at the start of an open `chain` by going back and forth along it.
pub(crate) fn enter_open(
    b: &mut Builder,
    chain: &Chain,
    entry: Entry,
    z_from: f64,
    z_to: f64,
    feed: f64,
) -> Result<(), OpError> {
    let Some(angle) = entry.angle() else {
        b.line([chain.start()[0], chain.start()[1], z_to], feed);
        return Ok(());
    };
    let len = chain.length();
    if len < 1e-3 {
        return Err(OpError::Geometry(format!(
            "a cut of {len:.4} mm at ({:.3}, {:.3}) is too short to ramp into: allow plunging",
            chain.start()[0],
            chain.start()[1]
        )));
    }
    let back = chain.reversed();
    let drop_per_pass = len * angle.tan();
    let mut z = z_from;
    while z > z_to + 1e-9 {
        // Out along the chain and back, descending all the way.
        let z_mid = (z - drop_per_pass).max(z_to);
        let z_end = (z_mid - drop_per_pass).max(z_to);
        let mut moves = Vec::new();
        chain.walk(&[(0.0, z), (len, z_mid)], feed, &mut moves);
        back.walk(&[(0.0, z_mid), (len, z_end)], feed, &mut moves);
        b.extend(moves);
        z = z_end;
    }
    Ok(())
}

/// A helix of `radius` about `centre` from `z_from` down to `z_to`, ending with one flat
/// turn at `z_to` at the helix start (centre + radius along X).
pub(crate) fn helix(
    b: &mut Builder,
    centre: [f64; 2],
    radius: f64,
    angle: f64,
    z_from: f64,
    z_to: f64,
    feed: f64,
) {
    let start = [centre[0] + radius, centre[1]];
    b.line([start[0], start[1], z_from], feed);
    let per_turn = TAU * radius * angle.tan();
    let turns = ((z_from - z_to) / per_turn).ceil().max(1.0) as usize;
    for k in 1..=turns {
        let z = z_from - (z_from - z_to) * k as f64 / turns as f64;
        b.push(Move::Arc {
            to: [start[0], start[1], z],
            center: centre,
            ccw: true,
            feed,
        });
    }
    b.push(Move::Arc {
        to: [start[0], start[1], z_to],
        center: centre,
        ccw: true,
        feed,
    });
}
