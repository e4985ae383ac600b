//! Code lenses (issue 15): counts above declarations, each opening the references view on the
//! places it counts.
//!
//! * a **graph** header: its instances (`instance X : G` in the groups) and its references
//!   (what find-references answers without the declaration: instances and test uses);
//! * a **group** header: its instances and its internal messages (the actuals wired to a
//!   message target `Inst.Msg`);
//! * a **state**: its incoming and outgoing transitions (the explicit endpoints naming it;
//!   `any` and `return` name no state);
//! * a **symbol** declared in a `symbols` table: its uses.
//!
//! Listing the lenses of a file only walks its syntax ([`Analysis::code_lenses`]); the counts
//! come from [`Analysis::resolve_code_lens`], which runs the references search of
//! `references.rs` for one lens, so a lens shows what find-references finds.

use higraph_syntax::{
    SyntaxKind, SyntaxNode, TextRange, TextSize,
    ast::{self, AstNode},
};

use super::{FilePosition, FileRange, defs};
use crate::{Analysis, Cancellable, db};

/// A lens before it is resolved: where it stands and what it counts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeLens {
    /// The header the lens stands above (from the keyword to the name).
    pub range: TextRange,
    /// The declared name the lens counts for (what [`Analysis::resolve_code_lens`] looks at).
    pub name: TextSize,
    pub kind: LensKind,
}

/// What a lens counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LensKind {
    GraphInstances,
    GraphReferences,
    GroupInstances,
    GroupMessages,
    StateIncoming,
    StateOutgoing,
    SymbolUses,
}

impl LensKind {
    /// The stable name of the kind (the language server's lens data).
    pub fn as_str(self) -> &'static str {
        match self {
            LensKind::GraphInstances => "graphInstances",
            LensKind::GraphReferences => "graphReferences",
            LensKind::GroupInstances => "groupInstances",
            LensKind::GroupMessages => "groupMessages",
            LensKind::StateIncoming => "stateIncoming",
            LensKind::StateOutgoing => "stateOutgoing",
            LensKind::SymbolUses => "symbolUses",
        }
    }

    /// Every kind, in a stable order: a kind's place here is its number
    /// ([`LensKind::number`], the language server's lens data).
    pub const ALL: [LensKind; 7] = [
        LensKind::GraphInstances,
        LensKind::GraphReferences,
        LensKind::GroupInstances,
        LensKind::GroupMessages,
        LensKind::StateIncoming,
        LensKind::StateOutgoing,
        LensKind::SymbolUses,
    ];

    /// The kind of a name given by [`LensKind::as_str`].
    pub fn from_name(name: &str) -> Option<LensKind> {
        LensKind::ALL.into_iter().find(|kind| kind.as_str() == name)
    }

    /// The kind's small stable number (its place in [`LensKind::ALL`]).
    pub fn number(self) -> u8 {
        LensKind::ALL
            .iter()
            .position(|kind| *kind == self)
            .map_or(0, |place| place as u8)
    }

    /// The kind of a number given by [`LensKind::number`].
    pub fn from_number(number: u64) -> Option<LensKind> {
        LensKind::ALL.get(usize::try_from(number).ok()?).copied()
    }

    /// The title for `count` places: `1 instance`, `3 references`.
    fn title(self, count: usize) -> String {
        let (one, many) = match self {
            LensKind::GraphInstances | LensKind::GroupInstances => ("instance", "instances"),
            LensKind::GraphReferences => ("reference", "references"),
            LensKind::GroupMessages => ("internal message", "internal messages"),
            LensKind::StateIncoming => ("incoming transition", "incoming transitions"),
            LensKind::StateOutgoing => ("outgoing transition", "outgoing transitions"),
            LensKind::SymbolUses => ("use", "uses"),
        };
        format!("{count} {}", if count == 1 { one } else { many })
    }
}

/// A resolved lens: its title and the places it counts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResolvedLens {
    /// `2 instances`, `1 incoming transition`, …
    pub title: String,
    /// The places counted, in workspace order (the title's number is their count).
    pub locations: Vec<FileRange>,
}

impl Analysis {
    /// The lenses of a file, unresolved, in text order. Cheap: a walk of the file's syntax.
    pub fn code_lenses(&self, path: &str) -> Cancellable<Vec<CodeLens>> {
        self.with_db(|db, _| {
            let Some(file) = self.file(path) else {
                return Vec::new();
            };
            lenses(&db::parse(db, file).syntax_node())
        })
    }

    /// Counts a lens of `kind` whose name is at `name`. `None` when the name there is no
    /// longer something of that kind (the file changed since the lens was listed).
    ///
    /// Cheap right after an edit: the lens's name is looked up as a declaration (no use index
    /// of its item is computed), a state's transitions come from the per-chunk endpoint
    /// lists of its graph ([`chunk_endpoints`]: after a keystroke only the edited chunk's
    /// list is computed again), a group's from its syntax; only graph and symbol lenses run
    /// the references search, over the items that can use them.
    pub fn resolve_code_lens(
        &self,
        name: &FilePosition,
        kind: LensKind,
    ) -> Cancellable<Option<ResolvedLens>> {
        self.with_db(|db, ws| {
            let file = self.file(&name.path)?;
            let at = defs::declaration_at(db, ws, file, name.offset)?;
            let ranges: Vec<FileRange> = match (&at.definition, kind) {
                (
                    defs::Definition::Graph(_) | defs::Definition::Symbol(_),
                    LensKind::GraphReferences | LensKind::SymbolUses,
                ) => references(db, ws, &at.definition, |_| true),
                (defs::Definition::Graph(_), LensKind::GraphInstances) => {
                    references(db, ws, &at.definition, |node| {
                        node.kind() == SyntaxKind::INSTANCE
                    })
                }
                (
                    defs::Definition::State { graph, number },
                    LensKind::StateIncoming | LensKind::StateOutgoing,
                ) => {
                    let side = if kind == LensKind::StateIncoming {
                        Side::Target
                    } else {
                        Side::Source
                    };
                    let start = defs::item_start(db, *graph);
                    let layout = db::graph_layout(db, defs::item_loc(db, *graph));
                    layout
                        .chunks
                        .iter()
                        .zip(&layout.offsets)
                        .flat_map(|(&chunk, &offset)| {
                            chunk_endpoints(db, chunk)
                                .iter()
                                .filter(|e| e.number == *number && e.side == side)
                                .map(move |e| FileRange {
                                    path: name.path.clone(),
                                    range: e.range + offset + start,
                                })
                        })
                        .collect()
                }
                (
                    defs::Definition::Group(_),
                    LensKind::GroupInstances | LensKind::GroupMessages,
                ) => {
                    let root = db::parse(db, file).syntax_node();
                    let group = defs::token_at(&root, name.offset)
                        .and_then(|t| t.parent_ancestors().find_map(ast::Group::cast))?;
                    let ranges: Vec<TextRange> = if kind == LensKind::GroupInstances {
                        group
                            .instances()
                            .filter_map(|i| i.name())
                            .map(|n| n.syntax().text_range())
                            .collect()
                    } else {
                        group
                            .instances()
                            .flat_map(|i| i.actuals())
                            .filter_map(|a| match a.value() {
                                Some(ast::Operand::MessageTarget(target)) => Some(TextRange::new(
                                    a.syntax().text_range().start(),
                                    target.syntax().text_range().end(),
                                )),
                                _ => None,
                            })
                            .collect()
                    };
                    ranges
                        .into_iter()
                        .map(|range| FileRange {
                            path: name.path.clone(),
                            range,
                        })
                        .collect()
                }
                _ => return None,
            };
            Some(ResolvedLens {
                title: kind.title(ranges.len()),
                locations: ranges,
            })
        })
    }
}

/// The references of `definition` (without the declaration, each place once, in workspace
/// order, as find-references answers them) whose syntax satisfies `keep`, which sees each
/// ancestor of the reference's token in turn.
fn references(
    db: &dyn salsa::Database,
    ws: db::Workspace,
    definition: &defs::Definition,
    keep: impl Fn(&SyntaxNode) -> bool,
) -> Vec<FileRange> {
    let mut out: Vec<FileRange> = Vec::new();
    for reference in defs::references(db, ws, definition) {
        if reference.kind == defs::ReferenceKind::Declaration {
            continue;
        }
        let root = db::parse(db, reference.file).syntax_node();
        let kept = defs::token_at(&root, reference.range.start())
            .is_some_and(|t| t.parent_ancestors().any(|node| keep(&node)));
        let range = FileRange {
            path: reference.file.path(db).clone(),
            range: reference.range,
        };
        if kept && !out.contains(&range) {
            out.push(range);
        }
    }
    out
}

/// Which end of a transition an endpoint is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Side {
    Source,
    Target,
}

/// An endpoint naming a state (`trans 1->2`: `1` and `2`), as the use index records it
/// (`defs.rs`): the number, which end, and the number's range relative to its chunk.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) struct StateEndpoint {
    number: u32,
    side: Side,
    range: TextRange,
}

/// The state endpoints of a chunk's transitions, in text order. Per chunk, so that after a
/// keystroke in a graph of thousands of members only the edited chunk is read again.
#[salsa::tracked(returns(ref))]
pub(crate) fn chunk_endpoints<'db>(
    db: &'db dyn salsa::Database,
    chunk: db::Chunk<'db>,
) -> Vec<StateEndpoint> {
    let mut out = Vec::new();
    for (green, offset) in chunk.members(db) {
        let Some(trans) = ast::Trans::cast(green.root()) else {
            continue;
        };
        for (endpoint, side) in [
            (trans.source(), Side::Source),
            (trans.target(), Side::Target),
        ] {
            let Some(endpoint) = endpoint else {
                continue;
            };
            if endpoint.kind() != Some(ast::EndpointKind::State) {
                continue;
            }
            let Some(token) = endpoint.token() else {
                continue;
            };
            if let Ok(number) = token.text().parse::<u32>() {
                out.push(StateEndpoint {
                    number,
                    side,
                    range: token.text_range() + *offset,
                });
            }
        }
    }
    out
}

/// The unresolved lenses of a file.
fn lenses(root: &SyntaxNode) -> Vec<CodeLens> {
    let mut out = Vec::new();
    let header =
        |node: &SyntaxNode, name: TextRange| TextRange::new(node.text_range().start(), name.end());
    for item in root.children().filter_map(ast::Item::cast) {
        match item {
            ast::Item::Graph(graph) => {
                if let Some(name) = graph.name().and_then(|n| n.token()) {
                    let range = header(graph.syntax(), name.text_range());
                    for kind in [LensKind::GraphInstances, LensKind::GraphReferences] {
                        out.push(CodeLens {
                            range,
                            name: name.text_range().start(),
                            kind,
                        });
                    }
                }
                for state in graph.states() {
                    let Some(number) = state.number() else {
                        continue;
                    };
                    let range = header(state.syntax(), number.text_range());
                    for kind in [LensKind::StateIncoming, LensKind::StateOutgoing] {
                        out.push(CodeLens {
                            range,
                            name: number.text_range().start(),
                            kind,
                        });
                    }
                }
            }
            ast::Item::Group(group) => {
                if let Some(name) = group.name().and_then(|n| n.token()) {
                    let range = header(group.syntax(), name.text_range());
                    for kind in [LensKind::GroupInstances, LensKind::GroupMessages] {
                        out.push(CodeLens {
                            range,
                            name: name.text_range().start(),
                            kind,
                        });
                    }
                }
            }
            ast::Item::Symbols(table) => {
                for symbol in table.symbols() {
                    if let Some(name) = symbol.name().and_then(|n| n.token()) {
                        out.push(CodeLens {
                            range: name.text_range(),
                            name: name.text_range().start(),
                            kind: LensKind::SymbolUses,
                        });
                    }
                }
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{FilePosition, LensKind};
    use crate::ide::fixture;

    /// Renders every lens of the cursor's file as `header: title [place, place]`.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let analysis = f.host.analysis();
        let path = f.position.path.clone();
        let lenses = analysis.code_lenses(&path).unwrap_or_default();
        lenses
            .iter()
            .map(|lens| {
                let resolved = analysis
                    .resolve_code_lens(
                        &FilePosition {
                            path: path.clone(),
                            offset: lens.name,
                        },
                        lens.kind,
                    )
                    .ok()
                    .flatten();
                let Some(resolved) = resolved else {
                    return format!("{}: unresolved", f.slice(&path, lens.range));
                };
                let places: Vec<String> = resolved
                    .locations
                    .iter()
                    .map(|l| {
                        format!(
                            "{}@{}",
                            f.slice(&l.path, l.range),
                            u32::from(l.range.start())
                        )
                    })
                    .collect();
                format!(
                    "{}: {} [{}]",
                    f.slice(&path, lens.range),
                    resolved.title,
                    places.join(", ")
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    const WORKSPACE: &str = r#"//- graphs/bohren.higraph
graph Bohren <
  in_out < IM_Oben : BOOL msg in; OM_Senken : BOOL msg out; >
  state 0 < C: U IM_Oben; >
  state 1 < C: S OM_Senken; U Taster; >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U IM_Oben; >
  trans 1->0 < U Taster; >
  trans 1->1 < U Taster; >
>
//- graphs/ventil.higraph
graph Ventil <
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  state 0 < C: S OM_Oben; U IM_Ab; >
  trans any->0 < U INIT_SD; >
>
//- group.higraph
group Bohrmaschine fc FC 1 db DB 1 <
  instance Bohren : Bohren < OM_Senken := Vorschub.IM_Ab; >
  instance Vorschub : Ventil < OM_Oben := Bohren.IM_Oben; >
  instance Vorschub2 : Ventil < OM_Oben := Bohren.IM_Oben; >
>
//- symbols.higraph
symbols <
  Taster : E 0.0 : BOOL;
  Unbenutzt : E 0.1 : BOOL;
>
"#;

    /// The fixture with the cursor in `path`.
    fn in_file(path: &str) -> String {
        WORKSPACE.replacen(&format!("//- {path}\n"), &format!("//- {path}\n$0"), 1)
    }

    #[test]
    fn graph_and_states() {
        insta::assert_snapshot!(check(&in_file("graphs/bohren.higraph")), @"
        graph Bohren: 1 instance [Bohren@57]
        graph Bohren: 1 reference [Bohren@57]
        state 0: 2 incoming transitions [0@158, 0@214]
        state 0: 1 outgoing transition [0@183]
        state 1: 2 incoming transitions [1@186, 1@241]
        state 1: 2 outgoing transitions [1@211, 1@238]
        ");
    }

    #[test]
    fn group() {
        insta::assert_snapshot!(check(&in_file("group.higraph")), @"
        group Bohrmaschine: 3 instances [Bohren@48, Vorschub@108, Vorschub2@168]
        group Bohrmaschine: 3 internal messages [OM_Senken := Vorschub.IM_Ab@66, OM_Oben := Bohren.IM_Oben@128, OM_Oben := Bohren.IM_Oben@189]
        ");
    }

    #[test]
    fn symbols() {
        insta::assert_snapshot!(check(&in_file("symbols.higraph")), @"
        Taster: 3 uses [Taster@135, Taster@220, Taster@247]
        Unbenutzt: 0 uses []
        ");
    }

    /// A reference lens counts exactly what find-references answers; a state's incoming and
    /// outgoing lenses together count its endpoint references.
    #[test]
    fn counts_equal_find_references() {
        for path in [
            "graphs/bohren.higraph",
            "graphs/ventil.higraph",
            "symbols.higraph",
        ] {
            let f = fixture::load(&in_file(path));
            let analysis = f.host.analysis();
            let lenses = analysis.code_lenses(path).unwrap_or_default();
            assert!(!lenses.is_empty());
            let mut checked = 0;
            for lens in &lenses {
                let position = FilePosition {
                    path: path.to_owned(),
                    offset: lens.name,
                };
                let found = analysis.references(&position, false).unwrap_or_default();
                let count = |kind| {
                    analysis
                        .resolve_code_lens(&position, kind)
                        .ok()
                        .flatten()
                        .map_or(usize::MAX, |r| r.locations.len())
                };
                match lens.kind {
                    LensKind::GraphReferences | LensKind::SymbolUses => {
                        assert_eq!(count(lens.kind), found.len());
                        checked += 1;
                    }
                    LensKind::StateIncoming => {
                        assert_eq!(
                            count(LensKind::StateIncoming) + count(LensKind::StateOutgoing),
                            found.len()
                        );
                        checked += 1;
                    }
                    _ => {}
                }
            }
            assert!(checked > 0);
        }
    }

    #[test]
    fn a_stale_lens_does_not_resolve() {
        let f = fixture::load(&in_file("group.higraph"));
        let position = FilePosition {
            path: "group.higraph".to_owned(),
            offset: 0.into(),
        };
        let resolved = f
            .host
            .analysis()
            .resolve_code_lens(&position, LensKind::GraphInstances)
            .ok()
            .flatten();
        assert_eq!(resolved, None);
    }
}
