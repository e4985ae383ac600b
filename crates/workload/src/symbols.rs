//! Absolute addresses and global symbols: an allocator that never hands out the same address
//! twice (HG6002), and a symbol table with unique, valid names of at most 24 characters
//! (HG6003, HG6006, HG11xx).

use std::collections::HashSet;
use std::fmt::Write;

use crate::mnemonic::Mnemonic;

/// What kind of operand to allocate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    InputBit,
    OutputBit,
    MemoryBit,
    /// A memory word with a 16-bit type (`INT`, `WORD`).
    MemoryWord(&'static str),
    /// A memory double word with a 32-bit type (`TIME`, `REAL`, `DINT`).
    MemoryDword(&'static str),
    InputWord(&'static str),
    OutputWord(&'static str),
    Timer,
    Counter,
}

/// Hands out distinct absolute addresses, per area.
#[derive(Debug, Clone)]
pub(crate) struct Addresses {
    input_bit: usize,
    output_bit: usize,
    memory_bit: usize,
    memory_byte: usize,
    input_word: usize,
    output_word: usize,
    timer: usize,
    counter: usize,
}

impl Addresses {
    /// Bit memory starts at `M 100.0`; memory words and double words at `MB 1000`, so that the
    /// two never overlap.
    pub(crate) fn new() -> Addresses {
        Addresses {
            input_bit: 0,
            output_bit: 0,
            memory_bit: 800,
            memory_byte: 1000,
            input_word: 512,
            output_word: 512,
            timer: 1,
            counter: 1,
        }
    }

    /// The next address of `kind`, written in mnemonic `m`, and its default type.
    pub(crate) fn next(&mut self, kind: Kind, m: Mnemonic) -> (String, &'static str) {
        fn bit(counter: &mut usize) -> (usize, usize) {
            let b = *counter;
            *counter += 1;
            (b / 8, b % 8)
        }
        match kind {
            Kind::InputBit => {
                let (byte, b) = bit(&mut self.input_bit);
                (format!("{} {byte}.{b}", m.area("E")), "BOOL")
            }
            Kind::OutputBit => {
                let (byte, b) = bit(&mut self.output_bit);
                (format!("{} {byte}.{b}", m.area("A")), "BOOL")
            }
            Kind::MemoryBit => {
                let (byte, b) = bit(&mut self.memory_bit);
                (format!("M {byte}.{b}"), "BOOL")
            }
            Kind::MemoryWord(ty) => {
                let byte = self.memory_byte;
                self.memory_byte += 2;
                (format!("MW {byte}"), ty)
            }
            Kind::MemoryDword(ty) => {
                let byte = self.memory_byte;
                self.memory_byte += 4;
                (format!("MD {byte}"), ty)
            }
            Kind::InputWord(ty) => {
                let byte = self.input_word;
                self.input_word += 2;
                (format!("{} {byte}", m.area("EW")), ty)
            }
            Kind::OutputWord(ty) => {
                let byte = self.output_word;
                self.output_word += 2;
                (format!("{} {byte}", m.area("AW")), ty)
            }
            Kind::Timer => {
                let n = self.timer;
                self.timer += 1;
                (format!("T {n}"), "TIMER")
            }
            Kind::Counter => {
                let n = self.counter;
                self.counter += 1;
                (format!("{} {n}", m.area("Z")), "COUNTER")
            }
        }
    }
}

#[derive(Debug, Clone)]
struct Symbol {
    /// As written: `Name` or `"Quoted name"`.
    name: String,
    address: String,
    ty: Option<&'static str>,
    comment: Option<String>,
}

/// A `symbols` table in the making.
#[derive(Debug, Clone)]
pub(crate) struct SymbolTable {
    symbols: Vec<Symbol>,
    names: HashSet<String>,
    pub(crate) addresses: Addresses,
}

impl SymbolTable {
    pub(crate) fn new() -> SymbolTable {
        SymbolTable {
            symbols: Vec::new(),
            names: HashSet::new(),
            addresses: Addresses::new(),
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.symbols.len()
    }

    /// Adds a symbol for a fresh address of `kind` and returns its name as written. The name is
    /// made valid and unique: at most 24 characters, no `__`, no trailing `_`.
    pub(crate) fn add(&mut self, wanted: &str, kind: Kind, comment: Option<String>) -> String {
        let (address, ty) = self.addresses.next(kind, Mnemonic::Simatic);
        // The type is written out for a third of the symbols; otherwise it is the default.
        let explicit =
            self.symbols.len().is_multiple_of(3) || !matches!(ty, "BOOL" | "TIMER" | "COUNTER");
        self.add_at(wanted, address, explicit.then_some(ty), comment)
    }

    /// Adds a symbol for a given address (block symbols `FC 10`, `DB 1`).
    pub(crate) fn add_at(
        &mut self,
        wanted: &str,
        address: String,
        ty: Option<&'static str>,
        comment: Option<String>,
    ) -> String {
        let name = self.unique_name(wanted);
        self.symbols.push(Symbol {
            name: name.clone(),
            address,
            ty,
            comment,
        });
        name
    }

    /// Adds a quoted symbol (`"Not Aus Halle 1"`), exempt from the name rules.
    pub(crate) fn add_quoted(
        &mut self,
        wanted: &str,
        kind: Kind,
        comment: Option<String>,
    ) -> String {
        let (address, ty) = self.addresses.next(kind, Mnemonic::Simatic);
        let mut name = wanted.to_string();
        let mut k = 2;
        while !self.names.insert(name.to_ascii_lowercase()) {
            name = format!("{wanted} {k}");
            k += 1;
        }
        let written = format!("\"{name}\"");
        self.symbols.push(Symbol {
            name: written.clone(),
            address,
            ty: Some(ty),
            comment,
        });
        written
    }

    fn unique_name(&mut self, wanted: &str) -> String {
        let clean = clean_name(wanted, 24);
        let mut name = clean.clone();
        let mut k = 2;
        while !self.names.insert(name.to_ascii_lowercase()) {
            let suffix = format!("_{k}");
            name = format!("{}{suffix}", clean_name(&clean, 24 - suffix.len()));
            k += 1;
        }
        name
    }

    /// The text of the `symbols` item, `:` aligned.
    pub(crate) fn render(&self, comment: &str) -> String {
        let width = self.symbols.iter().map(|s| s.name.len()).max().unwrap_or(0);
        let mut out = String::with_capacity(64 * self.symbols.len() + 64);
        writeln!(out, "// {comment}").unwrap();
        out.push_str("symbols <\n");
        for s in &self.symbols {
            write!(out, "  {:width$} : {}", s.name, s.address).unwrap();
            if let Some(ty) = s.ty {
                write!(out, " {ty}").unwrap();
            }
            if let Some(c) = &s.comment {
                write!(out, " \"{c}\"").unwrap();
            }
            out.push_str(";\n");
        }
        out.push_str(">\n");
        out
    }
}

/// `wanted` cut to at most `max` characters, with `__` collapsed and trailing `_` removed.
pub(crate) fn clean_name(wanted: &str, max: usize) -> String {
    let mut name = String::with_capacity(max);
    for c in wanted.chars() {
        if name.len() == max {
            break;
        }
        if c == '_' && name.ends_with('_') {
            continue;
        }
        name.push(c);
    }
    while name.ends_with('_') {
        name.pop();
    }
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_valid_and_unique() {
        let mut t = SymbolTable::new();
        let a = t.add("A_very_long_symbol_name_that_goes_on", Kind::InputBit, None);
        let b = t.add("A_very_long_symbol_name_that_goes_on", Kind::InputBit, None);
        assert!(a.len() <= 24 && b.len() <= 24, "{a} {b}");
        assert_ne!(a, b);
        assert!(!a.ends_with('_') && !b.contains("__"));
        assert_eq!(clean_name("X__y_", 24), "X_y");
    }

    #[test]
    fn addresses_are_distinct() {
        let mut a = Addresses::new();
        let x = a.next(Kind::InputBit, Mnemonic::Simatic).0;
        let y = a.next(Kind::InputBit, Mnemonic::Simatic).0;
        assert_eq!((x.as_str(), y.as_str()), ("E 0.0", "E 0.1"));
        assert_eq!(a.next(Kind::Counter, Mnemonic::International).0, "C 1");
    }
}
