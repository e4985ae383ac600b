fn main() {
    let path = std::env::args().nth(1).expect("path");
    let text = std::fs::read_to_string(path).expect("read");
    let parse = higraph_syntax::parse(&text);
    if std::env::args().nth(2).is_some() {
        print!("{}", parse.debug_tree());
    }
    for e in parse.errors() {
        println!("{e}");
    }
}
