//! Pictures of graphs, groups and charts (`tooling.md` §6): SVG laid out here, without
//! Graphviz, or Graphviz DOT text of the same structure.
//!
//! The flow is: find the item by name in the [global index](crate::db::global_index) → read
//! its [model] from the syntax tree → [`dot`] text, or [`layout`] to a [`Picture`] and then
//! SVG.

pub mod dot;
mod layered;
pub mod layout;
pub mod model;
pub mod picture;

use higraph_syntax::ast;

use crate::{Analysis, Cancellable, db};
pub use picture::{BBox, Data, Picture, Shape, Text};

/// The output format of [`Analysis::render`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderFormat {
    Svg,
    Dot,
}

/// The model of a named item.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Model {
    Graph(model::GraphModel),
    Group(model::GroupModel),
    Chart(model::ChartModel),
}

impl Model {
    /// The DOT text.
    pub fn dot(&self) -> String {
        match self {
            Model::Graph(m) => dot::graph(m),
            Model::Group(m) => dot::group(m),
            Model::Chart(m) => dot::chart(m),
        }
    }

    /// The laid-out picture.
    pub fn picture(&self) -> Picture {
        match self {
            Model::Graph(m) => layout::graph(m),
            Model::Group(m) => layout::group(m),
            Model::Chart(m) => layout::chart(m),
        }
    }
}

impl Analysis {
    /// A picture of the graph, group or chart `name` (case-insensitive). `Err` names what the
    /// workspace has when there is no such item.
    pub fn render(&self, name: &str, format: RenderFormat) -> Cancellable<Result<String, String>> {
        Ok(self.render_model(name)?.map(|model| match format {
            RenderFormat::Svg => model.picture().to_svg(),
            RenderFormat::Dot => model.dot(),
        }))
    }

    /// The laid-out picture of an item (for tests of the layout).
    pub fn render_picture(&self, name: &str) -> Cancellable<Result<Picture, String>> {
        Ok(self.render_model(name)?.map(|model| model.picture()))
    }

    /// Every graph, group or chart named `name` (case-insensitive), in workspace order, with
    /// where it is declared. More than one makes [`Analysis::render`] an error naming them; the
    /// command line asks for them to name the files its own way.
    pub fn render_candidates(&self, name: &str) -> Cancellable<Vec<Candidate>> {
        self.with_db(|db, ws| candidates(db, db::global_index(db, ws), name))
    }

    /// The model of the graph, group or chart `name`.
    pub fn render_model(&self, name: &str) -> Cancellable<Result<Model, String>> {
        let found = self.with_db(|db, ws| Some(find(db, ws, name)))?;
        Ok(found.unwrap_or_else(|| {
            Err(format!(
                "no graph, group or chart named '{name}': the workspace is empty"
            ))
        }))
    }
}

/// A graph, group or chart a name may mean, and where it is declared.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Candidate {
    /// `graph`, `group` or `chart`.
    pub kind: &'static str,
    /// The name as declared.
    pub name: String,
    /// The file's workspace path.
    pub file: String,
    /// The 1-based line of the name.
    pub line: u32,
}

/// The items a name may mean, in workspace order.
fn candidates(
    db: &dyn salsa::Database,
    index: &crate::index::GlobalIndex,
    name: &str,
) -> Vec<Candidate> {
    index
        .items_named(name)
        .filter_map(|item| {
            let kind = match item.kind {
                db::ItemKind::Graph => "graph",
                db::ItemKind::Group => "group",
                db::ItemKind::Chart => "chart",
                _ => return None,
            };
            let offset = db::absolute_range(db, &item.name_loc).start();
            let line = crate::LineIndex::new(item.file.contents(db).text())
                .line_column(offset)
                .line;
            Some(Candidate {
                kind,
                name: item.name.clone(),
                file: item.file.path(db).clone(),
                line,
            })
        })
        .collect()
}

/// The message for a name that several items share: `several graphs, groups or charts are
/// named 'X' (rename all but one to draw it): graph X at a.higraph:3, group X at b.higraph:1`.
/// `path` names a file (the command line names files relative to the current directory).
pub fn ambiguity_message(
    name: &str,
    candidates: &[Candidate],
    path: impl Fn(&str) -> String,
) -> String {
    let list: Vec<String> = candidates
        .iter()
        .map(|c| format!("{} {} at {}:{}", c.kind, c.name, path(&c.file), c.line))
        .collect();
    format!(
        "{} items are named '{name}', so it is not clear which to draw (rename all but one): {}",
        candidates.len(),
        list.join(", ")
    )
}

/// Finds and reads the item.
fn find(db: &dyn salsa::Database, ws: db::Workspace, name: &str) -> Result<Model, String> {
    let index = db::global_index(db, ws);
    let Some(item) = index.item(name) else {
        return Err(not_found(index, name));
    };
    let candidates = candidates(db, index, name);
    if candidates.len() > 1 {
        return Err(ambiguity_message(name, &candidates, str::to_owned));
    }
    let loc = db::ItemLoc::new(db, item.file, item.item);
    let root =
        db::item_root(db, loc).ok_or_else(|| format!("'{}' could not be read", item.name))?;
    let model = match ast::Item::cast(root) {
        Some(ast::Item::Graph(g)) => Model::Graph(model::graph_model(&g)),
        Some(ast::Item::Group(g)) => Model::Group(model::group_model(&g)),
        Some(ast::Item::Chart(c)) => Model::Chart(model::chart_model(&c)),
        _ => return Err(format!("'{}' is not a graph, group or chart", item.name)),
    };
    Ok(model)
}

/// The message for an unknown name: what there is instead.
fn not_found(index: &crate::index::GlobalIndex, name: &str) -> String {
    let list = |kind: db::ItemKind| -> String {
        let names: Vec<&str> = index
            .items
            .iter()
            .filter(|i| i.kind == kind)
            .map(|i| i.name.as_str())
            .collect();
        if names.is_empty() {
            "none".to_owned()
        } else {
            names.join(", ")
        }
    };
    format!(
        "no graph, group or chart named '{name}'; graphs: {}; groups: {}; charts: {}",
        list(db::ItemKind::Graph),
        list(db::ItemKind::Group),
        list(db::ItemKind::Chart)
    )
}
