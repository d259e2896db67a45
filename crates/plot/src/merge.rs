//! Merging strokes whose ends meet into as few strokes as possible.
//!
//! Strokes are the edges of a graph whose nodes are their end points, clustered within a
//! tolerance. A connected network with `k` odd-degree nodes cannot be drawn in fewer than
//! `max(1, k/2)` pen-down strokes, and that bound is reached: pair the odd nodes with virtual
//! edges, walk an Euler circuit (Hierholzer) and cut it at the virtual edges. This merges
//! whole networks (a grid, a mesh) where pairwise joining stops at the first junction.

use oficina_geom::Point;
use std::collections::HashMap;

use crate::strokes::Stroke;

/// Nodes within `tol` of each other, found on a grid of cell `tol`.
struct NodeGrid {
    tol: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
    pos: Vec<Point>,
}

impl NodeGrid {
    fn cell(&self, p: Point) -> (i64, i64) {
        (
            (p.x / self.tol).floor() as i64,
            (p.y / self.tol).floor() as i64,
        )
    }

    /// The node within `tol` of `p`, creating one when none is.
    fn node(&mut self, p: Point) -> usize {
        let (cx, cy) = self.cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(ids) = self.cells.get(&(cx + dx, cy + dy)) {
                    if let Some(&id) = ids.iter().find(|&&id| self.pos[id].distance(p) <= self.tol)
                    {
                        return id;
                    }
                }
            }
        }
        let id = self.pos.len();
        self.pos.push(p);
        self.cells.entry((cx, cy)).or_default().push(id);
        id
    }
}

/// An edge of the circuit: a stroke (forward or reversed) or a virtual pen-up link.
#[derive(Clone, Copy)]
enum Edge {
    Stroke(usize),
    Virtual,
}

/// Merges `strokes` (at least two points each) into the fewest strokes whose ends meet
/// within `tol` mm. The points of every stroke are kept; joins closer than `tol` are drawn.
pub fn merge(strokes: Vec<Stroke>, tol: f64) -> Vec<Stroke> {
    let tol = if tol.is_finite() && tol > 0.0 {
        tol
    } else {
        1e-9
    };
    let mut grid = NodeGrid {
        tol,
        cells: HashMap::new(),
        pos: Vec::new(),
    };
    let mut ends = Vec::with_capacity(strokes.len());
    for s in &strokes {
        let a = grid.node(s[0]);
        let b = grid.node(*s.last().unwrap());
        ends.push((a, b));
    }
    let n = grid.pos.len();
    // adj[v]: (edge id, other node, walked forward). Edge ids ≥ strokes.len() are virtual.
    let mut adj: Vec<Vec<(usize, usize, bool)>> = vec![Vec::new(); n];
    for (i, &(a, b)) in ends.iter().enumerate() {
        adj[a].push((i, b, true));
        adj[b].push((i, a, false));
    }
    let odd: Vec<usize> = (0..n).filter(|&v| adj[v].len() % 2 == 1).collect();
    let mut kinds: Vec<Edge> = (0..strokes.len()).map(Edge::Stroke).collect();
    for pair in odd.chunks(2) {
        let id = kinds.len();
        kinds.push(Edge::Virtual);
        adj[pair[0]].push((id, pair[1], true));
        adj[pair[1]].push((id, pair[0], false));
    }

    let mut used = vec![false; kinds.len()];
    let mut next = vec![0usize; n];
    let mut out: Vec<Stroke> = Vec::new();
    let mut circuit: Vec<(usize, bool)> = Vec::new();
    let mut stack: Vec<(usize, Option<(usize, bool)>)> = Vec::new();
    // Start at odd nodes first so open networks begin at a virtual edge.
    let starts = odd.iter().copied().chain(0..n);
    for start in starts {
        if next[start] >= adj[start].len() {
            continue;
        }
        circuit.clear();
        stack.push((start, None));
        while let Some(&(v, via)) = stack.last() {
            while next[v] < adj[v].len() && used[adj[v][next[v]].0] {
                next[v] += 1;
            }
            if let Some(&(e, w, fwd)) = adj[v].get(next[v]) {
                used[e] = true;
                stack.push((w, Some((e, fwd))));
            } else {
                stack.pop();
                if let Some(step) = via {
                    circuit.push(step);
                }
            }
        }
        // Hierholzer emits the circuit backwards: reverse it, then start after a virtual edge.
        circuit.reverse();
        if let Some(k) = circuit
            .iter()
            .position(|&(e, _)| matches!(kinds[e], Edge::Virtual))
        {
            circuit.rotate_left(k + 1);
        }
        let mut cur: Stroke = Vec::new();
        for &(e, fwd) in &circuit {
            match kinds[e] {
                Edge::Virtual => {
                    if cur.len() > 1 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur.clear();
                }
                Edge::Stroke(i) => {
                    let s = &strokes[i];
                    let skip_first = cur
                        .last()
                        .is_some_and(|l| *l == if fwd { s[0] } else { *s.last().unwrap() });
                    let k = usize::from(skip_first);
                    if fwd {
                        cur.extend(s.iter().skip(k));
                    } else {
                        cur.extend(s.iter().rev().skip(k));
                    }
                }
            }
        }
        if cur.len() > 1 {
            out.push(cur);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn a_grid_network_merges_to_its_odd_node_bound() {
        // A 3×3 grid of unit squares drawn as 24 separate unit segments: 16 nodes, the 8
        // edge-midpoint nodes have degree 3 → at least 4 strokes, and Euler gives exactly 4.
        let mut segs = Vec::new();
        for i in 0..4 {
            for j in 0..3 {
                segs.push(vec![p(j as f64, i as f64), p(j as f64 + 1.0, i as f64)]);
                segs.push(vec![p(i as f64, j as f64), p(i as f64, j as f64 + 1.0)]);
            }
        }
        let down: f64 = segs
            .iter()
            .map(|s| crate::strokes::polyline_length(s))
            .sum();
        let merged = merge(segs, 0.01);
        assert_eq!(merged.len(), 4);
        let after: f64 = merged
            .iter()
            .map(|s| crate::strokes::polyline_length(s))
            .sum();
        assert!((after - down).abs() < 1e-9);
    }

    #[test]
    fn ends_within_tolerance_join_and_far_ones_do_not() {
        let a = vec![p(0.0, 0.0), p(10.0, 0.0)];
        let b = vec![p(10.04, 0.0), p(20.0, 0.0)];
        let c = vec![p(20.5, 0.0), p(30.0, 0.0)];
        let merged = merge(vec![a, b, c], 0.05);
        assert_eq!(merged.len(), 2);
        let closed = merge(
            vec![
                vec![p(0.0, 0.0), p(1.0, 0.0)],
                vec![p(1.0, 1.0), p(1.0, 0.0)],
                vec![p(1.0, 1.0), p(0.0, 0.0)],
            ],
            1e-6,
        );
        assert_eq!(closed.len(), 1);
        assert_eq!(closed[0].first(), closed[0].last());
    }
}
