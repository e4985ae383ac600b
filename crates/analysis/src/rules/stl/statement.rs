//! One STL statement: the operation (HG4003, HG4007, HG4008), the operand's form (HG4003,
//! HG4004), its presence (HG4206), its type (HG4201–HG4205, HG4207), access rules (via
//! `access`) and actions in transition conditions (HG4402). CALL and CC go to `call`.
//!
//! C4: a statement that gets HG4003, HG4004 or HG4008 is not analysed further; one that gets
//! HG4007 is analysed in its translated form.

use higraph_syntax::{
    SyntaxKind, TextRange, ast,
    ast::AstNode,
    literal::{self, LiteralClass, LiteralValue},
};

use super::{
    Ctx,
    access::{self, Access},
    call, statement_range,
};
use crate::{
    address::Area,
    lang::{self, Mnemonic, OpClass, OutsideKind, Type},
    resolve::{self, GraphScope, Resolved, Role, Target, Usage},
    rules::has_error,
};

/// Where a statement stands.
pub(super) struct Place<'a> {
    /// The transition's label when the statement is in its condition part (HG4402).
    pub condition_of: Option<&'a str>,
}

/// A statement that was analysed: what the bracket rules need.
pub(super) struct Analyzed {
    /// The operation's SIMATIC name (`U(`, `)`, ...).
    pub op: String,
    /// The operation as the file's set spells it, for messages.
    pub display: String,
    pub opcode_range: TextRange,
}

/// Checks one statement. Returns `None` when it has no operation or is not analysed further.
pub(super) fn check(
    ctx: &mut Ctx<'_>,
    scope: &mut GraphScope,
    stmt: &ast::StlStmt,
    place: &Place<'_>,
) -> Option<Analyzed> {
    if let Some(label) = stmt.jump_label() {
        let diag = ctx.diag("HG4003", label.syntax().text_range(), JUMP_MESSAGE);
        ctx.push(diag);
        // Not analysed further (C4), but its brackets still count for HG4006: the label
        // does not take the statement out of its block.
        let opcode = stmt.opcode()?;
        let written = written_opcode(&opcode);
        let op = match lang::classify_op(&written, ctx.mnemonic) {
            OpClass::Subset(op) | OpClass::OtherSet { simatic: op, .. } => op,
            OpClass::Outside(_) | OpClass::Unknown => return None,
        };
        return Some(Analyzed {
            op,
            display: written,
            opcode_range: opcode.syntax().text_range(),
        });
    }
    let opcode = stmt.opcode()?;
    let opcode_range = opcode.syntax().text_range();
    let written = written_opcode(&opcode);
    let (op, other_set_op) = match lang::classify_op(&written, ctx.mnemonic) {
        OpClass::Subset(op) => (op, None),
        OpClass::OtherSet {
            simatic,
            translated,
        } => (simatic, Some(translated)),
        OpClass::Outside(kind) => {
            outside_subset(ctx, opcode_range, &written, kind);
            return None;
        }
        OpClass::Unknown => {
            unknown_operation(ctx, opcode_range, &written);
            return None;
        }
    };
    let display = other_set_op.clone().unwrap_or_else(|| written.clone());
    let analyzed = Analyzed {
        op: op.clone(),
        display: display.clone(),
        opcode_range,
    };
    let mark = ctx.out.diags.len();
    let further = analyse(
        ctx,
        scope,
        stmt,
        &op,
        &display,
        &written,
        other_set_op.as_deref(),
        place,
    );
    if has_error(stmt.syntax()) {
        // C1: nothing is reported for a broken statement, but its names still count as uses.
        ctx.out.diags.truncate(mark);
        return Some(analyzed);
    }
    further.then_some(analyzed)
}

/// The statement after its operation is known. Returns `false` if it is not analysed further
/// (HG4003, HG4004).
#[allow(clippy::too_many_arguments)]
fn analyse(
    ctx: &mut Ctx<'_>,
    scope: &mut GraphScope,
    stmt: &ast::StlStmt,
    op: &str,
    display: &str,
    written: &str,
    other_set_op: Option<&str>,
    place: &Place<'_>,
) -> bool {
    let Some(opcode) = stmt.opcode() else {
        return false;
    };
    let opcode_range = opcode.syntax().text_range();
    let stmt_range = statement_range(stmt).unwrap_or(opcode_range);
    if op == "CALL" || op == "CC" {
        let call = call::Call {
            stmt,
            op,
            display,
            opcode_range,
            stmt_range,
            condition_of: place.condition_of,
        };
        return call::check(ctx, scope, &call);
    }
    let operand = stmt.operand();
    let rule = OperandRule::of(op);
    if let Some(operand) = &operand {
        if rule == OperandRule::RegisterTransfer {
            // TAR1/TAR2 with an operand: outside the subset (HG4003).
            let message = format!("'{written}' is not part of the HiGraph STL subset");
            let diag = ctx.diag("HG4003", opcode_range, message);
            ctx.push(diag);
            return false;
        }
        if forbidden_operand(ctx, scope, operand) {
            return false;
        }
    }
    let resolved = operand.as_ref().map(|operand| {
        let usage = Usage {
            role: Role::Operand,
            implied: rule.implied_type(),
        };
        resolve::resolve_operand(ctx, scope, operand, usage)
    });
    report_other_set(
        ctx,
        stmt_range,
        opcode_range,
        written,
        other_set_op,
        resolved.as_ref(),
    );
    match &resolved {
        None => {
            if rule.requires_operand() {
                let diag = ctx.diag(
                    "HG4206",
                    opcode_range,
                    format!("'{display}' needs an operand"),
                );
                ctx.push(diag);
            }
        }
        Some(resolved) => {
            if rule.takes_no_operand() {
                let diag = ctx
                    .diag(
                        "HG4206",
                        resolved.range,
                        format!("'{display}' takes no operand"),
                    )
                    .fix(
                        "Remove the operand",
                        ctx.loc(TextRange::new(opcode_range.end(), resolved.range.end())),
                        "",
                    );
                ctx.push(diag);
            } else {
                check_operand_type(ctx, rule, display, resolved);
            }
            let access = rule.access(resolved.ty);
            access::check(ctx, scope, resolved, access, Some(display));
        }
    }
    if let Some(transition) = place.condition_of
        && changes_operands(op)
    {
        let operand_text = resolved.as_ref().map_or("", |r| r.text.as_str());
        action_in_condition(ctx, stmt, stmt_range, display, operand_text, transition);
    }
    true
}

// ------------------------------------------------------------------------------ operations

const JUMP_MESSAGE: &str =
    "jumps and jump labels are not available in HiGraph; use states and transitions";

/// HG4003 for an operation of Appendix A.3.
fn outside_subset(ctx: &mut Ctx<'_>, range: TextRange, written: &str, kind: OutsideKind) {
    let message = match kind {
        OutsideKind::Jump => JUMP_MESSAGE.to_owned(),
        OutsideKind::BlockEnd => format!("'{written}' (block end) is not available in HiGraph"),
        OutsideKind::Other => format!("'{written}' is not part of the HiGraph STL subset"),
    };
    let diag = ctx.diag("HG4003", range, message);
    ctx.push(diag);
}

/// HG4008: an opcode that is no operation at all.
fn unknown_operation(ctx: &mut Ctx<'_>, range: TextRange, written: &str) {
    let mut diag = ctx.diag("HG4008", range, format!("unknown operation '{written}'"));
    let ops = lang::subset_ops(ctx.mnemonic);
    diag = ctx.with_closest_fix(diag, range, written, ops.iter().map(String::as_str));
    ctx.push(diag);
}

/// The opcode as written, without white space (`U(` for `U (`), case kept.
fn written_opcode(opcode: &ast::Opcode) -> String {
    opcode
        .syntax()
        .children_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .map(|t| t.text().to_owned())
        .collect()
}

/// HG4003 / HG4004 for operands that are not analysed: `[...]`, status bits (`==0`) and
/// register names (`STW`, `AR1`, ...) with no variable or symbol of that name. Returns `true`
/// if the operand was rejected.
pub(super) fn forbidden_operand(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    operand: &ast::Operand,
) -> bool {
    let range = operand.syntax().text_range();
    let text = operand.syntax().text().to_string();
    let diag = match operand {
        ast::Operand::Indirect(_) => ctx.diag(
            "HG4004",
            range,
            "indirect addressing is not allowed in HiGraph",
        ),
        ast::Operand::Status(_) => ctx.diag(
            "HG4003",
            range,
            format!("'{text}' is not part of the HiGraph STL subset"),
        ),
        ast::Operand::NameRef(name)
            if lang::is_register_name(&name.text(), ctx.mnemonic)
                && scope.var(&name.text()).is_none()
                && ctx.index.symbol(&name.text()).is_none() =>
        {
            ctx.diag(
                "HG4003",
                range,
                format!("'{text}' is not part of the HiGraph STL subset"),
            )
        }
        _ => return false,
    };
    ctx.push(diag);
    true
}

// ------------------------------------------------------------------------------ HG4007

/// HG4007 once per statement: the offending opcode and/or address area, rewritten.
fn report_other_set(
    ctx: &mut Ctx<'_>,
    stmt_range: TextRange,
    opcode_range: TextRange,
    written: &str,
    other_set_op: Option<&str>,
    operand: Option<&Resolved<'_>>,
) {
    let mut offending: Vec<(TextRange, String)> = Vec::new();
    if other_set_op.is_some() {
        offending.push((opcode_range, written.to_owned()));
    }
    if let Some(area) = operand.and_then(|o| o.other_set.clone()) {
        offending.push(area);
    }
    let Some((first_range, first_token)) = offending.first().cloned() else {
        return;
    };
    let range = offending
        .iter()
        .fold(first_range, |range, (r, _)| range.cover(*r));
    let op = other_set_op.unwrap_or(written);
    let rewritten = match operand {
        Some(o) => format!("{op} {}", o.translated.as_deref().unwrap_or(&o.text)),
        None => op.to_owned(),
    };
    other_set_diag(ctx, range, &first_token, Some((stmt_range, rewritten)));
}

/// Pushes HG4007 for `token` at `range`, with an optional rewrite of `(range, text)`.
pub(super) fn other_set_diag(
    ctx: &mut Ctx<'_>,
    range: TextRange,
    token: &str,
    rewrite: Option<(TextRange, String)>,
) {
    let (token_set, file_set) = match ctx.mnemonic {
        Mnemonic::Simatic => ("an international", "SIMATIC"),
        Mnemonic::International => ("a SIMATIC", "international"),
    };
    let message = format!("'{token}' is {token_set} mnemonic; this file uses {file_set} mnemonics");
    let mut diag = ctx.diag("HG4007", range, message);
    if let Some((at, text)) = rewrite {
        diag = diag.fix(format!("Rewrite as '{text}'"), ctx.loc(at), text);
    }
    ctx.push(diag);
}

// ------------------------------------------------------------------------------ operands

/// The operand requirements of an operation (Appendix B), by SIMATIC name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum OperandRule {
    /// `U UN X XN ON`: a BOOL, TIMER or COUNTER operand, required.
    BitLogic,
    /// `O`: as bit logic, optional.
    Or,
    /// `=`: BOOL.
    Assign,
    /// `FP FN`: BOOL, read and rewritten.
    Edge,
    /// `S`: BOOL or COUNTER.
    Set,
    /// `R`: BOOL, TIMER or COUNTER.
    Reset,
    /// No operand.
    NoOperand,
    /// `TAR1 TAR2`: no operand; one is HG4003.
    RegisterTransfer,
    Load,
    LoadCoded,
    Transfer,
    /// `SI SV SE SS SA`.
    TimerStart,
    /// `FR`: TIMER or COUNTER.
    Enable,
    /// `ZV ZR`.
    Count,
    /// `UW OW XOW` / `UD OD XOD`: an optional constant of that type.
    WordLogic(Type),
    /// `+`: an integer constant.
    AddConstant,
    /// `INC DEC`: 0..255.
    IncDec,
    /// Shift and rotate counts: an optional integer 0..max.
    Shift(i64),
    Call,
}

impl OperandRule {
    pub(super) fn of(op: &str) -> OperandRule {
        use OperandRule::*;
        match op {
            "U" | "UN" | "X" | "XN" | "ON" => BitLogic,
            "O" => Or,
            "=" => Assign,
            "FP" | "FN" => Edge,
            "S" => Set,
            "R" => Reset,
            "L" => Load,
            "LC" => LoadCoded,
            "T" => Transfer,
            "SI" | "SV" | "SE" | "SS" | "SA" => TimerStart,
            "FR" => Enable,
            "ZV" | "ZR" => Count,
            "UW" | "OW" | "XOW" => WordLogic(Type::Word),
            "UD" | "OD" | "XOD" => WordLogic(Type::Dword),
            "+" => AddConstant,
            "INC" | "DEC" => IncDec,
            "SLW" | "SRW" | "SSI" => Shift(15),
            "SLD" | "SRD" | "SSD" | "RLD" | "RRD" => Shift(32),
            "TAR1" | "TAR2" => RegisterTransfer,
            "CALL" | "CC" => Call,
            _ => NoOperand,
        }
    }

    fn requires_operand(self) -> bool {
        use OperandRule::*;
        matches!(
            self,
            BitLogic
                | Assign
                | Edge
                | Set
                | Reset
                | Load
                | LoadCoded
                | Transfer
                | TimerStart
                | Enable
                | Count
                | AddConstant
                | IncDec
                | Call
        )
    }

    fn takes_no_operand(self) -> bool {
        matches!(self, OperandRule::NoOperand | OperandRule::RegisterTransfer)
    }

    /// The type the operation implies for an undeclared operand (HG4101's fix).
    fn implied_type(self) -> Option<Type> {
        use OperandRule::*;
        match self {
            BitLogic | Or | Assign | Edge | Set | Reset => Some(Type::Bool),
            TimerStart => Some(Type::Timer),
            Count => Some(Type::Counter),
            _ => None,
        }
    }

    /// The access kind of the operand (Appendix E).
    pub(super) fn access(self, ty: Option<Type>) -> Access {
        use OperandRule::*;
        let timer_or_counter = matches!(ty, Some(Type::Timer | Type::Counter));
        match self {
            Assign | Transfer => Access::Write,
            Edge | TimerStart | Enable | Count => Access::ReadWrite,
            Set if ty == Some(Type::Counter) => Access::ReadWrite,
            Reset if timer_or_counter => Access::ReadWrite,
            // Appendix E: `S`/`R` write a BOOL operand. On any other type they are a type
            // error (HG4201), not a write: a use, as for an unknown callee.
            Set | Reset if matches!(ty, Some(Type::Bool) | None) => Access::Write,
            Set | Reset => Access::Unknown,
            _ => Access::Read,
        }
    }
}

/// The type rules HG4201–HG4205 and HG4207 for one operand.
fn check_operand_type(ctx: &mut Ctx<'_>, rule: OperandRule, op: &str, operand: &Resolved<'_>) {
    use OperandRule::*;
    match rule {
        BitLogic | Or | Reset => bit_operand(
            ctx,
            op,
            operand,
            "a BOOL, TIMER or COUNTER operand",
            &[Type::Bool, Type::Timer, Type::Counter],
        ),
        Assign | Edge => bit_operand(ctx, op, operand, "a BOOL operand", &[Type::Bool]),
        Set => bit_operand(
            ctx,
            op,
            operand,
            "a BOOL or COUNTER operand",
            &[Type::Bool, Type::Counter],
        ),
        Load => load_operand(ctx, operand),
        LoadCoded => {
            let accepted = [Type::Timer, Type::Counter];
            if let Some(found) = type_violation(operand, &accepted) {
                let message = format!(
                    "'{op}' needs a timer or counter; {} is {found}",
                    operand.text
                );
                push(ctx, "HG4202", operand.range, message);
            }
        }
        Transfer => transfer_operand(ctx, operand),
        TimerStart => {
            if let Some(found) = type_violation(operand, &[Type::Timer]) {
                let message = format!("'{op}' needs a timer; {} is {found}", operand.text);
                push(ctx, "HG4204", operand.range, message);
            }
        }
        Enable => {
            if let Some(found) = type_violation(operand, &[Type::Timer, Type::Counter]) {
                let message = format!("'{op}' needs a timer; {} is {found}", operand.text);
                push(ctx, "HG4204", operand.range, message);
            }
        }
        Count => {
            if let Some(found) = type_violation(operand, &[Type::Counter]) {
                let message = format!("'{op}' needs a counter; {} is {found}", operand.text);
                push(ctx, "HG4205", operand.range, message);
            }
        }
        WordLogic(ty) => {
            let requirement = format!("a {ty} constant");
            constant_requirement(ctx, op, operand, &requirement, |lit| {
                literal::accepts(&ty.to_string(), lit) == literal::Acceptance::Accepted
            });
        }
        AddConstant => constant_requirement(
            ctx,
            op,
            operand,
            "an integer from -32768 to 32767 or an L# constant",
            |lit| match (lit.class, &lit.value) {
                (LiteralClass::Integer, LiteralValue::Int(v)) => (-32768..=32767).contains(v),
                (LiteralClass::LongInteger, _) => true,
                _ => false,
            },
        ),
        IncDec => constant_requirement(ctx, op, operand, "an integer from 0 to 255", |lit| {
            integer_in(lit, 0, 255)
        }),
        Shift(max) => {
            let requirement = format!("an integer from 0 to {max}");
            constant_requirement(ctx, op, operand, &requirement, |lit| {
                integer_in(lit, 0, max)
            });
        }
        NoOperand | RegisterTransfer | Call => {}
    }
}

fn push(ctx: &mut Ctx<'_>, code: &'static str, range: TextRange, message: String) {
    let diag = ctx.diag(code, range, message);
    ctx.push(diag);
}

/// HG4201: the operand of a bit operation.
fn bit_operand(
    ctx: &mut Ctx<'_>,
    op: &str,
    operand: &Resolved<'_>,
    accepted_text: &str,
    accepted: &[Type],
) {
    if let Some(found) = type_violation(operand, accepted) {
        let message = format!("'{op}' needs {accepted_text}; {} is {found}", operand.text);
        push(ctx, "HG4201", operand.range, message);
    }
}

/// `Some(what it is)` when the operand is a constant or has a type outside `accepted`;
/// `None` when it fits or its type is unknown (C2).
fn type_violation(operand: &Resolved<'_>, accepted: &[Type]) -> Option<String> {
    if operand.is_constant() {
        return Some("a constant".to_owned());
    }
    let ty = operand.ty?;
    (!accepted.contains(&ty)).then(|| ty.to_string())
}

/// HG4202 for `L`.
fn load_operand(ctx: &mut Ctx<'_>, operand: &Resolved<'_>) {
    let rejected = match &operand.target {
        Some(Target::Constant(lit)) => {
            let too_long = matches!(&lit.value, LiteralValue::Str(s) if s.chars().count() > 4);
            matches!(lit.class, LiteralClass::Boolean | LiteralClass::DateAndTime) || too_long
        }
        Some(_) => {
            let peripheral_output = operand
                .address()
                .is_some_and(|a| a.area == Area::PeripheralOutput);
            let loadable = operand
                .ty
                .is_none_or(|ty| transferable(ty) || matches!(ty, Type::Timer | Type::Counter));
            peripheral_output || !loadable
        }
        None => false,
    };
    if rejected {
        let ty = type_name(operand);
        let message = format!("'L' cannot load {} ({ty})", operand.text);
        push(ctx, "HG4202", operand.range, message);
    }
}

/// HG4203 for `T` (a read-only predefined variable is HG1209 instead).
fn transfer_operand(ctx: &mut Ctx<'_>, operand: &Resolved<'_>) {
    if let Some(Target::Predefined(p)) = &operand.target
        && !p.writable
    {
        return;
    }
    let found = if operand.is_constant() {
        Some("a constant".to_owned())
    } else if operand
        .address()
        .is_some_and(|a| a.area == Area::PeripheralInput)
    {
        operand.ty.map(|t| t.to_string())
    } else {
        operand
            .ty
            .filter(|ty| !transferable(*ty))
            .map(|t| t.to_string())
    };
    if let Some(found) = found {
        let message = format!(
            "'T' needs a writable BYTE, WORD, DWORD, INT, DINT, REAL, S5TIME, TIME, DATE, TOD or CHAR operand; {} is {found}",
            operand.text
        );
        push(ctx, "HG4203", operand.range, message);
    }
}

/// The types `T` can write (and `L` can load, with TIMER and COUNTER).
fn transferable(ty: Type) -> bool {
    matches!(
        ty,
        Type::Byte
            | Type::Word
            | Type::Dword
            | Type::Int
            | Type::Dint
            | Type::Real
            | Type::S5Time
            | Type::Time
            | Type::Date
            | Type::TimeOfDay
            | Type::Char
    )
}

/// HG4207: the operand must be a constant that `ok` accepts. Unresolved operands and invalid
/// constants are skipped (their type is unknown).
fn constant_requirement(
    ctx: &mut Ctx<'_>,
    op: &str,
    operand: &Resolved<'_>,
    requirement: &str,
    ok: impl Fn(&literal::Literal) -> bool,
) {
    let fits = match &operand.target {
        Some(Target::Constant(lit)) => ok(lit),
        Some(_) => false,
        None => true,
    };
    if !fits {
        let message = format!("'{op}' needs {requirement}; found {}", operand.text);
        push(ctx, "HG4207", operand.range, message);
    }
}

fn integer_in(lit: &literal::Literal, min: i64, max: i64) -> bool {
    matches!((lit.class, &lit.value), (LiteralClass::Integer, LiteralValue::Int(v)) if (min..=max).contains(v))
}

/// The type of an operand for messages: a constant's literal type, else the operand's type.
pub(super) fn type_name(operand: &Resolved<'_>) -> String {
    match &operand.target {
        Some(Target::Constant(lit)) => literal::literal_type(lit).to_owned(),
        _ => operand
            .ty
            .map_or_else(|| "unknown".to_owned(), |t| t.to_string()),
    }
}

// ------------------------------------------------------------------------------ HG4402

/// Operations that change their operand (HG4402; `FP`/`FN` are exempt).
fn changes_operands(op: &str) -> bool {
    matches!(
        op,
        "=" | "S"
            | "R"
            | "T"
            | "CALL"
            | "CC"
            | "SI"
            | "SV"
            | "SE"
            | "SS"
            | "SA"
            | "FR"
            | "ZV"
            | "ZR"
    )
}

/// HG4402: an action in the condition part of a transition.
pub(super) fn action_in_condition(
    ctx: &mut Ctx<'_>,
    stmt: &ast::StlStmt,
    stmt_range: TextRange,
    op: &str,
    operand: &str,
    transition: &str,
) {
    let message = format!(
        "'{op}' in the condition of {transition} changes {operand} while the condition is evaluated; put actions in a '!:' block"
    );
    let mut diag = ctx.diag("HG4402", stmt_range, message);
    if let Some(fix) = move_to_action_block(ctx, stmt) {
        diag = diag.fix_edits("Move it into a '!:' block", fix);
    }
    ctx.push(diag);
}

/// The edits moving a statement into its transition's last `!:` block, after that block's
/// last statement; when the transition has no `!:` block, into a new one at the end of the
/// body.
fn move_to_action_block(
    ctx: &Ctx<'_>,
    stmt: &ast::StlStmt,
) -> Option<Vec<(crate::diag::Loc, String)>> {
    let body = stmt
        .syntax()
        .ancestors()
        .find(|n| n.kind() == SyntaxKind::BODY)
        .and_then(ast::Body::cast)?;
    let text = stmt.syntax().text().to_string();
    let action_block = body
        .blocks()
        .filter(|b| b.label().is_some_and(|l| l.name() == "!"))
        .last();
    let (at, inserted) = match action_block {
        Some(block) => {
            let end = match block.statements().last() {
                Some(last) => last.syntax().text_range().end(),
                None => block.label()?.syntax().text_range().end(),
            };
            (end, format!(" {text}"))
        }
        None => (body.r_angle()?.text_range().start(), format!("!: {text} ")),
    };
    let removal = (ctx.loc(stmt.syntax().text_range()), String::new());
    let insertion = (ctx.loc(TextRange::empty(at)), inserted);
    Some(if at <= stmt.syntax().text_range().start() {
        vec![insertion, removal]
    } else {
        vec![removal, insertion]
    })
}
