//! `build --target awl`: the STEP 7 source of a group (`higraph_export::awl`), driven through
//! `Analysis::group_source`. Snapshots of the drilling machine's group (absolute and symbolic);
//! every example and runtime fixture group generates. When Awlsim's cache venv exists
//! (`~/.cache/higraph-awlsim/venv`, installed by `scripts/awlsim-diff`), the absolute sources
//! are also compiled and run in Awlsim (`crates/export/tests/awlsim/run.py`).

use higraph_analysis::build::BuildOptions;
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

fn load_dir(root: &std::path::Path) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    let mut stack = vec![root.to_path_buf()];
    let mut files = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("directory") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    for path in files {
        let rel = path
            .strip_prefix(root)
            .expect("inside")
            .to_string_lossy()
            .replace('\\', "/");
        let bytes = std::fs::read(&path).expect("readable");
        if rel.ends_with(".higraph") {
            data.files.push((rel, FileContents::from_bytes(bytes)));
        } else if rel == "higraph.toml" {
            data.config = Some((rel, FileContents::from_bytes(bytes)));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

fn repo(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn source(host: &AnalysisHost, group: &str, options: &BuildOptions) -> (String, Vec<u8>) {
    let (name, bytes, _) = host
        .analysis()
        .group_source(group, options)
        .expect("not cancelled")
        .expect("the group exists")
        .expect("the group generates");
    (name, bytes)
}

fn text(bytes: &[u8]) -> String {
    // Windows-1252 → text for the snapshot (the examples are ASCII apart from comments).
    bytes
        .iter()
        .map(|&b| b as char)
        .collect::<String>()
        .replace("\r\n", "\n")
}

const ABSOLUTE: BuildOptions = BuildOptions {
    target: higraph_analysis::build::Target::Awl,
    with_ob1: false,
    absolute: true,
};

#[test]
fn drilling_absolute() {
    let host = load_dir(&repo("examples/drilling"));
    let (name, bytes) = source(&host, "Bohrmaschine", &ABSOLUTE);
    assert_eq!(name, "Bohrmaschine.awl");
    assert!(bytes.windows(2).any(|w| w == b"\r\n"));
    assert!(
        !bytes
            .iter()
            .enumerate()
            .any(|(i, &b)| b == b'\n' && (i == 0 || bytes[i - 1] != b'\r'))
    );
    insta::assert_snapshot!(text(&bytes));
}

#[test]
fn drilling_symbolic_with_ob1() {
    let host = load_dir(&repo("examples/drilling"));
    let options = BuildOptions {
        with_ob1: true,
        absolute: false,
        ..ABSOLUTE
    };
    let (_, bytes) = source(&host, "Bohrmaschine", &options);
    let (_, _, symbols) = host
        .analysis()
        .group_source("Bohrmaschine", &options)
        .unwrap()
        .unwrap()
        .unwrap();
    let table = higraph_export::sdf::text(&symbols);
    insta::assert_snapshot!(format!("{}\n---- symbols.sdf\n{table}", text(&bytes)));
}

#[test]
fn deterministic() {
    let host = load_dir(&repo("examples/drilling"));
    let a = source(&host, "Bohrmaschine", &ABSOLUTE);
    let host = load_dir(&repo("examples/drilling"));
    let b = source(&host, "Bohrmaschine", &ABSOLUTE);
    assert_eq!(a, b);
}
