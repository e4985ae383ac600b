//! Import of the hand-written PLCopen files in `tests/data/plcopen/import/`: the generated
//! chart texts and the problem reports are insta snapshots; every generated text parses
//! without syntax diagnostics.

use std::fmt::Write as _;
use std::path::PathBuf;

fn data(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/plcopen/import")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The charts and the problems as the command line would report them.
fn render(name: &str) -> String {
    let out = higraph_import::import(&data(name)).expect("the file is a PLCopen project");
    let mut text = String::new();
    for chart in &out.charts {
        let _ = writeln!(text, "=== {}.higraph (POU {})", chart.name, chart.pou);
        text.push_str(&chart.text);
    }
    let _ = writeln!(text, "=== problems");
    for p in &out.problems {
        let _ = writeln!(text, "{name}:{}: warning: {p}", p.line);
    }
    let _ = writeln!(text, "=== skipped POUs without SFC: {:?}", out.skipped);
    text
}

/// Every generated chart parses without syntax diagnostics and is laid out as `fmt` lays it
/// out.
fn assert_parses(name: &str) {
    let out = higraph_import::import(&data(name)).expect("the file is a PLCopen project");
    for chart in &out.charts {
        let parse = higraph_syntax::parse(&chart.text);
        let errors: Vec<String> = parse
            .errors()
            .iter()
            .map(|e| format!("{}: {} at {:?}", e.code, e.message, e.range))
            .collect();
        assert!(
            errors.is_empty(),
            "{name}: chart {} has syntax errors:\n{}\n{}",
            chart.name,
            errors.join("\n"),
            chart.text
        );
        // The import writes the canonical layout itself (the command line formats anyway).
        let formatted = higraph_analysis::format::format(&chart.text).expect("formats");
        assert_eq!(
            chart.text, formatted,
            "{name}: chart {} is not in the layout of `fmt`",
            chart.name
        );
    }
}

#[test]
fn neutral_mixer() {
    insta::assert_snapshot!(render("neutral_mixer.xml"));
    assert_parses("neutral_mixer.xml");
}

#[test]
fn codesys_ampel() {
    insta::assert_snapshot!(render("codesys_ampel.xml"));
    assert_parses("codesys_ampel.xml");
}

#[test]
fn beremiz_station() {
    insta::assert_snapshot!(render("beremiz_station.xml"));
    assert_parses("beremiz_station.xml");
}

/// Beremiz conditions drawn as networks: LD contacts in series and parallel, FBD functions
/// through a connector, named transitions with FBD and LD bodies, standard function block
/// instances called in `pre` (one fed back by its own output), and branches that converge
/// only to jump back.
#[test]
fn beremiz_networks() {
    let out = render("beremiz_networks.xml");
    insta::assert_snapshot!(out);
    assert!(
        out.ends_with("=== problems\n=== skipped POUs without SFC: []\n"),
        "{out}"
    );
    assert_parses("beremiz_networks.xml");
}

/// What a network may hold that the language cannot express: each condition becomes FALSE
/// with a problem naming it, and the calls of a failed condition are not kept.
#[test]
fn network_problems_are_reported() {
    let out = render("network_problems.xml");
    insta::assert_snapshot!(out);
    assert!(!out.contains("pre <"), "{out}");
    assert_parses("network_problems.xml");
}

/// A network deeper than the limit, and one whose shared parts would make the expression
/// exponentially long: both are reported quickly instead of overflowing or blowing up.
#[test]
fn deep_and_wide_networks_are_bounded() {
    let chart = |network: &str, root: usize| {
        format!(
            "<project><types><pous><pou name=\"N\" pouType=\"program\">\
             <interface><inputVars><variable name=\"A\"><type><BOOL/></type></variable></inputVars></interface>\
             <body><SFC><step localId=\"1\" name=\"S\" initialStep=\"true\"/>\
             <transition localId=\"2\"><connectionPointIn><connection refLocalId=\"1\"/></connectionPointIn>\
             <condition><connectionPointIn><connection refLocalId=\"{root}\"/></connectionPointIn></condition></transition>\
             <step localId=\"3\" name=\"E\"><connectionPointIn><connection refLocalId=\"2\"/></connectionPointIn></step>\
             <inVariable localId=\"10\"><connectionPointOut/><expression>A</expression></inVariable>{network}</SFC></body></pou></pous></types></project>"
        )
    };
    let block = |id: usize, ty: &str, inputs: &[usize]| {
        let mut b = format!("<block localId=\"{id}\" typeName=\"{ty}\"><inputVariables>");
        for (k, i) in inputs.iter().enumerate() {
            let _ = write!(
                b,
                "<variable formalParameter=\"IN{}\"><connectionPointIn><connection refLocalId=\"{i}\"/></connectionPointIn></variable>",
                k + 1
            );
        }
        b.push_str("</inputVariables><outputVariables><variable formalParameter=\"OUT\"/></outputVariables></block>");
        b
    };
    // 10 000 NOT blocks in a chain.
    let mut net = String::new();
    for i in 0..10_000 {
        net.push_str(&block(11 + i, "NOT", &[10 + i]));
    }
    let out = higraph_import::import(&chart(&net, 10_010)).unwrap();
    assert!(
        out.problems
            .iter()
            .any(|p| p.message.contains("deeper than 40 elements")),
        "{:?}",
        out.problems
    );
    // 35 levels of AND(x, x): 2^35 copies of A if the sharing were expanded.
    let mut net = String::new();
    for i in 0..35 {
        net.push_str(&block(11 + i, "AND", &[10 + i, 10 + i]));
    }
    let started = std::time::Instant::now();
    let out = higraph_import::import(&chart(&net, 45)).unwrap();
    assert!(
        out.problems
            .iter()
            .any(|p| p.message.contains("longer than 20000 characters")),
        "{:?}",
        out.problems
    );
    assert!(started.elapsed().as_secs() < 5, "{:?}", started.elapsed());
}

#[test]
fn unsupported_constructs_are_reported_and_the_rest_imports() {
    insta::assert_snapshot!(render("unsupported.xml"));
    assert_parses("unsupported.xml");
}

#[test]
fn broken_connections_end_and_are_reported() {
    insta::assert_snapshot!(render("broken_graph.xml"));
    assert_parses("broken_graph.xml");
}

#[test]
fn documents_that_cannot_be_read() {
    let e = higraph_import::import(&data("malformed.xml")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid XML at 7:1: unexpected end of stream"
    );
    let e = higraph_import::import(&data("not_plcopen.xml")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "not a PLCopen project: the root element is <graph>, not <project>"
    );
    assert!(matches!(
        higraph_import::import("<!DOCTYPE x [<!ENTITY a \"b\">]><project/>"),
        Err(higraph_import::Error::Xml { .. })
    ));
    // A project without SFC POUs imports nothing and says so.
    let out = higraph_import::import("<project><types><pous/></types></project>").unwrap();
    assert!(out.charts.is_empty());
    assert_eq!(out.problems.len(), 1);
}

/// A long chain and deep nesting: linear time, no stack overflow, a clear problem past the
/// nesting limit.
#[test]
fn huge_and_deep_documents() {
    // 20 000 steps in a row with a jump back.
    let n = 20_000;
    let mut sfc = String::new();
    for i in 0..n {
        let step = 2 * i + 1;
        let trans = 2 * i + 2;
        let input = if i == 0 {
            String::new()
        } else {
            format!(
                "<connectionPointIn><connection refLocalId=\"{}\"/></connectionPointIn>",
                step - 1
            )
        };
        let initial = if i == 0 { " initialStep=\"true\"" } else { "" };
        let _ = write!(
            sfc,
            "<step localId=\"{step}\" name=\"S{i}\"{initial}>{input}</step>\
             <transition localId=\"{trans}\"><connectionPointIn><connection refLocalId=\"{step}\"/></connectionPointIn>\
             <condition><inline name=\"\"><ST><xhtml>x{i}</xhtml></ST></inline></condition></transition>"
        );
    }
    let _ = write!(
        sfc,
        "<jumpStep localId=\"{}\" targetName=\"S0\"><connectionPointIn><connection refLocalId=\"{}\"/></connectionPointIn></jumpStep>",
        2 * n + 1,
        2 * n
    );
    let doc = format!(
        "<project><types><pous><pou name=\"Long\" pouType=\"program\"><body><SFC>{sfc}</SFC></body></pou></pous></types></project>"
    );
    let out = higraph_import::import(&doc).unwrap();
    assert_eq!(out.charts.len(), 1);
    assert!(out.charts[0].text.contains("jump T20000->S0 < x19999; >"));

    // Selections nested 200 deep: the walk stops at its limit with a problem.
    let depth = 200;
    let mut sfc = String::from("<step localId=\"1\" name=\"S\" initialStep=\"true\"/>");
    let mut prev = 1;
    let mut id = 2;
    for _ in 0..depth {
        let _ = write!(
            sfc,
            "<selectionDivergence localId=\"{id}\"><connectionPointIn><connection refLocalId=\"{prev}\"/></connectionPointIn></selectionDivergence>\
             <transition localId=\"{}\"><connectionPointIn><connection refLocalId=\"{id}\"/></connectionPointIn>\
             <condition><inline name=\"\"><ST><xhtml>a</xhtml></ST></inline></condition></transition>\
             <step localId=\"{}\" name=\"S{id}\"><connectionPointIn><connection refLocalId=\"{}\"/></connectionPointIn></step>",
            id + 1,
            id + 2,
            id + 1
        );
        prev = id + 2;
        id += 3;
    }
    let doc = format!(
        "<project><types><pous><pou name=\"Deep\" pouType=\"program\"><body><SFC>{sfc}</SFC></body></pou></pous></types></project>"
    );
    let out = higraph_import::import(&doc).unwrap();
    assert!(
        out.problems
            .iter()
            .any(|p| p.message.contains("nested deeper than 64")),
        "{:?}",
        out.problems
    );
}

/// Random damage to the test files (bytes deleted, duplicated, swapped; ST keywords
/// sprinkled in): the import never panics, and every chart it writes parses cleanly and is
/// in the layout of `fmt`.
#[test]
fn damaged_files_never_panic() {
    let files = [
        "neutral_mixer.xml",
        "codesys_ampel.xml",
        "beremiz_station.xml",
        "unsupported.xml",
        "broken_graph.xml",
        "beremiz_networks.xml",
        "network_problems.xml",
    ];
    let words = [
        "IF ",
        "END_IF",
        "CASE ",
        "(*",
        "*)",
        "'",
        "\"",
        "<",
        ">",
        "&amp;",
        "(",
        ")",
        ":=",
        "..",
        "T#",
        "16#",
        ";",
        ".",
        "NOT ",
        "-",
        "<step localId=\"3\"/>",
        "refLocalId=\"1\"",
    ];
    let mut seed: u64 = std::env::var("IMPORT_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x9E37_79B9_7F4A_7C15);
    let mut next = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n.max(1) as u64) as usize
    };
    for round in 0..1000 {
        let mut text = data(files[round % files.len()]).into_bytes();
        for _ in 0..1 + next(8) {
            let at = next(text.len());
            match next(4) {
                0 => {
                    let len = next(40).min(text.len() - at);
                    text.drain(at..at + len);
                }
                1 => {
                    let len = next(60).min(text.len() - at);
                    let piece: Vec<u8> = text[at..at + len].to_vec();
                    let to = next(text.len());
                    text.splice(to..to, piece);
                }
                2 => {
                    let w = words[next(words.len())].as_bytes();
                    text.splice(at..at, w.iter().copied());
                }
                _ => {
                    let other = next(text.len());
                    text.swap(at, other);
                }
            }
        }
        let text = String::from_utf8_lossy(&text);
        if let Ok(out) = higraph_import::import(&text) {
            for chart in &out.charts {
                assert!(chart.text.ends_with(">\n"));
                assert!(!chart.text.contains("<?xml"));
                let errors = higraph_syntax::parse(&chart.text).errors().len();
                assert_eq!(errors, 0, "round {round}: syntax errors in\n{}", chart.text);
                let formatted = higraph_analysis::format::format(&chart.text).expect("formats");
                assert_eq!(
                    chart.text, formatted,
                    "round {round}: not in the layout of `fmt`"
                );
            }
        }
    }
}

/// Random structured text: whatever the converter accepts parses cleanly as an action body
/// and as a transition condition.
#[test]
fn converted_structured_text_always_parses() {
    let tokens = [
        "a", "b", "Timer", "Timer.Q", "Timer.ET", "S1.X", "x", "1", "-2", "3.5", "T#5s", "t#1m30s",
        "TRUE", "FALSE", "16#1F", "'txt'", ":=", "=>", "=", "<>", "<", ">", "<=", ">=", "+", "-",
        "*", "/", "MOD", "AND", "&", "OR", "XOR", "NOT", "(", ")", ",", ";", ":", "..", "IF",
        "THEN", "ELSIF", "ELSE", "END_IF", "CASE", "OF", "END_CASE", "(* c *)", "// c\n", "\n",
    ];
    let mut names = higraph_import::st::Names::default();
    names.fb_instances.insert("TIMER".into(), ());
    let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    let mut accepted = (0, 0);
    for _ in 0..40_000 {
        let len = 1 + next(14);
        let text: Vec<&str> = (0..len).map(|_| tokens[next(tokens.len())]).collect();
        let text = text.join(" ");
        if let Ok(body) = higraph_import::st::statements(&text, &names, 2) {
            accepted.0 += 1;
            let chart = format!(
                "chart C <\n  profile iec;\n  stat < a : INT; b : INT; x : BOOL; Timer : TON; >\n  sequencer Main <\n    step S1 < >\n  >\n  action A <\n{body}  >\n>\n"
            );
            let errors = higraph_syntax::parse(&chart).errors().len();
            assert_eq!(errors, 0, "ST `{text}` gave\n{chart}");
        }
        if let Ok(cond) = higraph_import::st::condition(&text, &names) {
            accepted.1 += 1;
            let chart = format!(
                "chart C <\n  profile iec;\n  sequencer Main <\n    step S1 < >\n    trans T < {cond}; >\n    step S2 < >\n  >\n>\n"
            );
            let errors = higraph_syntax::parse(&chart).errors().len();
            assert_eq!(errors, 0, "ST `{text}` gave\n{chart}");
        }
    }
    assert!(accepted.0 > 100 && accepted.1 > 100, "{accepted:?}");
}

/// CODESYS keeps the POUs of an application inside the resource's vendor data, and the
/// standard's own example tells the branches of a divergence apart by `formalParameter`.
#[test]
fn pous_in_vendor_data_and_branches_by_formal_parameter() {
    let doc = r#"<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0200">
  <types><dataTypes /><pous /></types>
  <instances><configurations><configuration name="Device"><resource name="Application">
    <addData><data name="http://www.3s-software.com/plcopenxml/pou" handleUnknown="implementation">
      <pou name="Branches" pouType="program">
        <interface><localVars>
          <variable name="A"><type><BOOL /></type></variable>
          <variable name="B"><type><BOOL /></type></variable>
        </localVars></interface>
        <body><SFC>
          <step localId="1" name="Start" initialStep="true"><connectionPointOut formalParameter="sfc" /></step>
          <selectionDivergence localId="2">
            <connectionPointIn><connection refLocalId="1" /></connectionPointIn>
            <connectionPointOut formalParameter="left" />
            <connectionPointOut formalParameter="right" />
          </selectionDivergence>
          <transition localId="3">
            <connectionPointIn><connection refLocalId="2" formalParameter="right" /></connectionPointIn>
            <condition><inline name="Right"><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">B</xhtml></ST></inline></condition>
          </transition>
          <transition localId="4">
            <connectionPointIn><connection refLocalId="2" formalParameter="left" /></connectionPointIn>
            <condition><inline name="Left"><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">A</xhtml></ST></inline></condition>
          </transition>
          <jumpStep localId="5" targetName="Start"><connectionPointIn><connection refLocalId="3" /></connectionPointIn></jumpStep>
          <jumpStep localId="6" targetName="Start"><connectionPointIn><connection refLocalId="4" /></connectionPointIn></jumpStep>
        </SFC></body>
      </pou>
    </data></addData>
  </resource></configuration></configurations></instances>
</project>"#;
    let out = higraph_import::import(doc).unwrap();
    assert!(out.problems.is_empty(), "{:?}", out.problems);
    assert_eq!(out.charts.len(), 1);
    let text = &out.charts[0].text;
    // Only jumps after the step: written as jumps, the left pin first.
    assert!(
        text.contains(
            "    step Start < >\n    jump Left->Start < A; >\n    jump Right->Start < B; >\n"
        ),
        "{text}"
    );
}
