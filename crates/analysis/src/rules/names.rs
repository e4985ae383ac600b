//! HG1101–HG1103: the name rules of the original declaration editor, for every declared name
//! (§2.2): graphs, groups, charts, variables (of graphs, charts and block interfaces),
//! instances, sequencers, steps, chart transitions, jumps, loops, and symbols written as a NAME.
//!
//! * HG1101 — the name ends with `_`; fix: drop the trailing underscores.
//! * HG1102 — the name contains `__`; fix: collapse each run of `_` into one.
//! * HG1103 — the name is a reserved word of Appendix A.1 for the file's mnemonic set.
//!
//! The rename fixes are offered only if the new name is valid (passes all three rules) and free
//! in the name's namespace. They are renames of the workspace rename engine
//! ([`crate::ide::rename`], deferred to [`crate::check`] through
//! [`crate::diag::DiagFix::rename_to`]): they edit the declaration and every reference to it in
//! every file, exactly as the editor's rename would — and are dropped where it refuses the new
//! name. Names that are not identifiers (quoted symbols, numeric step names) are exempt.

use std::collections::HashSet;

use higraph_syntax::{SyntaxKind, SyntaxToken, ast, ast::AstNode};

use super::Ctx;
use crate::lang;

/// Where a declared name lives: decides which names a rename must avoid.
enum Namespace {
    /// Graphs, groups, charts and `NAME` symbols: the workspace namespace.
    Global,
    /// A graph variable: the graph's variables and the predefined variables.
    GraphVariable(Vec<String>),
    /// A chart variable: the chart's variables.
    ChartVariable(Vec<String>),
    /// A block interface variable: the interface's variables.
    BlockVariable(Vec<String>),
    /// A group instance: the group's instances.
    Instance(Vec<String>),
    /// A sequencer: the chart's sequencers.
    Sequencer(Vec<String>),
    /// A step: the sequencer's steps.
    Step(Vec<String>),
    /// A chart transition, jump or loop: the sequencer's transitions.
    ChartTransition(Vec<String>),
}

/// Checks the graph's name and its variables.
pub(crate) fn check_graph(ctx: &mut Ctx<'_>, graph: &ast::Graph) {
    check_name(ctx, graph.name(), &Namespace::Global);
    check_variables(ctx, graph.var_sections(), Namespace::GraphVariable);
}

/// Checks the group's name and its instances.
pub(crate) fn check_group(ctx: &mut Ctx<'_>, group: &ast::Group) {
    check_name(ctx, group.name(), &Namespace::Global);
    let instances: Vec<String> = group
        .instances()
        .filter_map(|i| i.name())
        .map(|n| n.text())
        .collect();
    let namespace = Namespace::Instance(instances);
    let mut seen = HashSet::new();
    for instance in group.instances() {
        check_first_name(ctx, instance.name(), &namespace, &mut seen);
    }
}

/// Checks the chart's name, variables, sequencers and sequencer elements.
///
/// In an IEC chart (`profile iec;`) the chart's own names (not the chart's name, a workspace
/// name) reserve the words of `docs/iec.md` §2, and its actions are declared names too (in
/// the namespace of the chart's variables, HG7510).
pub(crate) fn check_chart(ctx: &mut Ctx<'_>, chart: &ast::Chart) {
    let iec = chart.profile() == ast::Profile::Iec;
    check_name(ctx, chart.name(), &Namespace::Global);
    check_variables_in(ctx, chart.var_sections(), Namespace::ChartVariable, iec);
    if iec {
        let names: Vec<String> = chart
            .var_sections()
            .flat_map(|s| s.decls())
            .filter_map(|d| d.name())
            .chain(chart.actions().filter_map(|a| a.name()))
            .map(|n| n.text())
            .collect();
        let namespace = Namespace::ChartVariable(names);
        let mut seen = HashSet::new();
        for action in chart.actions() {
            check_first_name_in(ctx, action.name(), &namespace, &mut seen, true);
        }
    }
    let sequencers: Vec<ast::Sequencer> = chart.sequencers().collect();
    let sequencer_names: Vec<String> = sequencers
        .iter()
        .filter_map(|s| s.name())
        .map(|n| n.text())
        .collect();
    let namespace = Namespace::Sequencer(sequencer_names);
    let mut seen = HashSet::new();
    for sequencer in &sequencers {
        if check_first_name_in(ctx, sequencer.name(), &namespace, &mut seen, iec) {
            check_sequencer_elements(ctx, sequencer, iec);
        }
    }
}

/// Steps, chart transitions, jumps and loops of one sequencer, at every nesting level.
fn check_sequencer_elements(ctx: &mut Ctx<'_>, sequencer: &ast::Sequencer, iec: bool) {
    let elements: Vec<ast::SeqElement> = sequencer
        .syntax()
        .descendants()
        .filter_map(ast::SeqElement::cast)
        .collect();
    let steps: Vec<String> = elements
        .iter()
        .filter_map(|e| match e {
            ast::SeqElement::Step(s) => s.name().map(|n| n.text()),
            _ => None,
        })
        .collect();
    let transitions: Vec<String> = elements
        .iter()
        .filter_map(|e| transition_name(e).flatten())
        .map(|n| n.text())
        .collect();
    let (steps, transitions) = (
        Namespace::Step(steps),
        Namespace::ChartTransition(transitions),
    );
    let (mut seen_steps, mut seen_transitions) = (HashSet::new(), HashSet::new());
    for element in &elements {
        let (name, ns, seen) = match element {
            ast::SeqElement::Step(s) => (s.name(), &steps, &mut seen_steps),
            _ => match transition_name(element) {
                Some(name) => (name, &transitions, &mut seen_transitions),
                None => continue,
            },
        };
        check_first_name_in(ctx, name, ns, seen, iec);
    }
}

/// The name of a chart transition, jump or loop (`None` inside if it has none); `None` for
/// other elements.
fn transition_name(element: &ast::SeqElement) -> Option<Option<ast::Name>> {
    match element {
        ast::SeqElement::Trans(t) => Some(t.name()),
        ast::SeqElement::Jump(j) => Some(j.name()),
        ast::SeqElement::Loop(l) => Some(l.name()),
        ast::SeqElement::Step(_) | ast::SeqElement::Parallel(_) | ast::SeqElement::Alt(_) => None,
    }
}

/// Checks the symbols written as a NAME (quoted symbols are exempt).
pub(crate) fn check_symbols(ctx: &mut Ctx<'_>, table: &ast::Symbols) {
    for symbol in table.symbols() {
        // A later symbol of a name is reported (HG6003, HG1301) and otherwise ignored (C3).
        if !super::is_later_symbol(ctx, &symbol) {
            check_name(ctx, symbol.name(), &Namespace::Global);
        }
    }
}

/// Checks the variables of a `block` interface.
pub(crate) fn check_block_interface(ctx: &mut Ctx<'_>, interface: &ast::BlockInterface) {
    check_variables(ctx, interface.var_sections(), Namespace::BlockVariable);
}

/// Checks the variables of some sections; `namespace` makes their namespace from the names of
/// all of them, in declaration order.
fn check_variables(
    ctx: &mut Ctx<'_>,
    sections: impl Iterator<Item = ast::VarSection>,
    namespace: fn(Vec<String>) -> Namespace,
) {
    check_variables_in(ctx, sections, namespace, false);
}

/// [`check_variables`] with the reserved words of an IEC chart when `iec`.
fn check_variables_in(
    ctx: &mut Ctx<'_>,
    sections: impl Iterator<Item = ast::VarSection>,
    namespace: fn(Vec<String>) -> Namespace,
    iec: bool,
) {
    let decls: Vec<ast::VarDecl> = sections.flat_map(|s| s.decls()).collect();
    let names: Vec<String> = decls
        .iter()
        .filter_map(|d| d.name())
        .map(|n| n.text())
        .collect();
    let namespace = namespace(names);
    let mut seen = HashSet::new();
    for decl in &decls {
        check_first_name_in(ctx, decl.name(), &namespace, &mut seen, iec);
    }
}

/// [`check_name`] for the first declaration of a name in its namespace (`seen` holds the
/// names so far); a later duplicate is reported by its own rule and otherwise ignored (C3).
/// Returns whether the name was the first.
fn check_first_name(
    ctx: &mut Ctx<'_>,
    name: Option<ast::Name>,
    ns: &Namespace,
    seen: &mut HashSet<String>,
) -> bool {
    check_first_name_in(ctx, name, ns, seen, false)
}

/// [`check_first_name`] with the reserved words of an IEC chart when `iec`.
fn check_first_name_in(
    ctx: &mut Ctx<'_>,
    name: Option<ast::Name>,
    ns: &Namespace,
    seen: &mut HashSet<String>,
    iec: bool,
) -> bool {
    if let Some(name) = &name
        && !seen.insert(crate::index::key(&name.text()))
    {
        return false;
    }
    check_name_in(ctx, name, ns, iec);
    true
}

/// HG1101–HG1103 for one declared name.
fn check_name(ctx: &mut Ctx<'_>, name: Option<ast::Name>, ns: &Namespace) {
    check_name_in(ctx, name, ns, false);
}

/// HG1101–HG1103 for one declared name; `iec`: a name of an IEC chart, where HG1103 reserves
/// the words of `docs/iec.md` §2 instead of the STL operations.
fn check_name_in(ctx: &mut Ctx<'_>, name: Option<ast::Name>, ns: &Namespace, iec: bool) {
    let Some(token) = name.and_then(|n| n.token()) else {
        return;
    };
    // Quoted symbols and numeric step names are not identifiers (§2.2, HG7102).
    if token.kind() != SyntaxKind::IDENT {
        return;
    }
    let text = token.text();
    let range = token.text_range();
    if text.ends_with('_') {
        let message = format!("name '{text}' must not end with '_'");
        let diag = ctx.diag("HG1101", range, message);
        let diag = with_rename(ctx, diag, &token, text.trim_end_matches('_'), ns);
        ctx.push(diag);
    }
    if text.contains("__") {
        let message = format!("name '{text}' must not contain '__'");
        let diag = ctx.diag("HG1102", range, message);
        let diag = with_rename(ctx, diag, &token, &collapse_underscores(text), ns);
        ctx.push(diag);
    }
    let reserved = if iec {
        crate::iec::reserved_kind(text)
    } else {
        lang::reserved_kind(text, ctx.mnemonic)
    };
    if let Some(kind) = reserved {
        let message = format!("'{text}' is reserved ({kind}) and cannot be used as a name");
        let diag = ctx.diag("HG1103", range, message);
        ctx.push(diag);
    }
}

/// `A__B___C` → `A_B_C`.
fn collapse_underscores(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c == '_' && out.ends_with('_') {
            continue;
        }
        out.push(c);
    }
    out
}

/// Adds the rename fix if `new_name` is valid and free (the rename engine decides the rest).
fn with_rename(
    ctx: &Ctx<'_>,
    diag: crate::diag::Diag,
    declaration: &SyntaxToken,
    new_name: &str,
    ns: &Namespace,
) -> crate::diag::Diag {
    if !is_valid_name(new_name, ctx.mnemonic) || !is_free(ctx, new_name, declaration.text(), ns) {
        return diag;
    }
    diag.rename_fix(
        format!("Rename to '{new_name}'"),
        ctx.loc(declaration.text_range()),
        new_name,
    )
}

/// Does `name` pass the name rules (an identifier without trailing `_`, without `__`, not
/// reserved)?
fn is_valid_name(name: &str, mnemonic: lang::Mnemonic) -> bool {
    lang::is_identifier(name)
        && !name.ends_with('_')
        && !name.contains("__")
        && lang::reserved_kind(name, mnemonic).is_none()
}

/// Is `new_name` unused in the namespace (apart from the declaration being renamed)?
fn is_free(ctx: &Ctx<'_>, new_name: &str, old_name: &str, ns: &Namespace) -> bool {
    let taken = |names: &Vec<String>| {
        names
            .iter()
            .any(|n| n.eq_ignore_ascii_case(new_name) && !n.eq_ignore_ascii_case(old_name))
    };
    match ns {
        Namespace::Global => {
            ctx.index.item(new_name).is_none() && ctx.index.symbol(new_name).is_none()
        }
        Namespace::GraphVariable(names) => !taken(names) && lang::predefined(new_name).is_none(),
        Namespace::ChartVariable(names)
        | Namespace::BlockVariable(names)
        | Namespace::Instance(names)
        | Namespace::Sequencer(names)
        | Namespace::Step(names)
        | Namespace::ChartTransition(names) => !taken(names),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collapses_runs_of_underscores() {
        assert_eq!(collapse_underscores("A__B___C"), "A_B_C");
        assert_eq!(collapse_underscores("__A"), "_A");
    }

    #[test]
    fn validates_new_names() {
        assert!(is_valid_name("Motor_1", lang::Mnemonic::Simatic));
        assert!(!is_valid_name("", lang::Mnemonic::Simatic));
        assert!(!is_valid_name("A_", lang::Mnemonic::Simatic));
        assert!(!is_valid_name("BOOL", lang::Mnemonic::Simatic));
        assert!(!is_valid_name("U", lang::Mnemonic::Simatic));
        assert!(is_valid_name("U", lang::Mnemonic::International));
    }
}
