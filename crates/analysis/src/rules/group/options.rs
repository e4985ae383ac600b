//! Group options (`diagnostics.md` §3.8): HG8001 (`reserve` without `restructure`), HG8006
//! (`restructure`, off by default), HG8007 (unknown option), HG8008 (option values) and HG8009
//! (an option given twice).

use std::collections::HashMap;

use higraph_syntax::{
    SyntaxKind, SyntaxNode, TextRange,
    ast::{self, AstNode},
};

use crate::rules::Ctx;

/// The known options, in the order of §3.8.
const KNOWN_OPTIONS: [&str; 6] = [
    "cyclic_rlo0",
    "any_once",
    "precyclic_on_entry",
    "restructure",
    "reserve",
    "refdata",
];

/// The largest memory reserve in words (HG8008).
const MAX_RESERVE: u64 = 32767;

/// One `option` of a group.
struct OptionInfo {
    /// The name as written.
    name: String,
    name_range: TextRange,
    /// The value token's text and range, if any.
    value: Option<(String, TextRange)>,
    /// The option: from `option` through the last token before `;`.
    range: TextRange,
    /// The whole option, `;` included.
    node: TextRange,
}

impl OptionInfo {
    fn from_node(option: &ast::GroupOption) -> Option<OptionInfo> {
        let name = option.name()?;
        let token = name.token()?;
        Some(OptionInfo {
            name: name.text(),
            name_range: token.text_range(),
            value: option
                .value()
                .map(|v| (v.text().to_owned(), v.text_range())),
            range: statement_range(option.syntax())?,
            node: option.syntax().text_range(),
        })
    }

    fn is(&self, known: &str) -> bool {
        self.name.eq_ignore_ascii_case(known)
    }
}

/// From the first significant token of `node` through the last one before its `;`.
pub(super) fn statement_range(node: &SyntaxNode) -> Option<TextRange> {
    let tokens: Vec<_> = node
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .collect();
    let first = tokens.first()?;
    let last = tokens
        .iter()
        .rev()
        .find(|t| t.kind() != SyntaxKind::SEMI)
        .unwrap_or(first);
    Some(TextRange::new(
        first.text_range().start(),
        last.text_range().end().max(first.text_range().start()),
    ))
}

/// HG8001 and HG8006–HG8009 for the options of one group.
pub(super) fn check(ctx: &mut Ctx<'_>, group: &ast::Group) {
    let options: Vec<OptionInfo> = group
        .options()
        .filter_map(|o| OptionInfo::from_node(&o))
        .collect();
    let mut first: HashMap<String, &OptionInfo> = HashMap::new();
    for option in &options {
        let Some(known) = KNOWN_OPTIONS.iter().find(|k| option.is(k)) else {
            report_unknown(ctx, option);
            continue;
        };
        if let Some(original) = first.get(*known) {
            report_repeated(ctx, option, original);
            continue;
        }
        first.insert((*known).to_owned(), option);
        check_value(ctx, option, known);
        if *known == "restructure" {
            let diag = ctx.diag(
                "HG8006",
                option.range,
                "'option restructure' rebuilds the DB; changes can then be loaded only with the CPU in STOP",
            );
            ctx.push(diag);
        }
    }
    if let Some(reserve) = first.get("reserve")
        && !first.contains_key("restructure")
    {
        let at = ctx.loc(TextRange::empty(reserve.range.start()));
        let diag = ctx
            .diag(
                "HG8001",
                reserve.range,
                "'option reserve' has no effect without 'option restructure'",
            )
            .fix("Add 'option restructure;'", at, "option restructure; ");
        ctx.push(diag);
    }
}

/// HG8007 with the closest known option as a fix.
fn report_unknown(ctx: &mut Ctx<'_>, option: &OptionInfo) {
    let diag = ctx.diag(
        "HG8007",
        option.name_range,
        format!("unknown option '{}'", option.name),
    );
    let diag = ctx.with_closest_fix(diag, option.name_range, &option.name, KNOWN_OPTIONS);
    ctx.push(diag);
}

/// HG8009 for a later repetition (which is otherwise ignored, C3).
fn report_repeated(ctx: &mut Ctx<'_>, option: &OptionInfo, original: &OptionInfo) {
    let diag = ctx
        .diag(
            "HG8009",
            option.range,
            format!("option {} is given twice", option.name),
        )
        .related(
            ctx.loc(original.range),
            format!("option {} is first given here", original.name),
        )
        .fix("Remove the repeated option", ctx.loc(option.node), "");
    ctx.push(diag);
}

/// HG8008: `reserve` needs 1..32767 words; the other options take no value.
fn check_value(ctx: &mut Ctx<'_>, option: &OptionInfo, known: &str) {
    if known == "reserve" {
        let valid = option
            .value
            .as_ref()
            .and_then(|(text, _)| text.parse::<u64>().ok())
            .is_some_and(|n| (1..=MAX_RESERVE).contains(&n));
        if !valid {
            let diag = ctx.diag(
                "HG8008",
                option.range,
                "option reserve needs a number of words from 1 to 32767",
            );
            ctx.push(diag);
        }
        return;
    }
    let Some((_, value_range)) = &option.value else {
        return;
    };
    let removal = TextRange::new(
        option.name_range.end(),
        value_range.end().max(option.name_range.end()),
    );
    let diag = ctx
        .diag(
            "HG8008",
            option.range,
            format!("option {} takes no value", option.name),
        )
        .fix("Remove the value", ctx.loc(removal), "");
    ctx.push(diag);
}
