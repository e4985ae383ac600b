//! Transition labels for messages (`diagnostics.md` §2.3): `{src}->{dst}`, with ` (prio {p})`
//! when two transitions would get the same label. `p` is the effective priority, explicit or
//! implicit (§2.6); which transitions need it, and their priorities, come from the graph
//! model (`TransEntry::label_priority`), which labels the structure rules' messages the same
//! way.

use higraph_syntax::{ast, ast::EndpointKind};

use crate::rules::graph::number_key;

/// The label of a transition: its plain label, with ` (prio {p})` if `prio` is given.
pub(crate) fn label(trans: &ast::Trans, prio: Option<u64>) -> String {
    let plain = plain_label(trans);
    match prio {
        Some(p) => format!("{plain} (prio {p})"),
        None => plain,
    }
}

/// `4->1`, `any->0`, `3->return`.
fn plain_label(trans: &ast::Trans) -> String {
    let endpoint = |e: Option<ast::Endpoint>| match e.as_ref().and_then(|e| e.kind()) {
        Some(EndpointKind::Any) => "any".to_owned(),
        Some(EndpointKind::Return) => "return".to_owned(),
        Some(EndpointKind::State) => e
            .and_then(|e| e.token())
            .map(|t| number_key(t.text()).to_owned())
            .unwrap_or_default(),
        None => "?".to_owned(),
    };
    format!("{}->{}", endpoint(trans.source()), endpoint(trans.target()))
}

#[cfg(test)]
mod tests {
    use higraph_syntax::{ast, ast::AstNode};

    use super::label;
    use crate::rules::graph::facts::MemberFacts;
    use crate::rules::graph::{GraphModel, VirtualLayout};

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
        let model = GraphModel::new(String::new(), &facts, false, VirtualLayout::Virtual);
        let transitions = members.iter().filter_map(|m| ast::Trans::cast(m.clone()));
        let labels: Vec<String> = transitions
            .zip(&model.transitions)
            .map(|(t, entry)| label(&t, entry.label_priority()))
            .collect();
        // The structure rules' messages label transitions the same way.
        let model_labels: Vec<String> = model.transitions.iter().map(|t| t.label()).collect();
        assert_eq!(labels, model_labels);
        labels
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

    #[test]
    fn labels_show_state_numbers_without_leading_zeros() {
        let g = "graph G < state 0 < > state 1 < > trans 00->1 < > trans 0->01 prio 3 < > \
             trans 1->return < > trans 1->return < > >";
        assert_eq!(
            labels(g),
            vec![
                "0->1 (prio 1)",
                "0->1 (prio 3)",
                "1->return (prio 1)",
                "1->return (prio 2)"
            ]
        );
    }

    #[test]
    fn transitions_outside_every_range_show_their_explicit_priority() {
        // `2` is no state: its transitions are in no range, so only `prio` tells them apart.
        let g = "graph G < state 0 < > trans 2->0 prio 4 < > trans 2->0 < > >";
        assert_eq!(labels(g), vec!["2->0 (prio 4)", "2->0"]);
    }
}
