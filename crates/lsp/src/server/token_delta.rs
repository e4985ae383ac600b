//! Semantic tokens delta (`textDocument/semanticTokens/full/delta`): the server remembers the
//! last tokens it sent for each open document, under a result id, and answers a delta
//! request naming that id with the edits that turn those tokens into the new ones (the
//! common start and end left out). An unknown or outdated id gets the full tokens.
//!
//! Memory stays bounded: one entry per open document, dropped when the document closes, and
//! entries of documents that are no longer open are dropped whenever tokens are stored.

use std::collections::HashMap;
use std::sync::Mutex;

use tower_lsp_server::ls_types as lsp;

/// The last tokens sent per open document, shared by the world and all snapshots.
#[derive(Default)]
pub(crate) struct TokenCache {
    inner: Mutex<Inner>,
}

#[derive(Default)]
struct Inner {
    /// The last result id given out.
    last_id: u64,
    /// By workspace path: the result id and the tokens sent with it.
    by_path: HashMap<String, (String, Vec<lsp::SemanticToken>)>,
}

impl TokenCache {
    /// Remembers `tokens` as the answer for `path` under a new result id, returned, and,
    /// when `previous` is the id of the tokens remembered so far, also the edits from those
    /// to `tokens`. `is_open` says which paths are open documents: only their tokens are
    /// kept (for another path the answer is `(None, None)`: full tokens without an id).
    pub(crate) fn store(
        &self,
        path: &str,
        previous: Option<&str>,
        tokens: &[lsp::SemanticToken],
        is_open: &dyn Fn(&str) -> bool,
    ) -> (Option<String>, Option<Vec<lsp::SemanticTokensEdit>>) {
        if !is_open(path) {
            return (None, None);
        }
        let Ok(mut inner) = self.inner.lock() else {
            return (None, None);
        };
        let edits = previous.and_then(|previous| {
            let (id, old) = inner.by_path.get(path)?;
            (id == previous).then(|| delta(old, tokens))
        });
        inner.last_id += 1;
        let id = inner.last_id.to_string();
        inner.by_path.retain(|p, _| is_open(p));
        inner
            .by_path
            .insert(path.to_owned(), (id.clone(), tokens.to_vec()));
        (Some(id), edits)
    }

    /// Drops what is remembered for `path` (its document closed).
    pub(crate) fn forget(&self, path: &str) {
        if let Ok(mut inner) = self.inner.lock() {
            inner.by_path.remove(path);
        }
    }

    #[cfg(test)]
    fn len(&self) -> usize {
        self.inner.lock().map_or(0, |inner| inner.by_path.len())
    }
}

/// The edits that turn `old` into `new`: none when they are equal, else one edit replacing
/// what lies between their common start and common end (whole tokens). Positions and counts
/// are in the integers of LSP's flat encoding, five per token.
pub(crate) fn delta(
    old: &[lsp::SemanticToken],
    new: &[lsp::SemanticToken],
) -> Vec<lsp::SemanticTokensEdit> {
    let prefix = old.iter().zip(new).take_while(|(a, b)| a == b).count();
    let suffix = old[prefix..]
        .iter()
        .rev()
        .zip(new[prefix..].iter().rev())
        .take_while(|(a, b)| a == b)
        .count();
    let deleted = old.len() - prefix - suffix;
    let inserted = &new[prefix..new.len() - suffix];
    if deleted == 0 && inserted.is_empty() {
        return Vec::new();
    }
    let ints = |tokens: usize| u32::try_from(tokens * 5).unwrap_or(u32::MAX);
    vec![lsp::SemanticTokensEdit {
        start: ints(prefix),
        delete_count: ints(deleted),
        data: (!inserted.is_empty()).then(|| inserted.to_vec()),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn token(delta_line: u32, delta_start: u32, length: u32) -> lsp::SemanticToken {
        lsp::SemanticToken {
            delta_line,
            delta_start,
            length,
            token_type: 1,
            token_modifiers_bitset: 0,
        }
    }

    /// The flat integers of LSP's encoding.
    fn flat(tokens: &[lsp::SemanticToken]) -> Vec<u32> {
        tokens
            .iter()
            .flat_map(|t| {
                [
                    t.delta_line,
                    t.delta_start,
                    t.length,
                    t.token_type,
                    t.token_modifiers_bitset,
                ]
            })
            .collect()
    }

    /// Applies edits as a client does: on the flat integers, from the last edit to the first.
    fn apply(old: &[lsp::SemanticToken], edits: &[lsp::SemanticTokensEdit]) -> Vec<u32> {
        let mut data = flat(old);
        for edit in edits.iter().rev() {
            let start = edit.start as usize;
            let end = start + edit.delete_count as usize;
            data.splice(start..end, flat(edit.data.as_deref().unwrap_or_default()));
        }
        data
    }

    #[test]
    fn applying_the_edits_to_the_old_tokens_gives_the_new_ones() {
        let a = token(0, 0, 5);
        let b = token(1, 2, 3);
        let c = token(0, 4, 1);
        let d = token(2, 0, 7);
        let e = token(0, 9, 2);
        let cases: [(Vec<lsp::SemanticToken>, Vec<lsp::SemanticToken>); 8] = [
            (vec![a, b, c], vec![a, b, c]),
            (vec![a, b, c], vec![a, d, c]),
            (vec![a, b, c], vec![a, c]),
            (vec![a, c], vec![a, b, d, c]),
            (vec![], vec![a, b]),
            (vec![a, b], vec![]),
            (vec![a, b, c], vec![d, e]),
            // Repeated tokens: prefix and suffix must not overlap.
            (vec![a, a, a], vec![a, a]),
        ];
        for (old, new) in cases {
            let edits = delta(&old, &new);
            assert_eq!(apply(&old, &edits), flat(&new), "{old:?} -> {new:?}");
            assert!(edits.len() <= 1);
            assert_eq!(edits.is_empty(), old == new);
        }
        // One changed token in the middle: an edit of that token only.
        let edits = delta(&[a, b, c], &[a, d, c]);
        assert_eq!(edits[0].start, 5);
        assert_eq!(edits[0].delete_count, 5);
        assert_eq!(edits[0].data, Some(vec![d]));
    }

    #[test]
    fn an_unknown_or_outdated_id_gets_full_tokens() {
        let cache = TokenCache::default();
        let open = |_: &str| true;
        let (first, edits) = cache.store("a.higraph", None, &[token(0, 0, 1)], &open);
        assert!(first.is_some() && edits.is_none());
        // An id never given out.
        let (second, edits) = cache.store("a.higraph", Some("nope"), &[token(0, 0, 2)], &open);
        assert!(edits.is_none());
        // The first id is outdated now.
        let (_, edits) = cache.store("a.higraph", first.as_deref(), &[token(0, 0, 2)], &open);
        assert!(edits.is_none());
        assert_ne!(first, second);
        // Another file's id does not serve.
        let (_, edits) = cache.store("b.higraph", second.as_deref(), &[token(0, 0, 2)], &open);
        assert!(edits.is_none());
    }

    #[test]
    fn the_latest_id_gets_edits_and_memory_stays_bounded() {
        let cache = TokenCache::default();
        let open = |path: &str| path != "closed.higraph";
        let (id, _) = cache.store("a.higraph", None, &[token(0, 0, 1)], &open);
        let (next, edits) = cache.store(
            "a.higraph",
            id.as_deref(),
            &[token(0, 0, 1), token(1, 0, 1)],
            &open,
        );
        assert!(next.is_some());
        assert_eq!(
            edits.map(|e| apply(&[token(0, 0, 1)], &e)),
            Some(flat(&[token(0, 0, 1), token(1, 0, 1)]))
        );
        // Documents that are not open are not remembered; one entry per open document.
        assert_eq!(
            cache.store("closed.higraph", None, &[token(0, 0, 1)], &open),
            (None, None)
        );
        cache.store("b.higraph", None, &[token(0, 0, 1)], &open);
        assert_eq!(cache.len(), 2);
        cache.forget("a.higraph");
        assert_eq!(cache.len(), 1);
        // Storing drops the entries of documents closed meanwhile.
        let only_c = |path: &str| path == "c.higraph";
        cache.store("c.higraph", None, &[token(0, 0, 1)], &only_c);
        assert_eq!(cache.len(), 1);
        let (_, edits) = cache.store("a.higraph", next.as_deref(), &[], &open);
        assert!(edits.is_none(), "forgotten on close");
    }
}
