//! Prepare rename and workspace-wide rename (`tooling.md` §4).
//!
//! The edits are the references of [`defs::references`], so a rename reaches everything that
//! refers to the name, in every file of the workspace (open in an editor or not):
//!
//! * a graph variable: every instruction of the graph (`Name` and `#Name`), the formal side of
//!   every actual in every instance of the graph, every `Inst.Var` message target;
//! * an instance: the `Inst.` prefixes of message targets;
//! * a graph: `instance X : Graph`;
//! * a symbol: every use, in graphs, groups (also `fc`/`db`), charts and `block` items. A
//!   quoted use stays quoted; a plain use becomes quoted when the new name could not stand
//!   there unquoted (not an identifier, read as an address, reserved in that file, or taken by
//!   a variable of the graph or chart that uses it);
//! * a state (renumbering, `state 3` → `state 7`): its transition endpoints;
//! * a chart step: the jump and loop targets.
//!
//! A rename is refused, with a message and no edit, for what cannot be renamed (predefined
//! variables, keywords, operations, addresses, constants, imported symbols), for a new name
//! that breaks the name rules (HG1101–HG1103, HG7101, identifiers of ASCII letters, digits and
//! `_`; a state number 0..65535), and for a new name that is taken in the same namespace or
//! would change what another name refers to.

use std::collections::HashMap;

use higraph_syntax::{SyntaxKind, TextRange, TextSize, ast, ast::AstNode};

use super::{
    Edit, FilePosition, FileRange, SourceChange,
    defs::{self, Definition, ItemId, NameAt, Reference, ReferenceKind, UseTarget},
};
use crate::{
    Analysis, Cancellable,
    db::{self, File, ItemKind, Workspace},
    index,
    lang::{self, Mnemonic},
    resolve::{self, GraphScope},
};

impl Analysis {
    /// Checks that the name at `pos` can be renamed: its range and its current name (as
    /// declared), or why not.
    pub fn prepare_rename(
        &self,
        pos: &FilePosition,
    ) -> Cancellable<Result<(FileRange, String), String>> {
        let result = self.with_db(|db, ws| {
            let file = self.file(&pos.path);
            Some(file.ok_or_else(|| not_in_workspace(pos)).and_then(|file| {
                let at = renamable(db, ws, file, pos.offset)?;
                let range = FileRange {
                    path: pos.path.clone(),
                    range: at.range,
                };
                Ok((range, defs::definition_name(db, ws, &at.definition)))
            }))
        })?;
        Ok(result.unwrap_or_else(|| Err(NO_WORKSPACE.to_owned())))
    }

    /// Renames the name at `pos` to `new_name` everywhere in the workspace, or says why not.
    pub fn rename(
        &self,
        pos: &FilePosition,
        new_name: &str,
    ) -> Cancellable<Result<SourceChange, String>> {
        let result = self.with_db(|db, ws| {
            let file = self.file(&pos.path);
            Some(
                file.ok_or_else(|| not_in_workspace(pos))
                    .and_then(|file| rename(db, ws, file, pos.offset, new_name))
                    // A formatted file stays formatted (`relayout`).
                    .map(|change| super::relayout::keep_formatted(db, ws, change)),
            )
        })?;
        Ok(result.unwrap_or_else(|| Err(NO_WORKSPACE.to_owned())))
    }
}

const NO_WORKSPACE: &str = "no workspace is loaded";

fn not_in_workspace(pos: &FilePosition) -> String {
    format!("'{}' is not a file of the workspace", pos.path)
}

// ------------------------------------------------------------------------------ what

/// The definition at `offset` if it can be renamed, else why not.
fn renamable(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Result<NameAt, String> {
    let Some(at) = defs::definition_at(db, ws, file, offset) else {
        return Err(not_renamable(db, ws, file, offset));
    };
    match &at.definition {
        Definition::Predefined { name, .. } => Err(format!(
            "'{name}' is a predefined variable of every graph and cannot be renamed"
        )),
        Definition::BlockInterface(_) => Err(
            "a block interface is named by its block; rename the block's symbol instead".to_owned(),
        ),
        Definition::Symbol(position) => {
            let index = db::global_index(db, ws);
            match index.symbols.get(*position) {
                Some(symbol) => match symbol.source {
                    index::SymbolSource::Imported(_) => Err(format!(
                        "symbol '{}' is imported from {}; rename it in the STEP 7 symbol table",
                        symbol.name,
                        symbol.name_loc.file.path(db)
                    )),
                    index::SymbolSource::Declared => Ok(at),
                },
                None => Err(not_renamable(db, ws, file, offset)),
            }
        }
        _ => {
            // A later duplicate declaration (HG1201, HG2101, HG5003, HG7103, ...) names the
            // same thing as the first one; renaming it here would rename the first.
            let declaration = defs::declaration(db, ws, &at.definition);
            let on_declaration = defs::uses_at(db, ws, file, offset).is_empty();
            match declaration {
                Some(decl)
                    if on_declaration && (decl.file != file || decl.focus_range != at.range) =>
                {
                    Err(format!(
                        "'{}' is declared again here; only its first declaration counts: rename that one, or remove this one",
                        decl.name
                    ))
                }
                _ => Ok(at),
            }
        }
    }
}

/// Why the token at `offset` cannot be renamed.
fn not_renamable(db: &dyn salsa::Database, ws: Workspace, file: File, offset: TextSize) -> String {
    let root = db::parse(db, file).syntax_node();
    let Some(token) = defs::token_at(&root, offset).filter(|t| !t.kind().is_trivia()) else {
        return "there is no name at the cursor".to_owned();
    };
    for node in token.parent_ancestors() {
        let text = || node.text().to_string();
        let why = match node.kind() {
            SyntaxKind::OPCODE => format!(
                "'{}' is an STL operation; operations cannot be renamed",
                text()
            ),
            SyntaxKind::ADDRESS => {
                format!(
                    "'{}' is an absolute address; addresses cannot be renamed",
                    text()
                )
            }
            SyntaxKind::LITERAL => {
                format!("'{}' is a constant; constants cannot be renamed", text())
            }
            SyntaxKind::LABEL => format!("'{}' is a block label", text()),
            SyntaxKind::TYPE_REF => format!("'{}' is a data type", text()),
            SyntaxKind::STATUS_OPERAND => format!("'{}' is a status bit", text()),
            _ => continue,
        };
        return why;
    }
    let address = defs::uses_at(db, ws, file, offset)
        .into_iter()
        .any(|u| matches!(u.target, UseTarget::Address(_)));
    if address {
        return format!(
            "'{}' is an absolute address; addresses cannot be renamed",
            token.text()
        );
    }
    if token.kind().is_keyword() {
        return format!(
            "'{}' is a keyword of the language and cannot be renamed",
            token.text()
        );
    }
    if token.kind() == SyntaxKind::IDENT
        && token
            .parent()
            .is_some_and(|p| p.kind() == SyntaxKind::NAME_REF || p.kind() == SyntaxKind::VAR_REF)
    {
        return format!(
            "'{}' does not refer to a declaration of the workspace",
            token.text()
        );
    }
    "there is nothing to rename at the cursor".to_owned()
}

// ------------------------------------------------------------------------------ rename

/// The rename of the declared name at `offset` of `file` to `new_name`, as the rename request
/// does it, or why not: also the edits of the HG1101/HG1102 quick fixes ([`crate::check`]).
pub(crate) fn rename(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
    new_name: &str,
) -> Result<SourceChange, String> {
    let at = renamable(db, ws, file, offset)?;
    let definition = &at.definition;
    let old_name = defs::definition_name(db, ws, definition);
    let references = defs::references(db, ws, definition);
    let new_name = new_name.trim();
    let rules = NameRules::of(db, definition, &references);
    let new_text = rules.validate(db, ws, new_name, &references)?;
    if !new_text.eq_ignore_ascii_case(&old_name) {
        check_free(db, ws, definition, &new_text)?;
        test_paths_keep_meaning(db, ws, definition, &new_text, &references)?;
    }
    let mut change = SourceChange::default();
    let mut quoting = Quoting::default();
    for reference in &references {
        if !ws.files(db).contains(&reference.file) {
            return Err(format!(
                "'{}' is not a file of the workspace; it cannot be edited",
                reference.file.path(db)
            ));
        }
        let text = match (definition, reference.quoted, reference.kind) {
            (Definition::Symbol(_), false, kind) if kind != ReferenceKind::Declaration => {
                if quoting.plain_ok(db, ws, reference, &new_text) {
                    new_text.clone()
                } else {
                    format!("\"{new_text}\"")
                }
            }
            _ => new_text.clone(),
        };
        change.insert(
            reference.file.path(db),
            Edit {
                range: reference.range,
                new_text: text,
            },
        );
    }
    Ok(change)
}

/// Which names a definition may take.
enum NameRules {
    /// A state number 0..65535.
    StateNumber,
    /// A quoted symbol: any text without quotes or line breaks (§2.2: exempt from the name
    /// rules).
    Quoted,
    /// A declared NAME: an identifier passing HG1101–HG1103 in the mnemonic sets of
    /// `mnemonics`.
    Name {
        /// Used by name as an operand: it must not read as an address or address area.
        operand: bool,
        /// Steps, chart transitions, jumps and loops: at most 16 characters (HG7101).
        max_len: Option<usize>,
    },
}

impl NameRules {
    fn of(
        db: &dyn salsa::Database,
        definition: &Definition,
        references: &[Reference],
    ) -> NameRules {
        let declared_quoted = references
            .iter()
            .any(|r| r.kind == ReferenceKind::Declaration && r.quoted);
        match definition {
            Definition::State { .. } => NameRules::StateNumber,
            Definition::Symbol(_) if declared_quoted => NameRules::Quoted,
            Definition::Symbol(_) => NameRules::Name {
                operand: true,
                max_len: None,
            },
            Definition::Variable { owner, .. } => NameRules::Name {
                operand: matches!(
                    defs::item_kind(db, *owner),
                    Some(ItemKind::Graph | ItemKind::Chart)
                ),
                max_len: None,
            },
            Definition::Step { .. } | Definition::ChartTransition { .. } => NameRules::Name {
                operand: false,
                max_len: Some(16),
            },
            _ => NameRules::Name {
                operand: false,
                max_len: None,
            },
        }
    }

    /// Checks `name` and returns the text to write.
    fn validate(
        &self,
        db: &dyn salsa::Database,
        ws: Workspace,
        name: &str,
        references: &[Reference],
    ) -> Result<String, String> {
        if name.is_empty() {
            return Err("the new name is empty".to_owned());
        }
        match self {
            NameRules::StateNumber => {
                let number = name
                    .bytes()
                    .all(|b| b.is_ascii_digit())
                    .then(|| name.parse::<u32>().ok())
                    .flatten()
                    .filter(|n| *n <= 65535)
                    .ok_or_else(|| {
                        format!("'{name}' is not a state number: states are numbered 0 to 65535")
                    })?;
                Ok(number.to_string())
            }
            NameRules::Quoted => {
                if name.contains(['"', '\n', '\r']) {
                    return Err(format!(
                        "'{name}' cannot be a quoted symbol name: it contains a quote or a line break"
                    ));
                }
                Ok(name.to_owned())
            }
            NameRules::Name { operand, max_len } => {
                if !is_identifier(name) {
                    return Err(format!(
                        "'{name}' is not a valid name: use ASCII letters, digits and '_', not starting with a digit"
                    ));
                }
                if name.ends_with('_') {
                    return Err(format!("name '{name}' must not end with '_' (HG1101)"));
                }
                if name.contains("__") {
                    return Err(format!("name '{name}' must not contain '__' (HG1102)"));
                }
                if let Some(max) = max_len
                    && name.chars().count() > *max
                {
                    return Err(format!(
                        "name '{name}' has {} characters; at most {max} are allowed (HG7101)",
                        name.chars().count()
                    ));
                }
                for mnemonic in plain_mnemonics(db, ws, references) {
                    if let Some(kind) = lang::reserved_kind(name, mnemonic) {
                        return Err(format!(
                            "'{name}' is reserved ({kind}) and cannot be used as a name (HG1103)"
                        ));
                    }
                    if *operand && let Some(why) = reads_as_address(name, mnemonic) {
                        return Err(why);
                    }
                }
                Ok(name.to_owned())
            }
        }
    }
}

/// The mnemonic sets of the files where the name is written unquoted.
fn plain_mnemonics(
    db: &dyn salsa::Database,
    ws: Workspace,
    references: &[Reference],
) -> Vec<Mnemonic> {
    let mut sets = Vec::new();
    for reference in references.iter().filter(|r| !r.quoted) {
        let set = db::file_mnemonic(db, ws, reference.file);
        if !sets.contains(&set) {
            sets.push(set);
        }
    }
    sets
}

/// Why `name`, written as an operand in a file of `mnemonic`, would read as an address.
fn reads_as_address(name: &str, mnemonic: Mnemonic) -> Option<String> {
    if let Some(read) = resolve::address_without_space(name, mnemonic) {
        let shown = read
            .address
            .map_or_else(|_| name.to_owned(), |a| a.display(mnemonic));
        return Some(format!(
            "'{name}' reads as the address {shown} in an operand; choose another name"
        ));
    }
    resolve::area_word(name, mnemonic).map(|word| {
        format!(
            "'{name}' reads as the address area {} ({}) in an operand; choose another name",
            word.canonical, word.meaning
        )
    })
}

/// Can `name` be written unquoted (ASCII letters, digits and `_`, not starting with a digit)?
fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

// ------------------------------------------------------------------------------ collisions

/// Does the chart item have an action of that name?
fn action_named(db: &dyn salsa::Database, chart: ItemId, name: &str) -> bool {
    db::item_root(db, defs::item_loc(db, chart))
        .and_then(ast::Chart::cast)
        .is_some_and(|c| {
            c.actions()
                .filter_map(|a| a.name())
                .any(|n| n.text().eq_ignore_ascii_case(name))
        })
}

/// Refuses a new name that another declaration of the same namespace has, or that would
/// capture a use of a global symbol.
fn check_free(
    db: &dyn salsa::Database,
    ws: Workspace,
    definition: &Definition,
    new_name: &str,
) -> Result<(), String> {
    let same = |a: &str| a.eq_ignore_ascii_case(new_name);
    match definition {
        Definition::Graph(item) | Definition::Group(item) | Definition::Chart(item) => {
            top_level_free(db, ws, new_name, Some(*item), None)
        }
        Definition::Symbol(position) => top_level_free(db, ws, new_name, None, Some(*position)),
        Definition::Variable { owner, .. } => {
            let owner_name = owner_description(db, *owner);
            if defs::var_decl(db, *owner, new_name).is_some() {
                return Err(format!("{owner_name} already has a variable '{new_name}'"));
            }
            match defs::item_kind(db, *owner) {
                Some(ItemKind::Graph) => {
                    if let Some(p) = lang::predefined(new_name) {
                        return Err(format!(
                            "'{}' is a predefined variable of every graph",
                            p.name
                        ));
                    }
                    symbol_not_captured(db, ws, *owner, &owner_name, new_name)
                }
                Some(ItemKind::Chart) => {
                    if action_named(db, *owner, new_name) {
                        return Err(format!("{owner_name} already has an action '{new_name}'"));
                    }
                    symbol_not_captured(db, ws, *owner, &owner_name, new_name)
                }
                _ => Ok(()),
            }
        }
        Definition::Action { chart, .. } => {
            if action_named(db, *chart, new_name) || defs::var_decl(db, *chart, new_name).is_some()
            {
                return Err(format!(
                    "{} already has an action or variable '{new_name}'",
                    owner_description(db, *chart)
                ));
            }
            Ok(())
        }
        Definition::Instance { group, .. } => {
            let node = db::item_root(db, defs::item_loc(db, *group)).and_then(ast::Group::cast);
            let taken = node.is_some_and(|g| {
                g.instances()
                    .filter_map(|i| i.name())
                    .any(|n| same(&n.text()))
            });
            if taken {
                return Err(format!(
                    "{} already has an instance '{new_name}'",
                    owner_description(db, *group)
                ));
            }
            Ok(())
        }
        Definition::State { graph, .. } => {
            let taken = new_name.parse::<u32>().ok().and_then(|n| {
                defs::declaration(
                    db,
                    ws,
                    &Definition::State {
                        graph: *graph,
                        number: n,
                    },
                )
            });
            if taken.is_some() {
                return Err(format!(
                    "{} already has a state {new_name}",
                    owner_description(db, *graph)
                ));
            }
            Ok(())
        }
        Definition::Sequencer { chart, .. } => {
            let node = db::item_root(db, defs::item_loc(db, *chart)).and_then(ast::Chart::cast);
            let taken = node.is_some_and(|c| {
                c.sequencers()
                    .filter_map(|s| s.name())
                    .any(|n| same(&n.text()))
            });
            if taken {
                return Err(format!(
                    "{} already has a sequencer '{new_name}'",
                    owner_description(db, *chart)
                ));
            }
            Ok(())
        }
        Definition::Step {
            chart, sequencer, ..
        }
        | Definition::ChartTransition {
            chart, sequencer, ..
        } => {
            let is_step = matches!(definition, Definition::Step { .. });
            let probe = if is_step {
                Definition::Step {
                    chart: *chart,
                    sequencer: sequencer.clone(),
                    name: new_name.to_owned(),
                }
            } else {
                Definition::ChartTransition {
                    chart: *chart,
                    sequencer: sequencer.clone(),
                    name: new_name.to_owned(),
                }
            };
            if defs::declaration(db, ws, &probe).is_some() {
                let what = if is_step { "step" } else { "transition" };
                return Err(format!(
                    "sequencer {sequencer} already has a {what} '{new_name}'"
                ));
            }
            Ok(())
        }
        Definition::Predefined { .. } | Definition::BlockInterface(_) => Ok(()),
    }
}

/// A name that test paths use must keep what they mean: a path's first name is read as a
/// chart, a group, then an instance, and inside a chart `state`, a variable, a sequencer, then
/// a step (`runtime.md` §5.3), so a new name that another of those already has would change
/// or break the paths.
fn test_paths_keep_meaning(
    db: &dyn salsa::Database,
    ws: Workspace,
    definition: &Definition,
    new_name: &str,
    references: &[Reference],
) -> Result<(), String> {
    let in_tests = references.iter().any(|r| {
        item_at(db, r.file, r.range).and_then(|i| defs::item_kind(db, i)) == Some(ItemKind::Test)
    });
    if !in_tests {
        return Ok(());
    }
    let same = |a: &str| a.eq_ignore_ascii_case(new_name);
    let refuse = |why: String| Err(format!("test paths use this name, and {why}"));
    let instance_elsewhere = || {
        defs::items_of_kind(db, ws, &[ItemKind::Group])
            .into_iter()
            .filter_map(|g| db::item_root(db, defs::item_loc(db, g)).and_then(ast::Group::cast))
            .any(|g| {
                g.instances()
                    .filter_map(|i| i.name())
                    .any(|n| same(&n.text()))
            })
    };
    let chart_node =
        |chart: &ItemId| db::item_root(db, defs::item_loc(db, *chart)).and_then(ast::Chart::cast);
    let step_named = |chart: &ast::Chart| {
        chart
            .syntax()
            .descendants()
            .filter_map(ast::Step::cast)
            .filter_map(|s| s.name())
            .any(|n| same(&n.text()))
    };
    let sequencer_named = |chart: &ast::Chart| {
        chart
            .sequencers()
            .filter_map(|s| s.name())
            .any(|n| same(&n.text()))
    };
    match definition {
        Definition::Instance { .. } => {
            let index = db::global_index(db, ws);
            if let Some(item) = index.item(new_name)
                && matches!(item.kind, ItemKind::Group | ItemKind::Chart)
            {
                return refuse(format!("a path starting with '{new_name}' names that item"));
            }
            if instance_elsewhere() {
                return refuse(format!(
                    "another instance is named '{new_name}': its paths would be ambiguous"
                ));
            }
            Ok(())
        }
        Definition::Group(_) | Definition::Chart(_) if instance_elsewhere() => refuse(format!(
            "an instance is named '{new_name}': its paths would name this item"
        )),
        Definition::Variable { owner, .. } => match defs::item_kind(db, *owner) {
            Some(ItemKind::Graph) if same("state") || same("previous") => {
                refuse(format!("'Inst.{new_name}' is the instance's state"))
            }
            Some(ItemKind::Chart) => {
                let chart = chart_node(owner);
                if same("state") || chart.as_ref().is_some_and(step_named) {
                    refuse(format!(
                        "'Chart.{new_name}' names a step or the chart's state"
                    ))
                } else {
                    Ok(())
                }
            }
            _ => Ok(()),
        },
        Definition::Step { chart, .. } => {
            let node = chart_node(chart);
            let taken = same("state")
                || defs::var_decl(db, *chart, new_name).is_some()
                || node
                    .as_ref()
                    .is_some_and(|c| sequencer_named(c) || step_named(c));
            if taken {
                refuse(format!(
                    "'{new_name}' is a variable, sequencer, step or the state of the chart"
                ))
            } else {
                Ok(())
            }
        }
        Definition::Sequencer { chart, .. } => {
            if chart_node(chart).as_ref().is_some_and(step_named) {
                refuse(format!("the chart has a step '{new_name}'"))
            } else {
                Ok(())
            }
        }
        _ => Ok(()),
    }
}

/// HG1301 / HG6003: a top-level name (graph, group, chart, symbol) must stay unique.
fn top_level_free(
    db: &dyn salsa::Database,
    ws: Workspace,
    new_name: &str,
    item: Option<ItemId>,
    symbol: Option<usize>,
) -> Result<(), String> {
    let index = db::global_index(db, ws);
    let other_item = index
        .items_named(new_name)
        .find(|i| item.is_none_or(|own| own.file != i.file || own.index != i.item));
    if let Some(other) = other_item {
        let kind = match other.kind {
            ItemKind::Group => "group",
            ItemKind::Chart => "chart",
            _ => "graph",
        };
        return Err(format!(
            "'{new_name}' is already the name of {kind} {} in {}",
            other.name,
            other.file.path(db)
        ));
    }
    let other_symbol = index
        .symbols
        .iter()
        .enumerate()
        .find(|(i, s)| s.name.eq_ignore_ascii_case(new_name) && Some(*i) != symbol);
    if let Some((_, other)) = other_symbol {
        return Err(format!(
            "'{new_name}' is already the name of a global symbol in {}",
            other.name_loc.file.path(db)
        ));
    }
    Ok(())
}

/// A graph or chart variable must not take the name of a global symbol that the same graph or
/// chart uses unquoted: that use would then name the variable.
fn symbol_not_captured(
    db: &dyn salsa::Database,
    ws: Workspace,
    owner: ItemId,
    owner_name: &str,
    new_name: &str,
) -> Result<(), String> {
    let index = db::global_index(db, ws);
    let uses = defs::item_uses(db, ws, defs::item_loc(db, owner));
    let captured = uses.uses.iter().any(|u| {
        !u.quoted
            && matches!(&u.target, UseTarget::Symbol(p)
                if index.symbols.get(*p).is_some_and(|s| s.name.eq_ignore_ascii_case(new_name)))
    });
    if captured {
        return Err(format!(
            "{owner_name} uses the global symbol '{new_name}' by name; a variable of that name would hide it"
        ));
    }
    Ok(())
}

/// `graph G`, `group G`, `chart C`, `block FC 10`.
fn owner_description(db: &dyn salsa::Database, item: ItemId) -> String {
    let summary = db::file_summary(db, item.file)
        .items
        .get(item.index as usize);
    let name = summary.and_then(|s| s.name.clone()).unwrap_or_default();
    match summary.map(|s| s.kind) {
        Some(ItemKind::Graph) => format!("graph {name}"),
        Some(ItemKind::Group) => format!("group {name}"),
        Some(ItemKind::Chart) => format!("chart {name}"),
        _ => "the block interface".to_owned(),
    }
}

// ------------------------------------------------------------------------------ quoting

/// Decides, per plain use of a renamed symbol, whether the new name can stay unquoted there.
/// Remembers the variables of each graph and chart it looked at.
#[derive(Default)]
struct Quoting {
    /// Per item: does it have a variable (or an active predefined variable) of the new name?
    captured: HashMap<ItemId, bool>,
}

impl Quoting {
    fn plain_ok(
        &mut self,
        db: &dyn salsa::Database,
        ws: Workspace,
        reference: &Reference,
        new_name: &str,
    ) -> bool {
        let mnemonic = db::file_mnemonic(db, ws, reference.file);
        if !is_identifier(new_name)
            || lang::reserved_kind(new_name, mnemonic).is_some()
            || reads_as_address(new_name, mnemonic).is_some()
        {
            return false;
        }
        let Some(item) = item_at(db, reference.file, reference.range) else {
            return true;
        };
        if defs::item_kind(db, item) == Some(ItemKind::Test) {
            // A path's first name is read as a chart, group or instance before a block
            // (`Sym.calls`); quoted it stays the symbol.
            return !names_chart_group_or_instance(db, ws, new_name);
        }
        let captured = *self
            .captured
            .entry(item)
            .or_insert_with(|| has_variable(db, item, new_name));
        !captured
    }
}

/// Does `name` name a group or chart item, or an instance of a group?
fn names_chart_group_or_instance(db: &dyn salsa::Database, ws: Workspace, name: &str) -> bool {
    let index = db::global_index(db, ws);
    if index
        .item(name)
        .is_some_and(|i| matches!(i.kind, ItemKind::Group | ItemKind::Chart))
    {
        return true;
    }
    defs::items_of_kind(db, ws, &[ItemKind::Group])
        .into_iter()
        .filter_map(|g| db::item_root(db, defs::item_loc(db, g)).and_then(ast::Group::cast))
        .any(|g| {
            g.instances()
                .filter_map(|i| i.name())
                .any(|n| n.text().eq_ignore_ascii_case(name))
        })
}

/// The item of `file` that holds `range`.
fn item_at(db: &dyn salsa::Database, file: File, range: TextRange) -> Option<ItemId> {
    let offsets = db::item_offsets(db, file);
    let index = offsets.partition_point(|start| *start <= range.start());
    let index = u32::try_from(index.checked_sub(1)?).ok()?;
    Some(ItemId { file, index })
}

/// Does the graph or chart at `item` have a variable `name` (for a graph also an active
/// predefined variable), so that a plain `name` there would not name a symbol?
fn has_variable(db: &dyn salsa::Database, item: ItemId, name: &str) -> bool {
    let Some(root) = db::item_root(db, defs::item_loc(db, item)) else {
        return false;
    };
    match ast::Item::cast(root) {
        Some(ast::Item::Graph(graph)) => GraphScope::new(&graph).has_graph_variable(name),
        Some(ast::Item::Chart(_)) => defs::var_decl(db, item, name).is_some(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use crate::{
        AnalysisHost, FileContents, WorkspaceData,
        ide::{SourceChange, fixture},
    };

    /// Applies a change to the fixture's texts.
    fn apply(files: &[(String, String)], change: &SourceChange) -> Vec<(String, String)> {
        files
            .iter()
            .map(|(path, text)| {
                let mut text = text.clone();
                if let Some((_, edits)) = change.files.iter().find(|(p, _)| p == path) {
                    for edit in edits.iter().rev() {
                        let range = std::ops::Range::<usize>::from(edit.range);
                        text.replace_range(range, &edit.new_text);
                    }
                }
                (path.clone(), text)
            })
            .collect()
    }

    /// Renames at the cursor and renders the changed files in full.
    fn check(fixture_text: &str, new_name: &str) -> String {
        let f = fixture::load(fixture_text);
        let analysis = f.host.analysis();
        let change = match analysis.rename(&f.position, new_name) {
            Ok(Ok(change)) => change,
            Ok(Err(message)) => return format!("refused: {message}"),
            Err(_) => return "cancelled".to_owned(),
        };
        let changed: Vec<&String> = change.files.iter().map(|(p, _)| p).collect();
        apply(&f.files, &change)
            .into_iter()
            .filter(|(p, _)| changed.contains(&p))
            .map(|(p, t)| format!("//- {p}\n{t}"))
            .collect::<Vec<_>>()
            .join("")
    }

    /// The error of a refused rename (panics in tests if it was not refused).
    fn refused(fixture_text: &str, new_name: &str) -> String {
        let out = check(fixture_text, new_name);
        match out.strip_prefix("refused: ") {
            Some(message) => message.to_owned(),
            None => panic!("rename to '{new_name}' was not refused:\n{out}"),
        }
    }

    /// The codes of all diagnostics of a workspace, per file, in order.
    fn codes(files: &[(String, String)]) -> Vec<(String, Vec<String>)> {
        let mut data = WorkspaceData::default();
        for (path, text) in files {
            data.files
                .push((path.clone(), FileContents::Text(text.clone())));
        }
        let mut host = AnalysisHost::new();
        host.load(data);
        let analysis = host.analysis();
        let paths: Vec<String> = analysis.files().into_iter().map(|f| f.path).collect();
        analysis
            .diagnostics()
            .into_iter()
            .map(|(id, diags)| {
                let path = paths.get(id.0 as usize).cloned().unwrap_or_default();
                (path, diags.iter().map(|d| d.code.to_string()).collect())
            })
            .collect()
    }

    const PLANT: &str = r#"//- graphs/ventil.higraph
graph Ventil "valve" <
  in < Oben : BOOL; Zeit : TIME; >
  out < Auf : BOOL; >
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  state 0 "Init" < C: U Start; = Auf; >
  state 1 "Oben" < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
  state 2 "Ab" < C: U #IM_Ab; = Auf; >
  trans any->0 prio 1 < U INIT_SD; >
  trans 0->1 prio 1 < U Oben; >
  trans 1->2 prio 1 < U IM_Ab; !: R IM_Ab; >
  trans 2->1 prio 1 < U "Start"; >
>
//- group.higraph
group Anlage fc FC 1 db DB 1 <
  instance V1 : Ventil < Oben := Start; Zeit := T#5S; Auf := A 1.0; OM_Oben := V2.IM_Ab; >
  instance V2 : Ventil < Oben := "Start"; Zeit := T#5S; Auf := A 1.1; OM_Oben := V1.IM_Ab; >
>
//- symbols.higraph
symbols <
  Start : E 0.0 BOOL "start button";
>
"#;

    fn cursor(fixture_text: &str, path: &str, needle: &str) -> String {
        let marker = format!("//- {path}\n");
        let start = fixture_text.find(&marker).map_or(0, |i| i + marker.len());
        let at = fixture_text[start..]
            .find(needle)
            .map_or(start, |i| start + i);
        format!("{}$0{}", &fixture_text[..at], &fixture_text[at..])
    }

    #[test]
    fn graph_variable_reaches_instructions_actuals_and_message_targets() {
        let text = cursor(PLANT, "graphs/ventil.higraph", "IM_Ab : BOOL");
        insta::assert_snapshot!(check(&text, "IM_Unten"), @r#"
        //- graphs/ventil.higraph
        graph Ventil "valve" <
          in < Oben : BOOL; Zeit : TIME; >
          out < Auf : BOOL; >
          in_out < IM_Unten : BOOL msg in; OM_Oben : BOOL msg out; >
          state 0 "Init" < C: U Start; = Auf; >
          state 1 "Oben" < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
          state 2 "Ab" < C: U #IM_Unten; = Auf; >
          trans any->0 prio 1 < U INIT_SD; >
          trans 0->1 prio 1 < U Oben; >
          trans 1->2 prio 1 < U IM_Unten; !: R IM_Unten; >
          trans 2->1 prio 1 < U "Start"; >
        >
        //- group.higraph
        group Anlage fc FC 1 db DB 1 <
          instance V1 : Ventil < Oben := Start; Zeit := T#5S; Auf := A 1.0; OM_Oben := V2.IM_Unten; >
          instance V2 : Ventil < Oben := "Start"; Zeit := T#5S; Auf := A 1.1; OM_Oben := V1.IM_Unten; >
        >
        "#);
    }

    #[test]
    fn renaming_from_a_group_reaches_the_graph_file() {
        // The cursor is on a formal in the group; the graph's file is edited too.
        let text = cursor(PLANT, "group.higraph", "Oben := Start");
        insta::assert_snapshot!(check(&text, "Oben_Pos"), @r#"
        //- graphs/ventil.higraph
        graph Ventil "valve" <
          in < Oben_Pos : BOOL; Zeit : TIME; >
          out < Auf : BOOL; >
          in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
          state 0 "Init" < C: U Start; = Auf; >
          state 1 "Oben" < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
          state 2 "Ab" < C: U #IM_Ab; = Auf; >
          trans any->0 prio 1 < U INIT_SD; >
          trans 0->1 prio 1 < U Oben_Pos; >
          trans 1->2 prio 1 < U IM_Ab; !: R IM_Ab; >
          trans 2->1 prio 1 < U "Start"; >
        >
        //- group.higraph
        group Anlage fc FC 1 db DB 1 <
          instance V1 : Ventil < Oben_Pos := Start; Zeit := T#5S; Auf := A 1.0; OM_Oben := V2.IM_Ab; >
          instance V2 : Ventil < Oben_Pos := "Start"; Zeit := T#5S; Auf := A 1.1; OM_Oben := V1.IM_Ab; >
        >
        "#);
    }

    const TESTED: &str = r#"//- plant.higraph
graph Ventil <
  in < Oben : BOOL; >
  out < Auf : BOOL; >
  state 0 < C: U Oben; = Auf; >
  trans any->0 < U INIT_SD; >
>
group Anlage fc FC 1 db DB 1 <
  instance V1 : Ventil < Oben := Start; >
>
chart Mischer <
  in < Freigabe : BOOL; >
  sequencer RUN <
    start < Freigabe; >
    step Heizen < >
    trans T1 < Freigabe; >
  >
>
symbols < Start : E 0.0 BOOL; "Motor 1" : A 1.0 BOOL; >
//- tests.higraph
test T1 <
  run Anlage, Mischer;
  set Start := TRUE;
  set V1.Oben := TRUE;
  set Mischer.Freigabe := TRUE;
  step;
  expect Anlage.V1.Auf and V1.state = 0;
  expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
  command Mischer start;
  confirm Mischer.Heizen;
>
"#;

    /// Renames at the cursor; renders the changed files' names and the test file, and checks
    /// that the diagnostics stay the same.
    fn check_tests(fixture_text: &str, new_name: &str) -> String {
        let f = fixture::load(fixture_text);
        let analysis = f.host.analysis();
        let change = match analysis.rename(&f.position, new_name) {
            Ok(Ok(change)) => change,
            Ok(Err(message)) => return format!("refused: {message}"),
            Err(_) => return "cancelled".to_owned(),
        };
        let after = apply(&f.files, &change);
        assert_eq!(codes(&f.files), codes(&after), "renaming to {new_name}");
        let changed: Vec<String> = change.files.iter().map(|(p, _)| p.clone()).collect();
        let tests = after
            .iter()
            .find(|(p, _)| p == "tests.higraph")
            .map(|(_, t)| t.clone())
            .unwrap_or_default();
        format!("changed: {}\n{tests}", changed.join(", "))
    }

    #[test]
    fn renames_reach_into_test_paths() {
        let group = cursor(TESTED, "tests.higraph", "Anlage,");
        insta::assert_snapshot!(check_tests(&group, "Werk"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Werk, Mischer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Werk.V1.Auf and V1.state = 0;
          expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
        let chart = cursor(TESTED, "plant.higraph", "Mischer <");
        insta::assert_snapshot!(check_tests(&chart, "Ruehrer"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Ruehrer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Ruehrer.Freigabe := TRUE;
          step;
          expect Anlage.V1.Auf and V1.state = 0;
          expect Ruehrer.RUN.Heizen.T > T#0S and "Motor 1";
          command Ruehrer start;
          confirm Ruehrer.Heizen;
        >
        "#);
        let instance = cursor(TESTED, "tests.higraph", "V1.state");
        insta::assert_snapshot!(check_tests(&instance, "Ventil_1"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Start := TRUE;
          set Ventil_1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Anlage.Ventil_1.Auf and Ventil_1.state = 0;
          expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
        let variable = cursor(TESTED, "tests.higraph", "Auf and");
        insta::assert_snapshot!(check_tests(&variable, "Offen"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Anlage.V1.Offen and V1.state = 0;
          expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
        let step = cursor(TESTED, "plant.higraph", "Heizen <");
        insta::assert_snapshot!(check_tests(&step, "Waermen"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Anlage.V1.Auf and V1.state = 0;
          expect Mischer.RUN.Waermen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Waermen;
        >
        "#);
        let chart_var = cursor(TESTED, "tests.higraph", "Freigabe :=");
        insta::assert_snapshot!(check_tests(&chart_var, "Erlaubt"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Erlaubt := TRUE;
          step;
          expect Anlage.V1.Auf and V1.state = 0;
          expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
        let symbol = cursor(TESTED, "tests.higraph", "Start :=");
        insta::assert_snapshot!(check_tests(&symbol, "Los"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Los := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Anlage.V1.Auf and V1.state = 0;
          expect Mischer.RUN.Heizen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
        let quoted = cursor(TESTED, "plant.higraph", "Motor 1");
        insta::assert_snapshot!(check_tests(&quoted, "Motor 2"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Anlage.V1.Auf and V1.state = 0;
          expect Mischer.RUN.Heizen.T > T#0S and "Motor 2";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
        let sequencer = cursor(TESTED, "tests.higraph", "RUN.");
        insta::assert_snapshot!(check_tests(&sequencer, "Ablauf"), @r#"
        changed: plant.higraph, tests.higraph
        test T1 <
          run Anlage, Mischer;
          set Start := TRUE;
          set V1.Oben := TRUE;
          set Mischer.Freigabe := TRUE;
          step;
          expect Anlage.V1.Auf and V1.state = 0;
          expect Mischer.Ablauf.Heizen.T > T#0S and "Motor 1";
          command Mischer start;
          confirm Mischer.Heizen;
        >
        "#);
    }

    #[test]
    fn renames_that_would_change_test_paths_are_refused() {
        let instance = cursor(TESTED, "tests.higraph", "V1.state");
        insta::assert_snapshot!(refused(&instance, "Mischer"), @"test paths use this name, and a path starting with 'Mischer' names that item");
        let chart_var = cursor(TESTED, "tests.higraph", "Freigabe :=");
        insta::assert_snapshot!(refused(&chart_var, "Heizen"), @"test paths use this name, and 'Chart.Heizen' names a step or the chart's state");
        let step = cursor(TESTED, "plant.higraph", "Heizen <");
        insta::assert_snapshot!(refused(&step, "Freigabe"), @"test paths use this name, and 'Freigabe' is a variable, sequencer, step or the state of the chart");
        insta::assert_snapshot!(refused(&step, "RUN"), @"test paths use this name, and 'RUN' is a variable, sequencer, step or the state of the chart");
        let variable = cursor(TESTED, "tests.higraph", "Auf and");
        insta::assert_snapshot!(refused(&variable, "previous"), @"test paths use this name, and 'Inst.previous' is the instance's state");
        let chart = cursor(TESTED, "plant.higraph", "Mischer <");
        insta::assert_snapshot!(refused(&chart, "V1"), @"test paths use this name, and an instance is named 'V1': its paths would name this item");
    }

    #[test]
    fn symbols_in_test_paths_are_quoted_where_a_run_name_would_capture_them() {
        let text = r#"//- plant.higraph
graph Ventil < state 0 < > trans any->0 < U INIT_SD; > >
group Anlage < instance V1 : Ventil < > >
symbols < Dosieren : FC 10; >
//- tests.higraph
test T <
  run Anlage;
  expect $0Dosieren.calls = 0;
>
"#;
        insta::assert_snapshot!(check_tests(text, "V1"), @r#"
        changed: plant.higraph, tests.higraph
        test T <
          run Anlage;
          expect "V1".calls = 0;
        >
        "#);
        insta::assert_snapshot!(check_tests(text, "Zuteilen"), @"
        changed: plant.higraph, tests.higraph
        test T <
          run Anlage;
          expect Zuteilen.calls = 0;
        >
        ");
    }

    #[test]
    fn instance_updates_message_prefixes() {
        let text = cursor(PLANT, "group.higraph", "V2 : Ventil");
        insta::assert_snapshot!(check(&text, "Ventil_2"), @r#"
        //- group.higraph
        group Anlage fc FC 1 db DB 1 <
          instance V1 : Ventil < Oben := Start; Zeit := T#5S; Auf := A 1.0; OM_Oben := Ventil_2.IM_Ab; >
          instance Ventil_2 : Ventil < Oben := "Start"; Zeit := T#5S; Auf := A 1.1; OM_Oben := V1.IM_Ab; >
        >
        "#);
    }

    #[test]
    fn graph_updates_instance_headers() {
        let text = cursor(PLANT, "group.higraph", "Ventil < Oben := Start");
        insta::assert_snapshot!(check(&text, "Ventil_2E"), @r#"
        //- graphs/ventil.higraph
        graph Ventil_2E "valve" <
          in < Oben : BOOL; Zeit : TIME; >
          out < Auf : BOOL; >
          in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
          state 0 "Init" < C: U Start; = Auf; >
          state 1 "Oben" < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
          state 2 "Ab" < C: U #IM_Ab; = Auf; >
          trans any->0 prio 1 < U INIT_SD; >
          trans 0->1 prio 1 < U Oben; >
          trans 1->2 prio 1 < U IM_Ab; !: R IM_Ab; >
          trans 2->1 prio 1 < U "Start"; >
        >
        //- group.higraph
        group Anlage fc FC 1 db DB 1 <
          instance V1 : Ventil_2E < Oben := Start; Zeit := T#5S; Auf := A 1.0; OM_Oben := V2.IM_Ab; >
          instance V2 : Ventil_2E < Oben := "Start"; Zeit := T#5S; Auf := A 1.1; OM_Oben := V1.IM_Ab; >
        >
        "#);
    }

    #[test]
    fn symbol_keeps_its_quoting() {
        let text = cursor(PLANT, "symbols.higraph", "Start :");
        insta::assert_snapshot!(check(&text, "Starttaster"), @r#"
        //- graphs/ventil.higraph
        graph Ventil "valve" <
          in < Oben : BOOL; Zeit : TIME; >
          out < Auf : BOOL; >
          in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
          state 0 "Init" < C: U Starttaster; = Auf; >
          state 1 "Oben" < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
          state 2 "Ab" < C: U #IM_Ab; = Auf; >
          trans any->0 prio 1 < U INIT_SD; >
          trans 0->1 prio 1 < U Oben; >
          trans 1->2 prio 1 < U IM_Ab; !: R IM_Ab; >
          trans 2->1 prio 1 < U "Starttaster"; >
        >
        //- group.higraph
        group Anlage fc FC 1 db DB 1 <
          instance V1 : Ventil < Oben := Starttaster; Zeit := T#5S; Auf := A 1.0; OM_Oben := V2.IM_Ab; >
          instance V2 : Ventil < Oben := "Starttaster"; Zeit := T#5S; Auf := A 1.1; OM_Oben := V1.IM_Ab; >
        >
        //- symbols.higraph
        symbols <
          Starttaster : E 0.0 BOOL "start button";
        >
        "#);
    }

    #[test]
    fn symbol_uses_are_quoted_where_a_variable_would_capture_them() {
        let text = r#"//- g.higraph
graph G <
  in < Taster : BOOL; >
  state 0 < C: U $0Start; U Taster; >
  trans any->0 < U INIT_SD; >
>
symbols < Start : E 0.0 BOOL; >
"#;
        insta::assert_snapshot!(check(text, "Taster"), @r#"
        //- g.higraph
        graph G <
          in < Taster : BOOL; >
          state 0 < C: U "Taster"; U Taster; >
          trans any->0 < U INIT_SD; >
        >
        symbols < Taster : E 0.0 BOOL; >
        "#);
    }

    #[test]
    fn quoted_symbol_may_take_any_text() {
        let text = r#"//- g.higraph
graph G <
  state 0 < C: U $0"Motor ein"; = A 1.0; >
  trans any->0 < U INIT_SD; >
>
symbols < "Motor ein" : E 0.0 BOOL; >
"#;
        insta::assert_snapshot!(check(text, "Motor aus"), @r#"
        //- g.higraph
        graph G <
          state 0 < C: U "Motor aus"; = A 1.0; >
          trans any->0 < U INIT_SD; >
        >
        symbols < "Motor aus" : E 0.0 BOOL; >
        "#);
    }

    #[test]
    fn state_renumbering_updates_endpoints() {
        let text = cursor(PLANT, "graphs/ventil.higraph", "1 \"Oben\"");
        insta::assert_snapshot!(check(&text, "7"), @r#"
        //- graphs/ventil.higraph
        graph Ventil "valve" <
          in < Oben : BOOL; Zeit : TIME; >
          out < Auf : BOOL; >
          in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
          state 0 "Init" < C: U Start; = Auf; >
          state 7 "Oben" < E: S OM_Oben; X: R OM_Oben; C: = Auf; supervise Zeit; >
          state 2 "Ab" < C: U #IM_Ab; = Auf; >
          trans any->0 prio 1 < U INIT_SD; >
          trans 0->7 prio 1 < U Oben; >
          trans 7->2 prio 1 < U IM_Ab; !: R IM_Ab; >
          trans 2->7 prio 1 < U "Start"; >
        >
        "#);
    }

    #[test]
    fn chart_step_updates_jump_and_loop_targets() {
        let text = r#"
chart Mischer <
  in < Voll : BOOL; Leer : BOOL; >
  sequencer RUN <
    start < Voll; >
    step $0START < >
    trans T1 < Voll; >
    step FUELLEN < >
    jump J1 -> START < Leer; >
    trans T2 < Leer; >
    step ENDE < >
    loop L1 -> start < Voll; >
  >
>
"#;
        insta::assert_snapshot!(check(text, "ANFANG"), @"
        //- main.higraph

        chart Mischer <
          in < Voll : BOOL; Leer : BOOL; >
          sequencer RUN <
            start < Voll; >
            step ANFANG < >
            trans T1 < Voll; >
            step FUELLEN < >
            jump J1 -> ANFANG < Leer; >
            trans T2 < Leer; >
            step ENDE < >
            loop L1 -> ANFANG < Voll; >
          >
        >
        ");
    }

    #[test]
    fn chart_variable_updates_conditions_and_statements() {
        let text = r#"
chart Mischer <
  in < $0Voll : BOOL; Pumpe : BOOL; >
  sequencer RUN <
    start < Voll; >
    step A < init < Pumpe := Voll; > N Pumpe; >
    trans T1 < not Voll; >
    step B < >
  >
>
"#;
        insta::assert_snapshot!(check(text, "Behaelter_Voll"), @"
        //- main.higraph

        chart Mischer <
          in < Behaelter_Voll : BOOL; Pumpe : BOOL; >
          sequencer RUN <
            start < Behaelter_Voll; >
            step A < init < Pumpe := Behaelter_Voll; > N Pumpe; >
            trans T1 < not Behaelter_Voll; >
            step B < >
          >
        >
        ");
    }

    #[test]
    fn prepare_rename_gives_the_range_and_the_declared_name() {
        let text = cursor(PLANT, "graphs/ventil.higraph", "IM_Ab; !:");
        let f = crate::ide::fixture::load(&text);
        let result = f.host.analysis().prepare_rename(&f.position);
        let Ok(Ok((range, name))) = result else {
            panic!("not renamable: {result:?}");
        };
        assert_eq!(f.slice(&range.path, range.range), "IM_Ab");
        assert_eq!(name, "IM_Ab");
        let keyword = cursor(PLANT, "graphs/ventil.higraph", "state 1");
        let f = crate::ide::fixture::load(&keyword);
        assert_eq!(
            f.host.analysis().prepare_rename(&f.position).ok(),
            Some(Err(
                "'state' is a keyword of the language and cannot be renamed".to_owned()
            ))
        );
    }

    #[test]
    fn what_cannot_be_renamed() {
        let at = |path: &str, needle: &str| refused(&cursor(PLANT, path, needle), "Neu");
        insta::assert_snapshot!(
            [
                at("graphs/ventil.higraph", "INIT_SD"),
                at("graphs/ventil.higraph", "trans 0->1"),
                at("graphs/ventil.higraph", "U Oben"),
                at("group.higraph", "A 1.0"),
                at("group.higraph", "T#5S; Auf"),
                at("graphs/ventil.higraph", "E: S"),
                at("graphs/ventil.higraph", "BOOL; Zeit"),
                at("graphs/ventil.higraph", "\"valve\""),
            ]
            .join("\n"),
            @"
        'INIT_SD' is a predefined variable of every graph and cannot be renamed
        'trans' is a keyword of the language and cannot be renamed
        'U' is an STL operation; operations cannot be renamed
        'A 1.0' is an absolute address; addresses cannot be renamed
        'T#5S' is a constant; constants cannot be renamed
        'E:' is a block label
        'BOOL' is a data type
        there is nothing to rename at the cursor
        "
        );
        let other = r#"
graph G <
  in < X : BOOL; >
  state 0 < C: L MW10; U Nix; CALL FC 10 (Menge := MW 2);  U X; >
  trans any->0 < U INIT_SD; >
>
block FC 10 < in < Menge : INT; > >
"#;
        let at = |needle: &str| refused(&other.replacen(needle, &format!("$0{needle}"), 1), "Neu");
        insta::assert_snapshot!(
            [at("MW10"), at("Nix"), at("FC 10 ("), at(" U X")].join("\n"),
            @"
        'MW10' is an absolute address; addresses cannot be renamed
        'Nix' does not refer to a declaration of the workspace
        a block interface is named by its block; rename the block's symbol instead
        there is no name at the cursor
        "
        );
    }

    #[test]
    fn invalid_new_names_are_refused() {
        let var = cursor(PLANT, "graphs/ventil.higraph", "Oben : BOOL");
        insta::assert_snapshot!(
            [
                refused(&var, ""),
                refused(&var, "1Oben"),
                refused(&var, "Oben unten"),
                refused(&var, "Öffnen"),
                refused(&var, "Oben_"),
                refused(&var, "Oben__Pos"),
                refused(&var, "BOOL"),
                refused(&var, "UN"),
                refused(&var, "MW10"),
                refused(&var, "Ab"),
                refused(&cursor(PLANT, "graphs/ventil.higraph", "1 \"Oben\""), "70000"),
                refused(&cursor(PLANT, "graphs/ventil.higraph", "1 \"Oben\""), "x1"),
            ]
            .join("\n"),
            @"
        the new name is empty
        '1Oben' is not a valid name: use ASCII letters, digits and '_', not starting with a digit
        'Oben unten' is not a valid name: use ASCII letters, digits and '_', not starting with a digit
        'Öffnen' is not a valid name: use ASCII letters, digits and '_', not starting with a digit
        name 'Oben_' must not end with '_' (HG1101)
        name 'Oben__Pos' must not contain '__' (HG1102)
        'BOOL' is reserved (a data type) and cannot be used as a name (HG1103)
        'UN' is reserved (a SIMATIC STL operation) and cannot be used as a name (HG1103)
        'MW10' reads as the address MW 10 in an operand; choose another name
        'Ab' reads as the address area AB (output byte) in an operand; choose another name
        '70000' is not a state number: states are numbered 0 to 65535
        'x1' is not a state number: states are numbered 0 to 65535
        "
        );
    }

    #[test]
    fn colliding_new_names_are_refused() {
        let var = cursor(PLANT, "graphs/ventil.higraph", "Oben : BOOL");
        let graph = cursor(PLANT, "graphs/ventil.higraph", "Ventil \"valve\"");
        let symbol = cursor(PLANT, "symbols.higraph", "Start :");
        let instance = cursor(PLANT, "group.higraph", "V2 : Ventil");
        let state = cursor(PLANT, "graphs/ventil.higraph", "1 \"Oben\"");
        insta::assert_snapshot!(
            [
                refused(&var, "auf"),
                refused(&var, "CurrentState"),
                refused(&var, "Start"),
                refused(&graph, "Anlage"),
                refused(&graph, "Start"),
                refused(&symbol, "Ventil"),
                refused(&instance, "v1"),
                refused(&state, "2"),
            ]
            .join("\n"),
            @"
        graph Ventil already has a variable 'auf'
        'CurrentState' is a predefined variable of every graph
        graph Ventil uses the global symbol 'Start' by name; a variable of that name would hide it
        'Anlage' is already the name of group Anlage in group.higraph
        'Start' is already the name of a global symbol in symbols.higraph
        'Ventil' is already the name of graph Ventil in graphs/ventil.higraph
        group Anlage already has an instance 'v1'
        graph Ventil already has a state 2
        "
        );
        let steps = r#"
chart C <
  sequencer S <
    step $0A < >
    trans T < TRUE; >
    step B < >
  >
>
"#;
        insta::assert_snapshot!(
            [refused(steps, "b"), refused(steps, "Ein_sehr_langer_Name")].join("\n"),
            @"
        sequencer S already has a step 'b'
        name 'Ein_sehr_langer_Name' has 20 characters; at most 16 are allowed (HG7101)
        "
        );
    }

    #[test]
    fn chart_and_interface_variables_collide_in_their_own_namespace() {
        let chart = r#"
chart C <
  in < $0Voll : BOOL; Leer : BOOL; >
  sequencer S < start < Voll and Leer and Taster; > step A < > >
>
symbols < Taster : E 0.0 BOOL; >
"#;
        let interface = r#"
block FC 10 < in < $0Menge : INT; Start : BOOL; > >
graph G < state 0 < C: CALL FC 10 (Menge := MW 2, Start := M 0.0); > trans any->0 < U INIT_SD; > >
"#;
        insta::assert_snapshot!(
            [refused(chart, "LEER"), refused(chart, "Taster"), refused(interface, "start")]
                .join("\n"),
            @"
        chart C already has a variable 'LEER'
        chart C uses the global symbol 'Taster' by name; a variable of that name would hide it
        the block interface already has a variable 'start'
        "
        );
        insta::assert_snapshot!(check(interface, "Anzahl"), @"
        //- main.higraph

        block FC 10 < in < Anzahl : INT; Start : BOOL; > >
        graph G < state 0 < C: CALL FC 10 (Anzahl := MW 2, Start := M 0.0); > trans any->0 < U INIT_SD; > >
        ");
    }

    #[test]
    fn later_duplicate_declarations_are_refused() {
        let text = r#"
graph G <
  in < X : BOOL; >
  stat < $0x : BOOL; >
  state 0 < C: U X; >
  trans any->0 < U INIT_SD; >
>
"#;
        insta::assert_snapshot!(refused(text, "Y"), @"'X' is declared again here; only its first declaration counts: rename that one, or remove this one");
        let first = text.replace("$0x", "x").replacen("< X", "< $0X", 1);
        assert!(!check(&first, "Y").starts_with("refused"));
    }

    #[test]
    fn rename_sees_edits_of_files_that_are_not_open() {
        // The host's database is the only source: an edit of the graph file (as a file
        // watcher would report it) is renamed too, without any editor state.
        let text = cursor(PLANT, "group.higraph", "Oben := Start");
        let mut f = fixture::load(&text);
        let graph = f.text("graphs/ventil.higraph").replace(
            "state 2 \"Ab\" < C: U #IM_Ab;",
            "state 2 \"Ab\" < C: U #IM_Ab; U #Oben;",
        );
        f.host
            .set_file_contents("graphs/ventil.higraph", FileContents::Text(graph));
        let change = f.host.analysis().rename(&f.position, "Oben_Pos");
        let Ok(Ok(change)) = change else {
            panic!("rename failed: {change:?}");
        };
        let edits: Vec<(String, usize)> = change
            .files
            .iter()
            .map(|(path, edits)| (path.clone(), edits.len()))
            .collect();
        assert_eq!(
            edits,
            vec![
                ("graphs/ventil.higraph".to_owned(), 3),
                ("group.higraph".to_owned(), 2)
            ]
        );
    }

    #[test]
    fn rename_preserves_the_diagnostics() {
        let cases = [
            (
                cursor(PLANT, "graphs/ventil.higraph", "IM_Ab : BOOL"),
                "IM_Unten",
            ),
            (
                cursor(PLANT, "graphs/ventil.higraph", "Oben : BOOL"),
                "Oben_Pos",
            ),
            (cursor(PLANT, "group.higraph", "V2 : Ventil"), "Ventil_2"),
            (
                cursor(PLANT, "group.higraph", "Ventil < Oben := Start"),
                "Ventil_2E",
            ),
            (cursor(PLANT, "symbols.higraph", "Start :"), "Starttaster"),
            (cursor(PLANT, "symbols.higraph", "Start :"), "Auf"),
            // Renumbering keeps the gap of the numbering (HG2105 stays).
            (
                "graph G < state 0 < > state $05 < > trans any->0 < U INIT_SD; > trans 0->5 < > >"
                    .to_owned(),
                "7",
            ),
        ];
        for (text, new_name) in cases {
            let f = fixture::load(&text);
            let before = codes(&f.files);
            let change = f.host.analysis().rename(&f.position, new_name);
            let Ok(Ok(change)) = change else {
                panic!("rename to {new_name} failed: {change:?}");
            };
            assert!(!change.files.is_empty());
            let after = codes(&apply(&f.files, &change));
            assert_eq!(before, after, "rename to {new_name}");
        }
    }

    #[test]
    fn max_group_message_variable_is_renamed_in_all_255_instances() {
        let target = higraph_workload::MAX_GROUP_RENAME;
        let files = higraph_workload::max_group(1);
        let mut data = WorkspaceData::default();
        for (path, text) in &files {
            data.files
                .push((path.clone(), FileContents::Text(text.clone())));
        }
        let mut host = AnalysisHost::new();
        host.load(data);
        let (_, text) = files
            .iter()
            .find(|(p, _)| p == target.file)
            .expect("the workload has the target file");
        let offset = text
            .find(&format!("{} :", target.variable))
            .expect("the variable is declared");
        let pos = crate::ide::FilePosition {
            path: target.file.to_owned(),
            offset: higraph_syntax::TextSize::from(offset as u32),
        };
        let change = host.analysis().rename(&pos, "IM_Fertig");
        let Ok(Ok(change)) = change else {
            panic!("rename failed: {change:?}");
        };
        let (_, group_edits) = change
            .files
            .iter()
            .find(|(p, _)| p == target.group_file)
            .expect("the group file is edited");
        // One edit per instance at least (the formal of each actual); the actuals are
        // re-aligned where the new name changes the width, each edit within a line.
        assert!(group_edits.len() >= 255, "{}", group_edits.len());
        assert!(
            change
                .files
                .iter()
                .all(|(_, edits)| edits.iter().all(|e| !e.new_text.contains('\n')))
        );
        let (_, text) = files
            .iter()
            .find(|(p, _)| p == target.group_file)
            .expect("the group file");
        let mut new = text.clone();
        for edit in group_edits.iter().rev() {
            new.replace_range(std::ops::Range::<usize>::from(edit.range), &edit.new_text);
        }
        assert_eq!(new.matches("IM_Fertig").count(), 255);
        if crate::format::format(text).is_ok_and(|f| f == *text) {
            assert_eq!(crate::format::format(&new).as_ref(), Ok(&new));
        }
    }

    /// The example workspaces of the repository, as `(path, text)`.
    fn example(name: &str) -> Vec<(String, String)> {
        let files: &[(&str, &str)] = match name {
            "drilling" => &[
                (
                    "bohrmaschine.higraph",
                    include_str!("../../../../examples/drilling/bohrmaschine.higraph"),
                ),
                (
                    "symbols.higraph",
                    include_str!("../../../../examples/drilling/symbols.higraph"),
                ),
                (
                    "graphs/bohren.higraph",
                    include_str!("../../../../examples/drilling/graphs/bohren.higraph"),
                ),
                (
                    "graphs/motor.higraph",
                    include_str!("../../../../examples/drilling/graphs/motor.higraph"),
                ),
                (
                    "graphs/spanner.higraph",
                    include_str!("../../../../examples/drilling/graphs/spanner.higraph"),
                ),
                (
                    "graphs/ventil_2e.higraph",
                    include_str!("../../../../examples/drilling/graphs/ventil_2e.higraph"),
                ),
            ],
            "mixer" => &[(
                "mixer.higraph",
                include_str!("../../../../examples/mixer/mixer.higraph"),
            )],
            _ => &[
                (
                    "ablauf.higraph",
                    include_str!("../../../../examples/mistakes/ablauf.higraph"),
                ),
                (
                    "anlage.higraph",
                    include_str!("../../../../examples/mistakes/anlage.higraph"),
                ),
                (
                    "steuerung.higraph",
                    include_str!("../../../../examples/mistakes/steuerung.higraph"),
                ),
                (
                    "symbols.higraph",
                    include_str!("../../../../examples/mistakes/symbols.higraph"),
                ),
                (
                    "ventil.higraph",
                    include_str!("../../../../examples/mistakes/ventil.higraph"),
                ),
            ],
        };
        files
            .iter()
            .map(|(p, t)| ((*p).to_owned(), (*t).to_owned()))
            .collect()
    }

    fn host_of(files: &[(String, String)]) -> AnalysisHost {
        let mut data = WorkspaceData::default();
        for (path, text) in files {
            data.files
                .push((path.clone(), FileContents::Text(text.clone())));
        }
        let mut host = AnalysisHost::new();
        host.load(data);
        host
    }

    /// The start, middle and end of every token of a text.
    fn token_offsets(text: &str) -> Vec<higraph_syntax::TextSize> {
        let mut offsets: Vec<higraph_syntax::TextSize> = higraph_syntax::parse(text)
            .syntax_node()
            .descendants_with_tokens()
            .filter_map(|e| e.into_token())
            .flat_map(|t| {
                let range = t.text_range();
                let middle = t
                    .text()
                    .char_indices()
                    .nth(t.text().chars().count() / 2)
                    .map_or(range.start(), |(i, _)| {
                        range.start() + higraph_syntax::TextSize::from(i as u32)
                    });
                [range.start(), middle, range.end()]
            })
            .collect();
        offsets.dedup();
        offsets
    }

    /// Every editor feature of this family at the start, middle and end of every token of the
    /// examples: no panic, and every rename offered has a range inside the file.
    #[test]
    fn every_position_of_the_examples_is_answered() {
        for name in ["drilling", "mixer", "mistakes"] {
            let files = example(name);
            let host = host_of(&files);
            let analysis = host.analysis();
            for (path, text) in &files {
                for offset in token_offsets(text) {
                    let pos = crate::ide::FilePosition {
                        path: path.clone(),
                        offset,
                    };
                    assert!(analysis.goto_definition(&pos).is_ok());
                    assert!(analysis.references(&pos, true).is_ok());
                    assert!(analysis.highlights(&pos).is_ok());
                    assert!(analysis.hover(&pos).is_ok());
                    if let Ok(Ok((range, _))) = analysis.prepare_rename(&pos) {
                        assert!(usize::from(range.range.end()) <= text.len());
                    }
                }
            }
        }
    }

    /// Renames every name of the clean examples that can be renamed (one position per
    /// distinct change) and checks that the diagnostics stay the same.
    #[test]
    fn renaming_any_name_of_the_examples_preserves_the_diagnostics() {
        for name in ["drilling", "mixer"] {
            let files = example(name);
            let before = codes(&files);
            let host = host_of(&files);
            let analysis = host.analysis();
            let mut seen: Vec<SourceChange> = Vec::new();
            for (path, text) in &files {
                for offset in token_offsets(text) {
                    let pos = crate::ide::FilePosition {
                        path: path.clone(),
                        offset,
                    };
                    let Ok(Ok((_, old))) = analysis.prepare_rename(&pos) else {
                        continue;
                    };
                    let new_name = if old.bytes().all(|b| b.is_ascii_digit()) {
                        "999"
                    } else {
                        "Neu_X"
                    };
                    let Ok(Ok(change)) = analysis.rename(&pos, new_name) else {
                        continue;
                    };
                    if seen.contains(&change) {
                        continue;
                    }
                    // Renumbering a state may open or close a gap in the numbering (HG2105,
                    // a hint about the renamed numbers themselves).
                    let without_gaps = |codes: Vec<(String, Vec<String>)>| {
                        codes
                            .into_iter()
                            .map(|(p, c)| (p, c.into_iter().filter(|c| c != "HG2105").collect()))
                            .collect::<Vec<(String, Vec<String>)>>()
                    };
                    let after = codes(&apply(&files, &change));
                    assert_eq!(
                        without_gaps(before.clone()),
                        without_gaps(after),
                        "{name}: renaming '{old}' at {path}:{offset:?}"
                    );
                    seen.push(change);
                }
            }
            assert!(seen.len() > 10, "{name}: only {} renames", seen.len());
        }
    }

    const IEC_CHART: &str = "chart Ampel <
  profile iec;
  stat < Uhr : TON; Teile : INT; >
  action Zaehlen < Teile := Teile + 1; >
  sequencer Haupt <
    step Rot < P1 Zaehlen; run < Uhr(IN := Rot.X, PT := T#5S); > >
    trans Weiter < Uhr.Q; >
    step Gruen < N zaehlen; >
  >
>
";

    #[test]
    fn renames_iec_instances_actions_and_steps_in_member_paths() {
        let instance = IEC_CHART.replacen("Uhr :", "$0Uhr :", 1);
        insta::assert_snapshot!(check(&instance, "Timer1"), @r#"
        //- main.higraph
        chart Ampel <
          profile iec;
          stat < Timer1 : TON; Teile : INT; >
          action Zaehlen < Teile := Teile + 1; >
          sequencer Haupt <
            step Rot < P1 Zaehlen; run < Timer1(IN := Rot.X, PT := T#5S); > >
            trans Weiter < Timer1.Q; >
            step Gruen < N zaehlen; >
          >
        >
        "#);
        let action = IEC_CHART.replacen("P1 Zaehlen", "P1 $0Zaehlen", 1);
        insta::assert_snapshot!(check(&action, "Zaehle"), @r#"
        //- main.higraph
        chart Ampel <
          profile iec;
          stat < Uhr : TON; Teile : INT; >
          action Zaehle < Teile := Teile + 1; >
          sequencer Haupt <
            step Rot < P1 Zaehle; run < Uhr(IN := Rot.X, PT := T#5S); > >
            trans Weiter < Uhr.Q; >
            step Gruen < N Zaehle; >
          >
        >
        "#);
        let step = IEC_CHART.replacen("step Rot", "step $0Rot", 1);
        let renamed = check(&step, "Stop");
        assert!(
            renamed.contains("step Stop <") && renamed.contains("IN := Stop.X"),
            "{renamed}"
        );
        assert_eq!(
            refused(&action, "Teile"),
            "chart Ampel already has an action or variable 'Teile'"
        );
        assert_eq!(
            refused(&instance, "Zaehlen"),
            "chart Ampel already has an action 'Zaehlen'"
        );
    }
}
