//! Building the green tree.
//!
//! rowan's `GreenNodeBuilder` keeps every finished child as a `GreenToken` or `GreenNode`,
//! which are atomically reference-counted: each token costs a hash lookup in its `NodeCache`
//! *and* an atomic increment, and a small node that turns out to be a duplicate drops those
//! references again. Profiles showed this as the largest part of parsing. This builder does the
//! same job with interning fitted to the parser:
//!
//! * Every distinct token (by kind and text, the text borrowed from the input) is created
//!   once and given a number, as the parser lexes it ([`TreeBuilder::intern_token`]).
//!   Punctuation, whose text is fixed per kind, is looked up by kind alone, indentation by
//!   its length; other tokens in a [`TokenTable`] by a [`TokenKey`] that hashes and compares
//!   short texts as integers. The grammar then adds tokens by number.
//! * The children stack holds these numbers ([`Child`]), not reference-counted handles.
//! * A node with at most [`MAX_INTERNED`] children that are all tokens or interned nodes is
//!   interned the same way, by kind and its children's numbers. A repeated node (`NAME_REF`
//!   of the same name, the same `OPCODE`, the same short `STL_STMT`) costs a lookup and
//!   touches no reference count; only a new node clones its children's handles. Nodes of a
//!   single token are found without hashing (`TreeBuilder::wrapped`,
//!   [`TreeBuilder::push_wrapped`]).
//! * Larger nodes are built directly and owned by the stack until their parent takes them.
//!
//! Green nodes compare structurally, so how nodes and tokens are shared does not change the
//! tree.

use rowan::{GreenNode, GreenToken, NodeOrToken};
use rustc_hash::FxHashMap;

use crate::{SyntaxKind, SyntaxKind::*};

/// Nodes with more children are never interned (they rarely repeat).
const MAX_INTERNED: usize = 4;

/// A finished child of an open node, packed into a `u32` so that the children stack is a
/// plain array of numbers (runs of trivia are copied onto it with one `memcpy`):
///
/// * a token number (below [`NODE_BIT`]), an index into `TreeBuilder::tokens`;
/// * [`NODE_BIT`] plus a node number, an index into `TreeBuilder::nodes` (interned nodes);
/// * [`OWNED`]: the next node of `TreeBuilder::owned` (owned nodes are taken in stack order).
type Child = u32;

/// Marks interned node numbers in a [`Child`].
const NODE_BIT: u32 = 1 << 30;

/// A child that is not interned but owned by the stack.
const OWNED: Child = u32::MAX;

/// Identity of an internable node: its kind, its number of children and the children's
/// [`Child`] numbers, packed so that it hashes quickly.
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
    /// Nodes that are not interned, in the order of their [`OWNED`] entries.
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
    token_ids: TokenTable<'t>,
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
            token_ids: TokenTable::new(),
            wrapped: Vec::new(),
            nodes: Vec::new(),
            node_ids: FxHashMap::default(),
        }
    }

    /// The number of the token of `kind` and `text`, created on first use. The parser
    /// interns every token once, as it is lexed, and adds it to the tree by number
    /// ([`TreeBuilder::push_token`], [`TreeBuilder::push_tokens`]).
    ///
    /// Punctuation and indentation (two thirds of all tokens) are found here without hashing;
    /// the rest in [`TreeBuilder::intern_token_slow`].
    #[inline]
    pub(crate) fn intern_token(&mut self, kind: SyntaxKind, text: &'t str) -> u32 {
        let id = if is_fixed(kind) {
            self.fixed[kind as usize]
        } else if kind == WHITESPACE {
            indentation_slot(text).map_or(u32::MAX, |slot| self.indentation[slot])
        } else {
            u32::MAX
        };
        if id != u32::MAX {
            debug_assert_eq!(self.tokens[id as usize].text(), text);
            return id;
        }
        self.intern_token_slow(kind, text)
    }

    /// [`TreeBuilder::intern_token`] for a token not in the tables of punctuation and
    /// indentation (yet).
    #[inline(never)]
    fn intern_token_slow(&mut self, kind: SyntaxKind, text: &'t str) -> u32 {
        if is_fixed(kind) {
            let id = self.new_token(kind, text);
            self.fixed[kind as usize] = id;
            return id;
        }
        if kind == WHITESPACE
            && let Some(slot) = indentation_slot(text)
        {
            let id = self.new_token(kind, text);
            self.indentation[slot] = id;
            return id;
        }
        let key = TokenKey::new(kind, text);
        match self.token_ids.get(&key) {
            Some(id) => id,
            None => {
                let id = self.new_token(kind, text);
                self.token_ids.insert(key, id);
                id
            }
        }
    }

    fn new_token(&mut self, kind: SyntaxKind, text: &str) -> u32 {
        self.wrapped.push((EOF_KIND, 0));
        let id = push_id(&mut self.tokens, GreenToken::new(kind.into(), text));
        assert!(id < NODE_BIT, "fewer than 2^30 distinct tokens");
        id
    }

    /// Adds the token numbered `id` ([`TreeBuilder::intern_token`]) to the current node.
    #[inline]
    pub(crate) fn push_token(&mut self, id: u32) {
        debug_assert!((id as usize) < self.tokens.len());
        self.children.push(id);
    }

    /// Adds the tokens numbered `ids` to the current node.
    #[inline]
    pub(crate) fn push_tokens(&mut self, ids: &[u32]) {
        // Runs of trivia are short (mostly one token): pushing them one by one is cheaper
        // than `extend_from_slice`, which calls `memcpy`.
        for &id in ids {
            self.push_token(id);
        }
    }

    /// Adds the node of `kind` that wraps just the token numbered `token`, if such a node was
    /// made before (see `TreeBuilder::wrapped`); `false` if not, and nothing is added.
    #[inline]
    pub(crate) fn push_wrapped(&mut self, kind: SyntaxKind, token: u32) -> bool {
        let (wrapper, id) = self.wrapped[token as usize];
        if wrapper == kind {
            self.children.push(id | NODE_BIT);
        }
        wrapper == kind
    }

    #[inline]
    pub(crate) fn start_node(&mut self, kind: SyntaxKind) {
        self.parents.push((kind, self.children.len()));
    }

    pub(crate) fn finish_node(&mut self) {
        let (kind, first) = self
            .parents
            .pop()
            .expect("finish_node without a matching start_node");
        let children = &self.children[first..];
        if let [token] = *children
            && token < NODE_BIT
        {
            let (wrapper, id) = self.wrapped[token as usize];
            if wrapper == kind {
                self.children[first] = id | NODE_BIT;
                return;
            }
        }
        let child = match intern_key(kind, children) {
            Some(key) => match self.node_ids.get(&key) {
                Some(&id) => id | NODE_BIT,
                None => {
                    let node = self.build(kind, first);
                    let id = push_id(&mut self.nodes, node);
                    assert!(id < OWNED - NODE_BIT, "fewer than 2^30 distinct nodes");
                    self.node_ids.insert(key, id);
                    if let [token] = self.children[first..]
                        && token < NODE_BIT
                    {
                        self.wrapped[token as usize] = (kind, id);
                    }
                    id | NODE_BIT
                }
            },
            None => {
                let node = self.build(kind, first);
                self.owned.push(node);
                OWNED
            }
        };
        self.children.truncate(first);
        self.children.push(child);
    }

    /// Creates the node of `kind` whose children are `children[first..]`, taking the owned
    /// ones off `owned`.
    fn build(&mut self, kind: SyntaxKind, first: usize) -> GreenNode {
        let children = &self.children[first..];
        let owned_count = children.iter().filter(|&&c| c == OWNED).count();
        let mut owned = self.owned.drain(self.owned.len() - owned_count..);
        let (tokens, nodes) = (&self.tokens, &self.nodes);
        let elements = children.iter().map(|&child| {
            if child < NODE_BIT {
                NodeOrToken::Token(tokens[child as usize].clone())
            } else if child != OWNED {
                NodeOrToken::Node(nodes[(child - NODE_BIT) as usize].clone())
            } else {
                NodeOrToken::Node(
                    owned
                        .next()
                        .expect("every owned child has its node on the stack"),
                )
            }
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
            Some(OWNED) => self.owned.pop(),
            Some(child) if child >= NODE_BIT => {
                self.nodes.get((child - NODE_BIT) as usize).cloned()
            }
            _ => None,
        }
        .expect("the parser must leave exactly one root node")
    }
}

/// The interning key of a node, or `None` if the node is not interned (too many children, or
/// an owned child).
#[inline]
fn intern_key(kind: SyntaxKind, children: &[Child]) -> Option<NodeKey> {
    if children.len() > MAX_INTERNED {
        return None;
    }
    let mut ids = [0u64; MAX_INTERNED];
    for (slot, &child) in ids.iter_mut().zip(children) {
        if child == OWNED {
            return None;
        }
        *slot = u64::from(child);
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
    #[inline]
    fn new(kind: SyntaxKind, text: &'t str) -> TokenKey<'t> {
        let bytes = text.as_bytes();
        // Overlapping reads from both ends cover every byte; with the length (in `head`)
        // they determine the text.
        let (first, last) = match bytes.len() {
            0 => (0, 0),
            len @ 1..=3 => {
                let spread = u64::from(bytes[0])
                    | u64::from(bytes[len / 2]) << 8
                    | u64::from(bytes[len - 1]) << 16;
                (spread, 0)
            }
            len @ 4..=8 => {
                let low = u64::from(read_u32(&bytes[..4]));
                let high = u64::from(read_u32(&bytes[len - 4..]));
                (low | high << 32, 0)
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

fn read_u32(bytes: &[u8]) -> u32 {
    let mut word = [0u8; 4];
    word.copy_from_slice(bytes);
    u32::from_le_bytes(word)
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

impl TokenKey<'_> {
    #[inline]
    fn hash(&self) -> u64 {
        const K: u64 = 0xf135_7aea_2e62_a9c5;
        let h = (self.head ^ self.first.rotate_left(20)).wrapping_mul(K);
        (h ^ self.last).wrapping_mul(K)
    }
}

/// Token numbers by [`TokenKey`]: an open-addressing table with linear probing, kept at
/// most half full. (A hand-made table because the key's hash is two multiplications and
/// tokens are never removed; this lookup runs for every identifier, number and string.)
struct TokenTable<'t> {
    /// Power-of-two many slots; `u32::MAX` marks an empty one.
    slots: Vec<(TokenKey<'t>, u32)>,
    len: usize,
}

impl<'t> TokenTable<'t> {
    const EMPTY: u32 = u32::MAX;

    fn new() -> TokenTable<'t> {
        TokenTable {
            slots: Vec::new(),
            len: 0,
        }
    }

    /// The slot where `key` is, or where it would go.
    #[inline]
    fn find(&self, key: &TokenKey<'t>) -> usize {
        let mask = self.slots.len() - 1;
        // The high bits of the hash are the well-mixed ones.
        let mut slot = (key.hash() >> 32) as usize & mask;
        loop {
            let (candidate, id) = &self.slots[slot];
            if *id == Self::EMPTY || candidate == key {
                return slot;
            }
            slot = (slot + 1) & mask;
        }
    }

    #[inline]
    fn get(&self, key: &TokenKey<'t>) -> Option<u32> {
        if self.slots.is_empty() {
            return None;
        }
        let id = self.slots[self.find(key)].1;
        (id != Self::EMPTY).then_some(id)
    }

    /// Adds `key` (which must not be in the table yet).
    fn insert(&mut self, key: TokenKey<'t>, id: u32) {
        if 2 * (self.len + 1) > self.slots.len() {
            self.grow();
        }
        let slot = self.find(&key);
        debug_assert_eq!(self.slots[slot].1, Self::EMPTY);
        self.slots[slot] = (key, id);
        self.len += 1;
    }

    fn grow(&mut self) {
        let size = (2 * self.slots.len()).max(1024);
        let empty = (TokenKey::new(EOF_KIND, ""), Self::EMPTY);
        let old = std::mem::replace(&mut self.slots, vec![empty; size]);
        for (key, id) in old {
            if id != Self::EMPTY {
                let slot = self.find(&key);
                self.slots[slot] = (key, id);
            }
        }
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

/// The slot of the white space `text` in `TreeBuilder::indentation`: spaces only, or `\n`
/// and spaces.
#[inline]
fn indentation_slot(text: &str) -> Option<usize> {
    let (line_break, spaces) = match text.as_bytes() {
        [b'\n', rest @ ..] => (MAX_INDENT, rest),
        rest => (0, rest),
    };
    (spaces.len() < MAX_INDENT && spaces.iter().all(|&b| b == b' '))
        .then(|| line_break + spaces.len())
}

/// Kinds whose text is always the same (single-character punctuation).
#[inline]
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
            "ba",
            "abc",
            "acb",
            "bac",
            "abcd",
            "abdc",
            "abcde",
            "abdce",
            "abcdefg",
            "abcfdeg",
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
