//! The structure of one graph as the graph rules see it: its states (with duplicates marked,
//! C3), its transitions with endpoints, priority ranges, effective priorities (§2.6), the
//! startup transitions and the labels used in messages (§2.3).

use std::collections::{HashMap, HashSet};

use higraph_syntax::{SyntaxKind, SyntaxToken, TextRange, ast, ast::AstNode};

use crate::lang::{self, Mnemonic};

/// One `state` whose number parsed.
pub(crate) struct StateEntry {
    pub node: ast::State,
    /// The number token as written.
    pub number: SyntaxToken,
    /// The number without leading zeros (equal numbers have equal keys).
    pub key: String,
    /// The number, if it fits a `u64`.
    pub value: Option<u64>,
    /// `state` through the number.
    pub header: TextRange,
    /// The earlier state with the same number, if this one is a duplicate (HG2101).
    pub first: Option<usize>,
}

impl StateEntry {
    /// Is the number within 0..65535?
    pub fn in_range(&self) -> bool {
        self.value.is_some_and(|v| v <= 65535)
    }

    /// The state's `wait` items, in text order.
    pub fn waits(&self) -> Vec<ast::WaitItem> {
        self.body_items()
            .into_iter()
            .filter_map(|i| match i {
                ast::BodyItem::Wait(w) => Some(w),
                _ => None,
            })
            .collect()
    }

    /// The state's `supervise` items, in text order.
    pub fn supervisions(&self) -> Vec<ast::SuperviseItem> {
        self.body_items()
            .into_iter()
            .filter_map(|i| match i {
                ast::BodyItem::Supervise(s) => Some(s),
                _ => None,
            })
            .collect()
    }

    fn body_items(&self) -> Vec<ast::BodyItem> {
        self.node
            .body()
            .map(|b| b.body_items().collect())
            .unwrap_or_default()
    }
}

/// What a transition endpoint names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum End {
    /// A state number (its key: the number without leading zeros).
    State(String),
    Any,
    Return,
}

/// One endpoint of a transition.
pub(crate) struct EndpointEntry {
    pub end: End,
    pub node: ast::Endpoint,
    /// As shown in labels: the number as written, `any` or `return`.
    pub text: String,
}

/// A priority range (§2.6): the transitions leaving one state, or all any-transitions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum PrioRange {
    Any,
    /// Index of the (first) source state.
    State(usize),
}

/// One `trans` of the graph.
pub(crate) struct TransEntry {
    pub source: Option<EndpointEntry>,
    pub target: Option<EndpointEntry>,
    /// `trans` through the target endpoint; `None` if the header did not parse.
    pub header: Option<TextRange>,
    pub prio_clause: Option<ast::PrioClause>,
    /// The explicit priority (saturating at `u64::MAX`).
    pub explicit: Option<u64>,
    pub range: Option<PrioRange>,
    /// The explicit or implicit priority; `None` outside every range.
    pub priority: Option<u64>,
    /// A startup transition (§2.6)?
    pub startup: bool,
    /// `{src}->{dst}`, with ` (prio {p})` where two transitions would share a label.
    pub label: String,
    /// The header's attributes with their lower-case keywords, in text order.
    pub attributes: Vec<(String, ast::Attribute)>,
    /// Is the condition part empty (§2.6)?
    pub empty_condition: bool,
}

impl TransEntry {
    /// A normal transition: a state to a state.
    pub fn is_normal(&self) -> bool {
        matches!(
            (self.source_end(), self.target_end()),
            (Some(End::State(_)), Some(End::State(_)))
        )
    }

    /// A return transition: a state to `return`.
    pub fn is_return(&self) -> bool {
        matches!(
            (self.source_end(), self.target_end()),
            (Some(End::State(_)), Some(End::Return))
        )
    }

    /// An any-transition.
    pub fn is_any(&self) -> bool {
        self.source_end() == Some(&End::Any)
    }

    /// What the source endpoint names, if it parsed.
    pub fn source_end(&self) -> Option<&End> {
        self.source.as_ref().map(|e| &e.end)
    }

    /// What the target endpoint names, if it parsed.
    pub fn target_end(&self) -> Option<&End> {
        self.target.as_ref().map(|e| &e.end)
    }

    /// Does the header carry the attribute `word` (lower case)?
    pub fn has(&self, word: &str) -> bool {
        self.attributes.iter().any(|(w, _)| w == word)
    }
}

/// Attributes with their lower-case keywords.
pub(crate) fn attributes(
    attrs: impl Iterator<Item = ast::Attribute>,
) -> Vec<(String, ast::Attribute)> {
    attrs
        .filter_map(|a| {
            let word = a.keyword()?.text().to_ascii_lowercase();
            Some((word, a))
        })
        .collect()
}

/// The graph as the structure rules see it.
pub(crate) struct GraphModel {
    /// The graph's name as declared.
    pub name: String,
    pub states: Vec<StateEntry>,
    /// The first state of each number key.
    by_key: HashMap<String, usize>,
    /// Every `trans` in text order.
    pub transitions: Vec<TransEntry>,
}

impl GraphModel {
    /// Reads the states and transitions of a graph and computes priorities and labels.
    pub fn new(graph: &ast::Graph) -> GraphModel {
        let name = graph.name().map(|n| n.text()).unwrap_or_default();
        let mut states: Vec<StateEntry> = Vec::new();
        let mut by_key: HashMap<String, usize> = HashMap::new();
        for node in graph.states() {
            let Some(entry) = state_entry(node) else {
                continue;
            };
            let index = states.len();
            let first = by_key.get(&entry.key).copied();
            if first.is_none() {
                by_key.insert(entry.key.clone(), index);
            }
            states.push(StateEntry { first, ..entry });
        }
        let declares_init_sd = declares_variable(graph, "INIT_SD");
        let transitions = graph
            .transitions()
            .map(|node| trans_entry(node, &by_key, declares_init_sd))
            .collect();
        let mut model = GraphModel {
            name,
            states,
            by_key,
            transitions,
        };
        model.assign_priorities();
        model.assign_labels();
        model
    }

    /// The first state with this number key.
    pub fn state(&self, key: &str) -> Option<usize> {
        self.by_key.get(key).copied()
    }

    /// Does the endpoint name an existing state?
    pub fn existing(&self, end: Option<&End>) -> Option<usize> {
        match end {
            Some(End::State(key)) => self.state(key),
            _ => None,
        }
    }

    /// The indexes of the transitions of a priority range, in text order.
    pub fn range_members(&self, range: PrioRange) -> Vec<usize> {
        (0..self.transitions.len())
            .filter(|&i| self.transitions[i].range == Some(range))
            .collect()
    }

    /// Every priority range that has at least one transition, in order of first appearance.
    pub fn ranges(&self) -> Vec<PrioRange> {
        let mut out: Vec<PrioRange> = Vec::new();
        for range in self.transitions.iter().filter_map(|t| t.range) {
            if !out.contains(&range) {
                out.push(range);
            }
        }
        out
    }

    /// The lowest priority ≥ 1 that no transition of the range has.
    pub fn lowest_free_priority(&self, range: PrioRange) -> u64 {
        let used: Vec<u64> = self
            .range_members(range)
            .into_iter()
            .filter_map(|i| self.transitions[i].priority)
            .collect();
        (1..).find(|p| !used.contains(p)).unwrap_or(1)
    }

    /// The startup transitions, in text order.
    pub fn startups(&self) -> impl Iterator<Item = &TransEntry> {
        self.transitions.iter().filter(|t| t.startup)
    }

    /// §2.6: explicit priorities as written; implicit ones the smallest integer above every
    /// earlier priority of the range that no explicit `prio` of the range uses.
    fn assign_priorities(&mut self) {
        for t in &mut self.transitions {
            if t.range.is_none() {
                t.priority = None;
            }
        }
        for range in self.ranges() {
            let members = self.range_members(range);
            let explicit: HashSet<u64> = members
                .iter()
                .filter_map(|&i| self.transitions[i].explicit)
                .collect();
            let mut highest: Option<u64> = None;
            for i in members {
                let t = &self.transitions[i];
                // A `prio` without its number (a syntax error, C1) has no known priority.
                if t.prio_clause.is_some() && t.explicit.is_none() {
                    continue;
                }
                let priority = match t.explicit {
                    Some(p) => p,
                    None => {
                        let mut p = highest.map_or(1, |h| h.saturating_add(1)).max(1);
                        while explicit.contains(&p) && p < u64::MAX {
                            p += 1;
                        }
                        p
                    }
                };
                self.transitions[i].priority = Some(priority);
                highest = Some(highest.map_or(priority, |h| h.max(priority)));
            }
        }
    }

    /// `{src}->{dst}`, disambiguated by ` (prio {p})` where labels repeat.
    fn assign_labels(&mut self) {
        let mut counts: HashMap<String, usize> = HashMap::new();
        for t in &self.transitions {
            *counts.entry(t.label.clone()).or_default() += 1;
        }
        for t in &mut self.transitions {
            if counts.get(&t.label).copied().unwrap_or(0) > 1 {
                if let Some(p) = t.priority.or(t.explicit) {
                    t.label = format!("{} (prio {p})", t.label);
                }
            }
        }
    }
}

/// The effective priority of every transition of the graph, in text order (§2.6): explicit
/// priorities as written, implicit ones computed per range; `None` for transitions that belong
/// to no priority range (source `return`, a state that does not exist, or a broken header).
// Public for the formatter, which writes implicit priorities out (`tooling.md` §2a).
#[allow(dead_code)]
pub fn effective_priorities(graph: &ast::Graph) -> Vec<Option<u64>> {
    GraphModel::new(graph)
        .transitions
        .iter()
        .map(|t| t.priority)
        .collect()
}

/// A number without leading zeros.
fn number_key(text: &str) -> String {
    let trimmed = text.trim_start_matches('0');
    if trimmed.is_empty() {
        "0".to_owned()
    } else {
        trimmed.to_owned()
    }
}

fn state_entry(node: ast::State) -> Option<StateEntry> {
    let number = node.number()?;
    let keyword = node.syntax().first_token()?;
    let header = TextRange::new(keyword.text_range().start(), number.text_range().end());
    Some(StateEntry {
        key: number_key(number.text()),
        value: number.text().parse().ok(),
        header,
        number,
        node,
        first: None,
    })
}

fn endpoint_entry(node: ast::Endpoint) -> Option<EndpointEntry> {
    let token = node.token()?;
    let (end, text) = match node.kind()? {
        ast::EndpointKind::Any => (End::Any, "any".to_owned()),
        ast::EndpointKind::Return => (End::Return, "return".to_owned()),
        ast::EndpointKind::State => (End::State(number_key(token.text())), token.text().into()),
    };
    Some(EndpointEntry { end, node, text })
}

fn trans_entry(
    node: ast::Trans,
    states: &HashMap<String, usize>,
    declares_init_sd: bool,
) -> TransEntry {
    let source = node.source().and_then(endpoint_entry);
    let target = node.target().and_then(endpoint_entry);
    let header = match (node.syntax().first_token(), &target) {
        (Some(keyword), Some(target)) => Some(TextRange::new(
            keyword.text_range().start(),
            target.node.syntax().text_range().end(),
        )),
        _ => None,
    };
    let prio_clause = node.prio();
    let explicit = prio_clause
        .as_ref()
        .and_then(|p| p.value())
        .map(|v| v.text().parse::<u64>().unwrap_or(u64::MAX));
    // A state's range holds its normal and return transitions; `s->any` is in none (HG2104).
    let range = match (&source, &target, header) {
        (Some(s), Some(t), Some(_)) => match (&s.end, &t.end) {
            (End::Any, _) => Some(PrioRange::Any),
            (End::State(key), End::State(_) | End::Return) => {
                states.get(key).map(|&i| PrioRange::State(i))
            }
            _ => None,
        },
        _ => None,
    };
    let startup = source.as_ref().is_some_and(|s| s.end == End::Any)
        && !declares_init_sd
        && condition_statements(&node).any(|s| queries_init_sd(&s));
    let label = format!(
        "{}->{}",
        source.as_ref().map_or("?", |e| e.text.as_str()),
        target.as_ref().map_or("?", |e| e.text.as_str())
    );
    let attributes = attributes(node.attributes());
    let empty_condition = !condition_statements(&node).any(|s| s.opcode().is_some());
    TransEntry {
        attributes,
        empty_condition,
        source,
        target,
        header,
        prio_clause,
        explicit,
        range,
        priority: None,
        startup,
        label,
    }
}

/// The condition part of a transition (§2.6): the statements before the first label and every
/// `?:` block.
pub(crate) fn condition_statements(trans: &ast::Trans) -> impl Iterator<Item = ast::StlStmt> {
    trans
        .body()
        .into_iter()
        .flat_map(|b| b.blocks())
        .filter(|b| b.label().is_none_or(|l| l.name() == "?"))
        .flat_map(|b| b.statements())
}

/// Does the graph declare a variable of this name (any section)?
fn declares_variable(graph: &ast::Graph, name: &str) -> bool {
    graph
        .var_sections()
        .flat_map(|s| s.decls())
        .filter_map(|d| d.name())
        .any(|n| n.text().eq_ignore_ascii_case(name))
}

/// Does a statement have an operand `INIT_SD` or `#INIT_SD` (the predefined variable, as the
/// graph declares no variable of that name)? Statements that are not analysed (jump labels,
/// operations of neither mnemonic set: C4) do not count.
fn queries_init_sd(stmt: &ast::StlStmt) -> bool {
    if stmt.jump_label().is_some() {
        return false;
    }
    let Some(opcode) = stmt.opcode() else {
        return false;
    };
    let op = opcode.text();
    if !lang::is_subset_op(&op, Mnemonic::Simatic)
        && !lang::is_subset_op(&op, Mnemonic::International)
    {
        return false;
    }
    let params = stmt
        .call_args()
        .into_iter()
        .flat_map(|a| a.params())
        .filter_map(|p| p.value());
    stmt.operand().into_iter().chain(params).any(|operand| {
        let name = match operand {
            ast::Operand::NameRef(n) => n.token(),
            ast::Operand::VarRef(v) => v.name(),
            _ => None,
        };
        name.is_some_and(|t| {
            t.kind() == SyntaxKind::IDENT && t.text().eq_ignore_ascii_case("INIT_SD")
        })
    })
}
