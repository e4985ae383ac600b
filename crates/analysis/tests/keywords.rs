//! Keywords are contextual (language.md §7): a graph, its variables, a group, its instances,
//! the symbols they wire and a test may be named like any keyword of the language, and the analysis then
//! reports nothing but what such a name gets anyway (HG1103 for reserved words, HG4102 for
//! address areas).

mod common;

use higraph_syntax::SyntaxKind;

/// Workspaces with names replaced by `word` (`{k}`): graphs, their variables, groups,
/// instances, formals, actuals, message targets and symbols named `word`. (Graphs, groups and
/// symbols share one namespace, so each workspace names only one of them `word`.)
const TEMPLATES: &[&str] = &[
    "\
graph {k} <
  in < {k} : BOOL; >
  out < Lampe : BOOL; >
  in_out < IM : BOOL msg in; OM : BOOL msg out; >
  state 0 < >
  state 1 < C: U {k}; = Lampe; >
  trans any->0 prio 1 < U INIT_SD; >
  trans 0->1 prio 1 < U {k}; U IM; !: R IM; S OM; >
  trans 1->0 prio 1 < UN {k}; !: R OM; >
>
symbols < Taster : E 0.0; Lampe1 : A 0.0; Lampe2 : A 0.1; >
group Anlage fc FC 1 db DB 1 <
  instance {k} : {k} < {k} := Taster; Lampe := Lampe1; OM := Zweite.IM; >
  instance Zweite : {k} < {k} := Taster; Lampe := Lampe2; OM := {k}.IM; >
>
",
    "\
graph Ventil < in < {k} : BOOL; > out < Auf : BOOL; >
  state 0 < > state 1 < C: = Auf; >
  trans any->0 prio 1 < U INIT_SD; > trans 0->1 prio 1 < U {k}; > trans 1->0 prio 1 < UN {k}; >
>
symbols < Taster : E 0.0; Ventil_Auf : A 0.0; >
group {k} fc FC 1 db DB 1 < instance {k} : Ventil < {k} := Taster; Auf := Ventil_Auf; > >
",
    "\
graph Ventil < in < Oben : BOOL; > out < Auf : BOOL; >
  state 0 < > state 1 < C: = Auf; >
  trans any->0 prio 1 < U INIT_SD; > trans 0->1 prio 1 < U Oben; > trans 1->0 prio 1 < UN Oben; >
>
symbols < {k} : E 0.0; Ventil_Auf : A 0.0; >
group Anlage fc FC 1 db DB 1 < instance V : Ventil < Oben := {k}; Auf := Ventil_Auf; > >
test {k} < run Anlage; step; expect not Ventil_Auf; >
",
];

#[test]
fn every_keyword_may_name_graphs_variables_groups_instances_and_symbols() {
    let mut failures = Vec::new();
    for &(word, kind) in SyntaxKind::KEYWORDS.iter() {
        use SyntaxKind::*;
        // What such names get anyway (language.md §7): the operators, `ANY` (a type) and
        // `SET` and `MOD` (STL operations) are reserved words (HG1103); `FC` and `DB` are
        // address areas, so STL writes `#fc` (HG4102).
        let expected: &[&str] = match kind {
            AND_KW | OR_KW | XOR_KW | NOT_KW | ANY_KW | SET_KW | MOD_KW => &["HG1103"],
            FC_KW | DB_KW => &["HG4102"],
            _ => &[],
        };
        for (i, template) in TEMPLATES.iter().enumerate() {
            let text = template.replace("{k}", word);
            let host = common::load_fixture(&[("main.higraph".to_owned(), text.into_bytes())]);
            for (_, diagnostics) in host.analysis().diagnostics() {
                for d in diagnostics {
                    if expected.contains(&d.code.as_str()) {
                        continue;
                    }
                    failures.push(format!("'{word}' in {i}: {} {}", d.code, d.message));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
