//! The interpolators of seed 002 (Goellner, 2006): the vector-normalised linear DDA and the
//! cross-coupled circular DDA, on integer step counts. They give the step *order*; timing is
//! one iteration per slot (linear) or per emitted step (circular, see the digest §10.3).

/// Steps of one linear-DDA iteration: per axis −1, 0 or +1.
pub(crate) type Tick = [i8; 3];

/// Linear DDA over up to three axes. `faithful` reproduces the seed exactly (accumulators start
/// at n, strict "greater than"); otherwise accumulators start at L/2 (smaller deviation).
pub(crate) struct LinearDda {
    n: [i64; 3],
    sign: [i8; 3],
    acc: [i64; 3],
    done: [i64; 3],
    limit: i64,
    faithful: bool,
}

impl LinearDda {
    pub(crate) fn new(delta: [i64; 3], faithful: bool) -> LinearDda {
        let n = delta.map(|d| d.abs());
        let limit = ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) as f64)
            .sqrt()
            .floor() as i64;
        let acc = if faithful { n } else { [limit / 2; 3] };
        LinearDda {
            n,
            sign: delta.map(|d| d.signum() as i8),
            acc,
            done: [0; 3],
            limit,
            faithful,
        }
    }

    /// `Limite` of the seed: ⌊√(Σn²)⌋, the number of iterations.
    #[cfg(test)]
    pub(crate) fn limit(&self) -> i64 {
        self.limit
    }
}

impl Iterator for LinearDda {
    type Item = Tick;
    fn next(&mut self) -> Option<Tick> {
        if (0..3).all(|i| self.done[i] >= self.n[i]) {
            return None;
        }
        let mut tick = [0i8; 3];
        for i in 0..3 {
            if self.done[i] >= self.n[i] {
                continue;
            }
            self.acc[i] += self.n[i];
            let fire = if self.faithful {
                self.acc[i] > self.limit
            } else {
                self.acc[i] >= self.limit
            };
            if fire {
                self.acc[i] -= self.limit;
                self.done[i] += 1;
                tick[i] = self.sign[i];
            }
        }
        Some(tick)
    }
}

/// One iteration of the seed's worked circular example (Table 11), in its own terms:
/// absolute coordinates, ΔX = K·CoordY, ΔY = K·CoordX, step when the sum reaches the limit.
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TableRow {
    pub iteration: u32,
    pub sum_x: f64,
    pub sum_y: f64,
    pub step_x: bool,
    pub step_y: bool,
    pub coord: (i64, i64),
}

/// Replays Table 11: a clockwise arc from `start` (absolute, first quadrant) with radius `r`,
/// for `iterations` iterations. Kept only to prove the reading of the seed; use
/// [`CircularDda`] for real arcs.
#[cfg(test)]
pub(crate) fn seed_table_11(start: (i64, i64), r: f64, iterations: u32) -> Vec<TableRow> {
    let k = 1.0 / r;
    let limit = (2.0 * r * r).sqrt();
    let (mut x, mut y) = start;
    let (mut sx, mut sy) = (0.0, 0.0);
    let (mut dx, mut dy) = (k * y as f64, k * x as f64);
    let mut rows = Vec::with_capacity(iterations as usize);
    for it in 1..=iterations {
        sx += dx;
        sy += dy;
        let (mut step_x, mut step_y) = (false, false);
        if sx >= limit {
            sx -= limit;
            x += 1;
            step_x = true;
        }
        if sy >= limit {
            sy -= limit;
            y -= 1;
            step_y = true;
        }
        // Increments follow the new coordinates from the next iteration on.
        dx = k * y as f64;
        dy = k * x as f64;
        rows.push(TableRow {
            iteration: it,
            sum_x: sx,
            sum_y: sy,
            step_x,
            step_y,
            coord: (x, y),
        });
    }
    rows
}

/// The circular DDA with centre-relative signed coordinates (the corrected form of seed
/// 002 §4.3): clockwise, X integrates K·Y and steps by the sign of its overflow; Y integrates
/// K·X and steps against it; counter-clockwise reverses both. It ends on the end point, or
/// snaps to it when the step budget runs out.
pub(crate) struct CircularDda {
    pos: (i64, i64),
    end: (i64, i64),
    k: f64,
    limit: f64,
    sum: (f64, f64),
    cw: bool,
    budget: u64,
    moved: bool,
    /// Angle swept so far and the angle to sweep (radians, positive).
    swept: f64,
    sweep: f64,
    snapping: bool,
}

impl CircularDda {
    /// `start` and `end` relative to the centre, in steps.
    pub(crate) fn new(start: (i64, i64), end: (i64, i64), cw: bool, sweep: f64) -> CircularDda {
        let r = ((start.0 * start.0 + start.1 * start.1) as f64)
            .sqrt()
            .max(1.0);
        let limit = (2.0 * r * r).sqrt();
        // About R·√2 iterations per step and ≤ √2·R·|sweep| steps along the arc.
        let budget = ((sweep.abs() * r * 2.0 + 8.0) * (limit + 2.0)) as u64;
        CircularDda {
            pos: start,
            end,
            k: 1.0 / r,
            limit,
            sum: (0.0, 0.0),
            cw,
            budget,
            moved: false,
            swept: 0.0,
            sweep: sweep.abs(),
            snapping: false,
        }
    }

    #[cfg(test)]
    pub(crate) fn position(&self) -> (i64, i64) {
        self.pos
    }

    /// True when the rest of the arc crosses no axis (where X or Y reaches an extreme), so
    /// both coordinates only move towards the end point.
    fn monotonic_to_end(&self) -> bool {
        let quarter = std::f64::consts::FRAC_PI_2;
        let angle = (self.pos.1 as f64).atan2(self.pos.0 as f64);
        // Angle to the next axis strictly ahead in the direction of travel, in (0, π/2].
        let to_axis = if self.cw {
            angle - ((angle / quarter).ceil() - 1.0) * quarter
        } else {
            ((angle / quarter).floor() + 1.0) * quarter - angle
        };
        to_axis >= self.sweep - self.swept - 1e-9
    }
}

impl Iterator for CircularDda {
    /// One emitted step: (dx, dy), each −1, 0 or +1.
    type Item = (i8, i8);
    fn next(&mut self) -> Option<(i8, i8)> {
        loop {
            if self.moved && self.pos == self.end {
                return None;
            }
            if self.budget == 0 || self.snapping {
                self.snapping = true;
                // Snap: walk straight to the end point, one step at a time.
                let dx = (self.end.0 - self.pos.0).signum();
                let dy = (self.end.1 - self.pos.1).signum();
                if dx == 0 && dy == 0 {
                    return None;
                }
                self.pos.0 += dx;
                self.pos.1 += dy;
                return Some((dx as i8, dy as i8));
            }
            self.budget -= 1;
            let dir = if self.cw { 1.0 } else { -1.0 };
            self.sum.0 += dir * self.k * self.pos.1 as f64;
            self.sum.1 += dir * self.k * self.pos.0 as f64;
            let (mut dx, mut dy) = (0i8, 0i8);
            if self.sum.0.abs() >= self.limit {
                let s = self.sum.0.signum();
                self.sum.0 -= s * self.limit;
                dx = s as i8;
            }
            if self.sum.1.abs() >= self.limit {
                let s = self.sum.1.signum();
                self.sum.1 -= s * self.limit;
                dy = -s as i8;
            }
            // On the last stretch, where neither coordinate turns back before the end, a step
            // past the end coordinate would only be undone by the snap: drop it.
            if self.monotonic_to_end() {
                if (self.end.0 - self.pos.0 - dx as i64).abs() > (self.end.0 - self.pos.0).abs() {
                    dx = 0;
                }
                if (self.end.1 - self.pos.1 - dy as i64).abs() > (self.end.1 - self.pos.1).abs() {
                    dy = 0;
                }
            }
            if dx != 0 || dy != 0 {
                let old = self.pos;
                self.pos.0 += dx as i64;
                self.pos.1 += dy as i64;
                self.moved = true;
                // Past the end angle the stepped path missed the end point by a step: snap.
                let cross = (old.0 * self.pos.1 - old.1 * self.pos.0) as f64;
                let dot = (old.0 * self.pos.0 + old.1 * self.pos.1) as f64;
                self.swept += if self.cw {
                    -cross.atan2(dot)
                } else {
                    cross.atan2(dot)
                };
                if self.swept >= self.sweep - 1e-9 {
                    self.snapping = true;
                }
                return Some((dx, dy));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_8_every_iteration_steps_x() {
        let ticks: Vec<Tick> = LinearDda::new([20, 0, 0], true).collect();
        assert_eq!(ticks.len(), 20);
        assert!(ticks.iter().all(|t| *t == [1, 0, 0]));
    }

    #[test]
    fn table_9_x10_y7_reproduced_exactly() {
        let d = LinearDda::new([10, 7, 0], true);
        assert_eq!(d.limit(), 12);
        let ticks: Vec<Tick> = d.collect();
        assert_eq!(ticks.len(), 12);
        let xs: Vec<usize> = (0..12)
            .filter(|&i| ticks[i][0] == 1)
            .map(|i| i + 1)
            .collect();
        let ys: Vec<usize> = (0..12)
            .filter(|&i| ticks[i][1] == 1)
            .map(|i| i + 1)
            .collect();
        assert_eq!(xs, vec![1, 2, 3, 4, 6, 7, 8, 9, 10, 12]);
        assert_eq!(ys, vec![1, 3, 5, 6, 8, 10, 12]);
    }

    #[test]
    fn table_11_first_overflows() {
        // G2 from X2 Y11 to X11 Y2 about X1 Y1, R = 11 − 1 = 10, limit √200.
        let rows = seed_table_11((2, 11), 10.0, 44);
        let xs: Vec<(u32, f64)> = rows
            .iter()
            .filter(|r| r.step_x)
            .map(|r| (r.iteration, r.sum_x))
            .collect();
        let ys: Vec<(u32, f64)> = rows
            .iter()
            .filter(|r| r.step_y)
            .map(|r| (r.iteration, r.sum_y))
            .collect();
        assert_eq!(xs.iter().map(|x| x.0).collect::<Vec<_>>(), vec![13, 26, 39]);
        // The seed prints remainders truncated to two decimals: 0,15 · 0,31 · 0,47 · 0,05.
        let trunc = |v: f64| (v * 100.0).floor() / 100.0;
        assert_eq!(
            xs.iter().map(|x| trunc(x.1)).collect::<Vec<_>>(),
            vec![0.15, 0.31, 0.47]
        );
        assert_eq!(ys, vec![(44, ys[0].1)]);
        assert_eq!(trunc(ys[0].1), 0.05);
        assert_eq!(rows[43].coord, (5, 10));
    }

    #[test]
    fn circular_dda_quarter_circles_of_test_1() {
        // Program 1's arcs: CW quarter circles of radius 80 and 160 steps about the origin.
        for &(s, e, r) in &[
            ((0, -80), (-80, 0), 80.0),
            ((-160, 0), (0, 160), 160.0),
            ((0, 80), (80, 0), 80.0),
        ] {
            let mut d = CircularDda::new(s, e, true, std::f64::consts::FRAC_PI_2);
            let mut worst: f64 = 0.0;
            let mut n = 0;
            while let Some(_) = d.next() {
                let p = d.position();
                worst = worst.max(((p.0 * p.0 + p.1 * p.1) as f64).sqrt() - r);
                n += 1;
            }
            assert_eq!(d.position(), e);
            assert!(worst.abs() <= 1.5, "radial error {worst}");
            assert!(n as f64 >= r * 1.4 && (n as f64) <= r * 2.1, "{n} steps");
        }
    }

    #[test]
    fn quarter_arcs_between_axes_step_each_axis_one_way_only() {
        // Test 1's quarter circles at 100 steps/mm, CW and CCW: no step past the end point
        // (which the snap would undo), so each motor steps exactly its displacement.
        for &(s, e) in &[
            ((0, -8000), (-8000, 0)),
            ((-16000, 0), (0, 16000)),
            ((0, 8000), (8000, 0)),
            ((16000, 0), (0, -16000)),
        ] {
            for (from, to, cw) in [(s, e, true), (e, s, false)] {
                let d = CircularDda::new(from, to, cw, std::f64::consts::FRAC_PI_2);
                let (mut moved, mut signs) = ((0i64, 0i64), (0i8, 0i8));
                for (dx, dy) in d {
                    moved.0 += dx.abs() as i64;
                    moved.1 += dy.abs() as i64;
                    for (d, sign) in [(dx, &mut signs.0), (dy, &mut signs.1)] {
                        assert!(
                            d == 0 || *sign == 0 || d == *sign,
                            "{from:?}→{to:?} reverses"
                        );
                        if d != 0 {
                            *sign = d;
                        }
                    }
                }
                assert_eq!(moved, ((to.0 - from.0).abs(), (to.1 - from.1).abs()));
            }
        }
    }
}
