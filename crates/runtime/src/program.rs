//! The lowered program: what `higraph-analysis` hands the machine. Resolved (every name is a
//! place), position-free (an [`Origin`] is an opaque number the lowering maps back to a file
//! range), and self-contained: a `Program` holds exactly the groups, graphs and charts one test
//! runs, plus the test itself.
//!
//! Layout decisions:
//! * Graph code is shared by its instances. An operand naming a graph variable is
//!   [`Operand::Var`]; each [`Instance`] binds every variable of its graph to a [`Place`] — its
//!   actual (a global address, another instance's message cell, a constant) or its own cell.
//!   That is `runtime.md` §2.1's "every use of a formal reads or writes its actual directly".
//! * Predefined variables come first in every graph's variable table, in the order of
//!   [`Predef`], so the engine finds `INIT_SD` or `CurrentState` of an instance by index.
//! * Cells hold raw bit patterns ([`crate::Value::to_bits`]); their types are in
//!   [`Program::cells`].

use crate::value::{Const, Ty, Value};

/// Index of a cell (an instance variable, a chart variable, an external reference of a chart).
pub type CellId = u32;
/// Index into [`Program::graphs`].
pub type GraphId = u32;
/// Index into a graph's variable table.
pub type VarIdx = u16;
/// Index into [`Program::blocks`].
pub type BlockId = u32;

/// Where a lowered construct came from: an index into the lowering's side table of
/// (file, range). `Origin::NONE` for code with no source of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Origin(pub u32);

impl Origin {
    pub const NONE: Origin = Origin(u32::MAX);
}

/// The whole lowered workspace part a test needs.
#[derive(Debug, Clone, Default)]
pub struct Program {
    /// Every cell with its type and initial value (§1.2: the declared initial value, else the
    /// type's zero; predefined variables as §2.7).
    pub cells: Vec<CellInfo>,
    /// Number of private timer and counter objects (unwired TIMER/COUNTER variables). Private
    /// object `i` is [`TimerId`]`(65536 + i)`.
    pub private_timers: u32,
    pub private_counters: u32,
    pub graphs: Vec<Graph>,
    pub groups: Vec<Group>,
    pub charts: Vec<Chart>,
    /// The blocks named by `CALL`/`CC` and by test stubs.
    pub blocks: Vec<BlockInfo>,
    /// The test to run (absent when only groups and charts are simulated, e.g. benchmarks).
    pub test: Option<Test>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CellInfo {
    pub ty: Ty,
    pub init: Value,
}

// ------------------------------------------------------------------------------- places

/// A memory area of §1.1. Peripheral areas are lowered to `Input`/`Output`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MemArea {
    Input,
    Output,
    Memory,
    Local,
    /// `DBn.DBX/DBB/DBW/DBD`.
    Db(u16),
}

/// The access width of an address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Width {
    /// A bit, 0..7.
    Bit(u8),
    Byte,
    Word,
    Dword,
}

/// A timer object: 0..=65535 are `T n`; from 65536 the private objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TimerId(pub u32);
/// A counter object: 0..=65535 are `Z n`; from 65536 the private objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CounterId(pub u32);

/// A resolved location.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// Absolute memory. `byte` is as written (an access past byte 65535 is a fault, §1.4).
    Mem {
        area: MemArea,
        byte: u32,
        width: Width,
    },
    /// A cell; its type is in [`Program::cells`].
    Cell(CellId),
    Timer(TimerId),
    Counter(CounterId),
    /// A constant actual: reads give it, writes are discarded (§2.1).
    Const(Value),
}

// ---------------------------------------------------------------------------------- STL

/// An STL operation, by its SIMATIC name (international spellings are lowered to these).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OpCode {
    // bit logic (§3.2)
    U,
    Un,
    O,
    On,
    X,
    Xn,
    /// `O` without operand.
    OrNone,
    UParen,
    UnParen,
    OParen,
    OnParen,
    XParen,
    XnParen,
    Close,
    Assign,
    /// `S`: on a BOOL, set; on a counter, the preset (§3.4).
    S,
    /// `R`: on a BOOL, reset; on a timer or counter, §3.3/§3.4.
    R,
    Set,
    Clr,
    Not,
    Fp,
    Fn,
    // timers and counters (§3.3, §3.4)
    Si,
    Sv,
    Se,
    Ss,
    Sa,
    /// `FR` on a timer or counter.
    Fr,
    Zv,
    Zr,
    // load and transfer (§3.5)
    L,
    Lc,
    T,
    Tak,
    Push,
    Pop,
    Inc,
    Dec,
    /// `+ n` with an INT constant.
    AddInt,
    /// `+ L#n`.
    AddDint,
    Taw,
    Tad,
    Tar,
    Tar1,
    Tar2,
    // word logic (§3.6)
    Uw,
    Ow,
    Xow,
    Ud,
    Od,
    Xod,
    // comparisons (§3.6)
    EqI,
    NeI,
    GtI,
    LtI,
    GeI,
    LeI,
    EqD,
    NeD,
    GtD,
    LtD,
    GeD,
    LeD,
    EqR,
    NeR,
    GtR,
    LtR,
    GeR,
    LeR,
    // integer arithmetic (§3.7)
    AddI,
    SubI,
    MulI,
    DivI,
    AddD,
    SubD,
    MulD,
    DivD,
    Mod,
    NegI,
    NegD,
    // real arithmetic (§3.8)
    AddR,
    SubR,
    MulR,
    DivR,
    Abs,
    Sqr,
    Sqrt,
    Exp,
    Ln,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    NegR,
    // shift and rotate (§3.9)
    Slw,
    Srw,
    Sld,
    Srd,
    Ssi,
    Ssd,
    Rld,
    Rrd,
    Rlda,
    Rrda,
    // conversion (§3.10)
    Bti,
    Btd,
    Itb,
    Dtb,
    Itd,
    Dtr,
    Invi,
    Invd,
    Rnd,
    RndPlus,
    RndMinus,
    Trunc,
    // calls (§3.11)
    Call,
    Cc,
}

impl OpCode {
    /// Does the instruction leave an RLO that no longer depends on the RLO before it (so the
    /// normal and the RLO-0 pass agree from here on)? NOT, `=`, S, R, `O` and the non-logic
    /// operations keep the difference; FP and FN are counted as ending it (their edge memories
    /// differ anyway). The interpreter and the STEP 7 generator share this rule.
    pub fn replaces_rlo(self) -> bool {
        use OpCode::*;
        matches!(
            self,
            U | Un
                | O
                | On
                | X
                | Xn
                | Close
                | Set
                | Clr
                | Fp
                | Fn
                | EqI
                | NeI
                | GtI
                | LtI
                | GeI
                | LeI
                | EqD
                | NeD
                | GtD
                | LtD
                | GeD
                | LeD
                | EqR
                | NeR
                | GtR
                | LtR
                | GeR
                | LeR
                | Call
                | Cc
        )
    }

    /// The operation of a SIMATIC name in upper case (`U(`, `==I`, `RND+`); `+` is `AddInt`
    /// (the lowering picks `AddDint` for `+ L#n`).
    pub fn from_simatic(name: &str) -> Option<OpCode> {
        use OpCode::*;
        Some(match name {
            "U" => U,
            "UN" => Un,
            "O" => O,
            "ON" => On,
            "X" => X,
            "XN" => Xn,
            "U(" => UParen,
            "UN(" => UnParen,
            "O(" => OParen,
            "ON(" => OnParen,
            "X(" => XParen,
            "XN(" => XnParen,
            ")" => Close,
            "=" => Assign,
            "S" => S,
            "R" => R,
            "SET" => Set,
            "CLR" => Clr,
            "NOT" => Not,
            "FP" => Fp,
            "FN" => Fn,
            "SI" => Si,
            "SV" => Sv,
            "SE" => Se,
            "SS" => Ss,
            "SA" => Sa,
            "FR" => Fr,
            "ZV" => Zv,
            "ZR" => Zr,
            "L" => L,
            "LC" => Lc,
            "T" => T,
            "TAK" => Tak,
            "PUSH" => Push,
            "POP" => Pop,
            "INC" => Inc,
            "DEC" => Dec,
            "+" => AddInt,
            "TAW" => Taw,
            "TAD" => Tad,
            "TAR" => Tar,
            "TAR1" => Tar1,
            "TAR2" => Tar2,
            "UW" => Uw,
            "OW" => Ow,
            "XOW" => Xow,
            "UD" => Ud,
            "OD" => Od,
            "XOD" => Xod,
            "==I" => EqI,
            "<>I" => NeI,
            ">I" => GtI,
            "<I" => LtI,
            ">=I" => GeI,
            "<=I" => LeI,
            "==D" => EqD,
            "<>D" => NeD,
            ">D" => GtD,
            "<D" => LtD,
            ">=D" => GeD,
            "<=D" => LeD,
            "==R" => EqR,
            "<>R" => NeR,
            ">R" => GtR,
            "<R" => LtR,
            ">=R" => GeR,
            "<=R" => LeR,
            "+I" => AddI,
            "-I" => SubI,
            "*I" => MulI,
            "/I" => DivI,
            "+D" => AddD,
            "-D" => SubD,
            "*D" => MulD,
            "/D" => DivD,
            "MOD" => Mod,
            "NEGI" => NegI,
            "NEGD" => NegD,
            "+R" => AddR,
            "-R" => SubR,
            "*R" => MulR,
            "/R" => DivR,
            "ABS" => Abs,
            "SQR" => Sqr,
            "SQRT" => Sqrt,
            "EXP" => Exp,
            "LN" => Ln,
            "SIN" => Sin,
            "COS" => Cos,
            "TAN" => Tan,
            "ASIN" => Asin,
            "ACOS" => Acos,
            "ATAN" => Atan,
            "NEGR" => NegR,
            "SLW" => Slw,
            "SRW" => Srw,
            "SLD" => Sld,
            "SRD" => Srd,
            "SSI" => Ssi,
            "SSD" => Ssd,
            "RLD" => Rld,
            "RRD" => Rrd,
            "RLDA" => Rlda,
            "RRDA" => Rrda,
            "BTI" => Bti,
            "BTD" => Btd,
            "ITB" => Itb,
            "DTB" => Dtb,
            "ITD" => Itd,
            "DTR" => Dtr,
            "INVI" => Invi,
            "INVD" => Invd,
            "RND" => Rnd,
            "RND+" => RndPlus,
            "RND-" => RndMinus,
            "TRUNC" => Trunc,
            "CALL" => Call,
            "CC" => Cc,
            _ => return None,
        })
    }
}

/// The operand of an instruction.
#[derive(Debug, Clone, PartialEq)]
pub enum Operand {
    None,
    /// A constant as its accumulator pattern ([`crate::value::load_pattern`]); also the `n`
    /// of `INC`, `+`, shifts and the constant of `UW`…
    Imm(u32),
    /// A variable of the graph; the running instance binds it.
    Var(VarIdx),
    /// A resolved global place (address or symbol) or chart cell.
    Place(Place),
    /// The block and parameters of `CALL`/`CC`.
    Call(Box<Call>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    pub block: BlockId,
    /// `(formal name as written, actual)`; the stub table is keyed by the formal name in
    /// upper case.
    pub params: Vec<(String, Operand)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Instr {
    pub op: OpCode,
    pub operand: Operand,
    pub origin: Origin,
}

/// An instruction block (§2.3: "blocks", §3.1): each starts with RLO = 1 (or 0 in the RLO-0
/// pass).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Block {
    pub code: Vec<Instr>,
}

/// A block a call can name: how the trace and the stubs call it.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockInfo {
    /// The canonical name (`FC10`, or the symbol).
    pub name: String,
}

// ------------------------------------------------------------------------------- graphs

/// The predefined variables, in the order they open every graph's variable table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u16)]
pub enum Predef {
    ManualMode,
    AutomaticMode,
    UsrMsgQuit,
    InitSd,
    CurrentState,
    PreviousState,
    StateChange,
    StExpired,
    StExpiredPrev,
    WtExpired,
    StStop,
    WtStop,
    StCurrValue,
    WtCurrValue,
    StValid,
    WtValid,
    UsrMsgSend,
    UsrMsgStat,
}

impl Predef {
    pub const ALL: [Predef; 18] = [
        Predef::ManualMode,
        Predef::AutomaticMode,
        Predef::UsrMsgQuit,
        Predef::InitSd,
        Predef::CurrentState,
        Predef::PreviousState,
        Predef::StateChange,
        Predef::StExpired,
        Predef::StExpiredPrev,
        Predef::WtExpired,
        Predef::StStop,
        Predef::WtStop,
        Predef::StCurrValue,
        Predef::WtCurrValue,
        Predef::StValid,
        Predef::WtValid,
        Predef::UsrMsgSend,
        Predef::UsrMsgStat,
    ];

    /// The variable index of the predefined variable.
    pub fn var(self) -> VarIdx {
        self as VarIdx
    }

    pub fn name(self) -> &'static str {
        match self {
            Predef::ManualMode => "ManualMode",
            Predef::AutomaticMode => "AutomaticMode",
            Predef::UsrMsgQuit => "UsrMsgQuit",
            Predef::InitSd => "INIT_SD",
            Predef::CurrentState => "CurrentState",
            Predef::PreviousState => "PreviousState",
            Predef::StateChange => "StateChange",
            Predef::StExpired => "ST_Expired",
            Predef::StExpiredPrev => "ST_ExpiredPrev",
            Predef::WtExpired => "WT_Expired",
            Predef::StStop => "ST_Stop",
            Predef::WtStop => "WT_Stop",
            Predef::StCurrValue => "ST_CurrValue",
            Predef::WtCurrValue => "WT_CurrValue",
            Predef::StValid => "ST_Valid",
            Predef::WtValid => "WT_Valid",
            Predef::UsrMsgSend => "UsrMsgSend",
            Predef::UsrMsgStat => "UsrMsgStat",
        }
    }

    pub fn ty(self) -> Ty {
        match self {
            Predef::CurrentState | Predef::PreviousState | Predef::UsrMsgStat => Ty::Word,
            Predef::StCurrValue | Predef::WtCurrValue => Ty::Dword,
            _ => Ty::Bool,
        }
    }
}

/// A graph variable.
#[derive(Debug, Clone, PartialEq)]
pub struct VarInfo {
    pub name: String,
    pub ty: Ty,
    /// `Some(true)` for `msg in`, `Some(false)` for `msg out`.
    pub msg_in: Option<bool>,
    pub init: Option<Value>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Graph {
    pub name: String,
    /// Predefined variables first (in [`Predef::ALL`] order), then the declared ones in text
    /// order.
    pub vars: Vec<VarInfo>,
    /// States in text order.
    pub states: Vec<State>,
    /// Any-transitions by effective priority (1 first); the startup transition among them.
    pub any: Vec<Trans>,
    /// Index into `any` of the startup transition (the any-transition querying INIT_SD).
    pub startup: Option<usize>,
    /// State number of the initial state (the startup transition's target).
    pub initial: Option<u16>,
    /// `permanent` `C-` and `C` blocks, text order.
    pub permanent_pre: Vec<Block>,
    pub permanent_post: Vec<Block>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct State {
    pub number: u16,
    pub name: Option<String>,
    /// `fault` or `message` (UsrMsgSend, §2.5).
    pub reports: bool,
    pub entry: Vec<Block>,
    /// `C-` blocks.
    pub pre: Vec<Block>,
    /// `C` blocks.
    pub cyclic: Vec<Block>,
    pub exit: Vec<Block>,
    pub wait: Option<TimeValue>,
    pub supervise: Option<TimeValue>,
    /// Normal and return transitions leaving this state, by effective priority (1 first).
    pub transitions: Vec<Trans>,
}

/// A `wait`/`supervise` value.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeValue {
    /// Milliseconds.
    Const(i64),
    /// A TIME operand, read once at entry (§2.6).
    Operand(Operand),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target {
    State(u16),
    Return,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Trans {
    /// `None` for an any-transition.
    pub from: Option<u16>,
    pub to: Target,
    pub prio: u32,
    pub auto: bool,
    pub manual: bool,
    pub waits: bool,
    /// Condition blocks (§2.4 step 4): the statements before the first label, then each `?:`.
    pub conditions: Vec<Block>,
    /// `!` blocks.
    pub actions: Vec<Block>,
    pub origin: Origin,
}

// ------------------------------------------------------------------------------- groups

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GroupOptions {
    pub cyclic_rlo0: bool,
    pub any_once: bool,
    pub precyclic_on_entry: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub name: String,
    pub options: GroupOptions,
    /// Run order (text order).
    pub instances: Vec<Instance>,
    /// The `msg in` cells an internal link targets (reset when the group is fresh, §2.2).
    pub internal_messages: Vec<InternalMessage>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct InternalMessage {
    /// The receiving instance (index in the group) and its `msg in` variable.
    pub instance: u32,
    pub var: VarIdx,
    pub cell: CellId,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    pub name: String,
    pub graph: GraphId,
    /// One place per variable of the graph (same indices as [`Graph::vars`]): the actual, or
    /// the instance's own cell.
    pub binding: Vec<Place>,
}

// ------------------------------------------------------------------------------- charts

/// A chart's operating state (§4.2), numbered as SFC Table 3-2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum OpState {
    Ready = 1,
    Starting = 2,
    Active = 3,
    Completing = 4,
    ErrorCompleting = 5,
    Completed = 6,
    Holding = 7,
    Held = 8,
    Resuming = 9,
    Error = 10,
    HeldError = 11,
    ResumingError = 12,
    Aborting = 13,
    Aborted = 14,
    Stopping = 15,
    Stopped = 16,
}

impl OpState {
    pub const ALL: [OpState; 16] = [
        OpState::Ready,
        OpState::Starting,
        OpState::Active,
        OpState::Completing,
        OpState::ErrorCompleting,
        OpState::Completed,
        OpState::Holding,
        OpState::Held,
        OpState::Resuming,
        OpState::Error,
        OpState::HeldError,
        OpState::ResumingError,
        OpState::Aborting,
        OpState::Aborted,
        OpState::Stopping,
        OpState::Stopped,
    ];

    pub fn name(self) -> &'static str {
        match self {
            OpState::Ready => "Ready",
            OpState::Starting => "Starting",
            OpState::Active => "Active",
            OpState::Completing => "Completing",
            OpState::ErrorCompleting => "ErrorCompleting",
            OpState::Completed => "Completed",
            OpState::Holding => "Holding",
            OpState::Held => "Held",
            OpState::Resuming => "Resuming",
            OpState::Error => "Error",
            OpState::HeldError => "HeldError",
            OpState::ResumingError => "ResumingError",
            OpState::Aborting => "Aborting",
            OpState::Aborted => "Aborted",
            OpState::Stopping => "Stopping",
            OpState::Stopped => "Stopped",
        }
    }

    /// By name, case-insensitive.
    pub fn from_name(name: &str) -> Option<OpState> {
        OpState::ALL
            .into_iter()
            .find(|s| s.name().eq_ignore_ascii_case(name))
    }

    pub fn from_number(n: u8) -> Option<OpState> {
        OpState::ALL.into_iter().find(|s| *s as u8 == n)
    }
}

/// The `SFC.` flags of §4.2 (other `SFC.` paths read FALSE: they lower to a constant).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SfcFlag {
    Idle,
    Starting,
    Run,
    Completing,
    Error,
    Completed,
    Holding,
    Held,
    Resuming,
    Aborting,
    Aborted,
    Stopping,
    Stopped,
}

/// A chart command of §4.2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    Start,
    Hold,
    Resume,
    Complete,
    Abort,
    Stop,
    Reset,
    Error,
}

impl Command {
    pub const ALL: [Command; 8] = [
        Command::Start,
        Command::Hold,
        Command::Resume,
        Command::Complete,
        Command::Abort,
        Command::Stop,
        Command::Reset,
        Command::Error,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Command::Start => "start",
            Command::Hold => "hold",
            Command::Resume => "resume",
            Command::Complete => "complete",
            Command::Abort => "abort",
            Command::Stop => "stop",
            Command::Reset => "reset",
            Command::Error => "error",
        }
    }

    pub fn from_name(name: &str) -> Option<Command> {
        Command::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(name))
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Switching {
    #[default]
    T,
    B,
    TOrB,
    TAndB,
    Step,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Qualifier {
    N,
    S,
    R,
    P,
    L,
    D,
    Sd,
    Ds,
    Sl,
    /// IEC: a pulse when the step becomes active (rising edge of its input).
    P1,
    /// IEC: a pulse when the step becomes inactive (falling edge of its input).
    P0,
    /// IEC: delayed and limited — on from `t` after the input rose until `2·t`, while it stays.
    Dl,
}

/// The chart profile (`profile pcs7;` default, `profile iec;`), `docs/iec.md`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Profile {
    #[default]
    Pcs7,
    Iec,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    pub name: String,
    /// PCS 7 (operating states, several sequencers) or IEC 61131-3 (one sequencer running from
    /// the first cycle, `docs/iec.md` §7).
    pub profile: Profile,
    /// Chart variables: `(name, cell)`.
    pub vars: Vec<(String, CellId)>,
    /// `mode auto;` (default manual).
    pub mode_auto: bool,
    pub switching: Switching,
    /// `run cyclic;`, `run time_monitoring;`, `run autostart;`.
    pub cyclic: bool,
    pub time_monitoring: bool,
    pub autostart: bool,
    pub sequencers: Vec<Sequencer>,
    /// The actions of §4.6: every BOOL place named by a qualifier, once; in an IEC chart also
    /// every `action` member (with a body).
    pub actions: Vec<Action>,
    /// The standard function block instances of the chart (IEC charts; `docs/iec.md` §3),
    /// indexed by [`FbId`].
    pub fbs: Vec<FbInstance>,
}

/// One action of §4.6.
#[derive(Debug, Clone, PartialEq)]
pub struct Action {
    /// How the trace names it (the operand as written first, without white space; the action
    /// name for an `action` member).
    pub name: String,
    /// Written with the action's activity each cycle (a BOOL; for an `action` member a hidden
    /// cell of the lowering).
    pub place: Place,
    /// The statements of an `action` member (IEC charts): run in every cycle in which the action
    /// is active and once more in the cycle in which it stops (the final scan). `None` for a
    /// BOOL variable action.
    pub body: Option<Vec<Statement>>,
}

/// A step index within its sequencer.
pub type StepIdx = u32;
/// A transition index within its sequencer.
pub type TransIdx = u32;

#[derive(Debug, Clone, PartialEq)]
pub struct Sequencer {
    pub name: String,
    /// Effective priority (a missing `prio` is 1).
    pub prio: u32,
    /// Start condition entries, ANDed; empty = FALSE.
    pub start: Vec<Expr>,
    pub pre: Vec<Statement>,
    pub post: Vec<Statement>,
    /// Steps in text order; the first is the start step, the last the end step.
    pub steps: Vec<Step>,
    /// `trans`, `jump` and `loop` units, text order.
    pub transitions: Vec<ChartTrans>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub name: String,
    pub init: Vec<Statement>,
    pub run: Vec<Statement>,
    pub term: Vec<Statement>,
    pub qualifiers: Vec<Association>,
    pub min: Option<Expr>,
    pub max: Option<Expr>,
    pub confirm: bool,
    /// The decision candidates of §4.5 step 2, in order: successor transitions, then this
    /// step's `loop`s and `jump`s in text order.
    pub candidates: Vec<TransIdx>,
    pub origin: Origin,
}

/// `(S, q, X)` of §4.6.
#[derive(Debug, Clone, PartialEq)]
pub struct Association {
    pub qualifier: Qualifier,
    /// Index into [`Chart::actions`].
    pub action: u32,
    /// The time of `L D SD DS SL` (a TIME expression, read at each evaluation).
    pub time: Option<Expr>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChartTransKind {
    Trans,
    Jump,
    Loop,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ChartTrans {
    pub kind: ChartTransKind,
    pub name: Option<String>,
    /// Predecessors that must all be active (more than one after a parallel: the last steps
    /// of all branches).
    pub from: Vec<StepIdx>,
    /// Successors activated when it fires (every first step of a parallel).
    pub to: Vec<StepIdx>,
    /// Conditions, ANDed; empty = TRUE.
    pub conditions: Vec<Expr>,
    pub origin: Origin,
}

/// A chart statement: an assignment ([`Stmt`]) or, in IEC charts, a structured statement
/// (`docs/iec.md` §5). Nesting is bounded by the parser's nesting limit (HG0012).
#[derive(Debug, Clone, PartialEq)]
pub enum Statement {
    Assign(Stmt),
    /// `IF c1 THEN .. ELSIF c2 THEN .. ELSE .. END_IF;`: the first arm whose condition holds
    /// runs, else `else_`.
    If {
        arms: Vec<(Expr, Vec<Statement>)>,
        else_: Vec<Statement>,
        origin: Origin,
    },
    /// `CASE sel OF labels: .. ELSE .. END_CASE;`: the first arm one of whose inclusive ranges
    /// `(low, high)` holds the selector runs, else `else_`.
    Case {
        selector: Expr,
        arms: Vec<CaseArm>,
        else_: Vec<Statement>,
        origin: Origin,
    },
    /// `Timer(IN := x, PT := T#5S, Q => y);`
    Call(FbCall),
}

/// An arm of a `CASE`: its labels as inclusive ranges `(low, high)` (a single label `n` is
/// `(n, n)`), and its statements.
pub type CaseArm = (Vec<(i64, i64)>, Vec<Statement>);

impl From<Stmt> for Statement {
    fn from(s: Stmt) -> Statement {
        Statement::Assign(s)
    }
}

/// A call of a standard function block instance: the inputs are evaluated and written into the
/// instance's input cells (left to right), the block runs once, then the outputs are copied.
#[derive(Debug, Clone, PartialEq)]
pub struct FbCall {
    /// Index into [`Chart::fbs`].
    pub fb: FbId,
    pub inputs: Vec<(FbMember, Expr)>,
    /// `(output member, target, target type)`.
    pub outputs: Vec<(FbMember, Place, Ty)>,
    pub origin: Origin,
}

/// Index into [`Chart::fbs`].
pub type FbId = u32;

/// A standard function block type of IEC 61131-3 (`docs/iec.md` §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FbType {
    Ton,
    Tof,
    Tp,
    RTrig,
    FTrig,
    Ctu,
    Ctd,
    Ctud,
    Sr,
    Rs,
}

/// A member (input or output) of a standard function block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FbMember {
    In,
    Pt,
    Q,
    Et,
    Clk,
    Cu,
    Cd,
    R,
    Ld,
    Pv,
    Qu,
    Qd,
    Cv,
    S1,
    S,
    R1,
    Q1,
}

impl FbMember {
    pub fn name(self) -> &'static str {
        use FbMember::*;
        match self {
            In => "IN",
            Pt => "PT",
            Q => "Q",
            Et => "ET",
            Clk => "CLK",
            Cu => "CU",
            Cd => "CD",
            R => "R",
            Ld => "LD",
            Pv => "PV",
            Qu => "QU",
            Qd => "QD",
            Cv => "CV",
            S1 => "S1",
            S => "S",
            R1 => "R1",
            Q1 => "Q1",
        }
    }

    /// The member's type: TIME for `PT`/`ET`, INT for `PV`/`CV`, else BOOL.
    pub fn ty(self) -> Ty {
        match self {
            FbMember::Pt | FbMember::Et => Ty::Time,
            FbMember::Pv | FbMember::Cv => Ty::Int,
            _ => Ty::Bool,
        }
    }
}

impl FbType {
    pub const ALL: [FbType; 10] = [
        FbType::Ton,
        FbType::Tof,
        FbType::Tp,
        FbType::RTrig,
        FbType::FTrig,
        FbType::Ctu,
        FbType::Ctd,
        FbType::Ctud,
        FbType::Sr,
        FbType::Rs,
    ];

    pub fn name(self) -> &'static str {
        match self {
            FbType::Ton => "TON",
            FbType::Tof => "TOF",
            FbType::Tp => "TP",
            FbType::RTrig => "R_TRIG",
            FbType::FTrig => "F_TRIG",
            FbType::Ctu => "CTU",
            FbType::Ctd => "CTD",
            FbType::Ctud => "CTUD",
            FbType::Sr => "SR",
            FbType::Rs => "RS",
        }
    }

    /// By name, case-insensitive.
    pub fn from_name(name: &str) -> Option<FbType> {
        FbType::ALL
            .into_iter()
            .find(|t| t.name().eq_ignore_ascii_case(name))
    }

    pub fn inputs(self) -> &'static [FbMember] {
        use FbMember::*;
        match self {
            FbType::Ton | FbType::Tof | FbType::Tp => &[In, Pt],
            FbType::RTrig | FbType::FTrig => &[Clk],
            FbType::Ctu => &[Cu, R, Pv],
            FbType::Ctd => &[Cd, Ld, Pv],
            FbType::Ctud => &[Cu, Cd, R, Ld, Pv],
            FbType::Sr => &[S1, R],
            FbType::Rs => &[S, R1],
        }
    }

    pub fn outputs(self) -> &'static [FbMember] {
        use FbMember::*;
        match self {
            FbType::Ton | FbType::Tof | FbType::Tp => &[Q, Et],
            FbType::RTrig | FbType::FTrig => &[Q],
            FbType::Ctu | FbType::Ctd => &[Q, Cv],
            FbType::Ctud => &[Qu, Qd, Cv],
            FbType::Sr | FbType::Rs => &[Q1],
        }
    }

    /// Inputs, then outputs: the order of [`FbInstance::members`].
    pub fn members(self) -> impl Iterator<Item = FbMember> {
        self.inputs().iter().chain(self.outputs()).copied()
    }

    /// A member by name, case-insensitive.
    pub fn member(self, name: &str) -> Option<FbMember> {
        self.members().find(|m| m.name().eq_ignore_ascii_case(name))
    }

    /// The types of the hidden state cells ([`FbInstance::state`]): timers keep the previous
    /// `IN` (BOOL) and the virtual time (ms, DWORD, compared with wrap-around) at which their
    /// interval started, TP also whether a pulse runs; edge detectors and counters the
    /// previous edge input(s); SR/RS none (Q1 is their state).
    pub fn state_tys(self) -> &'static [Ty] {
        match self {
            FbType::Ton | FbType::Tof => &[Ty::Bool, Ty::Dword],
            FbType::Tp => &[Ty::Bool, Ty::Dword, Ty::Bool],
            FbType::RTrig | FbType::FTrig | FbType::Ctu | FbType::Ctd => &[Ty::Bool],
            FbType::Ctud => &[Ty::Bool, Ty::Bool],
            FbType::Sr | FbType::Rs => &[],
        }
    }
}

/// One standard function block instance (a `stat` variable of an IEC chart). Its members and
/// its hidden state are ordinary cells, so `Chart.Timer.Q` is a cell read, `Timer.PT := ..` a
/// cell write, and a cold restart resets the instance with the other cells.
#[derive(Debug, Clone, PartialEq)]
pub struct FbInstance {
    pub name: String,
    pub ty: FbType,
    /// One cell per member, in [`FbType::members`] order (types [`FbMember::ty`]).
    pub members: Vec<CellId>,
    /// One cell per [`FbType::state_tys`] entry.
    pub state: Vec<CellId>,
}

impl FbInstance {
    /// The cell of a member.
    pub fn cell(&self, member: FbMember) -> Option<CellId> {
        self.ty
            .members()
            .position(|m| m == member)
            .and_then(|i| self.members.get(i).copied())
    }
}

/// A chart assignment `path := expr;`.
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    pub target: Place,
    /// The target's type: the value is converted to it (literal adaptation is done by the
    /// lowering, so this is a plain conversion of an already fitting value).
    pub ty: Ty,
    pub value: Expr,
    pub origin: Origin,
}

// -------------------------------------------------------------------------- expressions

/// A chart or test expression. Depth is bounded by the parser's nesting limit.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    Const(Value),
    /// A read of a path, with the path's text for `{values}` and traces.
    Read(Path),
    Not(Box<Expr>),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
    Xor(Box<Expr>, Box<Expr>),
    Cmp(CmpOp, Box<Expr>, Box<Expr>),
    /// Unary minus (INT, DINT wrap around; REAL; TIME).
    Neg(Box<Expr>),
    /// `+ - * / MOD` (`docs/iec.md` §4). The lowering gives both operands the result type
    /// (or TIME and an integer for `TIME * n`, `TIME / n`).
    Arith(ArithOp, Box<Expr>, Box<Expr>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ArithOp {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CmpOp {
    Eq,
    Ne,
    Lt,
    Gt,
    Le,
    Ge,
}

/// A readable (and maybe writable) path of a chart or test expression (§4.7, §5.3).
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    /// As written, white space removed (`Bohren.state`, `E0.3`).
    pub text: String,
    pub ty: Ty,
    pub kind: PathKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum PathKind {
    /// Memory, a symbol, a chart variable, an instance variable via its actual, an external
    /// reference. A timer or counter reads its status (§5.3).
    Place(Place),
    /// `[Group.]Inst.state` / `.previous`: group index, instance index.
    InstState {
        group: u32,
        instance: u32,
        previous: bool,
    },
    /// An `SFC.` flag of the chart whose code is running.
    Sfc(SfcFlag),
    /// `Chart.state`.
    ChartState { chart: u32 },
    /// `Chart.[Seq.]Step[.X]`, `.T`, `.error`.
    Step {
        chart: u32,
        sequencer: u32,
        step: StepIdx,
        member: StepMember,
    },
    /// `Block.Param`: the stub value (formal name in upper case).
    Stub { block: BlockId, param: String },
    /// `Block.calls`.
    Calls { block: BlockId },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StepMember {
    Active,
    Time,
    Error,
}

// -------------------------------------------------------------------------------- tests

#[derive(Debug, Clone, PartialEq)]
pub struct Test {
    pub name: String,
    /// Δ in ms (default 10).
    pub cycle_ms: u32,
    /// The run list, in order.
    pub run: Vec<RunEntry>,
    pub stmts: Vec<TestStmt>,
    /// Every path used in a `set`, `expect` or `until`, in first-use order (the trace's
    /// `watch`).
    pub watch: Vec<Path>,
    pub origin: Origin,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RunEntry {
    Group(u32),
    Chart(u32),
}

#[derive(Debug, Clone, PartialEq)]
pub struct TestStmt {
    pub kind: TestStmtKind,
    pub origin: Origin,
}

#[derive(Debug, Clone, PartialEq)]
pub enum TestStmtKind {
    Set {
        target: Path,
        value: Expr,
    },
    /// `step N;` and `wait d;` (already turned into ⌈d/Δ⌉ cycles).
    Step {
        cycles: u64,
    },
    /// `until e within d`: at most `cycles` cycles; `within` as written for the message.
    Until {
        cond: Expr,
        cycles: u64,
        within: String,
        message: Option<String>,
        /// The expression's origin (failures point at it).
        expr_origin: Origin,
    },
    Expect {
        cond: Expr,
        message: Option<String>,
        expr_origin: Origin,
    },
    Command {
        chart: u32,
        command: Command,
    },
    /// `confirm C.[Seq.]Step;`.
    Confirm {
        chart: u32,
        sequencer: u32,
        step: StepIdx,
        text: String,
    },
    Restart {
        cold: bool,
    },
}

impl Const {
    /// A helper for lowering: the `Imm` operand of a constant.
    pub fn imm(&self) -> Operand {
        Operand::Imm(crate::value::load_pattern(self))
    }
}
