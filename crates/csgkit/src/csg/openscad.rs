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
//! - `hull()` of solids or of 2D shapes: the exact convex hull ([`convex_hull`],
//!   [`convex_hull_2d`]) of its leaves' points, placed by the transforms below it, where the
//!   subtree holds only unions (a hull of a difference is an error);
//! - `import(file)` of a mesh file csgkit reads (STL, OBJ, OFF, 3MF, PLY, glTF), a path
//!   relative to the `.csg` file's directory, as OpenSCAD reads it (an export writes the path
//!   as the model names it), each file read once however often it is imported; its faces
//!   keep their materials. A 2D drawing (DXF, SVG) is an error.
//! - Modifiers: `%` and `*` leave their subtree out, `#` keeps it, `!` makes its subtree the
//!   whole model.
//!
//! Every other node (`minkowski`, `offset`, `text`, `surface`, `projection`, `resize`) is an
//! error naming the node and its line.
//!
//! # Tessellation (OpenSCAD 2021, `src/calc.cc`, `src/primitives.cc`, `src/degree_trig.cc`)
//! - Fragments of a circle of radius `r`: 3 when `r` is below 2^-20; `max($fn, 3)` when `$fn`
//!   > 0; otherwise `ceil(max(min(360 / $fa, 2πr / $fs), 5))`.
//! - A circle's points are at `360° · i / n` from angle 0, counter-clockwise.
//! - A sphere has `(n + 1) / 2` rings at polar angles `180° · (i + ½) / rings`.
//! - Angles are in degrees with OpenSCAD's exact values at multiples of 30° and 45°.
//! - `$fa` and `$fs` below 0.01 count as 0.01, as in OpenSCAD; a cylinder without height,
//!   or without radius at both ends, is no solid.
//!
//! # Limits
//! A number literal beyond f64's range, a negative or non-finite cylinder radius, and a `$fn`
//! or `slices` above 10 000 (a sphere of that many fragments has 5·10⁷ faces) are errors
//! naming their line, where OpenSCAD would render nothing, render garbage, or run out of memory.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::extrude::{Extrusion, LinearExtrude, RotateExtrude, prism};
use super::tree::{Node, NodeKind};
use crate::Operation;
use crate::io::read_mesh;
use crate::mesh::{Affine, Mesh, convex_hull, convex_hull_2d};
use crate::primitives::{Fragments, circle, cuboid, uv_sphere};

/// Why a `.csg` file could not be read: the line and what is wrong there.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct OpenScadError {
    /// The line (from 1).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Reads the text of a `.csg` file into a tree (see the module docs); `import()` reads the
/// files it names relative to `base`, the directory of the `.csg` file.
///
/// # Errors
/// [`OpenScadError`] naming the line of a malformed statement, an unsupported node or an
/// imported file that cannot be read (with the reader's own error: the file, and the line or
/// byte at fault).
pub fn parse_openscad_csg(text: &str, base: &Path) -> Result<Node, OpenScadError> {
    let tokens = tokenize(text)?;
    let mut parser = Parser {
        tokens,
        at: 0,
        outlines_made: 0,
        imports: Imports {
            base,
            read: HashMap::new(),
        },
    };
    let mut roots = Vec::new();
    let mut root_only = None;
    while !parser.done() {
        if let Some((built, root)) = parser.statement()? {
            if root && root_only.is_none() {
                root_only = Some(built.clone());
            }
            roots.push(built);
        }
    }
    let model = match root_only {
        Some(root) => root,
        None => combine(Operation::Union, roots, parser.line())?,
    };
    if model.dimension == Dimension::Flat {
        return Err(OpenScadError {
            line: model.line,
            message: "the model is 2D; csgkit evaluates solids (extrude it with \
                      linear_extrude or rotate_extrude)"
                .into(),
        });
    }
    Ok(model.node)
}

/// A node as the reader builds it: 2D shapes are prisms (see [`super::extrude`]) until an
/// extrusion sweeps them.
#[derive(Clone, Debug)]
struct Built {
    node: Node,
    dimension: Dimension,
    /// Where the node starts, for errors.
    line: usize,
}

/// Whether a subtree is a 2D shape or a solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dimension {
    /// No geometry (an empty group).
    Empty,
    /// A 2D shape (its prism).
    Flat,
    /// A solid.
    Solid,
}

/// `op` over `children`, which must all be 2D or all solids (OpenSCAD ignores the ones that
/// differ from the first with a warning; csgkit refuses the model instead).
fn combine(op: Operation, children: Vec<Built>, line: usize) -> Result<Built, OpenScadError> {
    let mut dimension = Dimension::Empty;
    for child in &children {
        match (dimension, child.dimension) {
            (_, Dimension::Empty) => {}
            (Dimension::Empty, d) => dimension = d,
            (d, e) if d != e => {
                return Err(OpenScadError {
                    line: child.line,
                    message: "2D shapes and solids are mixed in one operation".into(),
                });
            }
            _ => {}
        }
    }
    let nodes = children.into_iter().map(|c| c.node).collect();
    Ok(Built {
        node: Node::apply(op, nodes),
        dimension,
        line,
    })
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
                // A literal beyond f64's range parses as an infinity, which no solid holds.
                if !value.is_finite() {
                    return Err(OpenScadError {
                        line,
                        message: format!("{word} is beyond the range of f64 numbers"),
                    });
                }
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

struct Parser<'a> {
    tokens: Vec<(Token, usize)>,
    at: usize,
    /// Outlines of 2D shapes so far: each prism outline gets its own height (see
    /// [`super::extrude`]).
    outlines_made: u32,
    imports: Imports<'a>,
}

/// The mesh files `import()` names, each read once: a model that places one part many times
/// (a `for` loop of imports, which the export unrolls) reads its file once.
struct Imports<'a> {
    /// The directory relative paths start from.
    base: &'a Path,
    read: HashMap<PathBuf, Mesh>,
}

impl Imports<'_> {
    /// The mesh of `file`, or why there is none.
    fn mesh(&mut self, file: &str) -> Result<Mesh, String> {
        let path = self.base.join(file);
        if let Some(mesh) = self.read.get(&path) {
            return Ok(mesh.clone());
        }
        let extension = (path.extension().and_then(|e| e.to_str()))
            .unwrap_or_default()
            .to_ascii_lowercase();
        if matches!(extension.as_str(), "dxf" | "svg") {
            return Err(format!(
                "import(\"{file}\"): 2D drawings (DXF, SVG) are not supported by csgkit's .csg reader"
            ));
        }
        let mesh = read_mesh(&path)
            .map_err(|e| format!("import(\"{file}\"): {e}"))?
            .mesh;
        self.read.insert(path, mesh.clone());
        Ok(mesh)
    }
}

impl Parser<'_> {
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
    fn statement(&mut self) -> Result<Option<(Built, bool)>, OpenScadError> {
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
        let built = build(
            &name,
            &args,
            children,
            line,
            &mut self.outlines_made,
            &mut self.imports,
        )?;
        Ok((!skip).then_some((built, root)))
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
    children: Vec<Built>,
    line: usize,
    outlines_made: &mut u32,
    imports: &mut Imports,
) -> Result<Built, OpenScadError> {
    let bad = |message: String| OpenScadError { line, message };
    let union = |children| combine(Operation::Union, children, line);
    let solid = |node| Built {
        node,
        dimension: Dimension::Solid,
        line,
    };
    let mut flat = |outlines: &[Vec<[f64; 2]>]| Built {
        node: leaf(
            prism(outlines, |_| {
                *outlines_made += 1;
                f64::from(*outlines_made)
            }),
            name,
            line,
        ),
        dimension: Dimension::Flat,
        line,
    };
    Ok(match name {
        "group" | "union" | "render" => union(children)?,
        "difference" => combine(Operation::Difference, children, line)?,
        "intersection" => combine(Operation::Intersection, children, line)?,
        "multmatrix" => {
            let rows = argument(args, "m", 0)
                .and_then(|m| match m {
                    Value::Vector(rows) => rows.iter().map(vector).collect::<Option<Vec<_>>>(),
                    _ => None,
                })
                .filter(|rows| rows.len() >= 3 && rows.iter().all(|r| r.len() == 4))
                .ok_or_else(|| bad("multmatrix needs a 4 × 4 matrix".into()))?;
            let mut transform: Affine =
                std::array::from_fn(|i| std::array::from_fn(|j| rows[i][j]));
            let mut built = union(children)?;
            if built.dimension == Dimension::Flat {
                // A 2D shape moves in its plane (OpenSCAD's Transform2d): its prism keeps
                // z from 0 to 1.
                transform[2] = [0.0, 0.0, 1.0, 0.0];
                transform[0][2] = 0.0;
                transform[1][2] = 0.0;
            }
            built.node.transform = Some(transform);
            built
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
            let mut built = union(children)?;
            built.node.material = Some(material);
            built
        }
        "cube" => {
            let size = match argument(args, "size", 0) {
                Some(v) => per_axis(v)
                    .ok_or_else(|| bad("cube size must be a number or 3 numbers".into()))?,
                None => [1.0; 3],
            };
            let centre = matches!(argument(args, "center", 1), Some(Value::Bool(true)));
            let min = if centre {
                size.map(|s| -s / 2.0)
            } else {
                [0.0; 3]
            };
            solid(leaf(
                cuboid(min, [0, 1, 2].map(|k| min[k] + size[k])),
                name,
                line,
            ))
        }
        "sphere" => {
            let r = number(argument(args, "r", 0)).unwrap_or(1.0);
            solid(leaf(
                uv_sphere([0.0; 3], r, fragments(args).map_err(bad)?.count(r)),
                name,
                line,
            ))
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
            if ![h, r1, r2].iter().all(|x| x.is_finite()) || r1 < 0.0 || r2 < 0.0 {
                return Err(bad(format!(
                    "cylinder needs a finite height and finite radii of at least 0, not h = {h}, r1 = {r1}, r2 = {r2}"
                )));
            }
            // As OpenSCAD: no height, or no radius at either end, is no solid.
            if h <= 0.0 || (r1 == 0.0 && r2 == 0.0) {
                return Ok(solid(leaf(Mesh::new(), name, line)));
            }
            let n = fragments(args).map_err(bad)?.count(r1.max(r2));
            let z = if centre { -h / 2.0 } else { 0.0 };
            solid(leaf(cylinder(r1, r2, z, z + h, n), name, line))
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
            solid(leaf(mesh, name, line))
        }
        "square" => {
            let size = match argument(args, "size", 0) {
                Some(v) => per_axis(v)
                    .ok_or_else(|| bad("square size must be a number or 2 numbers".into()))?,
                None => [1.0; 2],
            };
            let centre = matches!(argument(args, "center", 1), Some(Value::Bool(true)));
            let [x0, y0] = if centre {
                size.map(|s| -s / 2.0)
            } else {
                [0.0; 2]
            };
            let [x1, y1] = [x0 + size[0], y0 + size[1]];
            // OpenSCAD makes nothing of a square without area, or a circle without radius.
            let positive = size.iter().all(|s| *s > 0.0 && s.is_finite());
            flat(
                &positive
                    .then(|| vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
                    .into_iter()
                    .collect::<Vec<_>>(),
            )
        }
        "circle" => {
            let r = number(argument(args, "r", 0)).unwrap_or(1.0);
            let positive = r > 0.0 && r.is_finite();
            let n = fragments(args).map_err(bad)?.count(r);
            flat(
                &positive
                    .then(|| circle(r, n))
                    .into_iter()
                    .collect::<Vec<_>>(),
            )
        }
        "polygon" => {
            let points = points_2d(argument(args, "points", 0))
                .ok_or_else(|| bad("polygon points must be 2-vectors".into()))?;
            let outlines = match argument(args, "paths", 1) {
                None | Some(Value::Undef) => vec![points],
                Some(Value::Vector(paths)) => {
                    let mut outlines = Vec::with_capacity(paths.len());
                    for path in paths {
                        let indices = vector(path).ok_or_else(|| {
                            bad("polygon paths must be lists of point indices".into())
                        })?;
                        let mut outline = Vec::with_capacity(indices.len());
                        for i in indices {
                            if i < 0.0 || i.fract() != 0.0 || i as usize >= points.len() {
                                return Err(bad(format!(
                                    "polygon path index {i} is not one of its {} points",
                                    points.len()
                                )));
                            }
                            outline.push(points[i as usize]);
                        }
                        outlines.push(outline);
                    }
                    outlines
                }
                Some(_) => return Err(bad("polygon paths must be lists of point indices".into())),
            };
            flat(&outlines)
        }
        "import" => {
            let Some(Value::Str(file)) = argument(args, "file", 0) else {
                return Err(bad("import needs a file name".into()));
            };
            let mesh = imports.mesh(file).map_err(bad)?;
            solid(Node::mesh(
                mesh,
                format!("import(\"{file}\") at line {line}"),
            ))
        }
        "hull" => {
            let built = union(children)?;
            let mut points = Vec::new();
            if !built.node.union_points(&mut points) {
                return Err(bad(
                    "hull() of a difference, an intersection or an extrusion \
                                is not supported by csgkit's .csg reader"
                        .into(),
                ));
            }
            match built.dimension {
                Dimension::Empty => built,
                Dimension::Solid => solid(leaf(convex_hull(&points), name, line)),
                Dimension::Flat => {
                    let plane: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[1]]).collect();
                    let ring = convex_hull_2d(&plane);
                    flat(
                        &(!ring.is_empty())
                            .then_some(ring)
                            .into_iter()
                            .collect::<Vec<_>>(),
                    )
                }
            }
        }
        "linear_extrude" | "rotate_extrude" => {
            let profile = union(children)?;
            if profile.dimension == Dimension::Solid {
                return Err(OpenScadError {
                    line: profile.line,
                    message: format!("{name} sweeps 2D shapes, not solids"),
                });
            }
            let extrusion = if name == "linear_extrude" {
                linear_extrude(args).map_err(bad)?
            } else {
                Extrusion::Rotate(RotateExtrude {
                    angle: number(argument(args, "angle", usize::MAX)).unwrap_or(360.0),
                    fragments: fragments(args).map_err(bad)?,
                })
            };
            solid(Node {
                kind: NodeKind::Extrude {
                    profile: Box::new(profile.node),
                    extrusion,
                    name: format!("{name} at line {line}"),
                },
                transform: None,
                material: None,
            })
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

/// `linear_extrude`'s parameters; `slices` defaults to OpenSCAD's rule for the shape's
/// twist and scale, decided when the profile is known.
fn linear_extrude(args: &[(Option<String>, Value)]) -> Result<Extrusion, String> {
    let height = number(argument(args, "height", 0)).unwrap_or(100.0);
    let scale = match argument(args, "scale", usize::MAX) {
        None | Some(Value::Undef) => [1.0; 2],
        Some(v) => per_axis(v).ok_or("linear_extrude scale must be a number or 2 numbers")?,
    };
    // OpenSCAD truncates slices and ignores fewer than 1, and clamps negative scales to 0.
    let slices = number(argument(args, "slices", usize::MAX)).filter(|&s| s >= 1.0);
    if let Some(slices) = slices.filter(|&s| s > MAX_FRAGMENTS) {
        return Err(format!(
            "slices = {slices} asks for more than the {MAX_FRAGMENTS} slices csgkit builds"
        ));
    }
    let scale = scale.map(|s: f64| s.max(0.0));
    Ok(Extrusion::Linear(LinearExtrude {
        height,
        center: matches!(
            argument(args, "center", usize::MAX),
            Some(Value::Bool(true))
        ),
        twist: number(argument(args, "twist", usize::MAX)).unwrap_or(0.0),
        slices: slices.map(|s| s as u32),
        scale,
        fragments: fragments(args)?,
    }))
}

/// A size or scale: one number for every axis, or one number per axis.
fn per_axis<const N: usize>(value: &Value) -> Option<[f64; N]> {
    match value {
        Value::Number(s) => Some([*s; N]),
        v => vector(v).and_then(|s| s.try_into().ok()),
    }
}

/// A list of 2-vectors.
fn points_2d(value: Option<&Value>) -> Option<Vec<[f64; 2]>> {
    match value? {
        Value::Vector(items) => items
            .iter()
            .map(|p| vector(p).filter(|p| p.len() == 2).map(|p| [p[0], p[1]]))
            .collect(),
        _ => None,
    }
}

/// The most fragments of a circle (`$fn`) or slices of an extrusion csgkit builds: a sphere
/// of this many fragments already has 5·10⁷ faces, and a count from a typo (`$fn = 1e9`)
/// would exhaust memory rather than fail.
const MAX_FRAGMENTS: f64 = 10_000.0;

/// The node's `$fn`, `$fa`, `$fs`; `$fa` and `$fs` below 0.01 count as 0.01, as in
/// OpenSCAD, and a `$fn` above [`MAX_FRAGMENTS`] is an error.
fn fragments(args: &[(Option<String>, Value)]) -> Result<Fragments, String> {
    let get = |name: &str| number(argument(args, name, usize::MAX));
    let default = Fragments::default();
    let fn_ = get("$fn").unwrap_or(default.fn_);
    if fn_ > MAX_FRAGMENTS {
        return Err(format!(
            "$fn = {fn_} asks for more than the {MAX_FRAGMENTS} fragments per circle csgkit builds"
        ));
    }
    Ok(Fragments {
        fn_,
        fa: get("$fa").unwrap_or(default.fa).max(0.01),
        fs: get("$fs").unwrap_or(default.fs).max(0.01),
    })
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

    /// The tree of `text`, with imports relative to the working directory.
    fn parse(text: &str) -> Result<Node, OpenScadError> {
        parse_openscad_csg(text, Path::new("."))
    }

    #[test]
    fn fragments_follow_openscad() {
        let args = |fn_: f64| vec![(Some("$fn".to_owned()), Value::Number(fn_))];
        assert_eq!(fragments(&args(0.0)).unwrap().count(10.0), 30); // min(360/12, 2π·10/2 = 31.4)
        assert_eq!(fragments(&args(0.0)).unwrap().count(1.0), 5);
        assert_eq!(fragments(&args(7.0)).unwrap().count(1.0), 7);
        assert_eq!(fragments(&args(2.0)).unwrap().count(1.0), 3);
        assert_eq!(fragments(&args(50.0)).unwrap().count(1e-7), 3);
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
            parse("group() {\n  cube(size = 1);\n  minkowski() { sphere(r = 1); }\n}").unwrap_err();
        assert_eq!(
            err.to_string(),
            "line 3: minkowski() is not supported by csgkit's .csg reader"
        );
    }

    #[test]
    fn hulls_of_solids_and_of_2d_shapes_are_exact() {
        let volume = |text: &str| {
            let tree = parse(text).unwrap();
            let out = super::super::evaluate(
                &tree,
                &crate::exact::BooleanOptions::default(),
                &crate::Progress::default(),
            )
            .unwrap();
            let report = out.result.mesh.report();
            assert!(report.is_valid_solid(), "{text}");
            report.measures.volume
        };
        // Two unit cubes a diagonal apart: the hull adds the prism between them.
        let cubes = "hull() { cube(size = 1); multmatrix([[1, 0, 0, 2], [0, 1, 0, 0], \
                     [0, 0, 1, 0], [0, 0, 0, 1]]) { cube(size = 1); } }";
        assert_eq!(volume(cubes), 3.0);
        // A square and a circle of 4 fragments (a diamond) beside it, extruded by 2.
        let flat = "linear_extrude(height = 2) { hull() { square(size = 1); \
                    multmatrix([[1, 0, 0, 3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) \
                    { circle(r = 1, $fn = 4); } } }";
        // The hull of (0,0), (1,0), (1,1), (0,1), (4,0), (3,1), (2,0), (3,-1) is the
        // pentagon (0,0), (3,-1), (4,0), (3,1), (0,1): area 5.5.
        assert_eq!(volume(flat), 2.0 * 5.5);
        let err = parse("hull() { difference() { cube(size = 2); cube(size = 1); } }").unwrap_err();
        assert!(err.message.starts_with("hull() of a difference"), "{err}");
    }

    /// A unit cube as OBJ text, its faces of material `steel`.
    const STEEL_CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n\
        v 1 1 1\nv 0 1 1\nusemtl steel\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\n\
        f 3 4 8 7\nf 4 1 5 8\n";

    #[test]
    fn imports_read_mesh_files_relative_to_the_csg_file_once() {
        let dir = tempfile::TempDir::new().unwrap();
        std::fs::create_dir(dir.path().join("parts")).unwrap();
        std::fs::write(dir.path().join("parts/cube.obj"), STEEL_CUBE).unwrap();
        // The part, and the part moved half its width along x: the union is 1.5 long.
        let text = "union() {\n  import(file = \"parts/cube.obj\", convexity = 1);\n  \
                    multmatrix([[1, 0, 0, 0.5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) \
                    { import(\"parts/cube.obj\"); }\n}";
        let tree = parse_openscad_csg(text, dir.path()).unwrap();
        let out = super::super::evaluate(
            &tree,
            &crate::exact::BooleanOptions::default(),
            &crate::Progress::default(),
        )
        .unwrap();
        let mesh = &out.result.mesh;
        let report = mesh.report();
        assert!(report.is_valid_solid(), "{report:?}");
        assert_eq!(report.measures.volume, 1.5);
        // The faces keep the part's material.
        assert_eq!(mesh.materials(), ["steel"]);
        assert!(mesh.face_materials().unwrap().iter().all(|&m| m == 0));

        // A file is read once: the second import of it comes from what the first read.
        let mut imports = Imports {
            base: dir.path(),
            read: HashMap::new(),
        };
        let first = imports.mesh("parts/cube.obj").unwrap();
        std::fs::remove_file(dir.path().join("parts/cube.obj")).unwrap();
        let again = imports.mesh("parts/cube.obj").unwrap();
        assert_eq!(first.positions(), again.positions());
    }

    #[test]
    fn imports_that_cannot_be_read_are_errors_naming_the_file_and_line() {
        let dir = tempfile::TempDir::new().unwrap();
        let err = parse_openscad_csg("cube(size = 1);\nimport(\"missing.stl\");", dir.path())
            .unwrap_err();
        assert_eq!(err.line, 2);
        assert!(
            err.message.starts_with("import(\"missing.stl\"): "),
            "{err}"
        );
        assert!(err.message.contains("missing.stl"), "{err}");
        // A truncated file: the reader's error, with its place in the file.
        std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
        let err = parse_openscad_csg("import(\"bad.obj\");", dir.path()).unwrap_err();
        assert!(err.message.contains("line 3"), "{err}");
        let err = parse_openscad_csg("import(file = \"plate.dxf\");", dir.path()).unwrap_err();
        assert!(err.message.contains("2D drawings"), "{err}");
        let err = parse_openscad_csg("import(convexity = 3);", dir.path()).unwrap_err();
        assert_eq!(err.message, "import needs a file name");
    }

    #[test]
    fn modifiers_follow_openscad() {
        let tree = parse("cube(size = 1);\n%sphere(r = 1);\n*cube(size = 2);").unwrap();
        let NodeKind::Apply(Operation::Union, children) = &tree.kind else {
            panic!()
        };
        assert_eq!(children.len(), 1);
        let tree = parse("cube(size = 1);\n!sphere(r = 1);").unwrap();
        assert!(matches!(tree.kind, NodeKind::Mesh { .. }));
    }

    #[test]
    fn cylinders_without_height_or_radius_are_empty_and_bad_ones_are_errors() {
        for text in [
            "cylinder(h = 1, r = 0);",
            "cylinder(h = 0, r = 1);",
            "cylinder(h = -2, r1 = 1, r2 = 2);",
        ] {
            let tree = parse(text).unwrap();
            // The file's statements are united; this one is the union's only child.
            let leaf = match &tree.kind {
                NodeKind::Apply(Operation::Union, children) if children.len() == 1 => {
                    &children[0].kind
                }
                kind => kind,
            };
            let NodeKind::Mesh { mesh, .. } = leaf else {
                panic!("{text}: {leaf:?}")
            };
            assert!(mesh.is_empty(), "{text}");
        }
        let err = parse("group() {\n  cylinder(h = 1, r1 = -1, r2 = 1);\n}").unwrap_err();
        assert_eq!(err.line, 2);
        assert!(err.message.contains("radii of at least 0"), "{err}");
    }

    #[test]
    fn numbers_beyond_f64_are_errors_naming_their_line() {
        let err = parse("cube(size = 1);\ncube(size = 1e999);").unwrap_err();
        assert_eq!(err.line, 2);
        assert_eq!(err.message, "1e999 is beyond the range of f64 numbers");
    }

    #[test]
    fn fragment_counts_beyond_the_limit_are_errors() {
        let err = parse("sphere($fn = 1e9, r = 1);").unwrap_err();
        assert_eq!(err.line, 1);
        assert!(
            err.message.starts_with("$fn = 1000000000 asks for more"),
            "{err}"
        );
        let extrude = "linear_extrude(height = 1, slices = 1e7) { square(size = 1); }";
        assert!(parse(extrude).unwrap_err().message.contains("slices"));
        // $fa and $fs of 0 count as 0.01: at most 360 / 0.01 fragments.
        let args = vec![
            (Some("$fa".to_owned()), Value::Number(0.0)),
            (Some("$fs".to_owned()), Value::Number(0.0)),
        ];
        assert_eq!(fragments(&args).unwrap().count(1e6), 36_000);
    }
}
