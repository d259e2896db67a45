//! Ordering and reversing strokes to cut pen-up travel: greedy nearest neighbour on an R-tree
//! of stroke ends, then 2-opt over a window of the tour.

use oficina_geom::Point;
use rstar::primitives::GeomWithData;
use rstar::RTree;

use crate::strokes::Stroke;

type End = GeomWithData<[f64; 2], (usize, bool)>;

fn end_point(s: &Stroke, at_end: bool) -> [f64; 2] {
    let p = if at_end { *s.last().unwrap() } else { s[0] };
    [p.x, p.y]
}

/// Greedy tour from `from`: always the nearest free stroke end next, drawn from that end.
/// Returns (stroke index, reversed).
pub fn nearest_neighbour(strokes: &[Stroke], from: Point) -> Vec<(usize, bool)> {
    let ends: Vec<End> = strokes
        .iter()
        .enumerate()
        .flat_map(|(i, s)| {
            [
                End::new(end_point(s, false), (i, false)),
                End::new(end_point(s, true), (i, true)),
            ]
        })
        .collect();
    let mut tree = RTree::bulk_load(ends);
    let mut tour = Vec::with_capacity(strokes.len());
    let mut at = [from.x, from.y];
    while let Some(near) = tree.nearest_neighbor(&at).copied() {
        let (i, reversed) = near.data;
        tree.remove(&near);
        tree.remove(&End::new(end_point(&strokes[i], !reversed), (i, !reversed)));
        tour.push((i, reversed));
        at = end_point(&strokes[i], !reversed);
    }
    tour
}

fn first(strokes: &[Stroke], t: (usize, bool)) -> Point {
    let s = &strokes[t.0];
    if t.1 {
        *s.last().unwrap()
    } else {
        s[0]
    }
}

fn last(strokes: &[Stroke], t: (usize, bool)) -> Point {
    first(strokes, (t.0, !t.1))
}

/// 2-opt: reversing the run `tour[i..=j]` (order and direction of each stroke) when that
/// shortens the two pen-up links around it,
///   gain = |prev→s_i| + |e_j→next| − |prev→e_j| − |s_i→next|,
/// with j within `window` of i so a pass costs O(n·window). Passes repeat while they gain
/// (at most `max_passes`). Returns the pen-up length saved.
pub fn two_opt(
    strokes: &[Stroke],
    tour: &mut [(usize, bool)],
    from: Point,
    window: usize,
    max_passes: usize,
) -> f64 {
    let n = tour.len();
    let mut saved = 0.0;
    for _ in 0..max_passes {
        let mut pass_gain = 0.0;
        for i in 0..n {
            let prev = if i == 0 {
                from
            } else {
                last(strokes, tour[i - 1])
            };
            let s_i = first(strokes, tour[i]);
            for j in i + 1..n.min(i + 1 + window) {
                let e_j = last(strokes, tour[j]);
                let (old_next, new_next) = match tour.get(j + 1) {
                    Some(&t) => {
                        let next = first(strokes, t);
                        (e_j.distance(next), s_i.distance(next))
                    }
                    None => (0.0, 0.0),
                };
                let gain = prev.distance(s_i) + old_next - prev.distance(e_j) - new_next;
                if gain > 1e-9 {
                    tour[i..=j].reverse();
                    for t in &mut tour[i..=j] {
                        t.1 = !t.1;
                    }
                    pass_gain += gain;
                    break;
                }
            }
        }
        saved += pass_gain;
        if pass_gain <= 0.0 {
            break;
        }
    }
    saved
}

/// Applies a tour: strokes in tour order, reversed where it says.
pub(crate) fn apply(strokes: Vec<Stroke>, tour: &[(usize, bool)]) -> Vec<Stroke> {
    let mut slots: Vec<Option<Stroke>> = strokes.into_iter().map(Some).collect();
    tour.iter()
        .map(|&(i, rev)| {
            let mut s = slots[i].take().expect("each stroke once in a tour");
            if rev {
                s.reverse();
            }
            s
        })
        .collect()
}

/// Pen-up length of strokes drawn in this order (between strokes only).
#[cfg(test)]
fn travel(strokes: &[Stroke], tour: &[(usize, bool)]) -> f64 {
    tour.windows(2)
        .map(|w| last(strokes, w[0]).distance(first(strokes, w[1])))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_neighbour_visits_each_stroke_once_and_two_opt_never_lengthens() {
        // Segments scattered on a pseudo-random lattice.
        let mut strokes = Vec::new();
        let mut x = 12345u64;
        let mut rnd = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 * 100.0
        };
        for _ in 0..500 {
            let a = Point::new(rnd(), rnd());
            strokes.push(vec![a, Point::new(a.x + 1.0, a.y + rnd() / 50.0)]);
        }
        let from = Point::new(0.0, 0.0);
        let mut tour = nearest_neighbour(&strokes, from);
        let mut seen = vec![false; strokes.len()];
        for &(i, _) in &tour {
            assert!(!seen[i]);
            seen[i] = true;
        }
        assert!(seen.iter().all(|&s| s));
        let identity: Vec<(usize, bool)> = (0..strokes.len()).map(|i| (i, false)).collect();
        let cost = |t: &[(usize, bool)]| from.distance(first(&strokes, t[0])) + travel(&strokes, t);
        let nn = cost(&tour);
        assert!(nn < cost(&identity) / 3.0);
        let saved = two_opt(&strokes, &mut tour, from, 50, 5);
        assert!((cost(&tour) - (nn - saved)).abs() < 1e-6);
        assert!(saved >= 0.0);
    }
}
