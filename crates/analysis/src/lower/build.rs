//! The lowering state: the program being built, the origin side table, and what the test
//! paths need to know about the groups, instances and charts lowered (their names).
//!
//! Groups and charts are lowered on demand (those of a run list); the graphs their instances
//! name are lowered once each, in order of first use. Everything is linear in the size of the
//! items lowered.

use std::collections::HashMap;

use higraph_runtime::Program;
use higraph_runtime::program::{
    BlockId, BlockInfo, CellId, CellInfo, CounterId, Group, GroupOptions, Instance,
    InternalMessage, Origin, Place, TimerId, VarIdx,
};
use higraph_runtime::value::{Ty, Value};
use higraph_syntax::{TextRange, ast};

use super::graph::{GraphLowering, GraphMeta};
use super::values;
use crate::db::{self, File, ItemLoc, Workspace};
use crate::index::{self, GlobalIndex};
use crate::lang::Mnemonic;
use crate::rules::Ctx;
use crate::rules::group::actuals::{self, Value as ActualValue};

/// The lowering of one program.
pub(crate) struct Lowerer<'a> {
    pub db: &'a dyn salsa::Database,
    pub ws: Workspace,
    pub index: &'a GlobalIndex,
    pub program: Program,
    pub origins: Vec<(String, TextRange)>,
    /// Graph items lowered, by (file, item index).
    graphs: HashMap<(File, u32), u32>,
    pub graph_meta: Vec<GraphMeta>,
    /// Blocks by key (normalised address, else upper-case symbol name).
    blocks: HashMap<String, BlockId>,
    /// External references of charts by upper-case text: one cell each.
    pub externals: HashMap<String, CellId>,
    /// What `build` needs to write names as the text did (`names.rs`).
    pub names: super::names::LowerNames,
}

impl<'a> Lowerer<'a> {
    pub fn new(db: &'a dyn salsa::Database, ws: Workspace) -> Lowerer<'a> {
        Lowerer {
            db,
            ws,
            index: db::global_index(db, ws),
            program: Program::default(),
            origins: Vec::new(),
            graphs: HashMap::new(),
            graph_meta: Vec::new(),
            blocks: HashMap::new(),
            externals: HashMap::new(),
            names: Default::default(),
        }
    }

    /// The origin of an item-relative range.
    pub fn origin(&mut self, file: File, item: u32, range: TextRange) -> Origin {
        let offset = db::item_offsets(self.db, file)
            .get(item as usize)
            .copied()
            .unwrap_or_default();
        self.origins
            .push((file.path(self.db).clone(), range + offset));
        Origin(u32::try_from(self.origins.len() - 1).unwrap_or(u32::MAX - 1))
    }

    /// A new cell.
    pub fn cell(&mut self, ty: Ty, init: Option<Value>) -> CellId {
        let init = init.unwrap_or_else(|| Value::zero(ty));
        self.program.cells.push(CellInfo { ty, init });
        (self.program.cells.len() - 1) as CellId
    }

    /// The block a `CALL`/`CC` target or a test path names, by key; registered on first use.
    pub fn block(&mut self, key: String, name: String) -> BlockId {
        if let Some(&id) = self.blocks.get(&key) {
            return id;
        }
        self.program.blocks.push(BlockInfo { name });
        let id = (self.program.blocks.len() - 1) as BlockId;
        self.blocks.insert(key, id);
        id
    }

    /// The block of a `CALL`/`CC` target.
    pub fn block_of_ref(&mut self, target: &ast::BlockRef, mnemonic: Mnemonic) -> Option<BlockId> {
        let text = if let Some(address) = target.address() {
            address.compact_text()
        } else if let Some(name) = target.name_ref() {
            name.text()
        } else {
            target.symbol_ref()?.name()
        };
        let (key, name) = super::paths::block_key(self.index, &text, mnemonic)?;
        Some(self.block(key, name))
    }

    /// Lowers a graph item once; its id and meta index.
    pub fn graph(&mut self, file: File, item: u32) -> Option<u32> {
        if let Some(&id) = self.graphs.get(&(file, item)) {
            return Some(id);
        }
        let loc = ItemLoc::new(self.db, file, item);
        let root = db::item_root(self.db, loc)?;
        let ast::Item::Graph(graph) = ast::Item::cast(root)? else {
            return None;
        };
        let scope = db::graph_scope(self.db, loc).clone()?;
        let ctx = Ctx::for_item(self.db, self.ws, loc);
        let mnemonic = ctx.mnemonic;
        let (lowered, meta) = {
            let mut gl = GraphLowering {
                lw: self,
                ctx,
                scope,
                item: loc,
                mnemonic,
                slot: None,
                time_slot: None,
            };
            gl.graph(&graph)
        };
        self.program.graphs.push(lowered);
        self.graph_meta.push(meta);
        let id = (self.program.graphs.len() - 1) as u32;
        self.graphs.insert((file, item), id);
        Some(id)
    }

    /// Lowers a group item; its index in `program.groups`.
    pub fn group(&mut self, file: File, item: u32) -> Option<u32> {
        let loc = ItemLoc::new(self.db, file, item);
        let root = db::item_root(self.db, loc)?;
        let ast::Item::Group(group) = ast::Item::cast(root)? else {
            return None;
        };
        let mut options = GroupOptions::default();
        for option in group.options() {
            let Some(name) = option.name().map(|n| n.text().to_ascii_lowercase()) else {
                continue;
            };
            match name.as_str() {
                "cyclic_rlo0" => options.cyclic_rlo0 = true,
                "any_once" => options.any_once = true,
                "precyclic_on_entry" => options.precyclic_on_entry = true,
                _ => {}
            }
        }
        // First pass: every instance (the first of each name, C3) with its graph and own
        // cells.
        let mut instances: Vec<(ast::Instance, Instance, Option<usize>)> = Vec::new();
        let mut by_name: HashMap<String, usize> = HashMap::new();
        for node in group.instances() {
            let Some(name) = node.name() else { continue };
            let key = index::key(&name.text());
            if by_name.contains_key(&key) {
                continue;
            }
            let graph_item = node
                .graph()
                .and_then(|g| self.index.graph(&g.text()))
                .map(|g| (g.file, g.item));
            let graph = graph_item.and_then(|(f, i)| self.graph(f, i));
            let Some(graph) = graph else {
                continue;
            };
            let vars = self.program.graphs[graph as usize].vars.clone();
            let binding = vars
                .iter()
                .map(|v| Place::Cell(self.cell(v.ty, v.init.clone())))
                .collect();
            by_name.insert(key, instances.len());
            instances.push((
                node,
                Instance {
                    name: name.text(),
                    graph,
                    binding,
                },
                Some(graph as usize),
            ));
        }
        // Second pass: the actuals.
        let mut ctx = Ctx::for_item(self.db, self.ws, loc);
        let own: Vec<Vec<Place>> = instances
            .iter()
            .map(|(_, i, _)| i.binding.clone())
            .collect();
        let graph_ids: Vec<u32> = instances.iter().map(|(_, i, _)| i.graph).collect();
        let mut internal: Vec<InternalMessage> = Vec::new();
        let mut internal_cells = std::collections::HashSet::new();
        let mut actual_symbols = HashMap::new();
        for (index, (node, instance, graph)) in instances.iter_mut().enumerate() {
            let Some(meta) = graph.map(|g| &self.graph_meta[g]) else {
                continue;
            };
            let graph = &self.program.graphs[instance.graph as usize];
            let mut wired = vec![false; instance.binding.len()];
            for actual in node.actuals() {
                let Some(formal) = actual.formal().map(|f| f.text()) else {
                    continue;
                };
                let Some(&var) = meta.vars.get(&index::key(&formal)) else {
                    continue;
                };
                let var = var as usize;
                if wired.get(var).copied().unwrap_or(true) {
                    continue;
                }
                let Some(operand) = actual.value() else {
                    continue;
                };
                let ty = graph.vars[var].ty;
                let place = match &operand {
                    ast::Operand::MessageTarget(target) => {
                        let receiver = target
                            .instance()
                            .and_then(|i| by_name.get(&index::key(&i.text())).copied());
                        let message = target.message().map(|m| m.text());
                        receiver.zip(message).and_then(|(r, msg)| {
                            let receiver_graph = graph_ids[r] as usize;
                            let msg_var = *self.graph_meta[receiver_graph]
                                .vars
                                .get(&index::key(&msg))?;
                            let place = own[r].get(msg_var as usize)?.clone();
                            if let Place::Cell(cell) = place
                                && self.program.graphs[receiver_graph].vars[msg_var as usize].msg_in
                                    == Some(true)
                                && internal_cells.insert(cell)
                            {
                                internal.push(InternalMessage {
                                    instance: r as u32,
                                    var: msg_var,
                                    cell,
                                });
                            }
                            Some(place)
                        })
                    }
                    other => match actuals::resolve(&mut ctx, other) {
                        ActualValue::Symbol(s) => {
                            actual_symbols.insert((index as u32, var as VarIdx), s.name.clone());
                            s.address.as_ref().and_then(values::place)
                        }
                        ActualValue::Address(a) => values::place(&a),
                        ActualValue::Constant(lit) => values::value_in(&lit, ty).map(Place::Const),
                        ActualValue::Message | ActualValue::Unknown => None,
                    },
                };
                ctx.out.diags.clear();
                if let Some(place) = place {
                    instance.binding[var] = place;
                    wired[var] = true;
                }
            }
            // Unwired TIMER and COUNTER variables are private objects.
            for (var, info) in graph.vars.iter().enumerate() {
                if wired[var] {
                    continue;
                }
                match info.ty {
                    Ty::Timer => {
                        instance.binding[var] =
                            Place::Timer(TimerId(65536 + self.program.private_timers));
                        self.program.private_timers += 1;
                    }
                    Ty::Counter => {
                        instance.binding[var] =
                            Place::Counter(CounterId(65536 + self.program.private_counters));
                        self.program.private_counters += 1;
                    }
                    _ => {}
                }
            }
        }
        self.names.group_own.push(
            own.iter()
                .map(|places| {
                    places
                        .iter()
                        .map(|p| match p {
                            Place::Cell(c) => *c,
                            _ => CellId::MAX,
                        })
                        .collect()
                })
                .collect(),
        );
        self.names.actual_symbols.push(actual_symbols);
        self.program.groups.push(Group {
            name: group.name().map(|n| n.text()).unwrap_or_default(),
            options,
            instances: instances.into_iter().map(|(_, i, _)| i).collect(),
            internal_messages: internal,
        });
        Some((self.program.groups.len() - 1) as u32)
    }

    /// The place of variable `var` of instance `i` of group `g`.
    pub fn var_place(&self, g: u32, i: u32, var: VarIdx) -> Option<&Place> {
        self.program
            .groups
            .get(g as usize)?
            .instances
            .get(i as usize)?
            .binding
            .get(var as usize)
    }
}

/// A readable dump of a lowered program (for snapshots and debugging): one line per cell,
/// graph variable, state, transition and instruction.
pub fn dump(program: &Program) -> String {
    super::dump::program(program)
}
