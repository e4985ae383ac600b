//! Types and typed values of the simulated machine (`runtime.md` §1.1).

use std::fmt;

/// A data type the machine knows. Mirrors the language's types; the block-interface-only types
/// never reach the machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Ty {
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
    /// `STRING[n]`.
    String(u16),
    Timer,
    Counter,
    /// A chart's operating state (`Chart.state`).
    OpState,
}

impl Ty {
    /// The width in bits of a value of this type in memory or an accumulator (§1.1); `None`
    /// for types that are never loaded into an accumulator (DATE_AND_TIME, STRING) and for
    /// timers, counters and operating states.
    pub fn bits(self) -> Option<u32> {
        Some(match self {
            Ty::Bool => 1,
            Ty::Byte | Ty::Char => 8,
            Ty::Word | Ty::Int | Ty::S5Time | Ty::Date => 16,
            Ty::Dword | Ty::Dint | Ty::Real | Ty::Time | Ty::TimeOfDay => 32,
            Ty::DateAndTime | Ty::String(_) | Ty::Timer | Ty::Counter | Ty::OpState => {
                return None;
            }
        })
    }
}

impl fmt::Display for Ty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Ty::Bool => "BOOL",
            Ty::Byte => "BYTE",
            Ty::Word => "WORD",
            Ty::Dword => "DWORD",
            Ty::Int => "INT",
            Ty::Dint => "DINT",
            Ty::Real => "REAL",
            Ty::S5Time => "S5TIME",
            Ty::Time => "TIME",
            Ty::Date => "DATE",
            Ty::TimeOfDay => "TIME_OF_DAY",
            Ty::DateAndTime => "DATE_AND_TIME",
            Ty::Char => "CHAR",
            Ty::String(n) => return write!(f, "STRING[{n}]"),
            Ty::Timer => "TIMER",
            Ty::Counter => "COUNTER",
            Ty::OpState => "operating state",
        };
        f.write_str(name)
    }
}

/// A typed value: what a test reads and writes, what a chart expression computes.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Bool(bool),
    Byte(u8),
    Word(u16),
    Dword(u32),
    Int(i16),
    Dint(i32),
    Real(f32),
    /// The raw S5TIME pattern (base in bits 12–13, three BCD digits).
    S5Time(u16),
    /// Milliseconds.
    Time(i32),
    /// Days since 1990-01-01.
    Date(u16),
    /// Milliseconds since midnight.
    TimeOfDay(u32),
    /// The 8 BCD-coded bytes of S7's DATE_AND_TIME.
    DateAndTime([u8; 8]),
    Char(u8),
    String(String),
    /// A chart operating state by its number (§4.2, 1..16).
    OpState(u8),
}

impl Value {
    /// The type of the value (`STRING` values report their own length).
    pub fn ty(&self) -> Ty {
        match self {
            Value::Bool(_) => Ty::Bool,
            Value::Byte(_) => Ty::Byte,
            Value::Word(_) => Ty::Word,
            Value::Dword(_) => Ty::Dword,
            Value::Int(_) => Ty::Int,
            Value::Dint(_) => Ty::Dint,
            Value::Real(_) => Ty::Real,
            Value::S5Time(_) => Ty::S5Time,
            Value::Time(_) => Ty::Time,
            Value::Date(_) => Ty::Date,
            Value::TimeOfDay(_) => Ty::TimeOfDay,
            Value::DateAndTime(_) => Ty::DateAndTime,
            Value::Char(_) => Ty::Char,
            Value::String(s) => Ty::String(s.len().min(254) as u16),
            Value::OpState(_) => Ty::OpState,
        }
    }

    /// The zero of a type (§1.2): FALSE, 0, 0.0, T#0MS, ''.
    pub fn zero(ty: Ty) -> Value {
        match ty {
            Ty::Bool | Ty::Timer | Ty::Counter => Value::Bool(false),
            Ty::Byte => Value::Byte(0),
            Ty::Word => Value::Word(0),
            Ty::Dword => Value::Dword(0),
            Ty::Int => Value::Int(0),
            Ty::Dint => Value::Dint(0),
            Ty::Real => Value::Real(0.0),
            Ty::S5Time => Value::S5Time(0),
            Ty::Time => Value::Time(0),
            Ty::Date => Value::Date(0),
            Ty::TimeOfDay => Value::TimeOfDay(0),
            Ty::DateAndTime => Value::DateAndTime([0; 8]),
            Ty::Char => Value::Char(0),
            Ty::String(_) => Value::String(String::new()),
            Ty::OpState => Value::OpState(1),
        }
    }

    /// The value's bit pattern as it sits in memory or an accumulator, zero-extended to 32
    /// bits; `None` for DATE_AND_TIME, STRING and operating states.
    pub fn to_bits(&self) -> Option<u32> {
        Some(match *self {
            Value::Bool(b) => b as u32,
            Value::Byte(v) | Value::Char(v) => v as u32,
            Value::Word(v) | Value::S5Time(v) | Value::Date(v) => v as u32,
            Value::Int(v) => v as u16 as u32,
            Value::Dword(v) | Value::TimeOfDay(v) => v,
            Value::Dint(v) | Value::Time(v) => v as u32,
            Value::Real(v) => v.to_bits(),
            Value::DateAndTime(_) | Value::String(_) | Value::OpState(_) => return None,
        })
    }

    /// The value of type `ty` whose pattern is the low bits of `bits`; `None` for the types
    /// [`Value::to_bits`] does not cover.
    pub fn from_bits(ty: Ty, bits: u32) -> Option<Value> {
        Some(match ty {
            Ty::Bool | Ty::Timer | Ty::Counter => Value::Bool(bits & 1 != 0),
            Ty::Byte => Value::Byte(bits as u8),
            Ty::Char => Value::Char(bits as u8),
            Ty::Word => Value::Word(bits as u16),
            Ty::S5Time => Value::S5Time(bits as u16),
            Ty::Date => Value::Date(bits as u16),
            Ty::Int => Value::Int(bits as u16 as i16),
            Ty::Dword => Value::Dword(bits),
            Ty::TimeOfDay => Value::TimeOfDay(bits),
            Ty::Dint => Value::Dint(bits as i32),
            Ty::Time => Value::Time(bits as i32),
            Ty::Real => Value::Real(f32::from_bits(bits)),
            Ty::DateAndTime | Ty::String(_) | Ty::OpState => return None,
        })
    }
}

/// A constant as the lowering hands it over, before it becomes an accumulator pattern
/// ([`load_pattern`], `runtime.md` §1.1 "`L` of a constant").
#[derive(Debug, Clone, PartialEq)]
pub enum Const {
    /// A plain integer (−32768..32767 loads as 16 bit, others as 32 bit).
    Int(i64),
    /// `L#n`.
    LongInt(i64),
    /// `B#16#`, `W#16#`, `DW#16#`, `2#`, `B#(…)`: the value.
    Bits(u64),
    /// `C#n`: the decimal value, loaded as BCD.
    Counter(u32),
    /// `S5T#`: milliseconds.
    S5Time(i64),
    /// `T#`: milliseconds.
    Time(i64),
    /// `TOD#`: milliseconds since midnight.
    TimeOfDay(u32),
    /// `D#`: days since 1990-01-01.
    Date(i64),
    Real(f64),
    /// `'c'` … `'cccc'`: the character codes.
    Chars(Vec<u8>),
    /// `P#`: area code (16#81 E … 16#86 L, 0 for an area-less pointer), byte, bit.
    Pointer {
        area: u8,
        byte: u32,
        bit: u8,
    },
    Bool(bool),
}

/// The 32-bit pattern `L` loads for a constant (§1.1).
pub fn load_pattern(c: &Const) -> u32 {
    crate::stl::load_pattern(c)
}
