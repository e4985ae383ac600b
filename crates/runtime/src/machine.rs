//! The machine of `runtime.md` §1: process images, bit memory, data blocks, local data, cells,
//! timers and counters, ACCU1/ACCU2, AR1/AR2, the status word, the virtual clock, call stubs.
//!
//! Layout (fast paths first):
//! * every byte area (inputs, outputs, bit memory, local data, each data block) is a `Vec<u8>`
//!   that grows on the first write past its end and reads as 0 beyond it, so a fresh machine
//!   allocates nothing large and zeroing local data is a `clear()`;
//! * data blocks are allocated lazily, indexed by number;
//! * cells are raw bit patterns in a `Vec<u32>` (with a per-cell width mask); STRING and
//!   DATE_AND_TIME cells keep their value in a side table;
//! * timers and counters are vectors indexed by object number, grown on first use;
//! * the status word is kept as separate flags (the interpreter tests and sets them one by one).

use std::collections::HashMap;

use crate::program::{MemArea, Origin, Place, Program, Width};
use crate::value::{Ty, Value};

/// A runtime fault (§1.4): the test stops with HG9903.
#[derive(Debug, Clone, PartialEq)]
pub struct Fault {
    /// The `{reason}` of HG9903's message.
    pub reason: String,
    /// The faulting STL statement, if the fault came from one.
    pub origin: Origin,
}

impl Fault {
    pub fn new(reason: impl Into<String>) -> Fault {
        Fault {
            reason: reason.into(),
            origin: Origin::NONE,
        }
    }
}

/// The highest byte address of every area (§1.1).
pub const MAX_BYTE: u32 = 65535;

/// The status word (§1.2). `bits()` packs it as S7 does: bit 0 /FC, 1 RLO, 2 STA, 3 OR, 4 OS,
/// 5 OV, 6 CC0, 7 CC1, 8 BR.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Status {
    pub fc: bool,
    pub rlo: bool,
    pub sta: bool,
    pub or: bool,
    pub os: bool,
    pub ov: bool,
    pub cc0: bool,
    pub cc1: bool,
    pub br: bool,
}

impl Status {
    pub fn bits(&self) -> u16 {
        (self.fc as u16)
            | (self.rlo as u16) << 1
            | (self.sta as u16) << 2
            | (self.or as u16) << 3
            | (self.os as u16) << 4
            | (self.ov as u16) << 5
            | (self.cc0 as u16) << 6
            | (self.cc1 as u16) << 7
            | (self.br as u16) << 8
    }

    pub fn from_bits(b: u16) -> Status {
        Status {
            fc: b & 1 != 0,
            rlo: b & 2 != 0,
            sta: b & 4 != 0,
            or: b & 8 != 0,
            os: b & 16 != 0,
            ov: b & 32 != 0,
            cc0: b & 64 != 0,
            cc1: b & 128 != 0,
            br: b & 256 != 0,
        }
    }
}

/// Which of the five start operations last ran on a timer (decides Q at expiry, §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimerKind {
    #[default]
    Pulse,
    Extended,
    OnDelay,
    Retentive,
    OffDelay,
}

/// A timer object (§3.3).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Timer {
    pub q: bool,
    pub running: bool,
    /// Virtual time in ms at which it expires.
    pub deadline: u64,
    /// Time base code 0..3 (10 ms, 100 ms, 1 s, 10 s).
    pub base: u8,
    /// The last start operation executed on it.
    pub kind: TimerKind,
    /// Start-edge memory e.
    pub e: bool,
    /// FR-edge memory f.
    pub f: bool,
}

/// A counter object (§3.4).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counter {
    pub v: u16,
    pub eu: bool,
    pub ed: bool,
    pub es: bool,
    pub ef: bool,
}

/// Milliseconds of a time base code.
pub fn base_ms(base: u8) -> u64 {
    match base & 3 {
        0 => 10,
        1 => 100,
        2 => 1000,
        _ => 10000,
    }
}

/// The simulated CPU.
#[derive(Debug, Clone)]
pub struct Machine {
    /// Virtual time t_k in ms (§1.3).
    pub now_ms: u64,
    pub accu1: u32,
    pub accu2: u32,
    pub ar1: u32,
    pub ar2: u32,
    pub status: Status,
    /// STL instructions executed so far (a faulting instruction counts); for benchmarks and
    /// statistics, counted per block so that it costs nothing per instruction.
    pub instructions: u64,
    inputs: Vec<u8>,
    outputs: Vec<u8>,
    memory: Vec<u8>,
    local: Vec<u8>,
    /// Data block n at index n (allocated lazily).
    dbs: Vec<Vec<u8>>,
    cells: Vec<u32>,
    /// Per cell: the mask of its width (0 for side-table cells).
    cell_mask: Vec<u32>,
    cell_ty: Vec<Ty>,
    /// STRING and DATE_AND_TIME cells.
    side: HashMap<u32, Value>,
    timers: Vec<Timer>,
    counters: Vec<Counter>,
    stubs: HashMap<(u32, String), Value>,
    calls: Vec<u32>,
}

fn mask_of(ty: Ty) -> u32 {
    match ty.bits() {
        Some(32) => u32::MAX,
        Some(n) => (1u32 << n) - 1,
        None => 0,
    }
}

fn width_bytes(w: Width) -> u32 {
    match w {
        Width::Bit(_) | Width::Byte => 1,
        Width::Word => 2,
        Width::Dword => 4,
    }
}

fn past_end(byte: u32, len: u32) -> Fault {
    Fault::new(format!(
        "access to byte {} past byte {MAX_BYTE}",
        byte as u64 + len as u64 - 1
    ))
}

impl Machine {
    /// A machine as §1.2 describes it at test start.
    pub fn new(program: &Program) -> Machine {
        let mut m = Machine {
            now_ms: 0,
            accu1: 0,
            accu2: 0,
            ar1: 0,
            ar2: 0,
            status: Status::default(),
            instructions: 0,
            inputs: Vec::new(),
            outputs: Vec::new(),
            memory: Vec::new(),
            local: Vec::new(),
            dbs: Vec::new(),
            cells: Vec::new(),
            cell_mask: Vec::new(),
            cell_ty: Vec::new(),
            side: HashMap::new(),
            timers: Vec::new(),
            counters: Vec::new(),
            stubs: HashMap::new(),
            calls: vec![0; program.blocks.len()],
        };
        m.init_cells(program);
        m
    }

    fn init_cells(&mut self, program: &Program) {
        let n = program.cells.len();
        self.cells.clear();
        self.cells.resize(n, 0);
        self.cell_mask.clear();
        self.cell_ty.clear();
        self.side.clear();
        for (i, c) in program.cells.iter().enumerate() {
            self.cell_mask.push(mask_of(c.ty));
            self.cell_ty.push(c.ty);
            match c.ty {
                Ty::String(_) | Ty::DateAndTime => {
                    let v = match (&c.init, c.ty) {
                        (Value::String(_), Ty::String(_)) | (Value::DateAndTime(_), _) => {
                            c.init.clone()
                        }
                        _ => Value::zero(c.ty),
                    };
                    self.side.insert(i as u32, v);
                }
                _ => self.cells[i] = c.init.to_bits().unwrap_or(0) & mask_of(c.ty),
            }
        }
    }

    // ------------------------------------------------------------------ byte areas

    #[inline]
    fn area(&self, area: MemArea) -> &[u8] {
        match area {
            MemArea::Input => &self.inputs,
            MemArea::Output => &self.outputs,
            MemArea::Memory => &self.memory,
            MemArea::Local => &self.local,
            MemArea::Db(n) => self.dbs.get(n as usize).map_or(&[], |v| v.as_slice()),
        }
    }

    /// The area as allocated so far (no growth).
    #[inline]
    fn area_slice_mut(&mut self, area: MemArea) -> &mut [u8] {
        match area {
            MemArea::Input => &mut self.inputs,
            MemArea::Output => &mut self.outputs,
            MemArea::Memory => &mut self.memory,
            MemArea::Local => &mut self.local,
            MemArea::Db(n) => self
                .dbs
                .get_mut(n as usize)
                .map_or(&mut [][..], |v| v.as_mut_slice()),
        }
    }

    #[inline]
    fn area_mut(&mut self, area: MemArea, end: usize) -> &mut [u8] {
        let v = match area {
            MemArea::Input => &mut self.inputs,
            MemArea::Output => &mut self.outputs,
            MemArea::Memory => &mut self.memory,
            MemArea::Local => &mut self.local,
            MemArea::Db(n) => {
                let n = n as usize;
                if self.dbs.len() <= n {
                    self.dbs.resize_with(n + 1, Vec::new);
                }
                &mut self.dbs[n]
            }
        };
        if v.len() < end {
            // Grow in steps so that a run of writes does not reallocate each time.
            let want = (end.next_power_of_two()).clamp(64, MAX_BYTE as usize + 1);
            v.resize(want.max(end), 0);
        }
        v
    }

    /// The bytes of an area as allocated so far (bytes past the end read as 0).
    pub fn area_bytes(&self, area: MemArea) -> &[u8] {
        self.area(area)
    }

    /// Reads `len` (1..=4) bytes big-endian.
    #[inline]
    pub fn read_bytes(&self, area: MemArea, byte: u32, len: u32) -> Result<u32, Fault> {
        if byte > MAX_BYTE + 1 - len {
            return Err(past_end(byte, len));
        }
        let a = self.area(area);
        let b = byte as usize;
        // Fast paths: the bytes exist.
        match len {
            1 => return Ok(a.get(b).copied().unwrap_or(0) as u32),
            2 => {
                if let Some(&[h, l]) = a.get(b..b + 2) {
                    return Ok(u16::from_be_bytes([h, l]) as u32);
                }
            }
            4 => {
                if let Some(&[x0, x1, x2, x3]) = a.get(b..b + 4) {
                    return Ok(u32::from_be_bytes([x0, x1, x2, x3]));
                }
            }
            _ => {}
        }
        let mut v = 0u32;
        for i in 0..len as usize {
            v = (v << 8) | a.get(b + i).copied().unwrap_or(0) as u32;
        }
        Ok(v)
    }

    /// Writes the low `len` (1..=4) bytes of `bits` big-endian.
    #[inline]
    pub fn write_bytes(
        &mut self,
        area: MemArea,
        byte: u32,
        len: u32,
        bits: u32,
    ) -> Result<(), Fault> {
        if byte > MAX_BYTE + 1 - len {
            return Err(past_end(byte, len));
        }
        let b = byte as usize;
        let a = self.area_mut(area, b + len as usize);
        match len {
            1 => a[b] = bits as u8,
            2 => a[b..b + 2].copy_from_slice(&(bits as u16).to_be_bytes()),
            4 => a[b..b + 4].copy_from_slice(&bits.to_be_bytes()),
            _ => {
                for i in 0..len as usize {
                    a[b + i] = (bits >> (8 * (len as usize - 1 - i))) as u8;
                }
            }
        }
        Ok(())
    }

    // ------------------------------------------------------------------ timers, counters

    #[inline]
    fn timer_slot(&mut self, id: u32) -> &mut Timer {
        let i = id as usize;
        if self.timers.len() <= i {
            self.timers.resize(i + 1, Timer::default());
        }
        &mut self.timers[i]
    }

    /// Timer `id` after the expiry check of §3.3.
    #[inline]
    pub fn timer(&mut self, id: u32) -> &mut Timer {
        let now = self.now_ms;
        let t = self.timer_slot(id);
        if t.running && now >= t.deadline {
            t.running = false;
            t.q = matches!(t.kind, TimerKind::OnDelay | TimerKind::Retentive);
        }
        t
    }

    /// Timer `id` as it is stored, without the expiry check (traces and tests).
    pub fn timer_raw(&self, id: u32) -> Timer {
        self.timers.get(id as usize).copied().unwrap_or_default()
    }

    #[inline]
    pub fn counter(&mut self, id: u32) -> &mut Counter {
        let i = id as usize;
        if self.counters.len() <= i {
            self.counters.resize(i + 1, Counter::default());
        }
        &mut self.counters[i]
    }

    pub fn counter_raw(&self, id: u32) -> Counter {
        self.counters.get(id as usize).copied().unwrap_or_default()
    }

    // ------------------------------------------------------------------ places

    /// The bit pattern at a place, zero-extended (a timer: its status Q; a counter: value ≠ 0).
    ///
    /// The common cases (a cell; memory already allocated) are inlined; the rest, including
    /// every fault, is [`Machine::read_slow`].
    #[inline(always)]
    pub fn read(&mut self, place: &Place) -> Result<u32, Fault> {
        match place {
            Place::Cell(id) => {
                if let Some(&c) = self.cells.get(*id as usize) {
                    return Ok(c);
                }
            }
            Place::Mem { area, byte, width } => {
                // In range of the allocated area means at most byte 65535 (areas never grow
                // past it), so no fault is possible here.
                let a = self.area(*area);
                let b = *byte as usize;
                match *width {
                    Width::Bit(x) => {
                        if let Some(&v) = a.get(b) {
                            return Ok((u32::from(v) >> (x & 7)) & 1);
                        }
                    }
                    Width::Byte => {
                        if let Some(&v) = a.get(b) {
                            return Ok(u32::from(v));
                        }
                    }
                    Width::Word => {
                        if let Some(&[h, l]) = a.get(b..b + 2) {
                            return Ok(u32::from(u16::from_be_bytes([h, l])));
                        }
                    }
                    Width::Dword => {
                        if let Some(&[b0, b1, b2, b3]) = a.get(b..b + 4) {
                            return Ok(u32::from_be_bytes([b0, b1, b2, b3]));
                        }
                    }
                }
                // Wholly past the allocated end and in range for any width: never written.
                if b >= a.len() && b <= MAX_BYTE as usize - 3 {
                    return Ok(0);
                }
            }
            _ => {}
        }
        self.read_slow(place)
    }

    #[inline(never)]
    fn read_slow(&mut self, place: &Place) -> Result<u32, Fault> {
        match place {
            Place::Mem { area, byte, width } => match *width {
                Width::Bit(x) => Ok((self.read_bytes(*area, *byte, 1)? >> (x & 7)) & 1),
                w => self.read_bytes(*area, *byte, width_bytes(w)),
            },
            Place::Cell(id) => self
                .cells
                .get(*id as usize)
                .copied()
                .ok_or_else(|| Fault::new(format!("no cell {id}"))),
            Place::Timer(t) => Ok(self.timer(t.0).q as u32),
            Place::Counter(c) => Ok((self.counter(c.0).v != 0) as u32),
            Place::Const(v) => Ok(v.to_bits().unwrap_or(0)),
        }
    }

    /// Writes the low bits of `bits` by the place's width (a constant place discards it).
    ///
    /// Inlined for a cell and for memory already allocated; the rest is
    /// [`Machine::write_slow`].
    #[inline(always)]
    pub fn write(&mut self, place: &Place, bits: u32) -> Result<(), Fault> {
        match place {
            Place::Cell(id) => {
                let i = *id as usize;
                if let (Some(c), Some(&m)) = (self.cells.get_mut(i), self.cell_mask.get(i)) {
                    *c = bits & m;
                    return Ok(());
                }
            }
            Place::Mem { area, byte, width } => {
                let a = self.area_slice_mut(*area);
                let b = *byte as usize;
                match *width {
                    Width::Bit(x) => {
                        if let Some(v) = a.get_mut(b) {
                            let m = 1u8 << (x & 7);
                            if bits & 1 != 0 {
                                *v |= m;
                            } else {
                                *v &= !m;
                            }
                            return Ok(());
                        }
                    }
                    Width::Byte => {
                        if let Some(v) = a.get_mut(b) {
                            *v = bits as u8;
                            return Ok(());
                        }
                    }
                    Width::Word => {
                        if let Some(v) = a.get_mut(b..b + 2) {
                            v.copy_from_slice(&(bits as u16).to_be_bytes());
                            return Ok(());
                        }
                    }
                    Width::Dword => {
                        if let Some(v) = a.get_mut(b..b + 4) {
                            v.copy_from_slice(&bits.to_be_bytes());
                            return Ok(());
                        }
                    }
                }
            }
            _ => {}
        }
        self.write_slow(place, bits)
    }

    #[inline(never)]
    fn write_slow(&mut self, place: &Place, bits: u32) -> Result<(), Fault> {
        match place {
            Place::Mem { area, byte, width } => match *width {
                Width::Bit(x) => {
                    let old = self.read_bytes(*area, *byte, 1)?;
                    let m = 1u32 << (x & 7);
                    let new = if bits & 1 != 0 { old | m } else { old & !m };
                    self.write_bytes(*area, *byte, 1, new)
                }
                w => self.write_bytes(*area, *byte, width_bytes(w), bits),
            },
            Place::Cell(id) => {
                let i = *id as usize;
                match (self.cells.get_mut(i), self.cell_mask.get(i)) {
                    (Some(c), Some(&m)) => {
                        *c = bits & m;
                        Ok(())
                    }
                    _ => Err(Fault::new(format!("no cell {id}"))),
                }
            }
            Place::Timer(_) | Place::Counter(_) => {
                Err(Fault::new("a timer or counter cannot be written"))
            }
            Place::Const(_) => Ok(()),
        }
    }

    /// A typed read (STRING and DATE_AND_TIME included).
    pub fn read_value(&mut self, place: &Place, ty: Ty) -> Result<Value, Fault> {
        match (place, ty) {
            (Place::Timer(_) | Place::Counter(_), _) => Ok(Value::Bool(self.read(place)? != 0)),
            (Place::Const(v), _) => Ok(v.clone()),
            (Place::Cell(id), Ty::String(_) | Ty::DateAndTime) => self
                .side
                .get(id)
                .cloned()
                .ok_or_else(|| Fault::new(format!("cell {id} holds no {ty}"))),
            (Place::Mem { area, byte, .. }, Ty::DateAndTime) => {
                let mut b = [0u8; 8];
                for (i, x) in b.iter_mut().enumerate() {
                    *x = self.read_bytes(*area, byte + i as u32, 1)? as u8;
                }
                Ok(Value::DateAndTime(b))
            }
            (Place::Mem { area, byte, .. }, Ty::String(_)) => {
                let cur = self.read_bytes(*area, byte + 1, 1)?;
                let mut s = String::with_capacity(cur as usize);
                for i in 0..cur {
                    s.push(self.read_bytes(*area, byte + 2 + i, 1)? as u8 as char);
                }
                Ok(Value::String(s))
            }
            (_, _) => {
                let bits = self.read(place)?;
                Value::from_bits(ty, bits).ok_or_else(|| Fault::new(format!("cannot read a {ty}")))
            }
        }
    }

    /// A typed write (`set` in tests, chart statements).
    pub fn write_value(&mut self, place: &Place, value: &Value) -> Result<(), Fault> {
        match (place, value) {
            (Place::Const(_), _) => Ok(()),
            (Place::Cell(id), Value::String(s)) => {
                let max = match self.cell_ty.get(*id as usize) {
                    Some(Ty::String(n)) => *n as usize,
                    _ => return Err(Fault::new(format!("cell {id} holds no STRING"))),
                };
                let s: String = s.chars().take(max).collect();
                self.side.insert(*id, Value::String(s));
                Ok(())
            }
            (Place::Cell(id), Value::DateAndTime(_)) => {
                if self.cell_ty.get(*id as usize) != Some(&Ty::DateAndTime) {
                    return Err(Fault::new(format!("cell {id} holds no DATE_AND_TIME")));
                }
                self.side.insert(*id, value.clone());
                Ok(())
            }
            (Place::Mem { area, byte, .. }, Value::DateAndTime(b)) => {
                for (i, x) in b.iter().enumerate() {
                    self.write_bytes(*area, byte + i as u32, 1, *x as u32)?;
                }
                Ok(())
            }
            (Place::Mem { area, byte, .. }, Value::String(s)) => {
                // S7 layout: maximum length, current length, characters. A zero maximum (never
                // written) is taken as 254.
                let mut max = self.read_bytes(*area, *byte, 1)?;
                if max == 0 {
                    max = 254;
                    self.write_bytes(*area, *byte, 1, max)?;
                }
                let bytes: Vec<u8> = s
                    .chars()
                    .map(|c| c as u32 as u8)
                    .take(max as usize)
                    .collect();
                self.write_bytes(*area, byte + 1, 1, bytes.len() as u32)?;
                for (i, c) in bytes.iter().enumerate() {
                    self.write_bytes(*area, byte + 2 + i as u32, 1, *c as u32)?;
                }
                Ok(())
            }
            (_, v) => match v.to_bits() {
                Some(bits) => self.write(place, bits),
                None => Err(Fault::new(format!("cannot write a {} there", v.ty()))),
            },
        }
    }

    /// Start of a group call (§2.2 step 1): ACCU1, ACCU2, the status word and local data := 0.
    pub fn begin_group_call(&mut self) {
        self.accu1 = 0;
        self.accu2 = 0;
        self.status = Status::default();
        // Local data reads as 0 past the vector's end: clearing it zeroes it.
        self.local.clear();
    }

    /// `restart cold` (§2.8): everything as §1.2 except inputs, stub values, call counters and
    /// the clock.
    pub fn restart_cold(&mut self, program: &Program) {
        self.accu1 = 0;
        self.accu2 = 0;
        self.ar1 = 0;
        self.ar2 = 0;
        self.status = Status::default();
        self.outputs.clear();
        self.memory.clear();
        self.local.clear();
        self.dbs.clear();
        self.timers.clear();
        self.counters.clear();
        self.init_cells(program);
    }

    /// The stub value a test set for `block.param` (param in upper case), if any.
    pub fn stub(&self, block: u32, param: &str) -> Option<&Value> {
        self.stubs.get(&(block, param.to_ascii_uppercase()))
    }

    pub fn set_stub(&mut self, block: u32, param: &str, value: Value) {
        self.stubs
            .insert((block, param.to_ascii_uppercase()), value);
    }

    /// `Block.calls`.
    pub fn calls(&self, block: u32) -> u32 {
        self.calls.get(block as usize).copied().unwrap_or(0)
    }

    pub fn has_stubs(&self) -> bool {
        !self.stubs.is_empty()
    }

    /// The type of a cell.
    pub fn cell_type(&self, id: u32) -> Option<Ty> {
        self.cell_ty.get(id as usize).copied()
    }

    /// Counts one call of `block`.
    pub fn count_call(&mut self, block: u32) {
        let i = block as usize;
        if self.calls.len() <= i {
            self.calls.resize(i + 1, 0);
        }
        self.calls[i] = self.calls[i].wrapping_add(1);
    }
}
