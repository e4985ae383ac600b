//! Checking of constants: the literal classes of `diagnostics.md` Appendix C.
//!
//! [`check_literal`] takes the text of one constant token — a typed constant (`B#16#FF`,
//! `T#5S`, `B#(1, 2)`, `P#M50.0`, ...), a number optionally preceded by `-`, a `'...'`
//! character or string constant, or `TRUE`/`FALSE` — and returns its [`LiteralClass`] and
//! checked [`LiteralValue`], or the HG0006 (malformed) / HG0007 (out of range) error with the
//! message of `diagnostics.md` §3.0.
//!
//! [`literal_type`] gives the type of a literal (C.1), [`accepts`] says whether a type accepts
//! a literal (C.2) and [`chart_literal_type`] implements the literal adaptation in charts (C.3).
//!
//! Decisions where the spec leaves room:
//!
//! * `_` is allowed between two digits in every numeric field (hex, binary, decimal, tuple
//!   elements, date and time-of-day fields) and additionally between two unit groups in `T#` and
//!   `S5T#`; it is not allowed in the byte and bit numbers of a `P#` constant (those are
//!   addresses, not numbers).
//! * Units of time constants are case-insensitive, like the prefixes (`T#5s`).
//! * Fractions of a millisecond in `T#`/`S5T#` (`T#1.0005S`) are well-formed; the value keeps
//!   whole milliseconds (truncated towards zero), but the range check is exact (`S5T#0.001MS` is
//!   not 0 and therefore out of range, `T#24D20H31M23S647.5MS` is above the maximum).
//! * `TOD#` and the time part of `DT#` take 1 to 3 fraction digits (`[.fff]`); their fields are
//!   limited one by one (hours 0..23, minutes and seconds 0..59), so `TOD#0:60:0` is out of range.
//!   Field widths are free (`D#1994-03-05`, `TOD#01:02:03`).
//! * In `B#( ... )` white space (spaces, tabs) is tolerated around every element, not only after
//!   commas; `B#()` and `B#( )` have zero elements.
//! * `P#` accepts the bit areas `E A M L I Q` of both mnemonic sets (which set is legal is decided
//!   in analysis, HG4007), `DBX` and `DIX` (`P#DBX5.0`), the fully qualified `P#DB10.DBX5.0`, and
//!   the area-less `P#0.0`. Spaces or tabs may stand between the area and the byte number
//!   (`P#M 100.0`, `P#DBX 8.6`: STEP 7 prints pointers so); the parser joins such a `P#M`
//!   token and the number after it on its line into one constant. The bit number is *not* checked here (a bit above 7 is HG4009, a byte
//!   number above 65535 is HG4010, both in analysis); the parts are returned in [`PointerValue`].
//! * An unclosed `'...` (which the lexer already reports as HG0005) gives an HG0006 error here;
//!   a caller should not report it a second time.
//! * Ranges in HG0007 messages are spelled in the literal's notation without its prefix:
//!   `(16#0 to 16#FF)`, `(0 to 999)`, `(10MS to 2H46M30S)`, `(1990-1-1 to 2168-12-31)`. Binary
//!   constants are limited by their digit count, so their range reads `(1 to 32 digits)`;
//!   strings read `(0 to 254)` (a number of characters, the template's bare bounds) or, for a
//!   character above U+00FF, `(U+0000 to U+00FF)`.

use std::fmt;

use crate::ErrorCode;

// ====================================================================================== types

/// The literal classes of `diagnostics.md` Appendix C.1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LiteralClass {
    /// `TRUE`, `FALSE`.
    Boolean,
    /// Optional `-`, then decimal digits.
    Integer,
    /// Decimal digits with a fraction and/or an exponent.
    Real,
    /// `B#16#h`, `BYTE#16#h`.
    ByteHex,
    /// `W#16#h`, `WORD#16#h`.
    WordHex,
    /// `DW#16#h`, `DWORD#16#h`.
    DwordHex,
    /// `2#` followed by binary digits.
    Binary,
    /// `B#(a,b)`, `B#(a,b,c,d)`, also with `BYTE#`.
    ByteTuple,
    /// `C#n`.
    Counter,
    /// `L#n`.
    LongInteger,
    /// `S5T#...`, `S5TIME#...`.
    S5Time,
    /// `T#...`, `TIME#...`.
    IecTime,
    /// `D#y-m-d`, `DATE#y-m-d`.
    Date,
    /// `TOD#h:m:s[.fff]`, `TIME_OF_DAY#...`.
    TimeOfDay,
    /// `DT#y-m-d-h:m:s[.fff]`, `DATE_AND_TIME#...`.
    DateAndTime,
    /// `'c'`: exactly one character.
    Character,
    /// `'...'` with 0 or 2 to 254 characters.
    String,
    /// `P#` followed by a bit address or by `byte.bit`.
    Pointer,
}

impl LiteralClass {
    /// Every literal class, in the order of Appendix C.1.
    pub const ALL: [LiteralClass; 18] = [
        LiteralClass::Boolean,
        LiteralClass::Integer,
        LiteralClass::Real,
        LiteralClass::ByteHex,
        LiteralClass::WordHex,
        LiteralClass::DwordHex,
        LiteralClass::Binary,
        LiteralClass::ByteTuple,
        LiteralClass::Counter,
        LiteralClass::LongInteger,
        LiteralClass::S5Time,
        LiteralClass::IecTime,
        LiteralClass::Date,
        LiteralClass::TimeOfDay,
        LiteralClass::DateAndTime,
        LiteralClass::Character,
        LiteralClass::String,
        LiteralClass::Pointer,
    ];

    /// The class name used as `{class}` in messages: the C.1 name in lower case (`"byte hex"`,
    /// `"S5 time"`, `"IEC time"`, `"time of day"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            LiteralClass::Boolean => "boolean",
            LiteralClass::Integer => "integer",
            LiteralClass::Real => "real",
            LiteralClass::ByteHex => "byte hex",
            LiteralClass::WordHex => "word hex",
            LiteralClass::DwordHex => "dword hex",
            LiteralClass::Binary => "binary",
            LiteralClass::ByteTuple => "byte tuple",
            LiteralClass::Counter => "counter",
            LiteralClass::LongInteger => "long integer",
            LiteralClass::S5Time => "S5 time",
            LiteralClass::IecTime => "IEC time",
            LiteralClass::Date => "date",
            LiteralClass::TimeOfDay => "time of day",
            LiteralClass::DateAndTime => "date and time",
            LiteralClass::Character => "character",
            LiteralClass::String => "string",
            LiteralClass::Pointer => "pointer",
        }
    }
}

impl fmt::Display for LiteralClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The parts of a `P#` constant. The numbers are not range-checked (HG4009 and HG4010 belong to
/// analysis); numbers too large for `u64` saturate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PointerValue {
    /// The data block number of `P#DB10.DBX5.0`.
    pub db: Option<u64>,
    /// The area in upper case (`"E"`, `"A"`, `"M"`, `"L"`, `"I"`, `"Q"`, `"DBX"`, `"DIX"`), or
    /// `None` for the area-less `P#byte.bit`.
    pub area: Option<&'static str>,
    /// The byte number.
    pub byte: u64,
    /// The bit number (may be above 7; that is HG4009).
    pub bit: u64,
}

/// A checked constant value.
#[derive(Debug, Clone, PartialEq)]
pub enum LiteralValue {
    /// `TRUE` / `FALSE`.
    Bool(bool),
    /// Integer, counter and long integer constants.
    Int(i64),
    /// Real constants.
    Real(f64),
    /// Hex and binary constants: the value and the number of digits written (without `_`,
    /// leading zeros included).
    Bits { value: u64, digits: u32 },
    /// Byte tuples: the 2 or 4 elements.
    Tuple(Vec<u8>),
    /// S5 and IEC time constants, in whole milliseconds (fractions truncated towards zero).
    Duration { millis: i64 },
    /// A date.
    Date { year: u16, month: u8, day: u8 },
    /// A time of day, in milliseconds since midnight.
    TimeOfDay { millis: u32 },
    /// A date and time; `millis` is the time of day in milliseconds since midnight.
    DateAndTime {
        year: u16,
        month: u8,
        day: u8,
        millis: u32,
    },
    /// A character constant (`''''` is the quote).
    Char(char),
    /// A string constant, with `''` already turned into `'`.
    Str(String),
    /// A `P#` constant.
    Pointer(PointerValue),
}

/// A checked constant: its class and value.
#[derive(Debug, Clone, PartialEq)]
pub struct Literal {
    /// The literal class (C.1).
    pub class: LiteralClass,
    /// The value.
    pub value: LiteralValue,
}

/// The two kinds of constant errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LiteralErrorCode {
    /// HG0006: a malformed constant.
    Malformed,
    /// HG0007: a well-formed constant outside the range of its class.
    OutOfRange,
}

impl LiteralErrorCode {
    /// The diagnostic code: HG0006 or HG0007.
    pub fn error_code(self) -> ErrorCode {
        match self {
            LiteralErrorCode::Malformed => ErrorCode::HG0006,
            LiteralErrorCode::OutOfRange => ErrorCode::HG0007,
        }
    }
}

/// Why a constant was rejected, with the complete diagnostic message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LiteralError {
    /// HG0006 or HG0007.
    pub code: LiteralErrorCode,
    /// The class the constant was read as; `None` when it could not be told (unknown prefix).
    pub class: Option<LiteralClass>,
    /// The message, following the templates of HG0006 and HG0007.
    pub message: String,
}

impl fmt::Display for LiteralError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.code.error_code(), self.message)
    }
}

impl std::error::Error for LiteralError {}

/// `invalid {class} constant '{text}': {reason}` (HG0006).
fn malformed(class: LiteralClass, text: &str, reason: impl fmt::Display) -> LiteralError {
    LiteralError {
        code: LiteralErrorCode::Malformed,
        class: Some(class),
        message: format!("invalid {} constant '{text}': {reason}", class.name()),
    }
}

/// HG0006 for a constant whose class cannot be told: `invalid typed constant ...`.
fn malformed_typed(text: &str, reason: impl fmt::Display) -> LiteralError {
    LiteralError {
        code: LiteralErrorCode::Malformed,
        class: None,
        message: format!("invalid typed constant '{text}': {reason}"),
    }
}

/// `{text} is out of range for {class} ({min} to {max})` (HG0007).
fn out_of_range(class: LiteralClass, text: &str, min: &str, max: &str) -> LiteralError {
    LiteralError {
        code: LiteralErrorCode::OutOfRange,
        class: Some(class),
        message: format!(
            "{text} is out of range for {} ({min} to {max})",
            class.name()
        ),
    }
}

/// `{text} is not a valid date` (HG0007).
fn invalid_date(class: LiteralClass, text: &str) -> LiteralError {
    LiteralError {
        code: LiteralErrorCode::OutOfRange,
        class: Some(class),
        message: format!("{text} is not a valid date"),
    }
}

fn ok(class: LiteralClass, value: LiteralValue) -> Result<Literal, LiteralError> {
    Ok(Literal { class, value })
}

// ====================================================================================== entry

/// Checks the text of one constant token: a `TYPED_CONST` token (`B#16#FF`, `T#5S`, `16#FF`,
/// `B#(1, 2)`, `P#M50.0`, ...), a `NUMBER` token optionally preceded by `-` (`-5`), a `CHAR`
/// token (`'A'`, `'it''s'`, `''`), or the words `TRUE`/`FALSE` (case-insensitive).
///
/// Returns the class and value, or the HG0006/HG0007 error. Never panics.
pub fn check_literal(text: &str) -> Result<Literal, LiteralError> {
    if text.starts_with('\'') {
        return check_quoted(text);
    }
    if text.eq_ignore_ascii_case("TRUE") {
        return ok(LiteralClass::Boolean, LiteralValue::Bool(true));
    }
    if text.eq_ignore_ascii_case("FALSE") {
        return ok(LiteralClass::Boolean, LiteralValue::Bool(false));
    }
    if let Some((prefix, body)) = text.split_once('#') {
        return check_typed(text, prefix, body);
    }
    if text.starts_with('-') || text.starts_with(|c: char| c.is_ascii_digit()) {
        return check_number(text);
    }
    Err(malformed_typed(text, "not a constant"))
}

/// Dispatches a typed constant on its (case-insensitive) prefix.
fn check_typed(text: &str, prefix: &str, body: &str) -> Result<Literal, LiteralError> {
    match prefix.to_ascii_uppercase().as_str() {
        "B" | "BYTE" => check_byte(text, prefix, body),
        "W" | "WORD" => check_hex_prefixed(text, prefix, body, LiteralClass::WordHex),
        "DW" | "DWORD" => check_hex_prefixed(text, prefix, body, LiteralClass::DwordHex),
        "2" => check_binary(text, body),
        "C" => check_counter(text, body),
        "L" => check_long(text, body),
        "S5T" | "S5TIME" => check_s5_time(text, body),
        "T" | "TIME" => check_iec_time(text, body),
        "D" | "DATE" => check_date(text, body),
        "TOD" | "TIME_OF_DAY" => check_time_of_day(text, body),
        "DT" | "DATE_AND_TIME" => check_date_and_time(text, body),
        "P" => check_pointer(text, body),
        "" => Err(malformed_typed(text, "missing prefix before '#'")),
        p if p.bytes().all(|b| b.is_ascii_digit()) => Err(malformed_typed(
            text,
            "a number followed by '#' must be '2#'",
        )),
        _ => Err(malformed_typed(
            text,
            format_args!("unknown prefix '{prefix}#'"),
        )),
    }
}

// ====================================================================================== digits

/// Why a run of digits is malformed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DigitError {
    /// No digits at all.
    Empty,
    /// A letter or digit that is not a digit of the radix.
    Radix(char),
    /// Any other character.
    Unexpected(char),
    /// An `_` that does not stand between two digits.
    Underscore,
}

impl DigitError {
    /// The standard HG0006 reason.
    fn reason(self, radix: u32) -> String {
        match self {
            DigitError::Empty => "empty body".to_owned(),
            DigitError::Radix(c) => format!("digit '{c}' outside radix {radix}"),
            DigitError::Unexpected(c) => format!("unexpected character '{c}'"),
            DigitError::Underscore => UNDERSCORE_REASON.to_owned(),
        }
    }
}

const UNDERSCORE_REASON: &str = "'_' must stand between two digits";
const TIME_UNDERSCORE_REASON: &str = "'_' must stand between two digits or two unit groups";

/// A run of digits: the value (saturating at `u128::MAX`) and the number of digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Digits {
    value: u128,
    count: usize,
}

/// Reads all of `s` as digits of `radix`; `_` may stand between two digits when `underscores`.
fn parse_digits(s: &str, radix: u32, underscores: bool) -> Result<Digits, DigitError> {
    let mut value: u128 = 0;
    let mut count = 0usize;
    let mut prev_digit = false;
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        if let Some(d) = c.to_digit(radix) {
            value = value
                .saturating_mul(u128::from(radix))
                .saturating_add(u128::from(d));
            count += 1;
            prev_digit = true;
            continue;
        }
        if c == '_' && underscores {
            let next_digit = chars.peek().is_some_and(|n| n.is_digit(radix));
            if !(prev_digit && next_digit) {
                return Err(DigitError::Underscore);
            }
            prev_digit = false;
            continue;
        }
        if c == '_' || !c.is_alphanumeric() {
            return Err(DigitError::Unexpected(c));
        }
        return Err(DigitError::Radix(c));
    }
    if count == 0 {
        Err(DigitError::Empty)
    } else {
        Ok(Digits { value, count })
    }
}

/// Saturating conversion of a digit count for [`LiteralValue::Bits`].
fn digit_count(count: usize) -> u32 {
    u32::try_from(count).unwrap_or(u32::MAX)
}

// ====================================================================================== numbers

/// A plain number, optionally negative: integer or real.
fn check_number(text: &str) -> Result<Literal, LiteralError> {
    let (negative, unsigned) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    let is_real = unsigned.contains(['.', 'e', 'E']);
    if !is_real {
        return check_integer(text, negative, unsigned);
    }
    check_real(text, unsigned)
}

/// Decimal digits without fraction or exponent; range DINT.
fn check_integer(text: &str, negative: bool, digits: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::Integer;
    let parsed = parse_digits(digits, 10, true).map_err(|e| match e {
        DigitError::Empty => malformed(class, text, "missing digits"),
        e => malformed(class, text, e.reason(10)),
    })?;
    match signed_dint(negative, parsed.value) {
        Some(v) => ok(class, LiteralValue::Int(v)),
        None => Err(out_of_range(class, text, DINT_MIN, DINT_MAX)),
    }
}

const DINT_MIN: &str = "-2147483648";
const DINT_MAX: &str = "2147483647";

/// The signed value if it lies in the DINT range.
fn signed_dint(negative: bool, magnitude: u128) -> Option<i64> {
    let limit: u128 = if negative { 1 << 31 } else { (1 << 31) - 1 };
    if magnitude > limit {
        return None;
    }
    let v = i64::try_from(magnitude).ok()?;
    Some(if negative { -v } else { v })
}

/// The largest magnitude of a REAL constant.
const REAL_MAX: f64 = 3.402823e38;

/// `digits [. digits] [e [+-] digits]` with a fraction or an exponent.
fn check_real(text: &str, unsigned: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::Real;
    let (mantissa, exponent) = match unsigned.find(['e', 'E']) {
        Some(i) => (&unsigned[..i], Some(&unsigned[i + 1..])),
        None => (unsigned, None),
    };
    let (int_part, frac_part) = match mantissa.split_once('.') {
        Some((i, f)) => (i, Some(f)),
        None => (mantissa, None),
    };
    let field = |s: &str, missing: &str| {
        parse_digits(s, 10, true).map_err(|e| match e {
            DigitError::Empty => malformed(class, text, missing),
            e => malformed(class, text, e.reason(10)),
        })
    };
    field(int_part, "missing digits before the fraction or exponent")?;
    if let Some(f) = frac_part {
        field(f, "missing digits after '.'")?;
    }
    if let Some(e) = exponent {
        let e = e.strip_prefix(['+', '-']).unwrap_or(e);
        field(e, "missing exponent digits")?;
    }
    let cleaned: String = text.chars().filter(|&c| c != '_').collect();
    let value: f64 = cleaned
        .parse()
        .map_err(|_| malformed(class, text, "not a number"))?;
    if !value.is_finite() || value.abs() > REAL_MAX {
        return Err(out_of_range(class, text, "-3.402823e+38", "3.402823e+38"));
    }
    ok(class, LiteralValue::Real(value))
}

// ============================================================================ hex, binary

/// `B#16#h` (byte hex) or `B#(a,b[,c,d])` (byte tuple).
fn check_byte(text: &str, prefix: &str, body: &str) -> Result<Literal, LiteralError> {
    if body.starts_with('(') {
        return check_tuple(text, body);
    }
    check_hex_prefixed(text, prefix, body, LiteralClass::ByteHex)
}

/// The `16#h` body of a byte, word or dword hex constant.
fn check_hex_prefixed(
    text: &str,
    prefix: &str,
    body: &str,
    class: LiteralClass,
) -> Result<Literal, LiteralError> {
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    let Some(hex) = body.strip_prefix("16#") else {
        let expected = if class == LiteralClass::ByteHex {
            "'16#' or '('"
        } else {
            "'16#'"
        };
        return Err(malformed(
            class,
            text,
            format_args!("expected {expected} after '{prefix}#'"),
        ));
    };
    let digits = parse_digits(hex, 16, true).map_err(|e| malformed(class, text, e.reason(16)))?;
    let (max, max_text) = match class {
        LiteralClass::ByteHex => (0xFF, "16#FF"),
        LiteralClass::WordHex => (0xFFFF, "16#FFFF"),
        _ => (0xFFFF_FFFF, "16#FFFF_FFFF"),
    };
    match u64::try_from(digits.value) {
        Ok(value) if value <= max => ok(
            class,
            LiteralValue::Bits {
                value,
                digits: digit_count(digits.count),
            },
        ),
        _ => Err(out_of_range(class, text, "16#0", max_text)),
    }
}

/// `2#` followed by at most 32 binary digits.
fn check_binary(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::Binary;
    let digits = parse_digits(body, 2, true).map_err(|e| malformed(class, text, e.reason(2)))?;
    match u64::try_from(digits.value) {
        Ok(value) if digits.count <= 32 => ok(
            class,
            LiteralValue::Bits {
                value,
                digits: digit_count(digits.count),
            },
        ),
        _ => Err(out_of_range(class, text, "1", "32 digits")),
    }
}

/// `(a,b)` or `(a,b,c,d)` with decimal elements 0 to 255.
fn check_tuple(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::ByteTuple;
    let inner = &body[1..]; // `body` starts with the ASCII '('.
    let Some((inner, after)) = inner.split_once(')') else {
        return Err(malformed(class, text, "missing ')'"));
    };
    if !after.is_empty() {
        return Err(malformed(class, text, "unexpected text after ')'"));
    }
    let is_blank = |c: char| c == ' ' || c == '\t';
    let mut values = Vec::new();
    if !inner.trim_matches(is_blank).is_empty() {
        for element in inner.split(',') {
            let element = element.trim_matches(is_blank);
            let digits = parse_digits(element, 10, true).map_err(|e| match e {
                DigitError::Empty => malformed(class, text, "empty element"),
                e => malformed(class, text, e.reason(10)),
            })?;
            values.push(digits.value);
        }
    }
    if values.len() != 2 && values.len() != 4 {
        return Err(malformed(class, text, "a byte tuple has 2 or 4 elements"));
    }
    let bytes: Option<Vec<u8>> = values.iter().map(|&v| u8::try_from(v).ok()).collect();
    match bytes {
        Some(bytes) => ok(class, LiteralValue::Tuple(bytes)),
        None => Err(out_of_range(class, text, "0", "255")),
    }
}

// ====================================================================================== C#, L#

/// `C#n`, decimal, 0 to 999.
fn check_counter(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::Counter;
    let digits = parse_digits(body, 10, true).map_err(|e| malformed(class, text, e.reason(10)))?;
    match i64::try_from(digits.value) {
        Ok(v) if v <= 999 => ok(class, LiteralValue::Int(v)),
        _ => Err(out_of_range(class, text, "0", "999")),
    }
}

/// `L#n`, signed decimal, DINT range.
fn check_long(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::LongInteger;
    let (negative, unsigned) = match body.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, body),
    };
    let digits = parse_digits(unsigned, 10, true).map_err(|e| match e {
        DigitError::Empty if negative => malformed(class, text, "missing digits after '-'"),
        e => malformed(class, text, e.reason(10)),
    })?;
    match signed_dint(negative, digits.value) {
        Some(v) => ok(class, LiteralValue::Int(v)),
        None => Err(out_of_range(class, text, DINT_MIN, DINT_MAX)),
    }
}

// ====================================================================================== time

/// A unit of a time constant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Unit {
    D,
    H,
    M,
    S,
    Ms,
}

impl Unit {
    fn from_letters(letters: &str) -> Option<Unit> {
        Some(match letters.to_ascii_uppercase().as_str() {
            "D" => Unit::D,
            "H" => Unit::H,
            "M" => Unit::M,
            "S" => Unit::S,
            "MS" => Unit::Ms,
            _ => return None,
        })
    }

    fn millis(self) -> u64 {
        match self {
            Unit::D => 86_400_000,
            Unit::H => 3_600_000,
            Unit::M => 60_000,
            Unit::S => 1_000,
            Unit::Ms => 1,
        }
    }
}

/// The exact total of a time constant: whole milliseconds (saturating) and whether a fraction
/// of a millisecond remains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct TimeTotal {
    whole: u128,
    sub_milli: bool,
}

impl TimeTotal {
    /// Is the exact value at most `limit` milliseconds?
    fn at_most(self, limit: u128) -> bool {
        self.whole < limit || (self.whole == limit && !self.sub_milli)
    }

    fn is_zero(self) -> bool {
        self.whole == 0 && !self.sub_milli
    }
}

/// Reads `[digits]` with `_` between digits from the front of `s`; returns the digits (without
/// `_`) and the rest. An `_` not followed by a digit ends the run (and is reported by the caller).
fn take_digits(s: &str) -> (String, &str) {
    let mut digits = String::new();
    let mut end = 0;
    let bytes = s.as_bytes();
    while end < bytes.len() {
        let b = bytes[end];
        if b.is_ascii_digit() {
            digits.push(char::from(b));
            end += 1;
        } else if b == b'_'
            && !digits.is_empty()
            && bytes.get(end + 1).is_some_and(u8::is_ascii_digit)
            && bytes
                .get(end.wrapping_sub(1))
                .is_some_and(u8::is_ascii_digit)
        {
            end += 1;
        } else {
            break;
        }
    }
    (digits, &s[end..])
}

/// The reason for a character that cannot continue a time constant.
fn unexpected_in_time(c: char) -> String {
    if c == '_' {
        TIME_UNDERSCORE_REASON.to_owned()
    } else {
        format!("unexpected character '{c}'")
    }
}

/// Parses the unit groups of a `T#`/`S5T#` body (without sign): numbers, each followed by a
/// unit of `allowed`, in order, each once; a fraction only on the last group; `_` between two
/// digits or two groups.
fn parse_time_groups(body: &str, allowed: &[Unit], class_name: &str) -> Result<TimeTotal, String> {
    let mut rest = body;
    let mut last_unit: Option<Unit> = None;
    let mut fraction_seen = false;
    let mut total = TimeTotal {
        whole: 0,
        sub_milli: false,
    };
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix('_') {
            // Only between two groups: after a unit, before a digit.
            let before_ok = last_unit.is_some() && body.len() > rest.len();
            if !(before_ok && after.starts_with(|c: char| c.is_ascii_digit())) {
                return Err(TIME_UNDERSCORE_REASON.to_owned());
            }
            rest = after;
        }
        let (int_digits, after_int) = take_digits(rest);
        if int_digits.is_empty() {
            return Err(match after_int.chars().next() {
                Some('.') => "missing digits before '.'".to_owned(),
                Some(c) if c.is_alphabetic() => format!("missing number before '{c}'"),
                Some(c) => unexpected_in_time(c),
                None => "empty body".to_owned(),
            });
        }
        let (frac_digits, after_number) = match after_int.strip_prefix('.') {
            Some(after_dot) => {
                let (f, r) = take_digits(after_dot);
                if f.is_empty() {
                    return Err("missing digits after '.'".to_owned());
                }
                (Some(f), r)
            }
            None => (None, after_int),
        };
        let letters_end = after_number
            .find(|c: char| !c.is_alphabetic())
            .unwrap_or(after_number.len());
        let (letters, after_unit) = after_number.split_at(letters_end);
        if letters.is_empty() {
            return Err(match after_number.chars().next() {
                None => format!("missing unit after '{int_digits}'"),
                Some(c) => unexpected_in_time(c),
            });
        }
        let unit =
            Unit::from_letters(letters).ok_or_else(|| format!("unknown unit '{letters}'"))?;
        if !allowed.contains(&unit) {
            return Err(format!("unit '{letters}' not allowed in {class_name}"));
        }
        if last_unit.is_some_and(|last| last >= unit) {
            return Err(format!("unit '{letters}' repeated or out of order"));
        }
        if fraction_seen {
            return Err("fraction only allowed on the last unit".to_owned());
        }
        fraction_seen = frac_digits.is_some();
        add_group(&mut total, &int_digits, frac_digits.as_deref(), unit);
        last_unit = Some(unit);
        rest = after_unit;
    }
    Ok(total)
}

/// Adds `int.frac` units to `total`, exactly.
fn add_group(total: &mut TimeTotal, int_digits: &str, frac_digits: Option<&str>, unit: Unit) {
    let unit_ms = unit.millis();
    let int_value = int_digits.bytes().fold(0u128, |acc, b| {
        acc.saturating_mul(10)
            .saturating_add(u128::from(b.saturating_sub(b'0')))
    });
    let mut whole = int_value.saturating_mul(u128::from(unit_ms));
    if let Some(frac) = frac_digits {
        // unit_ms * 0.frac, by multiplying the decimal digits from the right: the final carry
        // is the whole part, the produced digits are the remainder.
        let mut carry = 0u64;
        for b in frac.bytes().rev() {
            let p = u64::from(b.saturating_sub(b'0')) * unit_ms + carry;
            total.sub_milli |= !is_multiple(u128::from(p), 10);
            carry = p / 10;
        }
        whole = whole.saturating_add(u128::from(carry));
    }
    total.whole = total.whole.saturating_add(whole);
}

/// `S5T#`: unit groups `H M S MS`; 0 or 10 ms to 2H46M30S.
fn check_s5_time(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::S5Time;
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    if body.starts_with('-') {
        return Err(malformed(class, text, "an S5 time cannot be negative"));
    }
    let total = parse_time_groups(body, &[Unit::H, Unit::M, Unit::S, Unit::Ms], class.name())
        .map_err(|reason| malformed(class, text, reason))?;
    if !(total.is_zero() || (total.whole >= 10 && total.at_most(9_990_000))) {
        return Err(out_of_range(class, text, "10MS", "2H46M30S"));
    }
    let millis = i64::try_from(total.whole).unwrap_or(i64::MAX);
    ok(class, LiteralValue::Duration { millis })
}

/// `T#`: optional `-`, unit groups `D H M S MS`; −24D20H31M23S648MS to 24D20H31M23S647MS.
fn check_iec_time(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::IecTime;
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    let (negative, unsigned) = match body.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, body),
    };
    if unsigned.is_empty() {
        return Err(malformed(class, text, "missing value after '-'"));
    }
    let all = [Unit::D, Unit::H, Unit::M, Unit::S, Unit::Ms];
    let total = parse_time_groups(unsigned, &all, class.name())
        .map_err(|reason| malformed(class, text, reason))?;
    let limit: u128 = if negative { 1 << 31 } else { (1 << 31) - 1 };
    if !total.at_most(limit) {
        return Err(out_of_range(
            class,
            text,
            "-24D20H31M23S648MS",
            "24D20H31M23S647MS",
        ));
    }
    let magnitude = i64::try_from(total.whole).unwrap_or(i64::MAX);
    let millis = if negative { -magnitude } else { magnitude };
    ok(class, LiteralValue::Duration { millis })
}

// ====================================================================================== dates

/// A parsed but not yet validated date.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct DateFields {
    year: u128,
    month: u128,
    day: u128,
}

impl DateFields {
    fn is_calendar_date(self) -> bool {
        (1..=12).contains(&self.month) && self.day >= 1 && self.day <= self.days_in_month()
    }

    fn days_in_month(self) -> u128 {
        match self.month {
            4 | 6 | 9 | 11 => 30,
            2 if is_leap_year(self.year) => 29,
            2 => 28,
            _ => 31,
        }
    }

    /// Only call on fields within the year range (they fit).
    fn to_parts(self) -> (u16, u8, u8) {
        (
            u16::try_from(self.year).unwrap_or(u16::MAX),
            u8::try_from(self.month).unwrap_or(u8::MAX),
            u8::try_from(self.day).unwrap_or(u8::MAX),
        )
    }
}

fn is_leap_year(year: u128) -> bool {
    (is_multiple(year, 4) && !is_multiple(year, 100)) || is_multiple(year, 400)
}

/// `n % d == 0` (`u128::is_multiple_of` needs Rust 1.87; the workspace supports 1.85).
fn is_multiple(n: u128, d: u128) -> bool {
    n.checked_rem(d) == Some(0)
}

/// A parsed but not yet validated time of day.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct TodFields {
    hour: u128,
    minute: u128,
    second: u128,
    millis: u128,
}

impl TodFields {
    fn in_range(self) -> bool {
        self.hour <= 23 && self.minute <= 59 && self.second <= 59
    }

    /// Only call when [`TodFields::in_range`].
    fn total_millis(self) -> u32 {
        let ms = ((self.hour * 60 + self.minute) * 60 + self.second) * 1000 + self.millis;
        u32::try_from(ms).unwrap_or(u32::MAX)
    }
}

/// Parses one decimal field of a date or time of day; any malformed field gives `form`.
fn date_field(s: &str, form: &str) -> Result<u128, String> {
    parse_digits(s, 10, true)
        .map(|d| d.value)
        .map_err(|e| match e {
            DigitError::Underscore => UNDERSCORE_REASON.to_owned(),
            _ => format!("expected '{form}'"),
        })
}

const DATE_FORM: &str = "yyyy-m-d";
const TOD_FORM: &str = "h:m:s[.fff]";
const DT_FORM: &str = "yyyy-m-d-h:m:s[.fff]";

/// `y-m-d`.
fn parse_date(s: &str, form: &str) -> Result<DateFields, String> {
    let mut parts = s.split('-');
    let (Some(y), Some(m), Some(d), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(format!("expected '{form}'"));
    };
    Ok(DateFields {
        year: date_field(y, form)?,
        month: date_field(m, form)?,
        day: date_field(d, form)?,
    })
}

/// `h:m:s[.fff]`.
fn parse_time_of_day(s: &str, form: &str) -> Result<TodFields, String> {
    let mut parts = s.split(':');
    let (Some(h), Some(m), Some(sec), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(format!("expected '{form}'"));
    };
    let (sec, frac) = match sec.split_once('.') {
        Some((s, f)) => (s, Some(f)),
        None => (sec, None),
    };
    let millis = match frac {
        None => 0,
        Some(f) => {
            let digits = parse_digits(f, 10, false).map_err(|_| format!("expected '{form}'"))?;
            if digits.count > 3 {
                return Err("at most 3 digits after '.'".to_owned());
            }
            // `.3` is 300 ms, `.03` is 30 ms.
            digits.value * 10u128.pow(3 - u32::try_from(digits.count).unwrap_or(3))
        }
    };
    Ok(TodFields {
        hour: date_field(h, form)?,
        minute: date_field(m, form)?,
        second: date_field(sec, form)?,
        millis,
    })
}

/// `D#y-m-d`: a calendar date from 1990-1-1 to 2168-12-31.
fn check_date(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::Date;
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    let date = parse_date(body, DATE_FORM).map_err(|reason| malformed(class, text, reason))?;
    if !date.is_calendar_date() {
        return Err(invalid_date(class, text));
    }
    if !(1990..=2168).contains(&date.year) {
        return Err(out_of_range(class, text, "1990-1-1", "2168-12-31"));
    }
    let (year, month, day) = date.to_parts();
    ok(class, LiteralValue::Date { year, month, day })
}

/// `TOD#h:m:s[.fff]`: 0:0:0.0 to 23:59:59.999.
fn check_time_of_day(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::TimeOfDay;
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    let tod = parse_time_of_day(body, TOD_FORM).map_err(|reason| malformed(class, text, reason))?;
    if !tod.in_range() {
        return Err(out_of_range(class, text, "0:0:0.0", "23:59:59.999"));
    }
    ok(
        class,
        LiteralValue::TimeOfDay {
            millis: tod.total_millis(),
        },
    )
}

/// `DT#y-m-d-h:m:s[.fff]`: 1990-1-1-0:0:0.0 to 2089-12-31-23:59:59.999.
fn check_date_and_time(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::DateAndTime;
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    let form_error = || malformed(class, text, format_args!("expected '{DT_FORM}'"));
    // The date part is the text before the third '-'.
    let split = body
        .match_indices('-')
        .nth(2)
        .map(|(i, _)| i)
        .ok_or_else(form_error)?;
    let (date_text, time_text) = (&body[..split], &body[split + 1..]);
    let date = parse_date(date_text, DT_FORM).map_err(|reason| malformed(class, text, reason))?;
    let tod =
        parse_time_of_day(time_text, DT_FORM).map_err(|reason| malformed(class, text, reason))?;
    if !date.is_calendar_date() {
        return Err(invalid_date(class, text));
    }
    if !(1990..=2089).contains(&date.year) || !tod.in_range() {
        return Err(out_of_range(
            class,
            text,
            "1990-1-1-0:0:0.0",
            "2089-12-31-23:59:59.999",
        ));
    }
    let (year, month, day) = date.to_parts();
    ok(
        class,
        LiteralValue::DateAndTime {
            year,
            month,
            day,
            millis: tod.total_millis(),
        },
    )
}

// ====================================================================================== pointer

/// The areas a `P#` bit address may name.
const POINTER_AREAS: [&str; 8] = ["E", "A", "M", "L", "I", "Q", "DBX", "DIX"];

/// `P#` followed by `[DBn.]area byte.bit` or by `byte.bit`.
fn check_pointer(text: &str, body: &str) -> Result<Literal, LiteralError> {
    let class = LiteralClass::Pointer;
    if body.is_empty() {
        return Err(malformed(class, text, "empty body"));
    }
    parse_pointer(body)
        .map(|p| Literal {
            class,
            value: LiteralValue::Pointer(p),
        })
        .ok_or_else(|| {
            malformed(
                class,
                text,
                "expected a bit address or 'byte.bit' after 'P#'",
            )
        })
}

/// Splits a run of ASCII letters or of ASCII digits off the front of `s`.
fn split_run(s: &str, pred: fn(&u8) -> bool) -> (&str, &str) {
    let end = s.bytes().position(|b| !pred(&b)).unwrap_or(s.len());
    s.split_at(end)
}

/// Plain decimal digits (no `_`), saturating; `None` if `s` is not all digits.
fn address_number(s: &str) -> Option<u64> {
    let d = parse_digits(s, 10, false).ok()?;
    Some(u64::try_from(d.value).unwrap_or(u64::MAX))
}

fn parse_pointer(body: &str) -> Option<PointerValue> {
    let upper = body.to_ascii_uppercase();
    // `DBn.DBXbyte.bit`
    let db_number = upper
        .strip_prefix("DB")
        .filter(|r| r.starts_with(|c: char| c.is_ascii_digit()));
    if let Some(after_db) = db_number {
        let (number, after_number) = split_run(after_db, u8::is_ascii_digit);
        let db = Some(address_number(number)?);
        let rest = after_number.strip_prefix(".DBX")?;
        return bit_address(after_area(rest)?, db, Some("DBX"));
    }
    // `area byte.bit` or `byte.bit`
    let (letters, rest) = split_run(&upper, u8::is_ascii_alphabetic);
    if letters.is_empty() {
        return bit_address(rest, None, None);
    }
    let area = POINTER_AREAS.iter().copied().find(|a| *a == letters)?;
    bit_address(after_area(rest)?, None, Some(area))
}

/// What follows an area in a pointer: the space after the area is optional (`P#M 100.0`, as
/// STEP 7 prints pointers; language.md §3.5). Spaces and tabs only, and digits must follow.
fn after_area(rest: &str) -> Option<&str> {
    let digits = rest.trim_start_matches([' ', '\t']);
    digits
        .starts_with(|c: char| c.is_ascii_digit())
        .then_some(digits)
}

/// `byte.bit` after the area.
fn bit_address(s: &str, db: Option<u64>, area: Option<&'static str>) -> Option<PointerValue> {
    let (byte, bit) = s.split_once('.')?;
    Some(PointerValue {
        db,
        area,
        byte: address_number(byte)?,
        bit: address_number(bit)?,
    })
}

// ====================================================================================== quoted

/// `'...'`: one character → Character, otherwise String.
fn check_quoted(text: &str) -> Result<Literal, LiteralError> {
    let content = unquote(text).map_err(|reason| malformed(LiteralClass::String, text, reason))?;
    let mut chars = content.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        let class = LiteralClass::Character;
        if u32::from(c) > 0xFF {
            return Err(out_of_range(class, text, "U+0000", "U+00FF"));
        }
        return ok(class, LiteralValue::Char(c));
    }
    let class = LiteralClass::String;
    if content.chars().any(|c| u32::from(c) > 0xFF) {
        return Err(out_of_range(class, text, "U+0000", "U+00FF"));
    }
    if content.chars().count() > 254 {
        return Err(out_of_range(class, text, "0", "254"));
    }
    ok(class, LiteralValue::Str(content))
}

/// The content of a `'...'` constant with `''` turned into `'`.
fn unquote(text: &str) -> Result<String, &'static str> {
    let inner = text.strip_prefix('\'').unwrap_or(text);
    let mut content = String::new();
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\'' {
            content.push(c);
        } else if chars.peek() == Some(&'\'') {
            chars.next();
            content.push('\'');
        } else if chars.peek().is_none() {
            return Ok(content);
        } else {
            return Err("unexpected text after the closing quote");
        }
    }
    Err("missing closing quote")
}

// ====================================================================================== types

/// The type of a literal (Appendix C.1), as an upper-case type name: integers are `INT` from
/// −32768 to 32767 and `DINT` otherwise, binary constants are `BYTE`/`WORD`/`DWORD` by digit
/// count, byte tuples `WORD` (2 elements) or `DWORD` (4).
pub fn literal_type(lit: &Literal) -> &'static str {
    match lit.class {
        LiteralClass::Boolean => "BOOL",
        LiteralClass::Integer => match lit.value {
            LiteralValue::Int(v) if (-32768..=32767).contains(&v) => "INT",
            _ => "DINT",
        },
        LiteralClass::Real => "REAL",
        LiteralClass::ByteHex => "BYTE",
        LiteralClass::WordHex | LiteralClass::Counter => "WORD",
        LiteralClass::DwordHex => "DWORD",
        LiteralClass::Binary => match lit.value {
            LiteralValue::Bits { digits, .. } if digits <= 8 => "BYTE",
            LiteralValue::Bits { digits, .. } if digits <= 16 => "WORD",
            _ => "DWORD",
        },
        LiteralClass::ByteTuple => match &lit.value {
            LiteralValue::Tuple(t) if t.len() == 2 => "WORD",
            _ => "DWORD",
        },
        LiteralClass::LongInteger => "DINT",
        LiteralClass::S5Time => "S5TIME",
        LiteralClass::IecTime => "TIME",
        LiteralClass::Date => "DATE",
        LiteralClass::TimeOfDay => "TIME_OF_DAY",
        LiteralClass::DateAndTime => "DATE_AND_TIME",
        LiteralClass::Character => "CHAR",
        LiteralClass::String => "STRING",
        LiteralClass::Pointer => "POINTER",
    }
}

/// Whether a type accepts a literal (Appendix C.2).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Acceptance {
    /// The class is in the type's row and the value fits.
    Accepted,
    /// The class is in the type's row but the value lies outside the type's range (HG1206):
    /// the range, for `({min} to {max})`.
    OutOfRange { min: String, max: String },
    /// The class is not in the type's row (HG1205).
    Mismatch,
}

/// Whether the type `type_name` (case-insensitive: `"BYTE"`, `"int"`, `"STRING[10]"`, `"STRING"`
/// for `STRING[254]`) accepts `lit` (Appendix C.2).
///
/// The qualified classes of C.2 are read as class restrictions: a binary constant with more
/// digits than the type allows, or a 4-element tuple for WORD, is a [`Acceptance::Mismatch`];
/// an integer outside the type's range and a string longer than `n` are
/// [`Acceptance::OutOfRange`]. POINTER accepts a `P#` constant (Appendix D, rule 5). TIMER,
/// COUNTER and names outside C.2 accept nothing.
pub fn accepts(type_name: &str, lit: &Literal) -> Acceptance {
    use LiteralClass as C;
    let upper = type_name.trim().to_ascii_uppercase();
    if upper.starts_with("STRING") {
        return match string_length(&upper) {
            Some(n) => accepts_string(n, lit),
            None => Acceptance::Mismatch,
        };
    }
    let int = match lit.value {
        LiteralValue::Int(v) => v,
        _ => 0,
    };
    let binary_digits = match lit.value {
        LiteralValue::Bits { digits, .. } => digits,
        _ => 0,
    };
    let tuple_len = match &lit.value {
        LiteralValue::Tuple(t) => t.len(),
        _ => 0,
    };
    let in_range = |min: i64, max: i64| {
        if (min..=max).contains(&int) {
            Acceptance::Accepted
        } else {
            Acceptance::OutOfRange {
                min: min.to_string(),
                max: max.to_string(),
            }
        }
    };
    let yes = |b: bool| {
        if b {
            Acceptance::Accepted
        } else {
            Acceptance::Mismatch
        }
    };
    match (upper.as_str(), lit.class) {
        ("BOOL", C::Boolean) => Acceptance::Accepted,
        ("BYTE", C::ByteHex) => Acceptance::Accepted,
        ("BYTE", C::Binary) => yes(binary_digits <= 8),
        ("BYTE", C::Integer) => in_range(0, 255),
        ("WORD", C::ByteHex | C::WordHex | C::Counter) => Acceptance::Accepted,
        ("WORD", C::Binary) => yes(binary_digits <= 16),
        ("WORD", C::ByteTuple) => yes(tuple_len == 2),
        ("WORD", C::Integer) => in_range(0, 65535),
        ("DWORD", C::ByteHex | C::WordHex | C::DwordHex | C::Binary | C::ByteTuple) => {
            Acceptance::Accepted
        }
        ("DWORD", C::Integer) => in_range(0, 2_147_483_647),
        ("INT", C::Integer) => in_range(-32768, 32767),
        ("DINT", C::Integer | C::LongInteger) => Acceptance::Accepted,
        ("REAL", C::Real | C::Integer) => Acceptance::Accepted,
        ("S5TIME", C::S5Time)
        | ("TIME", C::IecTime)
        | ("DATE", C::Date)
        | ("TIME_OF_DAY", C::TimeOfDay)
        | ("DATE_AND_TIME", C::DateAndTime)
        | ("CHAR", C::Character)
        | ("POINTER", C::Pointer) => Acceptance::Accepted,
        _ => Acceptance::Mismatch,
    }
}

/// `STRING` → 254, `STRING[n]` → n; `None` for anything else.
fn string_length(upper: &str) -> Option<u64> {
    let rest = upper.strip_prefix("STRING")?.trim();
    if rest.is_empty() {
        return Some(254);
    }
    let inner = rest.strip_prefix('[')?.strip_suffix(']')?.trim();
    address_number(inner)
}

fn accepts_string(n: u64, lit: &Literal) -> Acceptance {
    let len = match &lit.value {
        LiteralValue::Char(_) => 1,
        LiteralValue::Str(s) => s.chars().count(),
        _ => return Acceptance::Mismatch,
    };
    if u64::try_from(len).is_ok_and(|len| len <= n) {
        Acceptance::Accepted
    } else {
        Acceptance::OutOfRange {
            min: "0".to_owned(),
            max: n.to_string(),
        }
    }
}

/// The type of a literal in a chart comparison or assignment (Appendix C.3).
///
/// `other_side` is the type of the other side; pass `None` when the other side is itself an
/// integer literal (two integer literals compare as DINT). An integer literal takes the other
/// side's type if it is INT, DINT, BYTE, WORD, DWORD or REAL and accepts the value (C.2);
/// every other literal has the fixed type of its class ([`literal_type`]).
pub fn chart_literal_type(lit: &Literal, other_side: Option<&str>) -> &'static str {
    if lit.class != LiteralClass::Integer {
        return literal_type(lit);
    }
    let Some(other) = other_side else {
        return "DINT";
    };
    const ADAPTABLE: [&str; 6] = ["INT", "DINT", "BYTE", "WORD", "DWORD", "REAL"];
    let upper = other.trim().to_ascii_uppercase();
    match ADAPTABLE.iter().copied().find(|t| *t == upper) {
        Some(t) if accepts(t, lit) == Acceptance::Accepted => t,
        _ => literal_type(lit),
    }
}

// ====================================================================================== tests

#[cfg(test)]
mod tests {
    use super::*;

    fn lit(text: &str) -> Literal {
        check_literal(text).unwrap_or_else(|e| panic!("{text}: unexpected error: {}", e.message))
    }

    fn value(text: &str) -> LiteralValue {
        lit(text).value
    }

    fn class(text: &str) -> LiteralClass {
        lit(text).class
    }

    fn ty(text: &str) -> &'static str {
        literal_type(&lit(text))
    }

    fn bits(value: u64, digits: u32) -> LiteralValue {
        LiteralValue::Bits { value, digits }
    }

    fn millis(text: &str) -> i64 {
        match value(text) {
            LiteralValue::Duration { millis } => millis,
            v => panic!("{text}: not a duration: {v:?}"),
        }
    }

    /// The error of `text`, which must have `code`.
    fn error(text: &str, code: LiteralErrorCode) -> String {
        match check_literal(text) {
            Ok(lit) => panic!("{text}: expected {code:?}, got {lit:?}"),
            Err(e) => {
                assert_eq!(e.code, code, "{text}: {}", e.message);
                e.message
            }
        }
    }

    /// Asserts HG0006 `invalid {class} constant '{text}': {reason}`.
    #[track_caller]
    fn bad(text: &str, class: &str, reason: &str) {
        let expected = format!("invalid {class} constant '{text}': {reason}");
        assert_eq!(error(text, LiteralErrorCode::Malformed), expected);
    }

    /// Asserts HG0007 `{text} is out of range for {class} ({range})`.
    #[track_caller]
    fn oor(text: &str, class: &str, range: &str) {
        let expected = format!("{text} is out of range for {class} ({range})");
        assert_eq!(error(text, LiteralErrorCode::OutOfRange), expected);
    }

    /// Asserts HG0007 `{text} is not a valid date`.
    #[track_caller]
    fn not_a_date(text: &str) {
        let expected = format!("{text} is not a valid date");
        assert_eq!(error(text, LiteralErrorCode::OutOfRange), expected);
    }

    #[test]
    fn class_names() {
        let names: Vec<&str> = LiteralClass::ALL.iter().map(|c| c.name()).collect();
        let expected = "boolean, integer, real, byte hex, word hex, dword hex, binary, byte tuple, \
                        counter, long integer, S5 time, IEC time, date, time of day, \
                        date and time, character, string, pointer";
        assert_eq!(names.join(", "), expected);
        assert_eq!(LiteralClass::S5Time.to_string(), "S5 time");
    }

    #[test]
    fn error_codes_and_display() {
        assert_eq!(LiteralErrorCode::Malformed.error_code(), ErrorCode::HG0006);
        assert_eq!(LiteralErrorCode::OutOfRange.error_code(), ErrorCode::HG0007);
        let e = check_literal("B#16#100").unwrap_err();
        assert_eq!(e.class, Some(LiteralClass::ByteHex));
        assert_eq!(
            e.to_string(),
            "HG0007: B#16#100 is out of range for byte hex (16#0 to 16#FF)"
        );
        assert_eq!(check_literal("X#1").unwrap_err().class, None);
    }

    #[test]
    fn boolean() {
        assert_eq!(value("TRUE"), LiteralValue::Bool(true));
        assert_eq!(value("true"), LiteralValue::Bool(true));
        assert_eq!(value("False"), LiteralValue::Bool(false));
        assert_eq!(class("FALSE"), LiteralClass::Boolean);
        assert_eq!(ty("FALSE"), "BOOL");
        bad("TRUEX", "typed", "not a constant");
    }

    #[test]
    fn integer() {
        assert_eq!(value("0"), LiteralValue::Int(0));
        assert_eq!(value("-5"), LiteralValue::Int(-5));
        assert_eq!(value("007"), LiteralValue::Int(7));
        assert_eq!(value("2147483647"), LiteralValue::Int(2_147_483_647));
        assert_eq!(value("-2147483648"), LiteralValue::Int(-2_147_483_648));
        assert_eq!(class("12"), LiteralClass::Integer);
        assert_eq!(ty("32767"), "INT");
        assert_eq!(ty("-32768"), "INT");
        assert_eq!(ty("32768"), "DINT");
        assert_eq!(ty("-32769"), "DINT");
        let range = "-2147483648 to 2147483647";
        oor("2147483648", "integer", range);
        oor("-2147483649", "integer", range);
        oor(
            "99999999999999999999999999999999999999999999",
            "integer",
            range,
        );
        bad("-", "integer", "missing digits");
        bad("12x", "integer", "digit 'x' outside radix 10");
        bad("--5", "integer", "unexpected character '-'");
    }

    #[test]
    fn real() {
        assert_eq!(value("1.5"), LiteralValue::Real(1.5));
        assert_eq!(value("-1.5"), LiteralValue::Real(-1.5));
        assert_eq!(value("1.234567e+13"), LiteralValue::Real(1.234567e13));
        assert_eq!(value("1e5"), LiteralValue::Real(1e5));
        assert_eq!(value("2E-3"), LiteralValue::Real(2e-3));
        assert_eq!(value("3.402823e+38"), LiteralValue::Real(3.402823e38));
        assert_eq!(value("-3.402823e38"), LiteralValue::Real(-3.402823e38));
        assert_eq!(value("1e-999"), LiteralValue::Real(0.0));
        assert_eq!(class("0.0"), LiteralClass::Real);
        assert_eq!(ty("0.0"), "REAL");
        let range = "-3.402823e+38 to 3.402823e+38";
        oor("1e39", "real", range);
        oor("-3.4029e38", "real", range);
        oor("1e999", "real", range);
        bad("1.", "real", "missing digits after '.'");
        bad("1e", "real", "missing exponent digits");
        bad("1e+", "real", "missing exponent digits");
        bad(
            "-.5",
            "real",
            "missing digits before the fraction or exponent",
        );
        bad("1.5.2", "real", "unexpected character '.'");
    }

    #[test]
    fn byte_hex() {
        assert_eq!(value("B#16#FF"), bits(0xFF, 2));
        assert_eq!(value("byte#16#10"), bits(0x10, 2));
        assert_eq!(value("b#16#0f"), bits(0x0F, 2));
        assert_eq!(value("B#16#0"), bits(0, 1));
        assert_eq!(value("B#16#F_F"), bits(0xFF, 2));
        assert_eq!(class("B#16#FF"), LiteralClass::ByteHex);
        assert_eq!(ty("B#16#FF"), "BYTE");
        oor("B#16#100", "byte hex", "16#0 to 16#FF");
        bad("B#", "byte hex", "empty body");
        bad("B#16#", "byte hex", "empty body");
        bad("B#16#FG", "byte hex", "digit 'G' outside radix 16");
        bad("B#FF", "byte hex", "expected '16#' or '(' after 'B#'");
        bad("B#16#_F", "byte hex", "'_' must stand between two digits");
        bad("B#16#F_", "byte hex", "'_' must stand between two digits");
        bad("B#16#F__F", "byte hex", "'_' must stand between two digits");
        bad("B#16#F.F", "byte hex", "unexpected character '.'");
    }

    #[test]
    fn word_hex() {
        assert_eq!(value("W#16#1000"), bits(0x1000, 4));
        assert_eq!(value("word#16#FFFF"), bits(0xFFFF, 4));
        assert_eq!(class("W#16#1"), LiteralClass::WordHex);
        assert_eq!(ty("W#16#1"), "WORD");
        oor("W#16#10000", "word hex", "16#0 to 16#FFFF");
        bad("W#FF", "word hex", "expected '16#' after 'W#'");
        bad("WORD#16#", "word hex", "empty body");
    }

    #[test]
    fn dword_hex() {
        assert_eq!(value("DW#16#00A2_1234"), bits(0x00A2_1234, 8));
        assert_eq!(value("dword#16#FFFF_FFFF"), bits(0xFFFF_FFFF, 8));
        assert_eq!(class("DW#16#0"), LiteralClass::DwordHex);
        assert_eq!(ty("DW#16#0"), "DWORD");
        let range = "16#0 to 16#FFFF_FFFF";
        oor("DW#16#1_0000_0000", "dword hex", range);
        oor(
            "DW#16#FFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF",
            "dword hex",
            range,
        );
        bad("DW#16#12345Z", "dword hex", "digit 'Z' outside radix 16");
        bad("DWORD#8#1", "dword hex", "expected '16#' after 'DWORD#'");
    }

    #[test]
    fn binary() {
        assert_eq!(value("2#0101_0000"), bits(0x50, 8));
        let dword = "2#1000_0001_0001_1000_1011_1011_0111_1111";
        assert_eq!(value(dword), bits(0x8118_BB7F, 32));
        assert_eq!(class("2#1"), LiteralClass::Binary);
        assert_eq!(ty("2#1"), "BYTE");
        assert_eq!(ty("2#0000_0000"), "BYTE");
        assert_eq!(ty("2#0_0000_0000"), "WORD");
        assert_eq!(ty("2#0001_0000_0000_0000"), "WORD");
        assert_eq!(ty("2#1_0000_0000_0000_0000"), "DWORD");
        assert_eq!(ty(dword), "DWORD");
        oor(&format!("2#{}", "1".repeat(33)), "binary", "1 to 32 digits");
        oor(&format!("2#{}", "0".repeat(40)), "binary", "1 to 32 digits");
        bad("2#", "binary", "empty body");
        bad("2#012", "binary", "digit '2' outside radix 2");
        bad("2#_01", "binary", "'_' must stand between two digits");
    }

    #[test]
    fn number_prefixes_and_unknown_prefixes() {
        let number = "a number followed by '#' must be '2#'";
        bad("16#FF", "typed", number);
        bad("8#17", "typed", number);
        bad("02#1", "typed", number);
        bad("X#1", "typed", "unknown prefix 'X#'");
        bad("Foo#12", "typed", "unknown prefix 'Foo#'");
        bad("1A#5", "typed", "unknown prefix '1A#'");
        bad("ä#1", "typed", "unknown prefix 'ä#'");
        bad("#", "typed", "missing prefix before '#'");
        bad("", "typed", "not a constant");
        bad("abc", "typed", "not a constant");
    }

    #[test]
    fn byte_tuple() {
        assert_eq!(value("B#(10,20)"), LiteralValue::Tuple(vec![10, 20]));
        assert_eq!(value("byte#(10,20)"), LiteralValue::Tuple(vec![10, 20]));
        assert_eq!(
            value("B#(1, 14,100,120)"),
            LiteralValue::Tuple(vec![1, 14, 100, 120])
        );
        assert_eq!(
            value("BYTE#(1,14,100,120)"),
            LiteralValue::Tuple(vec![1, 14, 100, 120])
        );
        assert_eq!(value("B#(0,255)"), LiteralValue::Tuple(vec![0, 255]));
        assert_eq!(value("B#( 1 ,\t2 )"), LiteralValue::Tuple(vec![1, 2]));
        assert_eq!(class("B#(0,0)"), LiteralClass::ByteTuple);
        assert_eq!(ty("B#(10,20)"), "WORD");
        assert_eq!(ty("B#(1,2,3,4)"), "DWORD");
        oor("B#(256,0)", "byte tuple", "0 to 255");
        oor(
            "B#(1,2,3,99999999999999999999999999999999999999999)",
            "byte tuple",
            "0 to 255",
        );
        let count = "a byte tuple has 2 or 4 elements";
        for t in ["B#()", "B#( )", "B#(1)", "B#(1,2,3)", "B#(1,2,3,4,5)"] {
            bad(t, "byte tuple", count);
        }
        // The shape is checked before the range.
        bad("B#(256,1,2)", "byte tuple", count);
        bad("B#(1,,2)", "byte tuple", "empty element");
        bad("B#(", "byte tuple", "missing ')'");
        bad("B#(1,2", "byte tuple", "missing ')'");
        bad("B#(1,2)3", "byte tuple", "unexpected text after ')'");
        bad("B#(1,-2)", "byte tuple", "unexpected character '-'");
        bad("B#(1,A)", "byte tuple", "digit 'A' outside radix 10");
    }

    #[test]
    fn counter() {
        assert_eq!(value("C#998"), LiteralValue::Int(998));
        assert_eq!(value("c#0"), LiteralValue::Int(0));
        assert_eq!(value("C#999"), LiteralValue::Int(999));
        assert_eq!(class("C#1"), LiteralClass::Counter);
        assert_eq!(ty("C#1"), "WORD");
        oor("C#1000", "counter", "0 to 999");
        bad("C#", "counter", "empty body");
        bad("C#-1", "counter", "unexpected character '-'");
        bad("C#9A", "counter", "digit 'A' outside radix 10");
    }

    #[test]
    fn long_integer() {
        assert_eq!(value("L#1"), LiteralValue::Int(1));
        assert_eq!(value("L#-5"), LiteralValue::Int(-5));
        assert_eq!(value("l#-2147483648"), LiteralValue::Int(-2_147_483_648));
        assert_eq!(value("L#2147483647"), LiteralValue::Int(2_147_483_647));
        assert_eq!(class("L#1"), LiteralClass::LongInteger);
        assert_eq!(ty("L#1"), "DINT");
        let range = "-2147483648 to 2147483647";
        oor("L#2147483648", "long integer", range);
        oor("L#-2147483649", "long integer", range);
        bad("L#", "long integer", "empty body");
        bad("L#-", "long integer", "missing digits after '-'");
        bad("L#1.5", "long integer", "unexpected character '.'");
    }

    #[test]
    fn s5_time() {
        assert_eq!(millis("S5T#1H_1M_0S"), 3_660_000);
        assert_eq!(millis("S5T#1H_1M"), 3_660_000);
        assert_eq!(millis("S5TIME#0H_1M_0S_0MS"), 60_000);
        assert_eq!(millis("s5t#10ms"), 10);
        assert_eq!(millis("S5T#0S"), 0);
        assert_eq!(millis("S5T#0MS"), 0);
        assert_eq!(millis("S5T#2H46M30S"), 9_990_000);
        assert_eq!(millis("S5T#2H_46M_30S_0MS"), 9_990_000);
        assert_eq!(millis("S5T#9990S"), 9_990_000);
        assert_eq!(millis("S5T#1.5S"), 1_500);
        assert_eq!(class("S5T#1S"), LiteralClass::S5Time);
        assert_eq!(ty("S5T#1S"), "S5TIME");
        let range = "10MS to 2H46M30S";
        oor("S5T#3H", "S5 time", range);
        oor("S5T#5MS", "S5 time", range);
        oor("S5T#9.9MS", "S5 time", range);
        oor("S5T#0.001MS", "S5 time", range);
        oor("S5T#2H46M30S1MS", "S5 time", range);
        oor("S5T#2H46M30.0001S", "S5 time", range);
        bad("S5T#", "S5 time", "empty body");
        bad("S5T#1D", "S5 time", "unit 'D' not allowed in S5 time");
        bad("S5T#-5S", "S5 time", "an S5 time cannot be negative");
        bad("S5T#1M1H", "S5 time", "unit 'H' repeated or out of order");
        bad(
            "S5T#1.5M1S",
            "S5 time",
            "fraction only allowed on the last unit",
        );
        bad(
            "S5T#1H__1M",
            "S5 time",
            "'_' must stand between two digits or two unit groups",
        );
    }

    #[test]
    fn iec_time() {
        assert_eq!(millis("T#5S"), 5_000);
        assert_eq!(millis("t#5s"), 5_000);
        assert_eq!(millis("T#-5S"), -5_000);
        assert_eq!(millis("TIME#0D_1H_1M_0S_0MS"), 3_660_000);
        assert_eq!(
            millis("T#3D4H2M1S44MS"),
            ((3 * 24 + 4) * 60 + 2) * 60_000 + 1_044
        );
        assert_eq!(millis("T#2.5H"), 9_000_000);
        assert_eq!(millis("T#13S750MS"), 13_750);
        assert_eq!(millis("T#1D_2H"), 93_600_000);
        assert_eq!(millis("T#1_000MS"), 1_000);
        assert_eq!(millis("T#0.5MS"), 0);
        assert_eq!(millis("T#1.0005S"), 1_000);
        assert_eq!(millis("T#90M"), 5_400_000); // fields are not limited one by one
        assert_eq!(millis("T#2147483647MS"), 2_147_483_647);
        assert_eq!(millis("T#24D20H31M23S647MS"), 2_147_483_647);
        assert_eq!(millis("T#-24D20H31M23S648MS"), -2_147_483_648);
        assert_eq!(millis("T#-24D_20H_31M_23S_648MS"), -2_147_483_648);
        assert_eq!(class("T#1S"), LiteralClass::IecTime);
        assert_eq!(ty("T#1S"), "TIME");
        let range = "-24D20H31M23S648MS to 24D20H31M23S647MS";
        oor("T#25D", "IEC time", range);
        oor("T#24D20H31M23S648MS", "IEC time", range);
        oor("T#-24D20H31M23S649MS", "IEC time", range);
        oor("T#24D20H31M23S647.5MS", "IEC time", range);
        oor(
            "T#99999999999999999999999999999999999999999999999D",
            "IEC time",
            range,
        );
    }

    #[test]
    fn iec_time_malformed() {
        let underscore = "'_' must stand between two digits or two unit groups";
        for (t, reason) in [
            ("T#", "empty body"),
            ("T#-", "missing value after '-'"),
            ("T#5S3M", "unit 'M' repeated or out of order"),
            ("T#5S5S", "unit 'S' repeated or out of order"),
            ("T#1MS1S", "unit 'S' repeated or out of order"),
            ("T#2.5H3M", "fraction only allowed on the last unit"),
            ("T#5", "missing unit after '5'"),
            ("T#5X", "unknown unit 'X'"),
            ("T#5HMS", "unknown unit 'HMS'"),
            ("T#.5S", "missing digits before '.'"),
            ("T#5.S", "missing digits after '.'"),
            ("T#S", "missing number before 'S'"),
            ("T#_5S", underscore),
            ("T#5_S", underscore),
            ("T#5S_", underscore),
            ("T#5S_M", underscore),
            ("T#1__0S", underscore),
            ("T#--5S", "unexpected character '-'"),
            ("T#5S-", "unexpected character '-'"),
            ("T#5S:1", "unexpected character ':'"),
            ("T#1.5.5S", "unexpected character '.'"),
        ] {
            bad(t, "IEC time", reason);
        }
    }

    #[test]
    fn date() {
        let date = |year, month, day| LiteralValue::Date { year, month, day };
        assert_eq!(value("D#1994-3-15"), date(1994, 3, 15));
        assert_eq!(value("DATE#1994-03-05"), date(1994, 3, 5));
        assert_eq!(value("d#1990-1-1"), date(1990, 1, 1));
        assert_eq!(value("D#2168-12-31"), date(2168, 12, 31));
        assert_eq!(value("D#2000-2-29"), date(2000, 2, 29));
        assert_eq!(value("D#1996-2-29"), date(1996, 2, 29));
        assert_eq!(class("D#1994-3-15"), LiteralClass::Date);
        assert_eq!(ty("D#1994-3-15"), "DATE");
        let invalid =
            "D#1994-2-30 D#1995-2-29 D#2100-2-29 D#1994-13-1 D#1994-0-1 D#1994-4-31 D#1994-1-0";
        for t in invalid.split_whitespace() {
            not_a_date(t);
        }
        oor("D#1989-12-31", "date", "1990-1-1 to 2168-12-31");
        oor("D#2169-1-1", "date", "1990-1-1 to 2168-12-31");
        bad("D#", "date", "empty body");
        for t in "D#1994-3 D#1994-3-15-1 D#1994--15 D#1994-3-1x D#1994:3:15".split_whitespace() {
            bad(t, "date", "expected 'yyyy-m-d'");
        }
        bad("D#1994-3-_1", "date", "'_' must stand between two digits");
    }

    #[test]
    fn time_of_day() {
        let tod = |millis| LiteralValue::TimeOfDay { millis };
        assert_eq!(value("TOD#1:10:3.3"), tod(4_203_300));
        assert_eq!(value("TIME_OF_DAY#1:10:3.3"), tod(4_203_300));
        assert_eq!(value("tod#0:0:0.0"), tod(0));
        assert_eq!(value("TOD#0:0:0"), tod(0));
        assert_eq!(value("TOD#0:0:0.03"), tod(30));
        assert_eq!(value("TOD#0:0:0.003"), tod(3));
        assert_eq!(value("TOD#23:59:59.999"), tod(86_399_999));
        assert_eq!(class("TOD#1:0:0"), LiteralClass::TimeOfDay);
        assert_eq!(ty("TOD#1:0:0"), "TIME_OF_DAY");
        let range = "0:0:0.0 to 23:59:59.999";
        oor("TOD#24:0:0.0", "time of day", range);
        oor("TOD#0:60:0", "time of day", range);
        oor("TOD#0:0:60", "time of day", range);
        bad("TOD#", "time of day", "empty body");
        for t in "TOD#1:10 TOD#1:10:3:3 TOD#1::3 TOD#1:10:3. TOD#1H".split_whitespace() {
            bad(t, "time of day", "expected 'h:m:s[.fff]'");
        }
        bad(
            "TOD#1:10:3.1234",
            "time of day",
            "at most 3 digits after '.'",
        );
    }

    #[test]
    fn date_and_time() {
        let dt = |year, month, day, millis| LiteralValue::DateAndTime {
            year,
            month,
            day,
            millis,
        };
        assert_eq!(value("DT#1994-3-15-1:10:3.3"), dt(1994, 3, 15, 4_203_300));
        assert_eq!(
            value("DATE_AND_TIME#1994-3-15-1:10:3.3"),
            dt(1994, 3, 15, 4_203_300)
        );
        assert_eq!(value("dt#1990-1-1-0:0:0.0"), dt(1990, 1, 1, 0));
        assert_eq!(
            value("DT#2089-12-31-23:59:59.999"),
            dt(2089, 12, 31, 86_399_999)
        );
        assert_eq!(class("DT#1994-3-15-1:10:3"), LiteralClass::DateAndTime);
        assert_eq!(ty("DT#1994-3-15-1:10:3"), "DATE_AND_TIME");
        let range = "1990-1-1-0:0:0.0 to 2089-12-31-23:59:59.999";
        oor("DT#2090-1-1-0:0:0", "date and time", range);
        oor("DT#1989-12-31-23:59:59", "date and time", range);
        oor("DT#1994-3-15-24:0:0", "date and time", range);
        not_a_date("DT#1994-2-29-1:0:0");
        bad("DT#", "date and time", "empty body");
        let malformed =
            "DT#1994-3-15 DT#1994-3-15:1:10:3.3 DT#1994-3-15-1:10 DT#1994-3-15-1:10:3-1";
        for t in malformed.split_whitespace() {
            bad(t, "date and time", "expected 'yyyy-m-d-h:m:s[.fff]'");
        }
        bad(
            "DT#1994-3-15-1:10:3.1234",
            "date and time",
            "at most 3 digits after '.'",
        );
    }

    #[test]
    fn character() {
        assert_eq!(value("'A'"), LiteralValue::Char('A'));
        assert_eq!(class("'A'"), LiteralClass::Character);
        assert_eq!(ty("'E'"), "CHAR");
        assert_eq!(value("''''"), LiteralValue::Char('\''));
        assert_eq!(class("''''"), LiteralClass::Character);
        assert_eq!(value("'ä'"), LiteralValue::Char('ä'));
        assert_eq!(value("'\u{FF}'"), LiteralValue::Char('\u{FF}'));
        oor("'€'", "character", "U+0000 to U+00FF");
        oor("'\u{100}'", "character", "U+0000 to U+00FF");
    }

    #[test]
    fn string() {
        assert_eq!(value("''"), LiteralValue::Str(String::new()));
        assert_eq!(class("''"), LiteralClass::String);
        assert_eq!(value("'AB'"), LiteralValue::Str("AB".to_owned()));
        assert_eq!(value("'it''s'"), LiteralValue::Str("it's".to_owned()));
        assert_eq!(value("''''''"), LiteralValue::Str("''".to_owned()));
        assert_eq!(ty("'AB'"), "STRING");
        assert_eq!(
            class(&format!("'{}'", "x".repeat(254))),
            LiteralClass::String
        );
        // `''` counts as one character.
        assert_eq!(
            class(&format!("'{}'", "''".repeat(254))),
            LiteralClass::String
        );
        oor(&format!("'{}'", "x".repeat(255)), "string", "0 to 254");
        oor("'a€'", "string", "U+0000 to U+00FF");
        bad("'", "string", "missing closing quote");
        bad("'abc", "string", "missing closing quote");
        bad("'''", "string", "missing closing quote");
        bad("'a'b'", "string", "unexpected text after the closing quote");
    }

    #[test]
    fn pointer() {
        let p = |db, area, byte, bit| {
            LiteralValue::Pointer(PointerValue {
                db,
                area,
                byte,
                bit,
            })
        };
        assert_eq!(value("P#M50.0"), p(None, Some("M"), 50, 0));
        assert_eq!(value("p#m50.0"), p(None, Some("M"), 50, 0));
        assert_eq!(value("P#0.0"), p(None, None, 0, 0));
        assert_eq!(value("P#10.0"), p(None, None, 10, 0));
        assert_eq!(value("P#E1.7"), p(None, Some("E"), 1, 7));
        assert_eq!(value("P#I1.7"), p(None, Some("I"), 1, 7));
        assert_eq!(value("P#A2.0"), p(None, Some("A"), 2, 0));
        assert_eq!(value("P#Q2.0"), p(None, Some("Q"), 2, 0));
        assert_eq!(value("P#L0.1"), p(None, Some("L"), 0, 1));
        assert_eq!(value("P#DBX5.0"), p(None, Some("DBX"), 5, 0));
        assert_eq!(value("P#DIX5.0"), p(None, Some("DIX"), 5, 0));
        assert_eq!(value("P#DB10.DBX5.0"), p(Some(10), Some("DBX"), 5, 0));
        // The space after the area is optional, as STEP 7 prints pointers.
        assert_eq!(value("P#M 100.0"), p(None, Some("M"), 100, 0));
        assert_eq!(value("P#DBX 8.6"), p(None, Some("DBX"), 8, 6));
        assert_eq!(value("P#DIX\t16.0"), p(None, Some("DIX"), 16, 0));
        assert_eq!(value("P#DB10.DBX  5.0"), p(Some(10), Some("DBX"), 5, 0));
        assert_eq!(ty("P#M 1.0"), "POINTER");
        assert_eq!(value("p#db10.dbx5.0"), p(Some(10), Some("DBX"), 5, 0));
        // Bit and byte numbers are checked in analysis (HG4009, HG4010).
        assert_eq!(value("P#M50.8"), p(None, Some("M"), 50, 8));
        assert_eq!(value("P#M99999.0"), p(None, Some("M"), 99_999, 0));
        assert_eq!(class("P#M50.0"), LiteralClass::Pointer);
        assert_eq!(ty("P#0.0"), "POINTER");
        bad("P#", "pointer", "empty body");
        let not_addresses = "P#M50 P#MW10 P#MW10.0 P#PE1.0 P#X1.0 P#DB10.DBW4 P#DB10.DBX5 P#DB10 \
                             P#DB.DBX1.0 P#M5_0.0 P#M50.0.1 P#.0 P#1. P#T5 P#M-1.0";
        let spaced = [
            "P# M50.0",
            "P#M 50",
            "P#M .0",
            "P# 0.0",
            "P#MW 10",
            "P#M 5 0.0",
            "P#M\n1.0",
        ];
        for t in not_addresses.split_whitespace().chain(spaced) {
            bad(
                t,
                "pointer",
                "expected a bit address or 'byte.bit' after 'P#'",
            );
        }
    }

    #[test]
    fn acceptance() {
        use Acceptance::{Accepted, Mismatch};
        let acc = |ty: &str, t: &str| accepts(ty, &lit(t));
        let range = |min: &str, max: &str| Acceptance::OutOfRange {
            min: min.to_owned(),
            max: max.to_owned(),
        };
        assert_eq!(acc("BOOL", "TRUE"), Accepted);
        assert_eq!(acc("BOOL", "1"), Mismatch);
        assert_eq!(acc("BYTE", "B#16#FF"), Accepted);
        assert_eq!(acc("byte", "2#1111_1111"), Accepted);
        assert_eq!(acc("BYTE", "2#1_1111_1111"), Mismatch);
        assert_eq!(acc("BYTE", "255"), Accepted);
        assert_eq!(acc("BYTE", "300"), range("0", "255"));
        assert_eq!(acc("BYTE", "-1"), range("0", "255"));
        assert_eq!(acc("BYTE", "W#16#1"), Mismatch);
        assert_eq!(acc("WORD", "B#16#1"), Accepted);
        assert_eq!(acc("WORD", "W#16#1"), Accepted);
        assert_eq!(acc("WORD", "DW#16#1"), Mismatch);
        assert_eq!(acc("WORD", "B#(1,2)"), Accepted);
        assert_eq!(acc("WORD", "B#(1,2,3,4)"), Mismatch);
        assert_eq!(acc("WORD", "C#5"), Accepted);
        assert_eq!(acc("WORD", "65535"), Accepted);
        assert_eq!(acc("WORD", "65536"), range("0", "65535"));
        assert_eq!(acc("DWORD", "B#(1,2,3,4)"), Accepted);
        assert_eq!(acc("DWORD", "B#(1,2)"), Accepted);
        assert_eq!(acc("DWORD", "2#1"), Accepted);
        assert_eq!(acc("DWORD", "-1"), range("0", "2147483647"));
        assert_eq!(acc("DWORD", "C#1"), Mismatch);
        assert_eq!(acc("INT", "40000"), range("-32768", "32767"));
        assert_eq!(acc("INT", "L#5"), Mismatch);
        assert_eq!(acc("INT", "W#16#1"), Mismatch);
        assert_eq!(acc("DINT", "40000"), Accepted);
        assert_eq!(acc("DINT", "L#5"), Accepted);
        assert_eq!(acc("REAL", "1.5"), Accepted);
        assert_eq!(acc("REAL", "15"), Accepted);
        assert_eq!(acc("S5TIME", "S5T#1S"), Accepted);
        assert_eq!(acc("S5TIME", "T#1S"), Mismatch);
        assert_eq!(acc("TIME", "T#1S"), Accepted);
        assert_eq!(acc("DATE", "D#1994-3-15"), Accepted);
        assert_eq!(acc("TIME_OF_DAY", "TOD#1:0:0"), Accepted);
        assert_eq!(acc("DATE_AND_TIME", "DT#1994-3-15-1:0:0"), Accepted);
        assert_eq!(acc("CHAR", "'A'"), Accepted);
        assert_eq!(acc("CHAR", "'AB'"), Mismatch);
        assert_eq!(acc("STRING[2]", "'AB'"), Accepted);
        assert_eq!(acc("string [ 2 ]", "'A'"), Accepted);
        assert_eq!(acc("STRING[1]", "'AB'"), range("0", "1"));
        assert_eq!(acc("STRING", "''"), Accepted);
        assert_eq!(acc("STRING[x]", "'A'"), Mismatch);
        assert_eq!(acc("STRING[2]", "5"), Mismatch);
        assert_eq!(acc("POINTER", "P#M1.0"), Accepted);
        assert_eq!(acc("TIMER", "T#1S"), Mismatch);
        assert_eq!(acc("COUNTER", "C#1"), Mismatch);
        assert_eq!(acc("ANY", "5"), Mismatch);
    }

    #[test]
    fn chart_adaptation() {
        let adapt = |t: &str, other: Option<&str>| chart_literal_type(&lit(t), other);
        assert_eq!(adapt("5", Some("BYTE")), "BYTE");
        assert_eq!(adapt("5", Some("word")), "WORD");
        assert_eq!(adapt("5", Some("REAL")), "REAL");
        assert_eq!(adapt("5", Some("DINT")), "DINT");
        assert_eq!(adapt("300", Some("BYTE")), "INT");
        assert_eq!(adapt("40000", Some("INT")), "DINT");
        assert_eq!(adapt("5", Some("TIME")), "INT");
        assert_eq!(adapt("5", None), "DINT");
        assert_eq!(adapt("1.5", Some("INT")), "REAL");
        assert_eq!(adapt("W#16#1", Some("DWORD")), "WORD");
        assert_eq!(adapt("T#1S", None), "TIME");
    }

    #[test]
    fn odd_inputs_never_panic() {
        let odd = "# ## B# T# B#( B#) 2# - '' ' ä é# #ä B#16#ä T#1ä T#ä D#ä-1-1 TOD#ä DT#ä P#ä P#Mä.0 \
                   B#(ä,1) C#ä L#-ä 'ä -ä 1ä 1.ä 1eä S5T#_ T#_ T#-_ T#1_ T#1._5S DT#--- DT#1-1-1- \
                   TOD#:: TOD#1:1:1. B#(,) B#(,,,) P#DB P#DB1 P#DB1. P#DB1.DBX P#DB1.DBX. 2#_ \
                   W#16#_ TRUE# S5T#1. T#1.5 T#99999999999999999999999999999999999999.9999999D \
                   B#16#FFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF \
                   D#99999999999999999999999999999999999999999999-99999999999999999999-1 \
                   TOD#99999999999999999999999999999999999999999:1:1.999";
        let special = [
            "", " ", "\u{FEFF}", "\n", "'\n'", "'a\u{0}'", "B#( )", "P#M 1.0",
        ];
        for text in odd.split_whitespace().chain(special) {
            let _ = check_literal(text);
        }
    }

    proptest::proptest! {
        #[test]
        fn never_panics_on_any_string(s in "\\PC*") {
            if let Ok(lit) = check_literal(&s) {
                let _ = literal_type(&lit);
                let _ = accepts("STRING[3]", &lit);
                let _ = chart_literal_type(&lit, Some("BYTE"));
            }
        }

        #[test]
        fn never_panics_on_typed_shapes(
            s in "(B|W|DW|C|L|S5T|T|D|TOD|DT|P|2|16|X)#[0-9A-Za-z_.:#()\\-, ä]{0,16}"
        ) {
            let _ = check_literal(&s);
        }
    }
}
