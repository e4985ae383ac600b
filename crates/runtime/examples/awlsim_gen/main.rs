//! The generator of the Awlsim differential suite (`runtime.md` §9.1).
//!
//! `cargo run -p higraph-runtime --example awlsim_gen -- [--count N] [--seed S]
//! [--family F[,F...]] [--cases DIR] [--bench N] > cases.jsonl`
//!
//! Writes one JSON object per line: a straight-line STL block (SIMATIC mnemonics), its initial
//! accumulators, status word and memory, and per cycle the state our interpreter reaches after
//! every instruction (ACCU1, ACCU2, the nine status bits, every byte the block touches) with a
//! comparison mode per instruction (exact; NaN by class; timer value ± one base unit; or an
//! excluded deviation of §9.2 from there on). `tests/awlsim/harness.py` runs the same blocks in
//! Awlsim and compares. `--cases DIR` adds the hand-written `*.awl` files of DIR. `--bench N`
//! instead times N runs of a typical block mix and prints instructions per second.

mod parse;

use std::fmt::Write as _;
use std::io::Write as _;

use higraph_runtime::machine::{Machine, Status};
use higraph_runtime::program::{Block, Instr, MemArea, OpCode, Operand, Place, Program, Width};
use higraph_runtime::stl;
use serde_json::{Value as J, json};

// ------------------------------------------------------------------------------ random

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.below((hi - lo + 1) as u64) as i64
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.below(100) < percent
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len() as u64) as usize]
    }
    fn u32(&mut self) -> u32 {
        self.next() as u32
    }
}

// ------------------------------------------------------------------------------ families

const FAMILIES: &[&str] = &[
    "bits",
    "timers",
    "counters",
    "load",
    "wordlogic",
    "compare",
    "intarith",
    "realarith",
    "shift",
    "convert",
];

const AREAS: &[&str] = &["E", "A", "M", "L", "DB1.DB"];

fn bit_addr(r: &mut Rng, bytes: u32) -> String {
    let a = *r.pick(AREAS);
    let byte = r.below(bytes as u64);
    let bit = r.below(8);
    if a == "DB1.DB" {
        format!("DB1.DBX {byte}.{bit}")
    } else {
        format!("{a} {byte}.{bit}")
    }
}

fn sized_addr(r: &mut Rng, size: char, bytes: u32) -> String {
    let a = *r.pick(AREAS);
    let byte = r.below(bytes as u64);
    if a == "DB1.DB" {
        format!("DB1.DB{size} {byte}")
    } else {
        format!("{a}{size} {byte}")
    }
}

/// An interesting 32-bit value.
fn value32(r: &mut Rng) -> u32 {
    match r.below(10) {
        0 => 0,
        1 => r.range(-3, 3) as i32 as u32,
        2 => *r.pick(&[
            0x7FFF,
            0x8000,
            0xFFFF,
            0x7FFF_FFFF,
            0x8000_0000,
            0xFFFF_8000,
            0x0001_0000,
        ]),
        3 => r.range(-40000, 40000) as i32 as u32,
        4 => r.range(-32768, 32767) as i16 as u16 as u32 | (r.u32() & 0xFFFF_0000),
        _ => r.u32(),
    }
}

fn real_value(r: &mut Rng) -> f32 {
    match r.below(14) {
        0 => 0.0,
        1 => -0.0,
        2 => *r.pick(&[1.0, -1.0, 0.5, 2.0, 3.0, -2.5, 10.0, 1e-7, 100.0]),
        3 => *r.pick(&[f32::INFINITY, f32::NEG_INFINITY, f32::NAN]),
        4 => *r.pick(&[
            f32::MAX,
            -f32::MAX,
            f32::MIN_POSITIVE,
            3e38,
            1e20,
            1e-20,
            1e-38,
        ]),
        5 => f32::from_bits(r.u32() & 0x807F_FFFF), // subnormal
        6 => r.range(-2_000_000_000, 2_000_000_000) as f32,
        7 => (r.range(-20000, 20000) as f32) / 8.0,
        8 => (r.range(-100, 100) as f32) / 10.0,
        9 => r.range(-3, 3) as f32 + 0.5,
        _ => {
            let e = r.range(-30, 30) as f32;
            let m = (r.u32() as f32 / u32::MAX as f32) * if r.chance(50) { 1.0 } else { -1.0 };
            m * 2f32.powf(e)
        }
    }
}

fn real_text(x: f32) -> String {
    if x.is_finite() && x != 0.0 && x.abs() >= 1e-30 && x.abs() <= 1e30 {
        // Exact round trip: Awlsim parses the literal as a double and rounds it to binary32.
        let t = format!("{x:e}");
        let (m, e) = t.split_once('e').unwrap_or((&t, "0"));
        if m.contains('.') {
            format!("{m}E{e}")
        } else {
            format!("{m}.0E{e}")
        }
    } else {
        format!("DW#16#{:08X}", x.to_bits())
    }
}

fn bcd3(r: &mut Rng) -> u32 {
    stl::to_bcd(r.below(1000) as u32)
}

/// Loads an interesting value by one of the constant spellings.
fn load_const(r: &mut Rng) -> String {
    match r.below(16) {
        0 => format!("L {}", r.range(-32768, 32767)),
        1 => format!("L L#{}", r.range(i32::MIN as i64, i32::MAX as i64)),
        2 => format!("L W#16#{:04X}", r.below(0x10000)),
        3 => format!("L DW#16#{:08X}", value32(r)),
        4 => format!("L B#16#{:02X}", r.below(256)),
        5 => format!("L 2#{:b}", r.below(0x10000)),
        6 => format!("L C#{}", r.below(1000)),
        7 => {
            // S5T# in the range where Awlsim does not truncate (bases 10 ms and 100 ms)
            let ms = if r.chance(50) {
                r.below(999) * 10
            } else {
                r.below(999) * 100
            };
            format!("L S5T#{}MS", ms.max(10))
        }
        // Multiples of 125 ms: Awlsim reads T# through floating-point seconds and truncates
        // (T#16037MS gives 16036), a literal-reading difference outside the STL semantics.
        8 => format!("L T#{}MS", r.range(-800, 800) * 125),
        9 => format!("L {}", real_text(real_value(r))),
        10 => {
            let cs: String = (0..r.range(1, 4))
                .map(|_| (b'A' + r.below(26) as u8) as char)
                .collect();
            format!("L '{cs}'")
        }
        11 => format!("L P#M {}.{}", r.below(100), r.below(8)),
        12 => format!(
            "L TOD#{}:{}:{}.{:03}",
            r.below(24),
            r.below(60),
            r.below(60),
            r.below(1000)
        ),
        13 => format!(
            "L D#{}-{:02}-{:02}",
            r.range(1990, 2150),
            r.range(1, 12),
            r.range(1, 28)
        ),
        14 => format!("L P#{}.{}", r.below(100), r.below(8)),
        _ => format!("L {}", value32(r) as i16),
    }
}

fn gen_bits(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(3, 24);
    let mut depth = 0;
    for _ in 0..n {
        let k = r.below(100);
        if k < 40 {
            let op = r.pick(&["U", "UN", "O", "ON", "X", "XN"]);
            code.push(format!("{op} {}", bit_addr(r, 6)));
        } else if k < 48 && depth < 7 {
            code.push(r.pick(&["U(", "UN(", "O(", "ON(", "X(", "XN("]).to_string());
            depth += 1;
        } else if k < 56 && depth > 0 {
            code.push(")".into());
            depth -= 1;
        } else if k < 60 {
            code.push("O".into());
        } else if k < 72 {
            let op = r.pick(&["=", "S", "R"]);
            code.push(format!("{op} {}", bit_addr(r, 6)));
        } else if k < 80 {
            code.push(r.pick(&["SET", "CLR", "NOT"]).to_string());
        } else if k < 88 {
            let op = r.pick(&["FP", "FN"]);
            code.push(format!("{op} M {}.{}", 20 + r.below(2), r.below(8)));
        } else {
            // comparisons inside the logic string
            code.push(format!("L {}", r.range(-3, 3)));
            code.push(format!("L {}", r.range(-3, 3)));
            code.push(
                r.pick(&["==I", "<>I", ">I", "<I", ">=I", "<=I"])
                    .to_string(),
            );
        }
    }
    for _ in 0..depth {
        code.push(")".into());
    }
    code.push(format!("= {}", bit_addr(r, 6)));
}

/// Timers over several cycles: the stimulus bits M 100.x change between cycles.
fn gen_timers(r: &mut Rng, code: &mut Vec<String>) {
    // One start operation per timer (mixing them on one timer is a deviation, see the report).
    let kinds: Vec<&str> = (0..3)
        .map(|_| *r.pick(&["SI", "SV", "SE", "SS", "SA"]))
        .collect();
    let n = r.range(3, 12);
    for _ in 0..n {
        let t = r.below(3) as usize;
        match r.below(100) {
            0..=34 => {
                code.push(format!("{} M 100.{}", r.pick(&["U", "UN"]), r.below(4)));
                if r.chance(30) {
                    code.push(format!(
                        "{} M 100.{}",
                        r.pick(&["U", "O", "UN"]),
                        r.below(4)
                    ));
                }
                let d = if r.chance(80) {
                    format!("S5T#{}MS", r.below(13) * 10)
                } else if r.chance(50) {
                    format!("W#16#{:04X}", 0x1000 | r.below(3))
                } else {
                    format!("W#16#{:04X}", r.below(13) as u32 | (r.below(2) as u32) << 4)
                };
                code.push(format!("L {d}"));
                code.push(format!("{} T {t}", kinds[t]));
            }
            35..=44 => {
                code.push(format!("U M 100.{}", r.below(4)));
                code.push(format!("FR T {t}"));
            }
            45..=50 => {
                code.push(format!("U M 100.{}", r.below(8)));
                code.push(format!("R T {t}"));
            }
            51..=79 => {
                code.push(format!("{} T {t}", r.pick(&["U", "UN", "O", "X"])));
                code.push(format!("= M 101.{}", r.below(8)));
            }
            _ => code.push(format!("{} T {t}", r.pick(&["L", "LC"]))),
        }
    }
    for t in 0..3 {
        code.push(format!("U T {t}"));
        code.push(format!("= M 102.{t}"));
    }
}

fn gen_counters(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(3, 14);
    for _ in 0..n {
        let c = r.below(3);
        match r.below(100) {
            0..=39 => {
                code.push(format!("{} M 100.{}", r.pick(&["U", "UN"]), r.below(4)));
                code.push(format!("{} Z {c}", r.pick(&["ZV", "ZR"])));
            }
            40..=54 => {
                code.push(format!("U M 100.{}", r.below(4)));
                if r.chance(85) {
                    let v = if r.chance(20) {
                        *r.pick(&[0, 1, 998, 999])
                    } else {
                        r.below(1000)
                    };
                    code.push(format!("L C#{v}"));
                }
                code.push(format!("S Z {c}"));
            }
            55..=62 => {
                code.push(format!("U M 100.{}", r.below(8)));
                code.push(format!("R Z {c}"));
            }
            63..=70 => {
                code.push(format!("U M 100.{}", r.below(4)));
                code.push(format!("FR Z {c}"));
            }
            71..=85 => {
                code.push(format!("{} Z {c}", r.pick(&["U", "UN", "O", "X"])));
                code.push(format!("= M 101.{}", r.below(8)));
            }
            _ => code.push(format!("{} Z {c}", r.pick(&["L", "LC"]))),
        }
    }
}

fn gen_load(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(3, 16);
    for _ in 0..n {
        match r.below(100) {
            0..=29 => code.push(load_const(r)),
            30..=49 => {
                let s = *r.pick(&['B', 'W', 'D']);
                code.push(format!("L {}", sized_addr(r, s, 12)));
            }
            50..=69 => {
                let s = *r.pick(&['B', 'W', 'D']);
                code.push(format!("T {}", sized_addr(r, s, 12)));
            }
            70..=74 => code.push(format!("{} {}", r.pick(&["INC", "DEC"]), r.below(256))),
            75..=79 => code.push(format!("+ {}", r.range(-32768, 32767))),
            80..=83 => code.push(format!("+ L#{}", r.range(i32::MIN as i64, i32::MAX as i64))),
            _ => code.push(
                r.pick(&["TAK", "PUSH", "POP", "TAW", "TAD", "TAR1", "TAR2", "TAR"])
                    .to_string(),
            ),
        }
    }
}

fn gen_wordlogic(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(2, 10);
    for _ in 0..n {
        match r.below(10) {
            0..=2 => code.push(format!("L DW#16#{:08X}", value32(r))),
            3..=5 => {
                let op = r.pick(&["UW", "OW", "XOW", "UD", "OD", "XOD"]);
                if r.chance(50) {
                    if op.ends_with('W') {
                        code.push(format!("{op} W#16#{:04X}", r.below(0x10000)));
                    } else {
                        code.push(format!("{op} DW#16#{:08X}", value32(r)));
                    }
                } else {
                    code.push(op.to_string());
                }
            }
            6 => code.push("TAK".into()),
            _ => code.push(format!("T MD {}", 4 * r.below(3))),
        }
    }
}

fn cmp_value(r: &mut Rng, kind: char, other: Option<u32>) -> String {
    if let (Some(o), true) = (other, r.chance(30)) {
        // equal or neighbouring values
        return match kind {
            'R' => real_text(f32::from_bits(o)),
            _ => format!("L#{}", (o as i32).wrapping_add(r.range(-1, 1) as i32)),
        };
    }
    match kind {
        'I' => format!("{}", {
            let xs = [r.range(-32768, 32767), r.range(-3, 3), 32767, -32768];
            *r.pick(&xs)
        }),
        'D' => format!("L#{}", value32(r) as i32),
        _ => real_text(real_value(r)),
    }
}

fn gen_compare(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(1, 5);
    for _ in 0..n {
        let kind = *r.pick(&['I', 'D', 'R']);
        let a = cmp_value(r, kind, None);
        let a_bits = parse::instr(&format!("L {a}")).map(|i| match i.operand {
            Operand::Imm(v) => v,
            _ => 0,
        });
        let b = cmp_value(r, kind, a_bits.ok());
        code.push(format!("L {a}"));
        code.push(format!("L {b}"));
        if r.chance(20) {
            code.push(format!("{} {}", r.pick(&["U", "O", "X"]), bit_addr(r, 4)));
        }
        let paren = r.chance(25);
        if paren {
            code.push(r.pick(&["U(", "O(", "X("]).to_string());
        }
        let op = r.pick(&["==", "<>", ">", "<", ">=", "<="]);
        code.push(format!("{op}{kind}"));
        if paren {
            code.push(")".into());
        }
        if r.chance(50) {
            code.push(format!(
                "{} {}",
                r.pick(&["U", "O", "X", "UN"]),
                bit_addr(r, 4)
            ));
        }
        code.push(format!("= {}", bit_addr(r, 4)));
    }
}

fn gen_intarith(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(1, 6);
    for _ in 0..n {
        let dint = r.chance(50);
        for _ in 0..2 {
            if dint {
                code.push(format!("L L#{}", value32(r) as i32));
            } else if r.chance(70) {
                let v = {
                    let xs = [r.range(-32768, 32767), r.range(-5, 5), 32767, -32768, -1, 0];
                    *r.pick(&xs)
                };
                code.push(format!("L {v}"));
            } else {
                code.push(format!("L DW#16#{:08X}", value32(r)));
            }
        }
        let op = if dint {
            r.pick(&["+D", "-D", "*D", "/D", "MOD", "NEGD"])
        } else {
            r.pick(&["+I", "-I", "*I", "/I", "NEGI"])
        };
        code.push(op.to_string());
        if r.chance(30) {
            code.push(
                r.pick(&["+I", "-I", "*I", "/I", "+D", "-D", "*D", "/D", "MOD"])
                    .to_string(),
            );
        }
        if r.chance(30) {
            code.push(format!("T MD {}", 4 * r.below(3)));
        }
    }
}

fn gen_realarith(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(1, 6);
    for _ in 0..n {
        code.push(format!("L {}", real_text(real_value(r))));
        if r.chance(70) {
            code.push(format!("L {}", real_text(real_value(r))));
            code.push(r.pick(&["+R", "-R", "*R", "/R"]).to_string());
        } else {
            if r.chance(50) {
                // arguments near the interesting points of the functions
                code.pop();
                let x = *r.pick(&[
                    0.5f32, -0.5, 0.9, -0.9, 1.5, 0.01, 2.0, 0.785, 3.25, 20.0, -20.0, 88.0, 89.0,
                    -104.0,
                ]);
                code.push(format!("L {}", real_text(x)));
            }
            code.push(
                r.pick(&[
                    "ABS", "NEGR", "SQR", "SQRT", "EXP", "LN", "SIN", "COS", "TAN", "ASIN", "ACOS",
                    "ATAN",
                ])
                .to_string(),
            );
        }
        if r.chance(20) {
            code.push("TAK".into());
        }
    }
}

fn gen_shift(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(1, 8);
    for _ in 0..n {
        match r.below(10) {
            0..=2 => code.push(format!("L DW#16#{:08X}", value32(r))),
            3 => code.push(format!("L {}", r.below(40))),
            _ => {
                let op = r.pick(&[
                    "SLW", "SRW", "SSI", "SLD", "SRD", "SSD", "RLD", "RRD", "RLDA", "RRDA",
                ]);
                if op.ends_with('A') || r.chance(40) {
                    code.push(op.to_string());
                } else {
                    let max = if op.ends_with('W') || *op == "SSI" {
                        16
                    } else {
                        32
                    };
                    let k = if r.chance(80) {
                        r.below(max + 1)
                    } else {
                        r.range(max as i64, 255) as u64
                    };
                    code.push(format!("{op} {k}"));
                }
            }
        }
    }
}

fn gen_convert(r: &mut Rng, code: &mut Vec<String>) {
    let n = r.range(1, 6);
    for _ in 0..n {
        match r.below(8) {
            0 => {
                let sign = if r.chance(50) { 0x8000 } else { 0 };
                code.push(format!(
                    "L W#16#{:04X}",
                    sign | bcd3(r) | (r.below(8) as u32) << 12 & 0x7000
                ));
                code.push("BTI".into());
            }
            1 => {
                let v = stl::to_bcd(r.below(10_000_000) as u32)
                    | if r.chance(50) { 0xF000_0000 } else { 0 };
                code.push(format!("L DW#16#{v:08X}"));
                code.push("BTD".into());
            }
            2 => {
                code.push(format!("L {}", {
                    let xs = [r.range(-999, 999), r.range(-32768, 32767), 999, -999, 1000];
                    *r.pick(&xs)
                }));
                code.push("ITB".into());
            }
            3 => {
                let v = {
                    let xs = [
                        r.range(-9_999_999, 9_999_999),
                        value32(r) as i32 as i64,
                        9_999_999,
                        -10_000_000,
                    ];
                    *r.pick(&xs)
                };
                code.push(format!("L L#{v}"));
                code.push("DTB".into());
            }
            4 => {
                code.push(format!("L DW#16#{:08X}", value32(r)));
                code.push(r.pick(&["ITD", "DTR", "INVI", "INVD"]).to_string());
            }
            _ => {
                let x = match r.below(4) {
                    0 => (r.range(-40, 40) as f32) / 4.0,
                    1 => *r.pick(&[
                        2147483520.0f32,
                        2147483648.0,
                        -2147483648.0,
                        -2147483904.0,
                        0.49999997,
                        -0.5,
                        1.5,
                        2.5,
                    ]),
                    _ => real_value(r),
                };
                code.push(format!("L {}", real_text(x)));
                code.push(r.pick(&["RND", "RND+", "RND-", "TRUNC"]).to_string());
            }
        }
    }
}

fn generate(family: &str, r: &mut Rng) -> Vec<String> {
    let mut code = Vec::new();
    match family {
        "bits" => gen_bits(r, &mut code),
        "timers" => gen_timers(r, &mut code),
        "counters" => gen_counters(r, &mut code),
        "load" => gen_load(r, &mut code),
        "wordlogic" => gen_wordlogic(r, &mut code),
        "compare" => gen_compare(r, &mut code),
        "intarith" => gen_intarith(r, &mut code),
        "realarith" => gen_realarith(r, &mut code),
        "shift" => gen_shift(r, &mut code),
        _ => gen_convert(r, &mut code),
    }
    code
}

fn cycles_of(family: &str) -> u64 {
    match family {
        "timers" => 16,
        "counters" => 8,
        _ => 1,
    }
}

// ------------------------------------------------------------------------------ running

fn area_name(a: MemArea) -> String {
    match a {
        MemArea::Input => "E".into(),
        MemArea::Output => "A".into(),
        MemArea::Memory => "M".into(),
        MemArea::Local => "L".into(),
        MemArea::Db(n) => format!("DB{n}"),
    }
}

/// The bytes an operand touches.
fn touched(code: &[Instr]) -> Vec<(MemArea, u32)> {
    let mut out: Vec<(MemArea, u32)> = Vec::new();
    for i in code {
        if let Operand::Place(Place::Mem { area, byte, width }) = &i.operand {
            let n = match width {
                Width::Bit(_) | Width::Byte => 1,
                Width::Word => 2,
                Width::Dword => 4,
            };
            for b in *byte..*byte + n {
                if !out.contains(&(*area, b)) {
                    out.push((*area, b));
                }
            }
        }
    }
    out
}

/// Comparison modes of one instruction (the harness's `mode`).
const EXACT: u8 = 0;
const NAN_CLASS: u8 = 1;
const STOP: u8 = 2;
const TIMER_VALUE: u8 = 3;
const NEAR: u8 = 4;
/// A STOP after which Awlsim may raise an error: the case runs alone.
const ISOLATE: u8 = 5;

fn f(v: u32) -> f32 {
    f32::from_bits(v)
}

fn is_sub(x: f64) -> bool {
    x != 0.0 && x.abs() < f32::MIN_POSITIVE as f64
}

/// The comparison mode of `ins` run on machine state `m` (before it): a known deviation of
/// §9.2 (or one found by this suite, listed in the report) ends the comparison of the block.
// Each branch names a different deviation, though several give the same mode.
#[allow(clippy::if_same_then_else)]
fn mode(ins: &Instr, m: &Machine, timers: &mut [(bool, bool); 4]) -> u8 {
    use OpCode::*;
    let (a, b) = (f(m.accu2) as f64, f(m.accu1) as f64);
    match ins.op {
        AddR | SubR | MulR | DivR => {
            let exact = match ins.op {
                AddR => a + b,
                SubR => a - b,
                MulR => a * b,
                _ => a / b,
            };
            let r = exact as f32;
            let (a_bits, b_bits) = (m.accu2, m.accu1);
            if ins.op == DivR && ((a.is_infinite() && b.is_infinite()) || (a == 0.0 && b == 0.0)) {
                STOP // ∞/∞, 0/0
            } else if ins.op == DivR
                && ((b.is_infinite() && (a.is_nan() || (a_bits ^ b_bits) >> 31 != 0))
                    || b_bits == 0x8000_0000
                    || (b == 0.0 && a.is_nan()))
            {
                STOP // unlisted: Awlsim's x/±∞ is +0.0, x/−0.0 is +∞ for x ≥ 0, NaN/0 is −∞
            } else if ins.op == MulR
                && ((b.is_infinite() && a.is_finite() && a != 0.0)
                    || (b.is_infinite() && a.is_nan())
                    || (a.is_infinite() && b.is_nan()))
            {
                STOP // unlisted: Awlsim's x · ±∞ gives ±x
            } else if r.is_infinite() && exact.is_finite() {
                STOP // overflow
            } else if is_sub(r as f64) || (r == 0.0 && exact != 0.0) {
                STOP // unlisted: Awlsim keeps the denormal pattern
            } else if r.is_nan() {
                NAN_CLASS
            } else {
                EXACT
            }
        }
        Sqr | Sqrt | Exp | Ln | Sin | Cos | Tan | Asin | Acos | Atan => {
            let x = b;
            let v = match ins.op {
                Sqr => x * x,
                Sqrt => x.sqrt(),
                Exp => x.exp(),
                Ln => x.ln(),
                Sin => x.sin(),
                Cos => x.cos(),
                Tan => x.tan(),
                Asin => x.asin(),
                Acos => x.acos(),
                _ => x.atan(),
            };
            let r = v as f32;
            if x.is_nan() || v.is_nan() {
                NAN_CLASS
            } else if x.is_infinite() || is_sub(b) {
                STOP // unlisted: Awlsim computes on ±∞ and denormal operands
            } else if (r.is_infinite() && v.is_finite()) || v.is_infinite() {
                STOP
            } else if is_sub(r as f64) || (r == 0.0 && v != 0.0) {
                STOP
            } else if (v + 1.0).abs() < 1e-6 || v.abs() < 1e-6 || (v - 1.0).abs() < 1e-6 {
                STOP // snapped near −1, 0, 1
            } else {
                NEAR
            }
        }
        EqR | NeR | GtR | LtR | GeR | LeR => {
            let d = a - b;
            if a.is_nan() || b.is_nan() {
                EXACT
            } else if (d as f32).is_infinite() || is_sub(d as f32 as f64) || d.is_nan() {
                STOP // difference overflows or is denormal (or ∞ − ∞)
            } else {
                EXACT
            }
        }
        // unlisted: Awlsim's RND+ of −0.0 gives 1
        RndPlus if m.accu1 == 0x8000_0000 => STOP,
        S if matches!(&ins.operand, Operand::Place(Place::Counter(_))) => {
            let Operand::Place(Place::Counter(c)) = &ins.operand else {
                return EXACT;
            };
            if m.status.rlo && !m.counter_raw(c.0).es && m.accu1 > 0x999 {
                ISOLATE // §9.2: preset bits 12–31 set (Awlsim stops with an error)
            } else {
                EXACT
            }
        }
        Si | Se | Sa | Sv | Ss | R | L | Lc | U | Un | O | On | X | Xn | Fr => {
            let Operand::Place(Place::Timer(t)) = &ins.operand else {
                return EXACT;
            };
            let id = t.0 as usize;
            if id >= 4 {
                return EXACT;
            }
            // Awlsim expires a timer only when it is read (U, O, X, L, LC) or stopped (SI/SE
            // with RLO 0, SA on a rising edge); we expire it before every operation. The
            // shadow tracks (stale: Awlsim's `L T` would give a stopped timer's old value,
            // pending: we expired it and Awlsim has not yet).
            let raw = m.timer_raw(t.0);
            let due = raw.running && m.now_ms >= raw.deadline;
            let running = raw.running && !due;
            let r = m.status.rlo;
            let (stale, pending) = &mut timers[id];
            let awlsim_checks = match ins.op {
                U | Un | O | On | X | Xn | L | Lc => true,
                Si | Se => !r,
                Sa => r && !raw.e,
                _ => false,
            };
            if due && !awlsim_checks {
                *pending = true;
            }
            if awlsim_checks {
                *pending = false;
            }
            match ins.op {
                L | Lc => return if *stale { STOP } else { TIMER_VALUE },
                R if r => {
                    *stale = false;
                    *pending = false;
                }
                Si | Se if !r && running => *stale = true,
                Sa if r && !raw.e && running => *stale = true,
                _ => {}
            }
            let starts = match ins.op {
                Si | Se | Sv | Ss => r && !raw.e,
                Sa => !r && raw.e,
                _ => false,
            };
            if starts {
                *stale = false;
                if *pending {
                    // unlisted: Awlsim restarts a timer past its deadline without expiring it
                    return STOP;
                }
            }
            EXACT
        }
        _ => EXACT,
    }
}

struct Case {
    id: String,
    family: String,
    code: Vec<String>,
    instrs: Vec<Instr>,
    rlo0: bool,
    accu1: u32,
    accu2: u32,
    /// OS OV CC0 CC1 BR as status-word bits.
    sw: u16,
    init: Vec<(MemArea, u32, u8)>,
    /// per cycle: stimulus (byte M 100 value)
    stim: Vec<u8>,
}

struct Watch<'a> {
    bytes: &'a [(MemArea, u32)],
    timers: [(bool, bool); 4],
    stopped: bool,
    isolate: bool,
    mode: u8,
    snaps: Vec<J>,
}

impl stl::Observer for Watch<'_> {
    fn before(&mut self, _i: usize, ins: &Instr, m: &Machine) {
        let mut md = if self.stopped {
            STOP
        } else {
            mode(ins, m, &mut self.timers)
        };
        if md == ISOLATE {
            self.isolate = true;
            md = STOP;
        }
        if md == STOP {
            self.stopped = true;
        }
        self.mode = md;
    }

    fn after(&mut self, _i: usize, _ins: &Instr, m: &Machine) {
        let mut hex = String::with_capacity(self.bytes.len() * 2);
        for (a, b) in self.bytes {
            let v = m.read_bytes(*a, *b, 1).unwrap_or(0);
            let _ = write!(hex, "{v:02x}");
        }
        self.snaps
            .push(json!([m.accu1, m.accu2, m.status.bits(), hex, self.mode]));
    }
}

fn run_case(c: &Case) -> J {
    let program = Program::default();
    let mut m = Machine::new(&program);
    for (a, b, v) in &c.init {
        let _ = m.write_bytes(*a, *b, 1, *v as u32);
    }
    let block = Block {
        code: c.instrs.clone(),
    };
    let bytes = touched(&c.instrs);
    let mut cycles = Vec::new();
    let mut fault = J::Null;
    let mut w = Watch {
        bytes: &bytes,
        timers: [(false, false); 4],
        stopped: false,
        isolate: false,
        mode: EXACT,
        snaps: Vec::new(),
    };
    for (k, stim) in c.stim.iter().enumerate() {
        m.now_ms = 10 * (k as u64 + 1);
        if c.stim.len() > 1 {
            let _ = m.write_bytes(MemArea::Memory, 100, 1, *stim as u32);
        }
        m.accu1 = c.accu1;
        m.accu2 = c.accu2;
        m.status = Status::from_bits(c.sw);
        let r = stl::run_block_with(&mut m, &[], &block, c.rlo0, &mut w);
        let snaps = std::mem::take(&mut w.snaps);
        let n = snaps.len();
        cycles.push(json!({"t": m.now_ms, "stim": stim, "snaps": snaps}));
        if let Err(e) = r {
            fault = json!({"cycle": k, "instr": n, "reason": e.reason});
            break;
        }
    }
    json!({
        "id": c.id,
        "family": c.family,
        "code": c.code,
        "rlo0": c.rlo0,
        "accu1": c.accu1,
        "accu2": c.accu2,
        "sw": c.sw,
        "init": c.init.iter().map(|(a, b, v)| json!([area_name(*a), b, v])).collect::<Vec<_>>(),
        "touched": bytes.iter().map(|(a, b)| json!([area_name(*a), b])).collect::<Vec<_>>(),
        "cycles": cycles,
        "stim": c.stim,
        "fault": fault,
        "isolate": w.isolate,
    })
}

fn make_case(id: String, family: &str, code: Vec<String>, r: &mut Rng) -> Result<Case, String> {
    let mut instrs = Vec::with_capacity(code.len());
    for (n, line) in code.iter().enumerate() {
        instrs.push(parse::instr(line).map_err(|e| format!("{id} line {}: {e}", n + 1))?);
    }
    let bytes = touched(&instrs);
    let init = bytes
        .iter()
        .map(|(a, b)| (*a, *b, if r.chance(20) { 0 } else { r.below(256) as u8 }))
        .collect();
    let ncycles = cycles_of(family);
    let mut stim = Vec::with_capacity(ncycles as usize);
    let mut s = r.below(256) as u8;
    for _ in 0..ncycles {
        // change a few stimulus bits now and then, so that edges and long runs both occur
        if r.chance(40) {
            s ^= 1 << r.below(4);
        }
        if r.chance(10) {
            s = r.below(256) as u8;
        }
        stim.push(s);
    }
    Ok(Case {
        id,
        family: family.to_string(),
        code,
        instrs,
        rlo0: r.chance(15),
        accu1: value32(r),
        accu2: value32(r),
        sw: (r.below(32) as u16) << 4,
        init,
        stim,
    })
}

/// A hand-written case file: `; family NAME`, `; cycles N`, `; rlo0`, `; stim HH HH ...` (MB 100
/// per cycle, which also sets the number of cycles), then STL lines (`//` starts a comment).
fn hand_case(path: &std::path::Path, r: &mut Rng) -> Result<Case, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut family = "bits".to_string();
    let mut code = Vec::new();
    let mut rlo0 = false;
    let mut cycles = None;
    let mut stim: Option<Vec<u8>> = None;
    for line in text.lines() {
        let l = line.trim();
        if let Some(c) = l.strip_prefix(';') {
            let c = c.trim();
            if let Some(f) = c.strip_prefix("family ") {
                family = f.trim().to_string();
            } else if let Some(n) = c.strip_prefix("cycles ") {
                cycles = n.trim().parse::<usize>().ok();
            } else if c == "rlo0" {
                rlo0 = true;
            } else if let Some(v) = c.strip_prefix("stim ") {
                stim = Some(
                    v.split_whitespace()
                        .map(|x| {
                            u8::from_str_radix(x, 16)
                                .map_err(|e| format!("{}: {e}", path.display()))
                        })
                        .collect::<Result<Vec<u8>, String>>()?,
                );
            }
            continue;
        }
        let l = l.split("//").next().unwrap_or("").trim();
        if !l.is_empty() {
            code.push(l.to_string());
        }
    }
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let mut c = make_case(format!("hand-{name}"), &family, code, r)?;
    c.rlo0 = rlo0;
    if let Some(n) = cycles {
        let last = c.stim.last().copied().unwrap_or(0);
        c.stim.resize(n.max(1), last);
    }
    if let Some(s) = stim {
        c.stim = s;
    }
    Ok(c)
}

fn bench(n: u64) {
    // A typical mix: bit logic with timers and an edge, a comparison, INT arithmetic, a move.
    let text = "U E 0.0\nU E 0.1\nO M 1.0\n= M 1.0\nU M 1.0\nL S5T#200MS\nSE T 1\nU T 1\n= A 0.0\nU E 0.2\nFP M 2.0\nS M 3.0\nL MW 10\nL 5\n+I\nT MW 10\nL MW 10\nL 100\n>I\n= A 0.1\nU(\nO E 0.3\nO E 0.4\n)\nUN M 3.0\n= A 0.2\nL DB1.DBD 0\nL DB1.DBD 4\n+D\nT DB1.DBD 8\n";
    let code: Vec<Instr> = text
        .lines()
        .map(|l| parse::instr(l).expect("bench code"))
        .collect();
    let per = code.len() as u64;
    let block = Block { code };
    let mut m = Machine::new(&Program::default());
    let start = std::time::Instant::now();
    for k in 0..n {
        m.now_ms = 10 * k;
        let _ = stl::run_block(&mut m, &[], &block, false);
    }
    let s = start.elapsed().as_secs_f64();
    let total = n * per;
    println!(
        "{{\"instructions\": {total}, \"seconds\": {s:.4}, \"per_second\": {:.0}}}",
        total as f64 / s
    );
    println!("BENCH-CODE");
    print!("{text}");
}

fn main() {
    let mut count = 100u64;
    let mut seed = 1u64;
    let mut families: Vec<String> = FAMILIES.iter().map(|s| s.to_string()).collect();
    let mut cases_dir: Option<String> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let v = args.next().unwrap_or_default();
        match a.as_str() {
            "--count" => count = v.parse().unwrap_or(count),
            "--seed" => seed = v.parse().unwrap_or(seed),
            "--family" => families = v.split(',').map(str::to_string).collect(),
            "--cases" => cases_dir = Some(v),
            "--bench" => return bench(v.parse().unwrap_or(100_000)),
            _ => {
                eprintln!("unknown argument {a}");
                std::process::exit(2);
            }
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut r = Rng(seed);
    if let Some(dir) = cases_dir {
        let mut paths: Vec<_> = std::fs::read_dir(&dir)
            .map(|d| d.filter_map(|e| e.ok()).map(|e| e.path()).collect())
            .unwrap_or_default();
        paths.retain(|p| p.extension().is_some_and(|e| e == "awl"));
        paths.sort();
        for p in paths {
            match hand_case(&p, &mut r) {
                Ok(c) => {
                    let _ = writeln!(out, "{}", run_case(&c));
                }
                Err(e) => {
                    eprintln!("{e}");
                    std::process::exit(1);
                }
            }
        }
    }
    for fam in &families {
        if !FAMILIES.contains(&fam.as_str()) {
            eprintln!("unknown family {fam}");
            std::process::exit(2);
        }
        let mut r = Rng(seed
            ^ fam
                .bytes()
                .fold(0u64, |h, b| h.wrapping_mul(31).wrapping_add(b as u64)));
        for n in 0..count {
            let code = generate(fam, &mut r);
            match make_case(format!("{fam}-{n}"), fam, code, &mut r) {
                Ok(c) => {
                    let _ = writeln!(out, "{}", run_case(&c));
                }
                Err(e) => {
                    eprintln!("generator bug: {e}");
                    std::process::exit(1);
                }
            }
        }
    }
}
