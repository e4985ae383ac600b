//! Graphviz DOT output: a `digraph` of the same structure the SVG shows. Deterministic: nodes
//! and edges come out in text order, with stable identifiers.

use std::fmt::Write as _;

use super::model::{ChartModel, Element, End, GraphModel, GroupModel};

/// A DOT string literal.
fn quote(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => {}
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn header(out: &mut String, name: &str, rankdir: &str) {
    let _ = writeln!(out, "digraph {} {{", quote(name));
    let _ = writeln!(out, "  rankdir={rankdir};");
    let _ = writeln!(out, "  node [fontname=\"sans-serif\"];");
    let _ = writeln!(out, "  edge [fontname=\"sans-serif\"];");
}

/// A state graph: states as circles, any- and return transitions from / to small bars.
pub fn graph(model: &GraphModel) -> String {
    let mut out = String::new();
    header(&mut out, &model.name, "TB");
    for state in &model.states {
        let label = match &state.name {
            Some(name) => format!("{}\n{}", state.number, name),
            None => state.number.to_string(),
        };
        let style = if model.initial == Some(state.number) {
            ", peripheries=2"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "  s{} [shape=circle, label={}{style}];",
            state.number,
            quote(&label)
        );
    }
    let numbers: std::collections::HashSet<u64> = model.states.iter().map(|s| s.number).collect();
    let exists = |n: u64| numbers.contains(&n);
    for (i, trans) in model.transitions.iter().enumerate() {
        let source = match trans.source {
            End::State(n) if exists(n) => format!("s{n}"),
            End::Any => {
                let id = format!("any{i}");
                let _ = writeln!(
                    out,
                    "  {id} [shape=box, style=filled, fillcolor=black, label=\"\", width=0.3, height=0.05];"
                );
                id
            }
            _ => continue,
        };
        let target = match trans.target {
            End::State(n) if exists(n) => format!("s{n}"),
            End::Return => {
                let id = format!("return{i}");
                let _ = writeln!(
                    out,
                    "  {id} [shape=box, style=filled, fillcolor=black, label=\"\", width=0.3, height=0.05];"
                );
                id
            }
            _ => continue,
        };
        let tooltip = trans
            .name
            .as_ref()
            .map(|n| format!(", tooltip={}", quote(n)))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "  {source} -> {target} [label={}{tooltip}];",
            quote(&trans.label())
        );
    }
    out.push_str("}\n");
    out
}

/// A graph group: instances as boxes in run order, message links as labelled edges.
pub fn group(model: &GroupModel) -> String {
    let mut out = String::new();
    header(&mut out, &model.name, "LR");
    for (i, instance) in model.instances.iter().enumerate() {
        let label = format!("{}\n: {}", instance.name, instance.graph);
        let _ = writeln!(out, "  i{i} [shape=box, label={}];", quote(&label));
    }
    // The run order, as invisible edges that keep the boxes in order.
    for i in 1..model.instances.len() {
        let _ = writeln!(out, "  i{} -> i{i} [style=invis];", i - 1);
    }
    for link in &model.links {
        let label = format!("{} → {}", link.out_message, link.in_message);
        let _ = writeln!(
            out,
            "  i{} -> i{} [label={}];",
            link.from,
            link.to,
            quote(&label)
        );
    }
    out.push_str("}\n");
    out
}

/// A chart: one cluster per sequencer; steps as boxes, transitions as bars, `parallel` and
/// `alt` as opening and closing bars, jumps and loops as dashed edges to their target step.
pub fn chart(model: &ChartModel) -> String {
    let mut out = String::new();
    header(&mut out, &model.name, "TB");
    for (s, sequencer) in model.sequencers.iter().enumerate() {
        let _ = writeln!(out, "  subgraph cluster_{s} {{");
        let _ = writeln!(out, "    label={};", quote(&sequencer.name));
        let mut writer = ChartWriter {
            out: &mut out,
            prefix: format!("q{s}_"),
            next: 0,
            steps: Vec::new(),
            jumps: Vec::new(),
        };
        writer.sequence(&sequencer.elements, Vec::new());
        let ChartWriter { steps, jumps, .. } = writer;
        // The first step of each name (case-insensitive).
        let mut step_ids: std::collections::HashMap<String, &String> =
            std::collections::HashMap::new();
        for (name, id) in &steps {
            step_ids.entry(name.to_ascii_uppercase()).or_insert(id);
        }
        for (from, label, target) in jumps {
            let to = step_ids
                .get(&target.to_ascii_uppercase())
                .map(|id| (*id).clone());
            if let Some(to) = to {
                for from in from {
                    let _ = writeln!(
                        out,
                        "    {from} -> {to} [style=dashed, label={}];",
                        quote(&label)
                    );
                }
            }
        }
        let _ = writeln!(out, "  }}");
    }
    out.push_str("}\n");
    out
}

/// Writes the nodes and flow edges of one sequencer.
struct ChartWriter<'a> {
    out: &'a mut String,
    prefix: String,
    next: usize,
    /// Step names and node ids, for jump and loop targets.
    steps: Vec<(String, String)>,
    /// Jumps and loops: source nodes, label, target step name.
    jumps: Vec<(Vec<String>, String, String)>,
}

impl ChartWriter<'_> {
    fn node(&mut self, attributes: &str) -> String {
        let id = format!("{}{}", self.prefix, self.next);
        self.next += 1;
        let _ = writeln!(self.out, "    {id} [{attributes}];");
        id
    }

    fn edges(&mut self, from: &[String], to: &str) {
        for from in from {
            let _ = writeln!(self.out, "    {from} -> {to};");
        }
    }

    /// Writes a list of elements whose predecessors are `before`; returns its exits.
    fn sequence(&mut self, elements: &[Element], mut before: Vec<String>) -> Vec<String> {
        for element in elements {
            before = match element {
                Element::Step(name) => {
                    let id = self.node(&format!("shape=box, label={}", quote(name)));
                    self.steps.push((name.clone(), id.clone()));
                    self.edges(&before, &id);
                    vec![id]
                }
                Element::Trans(name) => {
                    let id = self.node(&format!(
                        "shape=underline, height=0.2, label={}",
                        quote(name)
                    ));
                    self.edges(&before, &id);
                    vec![id]
                }
                Element::Parallel(branches) | Element::Alt(branches) => {
                    let (kind, periph) = match element {
                        Element::Parallel(_) => ("parallel", 2),
                        _ => ("alt", 1),
                    };
                    let bar = format!(
                        "shape=box, style=filled, fillcolor=black, label=\"\", height=0.03, width=1.5, peripheries={periph}, tooltip={}",
                        quote(kind)
                    );
                    let open = self.node(&bar);
                    self.edges(&before, &open);
                    let close_id = format!("{}{}", self.prefix, self.next);
                    self.next += 1;
                    let mut exits = Vec::new();
                    for branch in branches {
                        exits.extend(self.sequence(branch, vec![open.clone()]));
                    }
                    let _ = writeln!(self.out, "    {close_id} [{bar}];");
                    self.edges(&exits, &close_id);
                    vec![close_id]
                }
                Element::Jump { name, target } => {
                    self.jumps
                        .push((before.clone(), format!("jump {name}"), target.clone()));
                    before
                }
                Element::Loop { name, target } => {
                    self.jumps
                        .push((before.clone(), format!("loop {name}"), target.clone()));
                    before
                }
            };
        }
        before
    }
}
