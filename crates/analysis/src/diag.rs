//! Diagnostics as the rules produce them: positions as [`Loc`]s (a file, an item of it and a
//! range relative to that item), so that they stay equal when other items of the file move.
//! [`crate::check`] turns them into [`crate::Diagnostic`]s with absolute ranges and paths.

use higraph_syntax::TextRange;

use crate::{Code, db::File};

/// A place in the workspace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Loc {
    pub file: File,
    /// The item whose start `range` is relative to; `None` for a range relative to the file.
    pub item: Option<u32>,
    pub range: TextRange,
    /// `range` is relative to the graph member being analysed, not yet to the item: the
    /// per-member analyses ([`crate::db::chunk_stl`]) do not know where their member stands.
    /// [`Diag::place_member`] resolves it; no such `Loc` leaves the item's analysis.
    pub in_member: bool,
}

impl Loc {
    pub fn in_item(file: File, item: u32, range: TextRange) -> Loc {
        Loc {
            file,
            item: Some(item),
            range,
            in_member: false,
        }
    }

    pub fn in_file(file: File, range: TextRange) -> Loc {
        Loc {
            file,
            item: None,
            range,
            in_member: false,
        }
    }

    /// A place relative to the member being analysed (see [`Loc::in_member`]).
    pub fn in_member(file: File, item: u32, range: TextRange) -> Loc {
        Loc {
            file,
            item: Some(item),
            range,
            in_member: true,
        }
    }

    /// Resolves a member-relative place, given the member's offset in its item.
    fn placed(self, member_offset: higraph_syntax::TextSize) -> Loc {
        Loc {
            in_member: false,
            ..self.shifted(member_offset)
        }
    }

    /// Moves a member-relative place to be relative to a range that starts `offset` before
    /// the member (a chunk of members); it stays member-relative.
    fn shifted(self, offset: higraph_syntax::TextSize) -> Loc {
        if self.in_member {
            Loc {
                range: self.range + offset,
                ..self
            }
        } else {
            self
        }
    }
}

/// A quick fix: a title and edits.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DiagFix {
    pub title: String,
    pub edits: Vec<(Loc, String)>,
    /// A rename of the declared name at the first edit's place to this name, through the
    /// workspace rename engine ([`crate::ide::rename`]): when the diagnostic is converted
    /// ([`crate::check`]), the engine's edits — the declaration and every reference, in every
    /// file — replace `edits`, and the fix is dropped if the engine refuses the new name.
    /// An item's analysis cannot see the other files; this defers that part.
    pub rename_to: Option<String>,
    /// The most likely fix of its diagnostic (LSP `isPreferred`, the editor's "auto fix"):
    /// a replacement with the closest existing name. Whatever the rules mark, the only fix of
    /// a diagnostic is preferred too ([`crate::check`]).
    pub preferred: bool,
}

/// A diagnostic of a rule, before severities, suppressions and absolute positions.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Diag {
    pub code: Code,
    pub at: Loc,
    pub message: String,
    pub related: Vec<(Loc, String)>,
    pub fixes: Vec<DiagFix>,
    /// Unused code (HG1210, HG1212, HG6004): shown faded in editors.
    pub unnecessary: bool,
}

impl Diag {
    pub fn new(code: &'static str, at: Loc, message: impl Into<String>) -> Diag {
        Diag {
            code: Code::new(code),
            at,
            message: message.into(),
            related: Vec::new(),
            fixes: Vec::new(),
            unnecessary: matches!(code, "HG1210" | "HG1212" | "HG6004"),
        }
    }

    pub fn related(mut self, at: Loc, message: impl Into<String>) -> Diag {
        self.related.push((at, message.into()));
        self
    }

    /// A fix with one edit.
    pub fn fix(mut self, title: impl Into<String>, at: Loc, new_text: impl Into<String>) -> Diag {
        self.fixes.push(DiagFix {
            title: title.into(),
            edits: vec![(at, new_text.into())],
            rename_to: None,
            preferred: false,
        });
        self
    }

    /// Marks the last fix added as the most likely one ([`DiagFix::preferred`]).
    pub fn preferred(mut self) -> Diag {
        if let Some(fix) = self.fixes.last_mut() {
            fix.preferred = true;
        }
        self
    }

    /// A fix that renames the declared name at `at` to `new_name` everywhere in the workspace
    /// (see [`DiagFix::rename_to`]).
    pub fn rename_fix(mut self, title: impl Into<String>, at: Loc, new_name: &str) -> Diag {
        self.fixes.push(DiagFix {
            title: title.into(),
            edits: vec![(at, new_name.to_owned())],
            rename_to: Some(new_name.to_owned()),
            preferred: false,
        });
        self
    }

    /// The diagnostic with every member-relative place made relative to the item, the
    /// member standing at `member_offset` in it.
    pub fn place_member(&self, member_offset: higraph_syntax::TextSize) -> Diag {
        self.map_locs(|loc| loc.placed(member_offset))
    }

    /// The diagnostic with every member-relative place moved by `offset` (see
    /// [`Loc::shifted`]).
    pub fn shift_member(&self, offset: higraph_syntax::TextSize) -> Diag {
        self.map_locs(|loc| loc.shifted(offset))
    }

    /// The diagnostic with every range of the current item mapped by `f` (places in other
    /// items or files are left alone).
    pub fn map_ranges(&self, f: impl Fn(TextRange) -> TextRange) -> Diag {
        let (file, item) = (self.at.file, self.at.item);
        self.map_locs(|loc| {
            if loc.file == file && loc.item == item {
                Loc {
                    range: f(loc.range),
                    ..loc
                }
            } else {
                loc
            }
        })
    }

    fn map_locs(&self, f: impl Fn(Loc) -> Loc) -> Diag {
        let mut diag = self.clone();
        diag.at = f(diag.at);
        for (loc, _) in &mut diag.related {
            *loc = f(*loc);
        }
        for (loc, _) in diag.fixes.iter_mut().flat_map(|f| &mut f.edits) {
            *loc = f(*loc);
        }
        diag
    }

    /// A fix with several edits.
    pub fn fix_edits(mut self, title: impl Into<String>, edits: Vec<(Loc, String)>) -> Diag {
        self.fixes.push(DiagFix {
            title: title.into(),
            edits,
            rename_to: None,
            preferred: false,
        });
        self
    }
}
