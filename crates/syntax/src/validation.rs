//! Checks over the finished tree that need no parser state: constants (HG0006, HG0007) and the
//! placement of `mnemonic` directives (HG0010, HG0011).
use crate::{SyntaxError, SyntaxNode};

pub(crate) fn validate(_root: &SyntaxNode, _errors: &mut Vec<SyntaxError>) {}
