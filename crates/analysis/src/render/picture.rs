//! The drawing: a list of shapes in picture coordinates, with the bounding boxes tests use,
//! and its SVG text.

use std::fmt::Write as _;

/// Font size of ordinary labels, in picture units.
pub const FONT_SIZE: f64 = 12.0;

/// An axis-aligned rectangle: top-left corner and size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BBox {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl BBox {
    /// The box of that size centred on a point.
    pub fn centered(cx: f64, cy: f64, w: f64, h: f64) -> BBox {
        BBox {
            x: cx - w / 2.0,
            y: cy - h / 2.0,
            w,
            h,
        }
    }

    /// Whether the interiors of two boxes meet.
    pub fn overlaps(&self, other: &BBox) -> bool {
        self.x < other.x + other.w
            && other.x < self.x + self.w
            && self.y < other.y + other.h
            && other.y < self.y + self.h
    }

    /// The box grown by `d` on every side.
    pub fn inflate(&self, d: f64) -> BBox {
        BBox {
            x: self.x - d,
            y: self.y - d,
            w: self.w + 2.0 * d,
            h: self.h + 2.0 * d,
        }
    }

    fn union(&self, other: &BBox) -> BBox {
        let x = self.x.min(other.x);
        let y = self.y.min(other.y);
        BBox {
            x,
            y,
            w: (self.x + self.w).max(other.x + other.w) - x,
            h: (self.y + self.h).max(other.y + other.h) - y,
        }
    }
}

/// The estimated width of a text in the sans-serif font (no font metrics are available;
/// the estimate is generous so that boxes computed from it contain the drawn text).
pub fn text_width(text: &str, size: f64) -> f64 {
    let units: f64 = text
        .chars()
        .map(|c| match c {
            'i' | 'l' | 'j' | 'I' | '.' | ',' | ':' | ';' | '!' | '|' | '\'' => 0.3,
            'f' | 't' | 'r' | ' ' | '(' | ')' | '-' => 0.4,
            'm' | 'w' | 'M' | 'W' => 0.9,
            c if c.is_uppercase() => 0.7,
            _ => 0.58,
        })
        .sum();
    units * size
}

/// A text label: centred on (`x`, `y`).
#[derive(Debug, Clone, PartialEq)]
pub struct Text {
    pub x: f64,
    pub y: f64,
    /// One or more lines.
    pub lines: Vec<String>,
    pub size: f64,
    pub bold: bool,
}

impl Text {
    /// A one-line label of the ordinary size.
    pub fn new(x: f64, y: f64, text: impl Into<String>) -> Text {
        Text {
            x,
            y,
            lines: vec![text.into()],
            size: FONT_SIZE,
            bold: false,
        }
    }

    /// The size of a label of these lines.
    pub fn extent(lines: &[String], size: f64) -> (f64, f64) {
        let w = lines
            .iter()
            .map(|l| text_width(l, size))
            .fold(0.0, f64::max);
        (w + 4.0, lines.len() as f64 * size * 1.25 + 2.0)
    }

    /// The box the text occupies.
    pub fn bbox(&self) -> BBox {
        let (w, h) = Text::extent(&self.lines, self.size);
        BBox::centered(self.x, self.y, w, h)
    }
}

/// `data-*` attributes of a shape (name without `data-`, value), for a viewer that animates
/// the picture: `state` (a state circle), `trans` (`A->B:PRIO`, a transition arrow),
/// `instance` (an instance box), `sequencer` and `step` (a step box), `sequencer` and `trans`
/// (a chart transition bar or jump arrow, by name).
pub type Data = Vec<(&'static str, String)>;

/// One shape of a picture.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Circle {
        cx: f64,
        cy: f64,
        r: f64,
        /// Drawn with a double outline (the initial state).
        double: bool,
        data: Data,
    },
    Rect {
        bbox: BBox,
        /// Filled black (bars) rather than white with an outline.
        filled: bool,
        data: Data,
    },
    /// A straight line.
    Line {
        x1: f64,
        y1: f64,
        x2: f64,
        y2: f64,
        width: f64,
        data: Data,
    },
    /// An SVG path (`d` attribute), optionally ending in an arrowhead.
    Path {
        d: String,
        arrow: bool,
        dashed: bool,
        /// A tooltip (`<title>`), e.g. the transition's name.
        title: Option<String>,
        data: Data,
    },
    Text(Text),
}

/// A complete drawing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Picture {
    pub title: String,
    pub shapes: Vec<Shape>,
    /// Boxes the view must include besides the shapes' own (the control points of curves).
    pub extra: Vec<BBox>,
}

impl Picture {
    /// The state circles: centre and radius.
    pub fn circles(&self) -> Vec<(f64, f64, f64)> {
        self.shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Circle { cx, cy, r, .. } => Some((*cx, *cy, *r)),
                _ => None,
            })
            .collect()
    }

    /// Every text label with its bounding box.
    pub fn texts(&self) -> Vec<(&Text, BBox)> {
        self.shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Text(t) => Some((t, t.bbox())),
                _ => None,
            })
            .collect()
    }

    /// The box around every shape (paths are covered by their end nodes and by
    /// [`Picture::extra`]).
    pub fn bounds(&self) -> BBox {
        let mut bounds: Option<BBox> = None;
        let boxes = self
            .shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Circle { cx, cy, r, .. } => {
                    Some(BBox::centered(*cx, *cy, 2.0 * r + 4.0, 2.0 * r + 4.0))
                }
                Shape::Rect { bbox, .. } => Some(*bbox),
                Shape::Line { x1, y1, x2, y2, .. } => Some(BBox {
                    x: x1.min(*x2),
                    y: y1.min(*y2),
                    w: (x1 - x2).abs(),
                    h: (y1 - y2).abs(),
                }),
                Shape::Text(t) => Some(t.bbox()),
                Shape::Path { .. } => None,
            })
            .chain(self.extra.iter().copied());
        for b in boxes {
            bounds = Some(match bounds {
                Some(a) => a.union(&b),
                None => b,
            });
        }
        bounds.unwrap_or(BBox {
            x: 0.0,
            y: 0.0,
            w: 100.0,
            h: 50.0,
        })
    }

    /// The SVG document.
    pub fn to_svg(&self) -> String {
        let b = self.bounds().inflate(20.0);
        let mut out = String::new();
        let _ = writeln!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"{x:.1} {y:.1} {w:.1} {h:.1}\" font-family=\"sans-serif\" font-size=\"{FONT_SIZE}\">",
            x = b.x,
            y = b.y,
            w = b.w,
            h = b.h
        );
        let _ = writeln!(out, "<title>{}</title>", escape(&self.title));
        out.push_str(
            "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"8\" markerHeight=\"8\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"black\"/></marker></defs>\n",
        );
        let _ = writeln!(
            out,
            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"white\"/>",
            b.x, b.y, b.w, b.h
        );
        // Edges first, then nodes over them, then the labels on top.
        for shape in &self.shapes {
            match shape {
                Shape::Path {
                    d,
                    arrow,
                    dashed,
                    title,
                    data,
                } => {
                    let data = attributes(data);
                    let marker = if *arrow {
                        " marker-end=\"url(#arrow)\""
                    } else {
                        ""
                    };
                    let dash = if *dashed {
                        " stroke-dasharray=\"5,3\""
                    } else {
                        ""
                    };
                    match title {
                        Some(t) => {
                            let _ = writeln!(
                                out,
                                "<path d=\"{d}\" fill=\"none\" stroke=\"black\" stroke-width=\"1.2\"{marker}{dash}{data}><title>{}</title></path>",
                                escape(t)
                            );
                        }
                        None => {
                            let _ = writeln!(
                                out,
                                "<path d=\"{d}\" fill=\"none\" stroke=\"black\" stroke-width=\"1.2\"{marker}{dash}{data}/>"
                            );
                        }
                    }
                }
                Shape::Line {
                    x1,
                    y1,
                    x2,
                    y2,
                    width,
                    data,
                } => {
                    let data = attributes(data);
                    let _ = writeln!(
                        out,
                        "<line x1=\"{x1:.1}\" y1=\"{y1:.1}\" x2=\"{x2:.1}\" y2=\"{y2:.1}\" stroke=\"black\" stroke-width=\"{width}\"{data}/>"
                    );
                }
                _ => {}
            }
        }
        for shape in &self.shapes {
            match shape {
                Shape::Circle {
                    cx,
                    cy,
                    r,
                    double,
                    data,
                } => {
                    let data = attributes(data);
                    let _ = writeln!(
                        out,
                        "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"{r:.1}\" fill=\"#f4f8ff\" stroke=\"black\" stroke-width=\"1.5\"{data}/>"
                    );
                    if *double {
                        let _ = writeln!(
                            out,
                            "<circle cx=\"{cx:.1}\" cy=\"{cy:.1}\" r=\"{:.1}\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>",
                            r - 4.0
                        );
                    }
                }
                Shape::Rect { bbox, filled, data } => {
                    let data = attributes(data);
                    let style = if *filled {
                        "fill=\"black\""
                    } else {
                        "fill=\"#f4f8ff\" stroke=\"black\" stroke-width=\"1.5\""
                    };
                    let _ = writeln!(
                        out,
                        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" {style}{data}/>",
                        bbox.x, bbox.y, bbox.w, bbox.h
                    );
                }
                _ => {}
            }
        }
        for shape in &self.shapes {
            if let Shape::Text(text) = shape {
                write_text(&mut out, text);
            }
        }
        out.push_str("</svg>\n");
        out
    }
}

fn write_text(out: &mut String, text: &Text) {
    let line_height = text.size * 1.25;
    let first = text.y - line_height * (text.lines.len() as f64 - 1.0) / 2.0;
    let weight = if text.bold {
        " font-weight=\"bold\""
    } else {
        ""
    };
    let (w, h) = Text::extent(&text.lines, text.size);
    // A white backing keeps labels readable where they cross a line.
    let _ = writeln!(
        out,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"white\" fill-opacity=\"0.8\"/>",
        text.x - w / 2.0,
        text.y - h / 2.0
    );
    for (i, line) in text.lines.iter().enumerate() {
        let _ = writeln!(
            out,
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"{}\" text-anchor=\"middle\" dominant-baseline=\"central\"{weight}>{}</text>",
            text.x,
            first + i as f64 * line_height,
            text.size,
            escape(line)
        );
    }
}

/// ` data-name="value"` for each attribute.
fn attributes(data: &Data) -> String {
    let mut out = String::new();
    for (name, value) in data {
        let _ = write!(out, " data-{name}=\"{}\"", escape(value));
    }
    out
}

/// XML-escapes text and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}
