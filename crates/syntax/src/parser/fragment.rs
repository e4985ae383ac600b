//! Parsing a fragment of a file on its own, for incremental reparsing
//! ([`crate::reparse`]): the text of one graph member is parsed exactly as the graph body
//! would parse it.

use rowan::{GreenNode, NodeOrToken};

use super::{Parser, graph};
use crate::SyntaxError;

/// Parses `text` as one graph member (`state`, `trans`, `permanent`, ...). Returns the
/// member's node and its diagnostics (offsets relative to `text`) if the text is exactly one
/// member: it starts with the member, the member ends at the end of the text, and no trivia
/// is left over. Returns `None` otherwise; the caller then parses the whole file.
pub(crate) fn graph_member(text: &str) -> Option<(GreenNode, Vec<SyntaxError>)> {
    let mut p = Parser::new(text);
    if !p.starts_with_significant() {
        return None;
    }
    p.start_root();
    graph::member(&mut p);
    if !p.all_emitted() {
        return None;
    }
    p.finish_node();
    let (root, errors) = p.finish();
    let mut children = root.children();
    let member = match (children.next(), children.next()) {
        (Some(NodeOrToken::Node(node)), None) => node.to_owned(),
        _ => return None,
    };
    Some((member, errors))
}
