//! The lowering from the analysed workspace to the runtime's `Program`: small workspaces as
//! readable dumps (snapshots), and the examples and generated workloads without panics.

use higraph_analysis::fixture_workspace::{fixture_files, load_fixture};
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData, lower};

fn lowered(fixture: &str) -> String {
    let host = load_fixture(&fixture_files(fixture.as_bytes()));
    let lowered = host.analysis().lower_workspace().expect("not cancelled");
    lower::dump(&lowered.program)
}

fn load(files: Vec<(String, String)>) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    for (path, text) in files {
        if path.ends_with(".higraph") {
            data.files
                .push((path, FileContents::from_bytes(text.into_bytes())));
        } else if path == "higraph.toml" {
            data.config = Some((path, FileContents::from_bytes(text.into_bytes())));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

fn example(dir: &str) -> AnalysisHost {
    let root = format!("{}/../../examples/{dir}", env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    let mut stack = vec![std::path::PathBuf::from(&root)];
    while let Some(dir) = stack.pop() {
        let mut entries: Vec<_> = std::fs::read_dir(&dir)
            .expect("example directory")
            .map(|e| e.expect("entry").path())
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                stack.push(path);
            } else {
                let relative = path
                    .strip_prefix(&root)
                    .expect("inside the example")
                    .to_string_lossy()
                    .replace('\\', "/");
                let text = std::fs::read_to_string(&path).expect("readable");
                files.push((relative, text));
            }
        }
    }
    files.sort();
    load(files)
}

#[test]
fn a_group_with_messages_constants_and_private_timers() {
    insta::assert_snapshot!(lowered(
        r#"
symbols < Start : M 0.0; Lampe : A 4.0; Wert : MW 10 INT; >
graph Sender <
  in < Go : BOOL; Grenze : INT := 7; >
  in_out < OM_Los : BOOL msg out; >
  stat < Zeit : TIMER; Zaehler : INT; >
  activate ST_Stop;
  permanent < C-: U #Go; = ST_Stop; >
  state 0 "Init" < >
  state 1 "Laufen" message < E: S OM_Los; L Zaehler; + 1; T Zaehler; L L#5; + L#2; C: L S5T#50MS; U Go; SE Zeit; wait T#50MS; supervise Grenze; >
  trans any->0 prio 1 "startup" < U INIT_SD; >
  trans 0->1 waits < U Go; O; U Zeit; ?: L Zaehler; L Grenze; >=I; !: R Go; >
  trans 1->0 prio 2 < UN Go; >
  trans 1->return prio 1 auto < CALL FC 10 (Ergebnis := MW 20); >
>
graph Empfaenger <
  in_out < IM_Los : BOOL msg in; >
  state 0 < >
  state 1 < E: R IM_Los; >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U IM_Los; >
>
group Paar fc FC 1 db DB 1 <
  option any_once;
  instance S : Sender < Go := Start; Grenze := 12; OM_Los := E.IM_Los; AutomaticMode := Lampe; >
  instance E : Empfaenger < >
>
"#
    ));
}

#[test]
fn international_mnemonics_lower_to_simatic_opcodes() {
    insta::assert_snapshot!(lowered(
        r#"
mnemonic international;
graph G <
  stat < Zeit : TIMER; Z1 : COUNTER; >
  state 0 < C: A I 0.0; AN Q 1.1; = Q 1.2; L PIW 4; T QW 6; SD Zeit; SE Zeit; CU Z1; CD C 3; CAW; >
  trans any->0 < A INIT_SD; >
>
group Gr fc FC 2 db DB 2 < instance I : G < > >
"#
    ));
}

#[test]
fn a_chart_with_parallel_alt_jump_and_loop() {
    insta::assert_snapshot!(lowered(
        r#"
symbols < Pumpe : A 2.0; Mixer : A 2.1; P_Start : M 30.0; Pegel : MW 12 INT; >
chart Par <
  in < Weiter : BOOL; Grenze : REAL := 4.5; Zahl : INT; >
  switching T_or_B;
  run cyclic;
  sequencer RUN prio 2 <
    start < SFC.RUN; >
    pre < Zahl := Zahl; >
    step S1 < init < Zahl := 5; > >
    trans T1 < P_Start and Pegel > 3; >
    parallel <
      branch < step A < L Pumpe, T#30MS; N A 2.0; > trans TA < Weiter; > step A2 < > >
      branch < step B < N Mixer; S Extern.Ventil; min T#1S; > >
    >
    trans T2 < Grenze >= 2; >
    step S3 < confirm; >
    jump J1->S1 < Anlage.Stopp; >
    alt <
      branch < trans X1 < Weiter; > step S4 < > trans X2 < > >
      branch < trans Y1 < not Weiter; > >
    >
    step S9 < >
    loop L1->S3 < Zahl = 5; >
  >
>
"#
    ));
}

#[test]
fn an_iec_chart_with_function_blocks_statements_and_actions() {
    insta::assert_snapshot!(lowered(
        r#"
symbols < Lampe : A 0.0; Taste : E 0.0; >
chart Iec <
  profile iec;
  stat < Zeit : TON; Zaehler : CTU; Teile : INT; Modus : DINT; Dauer : TIME; >
  sequencer Lauf <
    pre < Zaehler(CU := Taste, PV := 3); >
    post < Zeit(IN := A.X, PT := T#1S + Dauer * 2, Q => Lampe); >
    step A <
      run <
        IF Teile > 10 THEN
          Teile := 0;
        ELSIF Teile < -Teile THEN
          Teile := (Teile + 1) MOD 7;
        ELSE
          CASE Modus OF
            1, 3..5: Teile := Teile / 2;
          ELSE
            Teile := -1;
          END_CASE;
        END_IF;
      >
      P1 Zaehlen;
      DL Lampe, T#2S;
    >
    alt <
      branch < trans T1 < Zeit.Q and A.T >= T#1S; > step B < P0 Zaehlen; > >
      branch < jump J -> A < Zaehler.Q; > >
    >
  >
  action Zaehlen < Teile := Teile + 1; >
>
"#
    ));
}

#[test]
fn the_examples_lower() {
    for dir in ["drilling", "mixer", "mistakes", "ampel"] {
        let host = example(dir);
        let lowered = host.analysis().lower_workspace().expect("not cancelled");
        let p = &lowered.program;
        if dir != "mistakes" {
            assert!(
                !p.groups.is_empty() || !p.charts.is_empty(),
                "{dir}: nothing lowered"
            );
        }
        if dir == "drilling" {
            let group = &p.groups[0];
            assert_eq!(group.instances.len(), 4);
            // Bohren's OM_MotorStart is the own cell of Bohrmotor's IM_MotorStart.
            assert_eq!(group.internal_messages.len(), 12);
            for graph in &p.graphs {
                assert_eq!(graph.initial, Some(0), "{}", graph.name);
                assert_eq!(graph.startup, Some(0), "{}", graph.name);
            }
        }
        // Every origin is a range of a workspace file.
        for (path, range) in &lowered.origins {
            let text = host
                .analysis()
                .file_contents(path)
                .expect("a workspace file");
            let len = text.text().len();
            assert!(usize::from(range.end()) <= len, "{path}: {range:?}");
        }
    }
}

#[test]
fn the_workloads_lower() {
    for files in [
        higraph_workload::max_group(1),
        higraph_workload::plant(1),
        max_graph_in_a_group(),
    ] {
        let host = load(files);
        let lowered = host.analysis().lower_workspace().expect("not cancelled");
        assert!(!lowered.program.groups.is_empty() || !lowered.program.charts.is_empty());
    }
}

/// `max-graph` with a group that instantiates it.
fn max_graph_in_a_group() -> Vec<(String, String)> {
    let text = higraph_workload::max_graph(1);
    let name = text
        .lines()
        .find_map(|l| l.trim_start().strip_prefix("graph "))
        .and_then(|rest| rest.split_whitespace().next())
        .expect("a graph")
        .to_owned();
    vec![
        ("max.higraph".to_owned(), text),
        (
            "group.higraph".to_owned(),
            format!("group G fc FC 1 db DB 1 < instance I : {name} < > >\n"),
        ),
    ]
}

/// Lowering is linear in what it lowers: doubling a chain at most about doubles the time
/// (measured as the better of two runs, with a generous margin for noise).
#[test]
fn lowering_time_grows_linearly() {
    use higraph_workload::scaling;
    fn graph_chain_in_a_group(n: usize) -> String {
        format!(
            "{}group G fc FC 1 db DB 1 < instance I : Chain < > >\n",
            scaling::graph_chain(n)
        )
    }
    type Make = fn(usize) -> String;
    let cases: [(&str, Make); 3] = [
        ("chart chain", scaling::chart_chain),
        ("graph chain", graph_chain_in_a_group),
        ("group chain", scaling::group_chain),
    ];
    for (name, make) in cases {
        let time = |n: usize| {
            let host = load(vec![("main.higraph".to_owned(), make(n))]);
            let analysis = host.analysis();
            // Warm the analysis' own queries: only the lowering is measured.
            let _ = analysis.diagnostics();
            (0..2)
                .map(|_| {
                    let start = std::time::Instant::now();
                    let lowered = analysis.lower_workspace().expect("not cancelled");
                    assert!(
                        !lowered.program.groups.is_empty() || !lowered.program.charts.is_empty(),
                        "{name}: nothing lowered"
                    );
                    start.elapsed()
                })
                .min()
                .unwrap_or_default()
        };
        let small = time(1000);
        let large = time(4000);
        assert!(
            large < small * 12 + std::time::Duration::from_millis(50),
            "{name}: 1000 → {small:?}, 4000 → {large:?}"
        );
    }
}

/// Every rule fixture (broken input of every kind) lowers without a panic: the workspace, and
/// each of its tests (to a program or to HG9904).
#[test]
fn every_rule_fixture_lowers() {
    let root = format!("{}/test_data/rules", env!("CARGO_MANIFEST_DIR"));
    let mut dirs: Vec<_> = std::fs::read_dir(&root)
        .expect("fixtures")
        .map(|e| e.expect("entry").path())
        .collect();
    dirs.sort();
    let mut count = 0;
    for dir in dirs {
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .expect("fixture directory")
            .map(|e| e.expect("entry").path())
            .collect();
        files.sort();
        for file in files {
            let bytes = std::fs::read(&file).expect("fixture");
            let host = load_fixture(&fixture_files(&bytes));
            let analysis = host.analysis();
            let _ = analysis.lower_workspace().expect("not cancelled");
            for test in analysis.tests().expect("not cancelled") {
                let _ = analysis
                    .lower_test(&test.path, &test.name)
                    .expect("not cancelled");
                count += 1;
            }
        }
    }
    assert!(count > 20, "only {count} tests lowered");
}
