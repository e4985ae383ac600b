//! What a picture shows, read from the syntax tree: the states and transitions of a graph,
//! the instances and message links of a group, the sequencers of a chart. Both outputs (SVG
//! and DOT) are made from these models, so they show the same structure.

use higraph_syntax::ast::{self, AstNode, EndpointKind};

use crate::format::implicit_priorities;

/// A state graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GraphModel {
    pub name: String,
    /// States in text order.
    pub states: Vec<StateModel>,
    /// Transitions in text order.
    pub transitions: Vec<TransModel>,
    /// The state number of the initial state (target of the startup transition), if any.
    pub initial: Option<u64>,
}

/// One state: its number and display name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateModel {
    pub number: u64,
    pub name: Option<String>,
}

/// A transition endpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    State(u64),
    Any,
    Return,
}

/// One transition.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TransModel {
    pub source: End,
    pub target: End,
    /// Explicit or computed priority.
    pub prio: Option<u64>,
    /// `auto`, `manual`, `waits`, `fault` in text order (lower case).
    pub attributes: Vec<String>,
    /// The display name.
    pub name: Option<String>,
}

impl TransModel {
    /// How a viewer names the transition (the SVG's `data-trans`): `A->B:PRIO` with `any` for
    /// an any-transition's source and `return` for a return transition's target, without
    /// `:PRIO` when the priority is unknown. A trace's fired transition names it alike.
    pub fn key(&self) -> String {
        let end = |end: End| match end {
            End::State(number) => number.to_string(),
            End::Any => "any".to_owned(),
            End::Return => "return".to_owned(),
        };
        let mut key = format!("{}->{}", end(self.source), end(self.target));
        if let Some(prio) = self.prio {
            key.push_str(&format!(":{prio}"));
        }
        key
    }

    /// The label drawn at the arrow: priority and attributes (`1 auto`).
    pub fn label(&self) -> String {
        let mut parts: Vec<String> = Vec::new();
        if let Some(prio) = self.prio {
            parts.push(prio.to_string());
        }
        parts.extend(self.attributes.iter().cloned());
        parts.join(" ")
    }
}

/// A graph group.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GroupModel {
    pub name: String,
    /// Instances in run (text) order.
    pub instances: Vec<InstanceModel>,
    /// Internal message links, in text order.
    pub links: Vec<LinkModel>,
}

/// One instance: its name and graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InstanceModel {
    pub name: String,
    pub graph: String,
}

/// `OM_x := Inst.IM_y` inside instance `from`: a message from `from` to `to`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinkModel {
    /// Index into [`GroupModel::instances`].
    pub from: usize,
    pub to: usize,
    /// The outgoing message formal (`OM_x`).
    pub out_message: String,
    /// The incoming message of the target (`IM_y`).
    pub in_message: String,
}

/// A sequence chart.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChartModel {
    pub name: String,
    pub sequencers: Vec<SequencerModel>,
}

/// One sequencer and its elements.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SequencerModel {
    pub name: String,
    pub elements: Vec<Element>,
}

/// One element of a sequencer or branch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Element {
    Step(String),
    Trans(String),
    /// Branches side by side, all run.
    Parallel(Vec<Vec<Element>>),
    /// Branches side by side, the leftmost true one runs.
    Alt(Vec<Vec<Element>>),
    Jump {
        name: String,
        target: String,
    },
    Loop {
        name: String,
        target: String,
    },
}

/// Reads a graph.
pub fn graph_model(graph: &ast::Graph) -> GraphModel {
    let name = graph.name().map(|n| n.text()).unwrap_or_default();
    let states = graph
        .states()
        .filter_map(|state| {
            let number = parse_number(state.number()?.text())?;
            Some(StateModel {
                number,
                name: state.comment().map(|c| c.value()),
            })
        })
        .collect();
    let implicit = implicit_priorities(graph);
    let mut initial = None;
    let mut transitions = Vec::new();
    for (i, trans) in graph.transitions().enumerate() {
        let (Some(source), Some(target)) = (
            trans.source().and_then(|e| endpoint(&e)),
            trans.target().and_then(|e| endpoint(&e)),
        ) else {
            continue;
        };
        let explicit = trans
            .prio()
            .and_then(|p| p.value())
            .and_then(|v| parse_number(v.text()));
        let prio = explicit.or(implicit.get(i).copied().flatten());
        let attributes = trans
            .attributes()
            .filter_map(|a| a.keyword())
            .map(|k| k.text().to_ascii_lowercase())
            .collect();
        if let (End::Any, End::State(number), None) = (source, target, initial) {
            let text = trans
                .body()
                .map(|b| b.syntax().text().to_string())
                .unwrap_or_default();
            if text.to_ascii_uppercase().contains("INIT_SD") {
                initial = Some(number);
            }
        }
        transitions.push(TransModel {
            source,
            target,
            prio,
            attributes,
            name: trans.comment().map(|c| c.value()),
        });
    }
    GraphModel {
        name,
        states,
        transitions,
        initial,
    }
}

fn endpoint(endpoint: &ast::Endpoint) -> Option<End> {
    Some(match endpoint.kind()? {
        EndpointKind::Any => End::Any,
        EndpointKind::Return => End::Return,
        EndpointKind::State => End::State(parse_number(endpoint.token()?.text())?),
    })
}

fn parse_number(text: &str) -> Option<u64> {
    text.trim().parse().ok()
}

/// Reads a group.
pub fn group_model(group: &ast::Group) -> GroupModel {
    let name = group.name().map(|n| n.text()).unwrap_or_default();
    let instances: Vec<(InstanceModel, ast::Instance)> = group
        .instances()
        .filter_map(|instance| {
            let model = InstanceModel {
                name: instance.name()?.text(),
                graph: instance.graph().map(|g| g.text()).unwrap_or_default(),
            };
            Some((model, instance))
        })
        .collect();
    // The first instance of each name (case-insensitive), found by lookup rather than by a
    // scan per link.
    let mut by_name: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    for (i, (m, _)) in instances.iter().enumerate() {
        by_name.entry(m.name.to_ascii_uppercase()).or_insert(i);
    }
    let position = |name: &str| by_name.get(&name.to_ascii_uppercase()).copied();
    let mut links = Vec::new();
    for (from, (_, instance)) in instances.iter().enumerate() {
        for actual in instance.actuals() {
            let Some(ast::Operand::MessageTarget(target)) = actual.value() else {
                continue;
            };
            let (Some(formal), Some(to_name), Some(message)) =
                (actual.formal(), target.instance(), target.message())
            else {
                continue;
            };
            let Some(to) = position(&to_name.text()) else {
                continue;
            };
            links.push(LinkModel {
                from,
                to,
                out_message: formal.text(),
                in_message: message.text(),
            });
        }
    }
    GroupModel {
        name,
        instances: instances.into_iter().map(|(m, _)| m).collect(),
        links,
    }
}

/// Reads a chart.
pub fn chart_model(chart: &ast::Chart) -> ChartModel {
    ChartModel {
        name: chart.name().map(|n| n.text()).unwrap_or_default(),
        sequencers: chart
            .sequencers()
            .map(|s| SequencerModel {
                name: s.name().map(|n| n.text()).unwrap_or_default(),
                elements: elements(s.elements()),
            })
            .collect(),
    }
}

fn elements(items: impl Iterator<Item = ast::SeqElement>) -> Vec<Element> {
    let branches = |b: Vec<ast::Branch>| -> Vec<Vec<Element>> {
        b.into_iter().map(|b| elements(b.elements())).collect()
    };
    items
        .map(|item| match item {
            ast::SeqElement::Step(s) => Element::Step(name_of(s.name())),
            ast::SeqElement::Trans(t) => Element::Trans(name_of(t.name())),
            ast::SeqElement::Parallel(p) => Element::Parallel(branches(p.branches().collect())),
            ast::SeqElement::Alt(a) => Element::Alt(branches(a.branches().collect())),
            ast::SeqElement::Jump(j) => Element::Jump {
                name: name_of(j.name()),
                target: j.target().map(|t| t.text()).unwrap_or_default(),
            },
            ast::SeqElement::Loop(l) => Element::Loop {
                name: name_of(l.name()),
                target: l.target().map(|t| t.text()).unwrap_or_default(),
            },
        })
        .collect()
}

fn name_of(name: Option<ast::Name>) -> String {
    name.map(|n| n.text()).unwrap_or_default()
}
