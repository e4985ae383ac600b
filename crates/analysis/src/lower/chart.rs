//! Charts → [`higraph_runtime::program::Chart`]: variables and external references as cells,
//! `SFC.` flags, statements with their target types, qualifiers → actions, steps with their
//! decision candidates and transitions with predecessors and successors (`runtime.md` §4).
//! Operands are resolved by the chart rules' resolver (`rules::chart::operands`).

use std::collections::HashMap;

use higraph_runtime::program::{
    Action, ArithOp, Association, Chart, ChartTrans, ChartTransKind, CmpOp, Expr, FbCall, FbId,
    FbInstance, FbType, Path, PathKind, Place, Profile, Qualifier, Sequencer, SfcFlag, Statement,
    Step, StepIdx, StepMember, Stmt, Switching, TransIdx,
};
use higraph_runtime::value::{Ty, Value};
use higraph_syntax::literal::{self, LiteralClass};
use higraph_syntax::{SyntaxKind, TextRange, ast, ast::AstNode};

use super::build::Lowerer;
use super::values;
use crate::db::{self, File, ItemLoc};
use crate::rules::Ctx;
use crate::rules::chart::model::{Kind, Tree};
use crate::rules::chart::operands::{self, Target, Unresolved};
use crate::rules::chart::{ChartInfo, Scope, header_range};

/// The `SFC.` flag of a name.
pub(crate) fn sfc_flag(name: &str) -> Option<SfcFlag> {
    use SfcFlag::*;
    Some(match name.to_ascii_uppercase().as_str() {
        "IDLE" => Idle,
        "STARTING" => Starting,
        "RUN" => Run,
        "COMPLETING" => Completing,
        "ERROR" => Error,
        "COMPLETED" => Completed,
        "HOLDING" => Holding,
        "HELD" => Held,
        "RESUMING" => Resuming,
        "ABORTING" => Aborting,
        "ABORTED" => Aborted,
        "STOPPING" => Stopping,
        "STOPPED" => Stopped,
        _ => return None,
    })
}

/// The comparison of an operator as written.
pub(crate) fn cmp_op(op: &str) -> Option<CmpOp> {
    Some(match op {
        "=" => CmpOp::Eq,
        "<>" => CmpOp::Ne,
        "<" => CmpOp::Lt,
        ">" => CmpOp::Gt,
        "<=" => CmpOp::Le,
        ">=" => CmpOp::Ge,
        _ => return None,
    })
}

/// A node's text without white space.
pub(crate) fn compact(node: &higraph_syntax::SyntaxNode) -> String {
    node.descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .map(|t| t.text().to_owned())
        .collect()
}

struct ChartLowering<'l, 'a> {
    lw: &'l mut Lowerer<'a>,
    ctx: Ctx<'a>,
    scope: Scope,
    file: File,
    item: u32,
    var_cells: Vec<(u32, Ty)>,
    /// IEC charts (`docs/iec.md`): `Step.X`/`Step.T`, function block members and actions are
    /// nameable.
    iec: bool,
    /// The chart's index in `program.charts` (it is pushed when lowered).
    chart_index: u32,
    /// Function block instances by variable key.
    fbs: HashMap<String, (FbId, FbInstance)>,
    /// Steps by key: the first step of that name in the chart (sequencer, step).
    steps: HashMap<String, (u32, StepIdx)>,
    /// `action` members by key: their index in the chart's actions.
    action_names: HashMap<String, u32>,
}

impl ChartLowering<'_, '_> {
    fn origin(&mut self, range: TextRange) -> higraph_runtime::program::Origin {
        self.lw.origin(self.file, self.item, range)
    }

    /// Resolves a path: its kind and type (`None` when unknown, e.g. an external reference).
    fn path(&mut self, path: &ast::Path, hint: Option<Ty>) -> Option<Path> {
        if let Some((kind, ty)) = self.iec_path(path) {
            return Some(Path {
                text: compact(path.syntax()),
                ty,
                kind,
            });
        }
        let target = operands::resolve(
            &mut self.ctx,
            &mut self.scope,
            path,
            Unresolved::Operand,
            false,
        );
        self.ctx.out.diags.clear();
        let text = compact(path.syntax());
        let (kind, ty) = match target {
            Target::Var(i) => {
                let (cell, ty) = *self.var_cells.get(i)?;
                (PathKind::Place(Place::Cell(cell)), ty)
            }
            Target::Symbol { ty, address, .. } => (
                PathKind::Place(values::place(address.as_ref()?)?),
                ty.and_then(values::ty).unwrap_or(Ty::Bool),
            ),
            Target::Address(Some(a)) => (PathKind::Place(values::place(&a)?), values::ty(a.ty())?),
            Target::Sfc => {
                let flag = path.segments().nth(1).and_then(|n| sfc_flag(&n.text()));
                match flag {
                    Some(flag) => (PathKind::Sfc(flag), Ty::Bool),
                    None => (PathKind::Place(Place::Const(Value::Bool(false))), Ty::Bool),
                }
            }
            Target::External => {
                let key = crate::index::key(&text);
                let cell = match self.lw.externals.get(&key) {
                    Some(&cell) => cell,
                    None => {
                        let ty = hint.unwrap_or(Ty::Bool);
                        let cell = self.lw.cell(ty, None);
                        self.lw.externals.insert(key, cell);
                        cell
                    }
                };
                let ty = self.lw.program.cells[cell as usize].ty;
                (PathKind::Place(Place::Cell(cell)), ty)
            }
            // The operands of the IEC profile (function block members, step flags).
            Target::Address(None) | Target::Unresolved | Target::Iec(_) => return None,
        };
        Some(Path { text, ty, kind })
    }

    /// In an IEC chart, `Fb.Member` (a cell of the instance) and `Step.X` / `Step.T`.
    fn iec_path(&self, path: &ast::Path) -> Option<(PathKind, Ty)> {
        if !self.iec || path.address().is_some() || path.symbol().is_some() {
            return None;
        }
        let segments: Vec<String> = path.segments().map(|s| s.text()).collect();
        let [first, member] = segments.as_slice() else {
            return None;
        };
        let first = crate::index::key(first);
        if let Some((_, fb)) = self.fbs.get(&first) {
            let m = fb.ty.member(member)?;
            return Some((PathKind::Place(Place::Cell(fb.cell(m)?)), m.ty()));
        }
        let &(sequencer, step) = self.steps.get(&first)?;
        let (member, ty) = match member.to_ascii_uppercase().as_str() {
            "X" => (StepMember::Active, Ty::Bool),
            "T" => (StepMember::Time, Ty::Time),
            _ => return None,
        };
        Some((
            PathKind::Step {
                chart: self.chart_index,
                sequencer,
                step,
                member,
            },
            ty,
        ))
    }

    /// The type of an expression before lowering, `None` for an integer literal (it adapts)
    /// and unknown paths.
    fn static_ty(&mut self, e: &ast::Expr) -> Option<Ty> {
        match e {
            ast::Expr::Literal(lit) => {
                let lit = literal::check_literal(&lit.text()).ok()?;
                if lit.class == LiteralClass::Integer {
                    None
                } else {
                    values::literal_ty(&lit)
                }
            }
            ast::Expr::Path(path) => {
                if let Some((_, ty)) = self.iec_path(path) {
                    return Some(ty);
                }
                let target = operands::resolve(
                    &mut self.ctx,
                    &mut self.scope,
                    path,
                    Unresolved::Operand,
                    false,
                );
                self.ctx.out.diags.clear();
                match target {
                    Target::Var(i) => self.var_cells.get(i).map(|c| c.1),
                    Target::Symbol { ty, .. } => ty.and_then(values::ty),
                    Target::Address(Some(a)) => values::ty(a.ty()),
                    Target::Sfc => Some(Ty::Bool),
                    Target::External => {
                        let key = crate::index::key(&compact(path.syntax()));
                        self.lw
                            .externals
                            .get(&key)
                            .map(|&c| self.lw.program.cells[c as usize].ty)
                    }
                    _ => None,
                }
            }
            ast::Expr::Paren(p) => p.expr().and_then(|e| self.static_ty(&e)),
            ast::Expr::TestPath(_) => None,
            // Unary minus and arithmetic: the operands' type (TIME * n is TIME); depth bounded
            // by the parser's nesting limit.
            ast::Expr::Prefix(p) if p.op() == Some(ast::PrefixOp::Neg) => {
                p.operand().and_then(|e| self.static_ty(&e))
            }
            ast::Expr::Bin(b) if b.op().is_some_and(ast::BinOp::is_arithmetic) => {
                let l = b.lhs().and_then(|e| self.static_ty(&e));
                match l {
                    Some(ty) => Some(ty),
                    None => b.rhs().and_then(|e| self.static_ty(&e)),
                }
            }
            ast::Expr::Prefix(_) | ast::Expr::Bin(_) => Some(Ty::Bool),
        }
    }

    /// Lowers an expression; `hint` is the type the context expects (literal adaptation).
    fn expr(&mut self, e: &ast::Expr, hint: Option<Ty>) -> Option<Expr> {
        Some(match e {
            ast::Expr::Literal(lit) => {
                let lit = literal::check_literal(&lit.text()).ok()?;
                let ty = values::adapted_ty(&lit, hint)?;
                Expr::Const(values::value_in(&lit, ty)?)
            }
            ast::Expr::Path(path) => Expr::Read(self.path(path, hint)?),
            ast::Expr::TestPath(_) => return None,
            ast::Expr::Paren(p) => self.expr(&p.expr()?, hint)?,
            ast::Expr::Prefix(p) if p.op() == Some(ast::PrefixOp::Neg) => {
                Expr::Neg(Box::new(self.expr(&p.operand()?, hint)?))
            }
            ast::Expr::Prefix(p) => Expr::Not(Box::new(self.expr(&p.operand()?, Some(Ty::Bool))?)),
            ast::Expr::Bin(b) if b.op().is_some_and(ast::BinOp::is_arithmetic) => {
                let op = match b.op()? {
                    ast::BinOp::Add => ArithOp::Add,
                    ast::BinOp::Sub => ArithOp::Sub,
                    ast::BinOp::Mul => ArithOp::Mul,
                    ast::BinOp::Div => ArithOp::Div,
                    _ => ArithOp::Mod,
                };
                let (lhs, rhs) = (b.lhs()?, b.rhs()?);
                let lt = self.static_ty(&lhs);
                let rt = self.static_ty(&rhs);
                // An integer constant adopts the other operand's type (`docs/iec.md` §4); the
                // factor of `TIME * n` / `TIME / n` is a DINT when it is a constant.
                let scaled = lt == Some(Ty::Time) && matches!(op, ArithOp::Mul | ArithOp::Div);
                let ty = lt.or(rt).or(hint);
                let l = self.expr(&lhs, ty)?;
                let r = if scaled {
                    self.expr(&rhs, rt.or(Some(Ty::Dint)))?
                } else {
                    self.expr(&rhs, rt.or(ty))?
                };
                Expr::Arith(op, Box::new(l), Box::new(r))
            }
            ast::Expr::Bin(b) => {
                let op = b.op_text()?;
                let (lhs, rhs) = (b.lhs()?, b.rhs()?);
                match op.as_str() {
                    "and" | "or" | "xor" => {
                        let l = Box::new(self.expr(&lhs, Some(Ty::Bool))?);
                        let r = Box::new(self.expr(&rhs, Some(Ty::Bool))?);
                        match op.as_str() {
                            "and" => Expr::And(l, r),
                            "or" => Expr::Or(l, r),
                            _ => Expr::Xor(l, r),
                        }
                    }
                    cmp => {
                        let cmp = cmp_op(cmp)?;
                        let lt = self.static_ty(&lhs);
                        let rt = self.static_ty(&rhs);
                        let l = self.expr(&lhs, rt)?;
                        let r = self.expr(&rhs, lt.or_else(|| expr_ty(&l)))?;
                        Expr::Cmp(cmp, Box::new(l), Box::new(r))
                    }
                }
            }
        })
    }

    /// A time value of a step (`min`, `max`, a qualifier's time).
    fn time(&mut self, operand: &ast::Operand) -> Option<Expr> {
        match operand {
            ast::Operand::Literal(lit) => {
                let lit = literal::check_literal(&lit.text()).ok()?;
                Some(Expr::Const(values::value_in(&lit, Ty::Time)?))
            }
            ast::Operand::Path(path) => Some(Expr::Read(self.path(path, Some(Ty::Time))?)),
            _ => None,
        }
    }

    /// The statements of a node's body.
    fn statements(&mut self, node: &higraph_syntax::SyntaxNode) -> Vec<Statement> {
        self.stmt_list(crate::rules::chart::body_children(node).filter_map(ast::Stmt::cast))
    }

    /// Lowers statements; recurses into `IF`/`CASE` bodies, whose depth the parser's nesting
    /// limit (HG0012) bounds. A statement that does not lower (an unknown path) is left out.
    fn stmt_list(&mut self, stmts: impl Iterator<Item = ast::Stmt>) -> Vec<Statement> {
        let mut out = Vec::new();
        for stmt in stmts {
            if let Some(s) = self.stmt(&stmt) {
                out.push(s);
            }
        }
        out
    }

    fn stmt(&mut self, stmt: &ast::Stmt) -> Option<Statement> {
        let range = crate::rules::chart::without_semi(stmt.syntax());
        match stmt {
            ast::Stmt::Assignment(assignment) => {
                let target = assignment.target()?;
                let value = assignment.value()?;
                let hint = self.static_ty(&value);
                let path = self.path(&target, hint)?;
                let place = match path.kind {
                    PathKind::Place(place) => place,
                    // Writes to `SFC.` paths (and step values) are ignored.
                    _ => Place::Const(Value::Bool(false)),
                };
                let value = self.expr(&value, Some(path.ty))?;
                let origin = self.origin(range);
                Some(Statement::Assign(Stmt {
                    target: place,
                    ty: path.ty,
                    value,
                    origin,
                }))
            }
            ast::Stmt::If(s) => {
                let origin = self.origin(range);
                let mut arms = Vec::new();
                let cond = self.expr(&s.condition()?, Some(Ty::Bool))?;
                arms.push((cond, self.stmt_list(s.then_statements())));
                for elsif in s.elsifs() {
                    let Some(cond) = elsif
                        .condition()
                        .and_then(|c| self.expr(&c, Some(Ty::Bool)))
                    else {
                        continue;
                    };
                    arms.push((cond, self.stmt_list(elsif.statements())));
                }
                let else_ = s
                    .else_clause()
                    .map(|e| self.stmt_list(e.statements()))
                    .unwrap_or_default();
                Some(Statement::If {
                    arms,
                    else_,
                    origin,
                })
            }
            ast::Stmt::Case(s) => {
                let origin = self.origin(range);
                let sel = s.selector()?;
                let hint = self.static_ty(&sel).or(Some(Ty::Dint));
                let selector = self.expr(&sel, hint)?;
                let mut arms = Vec::new();
                for arm in s.arms() {
                    let labels: Vec<(i64, i64)> = arm
                        .labels()
                        .filter_map(|l| Some((l.low()?, l.high()?)))
                        .collect();
                    arms.push((labels, self.stmt_list(arm.statements())));
                }
                let else_ = s
                    .else_clause()
                    .map(|e| self.stmt_list(e.statements()))
                    .unwrap_or_default();
                Some(Statement::Case {
                    selector,
                    arms,
                    else_,
                    origin,
                })
            }
            ast::Stmt::Call(call) => {
                let callee = crate::index::key(&call.callee()?.text());
                let (fb, ty) = self.fbs.get(&callee).map(|(id, fb)| (*id, fb.ty))?;
                let origin = self.origin(range);
                let mut inputs = Vec::new();
                let mut outputs = Vec::new();
                for arg in call.args() {
                    let Some(member) = arg.formal().and_then(|f| ty.member(&f.text())) else {
                        continue;
                    };
                    if arg.is_output() {
                        let Some(path) =
                            arg.target().and_then(|t| self.path(&t, Some(member.ty())))
                        else {
                            continue;
                        };
                        if let PathKind::Place(place) = path.kind {
                            outputs.push((member, place, path.ty));
                        }
                    } else if let Some(value) =
                        arg.value().and_then(|v| self.expr(&v, Some(member.ty())))
                    {
                        inputs.push((member, value));
                    }
                }
                Some(Statement::Call(FbCall {
                    fb,
                    inputs,
                    outputs,
                    origin,
                }))
            }
        }
    }

    /// The conditions of a node's body, in order.
    fn conditions(&mut self, node: &higraph_syntax::SyntaxNode) -> Vec<Expr> {
        crate::rules::chart::body_children(node)
            .filter_map(ast::Condition::cast)
            .filter_map(|c| c.expr())
            .filter_map(|e| self.expr(&e, Some(Ty::Bool)))
            .collect()
    }
}

/// Expressions that are certainly BOOL, or a read's type.
fn expr_ty(e: &Expr) -> Option<Ty> {
    match e {
        Expr::Const(v) => Some(v.ty()),
        Expr::Read(p) => Some(p.ty),
        _ => Some(Ty::Bool),
    }
}

fn qualifier(text: &str) -> Option<Qualifier> {
    Some(match text.to_ascii_uppercase().as_str() {
        "N" => Qualifier::N,
        "S" => Qualifier::S,
        "R" => Qualifier::R,
        "P" => Qualifier::P,
        "L" => Qualifier::L,
        "D" => Qualifier::D,
        "SD" => Qualifier::Sd,
        "DS" => Qualifier::Ds,
        "SL" => Qualifier::Sl,
        "P1" => Qualifier::P1,
        "P0" => Qualifier::P0,
        "DL" => Qualifier::Dl,
        _ => return None,
    })
}

impl Lowerer<'_> {
    /// Lowers a chart item; its index in `program.charts`.
    pub fn chart(&mut self, file: File, item: u32) -> Option<u32> {
        let loc = ItemLoc::new(self.db, file, item);
        let root = db::item_root(self.db, loc)?;
        let ast::Item::Chart(chart) = ast::Item::cast(root)? else {
            return None;
        };
        let name = chart.name()?.text();
        let mut ctx = Ctx::for_item(self.db, self.ws, loc);
        let info = ChartInfo {
            name: name.clone(),
            is_type: chart.is_type(),
            chart: chart.clone(),
        };
        let vars = crate::rules::chart::decls::declare(&mut ctx, &info);
        ctx.out.diags.clear();

        let mut decl_nodes: HashMap<String, ast::VarDecl> = HashMap::new();
        for (_, decl) in crate::rules::decls::declarations(chart.var_sections()) {
            if let Some(n) = decl.name() {
                decl_nodes
                    .entry(crate::index::key(&n.text()))
                    .or_insert(decl);
            }
        }
        let iec = chart.profile() == ast::Profile::Iec;
        let mut var_cells = Vec::with_capacity(vars.len());
        let mut cell_names = Vec::new();
        let mut fbs: HashMap<String, (FbId, FbInstance)> = HashMap::new();
        let mut fb_list: Vec<FbInstance> = Vec::new();
        for var in &vars {
            let ty = var.ty.and_then(values::ty).unwrap_or(Ty::Bool);
            let key = crate::index::key(&var.name);
            // a standard function block instance (IEC): cells for its members and state
            let fb_ty = decl_nodes
                .get(&key)
                .and_then(|d| d.ty())
                .and_then(|t| t.name())
                .and_then(|n| FbType::from_name(n.text()));
            if let (true, false, Some(fb_ty)) = (iec, var.duplicate, fb_ty) {
                let members = fb_ty.members().map(|m| self.cell(m.ty(), None)).collect();
                let state = fb_ty
                    .state_tys()
                    .iter()
                    .map(|t| self.cell(*t, None))
                    .collect();
                let fb = FbInstance {
                    name: var.name.clone(),
                    ty: fb_ty,
                    members,
                    state,
                };
                fbs.insert(key.clone(), (fb_list.len() as FbId, fb.clone()));
                fb_list.push(fb);
            }
            let init = if var.duplicate {
                None
            } else {
                decl_nodes
                    .get(&key)
                    .and_then(|d| d.initial_value())
                    .and_then(|v| v.literal())
                    .and_then(|l| literal::check_literal(&l.text()).ok())
                    .and_then(|l| values::value_in(&l, ty))
            };
            let cell = self.cell(ty, init);
            var_cells.push((cell, ty));
            if !var.duplicate {
                cell_names.push((var.name.clone(), cell));
            }
        }
        // Steps by name for `Step.X`/`Step.T` (IEC): numbered as `sequencer` numbers them.
        let mut steps = HashMap::new();
        if iec {
            let mut seen = std::collections::HashSet::new();
            let mut seq_index = 0u32;
            for sequencer in chart.sequencers() {
                let Some(seq_name) = sequencer.name().map(|n| n.text()) else {
                    continue;
                };
                if !seen.insert(crate::index::key(&seq_name)) {
                    continue;
                }
                let tree = Tree::build(&sequencer);
                let mut names = std::collections::HashSet::new();
                let mut index: StepIdx = 0;
                for elem in &tree.elems {
                    let key = crate::index::key(elem.label());
                    if elem.kind == Kind::Step && names.insert(key.clone()) {
                        steps.entry(key).or_insert((seq_index, index));
                        index += 1;
                    }
                }
                seq_index += 1;
            }
        }
        let chart_index = self.program.charts.len() as u32;
        let scope = Scope::new(info, vars);
        let mut cl = ChartLowering {
            lw: self,
            ctx,
            scope,
            file,
            item,
            var_cells,
            iec,
            chart_index,
            fbs,
            steps,
            action_names: HashMap::new(),
        };

        let mut out = Chart {
            name,
            vars: cell_names,
            mode_auto: false,
            switching: Switching::T,
            cyclic: false,
            time_monitoring: false,
            autostart: false,
            sequencers: Vec::new(),
            actions: Vec::new(),
            profile: if iec { Profile::Iec } else { Profile::Pcs7 },
            fbs: fb_list,
        };
        // `action` members (IEC), text order, before the variable actions of the steps: a
        // hidden BOOL cell holds the action's activity; the bodies follow once all are named.
        let members: Vec<ast::ChartAction> = if iec {
            chart.actions().collect()
        } else {
            Vec::new()
        };
        let mut bodies = Vec::new();
        for action in &members {
            let Some(name) = action.name().map(|n| n.text()) else {
                continue;
            };
            let key = crate::index::key(&name);
            if cl.action_names.contains_key(&key) {
                continue;
            }
            let cell = cl.lw.cell(Ty::Bool, None);
            cl.action_names.insert(key, out.actions.len() as u32);
            bodies.push((out.actions.len(), action.clone()));
            out.actions.push(Action {
                name,
                place: Place::Cell(cell),
                body: Some(Vec::new()),
            });
        }
        for (index, action) in bodies {
            let body = cl.statements(action.syntax());
            out.actions[index].body = Some(body);
        }
        for prop in chart.props() {
            let (Some(keyword), Some(value)) = (prop.keyword(), prop.value()) else {
                continue;
            };
            let value = value.text().to_ascii_lowercase();
            match (keyword.kind(), value.as_str()) {
                (SyntaxKind::MODE_KW, "auto") => out.mode_auto = true,
                (SyntaxKind::MODE_KW, "manual") => out.mode_auto = false,
                (SyntaxKind::SWITCHING_KW, v) => {
                    out.switching = match v {
                        "b" => Switching::B,
                        "t_or_b" => Switching::TOrB,
                        "t_and_b" => Switching::TAndB,
                        "step" => Switching::Step,
                        _ => Switching::T,
                    }
                }
                (SyntaxKind::RUN_KW, "cyclic") => out.cyclic = true,
                (SyntaxKind::RUN_KW, "time_monitoring") => out.time_monitoring = true,
                (SyntaxKind::RUN_KW, "autostart") => out.autostart = true,
                _ => {}
            }
        }
        let mut seen = std::collections::HashSet::new();
        for sequencer in chart.sequencers() {
            let Some(seq_name) = sequencer.name().map(|n| n.text()) else {
                continue;
            };
            if !seen.insert(crate::index::key(&seq_name)) {
                continue;
            }
            let (lowered, _steps) = cl.sequencer(&sequencer, seq_name.clone(), &mut out.actions);
            out.sequencers.push(lowered);
        }
        cl.lw.program.charts.push(out);
        Some((cl.lw.program.charts.len() - 1) as u32)
    }
}

impl ChartLowering<'_, '_> {
    #[allow(clippy::type_complexity)]
    fn sequencer(
        &mut self,
        sequencer: &ast::Sequencer,
        name: String,
        actions: &mut Vec<Action>,
    ) -> (Sequencer, Vec<(String, TextRange)>) {
        let prio = sequencer
            .prio()
            .and_then(|p| p.value())
            .and_then(|v| v.text().parse::<u32>().ok())
            .unwrap_or(1);
        let start = sequencer
            .start()
            .map(|s| self.conditions(s.syntax()))
            .unwrap_or_default();
        let pre = sequencer
            .pre()
            .map(|p| self.statements(p.syntax()))
            .unwrap_or_default();
        let post = sequencer
            .post()
            .map(|p| self.statements(p.syntax()))
            .unwrap_or_default();
        let tree = Tree::build(sequencer);
        let nav = Nav::new(&tree);
        // Steps by name (the first of each, C3), for jump and loop targets.
        let mut steps_by_name: HashMap<String, usize> = HashMap::new();
        for (id, elem) in tree.elems.iter().enumerate() {
            if elem.kind == Kind::Step {
                steps_by_name
                    .entry(crate::index::key(elem.label()))
                    .or_insert(id);
            }
        }
        // Steps (the first of each name, C3) and chart transitions, in text order.
        let mut step_of: HashMap<usize, StepIdx> = HashMap::new();
        let mut trans_of: HashMap<usize, TransIdx> = HashMap::new();
        let mut step_names = std::collections::HashSet::new();
        let mut trans_names = std::collections::HashSet::new();
        for (id, elem) in tree.elems.iter().enumerate() {
            let key = crate::index::key(elem.label());
            match elem.kind {
                Kind::Step if step_names.insert(key.clone()) => {
                    step_of.insert(id, step_of.len() as StepIdx);
                }
                k if k.is_chart_transition() && trans_names.insert(key) => {
                    trans_of.insert(id, trans_of.len() as TransIdx);
                }
                _ => {}
            }
        }
        let mut steps: Vec<Step> = Vec::with_capacity(step_of.len());
        let mut names = Vec::with_capacity(step_of.len());
        let mut transitions: Vec<ChartTrans> = Vec::with_capacity(trans_of.len());
        for (id, elem) in tree.elems.iter().enumerate() {
            match &elem.node {
                ast::SeqElement::Step(step) if step_of.contains_key(&id) => {
                    names.push((
                        elem.label().to_owned(),
                        elem.name_range.unwrap_or(elem.header),
                    ));
                    let lowered = self.step(step, elem.label(), elem.header, actions);
                    steps.push(lowered);
                }
                ast::SeqElement::Trans(_) | ast::SeqElement::Jump(_) | ast::SeqElement::Loop(_)
                    if trans_of.contains_key(&id) =>
                {
                    let (kind, from, to) = match elem.kind {
                        Kind::Trans => (
                            ChartTransKind::Trans,
                            predecessors(&tree, &nav, id, &step_of),
                            successors(&tree, &nav, id, &step_of),
                        ),
                        kind => {
                            // IEC: a jump that opens an `alt` branch leaves the step before
                            // the `alt`; a jump after a parallel leaves its last steps
                            let from = if self.iec {
                                predecessors(&tree, &nav, id, &step_of)
                            } else {
                                nav.previous_unit(&tree, id)
                                    .and_then(|s| step_of.get(&s).copied())
                                    .into_iter()
                                    .collect()
                            };
                            let to = elem
                                .target
                                .as_ref()
                                .and_then(|(t, _)| {
                                    steps_by_name.get(&crate::index::key(t)).copied()
                                })
                                .and_then(|s| step_of.get(&s).copied())
                                .into_iter()
                                .collect();
                            let kind = if kind == Kind::Jump {
                                ChartTransKind::Jump
                            } else {
                                ChartTransKind::Loop
                            };
                            (kind, from, to)
                        }
                    };
                    let conditions = self.conditions(elem.node.syntax());
                    let origin = self.origin(header_range(elem.node.syntax()));
                    transitions.push(ChartTrans {
                        kind,
                        name: elem.name.clone(),
                        from,
                        to,
                        conditions,
                        origin,
                    });
                }
                _ => {}
            }
        }
        // Decision candidates per step.
        for (id, elem) in tree.elems.iter().enumerate() {
            let Some(&s) = step_of.get(&id) else { continue };
            if elem.kind != Kind::Step {
                continue;
            }
            let mut candidates = Vec::new();
            // IEC: a step that ends an `alt` branch with a jump does not converge
            let ends_branch_with_jump = self.iec
                && nav.next_in_list(&tree, id).is_none()
                && nav.attachments(&tree, id).next().is_some();
            let next = if ends_branch_with_jump {
                None
            } else {
                nav.next_unit(&tree, id)
            };
            if let Some(next) = next {
                match tree.elems[next].kind {
                    Kind::Trans => candidates.extend(trans_of.get(&next).copied()),
                    Kind::Alt => {
                        for &branch in &tree.elems[next].branches {
                            // IEC: a branch may open with a jump (a transition with a target)
                            let opening = tree.lists[branch].elems.first().copied();
                            if let (true, Some(first)) = (self.iec, opening)
                                && tree.elems[first].kind.is_attachment()
                            {
                                candidates.extend(trans_of.get(&first).copied());
                            } else if let Some(first) = Nav::first_unit(&tree, branch)
                                && tree.elems[first].kind == Kind::Trans
                            {
                                candidates.extend(trans_of.get(&first).copied());
                            }
                        }
                    }
                    _ => {}
                }
            }
            for attachment in nav.attachments(&tree, id) {
                candidates.extend(trans_of.get(&attachment).copied());
            }
            if let Some(step) = steps.get_mut(s as usize) {
                step.candidates = candidates;
            }
        }
        (
            Sequencer {
                name,
                prio,
                start,
                pre,
                post,
                steps,
                transitions,
            },
            names,
        )
    }

    fn step(
        &mut self,
        step: &ast::Step,
        name: &str,
        header: TextRange,
        actions: &mut Vec<Action>,
    ) -> Step {
        let origin = self.origin(header);
        let mut out = Step {
            name: name.to_owned(),
            init: Vec::new(),
            run: Vec::new(),
            term: Vec::new(),
            qualifiers: Vec::new(),
            min: None,
            max: None,
            confirm: step.confirm().is_some(),
            candidates: Vec::new(),
            origin,
        };
        for item in crate::rules::chart::body_children(step.syntax()) {
            match item.kind() {
                SyntaxKind::STEP_PHASE => {
                    let Some(phase) = ast::StepPhase::cast(item) else {
                        continue;
                    };
                    let kind = phase.keyword().map(|k| k.kind());
                    let stmts = self.statements(phase.syntax());
                    match kind {
                        Some(SyntaxKind::INIT_KW) => out.init.extend(stmts),
                        Some(SyntaxKind::RUN_KW) => out.run.extend(stmts),
                        Some(SyntaxKind::TERM_KW) => out.term.extend(stmts),
                        _ => {}
                    }
                }
                SyntaxKind::QUALIFIER_ACTION => {
                    let Some(action) = ast::QualifierAction::cast(item) else {
                        continue;
                    };
                    let Some(q) = action.qualifier().and_then(|q| qualifier(q.text())) else {
                        continue;
                    };
                    let mut operands = action.operands();
                    let Some(ast::Operand::Path(path)) = operands.next() else {
                        continue;
                    };
                    let time = operands.next().and_then(|t| self.time(&t));
                    // an `action` member named by the qualifier (IEC)
                    let named = match path.segments().collect::<Vec<_>>().as_slice() {
                        [one] if path.address().is_none() && path.symbol().is_none() => self
                            .action_names
                            .get(&crate::index::key(&one.text()))
                            .copied(),
                        _ => None,
                    };
                    if let Some(index) = named {
                        out.qualifiers.push(Association {
                            qualifier: q,
                            action: index,
                            time,
                        });
                        continue;
                    }
                    let Some(lowered) = self.path(&path, Some(Ty::Bool)) else {
                        continue;
                    };
                    let PathKind::Place(place) = lowered.kind else {
                        continue;
                    };
                    let index = match actions
                        .iter()
                        .position(|a| a.body.is_none() && a.place == place)
                    {
                        Some(i) => i,
                        None => {
                            actions.push(Action {
                                name: lowered.text,
                                place,
                                body: None,
                            });
                            actions.len() - 1
                        }
                    };
                    out.qualifiers.push(Association {
                        qualifier: q,
                        action: index as u32,
                        time,
                    });
                }
                SyntaxKind::STEP_TIME => {
                    let Some(time) = ast::StepTime::cast(item) else {
                        continue;
                    };
                    let is_min = time
                        .keyword()
                        .is_some_and(|k| k.kind() == SyntaxKind::MIN_KW);
                    let value = time.value().and_then(|v| self.time(&v));
                    let slot = if is_min { &mut out.min } else { &mut out.max };
                    if slot.is_none() {
                        *slot = value;
                    }
                }
                _ => {}
            }
        }
        out
    }
}

/// The last steps of a step-kind unit: the step itself, or the last steps of every branch of
/// a parallel. Depth is bounded by the parser's nesting limit.
fn last_steps(tree: &Tree, unit: usize, out: &mut Vec<usize>) {
    match tree.elems[unit].kind {
        Kind::Step => out.push(unit),
        Kind::Parallel => {
            for &branch in &tree.elems[unit].branches {
                if let Some(last) = Nav::last_unit(tree, branch) {
                    last_steps(tree, last, out);
                }
            }
        }
        _ => {}
    }
}

/// The steps a `trans` leaves: the step-kind unit before it (the last steps of a parallel); at
/// the start of an `alt` branch, the unit before the `alt`.
fn predecessors(
    tree: &Tree,
    nav: &Nav,
    trans: usize,
    step_of: &HashMap<usize, StepIdx>,
) -> Vec<StepIdx> {
    let mut current = trans;
    // Bounded by the nesting depth: each round moves one `alt` outwards.
    for _ in 0..=tree.lists.len() {
        match nav.previous_unit(tree, current) {
            Some(unit) => {
                let mut steps = Vec::new();
                last_steps(tree, unit, &mut steps);
                return steps
                    .iter()
                    .filter_map(|s| step_of.get(s).copied())
                    .collect();
            }
            None => match tree.lists[tree.elems[current].list].owner {
                Some(owner) if tree.elems[owner].kind == Kind::Alt => current = owner,
                _ => return Vec::new(),
            },
        }
    }
    Vec::new()
}

/// The steps a `trans` activates: the first steps of the unit after it (in an `alt` branch,
/// the next unit of the branch or the unit after the `alt`).
fn successors(
    tree: &Tree,
    nav: &Nav,
    trans: usize,
    step_of: &HashMap<usize, StepIdx>,
) -> Vec<StepIdx> {
    let mut steps = Vec::new();
    if let Some(next) = nav.next_unit(tree, trans) {
        Nav::first_steps(tree, next, &mut steps);
    }
    steps
        .iter()
        .filter_map(|s| step_of.get(s).copied())
        .collect()
}

/// Where each element stands in its list, so that the neighbours of an element cost their own
/// distance, not the list's length (the tree's own helpers search the list).
struct Nav {
    pos: Vec<usize>,
}

impl Nav {
    fn new(tree: &Tree) -> Nav {
        let mut pos = vec![0; tree.elems.len()];
        for list in &tree.lists {
            for (i, &e) in list.elems.iter().enumerate() {
                pos[e] = i;
            }
        }
        Nav { pos }
    }

    /// The next unit after `elem`: in its list, else after the enclosing `parallel`/`alt`
    /// (bounded by the nesting depth).
    fn next_unit(&self, tree: &Tree, elem: usize) -> Option<usize> {
        let mut current = elem;
        for _ in 0..=tree.lists.len() {
            let list = &tree.lists[tree.elems[current].list];
            let next = list.elems[self.pos[current] + 1..]
                .iter()
                .copied()
                .find(|&e| !tree.elems[e].kind.is_attachment());
            match (next, list.owner) {
                (Some(next), _) => return Some(next),
                (None, Some(owner)) => current = owner,
                (None, None) => return None,
            }
        }
        None
    }

    /// The next unit after `elem` in its own list.
    fn next_in_list(&self, tree: &Tree, elem: usize) -> Option<usize> {
        let list = &tree.lists[tree.elems[elem].list];
        list.elems[self.pos[elem] + 1..]
            .iter()
            .copied()
            .find(|&e| !tree.elems[e].kind.is_attachment())
    }

    /// The unit before `elem` in its list.
    fn previous_unit(&self, tree: &Tree, elem: usize) -> Option<usize> {
        let list = &tree.lists[tree.elems[elem].list];
        list.elems[..self.pos[elem]]
            .iter()
            .rev()
            .copied()
            .find(|&e| !tree.elems[e].kind.is_attachment())
    }

    /// The jumps and loops right after `elem`.
    fn attachments<'t>(&self, tree: &'t Tree, elem: usize) -> impl Iterator<Item = usize> + 't {
        let list = &tree.lists[tree.elems[elem].list];
        list.elems[self.pos[elem] + 1..]
            .iter()
            .copied()
            .take_while(|&e| tree.elems[e].kind.is_attachment())
    }

    /// The first unit of a list.
    fn first_unit(tree: &Tree, list: usize) -> Option<usize> {
        tree.lists[list]
            .elems
            .iter()
            .copied()
            .find(|&e| !tree.elems[e].kind.is_attachment())
    }

    /// The last unit of a list.
    fn last_unit(tree: &Tree, list: usize) -> Option<usize> {
        tree.lists[list]
            .elems
            .iter()
            .rev()
            .copied()
            .find(|&e| !tree.elems[e].kind.is_attachment())
    }

    /// The first steps of a step-kind unit (a step, or every branch's first steps of a
    /// parallel; depth bounded by the parser's nesting limit).
    fn first_steps(tree: &Tree, unit: usize, out: &mut Vec<usize>) {
        match tree.elems[unit].kind {
            Kind::Step => out.push(unit),
            Kind::Parallel => {
                for &branch in &tree.elems[unit].branches {
                    if let Some(first) = Nav::first_unit(tree, branch)
                        && tree.elems[first].kind.is_step_kind()
                    {
                        Nav::first_steps(tree, first, out);
                    }
                }
            }
            _ => {}
        }
    }
}
