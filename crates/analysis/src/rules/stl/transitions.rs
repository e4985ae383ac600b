//! Transition labels for messages (`diagnostics.md` §2.3): `{src}->{dst}`, with ` (prio {p})`
//! when two transitions would get the same label. `p` is the effective priority, explicit or
//! implicit (§2.6).

use std::collections::{HashMap, HashSet};

use higraph_syntax::{ast, ast::EndpointKind};

/// One label per transition of `graph`, in text order.
pub(super) fn labels(graph: &ast::Graph) -> Vec<String> {
    let states: HashSet<u64> = graph
        .states()
        .filter_map(|s| s.number())
        .filter_map(|t| t.text().parse::<u64>().ok())
        .filter(|n| *n <= 65535)
        .collect();
    let transitions: Vec<ast::Trans> = graph.transitions().collect();
    let plain: Vec<String> = transitions.iter().map(plain_label).collect();
    let priorities = effective_priorities(&transitions, &states);
    let mut count: HashMap<&str, usize> = HashMap::new();
    for label in &plain {
        *count.entry(label.as_str()).or_default() += 1;
    }
    plain
        .iter()
        .zip(&priorities)
        .map(|(label, prio)| match prio {
            Some(p) if count.get(label.as_str()).copied().unwrap_or(0) > 1 => {
                format!("{label} (prio {p})")
            }
            _ => label.clone(),
        })
        .collect()
}

/// `4->1`, `any->0`, `3->return`.
fn plain_label(trans: &ast::Trans) -> String {
    let endpoint = |e: Option<ast::Endpoint>| match e.as_ref().and_then(|e| e.kind()) {
        Some(EndpointKind::Any) => "any".to_owned(),
        Some(EndpointKind::Return) => "return".to_owned(),
        Some(EndpointKind::State) => e
            .and_then(|e| e.token())
            .map(|t| {
                t.text()
                    .parse::<u64>()
                    .map_or_else(|_| t.text().to_owned(), |n| n.to_string())
            })
            .unwrap_or_default(),
        None => "?".to_owned(),
    };
    format!("{}->{}", endpoint(trans.source()), endpoint(trans.target()))
}

/// The priority range of a transition: its source state, or the any-transitions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Range {
    State(u64),
    Any,
}

fn range_of(trans: &ast::Trans, states: &HashSet<u64>) -> Option<Range> {
    let source = trans.source()?;
    match source.kind()? {
        EndpointKind::Any => Some(Range::Any),
        EndpointKind::Return => None,
        EndpointKind::State => {
            let n = source.token()?.text().parse::<u64>().ok()?;
            states.contains(&n).then_some(Range::State(n))
        }
    }
}

/// The effective priority of every transition (§2.6); `None` outside any range without an
/// explicit `prio`.
fn effective_priorities(transitions: &[ast::Trans], states: &HashSet<u64>) -> Vec<Option<u64>> {
    let explicit: Vec<Option<u64>> = transitions
        .iter()
        .map(|t| {
            t.prio()
                .and_then(|p| p.value())
                .and_then(|v| v.text().parse::<u64>().ok())
        })
        .collect();
    let ranges: Vec<Option<Range>> = transitions.iter().map(|t| range_of(t, states)).collect();
    let mut used: HashMap<Range, HashSet<u64>> = HashMap::new();
    for (range, prio) in ranges.iter().zip(&explicit) {
        if let (Some(range), Some(prio)) = (range, prio) {
            used.entry(*range).or_default().insert(*prio);
        }
    }
    let mut highest: HashMap<Range, u64> = HashMap::new();
    let mut out = Vec::with_capacity(transitions.len());
    for (range, prio) in ranges.iter().zip(&explicit) {
        let Some(range) = range else {
            out.push(*prio);
            continue;
        };
        let effective = match prio {
            Some(p) => *p,
            None => {
                let taken = used.get(range);
                let mut candidate = highest.get(range).map_or(1, |h| h + 1);
                while taken.is_some_and(|t| t.contains(&candidate)) {
                    candidate += 1;
                }
                candidate
            }
        };
        let entry = highest.entry(*range).or_insert(effective);
        *entry = (*entry).max(effective);
        out.push(Some(effective));
    }
    out
}

#[cfg(test)]
mod tests {
    use higraph_syntax::ast;

    use super::labels;

    fn graph(text: &str) -> ast::Graph {
        match higraph_syntax::parse(text).tree().items().next() {
            Some(ast::Item::Graph(g)) => g,
            _ => panic!("no graph"),
        }
    }

    #[test]
    fn duplicate_labels_get_their_priority() {
        let g = graph(
            "graph G < state 0 < > state 1 < > trans 0->1 < > trans 0->1 prio 1 < > \
             trans 1->0 < > trans any->0 < > >",
        );
        assert_eq!(
            labels(&g),
            vec!["0->1 (prio 2)", "0->1 (prio 1)", "1->0", "any->0"]
        );
    }
}
