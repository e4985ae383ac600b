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
    /// As in `--format json` (filled in by the caller, who knows files and positions).
    pub failures: Vec<FailureRecord>,
    pub initial: Initial,
    pub cycles: Vec<CycleRecord>,
    /// The internal messages before the first cycle (for the VCD; not in the JSON).
    #[serde(skip)]
    pub initial_messages: Vec<bool>,
    /// The watched values before the first cycle (for the VCD; not in the JSON).
    #[serde(skip)]
    pub initial_watch_values: Vec<Option<crate::Value>>,
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct Initial {
    /// Path text → VALUE (see [`json_value`]), in watch order.
    pub watch: OrderedMap,
}

/// A JSON object whose members keep their order (serde_json's own map sorts its keys).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OrderedMap(pub Vec<(String, Json)>);

impl OrderedMap {
    pub fn insert(&mut self, key: String, value: Json) {
        self.0.push((key, value));
    }
}

impl Serialize for OrderedMap {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (key, value) in &self.0 {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

/// A position of `diagnostics.md` §4.1: 0-based line, UTF-16 column.
#[derive(Debug, Clone, Copy, Serialize, Default, PartialEq, Eq)]
pub struct JsonPosition {
    pub line: u32,
    pub character: u32,
}

/// A range of `diagnostics.md` §4.1.
#[derive(Debug, Clone, Copy, Serialize, Default, PartialEq, Eq)]
pub struct JsonRange {
    pub start: JsonPosition,
    pub end: JsonPosition,
}

/// One failure as `--format json` and the trace write it (§7).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FailureRecord {
    pub code: String,
    pub message: String,
    pub file: String,
    pub range: JsonRange,
    pub cycle: u64,
    pub time_ms: u64,
    /// Path → VALUE, in the expression's order.
    pub values: OrderedMap,
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
    pub watch: OrderedMap,
    /// The watched values after the cycle, in watch order (`None`: unreadable); for the VCD.
    #[serde(skip)]
    pub watch_values: Vec<Option<crate::Value>>,
    /// Every internal message of the groups run, in run-list and group order, after the
    /// cycle; for the VCD.
    #[serde(skip)]
    pub messages: Vec<bool>,
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
                // The shortest text that reads back as the same binary32 (`0.1`, not
                // `0.10000000149011612`): parsed as a double, it prints the same digits.
                let shortest = crate::test::real_text(*x).parse::<f64>().unwrap_or(0.0);
                serde_json::Number::from_f64(shortest).map_or(Json::Null, Json::Number)
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
