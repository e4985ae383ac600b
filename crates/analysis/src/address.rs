//! Absolute addresses (`language.md` §3.5): reading `E 1.0`, `MW10`, `DB10.DBX 5.1`, `T 5`,
//! `FC 10` in a mnemonic set, their types, normal forms and the address rules HG4009–HG4012.

use std::fmt;

use crate::lang::{Mnemonic, Type};

/// The memory area of an address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Area {
    Input,
    Output,
    Memory,
    Local,
    PeripheralInput,
    PeripheralOutput,
    /// `DBX/DBB/DBW/DBD` — data in a data block.
    DataBlock,
    /// `DIX/DIB/DIW/DID` — data in the instance DB (not available, HG4011).
    InstanceData,
    Timer,
    Counter,
    Block(BlockKind),
}

/// The kind of a block address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BlockKind {
    Ob,
    Fc,
    Fb,
    Db,
    Sfc,
    Sfb,
    Udt,
}

impl BlockKind {
    pub fn as_str(self) -> &'static str {
        match self {
            BlockKind::Ob => "OB",
            BlockKind::Fc => "FC",
            BlockKind::Fb => "FB",
            BlockKind::Db => "DB",
            BlockKind::Sfc => "SFC",
            BlockKind::Sfb => "SFB",
            BlockKind::Udt => "UDT",
        }
    }

    /// FC, FB, SFC and SFB can be called.
    pub fn is_callable(self) -> bool {
        matches!(
            self,
            BlockKind::Fc | BlockKind::Fb | BlockKind::Sfc | BlockKind::Sfb
        )
    }
}

/// The access size of an address.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Size {
    Bit,
    Byte,
    Word,
    Dword,
    /// Timers, counters and blocks have no size.
    None,
}

/// One area identifier: its spelling in both sets, area and size.
struct AreaName {
    simatic: &'static str,
    international: &'static str,
    area: Area,
    size: Size,
    /// What the area means, for HG4102.
    meaning: &'static str,
}

const fn an(
    simatic: &'static str,
    international: &'static str,
    area: Area,
    size: Size,
    meaning: &'static str,
) -> AreaName {
    AreaName {
        simatic,
        international,
        area,
        size,
        meaning,
    }
}

/// Area identifiers of Appendix A.2, plus the bare peripheral areas (always malformed).
const AREA_NAMES: &[AreaName] = &[
    an("E", "I", Area::Input, Size::Bit, "input"),
    an("A", "Q", Area::Output, Size::Bit, "output"),
    an("M", "M", Area::Memory, Size::Bit, "bit memory"),
    an("L", "L", Area::Local, Size::Bit, "local data"),
    an("EB", "IB", Area::Input, Size::Byte, "input byte"),
    an("EW", "IW", Area::Input, Size::Word, "input word"),
    an("ED", "ID", Area::Input, Size::Dword, "input double word"),
    an("AB", "QB", Area::Output, Size::Byte, "output byte"),
    an("AW", "QW", Area::Output, Size::Word, "output word"),
    an("AD", "QD", Area::Output, Size::Dword, "output double word"),
    an("MB", "MB", Area::Memory, Size::Byte, "memory byte"),
    an("MW", "MW", Area::Memory, Size::Word, "memory word"),
    an("MD", "MD", Area::Memory, Size::Dword, "memory double word"),
    an("LB", "LB", Area::Local, Size::Byte, "local data byte"),
    an("LW", "LW", Area::Local, Size::Word, "local data word"),
    an(
        "LD",
        "LD",
        Area::Local,
        Size::Dword,
        "local data double word",
    ),
    an(
        "PE",
        "PI",
        Area::PeripheralInput,
        Size::Bit,
        "peripheral input",
    ),
    an(
        "PA",
        "PQ",
        Area::PeripheralOutput,
        Size::Bit,
        "peripheral output",
    ),
    an(
        "PEB",
        "PIB",
        Area::PeripheralInput,
        Size::Byte,
        "peripheral input byte",
    ),
    an(
        "PEW",
        "PIW",
        Area::PeripheralInput,
        Size::Word,
        "peripheral input word",
    ),
    an(
        "PED",
        "PID",
        Area::PeripheralInput,
        Size::Dword,
        "peripheral input double word",
    ),
    an(
        "PAB",
        "PQB",
        Area::PeripheralOutput,
        Size::Byte,
        "peripheral output byte",
    ),
    an(
        "PAW",
        "PQW",
        Area::PeripheralOutput,
        Size::Word,
        "peripheral output word",
    ),
    an(
        "PAD",
        "PQD",
        Area::PeripheralOutput,
        Size::Dword,
        "peripheral output double word",
    ),
    an("DBX", "DBX", Area::DataBlock, Size::Bit, "data block bit"),
    an("DBB", "DBB", Area::DataBlock, Size::Byte, "data block byte"),
    an("DBW", "DBW", Area::DataBlock, Size::Word, "data block word"),
    an(
        "DBD",
        "DBD",
        Area::DataBlock,
        Size::Dword,
        "data block double word",
    ),
    an(
        "DIX",
        "DIX",
        Area::InstanceData,
        Size::Bit,
        "instance data block bit",
    ),
    an(
        "DIB",
        "DIB",
        Area::InstanceData,
        Size::Byte,
        "instance data block byte",
    ),
    an(
        "DIW",
        "DIW",
        Area::InstanceData,
        Size::Word,
        "instance data block word",
    ),
    an(
        "DID",
        "DID",
        Area::InstanceData,
        Size::Dword,
        "instance data block double word",
    ),
    an("T", "T", Area::Timer, Size::None, "timer"),
    an("Z", "C", Area::Counter, Size::None, "counter"),
    an(
        "DB",
        "DB",
        Area::Block(BlockKind::Db),
        Size::None,
        "data block",
    ),
    an(
        "FC",
        "FC",
        Area::Block(BlockKind::Fc),
        Size::None,
        "function",
    ),
    an(
        "FB",
        "FB",
        Area::Block(BlockKind::Fb),
        Size::None,
        "function block",
    ),
    an(
        "SFC",
        "SFC",
        Area::Block(BlockKind::Sfc),
        Size::None,
        "system function",
    ),
    an(
        "SFB",
        "SFB",
        Area::Block(BlockKind::Sfb),
        Size::None,
        "system function block",
    ),
    an(
        "OB",
        "OB",
        Area::Block(BlockKind::Ob),
        Size::None,
        "organization block",
    ),
    an(
        "UDT",
        "UDT",
        Area::Block(BlockKind::Udt),
        Size::None,
        "user-defined data type",
    ),
];

/// How an area identifier reads in a set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AreaMatch {
    /// It is an area of the set.
    Active,
    /// It is an area only of the other set (HG4007).
    OtherSet,
}

fn find_area(word: &str, set: Mnemonic) -> Option<(&'static AreaName, AreaMatch)> {
    let upper = word.to_ascii_uppercase();
    let in_set = |a: &AreaName, s: Mnemonic| match s {
        Mnemonic::Simatic => a.simatic == upper,
        Mnemonic::International => a.international == upper,
    };
    if let Some(a) = AREA_NAMES.iter().find(|a| in_set(a, set)) {
        return Some((a, AreaMatch::Active));
    }
    AREA_NAMES
        .iter()
        .find(|a| in_set(a, set.other()))
        .map(|a| (a, AreaMatch::OtherSet))
}

/// Is `word` an address-area identifier of `set` (Appendix A.2; not the bare peripheral
/// `PE`/`PA`)?
pub fn is_area_word(word: &str, set: Mnemonic) -> bool {
    matches!(find_area(word, set), Some((a, AreaMatch::Active)) if !(a.size == Size::Bit && matches!(a.area, Area::PeripheralInput | Area::PeripheralOutput)))
}

/// Is `word` spelled like an address-area identifier of either set (Appendix A.2), the bare
/// peripheral `PE`/`PA`/`PI`/`PQ` included? (The formatter writes such words in upper case.)
pub fn is_area_spelling(word: &str) -> bool {
    find_area(word, Mnemonic::Simatic).is_some()
}

/// Is `word` a bit area of `set` (`E A M L`, `DBX`, `DIX`, or the bare peripheral `PE`/`PA`)?
pub fn is_bit_area(word: &str, set: Mnemonic) -> bool {
    matches!(find_area(word, set), Some((a, AreaMatch::Active)) if a.size == Size::Bit)
}

/// For an address-area identifier of `set` (Appendix A.2): its upper-case spelling and what
/// it means (`AB` → "output byte"), for HG4102.
pub fn area_meaning(word: &str, set: Mnemonic) -> Option<(&'static str, &'static str)> {
    if !is_area_word(word, set) {
        return None;
    }
    let (area, _) = find_area(word, set)?;
    let canonical = match set {
        Mnemonic::Simatic => area.simatic,
        Mnemonic::International => area.international,
    };
    Some((canonical, area.meaning))
}

/// A well-formed absolute address, normalised.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Address {
    pub area: Area,
    pub size: Size,
    /// `DBn.` prefix.
    pub db: Option<u32>,
    /// Byte, timer, counter or block number.
    pub number: u32,
    pub bit: Option<u32>,
}

impl Address {
    /// The type of an address (`language.md` §3.5, `diagnostics.md` §2.5).
    pub fn ty(&self) -> Type {
        match (self.area, self.size) {
            (Area::Timer, _) => Type::Timer,
            (Area::Counter, _) => Type::Counter,
            (Area::Block(_), _) => Type::Block,
            (_, Size::Bit) => Type::Bool,
            (_, Size::Byte) => Type::Byte,
            (_, Size::Word) => Type::Word,
            (_, Size::Dword) => Type::Dword,
            (_, Size::None) => Type::Block,
        }
    }

    /// Is it a bit address of the areas E A M (I Q M) or `DBn.DBX b.x` (HG5204)?
    pub fn is_global_bit(&self) -> bool {
        self.size == Size::Bit
            && (matches!(self.area, Area::Input | Area::Output | Area::Memory)
                || (self.area == Area::DataBlock && self.db.is_some()))
    }

    /// The address written in `set` (`E 1.0`, `DB10.DBX 5.1`).
    pub fn display(&self, set: Mnemonic) -> String {
        let name = AREA_NAMES
            .iter()
            .find(|a| a.area == self.area && a.size == self.size)
            .map_or("?", |a| match set {
                Mnemonic::Simatic => a.simatic,
                Mnemonic::International => a.international,
            });
        let mut text = String::new();
        if let Some(db) = self.db {
            text.push_str(&format!("DB{db}."));
        }
        text.push_str(name);
        text.push(' ');
        text.push_str(&self.number.to_string());
        if let Some(bit) = self.bit {
            text.push_str(&format!(".{bit}"));
        }
        text
    }

    /// The block kind of a block address.
    pub fn block_kind(&self) -> Option<BlockKind> {
        match self.area {
            Area::Block(kind) => Some(kind),
            _ => None,
        }
    }
}

/// Why an address-shaped operand is not a valid address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AddressError {
    /// HG4009: the bit number, as written, and its byte offset within the text.
    BitOutOfRange { bit: String, offset: usize },
    /// HG4010 with its reason.
    Malformed(String),
    /// HG4011: DBX without DB prefix.
    NeedsDb,
    /// HG4011: instance-DB operand.
    InstanceDb,
}

/// The result of reading an address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadAddress {
    pub address: Result<Address, AddressError>,
    /// The area identifiers that belong only to the other set (HG4007), by byte range within
    /// the compact text.
    pub other_set: bool,
}

/// Reads the compact text of an address (white space removed: `E1.0`, `DB10.DBX5.1`,
/// `MW10`, `FC10`) in `set`. Returns `None` if the text is not address-shaped at all.
pub fn read(compact: &str, set: Mnemonic) -> Option<ReadAddress> {
    let (db, rest) = match split_db_prefix(compact) {
        Some((db, rest)) => (Some(db), rest),
        None => (None, compact),
    };
    let letters_end = rest
        .find(|c: char| !c.is_ascii_alphabetic())
        .unwrap_or(rest.len());
    let (word, numbers) = rest.split_at(letters_end);
    let (area_name, matched) = find_area(word, set)?;
    let other_set = matched == AreaMatch::OtherSet;
    let finish = |address| Some(ReadAddress { address, other_set });
    if db.is_some() && area_name.area != Area::DataBlock {
        return None;
    }
    if numbers.is_empty() {
        return finish(Err(AddressError::Malformed(format!(
            "the area {} needs a number",
            word.to_ascii_uppercase()
        ))));
    }
    let (number_text, bit_text) = match numbers.split_once('.') {
        Some((n, b)) => (n, Some(b)),
        None => (numbers, None),
    };
    if number_text.is_empty() || !number_text.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    if let Some(bit) = bit_text
        && (bit.is_empty() || !bit.bytes().all(|b| b.is_ascii_digit()))
    {
        return None;
    }
    let number: u64 = number_text.parse().unwrap_or(u64::MAX);
    let area = area_name.area;
    let size = area_name.size;
    let is_bit_area = size == Size::Bit;
    let malformed = |reason: &str| finish(Err(AddressError::Malformed(reason.to_owned())));
    match area {
        Area::PeripheralInput | Area::PeripheralOutput if is_bit_area => {
            return malformed("peripheral areas have no bit addresses");
        }
        Area::InstanceData => return finish(Err(AddressError::InstanceDb)),
        Area::DataBlock if db.is_none() => return finish(Err(AddressError::NeedsDb)),
        _ => {}
    }
    if is_bit_area && bit_text.is_none() {
        return malformed(if area == Area::DataBlock {
            "a DBX address needs a bit number ('byte.bit')"
        } else {
            "a bit address needs a bit number ('byte.bit')"
        });
    }
    if !is_bit_area && bit_text.is_some() {
        let reason = match area {
            Area::Timer => "a timer has no bit number",
            Area::Counter => "a counter has no bit number",
            Area::Block(_) => "a block has no bit number",
            _ => "a byte, word or double-word address has no bit number",
        };
        return malformed(reason);
    }
    if number > 65535 {
        return malformed("the number is above 65535");
    }
    if area == Area::Block(BlockKind::Db) && number == 0 {
        return malformed("DB 0 does not exist");
    }
    if db == Some(0) {
        return malformed("DB 0 does not exist");
    }
    if db.is_some_and(|d| d > 65535) {
        return malformed("the number is above 65535");
    }
    let bit = match bit_text {
        Some(b) => {
            let value: u64 = b.parse().unwrap_or(u64::MAX);
            if value > 7 {
                let offset = compact.len() - b.len();
                return finish(Err(AddressError::BitOutOfRange {
                    bit: b.to_owned(),
                    offset,
                }));
            }
            Some(value as u32)
        }
        None => None,
    };
    finish(Ok(Address {
        area,
        size,
        db: db.map(|d| d.min(u32::MAX as u64) as u32),
        number: number as u32,
        bit,
    }))
}

/// `DB10.` prefix: returns the DB number and the rest.
fn split_db_prefix(text: &str) -> Option<(u64, &str)> {
    let upper = text.get(..2)?;
    if !upper.eq_ignore_ascii_case("DB") {
        return None;
    }
    let dot = text.find('.')?;
    let digits = &text[2..dot];
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let rest = &text[dot + 1..];
    let is_db_access = rest.len() >= 3 && rest[..3].to_ascii_uppercase().starts_with("DB");
    is_db_access.then(|| (digits.parse().unwrap_or(u64::MAX), rest))
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.display(Mnemonic::Simatic))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(text: &str, set: Mnemonic) -> Address {
        match read(text, set) {
            Some(ReadAddress { address: Ok(a), .. }) => a,
            other => panic!("{text}: {other:?}"),
        }
    }

    #[test]
    fn reads_addresses_of_both_sets() {
        assert_eq!(ok("E1.0", Mnemonic::Simatic).ty(), Type::Bool);
        assert_eq!(ok("MW10", Mnemonic::Simatic).ty(), Type::Word);
        assert_eq!(ok("T5", Mnemonic::Simatic).ty(), Type::Timer);
        assert_eq!(ok("Z3", Mnemonic::Simatic).ty(), Type::Counter);
        assert_eq!(ok("C3", Mnemonic::International).ty(), Type::Counter);
        assert_eq!(ok("DB10.DBX5.1", Mnemonic::Simatic).db, Some(10));
        assert_eq!(ok("DB10.DBW4", Mnemonic::Simatic).ty(), Type::Word);
        assert_eq!(
            ok("FC10", Mnemonic::Simatic).block_kind(),
            Some(BlockKind::Fc)
        );
        assert_eq!(
            ok("I1.0", Mnemonic::International),
            ok("E1.0", Mnemonic::Simatic)
        );
        let other = read("I1.0", Mnemonic::Simatic).expect("address");
        assert!(other.other_set);
    }

    #[test]
    fn reports_malformed_addresses() {
        let err = |t: &str| read(t, Mnemonic::Simatic).and_then(|r| r.address.err());
        assert!(matches!(err("M10"), Some(AddressError::Malformed(_))));
        assert!(matches!(err("MW10.1"), Some(AddressError::Malformed(_))));
        assert!(matches!(
            err("E1.8"),
            Some(AddressError::BitOutOfRange { .. })
        ));
        assert!(matches!(err("DBX5.0"), Some(AddressError::NeedsDb)));
        assert!(matches!(err("DIX5.0"), Some(AddressError::InstanceDb)));
        assert!(matches!(err("DB0"), Some(AddressError::Malformed(_))));
        assert!(matches!(err("MW70000"), Some(AddressError::Malformed(_))));
        assert!(matches!(err("PE1.0"), Some(AddressError::Malformed(_))));
        assert!(read("Motor", Mnemonic::Simatic).is_none());
    }
}
