//! The **classify** stage (`design/exact.md`, stage 6): where every piece of every operand's
//! surface lies relative to every other operand.
//!
//! # Contract
//! Sub-triangles are grouped into *patches*: connected through edges that have exactly two
//! sub-triangles, of one operand, and no other operand's sub-triangle. Intersection curves
//! are therefore patch boundaries, and inside a patch the winding number of every other
//! operand is constant, or the patch lies on that operand's surface (a coplanar shared
//! region). Each patch gets a [`Label`] per other operand; operands a patch is outside of are
//! left out (most patches are outside most operands of an n-ary operation).
//!
//! # Algorithm
//! Operands are closed, oriented outward and free of self-intersections, so the winding
//! number of operand `k` is 1 inside it and 0 outside.
//! 1. **Local tests.** Where a patch has an edge on the surface of another operand, the two
//!    faces of that operand at the edge form a wedge, and the patch's face there lies inside
//!    the wedge, outside it, or on one of its faces (same or opposite orientation), decided
//!    by [`orient3d_plane`] against the faces' input planes and, for a coplanar face,
//!    [`orient2d_projected`] across the edge. With two operands this labels every patch that
//!    touches the intersection curve.
//! 2. **Rays.** For the operands no local test covered, the patch casts a ray from one of its
//!    input vertices that lies on none of those operands' surfaces (such a vertex is in no
//!    contact with them, since a contact is found for every point two operands share): a ray
//!    along +x, crossings counted by [`orient2d`] in the yz projection with a symbolic
//!    perturbation of the ray's origin (`+ε` on y, `+ε²` on z), so rays through edges and
//!    vertices are counted once and consistently, and [`orient3d`] for the side of the plane.
//! 3. **Propagation.** A patch with neither (only with more than two operands) copies the
//!    labels for the operands it does not touch from a labelled patch of the same operand
//!    across one of its edges (the winding number of an operand whose surface is not at that
//!    edge does not change across it).
//!
//! # Complexity
//! One union-find pass over all sub-triangles (through the ingest neighbour table for
//! triangles that were not split; through sorted edge records near the intersection curves),
//! O(1) exact tests per patch edge on another operand, and one ray per patch that needs one
//! (the operands' trees of [`TriangleTrees`], or a parallel scan for a few rays where the
//! self-intersection check did not build those trees).

use crate::par::*;

use crate::index::Aabb;
use crate::kernel::{Point, Point3, Sign, orient2d, orient2d_projected, orient3d, orient3d_plane};
use crate::mesh::union_find::UnionFind;

use crate::progress::{Counter, Progress, Stage};

use super::ingest::{Input, NO_NEIGHBOUR, TriangleTrees};
use super::subdivide::{Arrangement, StageError};

/// Where a patch lies relative to another operand, when not outside it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Label {
    /// Inside the operand.
    Inside,
    /// On the operand's surface, facing the same way.
    OnSame,
    /// On the operand's surface, facing the opposite way.
    OnOpposite,
}

/// The labels of every patch.
pub(crate) struct Labels {
    /// The patch of each sub-triangle.
    pub patch_of: Vec<u32>,
    /// The first sub-triangle of each patch.
    pub first_sub: Vec<u32>,
    /// Per patch: `(operand, label)` for each other operand the patch is not outside of,
    /// sorted by operand.
    pub labels: Vec<Vec<(u32, Label)>>,
}

impl Labels {
    /// The number of patches.
    pub(crate) fn patch_count(&self) -> usize {
        self.labels.len()
    }
}

/// The patches of the arrangement: the patch of each sub-triangle, and the first
/// sub-triangle of each patch.
pub(crate) fn patch_partition(input: &Input, arr: &Arrangement) -> (Vec<u32>, Vec<u32>) {
    patches(input, arr, &EdgeGroups::new(input, arr))
}

/// Up to this many rays scan the triangles in parallel instead of building trees.
const RAYS_WITHOUT_INDEX: usize = 8;

/// Labels every patch, reporting local tests and rays done to `progress`.
///
/// # Errors
/// [`StageError::Unsupported`] when a patch has neither a clean vertex nor an edge where a
/// local test applies (only around non-manifold edges of several operands at once);
/// [`StageError::Cancelled`].
pub(crate) fn classify(
    input: &Input,
    trees: &TriangleTrees,
    arr: &Arrangement,
    progress: &Progress,
) -> Result<Labels, StageError> {
    let edges = EdgeGroups::new(input, arr);
    let (patch_of, first_sub) = patches(input, arr, &edges);
    let patch_count = first_sub.len();
    let operand_count = input.operand_count();

    // Local tests at the edges where other operands' faces meet each patch.
    let mut contacts: Vec<(u32, u32, u32)> = Vec::new(); // (patch, group, face)
    for (g, group) in edges.groups().enumerate() {
        if group.iter().any(|r| r.operand != group[0].operand) {
            for r in group {
                contacts.push((patch_of[r.face as usize], g as u32, r.face));
            }
        }
    }
    contacts.sort_unstable();
    let by_patch: Vec<&[(u32, u32, u32)]> = contacts.chunk_by(|x, y| x.0 == y.0).collect();
    // Units: one local test per patch with contacts, then one ray per patch (at most); the
    // patches that need no ray are counted when the rays are known.
    let counter = progress.counter(Stage::Classify, by_patch.len() + patch_count);
    let mut local = vec![LocalLabels::default(); patch_count];
    let found: Vec<(u32, LocalLabels)> = counter.par_chunks(&by_patch, |chunk, out| {
        out.extend(
            chunk
                .iter()
                .map(|c| (c[0].0, local_labels(input, arr, &edges, c))),
        );
    });
    progress.check()?;
    for (p, l) in found {
        local[p as usize] = l;
    }

    // Rays for the operands a patch does not touch along an edge.
    let mut labels: Vec<Option<Vec<(u32, Label)>>> = vec![None; patch_count];
    let ray_from = ray_vertices(input, arr, &patch_of, &local);
    let (ray_patches, rays): (Vec<usize>, Vec<(u32, u32)>) = (ray_from.iter().enumerate())
        .filter_map(|(p, v)| v.map(|v| (p, v)))
        .unzip();
    counter.advance(patch_count - rays.len());
    let cast = cast_rays(input, trees, &rays, &counter);
    counter.finish()?;
    for (p, inside) in ray_patches.into_iter().zip(cast) {
        let own = &local[p];
        let mut merged: Vec<(u32, Label)> = (inside.into_iter())
            .filter(|(k, _)| !own.touched.contains(k))
            .chain(own.labels.iter().copied())
            .collect();
        merged.sort_unstable_by_key(|e| e.0);
        labels[p] = Some(merged);
    }
    let mut pending = Vec::new();
    for (p, l) in local.into_iter().enumerate() {
        if labels[p].is_some() {
            continue;
        }
        if l.touched.len() + 1 == operand_count {
            labels[p] = Some(l.labels);
        } else {
            pending.push((p as u32, l));
        }
    }
    propagate(&edges, &patch_of, &mut labels, pending)?;
    let labels = (labels.into_iter().enumerate())
        .map(|(p, l)| {
            l.ok_or_else(|| {
                StageError::Unsupported(format!("surface patch {p} could not be classified"))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Labels {
        patch_of,
        first_sub,
        labels,
    })
}

/// One side of a sub-triangle, in an edge group.
#[derive(Clone, Copy, Debug)]
struct EdgeRecord {
    /// `(smaller vertex << 32) | larger vertex`.
    key: u64,
    /// The sub-triangle.
    face: u32,
    /// Its operand.
    operand: u32,
    /// Whether the side runs from the smaller vertex to the larger.
    forward: bool,
}

/// The sides of the sub-triangles near intersection curves, grouped by edge: those of split
/// triangles and of the unsplit triangles next to them. Other edges are plain two-sided
/// edges of one operand, found through the ingest neighbour table.
struct EdgeGroups {
    records: Vec<EdgeRecord>,
    /// Start of each group in `records`, plus `records.len()`.
    starts: Vec<u32>,
}

impl EdgeGroups {
    fn new(input: &Input, arr: &Arrangement) -> Self {
        let split = |t: usize| arr.touched[t];
        let near: Vec<u32> = (0..input.triangles.len())
            .into_par_iter()
            .filter(|&t| {
                split(t)
                    || (0..3).any(|i| {
                        let n = input.neighbours[3 * t + i];
                        n == NO_NEIGHBOUR || split(n as usize)
                    })
            })
            .map(|t| t as u32)
            .collect();
        let mut records: Vec<EdgeRecord> = near
            .par_iter()
            .flat_map_iter(|&t| {
                let range = arr.sub_starts[t as usize]..arr.sub_starts[t as usize + 1];
                let operand = input.operand[t as usize];
                range.flat_map(move |s| {
                    let tri = arr.triangles[s as usize];
                    (0..3).map(move |i| {
                        let (a, b) = (tri[i], tri[(i + 1) % 3]);
                        EdgeRecord {
                            key: (u64::from(a.min(b)) << 32) | u64::from(a.max(b)),
                            face: s,
                            operand,
                            forward: a < b,
                        }
                    })
                })
            })
            .collect();
        // By (key, operand, face), as one 128-bit number: one comparison where the tuple
        // took three.
        records.par_sort_unstable_by_key(|r| {
            u128::from(r.key) << 64 | u128::from(r.operand) << 32 | u128::from(r.face)
        });
        let mut starts: Vec<u32> = (0..records.len())
            .filter(|&i| i == 0 || records[i].key != records[i - 1].key)
            .map(|i| i as u32)
            .collect();
        starts.push(records.len() as u32);
        Self { records, starts }
    }

    fn groups(&self) -> impl Iterator<Item = &[EdgeRecord]> {
        self.starts
            .windows(2)
            .map(|w| &self.records[w[0] as usize..w[1] as usize])
    }

    fn group(&self, g: u32) -> &[EdgeRecord] {
        &self.records[self.starts[g as usize] as usize..self.starts[g as usize + 1] as usize]
    }
}

/// Patches by union-find; returns the patch of each sub-triangle (numbered by first
/// sub-triangle) and the first sub-triangle of each patch.
fn patches(input: &Input, arr: &Arrangement, edges: &EdgeGroups) -> (Vec<u32>, Vec<u32>) {
    // The links across unsplit triangles' sides, every triangle of every operand (two
    // million on two 1 M spheres), are made on all threads at once.
    let sets = UnionFind::new(arr.triangles.len());
    (0..input.triangles.len()).into_par_iter().for_each(|t| {
        if arr.touched[t] {
            return;
        }
        for i in 0..3 {
            let n = input.neighbours[3 * t + i];
            if n != NO_NEIGHBOUR && (n as usize) > t && !arr.touched[n as usize] {
                sets.union_shared(arr.sub_starts[t], arr.sub_starts[n as usize]);
            }
        }
    });
    for group in edges.groups() {
        if let [r, s] = group {
            if r.operand == s.operand && r.forward != s.forward {
                sets.union_shared(r.face, s.face);
            }
        }
    }
    // A root is the first sub-triangle of its set, so it is numbered before the others read
    // its number in its place.
    let mut patch_of = sets.roots();
    let mut first_sub = Vec::new();
    for s in 0..patch_of.len() {
        let root = patch_of[s] as usize;
        if root == s {
            patch_of[s] = first_sub.len() as u32;
            first_sub.push(s as u32);
        } else {
            patch_of[s] = patch_of[root];
        }
    }
    (patch_of, first_sub)
}

/// For each patch that local tests leave incomplete, a vertex to cast a ray from, with the
/// patch's operand: an input vertex that lies on no other operand's surface except those
/// the local tests covered (so the ray's winding numbers are defined for every operand it
/// is asked about, and equal the patch's).
fn ray_vertices(
    input: &Input,
    arr: &Arrangement,
    patch_of: &[u32],
    local: &[LocalLabels],
) -> Vec<Option<(u32, u32)>> {
    let n = input.positions.len();
    let operand_count = input.operand_count();
    let mut done: Vec<bool> = (local.iter())
        .map(|l| l.touched.len() + 1 == operand_count)
        .collect();
    let mut from = vec![None; local.len()];
    if done.iter().all(|&d| d) {
        return from;
    }
    let mut contacts = arr.contact_vertices.clone();
    contacts.par_sort_unstable();
    contacts.dedup();
    for (s, tri) in arr.triangles.iter().enumerate() {
        let p = patch_of[s] as usize;
        if done[p] {
            continue;
        }
        let own = input.operand[arr.source[s] as usize];
        let usable = |v: u32| {
            let start = contacts.partition_point(|c| c.0 < v);
            (contacts[start..].iter().take_while(|c| c.0 == v))
                .all(|&(_, k)| k == own || local[p].touched.contains(&k))
        };
        if let Some(&v) = tri.iter().find(|&&v| (v as usize) < n && usable(v)) {
            from[p] = Some((v, own));
            done[p] = true;
        }
    }
    from
}

/// The labels of each patch at its clean vertex, by exact ray casting: `rays` holds
/// `(vertex, operand of the patch)`; each ray advances `counter`, and after a cancellation
/// the labels are incomplete.
fn cast_rays(
    input: &Input,
    trees: &TriangleTrees,
    rays: &[(u32, u32)],
    counter: &Counter,
) -> Vec<Vec<(u32, Label)>> {
    let ray_box = |v: Point3| Aabb {
        min: v,
        max: [f64::INFINITY, v[1], v[2]],
    };
    let labels_at = |v: Point3, own: u32, hits: &mut dyn Iterator<Item = u32>| {
        let mut windings: Vec<(u32, i32)> = Vec::new();
        for t in hits {
            let k = input.operand[t as usize];
            let c = crossing(input.triangle_positions(t as usize), v);
            if k == own || c == 0 {
                continue;
            }
            match windings.iter_mut().find(|(o, _)| *o == k) {
                Some(entry) => entry.1 += c,
                None => windings.push((k, c)),
            }
        }
        let mut inside: Vec<(u32, Label)> = (windings.into_iter())
            .filter(|&(_, w)| w != 0)
            .map(|(k, _)| (k, Label::Inside))
            .collect();
        inside.sort_unstable_by_key(|e| e.0);
        inside
    };
    if rays.len() <= RAYS_WITHOUT_INDEX && !trees.are_built() {
        // A few rays: scanning is cheaper than building an index over every triangle.
        return (rays.iter())
            .map(|&(v, own)| {
                let pos = input.positions[v as usize];
                let query = ray_box(pos);
                let hits: Vec<u32> = (0..input.triangles.len() as u32)
                    .into_par_iter()
                    .filter(|&t| {
                        input.operand[t as usize] != own
                            && input.triangle_box(t as usize).overlaps(&query)
                    })
                    .collect();
                counter.advance(1);
                labels_at(pos, own, &mut hits.into_iter())
            })
            .collect();
    }
    trees.build_missing();
    counter.par_chunks(rays, |chunk, out| {
        for &(v, own) in chunk {
            let pos = input.positions[v as usize];
            let mut hits = Vec::new();
            trees.visit_overlapping(&ray_box(pos), |t| hits.push(t));
            out.push(labels_at(pos, own, &mut hits.into_iter()));
        }
    })
}

/// The signed crossing of the ray from `v` along +x with triangle `tri`: +1 leaving through
/// a face whose normal points along +x, −1 entering, 0 for no crossing. `v` must not lie
/// on the triangle. The ray's origin is perturbed symbolically by `(0, ε, ε²)`.
fn crossing(tri: [Point3; 3], v: Point3) -> i32 {
    let yz = |p: Point3| [p[1], p[2]];
    let [a, b, c] = tri.map(yz);
    let p = yz(v);
    let o = orient2d(a, b, c);
    if o == Sign::Zero {
        return 0; // parallel to the ray: the perturbed ray misses it
    }
    let side = |x: [f64; 2], y: [f64; 2]| match orient2d(x, y, p) {
        Sign::Zero => {
            let s = Sign::of(x[1] - y[1]);
            if s != Sign::Zero {
                s
            } else {
                Sign::of(y[0] - x[0])
            }
        }
        s => s,
    };
    if side(a, b) != o || side(b, c) != o || side(c, a) != o {
        return 0;
    }
    if orient3d(tri[0], tri[1], tri[2], v) != o {
        return 0; // the plane is behind the origin
    }
    if o == Sign::Positive { 1 } else { -1 }
}

/// Labels found by local tests, and the operands they cover.
#[derive(Clone, Debug, Default)]
struct LocalLabels {
    labels: Vec<(u32, Label)>,
    /// Operands whose surface the patch touches along an edge.
    touched: Vec<u32>,
}

/// Local tests for one patch against every operand that has faces on its boundary edges.
fn local_labels(
    input: &Input,
    arr: &Arrangement,
    edges: &EdgeGroups,
    contacts: &[(u32, u32, u32)],
) -> LocalLabels {
    let own = input.operand[arr.source[contacts[0].2 as usize] as usize];
    let mut touched: Vec<u32> = Vec::new();
    let mut labels = Vec::new();
    for &(_, g, face) in contacts {
        if input.operand[arr.source[face as usize] as usize] != own {
            continue;
        }
        let group = edges.group(g);
        let mut others: Vec<u32> = group
            .iter()
            .map(|r| r.operand)
            .filter(|&k| k != own)
            .collect();
        others.dedup();
        for k in others {
            if touched.contains(&k) {
                continue;
            }
            let faces: Vec<&EdgeRecord> = group.iter().filter(|r| r.operand == k).collect();
            if let [f, h] = faces[..] {
                let me = group
                    .iter()
                    .find(|r| r.face == face)
                    .expect("the face is in its group");
                if let Some(label) = wedge_test(input, arr, me, f, h) {
                    touched.push(k);
                    if let Some(label) = label {
                        labels.push((k, label));
                    }
                }
            }
        }
    }
    labels.sort_unstable_by_key(|e| e.0);
    touched.sort_unstable();
    LocalLabels { labels, touched }
}

/// Where sub-triangle `me` lies at its edge relative to the operand whose two faces there are
/// `f` and `h`: `Some(None)` outside, `Some(Some(label))` otherwise; `None` if the two faces
/// do not form a wedge (both run the same way).
fn wedge_test(
    input: &Input,
    arr: &Arrangement,
    me: &EdgeRecord,
    f: &EdgeRecord,
    h: &EdgeRecord,
) -> Option<Option<Label>> {
    if f.forward == h.forward {
        return None;
    }
    let (a, b) = ((me.key >> 32) as u32, me.key as u32);
    let third = |face: u32| -> u32 {
        let tri = arr.triangles[face as usize];
        *tri.iter()
            .find(|&&v| v != a && v != b)
            .expect("a triangle has three vertices")
    };
    let plane = |face: u32| input.triangle_positions(arr.source[face as usize] as usize);
    let drop = |face: u32| input.triangles[arr.source[face as usize] as usize].drop_axis();
    let d = arr.point(input, third(me.face));
    let pa = arr.point(input, a);
    let pb = arr.point(input, b);
    // On a face: coplanar with it and on its side of the edge.
    for r in [f, h] {
        if orient3d_plane_of(plane(r.face), &d) == Sign::Zero {
            let x = arr.point(input, third(r.face));
            let axis = drop(r.face);
            if orient2d_projected(&pa, &pb, &d, axis) == orient2d_projected(&pa, &pb, &x, axis) {
                let same = me.forward == r.forward;
                return Some(Some(if same {
                    Label::OnSame
                } else {
                    Label::OnOpposite
                }));
            }
        }
    }
    let x2 = arr.point(input, third(h.face));
    let convexity = orient3d_plane_of(plane(f.face), &x2);
    let s1 = orient3d_plane_of(plane(f.face), &d);
    let s2 = orient3d_plane_of(plane(h.face), &d);
    let inside = match convexity {
        Sign::Positive => s1 != Sign::Negative && s2 != Sign::Negative,
        Sign::Negative => s1 == Sign::Positive || s2 == Sign::Positive,
        Sign::Zero => s1 == Sign::Positive,
    };
    Some(inside.then_some(Label::Inside))
}

fn orient3d_plane_of(tri: [Point3; 3], d: &Point) -> Sign {
    orient3d_plane(tri[0], tri[1], tri[2], d)
}

/// Completes the labels of patches that touch only some operands, from neighbouring patches
/// of the same operand.
fn propagate(
    edges: &EdgeGroups,
    patch_of: &[u32],
    labels: &mut [Option<Vec<(u32, Label)>>],
    mut pending: Vec<(u32, LocalLabels)>,
) -> Result<(), StageError> {
    if pending.is_empty() {
        return Ok(());
    }
    // `(patch, group)` for the edge groups of each pending patch, in group order: a patch
    // looks only at its own edges, not at every group.
    let mut is_pending = vec![false; labels.len()];
    for (p, _) in &pending {
        is_pending[*p as usize] = true;
    }
    let mut groups_of: Vec<(u32, u32)> = (edges.groups().enumerate())
        .flat_map(|(g, group)| {
            group
                .iter()
                .map(move |r| (patch_of[r.face as usize], g as u32))
        })
        .filter(|&(p, _)| is_pending[p as usize])
        .collect();
    groups_of.sort_unstable();
    groups_of.dedup();
    while !pending.is_empty() {
        let before = pending.len();
        pending.retain(|(p, local)| {
            let start = groups_of.partition_point(|x| x.0 < *p);
            let mut groups = (groups_of[start..].iter())
                .take_while(|x| x.0 == *p)
                .map(|&(_, g)| edges.group(g));
            let neighbour = groups.find_map(|group| {
                let mine = group.iter().find(|r| patch_of[r.face as usize] == *p)?;
                group
                    .iter()
                    .filter(|r| r.operand == mine.operand && patch_of[r.face as usize] != *p)
                    .find_map(|r| labels[patch_of[r.face as usize] as usize].clone())
            });
            let Some(known) = neighbour else { return true };
            let mut merged: Vec<(u32, Label)> = (known.into_iter())
                .filter(|(k, _)| !local.touched.contains(k))
                .chain(local.labels.iter().copied())
                .collect();
            merged.sort_unstable_by_key(|e| e.0);
            labels[*p as usize] = Some(merged);
            false
        });
        if pending.len() == before {
            return Err(StageError::Unsupported(format!(
                "{} surface patches touch no classified patch",
                pending.len()
            )));
        }
    }
    Ok(())
}
