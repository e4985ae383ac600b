//! The workloads have the shape `tooling.md` §7 promises, read off the text without a parser.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use higraph_workload::{MAX_GROUP_RENAME, PLANT_SYMBOLS, max_graph, max_group, plant};

/// A generated transition: header line and the number of statements in its body.
struct Trans {
    source: String,
    prio: Option<u32>,
    statements: usize,
}

/// Transitions of generated text (headers at two spaces of indentation; a body is either on
/// the header line or ends with a line `  >`).
fn transitions(text: &str) -> Vec<Trans> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let Some(rest) = line.strip_prefix("  trans ") else {
            continue;
        };
        let source = rest.split("->").next().unwrap().to_string();
        let words: Vec<&str> = rest.split_whitespace().collect();
        let prio = words
            .iter()
            .position(|w| *w == "prio")
            .map(|i| words[i + 1].parse().unwrap());
        let mut statements = 0;
        if line.ends_with(" >") {
            statements = line.matches(';').count();
        } else {
            for body in lines.by_ref() {
                if body == "  >" {
                    break;
                }
                statements += body.matches(';').count();
            }
        }
        out.push(Trans {
            source,
            prio,
            statements,
        });
    }
    out
}

/// Identifier-like words of `text` with their counts (strings and comments included).
fn word_counts(text: &str) -> HashMap<&str, usize> {
    let mut counts = HashMap::new();
    for w in text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')) {
        if !w.is_empty() {
            *counts.entry(w).or_insert(0) += 1;
        }
    }
    counts
}

/// Declared variable names (lines `NAME : TYPE ...;` inside sections).
fn declared(text: &str) -> Vec<&str> {
    text.lines()
        .flat_map(|l| l.split(';'))
        .filter_map(|decl| {
            let decl = decl.rsplit('<').next().unwrap().trim();
            let (name, ty) = decl.split_once(" : ")?;
            let ty = ty.split_whitespace().next()?;
            let known = [
                "BOOL", "INT", "WORD", "DINT", "REAL", "TIME", "TIMER", "COUNTER",
            ];
            (known.contains(&ty) || ty.starts_with("STRING[")).then_some(name.trim())
        })
        .collect()
}

#[test]
fn deterministic_by_seed() {
    assert_eq!(max_graph(1), max_graph(1));
    assert_ne!(max_graph(1), max_graph(2));
    assert_eq!(max_group(5), max_group(5));
    assert_eq!(plant(9), plant(9));
}

#[test]
fn max_graph_is_at_the_limits() {
    for seed in [1, 2] {
        let text = max_graph(seed);
        let states: Vec<u32> = text
            .lines()
            .filter_map(|l| l.strip_prefix("  state "))
            .map(|r| r.split_whitespace().next().unwrap().parse().unwrap())
            .collect();
        assert_eq!(states, (0..255).collect::<Vec<_>>());

        let ts = transitions(&text);
        assert_eq!(ts.len(), 4090);
        assert!(text.contains("  trans any->0 prio 1 \"startup\" < U INIT_SD; >"));
        for t in &ts[1..] {
            assert!(
                (3..=6).contains(&t.statements),
                "{} statements",
                t.statements
            );
        }
        // Distinct priorities per source state (any-transitions form one range).
        let mut ranges: BTreeMap<&str, BTreeSet<u32>> = BTreeMap::new();
        for t in &ts {
            let p = t.prio.expect("max-graph writes every priority");
            assert!(
                ranges.entry(&t.source).or_default().insert(p),
                "priority {p} twice from {}",
                t.source
            );
        }
        assert!(text.contains("msg in;") && text.contains("msg out;"));
    }
}

#[test]
fn every_declared_variable_is_used() {
    let mut texts = vec![max_graph(1)];
    texts.extend(
        max_group(1)
            .into_iter()
            .filter(|(p, _)| p.starts_with("graphs/"))
            .map(|(_, t)| t),
    );
    for text in &texts {
        let counts = word_counts(text);
        for name in declared(text) {
            assert!(counts[name] >= 2, "{name} is declared but never used");
        }
    }
}

#[test]
fn max_group_wires_every_message() {
    let files = max_group(1);
    let graphs: Vec<_> = files
        .iter()
        .filter(|(p, _)| p.starts_with("graphs/"))
        .collect();
    assert_eq!(graphs.len(), 20);
    for (path, text) in &graphs {
        assert!(
            text.contains(" msg in;") && text.contains(" msg out;"),
            "{path} lacks a message"
        );
    }
    let group = &files
        .iter()
        .find(|(p, _)| p == MAX_GROUP_RENAME.group_file)
        .unwrap()
        .1;
    let instances: Vec<&str> = group
        .lines()
        .filter_map(|l| l.strip_prefix("  instance "))
        .map(|r| r.split(' ').next().unwrap())
        .collect();
    assert_eq!(instances.len(), 255);
    assert_eq!(instances.iter().collect::<BTreeSet<_>>().len(), 255);
    assert_eq!(instances[0], MAX_GROUP_RENAME.instance);
    let target = format!(
        "{}.{};",
        MAX_GROUP_RENAME.instance, MAX_GROUP_RENAME.variable
    );
    assert_eq!(
        group.matches(&target).count(),
        255,
        "every instance sends to {target}"
    );
    // Every internal message names an existing instance; every instance receives IM_Start.
    let receivers: BTreeSet<&str> = group
        .lines()
        .filter_map(|l| l.trim().strip_suffix(".IM_Start;"))
        .map(|l| l.rsplit(' ').next().unwrap())
        .collect();
    assert_eq!(receivers, instances.iter().copied().collect());
    let declaring = &files
        .iter()
        .find(|(p, _)| p == MAX_GROUP_RENAME.file)
        .unwrap()
        .1;
    assert!(declaring.contains(&format!("{} : BOOL msg in;", MAX_GROUP_RENAME.variable)));
}

#[test]
fn plant_has_its_parts() {
    let files = plant(1);
    let all: String = files.iter().map(|(_, t)| t.as_str()).collect();
    let count = |prefix: &str| all.lines().filter(|l| l.starts_with(prefix)).count();
    assert_eq!(count("graph "), 300);
    assert_eq!(count("group "), 20);
    assert_eq!(count("chart "), 10);
    assert_eq!(count("chart type "), 2);
    assert_eq!(count("  instance "), 300);
    assert!(all.contains("parallel <") && all.contains("alt <") && all.contains("loop "));
    assert!(all.contains("mnemonic international;"));

    let symbols = &files
        .iter()
        .find(|(p, _)| p == "common/symbole.higraph")
        .unwrap()
        .1;
    let names: Vec<String> = symbols
        .lines()
        .filter(|l| l.starts_with("  ") && l.ends_with(';'))
        .map(|l| l.split(" : ").next().unwrap().trim().to_ascii_lowercase())
        .collect();
    assert_eq!(names.len(), PLANT_SYMBOLS);
    assert_eq!(
        names.iter().collect::<BTreeSet<_>>().len(),
        PLANT_SYMBOLS,
        "symbol names are unique"
    );
    let addresses: Vec<&str> = symbols
        .lines()
        .filter(|l| l.starts_with("  ") && l.ends_with(';'))
        .map(|l| {
            let rest = l.split_once(" : ").unwrap().1;
            let words: Vec<&str> = rest.split_whitespace().collect();
            // area and number (`E 1.0`, `FC 10`), without the type and comment
            let end = rest.find(words[1]).unwrap() + words[1].len();
            rest[..end].trim_end_matches(';')
        })
        .collect();
    assert_eq!(
        addresses.iter().collect::<BTreeSet<_>>().len(),
        addresses.len(),
        "addresses are unique"
    );
    assert!(names.iter().all(|n| n.starts_with('"') || n.len() <= 24));

    let folders: BTreeSet<&str> = files
        .iter()
        .filter_map(|(p, _)| p.split_once('/').map(|x| x.0))
        .collect();
    assert!(folders.len() >= 22, "{folders:?}");
}

/// Pins the generated text, so benchmark figures stay comparable. If a generator changes on
/// purpose, update the value (and say so where figures are reported).
#[test]
fn output_is_pinned() {
    fn fnv(text: &str) -> u64 {
        text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
    }
    let text = max_graph(1);
    assert_eq!(
        (text.len(), fnv(&text)),
        (566_981, 11_119_620_050_930_271_289),
        "max_graph(1) changed"
    );
    let all =
        |files: Vec<(String, String)>| files.into_iter().map(|(p, t)| p + &t).collect::<String>();
    let group = all(max_group(1));
    assert_eq!(
        (group.len(), fnv(&group)),
        (262_440, 6_840_293_651_724_081_267),
        "max_group(1) changed"
    );
    let plant = all(plant(1));
    assert_eq!(
        (plant.len(), fnv(&plant)),
        (1_993_836, 159_718_594_183_103_545),
        "plant(1) changed"
    );
}
