//! Transition labels for messages (`diagnostics.md` §2.3): `{src}->{dst}`, with ` (prio {p})`
//! when two transitions would get the same label. `p` is the effective priority, explicit or
//! implicit (§2.6).

use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use higraph_syntax::{ast, ast::EndpointKind};

use crate::rules::graph::facts::{EndFact, EndpointFact, MemberFacts};

/// The label of a transition: its plain label, with ` (prio {p})` if `prio` is given.
pub(crate) fn label(trans: &ast::Trans, prio: Option<u64>) -> String {
    let plain = plain_label(trans);
    match prio {
        Some(p) => format!("{plain} (prio {p})"),
        None => plain,
    }
}

/// For every transition among `members` (in text order): its effective priority if another
/// transition has the same plain label, else `None` — what [`label`] needs.
pub(crate) fn label_priorities<'a>(
    members: impl IntoIterator<Item = &'a MemberFacts> + Clone,
) -> Vec<Option<u64>> {
    let states: HashSet<u64> = members
        .clone()
        .into_iter()
        .filter_map(|m| match m {
            MemberFacts::State(s) => s.number.as_ref()?.parse::<u64>().ok(),
            _ => None,
        })
        .filter(|n| *n <= 65535)
        .collect();
    let transitions: Vec<&crate::rules::graph::facts::TransFacts> = members
        .into_iter()
        .filter_map(|m| match m {
            MemberFacts::Trans(t) => Some(t),
            _ => None,
        })
        .collect();
    let plain: Vec<(&str, &str)> = transitions
        .iter()
        .map(|t| (end_key(t.source.as_ref()), end_key(t.target.as_ref())))
        .collect();
    let mut count: HashMap<(&str, &str), usize> =
        HashMap::with_capacity_and_hasher(plain.len(), Default::default());
    for key in &plain {
        *count.entry(*key).or_default() += 1;
    }
    let explicit: Vec<Option<u64>> = transitions
        .iter()
        .map(|t| t.prio.as_ref()?.value.as_ref()?.parse::<u64>().ok())
        .collect();
    let ranges: Vec<Option<Range>> = transitions
        .iter()
        .map(|t| range_of(t.source.as_ref()?, &states))
        .collect();
    effective_priorities(&ranges, &explicit)
        .into_iter()
        .zip(&plain)
        .map(|(prio, key)| prio.filter(|_| count.get(key).copied().unwrap_or(0) > 1))
        .collect()
}

/// An endpoint as labels show it, for counting equal labels: a number without leading
/// zeros (as written if it does not fit a `u64`), `any`, `return`, or `?`.
fn end_key(end: Option<&EndpointFact>) -> &str {
    match end.map(|e| &e.end) {
        Some(EndFact::State(text)) if text.parse::<u64>().is_ok() => {
            let trimmed = text.trim_start_matches('0');
            if trimmed.is_empty() { "0" } else { trimmed }
        }
        Some(EndFact::State(text)) => text,
        Some(EndFact::Any) => "any",
        Some(EndFact::Return) => "return",
        None => "?",
    }
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

fn range_of(source: &EndpointFact, states: &HashSet<u64>) -> Option<Range> {
    match &source.end {
        EndFact::Any => Some(Range::Any),
        EndFact::Return => None,
        EndFact::State(text) => {
            let n = text.parse::<u64>().ok()?;
            states.contains(&n).then_some(Range::State(n))
        }
    }
}

/// The effective priority of every transition (§2.6); `None` outside any range without an
/// explicit `prio`.
fn effective_priorities(ranges: &[Option<Range>], explicit: &[Option<u64>]) -> Vec<Option<u64>> {
    let mut used: HashMap<Range, HashSet<u64>> = HashMap::default();
    for (range, prio) in ranges.iter().zip(explicit) {
        if let (Some(range), Some(prio)) = (range, prio) {
            used.entry(*range).or_default().insert(*prio);
        }
    }
    let mut highest: HashMap<Range, u64> = HashMap::default();
    let mut out = Vec::with_capacity(ranges.len());
    for (range, prio) in ranges.iter().zip(explicit) {
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
    use higraph_syntax::{ast, ast::AstNode};

    use super::{label, label_priorities};
    use crate::rules::graph::facts::MemberFacts;

    fn labels(text: &str) -> Vec<String> {
        let Some(ast::Item::Graph(graph)) = higraph_syntax::parse(text).tree().items().next()
        else {
            panic!("no graph");
        };
        let members: Vec<_> = graph
            .body()
            .into_iter()
            .flat_map(|b| b.syntax().children())
            .collect();
        let facts: Vec<MemberFacts> = members.iter().map(MemberFacts::of).collect();
        let transitions = members.iter().filter_map(|m| ast::Trans::cast(m.clone()));
        transitions
            .zip(label_priorities(&facts))
            .map(|(t, prio)| label(&t, prio))
            .collect()
    }

    #[test]
    fn duplicate_labels_get_their_priority() {
        let g = "graph G < state 0 < > state 1 < > trans 0->1 < > trans 0->1 prio 1 < > \
             trans 1->0 < > trans any->0 < > >";
        assert_eq!(
            labels(g),
            vec!["0->1 (prio 2)", "0->1 (prio 1)", "1->0", "any->0"]
        );
    }
}
