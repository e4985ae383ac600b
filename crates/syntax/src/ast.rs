//! Typed accessors over the syntax tree, in the style of rust-analyzer's `ast` module.
//!
//! Each node kind gets a small wrapper struct (`Graph`, `State`, `Trans`, ...) that can be
//! cast from a [`SyntaxNode`] and offers accessor methods for its parts. Accessors return
//! `Option`s: the tree may be incomplete after a syntax error.

use crate::{SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken};

/// A typed view of a syntax node.
pub trait AstNode: Sized {
    fn can_cast(kind: SyntaxKind) -> bool;
    fn cast(node: SyntaxNode) -> Option<Self>;
    fn syntax(&self) -> &SyntaxNode;
}

macro_rules! ast_node {
    ($(#[$doc:meta])* $name:ident, $kind:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq, Eq, Hash)]
        pub struct $name {
            pub(crate) syntax: SyntaxNode,
        }

        impl AstNode for $name {
            fn can_cast(kind: SyntaxKind) -> bool {
                kind == $kind
            }
            fn cast(node: SyntaxNode) -> Option<Self> {
                Self::can_cast(node.kind()).then(|| $name { syntax: node })
            }
            fn syntax(&self) -> &SyntaxNode {
                &self.syntax
            }
        }
    };
}

/// The child nodes of `parent` of one kind. Scans the green children (no allocation) and
/// makes a syntax node only for the matches.
fn children_of_kind(parent: &SyntaxNode, kind: SyntaxKind) -> Vec<SyntaxNode> {
    let raw = rowan::SyntaxKind::from(kind);
    let mut offset = parent.text_range().start();
    let mut found = Vec::new();
    for child in parent.green().children() {
        let len = child.text_len();
        if let rowan::NodeOrToken::Node(node) = child
            && node.kind() == raw
            && let Some(rowan::NodeOrToken::Node(syntax)) =
                parent.child_or_token_at_range(rowan::TextRange::at(offset, len))
        {
            found.push(syntax);
        }
        offset += len;
    }
    found
}

fn child<N: AstNode>(parent: &SyntaxNode) -> Option<N> {
    parent.children().find_map(N::cast)
}

fn children<N: AstNode>(parent: &SyntaxNode) -> impl Iterator<Item = N> + use<N> {
    parent.children().filter_map(N::cast)
}

fn token(parent: &SyntaxNode, kind: SyntaxKind) -> Option<SyntaxToken> {
    parent
        .children_with_tokens()
        .filter_map(|e| e.into_token())
        .find(|t| t.kind() == kind)
}

/// One terminal of the grammar as written. Most terminals are one token; a negative `INT`
/// (language.md §1.5) is two: a `-` (MINUS) and a NUMBER token written together, both children
/// of the node that holds the integer (`STATE`, `ENDPOINT`, `PRIO_CLAUSE`, `OPTION`), so the
/// tokens stay as lexed. [`Terminal::text`] and [`Terminal::text_range`] cover the whole
/// terminal: `-1`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Terminal {
    /// The `-` of a negative number.
    minus: Option<SyntaxToken>,
    /// The NUMBER token of a number (after its `-`), or the one token of any other terminal.
    token: SyntaxToken,
    /// The text of a negative number: `-` and the number.
    negative: Option<String>,
}

impl Terminal {
    fn single(token: SyntaxToken) -> Terminal {
        Terminal {
            minus: None,
            token,
            negative: None,
        }
    }

    /// The number `parent` holds directly: its NUMBER token, with the `-` the parser put right
    /// before it (only one written together with the number).
    fn number_in(parent: &SyntaxNode) -> Option<Terminal> {
        let number = token(parent, NUMBER)?;
        let minus = number
            .prev_sibling_or_token()
            .and_then(|e| e.into_token())
            .filter(|t| t.kind() == MINUS);
        let negative = minus
            .as_ref()
            .map(|m| format!("{}{}", m.text(), number.text()));
        Some(Terminal {
            minus,
            token: number,
            negative,
        })
    }

    /// The terminal as written: `4`, `-1`, `any`.
    pub fn text(&self) -> &str {
        self.negative.as_deref().unwrap_or(self.token.text())
    }

    /// The whole terminal, a negative number's `-` included.
    pub fn text_range(&self) -> rowan::TextRange {
        let end = self.token.text_range();
        match &self.minus {
            Some(minus) => rowan::TextRange::new(minus.text_range().start(), end.end()),
            None => end,
        }
    }

    /// The kind of [`Terminal::token`]: `NUMBER` for a number (negative or not), else the
    /// token's kind.
    pub fn kind(&self) -> SyntaxKind {
        self.token.kind()
    }

    /// Is it a number written with a `-`?
    pub fn is_negative(&self) -> bool {
        self.minus.is_some()
    }

    /// The terminal's main token: a number's NUMBER token (without the `-`), or the one token.
    pub fn token(&self) -> &SyntaxToken {
        &self.token
    }
}

impl std::fmt::Display for Terminal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.text())
    }
}

/// The first significant (non-trivia) token directly inside `parent`.
fn first_token(parent: &SyntaxNode) -> Option<SyntaxToken> {
    parent
        .children_with_tokens()
        .filter_map(|e| e.into_token())
        .find(|t| !t.kind().is_trivia() && t.kind() != LEX_ERROR)
}

/// The text of a STRING token without its quotes.
pub fn unquote(text: &str) -> &str {
    let text = text.strip_prefix('"').unwrap_or(text);
    text.strip_suffix('"').unwrap_or(text)
}

ast_node!(
    /// The root of a file.
    SourceFile, SOURCE_FILE
);
ast_node!(
    /// `mnemonic simatic;`
    Mnemonic, MNEMONIC
);
ast_node!(
    /// `graph NAME ["comment"] < ... >`
    Graph, GRAPH
);
ast_node!(
    /// `< ... >`
    Body, BODY
);
ast_node!(
    /// A declared name.
    Name, NAME
);
ast_node!(
    /// A reference to a name declared elsewhere.
    NameRef, NAME_REF
);
ast_node!(
    /// A display name or comment.
    CommentString, COMMENT_STRING
);
ast_node!(
    /// `in < ... >` etc.
    VarSection, VAR_SECTION
);
ast_node!(
    /// One variable declaration.
    VarDecl, VAR_DECL
);
ast_node!(
    /// `BOOL`, `STRING[20]`.
    TypeRef, TYPE_REF
);
ast_node!(
    /// `msg in` / `msg out`.
    MsgKind, MSG_KIND
);
ast_node!(
    /// `:= constant`.
    InitialValue, INITIAL_VALUE
);
ast_node!(
    /// `activate A, B;`
    Activate, ACTIVATE
);
ast_node!(
    /// `permanent < ... >`
    Permanent, PERMANENT
);
ast_node!(
    /// `state N ...`
    State, STATE
);
ast_node!(
    /// `fault`, `message`, `auto`, `manual`, `waits`.
    Attribute, ATTRIBUTE
);
ast_node!(
    /// `trans A->B ...`
    Trans, TRANS
);
ast_node!(
    /// A transition endpoint.
    Endpoint, ENDPOINT
);
ast_node!(
    /// `prio N`.
    PrioClause, PRIO_CLAUSE
);
ast_node!(
    /// A labelled (or leading unlabelled) run of statements.
    Block, BLOCK
);
ast_node!(
    /// `E:` `C-:` `C:` `X:` `?:` `!:`.
    Label, LABEL
);
ast_node!(
    /// `wait value;`
    WaitItem, WAIT_ITEM
);
ast_node!(
    /// `supervise value;`
    SuperviseItem, SUPERVISE_ITEM
);
ast_node!(
    /// One STL statement.
    StlStmt, STL_STMT
);
ast_node!(
    /// The operation of an STL statement.
    Opcode, OPCODE
);
ast_node!(
    /// `NAME:` jump label (not allowed, HG4003).
    JumpLabel, JUMP_LABEL
);
ast_node!(
    /// An absolute address.
    Address, ADDRESS
);
ast_node!(
    /// `#Name`.
    VarRef, VAR_REF
);
ast_node!(
    /// `"Name"` in operand position.
    SymbolRef, SYMBOL_REF
);
ast_node!(
    /// A constant.
    Literal, LITERAL
);
ast_node!(
    /// `[ ... ]`.
    Indirect, INDIRECT
);
ast_node!(
    /// `==0` and friends.
    StatusOperand, STATUS_OPERAND
);
ast_node!(
    /// CALL / CC arguments.
    CallArgs, CALL_ARGS
);
ast_node!(
    /// A block reference.
    BlockRef, BLOCK_REF
);
ast_node!(
    /// `( P := x, ... )`.
    ParamList, PARAM_LIST
);
ast_node!(
    /// `P := x`.
    Param, PARAM
);
ast_node!(
    /// `group ...`
    Group, GROUP
);
ast_node!(
    /// `fc block_name`.
    FcClause, FC_CLAUSE
);
ast_node!(
    /// `db block_name`.
    DbClause, DB_CLAUSE
);
ast_node!(
    /// `option NAME [N];`
    GroupOption, OPTION
);
ast_node!(
    /// `instance NAME : GRAPH < ... >`
    Instance, INSTANCE
);
ast_node!(
    /// `Formal := value;`
    Actual, ACTUAL
);
ast_node!(
    /// `Inst.Msg`.
    MessageTarget, MESSAGE_TARGET
);
ast_node!(
    /// `symbols < ... >`
    Symbols, SYMBOLS
);
ast_node!(
    /// One symbol.
    Symbol, SYMBOL
);
ast_node!(
    /// `block FC 10 < ... >`
    BlockInterface, BLOCK_INTERFACE
);
ast_node!(
    /// `chart ...`
    Chart, CHART
);
ast_node!(
    /// `mode auto;` etc.
    ChartProp, CHART_PROP
);
ast_node!(
    /// `action NAME ["comment"] < statements >` in a chart.
    ChartAction, CHART_ACTION
);
ast_node!(
    /// `sequencer NAME ...`
    Sequencer, SEQUENCER
);
ast_node!(
    /// `start < ... >`
    StartPart, START_PART
);
ast_node!(
    /// `pre < ... >`
    PrePart, PRE_PART
);
ast_node!(
    /// `post < ... >`
    PostPart, POST_PART
);
ast_node!(
    /// `step NAME ...`
    Step, STEP
);
ast_node!(
    /// `init|run|term < ... >`
    StepPhase, STEP_PHASE
);
ast_node!(
    /// `N Valve;`
    QualifierAction, QUALIFIER_ACTION
);
ast_node!(
    /// `min T#..;` / `max T#..;`
    StepTime, STEP_TIME
);
ast_node!(
    /// `confirm;`
    Confirm, CONFIRM
);
ast_node!(
    /// `trans NAME < ... >` in a sequencer.
    ChartTrans, CHART_TRANS
);
ast_node!(
    /// `parallel < ... >`
    Parallel, PARALLEL
);
ast_node!(
    /// `alt < ... >`
    Alt, ALT
);
ast_node!(
    /// `branch < ... >`
    Branch, BRANCH
);
ast_node!(
    /// `jump NAME -> TARGET < ... >`
    Jump, JUMP
);
ast_node!(
    /// `loop NAME -> TARGET < ... >`
    Loop, LOOP
);
ast_node!(
    /// `expr;`
    Condition, CONDITION
);
ast_node!(
    /// `path := expr;`
    Assignment, ASSIGNMENT
);
ast_node!(
    /// `IF c THEN .. {ELSIF ..} [ELSE ..] END_IF;`
    IfStmt, IF_STMT
);
ast_node!(
    /// `ELSIF c THEN ..` of an `IF`.
    ElsifClause, ELSIF_CLAUSE
);
ast_node!(
    /// `ELSE ..` of an `IF` or a `CASE`.
    ElseClause, ELSE_CLAUSE
);
ast_node!(
    /// `CASE e OF .. [ELSE ..] END_CASE;`
    CaseStmt, CASE_STMT
);
ast_node!(
    /// `1, 3..5: ..` of a `CASE`.
    CaseArm, CASE_ARM
);
ast_node!(
    /// `3`, `-1` or `3..5` of a case arm.
    CaseLabel, CASE_LABEL
);
ast_node!(
    /// `Timer(IN := x, Q => y);`
    FbCall, FB_CALL
);
ast_node!(
    /// `IN := x` or `Q => y` of a call.
    FbArg, FB_ARG
);
ast_node!(
    /// A binary expression.
    BinExpr, BIN_EXPR
);
ast_node!(
    /// `not expr`.
    PrefixExpr, PREFIX_EXPR
);
ast_node!(
    /// `( expr )`.
    ParenExpr, PAREN_EXPR
);
ast_node!(
    /// A chart operand path.
    Path, PATH
);
ast_node!(
    /// `test NAME ["description"] < statements >`
    Test, TEST
);
ast_node!(
    /// `cycle T#10MS;`
    TestCycle, TEST_CYCLE
);
ast_node!(
    /// `run G, C;`
    TestRun, TEST_RUN
);
ast_node!(
    /// `set path := expr;`
    TestSet, TEST_SET
);
ast_node!(
    /// `step;` / `step N;`
    TestStep, TEST_STEP
);
ast_node!(
    /// `wait T#1S;`
    TestWait, TEST_WAIT
);
ast_node!(
    /// `until expr within T#1S ["message"];`
    TestUntil, TEST_UNTIL
);
ast_node!(
    /// `within T#1S` of an `until`.
    WithinClause, WITHIN_CLAUSE
);
ast_node!(
    /// `expect expr ["message"];`
    TestExpect, TEST_EXPECT
);
ast_node!(
    /// `command Chart start;`
    TestCommand, TEST_COMMAND
);
ast_node!(
    /// `confirm Chart.Step;`
    TestConfirm, TEST_CONFIRM
);
ast_node!(
    /// `restart cold;` / `restart warm;`
    TestRestart, TEST_RESTART
);
ast_node!(
    /// A path in a test: an address, or `NAME`/`"symbol"` followed by `.NAME` segments.
    TestPath, TEST_PATH
);

// ---------------------------------------------------------------------------- enums

/// A top-level item.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Item {
    Mnemonic(Mnemonic),
    Graph(Graph),
    Group(Group),
    Chart(Chart),
    Symbols(Symbols),
    BlockInterface(BlockInterface),
    Test(Test),
}

impl Item {
    pub fn cast(node: SyntaxNode) -> Option<Item> {
        Some(match node.kind() {
            MNEMONIC => Item::Mnemonic(Mnemonic { syntax: node }),
            GRAPH => Item::Graph(Graph { syntax: node }),
            GROUP => Item::Group(Group { syntax: node }),
            CHART => Item::Chart(Chart { syntax: node }),
            SYMBOLS => Item::Symbols(Symbols { syntax: node }),
            BLOCK_INTERFACE => Item::BlockInterface(BlockInterface { syntax: node }),
            TEST => Item::Test(Test { syntax: node }),
            _ => return None,
        })
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            Item::Mnemonic(it) => &it.syntax,
            Item::Graph(it) => &it.syntax,
            Item::Group(it) => &it.syntax,
            Item::Chart(it) => &it.syntax,
            Item::Symbols(it) => &it.syntax,
            Item::BlockInterface(it) => &it.syntax,
            Item::Test(it) => &it.syntax,
        }
    }
}

/// An STL operand or a value (time value, actual parameter).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Operand {
    Address(Address),
    VarRef(VarRef),
    NameRef(NameRef),
    SymbolRef(SymbolRef),
    Literal(Literal),
    Indirect(Indirect),
    Status(StatusOperand),
    MessageTarget(MessageTarget),
    Path(Path),
}

impl Operand {
    pub fn cast(node: SyntaxNode) -> Option<Operand> {
        Some(match node.kind() {
            ADDRESS => Operand::Address(Address { syntax: node }),
            VAR_REF => Operand::VarRef(VarRef { syntax: node }),
            NAME_REF => Operand::NameRef(NameRef { syntax: node }),
            SYMBOL_REF => Operand::SymbolRef(SymbolRef { syntax: node }),
            LITERAL => Operand::Literal(Literal { syntax: node }),
            INDIRECT => Operand::Indirect(Indirect { syntax: node }),
            STATUS_OPERAND => Operand::Status(StatusOperand { syntax: node }),
            MESSAGE_TARGET => Operand::MessageTarget(MessageTarget { syntax: node }),
            PATH => Operand::Path(Path { syntax: node }),
            _ => return None,
        })
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            Operand::Address(it) => &it.syntax,
            Operand::VarRef(it) => &it.syntax,
            Operand::NameRef(it) => &it.syntax,
            Operand::SymbolRef(it) => &it.syntax,
            Operand::Literal(it) => &it.syntax,
            Operand::Indirect(it) => &it.syntax,
            Operand::Status(it) => &it.syntax,
            Operand::MessageTarget(it) => &it.syntax,
            Operand::Path(it) => &it.syntax,
        }
    }
}

/// A member of a graph body.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum GraphMember {
    VarSection(VarSection),
    Activate(Activate),
    Permanent(Permanent),
    State(State),
    Trans(Trans),
}

/// An item of an instruction body (state, transition, permanent).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum BodyItem {
    Block(Block),
    Wait(WaitItem),
    Supervise(SuperviseItem),
}

/// An element of a sequencer or branch.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum SeqElement {
    Step(Step),
    Trans(ChartTrans),
    Parallel(Parallel),
    Alt(Alt),
    Jump(Jump),
    Loop(Loop),
}

impl SeqElement {
    pub fn cast(node: SyntaxNode) -> Option<SeqElement> {
        Some(match node.kind() {
            STEP => SeqElement::Step(Step { syntax: node }),
            CHART_TRANS => SeqElement::Trans(ChartTrans { syntax: node }),
            PARALLEL => SeqElement::Parallel(Parallel { syntax: node }),
            ALT => SeqElement::Alt(Alt { syntax: node }),
            JUMP => SeqElement::Jump(Jump { syntax: node }),
            LOOP => SeqElement::Loop(Loop { syntax: node }),
            _ => return None,
        })
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            SeqElement::Step(it) => &it.syntax,
            SeqElement::Trans(it) => &it.syntax,
            SeqElement::Parallel(it) => &it.syntax,
            SeqElement::Alt(it) => &it.syntax,
            SeqElement::Jump(it) => &it.syntax,
            SeqElement::Loop(it) => &it.syntax,
        }
    }
}

/// A chart or test expression (a test's operands are [`TestPath`]s, a chart's [`Path`]s).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Expr {
    Bin(BinExpr),
    Prefix(PrefixExpr),
    Paren(ParenExpr),
    Path(Path),
    Literal(Literal),
    TestPath(TestPath),
}

impl Expr {
    /// Is `kind` the kind of an expression node?
    pub fn can_cast(kind: SyntaxKind) -> bool {
        matches!(
            kind,
            BIN_EXPR | PREFIX_EXPR | PAREN_EXPR | PATH | LITERAL | TEST_PATH
        )
    }

    pub fn cast(node: SyntaxNode) -> Option<Expr> {
        Some(match node.kind() {
            BIN_EXPR => Expr::Bin(BinExpr { syntax: node }),
            PREFIX_EXPR => Expr::Prefix(PrefixExpr { syntax: node }),
            PAREN_EXPR => Expr::Paren(ParenExpr { syntax: node }),
            PATH => Expr::Path(Path { syntax: node }),
            LITERAL => Expr::Literal(Literal { syntax: node }),
            TEST_PATH => Expr::TestPath(TestPath { syntax: node }),
            _ => return None,
        })
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            Expr::Bin(it) => &it.syntax,
            Expr::Prefix(it) => &it.syntax,
            Expr::Paren(it) => &it.syntax,
            Expr::Path(it) => &it.syntax,
            Expr::Literal(it) => &it.syntax,
            Expr::TestPath(it) => &it.syntax,
        }
    }
}

/// A statement of a chart (step phases, `pre`, `post`, action bodies, and nested in `IF` and
/// `CASE`).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Stmt {
    Assignment(Assignment),
    If(IfStmt),
    Case(CaseStmt),
    Call(FbCall),
}

impl Stmt {
    /// Is `kind` the kind of a statement node?
    pub fn can_cast(kind: SyntaxKind) -> bool {
        matches!(kind, ASSIGNMENT | IF_STMT | CASE_STMT | FB_CALL)
    }

    pub fn cast(node: SyntaxNode) -> Option<Stmt> {
        Some(match node.kind() {
            ASSIGNMENT => Stmt::Assignment(Assignment { syntax: node }),
            IF_STMT => Stmt::If(IfStmt { syntax: node }),
            CASE_STMT => Stmt::Case(CaseStmt { syntax: node }),
            FB_CALL => Stmt::Call(FbCall { syntax: node }),
            _ => return None,
        })
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            Stmt::Assignment(it) => &it.syntax,
            Stmt::If(it) => &it.syntax,
            Stmt::Case(it) => &it.syntax,
            Stmt::Call(it) => &it.syntax,
        }
    }
}

/// The statements directly inside `parent`.
fn stmts(parent: &SyntaxNode) -> impl Iterator<Item = Stmt> + use<> {
    parent.children().filter_map(Stmt::cast)
}

/// The operator of a [`BinExpr`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BinOp {
    Or,
    Xor,
    And,
    Eq,
    Ne,
    Lt,
    Gt,
    Le,
    Ge,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
}

impl BinOp {
    /// The operator as the formatter writes it: `or`, `<>`, `+`, `MOD`.
    pub fn text(self) -> &'static str {
        match self {
            BinOp::Or => "or",
            BinOp::Xor => "xor",
            BinOp::And => "and",
            BinOp::Eq => "=",
            BinOp::Ne => "<>",
            BinOp::Lt => "<",
            BinOp::Gt => ">",
            BinOp::Le => "<=",
            BinOp::Ge => ">=",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "MOD",
        }
    }

    /// Is it `+ - * / MOD`?
    pub fn is_arithmetic(self) -> bool {
        matches!(
            self,
            BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Mod
        )
    }

    /// Is it a comparison?
    pub fn is_comparison(self) -> bool {
        matches!(
            self,
            BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Gt | BinOp::Le | BinOp::Ge
        )
    }
}

/// The operator of a [`PrefixExpr`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PrefixOp {
    /// `not`
    Not,
    /// unary `-`
    Neg,
}

/// A statement of a test body.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum TestStmt {
    Cycle(TestCycle),
    Run(TestRun),
    Set(TestSet),
    Step(TestStep),
    Wait(TestWait),
    Until(TestUntil),
    Expect(TestExpect),
    Command(TestCommand),
    Confirm(TestConfirm),
    Restart(TestRestart),
}

impl TestStmt {
    pub fn cast(node: SyntaxNode) -> Option<TestStmt> {
        Some(match node.kind() {
            TEST_CYCLE => TestStmt::Cycle(TestCycle { syntax: node }),
            TEST_RUN => TestStmt::Run(TestRun { syntax: node }),
            TEST_SET => TestStmt::Set(TestSet { syntax: node }),
            TEST_STEP => TestStmt::Step(TestStep { syntax: node }),
            TEST_WAIT => TestStmt::Wait(TestWait { syntax: node }),
            TEST_UNTIL => TestStmt::Until(TestUntil { syntax: node }),
            TEST_EXPECT => TestStmt::Expect(TestExpect { syntax: node }),
            TEST_COMMAND => TestStmt::Command(TestCommand { syntax: node }),
            TEST_CONFIRM => TestStmt::Confirm(TestConfirm { syntax: node }),
            TEST_RESTART => TestStmt::Restart(TestRestart { syntax: node }),
            _ => return None,
        })
    }

    pub fn syntax(&self) -> &SyntaxNode {
        match self {
            TestStmt::Cycle(it) => &it.syntax,
            TestStmt::Run(it) => &it.syntax,
            TestStmt::Set(it) => &it.syntax,
            TestStmt::Step(it) => &it.syntax,
            TestStmt::Wait(it) => &it.syntax,
            TestStmt::Until(it) => &it.syntax,
            TestStmt::Expect(it) => &it.syntax,
            TestStmt::Command(it) => &it.syntax,
            TestStmt::Confirm(it) => &it.syntax,
            TestStmt::Restart(it) => &it.syntax,
        }
    }

    /// The statement's keyword in lower case (`cycle`, `run`, ...).
    pub fn keyword(&self) -> &'static str {
        match self {
            TestStmt::Cycle(_) => "cycle",
            TestStmt::Run(_) => "run",
            TestStmt::Set(_) => "set",
            TestStmt::Step(_) => "step",
            TestStmt::Wait(_) => "wait",
            TestStmt::Until(_) => "until",
            TestStmt::Expect(_) => "expect",
            TestStmt::Command(_) => "command",
            TestStmt::Confirm(_) => "confirm",
            TestStmt::Restart(_) => "restart",
        }
    }
}

// ---------------------------------------------------------------------------- accessors

impl SourceFile {
    pub fn items(&self) -> impl Iterator<Item = Item> + use<> {
        self.syntax.children().filter_map(Item::cast)
    }
}

impl Mnemonic {
    /// `simatic` or `international` as written.
    pub fn set(&self) -> Option<SyntaxToken> {
        token(&self.syntax, SIMATIC_KW).or_else(|| token(&self.syntax, INTERNATIONAL_KW))
    }
}

impl Name {
    /// The IDENT, NUMBER or STRING token.
    pub fn token(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
    /// The name's text (without quotes for a quoted symbol).
    pub fn text(&self) -> String {
        self.token()
            .map(|t| unquote(t.text()).to_owned())
            .unwrap_or_default()
    }
}

impl NameRef {
    pub fn token(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
    pub fn text(&self) -> String {
        self.token()
            .map(|t| t.text().to_owned())
            .unwrap_or_default()
    }
}

impl CommentString {
    pub fn token(&self) -> Option<SyntaxToken> {
        token(&self.syntax, STRING)
    }
    /// The text between the quotes.
    pub fn value(&self) -> String {
        self.token()
            .map(|t| unquote(t.text()).to_owned())
            .unwrap_or_default()
    }
}

impl Body {
    pub fn l_angle(&self) -> Option<SyntaxToken> {
        token(&self.syntax, L_ANGLE)
    }
    pub fn r_angle(&self) -> Option<SyntaxToken> {
        token(&self.syntax, R_ANGLE)
    }
    /// Items of an instruction body.
    pub fn body_items(&self) -> impl Iterator<Item = BodyItem> + use<> {
        self.syntax.children().filter_map(|n| match n.kind() {
            BLOCK => Some(BodyItem::Block(Block { syntax: n })),
            WAIT_ITEM => Some(BodyItem::Wait(WaitItem { syntax: n })),
            SUPERVISE_ITEM => Some(BodyItem::Supervise(SuperviseItem { syntax: n })),
            _ => None,
        })
    }
    pub fn blocks(&self) -> impl Iterator<Item = Block> + use<> {
        children(&self.syntax)
    }
}

impl Graph {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    pub fn members(&self) -> impl Iterator<Item = GraphMember> + use<> {
        self.body().into_iter().flat_map(|b| {
            b.syntax.children().filter_map(|n| match n.kind() {
                VAR_SECTION => Some(GraphMember::VarSection(VarSection { syntax: n })),
                ACTIVATE => Some(GraphMember::Activate(Activate { syntax: n })),
                PERMANENT => Some(GraphMember::Permanent(Permanent { syntax: n })),
                STATE => Some(GraphMember::State(State { syntax: n })),
                TRANS => Some(GraphMember::Trans(Trans { syntax: n })),
                _ => None,
            })
        })
    }
    /// The variable sections. Found through the green tree, so a graph with thousands of
    /// states and transitions does not pay for a syntax node per member.
    pub fn var_sections(&self) -> impl Iterator<Item = VarSection> + use<> {
        self.body()
            .into_iter()
            .flat_map(|b| children_of_kind(&b.syntax, VAR_SECTION))
            .map(|syntax| VarSection { syntax })
    }
    /// The `activate` statements (found like [`Graph::var_sections`]).
    pub fn activates(&self) -> impl Iterator<Item = Activate> + use<> {
        self.body()
            .into_iter()
            .flat_map(|b| children_of_kind(&b.syntax, ACTIVATE))
            .map(|syntax| Activate { syntax })
    }
    pub fn states(&self) -> impl Iterator<Item = State> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn transitions(&self) -> impl Iterator<Item = Trans> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
}

impl VarSection {
    /// `IN_KW`, `OUT_KW`, `IN_OUT_KW` or `STAT_KW`.
    pub fn keyword(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
    pub fn decls(&self) -> impl Iterator<Item = VarDecl> + use<> {
        children(&self.syntax)
    }
}

impl VarDecl {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    pub fn ty(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn msg_kind(&self) -> Option<MsgKind> {
        child(&self.syntax)
    }
    pub fn initial_value(&self) -> Option<InitialValue> {
        child(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
}

impl TypeRef {
    /// The type name token.
    pub fn name(&self) -> Option<SyntaxToken> {
        token(&self.syntax, IDENT)
    }
    /// The length of `STRING[n]`.
    pub fn length(&self) -> Option<SyntaxToken> {
        token(&self.syntax, NUMBER)
    }
}

impl MsgKind {
    /// `true` for `msg in`, `false` for `msg out`.
    pub fn is_incoming(&self) -> bool {
        token(&self.syntax, IN_KW).is_some()
    }
}

impl InitialValue {
    pub fn literal(&self) -> Option<Literal> {
        child(&self.syntax)
    }
}

impl Activate {
    pub fn names(&self) -> impl Iterator<Item = NameRef> + use<> {
        children(&self.syntax)
    }
}

impl Permanent {
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
}

impl State {
    /// The state number as written (`4`, or `-1`, which the analysis reports).
    pub fn number(&self) -> Option<Terminal> {
        Terminal::number_in(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn attributes(&self) -> impl Iterator<Item = Attribute> + use<> {
        children(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
}

impl Attribute {
    pub fn keyword(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
}

impl Trans {
    pub fn source(&self) -> Option<Endpoint> {
        child(&self.syntax)
    }
    pub fn target(&self) -> Option<Endpoint> {
        children(&self.syntax).nth(1)
    }
    pub fn prio(&self) -> Option<PrioClause> {
        child(&self.syntax)
    }
    pub fn attributes(&self) -> impl Iterator<Item = Attribute> + use<> {
        children(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
}

/// What a transition endpoint names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EndpointKind {
    State,
    Any,
    Return,
}

impl Endpoint {
    /// The endpoint as written: a state number (`4`, `-1`), `any` or `return`.
    pub fn token(&self) -> Option<Terminal> {
        Terminal::number_in(&self.syntax)
            .or_else(|| first_token(&self.syntax).map(Terminal::single))
    }
    pub fn kind(&self) -> Option<EndpointKind> {
        Some(match self.token()?.kind() {
            ANY_KW => EndpointKind::Any,
            RETURN_KW => EndpointKind::Return,
            _ => EndpointKind::State,
        })
    }
}

impl PrioClause {
    /// The priority as written (`2`, or `-1`, which the analysis reports).
    pub fn value(&self) -> Option<Terminal> {
        Terminal::number_in(&self.syntax)
    }
}

impl Block {
    pub fn label(&self) -> Option<Label> {
        child(&self.syntax)
    }
    pub fn statements(&self) -> impl Iterator<Item = StlStmt> + use<> {
        children(&self.syntax)
    }
}

impl Label {
    /// The label as written without its colon, upper-cased: `E`, `C-`, `C`, `X`, `?`, `!`.
    pub fn name(&self) -> String {
        let text = self.syntax.text().to_string();
        text.trim_end_matches(':').to_ascii_uppercase()
    }
}

impl WaitItem {
    pub fn value(&self) -> Option<Operand> {
        self.syntax.children().find_map(Operand::cast)
    }
}

impl SuperviseItem {
    pub fn value(&self) -> Option<Operand> {
        self.syntax.children().find_map(Operand::cast)
    }
}

impl StlStmt {
    pub fn jump_label(&self) -> Option<JumpLabel> {
        child(&self.syntax)
    }
    pub fn opcode(&self) -> Option<Opcode> {
        child(&self.syntax)
    }
    pub fn operand(&self) -> Option<Operand> {
        self.syntax.children().find_map(Operand::cast)
    }
    pub fn call_args(&self) -> Option<CallArgs> {
        child(&self.syntax)
    }
    pub fn semicolon(&self) -> Option<SyntaxToken> {
        token(&self.syntax, SEMI)
    }
}

impl Opcode {
    /// The operation as written with white space removed (`U(` for `U (`), upper-cased.
    pub fn text(&self) -> String {
        let mut text = String::new();
        for t in self
            .syntax
            .children_with_tokens()
            .filter_map(|e| e.into_token())
        {
            if !t.kind().is_trivia() {
                text.push_str(t.text());
            }
        }
        text.to_ascii_uppercase()
    }
}

impl Address {
    /// The address as written with white space removed (`E1.0` for `E 1.0`).
    pub fn compact_text(&self) -> String {
        let mut text = String::new();
        for t in self
            .syntax
            .children_with_tokens()
            .filter_map(|e| e.into_token())
        {
            if !t.kind().is_trivia() {
                text.push_str(t.text());
            }
        }
        text
    }
}

impl VarRef {
    pub fn name(&self) -> Option<SyntaxToken> {
        token(&self.syntax, IDENT)
    }
}

impl SymbolRef {
    pub fn token(&self) -> Option<SyntaxToken> {
        token(&self.syntax, STRING)
    }
    pub fn name(&self) -> String {
        self.token()
            .map(|t| unquote(t.text()).to_owned())
            .unwrap_or_default()
    }
}

impl Literal {
    /// The constant's text (a joined `-` included).
    pub fn text(&self) -> String {
        self.syntax.text().to_string()
    }
}

impl CallArgs {
    pub fn blocks(&self) -> impl Iterator<Item = BlockRef> + use<> {
        children(&self.syntax)
    }
    pub fn params(&self) -> impl Iterator<Item = Param> + use<> {
        child::<ParamList>(&self.syntax)
            .into_iter()
            .flat_map(|l| children(&l.syntax))
    }
}

impl BlockRef {
    pub fn address(&self) -> Option<Address> {
        child(&self.syntax)
    }
    pub fn name_ref(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn symbol_ref(&self) -> Option<SymbolRef> {
        child(&self.syntax)
    }
}

impl Param {
    pub fn formal(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn value(&self) -> Option<Operand> {
        self.syntax.children().filter_map(Operand::cast).nth(1)
    }
}

impl Group {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    pub fn fc(&self) -> Option<BlockRef> {
        child::<FcClause>(&self.syntax).and_then(|c| child(&c.syntax))
    }
    pub fn db(&self) -> Option<BlockRef> {
        child::<DbClause>(&self.syntax).and_then(|c| child(&c.syntax))
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    pub fn options(&self) -> impl Iterator<Item = GroupOption> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn instances(&self) -> impl Iterator<Item = Instance> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
}

impl GroupOption {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    /// The value as written (`100`, or `-5`, which the analysis reports).
    pub fn value(&self) -> Option<Terminal> {
        Terminal::number_in(&self.syntax)
    }
}

impl Instance {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    /// The instantiated graph.
    pub fn graph(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    pub fn actuals(&self) -> impl Iterator<Item = Actual> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
}

impl Actual {
    pub fn formal(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn value(&self) -> Option<Operand> {
        self.syntax.children().filter_map(Operand::cast).nth(1)
    }
}

impl MessageTarget {
    pub fn instance(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn message(&self) -> Option<NameRef> {
        children(&self.syntax).nth(1)
    }
}

impl Symbols {
    pub fn symbols(&self) -> impl Iterator<Item = Symbol> + use<> {
        children(&self.syntax)
    }
}

impl Symbol {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    pub fn address(&self) -> Option<Address> {
        child(&self.syntax)
    }
    pub fn ty(&self) -> Option<TypeRef> {
        child(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
}

impl BlockInterface {
    pub fn block(&self) -> Option<BlockRef> {
        child(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn var_sections(&self) -> impl Iterator<Item = VarSection> + use<> {
        children(&self.syntax)
    }
}

impl Chart {
    /// `chart type NAME`?
    pub fn is_type(&self) -> bool {
        token(&self.syntax, TYPE_KW).is_some()
    }
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    pub fn var_sections(&self) -> impl Iterator<Item = VarSection> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn props(&self) -> impl Iterator<Item = ChartProp> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn sequencers(&self) -> impl Iterator<Item = Sequencer> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    /// The `action` members (IEC charts).
    pub fn actions(&self) -> impl Iterator<Item = ChartAction> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    /// The profile the chart follows: the value of its first `profile` property; PCS 7 when
    /// there is none or its value is unknown (docs/iec.md §1).
    pub fn profile(&self) -> Profile {
        self.props()
            .find(|p| p.keyword().is_some_and(|k| k.kind() == PROFILE_KW))
            .and_then(|p| p.value())
            .and_then(|v| v.token())
            .map_or(Profile::Pcs7, |t| {
                if t.text().eq_ignore_ascii_case("iec") {
                    Profile::Iec
                } else {
                    Profile::Pcs7
                }
            })
    }
}

/// The rules a chart follows (`profile pcs7;`, the default, or `profile iec;`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Profile {
    /// The PCS 7 SFC rules.
    #[default]
    Pcs7,
    /// IEC 61131-3 Sequential Function Chart (docs/iec.md).
    Iec,
}

impl ChartProp {
    /// `MODE_KW`, `SWITCHING_KW`, `RUN_KW` or `PROFILE_KW`.
    pub fn keyword(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
    pub fn value(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl Sequencer {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    pub fn prio(&self) -> Option<PrioClause> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    pub fn start(&self) -> Option<StartPart> {
        self.body().and_then(|b| child(&b.syntax))
    }
    pub fn pre(&self) -> Option<PrePart> {
        self.body().and_then(|b| child(&b.syntax))
    }
    pub fn post(&self) -> Option<PostPart> {
        self.body().and_then(|b| child(&b.syntax))
    }
    pub fn elements(&self) -> impl Iterator<Item = SeqElement> + use<> {
        self.body()
            .into_iter()
            .flat_map(|b| b.syntax.children().filter_map(SeqElement::cast))
    }
}

macro_rules! conditions_and_statements {
    ($($name:ident),*) => {$(
        impl $name {
            pub fn body(&self) -> Option<Body> {
                child(&self.syntax)
            }
            pub fn conditions(&self) -> impl Iterator<Item = Condition> + use<> {
                self.body().into_iter().flat_map(|b| children(&b.syntax))
            }
            pub fn assignments(&self) -> impl Iterator<Item = Assignment> + use<> {
                self.body().into_iter().flat_map(|b| children(&b.syntax))
            }
            /// The top-level statements of the body, in order.
            pub fn statements(&self) -> impl Iterator<Item = Stmt> + use<> {
                self.body().into_iter().flat_map(|b| stmts(&b.syntax))
            }
        }
    )*};
}

conditions_and_statements!(
    StartPart,
    PrePart,
    PostPart,
    StepPhase,
    ChartTrans,
    Jump,
    Loop,
    ChartAction
);

macro_rules! named_element {
    ($($name:ident),*) => {$(
        impl $name {
            pub fn name(&self) -> Option<Name> {
                child(&self.syntax)
            }
            pub fn comment(&self) -> Option<CommentString> {
                child(&self.syntax)
            }
        }
    )*};
}

named_element!(Step, ChartTrans, Jump, Loop, ChartAction);

impl IfStmt {
    /// The condition after `IF`.
    pub fn condition(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
    /// The statements after `THEN`, up to the first `ELSIF`, `ELSE` or `END_IF`.
    pub fn then_statements(&self) -> impl Iterator<Item = Stmt> + use<> {
        stmts(&self.syntax)
    }
    pub fn elsifs(&self) -> impl Iterator<Item = ElsifClause> + use<> {
        children(&self.syntax)
    }
    pub fn else_clause(&self) -> Option<ElseClause> {
        child(&self.syntax)
    }
    /// The `END_IF` keyword, if written.
    pub fn end_keyword(&self) -> Option<SyntaxToken> {
        token(&self.syntax, END_IF_KW)
    }
}

impl ElsifClause {
    pub fn condition(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
    pub fn statements(&self) -> impl Iterator<Item = Stmt> + use<> {
        stmts(&self.syntax)
    }
}

impl ElseClause {
    pub fn statements(&self) -> impl Iterator<Item = Stmt> + use<> {
        stmts(&self.syntax)
    }
}

impl CaseStmt {
    /// The expression after `CASE`.
    pub fn selector(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
    pub fn arms(&self) -> impl Iterator<Item = CaseArm> + use<> {
        children(&self.syntax)
    }
    pub fn else_clause(&self) -> Option<ElseClause> {
        child(&self.syntax)
    }
    /// The `END_CASE` keyword, if written.
    pub fn end_keyword(&self) -> Option<SyntaxToken> {
        token(&self.syntax, END_CASE_KW)
    }
}

impl CaseArm {
    pub fn labels(&self) -> impl Iterator<Item = CaseLabel> + use<> {
        children(&self.syntax)
    }
    pub fn statements(&self) -> impl Iterator<Item = Stmt> + use<> {
        stmts(&self.syntax)
    }
}

impl CaseLabel {
    /// The integers of the label, each with its sign: one, or two for a range.
    fn bounds(&self) -> Vec<Option<i64>> {
        let mut bounds = Vec::new();
        let mut negative = false;
        for token in self
            .syntax
            .children_with_tokens()
            .filter_map(|e| e.into_token())
        {
            match token.kind() {
                MINUS => negative = true,
                NUMBER => {
                    let value = token.text().parse::<i64>().ok();
                    bounds.push(if negative {
                        value.and_then(i64::checked_neg)
                    } else {
                        value
                    });
                    negative = false;
                }
                _ => {}
            }
        }
        bounds
    }
    /// The value (or the lower bound of a range); `None` if it is not an integer.
    pub fn low(&self) -> Option<i64> {
        self.bounds().first().copied().flatten()
    }
    /// The upper bound of a range; for a single value, the value itself.
    pub fn high(&self) -> Option<i64> {
        self.bounds()
            .get(1)
            .or(self.bounds().first())
            .copied()
            .flatten()
    }
    /// `low..high`?
    pub fn is_range(&self) -> bool {
        token(&self.syntax, DOT).is_some()
    }
}

impl FbCall {
    /// The function block instance called.
    pub fn callee(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    pub fn args(&self) -> impl Iterator<Item = FbArg> + use<> {
        children(&self.syntax)
    }
}

impl FbArg {
    /// The formal parameter (`IN`, `Q`).
    pub fn formal(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
    /// `Q => target` (an output) rather than `IN := value`?
    pub fn is_output(&self) -> bool {
        self.syntax.children().any(|n| n.kind() == OUTPUT_OP)
    }
    /// The value of an input argument.
    pub fn value(&self) -> Option<Expr> {
        if self.is_output() {
            return None;
        }
        self.syntax.children().find_map(Expr::cast)
    }
    /// The variable an output argument is read into.
    pub fn target(&self) -> Option<Path> {
        if !self.is_output() {
            return None;
        }
        child(&self.syntax)
    }
}

impl Jump {
    pub fn target(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl Loop {
    pub fn target(&self) -> Option<NameRef> {
        child(&self.syntax)
    }
}

impl Step {
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    pub fn phases(&self) -> impl Iterator<Item = StepPhase> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn actions(&self) -> impl Iterator<Item = QualifierAction> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn times(&self) -> impl Iterator<Item = StepTime> + use<> {
        self.body().into_iter().flat_map(|b| children(&b.syntax))
    }
    pub fn confirm(&self) -> Option<Confirm> {
        self.body().and_then(|b| child(&b.syntax))
    }
}

impl StepPhase {
    /// `INIT_KW`, `RUN_KW` or `TERM_KW`.
    pub fn keyword(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
}

impl QualifierAction {
    pub fn qualifier(&self) -> Option<SyntaxToken> {
        self.syntax
            .children()
            .find(|n| n.kind() == QUALIFIER)
            .and_then(|n| first_token(&n))
    }
    /// The operand and, for `L D SD DS SL`, the time value.
    pub fn operands(&self) -> impl Iterator<Item = Operand> + use<> {
        self.syntax.children().filter_map(Operand::cast)
    }
}

impl StepTime {
    /// `MIN_KW` or `MAX_KW`.
    pub fn keyword(&self) -> Option<SyntaxToken> {
        first_token(&self.syntax)
    }
    pub fn value(&self) -> Option<Operand> {
        self.syntax.children().find_map(Operand::cast)
    }
}

impl Parallel {
    pub fn branches(&self) -> impl Iterator<Item = Branch> + use<> {
        child::<Body>(&self.syntax)
            .into_iter()
            .flat_map(|b| children(&b.syntax))
    }
}

impl Alt {
    pub fn branches(&self) -> impl Iterator<Item = Branch> + use<> {
        child::<Body>(&self.syntax)
            .into_iter()
            .flat_map(|b| children(&b.syntax))
    }
}

impl Branch {
    pub fn elements(&self) -> impl Iterator<Item = SeqElement> + use<> {
        child::<Body>(&self.syntax)
            .into_iter()
            .flat_map(|b| b.syntax.children().filter_map(SeqElement::cast))
    }
}

impl Condition {
    pub fn expr(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
}

impl Assignment {
    pub fn target(&self) -> Option<Path> {
        child(&self.syntax)
    }
    pub fn value(&self) -> Option<Expr> {
        self.syntax.children().filter_map(Expr::cast).nth(1)
    }
}

impl BinExpr {
    pub fn lhs(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
    pub fn rhs(&self) -> Option<Expr> {
        self.syntax.children().filter_map(Expr::cast).nth(1)
    }
    /// The operator.
    pub fn op(&self) -> Option<BinOp> {
        self.syntax.children_with_tokens().find_map(|e| match e {
            rowan::NodeOrToken::Node(n) if n.kind() == COMPARE_OP => {
                Some(match n.text().to_string().as_str() {
                    "<>" => BinOp::Ne,
                    "<=" => BinOp::Le,
                    ">=" => BinOp::Ge,
                    _ => return None,
                })
            }
            rowan::NodeOrToken::Token(t) => Some(match t.kind() {
                OR_KW => BinOp::Or,
                XOR_KW => BinOp::Xor,
                AND_KW => BinOp::And,
                EQ => BinOp::Eq,
                L_ANGLE => BinOp::Lt,
                R_ANGLE => BinOp::Gt,
                PLUS => BinOp::Add,
                MINUS => BinOp::Sub,
                STAR => BinOp::Mul,
                SLASH => BinOp::Div,
                MOD_KW => BinOp::Mod,
                _ => return None,
            }),
            _ => None,
        })
    }
    /// The operator as written (`and`, `>=`, `=` ...), lower-cased.
    pub fn op_text(&self) -> Option<String> {
        self.syntax.children_with_tokens().find_map(|e| match e {
            rowan::NodeOrToken::Node(n) if n.kind() == COMPARE_OP => Some(n.text().to_string()),
            rowan::NodeOrToken::Token(t) if !t.kind().is_trivia() && t.kind() != LEX_ERROR => {
                Some(t.text().to_ascii_lowercase())
            }
            _ => None,
        })
    }
}

impl PrefixExpr {
    /// `not` or unary `-`.
    pub fn op(&self) -> Option<PrefixOp> {
        self.syntax
            .children_with_tokens()
            .filter_map(|e| e.into_token())
            .find_map(|t| match t.kind() {
                NOT_KW => Some(PrefixOp::Not),
                MINUS => Some(PrefixOp::Neg),
                _ => None,
            })
    }
    pub fn operand(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
}

impl ParenExpr {
    pub fn expr(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
}

impl Path {
    /// The segments of a dotted path.
    pub fn segments(&self) -> impl Iterator<Item = NameRef> + use<> {
        children(&self.syntax)
    }
    pub fn address(&self) -> Option<Address> {
        child(&self.syntax)
    }
    pub fn symbol(&self) -> Option<SymbolRef> {
        child(&self.syntax)
    }
}

impl Test {
    pub fn name(&self) -> Option<Name> {
        child(&self.syntax)
    }
    /// The description string after the name.
    pub fn comment(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
    pub fn body(&self) -> Option<Body> {
        child(&self.syntax)
    }
    /// The statements in text order.
    pub fn statements(&self) -> impl Iterator<Item = TestStmt> + use<> {
        self.body()
            .into_iter()
            .flat_map(|b| b.syntax.children().filter_map(TestStmt::cast))
    }
}

impl TestCycle {
    /// The cycle time (a `T#` constant).
    pub fn time(&self) -> Option<Literal> {
        child(&self.syntax)
    }
}

impl TestWait {
    /// The time to wait (a `T#` constant).
    pub fn time(&self) -> Option<Literal> {
        child(&self.syntax)
    }
}

impl TestRun {
    /// The groups and charts of the run list, in order.
    pub fn entries(&self) -> impl Iterator<Item = NameRef> + use<> {
        children(&self.syntax)
    }
}

impl TestSet {
    pub fn target(&self) -> Option<TestPath> {
        child(&self.syntax)
    }
    pub fn value(&self) -> Option<Expr> {
        self.syntax.children().filter_map(Expr::cast).nth(1)
    }
}

impl TestStep {
    /// The number of cycles as written (`None` for `step;`, meaning 1).
    pub fn count(&self) -> Option<Terminal> {
        Terminal::number_in(&self.syntax)
    }
}

impl TestUntil {
    pub fn condition(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
    pub fn within(&self) -> Option<WithinClause> {
        child(&self.syntax)
    }
    /// The time limit (the constant of the `within` clause).
    pub fn time(&self) -> Option<Literal> {
        self.within().and_then(|w| child(&w.syntax))
    }
    /// The failure message.
    pub fn message(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
}

impl TestExpect {
    pub fn condition(&self) -> Option<Expr> {
        self.syntax.children().find_map(Expr::cast)
    }
    /// The failure message.
    pub fn message(&self) -> Option<CommentString> {
        child(&self.syntax)
    }
}

impl TestCommand {
    pub fn chart(&self) -> Option<NameRef> {
        children(&self.syntax).next()
    }
    pub fn command(&self) -> Option<NameRef> {
        children(&self.syntax).nth(1)
    }
}

impl TestConfirm {
    pub fn path(&self) -> Option<TestPath> {
        child(&self.syntax)
    }
}

impl TestRestart {
    /// `COLD_KW` or `WARM_KW`.
    pub fn mode(&self) -> Option<SyntaxToken> {
        token(&self.syntax, COLD_KW).or_else(|| token(&self.syntax, WARM_KW))
    }
    /// Is it `restart warm`?
    pub fn is_warm(&self) -> bool {
        token(&self.syntax, WARM_KW).is_some()
    }
}

impl TestPath {
    /// An address path (`E 0.3`, `MW 10`, `DB1.DBX 0.1`).
    pub fn address(&self) -> Option<Address> {
        child(&self.syntax)
    }
    /// A quoted first segment (`"Motor 1".state`).
    pub fn symbol(&self) -> Option<SymbolRef> {
        child(&self.syntax)
    }
    /// The named segments, in order (the quoted first segment not included).
    pub fn segments(&self) -> impl Iterator<Item = NameRef> + use<> {
        children(&self.syntax)
    }
    /// Every segment's text (a quoted first one without its quotes) and range, in order;
    /// empty for an address.
    pub fn segment_texts(&self) -> Vec<(String, rowan::TextRange)> {
        let mut out = Vec::new();
        for node in self.syntax.children() {
            match node.kind() {
                SYMBOL_REF => {
                    let symbol = SymbolRef {
                        syntax: node.clone(),
                    };
                    out.push((symbol.name(), node.text_range()));
                }
                NAME_REF => {
                    let name = NameRef {
                        syntax: node.clone(),
                    };
                    out.push((name.text(), node.text_range()));
                }
                _ => {}
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accessors_reach_the_parts_of_a_graph() {
        let parse = crate::parse(
            "graph G \"g\" < in < a : BOOL msg in; > state 3 \"S\" fault < C: U #a; > \
             trans 3->any prio 2 auto < U a; > >",
        );
        let Some(Item::Graph(graph)) = parse.tree().items().next() else {
            panic!("no graph")
        };
        assert_eq!(graph.name().map(|n| n.text()), Some("G".to_owned()));
        let decl = graph
            .var_sections()
            .next()
            .and_then(|s| s.decls().next())
            .expect("decl");
        assert!(decl.msg_kind().is_some_and(|m| m.is_incoming()));
        let state = graph.states().next().expect("state");
        assert_eq!(
            state.number().map(|t| t.text().to_owned()),
            Some("3".to_owned())
        );
        let block = state.body().and_then(|b| b.blocks().next()).expect("block");
        assert_eq!(block.label().map(|l| l.name()), Some("C".to_owned()));
        let stmt = block.statements().next().expect("stmt");
        assert!(matches!(stmt.operand(), Some(Operand::VarRef(_))));
        let trans = graph.transitions().next().expect("trans");
        assert_eq!(
            trans.target().and_then(|e| e.kind()),
            Some(EndpointKind::Any)
        );
        assert_eq!(
            trans.prio().and_then(|p| p.value()).map(|t| t.to_string()),
            Some("2".into())
        );
    }

    #[test]
    fn a_negative_int_is_one_terminal() {
        let parse = crate::parse(
            "graph G < state -1 < > trans -1->-02 prio -3 < > trans any->4 prio 5 < > > \
             chart C < sequencer S prio -6 < step A < > > > group Gr < option reserve -7; >",
        );
        assert!(parse.errors().is_empty(), "{:?}", parse.errors());
        let items: Vec<_> = parse.tree().items().collect();
        let Item::Graph(graph) = &items[0] else {
            panic!("no graph")
        };
        let text = |t: Option<Terminal>| t.map(|t| (t.text().to_owned(), t.is_negative()));
        let state = graph.states().next().expect("state");
        let number = state.number().expect("number");
        assert_eq!((number.text(), number.kind()), ("-1", NUMBER));
        // The range covers the `-` (`graph G < state ` is 16 bytes).
        assert_eq!(
            number.text_range(),
            rowan::TextRange::new(16.into(), 18.into())
        );
        let transitions: Vec<_> = graph.transitions().collect();
        let (first, second) = (&transitions[0], &transitions[1]);
        assert_eq!(
            text(first.source().and_then(|e| e.token())),
            Some(("-1".into(), true))
        );
        assert_eq!(
            text(first.target().and_then(|e| e.token())),
            Some(("-02".into(), true))
        );
        assert_eq!(
            first.target().and_then(|e| e.kind()),
            Some(EndpointKind::State)
        );
        assert_eq!(
            text(first.prio().and_then(|p| p.value())),
            Some(("-3".into(), true))
        );
        assert_eq!(
            text(second.source().and_then(|e| e.token())),
            Some(("any".into(), false))
        );
        assert_eq!(
            text(second.target().and_then(|e| e.token())),
            Some(("4".into(), false))
        );
        assert_eq!(
            text(second.prio().and_then(|p| p.value())),
            Some(("5".into(), false))
        );
        let Item::Chart(chart) = &items[1] else {
            panic!("no chart")
        };
        let seq = chart.sequencers().next().expect("sequencer");
        assert_eq!(
            text(seq.prio().and_then(|p| p.value())),
            Some(("-6".into(), true))
        );
        let Item::Group(group) = &items[2] else {
            panic!("no group")
        };
        let option = group.options().next().expect("option");
        assert_eq!(text(option.value()), Some(("-7".into(), true)));
    }

    #[test]
    fn accessors_reach_group_and_chart_parts() {
        let parse = crate::parse(
            "group Gr fc FC 1 < instance I : G < OM := J.IM; X := E 1.0; > > \
             chart C < sequencer S < step A < N x; > jump J -> A < y; > > >",
        );
        let items: Vec<_> = parse.tree().items().collect();
        let Item::Group(group) = &items[0] else {
            panic!("no group")
        };
        assert!(group.fc().and_then(|b| b.address()).is_some());
        let inst = group.instances().next().expect("instance");
        let actuals: Vec<_> = inst.actuals().collect();
        assert!(matches!(
            actuals[0].value(),
            Some(Operand::MessageTarget(_))
        ));
        assert!(matches!(actuals[1].value(), Some(Operand::Address(_))));
        let Item::Chart(chart) = &items[1] else {
            panic!("no chart")
        };
        let seq = chart.sequencers().next().expect("sequencer");
        let elements: Vec<_> = seq.elements().collect();
        assert_eq!(elements.len(), 2);
        let SeqElement::Jump(jump) = &elements[1] else {
            panic!("no jump")
        };
        assert_eq!(jump.target().map(|t| t.text()), Some("A".to_owned()));
    }

    #[test]
    fn accessors_reach_the_parts_of_a_test() {
        let parse = crate::parse(
            "test T \"d\" < cycle T#5MS; run G, C; set \"S 1\".x := 1; step 3; step; \
             wait T#1S; until C.state = Held within T#2S \"m\"; expect not E 0.1; \
             command C start; confirm C.Seq.A; restart warm; >",
        );
        assert!(parse.errors().is_empty(), "{:?}", parse.errors());
        let Some(Item::Test(test)) = parse.tree().items().next() else {
            panic!("no test")
        };
        assert_eq!(test.name().map(|n| n.text()), Some("T".to_owned()));
        assert_eq!(test.comment().map(|c| c.value()), Some("d".to_owned()));
        let stmts: Vec<_> = test.statements().collect();
        let keywords: Vec<_> = stmts.iter().map(|s| s.keyword()).collect();
        assert_eq!(
            keywords,
            [
                "cycle", "run", "set", "step", "step", "wait", "until", "expect", "command",
                "confirm", "restart"
            ]
        );
        let TestStmt::Cycle(cycle) = &stmts[0] else {
            panic!("cycle")
        };
        assert_eq!(cycle.time().map(|l| l.text()), Some("T#5MS".to_owned()));
        let TestStmt::Run(run) = &stmts[1] else {
            panic!("run")
        };
        let entries: Vec<_> = run.entries().map(|n| n.text()).collect();
        assert_eq!(entries, ["G", "C"]);
        let TestStmt::Set(set) = &stmts[2] else {
            panic!("set")
        };
        let segments: Vec<_> = set
            .target()
            .map(|t| t.segment_texts())
            .unwrap_or_default()
            .into_iter()
            .map(|(s, _)| s)
            .collect();
        assert_eq!(segments, ["S 1", "x"]);
        assert!(matches!(set.value(), Some(Expr::Literal(_))));
        let TestStmt::Step(step) = &stmts[3] else {
            panic!("step")
        };
        assert_eq!(step.count().map(|c| c.text().to_owned()), Some("3".into()));
        let TestStmt::Step(step) = &stmts[4] else {
            panic!("step")
        };
        assert!(step.count().is_none());
        let TestStmt::Until(until) = &stmts[6] else {
            panic!("until")
        };
        assert!(matches!(until.condition(), Some(Expr::Bin(_))));
        assert_eq!(until.time().map(|l| l.text()), Some("T#2S".to_owned()));
        assert_eq!(until.message().map(|m| m.value()), Some("m".to_owned()));
        let TestStmt::Expect(expect) = &stmts[7] else {
            panic!("expect")
        };
        let Some(Expr::Prefix(not)) = expect.condition() else {
            panic!("not")
        };
        let Some(Expr::TestPath(path)) = not.operand() else {
            panic!("path")
        };
        assert!(path.address().is_some());
        assert!(expect.message().is_none());
        let TestStmt::Command(command) = &stmts[8] else {
            panic!("command")
        };
        assert_eq!(command.chart().map(|n| n.text()), Some("C".to_owned()));
        assert_eq!(
            command.command().map(|n| n.text()),
            Some("start".to_owned())
        );
        let TestStmt::Confirm(confirm) = &stmts[9] else {
            panic!("confirm")
        };
        assert_eq!(confirm.path().map(|p| p.segments().count()), Some(3));
        let TestStmt::Restart(restart) = &stmts[10] else {
            panic!("restart")
        };
        assert!(restart.is_warm());
    }
}

#[cfg(test)]
mod iec_tests {
    use super::*;

    fn chart(text: &str) -> Chart {
        let parse = crate::parse(text);
        assert!(parse.errors().is_empty(), "{:#?}", parse.errors());
        match parse.tree().items().next() {
            Some(Item::Chart(chart)) => chart,
            _ => panic!("no chart"),
        }
    }

    #[test]
    fn profile_actions_and_iec_qualifiers() {
        let c = chart(
            "chart C <\n  profile IEC;\n  action Count \"one part\" < N := TRUE; >\n  \
             sequencer S < step A < P1 Count; P0 X; DL Y, T#1S; > > >",
        );
        assert_eq!(c.profile(), Profile::Iec);
        let action = c.actions().next().expect("action");
        assert_eq!(
            action
                .name()
                .map(|n| n.syntax().text().to_string())
                .as_deref(),
            Some("Count")
        );
        assert!(action.comment().is_some());
        assert_eq!(action.statements().count(), 1);
        let step = match c.sequencers().next().and_then(|s| s.elements().next()) {
            Some(SeqElement::Step(step)) => step,
            _ => panic!("no step"),
        };
        let qualifiers: Vec<_> = step
            .actions()
            .filter_map(|a| a.qualifier())
            .map(|q| q.text().to_owned())
            .collect();
        assert_eq!(qualifiers, ["P1", "P0", "DL"]);
        assert_eq!(chart("chart C < >").profile(), Profile::Pcs7);
        assert_eq!(chart("chart C < profile pcs7; >").profile(), Profile::Pcs7);
        assert_eq!(
            chart("chart C < profile other; profile iec; >").profile(),
            Profile::Pcs7
        );
    }

    /// The operators of an expression, in prefix notation: `(+ a (* b c))`.
    fn shape(e: &Expr) -> String {
        match e {
            Expr::Bin(b) => format!(
                "({} {} {})",
                b.op().map_or("?", BinOp::text),
                b.lhs().map_or("?".into(), |e| shape(&e)),
                b.rhs().map_or("?".into(), |e| shape(&e))
            ),
            Expr::Prefix(p) => format!(
                "({:?} {})",
                p.op().expect("prefix op"),
                p.operand().map_or("?".into(), |e| shape(&e))
            ),
            Expr::Paren(p) => p.expr().map_or("?".into(), |e| shape(&e)),
            other => other.syntax().text().to_string(),
        }
    }

    fn condition_shape(condition: &str) -> String {
        let c = chart(&format!(
            "chart C < sequencer S < step A < > trans T < {condition}; > step B < > > >"
        ));
        let Some(SeqElement::Trans(t)) = c.sequencers().next().and_then(|s| s.elements().nth(1))
        else {
            panic!("no transition")
        };
        shape(&t.conditions().next().and_then(|c| c.expr()).expect("expr"))
    }

    #[test]
    fn arithmetic_precedence() {
        for (text, expected) in [
            ("a + b * c = d", "(= (+ a (* b c)) d)"),
            ("a - b - c", "(- (- a b) c)"),
            ("a-1 > -2", "(> (- a 1) -2)"),
            ("a MOD b / c", "(/ (MOD a b) c)"),
            ("-a * - b", "(* (Neg a) (Neg b))"),
            ("not a and b + 1 <> c", "(and (Not a) (<> (+ b 1) c))"),
            ("- (a + b) < 5 or x", "(or (< (Neg (+ a b)) 5) x)"),
            ("a mod -5", "(MOD a -5)"),
        ] {
            assert_eq!(condition_shape(text), expected, "{text}");
        }
    }

    #[test]
    fn structured_statements() {
        let c = chart(
            "chart C < action A <\n  IF a THEN x := 1; ELSIF b THEN y := 2; z := 3; ELSE Timer(IN := a, Q => q); END_IF;\n  \
             CASE n OF 1, -3..5: x := 1; ELSE END_CASE;\n  x := 0;\n> >",
        );
        let action = c.actions().next().expect("action");
        let stmts: Vec<_> = action.statements().collect();
        assert_eq!(stmts.len(), 3);
        assert_eq!(action.assignments().count(), 1);
        let Stmt::If(if_stmt) = &stmts[0] else {
            panic!("no IF")
        };
        assert_eq!(
            if_stmt
                .condition()
                .map(|e| e.syntax().text().to_string())
                .as_deref(),
            Some("a")
        );
        assert_eq!(if_stmt.then_statements().count(), 1);
        let elsifs: Vec<_> = if_stmt.elsifs().collect();
        assert_eq!(elsifs.len(), 1);
        assert_eq!(elsifs[0].statements().count(), 2);
        let else_stmts: Vec<_> = if_stmt.else_clause().expect("ELSE").statements().collect();
        let [Stmt::Call(call)] = else_stmts.as_slice() else {
            panic!("no call")
        };
        assert_eq!(
            call.callee()
                .map(|n| n.syntax().text().to_string())
                .as_deref(),
            Some("Timer")
        );
        let args: Vec<_> = call.args().collect();
        assert!(!args[0].is_output() && args[0].value().is_some() && args[0].target().is_none());
        assert!(args[1].is_output() && args[1].value().is_none() && args[1].target().is_some());
        let Stmt::Case(case) = &stmts[1] else {
            panic!("no CASE")
        };
        assert!(case.selector().is_some());
        let labels: Vec<_> = case
            .arms()
            .flat_map(|a| a.labels())
            .map(|l| (l.low(), l.high(), l.is_range()))
            .collect();
        assert_eq!(
            labels,
            [(Some(1), Some(1), false), (Some(-3), Some(5), true)]
        );
        assert_eq!(case.else_clause().map(|e| e.statements().count()), Some(0));
        assert!(case.end_keyword().is_some());
    }
}
