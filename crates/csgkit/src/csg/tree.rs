//! CSG trees and their evaluation in one exact pass.
//!
//! A [`Node`] is a leaf (a mesh with its attributes, named for errors) or an operation on
//! child nodes; any node may carry an affine transform and a material. [`evaluate`] flattens
//! the tree: every leaf's vertices are moved once by the product of the transforms above it
//! (faces reversed where that product mirrors), every leaf takes the material of its nearest
//! node that names one, and the tree becomes an [`Expression`] over the leaves, which the
//! exact engine evaluates in one arrangement of all leaves, rounded once
//! ([`boolean_expression`]): no chain of binary booleans, so no rounding between the
//! operations of a tree.
//!
//! One exception: an operation under a transform that turns the axes (its linear part is
//! not a scaled signed permutation), whose leaves have faces in a common axis-aligned plane
//! where they stand before the turn, is evaluated there first, in its own pass, and its
//! result is moved and becomes a leaf ([`turns_shared_planes`]). Rounding turned
//! coordinates moves each leaf's copy of a shared plane its own way, and the arrangement of
//! planes that no longer coincide fills with slivers a few ulps wide: OpenSCAD's example024,
//! a Menger sponge of 219 bars turned by 45°, did not end in 300 s as one pass, and takes a
//! fraction of a second with its bars' union in the orthogonal engine before the turn. The
//! result is then exact for the operands of each pass, rounded once more per such subtree.

use rustc_hash::FxHashMap;

use crate::Operation;
use crate::exact::{
    Boolean, BooleanError, BooleanOptions, BooleanStats, Expression, boolean_expression,
};
use crate::kernel::Precision;
use crate::mesh::{Affine, FaceMode, IDENTITY, Mesh, compose, moved, transformed};
use crate::ortho::{MeshOptions, OrthoError, bounded_box, box_union, plain_box};
use crate::progress::Progress;

use super::extrude::{ExtrudeError, Extrusion, Profile};

/// A node of a CSG tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// What the node is.
    pub kind: NodeKind,
    /// Applied to the node's points (after its children's own transforms).
    pub transform: Option<Affine>,
    /// The material of every face below that names none closer to it.
    pub material: Option<String>,
}

/// A leaf or an operation.
#[derive(Clone, Debug, PartialEq)]
pub enum NodeKind {
    /// A closed mesh; `name` says where it came from (a file, a primitive), for errors.
    Mesh {
        /// The mesh.
        mesh: Box<Mesh>,
        /// Where it came from.
        name: String,
    },
    /// An operation on the children (a difference: the first minus the others).
    Apply(Operation, Vec<Node>),
    /// The solid swept by a 2D shape: `profile` is a tree of [`prism`]s (2D booleans are
    /// booleans of prisms), evaluated on its own before the sweep.
    ///
    /// [`prism`]: super::extrude::prism
    Extrude {
        /// The 2D shape, as a tree of prisms.
        profile: Box<Node>,
        /// How it is swept.
        extrusion: Extrusion,
        /// Where it came from, for errors.
        name: String,
    },
}

impl Node {
    /// A leaf without transform or material.
    pub fn mesh(mesh: Mesh, name: impl Into<String>) -> Node {
        Node {
            kind: NodeKind::Mesh {
                mesh: Box::new(mesh),
                name: name.into(),
            },
            transform: None,
            material: None,
        }
    }

    /// The map that places this node's points: its own transform, then `outer`.
    fn placement(&self, outer: Affine) -> Affine {
        self.transform.map_or(outer, |own| compose(outer, own))
    }

    /// Collects the points of this subtree's leaves, placed by the transforms within it (its
    /// own included), where the subtree holds only unions: the points a convex hull of it
    /// spans (OpenSCAD's `hull()`, a scene's `"hull"`). False where it holds another operation
    /// or an extrusion, whose points are not its leaves'.
    pub(super) fn union_points(&self, points: &mut Vec<[f64; 3]>) -> bool {
        self.union_points_under(IDENTITY, points)
    }

    fn union_points_under(&self, outer: Affine, points: &mut Vec<[f64; 3]>) -> bool {
        let transform = self.placement(outer);
        match &self.kind {
            NodeKind::Mesh { mesh, .. } => {
                points.extend(mesh.positions().iter().map(|&p| moved(&transform, p)));
                true
            }
            NodeKind::Apply(Operation::Union, children) => {
                (children.iter()).all(|child| child.union_points_under(transform, points))
            }
            NodeKind::Apply(..) | NodeKind::Extrude { .. } => false,
        }
    }

    /// An operation node without transform or material.
    pub fn apply(op: Operation, children: Vec<Node>) -> Node {
        Node {
            kind: NodeKind::Apply(op, children),
            transform: None,
            material: None,
        }
    }
}

/// Why a tree could not be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CsgError {
    /// A transform has a non-finite entry or is singular.
    #[error("{leaf}: its transform is singular or not finite")]
    BadTransform {
        /// The leaf it applies to.
        leaf: String,
    },
    /// The orthogonal engine refused a union of boxes.
    #[error("a union of {boxes} boxes: {error}")]
    Boxes {
        /// How many boxes.
        boxes: usize,
        /// The engine's error.
        error: OrthoError,
    },
    /// A 2D shape could not be swept.
    #[error("{leaf}: {error}")]
    Extrude {
        /// The extrusion node.
        leaf: String,
        /// What is wrong.
        error: ExtrudeError,
    },
    /// The exact engine refused a leaf, or the operation failed.
    #[error("{}{error}", leaf.as_ref().map(|l| format!("{l}: ")).unwrap_or_default())]
    Boolean {
        /// The leaf the error names, if it names one.
        leaf: Option<String>,
        /// The engine's error.
        error: BooleanError,
    },
}

/// A tree's result, with its size.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// The exact engine's result and statistics.
    pub result: Boolean,
    /// Leaves of the tree.
    pub leaves: usize,
    /// Operation nodes of the tree.
    pub operations: usize,
}

/// A tree flattened: every leaf placed and painted (extrusions swept), in depth-first order,
/// and the expression over them.
#[derive(Clone, Debug)]
pub struct Flat {
    /// The tree's operations over the leaves.
    pub expression: Expression,
    /// The placed leaves.
    pub leaves: Vec<Mesh>,
    /// Where each leaf came from.
    pub names: Vec<String>,
    /// Operation nodes of the tree (the 2D ones below extrusions included).
    pub operations: usize,
}

/// Flattens `root` (see the module docs): the 2D subtree of every extrusion is evaluated on
/// its own, through `progress`, and swept into its leaf.
///
/// # Errors
/// [`CsgError::BadTransform`] for a singular or non-finite transform, [`CsgError::Extrude`]
/// for an extrusion that cannot be swept, [`CsgError::Boolean`] from a 2D subtree.
pub fn flatten(
    root: &Node,
    options: &BooleanOptions,
    progress: &Progress,
) -> Result<Flat, CsgError> {
    let mut flattened = Flattened::new(options, progress);
    let expression = flattened.visit(root, IDENTITY, None)?;
    Ok(Flat {
        expression,
        leaves: flattened.leaves,
        names: flattened.names,
        operations: flattened.operations,
    })
}

/// Evaluates `root` in one exact pass (see the module docs), reporting the exact engine's
/// stages to `progress`.
///
/// # Errors
/// As [`flatten`], and [`CsgError::Boolean`] (naming the leaf where the engine names an
/// operand) for the tree's operations, including a cancellation.
pub fn evaluate(
    root: &Node,
    options: &BooleanOptions,
    progress: &Progress,
) -> Result<Evaluation, CsgError> {
    let flat = flatten(root, options, progress)?;
    if flat.leaves.is_empty() {
        // A tree without leaves (an OpenSCAD model that only echoes) is the empty solid.
        return Ok(Evaluation {
            result: Boolean {
                mesh: Mesh::new(),
                stats: BooleanStats::default(),
            },
            leaves: 0,
            operations: flat.operations,
        });
    }
    let result = exact_pass(
        &flat.expression,
        &flat.leaves,
        &flat.names,
        options,
        progress,
    )?;
    Ok(Evaluation {
        result,
        leaves: flat.leaves.len(),
        operations: flat.operations,
    })
}

/// The exact engine's evaluation of `expression` over `leaves`, an error naming the leaf
/// (by `names`) where the engine names an operand.
fn exact_pass(
    expression: &Expression,
    leaves: &[Mesh],
    names: &[String],
    options: &BooleanOptions,
    progress: &Progress,
) -> Result<Boolean, CsgError> {
    let operands: Vec<&Mesh> = leaves.iter().collect();
    boolean_expression(expression, &operands, options, progress).map_err(|error| {
        let leaf = operand_of(&error).and_then(|k| names.get(k).cloned());
        CsgError::Boolean { leaf, error }
    })
}

/// The operand an engine error names.
fn operand_of(error: &BooleanError) -> Option<usize> {
    match error {
        BooleanError::InvalidOperand(invalid) => Some(invalid.operand()),
        _ => None,
    }
}

/// The leaves of a tree, transformed and painted, in depth-first order.
struct Flattened<'a, 'p> {
    options: &'a BooleanOptions,
    progress: &'a Progress<'p>,
    leaves: Vec<Mesh>,
    names: Vec<String>,
    operations: usize,
}

impl<'a, 'p> Flattened<'a, 'p> {
    fn new(options: &'a BooleanOptions, progress: &'a Progress<'p>) -> Self {
        Flattened {
            options,
            progress,
            leaves: Vec::new(),
            names: Vec::new(),
            operations: 0,
        }
    }

    fn visit(
        &mut self,
        node: &Node,
        outer: Affine,
        material: Option<&str>,
    ) -> Result<Expression, CsgError> {
        let transform = node.placement(outer);
        let material = node.material.as_deref().or(material);
        match &node.kind {
            NodeKind::Mesh { mesh, name } => self.leaf(mesh, name, transform, material),
            NodeKind::Extrude {
                profile,
                extrusion,
                name,
            } => {
                let prisms = evaluate(profile, self.options, self.progress)?;
                self.operations += prisms.operations;
                let profile = Profile::of_prisms(&prisms.result.mesh);
                let solid = extrusion
                    .solid(&profile)
                    .map_err(|error| CsgError::Extrude {
                        leaf: name.clone(),
                        error,
                    })?;
                self.leaf(&solid, name, transform, material)
            }
            NodeKind::Apply(..) if turns_shared_planes(node, transform) => {
                self.in_own_frame(node, transform, material)
            }
            NodeKind::Apply(Operation::Union, _) => {
                let mut boxes = Vec::new();
                if !(boxes_of(node, outer, &mut boxes) && boxes.len() >= 2) {
                    return self.apply(node, transform, material);
                }
                // A union of axis-aligned boxes: the orthogonal engine builds it exactly from
                // comparisons, and the exact engine meets one operand instead of many.
                self.operations += count_operations(node);
                let brep = box_union(&boxes).map_err(|error| CsgError::Boxes {
                    boxes: boxes.len(),
                    error,
                })?;
                let mesh = brep
                    .to_mesh(MeshOptions::default())
                    .map_err(|error| CsgError::Boxes {
                        boxes: boxes.len(),
                        error,
                    })?
                    .mesh;
                self.leaf(
                    &mesh,
                    &format!("a union of {} boxes", boxes.len()),
                    IDENTITY,
                    material,
                )
            }
            NodeKind::Apply(..) => self.apply(node, transform, material),
        }
    }

    /// An operation node: its children flattened under `transform`.
    fn apply(
        &mut self,
        node: &Node,
        transform: Affine,
        material: Option<&str>,
    ) -> Result<Expression, CsgError> {
        match &node.kind {
            NodeKind::Apply(op, children) => {
                self.operations += 1;
                let children = (children.iter())
                    .map(|child| self.visit(child, transform, material))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Expression::Apply(*op, children))
            }
            _ => unreachable!("apply is called on operation nodes"),
        }
    }

    /// An operation node evaluated in the frame of its children, in a pass of its own (see
    /// the module docs), its result moved by `transform` into the next operand. The pass
    /// gives an f64 mesh of triangles, whatever the options ask of the tree's final result.
    fn in_own_frame(
        &mut self,
        node: &Node,
        transform: Affine,
        material: Option<&str>,
    ) -> Result<Expression, CsgError> {
        let mut own = Flattened::new(self.options, self.progress);
        let expression = own.apply(node, IDENTITY, material)?;
        self.operations += own.operations;
        let options = BooleanOptions {
            precision: Precision::F64,
            faces: FaceMode::Triangles,
            split_non_manifold: false,
            merge_coplanar: false,
            simplify: None,
            ..*self.options
        };
        let result = exact_pass(
            &expression,
            &own.leaves,
            &own.names,
            &options,
            self.progress,
        )?;
        if result.mesh.is_empty() {
            return Ok(Expression::Apply(Operation::Union, Vec::new()));
        }
        let name = format!(
            "the result of {} leaves, evaluated before their turning transform",
            own.leaves.len()
        );
        // Its faces carry their leaves' materials already.
        self.leaf(&result.mesh, &name, transform, None)
    }

    /// Adds `mesh` as the next operand, moved and painted.
    fn leaf(
        &mut self,
        mesh: &Mesh,
        name: &str,
        transform: Affine,
        material: Option<&str>,
    ) -> Result<Expression, CsgError> {
        let leaf = placed(mesh, transform, material).ok_or_else(|| CsgError::BadTransform {
            leaf: name.to_owned(),
        })?;
        self.leaves.push(leaf);
        self.names.push(name.to_owned());
        Ok(Expression::Operand(self.leaves.len() - 1))
    }
}

/// Collects the boxes of a subtree made only of unions of cuboid leaves that bound
/// axis-aligned boxes once placed ([`bounded_box`]), with no material below its root and no
/// attribute on a leaf ([`plain_box`]: an imported part's materials or UVs, which the
/// orthogonal engine's boxes do not carry); false for any other subtree.
fn boxes_of(node: &Node, outer: Affine, boxes: &mut Vec<[f64; 6]>) -> bool {
    let transform = node.placement(outer);
    match &node.kind {
        NodeKind::Apply(Operation::Union, children) => (children.iter())
            .all(|child| child.material.is_none() && boxes_of(child, transform, boxes)),
        // Only a bare cuboid (its eight corners, nothing else): the orthogonal engine keeps
        // no other vertex, and a 2D shape's prism needs its ring in z = 0. A box moved by
        // anything but a scaled signed permutation is no longer one.
        NodeKind::Mesh { mesh, .. } if plain_box(mesh).is_some() => {
            match placed(mesh, transform, None).as_ref().and_then(bounded_box) {
                Some(b) => {
                    boxes.push(b);
                    true
                }
                None => false,
            }
        }
        _ => false,
    }
}

/// Whether `node`, an operation placed by `transform`, is one that [`evaluate`] evaluates
/// in its own frame (see the module docs): `transform` turns the axes, and two leaves below
/// the node, placed by the transforms between them and the node, have faces in one
/// axis-aligned plane. Extrusions are not looked at (their solids are swept later).
fn turns_shared_planes(node: &Node, transform: Affine) -> bool {
    let NodeKind::Apply(_, children) = &node.kind else {
        return false;
    };
    if keeps_axes(&transform) {
        return false;
    }
    // Each axis-aligned plane (axis, coordinate) with the first leaf that has a face in it.
    let mut planes: FxHashMap<(usize, u64), usize> = FxHashMap::default();
    let mut leaves = 0;
    children
        .iter()
        .any(|child| shares_a_plane(child, IDENTITY, &mut planes, &mut leaves))
}

/// Whether a leaf of `node` (placed by `outer` and the transforms within) has a face in an
/// axis-aligned plane that an earlier leaf (counted by `leaves`) has one in, recording the
/// planes of those it passes.
fn shares_a_plane(
    node: &Node,
    outer: Affine,
    planes: &mut FxHashMap<(usize, u64), usize>,
    leaves: &mut usize,
) -> bool {
    let transform = node.placement(outer);
    match &node.kind {
        NodeKind::Apply(_, children) => {
            (children.iter()).any(|child| shares_a_plane(child, transform, planes, leaves))
        }
        NodeKind::Extrude { .. } => false,
        NodeKind::Mesh { mesh, .. } => {
            let leaf = *leaves;
            *leaves += 1;
            let positions: Vec<[f64; 3]> = (mesh.positions().iter())
                .map(|&p| moved(&transform, p))
                .collect();
            mesh.faces().any(|face| {
                (0..3).any(|k| {
                    let x = positions[face[0] as usize][k];
                    face.iter().all(|&v| positions[v as usize][k] == x)
                        && *planes.entry((k, (x + 0.0).to_bits())).or_insert(leaf) != leaf
                })
            })
        }
    }
}

/// Whether the linear part of `transform` is a scaled signed permutation: axis-aligned planes
/// stay axis-aligned, and coordinates equal before it stay equal after it.
fn keeps_axes(transform: &Affine) -> bool {
    (0..3).all(|i| (0..3).filter(|&j| transform[i][j] != 0.0).count() == 1)
        && (0..3).all(|j| (0..3).filter(|&i| transform[i][j] != 0.0).count() == 1)
}

/// The operation nodes of a subtree.
fn count_operations(node: &Node) -> usize {
    match &node.kind {
        NodeKind::Apply(_, children) => 1 + children.iter().map(count_operations).sum::<usize>(),
        NodeKind::Extrude { .. } | NodeKind::Mesh { .. } => 0,
    }
}

/// `mesh` moved by `transform` (faces reversed where it mirrors) and painted `material`;
/// `None` when the transform is singular or not finite.
fn placed(mesh: &Mesh, transform: Affine, material: Option<&str>) -> Option<Mesh> {
    let mut parts = transformed(mesh, &transform)?.into_parts();
    if let Some(name) = material {
        parts.face_materials = Some(vec![0; mesh.face_count()]);
        parts.materials = vec![name.to_owned()];
    }
    Some(Mesh::from_parts(parts).expect("one material per face"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::cuboid;

    fn translate(x: f64) -> Affine {
        [
            [1.0, 0.0, 0.0, x],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ]
    }

    #[test]
    fn transforms_compose_from_the_leaf_up_and_mirrors_keep_solids_outward() {
        let unit = cuboid([0.0; 3], [1.0; 3]);
        let mirror = [
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let leaf = Node {
            transform: Some(translate(2.0)),
            ..Node::mesh(unit.clone(), "a")
        };
        let tree = Node {
            transform: Some(mirror),
            ..Node::apply(Operation::Union, vec![leaf, Node::mesh(unit, "b")])
        };
        let out = evaluate(&tree, &BooleanOptions::default(), &Progress::default()).unwrap();
        let report = out.result.mesh.report();
        assert!(report.is_valid_solid());
        assert_eq!(report.measures.volume, 2.0);
        assert_eq!(report.measures.bbox.expect("a box").min[0], -3.0);
        // Two boxes: one leaf from the orthogonal engine.
        assert_eq!((out.leaves, out.operations), (1, 1));
    }

    #[test]
    fn unions_of_axis_aligned_boxes_go_to_the_orthogonal_engine() {
        let moved = |transform: Affine| Node {
            transform: Some(transform),
            ..Node::mesh(cuboid([0.0; 3], [1.0; 3]), "cube")
        };
        let shift = |x: f64, y: f64| [[2.0, 0.0, 0.0, x], [0.0, 1.0, 0.0, y], [0.0, 0.0, 1.0, 0.0]];
        // A quarter turn about z swaps x and y exactly: still axis-aligned.
        let turned = [
            [0.0, -1.0, 0.0, 0.5],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let boxes = Node::apply(
            Operation::Union,
            vec![
                moved(shift(0.0, 0.0)),
                moved(shift(1.0, 0.5)),
                moved(turned),
            ],
        );
        let options = BooleanOptions::default();
        let flat = flatten(&boxes, &options, &Progress::default()).unwrap();
        assert_eq!(flat.leaves.len(), 1);
        assert_eq!(flat.operations, 1);
        let routed = evaluate(&boxes, &options, &Progress::default())
            .unwrap()
            .result
            .mesh;
        // 2 + 2 − overlap 1 · 0.5 + the turned cube's part outside the others (0.5 · 1 · 1).
        assert_eq!(routed.report().measures.volume, 4.0 - 0.5 + 0.5);
        assert!(routed.report().is_valid_solid());
        // A box turned by 45° keeps the union in the exact engine, with the same boxes' volume.
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let oblique = [[c, -c, 0.0, 10.0], [c, c, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]];
        let mixed = Node::apply(
            Operation::Union,
            vec![
                moved(shift(0.0, 0.0)),
                moved(shift(1.0, 0.5)),
                moved(oblique),
            ],
        );
        let flat = flatten(&mixed, &options, &Progress::default()).unwrap();
        assert_eq!(flat.leaves.len(), 3);
        // A cube whose own faces carry a material (an imported part) keeps the union in the
        // exact engine, whose result gives its faces that material back.
        let mut parts = cuboid([0.0; 3], [1.0; 3]).into_parts();
        parts.face_materials = Some(vec![0; 12]);
        parts.materials = vec!["steel".to_owned()];
        let painted = Node {
            transform: Some(shift(1.0, 0.5)),
            ..Node::mesh(Mesh::from_parts(parts).unwrap(), "painted cube")
        };
        let with_material = Node::apply(Operation::Union, vec![moved(shift(0.0, 0.0)), painted]);
        let flat = flatten(&with_material, &options, &Progress::default()).unwrap();
        assert_eq!(flat.leaves.len(), 2);
        let mesh = evaluate(&with_material, &options, &Progress::default())
            .unwrap()
            .result
            .mesh;
        assert_eq!(mesh.report().measures.volume, 3.5);
        let steel = mesh.materials().iter().position(|m| m == "steel").unwrap() as u32;
        let painted_faces = (mesh.face_materials().unwrap().iter()).filter(|&&m| m == steel);
        assert!(painted_faces.count() > 0);
    }

    /// A turn about the axis (1, 1, 1) by `angle`, as OpenSCAD's `rotate` writes it: rounded
    /// entries, so the turned coordinates of coincident faces round apart.
    fn turn(angle: f64) -> Affine {
        let (s, c) = angle.sin_cos();
        let (t, k) = (1.0 - c, 1.0 / 3f64.sqrt());
        let [x, y, z] = [k, k, k];
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.25],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0],
        ]
    }

    /// The report of `tree`'s result under the default options.
    fn evaluated_report(tree: &Node) -> crate::mesh::MeshReport {
        let options = BooleanOptions::default();
        let out = evaluate(tree, &options, &Progress::default()).unwrap();
        out.result.mesh.report()
    }

    /// A cube minus three bars through it, one per axis, whose faces share planes (a Menger
    /// sponge of level 1 without its corners' cubes): 27 − 7 unit cells.
    fn pierced_cube() -> Node {
        let bar = |axis: usize| {
            let (mut min, mut max) = ([1.0; 3], [2.0; 3]);
            (min[axis], max[axis]) = (-1.0, 4.0);
            Node::mesh(cuboid(min, max), format!("bar {axis}"))
        };
        Node::apply(
            Operation::Difference,
            vec![
                Node::mesh(cuboid([0.0; 3], [3.0; 3]), "cube"),
                Node::apply(Operation::Union, (0..3).map(bar).collect()),
            ],
        )
    }

    #[test]
    fn an_operation_turned_off_the_axes_with_shared_planes_is_evaluated_before_its_turn() {
        let options = BooleanOptions::default();
        let transform = turn(0.7);
        let tree = Node {
            transform: Some(transform),
            ..pierced_cube()
        };
        // One leaf: the pierced cube, evaluated unturned, then turned.
        let flat = flatten(&tree, &options, &Progress::default()).unwrap();
        assert_eq!((flat.leaves.len(), flat.operations), (1, 2));
        let out = evaluate(&tree, &options, &Progress::default()).unwrap();
        let report = out.result.mesh.report();
        assert!(report.is_valid_solid());
        assert!(crate::exact::self_intersections(&out.result.mesh).is_empty());
        let volume = 20.0 * crate::mesh::transform::determinant(&transform);
        assert!((report.measures.volume - volume).abs() < 1e-12 * volume);
        // Inside an operation that is not turned, beside a leaf that is.
        let outer = Node::apply(
            Operation::Union,
            vec![tree, Node::mesh(cuboid([10.0; 3], [11.0; 3]), "apart")],
        );
        let flat = flatten(&outer, &options, &Progress::default()).unwrap();
        assert_eq!(flat.leaves.len(), 2);
        let report = evaluated_report(&outer);
        assert!(report.is_valid_solid());
        assert!((report.measures.volume - (volume + 1.0)).abs() < 1e-12 * volume);
    }

    #[test]
    fn a_turned_operation_with_an_empty_result_adds_nothing() {
        let options = BooleanOptions::default();
        let cube = || Node::mesh(cuboid([0.0; 3], [1.0; 3]), "cube");
        let nothing = Node {
            transform: Some(turn(0.7)),
            ..Node::apply(Operation::Difference, vec![cube(), cube()])
        };
        let tree = Node::apply(
            Operation::Union,
            vec![nothing, Node::mesh(cuboid([5.0; 3], [7.0; 3]), "apart")],
        );
        let flat = flatten(&tree, &options, &Progress::default()).unwrap();
        assert_eq!(flat.leaves.len(), 1);
        let report = evaluated_report(&tree);
        assert!(report.is_valid_solid());
        assert_eq!(report.measures.volume, 8.0);
    }

    #[test]
    fn turned_leaves_without_shared_planes_stay_in_one_pass() {
        let options = BooleanOptions::default();
        let apart = Node::apply(
            Operation::Union,
            vec![
                Node::mesh(cuboid([0.0; 3], [1.0; 3]), "a"),
                Node::mesh(cuboid([0.5; 3], [1.5, 1.25, 1.75]), "b"),
            ],
        );
        let turned = Node {
            transform: Some(turn(0.7)),
            ..apart.clone()
        };
        assert_eq!(
            flatten(&turned, &options, &Progress::default())
                .unwrap()
                .leaves
                .len(),
            2
        );
        // A quarter turn keeps the axes: the pierced cube stays leaves of the one pass.
        let quarter = [
            [0.0, -1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let pierced = Node {
            transform: Some(quarter),
            ..pierced_cube()
        };
        let flat = flatten(&pierced, &options, &Progress::default()).unwrap();
        assert_eq!(flat.leaves.len(), 2, "the cube and the bars' union");
    }

    #[test]
    fn a_tree_without_leaves_is_empty() {
        let out = evaluate(
            &Node::apply(Operation::Union, Vec::new()),
            &BooleanOptions::default(),
            &Progress::default(),
        );
        assert!(out.unwrap().result.mesh.is_empty());
    }

    #[test]
    fn a_singular_transform_names_its_leaf() {
        let flat = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
        ];
        let leaf = Node {
            transform: Some(flat),
            ..Node::mesh(cuboid([0.0; 3], [1.0; 3]), "the cube")
        };
        let err = evaluate(&leaf, &BooleanOptions::default(), &Progress::default()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "the cube: its transform is singular or not finite"
        );
    }
}
