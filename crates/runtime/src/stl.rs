//! The STL interpreter (`runtime.md` §3).
//!
//! One instruction is one arm of [`exec`]: operands are resolved through the running
//! instance's binding, the status word lives in the machine, the nesting stack is a fixed
//! array local to the block (blocks start with an empty stack, §3.1). Nothing is allocated per
//! instruction; a [`Fault`] (the only allocation) carries the instruction's origin.

use crate::machine::{Fault, Machine, TimerKind, base_ms};
use crate::program::{Block, Call, Instr, OpCode, Operand, Place};
use crate::value::{Const, Ty, Value};

/// Depth of the nesting stack (§1.2).
pub const NESTING_DEPTH: usize = 7;

/// Runs one instruction block (§3.1) with the running instance's variable binding. In the
/// RLO-0 pass (`rlo0`) the block starts with RLO = STA = 0. Returns the RLO at the block's end.
pub fn run_block(
    m: &mut Machine,
    binding: &[Place],
    block: &Block,
    rlo0: bool,
) -> Result<bool, Fault> {
    run_block_with(m, binding, block, rlo0, &mut ())
}

/// Watches a block run instruction by instruction (the differential tests compare the machine
/// after every instruction). `()` watches nothing and costs nothing.
pub trait Observer {
    /// Before instruction `i` executes.
    fn before(&mut self, _i: usize, _ins: &Instr, _m: &Machine) {}
    /// After instruction `i` has executed.
    fn after(&mut self, _i: usize, _ins: &Instr, _m: &Machine) {}
}

impl Observer for () {}

/// [`run_block`] with an [`Observer`].
#[inline]
pub fn run_block_with<O: Observer>(
    m: &mut Machine,
    binding: &[Place],
    block: &Block,
    rlo0: bool,
    obs: &mut O,
) -> Result<bool, Fault> {
    m.status.rlo = !rlo0;
    m.status.sta = !rlo0;
    m.status.or = false;
    m.status.fc = false;
    let mut nest = Nest::default();
    // In the RLO-0 pass, timer and counter operations execute "exactly as they would with
    // RLO = 1 at block start" (§3.1): until an operation makes the RLO independent of the
    // block's start value (a first check, SET, CLR, a comparison, a call), they see the RLO
    // the normal pass would have, which is the negation of this pass's.
    let mut shadowed = rlo0;
    for (i, ins) in block.code.iter().enumerate() {
        obs.before(i, ins, m);
        let flip = shadowed && is_timer_or_counter_op(binding, ins);
        if flip {
            m.status.rlo = !m.status.rlo;
        }
        let result = exec(m, binding, ins, &mut nest);
        if flip {
            m.status.rlo = !m.status.rlo;
        }
        if let Err(mut f) = result {
            if f.origin == crate::program::Origin::NONE {
                f.origin = ins.origin;
            }
            m.instructions += i as u64 + 1;
            return Err(f);
        }
        if shadowed && ins.op.replaces_rlo() {
            shadowed = false;
        }
        obs.after(i, ins, m);
    }
    m.instructions += block.code.len() as u64;
    Ok(m.status.rlo)
}

/// Does the instruction operate a timer or counter with the RLO as its input?
fn is_timer_or_counter_op(binding: &[Place], ins: &Instr) -> bool {
    use OpCode::*;
    match ins.op {
        Si | Sv | Se | Ss | Sa | Fr | Zv | Zr => true,
        S | R => matches!(
            place(binding, &ins.operand),
            Ok(Place::Timer(_) | Place::Counter(_))
        ),
        _ => false,
    }
}

/// The nesting stack: per entry the opening kind, RLO, OR and /FC.
struct Nest {
    depth: usize,
    entries: [(OpCode, bool, bool, bool); NESTING_DEPTH],
}

impl Default for Nest {
    fn default() -> Self {
        Nest {
            depth: 0,
            entries: [(OpCode::UParen, false, false, false); NESTING_DEPTH],
        }
    }
}

#[inline(always)]
fn place<'a>(binding: &'a [Place], op: &'a Operand) -> Result<&'a Place, Fault> {
    match op {
        Operand::Var(i) => match binding.get(*i as usize) {
            Some(p) => Ok(p),
            None => Err(unbound(*i)),
        },
        Operand::Place(p) => Ok(p),
        _ => Err(Fault::new("the instruction needs an address operand")),
    }
}

#[cold]
fn unbound(i: u16) -> Fault {
    Fault::new(format!("variable {i} is not bound"))
}

#[inline(always)]
fn bit(m: &mut Machine, binding: &[Place], op: &Operand) -> Result<bool, Fault> {
    let p = place(binding, op)?;
    Ok(m.read(p)? & 1 != 0)
}

fn bad_operand(op: OpCode) -> Fault {
    Fault::new(format!("{op:?}: unsupported operand"))
}

/// Decodes `digits` BCD digits from the low bits of `v`; a digit above 9 is a fault (§1.4).
#[inline]
fn from_bcd(v: u32, digits: u32) -> Result<u32, Fault> {
    let mut r = 0u32;
    for i in (0..digits).rev() {
        let d = (v >> (4 * i)) & 0xF;
        if d > 9 {
            return Err(Fault::new(format!("BCD digit {d:X} in 16#{v:X}")));
        }
        r = r * 10 + d;
    }
    Ok(r)
}

/// `v` as BCD digits (v must fit).
#[inline]
pub fn to_bcd(mut v: u32) -> u32 {
    let mut r = 0u32;
    let mut shift = 0;
    while v > 0 {
        r |= (v % 10) << shift;
        v /= 10;
        shift += 4;
    }
    r
}

/// Round half to even of a non-negative ratio `n / d`.
#[inline]
fn div_round_even(n: u64, d: u64) -> u64 {
    let q = n / d;
    let r = n % d;
    if 2 * r > d || (2 * r == d && q % 2 == 1) {
        q + 1
    } else {
        q
    }
}

/// The duration in ms and the time base of an S5TIME pattern (§3.3).
#[inline]
pub fn s5time(pattern: u32) -> Result<(u64, u8), Fault> {
    let digits = from_bcd(pattern & 0xFFF, 3)? as u64;
    let base = ((pattern >> 12) & 3) as u8;
    Ok((digits * base_ms(base), base))
}

/// The S5TIME pattern of a duration in ms (`S5T#`, §3.3).
pub fn s5time_pattern(ms: i64) -> u32 {
    let v = ms.max(0) as u64;
    for base in 0u8..4 {
        let b = base_ms(base);
        if v <= 999 * b {
            return ((base as u32) << 12) | to_bcd(div_round_even(v, b) as u32);
        }
    }
    (3 << 12) | 0x999
}

// ------------------------------------------------------------------- status helpers

impl Machine {
    #[inline]
    fn cc_from_i64(&mut self, w: i64) {
        self.status.cc1 = w > 0;
        self.status.cc0 = w < 0;
    }

    #[inline]
    fn overflow(&mut self, ov: bool) {
        self.status.ov = ov;
        if ov {
            self.status.os = true;
        }
    }

    #[inline]
    fn div_zero(&mut self) {
        self.status.cc1 = true;
        self.status.cc0 = true;
        self.status.ov = true;
        self.status.os = true;
    }

    #[inline]
    fn push_accu(&mut self, v: u32) {
        self.accu2 = self.accu1;
        self.accu1 = v;
    }

    /// Classifies and stores a REAL result (§3.8).
    #[inline]
    fn real_result(&mut self, r: f32) {
        let s = &mut self.status;
        if r.is_nan() {
            s.cc1 = true;
            s.cc0 = true;
            s.ov = true;
            s.os = true;
            self.accu1 = 0xFFFF_FFFF;
        } else if r.is_infinite() {
            s.cc1 = r > 0.0;
            s.cc0 = r < 0.0;
            s.ov = true;
            s.os = true;
            self.accu1 = r.to_bits();
        } else if r == 0.0 {
            s.cc1 = false;
            s.cc0 = false;
            s.ov = false;
            self.accu1 = r.to_bits();
        } else if r.is_subnormal() {
            s.cc1 = false;
            s.cc0 = false;
            s.ov = true;
            s.os = true;
            self.accu1 = 0;
        } else {
            s.cc1 = r > 0.0;
            s.cc0 = r < 0.0;
            s.ov = false;
            self.accu1 = r.to_bits();
        }
    }

    #[inline]
    fn compare(&mut self, c: Option<std::cmp::Ordering>, op: OpCode) {
        use std::cmp::Ordering::*;
        let s = &mut self.status;
        s.or = false;
        s.fc = true;
        match c {
            None => {
                s.rlo = false;
                s.sta = false;
                s.cc1 = true;
                s.cc0 = true;
                s.ov = true;
                s.os = true;
            }
            Some(o) => {
                let r = match op {
                    OpCode::EqI | OpCode::EqD | OpCode::EqR => o == Equal,
                    OpCode::NeI | OpCode::NeD | OpCode::NeR => o != Equal,
                    OpCode::GtI | OpCode::GtD | OpCode::GtR => o == Greater,
                    OpCode::LtI | OpCode::LtD | OpCode::LtR => o == Less,
                    OpCode::GeI | OpCode::GeD | OpCode::GeR => o != Less,
                    _ => o != Greater,
                };
                s.rlo = r;
                s.sta = r;
                s.ov = false;
                s.cc1 = o == Greater;
                s.cc0 = o == Less;
            }
        }
    }
}

/// Executes one instruction.
#[inline]
fn exec(m: &mut Machine, binding: &[Place], ins: &Instr, nest: &mut Nest) -> Result<(), Fault> {
    use OpCode::*;
    let op = ins.op;
    match op {
        // ------------------------------------------------------------ bit logic (§3.2)
        U | Un => {
            let b = bit(m, binding, &ins.operand)?;
            let x = b ^ (op == Un);
            let s = &mut m.status;
            let o = s.or && s.fc;
            s.rlo = ((s.rlo || !s.fc) && x) || o;
            s.or = o;
            s.sta = b;
            s.fc = true;
        }
        O | On => {
            let b = bit(m, binding, &ins.operand)?;
            let x = b ^ (op == On);
            let s = &mut m.status;
            s.rlo = (s.rlo && s.fc) || x;
            s.or = false;
            s.sta = b;
            s.fc = true;
        }
        X | Xn => {
            let b = bit(m, binding, &ins.operand)?;
            let x = b ^ (op == Xn);
            let s = &mut m.status;
            s.rlo = (s.rlo && s.fc) ^ x;
            s.or = false;
            s.sta = b;
            s.fc = true;
        }
        OrNone => {
            let s = &mut m.status;
            s.or = (s.rlo || s.or) && s.fc;
            s.fc = s.rlo && s.fc;
            s.sta = true;
        }
        UParen | UnParen | OParen | OnParen | XParen | XnParen => {
            if nest.depth >= NESTING_DEPTH {
                return Err(Fault::new("nesting stack overflow (more than 7 levels)"));
            }
            let s = &mut m.status;
            nest.entries[nest.depth] = (op, s.rlo, s.or, s.fc);
            nest.depth += 1;
            s.or = false;
            s.sta = true;
            s.fc = false;
        }
        Close => {
            if nest.depth == 0 {
                return Err(Fault::new("')' without an open parenthesis"));
            }
            nest.depth -= 1;
            let (k, r, o, f) = nest.entries[nest.depth];
            let s = &mut m.status;
            let x = s.rlo ^ matches!(k, UnParen | OnParen | XnParen);
            match k {
                UParen | UnParen => {
                    let o2 = o && f;
                    s.rlo = ((r || !f) && x) || o2;
                    s.or = o2;
                }
                OParen | OnParen => {
                    s.rlo = (r && f) || x;
                    s.or = false;
                }
                _ => {
                    s.rlo = (r && f) ^ x;
                    s.or = false;
                }
            }
            s.sta = true;
            s.fc = true;
        }
        Assign => {
            let p = place(binding, &ins.operand)?;
            let r = m.status.rlo;
            m.write(p, r as u32)?;
            let s = &mut m.status;
            s.or = false;
            s.sta = r;
            s.fc = false;
        }
        S | R => {
            let p = place(binding, &ins.operand)?;
            let r = m.status.rlo;
            match p {
                Place::Timer(t) => {
                    if op == S {
                        return Err(bad_operand(op));
                    }
                    let t = m.timer(t.0);
                    if r {
                        t.running = false;
                        t.q = false;
                    }
                }
                Place::Counter(c) => {
                    if op == S {
                        let a = m.accu1;
                        let c = m.counter(c.0);
                        if r && !c.es {
                            c.v = from_bcd(a & 0xFFF, 3)? as u16;
                        }
                        c.es = r;
                    } else if r {
                        m.counter(c.0).v = 0;
                    }
                }
                _ => {
                    if r {
                        m.write(p, (op == S) as u32)?;
                    }
                    m.status.sta = r;
                }
            }
            let s = &mut m.status;
            s.or = false;
            s.fc = false;
        }
        Set | Clr => {
            let v = op == Set;
            let s = &mut m.status;
            s.rlo = v;
            s.sta = v;
            s.or = false;
            s.fc = false;
        }
        Not => {
            m.status.rlo = !m.status.rlo;
            m.status.sta = true;
        }
        Fp | Fn => {
            let p = place(binding, &ins.operand)?;
            let e = m.read(p)? & 1 != 0;
            let r = m.status.rlo;
            m.write(p, r as u32)?;
            let s = &mut m.status;
            s.sta = r;
            s.or = false;
            s.fc = true;
            s.rlo = if op == Fp { r && !e } else { !r && e };
        }

        // ------------------------------------------------------------ timers (§3.3)
        Si | Sv | Se | Ss | Sa => {
            let id = match place(binding, &ins.operand)? {
                Place::Timer(t) => t.0,
                _ => return Err(bad_operand(op)),
            };
            let r = m.status.rlo;
            let now = m.now_ms;
            let a = m.accu1;
            let t = m.timer(id);
            let e = t.e;
            let start = |t: &mut crate::machine::Timer| -> Result<(), Fault> {
                let (d, base) = s5time(a)?;
                t.running = true;
                t.deadline = now + d;
                t.base = base;
                Ok(())
            };
            match op {
                Si => {
                    if r {
                        if !e {
                            t.q = true;
                            start(t)?;
                        }
                    } else {
                        t.q = false;
                        t.running = false;
                    }
                    t.kind = TimerKind::Pulse;
                }
                Sv => {
                    if r && !e {
                        t.q = true;
                        start(t)?;
                    }
                    t.kind = TimerKind::Extended;
                }
                Se => {
                    if r {
                        if !e {
                            start(t)?;
                        }
                    } else {
                        t.q = false;
                        t.running = false;
                    }
                    t.kind = TimerKind::OnDelay;
                }
                Ss => {
                    if r && !e {
                        start(t)?;
                    }
                    t.kind = TimerKind::Retentive;
                }
                _ => {
                    if r && !e {
                        t.q = true;
                        t.running = false;
                    } else if !r && e {
                        t.q = true;
                        start(t)?;
                    }
                    t.kind = TimerKind::OffDelay;
                }
            }
            t.e = r;
            m.status.or = false;
            m.status.fc = false;
        }
        Fr => {
            let r = m.status.rlo;
            match place(binding, &ins.operand)? {
                Place::Timer(t) => {
                    let t = m.timer(t.0);
                    if r && !t.f {
                        t.e = false;
                    }
                    t.f = r;
                }
                Place::Counter(c) => {
                    let c = m.counter(c.0);
                    if r && !c.ef {
                        c.eu = false;
                        c.ed = false;
                        c.es = false;
                    }
                    c.ef = r;
                }
                _ => return Err(bad_operand(op)),
            }
            m.status.or = false;
            m.status.fc = false;
        }

        // ------------------------------------------------------------ counters (§3.4)
        Zv | Zr => {
            let id = match place(binding, &ins.operand)? {
                Place::Counter(c) => c.0,
                _ => return Err(bad_operand(op)),
            };
            let r = m.status.rlo;
            let c = m.counter(id);
            if op == Zv {
                if r && !c.eu && c.v < 999 {
                    c.v += 1;
                }
                c.eu = r;
            } else {
                if r && !c.ed && c.v > 0 {
                    c.v -= 1;
                }
                c.ed = r;
            }
            m.status.or = false;
            m.status.fc = false;
        }

        // ------------------------------------------------------------ load, transfer (§3.5)
        L | Lc => {
            let v = match &ins.operand {
                Operand::Imm(n) if op == L => *n,
                operand => match place(binding, operand)? {
                    Place::Timer(t) => {
                        let now = m.now_ms;
                        let t = m.timer(t.0);
                        let v = if t.running {
                            div_round_even(t.deadline.saturating_sub(now), base_ms(t.base)) as u32
                        } else {
                            0
                        };
                        if op == Lc {
                            to_bcd(v.min(999)) | ((t.base as u32) << 12)
                        } else {
                            v
                        }
                    }
                    Place::Counter(c) => {
                        let v = m.counter(c.0).v as u32;
                        if op == Lc { to_bcd(v) } else { v }
                    }
                    p if op == L => m.read(p)?,
                    _ => return Err(bad_operand(op)),
                },
            };
            m.push_accu(v);
        }
        T => {
            let p = place(binding, &ins.operand)?;
            let a = m.accu1;
            m.write(p, a)?;
        }
        Tak => std::mem::swap(&mut m.accu1, &mut m.accu2),
        Push => m.accu2 = m.accu1,
        Pop => m.accu1 = m.accu2,
        Inc | Dec => {
            let n = imm(ins)?;
            let lo = m.accu1 & 0xFF;
            let lo = if op == Inc {
                lo.wrapping_add(n)
            } else {
                lo.wrapping_sub(n)
            } & 0xFF;
            m.accu1 = (m.accu1 & !0xFF) | lo;
        }
        AddInt => {
            let n = imm(ins)?;
            m.accu1 = (m.accu1 & 0xFFFF_0000) | (m.accu1.wrapping_add(n) & 0xFFFF);
        }
        AddDint => {
            let n = imm(ins)?;
            m.accu1 = m.accu1.wrapping_add(n);
        }
        Taw => {
            m.accu1 = (m.accu1 & 0xFFFF_0000) | ((m.accu1 as u16).swap_bytes() as u32);
        }
        Tad => m.accu1 = m.accu1.swap_bytes(),
        Tar => std::mem::swap(&mut m.ar1, &mut m.ar2),
        Tar1 => {
            let v = m.ar1;
            m.push_accu(v);
        }
        Tar2 => {
            let v = m.ar2;
            m.push_accu(v);
        }

        // ------------------------------------------------------------ word logic (§3.6)
        Uw | Ow | Xow | Ud | Od | Xod => {
            let c = match ins.operand {
                Operand::Imm(n) => n,
                Operand::None => m.accu2,
                _ => return Err(bad_operand(op)),
            };
            let a = m.accu1;
            let r = match op {
                Uw | Ud => a & c,
                Ow | Od => a | c,
                _ => a ^ c,
            };
            let r = if matches!(op, Uw | Ow | Xow) {
                (a & 0xFFFF_0000) | (r & 0xFFFF)
            } else {
                r
            };
            m.accu1 = r;
            let nz = if matches!(op, Uw | Ow | Xow) {
                r & 0xFFFF != 0
            } else {
                r != 0
            };
            m.status.cc1 = nz;
            m.status.cc0 = false;
            m.status.ov = false;
        }

        // ------------------------------------------------------------ comparisons (§3.6)
        EqI | NeI | GtI | LtI | GeI | LeI => {
            let a = m.accu2 as u16 as i16;
            let b = m.accu1 as u16 as i16;
            m.compare(Some(a.cmp(&b)), op);
        }
        EqD | NeD | GtD | LtD | GeD | LeD => {
            let a = m.accu2 as i32;
            let b = m.accu1 as i32;
            m.compare(Some(a.cmp(&b)), op);
        }
        EqR | NeR | GtR | LtR | GeR | LeR => {
            let a = f32::from_bits(m.accu2);
            let b = f32::from_bits(m.accu1);
            m.compare(a.partial_cmp(&b), op);
        }

        // ------------------------------------------------------------ integer arithmetic (§3.7)
        AddI | SubI => {
            let a = m.accu2 as u16 as i16 as i64;
            let b = m.accu1 as u16 as i16 as i64;
            let v = if op == AddI { a + b } else { a - b };
            let stored = v as i16;
            m.accu1 = (m.accu1 & 0xFFFF_0000) | stored as u16 as u32;
            m.cc_from_i64(stored as i64);
            m.overflow(v != stored as i64);
        }
        NegI => {
            let v = -(m.accu1 as u16 as i16 as i64);
            let stored = v as i16;
            m.accu1 = (m.accu1 & 0xFFFF_0000) | stored as u16 as u32;
            m.cc_from_i64(stored as i64);
            m.overflow(v != stored as i64);
        }
        AddD | SubD => {
            let a = m.accu2 as i32 as i64;
            let b = m.accu1 as i32 as i64;
            let v = if op == AddD { a + b } else { a - b };
            let stored = v as i32;
            m.accu1 = stored as u32;
            m.cc_from_i64(stored as i64);
            m.overflow(v != stored as i64);
        }
        NegD => {
            let v = -(m.accu1 as i32 as i64);
            let stored = v as i32;
            m.accu1 = stored as u32;
            m.cc_from_i64(stored as i64);
            m.overflow(v != stored as i64);
        }
        MulI => {
            let v = (m.accu2 as u16 as i16 as i64) * (m.accu1 as u16 as i16 as i64);
            m.accu1 = v as i32 as u32;
            m.cc_from_i64(v);
            m.overflow(v != v as i16 as i64);
        }
        MulD => {
            let v = (m.accu2 as i32 as i64) * (m.accu1 as i32 as i64);
            m.accu1 = v as i32 as u32;
            m.cc_from_i64(v);
            m.overflow(v != v as i32 as i64);
        }
        DivI => {
            let a = m.accu2 as u16 as i16 as i64;
            let b = m.accu1 as u16 as i16 as i64;
            if b == 0 {
                m.div_zero();
            } else {
                let q = a / b;
                let rem = a - q * b;
                m.accu1 = ((rem as u16 as u32) << 16) | q as u16 as u32;
                m.cc_from_i64(q);
                m.overflow(q != q as i16 as i64);
            }
        }
        DivD | Mod => {
            let a = m.accu2 as i32 as i64;
            let b = m.accu1 as i32 as i64;
            if b == 0 {
                m.div_zero();
            } else {
                let v = if op == DivD { a / b } else { a % b };
                m.accu1 = v as i32 as u32;
                m.cc_from_i64(v);
                m.overflow(v != v as i32 as i64);
            }
        }

        // ------------------------------------------------------------ REAL arithmetic (§3.8)
        AddR | SubR | MulR | DivR => {
            let a = f32::from_bits(m.accu2);
            let b = f32::from_bits(m.accu1);
            let r = match op {
                AddR => a + b,
                SubR => a - b,
                MulR => a * b,
                _ => a / b,
            };
            m.real_result(r);
        }
        Sqr | Sqrt | Exp | Ln | Sin | Cos | Tan | Asin | Acos | Atan => {
            let x = f32::from_bits(m.accu1);
            let r = if x.is_infinite() {
                x
            } else {
                let d = x as f64;
                (match op {
                    Sqr => d * d,
                    Sqrt => d.sqrt(),
                    Exp => d.exp(),
                    Ln => d.ln(),
                    Sin => d.sin(),
                    Cos => d.cos(),
                    Tan => d.tan(),
                    Asin => d.asin(),
                    Acos => d.acos(),
                    _ => d.atan(),
                }) as f32
            };
            m.real_result(r);
        }
        Abs => m.accu1 &= 0x7FFF_FFFF,
        NegR => m.accu1 ^= 0x8000_0000,

        // ------------------------------------------------------------ shifts (§3.9)
        Slw | Srw | Ssi | Sld | Srd | Ssd | Rld | Rrd => {
            let n = match ins.operand {
                Operand::Imm(n) => n,
                Operand::None => m.accu2 & 0xFF,
                _ => return Err(bad_operand(op)),
            };
            if n != 0 {
                let a = m.accu1;
                let (r, cc1) = match op {
                    Slw | Srw | Ssi => {
                        let n = n.min(16);
                        let lo = a & 0xFFFF;
                        let (r, cc1) = match op {
                            Slw => ((lo << n) & 0xFFFF, (lo >> (16 - n)) & 1),
                            Srw => (lo >> n, (lo >> (n - 1)) & 1),
                            _ => {
                                let v = lo as u16 as i16 as i32;
                                ((v >> n) as u32 & 0xFFFF, ((v >> (n - 1)) & 1) as u32)
                            }
                        };
                        ((a & 0xFFFF_0000) | r, cc1)
                    }
                    Sld => {
                        let n = n.min(32);
                        (
                            ((a as u64) << n) as u32,
                            ((a as u64) >> (32 - n)) as u32 & 1,
                        )
                    }
                    Srd => {
                        let n = n.min(32);
                        (((a as u64) >> n) as u32, (a >> (n - 1)) & 1)
                    }
                    Ssd => {
                        let n = n.min(32);
                        let v = a as i32 as i64;
                        ((v >> n) as u32, ((v >> (n - 1)) & 1) as u32)
                    }
                    Rld => {
                        let r = a.rotate_left(n.min(32));
                        (r, r & 1)
                    }
                    _ => {
                        let r = a.rotate_right(n.min(32));
                        (r, r >> 31)
                    }
                };
                m.accu1 = r;
                m.status.cc1 = cc1 != 0;
                m.status.cc0 = false;
                m.status.ov = false;
            }
        }
        Rlda => {
            let a = m.accu1;
            m.accu1 = (a << 1) | m.status.cc1 as u32;
            m.status.cc1 = a >> 31 != 0;
            m.status.cc0 = false;
            m.status.ov = false;
        }
        Rrda => {
            let a = m.accu1;
            m.accu1 = (a >> 1) | ((m.status.cc1 as u32) << 31);
            m.status.cc1 = a & 1 != 0;
            m.status.cc0 = false;
            m.status.ov = false;
        }

        // ------------------------------------------------------------ conversion (§3.10)
        Bti => {
            let a = m.accu1;
            let v = from_bcd(a & 0xFFF, 3)? as i32;
            let v = if a & 0x8000 != 0 { -v } else { v };
            m.accu1 = (a & 0xFFFF_0000) | v as u16 as u32;
        }
        Btd => {
            let a = m.accu1;
            let v = from_bcd(a & 0x0FFF_FFFF, 7)? as i32;
            m.accu1 = if a & 0x8000_0000 != 0 { -v } else { v } as u32;
        }
        Itb => {
            let a = m.accu1;
            let v = a as u16 as i16 as i32;
            if v.unsigned_abs() > 999 {
                m.overflow(true);
            } else {
                let sign = if v < 0 { 0xF000 } else { 0 };
                m.accu1 = (a & 0xFFFF_0000) | sign | to_bcd(v.unsigned_abs());
                m.status.ov = false;
            }
        }
        Dtb => {
            let v = m.accu1 as i32;
            if v.unsigned_abs() > 9_999_999 {
                m.overflow(true);
            } else {
                let sign = if v < 0 { 0xF000_0000 } else { 0 };
                m.accu1 = sign | to_bcd(v.unsigned_abs());
                m.status.ov = false;
            }
        }
        Itd => m.accu1 = m.accu1 as u16 as i16 as i32 as u32,
        Dtr => m.accu1 = (m.accu1 as i32 as f32).to_bits(),
        Invi => m.accu1 ^= 0xFFFF,
        Invd => m.accu1 = !m.accu1,
        Rnd | RndPlus | RndMinus | Trunc => {
            let x = f32::from_bits(m.accu1) as f64;
            let r = match op {
                Rnd => x.round_ties_even(),
                RndPlus => x.ceil(),
                RndMinus => x.floor(),
                _ => x.trunc(),
            };
            if r.is_nan() || r < i32::MIN as f64 || r > i32::MAX as f64 {
                m.overflow(true);
            } else {
                m.accu1 = r as i32 as u32;
            }
        }

        // ------------------------------------------------------------ calls (§3.11)
        Call | Cc => {
            let call = match &ins.operand {
                Operand::Call(c) => c,
                _ => return Err(bad_operand(op)),
            };
            if op == Call || m.status.rlo {
                stub_call(m, binding, call, op == Call)?;
                m.status.br = true;
            }
            let s = &mut m.status;
            s.rlo = true;
            s.sta = true;
            s.or = false;
            s.os = false;
            s.fc = false;
        }
    }
    Ok(())
}

#[inline]
fn imm(ins: &Instr) -> Result<u32, Fault> {
    match ins.operand {
        Operand::Imm(n) => Ok(n),
        _ => Err(bad_operand(ins.op)),
    }
}

/// A stub call (§3.11): the stub values a test set are written to their actuals.
fn stub_call(m: &mut Machine, binding: &[Place], call: &Call, params: bool) -> Result<(), Fault> {
    if params && m.has_stubs() {
        for (name, actual) in &call.params {
            let Some(v) = m.stub(call.block, name).cloned() else {
                continue;
            };
            let p = place(binding, actual)?;
            if !m.fits(p, &v) {
                return Err(Fault::new(format!(
                    "the stub value of {name} ({}) does not fit its actual",
                    v.ty()
                )));
            }
            m.write_value(p, &v)?;
        }
    }
    m.count_call(call.block);
    Ok(())
}

impl Machine {
    /// Whether `v` fits the place's type (a stub value, §3.11).
    fn fits(&self, p: &Place, v: &Value) -> bool {
        use crate::program::Width;
        match p {
            Place::Const(_) => true,
            Place::Cell(id) => match (self.cell_type(*id), v.ty()) {
                (Some(Ty::String(_)), Ty::String(_)) => true,
                (Some(t), u) => t == u || (t.bits().is_some() && t.bits() == u.bits()),
                (None, _) => false,
            },
            Place::Mem { width, .. } => match (width, v.ty().bits()) {
                (Width::Bit(_), Some(1)) => true,
                (Width::Byte, Some(8)) => true,
                (Width::Word, Some(16)) => true,
                (Width::Dword, Some(32)) => true,
                (_, None) => matches!(v, Value::String(_) | Value::DateAndTime(_)),
                _ => false,
            },
            Place::Timer(_) | Place::Counter(_) => false,
        }
    }
}

/// The 32-bit pattern `L` loads for a constant (§1.1).
pub fn load_pattern(c: &Const) -> u32 {
    match c {
        Const::Int(n) => {
            if (-32768..=32767).contains(n) {
                *n as i16 as u16 as u32
            } else {
                *n as i32 as u32
            }
        }
        Const::LongInt(n) => *n as i32 as u32,
        Const::Bits(v) => *v as u32,
        Const::Counter(n) => to_bcd((*n).min(999)),
        Const::S5Time(ms) => s5time_pattern(*ms),
        Const::Time(ms) => *ms as i32 as u32,
        Const::TimeOfDay(ms) => *ms,
        Const::Date(d) => *d as u32 & 0xFFFF,
        Const::Real(f) => (*f as f32).to_bits(),
        Const::Chars(cs) => cs.iter().fold(0u32, |a, c| (a << 8) | *c as u32),
        Const::Pointer { area, byte, bit } => {
            ((*area as u32) << 24).wrapping_add(byte.wrapping_mul(8)) + (*bit as u32 & 7)
        }
        Const::Bool(b) => *b as u32,
    }
}
