//! Declarations of graphs and `block` interfaces: HG1201 (duplicate variable), HG1202
//! (predefined name declared), HG1203 (`msg` outside `in_out`), HG1204 (`msg` not BOOL),
//! HG1205/HG1206 (initial value), HG1211/HG1212 (`activate`), HG1213 (`STRING[n]` length),
//! HG1215 (unknown type).

use std::collections::HashMap;

use higraph_syntax::{
    SyntaxKind, SyntaxNode, TextRange, TextSize, ast,
    ast::AstNode,
    literal::{self, Acceptance},
};

use super::edit;
use crate::{
    closest::closest,
    index,
    lang::{self, Section, Type},
    rules::Ctx,
};

/// The item the declarations belong to.
#[derive(Debug, Clone, Copy)]
pub(super) enum Owner<'a> {
    Graph(&'a ast::Graph),
    /// A `block` interface: POINTER, ANY and the block types are allowed, `msg` is not.
    BlockInterface,
}

/// The block-interface-only type names (`language.md` §3.1).
const INTERFACE_TYPES: &[&str] = &["POINTER", "ANY", "BLOCK_FC", "BLOCK_FB", "BLOCK_DB"];

/// HG1201–HG1206, HG1213, HG1215 for every declaration of the sections. `owner_text` is the
/// `{owner}` of messages (`graph G`, `block FC 10`).
pub(super) fn check_sections(
    ctx: &mut Ctx<'_>,
    sections: &[ast::VarSection],
    owner: Owner<'_>,
    owner_text: &str,
) {
    let mut first: HashMap<String, (TextRange, String)> = HashMap::new();
    for section in sections {
        let Some(kind) = section
            .keyword()
            .and_then(|k| Section::from_keyword(k.text()))
        else {
            continue;
        };
        for decl in section.decls() {
            let Some(name) = decl.name() else {
                continue;
            };
            let Some(token) = name.token() else {
                continue;
            };
            let text = token.text().to_owned();
            let range = token.text_range();
            match first.get(&index::key(&text)) {
                Some((original, original_text)) => {
                    let diag = ctx
                        .diag(
                            "HG1201",
                            range,
                            format!("variable '{text}' is already declared in {owner_text}"),
                        )
                        .related(
                            ctx.loc(*original),
                            format!("first declaration of '{original_text}'"),
                        );
                    ctx.push(diag);
                }
                None => {
                    first.insert(index::key(&text), (range, text.clone()));
                }
            }
            if let Owner::Graph(graph) = owner {
                check_predefined(ctx, graph, &decl, &text, range);
            }
            // C1: a broken declaration still declares its name; its other parts are not
            // checked.
            if decl
                .syntax()
                .descendants()
                .any(|n| n.kind() == SyntaxKind::ERROR)
            {
                continue;
            }
            let ty = check_type(ctx, &decl, owner);
            check_msg(ctx, &decl, &text, kind, owner, ty);
            if let Some(ty) = ty {
                check_initial_value(ctx, &decl, ty);
            }
        }
    }
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
        .members()
        .filter_map(|m| match m {
            ast::GraphMember::Activate(a) => Some(a),
            _ => None,
        })
        .flat_map(|a| a.names())
        .any(|n| n.text().eq_ignore_ascii_case(name))
}

/// An edit that activates `name`: appended to the graph's first `activate`, or a new
/// `activate name;` after the last variable section.
pub(super) fn activation_edit(graph: &ast::Graph, name: &str) -> Option<(TextRange, String)> {
    let activate = graph.members().find_map(|m| match m {
        ast::GraphMember::Activate(a) => Some(a),
        _ => None,
    });
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

/// HG1213 and HG1215. Returns the declared type if it is known and valid.
fn check_type(ctx: &mut Ctx<'_>, decl: &ast::VarDecl, owner: Owner<'_>) -> Option<Type> {
    let type_ref = decl.ty()?;
    let name = type_ref.name()?;
    let interface = matches!(owner, Owner::BlockInterface);
    let Some(ty) = Type::from_name(name.text(), interface) else {
        let mut candidates: Vec<&str> = Type::NAMES.to_vec();
        if interface {
            candidates.extend_from_slice(INTERFACE_TYPES);
        }
        let mut diag = ctx.diag(
            "HG1215",
            name.text_range(),
            format!("unknown data type '{}'", name.text()),
        );
        if let Some(best) = closest(name.text(), candidates) {
            diag = diag.fix(
                format!("Replace with '{best}'"),
                ctx.loc(name.text_range()),
                best,
            );
        }
        ctx.push(diag);
        return None;
    };
    match (ty, type_ref.length()) {
        (Type::String(_), Some(length)) => {
            let n = length.text();
            match n.parse::<u16>() {
                Ok(n @ 1..=254) => Some(Type::String(n)),
                _ => {
                    let diag = ctx.diag(
                        "HG1213",
                        type_ref.syntax().text_range(),
                        format!("string length {n} is outside 1..254"),
                    );
                    ctx.push(diag);
                    None
                }
            }
        }
        (ty, _) => Some(ty),
    }
}

/// HG1203 and HG1204: `msg` outside a graph's `in_out`, and `msg` on a type other than BOOL.
fn check_msg(
    ctx: &mut Ctx<'_>,
    decl: &ast::VarDecl,
    name: &str,
    section: Section,
    owner: Owner<'_>,
    ty: Option<Type>,
) {
    let Some(msg) = decl.msg_kind() else {
        return;
    };
    if matches!(owner, Owner::BlockInterface) || section != Section::InOut {
        let diag = ctx
            .diag(
                "HG1203",
                msg.syntax().text_range(),
                format!(
                    "message variables belong in 'in_out'; '{name}' is in '{}'",
                    section.as_str()
                ),
            )
            .fix(
                "Remove the 'msg' clause",
                ctx.loc(edit::removal_range(msg.syntax())),
                "",
            );
        ctx.push(diag);
    }
    if let (Some(ty), Some(type_ref)) = (ty, decl.ty())
        && ty != Type::Bool
    {
        let range = type_ref.syntax().text_range();
        let diag = ctx
            .diag(
                "HG1204",
                range,
                format!("message variable '{name}' must be BOOL, not {ty}"),
            )
            .fix("Change the type to BOOL", ctx.loc(range), "BOOL");
        ctx.push(diag);
    }
}

/// HG1205 and HG1206: the initial value must fit the declared type (Appendix C.2).
fn check_initial_value(ctx: &mut Ctx<'_>, decl: &ast::VarDecl, ty: Type) {
    let Some(lit) = decl.initial_value().and_then(|v| v.literal()) else {
        return;
    };
    let range = lit.syntax().text_range();
    let text = lit.text().trim().to_owned();
    // A malformed or out-of-range constant has an unknown type (HG0006/HG0007, C2).
    let Ok(value) = literal::check_literal(&text) else {
        return;
    };
    let message = if matches!(ty, Type::Timer | Type::Counter) {
        format!("{ty} variables take no initial value")
    } else {
        match literal::accepts(&ty.to_string(), &value) {
            Acceptance::Accepted => return,
            Acceptance::Mismatch => format!("initial value {text} does not fit type {ty}"),
            Acceptance::OutOfRange { min, max } => {
                let diag = ctx.diag(
                    "HG1206",
                    range,
                    format!("initial value {text} is out of range for {ty} ({min} to {max})"),
                );
                ctx.push(diag);
                return;
            }
        }
    };
    let diag = ctx.diag("HG1205", range, message);
    ctx.push(diag);
}

/// HG1211 and HG1212: what `activate` may name.
pub(super) fn check_activate(ctx: &mut Ctx<'_>, graph: &ast::Graph) {
    let mut activated: Vec<String> = Vec::new();
    for activate in graph.members().filter_map(|m| match m {
        ast::GraphMember::Activate(a) => Some(a),
        _ => None,
    }) {
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
