//! The VCD file of a test run (`runtime.md` §7; IEEE 1364 §18 value change dump), for
//! waveform viewers such as GTKWave and Surfer. Built from a [`Trace`] and the program it ran.
//!
//! Layout:
//! * `$version higraph-lsp VERSION $end`, `$timescale 1 ms $end`, no `$date` (the file is
//!   byte-for-byte deterministic).
//! * `module {test}` holds, in run-list order, per group `module {group}` › per instance
//!   `module {instance}` with `wire 16 state`, one `wire 1 S{n}` per state (1 while the
//!   instance is in state n) and `wire 1 StateChange`; per chart `module {chart}` with
//!   `wire 8 state` (the number of the operating state) and per sequencer `module {sequencer}`
//!   with one `wire 1 {step}` per step (1 while active); then `module messages` with
//!   `wire 1 {Inst}.{Msg}` per internal message of the groups run (only when there is one);
//!   then `module watch` with one variable per watched path: BOOL `wire 1`; BYTE, CHAR 8;
//!   WORD, INT, S5TIME, DATE 16; other integers and TIME 32; REAL `real 1`; an operating
//!   state `wire 8`. STRING and DATE_AND_TIME paths are left out (VCD has no type for them).
//! * Identifier codes are given in declaration order: `!`, `"`, … `~`, then two characters
//!   (base 94, least significant first).
//! * `#0 $dumpvars … $end` holds the state before the first cycle (instances in state 0 with
//!   StateChange = 1, charts Ready, no step active); after cycle k the values that changed
//!   follow at `#t_k`. The last cycle's time is always written, so the dump spans the run.
//!   A value that could not be read is `x`.

use std::collections::HashMap;
use std::fmt::Write as _;

use crate::program::{OpState, Program, RunEntry};
use crate::trace::Trace;
use crate::value::{Ty, Value};

/// One declared variable.
struct Var {
    id: String,
    /// `None` for `real`.
    width: Option<u32>,
}

/// The VCD text of a run. `version` is the `higraph-lsp` version written in `$version`.
pub fn write(program: &Program, trace: &Trace, version: &str) -> String {
    let mut out = String::new();
    let mut vars: Vec<Var> = Vec::new();
    let mut declare = |out: &mut String, kind: &str, width: Option<u32>, name: &str| -> usize {
        let id = identifier(vars.len());
        let _ = writeln!(
            out,
            "$var {kind} {} {id} {} $end",
            width.unwrap_or(1),
            token(name)
        );
        vars.push(Var { id, width });
        vars.len() - 1
    };

    let _ = writeln!(out, "$version higraph-lsp {version} $end");
    out.push_str("$timescale 1 ms $end\n");
    let _ = writeln!(out, "$scope module {} $end", token(&trace.test));

    // Signals of instances: (group, instance) → (state var, first S var, state numbers,
    // StateChange var).
    struct InstanceVars {
        state: usize,
        states: Vec<(u16, usize)>,
        change: usize,
    }
    let mut instances: HashMap<(&str, &str), InstanceVars> = HashMap::new();
    let mut instance_order: Vec<(&str, &str)> = Vec::new();
    // Charts: name → (state var, step vars by "SEQ.STEP").
    struct ChartVars<'p> {
        state: usize,
        steps: Vec<(String, usize)>,
        _name: &'p str,
    }
    let mut charts: HashMap<&str, ChartVars<'_>> = HashMap::new();
    let mut chart_order: Vec<&str> = Vec::new();
    let run = program.test.as_ref().map_or(&[][..], |t| &t.run[..]);
    let mut message_vars = Vec::new();
    for entry in run {
        match *entry {
            RunEntry::Group(g) => {
                let Some(group) = program.groups.get(g as usize) else {
                    continue;
                };
                let _ = writeln!(out, "$scope module {} $end", token(&group.name));
                for instance in &group.instances {
                    let _ = writeln!(out, "$scope module {} $end", token(&instance.name));
                    let state = declare(&mut out, "wire", Some(16), "state");
                    let mut states = Vec::new();
                    if let Some(graph) = program.graphs.get(instance.graph as usize) {
                        for s in &graph.states {
                            let var = declare(&mut out, "wire", Some(1), &format!("S{}", s.number));
                            states.push((s.number, var));
                        }
                    }
                    let change = declare(&mut out, "wire", Some(1), "StateChange");
                    out.push_str("$upscope $end\n");
                    let key = (group.name.as_str(), instance.name.as_str());
                    instance_order.push(key);
                    instances.insert(
                        key,
                        InstanceVars {
                            state,
                            states,
                            change,
                        },
                    );
                }
                out.push_str("$upscope $end\n");
            }
            RunEntry::Chart(c) => {
                let Some(chart) = program.charts.get(c as usize) else {
                    continue;
                };
                let _ = writeln!(out, "$scope module {} $end", token(&chart.name));
                let state = declare(&mut out, "wire", Some(8), "state");
                let mut steps = Vec::new();
                for sequencer in &chart.sequencers {
                    let _ = writeln!(out, "$scope module {} $end", token(&sequencer.name));
                    for step in &sequencer.steps {
                        let var = declare(&mut out, "wire", Some(1), &step.name);
                        steps.push((format!("{}.{}", sequencer.name, step.name), var));
                    }
                    out.push_str("$upscope $end\n");
                }
                out.push_str("$upscope $end\n");
                chart_order.push(chart.name.as_str());
                charts.insert(
                    chart.name.as_str(),
                    ChartVars {
                        state,
                        steps,
                        _name: chart.name.as_str(),
                    },
                );
            }
        }
    }
    // Messages, in the order the runner records them (run list, then the group's order).
    let mut message_names = Vec::new();
    for entry in run {
        let RunEntry::Group(g) = *entry else { continue };
        let Some(group) = program.groups.get(g as usize) else {
            continue;
        };
        for message in &group.internal_messages {
            let instance = group.instances.get(message.instance as usize);
            let var_name = instance
                .and_then(|i| program.graphs.get(i.graph as usize))
                .and_then(|graph| graph.vars.get(message.var as usize))
                .map_or("?", |v| v.name.as_str());
            let instance_name = instance.map_or("?", |i| i.name.as_str());
            message_names.push(format!("{instance_name}.{var_name}"));
        }
    }
    if !message_names.is_empty() {
        out.push_str("$scope module messages $end\n");
        for name in &message_names {
            message_vars.push(declare(&mut out, "wire", Some(1), name));
        }
        out.push_str("$upscope $end\n");
    }
    // Watched paths: (index in the watch list, var).
    let mut watch_vars: Vec<(usize, usize)> = Vec::new();
    let watch = program.test.as_ref().map_or(&[][..], |t| &t.watch[..]);
    let shown: Vec<(usize, Option<u32>, &str)> = watch
        .iter()
        .enumerate()
        .filter_map(|(i, path)| watch_width(path.ty).map(|w| (i, w, path.text.as_str())))
        .collect();
    if !shown.is_empty() {
        out.push_str("$scope module watch $end\n");
        for (i, width, name) in shown {
            let kind = if width.is_none() { "real" } else { "wire" };
            watch_vars.push((i, declare(&mut out, kind, width, name)));
        }
        out.push_str("$upscope $end\n");
    }
    out.push_str("$upscope $end\n$enddefinitions $end\n");

    // Values: the current encoded value of each variable.
    let mut current: Vec<Option<String>> = vec![None; vars.len()];
    let mut now: Vec<String> = vars.iter().map(|var| encode(None, var.width)).collect();
    // The state before the first cycle.
    for key in &instance_order {
        let v = &instances[key];
        now[v.state] = bits(0, 16);
        for &(n, var) in &v.states {
            now[var] = bits(u64::from(n == 0), 1);
        }
        now[v.change] = bits(1, 1);
    }
    for name in &chart_order {
        let c = &charts[name];
        now[c.state] = bits(OpState::Ready as u64, 8);
        for (_, var) in &c.steps {
            now[*var] = bits(0, 1);
        }
    }
    for (i, var) in message_vars.iter().enumerate() {
        now[*var] = bits(
            u64::from(trace.initial_messages.get(i).copied().unwrap_or(false)),
            1,
        );
    }
    for &(i, var) in &watch_vars {
        now[var] = encode(
            trace.initial_watch_values.get(i).cloned().flatten(),
            vars[var].width,
        );
    }
    out.push_str("#0\n$dumpvars\n");
    for (var, value) in now.iter().enumerate() {
        push_change(&mut out, value, &vars[var].id);
        current[var] = Some(value.clone());
    }
    out.push_str("$end\n");

    let last = trace.cycles.len();
    for (index, cycle) in trace.cycles.iter().enumerate() {
        for record in &cycle.instances {
            let Some(v) = instances.get(&(record.group.as_str(), record.instance.as_str())) else {
                continue;
            };
            now[v.state] = bits(u64::from(record.state), 16);
            for &(n, var) in &v.states {
                now[var] = bits(u64::from(n == record.state), 1);
            }
            now[v.change] = bits(u64::from(record.state_change), 1);
        }
        for record in &cycle.charts {
            let Some(c) = charts.get(record.chart.as_str()) else {
                continue;
            };
            if let Some(state) = OpState::from_name(&record.state) {
                now[c.state] = bits(state as u64, 8);
            }
            for (name, var) in &c.steps {
                now[*var] = bits(u64::from(record.active.iter().any(|a| a == name)), 1);
            }
        }
        for (i, var) in message_vars.iter().enumerate() {
            if let Some(&value) = cycle.messages.get(i) {
                now[*var] = bits(u64::from(value), 1);
            }
        }
        for &(i, var) in &watch_vars {
            if let Some(value) = cycle.watch_values.get(i) {
                now[var] = encode(value.clone(), vars[var].width);
            }
        }
        let mut stamped = false;
        for var in 0..vars.len() {
            if current[var].as_ref() != Some(&now[var]) {
                if !stamped {
                    let _ = writeln!(out, "#{}", cycle.time_ms);
                    stamped = true;
                }
                push_change(&mut out, &now[var], &vars[var].id);
                current[var] = Some(now[var].clone());
            }
        }
        if !stamped && index + 1 == last && cycle.time_ms > 0 {
            let _ = writeln!(out, "#{}", cycle.time_ms);
        }
    }
    out
}

/// The VCD width of a watched path's type; `Some(None)` for `real`, `None` when it is left out.
fn watch_width(ty: Ty) -> Option<Option<u32>> {
    Some(match ty {
        Ty::Bool | Ty::Timer | Ty::Counter => Some(1),
        Ty::Byte | Ty::Char | Ty::OpState => Some(8),
        Ty::Word | Ty::Int | Ty::S5Time | Ty::Date => Some(16),
        Ty::Dword | Ty::Dint | Ty::Time | Ty::TimeOfDay => Some(32),
        Ty::Real => None,
        Ty::String(_) | Ty::DateAndTime => return None,
    })
}

/// A watched value in the encoding of its variable: `x` when unreadable.
fn encode(value: Option<Value>, width: Option<u32>) -> String {
    let Some(value) = value else {
        return match width {
            None => "rNaN".into(),
            Some(1) => "x".into(),
            Some(_) => "bx".into(),
        };
    };
    match width {
        None => match value {
            Value::Real(r) => format!("r{}", crate::test::real_text(r)),
            _ => "rNaN".into(),
        },
        Some(width) => {
            let pattern = match &value {
                Value::OpState(n) => Some(u32::from(*n)),
                other => other.to_bits(),
            };
            match pattern {
                Some(p) => bits(u64::from(p), width),
                None if width == 1 => "x".into(),
                None => "bx".into(),
            }
        }
    }
}

/// A value of `width` bits: `0`/`1` for one bit, else `b…` without leading zeros.
fn bits(value: u64, width: u32) -> String {
    let masked = if width >= 64 {
        value
    } else {
        value & ((1u64 << width) - 1)
    };
    if width == 1 {
        return if masked & 1 == 1 { "1" } else { "0" }.into();
    }
    format!("b{masked:b}")
}

/// One value change line: scalars as `0!`, vectors and reals as `b101 !` / `r1.5 !`.
fn push_change(out: &mut String, value: &str, id: &str) {
    if value.starts_with('b') || value.starts_with('r') {
        let _ = writeln!(out, "{value} {id}");
    } else {
        let _ = writeln!(out, "{value}{id}");
    }
}

/// The identifier code of the `n`th variable: base 94 over `!`..`~`, least significant first.
fn identifier(mut n: usize) -> String {
    let mut id = String::new();
    loop {
        id.push(char::from(b'!' + (n % 94) as u8));
        n /= 94;
        if n == 0 {
            return id;
        }
    }
}

/// A name as one VCD token: white space becomes `_`; an empty name `_`.
fn token(name: &str) -> String {
    if name.is_empty() {
        return "_".into();
    }
    name.chars()
        .map(|c| {
            if c.is_whitespace() || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_count_in_base_94() {
        assert_eq!(identifier(0), "!");
        assert_eq!(identifier(93), "~");
        assert_eq!(identifier(94), "!\"");
        assert_eq!(identifier(95), "\"\"");
    }

    #[test]
    fn vectors_drop_leading_zeros() {
        assert_eq!(bits(0, 16), "b0");
        assert_eq!(bits(5, 16), "b101");
        assert_eq!(bits(1, 1), "1");
        assert_eq!(bits(0xFFFF_FFFF, 16), "b1111111111111111");
        assert_eq!(encode(Some(Value::Int(-1)), Some(16)), "b1111111111111111");
        assert_eq!(encode(Some(Value::Real(1.5)), None), "r1.5");
        assert_eq!(encode(None, Some(8)), "bx");
        assert_eq!(encode(None, Some(1)), "x");
    }
}
