//! Operating modes of an instance (`diagnostics.md` §3.3): HG3103 (`ManualMode` and
//! `AutomaticMode` wired to the same operand) and HG3104 (`auto`/`manual` transitions whose
//! mode input is neither wired nor written by the graph).

use std::collections::HashMap;

use higraph_syntax::{TextRange, literal::LiteralValue};

use super::{
    actuals::Value,
    instances::{InstanceInfo, Wired},
    interface::{CalleeRef, GraphInterface, Mode},
};
use crate::{
    address, index,
    lang::Section,
    rules::{
        Ctx,
        symbols::{block_interface_addresses, interface_formal_section, well_formed_address},
    },
};

/// HG3103 and HG3104 for one instance whose graph is known.
pub(super) fn check_instance(
    ctx: &mut Ctx<'_>,
    instance: &InstanceInfo<'_>,
    graph: &GraphInterface,
    header: TextRange,
    wired: &HashMap<String, Wired<'_>>,
) {
    check_same_operand(ctx, instance, wired);
    for mode in [Mode::Automatic, Mode::Manual] {
        if graph.has_mode_transitions(mode)
            && !wired.contains_key(&index::key(mode.variable()))
            && !graph.writes(mode)
            && !call_may_write(ctx, graph, mode)
        {
            let diag = ctx.diag(
                "HG3104",
                header,
                format!(
                    "instance {}: graph {} has '{}' transitions, but {} is not wired, so they never fire",
                    instance.name,
                    graph.name,
                    mode.attribute(),
                    mode.variable()
                ),
            );
            ctx.push(diag);
        }
    }
}

/// HG3103: both mode inputs denote one operand, or both are `TRUE`.
fn check_same_operand(
    ctx: &mut Ctx<'_>,
    instance: &InstanceInfo<'_>,
    wired: &HashMap<String, Wired<'_>>,
) {
    let (Some(manual), Some(automatic)) = (
        wired.get(&index::key(Mode::Manual.variable())),
        wired.get(&index::key(Mode::Automatic.variable())),
    ) else {
        return;
    };
    if !same_operand(&manual.value, &automatic.value) {
        return;
    }
    let (earlier, later) = if manual.value_range.start() <= automatic.value_range.start() {
        (manual, automatic)
    } else {
        (automatic, manual)
    };
    let diag = ctx
        .diag(
            "HG3103",
            later.value_range,
            format!(
                "instance {}: ManualMode and AutomaticMode are wired to the same operand {}",
                instance.name, later.value_text
            ),
        )
        .related(
            ctx.loc(earlier.value_range),
            format!("{} is wired to {}", earlier.formal.name, earlier.value_text),
        );
    ctx.push(diag);
}

/// The same global symbol, the same normalised address, a symbol together with its own
/// address, or `TRUE` twice.
fn same_operand(a: &Value<'_>, b: &Value<'_>) -> bool {
    match (a, b) {
        (Value::Constant(x), Value::Constant(y)) => {
            x.value == LiteralValue::Bool(true) && y.value == LiteralValue::Bool(true)
        }
        (Value::Symbol(x), Value::Symbol(y)) if index::key(&x.name) == index::key(&y.name) => true,
        _ => match (a.address(), b.address()) {
            (Some(x), Some(y)) => x == y,
            _ => false,
        },
    }
}

/// Does a CALL of the graph pass the mode variable to a parameter that may write it (Appendix
/// E: an `out` or `in_out` formal, or a callee whose interface is unknown)?
fn call_may_write(ctx: &Ctx<'_>, graph: &GraphInterface, mode: Mode) -> bool {
    graph
        .mode_call_args
        .iter()
        .filter(|arg| arg.mode == mode)
        .any(|arg| {
            let Some(address) = callee_address(ctx, &arg.callee) else {
                return true;
            };
            let interfaces = block_interface_addresses(ctx.db, ctx.ws);
            let Some(interface) = interfaces.iter().find(|i| i.address == address) else {
                return true;
            };
            interface_formal_section(ctx.db, interface.file, interface.item, &arg.formal)
                != Some(Section::In)
        })
}

fn callee_address(ctx: &Ctx<'_>, callee: &CalleeRef) -> Option<address::Address> {
    match callee {
        CalleeRef::Address(text) => address::read(text, ctx.mnemonic).and_then(|r| r.address.ok()),
        CalleeRef::Name(name) => well_formed_address(name, ctx.mnemonic)
            .or_else(|| ctx.index.symbol(name).and_then(|s| s.address.clone())),
    }
}
