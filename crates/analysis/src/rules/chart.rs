//! Sequence charts (`language.md` §6, `diagnostics.md` §3.7): HG7xxx, and the chart side of
//! HG1xxx, HG3xxx and HG4xxx.
//!
//! | module      | codes |
//! |-------------|-------|
//! | `decls`     | chart variables: the declaration rules of `rules::decls`, and HG1210 |
//! | `props`     | HG7105, HG7206–HG7208, HG7401–HG7403, HG7406 |
//! | `model`     | the element tree of one sequencer (no diagnostics) |
//! | `names`     | HG7101–HG7104 |
//! | `topology`  | HG7001–HG7012, HG7201–HG7203, HG1104 on jump and loop targets |
//! | `parts`     | HG7204, HG7205, HG7209, HG7301, HG7302, HG7303, HG7401, HG7404, HG7405 |
//! | `operands`  | chart operand resolution (§2.4): HG4101, HG1104, HG7309, HG7310, HG4009–HG4012 |
//! | `exprs`     | conditions, statements and qualifier operands: HG7304–HG7308 |
//! | `times`     | `min`, `max` and qualifier times: HG3004–HG3006, HG3008 |
//! | `term`      | successor steps and HG7311 |
//!
//! Every item is checked from its own syntax tree, so all ranges here are item-relative.
//!
//! Decisions where `diagnostics.md` leaves room:
//!
//! * C1: a chart, sequencer, step, transition, jump or loop whose name did not parse is not
//!   checked by the rules that name it (and takes no part in the topology); a construct
//!   (condition, statement, qualifier action, `min`/`max`, property, declaration) with an error
//!   node still counts its operands as uses but gets no diagnostics.
//! * "Items" and "properties" (HG7403, HG7404, HG7405, HG7406) are underlined like statements:
//!   without their `;`.
//! * HG7008: a loop back to the step it is attached to is allowed (only a target *after* that
//!   step is reported). HG7007/HG7008/HG7011 need a resolved target; HG7008 and HG7011 also need
//!   a plain step as source (otherwise HG7009).
//! * HG7006's second variant repeats `{jump/loop} {j}: `.
//! * HG7307 names a constant operand `a constant` (its type would read oddly: `TRUE is BOOL`).
//! * HG7403 calls a repeated `run` option `run {option}`; the other properties by keyword.
//! * HG7311 compares variables, symbols and addresses; external references and `SFC.` paths
//!   are never "the same operand". Its `{part}` is that of the successor's first clashing write.
//! * Types: STRING lengths are not compared (HG7305, HG7306); a string literal is `STRING[n]`
//!   with its length. Comparisons and logic expressions are BOOL even when an operand is unknown.
//! * A name spelled like an address (`MW10`) is an address only in the file's mnemonic set; an
//!   address written with a space in the other set is read in its translated form (HG4007 is
//!   a rule of STL statements).
//! * The address rules HG4009–HG4012 apply to chart addresses too; HG1204, HG1213 and HG1215
//!   to chart variables (as in graphs).
//! * HG1203 in every section (`in_out` too: a chart has no messages); its message says so.

pub(crate) mod decls;
mod exprs;
pub(crate) mod model;
mod names;
pub(crate) mod operands;
mod parts;
mod props;
mod term;
mod times;
mod topology;

use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange,
    ast::{self, AstNode},
};

use super::{Ctx, decls::Var, has_error};

/// Checks one chart: its variables, properties and sequencers.
pub(crate) fn check(ctx: &mut Ctx<'_>, chart: &ast::Chart) {
    // C1: every chart rule names the chart; a chart whose name did not parse is not checked.
    let Some(name) = chart.name().and_then(|n| n.token()) else {
        return;
    };
    let info = ChartInfo {
        name: name.text().to_owned(),
        is_type: chart.is_type(),
        chart: chart.clone(),
    };
    let vars = decls::declare(ctx, &info);
    decls::check_fb_types(ctx, &info, &vars);
    let mut scope = Scope::new(info, vars);
    let chart_props = props::check_props(ctx, &scope.chart);
    props::check_sequencers(ctx, &scope.chart);
    check_actions(ctx, &scope);
    let mut seen = std::collections::HashSet::new();
    for sequencer in chart.sequencers() {
        let later = sequencer
            .name()
            .is_some_and(|n| !seen.insert(crate::index::key(&n.text())));
        let reported = ctx.out.diags.len();
        check_sequencer(ctx, &mut scope, &chart_props, &sequencer);
        if later {
            // C3: a later sequencer of a name is reported (HG7105) and otherwise ignored; the
            // variables it names still count as used (HG1210).
            ctx.out.diags.truncate(reported);
        }
    }
    exprs::Walker::new(ctx, &mut scope).actions();
    decls::report_unused(ctx, &scope);
    report_unused_actions(ctx, &scope);
}

/// HG7511: an action of an IEC chart that no qualifier names never runs.
fn report_unused_actions(ctx: &mut Ctx<'_>, scope: &Scope) {
    if !scope.iec {
        return;
    }
    for (action, used) in scope.actions.iter().zip(&scope.action_used) {
        if action.duplicate || *used {
            continue;
        }
        let diag = ctx.diag(
            "HG7511",
            action.name_range,
            format!(
                "action '{}' is never used: no qualifier of a step names it, so it never runs",
                action.name
            ),
        );
        ctx.push(diag);
    }
}

/// The chart's actions as declarations: HG7502 for each in a PCS 7 chart, HG7510 for a name
/// an earlier action or a variable has.
fn check_actions(ctx: &mut Ctx<'_>, scope: &Scope) {
    // `scope.actions` holds the named actions in text order.
    let mut decls = scope.actions.iter();
    for action in scope.chart.chart.actions() {
        let Some(token) = action.name().and_then(|n| n.token()) else {
            continue;
        };
        let decl = decls.next();
        if !scope.iec {
            let diag = ctx.diag(
                "HG7502",
                header_range(action.syntax()),
                format!("action {} needs 'profile iec;'", token.text()),
            );
            let diag = with_profile_fix(ctx, diag, &scope.chart.chart);
            ctx.push(diag);
            continue;
        }
        if !decl.is_some_and(|d| d.duplicate) {
            continue;
        }
        let name = token.text();
        let earlier_action = scope
            .actions
            .iter()
            .find(|a| !a.duplicate && a.name.eq_ignore_ascii_case(name));
        let earlier_var = scope.var(name).map(|i| &scope.vars[i]);
        let (range, what) = match (earlier_var, earlier_action) {
            (Some(var), _) => (var.name_range, format!("variable {}", var.name)),
            (None, Some(action)) => (action.name_range, format!("action {}", action.name)),
            (None, None) => continue,
        };
        let diag = ctx
            .diag(
                "HG7510",
                token.text_range(),
                format!(
                    "action name '{name}' is already used in chart {}",
                    scope.chart.name
                ),
            )
            .related(ctx.loc(range), format!("the {what}"));
        ctx.push(diag);
    }
}

/// `diag` with the fix that makes the chart an IEC chart: `profile iec;` after the chart's
/// `<`, or the value of an existing `profile` property replaced.
pub(crate) fn with_profile_fix(
    ctx: &Ctx<'_>,
    diag: crate::diag::Diag,
    chart: &ast::Chart,
) -> crate::diag::Diag {
    let existing = chart
        .props()
        .find(|p| {
            p.keyword()
                .is_some_and(|k| k.kind() == SyntaxKind::PROFILE_KW)
        })
        .and_then(|p| p.value())
        .and_then(|v| v.token());
    if let Some(value) = existing {
        return diag.fix(
            "Make the chart an IEC 61131-3 chart",
            ctx.loc(value.text_range()),
            "iec",
        );
    }
    let Some(open) = chart.body().and_then(|b| b.l_angle()) else {
        return diag;
    };
    diag.fix(
        "Make the chart an IEC 61131-3 chart",
        ctx.loc(TextRange::empty(open.text_range().end())),
        "\n  profile iec;",
    )
}

/// One sequencer: its element tree, names, topology, parts, operands and HG7311.
fn check_sequencer(
    ctx: &mut Ctx<'_>,
    scope: &mut Scope,
    chart_props: &props::ChartProps,
    sequencer: &ast::Sequencer,
) {
    let tree = model::Tree::build(sequencer);
    // C1: the rules of a sequencer name it; without a name only its operands are checked.
    let name = sequencer
        .name()
        .and_then(|n| n.token())
        .map(|t| t.text().to_owned());
    if let Some(name) = &name {
        names::check(ctx, &tree, name, scope.iec);
        topology::check(ctx, &tree, name, sequencer_header(sequencer), scope.iec);
        parts::check_sequencer(ctx, sequencer, name, scope.iec);
    }
    let chart_name = scope.chart.name.clone();
    let mut walker = exprs::Walker::new(ctx, scope);
    walker.sequencer_parts(sequencer);
    for element in model::nameless_elements(sequencer) {
        walker.element_body(&element);
    }
    let mut writes = Vec::with_capacity(tree.elems.len());
    let later = names::later_duplicates(&tree);
    for (elem, &later) in tree.elems.iter().zip(&later) {
        let reported = walker.ctx.out.diags.len();
        let node = elem.node.syntax();
        let mut step_writes = Vec::new();
        match &elem.node {
            ast::SeqElement::Step(step) => {
                parts::check_step(walker.ctx, step, elem.label(), chart_props, &chart_name);
                step_writes = walker.step(step, elem.label());
            }
            ast::SeqElement::Trans(_) | ast::SeqElement::Jump(_) | ast::SeqElement::Loop(_) => {
                if !chart_props.iec {
                    // HG7205 does not apply to IEC charts (docs/iec.md §2).
                    parts::check_conditions(walker.ctx, node, &elem.render(), elem.header);
                }
                walker.conditions(node);
            }
            ast::SeqElement::Parallel(_) | ast::SeqElement::Alt(_) => {}
        }
        if later {
            // C3: a later step or transition of a name (HG7103) is otherwise ignored; the
            // variables it names still count as used (HG1210).
            walker.ctx.out.diags.truncate(reported);
        }
        writes.push(step_writes);
    }
    if name.is_some() {
        term::check(ctx, &tree, &writes);
    }
}

/// The chart being checked.
pub(crate) struct ChartInfo {
    /// The chart's name as declared.
    pub name: String,
    /// `chart type`?
    pub is_type: bool,
    pub chart: ast::Chart,
}

impl ChartInfo {
    /// `chart C` for `{owner}` in messages (§1.4a).
    pub fn owner(&self) -> String {
        format!("chart {}", self.name)
    }
}

impl ChartInfo {
    /// Does the chart follow the IEC 61131-3 profile (`profile iec;`)?
    pub fn is_iec(&self) -> bool {
        self.chart.profile() == ast::Profile::Iec
    }
}

/// An `action` of the chart (`docs/iec.md` §6).
#[derive(Debug, Clone)]
pub(crate) struct ActionDecl {
    /// As declared.
    pub name: String,
    pub name_range: TextRange,
    /// A later action of a name an earlier action or a variable has (HG7510): ignored by
    /// references (C3).
    pub duplicate: bool,
}

/// The chart's variables and which of them are used (HG1210); its actions and step names
/// (IEC charts: qualifier operands naming actions, `Step.X`/`Step.T`).
pub(crate) struct Scope {
    pub chart: ChartInfo,
    pub vars: Vec<Var>,
    pub used: Vec<bool>,
    /// `profile iec;`.
    pub iec: bool,
    /// The chart's actions in text order (also in a PCS 7 chart, where each is HG7502, so
    /// that their uses do not cascade).
    pub actions: Vec<ActionDecl>,
    /// Which actions a qualifier names (HG7511).
    pub action_used: Vec<bool>,
    /// The names of every step of every sequencer, in text order.
    pub steps: Vec<String>,
}

impl Scope {
    pub(crate) fn new(chart: ChartInfo, vars: Vec<Var>) -> Scope {
        let used = vec![false; vars.len()];
        let iec = chart.is_iec();
        let mut actions: Vec<ActionDecl> = Vec::new();
        // Variable and action names so far (keys): one lookup per action.
        let mut taken: std::collections::HashSet<String> = vars
            .iter()
            .filter(|v| !v.duplicate)
            .map(|v| crate::index::key(&v.name))
            .collect();
        for action in chart.chart.actions() {
            let Some(token) = action.name().and_then(|n| n.token()) else {
                continue;
            };
            let name = token.text().to_owned();
            let duplicate = !taken.insert(crate::index::key(&name));
            actions.push(ActionDecl {
                name,
                name_range: token.text_range(),
                duplicate,
            });
        }
        let steps = chart
            .chart
            .sequencers()
            .flat_map(|s| {
                s.syntax()
                    .descendants()
                    .filter_map(ast::Step::cast)
                    .collect::<Vec<_>>()
            })
            .filter_map(|s| s.name().and_then(|n| n.token()))
            .map(|t| t.text().to_owned())
            .collect();
        let action_used = vec![false; actions.len()];
        Scope {
            chart,
            vars,
            used,
            iec,
            actions,
            action_used,
            steps,
        }
    }

    /// The action of that name (case-insensitive; later duplicates are ignored, C3).
    pub fn action(&self, name: &str) -> Option<usize> {
        self.actions
            .iter()
            .position(|a| !a.duplicate && a.name.eq_ignore_ascii_case(name))
    }

    /// Is there a step of that name in the chart?
    pub fn has_step(&self, name: &str) -> bool {
        self.steps.iter().any(|s| s.eq_ignore_ascii_case(name))
    }

    /// The variable of that name (case-insensitive; duplicates bind to the first, C3).
    pub fn var(&self, name: &str) -> Option<usize> {
        self.vars
            .iter()
            .position(|v| !v.duplicate && v.name.eq_ignore_ascii_case(name))
    }
}

// ------------------------------------------------------------------------------ syntax helpers

/// The first significant token of a node (its keyword, for most chart constructs).
pub(crate) fn first_token(node: &SyntaxNode) -> Option<SyntaxToken> {
    node.descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .find(|t| !t.kind().is_trivia())
}

/// The range of a node without a trailing `;` (a statement, item or property, §2.3).
pub(crate) fn without_semi(node: &SyntaxNode) -> TextRange {
    let tokens: Vec<SyntaxToken> = node
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .collect();
    let end_index = match tokens.last() {
        Some(t) if t.kind() == SyntaxKind::SEMI => tokens.len() - 1,
        _ => tokens.len(),
    };
    match (
        tokens.first(),
        end_index.checked_sub(1).and_then(|i| tokens.get(i)),
    ) {
        (Some(first), Some(last)) => {
            TextRange::new(first.text_range().start(), last.text_range().end())
        }
        _ => node.text_range(),
    }
}

/// From the node's keyword through its own name (§2.3 "element header", "sequencer header");
/// just the keyword when there is no name.
pub(crate) fn header_range(node: &SyntaxNode) -> TextRange {
    let start = first_token(node).map_or(node.text_range().start(), |t| t.text_range().start());
    let end = node
        .children()
        .find(|n| n.kind() == SyntaxKind::NAME)
        .map(|n| n.text_range().end())
        .or_else(|| first_token(node).map(|t| t.text_range().end()))
        .unwrap_or(start);
    TextRange::new(start, end.max(start))
}

/// The sequencer header: from `sequencer` through its name.
pub(crate) fn sequencer_header(sequencer: &ast::Sequencer) -> TextRange {
    header_range(sequencer.syntax())
}

/// The source text of a node with white space (and comments) collapsed to single spaces.
pub(crate) fn collapsed(node: &SyntaxNode) -> String {
    let mut out = String::new();
    let mut space = false;
    for token in node
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
    {
        if token.kind().is_trivia() {
            space = true;
            continue;
        }
        if space && !out.is_empty() {
            out.push(' ');
        }
        space = false;
        out.push_str(token.text());
    }
    out
}

/// The body children of a node's `BODY` child.
pub(crate) fn body_children(node: &SyntaxNode) -> impl Iterator<Item = SyntaxNode> + use<> {
    node.children()
        .find(|n| n.kind() == SyntaxKind::BODY)
        .into_iter()
        .flat_map(|b| b.children())
}
