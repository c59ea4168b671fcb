//! The star of a vertex in a triangle mesh being edited: its edges by neighbour, whether its
//! triangles make one disk, and where the faces around it change; and the triangles that
//! share each side. Shared by the two stages that join faces and remove vertices by
//! collapsing them onto a neighbour: reconstruct (exact decisions) and simplify (within a
//! tolerance).

use rustc_hash::FxHashMap;

/// The pairs of triangles (indices into `triangles`) that share a side no other triangle
/// uses, the lower index first, in order of the higher.
pub(crate) fn side_neighbours(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    // Each undirected side: its first use, and how many uses it has.
    let mut sides: FxHashMap<(u32, u32), (u32, u32)> = FxHashMap::default();
    for (k, t) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            sides.entry((a.min(b), a.max(b))).or_insert((k as u32, 0)).1 += 1;
        }
    }
    let mut pairs = Vec::new();
    for (k, t) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            let (first, uses) = sides[&(a.min(b), a.max(b))];
            if uses == 2 && first != k as u32 {
                pairs.push((first, k as u32));
            }
        }
    }
    pairs
}

/// A collapse of a vertex onto a neighbour: the shape of its worst new triangle, and each new
/// triangle with the one it replaces.
pub(crate) type Collapse = (f64, Vec<(u32, [u32; 3])>);

/// One edge at a vertex: the neighbour it leads to, how many triangles use it leaving the
/// vertex and arriving at it, and one of each.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spoke {
    pub to: u32,
    outgoing: u32,
    incoming: u32,
    out_triangle: u32,
    in_triangle: u32,
}

/// The spokes of `v`, whose triangles (indices into `triangles`) are `fan`, if they make one
/// disk around `v`: every edge used once in each direction, and turning around `v` from one
/// triangle meets them all. `None` otherwise (a boundary, a non-manifold edge or vertex).
pub(crate) fn disk(triangles: &[[u32; 3]], v: u32, fan: &[u32]) -> Option<Vec<Spoke>> {
    let corner = |f: u32| {
        let t = triangles[f as usize];
        let i = t.iter().position(|&x| x == v).expect("the fan uses v");
        (t[(i + 1) % 3], t[(i + 2) % 3])
    };
    let mut spokes: Vec<Spoke> = Vec::with_capacity(fan.len() + 1);
    for &f in fan {
        let (next, previous) = corner(f);
        for (to, leaving) in [(next, true), (previous, false)] {
            let at = match spokes.iter().position(|s| s.to == to) {
                Some(at) => at,
                None => {
                    spokes.push(Spoke {
                        to,
                        outgoing: 0,
                        incoming: 0,
                        out_triangle: f,
                        in_triangle: f,
                    });
                    spokes.len() - 1
                }
            };
            let s = &mut spokes[at];
            if leaving {
                s.outgoing += 1;
                s.out_triangle = f;
            } else {
                s.incoming += 1;
                s.in_triangle = f;
            }
        }
    }
    if spokes.len() != fan.len() || spokes.iter().any(|s| s.outgoing != 1 || s.incoming != 1) {
        return None;
    }
    let mut at = fan[0];
    for step in 1..=fan.len() {
        let next = corner(at).0;
        at = spokes
            .iter()
            .find(|s| s.to == next)
            .expect("every edge is a spoke")
            .in_triangle;
        if at == fan[0] {
            return (step == fan.len()).then_some(spokes);
        }
    }
    None
}

/// The neighbours whose spokes separate two faces (`face` of the triangles on either side
/// differ).
pub(crate) fn bounding(spokes: &[Spoke], face: impl Fn(u32) -> u32) -> Vec<u32> {
    (spokes.iter())
        .filter(|s| face(s.out_triangle) != face(s.in_triangle))
        .map(|s| s.to)
        .collect()
}
