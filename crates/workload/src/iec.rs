//! Random IEC 61131-3 charts (`profile iec;`, `docs/iec.md`), for the PLCopen round trip.
//!
//! [`iec_chart`] writes one chart from a seed: one sequencer whose first step is the initial
//! step, steps and transitions, `alt` branches that converge, end in a `jump` or consist of a
//! single `jump`, `parallel` branches, an optional cyclic `jump` after the last step; every
//! qualifier (`N S R P L D SD DS SL P1 P0 DL`, with durations) on BOOL outputs and on named
//! actions; action bodies with assignments, arithmetic (`+ - * / MOD`, unary `-`),
//! `IF`/`ELSIF`/`ELSE`, `CASE` and calls of standard function blocks; conditions with `Step.X`,
//! function block outputs and comparisons.
//!
//! Step code lives in named actions (after the sequencer, where the import writes them), not in
//! `init`/`run`/`term` parts: PLCopen has no step parts, the export writes them as inline
//! `P1`/`N`/`P0` actions and the import reads inline actions back as named actions, so a chart
//! with step parts does not come back as the same text (`docs/build.md`, IEC charts). With
//! `phases`, [`iec_chart_with`] writes step parts too (for tests of the checker and export).
//!
//! The text checks clean (no error, no warning; the round trip asserts it): types match (`INT`
//! with `INT`, `DINT` with `DINT`, no constant zero divisor), `CASE` labels never overlap,
//! `term` writes only `Last_Step` (which nothing else writes, HG7311), no transition is the
//! constant `TRUE` or `FALSE` (HG7012), every variable name is unique, and the alternative
//! branches follow the shapes described at [`Gen::trans_kind`]. Output depends on the seed
//! only.

use std::fmt::Write as _;

use crate::rng::Rng;

/// Names of the standard function block instances the generator may declare, with their type.
const FBS: &[(&str, &str)] = &[
    ("Timer1", "TON"),
    ("Timer2", "TOF"),
    ("Pulse1", "TP"),
    ("Edge1", "R_TRIG"),
    ("Edge2", "F_TRIG"),
    ("Counter1", "CTU"),
    ("Counter2", "CTD"),
    ("Counter3", "CTUD"),
    ("Latch1", "SR"),
    ("Latch2", "RS"),
];

const STEP_WORDS: &[&str] = &[
    "Fill", "Heat", "Stir", "Dose", "Wait", "Drain", "Rinse", "Check", "Cool", "Mix",
];

const OUTPUTS: &[&str] = &["Motor", "Lamp", "Valve", "Horn", "Pump", "Fan"];

/// Precedence levels of `docs/iec.md` §4 (higher binds tighter); atoms are [`ATOM`].
const OR: u8 = 1;
const XOR: u8 = 2;
const AND: u8 = 3;
const CMP: u8 = 4;
const ADD: u8 = 5;
const MUL: u8 = 6;
const UNARY: u8 = 7;
const ATOM: u8 = 8;

/// The text of one generated IEC chart, named `Gen<seed>`, without step parts.
pub fn iec_chart(seed: u64) -> String {
    iec_chart_with(seed, false)
}

/// [`iec_chart`], with `init`/`run`/`term` parts in some steps when `phases` is set.
pub fn iec_chart_with(seed: u64, phases: bool) -> String {
    let mut g = Gen {
        phases,
        cyclic: false,
        rng: Rng::new(seed ^ 0x1EC6_1131),
        fbs: Vec::new(),
        actions: Vec::new(),
        steps: Vec::new(),
        step_count: 0,
        trans_count: 0,
        jump_count: 0,
    };
    g.chart(seed)
}

struct Gen {
    /// Write `init`/`run`/`term` parts.
    phases: bool,
    /// The sequencer ends with jumps.
    cyclic: bool,
    rng: Rng,
    /// Declared function block instances: (name, type).
    fbs: Vec<(&'static str, &'static str)>,
    /// Names of the named actions.
    actions: Vec<String>,
    /// Steps declared so far (all of them, for `Step.X`).
    steps: Vec<String>,
    step_count: usize,
    trans_count: usize,
    jump_count: usize,
}

/// One element of a generated list.
enum El {
    Step(String),
    Trans(String),
    Jump(String),
    Alt(Vec<Vec<El>>),
    Parallel(Vec<Vec<El>>),
}

fn wrap(text: String, prec: u8, min: u8) -> String {
    if prec < min {
        format!("({text})")
    } else {
        text
    }
}

impl Gen {
    fn chart(&mut self, seed: u64) -> String {
        let mut fbs: Vec<(&'static str, &'static str)> = FBS.to_vec();
        self.rng.shuffle(&mut fbs);
        let n = self.rng.range(1, 5);
        fbs.truncate(n);
        // Declaration order as in FBS: stable text.
        fbs.sort_by_key(|(name, _)| FBS.iter().position(|(n, _)| n == name));
        self.fbs = fbs;
        let n_actions = self.rng.range(1, 4);
        self.actions = (1..=n_actions).map(|k| format!("Action_{k}")).collect();

        let mut out = String::new();
        let _ = writeln!(out, "chart Gen{seed} \"generated IEC chart {seed}\" <");
        out.push_str("  profile iec;\n");
        out.push_str("  in <\n    Start : BOOL;\n    Stop : BOOL \"stop request\";\n");
        out.push_str("    Level : INT;\n    Setpoint : REAL;\n  >\n");
        out.push_str("  out <\n");
        for o in OUTPUTS {
            let _ = writeln!(out, "    {o} : BOOL;");
        }
        out.push_str("  >\n  stat <\n");
        out.push_str("    Count : INT := 0 \"parts\";\n    Mode : DINT := 1;\n");
        out.push_str("    Ready : BOOL;\n    Ratio : REAL := 1.5;\n");
        out.push_str("    Delay : TIME := T#2s;\n    Elapsed : TIME;\n    Last_Step : INT;\n");
        for (name, ty) in self.fbs.clone() {
            let _ = writeln!(out, "    {name} : {ty};");
        }
        out.push_str("  >\n");
        // The first step is declared before anything refers to it.
        let first = self.step_name();
        let mut list = vec![El::Step(first.clone())];
        let mut body_steps = vec![first];
        let len = self.rng.range(1, 4);
        self.cyclic = self.rng.percent(60);
        for k in 0..len {
            let after_step = matches!(list.last(), Some(El::Step(_)));
            let targets = body_steps.clone();
            list.extend(self.trans_kind(0, false, after_step, &targets));
            // The sequencer ends with a plain step (HG7001).
            let step = if k + 1 == len {
                let name = self.step_name();
                body_steps.push(name.clone());
                El::Step(name)
            } else {
                self.step_kind(0, &mut body_steps)
            };
            list.push(step);
        }
        // Cyclic: one or two jumps after the last step.
        if self.cyclic {
            for _ in 0..self.rng.range(1, 2) {
                let target = self.rng.pick(&body_steps).clone();
                list.push(El::Jump(target));
            }
        }
        out.push_str("  sequencer Main <\n");
        self.list(&list, 2, &mut out);
        out.push_str("  >\n");
        for name in self.actions.clone() {
            let comment = if self.rng.percent(50) {
                format!(" \"does {}\"", name.to_ascii_lowercase())
            } else {
                String::new()
            };
            let _ = writeln!(out, "  action {name}{comment} <");
            let n = self.rng.range(1, 3);
            for _ in 0..n {
                self.statement(2, 2, &mut out);
            }
            out.push_str("  >\n");
        }
        out.push_str(">\n");
        out
    }

    fn step_name(&mut self) -> String {
        self.step_count += 1;
        let word = self.rng.choose(STEP_WORDS);
        let name = if self.rng.percent(20) {
            format!("Step_{}_{word}_and_wait_long", self.step_count)
        } else {
            format!("S{}_{word}", self.step_count)
        };
        self.steps.push(name.clone());
        name
    }

    /// A step, or (shallow) a parallel of 2..3 branches, each beginning and ending with a step.
    fn step_kind(&mut self, depth: usize, top: &mut Vec<String>) -> El {
        if depth < 2 && self.rng.percent(15) {
            let n = self.rng.range(2, 3);
            let branches = (0..n)
                .map(|_| {
                    let mut b = vec![El::Step(self.step_name())];
                    if self.rng.percent(40) {
                        let after_step = true;
                        b.extend(self.trans_kind(depth + 1, true, after_step, &[]));
                        b.push(El::Step(self.step_name()));
                    }
                    b
                })
                .collect();
            El::Parallel(branches)
        } else {
            let name = self.step_name();
            if depth == 0 {
                top.push(name.clone());
            }
            El::Step(name)
        }
    }

    /// A transition, or (shallow) an alt of 2..3 branches; `after_step`: the element before is a
    /// plain step. Outside parallels, a branch may end with a jump to one of `targets` or be a
    /// single jump.
    ///
    /// The shapes are those the import writes back (the XML cannot tell the others apart): an
    /// alt with one branch that continues (all others end in a jump) has no convergence in
    /// PLCopen, so that branch is a single transition; if it is the first branch, follows a
    /// plain step and every other branch is a single jump, the chart says it with jumps after
    /// the step (`step S; jump J -> X < c >; trans T`), which means the same.
    fn trans_kind(
        &mut self,
        depth: usize,
        in_parallel: bool,
        after_step: bool,
        targets: &[String],
    ) -> Vec<El> {
        if depth >= 2 || !self.rng.percent(30) {
            return vec![El::Trans(self.trans_name())];
        }
        let n = self.rng.range(2, 3);
        // A jump (also as a whole branch) must follow a step (HG7009).
        let jumps_allowed = !in_parallel && after_step && !targets.is_empty();
        // Which branches continue: one, or all but some jumps. In a cyclic chart, a single
        // continuing branch would reach the final jump, and the import keeps all that follows
        // inside the branch (it means the same): not generated.
        let single_open = jumps_allowed && !self.cyclic && self.rng.percent(50);
        let open = self.rng.below(n);
        // Otherwise at least two branches converge: with three, one may end in a jump.
        let jumper = if n == 3 && self.rng.percent(50) {
            (open + 1 + self.rng.below(2)) % 3
        } else {
            n
        };
        let mut branches: Vec<Vec<El>> = Vec::with_capacity(n);
        for i in 0..n {
            let jumps = jumps_allowed && i != open && (single_open || i == jumper);
            let branch = if jumps {
                let target = self.rng.pick(targets).clone();
                if self.rng.percent(50) {
                    vec![El::Jump(target)]
                } else {
                    vec![
                        El::Trans(self.trans_name()),
                        El::Step(self.step_name()),
                        El::Jump(target),
                    ]
                }
            } else if !single_open && self.rng.percent(40) {
                let t = El::Trans(self.trans_name());
                let s = El::Step(self.step_name());
                vec![t, s, El::Trans(self.trans_name())]
            } else {
                vec![El::Trans(self.trans_name())]
            };
            branches.push(branch);
        }
        let others_single_jumps = branches
            .iter()
            .enumerate()
            .all(|(i, b)| i == open || matches!(b.as_slice(), [El::Jump(_)]));
        if single_open && open == 0 && after_step && others_single_jumps {
            let normal = branches.remove(0);
            let mut out: Vec<El> = branches.into_iter().flatten().collect();
            out.extend(normal);
            return out;
        }
        vec![El::Alt(branches)]
    }

    fn trans_name(&mut self) -> String {
        self.trans_count += 1;
        format!("T{}", self.trans_count)
    }

    fn indent(out: &mut String, level: usize) {
        for _ in 0..level {
            out.push_str("  ");
        }
    }

    fn list(&mut self, list: &[El], level: usize, out: &mut String) {
        for el in list {
            match el {
                El::Step(name) => self.step(name, level, out),
                El::Trans(name) => {
                    Self::indent(out, level);
                    let cond = self.condition();
                    let comment = if self.rng.percent(15) {
                        " \"go on\""
                    } else {
                        ""
                    };
                    let _ = writeln!(out, "trans {name}{comment} < {cond}; >");
                }
                El::Jump(target) => {
                    self.jump_count += 1;
                    Self::indent(out, level);
                    let cond = self.condition();
                    let _ = writeln!(out, "jump Back_{} -> {target} < {cond}; >", self.jump_count);
                }
                El::Alt(branches) | El::Parallel(branches) => {
                    Self::indent(out, level);
                    let kw = if matches!(el, El::Alt(_)) {
                        "alt"
                    } else {
                        "parallel"
                    };
                    let _ = writeln!(out, "{kw} <");
                    for b in branches {
                        Self::indent(out, level + 1);
                        out.push_str("branch <\n");
                        self.list(b, level + 2, out);
                        Self::indent(out, level + 1);
                        out.push_str(">\n");
                    }
                    Self::indent(out, level);
                    out.push_str(">\n");
                }
            }
        }
    }

    fn step(&mut self, name: &str, level: usize, out: &mut String) {
        Self::indent(out, level);
        let comment = if self.rng.percent(15) {
            format!(" \"step {name}\"")
        } else {
            String::new()
        };
        let _ = writeln!(out, "step {name}{comment} <");
        if self.phases && self.rng.percent(30) {
            self.phase("init", level + 1, out);
        }
        // Qualifier actions: each output or action at most once per step.
        let mut operands: Vec<String> = OUTPUTS.iter().map(|s| s.to_string()).collect();
        operands.extend(self.actions.iter().cloned());
        self.rng.shuffle(&mut operands);
        let n = self.rng.range(0, 3).min(operands.len());
        for op in operands.into_iter().take(n) {
            let q = self.rng.choose(&[
                "N", "S", "R", "P", "L", "D", "SD", "DS", "SL", "P1", "P0", "DL",
            ]);
            Self::indent(out, level + 1);
            if matches!(q, "L" | "D" | "SD" | "DS" | "SL" | "DL") {
                let t = self
                    .rng
                    .choose(&["T#5s", "T#2s", "T#500ms", "T#1m30s", "Delay"]);
                let _ = writeln!(out, "{q} {op}, {t};");
            } else {
                let _ = writeln!(out, "{q} {op};");
            }
        }
        if self.phases && self.rng.percent(40) {
            self.phase("run", level + 1, out);
        }
        if self.phases && self.rng.percent(15) {
            Self::indent(out, level + 1);
            let _ = writeln!(out, "term < Last_Step := {}; >", self.steps.len());
        }
        Self::indent(out, level);
        out.push_str(">\n");
    }

    fn phase(&mut self, kw: &str, level: usize, out: &mut String) {
        Self::indent(out, level);
        let _ = writeln!(out, "{kw} <");
        let n = self.rng.range(1, 3);
        for _ in 0..n {
            self.statement(level + 1, 2, out);
        }
        Self::indent(out, level);
        out.push_str(">\n");
    }

    // ------------------------------------------------------------------------ statements

    /// One statement at `level`; `depth` bounds the nesting of IF/CASE.
    fn statement(&mut self, level: usize, depth: usize, out: &mut String) {
        let kind = if depth == 0 { 0 } else { self.rng.below(10) };
        match kind {
            7 => self.if_stmt(level, depth, out),
            8 => self.case_stmt(level, depth, out),
            9 if !self.fbs.is_empty() => self.call(level, out),
            _ => {
                let text = self.assignment();
                Self::indent(out, level);
                out.push_str(&text);
                out.push('\n');
            }
        }
    }

    fn block(&mut self, level: usize, depth: usize, out: &mut String) {
        let n = self.rng.range(1, 2);
        for _ in 0..n {
            self.statement(level, depth, out);
        }
    }

    fn if_stmt(&mut self, level: usize, depth: usize, out: &mut String) {
        Self::indent(out, level);
        let c = self.condition();
        let _ = writeln!(out, "IF {c} THEN");
        self.block(level + 1, depth - 1, out);
        for _ in 0..self.rng.range(0, 2) {
            Self::indent(out, level);
            let c = self.condition();
            let _ = writeln!(out, "ELSIF {c} THEN");
            self.block(level + 1, depth - 1, out);
        }
        if self.rng.percent(50) {
            Self::indent(out, level);
            out.push_str("ELSE\n");
            self.block(level + 1, depth - 1, out);
        }
        Self::indent(out, level);
        out.push_str("END_IF;\n");
    }

    fn case_stmt(&mut self, level: usize, depth: usize, out: &mut String) {
        Self::indent(out, level);
        let selector = if self.rng.percent(30) {
            self.dint(1).0
        } else {
            self.int(1).0
        };
        let _ = writeln!(out, "CASE {selector} OF");
        // Increasing, disjoint labels and ranges.
        let mut next: i64 = -3 + self.rng.below(3) as i64;
        for _ in 0..self.rng.range(1, 3) {
            let mut labels = Vec::new();
            for _ in 0..self.rng.range(1, 2) {
                let lo = next + self.rng.below(3) as i64;
                if self.rng.percent(30) {
                    let hi = lo + 1 + self.rng.below(3) as i64;
                    labels.push(format!("{lo}..{hi}"));
                    next = hi + 1;
                } else {
                    labels.push(lo.to_string());
                    next = lo + 1;
                }
            }
            Self::indent(out, level + 1);
            let _ = writeln!(out, "{}:", labels.join(", "));
            self.block(level + 2, depth - 1, out);
        }
        if self.rng.percent(50) {
            Self::indent(out, level + 1);
            out.push_str("ELSE\n");
            self.block(level + 2, depth - 1, out);
        }
        Self::indent(out, level);
        out.push_str("END_CASE;\n");
    }

    fn call(&mut self, level: usize, out: &mut String) {
        let (name, ty) = *self.rng.pick(&self.fbs);
        let mut args: Vec<String> = Vec::new();
        let b = |g: &mut Gen| g.bool_atom_or_small();
        match ty {
            "TON" | "TOF" | "TP" => {
                args.push(format!("IN := {}", b(self)));
                let t = self.time();
                args.push(format!("PT := {t}"));
                if self.rng.percent(40) {
                    args.push("ET => Elapsed".to_owned());
                }
                if self.rng.percent(30) {
                    args.push("Q => Ready".to_owned());
                }
            }
            "R_TRIG" | "F_TRIG" => args.push(format!("CLK := {}", b(self))),
            "CTU" => {
                args.push(format!("CU := {}", b(self)));
                args.push(format!("R := {}", b(self)));
                args.push(format!("PV := {}", self.rng.range(1, 20)));
                if self.rng.percent(50) {
                    args.push("CV => Count".to_owned());
                }
            }
            "CTD" => {
                args.push(format!("CD := {}", b(self)));
                args.push(format!("LD := {}", b(self)));
                args.push(format!("PV := {}", self.int(1).0));
            }
            "CTUD" => {
                args.push(format!("CU := {}", b(self)));
                args.push(format!("CD := {}", b(self)));
                args.push(format!("R := {}", b(self)));
                args.push(format!("LD := {}", b(self)));
                args.push(format!("PV := {}", self.rng.range(1, 20)));
                if self.rng.percent(40) {
                    args.push("QU => Ready".to_owned());
                }
            }
            "SR" => {
                args.push(format!("S1 := {}", b(self)));
                args.push(format!("R := {}", b(self)));
            }
            _ => {
                args.push(format!("S := {}", b(self)));
                args.push(format!("R1 := {}", b(self)));
                if self.rng.percent(40) {
                    args.push("Q1 => Ready".to_owned());
                }
            }
        }
        if self.rng.percent(15) {
            args.clear();
        }
        Self::indent(out, level);
        let _ = writeln!(out, "{name}({});", args.join(", "));
    }

    fn assignment(&mut self) -> String {
        match self.rng.below(7) {
            0 => format!("Count := {};", self.int(2).0),
            1 => format!("Mode := {};", self.dint(2).0),
            2 => format!("Ratio := {};", self.real(2).0),
            3 => format!("Elapsed := {};", self.time()),
            4 if self
                .fbs
                .iter()
                .any(|(_, t)| matches!(*t, "TON" | "TOF" | "TP")) =>
            {
                let timers: Vec<&str> = self
                    .fbs
                    .iter()
                    .filter(|(_, t)| matches!(*t, "TON" | "TOF" | "TP"))
                    .map(|(n, _)| *n)
                    .collect();
                let t = self.rng.choose(&timers);
                format!("{t}.PT := {};", self.time())
            }
            _ => format!("Ready := {};", self.bool_expr(2).0),
        }
    }

    // ------------------------------------------------------------------------ expressions

    /// A transition condition; never the constant `TRUE`/`FALSE` alone, which would make
    /// steps unreachable (HG7012).
    fn condition(&mut self) -> String {
        for _ in 0..8 {
            let c = self.bool_expr(3).0;
            if c != "TRUE" && c != "FALSE" {
                return c;
            }
        }
        "Start".to_owned()
    }

    /// A BOOL operand for a function block input: an atom or a negated atom.
    fn bool_atom_or_small(&mut self) -> String {
        let (text, prec) = self.bool_atom();
        if self.rng.percent(20) {
            format!("not {}", wrap(text, prec, UNARY))
        } else {
            text
        }
    }

    fn bool_atom(&mut self) -> (String, u8) {
        let fb_outputs: Vec<String> = self
            .fbs
            .iter()
            .map(|(n, t)| match *t {
                "CTUD" => format!("{n}.QU"),
                "SR" | "RS" => format!("{n}.Q1"),
                _ => format!("{n}.Q"),
            })
            .collect();
        match self.rng.below(8) {
            0 | 1 => (
                self.rng.choose(&["Start", "Stop", "Ready"]).to_owned(),
                ATOM,
            ),
            2 if !fb_outputs.is_empty() => (self.rng.pick(&fb_outputs).clone(), ATOM),
            3 if !self.steps.is_empty() => {
                let s = self.rng.pick(&self.steps).clone();
                (format!("{s}.X"), ATOM)
            }
            4 => (self.rng.choose(&["TRUE", "FALSE"]).to_owned(), ATOM),
            5 => (self.rng.choose(OUTPUTS).to_owned(), ATOM),
            _ => (
                self.rng.choose(&["Start", "Stop", "Ready"]).to_owned(),
                ATOM,
            ),
        }
    }

    fn bool_expr(&mut self, depth: usize) -> (String, u8) {
        if depth == 0 {
            return self.bool_atom();
        }
        match self.rng.below(10) {
            0..=2 => self.bool_atom(),
            3 => {
                let (t, p) = self.bool_expr(depth - 1);
                (format!("not {}", wrap(t, p, UNARY)), UNARY)
            }
            4 | 5 => {
                let (op, prec) = self.rng.choose(&[("and", AND), ("or", OR), ("xor", XOR)]);
                let (l, lp) = self.bool_expr(depth - 1);
                let (r, rp) = self.bool_expr(depth - 1);
                (
                    format!("{} {op} {}", wrap(l, lp, prec), wrap(r, rp, prec + 1)),
                    prec,
                )
            }
            6 | 7 => {
                let op = self.rng.choose(&["=", "<>", "<", ">", "<=", ">="]);
                let (l, r) = match self.rng.below(4) {
                    0 => (self.dint(depth - 1), self.dint(depth - 1)),
                    1 => (self.real(depth - 1), self.real(depth - 1)),
                    _ => (self.int(depth - 1), self.int(depth - 1)),
                };
                (
                    format!("{} {op} {}", wrap(l.0, l.1, ADD), wrap(r.0, r.1, ADD)),
                    CMP,
                )
            }
            8 => {
                let op = self.rng.choose(&[">=", "<"]);
                let t = self.time();
                let timers: Vec<&str> = self
                    .fbs
                    .iter()
                    .filter(|(_, t)| matches!(*t, "TON" | "TOF" | "TP"))
                    .map(|(n, _)| *n)
                    .collect();
                let lhs = if !self.steps.is_empty() && self.rng.percent(30) {
                    format!("{}.T", self.rng.pick(&self.steps))
                } else if timers.is_empty() {
                    "Elapsed".to_owned()
                } else {
                    format!("{}.ET", self.rng.choose(&timers))
                };
                (format!("{lhs} {op} {t}"), CMP)
            }
            // Parentheses only where the precedence needs them, as the import writes them.
            _ => self.bool_expr(depth - 1),
        }
    }

    /// An INT expression.
    fn int(&mut self, depth: usize) -> (String, u8) {
        let counters: Vec<String> = self
            .fbs
            .iter()
            .filter(|(_, t)| t.starts_with("CT"))
            .map(|(n, _)| format!("{n}.CV"))
            .collect();
        let atom = |g: &mut Gen| -> (String, u8) {
            match g.rng.below(5) {
                0 => ("Count".to_owned(), ATOM),
                1 => ("Level".to_owned(), ATOM),
                2 if !counters.is_empty() => (g.rng.pick(&counters).clone(), ATOM),
                3 => ("-2".to_owned(), ATOM),
                _ => (g.rng.range(0, 100).to_string(), ATOM),
            }
        };
        self.arith(depth, &atom, "3")
    }

    fn dint(&mut self, depth: usize) -> (String, u8) {
        let atom = |g: &mut Gen| -> (String, u8) {
            match g.rng.below(3) {
                0 | 1 => ("Mode".to_owned(), ATOM),
                _ => (g.rng.range(0, 1000).to_string(), ATOM),
            }
        };
        self.arith(depth, &atom, "7")
    }

    fn real(&mut self, depth: usize) -> (String, u8) {
        let atom = |g: &mut Gen| -> (String, u8) {
            match g.rng.below(4) {
                0 => ("Ratio".to_owned(), ATOM),
                1 => ("Setpoint".to_owned(), ATOM),
                _ => (
                    g.rng.choose(&["0.5", "2.0", "100.0", "-1.5"]).to_owned(),
                    ATOM,
                ),
            }
        };
        // MOD is for integers only.
        self.arith(depth, &atom, "")
    }

    /// Arithmetic over `atom`s; `divisor` is a non-zero constant for `/` and `MOD` (empty: no
    /// `MOD`, `/` by 2.0).
    fn arith(
        &mut self,
        depth: usize,
        atom: &dyn Fn(&mut Gen) -> (String, u8),
        divisor: &str,
    ) -> (String, u8) {
        if depth == 0 {
            return atom(self);
        }
        match self.rng.below(8) {
            0..=2 => atom(self),
            3 => {
                let (t, p) = self.arith(depth - 1, atom, divisor);
                if t.starts_with('-') {
                    (format!("-({t})"), UNARY)
                } else {
                    (format!("-{}", wrap(t, p, UNARY)), UNARY)
                }
            }
            4 | 5 => {
                let op = self.rng.choose(&["+", "-"]);
                let (l, lp) = self.arith(depth - 1, atom, divisor);
                let (r, rp) = self.arith(depth - 1, atom, divisor);
                (
                    format!("{} {op} {}", wrap(l, lp, ADD), wrap(r, rp, ADD + 1)),
                    ADD,
                )
            }
            6 => {
                let (l, lp) = self.arith(depth - 1, atom, divisor);
                let (r, rp) = self.arith(depth - 1, atom, divisor);
                (
                    format!("{} * {}", wrap(l, lp, MUL), wrap(r, rp, MUL + 1)),
                    MUL,
                )
            }
            _ => {
                let (l, lp) = self.arith(depth - 1, atom, divisor);
                let (op, d) = match (divisor, self.rng.percent(50)) {
                    ("", _) => ("/", "2.0"),
                    (d, true) => ("MOD", d),
                    (d, false) => ("/", d),
                };
                (format!("{} {op} {d}", wrap(l, lp, MUL)), MUL)
            }
        }
    }

    fn time(&mut self) -> String {
        match self.rng.below(5) {
            0 => "Delay".to_owned(),
            1 => "Delay + T#1s".to_owned(),
            _ => self
                .rng
                .choose(&["T#5s", "T#250ms", "T#1m", "t#3s"])
                .to_owned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{iec_chart, iec_chart_with};

    #[test]
    fn deterministic_by_seed() {
        assert_eq!(iec_chart(7), iec_chart(7));
        assert_ne!(iec_chart(7), iec_chart(8));
        assert!(!iec_chart(7).contains("run <"));
    }

    #[test]
    fn covers_the_constructs() {
        let all: String = (0..300).map(|s| iec_chart_with(s, true)).collect();
        for needle in [
            "profile iec;",
            "alt <",
            "parallel <",
            "jump Back_",
            "IF ",
            "ELSIF ",
            "CASE ",
            "END_CASE;",
            "..",
            "MOD",
            " / ",
            " * ",
            "-(",
            "(",
            ".X",
            ".T >",
            "Timer1(",
            "=> ",
            "action Action_",
            "P1 ",
            "P0 ",
            "DL ",
            "SD ",
            "SL ",
            "DS ",
            "init <",
            "run <",
            "term <",
        ] {
            assert!(all.contains(needle), "{needle}");
        }
    }
}
