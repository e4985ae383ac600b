//! Where the states of a graph go: a small layered (Sugiyama-style) placement.
//!
//! 1. **Layers**: breadth-first depth from the initial state along the transitions; states it
//!    does not reach are layered the same way from the first of them in text order, after the
//!    others. A transition to an earlier or the same layer is a back edge (drawn as an arc).
//! 2. **Order within a layer**: a few barycenter sweeps (down, then up) order each layer by the
//!    mean position of its neighbours in the layer before (after), which removes most
//!    crossings.
//! 3. **Folding**: a layer is a column; a tall layer is split into columns of at most `R`
//!    states, and the columns flow left to right in bands of `k`, every other band right to
//!    left (like a snake), so that a long chain — the usual machine cycle — is drawn in rows,
//!    never as one tall column or one long line. `R` and `k` are chosen so that the picture's
//!    width to height comes closest to [`TARGET_RATIO`].
//!
//! Every step is linear in the states and transitions except the sorting of the layers, so
//! the placement is O((n + e) log n).

/// The width-to-height ratio the folding aims at.
const TARGET_RATIO: f64 = 1.4;
/// Barycenter sweeps (each one down and one up).
const SWEEPS: usize = 3;

/// The centre of every state, in the order of the states.
pub(crate) fn place(
    n: usize,
    edges: &[(usize, usize)],
    start: Option<usize>,
    column_width: f64,
    row_height: f64,
) -> Vec<(f64, f64)> {
    if n == 0 {
        return Vec::new();
    }
    let mut successors: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(from, to) in edges {
        if from < n && to < n && from != to {
            successors[from].push(to);
        }
    }
    let layers = layers(n, &successors, start.filter(|&s| s < n).unwrap_or(0));
    let layers = order(n, layers, edges);
    let columns = fold(&layers, column_width, row_height);
    positions(n, &columns, column_width, row_height)
}

/// Breadth-first layers: from `start`, then from each state not yet reached, in text order.
fn layers(n: usize, successors: &[Vec<usize>], start: usize) -> Vec<Vec<usize>> {
    let mut layer: Vec<Option<usize>> = vec![None; n];
    let mut layers: Vec<Vec<usize>> = Vec::new();
    let mut queue = std::collections::VecDeque::new();
    for root in std::iter::once(start).chain(0..n) {
        if layer[root].is_some() {
            continue;
        }
        let base = layers.len();
        layer[root] = Some(base);
        queue.push_back(root);
        while let Some(s) = queue.pop_front() {
            let depth = layer[s].unwrap_or(base);
            if layers.len() <= depth {
                layers.resize(depth + 1, Vec::new());
            }
            layers[depth].push(s);
            for &t in &successors[s] {
                if layer[t].is_none() {
                    layer[t] = Some(depth + 1);
                    queue.push_back(t);
                }
            }
        }
    }
    layers
}

/// Barycenter sweeps over the layers; neighbours are states joined by a transition (either
/// way) in the adjacent layer.
fn order(n: usize, mut layers: Vec<Vec<usize>>, edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut layer_of = vec![0usize; n];
    let mut position = vec![0f64; n];
    for (l, states) in layers.iter().enumerate() {
        for (i, &s) in states.iter().enumerate() {
            layer_of[s] = l;
            position[s] = i as f64;
        }
    }
    // Neighbours in the layer above (`before`) and below (`after`).
    let mut before: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b) in edges {
        if a >= n || b >= n {
            continue;
        }
        let (la, lb) = (layer_of[a], layer_of[b]);
        if lb == la + 1 {
            before[b].push(a);
            after[a].push(b);
        } else if la == lb + 1 {
            before[a].push(b);
            after[b].push(a);
        }
    }
    let mut sweep = |layers: &mut Vec<Vec<usize>>, l: usize, neighbours: &[Vec<usize>]| {
        let keys: Vec<(f64, usize)> = layers[l]
            .iter()
            .map(|&s| {
                let near = &neighbours[s];
                let key = if near.is_empty() {
                    position[s]
                } else {
                    near.iter().map(|&t| position[t]).sum::<f64>() / near.len() as f64
                };
                (key, s)
            })
            .collect();
        let mut keyed = keys;
        keyed.sort_by(|a, b| {
            a.0.total_cmp(&b.0)
                .then(position[a.1].total_cmp(&position[b.1]))
        });
        layers[l] = keyed.iter().map(|&(_, s)| s).collect();
        for (i, &s) in layers[l].iter().enumerate() {
            position[s] = i as f64;
        }
    };
    for _ in 0..SWEEPS {
        for l in 1..layers.len() {
            sweep(&mut layers, l, &before);
        }
        for l in (0..layers.len().saturating_sub(1)).rev() {
            sweep(&mut layers, l, &after);
        }
    }
    layers
}

/// The columns and the number of columns per band.
struct Columns {
    columns: Vec<Vec<usize>>,
    per_band: usize,
}

/// Splits the layers into columns and chooses how many columns go in one band.
fn fold(layers: &[Vec<usize>], column_width: f64, row_height: f64) -> Columns {
    let tallest = layers.iter().map(Vec::len).max().unwrap_or(1).max(1);
    let mut heights: Vec<usize> = (2..=8).filter(|&r| r < tallest).collect();
    heights.push(tallest);
    let mut best: Option<(f64, usize, usize)> = None;
    for &rows in heights.iter().rev() {
        let lengths: Vec<usize> = layers
            .iter()
            .flat_map(|layer| {
                let full = layer.len() / rows;
                let rest = layer.len() % rows;
                std::iter::repeat_n(rows, full).chain((rest > 0).then_some(rest))
            })
            .collect();
        let count = lengths.len();
        // Candidate band widths: every one up to 64 columns, then a few around the square
        // root (a huge chain does not need the exact best).
        let root = (count as f64).sqrt().ceil() as usize;
        let candidates = (1..=count.min(64)).chain([root, root * 2, root * 4, count]);
        for per_band in candidates.filter(|&k| k >= 1 && k <= count) {
            let width = per_band.min(count) as f64 * column_width;
            let height: usize = lengths
                .chunks(per_band)
                .map(|band| band.iter().copied().max().unwrap_or(1))
                .sum();
            let height = height as f64 * row_height;
            let score = (width / height / TARGET_RATIO).ln().abs();
            if best.is_none_or(|(s, _, _)| score < s - 1e-9) {
                best = Some((score, rows, per_band));
            }
        }
    }
    let (_, rows, per_band) = best.unwrap_or((0.0, tallest, layers.len().max(1)));
    let columns = layers
        .iter()
        .flat_map(|layer| layer.chunks(rows).map(<[usize]>::to_vec))
        .collect();
    Columns { columns, per_band }
}

/// The centres: columns left to right in bands (odd bands right to left), each column
/// centred vertically in its band.
fn positions(n: usize, columns: &Columns, column_width: f64, row_height: f64) -> Vec<(f64, f64)> {
    let mut at = vec![(0.0, 0.0); n];
    let per_band = columns.per_band.max(1);
    let mut top = 0.0;
    for (b, band) in columns.columns.chunks(per_band).enumerate() {
        let rows = band.iter().map(Vec::len).max().unwrap_or(1);
        for (j, column) in band.iter().enumerate() {
            let slot = if b % 2 == 1 { per_band - 1 - j } else { j };
            let x = slot as f64 * column_width;
            let offset = (rows - column.len()) as f64 / 2.0;
            for (i, &s) in column.iter().enumerate() {
                at[s] = (x, top + (offset + i as f64) * row_height);
            }
        }
        top += rows as f64 * row_height;
    }
    at
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_is_folded_into_rows() {
        let edges: Vec<(usize, usize)> = (0..9).map(|i| (i, (i + 1) % 9)).collect();
        let at = place(9, &edges, Some(0), 100.0, 100.0);
        let xs: std::collections::BTreeSet<i64> = at.iter().map(|p| p.0 as i64).collect();
        let ys: std::collections::BTreeSet<i64> = at.iter().map(|p| p.1 as i64).collect();
        assert!(xs.len() >= 3 && ys.len() >= 2, "{at:?}");
        // Snake: consecutive states are neighbours.
        for i in 0..8 {
            let (a, b) = (at[i], at[i + 1]);
            assert!(
                (a.0 - b.0).abs() + (a.1 - b.1).abs() <= 100.0 + 1e-9,
                "{at:?}"
            );
        }
    }

    #[test]
    fn barycenters_uncross_two_layers() {
        // Breadth first gives layer 2 as [3, 4], but 3 is mostly joined to 2 and 4 to 1.
        let edges = [
            (0, 1),
            (0, 2),
            (1, 3),
            (2, 4),
            (2, 3),
            (2, 3),
            (1, 4),
            (1, 4),
        ];
        let first = layers(5, &succ(5, &edges), 0);
        assert_eq!(first[2], [3, 4]);
        let layers = order(5, first, &edges);
        assert_eq!(layers[1], [1, 2]);
        assert_eq!(layers[2], [4, 3]);
    }

    fn succ(n: usize, edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
        let mut s = vec![Vec::new(); n];
        for &(a, b) in edges {
            s[a].push(b);
        }
        s
    }
}
