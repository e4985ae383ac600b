//! STL in graphs: operand resolution (§2.4, via [`crate::resolve`]) and the rules about
//! instruction bodies, statements, operands, calls and time values.
//!
//! | module        | codes |
//! |---------------|-------|
//! | this file     | HG4001, HG4002 (labels), HG4005, HG4006 (brackets), HG1210 (unused) |
//! | `statement`   | HG4003, HG4004, HG4007, HG4008, HG4201–HG4207, HG4402 |
//! | `access`      | HG1209, HG1214, HG4401, HG4403 |
//! | `call`        | HG4301–HG4308 |
//! | `time`        | HG3004, HG3006, HG3008 (shared with charts) |
//! | `transitions` | transition labels with implicit priorities (§2.3, §2.6) |
//! | `resolve`     | HG1104, HG1207, HG1208, HG3005, HG4009–HG4012, HG4101–HG4103 |

use higraph_syntax::{SyntaxKind, TextRange, ast, ast::AstNode};

use super::Ctx;
use crate::resolve::{self, GraphScope, Role, Usage};

mod access;
mod call;
mod statement;
pub(crate) mod time;
mod transitions;

use statement::{Analyzed, Place};

pub(crate) use access::Access;

/// The access kind (Appendix E) of the operand of `op` (a SIMATIC operation name) whose type
/// is `ty`. CALL actuals are not covered: their access depends on the callee's interface.
pub(crate) fn operand_access(op: &str, ty: Option<crate::lang::Type>) -> Access {
    statement::OperandRule::of(op).access(ty)
}

/// What the STL rules found in one member, or a chunk of members, of a graph ([`crate::db::chunk_stl`]).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MemberStl {
    /// Places relative to the member, except where the graph's scope put them (see
    /// [`crate::diag::Loc::in_member`]).
    pub diags: Vec<crate::diag::Diag>,
    /// Per declared variable of the graph (in declaration order): used here?
    pub used_vars: Vec<bool>,
    /// The predefined variables some operand here resolves to, sorted.
    pub used_predefined: Vec<&'static str>,
    /// The global symbols used here (for HG6004).
    pub used_symbols: std::collections::BTreeSet<String>,
}

impl MemberStl {
    /// Adds the findings of a member that stands at `offset` from the start of this one's
    /// range (a chunk or the item).
    pub(crate) fn merge(&mut self, other: &MemberStl, offset: higraph_syntax::TextSize) {
        self.diags
            .extend(other.diags.iter().map(|d| d.shift_member(offset)));
        if self.used_vars.len() < other.used_vars.len() {
            self.used_vars.resize(other.used_vars.len(), false);
        }
        for (used, here) in self.used_vars.iter_mut().zip(&other.used_vars) {
            *used |= *here;
        }
        for name in &other.used_predefined {
            if let Err(at) = self.used_predefined.binary_search(name) {
                self.used_predefined.insert(at, name);
            }
        }
        self.used_symbols.extend(other.used_symbols.iter().cloned());
    }
}

/// Checks the STL of one member of a graph, rooted at the member (`ctx.in_member`).
/// `label_prio` is the transition's priority when its label needs one (§2.3, from the graph
/// model: `TransEntry::label_priority`).
pub(crate) fn check_member(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    member: &higraph_syntax::SyntaxNode,
    label_prio: Option<u64>,
) -> MemberStl {
    let mut scope = scope.clone();
    if let Some(state) = ast::State::cast(member.clone()) {
        let number = state
            .number()
            .map(|t| t.text().to_owned())
            .unwrap_or_default();
        if let Some(body) = state.body() {
            check_body(ctx, &mut scope, &body, &BodyKind::State { number });
        }
    } else if let Some(trans) = ast::Trans::cast(member.clone()) {
        let label = transitions::label(&trans, label_prio);
        if let Some(body) = trans.body() {
            check_body(ctx, &mut scope, &body, &BodyKind::Transition { label });
        }
    } else if let Some(body) = ast::Permanent::cast(member.clone()).and_then(|p| p.body()) {
        check_body(ctx, &mut scope, &body, &BodyKind::Permanent);
    }
    let mut used_predefined: Vec<&'static str> = scope.used_predefined.into_iter().collect();
    used_predefined.sort_unstable();
    MemberStl {
        diags: std::mem::take(&mut ctx.out.diags),
        used_vars: scope.used_vars,
        used_predefined,
        used_symbols: std::mem::take(&mut ctx.out.used_symbols),
    }
}

/// Which kind of instruction body is being checked.
enum BodyKind {
    State { number: String },
    Transition { label: String },
    Permanent,
}

impl BodyKind {
    /// The labels allowed in this body (HG4002), as written in messages.
    fn allowed_labels(&self) -> &'static [&'static str] {
        match self {
            BodyKind::State { .. } => &["E", "C-", "C", "X"],
            BodyKind::Transition { .. } => &["?", "!"],
            BodyKind::Permanent => &["C-", "C"],
        }
    }

    fn description(&self) -> &'static str {
        match self {
            BodyKind::State { .. } => "a state",
            BodyKind::Transition { .. } => "a transition",
            BodyKind::Permanent => "permanent instructions",
        }
    }
}

fn check_body(ctx: &mut Ctx<'_>, scope: &mut GraphScope, body: &ast::Body, kind: &BodyKind) {
    let mut unlabelled = UnlabelledRun::default();
    for item in body.body_items() {
        match item {
            ast::BodyItem::Block(block) => {
                match block.label() {
                    None => unlabelled.add(&block),
                    Some(_) => unlabelled.report(ctx, kind),
                }
                check_block(ctx, scope, &block, kind);
            }
            ast::BodyItem::Wait(wait) => {
                let range = wait.syntax().text_range();
                if let Some(value) = wait.value() {
                    check_time_item(ctx, scope, &value, time::TimeKind::Wait, range);
                }
            }
            ast::BodyItem::Supervise(supervise) => {
                let range = supervise.syntax().text_range();
                if let Some(value) = supervise.value() {
                    check_time_item(ctx, scope, &value, time::TimeKind::Supervision, range);
                }
            }
        }
    }
    unlabelled.report(ctx, kind);
}

/// One block: its label (HG4001, HG4002), its statements and its brackets (HG4005, HG4006).
fn check_block(ctx: &mut Ctx<'_>, scope: &mut GraphScope, block: &ast::Block, kind: &BodyKind) {
    let label = block.label();
    let label_name = label.as_ref().map(|l| l.name());
    if let Some(label) = &label {
        check_label(ctx, label, kind);
    }
    let condition_of = match kind {
        BodyKind::Transition { label } if matches!(label_name.as_deref(), None | Some("?")) => {
            Some(label.as_str())
        }
        _ => None,
    };
    let place = Place { condition_of };
    let mut brackets = Brackets::default();
    for stmt in block.statements() {
        if let Some(analyzed) = statement::check(ctx, scope, &stmt, &place) {
            brackets.step(ctx, &analyzed);
        }
    }
    let end = block
        .statements()
        .last()
        .map_or(block.syntax().text_range().end(), |s| {
            s.syntax().text_range().end()
        });
    brackets.finish(ctx, end);
}

/// HG4001: the unlabelled statements of a state or of `permanent` up to the next label (or the
/// end of the body). A `wait` or `supervise` item ends a block, so one run may be several
/// unlabelled blocks (`U Ein; supervise T#5S; = b;`): it gets one diagnostic, from its first
/// statement through its last, and its fix labels each of those blocks, so that no statement
/// is left outside a block.
#[derive(Default)]
struct UnlabelledRun {
    /// The range of each unlabelled block's statements, in text order.
    blocks: Vec<TextRange>,
}

impl UnlabelledRun {
    fn add(&mut self, block: &ast::Block) {
        let mut ranges = block.statements().filter_map(|s| statement_range(&s));
        if let Some(first) = ranges.next() {
            let last = ranges.last().unwrap_or(first);
            self.blocks.push(first.cover(last));
        }
    }

    fn report(&mut self, ctx: &mut Ctx<'_>, kind: &BodyKind) {
        let blocks = std::mem::take(&mut self.blocks);
        let (Some(first), Some(last)) = (blocks.first(), blocks.last()) else {
            return;
        };
        let message = match kind {
            BodyKind::State { number } => format!(
                "statement outside an instruction block: state {number} needs a label such as 'C:' before it"
            ),
            BodyKind::Permanent => "statement outside an instruction block: permanent instructions need 'C-:' or 'C:' before it".to_owned(),
            BodyKind::Transition { .. } => return,
        };
        let edits = blocks
            .iter()
            .map(|block| (ctx.loc(TextRange::empty(block.start())), "C: ".to_owned()))
            .collect();
        let diag = ctx
            .diag("HG4001", first.cover(*last), message)
            .fix_edits("Insert 'C:'", edits);
        ctx.push(diag);
    }
}

/// HG4002: a label that is not allowed in this kind of body.
fn check_label(ctx: &mut Ctx<'_>, label: &ast::Label, kind: &BodyKind) {
    let allowed = kind.allowed_labels();
    let name = label.name();
    if allowed.contains(&name.as_str()) {
        return;
    }
    let list = allowed
        .iter()
        .map(|l| format!("'{l}:'"))
        .collect::<Vec<_>>()
        .join(", ");
    let written = label.syntax().text().to_string();
    let message = format!(
        "label '{written}' is not allowed in {}; allowed: {list}",
        kind.description()
    );
    let diag = ctx.diag("HG4002", label.syntax().text_range(), message);
    ctx.push(diag);
}

/// The nesting stack of one block (HG4005, HG4006).
#[derive(Default)]
struct Brackets {
    open: Vec<(String, TextRange)>,
}

/// The nesting stack holds at most this many entries (HG4005).
const NESTING_LIMIT: usize = 7;

impl Brackets {
    fn step(&mut self, ctx: &mut Ctx<'_>, analyzed: &Analyzed) {
        match analyzed.op.as_str() {
            "U(" | "UN(" | "O(" | "ON(" | "X(" | "XN(" => {
                self.open
                    .push((analyzed.display.clone(), analyzed.opcode_range));
                let depth = self.open.len();
                if depth > NESTING_LIMIT {
                    let message = format!(
                        "bracket nesting depth {depth} exceeds the 7-entry nesting stack; the original compiler does not check this"
                    );
                    let diag = ctx.diag("HG4005", analyzed.opcode_range, message);
                    ctx.push(diag);
                }
            }
            // The guard pops the matching bracket; only an unmatched `)` reaches the body.
            ")" if self.open.pop().is_none() => {
                let diag = ctx.diag(
                    "HG4006",
                    analyzed.opcode_range,
                    "')' has no matching opening bracket",
                );
                ctx.push(diag);
            }
            _ => {}
        }
    }

    /// HG4006 (b): brackets still open at the end of the block (`end`).
    fn finish(self, ctx: &mut Ctx<'_>, end: higraph_syntax::TextSize) {
        for (op, range) in self.open {
            let message = format!("'{op}' is not closed before the end of the block");
            let diag = ctx.diag("HG4006", range, message).fix(
                "Insert ');' at the end of the block",
                ctx.loc(TextRange::empty(end)),
                " );",
            );
            ctx.push(diag);
        }
    }
}

/// A `wait` or `supervise` item: resolution, then the time rules.
fn check_time_item(
    ctx: &mut Ctx<'_>,
    scope: &mut GraphScope,
    value: &ast::Operand,
    kind: time::TimeKind,
    item: TextRange,
) {
    if statement::forbidden_operand(ctx, scope, value) {
        return;
    }
    let usage = Usage {
        role: Role::TimeValue,
        implied: None,
    };
    let resolved = resolve::resolve_operand(ctx, scope, value, usage);
    if let Some((range, area)) = &resolved.other_set {
        statement::other_set_diag(ctx, *range, area, None);
    }
    access::check(ctx, scope, &resolved, access::Access::Read, None);
    if resolved.target.is_some() || matches!(value, ast::Operand::Literal(_)) {
        time::check_time_value(ctx, value, resolved.ty, kind, Some(item));
    }
}

/// HG1210: declared variables and activated predefined variables that no operand uses (`scope`
/// holds the uses of every member of the graph, merged).
pub(crate) fn report_unused(ctx: &mut Ctx<'_>, scope: &GraphScope) {
    let owner = scope.owner();
    for (var, used) in scope.vars.iter().zip(&scope.used_vars) {
        if !*used {
            super::decls::report_unused(ctx, &owner, var);
        }
    }
    let mut seen = std::collections::HashSet::new();
    for name in scope.activated.iter() {
        let Some(predefined) = crate::lang::predefined(&name.text) else {
            continue;
        };
        if !seen.insert(predefined.name) || scope.used_predefined.contains(predefined.name) {
            continue;
        }
        let message = format!("'{}' is activated but never used", name.text);
        let removal = name.sole_in.unwrap_or(name.removal);
        let diag = ctx.diag("HG1210", name.range, message).fix(
            format!("Remove '{}' from 'activate'", name.text),
            ctx.loc(removal),
            "",
        );
        ctx.push(diag);
    }
}

/// The statement range of §2.3: its first token through the last token before its `;`.
pub(crate) fn statement_range(stmt: &ast::StlStmt) -> Option<TextRange> {
    let mut tokens = stmt
        .syntax()
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia() && t.kind() != SyntaxKind::SEMI);
    let first = tokens.next()?;
    let last = tokens.last().unwrap_or_else(|| first.clone());
    Some(first.text_range().cover(last.text_range()))
}
