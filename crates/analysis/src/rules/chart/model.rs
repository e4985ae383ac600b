//! The element tree of one sequencer: its elements in text order (steps, transitions,
//! `parallel`, `alt`, jumps and loops at every nesting level) and the element lists they stand
//! in (the sequencer's own list and one list per branch). The topology rules and HG7311 walk it.
//!
//! Vocabulary of `diagnostics.md` §3.7: step-kind units (`step`, `parallel`), transition-kind
//! units (`trans`, `alt`) and attachments (`jump`, `loop`).

use higraph_syntax::{
    SyntaxKind, TextRange,
    ast::{self, AstNode},
};

use super::{first_token, header_range};

/// Index of an element in [`Tree::elems`].
pub(crate) type ElemId = usize;
/// Index of a list in [`Tree::lists`].
pub(crate) type ListId = usize;

/// What an element is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Step,
    Trans,
    Parallel,
    Alt,
    Jump,
    Loop,
}

impl Kind {
    /// Jumps and loops are attachments: left out when alternation is checked.
    pub fn is_attachment(self) -> bool {
        matches!(self, Kind::Jump | Kind::Loop)
    }

    /// Steps and parallels.
    pub fn is_step_kind(self) -> bool {
        matches!(self, Kind::Step | Kind::Parallel)
    }

    /// Chart transitions: `trans`, `jump` and `loop` (one name space, HG7103; HG7203).
    pub fn is_chart_transition(self) -> bool {
        matches!(self, Kind::Trans | Kind::Jump | Kind::Loop)
    }
}

/// One element of the sequencer.
pub(crate) struct Elem {
    pub node: ast::SeqElement,
    pub kind: Kind,
    /// The element's own name as declared.
    pub name: Option<String>,
    pub name_range: Option<TextRange>,
    /// The element header (§2.3).
    pub header: TextRange,
    /// The target of a jump or loop, as written.
    pub target: Option<(String, TextRange)>,
    /// The list the element stands in.
    pub list: ListId,
    /// The branches of a `parallel` or `alt`.
    pub branches: Vec<ListId>,
}

impl Elem {
    /// The element's name, or an empty string.
    pub fn label(&self) -> &str {
        self.name.as_deref().unwrap_or("")
    }

    /// The unit as messages name it (§2.7a): `step S`, `transition T`, `jump J`, `loop L`,
    /// `parallel`, `alt`.
    pub fn render(&self) -> String {
        match self.kind {
            Kind::Step => format!("step {}", self.label()),
            Kind::Trans => format!("transition {}", self.label()),
            Kind::Jump => format!("jump {}", self.label()),
            Kind::Loop => format!("loop {}", self.label()),
            Kind::Parallel => "parallel".to_owned(),
            Kind::Alt => "alt".to_owned(),
        }
    }

    /// The conditions of a `trans`, `jump` or `loop`.
    pub fn conditions(&self) -> Vec<ast::Condition> {
        match &self.node {
            ast::SeqElement::Trans(t) => t.conditions().collect(),
            ast::SeqElement::Jump(j) => j.conditions().collect(),
            ast::SeqElement::Loop(l) => l.conditions().collect(),
            _ => Vec::new(),
        }
    }
}

/// An element list: the sequencer's or a branch's.
pub(crate) struct List {
    pub elems: Vec<ElemId>,
    /// The `parallel` or `alt` whose branch this is; `None` for the sequencer's own list.
    pub owner: Option<ElemId>,
    /// The `branch` keyword.
    pub keyword: Option<TextRange>,
}

/// Is it a step, transition, jump or loop whose name did not parse?
fn is_nameless(node: &ast::SeqElement) -> bool {
    let named = matches!(
        node,
        ast::SeqElement::Step(_)
            | ast::SeqElement::Trans(_)
            | ast::SeqElement::Jump(_)
            | ast::SeqElement::Loop(_)
    );
    named
        && !node
            .syntax()
            .children()
            .any(|n| n.kind() == SyntaxKind::NAME)
}

/// The steps, transitions, jumps and loops of a sequencer whose name did not parse (left out
/// of the [`Tree`]).
pub(crate) fn nameless_elements(sequencer: &ast::Sequencer) -> Vec<ast::SeqElement> {
    sequencer
        .syntax()
        .descendants()
        .filter_map(ast::SeqElement::cast)
        .filter(is_nameless)
        .collect()
}

/// The elements and lists of one sequencer.
pub(crate) struct Tree {
    /// In text order (pre-order).
    pub elems: Vec<Elem>,
    /// List 0 is the sequencer's own list.
    pub lists: Vec<List>,
}

impl Tree {
    /// Builds the tree of a sequencer.
    pub fn build(sequencer: &ast::Sequencer) -> Tree {
        let mut tree = Tree {
            elems: Vec::new(),
            lists: vec![List {
                elems: Vec::new(),
                owner: None,
                keyword: None,
            }],
        };
        for element in sequencer.elements() {
            tree.add(0, element);
        }
        tree
    }

    fn add(&mut self, list: ListId, node: ast::SeqElement) {
        if is_nameless(&node) {
            // C1: an element whose name did not parse is not declared and takes no part in the
            // topology; its body is still walked (see `nameless_elements`).
            return;
        }
        let id = self.elems.len();
        let kind = match &node {
            ast::SeqElement::Step(_) => Kind::Step,
            ast::SeqElement::Trans(_) => Kind::Trans,
            ast::SeqElement::Parallel(_) => Kind::Parallel,
            ast::SeqElement::Alt(_) => Kind::Alt,
            ast::SeqElement::Jump(_) => Kind::Jump,
            ast::SeqElement::Loop(_) => Kind::Loop,
        };
        let syntax = node.syntax().clone();
        let name = syntax
            .children()
            .find(|n| n.kind() == SyntaxKind::NAME)
            .and_then(|n| first_token(&n));
        let target = match &node {
            ast::SeqElement::Jump(j) => j.target(),
            ast::SeqElement::Loop(l) => l.target(),
            _ => None,
        }
        .and_then(|t| t.token())
        .map(|t| (t.text().to_owned(), t.text_range()));
        let branches: Vec<ast::Branch> = match &node {
            ast::SeqElement::Parallel(p) => p.branches().collect(),
            ast::SeqElement::Alt(a) => a.branches().collect(),
            _ => Vec::new(),
        };
        self.elems.push(Elem {
            node,
            kind,
            name: name.as_ref().map(|t| t.text().to_owned()),
            name_range: name.as_ref().map(|t| t.text_range()),
            header: header_range(&syntax),
            target,
            list,
            branches: Vec::new(),
        });
        self.lists[list].elems.push(id);
        for branch in branches {
            let branch_list = self.lists.len();
            self.lists.push(List {
                elems: Vec::new(),
                owner: Some(id),
                keyword: first_token(branch.syntax()).map(|t| t.text_range()),
            });
            self.elems[id].branches.push(branch_list);
            for element in branch.elements() {
                self.add(branch_list, element);
            }
        }
    }

    /// The units of a list (attachments left out).
    pub fn units(&self, list: ListId) -> Vec<ElemId> {
        self.lists[list]
            .elems
            .iter()
            .copied()
            .filter(|&e| !self.elems[e].kind.is_attachment())
            .collect()
    }

    /// The element a jump or loop is attached to: the nearest element before it in its list
    /// that is not an attachment.
    pub fn attached_to(&self, elem: ElemId) -> Option<ElemId> {
        let list = &self.lists[self.elems[elem].list].elems;
        let position = list.iter().position(|&e| e == elem)?;
        list[..position]
            .iter()
            .rev()
            .copied()
            .find(|&e| !self.elems[e].kind.is_attachment())
    }

    /// The source of a jump that is the first element of an `alt` branch (an IEC branch that
    /// consists of a jump, `docs/iec.md` §2): the unit before the `alt`.
    pub fn branch_jump_source(&self, elem: ElemId) -> Option<ElemId> {
        if self.elems[elem].kind != Kind::Jump {
            return None;
        }
        let list = &self.lists[self.elems[elem].list];
        let owner = list.owner?;
        if list.elems.first() != Some(&elem) || self.elems[owner].kind != Kind::Alt {
            return None;
        }
        self.attached_to(owner)
    }

    /// The jumps and loops attached to an element, in text order.
    pub fn attachments(&self, elem: ElemId) -> Vec<ElemId> {
        let list = &self.lists[self.elems[elem].list].elems;
        let Some(position) = list.iter().position(|&e| e == elem) else {
            return Vec::new();
        };
        list[position + 1..]
            .iter()
            .copied()
            .take_while(|&e| self.elems[e].kind.is_attachment())
            .collect()
    }

    /// The first step of that name at any nesting level (C3: duplicates bind to the first).
    pub fn step_named(&self, name: &str) -> Option<ElemId> {
        self.elems.iter().position(|e| {
            e.kind == Kind::Step
                && e.name
                    .as_deref()
                    .is_some_and(|n| n.eq_ignore_ascii_case(name))
        })
    }

    /// Is there a chart transition (`trans`, `jump`, `loop`) of that name?
    pub fn transition_named(&self, name: &str) -> bool {
        self.elems.iter().any(|e| {
            e.kind.is_chart_transition()
                && e.name
                    .as_deref()
                    .is_some_and(|n| n.eq_ignore_ascii_case(name))
        })
    }

    /// The steps of the sequencer in text order.
    pub fn steps(&self) -> impl Iterator<Item = ElemId> + '_ {
        (0..self.elems.len()).filter(|&e| self.elems[e].kind == Kind::Step)
    }

    /// Does the list contain the element, at any depth?
    pub fn contains(&self, list: ListId, elem: ElemId) -> bool {
        let mut current = self.elems[elem].list;
        loop {
            if current == list {
                return true;
            }
            match self.lists[current].owner {
                Some(owner) => current = self.elems[owner].list,
                None => return false,
            }
        }
    }

    /// Every branch list of every `parallel`.
    pub fn parallel_branches(&self) -> Vec<ListId> {
        self.elems
            .iter()
            .filter(|e| e.kind == Kind::Parallel)
            .flat_map(|e| e.branches.iter().copied())
            .collect()
    }

    /// The first steps of a step-kind unit: a step itself; the first steps of each branch of
    /// a parallel.
    pub fn first_steps(&self, unit: ElemId) -> Vec<ElemId> {
        match self.elems[unit].kind {
            Kind::Step => vec![unit],
            Kind::Parallel => self.elems[unit]
                .branches
                .iter()
                .filter_map(|&b| self.units(b).first().copied())
                .filter(|&u| self.elems[u].kind.is_step_kind())
                .flat_map(|u| self.first_steps(u))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The unit that follows an element: the next unit of its list, or, at the end of a
    /// branch, the unit that follows the enclosing `parallel` or `alt`.
    pub fn next_unit(&self, elem: ElemId) -> Option<ElemId> {
        let list = &self.lists[self.elems[elem].list];
        let position = list.elems.iter().position(|&e| e == elem)?;
        let next = list.elems[position + 1..]
            .iter()
            .copied()
            .find(|&e| !self.elems[e].kind.is_attachment());
        match next {
            Some(next) => Some(next),
            None => list.owner.and_then(|owner| self.next_unit(owner)),
        }
    }
}
