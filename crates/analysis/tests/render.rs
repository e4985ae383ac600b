//! `render` (tooling.md §6): DOT snapshots of the examples, the geometry of the SVG layout
//! (no state circles overlap, no labels overlap) and well-formed SVG.

use std::path::Path;

use higraph_analysis::render::{BBox, Picture, RenderFormat};
use higraph_analysis::{Analysis, AnalysisHost, FileContents, WorkspaceData};

/// The `.higraph` files of one example folder, loaded.
fn example(folder: &str) -> AnalysisHost {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(folder);
    let mut files = Vec::new();
    collect(&root, &root, &mut files);
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files,
        ..WorkspaceData::default()
    });
    host
}

fn collect(root: &Path, dir: &Path, out: &mut Vec<(String, FileContents)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("example folder")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            collect(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "higraph") {
            let text = std::fs::read_to_string(&path).expect("example file");
            let relative = path
                .strip_prefix(root)
                .expect("under the root")
                .to_string_lossy()
                .replace('\\', "/");
            out.push((relative, FileContents::Text(text)));
        }
    }
}

fn render(analysis: &Analysis, name: &str, format: RenderFormat) -> String {
    analysis
        .render(name, format)
        .expect("not cancelled")
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn picture(analysis: &Analysis, name: &str) -> Picture {
    analysis
        .render_picture(name)
        .expect("not cancelled")
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn dot_of_the_drilling_graphs_and_group() {
    let analysis = example("drilling").analysis();
    insta::assert_snapshot!(
        "dot_ventil_2e",
        render(&analysis, "Ventil_2E", RenderFormat::Dot)
    );
    insta::assert_snapshot!("dot_bohren", render(&analysis, "bohren", RenderFormat::Dot));
    insta::assert_snapshot!(
        "dot_bohrmaschine",
        render(&analysis, "Bohrmaschine", RenderFormat::Dot)
    );
}

#[test]
fn dot_of_the_mixer_chart() {
    let analysis = example("mixer").analysis();
    insta::assert_snapshot!(
        "dot_mischer",
        render(&analysis, "Mischer", RenderFormat::Dot)
    );
}

#[test]
fn output_is_deterministic() {
    let analysis = example("drilling").analysis();
    for name in ["Ventil_2E", "Bohrmaschine"] {
        for format in [RenderFormat::Svg, RenderFormat::Dot] {
            assert_eq!(
                render(&analysis, name, format),
                render(&analysis, name, format)
            );
        }
    }
}

#[test]
fn unknown_names_list_what_exists() {
    let analysis = example("drilling").analysis();
    let error = analysis
        .render("Nope", RenderFormat::Svg)
        .expect("not cancelled")
        .expect_err("no such item");
    assert!(error.contains("'Nope'"), "{error}");
    assert!(
        error.contains("Ventil_2E") && error.contains("Bohrmaschine"),
        "{error}"
    );
    let empty = AnalysisHost::new().analysis();
    assert!(
        empty
            .render("x", RenderFormat::Dot)
            .expect("not cancelled")
            .is_err()
    );
}

/// Checks that no two circles and no two text boxes overlap.
fn assert_no_overlaps(name: &str, picture: &Picture) {
    let circles = picture.circles();
    assert!(!circles.is_empty(), "{name}: no states drawn");
    for (i, a) in circles.iter().enumerate() {
        for b in &circles[i + 1..] {
            let distance = (a.0 - b.0).hypot(a.1 - b.1);
            assert!(
                distance >= a.2 + b.2,
                "{name}: circles at {a:?} and {b:?} overlap"
            );
        }
    }
    let texts = picture.texts();
    for (i, (ta, a)) in texts.iter().enumerate() {
        for (tb, b) in &texts[i + 1..] {
            assert!(
                !a.overlaps(b),
                "{name}: labels {:?} {a:?} and {:?} {b:?} overlap",
                ta.lines,
                tb.lines
            );
        }
    }
}

#[test]
fn drilling_graphs_have_no_overlaps() {
    let analysis = example("drilling").analysis();
    for name in ["Ventil_2E", "Bohren", "Motor", "Spanner"] {
        assert_no_overlaps(name, &picture(&analysis, name));
    }
}

/// A 60-state graph with wide BFS layers, back edges, parallel and opposite transitions,
/// self loops, several any- and return transitions and long state names.
fn generated_graph(states: u32) -> String {
    let mut text = String::from("graph Gross <\n");
    for n in 0..states {
        let name = if n % 7 == 0 {
            format!("Zustand mit langem Namen {n}")
        } else {
            format!("S{n}")
        };
        text.push_str(&format!("  state {n} \"{name}\" < >\n"));
    }
    text.push_str("  trans any->0 < U INIT_SD; >\n");
    text.push_str("  trans any->5 manual < U E 0.0; >\n");
    text.push_str("  trans any->5 < U E 0.1; >\n");
    let mut seed: u32 = 12345;
    let mut next = || {
        seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
        (seed >> 16) % states
    };
    // A wide first layer and a tree below it.
    for n in 1..states.min(12) {
        text.push_str(&format!("  trans 0->{n} < >\n"));
    }
    for n in 12..states {
        text.push_str(&format!("  trans {}->{n} auto < >\n", n / 3));
    }
    for _ in 0..40 {
        let (a, b) = (next(), next());
        text.push_str(&format!("  trans {a}->{b} waits < >\n"));
    }
    text.push_str("  trans 3->4 < >\n  trans 4->3 < >\n  trans 3->4 fault < >\n");
    text.push_str("  trans 9->9 < >\n  trans 9->return < >\n  trans 9->return < >\n");
    text.push_str(">\n");
    text
}

#[test]
fn a_large_generated_graph_has_no_overlaps() {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(
            "gross.higraph".into(),
            FileContents::Text(generated_graph(60)),
        )],
        ..WorkspaceData::default()
    });
    let analysis = host.analysis();
    let picture = picture(&analysis, "gross");
    assert_eq!(picture.circles().len(), 60);
    assert_no_overlaps("Gross", &picture);
    let dot = render(&analysis, "Gross", RenderFormat::Dot);
    assert_eq!(dot.matches("shape=circle").count(), 60);
}

/// A minimal XML well-formedness check: one root, balanced and properly nested tags, no
/// raw `<` or `&` in text, quoted attributes.
fn assert_well_formed(name: &str, svg: &str) {
    let mut stack: Vec<String> = Vec::new();
    let mut roots = 0;
    let mut rest = svg;
    while let Some(open) = rest.find('<') {
        let text = &rest[..open];
        check_text(name, text);
        let after = &rest[open + 1..];
        let close = after
            .find('>')
            .unwrap_or_else(|| panic!("{name}: unclosed tag"));
        let tag = &after[..close];
        rest = &after[close + 1..];
        if let Some(closing) = tag.strip_prefix('/') {
            let top = stack.pop();
            assert_eq!(
                top.as_deref(),
                Some(closing.trim()),
                "{name}: mismatched </{closing}>"
            );
            continue;
        }
        let self_closing = tag.ends_with('/');
        let body = tag.trim_end_matches('/');
        let element = body.split_whitespace().next().unwrap_or_default();
        assert!(!element.is_empty(), "{name}: empty tag");
        // Attribute values are quoted and hold no raw `<`.
        assert_eq!(
            body.matches('"').count() % 2,
            0,
            "{name}: unbalanced quotes in <{body}>"
        );
        check_text(name, body);
        if stack.is_empty() {
            roots += 1;
        }
        if !self_closing {
            stack.push(element.to_owned());
        }
    }
    check_text(name, rest);
    assert!(stack.is_empty(), "{name}: unclosed {stack:?}");
    assert_eq!(roots, 1, "{name}: one root element");
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(!svg.contains("<script") && !svg.contains("@import") && !svg.contains("href=\"http"));
}

/// `&` only as an entity.
fn check_text(name: &str, text: &str) {
    for (i, _) in text.match_indices('&') {
        let entity = &text[i..];
        assert!(
            ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
                .iter()
                .any(|e| entity.starts_with(e)),
            "{name}: raw & in {text:?}"
        );
    }
}

#[test]
fn svg_is_well_formed() {
    let drilling = example("drilling").analysis();
    for name in ["Ventil_2E", "Bohren", "Motor", "Spanner", "Bohrmaschine"] {
        assert_well_formed(name, &render(&drilling, name, RenderFormat::Svg));
    }
    let mixer = example("mixer").analysis();
    assert_well_formed("Mischer", &render(&mixer, "Mischer", RenderFormat::Svg));
    // Text that needs escaping.
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(
            "x.higraph".into(),
            FileContents::Text(
                "graph G <\n  state 0 \"a < b & 'c' \\\"d\\\"\" < >\n  trans any->0 \"<&>\" < U INIT_SD; >\n>\n"
                    .into(),
            ),
        )],
        ..WorkspaceData::default()
    });
    let svg = render(&host.analysis(), "G", RenderFormat::Svg);
    assert_well_formed("G", &svg);
    assert!(svg.contains("&lt;") && svg.contains("&amp;"));
}

#[test]
fn chart_and_group_pictures_hold_their_elements() {
    let mixer = example("mixer").analysis();
    let chart = picture(&mixer, "Mischer");
    let texts: Vec<String> = chart
        .texts()
        .iter()
        .flat_map(|(t, _)| t.lines.clone())
        .collect();
    for expected in ["Bereit", "Tank_Ist_Leer", "Temp_Halten", "Ende"] {
        assert!(texts.iter().any(|t| t == expected), "{expected} missing");
    }
    assert!(texts.iter().any(|t| t.contains("loop Naechste")));
    let drilling = example("drilling").analysis();
    let group = picture(&drilling, "Bohrmaschine");
    let boxes: Vec<BBox> = group
        .shapes
        .iter()
        .filter_map(|s| match s {
            higraph_analysis::render::Shape::Rect {
                bbox,
                filled: false,
            } => Some(*bbox),
            _ => None,
        })
        .collect();
    assert_eq!(boxes.len(), 4);
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            assert!(!a.overlaps(b));
        }
    }
    assert_no_overlaps_of_texts("Bohrmaschine", &group);
}

fn assert_no_overlaps_of_texts(name: &str, picture: &Picture) {
    let texts = picture.texts();
    for (i, (ta, a)) in texts.iter().enumerate() {
        for (tb, b) in &texts[i + 1..] {
            assert!(
                !a.overlaps(b),
                "{name}: {:?} and {:?} overlap",
                ta.lines,
                tb.lines
            );
        }
    }
}
