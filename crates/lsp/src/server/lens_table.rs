//! The document numbers of the count lenses' data.
//!
//! A big graph lists hundreds of unresolved lenses, and the answer's size is what it costs
//! over stdio. So a lens's data names its document by a small number, not by its URI: the
//! server gives each document a number when it lists the document's lenses and maps the
//! number back on `codeLens/resolve`. Numbers are never reused, so a lens listed before its
//! document was closed cannot resolve against another document. The table only keeps open
//! documents (and the one listed last): it stays bounded by the open documents.

use std::collections::HashMap;
use std::sync::Mutex;

/// The lens document numbers, shared by the world and all snapshots.
#[derive(Default)]
pub(crate) struct LensTable {
    inner: Mutex<Inner>,
}

#[derive(Default)]
struct Inner {
    /// The last number given out (0 is never given).
    last: u64,
    /// By workspace path: the document's number.
    by_path: HashMap<String, u64>,
    /// By number: the workspace path.
    by_number: HashMap<u64, String>,
}

impl LensTable {
    /// The number of `path` (a new one if it has none), dropping first the entries of
    /// documents that `is_open` says are no longer open. `None` only if the table is
    /// poisoned.
    pub(crate) fn number(&self, path: &str, is_open: &dyn Fn(&str) -> bool) -> Option<u64> {
        let mut inner = self.inner.lock().ok()?;
        let inner = &mut *inner;
        if let Some(&number) = inner.by_path.get(path) {
            return Some(number);
        }
        inner.by_path.retain(|p, _| is_open(p));
        let by_path = &inner.by_path;
        inner.by_number.retain(|_, p| by_path.contains_key(p));
        inner.last += 1;
        let number = inner.last;
        inner.by_path.insert(path.to_owned(), number);
        inner.by_number.insert(number, path.to_owned());
        Some(number)
    }

    /// The workspace path of a number; `None` for a number this table does not hold (never
    /// given, or its document was closed).
    pub(crate) fn path(&self, number: u64) -> Option<String> {
        self.inner.lock().ok()?.by_number.get(&number).cloned()
    }

    /// Drops the entry of a closed document.
    pub(crate) fn forget(&self, path: &str) {
        if let Ok(mut inner) = self.inner.lock()
            && let Some(number) = inner.by_path.remove(path)
        {
            inner.by_number.remove(&number);
        }
    }

    /// How many documents the table holds.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.inner.lock().map_or(0, |inner| inner.by_path.len())
    }
}

#[cfg(test)]
mod tests {
    use super::LensTable;

    #[test]
    fn numbers_are_stable_bounded_and_never_reused() {
        let table = LensTable::default();
        let open = |p: &str| p == "a.higraph" || p == "b.higraph";
        let a = table.number("a.higraph", &open).unwrap();
        let b = table.number("b.higraph", &open).unwrap();
        assert_ne!(a, b);
        assert_eq!(table.number("a.higraph", &open), Some(a));
        assert_eq!(table.path(b).as_deref(), Some("b.higraph"));
        table.forget("b.higraph");
        assert_eq!(table.path(b), None);
        // A document that is not open gets a number, dropped at the next new listing.
        let c = table.number("c.higraph", &open).unwrap();
        assert!(c > b);
        assert_eq!(table.path(c).as_deref(), Some("c.higraph"));
        let b2 = table.number("b.higraph", &open).unwrap();
        assert!(b2 > c, "a number is never given twice");
        assert_eq!(table.path(c), None);
        assert_eq!(table.len(), 2);
        assert_eq!(table.path(0), None);
    }
}
