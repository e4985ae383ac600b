//! The structure of one graph as the graph rules see it: its states (with duplicates marked,
//! C3), its transitions with endpoints, priority ranges, effective priorities (§2.6), the
//! startup transitions and the labels used in messages (§2.3).
//!
//! The model is built from the cached [`MemberFacts`] of the graph's members and their
//! offsets; every range it hands out is relative to the item. Lookups the rules repeat
//! (a state by number, the transitions of a priority range, the transitions leaving a state)
//! are indexed once, so the rules stay linear in the size of the graph.

use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use higraph_syntax::{TextRange, TextSize, ast, ast::AstNode};

use super::VirtualLayout;
use super::facts::{
    AttrFact, BodyItemFact, EndFact, EndpointFact, MemberFacts, StateFacts, TransFacts,
};

/// A range from a member's facts, made relative to the item.
fn at(offset: TextSize, range: TextRange) -> TextRange {
    range + offset
}

/// An attribute of a header, with item-relative ranges.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Attr<'a> {
    /// The keyword in lower case.
    pub word: &'a str,
    pub range: TextRange,
    /// The attribute with the white space before it.
    pub removal: TextRange,
}

fn attrs(offset: TextSize, facts: &[AttrFact]) -> impl Iterator<Item = Attr<'_>> {
    facts.iter().map(move |a| Attr {
        word: &a.word,
        range: at(offset, a.range),
        removal: at(offset, a.removal),
    })
}

/// A `wait` or `supervise` item, with item-relative ranges.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BodyItem {
    pub keyword: &'static str,
    /// Without the `;`.
    pub range: TextRange,
    /// With the white space before it.
    pub removal: TextRange,
}

fn body_items(offset: TextSize, facts: &[BodyItemFact]) -> Vec<BodyItem> {
    facts
        .iter()
        .map(|i| BodyItem {
            keyword: i.keyword,
            range: at(offset, i.range),
            removal: at(offset, i.removal),
        })
        .collect()
}

/// One `state` whose number parsed.
pub(crate) struct StateEntry<'a> {
    facts: &'a StateFacts,
    offset: TextSize,
    /// The number as written.
    number: &'a str,
    /// The number, if it fits a `u64`.
    pub value: Option<u64>,
    /// The earlier state with the same number, if this one is a duplicate (HG2101).
    pub first: Option<usize>,
}

impl<'a> StateEntry<'a> {
    /// The number as written.
    pub fn number(&self) -> &'a str {
        self.number
    }

    pub fn number_range(&self) -> TextRange {
        at(self.offset, self.facts.number_range)
    }

    /// `state` through the number.
    pub fn header(&self) -> TextRange {
        at(self.offset, self.facts.header)
    }

    /// Is the number within 0..65535?
    pub fn in_range(&self) -> bool {
        self.value.is_some_and(|v| v <= 65535)
    }

    /// The state's `wait` items, in text order.
    pub fn waits(&self) -> Vec<BodyItem> {
        body_items(self.offset, &self.facts.waits)
    }

    /// The state's `supervise` items, in text order.
    pub fn supervisions(&self) -> Vec<BodyItem> {
        body_items(self.offset, &self.facts.supervisions)
    }

    pub fn has_wait(&self) -> bool {
        !self.facts.waits.is_empty()
    }
}

/// What a transition endpoint names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum End<'a> {
    /// A state number (its key: the number without leading zeros).
    State(&'a str),
    Any,
    Return,
}

/// One endpoint of a transition.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EndpointEntry<'a> {
    pub end: End<'a>,
    /// As shown in labels: the number as written, `any` or `return`.
    pub text: &'a str,
    pub range: TextRange,
}

fn endpoint(offset: TextSize, fact: &EndpointFact) -> EndpointEntry<'_> {
    EndpointEntry {
        end: match &fact.end {
            EndFact::State { key, .. } => End::State(key),
            EndFact::Any => End::Any,
            EndFact::Return => End::Return,
        },
        text: fact.text(),
        range: at(offset, fact.range),
    }
}

/// A priority range (§2.6): the transitions leaving one state, or all any-transitions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum PrioRange {
    Any,
    /// Index of the (first) source state.
    State(usize),
}

/// One `trans` of the graph.
pub(crate) struct TransEntry<'a> {
    facts: &'a TransFacts,
    offset: TextSize,
    pub source: Option<EndpointEntry<'a>>,
    pub target: Option<EndpointEntry<'a>>,
    /// The state the source names, if it exists.
    pub source_state: Option<usize>,
    /// The state the target names, if it exists.
    pub target_state: Option<usize>,
    /// The explicit priority (saturating at `u64::MAX`); `None` for a negative one.
    pub explicit: Option<u64>,
    /// A negative explicit priority (`prio -1`; an `INT` may be negative, language.md §1.5)
    /// by its magnitude (saturating at `u64::MAX`). It is outside 1..65535 (HG2303) and has
    /// no place in the order of its range: the transition gets no effective priority, as
    /// with a `prio` without a number. The implicit priorities of the range are what they
    /// would be if it counted as a number below 1.
    pub negative: Option<u64>,
    pub range: Option<PrioRange>,
    /// The explicit or implicit priority; `None` outside every range.
    pub priority: Option<u64>,
    /// A startup transition (§2.6)?
    pub startup: bool,
    /// Does another transition have the same `{src}->{dst}`?
    shared_label: bool,
}

impl<'a> TransEntry<'a> {
    /// `trans` through the target endpoint; `None` if the header did not parse.
    pub fn header(&self) -> Option<TextRange> {
        self.facts.header.map(|h| at(self.offset, h))
    }

    /// The `prio` clause's range, if there is one.
    pub fn prio_range(&self) -> Option<TextRange> {
        self.facts.prio.as_ref().map(|p| at(self.offset, p.range))
    }

    /// The explicit priority as a signed number (for comparing explicit priorities, HG2301,
    /// HG2302, and the range check, HG2303).
    pub fn explicit_value(&self) -> Option<i128> {
        match (self.explicit, self.negative) {
            (Some(p), _) => Some(i128::from(p)),
            (None, Some(m)) => Some(-i128::from(m)),
            (None, None) => None,
        }
    }

    /// The number of the `prio` clause as written (empty if there is none).
    pub fn prio_text(&self) -> &'a str {
        self.facts
            .prio
            .as_ref()
            .and_then(|p| p.value.as_deref())
            .unwrap_or_default()
    }

    /// The header's attributes, in text order.
    pub fn attributes(&self) -> impl Iterator<Item = Attr<'a>> + use<'a> {
        attrs(self.offset, &self.facts.attributes)
    }

    /// Is the condition part empty (§2.6)?
    pub fn empty_condition(&self) -> bool {
        self.facts.empty_condition
    }

    /// `{src}->{dst}`, with ` (prio {p})` where two transitions would share a label (§2.3).
    pub fn label(&self) -> String {
        let plain = format!(
            "{}->{}",
            label_key(self.source.as_ref()),
            label_key(self.target.as_ref())
        );
        match self.label_priority() {
            Some(p) => format!("{plain} (prio {p})"),
            None => plain,
        }
    }

    /// The priority the transition's label shows: its effective priority (explicit outside
    /// every range) if another transition has the same `{src}->{dst}`, else `None`.
    pub fn label_priority(&self) -> Option<u64> {
        self.priority
            .or(self.explicit)
            .filter(|_| self.shared_label)
    }

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
        self.source_end() == Some(End::Any)
    }

    /// What the source endpoint names, if it parsed.
    pub fn source_end(&self) -> Option<End<'a>> {
        self.source.map(|e| e.end)
    }

    /// What the target endpoint names, if it parsed.
    pub fn target_end(&self) -> Option<End<'a>> {
        self.target.map(|e| e.end)
    }

    /// Does the header carry the attribute `word` (lower case)?
    pub fn has(&self, word: &str) -> bool {
        self.facts.attributes.iter().any(|a| a.word == word)
    }
}

/// The graph as the structure rules see it.
pub(crate) struct GraphModel<'a> {
    /// The graph's name as declared.
    pub name: String,
    pub states: Vec<StateEntry<'a>>,
    /// The first state of each number key.
    by_key: HashMap<&'a str, usize>,
    /// Every `trans` in text order.
    pub transitions: Vec<TransEntry<'a>>,
    /// The priority ranges with transitions, in order of first appearance, with their
    /// transitions in text order.
    ranges: Vec<(PrioRange, Vec<usize>)>,
    /// Per state: the normal and return transitions leaving it, in text order.
    leaving: Vec<Vec<usize>>,
    /// The attributes of every state (numbered or not) with the state's offset, in text
    /// order (HG2106).
    state_attributes: Vec<(TextSize, &'a [AttrFact])>,
    /// `wait`/`supervise` items of transitions and `permanent` blocks, in text order.
    pub misplaced: Vec<BodyItem>,
    /// Where the members stand.
    pub layout: VirtualLayout,
}

impl<'a> GraphModel<'a> {
    /// Builds the model from the facts of the graph's members, placed in `layout`.
    /// `declares_init_sd`: the graph declares a variable `INIT_SD` (then no transition is a
    /// startup transition).
    pub fn new(
        name: String,
        members: impl IntoIterator<Item = &'a MemberFacts>,
        declares_init_sd: bool,
        layout: VirtualLayout,
    ) -> GraphModel<'a> {
        let mut model = GraphModel {
            name,
            states: Vec::new(),
            by_key: HashMap::default(),
            transitions: Vec::new(),
            ranges: Vec::new(),
            leaving: Vec::new(),
            state_attributes: Vec::new(),
            misplaced: Vec::new(),
            layout,
        };
        let mut trans_facts = Vec::new();
        for (ordinal, facts) in members.into_iter().enumerate() {
            let offset = model.layout.offset(ordinal);
            match facts {
                MemberFacts::State(state) => {
                    model.state_attributes.push((offset, &state.attributes));
                    let Some(number) = &state.number else {
                        continue;
                    };
                    let key = state.key.as_str();
                    let index = model.states.len();
                    let first = model.by_key.get(key).copied();
                    if first.is_none() {
                        model.by_key.insert(key, index);
                    }
                    model.states.push(StateEntry {
                        facts: state,
                        offset,
                        number,
                        value: key.parse().ok(),
                        first,
                    });
                }
                MemberFacts::Trans(trans) => {
                    model.misplaced.extend(body_items(offset, &trans.misplaced));
                    trans_facts.push((offset, trans));
                }
                MemberFacts::Permanent { misplaced } => {
                    model.misplaced.extend(body_items(offset, misplaced));
                }
                MemberFacts::Other => {}
            }
        }
        model.transitions = trans_facts
            .into_iter()
            .map(|(offset, facts)| model.trans_entry(offset, facts, declares_init_sd))
            .collect();
        model.index_ranges();
        model.assign_priorities();
        model.mark_shared_labels();
        model
    }

    fn trans_entry(
        &self,
        offset: TextSize,
        facts: &'a TransFacts,
        declares_init_sd: bool,
    ) -> TransEntry<'a> {
        let source = facts.source.as_ref().map(|e| endpoint(offset, e));
        let target = facts.target.as_ref().map(|e| endpoint(offset, e));
        let source_state = self.existing(source.map(|e| e.end));
        let target_state = self.existing(target.map(|e| e.end));
        let written = facts.prio.as_ref().and_then(|p| p.value.as_deref());
        let (explicit, negative) = match written.map(parse_priority) {
            Some((false, p)) => (Some(p), None),
            Some((true, m)) => (None, Some(m)),
            None => (None, None),
        };
        // A state's range holds its normal and return transitions; `s->any` is in none (HG2104).
        let range = match (&source, &target, facts.header) {
            (Some(s), Some(t), Some(_)) => match (s.end, t.end) {
                (End::Any, _) => Some(PrioRange::Any),
                (End::State(_), End::State(_) | End::Return) => source_state.map(PrioRange::State),
                _ => None,
            },
            _ => None,
        };
        TransEntry {
            facts,
            offset,
            source,
            target,
            source_state,
            target_state,
            explicit,
            negative,
            range,
            priority: None,
            startup: facts.queries_init_sd && !declares_init_sd,
            shared_label: false,
        }
    }

    /// The attributes of every state header (numbered or not) and then of every transition
    /// header, in text order (HG2106).
    pub fn headers(&self) -> impl Iterator<Item = impl Iterator<Item = Attr<'a>>> + '_ {
        let transitions = self
            .transitions
            .iter()
            .map(|t| (t.offset, t.facts.attributes.as_slice()));
        self.state_attributes
            .iter()
            .copied()
            .chain(transitions)
            .map(|(offset, facts)| attrs(offset, facts))
    }

    /// The first state with this number key.
    pub fn state(&self, key: &str) -> Option<usize> {
        self.by_key.get(key).copied()
    }

    /// Does the endpoint name an existing state?
    pub fn existing(&self, end: Option<End<'_>>) -> Option<usize> {
        match end {
            Some(End::State(key)) => self.state(key),
            _ => None,
        }
    }

    /// The indexes of the transitions of a priority range, in text order.
    pub fn range_members(&self, range: PrioRange) -> &[usize] {
        self.ranges
            .iter()
            .find(|(r, _)| *r == range)
            .map_or(&[], |(_, members)| members)
    }

    /// Every priority range that has at least one transition, in order of first appearance,
    /// with its transitions.
    pub fn ranges(&self) -> &[(PrioRange, Vec<usize>)] {
        &self.ranges
    }

    /// The normal and return transitions leaving state `state`, in text order.
    pub fn leaving(&self, state: usize) -> &[usize] {
        self.leaving.get(state).map_or(&[], |l| l)
    }

    /// The lowest priority ≥ 1 that no transition of the range has.
    pub fn lowest_free_priority(&self, range: PrioRange) -> u64 {
        let used: HashSet<u64> = self
            .range_members(range)
            .iter()
            .filter_map(|&i| self.transitions[i].priority)
            .collect();
        (1..).find(|p| !used.contains(p)).unwrap_or(1)
    }

    /// The startup transitions, in text order.
    pub fn startups(&self) -> impl Iterator<Item = &TransEntry<'a>> {
        self.transitions.iter().filter(|t| t.startup)
    }

    fn index_ranges(&mut self) {
        let mut position: HashMap<PrioRange, usize> =
            HashMap::with_capacity_and_hasher(self.states.len() + 1, Default::default());
        self.leaving = vec![Vec::new(); self.states.len()];
        for (i, t) in self.transitions.iter().enumerate() {
            if let Some(range) = t.range {
                let at = *position.entry(range).or_insert_with(|| {
                    self.ranges.push((range, Vec::new()));
                    self.ranges.len() - 1
                });
                self.ranges[at].1.push(i);
            }
            if let (true, Some(source)) = (t.is_normal() || t.is_return(), t.source_state) {
                self.leaving[source].push(i);
            }
        }
    }

    /// §2.6: explicit priorities as written; implicit ones the smallest integer above every
    /// earlier priority of the range that no explicit `prio` of the range uses.
    fn assign_priorities(&mut self) {
        for (_, members) in &self.ranges {
            let explicit: HashSet<u64> = members
                .iter()
                .filter_map(|&i| self.transitions[i].explicit)
                .collect();
            let mut highest: Option<u64> = None;
            for &i in members {
                let t = &self.transitions[i];
                // A `prio` without its number (a syntax error, C1) has no known priority.
                if t.facts.prio.is_some() && t.explicit.is_none() {
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

    /// Marks the transitions whose `{src}->{dst}` another transition shares.
    fn mark_shared_labels(&mut self) {
        let plain =
            |t: &TransEntry<'a>| (label_key(t.source.as_ref()), label_key(t.target.as_ref()));
        let mut counts: HashMap<(&str, &str), usize> =
            HashMap::with_capacity_and_hasher(self.transitions.len(), Default::default());
        for t in &self.transitions {
            *counts.entry(plain(t)).or_default() += 1;
        }
        for t in &mut self.transitions {
            t.shared_label = counts.get(&plain(t)).copied().unwrap_or(0) > 1;
        }
    }
}

/// The effective priority of every transition of the graph, in text order (§2.6): explicit
/// priorities as written, implicit ones computed per range; `None` for transitions that belong
/// to no priority range (source `return`, a state that does not exist, or a broken header).
// Public for the formatter, which writes implicit priorities out (`tooling.md` §2a).
pub fn effective_priorities(graph: &ast::Graph) -> Vec<Option<u64>> {
    let members: Vec<_> = graph
        .body()
        .into_iter()
        .flat_map(|b| b.syntax().children())
        .collect();
    let facts: Vec<MemberFacts> = members.iter().map(MemberFacts::of).collect();
    // The members where they stand: the virtual layout holds only so many members (and the
    // positions do not matter here).
    let offsets = members.iter().map(|m| m.text_range().start()).collect();
    let model = GraphModel::new(String::new(), &facts, false, VirtualLayout::Real(offsets));
    model.transitions.iter().map(|t| t.priority).collect()
}

/// A priority as written: whether it is negative (`-0` is not), and its magnitude (too large
/// values become `u64::MAX`).
fn parse_priority(text: &str) -> (bool, u64) {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(digits) => (true, digits),
        None => (false, text),
    };
    let magnitude = digits.parse::<u64>().unwrap_or(u64::MAX);
    (negative && magnitude > 0, magnitude)
}

/// An endpoint as transition labels show it (§2.3): a state number without leading zeros,
/// `any`, `return`, or `?` if it did not parse.
fn label_key<'a>(end: Option<&EndpointEntry<'a>>) -> &'a str {
    match end.map(|e| e.end) {
        Some(End::State(key)) => key,
        Some(End::Any) => "any",
        Some(End::Return) => "return",
        None => "?",
    }
}
