//! The registry of every diagnostic code of `diagnostics.md` §3: default severity, whether
//! the rule is off by default (§2.9), and a short description (the message template, used
//! by SARIF's `shortDescription` and by `explain`'s header).
//!
//! Besides the catalogue's codes it holds the few this project adds (HG0012, HG0013, and the
//! HG81xx that only `build` reports, in the sub-range 81xx "build" of HG8xxx "group options
//! and compile settings"); the conformance test lists them.
//!
//! The registry test checks this list against the rule documentation in `docs/rules/` and the
//! fixtures; the conformance test compares it with the catalogue itself.

use crate::{Code, Severity};

/// One rule of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rule {
    pub code: Code,
    pub default_severity: Severity,
    /// Not evaluated unless the workspace gives it a severity (§2.9).
    pub off_by_default: bool,
    /// The message template.
    pub template: &'static str,
}

const fn rule(
    code: &'static str,
    default_severity: Severity,
    off_by_default: bool,
    template: &'static str,
) -> Rule {
    Rule {
        code: Code::new(code),
        default_severity,
        off_by_default,
        template,
    }
}

/// Every rule, ordered by code.
pub const RULES: &[Rule] = &[
    rule(
        "HG0001",
        Severity::Error,
        false,
        "expected {expected}, found {found}",
    ),
    rule(
        "HG0002",
        Severity::Error,
        false,
        "missing ';' after {element}",
    ),
    rule(
        "HG0003",
        Severity::Error,
        false,
        "'<' of {construct} is never closed",
    ),
    rule(
        "HG0004",
        Severity::Error,
        false,
        "string is not closed before the end of the line",
    ),
    rule(
        "HG0005",
        Severity::Error,
        false,
        "character constant is not closed before the end of the line",
    ),
    rule(
        "HG0006",
        Severity::Error,
        false,
        "invalid {class} constant '{text}': {reason}",
    ),
    rule(
        "HG0007",
        Severity::Error,
        false,
        "{text} is out of range for {class} ({min} to {max})",
    ),
    rule(
        "HG0008",
        Severity::Error,
        false,
        "'>' without an open block",
    ),
    rule(
        "HG0009",
        Severity::Error,
        false,
        "unexpected character '{c}' (U+{hex})",
    ),
    rule(
        "HG0010",
        Severity::Error,
        false,
        "'mnemonic' must be the first item of the file",
    ),
    rule(
        "HG0011",
        Severity::Error,
        false,
        "second 'mnemonic' directive; the first one ({set}) applies",
    ),
    rule(
        "HG0012",
        Severity::Error,
        false,
        "nesting is deeper than {limit} levels",
    ),
    rule(
        "HG0013",
        Severity::Error,
        false,
        "{n} more syntax errors in this file are not listed",
    ),
    rule(
        "HG1101",
        Severity::Error,
        false,
        "name '{name}' must not end with '_'",
    ),
    rule(
        "HG1102",
        Severity::Error,
        false,
        "name '{name}' must not contain '__'",
    ),
    rule(
        "HG1103",
        Severity::Error,
        false,
        "'{name}' is reserved ({kind}) and cannot be used as a name",
    ),
    rule(
        "HG1104",
        Severity::Hint,
        false,
        "'{used}' is declared as '{declared}'",
    ),
    rule(
        "HG1201",
        Severity::Error,
        false,
        "variable '{name}' is already declared in {owner}",
    ),
    rule(
        "HG1202",
        Severity::Error,
        false,
        "'{name}' is predefined in every graph and must not be declared",
    ),
    rule(
        "HG1203",
        Severity::Error,
        false,
        "message variables belong in 'in_out'; '{name}' is in '{section}'",
    ),
    rule(
        "HG1204",
        Severity::Error,
        false,
        "message variable '{name}' must be BOOL, not {type}",
    ),
    rule(
        "HG1205",
        Severity::Error,
        false,
        "initial value {value} does not fit type {type}",
    ),
    rule(
        "HG1206",
        Severity::Error,
        false,
        "initial value {value} is out of range for {type} ({min} to {max})",
    ),
    rule(
        "HG1207",
        Severity::Error,
        false,
        "'{name}' is inactive in graph {graph}; add 'activate {name};'",
    ),
    rule(
        "HG1208",
        Severity::Error,
        false,
        "'{old}' is the HiGraph V2.7 name; use '{new}'",
    ),
    rule(
        "HG1209",
        Severity::Error,
        false,
        "'{name}' is read-only; the graph runtime sets it",
    ),
    rule(
        "HG1210",
        Severity::Hint,
        false,
        "variable '{name}' is never used in {owner}",
    ),
    rule(
        "HG1211",
        Severity::Error,
        false,
        "only predefined variables can be activated; '{name}' is not one",
    ),
    rule(
        "HG1212",
        Severity::Hint,
        false,
        "'{name}' is already active",
    ),
    rule(
        "HG1213",
        Severity::Error,
        false,
        "string length {n} is outside 1..254",
    ),
    rule(
        "HG1214",
        Severity::Warning,
        false,
        "'{name}' is for internal use of the generated code; do not rely on it",
    ),
    rule(
        "HG1215",
        Severity::Error,
        false,
        "unknown data type '{name}'",
    ),
    rule(
        "HG1301",
        Severity::Error,
        false,
        "'{name}' is already the name of {kind} in {file}",
    ),
    rule(
        "HG2001",
        Severity::Error,
        false,
        "graph {graph} has {n} states; at most 255 are allowed",
    ),
    rule(
        "HG2002",
        Severity::Error,
        false,
        "graph {graph} has {n} transitions; at most 4090 are allowed",
    ),
    rule(
        "HG2101",
        Severity::Error,
        false,
        "state number {n} is already used in graph {graph}",
    ),
    rule(
        "HG2102",
        Severity::Error,
        false,
        "state number {n} is outside 0..65535",
    ),
    rule(
        "HG2103",
        Severity::Error,
        false,
        "state {n} does not exist in graph {graph}",
    ),
    rule(
        "HG2104",
        Severity::Error,
        false,
        "'any' can only be the source of a transition",
    ),
    rule(
        "HG2105",
        Severity::Hint,
        false,
        "states of {graph} are not numbered 0 to {n-1} without gaps (missing: {list})",
    ),
    rule(
        "HG2106",
        Severity::Warning,
        false,
        "attribute '{attr}' is given twice",
    ),
    rule(
        "HG2201",
        Severity::Error,
        false,
        "graph {graph} has no startup transition (an any-transition that queries INIT_SD), so it has no initial state",
    ),
    rule(
        "HG2202",
        Severity::Error,
        false,
        "graph {graph} already has a startup transition ({t}); the initial state must be unique",
    ),
    rule(
        "HG2203",
        Severity::Warning,
        false,
        "the startup transition has '{attr}', so a restart may not initialise graph {graph}",
    ),
    rule(
        "HG2301",
        Severity::Error,
        false,
        "transition {t}: priority {p} is already used by {other}",
    ),
    rule(
        "HG2302",
        Severity::Error,
        false,
        "any-transition {t}: priority {p} is already used by {other}",
    ),
    rule(
        "HG2303",
        Severity::Error,
        false,
        "priority {p} is outside 1..65535 (1 is the highest)",
    ),
    rule(
        "HG2304",
        Severity::Warning,
        false,
        "transition {t} leads back to its own source state",
    ),
    rule(
        "HG2305",
        Severity::Warning,
        false,
        "any-transition {t} has no condition and fires in every cycle",
    ),
    rule(
        "HG2306",
        Severity::Warning,
        false,
        "transition {t} can never fire: {u} (priority {p}) has no condition and is checked first",
    ),
    rule(
        "HG2401",
        Severity::Warning,
        false,
        "state {n} cannot be reached from the initial state {i}",
    ),
    rule(
        "HG2402",
        Severity::Info,
        false,
        "state {n} has no way out; only a restart leaves it",
    ),
    rule(
        "HG3001",
        Severity::Warning,
        false,
        "transition {t} waits, but state {s} has no wait time",
    ),
    rule(
        "HG3002",
        Severity::Warning,
        false,
        "the wait time of state {n} has no effect: no transition leaving it is marked 'waits'",
    ),
    rule(
        "HG3003",
        Severity::Error,
        false,
        "state {n} already has a {wait time/supervision time}; only one is allowed",
    ),
    rule(
        "HG3004",
        Severity::Error,
        false,
        "a time value must be of type TIME; {value} is {type}",
    ),
    rule(
        "HG3005",
        Severity::Error,
        false,
        "time operand '{name}' is neither a variable of {owner} nor a global symbol",
    ),
    rule(
        "HG3006",
        Severity::Error,
        false,
        "time value {value} is negative",
    ),
    rule(
        "HG3007",
        Severity::Error,
        false,
        "'{keyword}' is only allowed in a state",
    ),
    rule(
        "HG3008",
        Severity::Warning,
        false,
        "time value {value} is zero, so the {wait time/supervision time/minimum run time/maximum run time/action time} has no useful effect",
    ),
    rule(
        "HG3101",
        Severity::Warning,
        false,
        "transition {t} is marked both 'auto' and 'manual'; ManualMode and AutomaticMode must never both be 1, so it can never fire",
    ),
    rule(
        "HG3102",
        Severity::Hint,
        false,
        "transition {t} has no operating mode, while other transitions of {graph} have one",
    ),
    rule(
        "HG3103",
        Severity::Warning,
        false,
        "instance {i}: ManualMode and AutomaticMode are wired to the same operand {x}",
    ),
    rule(
        "HG3104",
        Severity::Warning,
        false,
        "instance {i}: graph {g} has '{auto/manual}' transitions, but {AutomaticMode/ManualMode} is not wired, so they never fire",
    ),
    rule(
        "HG4001",
        Severity::Error,
        false,
        "statement outside an instruction block: state {n} needs a label such as 'C:' before it",
    ),
    rule(
        "HG4002",
        Severity::Error,
        false,
        "label '{label}' is not allowed in {a transition/a state/permanent instructions}; allowed: {list}",
    ),
    rule(
        "HG4003",
        Severity::Error,
        false,
        "jumps and jump labels are not available in HiGraph; use states and transitions",
    ),
    rule(
        "HG4004",
        Severity::Error,
        false,
        "indirect addressing is not allowed in HiGraph",
    ),
    rule(
        "HG4005",
        Severity::Error,
        false,
        "bracket nesting depth {d} exceeds the 7-entry nesting stack; the original compiler does not check this",
    ),
    rule(
        "HG4006",
        Severity::Error,
        false,
        "')' has no matching opening bracket",
    ),
    rule(
        "HG4007",
        Severity::Error,
        false,
        "'{token}' is {an international/a SIMATIC} mnemonic; this file uses {SIMATIC/international} mnemonics",
    ),
    rule("HG4008", Severity::Error, false, "unknown operation '{op}'"),
    rule(
        "HG4009",
        Severity::Error,
        false,
        "bit number {b} is outside 0..7",
    ),
    rule(
        "HG4010",
        Severity::Error,
        false,
        "'{address}' is not a valid address: {reason}",
    ),
    rule(
        "HG4011",
        Severity::Error,
        false,
        "'{address}' needs a data block number ('DBn.{address}'); no DB can be opened in HiGraph",
    ),
    rule(
        "HG4012",
        Severity::Warning,
        false,
        "'{address}' is temporary local data of the generated FC; its value is not kept",
    ),
    rule(
        "HG4101",
        Severity::Error,
        false,
        "'{name}' is neither a variable of {owner} nor a global symbol",
    ),
    rule(
        "HG4102",
        Severity::Error,
        false,
        "'{name}' reads as the address area {area} ({meaning}); write '#{name}' for the variable",
    ),
    rule(
        "HG4103",
        Severity::Warning,
        false,
        "'{name}' is read as the address {address}, not as the {variable/symbol} {name}",
    ),
    rule(
        "HG4201",
        Severity::Error,
        false,
        "'{op}' needs {accepted}; {operand} is {type}",
    ),
    rule(
        "HG4202",
        Severity::Error,
        false,
        "'L' cannot load {operand} ({type})",
    ),
    rule(
        "HG4203",
        Severity::Error,
        false,
        "'T' needs a writable BYTE, WORD, DWORD, INT, DINT, REAL, S5TIME, TIME, DATE, TOD or CHAR operand; {operand} is {type/a constant}",
    ),
    rule(
        "HG4204",
        Severity::Error,
        false,
        "'{op}' needs a timer; {operand} is {type}",
    ),
    rule(
        "HG4205",
        Severity::Error,
        false,
        "'{op}' needs a counter; {operand} is {type}",
    ),
    rule("HG4206", Severity::Error, false, "'{op}' needs an operand"),
    rule(
        "HG4207",
        Severity::Error,
        false,
        "'{op}' needs {requirement}; found {operand}",
    ),
    rule("HG4301", Severity::Error, false, "unknown block '{name}'"),
    rule(
        "HG4302",
        Severity::Error,
        false,
        "{block} needs an instance DB: 'CALL {block}, DB n'",
    ),
    rule(
        "HG4303",
        Severity::Error,
        false,
        "type conflict: parameter {p} of {block} is {F}, the actual {x} is {A}",
    ),
    rule(
        "HG4304",
        Severity::Error,
        false,
        "{block} has no parameter '{p}'",
    ),
    rule(
        "HG4305",
        Severity::Error,
        false,
        "call of {block} lacks parameter(s) {list}",
    ),
    rule(
        "HG4306",
        Severity::Error,
        false,
        "parameter '{p}' is given twice",
    ),
    rule(
        "HG4307",
        Severity::Hint,
        true,
        "interface of {block} is unknown; its parameters are not checked",
    ),
    rule(
        "HG4308",
        Severity::Error,
        false,
        "'CC' calls only an FC or SFC without parameters",
    ),
    rule(
        "HG4309",
        Severity::Error,
        false,
        "'{x}' is {kind}; only FC, FB, SFC and SFB interfaces can be declared",
    ),
    rule(
        "HG4310",
        Severity::Error,
        false,
        "interface of {block} is already declared in {file}",
    ),
    rule(
        "HG4401",
        Severity::Warning,
        false,
        "'{op}' writes the input parameter '{name}'",
    ),
    rule(
        "HG4402",
        Severity::Warning,
        false,
        "'{op}' in the condition of {t} changes {operand} while the condition is evaluated; put actions in a '!:' block",
    ),
    rule(
        "HG4403",
        Severity::Hint,
        true,
        "graph {graph} uses the global operand {x} directly; a formal parameter keeps the graph reusable",
    ),
    rule(
        "HG5001",
        Severity::Error,
        false,
        "graph '{name}' does not exist",
    ),
    rule(
        "HG5002",
        Severity::Error,
        false,
        "group {g} has {n} instances; at most 255 are allowed",
    ),
    rule(
        "HG5003",
        Severity::Error,
        false,
        "instance name '{name}' is already used in group {g}",
    ),
    rule(
        "HG5101",
        Severity::Error,
        false,
        "graph {graph} has no formal parameter '{name}'",
    ),
    rule(
        "HG5102",
        Severity::Error,
        false,
        "'{name}' already has an actual in instance {i}",
    ),
    rule(
        "HG5103",
        Severity::Warning,
        false,
        "instance {i}: no actual for {list}",
    ),
    rule(
        "HG5104",
        Severity::Error,
        false,
        "type conflict: {formal} of {graph} is {F}, the actual {x} is {A}",
    ),
    rule(
        "HG5105",
        Severity::Error,
        false,
        "'{formal}' is an {out/in_out} parameter; a constant cannot receive values",
    ),
    rule(
        "HG5201",
        Severity::Error,
        false,
        "no instance '{inst}' in group {g}",
    ),
    rule(
        "HG5202",
        Severity::Error,
        false,
        "{inst}.{msg} is not an incoming message (it is {what})",
    ),
    rule(
        "HG5203",
        Severity::Error,
        false,
        "the receiver is named at the sender; leave incoming message '{formal}' unwired",
    ),
    rule(
        "HG5204",
        Severity::Error,
        false,
        "message '{formal}' needs a bit address or a BOOL symbol; {x} is {type/a constant}",
    ),
    rule(
        "HG5205",
        Severity::Warning,
        false,
        "instance {i}: outgoing message '{msg}' is not wired",
    ),
    rule(
        "HG5206",
        Severity::Warning,
        false,
        "instance {i}: incoming message '{msg}' has no sender in group {g} and no external address",
    ),
    rule(
        "HG5207",
        Severity::Warning,
        false,
        "instance {i}: incoming message '{msg}' is wired to {address}, but {sender} sends to it internally; that message never arrives",
    ),
    rule(
        "HG6001",
        Severity::Error,
        false,
        "unknown data type '{name}'",
    ),
    rule(
        "HG6002",
        Severity::Error,
        false,
        "{address} is already named by symbol {first}",
    ),
    rule(
        "HG6003",
        Severity::Error,
        false,
        "symbol '{name}' is already defined in {file}",
    ),
    rule(
        "HG6004",
        Severity::Hint,
        false,
        "symbol '{name}' is never used",
    ),
    rule(
        "HG6005",
        Severity::Error,
        false,
        "cannot import symbol table {file}: {reason}",
    ),
    rule(
        "HG6006",
        Severity::Warning,
        false,
        "symbol name '{name}' has {n} characters; STEP 7 allows at most 24",
    ),
    rule(
        "HG6007",
        Severity::Warning,
        false,
        "imported symbol '{name}' has data type {t}, which is not supported; it is treated as untyped",
    ),
    rule("HG6101", Severity::Error, false, "higraph.toml: {problem}"),
    rule(
        "HG6102",
        Severity::Error,
        false,
        "file is not valid UTF-8 (invalid byte at offset {n})",
    ),
    rule(
        "HG6103",
        Severity::Error,
        false,
        "cannot read file: {reason}",
    ),
    rule(
        "HG6104",
        Severity::Warning,
        false,
        "unknown diagnostic code '{c}' in higraph-allow",
    ),
    rule(
        "HG7001",
        Severity::Error,
        false,
        "expected a {transition/step} after {previous}, found {found}",
    ),
    rule(
        "HG7002",
        Severity::Error,
        false,
        "{parallel/alt} needs at least 2 branches; it has {n}",
    ),
    rule(
        "HG7003",
        Severity::Error,
        false,
        "a parallel branch must begin and end with a step; this one {is empty/begins with {x}/ends with {x}}",
    ),
    rule(
        "HG7004",
        Severity::Error,
        false,
        "an alternative branch must begin and end with a transition; this one {is empty/begins with {x}/ends with {x}}",
    ),
    rule(
        "HG7005",
        Severity::Error,
        false,
        "first transition {t} of an alternative branch has no condition, so it would always win",
    ),
    rule(
        "HG7006",
        Severity::Error,
        false,
        "{jump/loop} {j}: sequencer {s} has no step '{target}'",
    ),
    rule(
        "HG7007",
        Severity::Error,
        false,
        "loop {l} would cross a branch boundary: step {target} is not on the same branch level",
    ),
    rule(
        "HG7008",
        Severity::Error,
        false,
        "loop {l} must lead back to an earlier step; {target} comes after {source}",
    ),
    rule(
        "HG7009",
        Severity::Error,
        false,
        "{jump/loop} {j} must directly follow a step",
    ),
    rule(
        "HG7010",
        Severity::Error,
        false,
        "{jump/loop} {j} follows the end step {s}, which has no successor",
    ),
    rule(
        "HG7011",
        Severity::Warning,
        false,
        "jump {j} {leaves/enters} a parallel branch; the other branches are not synchronised",
    ),
    rule(
        "HG7012",
        Severity::Warning,
        false,
        "step {s} can never become active",
    ),
    rule(
        "HG7101",
        Severity::Error,
        false,
        "name '{name}' has {n} characters; at most 16 are allowed",
    ),
    rule(
        "HG7102",
        Severity::Error,
        false,
        "name '{name}' must not consist only of digits",
    ),
    rule(
        "HG7103",
        Severity::Error,
        false,
        "{step/transition} name '{name}' is already used in sequencer {s}",
    ),
    rule(
        "HG7104",
        Severity::Error,
        false,
        "comment has {n} characters; at most 80 are allowed",
    ),
    rule(
        "HG7105",
        Severity::Error,
        false,
        "sequencer name '{name}' is already used in chart {c}",
    ),
    rule(
        "HG7201",
        Severity::Error,
        false,
        "sequencer {s} has {n} steps; at most 255 are allowed",
    ),
    rule(
        "HG7202",
        Severity::Error,
        false,
        "sequencer {s} has {n} step(s); a start step and an end step are required",
    ),
    rule(
        "HG7203",
        Severity::Error,
        false,
        "sequencer {s} has {n} transitions; at most 255 are allowed",
    ),
    rule(
        "HG7204",
        Severity::Error,
        false,
        "the {part} part of {step/sequencer} {name} has {n} statements; at most 50 are allowed",
    ),
    rule(
        "HG7205",
        Severity::Error,
        false,
        "{element} has {n} conditions; at most 16 are allowed",
    ),
    rule(
        "HG7206",
        Severity::Error,
        false,
        "chart {c} has {n} sequencers; at most {8/32} are allowed",
    ),
    rule(
        "HG7207",
        Severity::Error,
        false,
        "sequencer priority {p} is outside 1..32",
    ),
    rule(
        "HG7208",
        Severity::Error,
        false,
        "chart {c} has no sequencer",
    ),
    rule(
        "HG7209",
        Severity::Error,
        false,
        "{step/sequencer} {name} already has a '{part}' part",
    ),
    rule(
        "HG7301",
        Severity::Warning,
        false,
        "sequencer {s} has an empty start condition; an empty start condition is false, so the sequencer never runs",
    ),
    rule(
        "HG7302",
        Severity::Error,
        false,
        "qualifier {q} needs a time: '{q} {operand}, T#...;'",
    ),
    rule(
        "HG7303",
        Severity::Error,
        false,
        "qualifier {q} takes no time",
    ),
    rule(
        "HG7304",
        Severity::Error,
        false,
        "condition must be BOOL; {expr} is {type}",
    ),
    rule(
        "HG7305",
        Severity::Error,
        false,
        "cannot compare {A} with {B}",
    ),
    rule(
        "HG7306",
        Severity::Error,
        false,
        "cannot assign {B} to {target} ({A})",
    ),
    rule(
        "HG7307",
        Severity::Error,
        false,
        "action qualifier {q} needs a BOOL operand; {operand} is {type}",
    ),
    rule(
        "HG7308",
        Severity::Warning,
        false,
        "'{name}' is an input of chart {c}; the chart should not write it",
    ),
    rule(
        "HG7309",
        Severity::Error,
        false,
        "chart type {c} may only use its own interface; {x} is {a global symbol/an absolute address/an external reference}",
    ),
    rule(
        "HG7310",
        Severity::Info,
        false,
        "'{path}' is an external reference; it is not checked",
    ),
    rule(
        "HG7311",
        Severity::Warning,
        false,
        "step {s} writes {x} in 'term', and successor {t} writes it in '{part}' in the same cycle; the 'term' value never takes effect",
    ),
    rule(
        "HG7401",
        Severity::Warning,
        false,
        "'confirm' only has an effect with 'switching step;'; chart {c} uses {mode}",
    ),
    rule(
        "HG7402",
        Severity::Error,
        false,
        "unknown run option '{o}'; known: cyclic, time_monitoring, autostart",
    ),
    rule(
        "HG7403",
        Severity::Warning,
        false,
        "chart property '{p}' is given twice; the first one applies",
    ),
    rule(
        "HG7404",
        Severity::Info,
        false,
        "step {s} has a maximum run time, but 'run time_monitoring;' is not set, so it is never checked",
    ),
    rule(
        "HG7405",
        Severity::Warning,
        false,
        "step {s}: minimum run time {min} is longer than maximum run time {max}",
    ),
    rule(
        "HG7406",
        Severity::Warning,
        false,
        "switching mode {m} is not available in operating mode auto (only T and step)",
    ),
    rule(
        "HG7501",
        Severity::Error,
        false,
        "unknown profile '{p}'; known: pcs7, iec",
    ),
    rule(
        "HG7502",
        Severity::Error,
        false,
        "{construct} needs 'profile iec;'",
    ),
    rule(
        "HG7503",
        Severity::Error,
        false,
        "an IEC chart has one sequencer without 'start' and 'prio'; {problem}",
    ),
    rule(
        "HG7504",
        Severity::Error,
        false,
        "function block instance {name} must be declared in 'stat', not in '{section}'",
    ),
    rule(
        "HG7505",
        Severity::Error,
        false,
        "{problem} (function block {fb})",
    ),
    rule(
        "HG7506",
        Severity::Error,
        false,
        "'{op}' is not defined for {A} and {B}",
    ),
    rule(
        "HG7507",
        Severity::Error,
        false,
        "{op} by the constant zero",
    ),
    rule(
        "HG7508",
        Severity::Error,
        false,
        "CASE label {label} is already covered by an earlier arm",
    ),
    rule(
        "HG7509",
        Severity::Error,
        false,
        "CASE selector must be INT or DINT; {expr} is {type}",
    ),
    rule(
        "HG7510",
        Severity::Error,
        false,
        "action name '{name}' is already used in chart {c}",
    ),
    rule(
        "HG7511",
        Severity::Hint,
        false,
        "action '{name}' is never used: no qualifier of a step names it, so it never runs",
    ),
    rule(
        "HG8001",
        Severity::Warning,
        false,
        "'option reserve' has no effect without 'option restructure'",
    ),
    rule(
        "HG8002",
        Severity::Warning,
        false,
        "group {g} does not name its FC",
    ),
    rule(
        "HG8003",
        Severity::Warning,
        false,
        "group {g} does not name its DB",
    ),
    rule(
        "HG8004",
        Severity::Error,
        false,
        "{FC/DB} {n} is already generated by group {h}",
    ),
    rule(
        "HG8005",
        Severity::Error,
        false,
        "'{x}' is not {an FC/a DB}: {reason}",
    ),
    rule(
        "HG8006",
        Severity::Info,
        true,
        "'option restructure' rebuilds the DB; changes can then be loaded only with the CPU in STOP",
    ),
    rule("HG8007", Severity::Error, false, "unknown option '{o}'"),
    rule(
        "HG8008",
        Severity::Error,
        false,
        "option reserve needs a number of words from 1 to 32767",
    ),
    rule(
        "HG8009",
        Severity::Warning,
        false,
        "option {o} is given twice",
    ),
    rule(
        "HG8010",
        Severity::Error,
        false,
        "{FC/DB} {n} is generated by group {g} and cannot be {called/used as an instance DB}",
    ),
    rule(
        "HG8011",
        Severity::Warning,
        false,
        "{address} lies in DB {n}, which group {g} generates; its layout is not under your control",
    ),
    rule(
        "HG8101",
        Severity::Error,
        false,
        "group {g} has no {'fc'/'db'} clause(s); build generates the FC and DB they name",
    ),
    rule(
        "HG8102",
        Severity::Error,
        false,
        "'{c}' (U+{hex}) is not in Windows-1252, the encoding of STEP 7 sources{; n more}",
    ),
    rule(
        "HG8103",
        Severity::Error,
        false,
        "'{x}' is {type}, an S7 type that IEC 61131-3 lacks; PLCopen XML cannot express it",
    ),
    rule(
        "HG8104",
        Severity::Info,
        false,
        "{feature} has no PLCopen equivalent; the export keeps it only in the documentation of {c}",
    ),
    rule(
        "HG8105",
        Severity::Error,
        false,
        "FC {n} is declared as an external block by 'block {x}'; building group {g} would overwrite it",
    ),
    rule(
        "HG8106",
        Severity::Error,
        false,
        "'{x}' is a keyword of IEC 61131-3; PLCopen tools cannot read it as a name",
    ),
    rule(
        "HG9001",
        Severity::Error,
        false,
        "'{kw}' must come first in test {t} / test {t} already has '{kw}'",
    ),
    rule(
        "HG9002",
        Severity::Error,
        false,
        "test '{name}' is already defined in {file}",
    ),
    rule(
        "HG9003",
        Severity::Error,
        false,
        "cycle time {value} must be whole milliseconds from T#1MS to T#10S",
    ),
    rule(
        "HG9004",
        Severity::Error,
        false,
        "step count {n} is outside 1..1000000 / time {value} is negative",
    ),
    rule(
        "HG9005",
        Severity::Warning,
        false,
        "test {t} checks nothing",
    ),
    rule(
        "HG9006",
        Severity::Error,
        false,
        "'{x}' is {kind}; a test runs groups and charts",
    ),
    rule(
        "HG9007",
        Severity::Warning,
        false,
        "'{x}' is already in the run list",
    ),
    rule(
        "HG9008",
        Severity::Error,
        false,
        "test {t} has nothing to run",
    ),
    rule(
        "HG9009",
        Severity::Info,
        false,
        "{d} is not a multiple of the cycle time; {n} cycles are run",
    ),
    rule("HG9010", Severity::Warning, false, "{d} runs no cycle"),
    rule(
        "HG9101",
        Severity::Error,
        false,
        "'{path}' is no symbol, address, instance, chart or block / {owner} has no variable or step '{x}'",
    ),
    rule(
        "HG9102",
        Severity::Error,
        false,
        "'{x}' is ambiguous; write {candidates}",
    ),
    rule(
        "HG9103",
        Severity::Error,
        false,
        "{g} is not run by test {t}",
    ),
    rule(
        "HG9104",
        Severity::Error,
        false,
        "'{path}' cannot be set: {reason}",
    ),
    rule(
        "HG9105",
        Severity::Error,
        false,
        "cannot set {target} ({A}) to {value} ({B})",
    ),
    rule(
        "HG9106",
        Severity::Error,
        false,
        "condition must be BOOL; {expr} is {type}",
    ),
    rule(
        "HG9107",
        Severity::Error,
        false,
        "cannot compare {A} with {B} / '{op}' is not defined for {type}",
    ),
    rule(
        "HG9108",
        Severity::Error,
        false,
        "'{x}' is not an operating state",
    ),
    rule(
        "HG9109",
        Severity::Error,
        false,
        "'{x}' is not a chart / unknown command '{x}'",
    ),
    rule("HG9110", Severity::Error, false, "'{path}' is not a step"),
    rule(
        "HG9111",
        Severity::Error,
        false,
        "{block} has no output parameter '{p}'",
    ),
    rule(
        "HG9901",
        Severity::Error,
        false,
        "expect failed{: msg}: at cycle {k} (t = {t}): {values}",
    ),
    rule(
        "HG9902",
        Severity::Error,
        false,
        "'{expr}' did not hold within {d}{: msg}: at cycle {k}: {values}",
    ),
    rule(
        "HG9903",
        Severity::Error,
        false,
        "runtime fault at cycle {k}: {reason}",
    ),
    rule(
        "HG9904",
        Severity::Error,
        false,
        "test {t} cannot run: {n} error(s) in {list}",
    ),
];

/// The rule of a code.
pub fn rule_of(code: &str) -> Option<&'static Rule> {
    // `RULES` is sorted by code (a test checks it).
    RULES
        .binary_search_by(|r| r.code.as_str().cmp(code))
        .ok()
        .map(|i| &RULES[i])
}

/// Is `code` a syntax code (HG0xxx), which cannot be reconfigured or suppressed?
pub fn is_syntax_code(code: &str) -> bool {
    code.starts_with("HG0")
}

include!(concat!(env!("OUT_DIR"), "/rule_docs.rs"));

/// The documentation of every rule, `(code, markdown)`, sorted by code: `docs/rules/*.md`,
/// embedded at build time (see `build.rs`).
pub fn rule_docs() -> &'static [(&'static str, &'static str)] {
    RULE_DOCS
}

/// The documentation of one code (`HG2105`, upper case).
pub fn rule_doc(code: &str) -> Option<&'static str> {
    RULE_DOCS
        .binary_search_by(|(c, _)| (*c).cmp(code))
        .ok()
        .map(|i| RULE_DOCS[i].1)
}
