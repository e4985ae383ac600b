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
    operands::{self, IecTarget, Target, Unresolved},
    parts, times, without_semi,
};
use crate::{
    iec::{Direction, FbMember, FbType},
    lang::{Section, Type},
    resolve,
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
    /// Arithmetic on integer constants only (`2 * 3`, IEC charts): adapts to INT, DINT or
    /// REAL, otherwise DINT.
    IntConst,
    Unknown,
}

impl Ty {
    /// The type without adaptation.
    fn fixed(&self) -> Option<Type> {
        match self {
            Ty::Known(t) => Some(*t),
            Ty::IntLit(lit) => type_named(literal_type(lit)),
            Ty::IntConst => Some(Type::Dint),
            Ty::Unknown => None,
        }
    }

    /// An integer literal or constant arithmetic.
    fn is_int_constant(&self) -> bool {
        matches!(self, Ty::IntLit(_) | Ty::IntConst)
    }

    /// The integer literal `0` or `1` (BOOL in an IEC chart where a BOOL is expected).
    fn is_bool_constant(&self) -> bool {
        matches!(self, Ty::IntLit(lit) if matches!(lit.value, LiteralValue::Int(0 | 1)))
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
                    let mut writes = Vec::new();
                    for statement in statements(&part) {
                        self.statement(&statement, &Part::Run, &mut writes, true);
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
            self.statement(&statement, &part, writes, true);
        }
    }

    /// The bodies of the chart's actions (`docs/iec.md` §6). In a PCS 7 chart (where each
    /// action is HG7502) and for a later action of a name (HG7510, C3) only the uses count.
    pub fn actions(&mut self) {
        let actions: Vec<ast::ChartAction> = self.scope.chart.chart.actions().collect();
        // `scope.actions` holds the named actions in text order.
        let mut named = 0;
        for action in actions {
            let duplicate = match action.name().and_then(|n| n.token()) {
                Some(_) => {
                    named += 1;
                    self.scope
                        .actions
                        .get(named - 1)
                        .is_some_and(|a| a.duplicate)
                }
                None => false,
            };
            let report = self.scope.iec && !duplicate;
            let mut writes = Vec::new();
            for statement in action.statements() {
                self.statement(&statement, &Part::Run, &mut writes, report);
            }
        }
    }

    /// One statement (nested ones too); its writes go to `writes` (HG7311). The structured
    /// statements are HG7502 in a PCS 7 chart, with nothing reported inside them.
    fn statement(
        &mut self,
        statement: &ast::Stmt,
        part: &Part,
        writes: &mut Vec<Write>,
        report: bool,
    ) {
        let report = report && !has_error(statement.syntax());
        match statement {
            ast::Stmt::Assignment(assignment) => {
                if let Some((target, text)) = self.assignment(assignment, report) {
                    writes.push(Write {
                        part: part.clone(),
                        target,
                        range: without_semi(assignment.syntax()),
                        text,
                    });
                }
            }
            ast::Stmt::If(stmt) => {
                let report = report && self.iec_only(stmt.syntax(), "an IF statement");
                if let Some(condition) = stmt.condition() {
                    self.bool_expr(&condition, report);
                }
                for inner in stmt.then_statements() {
                    self.statement(&inner, part, writes, report);
                }
                for elsif in stmt.elsifs() {
                    if let Some(condition) = elsif.condition() {
                        self.bool_expr(&condition, report);
                    }
                    for inner in elsif.statements() {
                        self.statement(&inner, part, writes, report);
                    }
                }
                for inner in stmt.else_clause().into_iter().flat_map(|e| e.statements()) {
                    self.statement(&inner, part, writes, report);
                }
            }
            ast::Stmt::Case(stmt) => {
                let report = report && self.iec_only(stmt.syntax(), "a CASE statement");
                self.case(stmt, report);
                for arm in stmt.arms() {
                    for inner in arm.statements() {
                        self.statement(&inner, part, writes, report);
                    }
                }
                for inner in stmt.else_clause().into_iter().flat_map(|e| e.statements()) {
                    self.statement(&inner, part, writes, report);
                }
            }
            ast::Stmt::Call(call) => {
                let report = report && self.iec_only(call.syntax(), "a function block call");
                self.call(call, part, writes, report);
            }
        }
    }

    /// In a PCS 7 chart: HG7502 on the construct's first token (its keyword, or a call's
    /// block name), and `false` (nothing more is reported inside it). `true` in an IEC chart.
    fn iec_only(&mut self, node: &SyntaxNode, construct: &str) -> bool {
        if self.scope.iec {
            return true;
        }
        let Some(keyword) = super::first_token(node) else {
            return false;
        };
        let diag = self.ctx.diag(
            "HG7502",
            keyword.text_range(),
            format!("{construct} needs 'profile iec;'"),
        );
        let diag = super::with_profile_fix(self.ctx, diag, &self.scope.chart.chart);
        self.ctx.push(diag);
        false
    }

    /// An expression that must be BOOL (`IF`/`ELSIF` conditions): HG7304.
    fn bool_expr(&mut self, expr: &ast::Expr, report: bool) {
        let ty = self.expr(expr, report);
        if report {
            self.require_bool(expr, &ty);
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

    /// `target := value;` — HG7308, HG7306; HG7505 for a write to a function block output
    /// or instance. Returns the target (for HG7311).
    fn assignment(
        &mut self,
        assignment: &ast::Assignment,
        report: bool,
    ) -> Option<(Target, String)> {
        let path = assignment.target()?;
        let target = operands::resolve(self.ctx, self.scope, &path, Unresolved::Operand, report);
        let written = path.syntax().text().to_string();
        let mut report = report;
        if report {
            self.writes_input(&target, &written, path.syntax().text_range());
            if let Some(problem) = self.read_only(&target) {
                let diag = self.ctx.diag(
                    "HG7505",
                    path.syntax().text_range(),
                    format!("cannot assign to {written}: {problem}"),
                );
                self.ctx.push(diag);
                report = false;
            }
        }
        if let Some(value) = assignment.value() {
            let value_ty = self.expr(&value, report);
            if report && let Some(target_ty) = target.ty(self.scope) {
                let value_ty = adapt_to(&value_ty, target_ty, self.scope.iec);
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
        let mut report = !has_error(action.syntax());
        let qualifier = action.qualifier()?;
        let q = qualifier.text().to_owned();
        if ["P1", "P0", "DL"]
            .iter()
            .any(|i| i.eq_ignore_ascii_case(&q))
            && !self.scope.iec
        {
            if report {
                let diag = self.ctx.diag(
                    "HG7502",
                    qualifier.text_range(),
                    format!("qualifier {q} needs 'profile iec;'"),
                );
                let diag = super::with_profile_fix(self.ctx, diag, &self.scope.chart.chart);
                self.ctx.push(diag);
            }
            report = false;
        }
        let mut operands = action.operands();
        let operand = operands.next()?;
        let time = operands.next();
        let written = operand.syntax().text().to_string();
        if self.action_operand(&operand).is_some() {
            // A qualifier's operand may name an action (`docs/iec.md` §6): not a variable write.
            let time_ok = !report
                || parts::check_qualifier_time(
                    self.ctx,
                    action,
                    &qualifier,
                    &written,
                    time.as_ref(),
                );
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
            return None;
        }
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

    /// The action a qualifier operand names: a single name that is no variable of the chart
    /// but one of its actions (recorded as used).
    fn action_operand(&mut self, operand: &ast::Operand) -> Option<usize> {
        let ast::Operand::Path(path) = operand else {
            return None;
        };
        if path.address().is_some() || path.symbol().is_some() {
            return None;
        }
        let mut segments = path.segments();
        let name = segments.next()?;
        if segments.next().is_some() {
            return None;
        }
        let token = name.token()?;
        if self.scope.var(token.text()).is_some() {
            return None;
        }
        let i = self.scope.action(token.text())?;
        if let Some(used) = self.scope.action_used.get_mut(i) {
            *used = true;
        }
        if let Some(action) = self.scope.actions.get(i) {
            resolve::case_hint(self.ctx, token.text_range(), token.text(), &action.name);
        }
        Some(i)
    }

    /// Why a target cannot be written, if it cannot: a function block output or instance, a
    /// step flag.
    fn read_only(&self, target: &Target) -> Option<String> {
        match target {
            Target::Iec(IecTarget::FbMember { var, member }) => {
                let fb = self.scope.vars.get(*var).and_then(|v| v.fb)?;
                (member.direction == Direction::Output).then(|| {
                    format!(
                        "{} is an output of {}; only the block writes it",
                        member.name,
                        fb.name()
                    )
                })
            }
            Target::Iec(IecTarget::StepFlag { .. }) => {
                Some("the flags of a step can only be read".to_owned())
            }
            Target::Var(i) => {
                let fb = self.scope.vars.get(*i).and_then(|v| v.fb)?;
                Some(format!(
                    "it is a function block instance ({}); assign its inputs or call it",
                    fb.name()
                ))
            }
            _ => None,
        }
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
        let instance = match target {
            Target::Var(i) if self.scope.iec => self.scope.vars.get(*i).and_then(|v| v.fb),
            _ => None,
        };
        let problem = match operand {
            ast::Operand::Literal(_) => Some("a constant".to_owned()),
            _ if instance.is_some() => {
                instance.map(|fb| format!("a function block instance ({})", fb.name()))
            }
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

    /// HG7304 when a known type is not BOOL (in an IEC chart the integer constants `0` and
    /// `1` are BOOL, `docs/iec.md` §3).
    fn require_bool(&mut self, expr: &ast::Expr, ty: &Ty) {
        if self.scope.iec && ty.is_bool_constant() {
            return;
        }
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
                if report && let Target::Var(i) = target {
                    self.instance_as_value(i, path);
                }
                target.ty(self.scope).map_or(Ty::Unknown, Ty::Known)
            }
            ast::Expr::Paren(paren) => match paren.expr() {
                Some(inner) => self.expr(&inner, report),
                None => Ty::Unknown,
            },
            ast::Expr::Prefix(prefix) => self.prefix(prefix, report),
            ast::Expr::Bin(bin) => self.binary(bin, report),
        }
    }

    /// HG7505: a function block instance used as a value.
    fn instance_as_value(&mut self, var: usize, path: &ast::Path) {
        let Some(fb) = self.scope.vars.get(var).and_then(|v| v.fb) else {
            return;
        };
        if !self.scope.iec {
            return;
        }
        let diag = self.ctx.diag(
            "HG7505",
            path.syntax().text_range(),
            format!(
                "{} is a function block instance ({}), not a value; read one of its outputs",
                path.syntax().text(),
                fb.name()
            ),
        );
        self.ctx.push(diag);
    }

    /// `not` (operand BOOL, HG7304) or unary `-` (HG7506; HG7502 in a PCS 7 chart).
    fn prefix(&mut self, prefix: &ast::PrefixExpr, report: bool) -> Ty {
        if prefix.op() == Some(ast::PrefixOp::Neg) {
            let report = self.arithmetic_allowed(prefix.syntax(), "unary '-'", report) && report;
            let Some(operand) = prefix.operand() else {
                return Ty::Unknown;
            };
            let ty = self.expr(&operand, report);
            if !self.scope.iec {
                return Ty::Unknown;
            }
            return match ty {
                Ty::IntLit(_) | Ty::IntConst => Ty::IntConst,
                Ty::Unknown => Ty::Unknown,
                Ty::Known(t @ (Type::Int | Type::Dint | Type::Real | Type::Time)) => Ty::Known(t),
                Ty::Known(t) => {
                    if report {
                        let diag = self.ctx.diag(
                            "HG7506",
                            prefix.syntax().text_range(),
                            format!("unary '-' is not defined for {t}"),
                        );
                        self.ctx.push(diag);
                    }
                    Ty::Unknown
                }
            };
        }
        if let Some(operand) = prefix.operand() {
            let ty = self.expr(&operand, report);
            if report {
                self.require_bool(&operand, &ty);
            }
        }
        Ty::Known(Type::Bool)
    }

    /// In a PCS 7 chart, the outermost arithmetic expression is HG7502 (nothing inside it is
    /// reported, and its type is unknown). Returns whether to go on reporting.
    fn arithmetic_allowed(&mut self, node: &SyntaxNode, op: &str, report: bool) -> bool {
        if self.scope.iec {
            return true;
        }
        if report {
            let diag = self.ctx.diag(
                "HG7502",
                node.text_range(),
                format!("arithmetic ({op}) needs 'profile iec;'"),
            );
            let diag = super::with_profile_fix(self.ctx, diag, &self.scope.chart.chart);
            self.ctx.push(diag);
        }
        false
    }

    /// `and`/`or`/`xor` (both sides BOOL, HG7304), a comparison (HG7305) or arithmetic
    /// (HG7506, HG7507).
    fn binary(&mut self, bin: &ast::BinExpr, report: bool) -> Ty {
        let op = bin.op();
        if let Some(op) = op.filter(|o| o.is_arithmetic()) {
            return self.arithmetic(bin, op, report);
        }
        let op_text = bin.op_text().unwrap_or_default();
        let lhs = bin.lhs();
        let rhs = bin.rhs();
        let lhs_ty = lhs.as_ref().map_or(Ty::Unknown, |e| self.expr(e, report));
        let rhs_ty = rhs.as_ref().map_or(Ty::Unknown, |e| self.expr(e, report));
        if matches!(op_text.as_str(), "and" | "or" | "xor") {
            if report {
                for (side, ty) in [(&lhs, &lhs_ty), (&rhs, &rhs_ty)] {
                    if let Some(side) = side {
                        self.require_bool(side, ty);
                    }
                }
            }
        } else if report {
            self.comparison(bin, &op_text, &lhs_ty, &rhs_ty);
        }
        Ty::Known(Type::Bool)
    }

    /// `+ - * / MOD` (`docs/iec.md` §4): HG7506 for operands that do not fit, HG7507 for a
    /// constant zero divisor; HG7502 in a PCS 7 chart.
    fn arithmetic(&mut self, bin: &ast::BinExpr, op: ast::BinOp, report: bool) -> Ty {
        let allowed = self.arithmetic_allowed(bin.syntax(), &format!("'{}'", op.text()), report);
        let report = report && allowed;
        let lhs = bin.lhs();
        let rhs = bin.rhs();
        let lhs_ty = lhs.as_ref().map_or(Ty::Unknown, |e| self.expr(e, report));
        let rhs_ty = rhs.as_ref().map_or(Ty::Unknown, |e| self.expr(e, report));
        if !allowed {
            return Ty::Unknown;
        }
        if report
            && matches!(op, ast::BinOp::Div | ast::BinOp::Mod)
            && let Some(rhs) = &rhs
            && is_zero(rhs)
        {
            let what = if op == ast::BinOp::Div {
                "division"
            } else {
                "MOD"
            };
            let diag = self.ctx.diag(
                "HG7507",
                rhs.syntax().text_range(),
                format!("{what} by the constant zero"),
            );
            self.ctx.push(diag);
        }
        let result = arithmetic_type(op, &lhs_ty, &rhs_ty);
        if let Err((a, b)) = &result
            && report
        {
            let diag = self.ctx.diag(
                "HG7506",
                bin.syntax().text_range(),
                format!("'{}' is not defined for {a} and {b}", op.text()),
            );
            self.ctx.push(diag);
        }
        result.unwrap_or(Ty::Unknown)
    }

    /// HG7305: both sides of a comparison have the same type after adaptation, and ordering
    /// comparisons need an ordered type.
    fn comparison(&mut self, bin: &ast::BinExpr, op: &str, lhs: &Ty, rhs: &Ty) {
        let Some((a, b)) = adapt_pair(lhs, rhs, self.scope.iec) else {
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

    /// A `CASE` statement's selector (HG7509) and labels (HG7509 out of range, HG7508 covered
    /// twice or empty).
    fn case(&mut self, stmt: &ast::CaseStmt, report: bool) {
        let selector_ty = stmt
            .selector()
            .map_or(Ty::Unknown, |e| self.expr(&e, report));
        if !report {
            return;
        }
        let selector = match &selector_ty {
            Ty::Known(t @ (Type::Int | Type::Dint)) => Some(*t),
            Ty::IntLit(_) | Ty::IntConst => Some(Type::Dint),
            Ty::Unknown => None,
            Ty::Known(t) => {
                if let Some(expr) = stmt.selector() {
                    let diag = self.ctx.diag(
                        "HG7509",
                        expr.syntax().text_range(),
                        format!(
                            "CASE selector must be INT or DINT; {} is {t}",
                            collapsed(expr.syntax())
                        ),
                    );
                    self.ctx.push(diag);
                }
                None
            }
        };
        // The labels so far as disjoint intervals by their low end: linear in the labels
        // (times a logarithm), not quadratic.
        let mut covered: std::collections::BTreeMap<i64, (i64, TextRange)> =
            std::collections::BTreeMap::new();
        for label in stmt.arms().flat_map(|a| a.labels().collect::<Vec<_>>()) {
            if has_error(label.syntax()) {
                continue;
            }
            let Some(low) = label.low() else {
                continue;
            };
            let high = label.high().unwrap_or(low);
            let range = label.syntax().text_range();
            let text = collapsed(label.syntax());
            if let Some(ty) = selector {
                let (min, max) = if ty == Type::Int {
                    (i64::from(i16::MIN), i64::from(i16::MAX))
                } else {
                    (i64::from(i32::MIN), i64::from(i32::MAX))
                };
                if low < min || high > max || low > max || high < min {
                    let diag = self.ctx.diag(
                        "HG7509",
                        range,
                        format!(
                            "CASE label {text} is outside the range of the selector's type {ty}"
                        ),
                    );
                    self.ctx.push(diag);
                    continue;
                }
            }
            if low > high {
                let diag = self.ctx.diag(
                    "HG7508",
                    range,
                    format!("CASE range {text} is empty: {low} is greater than {high}"),
                );
                self.ctx.push(diag);
                continue;
            }
            let overlap = covered
                .range(..=high)
                .next_back()
                .filter(|(_, (end, _))| *end >= low)
                .map(|(_, (_, r))| *r);
            if let Some(earlier) = overlap {
                let diag = self
                    .ctx
                    .diag(
                        "HG7508",
                        range,
                        format!("CASE label {text} is already covered by an earlier arm"),
                    )
                    .related(self.ctx.loc(earlier), "the earlier label");
                self.ctx.push(diag);
                continue;
            }
            covered.insert(low, (high, range));
        }
    }

    /// A function block call (`docs/iec.md` §5): HG7505 for a callee that is no instance, an
    /// unknown or repeated formal, the wrong direction or a wrong type; HG7308 and the writes
    /// (HG7311) of its outputs.
    fn call(&mut self, call: &ast::FbCall, part: &Part, writes: &mut Vec<Write>, report: bool) {
        let fb = call
            .callee()
            .and_then(|callee| self.callee(&callee, report));
        let report_args = report && fb.is_some();
        let mut given: Vec<(&'static str, TextRange)> = Vec::new();
        for arg in call.args() {
            let report = report_args && !has_error(arg.syntax());
            let member = match (fb, arg.formal().and_then(|f| f.token())) {
                (Some(fb), Some(formal)) => {
                    self.formal(fb, &formal, arg.is_output(), &mut given, report)
                }
                _ => None,
            };
            let report = report && member.is_some();
            if let Some(value) = arg.value() {
                let ty = self.expr(&value, report);
                if report
                    && let Some(member) = member
                    && let Some(ty) = adapt_to(&ty, member.ty, self.scope.iec)
                    && !same_type(ty, member.ty)
                {
                    let diag = self.ctx.diag(
                        "HG7505",
                        value.syntax().text_range(),
                        format!("cannot pass {ty} to {} ({})", member.name, member.ty),
                    );
                    self.ctx.push(diag);
                }
            }
            if let Some(path) = arg.target() {
                let target =
                    operands::resolve(self.ctx, self.scope, &path, Unresolved::Operand, report);
                let written = path.syntax().text().to_string();
                let range = path.syntax().text_range();
                if report && let Some(member) = member {
                    self.writes_input(&target, &written, range);
                    if let Some(problem) = self.read_only(&target) {
                        let diag = self.ctx.diag(
                            "HG7505",
                            range,
                            format!("cannot read {} into {written}: {problem}", member.name),
                        );
                        self.ctx.push(diag);
                    } else if let Some(ty) = target.ty(self.scope)
                        && !same_type(ty, member.ty)
                    {
                        let diag = self.ctx.diag(
                            "HG7505",
                            range,
                            format!(
                                "cannot read {} ({}) into {written} ({ty})",
                                member.name, member.ty
                            ),
                        );
                        self.ctx.push(diag);
                    }
                }
                writes.push(Write {
                    part: part.clone(),
                    target,
                    range: arg.syntax().text_range(),
                    text: written,
                });
            }
        }
    }

    /// The block a call names: a chart variable of a standard function block type (recorded
    /// as used); HG7505 otherwise.
    fn callee(&mut self, callee: &ast::NameRef, report: bool) -> Option<FbType> {
        let token = callee.token()?;
        let name = token.text();
        let range = token.text_range();
        if let Some(i) = self.scope.var(name) {
            self.scope.used[i] = true;
            let var = &self.scope.vars[i];
            if report {
                resolve::case_hint(self.ctx, range, name, &var.name.clone());
            }
            if let Some(fb) = var.fb {
                return Some(fb);
            }
            if report {
                let what = var.ty.map_or("a variable".to_owned(), |t| {
                    format!("a variable of type {t}")
                });
                let diag = self.ctx.diag(
                    "HG7505",
                    range,
                    format!("'{name}' is {what}, not a function block instance; only instances can be called"),
                );
                self.ctx.push(diag);
            }
            return None;
        }
        if report {
            let diag = self.ctx.diag(
                "HG7505",
                range,
                format!(
                    "'{name}' is not a function block instance of {}",
                    self.scope.chart.owner()
                ),
            );
            let instances: Vec<String> = self
                .scope
                .vars
                .iter()
                .filter(|v| v.fb.is_some() && !v.duplicate)
                .map(|v| v.name.clone())
                .collect();
            let diag =
                self.ctx
                    .with_closest_fix(diag, range, name, instances.iter().map(String::as_str));
            self.ctx.push(diag);
        }
        None
    }

    /// One formal of a call: HG7505 for an unknown or repeated formal or the wrong direction.
    /// Returns the member when the argument can be checked further.
    fn formal(
        &mut self,
        fb: FbType,
        formal: &higraph_syntax::SyntaxToken,
        is_output: bool,
        given: &mut Vec<(&'static str, TextRange)>,
        report: bool,
    ) -> Option<&'static FbMember> {
        let name = formal.text();
        let range = formal.text_range();
        let Some(member) = fb.member(name) else {
            if report {
                let diag = self.ctx.diag(
                    "HG7505",
                    range,
                    format!("{} has no formal '{name}'", fb.name()),
                );
                let diag = self.ctx.with_closest_fix(
                    diag,
                    range,
                    name,
                    fb.members().iter().map(|m| m.name),
                );
                self.ctx.push(diag);
            }
            return None;
        };
        if let Some((_, first)) = given.iter().find(|(n, _)| *n == member.name) {
            if report {
                let diag = self
                    .ctx
                    .diag(
                        "HG7505",
                        range,
                        format!("formal '{}' is given twice", member.name),
                    )
                    .related(self.ctx.loc(*first), "the first one");
                self.ctx.push(diag);
            }
            return None;
        }
        given.push((member.name, range));
        let problem = match (member.direction, is_output) {
            (Direction::Input, true) => Some(format!(
                "{} is an input of {}; pass it with '{} := value'",
                member.name,
                fb.name(),
                member.name
            )),
            (Direction::Output, false) => Some(format!(
                "{} is an output of {}; read it with '{} => variable'",
                member.name,
                fb.name(),
                member.name
            )),
            _ => None,
        };
        if let Some(problem) = problem {
            if report {
                let diag = self.ctx.diag("HG7505", range, problem);
                self.ctx.push(diag);
            }
            return None;
        }
        if report {
            resolve::case_hint(self.ctx, range, name, member.name);
        }
        Some(member)
    }
}

/// The statements of a part (`pre`, `post`, `init`, `run`, `term`).
fn statements(part: &SyntaxNode) -> impl Iterator<Item = ast::Stmt> + use<> {
    body_children(part).filter_map(ast::Stmt::cast)
}

/// Is the expression the constant zero (`0`, `0.0`, `T#0S`, in parentheses too)?
fn is_zero(expr: &ast::Expr) -> bool {
    let mut expr = expr.clone();
    while let ast::Expr::Paren(p) = &expr {
        match p.expr() {
            Some(inner) => expr = inner,
            None => return false,
        }
    }
    let ast::Expr::Literal(literal) = expr else {
        return false;
    };
    match check_literal(literal.text().trim()).map(|l| l.value) {
        Ok(LiteralValue::Int(0)) | Ok(LiteralValue::Duration { millis: 0 }) => true,
        Ok(LiteralValue::Real(r)) => r == 0.0,
        _ => false,
    }
}

/// The result type of `lhs op rhs` (`docs/iec.md` §4), or the two operand types it is not
/// defined for. Unknown operands give an unknown result (C2).
fn arithmetic_type(op: ast::BinOp, lhs: &Ty, rhs: &Ty) -> Result<Ty, (Type, Type)> {
    if matches!(lhs, Ty::Unknown) || matches!(rhs, Ty::Unknown) {
        return Ok(Ty::Unknown);
    }
    if lhs.is_int_constant() && rhs.is_int_constant() {
        return Ok(Ty::IntConst);
    }
    let Some((a, b)) = adapt_pair(lhs, rhs, false) else {
        return Ok(Ty::Unknown);
    };
    let numeric = |t: Type| matches!(t, Type::Int | Type::Dint | Type::Real);
    let integer = |t: Type| matches!(t, Type::Int | Type::Dint);
    let ok = match op {
        ast::BinOp::Add | ast::BinOp::Sub => {
            (a == Type::Time && b == Type::Time) || (a == b && numeric(a))
        }
        ast::BinOp::Mul => {
            (a == Type::Time && integer(b))
                || (integer(a) && b == Type::Time)
                || (a == b && numeric(a))
        }
        ast::BinOp::Div => (a == Type::Time && integer(b)) || (a == b && numeric(a)),
        _ => a == b && integer(a),
    };
    if !ok {
        return Err((a, b));
    }
    let result = if b == Type::Time { b } else { a };
    Ok(Ty::Known(result))
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

/// The type of one side after adapting an integer constant to `other` (C.3); in an IEC chart
/// `0` and `1` are BOOL where a BOOL is expected.
fn adapt_to(ty: &Ty, other: Type, iec: bool) -> Option<Type> {
    match ty {
        Ty::Known(t) => Some(*t),
        Ty::IntLit(_) if iec && other == Type::Bool && ty.is_bool_constant() => Some(Type::Bool),
        Ty::IntLit(lit) => type_named(chart_literal_type(lit, Some(&other.to_string()))),
        Ty::IntConst => Some(match other {
            Type::Int | Type::Dint | Type::Real => other,
            _ => Type::Dint,
        }),
        Ty::Unknown => None,
    }
}

/// Both sides of a comparison after adaptation; two integer constants compare as DINT.
fn adapt_pair(lhs: &Ty, rhs: &Ty, iec: bool) -> Option<(Type, Type)> {
    match (lhs, rhs) {
        (Ty::Unknown, _) | (_, Ty::Unknown) => None,
        _ if lhs.is_int_constant() && rhs.is_int_constant() => Some((Type::Dint, Type::Dint)),
        (_, Ty::Known(b)) => Some((adapt_to(lhs, *b, iec)?, *b)),
        (Ty::Known(a), _) => Some((*a, adapt_to(rhs, *a, iec)?)),
        _ => None,
    }
}

/// Type equality for comparisons and assignments; STRING lengths are not compared.
fn same_type(a: Type, b: Type) -> bool {
    matches!((a, b), (Type::String(_), Type::String(_))) || a == b
}
