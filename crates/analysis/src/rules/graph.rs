//! State graphs: declarations and structure.
//!
//! * `decls` — HG1202, HG1211, HG1212 (predefined names declared, `activate`); the rules of
//!   every variable declaration are in [`crate::rules::decls`];
//! * `structure` — HG2001, HG2002, HG2101–HG2106 (limits, state numbers, endpoints);
//! * `startup` — HG2201–HG2203, HG2401, HG2402 (startup transition, reachability);
//! * `priority` — HG2301–HG2306 (priorities per range, §2.6);
//! * `modes` — HG3001–HG3003, HG3007, HG3101, HG3102 (wait times, operating modes);
//! * `model` — the graph as these rules see it, and [`effective_priorities`] for the
//!   formatter; `facts` — what the model is built from, per member.
//!
//! The structure rules (`structure`, `startup`, `priority`, `modes`) see only member facts
//! and a [`GraphHeader`], never positions of the item: their findings are placed in a
//! [`VirtualLayout`] and moved to the real positions afterwards, so that a keystroke, which
//! moves every member after it, leaves their result equal (salsa then does not run them).
//!
//! Time values themselves (HG3004–HG3006, HG3008) are checked with the STL operands.

mod decls;
pub(crate) mod facts;
pub(crate) mod model;
mod modes;
mod priority;
mod startup;
mod structure;

use higraph_syntax::{TextRange, TextSize, ast, ast::AstNode};

use super::edit;
// Re-exported for the formatter; `rules/mod.rs` has to make `graph` visible to it.
#[allow(unused_imports)]
pub use self::model::effective_priorities;
pub(crate) use self::{facts::number_key, model::GraphModel};
use super::Ctx;

/// The declaration rules of a graph (its variable sections and `activate`), on its tree.
pub(crate) fn check_declarations(ctx: &mut Ctx<'_>, graph: &ast::Graph, name: &str) {
    decls::check_variables(ctx, graph, &format!("graph {name}"));
    decls::check_activate(ctx, graph);
}

/// The structure rules of a graph, on its member facts (`model`) and header.
pub(crate) fn check_structure(ctx: &mut Ctx<'_>, header: &GraphHeader, model: &GraphModel<'_>) {
    structure::check(ctx, header, model);
    startup::check(ctx, header, model);
    priority::check(ctx, model);
    modes::check(ctx, model);
}

/// What the structure rules need of a graph besides its members. Its positions lie in the
/// graph's header, before the first member, where edits of members do not move them.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct GraphHeader {
    pub name: String,
    /// The name token.
    pub name_range: Option<TextRange>,
    /// Does the graph declare a variable `INIT_SD` (then no transition is a startup one)?
    pub declares_init_sd: bool,
    /// Where a new member goes (the fix of HG2201).
    pub insertion: Option<Insertion>,
}

/// Where a new member of a graph goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Insertion {
    /// On a new line after the last member, with its indentation.
    AfterMember {
        ordinal: usize,
        len: TextSize,
        indent: String,
    },
    /// On a line of its own after the body's `<`.
    AfterOpen(TextSize),
}

impl GraphHeader {
    pub(crate) fn of(graph: &ast::Graph) -> GraphHeader {
        let name_token = graph.name().and_then(|n| n.token());
        let body = graph.body();
        let insertion = body.as_ref().and_then(|body| {
            // Counted on the green tree: no syntax node per member.
            let members = body
                .syntax()
                .green()
                .children()
                .filter(|c| c.as_node().is_some())
                .count();
            match body.syntax().last_child() {
                Some(last) => Some(Insertion::AfterMember {
                    ordinal: members - 1,
                    len: last.text_range().len(),
                    indent: edit::indentation(&last),
                }),
                None => body
                    .l_angle()
                    .map(|open| Insertion::AfterOpen(open.text_range().end())),
            }
        });
        GraphHeader {
            name: name_token
                .as_ref()
                .map(|t| t.text().to_owned())
                .unwrap_or_default(),
            name_range: name_token.map(|t| t.text_range()),
            declares_init_sd: declares_variable(graph, "INIT_SD"),
            insertion,
        }
    }

    /// The insertion of `member` as a text edit in `layout`.
    pub(crate) fn insert_member(
        &self,
        layout: &VirtualLayout,
        member: &str,
    ) -> Option<(TextRange, String)> {
        match self.insertion.as_ref()? {
            Insertion::AfterMember {
                ordinal,
                len,
                indent,
            } => Some((
                TextRange::empty(layout.offset(*ordinal) + *len),
                format!("\n{indent}{member}"),
            )),
            Insertion::AfterOpen(at) => Some((TextRange::empty(*at), format!("\n  {member}\n"))),
        }
    }
}

/// Where the structure rules place members: either at their real offsets, or — so that their
/// results do not depend on where members stand — member `i` at `(i + 1) × 64 KiB`, with the
/// graph's header (positions before the first member) at its real offsets in the first
/// 64 KiB. [`VirtualLayout::place`] turns a virtual position back into a real one.
#[derive(Debug, Clone)]
pub enum VirtualLayout {
    Virtual,
    Real(Vec<TextSize>),
}

impl VirtualLayout {
    /// The size of a member's slot.
    pub const SLOT: u32 = 1 << 16;
    /// The most members the virtual layout holds.
    pub const MAX_MEMBERS: usize = (u32::MAX / Self::SLOT) as usize - 1;

    /// Where member `ordinal` starts. The virtual layout is only used for graphs that fit it
    /// (`GraphLayout::virtual_ok`: fewer than [`VirtualLayout::MAX_MEMBERS`] members, each and
    /// the header shorter than a slot), so that no position in it passes `u32::MAX`; past
    /// that it saturates rather than wrap or panic.
    pub fn offset(&self, ordinal: usize) -> TextSize {
        match self {
            VirtualLayout::Virtual => TextSize::from(
                u32::try_from(ordinal)
                    .ok()
                    .and_then(|o| o.checked_add(1))
                    .and_then(|slot| slot.checked_mul(Self::SLOT))
                    .unwrap_or(u32::MAX),
            ),
            VirtualLayout::Real(offsets) => offsets.get(ordinal).copied().unwrap_or_default(),
        }
    }

    /// The real position of a virtual one, given the real offsets of the members.
    pub fn place(position: TextSize, offsets: &[TextSize]) -> TextSize {
        let position = u32::from(position);
        match (position / Self::SLOT) as usize {
            0 => position.into(),
            slot => {
                offsets.get(slot - 1).copied().unwrap_or_default()
                    + TextSize::from(position % Self::SLOT)
            }
        }
    }
}

/// Does the graph declare a variable of this name (any section)?
pub(crate) fn declares_variable(graph: &ast::Graph, name: &str) -> bool {
    graph
        .var_sections()
        .flat_map(|s| s.decls())
        .filter_map(|d| d.name())
        .any(|n| n.text().eq_ignore_ascii_case(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn priorities(text: &str) -> Vec<Option<u64>> {
        let parse = higraph_syntax::parse(text);
        let Some(ast::Item::Graph(graph)) = parse.tree().items().next() else {
            return Vec::new();
        };
        effective_priorities(&graph)
    }

    #[test]
    fn implicit_priorities_follow_section_2_6() {
        // Range of state 0: implicit, explicit 1, implicit, explicit 3, implicit.
        let text = "graph G < state 0 < > state 1 < > \
                    trans 0->1 < > trans 0->1 prio 1 < > trans 0->1 < > \
                    trans 0->1 prio 3 < > trans 0->1 < > \
                    trans any->0 < > trans any->1 prio 1 < > \
                    trans 5->0 < > trans return->0 < > >";
        assert_eq!(
            priorities(text),
            vec![
                Some(2),
                Some(1),
                Some(4),
                Some(3),
                Some(5),
                Some(2),
                Some(1),
                None,
                None
            ]
        );
    }

    #[test]
    fn a_negative_priority_has_no_place_in_the_order() {
        // Range of state 0: -1 (no effective priority), implicit, explicit 0, implicit.
        let text = "graph G < state 0 < > state 1 < > \
                    trans 0->1 prio -1 < > trans 0->1 < > trans 0->1 prio 0 < > \
                    trans 0->1 < > trans 1->0 prio -0 < > trans 1->0 < > >";
        assert_eq!(
            priorities(text),
            vec![None, Some(1), Some(0), Some(2), Some(0), Some(1)]
        );
    }

    #[test]
    fn number_keys_are_the_integers() {
        for (text, key) in [
            ("7", "7"),
            ("007", "7"),
            ("0", "0"),
            ("000", "0"),
            ("-1", "-1"),
            ("-001", "-1"),
            ("-0", "0"),
            ("-00", "0"),
        ] {
            assert_eq!(number_key(text), key, "{text}");
        }
    }
}
