//! A graph group as a STEP 7 external source: one `DATA_BLOCK` (the group's DB), one
//! `FUNCTION` (the group's FC, called once per cycle) and, on request, an
//! `ORGANIZATION_BLOCK OB 1` that calls it (`export.md` §3).
//!
//! # Shape of the generated code
//!
//! The FC performs one group call of `runtime.md` §2 exactly as the simulator does it
//! (`crates/runtime/src/group.rs` is the reference: this module mirrors `call`, `Turn::run`,
//! `eligible`, `change`, `enter`, `entered`, `update_time` and `load_time` step by step).
//!
//! * **Blocks.** Every instruction block of the user starts with `SET` (the RLO-0 pass of
//!   `option cyclic_rlo0`: `CLR`), which is exactly the block start of §3.1 (RLO, STA, OR, /FC).
//!   A condition block ends with `SPBN` to the transition's "not eligible" label; the jump only
//!   touches RLO, STA, OR and /FC, which the next block start resets anyway. In the RLO-0 pass
//!   a timer or counter operation that still sees the block's start RLO (no first check, `SET`,
//!   `CLR`, comparison or call before it) is wrapped in `NOT` … `NOT`, because the simulator
//!   runs those as they would run with RLO = 1 (`stl.rs`, `is_timer_or_counter_op`).
//! * **Registers carry over.** ACCU1, ACCU2 and OV, OS, CC0, CC1, BR carry over between user
//!   blocks and instances (§3.1). Glue code that needs the accumulators (time arithmetic,
//!   state numbers, jump lists) runs between a *save* (`T #HG_A1`, `TAK`, `T #HG_A2`,
//!   `L STW`, `T #HG_SW`) and a *restore* (`L #HG_SW`, `T STW`, `L #HG_A2`, `L #HG_A1`), so
//!   user code sees exactly what the simulator gives it. Glue between user blocks that only
//!   needs bits (modes, waits, flags) uses `U`/`SPB`/`SPBN`, which leave the accumulators and
//!   those status bits alone; such glue starts with `SET` so that it never combines with an
//!   RLO left over by a restore.
//! * **States.** The state number at turn start is kept in `#HG_S`, the state whose `C` blocks
//!   run at step 8 in `#HG_C`, the target of a return transition in `#HG_T`. Code that depends
//!   on a state known only at run time (the `X` blocks of the source of an any-transition,
//!   the entry into the target of a return transition, the `C` blocks of step 8, the `C-`
//!   blocks and transitions of step 4) is reached through a jump list (`SPL`; a chain of
//!   comparisons when a state number is 255 or above).
//! * **Times from the CPU clock.** Each call reads `TIME_TCK` (`CALL SFC 64`) and takes the
//!   milliseconds since the previous call as Δ (wrapping at 2^31 as the clock does); a fresh
//!   DB updates no time (§2.6). Virtual time in Awlsim and real time on a CPU both work.
//! * **Fresh.** The DB's own flag `HG_Init` (initial value FALSE) is set by the first call, so
//!   loading a new DB gives the initial entry and resets the internal incoming messages;
//!   otherwise `INIT_SD` of the FC input drives the startup transition.
//! * **Formals are substituted** by their actuals: an absolute address or symbol as written,
//!   another instance's message cell (its DB member), a constant (reads give the member holding
//!   it, writes go to a dump member `HG_Dump*`). Unwired TIMER and COUNTER variables get free
//!   timer and counter numbers, used nowhere else in the group's code (listed in the FC's
//!   comment).
//! * **Local data.** The bytes of `L` that the user addresses are declared first in `VAR_TEMP`
//!   (`HG_User`, an array) and zeroed at the start of each call (§2.2); the generator's own
//!   temporaries follow, so they never overlap.
//! * **DB layout.** One `STRUCT` per instance, named like the instance, whose members are named
//!   like the graph's variables (predefined ones first, as `runtime.md` §2.7 names them;
//!   TIMER and COUNTER variables have no member), with the simulator's initial values; then
//!   the generator's data (`HG_` prefix). STEP 7's layout rules (BOOLs packed, everything else
//!   on a byte, 16- and 32-bit types and structures on an even byte, a structure's size even)
//!   are applied, and a structure of odd size gets an explicit `HG_Pad` byte so that Awlsim
//!   (which does not round a structure's size) lays the DB out the same way.
//!
//! Known differences from the simulator, none observable by a test or by the proof harness:
//! the `NOT` around a timer or counter operation in the RLO-0 pass also sets STA (which the
//! HiGraph subset cannot read); `FP`/`FN` on a formal wired to a constant, and a `CALL` output
//! wired to such a formal, write the member that holds the constant (the simulator discards
//! those writes).

use std::collections::{BTreeSet, HashMap, HashSet};
use std::fmt::Write as _;

use higraph_runtime::program::{
    Block, CellId, GraphId, Instr, OpCode, Operand, Origin, Place, Predef, Program, State, Target,
    TimeValue, Trans, VarIdx, Width,
};
use higraph_runtime::program::{CounterId, Graph, Instance, MemArea, TimerId};
use higraph_runtime::value::{Ty, Value};

use crate::sdf;

/// The mnemonic set of the generated statements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mnemonic {
    #[default]
    Simatic,
    International,
}

/// A block as the workspace names it: its number and, when the source names it by a symbol,
/// that symbol.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct BlockName {
    /// `FC`, `DB`, `SFC`, `FB`, ...
    pub kind: String,
    pub number: u32,
    pub symbol: Option<String>,
}

/// A global symbol the generated code may name (for the symbol table).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SymbolInfo {
    pub name: String,
    /// Absolute address in the build's mnemonics.
    pub address: String,
    pub ty: String,
    pub comment: String,
}

/// Where an operand is: the instruction's origin and a slot (0 the instruction's own operand,
/// `1 + i` the actual of the `i`-th `CALL` parameter).
pub type Slot = (Origin, u32);

/// What the analysis knows of the names behind a lowered group: everything the program itself
/// does not keep (how operands were written, block numbers, comments).
#[derive(Debug, Clone, Default)]
pub struct Names {
    /// The group's name and comment.
    pub group: String,
    pub comment: Option<String>,
    pub fc: BlockName,
    pub db: BlockName,
    /// Per instance of the group (run order): its comment.
    pub instance_comments: Vec<Option<String>>,
    /// Per instance: the instance's own cell of every variable (before wiring), by variable
    /// index.
    pub own_cells: Vec<Vec<CellId>>,
    /// `(instance, variable)` → the symbol its actual was written as.
    pub actual_symbols: HashMap<(u32, VarIdx), String>,
    /// Operands written as a symbol: the symbol's name.
    pub operand_symbols: HashMap<Slot, String>,
    /// Constant operands as written (`T#2S`, `W#16#FF`).
    pub literals: HashMap<Slot, String>,
    /// `wait`/`supervise` operands written as a symbol: (graph, state number, supervise).
    pub time_symbols: HashMap<(GraphId, u16, bool), String>,
    /// Per block of [`Program::blocks`]: the block called.
    pub blocks: Vec<BlockName>,
    /// `CALL FB n, DB m`: the instance data block, by the call's origin.
    pub call_dbs: HashMap<Origin, BlockName>,
    /// Global symbols by upper-case name.
    pub symbols: HashMap<String, SymbolInfo>,
    /// Per graph, per declared or predefined variable: its comment.
    pub var_comments: HashMap<(GraphId, VarIdx), String>,
}

/// What to generate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Options {
    pub absolute: bool,
    pub with_ob1: bool,
    pub mnemonic: Mnemonic,
}

/// The generated source (text with LF line ends; [`crate::cp1252::encode`] makes the file) and
/// the symbols it names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Output {
    pub text: String,
    pub symbols: Vec<sdf::Symbol>,
}

/// Why a group cannot be generated.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error(pub String);

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

// ---------------------------------------------------------------------------- DB layout

/// A member's position in the DB.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offset {
    pub byte: u32,
    pub bit: u8,
}

/// Lays out members in STEP 7 order: BOOLs packed bit by bit, BYTE/CHAR on the next byte,
/// everything else on the next even byte.
#[derive(Debug, Default, Clone)]
pub struct Layout {
    /// Position in bits.
    bits: u32,
}

impl Layout {
    pub fn new() -> Layout {
        Layout::default()
    }

    /// Places a member of type `ty`; its offset.
    pub fn place(&mut self, ty: Ty) -> Offset {
        match ty {
            Ty::Bool => {
                let at = Offset {
                    byte: self.bits / 8,
                    bit: (self.bits % 8) as u8,
                };
                self.bits += 1;
                at
            }
            Ty::Byte | Ty::Char => {
                self.align(8);
                let at = self.at();
                self.bits += 8;
                at
            }
            _ => {
                self.align(16);
                let at = self.at();
                self.bits += 8 * size_bytes(ty);
                at
            }
        }
    }

    /// Starts a structure (on an even byte).
    pub fn begin_struct(&mut self) -> Offset {
        self.align(16);
        self.at()
    }

    /// Whether the structure ending here would have an odd size (it needs a pad byte).
    pub fn needs_pad(&self) -> bool {
        self.bits.div_ceil(8) % 2 == 1
    }

    /// Ends a structure: its size rounds up to an even number of bytes.
    pub fn end_struct(&mut self) {
        self.align(16);
    }

    /// The size so far in bytes.
    pub fn size(&self) -> u32 {
        self.bits.div_ceil(8)
    }

    fn align(&mut self, to: u32) {
        self.bits = self.bits.div_ceil(to) * to;
    }

    fn at(&self) -> Offset {
        Offset {
            byte: self.bits / 8,
            bit: 0,
        }
    }
}

fn size_bytes(ty: Ty) -> u32 {
    match ty {
        Ty::Bool | Ty::Byte | Ty::Char => 1,
        Ty::Word | Ty::Int | Ty::S5Time | Ty::Date => 2,
        Ty::Dword | Ty::Dint | Ty::Real | Ty::Time | Ty::TimeOfDay => 4,
        Ty::DateAndTime => 8,
        Ty::String(n) => u32::from(n) + 2,
        Ty::Timer | Ty::Counter | Ty::OpState => 2,
    }
}

/// The STEP 7 name of a type in a declaration.
fn type_name(ty: Ty) -> String {
    match ty {
        Ty::TimeOfDay => "TIME_OF_DAY".to_owned(),
        other => other.to_string(),
    }
}

/// A member that the DB holds.
fn has_member(ty: Ty) -> bool {
    !matches!(ty, Ty::Timer | Ty::Counter | Ty::OpState)
}

/// An initial value in STEP 7 syntax (`None`: the type's zero needs no initial value).
fn initial(v: &Value) -> Option<String> {
    let text = match v {
        Value::Bool(b) => {
            if !*b {
                return None;
            }
            "TRUE".to_owned()
        }
        Value::Byte(b) => format!("B#16#{b:X}"),
        Value::Word(w) => format!("W#16#{w:X}"),
        Value::Dword(d) => format!("DW#16#{d:X}"),
        Value::Int(i) => i.to_string(),
        Value::Dint(i) => format!("L#{i}"),
        Value::Real(r) => format!("{r:e}").replace('e', "e+").replace("e+-", "e-"),
        Value::S5Time(p) => s5time(*p)?,
        Value::Time(ms) => time_literal(i64::from(*ms)),
        Value::Date(d) => format!("W#16#{d:X}"),
        Value::TimeOfDay(ms) => format!(
            "TOD#{}:{:02}:{:02}.{:03}",
            ms / 3_600_000,
            ms / 60_000 % 60,
            ms / 1000 % 60,
            ms % 1000
        ),
        Value::Char(c) => {
            if c.is_ascii_graphic() && *c != b'\'' {
                format!("'{}'", *c as char)
            } else {
                format!("B#16#{c:X}")
            }
        }
        Value::DateAndTime(_) | Value::String(_) | Value::OpState(_) => return None,
    };
    let zero = match v {
        Value::Real(r) => *r == 0.0 && r.is_sign_positive(),
        other => other.to_bits() == Some(0),
    };
    (!zero).then_some(text)
}

fn s5time(p: u16) -> Option<String> {
    let digits =
        u32::from(p & 0xF) + 10 * u32::from((p >> 4) & 0xF) + 100 * u32::from((p >> 8) & 0xF);
    let base = [10u32, 100, 1000, 10_000][usize::from((p >> 12) & 3)];
    Some(format!("S5T#{}MS", digits * base))
}

fn time_literal(ms: i64) -> String {
    if ms < 0 {
        format!("T#-{}MS", -ms)
    } else {
        format!("T#{ms}MS")
    }
}

// --------------------------------------------------------------------------- mnemonics

/// The name of an operation in the build's mnemonics.
fn op_name(op: OpCode, m: Mnemonic) -> &'static str {
    use OpCode::*;
    let (simatic, international) = match op {
        U => ("U", "A"),
        Un => ("UN", "AN"),
        O | OrNone => ("O", "O"),
        On => ("ON", "ON"),
        X => ("X", "X"),
        Xn => ("XN", "XN"),
        UParen => ("U(", "A("),
        UnParen => ("UN(", "AN("),
        OParen => ("O(", "O("),
        OnParen => ("ON(", "ON("),
        XParen => ("X(", "X("),
        XnParen => ("XN(", "XN("),
        Close => (")", ")"),
        Assign => ("=", "="),
        S => ("S", "S"),
        R => ("R", "R"),
        Set => ("SET", "SET"),
        Clr => ("CLR", "CLR"),
        Not => ("NOT", "NOT"),
        Fp => ("FP", "FP"),
        Fn => ("FN", "FN"),
        Si => ("SI", "SP"),
        Sv => ("SV", "SE"),
        Se => ("SE", "SD"),
        Ss => ("SS", "SS"),
        Sa => ("SA", "SF"),
        Fr => ("FR", "FR"),
        Zv => ("ZV", "CU"),
        Zr => ("ZR", "CD"),
        L => ("L", "L"),
        Lc => ("LC", "LC"),
        T => ("T", "T"),
        Tak => ("TAK", "TAK"),
        Push => ("PUSH", "PUSH"),
        Pop => ("POP", "POP"),
        Inc => ("INC", "INC"),
        Dec => ("DEC", "DEC"),
        AddInt | AddDint => ("+", "+"),
        Taw => ("TAW", "CAW"),
        Tad => ("TAD", "CAD"),
        Tar => ("TAR", "CAR"),
        Tar1 => ("TAR1", "TAR1"),
        Tar2 => ("TAR2", "TAR2"),
        Uw => ("UW", "AW"),
        Ow => ("OW", "OW"),
        Xow => ("XOW", "XOW"),
        Ud => ("UD", "AD"),
        Od => ("OD", "OD"),
        Xod => ("XOD", "XOD"),
        EqI => ("==I", "==I"),
        NeI => ("<>I", "<>I"),
        GtI => (">I", ">I"),
        LtI => ("<I", "<I"),
        GeI => (">=I", ">=I"),
        LeI => ("<=I", "<=I"),
        EqD => ("==D", "==D"),
        NeD => ("<>D", "<>D"),
        GtD => (">D", ">D"),
        LtD => ("<D", "<D"),
        GeD => (">=D", ">=D"),
        LeD => ("<=D", "<=D"),
        EqR => ("==R", "==R"),
        NeR => ("<>R", "<>R"),
        GtR => (">R", ">R"),
        LtR => ("<R", "<R"),
        GeR => (">=R", ">=R"),
        LeR => ("<=R", "<=R"),
        AddI => ("+I", "+I"),
        SubI => ("-I", "-I"),
        MulI => ("*I", "*I"),
        DivI => ("/I", "/I"),
        AddD => ("+D", "+D"),
        SubD => ("-D", "-D"),
        MulD => ("*D", "*D"),
        DivD => ("/D", "/D"),
        Mod => ("MOD", "MOD"),
        NegI => ("NEGI", "NEGI"),
        NegD => ("NEGD", "NEGD"),
        AddR => ("+R", "+R"),
        SubR => ("-R", "-R"),
        MulR => ("*R", "*R"),
        DivR => ("/R", "/R"),
        Abs => ("ABS", "ABS"),
        Sqr => ("SQR", "SQR"),
        Sqrt => ("SQRT", "SQRT"),
        Exp => ("EXP", "EXP"),
        Ln => ("LN", "LN"),
        Sin => ("SIN", "SIN"),
        Cos => ("COS", "COS"),
        Tan => ("TAN", "TAN"),
        Asin => ("ASIN", "ASIN"),
        Acos => ("ACOS", "ACOS"),
        Atan => ("ATAN", "ATAN"),
        NegR => ("NEGR", "NEGR"),
        Slw => ("SLW", "SLW"),
        Srw => ("SRW", "SRW"),
        Sld => ("SLD", "SLD"),
        Srd => ("SRD", "SRD"),
        Ssi => ("SSI", "SSI"),
        Ssd => ("SSD", "SSD"),
        Rld => ("RLD", "RLD"),
        Rrd => ("RRD", "RRD"),
        Rlda => ("RLDA", "RLDA"),
        Rrda => ("RRDA", "RRDA"),
        Bti => ("BTI", "BTI"),
        Btd => ("BTD", "BTD"),
        Itb => ("ITB", "ITB"),
        Dtb => ("DTB", "DTB"),
        Itd => ("ITD", "ITD"),
        Dtr => ("DTR", "DTR"),
        Invi => ("INVI", "INVI"),
        Invd => ("INVD", "INVD"),
        Rnd => ("RND", "RND"),
        RndPlus => ("RND+", "RND+"),
        RndMinus => ("RND-", "RND-"),
        Trunc => ("TRUNC", "TRUNC"),
        Call => ("CALL", "CALL"),
        Cc => ("CC", "CC"),
    };
    match m {
        Mnemonic::Simatic => simatic,
        Mnemonic::International => international,
    }
}

/// Glue operations whose names differ between the sets.
fn glue(name: &'static str, m: Mnemonic) -> &'static str {
    if m == Mnemonic::Simatic {
        return name;
    }
    match name {
        "U" => "A",
        "UN" => "AN",
        "SPB" => "JC",
        "SPBN" => "JCN",
        "SPA" => "JU",
        "SPL" => "JL",
        other => other,
    }
}

fn area_name(area: MemArea, width: Width, m: Mnemonic) -> String {
    let intl = m == Mnemonic::International;
    let letter = match area {
        MemArea::Input => {
            if intl {
                "I"
            } else {
                "E"
            }
        }
        MemArea::Output => {
            if intl {
                "Q"
            } else {
                "A"
            }
        }
        MemArea::Memory => "M",
        MemArea::Local => "L",
        MemArea::Db(_) => "DB",
    };
    let suffix = match (area, width) {
        (MemArea::Db(_), Width::Bit(_)) => "X",
        (_, Width::Bit(_)) => "",
        (_, Width::Byte) => "B",
        (_, Width::Word) => "W",
        (_, Width::Dword) => "D",
    };
    format!("{letter}{suffix}")
}

fn mem_text(area: MemArea, byte: u32, width: Width, m: Mnemonic) -> String {
    let name = area_name(area, width, m);
    let prefix = match area {
        MemArea::Db(n) => format!("DB{n}."),
        _ => String::new(),
    };
    match width {
        Width::Bit(b) => format!("{prefix}{name} {byte}.{b}"),
        _ => format!("{prefix}{name} {byte}"),
    }
}

/// The memory width of a type.
fn width_of(ty: Ty, bit: u8) -> Width {
    match ty {
        Ty::Bool => Width::Bit(bit),
        Ty::Byte | Ty::Char => Width::Byte,
        Ty::Word | Ty::Int | Ty::S5Time | Ty::Date => Width::Word,
        _ => Width::Dword,
    }
}

// ---------------------------------------------------------------------------- generator

/// Whether an operand is read or written by its operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Access {
    Read,
    Write,
}

/// The generator's temporaries (`VAR_TEMP`, after the user's local bytes).
const TEMPS: [(&str, Ty); 11] = [
    ("HG_A1", Ty::Dword),
    ("HG_A2", Ty::Dword),
    ("HG_Now", Ty::Time),
    ("HG_Dt", Ty::Dint),
    ("HG_SW", Ty::Word),
    ("HG_S", Ty::Word),
    ("HG_C", Ty::Word),
    ("HG_T", Ty::Word),
    ("HG_Fresh", Ty::Bool),
    ("HG_Blk", Ty::Bool),
    ("HG_Ok", Ty::Bool),
];

/// DB members of the generator (after the instances), in layout order.
const DB_GLUE: [(&str, Ty, &str); 6] = [
    ("HG_Last", Ty::Time, "TIME_TCK of the previous call"),
    ("HG_DumpD", Ty::Dword, "writes to constant actuals (32 bit)"),
    ("HG_DumpW", Ty::Word, "writes to constant actuals (16 bit)"),
    ("HG_DumpB", Ty::Byte, "writes to constant actuals (8 bit)"),
    (
        "HG_Init",
        Ty::Bool,
        "FALSE until the first call: a fresh DB",
    ),
    ("HG_DumpX", Ty::Bool, "writes to constant actuals (BOOL)"),
];

struct Gen<'a> {
    p: &'a Program,
    names: &'a Names,
    opt: Options,
    group: &'a higraph_runtime::program::Group,
    /// Cell → (instance, variable) of its owner.
    owner: HashMap<CellId, (u32, VarIdx)>,
    /// Per instance, per variable: DB offset (None: no member).
    offsets: Vec<Vec<Option<Offset>>>,
    glue_offsets: HashMap<&'static str, Offset>,
    /// Private timer / counter objects → their numbers.
    timers: HashMap<u32, u32>,
    counters: HashMap<u32, u32>,
    /// Local bytes the user addresses (the temporaries start here).
    user_local: u32,
    temp_offsets: HashMap<&'static str, Offset>,
    labels: u32,
    out: String,
    /// Symbols named (upper-case key → info), in first-use order.
    used_symbols: Vec<sdf::Symbol>,
    used_keys: HashSet<String>,
    /// The instance whose turn is being written.
    inst: u32,
    /// The shared entries into states the turn jumps to (state → label).
    entries: std::collections::BTreeMap<u16, String>,
    /// The last statement left RLO = 1 and /FC = 0 (a following glue `SET` is redundant).
    rlo_one: bool,
}

/// Generates the source of group `group` of `program`.
pub fn generate(
    program: &Program,
    group: u32,
    names: &Names,
    opt: Options,
) -> Result<Output, Error> {
    let g = program
        .groups
        .get(group as usize)
        .ok_or_else(|| Error(format!("no group {group} in the program")))?;
    if names.db.number == 0 || names.fc.number == 0 {
        return Err(Error(format!(
            "group {} has no `fc` and `db` block numbers",
            g.name
        )));
    }
    let mut w = Gen {
        p: program,
        names,
        opt,
        group: g,
        owner: HashMap::new(),
        offsets: Vec::new(),
        glue_offsets: HashMap::new(),
        timers: HashMap::new(),
        counters: HashMap::new(),
        user_local: 0,
        temp_offsets: HashMap::new(),
        labels: 0,
        out: String::new(),
        used_symbols: Vec::new(),
        used_keys: HashSet::new(),
        inst: 0,
        entries: std::collections::BTreeMap::new(),
        rlo_one: false,
    };
    // The FC and the DB lead the symbol table; they are not listed again.
    for b in [&names.fc, &names.db] {
        if let Some(sym) = &b.symbol {
            w.used_keys.insert(sym.to_ascii_uppercase());
        }
    }
    w.prepare()?;
    let fc_body = w.fc_body()?;
    let mut text = String::new();
    text.push_str(&w.db_source());
    text.push('\n');
    text.push_str(&w.fc_source(&fc_body));
    if opt.with_ob1 {
        text.push('\n');
        text.push_str(&w.ob1_source());
    }
    // The FC and the DB first in the symbol table.
    let mut symbols = Vec::new();
    if !opt.absolute {
        for (b, ty) in [(&names.fc, "FC"), (&names.db, "DB")] {
            if let Some(sym) = &b.symbol {
                symbols.push(sdf::Symbol {
                    name: sym.clone(),
                    address: format!("{ty} {}", b.number),
                    ty: format!("{ty} {}", b.number),
                    comment: names
                        .symbols
                        .get(&sym.to_ascii_uppercase())
                        .map(|s| s.comment.clone())
                        .unwrap_or_default(),
                });
            }
        }
        symbols.extend(w.used_symbols.iter().cloned());
    }
    Ok(Output { text, symbols })
}

impl<'a> Gen<'a> {
    fn graph(&self, inst: &Instance) -> Result<&'a Graph, Error> {
        self.p
            .graphs
            .get(inst.graph as usize)
            .ok_or_else(|| Error(format!("instance {} names no graph", inst.name)))
    }

    /// Owners, DB layout, private objects, local bytes.
    fn prepare(&mut self) -> Result<(), Error> {
        let mut layout = Layout::new();
        for (i, inst) in self.group.instances.iter().enumerate() {
            let graph = self.graph(inst)?;
            let own = self.names.own_cells.get(i);
            layout.begin_struct();
            let mut offs = Vec::new();
            for (v, var) in graph.vars.iter().enumerate() {
                if let Some(&cell) = own.and_then(|o| o.get(v)) {
                    self.owner.insert(cell, (i as u32, v as VarIdx));
                }
                offs.push(has_member(var.ty).then(|| layout.place(var.ty)));
            }
            if layout.needs_pad() {
                layout.place(Ty::Byte);
            }
            layout.end_struct();
            self.offsets.push(offs);
        }
        for (name, ty, _) in DB_GLUE {
            self.glue_offsets.insert(name, layout.place(ty));
        }
        // Timer and counter numbers the group names.
        let mut timers = BTreeSet::new();
        let mut counters = BTreeSet::new();
        let mut local_end = 0u32;
        let mut see = |place: &Place| match place {
            Place::Timer(t) => {
                timers.insert(t.0);
            }
            Place::Counter(c) => {
                counters.insert(c.0);
            }
            Place::Mem {
                area: MemArea::Local,
                byte,
                width,
            } => {
                let size = match width {
                    Width::Bit(_) | Width::Byte => 1,
                    Width::Word => 2,
                    Width::Dword => 4,
                };
                local_end = local_end.max(byte + size);
            }
            _ => {}
        };
        for inst in &self.group.instances {
            for place in &inst.binding {
                see(place);
            }
            let graph = self.graph(inst)?;
            for_each_instr(graph, |ins| {
                visit_operand(&ins.operand, &mut see);
            });
            for st in &graph.states {
                for tv in [&st.wait, &st.supervise].into_iter().flatten() {
                    if let TimeValue::Operand(op) = tv {
                        visit_operand(op, &mut see);
                    }
                }
            }
        }
        let mut next = 0u32;
        for &t in timers.iter().filter(|&&t| t >= 65536) {
            while timers.contains(&next) {
                next += 1;
            }
            self.timers.insert(t, next);
            next += 1;
        }
        let mut next = 0u32;
        for &c in counters.iter().filter(|&&c| c >= 65536) {
            while counters.contains(&next) {
                next += 1;
            }
            self.counters.insert(c, next);
            next += 1;
        }
        self.user_local = local_end.div_ceil(2) * 2;
        let mut tl = Layout {
            bits: self.user_local * 8,
        };
        for (name, ty) in TEMPS {
            self.temp_offsets.insert(name, tl.place(ty));
        }
        Ok(())
    }

    // ------------------------------------------------------------------ operands

    fn sym(&mut self, name: &str) -> String {
        let key = name.to_ascii_uppercase();
        if self.used_keys.insert(key.clone())
            && let Some(info) = self.names.symbols.get(&key)
        {
            self.used_symbols.push(sdf::Symbol {
                name: info.name.clone(),
                address: info.address.clone(),
                ty: info.ty.clone(),
                comment: info.comment.clone(),
            });
        }
        format!("\"{name}\"")
    }

    fn db_symbolic(&self) -> Option<&'a str> {
        if self.opt.absolute {
            None
        } else {
            self.names.db.symbol.as_deref()
        }
    }

    /// A member of the DB: `"DB".Inst.Var` or `DBn.DBX b.x`.
    fn member(&mut self, inst: u32, var: VarIdx) -> Result<String, Error> {
        let i = self
            .group
            .instances
            .get(inst as usize)
            .ok_or_else(|| Error(format!("no instance {inst}")))?;
        let graph = self.graph(i)?;
        let info = graph
            .vars
            .get(var as usize)
            .ok_or_else(|| Error(format!("no variable {var} in graph {}", graph.name)))?;
        let off = self.offsets[inst as usize][var as usize]
            .ok_or_else(|| Error(format!("{}.{} has no DB member", i.name, info.name)))?;
        Ok(match self.db_symbolic() {
            Some(db) => {
                let db = self.sym(db);
                format!("{db}.{}.{}", i.name, info.name)
            }
            None => note(
                mem_text(
                    MemArea::Db(self.names.db.number as u16),
                    off.byte,
                    width_of(info.ty, off.bit),
                    self.opt.mnemonic,
                ),
                &format!("{}.{}", i.name, info.name),
            ),
        })
    }

    fn glue_member(&mut self, name: &'static str) -> String {
        match self.db_symbolic() {
            Some(db) => {
                let db = self.sym(db);
                format!("{db}.{name}")
            }
            None => {
                let off = self.glue_offsets[name];
                let ty = DB_GLUE
                    .iter()
                    .find(|g| g.0 == name)
                    .map_or(Ty::Bool, |g| g.1);
                note(
                    mem_text(
                        MemArea::Db(self.names.db.number as u16),
                        off.byte,
                        width_of(ty, off.bit),
                        self.opt.mnemonic,
                    ),
                    name,
                )
            }
        }
    }

    fn temp(&self, name: &'static str) -> String {
        if self.opt.absolute {
            let off = self.temp_offsets[name];
            let ty = TEMPS.iter().find(|t| t.0 == name).map_or(Ty::Bool, |t| t.1);
            note(
                mem_text(
                    MemArea::Local,
                    off.byte,
                    width_of(ty, off.bit),
                    self.opt.mnemonic,
                ),
                name,
            )
        } else {
            format!("#{name}")
        }
    }

    fn place_text(
        &mut self,
        place: &Place,
        written: Option<&str>,
        access: Access,
        own: Option<(u32, VarIdx)>,
        ty: Option<Ty>,
    ) -> Result<String, Error> {
        let global = matches!(
            place,
            Place::Mem { .. } | Place::Timer(_) | Place::Counter(_)
        );
        if let Some(sym) = written
            && global
        {
            if !self.opt.absolute {
                return Ok(self.sym(sym));
            }
            let text = self.place_text(place, None, access, own, ty)?;
            return Ok(note(text, &format!("\"{sym}\"")));
        }
        if let (Place::Timer(TimerId(n)) | Place::Counter(CounterId(n)), Some((i, v))) =
            (place, own)
            && *n >= 65536
        {
            let text = self.place_text(place, None, access, None, ty)?;
            let inst = &self.group.instances[i as usize];
            let var = self
                .graph(inst)?
                .vars
                .get(v as usize)
                .map_or("", |var| var.name.as_str());
            return Ok(note(text, &format!("{}.{var}", inst.name)));
        }
        Ok(match place {
            Place::Mem { area, byte, width } => mem_text(*area, *byte, *width, self.opt.mnemonic),
            Place::Cell(c) => {
                let (i, v) = *self
                    .owner
                    .get(c)
                    .ok_or_else(|| Error(format!("cell {c} belongs to no instance")))?;
                self.member(i, v)?
            }
            Place::Timer(t) => {
                let n = self.timers.get(&t.0).copied().unwrap_or(t.0);
                format!("T {n}")
            }
            Place::Counter(c) => {
                let n = self.counters.get(&c.0).copied().unwrap_or(c.0);
                let z = if self.opt.mnemonic == Mnemonic::International {
                    "C"
                } else {
                    "Z"
                };
                format!("{z} {n}")
            }
            Place::Const(v) => match (access, own) {
                (Access::Read, Some((i, var))) => self.member(i, var)?,
                (Access::Read, None) => {
                    return Err(Error("a constant place outside an instance".into()));
                }
                (Access::Write, _) => {
                    let ty = ty.unwrap_or(v.ty());
                    let name = match ty.bits() {
                        Some(1) => "HG_DumpX",
                        Some(8) => "HG_DumpB",
                        Some(16) => "HG_DumpW",
                        _ => "HG_DumpD",
                    };
                    self.glue_member(name)
                }
            },
        })
    }

    /// The text of an instruction's operand (slot 0) or a call parameter's actual.
    fn operand_text(
        &mut self,
        op: OpCode,
        operand: &Operand,
        slot: Slot,
        access: Access,
    ) -> Result<String, Error> {
        let inst = &self.group.instances[self.inst as usize];
        Ok(match operand {
            Operand::None | Operand::Call(_) => String::new(),
            Operand::Imm(bits) => match self.names.literals.get(&slot) {
                Some(text) => short_literal(text),
                None => imm_text(op, *bits),
            },
            Operand::Var(v) => {
                let place = inst
                    .binding
                    .get(*v as usize)
                    .ok_or_else(|| Error(format!("no binding for variable {v}")))?
                    .clone();
                let written = self.names.actual_symbols.get(&(self.inst, *v)).cloned();
                let ty = self.graph(inst)?.vars.get(*v as usize).map(|var| var.ty);
                self.place_text(
                    &place,
                    written.as_deref(),
                    access,
                    Some((self.inst, *v)),
                    ty,
                )?
            }
            Operand::Place(place) => {
                let written = self.names.operand_symbols.get(&slot).cloned();
                self.place_text(place, written.as_deref(), access, None, None)?
            }
        })
    }

    // ------------------------------------------------------------------- emitting

    fn label(&mut self) -> String {
        self.labels += 1;
        let n = self.labels;
        if n < 1000 {
            format!("M{n:03}")
        } else {
            // Letter + three base-36 digits: plenty for any group.
            const D: &[u8; 36] = b"0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ";
            let letters = b"NPQRSUVWXY";
            let hi = (n / 46_656) as usize;
            let lo = n % 46_656;
            format!(
                "{}{}{}{}",
                letters[hi % letters.len()] as char,
                D[(lo / 1296) as usize] as char,
                D[(lo / 36 % 36) as usize] as char,
                D[(lo % 36) as usize] as char
            )
        }
    }

    fn line(&mut self, op: &str, operand: &str) {
        self.rlo_one = false;
        self.out.push_str(&statement(op, operand));
    }

    /// A glue statement. A `SET` is left out when the RLO is known to be 1 with /FC = 0
    /// already (right after a `SET` and the `S`, `R`, `=` that follow it).
    fn g(&mut self, op: &'static str, operand: &str) {
        if op == "SET" && self.rlo_one {
            return;
        }
        let was = self.rlo_one;
        self.line(glue(op, self.opt.mnemonic), operand);
        self.rlo_one = op == "SET" || (was && matches!(op, "S" | "R" | "="));
    }

    fn put_label(&mut self, label: &str) {
        self.rlo_one = false;
        let _ = writeln!(self.out, "{label}: NOP   0;");
    }

    fn comment(&mut self, text: &str) {
        let _ = writeln!(self.out, "// {}", one_line(text));
    }

    fn save(&mut self) {
        let (a1, a2, sw) = (self.temp("HG_A1"), self.temp("HG_A2"), self.temp("HG_SW"));
        self.g("T", &a1);
        self.g("TAK", "");
        self.g("T", &a2);
        self.g("L", "STW");
        self.g("T", &sw);
    }

    fn restore(&mut self) {
        let (a1, a2, sw) = (self.temp("HG_A1"), self.temp("HG_A2"), self.temp("HG_SW"));
        self.g("L", &sw);
        self.g("T", "STW");
        self.g("L", &a2);
        self.g("L", &a1);
    }

    /// A predefined variable of the running instance, for reading or writing.
    fn pv(&mut self, p: Predef, access: Access) -> Result<String, Error> {
        self.operand_text(OpCode::U, &Operand::Var(p.var()), (Origin::NONE, 0), access)
    }

    /// `SET; U bits...` then `SPB`/`SPBN` — bit-only glue.
    fn set_bit(&mut self, p: Predef, value: bool) -> Result<(), Error> {
        let t = self.pv(p, Access::Write)?;
        self.g("SET", "");
        self.g(if value { "S" } else { "R" }, &t);
        Ok(())
    }

    /// One user block (§3.1): `SET` (RLO-0 pass: `CLR`), then its instructions.
    fn block(&mut self, blk: &Block, rlo0: bool) -> Result<(), Error> {
        if blk.code.is_empty() {
            return Ok(());
        }
        self.g(if rlo0 { "CLR" } else { "SET" }, "");
        let mut shadowed = rlo0;
        for ins in &blk.code {
            let flip = shadowed && self.is_timer_or_counter_op(ins);
            if flip {
                self.g("NOT", "");
            }
            self.instr(ins)?;
            if flip {
                self.g("NOT", "");
            }
            if shadowed && ins.op.replaces_rlo() {
                shadowed = false;
            }
        }
        Ok(())
    }

    fn blocks(&mut self, blks: &[Block], rlo0: bool, what: &str) -> Result<(), Error> {
        if blks.iter().any(|b| !b.code.is_empty()) {
            self.comment(what);
        }
        for b in blks {
            self.block(b, rlo0)?;
        }
        Ok(())
    }

    fn is_timer_or_counter_op(&self, ins: &Instr) -> bool {
        use OpCode::*;
        match ins.op {
            Si | Sv | Se | Ss | Sa | Fr | Zv | Zr => true,
            S | R => {
                let place = match &ins.operand {
                    Operand::Var(v) => self.group.instances[self.inst as usize]
                        .binding
                        .get(*v as usize),
                    Operand::Place(p) => Some(p),
                    _ => None,
                };
                matches!(place, Some(Place::Timer(_) | Place::Counter(_)))
            }
            _ => false,
        }
    }

    fn instr(&mut self, ins: &Instr) -> Result<(), Error> {
        use OpCode::*;
        let name = op_name(ins.op, self.opt.mnemonic);
        if let Operand::Call(call) = &ins.operand {
            let block = self
                .names
                .blocks
                .get(call.block as usize)
                .cloned()
                .ok_or_else(|| Error(format!("no block {}", call.block)))?;
            let mut target = match (&block.symbol, self.opt.absolute) {
                (Some(sym), false) => self.sym(sym),
                _ => format!("{} {}", block.kind, block.number),
            };
            if let Some(idb) = self.names.call_dbs.get(&ins.origin).cloned() {
                let idb = match (&idb.symbol, self.opt.absolute) {
                    (Some(sym), false) => self.sym(sym),
                    _ => format!("{} {}", idb.kind, idb.number),
                };
                target = format!("{target}, {idb}");
            }
            if call.params.is_empty() || ins.op == Cc {
                self.line(name, &target);
                return Ok(());
            }
            let mut params = Vec::new();
            for (k, (formal, actual)) in call.params.iter().enumerate() {
                // Read: a constant actual passes the member holding it.
                let text =
                    self.operand_text(L, actual, (ins.origin, k as u32 + 1), Access::Read)?;
                params.push((formal.clone(), text));
            }
            self.rlo_one = false;
            let _ = writeln!(self.out, "      {name:<5} {target} (");
            let n = params.len();
            for (k, (formal, text)) in params.into_iter().enumerate() {
                let end = if k + 1 == n { ");" } else { "," };
                let _ = writeln!(self.out, "           {formal:<24} := {}{end}", bare(&text));
            }
            return Ok(());
        }
        let access = match ins.op {
            Assign | T => Access::Write,
            S | R => match &ins.operand {
                Operand::Var(v) => match self.group.instances[self.inst as usize]
                    .binding
                    .get(*v as usize)
                {
                    Some(Place::Timer(_) | Place::Counter(_)) => Access::Read,
                    _ => Access::Write,
                },
                _ => Access::Write,
            },
            _ => Access::Read,
        };
        let operand = self.operand_text(ins.op, &ins.operand, (ins.origin, 0), access)?;
        self.line(name, &operand);
        Ok(())
    }

    // ------------------------------------------------------------------ the FC

    fn fc_body(&mut self) -> Result<String, Error> {
        let m = self.opt.mnemonic;
        let _ = m;
        // Call start (§2.2, and Δ from the CPU clock).
        self.rlo_one = false;
        let _ = writeln!(self.out, "NETWORK");
        let _ = writeln!(self.out, "TITLE = group call: clock, fresh DB, INIT_SD");
        let now = self.temp("HG_Now");
        let dt = self.temp("HG_Dt");
        let last = self.glue_member("HG_Last");
        let init = self.glue_member("HG_Init");
        let fresh = self.temp("HG_Fresh");
        self.rlo_one = false;
        let _ = writeln!(self.out, "      CALL  SFC 64 (");
        let _ = writeln!(
            self.out,
            "           RET_VAL                  := {});",
            bare(&now)
        );
        self.g("L", &now);
        self.g("L", &last);
        self.g("-D", "");
        self.g("T", &dt);
        self.g("L", "L#0");
        self.g(">=D", "");
        let ok = self.label();
        self.g("SPB", &ok);
        self.g("L", &dt);
        self.g("L", "L#2147483647");
        self.g("+D", "");
        self.g("+", "L#1");
        self.g("T", &dt);
        self.put_label(&ok);
        self.g("L", &now);
        self.g("T", &last);
        self.g("SET", "");
        self.g("UN", &init);
        self.g("=", &fresh);
        self.g("SET", "");
        self.g("=", &init);
        // Step 1: registers and local data := 0.
        if self.user_local > 0 {
            self.comment("local data of the graphs := 0");
            self.g("L", "0");
            let mut b = 0;
            while b < self.user_local {
                let (w, size) = if b + 4 <= self.user_local {
                    (Width::Dword, 4)
                } else {
                    (Width::Word, 2)
                };
                let t = mem_text(MemArea::Local, b, w, self.opt.mnemonic);
                self.g("T", &t);
                b += size;
            }
        }
        self.g("L", "0");
        self.g("T", "STW");
        self.g("L", "0");
        // Step 2: INIT_SD.
        // The FC's parameter is named in both modes (parameters have no absolute address).
        let init_sd = "#INIT_SD".to_owned();
        for i in 0..self.group.instances.len() {
            self.inst = i as u32;
            let t = self.pv(Predef::InitSd, Access::Write)?;
            self.g("U", &init_sd);
            self.g("=", &t);
        }
        // Step 3: a fresh DB resets the internal incoming messages.
        if !self.group.internal_messages.is_empty() {
            self.comment("fresh DB: internal incoming messages := 0");
            self.g("SET", "");
            self.g("U", &fresh);
            for msg in self.group.internal_messages.clone() {
                let t = self.place_text(&Place::Cell(msg.cell), None, Access::Write, None, None)?;
                self.g("R", &t);
            }
        }
        // Step 4.
        for i in 0..self.group.instances.len() {
            self.inst = i as u32;
            self.turn()?;
        }
        Ok(std::mem::take(&mut self.out))
    }

    /// One instance turn (§2.3), as `Turn::run`.
    fn turn(&mut self) -> Result<(), Error> {
        let inst = &self.group.instances[self.inst as usize];
        let graph = self.graph(inst)?;
        self.rlo_one = false;
        let _ = writeln!(self.out, "NETWORK");
        let title = match self.names.instance_comments.get(self.inst as usize) {
            Some(Some(c)) => format!("{} : {} \"{}\"", inst.name, graph.name, one_line(c)),
            _ => format!("{} : {}", inst.name, graph.name),
        };
        let _ = writeln!(self.out, "TITLE = {}", one_line(&title));
        let (hs, hc, fresh) = (self.temp("HG_S"), self.temp("HG_C"), self.temp("HG_Fresh"));
        // s, step 0.
        self.save();
        let cs = self.pv(Predef::CurrentState, Access::Read)?;
        self.g("L", &cs);
        self.g("T", &hs);
        self.g("T", &hc);
        self.set_bit(Predef::StateChange, false)?;
        let t0 = self.label();
        self.g("SET", "");
        self.g("U", &fresh);
        self.g("SPB", &t0);
        self.update_time(
            Predef::WtValid,
            Predef::WtStop,
            Predef::WtCurrValue,
            Predef::WtExpired,
        )?;
        self.update_time(
            Predef::StValid,
            Predef::StStop,
            Predef::StCurrValue,
            Predef::StExpired,
        )?;
        self.put_label(&t0);
        self.restore();
        // Step 1.
        self.blocks(&graph.permanent_pre, false, "permanent C-")?;
        let step8 = self.label();
        let not_fresh = self.label();
        self.g("SET", "");
        self.g("U", &fresh);
        self.g("SPBN", &not_fresh);
        // Step 2: the initial entry.
        let d = graph.initial.unwrap_or(0);
        self.comment(&format!("fresh DB: initial entry into state {d}"));
        self.save();
        self.enter_front(ChangeKind::Initial)?;
        self.jump_to_entry(graph, Target::State(d), &step8);
        self.put_label(&not_fresh);
        // Step 3: any-transitions.
        let blk = self.temp("HG_Blk");
        self.g("SET", "");
        self.g("R", &blk);
        let step4 = self.label();
        let blocked = self.label();
        let mut firings: Vec<(String, &Trans, bool)> = Vec::new();
        for (i, t) in graph.any.iter().enumerate() {
            let no = self.label();
            let fire = self.label();
            self.comment(&format!("any->{} prio {}", target_text(t.to), t.prio));
            self.eligible(graph, t, &no)?;
            if self.group.options.any_once {
                // Blocked when the target is s.
                self.save();
                match t.to {
                    Target::State(n) => {
                        self.g("L", &hs);
                        self.g("L", &format!("L#{n}"));
                    }
                    Target::Return => {
                        let ht = self.temp("HG_T");
                        self.g("L", &hs);
                        self.g("L", &ht);
                    }
                }
                self.g("==D", "");
                self.g("=", &blk);
                self.restore();
                self.g("SET", "");
                self.g("U", &blk);
                self.g("SPB", &blocked);
            }
            self.g("SPA", &fire);
            self.put_label(&no);
            firings.push((fire, t, graph.startup == Some(i)));
        }
        self.g("SPA", &step4);
        self.put_label(&blocked);
        self.g("SET", "");
        self.g("S", &blk);
        // Step 4: C- of s and its transitions.
        self.put_label(&step4);
        let states: Vec<&State> = graph
            .states
            .iter()
            .filter(|st| st.pre.iter().any(|b| !b.code.is_empty()) || !st.transitions.is_empty())
            .collect();
        let any_once = self.group.options.any_once;
        let mut state_firings: Vec<(String, &Trans, u16)> = Vec::new();
        self.dispatch(&hs, &states, &step8, |w, st| {
            w.blocks(&st.pre, false, &format!("state {} C-", st.number))?;
            if any_once {
                w.g("SET", "");
                w.g("U", &blk);
                w.g("SPB", &step8);
            }
            for t in &st.transitions {
                let no = w.label();
                let fire = w.label();
                w.comment(&format!(
                    "{}->{} prio {}",
                    st.number,
                    target_text(t.to),
                    t.prio
                ));
                w.eligible(graph, t, &no)?;
                w.g("SPA", &fire);
                w.put_label(&no);
                state_firings.push((fire, t, st.number));
            }
            Ok(())
        })?;
        // Steps 5–7: the firings.
        for (fire, t, startup) in firings {
            self.put_label(&fire);
            self.comment(&format!("fire any->{} prio {}", target_text(t.to), t.prio));
            self.blocks(&t.actions, false, "!")?;
            // C (RLO 0) and X of s, whichever state s is.
            let with_exit: Vec<&State> = graph
                .states
                .iter()
                .filter(|st| {
                    (self.group.options.cyclic_rlo0 && st.cyclic.iter().any(|b| !b.code.is_empty()))
                        || st.exit.iter().any(|b| !b.code.is_empty())
                })
                .collect();
            let cont = self.label();
            self.dispatch(&hs, &with_exit, &cont, |w, st| w.leave(st))?;
            self.put_label(&cont);
            let kind = if startup {
                ChangeKind::Startup
            } else {
                ChangeKind::Normal
            };
            self.save();
            self.enter_front(kind)?;
            self.jump_to_entry(graph, t.to, &step8);
        }
        for (fire, t, from) in state_firings {
            self.put_label(&fire);
            self.comment(&format!(
                "fire {}->{} prio {}",
                from,
                target_text(t.to),
                t.prio
            ));
            self.blocks(&t.actions, false, "!")?;
            if let Some(st) = graph.states.iter().find(|s| s.number == from) {
                self.leave(st)?;
            }
            self.save();
            self.enter_front(ChangeKind::Normal)?;
            self.jump_to_entry(graph, t.to, &step8);
        }
        self.entries(graph, &step8)?;
        // Step 8: C of the current state.
        self.put_label(&step8);
        let cyclic: Vec<&State> = graph
            .states
            .iter()
            .filter(|st| st.cyclic.iter().any(|b| !b.code.is_empty()))
            .collect();
        let step9 = self.label();
        self.dispatch(&hc, &cyclic, &step9, |w, st| {
            w.blocks(&st.cyclic, false, &format!("state {} C", st.number))
        })?;
        self.put_label(&step9);
        // Step 9.
        self.blocks(&graph.permanent_post, false, "permanent C")?;
        Ok(())
    }

    /// Inside a save: jumps by the state number in the WORD `var` to the label of its entry
    /// in `targets`, or to `default`. A jump list (`SPL`) when every number is below 255,
    /// else a chain of comparisons.
    fn jump_by_state(&mut self, var: &str, targets: &[(u16, String)], default: &str) {
        let max = targets.iter().map(|t| t.0).max().unwrap_or(0);
        if targets.is_empty() {
            self.g("SPA", default);
        } else if max < 255 {
            // A jump list holds at most 255 jumps: numbers 0..=max, above max the default.
            let list_end = self.label();
            // As a DINT: the WORD zero-extended, so 32768.. is not negative.
            self.g("L", var);
            self.g("L", &format!("L#{max}"));
            self.g(">D", "");
            self.g("SPB", default);
            self.g("L", var);
            self.g("SPL", &list_end);
            for n in 0..=max {
                match targets.iter().find(|t| t.0 == n) {
                    Some((_, l)) => {
                        let l = l.clone();
                        self.g("SPA", &l);
                    }
                    None => self.g("SPA", default),
                }
            }
            let op = glue("SPA", self.opt.mnemonic);
            self.rlo_one = false;
            let _ = writeln!(self.out, "{list_end}: {op:<5} {default};");
        } else {
            for (n, l) in targets {
                self.g("L", var);
                self.g("L", &format!("L#{n}"));
                self.g("==D", "");
                let l = l.clone();
                self.g("SPB", &l);
            }
            self.g("SPA", default);
        }
    }

    /// Jumps by the state number in `var` to the code `body` writes for each of `states`,
    /// which then continues at `cont`; other numbers go straight to `cont`. Registers are
    /// saved around the jump list and restored before each body.
    fn dispatch<'s, F>(
        &mut self,
        var: &str,
        states: &[&'s State],
        cont: &str,
        mut body: F,
    ) -> Result<(), Error>
    where
        F: FnMut(&mut Self, &'s State) -> Result<(), Error>,
    {
        if states.is_empty() {
            self.g("SPA", cont);
            return Ok(());
        }
        let labels: Vec<String> = states.iter().map(|_| self.label()).collect();
        let dflt = self.label();
        self.save();
        let targets: Vec<(u16, String)> = states
            .iter()
            .zip(&labels)
            .map(|(st, l)| (st.number, l.clone()))
            .collect();
        self.jump_by_state(var, &targets, &dflt);
        self.put_label(&dflt);
        self.restore();
        self.g("SPA", cont);
        for (k, st) in states.iter().enumerate() {
            let l = labels[k].clone();
            self.put_label(&l);
            self.restore();
            body(self, st)?;
            self.g("SPA", cont);
        }
        Ok(())
    }

    /// §2.6 update of one time (inside a save).
    fn update_time(
        &mut self,
        valid: Predef,
        stop: Predef,
        curr: Predef,
        expired: Predef,
    ) -> Result<(), Error> {
        let skip = self.label();
        let (v, s) = (self.pv(valid, Access::Read)?, self.pv(stop, Access::Read)?);
        let c = self.pv(curr, Access::Read)?;
        let cw = self.pv(curr, Access::Write)?;
        let vw = self.pv(valid, Access::Write)?;
        let ew = self.pv(expired, Access::Write)?;
        let dt = self.temp("HG_Dt");
        self.g("SET", "");
        self.g("U", &v);
        self.g("UN", &s);
        self.g("SPBN", &skip);
        self.g("L", &c);
        self.g("L", &dt);
        self.g(">D", "");
        let zero = self.label();
        self.g("SPBN", &zero);
        self.g("-D", "");
        self.g("T", &cw);
        self.g("SPA", &skip);
        self.put_label(&zero);
        self.g("L", "L#0");
        self.g("T", &cw);
        self.g("SET", "");
        self.g("R", &vw);
        self.g("S", &ew);
        self.put_label(&skip);
        Ok(())
    }

    /// §2.4: falls through when `t` is eligible, jumps to `no` otherwise. For a return
    /// transition the target is left in `#HG_T`.
    fn eligible(&mut self, graph: &Graph, t: &Trans, no: &str) -> Result<(), Error> {
        if t.auto {
            let a = self.pv(Predef::AutomaticMode, Access::Read)?;
            self.g("SET", "");
            self.g("U", &a);
            self.g("SPBN", no);
        }
        if t.manual {
            let a = self.pv(Predef::ManualMode, Access::Read)?;
            self.g("SET", "");
            self.g("U", &a);
            self.g("SPBN", no);
        }
        if t.waits {
            let v = self.pv(Predef::WtValid, Access::Read)?;
            let e = self.pv(Predef::WtExpired, Access::Read)?;
            self.g("SET", "");
            self.g("U", &v);
            self.g("UN", &e);
            self.g("SPB", no);
        }
        if t.to == Target::Return {
            // PreviousState must be a state of the graph: a jump list over its states.
            let prev = self.pv(Predef::PreviousState, Access::Read)?;
            let ht = self.temp("HG_T");
            let ok = self.temp("HG_Ok");
            let (yes, done) = (self.label(), self.label());
            self.save();
            self.g("L", &prev);
            self.g("T", &ht);
            self.g("SET", "");
            self.g("R", &ok);
            let targets: Vec<(u16, String)> = graph
                .states
                .iter()
                .map(|st| (st.number, yes.clone()))
                .collect();
            self.jump_by_state(&ht, &targets, &done);
            self.put_label(&yes);
            self.g("SET", "");
            self.g("S", &ok);
            self.put_label(&done);
            self.restore();
            self.g("SET", "");
            self.g("U", &ok);
            self.g("SPBN", no);
        }
        for blk in &t.conditions {
            if blk.code.is_empty() {
                continue;
            }
            self.block(blk, false)?;
            self.g("SPBN", no);
        }
        Ok(())
    }

    /// §2.5 steps 2–3 for the state being left: `C` with RLO 0 (`cyclic_rlo0`), then `X`.
    fn leave(&mut self, st: &State) -> Result<(), Error> {
        if self.group.options.cyclic_rlo0 {
            self.blocks(&st.cyclic, true, &format!("state {} C, RLO 0", st.number))?;
        }
        self.blocks(&st.exit, false, &format!("state {} X", st.number))
    }

    /// §2.5 step 4, the part that does not depend on the target: ST_ExpiredPrev and
    /// PreviousState.
    fn enter_front(&mut self, kind: ChangeKind) -> Result<(), Error> {
        let hs = self.temp("HG_S");
        let prev = self.pv(Predef::PreviousState, Access::Write)?;
        let sep = self.pv(Predef::StExpiredPrev, Access::Write)?;
        match kind {
            ChangeKind::Initial => {
                self.g("SET", "");
                self.g("R", &sep);
                self.g("L", "0");
                self.g("T", &prev);
            }
            ChangeKind::Startup => {
                self.g("L", &hs);
                self.g("T", &prev);
            }
            ChangeKind::Normal => {
                let se = self.pv(Predef::StExpired, Access::Read)?;
                self.g("SET", "");
                self.g("U", &se);
                self.g("=", &sep);
                self.g("L", &hs);
                self.g("T", &prev);
            }
        }
        Ok(())
    }

    /// Inside a save: jumps to the entry into a transition's target (by `#HG_T` for a
    /// return), noting which entries the turn needs.
    fn jump_to_entry(&mut self, graph: &Graph, to: Target, step8: &str) {
        match to {
            Target::State(d) => {
                let l = self.entry_label(d);
                self.g("SPA", &l);
            }
            Target::Return => {
                let ht = self.temp("HG_T");
                let targets: Vec<(u16, String)> = graph
                    .states
                    .iter()
                    .map(|st| (st.number, self.entry_label(st.number)))
                    .collect();
                let bad = self.label();
                self.jump_by_state(&ht, &targets, &bad);
                self.put_label(&bad);
                self.restore();
                self.g("SPA", step8);
            }
        }
    }

    /// The label of the shared entry into state `d` of the running turn.
    fn entry_label(&mut self, d: u16) -> String {
        if let Some(l) = self.entries.get(&d) {
            return l.clone();
        }
        let l = self.label();
        self.entries.insert(d, l.clone());
        l
    }

    /// The shared entries of the turn: each starts inside a save, does §2.5 step 4 for its
    /// state `d` (CurrentState, StateChange, UsrMsgSend, the times; `#HG_C` := d), restores,
    /// runs steps 6–7 (`E`, `C-` with `precyclic_on_entry`) and continues at step 8.
    fn entries(&mut self, graph: &Graph, step8: &str) -> Result<(), Error> {
        let entries = std::mem::take(&mut self.entries);
        for (d, label) in entries {
            self.put_label(&label);
            self.comment(&format!("entry into state {d}"));
            self.enter_state(graph, d)?;
            self.g("SPA", step8);
        }
        Ok(())
    }

    fn enter_state(&mut self, graph: &Graph, d: u16) -> Result<(), Error> {
        let st = graph.states.iter().find(|s| s.number == d);
        let cs = self.pv(Predef::CurrentState, Access::Write)?;
        let hc = self.temp("HG_C");
        self.g("L", &word_literal(d));
        self.g("T", &cs);
        self.g("T", &hc);
        self.set_bit(Predef::StateChange, true)?;
        self.set_bit(Predef::UsrMsgSend, st.is_some_and(|s| s.reports))?;
        let (wait, sup) = match st {
            Some(st) => (st.wait.clone(), st.supervise.clone()),
            None => (None, None),
        };
        self.load_time(
            graph,
            d,
            false,
            wait.as_ref(),
            Predef::WtValid,
            Predef::WtExpired,
            Predef::WtCurrValue,
        )?;
        self.load_time(
            graph,
            d,
            true,
            sup.as_ref(),
            Predef::StValid,
            Predef::StExpired,
            Predef::StCurrValue,
        )?;
        self.restore();
        if let Some(st) = st {
            self.blocks(&st.entry, false, &format!("state {d} E"))?;
            if self.group.options.precyclic_on_entry {
                self.blocks(&st.pre, false, &format!("state {d} C-"))?;
            }
        }
        Ok(())
    }

    /// §2.6 load (inside a save).
    #[allow(clippy::too_many_arguments)]
    fn load_time(
        &mut self,
        graph: &Graph,
        d: u16,
        supervise: bool,
        value: Option<&TimeValue>,
        valid: Predef,
        expired: Predef,
        curr: Predef,
    ) -> Result<(), Error> {
        let vw = self.pv(valid, Access::Write)?;
        let ew = self.pv(expired, Access::Write)?;
        let cw = self.pv(curr, Access::Write)?;
        match value {
            None => {
                self.g("SET", "");
                self.g("R", &vw);
                self.g("R", &ew);
                self.g("L", "L#0");
                self.g("T", &cw);
            }
            Some(TimeValue::Const(ms)) => {
                self.g("SET", "");
                if *ms > 0 {
                    self.g("S", &vw);
                    self.g("R", &ew);
                    self.g("L", &format!("L#{}", (*ms).min(i64::from(i32::MAX))));
                } else {
                    self.g("R", &vw);
                    self.g("R", &ew);
                    self.g("L", "L#0");
                }
                self.g("T", &cw);
            }
            Some(TimeValue::Operand(op)) => {
                let text = match op {
                    Operand::Place(place) => {
                        let written = self
                            .names
                            .time_symbols
                            .get(&(self.group.instances[self.inst as usize].graph, d, supervise))
                            .cloned();
                        self.place_text(place, written.as_deref(), Access::Read, None, None)?
                    }
                    other => {
                        self.operand_text(OpCode::L, other, (Origin::NONE, 0), Access::Read)?
                    }
                };
                let _ = graph;
                let pos = self.label();
                let done = self.label();
                self.g("L", &text);
                self.g("L", "L#0");
                self.g(">D", "");
                self.g("=", &vw);
                self.g("SPB", &pos);
                self.g("T", &cw);
                self.g("SPA", &done);
                self.put_label(&pos);
                self.g("TAK", "");
                self.g("T", &cw);
                self.put_label(&done);
                self.g("SET", "");
                self.g("R", &ew);
            }
        }
        Ok(())
    }

    // ------------------------------------------------------------------ blocks

    fn header(&self, title: &str) -> String {
        let mut name: String = self.names.group.chars().take(8).collect();
        if name.is_empty() {
            name = "GROUP".into();
        }
        format!(
            "TITLE = {}\nAUTHOR : higraph\nFAMILY : HIGRAPH\nNAME : {}\nVERSION : 0.1\n\n",
            one_line(title),
            name
        )
    }

    fn block_ref(&mut self, b: &BlockName) -> String {
        match (&b.symbol, self.opt.absolute) {
            (Some(sym), false) => format!("\"{sym}\""),
            _ => format!("{} {}", b.kind, b.number),
        }
    }

    fn db_source(&mut self) -> String {
        let mut s = String::new();
        let db = self.names.db.clone();
        let _ = writeln!(s, "DATA_BLOCK {}", self.block_ref(&db));
        let title = match &self.names.comment {
            Some(c) => format!("group {} \"{}\": instance data", self.names.group, c),
            None => format!("group {}: instance data", self.names.group),
        };
        s.push_str(&self.header(&title));
        let _ = writeln!(s, "  STRUCT");
        let mut inits = Vec::new();
        let mut layout = Layout::new();
        for (i, inst) in self.group.instances.iter().enumerate() {
            let Ok(graph) = self.graph(inst) else {
                continue;
            };
            let ic = self.names.instance_comments.get(i).cloned().flatten();
            let c = match ic {
                Some(c) => format!("\t//{}", one_line(&c)),
                None => String::new(),
            };
            let _ = writeln!(s, "   {} : STRUCT {c}", inst.name);
            layout.begin_struct();
            for (v, var) in graph.vars.iter().enumerate() {
                if !has_member(var.ty) {
                    continue;
                }
                layout.place(var.ty);
                // The initial value: a constant actual, else the cell's (the simulator's).
                let value = match inst.binding.get(v) {
                    Some(Place::Const(c)) => Some(c.clone()),
                    _ => self
                        .names
                        .own_cells
                        .get(i)
                        .and_then(|o| o.get(v))
                        .and_then(|&c| self.p.cells.get(c as usize))
                        .map(|ci| ci.init.clone()),
                };
                let init = value.as_ref().and_then(initial);
                let comment = self
                    .names
                    .var_comments
                    .get(&(inst.graph, v as VarIdx))
                    .map(String::as_str)
                    .or_else(|| Predef::ALL.get(v).map(|p| predef_comment(*p)))
                    .map(|c| format!("\t//{}", one_line(c)))
                    .unwrap_or_default();
                match &init {
                    Some(text) => {
                        let _ = writeln!(
                            s,
                            "    {} : {} := {text};{comment}",
                            var.name,
                            type_name(var.ty)
                        );
                        inits.push(format!("{}.{}", inst.name, var.name));
                    }
                    None => {
                        let _ = writeln!(s, "    {} : {};{comment}", var.name, type_name(var.ty));
                    }
                }
            }
            if layout.needs_pad() {
                layout.place(Ty::Byte);
                let _ = writeln!(s, "    HG_Pad : BYTE;\t//even size, as STEP 7 lays it out");
            }
            layout.end_struct();
            let _ = writeln!(s, "   END_STRUCT ;");
        }
        for (name, ty, comment) in DB_GLUE {
            let _ = writeln!(s, "   {name} : {};\t//{comment}", type_name(ty));
        }
        let _ = writeln!(s, "  END_STRUCT ;");
        let _ = writeln!(s, "BEGIN");
        let _ = writeln!(s, "END_DATA_BLOCK");
        s
    }

    fn fc_source(&mut self, body: &str) -> String {
        let mut s = String::new();
        let fc = self.names.fc.clone();
        let _ = writeln!(s, "FUNCTION {} : VOID", self.block_ref(&fc));
        let title = match &self.names.comment {
            Some(c) => format!("group {} \"{}\": one group cycle", self.names.group, c),
            None => format!("group {}: one group cycle", self.names.group),
        };
        s.push_str(&self.header(&title));
        let mut objects = Vec::new();
        let mut timers: Vec<_> = self.timers.values().copied().collect();
        timers.sort_unstable();
        let mut counters: Vec<_> = self.counters.values().copied().collect();
        counters.sort_unstable();
        if !timers.is_empty() {
            objects.push(format!(
                "timers {} for unwired TIMER variables",
                timers
                    .iter()
                    .map(|t| format!("T {t}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if !counters.is_empty() {
            let z = if self.opt.mnemonic == Mnemonic::International {
                "C"
            } else {
                "Z"
            };
            objects.push(format!(
                "counters {} for unwired COUNTER variables",
                counters
                    .iter()
                    .map(|t| format!("{z} {t}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let _ = writeln!(s, "VAR_INPUT");
        let _ = writeln!(
            s,
            "  INIT_SD : BOOL ;\t//1: startup transition (first cycle after a restart)"
        );
        let _ = writeln!(s, "END_VAR");
        let _ = writeln!(s, "VAR_TEMP");
        if self.user_local > 0 {
            let _ = writeln!(
                s,
                "  HG_User : ARRAY  [0 .. {} ] OF BYTE ;\t//local data L 0 .. {} of the graphs",
                self.user_local - 1,
                self.user_local - 1
            );
        }
        for (name, ty) in TEMPS {
            let _ = writeln!(s, "  {name} : {} ;", type_name(ty));
        }
        let _ = writeln!(s, "END_VAR");
        let _ = writeln!(s, "BEGIN");
        for o in objects {
            let _ = writeln!(s, "// {o}");
        }
        s.push_str(body);
        let _ = writeln!(s, "END_FUNCTION");
        s
    }

    fn ob1_source(&mut self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "ORGANIZATION_BLOCK OB 1");
        s.push_str(&self.header(&format!("cycle: calls group {}", self.names.group)));
        let _ = writeln!(s, "VAR_TEMP");
        for (name, ty) in [
            ("OB1_EV_CLASS", "BYTE"),
            ("OB1_SCAN_1", "BYTE"),
            ("OB1_PRIORITY", "BYTE"),
            ("OB1_OB_NUMBR", "BYTE"),
            ("OB1_RESERVED_1", "BYTE"),
            ("OB1_RESERVED_2", "BYTE"),
            ("OB1_PREV_CYCLE", "INT"),
            ("OB1_MIN_CYCLE", "INT"),
            ("OB1_MAX_CYCLE", "INT"),
            ("OB1_DATE_TIME", "DATE_AND_TIME"),
            ("HG_InitSd", "BOOL"),
        ] {
            let _ = writeln!(s, "  {name} : {ty} ;");
        }
        let _ = writeln!(s, "END_VAR");
        let _ = writeln!(s, "BEGIN");
        let _ = writeln!(s, "NETWORK");
        let _ = writeln!(
            s,
            "TITLE = INIT_SD: first cycle after a restart (OB1_SCAN_1 = 1) or a fresh DB"
        );
        let (scan, init_sd) = if self.opt.absolute {
            (
                note("LB 1".to_owned(), "OB1_SCAN_1"),
                note(
                    mem_text(MemArea::Local, 20, Width::Bit(0), self.opt.mnemonic),
                    "HG_InitSd",
                ),
            )
        } else {
            ("#OB1_SCAN_1".to_owned(), "#HG_InitSd".to_owned())
        };
        let init = self.glue_member("HG_Init");
        let m = self.opt.mnemonic;
        let mut line = |op: &'static str, operand: &str| {
            s.push_str(&statement(glue(op, m), operand));
        };
        line("L", &scan);
        line("L", "1");
        line("==I", "");
        line("ON", &init);
        line("=", &init_sd);
        let fc = self.names.fc.clone();
        let target = self.block_ref(&fc);
        let _ = writeln!(s, "      CALL  {target} (");
        let _ = writeln!(
            s,
            "           INIT_SD                  := {});",
            bare(&init_sd)
        );
        let _ = writeln!(s, "END_ORGANIZATION_BLOCK");
        s
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ChangeKind {
    Initial,
    Startup,
    Normal,
}

/// What a predefined variable's DB member holds (`runtime.md` §2.7).
fn predef_comment(p: Predef) -> &'static str {
    match p {
        Predef::ManualMode => "manual transitions allowed",
        Predef::AutomaticMode => "automatic transitions allowed",
        Predef::UsrMsgQuit => "acknowledgement (no effect)",
        Predef::InitSd => "copy of the FC input INIT_SD",
        Predef::CurrentState => "current state number",
        Predef::PreviousState => "state before the last change",
        Predef::StateChange => "1 in the cycle of a change",
        Predef::StExpired => "supervision time ran out",
        Predef::StExpiredPrev => "ST_Expired when the previous state was left",
        Predef::WtExpired => "wait time ran out",
        Predef::StStop => "pause the supervision time",
        Predef::WtStop => "pause the wait time",
        Predef::StCurrValue => "supervision time left (ms)",
        Predef::WtCurrValue => "wait time left (ms)",
        Predef::StValid => "a supervision time runs",
        Predef::WtValid => "a wait time runs",
        Predef::UsrMsgSend => "the state is a fault or message state",
        Predef::UsrMsgStat => "always 0",
    }
}

/// Separates an absolute operand from the name it stands for (written as a comment).
const NOTE: char = '\u{1}';

/// `text` with `name` to be written as the statement's comment.
fn note(text: String, name: &str) -> String {
    format!("{text}{NOTE}{name}")
}

/// An operand without its note.
fn bare(operand: &str) -> &str {
    operand.split(NOTE).next().unwrap_or(operand)
}

/// One statement line: the operation padded to a column, the operand, `;`, and the names of
/// absolute operands as a comment.
fn statement(op: &str, operand: &str) -> String {
    let mut parts = operand.split(NOTE);
    let text = parts.next().unwrap_or("");
    let notes: Vec<&str> = parts.collect();
    let mut line = if text.is_empty() {
        format!("      {op};")
    } else {
        format!("      {op:<5} {text};")
    };
    if !notes.is_empty() {
        let pad = 30usize.saturating_sub(line.len()).max(1);
        line.push_str(&" ".repeat(pad));
        line.push_str("//");
        line.push_str(&notes.join(", "));
    }
    line.push('\n');
    line
}

/// A state number as a 16-bit constant (`L 40000` would be a DINT).
fn word_literal(n: u16) -> String {
    if n <= 32767 {
        n.to_string()
    } else {
        format!("W#16#{n:X}")
    }
}

fn target_text(t: Target) -> String {
    match t {
        Target::State(n) => n.to_string(),
        Target::Return => "return".into(),
    }
}

fn one_line(text: &str) -> String {
    text.replace(['\r', '\n'], " ")
}

/// A constant as written, with the long type prefixes in their short form (`S5TIME#10S` →
/// `S5T#10S`, `TIME#` → `T#`, `DATE#` → `D#`, `TIME_OF_DAY#` → `TOD#`), which every STEP 7
/// compiler and Awlsim read.
fn short_literal(text: &str) -> String {
    const LONG: [(&str, &str); 5] = [
        ("S5TIME#", "S5T#"),
        ("TIME_OF_DAY#", "TOD#"),
        ("DATE_AND_TIME#", "DT#"),
        ("TIME#", "T#"),
        ("DATE#", "D#"),
    ];
    let (sign, body) = match text.strip_prefix('-') {
        Some(rest) => ("-", rest),
        None => ("", text),
    };
    for (long, short) in LONG {
        if body.len() >= long.len() && body[..long.len()].eq_ignore_ascii_case(long) {
            return format!("{sign}{short}{}", &body[long.len()..]);
        }
    }
    text.to_owned()
}

/// The text of an immediate without a written form.
fn imm_text(op: OpCode, bits: u32) -> String {
    use OpCode::*;
    match op {
        Inc | Dec | Slw | Srw | Sld | Srd | Ssi | Ssd | Rld | Rrd => bits.to_string(),
        AddInt => (bits as u16 as i16).to_string(),
        AddDint => format!("L#{}", bits as i32),
        Uw | Ow | Xow => format!("W#16#{:X}", bits & 0xFFFF),
        _ => format!("DW#16#{bits:X}"),
    }
}

fn for_each_instr(graph: &Graph, mut f: impl FnMut(&Instr)) {
    let mut blocks: Vec<&Block> = Vec::new();
    blocks.extend(&graph.permanent_pre);
    blocks.extend(&graph.permanent_post);
    for t in &graph.any {
        blocks.extend(&t.conditions);
        blocks.extend(&t.actions);
    }
    for st in &graph.states {
        blocks.extend(&st.entry);
        blocks.extend(&st.pre);
        blocks.extend(&st.cyclic);
        blocks.extend(&st.exit);
        for t in &st.transitions {
            blocks.extend(&t.conditions);
            blocks.extend(&t.actions);
        }
    }
    for b in blocks {
        for ins in &b.code {
            f(ins);
        }
    }
}

fn visit_operand(op: &Operand, f: &mut impl FnMut(&Place)) {
    match op {
        Operand::Place(p) => f(p),
        Operand::Call(call) => {
            for (_, actual) in &call.params {
                if let Operand::Place(p) = actual {
                    f(p);
                }
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_packs_bools_and_aligns_words() {
        let mut l = Layout::new();
        assert_eq!(l.begin_struct(), Offset { byte: 0, bit: 0 });
        assert_eq!(l.place(Ty::Bool), Offset { byte: 0, bit: 0 });
        assert_eq!(l.place(Ty::Bool), Offset { byte: 0, bit: 1 });
        assert_eq!(l.place(Ty::Word), Offset { byte: 2, bit: 0 });
        assert_eq!(l.place(Ty::Bool), Offset { byte: 4, bit: 0 });
        assert_eq!(l.place(Ty::Byte), Offset { byte: 5, bit: 0 });
        assert_eq!(l.place(Ty::Dword), Offset { byte: 6, bit: 0 });
        assert_eq!(l.place(Ty::Bool), Offset { byte: 10, bit: 0 });
        assert!(l.needs_pad());
        l.place(Ty::Byte);
        l.end_struct();
        assert_eq!(l.size(), 12);
        assert_eq!(l.begin_struct(), Offset { byte: 12, bit: 0 });
        assert_eq!(l.place(Ty::Char), Offset { byte: 12, bit: 0 });
        assert_eq!(l.place(Ty::Int), Offset { byte: 14, bit: 0 });
        assert_eq!(l.place(Ty::String(4)), Offset { byte: 16, bit: 0 });
        assert_eq!(l.place(Ty::Real), Offset { byte: 22, bit: 0 });
    }

    #[test]
    fn long_literal_prefixes_are_shortened() {
        assert_eq!(short_literal("S5TIME#10S"), "S5T#10S");
        assert_eq!(short_literal("s5time#10s"), "S5T#10s");
        assert_eq!(short_literal("TIME#1H"), "T#1H");
        assert_eq!(short_literal("TIME_OF_DAY#1:00:00"), "TOD#1:00:00");
        assert_eq!(short_literal("DATE#1990-01-02"), "D#1990-01-02");
        assert_eq!(short_literal("T#5S"), "T#5S");
        assert_eq!(short_literal("'T'"), "'T'");
        assert_eq!(short_literal("W#16#FF"), "W#16#FF");
    }

    #[test]
    fn initial_values() {
        assert_eq!(initial(&Value::Bool(true)).as_deref(), Some("TRUE"));
        assert_eq!(initial(&Value::Bool(false)), None);
        assert_eq!(initial(&Value::Int(-5)).as_deref(), Some("-5"));
        assert_eq!(initial(&Value::Time(2000)).as_deref(), Some("T#2000MS"));
        assert_eq!(initial(&Value::Real(1.5)).as_deref(), Some("1.5e+0"));
        assert_eq!(initial(&Value::Word(0)), None);
    }
}
