//! Fixed facts of the language: data types, predefined variables, mnemonic sets, the STL
//! operations of the HiGraph subset and the word lists of `diagnostics.md` Appendix A.

use std::fmt;

/// The STL mnemonic set of a file (`language.md` §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Mnemonic {
    #[default]
    Simatic,
    International,
}

impl Mnemonic {
    pub fn other(self) -> Mnemonic {
        match self {
            Mnemonic::Simatic => Mnemonic::International,
            Mnemonic::International => Mnemonic::Simatic,
        }
    }

    /// `SIMATIC` / `international` as used in messages.
    pub fn display(self) -> &'static str {
        match self {
            Mnemonic::Simatic => "SIMATIC",
            Mnemonic::International => "international",
        }
    }

    pub fn parse(word: &str) -> Option<Mnemonic> {
        if word.eq_ignore_ascii_case("simatic") {
            Some(Mnemonic::Simatic)
        } else if word.eq_ignore_ascii_case("international") {
            Some(Mnemonic::International)
        } else {
            None
        }
    }
}

/// A data type (`language.md` §3.1), plus the block-interface-only types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Type {
    Bool,
    Byte,
    Word,
    Dword,
    Int,
    Dint,
    Real,
    S5Time,
    Time,
    Date,
    TimeOfDay,
    DateAndTime,
    Char,
    /// `STRING[n]`; plain `STRING` is `STRING[254]`.
    String(u16),
    Timer,
    Counter,
    Pointer,
    Any,
    BlockFc,
    BlockFb,
    BlockDb,
    /// The type of a block address (`FC 10`).
    Block,
}

impl Type {
    /// Parses a type name (case-insensitive; `TOD` and `DT` are aliases). `STRING` lengths are
    /// given separately. `interface` allows the block-interface-only types.
    pub fn from_name(name: &str, interface: bool) -> Option<Type> {
        let ty = match name.to_ascii_uppercase().as_str() {
            "BOOL" => Type::Bool,
            "BYTE" => Type::Byte,
            "WORD" => Type::Word,
            "DWORD" => Type::Dword,
            "INT" => Type::Int,
            "DINT" => Type::Dint,
            "REAL" => Type::Real,
            "S5TIME" => Type::S5Time,
            "TIME" => Type::Time,
            "DATE" => Type::Date,
            "TIME_OF_DAY" | "TOD" => Type::TimeOfDay,
            "DATE_AND_TIME" | "DT" => Type::DateAndTime,
            "CHAR" => Type::Char,
            "STRING" => Type::String(254),
            "TIMER" => Type::Timer,
            "COUNTER" => Type::Counter,
            "POINTER" if interface => Type::Pointer,
            "ANY" if interface => Type::Any,
            "BLOCK_FC" if interface => Type::BlockFc,
            "BLOCK_FB" if interface => Type::BlockFb,
            "BLOCK_DB" if interface => Type::BlockDb,
            _ => return None,
        };
        Some(ty)
    }

    /// Every type name usable in a declaration (for closest-name fixes).
    pub const NAMES: &'static [&'static str] = &[
        "BOOL",
        "BYTE",
        "WORD",
        "DWORD",
        "INT",
        "DINT",
        "REAL",
        "S5TIME",
        "TIME",
        "DATE",
        "TIME_OF_DAY",
        "TOD",
        "DATE_AND_TIME",
        "DT",
        "CHAR",
        "STRING",
        "TIMER",
        "COUNTER",
    ];
}

impl fmt::Display for Type {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Type::Bool => "BOOL",
            Type::Byte => "BYTE",
            Type::Word => "WORD",
            Type::Dword => "DWORD",
            Type::Int => "INT",
            Type::Dint => "DINT",
            Type::Real => "REAL",
            Type::S5Time => "S5TIME",
            Type::Time => "TIME",
            Type::Date => "DATE",
            Type::TimeOfDay => "TIME_OF_DAY",
            Type::DateAndTime => "DATE_AND_TIME",
            Type::Char => "CHAR",
            Type::String(n) => return write!(f, "STRING[{n}]"),
            Type::Timer => "TIMER",
            Type::Counter => "COUNTER",
            Type::Pointer => "POINTER",
            Type::Any => "ANY",
            Type::BlockFc => "BLOCK_FC",
            Type::BlockFb => "BLOCK_FB",
            Type::BlockDb => "BLOCK_DB",
            Type::Block => "BLOCK",
        };
        f.write_str(name)
    }
}

/// The section a variable is declared in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Section {
    In,
    Out,
    InOut,
    Stat,
}

impl Section {
    pub fn as_str(self) -> &'static str {
        match self {
            Section::In => "in",
            Section::Out => "out",
            Section::InOut => "in_out",
            Section::Stat => "stat",
        }
    }

    pub fn from_keyword(word: &str) -> Option<Section> {
        Some(match word.to_ascii_lowercase().as_str() {
            "in" => Section::In,
            "out" => Section::Out,
            "in_out" => Section::InOut,
            "stat" => Section::Stat,
            _ => return None,
        })
    }

    /// `in`, `out` and `in_out` variables are formal parameters.
    pub fn is_formal(self) -> bool {
        self != Section::Stat
    }
}

/// Can `name` be written without quotes: a letter or `_`, then letters, digits and `_`?
pub(crate) fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// How `name` is written as an operand: bare if it is an identifier, else in quotes (a global
/// symbol such as `"Motor 1"`).
pub(crate) fn operand_spelling(name: &str) -> String {
    if is_identifier(name) {
        name.to_owned()
    } else {
        format!("\"{name}\"")
    }
}

/// A predefined variable of every graph (`language.md` §3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Predefined {
    pub name: &'static str,
    pub section: Section,
    pub ty: Type,
    /// May the user write it? (HG1209)
    pub writable: bool,
    /// Active without `activate`?
    pub active_by_default: bool,
    /// For internal use only (HG1214).
    pub internal: bool,
    /// What it means, for hover.
    pub meaning: &'static str,
}

const fn pre(
    name: &'static str,
    section: Section,
    ty: Type,
    writable: bool,
    active_by_default: bool,
    internal: bool,
    meaning: &'static str,
) -> Predefined {
    Predefined {
        name,
        section,
        ty,
        writable,
        active_by_default,
        internal,
        meaning,
    }
}

/// The predefined variables, in the order of `language.md` §3.1.
pub const PREDEFINED: &[Predefined] = &[
    pre(
        "ManualMode",
        Section::In,
        Type::Bool,
        true,
        true,
        false,
        "manual operating mode: transitions marked 'manual' fire only while it is 1",
    ),
    pre(
        "AutomaticMode",
        Section::In,
        Type::Bool,
        true,
        true,
        false,
        "automatic operating mode: transitions marked 'auto' fire only while it is 1",
    ),
    pre(
        "UsrMsgQuit",
        Section::In,
        Type::Bool,
        true,
        true,
        false,
        "acknowledges a user message",
    ),
    pre(
        "INIT_SD",
        Section::Stat,
        Type::Bool,
        true,
        true,
        false,
        "startup: set by the group FC on restart; the startup any-transition queries it",
    ),
    pre(
        "CurrentState",
        Section::Stat,
        Type::Word,
        false,
        false,
        false,
        "number of the active state",
    ),
    pre(
        "PreviousState",
        Section::Stat,
        Type::Word,
        false,
        false,
        false,
        "number of the previously active state",
    ),
    pre(
        "StateChange",
        Section::Stat,
        Type::Bool,
        false,
        false,
        false,
        "1 in the cycle in which the state changed",
    ),
    pre(
        "ST_Expired",
        Section::Stat,
        Type::Bool,
        false,
        true,
        false,
        "the supervision time of the active state has run out",
    ),
    pre(
        "ST_ExpiredPrev",
        Section::Stat,
        Type::Bool,
        false,
        true,
        false,
        "the supervision time had run out in the previous state",
    ),
    pre(
        "WT_Expired",
        Section::Stat,
        Type::Bool,
        false,
        true,
        false,
        "the wait time of the active state has run out",
    ),
    pre(
        "ST_Stop",
        Section::Stat,
        Type::Bool,
        true,
        false,
        false,
        "stops the supervision time",
    ),
    pre(
        "WT_Stop",
        Section::Stat,
        Type::Bool,
        true,
        false,
        false,
        "stops the wait time",
    ),
    pre(
        "ST_CurrValue",
        Section::Stat,
        Type::Dword,
        false,
        true,
        false,
        "elapsed supervision time",
    ),
    pre(
        "WT_CurrValue",
        Section::Stat,
        Type::Dword,
        false,
        true,
        false,
        "elapsed wait time",
    ),
    pre(
        "ST_Valid",
        Section::Stat,
        Type::Bool,
        false,
        true,
        true,
        "internal: the supervision time is valid",
    ),
    pre(
        "WT_Valid",
        Section::Stat,
        Type::Bool,
        false,
        true,
        true,
        "internal: the wait time is valid",
    ),
    pre(
        "UsrMsgSend",
        Section::Stat,
        Type::Bool,
        false,
        true,
        false,
        "a user message is being sent",
    ),
    pre(
        "UsrMsgStat",
        Section::Stat,
        Type::Word,
        false,
        true,
        true,
        "internal: user message status",
    ),
];

/// Looks up a predefined variable (case-insensitive).
pub fn predefined(name: &str) -> Option<&'static Predefined> {
    PREDEFINED
        .iter()
        .find(|p| p.name.eq_ignore_ascii_case(name))
}

/// V2.7 names and their successors (Appendix A.4).
pub const V27_NAMES: &[(&str, &str)] = &[
    ("BA_HAND", "ManualMode"),
    ("BA_AUTO", "AutomaticMode"),
    ("ANLAUF", "INIT_SD"),
    ("AKTUELLER_ZUSTAND", "CurrentState"),
    ("LETZTER_ZUSTAND", "PreviousState"),
    ("ZUSTANDS_WECHSEL", "StateChange"),
    ("Z_FEHLER", "ST_Expired"),
    ("Z_FEHLER_ALT", "ST_ExpiredPrev"),
    ("STOP_WATCH_TIME", "ST_Stop"),
    ("STOP_WAIT_TIME", "WT_Stop"),
];

/// Reserved type names (Appendix A.1).
pub const RESERVED_TYPES: &[&str] = &[
    "BOOL",
    "BYTE",
    "WORD",
    "DWORD",
    "INT",
    "DINT",
    "REAL",
    "S5TIME",
    "TIME",
    "DATE",
    "TIME_OF_DAY",
    "TOD",
    "DATE_AND_TIME",
    "DT",
    "CHAR",
    "STRING",
    "TIMER",
    "COUNTER",
    "POINTER",
    "ANY",
    "ARRAY",
    "STRUCT",
];

/// Reserved literals and operators (Appendix A.1).
pub const RESERVED_LITERALS: &[&str] = &["TRUE", "FALSE", "AND", "OR", "XOR", "NOT"];

/// The alphabetic operations of the HiGraph subset in SIMATIC mnemonics (Appendix A.1).
pub const SIMATIC_WORD_OPS: &[&str] = &[
    "U", "UN", "O", "ON", "X", "XN", "S", "R", "SET", "CLR", "NOT", "FP", "FN", "UW", "OW", "XOW",
    "UD", "OD", "XOD", "SI", "SV", "SE", "SS", "SA", "FR", "L", "LC", "ZV", "ZR", "T", "TAR",
    "TAR1", "TAR2", "CALL", "CC", "MOD", "ABS", "SQR", "SQRT", "EXP", "LN", "SIN", "COS", "TAN",
    "ASIN", "ACOS", "ATAN", "SLW", "SRW", "SLD", "SRD", "SSI", "SSD", "RLD", "RRD", "RLDA", "RRDA",
    "INC", "DEC", "TAK", "PUSH", "POP", "TAD", "TAW", "BTI", "BTD", "ITB", "DTB", "ITD", "DTR",
    "INVI", "INVD", "NEGI", "NEGD", "NEGR", "RND", "TRUNC",
];

/// SIMATIC ↔ international operation names that differ (Appendix A.5).
pub const OP_TRANSLATION: &[(&str, &str)] = &[
    ("U", "A"),
    ("UN", "AN"),
    ("U(", "A("),
    ("UN(", "AN("),
    ("UW", "AW"),
    ("UD", "AD"),
    ("SI", "SP"),
    ("SV", "SE"),
    ("SE", "SD"),
    ("SA", "SF"),
    ("ZV", "CU"),
    ("ZR", "CD"),
    ("TAR", "CAR"),
    ("TAR1", "CAR1"),
    ("TAR2", "CAR2"),
    ("TAD", "CAD"),
    ("TAW", "CAW"),
];

/// SIMATIC ↔ international area names that differ (Appendix A.5).
pub const AREA_TRANSLATION: &[(&str, &str)] = &[
    ("E", "I"),
    ("EB", "IB"),
    ("EW", "IW"),
    ("ED", "ID"),
    ("A", "Q"),
    ("AB", "QB"),
    ("AW", "QW"),
    ("AD", "QD"),
    ("PEB", "PIB"),
    ("PEW", "PIW"),
    ("PED", "PID"),
    ("PAB", "PQB"),
    ("PAW", "PQW"),
    ("PAD", "PQD"),
    ("Z", "C"),
];

/// Operations spelled with punctuation, the same in both sets.
pub const SYMBOL_OPS: &[&str] = &[
    "O(", "ON(", "X(", "XN(", ")", "=", "+", "==I", "<>I", ">I", "<I", ">=I", "<=I", "==D", "<>D",
    ">D", "<D", ">=D", "<=D", "==R", "<>R", ">R", "<R", ">=R", "<=R", "+I", "-I", "*I", "/I", "+D",
    "-D", "*D", "/D", "+R", "-R", "*R", "/R", "RND+", "RND-",
];

/// Translates a SIMATIC operation to `set` (identity for ops that do not differ).
pub fn op_in_set(simatic_op: &str, set: Mnemonic) -> String {
    let upper = simatic_op.to_ascii_uppercase();
    if set == Mnemonic::Simatic {
        return upper;
    }
    OP_TRANSLATION
        .iter()
        .find(|(s, _)| *s == upper)
        .map_or(upper.clone(), |(_, i)| (*i).to_owned())
}

/// Is `op` (upper case, e.g. `U(`) an operation of the subset in `set`?
pub fn is_subset_op(op: &str, set: Mnemonic) -> bool {
    to_simatic_op(op, set).is_some()
}

/// The SIMATIC name of `op` read in `set` (`A` in an international file is `U`), if `op` is an
/// operation of the subset in that set.
pub fn to_simatic_op(op: &str, set: Mnemonic) -> Option<String> {
    let upper = op.to_ascii_uppercase();
    let simatic = match set {
        Mnemonic::Simatic => upper,
        Mnemonic::International => {
            if let Some((s, _)) = OP_TRANSLATION.iter().find(|(_, i)| *i == upper) {
                (*s).to_owned()
            } else if OP_TRANSLATION.iter().any(|(s, _)| *s == upper) {
                // A SIMATIC-only name (`U`, `ZV`).
                return None;
            } else {
                upper
            }
        }
    };
    let known = SIMATIC_WORD_OPS.contains(&simatic.as_str())
        || SYMBOL_OPS.contains(&simatic.as_str())
        || simatic == "U("
        || simatic == "UN(";
    known.then_some(simatic)
}

/// Known STEP 7 operations outside the HiGraph subset (Appendix A.3), both sets.
pub const OUTSIDE_SUBSET: &[&str] = &[
    "SPA", "SPB", "SPBN", "SPBB", "SPBNB", "SPBI", "SPBIN", "SPO", "SPS", "SPZ", "SPN", "SPP",
    "SPM", "SPPZ", "SPMZ", "SPU", "SPL", "LOOP", "JU", "JC", "JCN", "JCB", "JNB", "JBI", "JNBI",
    "JO", "JOS", "JZ", "JN", "JP", "JM", "JPZ", "JMZ", "JUO", "JL", "BE", "BEA", "BEB", "BEU",
    "BEC", "UC", "AUF", "TDB", "OPN", "CDB", "MCRA", "MCRD", "MCR(", ")MCR", "LAR1", "LAR2",
    "+AR1", "+AR2", "SAVE", "ENT", "LEAVE", "BLD", "NOP",
];

/// Block-end operations (for HG4003's message).
pub const BLOCK_END_OPS: &[&str] = &["BE", "BEA", "BEB", "BEU", "BEC"];

/// Jump operations (for HG4003's message).
pub fn is_jump_op(op: &str) -> bool {
    let upper = op.to_ascii_uppercase();
    (upper.starts_with("SP") || upper.starts_with('J') || upper == "LOOP")
        && OUTSIDE_SUBSET.contains(&upper.as_str())
}

/// How an opcode reads in a file's mnemonic set (HG4003, HG4007, HG4008).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum OpClass {
    /// An operation of the HiGraph subset in the file's set; its SIMATIC name.
    Subset(String),
    /// An operation only of the other set's subset (HG4007): its SIMATIC name and its
    /// spelling in the file's set.
    OtherSet { simatic: String, translated: String },
    /// A known STEP 7 operation outside the subset (Appendix A.3, HG4003).
    Outside(OutsideKind),
    /// Not an operation at all (HG4008).
    Unknown,
}

/// Which message HG4003 uses for an operation outside the subset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutsideKind {
    Jump,
    BlockEnd,
    Other,
}

/// Classifies an opcode (as written, any case) in `set`.
pub fn classify_op(op: &str, set: Mnemonic) -> OpClass {
    let upper = op.to_ascii_uppercase();
    if let Some(simatic) = to_simatic_op(&upper, set) {
        return OpClass::Subset(simatic);
    }
    if let Some(simatic) = to_simatic_op(&upper, set.other()) {
        let translated = op_in_set(&simatic, set);
        return OpClass::OtherSet {
            simatic,
            translated,
        };
    }
    if OUTSIDE_SUBSET.contains(&upper.as_str()) {
        let kind = if is_jump_op(&upper) {
            OutsideKind::Jump
        } else if BLOCK_END_OPS.contains(&upper.as_str()) {
            OutsideKind::BlockEnd
        } else {
            OutsideKind::Other
        };
        return OpClass::Outside(kind);
    }
    OpClass::Unknown
}

/// Every operation of the subset spelled in `set` (for closest-name fixes of HG4008).
pub fn subset_ops(set: Mnemonic) -> Vec<String> {
    let mut ops: Vec<String> = SIMATIC_WORD_OPS
        .iter()
        .chain(SYMBOL_OPS)
        .chain(&["U(", "UN("])
        .map(|op| op_in_set(op, set))
        .collect();
    ops.dedup();
    ops
}

/// Register and status operands (Appendix A.2b).
pub fn is_register_name(name: &str, set: Mnemonic) -> bool {
    let upper = name.to_ascii_uppercase();
    let common = [
        "STW", "AR1", "AR2", "DBLG", "DBNO", "DILG", "DINO", "OV", "OS", "UO",
    ];
    common.contains(&upper.as_str())
        || (set == Mnemonic::Simatic && upper == "BIE")
        || (set == Mnemonic::International && upper == "BR")
}

/// Register and status names (Appendix A.2b) with what they mean: the upper-case spelling and
/// the meaning (for HG4102).
pub fn register_meaning(name: &str, set: Mnemonic) -> Option<(&'static str, &'static str)> {
    const REGISTERS: &[(&str, &str)] = &[
        ("STW", "status word"),
        ("AR1", "address register 1"),
        ("AR2", "address register 2"),
        ("DBLG", "length of the open data block"),
        ("DBNO", "number of the open data block"),
        ("DILG", "length of the open instance data block"),
        ("DINO", "number of the open instance data block"),
        ("OV", "overflow bit"),
        ("OS", "stored overflow bit"),
        ("UO", "unordered bit"),
        ("BIE", "binary result bit"),
        ("BR", "binary result bit"),
    ];
    if !is_register_name(name, set) {
        return None;
    }
    REGISTERS
        .iter()
        .find(|(r, _)| r.eq_ignore_ascii_case(name))
        .map(|&(r, m)| (r, m))
}

/// A reserved word (HG1103) for `set`: returns what kind of reserved word it is.
pub fn reserved_kind(name: &str, set: Mnemonic) -> Option<&'static str> {
    let upper = name.to_ascii_uppercase();
    if RESERVED_TYPES.contains(&upper.as_str()) {
        return Some("a data type");
    }
    if RESERVED_LITERALS.contains(&upper.as_str()) {
        return Some(if upper == "TRUE" || upper == "FALSE" {
            "a constant"
        } else {
            "an operator"
        });
    }
    let op = match set {
        Mnemonic::Simatic => SIMATIC_WORD_OPS.contains(&upper.as_str()),
        Mnemonic::International => {
            let simatic = OP_TRANSLATION
                .iter()
                .find(|(_, i)| *i == upper)
                .map(|(s, _)| *s);
            match simatic {
                Some(_) => true,
                None => {
                    SIMATIC_WORD_OPS.contains(&upper.as_str())
                        && !OP_TRANSLATION.iter().any(|(s, _)| *s == upper)
                }
            }
        }
    };
    op.then_some(match set {
        Mnemonic::Simatic => "a SIMATIC STL operation",
        Mnemonic::International => "an international STL operation",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn operations_per_set() {
        assert_eq!(to_simatic_op("U", Mnemonic::Simatic).as_deref(), Some("U"));
        assert_eq!(to_simatic_op("A", Mnemonic::Simatic), None);
        assert_eq!(
            to_simatic_op("A", Mnemonic::International).as_deref(),
            Some("U")
        );
        assert_eq!(to_simatic_op("U", Mnemonic::International), None);
        // SE is in both sets, with different meanings.
        assert_eq!(
            to_simatic_op("SE", Mnemonic::Simatic).as_deref(),
            Some("SE")
        );
        assert_eq!(
            to_simatic_op("SE", Mnemonic::International).as_deref(),
            Some("SV")
        );
        assert_eq!(
            to_simatic_op("SD", Mnemonic::International).as_deref(),
            Some("SE")
        );
        assert_eq!(
            to_simatic_op("A(", Mnemonic::International).as_deref(),
            Some("U(")
        );
        assert_eq!(
            to_simatic_op("L", Mnemonic::International).as_deref(),
            Some("L")
        );
        assert_eq!(to_simatic_op("SPA", Mnemonic::Simatic), None);
        assert_eq!(op_in_set("ZV", Mnemonic::International), "CU");
        assert_eq!(
            classify_op("A", Mnemonic::Simatic),
            OpClass::OtherSet {
                simatic: "U".into(),
                translated: "U".into()
            }
        );
        assert_eq!(
            classify_op("SD", Mnemonic::Simatic),
            OpClass::OtherSet {
                simatic: "SE".into(),
                translated: "SE".into()
            }
        );
        assert_eq!(
            classify_op("SPA", Mnemonic::Simatic),
            OpClass::Outside(OutsideKind::Jump)
        );
        assert_eq!(
            classify_op("BEA", Mnemonic::Simatic),
            OpClass::Outside(OutsideKind::BlockEnd)
        );
        assert_eq!(classify_op("FOO", Mnemonic::Simatic), OpClass::Unknown);
    }

    #[test]
    fn reserved_words_depend_on_the_set() {
        assert!(reserved_kind("U", Mnemonic::Simatic).is_some());
        assert!(reserved_kind("U", Mnemonic::International).is_none());
        assert!(reserved_kind("A", Mnemonic::International).is_some());
        assert!(reserved_kind("A", Mnemonic::Simatic).is_none());
        assert!(reserved_kind("Auf", Mnemonic::Simatic).is_none());
        assert!(reserved_kind("bool", Mnemonic::Simatic).is_some());
        assert!(reserved_kind("state", Mnemonic::Simatic).is_none());
    }
}
