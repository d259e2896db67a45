//! The probe routines' refusals: numbers that are not numbers, out of range, or a probing
//! move the link would not wait for.

use super::{Approach, ProbeError, ProbeLink};

/// The longest travel, size or offset a routine accepts, mm.
pub(super) const MAX_TRAVEL: f64 = 1000.0;
/// The fastest feed a routine accepts, mm/min.
const MAX_FEED: f64 = 100_000.0;

impl Approach {
    /// Its search and its touch each end within what `link` waits for a reply.
    pub(super) fn fits<L: ProbeLink + ?Sized>(&self, link: &L) -> Result<(), ProbeError> {
        fits(link, self.travel, self.feed)?;
        fits(link, 2.0 * self.retract, self.slow_feed)
    }

    pub(super) fn check(&self) -> Result<(), ProbeError> {
        check_range("travel", self.travel, 0.0, MAX_TRAVEL)?;
        check_positive("travel", self.travel)?;
        check_positive("retract", self.retract)?;
        check_range("retract", self.retract, 0.0, MAX_TRAVEL / 2.0)?;
        for (what, f) in [("feed", self.feed), ("slow feed", self.slow_feed)] {
            check_positive(what, f)?;
            check_range(what, f, 0.0, MAX_FEED)?;
        }
        Ok(())
    }
}

/// A probing move of `distance` at `feed` ends within what `link` waits for a reply
/// (with two seconds for acceleration and the reply), or it is refused before anything
/// moves: the firmware would still be moving when the link gave up.
pub(super) fn fits<L: ProbeLink + ?Sized>(
    link: &L,
    distance: f64,
    feed: f64,
) -> Result<(), ProbeError> {
    let seconds = distance / feed * 60.0;
    match link.longest_wait() {
        Some(limit) if seconds + 2.0 > limit.as_secs_f64() => Err(ProbeError::Input(format!(
            "a probing move of {distance} mm at F{feed} may take {seconds:.0} s, longer than this link waits for a reply ({} s): raise the feed or shorten the travel",
            limit.as_secs()
        ))),
        _ => Ok(()),
    }
}

pub(super) fn check_range(what: &str, v: f64, lo: f64, hi: f64) -> Result<(), ProbeError> {
    if !v.is_finite() {
        return Err(ProbeError::Input(format!(
            "{what} must be a number, got {v}"
        )));
    }
    if v < lo || v > hi {
        return Err(ProbeError::Input(format!(
            "{what} {v} is outside {lo} … {hi}"
        )));
    }
    Ok(())
}

pub(super) fn check_positive(what: &str, v: f64) -> Result<(), ProbeError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ProbeError::Input(format!(
            "{what} must be more than 0, got {v}"
        )))
    }
}

pub(super) fn check_thickness(t: f64) -> Result<(), ProbeError> {
    if t.is_finite() && t < 0.0 {
        return Err(ProbeError::Input(format!(
            "plate thickness cannot be negative, got {t} mm"
        )));
    }
    check_range("plate thickness", t, 0.0, MAX_TRAVEL)
}

pub(super) fn check_wcs(wcs: u8) -> Result<(), ProbeError> {
    if (1..=6).contains(&wcs) {
        Ok(())
    } else {
        Err(ProbeError::Input(format!(
            "coordinate system {wcs}: grbl has 1 (G54) … 6 (G59)"
        )))
    }
}
