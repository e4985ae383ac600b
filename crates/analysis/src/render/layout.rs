//! Layout: places the nodes of a graph or group, routes the edges around other nodes and puts
//! every edge label where it meets no other label and no node. Charts are laid out as columns
//! (see [`chart`]).
//!
//! Everything is deterministic: the same model gives the same picture.

use rustc_hash::FxHashMap as HashMap;

use super::model::{ChartModel, Element, End, GraphModel, GroupModel};
use super::picture::{BBox, Data, FONT_SIZE, Picture, Shape, Text, text_width};

/// Radius of a state circle.
const STATE_RADIUS: f64 = 28.0;
/// Vertical distance of the rows of a state graph.
const ROW_HEIGHT: f64 = 150.0;
/// Names longer than this are cut (with `…`) so that neighbouring names never meet.
const MAX_NAME_CHARS: usize = 28;

/// The outline of a node.
#[derive(Debug, Clone, Copy)]
enum Outline {
    Circle(f64),
    /// Width and height.
    Rect(f64, f64),
}

/// A node edges attach to.
#[derive(Debug, Clone, Copy)]
struct Node {
    x: f64,
    y: f64,
    outline: Outline,
}

impl Node {
    /// The point of the outline in the direction of (`px`, `py`).
    fn boundary_toward(&self, px: f64, py: f64) -> (f64, f64) {
        let (dx, dy) = (px - self.x, py - self.y);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            return (self.x, self.y);
        }
        match self.outline {
            Outline::Circle(r) => (self.x + dx / len * r, self.y + dy / len * r),
            Outline::Rect(w, h) => {
                let sx = if dx.abs() > 1e-9 {
                    (w / 2.0) / dx.abs()
                } else {
                    f64::INFINITY
                };
                let sy = if dy.abs() > 1e-9 {
                    (h / 2.0) / dy.abs()
                } else {
                    f64::INFINITY
                };
                let s = sx.min(sy);
                (self.x + dx * s, self.y + dy * s)
            }
        }
    }

    /// Whether a point lies within `margin` of the node.
    fn near(&self, px: f64, py: f64, margin: f64) -> bool {
        match self.outline {
            Outline::Circle(r) => (px - self.x).hypot(py - self.y) < r + margin,
            Outline::Rect(w, h) => {
                (px - self.x).abs() < w / 2.0 + margin && (py - self.y).abs() < h / 2.0 + margin
            }
        }
    }

    fn bbox(&self) -> BBox {
        match self.outline {
            Outline::Circle(r) => BBox::centered(self.x, self.y, 2.0 * r, 2.0 * r),
            Outline::Rect(w, h) => BBox::centered(self.x, self.y, w, h),
        }
    }
}

/// A cubic Bézier curve.
#[derive(Debug, Clone, Copy)]
struct Curve {
    p0: (f64, f64),
    p1: (f64, f64),
    p2: (f64, f64),
    p3: (f64, f64),
}

impl Curve {
    fn at(&self, t: f64) -> (f64, f64) {
        let u = 1.0 - t;
        let (a, b, c, d) = (u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t);
        (
            a * self.p0.0 + b * self.p1.0 + c * self.p2.0 + d * self.p3.0,
            a * self.p0.1 + b * self.p1.1 + c * self.p2.1 + d * self.p3.1,
        )
    }

    fn path(&self) -> String {
        format!(
            "M{:.1},{:.1} C{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}",
            self.p0.0, self.p0.1, self.p1.0, self.p1.1, self.p2.0, self.p2.1, self.p3.0, self.p3.1
        )
    }
}

/// Boxes filed by the square cells of [`Grid::CELL`] they touch, so that "what is near this
/// point or box" costs the few boxes there, not all of them: routing and labelling stay
/// linear in the size of the picture. A box too large (or not finite) to file cell by cell
/// is kept aside and always looked at; there are few of them.
#[derive(Default)]
struct Grid {
    boxes: Vec<BBox>,
    cells: HashMap<(i64, i64), Vec<usize>>,
    large: Vec<usize>,
}

impl Grid {
    const CELL: f64 = 80.0;
    /// A box spanning more cells than this goes to [`Grid::large`].
    const MAX_CELLS: i64 = 256;

    /// The cells a box touches, or `None` for a box too large or not finite.
    fn cell_range(b: &BBox) -> Option<((i64, i64), (i64, i64))> {
        if ![b.x, b.y, b.w, b.h].iter().all(|v| v.is_finite()) {
            return None;
        }
        let cell = |v: f64| (v / Self::CELL).floor() as i64;
        let (x0, y0, x1, y1) = (cell(b.x), cell(b.y), cell(b.x + b.w), cell(b.y + b.h));
        let count = (x1 - x0 + 1).saturating_mul(y1 - y0 + 1);
        (count <= Self::MAX_CELLS).then_some(((x0, y0), (x1, y1)))
    }

    fn insert(&mut self, b: BBox) -> usize {
        let id = self.boxes.len();
        self.boxes.push(b);
        match Self::cell_range(&b) {
            Some(((x0, y0), (x1, y1))) => {
                for cx in x0..=x1 {
                    for cy in y0..=y1 {
                        self.cells.entry((cx, cy)).or_default().push(id);
                    }
                }
            }
            None => self.large.push(id),
        }
        id
    }

    /// Ids of boxes that may overlap `b` (each box in a cell `b` touches; maybe repeated).
    fn near(&self, b: &BBox) -> Box<dyn Iterator<Item = usize> + '_> {
        let large = self.large.iter().copied();
        match Self::cell_range(b) {
            Some(((x0, y0), (x1, y1))) => Box::new(
                large.chain(
                    (x0..=x1)
                        .flat_map(move |cx| (y0..=y1).map(move |cy| (cx, cy)))
                        .filter_map(|key| self.cells.get(&key))
                        .flatten()
                        .copied(),
                ),
            ),
            None => Box::new(0..self.boxes.len()),
        }
    }

    /// Whether no box overlaps `b`.
    fn is_free(&self, b: &BBox) -> bool {
        self.near(b).all(|id| !self.boxes[id].overlaps(b))
    }
}

/// How far from a node a routed curve keeps.
const NODE_MARGIN: f64 = 8.0;

/// Collects nodes, routed edges and placed labels.
#[derive(Default)]
struct Router {
    nodes: Vec<Node>,
    /// The nodes' boxes grown by [`NODE_MARGIN`] (ids are node indices).
    node_grid: Grid,
    /// Boxes labels must keep clear of: nodes and placed labels.
    taken: Grid,
    /// The fixed labels (state names, instance texts): curves keep clear of them where they
    /// can, and an arrowhead never ends under one.
    fixed: Grid,
    picture: Picture,
    /// The bends already used per unordered node pair (in the frame of the lower index).
    bends: HashMap<(usize, usize), Vec<i32>>,
    /// Points along every routed curve (labels keep clear of them where they can).
    curves: Grid,
    /// The arrowheads (labels always keep clear of them).
    heads: Grid,
    /// Arrows still to be labelled, with their labels.
    pending: Vec<(Curve, Vec<String>)>,
}

impl Router {
    fn add_node(&mut self, node: Node) -> usize {
        self.taken.insert(node.bbox().inflate(2.0));
        self.node_grid.insert(node.bbox().inflate(NODE_MARGIN));
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    /// A fixed label (state name, instance text); it is drawn and kept clear of.
    fn fixed_label(&mut self, text: Text) {
        self.taken.insert(text.bbox());
        self.fixed.insert(text.bbox().inflate(2.0));
        self.picture.shapes.push(Shape::Text(text));
    }

    /// Whether a point lies under a fixed label.
    fn under_label(&self, (x, y): (f64, f64)) -> bool {
        let point = BBox::centered(x, y, 0.0, 0.0);
        self.fixed.near(&point).any(|i| {
            let b = &self.fixed.boxes[i];
            x > b.x && x < b.x + b.w && y > b.y && y < b.y + b.h
        })
    }

    /// How badly a curve from node `from` to node `to` is placed: the samples that pass
    /// another node or a fixed label, and much more for an arrowhead under a label.
    fn badness(&self, curve: &Curve, len: f64, from: usize, to: usize) -> usize {
        // About one sample per 30 units of length, so long arcs are checked as closely.
        let samples = ((len / 30.0) as u32).clamp(20, 400);
        let passes = (1..samples)
            .map(|i| curve.at(f64::from(i) / f64::from(samples)))
            .filter(|&p| self.hits_node(p, from, to) || self.under_label(p))
            .count();
        let (ex, ey) = (curve.p3.0 - curve.p2.0, curve.p3.1 - curve.p2.1);
        let elen = ex.hypot(ey).max(1e-9);
        let head = [0.0, 5.0, 10.0]
            .iter()
            .filter(|&&back| {
                self.under_label((curve.p3.0 - ex / elen * back, curve.p3.1 - ey / elen * back))
            })
            .count();
        passes + 20 * head
    }

    /// Whether a point of a curve passes a node other than `from` and `to`.
    fn hits_node(&self, (x, y): (f64, f64), from: usize, to: usize) -> bool {
        self.node_grid
            .near(&BBox::centered(x, y, 0.0, 0.0))
            .any(|i| i != from && i != to && self.nodes[i].near(x, y, NODE_MARGIN))
    }

    /// Routes an arrow from node `from` to node `to` and labels it.
    fn edge(
        &mut self,
        from: usize,
        to: usize,
        label: Vec<String>,
        title: Option<String>,
        data: Data,
    ) {
        let (Some(&a), Some(&b)) = (self.nodes.get(from), self.nodes.get(to)) else {
            return;
        };
        let curve = if from == to {
            self.self_loop(from, a)
        } else {
            self.route(from, to, a, b)
        };
        self.picture.shapes.push(Shape::Path {
            d: curve.path(),
            arrow: true,
            dashed: false,
            title,
            data,
        });
        for p in [curve.p1, curve.p2] {
            self.picture.extra.push(BBox::centered(p.0, p.1, 1.0, 1.0));
        }
        // Points along the curve about every 4 units, which labels keep clear of.
        let length = [
            (curve.p0, curve.p1),
            (curve.p1, curve.p2),
            (curve.p2, curve.p3),
        ]
        .iter()
        .map(|(a, b)| (b.0 - a.0).hypot(b.1 - a.1))
        .sum::<f64>();
        let samples = ((length / 4.0) as u32).clamp(8, 4000);
        for i in 0..=samples {
            let (x, y) = curve.at(f64::from(i) / f64::from(samples));
            self.curves.insert(BBox::centered(x, y, 0.5, 0.5));
        }
        let (ex, ey) = (curve.p3.0 - curve.p2.0, curve.p3.1 - curve.p2.1);
        let elen = ex.hypot(ey).max(1e-9);
        let head = (curve.p3.0 - ex / elen * 6.0, curve.p3.1 - ey / elen * 6.0);
        self.heads
            .insert(BBox::centered(head.0, head.1, 16.0, 16.0));
        if label.iter().any(|l| !l.is_empty()) {
            // Labelled once every arrow is drawn, so that no later arrow crosses a label.
            self.pending.push((curve, label));
        }
    }

    /// A loop above a node back to itself; further loops of the same node grow.
    fn self_loop(&mut self, index: usize, node: Node) -> Curve {
        let used = self.bends.entry((index, index)).or_default();
        let k = used.len() as f64;
        used.push(used.len() as i32);
        let r = match node.outline {
            Outline::Circle(r) => r,
            Outline::Rect(_, h) => h / 2.0,
        };
        let angle = |deg: f64| (deg.to_radians().cos(), deg.to_radians().sin());
        let (c1, c2) = (angle(-60.0), angle(-120.0));
        let reach = r + 45.0 + 20.0 * k;
        Curve {
            p0: node.boundary_toward(node.x + c1.0, node.y + c1.1),
            p1: (node.x + c1.0 * reach * 1.6, node.y + c1.1 * reach),
            p2: (node.x + c2.0 * reach * 1.6, node.y + c2.1 * reach),
            p3: node.boundary_toward(node.x + c2.0, node.y + c2.1),
        }
    }

    /// The straightest curve from `a` to `b` that passes no other node and does not lie on
    /// an earlier edge between the same two nodes.
    fn route(&mut self, from: usize, to: usize, a: Node, b: Node) -> Curve {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let len = dx.hypot(dy).max(1e-9);
        let normal = (-dy / len, dx / len);
        let key = (from.min(to), from.max(to));
        let frame = if from < to { 1 } else { -1 };
        let used = self.bends.get(&key).cloned().unwrap_or_default();
        let make = |bend: i32| -> Curve {
            // Longer edges bend more, so that the curve clears the nodes it passes.
            let h = f64::from(bend) * (len * 0.12).max(40.0);
            // Control points a third of the way in from each end, outside both nodes, so the
            // curve leaves `a` and enters `b` head-on and the arrowhead at `b` is visible.
            let c1 = outside(
                &a,
                (a.x + dx / 3.0 + normal.0 * h, a.y + dy / 3.0 + normal.1 * h),
            );
            let c2 = outside(
                &b,
                (
                    a.x + dx * 2.0 / 3.0 + normal.0 * h,
                    a.y + dy * 2.0 / 3.0 + normal.1 * h,
                ),
            );
            if bend == 0 {
                let p0 = a.boundary_toward(b.x, b.y);
                let p3 = b.boundary_toward(a.x, a.y);
                // A straight line: control points on it.
                let third = |s: f64| (p0.0 + (p3.0 - p0.0) * s, p0.1 + (p3.1 - p0.1) * s);
                Curve {
                    p0,
                    p1: third(1.0 / 3.0),
                    p2: third(2.0 / 3.0),
                    p3,
                }
            } else {
                Curve {
                    p0: a.boundary_toward(c1.0, c1.1),
                    p1: c1,
                    p2: c2,
                    p3: b.boundary_toward(c2.0, c2.1),
                }
            }
        };
        let mut best: Option<(usize, i32, Curve)> = None;
        for bend in [0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6, -6] {
            if used.contains(&(bend * frame)) {
                continue;
            }
            let curve = make(bend);
            let hits = self.badness(&curve, len, from, to);
            if best.as_ref().is_none_or(|(h, _, _)| hits < *h) {
                best = Some((hits, bend, curve));
            }
            if hits == 0 {
                break;
            }
        }
        let (bend, curve) = match best {
            Some((_, bend, curve)) => (bend, curve),
            None => {
                let bend = 7 + used.len() as i32;
                (bend, make(bend))
            }
        };
        self.bends.entry(key).or_default().push(bend * frame);
        curve
    }

    /// Labels every arrow, in the order they were drawn.
    fn place_labels(&mut self) {
        for (curve, lines) in std::mem::take(&mut self.pending) {
            self.place_label(&curve, lines);
        }
    }

    /// Puts a label beside the middle of a curve where it meets no node, no label and no
    /// arrow; failing that, on the curve where it meets no node and no label; failing that,
    /// the nearest such place below its middle.
    fn place_label(&mut self, curve: &Curve, lines: Vec<String>) {
        let (w, h) = Text::extent(&lines, FONT_SIZE);
        let free = |b: &BBox, taken: &Grid| taken.is_free(b);
        let mut chosen = None;
        'search: for clear_of_arrows in [true, false] {
            for t in [0.5, 0.4, 0.6, 0.3, 0.7, 0.25, 0.75, 0.2, 0.8, 0.15, 0.85] {
                let (x, y) = curve.at(t);
                for (ox, oy) in [
                    (0.0, -h / 2.0 - 3.0),
                    (0.0, h / 2.0 + 3.0),
                    (w / 2.0 + 4.0, 0.0),
                    (-w / 2.0 - 4.0, 0.0),
                    (w / 2.0 + 4.0, -h / 2.0 - 3.0),
                    (-w / 2.0 - 4.0, -h / 2.0 - 3.0),
                    (w / 2.0 + 4.0, h / 2.0 + 3.0),
                    (-w / 2.0 - 4.0, h / 2.0 + 3.0),
                    (0.0, -h - 8.0),
                    (0.0, h + 8.0),
                    (0.0, 0.0),
                ] {
                    let b = BBox::centered(x + ox, y + oy, w, h);
                    if free(&b, &self.taken)
                        && free(&b, &self.heads)
                        && (!clear_of_arrows || free(&b.inflate(3.0), &self.curves))
                    {
                        chosen = Some((x + ox, y + oy));
                        break 'search;
                    }
                }
            }
        }
        let (x, y) = match chosen {
            Some(point) => point,
            None => {
                let (x, mut y) = curve.at(0.5);
                // Terminates: the taken boxes are finitely many and finite.
                for _ in 0..100_000 {
                    let b = BBox::centered(x, y, w, h);
                    if free(&b, &self.taken) && free(&b, &self.heads) {
                        break;
                    }
                    y += 6.0;
                }
                (x, y)
            }
        };
        let text = Text {
            x,
            y,
            lines,
            size: FONT_SIZE,
            bold: false,
        };
        self.taken.insert(text.bbox());
        self.picture.shapes.push(Shape::Text(text));
    }

    /// The finished picture, with a heading above everything.
    fn finish(mut self, title: String, heading: String) -> Picture {
        self.place_labels();
        let bounds = self.picture.bounds();
        self.picture.shapes.push(Shape::Text(Text {
            x: bounds.x + bounds.w / 2.0,
            y: bounds.y - 24.0,
            lines: vec![heading],
            size: 15.0,
            bold: true,
        }));
        self.picture.title = title;
        self.picture
    }
}

/// `point` if it lies outside `node` (with a margin), else the point outside it in the same
/// direction from its centre.
fn outside(node: &Node, point: (f64, f64)) -> (f64, f64) {
    if !node.near(point.0, point.1, 12.0) {
        return point;
    }
    let (dx, dy) = (point.0 - node.x, point.1 - node.y);
    let len = dx.hypot(dy);
    if len < 1e-9 {
        return point;
    }
    let (bx, by) = node.boundary_toward(point.0, point.1);
    let reach = (bx - node.x).hypot(by - node.y) + 24.0;
    (node.x + dx / len * reach, node.y + dy / len * reach)
}

/// Cuts a label to at most [`MAX_NAME_CHARS`] characters.
fn shorten(text: &str) -> String {
    if text.chars().count() <= MAX_NAME_CHARS {
        text.to_owned()
    } else {
        let mut cut: String = text.chars().take(MAX_NAME_CHARS - 1).collect();
        cut.push('…');
        cut
    }
}

/// A state graph: states placed in layers from the initial state ([`super::layered`]: breadth
/// first, barycenter-ordered, folded into rows so the picture is about as wide as high);
/// transitions to earlier layers are drawn as arcs around the states between. Any-transitions
/// start at a small bar above left of their target, return transitions end at a small bar
/// right of their source.
pub fn graph(model: &GraphModel) -> Picture {
    let n = model.states.len();
    let mut index: HashMap<u64, usize> = HashMap::default();
    for (i, state) in model.states.iter().enumerate() {
        index.entry(state.number).or_insert(i);
    }
    let edges: Vec<(usize, usize)> = model
        .transitions
        .iter()
        .filter_map(|trans| match (trans.source, trans.target) {
            (End::State(s), End::State(t)) => Some((*index.get(&s)?, *index.get(&t)?)),
            _ => None,
        })
        .collect();
    let start = model
        .initial
        .and_then(|number| index.get(&number).copied())
        .unwrap_or(0);

    let names: Vec<Option<String>> = model
        .states
        .iter()
        .map(|s| s.name.as_deref().map(shorten))
        .collect();
    let widest = names
        .iter()
        .flatten()
        .map(|name| text_width(name, FONT_SIZE) + 4.0)
        .fold(0.0, f64::max);
    let column_width = (widest + 40.0).max(170.0);

    let centres = super::layered::place(n, &edges, Some(start), column_width, ROW_HEIGHT);
    let mut router = Router::default();
    let mut node_of = vec![0; n];
    for (s, &(x, y)) in centres.iter().enumerate() {
        node_of[s] = router.add_node(Node {
            x,
            y,
            outline: Outline::Circle(STATE_RADIUS),
        });
        let state = &model.states[s];
        router.picture.shapes.push(Shape::Circle {
            cx: x,
            cy: y,
            r: STATE_RADIUS,
            double: s == start && model.initial.is_some(),
            data: vec![("state", state.number.to_string())],
        });
        router.picture.shapes.push(Shape::Text(Text {
            x,
            y,
            lines: vec![state.number.to_string()],
            size: 14.0,
            bold: true,
        }));
        if let Some(name) = &names[s] {
            router.fixed_label(Text::new(x, y + STATE_RADIUS + 12.0, name.clone()));
        }
    }

    // Bars for any- and return transitions, several per state side by side.
    let mut any_bars: HashMap<usize, usize> = HashMap::default();
    let mut return_bars: HashMap<usize, usize> = HashMap::default();
    for trans in &model.transitions {
        let label = vec![trans.label()];
        let data = vec![("trans", trans.key())];
        let state = |end: End| match end {
            End::State(number) => index.get(&number).map(|&s| node_of[s]),
            _ => None,
        };
        let bar = |router: &mut Router, node: usize, dx: f64, dy: f64| -> usize {
            let (x, y) = (router.nodes[node].x + dx, router.nodes[node].y + dy);
            let bbox = BBox::centered(x, y, 26.0, 5.0);
            router.picture.shapes.push(Shape::Rect {
                bbox,
                filled: true,
                data: Data::new(),
            });
            router.add_node(Node {
                x,
                y,
                outline: Outline::Rect(26.0, 5.0),
            })
        };
        match (trans.source, trans.target) {
            (End::Any, target) => {
                let Some(target) = state(target) else {
                    continue;
                };
                let k = any_bars.entry(target).or_default();
                let dx = -70.0 - 34.0 * (*k as f64);
                *k += 1;
                let from = bar(&mut router, target, dx, -62.0);
                router.edge(from, target, label, trans.name.clone(), data);
            }
            (source, End::Return) => {
                let Some(source) = state(source) else {
                    continue;
                };
                let k = return_bars.entry(source).or_default();
                let dy = 14.0 * (*k as f64);
                *k += 1;
                let to = bar(&mut router, source, 72.0, 10.0 + dy);
                router.edge(source, to, label, trans.name.clone(), data);
            }
            (source, target) => {
                if let (Some(from), Some(to)) = (state(source), state(target)) {
                    router.edge(from, to, label, trans.name.clone(), data);
                }
            }
        }
    }
    router.finish(
        format!("graph {}", model.name),
        format!("graph {}", model.name),
    )
}

/// A graph group: instance boxes in run order, left to right in rows of about the square
/// root of their number (at most four), so that most links join neighbours; one arrow per
/// sending and receiving instance, labelled with the messages it carries.
pub fn group(model: &GroupModel) -> Picture {
    let per_row = ((model.instances.len() as f64).sqrt().ceil() as usize).clamp(1, 4);
    let lines: Vec<[String; 2]> = model
        .instances
        .iter()
        .map(|i| [shorten(&i.name), format!(": {}", shorten(&i.graph))])
        .collect();
    let width = lines
        .iter()
        .flatten()
        .map(|l| text_width(l, FONT_SIZE + 1.0) + 24.0)
        .fold(110.0, f64::max);
    let height = 46.0;
    let mut router = Router::default();
    for (i, ([name, graph], instance)) in lines.iter().zip(&model.instances).enumerate() {
        let x = (i % per_row) as f64 * (width + 190.0);
        let y = (i / per_row) as f64 * (height + 190.0);
        router.add_node(Node {
            x,
            y,
            outline: Outline::Rect(width, height),
        });
        router.picture.shapes.push(Shape::Rect {
            bbox: BBox::centered(x, y, width, height),
            filled: false,
            data: vec![("instance", instance.name.clone())],
        });
        router.picture.shapes.push(Shape::Text(Text {
            x,
            y: y - 8.0,
            lines: vec![name.clone()],
            size: FONT_SIZE + 1.0,
            bold: true,
        }));
        router
            .picture
            .shapes
            .push(Shape::Text(Text::new(x, y + 10.0, graph.clone())));
    }
    // One arrow per directed pair, in the order of the first link.
    let mut pairs: Vec<((usize, usize), Vec<String>)> = Vec::new();
    let mut pair_of: HashMap<(usize, usize), usize> = HashMap::default();
    for link in &model.links {
        let line = format!("{} → {}", link.out_message, link.in_message);
        let key = (link.from, link.to);
        match pair_of.get(&key) {
            Some(&k) => pairs[k].1.push(line),
            None => {
                pair_of.insert(key, pairs.len());
                pairs.push((key, vec![line]));
            }
        }
    }
    for ((from, to), lines) in pairs {
        router.edge(from, to, lines, None, Data::new());
    }
    router.finish(
        format!("group {}", model.name),
        format!("group {}", model.name),
    )
}

/// Vertical gap between the elements of a sequence.
const GAP: f64 = 16.0;
/// Horizontal gap between the branches of `parallel` and `alt`.
const BRANCH_GAP: f64 = 30.0;

/// The extent of a laid-out sequence around its centre line.
#[derive(Debug, Clone, Copy, Default)]
struct Extent {
    left: f64,
    right: f64,
    height: f64,
}

fn step_width(name: &str) -> f64 {
    (text_width(name, FONT_SIZE) + 24.0).max(80.0)
}

fn jump_label(kind: &str, name: &str, target: &str) -> String {
    format!("{kind} {name} → {target}")
}

/// The extents of a chart's elements, each measured once: drawing a nested `parallel` or
/// `alt` asks for the extents of its branches at every level, which would otherwise measure
/// deep nestings again and again. Elements are keyed by address (the model does not change
/// while it is drawn).
#[derive(Default)]
struct Measures {
    elements: HashMap<usize, Extent>,
}

impl Measures {
    /// The extent of one element.
    fn element(&mut self, element: &Element) -> Extent {
        let key = element as *const Element as usize;
        if let Some(&extent) = self.elements.get(&key) {
            return extent;
        }
        let extent = match element {
            Element::Step(name) => {
                let w = step_width(name);
                Extent {
                    left: w / 2.0,
                    right: w / 2.0,
                    height: 32.0,
                }
            }
            Element::Trans(name) => Extent {
                left: 16.0,
                right: 22.0 + text_width(name, FONT_SIZE) + 4.0,
                height: 22.0,
            },
            Element::Jump { name, target } | Element::Loop { name, target } => Extent {
                left: 8.0,
                right: 14.0 + text_width(&jump_label("jump", name, target), FONT_SIZE) + 4.0,
                height: 30.0,
            },
            Element::Parallel(branches) | Element::Alt(branches) => {
                let (width, height) = self.branches_size(branches);
                Extent {
                    left: width / 2.0,
                    right: width / 2.0,
                    height: height + 28.0,
                }
            }
        };
        self.elements.insert(key, extent);
        extent
    }

    /// Total width and greatest height of side-by-side branches.
    fn branches_size(&mut self, branches: &[Vec<Element>]) -> (f64, f64) {
        let extents: Vec<Extent> = branches.iter().map(|b| self.sequence(b)).collect();
        let width = extents.iter().map(|e| e.left + e.right).sum::<f64>()
            + BRANCH_GAP * (extents.len().saturating_sub(1) as f64);
        let height = extents.iter().map(|e| e.height).fold(0.0, f64::max);
        (width.max(40.0), height)
    }

    /// The extent of a sequence.
    fn sequence(&mut self, elements: &[Element]) -> Extent {
        let mut extent = Extent::default();
        for (i, e) in elements.iter().enumerate() {
            let m = self.element(e);
            extent.left = extent.left.max(m.left);
            extent.right = extent.right.max(m.right);
            extent.height += m.height + if i > 0 { GAP } else { 0.0 };
        }
        extent.left = extent.left.max(10.0);
        extent.right = extent.right.max(10.0);
        extent
    }
}

/// Draws charts: remembers where steps are and which jumps and loops still need arrows.
#[derive(Default)]
struct ChartPainter {
    picture: Picture,
    /// Step name (upper case) → right edge and vertical middle.
    steps: HashMap<String, (f64, f64)>,
    /// Jumps and loops: start point, target step name, own name.
    jumps: Vec<((f64, f64), String, String)>,
    /// The name of the sequencer being drawn (for the `data-` attributes).
    sequencer: String,
    measures: Measures,
}

impl ChartPainter {
    fn line(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, width: f64) {
        self.tagged_line(x1, y1, x2, y2, width, Data::new());
    }

    fn tagged_line(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, width: f64, data: Data) {
        self.picture.shapes.push(Shape::Line {
            x1,
            y1,
            x2,
            y2,
            width,
            data,
        });
    }

    /// Draws a sequence with its centre line at `x`, starting at `y`; returns its bottom.
    fn sequence(&mut self, elements: &[Element], x: f64, y: f64) -> f64 {
        let mut y = y;
        for (i, element) in elements.iter().enumerate() {
            if i > 0 {
                self.line(x, y, x, y + GAP, 1.2);
                y += GAP;
            }
            y = self.element(element, x, y);
        }
        y
    }

    /// Draws one element whose top is at `y`; returns its bottom.
    fn element(&mut self, element: &Element, x: f64, y: f64) -> f64 {
        let extent = self.measures.element(element);
        let bottom = y + extent.height;
        match element {
            Element::Step(name) => {
                let w = step_width(name);
                self.picture.shapes.push(Shape::Rect {
                    bbox: BBox {
                        x: x - w / 2.0,
                        y,
                        w,
                        h: extent.height,
                    },
                    filled: false,
                    data: vec![
                        ("sequencer", self.sequencer.clone()),
                        ("step", name.clone()),
                    ],
                });
                self.picture.shapes.push(Shape::Text(Text::new(
                    x,
                    y + extent.height / 2.0,
                    name.clone(),
                )));
                self.steps
                    .entry(name.to_ascii_uppercase())
                    .or_insert((x + w / 2.0, y + extent.height / 2.0));
            }
            Element::Trans(name) => {
                let mid = y + extent.height / 2.0;
                self.line(x, y, x, bottom, 1.2);
                let data = vec![
                    ("sequencer", self.sequencer.clone()),
                    ("trans", name.clone()),
                ];
                self.tagged_line(x - 14.0, mid, x + 14.0, mid, 3.0, data);
                let w = text_width(name, FONT_SIZE) + 4.0;
                self.picture.shapes.push(Shape::Text(Text::new(
                    x + 22.0 + w / 2.0,
                    mid,
                    name.clone(),
                )));
            }
            Element::Jump { name, target } | Element::Loop { name, target } => {
                let kind = if matches!(element, Element::Jump { .. }) {
                    "jump"
                } else {
                    "loop"
                };
                self.line(x, y, x, bottom, 1.2);
                let text = jump_label(kind, name, target);
                let w = text_width(&text, FONT_SIZE) + 4.0;
                self.picture
                    .shapes
                    .push(Shape::Text(Text::new(x + 14.0 + w / 2.0, y + 9.0, text)));
                self.jumps
                    .push(((x, y + 22.0), target.to_ascii_uppercase(), name.clone()));
            }
            Element::Parallel(branches) | Element::Alt(branches) => {
                let double = matches!(element, Element::Parallel(_));
                let (width, _) = self.measures.branches_size(branches);
                let extents: Vec<Extent> =
                    branches.iter().map(|b| self.measures.sequence(b)).collect();
                let mut left = x - width / 2.0;
                let mut centres = Vec::new();
                for e in &extents {
                    centres.push(left + e.left);
                    left += e.left + e.right + BRANCH_GAP;
                }
                let first = centres.first().copied().unwrap_or(x);
                let last = centres.last().copied().unwrap_or(x);
                let (bar_left, bar_right) = (first.min(x) - 12.0, last.max(x) + 12.0);
                let top = y + 6.0;
                let base = bottom - 6.0;
                self.line(x, y, x, top, 1.2);
                self.line(x, base, x, bottom, 1.2);
                for bar in [top, base] {
                    self.line(bar_left, bar, bar_right, bar, 1.5);
                }
                if double {
                    self.line(bar_left, top + 4.0, bar_right, top + 4.0, 1.5);
                    self.line(bar_left, base - 4.0, bar_right, base - 4.0, 1.5);
                }
                let inner_top = top + if double { 4.0 } else { 0.0 };
                let inner_base = base - if double { 4.0 } else { 0.0 };
                for (branch, &cx) in branches.iter().zip(&centres) {
                    self.line(cx, inner_top, cx, y + 14.0, 1.2);
                    let end = self.sequence(branch, cx, y + 14.0);
                    self.line(cx, end, cx, inner_base, 1.2);
                }
            }
        }
        bottom
    }
}

/// A chart: one column per sequencer. Steps are boxes on a vertical line, transitions short
/// thick bars with their names at the right, `parallel` opens and closes with double lines
/// and `alt` with single lines, branches side by side; jumps and loops are arrows along a
/// lane right of the column into the right side of their target step.
pub fn chart(model: &ChartModel) -> Picture {
    let mut painter = ChartPainter::default();
    let mut offset = 0.0;
    for sequencer in &model.sequencers {
        let extent = painter.measures.sequence(&sequencer.elements);
        let heading = format!("sequencer {}", sequencer.name);
        let heading_width = text_width(&heading, FONT_SIZE + 1.0) + 4.0;
        let x = offset + extent.left.max(heading_width / 2.0);
        painter.picture.shapes.push(Shape::Text(Text {
            x,
            y: 0.0,
            lines: vec![heading],
            size: FONT_SIZE + 1.0,
            bold: true,
        }));
        painter.jumps.clear();
        painter.steps.clear();
        painter.sequencer = sequencer.name.clone();
        painter.sequence(&sequencer.elements, x, 24.0);
        let right = x + extent.right.max(heading_width / 2.0);
        let jumps = std::mem::take(&mut painter.jumps);
        for (k, ((sx, sy), target, name)) in jumps.iter().enumerate() {
            let lane = right + 16.0 + 14.0 * k as f64;
            let d = match painter.steps.get(target) {
                Some(&(tx, ty)) => {
                    format!("M{sx:.1},{sy:.1} H{lane:.1} V{ty:.1} H{tx:.1}")
                }
                // An unknown target: a short stub.
                None => format!("M{sx:.1},{sy:.1} H{lane:.1}"),
            };
            painter.picture.shapes.push(Shape::Path {
                d,
                arrow: true,
                dashed: false,
                title: None,
                data: vec![
                    ("sequencer", sequencer.name.clone()),
                    ("trans", name.clone()),
                ],
            });
            painter
                .picture
                .extra
                .push(BBox::centered(lane, *sy, 2.0, 2.0));
        }
        offset = right + 16.0 + 14.0 * jumps.len() as f64 + 60.0;
    }
    let router = Router {
        picture: painter.picture,
        ..Router::default()
    };
    router.finish(
        format!("chart {}", model.name),
        format!("chart {}", model.name),
    )
}
