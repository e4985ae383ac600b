//! The standard function blocks of IEC 61131-3 (`docs/iec.md` §3, §7) on virtual time.
//!
//! An instance is a set of cells ([`FbInstance`]): its inputs, its outputs and a little hidden
//! state. A call ([`call`]) reads the input cells, runs the block once and writes the outputs;
//! between calls nothing happens (a timer that is not called does not update `Q` or `ET`, as
//! on a PLC). Time is the machine's virtual clock [`Machine::now_ms`]: the same for every call
//! in one cycle, so `ET` is a multiple of the cycle time Δ.
//!
//! The definitions, with `now` the virtual time of the call:
//!
//! * `TON`: while `IN`, `ET := min(now − start, PT)` where `start` is the time of the call that
//!   saw `IN` rise; `Q := IN ∧ ET ≥ PT`. Without `IN`, `Q := FALSE`, `ET := 0`.
//! * `TOF`: while `IN`, `Q := TRUE`, `ET := 0`. At the call that sees `IN` fall the interval
//!   starts; then `ET := min(now − start, PT)`, `Q := ET < PT`. `ET` stays at `PT` afterwards.
//! * `TP`: a rising `IN` while no pulse runs starts a pulse; while it runs
//!   `ET := min(now − start, PT)` and `Q := ET < PT` (the pulse ends when `ET` reaches `PT`,
//!   independent of `IN`). Without a pulse `Q := FALSE`, and `ET := 0` once `IN` is FALSE
//!   (`ET` stays at `PT` while `IN` stays TRUE).
//! * `R_TRIG`: `Q := CLK ∧ ¬M; M := CLK`. `F_TRIG`: `Q := ¬CLK ∧ ¬M; M := ¬CLK` — as in the
//!   standard, the first call with `CLK = FALSE` gives `Q = TRUE` (M starts FALSE).
//! * `CTU`: `IF R THEN CV := 0 ELSIF CU rose ∧ CV < 32767 THEN CV := CV + 1`; `Q := CV ≥ PV`.
//! * `CTD`: `IF LD THEN CV := PV ELSIF CD rose ∧ CV > −32768 THEN CV := CV − 1`; `Q := CV ≤ 0`.
//! * `CTUD`: `IF R THEN CV := 0 ELSIF LD THEN CV := PV ELSIF ¬(CU rose ∧ CD rose) THEN` count
//!   up on a rising `CU` (below 32767) or down on a rising `CD` (above −32768); `QU := CV ≥ PV`,
//!   `QD := CV ≤ 0`.
//!   The edge memories of the counters follow their input at every call, also under `R`/`LD`.
//! * `SR` (set dominant): `Q1 := S1 ∨ (¬R ∧ Q1)`. `RS` (reset dominant): `Q1 := ¬R1 ∧ (S ∨ Q1)`.
//!
//! A negative `PT` counts as zero.

use crate::machine::{Fault, Machine};
use crate::program::{FbInstance, FbMember, FbType, Place};
use crate::value::{Ty, Value};

struct Io<'a> {
    m: &'a mut Machine,
    fb: &'a FbInstance,
}

impl Io<'_> {
    fn cell(&self, member: FbMember) -> Result<Place, Fault> {
        self.fb
            .cell(member)
            .map(Place::Cell)
            .ok_or_else(|| Fault::new(format!("{} has no {}", self.fb.name, member.name())))
    }
    fn state_cell(&self, i: usize) -> Result<Place, Fault> {
        self.fb
            .state
            .get(i)
            .map(|c| Place::Cell(*c))
            .ok_or_else(|| Fault::new(format!("{} has no state {i}", self.fb.name)))
    }
    fn bool(&mut self, member: FbMember) -> Result<bool, Fault> {
        let p = self.cell(member)?;
        Ok(self.m.read(&p)? != 0)
    }
    fn int(&mut self, member: FbMember) -> Result<i64, Fault> {
        let p = self.cell(member)?;
        Ok(match self.m.read_value(&p, member.ty())? {
            Value::Int(x) => i64::from(x),
            Value::Time(x) | Value::Dint(x) => i64::from(x),
            _ => 0,
        })
    }
    fn set_bool(&mut self, member: FbMember, v: bool) -> Result<(), Fault> {
        let p = self.cell(member)?;
        self.m.write_value(&p, &Value::Bool(v))
    }
    fn set_int(&mut self, member: FbMember, v: i64) -> Result<(), Fault> {
        let p = self.cell(member)?;
        let v = match member.ty() {
            Ty::Time => Value::Time(v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32),
            _ => Value::Int(v.clamp(i64::from(i16::MIN), i64::from(i16::MAX)) as i16),
        };
        self.m.write_value(&p, &v)
    }
    fn state_bool(&mut self, i: usize) -> Result<bool, Fault> {
        let p = self.state_cell(i)?;
        Ok(self.m.read(&p)? != 0)
    }
    fn set_state_bool(&mut self, i: usize, v: bool) -> Result<(), Fault> {
        let p = self.state_cell(i)?;
        self.m.write_value(&p, &Value::Bool(v))
    }
    /// The time since the instant kept in state cell `i` (ms, wrap-safe over 49 days).
    fn since(&mut self, i: usize) -> Result<i64, Fault> {
        let p = self.state_cell(i)?;
        let start = self.m.read(&p)?;
        let now = self.m.now_ms as u32;
        Ok(i64::from(now.wrapping_sub(start)))
    }
    fn start_now(&mut self, i: usize) -> Result<(), Fault> {
        let p = self.state_cell(i)?;
        let now = self.m.now_ms as u32;
        self.m.write_value(&p, &Value::Dword(now))
    }
}

/// Runs one call of a standard function block on its cells (the inputs are already written).
pub fn call(m: &mut Machine, fb: &FbInstance) -> Result<(), Fault> {
    use FbMember as M;
    let mut io = Io { m, fb };
    match fb.ty {
        FbType::Ton => {
            let input = io.bool(M::In)?;
            let pt = io.int(M::Pt)?.max(0);
            let prev = io.state_bool(0)?;
            io.set_state_bool(0, input)?;
            if input {
                if !prev {
                    io.start_now(1)?;
                }
                let et = io.since(1)?.min(pt);
                io.set_int(M::Et, et)?;
                io.set_bool(M::Q, et >= pt)?;
            } else {
                io.set_int(M::Et, 0)?;
                io.set_bool(M::Q, false)?;
            }
        }
        FbType::Tof => {
            let input = io.bool(M::In)?;
            let pt = io.int(M::Pt)?.max(0);
            let prev = io.state_bool(0)?;
            io.set_state_bool(0, input)?;
            if input {
                io.set_int(M::Et, 0)?;
                io.set_bool(M::Q, true)?;
            } else {
                if prev {
                    io.start_now(1)?;
                }
                if prev || io.bool(M::Q)? {
                    let et = io.since(1)?.min(pt);
                    io.set_int(M::Et, et)?;
                    io.set_bool(M::Q, et < pt)?;
                }
            }
        }
        FbType::Tp => {
            let input = io.bool(M::In)?;
            let pt = io.int(M::Pt)?.max(0);
            let prev = io.state_bool(0)?;
            io.set_state_bool(0, input)?;
            let mut running = io.state_bool(2)?;
            if !running && input && !prev {
                running = true;
                io.start_now(1)?;
            }
            if running {
                let et = io.since(1)?.min(pt);
                io.set_int(M::Et, et)?;
                running = et < pt;
                io.set_bool(M::Q, running)?;
            } else {
                io.set_bool(M::Q, false)?;
                if !input {
                    io.set_int(M::Et, 0)?;
                }
            }
            io.set_state_bool(2, running)?;
        }
        FbType::RTrig => {
            let clk = io.bool(M::Clk)?;
            let mem = io.state_bool(0)?;
            io.set_bool(M::Q, clk && !mem)?;
            io.set_state_bool(0, clk)?;
        }
        FbType::FTrig => {
            let clk = io.bool(M::Clk)?;
            let mem = io.state_bool(0)?;
            io.set_bool(M::Q, !clk && !mem)?;
            io.set_state_bool(0, !clk)?;
        }
        FbType::Ctu => {
            let cu = io.bool(M::Cu)?;
            let rose = cu && !io.state_bool(0)?;
            io.set_state_bool(0, cu)?;
            let mut cv = io.int(M::Cv)?;
            if io.bool(M::R)? {
                cv = 0;
            } else if rose && cv < i64::from(i16::MAX) {
                cv += 1;
            }
            let pv = io.int(M::Pv)?;
            io.set_int(M::Cv, cv)?;
            io.set_bool(M::Q, cv >= pv)?;
        }
        FbType::Ctd => {
            let cd = io.bool(M::Cd)?;
            let rose = cd && !io.state_bool(0)?;
            io.set_state_bool(0, cd)?;
            let mut cv = io.int(M::Cv)?;
            let pv = io.int(M::Pv)?;
            if io.bool(M::Ld)? {
                cv = pv;
            } else if rose && cv > i64::from(i16::MIN) {
                cv -= 1;
            }
            io.set_int(M::Cv, cv)?;
            io.set_bool(M::Q, cv <= 0)?;
        }
        FbType::Ctud => {
            let cu = io.bool(M::Cu)?;
            let cd = io.bool(M::Cd)?;
            let up = cu && !io.state_bool(0)?;
            let down = cd && !io.state_bool(1)?;
            io.set_state_bool(0, cu)?;
            io.set_state_bool(1, cd)?;
            let mut cv = io.int(M::Cv)?;
            let pv = io.int(M::Pv)?;
            if io.bool(M::R)? {
                cv = 0;
            } else if io.bool(M::Ld)? {
                cv = pv;
            } else if !(up && down) {
                if up && cv < i64::from(i16::MAX) {
                    cv += 1;
                } else if down && cv > i64::from(i16::MIN) {
                    cv -= 1;
                }
            }
            io.set_int(M::Cv, cv)?;
            io.set_bool(M::Qu, cv >= pv)?;
            io.set_bool(M::Qd, cv <= 0)?;
        }
        FbType::Sr => {
            let q = io.bool(M::S1)? || (!io.bool(M::R)? && io.bool(M::Q1)?);
            io.set_bool(M::Q1, q)?;
        }
        FbType::Rs => {
            let q = !io.bool(M::R1)? && (io.bool(M::S)? || io.bool(M::Q1)?);
            io.set_bool(M::Q1, q)?;
        }
    }
    Ok(())
}
