//! A readable text form of a lowered [`Program`], for snapshot tests and debugging.

use std::fmt::Write;

use higraph_runtime::Program;
use higraph_runtime::program::{
    Block, Expr, Instr, MemArea, Operand, Path, PathKind, Place, Profile, Statement, TestStmtKind,
    TimeValue, Trans, Width,
};

fn place(p: &Place) -> String {
    match p {
        Place::Mem { area, byte, width } => {
            let area = match area {
                MemArea::Input => "E".to_owned(),
                MemArea::Output => "A".to_owned(),
                MemArea::Memory => "M".to_owned(),
                MemArea::Local => "L".to_owned(),
                MemArea::Db(n) => format!("DB{n}.DB"),
            };
            match width {
                Width::Bit(b) => {
                    let area = if area.ends_with(".DB") {
                        format!("{area}X")
                    } else {
                        area
                    };
                    format!("{area} {byte}.{b}")
                }
                Width::Byte => format!("{area}B {byte}"),
                Width::Word => format!("{area}W {byte}"),
                Width::Dword => format!("{area}D {byte}"),
            }
        }
        Place::Cell(c) => format!("cell{c}"),
        Place::Timer(t) => format!("T{}", t.0),
        Place::Counter(c) => format!("Z{}", c.0),
        Place::Const(v) => format!("const {v:?}"),
    }
}

fn operand(o: &Operand) -> String {
    match o {
        Operand::None => String::new(),
        Operand::Imm(v) => format!("#16#{v:X}"),
        Operand::Var(v) => format!("var{v}"),
        Operand::Place(p) => place(p),
        Operand::Call(c) => {
            let params: Vec<String> = c
                .params
                .iter()
                .map(|(f, a)| format!("{f} := {}", operand(a)))
                .collect();
            format!("block{} ({})", c.block, params.join(", "))
        }
    }
}

fn instr(i: &Instr) -> String {
    let o = operand(&i.operand);
    if o.is_empty() {
        format!("{:?}", i.op)
    } else {
        format!("{:?} {o}", i.op)
    }
}

fn block(out: &mut String, indent: &str, label: &str, b: &Block) {
    let code: Vec<String> = b.code.iter().map(instr).collect();
    let _ = writeln!(out, "{indent}{label}: {}", code.join("; "));
}

fn path(p: &Path) -> String {
    let kind = match &p.kind {
        PathKind::Place(pl) => place(pl),
        PathKind::InstState {
            group,
            instance,
            previous,
        } => format!(
            "group{group}.inst{instance}.{}",
            if *previous { "previous" } else { "state" }
        ),
        PathKind::Sfc(f) => format!("SFC {f:?}"),
        PathKind::ChartState { chart } => format!("chart{chart}.state"),
        PathKind::Step {
            chart,
            sequencer,
            step,
            member,
        } => format!("chart{chart}.seq{sequencer}.step{step}.{member:?}"),
        PathKind::Stub { block, param } => format!("block{block}.{param}"),
        PathKind::Calls { block } => format!("block{block}.calls"),
    };
    format!("{}[{} {}]", p.text, p.ty, kind)
}

pub(crate) fn expr(e: &Expr) -> String {
    match e {
        Expr::Const(v) => format!("{v:?}"),
        Expr::Read(p) => path(p),
        Expr::Not(x) => format!("not {}", expr(x)),
        Expr::And(a, b) => format!("({} and {})", expr(a), expr(b)),
        Expr::Or(a, b) => format!("({} or {})", expr(a), expr(b)),
        Expr::Xor(a, b) => format!("({} xor {})", expr(a), expr(b)),
        Expr::Cmp(op, a, b) => format!("({} {op:?} {})", expr(a), expr(b)),
        Expr::Neg(x) => format!("-{}", expr(x)),
        Expr::Arith(op, a, b) => format!("({} {op:?} {})", expr(a), expr(b)),
    }
}

/// Statements, nested ones indented by two more (depth bounded by the parser's nesting limit).
fn stmts(out: &mut String, indent: &str, label: &str, s: &[Statement]) {
    for st in s {
        match st {
            Statement::Assign(st) => {
                let _ = writeln!(
                    out,
                    "{indent}{label}: {} ({}) := {}",
                    place(&st.target),
                    st.ty,
                    expr(&st.value)
                );
            }
            Statement::If { arms, else_, .. } => {
                let inner = format!("{indent}  ");
                for (i, (cond, body)) in arms.iter().enumerate() {
                    let kw = if i == 0 { "IF" } else { "ELSIF" };
                    let _ = writeln!(out, "{indent}{label}: {kw} {}", expr(cond));
                    stmts(out, &inner, label, body);
                }
                if !else_.is_empty() {
                    let _ = writeln!(out, "{indent}{label}: ELSE");
                    stmts(out, &inner, label, else_);
                }
                let _ = writeln!(out, "{indent}{label}: END_IF");
            }
            Statement::Case {
                selector,
                arms,
                else_,
                ..
            } => {
                let inner = format!("{indent}  ");
                let _ = writeln!(out, "{indent}{label}: CASE {}", expr(selector));
                for (labels, body) in arms {
                    let _ = writeln!(out, "{indent}{label}: {labels:?}");
                    stmts(out, &inner, label, body);
                }
                if !else_.is_empty() {
                    let _ = writeln!(out, "{indent}{label}: ELSE");
                    stmts(out, &inner, label, else_);
                }
                let _ = writeln!(out, "{indent}{label}: END_CASE");
            }
            Statement::Call(c) => {
                let ins: Vec<String> = c
                    .inputs
                    .iter()
                    .map(|(m, e)| format!("{} := {}", m.name(), expr(e)))
                    .collect();
                let outs: Vec<String> = c
                    .outputs
                    .iter()
                    .map(|(m, p, ty)| format!("{} => {} ({ty})", m.name(), place(p)))
                    .collect();
                let _ = writeln!(
                    out,
                    "{indent}{label}: fb{}({}{}{})",
                    c.fb,
                    ins.join(", "),
                    if ins.is_empty() || outs.is_empty() {
                        ""
                    } else {
                        ", "
                    },
                    outs.join(", ")
                );
            }
        }
    }
}

fn time(t: &Option<TimeValue>) -> String {
    match t {
        None => "-".to_owned(),
        Some(TimeValue::Const(ms)) => format!("{ms}ms"),
        Some(TimeValue::Operand(o)) => operand(o),
    }
}

fn trans(out: &mut String, t: &Trans) {
    let from = t.from.map_or("any".to_owned(), |f| f.to_string());
    let to = match t.to {
        higraph_runtime::program::Target::State(n) => n.to_string(),
        higraph_runtime::program::Target::Return => "return".to_owned(),
    };
    let mut flags = String::new();
    for (on, word) in [
        (t.auto, " auto"),
        (t.manual, " manual"),
        (t.waits, " waits"),
    ] {
        if on {
            flags.push_str(word);
        }
    }
    let _ = writeln!(out, "    trans {from}->{to} prio {}{flags}", t.prio);
    for c in &t.conditions {
        block(out, "      ", "?", c);
    }
    for a in &t.actions {
        block(out, "      ", "!", a);
    }
}

/// The dump.
pub(crate) fn program(p: &Program) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "cells {}, private timers {}, private counters {}",
        p.cells.len(),
        p.private_timers,
        p.private_counters
    );
    for (i, g) in p.graphs.iter().enumerate() {
        let _ = writeln!(
            out,
            "graph{i} {} (startup {:?}, initial {:?})",
            g.name, g.startup, g.initial
        );
        for (v, var) in g.vars.iter().enumerate().skip(18) {
            let msg = match var.msg_in {
                Some(true) => " msg in",
                Some(false) => " msg out",
                None => "",
            };
            let init = var
                .init
                .as_ref()
                .map(|v| format!(" := {v:?}"))
                .unwrap_or_default();
            let _ = writeln!(out, "  var{v} {} : {}{msg}{init}", var.name, var.ty);
        }
        for b in &g.permanent_pre {
            block(&mut out, "  ", "permanent C-", b);
        }
        for b in &g.permanent_post {
            block(&mut out, "  ", "permanent C", b);
        }
        for t in &g.any {
            trans(&mut out, t);
        }
        for s in &g.states {
            let _ = writeln!(
                out,
                "  state {}{}{} wait {} supervise {}",
                s.number,
                s.name
                    .as_ref()
                    .map(|n| format!(" \"{n}\""))
                    .unwrap_or_default(),
                if s.reports { " reports" } else { "" },
                time(&s.wait),
                time(&s.supervise)
            );
            for (label, blocks) in [
                ("E", &s.entry),
                ("C-", &s.pre),
                ("C", &s.cyclic),
                ("X", &s.exit),
            ] {
                for b in blocks {
                    block(&mut out, "    ", label, b);
                }
            }
            for t in &s.transitions {
                trans(&mut out, t);
            }
        }
    }
    for g in &p.groups {
        let _ = writeln!(out, "group {} {:?}", g.name, g.options);
        for inst in &g.instances {
            let graph = &p.graphs[inst.graph as usize];
            let wired: Vec<String> = inst
                .binding
                .iter()
                .enumerate()
                .filter(|(_, pl)| !matches!(pl, Place::Cell(_)))
                .map(|(v, pl)| format!("{} = {}", graph.vars[v].name, place(pl)))
                .collect();
            let _ = writeln!(
                out,
                "  instance {} : graph{} [{}]",
                inst.name,
                inst.graph,
                wired.join(", ")
            );
        }
        for m in &g.internal_messages {
            let _ = writeln!(
                out,
                "  internal message inst{}.var{} cell{}",
                m.instance, m.var, m.cell
            );
        }
    }
    for c in &p.charts {
        let _ = writeln!(
            out,
            "chart {} auto {} switching {:?} cyclic {} time_monitoring {} autostart {}",
            c.name, c.mode_auto, c.switching, c.cyclic, c.time_monitoring, c.autostart
        );
        for (name, cell) in &c.vars {
            let _ = writeln!(out, "  var {name} cell{cell}");
        }
        if c.profile == Profile::Iec {
            let _ = writeln!(out, "  profile iec");
        }
        for (i, fb) in c.fbs.iter().enumerate() {
            let _ = writeln!(
                out,
                "  fb{i} {} : {} members {:?} state {:?}",
                fb.name,
                fb.ty.name(),
                fb.members,
                fb.state
            );
        }
        for (i, a) in c.actions.iter().enumerate() {
            let _ = writeln!(out, "  action{i} {} = {}", a.name, place(&a.place));
            if let Some(body) = &a.body {
                stmts(&mut out, "    ", "body", body);
            }
        }
        for s in &c.sequencers {
            let start: Vec<String> = s.start.iter().map(expr).collect();
            let _ = writeln!(
                out,
                "  sequencer {} prio {} start [{}]",
                s.name,
                s.prio,
                start.join("; ")
            );
            stmts(&mut out, "    ", "pre", &s.pre);
            stmts(&mut out, "    ", "post", &s.post);
            for (i, st) in s.steps.iter().enumerate() {
                let quals: Vec<String> = st
                    .qualifiers
                    .iter()
                    .map(|q| {
                        let t = q
                            .time
                            .as_ref()
                            .map(|t| format!(", {}", expr(t)))
                            .unwrap_or_default();
                        format!("{:?} action{}{t}", q.qualifier, q.action)
                    })
                    .collect();
                let _ = writeln!(
                    out,
                    "    step{i} {} candidates {:?}{}{}{}{}",
                    st.name,
                    st.candidates,
                    if quals.is_empty() {
                        String::new()
                    } else {
                        format!(" [{}]", quals.join("; "))
                    },
                    st.min
                        .as_ref()
                        .map(|m| format!(" min {}", expr(m)))
                        .unwrap_or_default(),
                    st.max
                        .as_ref()
                        .map(|m| format!(" max {}", expr(m)))
                        .unwrap_or_default(),
                    if st.confirm { " confirm" } else { "" }
                );
                stmts(&mut out, "      ", "init", &st.init);
                stmts(&mut out, "      ", "run", &st.run);
                stmts(&mut out, "      ", "term", &st.term);
            }
            for (i, t) in s.transitions.iter().enumerate() {
                let conds: Vec<String> = t.conditions.iter().map(expr).collect();
                let _ = writeln!(
                    out,
                    "    trans{i} {:?} {} {:?}->{:?} [{}]",
                    t.kind,
                    t.name.as_deref().unwrap_or("-"),
                    t.from,
                    t.to,
                    conds.join("; ")
                );
            }
        }
    }
    for (i, b) in p.blocks.iter().enumerate() {
        let _ = writeln!(out, "block{i} {}", b.name);
    }
    if let Some(t) = &p.test {
        let run: Vec<String> = t.run.iter().map(|r| format!("{r:?}")).collect();
        let _ = writeln!(
            out,
            "test {} cycle {}ms run [{}]",
            t.name,
            t.cycle_ms,
            run.join(", ")
        );
        for s in &t.stmts {
            let line = match &s.kind {
                TestStmtKind::Set { target, value } => {
                    format!("set {} := {}", path(target), expr(value))
                }
                TestStmtKind::Step { cycles } => format!("step {cycles}"),
                TestStmtKind::Until {
                    cond,
                    cycles,
                    within,
                    message,
                    ..
                } => format!(
                    "until {} within {within} ({cycles} cycles) {message:?}",
                    expr(cond)
                ),
                TestStmtKind::Expect { cond, message, .. } => {
                    format!("expect {} {message:?}", expr(cond))
                }
                TestStmtKind::Command { chart, command } => {
                    format!("command chart{chart} {command:?}")
                }
                TestStmtKind::Confirm {
                    chart,
                    sequencer,
                    step,
                    text,
                } => format!("confirm chart{chart}.seq{sequencer}.step{step} ({text})"),
                TestStmtKind::Restart { cold } => {
                    format!("restart {}", if *cold { "cold" } else { "warm" })
                }
            };
            let _ = writeln!(out, "  {line}");
        }
        let watch: Vec<&str> = t.watch.iter().map(|p| p.text.as_str()).collect();
        let _ = writeln!(out, "  watch [{}]", watch.join(", "));
    }
    out
}
