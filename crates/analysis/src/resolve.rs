//! Operand resolution inside a graph (`diagnostics.md` §2.4) and the address rules that go
//! with it.
//!
//! [`GraphScope`] holds what a graph declares (variables, `activate`) and records which of them
//! operands use (HG1210). [`resolve_operand`] resolves one STL operand, CALL actual or time
//! value and reports what resolution itself finds: HG1104 (letter case), HG1207 (inactive
//! predefined variable), HG1208 (V2.7 name), HG3005 / HG4101 (unresolved), HG4102 (address
//! area used as a name), HG4103 (a name read as an address) and the address rules
//! HG4009–HG4012. Mnemonic-set conflicts (HG4007) are returned, not reported, because HG4007 is
//! reported once per statement.
//!
//! [`read_address_node`] (HG4009–HG4011) is shared with the other rule modules: every place
//! where an address stands uses it. So are the diagnostics themselves: [`report_address_error`]
//! (HG4009–HG4011), [`local_data_warning`] (HG4012), [`case_hint`] (HG1104) and
//! [`time_operand_not_found`] (HG3005), also used by charts, groups and symbol tables.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use higraph_syntax::{
    SyntaxKind, TextRange, TextSize, ast,
    ast::AstNode,
    literal::{self, Literal},
};

use crate::{
    address::{self, Address, AddressError, Area},
    closest,
    index::{self, Symbol},
    lang::{self, Mnemonic, Predefined, Section, Type},
    rules::{
        Ctx,
        decls::{self, Var},
    },
};

// ------------------------------------------------------------------------------ scope

/// A name in the graph's `activate` list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ActivatedName {
    /// The name as written.
    pub text: String,
    pub range: TextRange,
    /// The range to delete to remove it from the list (with its comma).
    pub removal: TextRange,
    /// The whole `activate` statement, when this is its only name.
    pub sole_in: Option<TextRange>,
}

/// What a graph declares, and which declarations its operands use. The declarations are
/// shared (`Arc`): every member of a graph is checked with its own copy of the scope, and
/// only the uses are its own.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct GraphScope {
    /// The graph's name as declared.
    pub name: String,
    /// Declared variables in declaration order: the first declaration of each name (C3), with
    /// its type as written (not checked: a `STRING[n]` keeps any length).
    pub vars: Arc<Vec<Var>>,
    vars_by_key: Arc<HashMap<String, usize>>,
    /// Every name of every `activate`, in text order.
    pub activated: Arc<Vec<ActivatedName>>,
    activated_keys: Arc<HashSet<String>>,
    /// Where a new `in` declaration goes: before the `>` of the first `in` section, or (no
    /// `in` section) right after the graph's `<`.
    pub in_insert: Option<(TextSize, bool)>,
    /// Where a new `activate` goes: after the last variable section, else after the `<`.
    pub activate_insert: Option<TextSize>,
    /// Uses per declared variable (HG1210 a).
    pub used_vars: Vec<bool>,
    /// Predefined variables some operand resolves to (HG1210 b), by canonical name.
    pub used_predefined: HashSet<&'static str>,
}

impl GraphScope {
    /// Collects the declarations of `graph`.
    pub fn new(graph: &ast::Graph) -> GraphScope {
        let mut scope = GraphScope {
            name: graph.name().map(|n| n.text()).unwrap_or_default(),
            vars: Arc::default(),
            vars_by_key: Arc::default(),
            activated: Arc::default(),
            activated_keys: Arc::default(),
            in_insert: None,
            activate_insert: None,
            used_vars: Vec::new(),
            used_predefined: HashSet::new(),
        };
        let body = graph.body();
        let after_open = body
            .as_ref()
            .and_then(|b| b.l_angle())
            .map(|t| t.text_range().end());
        scope.activate_insert = after_open;
        // Sections and `activate`s do not depend on each other's order.
        for section in graph.var_sections() {
            scope.add_section(&section);
        }
        for activate in graph.activates() {
            scope.add_activate(&activate);
        }
        if scope.in_insert.is_none() {
            scope.in_insert = after_open.map(|at| (at, true));
        }
        scope.used_vars = vec![false; scope.vars.len()];
        scope
    }

    fn add_section(&mut self, section: &ast::VarSection) {
        let Some(kind) = decls::section_kind(section) else {
            return;
        };
        let close = section
            .syntax()
            .children_with_tokens()
            .filter_map(|e| e.into_token())
            .find(|t| t.kind() == SyntaxKind::R_ANGLE);
        if kind == Section::In
            && self.in_insert.is_none()
            && let Some(close) = &close
        {
            self.in_insert = Some((close.text_range().start(), false));
        }
        self.activate_insert = Some(section.syntax().text_range().end());
        for decl in section.decls() {
            let Some(name) = decl.name() else { continue };
            let Some(token) = name.token() else { continue };
            let text = name.text();
            let key = index::key(&text);
            if self.vars_by_key.contains_key(&key) {
                continue;
            }
            Arc::make_mut(&mut self.vars_by_key).insert(key, self.vars.len());
            Arc::make_mut(&mut self.vars).push(Var {
                name: text,
                name_range: token.text_range(),
                section: kind,
                ty: decl.ty().and_then(|t| index::declared_type(&t)),
                decl_range: decl.syntax().text_range(),
                duplicate: false,
                fb: None,
            });
        }
    }

    fn add_activate(&mut self, activate: &ast::Activate) {
        let names: Vec<ast::NameRef> = activate.names().collect();
        let sole = (names.len() == 1).then(|| activate.syntax().text_range());
        for (i, name) in names.iter().enumerate() {
            let Some(token) = name.token() else { continue };
            let range = token.text_range();
            // Remove "A, " (or ", A" for the last name) from the list.
            let removal = match (
                names.get(i + 1),
                i.checked_sub(1).and_then(|p| names.get(p)),
            ) {
                (Some(next), _) => {
                    TextRange::new(range.start(), next.syntax().text_range().start())
                }
                (None, Some(prev)) => TextRange::new(prev.syntax().text_range().end(), range.end()),
                (None, None) => range,
            };
            let text = token.text().to_owned();
            if lang::predefined(&text).is_some() {
                Arc::make_mut(&mut self.activated_keys).insert(index::key(&text));
            }
            Arc::make_mut(&mut self.activated).push(ActivatedName {
                text,
                range,
                removal,
                sole_in: sole,
            });
        }
    }

    /// The declared variable of that name (case-insensitive).
    pub fn var(&self, name: &str) -> Option<usize> {
        self.vars_by_key.get(&index::key(name)).copied()
    }

    /// Is the predefined variable active in this graph (by default or by `activate`)?
    pub fn is_active(&self, predefined: &Predefined) -> bool {
        predefined.active_by_default || self.activated_keys.contains(&index::key(predefined.name))
    }

    /// The active predefined variable of that name.
    pub fn active_predefined(&self, name: &str) -> Option<&'static Predefined> {
        lang::predefined(name).filter(|p| self.is_active(p))
    }

    /// Does `#name` (a variable of the graph) resolve?
    pub fn has_graph_variable(&self, name: &str) -> bool {
        self.var(name).is_some() || self.active_predefined(name).is_some()
    }

    /// `graph G`, for `{owner}`.
    pub fn owner(&self) -> String {
        format!("graph {}", self.name)
    }

    fn mark_var(&mut self, var: usize) {
        if let Some(used) = self.used_vars.get_mut(var) {
            *used = true;
        }
    }
}

// ------------------------------------------------------------------------------ results

/// What an operand denotes.
#[derive(Debug, Clone)]
pub(crate) enum Target<'a> {
    /// A declared variable of the graph (index into [`GraphScope::vars`]).
    Var(usize),
    /// An active predefined variable.
    Predefined(&'static Predefined),
    /// A global symbol.
    Symbol(&'a Symbol),
    /// An absolute address (possibly translated from the other mnemonic set).
    Address(Address),
    /// A valid constant.
    Constant(Literal),
}

/// An operand after resolution.
#[derive(Debug, Clone)]
pub(crate) struct Resolved<'a> {
    /// What it denotes; `None` when resolution failed (already reported) or the constant is
    /// invalid (HG0006/HG0007).
    pub target: Option<Target<'a>>,
    /// Its type; `None` when unknown (§2.4), which turns type rules off (C2).
    pub ty: Option<Type>,
    /// The operand's range.
    pub range: TextRange,
    /// The operand as written.
    pub text: String,
    /// Area tokens that belong only to the other mnemonic set (HG4007): range and the area as
    /// written.
    pub other_set: Option<(TextRange, String)>,
    /// The operand in the file's own mnemonic set (for HG4007's rewrite), if it differs.
    pub translated: Option<String>,
}

impl Resolved<'_> {
    fn new(range: TextRange, text: String) -> Self {
        Resolved {
            target: None,
            ty: None,
            range,
            text,
            other_set: None,
            translated: None,
        }
    }

    /// Binds it to an absolute address.
    fn bind_address(&mut self, addr: Address) {
        self.ty = Some(addr.ty());
        self.target = Some(Target::Address(addr));
    }

    /// Is it a constant (valid or not)?
    pub fn is_constant(&self) -> bool {
        matches!(self.target, Some(Target::Constant(_)))
    }

    /// The address it stands for: an absolute address, or a symbol's address.
    pub fn address(&self) -> Option<&Address> {
        match &self.target {
            Some(Target::Address(a)) => Some(a),
            Some(Target::Symbol(s)) => s.address.as_ref(),
            _ => None,
        }
    }
}

/// Where an operand stands; decides how a failed resolution is reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// An STL operand or CALL actual: HG4101.
    Operand,
    /// A `wait` / `supervise` value: HG3005.
    TimeValue,
}

/// How an operand is resolved.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Usage {
    pub role: Role,
    /// The type the operation implies, for HG4101's "declare it" fix (BOOL for bit logic,
    /// TIMER for timer starts, COUNTER for counting).
    pub implied: Option<Type>,
}

// ------------------------------------------------------------------------------ resolution

/// Resolves one operand of a graph (§2.4) and reports HG1104, HG1207, HG1208, HG3005, HG4009–
/// HG4012, HG4101, HG4102 and HG4103. Records uses of variables (HG1210) and global symbols
/// (HG6004). The caller has already ruled out `[...]` and status operands (HG4003/HG4004).
pub(crate) fn resolve_operand<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    operand: &ast::Operand,
    usage: Usage,
) -> Resolved<'a> {
    let node = operand.syntax();
    let mut out = Resolved::new(node.text_range(), node.text().to_string());
    match operand {
        ast::Operand::Literal(lit) => {
            if let Ok(value) = literal::check_literal(&lit.text())
                && pointer_is_valid(ctx, out.range, &out.text, &value)
            {
                out.ty = literal_type(&value);
                out.target = Some(Target::Constant(value));
            }
        }
        ast::Operand::Address(address) => {
            let read = read_address_node(ctx, address);
            if let Some((range, area)) = read.other_set {
                out.translated = read.address.as_ref().map(|a| a.display(ctx.mnemonic));
                out.other_set = Some((range, area));
            }
            if let Some(addr) = read.address {
                local_data_warning(ctx, out.range, &out.text, &addr);
                out.bind_address(addr);
            }
        }
        ast::Operand::VarRef(var_ref) => {
            if let Some(token) = var_ref.name() {
                resolve_var_ref(
                    ctx,
                    scope,
                    &mut out,
                    token.text(),
                    token.text_range(),
                    usage,
                );
            }
        }
        ast::Operand::SymbolRef(symbol_ref) => {
            let name = symbol_ref.name();
            let reference = symbol_ref
                .token()
                .map_or(out.range, |t| string_inner_range(&t));
            resolve_symbol_ref(ctx, scope, &mut out, &name, reference, usage);
        }
        ast::Operand::NameRef(name_ref) => {
            if let Some(token) = name_ref.token() {
                resolve_name(
                    ctx,
                    scope,
                    &mut out,
                    token.text(),
                    token.text_range(),
                    usage,
                );
            }
        }
        // Indirect and status operands are rejected before resolution; message targets and
        // paths do not occur in graphs.
        _ => {}
    }
    out
}

/// `#Name`: a declared variable or an active predefined variable (§2.4 rule 3).
fn resolve_var_ref<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    out: &mut Resolved<'a>,
    name: &str,
    reference: TextRange,
    usage: Usage,
) {
    if bind_variable(ctx, scope, out, name, reference) {
        return;
    }
    if replaced_by_specific_code(ctx, scope, name, reference) {
        return;
    }
    match usage.role {
        Role::TimeValue => unresolved_time_operand(ctx, scope, out.range, name),
        Role::Operand => {
            let symbol_hint = if ctx.index.symbol(name).is_some() {
                format!("; \"{name}\" is a global symbol")
            } else {
                String::new()
            };
            let message = format!(
                "'#{name}' is not a variable of graph {}{symbol_hint}",
                scope.name
            );
            let mut diag = ctx.diag("HG4101", out.range, message);
            let candidates = variable_candidates(scope);
            if let Some(best) = closest::closest(name, candidates.iter().map(String::as_str)) {
                diag = diag
                    .fix(format!("Replace with '#{best}'"), ctx.loc(reference), best)
                    .preferred();
            }
            diag = declare_fix(ctx, scope, diag, name, usage.implied);
            ctx.push(diag);
        }
    }
}

/// `"Name"`: a global symbol (§2.4 rule 5).
fn resolve_symbol_ref<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    out: &mut Resolved<'a>,
    name: &str,
    reference: TextRange,
    usage: Usage,
) {
    if bind_symbol(ctx, out, name, reference) {
        return;
    }
    match usage.role {
        Role::TimeValue => unresolved_time_operand(ctx, scope, out.range, name),
        Role::Operand => {
            let variable_hint = if scope.has_graph_variable(name) {
                format!("; write #{name} for the variable")
            } else {
                String::new()
            };
            let message = format!("\"{name}\" is not a global symbol{variable_hint}");
            let mut diag = ctx.diag("HG4101", out.range, message);
            let index = ctx.index;
            let symbols = index.symbols.iter().map(|s| s.name.as_str());
            if let Some(best) = closest::closest(name, symbols) {
                diag = diag
                    .fix(format!("Replace with \"{best}\""), ctx.loc(reference), best)
                    .preferred();
            }
            ctx.push(diag);
        }
    }
}

/// `Name`: an address without a space, else a variable, an active predefined variable or a
/// global symbol (§2.4 rules 1, 2 and 4).
fn resolve_name<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    out: &mut Resolved<'a>,
    name: &str,
    reference: TextRange,
    usage: Usage,
) {
    if let Some(area) = area_word(name, ctx.mnemonic) {
        resolve_area_word(ctx, scope, out, name, reference, area);
        return;
    }
    if let Some(read) = address_without_space(name, ctx.mnemonic) {
        read_address_name(ctx, scope, out, name, read);
        return;
    }
    if scope.var(name).is_none()
        && ctx.index.symbol(name).is_none()
        && let Some(read) = other_set_address_without_space(name, ctx.mnemonic)
    {
        let letters = name.trim_end_matches(|c: char| c.is_ascii_digit());
        out.other_set = Some((reference, letters.to_owned()));
        match read.address {
            Ok(addr) => {
                out.translated = Some(addr.display(ctx.mnemonic));
                out.bind_address(addr);
            }
            Err(error) => report_address_error(ctx, out.range, &out.text, &error),
        }
        return;
    }
    if bind_variable(ctx, scope, out, name, reference) || bind_symbol(ctx, out, name, reference) {
        return;
    }
    if replaced_by_specific_code(ctx, scope, name, reference) {
        return;
    }
    match usage.role {
        Role::TimeValue => unresolved_time_operand(ctx, scope, out.range, name),
        Role::Operand => {
            let message = format!(
                "'{name}' is neither a variable of {} nor a global symbol",
                scope.owner()
            );
            let mut diag = ctx.diag("HG4101", out.range, message);
            let index = ctx.index;
            let mut candidates = variable_candidates(scope);
            candidates.extend(index.symbols.iter().map(|s| s.name.clone()));
            if let Some(best) = closest::closest(name, candidates.iter().map(String::as_str)) {
                let text = lang::operand_spelling(best);
                diag = diag
                    .fix(format!("Replace with '{text}'"), ctx.loc(reference), text)
                    .preferred();
            }
            diag = declare_fix(ctx, scope, diag, name, usage.implied);
            ctx.push(diag);
        }
    }
}

/// HG4102 / HG4010: an area identifier (or register name) with no number after it (§2.4 rule
/// 2). With a variable or symbol of that name it reads as that (HG4102); otherwise it is a
/// malformed address (HG4010) or a register operand (HG4003, reported before resolution).
fn resolve_area_word<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    out: &mut Resolved<'a>,
    name: &str,
    reference: TextRange,
    area: AreaWord,
) {
    let (canonical, meaning) = (area.canonical, area.meaning);
    let prefix = format!("'{name}' reads as the address area {canonical} ({meaning})");
    if scope.var(name).is_some() {
        let diag = ctx
            .diag(
                "HG4102",
                reference,
                format!("{prefix}; write '#{name}' for the variable"),
            )
            .fix(
                format!("Replace with '#{name}'"),
                ctx.loc(reference),
                format!("#{name}"),
            );
        ctx.push(diag);
        bind_variable(ctx, scope, out, name, reference);
    } else if ctx.index.symbol(name).is_some() {
        let diag = ctx
            .diag(
                "HG4102",
                reference,
                format!("{prefix}; write \"{name}\" for the symbol"),
            )
            .fix(
                format!("Replace with \"{name}\""),
                ctx.loc(reference),
                format!("\"{name}\""),
            );
        ctx.push(diag);
        bind_symbol(ctx, out, name, reference);
    } else if !area.register {
        let message =
            format!("'{name}' is not a valid address: the area {canonical} needs a number");
        let diag = ctx.diag("HG4010", out.range, message);
        ctx.push(diag);
    }
}

/// §2.4 rule 1 for an identifier such as `MW10`, `T1`, `FC1`: it is that address; HG4103 warns
/// when a variable or symbol of that spelling names something else.
fn read_address_name<'a>(
    ctx: &mut Ctx<'a>,
    scope: &GraphScope,
    out: &mut Resolved<'a>,
    name: &str,
    read: address::ReadAddress,
) {
    match read.address {
        Ok(addr) => {
            shadowed_name_warning(ctx, scope, out.range, name, &addr);
            local_data_warning(ctx, out.range, &out.text, &addr);
            out.bind_address(addr);
        }
        Err(error) => report_address_error(ctx, out.range, &out.text, &error),
    }
}

/// HG4103: `name` is read as `addr`, but a variable or symbol is spelled the same.
pub(crate) fn shadowed_name_warning(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    range: TextRange,
    name: &str,
    addr: &Address,
) {
    let (kind, replacement) = if scope.var(name).is_some() {
        ("variable", format!("#{name}"))
    } else if ctx
        .index
        .symbol(name)
        .is_some_and(|s| s.address.as_ref() != Some(addr))
    {
        ("symbol", format!("\"{name}\""))
    } else {
        return;
    };
    let message = format!(
        "'{name}' is read as the address {}, not as the {kind} {name}",
        addr.display(ctx.mnemonic)
    );
    let diag = ctx.diag("HG4103", range, message).fix(
        format!("Replace with '{replacement}'"),
        ctx.loc(range),
        replacement,
    );
    ctx.push(diag);
}

/// Binds `name` to a declared variable or an active predefined variable.
fn bind_variable<'a>(
    ctx: &mut Ctx<'a>,
    scope: &mut GraphScope,
    out: &mut Resolved<'a>,
    name: &str,
    reference: TextRange,
) -> bool {
    if let Some(var) = scope.var(name) {
        let declared = scope.vars[var].name.clone();
        case_hint(ctx, reference, name, &declared);
        scope.mark_var(var);
        out.ty = scope.vars[var].ty;
        out.target = Some(Target::Var(var));
        return true;
    }
    if let Some(predefined) = scope.active_predefined(name) {
        case_hint(ctx, reference, name, predefined.name);
        scope.used_predefined.insert(predefined.name);
        out.ty = Some(predefined.ty);
        out.target = Some(Target::Predefined(predefined));
        return true;
    }
    false
}

/// Binds `name` to a global symbol.
fn bind_symbol<'a>(
    ctx: &mut Ctx<'a>,
    out: &mut Resolved<'a>,
    name: &str,
    reference: TextRange,
) -> bool {
    let index = ctx.index;
    let Some(symbol) = index.symbol(name) else {
        return false;
    };
    case_hint(ctx, reference, name, &symbol.name);
    ctx.use_symbol(&symbol.name);
    out.ty = symbol.ty;
    out.target = Some(Target::Symbol(symbol));
    true
}

/// HG1207 / HG1208 for a name that did not resolve: they replace HG4101 and HG3005 (C4).
fn replaced_by_specific_code(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    name: &str,
    reference: TextRange,
) -> bool {
    if let Some(predefined) = lang::predefined(name).filter(|p| !scope.is_active(p)) {
        inactive_variable(ctx, scope, name, reference, predefined);
        return true;
    }
    if let Some(&(_, new)) = lang::V27_NAMES
        .iter()
        .find(|(old, _)| old.eq_ignore_ascii_case(name))
    {
        let mut edits = vec![(ctx.loc(reference), new.to_owned())];
        if let Some(p) = lang::predefined(new).filter(|p| !scope.is_active(p)) {
            edits.extend(activate_edit(ctx, scope, p.name));
        }
        let diag = ctx
            .diag(
                "HG1208",
                reference,
                format!("'{name}' is the HiGraph V2.7 name; use '{new}'"),
            )
            .fix_edits(format!("Replace with '{new}'"), edits);
        ctx.push(diag);
        return true;
    }
    false
}

/// HG1207: an inactive predefined variable.
fn inactive_variable(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    name: &str,
    reference: TextRange,
    predefined: &Predefined,
) {
    let message = format!(
        "'{name}' is inactive in graph {}; add 'activate {name};'",
        scope.name
    );
    let mut diag = ctx.diag("HG1207", reference, message);
    let edits = activate_edit(ctx, scope, predefined.name);
    if !edits.is_empty() {
        diag = diag.fix_edits(format!("Activate {}", predefined.name), edits);
    }
    ctx.push(diag);
}

/// The edit that activates `name`: append it to the graph's `activate`, or insert a new one.
fn activate_edit(ctx: &Ctx<'_>, scope: &GraphScope, name: &str) -> Vec<(crate::diag::Loc, String)> {
    if let Some(last) = scope.activated.last() {
        let at = TextRange::empty(last.range.end());
        return vec![(ctx.item_loc(at), format!(", {name}"))];
    }
    scope
        .activate_insert
        .map(|at| {
            vec![(
                ctx.item_loc(TextRange::empty(at)),
                format!(" activate {name};"),
            )]
        })
        .unwrap_or_default()
}

/// HG3005 (without its fix): a time operand `name` at `range` that does not resolve in
/// `owner` (`graph G`, `chart C`). Charts use it too.
pub(crate) fn time_operand_not_found(
    ctx: &Ctx<'_>,
    range: TextRange,
    name: &str,
    owner: &str,
) -> crate::diag::Diag {
    let message =
        format!("time operand '{name}' is neither a variable of {owner} nor a global symbol");
    ctx.diag("HG3005", range, message)
}

/// HG3005 in a graph, with the fix declaring the name in `in`.
fn unresolved_time_operand(ctx: &mut Ctx<'_>, scope: &GraphScope, range: TextRange, name: &str) {
    let mut diag = time_operand_not_found(ctx, range, name, &scope.owner());
    if let Some(edit) = in_declaration_edit(ctx, scope, name, Type::Time) {
        diag = diag.fix_edits(format!("Declare '{name} : TIME;' in 'in'"), vec![edit]);
    }
    ctx.push(diag);
}

/// HG4101's second fix: declare the name in `in` with the type the operation implies.
fn declare_fix(
    ctx: &Ctx<'_>,
    scope: &GraphScope,
    diag: crate::diag::Diag,
    name: &str,
    implied: Option<Type>,
) -> crate::diag::Diag {
    let Some(ty) = implied else { return diag };
    if !lang::is_identifier(name) {
        return diag;
    }
    match in_declaration_edit(ctx, scope, name, ty) {
        Some(edit) => diag.fix_edits(format!("Declare '{name} : {ty};' in 'in'"), vec![edit]),
        None => diag,
    }
}

/// The edit inserting `name : ty;` into the graph's `in` section (creating one if needed).
fn in_declaration_edit(
    ctx: &Ctx<'_>,
    scope: &GraphScope,
    name: &str,
    ty: Type,
) -> Option<(crate::diag::Loc, String)> {
    let (at, new_section) = scope.in_insert?;
    let text = if new_section {
        format!(" in < {name} : {ty}; >")
    } else {
        format!("{name} : {ty}; ")
    };
    Some((ctx.item_loc(TextRange::empty(at)), text))
}

/// HG1104: a reference spelled in another letter case than its declaration.
pub(crate) fn case_hint(ctx: &mut Ctx<'_>, reference: TextRange, used: &str, declared: &str) {
    if used == declared {
        return;
    }
    let diag = ctx
        .diag(
            "HG1104",
            reference,
            format!("'{used}' is declared as '{declared}'"),
        )
        .fix(
            format!("Replace with '{declared}'"),
            ctx.loc(reference),
            declared,
        );
    ctx.push(diag);
}

/// Names of the graph's variables and active predefined variables, for closest-name fixes.
fn variable_candidates(scope: &GraphScope) -> Vec<String> {
    let mut names: Vec<String> = scope.vars.iter().map(|v| v.name.clone()).collect();
    names.extend(
        lang::PREDEFINED
            .iter()
            .filter(|p| scope.is_active(p))
            .map(|p| p.name.to_owned()),
    );
    names
}

// ------------------------------------------------------------------------------ addresses

/// An ADDRESS node read in the file's mnemonic set.
#[derive(Debug, Clone)]
pub(crate) struct AddressRead {
    /// The address, if it is valid (in the file's set, or translated from the other one).
    pub address: Option<Address>,
    /// The area token if it belongs only to the other mnemonic set (HG4007): its range and
    /// the area as written.
    pub other_set: Option<(TextRange, String)>,
}

/// Reads an ADDRESS node and reports HG4009, HG4010 and HG4011. An area of the other mnemonic
/// set is read in that set (the translated address); the caller reports HG4007.
pub(crate) fn read_address_node(ctx: &mut Ctx<'_>, node: &ast::Address) -> AddressRead {
    let range = node.syntax().text_range();
    let written = node.syntax().text().to_string();
    let compact = node.compact_text();
    let mut out = AddressRead {
        address: None,
        other_set: None,
    };
    let read = address::read(&compact, ctx.mnemonic).or_else(|| {
        // Not address-shaped in this set: try the other set (e.g. an area spelled only there).
        address::read(&compact, ctx.mnemonic.other())
    });
    let Some(read) = read else {
        let message = format!("'{written}' is not a valid address: the number is malformed");
        let diag = ctx.diag("HG4010", range, message);
        ctx.push(diag);
        return out;
    };
    if read.other_set {
        out.other_set = area_token(node);
    }
    match read.address {
        Ok(addr) => out.address = Some(addr),
        Err(error) => report_address_error(ctx, range, &written, &error),
    }
    out
}

/// The first identifier of an address that is its area (`I` of `I 1.0`, `I1` of `I1.0`; not
/// the `DB10` of a data-block address), with the area letters as written.
fn area_token(node: &ast::Address) -> Option<(TextRange, String)> {
    let token = node
        .syntax()
        .children_with_tokens()
        .filter_map(|e| e.into_token())
        .find(|t| t.kind() == SyntaxKind::IDENT)?;
    let letters: String = token
        .text()
        .chars()
        .take_while(|c| c.is_ascii_alphabetic())
        .collect();
    Some((token.text_range(), letters))
}

/// Reports an address error: HG4009, HG4010 or HG4011. `range` is the address, `written` its
/// text.
pub(crate) fn report_address_error(
    ctx: &mut Ctx<'_>,
    range: TextRange,
    written: &str,
    error: &AddressError,
) {
    let diag = match error {
        AddressError::BitOutOfRange { bit, .. } => {
            let len = TextSize::from(u32::try_from(bit.len()).unwrap_or(0));
            let bit_range = if len <= range.len() {
                TextRange::new(range.end() - len, range.end())
            } else {
                range
            };
            ctx.diag(
                "HG4009",
                bit_range,
                format!("bit number {bit} is outside 0..7"),
            )
        }
        AddressError::Malformed(reason) => ctx.diag(
            "HG4010",
            range,
            format!("'{written}' is not a valid address: {reason}"),
        ),
        AddressError::NeedsDb => ctx.diag(
            "HG4011",
            range,
            format!(
                "'{written}' needs a data block number ('DBn.{written}'); no DB can be opened in HiGraph"
            ),
        ),
        AddressError::InstanceDb => ctx.diag(
            "HG4011",
            range,
            "instance-DB operands are not available in HiGraph",
        ),
    };
    ctx.push(diag);
}

/// HG4009 / HG4010 for the bit address of a `P#` constant (Appendix C.1). Returns `false`
/// if it was reported.
fn pointer_is_valid(ctx: &mut Ctx<'_>, range: TextRange, text: &str, lit: &Literal) -> bool {
    let literal::LiteralValue::Pointer(pointer) = &lit.value else {
        return true;
    };
    let error = if pointer.bit > 7 {
        let bit = text.rsplit('.').next().unwrap_or_default().to_owned();
        AddressError::BitOutOfRange { bit, offset: 0 }
    } else if pointer.byte > 65535 || pointer.db.is_some_and(|db| db > 65535) {
        AddressError::Malformed("the number is above 65535".to_owned())
    } else if pointer.db == Some(0) {
        AddressError::Malformed("DB 0 does not exist".to_owned())
    } else {
        return true;
    };
    report_address_error(ctx, range, text, &error);
    false
}

/// HG4012: temporary local data.
pub(crate) fn local_data_warning(
    ctx: &mut Ctx<'_>,
    range: TextRange,
    written: &str,
    addr: &Address,
) {
    if addr.area == Area::Local {
        let message = format!(
            "'{written}' is temporary local data of the generated FC; its value is not kept"
        );
        let diag = ctx.diag("HG4012", range, message);
        ctx.push(diag);
    }
}

/// §2.4 rule 1: an identifier that is a well-formed address of `set` written without a space
/// (`MW10`, `T1`, `FC1`, `DB5`; not `M1`, whose bit is missing).
pub(crate) fn address_without_space(name: &str, set: Mnemonic) -> Option<address::ReadAddress> {
    let read = address::read(name, set)?;
    (!read.other_set && well_formed_shape(name, set)).then_some(read)
}

/// An operand written as one word that is an address (§2.4 rule 1: `mw10`, `t5`, `fc1`, in
/// either mnemonic set, the other one being HG4007) where such a word always is that address:
/// graph operands, CALL targets and actuals, group actuals and `fc`/`db` clauses, `block`
/// headers. Not in charts, where a variable of that spelling comes first, and not where a
/// name is expected (the graph of an instance). `fmt` writes such a word in upper case, as it
/// writes every address, and the semantic model compares it so.
pub(crate) fn is_one_word_address_operand(token: &higraph_syntax::SyntaxToken) -> bool {
    use higraph_syntax::SyntaxKind::{ACTIVATE, CHART, INSTANCE, NAME_REF};
    let Some(name_ref) = token.parent().filter(|p| p.kind() == NAME_REF) else {
        return false;
    };
    if name_ref
        .parent()
        .is_some_and(|p| matches!(p.kind(), INSTANCE | ACTIVATE))
        || name_ref.ancestors().any(|n| n.kind() == CHART)
    {
        return false;
    }
    let text = token.text();
    [
        crate::lang::Mnemonic::Simatic,
        crate::lang::Mnemonic::International,
    ]
    .into_iter()
    .any(|set| address_without_space(text, set).is_some())
}

/// HG4007: an identifier whose letters are an area only of the other set, followed by digits
/// (`I1`, `IW2`, `C5` in a SIMATIC file). Read in the other set.
fn other_set_address_without_space(name: &str, set: Mnemonic) -> Option<address::ReadAddress> {
    let (letters, _) = split_at_number(name)?;
    if address::is_area_word(letters, set) || !address::is_area_word(letters, set.other()) {
        return None;
    }
    address::read(name, set.other())
}

/// Area letters followed by digits, where the area is not a bit area (an identifier cannot
/// hold the `.bit`).
fn well_formed_shape(name: &str, set: Mnemonic) -> bool {
    split_at_number(name).is_some_and(|(letters, _)| {
        address::is_area_word(letters, set) && !address::is_bit_area(letters, set)
    })
}

/// An identifier that ends in a number, split before its first digit (`MW` and `10` of
/// `MW10`); `None` if there is no digit or a non-digit follows the first one.
fn split_at_number(name: &str) -> Option<(&str, &str)> {
    let letters_end = name.find(|c: char| c.is_ascii_digit())?;
    let (letters, digits) = name.split_at(letters_end);
    (!digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())).then_some((letters, digits))
}

/// An area identifier or register name written alone (§2.4 rule 2, Appendix A.2b).
#[derive(Debug, Clone, Copy)]
pub(crate) struct AreaWord {
    /// The area as the active set spells it, upper case.
    pub canonical: &'static str,
    /// What the area means (for HG4102).
    pub meaning: &'static str,
    /// A register or status name rather than an area.
    pub register: bool,
}

/// Is `name` an address-area identifier of `set` or a register name (Appendix A.2, A.2b)?
pub(crate) fn area_word(name: &str, set: Mnemonic) -> Option<AreaWord> {
    if let Some((canonical, meaning)) = address::area_meaning(name, set) {
        return Some(AreaWord {
            canonical,
            meaning,
            register: false,
        });
    }
    lang::register_meaning(name, set).map(|(canonical, meaning)| AreaWord {
        canonical,
        meaning,
        register: true,
    })
}

// ------------------------------------------------------------------------------ helpers

/// The type of a valid constant (Appendix C.1).
pub(crate) fn literal_type(lit: &Literal) -> Option<Type> {
    let name = literal::literal_type(lit);
    match lit.class {
        literal::LiteralClass::String => match &lit.value {
            literal::LiteralValue::Str(s) => Some(Type::String(
                u16::try_from(s.chars().count()).unwrap_or(254),
            )),
            _ => Some(Type::String(254)),
        },
        literal::LiteralClass::Pointer => Some(Type::Pointer),
        _ => Type::from_name(name, true),
    }
}

/// The reference of a block reference (`FC 10`, `FC10`, `Name`, `"Name"`) in the sense of
/// `diagnostics.md` §2.3: the whole reference, except that a quoted symbol is meant without
/// its quotes.
pub(crate) fn block_reference_range(block: &ast::BlockRef) -> TextRange {
    block
        .symbol_ref()
        .and_then(|s| s.token())
        .map_or_else(|| block.syntax().text_range(), |t| string_inner_range(&t))
}

/// The range of a STRING token without its quotes.
pub(crate) fn string_inner_range(token: &higraph_syntax::SyntaxToken) -> TextRange {
    let range = token.text_range();
    let text = token.text();
    let start = range.start() + TextSize::from(u32::from(text.starts_with('"')));
    let end_trim = u32::from(text.len() > 1 && text.ends_with('"'));
    let end = range.end() - TextSize::from(end_trim);
    if start <= end {
        TextRange::new(start, end)
    } else {
        range
    }
}
