//! Profiling aid: re-checks max-graph after one-character edits, N times.
//! `cargo run --release -p higraph-analysis --example recheck -- [N]`
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(50);
    let text = higraph_workload::max_graph(1);
    let path = "max_graph.higraph".to_owned();
    let mut host = AnalysisHost::new();
    host.load(WorkspaceData {
        files: vec![(path.clone(), FileContents::Text(text.clone()))],
        ..WorkspaceData::default()
    });
    let _ = host.analysis().diagnostics();
    let at = text
        .find("trans 0->")
        .and_then(|t| text[t..].find(" UN ").map(|i| t + i + 1))
        .expect("a UN condition");
    let variants = [text.clone(), format!("{}O{}", &text[..at], &text[at + 1..])];
    let start = std::time::Instant::now();
    for i in 0..n {
        host.set_file_contents(&path, FileContents::Text(variants[i % 2].clone()));
        let _ = host.analysis().diagnostics().len();
    }
    println!("{:?} per edit", start.elapsed() / n as u32);
}
