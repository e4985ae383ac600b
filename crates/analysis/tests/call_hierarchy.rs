//! The call hierarchy on the generated workloads (issue 15, item 3): every group calls each of
//! its instances, every instance is called by its group and calls its graph, and every graph
//! is called by each instance of it. Each answer is timed (printed with `--nocapture`).

use std::time::{Duration, Instant};

use higraph_analysis::ide::{FilePosition, SymbolKind};
use higraph_analysis::{AnalysisHost, FileContents, TextSize, WorkspaceData};

fn load(files: &[(String, String)]) -> AnalysisHost {
    let mut data = WorkspaceData::default();
    for (path, text) in files {
        if path.ends_with(".higraph") {
            let contents = FileContents::from_bytes(text.clone().into_bytes());
            data.files.push((path.clone(), contents));
        }
    }
    let mut host = AnalysisHost::new();
    host.load(data);
    host
}

/// The positions of the names after `keyword ` at the start of a line.
fn declared(files: &[(String, String)], keyword: &str) -> Vec<FilePosition> {
    let mut out = Vec::new();
    for (path, text) in files {
        let mut offset = 0;
        for line in text.split_inclusive('\n') {
            let trimmed = line.trim_start();
            if let Some(rest) = trimmed.strip_prefix(keyword)
                && rest.starts_with(' ')
            {
                let at = offset + (line.len() - trimmed.len()) + keyword.len() + 1;
                out.push(FilePosition {
                    path: path.clone(),
                    offset: TextSize::from(at as u32),
                });
            }
            offset += line.len();
        }
    }
    out
}

#[test]
fn workloads_group_instance_graph() {
    for (name, files) in [
        ("max-group", higraph_workload::max_group(1)),
        ("plant", higraph_workload::plant(1)),
    ] {
        let host = load(&files);
        let analysis = host.analysis();
        let mut slowest = Duration::ZERO;
        let mut timed = |f: &mut dyn FnMut()| {
            let start = Instant::now();
            f();
            slowest = slowest.max(start.elapsed());
        };
        let groups = declared(&files, "group");
        let instances = declared(&files, "instance");
        let graphs = declared(&files, "graph");
        assert!(!groups.is_empty() && !instances.is_empty(), "{name}");

        let mut called = 0;
        for pos in &groups {
            let item = analysis
                .prepare_call_hierarchy(pos)
                .unwrap()
                .expect("group");
            assert_eq!(item.kind, SymbolKind::Group);
            timed(&mut || {
                let calls = analysis.outgoing_calls(pos).unwrap();
                assert!(calls.iter().all(|c| c.item.kind == SymbolKind::Instance));
                called += calls.len();
            });
        }
        assert_eq!(called, instances.len(), "{name}: every instance is called");

        for pos in &instances {
            timed(&mut || {
                let incoming = analysis.incoming_calls(pos).unwrap();
                assert_eq!(
                    incoming.first().map(|c| c.item.kind),
                    Some(SymbolKind::Group)
                );
                let outgoing = analysis.outgoing_calls(pos).unwrap();
                assert_eq!(
                    outgoing.first().map(|c| c.item.kind),
                    Some(SymbolKind::Graph)
                );
            });
        }

        let mut instantiated = 0;
        for pos in &graphs {
            timed(&mut || {
                let calls = analysis.incoming_calls(pos).unwrap();
                instantiated += calls.len();
            });
        }
        assert_eq!(
            instantiated,
            instances.len(),
            "{name}: every instance calls its graph"
        );
        eprintln!(
            "{name}: {} groups, {} instances, {} graphs; slowest answer {slowest:?}",
            groups.len(),
            instances.len(),
            graphs.len()
        );
    }
}
