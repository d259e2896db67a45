//! The order that saves tool changes: operations grouped by tool, never across a cut-out
//! (a profile through the stock frees the part, so what comes before it stays before and
//! what comes after stays after).

/// The cutting order of operations given as (tool number, is a cut-out), as indices.
/// Between cut-outs the operations run grouped by tool, in the order the tools first
/// appear, except that the tool already loaded goes first and the next cut-out's tool
/// last; within a tool, as written.
pub(crate) fn order_by_tool(ops: &[(u32, bool)]) -> Vec<usize> {
    let mut out = Vec::with_capacity(ops.len());
    let mut loaded: Option<u32> = None;
    let mut start = 0;
    while start < ops.len() {
        // The segment: up to and including the next cut-out.
        let end = (start..ops.len())
            .find(|&k| ops[k].1)
            .map_or(ops.len(), |k| k + 1);
        let barrier = ops[end - 1].1.then_some(end - 1);
        let body: Vec<usize> = (start..end).filter(|&k| Some(k) != barrier).collect();
        let mut tools: Vec<u32> = Vec::new();
        for &k in &body {
            if !tools.contains(&ops[k].0) {
                tools.push(ops[k].0);
            }
        }
        let last = barrier.map(|b| ops[b].0);
        // The loaded tool first, unless it is the cut-out's (then it waits for it).
        if let Some(t) = loaded.filter(|t| Some(*t) != last) {
            if let Some(i) = tools.iter().position(|&x| x == t) {
                let t = tools.remove(i);
                tools.insert(0, t);
            }
        }
        if let Some(t) = last {
            if let Some(i) = tools.iter().position(|&x| x == t) {
                let t = tools.remove(i);
                tools.push(t);
            }
        }
        for t in tools {
            out.extend(body.iter().copied().filter(|&k| ops[k].0 == t));
        }
        out.extend(barrier);
        loaded = out.last().map(|&k| ops[k].0);
        start = end;
    }
    out
}

/// Tool changes in running `ops` in `order` (the first load counts).
pub(crate) fn changes(ops: &[(u32, bool)], order: &[usize]) -> usize {
    let mut n = 0;
    let mut loaded = None;
    for &k in order {
        if loaded != Some(ops[k].0) {
            n += 1;
            loaded = Some(ops[k].0);
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every permutation of `ops` that keeps each cut-out's place relative to the others
    /// (what comes before a cut-out stays before it): the fewest changes by brute force.
    fn fewest(ops: &[(u32, bool)]) -> usize {
        fn perms(rest: Vec<usize>, acc: &mut Vec<usize>, all: &mut Vec<Vec<usize>>) {
            if rest.is_empty() {
                all.push(acc.clone());
            }
            for i in 0..rest.len() {
                let mut r = rest.clone();
                let k = r.remove(i);
                acc.push(k);
                perms(r, acc, all);
                acc.pop();
            }
        }
        let mut all = vec![];
        perms((0..ops.len()).collect(), &mut vec![], &mut all);
        all.iter()
            .filter(|p| respects(ops, p))
            .map(|p| changes(ops, p))
            .min()
            .unwrap()
    }

    fn respects(ops: &[(u32, bool)], order: &[usize]) -> bool {
        let pos = |k: usize| order.iter().position(|&x| x == k).unwrap();
        (0..ops.len())
            .all(|a| (0..ops.len()).all(|b| !(a < b && (ops[a].1 || ops[b].1)) || pos(a) < pos(b)))
    }

    #[test]
    fn grouping_is_as_good_as_any_order_that_keeps_the_cut_outs() {
        let cases: &[&[(u32, bool)]] = &[
            &[(1, false), (2, false), (1, false), (1, true)],
            &[
                (1, false),
                (2, false),
                (1, false),
                (2, false),
                (1, true),
                (2, false),
            ],
            &[
                (3, false),
                (1, false),
                (3, false),
                (2, true),
                (1, false),
                (2, false),
            ],
            &[(1, true), (2, false), (1, false), (2, false)],
        ];
        for ops in cases {
            let order = order_by_tool(ops);
            let mut sorted = order.clone();
            sorted.sort();
            assert_eq!(sorted, (0..ops.len()).collect::<Vec<_>>());
            assert!(respects(ops, &order), "{ops:?} → {order:?}");
            assert_eq!(changes(ops, &order), fewest(ops), "{ops:?} → {order:?}");
        }
    }
}
