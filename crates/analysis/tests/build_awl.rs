//! `build --target awl`: the STEP 7 source of a group (`higraph_export::awl`), driven through
//! `Analysis::group_source`. Snapshots of the drilling machine's group (absolute and symbolic);
//! every example and runtime fixture group generates. When Awlsim's cache venv exists
//! (`~/.cache/higraph-awlsim/venv`, installed by `scripts/awlsim-diff`), the absolute sources
//! are also compiled and run in Awlsim (`crates/export/tests/awlsim/run.py`).

use higraph_analysis::build::BuildOptions;
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

fn load_dir(root: &std::path::Path) -> AnalysisHost {
    load_dir_with(root, None)
}

/// The workspace at `root`, with another `higraph.toml` when `config` is given.
fn load_dir_with(root: &std::path::Path, config: Option<&str>) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    let mut stack = vec![root.to_path_buf()];
    let mut files = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("directory") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    for path in files {
        let rel = path
            .strip_prefix(root)
            .expect("inside")
            .to_string_lossy()
            .replace('\\', "/");
        let bytes = std::fs::read(&path).expect("readable");
        if rel.ends_with(".higraph") {
            data.files.push((rel, FileContents::from_bytes(bytes)));
        } else if rel == "higraph.toml" {
            data.config = Some((rel, FileContents::from_bytes(bytes)));
        }
    }
    if let Some(text) = config {
        data.config = Some((
            "higraph.toml".to_owned(),
            FileContents::from_bytes(text.as_bytes().to_vec()),
        ));
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

fn repo(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn source(host: &AnalysisHost, group: &str, options: &BuildOptions) -> (String, Vec<u8>) {
    let (name, bytes, _) = host
        .analysis()
        .group_source(group, options)
        .expect("not cancelled")
        .expect("the group exists")
        .expect("the group generates");
    (name, bytes)
}

fn text(bytes: &[u8]) -> String {
    // Windows-1252 → text for the snapshot (the examples are ASCII apart from comments).
    bytes
        .iter()
        .map(|&b| b as char)
        .collect::<String>()
        .replace("\r\n", "\n")
}

const ABSOLUTE: BuildOptions = BuildOptions {
    target: higraph_analysis::build::Target::Awl,
    with_ob1: false,
    absolute: true,
};

#[test]
fn drilling_absolute() {
    let host = load_dir(&repo("examples/drilling"));
    let (name, bytes) = source(&host, "Bohrmaschine", &ABSOLUTE);
    assert_eq!(name, "Bohrmaschine.awl");
    assert!(bytes.windows(2).any(|w| w == b"\r\n"));
    assert!(
        !bytes
            .iter()
            .enumerate()
            .any(|(i, &b)| b == b'\n' && (i == 0 || bytes[i - 1] != b'\r'))
    );
    insta::assert_snapshot!(text(&bytes));
}

#[test]
fn drilling_symbolic_with_ob1() {
    let host = load_dir(&repo("examples/drilling"));
    let options = BuildOptions {
        with_ob1: true,
        absolute: false,
        ..ABSOLUTE
    };
    let (_, bytes) = source(&host, "Bohrmaschine", &options);
    let (_, _, symbols) = host
        .analysis()
        .group_source("Bohrmaschine", &options)
        .unwrap()
        .unwrap()
        .unwrap();
    let table = higraph_export::sdf::text(&symbols);
    insta::assert_snapshot!(format!("{}\n---- symbols.sdf\n{table}", text(&bytes)));
}

#[test]
fn deterministic() {
    let host = load_dir(&repo("examples/drilling"));
    let a = source(&host, "Bohrmaschine", &ABSOLUTE);
    let host = load_dir(&repo("examples/drilling"));
    let b = source(&host, "Bohrmaschine", &ABSOLUTE);
    assert_eq!(a, b);
}

// ------------------------------------------------------------------ against the simulator

use higraph_runtime::program::{MemArea, OpCode, Operand, Place, Predef, RunEntry, Width};

/// A small deterministic generator (xorshift).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// The input bits of a group: every E bit it names, and every M bit it reads but never writes.
fn input_bits(program: &higraph_runtime::Program, g: usize) -> Vec<(MemArea, u32, u8)> {
    let mut read = std::collections::BTreeSet::new();
    let mut written = std::collections::BTreeSet::new();
    let group = &program.groups[g];
    let key = |p: &Place| match p {
        Place::Mem {
            area: area @ (MemArea::Input | MemArea::Memory),
            byte,
            width: Width::Bit(b),
        } => Some((matches!(area, MemArea::Input), *byte, *b)),
        _ => None,
    };
    for inst in &group.instances {
        for p in &inst.binding {
            read.extend(key(p));
        }
        let graph = &program.graphs[inst.graph as usize];
        let mut blocks = Vec::new();
        blocks.extend(&graph.permanent_pre);
        blocks.extend(&graph.permanent_post);
        for t in &graph.any {
            blocks.extend(&t.conditions);
            blocks.extend(&t.actions);
        }
        for st in &graph.states {
            for b in [&st.entry, &st.pre, &st.cyclic, &st.exit] {
                blocks.extend(b);
            }
            for t in &st.transitions {
                blocks.extend(&t.conditions);
                blocks.extend(&t.actions);
            }
        }
        for b in blocks {
            for ins in &b.code {
                let place = match &ins.operand {
                    Operand::Var(v) => inst.binding.get(*v as usize),
                    Operand::Place(p) => Some(p),
                    _ => None,
                };
                let Some(k) = place.and_then(key) else {
                    continue;
                };
                read.insert(k);
                if matches!(
                    ins.op,
                    OpCode::Assign | OpCode::S | OpCode::R | OpCode::Fp | OpCode::Fn | OpCode::T
                ) {
                    written.insert(k);
                }
            }
        }
    }
    read.into_iter()
        .filter(|k| k.0 || !written.contains(k))
        .map(|(input, byte, bit)| {
            (
                if input {
                    MemArea::Input
                } else {
                    MemArea::Memory
                },
                byte,
                bit,
            )
        })
        .collect()
}

fn python() -> Option<std::path::PathBuf> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| std::path::PathBuf::from(h).join(".cache")))?;
    let p = cache.join("higraph-awlsim/venv/bin/python");
    p.exists().then_some(p)
}

/// Runs group `group` of the workspace at `dir` for `cycles` cycles with random inputs in the
/// simulator and in Awlsim (its generated absolute source with OB 1) and compares after every
/// cycle each instance's predefined variables (and own declared variables), the outputs and
/// the bit memory.
fn differential(dir: &str, group: &str, seed: u64, cycles: usize) {
    differential_with(dir, None, group, seed, cycles, true)
}

/// The generated workload's 255 instances (slow: Awlsim compiles 11 MB of source).
#[test]
#[ignore]
fn awlsim_max_group() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("max-group-ws");
    for (path, text) in higraph_workload::max_group(1) {
        let p = dir.join(&path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    differential_with(dir.to_str().unwrap(), None, "Anlage", 3, 20, true);
}

fn differential_with(
    dir: &str,
    config: Option<&str>,
    group: &str,
    seed: u64,
    cycles: usize,
    absolute: bool,
) {
    let Some(python) = python() else {
        eprintln!("Awlsim's venv is missing (run scripts/awlsim-diff once): skipped");
        return;
    };
    let host = load_dir_with(&repo(dir), config);
    let errors: Vec<String> = host
        .analysis()
        .diagnostics()
        .into_iter()
        .flat_map(|(_, d)| d)
        .filter(|d| d.severity == higraph_analysis::Severity::Error)
        .map(|d| format!("{} {}", d.code, d.message))
        .collect();
    assert!(errors.is_empty(), "{dir}: {errors:#?}");
    let options = BuildOptions {
        with_ob1: true,
        absolute,
        ..ABSOLUTE
    };
    let (name, bytes, symbols) = host
        .analysis()
        .group_source(group, &options)
        .expect("not cancelled")
        .expect("the group exists")
        .expect("the group generates");
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("build_awl");
    std::fs::create_dir_all(&out).unwrap();
    let intl = config.is_some_and(|c| c.contains("international"));
    let awl = out.join(format!(
        "{}{}{}-{name}",
        dir.replace('/', "_"),
        if intl { "-intl" } else { "" },
        if absolute { "" } else { "-symbolic" }
    ));
    // Data blocks the graphs address besides the group's own exist in the simulator (every
    // DB does); Awlsim needs them declared.
    let mut file = bytes.clone();
    {
        let lowered = host.analysis().lower_workspace().unwrap();
        let mut dbs = std::collections::BTreeSet::new();
        for inst in lowered.program.groups.iter().flat_map(|g| &g.instances) {
            for p in &inst.binding {
                if let Place::Mem {
                    area: MemArea::Db(n),
                    ..
                } = p
                {
                    dbs.insert(*n);
                }
            }
        }
        for graph in &lowered.program.graphs {
            let mut all = Vec::new();
            all.extend(&graph.permanent_pre);
            all.extend(&graph.permanent_post);
            for t in &graph.any {
                all.extend(&t.conditions);
                all.extend(&t.actions);
            }
            for st in &graph.states {
                for b in [&st.entry, &st.pre, &st.cyclic, &st.exit] {
                    all.extend(b);
                }
                for t in &st.transitions {
                    all.extend(&t.conditions);
                    all.extend(&t.actions);
                }
            }
            for b in all {
                for ins in &b.code {
                    if let Operand::Place(Place::Mem {
                        area: MemArea::Db(n),
                        ..
                    }) = &ins.operand
                    {
                        dbs.insert(*n);
                    }
                }
            }
        }
        let text = self::text(&bytes);
        for n in dbs {
            if !text.contains(&format!("DATA_BLOCK DB {n}\n")) {
                file.extend_from_slice(
                    format!(
                        "\r\nDATA_BLOCK DB {n}\r\n  STRUCT\r\n   a : ARRAY [0 .. 1023] OF BYTE;\r\n  END_STRUCT ;\r\nBEGIN\r\nEND_DATA_BLOCK\r\n"
                    )
                    .as_bytes(),
                );
            }
        }
    }
    std::fs::write(&awl, &file).unwrap();
    let sdf = awl.with_extension("sdf");
    std::fs::write(&sdf, higraph_export::sdf::write(&symbols).unwrap()).unwrap();
    let text = text(&bytes);
    let db: u32 = text
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("DATA_BLOCK "))
        .and_then(|n| {
            let n = n.trim();
            match n.strip_prefix("DB ") {
                Some(n) => n.trim().parse().ok(),
                // A symbol: its number from the symbol table.
                None => symbols
                    .iter()
                    .find(|s| format!("\"{}\"", s.name) == n)
                    .and_then(|s| s.address.strip_prefix("DB "))
                    .and_then(|n| n.trim().parse().ok()),
            }
        })
        .expect("DATA_BLOCK DB n");

    let lowered = host.analysis().lower_workspace().unwrap();
    let program = &lowered.program;
    let g = program
        .groups
        .iter()
        .position(|x| x.name == group)
        .expect("lowered");
    let mut sim = higraph_runtime::sim::Sim::new(program);
    sim.run = vec![RunEntry::Group(g as u32)];
    let inputs = input_bits(program, g);
    // Fields: predefined variables and declared ones whose cell no other binding shares.
    let grp = &program.groups[g];
    let mut uses = std::collections::HashMap::new();
    for inst in &grp.instances {
        for p in &inst.binding {
            if let Place::Cell(c) = p {
                *uses.entry(*c).or_insert(0) += 1;
            }
        }
    }
    let mut fields = Vec::new();
    for inst in &grp.instances {
        let graph = &program.graphs[inst.graph as usize];
        for (v, var) in graph.vars.iter().enumerate() {
            let Some(Place::Cell(c)) = inst.binding.get(v) else {
                continue;
            };
            let predefined = v < Predef::ALL.len();
            if var.ty.bits().is_some() && (predefined || uses[c] == 1) {
                fields.push((format!("{}.{}", inst.name, var.name), Place::Cell(*c)));
            }
        }
    }
    let mut rng = Rng(seed);
    let mut values: Vec<bool> = vec![false; inputs.len()];
    let mut cyc_json = Vec::new();
    for _ in 0..cycles {
        let mut sets = Vec::new();
        for (i, &(area, byte, bit)) in inputs.iter().enumerate() {
            if rng.next().is_multiple_of(4) {
                values[i] = !values[i];
                let place = Place::Mem {
                    area,
                    byte,
                    width: Width::Bit(bit),
                };
                sim.machine.write(&place, u32::from(values[i])).unwrap();
                let a = if area == MemArea::Input { "E" } else { "M" };
                sets.push(format!("[\"{a}\",{byte},{bit},{}]", u32::from(values[i])));
            }
        }
        sim.step(None).expect("no fault");
        let f: Vec<String> = fields
            .iter()
            .map(|(_, p)| sim.machine.read(p).unwrap().to_string())
            .collect();
        let mut mem = Vec::new();
        for (area, n) in [(MemArea::Output, 8), (MemArea::Memory, 64)] {
            let b: Vec<String> = (0..n)
                .map(|i| sim.machine.read_bytes(area, i, 1).unwrap().to_string())
                .collect();
            mem.push(format!("[{}]", b.join(",")));
        }
        cyc_json.push(format!(
            "{{\"set\":[{}],\"fields\":[{}],\"bytes\":[{}]}}",
            sets.join(","),
            f.join(","),
            mem.join(",")
        ));
    }
    let names: Vec<String> = fields.iter().map(|(n, _)| format!("\"{n}\"")).collect();
    let scenario = format!(
        "{{\"awl\":{:?},\"sdf\":{:?},\"mnemonics\":\"{}\",\"db\":{db},\"dt\":10,\"fields\":[{}],\"bytes\":[[\"A\",0,8],[\"M\",0,64]],\"cycles\":[{}]}}",
        awl.to_string_lossy(),
        if absolute {
            String::new()
        } else {
            sdf.to_string_lossy().into_owned()
        },
        if intl { "en" } else { "de" },
        names.join(","),
        cyc_json.join(",\n")
    );
    let sc = awl.with_extension("json");
    std::fs::write(&sc, scenario).unwrap();
    let script = repo("crates/export/tests/awlsim/compare.py");
    let result = std::process::Command::new(python)
        .arg(&script)
        .arg(&sc)
        .output()
        .expect("python runs");
    let stdout = String::from_utf8_lossy(&result.stdout);
    let stderr = String::from_utf8_lossy(&result.stderr);
    eprintln!("{dir} {group}: {}", stdout.trim());
    assert!(
        result.status.success(),
        "{dir} {group}: Awlsim differs from the simulator\n{stdout}\n{stderr}\n(source {})",
        awl.display()
    );
}

#[test]
fn awlsim_drilling() {
    differential("examples/drilling", "Bohrmaschine", 7, 400);
}

#[test]
fn awlsim_runtime_examples() {
    for (dir, group) in [
        ("tests/data/runtime/drilling", "Bohrmaschine"),
        ("tests/data/runtime/e1", "GP"),
        ("tests/data/runtime/e1", "GO"),
        ("tests/data/runtime/e2", "G"),
        ("tests/data/runtime/e3", "RG"),
        ("tests/data/runtime/e3", "NG"),
        ("tests/data/runtime/e4", "G"),
        ("tests/data/runtime/e5", "Vorwaerts"),
        ("tests/data/runtime/e5", "Rueckwaerts"),
        ("crates/analysis/tests/build_awl/features", "Paar"),
        ("crates/analysis/tests/build_awl/features", "Einfach"),
    ] {
        for seed in [11, 12, 13] {
            differential(dir, group, seed, 300);
        }
    }
}

#[test]
fn awlsim_international_mnemonics() {
    // The sources stay SIMATIC (their own `mnemonic` item would say so; here the workspace
    // setting changes and the files are read in the international set): a file with SIMATIC
    // operations in an international workspace is translated.
    let config = "[workspace]\nmnemonic = \"international\"\n";
    differential_with(
        "crates/analysis/tests/build_awl/features_intl",
        Some(config),
        "Paar",
        21,
        300,
        true,
    );
}

#[test]
fn awlsim_symbolic() {
    // The symbolic sources with the symbol table `build` writes beside them.
    differential_with("examples/drilling", None, "Bohrmaschine", 5, 300, false);
    differential_with(
        "crates/analysis/tests/build_awl/features",
        None,
        "Paar",
        5,
        300,
        false,
    );
}

fn load_text(text: &str) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    data.files.push((
        "w.higraph".to_owned(),
        FileContents::from_bytes(text.as_bytes().to_vec()),
    ));
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

#[test]
fn calls_are_written_as_called() {
    let host = load_text(
        r#"
symbols < Dosieren : FC 30; IDB : DB 21; Menge : MW 12 INT; Wartezeit : MD 60 TIME; >
graph G <
  in < Go : BOOL; K : INT; >
  state 0 <
    wait Wartezeit;
    C:
      CALL FB 20, DB 20 (Start := Go, Wert := K, Ziel := Menge);
      CALL Dosieren (Menge := 5);
      CALL FB 22, IDB;
      U Go;
      CC FC 10;
  >
  trans any->0 < U INIT_SD; >
>
group Gr fc FC 1 db DB 1 < instance I : G < Go := M 0.0; K := 7; > >
"#,
    );
    let (_, bytes) = source(&host, "Gr", &ABSOLUTE);
    let abs = text(&bytes);
    assert!(abs.contains("      CALL  FB 20, DB 20 (\n"), "{abs}");
    assert!(
        abs.contains("           Start                    := M 0.0,\n"),
        "{abs}"
    );
    // The constant actual K := 7 passes the member holding it.
    assert!(
        abs.contains("           Wert                     := DB1.DBW "),
        "{abs}"
    );
    assert!(
        abs.contains("           Ziel                     := MW 12);\n"),
        "{abs}"
    );
    assert!(
        abs.contains("      CALL  FC 30 (\n           Menge                    := 5);\n"),
        "{abs}"
    );
    assert!(abs.contains("      CALL  FB 22, DB 21;\n"), "{abs}");
    assert!(abs.contains("      CC    FC 10;\n"), "{abs}");
    assert!(abs.contains("    K : INT := 7;"), "{abs}");
    assert!(
        abs.contains("      L     MD 60;            //\"Wartezeit\"\n"),
        "{abs}"
    );
    let symbolic = BuildOptions {
        absolute: false,
        ..ABSOLUTE
    };
    let (_, bytes) = source(&host, "Gr", &symbolic);
    let sym = text(&bytes);
    assert!(sym.contains("      CALL  \"Dosieren\" (\n"), "{sym}");
    assert!(sym.contains("      CALL  FB 22, \"IDB\";\n"), "{sym}");
    assert!(sym.contains("      L     \"Wartezeit\";\n"), "{sym}");
    assert!(
        sym.contains("           Ziel                     := \"Menge\");\n"),
        "{sym}"
    );
}

#[test]
fn unencodable_comments_are_refused() {
    let host = load_text(
        "graph G < state 0 \"\u{2192} Start\" < > trans any->0 < U INIT_SD; > >\n\
         group Gr fc FC 1 db DB 1 \"Pfeil \u{2192}\" < instance I : G < > >\n",
    );
    let err = host
        .analysis()
        .group_source("Gr", &ABSOLUTE)
        .unwrap()
        .unwrap()
        .unwrap_err();
    assert!(err.contains("U+2192"), "{err}");
}

#[test]
fn max_group_generates_and_runs() {
    let files = higraph_workload::max_group(1);
    let mut data = WorkspaceData::default();
    let mut groups = Vec::new();
    for (path, text) in files {
        for line in text.lines() {
            if let Some(rest) = line.trim_start().strip_prefix("group ") {
                groups.push(rest.split_whitespace().next().unwrap_or("").to_owned());
            }
        }
        if path.ends_with(".higraph") {
            data.files
                .push((path, FileContents::from_bytes(text.into_bytes())));
        } else if path == "higraph.toml" {
            data.config = Some((path, FileContents::from_bytes(text.into_bytes())));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    for g in &groups {
        let t = std::time::Instant::now();
        let (_, bytes) = source(&host, g, &ABSOLUTE);
        std::fs::write(
            std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("max-group.awl"),
            &bytes,
        )
        .unwrap();
        eprintln!(
            "{g}: {} bytes, {} lines in {:?}",
            bytes.len(),
            bytes.split(|&b| b == b'\n').count(),
            t.elapsed()
        );
    }
}
