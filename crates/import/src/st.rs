//! Structured text (IEC 61131-3) to the statements and expressions of an IEC chart
//! (`docs/iec.md` §4, §5).
//!
//! The ST of a body is lexed and parsed into a small tree, then written in the language's
//! spelling: `AND`/`&` → `and`, `OR` → `or`, `XOR` → `xor`, `NOT` → `not`, `IF THEN ELSIF ELSE
//! END_IF CASE OF END_CASE MOD TRUE FALSE` upper case, names (and time literals such as
//! `T#5s`) as written, parentheses where the language's precedence needs them. Comments that
//! stand between statements become `//` lines; comments inside a statement are dropped.
//!
//! Anything outside the subset the language has (loops, `EXIT`/`RETURN`, function calls other
//! than calls of standard function block instances, arrays, pointers, `**`, direct addresses,
//! wide strings, enumerated labels) is an [`Unsupported`] error naming the construct and its
//! line in the text, and the caller leaves the whole body out. Nesting is bounded by
//! [`MAX_DEPTH`]; every loop consumes a token, so the cost is linear in the text.

use std::collections::HashMap;
use std::fmt::Write as _;

use higraph_syntax::literal::check_literal;

/// Deepest nesting of expressions and statements that is converted (the language's parser
/// accepts 256 levels; this leaves room for the chart around it).
pub const MAX_DEPTH: usize = 100;

/// Why a text cannot be converted: the reason and its 1-based line in the text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unsupported {
    pub line: usize,
    pub reason: String,
}

/// What the converter knows of the POU: how names are written in the output, and which
/// names are instances of standard function blocks (the only callable things).
#[derive(Debug, Default)]
pub struct Names {
    /// Upper-cased IEC name → the name in the output (only for renamed names).
    pub renamed: HashMap<String, String>,
    /// Upper-cased names of standard function block instances.
    pub fb_instances: HashMap<String, ()>,
    /// Upper-cased names of variables of elementary types (no members).
    pub elementary: HashMap<String, ()>,
}

impl Names {
    fn name(&self, name: &str) -> String {
        self.renamed
            .get(&name.to_ascii_uppercase())
            .cloned()
            .unwrap_or_else(|| name.to_owned())
    }
}

// ------------------------------------------------------------------------------------ lexer

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    /// A number, already in the language's spelling.
    Number(String),
    /// A typed literal (time, date, ...) kept as written.
    Typed(String),
    /// `'text'`.
    Str(String),
    /// Punctuation and operators.
    Punct(&'static str),
    /// A comment's text (without its delimiters).
    Comment(String),
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    line: usize,
}

const PUNCT: &[&str] = &[
    ":=", "=>", "<=", ">=", "<>", "**", "..", "=", "<", ">", "+", "-", "*", "/", "(", ")", "[",
    "]", ",", ";", ":", ".", "^", "&", "#",
];

fn err<T>(line: usize, reason: impl Into<String>) -> Result<T, Unsupported> {
    Err(Unsupported {
        line,
        reason: reason.into(),
    })
}

/// Splits ST text into tokens.
fn lex(text: &str) -> Result<Vec<Token>, Unsupported> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    let mut line = 1;
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'\n' {
            line += 1;
            i += 1;
            continue;
        }
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start_line = line;
        // Comments: (* *), /* */ and //.
        if text[i..].starts_with("(*") || text[i..].starts_with("/*") {
            let close = if c == b'(' { "*)" } else { "*/" };
            let end = text[i + 2..].find(close).map(|e| i + 2 + e);
            let Some(end) = end else {
                return err(line, "a comment that is not closed");
            };
            let body = &text[i + 2..end];
            line += body.matches('\n').count();
            tokens.push(Token {
                tok: Tok::Comment(body.to_owned()),
                line: start_line,
            });
            i = end + 2;
            continue;
        }
        if text[i..].starts_with("//") {
            let end = text[i..].find('\n').map_or(bytes.len(), |e| i + e);
            tokens.push(Token {
                tok: Tok::Comment(text[i + 2..end].to_owned()),
                line,
            });
            i = end;
            continue;
        }
        // Pragmas ({attribute ...}) are dropped.
        if c == b'{' {
            let end = text[i..].find('}').map(|e| i + e);
            let Some(end) = end else {
                return err(line, "a pragma `{` that is not closed");
            };
            line += text[i..end].matches('\n').count();
            i = end + 1;
            continue;
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            let word = &text[start..i];
            if i < bytes.len() && bytes[i] == b'#' {
                // A typed literal: T#5s, TIME#1m, D#2020-01-01, INT#5, 16#FF is a number.
                i += 1;
                let upper = word.to_ascii_uppercase();
                let dateish = matches!(
                    upper.as_str(),
                    "D" | "DATE" | "DT" | "DATE_AND_TIME" | "TOD" | "TIME_OF_DAY"
                );
                if i < bytes.len() && bytes[i] == b'-' {
                    i += 1;
                }
                while i < bytes.len()
                    && (bytes[i].is_ascii_alphanumeric()
                        || bytes[i] == b'_'
                        || bytes[i] == b'.'
                        || bytes[i] == b'#'
                        || (dateish && (bytes[i] == b'-' || bytes[i] == b':')))
                {
                    i += 1;
                }
                tokens.push(Token {
                    tok: typed_literal(word, &text[start..i], line)?,
                    line,
                });
                continue;
            }
            tokens.push(Token {
                tok: Tok::Ident(word.to_owned()),
                line,
            });
            continue;
        }
        if c.is_ascii_digit() {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            if i < bytes.len() && bytes[i] == b'#' {
                // 16#FF, 2#1010, 8#17.
                i += 1;
                while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                    i += 1;
                }
                tokens.push(Token {
                    tok: Tok::Number(based_number(&text[start..i], line)?),
                    line,
                });
                continue;
            }
            // A real: digits '.' digits [e[+-]digits]; not `1..5`.
            if i + 1 < bytes.len() && bytes[i] == b'.' && bytes[i + 1].is_ascii_digit() {
                i += 1;
                while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                    if (bytes[i] == b'e' || bytes[i] == b'E')
                        && i + 1 < bytes.len()
                        && (bytes[i + 1] == b'-' || bytes[i + 1] == b'+')
                    {
                        i += 1;
                    }
                    i += 1;
                }
            }
            let number: String = text[start..i].chars().filter(|&c| c != '_').collect();
            if !number
                .chars()
                .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'))
                || check_literal(&number).is_err()
            {
                return err(line, format!("the number `{number}`"));
            }
            tokens.push(Token {
                tok: Tok::Number(number),
                line,
            });
            continue;
        }
        if c == b'\'' {
            let end = text[i + 1..].find('\'').map(|e| i + 1 + e);
            let Some(end) = end else {
                return err(line, "a string that is not closed");
            };
            let s = &text[i + 1..end];
            if s.contains('\n') || s.contains('$') || s.contains('"') {
                return err(line, "a string with line breaks or `$` escapes");
            }
            tokens.push(Token {
                tok: Tok::Str(s.to_owned()),
                line,
            });
            i = end + 1;
            continue;
        }
        if c == b'"' {
            return err(line, "a WSTRING literal");
        }
        if c == b'%' {
            return err(line, "a direct address (`%...`)");
        }
        let Some(p) = PUNCT.iter().find(|p| text[i..].starts_with(**p)) else {
            let ch = text[i..].chars().next().unwrap_or('?');
            return err(line, format!("the character `{ch}`"));
        };
        tokens.push(Token {
            tok: Tok::Punct(p),
            line,
        });
        i += p.len();
    }
    Ok(tokens)
}

/// `T#5s` stays; `INT#5`, `DINT#5`, `REAL#1.5` become plain numbers; `BOOL#1` TRUE.
fn typed_literal(prefix: &str, whole: &str, line: usize) -> Result<Tok, Unsupported> {
    let upper = prefix.to_ascii_uppercase();
    let value = &whole[prefix.len() + 1..];
    match upper.as_str() {
        "T" | "TIME" | "D" | "DATE" | "DT" | "DATE_AND_TIME" | "TOD" | "TIME_OF_DAY" => {
            // Only what the language reads (units in order, values in range).
            match check_literal(whole) {
                Ok(_) => Ok(Tok::Typed(whole.to_owned())),
                Err(e) => err(line, format!("the literal `{whole}` ({})", e.message)),
            }
        }
        "INT" | "SINT" | "DINT" | "REAL" | "LREAL" | "UINT" | "USINT" | "UDINT" => {
            if value.contains('#') {
                return Ok(Tok::Number(based_number(value, line)?));
            }
            let number: String = value.chars().filter(|&c| c != '_').collect();
            if number.is_empty() || number.parse::<f64>().is_err() {
                return err(line, format!("the literal `{whole}`"));
            }
            Ok(Tok::Number(number))
        }
        "BOOL" => match value {
            "1" => Ok(Tok::Ident("TRUE".to_owned())),
            "0" => Ok(Tok::Ident("FALSE".to_owned())),
            _ => Ok(Tok::Ident(value.to_ascii_uppercase())),
        },
        _ => err(line, format!("the typed literal `{whole}`")),
    }
}

/// `16#FF` → `255`.
fn based_number(text: &str, line: usize) -> Result<String, Unsupported> {
    let (base, digits) = text.split_once('#').unwrap_or(("10", text));
    let digits: String = digits.chars().filter(|&c| c != '_').collect();
    let value = base
        .parse::<u32>()
        .ok()
        .filter(|b| matches!(b, 2 | 8 | 16))
        .and_then(|b| i64::from_str_radix(&digits, b).ok());
    match value {
        Some(v) => Ok(v.to_string()),
        None => err(line, format!("the number `{text}`")),
    }
}

// ------------------------------------------------------------------------------------ tree

#[derive(Debug, Clone)]
enum Expr {
    /// A literal or a path, in output spelling.
    Atom(String),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UnOp {
    Not,
    Neg,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BinOp {
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
    /// Precedence in the language (`docs/iec.md` §4).
    fn prec(self) -> u8 {
        match self {
            BinOp::Or => 1,
            BinOp::Xor => 2,
            BinOp::And => 3,
            BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Gt | BinOp::Le | BinOp::Ge => 4,
            BinOp::Add | BinOp::Sub => 5,
            BinOp::Mul | BinOp::Div | BinOp::Mod => 6,
        }
    }

    fn text(self) -> &'static str {
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
}

#[derive(Debug, Clone)]
enum Stmt {
    Comment(String),
    Assign(String, Expr),
    If {
        arms: Vec<(Expr, Vec<Stmt>)>,
        else_: Option<Vec<Stmt>>,
    },
    Case {
        selector: Expr,
        arms: Vec<(Vec<String>, Vec<Stmt>)>,
        else_: Option<Vec<Stmt>>,
    },
    /// `Timer(IN := x, Q => y);` — the callee and its arguments, written.
    Call(String, Vec<String>),
}

// ------------------------------------------------------------------------------------ parser

struct Parser<'a> {
    tokens: Vec<Token>,
    pos: usize,
    names: &'a Names,
    depth: usize,
    last_line: usize,
}

const KEYWORDS: &[&str] = &[
    "IF",
    "THEN",
    "ELSIF",
    "ELSE",
    "END_IF",
    "CASE",
    "OF",
    "END_CASE",
    "FOR",
    "TO",
    "BY",
    "DO",
    "END_FOR",
    "WHILE",
    "END_WHILE",
    "REPEAT",
    "UNTIL",
    "END_REPEAT",
    "EXIT",
    "RETURN",
    "CONTINUE",
    "JMP",
    "AND",
    "OR",
    "XOR",
    "NOT",
    "MOD",
    "TRUE",
    "FALSE",
];

fn is_keyword(word: &str) -> bool {
    KEYWORDS.iter().any(|k| k.eq_ignore_ascii_case(word))
}

impl<'a> Parser<'a> {
    fn new(text: &str, names: &'a Names) -> Result<Parser<'a>, Unsupported> {
        Ok(Parser {
            tokens: lex(text)?,
            pos: 0,
            names,
            depth: 0,
            last_line: 1,
        })
    }

    /// The next significant token (comments skipped).
    fn peek_n(&self, n: usize) -> Option<&Token> {
        self.tokens[self.pos.min(self.tokens.len())..]
            .iter()
            .filter(|t| !matches!(t.tok, Tok::Comment(_)))
            .nth(n)
    }

    fn peek(&self) -> Option<&Tok> {
        self.peek_n(0).map(|t| &t.tok)
    }

    fn line(&self) -> usize {
        self.peek_n(0).map_or(self.last_line, |t| t.line)
    }

    /// Skips comments (inside a statement they are dropped).
    fn skip_comments(&mut self) {
        while let Some(Token {
            tok: Tok::Comment(_),
            ..
        }) = self.tokens.get(self.pos)
        {
            self.pos += 1;
        }
    }

    fn bump(&mut self) -> Option<Tok> {
        self.skip_comments();
        let t = self.tokens.get(self.pos).cloned()?;
        self.pos += 1;
        self.last_line = t.line;
        Some(t.tok)
    }

    fn at_punct(&self, p: &str) -> bool {
        matches!(self.peek(), Some(Tok::Punct(q)) if *q == p)
    }

    fn at_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Some(Tok::Ident(w)) if w.eq_ignore_ascii_case(kw))
    }

    fn nth_is_punct(&self, n: usize, p: &str) -> bool {
        matches!(self.peek_n(n).map(|t| &t.tok), Some(Tok::Punct(q)) if *q == p)
    }

    fn expect_punct(&mut self, p: &str) -> Result<(), Unsupported> {
        if self.at_punct(p) {
            self.bump();
            Ok(())
        } else {
            err(self.line(), format!("`{p}` expected {}", self.found()))
        }
    }

    fn expect_kw(&mut self, kw: &str) -> Result<(), Unsupported> {
        if self.at_kw(kw) {
            self.bump();
            Ok(())
        } else {
            err(self.line(), format!("`{kw}` expected {}", self.found()))
        }
    }

    fn found(&self) -> String {
        match self.peek() {
            None => "at the end of the text".to_owned(),
            Some(Tok::Ident(w) | Tok::Number(w) | Tok::Typed(w)) => format!("before `{w}`"),
            Some(Tok::Str(s)) => format!("before `'{s}'`"),
            Some(Tok::Punct(p)) => format!("before `{p}`"),
            Some(Tok::Comment(_)) => String::new(),
        }
    }

    fn enter(&mut self) -> Result<(), Unsupported> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return err(
                self.line(),
                format!("nesting deeper than {MAX_DEPTH} levels"),
            );
        }
        Ok(())
    }

    // ---- statements

    /// Statements until one of `ends` (keywords) or the end of the text.
    fn statements(&mut self, ends: &[&str]) -> Result<Vec<Stmt>, Unsupported> {
        self.enter()?;
        let mut out = Vec::new();
        loop {
            // Comments between statements are kept.
            while let Some(Token {
                tok: Tok::Comment(c),
                ..
            }) = self.tokens.get(self.pos)
            {
                for line in c.lines() {
                    let line = line.trim().trim_matches('*').trim();
                    if !line.is_empty() {
                        out.push(Stmt::Comment(line.to_owned()));
                    }
                }
                self.pos += 1;
            }
            match self.peek() {
                None => break,
                Some(Tok::Ident(w)) if ends.iter().any(|e| e.eq_ignore_ascii_case(w)) => break,
                _ => {}
            }
            if self.at_punct(";") {
                self.bump();
                continue;
            }
            // A CASE arm's label ends the arm's statements.
            if ends.contains(&"END_CASE") && self.at_case_label() {
                break;
            }
            out.push(self.statement()?);
        }
        self.depth -= 1;
        Ok(out)
    }

    fn at_case_label(&self) -> bool {
        match self.peek() {
            Some(Tok::Number(_)) => true,
            Some(Tok::Punct("-")) => matches!(self.peek_n(1).map(|t| &t.tok), Some(Tok::Number(_))),
            Some(Tok::Ident(w)) if !is_keyword(w) => {
                self.nth_is_punct(1, ":") || self.nth_is_punct(1, ",")
            }
            _ => false,
        }
    }

    fn statement(&mut self) -> Result<Stmt, Unsupported> {
        let line = self.line();
        let Some(Tok::Ident(word)) = self.peek().cloned() else {
            return err(line, format!("a statement expected {}", self.found()));
        };
        let upper = word.to_ascii_uppercase();
        match upper.as_str() {
            "IF" => return self.if_stmt(),
            "CASE" => return self.case_stmt(),
            "FOR" | "WHILE" | "REPEAT" => {
                return err(line, format!("{upper} loops are not supported"));
            }
            "EXIT" | "RETURN" | "CONTINUE" | "JMP" => {
                return err(line, format!("`{upper}` is not supported"));
            }
            _ if is_keyword(&upper) => {
                return err(line, format!("a statement expected before `{word}`"));
            }
            _ => {}
        }
        if self.nth_is_punct(1, ":") {
            return err(line, "labels are not supported");
        }
        let target = self.path()?;
        if self.at_punct("(") {
            return self.call(target, line);
        }
        if self.at_punct(":=") {
            self.bump();
            let value = self.expr()?;
            if self.at_punct(":=") {
                return err(line, "chained assignments are not supported");
            }
            self.expect_punct(";")?;
            return Ok(Stmt::Assign(target, value));
        }
        if let Some(Tok::Ident(w)) = self.peek()
            && (w.eq_ignore_ascii_case("S") || w.eq_ignore_ascii_case("R"))
            && self.nth_is_punct(1, "=")
        {
            return err(line, "`S=`/`R=` assignments are not supported");
        }
        err(line, format!("`:=` expected {}", self.found()))
    }

    fn if_stmt(&mut self) -> Result<Stmt, Unsupported> {
        self.enter()?;
        self.expect_kw("IF")?;
        let mut arms = Vec::new();
        let cond = self.expr()?;
        self.expect_kw("THEN")?;
        let body = self.statements(&["ELSIF", "ELSE", "END_IF"])?;
        arms.push((cond, body));
        let mut else_ = None;
        loop {
            if self.at_kw("ELSIF") {
                self.bump();
                let cond = self.expr()?;
                self.expect_kw("THEN")?;
                let body = self.statements(&["ELSIF", "ELSE", "END_IF"])?;
                arms.push((cond, body));
            } else if self.at_kw("ELSE") {
                self.bump();
                else_ = Some(self.statements(&["END_IF"])?);
            } else {
                break;
            }
        }
        self.expect_kw("END_IF")?;
        if self.at_punct(";") {
            self.bump();
        }
        self.depth -= 1;
        Ok(Stmt::If { arms, else_ })
    }

    fn case_stmt(&mut self) -> Result<Stmt, Unsupported> {
        self.enter()?;
        self.expect_kw("CASE")?;
        let selector = self.expr()?;
        self.expect_kw("OF")?;
        let mut arms = Vec::new();
        let mut else_ = None;
        loop {
            if self.at_kw("END_CASE") {
                break;
            }
            if self.at_kw("ELSE") {
                self.bump();
                else_ = Some(self.statements(&["END_CASE"])?);
                break;
            }
            let mut labels = Vec::new();
            loop {
                let low = self.case_label()?;
                if self.at_punct("..") {
                    self.bump();
                    let high = self.case_label()?;
                    labels.push(format!("{low}..{high}"));
                } else {
                    labels.push(low);
                }
                if self.at_punct(",") {
                    self.bump();
                    continue;
                }
                break;
            }
            self.expect_punct(":")?;
            let body = self.statements(&["ELSE", "END_CASE"])?;
            arms.push((labels, body));
        }
        self.expect_kw("END_CASE")?;
        if self.at_punct(";") {
            self.bump();
        }
        self.depth -= 1;
        Ok(Stmt::Case {
            selector,
            arms,
            else_,
        })
    }

    fn case_label(&mut self) -> Result<String, Unsupported> {
        let line = self.line();
        let negative = if self.at_punct("-") {
            self.bump();
            true
        } else {
            false
        };
        match self.bump() {
            Some(Tok::Number(n)) if n.chars().all(|c| c.is_ascii_digit()) => {
                Ok(if negative { format!("-{n}") } else { n })
            }
            Some(Tok::Ident(w)) => err(
                line,
                format!("CASE label `{w}` (enumerated values are not supported)"),
            ),
            _ => err(line, "a CASE label that is not an integer constant"),
        }
    }

    fn call(&mut self, callee: String, line: usize) -> Result<Stmt, Unsupported> {
        if callee.contains('.') {
            return err(line, format!("the method call `{callee}(...)`"));
        }
        if !self
            .names
            .fb_instances
            .contains_key(&callee.to_ascii_uppercase())
        {
            return err(
                line,
                format!(
                    "the call of `{callee}` (only instances of standard function blocks can be called)"
                ),
            );
        }
        self.expect_punct("(")?;
        let mut args = Vec::new();
        if !self.at_punct(")") {
            loop {
                let arg_line = self.line();
                let formal = match self.bump() {
                    Some(Tok::Ident(w)) if !is_keyword(&w) => w,
                    _ => return err(arg_line, "a formal parameter name expected in the call"),
                };
                if self.at_punct(":=") {
                    self.bump();
                    let value = self.expr()?;
                    args.push(format!("{formal} := {}", print_expr(&value, 0)));
                } else if self.at_punct("=>") {
                    self.bump();
                    let target = self.path()?;
                    args.push(format!("{formal} => {target}"));
                } else {
                    return err(
                        arg_line,
                        "positional arguments are not supported (write `NAME := value`)",
                    );
                }
                if self.at_punct(",") {
                    self.bump();
                    continue;
                }
                break;
            }
        }
        self.expect_punct(")")?;
        self.expect_punct(";")?;
        Ok(Stmt::Call(self.names.name(&callee), args))
    }

    /// `A`, `A.B.C` — output spelling (the first name renamed as the POU's names are).
    fn path(&mut self) -> Result<String, Unsupported> {
        let line = self.line();
        let mut out = match self.bump() {
            Some(Tok::Ident(w)) if !is_keyword(&w) => self.names.name(&w),
            _ => return err(line, format!("a name expected {}", self.found())),
        };
        let first = out.to_ascii_uppercase();
        while self.at_punct(".") {
            self.bump();
            if self.names.elementary.contains_key(&first) {
                return err(line, format!("member access on the variable `{out}`"));
            }
            match self.bump() {
                Some(Tok::Ident(w)) => {
                    out.push('.');
                    out.push_str(&w);
                }
                Some(Tok::Number(n)) if n.chars().all(|c| c.is_ascii_digit()) => {
                    return err(line, format!("the bit access `{out}.{n}`"));
                }
                _ => return err(line, "a member name expected after `.`"),
            }
        }
        if self.at_punct("[") {
            return err(line, format!("the array access `{out}[...]`"));
        }
        if self.at_punct("^") {
            return err(line, format!("the pointer dereference `{out}^`"));
        }
        Ok(out)
    }

    // ---- expressions

    fn expr(&mut self) -> Result<Expr, Unsupported> {
        self.enter()?;
        let e = self.binary(1)?;
        self.depth -= 1;
        Ok(e)
    }

    fn binop(&self) -> Option<(BinOp, u8)> {
        // IEC precedence: OR 1, XOR 2, AND/& 3, = <> 4, < > <= >= 5, + - 6, * / MOD 7.
        let op = match self.peek()? {
            Tok::Ident(w) => match w.to_ascii_uppercase().as_str() {
                "OR" => BinOp::Or,
                "XOR" => BinOp::Xor,
                "AND" => BinOp::And,
                "MOD" => BinOp::Mod,
                _ => return None,
            },
            Tok::Punct(p) => match *p {
                "&" => BinOp::And,
                "=" => BinOp::Eq,
                "<>" => BinOp::Ne,
                "<" => BinOp::Lt,
                ">" => BinOp::Gt,
                "<=" => BinOp::Le,
                ">=" => BinOp::Ge,
                "+" => BinOp::Add,
                "-" => BinOp::Sub,
                "*" => BinOp::Mul,
                "/" => BinOp::Div,
                _ => return None,
            },
            _ => return None,
        };
        let level = match op {
            BinOp::Or => 1,
            BinOp::Xor => 2,
            BinOp::And => 3,
            BinOp::Eq | BinOp::Ne => 4,
            BinOp::Lt | BinOp::Gt | BinOp::Le | BinOp::Ge => 5,
            BinOp::Add | BinOp::Sub => 6,
            BinOp::Mul | BinOp::Div | BinOp::Mod => 7,
        };
        Some((op, level))
    }

    /// Precedence climbing; left-associative. Depth is bounded by the number of levels and
    /// by `enter` on parentheses and unary operators.
    fn binary(&mut self, min: u8) -> Result<Expr, Unsupported> {
        let mut left = self.unary()?;
        while let Some((op, level)) = self.binop() {
            if level < min {
                break;
            }
            self.bump();
            let right = self.binary(level + 1)?;
            left = Expr::Binary(op, Box::new(left), Box::new(right));
        }
        if self.at_punct("**") {
            return err(self.line(), "the power operator `**`");
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Expr, Unsupported> {
        let line = self.line();
        if self.at_kw("NOT") {
            self.bump();
            self.enter()?;
            let e = self.unary()?;
            self.depth -= 1;
            return Ok(Expr::Unary(UnOp::Not, Box::new(e)));
        }
        if self.at_punct("-") {
            self.bump();
            if let Some(Tok::Number(n)) = self.peek().cloned() {
                self.bump();
                return Ok(Expr::Atom(format!("-{n}")));
            }
            self.enter()?;
            let e = self.unary()?;
            self.depth -= 1;
            return Ok(Expr::Unary(UnOp::Neg, Box::new(e)));
        }
        if self.at_punct("+") {
            self.bump();
            return self.unary();
        }
        match self.peek().cloned() {
            Some(Tok::Punct("(")) => {
                self.bump();
                let e = self.expr()?;
                self.expect_punct(")")?;
                Ok(e)
            }
            Some(Tok::Number(n)) => {
                self.bump();
                Ok(Expr::Atom(n))
            }
            Some(Tok::Typed(t)) => {
                self.bump();
                Ok(Expr::Atom(t))
            }
            Some(Tok::Str(s)) => {
                self.bump();
                Ok(Expr::Atom(format!("'{s}'")))
            }
            Some(Tok::Ident(w)) if w.eq_ignore_ascii_case("TRUE") => {
                self.bump();
                Ok(Expr::Atom("TRUE".to_owned()))
            }
            Some(Tok::Ident(w)) if w.eq_ignore_ascii_case("FALSE") => {
                self.bump();
                Ok(Expr::Atom("FALSE".to_owned()))
            }
            Some(Tok::Ident(w)) if !is_keyword(&w) => {
                if self.nth_is_punct(1, "(") {
                    return err(line, format!("the function call `{w}(...)`"));
                }
                let p = self.path()?;
                if self.at_punct("(") {
                    return err(line, format!("the call `{p}(...)` inside an expression"));
                }
                Ok(Expr::Atom(p))
            }
            _ => err(line, format!("an operand expected {}", self.found())),
        }
    }
}

// ------------------------------------------------------------------------------------ printer

/// Writes an expression; `parent` is the precedence of the operator around it (0: none).
fn print_expr(e: &Expr, parent: u8) -> String {
    let mut out = String::new();
    write_expr(&mut out, e, parent, 0);
    out
}

fn write_expr(out: &mut String, e: &Expr, parent: u8, depth: usize) {
    if depth > MAX_DEPTH * 2 {
        out.push_str("FALSE");
        return;
    }
    match e {
        Expr::Atom(a) => out.push_str(a),
        Expr::Unary(op, inner) => {
            out.push_str(match op {
                UnOp::Not => "not ",
                UnOp::Neg => "-",
            });
            let needs = match &**inner {
                Expr::Binary(..) => true,
                Expr::Atom(a) => *op == UnOp::Neg && a.starts_with('-'),
                Expr::Unary(inner_op, _) => *op == UnOp::Neg && *inner_op == UnOp::Neg,
            };
            if needs {
                out.push('(');
                write_expr(out, inner, 0, depth + 1);
                out.push(')');
            } else {
                write_expr(out, inner, 7, depth + 1);
            }
        }
        Expr::Binary(op, l, r) => {
            let p = op.prec();
            let paren = p < parent;
            if paren {
                out.push('(');
            }
            // Comparisons are not chained: a comparison operand of one is parenthesized.
            // Otherwise operators bind to the left: a right operand of the same precedence
            // is parenthesized.
            let (left_ctx, right_ctx) = if p == 4 { (5, 5) } else { (p, p + 1) };
            write_expr(out, l, left_ctx, depth + 1);
            out.push(' ');
            out.push_str(op.text());
            out.push(' ');
            write_expr(out, r, right_ctx, depth + 1);
            if paren {
                out.push(')');
            }
        }
    }
}

fn write_stmts(out: &mut String, stmts: &[Stmt], indent: usize) {
    for s in stmts {
        write_stmt(out, s, indent);
    }
}

fn pad(out: &mut String, indent: usize) {
    for _ in 0..indent {
        out.push_str("  ");
    }
}

fn write_stmt(out: &mut String, s: &Stmt, indent: usize) {
    pad(out, indent);
    match s {
        Stmt::Comment(c) => {
            let _ = writeln!(out, "// {c}");
        }
        Stmt::Assign(t, e) => {
            let _ = writeln!(out, "{t} := {};", print_expr(e, 0));
        }
        Stmt::Call(callee, args) => {
            let _ = writeln!(out, "{callee}({});", args.join(", "));
        }
        Stmt::If { arms, else_ } => {
            for (i, (cond, body)) in arms.iter().enumerate() {
                if i > 0 {
                    pad(out, indent);
                }
                let kw = if i == 0 { "IF" } else { "ELSIF" };
                let _ = writeln!(out, "{kw} {} THEN", print_expr(cond, 0));
                write_stmts(out, body, indent + 1);
            }
            if let Some(body) = else_ {
                pad(out, indent);
                out.push_str("ELSE\n");
                write_stmts(out, body, indent + 1);
            }
            pad(out, indent);
            out.push_str("END_IF;\n");
        }
        Stmt::Case {
            selector,
            arms,
            else_,
        } => {
            let _ = writeln!(out, "CASE {} OF", print_expr(selector, 0));
            for (labels, body) in arms {
                pad(out, indent + 1);
                let _ = writeln!(out, "{}:", labels.join(", "));
                write_stmts(out, body, indent + 2);
            }
            if let Some(body) = else_ {
                // As `fmt` lays it out: the ELSE of a CASE stands with the arms.
                pad(out, indent + 1);
                out.push_str("ELSE\n");
                write_stmts(out, body, indent + 2);
            }
            pad(out, indent);
            out.push_str("END_CASE;\n");
        }
    }
}

// ------------------------------------------------------------------------------------ API

/// Converts an ST expression (a transition condition) to the language's spelling. A body
/// written as `:= expr;` (as some tools store a named transition) or `NAME := expr;` is
/// accepted too.
pub fn condition(text: &str, names: &Names) -> Result<String, Unsupported> {
    let mut p = Parser::new(text, names)?;
    if p.peek().is_none() {
        return err(1, "an empty condition");
    }
    if p.at_punct(":=") {
        p.bump();
    } else if matches!(p.peek(), Some(Tok::Ident(_))) && p.nth_is_punct(1, ":=") {
        p.bump();
        p.bump();
    }
    let e = p.expr()?;
    if p.at_punct(";") {
        p.bump();
    }
    if p.peek().is_some() {
        return err(p.line(), format!("the condition ends {}", p.found()));
    }
    Ok(print_expr(&e, 0))
}

/// Converts ST statements (an action body) to the language's statements, one per line at
/// `indent` levels of two spaces.
pub fn statements(text: &str, names: &Names, indent: usize) -> Result<String, Unsupported> {
    let mut p = Parser::new(text, names)?;
    let stmts = p.statements(&[])?;
    if p.peek().is_some() {
        return err(p.line(), format!("a statement expected {}", p.found()));
    }
    let mut out = String::new();
    write_stmts(&mut out, &stmts, indent);
    Ok(out)
}

/// An initial value: a literal in the language's spelling, or why not.
pub fn literal(text: &str) -> Result<String, Unsupported> {
    let names = Names::default();
    let mut p = Parser::new(text, &names)?;
    let e = p.unary()?;
    if p.peek().is_some() {
        return err(1, format!("the initial value `{}`", text.trim()));
    }
    match e {
        Expr::Atom(a)
            if !a.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                || a == "TRUE"
                || a == "FALSE"
                || a.contains('#') =>
        {
            Ok(a)
        }
        _ => err(1, format!("the initial value `{}`", text.trim())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Names {
        let mut n = Names::default();
        n.fb_instances.insert("TIMER".into(), ());
        n.elementary.insert("X".into(), ());
        n
    }

    #[test]
    fn conditions() {
        let n = names();
        let c = |t: &str| condition(t, &n).map_err(|e| e.reason);
        assert_eq!(c("a AND b OR NOT c").unwrap(), "a and b or not c");
        assert_eq!(c("a & (b OR c)").unwrap(), "a and (b or c)");
        assert_eq!(c("Timer.Q").unwrap(), "Timer.Q");
        assert_eq!(c("x > 5 (* five *)").unwrap(), "x > 5");
        assert_eq!(c("a = b = c").unwrap(), "(a = b) = c");
        assert_eq!(c("a < b = c").unwrap(), "(a < b) = c");
        assert_eq!(c("NOT (a AND b)").unwrap(), "not (a and b)");
        assert_eq!(c("a - (b - c)").unwrap(), "a - (b - c)");
        assert_eq!(c("(a - b) - c").unwrap(), "a - b - c");
        assert_eq!(c("-x * 2 MOD 3").unwrap(), "-x * 2 MOD 3");
        assert_eq!(c("- -5").unwrap(), "-(-5)");
        assert_eq!(c("16#FF = 255").unwrap(), "255 = 255");
        assert_eq!(c(":= Start;").unwrap(), "Start");
        assert_eq!(c("Step1.T >= t#5s").unwrap(), "Step1.T >= t#5s");
        assert!(c("ABS(x) > 1").unwrap_err().contains("function call `ABS"));
        assert!(c("a[1]").unwrap_err().contains("array"));
        assert!(c("a ** 2").unwrap_err().contains("power"));
        assert!(c("%IX0.0").unwrap_err().contains("direct address"));
        assert!(c("x.Q").unwrap_err().contains("member access"));
        assert!(c("").is_err());
    }

    #[test]
    fn statements_convert() {
        let n = names();
        let text = "(* count *)\nIF a THEN b := 1; ELSIF c THEN b := 2; ELSE b := -3; END_IF;\n\
                    CASE b OF 1, 2: y := TRUE; 3..5: y := FALSE; ELSE y := a; END_CASE\n\
                    Timer(IN := TRUE, PT := T#5s, Q => z);";
        let out = statements(text, &n, 0).unwrap();
        assert_eq!(
            out,
            "// count\nIF a THEN\n  b := 1;\nELSIF c THEN\n  b := 2;\nELSE\n  b := -3;\nEND_IF;\n\
             CASE b OF\n  1, 2:\n    y := TRUE;\n  3..5:\n    y := FALSE;\n  ELSE\n    y := a;\nEND_CASE;\n\
             Timer(IN := TRUE, PT := T#5s, Q => z);\n"
        );
        let e = statements("a := 1;\nFOR i := 1 TO 3 DO END_FOR;", &n, 0).unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.reason.contains("FOR loops"));
        assert!(
            statements("Foo(1);", &n, 0)
                .unwrap_err()
                .reason
                .contains("call of `Foo`")
        );
        assert!(statements("CASE s OF Red: a := 1; END_CASE;", &n, 0).is_err());
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowing() {
        let n = names();
        let deep = format!("{}a{}", "(".repeat(100_000), ")".repeat(100_000));
        assert!(condition(&deep, &n).unwrap_err().reason.contains("nesting"));
        let nots = format!("{}a", "NOT ".repeat(100_000));
        assert!(condition(&nots, &n).is_err());
        let ifs = "IF a THEN ".repeat(10_000);
        assert!(statements(&ifs, &n, 0).is_err());
    }

    #[test]
    fn literals() {
        assert_eq!(literal("T#5s").unwrap(), "T#5s");
        assert_eq!(literal("-12").unwrap(), "-12");
        assert_eq!(literal("TRUE").unwrap(), "TRUE");
        assert_eq!(literal("16#10").unwrap(), "16");
        assert!(literal("[1,2]").is_err());
        assert!(literal("Red").is_err());
    }
}
