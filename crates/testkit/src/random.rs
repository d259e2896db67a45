//! The seeded pseudo-random numbers the tests draw their workloads from: Marsaglia's
//! xorshift64 (shifts 13, 7, 17), the same sequence on every machine and run.

/// A xorshift64 generator; the seed must not be 0 (the sequence would stay 0).
pub struct Xorshift(u64);

impl Xorshift {
    /// A generator starting from `seed` (not 0).
    pub fn new(seed: u64) -> Xorshift {
        assert_ne!(seed, 0, "xorshift needs a seed other than 0");
        Xorshift(seed)
    }

    /// The next 64-bit state.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// The next number in [0, 1): the state's top 53 bits over 2^53.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sequence_is_marsaglias_xorshift64() {
        // x ^= x << 13; x ^= x >> 7; x ^= x << 17 from 1, written out by hand.
        let mut r = Xorshift::new(1);
        let mut x: u64 = 1;
        for _ in 0..5 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            assert_eq!(r.next_u64(), x);
        }
        let u = Xorshift::new(0x9e37_79b9_7f4a_7c15).unit();
        assert!((0.0..1.0).contains(&u));
    }
}
