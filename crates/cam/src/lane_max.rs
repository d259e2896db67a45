//! The hot loop of drop-cutter: for a block of `LANES` neighbouring output samples, the max
//! over one kernel row of `source − lift`. The accumulators stay in registers for the whole
//! row (fixed-size arrays the compiler turns into vector registers), so each offset costs one
//! unaligned load, a subtract and a max per vector. AVX2 is used when the CPU has it.

/// Output samples handled together: four AVX2 vectors.
pub(crate) const LANES: usize = 32;

/// `acc[l] = max(acc[l], src[base + dx + l] − lift)` over every `(dx, lift)` in `offsets`.
/// `base + dx` must stay in `0..=src.len() − LANES` (the caller pads the rows).
pub(crate) fn fold_offsets(
    acc: &mut [f32; LANES],
    src: &[f32],
    base: usize,
    offsets: &[(i32, f32)],
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above); the body is safe Rust.
            unsafe { fold_avx2(acc, src, base, offsets) };
            return;
        }
    }
    fold_generic(acc, src, base, offsets);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn fold_avx2(acc: &mut [f32; LANES], src: &[f32], base: usize, offsets: &[(i32, f32)]) {
    fold_generic(acc, src, base, offsets);
}

#[inline(always)]
fn fold_generic(acc: &mut [f32; LANES], src: &[f32], base: usize, offsets: &[(i32, f32)]) {
    let mut a = *acc;
    for &(dx, lift) in offsets {
        let start = (base as isize + dx as isize) as usize;
        let s: &[f32; LANES] = src[start..start + LANES].try_into().expect("LANES long");
        for l in 0..LANES {
            // A plain compare (not f32::max) so it compiles to one vector max.
            let v = s[l] - lift;
            if v > a[l] {
                a[l] = v;
            }
        }
    }
    *acc = a;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_every_offset_into_every_lane() {
        let src: Vec<f32> = (0..100).map(|i| ((i * 29) % 17) as f32 * 0.5).collect();
        let offsets = [(-3, 0.25f32), (0, 0.0), (2, 1.5), (7, -0.5)];
        let mut acc = [f32::NEG_INFINITY; LANES];
        acc[5] = 100.0;
        fold_offsets(&mut acc, &src, 10, &offsets);
        for (l, &got) in acc.iter().enumerate() {
            let mut want = if l == 5 { 100.0 } else { f32::NEG_INFINITY };
            for &(dx, lift) in &offsets {
                want = want.max(src[(10 + dx + l as i32) as usize] - lift);
            }
            assert_eq!(got, want, "lane {l}");
        }
    }
}
