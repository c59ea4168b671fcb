//! The 256-entry octant table: the local topology of a point of an orthogonal solid.
//!
//! **Octant code.** Bit `sx | sy << 1 | sz << 2` of a point's code is 1 iff the open octant on
//! side `(sx, sy, sz)` of the point is inside the solid (side 0 is the negative side).
//! `design/ortho.md` §A2.
//!
//! **Face pieces.** In the plane through the point perpendicular to axis k, a quadrant carries
//! a face iff the octants on its two sides differ; its outward normal points to the empty one.
//! Per orientation (order +x, −x, +y, −y, +z, −z) this gives 0–4 quadrants, from which
//! - the *corner multiplicity* is 1 for one or three quadrants, 2 for two diagonal quadrants
//!   (a 2D pinch) and 0 otherwise;
//! - the orientation is *pass-through* when the quadrants are two adjacent ones: the face's
//!   boundary runs straight through the point.
//!
//! A point is a vertex iff some corner multiplicity is positive. Up to the 48 symmetries of the
//! cube and complement the vertex codes form exactly 10 classes (named by their smallest code),
//! the paper's configurations (a)–(j).
//!
//! **Degree conventions** ([`DegreeConvention`]): `corner` is the multiplicity, `seed` (the
//! paper's) also counts the two pass-through faces of class 27 twice, and `conforming` (the
//! default) counts every pass-through face twice, so face polygons have a vertex wherever any
//! B-rep vertex lies on their boundary and meshes have no T-junctions.
//!
//! The table is computed by `const fn` at compile time; no arithmetic on coordinates happens here.

/// How vertex degrees count pass-through faces (`design/ortho.md` §A2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DegreeConvention {
    /// Corner multiplicity plus two for every pass-through face: no T-junctions (default).
    #[default]
    Conforming,
    /// The paper's (Vigo et al.) input: corner multiplicity, with class 27's two pass-through
    /// faces doubled. Class-25 vertices then leave a T-junction.
    Seed,
    /// Corner multiplicity only: maximal edges.
    Corner,
}

/// One entry of the octant table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OctantInfo {
    /// The class: the smallest code of the code's orbit under the cube's symmetries and
    /// complement.
    pub class: u8,
    /// Corner multiplicity per orientation (+x, −x, +y, −y, +z, −z).
    pub corner: [u8; 6],
    /// Whether each orientation passes straight through the point.
    pub pass_through: [bool; 6],
}

impl OctantInfo {
    /// True iff the point is a vertex of the boundary.
    pub const fn is_vertex(&self) -> bool {
        let mut o = 0;
        while o < 6 {
            if self.corner[o] > 0 {
                return true;
            }
            o += 1;
        }
        false
    }

    /// The six face degrees (+x, −x, +y, −y, +z, −z) under `convention`.
    pub fn degrees(&self, convention: DegreeConvention) -> [u8; 6] {
        let double = match convention {
            DegreeConvention::Conforming => true,
            DegreeConvention::Seed => self.class == 27,
            DegreeConvention::Corner => false,
        };
        std::array::from_fn(|o| self.corner[o] + 2 * u8::from(double && self.pass_through[o]))
    }
}

/// The octant table, indexed by code.
pub static OCTANT_TABLE: [OctantInfo; 256] = build_table();

/// Occupancy of octant `(s[0], s[1], s[2])` in `code`.
const fn occupied(code: u8, s: [usize; 3]) -> bool {
    code >> (s[0] | (s[1] << 1) | (s[2] << 2)) & 1 == 1
}

/// Corner multiplicity and pass-through flag of the quadrant set `q` (bit `u | v << 1`).
pub(crate) const fn classify_quadrants(q: u8) -> (u8, bool) {
    match q.count_ones() {
        1 | 3 => (1, false),
        2 if q == 0b1001 || q == 0b0110 => (2, false),
        2 => (0, true),
        _ => (0, false),
    }
}

const fn face_info(code: u8) -> ([u8; 6], [bool; 6]) {
    let mut corner = [0u8; 6];
    let mut pass = [false; 6];
    let mut k = 0;
    while k < 3 {
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        let (mut qpos, mut qneg) = (0u8, 0u8);
        let mut q = 0;
        while q < 4 {
            let mut lo = [0usize; 3];
            lo[a] = q & 1;
            lo[b] = q >> 1;
            let mut hi = lo;
            hi[k] = 1;
            let (neg, pos) = (occupied(code, lo), occupied(code, hi));
            if neg && !pos {
                qpos |= 1 << q;
            }
            if pos && !neg {
                qneg |= 1 << q;
            }
            q += 1;
        }
        let (m, p) = classify_quadrants(qpos);
        corner[2 * k] = m;
        pass[2 * k] = p;
        let (m, p) = classify_quadrants(qneg);
        corner[2 * k + 1] = m;
        pass[2 * k + 1] = p;
        k += 1;
    }
    (corner, pass)
}

/// The image of `code` under the axis permutation `perm` followed by the reflections `flip`.
const fn transform(code: u8, perm: [usize; 3], flip: usize) -> u8 {
    let mut out = 0u8;
    let mut o = 0;
    while o < 8 {
        if code >> o & 1 == 1 {
            let s = [o & 1, (o >> 1) & 1, (o >> 2) & 1];
            let mut t = [0usize; 3];
            let mut i = 0;
            while i < 3 {
                t[perm[i]] = s[i] ^ ((flip >> i) & 1);
                i += 1;
            }
            out |= 1 << (t[0] | (t[1] << 1) | (t[2] << 2));
        }
        o += 1;
    }
    out
}

const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

const fn class_of(code: u8) -> u8 {
    let mut best = code;
    let mut p = 0;
    while p < 6 {
        let mut f = 0;
        while f < 8 {
            let t = transform(code, PERMUTATIONS[p], f);
            if t < best {
                best = t;
            }
            if !t < best {
                best = !t;
            }
            f += 1;
        }
        p += 1;
    }
    best
}

const fn build_table() -> [OctantInfo; 256] {
    let mut table = [OctantInfo {
        class: 0,
        corner: [0; 6],
        pass_through: [false; 6],
    }; 256];
    let mut c = 0;
    while c < 256 {
        let (corner, pass_through) = face_info(c as u8);
        table[c] = OctantInfo {
            class: class_of(c as u8),
            corner,
            pass_through,
        };
        c += 1;
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Code of a list of occupied octants `(sx, sy, sz)`.
    fn code(octants: &[(u8, u8, u8)]) -> u8 {
        octants
            .iter()
            .fold(0, |c, &(x, y, z)| c | 1 << (x | y << 1 | z << 2))
    }

    #[test]
    fn vertex_classes_are_the_ten_of_the_paper() {
        let mut vertex_classes: Vec<u8> = (0..=255u8)
            .map(|c| OCTANT_TABLE[c as usize])
            .filter(OctantInfo::is_vertex)
            .map(|i| i.class)
            .collect();
        vertex_classes.sort_unstable();
        vertex_classes.dedup();
        assert_eq!(vertex_classes, [1, 6, 7, 22, 23, 24, 25, 27, 30, 105]);
        let mut other: Vec<u8> = (0..=255u8)
            .map(|c| OCTANT_TABLE[c as usize])
            .filter(|i| !i.is_vertex())
            .map(|i| i.class)
            .collect();
        other.sort_unstable();
        other.dedup();
        assert_eq!(other, [0, 3, 15, 60]);
    }

    #[test]
    fn every_code_agrees_with_its_class_and_complement() {
        for c in 0..=255u8 {
            let info = OCTANT_TABLE[c as usize];
            let rep = OCTANT_TABLE[info.class as usize];
            assert_eq!(info.class, rep.class, "code {c}");
            assert_eq!(info.is_vertex(), rep.is_vertex(), "code {c}");
            let sum = |i: OctantInfo| i.degrees(DegreeConvention::Conforming).iter().sum::<u8>();
            assert_eq!(sum(info), sum(rep), "code {c}");
            // The complement swaps +/− of every orientation.
            let comp = OCTANT_TABLE[!c as usize];
            for o in 0..6 {
                assert_eq!(
                    info.corner[o],
                    comp.corner[o ^ 1],
                    "code {c} orientation {o}"
                );
            }
        }
    }

    /// (occupied octants, class, corner degrees, conforming degrees).
    type ClassCase = (&'static [(u8, u8, u8)], u8, [u8; 6], [u8; 6]);

    #[test]
    fn representatives_have_the_degrees_of_the_design_table() {
        let cases: [ClassCase; 10] = [
            (&[(0, 0, 0)], 1, [1, 0, 1, 0, 1, 0], [1, 0, 1, 0, 1, 0]),
            (
                &[(0, 0, 0), (1, 0, 0), (0, 1, 0)],
                7,
                [1, 0, 1, 0, 1, 0],
                [1, 0, 1, 0, 1, 0],
            ),
            (
                &[(0, 0, 0), (1, 1, 0), (0, 0, 1)],
                25,
                [0, 1, 0, 1, 1, 0],
                [2, 1, 2, 1, 1, 0],
            ),
            (
                &[(1, 0, 0), (0, 1, 0)],
                6,
                [1, 1, 1, 1, 2, 0],
                [1, 1, 1, 1, 2, 0],
            ),
            (
                &[(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
                23,
                [2, 0, 2, 0, 2, 0],
                [2, 0, 2, 0, 2, 0],
            ),
            (&[(1, 1, 0), (0, 0, 1)], 24, [1; 6], [1; 6]),
            (
                &[(1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1)],
                30,
                [1; 6],
                [1; 6],
            ),
            (
                &[(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 0, 1)],
                27,
                [1, 1, 0, 0, 0, 0],
                [1, 1, 2, 0, 2, 0],
            ),
            (
                &[(1, 0, 0), (0, 1, 0), (0, 0, 1)],
                22,
                [2, 1, 2, 1, 2, 1],
                [2, 1, 2, 1, 2, 1],
            ),
            (
                &[(0, 0, 0), (1, 1, 0), (1, 0, 1), (0, 1, 1)],
                105,
                [2; 6],
                [2; 6],
            ),
        ];
        for (octants, class, corner, conforming) in cases {
            let info = OCTANT_TABLE[code(octants) as usize];
            assert_eq!(info.class, class, "{octants:?}");
            assert_eq!(info.corner, corner, "{octants:?}");
            assert_eq!(info.degrees(DegreeConvention::Corner), corner);
            assert_eq!(
                info.degrees(DegreeConvention::Conforming),
                conforming,
                "{octants:?}"
            );
        }
        let h = OCTANT_TABLE[code(&[(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 0, 1)]) as usize];
        assert_eq!(h.degrees(DegreeConvention::Seed), [1, 1, 2, 0, 2, 0]);
        let t = OCTANT_TABLE[code(&[(0, 0, 0), (1, 1, 0), (0, 0, 1)]) as usize];
        assert_eq!(t.degrees(DegreeConvention::Seed), [0, 1, 0, 1, 1, 0]);
    }
}
