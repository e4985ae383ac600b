//! Test paths (`runtime.md` §5.3): the one resolver the lowering, the HG91xx rules and the
//! editor features share.
//!
//! A [`RunScope`] holds what a test's run list makes nameable — its groups with their
//! instances and graph variables, its charts with variables, sequencers and steps, and the
//! external references of its charts — built from the analysis' own per-item data
//! (`db::graph_scope`, the chart rules' element tree). [`resolve`] reads one path against it
//! and returns a [`Resolution`]: what the path denotes ([`PathTarget`]), its type, whether it
//! can be `set`, and for every segment what it names ([`SegmentDef`], for hover, definition,
//! references and rename).

use std::collections::HashSet;

use higraph_runtime::program::{FbMember, FbType, StepMember, VarIdx};
use higraph_runtime::value::Ty;
use higraph_syntax::{TextRange, ast, ast::AstNode};

use super::graph::predef_index;
use super::values;
use crate::address::{Address, Area};
use crate::db::{self, File, ItemKind, ItemLoc, Workspace};
use crate::index::{self, GlobalIndex};
use crate::lang::{self, Mnemonic, Section, Type};
use crate::rules::chart::model::{Kind, Tree};

/// An instance of a group of the run list.
#[derive(Debug, Clone)]
pub(crate) struct ScopeInstance {
    pub name: String,
    /// The instance name (relative to the group item).
    pub name_range: TextRange,
    /// The graph item.
    pub graph: (File, u32),
}

#[derive(Debug, Clone)]
pub(crate) struct ScopeGroup {
    pub name: String,
    pub file: File,
    pub item: u32,
    /// The instances the lowering runs (the first of each name whose graph exists), in order.
    pub instances: Vec<ScopeInstance>,
}

#[derive(Debug, Clone)]
pub(crate) struct ScopeSequencer {
    pub name: String,
    pub name_range: TextRange,
    /// Steps (the first of each name) in text order, with their name ranges.
    pub steps: Vec<(String, TextRange)>,
}

#[derive(Debug, Clone)]
pub(crate) struct ScopeChart {
    pub name: String,
    pub file: File,
    pub item: u32,
    /// Variables (the first of each name): name, name range, type.
    pub vars: Vec<(String, TextRange, Option<Type>)>,
    /// Per variable (same indices): its standard function block type in an IEC chart.
    pub fb_types: Vec<Option<FbType>>,
    pub sequencers: Vec<ScopeSequencer>,
}

/// What a test's run list makes nameable.
#[derive(Debug, Clone, Default)]
pub(crate) struct RunScope {
    pub groups: Vec<ScopeGroup>,
    pub charts: Vec<ScopeChart>,
    /// External references of the charts (upper-case text without white space).
    pub externals: HashSet<String>,
}

/// What a path denotes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PathTarget {
    Address(Address),
    /// A global symbol (index into [`GlobalIndex::symbols`]) and its address.
    Symbol(usize, Option<Address>),
    /// A variable of instance `instance` of run group `group`.
    InstVar {
        group: usize,
        instance: usize,
        var: VarIdx,
    },
    InstState {
        group: usize,
        instance: usize,
        previous: bool,
    },
    ChartState {
        chart: usize,
    },
    ChartVar {
        chart: usize,
        var: usize,
    },
    /// `Chart.Fb.Member`: a member of a function block instance of an IEC chart.
    ChartFb {
        chart: usize,
        var: usize,
        member: FbMember,
    },
    Step {
        chart: usize,
        sequencer: usize,
        step: usize,
        member: StepMember,
    },
    /// `Block.Param`: the block's key and canonical name, the formal as written.
    Stub {
        key: String,
        name: String,
        param: String,
    },
    Calls {
        key: String,
        name: String,
    },
    /// An external reference of a chart of the run list (upper-case text).
    External(String),
}

/// What one segment of a path names (for the editor features).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SegmentDef {
    Symbol {
        name: String,
    },
    Address,
    Group {
        file: String,
        range: TextRange,
    },
    Instance {
        file: String,
        range: TextRange,
    },
    /// A declared variable of a graph (its declaration's name).
    GraphVariable {
        file: String,
        range: TextRange,
    },
    /// A predefined variable, by canonical name.
    Predefined {
        name: &'static str,
    },
    Chart {
        file: String,
        range: TextRange,
    },
    ChartVariable {
        file: String,
        range: TextRange,
    },
    Sequencer {
        file: String,
        range: TextRange,
    },
    Step {
        file: String,
        range: TextRange,
    },
    Block {
        name: String,
    },
    /// `state previous calls X T error`, a formal of a block, or an external reference.
    Member,
}

/// A resolved path.
#[derive(Debug, Clone)]
pub(crate) struct Resolution {
    pub target: PathTarget,
    /// `None` for a stub whose formal is unknown (the value's type applies) and external
    /// references (the first use's type).
    pub ty: Option<Ty>,
    /// `Err(reason)` when `set` cannot write it (HG9104).
    pub settable: Result<(), String>,
    /// Per segment (for addresses: one), in order, with its range in the test item.
    pub segments: Vec<(TextRange, SegmentDef)>,
    /// A `Block.Param` whose block has an interface where Param is no output (HG9111).
    pub not_an_output: Option<(String, String, TextRange)>,
}

/// Why a path does not resolve.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum PathError {
    /// HG9101, at `range`, with candidates for a closest-name fix.
    Unresolved {
        range: TextRange,
        message: String,
        written: String,
        candidates: Vec<String>,
    },
    /// HG9102 at the segment: every full spelling that would be unambiguous.
    Ambiguous {
        range: TextRange,
        written: String,
        candidates: Vec<String>,
    },
    /// HG9103: `{g} is not run by test {t}`, `g` the group or chart to add.
    NotRun { name: String },
}

fn key(s: &str) -> String {
    index::key(s)
}

impl RunScope {
    /// The scope of a run list (group and chart items, in run order).
    pub fn build(
        db: &dyn salsa::Database,
        ws: Workspace,
        run: &[(ItemKind, File, u32)],
    ) -> RunScope {
        let index = db::global_index(db, ws);
        let mut scope = RunScope::default();
        for &(kind, file, item) in run {
            let loc = ItemLoc::new(db, file, item);
            let Some(root) = db::item_root(db, loc) else {
                continue;
            };
            match (kind, ast::Item::cast(root)) {
                (ItemKind::Group, Some(ast::Item::Group(group))) => {
                    scope.groups.push(group_scope(index, &group, file, item));
                }
                (ItemKind::Chart, Some(ast::Item::Chart(chart))) => {
                    for path in chart.syntax().descendants().filter_map(ast::Path::cast) {
                        let mut segments = path.segments();
                        if let (Some(first), Some(_)) = (segments.next(), segments.next())
                            && !first.text().eq_ignore_ascii_case("SFC")
                        {
                            scope
                                .externals
                                .insert(key(&super::chart::compact(path.syntax())));
                        }
                    }
                    scope.charts.push(chart_scope(&chart, file, item));
                }
                _ => {}
            }
        }
        scope
    }

    fn chart_named(&self, name: &str) -> Option<usize> {
        self.charts
            .iter()
            .position(|c| c.name.eq_ignore_ascii_case(name))
    }

    fn group_named(&self, name: &str) -> Option<usize> {
        self.groups
            .iter()
            .position(|g| g.name.eq_ignore_ascii_case(name))
    }

    /// Every (group, instance) of that instance name.
    fn instances_named(&self, name: &str) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (g, group) in self.groups.iter().enumerate() {
            if let Some(i) = group
                .instances
                .iter()
                .position(|i| i.name.eq_ignore_ascii_case(name))
            {
                out.push((g, i));
            }
        }
        out
    }
}

/// The instances of a group as the lowering runs them.
pub(crate) fn group_scope(
    index: &GlobalIndex,
    group: &ast::Group,
    file: File,
    item: u32,
) -> ScopeGroup {
    let mut seen = HashSet::new();
    let mut instances = Vec::new();
    for node in group.instances() {
        let Some(name) = node.name() else { continue };
        let Some(token) = name.token() else { continue };
        if !seen.insert(key(&name.text())) {
            continue;
        }
        let Some(graph) = node.graph().and_then(|g| index.graph(&g.text())) else {
            continue;
        };
        instances.push(ScopeInstance {
            name: name.text(),
            name_range: token.text_range(),
            graph: (graph.file, graph.item),
        });
    }
    ScopeGroup {
        name: group.name().map(|n| n.text()).unwrap_or_default(),
        file,
        item,
        instances,
    }
}

/// The variables, sequencers and steps of a chart as the lowering numbers them.
pub(crate) fn chart_scope(chart: &ast::Chart, file: File, item: u32) -> ScopeChart {
    let mut vars = Vec::new();
    let mut fb_types = Vec::new();
    let iec = chart.profile() == ast::Profile::Iec;
    let mut seen = HashSet::new();
    for (_, decl) in crate::rules::decls::declarations(chart.var_sections()) {
        let Some(name) = decl.name() else { continue };
        let Some(token) = name.token() else { continue };
        if !seen.insert(key(&name.text())) {
            continue;
        }
        fb_types.push(
            decl.ty()
                .and_then(|t| t.name())
                .and_then(|n| FbType::from_name(n.text()))
                .filter(|_| iec),
        );
        vars.push((
            name.text(),
            token.text_range(),
            decl.ty().and_then(|t| index::declared_type(&t)),
        ));
    }
    let mut sequencers = Vec::new();
    let mut seen = HashSet::new();
    for sequencer in chart.sequencers() {
        let Some(name) = sequencer.name() else {
            continue;
        };
        let Some(token) = name.token() else { continue };
        if !seen.insert(key(&name.text())) {
            continue;
        }
        let tree = Tree::build(&sequencer);
        let mut names = HashSet::new();
        let steps = tree
            .elems
            .iter()
            .filter(|e| e.kind == Kind::Step && names.insert(key(e.label())))
            .map(|e| (e.label().to_owned(), e.name_range.unwrap_or(e.header)))
            .collect();
        sequencers.push(ScopeSequencer {
            name: name.text(),
            name_range: token.text_range(),
            steps,
        });
    }
    ScopeChart {
        name: chart.name().map(|n| n.text()).unwrap_or_default(),
        file,
        item,
        vars,
        fb_types,
        sequencers,
    }
}

/// The resolution context: the workspace's names and the test's run scope.
pub(crate) struct Resolver<'a> {
    pub db: &'a dyn salsa::Database,
    pub ws: Workspace,
    pub index: &'a GlobalIndex,
    pub mnemonic: Mnemonic,
    pub scope: &'a RunScope,
}

const PSEUDO_INSTANCE: [&str; 2] = ["state", "previous"];

impl Resolver<'_> {
    fn loc(&self, file: File, item: u32, range: TextRange) -> (String, TextRange) {
        let offset = db::item_offsets(self.db, file)
            .get(item as usize)
            .copied()
            .unwrap_or_default();
        (file.path(self.db).clone(), range + offset)
    }

    fn graph_scope(&self, graph: (File, u32)) -> Option<&crate::resolve::GraphScope> {
        db::graph_scope(self.db, ItemLoc::new(self.db, graph.0, graph.1)).as_ref()
    }

    /// The name as declared that a segment's definition points at (for HG1104).
    pub fn declared_name(&self, def: &SegmentDef) -> Option<String> {
        match def {
            SegmentDef::Symbol { name } => Some(name.clone()),
            SegmentDef::Predefined { name } => Some((*name).to_owned()),
            SegmentDef::Group { file, range }
            | SegmentDef::Instance { file, range }
            | SegmentDef::GraphVariable { file, range }
            | SegmentDef::Chart { file, range }
            | SegmentDef::ChartVariable { file, range }
            | SegmentDef::Sequencer { file, range }
            | SegmentDef::Step { file, range } => {
                let table = crate::check::output_file_table(self.db, self.ws);
                let file = table.source_paths.get(file)?;
                let text = file.contents(self.db).text();
                text.get(usize::from(range.start())..usize::from(range.end()))
                    .map(str::to_owned)
            }
            SegmentDef::Address | SegmentDef::Block { .. } | SegmentDef::Member => None,
        }
    }

    /// Resolves a test path.
    pub fn resolve(&self, path: &ast::TestPath) -> Result<Resolution, PathError> {
        let whole = path.syntax().text_range();
        if let Some(address) = path.address() {
            let compact = address.compact_text();
            let read = crate::address::read(&compact, self.mnemonic)
                .or_else(|| crate::address::read(&compact, self.mnemonic.other()));
            let Some(Ok(a)) = read.map(|r| r.address) else {
                return Err(PathError::Unresolved {
                    range: whole,
                    message: format!("'{compact}' is no symbol, address, instance, chart or block"),
                    written: compact,
                    candidates: Vec::new(),
                });
            };
            return Ok(self.address(a, whole));
        }
        let segments = path.segment_texts();
        let quoted = path.symbol().is_some();
        let text = super::chart::compact(path.syntax());
        let Some((first, first_range)) = segments.first().cloned() else {
            return Err(self.unresolved(whole, &text, &text));
        };
        if segments.len() == 1 {
            // A global symbol, or an address written without a space (`MW10`).
            if let Some(position) = self.index.symbol_position(&first) {
                return Ok(self.symbol(position, first_range));
            }
            if !quoted && let Some(a) = index::read_address(&first, self.mnemonic) {
                return Ok(self.address(a, whole));
            }
            let mut candidates: Vec<String> =
                self.index.symbols.iter().map(|s| s.name.clone()).collect();
            candidates.extend(self.scope.charts.iter().map(|c| c.name.clone()));
            return Err(PathError::Unresolved {
                range: whole,
                message: format!("'{text}' is no symbol, address, instance, chart or block"),
                written: first,
                candidates,
            });
        }
        let rest = &segments[1..];
        // `DBn.DBX…` is an address (the parser reads it as one; a NAME `DB1` is one too).
        if !quoted && let Some(a) = index::read_address(&text, self.mnemonic) {
            return Ok(self.address(a, whole));
        }
        if !quoted {
            if let Some(c) = self.scope.chart_named(&first) {
                return self.chart_path(c, first_range, rest, &text);
            }
            if let Some(g) = self.scope.group_named(&first) {
                let group = &self.scope.groups[g];
                let mut segs = vec![(first_range, self.group_def(g))];
                let Some((inst, inst_range)) = rest.first() else {
                    return Err(self.unresolved(whole, &text, &first));
                };
                let Some(i) = group
                    .instances
                    .iter()
                    .position(|i| i.name.eq_ignore_ascii_case(inst))
                else {
                    return Err(PathError::Unresolved {
                        range: *inst_range,
                        message: format!("group {} has no variable or step '{inst}'", group.name),
                        written: inst.clone(),
                        candidates: group.instances.iter().map(|i| i.name.clone()).collect(),
                    });
                };
                segs.push((*inst_range, self.instance_def(g, i)));
                return self.instance_path(g, i, segs, &rest[1..], whole, &text);
            }
            let instances = self.scope.instances_named(&first);
            match instances.as_slice() {
                [(g, i)] => {
                    let segs = vec![(first_range, self.instance_def(*g, *i))];
                    return self.instance_path(*g, *i, segs, rest, whole, &text);
                }
                [_, _, ..] => {
                    let tail: String = rest.iter().map(|(s, _)| format!(".{s}")).collect();
                    return Err(PathError::Ambiguous {
                        range: first_range,
                        written: first.clone(),
                        candidates: instances
                            .iter()
                            .map(|&(g, i)| {
                                format!(
                                    "{}.{}{tail}",
                                    self.scope.groups[g].name,
                                    self.scope.groups[g].instances[i].name
                                )
                            })
                            .collect(),
                    });
                }
                [] => {}
            }
        }
        // A block: `Block.Param`, `Block.calls`.
        if let Some((block_key, name)) = self.block_key(&first)
            && rest.len() == 1
        {
            let (member, member_range) = &rest[0];
            let segs = vec![
                (first_range, SegmentDef::Block { name: name.clone() }),
                (*member_range, SegmentDef::Member),
            ];
            if member.eq_ignore_ascii_case("calls") {
                return Ok(Resolution {
                    settable: Err(format!("{name}.calls counts the calls")),
                    target: PathTarget::Calls {
                        key: block_key,
                        name,
                    },
                    ty: Some(Ty::Dint),
                    segments: segs,
                    not_an_output: None,
                });
            }
            let formal = self.block_formal(&first, &block_key, member);
            let (ty, not_an_output) = match formal {
                Formal::Unknown => (None, None),
                Formal::Output(ty) => (ty.and_then(values::ty), None),
                Formal::NotAnOutput => (None, Some((name.clone(), member.clone(), *member_range))),
            };
            return Ok(Resolution {
                target: PathTarget::Stub {
                    key: block_key,
                    name,
                    param: member.to_ascii_uppercase(),
                },
                ty,
                settable: Ok(()),
                segments: segs,
                not_an_output,
            });
        }
        // An external reference of a chart of the run list.
        let upper = key(&text);
        if self.scope.externals.contains(&upper) {
            return Ok(Resolution {
                target: PathTarget::External(upper),
                ty: None,
                settable: Ok(()),
                segments: segments
                    .iter()
                    .map(|(_, r)| (*r, SegmentDef::Member))
                    .collect(),
                not_an_output: None,
            });
        }
        // Not run by this test?
        if let Some(item) = self.index.item(&first)
            && matches!(item.kind, ItemKind::Group | ItemKind::Chart)
        {
            return Err(PathError::NotRun {
                name: item.name.clone(),
            });
        }
        if let Some(group) = self.group_with_instance(&first) {
            return Err(PathError::NotRun { name: group });
        }
        let mut candidates: Vec<String> =
            self.scope.charts.iter().map(|c| c.name.clone()).collect();
        candidates.extend(self.scope.groups.iter().map(|g| g.name.clone()));
        for g in &self.scope.groups {
            candidates.extend(g.instances.iter().map(|i| i.name.clone()));
        }
        Err(PathError::Unresolved {
            range: first_range,
            message: format!("'{text}' is no symbol, address, instance, chart or block"),
            written: first,
            candidates,
        })
    }

    fn unresolved(&self, range: TextRange, text: &str, written: &str) -> PathError {
        PathError::Unresolved {
            range,
            message: format!("'{text}' is no symbol, address, instance, chart or block"),
            written: written.to_owned(),
            candidates: Vec::new(),
        }
    }

    /// A group of the workspace (not in the run list) with an instance of that name.
    fn group_with_instance(&self, name: &str) -> Option<String> {
        for item in self
            .index
            .items
            .iter()
            .filter(|i| i.kind == ItemKind::Group)
        {
            let loc = ItemLoc::new(self.db, item.file, item.item);
            let Some(ast::Item::Group(group)) =
                db::item_root(self.db, loc).and_then(ast::Item::cast)
            else {
                continue;
            };
            if group.instances().any(|i| {
                i.name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
            }) {
                return Some(item.name.clone());
            }
        }
        None
    }

    fn address(&self, a: Address, range: TextRange) -> Resolution {
        let (ty, settable) = match a.area {
            Area::Timer | Area::Counter => (
                Some(Ty::Bool),
                Err("a timer or counter is set by its operations".to_owned()),
            ),
            _ => (values::ty(a.ty()), Ok(())),
        };
        Resolution {
            target: PathTarget::Address(a),
            ty,
            settable,
            segments: vec![(range, SegmentDef::Address)],
            not_an_output: None,
        }
    }

    fn symbol(&self, position: usize, range: TextRange) -> Resolution {
        let symbol = &self.index.symbols[position];
        let timer = matches!(symbol.ty, Some(Type::Timer | Type::Counter))
            || symbol
                .address
                .as_ref()
                .is_some_and(|a| matches!(a.area, Area::Timer | Area::Counter));
        let (ty, settable) = if timer {
            (
                Some(Ty::Bool),
                Err("a timer or counter is set by its operations".to_owned()),
            )
        } else {
            (symbol.ty.and_then(values::ty), Ok(()))
        };
        Resolution {
            target: PathTarget::Symbol(position, symbol.address.clone()),
            ty,
            settable,
            segments: vec![(
                range,
                SegmentDef::Symbol {
                    name: symbol.name.clone(),
                },
            )],
            not_an_output: None,
        }
    }

    fn group_def(&self, g: usize) -> SegmentDef {
        let group = &self.scope.groups[g];
        let range = self
            .index
            .items_named(&group.name)
            .find(|i| i.file == group.file && i.item == group.item)
            .map(|i| i.name_loc.range)
            .unwrap_or_default();
        let (file, range) = self.loc(group.file, group.item, range);
        SegmentDef::Group { file, range }
    }

    fn instance_def(&self, g: usize, i: usize) -> SegmentDef {
        let group = &self.scope.groups[g];
        let (file, range) = self.loc(group.file, group.item, group.instances[i].name_range);
        SegmentDef::Instance { file, range }
    }

    /// `Inst.Var`, `Inst.state`, `Inst.previous` after the instance.
    fn instance_path(
        &self,
        g: usize,
        i: usize,
        mut segs: Vec<(TextRange, SegmentDef)>,
        rest: &[(String, TextRange)],
        whole: TextRange,
        text: &str,
    ) -> Result<Resolution, PathError> {
        let instance = &self.scope.groups[g].instances[i];
        let [(member, member_range)] = rest else {
            return Err(self.unresolved(whole, text, text));
        };
        if let Some(p) = PSEUDO_INSTANCE
            .iter()
            .position(|p| p.eq_ignore_ascii_case(member))
        {
            segs.push((*member_range, SegmentDef::Member));
            return Ok(Resolution {
                target: PathTarget::InstState {
                    group: g,
                    instance: i,
                    previous: p == 1,
                },
                ty: Some(Ty::Word),
                settable: Err(format!(
                    "{}.{member} is kept by the instance",
                    instance.name
                )),
                segments: segs,
                not_an_output: None,
            });
        }
        let scope = self.graph_scope(instance.graph);
        if let Some(scope) = scope
            && let Some(v) = scope.var(member)
        {
            let var = &scope.vars[v];
            let (file, range) = self.loc(instance.graph.0, instance.graph.1, var.name_range);
            segs.push((*member_range, SegmentDef::GraphVariable { file, range }));
            let ty = var.ty.and_then(values::ty);
            let settable = match (ty, self.constant_actual(g, i, member)) {
                (Some(Ty::Timer | Ty::Counter), _) => {
                    Err("a timer or counter is set by its operations".to_owned())
                }
                (_, Some(constant)) => Err(format!("its actual is the constant {constant}")),
                _ => Ok(()),
            };
            return Ok(Resolution {
                target: PathTarget::InstVar {
                    group: g,
                    instance: i,
                    var: predef_count() + v as VarIdx,
                },
                ty: ty.map(|t| {
                    if matches!(t, Ty::Timer | Ty::Counter) {
                        Ty::Bool
                    } else {
                        t
                    }
                }),
                settable,
                segments: segs,
                not_an_output: None,
            });
        }
        if let (Some(var), Some(p)) = (predef_index(member), lang::predefined(member)) {
            segs.push((*member_range, SegmentDef::Predefined { name: p.name }));
            let settable = if !p.writable || p.name == "INIT_SD" {
                Err(format!("{} is kept by the instance", p.name))
            } else if let Some(constant) = self.constant_actual(g, i, member) {
                Err(format!("its actual is the constant {constant}"))
            } else {
                Ok(())
            };
            return Ok(Resolution {
                target: PathTarget::InstVar {
                    group: g,
                    instance: i,
                    var,
                },
                ty: values::ty(p.ty),
                settable,
                segments: segs,
                not_an_output: None,
            });
        }
        let mut candidates: Vec<String> = scope
            .map(|s| s.vars.iter().map(|v| v.name.clone()).collect())
            .unwrap_or_default();
        candidates.extend(lang::PREDEFINED.iter().map(|p| p.name.to_owned()));
        candidates.extend(PSEUDO_INSTANCE.iter().map(|s| (*s).to_owned()));
        Err(PathError::Unresolved {
            range: *member_range,
            message: format!(
                "{} has no variable or step '{member}'",
                scope.map_or_else(|| format!("instance {}", instance.name), |s| s.owner())
            ),
            written: member.clone(),
            candidates,
        })
    }

    /// The constant an instance wires to the formal `member`, as written (§2.1: writes to it
    /// are discarded, so a test cannot set it).
    fn constant_actual(&self, g: usize, i: usize, member: &str) -> Option<String> {
        let group = &self.scope.groups[g];
        let loc = ItemLoc::new(self.db, group.file, group.item);
        let Some(ast::Item::Group(node)) = db::item_root(self.db, loc).and_then(ast::Item::cast)
        else {
            return None;
        };
        let name = &group.instances[i].name;
        let instance = node.instances().find(|n| {
            n.name()
                .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
        })?;
        let actual = instance.actuals().find(|a| {
            a.formal()
                .is_some_and(|f| f.text().eq_ignore_ascii_case(member))
        })?;
        match actual.value()? {
            ast::Operand::Literal(lit) => Some(lit.text()),
            _ => None,
        }
    }

    /// `Chart.state`, `Chart.Var`, `Chart.[Seq.]Step[.X|.T|.error]`.
    fn chart_path(
        &self,
        c: usize,
        first_range: TextRange,
        rest: &[(String, TextRange)],
        text: &str,
    ) -> Result<Resolution, PathError> {
        let chart = &self.scope.charts[c];
        let chart_def = {
            let range = self
                .index
                .items_named(&chart.name)
                .find(|i| i.file == chart.file && i.item == chart.item)
                .map(|i| i.name_loc.range)
                .unwrap_or_default();
            let (file, range) = self.loc(chart.file, chart.item, range);
            SegmentDef::Chart { file, range }
        };
        let mut segs = vec![(first_range, chart_def)];
        let owner = format!("chart {}", chart.name);
        let (name, name_range) = &rest[0];
        if rest.len() == 1 && name.eq_ignore_ascii_case("state") {
            segs.push((*name_range, SegmentDef::Member));
            return Ok(Resolution {
                target: PathTarget::ChartState { chart: c },
                ty: Some(Ty::OpState),
                settable: Err(format!("{}.state changes by commands", chart.name)),
                segments: segs,
                not_an_output: None,
            });
        }
        if rest.len() == 1
            && let Some(v) = chart
                .vars
                .iter()
                .position(|v| v.0.eq_ignore_ascii_case(name))
        {
            if let Some(Some(fb_ty)) = chart.fb_types.get(v) {
                return Err(PathError::Unresolved {
                    range: *name_range,
                    message: format!(
                        "{} '{}' is a function block instance: name one of its members",
                        fb_ty.name(),
                        chart.vars[v].0
                    ),
                    written: name.clone(),
                    candidates: fb_ty
                        .members()
                        .map(|m| format!("{}.{}", chart.vars[v].0, m.name()))
                        .collect(),
                });
            }
            let (file, range) = self.loc(chart.file, chart.item, chart.vars[v].1);
            segs.push((*name_range, SegmentDef::ChartVariable { file, range }));
            return Ok(Resolution {
                target: PathTarget::ChartVar { chart: c, var: v },
                ty: Some(chart.vars[v].2.and_then(values::ty).unwrap_or(Ty::Bool)),
                settable: Ok(()),
                segments: segs,
                not_an_output: None,
            });
        }
        // `Fb.Member` of an IEC chart: inputs can be set, outputs only read.
        if rest.len() == 2
            && let Some(v) = chart
                .vars
                .iter()
                .position(|v| v.0.eq_ignore_ascii_case(name))
            && let Some(Some(fb_ty)) = chart.fb_types.get(v)
        {
            let (member_name, member_range) = &rest[1];
            let Some(member) = fb_ty.member(member_name) else {
                return Err(PathError::Unresolved {
                    range: *member_range,
                    message: format!(
                        "{} '{}' has no member '{member_name}'",
                        fb_ty.name(),
                        chart.vars[v].0
                    ),
                    written: member_name.clone(),
                    candidates: fb_ty.members().map(|m| m.name().to_owned()).collect(),
                });
            };
            let (file, range) = self.loc(chart.file, chart.item, chart.vars[v].1);
            segs.push((*name_range, SegmentDef::ChartVariable { file, range }));
            segs.push((*member_range, SegmentDef::Member));
            let settable = if fb_ty.inputs().contains(&member) {
                Ok(())
            } else {
                Err(format!(
                    "{text} is an output of the function block, computed when it is called"
                ))
            };
            return Ok(Resolution {
                target: PathTarget::ChartFb {
                    chart: c,
                    var: v,
                    member,
                },
                ty: Some(member.ty()),
                settable,
                segments: segs,
                not_an_output: None,
            });
        }
        // `Seq.Step…` or `Step…`.
        let seq = chart
            .sequencers
            .iter()
            .position(|s| s.name.eq_ignore_ascii_case(name))
            .filter(|_| rest.len() >= 2);
        let (candidates, step_rest): (Vec<(usize, usize)>, &[Segment]) = match seq {
            Some(s) => {
                let (file, range) =
                    self.loc(chart.file, chart.item, chart.sequencers[s].name_range);
                segs.push((*name_range, SegmentDef::Sequencer { file, range }));
                let (step, _) = &rest[1];
                let found = chart.sequencers[s]
                    .steps
                    .iter()
                    .position(|(n, _)| n.eq_ignore_ascii_case(step))
                    .map(|p| (s, p));
                (found.into_iter().collect(), &rest[1..])
            }
            None => {
                let found = chart
                    .sequencers
                    .iter()
                    .enumerate()
                    .filter_map(|(s, seq)| {
                        seq.steps
                            .iter()
                            .position(|(n, _)| n.eq_ignore_ascii_case(name))
                            .map(|p| (s, p))
                    })
                    .collect();
                (found, rest)
            }
        };
        let (step_name, step_range) = &step_rest[0];
        let member = match step_rest.get(1) {
            None => Some(StepMember::Active),
            Some((m, _)) => match m.to_ascii_lowercase().as_str() {
                "x" => Some(StepMember::Active),
                "t" => Some(StepMember::Time),
                "error" => Some(StepMember::Error),
                _ => None,
            },
        };
        match candidates.as_slice() {
            [(s, p)] if step_rest.len() <= 2 && member.is_some() => {
                let (file, range) =
                    self.loc(chart.file, chart.item, chart.sequencers[*s].steps[*p].1);
                segs.push((*step_range, SegmentDef::Step { file, range }));
                if let Some((_, r)) = step_rest.get(1) {
                    segs.push((*r, SegmentDef::Member));
                }
                let member = member.unwrap_or(StepMember::Active);
                Ok(Resolution {
                    target: PathTarget::Step {
                        chart: c,
                        sequencer: *s,
                        step: *p,
                        member,
                    },
                    ty: Some(if member == StepMember::Time {
                        Ty::Time
                    } else {
                        Ty::Bool
                    }),
                    settable: Err(format!("{text} is kept by the chart")),
                    segments: segs,
                    not_an_output: None,
                })
            }
            [_, _, ..] => {
                let tail: String = step_rest[1..]
                    .iter()
                    .map(|(s, _)| format!(".{s}"))
                    .collect();
                Err(PathError::Ambiguous {
                    range: *step_range,
                    written: step_name.clone(),
                    candidates: candidates
                        .iter()
                        .map(|&(s, p)| {
                            format!(
                                "{}.{}.{}{tail}",
                                chart.name,
                                chart.sequencers[s].name,
                                chart.sequencers[s].steps[p].0
                            )
                        })
                        .collect(),
                })
            }
            _ => {
                // Report the first segment that does not fit.
                let (bad, bad_range) = if candidates.is_empty() {
                    (step_name.clone(), *step_range)
                } else {
                    step_rest
                        .get(1)
                        .cloned()
                        .or_else(|| step_rest.get(2).cloned())
                        .unwrap_or((step_name.clone(), *step_range))
                };
                let mut names: Vec<String> = chart.vars.iter().map(|v| v.0.clone()).collect();
                for s in &chart.sequencers {
                    names.push(s.name.clone());
                    names.extend(s.steps.iter().map(|(n, _)| n.clone()));
                }
                names.push("state".to_owned());
                Err(PathError::Unresolved {
                    range: bad_range,
                    message: format!("{owner} has no variable or step '{bad}'"),
                    written: bad,
                    candidates: names,
                })
            }
        }
    }

    /// The key and canonical name of a block named by a path's first segment.
    pub fn block_key(&self, text: &str) -> Option<(String, String)> {
        block_key(self.index, text, self.mnemonic)
    }

    /// The formal `param` of the block's interface, if the workspace declares one.
    fn block_formal(&self, written: &str, wanted: &str, param: &str) -> Formal {
        for entry in &self.index.block_interfaces {
            let reference = entry.reference.trim();
            let reference = ast::unquote(reference);
            let same = block_key(self.index, reference, self.mnemonic)
                .is_some_and(|(k, _)| k == wanted)
                || reference.eq_ignore_ascii_case(written);
            if !same {
                continue;
            }
            let loc = ItemLoc::new(self.db, entry.file, entry.item);
            let Some(ast::Item::BlockInterface(interface)) =
                db::item_root(self.db, loc).and_then(ast::Item::cast)
            else {
                return Formal::Unknown;
            };
            for (section, decl) in crate::rules::decls::declarations(interface.var_sections()) {
                if decl
                    .name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(param))
                {
                    return match section {
                        Section::Out | Section::InOut => Formal::Output(
                            decl.ty().and_then(|t| index::declared_type_in(&t, true)),
                        ),
                        _ => Formal::NotAnOutput,
                    };
                }
            }
            return Formal::NotAnOutput;
        }
        Formal::Unknown
    }
}

/// A segment of a path as written, with its range.
type Segment = (String, TextRange);

enum Formal {
    Unknown,
    Output(Option<Type>),
    NotAnOutput,
}

fn predef_count() -> VarIdx {
    higraph_runtime::program::Predef::ALL.len() as VarIdx
}

/// The key and canonical name of a block written as `text` (an address with or without
/// spaces, or a symbol name without quotes); `None` if it names no callable block.
pub(crate) fn block_key(
    index: &GlobalIndex,
    text: &str,
    mnemonic: Mnemonic,
) -> Option<(String, String)> {
    let compact: String = text.split_whitespace().collect();
    if let Some(address) = index::read_address(&compact, mnemonic)
        && address.block_kind().is_some_and(|k| k.is_callable())
    {
        let shown = address.display(Mnemonic::Simatic).replace(' ', "");
        return Some((shown.clone(), shown));
    }
    let symbol = index.symbol(text)?;
    match &symbol.address {
        Some(a) if a.block_kind().is_some_and(|k| k.is_callable()) => Some((
            a.display(Mnemonic::Simatic).replace(' ', ""),
            symbol.name.clone(),
        )),
        Some(_) => None,
        None => Some((index::key(&symbol.name), symbol.name.clone())),
    }
}

/// The run list of a test: its `run` entries (groups and plain charts the index knows, in
/// order, each once), else every group and plain chart of the workspace.
pub(crate) fn run_list(
    db: &dyn salsa::Database,
    ws: Workspace,
    test: &ast::Test,
) -> Vec<(ItemKind, File, u32)> {
    let index = db::global_index(db, ws);
    let run = test.statements().find_map(|s| match s {
        ast::TestStmt::Run(run) => Some(run),
        _ => None,
    });
    let Some(run) = run else {
        return default_run(db, ws);
    };
    let mut out: Vec<(ItemKind, File, u32)> = Vec::new();
    for entry in run.entries() {
        let Some(item) = index.item(&entry.text()) else {
            continue;
        };
        if !matches!(item.kind, ItemKind::Group | ItemKind::Chart)
            || (item.kind == ItemKind::Chart && is_chart_type(db, item.file, item.item))
        {
            continue;
        }
        let this = (item.kind, item.file, item.item);
        if !out.contains(&this) {
            out.push(this);
        }
    }
    out
}

/// Every group and plain chart of the workspace (the first of each name), in workspace order.
pub(crate) fn default_run(db: &dyn salsa::Database, ws: Workspace) -> Vec<(ItemKind, File, u32)> {
    let index = db::global_index(db, ws);
    index
        .items
        .iter()
        .filter(|i| matches!(i.kind, ItemKind::Group | ItemKind::Chart))
        .filter(|i| {
            index
                .items_named(&i.name)
                .next()
                .is_some_and(|first| first.file == i.file && first.item == i.item)
        })
        .filter(|i| i.kind != ItemKind::Chart || !is_chart_type(db, i.file, i.item))
        .map(|i| (i.kind, i.file, i.item))
        .collect()
}

fn is_chart_type(db: &dyn salsa::Database, file: File, item: u32) -> bool {
    let loc = ItemLoc::new(db, file, item);
    matches!(
        db::item_root(db, loc).and_then(ast::Item::cast),
        Some(ast::Item::Chart(c)) if c.is_type()
    )
}
