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
  set Betrieb_Auto := TRUE;
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
}
