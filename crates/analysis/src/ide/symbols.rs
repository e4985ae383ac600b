//! Document symbols (the outline of a file) and workspace symbols (`tooling.md` §4).
//!
//! The outline of each item is a salsa query ([`item_outline`]) with ranges relative to the
//! item's start, so it is computed once per version of the item and reused while other items
//! are edited; [`Analysis::document_symbols`] only shifts it into place.
//!
//! The hierarchy:
//!
//! * graph › sections `in` `out` `in_out` `stat` › variables; states; transitions;
//! * group › instances;
//! * chart › sections › variables; sequencers › steps and transitions (also jumps and loops).
//!   The steps and transitions inside `parallel` and `alt` branches are listed in text order
//!   under their sequencer, as if the branches were flat;
//! * symbols › symbol;
//! * block interface › sections › variables.
//!
//! Names: a state is `3 "Unten"` (number and display name, or just the number); a
//! transition is `1->2` as its endpoints are written, with its display name if it has one
//! (`any->0 "startup"`) and the names of its states as detail (`Oben → Ab`); a jump is
//! `J1 -> START`.
//!
//! Workspace symbols are the graphs, groups, charts, global symbols (declared and imported),
//! instances, states and steps of the workspace. Names of nested symbols are qualified by
//! their container, `.`-separated: `Bohrmaschine.Vorschub` (instance), `Ventil_2E.3 "Unten"`
//! (state), `Mischer.RUN.HEIZEN` (step). A symbol matches a query when the query's characters
//! appear in its qualified name in order, ignoring case; the best matches come first: an exact
//! name, then a name that starts with the query, then one that contains it, then the other
//! matches with the fewest gaps; at most [`WORKSPACE_SYMBOL_LIMIT`] are returned.

use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode},
};

use super::{NavigationTarget, SymbolKind};
use crate::{
    Analysis, Cancellable,
    db::{self, File, ItemLoc, Workspace},
    index::SymbolSource,
    lang::Section,
};

/// The most workspace symbols one query returns.
pub const WORKSPACE_SYMBOL_LIMIT: usize = 256;

/// A symbol of a document outline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DocumentSymbol {
    /// Never empty.
    pub name: String,
    /// Shown beside the name: a type, a graph, a comment, the states of a transition.
    pub detail: Option<String>,
    /// What it is (for the icon).
    pub kind: SymbolKind,
    /// The whole construct.
    pub full_range: TextRange,
    /// What to select: the name (inside `full_range`).
    pub selection_range: TextRange,
    /// The members, in text order.
    pub children: Vec<DocumentSymbol>,
}

impl DocumentSymbol {
    fn new(name: String, kind: SymbolKind, node: &SyntaxNode, focus: TextRange) -> DocumentSymbol {
        let full_range = node.text_range();
        let name = if name.trim().is_empty() {
            "?".to_owned()
        } else {
            name
        };
        DocumentSymbol {
            name,
            detail: None,
            kind,
            full_range,
            selection_range: clamp(focus, full_range),
            children: Vec::new(),
        }
    }

    fn detail(mut self, detail: Option<String>) -> DocumentSymbol {
        self.detail = detail.filter(|d| !d.is_empty());
        self
    }

    /// Moves the symbol and its children by `offset`.
    fn shift(&mut self, offset: TextSize) {
        self.full_range += offset;
        self.selection_range += offset;
        for child in &mut self.children {
            child.shift(offset);
        }
    }
}

/// `focus` if it lies inside `full`, else the start of `full`.
fn clamp(focus: TextRange, full: TextRange) -> TextRange {
    if full.contains_range(focus) {
        focus
    } else {
        TextRange::empty(full.start())
    }
}

impl Analysis {
    /// The outline of a file: one symbol per item with its members as children.
    pub fn document_symbols(&self, path: &str) -> Cancellable<Vec<DocumentSymbol>> {
        self.with_db(|db, _| {
            let Some(file) = self.file(path) else {
                return Vec::new();
            };
            file_outline(db, file)
        })
    }

    /// The graphs, groups, charts, global symbols, instances, states and steps whose name
    /// matches `query` (see the module documentation), best first.
    pub fn workspace_symbols(&self, query: &str) -> Cancellable<Vec<NavigationTarget>> {
        self.with_db(|db, ws| workspace_symbols(db, ws, query))
    }
}

fn file_outline(db: &dyn salsa::Database, file: File) -> Vec<DocumentSymbol> {
    let offsets = db::item_offsets(db, file);
    let mut out = Vec::new();
    for (index, &offset) in offsets.iter().enumerate() {
        let Ok(index) = u32::try_from(index) else {
            break;
        };
        if let Some(symbol) = item_outline(db, ItemLoc::new(db, file, index)) {
            let mut symbol = symbol.clone();
            symbol.shift(offset);
            out.push(symbol);
        }
    }
    out
}

// ------------------------------------------------------------------------------ outlines

/// The outline of one item, ranges relative to the item's start; `None` for a `mnemonic`.
#[salsa::tracked(returns(ref))]
pub(crate) fn item_outline<'db>(
    db: &'db dyn salsa::Database,
    item: ItemLoc<'db>,
) -> Option<DocumentSymbol> {
    let root = db::item_root(db, item)?;
    match ast::Item::cast(root)? {
        ast::Item::Graph(graph) => Some(graph_outline(&graph)),
        ast::Item::Group(group) => Some(group_outline(&group)),
        ast::Item::Chart(chart) => Some(chart_outline(&chart)),
        ast::Item::Symbols(table) => Some(symbols_outline(&table)),
        ast::Item::BlockInterface(interface) => Some(interface_outline(&interface)),
        ast::Item::Test(_) => None,
        ast::Item::Mnemonic(_) => None,
    }
}

/// The first significant token of a node (its keyword for most constructs).
fn keyword(node: &SyntaxNode) -> Option<SyntaxToken> {
    node.children_with_tokens()
        .filter_map(|e| e.into_token())
        .find(|t| !t.kind().is_trivia() && t.kind() != SyntaxKind::LEX_ERROR)
}

/// The range of a node's keyword, else the start of the node.
fn keyword_range(node: &SyntaxNode) -> TextRange {
    keyword(node).map_or(TextRange::empty(node.text_range().start()), |t| {
        t.text_range()
    })
}

/// Name, and the range to select, of a NAME node (falling back to the keyword).
fn named(node: &SyntaxNode, name: Option<ast::Name>) -> (String, TextRange) {
    match name.and_then(|n| Some((n.text(), n.token()?.text_range()))) {
        Some((text, range)) => (text, range),
        None => (String::new(), keyword_range(node)),
    }
}

fn graph_outline(graph: &ast::Graph) -> DocumentSymbol {
    let (name, focus) = named(graph.syntax(), graph.name());
    let mut symbol = DocumentSymbol::new(name, SymbolKind::Graph, graph.syntax(), focus)
        .detail(graph.comment().map(|c| c.value()));
    let mut states: Vec<(u32, String)> = Vec::new();
    for state in graph.states() {
        if let (Some(number), Some(name)) = (
            state.number().and_then(|n| n.text().parse::<u32>().ok()),
            state.comment().map(|c| c.value()),
        ) && !states.iter().any(|(n, _)| *n == number)
        {
            states.push((number, name));
        }
    }
    for member in graph.members() {
        match member {
            ast::GraphMember::VarSection(section) => {
                symbol.children.push(section_outline(&section));
            }
            ast::GraphMember::State(state) => symbol.children.push(state_outline(&state)),
            ast::GraphMember::Trans(trans) => {
                symbol.children.push(trans_outline(&trans, &states));
            }
            ast::GraphMember::Activate(_) | ast::GraphMember::Permanent(_) => {}
        }
    }
    symbol
}

/// `in` › variables.
fn section_outline(section: &ast::VarSection) -> DocumentSymbol {
    let keyword = section.keyword();
    let name = keyword
        .as_ref()
        .map_or_else(String::new, |k| k.text().to_ascii_lowercase());
    let focus = keyword.map_or(keyword_range(section.syntax()), |k| k.text_range());
    let mut symbol = DocumentSymbol::new(name, SymbolKind::Section, section.syntax(), focus);
    let is_in_out = section
        .keyword()
        .and_then(|k| Section::from_keyword(k.text()))
        == Some(Section::InOut);
    for decl in section.decls() {
        let (name, focus) = named(decl.syntax(), decl.name());
        let msg = decl.msg_kind();
        let kind = if msg.is_some() && is_in_out {
            SymbolKind::Message
        } else {
            SymbolKind::Variable
        };
        let mut detail = decl
            .ty()
            .map(|t| t.syntax().text().to_string())
            .unwrap_or_default();
        if let Some(msg) = msg {
            detail.push_str(if msg.is_incoming() {
                " msg in"
            } else {
                " msg out"
            });
        }
        symbol
            .children
            .push(DocumentSymbol::new(name, kind, decl.syntax(), focus).detail(Some(detail)));
    }
    symbol
}

/// `3 "Unten"`, detail: the attributes.
fn state_outline(state: &ast::State) -> DocumentSymbol {
    let number = state.number();
    let mut name = number
        .as_ref()
        .map_or_else(|| "state".to_owned(), |n| n.text().to_owned());
    if let Some(comment) = state.comment() {
        name.push_str(&format!(" \"{}\"", comment.value()));
    }
    let focus = number.map_or(keyword_range(state.syntax()), |n| n.text_range());
    let attributes: Vec<String> = state
        .attributes()
        .filter_map(|a| a.keyword())
        .map(|k| k.text().to_ascii_lowercase())
        .collect();
    DocumentSymbol::new(name, SymbolKind::State, state.syntax(), focus)
        .detail(Some(attributes.join(" ")))
}

/// `1->2 "name"`, detail: `Oben → Ab`.
fn trans_outline(trans: &ast::Trans, states: &[(u32, String)]) -> DocumentSymbol {
    let endpoint_text = |e: Option<ast::Endpoint>| {
        e.and_then(|e| e.token())
            .map_or_else(|| "?".to_owned(), |t| t.text().to_owned())
    };
    let mut name = format!(
        "{}->{}",
        endpoint_text(trans.source()),
        endpoint_text(trans.target())
    );
    if let Some(comment) = trans.comment() {
        name.push_str(&format!(" \"{}\"", comment.value()));
    }
    let focus = match (trans.source(), trans.target()) {
        (Some(source), Some(target)) => TextRange::new(
            source.syntax().text_range().start(),
            target.syntax().text_range().end(),
        ),
        (Some(source), None) => source.syntax().text_range(),
        _ => keyword_range(trans.syntax()),
    };
    let detail = super::inlay_hints::transition_label(
        trans.source().as_ref(),
        trans.target().as_ref(),
        |n| {
            states
                .iter()
                .find(|(number, _)| *number == n)
                .map(|(_, name)| name.as_str())
        },
    );
    DocumentSymbol::new(name, SymbolKind::Transition, trans.syntax(), focus).detail(detail)
}

fn group_outline(group: &ast::Group) -> DocumentSymbol {
    let (name, focus) = named(group.syntax(), group.name());
    let mut symbol = DocumentSymbol::new(name, SymbolKind::Group, group.syntax(), focus)
        .detail(group.comment().map(|c| c.value()));
    for instance in group.instances() {
        let (name, focus) = named(instance.syntax(), instance.name());
        symbol.children.push(
            DocumentSymbol::new(name, SymbolKind::Instance, instance.syntax(), focus)
                .detail(instance.graph().map(|g| g.text())),
        );
    }
    symbol
}

fn chart_outline(chart: &ast::Chart) -> DocumentSymbol {
    let (name, focus) = named(chart.syntax(), chart.name());
    let comment = chart.comment().map(|c| c.value());
    let detail = match (chart.is_type(), comment) {
        (true, Some(comment)) => Some(format!("chart type · {comment}")),
        (true, None) => Some("chart type".to_owned()),
        (false, comment) => comment,
    };
    let mut symbol =
        DocumentSymbol::new(name, SymbolKind::Chart, chart.syntax(), focus).detail(detail);
    for section in chart.var_sections() {
        symbol.children.push(section_outline(&section));
    }
    for sequencer in chart.sequencers() {
        let (name, focus) = named(sequencer.syntax(), sequencer.name());
        let prio = sequencer
            .prio()
            .and_then(|p| p.value())
            .map(|v| format!("prio {}", v.text()));
        let mut seq = DocumentSymbol::new(name, SymbolKind::Sequencer, sequencer.syntax(), focus)
            .detail(prio);
        seq_elements(sequencer.elements(), &mut seq.children);
        symbol.children.push(seq);
    }
    symbol
}

/// Steps and transitions of a sequencer or branch, branches flattened.
fn seq_elements(elements: impl Iterator<Item = ast::SeqElement>, out: &mut Vec<DocumentSymbol>) {
    for element in elements {
        match element {
            ast::SeqElement::Step(step) => {
                let (name, focus) = named(step.syntax(), step.name());
                out.push(
                    DocumentSymbol::new(name, SymbolKind::Step, step.syntax(), focus)
                        .detail(step.comment().map(|c| c.value())),
                );
            }
            ast::SeqElement::Trans(trans) => {
                let (name, focus) = named(trans.syntax(), trans.name());
                out.push(
                    DocumentSymbol::new(name, SymbolKind::ChartTransition, trans.syntax(), focus)
                        .detail(trans.comment().map(|c| c.value())),
                );
            }
            ast::SeqElement::Jump(jump) => {
                out.push(jump_outline(
                    jump.syntax(),
                    jump.name(),
                    jump.target(),
                    "jump",
                ));
            }
            ast::SeqElement::Loop(looping) => {
                out.push(jump_outline(
                    looping.syntax(),
                    looping.name(),
                    looping.target(),
                    "loop",
                ));
            }
            ast::SeqElement::Parallel(parallel) => {
                for branch in parallel.branches() {
                    seq_elements(branch.elements(), out);
                }
            }
            ast::SeqElement::Alt(alt) => {
                for branch in alt.branches() {
                    seq_elements(branch.elements(), out);
                }
            }
        }
    }
}

/// `J1 -> START`, detail `jump` / `loop`.
fn jump_outline(
    node: &SyntaxNode,
    name: Option<ast::Name>,
    target: Option<ast::NameRef>,
    what: &str,
) -> DocumentSymbol {
    let (mut name, focus) = named(node, name);
    if let Some(target) = target {
        name.push_str(&format!(" -> {}", target.text()));
    }
    DocumentSymbol::new(name, SymbolKind::ChartTransition, node, focus)
        .detail(Some(what.to_owned()))
}

fn symbols_outline(table: &ast::Symbols) -> DocumentSymbol {
    let mut symbol = DocumentSymbol::new(
        "symbols".to_owned(),
        SymbolKind::Section,
        table.syntax(),
        keyword_range(table.syntax()),
    );
    for entry in table.symbols() {
        let (name, focus) = named(entry.syntax(), entry.name());
        let mut detail = entry
            .address()
            .map(|a| normalise_spaces(&a.syntax().text().to_string()))
            .unwrap_or_default();
        if let Some(ty) = entry.ty() {
            detail.push(' ');
            detail.push_str(&ty.syntax().text().to_string());
        }
        symbol.children.push(
            DocumentSymbol::new(name, SymbolKind::Symbol, entry.syntax(), focus)
                .detail(Some(detail)),
        );
    }
    symbol
}

fn interface_outline(interface: &ast::BlockInterface) -> DocumentSymbol {
    let block = interface.block();
    let name = block
        .as_ref()
        .map(|b| normalise_spaces(&b.syntax().text().to_string()))
        .unwrap_or_default();
    let focus = block.map_or(keyword_range(interface.syntax()), |b| {
        b.syntax().text_range()
    });
    let mut symbol =
        DocumentSymbol::new(name, SymbolKind::BlockInterface, interface.syntax(), focus)
            .detail(interface.comment().map(|c| c.value()));
    for section in interface.var_sections() {
        symbol.children.push(section_outline(&section));
    }
    symbol
}

/// Runs of white space as one space.
fn normalise_spaces(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

// ------------------------------------------------------------------------------ workspace

/// A workspace symbol before ranking.
struct Candidate {
    target: NavigationTarget,
    /// The symbol's own name (the last part of the qualified one).
    own: String,
}

fn workspace_symbols(
    db: &dyn salsa::Database,
    ws: Workspace,
    query: &str,
) -> Vec<NavigationTarget> {
    let query = query.trim().to_ascii_lowercase();
    let mut ranked: Vec<(Rank, Candidate)> = Vec::new();
    let mut consider = |candidate: Candidate| {
        if let Some(rank) = rank(&query, &candidate) {
            ranked.push((rank, candidate));
        }
    };
    for &file in ws.files(db) {
        let path = file.path(db);
        let offsets = db::item_offsets(db, file);
        for (index, &offset) in offsets.iter().enumerate() {
            let Ok(index) = u32::try_from(index) else {
                break;
            };
            if let Some(outline) = item_outline(db, ItemLoc::new(db, file, index)) {
                collect(outline, None, path, offset, &mut consider);
            }
        }
    }
    let index = db::global_index(db, ws);
    for symbol in &index.symbols {
        if !matches!(symbol.source, SymbolSource::Imported(_)) {
            continue;
        }
        let range = db::absolute_range(db, &symbol.name_loc);
        consider(Candidate {
            target: NavigationTarget {
                path: symbol.name_loc.file.path(db).clone(),
                full_range: range,
                focus_range: range,
                name: symbol.name.clone(),
                kind: SymbolKind::Symbol,
            },
            own: symbol.name.clone(),
        });
    }
    ranked.sort_by(|(a, x), (b, y)| {
        a.cmp(b)
            .then_with(|| x.target.name.len().cmp(&y.target.name.len()))
            .then_with(|| x.target.name.cmp(&y.target.name))
            .then_with(|| x.target.path.cmp(&y.target.path))
            .then_with(|| {
                x.target
                    .full_range
                    .start()
                    .cmp(&y.target.full_range.start())
            })
    });
    ranked.truncate(WORKSPACE_SYMBOL_LIMIT);
    ranked.into_iter().map(|(_, c)| c.target).collect()
}

/// Walks an outline and offers its workspace symbols. `container` is the qualified name of
/// the enclosing graph, group, chart or sequencer.
fn collect(
    symbol: &DocumentSymbol,
    container: Option<&str>,
    path: &str,
    offset: TextSize,
    consider: &mut impl FnMut(Candidate),
) {
    let listed = matches!(
        symbol.kind,
        SymbolKind::Graph
            | SymbolKind::Group
            | SymbolKind::Chart
            | SymbolKind::Symbol
            | SymbolKind::Instance
            | SymbolKind::State
            | SymbolKind::Step
    );
    let nested = matches!(
        symbol.kind,
        SymbolKind::Instance | SymbolKind::State | SymbolKind::Step | SymbolKind::Sequencer
    );
    let qualified = match container {
        Some(container) if nested => format!("{container}.{}", symbol.name),
        _ => symbol.name.clone(),
    };
    if listed {
        consider(Candidate {
            target: NavigationTarget {
                path: path.to_owned(),
                full_range: symbol.full_range + offset,
                focus_range: symbol.selection_range + offset,
                name: qualified.clone(),
                kind: symbol.kind,
            },
            own: symbol.name.clone(),
        });
    }
    let is_container = matches!(
        symbol.kind,
        SymbolKind::Graph | SymbolKind::Group | SymbolKind::Chart | SymbolKind::Sequencer
    );
    let inner = if is_container {
        Some(qualified.as_str())
    } else {
        container
    };
    for child in &symbol.children {
        collect(child, inner, path, offset, consider);
    }
}

/// How well a candidate matches: lower is better.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Rank {
    /// 0 exact name, 1 name prefix, 2 name contains the query, 3 qualified name contains it,
    /// 4 a scattered subsequence.
    class: u8,
    /// Characters skipped between the matched ones (subsequence matches).
    gaps: usize,
    /// Top-level items before symbols before nested symbols.
    kind: u8,
}

/// The rank of a candidate for a lower-case query; `None` if it does not match.
fn rank(query: &str, candidate: &Candidate) -> Option<Rank> {
    let own = candidate.own.to_ascii_lowercase();
    let qualified = candidate.target.name.to_ascii_lowercase();
    let gaps = subsequence_gaps(query, &qualified)?;
    let class = if own == query {
        0
    } else if own.starts_with(query) {
        1
    } else if own.contains(query) {
        2
    } else if qualified.contains(query) {
        3
    } else {
        4
    };
    let kind = match candidate.target.kind {
        SymbolKind::Graph | SymbolKind::Group | SymbolKind::Chart => 0,
        SymbolKind::Symbol => 1,
        _ => 2,
    };
    Some(Rank {
        class,
        gaps: if class == 4 { gaps } else { 0 },
        kind,
    })
}

/// If `query` is a subsequence of `text` (both lower case), the number of characters skipped
/// between the first and the last matched character, matching greedily.
fn subsequence_gaps(query: &str, text: &str) -> Option<usize> {
    let mut chars = text.chars().enumerate();
    let mut first = None;
    let mut last = 0;
    let mut matched = 0;
    for q in query.chars() {
        let (at, _) = chars.find(|&(_, c)| c == q)?;
        first.get_or_insert(at);
        last = at;
        matched += 1;
    }
    Some(first.map_or(0, |first| last - first + 1 - matched))
}

#[cfg(test)]
mod tests {
    use std::fmt::Write;

    use crate::ide::fixture;

    use super::DocumentSymbol;

    /// The outline of the cursor's file as an indented tree: kind, name, detail, and the text
    /// of the selection range.
    fn outline(text: &str) -> String {
        let f = fixture::load(text);
        let path = f.position.path.clone();
        let symbols = f
            .host
            .analysis()
            .document_symbols(&path)
            .expect("not cancelled");
        let mut out = String::new();
        for symbol in &symbols {
            render(&f, &path, symbol, 0, &mut out);
        }
        out
    }

    fn render(
        f: &fixture::Fixture,
        path: &str,
        symbol: &DocumentSymbol,
        depth: usize,
        out: &mut String,
    ) {
        assert!(symbol.full_range.contains_range(symbol.selection_range));
        let detail = symbol
            .detail
            .as_ref()
            .map(|d| format!(" · {d}"))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "{:indent$}{:?} {}{detail} [{}]",
            "",
            symbol.kind,
            symbol.name,
            f.slice(path, symbol.selection_range),
            indent = depth * 2
        );
        for child in &symbol.children {
            assert!(symbol.full_range.contains_range(child.full_range));
            render(f, path, child, depth + 1, out);
        }
    }

    /// Workspace symbols for a query: kind, name, path and the selected text.
    fn search(text: &str, query: &str) -> String {
        let f = fixture::load(text);
        let targets = f
            .host
            .analysis()
            .workspace_symbols(query)
            .expect("not cancelled");
        targets
            .iter()
            .map(|t| {
                format!(
                    "{:?} {} ({}: {})",
                    t.kind,
                    t.name,
                    t.path,
                    f.slice(&t.path, t.focus_range)
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    const DRILL: &str = r#"//- graphs.higraph
$0mnemonic simatic;
graph Ventil_2E "valve with two end positions" <
  in     < Oben : BOOL; Unten : BOOL; >
  out    < Auf : BOOL; Ab : BOOL; >
  in_out <
    IM_Ab    : BOOL msg in;
    OM_Oben  : BOOL msg out;
  >
  stat < Merker : BOOL; >
  activate CurrentState;
  permanent < C: U Oben; >
  state 0 "Initialisierung" < >
  state 1 "Oben" fault message < E: S OM_Oben; >
  state 2 < >
  trans any->0 prio 1 "startup" < U INIT_SD; >
  trans 0->1 prio 1 < U Oben; >
  trans 1->2 prio 1 auto < U IM_Ab; >
  trans 2->return < >
>
symbols <
  Bohrer_Oben : E 0.0 BOOL "drill at top";
  "Not Aus" : E   0.1;
  GG_Bohr : FC 1;
>
block FC 10 "Dosieren" < in < Menge : INT; > out < Fertig : BOOL; > >
//- group.higraph
group Bohrmaschine fc FC1 db DB1 "drilling machine" <
  option cyclic_rlo0;
  instance Vorschub : Ventil_2E "feed" <
    Oben := Bohrer_Oben;
  >
  instance Spanner : Ventil_2E < >
>
//- chart.higraph
chart Mischer "batch mixer" <
  in < Fuellstand : REAL; >
  sequencer RUN prio 1 <
    start < Fuellstand > 1.0; >
    step START < >
    trans T1 < Fuellstand >= 80.0; >
    parallel <
      branch < step HEIZEN "heat" < > >
      branch < step RUEHREN < > >
    >
    trans T2 < TRUE; >
    step ENDE < >
    loop L1 -> START < Fuellstand < 5.0; >
  >
  sequencer AUX < step A < > >
>
chart type Vorlage < in < X : BOOL; > >
"#;

    #[test]
    fn graph_symbols_and_block_interfaces() {
        insta::assert_snapshot!(outline(DRILL), @r#"
Graph Ventil_2E · valve with two end positions [Ventil_2E]
  Section in [in]
    Variable Oben · BOOL [Oben]
    Variable Unten · BOOL [Unten]
  Section out [out]
    Variable Auf · BOOL [Auf]
    Variable Ab · BOOL [Ab]
  Section in_out [in_out]
    Message IM_Ab · BOOL msg in [IM_Ab]
    Message OM_Oben · BOOL msg out [OM_Oben]
  Section stat [stat]
    Variable Merker · BOOL [Merker]
  State 0 "Initialisierung" [0]
  State 1 "Oben" · fault message [1]
  State 2 [2]
  Transition any->0 "startup" · any → Initialisierung [any->0]
  Transition 0->1 · Initialisierung → Oben [0->1]
  Transition 1->2 · Oben → 2 [1->2]
  Transition 2->return [2->return]
Section symbols [symbols]
  Symbol Bohrer_Oben · E 0.0 BOOL [Bohrer_Oben]
  Symbol Not Aus · E 0.1 ["Not Aus"]
  Symbol GG_Bohr · FC 1 [GG_Bohr]
BlockInterface FC 10 · Dosieren [FC 10]
  Section in [in]
    Variable Menge · INT [Menge]
  Section out [out]
    Variable Fertig · BOOL [Fertig]
"#);
    }

    #[test]
    fn group_symbols() {
        insta::assert_snapshot!(outline(&DRILL.replace("$0", "").replace("//- group.higraph\n", "//- group.higraph\n$0")), @r#"
Group Bohrmaschine · drilling machine [Bohrmaschine]
  Instance Vorschub · Ventil_2E [Vorschub]
  Instance Spanner · Ventil_2E [Spanner]
"#);
    }

    #[test]
    fn chart_symbols() {
        insta::assert_snapshot!(outline(&DRILL.replace("$0", "").replace("//- chart.higraph\n", "//- chart.higraph\n$0")), @r#"
Chart Mischer · batch mixer [Mischer]
  Section in [in]
    Variable Fuellstand · REAL [Fuellstand]
  Sequencer RUN · prio 1 [RUN]
    Step START [START]
    ChartTransition T1 [T1]
    Step HEIZEN · heat [HEIZEN]
    Step RUEHREN [RUEHREN]
    ChartTransition T2 [T2]
    Step ENDE [ENDE]
    ChartTransition L1 -> START · loop [L1]
  Sequencer AUX [AUX]
    Step A [A]
Chart Vorlage · chart type [Vorlage]
  Section in [in]
    Variable X · BOOL [X]
"#);
    }

    #[test]
    fn incomplete_items_still_have_symbols() {
        insta::assert_snapshot!(outline("$0graph G <\n  in < A : ; B\n  state 3 \"Drei\" < C: U\n  trans 3->\n  state\n>\ngroup < instance : <\nchart C < sequencer < step < >"), @r#"
Graph G [G]
  Section in [in]
    Variable A [A]
    Variable B [B]
  Transition 3->? [3]
Group ? [group]
  Instance ? [instance]
Chart C [C]
  Sequencer ? [sequencer]
    Step ? [step]
"#);
    }

    #[test]
    fn workspace_symbols_rank_exact_prefix_substring_subsequence() {
        insta::assert_snapshot!(search(DRILL, "oben"), @r#"
Symbol Bohrer_Oben (graphs.higraph: Bohrer_Oben)
State Ventil_2E.1 "Oben" (graphs.higraph: 1)
"#);
        insta::assert_snapshot!(search(DRILL, "Vorschub"), @"Instance Bohrmaschine.Vorschub (group.higraph: Vorschub)");
        insta::assert_snapshot!(search(DRILL, "heizen"), @"Step Mischer.RUN.HEIZEN (chart.higraph: HEIZEN)");
        insta::assert_snapshot!(search(DRILL, "mr"), @r#"
Chart Mischer (chart.higraph: Mischer)
Step Mischer.AUX.A (chart.higraph: A)
Step Mischer.RUN.ENDE (chart.higraph: ENDE)
Step Mischer.RUN.START (chart.higraph: START)
Step Mischer.RUN.HEIZEN (chart.higraph: HEIZEN)
Step Mischer.RUN.RUEHREN (chart.higraph: RUEHREN)
Instance Bohrmaschine.Vorschub (group.higraph: Vorschub)
Instance Bohrmaschine.Spanner (group.higraph: Spanner)
"#);
    }

    #[test]
    fn workspace_symbols_include_imported_symbols() {
        let sdf = b"\"Anlage_Ein\",\"E       1.0\",\"BOOL\",\"on\"\r\n".to_vec();
        let data = crate::WorkspaceData {
            files: vec![(
                "a.higraph".to_owned(),
                crate::FileContents::Text("graph Anlage < >\n".to_owned()),
            )],
            config: Some((
                "higraph.toml".to_owned(),
                crate::FileContents::Text("[workspace]\nsymbols = [\"plc.sdf\"]\n".to_owned()),
            )),
            imports: [("plc.sdf".to_owned(), Ok(sdf))].into_iter().collect(),
            ..Default::default()
        };
        let mut host = crate::AnalysisHost::new();
        host.load(data);
        let targets = host
            .analysis()
            .workspace_symbols("anlage")
            .expect("not cancelled");
        let found: Vec<(String, String)> = targets.into_iter().map(|t| (t.name, t.path)).collect();
        assert_eq!(
            found,
            [
                ("Anlage".to_owned(), "a.higraph".to_owned()),
                ("Anlage_Ein".to_owned(), "plc.sdf".to_owned())
            ]
        );
    }

    #[test]
    fn workspace_symbols_are_capped() {
        let mut text = String::from("//- a.higraph\n$0graph G <\n");
        for i in 0..400 {
            text.push_str(&format!("  state {i} \"S{i}\" < >\n"));
        }
        text.push_str(">\n");
        let f = fixture::load(&text);
        let all = f
            .host
            .analysis()
            .workspace_symbols("")
            .expect("not cancelled");
        assert_eq!(all.len(), super::WORKSPACE_SYMBOL_LIMIT);
        assert_eq!(all[0].name, "G");
        let some = f
            .host
            .analysis()
            .workspace_symbols("s39")
            .expect("not cancelled");
        assert_eq!(some[0].name, "G.39 \"S39\"");
    }

    #[test]
    fn subsequence_gaps() {
        assert_eq!(super::subsequence_gaps("abc", "abc"), Some(0));
        assert_eq!(super::subsequence_gaps("ac", "abc"), Some(1));
        assert_eq!(super::subsequence_gaps("", "abc"), Some(0));
        assert_eq!(super::subsequence_gaps("ca", "abc"), None);
    }
}
