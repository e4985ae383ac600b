//! Instances and their actual parameters (`diagnostics.md` §3.5, §3.3): HG5001–HG5003,
//! HG5101–HG5105, HG3103, HG3104, HG1104 for graph and formal names; the message rules
//! HG5201–HG5207 live in [`super::messages`].

use std::collections::{HashMap, HashSet};

use higraph_syntax::{
    SyntaxKind, TextRange,
    ast::{self, AstNode},
};

use super::{
    actuals::{self, Value},
    interface::{GraphInterface, MsgDir, PREDEFINED_FORMALS, graph_interface, is_predefined_stat},
    messages, modes,
};
use crate::{
    closest::closest,
    db::{ItemKind, ItemLoc},
    index,
    lang::{Section, Type},
    rules::{
        Ctx, has_error,
        symbols::{check_case, node_text},
    },
};

/// The most instances a group may hold (HG5002).
const MAX_INSTANCES: usize = 255;

/// One instance of the group.
pub(super) struct InstanceInfo<'a> {
    pub node: ast::Instance,
    /// The instance name as declared.
    pub name: String,
    pub name_range: TextRange,
    /// From `instance` through the graph name.
    pub header: Option<TextRange>,
    /// The instantiated graph, if it exists (no HG5001).
    pub graph: Option<&'a GraphInterface>,
}

/// A resolved formal parameter of the instance's graph.
#[derive(Debug, Clone)]
pub(super) struct Formal {
    /// As declared.
    pub name: String,
    pub section: Section,
    pub ty: Option<Type>,
    pub message: Option<MsgDir>,
}

/// The first actual of a formal in an instance.
pub(super) struct Wired<'a> {
    pub formal: Formal,
    pub value: Value<'a>,
    /// The actual value: everything between `:=` and `;`.
    pub value_range: TextRange,
    pub value_text: String,
}

/// An `Inst.Msg` actual anywhere in the group.
pub(super) struct Sender {
    /// The target instance and message, as written.
    pub instance: String,
    pub message: String,
    /// The sending instance, as declared.
    pub sender: String,
    /// The actual value `Inst.Msg`.
    pub range: TextRange,
}

/// Everything the instance rules need about the group.
pub(super) struct GroupInfo<'a> {
    /// The group's name as declared.
    pub name: String,
    pub instances: Vec<InstanceInfo<'a>>,
    pub senders: Vec<Sender>,
}

impl<'a> GroupInfo<'a> {
    /// The first instance of that name (C3).
    pub fn instance(&self, name: &str) -> Option<&InstanceInfo<'a>> {
        self.instances
            .iter()
            .find(|i| i.name.eq_ignore_ascii_case(name))
    }

    /// Is `instance` the one its name refers to (not a later duplicate)?
    pub fn is_first(&self, instance: &InstanceInfo<'a>) -> bool {
        self.instance(&instance.name)
            .is_some_and(|first| first.name_range == instance.name_range)
    }
}

/// The instance rules of one group: HG5002, HG5003, then each instance.
pub(super) fn check(ctx: &mut Ctx<'_>, group: &ast::Group, group_name: &str) {
    let instances: Vec<InstanceInfo<'_>> = group
        .instances()
        .filter_map(|node| instance_info(ctx, node))
        .collect();
    let info = GroupInfo {
        name: group_name.to_owned(),
        senders: collect_senders(&instances),
        instances,
    };
    check_count(ctx, &info);
    check_names(ctx, &info);
    for instance in &info.instances {
        if info.is_first(instance) {
            check_instance(ctx, &info, instance);
        } else {
            record_uses(ctx, instance);
        }
    }
}

/// A later instance of a duplicated name is reported (HG5003) and otherwise ignored (C3); the
/// symbols its actuals name still count as used (HG6004).
fn record_uses(ctx: &mut Ctx<'_>, instance: &InstanceInfo<'_>) {
    let reported = ctx.out.diags.len();
    for actual in instance.node.actuals() {
        if let Some(operand) = actual.value().filter(|_| !has_error(actual.syntax())) {
            actuals::resolve(ctx, &operand);
        }
    }
    ctx.out.diags.truncate(reported);
}

fn instance_info<'a>(ctx: &mut Ctx<'a>, node: ast::Instance) -> Option<InstanceInfo<'a>> {
    let name = node.name()?;
    let name_range = name.token()?.text_range();
    let header = instance_header(&node);
    let db = ctx.db;
    let graph = node
        .graph()
        .and_then(|g| ctx.index.graph(&g.text()))
        .map(|item| graph_interface(db, ItemLoc::new(db, item.file, item.item)));
    Some(InstanceInfo {
        name: name.text(),
        name_range,
        header,
        graph,
        node,
    })
}

/// From `instance` through the graph name.
fn instance_header(node: &ast::Instance) -> Option<TextRange> {
    let start = node
        .syntax()
        .children_with_tokens()
        .filter_map(|e| e.into_token())
        .find(|t| t.kind() == SyntaxKind::INSTANCE_KW)?
        .text_range()
        .start();
    let end = node.graph()?.syntax().text_range().end();
    (start <= end).then(|| TextRange::new(start, end))
}

/// The `Inst.Msg` actuals of the group. A later instance of a duplicated name, and a later
/// actual of a formal that an earlier actual wires (HG5102), are ignored (C3): they send
/// nothing.
fn collect_senders(instances: &[InstanceInfo<'_>]) -> Vec<Sender> {
    let mut senders = Vec::new();
    let mut seen = HashSet::new();
    for instance in instances {
        if !seen.insert(index::key(&instance.name)) {
            continue;
        }
        let mut formals = HashSet::new();
        for actual in instance.node.actuals() {
            if let Some(formal) = actual.formal()
                && !formals.insert(index::key(&formal.text()))
            {
                continue;
            }
            let Some(ast::Operand::MessageTarget(target)) = actual.value() else {
                continue;
            };
            let (Some(inst), Some(msg)) = (target.instance(), target.message()) else {
                continue;
            };
            senders.push(Sender {
                instance: inst.text(),
                message: msg.text(),
                sender: instance.name.clone(),
                range: target.syntax().text_range(),
            });
        }
    }
    senders
}

/// HG5002: more than 255 instances, reported once on the 256th.
fn check_count(ctx: &mut Ctx<'_>, info: &GroupInfo<'_>) {
    let counted: Vec<TextRange> = info.instances.iter().filter_map(|i| i.header).collect();
    if let Some(&header) = counted.get(MAX_INSTANCES) {
        let diag = ctx.diag(
            "HG5002",
            header,
            format!(
                "group {} has {} instances; at most {MAX_INSTANCES} are allowed",
                info.name,
                counted.len()
            ),
        );
        ctx.push(diag);
    }
}

/// HG5003: an instance name used a second time.
fn check_names(ctx: &mut Ctx<'_>, info: &GroupInfo<'_>) {
    let mut first: HashMap<String, &InstanceInfo<'_>> = HashMap::new();
    for instance in &info.instances {
        match first.get(&index::key(&instance.name)) {
            Some(original) => {
                let diag = ctx
                    .diag(
                        "HG5003",
                        instance.name_range,
                        format!(
                            "instance name '{}' is already used in group {}",
                            instance.name, info.name
                        ),
                    )
                    .related(
                        ctx.loc(original.name_range),
                        format!("instance '{}' is declared here", original.name),
                    );
                ctx.push(diag);
            }
            None => {
                first.insert(index::key(&instance.name), instance);
            }
        }
    }
}

fn check_instance(ctx: &mut Ctx<'_>, info: &GroupInfo<'_>, instance: &InstanceInfo<'_>) {
    check_graph_name(ctx, instance);
    let wired = check_actuals(ctx, info, instance);
    let (Some(graph), Some(header)) = (instance.graph, instance.header) else {
        return;
    };
    check_missing(ctx, instance, graph, header, &wired);
    messages::check_instance(ctx, info, instance, graph, header, &wired);
    modes::check_instance(ctx, instance, graph, header, &wired);
}

/// HG5001 for a graph name that names no graph; HG1104 for one spelled in another case.
fn check_graph_name(ctx: &mut Ctx<'_>, instance: &InstanceInfo<'_>) {
    let Some(graph_ref) = instance.node.graph() else {
        return;
    };
    let Some(token) = graph_ref.token() else {
        return;
    };
    let written = graph_ref.text();
    if let Some(graph) = instance.graph {
        check_case(ctx, &token, &written, &graph.name);
        return;
    }
    let index = ctx.index;
    let other = index.items_named(&written).next().map(|i| match i.kind {
        ItemKind::Group => "a group",
        _ => "a chart",
    });
    let other = other.or_else(|| index.symbol(&written).map(|_| "a symbol"));
    let message = match other {
        Some(kind) => format!("'{written}' is {kind}, not a graph"),
        None => format!("graph '{written}' does not exist"),
    };
    let range = token.text_range();
    let mut diag = ctx.diag("HG5001", range, message);
    let graphs = index
        .items
        .iter()
        .filter(|i| i.kind == ItemKind::Graph)
        .map(|i| i.name.as_str());
    diag = ctx.with_closest_fix(diag, range, &written, graphs);
    ctx.push(diag);
}

/// The formal of that name: a declared `in`/`out`/`in_out` variable or a predefined input.
fn resolve_formal(graph: &GraphInterface, name: &str) -> Option<Formal> {
    if let Some(var) = graph.var(name) {
        return var.section.is_formal().then(|| Formal {
            name: var.name.clone(),
            section: var.section,
            ty: var.ty,
            message: var.message(),
        });
    }
    PREDEFINED_FORMALS
        .iter()
        .find(|p| p.eq_ignore_ascii_case(name))
        .map(|p| Formal {
            name: (*p).to_owned(),
            section: Section::In,
            ty: Some(Type::Bool),
            message: None,
        })
}

/// The actuals of one instance: HG5101, HG5102, HG1104, value resolution and HG5104/HG5105/
/// HG5203/HG5204. Returns the first actual of each formal, by upper-case formal name.
fn check_actuals<'a>(
    ctx: &mut Ctx<'a>,
    info: &GroupInfo<'_>,
    instance: &InstanceInfo<'_>,
) -> HashMap<String, Wired<'a>> {
    let written_formals: HashSet<String> = instance
        .node
        .actuals()
        .filter_map(|a| a.formal())
        .map(|f| index::key(&f.text()))
        .collect();
    let mut wired: HashMap<String, Wired<'a>> = HashMap::new();
    for actual in instance.node.actuals() {
        let Some(formal_ref) = actual.formal() else {
            continue;
        };
        let Some(token) = formal_ref.token() else {
            continue;
        };
        let formal = match instance.graph {
            Some(graph) => check_formal(
                ctx,
                instance,
                graph,
                &actual,
                &token,
                &wired,
                &written_formals,
            ),
            None => None,
        };
        let operand = if has_error(actual.syntax()) {
            None
        } else {
            actual.value()
        };
        // A broken value still wires its formal (C1); it is not checked further.
        let (value, value_range, value_text) = match operand {
            Some(operand) => {
                let range = operand.syntax().text_range();
                let text = node_text(operand.syntax());
                let value = check_operand(ctx, info, instance, formal.as_ref(), &actual, &operand);
                (value, range, text)
            }
            None => (Value::Unknown, actual.syntax().text_range(), String::new()),
        };
        if let Some(formal) = formal {
            wired.insert(
                index::key(&formal.name),
                Wired {
                    formal,
                    value,
                    value_range,
                    value_text,
                },
            );
        }
    }
    wired
}

/// Resolves the value of an actual and checks it against its formal: HG5203 and the target
/// rules for `Inst.Msg`, else value resolution and HG5204/HG5105/HG5104.
fn check_operand<'a>(
    ctx: &mut Ctx<'a>,
    info: &GroupInfo<'_>,
    instance: &InstanceInfo<'_>,
    formal: Option<&Formal>,
    actual: &ast::Actual,
    operand: &ast::Operand,
) -> Value<'a> {
    let range = operand.syntax().text_range();
    if let ast::Operand::MessageTarget(target) = operand {
        let reported = formal.is_some_and(|f| messages::check_receiver(ctx, f, actual, range));
        if !reported {
            messages::check_target(ctx, info, target);
        }
        return Value::Message;
    }
    let value = actuals::resolve(ctx, operand);
    if let (Some(graph), Some(formal)) = (instance.graph, formal) {
        check_value(
            ctx,
            graph,
            formal,
            &value,
            range,
            &node_text(operand.syntax()),
        );
    }
    value
}

/// HG5101, HG5102 and HG1104 for the formal name of an actual. Returns the formal if the
/// actual is its first one.
fn check_formal(
    ctx: &mut Ctx<'_>,
    instance: &InstanceInfo<'_>,
    graph: &GraphInterface,
    actual: &ast::Actual,
    token: &higraph_syntax::SyntaxToken,
    wired: &HashMap<String, Wired<'_>>,
    written_formals: &HashSet<String>,
) -> Option<Formal> {
    let written = token.text();
    let range = token.text_range();
    let Some(formal) = resolve_formal(graph, written) else {
        report_not_a_formal(ctx, graph, written, range, written_formals);
        return None;
    };
    if let Some(first) = wired.get(&index::key(&formal.name)) {
        let first_range = first.value_range;
        let diag = ctx
            .diag(
                "HG5102",
                range,
                format!(
                    "'{written}' already has an actual in instance {}",
                    instance.name
                ),
            )
            .related(
                ctx.loc(first_range),
                format!("the first actual of '{}'", formal.name),
            )
            .fix(
                "Remove the later actual",
                ctx.loc(actual.syntax().text_range()),
                "",
            );
        ctx.push(diag);
        return None;
    }
    check_case(ctx, token, written, &formal.name);
    Some(formal)
}

/// HG5101 with its three variants.
fn report_not_a_formal(
    ctx: &mut Ctx<'_>,
    graph: &GraphInterface,
    written: &str,
    range: TextRange,
    written_formals: &HashSet<String>,
) {
    let is_stat = graph.var(written).map_or_else(
        || is_predefined_stat(written),
        |v| v.section == Section::Stat,
    );
    let message = if written.eq_ignore_ascii_case("INIT_SD") {
        "INIT_SD is supplied by the group FC and cannot be wired".to_owned()
    } else if is_stat {
        format!(
            "'{written}' is a stat variable of {}, not a formal parameter",
            graph.name
        )
    } else {
        format!("graph {} has no formal parameter '{written}'", graph.name)
    };
    let mut diag = ctx.diag("HG5101", range, message);
    if !written.eq_ignore_ascii_case("INIT_SD") {
        let free = graph
            .formal_names()
            .filter(|f| !written_formals.contains(&index::key(f)));
        if let Some(best) = closest(written, free) {
            diag = diag
                .fix(format!("Rename to '{best}'"), ctx.loc(range), best)
                .preferred();
        }
    }
    ctx.push(diag);
}

/// HG5204, HG5105 and HG5104 for a value that is not `Inst.Msg`.
fn check_value(
    ctx: &mut Ctx<'_>,
    graph: &GraphInterface,
    formal: &Formal,
    value: &Value<'_>,
    range: TextRange,
    text: &str,
) {
    if formal.message.is_some() {
        if value.is_external_message() == Some(false) {
            let what = if value.is_constant() {
                "a constant".to_owned()
            } else {
                value.ty().unwrap_or_default()
            };
            let diag = ctx.diag(
                "HG5204",
                range,
                format!(
                    "message '{}' needs a bit address or a BOOL symbol; {text} is {what}",
                    formal.name
                ),
            );
            ctx.push(diag);
        }
        return;
    }
    if value.is_constant() && matches!(formal.section, Section::Out | Section::InOut) {
        let diag = ctx.diag(
            "HG5105",
            range,
            format!(
                "'{}' is an {} parameter; a constant cannot receive values",
                formal.name,
                formal.section.as_str()
            ),
        );
        ctx.push(diag);
        return;
    }
    let Some(ty) = formal.ty else {
        return;
    };
    if value.compatible(ty) == Some(false) {
        let actual_type = value.ty().unwrap_or_default();
        let diag = ctx.diag(
            "HG5104",
            range,
            format!(
                "type conflict: {} of {} is {ty}, the actual {text} is {actual_type}",
                formal.name, graph.name
            ),
        );
        ctx.push(diag);
    }
}

/// HG5103: user formals (not messages) without an actual; one diagnostic per instance.
fn check_missing(
    ctx: &mut Ctx<'_>,
    instance: &InstanceInfo<'_>,
    graph: &GraphInterface,
    header: TextRange,
    wired: &HashMap<String, Wired<'_>>,
) {
    let missing: Vec<&str> = graph
        .vars
        .iter()
        .filter(|v| v.section.is_formal() && v.message().is_none())
        .filter(|v| !wired.contains_key(&index::key(&v.name)))
        .map(|v| v.name.as_str())
        .collect();
    if missing.is_empty() {
        return;
    }
    let list = missing
        .iter()
        .map(|m| format!("'{m}'"))
        .collect::<Vec<_>>()
        .join(", ");
    let mut diag = ctx.diag(
        "HG5103",
        header,
        format!("instance {}: no actual for {list}", instance.name),
    );
    if let Some(r_angle) = instance.node.body().and_then(|b| b.r_angle()) {
        let text: String = missing.iter().map(|m| format!("{m} := {m}; ")).collect();
        diag = diag.fix(
            "Add the missing actual parameters",
            ctx.loc(TextRange::empty(r_angle.text_range().start())),
            text,
        );
    }
    ctx.push(diag);
}
