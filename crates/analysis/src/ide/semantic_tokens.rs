//! Semantic highlighting (`tooling.md` §4 "semanticTokens"): every token that means something
//! gets a [`TokenKind`] and a set of [`TokenModifier`]s.
//!
//! Names are coloured by what they *resolve to*, with the resolution the rules use: graph
//! operands through [`crate::resolve`], chart paths through the chart operand rules, actual
//! values through the group rules. So `A` in `= A;` is a parameter when the graph declares
//! `A`, and `MW10` is an address; a name that resolves to nothing gets no token.
//!
//! # Legend
//!
//! [`TOKEN_KINDS`] and [`TOKEN_MODIFIERS`] are the LSP legend. Several kinds share one LSP
//! token type and differ by modifiers; [`TokenKind::legend_index`] is the index into
//! [`TOKEN_KINDS`], and [`SemanticToken::modifiers`] is the complete LSP modifier bit set
//! (bit `i` is `TOKEN_MODIFIERS[i]`), implied modifiers included, so a server passes both
//! through unchanged.
//!
//! | kind                 | LSP type     | modifiers always set      | what |
//! |----------------------|--------------|---------------------------|------|
//! | `Keyword`            | `keyword`    |                           | keywords; `mode`/`switching`/`run` values; option names |
//! | `Opcode`             | `function`   |                           | STL operations (`U`, `U(`, `==I`, `CALL`), action qualifiers (`N`, `SD`) |
//! | `Operator`           | `operator`   |                           | chart operators (`and`, `not`, `>=`, `+`), status operands (`==0`) |
//! | `Label`              | `label`      |                           | block labels (`E:`, `C-:`, `!:`), jump labels |
//! | `Parameter`          | `parameter`  | `input` / `output`        | `in`, `out`, `in_out` variables without `msg`; CALL formals |
//! | `Variable`           | `variable`   |                           | `stat` variables |
//! | `PredefinedVariable` | `variable`   | `defaultLibrary` (`readonly` if not writable, direction) | `CurrentState`, `INIT_SD`, …; `SFC.…` paths |
//! | `Symbol`             | `variable`   | `static`                  | global symbols |
//! | `Message`            | `property`   | `input` (msg in) / `output` (msg out) | message variables, `Inst.Msg` |
//! | `State`              | `enumMember` |                           | state numbers in state headers and transition endpoints |
//! | `Step`               | `enumMember` |                           | chart steps, jump and loop targets |
//! | `Transition`         | `event`      |                           | names of chart transitions, jumps and loops |
//! | `Address`            | `macro`      |                           | absolute addresses (`E 1.0`, `MW10`, `FC 10`) |
//! | `Constant`           | `number`     |                           | constants (`T#5S`, `16#FF` …, `TRUE`), priorities, option values |
//! | `String`             | `string`     |                           | display names and comments (`"…"`), `'…'` constants |
//! | `Comment`            | `comment`    |                           | `// …` |
//! | `Type`               | `type`       | `defaultLibrary`          | `BOOL`, `STRING[20]` (the length is a `Constant`) |
//! | `Item`               | `class`      |                           | graph, group, chart and test names; `instance X : Graph`; groups and charts in tests |
//! | `Instance`           | `namespace`  |                           | instance names, the `Inst` of `Inst.Msg` |
//! | `Sequencer`          | `namespace`  |                           | sequencer names |
//!
//! In tests, paths are classed by their shape and the global names (the lowering resolves
//! them fully): addresses, symbols, groups and charts, operating state names (`State`) and the
//! pseudo-members `state`, `previous`, `calls`, `X`, `T`, `error` (`PredefinedVariable`,
//! `readonly`); a command (`start`) is a `Keyword`.
//!
//! Declarations carry `declaration`. Direction modifiers: `input` for `in` (and `msg in`),
//! `output` for `out` (and `msg out`), both for `in_out`.
//!
//! Tokens are sorted, do not overlap and never span a line break: a construct spread over
//! several lines (or holding a comment) is split into its tokens.

use std::collections::HashMap;

use higraph_syntax::{
    SyntaxKind::*,
    SyntaxNode, SyntaxToken, TextRange,
    ast::{self, AstNode},
    rowan::NodeOrToken,
};

use crate::{
    Analysis, Cancellable,
    db::{self, File, ItemLoc, Workspace},
    index::{self, GlobalIndex},
    lang::{self, Predefined, Section},
    resolve::{self, GraphScope, Role, Target, Usage},
    rules::{
        Ctx, ItemAnalysis,
        chart::{self, ChartInfo, decls, operands},
        group::{
            actuals::{self, Value},
            interface::{GraphInterface, MsgDir, graph_interface},
        },
    },
};

/// The LSP token types of the legend; [`TokenKind::legend_index`] indexes it.
pub const TOKEN_KINDS: &[&str] = &[
    "keyword",
    "function",
    "operator",
    "label",
    "parameter",
    "variable",
    "property",
    "enumMember",
    "event",
    "macro",
    "number",
    "string",
    "comment",
    "type",
    "class",
    "namespace",
];

/// The LSP token modifiers of the legend; bit `i` of [`SemanticToken::modifiers`] is the
/// `i`th. `input` and `output` are custom modifiers (a variable's direction).
pub const TOKEN_MODIFIERS: &[&str] = &[
    "declaration",
    "readonly",
    "defaultLibrary",
    "static",
    "input",
    "output",
];

/// What a highlighted token is (see the module documentation for the legend).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TokenKind {
    /// A keyword of the language, a chart property value or a group option name.
    Keyword,
    /// An STL operation, a chart action qualifier or an IEC action.
    Opcode,
    /// A chart operator or a status operand.
    Operator,
    /// A block label or jump label.
    Label,
    /// An `in`, `out` or `in_out` variable (not a message), or a CALL formal.
    Parameter,
    /// A `stat` variable.
    Variable,
    /// A predefined variable (or a chart's `SFC.…` interface).
    PredefinedVariable,
    /// A global symbol.
    Symbol,
    /// A message variable (`msg in` / `msg out`).
    Message,
    /// A state number.
    State,
    /// A chart step.
    Step,
    /// The name of a chart transition, jump or loop.
    Transition,
    /// An absolute address.
    Address,
    /// A constant.
    Constant,
    /// A string: display name, comment string, `'…'` constant.
    String,
    /// A line comment.
    Comment,
    /// A type name.
    Type,
    /// A graph, group or chart name.
    Item,
    /// An instance name.
    Instance,
    /// A sequencer name.
    Sequencer,
}

impl TokenKind {
    /// The index of the kind's LSP token type in [`TOKEN_KINDS`].
    pub fn legend_index(self) -> u32 {
        match self {
            TokenKind::Keyword => 0,
            TokenKind::Opcode => 1,
            TokenKind::Operator => 2,
            TokenKind::Label => 3,
            TokenKind::Parameter => 4,
            TokenKind::Variable | TokenKind::PredefinedVariable | TokenKind::Symbol => 5,
            TokenKind::Message => 6,
            TokenKind::State | TokenKind::Step => 7,
            TokenKind::Transition => 8,
            TokenKind::Address => 9,
            TokenKind::Constant => 10,
            TokenKind::String => 11,
            TokenKind::Comment => 12,
            TokenKind::Type => 13,
            TokenKind::Item => 14,
            TokenKind::Instance | TokenKind::Sequencer => 15,
        }
    }

    /// The kind's LSP token type (`"keyword"`, `"variable"`, …).
    pub fn lsp_type(self) -> &'static str {
        TOKEN_KINDS
            .get(self.legend_index() as usize)
            .copied()
            .unwrap_or("variable")
    }

    /// Modifiers every token of this kind has.
    fn implied_modifiers(self) -> u32 {
        match self {
            TokenKind::PredefinedVariable | TokenKind::Type => TokenModifier::DefaultLibrary.bit(),
            TokenKind::Symbol => TokenModifier::Static.bit(),
            _ => 0,
        }
    }
}

/// A token modifier of the legend.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TokenModifier {
    /// The declaration of a name.
    Declaration,
    /// A predefined variable the program may not write.
    Readonly,
    /// Predefined by the language: predefined variables, type names.
    DefaultLibrary,
    /// A global symbol.
    Static,
    /// An input: `in`, `in_out`, `msg in`.
    Input,
    /// An output: `out`, `in_out`, `msg out`.
    Output,
}

impl TokenModifier {
    /// The modifier's bit in [`SemanticToken::modifiers`].
    pub const fn bit(self) -> u32 {
        1 << self as u32
    }

    /// The modifier's LSP name (its entry in [`TOKEN_MODIFIERS`]).
    pub fn as_str(self) -> &'static str {
        TOKEN_MODIFIERS
            .get(self as usize)
            .copied()
            .unwrap_or("declaration")
    }
}

/// One highlighted token.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SemanticToken {
    /// Byte range in the file; never spans a line break.
    pub range: TextRange,
    pub kind: TokenKind,
    /// The LSP modifier bit set over [`TOKEN_MODIFIERS`], the kind's implied ones included.
    pub modifiers: u32,
}

impl Analysis {
    /// The semantic tokens of a `.higraph` file, sorted and non-overlapping. With `range`,
    /// only the tokens that overlap it. An unknown path has no tokens.
    pub fn semantic_tokens(
        &self,
        path: &str,
        range: Option<TextRange>,
    ) -> Cancellable<Vec<SemanticToken>> {
        let Some(file) = self.file(path) else {
            return Ok(Vec::new());
        };
        self.with_db(|db, ws| highlight(db, ws, file, range))
    }
}

fn highlight(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    range: Option<TextRange>,
) -> Vec<SemanticToken> {
    let root = db::parse(db, file).syntax_node();
    let mut highlighter = Highlighter {
        range,
        index: db::global_index(db, ws),
        tokens: Vec::new(),
    };
    let mut item = 0u32;
    for element in root.children_with_tokens() {
        match element {
            NodeOrToken::Node(node) => {
                if ast::Item::cast(node.clone()).is_some() {
                    if highlighter.wanted(node.text_range()) {
                        let mut resolver = Resolver::new(db, ws, file, item, &node);
                        highlighter.walk(&node, &mut resolver);
                    }
                    item += 1;
                } else {
                    highlighter.walk(&node, &mut Resolver::None);
                }
            }
            NodeOrToken::Token(token) => highlighter.token(&token),
        }
    }
    let mut tokens = highlighter.tokens;
    // The walk emits in text order; keep the promise even if a construct nests oddly.
    tokens.sort_by_key(|t| (t.range.start(), t.range.end()));
    let mut out: Vec<SemanticToken> = Vec::with_capacity(tokens.len());
    for token in tokens {
        if out
            .last()
            .is_none_or(|last| last.range.end() <= token.range.start())
        {
            out.push(token);
        }
    }
    out
}

/// What names resolve against in the item being highlighted.
enum Resolver<'a> {
    /// Outside items (or in items without references to resolve).
    None,
    Graph {
        ctx: Ctx<'a>,
        scope: GraphScope,
        interface: &'a GraphInterface,
    },
    Group {
        ctx: Ctx<'a>,
        /// Instance name (key) → the interface of its graph, if the graph exists.
        instances: HashMap<String, Option<&'a GraphInterface>>,
    },
    Chart {
        ctx: Ctx<'a>,
        scope: chart::Scope,
    },
}

impl<'a> Resolver<'a> {
    fn new(
        db: &'a dyn salsa::Database,
        ws: Workspace,
        file: File,
        item: u32,
        node: &SyntaxNode,
    ) -> Resolver<'a> {
        let index = db::global_index(db, ws);
        // The rules' context; the diagnostics it collects are dropped.
        let mut ctx = Ctx {
            db,
            ws,
            file,
            item,
            mnemonic: db::file_mnemonic(db, ws, file),
            index,
            out: ItemAnalysis::default(),
            in_member: false,
        };
        match ast::Item::cast(node.clone()) {
            Some(ast::Item::Graph(graph)) => Resolver::Graph {
                ctx,
                scope: GraphScope::new(&graph),
                interface: graph_interface(db, ItemLoc::new(db, file, item)),
            },
            Some(ast::Item::Group(group)) => {
                let instances = group
                    .instances()
                    .filter_map(|instance| {
                        let name = instance.name()?.text();
                        let interface = instance
                            .graph()
                            .and_then(|g| index.graph(&g.text()))
                            .map(|g| graph_interface(db, ItemLoc::new(db, g.file, g.item)));
                        Some((index::key(&name), interface))
                    })
                    .collect();
                Resolver::Group { ctx, instances }
            }
            Some(ast::Item::Chart(chart)) => {
                let info = ChartInfo {
                    name: chart.name().map(|n| n.text()).unwrap_or_default(),
                    is_type: chart.is_type(),
                    chart,
                };
                let vars = decls::declare(&mut ctx, &info);
                Resolver::Chart {
                    ctx,
                    scope: chart::Scope::new(info, vars),
                }
            }
            _ => Resolver::None,
        }
    }
}

/// How graph operands are resolved here: only the target matters, not the diagnostics.
const OPERAND: Usage = Usage {
    role: Role::Operand,
    implied: None,
};

struct Highlighter<'a> {
    range: Option<TextRange>,
    index: &'a GlobalIndex,
    tokens: Vec<SemanticToken>,
}

impl Highlighter<'_> {
    /// Does `range` overlap the requested range?
    fn wanted(&self, range: TextRange) -> bool {
        self.range.is_none_or(|r| {
            if r.is_empty() {
                range.contains_inclusive(r.start())
            } else {
                r.start() < range.end() && range.start() < r.end()
            }
        })
    }

    fn push(&mut self, range: TextRange, kind: TokenKind, modifiers: u32) {
        if range.is_empty() || !self.wanted(range) {
            return;
        }
        self.tokens.push(SemanticToken {
            range,
            kind,
            modifiers: modifiers | kind.implied_modifiers(),
        });
    }

    /// Highlights a node as one token, or token by token when it spans lines or holds a
    /// comment (comments then keep their own kind).
    fn push_node(&mut self, node: &SyntaxNode, kind: TokenKind, modifiers: u32) {
        let tokens: Vec<SyntaxToken> = node
            .descendants_with_tokens()
            .filter_map(|e| e.into_token())
            .collect();
        let significant = |t: &&SyntaxToken| !t.kind().is_trivia() && t.kind() != LEX_ERROR;
        let (Some(first), Some(last)) = (
            tokens.iter().find(significant),
            tokens.iter().rev().find(significant),
        ) else {
            return;
        };
        let range = TextRange::new(first.text_range().start(), last.text_range().end());
        let inner = tokens
            .iter()
            .filter(|t| range.contains_range(t.text_range()));
        let split = inner
            .clone()
            .any(|t| t.kind() == COMMENT || t.text().contains(['\n', '\r']));
        if !split {
            self.push(range, kind, modifiers);
            return;
        }
        for token in inner {
            match token.kind() {
                COMMENT => self.push(token.text_range(), TokenKind::Comment, 0),
                WHITESPACE | LEX_ERROR => {}
                _ => self.push(token.text_range(), kind, modifiers),
            }
        }
    }

    fn push_token(&mut self, token: &SyntaxToken, kind: TokenKind, modifiers: u32) {
        self.push(token.text_range(), kind, modifiers);
    }

    /// Pre-order walk: constructs with a meaning of their own are highlighted as a whole.
    fn walk(&mut self, node: &SyntaxNode, resolver: &mut Resolver<'_>) {
        if !self.wanted(node.text_range()) {
            return;
        }
        match node.kind() {
            NAME => self.name(node),
            NAME_REF => self.name_ref(node, resolver),
            VAR_REF | SYMBOL_REF => self.reference(node, resolver),
            PATH => self.path(node, resolver),
            TEST_PATH => self.test_path(node),
            MESSAGE_TARGET => self.message_target(node, resolver),
            OPCODE | QUALIFIER => self.push_node(node, TokenKind::Opcode, 0),
            LABEL | JUMP_LABEL => self.push_node(node, TokenKind::Label, 0),
            ADDRESS => self.push_node(node, TokenKind::Address, 0),
            COMPARE_OP | STATUS_OPERAND => self.push_node(node, TokenKind::Operator, 0),
            LITERAL => {
                let is_text = node
                    .descendants_with_tokens()
                    .any(|e| e.kind() == CHAR || e.kind() == STRING);
                let kind = if is_text {
                    TokenKind::String
                } else {
                    TokenKind::Constant
                };
                self.push_node(node, kind, 0);
            }
            TYPE_REF => {
                for token in node.children_with_tokens().filter_map(|e| e.into_token()) {
                    match token.kind() {
                        IDENT => self.push_token(&token, TokenKind::Type, 0),
                        NUMBER => self.push_token(&token, TokenKind::Constant, 0),
                        COMMENT => self.push_token(&token, TokenKind::Comment, 0),
                        _ => {}
                    }
                }
            }
            _ => {
                for element in node.children_with_tokens() {
                    match element {
                        NodeOrToken::Node(child) => self.walk(&child, resolver),
                        NodeOrToken::Token(token) => self.token(&token),
                    }
                }
            }
        }
    }

    /// A token outside the constructs `walk` handles as a whole.
    fn token(&mut self, token: &SyntaxToken) {
        let kind = token.kind();
        let parent = token.parent().map(|p| p.kind());
        let (kind, modifiers) = match kind {
            COMMENT => (TokenKind::Comment, 0),
            AND_KW | OR_KW | XOR_KW | NOT_KW | MOD_KW => (TokenKind::Operator, 0),
            _ if kind.is_keyword() => (TokenKind::Keyword, 0),
            STRING => (TokenKind::String, 0),
            NUMBER => match parent {
                Some(STATE) => (TokenKind::State, TokenModifier::Declaration.bit()),
                Some(ENDPOINT) => (TokenKind::State, 0),
                Some(PRIO_CLAUSE | OPTION | TEST_STEP) => (TokenKind::Constant, 0),
                _ => return,
            },
            L_ANGLE | R_ANGLE | EQ | PLUS | MINUS | STAR | SLASH if parent == Some(BIN_EXPR) => {
                (TokenKind::Operator, 0)
            }
            // Unary minus (IEC charts).
            MINUS if parent == Some(PREFIX_EXPR) => (TokenKind::Operator, 0),
            // The `-` of a negative step count.
            MINUS if parent == Some(TEST_STEP) => (TokenKind::Constant, 0),
            _ => return,
        };
        self.push_token(token, kind, modifiers);
    }

    /// A declared name, by what it declares.
    fn name(&mut self, node: &SyntaxNode) {
        let Some(parent) = node.parent() else { return };
        let declaration = TokenModifier::Declaration.bit();
        let (kind, modifiers) = match parent.kind() {
            GRAPH | GROUP | CHART => (TokenKind::Item, declaration),
            VAR_DECL => {
                let Some(decl) = ast::VarDecl::cast(parent) else {
                    return;
                };
                let section = decl
                    .syntax()
                    .parent()
                    .and_then(ast::VarSection::cast)
                    .and_then(|s| s.keyword())
                    .and_then(|k| Section::from_keyword(k.text()));
                let Some(section) = section else { return };
                let msg = decl.msg_kind().map(|m| m.is_incoming());
                let (kind, modifiers) = variable_class(section, msg);
                (kind, modifiers | declaration)
            }
            INSTANCE => (TokenKind::Instance, declaration),
            SYMBOL => (TokenKind::Symbol, declaration),
            OPTION => (TokenKind::Keyword, 0),
            SEQUENCER => (TokenKind::Sequencer, declaration),
            STEP => (TokenKind::Step, declaration),
            CHART_TRANS | JUMP | LOOP => (TokenKind::Transition, declaration),
            // An IEC action: a named piece of code ("function").
            CHART_ACTION => (TokenKind::Opcode, declaration),
            TEST => (TokenKind::Item, declaration),
            _ => return,
        };
        self.push_node(node, kind, modifiers);
    }

    /// A name used somewhere, by what it resolves to.
    fn name_ref(&mut self, node: &SyntaxNode, resolver: &mut Resolver<'_>) {
        let Some(parent) = node.parent() else { return };
        let text = ast::NameRef::cast(node.clone())
            .map(|n| n.text())
            .unwrap_or_default();
        let class = match parent.kind() {
            ACTIVATE => lang::predefined(&text).map(predefined_class),
            INSTANCE => self.index.graph(&text).map(|_| (TokenKind::Item, 0)),
            CHART_PROP => Some((TokenKind::Keyword, 0)),
            JUMP | LOOP => Some((TokenKind::Step, 0)),
            BLOCK_REF => self.index.symbol(&text).map(|_| (TokenKind::Symbol, 0)),
            ACTUAL if is_first_name_ref(&parent, node) => formal_class(&parent, &text, resolver),
            PARAM if is_first_name_ref(&parent, node) => Some((TokenKind::Parameter, 0)),
            TEST_RUN => self.index.item(&text).map(|_| (TokenKind::Item, 0)),
            FB_CALL => match resolver {
                Resolver::Chart { scope, .. } => scope
                    .var(&text)
                    .and_then(|i| scope.vars.get(i))
                    .map(|v| variable_class(v.section, None)),
                _ => None,
            },
            FB_ARG if is_first_name_ref(&parent, node) => {
                let output = ast::FbArg::cast(parent.clone()).is_some_and(|a| a.is_output());
                let modifier = if output {
                    TokenModifier::Output
                } else {
                    TokenModifier::Input
                };
                Some((TokenKind::Parameter, modifier.bit()))
            }
            TEST_COMMAND if is_first_name_ref(&parent, node) => {
                self.index.item(&text).map(|_| (TokenKind::Item, 0))
            }
            TEST_COMMAND => {
                higraph_runtime::program::Command::from_name(&text).map(|_| (TokenKind::Keyword, 0))
            }
            _ => self.operand_class(node, &parent, resolver),
        };
        if let Some((kind, modifiers)) = class {
            self.push_node(node, kind, modifiers);
        }
    }

    /// `#Name` and `"Name"`.
    fn reference(&mut self, node: &SyntaxNode, resolver: &mut Resolver<'_>) {
        let Some(parent) = node.parent() else { return };
        let class = self.operand_class(node, &parent, resolver).or_else(|| {
            // `"Name"` naming a block (CALL, fc/db clauses, block interfaces).
            let symbol = ast::SymbolRef::cast(node.clone())?;
            self.index
                .symbol(&symbol.name())
                .map(|_| (TokenKind::Symbol, 0))
        });
        if let Some((kind, modifiers)) = class {
            self.push_node(node, kind, modifiers);
        }
    }

    /// An operand of a graph statement, time item or CALL, or the value of an actual.
    fn operand_class(
        &self,
        node: &SyntaxNode,
        parent: &SyntaxNode,
        resolver: &mut Resolver<'_>,
    ) -> Option<(TokenKind, u32)> {
        let operand = ast::Operand::cast(node.clone())?;
        match resolver {
            Resolver::Graph {
                ctx,
                scope,
                interface,
            } if matches!(parent.kind(), STL_STMT | WAIT_ITEM | SUPERVISE_ITEM | PARAM) => {
                let resolved = resolve::resolve_operand(ctx, scope, &operand, OPERAND);
                match resolved.target? {
                    Target::Var(i) => {
                        let var = scope.vars.get(i)?;
                        let msg = interface
                            .var(&var.name)
                            .and_then(|v| v.msg)
                            .map(|m| m == MsgDir::Incoming);
                        Some(variable_class(var.section, msg))
                    }
                    Target::Predefined(p) => Some(predefined_class(p)),
                    Target::Symbol(_) => Some((TokenKind::Symbol, 0)),
                    Target::Address(_) => Some((TokenKind::Address, 0)),
                    Target::Constant(_) => Some((TokenKind::Constant, 0)),
                }
            }
            Resolver::Group { ctx, .. } if parent.kind() == ACTUAL => {
                match actuals::resolve(ctx, &operand) {
                    Value::Symbol(_) => Some((TokenKind::Symbol, 0)),
                    Value::Address(_) => Some((TokenKind::Address, 0)),
                    Value::Constant(_) => Some((TokenKind::Constant, 0)),
                    Value::Message | Value::Unknown => None,
                }
            }
            _ => None,
        }
    }

    /// A chart operand: a variable, symbol, address, `SFC.…` or an external reference.
    fn path(&mut self, node: &SyntaxNode, resolver: &mut Resolver<'_>) {
        let Resolver::Chart { ctx, scope } = resolver else {
            return;
        };
        let Some(path) = ast::Path::cast(node.clone()) else {
            return;
        };
        let target = operands::resolve(ctx, scope, &path, operands::Unresolved::Operand, false);
        let class = match target {
            operands::Target::Var(i) => scope.vars.get(i).map(|v| variable_class(v.section, None)),
            operands::Target::Symbol { .. } => Some((TokenKind::Symbol, 0)),
            operands::Target::Address(_) => Some((TokenKind::Address, 0)),
            operands::Target::Sfc => {
                for segment in path.segments() {
                    self.push_node(segment.syntax(), TokenKind::PredefinedVariable, 0);
                }
                None
            }
            operands::Target::Iec(operands::IecTarget::FbMember { var, member }) => {
                let mut segments = path.segments();
                if let (Some(instance), Some(var)) = (segments.next(), scope.vars.get(var)) {
                    let (kind, modifiers) = variable_class(var.section, None);
                    self.push_node(instance.syntax(), kind, modifiers);
                }
                if let Some(segment) = segments.next() {
                    let modifier = match member.direction {
                        crate::iec::Direction::Input => TokenModifier::Input,
                        crate::iec::Direction::Output => TokenModifier::Output,
                    };
                    self.push_node(segment.syntax(), TokenKind::Parameter, modifier.bit());
                }
                None
            }
            operands::Target::Iec(operands::IecTarget::StepFlag { .. }) => {
                let mut segments = path.segments();
                if let Some(step) = segments.next() {
                    self.push_node(step.syntax(), TokenKind::Step, 0);
                }
                if let Some(flag) = segments.next() {
                    let modifiers = TokenModifier::Readonly.bit();
                    self.push_node(flag.syntax(), TokenKind::PredefinedVariable, modifiers);
                }
                None
            }
            operands::Target::Unresolved
                if node.parent().is_some_and(|p| p.kind() == QUALIFIER_ACTION)
                    && scope.action(&node.text().to_string()).is_some() =>
            {
                Some((TokenKind::Opcode, 0))
            }
            operands::Target::External | operands::Target::Unresolved => None,
        };
        if let Some((kind, modifiers)) = class {
            self.push_node(node, kind, modifiers);
        }
    }

    /// A test path, by its shape and the workspace's global names (the full resolution of
    /// `runtime.md` §5.3 is the lowering's): an address; a global symbol; a group or chart;
    /// an operating state name (`Chart.state = Ready`); the pseudo-members `state`,
    /// `previous`, `calls`, `X`, `T` and `error` after a dot. Other segments get no token.
    fn test_path(&mut self, node: &SyntaxNode) {
        let Some(path) = ast::TestPath::cast(node.clone()) else {
            return;
        };
        if let Some(address) = path.address() {
            self.push_node(address.syntax(), TokenKind::Address, 0);
            return;
        }
        let single = path.segment_texts().len() == 1;
        if let Some(symbol) = path.symbol()
            && self.index.symbol(&symbol.name()).is_some()
        {
            self.push_node(symbol.syntax(), TokenKind::Symbol, 0);
        }
        for (i, segment) in path.segments().enumerate() {
            let text = segment.text();
            let first = i == 0 && path.symbol().is_none();
            let class = if first {
                if self.index.symbol(&text).is_some() {
                    Some((TokenKind::Symbol, 0))
                } else if self.index.item(&text).is_some() {
                    Some((TokenKind::Item, 0))
                } else if single && higraph_runtime::program::OpState::from_name(&text).is_some() {
                    Some((TokenKind::State, 0))
                } else {
                    None
                }
            } else if TEST_PSEUDO_MEMBERS
                .iter()
                .any(|m| m.eq_ignore_ascii_case(&text))
            {
                Some((TokenKind::PredefinedVariable, TokenModifier::Readonly.bit()))
            } else {
                None
            };
            if let Some((kind, modifiers)) = class {
                self.push_node(segment.syntax(), kind, modifiers);
            }
        }
    }

    /// `Inst.Msg` in an actual: the instance, and the message variable of its graph.
    fn message_target(&mut self, node: &SyntaxNode, resolver: &mut Resolver<'_>) {
        let Resolver::Group { instances, .. } = resolver else {
            return;
        };
        let Some(target) = ast::MessageTarget::cast(node.clone()) else {
            return;
        };
        let Some(instance) = target.instance() else {
            return;
        };
        let Some(interface) = instances.get(&index::key(&instance.text())) else {
            return;
        };
        self.push_node(instance.syntax(), TokenKind::Instance, 0);
        let Some(message) = target.message() else {
            return;
        };
        let class = interface
            .and_then(|i| i.var(&message.text()))
            .map(|v| interface_var_class(v.section, v.msg));
        if let Some((kind, modifiers)) = class {
            self.push_node(message.syntax(), kind, modifiers);
        }
    }
}

/// The last segments of a test path that name no variable but a value of the machine
/// (`runtime.md` §5.3).
const TEST_PSEUDO_MEMBERS: &[&str] = &["state", "previous", "calls", "X", "T", "error"];

/// Is `node` the first NAME_REF child of `parent` (the formal of an actual or CALL parameter)?
fn is_first_name_ref(parent: &SyntaxNode, node: &SyntaxNode) -> bool {
    parent.children().find(|n| n.kind() == NAME_REF).as_ref() == Some(node)
}

/// The formal of an actual parameter: a variable of the instance's graph, or a predefined
/// formal (`ManualMode`, …).
fn formal_class(
    actual: &SyntaxNode,
    formal: &str,
    resolver: &Resolver<'_>,
) -> Option<(TokenKind, u32)> {
    let Resolver::Group { instances, .. } = resolver else {
        return None;
    };
    let instance = actual.ancestors().find_map(ast::Instance::cast)?;
    let name = instance.name()?.text();
    let interface = instances.get(&index::key(&name)).copied().flatten()?;
    match interface.var(formal) {
        Some(var) => Some(interface_var_class(var.section, var.msg)),
        None => lang::predefined(formal)
            .filter(|p| p.section.is_formal())
            .map(predefined_class),
    }
}

fn interface_var_class(section: Section, msg: Option<MsgDir>) -> (TokenKind, u32) {
    variable_class(section, msg.map(|m| m == MsgDir::Incoming))
}

/// The kind and direction of a declared variable; `msg` is `Some(true)` for `msg in`.
fn variable_class(section: Section, msg: Option<bool>) -> (TokenKind, u32) {
    let input = TokenModifier::Input.bit();
    let output = TokenModifier::Output.bit();
    match (msg, section) {
        (Some(true), _) => (TokenKind::Message, input),
        (Some(false), _) => (TokenKind::Message, output),
        (None, Section::In) => (TokenKind::Parameter, input),
        (None, Section::Out) => (TokenKind::Parameter, output),
        (None, Section::InOut) => (TokenKind::Parameter, input | output),
        (None, Section::Stat) => (TokenKind::Variable, 0),
    }
}

fn predefined_class(predefined: &Predefined) -> (TokenKind, u32) {
    let mut modifiers = match predefined.section {
        Section::In => TokenModifier::Input.bit(),
        Section::Out => TokenModifier::Output.bit(),
        Section::InOut => TokenModifier::Input.bit() | TokenModifier::Output.bit(),
        Section::Stat => 0,
    };
    if !predefined.writable {
        modifiers |= TokenModifier::Readonly.bit();
    }
    (TokenKind::PredefinedVariable, modifiers)
}

#[cfg(test)]
mod tests {
    use std::fmt::Write;

    use higraph_syntax::{TextRange, TextSize};

    use super::{SemanticToken, TOKEN_KINDS, TOKEN_MODIFIERS, TokenKind};
    use crate::ide::fixture;

    /// One line per token: the text, the kind and the modifiers.
    fn render(text: &str, tokens: &[SemanticToken]) -> String {
        let mut out = String::new();
        for token in tokens {
            let slice = text
                .get(std::ops::Range::<usize>::from(token.range))
                .unwrap_or("?");
            let modifiers: Vec<&str> = TOKEN_MODIFIERS
                .iter()
                .enumerate()
                .filter(|(i, _)| token.modifiers & (1 << i) != 0)
                .map(|(_, m)| *m)
                .collect();
            let _ = writeln!(out, "{slice:<14} {:?} {}", token.kind, modifiers.join(" "));
        }
        out
    }

    /// The tokens of `main.higraph` (or the cursor's file) of a fixture, rendered.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let path = f.position.path.clone();
        let tokens = f
            .host
            .analysis()
            .semantic_tokens(&path, None)
            .unwrap_or_default();
        assert_well_formed(f.text(&path), &tokens);
        render(f.text(&path), &tokens)
    }

    fn assert_well_formed(text: &str, tokens: &[SemanticToken]) {
        for pair in tokens.windows(2) {
            assert!(
                pair[0].range.end() <= pair[1].range.start(),
                "overlap: {pair:?}"
            );
        }
        for token in tokens {
            let slice = text
                .get(std::ops::Range::<usize>::from(token.range))
                .unwrap_or("");
            assert!(!slice.is_empty(), "empty token {token:?}");
            assert!(!slice.contains(['\n', '\r']), "multi-line token {token:?}");
            assert!(
                token.modifiers < 1 << TOKEN_MODIFIERS.len(),
                "unknown modifier {token:?}"
            );
        }
    }

    #[test]
    fn legend_covers_every_kind() {
        use TokenKind::*;
        for kind in [
            Keyword,
            Opcode,
            Operator,
            Label,
            Parameter,
            Variable,
            PredefinedVariable,
            Symbol,
            Message,
            State,
            Step,
            Transition,
            Address,
            Constant,
            String,
            Comment,
            Type,
            Item,
            Instance,
            Sequencer,
        ] {
            assert!((kind.legend_index() as usize) < TOKEN_KINDS.len());
        }
        assert_eq!(Parameter.lsp_type(), "parameter");
        assert_eq!(Symbol.lsp_type(), "variable");
        assert_eq!(State.lsp_type(), "enumMember");
    }

    #[test]
    fn graph_names_are_coloured_by_what_they_resolve_to() {
        insta::assert_snapshot!(check(
            r#"graph G "valve" <
  in < Oben : BOOL; Dauer : TIME; >
  out < Auf : BOOL; >
  in_out < IM : BOOL msg in; OM : BOOL msg out; Z : INT; >
  stat < N : INT := 5; >
  activate CurrentState;
  state 1 "Auf" < E: S OM; C: U Oben; = Auf; L CurrentState; T MW 10; X: U #Z; supervise Dauer; >
  trans any->1 prio 1 < U INIT_SD; U "Taste"; U MW10; U Unbekannt; >
>
symbols < Taste : E 0.0 BOOL "button"; >
"#
        ), @r#"
        graph          Keyword 
        G              Item declaration
        "valve"        String 
        in             Keyword 
        Oben           Parameter declaration input
        BOOL           Type defaultLibrary
        Dauer          Parameter declaration input
        TIME           Type defaultLibrary
        out            Keyword 
        Auf            Parameter declaration output
        BOOL           Type defaultLibrary
        in_out         Keyword 
        IM             Message declaration input
        BOOL           Type defaultLibrary
        msg            Keyword 
        in             Keyword 
        OM             Message declaration output
        BOOL           Type defaultLibrary
        msg            Keyword 
        out            Keyword 
        Z              Parameter declaration input output
        INT            Type defaultLibrary
        stat           Keyword 
        N              Variable declaration
        INT            Type defaultLibrary
        5              Constant 
        activate       Keyword 
        CurrentState   PredefinedVariable readonly defaultLibrary
        state          Keyword 
        1              State declaration
        "Auf"          String 
        E:             Label 
        S              Opcode 
        OM             Message output
        C:             Label 
        U              Opcode 
        Oben           Parameter input
        =              Opcode 
        Auf            Parameter output
        L              Opcode 
        CurrentState   PredefinedVariable readonly defaultLibrary
        T              Opcode 
        MW 10          Address 
        X:             Label 
        U              Opcode 
        #Z             Parameter input output
        supervise      Keyword 
        Dauer          Parameter input
        trans          Keyword 
        any            Keyword 
        1              State 
        prio           Keyword 
        1              Constant 
        U              Opcode 
        INIT_SD        PredefinedVariable defaultLibrary
        U              Opcode 
        "Taste"        Symbol static
        U              Opcode 
        MW10           Address 
        U              Opcode 
        symbols        Keyword 
        Taste          Symbol declaration static
        E 0.0          Address 
        BOOL           Type defaultLibrary
        "button"       String
        "#);
    }

    #[test]
    fn tests_highlight_keywords_names_and_paths() {
        insta::assert_snapshot!(check(
            r#"test Lauf "run it" <
  cycle T#10MS;
  run Linie, Unbekannt;
  set Taste := TRUE;
  set "Taste" := not E 0.1;
  step 2;
  expect Linie.Inst.state = 1 and Tank.state = Ready "home";
  until Tank.S.A.X within T#1S;
  command Tank start;
  confirm Tank.A;
  restart warm;
>
group Linie < >
chart Tank < >
symbols < Taste : E 0.0 BOOL; >
"#
        ), @r#"
        test           Keyword 
        Lauf           Item declaration
        "run it"       String 
        cycle          Keyword 
        T#10MS         Constant 
        run            Keyword 
        Linie          Item 
        set            Keyword 
        Taste          Symbol static
        TRUE           Constant 
        set            Keyword 
        "Taste"        Symbol static
        not            Operator 
        E 0.1          Address 
        step           Keyword 
        2              Constant 
        expect         Keyword 
        Linie          Item 
        state          PredefinedVariable readonly defaultLibrary
        =              Operator 
        1              Constant 
        and            Operator 
        Tank           Item 
        state          PredefinedVariable readonly defaultLibrary
        =              Operator 
        Ready          State 
        "home"         String 
        until          Keyword 
        Tank           Item 
        X              PredefinedVariable readonly defaultLibrary
        within         Keyword 
        T#1S           Constant 
        command        Keyword 
        Tank           Item 
        start          Keyword 
        confirm        Keyword 
        Tank           Item 
        restart        Keyword 
        warm           Keyword 
        group          Keyword 
        Linie          Item declaration
        chart          Keyword 
        Tank           Item declaration
        symbols        Keyword 
        Taste          Symbol declaration static
        E 0.0          Address 
        BOOL           Type defaultLibrary
        "#);
    }

    #[test]
    fn chart_paths_resolve_like_the_chart_rules() {
        insta::assert_snapshot!(check(
            r#"chart Mixer <
  in < Freigabe : BOOL; >
  out < Ruehrer : BOOL; >
  mode auto;
  sequencer Haupt prio 1 <
    start < Freigabe and not Taste; >
    step Start < init < Ruehrer := Stand > 10.0; > L Ruehrer, T#5S; N MW 4; >
    trans T1 "full" < SFC.Haupt; Anderer.X; Unbekannt; >
    jump J1 -> Start < Stand <> 2; >
  >
>
symbols < Taste : E 0.0 BOOL; Stand : EW 2 INT; >
"#
        ), @r#"
        chart          Keyword 
        Mixer          Item declaration
        in             Keyword 
        Freigabe       Parameter declaration input
        BOOL           Type defaultLibrary
        out            Keyword 
        Ruehrer        Parameter declaration output
        BOOL           Type defaultLibrary
        mode           Keyword 
        auto           Keyword 
        sequencer      Keyword 
        Haupt          Sequencer declaration
        prio           Keyword 
        1              Constant 
        start          Keyword 
        Freigabe       Parameter input
        and            Operator 
        not            Operator 
        Taste          Symbol static
        step           Keyword 
        Start          Step declaration
        init           Keyword 
        Ruehrer        Parameter output
        Stand          Symbol static
        >              Operator 
        10.0           Constant 
        L              Opcode 
        Ruehrer        Parameter output
        T#5S           Constant 
        N              Opcode 
        MW 4           Address 
        trans          Keyword 
        T1             Transition declaration
        "full"         String 
        SFC            PredefinedVariable defaultLibrary
        Haupt          PredefinedVariable defaultLibrary
        jump           Keyword 
        J1             Transition declaration
        Start          Step 
        Stand          Symbol static
        <>             Operator 
        2              Constant 
        symbols        Keyword 
        Taste          Symbol declaration static
        E 0.0          Address 
        BOOL           Type defaultLibrary
        Stand          Symbol declaration static
        EW 2           Address 
        INT            Type defaultLibrary
        "#);
    }

    #[test]
    fn group_actuals_and_messages_resolve_through_the_instances() {
        insta::assert_snapshot!(check(
            r#"//- group.higraph
group Anlage fc GG_Anlage db DB 1 <
  option cyclic_rlo0;
  instance V : Ventil "valve" <
    Oben := Taste; Auf := A 4.0; Zeit := T#5S; ManualMode := MW10;
    OM := S.IM; IM := V.OM; Fehlt := V.Nichts;
  >
  instance S : Ventil < >
>
symbols < Taste : E 0.0 BOOL; GG_Anlage : FC 1; >
//- ventil.higraph
graph Ventil <
  in < Oben : BOOL; Zeit : TIME; >
  out < Auf : BOOL; >
  in_out < IM : BOOL msg in; OM : BOOL msg out; >
>
"#
        ), @r#"
        group          Keyword 
        Anlage         Item declaration
        fc             Keyword 
        GG_Anlage      Symbol static
        db             Keyword 
        DB 1           Address 
        option         Keyword 
        cyclic_rlo0    Keyword 
        instance       Keyword 
        V              Instance declaration
        Ventil         Item 
        "valve"        String 
        Oben           Parameter input
        Taste          Symbol static
        Auf            Parameter output
        A 4.0          Address 
        Zeit           Parameter input
        T#5S           Constant 
        ManualMode     PredefinedVariable defaultLibrary input
        MW10           Address 
        OM             Message output
        S              Instance 
        IM             Message input
        IM             Message input
        V              Instance 
        OM             Message output
        V              Instance 
        instance       Keyword 
        S              Instance declaration
        Ventil         Item 
        symbols        Keyword 
        Taste          Symbol declaration static
        E 0.0          Address 
        BOOL           Type defaultLibrary
        GG_Anlage      Symbol declaration static
        FC 1           Address
        "#);
    }

    #[test]
    fn calls_and_block_interfaces() {
        insta::assert_snapshot!(check(
            r#"graph G <
  state 0 < C: CALL FC 10 (P := TRUE, Q := 'x'); CALL "Dosieren"; >
>
block FC 10 < in < P : BOOL; Q : CHAR; > >
symbols < Dosieren : FC 11; >
"#
        ), @r#"
        graph          Keyword 
        G              Item declaration
        state          Keyword 
        0              State declaration
        C:             Label 
        CALL           Opcode 
        FC 10          Address 
        P              Parameter 
        TRUE           Constant 
        Q              Parameter 
        'x'            String 
        CALL           Opcode 
        "Dosieren"     Symbol static
        block          Keyword 
        FC 10          Address 
        in             Keyword 
        P              Parameter declaration input
        BOOL           Type defaultLibrary
        Q              Parameter declaration input
        CHAR           Type defaultLibrary
        symbols        Keyword 
        Dosieren       Symbol declaration static
        FC 11          Address
        "#);
    }

    #[test]
    fn spaced_constructs_are_one_token() {
        insta::assert_snapshot!(check(
            "graph G <\n  state 0 < C: U ( ; ) ; = E  1.0; L -5; > // end\n>\n"
        ), @r#"
        graph          Keyword 
        G              Item declaration
        state          Keyword 
        0              State declaration
        C:             Label 
        U (            Opcode 
        )              Opcode 
        =              Opcode 
        E  1.0         Address 
        L              Opcode 
        -5             Constant 
        // end         Comment
        "#);
    }

    #[test]
    fn a_construct_over_several_lines_is_split_into_its_tokens() {
        let text = "graph G <\n  state 0 // zero\n  < >\n>\n";
        let parse = higraph_syntax::parse(text);
        let Some(state) = parse
            .syntax_node()
            .descendants()
            .find(|n| n.kind() == higraph_syntax::SyntaxKind::STATE)
        else {
            panic!("no state");
        };
        let index = crate::index::GlobalIndex::default();
        let mut highlighter = super::Highlighter {
            range: None,
            index: &index,
            tokens: Vec::new(),
        };
        highlighter.push_node(&state, TokenKind::State, 0);
        assert_well_formed(text, &highlighter.tokens);
        insta::assert_snapshot!(render(text, &highlighter.tokens), @r#"
        state          State 
        0              State 
        // zero        Comment 
        <              State 
        >              State
        "#);
    }

    #[test]
    fn a_range_request_returns_the_overlapping_tokens() {
        let text = "graph G <\n  state 0 < C: U INIT_SD; >\n  trans any->0 < U INIT_SD; >\n>\n";
        let f = fixture::load(text);
        let start = text.find("state").unwrap_or(0);
        let end = text.find("trans").unwrap_or(0);
        let range = TextRange::new(TextSize::from(start as u32), TextSize::from(end as u32));
        let tokens = f
            .host
            .analysis()
            .semantic_tokens("main.higraph", Some(range))
            .unwrap_or_default();
        insta::assert_snapshot!(render(text, &tokens), @r#"
        state          Keyword 
        0              State declaration
        C:             Label 
        U              Opcode 
        INIT_SD        PredefinedVariable defaultLibrary
        "#);
    }

    #[test]
    fn example_files_give_well_formed_tokens() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        let mut checked = 0;
        for dir in std::fs::read_dir(&root).into_iter().flatten().flatten() {
            let mut data = crate::WorkspaceData::default();
            let mut texts = Vec::new();
            for entry in walk(&dir.path()) {
                if entry.extension().is_some_and(|e| e == "higraph") {
                    let Ok(text) = std::fs::read_to_string(&entry) else {
                        continue;
                    };
                    let path = entry.display().to_string();
                    data.files
                        .push((path.clone(), crate::FileContents::Text(text.clone())));
                    texts.push((path, text));
                }
            }
            let mut host = crate::AnalysisHost::new();
            host.load(data);
            let analysis = host.analysis();
            for (path, text) in &texts {
                let tokens = analysis.semantic_tokens(path, None).unwrap_or_default();
                assert_well_formed(text, &tokens);
                assert!(!tokens.is_empty(), "{path}");
                checked += 1;
            }
        }
        assert!(checked >= 5, "only {checked} example files");
    }

    fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        let mut out = Vec::new();
        for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                out.extend(walk(&path));
            } else {
                out.push(path);
            }
        }
        out.sort();
        out
    }

    #[test]
    fn iec_charts_highlight_statements_members_and_actions() {
        let text = "chart Ampel <
  profile iec;
  stat < Uhr : TON; Teile : INT; >
  action Zaehlen < Teile := -Teile MOD 3; >
  sequencer Haupt <
    step Rot < P1 Zaehlen; run < IF Rot.X THEN Uhr(IN := TRUE, Q => Teile); END_IF; > >
    trans W < Uhr.Q; >
    step Gruen < >
  >
>
";
        let out = check(text);
        for expected in [
            "Zaehlen        Opcode declaration",
            "-              Operator",
            "MOD            Operator",
            "Zaehlen        Opcode \n",
            "IF             Keyword",
            "THEN           Keyword",
            "END_IF         Keyword",
            "Rot            Step \n",
            "X              PredefinedVariable readonly defaultLibrary",
            "Uhr            Variable \n",
            "IN             Parameter input",
            "Q              Parameter output",
            "TON            Type defaultLibrary",
        ] {
            assert!(out.contains(expected), "{expected:?} missing in\n{out}");
        }
    }
}
