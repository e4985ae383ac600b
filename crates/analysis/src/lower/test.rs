//! `test` items: their statements against the run scope ([`super::paths`]), both as the rules
//! HG9101–HG9111 see them and as the lowering turns them into [`TestStmtKind`]s. One walker
//! does both, so that a test without HG91xx errors lowers to exactly what the rules checked.

use std::collections::HashSet;

use higraph_runtime::program::{
    ArithOp, Command, Expr, OpState, Origin, Path, PathKind, Place, RunEntry, StepMember, Test,
    TestStmt, TestStmtKind,
};
use higraph_runtime::value::{Ty, Value};
use higraph_syntax::literal::{self, LiteralClass, LiteralValue};
use higraph_syntax::{TextRange, TextSize, ast, ast::AstNode};

use super::build::Lowerer;
use super::chart::{cmp_op, compact};
use super::paths::{PathError, PathTarget, Resolution, Resolver};
use super::values;
use crate::db::{File, ItemKind};
use crate::diag::{Diag, Loc};

/// What the lowering needs besides the resolver: the program being built and where the run
/// scope's groups and charts went in it.
pub(crate) struct Placer<'p, 'a> {
    pub lw: &'p mut Lowerer<'a>,
    /// Program group index of each scope group.
    pub groups: Vec<u32>,
    /// Program chart index of each scope chart.
    pub charts: Vec<u32>,
}

/// Walks one test.
pub(crate) struct TestWalker<'r, 'p, 'a> {
    pub r: Resolver<'r>,
    pub file: File,
    pub item: u32,
    pub test_name: String,
    pub diags: Vec<Diag>,
    pub placer: Option<Placer<'p, 'a>>,
    pub watch: Vec<Path>,
    watched: HashSet<String>,
    /// Collect paths into the watch list (in `set`, `expect`, `until`)?
    watching: bool,
    /// Where `, Name` goes to add a group or chart to the `run` statement (HG9103's fix).
    pub run_insert: Option<TextSize>,
    /// Δ in ms.
    pub cycle_ms: u32,
    /// The global symbols the test's paths name (HG6004).
    pub used_symbols: Vec<String>,
}

/// An expression's type while it is walked.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ETy {
    Known(Ty),
    /// An integer literal without context: adapts to the other side (C.3).
    IntLit,
    /// Unknown (an unresolved path, a stub of unknown type): no type rules (C2).
    Unknown,
}

fn known(t: ETy) -> Option<Ty> {
    match t {
        ETy::Known(t) => Some(t),
        _ => None,
    }
}

fn ty_name(t: Ty) -> String {
    match t {
        Ty::OpState => "operating state".to_owned(),
        t => t.to_string(),
    }
}

impl<'r, 'p, 'a> TestWalker<'r, 'p, 'a> {
    pub fn new(
        r: Resolver<'r>,
        file: File,
        item: u32,
        test: &ast::Test,
        placer: Option<Placer<'p, 'a>>,
    ) -> Self {
        TestWalker {
            r,
            file,
            item,
            test_name: test.name().map(|n| n.text()).unwrap_or_default(),
            diags: Vec::new(),
            placer,
            watch: Vec::new(),
            watched: HashSet::new(),
            watching: false,
            run_insert: run_insert(test),
            cycle_ms: cycle_ms(test),
            used_symbols: Vec::new(),
        }
    }

    fn loc(&self, range: TextRange) -> Loc {
        Loc::in_item(self.file, self.item, range)
    }

    fn push(&mut self, code: &'static str, range: TextRange, message: String) {
        let diag = Diag::new(code, self.loc(range), message);
        self.diags.push(diag);
    }

    fn closest_fix(
        &self,
        diag: Diag,
        range: TextRange,
        written: &str,
        candidates: &[String],
    ) -> Diag {
        match crate::closest::closest(written, candidates.iter().map(String::as_str)) {
            Some(best) => diag
                .fix(format!("Replace with '{best}'"), self.loc(range), best)
                .preferred(),
            None => diag,
        }
    }

    /// Reports a path error (HG9101–HG9103); `path` is the whole path's range.
    fn path_error(&mut self, error: PathError, path: TextRange) {
        let diag = match error {
            PathError::Unresolved {
                range,
                message,
                written,
                candidates,
            } => {
                let diag = Diag::new("HG9101", self.loc(range), message);
                self.closest_fix(diag, range, &written, &candidates)
            }
            PathError::Ambiguous {
                range,
                written,
                candidates,
            } => {
                let list = candidates
                    .iter()
                    .map(|c| format!("'{c}'"))
                    .collect::<Vec<_>>()
                    .join(" or ");
                let mut diag = Diag::new(
                    "HG9102",
                    self.loc(range),
                    format!("'{written}' is ambiguous; write {list}"),
                );
                for c in &candidates {
                    diag = diag.fix(format!("Replace with '{c}'"), self.loc(path), c.clone());
                }
                diag
            }
            PathError::NotRun { name } => self.not_run(path, &name),
        };
        self.diags.push(diag);
    }

    /// HG9103 for `name` (a group or chart) at `range`.
    fn not_run(&self, range: TextRange, name: &str) -> Diag {
        let diag = Diag::new(
            "HG9103",
            self.loc(range),
            format!("{name} is not run by test {}", self.test_name),
        );
        match self.run_insert {
            Some(at) => diag.fix(
                format!("Add {name} to 'run'"),
                self.loc(TextRange::empty(at)),
                format!(", {name}"),
            ),
            None => diag,
        }
    }

    /// Resolves a path and reports its errors.
    fn resolve(&mut self, path: &ast::TestPath) -> Option<Resolution> {
        match self.r.resolve(path) {
            Ok(resolution) => {
                if let PathTarget::Symbol(position, _) = &resolution.target
                    && let Some(symbol) = self.r.index.symbols.get(*position)
                {
                    self.used_symbols.push(symbol.name.clone());
                }
                if self.placer.is_none() && path.symbol().is_none() {
                    self.case_hints(path, &resolution);
                }
                if let Some((block, param, range)) = &resolution.not_an_output {
                    let diag = Diag::new(
                        "HG9111",
                        self.loc(*range),
                        format!("{block} has no output parameter '{param}'"),
                    );
                    self.diags.push(diag);
                }
                Some(resolution)
            }
            Err(error) => {
                self.path_error(error, path.syntax().text_range());
                None
            }
        }
    }

    /// HG1104: a segment whose letter case differs from its declaration.
    fn case_hints(&mut self, path: &ast::TestPath, resolution: &Resolution) {
        let written = path.segment_texts();
        for (range, def) in &resolution.segments {
            let Some((used, _)) = written.iter().find(|(_, r)| r == range) else {
                continue;
            };
            let Some(declared) = self.r.declared_name(def) else {
                continue;
            };
            if *used != declared && used.eq_ignore_ascii_case(&declared) {
                let diag = Diag::new(
                    "HG1104",
                    self.loc(*range),
                    format!("'{used}' is declared as '{declared}'"),
                )
                .fix(
                    format!("Replace with '{declared}'"),
                    self.loc(*range),
                    declared,
                );
                self.diags.push(diag);
            }
        }
    }

    /// The program path of a resolution (`ty` fills an unknown type); adds it to the watch
    /// list when watching. `None` when only checking.
    fn lower_path(&mut self, path: &ast::TestPath, res: &Resolution, ty: Ty) -> Option<Path> {
        let text = compact(path.syntax());
        let ty = res.ty.unwrap_or(ty);
        let placer = self.placer.as_mut()?;
        let kind = match &res.target {
            PathTarget::Address(a) => PathKind::Place(values::place(a)?),
            PathTarget::Symbol(_, a) => PathKind::Place(values::place(a.as_ref()?)?),
            PathTarget::InstVar {
                group,
                instance,
                var,
            } => PathKind::Place(
                placer
                    .lw
                    .var_place(*placer.groups.get(*group)?, *instance as u32, *var)?
                    .clone(),
            ),
            PathTarget::InstState {
                group,
                instance,
                previous,
            } => PathKind::InstState {
                group: *placer.groups.get(*group)?,
                instance: *instance as u32,
                previous: *previous,
            },
            PathTarget::ChartState { chart } => PathKind::ChartState {
                chart: *placer.charts.get(*chart)?,
            },
            PathTarget::ChartVar { chart, var } => {
                let c = *placer.charts.get(*chart)?;
                let cell = placer.lw.program.charts.get(c as usize)?.vars.get(*var)?.1;
                PathKind::Place(Place::Cell(cell))
            }
            PathTarget::ChartFb { chart, var, member } => {
                let c = *placer.charts.get(*chart)?;
                let lowered = placer.lw.program.charts.get(c as usize)?;
                let name = &lowered.vars.get(*var)?.0;
                let fb = lowered
                    .fbs
                    .iter()
                    .find(|f| f.name.eq_ignore_ascii_case(name))?;
                PathKind::Place(Place::Cell(fb.cell(*member)?))
            }
            PathTarget::Step {
                chart,
                sequencer,
                step,
                member,
            } => PathKind::Step {
                chart: *placer.charts.get(*chart)?,
                sequencer: *sequencer as u32,
                step: *step as u32,
                member: *member,
            },
            PathTarget::Stub { key, name, param } => PathKind::Stub {
                block: placer.lw.block(key.clone(), name.clone()),
                param: param.clone(),
            },
            PathTarget::Calls { key, name } => PathKind::Calls {
                block: placer.lw.block(key.clone(), name.clone()),
            },
            PathTarget::External(key) => {
                let cell = match placer.lw.externals.get(key) {
                    Some(&cell) => cell,
                    None => {
                        let cell = placer.lw.cell(ty, None);
                        placer.lw.externals.insert(key.clone(), cell);
                        cell
                    }
                };
                PathKind::Place(Place::Cell(cell))
            }
        };
        let ty = match (&kind, &res.target) {
            (PathKind::Place(Place::Cell(c)), PathTarget::External(_)) => placer
                .lw
                .program
                .cells
                .get(*c as usize)
                .map_or(ty, |info| info.ty),
            _ => ty,
        };
        let path = Path { text, ty, kind };
        if self.watching && self.watched.insert(path.text.clone()) {
            self.watch.push(path.clone());
        }
        Some(path)
    }

    /// The type of an expression, reporting nothing.
    fn static_ty(&mut self, e: &ast::Expr) -> ETy {
        match e {
            ast::Expr::Literal(lit) => match literal::check_literal(&lit.text()) {
                Ok(l) if l.class == LiteralClass::Integer => ETy::IntLit,
                Ok(l) => values::literal_ty(&l).map_or(ETy::Unknown, ETy::Known),
                Err(_) => ETy::Unknown,
            },
            ast::Expr::TestPath(path) => match self.r.resolve(path) {
                Ok(res) => res.ty.map_or(ETy::Unknown, ETy::Known),
                Err(_) => ETy::Unknown,
            },
            ast::Expr::Path(_) => ETy::Unknown,
            ast::Expr::Paren(p) => p.expr().map_or(ETy::Unknown, |e| self.static_ty(&e)),
            // Unary minus and arithmetic (IEC, `docs/iec.md` §4): the operands' type; depth
            // bounded by the parser's nesting limit.
            ast::Expr::Prefix(p) if p.op() == Some(ast::PrefixOp::Neg) => {
                p.operand().map_or(ETy::Unknown, |e| self.static_ty(&e))
            }
            ast::Expr::Bin(b) if b.op().is_some_and(ast::BinOp::is_arithmetic) => {
                let l = b.lhs().map_or(ETy::Unknown, |e| self.static_ty(&e));
                let r = b.rhs().map_or(ETy::Unknown, |e| self.static_ty(&e));
                match (l, r) {
                    (ETy::Known(t), _) | (_, ETy::Known(t)) => ETy::Known(t),
                    (ETy::IntLit, ETy::IntLit) => ETy::IntLit,
                    _ => ETy::Unknown,
                }
            }
            ast::Expr::Prefix(_) | ast::Expr::Bin(_) => ETy::Known(Ty::Bool),
        }
    }

    /// Walks an expression: reports type errors and (when lowering) returns the program
    /// expression. `hint` is the type the context gives an integer literal.
    fn expr(&mut self, e: &ast::Expr, hint: Option<Ty>) -> (Option<Expr>, ETy) {
        match e {
            ast::Expr::Literal(lit) => {
                let Ok(l) = literal::check_literal(&lit.text()) else {
                    return (None, ETy::Unknown);
                };
                let Some(ty) = values::adapted_ty(&l, hint) else {
                    return (None, ETy::Unknown);
                };
                let ety = if l.class == LiteralClass::Integer && hint.is_none() {
                    ETy::IntLit
                } else {
                    ETy::Known(ty)
                };
                (values::value_in(&l, ty).map(Expr::Const), ety)
            }
            ast::Expr::TestPath(path) => {
                let Some(res) = self.resolve(path) else {
                    return (None, ETy::Unknown);
                };
                let ety = res.ty.map_or(ETy::Unknown, ETy::Known);
                let lowered = self.lower_path(path, &res, hint.unwrap_or(Ty::Bool));
                (lowered.map(Expr::Read), ety)
            }
            ast::Expr::Path(_) => (None, ETy::Unknown),
            ast::Expr::Paren(p) => match p.expr() {
                Some(inner) => self.expr(&inner, hint),
                None => (None, ETy::Unknown),
            },
            ast::Expr::Prefix(p) if p.op() == Some(ast::PrefixOp::Neg) => {
                let Some(operand) = p.operand() else {
                    return (None, ETy::Unknown);
                };
                let (x, ty) = self.expr(&operand, hint);
                (x.map(|x| Expr::Neg(Box::new(x))), ty)
            }
            ast::Expr::Bin(b) if b.op().is_some_and(ast::BinOp::is_arithmetic) => {
                let (Some(op), Some(lhs), Some(rhs)) = (b.op(), b.lhs(), b.rhs()) else {
                    return (None, ETy::Unknown);
                };
                let op = match op {
                    ast::BinOp::Add => ArithOp::Add,
                    ast::BinOp::Sub => ArithOp::Sub,
                    ast::BinOp::Mul => ArithOp::Mul,
                    ast::BinOp::Div => ArithOp::Div,
                    _ => ArithOp::Mod,
                };
                let lt = self.static_ty(&lhs);
                let rt = self.static_ty(&rhs);
                // as in charts: an integer constant adopts the other operand's type; the
                // factor of `TIME * n`, `TIME / n` is a DINT constant
                let scaled =
                    lt == ETy::Known(Ty::Time) && matches!(op, ArithOp::Mul | ArithOp::Div);
                let ty = known(lt).or(known(rt)).or(hint);
                let (l, _) = self.expr(&lhs, ty);
                let rhint = if scaled {
                    known(rt).or(Some(Ty::Dint))
                } else {
                    known(rt).or(ty)
                };
                let (r, _) = self.expr(&rhs, rhint);
                let ety = match (ty, lt, rt) {
                    (Some(t), _, _) => ETy::Known(t),
                    (None, ETy::IntLit, ETy::IntLit) => ETy::IntLit,
                    _ => ETy::Unknown,
                };
                let x = l
                    .zip(r)
                    .map(|(l, r)| Expr::Arith(op, Box::new(l), Box::new(r)));
                (x, ety)
            }
            ast::Expr::Prefix(p) => {
                let Some(operand) = p.operand() else {
                    return (None, ETy::Known(Ty::Bool));
                };
                let (x, ty) = self.expr(&operand, Some(Ty::Bool));
                self.require_bool(&operand, ty);
                (x.map(|x| Expr::Not(Box::new(x))), ETy::Known(Ty::Bool))
            }
            ast::Expr::Bin(b) => {
                let (Some(op), Some(lhs), Some(rhs)) = (b.op_text(), b.lhs(), b.rhs()) else {
                    return (None, ETy::Unknown);
                };
                match op.as_str() {
                    "and" | "or" | "xor" => {
                        let (l, lt) = self.expr(&lhs, Some(Ty::Bool));
                        self.require_bool(&lhs, lt);
                        let (r, rt) = self.expr(&rhs, Some(Ty::Bool));
                        self.require_bool(&rhs, rt);
                        let x = l.zip(r).map(|(l, r)| {
                            let (l, r) = (Box::new(l), Box::new(r));
                            match op.as_str() {
                                "and" => Expr::And(l, r),
                                "or" => Expr::Or(l, r),
                                _ => Expr::Xor(l, r),
                            }
                        });
                        (x, ETy::Known(Ty::Bool))
                    }
                    _ => (self.comparison(b, &op, &lhs, &rhs), ETy::Known(Ty::Bool)),
                }
            }
        }
    }

    /// HG9106: an operand of `and or xor not`, or a condition, that is not BOOL.
    fn require_bool(&mut self, e: &ast::Expr, ty: ETy) {
        let shown = match ty {
            ETy::Known(Ty::Bool) | ETy::Unknown => return,
            ETy::Known(t) => ty_name(t),
            ETy::IntLit => "DINT".to_owned(),
        };
        let text = crate::rules::chart::collapsed(e.syntax());
        self.push(
            "HG9106",
            e.syntax().text_range(),
            format!("condition must be BOOL; {text} is {shown}"),
        );
    }

    fn comparison(
        &mut self,
        b: &ast::BinExpr,
        op: &str,
        lhs: &ast::Expr,
        rhs: &ast::Expr,
    ) -> Option<Expr> {
        let cmp = cmp_op(op)?;
        let range = b.syntax().text_range();
        let lt = self.static_ty(lhs);
        let rt = self.static_ty(rhs);
        // `Chart.state = Name` (also when `Chart.state` did not resolve: the name is then no
        // path of its own).
        let state = ETy::Known(Ty::OpState);
        let state_left = lt == state || (lt == ETy::Unknown && self.is_state_name(rhs));
        let state_right = rt == state || (rt == ETy::Unknown && self.is_state_name(lhs));
        if state_left || state_right {
            let (state_side, other) = if state_left { (lhs, rhs) } else { (rhs, lhs) };
            if !matches!(op, "=" | "<>") {
                self.push(
                    "HG9107",
                    range,
                    format!("'{op}' is not defined for operating state"),
                );
            }
            let (s, _) = self.expr(state_side, None);
            let value = Expr::Const(self.state_name(other)?);
            let s = s?;
            return Some(if state_left {
                Expr::Cmp(cmp, Box::new(s), Box::new(value))
            } else {
                Expr::Cmp(cmp, Box::new(value), Box::new(s))
            });
        }
        let (l, lt2) = self.expr(lhs, known(rt));
        let (r, rt2) = self.expr(rhs, known(lt2).or(known(lt)));
        let (a, c) = match (lt2, rt2) {
            (ETy::IntLit, ETy::IntLit) => (Ty::Dint, Ty::Dint),
            (ETy::Known(a), ETy::Known(c)) => (a, c),
            (ETy::Known(a), ETy::IntLit) => (a, Ty::Dint),
            (ETy::IntLit, ETy::Known(c)) => (Ty::Dint, c),
            _ => {
                return l
                    .zip(r)
                    .map(|(l, r)| Expr::Cmp(cmp, Box::new(l), Box::new(r)));
            }
        };
        let same = a == c || matches!((a, c), (Ty::String(_), Ty::String(_)));
        if !same {
            self.push(
                "HG9107",
                range,
                format!("cannot compare {} with {}", ty_name(a), ty_name(c)),
            );
            return None;
        }
        if !matches!(op, "=" | "<>") && matches!(a, Ty::Bool | Ty::String(_)) {
            let shown = if matches!(a, Ty::String(_)) {
                "STRING".to_owned()
            } else {
                ty_name(a)
            };
            self.push(
                "HG9107",
                range,
                format!("'{op}' is not defined for {shown}"),
            );
            return None;
        }
        l.zip(r)
            .map(|(l, r)| Expr::Cmp(cmp, Box::new(l), Box::new(r)))
    }

    /// Is the expression a bare name of an operating state that is no global symbol?
    fn is_state_name(&self, e: &ast::Expr) -> bool {
        match e {
            ast::Expr::TestPath(p) if p.address().is_none() && p.symbol().is_none() => {
                match p.segment_texts().as_slice() {
                    [(name, _)] => {
                        OpState::from_name(name).is_some() && self.r.index.symbol(name).is_none()
                    }
                    _ => false,
                }
            }
            _ => false,
        }
    }

    /// The operating state the other side of `Chart.state =` names (HG9108).
    fn state_name(&mut self, e: &ast::Expr) -> Option<Value> {
        let written = match e {
            ast::Expr::TestPath(p) if p.address().is_none() && p.symbol().is_none() => {
                match p.segment_texts().as_slice() {
                    [(name, _)] => Some(name.clone()),
                    _ => None,
                }
            }
            _ => None,
        };
        if let Some(state) = written.as_deref().and_then(OpState::from_name) {
            return Some(Value::OpState(state as u8));
        }
        let text = crate::rules::chart::collapsed(e.syntax());
        let range = e.syntax().text_range();
        let diag = Diag::new(
            "HG9108",
            self.loc(range),
            format!("'{text}' is not an operating state"),
        );
        let names: Vec<String> = OpState::ALL.iter().map(|s| s.name().to_owned()).collect();
        let diag = self.closest_fix(diag, range, &text, &names);
        self.diags.push(diag);
        None
    }

    /// A condition of `expect`/`until`: BOOL (HG9106); its paths are watched.
    fn condition(&mut self, e: &ast::Expr) -> Option<Expr> {
        self.watching = true;
        let (x, ty) = self.expr(e, Some(Ty::Bool));
        self.watching = false;
        self.require_bool(e, ty);
        x
    }

    /// ⌈d/Δ⌉ for a time constant (0 for a negative or zero time), and the constant as written.
    fn cycles(&self, lit: Option<ast::Literal>) -> (u64, String) {
        let Some(lit) = lit else {
            return (0, String::new());
        };
        let text = lit.text();
        let millis = match literal::check_literal(&text).map(|l| l.value) {
            Ok(LiteralValue::Duration { millis }) => millis,
            _ => 0,
        };
        let d = u64::try_from(millis).unwrap_or(0);
        (d.div_ceil(u64::from(self.cycle_ms.max(1))), text)
    }

    pub fn origin(&mut self, range: TextRange) -> Origin {
        match self.placer.as_mut() {
            Some(p) => p.lw.origin(self.file, self.item, range),
            None => Origin::NONE,
        }
    }

    /// Walks every statement; returns the lowered ones (none when only checking).
    pub fn statements(&mut self, test: &ast::Test) -> Vec<TestStmt> {
        let mut out = Vec::new();
        for stmt in test.statements() {
            // C1: a statement with a syntax error is not analysed.
            if crate::rules::has_error(stmt.syntax()) {
                continue;
            }
            let range = crate::rules::chart::without_semi(stmt.syntax());
            let kind = match &stmt {
                ast::TestStmt::Cycle(_) | ast::TestStmt::Run(_) => None,
                ast::TestStmt::Set(set) => self.set(set),
                ast::TestStmt::Step(step) => {
                    let cycles = step
                        .count()
                        .and_then(|c| c.text().parse::<u64>().ok())
                        .unwrap_or(1);
                    Some(TestStmtKind::Step { cycles })
                }
                ast::TestStmt::Wait(wait) => Some(TestStmtKind::Step {
                    cycles: self.cycles(wait.time()).0,
                }),
                ast::TestStmt::Until(until) => {
                    let cond = until.condition().and_then(|c| {
                        let range = c.syntax().text_range();
                        self.condition(&c).map(|x| (x, range))
                    });
                    let (cycles, within) = self.cycles(until.time());
                    match cond {
                        Some((cond, expr_range)) => {
                            let expr_origin = self.origin(expr_range);
                            Some(TestStmtKind::Until {
                                cond,
                                cycles,
                                within,
                                message: until.message().map(|m| m.value()),
                                expr_origin,
                            })
                        }
                        None => None,
                    }
                }
                ast::TestStmt::Expect(expect) => {
                    let cond = expect.condition().and_then(|c| {
                        let range = c.syntax().text_range();
                        self.condition(&c).map(|x| (x, range))
                    });
                    match cond {
                        Some((cond, expr_range)) => {
                            let expr_origin = self.origin(expr_range);
                            Some(TestStmtKind::Expect {
                                cond,
                                message: expect.message().map(|m| m.value()),
                                expr_origin,
                            })
                        }
                        None => None,
                    }
                }
                ast::TestStmt::Command(command) => self.command(command),
                ast::TestStmt::Confirm(confirm) => self.confirm(confirm),
                ast::TestStmt::Restart(restart) => Some(TestStmtKind::Restart {
                    cold: !restart.is_warm(),
                }),
            };
            if let Some(kind) = kind
                && self.placer.is_some()
            {
                let origin = self.origin(range);
                out.push(TestStmt { kind, origin });
            }
        }
        out
    }

    fn set(&mut self, set: &ast::TestSet) -> Option<TestStmtKind> {
        let target = set.target()?;
        let value = set.value()?;
        let res = self.resolve(&target)?;
        let target_text = compact(target.syntax());
        if let Err(reason) = &res.settable {
            self.push(
                "HG9104",
                target.syntax().text_range(),
                format!("'{target_text}' cannot be set: {reason}"),
            );
            return None;
        }
        let target_ty = res.ty.or(known(self.static_ty(&value)));
        // The target is used first (the watch list is in first-use order).
        self.watching = true;
        let path = self.lower_path(&target, &res, target_ty.unwrap_or(Ty::Bool));
        let (x, ety) = self.expr(&value, target_ty);
        self.watching = false;
        let value_ty = match ety {
            ETy::Known(v) => Some(v),
            ETy::IntLit => Some(Ty::Dint),
            ETy::Unknown => None,
        };
        let fits = match (target_ty, value_ty) {
            (Some(t), Some(v)) => {
                (t == v || matches!((t, v), (Ty::String(n), Ty::String(m)) if m <= n))
                    && !(matches!(value, ast::Expr::Literal(_)) && x.is_none())
            }
            _ => true,
        };
        if !fits && let (Some(t), Some(v)) = (target_ty, value_ty) {
            let value_text = crate::rules::chart::collapsed(value.syntax());
            self.push(
                "HG9105",
                value.syntax().text_range(),
                format!(
                    "cannot set {target_text} ({}) to {value_text} ({})",
                    ty_name(t),
                    ty_name(v)
                ),
            );
            return None;
        }
        Some(TestStmtKind::Set {
            target: path?,
            value: x?,
        })
    }

    fn command(&mut self, command: &ast::TestCommand) -> Option<TestStmtKind> {
        let chart = command.chart()?;
        let chart_name = chart.text();
        let range = chart.syntax().text_range();
        let position = self
            .r
            .scope
            .charts
            .iter()
            .position(|c| c.name.eq_ignore_ascii_case(&chart_name));
        let Some(c) = position else {
            let diag = match self.r.index.item(&chart_name) {
                Some(item) if item.kind == ItemKind::Chart => {
                    let name = item.name.clone();
                    self.not_run(range, &name)
                }
                _ => {
                    let diag = Diag::new(
                        "HG9109",
                        self.loc(range),
                        format!("'{chart_name}' is not a chart"),
                    );
                    let names: Vec<String> =
                        self.r.scope.charts.iter().map(|c| c.name.clone()).collect();
                    self.closest_fix(diag, range, &chart_name, &names)
                }
            };
            self.diags.push(diag);
            return None;
        };
        let word = command.command()?;
        let Some(cmd) = Command::from_name(&word.text()) else {
            let range = word.syntax().text_range();
            let diag = Diag::new(
                "HG9109",
                self.loc(range),
                format!("unknown command '{}'", word.text()),
            );
            let names: Vec<String> = Command::ALL.iter().map(|c| c.name().to_owned()).collect();
            let diag = self.closest_fix(diag, range, &word.text(), &names);
            self.diags.push(diag);
            return None;
        };
        let chart = *self.placer.as_ref()?.charts.get(c)?;
        Some(TestStmtKind::Command {
            chart,
            command: cmd,
        })
    }

    fn confirm(&mut self, confirm: &ast::TestConfirm) -> Option<TestStmtKind> {
        let path = confirm.path()?;
        let res = self.resolve(&path)?;
        let text = compact(path.syntax());
        let PathTarget::Step {
            chart,
            sequencer,
            step,
            member: StepMember::Active,
        } = res.target
        else {
            self.push(
                "HG9110",
                path.syntax().text_range(),
                format!("'{text}' is not a step"),
            );
            return None;
        };
        let chart = *self.placer.as_ref()?.charts.get(chart)?;
        Some(TestStmtKind::Confirm {
            chart,
            sequencer: sequencer as u32,
            step: step as u32,
            text,
        })
    }
}

/// The test of a program whose run list is lowered already.
pub(crate) fn lower(
    walker: &mut TestWalker<'_, '_, '_>,
    test: &ast::Test,
    run: Vec<RunEntry>,
) -> Test {
    let stmts = walker.statements(test);
    let origin_range = test
        .name()
        .and_then(|n| n.token())
        .map_or(test.syntax().text_range(), |t| t.text_range());
    let origin = walker.origin(origin_range);
    Test {
        name: walker.test_name.clone(),
        cycle_ms: walker.cycle_ms,
        run,
        stmts,
        watch: std::mem::take(&mut walker.watch),
        origin,
    }
}

/// Where `, Name` goes in the test's `run` statement.
fn run_insert(test: &ast::Test) -> Option<TextSize> {
    test.statements().find_map(|s| match s {
        ast::TestStmt::Run(run) => run.entries().last().map(|e| e.syntax().text_range().end()),
        _ => None,
    })
}

/// Δ in ms: the first `cycle` statement's whole milliseconds, else 10.
fn cycle_ms(test: &ast::Test) -> u32 {
    test.statements()
        .find_map(|s| match s {
            ast::TestStmt::Cycle(cycle) => cycle.time(),
            _ => None,
        })
        .and_then(
            |t| match literal::check_literal(&t.text()).map(|l| l.value) {
                Ok(LiteralValue::Duration { millis }) => u32::try_from(millis).ok(),
                _ => None,
            },
        )
        .filter(|&ms| ms > 0)
        .unwrap_or(10)
}
