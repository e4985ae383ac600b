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
    assert_arrowheads_visible("Gross", &picture);
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
                ..
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

/// The end point and the direction at the end of an SVG path `M x,y C x1,y1 x2,y2 x3,y3` (or
/// of a chart's `M… H… V… H…` path: only the last two points).
fn path_end(d: &str) -> ((f64, f64), (f64, f64)) {
    let numbers: Vec<f64> = d
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().expect("a number"))
        .collect();
    assert!(numbers.len() >= 8 && d.contains('C'), "a cubic curve: {d}");
    let n = numbers.len();
    let end = (numbers[n - 2], numbers[n - 1]);
    let before = (numbers[n - 4], numbers[n - 3]);
    let (dx, dy) = (end.0 - before.0, end.1 - before.1);
    let len = dx.hypot(dy).max(1e-9);
    (end, (dx / len, dy / len))
}

/// Every arrow of a graph or group picture ends in a visible arrowhead: the path has a
/// marker, its end lies on a node and points into it, and the arrowhead (the last 8 units)
/// lies outside every node and every label.
fn assert_arrowheads_visible(name: &str, picture: &Picture) {
    use higraph_analysis::render::Shape;
    let svg = picture.to_svg();
    assert_eq!(
        // Edge paths (the marker's own triangle is filled).
        svg.matches("<path d=\"M").count() - svg.matches("<path d=\"M0,0 L10,5").count(),
        svg.matches("marker-end=\"url(#arrow)\"").count(),
        "{name}: every edge path has a marker-end"
    );
    let circles = picture.circles();
    let rects: Vec<BBox> = picture
        .shapes
        .iter()
        .filter_map(|s| match s {
            Shape::Rect { bbox, .. } => Some(*bbox),
            _ => None,
        })
        .collect();
    let inside_node = |(x, y): (f64, f64), slack: f64| {
        circles
            .iter()
            .any(|&(cx, cy, r)| (x - cx).hypot(y - cy) < r + slack)
            || rects.iter().any(|b| {
                x > b.x - slack && x < b.x + b.w + slack && y > b.y - slack && y < b.y + b.h + slack
            })
    };
    let texts = picture.texts();
    let mut arrows = 0;
    for shape in &picture.shapes {
        let Shape::Path { d, arrow, .. } = shape else {
            continue;
        };
        assert!(*arrow, "{name}: {d} has no arrowhead");
        arrows += 1;
        let (end, dir) = path_end(d);
        assert!(
            inside_node((end.0 + dir.0 * 3.0, end.1 + dir.1 * 3.0), 0.0),
            "{name}: {d} does not point into a node"
        );
        for back in [4.0, 8.0] {
            let p = (end.0 - dir.0 * back, end.1 - dir.1 * back);
            assert!(
                !inside_node(p, -0.5),
                "{name}: the arrowhead of {d} is under a node"
            );
            for (text, b) in &texts {
                assert!(
                    !(p.0 > b.x && p.0 < b.x + b.w && p.1 > b.y && p.1 < b.y + b.h),
                    "{name}: the arrowhead of {d} is under the label {:?}",
                    text.lines
                );
            }
        }
    }
    assert!(arrows > 0, "{name}: no arrows");
}

/// Width to height of the whole picture.
fn aspect(picture: &Picture) -> f64 {
    let b = picture.bounds();
    b.w / b.h
}

#[test]
fn every_arrow_of_the_drilling_pictures_has_a_visible_head() {
    let analysis = example("drilling").analysis();
    for name in ["Ventil_2E", "Bohren", "Motor", "Spanner", "Bohrmaschine"] {
        assert_arrowheads_visible(name, &picture(&analysis, name));
    }
}

#[test]
fn drilling_graphs_are_about_as_wide_as_high() {
    let analysis = example("drilling").analysis();
    for name in ["Ventil_2E", "Bohren", "Motor", "Spanner"] {
        let ratio = aspect(&picture(&analysis, name));
        assert!((0.5..=2.0).contains(&ratio), "{name}: width/height {ratio}");
    }
}

/// A cycle of `n` states (`0 -> 1 -> … -> n-1 -> 1`) with a startup transition, named.
fn cycle(n: u32) -> String {
    let mut text = String::from("graph Kreis <\n");
    for s in 0..n {
        text.push_str(&format!("  state {s} \"Schritt {s}\" < >\n"));
    }
    text.push_str("  trans any->0 < U INIT_SD; >\n");
    for s in 0..n - 1 {
        text.push_str(&format!("  trans {s}->{} < >\n", s + 1));
    }
    text.push_str(&format!("  trans {}->1 < >\n>\n", n - 1));
    text
}

fn single_file(text: String) -> AnalysisHost {
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![("g.higraph".into(), FileContents::Text(text))],
        ..WorkspaceData::default()
    });
    host
}

#[test]
fn cycles_of_up_to_20_states_are_drawn_in_rows_not_a_column() {
    for n in [3, 5, 8, 12, 16, 20] {
        let host = single_file(cycle(n));
        let picture = picture(&host.analysis(), "Kreis");
        let ratio = aspect(&picture);
        assert!(
            (0.5..=2.0).contains(&ratio),
            "{n} states: width/height {ratio}"
        );
        assert_no_overlaps(&format!("cycle of {n}"), &picture);
        assert_arrowheads_visible(&format!("cycle of {n}"), &picture);
    }
}

#[test]
fn transitions_are_labelled_with_priority_and_attributes() {
    let host = single_file(
        "graph G <\n  state 0 < >\n  state 1 < >\n  trans any->0 < U INIT_SD; >\n  trans 0->1 prio 2 auto waits < >\n  trans 0->1 prio 1 fault < >\n>\n"
            .to_string(),
    );
    let picture = picture(&host.analysis(), "G");
    let labels: Vec<String> = picture
        .texts()
        .iter()
        .flat_map(|(t, _)| t.lines.clone())
        .collect();
    assert!(labels.contains(&"2 auto waits".to_string()), "{labels:?}");
    assert!(labels.contains(&"1 fault".to_string()), "{labels:?}");
    // The two parallel arrows are fanned out: different paths.
    let paths: Vec<&str> = picture
        .shapes
        .iter()
        .filter_map(|s| match s {
            higraph_analysis::render::Shape::Path { d, .. } => Some(d.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(paths.len(), 3);
    assert_ne!(paths[1], paths[2]);
    assert_arrowheads_visible("G", &picture);
}

#[test]
fn a_long_chain_renders_in_layers() {
    // 16 000 states in a cycle: the layout must be (near) linear; a quadratic one takes
    // minutes here.
    let host = single_file(cycle(16_000));
    let picture = picture(&host.analysis(), "Kreis");
    assert_eq!(picture.circles().len(), 16_000);
    let ratio = aspect(&picture);
    assert!((0.25..=4.0).contains(&ratio), "width/height {ratio}");
}

#[test]
fn svg_of_the_examples() {
    let drilling = example("drilling").analysis();
    for name in ["Ventil_2E", "Bohren", "Bohrmaschine"] {
        insta::assert_snapshot!(
            format!("svg_{}", name.to_lowercase()),
            render(&drilling, name, RenderFormat::Svg)
        );
    }
    let mixer = example("mixer").analysis();
    insta::assert_snapshot!("svg_mischer", render(&mixer, "Mischer", RenderFormat::Svg));
}

/// No transition label lies on an arrow: no point of a curve is inside its box. (State
/// numbers sit inside their circles; state names are placed first and arrows avoid them
/// where a modest arc can, which is not always.)
fn assert_labels_clear_of_arrows(name: &str, picture: &Picture) {
    use higraph_analysis::render::Shape;
    let circles = picture.circles();
    let is_state_name = |x: f64, y: f64| {
        circles
            .iter()
            .any(|&(cx, cy, r)| (x - cx).abs() < 0.01 && (y - (cy + r + 12.0)).abs() < 0.01)
    };
    let texts: Vec<(String, BBox)> = picture
        .texts()
        .into_iter()
        .filter(|(t, _)| !t.bold && !is_state_name(t.x, t.y))
        .map(|(t, b)| (t.lines.join(" "), b.inflate(-1.0)))
        .collect();
    for shape in &picture.shapes {
        let Shape::Path { d, .. } = shape else {
            continue;
        };
        let v: Vec<f64> = d
            .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().expect("a number"))
            .collect();
        let p = |i: usize| (v[2 * i], v[2 * i + 1]);
        let (p0, p1, p2, p3) = (p(0), p(1), p(2), p(3));
        for i in 0..=200 {
            let t = f64::from(i) / 200.0;
            let u = 1.0 - t;
            let (a, b, c, e) = (u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t);
            let x = a * p0.0 + b * p1.0 + c * p2.0 + e * p3.0;
            let y = a * p0.1 + b * p1.1 + c * p2.1 + e * p3.1;
            for (text, bx) in &texts {
                assert!(
                    !(x > bx.x && x < bx.x + bx.w && y > bx.y && y < bx.y + bx.h),
                    "{name}: the arrow {d} crosses the label {text:?}"
                );
            }
        }
    }
}

#[test]
fn labels_do_not_lie_on_arrows() {
    let analysis = example("drilling").analysis();
    // Graphs (the group's wide message labels may have to sit on a link between close
    // boxes; they are drawn on a white backing).
    for name in ["Ventil_2E", "Bohren", "Motor", "Spanner"] {
        assert_labels_clear_of_arrows(name, &picture(&analysis, name));
    }
    for n in [3, 8, 12, 20] {
        let host = single_file(cycle(n));
        assert_labels_clear_of_arrows(
            &format!("cycle of {n}"),
            &picture(&host.analysis(), "Kreis"),
        );
    }
}

/// The SVG names what a trace viewer animates: states, transitions (`A->B:PRIO`), instances,
/// and the steps and transitions of each sequencer.
#[test]
fn svg_carries_data_attributes_for_the_trace_viewer() {
    let drilling = example("drilling").analysis();
    let bohren = render(&drilling, "Bohren", RenderFormat::Svg);
    for attribute in [
        "<circle cx=",
        "data-state=\"0\"",
        "data-state=\"8\"",
        "data-trans=\"any-&gt;0:1\"",
        "data-trans=\"5-&gt;6:1\"",
        "data-trans=\"8-&gt;1:1\"",
    ] {
        assert!(bohren.contains(attribute), "{attribute} in\n{bohren}");
    }
    assert_eq!(bohren.matches("data-state=").count(), 9);
    let group = render(&drilling, "Bohrmaschine", RenderFormat::Svg);
    assert_eq!(group.matches("data-instance=").count(), 4, "{group}");
    let mixer = example("mixer").analysis();
    let chart = render(&mixer, "Mischer", RenderFormat::Svg);
    for attribute in [
        "data-sequencer=\"Ablauf\" data-step=\"Bereit\"",
        "data-sequencer=\"Ablauf\" data-trans=\"Tank_Ist_Leer\"",
        "data-sequencer=\"Ablauf\" data-trans=\"Verwerfen\"",
    ] {
        assert!(chart.contains(attribute), "{attribute} in\n{chart}");
    }
    // An unnumbered priority leaves `:PRIO` out; return transitions end in `return`.
    let host = single_file(
        "graph R <\n  state 0 < >\n  state 1 < >\n  trans any->0 prio 1 < U INIT_SD; >\n  trans 0->1 prio 2 < >\n  trans 1->return prio 1 < >\n>\n"
            .to_owned(),
    );
    let svg = render(&host.analysis(), "R", RenderFormat::Svg);
    assert!(svg.contains("data-trans=\"1-&gt;return:1\""), "{svg}");
    assert!(svg.contains("data-trans=\"0-&gt;1:2\""), "{svg}");
}
