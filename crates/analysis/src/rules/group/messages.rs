//! Messages between the instances of a group (`diagnostics.md` §3.5, §2.7a): HG5201 (the
//! target `Inst.Msg` does not exist), HG5202 (it is not an incoming message), HG5203 (`Inst.Msg`
//! on a formal that is not an outgoing message), HG5205 (outgoing message not wired), HG5206
//! (incoming message without sender or address) and HG5207 (an incoming message wired both
//! externally and internally). HG5204 is checked with the other values in
//! [`super::instances`].

use std::collections::HashMap;

use higraph_syntax::{
    TextRange,
    ast::{self, AstNode},
};

use super::{
    actuals::Value,
    instances::{Formal, GroupInfo, InstanceInfo, Wired},
    interface::{GraphInterface, InterfaceVar, MsgDir},
};
use crate::{
    index,
    lang::{self, Section},
    rules::{Ctx, symbols::check_case},
};

/// HG5203 for `Inst.Msg` given to a formal that is not an outgoing message. Returns whether
/// it was reported (then HG5201/HG5202 are not evaluated for the actual, C4).
pub(super) fn check_receiver(
    ctx: &mut Ctx<'_>,
    formal: &Formal,
    actual: &ast::Actual,
    value_range: TextRange,
) -> bool {
    let diag = match formal.message {
        Some(MsgDir::Outgoing) => return false,
        Some(MsgDir::Incoming) => ctx
            .diag(
                "HG5203",
                value_range,
                format!(
                    "the receiver is named at the sender; leave incoming message '{}' unwired",
                    formal.name
                ),
            )
            .fix(
                "Remove the actual",
                ctx.loc(actual.syntax().text_range()),
                "",
            ),
        None => ctx.diag(
            "HG5203",
            value_range,
            format!(
                "'{}' is not a message; 'Instance.Message' is only for outgoing messages",
                formal.name
            ),
        ),
    };
    ctx.push(diag);
    true
}

/// What a variable of the target graph is, for HG5202.
fn describe(var: &InterfaceVar) -> &'static str {
    match (var.message(), var.section) {
        (Some(MsgDir::Outgoing), _) => "an outgoing message",
        (Some(MsgDir::Incoming), _) => "an incoming message",
        (None, Section::In) => "an in variable",
        (None, Section::Out) => "an out variable",
        (None, Section::InOut) => "an in_out variable",
        (None, Section::Stat) => "a stat variable",
    }
}

/// HG5201, HG5202 and HG1104 for a message target `Inst.Msg`.
pub(super) fn check_target(ctx: &mut Ctx<'_>, info: &GroupInfo<'_>, target: &ast::MessageTarget) {
    let (Some(inst_ref), Some(msg_ref)) = (target.instance(), target.message()) else {
        return;
    };
    let (Some(inst_token), Some(msg_token)) = (inst_ref.token(), msg_ref.token()) else {
        return;
    };
    let inst = inst_ref.text();
    let msg = msg_ref.text();
    let Some(instance) = info.instance(&inst) else {
        let range = inst_token.text_range();
        let mut diag = ctx.diag(
            "HG5201",
            range,
            format!("no instance '{inst}' in group {}", info.name),
        );
        let names = info.instances.iter().map(|i| i.name.as_str());
        diag = ctx.with_closest_fix(diag, range, &inst, names);
        ctx.push(diag);
        return;
    };
    check_case(ctx, &inst_token, &inst, &instance.name);
    let Some(graph) = instance.graph else {
        // HG5001 turns off HG5201/HG5202 for targets inside that instance (C4).
        return;
    };
    let range = msg_token.text_range();
    if let Some(var) = graph.var(&msg) {
        check_case(ctx, &msg_token, &msg, &var.name);
        if var.message() != Some(MsgDir::Incoming) {
            let diag = ctx.diag(
                "HG5202",
                range,
                format!(
                    "{inst}.{msg} is not an incoming message (it is {})",
                    describe(var)
                ),
            );
            ctx.push(diag);
        }
        return;
    }
    if let Some(predefined) = lang::predefined(&msg) {
        check_case(ctx, &msg_token, &msg, predefined.name);
        let diag = ctx.diag(
            "HG5202",
            range,
            format!("{inst}.{msg} is not an incoming message (it is a predefined variable)"),
        );
        ctx.push(diag);
        return;
    }
    let mut diag = ctx.diag(
        "HG5201",
        range,
        format!(
            "graph {} of instance {inst} has no variable '{msg}'",
            graph.name
        ),
    );
    let incoming = incoming_messages(graph).map(|v| v.name.as_str());
    diag = ctx.with_closest_fix(diag, range, &msg, incoming);
    ctx.push(diag);
}

fn incoming_messages(graph: &GraphInterface) -> impl Iterator<Item = &InterfaceVar> {
    graph
        .vars
        .iter()
        .filter(|v| v.message() == Some(MsgDir::Incoming))
}

fn outgoing_messages(graph: &GraphInterface) -> impl Iterator<Item = &InterfaceVar> {
    graph
        .vars
        .iter()
        .filter(|v| v.message() == Some(MsgDir::Outgoing))
}

/// HG5205, HG5206 and HG5207 for the message formals of one instance.
pub(super) fn check_instance(
    ctx: &mut Ctx<'_>,
    info: &GroupInfo<'_>,
    instance: &InstanceInfo<'_>,
    graph: &GraphInterface,
    header: TextRange,
    wired: &HashMap<String, Wired<'_>>,
) {
    for var in outgoing_messages(graph) {
        if !wired.contains_key(&index::key(&var.name)) {
            let diag = ctx.diag(
                "HG5205",
                header,
                format!(
                    "instance {}: outgoing message '{}' is not wired",
                    instance.name, var.name
                ),
            );
            ctx.push(diag);
        }
    }
    let is_first = info.is_first(instance);
    for var in incoming_messages(graph) {
        let senders: Vec<&super::instances::Sender> = info
            .senders
            .iter()
            .filter(|s| {
                is_first
                    && s.instance.eq_ignore_ascii_case(&instance.name)
                    && s.message.eq_ignore_ascii_case(&var.name)
            })
            .collect();
        match wired.get(&index::key(&var.name)) {
            None if senders.is_empty() => {
                let diag = ctx.diag(
                    "HG5206",
                    header,
                    format!(
                        "instance {}: incoming message '{}' has no sender in group {} and no external address",
                        instance.name, var.name, info.name
                    ),
                );
                ctx.push(diag);
            }
            Some(actual)
                if !senders.is_empty()
                    && !actual.value_text.is_empty()
                    && !matches!(actual.value, Value::Message) =>
            {
                report_double_wiring(ctx, instance, var, actual, &senders);
            }
            _ => {}
        }
    }
}

/// HG5207: an external actual of an incoming message that also has internal senders.
fn report_double_wiring(
    ctx: &mut Ctx<'_>,
    instance: &InstanceInfo<'_>,
    var: &InterfaceVar,
    actual: &Wired<'_>,
    senders: &[&super::instances::Sender],
) {
    let Some(first) = senders.first() else {
        return;
    };
    let mut diag = ctx.diag(
        "HG5207",
        actual.value_range,
        format!(
            "instance {}: incoming message '{}' is wired to {}, but {} sends to it internally; that message never arrives",
            instance.name, var.name, actual.value_text, first.sender
        ),
    );
    for sender in senders {
        diag = diag.related(
            ctx.loc(sender.range),
            format!(
                "{} sends {}.{} here",
                sender.sender, instance.name, var.name
            ),
        );
    }
    ctx.push(diag);
}
