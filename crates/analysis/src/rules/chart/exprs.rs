//! Conditions, statements and action qualifiers of a sequencer: operand resolution (through
//! `operands`), the type rules HG7304 (not BOOL), HG7305 (comparison), HG7306 (assignment) and
//! HG7307 (qualifier operand) with the literal adaptation of Appendix C.3, HG7308 (writing an
//! input) and the time values of steps (through `times`, plus HG7405).
//!
//! A construct with a syntax error (C1) is still walked so that its operands count as uses,
//! but gets no diagnostics. A type rule is skipped when a type involved is unknown (C2).

use higraph_syntax::{
    SyntaxKind, SyntaxNode, TextRange,
    ast::{self, AstNode},
    literal::{
        Literal, LiteralClass, LiteralValue, chart_literal_type, check_literal, literal_type,
    },
};

use super::{
    Scope, body_children, collapsed, has_error,
    operands::{self, Target, Unresolved},
    parts, times, without_semi,
};
use crate::{
    lang::{Section, Type},
    rules::{Ctx, stl::time::TimeKind},
};

/// Where a step writes an operand (HG7311).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Part {
    Init,
    Run,
    Term,
    /// A qualifier action, with the qualifier as written.
    Qualifier(String),
}

impl Part {
    /// `init`, `run`, `term` or `qualifier {q}` (§2.7a).
    pub fn display(&self) -> String {
        match self {
            Part::Init => "init".to_owned(),
            Part::Run => "run".to_owned(),
            Part::Term => "term".to_owned(),
            Part::Qualifier(q) => format!("qualifier {q}"),
        }
    }
}

/// A write of a step: an assignment target or a qualifier operand.
pub(crate) struct Write {
    pub part: Part,
    pub target: Target,
    /// The statement (without `;`) or the qualifier action.
    pub range: TextRange,
    /// The written operand as written.
    pub text: String,
}

/// The type of an expression.
#[derive(Debug, Clone)]
enum Ty {
    Known(Type),
    /// An integer literal, which adapts to the other side (C.3).
    IntLit(Literal),
    Unknown,
}

impl Ty {
    /// The type without adaptation.
    fn fixed(&self) -> Option<Type> {
        match self {
            Ty::Known(t) => Some(*t),
            Ty::IntLit(lit) => type_named(literal_type(lit)),
            Ty::Unknown => None,
        }
    }
}

/// Walks the operands of one sequencer, checking them against the chart's scope.
pub(crate) struct Walker<'c, 'a> {
    pub ctx: &'c mut Ctx<'a>,
    pub scope: &'c mut Scope,
}

impl<'c, 'a> Walker<'c, 'a> {
    /// A walker over the chart's scope.
    pub fn new(ctx: &'c mut Ctx<'a>, scope: &'c mut Scope) -> Walker<'c, 'a> {
        Walker { ctx, scope }
    }

    /// The `start`, `pre` and `post` parts of a sequencer (repeated ones too).
    pub fn sequencer_parts(&mut self, sequencer: &ast::Sequencer) {
        for part in sequencer
            .syntax()
            .children()
            .filter(|n| n.kind() == SyntaxKind::BODY)
            .flat_map(|b| b.children())
        {
            match part.kind() {
                SyntaxKind::START_PART => self.conditions(&part),
                SyntaxKind::PRE_PART | SyntaxKind::POST_PART => {
                    for statement in statements(&part) {
                        self.assignment(&statement);
                    }
                }
                _ => {}
            }
        }
    }

    /// The conditions of a `trans`, `jump`, `loop` or `start` node.
    pub fn conditions(&mut self, node: &SyntaxNode) {
        for condition in body_children(node).filter_map(ast::Condition::cast) {
            self.condition(&condition);
        }
    }

    /// The operands of an element that is not part of the tree (its name did not parse).
    pub fn element_body(&mut self, element: &ast::SeqElement) {
        match element {
            ast::SeqElement::Step(step) => {
                self.step(step, "");
            }
            ast::SeqElement::Trans(_) | ast::SeqElement::Jump(_) | ast::SeqElement::Loop(_) => {
                self.conditions(element.syntax());
            }
            ast::SeqElement::Parallel(_) | ast::SeqElement::Alt(_) => {}
        }
    }

    /// A step: its phases, qualifier actions and times. Returns its writes (HG7311).
    pub fn step(&mut self, step: &ast::Step, name: &str) -> Vec<Write> {
        let mut writes = Vec::new();
        let mut min: Option<(i64, TextRange, String)> = None;
        let mut max: Option<(i64, TextRange, String)> = None;
        let mut seen_min = false;
        let mut seen_max = false;
        for item in body_children(step.syntax()) {
            match item.kind() {
                SyntaxKind::STEP_PHASE => self.phase(&item, &mut writes),
                SyntaxKind::QUALIFIER_ACTION => {
                    if let Some(action) = ast::QualifierAction::cast(item)
                        && let Some(write) = self.qualifier(&action)
                    {
                        writes.push(write);
                    }
                }
                SyntaxKind::STEP_TIME => {
                    let Some(time) = ast::StepTime::cast(item) else {
                        continue;
                    };
                    let is_min = time
                        .keyword()
                        .is_some_and(|k| k.kind() == SyntaxKind::MIN_KW);
                    let value = self.step_time(&time, is_min);
                    // HG7209: a repeated `min` or `max` does not apply.
                    let (slot, seen) = if is_min {
                        (&mut min, &mut seen_min)
                    } else {
                        (&mut max, &mut seen_max)
                    };
                    if !*seen {
                        *seen = true;
                        *slot = value;
                    }
                }
                _ => {}
            }
        }
        if let (Some(min), Some(max)) = (min, max)
            && !name.is_empty()
        {
            times::check_min_max(self.ctx, name, min, max);
        }
        writes
    }

    /// `min` or `max`: the time value; returns its constant value, range and text.
    fn step_time(
        &mut self,
        time: &ast::StepTime,
        is_min: bool,
    ) -> Option<(i64, TextRange, String)> {
        let value = time.value()?;
        let kind = if is_min {
            TimeKind::MinRunTime
        } else {
            TimeKind::MaxRunTime
        };
        let report = !has_error(time.syntax());
        let item = time.syntax().text_range();
        let millis = times::check(self.ctx, self.scope, &value, kind, Some(item), report)?;
        Some((
            millis,
            without_semi(time.syntax()),
            value.syntax().text().to_string(),
        ))
    }

    /// `init`, `run` or `term`: its statements.
    fn phase(&mut self, phase: &SyntaxNode, writes: &mut Vec<Write>) {
        let part = match super::first_token(phase).map(|t| t.kind()) {
            Some(SyntaxKind::INIT_KW) => Part::Init,
            Some(SyntaxKind::RUN_KW) => Part::Run,
            _ => Part::Term,
        };
        for statement in statements(phase) {
            if let Some((target, text)) = self.assignment(&statement) {
                writes.push(Write {
                    part: part.clone(),
                    target,
                    range: without_semi(statement.syntax()),
                    text,
                });
            }
        }
    }

    /// A condition: the whole expression must be BOOL (HG7304).
    fn condition(&mut self, condition: &ast::Condition) {
        let report = !has_error(condition.syntax());
        let Some(expr) = condition.expr() else {
            return;
        };
        let ty = self.expr(&expr, report);
        if report {
            self.require_bool(&expr, &ty);
        }
    }

    /// `target := value;` — HG7308, HG7306. Returns the target (for HG7311).
    fn assignment(&mut self, assignment: &ast::Assignment) -> Option<(Target, String)> {
        let report = !has_error(assignment.syntax());
        let path = assignment.target()?;
        let target = operands::resolve(self.ctx, self.scope, &path, Unresolved::Operand, report);
        let written = path.syntax().text().to_string();
        if report {
            self.writes_input(&target, &written, path.syntax().text_range());
        }
        if let Some(value) = assignment.value() {
            let value_ty = self.expr(&value, report);
            if report && let Some(target_ty) = target.ty(self.scope) {
                let value_ty = adapt_to(&value_ty, target_ty);
                if let Some(value_ty) = value_ty
                    && !same_type(value_ty, target_ty)
                {
                    let diag = self.ctx.diag(
                        "HG7306",
                        value.syntax().text_range(),
                        format!("cannot assign {value_ty} to {written} ({target_ty})"),
                    );
                    self.ctx.push(diag);
                }
            }
        }
        Some((target, written))
    }

    /// A qualifier action: HG7302/HG7303 (time), HG7307 (operand), HG7308, its time value.
    fn qualifier(&mut self, action: &ast::QualifierAction) -> Option<Write> {
        let report = !has_error(action.syntax());
        let qualifier = action.qualifier()?;
        let q = qualifier.text().to_owned();
        let mut operands = action.operands();
        let operand = operands.next()?;
        let time = operands.next();
        let written = operand.syntax().text().to_string();
        let time_ok = !report
            || parts::check_qualifier_time(self.ctx, action, &qualifier, &written, time.as_ref());
        if let Some(time) = &time {
            let report = report && time_ok;
            times::check(
                self.ctx,
                self.scope,
                time,
                TimeKind::ActionTime,
                None,
                report,
            );
        }
        let target = match &operand {
            ast::Operand::Path(path) => {
                operands::resolve(self.ctx, self.scope, path, Unresolved::Operand, report)
            }
            _ => Target::Unresolved,
        };
        if report {
            self.qualifier_operand(&q, &operand, &target, &written);
        }
        if !matches!(operand, ast::Operand::Path(_)) {
            return None;
        }
        Some(Write {
            part: Part::Qualifier(q),
            target,
            range: without_semi(action.syntax()),
            text: written,
        })
    }

    /// HG7307: the operand of an action qualifier is a BOOL operand, not a constant; HG7308.
    fn qualifier_operand(
        &mut self,
        q: &str,
        operand: &ast::Operand,
        target: &Target,
        written: &str,
    ) {
        let range = operand.syntax().text_range();
        let problem = match operand {
            ast::Operand::Literal(_) => Some("a constant".to_owned()),
            _ => match target.ty(self.scope) {
                Some(Type::Bool) | None => None,
                Some(ty) => Some(ty.to_string()),
            },
        };
        if let Some(problem) = problem {
            let diag = self.ctx.diag(
                "HG7307",
                range,
                format!("action qualifier {q} needs a BOOL operand; {written} is {problem}"),
            );
            self.ctx.push(diag);
        }
        self.writes_input(target, written, range);
    }

    /// HG7308: an assignment target or qualifier operand that is an input of the chart.
    fn writes_input(&mut self, target: &Target, written: &str, range: TextRange) {
        let Target::Var(i) = target else {
            return;
        };
        if self
            .scope
            .vars
            .get(*i)
            .is_some_and(|v| v.section == Section::In)
        {
            let diag = self.ctx.diag(
                "HG7308",
                range,
                format!(
                    "'{written}' is an input of chart {}; the chart should not write it",
                    self.scope.chart.name
                ),
            );
            self.ctx.push(diag);
        }
    }

    /// HG7304 when a known type is not BOOL.
    fn require_bool(&mut self, expr: &ast::Expr, ty: &Ty) {
        let Some(ty) = ty.fixed() else {
            return;
        };
        if ty == Type::Bool {
            return;
        }
        let diag = self.ctx.diag(
            "HG7304",
            expr.syntax().text_range(),
            format!(
                "condition must be BOOL; {} is {ty}",
                collapsed(expr.syntax())
            ),
        );
        self.ctx.push(diag);
    }

    /// The type of an expression, checking its parts.
    fn expr(&mut self, expr: &ast::Expr, report: bool) -> Ty {
        match expr {
            ast::Expr::Literal(literal) => literal_ty(literal),
            // Only tests have test paths.
            ast::Expr::TestPath(_) => Ty::Unknown,
            ast::Expr::Path(path) => {
                let target =
                    operands::resolve(self.ctx, self.scope, path, Unresolved::Operand, report);
                target.ty(self.scope).map_or(Ty::Unknown, Ty::Known)
            }
            ast::Expr::Paren(paren) => match paren.expr() {
                Some(inner) => self.expr(&inner, report),
                None => Ty::Unknown,
            },
            ast::Expr::Prefix(prefix) => {
                if let Some(operand) = prefix.operand() {
                    let ty = self.expr(&operand, report);
                    if report {
                        self.require_bool(&operand, &ty);
                    }
                }
                Ty::Known(Type::Bool)
            }
            ast::Expr::Bin(bin) => self.binary(bin, report),
        }
    }

    /// `and`/`or`/`xor` (both sides BOOL, HG7304) or a comparison (HG7305).
    fn binary(&mut self, bin: &ast::BinExpr, report: bool) -> Ty {
        let op = bin.op_text().unwrap_or_default();
        let lhs = bin.lhs();
        let rhs = bin.rhs();
        let lhs_ty = lhs.as_ref().map_or(Ty::Unknown, |e| self.expr(e, report));
        let rhs_ty = rhs.as_ref().map_or(Ty::Unknown, |e| self.expr(e, report));
        if matches!(op.as_str(), "and" | "or" | "xor") {
            if report {
                for (side, ty) in [(&lhs, &lhs_ty), (&rhs, &rhs_ty)] {
                    if let Some(side) = side {
                        self.require_bool(side, ty);
                    }
                }
            }
        } else if report {
            self.comparison(bin, &op, &lhs_ty, &rhs_ty);
        }
        Ty::Known(Type::Bool)
    }

    /// HG7305: both sides of a comparison have the same type after adaptation, and ordering
    /// comparisons need an ordered type.
    fn comparison(&mut self, bin: &ast::BinExpr, op: &str, lhs: &Ty, rhs: &Ty) {
        let Some((a, b)) = adapt_pair(lhs, rhs) else {
            return;
        };
        let range = bin.syntax().text_range();
        let message = if !same_type(a, b) {
            format!("cannot compare {a} with {b}")
        } else if matches!(op, "<" | ">" | "<=" | ">=")
            && matches!(
                a,
                Type::Bool | Type::String(_) | Type::Timer | Type::Counter
            )
        {
            format!("'{op}' is not defined for {a}")
        } else {
            return;
        };
        let diag = self.ctx.diag("HG7305", range, message);
        self.ctx.push(diag);
    }
}

/// The assignments of a part (`pre`, `post`, `init`, `run`, `term`).
fn statements(part: &SyntaxNode) -> impl Iterator<Item = ast::Assignment> + use<> {
    body_children(part).filter_map(ast::Assignment::cast)
}

/// The type of a literal: integer literals stay adaptable; malformed ones are unknown.
fn literal_ty(literal: &ast::Literal) -> Ty {
    let Ok(value) = check_literal(literal.text().trim()) else {
        return Ty::Unknown;
    };
    match (value.class, &value.value) {
        (LiteralClass::Integer, _) => Ty::IntLit(value),
        (LiteralClass::String, LiteralValue::Str(s)) => Ty::Known(Type::String(
            u16::try_from(s.chars().count()).unwrap_or(u16::MAX),
        )),
        _ => type_named(literal_type(&value)).map_or(Ty::Unknown, Ty::Known),
    }
}

/// A type from its canonical name (`INT`, `TIME_OF_DAY`, `POINTER`, ...).
fn type_named(name: &str) -> Option<Type> {
    Type::from_name(name, true)
}

/// The type of one side after adapting an integer literal to `other` (C.3).
fn adapt_to(ty: &Ty, other: Type) -> Option<Type> {
    match ty {
        Ty::Known(t) => Some(*t),
        Ty::IntLit(lit) => type_named(chart_literal_type(lit, Some(&other.to_string()))),
        Ty::Unknown => None,
    }
}

/// Both sides of a comparison after adaptation; two integer literals compare as DINT.
fn adapt_pair(lhs: &Ty, rhs: &Ty) -> Option<(Type, Type)> {
    match (lhs, rhs) {
        (Ty::IntLit(_), Ty::IntLit(_)) => Some((Type::Dint, Type::Dint)),
        (Ty::Unknown, _) | (_, Ty::Unknown) => None,
        (Ty::IntLit(_), Ty::Known(b)) => Some((adapt_to(lhs, *b)?, *b)),
        (Ty::Known(a), Ty::IntLit(_)) => Some((*a, adapt_to(rhs, *a)?)),
        (Ty::Known(a), Ty::Known(b)) => Some((*a, *b)),
    }
}

/// Type equality for comparisons and assignments; STRING lengths are not compared.
fn same_type(a: Type, b: Type) -> bool {
    matches!((a, b), (Type::String(_), Type::String(_))) || a == b
}
