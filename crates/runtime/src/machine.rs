//! The machine of `runtime.md` §1: process images, bit memory, data blocks, local data, cells,
//! timers and counters, ACCU1/ACCU2, AR1/AR2, the status word, the virtual clock, call stubs.

use crate::program::{Origin, Place, Program};
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

/// The simulated CPU.
#[derive(Debug, Clone)]
pub struct Machine {
    /// Virtual time t_k in ms (§1.3).
    pub now_ms: u64,
    // The rest is private to the machine (filled in by the STL work).
}

impl Machine {
    /// A machine as §1.2 describes it at test start.
    pub fn new(program: &Program) -> Machine {
        let _ = program;
        todo!("machine: §1.2")
    }

    /// The bit pattern at a place, zero-extended (a timer: its status Q; a counter: value ≠ 0).
    pub fn read(&mut self, place: &Place) -> Result<u32, Fault> {
        let _ = place;
        todo!()
    }

    /// Writes the low bits of `bits` by the place's width (a constant place discards it).
    pub fn write(&mut self, place: &Place, bits: u32) -> Result<(), Fault> {
        let _ = (place, bits);
        todo!()
    }

    /// A typed read (STRING and DATE_AND_TIME included).
    pub fn read_value(&mut self, place: &Place, ty: Ty) -> Result<Value, Fault> {
        let _ = (place, ty);
        todo!()
    }

    /// A typed write (`set` in tests, chart statements).
    pub fn write_value(&mut self, place: &Place, value: &Value) -> Result<(), Fault> {
        let _ = (place, value);
        todo!()
    }

    /// Start of a group call (§2.2 step 1): ACCU1, ACCU2, the status word and local data := 0.
    pub fn begin_group_call(&mut self) {
        todo!()
    }

    /// `restart cold` (§2.8): everything as §1.2 except inputs, stub values, call counters and
    /// the clock.
    pub fn restart_cold(&mut self, program: &Program) {
        let _ = program;
        todo!()
    }

    /// The stub value a test set for `block.param` (param in upper case), if any.
    pub fn stub(&self, block: u32, param: &str) -> Option<&Value> {
        let _ = (block, param);
        todo!()
    }

    pub fn set_stub(&mut self, block: u32, param: &str, value: Value) {
        let _ = (block, param, value);
        todo!()
    }

    /// `Block.calls`.
    pub fn calls(&self, block: u32) -> u32 {
        let _ = block;
        todo!()
    }
}
