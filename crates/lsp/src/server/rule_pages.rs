//! Where the documentation page of a rule lives, for document links on the codes of
//! `higraph-allow` comments and for `codeDescription.href` on diagnostics.
//!
//! The pages are `docs/rules/HGnnnn.md` of the higraph-lsp repository, which is usually not
//! the user's workspace. The base is therefore the initialization option `rulesBaseUri`: a
//! URI the code and `.md` are appended to (`https://example.org/higraph/docs/rules/` gives
//! `https://example.org/higraph/docs/rules/HG2105.md`; a missing final `/` is added). An
//! empty string turns the links off. Without the option, the base is the `docs/rules/`
//! folder of the workspace root when there is one (a checkout of the repository, or a
//! workspace that keeps a copy of the pages), else there are no rule links.

use std::path::Path;
use std::str::FromStr;

use tower_lsp_server::ls_types::Uri;

/// The name of the initialization option.
pub(crate) const OPTION: &str = "rulesBaseUri";

/// The value of the option in the client's `initializationOptions`, if it is a string.
pub(crate) fn option(options: Option<&serde_json::Value>) -> Option<String> {
    options?.get(OPTION)?.as_str().map(str::to_owned)
}

/// The base URI (ending in `/`) from the option and the canonical workspace root; `None`
/// when rule links are off. `Err` names an option that is not a usable URI.
pub(crate) fn base(option: Option<&str>, root: Option<&Path>) -> Result<Option<String>, String> {
    match option {
        Some("") => Ok(None),
        Some(base) => {
            let base = if base.ends_with('/') {
                base.to_owned()
            } else {
                format!("{base}/")
            };
            match Uri::from_str(&format!("{base}HG0001.md")) {
                Ok(_) => Ok(Some(base)),
                Err(_) => Err(format!("'{OPTION}' is not a URI: '{base}'")),
            }
        }
        None => {
            let Some(folder) = root.map(|root| root.join("docs").join("rules")) else {
                return Ok(None);
            };
            if !folder.is_dir() {
                return Ok(None);
            }
            Ok(Uri::from_file_path(&folder).map(|uri| {
                let text = uri.as_str().trim_end_matches('/');
                format!("{text}/")
            }))
        }
    }
}

/// The page of a rule (`HG2105`) under a base.
pub(crate) fn page(base: &str, code: &str) -> Option<Uri> {
    Uri::from_str(&format!("{base}{code}.md")).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn option_base_and_pages() {
        let options = serde_json::json!({ "rulesBaseUri": "https://example.org/docs/rules" });
        let option = option(Some(&options));
        assert_eq!(option.as_deref(), Some("https://example.org/docs/rules"));
        let base = base(option.as_deref(), None);
        assert_eq!(base, Ok(Some("https://example.org/docs/rules/".to_owned())));
        let page = page("https://example.org/docs/rules/", "HG2105").map(|u| u.to_string());
        assert_eq!(
            page.as_deref(),
            Some("https://example.org/docs/rules/HG2105.md")
        );
    }

    #[test]
    fn empty_turns_off_and_bad_is_refused() {
        assert_eq!(base(Some(""), Some(Path::new("/"))), Ok(None));
        assert!(base(Some("not a uri with spaces"), None).is_err());
    }

    #[test]
    fn default_is_the_workspace_docs_folder() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let root = dir.path().canonicalize().expect("canonical");
        assert_eq!(base(None, Some(&root)), Ok(None));
        std::fs::create_dir_all(root.join("docs/rules")).expect("folder");
        let base = base(None, Some(&root)).ok().flatten().unwrap_or_default();
        assert!(base.starts_with("file://"), "{base}");
        assert!(base.ends_with("/docs/rules/"), "{base}");
    }
}
