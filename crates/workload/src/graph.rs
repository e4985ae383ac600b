//! State graphs: the variable model, the STL statement vocabulary and the text of one graph.
//!
//! Everything written here is meant to be clean, not only syntactically valid: operands resolve
//! to declared variables (or to global symbols and addresses the caller provides), operand
//! types fit their operations (`diagnostics.md` Appendix B), conditions never write (HG4402),
//! every declared variable is used (HG1210), priorities are distinct per range (HG2301), every
//! state is reachable from the initial state (HG2401) and has a way out (HG2402), and the
//! operating-mode, wait and supervision attributes are consistent (HG3001, HG3002, HG3102).

use std::collections::HashSet;
use std::fmt::Write;

use crate::mnemonic::Mnemonic;
use crate::rng::Rng;

/// What a variable is for; decides its section, its type and the statements that use it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Role {
    /// `in`, BOOL: read by bit logic.
    Sensor,
    /// `in`, INT: loaded.
    Setpoint,
    /// `in`, TIME: a state's `wait`.
    WaitTime,
    /// `in`, TIME: a state's `supervise`.
    SuperviseTime,
    /// `in`, TIMER: started, queried, reset.
    Timer,
    /// `in`, COUNTER: counted, queried, reset.
    Counter,
    /// `out`, BOOL: assigned, set, reset, read.
    Actuator,
    /// `out`, INT: transferred.
    ActualValue,
    /// `in_out`, BOOL `msg in`.
    MsgIn,
    /// `in_out`, BOOL `msg out`.
    MsgOut,
    /// `in_out`, INT without `msg`.
    Parameter,
    /// `stat`, BOOL.
    Flag,
    /// `stat`, BOOL edge memory for `FP`/`FN`.
    Edge,
    /// `stat`, INT.
    Count,
    /// `stat`, WORD for word logic and shifts.
    StatusWord,
    /// `stat`, WORD receiving `CurrentState`.
    StateCopy,
    /// `stat`, REAL.
    Measure,
    /// `stat`, DINT.
    Sum,
    /// `stat`, `STRING[32]`, passed to a block call.
    Text,
}

impl Role {
    pub(crate) fn section(self) -> &'static str {
        match self {
            Role::Sensor
            | Role::Setpoint
            | Role::WaitTime
            | Role::SuperviseTime
            | Role::Timer
            | Role::Counter => "in",
            Role::Actuator | Role::ActualValue => "out",
            Role::MsgIn | Role::MsgOut | Role::Parameter => "in_out",
            Role::Flag
            | Role::Edge
            | Role::Count
            | Role::StatusWord
            | Role::StateCopy
            | Role::Measure
            | Role::Sum
            | Role::Text => "stat",
        }
    }

    pub(crate) fn type_name(self) -> &'static str {
        match self {
            Role::Sensor
            | Role::Actuator
            | Role::MsgIn
            | Role::MsgOut
            | Role::Flag
            | Role::Edge => "BOOL",
            Role::Setpoint | Role::ActualValue | Role::Parameter | Role::Count => "INT",
            Role::WaitTime | Role::SuperviseTime => "TIME",
            Role::Timer => "TIMER",
            Role::Counter => "COUNTER",
            Role::StatusWord | Role::StateCopy => "WORD",
            Role::Measure => "REAL",
            Role::Sum => "DINT",
            Role::Text => "STRING[32]",
        }
    }

    /// A formal parameter is wired by group instances (HG5103).
    pub(crate) fn is_formal(self) -> bool {
        self.section() != "stat"
    }

    fn is_bool_read(self) -> bool {
        matches!(
            self,
            Role::Sensor | Role::Actuator | Role::MsgIn | Role::Flag
        )
    }

    fn is_bool_write(self) -> bool {
        matches!(self, Role::Actuator | Role::MsgOut | Role::Flag)
    }

    fn is_int_read(self) -> bool {
        matches!(
            self,
            Role::Setpoint | Role::ActualValue | Role::Parameter | Role::Count
        )
    }

    fn is_int_write(self) -> bool {
        matches!(self, Role::ActualValue | Role::Parameter | Role::Count)
    }
}

/// A declared variable of a graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Var {
    pub(crate) name: String,
    pub(crate) role: Role,
    pub(crate) init: Option<String>,
    pub(crate) comment: Option<String>,
}

/// How many variables of each role a graph declares (messages are named by the caller).
#[derive(Debug, Clone, Default)]
pub(crate) struct VarCounts {
    pub(crate) sensors: usize,
    pub(crate) setpoints: usize,
    pub(crate) wait_time: bool,
    pub(crate) supervise_time: bool,
    pub(crate) timers: usize,
    pub(crate) counters: usize,
    pub(crate) actuators: usize,
    pub(crate) actual_values: usize,
    pub(crate) parameters: usize,
    pub(crate) flags: usize,
    pub(crate) edges: usize,
    pub(crate) counts: usize,
    pub(crate) status_word: bool,
    pub(crate) measures: usize,
    pub(crate) sums: usize,
    pub(crate) text: bool,
}

const SENSORS: &[&str] = &[
    "Endlage_Oben",
    "Endlage_Unten",
    "Endlage_Vorne",
    "Endlage_Hinten",
    "Teil_Vorhanden",
    "Druck_Ok",
    "Temperatur_Ok",
    "Niveau_Min",
    "Niveau_Max",
    "Tuer_Geschlossen",
    "Freigabe",
    "Starttaster",
    "Stopptaster",
    "Quittiertaster",
    "Lichtschranke",
    "Motorschutz_Ok",
    "Sicherheit_Ok",
    "Position_Ok",
    "Werkzeug_Da",
    "Kuehlmittel_Ok",
    "Luftdruck_Ok",
    "Band_Laeuft",
    "Greifer_Offen",
    "Greifer_Geschlossen",
    "Sperre_Aus",
];
const ACTUATORS: &[&str] = &[
    "Motor_Ein",
    "Ventil_Auf",
    "Ventil_Zu",
    "Heben",
    "Senken",
    "Greifen",
    "Loesen",
    "Lampe_Gruen",
    "Lampe_Rot",
    "Hupe",
    "Pumpe_Ein",
    "Luefter_Ein",
    "Heizen",
    "Kuehlen",
    "Vorschub",
    "Rueckzug",
    "Bremse_Los",
    "Spannen",
    "Kupplung",
    "Signal_Bereit",
    "Ausstossen",
    "Drehen_Links",
    "Drehen_Rechts",
    "Blasluft",
    "Schmierung",
];
const FLAGS: &[&str] = &[
    "Schritt_Ok",
    "Teil_Gemeldet",
    "Fehler_Gespeichert",
    "Zyklus_Ende",
    "Ablauf_Aktiv",
    "Warnung",
    "Anforderung",
    "Halt_Gespeichert",
];
const EDGES: &[&str] = &["Flanke_Start", "Flanke_Teil", "Flanke_Quitt", "Flanke_Takt"];
const COUNTS: &[&str] = &[
    "Stueckzahl",
    "Zyklen",
    "Fehlerzahl",
    "Wiederholungen",
    "Schrittnummer",
];
const SETPOINTS: &[&str] = &["Sollwert", "Grenzwert", "Vorgabe", "Sollmenge"];
const ACTUAL_VALUES: &[&str] = &["Istwert", "Restmenge", "Anzeige"];
const PARAMETERS: &[&str] = &["Rezeptnummer", "Chargennummer", "Betriebsdaten"];
const TIMERS: &[&str] = &[
    "Zeit_Ueberwachung",
    "Zeit_Puls",
    "Zeit_Verzoegerung",
    "Zeit_Nachlauf",
];
const COUNTERS: &[&str] = &["Teilezaehler", "Fehlerzaehler", "Hubzaehler"];
const MEASURES: &[&str] = &["Temperatur", "Druck", "Drehzahl", "Fuellstand"];
const SUMS: &[&str] = &["Gesamtmenge", "Betriebsstunden", "Laufzeit_Summe"];

const STATE_NAMES: &[&str] = &[
    "Grundstellung",
    "Bereit",
    "Anfahren",
    "Heben",
    "Senken",
    "Greifen",
    "Transport",
    "Ablegen",
    "Warten",
    "Pruefen",
    "Fuellen",
    "Entleeren",
    "Heizen",
    "Kuehlen",
    "Spuelen",
    "Reinigen",
    "Nachlauf",
    "Handbetrieb",
    "Quittieren",
    "Positionieren",
];
const TRANSITION_NAMES: &[&str] = &[
    "Teil erkannt",
    "Zeit abgelaufen",
    "Endlage erreicht",
    "Freigabe",
    "Quittiert",
    "Druck aufgebaut",
    "leer",
    "voll",
    "Weiter",
];

/// Builds the variables of `counts`, plus the given messages (`(name, incoming)`), with unique
/// names drawn from German word lists.
pub(crate) fn build_vars(counts: &VarCounts, messages: &[(&str, bool)], rng: &mut Rng) -> Vec<Var> {
    let mut vars = Vec::new();
    let mut taken = HashSet::new();
    let add = |vars: &mut Vec<Var>,
               taken: &mut HashSet<String>,
               words: &[&str],
               n: usize,
               role: Role,
               rng: &mut Rng| {
        for k in 0..n {
            let base = words[k % words.len()];
            let mut name = if k < words.len() {
                base.to_string()
            } else {
                format!("{base}_{}", k / words.len() + 1)
            };
            while !taken.insert(name.to_ascii_lowercase()) {
                name.push('X');
            }
            let init = match role {
                Role::Flag if rng.percent(30) => Some("FALSE".to_string()),
                Role::Count if rng.percent(50) => Some("0".to_string()),
                Role::Setpoint if rng.percent(40) => Some(format!("{}", rng.range(1, 500))),
                Role::Parameter if rng.percent(30) => Some("-1".to_string()),
                Role::Measure => Some("0.0".to_string()),
                Role::Sum => Some("L#0".to_string()),
                Role::StatusWord => Some("W#16#0000".to_string()),
                Role::WaitTime => Some("T#2S".to_string()),
                Role::SuperviseTime => Some("T#30S".to_string()),
                Role::Text => Some("'Bereit'".to_string()),
                _ => None,
            };
            let comment = match role {
                Role::Sensor if rng.percent(25) => Some(format!("Eingang {}", k + 1)),
                Role::Actuator if rng.percent(25) => Some(format!("Ausgang {}", k + 1)),
                Role::Timer => Some("S5-Zeit".to_string()),
                _ => None,
            };
            vars.push(Var {
                name,
                role,
                init,
                comment,
            });
        }
    };
    add(
        &mut vars,
        &mut taken,
        SENSORS,
        counts.sensors,
        Role::Sensor,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        SETPOINTS,
        counts.setpoints,
        Role::Setpoint,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        &["Wartezeit"],
        usize::from(counts.wait_time),
        Role::WaitTime,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        &["Ueberwachungszeit"],
        usize::from(counts.supervise_time),
        Role::SuperviseTime,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        TIMERS,
        counts.timers,
        Role::Timer,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        COUNTERS,
        counts.counters,
        Role::Counter,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        ACTUATORS,
        counts.actuators,
        Role::Actuator,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        ACTUAL_VALUES,
        counts.actual_values,
        Role::ActualValue,
        rng,
    );
    for &(name, incoming) in messages {
        taken.insert(name.to_ascii_lowercase());
        let role = if incoming { Role::MsgIn } else { Role::MsgOut };
        vars.push(Var {
            name: name.to_string(),
            role,
            init: None,
            comment: None,
        });
    }
    add(
        &mut vars,
        &mut taken,
        PARAMETERS,
        counts.parameters,
        Role::Parameter,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        FLAGS,
        counts.flags.max(1),
        Role::Flag,
        rng,
    );
    add(&mut vars, &mut taken, EDGES, counts.edges, Role::Edge, rng);
    add(
        &mut vars,
        &mut taken,
        COUNTS,
        counts.counts.max(1),
        Role::Count,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        &["Statuswort"],
        usize::from(counts.status_word),
        Role::StatusWord,
        rng,
    );
    add(
        &mut vars,
        &mut taken,
        MEASURES,
        counts.measures,
        Role::Measure,
        rng,
    );
    add(&mut vars, &mut taken, SUMS, counts.sums, Role::Sum, rng);
    add(
        &mut vars,
        &mut taken,
        &["Meldetext"],
        usize::from(counts.text),
        Role::Text,
        rng,
    );
    vars
}

/// What a block parameter needs from the calling graph.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Need {
    BoolRead,
    BoolWrite,
    IntRead,
    RealRead,
    RealWrite,
    Text,
}

/// A block a graph may `CALL`: the target as written (`FC 10`, `Dosieren`, `FB 20, DB 120`)
/// and its parameters.
#[derive(Debug, Clone)]
pub(crate) struct CallTemplate {
    pub(crate) target: String,
    pub(crate) params: Vec<(&'static str, Need)>,
}

/// Everything that shapes one generated graph.
#[derive(Debug, Clone)]
pub(crate) struct GraphSpec {
    pub(crate) name: String,
    pub(crate) title: Option<String>,
    pub(crate) mnemonic: Mnemonic,
    /// States `0..states`.
    pub(crate) states: usize,
    /// Normal and return transitions (the any-transitions come on top).
    pub(crate) normal_transitions: usize,
    /// A second any-transition, into the last state, marked `fault`.
    pub(crate) fault_any: bool,
    /// STL statements per transition (the startup transition has one).
    pub(crate) statements: (usize, usize),
    /// Every transition but the startup one gets `auto` or `manual`.
    pub(crate) modes: bool,
    /// Percentage of transitions with an explicit `prio`.
    pub(crate) explicit_prio: usize,
    pub(crate) vars: Vec<Var>,
    /// `activate CurrentState, StateChange;` (needs a `StateCopy` variable, added if absent).
    pub(crate) activate: bool,
    pub(crate) calls: Vec<CallTemplate>,
    /// BOOL global symbols (as written: `Name` or `"Name"`) that conditions may read.
    pub(crate) globals: Vec<String>,
    /// Whether STL may use absolute addresses (`E 1.0`, `MW 20`, `DB10.DBX 2.3`).
    pub(crate) absolute: bool,
    /// Percentage of operands written `#Name`.
    pub(crate) hash_percent: usize,
}

/// A generated graph: its text and the variables it declares.
#[derive(Debug, Clone)]
pub(crate) struct Graph {
    pub(crate) name: String,
    pub(crate) text: String,
    pub(crate) vars: Vec<Var>,
}

impl Graph {
    /// The formal parameters (in, out, in_out), in declaration order.
    pub(crate) fn formals(&self) -> impl Iterator<Item = &Var> {
        self.vars.iter().filter(|v| v.role.is_formal())
    }
}

/// One element of an instruction body: a statement, a block label, or a state item
/// (`wait`/`supervise`).
#[derive(Debug, Clone)]
enum Part {
    Stmt(String),
    Label(&'static str),
    Item(String),
}

struct Transition {
    source: String,
    target: String,
    prio: Option<usize>,
    attrs: Vec<&'static str>,
    name: Option<&'static str>,
    body: Vec<Part>,
    comment: Option<String>,
}

/// Round-robin plus random picks from one pool of variable indices, so that every variable is
/// used once there are enough picks, and the rest looks random.
#[derive(Default)]
struct Pool {
    items: Vec<usize>,
    cursor: usize,
}

impl Pool {
    fn pick(&mut self, rng: &mut Rng) -> Option<usize> {
        if self.items.is_empty() {
            return None;
        }
        if rng.percent(50) {
            let v = self.items[self.cursor % self.items.len()];
            self.cursor += 1;
            Some(v)
        } else {
            Some(rng.choose(&self.items))
        }
    }

    fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}

struct Pools {
    bool_read: Pool,
    bool_write: Pool,
    msg_in: Pool,
    int_read: Pool,
    int_write: Pool,
    timers: Pool,
    counters: Pool,
    edges: Pool,
    status: Pool,
    measures: Pool,
    sums: Pool,
    state_copy: Pool,
    text: Pool,
    wait_time: Option<usize>,
    supervise_time: Option<usize>,
}

struct Gen<'a> {
    spec: &'a GraphSpec,
    vars: Vec<Var>,
    rng: Rng,
    used: Vec<bool>,
    pools: Pools,
    m: Mnemonic,
}

/// Generates the text of one graph.
pub(crate) fn generate(spec: &GraphSpec, rng: &mut Rng) -> Graph {
    let mut vars = spec.vars.clone();
    if spec.activate && !vars.iter().any(|v| v.role == Role::StateCopy) {
        vars.push(Var {
            name: "Zustand_Kopie".into(),
            role: Role::StateCopy,
            init: None,
            comment: None,
        });
    }
    let pool = |f: &dyn Fn(Role) -> bool| Pool {
        items: vars
            .iter()
            .enumerate()
            .filter(|(_, v)| f(v.role))
            .map(|(i, _)| i)
            .collect(),
        cursor: 0,
    };
    let pools = Pools {
        bool_read: pool(&|r| r.is_bool_read()),
        bool_write: pool(&|r| r.is_bool_write()),
        msg_in: pool(&|r| r == Role::MsgIn),
        int_read: pool(&|r| r.is_int_read()),
        int_write: pool(&|r| r.is_int_write()),
        timers: pool(&|r| r == Role::Timer),
        counters: pool(&|r| r == Role::Counter),
        edges: pool(&|r| r == Role::Edge),
        status: pool(&|r| r == Role::StatusWord),
        measures: pool(&|r| r == Role::Measure),
        sums: pool(&|r| r == Role::Sum),
        state_copy: pool(&|r| r == Role::StateCopy),
        text: pool(&|r| r == Role::Text),
        wait_time: vars.iter().position(|v| v.role == Role::WaitTime),
        supervise_time: vars.iter().position(|v| v.role == Role::SuperviseTime),
    };
    assert!(
        !pools.bool_write.is_empty() && !pools.int_write.is_empty(),
        "a graph needs a flag and a count"
    );
    let used = vec![false; vars.len()];
    let mut generator = Gen {
        spec,
        vars,
        rng: rng.fork(0x6A),
        used,
        pools,
        m: spec.mnemonic,
    };
    let text = generator.run();
    Graph {
        name: spec.name.clone(),
        text,
        vars: generator.vars,
    }
}

impl Gen<'_> {
    fn op(&self, simatic: &'static str) -> &'static str {
        self.m.op(simatic)
    }

    /// The operand text of variable `i`, marking it used.
    fn operand(&mut self, i: usize) -> String {
        self.used[i] = true;
        if self.rng.percent(self.spec.hash_percent) {
            format!("#{}", self.vars[i].name)
        } else {
            self.vars[i].name.clone()
        }
    }

    fn pick(&mut self, which: fn(&mut Pools) -> &mut Pool) -> Option<String> {
        let i = which(&mut self.pools).pick(&mut self.rng)?;
        Some(self.operand(i))
    }

    fn bool_read(&mut self) -> String {
        if !self.spec.globals.is_empty() && self.rng.percent(4) {
            return self.rng.pick(&self.spec.globals).clone();
        }
        if self.spec.absolute && self.rng.percent(4) {
            return self.bit_address(false);
        }
        match self.pick(|p| &mut p.bool_read) {
            Some(op) => op,
            // Only messages and flags are always present; flags are readable.
            None => self.pick(|p| &mut p.bool_write).expect("flags exist"),
        }
    }

    fn bool_write(&mut self) -> String {
        if self.spec.absolute && self.rng.percent(3) {
            return self.bit_address(true);
        }
        self.pick(|p| &mut p.bool_write).expect("flags exist")
    }

    fn int_read(&mut self) -> String {
        if self.spec.absolute && self.rng.percent(5) {
            let area = self.m.area(self.rng.choose(&["MW", "EW"]));
            return self.byte_address(area);
        }
        self.pick(|p| &mut p.int_read).expect("counts exist")
    }

    fn int_write(&mut self) -> String {
        if self.spec.absolute && self.rng.percent(5) {
            return self.byte_address("MW");
        }
        self.pick(|p| &mut p.int_write).expect("counts exist")
    }

    /// `E 1.0`, `M10.3`, `DB10.DBX 2.3`: a bit address to read, or (`write`) to assign.
    fn bit_address(&mut self, write: bool) -> String {
        let byte = self.rng.below(128);
        let bit = self.rng.below(8);
        if !write && self.rng.percent(20) {
            return format!("DB{}.DBX {byte}.{bit}", self.rng.range(100, 119));
        }
        let area = if write {
            self.m.area(self.rng.choose(&["A", "M"]))
        } else {
            self.m.area(self.rng.choose(&["E", "M", "A"]))
        };
        if self.rng.percent(30) {
            format!("{area}{byte}.{bit}")
        } else {
            format!("{area} {byte}.{bit}")
        }
    }

    /// `MW 20`, `EW4`, `DB12.DBW 6`: a word address (even byte numbers, so words never overlap).
    fn byte_address(&mut self, area: &str) -> String {
        let byte = 2 * self.rng.below(100);
        if area == "MW" && self.rng.percent(15) {
            return format!("DB{}.DBW {byte}", self.rng.range(100, 119));
        }
        if self.rng.percent(30) {
            format!("{area}{byte}")
        } else {
            format!("{area} {byte}")
        }
    }

    fn int_constant(&mut self) -> String {
        match self.rng.below(6) {
            0 => format!("-{}", self.rng.range(1, 100)),
            1 => format!("{}", self.rng.below(10)),
            _ => format!("{}", self.rng.range(10, 30000)),
        }
    }

    fn s5time(&mut self) -> &'static str {
        self.rng.choose(&[
            "S5T#500MS",
            "S5T#2S",
            "S5T#5S",
            "S5T#1M30S",
            "S5T#0H_1M_0S",
            "S5TIME#10S",
        ])
    }

    fn time(&mut self) -> &'static str {
        self.rng.choose(&[
            "T#2S",
            "T#500MS",
            "T#10S",
            "T#1M30S",
            "T#13S750MS",
            "T#1.5S",
            "TIME#20S",
        ])
    }

    // ------------------------------------------------------------------ conditions

    /// A piece of a transition condition with at most `max` statements. Conditions only read
    /// (HG4402).
    fn condition(&mut self, max: usize) -> Vec<String> {
        loop {
            let choice = self.rng.below(100);
            let out = match choice {
                0..=44 => {
                    let op = self
                        .rng
                        .choose(&["U", "U", "U", "UN", "O", "ON", "X", "XN"]);
                    vec![format!("{} {}", self.op(op), self.bool_read())]
                }
                45..=51 if !self.pools.msg_in.is_empty() => {
                    vec![format!(
                        "{} {}",
                        self.op("U"),
                        self.pick(|p| &mut p.msg_in).unwrap()
                    )]
                }
                52..=56 if !self.pools.timers.is_empty() => {
                    let op = self.rng.choose(&["U", "UN"]);
                    vec![format!(
                        "{} {}",
                        self.op(op),
                        self.pick(|p| &mut p.timers).unwrap()
                    )]
                }
                57..=59 if !self.pools.counters.is_empty() => {
                    vec![format!(
                        "{} {}",
                        self.op("U"),
                        self.pick(|p| &mut p.counters).unwrap()
                    )]
                }
                60..=74 if max >= 3 => {
                    let a = self.int_read();
                    let b = if self.rng.percent(60) {
                        self.int_constant()
                    } else {
                        self.int_read()
                    };
                    let cmp = self.rng.choose(&["==I", "<>I", ">I", "<I", ">=I", "<=I"]);
                    vec![format!("L {a}"), format!("L {b}"), cmp.to_string()]
                }
                75..=79 if max >= 3 && !self.pools.measures.is_empty() => {
                    let a = self.pick(|p| &mut p.measures).unwrap();
                    let b = self.rng.choose(&["1.5", "2.5e+1", "100.0", "0.5"]);
                    let cmp = self.rng.choose(&[">R", "<R", ">=R", "<=R"]);
                    vec![format!("L {a}"), format!("L {b}"), cmp.to_string()]
                }
                80..=82 if max >= 3 && !self.pools.sums.is_empty() => {
                    let a = self.pick(|p| &mut p.sums).unwrap();
                    let b = format!("L#{}", self.rng.range(1000, 2_000_000));
                    let cmp = self.rng.choose(&[">D", "<D", "==D"]);
                    vec![format!("L {a}"), format!("L {b}"), cmp.to_string()]
                }
                83..=92 if max >= 4 => {
                    let open = self.rng.choose(&["U(", "UN(", "O(", "X("]);
                    let mut v = vec![self.op(open).to_string()];
                    let inner = self.rng.range(2, (max - 2).min(3));
                    for k in 0..inner {
                        let op = if k == 0 {
                            "U"
                        } else {
                            self.rng.choose(&["O", "U", "ON"])
                        };
                        v.push(format!("{} {}", self.op(op), self.bool_read()));
                    }
                    v.push(")".to_string());
                    v
                }
                93..=95 if max >= 6 => {
                    // Two nesting levels: U( U a; O( U b; U c; ) )
                    let mut v = vec![self.op("U(").to_string()];
                    v.push(format!("{} {}", self.op("U"), self.bool_read()));
                    v.push(self.op("O(").to_string());
                    v.push(format!("{} {}", self.op("UN"), self.bool_read()));
                    v.push(")".to_string());
                    v.push(")".to_string());
                    v
                }
                96..=99 if max >= 2 && !self.pools.edges.is_empty() => {
                    let x = self.bool_read();
                    let e = self.pick(|p| &mut p.edges).unwrap();
                    let op = self.rng.choose(&["FP", "FN"]);
                    vec![format!("{} {x}", self.op("U")), format!("{op} {e}")]
                }
                _ => continue,
            };
            return out;
        }
    }

    // ------------------------------------------------------------------ actions

    /// A piece of an action block with at most `max` statements.
    fn action(&mut self, max: usize) -> Vec<String> {
        loop {
            let choice = self.rng.below(100);
            let out = match choice {
                0..=29 => {
                    let op = self.rng.choose(&["S", "R", "=", "S", "R"]);
                    if op == "R" && !self.pools.msg_in.is_empty() && self.rng.percent(20) {
                        vec![format!("R {}", self.pick(|p| &mut p.msg_in).unwrap())]
                    } else {
                        vec![format!("{op} {}", self.bool_write())]
                    }
                }
                30..=44 if max >= 2 => {
                    let op = self.rng.choose(&["U", "UN", "O"]);
                    let x = self.bool_read();
                    let w = self.bool_write();
                    vec![format!("{} {x}", self.op(op)), format!("= {w}")]
                }
                45..=52 if max >= 4 => {
                    let c = self.int_write();
                    let op = self.rng.choose(&["+I", "-I", "*I", "+I"]);
                    let k = self.rng.range(1, 9);
                    vec![
                        format!("L {c}"),
                        format!("L {k}"),
                        op.to_string(),
                        format!("T {c}"),
                    ]
                }
                53..=56 if max >= 2 => {
                    let a = self.int_read();
                    let b = self.int_write();
                    vec![format!("L {a}"), format!("T {b}")]
                }
                57..=62 if max >= 2 && !self.pools.timers.is_empty() => {
                    let t = self.pick(|p| &mut p.timers).unwrap();
                    let start = self.rng.choose(&["SE", "SI", "SV", "SS", "SA", "SE"]);
                    let v = self.s5time();
                    if max >= 3 && self.rng.percent(50) {
                        let x = self.bool_read();
                        vec![
                            format!("{} {x}", self.op("U")),
                            format!("L {v}"),
                            format!("{} {t}", self.op(start)),
                        ]
                    } else {
                        vec![format!("L {v}"), format!("{} {t}", self.op(start))]
                    }
                }
                63..=64 if !self.pools.timers.is_empty() => {
                    let op = self.rng.choose(&["R", "FR"]);
                    vec![format!("{op} {}", self.pick(|p| &mut p.timers).unwrap())]
                }
                65..=68 if max >= 2 && !self.pools.counters.is_empty() => {
                    let x = self.bool_read();
                    let z = self.pick(|p| &mut p.counters).unwrap();
                    let op = self.rng.choose(&["ZV", "ZV", "ZR", "R"]);
                    vec![
                        format!("{} {x}", self.op("U")),
                        format!("{} {z}", self.op(op)),
                    ]
                }
                69..=71 if max >= 3 && !self.pools.status.is_empty() => {
                    let s = self.pick(|p| &mut p.status).unwrap();
                    let (op, k) = self.rng.choose(&[
                        ("UW", "W#16#00FF"),
                        ("OW", "W#16#0F00"),
                        ("XOW", "2#0101_0000"),
                        ("SLW", "2"),
                        ("SRW", "4"),
                        ("OW", "C#100"),
                    ]);
                    vec![
                        format!("L {s}"),
                        format!("{} {k}", self.op(op)),
                        format!("T {s}"),
                    ]
                }
                72..=74 if max >= 4 && !self.pools.measures.is_empty() => {
                    let m = self.pick(|p| &mut p.measures).unwrap();
                    let op = self.rng.choose(&["+R", "-R", "*R", "/R"]);
                    let k = self.rng.choose(&["1.5", "2.0", "1.234567e+1", "0.25"]);
                    vec![
                        format!("L {m}"),
                        format!("L {k}"),
                        op.to_string(),
                        format!("T {m}"),
                    ]
                }
                75..=76 if max >= 4 && !self.pools.measures.is_empty() => {
                    let a = self.int_read();
                    let m = self.pick(|p| &mut p.measures).unwrap();
                    vec![
                        format!("L {a}"),
                        "ITD".into(),
                        "DTR".into(),
                        format!("T {m}"),
                    ]
                }
                77..=79 if max >= 4 && !self.pools.sums.is_empty() => {
                    let s = self.pick(|p| &mut p.sums).unwrap();
                    let op = self.rng.choose(&["+D", "-D", "+D"]);
                    vec![
                        format!("L {s}"),
                        "L L#1".into(),
                        op.to_string(),
                        format!("T {s}"),
                    ]
                }
                80..=82 if max >= 2 => {
                    let op = self.rng.choose(&["SET", "CLR", "NOT"]);
                    let w = self.bool_write();
                    if op == "NOT" {
                        let x = self.bool_read();
                        if max >= 3 {
                            vec![format!("{} {x}", self.op("U")), op.into(), format!("= {w}")]
                        } else {
                            continue;
                        }
                    } else {
                        vec![op.to_string(), format!("= {w}")]
                    }
                }
                83..=86 if max >= 3 && !self.pools.edges.is_empty() => {
                    let x = self.bool_read();
                    let e = self.pick(|p| &mut p.edges).unwrap();
                    let w = self.bool_write();
                    vec![
                        format!("{} {x}", self.op("U")),
                        format!("FP {e}"),
                        format!("S {w}"),
                    ]
                }
                87..=90 if !self.spec.calls.is_empty() => match self.call(None) {
                    Some(call) => vec![call],
                    None => continue,
                },
                91..=93 if max >= 2 && !self.pools.state_copy.is_empty() => {
                    let c = self.pick(|p| &mut p.state_copy).unwrap();
                    vec!["L CurrentState".into(), format!("T {c}")]
                }
                94..=96 if max >= 2 => {
                    let k = self.int_constant();
                    let c = self.int_write();
                    vec![format!("L {k}"), format!("T {c}")]
                }
                97..=99 if max >= 2 => {
                    let x = self.bool_read();
                    let w = self.bool_write();
                    vec![format!("{} {x}", self.op("UN")), format!("= {w}")]
                }
                _ => continue,
            };
            return out;
        }
    }

    /// A `CALL` of one of the spec's blocks (the first that needs `need`, if given), or `None`
    /// when the graph lacks a variable some parameter needs.
    fn call(&mut self, need: Option<Need>) -> Option<String> {
        let template = match need {
            Some(need) => self
                .spec
                .calls
                .iter()
                .find(|c| c.params.iter().any(|p| p.1 == need))?
                .clone(),
            None => self.rng.pick(&self.spec.calls).clone(),
        };
        let mut actuals = Vec::new();
        for &(param, need) in &template.params {
            let actual = match need {
                Need::BoolRead => self.bool_read(),
                Need::BoolWrite => self.bool_write(),
                Need::IntRead => self.int_read(),
                Need::RealRead | Need::RealWrite => self.pick(|p| &mut p.measures)?,
                Need::Text => self.pick(|p| &mut p.text)?,
            };
            actuals.push(format!("{param} := {actual}"));
        }
        Some(if actuals.len() > 3 {
            format!(
                "CALL {} (\n        {})",
                template.target,
                actuals.join(",\n        ")
            )
        } else {
            format!("CALL {} ({})", template.target, actuals.join(", "))
        })
    }

    /// Action pieces adding up to exactly `n` statements.
    fn actions_exact(&mut self, n: usize) -> Vec<String> {
        let mut out = Vec::new();
        while out.len() < n {
            out.extend(self.action(n - out.len()));
        }
        out
    }

    fn conditions_exact(&mut self, n: usize) -> Vec<String> {
        let mut out = Vec::new();
        while out.len() < n {
            out.extend(self.condition(n - out.len()));
        }
        out
    }

    // ------------------------------------------------------------------ the graph

    fn run(&mut self) -> String {
        let spec = self.spec;
        let n = spec.states;
        assert!(
            n >= 2 && spec.normal_transitions >= n,
            "{}: every state needs a way out",
            spec.name
        );

        // Which states have wait / supervise (first the ones that use the TIME variables).
        let mut wait: Vec<Option<String>> = vec![None; n];
        let mut supervise: Vec<Option<String>> = vec![None; n];
        if let Some(i) = self.pools.wait_time {
            wait[1] = Some(self.operand(i));
        }
        if let Some(i) = self.pools.supervise_time {
            supervise[2 % n] = Some(self.operand(i));
        }
        for s in 0..n {
            if wait[s].is_none() && self.rng.percent(6) {
                wait[s] = Some(self.time().to_string());
            }
            if supervise[s].is_none() && self.rng.percent(15) {
                supervise[s] = Some(
                    self.rng
                        .pick(&["T#10S", "T#30S", "T#1M", "T#2M30S", "T#5S"])
                        .to_string(),
                );
            }
        }

        // States.
        let mut states = Vec::with_capacity(n);
        for s in 0..n {
            states.push(self.state(s, wait[s].take(), supervise[s].take()));
        }

        // Transitions: the startup transition, maybe a fault any-transition, then the normal
        // ones, grouped by source state.
        let mut transitions = vec![Transition {
            source: "any".into(),
            target: "0".into(),
            prio: Some(1),
            attrs: vec![],
            name: Some("startup"),
            body: vec![Part::Stmt(format!("{} INIT_SD", self.op("U")))],
            comment: Some("startup: the initial state is 0".into()),
        }];
        if spec.fault_any {
            let k = self.rng.range(spec.statements.0, spec.statements.1).max(2);
            let mut body: Vec<Part> = self
                .conditions_exact(k - 1)
                .into_iter()
                .map(Part::Stmt)
                .collect();
            body.push(Part::Stmt(format!("{} ST_Expired", self.op("O"))));
            transitions.push(Transition {
                source: "any".into(),
                target: (n - 1).to_string(),
                prio: Some(2),
                attrs: if spec.modes {
                    vec!["auto", "fault"]
                } else {
                    vec!["fault"]
                },
                name: Some("Stoerung"),
                body,
                comment: None,
            });
        }
        let mut per_state = vec![spec.normal_transitions / n; n];
        let mut extra: Vec<usize> = (0..n).collect();
        self.rng.shuffle(&mut extra);
        for &s in extra.iter().take(spec.normal_transitions % n) {
            per_state[s] += 1;
        }
        let has_wait: Vec<bool> = states.iter().map(|s| s.has_wait).collect();
        for s in 0..n {
            let targets = self.targets(s, per_state[s]);
            let mut prio = 0;
            for (k, target) in targets.into_iter().enumerate() {
                prio += 1;
                if self.rng.percent(8) {
                    prio += self.rng.range(1, 3);
                }
                let explicit = k == 0 || self.rng.percent(spec.explicit_prio);
                let mut attrs = Vec::new();
                if spec.modes {
                    attrs.push(if self.rng.percent(85) {
                        "auto"
                    } else {
                        "manual"
                    });
                }
                if k == 0 && has_wait[s] {
                    attrs.push("waits");
                }
                if self.rng.percent(2) {
                    attrs.push("fault");
                }
                let name = if self.rng.percent(12) {
                    Some(self.rng.choose(TRANSITION_NAMES))
                } else {
                    None
                };
                let body = self.transition_body();
                transitions.push(Transition {
                    source: s.to_string(),
                    target,
                    prio: explicit.then_some(prio),
                    attrs,
                    name,
                    body,
                    comment: None,
                });
            }
        }

        let permanent = self.permanent();
        self.render(&states, &permanent, &transitions)
    }

    /// `count` targets for transitions leaving `s`: first the next state (so that every state
    /// is reachable from state 0), then distinct other states, occasionally `return`.
    fn targets(&mut self, s: usize, count: usize) -> Vec<String> {
        let n = self.spec.states;
        let next = (s + 1) % n;
        let mut others: Vec<usize> = (0..n).filter(|&t| t != s && t != next).collect();
        self.rng.shuffle(&mut others);
        let mut out = vec![next.to_string()];
        let mut returned = false;
        let mut k = 0;
        while out.len() < count {
            if !returned && self.rng.percent(3) {
                returned = true;
                out.push("return".into());
            } else if others.is_empty() {
                out.push(next.to_string());
            } else {
                out.push(others[k % others.len()].to_string());
                k += 1;
            }
        }
        out
    }

    fn transition_body(&mut self) -> Vec<Part> {
        let (lo, hi) = self.spec.statements;
        let total = self.rng.range(lo, hi);
        let actions = if total >= 2 {
            self.rng.below(total.min(3))
        } else {
            0
        };
        let mut body = Vec::new();
        if self.rng.percent(8) {
            body.push(Part::Label("?:"));
        }
        body.extend(
            self.conditions_exact(total - actions)
                .into_iter()
                .map(Part::Stmt),
        );
        if actions > 0 {
            body.push(Part::Label("!:"));
            body.extend(self.actions_exact(actions).into_iter().map(Part::Stmt));
        }
        body
    }

    fn state(&mut self, s: usize, wait: Option<String>, supervise: Option<String>) -> State {
        let n = self.spec.states;
        let mut body = Vec::new();
        let mut block = |g: &mut Self, label: &'static str, percent: usize, max: usize| {
            if g.rng.percent(percent) {
                body.push(Part::Label(label));
                let k = g.rng.range(1, max);
                body.extend(g.actions_exact(k).into_iter().map(Part::Stmt));
            }
        };
        block(self, "E:", 60, 3);
        block(self, "C-:", 10, 2);
        block(self, "C:", 50, 3);
        if self.rng.percent(10) {
            block(self, "C:", 100, 1);
        }
        block(self, "X:", 25, 2);
        let has_wait = wait.is_some();
        if let Some(w) = wait {
            body.push(Part::Item(format!("wait {w}")));
        }
        if let Some(v) = supervise {
            body.push(Part::Item(format!("supervise {v}")));
        }
        let name = if s == 0 {
            "Grundstellung".to_string()
        } else if s == n - 1 && self.spec.fault_any {
            "Stoerung".to_string()
        } else {
            format!("{} {s}", self.rng.pick(&STATE_NAMES[1..]))
        };
        let mut attrs = Vec::new();
        if (s == n - 1 && self.spec.fault_any) || (s > 0 && self.rng.percent(3)) {
            attrs.push("fault");
        }
        if s > 0 && self.rng.percent(5) {
            attrs.push("message");
        }
        State {
            number: s,
            name,
            attrs,
            body,
            has_wait,
        }
    }

    /// The `permanent` instructions: the uses of the activated predefined variables, plus one
    /// use of every variable that the random parts left unused (HG1210).
    fn permanent(&mut self) -> Vec<Part> {
        let mut pre = Vec::new();
        let mut post = Vec::new();
        if self.spec.activate {
            let flag = self.bool_write();
            pre.push(format!("{} StateChange", self.op("U")));
            pre.push(format!("R {flag}"));
            let copy = self
                .pick(|p| &mut p.state_copy)
                .expect("activate adds a state copy");
            post.push("L CurrentState".to_string());
            post.push(format!("T {copy}"));
        }
        if !self.spec.globals.is_empty() {
            let g = self.rng.pick(&self.spec.globals).clone();
            let w = self.bool_write();
            post.push(format!("{} {g}", self.op("UN")));
            post.push(format!("R {w}"));
        }
        for i in 0..self.vars.len() {
            if self.used[i] {
                continue;
            }
            let role = self.vars[i].role;
            let op = self.operand(i);
            match role {
                Role::Sensor | Role::MsgIn => {
                    let w = self.bool_write();
                    post.push(format!("{} {op}", self.op("U")));
                    post.push(format!("= {w}"));
                }
                Role::Actuator | Role::Flag | Role::MsgOut => {
                    let x = self.bool_read();
                    post.push(format!("{} {x}", self.op("U")));
                    post.push(format!("= {op}"));
                }
                Role::Edge => {
                    let x = self.bool_read();
                    let w = self.bool_write();
                    post.push(format!("{} {x}", self.op("U")));
                    post.push(format!("FN {op}"));
                    post.push(format!("R {w}"));
                }
                Role::Setpoint => {
                    let w = self.int_write();
                    post.push(format!("L {op}"));
                    post.push(format!("T {w}"));
                }
                Role::ActualValue
                | Role::Parameter
                | Role::Count
                | Role::StatusWord
                | Role::StateCopy
                | Role::Measure
                | Role::Sum => {
                    post.push(format!("L {op}"));
                    post.push(format!("T {op}"));
                }
                Role::Timer | Role::Counter => post.push(format!("R {op}")),
                Role::Text => match self.call(Some(Need::Text)) {
                    Some(call) => post.push(call),
                    None => panic!(
                        "{}: a Text variable needs a call that takes it",
                        self.spec.name
                    ),
                },
                Role::WaitTime | Role::SuperviseTime => unreachable!("always used by a state"),
            }
        }
        let mut parts = Vec::new();
        if !pre.is_empty() {
            parts.push(Part::Label("C-:"));
            parts.extend(pre.into_iter().map(Part::Stmt));
        }
        if !post.is_empty() {
            parts.push(Part::Label("C:"));
            parts.extend(post.into_iter().map(Part::Stmt));
        }
        parts
    }

    // ------------------------------------------------------------------ text

    fn render(
        &mut self,
        states: &[State],
        permanent: &[Part],
        transitions: &[Transition],
    ) -> String {
        let spec = self.spec;
        let mut out = String::with_capacity(160 * transitions.len() + 4096);
        match &spec.title {
            Some(title) => writeln!(out, "graph {} \"{title}\" <", spec.name).unwrap(),
            None => writeln!(out, "graph {} <", spec.name).unwrap(),
        }
        for section in ["in", "out", "in_out", "stat"] {
            let decls: Vec<String> = self
                .vars
                .iter()
                .filter(|v| v.role.section() == section)
                .map(declaration)
                .collect();
            if decls.is_empty() {
                continue;
            }
            let one_line = format!("  {section} < {} >", decls.join(" "));
            if one_line.len() <= 100 {
                writeln!(out, "{one_line}").unwrap();
            } else {
                writeln!(out, "  {section} <").unwrap();
                for d in decls {
                    writeln!(out, "    {d}").unwrap();
                }
                writeln!(out, "  >").unwrap();
            }
        }
        if spec.activate {
            writeln!(out, "  activate CurrentState, StateChange;").unwrap();
        }
        if !permanent.is_empty() {
            out.push('\n');
            render_body(&mut out, "  permanent", permanent);
        }
        out.push('\n');
        for state in states {
            if state.number > 0 && state.number % 10 == 0 {
                writeln!(out, "  // ---- states {}..", state.number).unwrap();
            }
            let mut header = format!("  state {} \"{}\"", state.number, state.name);
            for a in &state.attrs {
                header.push(' ');
                header.push_str(a);
            }
            render_body(&mut out, &header, &state.body);
        }
        out.push('\n');
        for t in transitions {
            if let Some(c) = &t.comment {
                writeln!(out, "  // {c}").unwrap();
            }
            let mut header = format!("  trans {}->{}", t.source, t.target);
            if let Some(p) = t.prio {
                write!(header, " prio {p}").unwrap();
            }
            for a in &t.attrs {
                header.push(' ');
                header.push_str(a);
            }
            if let Some(name) = t.name {
                write!(header, " \"{name}\"").unwrap();
            }
            render_body(&mut out, &header, &t.body);
        }
        out.push_str(">\n");
        out
    }
}

struct State {
    number: usize,
    name: String,
    attrs: Vec<&'static str>,
    body: Vec<Part>,
    has_wait: bool,
}

fn declaration(v: &Var) -> String {
    let mut d = format!("{} : {}", v.name, v.role.type_name());
    match v.role {
        Role::MsgIn => d.push_str(" msg in"),
        Role::MsgOut => d.push_str(" msg out"),
        _ => {}
    }
    if let Some(init) = &v.init {
        write!(d, " := {init}").unwrap();
    }
    if let Some(c) = &v.comment {
        write!(d, " \"{c}\"").unwrap();
    }
    d.push(';');
    d
}

/// Writes `header < body >`: on one line when the body is at most one block with at most one
/// statement, otherwise one label or item per line and statements indented below their label.
fn render_body(out: &mut String, header: &str, body: &[Part]) {
    let statements = body.iter().filter(|p| !matches!(p, Part::Label(_))).count();
    let labels = body.iter().filter(|p| matches!(p, Part::Label(_))).count();
    let multiline = body
        .iter()
        .any(|p| matches!(p, Part::Stmt(s) if s.contains('\n')));
    if statements <= 1 && labels <= 1 && !multiline {
        let inner: Vec<String> = body
            .iter()
            .map(|p| match p {
                Part::Stmt(s) | Part::Item(s) => format!("{s};"),
                Part::Label(l) => (*l).to_string(),
            })
            .collect();
        if inner.is_empty() {
            writeln!(out, "{header} < >").unwrap();
        } else {
            writeln!(out, "{header} < {} >", inner.join(" ")).unwrap();
        }
        return;
    }
    writeln!(out, "{header} <").unwrap();
    let base = header.len() - header.trim_start().len() + 2;
    let mut in_block = false;
    for p in body {
        match p {
            Part::Label(l) => {
                writeln!(out, "{:base$}{l}", "").unwrap();
                in_block = true;
            }
            Part::Item(s) => {
                writeln!(out, "{:base$}{s};", "").unwrap();
                in_block = false;
            }
            Part::Stmt(s) => {
                let indent = if in_block { base + 2 } else { base };
                writeln!(out, "{:indent$}{s};", "").unwrap();
            }
        }
    }
    writeln!(out, "{:width$}>", "", width = base - 2).unwrap();
}
