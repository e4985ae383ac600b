//! FBD and LD networks of transition conditions → one expression.
//!
//! A condition given as a network (`<condition><connectionPointIn>` into the SFC body's own
//! FBD/LD elements, or the FBD/LD body of a named transition) is read backwards from the
//! connection that gives its value:
//!
//! * `inVariable` → its ST expression; `leftPowerRail` → `TRUE`;
//! * `contact` → its variable (`NOT` when negated) AND whatever powers it; several connections
//!   into one `connectionPointIn` are wired in parallel (OR);
//! * `block` of a standard function (`AND OR XOR NOT`, the comparisons, `ADD SUB MUL DIV MOD`,
//!   `MOVE`) → the operator; negated inputs and outputs become `NOT`;
//! * `block` of a standard function block instance (`TON`, `SR`, ...) → a read of its output
//!   (`TON3.Q`) and a call of the instance with its connected inputs in the sequencer's
//!   `pre` part, as Beremiz runs the blocks of condition networks in every cycle before the
//!   SFC; a block reached again through its own inputs (feedback) reads the output of the
//!   previous call;
//! * `connector` / `continuation` pairs are followed by name.
//!
//! Everything else (edge contacts, coils inside the network, unknown block types, `EN`/`ENO`,
//! cycles without a function block instance) is an error naming it. The expression is built
//! as ST text with parentheses around every operand and then converted by [`crate::st`],
//! which writes the language's spelling with the parentheses that are needed.
//!
//! Cost: every element's value is computed once per network (memoized, errors included); the
//! recursion is at most [`MAX_DEPTH`] elements deep, and an expression longer than
//! [`MAX_TEXT`] characters (shared sub-networks copied many times) is refused.

use std::collections::HashMap;

use roxmltree::Node;

use crate::st::{self, Names};
use crate::xml::{self, attr, child, children};

/// Longest chain of elements followed from a condition.
pub const MAX_DEPTH: usize = 40;
/// Longest expression text built from a network.
pub const MAX_TEXT: usize = 20_000;

/// Inputs and outputs of the standard function blocks (`docs/iec.md` §3).
fn fb_interface(ty: &str) -> Option<(&'static [&'static str], &'static [&'static str])> {
    Some(match ty {
        "TON" | "TOF" | "TP" => (&["IN", "PT"], &["Q", "ET"]),
        "R_TRIG" | "F_TRIG" => (&["CLK"], &["Q"]),
        "CTU" => (&["CU", "R", "PV"], &["Q", "CV"]),
        "CTD" => (&["CD", "LD", "PV"], &["Q", "CV"]),
        "CTUD" => (&["CU", "CD", "R", "LD", "PV"], &["QU", "QD", "CV"]),
        "SR" => (&["S1", "R"], &["Q1"]),
        "RS" => (&["S", "R1"], &["Q1"]),
        _ => return None,
    })
}

/// The elements of one network by `localId`, and its connectors by name.
pub struct Net<'a, 'i> {
    elements: HashMap<u64, Node<'a, 'i>>,
    connectors: HashMap<String, Node<'a, 'i>>,
}

impl<'a, 'i> Net<'a, 'i> {
    /// The network of these elements (the children of an `FBD`/`LD` body, or the non-SFC
    /// elements of an SFC body); the first element of a `localId` counts.
    pub fn new(elements: impl Iterator<Item = Node<'a, 'i>>) -> Net<'a, 'i> {
        let mut net = Net {
            elements: HashMap::new(),
            connectors: HashMap::new(),
        };
        for e in elements.filter(|e| e.is_element()) {
            if let Some(id) = attr(e, "localId").and_then(|v| v.trim().parse::<u64>().ok()) {
                net.elements.entry(id).or_insert(e);
            }
            if xml::local(e) == "connector"
                && let Some(n) = attr(e, "name")
            {
                net.connectors
                    .entry(n.trim().to_ascii_uppercase())
                    .or_insert(e);
            }
        }
        net
    }

    /// The element that gives the value of the named transition `name` in its FBD/LD body:
    /// the `outVariable` or `coil` named like the transition, else the only one there is.
    pub fn result(&self, name: &str) -> Result<Node<'a, 'i>, String> {
        let mut outs: Vec<Node<'a, 'i>> = self
            .elements
            .values()
            .copied()
            .filter(|e| matches!(xml::local(*e), "outVariable" | "coil"))
            .collect();
        outs.sort_by_key(|e| e.range().start);
        let named = |e: &Node<'_, '_>| {
            let text = match xml::local(*e) {
                "outVariable" => child(*e, "expression").map(xml::text),
                _ => child(*e, "variable").map(xml::text),
            };
            text.is_some_and(|t| !name.is_empty() && t.trim().eq_ignore_ascii_case(name))
        };
        if let Some(e) = outs.iter().find(|e| named(e)) {
            return Ok(*e);
        }
        match outs.as_slice() {
            [only] => Ok(*only),
            [] => Err("its network has no output variable or coil".to_owned()),
            _ => Err(format!(
                "its network has several outputs and none is named {name}"
            )),
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Visit {
    InProgress,
    Called,
}

/// The state of one network across the conditions that read it: the values computed so far
/// and the function block instances already called.
#[derive(Default)]
pub struct NetState {
    memo: HashMap<u64, Result<String, String>>,
    visits: HashMap<u64, Visit>,
}

/// Builds conditions from networks; the calls of function block instances met on the way
/// collect in `calls` (ST text, in the order they must run).
pub struct Translator<'n> {
    pub names: &'n Names,
    /// Upper-cased instance name → upper-cased standard function block type.
    pub fb_types: &'n HashMap<String, String>,
    pub calls: Vec<String>,
}

/// One condition being built: the instance calls it added (undone when it fails).
struct Attempt {
    calls: Vec<String>,
    called: Vec<u64>,
}

impl Translator<'_> {
    /// The condition given by `result` (an `outVariable` or `coil` of a named transition's
    /// body, or the `connectionPointIn` of an SFC condition) in the language's spelling.
    pub fn condition(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        result: Node<'_, '_>,
    ) -> Result<String, String> {
        let mut attempt = Attempt {
            calls: Vec::new(),
            called: Vec::new(),
        };
        let text = self.result_text(net, state, result, &mut attempt);
        let text = text.and_then(|t| {
            st::condition(&t, self.names)
                .map_err(|e| format!("the expression the network gives: {}", e.reason))
        });
        // The calls in the language's spelling (each argument was converted on the way).
        let text = text.and_then(|t| {
            let mut calls = Vec::with_capacity(attempt.calls.len());
            for c in &attempt.calls {
                let call = st::statements(c, self.names, 0)
                    .map_err(|e| format!("the call `{c}`: {}", e.reason))?;
                calls.push(call.trim().to_owned());
            }
            Ok((t, calls))
        });
        match text {
            Ok((t, mut calls)) => {
                self.calls.append(&mut calls);
                Ok(t)
            }
            Err(e) => {
                for id in attempt.called {
                    state.visits.remove(&id);
                }
                Err(e)
            }
        }
    }

    fn result_text(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        result: Node<'_, '_>,
        attempt: &mut Attempt,
    ) -> Result<String, String> {
        match xml::local(result) {
            "connectionPointIn" => self.input(net, state, result, attempt, 0),
            "outVariable" | "coil" => {
                if xml::local(result) == "coil"
                    && let Some(s) = attr(result, "storage").filter(|s| *s != "none")
                {
                    return Err(format!("a {s} coil gives the condition"));
                }
                let Some(cpi) = child(result, "connectionPointIn") else {
                    return Err(format!("the <{}> is not connected", xml::local(result)));
                };
                let value = self.input(net, state, cpi, attempt, 0)?;
                Ok(negated(result, value))
            }
            other => Err(format!("<{other}> cannot give a condition")),
        }
    }

    /// The value flowing into a `connectionPointIn`: the OR of its connections.
    fn input(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        cpi: Node<'_, '_>,
        attempt: &mut Attempt,
        depth: usize,
    ) -> Result<String, String> {
        let mut parts: Vec<String> = Vec::new();
        for c in children(cpi, "connection") {
            let Some(id) = attr(c, "refLocalId").and_then(|v| v.trim().parse::<u64>().ok()) else {
                return Err("a connection without a valid refLocalId".to_owned());
            };
            let pin = attr(c, "formalParameter")
                .map(str::trim)
                .filter(|p| !p.is_empty());
            let value = self.value(net, state, id, pin, attempt, depth + 1)?;
            if value == "TRUE" {
                // Power from the rail: the parallel wires are TRUE as a whole.
                return Ok(value);
            }
            parts.push(value);
        }
        match parts.len() {
            0 => Err("an input of the network is not connected".to_owned()),
            1 => Ok(parts.pop().unwrap_or_default()),
            _ => bounded(paren(&parts.join(" OR "))),
        }
    }

    /// The value of element `id` (its output `pin`, for a function block instance).
    fn value(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        id: u64,
        pin: Option<&str>,
        attempt: &mut Attempt,
        depth: usize,
    ) -> Result<String, String> {
        if depth > MAX_DEPTH {
            return Err(format!("the network is deeper than {MAX_DEPTH} elements"));
        }
        let Some(&e) = net.elements.get(&id) else {
            return Err(format!(
                "a connection to localId {id}, which is not in the network"
            ));
        };
        if xml::local(e) == "block" && is_instance(e) {
            return self.instance(net, state, id, e, pin, attempt, depth);
        }
        if let Some(m) = state.memo.get(&id) {
            return m.clone();
        }
        if state.visits.get(&id) == Some(&Visit::InProgress) {
            let what = match xml::local(e) {
                "block" => format!("the {} block", attr(e, "typeName").unwrap_or("").trim()),
                other => format!("<{other}>"),
            };
            return Err(format!(
                "a cycle through {what} (localId {id}) without a function block instance"
            ));
        }
        state.visits.insert(id, Visit::InProgress);
        let v = self.compute(net, state, e, pin, attempt, depth);
        state.visits.remove(&id);
        let v = v.and_then(bounded);
        state.memo.insert(id, v.clone());
        v
    }

    fn compute(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        e: Node<'_, '_>,
        pin: Option<&str>,
        attempt: &mut Attempt,
        depth: usize,
    ) -> Result<String, String> {
        match xml::local(e) {
            "inVariable" => {
                let expr = child(e, "expression").map(xml::text).unwrap_or_default();
                let expr = expr.trim();
                st::condition(expr, self.names)
                    .map_err(|err| format!("the variable `{expr}`: {}", err.reason))?;
                Ok(negated(e, paren(expr)))
            }
            "leftPowerRail" => Ok("TRUE".to_owned()),
            "contact" => {
                let var = child(e, "variable").map(xml::text).unwrap_or_default();
                let var = var.trim();
                if let Some(edge) = attr(e, "edge").filter(|s| *s != "none") {
                    return Err(format!(
                        "the {edge} edge contact on `{var}` is not supported"
                    ));
                }
                st::condition(var, self.names)
                    .map_err(|err| format!("the contact `{var}`: {}", err.reason))?;
                let own = negated(e, paren(var));
                let Some(cpi) = child(e, "connectionPointIn") else {
                    return Err(format!("the contact `{var}` is not connected"));
                };
                let power = self.input(net, state, cpi, attempt, depth)?;
                Ok(if power == "TRUE" {
                    own
                } else {
                    paren(&format!("{power} AND {own}"))
                })
            }
            "connector" => match child(e, "connectionPointIn") {
                Some(cpi) => self.input(net, state, cpi, attempt, depth),
                None => Err("a connector that is not connected".to_owned()),
            },
            "continuation" => {
                let name = attr(e, "name").unwrap_or("").trim().to_ascii_uppercase();
                let connector = net.connectors.get(&name).copied();
                match connector.and_then(|c| child(c, "connectionPointIn")) {
                    Some(cpi) => self.input(net, state, cpi, attempt, depth),
                    None => Err(format!("the continuation {name} has no connector")),
                }
            }
            "block" => self.function(net, state, e, pin, attempt, depth),
            "coil" => Err(format!(
                "a coil (`{}`) inside the condition network is not supported",
                child(e, "variable")
                    .map(xml::text)
                    .unwrap_or_default()
                    .trim()
            )),
            other => Err(format!(
                "<{other}> in the condition network is not supported"
            )),
        }
    }

    /// A standard function block: its operator over its inputs in document order.
    fn function(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        e: Node<'_, '_>,
        pin: Option<&str>,
        attempt: &mut Attempt,
        depth: usize,
    ) -> Result<String, String> {
        let ty = attr(e, "typeName")
            .unwrap_or("")
            .trim()
            .to_ascii_uppercase();
        let outputs: Vec<Node<'_, '_>> = child(e, "outputVariables")
            .map(|o| children(o, "variable").collect())
            .unwrap_or_default();
        let out = match pin {
            Some(p) => outputs
                .iter()
                .find(|o| attr(**o, "formalParameter").is_some_and(|f| f.eq_ignore_ascii_case(p))),
            None => outputs.first(),
        };
        if pin.is_some_and(|p| p.eq_ignore_ascii_case("ENO")) {
            return Err(format!("the ENO output of the {ty} block is not supported"));
        }
        let mut args = Vec::new();
        for v in child(e, "inputVariables")
            .into_iter()
            .flat_map(|i| children(i, "variable"))
        {
            let formal = attr(v, "formalParameter").unwrap_or("").trim();
            let cpi = child(v, "connectionPointIn");
            let connected = cpi.is_some_and(|c| child(c, "connection").is_some());
            if formal.eq_ignore_ascii_case("EN") {
                if connected {
                    return Err(format!("the EN input of the {ty} block is not supported"));
                }
                continue;
            }
            if let Some(edge) = attr(v, "edge").filter(|s| *s != "none") {
                return Err(format!(
                    "the {edge} edge input {formal} of the {ty} block is not supported"
                ));
            }
            let Some(cpi) = cpi.filter(|_| connected) else {
                return Err(format!(
                    "the input {formal} of the {ty} block is not connected"
                ));
            };
            let value = self.input(net, state, cpi, attempt, depth)?;
            args.push(negated(v, value));
        }
        let n = args.len();
        let text = match (ty.as_str(), n) {
            ("AND" | "OR" | "XOR", 2..) => paren(&args.join(&format!(" {ty} "))),
            ("ADD", 2..) => paren(&args.join(" + ")),
            ("MUL", 2..) => paren(&args.join(" * ")),
            ("SUB", 2) => paren(&args.join(" - ")),
            ("DIV", 2) => paren(&args.join(" / ")),
            ("MOD", 2) => paren(&args.join(" MOD ")),
            ("NOT", 1) => paren(&format!("NOT {}", args[0])),
            ("MOVE", 1) => args[0].clone(),
            ("NE", 2) => paren(&args.join(" <> ")),
            ("GT" | "GE" | "EQ" | "LT" | "LE", 2..) => {
                let op = match ty.as_str() {
                    "GT" => ">",
                    "GE" => ">=",
                    "EQ" => "=",
                    "LT" => "<",
                    _ => "<=",
                };
                // IEC extends comparisons: GT(a, b, c) is a > b AND b > c.
                let pairs: Vec<String> = args
                    .windows(2)
                    .map(|w| paren(&format!("{} {op} {}", w[0], w[1])))
                    .collect();
                if pairs.len() == 1 {
                    pairs.join("")
                } else {
                    paren(&pairs.join(" AND "))
                }
            }
            (
                "AND" | "OR" | "XOR" | "ADD" | "MUL" | "SUB" | "DIV" | "MOD" | "NOT" | "MOVE"
                | "NE" | "GT" | "GE" | "EQ" | "LT" | "LE",
                _,
            ) => return Err(format!("the {ty} block with {n} inputs")),
            ("", _) => return Err("a block without a type".to_owned()),
            _ => {
                return Err(format!(
                    "the block {ty} is not supported (only AND OR XOR NOT, comparisons, ADD SUB MUL DIV MOD, MOVE and standard function block instances are)"
                ));
            }
        };
        Ok(match out {
            Some(o) => negated(*o, text),
            None => text,
        })
    }

    /// A function block instance: a call in `pre` (once), and the read of output `pin`.
    #[allow(clippy::too_many_arguments)]
    fn instance(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        id: u64,
        e: Node<'_, '_>,
        pin: Option<&str>,
        attempt: &mut Attempt,
        depth: usize,
    ) -> Result<String, String> {
        let ty = attr(e, "typeName")
            .unwrap_or("")
            .trim()
            .to_ascii_uppercase();
        let inst = attr(e, "instanceName").unwrap_or("").trim().to_owned();
        let Some((inputs, outputs)) = fb_interface(&ty) else {
            return Err(format!(
                "the function block {ty} (instance {inst}) is not a standard function block"
            ));
        };
        let upper = inst.to_ascii_uppercase();
        let key = self
            .names
            .renamed
            .get(&upper)
            .map_or(upper, |n| n.to_ascii_uppercase());
        match self.fb_types.get(&key) {
            Some(t) if *t == ty => {}
            Some(t) => {
                return Err(format!(
                    "the block {ty} names the instance {inst}, which is a {t}"
                ));
            }
            None => {
                return Err(format!(
                    "the {ty} block names `{inst}`, which is not a function block instance of the POU"
                ));
            }
        }
        let Some(pin) = pin
            .map(str::to_ascii_uppercase)
            .or_else(|| (outputs.len() == 1).then(|| outputs[0].to_owned()))
        else {
            return Err(format!("a connection to {inst} does not name its output"));
        };
        if !outputs.contains(&pin.as_str()) {
            return Err(format!("{pin} is not an output of {ty} ({inst})"));
        }
        let out_negated = child(e, "outputVariables")
            .into_iter()
            .flat_map(|o| children(o, "variable"))
            .find(|o| attr(*o, "formalParameter").is_some_and(|f| f.eq_ignore_ascii_case(&pin)))
            .is_some_and(|o| attr(o, "negated") == Some("true"));
        let read = if out_negated {
            format!("(NOT {inst}.{pin})")
        } else {
            format!("({inst}.{pin})")
        };
        if state.visits.contains_key(&id) {
            // Called already, or being called: its inputs read its output (feedback).
            return Ok(read);
        }
        state.visits.insert(id, Visit::InProgress);
        let args = self.instance_args(net, state, e, &ty, &inst, inputs, attempt, depth);
        match args {
            Ok(args) => {
                state.visits.insert(id, Visit::Called);
                attempt.called.push(id);
                attempt.calls.push(format!("{inst}({});", args.join(", ")));
                Ok(read)
            }
            Err(err) => {
                state.visits.remove(&id);
                Err(err)
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn instance_args(
        &mut self,
        net: &Net<'_, '_>,
        state: &mut NetState,
        e: Node<'_, '_>,
        ty: &str,
        inst: &str,
        inputs: &[&str],
        attempt: &mut Attempt,
        depth: usize,
    ) -> Result<Vec<String>, String> {
        let mut args = Vec::new();
        for v in child(e, "inputVariables")
            .into_iter()
            .flat_map(|i| children(i, "variable"))
        {
            let formal = attr(v, "formalParameter")
                .unwrap_or("")
                .trim()
                .to_ascii_uppercase();
            let Some(cpi) =
                child(v, "connectionPointIn").filter(|c| child(*c, "connection").is_some())
            else {
                continue;
            };
            if formal == "EN" {
                return Err(format!("the EN input of {inst} is not supported"));
            }
            if !inputs.contains(&formal.as_str()) {
                return Err(format!("{formal} is not an input of {ty} ({inst})"));
            }
            if let Some(edge) = attr(v, "edge").filter(|s| *s != "none") {
                return Err(format!(
                    "the {edge} edge input {formal} of {inst} is not supported"
                ));
            }
            let value = self.input(net, state, cpi, attempt, depth)?;
            args.push(format!("{formal} := {}", negated(v, value)));
        }
        Ok(args)
    }
}

/// A block of a function block type (it has an instance), as opposed to a function.
fn is_instance(e: Node<'_, '_>) -> bool {
    attr(e, "instanceName").is_some_and(|n| !n.trim().is_empty())
        || fb_interface(
            &attr(e, "typeName")
                .unwrap_or("")
                .trim()
                .to_ascii_uppercase(),
        )
        .is_some()
}

/// `(NOT value)` when the element says `negated="true"`; `value` is an operand already
/// (`TRUE` or parenthesized).
fn negated(e: Node<'_, '_>, value: String) -> String {
    if attr(e, "negated") == Some("true") {
        paren(&format!("NOT {value}"))
    } else {
        value
    }
}

/// Every value of the network is an operand: `TRUE` or a parenthesized expression.
fn paren(text: &str) -> String {
    format!("({text})")
}

fn bounded(text: String) -> Result<String, String> {
    if text.len() > MAX_TEXT {
        Err(format!(
            "the network's expression is longer than {MAX_TEXT} characters"
        ))
    } else {
        Ok(text)
    }
}
