//! Shared by the syntax crate's integration tests.

use std::{fs, path::Path};

/// Every `.higraph` file of the syntax test data and of the examples, in path order.
pub fn corpus() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in [root.join("test_data"), root.join("../../examples")] {
        collect(&dir, &mut files);
    }
    files.sort();
    files
        .iter()
        .filter_map(|p| fs::read_to_string(p).ok())
        .collect()
}

/// Every `.higraph` file under `dir`, recursively.
pub fn collect(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(&path, out);
        } else if path.extension().is_some_and(|e| e == "higraph") {
            out.push(path);
        }
    }
}
