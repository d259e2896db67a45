//! Durations as the CLI prints them: `h:mm:ss`, optionally with decimals of a second.

/// Seconds as `h:mm:ss` with `decimals` digits after the seconds (0 → `1:02:03`,
/// 1 → `1:02:03.4`). Rounds once, to the last digit shown, before splitting, so 59.96 s with
/// one decimal reads `0:01:00.0`, never `0:00:60.0`. Negative durations read as zero.
///
/// ```
/// use oficina_motion::format_hms;
/// assert_eq!(format_hms(3723.4, 0), "1:02:03");
/// assert_eq!(format_hms(3723.44, 1), "1:02:03.4");
/// assert_eq!(format_hms(59.96, 1), "0:01:00.0");
/// ```
pub fn format_hms(seconds: f64, decimals: usize) -> String {
    let decimals = decimals.min(9);
    let scale = 10u64.pow(decimals as u32);
    // `as` saturates: NaN and negatives read 0, absurd lengths the largest u64.
    let t = (seconds.max(0.0) * scale as f64).round() as u64;
    let (whole, frac) = (t / scale, t % scale);
    let hms = format!("{}:{:02}:{:02}", whole / 3600, whole / 60 % 60, whole % 60);
    if decimals == 0 {
        hms
    } else {
        format!("{hms}.{frac:0decimals$}")
    }
}

#[cfg(test)]
mod tests {
    use super::format_hms;

    #[test]
    fn hours_minutes_seconds_and_tenths() {
        assert_eq!(format_hms(0.0, 0), "0:00:00");
        assert_eq!(format_hms(59.5, 0), "0:01:00");
        assert_eq!(format_hms(36_000.0 + 61.0, 0), "10:01:01");
        assert_eq!(format_hms(5.25, 1), "0:00:05.3");
        assert_eq!(format_hms(-3.0, 1), "0:00:00.0");
        assert_eq!(format_hms(f64::NAN, 0), "0:00:00");
        assert_eq!(format_hms(1.5, 3), "0:00:01.500");
    }
}
