//! The JSON trace of `runtime.md` §7 (also the result of `higraph/simulate`) and the records
//! the engines fill in per cycle. Field order is the spec's; serialisation is deterministic.

use serde::Serialize;
use serde_json::Value as Json;

/// The whole trace of one test run.
#[derive(Debug, Clone, Serialize)]
pub struct Trace {
    pub version: u32,
    pub test: String,
    pub file: String,
    pub cycle_ms: u32,
    pub run: Vec<String>,
    /// "passed", "failed" or "error".
    pub result: String,
    /// As in `--format json` (objects built by the runner).
    pub failures: Vec<Json>,
    pub initial: Initial,
    pub cycles: Vec<CycleRecord>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Initial {
    /// Path text → VALUE (see [`json_value`]), in watch order.
    pub watch: serde_json::Map<String, Json>,
}

/// One machine cycle.
#[derive(Debug, Clone, Serialize, Default)]
pub struct CycleRecord {
    pub cycle: u64,
    pub time_ms: u64,
    pub init_sd: bool,
    /// The test statements that acted since the previous cycle.
    pub before: Vec<Before>,
    pub instances: Vec<InstanceRecord>,
    pub charts: Vec<ChartRecord>,
    pub watch: serde_json::Map<String, Json>,
}

#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Before {
    Set { set: String, value: Json },
    Command { command: String, chart: String },
    Confirm { confirm: String },
    Restart { restart: String },
}

/// One instance turn (§7 "instances").
#[derive(Debug, Clone, Serialize, Default)]
pub struct InstanceRecord {
    pub group: String,
    pub instance: String,
    pub state: u16,
    pub previous: u16,
    pub state_change: bool,
    pub fired: Option<Fired>,
    pub blocked_by: Option<Blocked>,
    /// Executed parts with at least one statement, in order: `permanent C-`, `state N C-`,
    /// `trans A->B !`, `state N C0`, `state N X`, `state N E`, `state N C`, `permanent C`.
    pub parts: Vec<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Fired {
    /// "initial", "startup", "any", "normal" or "return".
    pub kind: &'static str,
    pub from: Option<u16>,
    pub to: u16,
    pub prio: Option<u32>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Blocked {
    pub prio: u32,
}

/// One chart cycle (§7 "charts").
#[derive(Debug, Clone, Serialize, Default)]
pub struct ChartRecord {
    pub chart: String,
    pub state: String,
    pub commands: Vec<CommandRecord>,
    /// `"Starting->Active"`, …
    pub implicit: Vec<String>,
    pub running: Option<String>,
    pub suspended: Option<String>,
    /// `"SEQ.STEP"` of every active step after the cycle.
    pub active: Vec<String>,
    pub fired: Vec<ChartFired>,
    /// `"SEQ.STEP init"` / `run` / `term`, in execution order.
    pub phases: Vec<String>,
    /// Action operand → value written this cycle.
    pub actions: serde_json::Map<String, Json>,
}

#[derive(Debug, Clone, Serialize)]
pub struct CommandRecord {
    pub command: String,
    pub accepted: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct ChartFired {
    pub sequencer: String,
    /// "trans", "jump", "loop", "start" or "abort".
    pub kind: &'static str,
    pub name: Option<String>,
    pub from: Vec<String>,
    pub to: Vec<String>,
}

/// A value as the trace writes it (§7 VALUE): booleans, numbers (TIME in ms), non-finite
/// REAL as `"NaN"`/`"inf"`/`"-inf"`, strings for STRING, CHAR and operating states.
pub fn json_value(v: &crate::Value) -> Json {
    use crate::Value as V;
    match v {
        V::Bool(b) => Json::Bool(*b),
        V::Byte(x) => Json::from(*x),
        V::Word(x) | V::S5Time(x) | V::Date(x) => Json::from(*x),
        V::Dword(x) | V::TimeOfDay(x) => Json::from(*x),
        V::Int(x) => Json::from(*x),
        V::Dint(x) | V::Time(x) => Json::from(*x),
        V::Real(x) => {
            if x.is_nan() {
                Json::from("NaN")
            } else if x.is_infinite() {
                Json::from(if *x > 0.0 { "inf" } else { "-inf" })
            } else {
                serde_json::Number::from_f64(f64::from(*x)).map_or(Json::Null, Json::Number)
            }
        }
        V::DateAndTime(bytes) => {
            Json::from(bytes.iter().map(|b| format!("{b:02X}")).collect::<String>())
        }
        V::Char(c) => Json::from(char::from(*c).to_string()),
        V::String(s) => Json::from(s.clone()),
        V::OpState(n) => {
            Json::from(crate::program::OpState::from_number(*n).map_or("?", |s| s.name()))
        }
    }
}
