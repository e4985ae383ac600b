//! State graphs: declarations and structure.
//!
//! * `decls` — HG1202, HG1211, HG1212 (predefined names declared, `activate`); the rules of
//!   every variable declaration are in [`crate::rules::decls`];
//! * `structure` — HG2001, HG2002, HG2101–HG2106 (limits, state numbers, endpoints);
//! * `startup` — HG2201–HG2203, HG2401, HG2402 (startup transition, reachability);
//! * `priority` — HG2301–HG2306 (priorities per range, §2.6);
//! * `modes` — HG3001–HG3003, HG3007, HG3101, HG3102 (wait times, operating modes);
//! * `model` — the graph as these rules see it, and [`effective_priorities`] for the
//!   formatter.
//!
//! Time values themselves (HG3004–HG3006, HG3008) are checked with the STL operands.

mod decls;
pub(crate) mod facts;
pub(crate) mod model;
mod modes;
mod priority;
mod startup;
mod structure;

use higraph_syntax::ast;

use super::edit;
// Re-exported for the formatter; `rules/mod.rs` has to make `graph` visible to it.
pub(crate) use self::model::GraphModel;
#[allow(unused_imports)]
pub use self::model::effective_priorities;
use super::Ctx;

/// Runs every graph rule of this module on one graph, whose members `model` describes.
pub(crate) fn check(ctx: &mut Ctx<'_>, graph: &ast::Graph, model: &GraphModel<'_>) {
    decls::check_variables(ctx, graph, &format!("graph {}", model.name));
    decls::check_activate(ctx, graph);
    structure::check(ctx, graph, model);
    startup::check(ctx, graph, model);
    priority::check(ctx, model);
    modes::check(ctx, model);
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
}
