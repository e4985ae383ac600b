//! Call hierarchy and message flow. The items are groups, instances, graphs and message
//! variables (`msg in` / `msg out` in a graph's `in_out` section):
//!
//! * a group calls its instances, an instance calls its graph (outgoing); a graph is called by
//!   the instances that instantiate it, an instance by its group (incoming);
//! * message flow: an instance also calls the instances its outgoing messages are wired to
//!   (`OM_Senken := Vorschub.IM_Ab;`) and is called by the instances that send to it; the
//!   incoming calls of a `msg in` variable are the instances that send to it (the `Inst.Msg`
//!   targets naming it, across every group), the outgoing calls of a `msg out` variable are the
//!   incoming messages it is wired to.
//!
//! Nothing is resolved here: the graph of an instance, the instance and the message of an
//! `Inst.Msg` target and the formal of an actual are read from the per-item use index
//! ([`defs::item_uses`], which the group rules' actual resolution fills). An item is identified
//! again by the position of its name ([`CallItem::focus_range`]), so a client can hand it back.
//! Ranges of a call are in the caller's file (incoming) or in the item's own file (outgoing), as
//! LSP wants them. External messages (wired to a symbol or an address) have no call. A
//! group's instances and wires are a salsa query per group ([`group_flow`]), so an edit elsewhere
//! leaves them cached.

use std::collections::{HashMap, HashSet};

use higraph_syntax::{
    TextRange, TextSize,
    ast::{self, AstNode},
};

use super::{
    FilePosition, SymbolKind,
    defs::{self, Definition, ItemId, UseTarget},
};
use crate::{
    Analysis, Cancellable,
    db::{self, ItemKind, Workspace},
    rules::group::interface::{MsgDir, graph_interface},
};

/// One node of the call hierarchy.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CallItem {
    pub name: String,
    /// Group, Instance, Graph or Message.
    pub kind: SymbolKind,
    /// The graph of an instance, the group it belongs to; the direction of a message.
    pub detail: String,
    /// Workspace-relative path of the declaring file.
    pub path: String,
    /// The whole declaration.
    pub full_range: TextRange,
    /// The declared name; its start re-identifies the item.
    pub focus_range: TextRange,
}

/// A call from or to an item, with the ranges where it happens.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Call {
    /// The caller (incoming calls) or the callee (outgoing calls).
    pub item: CallItem,
    /// In the caller's file: the instance name, the graph name of `instance X : G`, the
    /// `Inst.Msg` target, or the graph's writes of an outgoing message.
    pub ranges: Vec<TextRange>,
}

impl Analysis {
    /// The call hierarchy item at `pos`: a group, instance, graph or message variable named
    /// (declared or used) there.
    pub fn prepare_call_hierarchy(&self, pos: &FilePosition) -> Cancellable<Option<CallItem>> {
        self.with_db(|db, ws| {
            let file = self.file(&pos.path)?;
            let at = defs::definition_at(db, ws, file, pos.offset)?;
            let definition = callable(db, at.definition)?;
            call_item(db, ws, &definition)
        })
    }

    /// Who calls the item at `pos` (an item's focus position, as from
    /// [`Analysis::prepare_call_hierarchy`]).
    pub fn incoming_calls(&self, pos: &FilePosition) -> Cancellable<Vec<Call>> {
        self.with_db(|db, ws| {
            let Some(definition) = self
                .file(&pos.path)
                .and_then(|file| defs::definition_at(db, ws, file, pos.offset))
                .and_then(|at| callable(db, at.definition))
            else {
                return Vec::new();
            };
            let mut calls = Calls::default();
            let flows = flows(db, ws, &definition);
            match &definition {
                Definition::Group(_) => {}
                Definition::Instance { group, name } => {
                    for flow in flows.iter().filter(|f| f.group == *group) {
                        let Some(this) = flow.instance(name) else {
                            continue;
                        };
                        let range = flow.instances[this].name_range + flow.start;
                        calls.add(db, ws, &Definition::Group(flow.group), range);
                        for wire in flow.wires.iter().filter(|w| w.receiver == this) {
                            calls.add_item(
                                flow.instance_item(db, wire.sender),
                                &[wire.target_range + flow.start],
                            );
                        }
                    }
                }
                Definition::Graph(graph) => {
                    for flow in &flows {
                        for (i, inst) in flow.instances.iter().enumerate() {
                            if let (Some(g), Some(range)) = (inst.graph, inst.graph_range)
                                && g == *graph
                            {
                                calls.add_item(flow.instance_item(db, i), &[range + flow.start]);
                            }
                        }
                    }
                }
                Definition::Variable { owner, name } => {
                    for flow in &flows {
                        for wire in &flow.wires {
                            let receiver = &flow.instances[wire.receiver];
                            if receiver.graph == Some(*owner)
                                && wire
                                    .message
                                    .as_deref()
                                    .is_some_and(|m| m.eq_ignore_ascii_case(name))
                            {
                                calls.add_item(
                                    flow.instance_item(db, wire.sender),
                                    &[wire.target_range + flow.start],
                                );
                            }
                        }
                    }
                }
                _ => {}
            }
            calls.0
        })
    }

    /// What the item at `pos` calls (an item's focus position, as from
    /// [`Analysis::prepare_call_hierarchy`]).
    pub fn outgoing_calls(&self, pos: &FilePosition) -> Cancellable<Vec<Call>> {
        self.with_db(|db, ws| {
            let Some(definition) = self
                .file(&pos.path)
                .and_then(|file| defs::definition_at(db, ws, file, pos.offset))
                .and_then(|at| callable(db, at.definition))
            else {
                return Vec::new();
            };
            let mut calls = Calls::default();
            let flows = flows(db, ws, &definition);
            match &definition {
                Definition::Group(group) => {
                    for flow in flows.iter().filter(|f| f.group == *group) {
                        for (i, inst) in flow.instances.iter().enumerate() {
                            calls.add_item(
                                flow.instance_item(db, i),
                                &[inst.name_range + flow.start],
                            );
                        }
                    }
                }
                Definition::Instance { group, name } => {
                    for flow in flows.iter().filter(|f| f.group == *group) {
                        let Some(this) = flow.instance(name) else {
                            continue;
                        };
                        let inst = &flow.instances[this];
                        if let (Some(graph), Some(range)) = (inst.graph, inst.graph_range) {
                            calls.add(db, ws, &Definition::Graph(graph), range + flow.start);
                        }
                        for wire in flow.wires.iter().filter(|w| w.sender == this) {
                            calls.add_item(
                                flow.instance_item(db, wire.receiver),
                                &[wire.target_range + flow.start],
                            );
                        }
                    }
                }
                Definition::Variable { owner, name } => {
                    // Where the graph sends the message: its writes of the variable.
                    let start = defs::item_start(db, *owner);
                    let writes: Vec<TextRange> = defs::item_uses(
                        db,
                        ws,
                        defs::item_loc(db, *owner),
                    )
                    .uses
                    .iter()
                    .filter(|u| {
                        matches!(&u.target, UseTarget::Var(n) if n.eq_ignore_ascii_case(name))
                            && matches!(
                                u.kind,
                                defs::ReferenceKind::Write | defs::ReferenceKind::ReadWrite
                            )
                    })
                    .map(|u| u.range + start)
                    .collect();
                    for flow in &flows {
                        for wire in &flow.wires {
                            let sender = &flow.instances[wire.sender];
                            let (Some(formal), Some(graph), Some(message)) = (
                                wire.formal.as_deref(),
                                flow.instances[wire.receiver].graph,
                                wire.message.as_ref(),
                            ) else {
                                continue;
                            };
                            if sender.graph != Some(*owner) || !formal.eq_ignore_ascii_case(name) {
                                continue;
                            }
                            let callee = Definition::Variable {
                                owner: graph,
                                name: message.clone(),
                            };
                            calls.add_all(db, ws, &callee, &writes);
                        }
                    }
                }
                _ => {}
            }
            calls.0
        })
    }
}

/// The definition as a call hierarchy item's: groups, instances, graphs and message variables
/// of graphs.
fn callable(db: &dyn salsa::Database, definition: Definition) -> Option<Definition> {
    match &definition {
        Definition::Group(_) | Definition::Instance { .. } | Definition::Graph(_) => {
            Some(definition)
        }
        Definition::Variable { owner, name } => {
            (defs::item_kind(db, *owner) == Some(ItemKind::Graph)).then_some(())?;
            let interface = graph_interface(db, defs::item_loc(db, *owner));
            interface.var(name)?.message()?;
            Some(definition)
        }
        _ => None,
    }
}

/// The item of a callable definition.
fn call_item(db: &dyn salsa::Database, ws: Workspace, definition: &Definition) -> Option<CallItem> {
    let decl = defs::declaration(db, ws, definition)?;
    let item_name = |item: ItemId| {
        db::file_summary(db, item.file)
            .items
            .get(item.index as usize)
            .and_then(|s| s.name.clone())
            .unwrap_or_default()
    };
    let detail = match definition {
        Definition::Group(_) => "group".to_owned(),
        Definition::Graph(_) => "graph".to_owned(),
        Definition::Instance { group, name } => {
            let graph = db::item_root(db, defs::item_loc(db, *group))
                .and_then(ast::Group::cast)
                .and_then(|g| {
                    g.instances().find(|i| {
                        i.name()
                            .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
                    })
                })
                .and_then(|i| i.graph())
                .map(|g| g.text())
                .unwrap_or_default();
            format!("{} : {graph}", item_name(*group))
        }
        Definition::Variable { owner, name } => {
            let interface = graph_interface(db, defs::item_loc(db, *owner));
            let dir = match interface.var(name).and_then(|v| v.message()) {
                Some(MsgDir::Incoming) => "msg in",
                Some(MsgDir::Outgoing) => "msg out",
                None => "",
            };
            format!("{} {dir}", item_name(*owner))
        }
        _ => String::new(),
    };
    let kind = match definition {
        Definition::Variable { .. } => SymbolKind::Message,
        _ => decl.kind,
    };
    Some(CallItem {
        name: decl.name,
        kind,
        detail,
        path: decl.file.path(db).clone(),
        full_range: decl.full_range,
        focus_range: decl.focus_range,
    })
}

/// Calls collected in order, one per item (found by its file and name position), with their
/// ranges.
#[derive(Default)]
struct Calls(
    Vec<Call>,
    HashMap<(String, TextSize), usize>,
    HashSet<(usize, TextRange)>,
);

impl Calls {
    fn add(&mut self, db: &dyn salsa::Database, ws: Workspace, to: &Definition, range: TextRange) {
        self.add_all(db, ws, to, &[range]);
    }

    fn add_all(
        &mut self,
        db: &dyn salsa::Database,
        ws: Workspace,
        to: &Definition,
        ranges: &[TextRange],
    ) {
        if let Some(item) = call_item(db, ws, to) {
            self.add_item(item, ranges);
        }
    }

    fn add_item(&mut self, item: CallItem, ranges: &[TextRange]) {
        let key = (item.path.clone(), item.focus_range.start());
        let at = *self.1.entry(key).or_insert_with(|| {
            self.0.push(Call {
                item,
                ranges: Vec::new(),
            });
            self.0.len() - 1
        });
        for range in ranges {
            if self.2.insert((at, *range)) {
                self.0[at].ranges.push(*range);
            }
        }
    }
}

// ------------------------------------------------------------------------------ message flow

/// An instance of a group (the first of each name, as the rules count them). Ranges are
/// relative to the group item.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Instance {
    name: String,
    name_range: TextRange,
    full_range: TextRange,
    /// The graph as written.
    graph_name: String,
    /// The graph, as the use index resolved `instance X : G`.
    graph: Option<ItemId>,
    graph_range: Option<TextRange>,
}

/// An internal message: `formal := Receiver.message` in the sender's block.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Wire {
    sender: usize,
    /// The sender's formal as declared in its graph.
    formal: Option<String>,
    receiver: usize,
    /// The receiver's message variable as declared in its graph.
    message: Option<String>,
    /// `Receiver.message`, relative to the group item.
    target_range: TextRange,
}

/// The instances and internal messages of one group.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Flow {
    group: ItemId,
    /// The group's name.
    name: String,
    start: TextSize,
    instances: Vec<Instance>,
    wires: Vec<Wire>,
}

impl Flow {
    fn instance(&self, name: &str) -> Option<usize> {
        self.instances
            .iter()
            .position(|i| i.name.eq_ignore_ascii_case(name))
    }

    /// The call hierarchy item of an instance, without looking for its declaration again.
    fn instance_item(&self, db: &dyn salsa::Database, index: usize) -> CallItem {
        let inst = &self.instances[index];
        CallItem {
            name: inst.name.clone(),
            kind: SymbolKind::Instance,
            detail: format!("{} : {}", self.name, inst.graph_name),
            path: self.group.file.path(db).clone(),
            full_range: inst.full_range + self.start,
            focus_range: inst.name_range + self.start,
        }
    }
}

/// The flows the calls of `definition` need: its group's for a group or an instance, else
/// those of every group of the workspace, in workspace order.
fn flows<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    definition: &Definition,
) -> Vec<&'db Flow> {
    let groups = match definition {
        Definition::Group(group) | Definition::Instance { group, .. } => vec![*group],
        _ => defs::items_of_kind(db, ws, &[ItemKind::Group]),
    };
    groups
        .into_iter()
        .filter_map(|group| group_flow(db, ws, defs::item_loc(db, group)).as_ref())
        .collect()
}

/// The flow of a group item, cached: an edit elsewhere leaves it as it is.
#[salsa::tracked(returns(ref))]
fn group_flow<'db>(
    db: &'db dyn salsa::Database,
    ws: Workspace,
    item: crate::db::ItemLoc<'db>,
) -> Option<Flow> {
    let group = ItemId {
        file: item.file(db),
        index: item.index(db),
    };
    flow(db, ws, group)
}

/// The instances and wires of a group, read from its syntax and its use index.
fn flow(db: &dyn salsa::Database, ws: Workspace, group: ItemId) -> Option<Flow> {
    let root = db::item_root(db, defs::item_loc(db, group)).and_then(ast::Group::cast)?;
    let uses = &defs::item_uses(db, ws, defs::item_loc(db, group)).uses;
    // The use index is in text order: binary search by start.
    let use_at = |range: TextRange| {
        let from = uses.partition_point(|u| u.range.start() < range.start());
        uses[from..]
            .iter()
            .take_while(|u| u.range.start() == range.start())
            .find(|u| u.range == range)
            .map(|u| &u.target)
    };
    let mut instances: Vec<Instance> = Vec::new();
    let mut blocks: Vec<(usize, ast::Instance)> = Vec::new();
    for node in root.instances() {
        let Some(name) = node.name() else { continue };
        let text = name.text();
        if let Some(i) = instances
            .iter()
            .position(|i| i.name.eq_ignore_ascii_case(&text))
        {
            blocks.push((i, node));
            continue;
        }
        let graph_name = node.graph().map(|g| g.text()).unwrap_or_default();
        let graph_ref = node.graph().and_then(|g| g.token());
        let graph_range = graph_ref.as_ref().map(|t| t.text_range());
        let graph = graph_range.and_then(|r| match use_at(r) {
            Some(UseTarget::Graph(g)) => Some(*g),
            _ => None,
        });
        instances.push(Instance {
            name: text,
            graph_name,
            name_range: name.syntax().text_range(),
            full_range: node.syntax().text_range(),
            graph,
            graph_range: graph.and(graph_range),
        });
        blocks.push((instances.len() - 1, node));
    }
    let mut wires = Vec::new();
    for (sender, node) in blocks {
        // A later instance of the same name is no instance of its own (C3).
        if instances[sender].full_range != node.syntax().text_range() {
            continue;
        }
        for actual in node.actuals() {
            let Some(ast::Operand::MessageTarget(target)) = actual.value() else {
                continue;
            };
            let receiver = target
                .instance()
                .and_then(|i| i.token())
                .and_then(|t| match use_at(t.text_range()) {
                    Some(UseTarget::Instance(name)) => Some(name.clone()),
                    _ => None,
                })
                .and_then(|name| {
                    instances
                        .iter()
                        .position(|i| i.name.eq_ignore_ascii_case(&name))
                });
            let Some(receiver) = receiver else { continue };
            let declared = |token: Option<higraph_syntax::SyntaxToken>| {
                token.and_then(|t| match use_at(t.text_range()) {
                    Some(UseTarget::Formal { name, .. }) => Some(name.clone()),
                    _ => None,
                })
            };
            wires.push(Wire {
                sender,
                formal: declared(actual.formal().and_then(|f| f.token())),
                receiver,
                message: declared(target.message().and_then(|m| m.token())),
                target_range: target.syntax().text_range(),
            });
        }
    }
    Some(Flow {
        group,
        name: root.name().map(|n| n.text()).unwrap_or_default(),
        start: defs::item_start(db, group),
        instances,
        wires,
    })
}

#[cfg(test)]
mod tests {
    use crate::ide::{FilePosition, fixture};

    /// The drilling machine's shape: three graphs in their own files, a group wiring them.
    const DRILLING: &str = r#"//- graphs/bohren.higraph
graph Bohren <
  in_out < IM_Oben : BOOL msg in; OM_Senken : BOOL msg out; >
  state 0 < C: U IM_Oben; R IM_Oben; S OM_Senken; >
  trans any->0 < U INIT_SD; >
>
//- graphs/ventil.higraph
graph Ventil <
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  in < Oben : BOOL; >
  state 0 < C: S OM_Oben; U IM_Ab; >
  trans any->0 < U INIT_SD; >
>
//- symbols.higraph
symbols < Bohrer_Oben : E 0.0 : BOOL; Meldung : A 4.0 : BOOL; >
//- group.higraph
group Bohrmaschine fc FC 1 db DB 1 <
  instance Bohren : Bohren < OM_Senken := Vorschub.IM_Ab; >
  instance Vorschub : Ventil < Oben := Bohrer_Oben; OM_Oben := Bohren.IM_Oben; >
  instance Vorschub2 : Ventil < OM_Oben := Bohren.IM_Oben; >
>
"#;

    /// The fixture with `$0` before the `nth` occurrence of `needle` in `path`.
    fn at(path: &str, needle: &str, nth: usize) -> String {
        let marker = format!("//- {path}\n");
        let start = DRILLING.find(&marker).expect("path") + marker.len();
        let mut offset = start;
        for _ in 0..=nth {
            offset = DRILLING[offset..].find(needle).expect("needle") + offset + 1;
        }
        let mut text = DRILLING.to_owned();
        text.insert_str(offset - 1, "$0");
        text
    }

    /// The item, then the calls as `name (detail) at path 'range', ...`.
    fn check(fixture_text: &str) -> String {
        let f = fixture::load(fixture_text);
        let analysis = f.host.analysis();
        let Some(item) = analysis.prepare_call_hierarchy(&f.position).unwrap() else {
            return "no item".to_owned();
        };
        let pos = FilePosition {
            path: item.path.clone(),
            offset: item.focus_range.start(),
        };
        let mut out = format!(
            "{:?} {} ({}) in {} '{}'",
            item.kind,
            item.name,
            item.detail,
            item.path,
            f.slice(&item.path, item.focus_range)
        );
        for (label, calls, in_caller) in [
            ("in", analysis.incoming_calls(&pos).unwrap(), true),
            ("out", analysis.outgoing_calls(&pos).unwrap(), false),
        ] {
            for call in calls {
                let file = if in_caller {
                    &call.item.path
                } else {
                    &item.path
                };
                let ranges: Vec<&str> = call.ranges.iter().map(|r| f.slice(file, *r)).collect();
                out.push_str(&format!(
                    "\n{label}: {:?} {} ({}) at {}",
                    call.item.kind,
                    call.item.name,
                    call.item.detail,
                    ranges.join(", ")
                ));
            }
        }
        out
    }

    #[test]
    fn group_calls_its_instances() {
        insta::assert_snapshot!(check(&at("group.higraph", "Bohrmaschine", 0)), @"
        Group Bohrmaschine (group) in group.higraph 'Bohrmaschine'
        out: Instance Bohren (Bohrmaschine : Bohren) at Bohren
        out: Instance Vorschub (Bohrmaschine : Ventil) at Vorschub
        out: Instance Vorschub2 (Bohrmaschine : Ventil) at Vorschub2
        ");
    }

    #[test]
    fn instance_calls_its_graph_and_its_receivers() {
        insta::assert_snapshot!(check(&at("group.higraph", "Vorschub", 0)), @"
        Instance Vorschub (Bohrmaschine : Ventil) in group.higraph 'Vorschub'
        in: Group Bohrmaschine (group) at Vorschub
        in: Instance Bohren (Bohrmaschine : Bohren) at Vorschub.IM_Ab
        out: Graph Ventil (graph) at Ventil
        out: Instance Bohren (Bohrmaschine : Bohren) at Bohren.IM_Oben
        ");
    }

    #[test]
    fn instance_is_called_by_its_group_and_its_senders() {
        insta::assert_snapshot!(check(&at("group.higraph", "Bohren :", 0)), @"
        Instance Bohren (Bohrmaschine : Bohren) in group.higraph 'Bohren'
        in: Group Bohrmaschine (group) at Bohren
        in: Instance Vorschub (Bohrmaschine : Ventil) at Bohren.IM_Oben
        in: Instance Vorschub2 (Bohrmaschine : Ventil) at Bohren.IM_Oben
        out: Graph Bohren (graph) at Bohren
        out: Instance Vorschub (Bohrmaschine : Ventil) at Vorschub.IM_Ab
        ");
    }

    #[test]
    fn graph_is_called_by_its_instances() {
        insta::assert_snapshot!(check(&at("graphs/ventil.higraph", "Ventil", 0)), @"
        Graph Ventil (graph) in graphs/ventil.higraph 'Ventil'
        in: Instance Vorschub (Bohrmaschine : Ventil) at Ventil
        in: Instance Vorschub2 (Bohrmaschine : Ventil) at Ventil
        ");
    }

    #[test]
    fn incoming_message_is_called_by_its_senders() {
        insta::assert_snapshot!(check(&at("graphs/bohren.higraph", "IM_Oben", 0)), @"
        Message IM_Oben (Bohren msg in) in graphs/bohren.higraph 'IM_Oben'
        in: Instance Vorschub (Bohrmaschine : Ventil) at Bohren.IM_Oben
        in: Instance Vorschub2 (Bohrmaschine : Ventil) at Bohren.IM_Oben
        ");
    }

    #[test]
    fn outgoing_message_goes_to_its_receivers() {
        insta::assert_snapshot!(check(&at("graphs/ventil.higraph", "OM_Oben", 0)), @"
        Message OM_Oben (Ventil msg out) in graphs/ventil.higraph 'OM_Oben'
        out: Message IM_Oben (Bohren msg in) at OM_Oben
        ");
    }

    #[test]
    fn prepared_from_a_message_target_in_the_group() {
        // `Vorschub.IM_Ab`: the cursor on the message names Ventil's incoming message.
        insta::assert_snapshot!(check(&at("group.higraph", "IM_Ab", 0)), @"
        Message IM_Ab (Ventil msg in) in graphs/ventil.higraph 'IM_Ab'
        in: Instance Bohren (Bohrmaschine : Bohren) at Vorschub.IM_Ab
        ");
    }

    /// A second group: Ventil's report goes to a symbol (external) in one instance and to
    /// Bohren in the other; the first group's wires count too.
    const TWO_GROUPS: &str = r#"//- group2.higraph
group Zweite fc FC 2 db DB 2 <
  instance B : Bohren < >
  instance Extern : Ventil < OM_Oben := Meldung; >
  instance Intern : Ventil < OM_Oben := B.IM_Oben; >
>
"#;

    fn with_second_group(path: &str, needle: &str) -> String {
        format!("{}{TWO_GROUPS}", at(path, needle, 0))
    }

    #[test]
    fn across_groups_without_external_messages() {
        insta::assert_snapshot!(check(&with_second_group("graphs/bohren.higraph", "IM_Oben")), @"
        Message IM_Oben (Bohren msg in) in graphs/bohren.higraph 'IM_Oben'
        in: Instance Vorschub (Bohrmaschine : Ventil) at Bohren.IM_Oben
        in: Instance Vorschub2 (Bohrmaschine : Ventil) at Bohren.IM_Oben
        in: Instance Intern (Zweite : Ventil) at B.IM_Oben
        ");
        insta::assert_snapshot!(check(&with_second_group("graphs/ventil.higraph", "OM_Oben")), @"
        Message OM_Oben (Ventil msg out) in graphs/ventil.higraph 'OM_Oben'
        out: Message IM_Oben (Bohren msg in) at OM_Oben
        ");
        insta::assert_snapshot!(check(&with_second_group("graphs/ventil.higraph", "Ventil")), @"
        Graph Ventil (graph) in graphs/ventil.higraph 'Ventil'
        in: Instance Vorschub (Bohrmaschine : Ventil) at Ventil
        in: Instance Vorschub2 (Bohrmaschine : Ventil) at Ventil
        in: Instance Extern (Zweite : Ventil) at Ventil
        in: Instance Intern (Zweite : Ventil) at Ventil
        ");
    }

    #[test]
    fn no_item_at_a_plain_variable_or_a_state() {
        assert_eq!(
            check(&at("graphs/ventil.higraph", "Oben : BOOL;", 0)),
            "no item"
        );
        assert_eq!(check(&at("graphs/ventil.higraph", "state", 0)), "no item");
    }
}
