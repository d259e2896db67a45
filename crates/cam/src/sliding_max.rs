//! Running maximum over a fixed-length window (van Herk / Gil-Werman): block prefix and
//! suffix maxima give every window's maximum in three compares per element, whatever the
//! window's length. Flat pieces of a tool (flat bottom, shank) need nothing else.

/// `out[s] = max(src[s .. s + len])` for every start `s` with the window inside `src`
/// (`out` has `src.len() + 1 − len` entries; none when `len` is 0 or too long).
pub(crate) fn window_max(src: &[f32], len: usize, out: &mut Vec<f32>) {
    out.clear();
    let n = src.len();
    if len == 0 || len > n {
        return;
    }
    if len == 1 {
        out.extend_from_slice(src);
        return;
    }
    let mut prefix = vec![f32::NEG_INFINITY; n];
    let mut suffix = vec![f32::NEG_INFINITY; n];
    for start in (0..n).step_by(len) {
        let end = (start + len).min(n);
        let mut m = f32::NEG_INFINITY;
        for i in start..end {
            m = m.max(src[i]);
            prefix[i] = m;
        }
        m = f32::NEG_INFINITY;
        for i in (start..end).rev() {
            m = m.max(src[i]);
            suffix[i] = m;
        }
    }
    out.extend((0..=n - len).map(|s| suffix[s].max(prefix[s + len - 1])));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_window_gets_its_maximum() {
        let src: Vec<f32> = (0..50).map(|i| ((i * 37) % 11) as f32).collect();
        let mut out = Vec::new();
        for len in 1..13 {
            window_max(&src, len, &mut out);
            assert_eq!(out.len(), src.len() + 1 - len);
            for (s, &got) in out.iter().enumerate() {
                let want = src[s..s + len].iter().cloned().fold(f32::MIN, f32::max);
                assert_eq!(got, want, "len {len} at {s}");
            }
        }
        window_max(&src, 51, &mut out);
        assert!(out.is_empty());
    }
}
