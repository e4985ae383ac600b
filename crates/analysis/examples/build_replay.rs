//! The simulator's side of the proof that generated STL equals the simulator
//! (`export.md` §5, `scripts/build-diff`, `docs/build.md` "How the generated code is proven").
//!
//! `cargo run -p higraph-analysis --example build_replay -- --out DIR [--cycles N]
//! [--workload-cycles N] [--seed S] [--only NAME] [--workspace DIR]...`
//!
//! For every workspace it covers — each folder of `examples/`, and the generated workloads
//! `max-group` and `plant` (seed 1) — it builds the AWL target with `--absolute` semantics
//! (`Analysis::build`, no OB 1) and writes into DIR:
//!
//! * `<workspace>/<group>.awl`, the generated sources;
//! * one replay file `NNN-<scenario>.json` per scenario: a `test` item of the examples (run by
//!   the runtime's test runner, observed through `higraph_runtime::test::Observer`), or a seeded
//!   random input sequence over one group (the simulator driven directly).
//!
//! A replay file names the `.awl` files, Δ, the virtual time of cycle 0, the groups run (FC
//! order, instances, the DB fields of their message bits), and per cycle: the writes the test
//! statements (or the random stimulus) made before it, restarts, INIT_SD, and what the
//! simulator holds after it (each instance's CurrentState, each message bit in the DB, the
//! input, output and bit-memory areas). When a scenario cannot be replayed in Awlsim (the build
//! was refused or the generator failed, the test runs charts or sets stub values), the file
//! says so in `skip` and the harness reports it — nothing is left out silently.
//!
//! It also checks that the build is deterministic: every workspace is built twice from fresh
//! hosts, the files must be byte-identical and contain neither the machine's paths nor a time
//! stamp. Those findings go to `DIR/determinism.txt` (one line per problem; empty when none).

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use higraph_analysis::build::{BuildOptions, Target};
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};
use higraph_runtime::program::{
    Block, Graph, MemArea, Operand, Place, Predef, Program, RunEntry, Width,
};
use higraph_runtime::sim::Sim;
use higraph_runtime::test::{Observer, RunOptions};
use higraph_runtime::{Machine, Value};
use serde_json::{Value as Json, json};

/// Awlsim's clock at virtual time 0, ms (TIME_TCK must not be assumed to start at 0).
const T0_MS: u64 = 1_000_000;
/// For one random scenario per workspace: TIME_TCK wraps from 2^31 - 1 to 0 after ~0.6 s.
const T0_WRAP_MS: u64 = (1u64 << 31) - 600;

struct Args {
    out: PathBuf,
    cycles: u64,
    workload_cycles: u64,
    seed: u64,
    only: Option<String>,
    /// Extra workspaces (`--workspace DIR`), treated like the examples.
    extra: Vec<PathBuf>,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        out: PathBuf::new(),
        cycles: 300,
        workload_cycles: 30,
        seed: 1,
        only: None,
        extra: Vec::new(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let v = it.next().ok_or_else(|| format!("{k} needs a value"))?;
        let num = |v: &str| {
            v.parse::<u64>()
                .map_err(|_| format!("{k}: not a number: {v}"))
        };
        match k.as_str() {
            "--out" => a.out = PathBuf::from(v),
            "--cycles" => a.cycles = num(&v)?,
            "--workload-cycles" => a.workload_cycles = num(&v)?,
            "--seed" => a.seed = num(&v)?,
            "--only" => a.only = Some(v),
            "--workspace" => a.extra.push(PathBuf::from(v)),
            _ => return Err(format!("unknown argument {k}")),
        }
    }
    if a.out.as_os_str().is_empty() {
        return Err("--out DIR is required".into());
    }
    Ok(a)
}

fn main() {
    let a = match args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!(
                "build_replay: {e}\nusage: build_replay --out DIR [--cycles N] \
                 [--workload-cycles N] [--seed S] [--only WORKSPACE] [--workspace DIR]..."
            );
            std::process::exit(2);
        }
    };
    if let Err(e) = std::fs::create_dir_all(&a.out) {
        eprintln!("build_replay: {}: {e}", a.out.display());
        std::process::exit(2);
    }
    // Panics of the generator are caught and reported per workspace; keep stderr quiet.
    std::panic::set_hook(Box::new(|_| {}));
    let root = PathBuf::from(format!("{}/../..", env!("CARGO_MANIFEST_DIR")));
    let mut workspaces: Vec<(String, Files, bool)> = Vec::new();
    let mut names: Vec<String> = std::fs::read_dir(root.join("examples"))
        .map(|d| {
            d.filter_map(|e| e.ok())
                .filter(|e| e.path().is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    for name in names {
        workspaces.push((
            name.clone(),
            example_files(&root.join("examples").join(&name)),
            true,
        ));
    }
    for dir in &a.extra {
        let name = dir
            .file_name()
            .map_or_else(|| "workspace".into(), |n| n.to_string_lossy().into_owned());
        workspaces.push((name, example_files(dir), true));
    }
    workspaces.push(("max-group".into(), higraph_workload::max_group(1), false));
    workspaces.push(("plant".into(), higraph_workload::plant(1), false));

    let mut out = Out {
        dir: a.out.clone(),
        n: 0,
        determinism: String::new(),
    };
    let secrets = machine_strings(&root);
    for (name, files, example) in &workspaces {
        if a.only.as_ref().is_some_and(|o| o != name) {
            continue;
        }
        let cycles = if *example {
            a.cycles
        } else {
            a.workload_cycles
        };
        workspace(&mut out, name, files, *example, cycles, a.seed, &secrets);
    }
    let det = out.dir.join("determinism.txt");
    if let Err(e) = std::fs::write(&det, &out.determinism) {
        eprintln!("build_replay: {}: {e}", det.display());
        std::process::exit(2);
    }
    println!("build_replay: {} scenarios in {}", out.n, out.dir.display());
}

/// A workspace's files: (workspace-relative path, text).
type Files = Vec<(String, String)>;

struct Out {
    dir: PathBuf,
    n: usize,
    determinism: String,
}

impl Out {
    fn write(&mut self, slug: &str, value: &Json) {
        self.n += 1;
        let file: String = slug
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let path = self.dir.join(format!("{:03}-{file}.json", self.n));
        let text = serde_json::to_string(value).unwrap_or_default();
        if let Err(e) = std::fs::write(&path, text) {
            eprintln!("build_replay: {}: {e}", path.display());
            std::process::exit(2);
        }
    }
}

fn example_files(root: &Path) -> Vec<(String, String)> {
    let mut files = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.filter_map(|e| e.ok()) {
            let path = e.path();
            if path.is_dir() {
                stack.push(path);
            } else if let (Ok(rel), Ok(text)) =
                (path.strip_prefix(root), std::fs::read_to_string(&path))
            {
                files.push((rel.to_string_lossy().replace('\\', "/"), text));
            }
        }
    }
    files.sort();
    files
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

/// Texts that must not appear in generated files: the machine's paths.
fn machine_strings(root: &Path) -> Vec<String> {
    let mut out = Vec::new();
    if let Ok(root) = root.canonicalize() {
        out.push(root.to_string_lossy().into_owned());
    }
    if let Ok(home) = std::env::var("HOME")
        && home.len() > 1
    {
        out.push(home);
    }
    if let Ok(dir) = std::env::current_dir() {
        out.push(dir.to_string_lossy().into_owned());
    }
    // `/` alone is in every file; a path of the machine is longer.
    out.retain(|s| s.len() > 1);
    out
}

/// The outcome of building one workspace: the files by name, or why there are none.
type Built = Result<BTreeMap<String, Vec<u8>>, String>;

fn build(files: &[(String, String)], with_ob1: bool) -> Built {
    let h = host(files);
    let analysis = h.analysis();
    let options = BuildOptions {
        target: Target::Awl,
        with_ob1,
        absolute: true,
    };
    let result = catch_unwind(AssertUnwindSafe(|| analysis.build(&[], &options)));
    match result {
        Err(panic) => {
            // The orchestrator (or a part it calls, like the HG81xx rules) is not finished:
            // generate each group's source directly, and say so.
            let why = panic_text(&panic);
            let errors = analysis
                .diagnostics()
                .iter()
                .flat_map(|(_, d)| d)
                .filter(|d| d.severity == higraph_analysis::Severity::Error)
                .count();
            if errors > 0 {
                return Err(format!(
                    "build refused ({errors} error-level diagnostics; checked here because \
                     Analysis::build panicked: {why})"
                ));
            }
            let mut files = BTreeMap::new();
            let Ok(lowered) = analysis.lower_workspace() else {
                return Err("cancelled".into());
            };
            for group in &lowered.program.groups {
                let one = catch_unwind(AssertUnwindSafe(|| {
                    analysis.group_source(&group.name, &options)
                }));
                match one {
                    Err(p) => {
                        return Err(format!(
                            "Analysis::build panicked ({why}), and the generator panicked on \
                             group {}: {}",
                            group.name,
                            panic_text(&p)
                        ));
                    }
                    Ok(Ok(Some(Ok((name, bytes, _))))) => {
                        files.insert(name, bytes);
                    }
                    Ok(Ok(Some(Err(e)))) => {
                        return Err(format!("the generator refused group {}: {e}", group.name));
                    }
                    Ok(Ok(None)) | Ok(Err(_)) => {
                        return Err(format!("no source for group {}", group.name));
                    }
                }
            }
            eprintln!(
                "build_replay: Analysis::build panicked ({why}); the sources come from \
                 Analysis::group_source"
            );
            Ok(files)
        }
        Ok(Err(_)) => Err("the build was cancelled".into()),
        Ok(Ok(r)) if r.failure.is_some() => Err(format!(
            "the generator failed: {}",
            r.failure.unwrap_or_default()
        )),
        Ok(Ok(r)) if !r.refused.is_empty() => Err(format!(
            "build refused (error-level diagnostics in {})",
            r.refused.join(", ")
        )),
        Ok(Ok(r)) => Ok(r.files.into_iter().map(|f| (f.name, f.bytes)).collect()),
    }
}

fn panic_text(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "a panic".into())
}

/// The determinism findings of two builds (`export.md` §2).
fn determinism(
    name: &str,
    inputs: &[(String, String)],
    a: &Built,
    b: &Built,
    secrets: &[String],
    out: &mut String,
) {
    let (Ok(a), Ok(b)) = (a, b) else {
        if a.is_ok() != b.is_ok() {
            let _ = writeln!(out, "{name}: one build went through, the other did not");
        } else if let Err(e) = a {
            println!("determinism: {name}: not built ({e})");
        }
        return;
    };
    println!(
        "determinism: {name}: {} files, {} bytes, built twice",
        a.len(),
        a.values().map(Vec::len).sum::<usize>()
    );
    if a.keys().ne(b.keys()) {
        let _ = writeln!(out, "{name}: the two builds wrote different file lists");
    }
    for (file, bytes) in a {
        if b.get(file) != Some(bytes) {
            let _ = writeln!(out, "{name}/{file}: the two builds differ");
        }
        let text = String::from_utf8_lossy(bytes);
        for s in secrets {
            if text.contains(s.as_str()) {
                let _ = writeln!(out, "{name}/{file}: contains the machine path {s}");
            }
        }
        // A date or time the input does not contain (a constant or comment copied from the
        // text is not a time stamp).
        if let Some(stamp) = time_stamps(&text)
            .into_iter()
            .find(|s| !inputs.iter().any(|(_, t)| t.contains(s)))
        {
            let _ = writeln!(out, "{name}/{file}: contains a time stamp: {stamp}");
        }
    }
}

/// The dates `YYYY-MM-DD` or `YYYY/MM/DD` (a year 19xx/20xx) and clock times `HH:MM:SS` of a
/// text, each as the date or time alone (STEP 7 sources need neither).
fn time_stamps(text: &str) -> Vec<&str> {
    let b = text.as_bytes();
    let digit = |i: usize| b.get(i).is_some_and(|c| c.is_ascii_digit());
    let mut out = Vec::new();
    for i in 0..b.len() {
        let at_word = i == 0 || !b[i - 1].is_ascii_alphanumeric();
        if !at_word {
            continue;
        }
        let date = (b[i..].starts_with(b"19") || b[i..].starts_with(b"20"))
            && digit(i + 2)
            && digit(i + 3)
            && matches!(b.get(i + 4), Some(b'-' | b'/'))
            && digit(i + 5)
            && digit(i + 6)
            && b.get(i + 7) == b.get(i + 4)
            && digit(i + 8)
            && digit(i + 9);
        let clock = digit(i)
            && digit(i + 1)
            && b.get(i + 2) == Some(&b':')
            && digit(i + 3)
            && digit(i + 4)
            && b.get(i + 5) == Some(&b':')
            && digit(i + 6)
            && digit(i + 7);
        if date {
            out.extend(text.get(i..i + 10));
        } else if clock {
            out.extend(text.get(i..i + 8));
        }
    }
    out
}

fn workspace(
    out: &mut Out,
    name: &str,
    files: &[(String, String)],
    example: bool,
    cycles: u64,
    seed: u64,
    secrets: &[String],
) {
    let built = build(files, false);
    let again = build(files, false);
    // The examples also with the generated OB 1 (`--with-ob1`), replayed for single-group
    // scenarios: Awlsim's OB1_SCAN_1 is then 1 in the first cycle after a (re)start.
    let built_ob1 = if example {
        build(files, true)
    } else {
        Err(String::new())
    };
    let international = files.iter().any(|(path, text)| {
        path.ends_with("higraph.toml")
            && text.lines().any(|l| {
                let l = l.replace(' ', "");
                l.starts_with("mnemonic=") && l.contains("international")
            })
    });
    let mnemonic = if international { "en" } else { "de" };
    determinism(name, files, &built, &again, secrets, &mut out.determinism);
    let dir = out.dir.join(name);
    let _ = std::fs::create_dir_all(&dir);
    if let Ok(built) = &built {
        for (file, bytes) in built {
            let _ = std::fs::write(dir.join(file), bytes);
        }
    }
    if let Ok(built) = &built_ob1 {
        let _ = std::fs::create_dir_all(dir.join("ob1"));
        for (file, bytes) in built {
            let _ = std::fs::write(dir.join("ob1").join(file), bytes);
        }
    }
    let with_ob1 = |scenario: &Json| -> Option<Json> {
        let mut v = scenario.clone();
        let obj = v.as_object_mut()?;
        if obj.contains_key("skip") || obj.get("groups")?.as_array()?.len() != 1 {
            return None;
        }
        let title = format!("{} (the generated OB 1)", obj.get("name")?.as_str()?);
        obj.insert("name".into(), json!(title));
        obj.insert("generated_ob1".into(), json!(true));
        obj.insert("build_error".into(), json!(built_ob1.as_ref().err()));
        let group = obj
            .get_mut("groups")?
            .as_array_mut()?
            .first_mut()?
            .as_object_mut()?;
        let awl = format!("ob1/{}", group.get("awl")?.as_str()?);
        group.insert("awl".into(), json!(awl));
        Some(v)
    };
    let h = host(files);
    let analysis = h.analysis();
    let Ok(lowered) = analysis.lower_workspace() else {
        return;
    };
    let program = &lowered.program;
    // The example tests.
    if example {
        let tests = analysis.tests().unwrap_or_default();
        for t in tests {
            let slug = format!("{name}-test-{}", t.name);
            let title = format!("{name}: test {}", t.name);
            let lowered = match analysis.lower_test(&t.path, &t.name) {
                Ok(Ok(l)) => l,
                Ok(Err(d)) => {
                    out.write(
                        &slug,
                        &skipped(
                            &title,
                            &format!("the test cannot run: {}", d.message),
                            false,
                        ),
                    );
                    continue;
                }
                Err(_) => continue,
            };
            let scenario = test_scenario(name, &title, &lowered.program, &built, mnemonic);
            out.write(&slug, &scenario);
            if let Some(v) = with_ob1(&scenario) {
                out.write(&format!("{slug}-ob1"), &v);
            }
        }
    }
    // Random input sequences, one per group (and for the examples a second one across the
    // wrap of TIME_TCK).
    if program.groups.is_empty() {
        out.write(
            &format!("{name}-nogroup"),
            &skipped(
                &format!("{name}: no group"),
                "the workspace has no group",
                true,
            ),
        );
    }
    for g in 0..program.groups.len() {
        let gname = &program.groups[g].name;
        let title = format!("{name}: random inputs over group {gname} (seed {seed})");
        let slug = format!("{name}-random-{gname}");
        let scenario = random_scenario(
            name, &title, program, g, cycles, seed, T0_MS, example, &built, mnemonic,
        );
        out.write(&slug, &scenario);
        if let Some(v) = with_ob1(&scenario).filter(|_| example) {
            out.write(&format!("{slug}-ob1"), &v);
        }
        if example {
            let title = format!(
                "{name}: random inputs over group {gname} (seed {}), TIME_TCK wraps",
                seed + 1
            );
            out.write(
                &format!("{slug}-wrap"),
                &random_scenario(
                    name,
                    &title,
                    program,
                    g,
                    cycles.min(200),
                    seed + 1,
                    T0_WRAP_MS,
                    false,
                    &built,
                    mnemonic,
                ),
            );
        }
    }
}

/// A scenario the harness cannot run. `by_design`: not the generator's fault (a test of
/// charts, a workspace full of deliberate errors); otherwise the proof is incomplete.
fn skipped(title: &str, reason: &str, by_design: bool) -> Json {
    json!({ "name": title, "skip": reason, "by_design": by_design })
}

fn area_name(area: MemArea) -> String {
    match area {
        MemArea::Input => "E".into(),
        MemArea::Output => "A".into(),
        MemArea::Memory => "M".into(),
        MemArea::Local => "L".into(),
        MemArea::Db(n) => format!("DB{n}"),
    }
}

fn width_name(width: Width) -> String {
    match width {
        Width::Bit(b) => format!("X{b}"),
        Width::Byte => "B".into(),
        Width::Word => "W".into(),
        Width::Dword => "D".into(),
    }
}

/// What the replay needs of the groups run: per group its `.awl`, instances and message bits;
/// per cell of an instance its DB field (for `set Instance.Var`).
struct Layout {
    groups: Vec<u32>,
    header: Vec<Json>,
    fields: HashMap<u32, (usize, String)>,
}

fn layout(program: &Program, groups: &[u32], built: &Built) -> Result<Layout, String> {
    let mut header = Vec::new();
    let mut fields = HashMap::new();
    // Who owns a cell: the instance whose `msg in` it is (a `msg out` wired to it writes into
    // another instance's cell), else the one instance that binds it.
    let mut owners: HashMap<u32, Vec<(usize, String, bool)>> = HashMap::new();
    for (gi, &g) in groups.iter().enumerate() {
        let group = &program.groups[g as usize];
        for inst in &group.instances {
            let Some(graph) = program.graphs.get(inst.graph as usize) else {
                continue;
            };
            for (v, var) in graph.vars.iter().enumerate() {
                if let Some(Place::Cell(c)) = inst.binding.get(v) {
                    owners.entry(*c).or_default().push((
                        gi,
                        format!("{}.{}", inst.name, var.name),
                        var.msg_in == Some(true),
                    ));
                }
            }
        }
    }
    for (c, list) in &owners {
        let owner = list
            .iter()
            .find(|(_, _, msg_in)| *msg_in)
            .or(if list.len() == 1 { list.first() } else { None });
        if let Some((gi, field, _)) = owner {
            fields.insert(*c, (*gi, field.clone()));
        }
    }
    for &g in groups {
        let group = &program.groups[g as usize];
        let awl = format!("{}.awl", group.name);
        if let Ok(built) = built
            && !built.contains_key(&awl)
        {
            return Err(format!("the build wrote no {awl}"));
        }
        let mut instances = Vec::new();
        let mut msgs = Vec::new();
        for inst in &group.instances {
            instances.push(json!(inst.name));
            let Some(graph) = program.graphs.get(inst.graph as usize) else {
                continue;
            };
            for (v, var) in graph.vars.iter().enumerate() {
                if let (Some(_), Some(Place::Cell(c))) = (var.msg_in, inst.binding.get(v)) {
                    let field = format!("{}.{}", inst.name, var.name);
                    if fields.get(c).is_some_and(|(_, f)| *f == field) {
                        msgs.push(json!(field));
                    }
                }
            }
        }
        header
            .push(json!({ "name": group.name, "awl": awl, "instances": instances, "msgs": msgs }));
    }
    Ok(Layout {
        groups: groups.to_vec(),
        header,
        fields,
    })
}

fn hex(bytes: &[u8]) -> String {
    let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
    bytes[..end].iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// The simulator's state after a cycle.
fn expected(m: &mut Machine, program: &Program, lay: &Layout) -> Json {
    let mut states = Vec::new();
    let mut msgs = Vec::new();
    for &g in &lay.groups {
        let group = &program.groups[g as usize];
        let mut st = Vec::new();
        let mut ms = Vec::new();
        for inst in &group.instances {
            let place = &inst.binding[Predef::CurrentState.var() as usize];
            st.push(json!(m.read(place).unwrap_or(u32::MAX)));
            let Some(graph) = program.graphs.get(inst.graph as usize) else {
                continue;
            };
            for (v, var) in graph.vars.iter().enumerate() {
                if let (Some(_), Some(place @ Place::Cell(c))) = (var.msg_in, inst.binding.get(v)) {
                    let field = format!("{}.{}", inst.name, var.name);
                    if lay.fields.get(c).is_some_and(|(_, f)| *f == field) {
                        ms.push(json!(m.read(place).unwrap_or(0) & 1));
                    }
                }
            }
        }
        states.push(json!(st));
        msgs.push(json!(ms));
    }
    json!({
        "states": states,
        "msgs": msgs,
        "E": hex(m.area_bytes(MemArea::Input)),
        "A": hex(m.area_bytes(MemArea::Output)),
        "M": hex(m.area_bytes(MemArea::Memory)),
    })
}

/// A write before a cycle, as the harness replays it.
fn write_json(place: &Place, bits: u32, lay: &Layout) -> Result<Json, String> {
    match place {
        Place::Mem { area, byte, width } => Ok(json!({
            "area": area_name(*area), "byte": byte, "width": width_name(*width), "bits": bits
        })),
        Place::Cell(c) => match lay.fields.get(c) {
            Some((g, field)) => Ok(json!({ "group": g, "field": field, "bits": bits })),
            None => Err(format!(
                "a test statement writes cell {c}, which no instance of the groups run owns"
            )),
        },
        Place::Const(_) => Ok(Json::Null),
        Place::Timer(_) | Place::Counter(_) => {
            Err("a test statement writes a timer or counter".into())
        }
    }
}

struct Recorder<'l> {
    program: &'l Program,
    lay: &'l Layout,
    before: Vec<Json>,
    cycles: Vec<Json>,
    /// Why the test cannot be replayed, and whether that is by design (stub values model
    /// external blocks, whose code `build` does not generate) or a gap of the replay.
    problem: Option<(String, bool)>,
}

impl Observer for Recorder<'_> {
    fn set(&mut self, place: &Place, value: &Value) {
        let Some(bits) = value.to_bits() else {
            self.problem.get_or_insert_with(|| {
                (
                    "a test statement writes a STRING or DATE_AND_TIME, which the replay \
                     cannot"
                        .into(),
                    false,
                )
            });
            return;
        };
        match write_json(place, bits, self.lay) {
            Ok(Json::Null) => {}
            Ok(w) => self.before.push(w),
            Err(e) => {
                self.problem.get_or_insert((e, false));
            }
        }
    }
    fn stub(&mut self) {
        self.problem.get_or_insert_with(|| {
            (
                "the test sets a stub value of an external block (its code is not generated)"
                    .into(),
                true,
            )
        });
    }
    fn restart(&mut self, cold: bool) {
        self.before
            .push(json!({ "restart": if cold { "cold" } else { "warm" } }));
    }
    fn before_cycle(&mut self, sim: &mut Sim<'_>) {
        let init_sd = sim.next_is_first();
        let before = std::mem::take(&mut self.before);
        self.cycles
            .push(json!({ "before": before, "init_sd": init_sd }));
    }
    fn after_cycle(&mut self, sim: &mut Sim<'_>) {
        let e = expected(&mut sim.machine, self.program, self.lay);
        if let Some(Json::Object(c)) = self.cycles.last_mut() {
            c.insert("expect".into(), e);
        }
    }
}

fn test_scenario(ws: &str, title: &str, program: &Program, built: &Built, mnemonic: &str) -> Json {
    let Some(test) = &program.test else {
        return skipped(title, "no test", false);
    };
    let mut groups = Vec::new();
    for entry in &test.run {
        match entry {
            RunEntry::Group(g) => groups.push(*g),
            RunEntry::Chart(_) => {
                return skipped(
                    title,
                    "the test runs a chart (charts are exported to PLCopen XML, not AWL)",
                    true,
                );
            }
        }
    }
    let lay = match layout(program, &groups, built) {
        Ok(l) => l,
        Err(e) => return skipped(title, &e, false),
    };
    let mut rec = Recorder {
        program,
        lay: &lay,
        before: Vec::new(),
        cycles: Vec::new(),
        problem: None,
    };
    let options = RunOptions {
        trace: false,
        cancelled: &|| false,
    };
    let run = higraph_runtime::test::run_observed(program, &options, &mut rec);
    if let Some((p, by_design)) = rec.problem {
        return skipped(title, &p, by_design);
    }
    // A cycle that faulted has no "expect": the replay ends before it.
    let mut cycles = rec.cycles;
    if cycles.last().is_some_and(|c| c.get("expect").is_none()) {
        cycles.pop();
    }
    json!({
        "name": title,
        "workspace": ws,
        "cycle_ms": test.cycle_ms.max(1),
        "t0_ms": T0_MS,
        "mnemonic": mnemonic,
        "groups": lay.header,
        "outcome": run.map(|r| r.outcome.as_str()),
        "build_error": built.as_ref().err(),
        "refused_by_design": ws == "mistakes",
        "cycles": cycles,
    })
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
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
}

/// The input and bit-memory bits and words a group reads: the actuals bound to its instances
/// and the addresses its graphs' STL names.
fn stimulus(program: &Program, group: u32) -> (Vec<Place>, Vec<Place>) {
    let mut bits = Vec::new();
    let mut words = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut add = |place: &Place| {
        if let Place::Mem { area, byte, width } = place
            && matches!(area, MemArea::Input | MemArea::Memory)
            && seen.insert((*area, *byte, *width))
        {
            match width {
                Width::Bit(_) => bits.push(place.clone()),
                Width::Word => words.push(place.clone()),
                _ => {}
            }
        }
    };
    let g = &program.groups[group as usize];
    let mut graphs = Vec::new();
    for inst in &g.instances {
        for place in &inst.binding {
            add(place);
        }
        if !graphs.contains(&inst.graph) {
            graphs.push(inst.graph);
        }
    }
    for gr in graphs {
        if let Some(graph) = program.graphs.get(gr as usize) {
            for block in graph_blocks(graph) {
                for instr in &block.code {
                    if let Operand::Place(p) = &instr.operand {
                        add(p);
                    }
                }
            }
        }
    }
    (bits, words)
}

fn graph_blocks(graph: &Graph) -> impl Iterator<Item = &Block> {
    let states = graph.states.iter().flat_map(|s| {
        s.entry
            .iter()
            .chain(&s.pre)
            .chain(&s.cyclic)
            .chain(&s.exit)
            .chain(
                s.transitions
                    .iter()
                    .flat_map(|t| t.conditions.iter().chain(&t.actions)),
            )
    });
    graph
        .permanent_pre
        .iter()
        .chain(&graph.permanent_post)
        .chain(
            graph
                .any
                .iter()
                .flat_map(|t| t.conditions.iter().chain(&t.actions)),
        )
        .chain(states)
}

#[allow(clippy::too_many_arguments)]
fn random_scenario(
    ws: &str,
    title: &str,
    program: &Program,
    group: usize,
    cycles: u64,
    seed: u64,
    t0_ms: u64,
    restarts: bool,
    built: &Built,
    mnemonic: &str,
) -> Json {
    let g = group as u32;
    let lay = match layout(program, &[g], built) {
        Ok(l) => l,
        Err(e) => return skipped(title, &e, false),
    };
    let (bits, words) = stimulus(program, g);
    let first = &program.groups[group].instances;
    let mode = |p: Predef| first.first().map(|i| i.binding[p.var() as usize].clone());
    let (auto, manual) = (mode(Predef::AutomaticMode), mode(Predef::ManualMode));
    let mut sim = Sim::new(program);
    sim.run = vec![RunEntry::Group(g)];
    let mut rng = Rng(seed ^ (group as u64).wrapping_mul(0x1000_0001));
    let mut out = Vec::new();
    let write = |sim: &mut Sim<'_>, place: &Place, bits: u32, before: &mut Vec<Json>| {
        if sim.machine.write(place, bits).is_ok()
            && let Ok(w) = write_json(place, bits, &lay)
            && !w.is_null()
        {
            before.push(w);
        }
    };
    for k in 1..=cycles {
        let mut before = Vec::new();
        if restarts && (k == cycles / 2 || k == cycles * 3 / 4) {
            let cold = k != cycles / 2;
            sim.restart(cold);
            before.push(json!({ "restart": if cold { "cold" } else { "warm" } }));
        }
        // Automatic mode most of the time, manual now and then.
        if k == 1 || rng.below(50) == 0 {
            let manual_now = k > 1 && rng.below(4) == 0;
            if let Some(p) = &auto {
                write(&mut sim, p, u32::from(!manual_now), &mut before);
            }
            if let Some(p) = &manual {
                write(&mut sim, p, u32::from(manual_now), &mut before);
            }
        }
        for p in &bits {
            if Some(p) == auto.as_ref() || Some(p) == manual.as_ref() {
                continue;
            }
            if rng.below(4) == 0 {
                let v = (rng.next() & 1) as u32;
                write(&mut sim, p, v, &mut before);
            }
        }
        if k % 10 == 1 && !words.is_empty() {
            let p = &words[rng.below(words.len() as u64) as usize];
            let v = rng.below(200) as u32;
            write(&mut sim, p, v, &mut before);
        }
        let init_sd = sim.next_is_first();
        let mut cycle = json!({ "before": before, "init_sd": init_sd });
        if let Err(f) = sim.step(None) {
            // The simulator faulted: the replay stops before this cycle.
            let _ = f;
            break;
        }
        let e = expected(&mut sim.machine, program, &lay);
        if let Json::Object(c) = &mut cycle {
            c.insert("expect".into(), e);
        }
        out.push(cycle);
    }
    json!({
        "name": title,
        "workspace": ws,
        "cycle_ms": sim.cycle_ms,
        "t0_ms": t0_ms,
        "mnemonic": mnemonic,
        "groups": lay.header,
        "build_error": built.as_ref().err(),
        "refused_by_design": ws == "mistakes",
        "cycles": out,
    })
}
