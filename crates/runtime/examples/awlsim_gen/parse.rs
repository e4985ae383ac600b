//! A small reader of STL text for the differential cases: one instruction per line, SIMATIC
//! mnemonics, absolute operands only (the subset the generator writes and the hand-written
//! cases use). Constants go through `load_pattern`, so their spelling is tested as well.

use higraph_runtime::program::{
    CounterId, Instr, MemArea, OpCode, Operand, Origin, Place, TimerId, Width,
};
use higraph_runtime::stl::load_pattern;
use higraph_runtime::value::Const;

pub fn opcode(s: &str) -> Option<OpCode> {
    OpCode::from_simatic(s)
}

fn num(s: &str) -> Result<u32, String> {
    s.parse::<u32>().map_err(|_| format!("bad number '{s}'"))
}

/// An address: `M 3.1`, `MW 4`, `DB1.DBX 2.0`, `T 3`, `Z 1`, `LB 0`.
pub fn address(s: &str) -> Result<Option<Place>, String> {
    let (head, arg) = match s.split_once(' ') {
        Some((h, a)) => (h.trim(), a.trim()),
        None => return Ok(None),
    };
    let (area, rest) = if let Some(db) = head.strip_prefix("DB") {
        match db.split_once(".DB") {
            Some((n, w)) => (MemArea::Db(num(n)? as u16), w),
            None => return Ok(None),
        }
    } else {
        let mut ch = head.chars();
        let a = match ch.next() {
            Some('E') => MemArea::Input,
            Some('A') => MemArea::Output,
            Some('M') => MemArea::Memory,
            Some('L') => MemArea::Local,
            Some('T') if head == "T" => return Ok(Some(Place::Timer(TimerId(num(arg)?)))),
            Some('Z') if head == "Z" => return Ok(Some(Place::Counter(CounterId(num(arg)?)))),
            _ => return Ok(None),
        };
        (a, ch.as_str())
    };
    let width = match rest {
        "" | "X" => {
            let (b, x) = arg.split_once('.').ok_or("bit address without '.'")?;
            return Ok(Some(Place::Mem {
                area,
                byte: num(b)?,
                width: Width::Bit(num(x)? as u8),
            }));
        }
        "B" => Width::Byte,
        "W" => Width::Word,
        "D" => Width::Dword,
        _ => return Ok(None),
    };
    Ok(Some(Place::Mem {
        area,
        byte: num(arg)?,
        width,
    }))
}

fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146097 + doe - 719468
}

/// `T#1S500MS` style durations in ms.
fn duration(s: &str) -> Result<i64, String> {
    let (neg, s) = match s.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, s),
    };
    let mut total = 0i64;
    let mut n = String::new();
    let up = s.to_ascii_uppercase();
    let b = up.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let c = b[i] as char;
        if c.is_ascii_digit() {
            n.push(c);
            i += 1;
            continue;
        }
        if c == '_' {
            i += 1;
            continue;
        }
        let (mult, len) = if up[i..].starts_with("MS") {
            (1, 2)
        } else {
            match c {
                'D' => (86_400_000, 1),
                'H' => (3_600_000, 1),
                'M' => (60_000, 1),
                'S' => (1000, 1),
                _ => return Err(format!("bad duration '{s}'")),
            }
        };
        total += n
            .parse::<i64>()
            .map_err(|_| format!("bad duration '{s}'"))?
            * mult;
        n.clear();
        i += len;
    }
    Ok(if neg { -total } else { total })
}

/// A constant operand.
pub fn constant(s: &str) -> Result<Const, String> {
    let u = s.to_ascii_uppercase();
    let hex = |t: &str| u64::from_str_radix(&t.replace('_', ""), 16).map_err(|e| e.to_string());
    if let Some(t) = u
        .strip_prefix("DW#16#")
        .or(u.strip_prefix("W#16#"))
        .or(u.strip_prefix("B#16#"))
    {
        return Ok(Const::Bits(hex(t)?));
    }
    if let Some(t) = u.strip_prefix("2#") {
        return Ok(Const::Bits(
            u64::from_str_radix(&t.replace('_', ""), 2).map_err(|e| e.to_string())?,
        ));
    }
    if let Some(t) = u.strip_prefix("L#") {
        return Ok(Const::LongInt(
            t.parse().map_err(|_| format!("bad L# '{s}'"))?,
        ));
    }
    if let Some(t) = u.strip_prefix("C#") {
        return Ok(Const::Counter(
            t.parse().map_err(|_| format!("bad C# '{s}'"))?,
        ));
    }
    if let Some(t) = u.strip_prefix("S5T#") {
        return Ok(Const::S5Time(duration(t)?));
    }
    if let Some(t) = u.strip_prefix("T#") {
        return Ok(Const::Time(duration(t)?));
    }
    if let Some(t) = u.strip_prefix("TOD#") {
        let (hms, frac) = t.split_once('.').unwrap_or((t, "0"));
        let mut it = hms.split(':');
        let mut f = |mul: u32| -> Result<u32, String> {
            Ok(it
                .next()
                .unwrap_or("0")
                .parse::<u32>()
                .map_err(|e| e.to_string())?
                * mul)
        };
        let frac: String = frac.chars().chain("000".chars()).take(3).collect();
        let ms = f(3_600_000)?
            + f(60_000)?
            + f(1000)?
            + frac.parse::<u32>().map_err(|e| e.to_string())?;
        return Ok(Const::TimeOfDay(ms));
    }
    if let Some(t) = u.strip_prefix("D#") {
        let p: Vec<i64> = t.split('-').filter_map(|x| x.parse().ok()).collect();
        if p.len() != 3 {
            return Err(format!("bad date '{s}'"));
        }
        return Ok(Const::Date(
            days_from_civil(p[0], p[1], p[2]) - days_from_civil(1990, 1, 1),
        ));
    }
    if let Some(t) = u.strip_prefix("P#") {
        let (area, rest) = match t.split_once(' ') {
            Some((a, r)) => (
                match a {
                    "E" => 0x81,
                    "A" => 0x82,
                    "M" => 0x83,
                    "DBX" => 0x84,
                    "L" => 0x86,
                    _ => return Err(format!("bad pointer '{s}'")),
                },
                r,
            ),
            None => (0, t),
        };
        let (b, x) = rest.split_once('.').ok_or("bad pointer")?;
        return Ok(Const::Pointer {
            area,
            byte: num(b)?,
            bit: num(x)? as u8,
        });
    }
    if s.starts_with('\'') && s.ends_with('\'') && s.len() >= 3 {
        return Ok(Const::Chars(s[1..s.len() - 1].bytes().collect()));
    }
    if u.contains('.') || u.contains('E') {
        return Ok(Const::Real(
            u.parse().map_err(|_| format!("bad real '{s}'"))?,
        ));
    }
    Ok(Const::Int(
        u.parse().map_err(|_| format!("bad integer '{s}'"))?,
    ))
}

/// One line of STL.
pub fn instr(line: &str) -> Result<Instr, String> {
    let line = line.trim();
    let (op, arg) = match line.split_once(char::is_whitespace) {
        Some((o, a)) => (o, a.trim()),
        None => (line, ""),
    };
    let code = opcode(op).ok_or_else(|| format!("unknown operation '{op}'"))?;
    let code = if code == OpCode::O && arg.is_empty() {
        OpCode::OrNone
    } else {
        code
    };
    let operand = if arg.is_empty() {
        Operand::None
    } else if let Some(p) = address(arg)? {
        Operand::Place(p)
    } else {
        let c = constant(arg)?;
        let code_is_dint_add = code == OpCode::AddInt && matches!(c, Const::LongInt(_));
        let o = Operand::Imm(load_pattern(&c));
        if code_is_dint_add {
            return Ok(Instr {
                op: OpCode::AddDint,
                operand: o,
                origin: Origin(0),
            });
        }
        o
    };
    Ok(Instr {
        op: code,
        operand,
        origin: Origin(0),
    })
}
