//! Inlay hints (`tooling.md` §4).
//!
//! * **State names** after the endpoints of a transition header: `trans 1->2` shows
//!   `Oben → Ab`. An endpoint without a display name shows its number, `any` and `return`
//!   show as written, and a transition none of whose states has a name gets no hint (it would
//!   only repeat the numbers).
//! * **Formal types** after the value of an actual parameter, where the formal's type differs
//!   in kind from the value: `Menge := MW 10;` shows `: INT` after `MW 10`. "Differs in kind"
//!   means that the value's own type is not the formal's type (`STRING` lengths ignored): an
//!   address has the type of its size (`MW 10` is a WORD, `E 1.0` a BOOL), a symbol its
//!   declared type, a constant the type of its literal (`5` is an INT, `T#5S` a TIME). So a
//!   word wired to an INT formal, a byte symbol wired to a BOOL formal or `5` wired to a DINT
//!   formal get a hint; a BOOL symbol wired to a BOOL formal does not. Values whose type is
//!   unknown (unresolved names, `Inst.Msg` message targets) and formals whose type is unknown
//!   get none.
//!
//! Labels carry no padding; the language server adds a space before them.

use std::collections::HashMap;

use higraph_syntax::{
    SyntaxNode, TextRange, TextSize,
    ast::{self, AstNode, EndpointKind},
    literal,
};

use super::completion::graph_members;
use crate::{
    Analysis, Cancellable,
    db::{self, File, ItemLoc, Workspace},
    index::{self, GlobalIndex},
    lang::{Mnemonic, Type},
    resolve,
    rules::group::interface::{PREDEFINED_FORMALS, graph_interface},
};

/// A piece of text the editor shows inside the code.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InlayHint {
    /// Where the hint stands (it is shown before the character at this offset).
    pub offset: TextSize,
    /// The text shown (without padding).
    pub label: String,
    /// What the hint shows.
    pub kind: InlayKind,
}

/// What an inlay hint shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InlayKind {
    /// The names of a transition's states, after its header's endpoints.
    StateNames,
    /// The formal's type, after the value of an actual parameter.
    FormalType,
}

impl Analysis {
    /// The inlay hints of a file whose offsets lie in `range` (the whole file if `None`), in
    /// text order.
    pub fn inlay_hints(&self, path: &str, range: Option<TextRange>) -> Cancellable<Vec<InlayHint>> {
        self.with_db(|db, ws| {
            let Some(file) = self.file(path) else {
                return Vec::new();
            };
            hints(db, ws, file, range)
        })
    }
}

fn hints(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    range: Option<TextRange>,
) -> Vec<InlayHint> {
    let root = db::parse(db, file).syntax_node();
    let range = range.unwrap_or(root.text_range());
    let mut out = Vec::new();
    let items = root
        .children()
        .filter(|n| ast::Item::cast(n.clone()).is_some());
    for (index, node) in items.enumerate() {
        if !touches(node.text_range(), range) {
            continue;
        }
        let Ok(index) = u32::try_from(index) else {
            break;
        };
        match ast::Item::cast(node) {
            Some(ast::Item::Graph(graph)) => {
                let item = ItemLoc::new(db, file, index);
                state_name_hints(db, item, &graph, range, &mut out);
            }
            Some(ast::Item::Group(group)) => {
                let cx = GroupCx {
                    db,
                    index: db::global_index(db, ws),
                    mnemonic: db::file_mnemonic(db, ws, file),
                };
                formal_type_hints(&cx, &group, range, &mut out);
            }
            _ => {}
        }
    }
    out.retain(|hint| range.contains_inclusive(hint.offset));
    out
}

/// Do the ranges overlap or touch?
fn touches(a: TextRange, b: TextRange) -> bool {
    a.start() <= b.end() && b.start() <= a.end()
}

/// The members of a graph or group body that touch `range`. The first one is found by binary
/// search, so a small range in a large graph costs little.
fn members_in(body: Option<ast::Body>, range: TextRange) -> Vec<SyntaxNode> {
    let Some(body) = body else {
        return Vec::new();
    };
    let node = body.syntax();
    let Some(visible) = range.intersect(node.text_range()) else {
        return Vec::new();
    };
    let first = node
        .child_or_token_at_range(TextRange::empty(visible.start()))
        .or_else(|| node.first_child_or_token());
    std::iter::successors(first, |e| e.next_sibling_or_token())
        .filter_map(|e| e.into_node())
        .skip_while(|n| n.text_range().end() < range.start())
        .take_while(|n| n.text_range().start() <= range.end())
        .collect()
}

// ------------------------------------------------------------------------------ state names

fn state_name_hints(
    db: &dyn salsa::Database,
    item: ItemLoc<'_>,
    graph: &ast::Graph,
    range: TextRange,
    out: &mut Vec<InlayHint>,
) {
    let members = graph_members(db, item);
    let mut names: HashMap<u32, &str> = HashMap::new();
    for state in &members.states {
        if let Some(name) = &state.name {
            names.entry(state.number).or_insert(name.as_str());
        }
    }
    if names.is_empty() {
        return;
    }
    for node in members_in(graph.body(), range) {
        let Some(trans) = ast::Trans::cast(node) else {
            continue;
        };
        let (source, target) = (trans.source(), trans.target());
        let Some(end) = target.as_ref().map(|t| t.syntax().text_range().end()) else {
            continue;
        };
        if let Some(label) =
            transition_label(source.as_ref(), target.as_ref(), |n| names.get(&n).copied())
        {
            out.push(InlayHint {
                offset: end,
                label,
                kind: InlayKind::StateNames,
            });
        }
    }
}

/// `Oben → Ab` for a transition, given the display names of the states by number; `None`
/// when neither endpoint is a state with a name.
pub(crate) fn transition_label<'n>(
    source: Option<&ast::Endpoint>,
    target: Option<&ast::Endpoint>,
    name_of: impl Fn(u32) -> Option<&'n str>,
) -> Option<String> {
    let mut named = false;
    let mut part = |endpoint: Option<&ast::Endpoint>| -> String {
        let Some(token) = endpoint.and_then(|e| e.token()) else {
            return "?".to_owned();
        };
        match endpoint.and_then(|e| e.kind()) {
            Some(EndpointKind::State) => {
                match token.text().parse::<u32>().ok().and_then(&name_of) {
                    Some(name) => {
                        named = true;
                        name.to_owned()
                    }
                    None => token.text().to_owned(),
                }
            }
            _ => token.text().to_ascii_lowercase(),
        }
    };
    let label = format!("{} → {}", part(source), part(target));
    named.then_some(label)
}

// ------------------------------------------------------------------------------ formal types

/// What formal type hints need.
struct GroupCx<'a> {
    db: &'a dyn salsa::Database,
    index: &'a GlobalIndex,
    mnemonic: Mnemonic,
}

fn formal_type_hints(
    cx: &GroupCx<'_>,
    group: &ast::Group,
    range: TextRange,
    out: &mut Vec<InlayHint>,
) {
    for node in members_in(group.body(), range) {
        let Some(instance) = ast::Instance::cast(node) else {
            continue;
        };
        let Some(graph) = instance.graph().and_then(|g| cx.index.graph(&g.text())) else {
            continue;
        };
        let interface = graph_interface(cx.db, ItemLoc::new(cx.db, graph.file, graph.item));
        let actuals = instance
            .actuals()
            .filter(|a| touches(a.syntax().text_range(), range));
        for actual in actuals {
            let Some(formal) = actual.formal().map(|f| f.text()) else {
                continue;
            };
            let formal_ty = match interface.var(&formal) {
                Some(var) => var.ty,
                None => PREDEFINED_FORMALS
                    .iter()
                    .any(|p| p.eq_ignore_ascii_case(&formal))
                    .then_some(Type::Bool),
            };
            let Some(formal_ty) = formal_ty else { continue };
            let Some(value) = actual.value() else {
                continue;
            };
            let Some(value_ty) = value_type(cx, &value) else {
                continue;
            };
            if !same_type(value_ty, formal_ty) {
                out.push(InlayHint {
                    offset: value.syntax().text_range().end(),
                    label: format!(": {formal_ty}"),
                    kind: InlayKind::FormalType,
                });
            }
        }
    }
}

/// The type of an actual value, resolved as in a group (`diagnostics.md` §2.4): an address,
/// an identifier that is an address written without a space, a global symbol, a constant.
fn value_type(cx: &GroupCx<'_>, value: &ast::Operand) -> Option<Type> {
    match value {
        ast::Operand::Address(address) => {
            index::read_address(&address.compact_text(), cx.mnemonic).map(|a| a.ty())
        }
        ast::Operand::NameRef(name) => {
            let text = name.text();
            match resolve::address_without_space(&text, cx.mnemonic).and_then(|r| r.address.ok()) {
                Some(address) => Some(address.ty()),
                None => cx.index.symbol(&text).and_then(|s| s.ty),
            }
        }
        ast::Operand::SymbolRef(symbol) => cx.index.symbol(&symbol.name()).and_then(|s| s.ty),
        ast::Operand::Literal(lit) => literal::check_literal(&lit.text())
            .ok()
            .and_then(|l| resolve::literal_type(&l)),
        _ => None,
    }
}

/// Equal types; `STRING` lengths are not compared.
fn same_type(a: Type, b: Type) -> bool {
    matches!((a, b), (Type::String(_), Type::String(_))) || a == b
}

#[cfg(test)]
mod tests {
    use higraph_syntax::TextRange;

    use crate::ide::fixture;

    /// The hints of the cursor's file (of the selection between two `$0`, if any), each shown
    /// in its line: the line up to the hint, `⟨label⟩`, the rest of the line.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let path = f.position.path.clone();
        let hints = f
            .host
            .analysis()
            .inlay_hints(&path, f.selection)
            .expect("not cancelled");
        let source = f.text(&path);
        hints
            .iter()
            .map(|hint| {
                let at = usize::from(hint.offset);
                let line_start = source[..at].rfind('\n').map_or(0, |i| i + 1);
                let line_end = source[at..].find('\n').map_or(source.len(), |i| at + i);
                format!(
                    "{:?}: {}⟨{}⟩{}",
                    hint.kind,
                    source[line_start..at].trim_start(),
                    hint.label,
                    &source[at..line_end]
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn state_names_after_transition_headers() {
        insta::assert_snapshot!(check(r#"$0
graph Ventil_2E <
  state 0 "Initialisierung" < >
  state 1 "Oben" < >
  state 2 "Ab" < >
  state 3 < >
  trans any->0 prio 1 "startup" < U INIT_SD; >
  trans 0->1 < >
  trans 1->2 prio 1 auto < >
  trans 2->3 < >
  trans 3->return < >
  trans 2->return < >
  trans 3->3 < >
  trans 1->9 < >
>
"#), @r#"
StateNames: trans any->0⟨any → Initialisierung⟩ prio 1 "startup" < U INIT_SD; >
StateNames: trans 0->1⟨Initialisierung → Oben⟩ < >
StateNames: trans 1->2⟨Oben → Ab⟩ prio 1 auto < >
StateNames: trans 2->3⟨Ab → 3⟩ < >
StateNames: trans 2->return⟨Ab → return⟩ < >
StateNames: trans 1->9⟨Oben → 9⟩ < >
"#);
    }

    #[test]
    fn graphs_without_state_names_have_no_hints() {
        assert_eq!(
            check("$0graph G < state 0 < > state 1 < > trans 0->1 < > >"),
            ""
        );
    }

    #[test]
    fn hints_only_in_the_range() {
        let text = r#"
graph G <
  state 0 "A" < >
  state 1 "B" < >
  trans 0->1 < >
  $0trans 1->0 < >
  trans 0->0 < >$0
  trans 1->1 < >
>
"#;
        insta::assert_snapshot!(check(text), @r#"
StateNames: trans 1->0⟨B → A⟩ < >
StateNames: trans 0->0⟨A → A⟩ < >
"#);
    }

    #[test]
    fn formal_types_where_the_value_differs_in_kind() {
        insta::assert_snapshot!(check(r#"//- graphs.higraph
graph Dosierer <
  in < Menge : INT; Start : BOOL; Grenze : DINT; Zeit : TIME; Text : STRING[10]; Zaehler : COUNTER; >
  out < Fertig : BOOL; Stand : WORD; >
  in_out < OM_Fertig : BOOL msg out; >
>
//- symbols.higraph
symbols <
  Starttaster : E 0.0 BOOL;
  Menge_Soll : MW 10 INT;
  Status : MB 3;
  "Zeit Soll" : MD 20 TIME;
>
//- group.higraph
$0group G <
  instance A : Dosierer <
    Menge     := MW 12;
    Start     := Starttaster;
    Grenze    := 5;
    Zeit      := "Zeit Soll";
    Text      := 'abc';
    Zaehler   := Z 3;
    Fertig    := Status;
    Stand     := MW14;
    ManualMode := M 1.0;
    AutomaticMode := MB 2;
    OM_Fertig := B.IM_X;
    Unbekannt := MW 2;
  >
  instance B : Dosierer <
    Menge := Menge_Soll;
    Start := Nirgends;
    Grenze := L#5;
  >
>
"#), @r#"
FormalType: Menge     := MW 12⟨: INT⟩;
FormalType: Grenze    := 5⟨: DINT⟩;
FormalType: Fertig    := Status⟨: BOOL⟩;
FormalType: AutomaticMode := MB 2⟨: BOOL⟩;
"#);
    }

    #[test]
    fn international_addresses() {
        let text = "//- higraph.toml\n[workspace]\nmnemonic = \"international\"\n//- a.higraph\ngraph G < in < X : WORD; > >\n$0group Gr < instance I : G < X := IB 4; > >\n";
        insta::assert_snapshot!(check(text), @"FormalType: group Gr < instance I : G < X := IB 4⟨: WORD⟩; > >");
    }

    #[test]
    fn no_hints_for_unknown_files_or_empty_ranges() {
        let f = fixture::load("$0graph G < state 0 \"A\" < > trans 0->0 < > >");
        let analysis = f.host.analysis();
        assert_eq!(
            analysis.inlay_hints("nope.higraph", None).ok(),
            Some(Vec::new())
        );
        let empty = TextRange::empty(0.into());
        assert_eq!(
            analysis.inlay_hints("main.higraph", Some(empty)).ok(),
            Some(Vec::new())
        );
    }
}
