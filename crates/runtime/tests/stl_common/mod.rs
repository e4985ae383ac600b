//! Helpers shared by the STL tests: blocks written compactly, a machine with no program.
#![allow(dead_code)]

use higraph_runtime::machine::Machine;
use higraph_runtime::program::{
    Block, CounterId, Instr, MemArea, OpCode, Operand, Origin, Place, Program, TimerId, Width,
};
use higraph_runtime::stl;
use higraph_runtime::value::Const;

pub fn machine() -> Machine {
    Machine::new(&Program::default())
}

pub fn m(byte: u32, bit: u8) -> Operand {
    Operand::Place(Place::Mem {
        area: MemArea::Memory,
        byte,
        width: Width::Bit(bit),
    })
}

pub fn mp(byte: u32, bit: u8) -> Place {
    Place::Mem {
        area: MemArea::Memory,
        byte,
        width: Width::Bit(bit),
    }
}

pub fn mem(area: MemArea, byte: u32, width: Width) -> Place {
    Place::Mem { area, byte, width }
}

pub fn mb(byte: u32) -> Operand {
    Operand::Place(mem(MemArea::Memory, byte, Width::Byte))
}
pub fn mw(byte: u32) -> Operand {
    Operand::Place(mem(MemArea::Memory, byte, Width::Word))
}
pub fn md(byte: u32) -> Operand {
    Operand::Place(mem(MemArea::Memory, byte, Width::Dword))
}
pub fn t(n: u32) -> Operand {
    Operand::Place(Place::Timer(TimerId(n)))
}
pub fn z(n: u32) -> Operand {
    Operand::Place(Place::Counter(CounterId(n)))
}
pub fn imm(c: Const) -> Operand {
    Operand::Imm(stl::load_pattern(&c))
}
pub fn int(n: i64) -> Operand {
    imm(Const::Int(n))
}
pub fn dint(n: i64) -> Operand {
    imm(Const::LongInt(n))
}
pub fn real(x: f64) -> Operand {
    imm(Const::Real(x))
}
pub fn bits(v: u64) -> Operand {
    Operand::Imm(v as u32)
}

pub fn i(op: OpCode, operand: Operand) -> Instr {
    Instr {
        op,
        operand,
        origin: Origin(0),
    }
}
pub fn n(op: OpCode) -> Instr {
    i(op, Operand::None)
}

pub fn block(code: Vec<Instr>) -> Block {
    Block { code }
}

/// Runs a block (RLO = 1 at its start) and returns the final RLO.
pub fn run(mach: &mut Machine, code: Vec<Instr>) -> bool {
    stl::run_block(mach, &[], &block(code), false).expect("no fault")
}

pub fn bit(mach: &mut Machine, byte: u32, b: u8) -> bool {
    mach.read(&mp(byte, b)).unwrap() != 0
}

pub fn set_bit(mach: &mut Machine, byte: u32, b: u8, v: bool) {
    mach.write(&mp(byte, b), v as u32).unwrap();
}
