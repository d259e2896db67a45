//! Raster passes over a tool-tip surface: which samples of a row need cutting, how to
//! merge them into few straight feeds that never dip below the surface, and how to travel
//! between them with the least air time.

use crate::toolpath::Move;

/// Known-free tip heights: the tool at or above this height touches no stock.
pub(crate) enum Clear<'a> {
    /// Fresh stock with its top at this height.
    Top(f32),
    /// A grid (same size as the raster grid) from the simulated stock.
    Grid { width: usize, z: &'a [f32] },
}

impl Clear<'_> {
    pub(crate) fn at(&self, ix: usize, iy: usize) -> f32 {
        match self {
            Clear::Top(z) => *z,
            Clear::Grid { width, z } => z[iy * width + ix],
        }
    }
}

/// Cutting data in internal units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feeds {
    /// mm/s
    pub cut: f64,
    /// mm/s, for going down into material.
    pub plunge: f64,
    /// mm/s, what a rapid is assumed to achieve when choosing between lifting and feeding.
    pub rapid: f64,
}

/// One raster row: the samples' tip heights to reach and the known-free heights.
pub(crate) struct Row {
    /// Grid row index (in the raster's own, possibly transposed, grid).
    pub index: usize,
    pub target: Vec<f32>,
    pub clear: Vec<f32>,
    /// Samples the pass may visit (a rest-machining region); `None` = all.
    pub allowed: Option<Vec<bool>>,
}

/// Rows spaced at most `stepover` mm apart, first and last rows included.
pub(crate) fn raster_rows(count: usize, pixel: f64, stepover: f64) -> Vec<usize> {
    if count == 0 {
        return Vec::new();
    }
    let span = (count - 1) as f64 * pixel;
    // Never more rows than the grid has (an infinite span must not ask for more).
    let n = (span / stepover.max(pixel))
        .ceil()
        .clamp(1.0, (count - 1).max(1) as f64) as usize;
    let mut rows: Vec<usize> = (0..=n)
        .map(|i| ((i * (count - 1)) as f64 / n as f64).round() as usize)
        .collect();
    rows.dedup();
    rows
}

/// Inclusive sample ranges where `target < clear − min_cut`, each grown by one sample so
/// the tool enters and leaves on already-free ground.
pub(crate) fn cut_runs(row: &Row, min_cut: f32) -> Vec<(usize, usize)> {
    let n = row.target.len();
    let allowed = |i: usize| row.allowed.as_ref().is_none_or(|a| a[i]);
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut i = 0;
    while i < n {
        if allowed(i) && row.target[i] < row.clear[i] - min_cut {
            let start = i;
            while i < n && allowed(i) && row.target[i] < row.clear[i] - min_cut {
                i += 1;
            }
            let (a, b) = (start.saturating_sub(1), i.min(n - 1));
            match runs.last_mut() {
                Some(last) if last.1 + 1 >= a => last.1 = b,
                _ => runs.push((a, b)),
            }
        } else {
            i += 1;
        }
    }
    runs
}

/// Vertices `(sample index, height)` of a polyline over the samples that stays on or above
/// every sample and at most `tol` above it (one-sided: never below). Vertices may sit
/// anywhere in that band, not only on the samples: on a dome (concave) a chord between two
/// samples dips under the ones between, so vertices pinned to the samples would keep every
/// one of them there. Greedy: each segment runs as far as a slope exists that keeps every
/// sample so far inside its band (a shrinking window of slopes, linear per segment), and
/// takes the lowest such slope. The first vertex is on the first sample.
pub(crate) fn simplify(z: &[f32], tol: f64, out: &mut Vec<(usize, f64)>) {
    out.clear();
    let Some(&first) = z.first() else { return };
    let (mut a, mut za) = (0usize, first as f64);
    out.push((a, za));
    while a + 1 < z.len() {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut end, mut slope) = (a + 1, 0.0);
        for (j, &zj) in z.iter().enumerate().skip(a + 1) {
            let d = (j - a) as f64;
            let (nlo, nhi) = (
                lo.max((zj as f64 - za) / d),
                hi.min((zj as f64 + tol - za) / d),
            );
            if nlo > nhi {
                break;
            }
            (lo, hi, end, slope) = (nlo, nhi, j, nlo);
        }
        // Never below the end sample, whatever the rounding of the slope.
        let zb = (za + slope * (end - a) as f64).max(z[end] as f64);
        out.push((end, zb));
        (a, za) = (end, zb);
    }
}

/// Builds moves for a sequence of strokes, choosing for each gap between them whether to
/// stay down or to lift.
pub(crate) struct Emitter {
    pub moves: Vec<Move>,
    pub pos: Option<[f64; 3]>,
    pub feeds: Feeds,
    pub safe_z: f64,
    /// Height above known-free stock at which short travels happen.
    pub clearance: f64,
}

impl Emitter {
    pub(crate) fn new(feeds: Feeds, safe_z: f64, clearance: f64) -> Emitter {
        Emitter {
            moves: Vec::new(),
            pos: None,
            feeds,
            safe_z,
            clearance,
        }
    }

    /// Lifts to `travel_z`, crosses to above `to`, comes down fast to `free_z + clearance`
    /// and plunges at the plunge feed.
    pub(crate) fn travel(&mut self, to: [f64; 3], travel_z: f64, free_z: f64) {
        let Some(from) = self.pos else {
            self.moves.push(Move::Rapid {
                to: [to[0], to[1], self.safe_z],
            });
            self.pos = Some([to[0], to[1], self.safe_z]);
            return self.travel(to, self.safe_z, free_z);
        };
        let h = travel_z
            .max(from[2])
            .max(to[2])
            .min(self.safe_z.max(from[2]));
        if h > from[2] {
            self.moves.push(Move::Rapid {
                to: [from[0], from[1], h],
            });
        }
        if from[0] != to[0] || from[1] != to[1] {
            self.moves.push(Move::Rapid {
                to: [to[0], to[1], h],
            });
        }
        let approach = (free_z + self.clearance).min(h).max(to[2]);
        if approach < h {
            self.moves.push(Move::Rapid {
                to: [to[0], to[1], approach],
            });
        }
        if to[2] < approach {
            self.moves.push(Move::Line {
                to,
                feed: self.feeds.plunge,
            });
        }
        self.pos = Some(to);
    }

    /// Straight feeds through `points`; steep descents go at the plunge feed.
    pub(crate) fn feed_through(&mut self, points: &[[f64; 3]]) {
        for &p in points {
            let from = self.pos.unwrap_or(p);
            let run = ((p[0] - from[0]).powi(2) + (p[1] - from[1]).powi(2)).sqrt();
            let drop = from[2] - p[2];
            let feed = if drop > run {
                self.feeds.plunge
            } else {
                self.feeds.cut
            };
            if p != from {
                self.moves.push(Move::Line { to: p, feed });
            }
            self.pos = Some(p);
        }
    }

    /// Retract to safe Z.
    pub(crate) fn retract(&mut self) {
        if let Some(p) = self.pos {
            if p[2] < self.safe_z {
                self.moves.push(Move::Rapid {
                    to: [p[0], p[1], self.safe_z],
                });
                self.pos = Some([p[0], p[1], self.safe_z]);
            }
        }
    }
}

/// Geometry of the raster grid: spacing, whether rows run along Y (transposed grid) and how
/// many samples a row has per pixel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    pub pixel: f64,
    pub along_y: bool,
    pub sub: usize,
}

impl Frame {
    /// Distance between samples along a row, mm.
    pub(crate) fn step(&self) -> f64 {
        self.pixel / self.sub as f64
    }

    pub(crate) fn point(&self, row: usize, sample: usize, z: f64) -> [f64; 3] {
        let a = sample as f64 * self.pixel / self.sub as f64;
        let b = row as f64 * self.pixel;
        if self.along_y {
            [b, a, z]
        } else {
            [a, b, z]
        }
    }
}

/// Cuts the rows (already in visiting order) at the given tip heights: per row the cut
/// runs, gaps bridged at feed when that is quicker than lifting, zig-zag or one-way.
pub(crate) fn cut_rows(
    em: &mut Emitter,
    frame: Frame,
    rows: &[Row],
    clear: &Clear,
    zigzag: bool,
    min_cut: f32,
    tol: f64,
) {
    let mut forward = true;
    // Buffers reused for every run.
    let (mut z, mut vertices, mut pts) = (Vec::new(), Vec::new(), Vec::new());
    for row in rows {
        let mut runs = cut_runs(row, min_cut);
        if runs.is_empty() {
            continue;
        }
        runs = bridge_gaps(runs, row, frame.step(), &em.feeds, em.clearance);
        let reverse = zigzag && !forward;
        if reverse {
            runs.reverse();
        }
        for (a, b) in runs {
            // Samples in cutting order.
            z.clear();
            z.extend_from_slice(&row.target[a..=b]);
            if reverse {
                z.reverse();
            }
            let sample = |k: usize| if reverse { b - k } else { a + k };
            simplify(&z, tol, &mut vertices);
            pts.clear();
            pts.extend(
                vertices
                    .iter()
                    .map(|&(k, h)| frame.point(row.index, sample(k), h)),
            );
            let start = pts[0];
            let free_here = row.clear[sample(0)] as f64;
            let travel_z = em.pos.map_or(em.safe_z, |p| {
                travel_height(frame, clear, p, start, em.safe_z)
            }) + em.clearance;
            em.travel(start, travel_z, free_here);
            em.feed_through(&pts[1..]);
        }
        forward = !forward;
    }
}

/// Merges neighbouring runs when feeding across the gap on the surface is quicker than
/// lifting, crossing at rapid and plunging again.
fn bridge_gaps(
    runs: Vec<(usize, usize)>,
    row: &Row,
    pixel: f64,
    feeds: &Feeds,
    clearance: f64,
) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::with_capacity(runs.len());
    for (a, b) in runs {
        if let Some(last) = out.last_mut() {
            let gap = &row.target[last.1..=a];
            let allowed = row
                .allowed
                .as_ref()
                .is_none_or(|m| m[last.1..=a].iter().all(|&v| v));
            let len = (a - last.1) as f64 * pixel;
            let top = gap.iter().cloned().fold(f32::NEG_INFINITY, f32::max) as f64 + clearance;
            let (za, zb) = (row.target[last.1] as f64, row.target[a] as f64);
            let lift = (top - za) / feeds.rapid + len / feeds.rapid + (top - zb) / feeds.plunge;
            if allowed && len / feeds.cut <= lift {
                last.1 = b;
                continue;
            }
        }
        out.push((a, b));
    }
    out
}

/// Highest known-free height under the straight XY line from `from` to `to`, sampled per
/// pixel (with the neighbouring grid points, since samples fall between them).
fn travel_height(frame: Frame, clear: &Clear, from: [f64; 3], to: [f64; 3], cap: f64) -> f64 {
    let (width, height) = match clear {
        Clear::Top(z) => return (*z as f64).min(cap),
        Clear::Grid { width, z } => (*width, z.len() / width),
    };
    let (mut fx, mut fy, mut tx, mut ty) = (from[0], from[1], to[0], to[1]);
    if frame.along_y {
        std::mem::swap(&mut fx, &mut fy);
        std::mem::swap(&mut tx, &mut ty);
    }
    let len = ((tx - fx).powi(2) + (ty - fy).powi(2)).sqrt();
    let steps = (len / frame.pixel).ceil() as usize + 1;
    let mut top = f64::NEG_INFINITY;
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let (gx, gy) = (
            (fx + (tx - fx) * t) / frame.pixel,
            (fy + (ty - fy) * t) / frame.pixel,
        );
        for ix in [gx.floor(), gx.ceil()] {
            for iy in [gy.floor(), gy.ceil()] {
                let (ix, iy) = (
                    ix.clamp(0.0, (width - 1) as f64) as usize,
                    iy.clamp(0.0, (height - 1) as f64) as usize,
                );
                top = top.max(clear.at(ix, iy) as f64);
            }
        }
    }
    top.min(cap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simplify_never_dips_below_and_respects_tolerance() {
        let z: Vec<f32> = (0..400)
            .map(|i| ((i as f32) * 0.05).sin() * 3.0 + if i % 97 == 0 { 1.0 } else { 0.0 })
            .collect();
        let mut v = Vec::new();
        for tol in [0.0, 0.001, 0.05] {
            simplify(&z, tol, &mut v);
            assert_eq!(v[0], (0, z[0] as f64));
            assert_eq!(v.last().unwrap().0, z.len() - 1);
            for w in v.windows(2) {
                let ((a, za), (b, zb)) = (w[0], w[1]);
                assert!(b > a);
                for j in a..=b {
                    let chord = za + (zb - za) * (j - a) as f64 / (b - a) as f64;
                    assert!(
                        chord >= z[j] as f64 - 1e-6 && chord <= z[j] as f64 + tol + 1e-6,
                        "tol {tol} at {j}: {chord} vs {}",
                        z[j]
                    );
                }
            }
        }
        // A straight ramp collapses to its two ends.
        let ramp: Vec<f32> = (0..100).map(|i| i as f32 * 0.25).collect();
        simplify(&ramp, 0.0, &mut v);
        assert_eq!(v.iter().map(|p| p.0).collect::<Vec<_>>(), vec![0, 99]);
        // On a dome, vertices off the samples merge what pinned vertices could not (every
        // chord between two samples of a circle dips under the ones between): near the top
        // of a 3 mm circle sampled every 0.025 mm a chord may span sqrt(8 · 3 · tol) =
        // 0.22 mm at tol = 0.002, about 9 samples; steeper flanks need shorter ones.
        let dome: Vec<f32> = (0..=200)
            .map(|i| {
                let x = (i as f64 - 100.0) * 0.025;
                (9.0 - x * x).sqrt() as f32
            })
            .collect();
        simplify(&dome, 0.002, &mut v);
        assert!(v.len() < 200 / 4, "{} vertices", v.len());
    }

    #[test]
    fn runs_cover_cut_samples_with_a_margin() {
        let row = Row {
            index: 0,
            target: vec![0.0, 0.0, -1.0, -1.0, 0.0, 0.0, 0.0, -2.0, 0.0],
            clear: vec![0.0; 9],
            allowed: None,
        };
        assert_eq!(cut_runs(&row, 0.001), vec![(1, 4), (6, 8)]);
        assert_eq!(raster_rows(11, 1.0, 3.0), vec![0, 3, 5, 8, 10]);
        assert_eq!(raster_rows(1, 1.0, 3.0), vec![0]);
    }
}
