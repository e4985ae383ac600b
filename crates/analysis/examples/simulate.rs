//! Simulation speed (README, "Simulation speed"): the generated `max-group` workload (255
//! instances of 20 graphs, `tooling.md` §7) lowered with `lower_workspace` and simulated for
//! N group calls with varying inputs; the same STL run straight through by our interpreter and,
//! with `--awlsim PYTHON`, by Awlsim 0.77.1 in the same run; and the drilling example lowered
//! and simulated for 1 000 cycles end to end.
//!
//! `cargo run --release -p higraph-analysis --example simulate -- [--cycles N] [--seed S]
//! [--awlsim PYTHON] [--awl FILE]` (`scripts/bench-simulate` sets up Awlsim and runs it).
//!
//! How instructions are counted: `Machine::instructions`, which the interpreter advances by a
//! block's length when the block ends (STL blocks are straight-line, so that is exact) and
//! costs one addition per block, not per instruction.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::time::Instant;

use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};
use higraph_runtime::group::{self, GroupRt};
use higraph_runtime::program::{
    Block, Graph, Instr, MemArea, OpCode, Operand, Place, Predef, Program, Width,
};
use higraph_runtime::{Machine, Ty, stl};

/// The Awlsim side (`--awlsim`): loads the program text, runs OB 1 for at least `seconds`.
const AWLSIM_RUNNER: &str = r#"
import sys, time
from awlsim_loader.common import *
from awlsim_loader.core import *
from awlsim_loader.awlcompiler import *
path, per_cycle, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
t0 = time.time()
project = Project.fromProjectOrRawAwlData(open(path, "rb").read())
parser = AwlParser()
for s in project.getAwlSources():
    parser.parseSource(s)
sim = AwlSim()
sim.reset()
cpu = sim.getCPU()
cpu.getConf().setConfiguredMnemonics(S7CPUConfig.MNEMONICS_DE)
specs = cpu.getSpecs()
specs.setNrInputs(65536)
specs.setNrOutputs(65536)
specs.setNrFlags(65536)
specs.setNrTimers(2048)
specs.setNrCounters(2048)
sim.load(parser.getParseTree())
sim.build()
sim.startup()
load = time.time() - t0
sim.runCycle()
n = 0
t = time.time()
c = time.thread_time()
while True:
    sim.runCycle()
    n += 1
    s = time.time() - t
    if s >= seconds and n >= 3:
        break
cpu = time.thread_time() - c
total = n * per_cycle
print(n, s, cpu, total, load)
"#;

struct Args {
    cycles: u64,
    seed: u64,
    awlsim: Option<String>,
    awl: Option<String>,
    awlsim_seconds: f64,
    /// Profiling: `group` or `line` runs only that part.
    only: Option<String>,
}

fn args() -> Args {
    let mut a = Args {
        cycles: 10_000,
        seed: 1,
        awlsim: None,
        awl: None,
        awlsim_seconds: 20.0,
        only: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let v = it.next().unwrap_or_default();
        match k.as_str() {
            "--cycles" => a.cycles = v.parse().expect("--cycles N"),
            "--seed" => a.seed = v.parse().expect("--seed S"),
            "--awlsim" => a.awlsim = Some(v),
            "--awl" => a.awl = Some(v),
            "--only" => a.only = Some(v),
            "--awlsim-seconds" => a.awlsim_seconds = v.parse().expect("--awlsim-seconds S"),
            _ => panic!(
                "usage: simulate [--cycles N] [--seed S] [--awlsim PYTHON] [--awl FILE] \
                 [--awlsim-seconds S] [--only group|line]"
            ),
        }
    }
    a
}

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn host(files: Vec<(String, String)>) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    for (path, text) in files {
        if path.ends_with(".higraph") {
            data.files
                .push((path, FileContents::from_bytes(text.into_bytes())));
        } else if path.ends_with("higraph.toml") {
            data.config = Some((path, FileContents::from_bytes(text.into_bytes())));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

fn example_files(dir: &str) -> Vec<(String, String)> {
    let root = std::path::PathBuf::from(format!(
        "{}/../../examples/{dir}",
        env!("CARGO_MANIFEST_DIR")
    ));
    let mut files = Vec::new();
    let mut stack = vec![root.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("example directory") {
            let path = e.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let rel = path
                    .strip_prefix(&root)
                    .expect("inside")
                    .to_string_lossy()
                    .replace('\\', "/");
                files.push((rel, std::fs::read_to_string(&path).expect("readable")));
            }
        }
    }
    files.sort();
    files
}

/// The places the simulation drives: input and bit-memory bits and words bound to instances
/// (sensors, set points, parameters, external messages), except the two mode bits.
struct Stimulus {
    bits: Vec<Place>,
    words: Vec<Place>,
    auto: Place,
    manual: Place,
}

fn stimulus(p: &Program, group: usize) -> Stimulus {
    let g = &p.groups[group];
    let auto = g.instances[0].binding[Predef::AutomaticMode.var() as usize].clone();
    let manual = g.instances[0].binding[Predef::ManualMode.var() as usize].clone();
    let mut seen = std::collections::HashSet::new();
    let (mut bits, mut words) = (Vec::new(), Vec::new());
    for inst in &g.instances {
        for place in &inst.binding[Predef::ALL.len().min(inst.binding.len())..] {
            let Place::Mem { area, byte, width } = place else {
                continue;
            };
            if !matches!(area, MemArea::Input | MemArea::Memory)
                || *place == auto
                || *place == manual
                || !seen.insert((*area, *byte, *width))
            {
                continue;
            }
            match width {
                Width::Bit(_) => bits.push(place.clone()),
                Width::Word => words.push(place.clone()),
                _ => {}
            }
        }
    }
    Stimulus {
        bits,
        words,
        auto,
        manual,
    }
}

struct GroupRun {
    cycles: u64,
    instances: usize,
    seconds: f64,
    /// The same in this thread's CPU time.
    cpu: f64,
    instructions: u64,
    changes: u64,
    faults: u64,
    first_fault: Option<String>,
}

/// `cycles` group calls; per cycle the clock advances by Δ and a few stimulus places change.
/// Only the calls and the input writes are timed.
fn run_group(p: &Program, group: usize, cycles: u64, seed: u64) -> GroupRun {
    let st = stimulus(p, group);
    let mut m = Machine::new(p);
    let mut rt = GroupRt::new();
    let dt = group::DEFAULT_CYCLE_MS as u64;
    let mut rng = Rng(seed);
    let insts = &p.groups[group].instances;
    let change_places: Vec<&Place> = insts
        .iter()
        .map(|i| &i.binding[Predef::StateChange.var() as usize])
        .collect();
    m.write(&st.auto, 1).expect("mode bit");
    let (mut changes, mut faults, mut first_fault) = (0u64, 0u64, None);
    let (mut seconds, mut cpu) = (0.0, 0.0);
    for k in 0..cycles {
        let c = cpu_now();
        let t = Instant::now();
        m.now_ms += dt;
        // A few sensors change every cycle, a set point every tenth; manual mode now and then.
        for _ in 0..8 {
            if !st.bits.is_empty() {
                let pl = &st.bits[rng.below(st.bits.len())];
                let v = (rng.next() & 1) as u32;
                m.write(pl, v).expect("stimulus bit");
            }
        }
        if k % 10 == 0 && !st.words.is_empty() {
            let pl = &st.words[rng.below(st.words.len())];
            m.write(pl, rng.below(200) as u32).expect("stimulus word");
        }
        if k % 500 == 499 {
            let manual = rng.below(4) == 0;
            m.write(&st.manual, manual as u32).expect("mode bit");
            m.write(&st.auto, !manual as u32).expect("mode bit");
        }
        let r = group::call(&mut m, p, group as u32, &mut rt, false, None);
        seconds += t.elapsed().as_secs_f64();
        cpu += cpu_now() - c;
        if let Err(f) = r {
            faults += 1;
            first_fault.get_or_insert(f.reason);
        }
        if k > 0 {
            for pl in &change_places {
                changes += u64::from(m.read(pl).unwrap_or(0) & 1);
            }
        }
    }
    GroupRun {
        cycles,
        instances: insts.len(),
        seconds,
        cpu,
        instructions: m.instructions,
        changes,
        faults,
        first_fault,
    }
}

// ------------------------------------------------------------------------- straight-line code

/// Every instruction block of every instance, in run order, with the instance's binding.
fn all_blocks(p: &Program, group: usize) -> Vec<(&[Place], &Block)> {
    fn push<'p>(out: &mut Vec<(&'p [Place], &'p Block)>, b: &'p [Place], blocks: &'p [Block]) {
        for blk in blocks {
            if !blk.code.is_empty() {
                out.push((b, blk));
            }
        }
    }
    let mut out = Vec::new();
    for inst in &p.groups[group].instances {
        let g: &Graph = &p.graphs[inst.graph as usize];
        let b = &inst.binding[..];
        push(&mut out, b, &g.permanent_pre);
        for t in &g.any {
            push(&mut out, b, &t.conditions);
            push(&mut out, b, &t.actions);
        }
        for s in &g.states {
            push(&mut out, b, &s.entry);
            push(&mut out, b, &s.pre);
            for t in &s.transitions {
                push(&mut out, b, &t.conditions);
                push(&mut out, b, &t.actions);
            }
            push(&mut out, b, &s.cyclic);
            push(&mut out, b, &s.exit);
        }
        push(&mut out, b, &g.permanent_post);
    }
    out
}

/// Writes STL as Awlsim reads it (SIMATIC/German mnemonics): global places as addresses,
/// cells of instances in one data block, private timers and counters from number 1000 up.
struct Awl {
    cell_db: u16,
    cells: HashMap<u32, (u32, Width)>,
    next_bit: u32,
    next_byte: u32,
    dbs: BTreeMap<u16, u32>,
    cell_ty: Vec<Ty>,
}

impl Awl {
    fn new(p: &Program) -> Awl {
        Awl {
            cell_db: 900,
            cells: HashMap::new(),
            next_bit: 0,
            next_byte: 8192,
            dbs: BTreeMap::new(),
            cell_ty: p.cells.iter().map(|c| c.ty).collect(),
        }
    }

    fn mem(&mut self, area: MemArea, byte: u32, width: Width) -> String {
        let (pre, db) = match area {
            MemArea::Input => ("E", false),
            MemArea::Output => ("A", false),
            MemArea::Memory => ("M", false),
            MemArea::Local => ("L", false),
            MemArea::Db(n) => {
                let e = self.dbs.entry(n).or_insert(0);
                *e = (*e).max(byte + 4);
                return match width {
                    Width::Bit(x) => format!("DB{n}.DBX {byte}.{x}"),
                    Width::Byte => format!("DB{n}.DBB {byte}"),
                    Width::Word => format!("DB{n}.DBW {byte}"),
                    Width::Dword => format!("DB{n}.DBD {byte}"),
                };
            }
        };
        let _ = db;
        match width {
            Width::Bit(x) => format!("{pre} {byte}.{x}"),
            Width::Byte => format!("{pre}B {byte}"),
            Width::Word => format!("{pre}W {byte}"),
            Width::Dword => format!("{pre}D {byte}"),
        }
    }

    /// A cell (or a constant actual) as a slot of the cells' data block.
    fn cell(&mut self, key: u32, ty: Ty) -> String {
        let (byte, width) = match self.cells.get(&key) {
            Some(&s) => s,
            None => {
                let s = match ty.bits() {
                    Some(1) => {
                        let b = self.next_bit;
                        self.next_bit += 1;
                        (b / 8, Width::Bit((b % 8) as u8))
                    }
                    Some(8) => {
                        self.next_byte += 1;
                        (self.next_byte - 1, Width::Byte)
                    }
                    Some(16) => {
                        self.next_byte += 2;
                        (self.next_byte - 2, Width::Word)
                    }
                    _ => {
                        self.next_byte += 4;
                        (self.next_byte - 4, Width::Dword)
                    }
                };
                assert!(self.next_bit / 8 < 8192, "too many BOOL cells");
                self.cells.insert(key, s);
                s
            }
        };
        self.mem(MemArea::Db(self.cell_db), byte, width)
    }

    fn place(&mut self, place: &Place) -> String {
        match place {
            Place::Mem { area, byte, width } => self.mem(*area, *byte, *width),
            Place::Cell(id) => {
                let ty = self.cell_ty.get(*id as usize).copied().unwrap_or(Ty::Dword);
                self.cell(*id, ty)
            }
            Place::Timer(t) => format!("T {}", map_object(t.0)),
            Place::Counter(c) => format!("Z {}", map_object(c.0)),
            // A constant actual: a slot of its own (reads give its initial value, zero here;
            // the instructions are the same).
            Place::Const(v) => self.cell(0x8000_0000 | self.cells.len() as u32, v.ty()),
        }
    }

    fn operand(&mut self, binding: &[Place], ins: &Instr) -> String {
        use OpCode::*;
        match &ins.operand {
            Operand::None => String::new(),
            Operand::Var(i) => match binding.get(*i as usize) {
                Some(Place::Const(v)) if ins.op == L => {
                    format!("DW#16#{:X}", v.to_bits().unwrap_or(0))
                }
                Some(p) => self.place(p),
                None => panic!("unbound variable {i}"),
            },
            Operand::Place(Place::Const(v)) if ins.op == L => {
                format!("DW#16#{:X}", v.to_bits().unwrap_or(0))
            }
            Operand::Place(p) => self.place(p),
            Operand::Imm(n) => match ins.op {
                L => format!("DW#16#{n:X}"),
                AddInt => format!("{}", *n as u16 as i16),
                AddDint => format!("L#{}", *n as i32),
                Uw | Ow | Xow => format!("W#16#{:X}", n & 0xFFFF),
                Ud | Od | Xod => format!("DW#16#{n:X}"),
                _ => format!("{n}"),
            },
            Operand::Call(_) => panic!("CALL in the benchmark code"),
        }
    }

    fn instr(&mut self, binding: &[Place], ins: &Instr) -> String {
        let m = mnemonic(ins.op);
        let o = self.operand(binding, ins);
        if o.is_empty() {
            m.to_owned()
        } else {
            format!("{m} {o}")
        }
    }

    fn program(&mut self, blocks: &[(&[Place], &Block)]) -> (String, u64) {
        let mut ob = String::new();
        let mut n = 0u64;
        for (b, blk) in blocks {
            // Our blocks start with a fresh logic operation and RLO = 1 (§3.1): SET does that.
            ob.push_str("\tSET\n");
            n += 1;
            for ins in &blk.code {
                let line = self.instr(b, ins);
                writeln!(ob, "\t{line}").expect("string");
                n += 1;
            }
        }
        let mut src = format!("ORGANIZATION_BLOCK OB 1\nBEGIN\n{ob}END_ORGANIZATION_BLOCK\n\n");
        let cell_bytes = self.next_byte.max(8192 + 4);
        let e = self.dbs.entry(self.cell_db).or_insert(0);
        *e = (*e).max(cell_bytes);
        for (db, size) in &self.dbs {
            write!(
                src,
                "DATA_BLOCK DB {db}\nSTRUCT\n a : ARRAY [0..{}] OF BYTE;\nEND_STRUCT;\nBEGIN\nEND_DATA_BLOCK\n\n",
                size - 1
            )
            .expect("string");
        }
        (src, n)
    }
}

/// Private timer/counter objects (65536 + i) as T/Z 1000 + i; the others as they are.
fn map_object(id: u32) -> u32 {
    if id >= 65536 { 1000 + id - 65536 } else { id }
}

fn mnemonic(op: OpCode) -> &'static str {
    use OpCode::*;
    match op {
        U => "U",
        Un => "UN",
        O => "O",
        On => "ON",
        X => "X",
        Xn => "XN",
        OrNone => "O",
        UParen => "U(",
        UnParen => "UN(",
        OParen => "O(",
        OnParen => "ON(",
        XParen => "X(",
        XnParen => "XN(",
        Close => ")",
        Assign => "=",
        S => "S",
        R => "R",
        Set => "SET",
        Clr => "CLR",
        Not => "NOT",
        Fp => "FP",
        Fn => "FN",
        Si => "SI",
        Sv => "SV",
        Se => "SE",
        Ss => "SS",
        Sa => "SA",
        Fr => "FR",
        Zv => "ZV",
        Zr => "ZR",
        L => "L",
        Lc => "LC",
        T => "T",
        Tak => "TAK",
        Push => "PUSH",
        Pop => "POP",
        Inc => "INC",
        Dec => "DEC",
        AddInt | AddDint => "+",
        Taw => "TAW",
        Tad => "TAD",
        Tar => "TAR",
        Tar1 => "TAR1",
        Tar2 => "TAR2",
        Uw => "UW",
        Ow => "OW",
        Xow => "XOW",
        Ud => "UD",
        Od => "OD",
        Xod => "XOD",
        EqI => "==I",
        NeI => "<>I",
        GtI => ">I",
        LtI => "<I",
        GeI => ">=I",
        LeI => "<=I",
        EqD => "==D",
        NeD => "<>D",
        GtD => ">D",
        LtD => "<D",
        GeD => ">=D",
        LeD => "<=D",
        EqR => "==R",
        NeR => "<>R",
        GtR => ">R",
        LtR => "<R",
        GeR => ">=R",
        LeR => "<=R",
        AddI => "+I",
        SubI => "-I",
        MulI => "*I",
        DivI => "/I",
        AddD => "+D",
        SubD => "-D",
        MulD => "*D",
        DivD => "/D",
        Mod => "MOD",
        NegI => "NEGI",
        NegD => "NEGD",
        AddR => "+R",
        SubR => "-R",
        MulR => "*R",
        DivR => "/R",
        Abs => "ABS",
        Sqr => "SQR",
        Sqrt => "SQRT",
        Exp => "EXP",
        Ln => "LN",
        Sin => "SIN",
        Cos => "COS",
        Tan => "TAN",
        Asin => "ASIN",
        Acos => "ACOS",
        Atan => "ATAN",
        NegR => "NEGR",
        Slw => "SLW",
        Srw => "SRW",
        Sld => "SLD",
        Srd => "SRD",
        Ssi => "SSI",
        Ssd => "SSD",
        Rld => "RLD",
        Rrd => "RRD",
        Rlda => "RLDA",
        Rrda => "RRDA",
        Bti => "BTI",
        Btd => "BTD",
        Itb => "ITB",
        Dtb => "DTB",
        Itd => "ITD",
        Dtr => "DTR",
        Invi => "INVI",
        Invd => "INVD",
        Rnd => "RND",
        RndPlus => "RND+",
        RndMinus => "RND-",
        Trunc => "TRUNC",
        Call => "CALL",
        Cc => "CC",
    }
}

/// An instruction block with the binding of the instance that runs it.
type BoundBlock<'p> = (&'p [Place], &'p Block);

/// Our interpreter on the straight-line code: every block once per pass, for at least
/// `min_seconds`. Blocks that fault on the first pass are left out (of Awlsim's code too).
fn straight_line<'p>(
    p: &Program,
    blocks: Vec<BoundBlock<'p>>,
    min_seconds: f64,
    min_passes: u64,
) -> (Vec<BoundBlock<'p>>, u64, f64, f64) {
    let mut m = Machine::new(p);
    let mut kept = Vec::with_capacity(blocks.len());
    for (b, blk) in blocks {
        if stl::run_block(&mut m, b, blk, false).is_ok() {
            kept.push((b, blk));
        }
    }
    let mut m = Machine::new(p);
    let c = cpu_now();
    let start = Instant::now();
    let mut passes = 0u64;
    loop {
        m.now_ms += 10;
        m.begin_group_call();
        for (b, blk) in &kept {
            let _ = stl::run_block(&mut m, b, blk, false);
        }
        passes += 1;
        if start.elapsed().as_secs_f64() >= min_seconds && passes >= min_passes {
            break;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    (kept, m.instructions, wall, cpu_now() - c)
}

/// This thread's CPU time in seconds (wall time where there is no such clock).
#[cfg(unix)]
fn cpu_now() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec it is given.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

#[cfg(not(unix))]
fn cpu_now() -> f64 {
    use std::sync::OnceLock;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

/// `n` per second by wall time and by CPU time.
fn rates(n: f64, wall: f64, cpu: f64) -> String {
    format!(
        "{:.2} M (wall), {:.2} M (CPU)",
        n / wall / 1e6,
        n / cpu / 1e6
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let a = args();

    // ---------------------------------------------------------------- max-group
    let t = Instant::now();
    let files = higraph_workload::max_group(a.seed);
    let h = host(files);
    let lowered = h.analysis().lower_workspace().expect("not cancelled");
    let lower_s = t.elapsed().as_secs_f64();
    let p = &lowered.program;
    let group = p
        .groups
        .iter()
        .position(|g| g.instances.len() == 255)
        .expect("max-group has a group of 255 instances");
    let cycles = if a.only.as_deref() == Some("line") {
        1
    } else {
        a.cycles
    };
    let r = run_group(p, group, cycles, a.seed);
    let turns = r.cycles as f64 * r.instances as f64;
    println!(
        "max-group (seed {}): {} graphs, {} instances; generation, analysis and lowering {:.0} ms",
        a.seed,
        p.graphs.len(),
        r.instances,
        lower_s * 1e3
    );
    println!(
        "  {} cycles in {:.3} s ({:.3} s CPU): {:.1} instructions per turn, {:.2} state changes \
         per cycle, {} faulting calls{}",
        r.cycles,
        r.seconds,
        r.cpu,
        r.instructions as f64 / turns,
        r.changes as f64 / (r.cycles.max(2) - 1) as f64,
        r.faults,
        r.first_fault
            .as_deref()
            .map(|f| format!(": {f}"))
            .unwrap_or_default()
    );
    println!(
        "  instance turns/s:          {}",
        rates(turns, r.seconds, r.cpu)
    );
    println!(
        "  STL instructions/s:        {}",
        rates(r.instructions as f64, r.seconds, r.cpu)
    );

    if a.only.as_deref() == Some("group") {
        return;
    }
    // ---------------------------------------------------------------- straight-line STL
    let blocks = all_blocks(p, group);
    let (kept, ours_n, ours_s, ours_cpu) = if a.only.is_some() {
        straight_line(p, blocks, 0.0, 20)
    } else {
        straight_line(p, blocks, 2.0, 3)
    };
    let (src, awl_per_cycle) = Awl::new(p).program(&kept);
    let code_n: usize = kept.iter().map(|(_, b)| b.code.len()).sum();
    println!(
        "  straight-line STL, every block of every instance once per pass ({} blocks, {} \
         instructions):",
        kept.len(),
        code_n
    );
    println!(
        "    ours:   {} instructions/s",
        rates(ours_n as f64, ours_s, ours_cpu)
    );
    if let Some(path) = &a.awl {
        std::fs::write(path, &src).expect("write --awl file");
    }
    if a.only.is_some() {
        return;
    }
    // One line for scripts/bench-simulate: rates in millions per second.
    let mut summary = format!(
        "summary turns_wall={:.3} turns_cpu={:.3} stl_wall={:.3} stl_cpu={:.3} line_wall={:.3} \
         line_cpu={:.3}",
        turns / r.seconds / 1e6,
        turns / r.cpu / 1e6,
        r.instructions as f64 / r.seconds / 1e6,
        r.instructions as f64 / r.cpu / 1e6,
        ours_n as f64 / ours_s / 1e6,
        ours_n as f64 / ours_cpu / 1e6
    );
    if let Some(python) = &a.awlsim {
        let path =
            std::env::temp_dir().join(format!("higraph-simulate-{}.awl", std::process::id()));
        std::fs::write(&path, &src).expect("write the Awlsim program");
        let out = std::process::Command::new(python)
            .arg("-c")
            .arg(AWLSIM_RUNNER)
            .arg(&path)
            .arg(awl_per_cycle.to_string())
            .arg(a.awlsim_seconds.to_string())
            .output()
            .expect("run Awlsim's python");
        let _ = std::fs::remove_file(&path);
        let stdout = String::from_utf8_lossy(&out.stdout);
        let Some(line) = stdout.lines().last().filter(|_| out.status.success()) else {
            panic!(
                "Awlsim failed:\n{}\n{}",
                stdout,
                String::from_utf8_lossy(&out.stderr)
            );
        };
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        let [cycles, secs, cpu, _, load] = f[..] else {
            panic!("Awlsim said {line}");
        };
        // Counted as the same instructions ours executes: the SET opening each block does
        // what our block start does and is not counted on either side.
        let n = cycles * code_n as f64;
        println!(
            "    Awlsim: {} instructions/s (0.77.1; one OB 1 of {awl_per_cycle} lines, a SET \
             opening each block; loading {load:.1} s; {cycles} cycles)",
            rates(n, secs, cpu)
        );
        println!(
            "  ratio by CPU time: {:.0}x (group simulation / Awlsim), {:.0}x (straight-line / \
             Awlsim)",
            r.instructions as f64 / r.cpu / (n / cpu),
            ours_n as f64 / ours_cpu / (n / cpu)
        );
        write!(
            summary,
            " awlsim_wall={:.4} awlsim_cpu={:.4} ratio_group={:.1} ratio_line={:.1}",
            n / secs / 1e6,
            n / cpu / 1e6,
            r.instructions as f64 / r.cpu / (n / cpu),
            ours_n as f64 / ours_cpu / (n / cpu)
        )
        .expect("string");
    }

    // ---------------------------------------------------------------- drilling, end to end
    let files = example_files("drilling");
    let mut cold = Vec::new();
    let mut warm = Vec::new();
    for _ in 0..11 {
        let t = Instant::now();
        let h = host(files.clone());
        let c = drilling(&h);
        cold.push(t.elapsed().as_secs_f64());
        // As in the editor: the workspace is analysed already, the code lens runs the test.
        let _ = h.analysis().diagnostics();
        let t = Instant::now();
        let w = drilling(&h);
        warm.push(t.elapsed().as_secs_f64());
        assert_eq!(c, w);
    }
    println!(
        "drilling: lowering + 1000 cycles {:.2} ms on an analysed workspace (editor), {:.2} ms \
         from the files (parse, analyse, lower, run); medians of 11",
        median(warm.clone()) * 1e3,
        median(cold.clone()) * 1e3
    );
    println!(
        "{summary} drilling_warm_ms={:.3} drilling_cold_ms={:.3}",
        median(warm) * 1e3,
        median(cold) * 1e3
    );
}

/// Lowers the drilling example and runs 1000 cycles of its group with the start button
/// pressed and the sensors following the actuators a cycle later; returns the state changes.
fn drilling(h: &AnalysisHost) -> u64 {
    let lowered = h.analysis().lower_workspace().expect("not cancelled");
    let p = &lowered.program;
    let mut m = Machine::new(p);
    let mut rt = GroupRt::new();
    let st = stimulus(p, 0);
    let mut rng = Rng(7);
    let _ = m.write(&st.auto, 1);
    let changes: Vec<&Place> = p.groups[0]
        .instances
        .iter()
        .map(|i| &i.binding[Predef::StateChange.var() as usize])
        .collect();
    let mut n = 0u64;
    for _ in 0..1000 {
        m.now_ms += group::DEFAULT_CYCLE_MS as u64;
        if !st.bits.is_empty() {
            let pl = &st.bits[rng.below(st.bits.len())];
            let _ = m.write(pl, (rng.next() & 1) as u32);
        }
        let _ = group::call(&mut m, p, 0, &mut rt, false, None);
        for pl in &changes {
            n += u64::from(m.read(pl).unwrap_or(0) & 1);
        }
    }
    n
}
