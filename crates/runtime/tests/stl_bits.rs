//! Bit logic, load/transfer, comparisons and the first timers (runtime.md §3.2, §3.3, §3.5, §3.6).

mod stl_common;
use higraph_runtime::program::OpCode::*;
use higraph_runtime::value::Const;
use stl_common::*;

#[test]
fn and_or_xor_and_assign() {
    let mut x = machine();
    set_bit(&mut x, 0, 0, true);
    // M0.0 ∧ ¬M0.1 → M1.0
    assert!(run(
        &mut x,
        vec![i(U, m(0, 0)), i(Un, m(0, 1)), i(Assign, m(1, 0))]
    ));
    assert!(bit(&mut x, 1, 0));
    // M0.1 ∨ M0.0
    assert!(run(&mut x, vec![i(U, m(0, 1)), i(O, m(0, 0))]));
    // first check after SET: U takes the operand
    assert!(!run(&mut x, vec![i(U, m(0, 1))]));
    // X: 1 ⊕ 1 = 0
    assert!(!run(&mut x, vec![i(X, m(0, 0)), i(X, m(0, 0))]));
    assert!(run(&mut x, vec![i(X, m(0, 0)), i(Xn, m(0, 0))]));
    // status after U: STA = the operand, /FC = 1
    run(&mut x, vec![i(U, m(0, 0))]);
    assert!(x.status.sta && x.status.fc && x.status.rlo && !x.status.or);
    // = ends the string: /FC = 0, STA = RLO
    run(&mut x, vec![i(Un, m(0, 0)), i(Assign, m(1, 1))]);
    assert!(!bit(&mut x, 1, 1));
    assert!(!x.status.fc && !x.status.sta && !x.status.rlo);
}

#[test]
fn and_before_or_without_operand() {
    // (M0.0 ∧ M0.1) ∨ (M0.2 ∧ M0.3): O without operand
    let prog = |x: &mut _| {
        run(
            x,
            vec![
                i(U, m(0, 0)),
                i(U, m(0, 1)),
                n(OrNone),
                i(U, m(0, 2)),
                i(U, m(0, 3)),
                i(Assign, m(2, 0)),
            ],
        );
        bit(x, 2, 0)
    };
    for v in 0u8..16 {
        let mut x = machine();
        for b in 0..4 {
            set_bit(&mut x, 0, b, v & (1 << b) != 0);
        }
        let want = (v & 3 == 3) || (v & 12 == 12);
        assert_eq!(prog(&mut x), want, "inputs {v:04b}");
    }
}

#[test]
fn nesting() {
    for v in 0u8..8 {
        let mut x = machine();
        for b in 0..3 {
            set_bit(&mut x, 0, b, v & (1 << b) != 0);
        }
        let (a, b, c) = (v & 1 != 0, v & 2 != 0, v & 4 != 0);
        // a ∧ (b ∨ c)
        let r = run(
            &mut x,
            vec![
                i(U, m(0, 0)),
                n(UParen),
                i(U, m(0, 1)),
                i(O, m(0, 2)),
                n(Close),
            ],
        );
        assert_eq!(r, a && (b || c));
        // a ∨ ¬(b ∧ c)
        let r = run(
            &mut x,
            vec![
                i(U, m(0, 0)),
                n(OnParen),
                i(U, m(0, 1)),
                i(U, m(0, 2)),
                n(Close),
            ],
        );
        assert_eq!(r, a || !(b && c));
        // a ⊕ (b ∧ ¬c)
        let r = run(
            &mut x,
            vec![
                i(U, m(0, 0)),
                n(XParen),
                i(U, m(0, 1)),
                i(Un, m(0, 2)),
                n(Close),
            ],
        );
        assert_eq!(r, a ^ (b && !c));
        // ¬(a) first in the string: UN( … ) as the first check
        let r = run(
            &mut x,
            vec![n(UnParen), i(U, m(0, 0)), n(Close), i(U, m(0, 1))],
        );
        assert_eq!(r, !a && b);
    }
    // More than 7 levels is a fault carrying the origin.
    let mut x = machine();
    let code = vec![n(UParen); 8];
    let f = higraph_runtime::stl::run_block(&mut x, &[], &block(code), false).unwrap_err();
    assert_eq!(f.origin, higraph_runtime::program::Origin(0));
}

#[test]
fn set_reset_set_clr_not() {
    let mut x = machine();
    run(&mut x, vec![n(Clr), i(S, m(3, 0))]);
    assert!(!bit(&mut x, 3, 0));
    run(&mut x, vec![n(Set), i(S, m(3, 0))]);
    assert!(bit(&mut x, 3, 0));
    run(&mut x, vec![n(Clr), n(Not), i(R, m(3, 0))]);
    assert!(!bit(&mut x, 3, 0));
    assert!(x.status.sta && !x.status.fc);
    assert!(!run(&mut x, vec![n(Clr)]));
    assert!(!x.status.sta);
}

#[test]
fn rlo0_block() {
    let mut x = machine();
    set_bit(&mut x, 0, 0, true);
    set_bit(&mut x, 1, 0, true);
    set_bit(&mut x, 1, 1, true);
    let b = block(vec![i(Assign, m(1, 0)), i(S, m(1, 2)), i(R, m(1, 1))]);
    assert!(!higraph_runtime::stl::run_block(&mut x, &[], &b, true).unwrap());
    assert!(!bit(&mut x, 1, 0), "= resets in the RLO-0 pass");
    assert!(
        !bit(&mut x, 1, 2) && bit(&mut x, 1, 1),
        "S and R do nothing"
    );
    // U is a first check
    let b = block(vec![i(U, m(0, 0)), i(Assign, m(1, 3))]);
    assert!(higraph_runtime::stl::run_block(&mut x, &[], &b, true).unwrap());
    assert!(bit(&mut x, 1, 3));
}

#[test]
fn edges() {
    let mut x = machine();
    let fp = |x: &mut _| run(x, vec![i(U, m(0, 0)), i(Fp, m(9, 0))]);
    let fneg = |x: &mut _| run(x, vec![i(U, m(0, 0)), i(Fn, m(9, 1))]);
    assert!(!fp(&mut x) && !fneg(&mut x));
    set_bit(&mut x, 0, 0, true);
    assert!(fp(&mut x), "rising edge");
    assert!(!fneg(&mut x));
    assert!(!fp(&mut x), "no edge while it stays 1");
    assert!(bit(&mut x, 9, 0));
    set_bit(&mut x, 0, 0, false);
    assert!(!fp(&mut x));
    assert!(fneg(&mut x), "falling edge");
    assert!(!fneg(&mut x));
}

#[test]
fn load_transfer_and_constants() {
    use higraph_runtime::stl::load_pattern as lp;
    assert_eq!(lp(&Const::Int(-1)), 0x0000_FFFF);
    assert_eq!(lp(&Const::Int(40000)), 40000);
    assert_eq!(lp(&Const::Int(-40000)), (-40000i32) as u32);
    assert_eq!(lp(&Const::LongInt(-1)), 0xFFFF_FFFF);
    assert_eq!(lp(&Const::Counter(123)), 0x0123);
    assert_eq!(lp(&Const::S5Time(50)), 0x0005);
    assert_eq!(lp(&Const::S5Time(2_500)), 0x0250);
    assert_eq!(lp(&Const::S5Time(12_000)), 0x1120);
    assert_eq!(lp(&Const::S5Time(9_990)), 0x0999);
    assert_eq!(lp(&Const::S5Time(15)), 0x0002, "1.5 → 2 (half even)");
    assert_eq!(lp(&Const::S5Time(25)), 0x0002, "2.5 → 2 (half even)");
    assert_eq!(lp(&Const::S5Time(1_500_000)), 0x3150, "1500 s in base 10 s");
    assert_eq!(lp(&Const::Real(1.0)), 0x3F80_0000);
    assert_eq!(lp(&Const::Chars(b"AB".to_vec())), 0x4142);
    assert_eq!(
        lp(&Const::Pointer {
            area: 0x83,
            byte: 50,
            bit: 0
        }),
        0x8300_0190
    );
    assert_eq!(
        lp(&Const::Pointer {
            area: 0,
            byte: 2,
            bit: 3
        }),
        19
    );
    assert_eq!(lp(&Const::Time(-5)), (-5i32) as u32);

    let mut x = machine();
    run(&mut x, vec![i(L, bits(0x1234_5678)), i(T, md(10))]);
    assert_eq!(
        x.read(&stl_common::mem(
            higraph_runtime::program::MemArea::Memory,
            10,
            higraph_runtime::program::Width::Word
        ))
        .unwrap(),
        0x1234
    );
    run(&mut x, vec![i(L, mb(11)), i(L, mw(12))]);
    assert_eq!((x.accu1, x.accu2), (0x5678, 0x34));
    // T by width: low byte only
    run(&mut x, vec![i(L, bits(0xABCD)), i(T, mb(20))]);
    run(&mut x, vec![i(L, mb(20))]);
    assert_eq!(x.accu1, 0xCD);
    // loads leave the status word alone
    run(&mut x, vec![i(U, m(0, 0)), i(L, int(3))]);
    assert!(x.status.fc && !x.status.rlo);
}

#[test]
fn add_int() {
    let mut x = machine();
    run(
        &mut x,
        vec![i(L, int(30000)), i(L, int(10000)), n(AddI), i(T, mw(0))],
    );
    assert_eq!(x.accu1 & 0xFFFF, (40000i32 - 65536) as u16 as u32);
    assert!(x.status.ov && x.status.os);
    // CC from the stored (negative) value
    assert!(x.status.cc0 && !x.status.cc1);
    run(&mut x, vec![i(L, int(3)), i(L, int(-5)), n(AddI)]);
    assert_eq!(x.accu1, 0xFFFE);
    assert!(!x.status.ov && x.status.os, "OS stays");
    assert!(x.status.cc0 && !x.status.cc1);
    // ACCU1-H unchanged
    run(&mut x, vec![i(L, int(1)), i(L, dint(0x0007_0002)), n(AddI)]);
    assert_eq!(x.accu1, 0x0007_0003);
    assert_eq!(x.accu2, 1, "ACCU2 unchanged");
}

#[test]
fn comparisons_replace_the_rlo() {
    // runtime.md §3.6: U M 1.0 = 0, then L 5; L 5; ==I; = M 0.4 sets M 0.4.
    let mut x = machine();
    run(
        &mut x,
        vec![
            i(U, m(1, 0)),
            i(L, int(5)),
            i(L, int(5)),
            n(EqI),
            i(Assign, m(0, 4)),
        ],
    );
    assert!(bit(&mut x, 0, 4));
    run(&mut x, vec![i(L, int(-3)), i(L, int(2)), n(LtI)]);
    assert!(x.status.rlo && x.status.sta && x.status.fc && !x.status.or);
    assert!(x.status.cc0 && !x.status.cc1 && !x.status.ov);
    run(&mut x, vec![i(L, dint(70000)), i(L, dint(-70000)), n(GtD)]);
    assert!(x.status.rlo && x.status.cc1 && !x.status.cc0);
    // INT compares the low words only
    run(&mut x, vec![i(L, bits(0x0001_0005)), i(L, int(5)), n(EqI)]);
    assert!(x.status.rlo);
    run(&mut x, vec![i(L, bits(0x0001_0005)), i(L, int(5)), n(EqD)]);
    assert!(!x.status.rlo);
    // REAL; NaN
    run(&mut x, vec![i(L, real(1.5)), i(L, real(1.5)), n(GeR)]);
    assert!(x.status.rlo && !x.status.cc0 && !x.status.cc1);
    run(
        &mut x,
        vec![i(L, bits(0x7FC0_0000)), i(L, real(1.0)), n(NeR)],
    );
    assert!(!x.status.rlo && !x.status.sta);
    assert!(x.status.cc0 && x.status.cc1 && x.status.ov && x.status.os);
}

/// Runs `code` once per cycle of 10 ms from cycle `from` to `to`, returning the cycles in which
/// the final RLO was 1.
fn cycles(
    x: &mut higraph_runtime::machine::Machine,
    code: &[higraph_runtime::program::Instr],
    from: u64,
    to: u64,
    input: impl std::ops::Fn(u64) -> bool,
) -> Vec<u64> {
    let mut ones = Vec::new();
    for k in from..=to {
        x.now_ms = 10 * k;
        set_bit(x, 0, 0, input(k));
        if run(x, code.to_vec()) {
            ones.push(k);
        }
    }
    ones
}

#[test]
fn on_delay_example() {
    // runtime.md §3.3: SE with S5T#50MS first run with RLO = 1 in cycle k: U T reads 1 from
    // cycle k + 5.
    let mut x = machine();
    let code = vec![
        i(U, m(0, 0)),
        i(L, imm(Const::S5Time(50))),
        i(Se, t(1)),
        i(U, t(1)),
    ];
    let ones = cycles(&mut x, &code, 1, 12, |k| k >= 3);
    assert_eq!(ones, (8..=12).collect::<Vec<_>>());
    // RLO 0 resets it
    x.now_ms = 130;
    set_bit(&mut x, 0, 0, false);
    assert!(!run(&mut x, code.clone()));
    assert!(
        x.read(&higraph_runtime::program::Place::Timer(
            higraph_runtime::program::TimerId(1)
        ))
        .unwrap()
            == 0
    );
}

#[test]
fn pulse_timer() {
    let mut x = machine();
    let code = vec![
        i(U, m(0, 0)),
        i(L, imm(Const::S5Time(30))),
        i(Si, t(2)),
        i(U, t(2)),
    ];
    // input 1 in cycles 2..=10: Q in cycles 2, 3, 4 (expires at t = 50)
    assert_eq!(
        cycles(&mut x, &code, 1, 12, |k| (2..=10).contains(&k)),
        vec![2, 3, 4]
    );
    // input falling early ends the pulse
    let mut x = machine();
    assert_eq!(cycles(&mut x, &code, 1, 6, |k| k == 2), vec![2]);
}

#[test]
fn load_timer_value() {
    let mut x = machine();
    x.now_ms = 100;
    run(&mut x, vec![i(L, imm(Const::S5Time(2_500))), i(Se, t(3))]);
    x.now_ms = 1_000;
    run(&mut x, vec![i(L, t(3)), i(Lc, t(3))]);
    // 1600 ms remain at base 10 ms: 160; LC: 16#0160
    assert_eq!(x.accu2, 160);
    assert_eq!(x.accu1, 0x0160);
    x.now_ms = 2_600;
    run(&mut x, vec![i(L, t(3)), i(U, t(3))]);
    assert_eq!(x.accu1, 0);
    assert!(x.status.rlo);
}
