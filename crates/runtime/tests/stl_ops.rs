//! Timers, counters, word logic, arithmetic, shifts, conversions and stub calls
//! (runtime.md §3.3–§3.11), with hand-computed expectations.

mod stl_common;
use higraph_runtime::machine::Machine;
use higraph_runtime::program::OpCode::*;
use higraph_runtime::program::{
    BlockInfo, Call, CellInfo, Instr, MemArea, Operand, Origin, Place, Program, Width,
};
use higraph_runtime::stl;
use higraph_runtime::value::{Const, Ty, Value};
use stl_common::*;

fn st(x: &Machine) -> (bool, bool, bool, bool) {
    (x.status.cc1, x.status.cc0, x.status.ov, x.status.os)
}

/// Runs `code` in cycles `1..=to` (Δ = 10 ms) with M 0.0 = input(k); returns M 1.0 per cycle.
fn timer_run(code: &[Instr], to: u64, input: impl std::ops::Fn(u64) -> bool) -> Vec<u8> {
    let mut x = machine();
    let mut out = Vec::new();
    for k in 1..=to {
        x.now_ms = 10 * k;
        set_bit(&mut x, 0, 0, input(k));
        let mut c = code.to_vec();
        c.push(i(U, t(1)));
        c.push(i(Assign, m(1, 0)));
        run(&mut x, c);
        out.push(bit(&mut x, 1, 0) as u8);
    }
    out
}

fn start(op: higraph_runtime::program::OpCode, ms: i64) -> Vec<Instr> {
    vec![i(U, m(0, 0)), i(L, imm(Const::S5Time(ms))), i(op, t(1))]
}

#[test]
fn extended_pulse_retentive_and_off_delay() {
    // SV: a short input pulse in cycle 2 gives Q for 30 ms (cycles 2, 3, 4)
    assert_eq!(
        timer_run(&start(Sv, 30), 7, |k| k == 2),
        vec![0, 1, 1, 1, 0, 0, 0]
    );
    // SS: input pulse in cycle 2 → Q from cycle 5 on, stays 1 (no R)
    assert_eq!(
        timer_run(&start(Ss, 30), 8, |k| k == 2),
        vec![0, 0, 0, 0, 1, 1, 1, 1]
    );
    // SA: Q while input, then 30 ms longer (cycles 5, 6, 7 after the input fell in cycle 5)
    assert_eq!(
        timer_run(&start(Sa, 30), 9, |k| (2..=4).contains(&k)),
        vec![0, 1, 1, 1, 1, 1, 1, 0, 0]
    );
    // SA restarted by a new rising edge while running keeps Q
    assert_eq!(
        timer_run(&start(Sa, 30), 9, |k| k == 2 || k == 4),
        vec![0, 1, 1, 1, 1, 1, 1, 0, 0]
    );
}

#[test]
fn reset_and_enable() {
    // SS then R in cycle 6 (input M 0.1)
    let mut code = start(Ss, 20);
    code.extend([i(U, m(0, 1)), i(R, t(1))]);
    let mut x = machine();
    let mut out = Vec::new();
    for k in 1..=8u64 {
        x.now_ms = 10 * k;
        set_bit(&mut x, 0, 0, k == 1);
        set_bit(&mut x, 0, 1, k == 6);
        let mut c = code.clone();
        c.push(i(U, t(1)));
        out.push(run(&mut x, c) as u8);
    }
    assert_eq!(out, vec![0, 0, 1, 1, 1, 0, 0, 0]);
    // FR lets SE restart without the RLO going to 0: SE 20 ms, FR in cycle 4
    let mut code = start(Se, 20);
    code.splice(0..0, [i(U, m(0, 1)), i(Fr, t(1))]);
    let mut x = machine();
    let mut vals = Vec::new();
    for k in 1..=6u64 {
        x.now_ms = 10 * k;
        set_bit(&mut x, 0, 0, true);
        set_bit(&mut x, 0, 1, k == 4);
        let mut c = code.clone();
        c.push(i(L, t(1)));
        run(&mut x, c);
        vals.push(x.accu1);
    }
    // started in cycle 1 (deadline 30): 2, 1, expired (0) in cycle 3; FR in cycle 4 restarts
    // (deadline 60): 2, 1, then expired
    assert_eq!(vals, vec![2, 1, 0, 2, 1, 0]);
}

#[test]
fn s5time_faults_on_bad_bcd() {
    let mut x = machine();
    let b = block(vec![i(L, bits(0x00A0)), i(Se, t(1))]);
    let f = stl::run_block(&mut x, &[], &b, false).unwrap_err();
    assert!(f.reason.contains("BCD"), "{}", f.reason);
    // bits 14–15 are ignored: 16#C010 is 10 × 10 ms
    let mut x = machine();
    x.now_ms = 100;
    run(&mut x, vec![i(L, bits(0xC010)), i(Se, t(1)), i(L, t(1))]);
    assert_eq!(x.accu1, 10);
}

#[test]
fn counters() {
    let mut x = machine();
    let cycle = |x: &mut Machine, up: bool, down: bool| {
        set_bit(x, 0, 0, up);
        set_bit(x, 0, 1, down);
        run(
            x,
            vec![
                i(U, m(0, 0)),
                i(Zv, z(2)),
                i(U, m(0, 1)),
                i(Zr, z(2)),
                i(L, z(2)),
            ],
        );
        x.accu1
    };
    assert_eq!(cycle(&mut x, true, false), 1);
    assert_eq!(cycle(&mut x, true, false), 1, "no edge");
    assert_eq!(cycle(&mut x, false, false), 1);
    assert_eq!(cycle(&mut x, true, false), 2);
    assert_eq!(cycle(&mut x, false, true), 1);
    assert_eq!(cycle(&mut x, false, true), 1);
    assert_eq!(cycle(&mut x, false, false), 1);
    assert_eq!(cycle(&mut x, false, true), 0);
    assert_eq!(cycle(&mut x, false, false), 0);
    assert_eq!(cycle(&mut x, false, true), 0, "not below 0");
    // preset, LC, bit value, reset
    run(
        &mut x,
        vec![i(L, imm(Const::Counter(999))), i(S, z(2)), i(Zv, z(2))],
    );
    run(&mut x, vec![i(Lc, z(2)), i(U, z(2))]);
    assert_eq!(x.accu1, 0x999, "not above 999");
    assert!(x.status.rlo);
    run(&mut x, vec![i(R, z(2)), i(U, z(2))]);
    assert!(!x.status.rlo);
    // FR re-arms the edge of S
    let mut x = machine();
    run(&mut x, vec![i(L, imm(Const::Counter(5))), i(S, z(1))]);
    run(
        &mut x,
        vec![i(L, imm(Const::Counter(7))), i(S, z(1)), i(L, z(1))],
    );
    assert_eq!(x.accu1, 5, "no edge");
    run(
        &mut x,
        vec![
            i(Fr, z(1)),
            i(L, imm(Const::Counter(7))),
            i(S, z(1)),
            i(L, z(1)),
        ],
    );
    assert_eq!(x.accu1, 7);
    // an invalid BCD preset is a fault
    let f = stl::run_block(
        &mut machine(),
        &[],
        &block(vec![i(L, bits(0x1A)), i(S, z(0))]),
        false,
    );
    assert!(f.is_err());
}

#[test]
fn load_transfer_accumulators() {
    let mut x = machine();
    run(&mut x, vec![i(L, dint(1)), i(L, dint(2)), n(Tak)]);
    assert_eq!((x.accu1, x.accu2), (1, 2));
    run(&mut x, vec![n(Push)]);
    assert_eq!((x.accu1, x.accu2), (1, 1));
    run(&mut x, vec![i(L, dint(9)), n(Pop)]);
    assert_eq!((x.accu1, x.accu2), (1, 1));
    run(&mut x, vec![i(L, bits(0x1234_56FF)), i(Inc, bits(2))]);
    assert_eq!(x.accu1, 0x1234_5601);
    run(&mut x, vec![i(Dec, bits(3))]);
    assert_eq!(x.accu1, 0x1234_56FE);
    run(&mut x, vec![i(L, bits(0x0001_FFFF)), i(AddInt, int(1))]);
    assert_eq!(x.accu1, 0x0001_0000);
    run(&mut x, vec![i(L, bits(0x0001_FFFF)), i(AddDint, dint(1))]);
    assert_eq!(x.accu1, 0x0002_0000);
    run(&mut x, vec![i(L, bits(0x1122_3344)), n(Taw)]);
    assert_eq!(x.accu1, 0x1122_4433);
    run(&mut x, vec![n(Tad)]);
    assert_eq!(x.accu1, 0x3344_2211);
    x.ar1 = 5;
    x.ar2 = 6;
    run(&mut x, vec![n(Tar), n(Tar1)]);
    assert_eq!((x.accu1, x.ar2), (6, 5));
}

#[test]
fn word_logic() {
    let mut x = machine();
    run(&mut x, vec![i(L, bits(0xFFFF_00F0)), i(Uw, bits(0x0F0F))]);
    assert_eq!(x.accu1, 0xFFFF_0000);
    assert_eq!(
        st(&x),
        (false, false, false, false),
        "CC1 = result ≠ 0 (low word)"
    );
    run(&mut x, vec![i(L, bits(0xF0)), i(L, bits(0x0F)), n(Ow)]);
    assert_eq!(x.accu1, 0xFF);
    assert!(x.status.cc1);
    run(
        &mut x,
        vec![i(L, bits(0xFFFF_FFFF)), i(Xod, bits(0x0F0F_0F0F))],
    );
    assert_eq!(x.accu1, 0xF0F0_F0F0);
    run(&mut x, vec![i(Ud, bits(0))]);
    assert_eq!((x.accu1, x.status.cc1), (0, false));
}

#[test]
fn integer_arithmetic() {
    let mut x = machine();
    // /I: quotient in ACCU1-L, remainder in ACCU1-H
    run(&mut x, vec![i(L, int(7)), i(L, int(2)), n(DivI)]);
    assert_eq!(x.accu1, 0x0001_0003);
    run(&mut x, vec![i(L, int(-7)), i(L, int(2)), n(DivI)]);
    assert_eq!(x.accu1, 0xFFFF_FFFD, "q = −3, rem = −1");
    assert_eq!(st(&x), (false, true, false, false));
    run(&mut x, vec![i(L, int(-32768)), i(L, int(-1)), n(DivI)]);
    assert_eq!(x.accu1 & 0xFFFF, 0x8000);
    assert_eq!(
        st(&x),
        (true, false, true, true),
        "q = 32768: OV, CC from q > 0"
    );
    // division by zero: ACCU1 unchanged, CC1 CC0 OV OS
    let mut x = machine();
    run(&mut x, vec![i(L, int(5)), i(L, int(0)), n(DivI)]);
    assert_eq!(x.accu1, 0);
    assert_eq!(st(&x), (true, true, true, true));
    let mut x = machine();
    run(&mut x, vec![i(L, dint(-7)), i(L, dint(2)), n(Mod)]);
    assert_eq!(x.accu1 as i32, -1);
    run(
        &mut x,
        vec![i(L, dint(i32::MIN as i64)), i(L, dint(-1)), n(DivD)],
    );
    assert_eq!(x.accu1, 0x8000_0000);
    assert!(x.status.ov && x.status.os);
    let mut x = machine();
    run(&mut x, vec![i(L, int(300)), i(L, int(300)), n(MulI)]);
    assert_eq!(x.accu1, 90000, "32-bit product");
    assert_eq!(st(&x), (true, false, true, true));
    let mut x = machine();
    run(&mut x, vec![i(L, int(-32768)), n(NegI)]);
    assert_eq!(x.accu1 & 0xFFFF, 0x8000);
    assert!(x.status.ov);
    run(&mut x, vec![i(L, dint(5)), i(L, dint(7)), n(SubD)]);
    assert_eq!(x.accu1 as i32, -2, "ACCU2 − ACCU1");
    assert_eq!(st(&x), (false, true, false, true), "OS stays");
    assert_eq!(x.accu2, 5, "ACCU2 unchanged");
    run(&mut x, vec![i(L, dint(65536)), i(L, dint(65536)), n(MulD)]);
    assert_eq!(x.accu1, 0);
    assert_eq!(
        st(&x),
        (true, false, true, true),
        "CC from the true product"
    );
}

fn real_op(code: Vec<Instr>) -> (u32, (bool, bool, bool, bool)) {
    let mut x = machine();
    run(&mut x, code);
    (x.accu1, st(&x))
}

#[test]
fn real_classification() {
    // the table of runtime.md §3.8
    assert_eq!(
        real_op(vec![i(L, real(1.0)), i(L, real(2.0)), n(AddR)]),
        (3.0f32.to_bits(), (true, false, false, false))
    );
    assert_eq!(
        real_op(vec![i(L, real(1.0)), i(L, real(2.0)), n(SubR)]),
        ((-1.0f32).to_bits(), (false, true, false, false))
    );
    assert_eq!(
        real_op(vec![i(L, real(2.0)), i(L, real(-2.0)), n(AddR)]),
        (0, (false, false, false, false))
    );
    // nonzero below 2^−126: +0.0 with OV, OS
    assert_eq!(
        real_op(vec![i(L, real(1e-30)), i(L, real(1e-10)), n(MulR)]),
        (0, (false, false, true, true))
    );
    // overflow: ±∞
    assert_eq!(
        real_op(vec![i(L, real(3e38)), i(L, real(3e38)), n(AddR)]),
        (f32::INFINITY.to_bits(), (true, false, true, true))
    );
    assert_eq!(
        real_op(vec![i(L, real(-3e38)), i(L, real(10.0)), n(MulR)]),
        (f32::NEG_INFINITY.to_bits(), (false, true, true, true))
    );
    // NaN: all ones
    assert_eq!(
        real_op(vec![i(L, real(0.0)), i(L, real(0.0)), n(DivR)]),
        (0xFFFF_FFFF, (true, true, true, true))
    );
    assert_eq!(real_op(vec![i(L, real(-1.0)), n(Sqrt)]).0, 0xFFFF_FFFF);
    assert_eq!(real_op(vec![i(L, real(2.0)), n(Asin)]).0, 0xFFFF_FFFF);
    assert_eq!(
        real_op(vec![i(L, real(0.0)), n(Ln)]).0,
        f32::NEG_INFINITY.to_bits()
    );
    assert_eq!(
        real_op(vec![i(L, real(1.0)), i(L, real(0.0)), n(DivR)]).0,
        f32::INFINITY.to_bits()
    );
    // functions: the double result rounded; ±∞ returned unchanged
    assert_eq!(
        real_op(vec![i(L, real(2.0)), n(Sqrt)]).0,
        2f32.sqrt().to_bits()
    );
    assert_eq!(
        real_op(vec![i(L, real(1.0)), n(Exp)]).0,
        (1f64.exp() as f32).to_bits()
    );
    assert_eq!(
        real_op(vec![i(L, bits(f32::NEG_INFINITY.to_bits() as u64)), n(Sin)]).0,
        f32::NEG_INFINITY.to_bits()
    );
    assert_eq!(real_op(vec![i(L, real(-3.0)), n(Sqr)]).0, 9f32.to_bits());
    // ABS, NEGR: bit 31 only, status word alone
    let mut x = machine();
    run(&mut x, vec![i(L, real(-2.5)), n(Abs)]);
    assert_eq!(x.accu1, 2.5f32.to_bits());
    run(&mut x, vec![n(NegR), n(NegR), n(NegR)]);
    assert_eq!(x.accu1, (-2.5f32).to_bits());
    assert_eq!(st(&x), (false, false, false, false));
}

#[test]
fn shifts_and_rotates() {
    let mut x = machine();
    run(&mut x, vec![i(L, bits(0xAAAA_8001)), i(Slw, bits(1))]);
    assert_eq!(x.accu1, 0xAAAA_0002);
    assert!(x.status.cc1, "the bit shifted out");
    run(&mut x, vec![i(L, bits(0x0000_8001)), i(Ssi, bits(4))]);
    assert_eq!(x.accu1, 0x0000_F800);
    assert!(!x.status.cc1);
    run(&mut x, vec![i(L, bits(0x0000_8001)), i(Srw, bits(20))]);
    assert_eq!(x.accu1, 0, "above 16 acts as 16");
    assert!(x.status.cc1, "last out: bit 15");
    run(&mut x, vec![i(L, bits(0x8000_0001)), i(Sld, bits(0))]);
    assert_eq!(x.accu1, 0x8000_0001, "0 changes nothing");
    assert!(x.status.cc1, "status too");
    run(&mut x, vec![i(L, bits(0x8000_0001)), i(Ssd, bits(33))]);
    assert_eq!(x.accu1, 0xFFFF_FFFF);
    run(&mut x, vec![i(L, int(4)), i(L, bits(0x8000_0001)), n(Rld)]);
    assert_eq!(x.accu1, 0x0000_0018, "n from ACCU2");
    assert!(!x.status.cc1);
    run(&mut x, vec![i(L, bits(0x0000_0001)), i(Rrd, bits(1))]);
    assert_eq!(x.accu1, 0x8000_0000);
    assert!(x.status.cc1);
    run(&mut x, vec![i(L, bits(0x8000_0000)), n(Rlda)]);
    assert_eq!(x.accu1, 1, "old CC1 enters");
    assert!(x.status.cc1);
    run(&mut x, vec![n(Rrda)]);
    assert_eq!(x.accu1, 0x8000_0000);
    assert!(x.status.cc1);
    assert!(!x.status.cc0 && !x.status.ov);
}

#[test]
fn conversions() {
    let mut x = machine();
    run(&mut x, vec![i(L, bits(0x1234_8123)), n(Bti)]);
    assert_eq!(x.accu1, 0x1234_0000 | (-123i16 as u16 as u32));
    run(&mut x, vec![i(L, bits(0x8123_4567)), n(Btd)]);
    assert_eq!(x.accu1 as i32, -1_234_567);
    run(
        &mut x,
        vec![i(L, bits(0x5555_0000 | (-999i16 as u16 as u64))), n(Itb)],
    );
    assert_eq!(x.accu1, 0x5555_F999);
    run(&mut x, vec![i(L, int(1000)), n(Itb)]);
    assert_eq!(x.accu1, 1000, "unchanged");
    assert!(x.status.ov && x.status.os);
    run(&mut x, vec![i(L, dint(-9_999_999)), n(Dtb)]);
    assert_eq!(x.accu1, 0xF999_9999);
    assert!(!x.status.ov);
    run(&mut x, vec![i(L, int(-5)), n(Itd)]);
    assert_eq!(x.accu1 as i32, -5);
    run(&mut x, vec![n(Dtr)]);
    assert_eq!(x.accu1, (-5.0f32).to_bits());
    run(&mut x, vec![i(L, dint(16_777_217)), n(Dtr)]);
    assert_eq!(x.accu1, 16_777_216f32.to_bits(), "nearest even");
    run(&mut x, vec![i(L, bits(0x1234_00FF)), n(Invi)]);
    assert_eq!(x.accu1, 0x1234_FF00);
    run(&mut x, vec![n(Invd)]);
    assert_eq!(x.accu1, 0xEDCB_00FF);
    let rnd = |op, v: f64| {
        let mut x = machine();
        run(&mut x, vec![i(L, real(v)), n(op)]);
        x.accu1 as i32
    };
    assert_eq!(rnd(Rnd, 2.5), 2);
    assert_eq!(rnd(Rnd, 3.5), 4);
    assert_eq!(rnd(Rnd, -2.5), -2);
    assert_eq!(rnd(RndPlus, 2.1), 3);
    assert_eq!(rnd(RndPlus, -2.9), -2);
    assert_eq!(rnd(RndMinus, -2.1), -3);
    assert_eq!(rnd(Trunc, -2.9), -2);
    let mut x = machine();
    run(&mut x, vec![i(L, real(3e9)), n(Rnd)]);
    assert_eq!(x.accu1, 3e9f32.to_bits(), "outside DINT: unchanged");
    assert!(x.status.ov && x.status.os);
    let f = stl::run_block(
        &mut machine(),
        &[],
        &block(vec![i(L, bits(0x00A0)), n(Bti)]),
        false,
    );
    assert!(f.is_err(), "BCD digit above 9");
}

fn stub_program() -> Program {
    Program {
        cells: vec![CellInfo {
            ty: Ty::Int,
            init: Value::Int(3),
        }],
        blocks: vec![BlockInfo {
            name: "FC10".into(),
        }],
        ..Program::default()
    }
}

#[test]
fn stub_calls() {
    let p = stub_program();
    let mut x = Machine::new(&p);
    x.set_stub(0, "out1", Value::Int(-4));
    let call = |params: Vec<(String, Operand)>| Operand::Call(Box::new(Call { block: 0, params }));
    let mw10 = Place::Mem {
        area: MemArea::Memory,
        byte: 10,
        width: Width::Word,
    };
    let code = vec![
        n(Clr),
        i(
            Call,
            call(vec![
                ("Out1".into(), Operand::Place(mw10.clone())),
                ("IN1".into(), Operand::Place(Place::Cell(0))),
            ]),
        ),
    ];
    run(&mut x, code);
    assert_eq!(x.read(&mw10).unwrap(), (-4i16) as u16 as u32);
    assert_eq!(x.read(&Place::Cell(0)).unwrap(), 3, "untouched");
    assert!(x.status.br && x.status.rlo && x.status.sta && !x.status.os);
    assert_eq!(x.calls(0), 1);
    assert_eq!(x.stub(0, "OUT1"), Some(&Value::Int(-4)));
    // CC with RLO 0 does not call, but sets RLO
    run(&mut x, vec![n(Clr), i(Cc, call(vec![]))]);
    assert_eq!(x.calls(0), 1);
    assert!(x.status.rlo);
    run(&mut x, vec![n(Set), i(Cc, call(vec![]))]);
    assert_eq!(x.calls(0), 2);
    // a stub value that does not fit its actual: a fault
    x.set_stub(0, "OUT2", Value::Real(1.0));
    let code = vec![i(
        Call,
        call(vec![(
            "OUT2".into(),
            Operand::Place(Place::Mem {
                area: MemArea::Memory,
                byte: 0,
                width: Width::Bit(0),
            }),
        )]),
    )];
    let f = stl::run_block(&mut x, &[], &block(code), false).unwrap_err();
    assert_eq!(f.origin, Origin(0));
}

#[test]
fn operands_through_the_binding() {
    let p = stub_program();
    let mut x = Machine::new(&p);
    let binding = vec![Place::Cell(0), mp(5, 1)];
    let code = block(vec![
        i(L, Operand::Var(0)),
        i(AddInt, int(1)),
        i(T, Operand::Var(0)),
        i(Assign, Operand::Var(1)),
    ]);
    stl::run_block(&mut x, &binding, &code, false).unwrap();
    assert_eq!(
        x.read_value(&Place::Cell(0), Ty::Int).unwrap(),
        Value::Int(4)
    );
    assert!(bit(&mut x, 5, 1));
    // an unbound variable is a fault, not a panic
    let code = block(vec![i(L, Operand::Var(7))]);
    assert!(stl::run_block(&mut x, &binding, &code, false).is_err());
}

#[test]
fn machine_memory() {
    let p = Program {
        cells: vec![
            CellInfo {
                ty: Ty::String(4),
                init: Value::String("ab".into()),
            },
            CellInfo {
                ty: Ty::Bool,
                init: Value::Bool(true),
            },
            CellInfo {
                ty: Ty::Real,
                init: Value::Real(1.5),
            },
        ],
        ..Program::default()
    };
    let mut x = Machine::new(&p);
    let mw = |b| Place::Mem {
        area: MemArea::Memory,
        byte: b,
        width: Width::Word,
    };
    let mb = |b| Place::Mem {
        area: MemArea::Memory,
        byte: b,
        width: Width::Byte,
    };
    // big-endian, overlapping words
    x.write(&mw(10), 0x1234).unwrap();
    assert_eq!(x.read(&mb(10)).unwrap(), 0x12);
    assert_eq!(x.read(&mw(11)).unwrap(), 0x3400);
    // past byte 65535: a fault
    assert!(x.read(&mw(65535)).is_err());
    assert!(x.write(&mb(65535), 1).is_ok());
    assert!(x.write(&mb(65536), 1).is_err());
    // every DB exists, zeroed
    let db = Place::Mem {
        area: MemArea::Db(60000),
        byte: 65532,
        width: Width::Dword,
    };
    assert_eq!(x.read(&db).unwrap(), 0);
    x.write(&db, 7).unwrap();
    assert_eq!(x.read(&db).unwrap(), 7);
    // cells: typed values, STRING in the side table, truncated to its length
    assert_eq!(
        x.read_value(&Place::Cell(0), Ty::String(4)).unwrap(),
        Value::String("ab".into())
    );
    x.write_value(&Place::Cell(0), &Value::String("abcdef".into()))
        .unwrap();
    assert_eq!(
        x.read_value(&Place::Cell(0), Ty::String(4)).unwrap(),
        Value::String("abcd".into())
    );
    assert_eq!(x.read(&Place::Cell(1)).unwrap(), 1);
    assert_eq!(
        x.read_value(&Place::Cell(2), Ty::Real).unwrap(),
        Value::Real(1.5)
    );
    // a constant place discards writes
    let c = Place::Const(Value::Int(5));
    x.write(&c, 9).unwrap();
    assert_eq!(x.read(&c).unwrap(), 5);
    // STRING in memory: S7 layout
    x.write_value(&mb(100), &Value::String("xy".into()))
        .unwrap();
    assert_eq!(x.read(&mw(100)).unwrap(), 0xFE02);
    assert_eq!(
        x.read_value(&mb(100), Ty::String(254)).unwrap(),
        Value::String("xy".into())
    );
    // group call start: accumulators, status word, local data
    let lw = Place::Mem {
        area: MemArea::Local,
        byte: 4,
        width: Width::Word,
    };
    x.write(&lw, 77).unwrap();
    x.accu1 = 1;
    x.accu2 = 2;
    x.status.or = true;
    x.ar1 = 9;
    x.begin_group_call();
    assert_eq!(
        (x.accu1, x.accu2, x.status.bits(), x.read(&lw).unwrap()),
        (0, 0, 0, 0)
    );
    assert_eq!(x.ar1, 9, "AR1 is not part of §2.2 step 1");
    // cold restart: memory and cells back to §1.2, inputs and stubs kept
    let e0 = Place::Mem {
        area: MemArea::Input,
        byte: 0,
        width: Width::Byte,
    };
    x.write(&e0, 5).unwrap();
    x.set_stub(0, "X", Value::Bool(true));
    x.write(&Place::Cell(1), 0).unwrap();
    x.restart_cold(&p);
    assert_eq!(x.read(&mw(10)).unwrap(), 0);
    assert_eq!(x.read(&db).unwrap(), 0);
    assert_eq!(x.read(&e0).unwrap(), 5);
    assert_eq!(x.read(&Place::Cell(1)).unwrap(), 1);
    assert!(x.stub(0, "x").is_some());
}
