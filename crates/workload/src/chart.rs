//! Sequence charts: sequencers of alternating steps and transitions, with parallel and
//! alternative branches, jumps and loops (`language.md` §6), clean under the HG7xxx rules.

use std::fmt::Write;

use crate::rng::Rng;

/// Everything that shapes one generated chart.
#[derive(Debug, Clone)]
pub(crate) struct ChartSpec {
    pub(crate) name: String,
    pub(crate) title: String,
    /// `chart type`: uses only its own interface (HG7309).
    pub(crate) chart_type: bool,
    /// 1..=8 for a plain chart.
    pub(crate) sequencers: usize,
    /// Top-level units (steps and transitions) per sequencer, odd.
    pub(crate) units: (usize, usize),
    pub(crate) mode: &'static str,
    pub(crate) switching: &'static str,
    pub(crate) time_monitoring: bool,
    pub(crate) in_bools: usize,
    pub(crate) in_reals: usize,
    pub(crate) out_bools: usize,
    /// BOOL global symbols a plain chart reads in conditions.
    pub(crate) global_inputs: Vec<String>,
    /// BOOL global symbols a plain chart writes with qualifiers and assignments.
    pub(crate) global_outputs: Vec<String>,
}

#[derive(Debug)]
enum Element {
    Step {
        name: String,
        comment: Option<String>,
        items: Vec<String>,
    },
    Trans {
        name: String,
        conditions: Vec<String>,
    },
    Parallel(Vec<Vec<Element>>),
    Alt(Vec<Vec<Element>>),
    Jump {
        name: String,
        target: String,
        conditions: Vec<String>,
    },
    Loop {
        name: String,
        target: String,
        conditions: Vec<String>,
    },
}

const STEP_WORDS: &[&str] = &[
    "Fuellen",
    "Heizen",
    "Ruehren",
    "Dosieren",
    "Warten",
    "Entleeren",
    "Spuelen",
    "Pruefen",
    "Kuehlen",
    "Mischen",
    "Ablassen",
    "Wiegen",
    "Belueften",
    "Trocknen",
];

struct Vars {
    in_bools: Vec<String>,
    in_reals: Vec<String>,
    out_bools: Vec<String>,
    used: std::collections::HashSet<String>,
    cursor: usize,
}

struct Gen<'a> {
    spec: &'a ChartSpec,
    rng: Rng,
    vars: Vars,
    steps: usize,
    transitions: usize,
}

/// Generates the text of one chart.
pub(crate) fn generate(spec: &ChartSpec, rng: &mut Rng) -> String {
    let vars = Vars {
        in_bools: (1..=spec.in_bools)
            .map(|k| format!("Freigabe_{k}"))
            .collect(),
        in_reals: (1..=spec.in_reals)
            .map(|k| format!("Messwert_{k}"))
            .collect(),
        out_bools: (1..=spec.out_bools)
            .map(|k| format!("Antrieb_{k}"))
            .collect(),
        used: Default::default(),
        cursor: 0,
    };
    let mut g = Gen {
        spec,
        rng: rng.fork(0xC4),
        vars,
        steps: 0,
        transitions: 0,
    };
    g.run()
}

impl Gen<'_> {
    fn mark(&mut self, name: &str) -> String {
        self.vars.used.insert(name.to_string());
        name.to_string()
    }

    fn bool_input(&mut self) -> String {
        if !self.spec.chart_type && !self.spec.global_inputs.is_empty() && self.rng.percent(15) {
            return self.rng.pick(&self.spec.global_inputs).clone();
        }
        let list = &self.vars.in_bools;
        let name = if self.rng.percent(50) {
            self.vars.cursor += 1;
            list[self.vars.cursor % list.len()].clone()
        } else {
            self.rng.pick(list).clone()
        };
        self.mark(&name)
    }

    fn real_input(&mut self) -> String {
        let name = self.rng.pick(&self.vars.in_reals).clone();
        self.mark(&name)
    }

    fn bool_output(&mut self) -> String {
        if !self.spec.chart_type && !self.spec.global_outputs.is_empty() && self.rng.percent(15) {
            return self.rng.pick(&self.spec.global_outputs).clone();
        }
        let list = &self.vars.out_bools;
        let name = if self.rng.percent(50) {
            self.vars.cursor += 1;
            list[self.vars.cursor % list.len()].clone()
        } else {
            self.rng.pick(list).clone()
        };
        self.mark(&name)
    }

    /// One BOOL condition with at most 3 atomic conditions.
    fn condition(&mut self) -> String {
        match self.rng.below(10) {
            0..=2 => self.bool_input(),
            3 => format!("not {}", self.bool_input()),
            4 => format!("{} and {}", self.bool_input(), self.bool_input()),
            5 => {
                let (a, b, c) = (self.bool_input(), self.bool_input(), self.bool_input());
                format!("({a} or {b}) and not {c}")
            }
            6 if !self.vars.in_reals.is_empty() => {
                let op = self.rng.choose(&[">=", "<=", ">", "<", "<>"]);
                let k = self.rng.choose(&["80.0", "5.0", "60.0", "0.5", "1.5e+2"]);
                format!("{} {op} {k}", self.real_input())
            }
            7 => {
                let op = self.rng.choose(&[">", "<", "=", "<>", ">=", "<="]);
                format!("Zaehler {op} {}", self.rng.range(0, 20))
            }
            8 => format!("{} xor Bereit", self.bool_input()),
            _ => format!("{} = TRUE", self.bool_input()),
        }
    }

    fn conditions(&mut self, lo: usize, hi: usize) -> Vec<String> {
        let n = self.rng.range(lo, hi);
        (0..n).map(|_| self.condition()).collect()
    }

    fn statement(&mut self) -> String {
        match self.rng.below(6) {
            0 | 1 => format!(
                "{} := {}",
                self.bool_output(),
                if self.rng.percent(50) {
                    "TRUE"
                } else {
                    "FALSE"
                }
            ),
            2 => format!("Bereit := {} and {}", self.bool_input(), self.bool_input()),
            3 => format!("Zaehler := {}", self.rng.range(0, 100)),
            4 => format!("{} := not {}", self.bool_output(), self.bool_input()),
            _ => format!("Bereit := {}", self.condition()),
        }
    }

    fn step(&mut self, name: Option<String>) -> Element {
        self.steps += 1;
        let k = self.steps;
        let name = name.unwrap_or_else(|| format!("S{k:02}_{}", self.rng.pick(STEP_WORDS)));
        let mut items = Vec::new();
        if self.rng.percent(35) {
            let stmts: Vec<String> = (0..self.rng.range(1, 3))
                .map(|_| self.statement())
                .collect();
            items.push(phase("init", &stmts));
        }
        for _ in 0..self.rng.range(0, 2) {
            let q = self
                .rng
                .choose(&["N", "N", "S", "R", "P", "L", "D", "SD", "DS", "SL"]);
            let op = self.bool_output();
            if matches!(q, "L" | "D" | "SD" | "DS" | "SL") {
                let t = self.rng.choose(&["T#5S", "T#2S", "T#30S", "T#1M"]);
                items.push(format!("{q} {op}, {t};"));
            } else {
                items.push(format!("{q} {op};"));
            }
        }
        if self.rng.percent(25) {
            let stmts: Vec<String> = (0..self.rng.range(1, 2))
                .map(|_| self.statement())
                .collect();
            items.push(phase("run", &stmts));
        }
        if self.rng.percent(15) {
            // HG7311: `term` writes only Letzter_Schritt, which no init/run/qualifier writes.
            items.push(phase("term", &[format!("Letzter_Schritt := {k}")]));
        }
        if self.rng.percent(15) {
            items.push("min T#1S;".to_string());
        }
        if self.spec.time_monitoring && self.rng.percent(20) {
            items.push(format!(
                "max {};",
                self.rng.pick(&["T#10M", "T#30S", "T#1H"])
            ));
        }
        if self.spec.switching == "step" && self.rng.percent(20) {
            items.push("confirm;".to_string());
        }
        let comment = self.rng.percent(20).then(|| format!("Schritt {k}"));
        Element::Step {
            name,
            comment,
            items,
        }
    }

    fn trans(&mut self) -> Element {
        self.transitions += 1;
        let name = format!("Tr{:02}", self.transitions);
        let conditions = self.conditions(1, 3);
        Element::Trans { name, conditions }
    }

    /// Step-kind unit: a step, or (not too deep) a parallel of 2..3 branches.
    fn step_kind(&mut self, depth: usize) -> Element {
        if depth < 2 && self.rng.percent(12) {
            let branches = self.rng.range(2, 3);
            Element::Parallel(
                (0..branches)
                    .map(|_| {
                        let len = self.odd(1, 3);
                        self.step_list(depth + 1, len)
                    })
                    .collect(),
            )
        } else {
            self.step(None)
        }
    }

    /// Transition-kind unit: a transition, or (not too deep) an alt of 2..3 branches.
    fn trans_kind(&mut self, depth: usize) -> Element {
        if depth < 2 && self.rng.percent(12) {
            let branches = self.rng.range(2, 3);
            Element::Alt(
                (0..branches)
                    .map(|_| {
                        let len = self.odd(1, 3);
                        self.trans_list(depth + 1, len)
                    })
                    .collect(),
            )
        } else {
            self.trans()
        }
    }

    fn odd(&mut self, lo: usize, hi: usize) -> usize {
        let n = self.rng.range(lo, hi);
        n | 1
    }

    /// `len` (odd) units beginning and ending with a plain step, alternating; loops attached to
    /// some steps lead back to an earlier step of this list (HG7007, HG7008).
    fn step_list(&mut self, depth: usize, len: usize) -> Vec<Element> {
        let mut list = Vec::new();
        let mut steps_here: Vec<String> = Vec::new();
        for i in 0..len {
            let el = if i % 2 == 1 {
                self.trans_kind(depth)
            } else if i == 0 || i == len - 1 {
                self.step(None)
            } else {
                self.step_kind(depth)
            };
            let step_name = match &el {
                Element::Step { name, .. } => Some(name.clone()),
                _ => None,
            };
            list.push(el);
            if let Some(name) = step_name {
                if i != len - 1 && !steps_here.is_empty() && self.rng.percent(10) {
                    self.transitions += 1;
                    let target = self.rng.pick(&steps_here).clone();
                    let conditions = self.conditions(1, 2);
                    list.push(Element::Loop {
                        name: format!("Schleife{}", self.transitions),
                        target,
                        conditions,
                    });
                }
                steps_here.push(name);
            }
        }
        list
    }

    /// `len` (odd) units beginning and ending with a transition (an alternative branch).
    fn trans_list(&mut self, depth: usize, len: usize) -> Vec<Element> {
        (0..len)
            .map(|i| {
                if i % 2 == 0 {
                    if i == 0 {
                        self.trans()
                    } else {
                        self.trans_kind(depth)
                    }
                } else {
                    self.step_kind(depth)
                }
            })
            .collect()
    }

    fn sequencer(&mut self, index: usize, out: &mut String) {
        let len = self.odd(self.spec.units.0, self.spec.units.1).max(3);
        let mut list = Vec::new();
        let mut first = self.step(Some("Grundstellung".into()));
        if let Element::Step { items, .. } = &mut first {
            // Letzter_Schritt is written only in `term` parts; this one makes sure it is used.
            items.retain(|i| !i.starts_with("term"));
            items.push(phase("term", &["Letzter_Schritt := 1".to_string()]));
        }
        list.push(first);
        list.push(self.trans());
        let mut body = self.step_list(0, len - 2);
        list.append(&mut body);
        let last = list.len() - 1;
        if let Element::Step { name, .. } = &mut list[last] {
            *name = "Ende".into();
        }
        // Jumps: from a top-level plain step (not the last) to another top-level step.
        let top_steps: Vec<(usize, String)> = list
            .iter()
            .enumerate()
            .filter_map(|(i, e)| match e {
                Element::Step { name, .. } => Some((i, name.clone())),
                _ => None,
            })
            .collect();
        let mut jumps = Vec::new();
        for (i, name) in &top_steps {
            if *i != last && top_steps.len() > 2 && self.rng.percent(8) {
                let (_, target) = self.rng.pick(&top_steps).clone();
                if &target != name {
                    self.transitions += 1;
                    let conditions = self.conditions(1, 2);
                    jumps.push((
                        *i,
                        Element::Jump {
                            name: format!("Sprung{}", self.transitions),
                            target,
                            conditions,
                        },
                    ));
                }
            }
        }
        for (i, jump) in jumps.into_iter().rev() {
            // After the step and after any loop already attached to it.
            let mut at = i + 1;
            while matches!(list.get(at), Some(Element::Loop { .. })) {
                at += 1;
            }
            list.insert(at, jump);
        }

        let prio = if self.spec.sequencers > 1 {
            format!(" prio {index}")
        } else {
            String::new()
        };
        writeln!(out, "  sequencer Ablauf_{index}{prio} <").unwrap();
        let start = self.conditions(1, 2);
        writeln!(
            out,
            "    start < {} >",
            start
                .iter()
                .map(|c| format!("{c};"))
                .collect::<Vec<_>>()
                .join(" ")
        )
        .unwrap();
        if self.rng.percent(40) {
            let s = self.statement();
            writeln!(out, "    pre < {s}; >").unwrap();
        }
        let mut tail = String::new();
        render_list(&mut tail, &list, 4);
        if index == 1 {
            // Every variable is used (HG1210): unused inputs are read and unused outputs
            // written in the first sequencer's `post` part.
            let mut post = Vec::new();
            for v in self.vars.in_bools.clone() {
                if !self.vars.used.contains(&v) {
                    post.push(format!("Bereit := {v}"));
                }
            }
            for v in self.vars.in_reals.clone() {
                if !self.vars.used.contains(&v) {
                    post.push(format!("Bereit := {v} > 0.0"));
                }
            }
            for v in self.vars.out_bools.clone() {
                if !self.vars.used.contains(&v) {
                    post.push(format!("{v} := FALSE"));
                }
            }
            post.push("Zaehler := 0".into());
            out.push_str(&tail);
            out.push_str(&phase_at("post", &post, 4));
        } else {
            out.push_str(&tail);
        }
        writeln!(out, "  >").unwrap();
    }

    fn run(&mut self) -> String {
        let spec = self.spec;
        let mut out = String::new();
        let kw = if spec.chart_type {
            "chart type"
        } else {
            "chart"
        };
        writeln!(out, "{kw} {} \"{}\" <", spec.name, spec.title).unwrap();
        let decl = |names: &[String], ty: &str| {
            names
                .iter()
                .map(|n| format!("{n} : {ty};"))
                .collect::<Vec<_>>()
        };
        let mut ins = decl(&self.vars.in_bools, "BOOL");
        ins.extend(decl(&self.vars.in_reals, "REAL"));
        section(&mut out, "in", &ins);
        section(&mut out, "out", &decl(&self.vars.out_bools, "BOOL"));
        section(
            &mut out,
            "stat",
            &[
                "Bereit : BOOL;".into(),
                "Zaehler : INT := 0;".into(),
                "Letzter_Schritt : INT;".into(),
            ],
        );
        writeln!(out, "  mode {};", spec.mode).unwrap();
        writeln!(out, "  switching {};", spec.switching).unwrap();
        writeln!(out, "  run cyclic;").unwrap();
        if spec.time_monitoring {
            writeln!(out, "  run time_monitoring;").unwrap();
        }
        // Sequencers are generated in reverse so that the first one, which holds the `post`
        // part using every leftover variable, sees all uses; they are printed in order.
        let mut texts = Vec::new();
        for index in (1..=spec.sequencers).rev() {
            self.steps = 0;
            self.transitions = 0;
            let mut s = String::new();
            self.sequencer(index, &mut s);
            texts.push(s);
        }
        for s in texts.into_iter().rev() {
            out.push_str(&s);
        }
        out.push_str(">\n");
        out
    }
}

fn section(out: &mut String, kw: &str, decls: &[String]) {
    if decls.is_empty() {
        return;
    }
    let line = format!("  {kw} < {} >", decls.join(" "));
    if line.len() <= 100 {
        writeln!(out, "{line}").unwrap();
    } else {
        writeln!(out, "  {kw} <").unwrap();
        for d in decls {
            writeln!(out, "    {d}").unwrap();
        }
        writeln!(out, "  >").unwrap();
    }
}

fn phase(kw: &str, statements: &[String]) -> String {
    format!(
        "{kw} < {} >",
        statements
            .iter()
            .map(|s| format!("{s};"))
            .collect::<Vec<_>>()
            .join(" ")
    )
}

fn phase_at(kw: &str, statements: &[String], indent: usize) -> String {
    let line = format!("{:indent$}{}\n", "", phase(kw, statements));
    if line.len() <= 101 {
        return line;
    }
    let mut out = format!("{:indent$}{kw} <\n", "");
    for s in statements {
        writeln!(out, "{:width$}{s};", "", width = indent + 2).unwrap();
    }
    writeln!(out, "{:indent$}>", "").unwrap();
    out
}

fn conditions_text(conditions: &[String]) -> String {
    conditions
        .iter()
        .map(|c| format!("{c};"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn render_list(out: &mut String, list: &[Element], indent: usize) {
    for el in list {
        match el {
            Element::Step {
                name,
                comment,
                items,
            } => {
                let header = match comment {
                    Some(c) => format!("step {name} \"{c}\""),
                    None => format!("step {name}"),
                };
                let line = format!("{:indent$}{header} < {} >", "", items.join(" "));
                if items.is_empty() {
                    writeln!(out, "{:indent$}{header} < >", "").unwrap();
                } else if items.len() == 1 && line.len() <= 100 {
                    writeln!(out, "{line}").unwrap();
                } else {
                    writeln!(out, "{:indent$}{header} <", "").unwrap();
                    for item in items {
                        writeln!(out, "{:width$}{item}", "", width = indent + 2).unwrap();
                    }
                    writeln!(out, "{:indent$}>", "").unwrap();
                }
            }
            Element::Trans { name, conditions } => {
                writeln!(
                    out,
                    "{:indent$}trans {name} < {} >",
                    "",
                    conditions_text(conditions)
                )
                .unwrap();
            }
            Element::Jump {
                name,
                target,
                conditions,
            } => {
                writeln!(
                    out,
                    "{:indent$}jump {name} -> {target} < {} >",
                    "",
                    conditions_text(conditions)
                )
                .unwrap();
            }
            Element::Loop {
                name,
                target,
                conditions,
            } => {
                writeln!(
                    out,
                    "{:indent$}loop {name} -> {target} < {} >",
                    "",
                    conditions_text(conditions)
                )
                .unwrap();
            }
            Element::Parallel(branches) | Element::Alt(branches) => {
                let kw = if matches!(el, Element::Parallel(_)) {
                    "parallel"
                } else {
                    "alt"
                };
                writeln!(out, "{:indent$}{kw} <", "").unwrap();
                for b in branches {
                    writeln!(out, "{:width$}branch <", "", width = indent + 2).unwrap();
                    render_list(out, b, indent + 4);
                    writeln!(out, "{:width$}>", "", width = indent + 2).unwrap();
                }
                writeln!(out, "{:indent$}>", "").unwrap();
            }
        }
    }
}
