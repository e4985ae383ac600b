//! The charts of a build → one PLCopen TC6 XML 2.01 document (`charts.xml`, `export.md` §4).
//!
//! Each chart is read from its syntax tree (the element tree of `rules::chart::model`, the
//! operand resolver of `rules::chart::operands`) into the plain model of
//! `higraph_export::plcopen`, which lays it out and writes the XML. How the chart's notions
//! become IEC ones (and what cannot) is described in `docs/build.md`, "Charts as PLCopen XML";
//! in short:
//!
//! * `in`/`out`/`in_out`/`stat` → `inputVars`/`outputVars`/`inOutVars`/`localVars`.
//! * Global symbols → `externalVars` of the POU and `globalVars` (with their direct address,
//!   `%IX1.0`) of one configuration `Charts`; absolute operands → direct addresses in ST
//!   (`%IX1.0`, `%MW10`); as an action operand an address becomes a global variable named
//!   after it (`QX1_0 AT %QX1.0`), since an action must name a variable. DB and local data
//!   addresses have no IEC form: a global variable without address named after them.
//! * `SFC.<flag>` (the PCS 7 operating state) → BOOL input `SFC_<flag>`, set by the caller.
//! * One sequencer: its start step is the initial step. Several: a common initial step `Idle`,
//!   a selection divergence with one branch per sequencer ordered by `prio` (then text order),
//!   its start condition as the branch's first transition, and after its end step a `TRUE`
//!   transition jumping back to `Idle`.
//! * `jump`/`loop` → a selection divergence after the step: the normal successor first (or the
//!   branches of a following `alt`), then the jumps and loops in text order, each a transition
//!   and a jump step.

use std::collections::{HashMap, HashSet};

use higraph_export::plcopen::{
    ActionAssoc, ActionBody, Element, IecType, NamedAction, Pou, Project, Qualifier, Step,
    Transition, Variable,
};
use higraph_syntax::{
    SyntaxKind,
    ast::{self, AstNode},
};

use crate::address::{Address, Area, Size};
use crate::db::{self, File, ItemLoc, Workspace};
use crate::lang::{Section, Type};
use crate::rules::Ctx;
use crate::rules::chart::model::{Kind, ListId, Tree};
use crate::rules::chart::operands::{self, Target, Unresolved};
use crate::rules::chart::{ChartInfo, Scope, body_children};

/// Deeper nesting of branches than this is not exported (the parser's limit is far below).
const MAX_DEPTH: usize = 200;

/// The document for the charts `(file, item)`, in the given order. UTF-8 XML.
pub(super) fn charts_xml(
    db: &dyn salsa::Database,
    ws: Workspace,
    charts: &[(File, u32)],
) -> Vec<u8> {
    higraph_export::plcopen::write(&charts_project(db, ws, charts))
}

/// The model of the document (for tests and for [`charts_xml`]).
pub(crate) fn charts_project(
    db: &dyn salsa::Database,
    ws: Workspace,
    charts: &[(File, u32)],
) -> Project {
    let mut globals = Globals::default();
    let mut project = Project::default();
    for &(file, item) in charts {
        if let Some(pou) = chart_pou(db, ws, file, item, &mut globals) {
            project.pous.push(pou);
        }
    }
    project.globals = globals.vars;
    project
}

/// The global variables of the document: one per symbol (or address without an IEC form),
/// named once for every POU.
#[derive(Default)]
struct Globals {
    vars: Vec<Variable>,
    /// Symbol key (or address text) → index in `vars`.
    by_key: HashMap<String, usize>,
    names: HashSet<String>,
}

impl Globals {
    fn get(
        &mut self,
        key: String,
        wanted: &str,
        ty: IecType,
        address: Option<String>,
        documentation: Option<String>,
    ) -> &Variable {
        if let Some(&i) = self.by_key.get(&key) {
            return &self.vars[i];
        }
        let name = unique(&identifier(wanted), &mut self.names);
        self.vars.push(Variable {
            name,
            ty,
            address,
            initial: None,
            documentation,
        });
        self.by_key.insert(key, self.vars.len() - 1);
        &self.vars[self.vars.len() - 1]
    }
}

/// An IEC identifier for a name: letters, digits and single `_`, not starting with a digit.
fn identifier(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars() {
        let c = if c.is_ascii_alphanumeric() { c } else { '_' };
        if c == '_' && out.ends_with('_') {
            continue;
        }
        out.push(c);
    }
    let trimmed = out.trim_end_matches('_');
    let mut out = trimmed.to_owned();
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        out.insert_str(0, "S_");
    }
    out
}

/// `wanted`, or `wanted_2`, `wanted_3`, ... whichever is free (case-insensitively); marks it
/// taken.
fn unique(wanted: &str, taken: &mut HashSet<String>) -> String {
    if taken.insert(wanted.to_ascii_uppercase()) {
        return wanted.to_owned();
    }
    for n in 2.. {
        let candidate = format!("{wanted}_{n}");
        if taken.insert(candidate.to_ascii_uppercase()) {
            return candidate;
        }
    }
    unreachable!("an unbounded range yields a free name")
}

fn iec_type(ty: Option<Type>) -> IecType {
    match ty {
        Some(Type::Bool) | None => IecType::Bool,
        Some(Type::Byte) => IecType::Byte,
        Some(Type::Word) => IecType::Word,
        Some(Type::Dword) => IecType::Dword,
        Some(Type::Int) => IecType::Int,
        Some(Type::Dint) => IecType::Dint,
        Some(Type::Real) => IecType::Real,
        // S5TIME, TIMER and COUNTER are S7-only: `build` refuses them (HG81xx); should one get
        // here, the nearest IEC type keeps the document valid.
        Some(Type::Time | Type::S5Time) => IecType::Time,
        Some(Type::Date) => IecType::Date,
        Some(Type::TimeOfDay) => IecType::Tod,
        Some(Type::DateAndTime) => IecType::Dt,
        Some(Type::Char) => IecType::String(1),
        Some(Type::String(n)) => IecType::String(n),
        Some(Type::Timer | Type::Counter) => IecType::Word,
        Some(_) => IecType::Dword,
    }
}

/// The IEC direct address of an S7 address (`E 1.0` → `%IX1.0`), if it has one.
fn direct_address(a: &Address) -> Option<String> {
    let area = match a.area {
        Area::Input | Area::PeripheralInput => 'I',
        Area::Output | Area::PeripheralOutput => 'Q',
        Area::Memory => 'M',
        _ => return None,
    };
    if a.db.is_some() {
        return None;
    }
    Some(match (a.size, a.bit) {
        (Size::Bit, Some(bit)) => format!("%{area}X{}.{bit}", a.number),
        (Size::Byte, _) => format!("%{area}B{}", a.number),
        (Size::Word, _) => format!("%{area}W{}", a.number),
        (Size::Dword, _) => format!("%{area}D{}", a.number),
        _ => return None,
    })
}

/// A chart literal in IEC spelling: STEP 7's `W#16#`, `DW#16#`, `B#16#`, `L#`, `S5T#` become
/// `WORD#16#`, `DWORD#16#`, `BYTE#16#`, `DINT#`, `T#`; the rest is IEC already.
fn iec_literal(text: &str) -> String {
    let upper = text.to_ascii_uppercase();
    for (s7, iec) in [
        ("DW#16#", "DWORD#16#"),
        ("W#16#", "WORD#16#"),
        ("B#16#", "BYTE#16#"),
        ("L#", "DINT#"),
        ("S5TIME#", "T#"),
        ("S5T#", "T#"),
        ("C#", ""),
    ] {
        if upper.starts_with(s7) {
            return format!("{iec}{}", &text[s7.len()..]);
        }
    }
    if upper == "TRUE" || upper == "FALSE" {
        return upper;
    }
    text.to_owned()
}

/// What a chart needs while it is read: the resolver's context and the POU being filled.
struct Reader<'g, 'a> {
    ctx: Ctx<'a>,
    scope: Scope,
    globals: &'g mut Globals,
    /// Externals of this POU (global names, in first-use order).
    externals: Vec<Variable>,
    external_names: HashSet<String>,
    /// `SFC_<flag>` inputs, in first-use order.
    sfc_inputs: Vec<Variable>,
    /// What PLCopen cannot express, for the POU documentation.
    notes: Vec<String>,
    /// The chart says `profile iec;` (`docs/iec.md`): ST statements, IEC jumps, FB members.
    iec: bool,
    /// The chart's named actions by key (`index::key`), spelled as declared: a qualifier
    /// may name an action in any letter case, the POU's reference uses the declaration's.
    action_names: HashMap<String, String>,
}

impl Reader<'_, '_> {
    fn external(&mut self, var: Variable) -> String {
        let name = var.name.clone();
        if self.external_names.insert(name.to_ascii_uppercase()) {
            self.externals.push(Variable {
                address: None,
                documentation: None,
                ..var
            });
        }
        name
    }

    /// An operand as ST. `action`: it names an action (a variable is required, so an address
    /// becomes a global variable).
    fn path(&mut self, path: &ast::Path, action: bool) -> Option<String> {
        if action
            && let Some(declared) = path
                .segments()
                .next()
                .filter(|_| path.segments().nth(1).is_none())
                .and_then(|name| self.action_names.get(&crate::index::key(&name.text())))
        {
            return Some(declared.clone());
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
        Some(match target {
            // `Timer.Q`, `Timer.PT`: a member of a function block instance (IEC charts).
            Target::Var(_) if self.iec && path.segments().nth(1).is_some() => text,
            Target::Var(i) => self.scope.vars.get(i)?.name.clone(),
            Target::Symbol { name, ty, address } => {
                let addr = address.as_ref().and_then(direct_address);
                let comment = self
                    .ctx
                    .index
                    .symbol(&name)
                    .and_then(|s| s.comment.clone())
                    .filter(|c| !c.is_empty());
                let doc = match (&address, &addr) {
                    (Some(a), None) => Some(format!(
                        "{}STEP 7 address {} has no IEC direct address",
                        comment.map(|c| format!("{c}; ")).unwrap_or_default(),
                        a.display(crate::lang::Mnemonic::Simatic)
                    )),
                    _ => comment,
                };
                let var = self
                    .globals
                    .get(crate::index::key(&name), &name, iec_type(ty), addr, doc)
                    .clone();
                self.external(var)
            }
            Target::Address(Some(a)) => {
                let display = a.display(crate::lang::Mnemonic::Simatic);
                match direct_address(&a) {
                    Some(direct) if !action => direct,
                    direct => {
                        let doc = if direct.is_none() {
                            Some(format!(
                                "STEP 7 address {display} has no IEC direct address"
                            ))
                        } else {
                            None
                        };
                        let wanted = direct
                            .as_deref()
                            .map_or(display.clone(), |d| d.trim_start_matches('%').to_owned());
                        let var = self
                            .globals
                            .get(
                                format!("@{display}"),
                                &wanted,
                                iec_type(Some(a.ty())),
                                direct,
                                doc,
                            )
                            .clone();
                        self.external(var)
                    }
                }
            }
            Target::Sfc => {
                let flag = path.segments().nth(1).map(|n| n.text())?;
                if !SFC_FLAGS.contains(&flag.to_ascii_uppercase().as_str()) {
                    return Some("FALSE".to_owned());
                }
                let name = format!("SFC_{}", flag.to_ascii_uppercase());
                if !self.sfc_inputs.iter().any(|v| v.name == name) {
                    self.sfc_inputs.push(Variable {
                        name: name.clone(),
                        ty: IecType::Bool,
                        address: None,
                        initial: None,
                        documentation: Some(format!(
                            "operating-state flag SFC.{}: set by the caller",
                            flag.to_ascii_uppercase()
                        )),
                    });
                }
                name
            }
            Target::External | Target::Address(None) | Target::Unresolved | Target::Iec(_) => text,
        })
    }

    /// An expression as ST (the chart's precedence is ST's; parentheses are kept as written).
    fn expr(&mut self, e: &ast::Expr, depth: usize) -> String {
        if depth > MAX_DEPTH {
            return "FALSE".to_owned();
        }
        match e {
            ast::Expr::Literal(l) => iec_literal(l.text().trim()),
            ast::Expr::Path(p) => self.path(p, false).unwrap_or_else(|| "FALSE".to_owned()),
            ast::Expr::TestPath(_) => "FALSE".to_owned(),
            ast::Expr::Paren(p) => match p.expr() {
                Some(inner) => format!("({})", self.expr(&inner, depth + 1)),
                None => "FALSE".to_owned(),
            },
            ast::Expr::Prefix(p) => match (p.op(), p.operand()) {
                (Some(ast::PrefixOp::Neg), Some(operand)) => {
                    let operand = self.expr(&operand, depth + 1);
                    // `- -5`: two minus signs in a row would read as one token elsewhere.
                    let gap = if operand.starts_with('-') { " " } else { "" };
                    format!("-{gap}{operand}")
                }
                (_, Some(operand)) => format!("NOT {}", self.expr(&operand, depth + 1)),
                (_, None) => "FALSE".to_owned(),
            },
            ast::Expr::Bin(b) => {
                let (Some(op), Some(lhs), Some(rhs)) = (b.op_text(), b.lhs(), b.rhs()) else {
                    return "FALSE".to_owned();
                };
                let op = match op.to_ascii_lowercase().as_str() {
                    "and" => "AND".to_owned(),
                    "or" => "OR".to_owned(),
                    "xor" => "XOR".to_owned(),
                    "mod" => "MOD".to_owned(),
                    _ => op,
                };
                let l = self.expr(&lhs, depth + 1);
                let r = self.expr(&rhs, depth + 1);
                format!("{l} {op} {r}")
            }
        }
    }

    /// The conditions of a node's body, ANDed; `empty` when there are none.
    fn conditions(&mut self, node: &higraph_syntax::SyntaxNode, empty: &str) -> String {
        let exprs: Vec<ast::Expr> = body_children(node)
            .filter_map(ast::Condition::cast)
            .filter_map(|c| c.expr())
            .collect();
        // An IEC chart's single condition is written as it stands (the import reads it back).
        let single = self.iec && exprs.len() == 1;
        let parts: Vec<String> = exprs
            .into_iter()
            .map(|e| {
                let text = self.expr(&e, 0);
                let loose = matches!(&e, ast::Expr::Bin(b)
                    if b.op_text().is_some_and(|o| matches!(o.to_ascii_lowercase().as_str(), "or" | "xor")));
                if loose && !single { format!("({text})") } else { text }
            })
            .collect();
        if parts.is_empty() {
            empty.to_owned()
        } else {
            parts.join(" AND ")
        }
    }

    /// `path := expr;` statements of a node's body, one a line (in an IEC chart every
    /// structured-text statement, [`Reader::st`]).
    fn statements(&mut self, node: &higraph_syntax::SyntaxNode) -> String {
        if self.iec {
            let stmts: Vec<ast::Stmt> = body_children(node).filter_map(ast::Stmt::cast).collect();
            let mut lines = Vec::new();
            self.st(&stmts, 0, &mut lines);
            return lines.join("\n");
        }
        let mut lines = Vec::new();
        for a in body_children(node).filter_map(ast::Assignment::cast) {
            let (Some(target), Some(value)) = (a.target(), a.value()) else {
                continue;
            };
            let value = self.expr(&value, 0);
            let is_sfc = target
                .segments()
                .next()
                .is_some_and(|n| n.text().eq_ignore_ascii_case("SFC"))
                && target.segments().nth(1).is_some();
            if is_sfc {
                lines.push(format!(
                    "(* {} := {value}; ignored: operating-state flags are read-only *)",
                    compact(target.syntax())
                ));
                continue;
            }
            let Some(target) = self.path(&target, false) else {
                continue;
            };
            lines.push(format!("{target} := {value};"));
        }
        lines.join("\n")
    }

    /// Structured-text statements as ST, two spaces of indentation per nesting level.
    fn st(&mut self, stmts: &[ast::Stmt], depth: usize, lines: &mut Vec<String>) {
        let pad = "  ".repeat(depth.min(MAX_DEPTH));
        if depth > MAX_DEPTH {
            return;
        }
        for stmt in stmts {
            match stmt {
                ast::Stmt::Assignment(a) => {
                    let (Some(target), Some(value)) = (a.target(), a.value()) else {
                        continue;
                    };
                    let value = self.expr(&value, depth);
                    let Some(target) = self.path(&target, false) else {
                        continue;
                    };
                    lines.push(format!("{pad}{target} := {value};"));
                }
                ast::Stmt::If(s) => {
                    let cond = self.opt_expr(s.condition(), depth);
                    lines.push(format!("{pad}IF {cond} THEN"));
                    let then: Vec<ast::Stmt> = s.then_statements().collect();
                    self.st(&then, depth + 1, lines);
                    for elsif in s.elsifs() {
                        let cond = self.opt_expr(elsif.condition(), depth);
                        lines.push(format!("{pad}ELSIF {cond} THEN"));
                        let body: Vec<ast::Stmt> = elsif.statements().collect();
                        self.st(&body, depth + 1, lines);
                    }
                    if let Some(e) = s.else_clause() {
                        lines.push(format!("{pad}ELSE"));
                        let body: Vec<ast::Stmt> = e.statements().collect();
                        self.st(&body, depth + 1, lines);
                    }
                    lines.push(format!("{pad}END_IF;"));
                }
                ast::Stmt::Case(s) => {
                    let selector = self.opt_expr(s.selector(), depth);
                    lines.push(format!("{pad}CASE {selector} OF"));
                    for arm in s.arms() {
                        let labels: Vec<String> = arm
                            .labels()
                            .filter_map(|l| {
                                let low = l.low()?;
                                Some(match l.high() {
                                    Some(high) if l.is_range() => format!("{low}..{high}"),
                                    _ => low.to_string(),
                                })
                            })
                            .collect();
                        lines.push(format!("{pad}  {}:", labels.join(", ")));
                        let body: Vec<ast::Stmt> = arm.statements().collect();
                        self.st(&body, depth + 2, lines);
                    }
                    if let Some(e) = s.else_clause() {
                        lines.push(format!("{pad}  ELSE"));
                        let body: Vec<ast::Stmt> = e.statements().collect();
                        self.st(&body, depth + 2, lines);
                    }
                    lines.push(format!("{pad}END_CASE;"));
                }
                ast::Stmt::Call(c) => {
                    let Some(callee) = c.callee() else { continue };
                    let mut args = Vec::new();
                    for arg in c.args() {
                        let Some(formal) = arg.formal() else { continue };
                        let formal = formal.text();
                        if arg.is_output() {
                            if let Some(target) = arg.target().and_then(|t| self.path(&t, false)) {
                                args.push(format!("{formal} => {target}"));
                            }
                        } else if let Some(value) = arg.value() {
                            args.push(format!("{formal} := {}", self.expr(&value, depth)));
                        }
                    }
                    lines.push(format!("{pad}{}({});", callee.text(), args.join(", ")));
                }
            }
        }
    }

    fn opt_expr(&mut self, e: Option<ast::Expr>, depth: usize) -> String {
        e.map_or_else(|| "FALSE".to_owned(), |e| self.expr(&e, depth))
    }

    /// A time operand (`T#5S` or a TIME variable).
    fn time(&mut self, operand: &ast::Operand) -> Option<String> {
        match operand {
            ast::Operand::Literal(l) => Some(iec_literal(l.text().trim())),
            ast::Operand::Path(p) => self.path(p, false),
            _ => None,
        }
    }
}

/// The standard function blocks of IEC 61131-3 a chart variable may have as its type
/// (`docs/iec.md` §3): written as `<derived name="TON"/>`.
const STANDARD_FBS: [&str; 10] = [
    "TON", "TOF", "TP", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "SR", "RS",
];

/// The operating-state flags of `runtime.md` §4.2 (other `SFC.` paths read FALSE).
const SFC_FLAGS: [&str; 13] = [
    "IDLE",
    "STARTING",
    "RUN",
    "COMPLETING",
    "ERROR",
    "COMPLETED",
    "HOLDING",
    "HELD",
    "RESUMING",
    "ABORTING",
    "ABORTED",
    "STOPPING",
    "STOPPED",
];

/// A node's text without white space.
fn compact(node: &higraph_syntax::SyntaxNode) -> String {
    node.descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| !t.kind().is_trivia())
        .map(|t| t.text().to_owned())
        .collect()
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

fn comment(node: &higraph_syntax::SyntaxNode) -> Option<String> {
    node.children()
        .find_map(ast::CommentString::cast)
        .map(|c| c.value())
        .filter(|c| !c.is_empty())
}

/// One sequencer, read: its elements and the names of its steps as written.
struct SeqOut {
    name: String,
    prio: u32,
    start: String,
    elements: Vec<Element>,
}

impl Reader<'_, '_> {
    fn step(&mut self, step: &ast::Step, name: &str, seq: &str) -> Step {
        let mut actions = Vec::new();
        let mut notes = Vec::new();
        for item in body_children(step.syntax()) {
            match item.kind() {
                SyntaxKind::STEP_PHASE => {
                    let Some(phase) = ast::StepPhase::cast(item) else {
                        continue;
                    };
                    let q = match phase.keyword().map(|k| k.kind()) {
                        Some(SyntaxKind::INIT_KW) => Qualifier::P1,
                        Some(SyntaxKind::RUN_KW) => Qualifier::N,
                        Some(SyntaxKind::TERM_KW) => Qualifier::P0,
                        _ => continue,
                    };
                    let body = self.statements(phase.syntax());
                    if body.is_empty() {
                        continue;
                    }
                    actions.push(ActionAssoc {
                        qualifier: q,
                        duration: None,
                        body: ActionBody::Inline(body),
                    });
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
                    let Some(target) = self.path(&path, true) else {
                        continue;
                    };
                    let duration = operands.next().and_then(|t| self.time(&t));
                    actions.push(ActionAssoc {
                        qualifier: q,
                        duration,
                        body: ActionBody::Reference(target),
                    });
                }
                SyntaxKind::STEP_TIME => {
                    let Some(time) = ast::StepTime::cast(item) else {
                        continue;
                    };
                    let kw = time
                        .keyword()
                        .map(|k| k.text().to_ascii_lowercase())
                        .unwrap_or_default();
                    let value = time.value().and_then(|v| self.time(&v)).unwrap_or_default();
                    let what = if kw == "min" {
                        "minimum step time"
                    } else {
                        "maximum step time"
                    };
                    notes.push(format!("{what} {value}"));
                    self.notes
                        .push(format!("step {seq}.{name}: {kw} {value} ({what})"));
                }
                SyntaxKind::CONFIRM => {
                    notes.push("confirm".to_owned());
                    self.notes.push(format!(
                        "step {seq}.{name}: confirm (operator confirmation in switching mode step)"
                    ));
                }
                _ => {}
            }
        }
        let mut documentation = comment(step.syntax()).unwrap_or_default();
        if !notes.is_empty() {
            if !documentation.is_empty() {
                documentation.push('\n');
            }
            documentation.push_str(&format!("not in IEC: {}", notes.join(", ")));
        }
        Step {
            name: name.to_owned(),
            initial: false,
            actions,
            documentation: (!documentation.is_empty()).then_some(documentation),
        }
    }

    fn transition(&mut self, elem: &crate::rules::chart::model::Elem) -> Transition {
        Transition {
            name: elem.label().to_owned(),
            condition: self.conditions(elem.node.syntax(), "TRUE"),
            documentation: comment(elem.node.syntax()),
        }
    }

    /// The elements of one list of the tree (the sequencer's or a branch's).
    fn list(&mut self, tree: &Tree, list: ListId, seq: &str, depth: usize) -> Vec<Element> {
        let mut out = Vec::new();
        if depth > MAX_DEPTH {
            return out;
        }
        let elems = &tree.lists[list].elems;
        let mut i = 0;
        while i < elems.len() {
            let id = elems[i];
            let elem = &tree.elems[id];
            i += 1;
            match elem.kind {
                Kind::Step => {
                    let ast::SeqElement::Step(step) = &elem.node else {
                        continue;
                    };
                    out.push(Element::Step(self.step(step, elem.label(), seq)));
                    // Jumps and loops right after the step.
                    let mut exits = Vec::new();
                    while i < elems.len() && tree.elems[elems[i]].kind.is_attachment() {
                        exits.push(elems[i]);
                        i += 1;
                    }
                    if exits.is_empty() {
                        continue;
                    }
                    let next = elems.get(i).map(|&n| (n, tree.elems[n].kind));
                    let mut branches: Vec<Vec<Element>> = match next {
                        Some((n, Kind::Trans)) => {
                            i += 1;
                            vec![vec![Element::Transition(self.transition(&tree.elems[n]))]]
                        }
                        Some((n, Kind::Alt)) => {
                            i += 1;
                            tree.elems[n]
                                .branches
                                .iter()
                                .map(|&b| self.list(tree, b, seq, depth + 1))
                                .collect()
                        }
                        // IEC: the jumps are the step's only exits (a cyclic chart, an `alt`
                        // branch ending in a jump): a transition and a jump step each, in a
                        // selection divergence when there are several.
                        _ if self.iec => {
                            let mut branches: Vec<Vec<Element>> =
                                exits.iter().map(|&x| self.jump(tree, x)).collect();
                            if branches.len() == 1 {
                                out.append(&mut branches[0]);
                            } else {
                                out.push(Element::Selection(branches));
                            }
                            continue;
                        }
                        _ => {
                            for &x in &exits {
                                self.notes.push(format!(
                                    "{} in sequencer {seq}: not exported (it follows a step without a successor transition)",
                                    tree.elems[x].render()
                                ));
                            }
                            continue;
                        }
                    };
                    for &x in &exits {
                        branches.push(self.jump(tree, x));
                    }
                    out.push(Element::Selection(branches));
                }
                Kind::Trans => out.push(Element::Transition(self.transition(elem))),
                Kind::Parallel | Kind::Alt => {
                    let branches = elem
                        .branches
                        .iter()
                        .map(|&b| self.list(tree, b, seq, depth + 1))
                        .collect();
                    out.push(if elem.kind == Kind::Parallel {
                        Element::Simultaneous(branches)
                    } else {
                        Element::Selection(branches)
                    });
                }
                // IEC: an `alt` branch that is a single jump.
                Kind::Jump | Kind::Loop if self.iec => out.extend(self.jump(tree, id)),
                Kind::Jump | Kind::Loop => self.notes.push(format!(
                    "{} in sequencer {seq}: not exported (it does not follow a step)",
                    elem.render()
                )),
            }
        }
        out
    }

    /// A jump or loop: its transition and a jump step to its target.
    fn jump(&mut self, tree: &Tree, x: crate::rules::chart::model::ElemId) -> Vec<Element> {
        let target = tree.elems[x]
            .target
            .as_ref()
            .map(|(t, _)| t.clone())
            .unwrap_or_default();
        vec![
            Element::Transition(self.transition(&tree.elems[x])),
            Element::Jump(target),
        ]
    }

    fn sequencer(&mut self, sequencer: &ast::Sequencer, name: &str) -> SeqOut {
        let prio = sequencer
            .prio()
            .and_then(|p| p.value())
            .and_then(|v| v.text().parse::<u32>().ok())
            .unwrap_or(1);
        let start = sequencer
            .start()
            .map(|s| self.conditions(s.syntax(), "FALSE"))
            .unwrap_or_else(|| "FALSE".to_owned());
        for (part, node) in [
            ("pre", sequencer.pre().map(|p| p.syntax().clone())),
            ("post", sequencer.post().map(|p| p.syntax().clone())),
        ] {
            if let Some(node) = node {
                let body = self.statements(&node);
                if !body.is_empty() {
                    self.notes.push(format!(
                        "sequencer {name}: {part} statements (every cycle {} the steps): {}",
                        if part == "pre" { "before" } else { "after" },
                        body.replace('\n', " ")
                    ));
                }
            }
        }
        let tree = Tree::build(sequencer);
        let elements = self.list(&tree, 0, name, 0);
        SeqOut {
            name: name.to_owned(),
            prio,
            start,
            elements,
        }
    }
}

/// Renames steps (and the jump targets naming them) whose names are taken in the POU:
/// `<sequencer>_<step>`, then numbered.
fn rename_steps(elements: &mut [Element], seq: &str, taken: &mut HashSet<String>) {
    let mut renames: HashMap<String, String> = HashMap::new();
    let mut stack: Vec<&mut Element> = elements.iter_mut().collect();
    let mut jumps: Vec<&mut String> = Vec::new();
    // Iterative walk in document order: steps are named in the order they are met.
    stack.reverse();
    while let Some(e) = stack.pop() {
        match e {
            Element::Step(s) => {
                let key = s.name.to_ascii_uppercase();
                if renames.contains_key(&key) {
                    continue;
                }
                let name = if taken.insert(key.clone()) {
                    s.name.clone()
                } else {
                    unique(&format!("{seq}_{}", s.name), taken)
                };
                renames.insert(key, name.clone());
                s.name = name;
            }
            Element::Jump(t) => jumps.push(t),
            Element::Simultaneous(b) | Element::Selection(b) => {
                let mut inner: Vec<&mut Element> = b.iter_mut().flatten().collect();
                inner.reverse();
                stack.extend(inner);
            }
            Element::Transition(_) => {}
        }
    }
    for t in jumps {
        if let Some(n) = renames.get(&t.to_ascii_uppercase()) {
            *t = n.clone();
        }
    }
}

fn chart_pou(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
    globals: &mut Globals,
) -> Option<Pou> {
    let loc = ItemLoc::new(db, file, item);
    let root = db::item_root(db, loc)?;
    let ast::Item::Chart(chart) = ast::Item::cast(root)? else {
        return None;
    };
    let name = chart.name()?.text();
    let mut ctx = Ctx::for_item(db, ws, loc);
    let info = ChartInfo {
        name: name.clone(),
        is_type: chart.is_type(),
        chart: chart.clone(),
    };
    let vars = crate::rules::chart::decls::declare(&mut ctx, &info);
    ctx.out.diags.clear();

    let mut decls: HashMap<String, ast::VarDecl> = HashMap::new();
    for (_, decl) in crate::rules::decls::declarations(chart.var_sections()) {
        if let Some(n) = decl.name() {
            decls.entry(crate::index::key(&n.text())).or_insert(decl);
        }
    }
    let mut pou = Pou {
        name: identifier(&name),
        ..Pou::default()
    };
    let iec = chart.profile() == ast::Profile::Iec;
    let mut taken: HashSet<String> = HashSet::new();
    for var in vars.iter().filter(|v| !v.duplicate) {
        let decl = decls.get(&crate::index::key(&var.name));
        // A standard function block instance (IEC charts): the type by name.
        let fb = decl
            .and_then(|d| d.ty())
            .map(|t| compact(t.syntax()).to_ascii_uppercase())
            .filter(|t| iec && STANDARD_FBS.contains(&t.as_str()));
        let v = Variable {
            name: var.name.clone(),
            ty: fb.map_or_else(|| iec_type(var.ty), IecType::Derived),
            address: None,
            initial: decl
                .and_then(|d| d.initial_value())
                .and_then(|v| v.literal())
                .map(|l| iec_literal(l.text().trim())),
            documentation: decl.and_then(|d| d.comment()).map(|c| c.value()),
        };
        taken.insert(var.name.to_ascii_uppercase());
        match var.section {
            Section::In => pou.inputs.push(v),
            Section::Out => pou.outputs.push(v),
            Section::InOut => pou.in_outs.push(v),
            Section::Stat => pou.locals.push(v),
        }
    }

    let mut reader = Reader {
        ctx,
        scope: Scope::new(info, vars),
        globals,
        externals: Vec::new(),
        external_names: HashSet::new(),
        sfc_inputs: Vec::new(),
        notes: Vec::new(),
        iec,
        action_names: HashMap::new(),
    };
    for name in chart.actions().filter_map(|a| a.name().map(|n| n.text())) {
        // The first declaration of a name wins (HG7510).
        reader
            .action_names
            .entry(crate::index::key(&name))
            .or_insert(name);
    }
    let mut props = Vec::new();
    for prop in chart.props() {
        let (Some(keyword), Some(value)) = (prop.keyword(), prop.value()) else {
            continue;
        };
        // The profile is what the export follows, nothing PLCopen lacks.
        if keyword.kind() == SyntaxKind::PROFILE_KW {
            continue;
        }
        let value = value.text();
        let keyword = keyword.text().to_ascii_lowercase();
        props.push(format!("{keyword} {value}"));
    }
    let mut seen = HashSet::new();
    let mut seqs = Vec::new();
    for sequencer in chart.sequencers() {
        let Some(seq_name) = sequencer.name().map(|n| n.text()) else {
            continue;
        };
        if !seen.insert(crate::index::key(&seq_name)) {
            continue;
        }
        seqs.push(reader.sequencer(&sequencer, &seq_name));
    }

    // Named actions (IEC charts): the POU's actions, with ST bodies.
    let mut actions_seen = HashSet::new();
    for action in chart.actions() {
        let Some(action_name) = action.name().map(|n| n.text()) else {
            continue;
        };
        if !actions_seen.insert(crate::index::key(&action_name)) {
            continue;
        }
        let body = reader.statements(action.syntax());
        pou.actions.push(NamedAction {
            name: action_name.clone(),
            body,
            documentation: comment(action.syntax()),
        });
        taken.insert(action_name.to_ascii_uppercase());
    }

    // Identifiers of the POU: variables, externals, the operating-state inputs, then steps.
    for v in reader.externals.iter().chain(&reader.sfc_inputs) {
        taken.insert(v.name.to_ascii_uppercase());
    }
    let several = seqs.len() > 1;
    let idle = if several || seqs.is_empty() {
        unique("Idle", &mut taken)
    } else {
        String::new()
    };
    for s in &mut seqs {
        rename_steps(&mut s.elements, &s.name, &mut taken);
    }

    let mut doc = Vec::new();
    if iec {
        // An IEC chart is an IEC function block already: its comment is the documentation,
        // followed by what PLCopen cannot hold (`pre`/`post` statements).
        doc.extend(comment(chart.syntax()));
        if !props.is_empty() || !reader.notes.is_empty() {
            doc.push("Not in PLCopen:".to_owned());
            doc.extend(props.iter().map(|p| format!("- {p}")));
            doc.extend(reader.notes.iter().map(|n| format!("- {n}")));
        }
    } else {
        let title = match comment(chart.syntax()) {
            Some(c) => format!("HiGraph chart {name} \"{c}\", exported by higraph-lsp build."),
            None => format!("HiGraph chart {name}, exported by higraph-lsp build."),
        };
        doc.push(title);
        doc.push(
            "Call this function block once per PLC cycle. The PCS 7 operating-state logic \
             (commands start, hold, resume, complete, abort, stop, reset, error and the states they \
             lead to) has no IEC form: the caller decides when to call the block; SFC.* flags are \
             BOOL inputs SFC_*."
                .to_owned(),
        );
        if several {
            let order: Vec<String> = {
                let mut by_prio: Vec<&SeqOut> = seqs.iter().collect();
                by_prio.sort_by_key(|s| s.prio);
                by_prio
                    .iter()
                    .map(|s| format!("{} (prio {})", s.name, s.prio))
                    .collect()
            };
            doc.push(format!(
                "Sequencers: step {idle} selects one by its start condition in the order {}; after \
                 its end step the chart returns to {idle}. Not in IEC: a sequencer of higher priority \
                 displacing a running one.",
                order.join(", ")
            ));
        } else if let Some(s) = seqs.first() {
            doc.push(format!(
                "Sequencer {} (prio {}): its start step is the initial step; its start condition \
                 ({}) is the caller's to check.",
                s.name, s.prio, s.start
            ));
        }
        if !props.is_empty() || !reader.notes.is_empty() {
            doc.push("Not in IEC:".to_owned());
            for p in &props {
                doc.push(format!("- {p}"));
            }
            for n in &reader.notes {
                doc.push(format!("- {n}"));
            }
        }
    }
    pou.documentation = doc.join("\n");

    pou.body = if several {
        let mut order: Vec<SeqOut> = seqs;
        // Stable: equal priorities keep text order.
        order.sort_by_key(|s| s.prio);
        let branches = order
            .into_iter()
            .map(|s| {
                let mut b = vec![Element::Transition(Transition {
                    name: format!("Start_{}", s.name),
                    condition: s.start,
                    documentation: Some(format!("start condition of sequencer {}", s.name)),
                })];
                b.extend(s.elements);
                b.push(Element::Transition(Transition {
                    name: format!("Done_{}", s.name),
                    condition: "TRUE".to_owned(),
                    documentation: Some(format!("sequencer {} completed", s.name)),
                }));
                b.push(Element::Jump(idle.clone()));
                b
            })
            .collect();
        vec![
            Element::Step(Step {
                name: idle,
                initial: true,
                actions: Vec::new(),
                documentation: Some("no sequencer running".to_owned()),
            }),
            Element::Selection(branches),
        ]
    } else if let Some(s) = seqs.pop() {
        let mut elements = s.elements;
        if let Some(Element::Step(first)) = elements.first_mut() {
            first.initial = true;
        }
        elements
    } else {
        vec![Element::Step(Step {
            name: idle,
            initial: true,
            actions: Vec::new(),
            documentation: Some("the chart has no sequencer".to_owned()),
        })]
    };
    pou.inputs.extend(reader.sfc_inputs);
    pou.externals = reader.externals;
    Some(pou)
}

#[cfg(test)]
mod tests {
    //! Snapshots of the XML of the mixer example and small fixture charts
    //! (`test_data/plcopen/`), the wiring invariants, and the hook `scripts/plcopen-check`
    //! uses until `higraph-lsp build` exists: with `HIGRAPH_PLCOPEN_OUT=DIR`,
    //! `export_for_check` writes one document per workspace into DIR.

    use std::path::{Path, PathBuf};

    use crate::fixture_workspace::{FixtureFile, load_fixture};
    use crate::{AnalysisHost, Severity};

    fn root() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
    }

    /// The `.higraph` files, `higraph.toml` and symbol tables of a folder, as a workspace.
    fn folder(dir: &Path) -> Vec<FixtureFile> {
        let mut files = Vec::new();
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .map(|r| r.filter_map(Result::ok).map(|e| e.path()).collect())
            .unwrap_or_default();
        entries.sort();
        for path in entries {
            if !path.is_file() {
                continue;
            }
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            if name.ends_with(".higraph") || name == "higraph.toml" || name.ends_with(".sdf") {
                files.push((name, std::fs::read(&path).unwrap_or_default()));
            }
        }
        files
    }

    /// The document of every chart of a workspace, and whether the workspace has errors.
    fn xml(host: &AnalysisHost) -> (String, bool) {
        let analysis = host.analysis();
        let errors = analysis
            .diagnostics()
            .iter()
            .flat_map(|(_, d)| d)
            .any(|d| d.severity == Severity::Error);
        let bytes = analysis
            .with_db(|db, ws| {
                let index = crate::db::global_index(db, ws);
                let charts: Vec<_> = index
                    .items
                    .iter()
                    .filter(|i| i.kind == crate::db::ItemKind::Chart)
                    .map(|i| (i.file, i.item))
                    .collect();
                super::charts_xml(db, ws, &charts)
            })
            .unwrap_or_default();
        (String::from_utf8(bytes).unwrap_or_default(), errors)
    }

    fn fixture(name: &str) -> String {
        let path = root().join("crates/analysis/test_data/plcopen").join(name);
        let text = std::fs::read(&path).unwrap_or_default();
        let (xml, errors) = xml(&load_fixture(&[(name.to_owned(), text)]));
        assert!(!errors, "{name} has errors");
        check_wiring(&xml);
        xml
    }

    /// The values of `attr="..."` in document order.
    fn attrs(xml: &str, attr: &str) -> Vec<u64> {
        let needle = format!(" {attr}=\"");
        xml.match_indices(&needle)
            .filter_map(|(i, _)| {
                let rest = &xml[i + needle.len()..];
                rest[..rest.find('"')?].parse().ok()
            })
            .collect()
    }

    /// Every `localId` is unique; every `refLocalId` names one; every element but the initial
    /// steps is connected.
    fn check_wiring(xml: &str) {
        let ids = attrs(xml, "localId");
        let unique: std::collections::HashSet<_> = ids.iter().copied().collect();
        assert_eq!(unique.len(), ids.len(), "duplicate localId");
        let refs = attrs(xml, "refLocalId");
        assert!(!refs.is_empty() || ids.len() <= 1);
        for r in &refs {
            assert!(unique.contains(r), "refLocalId {r} names no element");
        }
        let connected = xml.matches("<connection refLocalId").count();
        let initial = xml.matches("initialStep=\"true\"").count();
        let elements = ["<step ", "<transition ", "<jumpStep ", "<actionBlock "]
            .iter()
            .map(|e| xml.matches(e).count())
            .sum::<usize>()
            + xml.matches("Divergence localId").count();
        let convergence_inputs: usize = xml
            .split("Convergence localId")
            .skip(1)
            .map(|part| {
                part.split("Convergence>")
                    .next()
                    .map_or(0, |p| p.matches("<connection ").count())
            })
            .sum();
        assert_eq!(
            connected,
            elements - initial + convergence_inputs,
            "an element without a connection"
        );
    }

    #[test]
    fn mixer_example() {
        let files = folder(&root().join("examples/mixer"));
        let (xml, errors) = xml(&load_fixture(&files));
        assert!(!errors);
        check_wiring(&xml);
        // The mixer's jump sits on a step followed by an alt: one divergence, the alt's
        // branches first (priorities 1, 2), the jump last (3); its loop comes after the
        // normal successor Entleert (1, 2).
        assert!(xml.contains("targetName=\"Entleeren\""));
        assert!(xml.contains("targetName=\"Fuellen_A\""));
        assert!(xml.contains("<inline name=\"A_Mit_B\">"));
        assert!(xml.contains("Fuellstand &gt;= Menge_A AND Mit_B"));
        assert!(xml.contains("address=\"%IX1.0\""));
        insta::assert_snapshot!(xml);
    }

    #[test]
    fn alt() {
        let xml = fixture("alt.higraph");
        assert_eq!(xml.matches("<selectionDivergence").count(), 1);
        assert_eq!(xml.matches("<selectionConvergence").count(), 1);
        assert!(xml.contains("NOT A OR B"));
        assert!(xml.contains("B &lt;&gt; A"));
        insta::assert_snapshot!(xml);
    }

    #[test]
    fn parallel() {
        let xml = fixture("parallel.higraph");
        assert_eq!(xml.matches("<simultaneousDivergence").count(), 1);
        assert_eq!(xml.matches("<simultaneousConvergence").count(), 1);
        insta::assert_snapshot!(xml);
    }

    #[test]
    fn jump_and_loop() {
        let xml = fixture("jump_loop.higraph");
        // Each attachment: one divergence, the normal successor first.
        assert_eq!(xml.matches("<selectionDivergence").count(), 2);
        assert_eq!(xml.matches("<selectionConvergence").count(), 0);
        let weiter = xml.find("<inline name=\"Weiter\">").unwrap_or(0);
        let vor = xml.find("<inline name=\"Vor\">").unwrap_or(0);
        assert!(0 < weiter && weiter < vor);
        assert_eq!(attrs(&xml, "priority"), vec![1, 2, 1, 2]);
        insta::assert_snapshot!(xml);
    }

    #[test]
    fn several_sequencers() {
        let xml = fixture("sequencers.higraph");
        // A common initial step; prio 1 (Hoch) left of prio 2 (Nieder).
        assert_eq!(xml.matches("initialStep=\"true\"").count(), 1);
        assert!(xml.contains("name=\"Idle\" initialStep=\"true\""));
        let hoch = xml.find("Start_Hoch").unwrap_or(0);
        let nieder = xml.find("Start_Nieder").unwrap_or(0);
        assert!(0 < hoch && hoch < nieder);
        assert!(xml.contains("B AND SFC_RUN"));
        // Both sequencers have a step Ende: the later one in the text is renamed.
        assert!(xml.contains("name=\"Ende\""));
        assert!(xml.contains("name=\"Hoch_Ende\""));
        insta::assert_snapshot!(xml);
    }

    #[test]
    fn qualifiers_with_durations() {
        let xml = fixture("qualifiers.higraph");
        for q in ["P1", "N", "P0", "S", "R", "P", "L", "D", "SD", "DS", "SL"] {
            assert!(xml.contains(&format!("qualifier=\"{q}\"")), "{q}");
        }
        assert!(xml.contains("qualifier=\"L\" duration=\"T#5S\""));
        assert!(xml.contains("qualifier=\"D\" duration=\"Dauer\""));
        assert!(xml.contains("Q_N := Taster AND %IX0.1;"));
        assert!(xml.contains("<reference name=\"QX4_2\"/>"));
        assert!(xml.contains("Wert &gt;= WORD#16#10"));
        insta::assert_snapshot!(xml);
    }

    /// An IEC chart: no `Idle`, the first step initial, the cyclic jump as a transition and a
    /// jump step, FB instances as derived types, a named action, P1.
    #[test]
    fn iec_traffic_light() {
        let xml = fixture("iec_ampel.higraph");
        assert_eq!(xml.matches("initialStep=\"true\"").count(), 1);
        assert!(xml.contains("name=\"Rot_Phase\" initialStep=\"true\""));
        assert!(!xml.contains("Idle"));
        assert!(xml.contains("<derived name=\"TON\"/>"));
        assert!(xml.contains("<derived name=\"CTU\"/>"));
        assert!(xml.contains("<action name=\"Zaehlen\">"));
        assert!(xml.contains("Zyklen(CU := TRUE, R := FALSE, PV := 100, CV =&gt; Anzahl);"));
        assert!(xml.contains("qualifier=\"P1\""));
        assert!(xml.contains("<reference name=\"Zaehlen\"/>"));
        assert!(xml.contains("Takt.Q AND Anforderung"));
        assert!(xml.contains("Rot_Gelb_Phase_mit_langem_Namen.T &gt;= T#2s"));
        assert!(xml.contains("NOT Anforderung OR Anzahl MOD 2 = 1"));
        // The cyclic jump: its transition, then the jump step; no divergence.
        assert_eq!(xml.matches("<selectionDivergence").count(), 0);
        let zurueck = xml.find("<inline name=\"Zurueck\">").unwrap_or(0);
        let jump = xml.find("targetName=\"Rot_Phase\"").unwrap_or(0);
        assert!(0 < zurueck && zurueck < jump);
        // The documentation is the comment.
        assert!(xml.contains("<documentation><xhtml:p>traffic light</xhtml:p></documentation>"));
        insta::assert_snapshot!(xml);
    }

    /// Alt branches converging, ending in a jump and being one; parallel; every qualifier;
    /// IF/CASE/calls in ST.
    #[test]
    fn iec_constructs() {
        let xml = fixture("iec_constructs.higraph");
        for q in [
            "P1", "N", "P0", "S", "R", "P", "L", "D", "SD", "DS", "SL", "DL",
        ] {
            assert!(xml.contains(&format!("qualifier=\"{q}\"")), "{q}");
        }
        assert!(xml.contains("qualifier=\"DL\" duration=\"T#1s\""));
        assert!(xml.contains("qualifier=\"SD\" duration=\"Dauer\""));
        // The alt: three branches, priorities 1..3, one open branch (no convergence).
        assert_eq!(xml.matches("<selectionDivergence").count(), 1);
        assert_eq!(xml.matches("<selectionConvergence").count(), 0);
        assert_eq!(attrs(&xml, "priority"), vec![1, 2, 3]);
        assert_eq!(xml.matches("<jumpStep").count(), 3);
        assert_eq!(xml.matches("<simultaneousDivergence").count(), 1);
        assert!(xml.contains("Start AND (Stufe + 1) * 2 &gt; 4"));
        assert!(xml.contains("Stufe = -1"));
        assert!(xml.contains("Modus := -Modus * 2;"));
        assert!(xml.contains("IF Teile &gt; 10 AND NOT Start THEN\n  Teile := 0;\nELSIF"));
        assert!(xml.contains("CASE Stufe OF\n  1:\n    Modus := 1;\n  2..4, -1:"));
        assert!(xml.contains("  ELSE\n    Speicher(S1 := Start, R := FALSE);\nEND_CASE;"));
        assert!(xml.contains("Pruefen.X OR Teile &gt; 0"));
        assert!(xml.contains("<derived name=\"CTUD\"/>"));
        insta::assert_snapshot!(xml);
    }

    #[test]
    fn deterministic() {
        let files = folder(&root().join("examples/mixer"));
        assert_eq!(xml(&load_fixture(&files)).0, xml(&load_fixture(&files)).0);
    }

    /// Every chart of the rule fixtures, those with errors included (a build would refuse
    /// them, but the export must not panic on any input): the ids still hold.
    #[test]
    fn any_chart_fixture_exports_without_panic() {
        let mut stack = vec![root().join("crates/analysis/test_data")];
        let mut n = 0;
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                    continue;
                }
                let text = std::fs::read(&p).unwrap_or_default();
                if p.extension().is_none_or(|x| x != "higraph")
                    || !String::from_utf8_lossy(&text).contains("chart")
                {
                    continue;
                }
                let (xml, _) = xml(&load_fixture(&[("main.higraph".to_owned(), text)]));
                let ids = attrs(&xml, "localId");
                let unique: std::collections::HashSet<_> = ids.iter().collect();
                assert_eq!(unique.len(), ids.len(), "{}", p.display());
                for r in attrs(&xml, "refLocalId") {
                    assert!(unique.contains(&r), "{}", p.display());
                }
                n += 1;
            }
        }
        assert!(n > 100, "{n} chart fixtures");
    }

    /// The charts `higraph-lsp import` makes of the PLCopen files of real tools' dialects
    /// (`tests/data/plcopen/import/`, CODESYS, Beremiz and the neutral format), formatted:
    /// `(file stem + POU, text)`.
    fn imported_charts() -> Vec<(String, String)> {
        let mut out = Vec::new();
        for stem in [
            "codesys_ampel",
            "beremiz_station",
            "neutral_mixer",
            "beremiz_networks",
        ] {
            let path = root().join(format!("tests/data/plcopen/import/{stem}.xml"));
            let xml = std::fs::read_to_string(&path).unwrap_or_default();
            let Ok(import) = higraph_import::import(&xml) else {
                continue;
            };
            for chart in import.charts {
                let text = crate::format::format(&chart.text).unwrap_or(chart.text);
                out.push((format!("{stem}-{}", chart.pou), text));
            }
        }
        out
    }

    /// A real IEC chart imports, checks clean and exports back (issue 14, "done when"): the
    /// charts imported from the CODESYS, Beremiz and neutral files build, with the wiring
    /// intact (`scripts/plcopen-check` validates the same documents against the schema).
    #[test]
    fn imported_charts_export_back() {
        let charts = imported_charts();
        assert!(charts.len() >= 3, "{charts:?}");
        for (name, text) in charts {
            let (xml, errors) = xml(&load_fixture(&[(
                "main.higraph".to_owned(),
                text.clone().into_bytes(),
            )]));
            assert!(!errors, "{name} has errors:\n{text}");
            check_wiring(&xml);
            assert!(xml.contains("initialStep=\"true\""), "{name}");
        }
    }

    /// For `scripts/plcopen-check`: writes the documents of the examples, the fixtures and the
    /// test data charts that check clean into `$HIGRAPH_PLCOPEN_OUT` (does nothing without).
    #[test]
    fn export_for_check() {
        let Some(out) = std::env::var_os("HIGRAPH_PLCOPEN_OUT") else {
            return;
        };
        let out = PathBuf::from(out);
        std::fs::create_dir_all(&out).expect("output folder");
        let mut workspaces: Vec<(String, Vec<FixtureFile>)> = Vec::new();
        for (prefix, dir) in [("example", "examples"), ("runtime", "tests/data/runtime")] {
            let mut dirs: Vec<_> = std::fs::read_dir(root().join(dir))
                .map(|r| r.filter_map(Result::ok).map(|e| e.path()).collect())
                .unwrap_or_default();
            dirs.sort();
            for d in dirs.into_iter().filter(|d| d.is_dir()) {
                let name = d
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                workspaces.push((format!("{prefix}-{name}"), folder(&d)));
            }
        }
        let mut singles: Vec<PathBuf> = Vec::new();
        for dir in [
            "crates/analysis/test_data/plcopen",
            "crates/analysis/test_data/rules",
        ] {
            let mut stack = vec![root().join(dir)];
            while let Some(d) = stack.pop() {
                for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
                    let p = e.path();
                    if p.is_dir() {
                        stack.push(p);
                    } else if p.extension().is_some_and(|x| x == "higraph") {
                        singles.push(p);
                    }
                }
            }
        }
        singles.sort();
        for p in singles {
            let text = std::fs::read(&p).unwrap_or_default();
            if !String::from_utf8_lossy(&text).contains("chart ") {
                continue;
            }
            let rel = p
                .strip_prefix(root())
                .map(|r| r.to_string_lossy().replace(['/', '\\'], "-"))
                .unwrap_or_default();
            workspaces.push((
                rel.trim_end_matches(".higraph").to_owned(),
                vec![("main.higraph".to_owned(), text)],
            ));
        }
        // The charts the import makes of the hand-written CODESYS, Beremiz and neutral files:
        // what a real IEC chart becomes after `import`, exported back.
        for (name, text) in imported_charts() {
            workspaces.push((
                format!("reexport-{name}"),
                vec![("main.higraph".to_owned(), text.into_bytes())],
            ));
        }
        // Generated IEC charts (the round trip's input), a few seeds.
        for seed in 0..20 {
            workspaces.push((
                format!("iec-generated-{seed}"),
                vec![(
                    "main.higraph".to_owned(),
                    higraph_workload::iec_chart(seed).into_bytes(),
                )],
            ));
        }
        let mut written = 0;
        for (name, files) in workspaces {
            let (xml, errors) = xml(&load_fixture(&files));
            if errors || !xml.contains("<pou ") {
                continue;
            }
            std::fs::write(out.join(format!("{name}.xml")), xml).expect("write");
            written += 1;
        }
        assert!(written > 0);
    }
}
