//! `bench gcode`'s inputs: two deterministic programs, a mixed one (G1/G2/G3 with
//! parameters and expressions, the work a real interpreter does) and a plain one (`G1 X… Y…`
//! lines only, which measures raw reading speed). The same program on every machine, so
//! figures from different runs compare.

use std::io::Write;

/// A small deterministic generator (SplitMix64): the same program on every machine.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Rounds to the 4 decimals the program is written with, so the generator tracks exactly the
/// point the interpreter will be at.
fn r4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

/// Writes the mixed program: `blocks` lines in all, ending with M2. Arcs are built from the
/// current (rounded) point so their end radius matches the start radius within rounding.
/// One block in twenty is a spline: a G5 cubic, a G5.1 quadratic or a G5.2 … G5.3 NURBS of
/// four weighted points (five lines), which rs274 reads and Oficina also flattens into feeds.
pub fn write_mixed_program(out: &mut impl Write, blocks: u64) -> std::io::Result<()> {
    let mut rng = SplitMix(0x0f1c_1a00);
    writeln!(out, "G21 G17 G90 G94 F1500")?;
    writeln!(
        out,
        "#1 = 0 (exact zero: keeps expression results exactly on the written value)"
    )?;
    writeln!(out, "#<scale> = 1")?;
    let (mut x, mut y) = (0.0f64, 0.0f64);
    let last = blocks.saturating_sub(1);
    let mut n = 3;
    while n < last {
        let kind = rng.next() % 10;
        // Pull the walk back towards the origin so coordinates stay small.
        let bias = |v: f64| {
            if v > 50.0 {
                -1.0
            } else if v < -50.0 {
                1.0
            } else {
                0.0
            }
        };
        match kind {
            0..=4 => {
                x = r4(x + rng.range(-5.0, 5.0) + bias(x) * 5.0);
                y = r4(y + rng.range(-5.0, 5.0) + bias(y) * 5.0);
                let z = r4(rng.range(-2.0, 0.0));
                match n % 3 {
                    0 => writeln!(out, "G1 X{x:.4} Y{y:.4} Z{z:.4}")?,
                    1 => writeln!(out, "G1 X[{x:.4} + #1] Y[{y:.4} * #<scale>]")?,
                    _ => writeln!(out, "G1 X[{x:.4} - #1] Y{y:.4} F[1000 + {}]", n % 500)?,
                }
            }
            5..=8 => {
                let radius = rng.range(1.0, 6.0);
                let start_angle = rng.range(0.0, std::f64::consts::TAU);
                let sweep = rng.range(0.3, 2.5);
                let (cx, cy) = (
                    x - radius * start_angle.cos(),
                    y - radius * start_angle.sin(),
                );
                let (i, j) = (r4(cx - x), r4(cy - y));
                let (cx, cy) = (x + i, y + j);
                let r = (i * i + j * j).sqrt();
                let clockwise = kind.is_multiple_of(2);
                let end_angle = start_angle + if clockwise { -sweep } else { sweep };
                let (ex, ey) = (r4(cx + r * end_angle.cos()), r4(cy + r * end_angle.sin()));
                let code = if clockwise { "G2" } else { "G3" };
                writeln!(out, "{code} X{ex:.4} Y{ey:.4} I[{i:.4} + #1] J{j:.4}")?;
                x = ex;
                y = ey;
            }
            _ if n % 2 == 1 => {
                let lines = write_spline(out, &mut rng, &mut x, &mut y, n, last - n)?;
                n += lines - 1;
            }
            _ => writeln!(out, "#<scale> = [ABS[SIN[{}]] * 0 + 1]", n % 360)?,
        }
        n += 1;
    }
    writeln!(out, "M2")
}

/// One spline from (x, y), which it moves to the curve's end; the lines written (at most
/// `room`). The curve stays within about 6 mm of its start; every point is rounded as
/// written, so the next block starts exactly where the interpreter is.
fn write_spline(
    out: &mut impl Write,
    rng: &mut SplitMix,
    x: &mut f64,
    y: &mut f64,
    n: u64,
    room: u64,
) -> std::io::Result<u64> {
    let step = |v: f64, rng: &mut SplitMix| r4(v + rng.range(-5.0, 5.0) - v.signum() * 0.5);
    let (ex, ey) = (step(*x, rng), step(*y, rng));
    let (i, j) = (r4(rng.range(-3.0, 3.0)), r4(rng.range(-3.0, 3.0)));
    let lines = match n % 3 {
        0 => {
            let (p, q) = (r4(rng.range(-3.0, 3.0)), r4(rng.range(-3.0, 3.0)));
            writeln!(out, "G5 X{ex:.4} Y{ey:.4} I{i:.4} J{j:.4} P{p:.4} Q{q:.4}")?;
            (*x, *y) = (ex, ey);
            1
        }
        1 => {
            writeln!(out, "G5.1 X{ex:.4} Y{ey:.4} I{i:.4} J{j:.4}")?;
            (*x, *y) = (ex, ey);
            1
        }
        _ if room >= 5 => {
            // Four control points after the start, order 3, one heavier weight.
            for k in 0..4 {
                let (px, py) = (step(*x, rng), step(*y, rng));
                let w = if k == 1 { 2.0 } else { 1.0 };
                match k {
                    0 => writeln!(out, "G5.2 X{px:.4} Y{py:.4} P{w} L3")?,
                    _ => writeln!(out, "X{px:.4} Y{py:.4} P{w}")?,
                }
                (*x, *y) = (px, py);
            }
            writeln!(out, "G5.3")?;
            5
        }
        _ => {
            writeln!(out, "G5.1 X{ex:.4} Y{ey:.4} I{i:.4} J{j:.4}")?;
            (*x, *y) = (ex, ey);
            1
        }
    };
    Ok(lines)
}

/// Writes `blocks` plain `G1 X… Y…` lines (first line sets units and feed, last is M2).
pub fn write_plain_program(out: &mut impl Write, blocks: u64) -> std::io::Result<()> {
    let mut rng = SplitMix(0x9a1b_2c3d);
    writeln!(out, "G21 G90 G94 F2000")?;
    for _ in 1..blocks.saturating_sub(1) {
        writeln!(
            out,
            "G1 X{:.4} Y{:.4}",
            rng.range(-100.0, 100.0),
            rng.range(-100.0, 100.0)
        )?;
    }
    writeln!(out, "M2")
}
