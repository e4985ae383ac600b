//! Prints what `higraph_import::import` makes of a file (for trying files by hand).
fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: import_file FILE");
        std::process::exit(2);
    };
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    match higraph_import::import(&text) {
        Ok(out) => {
            for c in &out.charts {
                println!("=== {}\n{}", c.name, c.text);
            }
            for p in &out.problems {
                println!("{path}:{}: warning: {p}", p.line);
            }
        }
        Err(e) => println!("error: {e}"),
    }
}
