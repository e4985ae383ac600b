//! Random instruction sequences with random operands (wrong kinds, addresses past the end,
//! unbalanced parentheses, unbound variables) end in a result or a fault, never a panic.

use higraph_runtime::machine::Machine;
use higraph_runtime::program::OpCode::{self, *};
use higraph_runtime::program::{
    Block, BlockInfo, Call, CellInfo, CounterId, Instr, MemArea, Operand, Origin, Place, Program,
    TimerId, Width,
};
use higraph_runtime::stl;
use higraph_runtime::value::{Ty, Value};

const OPS: &[OpCode] = &[
    U, Un, O, On, X, Xn, OrNone, UParen, UnParen, OParen, OnParen, XParen, XnParen, Close, Assign,
    S, R, Set, Clr, Not, Fp, Fn, Si, Sv, Se, Ss, Sa, Fr, Zv, Zr, L, Lc, T, Tak, Push, Pop, Inc,
    Dec, AddInt, AddDint, Taw, Tad, Tar, Tar1, Tar2, Uw, Ow, Xow, Ud, Od, Xod, EqI, NeI, GtI, LtI,
    GeI, LeI, EqD, NeD, GtD, LtD, GeD, LeD, EqR, NeR, GtR, LtR, GeR, LeR, AddI, SubI, MulI, DivI,
    AddD, SubD, MulD, DivD, Mod, NegI, NegD, AddR, SubR, MulR, DivR, Abs, Sqr, Sqrt, Exp, Ln, Sin,
    Cos, Tan, Asin, Acos, Atan, NegR, Slw, Srw, Sld, Srd, Ssi, Ssd, Rld, Rrd, Rlda, Rrda, Bti, Btd,
    Itb, Dtb, Itd, Dtr, Invi, Invd, Rnd, RndPlus, RndMinus, Trunc, Call, Cc,
];

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

fn operand(r: &mut Rng) -> Operand {
    let area = [
        MemArea::Input,
        MemArea::Output,
        MemArea::Memory,
        MemArea::Local,
        MemArea::Db(7),
    ][r.below(5) as usize];
    let byte = if r.below(10) == 0 {
        65530 + r.below(10) as u32
    } else {
        r.below(16) as u32
    };
    let width = [
        Width::Bit(r.below(8) as u8),
        Width::Byte,
        Width::Word,
        Width::Dword,
    ][r.below(4) as usize];
    match r.below(9) {
        0 => Operand::None,
        1 => Operand::Imm(r.next() as u32),
        2 => Operand::Var(r.below(4) as u16),
        3 => Operand::Place(Place::Timer(TimerId(r.below(3) as u32))),
        4 => Operand::Place(Place::Counter(CounterId(r.below(3) as u32))),
        5 => Operand::Place(Place::Cell(r.below(3) as u32)),
        6 => Operand::Place(Place::Const(Value::Int(3))),
        7 => Operand::Call(Box::new(Call {
            block: r.below(2) as u32,
            params: vec![("P".into(), operand_place(r))],
        })),
        _ => Operand::Place(Place::Mem { area, byte, width }),
    }
}

fn operand_place(r: &mut Rng) -> Operand {
    Operand::Place(Place::Mem {
        area: MemArea::Memory,
        byte: r.below(8) as u32,
        width: Width::Word,
    })
}

#[test]
fn random_blocks_never_panic() {
    let p = Program {
        cells: vec![
            CellInfo {
                ty: Ty::Int,
                init: Value::Int(1),
            },
            CellInfo {
                ty: Ty::String(8),
                init: Value::String("x".into()),
            },
        ],
        blocks: vec![BlockInfo { name: "FC1".into() }],
        ..Program::default()
    };
    let mut m = Machine::new(&p);
    m.set_stub(0, "P", Value::Word(5));
    let binding = vec![Place::Cell(0), Place::Timer(TimerId(70000)), Place::Cell(1)];
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    let (mut ok, mut faults) = (0, 0);
    for k in 0..20_000u64 {
        let n = 1 + r.below(20) as usize;
        let code: Vec<Instr> = (0..n)
            .map(|_| Instr {
                op: OPS[r.below(OPS.len() as u64) as usize],
                operand: operand(&mut r),
                origin: Origin(7),
            })
            .collect();
        m.now_ms = 10 * k;
        m.accu1 = r.next() as u32;
        m.accu2 = r.next() as u32;
        match stl::run_block(&mut m, &binding, &Block { code }, r.below(2) == 0) {
            Ok(_) => ok += 1,
            Err(f) => {
                assert_eq!(f.origin, Origin(7));
                faults += 1;
            }
        }
    }
    assert!(ok > 100 && faults > 100, "{ok} ok, {faults} faults");
}
