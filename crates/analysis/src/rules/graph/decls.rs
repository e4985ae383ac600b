//! Declarations of graphs: HG1202 (predefined name declared) and HG1211/HG1212 (`activate`).
//! The rules every variable declaration has (HG1201, HG1203–HG1206, HG1213, HG1215) are in
//! [`crate::rules::decls`], which calls back here for HG1202 on every declared name.

use higraph_syntax::{SyntaxNode, TextRange, TextSize, ast, ast::AstNode};

use super::edit;
use crate::{
    lang,
    rules::{
        Ctx,
        decls::{self, Owner},
    },
};

/// HG1201–HG1206, HG1213 and HG1215 for the graph's variables. `owner_text` is the `{owner}`
/// of messages (`graph G`).
pub(super) fn check_variables(ctx: &mut Ctx<'_>, graph: &ast::Graph, owner_text: &str) {
    decls::check_sections(
        ctx,
        graph.var_sections(),
        Owner::Graph,
        owner_text,
        |ctx, decl, name, range| check_predefined(ctx, graph, decl, name, range),
    );
}

/// HG1202: a declared predefined variable.
fn check_predefined(
    ctx: &mut Ctx<'_>,
    graph: &ast::Graph,
    decl: &ast::VarDecl,
    text: &str,
    range: TextRange,
) {
    let Some(pre) = lang::predefined(text) else {
        return;
    };
    let removal = (ctx.loc(edit::removal_range(decl.syntax())), String::new());
    let diag = if pre.active_by_default {
        ctx.diag(
            "HG1202",
            range,
            format!("'{text}' is predefined in every graph and must not be declared"),
        )
        .fix_edits("Remove the declaration", vec![removal])
    } else {
        let message = format!(
            "'{text}' is predefined in every graph and must not be declared; use 'activate {text};' instead"
        );
        let activation = (!activates(graph, pre.name))
            .then(|| activation_edit(graph, pre.name))
            .flatten();
        let diag = ctx.diag("HG1202", range, message);
        match activation {
            Some((at, new)) => diag.fix_edits(
                format!("Remove the declaration and activate '{}'", pre.name),
                vec![removal, (ctx.loc(at), new)],
            ),
            None => diag.fix_edits("Remove the declaration", vec![removal]),
        }
    };
    ctx.push(diag);
}

/// Does an `activate` of the graph name `name`?
fn activates(graph: &ast::Graph, name: &str) -> bool {
    graph
        .activates()
        .flat_map(|a| a.names())
        .any(|n| n.text().eq_ignore_ascii_case(name))
}

/// An edit that activates `name`: appended to the graph's first `activate`, or a new
/// `activate name;` after the last variable section.
pub(super) fn activation_edit(graph: &ast::Graph, name: &str) -> Option<(TextRange, String)> {
    let activate = graph.activates().next();
    if let Some(last) = activate.and_then(|a| a.names().last()) {
        let end = last.syntax().text_range().end();
        return Some((TextRange::empty(end), format!(", {name}")));
    }
    let section = graph.var_sections().last()?;
    Some(edit::insert_member_after(
        section.syntax(),
        &format!("activate {name};"),
    ))
}

/// HG1211 and HG1212: what `activate` may name.
pub(super) fn check_activate(ctx: &mut Ctx<'_>, graph: &ast::Graph) {
    let mut activated: Vec<String> = Vec::new();
    for activate in graph.activates() {
        let names: Vec<ast::NameRef> = activate.names().collect();
        for (i, name) in names.iter().enumerate() {
            let Some(token) = name.token() else {
                continue;
            };
            let text = token.text();
            let range = token.text_range();
            let removal = list_removal(activate.syntax(), &names, i);
            let diag = match lang::predefined(text) {
                None => ctx.diag(
                    "HG1211",
                    range,
                    format!("only predefined variables can be activated; '{text}' is not one"),
                ),
                Some(pre)
                    if pre.active_by_default
                        || activated.iter().any(|a| a.eq_ignore_ascii_case(pre.name)) =>
                {
                    ctx.diag("HG1212", range, format!("'{text}' is already active"))
                }
                Some(pre) => {
                    activated.push(pre.name.to_owned());
                    continue;
                }
            };
            let diag = diag.fix(
                format!("Remove '{text}' from the list"),
                ctx.loc(removal),
                "",
            );
            ctx.push(diag);
        }
    }
}

/// The text to delete to remove the `i`th name of an `activate` list: the name and one
/// adjacent comma, or the whole statement if it is the only name.
fn list_removal(activate: &SyntaxNode, names: &[ast::NameRef], i: usize) -> TextRange {
    let range = |n: &ast::NameRef| n.syntax().text_range();
    if names.len() <= 1 {
        return edit::removal_range(activate);
    }
    match (names.get(i), names.get(i + 1)) {
        (Some(this), Some(next)) => TextRange::new(range(this).start(), range(next).start()),
        (Some(this), None) => {
            let start = i
                .checked_sub(1)
                .and_then(|p| names.get(p))
                .map_or(range(this).start(), |p| range(p).end());
            TextRange::new(start, range(this).end())
        }
        _ => TextRange::empty(TextSize::from(0)),
    }
}
