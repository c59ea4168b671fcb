//! OpenSCAD's `.csg` files (what `openscad -o model.csg model.scad` writes), read into a
//! [`Node`] with OpenSCAD's own tessellation, so results compare with OpenSCAD's renders.
//!
//! # Nodes
//! - `group`, `union`, `render`: a union of the children; `difference`, `intersection`;
//!   `multmatrix(m)`: the children moved by the 4 × 4 matrix; `color(c)`: the children's
//!   faces get the material named by the colour (`#rrggbbaa`) and that face colour;
//! - `cube(size, center)`, `sphere(r)`, `cylinder(h, r1, r2, center)` with `$fn`, `$fa`,
//!   `$fs`; `polyhedron(points, faces)` (OpenSCAD lists faces clockwise seen from outside, so
//!   they are reversed).
//! - Modifiers: `%` and `*` leave their subtree out, `#` keeps it, `!` makes its subtree the
//!   whole model.
//!
//! Every other node (2D shapes and extrusions, `hull`, `minkowski`, `offset`, `text`,
//! `import`, `surface`, `projection`, `resize`) is an error naming the node and its line.
//!
//! # Tessellation (OpenSCAD 2021, `src/calc.cc`, `src/primitives.cc`, `src/degree_trig.cc`)
//! - Fragments of a circle of radius `r`: 3 when `r` is below 2^-20; `max($fn, 3)` when `$fn`
//!   > 0; otherwise `ceil(max(min(360 / $fa, 2πr / $fs), 5))`.
//! - A circle's points are at `360° · i / n` from angle 0, counter-clockwise.
//! - A sphere has `(n + 1) / 2` rings at polar angles `180° · (i + ½) / rings`.
//! - Angles are in degrees with OpenSCAD's exact values at multiples of 30° and 45°.

use super::tree::{Affine, Node};
use crate::Operation;
use crate::mesh::Mesh;
use crate::primitives::{circle, cuboid, uv_sphere};

/// Why a `.csg` file could not be read: the line and what is wrong there.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct OpenScadError {
    /// The line (from 1).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Reads the text of a `.csg` file into a tree (see the module docs).
///
/// # Errors
/// [`OpenScadError`] naming the line of a malformed statement or an unsupported node.
pub fn parse_openscad_csg(text: &str) -> Result<Node, OpenScadError> {
    let tokens = tokenize(text)?;
    let mut parser = Parser { tokens, at: 0 };
    let mut roots = Vec::new();
    let mut root_only = None;
    while !parser.done() {
        if let Some((node, root)) = parser.statement()? {
            if root && root_only.is_none() {
                root_only = Some(node.clone());
            }
            roots.push(node);
        }
    }
    Ok(root_only.unwrap_or_else(|| Node::apply(Operation::Union, roots)))
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Ident(String),
    Number(f64),
    Str(String),
    Punct(char),
}

fn tokenize(text: &str) -> Result<Vec<(Token, usize)>, OpenScadError> {
    let mut out = Vec::new();
    let bytes: Vec<char> = text.chars().collect();
    let (mut i, mut line) = (0, 1);
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            '\n' => {
                line += 1;
                i += 1;
            }
            c if c.is_whitespace() => i += 1,
            '/' if bytes.get(i + 1) == Some(&'/') => {
                while i < bytes.len() && bytes[i] != '\n' {
                    i += 1;
                }
            }
            '"' => {
                let mut s = String::new();
                i += 1;
                while i < bytes.len() && bytes[i] != '"' {
                    if bytes[i] == '\\' && i + 1 < bytes.len() {
                        i += 1;
                    }
                    s.push(bytes[i]);
                    i += 1;
                }
                if i >= bytes.len() {
                    return Err(OpenScadError {
                        line,
                        message: "a string is not closed".into(),
                    });
                }
                i += 1;
                out.push((Token::Str(s), line));
            }
            c if c.is_ascii_digit() || c == '.' || (c == '-' && next_is_number(&bytes, i)) => {
                let start = i;
                i += 1;
                while i < bytes.len()
                    && (bytes[i].is_ascii_alphanumeric()
                        || bytes[i] == '.'
                        || ((bytes[i] == '-' || bytes[i] == '+')
                            && matches!(bytes[i - 1], 'e' | 'E')))
                {
                    i += 1;
                }
                let word: String = bytes[start..i].iter().collect();
                let value = word.parse::<f64>().map_err(|_| OpenScadError {
                    line,
                    message: format!("{word:?} is not a number"),
                })?;
                out.push((Token::Number(value), line));
            }
            c if c.is_alphabetic() || c == '_' || c == '$' => {
                let start = i;
                while i < bytes.len()
                    && (bytes[i].is_alphanumeric() || bytes[i] == '_' || bytes[i] == '$')
                {
                    i += 1;
                }
                out.push((Token::Ident(bytes[start..i].iter().collect()), line));
            }
            '(' | ')' | '{' | '}' | '[' | ']' | ';' | ',' | '=' | '%' | '#' | '!' | '*' => {
                out.push((Token::Punct(c), line));
                i += 1;
            }
            other => {
                return Err(OpenScadError {
                    line,
                    message: format!("unexpected character {other:?}"),
                });
            }
        }
    }
    Ok(out)
}

fn next_is_number(chars: &[char], i: usize) -> bool {
    chars
        .get(i + 1)
        .is_some_and(|c| c.is_ascii_digit() || *c == '.')
}

/// An argument value.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Number(f64),
    Bool(bool),
    Str(String),
    Vector(Vec<Value>),
    Undef,
}

struct Parser {
    tokens: Vec<(Token, usize)>,
    at: usize,
}

impl Parser {
    fn done(&self) -> bool {
        self.at >= self.tokens.len()
    }

    fn line(&self) -> usize {
        (self.tokens.get(self.at).or(self.tokens.last())).map_or(1, |t| t.1)
    }

    fn error<T>(&self, message: impl Into<String>) -> Result<T, OpenScadError> {
        Err(OpenScadError {
            line: self.line(),
            message: message.into(),
        })
    }

    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.at).map(|t| &t.0)
    }

    fn next(&mut self) -> Option<Token> {
        let t = self.tokens.get(self.at).map(|t| t.0.clone());
        self.at += 1;
        t
    }

    fn expect(&mut self, c: char) -> Result<(), OpenScadError> {
        match self.next() {
            Some(Token::Punct(p)) if p == c => Ok(()),
            other => {
                self.at -= 1;
                self.error(format!("expected {c:?}, found {other:?}"))
            }
        }
    }

    /// One statement: its node (`None` when a modifier leaves it out) and whether it is
    /// marked root (`!`).
    fn statement(&mut self) -> Result<Option<(Node, bool)>, OpenScadError> {
        let (mut skip, mut root) = (false, false);
        while let Some(Token::Punct(c @ ('%' | '#' | '!' | '*'))) = self.peek().cloned() {
            self.at += 1;
            match c {
                '%' | '*' => skip = true,
                '!' => root = true,
                _ => {}
            }
        }
        if let Some(Token::Punct(';')) = self.peek() {
            self.at += 1;
            return Ok(None);
        }
        let line = self.line();
        let Some(Token::Ident(name)) = self.next() else {
            self.at -= 1;
            return self.error("expected a node name");
        };
        self.expect('(')?;
        let args = self.arguments()?;
        let mut children = Vec::new();
        let mut root_child = None;
        match self.next() {
            Some(Token::Punct(';')) => {}
            Some(Token::Punct('{')) => {
                while !matches!(self.peek(), Some(Token::Punct('}'))) {
                    if self.done() {
                        return self.error(format!("{name} at line {line} is not closed"));
                    }
                    if let Some((child, child_root)) = self.statement()? {
                        if child_root && root_child.is_none() {
                            root_child = Some(child.clone());
                        }
                        children.push(child);
                    }
                }
                self.at += 1;
            }
            _ => {
                self.at -= 1;
                return self.error(format!("expected ';' or '{{' after {name}(…)"));
            }
        }
        if let Some(child) = root_child {
            return Ok(Some((child, true)));
        }
        let node = build(&name, &args, children, line)?;
        Ok((!skip).then_some((node, root)))
    }

    fn arguments(&mut self) -> Result<Vec<(Option<String>, Value)>, OpenScadError> {
        let mut out = Vec::new();
        loop {
            if let Some(Token::Punct(')')) = self.peek() {
                self.at += 1;
                return Ok(out);
            }
            let named = match (self.tokens.get(self.at), self.tokens.get(self.at + 1)) {
                (Some((Token::Ident(n), _)), Some((Token::Punct('='), _))) => {
                    let n = n.clone();
                    self.at += 2;
                    Some(n)
                }
                _ => None,
            };
            let value = self.value()?;
            out.push((named, value));
            match self.next() {
                Some(Token::Punct(',')) => {}
                Some(Token::Punct(')')) => return Ok(out),
                _ => {
                    self.at -= 1;
                    return self.error("expected ',' or ')' in the arguments");
                }
            }
        }
    }

    fn value(&mut self) -> Result<Value, OpenScadError> {
        match self.next() {
            Some(Token::Number(x)) => Ok(Value::Number(x)),
            Some(Token::Str(s)) => Ok(Value::Str(s)),
            Some(Token::Ident(word)) => match word.as_str() {
                "true" => Ok(Value::Bool(true)),
                "false" => Ok(Value::Bool(false)),
                "undef" => Ok(Value::Undef),
                _ => self.error(format!("unexpected {word:?} in a value")),
            },
            Some(Token::Punct('[')) => {
                let mut items = Vec::new();
                loop {
                    if let Some(Token::Punct(']')) = self.peek() {
                        self.at += 1;
                        return Ok(Value::Vector(items));
                    }
                    items.push(self.value()?);
                    match self.next() {
                        Some(Token::Punct(',')) => {}
                        Some(Token::Punct(']')) => return Ok(Value::Vector(items)),
                        _ => {
                            self.at -= 1;
                            return self.error("expected ',' or ']' in a vector");
                        }
                    }
                }
            }
            other => {
                self.at -= 1;
                self.error(format!("expected a value, found {other:?}"))
            }
        }
    }
}

/// The named argument `name`, or else the positional one at `position`.
fn argument<'a>(
    args: &'a [(Option<String>, Value)],
    name: &str,
    position: usize,
) -> Option<&'a Value> {
    (args.iter())
        .find(|(n, _)| n.as_deref() == Some(name))
        .map(|(_, v)| v)
        .or_else(|| {
            (args.iter())
                .filter(|(n, _)| n.is_none())
                .nth(position)
                .map(|(_, v)| v)
        })
}

fn number(value: Option<&Value>) -> Option<f64> {
    match value {
        Some(Value::Number(x)) => Some(*x),
        _ => None,
    }
}

fn vector(value: &Value) -> Option<Vec<f64>> {
    match value {
        Value::Vector(items) => items
            .iter()
            .map(|v| number(Some(v)))
            .collect::<Option<Vec<f64>>>(),
        _ => None,
    }
}

/// The node a statement makes.
fn build(
    name: &str,
    args: &[(Option<String>, Value)],
    children: Vec<Node>,
    line: usize,
) -> Result<Node, OpenScadError> {
    let bad = |message: String| OpenScadError { line, message };
    let union = |children| Node::apply(Operation::Union, children);
    Ok(match name {
        "group" | "union" | "render" => union(children),
        "difference" => Node::apply(Operation::Difference, children),
        "intersection" => Node::apply(Operation::Intersection, children),
        "multmatrix" => {
            let rows = argument(args, "m", 0)
                .and_then(|m| match m {
                    Value::Vector(rows) => rows.iter().map(vector).collect::<Option<Vec<_>>>(),
                    _ => None,
                })
                .filter(|rows| rows.len() >= 3 && rows.iter().all(|r| r.len() == 4))
                .ok_or_else(|| bad("multmatrix needs a 4 × 4 matrix".into()))?;
            let transform: Affine = std::array::from_fn(|i| std::array::from_fn(|j| rows[i][j]));
            Node {
                transform: Some(transform),
                ..union(children)
            }
        }
        "color" => {
            let rgba = argument(args, "c", 0)
                .and_then(vector)
                .filter(|c| c.len() >= 3)
                .map(|c| [c[0], c[1], c[2], c.get(3).copied().unwrap_or(1.0)]);
            let material = match rgba {
                Some(c) => {
                    let byte = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
                    let [r, g, b, a] = c.map(byte);
                    format!("#{r:02x}{g:02x}{b:02x}{a:02x}")
                }
                None => match argument(args, "c", 0) {
                    Some(Value::Str(name)) => name.clone(),
                    _ => return Err(bad("color needs a colour".into())),
                },
            };
            Node {
                material: Some(material),
                ..union(children)
            }
        }
        "cube" => {
            let size = match argument(args, "size", 0) {
                Some(Value::Number(s)) => [*s; 3],
                Some(v) => {
                    let s = vector(v).filter(|s| s.len() == 3);
                    let s =
                        s.ok_or_else(|| bad("cube size must be a number or 3 numbers".into()))?;
                    [s[0], s[1], s[2]]
                }
                None => [1.0; 3],
            };
            let centre = matches!(argument(args, "center", 1), Some(Value::Bool(true)));
            let min = if centre {
                size.map(|s| -s / 2.0)
            } else {
                [0.0; 3]
            };
            leaf(cuboid(min, [0, 1, 2].map(|k| min[k] + size[k])), name, line)
        }
        "sphere" => {
            let r = number(argument(args, "r", 0)).unwrap_or(1.0);
            leaf(uv_sphere([0.0; 3], r, fragments(r, args)), name, line)
        }
        "cylinder" => {
            let h = number(argument(args, "h", 0)).unwrap_or(1.0);
            let r = number(argument(args, "r", usize::MAX));
            let r1 = number(argument(args, "r1", 1)).or(r).unwrap_or(1.0);
            let r2 = number(argument(args, "r2", 2)).or(r).unwrap_or(1.0);
            let centre = matches!(
                argument(args, "center", usize::MAX),
                Some(Value::Bool(true))
            );
            let n = fragments(r1.max(r2), args);
            let z = if centre { -h / 2.0 } else { 0.0 };
            leaf(cylinder(r1, r2, z, z + h, n), name, line)
        }
        "polyhedron" => {
            let points: Vec<[f64; 3]> = (argument(args, "points", 0))
                .and_then(|p| match p {
                    Value::Vector(items) => items.iter().map(vector).collect::<Option<Vec<_>>>(),
                    _ => None,
                })
                .filter(|ps| ps.iter().all(|p| p.len() == 3))
                .map(|ps| ps.into_iter().map(|p| [p[0], p[1], p[2]]).collect())
                .ok_or_else(|| bad("polyhedron points must be 3-vectors".into()))?;
            let faces = argument(args, "faces", 1).or_else(|| argument(args, "triangles", 1));
            let faces: Vec<Vec<f64>> = faces
                .and_then(|f| match f {
                    Value::Vector(items) => items.iter().map(vector).collect::<Option<Vec<_>>>(),
                    _ => None,
                })
                .ok_or_else(|| bad("polyhedron faces must be lists of indices".into()))?;
            let mut polygons = Vec::with_capacity(faces.len());
            for face in &faces {
                let valid = |&i: &f64| i >= 0.0 && i.fract() == 0.0 && (i as usize) < points.len();
                if face.len() < 3 || !face.iter().all(valid) {
                    return Err(bad(format!(
                        "polyhedron face {face:?} is not a polygon of its points"
                    )));
                }
                polygons.push(face.iter().rev().map(|&i| i as u32).collect::<Vec<u32>>());
            }
            let mesh = Mesh::from_polygons(points, &polygons)
                .map_err(|e| bad(format!("polyhedron: {e}")))?;
            leaf(mesh, name, line)
        }
        other => {
            return Err(bad(format!(
                "{other}() is not supported by csgkit's .csg reader"
            )));
        }
    })
}

fn leaf(mesh: Mesh, name: &str, line: usize) -> Node {
    Node::mesh(mesh, format!("{name} at line {line}"))
}

/// OpenSCAD's fragment count for a circle of radius `r` under the node's `$fn`, `$fa`,
/// `$fs` (`Calc::get_fragments_from_r`).
fn fragments(r: f64, args: &[(Option<String>, Value)]) -> u32 {
    let get =
        |name: &str, default: f64| number(argument(args, name, usize::MAX)).unwrap_or(default);
    let (fn_, fa, fs) = (get("$fn", 0.0), get("$fa", 12.0), get("$fs", 2.0));
    if r < 1.0 / f64::from(1u32 << 20) {
        return 3;
    }
    if fn_ > 0.0 {
        return if fn_ >= 3.0 { fn_ as u32 } else { 3 };
    }
    (360.0 / fa)
        .min(r * 2.0 * std::f64::consts::PI / fs)
        .max(5.0)
        .ceil() as u32
}

/// OpenSCAD's cylinder (or cone, where a radius is 0) between heights `z1` and `z2`.
fn cylinder(r1: f64, r2: f64, z1: f64, z2: f64, n: u32) -> Mesh {
    let ring = |r: f64, z: f64| -> Vec<[f64; 3]> {
        if r > 0.0 {
            circle(r, n).into_iter().map(|[x, y]| [x, y, z]).collect()
        } else {
            vec![[0.0, 0.0, z]]
        }
    };
    let (bottom, top) = (ring(r1, z1), ring(r2, z2));
    let (nb, nt) = (bottom.len() as u32, top.len() as u32);
    let mut positions = bottom;
    positions.extend(top);
    let b = |j: u32| j % nb;
    let t = |j: u32| nb + j % nt;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    if nb > 1 {
        faces.push((0..nb).rev().map(b).collect());
    }
    if nt > 1 {
        faces.push((0..nt).map(t).collect());
    }
    for j in 0..n {
        let mut side = vec![b(j), b(j + 1)];
        if nt > 1 {
            side.push(t(j + 1));
        }
        side.push(t(j));
        if nb == 1 {
            side.remove(0);
        }
        faces.push(side);
    }
    Mesh::from_polygons(positions, &faces).expect("primitive faces index its points")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::csg::NodeKind;
    use crate::primitives::{cos_degrees, sin_degrees};

    #[test]
    fn fragments_follow_openscad() {
        let args = |fn_: f64| vec![(Some("$fn".to_owned()), Value::Number(fn_))];
        assert_eq!(fragments(10.0, &args(0.0)), 30); // min(360/12, 2π·10/2 = 31.4)
        assert_eq!(fragments(1.0, &args(0.0)), 5);
        assert_eq!(fragments(1.0, &args(7.0)), 7);
        assert_eq!(fragments(1.0, &args(2.0)), 3);
        assert_eq!(fragments(1e-7, &args(50.0)), 3);
        assert_eq!(sin_degrees(30.0), 0.5);
        assert_eq!(cos_degrees(90.0), 0.0);
        assert_eq!(cos_degrees(180.0), -1.0);
    }

    #[test]
    fn primitives_are_closed_solids() {
        for mesh in [
            uv_sphere([0.0; 3], 2.0, 9),
            cylinder(1.0, 0.5, -1.0, 1.0, 7),
            cylinder(1.0, 0.0, 0.0, 2.0, 6),
        ] {
            let report = mesh.report();
            assert!(report.is_valid_solid(), "{report:?}");
            assert!(report.measures.volume > 0.0);
        }
    }

    #[test]
    fn unsupported_nodes_are_named_with_their_line() {
        let err =
            parse_openscad_csg("group() {\n  cube(size = 1);\n  hull() { sphere(r = 1); }\n}")
                .unwrap_err();
        assert_eq!(
            err.to_string(),
            "line 3: hull() is not supported by csgkit's .csg reader"
        );
    }

    #[test]
    fn modifiers_follow_openscad() {
        let tree =
            parse_openscad_csg("cube(size = 1);\n%sphere(r = 1);\n*cube(size = 2);").unwrap();
        let NodeKind::Apply(Operation::Union, children) = &tree.kind else {
            panic!()
        };
        assert_eq!(children.len(), 1);
        let tree = parse_openscad_csg("cube(size = 1);\n!sphere(r = 1);").unwrap();
        assert!(matches!(tree.kind, NodeKind::Mesh { .. }));
    }
}
