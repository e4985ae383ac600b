//! The PLCopen round trip of issue 14: a generated IEC chart (`higraph_workload::iec_chart`)
//! checks clean, `build --target plcopen` writes it, the import reads the XML back, and the
//! formatted result has the semantic model (`model::model_of`) of the original.
//!
//! `HIGRAPH_ROUNDTRIP_CHARTS=N` changes the number of charts (default [`CHARTS`]); the seeds
//! are `0..N`, so a failure names a seed that reproduces it. `HIGRAPH_ROUNDTRIP_DUMP=DIR`
//! writes each chart's original text, XML and imported text into DIR.

use higraph_analysis::build::{BuildOptions, Target};
use higraph_analysis::fixture_workspace::load_fixture;
use higraph_analysis::model::model_of;
use higraph_analysis::{Analysis, Severity};

/// How many generated charts the test runs by default.
const CHARTS: u64 = 300;

fn charts() -> u64 {
    std::env::var("HIGRAPH_ROUNDTRIP_CHARTS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(CHARTS)
}

/// `check`'s errors and warnings of a one-file workspace, rendered: a generated chart is clean.
fn errors(analysis: &Analysis) -> Vec<String> {
    analysis
        .diagnostics()
        .into_iter()
        .flat_map(|(_, ds)| ds)
        .filter(|d| matches!(d.severity, Severity::Error | Severity::Warning))
        .map(|d| format!("{} {:?} {}", d.code, d.range, d.message))
        .collect()
}

/// The `charts.xml` of a chart text, which must check clean.
fn build(seed: u64, text: &str) -> String {
    let host = load_fixture(&[("main.higraph".to_owned(), text.as_bytes().to_vec())]);
    let analysis = host.analysis();
    let errors = errors(&analysis);
    assert!(
        errors.is_empty(),
        "seed {seed}: the generated chart has errors or warnings:\n{}\n{text}",
        errors.join("\n")
    );
    let result = analysis
        .build(
            &[],
            &BuildOptions {
                target: Target::Plcopen,
                ..BuildOptions::default()
            },
        )
        .expect("not cancelled");
    assert!(
        result.refused.is_empty(),
        "seed {seed}: build refused: {:?}\n{text}",
        result.diagnostics
    );
    assert_eq!(result.charts, 1, "seed {seed}");
    let file = result
        .files
        .iter()
        .find(|f| f.name == "charts.xml")
        .expect("charts.xml");
    String::from_utf8(file.bytes.clone()).expect("UTF-8")
}

/// Every generated chart checks clean and builds; the XML is deterministic and its wiring holds.
#[test]
fn generated_iec_charts_build() {
    for seed in 0..charts() {
        let text = higraph_workload::iec_chart(seed);
        let xml = build(seed, &text);
        assert_eq!(xml, build(seed, &text), "seed {seed}: not deterministic");
        assert!(xml.contains("initialStep=\"true\""), "seed {seed}");
        assert!(!xml.contains("name=\"Idle\""), "seed {seed}");
        // Every referenced localId exists.
        let ids: std::collections::HashSet<&str> = xml
            .split(" localId=\"")
            .skip(1)
            .filter_map(|s| s.split('"').next())
            .collect();
        for r in xml.split("refLocalId=\"").skip(1) {
            let r = r.split('"').next().unwrap_or_default();
            assert!(ids.contains(r), "seed {seed}: refLocalId {r}");
        }
    }
}

/// The import of a chart's XML, formatted; no problem, one chart.
fn import(seed: u64, xml: &str) -> String {
    let import = higraph_import::import(xml)
        .unwrap_or_else(|e| panic!("seed {seed}: the import refuses the XML: {e}\n{xml}"));
    assert!(
        import.problems.is_empty(),
        "seed {seed}: import problems: {:?}",
        import
            .problems
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
    );
    assert_eq!(import.charts.len(), 1, "seed {seed}");
    let text = &import.charts[0].text;
    higraph_analysis::format::format(text)
        .unwrap_or_else(|e| panic!("seed {seed}: the import does not format: {e:?}\n{text}"))
}

/// Generated charts with `init`/`run`/`term` parts check clean and build (the parts are inline
/// P1/N/P0 actions). They come back as named actions, so they are not in the round trip above;
/// but the imported chart checks clean, and building and importing it again is a fixed point.
#[test]
fn generated_iec_charts_with_step_parts_build() {
    let mut inline = 0;
    for seed in 0..charts() / 3 {
        let text = higraph_workload::iec_chart_with(seed, true);
        let xml = build(seed, &text);
        inline += xml.matches("<inline>").count();
        let once = import(seed, &xml);
        let twice = import(seed, &build(seed, &once));
        same_model(seed, &once, &twice);
    }
    assert!(inline > 0, "no step part was exported");
}

/// The models of two texts, for the failure message: the first differing line.
fn first_difference(a: &str, b: &str) -> String {
    for (i, (x, y)) in a.lines().zip(b.lines()).enumerate() {
        if x != y {
            return format!("line {i}:\n  original: {x}\n  imported: {y}");
        }
    }
    format!(
        "one model is a prefix of the other ({} vs {} lines)",
        a.lines().count(),
        b.lines().count()
    )
}

fn same_model(seed: u64, original: &str, imported: &str) {
    let formatted = match higraph_analysis::format::format(imported) {
        Ok(f) => f,
        Err(e) if std::env::var_os("HIGRAPH_ROUNDTRIP_NO_FORMAT").is_some() => {
            eprintln!("seed {seed}: the import does not format: {e:?}");
            imported.to_owned()
        }
        Err(e) => panic!("seed {seed}: the import does not format: {e:?}\n{imported}"),
    };
    let a = model_of(&higraph_syntax::parse(original).syntax_node());
    let b = model_of(&higraph_syntax::parse(&formatted).syntax_node());
    assert!(
        a == b,
        "seed {seed}: the models differ, {}\n--- original\n{original}\n--- imported\n{formatted}",
        first_difference(&a, &b)
    );
}

/// The round trip: build → import → format gives the model of the original.
#[test]
fn generated_iec_charts_round_trip() {
    let mut failures = Vec::new();
    for seed in 0..charts() {
        let original = higraph_workload::iec_chart(seed);
        let xml = build(seed, &original);
        let import = higraph_import::import(&xml)
            .unwrap_or_else(|e| panic!("seed {seed}: the import refuses the XML: {e}\n{xml}"));
        assert!(
            import.problems.is_empty(),
            "seed {seed}: import problems: {:?}\n{original}",
            import
                .problems
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
        );
        assert_eq!(import.charts.len(), 1, "seed {seed}");
        let imported = &import.charts[0].text;
        if let Some(dir) = std::env::var_os("HIGRAPH_ROUNDTRIP_DUMP") {
            let dir = std::path::PathBuf::from(dir);
            let _ = std::fs::create_dir_all(&dir);
            let _ = std::fs::write(dir.join(format!("{seed}.original.higraph")), &original);
            let _ = std::fs::write(dir.join(format!("{seed}.xml")), &xml);
            let _ = std::fs::write(dir.join(format!("{seed}.imported.higraph")), imported);
        }
        if let Err(e) = std::panic::catch_unwind(|| same_model(seed, &original, imported)) {
            let message = e
                .downcast_ref::<String>()
                .cloned()
                .unwrap_or_else(|| format!("seed {seed}: failed"));
            failures.push(message);
            if failures.len() >= 3 {
                break;
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The comparison is not vacuous: a chart whose import swapped two branches, dropped a
/// comment or changed a qualifier has another model.
#[test]
fn the_model_sees_what_an_import_could_lose() {
    let original = "chart C \"c\" <\n  profile iec;\n  out < Q : BOOL; R : BOOL; >\n  \
                    sequencer Main <\n    step A < N Q; >\n    alt <\n      branch <\n        \
                    trans T1 < Q; >\n      >\n      branch <\n        trans T2 < R; >\n      \
                    >\n    >\n    step B < >\n  >\n>\n";
    let model = |text: &str| model_of(&higraph_syntax::parse(text).syntax_node());
    for changed in [
        original.replace("T1 < Q; >", "T1 < R; >"),
        original.replace("N Q;", "S Q;"),
        original.replace("chart C \"c\"", "chart C"),
        original
            .replace("trans T1 < Q; >", "trans T9 < R; >")
            .replace("trans T2 < R; >", "trans T1 < Q; >")
            .replace("trans T9 < R; >", "trans T2 < R; >"),
    ] {
        assert_ne!(changed, original);
        assert_ne!(model(&changed), model(original), "{changed}");
    }
}
