//! Types, constants and addresses as the machine wants them: `lang::Type` → [`Ty`], checked
//! literals → [`Const`] (STL operands) or typed [`Value`]s (initial values, actuals, chart and
//! test constants, with the literal adaptation of `diagnostics.md` C.2/C.3), addresses →
//! [`Place`]s.

use higraph_runtime::program::{CounterId, MemArea, Place, TimerId, Width};
use higraph_runtime::value::{Const, Ty, Value, load_pattern};
use higraph_syntax::literal::{self, Acceptance, Literal, LiteralClass, LiteralValue};

use crate::address::{Address, Area, Size};
use crate::lang::Type;

/// The machine type of a language type; `None` for the block-interface-only types.
pub(crate) fn ty(t: Type) -> Option<Ty> {
    Some(match t {
        Type::Bool => Ty::Bool,
        Type::Byte => Ty::Byte,
        Type::Word => Ty::Word,
        Type::Dword => Ty::Dword,
        Type::Int => Ty::Int,
        Type::Dint => Ty::Dint,
        Type::Real => Ty::Real,
        Type::S5Time => Ty::S5Time,
        Type::Time => Ty::Time,
        Type::Date => Ty::Date,
        Type::TimeOfDay => Ty::TimeOfDay,
        Type::DateAndTime => Ty::DateAndTime,
        Type::Char => Ty::Char,
        Type::String(n) => Ty::String(n),
        Type::Timer => Ty::Timer,
        Type::Counter => Ty::Counter,
        Type::Pointer | Type::Any | Type::BlockFc | Type::BlockFb | Type::BlockDb | Type::Block => {
            return None;
        }
    })
}

/// The type name `literal::accepts` understands.
pub(crate) fn type_name(t: Ty) -> String {
    match t {
        Ty::String(n) => format!("STRING[{n}]"),
        other => other.to_string(),
    }
}

/// The place of an absolute address; `None` for instance data and block addresses.
pub(crate) fn place(a: &Address) -> Option<Place> {
    let area = match a.area {
        Area::Input | Area::PeripheralInput => MemArea::Input,
        Area::Output | Area::PeripheralOutput => MemArea::Output,
        Area::Memory => MemArea::Memory,
        Area::Local => MemArea::Local,
        Area::DataBlock => MemArea::Db(u16::try_from(a.db?).ok()?),
        Area::Timer => return Some(Place::Timer(TimerId(a.number))),
        Area::Counter => return Some(Place::Counter(CounterId(a.number))),
        Area::InstanceData | Area::Block(_) => return None,
    };
    let width = match a.size {
        Size::Bit => Width::Bit(u8::try_from(a.bit.unwrap_or(0)).ok()?.min(7)),
        Size::Byte => Width::Byte,
        Size::Word => Width::Word,
        Size::Dword => Width::Dword,
        Size::None => return None,
    };
    Some(Place::Mem {
        area,
        byte: a.number,
        width,
    })
}

/// The type of a literal without adaptation (C.1).
pub(crate) fn literal_ty(lit: &Literal) -> Option<Ty> {
    Some(match literal::literal_type(lit) {
        "BOOL" => Ty::Bool,
        "INT" => Ty::Int,
        "DINT" => Ty::Dint,
        "REAL" => Ty::Real,
        "BYTE" => Ty::Byte,
        "WORD" => Ty::Word,
        "DWORD" => Ty::Dword,
        "S5TIME" => Ty::S5Time,
        "TIME" => Ty::Time,
        "DATE" => Ty::Date,
        "TIME_OF_DAY" => Ty::TimeOfDay,
        "DATE_AND_TIME" => Ty::DateAndTime,
        "CHAR" => Ty::Char,
        "STRING" => match &lit.value {
            LiteralValue::Str(s) => Ty::String(s.chars().count().min(254) as u16),
            _ => Ty::String(254),
        },
        _ => return None,
    })
}

/// A checked literal as an STL constant.
pub(crate) fn constant(lit: &Literal) -> Option<Const> {
    Some(match &lit.value {
        LiteralValue::Bool(b) => Const::Bool(*b),
        LiteralValue::Int(v) => match lit.class {
            LiteralClass::LongInteger => Const::LongInt(*v),
            LiteralClass::Counter => Const::Counter(u32::try_from(*v).ok()?),
            _ => Const::Int(*v),
        },
        LiteralValue::Real(r) => Const::Real(*r),
        LiteralValue::Bits { value, .. } => Const::Bits(*value),
        LiteralValue::Tuple(bytes) => {
            Const::Bits(bytes.iter().fold(0u64, |acc, b| (acc << 8) | u64::from(*b)))
        }
        LiteralValue::Duration { millis } => match lit.class {
            LiteralClass::S5Time => Const::S5Time(*millis),
            _ => Const::Time(*millis),
        },
        LiteralValue::Date { year, month, day } => {
            Const::Date(days_since_1990(*year, *month, *day))
        }
        LiteralValue::TimeOfDay { millis } => Const::TimeOfDay(*millis),
        LiteralValue::Char(c) => Const::Chars(vec![u8::try_from(u32::from(*c)).unwrap_or(b'?')]),
        LiteralValue::Str(s) => Const::Chars(s.bytes().take(4).collect()),
        LiteralValue::Pointer(p) => {
            let area = match p.area {
                Some("E") | Some("I") => 0x81,
                Some("A") | Some("Q") => 0x82,
                Some("M") => 0x83,
                Some("DBX") => 0x84,
                Some("DIX") => 0x85,
                Some("L") => 0x86,
                _ => 0,
            };
            Const::Pointer {
                area,
                byte: u32::try_from(p.byte).unwrap_or(u32::MAX),
                bit: u8::try_from(p.bit.min(7)).unwrap_or(0),
            }
        }
        LiteralValue::DateAndTime { .. } => return None,
    })
}

/// The value of a literal in type `ty` (C.2: the type must accept the literal); `None` if it
/// does not fit.
pub(crate) fn value_in(lit: &Literal, ty: Ty) -> Option<Value> {
    if !matches!(ty, Ty::OpState | Ty::Timer | Ty::Counter)
        && literal::accepts(&type_name(ty), lit) != Acceptance::Accepted
    {
        return None;
    }
    let bits = || constant(lit).map(|c| load_pattern(&c));
    Some(match (ty, &lit.value) {
        (Ty::Bool, LiteralValue::Bool(b)) => Value::Bool(*b),
        (Ty::Int, LiteralValue::Int(v)) => Value::Int(i16::try_from(*v).ok()?),
        (Ty::Dint, LiteralValue::Int(v)) => Value::Dint(i32::try_from(*v).ok()?),
        (Ty::Byte, LiteralValue::Int(v)) => Value::Byte(u8::try_from(*v).ok()?),
        (Ty::Word, LiteralValue::Int(v)) if lit.class == LiteralClass::Integer => {
            Value::Word(u16::try_from(*v).ok()?)
        }
        (Ty::Dword, LiteralValue::Int(v)) => Value::Dword(u32::try_from(*v).ok()?),
        (Ty::Real, LiteralValue::Int(v)) => Value::Real(*v as f32),
        (Ty::Real, LiteralValue::Real(r)) => Value::Real(*r as f32),
        (Ty::Byte | Ty::Word | Ty::Dword, _) => Value::from_bits(ty, bits()?)?,
        (Ty::S5Time, _) => Value::S5Time(bits()? as u16),
        (Ty::Time, LiteralValue::Duration { millis }) => Value::Time(i32::try_from(*millis).ok()?),
        (Ty::Date, LiteralValue::Date { year, month, day }) => {
            Value::Date(u16::try_from(days_since_1990(*year, *month, *day)).ok()?)
        }
        (Ty::TimeOfDay, LiteralValue::TimeOfDay { millis }) => Value::TimeOfDay(*millis),
        (
            Ty::DateAndTime,
            LiteralValue::DateAndTime {
                year,
                month,
                day,
                millis,
            },
        ) => Value::DateAndTime(date_and_time(*year, *month, *day, *millis)),
        (Ty::Char, LiteralValue::Char(c)) => Value::Char(u8::try_from(u32::from(*c)).ok()?),
        (Ty::String(_), LiteralValue::Str(s)) => Value::String(s.clone()),
        (Ty::String(_), LiteralValue::Char(c)) => Value::String(c.to_string()),
        _ => return None,
    })
}

/// The type a literal takes in a chart or test comparison or assignment (C.3): an integer
/// literal adapts to the other side's type if that accepts it; every other literal has its
/// class's type.
pub(crate) fn adapted_ty(lit: &Literal, other: Option<Ty>) -> Option<Ty> {
    if lit.class != LiteralClass::Integer {
        return literal_ty(lit);
    }
    match other {
        Some(t @ (Ty::Int | Ty::Dint | Ty::Byte | Ty::Word | Ty::Dword | Ty::Real))
            if value_in(lit, t).is_some() =>
        {
            Some(t)
        }
        // Two integer literals, or a side that does not adapt: DINT (C.3).
        Some(_) => literal_ty(lit),
        None => Some(Ty::Dint),
    }
}

/// Days from 1990-01-01 to a date (negative before it).
pub(crate) fn days_since_1990(year: u16, month: u8, day: u8) -> i64 {
    days_from_civil(i64::from(year), i64::from(month), i64::from(day)) - days_from_civil(1990, 1, 1)
}

/// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's algorithm).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// S7's DATE_AND_TIME: BCD year (2 digits), month, day, hour, minute, second, then the
/// milliseconds (3 digits) and the weekday (1 = Sunday) in the last one and a half bytes.
fn date_and_time(year: u16, month: u8, day: u8, millis: u32) -> [u8; 8] {
    let bcd = |v: u32| -> u8 { (((v / 10) % 10) << 4 | (v % 10)) as u8 };
    let secs = millis / 1000;
    let ms = millis % 1000;
    let weekday = (days_from_civil(i64::from(year), i64::from(month), i64::from(day)) + 4)
        .rem_euclid(7) as u32
        + 1;
    [
        bcd(u32::from(year) % 100),
        bcd(u32::from(month)),
        bcd(u32::from(day)),
        bcd(secs / 3600),
        bcd((secs / 60) % 60),
        bcd(secs % 60),
        bcd(ms / 10),
        (((ms % 10) << 4) | weekday) as u8,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lit(text: &str) -> Literal {
        literal::check_literal(text).expect("valid literal")
    }

    #[test]
    fn dates_count_from_1990() {
        assert_eq!(days_since_1990(1990, 1, 1), 0);
        assert_eq!(days_since_1990(1990, 1, 2), 1);
        assert_eq!(days_since_1990(1991, 1, 1), 365);
        assert_eq!(days_since_1990(2000, 3, 1), 3712);
    }

    #[test]
    fn integer_literals_adapt_to_the_other_side() {
        assert_eq!(adapted_ty(&lit("5"), Some(Ty::Real)), Some(Ty::Real));
        assert_eq!(adapted_ty(&lit("5"), Some(Ty::Int)), Some(Ty::Int));
        assert_eq!(adapted_ty(&lit("70000"), Some(Ty::Int)), Some(Ty::Dint));
        assert_eq!(adapted_ty(&lit("5"), None), Some(Ty::Dint));
        assert_eq!(adapted_ty(&lit("T#1S"), Some(Ty::Int)), Some(Ty::Time));
        assert_eq!(value_in(&lit("5"), Ty::Real), Some(Value::Real(5.0)));
        assert_eq!(value_in(&lit("-1"), Ty::Word), None);
        assert_eq!(value_in(&lit("T#1S"), Ty::Time), Some(Value::Time(1000)));
        assert_eq!(value_in(&lit("TRUE"), Ty::Int), None);
    }
}
