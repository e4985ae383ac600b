//! Helpers over `roxmltree`: elements by local name (namespaces ignored), body texts, lines.

use roxmltree::Node;

/// Offsets → 1-based lines, by binary search over the line starts.
pub struct Lines {
    starts: Vec<usize>,
}

impl Lines {
    pub fn new(text: &str) -> Lines {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i + 1),
        );
        Lines { starts }
    }

    pub fn line(&self, offset: usize) -> usize {
        match self.starts.binary_search(&offset) {
            Ok(i) => i + 1,
            Err(i) => i,
        }
    }
}

pub fn local<'a>(node: Node<'a, '_>) -> &'a str {
    node.tag_name().name()
}

/// Element children with this local name.
pub fn children<'a, 'i>(
    node: Node<'a, 'i>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children()
        .filter(move |c| c.is_element() && local(*c) == name)
}

pub fn child<'a, 'i>(node: Node<'a, 'i>, name: &'static str) -> Option<Node<'a, 'i>> {
    children(node, name).next()
}

/// The first element child, whatever its name.
pub fn first_element<'a, 'i>(node: Node<'a, 'i>) -> Option<Node<'a, 'i>> {
    node.children().find(|c| c.is_element())
}

/// All text below `node` (CDATA included), paragraphs (`<p>`, `<xhtml>`, `<br>`) separated by
/// line breaks. Iterative: `descendants` walks the flat node list.
pub fn text(node: Node<'_, '_>) -> String {
    let mut out = String::new();
    for d in node.descendants() {
        if d.is_text() {
            out.push_str(d.text().unwrap_or(""));
        } else if d.is_element()
            && d != node
            && matches!(local(d), "p" | "br" | "div")
            && !out.is_empty()
            && !out.ends_with('\n')
        {
            out.push('\n');
        }
    }
    out
}

/// An attribute by local name (namespaced or not).
pub fn attr<'a>(node: Node<'a, '_>, name: &str) -> Option<&'a str> {
    node.attributes()
        .find(|a| a.name() == name)
        .map(|a| a.value())
}

/// The `documentation` child's text, trimmed; `None` when empty.
pub fn documentation(node: Node<'_, '_>) -> Option<String> {
    let doc = child(node, "documentation")?;
    let t = text(doc);
    let t = t.trim();
    (!t.is_empty()).then(|| t.to_owned())
}
