//! The IEC 61131-3 profile of charts (`docs/iec.md`): the standard function blocks with their
//! members (§3) and the words reserved in an IEC chart (§2). Shared by the chart rules, the
//! editor features and whoever else needs the tables (lowering, export).

use crate::lang::Type;

/// A standard function block type (`docs/iec.md` §3).
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

/// Whether a member is an input or an output of its function block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    Input,
    Output,
}

/// One member (formal parameter) of a standard function block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FbMember {
    pub name: &'static str,
    pub direction: Direction,
    pub ty: Type,
    /// One line for hover and completion.
    pub doc: &'static str,
}

const fn input(name: &'static str, ty: Type, doc: &'static str) -> FbMember {
    FbMember {
        name,
        direction: Direction::Input,
        ty,
        doc,
    }
}

const fn output(name: &'static str, ty: Type, doc: &'static str) -> FbMember {
    FbMember {
        name,
        direction: Direction::Output,
        ty,
        doc,
    }
}

const TIMER_MEMBERS: [FbMember; 4] = [
    input("IN", Type::Bool, "the input the timer watches"),
    input("PT", Type::Time, "the preset time"),
    output("Q", Type::Bool, "the timer's output"),
    output("ET", Type::Time, "the elapsed time"),
];
const TRIG_MEMBERS: [FbMember; 2] = [
    input("CLK", Type::Bool, "the watched signal"),
    output("Q", Type::Bool, "TRUE for one call after the edge"),
];
const CTU_MEMBERS: [FbMember; 5] = [
    input("CU", Type::Bool, "counts up on a rising edge"),
    input("R", Type::Bool, "resets the counter to 0"),
    input("PV", Type::Int, "the preset value"),
    output("Q", Type::Bool, "TRUE when CV >= PV"),
    output("CV", Type::Int, "the counter value"),
];
const CTD_MEMBERS: [FbMember; 5] = [
    input("CD", Type::Bool, "counts down on a rising edge"),
    input("LD", Type::Bool, "loads PV into the counter"),
    input("PV", Type::Int, "the preset value"),
    output("Q", Type::Bool, "TRUE when CV <= 0"),
    output("CV", Type::Int, "the counter value"),
];
const CTUD_MEMBERS: [FbMember; 8] = [
    input("CU", Type::Bool, "counts up on a rising edge"),
    input("CD", Type::Bool, "counts down on a rising edge"),
    input("R", Type::Bool, "resets the counter to 0"),
    input("LD", Type::Bool, "loads PV into the counter"),
    input("PV", Type::Int, "the preset value"),
    output("QU", Type::Bool, "TRUE when CV >= PV"),
    output("QD", Type::Bool, "TRUE when CV <= 0"),
    output("CV", Type::Int, "the counter value"),
];
const SR_MEMBERS: [FbMember; 3] = [
    input("S1", Type::Bool, "sets Q1 (dominant)"),
    input("R", Type::Bool, "resets Q1"),
    output("Q1", Type::Bool, "the flip-flop's state"),
];
const RS_MEMBERS: [FbMember; 3] = [
    input("S", Type::Bool, "sets Q1"),
    input("R1", Type::Bool, "resets Q1 (dominant)"),
    output("Q1", Type::Bool, "the flip-flop's state"),
];

impl FbType {
    /// Every standard function block, in the order of `docs/iec.md` §3.
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

    /// The type of that name (case-insensitive).
    pub fn from_name(name: &str) -> Option<FbType> {
        FbType::ALL
            .into_iter()
            .find(|t| t.name().eq_ignore_ascii_case(name))
    }

    /// The canonical (upper-case) name.
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

    /// What the block does, in one line.
    pub fn doc(self) -> &'static str {
        match self {
            FbType::Ton => "on-delay timer: Q follows IN after PT",
            FbType::Tof => "off-delay timer: Q stays TRUE for PT after IN falls",
            FbType::Tp => "pulse timer: Q is TRUE for PT from a rising edge of IN",
            FbType::RTrig => "rising edge detection",
            FbType::FTrig => "falling edge detection",
            FbType::Ctu => "up counter",
            FbType::Ctd => "down counter",
            FbType::Ctud => "up-down counter",
            FbType::Sr => "set-dominant bistable",
            FbType::Rs => "reset-dominant bistable",
        }
    }

    /// The inputs, then the outputs, in declaration order.
    pub fn members(self) -> &'static [FbMember] {
        match self {
            FbType::Ton | FbType::Tof | FbType::Tp => &TIMER_MEMBERS,
            FbType::RTrig | FbType::FTrig => &TRIG_MEMBERS,
            FbType::Ctu => &CTU_MEMBERS,
            FbType::Ctd => &CTD_MEMBERS,
            FbType::Ctud => &CTUD_MEMBERS,
            FbType::Sr => &SR_MEMBERS,
            FbType::Rs => &RS_MEMBERS,
        }
    }

    /// The member of that name (case-insensitive).
    pub fn member(self, name: &str) -> Option<&'static FbMember> {
        self.members()
            .iter()
            .find(|m| m.name.eq_ignore_ascii_case(name))
    }

    /// The signature as hover and signature help show it:
    /// `TON(IN : BOOL, PT : TIME) => (Q : BOOL, ET : TIME)`.
    pub fn signature(self) -> String {
        let list = |direction| {
            self.members()
                .iter()
                .filter(|m| m.direction == direction)
                .map(|m| format!("{} : {}", m.name, m.ty))
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "{}({}) => ({})",
            self.name(),
            list(Direction::Input),
            list(Direction::Output)
        )
    }
}

/// The structured-text keywords of an IEC chart (`docs/iec.md` §2), reserved as names there.
pub const KEYWORDS: &[&str] = &[
    "IF", "THEN", "ELSIF", "ELSE", "END_IF", "CASE", "OF", "END_CASE", "MOD",
];

/// What a name is reserved as in an IEC chart (`docs/iec.md` §2): the IEC keywords, the
/// operators and literals, the type names and the standard function block names. The
/// operations of the STL subset are not reserved there.
pub fn reserved_kind(name: &str) -> Option<&'static str> {
    let upper = name.to_ascii_uppercase();
    // TIMER and COUNTER are S7 types, not IEC ones: `Timer` is a usual IEC instance name.
    if crate::lang::RESERVED_TYPES.contains(&upper.as_str())
        && !matches!(upper.as_str(), "TIMER" | "COUNTER")
    {
        return Some("a data type");
    }
    if upper == "TRUE" || upper == "FALSE" {
        return Some("a constant");
    }
    if crate::lang::RESERVED_LITERALS.contains(&upper.as_str()) {
        return Some("an operator");
    }
    if KEYWORDS.contains(&upper.as_str()) {
        return Some("an IEC 61131-3 keyword");
    }
    if FbType::from_name(&upper).is_some() {
        return Some("a standard function block");
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables() {
        assert_eq!(FbType::from_name("r_trig"), Some(FbType::RTrig));
        assert_eq!(FbType::from_name("TIMER"), None);
        assert_eq!(
            FbType::Ton.signature(),
            "TON(IN : BOOL, PT : TIME) => (Q : BOOL, ET : TIME)"
        );
        assert_eq!(FbType::Ctud.member("qd").map(|m| m.ty), Some(Type::Bool));
        assert_eq!(
            FbType::Ctu.member("CV").map(|m| m.direction),
            Some(Direction::Output)
        );
    }

    #[test]
    fn reserved_words() {
        assert_eq!(reserved_kind("end_if"), Some("an IEC 61131-3 keyword"));
        assert_eq!(reserved_kind("Ton"), Some("a standard function block"));
        assert_eq!(reserved_kind("BOOL"), Some("a data type"));
        // STL operations are not reserved in an IEC chart.
        assert_eq!(reserved_kind("SET"), None);
        assert_eq!(reserved_kind("L"), None);
        assert_eq!(reserved_kind("Timer"), None);
    }
}
