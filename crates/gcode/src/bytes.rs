//! Byte search eight bytes at a time: finding the end of each line and scanning a whole
//! program for `<_` are on the path of every byte read, where a byte-by-byte loop costs
//! more than the parsing itself.

const LOW: u64 = 0x0101_0101_0101_0101;
const HIGH: u64 = 0x8080_8080_8080_8080;

/// Position of the first `needle` in `hay`.
pub(crate) fn find_byte(needle: u8, hay: &[u8]) -> Option<usize> {
    let pattern = LOW * u64::from(needle);
    let mut chunks = hay.chunks_exact(8);
    let mut base = 0;
    for chunk in &mut chunks {
        let word = u64::from_le_bytes(chunk.try_into().unwrap_or([0; 8]));
        let x = word ^ pattern;
        // A zero byte of x is a match; the lowest flagged byte is always a true one.
        let found = x.wrapping_sub(LOW) & !x & HIGH;
        if found != 0 {
            return Some(base + (found.trailing_zeros() / 8) as usize);
        }
        base += 8;
    }
    chunks
        .remainder()
        .iter()
        .position(|&b| b == needle)
        .map(|i| base + i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_first_occurrence_like_a_plain_search() {
        let hay: Vec<u8> = (0..100u8).map(|i| i.wrapping_mul(37) % 61).collect();
        for needle in 0..70u8 {
            for start in 0..20 {
                for end in start..hay.len() {
                    let h = &hay[start..end];
                    assert_eq!(
                        find_byte(needle, h),
                        h.iter().position(|&b| b == needle),
                        "{needle} in {start}..{end}"
                    );
                }
            }
        }
        assert_eq!(find_byte(b'\n', &[0x80, 0x0a, 0x0a]), Some(1));
        assert_eq!(find_byte(0x80, &[1, 0x81, 0x80, 0, 0, 0, 0, 0, 0]), Some(2));
    }
}
