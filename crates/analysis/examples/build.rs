//! Build speed and code size (README, "Build speed and code size"; issue 13 "Performance"):
//! `Analysis::build` of the generated `plant` workload (300 graphs in 20 groups, 10 charts,
//! `tooling.md` §7).
//!
//! `cargo run --release -p higraph-analysis --example build -- [--seed S] [--runs N]
//! [--out DIR] [--absolute]` (`scripts/bench-build` runs it and adds Awlsim's instruction
//! counts).
//!
//! What it measures:
//!
//! * **time**: a cold build per target (a fresh database: parse, analyse, check the items,
//!   generate) and the median of `--runs` further builds on the same database (analysis
//!   cached, so mostly generation), and a cold `check` of the same workload for comparison;
//! * **output**: the bytes of each kind of file (`.awl`, `charts.xml`, `symbols.sdf`);
//! * **code size** of each group's FC, estimated like the original manual does (§7.3 of the
//!   HiGraph manual, `facts-higraph.md` C.5): *our* FC's STL statements — in the FC's body
//!   (`BEGIN` … `END_FUNCTION`), every statement ending in `;` outside comments, so a `CALL`
//!   with its parameter lines is one — times 4.3 bytes, against the original compiler's
//!   formula for the same group (34 or 82 bytes per group, 52 per graph + 22/56/60 for wait
//!   times/supervision/message states, 16 per state + 8/8 for wait/supervision, 20 per
//!   transition + 8 wait + 8 mode + 4 with code, 24 per any or return transition + 12 wait +
//!   8 mode + 4 with code, and 4.3 bytes per STL instruction the user wrote). The original
//!   substitutes actual parameters into the code as we do, so its formula is applied once per
//!   *instance*. Standard diagnostics (which add to the original) are not counted.
//!
//! With `--out DIR` the files are also written there (for `scripts/bench-build`'s Awlsim
//! count, with `--absolute`, since Awlsim reads no symbol table).

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use higraph_analysis::build::{BuildOptions, BuildResult, Target};
use higraph_analysis::{AnalysisHost, FileContents, Severity, WorkspaceData};
use higraph_runtime::program::{Block, Graph, Program, Target as TransTarget, Trans};

/// Bytes per STL instruction in MC7, the original manual's average.
const BYTES_PER_INSTRUCTION: f64 = 4.3;

struct Args {
    seed: u64,
    runs: usize,
    out: Option<String>,
    absolute: bool,
}

fn args() -> Args {
    let mut a = Args {
        seed: 1,
        runs: 5,
        out: None,
        absolute: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--seed" => a.seed = it.next().and_then(|v| v.parse().ok()).unwrap_or(1),
            "--runs" => a.runs = it.next().and_then(|v| v.parse().ok()).unwrap_or(5).max(1),
            "--out" => a.out = it.next(),
            "--absolute" => a.absolute = true,
            _ => {
                eprintln!(
                    "usage: build [--seed S] [--runs N] [--out DIR] [--absolute]  (got {arg})"
                );
                std::process::exit(2);
            }
        }
    }
    a
}

fn host(files: &[(String, String)]) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    for (path, text) in files {
        if path.ends_with(".higraph") {
            data.files.push((
                path.clone(),
                FileContents::from_bytes(text.clone().into_bytes()),
            ));
        } else if path.ends_with("higraph.toml") {
            data.config = Some((
                path.clone(),
                FileContents::from_bytes(text.clone().into_bytes()),
            ));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1000.0
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One target: the cold build, the median of the warm ones, the result of the last.
fn measure(
    files: &[(String, String)],
    options: &BuildOptions,
    runs: usize,
) -> (f64, f64, BuildResult) {
    let host = host(files);
    let analysis = host.analysis();
    let t = Instant::now();
    let Ok(first) = analysis.build(&[], options) else {
        eprintln!("build: cancelled");
        std::process::exit(1);
    };
    let cold = ms(t.elapsed());
    let mut warm = Vec::new();
    let mut last = first;
    for _ in 0..runs {
        let t = Instant::now();
        let Ok(r) = analysis.build(&[], options) else {
            eprintln!("build: cancelled");
            std::process::exit(1);
        };
        warm.push(ms(t.elapsed()));
        last = r;
    }
    (cold, median(warm), last)
}

fn report_refusal(target: &str, r: &BuildResult) {
    eprintln!(
        "build ({target}) refused: errors in {} file(s): {}",
        r.refused.len(),
        r.refused.join(", ")
    );
    for (path, d) in r
        .diagnostics
        .iter()
        .filter(|(_, d)| d.severity == Severity::Error)
        .take(10)
    {
        eprintln!("  {path}: {:?} {}", d.code, d.message);
    }
}

// ------------------------------------------------------------------------ counting our code

/// The STL statements of the FC bodies of one STEP 7 source: after `BEGIN` of a `FUNCTION`
/// up to `END_FUNCTION`, every `;` that ends a statement (outside `//` comments and quoted
/// names/strings). Returns one count per FC, in file order.
fn fc_statements(source: &[u8]) -> Vec<usize> {
    // Windows-1252: every byte a character; only ASCII matters here.
    let text: String = source
        .iter()
        .map(|&b| if b.is_ascii() { b as char } else { '?' })
        .collect();
    let mut counts = Vec::new();
    let mut in_fc = false;
    let mut in_body = false;
    let mut n = 0;
    for raw in text.lines() {
        let line = strip_comment(raw);
        let word = line.split_whitespace().next().unwrap_or("");
        if !in_fc {
            if word.eq_ignore_ascii_case("FUNCTION") {
                in_fc = true;
                in_body = false;
                n = 0;
            }
            continue;
        }
        if word.eq_ignore_ascii_case("END_FUNCTION") {
            counts.push(n);
            in_fc = false;
            continue;
        }
        if !in_body {
            in_body = word.eq_ignore_ascii_case("BEGIN");
            continue;
        }
        n += line.matches(';').count();
    }
    counts
}

/// The line without its `//` comment, and with quoted names and strings blanked (a `;` or
/// `//` inside quotes is no statement end and no comment).
fn strip_comment(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut quote: Option<char> = None;
    let mut prev = '\0';
    for c in line.chars() {
        match quote {
            Some(q) => {
                if c == q {
                    quote = None;
                }
                out.push(' ');
            }
            None => {
                if c == '/' && prev == '/' {
                    out.pop();
                    break;
                }
                if c == '"' || c == '\'' {
                    quote = Some(c);
                    out.push(' ');
                } else {
                    out.push(c);
                }
            }
        }
        prev = c;
    }
    out
}

// ------------------------------------------------------------- the original compiler's formula

fn instrs(blocks: &[Block]) -> usize {
    blocks.iter().map(|b| b.code.len()).sum()
}

fn trans_bytes(t: &Trans, any_or_return: bool) -> f64 {
    let code = instrs(&t.conditions) + instrs(&t.actions);
    let (fixed, wait) = if any_or_return {
        (24.0, 12.0)
    } else {
        (20.0, 8.0)
    };
    let mut b = fixed;
    if t.waits {
        b += wait;
    }
    if t.auto || t.manual {
        b += 8.0;
    }
    if code > 0 {
        b += 4.0 + BYTES_PER_INSTRUCTION * code as f64;
    }
    b
}

/// The original FC bytes of one graph (C.5.1), and the STL instructions the user wrote in it.
fn graph_bytes(g: &Graph) -> (f64, usize) {
    let mut b = 52.0;
    if g.states.iter().any(|s| s.wait.is_some()) {
        b += 22.0;
    }
    if g.states.iter().any(|s| s.supervise.is_some()) {
        b += 56.0;
    }
    if g.states.iter().any(|s| s.reports) {
        b += 60.0;
    }
    let mut user = instrs(&g.permanent_pre) + instrs(&g.permanent_post);
    b += BYTES_PER_INSTRUCTION * user as f64;
    for s in &g.states {
        b += 16.0;
        if s.wait.is_some() {
            b += 8.0;
        }
        if s.supervise.is_some() {
            b += 8.0;
        }
        let code = instrs(&s.entry) + instrs(&s.pre) + instrs(&s.cyclic) + instrs(&s.exit);
        b += BYTES_PER_INSTRUCTION * code as f64;
        user += code;
        for t in &s.transitions {
            b += trans_bytes(t, matches!(t.to, TransTarget::Return));
            user += instrs(&t.conditions) + instrs(&t.actions);
        }
    }
    for t in &g.any {
        b += trans_bytes(t, true);
        user += instrs(&t.conditions) + instrs(&t.actions);
    }
    (b, user)
}

struct Original {
    bytes: f64,
    instances: usize,
    states: usize,
    transitions: usize,
    user_instructions: usize,
}

/// The original formula for each group of the program, by group name.
fn original(program: &Program) -> BTreeMap<String, Original> {
    let mut out = BTreeMap::new();
    for group in &program.groups {
        let graphs: Vec<&Graph> = group
            .instances
            .iter()
            .filter_map(|i| program.graphs.get(i.graph as usize))
            .collect();
        let timed = graphs.iter().any(|g| {
            g.states
                .iter()
                .any(|s| s.wait.is_some() || s.supervise.is_some())
        });
        let mut o = Original {
            bytes: if timed { 82.0 } else { 34.0 },
            instances: graphs.len(),
            states: 0,
            transitions: 0,
            user_instructions: 0,
        };
        for g in graphs {
            let (b, user) = graph_bytes(g);
            o.bytes += b;
            o.user_instructions += user;
            o.states += g.states.len();
            o.transitions +=
                g.any.len() + g.states.iter().map(|s| s.transitions.len()).sum::<usize>();
        }
        out.insert(group.name.clone(), o);
    }
    out
}

// ----------------------------------------------------------------------------------- main

fn main() {
    let a = args();
    let files = higraph_workload::plant(a.seed);
    let input_bytes: usize = files.iter().map(|(_, t)| t.len()).sum();
    println!(
        "== plant (seed {}): {} files, {:.2} MB of text; {} warm runs",
        a.seed,
        files.len(),
        input_bytes as f64 / 1e6,
        a.runs
    );

    // A cold check, for comparison: what `build` costs on top of the analysis.
    let t = Instant::now();
    let checked = host(&files).analysis().diagnostics();
    let check_ms = ms(t.elapsed());
    let errors: usize = checked
        .iter()
        .flat_map(|(_, ds)| ds.iter())
        .filter(|d| d.severity == Severity::Error)
        .count();
    println!("check (cold)               {check_ms:9.1} ms   ({errors} error(s) in the workload)");

    // The original compiler's formula, from the lowered groups (what the simulator runs).
    let Ok(lowered) = host(&files).analysis().lower_workspace() else {
        eprintln!("lowering cancelled");
        std::process::exit(1);
    };
    let orig = original(&lowered.program);
    let (n, b) = orig
        .values()
        .fold((0, 0.0), |(n, b), o| (n + o.instances, b + o.bytes));
    println!(
        "original formula: {} group(s), {n} instance(s), {b:.0} bytes of FC, {:.0} per instance",
        orig.len(),
        b / n.max(1) as f64
    );

    let mut summary = vec![format!("check_cold_ms={check_ms:.1}")];
    let mut awl_result = None;
    for (label, target) in [("awl", Target::Awl), ("plcopen", Target::Plcopen)] {
        let options = BuildOptions {
            target,
            with_ob1: false,
            absolute: a.absolute,
        };
        let (cold, warm, result) = measure(&files, &options, a.runs);
        if !result.refused.is_empty() {
            report_refusal(label, &result);
        }
        let bytes: usize = result.files.iter().map(|f| f.bytes.len()).sum();
        println!(
            "build --target {label:<8} cold {cold:9.1} ms, again {warm:8.1} ms; {} group(s), {} chart(s), {} file(s), {:.2} MB",
            result.groups,
            result.charts,
            result.files.len(),
            bytes as f64 / 1e6
        );
        summary.push(format!("{label}_cold_ms={cold:.1}"));
        summary.push(format!("{label}_warm_ms={warm:.1}"));
        summary.push(format!("{label}_bytes={bytes}"));
        if let Some(dir) = &a.out {
            write_files(dir, &result);
        }
        if target == Target::Awl {
            awl_result = Some(result);
        }
    }

    // Output by kind of file.
    let Some(awl) = awl_result else { return };
    let mut kinds: BTreeMap<&str, (usize, usize)> = BTreeMap::new();
    for f in &awl.files {
        let kind = f.name.rsplit_once('.').map_or("", |(_, e)| e);
        let e = kinds.entry(kind).or_default();
        e.0 += 1;
        e.1 += f.bytes.len();
    }
    for (kind, (n, b)) in &kinds {
        println!("  .{kind:<4} {n:4} file(s) {:10} bytes", b);
    }

    // Code size per group and per instance.
    println!();
    println!(
        "{:<14} {:>5} {:>6} {:>6} {:>8} {:>9} {:>10} {:>10} {:>6}",
        "group",
        "inst",
        "states",
        "trans",
        "user STL",
        "our STL",
        "our bytes",
        "orig bytes",
        "ratio"
    );
    let (mut t_inst, mut t_user, mut t_ours, mut t_orig) = (0usize, 0usize, 0usize, 0.0f64);
    let mut missing = 0;
    for (name, o) in &orig {
        let file = awl.files.iter().find(|f| f.name == format!("{name}.awl"));
        let Some(file) = file else {
            missing += 1;
            continue;
        };
        let ours: usize = fc_statements(&file.bytes).iter().sum();
        let ours_bytes = ours as f64 * BYTES_PER_INSTRUCTION;
        println!(
            "{:<14} {:>5} {:>6} {:>6} {:>8} {:>9} {:>10.0} {:>10.0} {:>6.2}",
            name,
            o.instances,
            o.states,
            o.transitions,
            o.user_instructions,
            ours,
            ours_bytes,
            o.bytes,
            ours_bytes / o.bytes
        );
        t_inst += o.instances;
        t_user += o.user_instructions;
        t_ours += ours;
        t_orig += o.bytes;
    }
    if missing > 0 {
        println!("({missing} group(s) without a generated .awl)");
    }
    if t_inst == 0 {
        return;
    }
    let ours_bytes = t_ours as f64 * BYTES_PER_INSTRUCTION;
    println!(
        "{:<14} {:>5} {:>6} {:>6} {:>8} {:>9} {:>10.0} {:>10.0} {:>6.2}",
        "total",
        t_inst,
        "",
        "",
        t_user,
        t_ours,
        ours_bytes,
        t_orig,
        ours_bytes / t_orig
    );
    println!(
        "per instance: our FC {:.0} STL statements ≈ {:.0} bytes of MC7; the original's formula {:.0} bytes; ratio {:.2}",
        t_ours as f64 / t_inst as f64,
        ours_bytes / t_inst as f64,
        t_orig / t_inst as f64,
        ours_bytes / t_orig
    );
    summary.push(format!("instances={t_inst}"));
    summary.push(format!("user_stl={t_user}"));
    summary.push(format!("our_stl={t_ours}"));
    summary.push(format!("orig_bytes={t_orig:.0}"));
    summary.push(format!("ratio={:.3}", ours_bytes / t_orig));
    println!("summary {}", summary.join(" "));
}

fn write_files(dir: &str, r: &BuildResult) {
    let dir = std::path::Path::new(dir);
    if let Err(e) = std::fs::create_dir_all(dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        std::process::exit(2);
    }
    for f in &r.files {
        if let Err(e) = std::fs::write(dir.join(&f.name), &f.bytes) {
            eprintln!("cannot write {}: {e}", f.name);
            std::process::exit(2);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_statements_of_fc_bodies_only() {
        let src = b"DATA_BLOCK DB 1\r\nSTRUCT\r\n a : BOOL ;\r\nEND_STRUCT ;\r\nBEGIN\r\nEND_DATA_BLOCK\r\n\
FUNCTION FC 1 : VOID\r\nVAR_INPUT\r\n  INIT_SD : BOOL ;\r\nEND_VAR\r\nBEGIN\r\nNETWORK\r\nTITLE =\r\n\
      U     \"a;b\" ; // c; d\r\nM001: =     A 0.0 ;\r\n      CALL FC 10 (\r\n        X := E 0.0,\r\n        Y := A 0.1) ;\r\n\
END_FUNCTION\r\n";
        assert_eq!(fc_statements(src), vec![3]);
    }
}
