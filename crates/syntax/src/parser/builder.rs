//! Building the green tree.
//!
//! rowan's `GreenNodeBuilder` keeps every finished child as a `GreenToken` or `GreenNode`,
//! which are atomically reference-counted: each token costs a hash lookup in its `NodeCache`
//! *and* an atomic increment, and a small node that turns out to be a duplicate drops those
//! references again. Profiles showed this as the largest part of parsing. This builder does the
//! same job with interning fitted to the parser:
//!
//! * Every distinct token (by kind and text, the text borrowed from the input) is created
//!   once and given a number. Punctuation, whose text is fixed per kind, is looked up by kind
//!   alone; other tokens by a [`TokenKey`] that hashes and compares short texts as integers.
//!   The children stack holds these numbers, not reference-counted handles.
//! * A node with at most [`MAX_INTERNED`] children that are all tokens or interned nodes is
//!   interned the same way, by kind and its children's numbers. A repeated node (`NAME_REF`
//!   of the same name, the same `OPCODE`, the same short `STL_STMT`) costs a lookup and
//!   touches no reference count; only a new node clones its children's handles. Nodes of a
//!   single token are found without hashing (`TreeBuilder::wrapped`).
//! * Larger nodes are built directly and owned by the stack until their parent takes them.
//!
//! Green nodes compare structurally, so how nodes and tokens are shared does not change the
//! tree.

use std::hash::{Hash, Hasher};

use rowan::{GreenNode, GreenToken, NodeOrToken};
use rustc_hash::FxHashMap;

use crate::{SyntaxKind, SyntaxKind::*};

/// Nodes with more children are never interned (they rarely repeat).
const MAX_INTERNED: usize = 4;

/// A finished child of an open node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Child {
    /// Index into `TreeBuilder::tokens`.
    Token(u32),
    /// Index into `TreeBuilder::nodes`.
    Interned(u32),
    /// The next node of `TreeBuilder::owned` (owned nodes are taken in stack order).
    Owned,
}

/// Identity of an internable node: its kind, its number of children and the children's
/// numbers (tokens as is, nodes with bit 31 set), packed so that it hashes quickly.
type NodeKey = [u64; 3];

/// Marks a place in the children stack where a node may later be started
/// ([`TreeBuilder::start_node_at`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Checkpoint(usize);

pub(crate) struct TreeBuilder<'t> {
    /// Open nodes: kind and the index of their first child in `children`.
    parents: Vec<(SyntaxKind, usize)>,
    /// Finished children of all open nodes, innermost last.
    children: Vec<Child>,
    /// Nodes that are not interned, in the order of their `Child::Owned` entries.
    owned: Vec<GreenNode>,
    /// Distinct tokens.
    tokens: Vec<GreenToken>,
    /// Numbers of the fixed-text tokens (punctuation) by kind, `u32::MAX` if not yet created.
    fixed: Vec<u32>,
    /// Numbers of the white-space tokens that are a line break and indentation, or only
    /// spaces, by [`indentation_slot`]; `u32::MAX` if not yet created. Half of all tokens are
    /// such white space.
    indentation: Vec<u32>,
    /// Numbers of all other tokens by kind and text.
    token_ids: FxHashMap<TokenKey<'t>, u32>,
    /// For each token: the last node that wraps just this token, as (kind, node number).
    /// Most one-token nodes (`NAME_REF`, `OPCODE`, `LITERAL`, ...) wrap a given token with
    /// the same kind every time, so this answers them without a hash lookup.
    wrapped: Vec<(SyntaxKind, u32)>,
    /// Interned nodes.
    nodes: Vec<GreenNode>,
    node_ids: FxHashMap<NodeKey, u32>,
}

impl<'t> TreeBuilder<'t> {
    pub(crate) fn new() -> TreeBuilder<'t> {
        TreeBuilder {
            parents: Vec::with_capacity(32),
            children: Vec::with_capacity(256),
            owned: Vec::with_capacity(64),
            tokens: Vec::new(),
            fixed: vec![u32::MAX; LEX_ERROR as usize],
            indentation: vec![u32::MAX; 2 * MAX_INDENT],
            token_ids: FxHashMap::default(),
            wrapped: Vec::new(),
            nodes: Vec::new(),
            node_ids: FxHashMap::default(),
        }
    }

    /// Adds a token to the current node.
    pub(crate) fn token(&mut self, kind: SyntaxKind, text: &'t str) {
        let id = if is_fixed(kind) {
            let slot = self.fixed[kind as usize];
            if slot == u32::MAX {
                let id = self.new_token(kind, text);
                self.fixed[kind as usize] = id;
                id
            } else {
                debug_assert_eq!(self.tokens[slot as usize].text(), text);
                slot
            }
        } else if let Some(slot) = indentation_slot(kind, text) {
            let id = self.indentation[slot];
            if id == u32::MAX {
                let id = self.new_token(kind, text);
                self.indentation[slot] = id;
                id
            } else {
                id
            }
        } else {
            let key = TokenKey::new(kind, text);
            match self.token_ids.get(&key) {
                Some(&id) => id,
                None => {
                    let id = self.new_token(kind, text);
                    self.token_ids.insert(key, id);
                    id
                }
            }
        };
        self.children.push(Child::Token(id));
    }

    fn new_token(&mut self, kind: SyntaxKind, text: &str) -> u32 {
        self.wrapped.push((EOF_KIND, 0));
        push_id(&mut self.tokens, GreenToken::new(kind.into(), text))
    }

    pub(crate) fn start_node(&mut self, kind: SyntaxKind) {
        self.parents.push((kind, self.children.len()));
    }

    pub(crate) fn finish_node(&mut self) {
        let (kind, first) = self
            .parents
            .pop()
            .expect("finish_node without a matching start_node");
        let children = &self.children[first..];
        if let [Child::Token(token)] = *children {
            let (wrapper, id) = self.wrapped[token as usize];
            if wrapper == kind {
                self.children.truncate(first);
                self.children.push(Child::Interned(id));
                return;
            }
        }
        let child = match intern_key(kind, children) {
            Some(key) => match self.node_ids.get(&key) {
                Some(&id) => Child::Interned(id),
                None => {
                    let node = self.build(kind, first);
                    let id = push_id(&mut self.nodes, node);
                    self.node_ids.insert(key, id);
                    Child::Interned(id)
                }
            },
            None => {
                let node = self.build(kind, first);
                self.owned.push(node);
                Child::Owned
            }
        };
        if let ([Child::Token(token)], Child::Interned(id)) = (&self.children[first..], child) {
            self.wrapped[*token as usize] = (kind, id);
        }
        self.children.truncate(first);
        self.children.push(child);
    }

    /// Creates the node of `kind` whose children are `children[first..]`, taking the owned
    /// ones off `owned`.
    fn build(&mut self, kind: SyntaxKind, first: usize) -> GreenNode {
        let children = &self.children[first..];
        let owned_count = children.iter().filter(|c| **c == Child::Owned).count();
        let mut owned = self.owned.drain(self.owned.len() - owned_count..);
        let (tokens, nodes) = (&self.tokens, &self.nodes);
        let elements = children.iter().map(|child| match *child {
            Child::Token(id) => NodeOrToken::Token(tokens[id as usize].clone()),
            Child::Interned(id) => NodeOrToken::Node(nodes[id as usize].clone()),
            Child::Owned => NodeOrToken::Node(
                owned
                    .next()
                    .expect("every owned child has its node on the stack"),
            ),
        });
        GreenNode::new(kind.into(), elements)
    }

    pub(crate) fn checkpoint(&self) -> Checkpoint {
        Checkpoint(self.children.len())
    }

    /// Starts a node whose first child is the element added right after `checkpoint`.
    pub(crate) fn start_node_at(&mut self, checkpoint: Checkpoint, kind: SyntaxKind) {
        let Checkpoint(at) = checkpoint;
        debug_assert!(at <= self.children.len());
        debug_assert!(self.parents.last().is_none_or(|&(_, first)| at >= first));
        self.parents.push((kind, at));
    }

    /// The root node: the one element left once every node is finished.
    pub(crate) fn finish(mut self) -> GreenNode {
        debug_assert!(self.parents.is_empty() && self.children.len() == 1);
        match self.children.pop() {
            Some(Child::Owned) => self.owned.pop(),
            Some(Child::Interned(id)) => self.nodes.get(id as usize).cloned(),
            _ => None,
        }
        .expect("the parser must leave exactly one root node")
    }
}

/// The interning key of a node, or `None` if the node is not interned (too many children, or
/// a child that is not interned).
fn intern_key(kind: SyntaxKind, children: &[Child]) -> Option<NodeKey> {
    /// Marks node numbers; numbers at or above it are not interned (no file comes close).
    const NODE_BIT: u32 = 1 << 31;
    if children.len() > MAX_INTERNED {
        return None;
    }
    let mut ids = [0u64; MAX_INTERNED];
    for (slot, &child) in ids.iter_mut().zip(children) {
        let id = match child {
            Child::Token(id) if id < NODE_BIT => id,
            Child::Interned(id) if id < NODE_BIT => id | NODE_BIT,
            _ => return None,
        };
        *slot = u64::from(id);
    }
    let head = kind as u64 | (children.len() as u64) << 16;
    Some([head | ids[0] << 32, ids[1] | ids[2] << 32, ids[3]])
}

/// Marks an unused `TreeBuilder::wrapped` entry (no node has this kind).
const EOF_KIND: SyntaxKind = SyntaxKind::__LAST_TOKEN;

/// A token's kind and text, with the text's length, first and last eight bytes read out up
/// front: these decide hashing, and equality for texts of up to 16 bytes (almost all tokens),
/// without a call to `memcmp`.
#[derive(Debug, Clone, Copy)]
struct TokenKey<'t> {
    text: &'t str,
    /// Kind and length.
    head: u64,
    /// The first eight bytes (zero-padded) and the last eight (zero if shorter than nine).
    first: u64,
    last: u64,
}

impl<'t> TokenKey<'t> {
    fn new(kind: SyntaxKind, text: &'t str) -> TokenKey<'t> {
        let bytes = text.as_bytes();
        let (first, last) = match bytes.len() {
            0..=8 => {
                let mut first = 0u64;
                for (i, &b) in bytes.iter().enumerate() {
                    first |= u64::from(b) << (8 * i);
                }
                (first, 0)
            }
            len => (read_u64(&bytes[..8]), read_u64(&bytes[len - 8..])),
        };
        TokenKey {
            text,
            head: kind as u64 | (bytes.len() as u64) << 16,
            first,
            last,
        }
    }
}

fn read_u64(bytes: &[u8]) -> u64 {
    let mut word = [0u8; 8];
    word.copy_from_slice(bytes);
    u64::from_le_bytes(word)
}

impl PartialEq for TokenKey<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.head == other.head
            && self.first == other.first
            && self.last == other.last
            && (self.text.len() <= 16 || self.text == other.text)
    }
}

impl Eq for TokenKey<'_> {}

impl Hash for TokenKey<'_> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(self.head);
        state.write_u64(self.first);
        state.write_u64(self.last);
    }
}

/// Appends `value` and returns its index.
fn push_id<T>(values: &mut Vec<T>, value: T) -> u32 {
    let id = u32::try_from(values.len()).expect("fewer than 2^32 distinct tokens and nodes");
    values.push(value);
    id
}

/// Longest run of spaces with a slot in `TreeBuilder::indentation`.
const MAX_INDENT: usize = 64;

/// The slot of `text` in `TreeBuilder::indentation`: spaces only, or `\n` and spaces.
fn indentation_slot(kind: SyntaxKind, text: &str) -> Option<usize> {
    if kind != WHITESPACE {
        return None;
    }
    let (line_break, spaces) = match text.as_bytes() {
        [b'\n', rest @ ..] => (MAX_INDENT, rest),
        rest => (0, rest),
    };
    (spaces.len() < MAX_INDENT && spaces.iter().all(|&b| b == b' '))
        .then(|| line_break + spaces.len())
}

/// Kinds whose text is always the same (single-character punctuation).
fn is_fixed(kind: SyntaxKind) -> bool {
    (L_ANGLE as u16..=HASH as u16).contains(&(kind as u16))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn token_keys_tell_texts_apart() {
        let texts = [
            "",
            "a",
            "a\0",
            "ab",
            "abcdefgh",
            "abcdefgh\0",
            "abcdefghi",
            "abcdefghijklmnop",
            "abcdefghijklmnoq",
            "abcdefghijklmnopq",
            "abcdefghXjklmnopq",
            "abcdefgXijklmnopq",
        ];
        for (i, a) in texts.iter().enumerate() {
            for (j, b) in texts.iter().enumerate() {
                let equal = TokenKey::new(IDENT, a) == TokenKey::new(IDENT, b);
                assert_eq!(equal, i == j, "{a:?} vs {b:?}");
            }
            assert_ne!(TokenKey::new(IDENT, a), TokenKey::new(NUMBER, a));
        }
    }
}
