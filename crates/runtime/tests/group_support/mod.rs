//! Test support for the group engine: hand-built programs from a few lines of text, and a tiny
//! driver that runs machine cycles like the runner does (clock, INIT_SD, restarts).
//!
//! The STL here is a small subset in SIMATIC mnemonics: bit logic, `L`/`T`, `+ n`; operands
//! are graph variables (`Start`, `#Zaehler`, `INIT_SD`), absolute addresses (`M 0.1`, `MW 4`,
//! `MD 8`) and integer or `T#…MS` constants. Bodies are `label: stmt; stmt; label: …` with the
//! labels `E C- C X` (states), `?` and `!` (transitions), `C-` and `C` (permanent).
#![allow(dead_code)]

use higraph_runtime::group::{self, GroupRt};
use higraph_runtime::program::CellInfo;
use higraph_runtime::program::{
    Block, Graph, GraphId, Group, GroupOptions, Instance, Instr, InternalMessage, MemArea, OpCode,
    Operand, Origin, Place, Predef, Program, State, Target, TimeValue, Trans, VarInfo, Width,
};
use higraph_runtime::trace::InstanceRecord;
use higraph_runtime::{Fault, Machine, Ty, Value};

// ----------------------------------------------------------------------------------- STL

fn parse_addr(text: &str) -> Option<Place> {
    let t = text.trim();
    let split = t.find(|c: char| c.is_ascii_digit() || c == ' ')?;
    let (area_text, rest) = t.split_at(split);
    let rest = rest.trim();
    let (area, width_letter) = match area_text {
        "M" => (MemArea::Memory, None),
        "MB" | "MW" | "MD" => (MemArea::Memory, area_text.chars().nth(1)),
        "E" | "I" => (MemArea::Input, None),
        "EB" | "EW" | "ED" => (MemArea::Input, area_text.chars().nth(1)),
        "A" | "Q" => (MemArea::Output, None),
        "AB" | "AW" | "AD" => (MemArea::Output, area_text.chars().nth(1)),
        _ => return None,
    };
    let width_of = |c: Option<char>| match c {
        Some('B') => Width::Byte,
        Some('W') => Width::Word,
        _ => Width::Dword,
    };
    match width_letter {
        None => {
            let (byte, bit) = rest.split_once('.')?;
            Some(Place::Mem {
                area,
                byte: byte.trim().parse().ok()?,
                width: Width::Bit(bit.trim().parse().ok()?),
            })
        }
        w => Some(Place::Mem {
            area,
            byte: rest.parse().ok()?,
            width: width_of(w),
        }),
    }
}

fn parse_time_ms(text: &str) -> Option<i64> {
    let t = text.trim().to_ascii_uppercase();
    let ms = t.strip_prefix("T#")?.strip_suffix("MS")?;
    ms.parse().ok()
}

fn var_index(vars: &[VarInfo], name: &str) -> Option<u16> {
    let name = name.trim().trim_start_matches('#');
    vars.iter()
        .position(|v| v.name.eq_ignore_ascii_case(name))
        .map(|i| i as u16)
}

fn operand(vars: &[VarInfo], text: &str) -> Operand {
    let t = text.trim();
    if t.is_empty() {
        return Operand::None;
    }
    if let Some(p) = parse_addr(t) {
        return Operand::Place(p);
    }
    if let Some(ms) = parse_time_ms(t) {
        return Operand::Imm(ms as i32 as u32);
    }
    if let Ok(n) = t.parse::<i64>() {
        return Operand::Imm(if (-32768..=32767).contains(&n) {
            n as i16 as u16 as u32
        } else {
            n as i32 as u32
        });
    }
    match var_index(vars, t) {
        Some(i) => Operand::Var(i),
        None => panic!("test STL: unknown operand {t:?}"),
    }
}

fn instr(vars: &[VarInfo], stmt: &str) -> Instr {
    let stmt = stmt.trim();
    let (op_text, rest) = stmt.split_once(' ').unwrap_or((stmt, ""));
    let op = match op_text.to_ascii_uppercase().as_str() {
        "U" | "A" => OpCode::U,
        "UN" | "AN" => OpCode::Un,
        "O" if rest.trim().is_empty() => OpCode::OrNone,
        "O" => OpCode::O,
        "ON" => OpCode::On,
        "X" => OpCode::X,
        "XN" => OpCode::Xn,
        "=" => OpCode::Assign,
        "S" => OpCode::S,
        "R" => OpCode::R,
        "SET" => OpCode::Set,
        "CLR" => OpCode::Clr,
        "NOT" => OpCode::Not,
        "FP" => OpCode::Fp,
        "FN" => OpCode::Fn,
        "L" => OpCode::L,
        "T" => OpCode::T,
        "+" => OpCode::AddInt,
        "+I" => OpCode::AddI,
        "-I" => OpCode::SubI,
        "==I" => OpCode::EqI,
        ">=I" => OpCode::GeI,
        other => panic!("test STL: unknown operation {other:?}"),
    };
    Instr {
        op,
        operand: operand(vars, rest),
        origin: Origin::NONE,
    }
}

/// `label: stmt; stmt; label: stmt;` → (label, block) in text order; the statements before the
/// first label get the label "".
pub fn body(vars: &[VarInfo], text: &str) -> Vec<(String, Block)> {
    let mut out: Vec<(String, Block)> = Vec::new();
    for raw in text.split(';') {
        let mut stmt = raw.trim();
        if stmt.is_empty() {
            continue;
        }
        // A label is the first word when it ends with ':' (`E:`, `C-:`, `?:`, `!:`).
        if let Some((first, rest)) = stmt.split_once(':')
            && matches!(first.trim(), "E" | "C" | "C-" | "X" | "?" | "!")
        {
            out.push((first.trim().to_owned(), Block::default()));
            stmt = rest.trim();
            if stmt.is_empty() {
                continue;
            }
        }
        if out.is_empty() {
            out.push((String::new(), Block::default()));
        }
        let vars_ref = vars;
        out.last_mut()
            .map(|(_, b)| b.code.push(instr(vars_ref, stmt)))
            .unwrap_or(());
    }
    out
}

// -------------------------------------------------------------------------------- graphs

pub struct GraphB {
    g: Graph,
}

impl GraphB {
    /// A graph with the predefined variables and `vars` (name, type) declared in order.
    pub fn new(name: &str, vars: &[(&str, Ty)]) -> GraphB {
        let mut all: Vec<VarInfo> = Predef::ALL
            .iter()
            .map(|p| VarInfo {
                name: p.name().to_owned(),
                ty: p.ty(),
                msg_in: None,
                init: None,
            })
            .collect();
        for (n, ty) in vars {
            all.push(VarInfo {
                name: (*n).to_owned(),
                ty: *ty,
                msg_in: None,
                init: None,
            });
        }
        GraphB {
            g: Graph {
                name: name.to_owned(),
                vars: all,
                states: Vec::new(),
                any: Vec::new(),
                startup: None,
                initial: None,
                permanent_pre: Vec::new(),
                permanent_post: Vec::new(),
            },
        }
    }

    /// Marks a variable `msg in` (`true`) or `msg out`.
    pub fn msg(mut self, name: &str, msg_in: bool) -> GraphB {
        let i = var_index(&self.g.vars, name).expect("msg variable") as usize;
        self.g.vars[i].msg_in = Some(msg_in);
        self
    }

    /// A state with its body (`E: …; C-: …; C: …; X: …;`).
    pub fn state(mut self, number: u16, text: &str) -> GraphB {
        let mut st = State {
            number,
            name: None,
            reports: false,
            entry: Vec::new(),
            pre: Vec::new(),
            cyclic: Vec::new(),
            exit: Vec::new(),
            wait: None,
            supervise: None,
            transitions: Vec::new(),
        };
        for (label, block) in body(&self.g.vars, text) {
            match label.as_str() {
                "E" => st.entry.push(block),
                "C-" => st.pre.push(block),
                "C" => st.cyclic.push(block),
                "X" => st.exit.push(block),
                other => panic!("state label {other:?}"),
            }
        }
        self.g.states.push(st);
        self
    }

    fn state_mut(&mut self, number: u16) -> &mut State {
        self.g
            .states
            .iter_mut()
            .find(|s| s.number == number)
            .expect("state")
    }

    pub fn wait(mut self, number: u16, value: TimeValue) -> GraphB {
        self.state_mut(number).wait = Some(value);
        self
    }

    pub fn supervise(mut self, number: u16, value: TimeValue) -> GraphB {
        self.state_mut(number).supervise = Some(value);
        self
    }

    /// `fault` / `message` state.
    pub fn reports(mut self, number: u16) -> GraphB {
        self.state_mut(number).reports = true;
        self
    }

    /// The declared initial value of a variable.
    pub fn init(mut self, name: &str, value: Value) -> GraphB {
        let i = var_index(&self.g.vars, name).expect("variable") as usize;
        self.g.vars[i].init = Some(value);
        self
    }

    pub fn permanent(mut self, text: &str) -> GraphB {
        for (label, block) in body(&self.g.vars, text) {
            match label.as_str() {
                "C-" => self.g.permanent_pre.push(block),
                "C" => self.g.permanent_post.push(block),
                other => panic!("permanent label {other:?}"),
            }
        }
        self
    }

    /// `A->B [prio n] [auto] [manual] [waits]` with A = `any` or a number, B a number or
    /// `return`; body: conditions (unlabelled, `?:`) and actions (`!:`). Transitions must be
    /// added after the states they leave.
    pub fn trans(mut self, header: &str, text: &str) -> GraphB {
        let mut words = header.split_whitespace();
        let arrow = words.next().expect("A->B");
        let (a, b) = arrow.split_once("->").expect("A->B");
        let from = if a == "any" {
            None
        } else {
            Some(a.parse::<u16>().expect("from"))
        };
        let to = if b == "return" {
            Target::Return
        } else {
            Target::State(b.parse().expect("to"))
        };
        // Default priority: text order among the transitions of the same list.
        let default_prio = match from {
            None => self.g.any.len() as u32 + 1,
            Some(n) => self.state_mut(n).transitions.len() as u32 + 1,
        };
        let mut t = Trans {
            from,
            to,
            prio: default_prio,
            auto: false,
            manual: false,
            waits: false,
            conditions: Vec::new(),
            actions: Vec::new(),
            origin: Origin::NONE,
        };
        while let Some(w) = words.next() {
            match w {
                "prio" => t.prio = words.next().and_then(|p| p.parse().ok()).expect("prio"),
                "auto" => t.auto = true,
                "manual" => t.manual = true,
                "waits" => t.waits = true,
                other => panic!("transition attribute {other:?}"),
            }
        }
        for (label, block) in body(&self.g.vars, text) {
            match label.as_str() {
                "" | "?" => t.conditions.push(block),
                "!" => t.actions.push(block),
                other => panic!("transition label {other:?}"),
            }
        }
        match from {
            None => self.g.any.push(t),
            Some(n) => self.state_mut(n).transitions.push(t),
        }
        self
    }

    pub fn build(mut self) -> Graph {
        self.g.any.sort_by_key(|t| t.prio);
        for st in &mut self.g.states {
            st.transitions.sort_by_key(|t| t.prio);
        }
        let init_sd = Predef::InitSd.var();
        self.g.startup = self.g.any.iter().position(|t| {
            t.conditions
                .iter()
                .flat_map(|b| &b.code)
                .any(|i| i.operand == Operand::Var(init_sd))
        });
        self.g.initial = self.g.startup.and_then(|i| match self.g.any[i].to {
            Target::State(n) => Some(n),
            Target::Return => None,
        });
        self.g
    }
}

// ------------------------------------------------------------------------------- programs

pub struct ProgramB {
    p: Program,
}

/// An instance: name, graph, wiring `(formal, actual)` with actuals `M 0.0`, `Inst.Var`,
/// `TRUE`/`FALSE`, an integer.
pub type InstSpec<'a> = (&'a str, GraphId, &'a [(&'a str, &'a str)]);

impl ProgramB {
    pub fn new() -> ProgramB {
        ProgramB {
            p: Program::default(),
        }
    }

    pub fn graph(&mut self, g: Graph) -> GraphId {
        self.p.graphs.push(g);
        (self.p.graphs.len() - 1) as GraphId
    }

    pub fn group(&mut self, name: &str, options: GroupOptions, instances: &[InstSpec<'_>]) -> u32 {
        // Every instance gets a cell for every variable (§2.1), allocated first so that
        // `Inst.Msg` actuals can name later instances.
        let mut first_cell = Vec::new();
        for (_, graph, _) in instances {
            first_cell.push(self.p.cells.len() as u32);
            for (i, v) in self.p.graphs[*graph as usize].vars.iter().enumerate() {
                let init = if i == Predef::StateChange.var() as usize {
                    Value::Bool(true)
                } else {
                    v.init.clone().unwrap_or_else(|| Value::zero(v.ty))
                };
                self.p.cells.push(CellInfo { ty: v.ty, init });
            }
        }
        let mut group = Group {
            name: name.to_owned(),
            options,
            instances: Vec::new(),
            internal_messages: Vec::new(),
        };
        for (k, (iname, graph, wiring)) in instances.iter().enumerate() {
            let vars = &self.p.graphs[*graph as usize].vars;
            let mut binding: Vec<Place> = (0..vars.len())
                .map(|i| Place::Cell(first_cell[k] + i as u32))
                .collect();
            for (formal, actual) in *wiring {
                let i = var_index(vars, formal).expect("formal") as usize;
                binding[i] = if let Some(p) = parse_addr(actual) {
                    p
                } else if actual.eq_ignore_ascii_case("TRUE") {
                    Place::Const(Value::Bool(true))
                } else if actual.eq_ignore_ascii_case("FALSE") {
                    Place::Const(Value::Bool(false))
                } else if let Ok(n) = actual.parse::<i16>() {
                    Place::Const(Value::Int(n))
                } else {
                    let (inst, var) = actual.split_once('.').expect("Inst.Var");
                    let j = instances
                        .iter()
                        .position(|(n, _, _)| *n == inst)
                        .expect("instance");
                    let target_vars = &self.p.graphs[instances[j].1 as usize].vars;
                    let vi = var_index(target_vars, var).expect("variable");
                    let cell = first_cell[j] + u32::from(vi);
                    if target_vars[vi as usize].msg_in == Some(true) {
                        group.internal_messages.push(InternalMessage {
                            instance: j as u32,
                            var: vi,
                            cell,
                        });
                    }
                    Place::Cell(cell)
                };
            }
            group.instances.push(Instance {
                name: (*iname).to_owned(),
                graph: *graph,
                binding,
            });
        }
        self.p.groups.push(group);
        (self.p.groups.len() - 1) as u32
    }

    pub fn build(self) -> Program {
        self.p
    }
}

impl Default for ProgramB {
    fn default() -> Self {
        ProgramB::new()
    }
}

// ---------------------------------------------------------------------------------- driver

/// Runs machine cycles the way the runner does: cycle k at t = k·Δ, INIT_SD = 1 in the first
/// cycle and after a restart, every group of the program in program order.
pub struct Sim {
    pub program: Program,
    pub m: Machine,
    pub rts: Vec<GroupRt>,
    pub cycle: u64,
    pub cycle_ms: u32,
    init_sd: bool,
    /// Record the turns (`records` then holds the last cycle's).
    pub record: bool,
    pub records: Vec<InstanceRecord>,
}

impl Sim {
    pub fn new(program: Program) -> Sim {
        let m = Machine::new(&program);
        // Like the runner: Δ is the test's (10 ms without one); the groups take it from the
        // program.
        let cycle_ms = program.test.as_ref().map_or(10, |t| t.cycle_ms);
        let rts = program.groups.iter().map(|_| GroupRt::new()).collect();
        Sim {
            program,
            m,
            rts,
            cycle: 0,
            cycle_ms,
            init_sd: true,
            record: true,
            records: Vec::new(),
        }
    }

    pub fn try_step(&mut self) -> Result<(), Fault> {
        self.cycle += 1;
        self.m.now_ms = self.cycle * u64::from(self.cycle_ms);
        self.records.clear();
        let init_sd = std::mem::replace(&mut self.init_sd, false);
        for (g, rt) in self.rts.iter_mut().enumerate() {
            let rec = if self.record {
                Some(&mut self.records)
            } else {
                None
            };
            group::call(&mut self.m, &self.program, g as u32, rt, init_sd, rec)?;
        }
        Ok(())
    }

    pub fn step(&mut self) {
        if let Err(f) = self.try_step() {
            panic!("fault in cycle {}: {}", self.cycle, f.reason);
        }
    }

    /// `restart cold|warm` between cycles (§2.8).
    pub fn restart(&mut self, cold: bool) {
        if cold {
            self.m.restart_cold(&self.program);
        }
        for rt in &mut self.rts {
            rt.restart(cold);
        }
        self.init_sd = true;
    }

    pub fn set(&mut self, addr: &str, bits: u32) {
        let p = parse_addr(addr).expect("address");
        self.m.write(&p, bits).expect("write");
    }

    pub fn mem(&mut self, addr: &str) -> u32 {
        let p = parse_addr(addr).expect("address");
        self.m.read(&p).expect("read")
    }

    fn place(&self, group: &str, inst: &str, var: &str) -> Place {
        let g = self
            .program
            .groups
            .iter()
            .find(|g| g.name == group)
            .expect("group");
        let i = g
            .instances
            .iter()
            .find(|i| i.name == inst)
            .expect("instance");
        let vars = &self.program.graphs[i.graph as usize].vars;
        let vi = var_index(vars, var).expect("variable") as usize;
        i.binding[vi].clone()
    }

    /// An instance variable through its binding (the actual when wired).
    pub fn var(&mut self, group: &str, inst: &str, var: &str) -> u32 {
        let p = self.place(group, inst, var);
        self.m.read(&p).expect("read")
    }

    pub fn set_var(&mut self, group: &str, inst: &str, var: &str, bits: u32) {
        let p = self.place(group, inst, var);
        self.m.write(&p, bits).expect("write");
    }

    /// The record of one instance in the last cycle.
    pub fn rec(&self, group: &str, inst: &str) -> &InstanceRecord {
        self.records
            .iter()
            .find(|r| r.group == group && r.instance == inst)
            .expect("record")
    }
}
