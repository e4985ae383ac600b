//! Lowering `test` items (`runtime.md` §5): run lists, statements, paths, the watch list,
//! HG9904; and the test path resolver the editor uses.

use higraph_analysis::fixture_workspace::{fixture_files, load_fixture};
use higraph_analysis::lower::{self, SegmentDef};
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

fn host(fixture: &str) -> AnalysisHost {
    load_fixture(&fixture_files(fixture.as_bytes()))
}

/// The dump of test `name` of `main.higraph`, or the HG9904 message.
fn lowered(host: &AnalysisHost, path: &str, name: &str) -> String {
    match host
        .analysis()
        .lower_test(path, name)
        .expect("not cancelled")
    {
        Ok(t) => lower::dump(&t.program),
        Err(d) => format!("{}: {}", d.code, d.message),
    }
}

/// The drilling example with the test of `runtime.md` §5.4.
fn drilling() -> AnalysisHost {
    let root = format!("{}/../../examples/drilling", env!("CARGO_MANIFEST_DIR"));
    let mut data = WorkspaceData::default();
    for path in [
        "symbols.higraph",
        "graphs/bohren.higraph",
        "graphs/motor.higraph",
        "graphs/spanner.higraph",
        "graphs/ventil_2e.higraph",
        "bohrmaschine.higraph",
    ] {
        let text = std::fs::read(format!("{root}/{path}")).expect("example file");
        data.files
            .push((path.to_owned(), FileContents::from_bytes(text)));
    }
    data.files.push((
        "tests.higraph".to_owned(),
        FileContents::from_bytes(DRILLING_TEST.as_bytes().to_vec()),
    ));
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

const DRILLING_TEST: &str = r#"test Bohrzyklus "one drilling cycle from the home position" <
  run Bohrmaschine;
  set Bohrer_Oben := TRUE;
  set Bohrmotor_Steht := TRUE;
  step 3;
  expect Bohren.state = 1 "coordinator in its home position";
  expect Vorschub.state = 1 and Bohrmotor.state = 1 and Spanneinrichtung.state = 1;
  set Starttaster := TRUE;
  step;
  set Starttaster := FALSE;
  expect Bohren.state = 2 and Spanneinrichtung.state = 2 and Werkstueck_Spannen;
  expect not Bohren.IM_Geloest "X of Spanner state 1 reset the message";
  set Spanndruck_Erreicht := TRUE;
  until Bohrmotor_Ein within T#100MS;
  wait T#200MS;
  expect Vorschub.state = 2 and not Vorschub.ST_Expired;
  expect Vorschub.ST_CurrValue = 9800 "remaining supervision time in ms";
  expect Bohrmaschine.Bohren.previous = 7;
>
"#;

#[test]
fn the_drilling_test_lowers() {
    let host = drilling();
    let tests = host.analysis().tests().expect("not cancelled");
    assert_eq!(tests.len(), 1);
    assert_eq!(tests[0].name, "Bohrzyklus");
    assert_eq!(tests[0].path, "tests.higraph");
    let dump = lowered(&host, "tests.higraph", "Bohrzyklus");
    let test_part = &dump[dump.find("test Bohrzyklus").expect("a test")..];
    insta::assert_snapshot!(test_part);
}

#[test]
fn a_chart_test_lowers() {
    let host = host(
        r#"
symbols < Flasche_da : E 4.0; Voll : E 4.1; Ventil : A 4.0; Ventil_Sperre : M 40.0; >
chart Abfuellen "bottle filling" <
  in < Menge : INT; Faktor : REAL; >
  run time_monitoring;
  sequencer RUN prio 2 <
    start < SFC.RUN; >
    step BEREIT < >
    trans T1 < Flasche_da and Anlage.Frei; >
    step FUELLEN < N Ventil; max T#5S; confirm; >
    trans T2 < Voll; >
    step ENDE < >
  >
  sequencer HALT prio 1 <
    start < SFC.HOLDING; >
    step H1 < init < Ventil_Sperre := TRUE; > >
    trans TH < >
    step H2 < >
  >
>
test Abfuellen_Halten "hold interrupts filling" <
  cycle T#100MS;
  run Abfuellen;
  expect Abfuellen.state = Ready;
  command Abfuellen start;
  set Abfuellen.Menge := 7;
  set Abfuellen.Faktor := 2;
  set Anlage.Frei := TRUE;
  step;
  expect Abfuellen.state <> Active and Abfuellen.BEREIT;
  wait T#250MS;
  until Abfuellen.state = Held within T#1S "held";
  confirm Abfuellen.RUN.FUELLEN;
  expect not Abfuellen.FUELLEN.error and Abfuellen.FUELLEN.T >= T#1S;
  restart warm;
  restart cold;
>
"#,
    );
    insta::assert_snapshot!(lowered(&host, "main.higraph", "Abfuellen_Halten"));
}

#[test]
fn errors_in_what_a_test_runs_stop_it() {
    let host = host(
        r#"
graph G < state 0 < C: U #Nichts; > trans any->0 < U INIT_SD; > >
group Gr fc FC 1 db DB 1 < instance I : G < > >
test T < run Gr; expect I.state = 0; >
"#,
    );
    let message = lowered(&host, "main.higraph", "T");
    assert!(
        message.starts_with("HG9904: test T cannot run: "),
        "{message}"
    );
    assert!(message.contains("graph G"), "{message}");
    assert_eq!(
        lowered(&host, "main.higraph", "Nope"),
        "HG9904: test Nope cannot run: there is no test Nope in main.higraph"
    );
}

#[test]
fn test_paths_name_their_definitions() {
    let host = drilling();
    let analysis = host.analysis();
    let text = analysis
        .file_contents("tests.higraph")
        .expect("file")
        .text()
        .to_owned();
    let at = text.find("Bohrmaschine.Bohren.previous").expect("path");
    let segments = analysis
        .test_path_at("tests.higraph", (at as u32 + 3).into())
        .expect("not cancelled");
    let kinds: Vec<&str> = segments
        .iter()
        .map(|(_, d)| match d {
            SegmentDef::Group { .. } => "group",
            SegmentDef::Instance { .. } => "instance",
            SegmentDef::Member => "member",
            _ => "other",
        })
        .collect();
    assert_eq!(kinds, ["group", "instance", "member"]);
    let SegmentDef::Instance { file, range } = &segments[1].1 else {
        panic!("instance")
    };
    assert_eq!(file, "bohrmaschine.higraph");
    let group_text = analysis
        .file_contents(file)
        .expect("file")
        .text()
        .to_owned();
    assert_eq!(
        &group_text[usize::from(range.start())..usize::from(range.end())],
        "Bohren"
    );
    let at = text.find("Vorschub.ST_Expired").expect("path");
    let segments = analysis
        .test_path_at("tests.higraph", (at as u32 + 10).into())
        .expect("not cancelled");
    assert!(matches!(
        segments[1].1,
        SegmentDef::Predefined { name: "ST_Expired" }
    ));
    // Every segment of every path of the file.
    let all = analysis
        .test_path_segments("tests.higraph")
        .expect("not cancelled");
    let symbols = all
        .iter()
        .filter(|(_, d)| matches!(d, SegmentDef::Symbol { .. }))
        .count();
    assert_eq!(symbols, 7);
    for (range, def) in &all {
        let written = &text[usize::from(range.start())..usize::from(range.end())];
        if let SegmentDef::Symbol { name } = def {
            assert_eq!(written, name);
        }
    }
}

/// Lowers and runs a test; the failures' messages.
fn run(host: &AnalysisHost, path: &str, name: &str) -> Vec<String> {
    let lowered = match host
        .analysis()
        .lower_test(path, name)
        .expect("not cancelled")
    {
        Ok(t) => t,
        Err(d) => return vec![format!("{}: {}", d.code, d.message)],
    };
    let options = higraph_runtime::test::RunOptions {
        trace: false,
        cancelled: &|| false,
    };
    let run = higraph_runtime::test::run(&lowered.program, &options).expect("not cancelled");
    if std::env::var("LOWER_TRACE").is_ok() {
        let traced = higraph_runtime::test::run(
            &lowered.program,
            &higraph_runtime::test::RunOptions {
                trace: true,
                cancelled: &|| false,
            },
        )
        .expect("not cancelled");
        for c in &traced.trace.expect("trace").cycles {
            let states: Vec<String> = c
                .instances
                .iter()
                .map(|i| format!("{}={}/{} {:?}", i.instance, i.state, i.previous, i.parts))
                .collect();
            eprintln!("cycle {}: {}", c.cycle, states.join("  "));
        }
    }
    run.failures
        .iter()
        .map(|f| {
            let at = lowered
                .origin(f.origin)
                .map(|(file, range)| format!("{file}@{range:?}"))
                .unwrap_or_default();
            format!("{} {} ({at})", f.code, f.message)
        })
        .collect()
}

/// `runtime.md` §5.4 on the drilling example (whose coordinator dwells 2 s at the bottom
/// and has eight states, and whose clamp waits 1 s for its jaws): passes.
#[test]
fn the_drilling_test_passes() {
    let text = r#"test Bohrzyklus2 <
  run Bohrmaschine;
  set Bohrer_Oben := TRUE;
  set Bohrmotor_Steht := TRUE;
  step 3;
  expect Bohren.state = 1 "coordinator in its home position";
  expect Vorschub.state = 1 and Bohrmotor.state = 1 and Spanneinrichtung.state = 1;
  set Starttaster := TRUE;
  step;
  set Starttaster := FALSE;
  expect Bohren.state = 2 and Spanneinrichtung.state = 2 and Werkstueck_Spannen;
  expect not Bohren.IM_Geloest "X of Spanner state 1 reset the message";
  set Spanndruck_Erreicht := TRUE;
  until Bohrmotor_Ein within T#100MS;
  set Bohrmotor_Steht := FALSE;
  set Bohrmotor_Laeuft := TRUE;
  until Bohrer_Senken within T#100MS;
  set Bohrer_Oben := FALSE;
  wait T#200MS;
  expect Vorschub.state = 2 and not Vorschub.ST_Expired;
  set Bohrer_Unten := TRUE;
  until Bohrer_Heben within T#2100MS;
  expect not Bohrer_Senken "cyclic_rlo0 reset the lowering valve";
  set Bohrer_Unten := FALSE;
  set Bohrer_Oben := TRUE;
  until not Bohrmotor_Ein within T#100MS;
  set Bohrmotor_Laeuft := FALSE;
  set Bohrmotor_Steht := TRUE;
  set Spanndruck_Erreicht := FALSE;
  until Bohren.state = 1 within T#1200MS;
  expect Bohren.previous = 8;
  expect not (Bohrmotor_Ein or Bohrer_Senken or Bohrer_Heben or Werkstueck_Spannen);
>
"#;
    let mut host = drilling();
    host.set_file_contents(
        "tests.higraph",
        FileContents::from_bytes(format!("{DRILLING_TEST}{text}").into_bytes()),
    );
    assert_eq!(
        run(&host, "tests.higraph", "Bohrzyklus2"),
        Vec::<String>::new()
    );
}

/// `runtime.md` §5.5: hold and resume of a chart, passes.
#[test]
fn the_chart_hold_test_passes() {
    let host = host(
        r#"symbols < Flasche_da : E 4.0; Voll : E 4.1; Ventil : A 4.0; Ventil_Sperre : M 40.0; >
chart Abfuellen "bottle filling" <
  run time_monitoring;
  sequencer RUN prio 2 <
    start < SFC.RUN; >
    step BEREIT < >
    trans T1 < Flasche_da; >
    step FUELLEN < N Ventil; max T#5S; >
    trans T2 < Voll; >
    step ENDE < >
  >
  sequencer HALT prio 1 <
    start < SFC.HOLDING; >
    step H1 < init < Ventil_Sperre := TRUE; > >
    trans TH < >
    step H2 < >
  >
>
test Abfuellen_Halten "hold interrupts filling; resume continues it" <
  cycle T#100MS;
  run Abfuellen;
  expect Abfuellen.state = Ready;
  command Abfuellen start;
  step;
  expect Abfuellen.state = Active and Abfuellen.BEREIT;
  set Flasche_da := TRUE;
  step;
  expect Abfuellen.FUELLEN and Ventil;
  command Abfuellen hold;
  step;
  expect Abfuellen.state = Holding and not Ventil and Ventil_Sperre;
  expect Abfuellen.FUELLEN "a suspended step stays active";
  until Abfuellen.state = Held within T#1S;
  command Abfuellen resume;
  step;
  expect Abfuellen.state = Active and Ventil;
  wait T#4900MS;
  expect not Abfuellen.FUELLEN.error;
  step;
  expect Abfuellen.RUN.FUELLEN.error;
  set Voll := TRUE;
  until Abfuellen.state = Completed within T#1S;
  expect not Ventil;
>
"#,
    );
    assert_eq!(
        run(&host, "main.higraph", "Abfuellen_Halten"),
        Vec::<String>::new()
    );
}

/// `runtime.md` §9.3 E5: the internal message hand-shake, passes.
#[test]
fn the_message_handshake_passes() {
    let host = host(
        r#"graph Auftraggeber <
  in < Start : BOOL; >
  in_out < OM_Go : BOOL msg out; IM_Fertig : BOOL msg in; >
  state 0 < > state 1 < E: S OM_Go; > state 2 < >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U Start; >
  trans 1->2 < U IM_Fertig; !: R IM_Fertig; >
>
graph Ausfuehrer <
  in_out < IM_Go : BOOL msg in; OM_Fertig : BOOL msg out; >
  state 0 < > state 1 < E: S OM_Fertig; >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U IM_Go; !: R IM_Go; >
  trans 1->0 < >
>
group Paar fc FC 1 db DB 1 <
  instance A : Auftraggeber < Start := M 0.0; OM_Go := B.IM_Go; >
  instance B : Ausfuehrer < OM_Fertig := A.IM_Fertig; >
>
test E5 <
  step;
  expect A.state = 0 and not A.IM_Fertig and B.state = 0 and not B.IM_Go;
  set M 0.0 := TRUE;
  step;
  expect A.state = 1 and A.IM_Fertig and B.state = 1 and not B.IM_Go;
  step;
  expect A.state = 2 and not A.IM_Fertig and B.state = 0 and not B.IM_Go;
>
"#,
    );
    assert_eq!(run(&host, "main.higraph", "E5"), Vec::<String>::new());
}

/// `runtime.md` §9.3 E6: a parallel branch and the `L` qualifier, passes.
#[test]
fn the_parallel_chart_passes() {
    let host = host(
        r#"symbols < P_Start : M 30.0; P_Fertig : M 30.1; P_Ende : M 30.2; Pumpe : A 2.0; Mixer : A 2.1; >
chart Par <
  sequencer RUN <
    start < SFC.RUN; >
    step S1 < >
    trans T1 < P_Start; >
    parallel <
      branch < step A < L Pumpe, T#30MS; > trans TA < P_Fertig; > step A2 < > >
      branch < step B < N Mixer; > >
    >
    trans T2 < P_Ende; >
    step S9 < >
  >
>
test E6 <
  command Par start;
  set P_Start := TRUE;
  step;
  expect Par.state = Active and Par.S1 and not Pumpe and not Mixer;
  step;
  expect Par.A and Par.B and not Par.S1 and Pumpe and Mixer;
  step 2;
  expect Par.A and Par.B and Pumpe and Mixer;
  step;
  expect Par.A and Par.B and not Pumpe and Mixer;
  set P_Fertig := TRUE;
  step;
  expect Par.A2 and Par.B and not Pumpe and Mixer;
  set P_Ende := TRUE;
  step;
  expect Par.S9 and not Par.A2 and not Par.B and not Pumpe and not Mixer;
  step 2;
  expect not Par.S9 and Par.state = Active;
  step;
  expect Par.state = Completed;
>
"#,
    );
    assert_eq!(run(&host, "main.higraph", "E6"), Vec::<String>::new());
}

/// An `alt`, a `jump` and a `loop`: decision candidates and targets as §4.5 orders them.
#[test]
fn alt_jump_and_loop_pass() {
    let host = host(
        r#"chart J <
  in < Xa : BOOL; Ya : BOOL; Za : BOOL; >
  sequencer Seq <
    start < SFC.RUN; >
    step A < >
    jump J1->C < Za; >
    alt <
      branch < trans TX < Xa; > step B < > trans TB < TRUE; > >
      branch < trans TY < Ya; > >
    >
    step C < >
    loop L1->A < Xa; >
    trans TC < Ya; >
    step E < >
  >
>
test Wege <
  command J start;
  step;
  expect J.A;
  set J.Xa := TRUE;
  step;
  expect J.B and not J.A;
  step;
  expect J.C;
  step;
  expect J.A and not J.C "the loop fires after TC did not";
  set J.Xa := FALSE;
  set J.Za := TRUE;
  step;
  expect J.C and not J.A "the jump";
  set J.Za := FALSE;
  set J.Ya := TRUE;
  step;
  expect J.E and not J.C;
>
"#,
    );
    assert_eq!(run(&host, "main.higraph", "Wege"), Vec::<String>::new());
}

/// `CALL` stubs (§3.11): a test sets `Block.Param`, the call writes it to its actual, and
/// `Block.calls` counts; a symbol and the block's address name the same block.
#[test]
fn call_stubs_pass() {
    let host = host(
        r#"symbols < Dosieren : FC 10; Fertig_Bit : M 1.0; >
block Dosieren < in < Menge : INT; > out < Fertig : BOOL; Rest : INT; > >
graph G <
  state 0 < C: CALL Dosieren (Menge := 5, Fertig := Fertig_Bit, Rest := MW 4); >
  trans any->0 < U INIT_SD; >
>
group Gr fc FC 1 db DB 1 < instance I : G < > >
test Stubs <
  set Dosieren.Fertig := TRUE;
  set FC10.Rest := 42;
  step 2;
  expect Fertig_Bit and MW 4 = 42 and Dosieren.calls = 2 and FC10.calls = 2;
>
"#,
    );
    assert_eq!(run(&host, "main.higraph", "Stubs"), Vec::<String>::new());
}

// ------------------------------------------------------------------------------ IEC charts

/// The example `examples/ampel` (an IEC chart) with `replace` applied to its tests.
fn ampel(replace: Option<(&str, &str)>) -> AnalysisHost {
    let root = format!("{}/../../examples/ampel", env!("CARGO_MANIFEST_DIR"));
    let mut data = WorkspaceData::default();
    for path in ["ampel.higraph", "tests.higraph"] {
        let mut text = std::fs::read_to_string(format!("{root}/{path}")).expect("example file");
        if let Some((from, to)) = replace {
            text = text.replacen(from, to, 1);
        }
        data.files
            .push((path.to_owned(), FileContents::from_bytes(text.into_bytes())));
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

/// The failures of an IEC test, lowered even where the checker still reports errors (the
/// HG75xx rules of IEC charts are checked elsewhere).
fn run_iec(host: &AnalysisHost, path: &str, name: &str) -> Vec<String> {
    let lowered = match host
        .analysis()
        .lower_test_ignoring_errors(path, name)
        .expect("not cancelled")
    {
        Ok(t) => t,
        Err(d) => return vec![format!("{}: {}", d.code, d.message)],
    };
    let options = higraph_runtime::test::RunOptions {
        trace: false,
        cancelled: &|| false,
    };
    let run = higraph_runtime::test::run(&lowered.program, &options).expect("not cancelled");
    run.failures
        .iter()
        .map(|f| format!("{} {}", f.code, f.message))
        .collect()
}

#[test]
fn the_ampel_example_runs_on_the_simulator() {
    let host = ampel(None);
    for name in ["Ampel_Runde", "Teile_Zaehlen"] {
        assert_eq!(
            run_iec(&host, "tests.higraph", name),
            Vec::<String>::new(),
            "{name}"
        );
    }
}

#[test]
fn a_changed_expectation_of_the_ampel_example_fails() {
    let host = ampel(Some((
        "expect Ampel.Zaehler.CV = 5 and Kiste_Voll;",
        "expect Ampel.Zaehler.CV = 6 and Kiste_Voll;",
    )));
    let failures = run_iec(&host, "tests.higraph", "Teile_Zaehlen");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(
        failures[0].starts_with("HG9901 expect failed: at cycle 10 (t = 100 ms): "),
        "{failures:?}"
    );
    assert!(failures[0].contains("Ampel.Zaehler.CV = 5"), "{failures:?}");
    // arithmetic in a test expression is evaluated, not dropped
    let host = ampel(Some((
        "Ampel.Zaehler.CV * 2 - 1 = 9",
        "Ampel.Zaehler.CV * 2 - 1 = 8",
    )));
    let failures = run_iec(&host, "tests.higraph", "Teile_Zaehlen");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("arithmetic in tests"), "{failures:?}");
    // the timing of the light: one cycle later is wrong
    let host = ampel(Some(("step 30; // 31", "step 29; // 30")));
    let failures = run_iec(&host, "tests.higraph", "Ampel_Runde");
    assert!(!failures.is_empty());
}

/// Test paths into an IEC chart: function block members (inputs settable, outputs not), the
/// instance alone is no path, chart variables are settable.
#[test]
fn test_paths_of_iec_function_blocks() {
    let host = host(
        r#"
chart C <
  profile iec;
  stat < Zeit : TON; Zahl : INT; >
  sequencer S <
    post < Zeit(IN := A.X); >
    step A < >
    trans T < Zeit.Q; >
    step B < >
  >
>
test Gut <
  run C;
  set C.Zeit.PT := T#30MS;
  set C.Zahl := 7;
  step 3;
  expect not C.Zeit.Q and C.Zeit.ET = T#20MS and C.A;
  step;
  expect C.Zeit.Q and C.Zahl = 7;
  step;
  expect C.B and not C.Zeit.Q;
>
test Schlecht <
  run C;
  set C.Zeit.Q := TRUE;
  expect C.Zeit;
>
"#,
    );
    assert_eq!(run(&host, "main.higraph", "Gut"), Vec::<String>::new());
    let diagnostics = host.analysis().diagnostics();
    let codes: Vec<String> = diagnostics
        .iter()
        .flat_map(|(_, d)| d.iter())
        .map(|d| format!("{} {}", d.code, d.message))
        .filter(|c| c.starts_with("HG91"))
        .collect();
    assert!(
        codes
            .iter()
            .any(|c| c.starts_with("HG9104 ") && c.contains("output of the function block")),
        "{codes:#?}"
    );
    assert!(
        codes
            .iter()
            .any(|c| c.starts_with("HG9101 ") && c.contains("'Zeit' is a function block instance")),
        "{codes:#?}"
    );
    assert_eq!(codes.len(), 2, "{codes:#?}");
}

/// IEC structure: an `alt` branch that ends with a jump does not converge, a branch may be a
/// single jump, the last step jumps back to the initial step.
#[test]
fn iec_branches_ending_in_or_being_a_jump() {
    let host = host(
        r#"
chart C <
  profile iec;
  in < Links : BOOL; Rechts : BOOL; Weiter : BOOL; >
  sequencer S <
    step A < >
    alt <
      branch < trans TL < Links; > step B < > jump JB -> A < Rechts; > >
      branch < jump JR -> D < Rechts; > >
      branch < trans TW < Weiter; > step W < > trans T3 < Weiter; > >
    >
    step D < >
    jump Zurueck -> A < Links and Rechts; >
  >
>
test Wege <
  run C;
  step;
  set C.Links := TRUE;
  set C.Weiter := TRUE;
  step;
  expect C.B;
  step;
  expect C.B "B ends its branch with a jump: nothing else follows it";
  set C.Links := FALSE;
  set C.Weiter := FALSE;
  set C.Rechts := TRUE;
  step;
  expect C.A and not C.B;
  step;
  expect C.D and not C.A "a branch that is a jump";
  set C.Links := TRUE;
  step;
  expect C.A "the cyclic jump";
  set C.Links := FALSE;
  set C.Rechts := FALSE;
  set C.Weiter := TRUE;
  step;
  expect C.W;
  step;
  expect C.D "the branch converges";
>
"#,
    );
    assert_eq!(run(&host, "main.higraph", "Wege"), Vec::<String>::new());
}
