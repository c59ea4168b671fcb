//! f64 vector arithmetic on points `[f64; 3]`: for measures and for choices between valid
//! alternatives (shapes, normals' directions), never for topological decisions, which the
//! exact predicates of [`kernel`](crate::kernel) make.

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Twice the area vector of triangle `t` (its normal, by the right-hand rule).
pub(crate) fn triangle_normal(t: [[f64; 3]; 3]) -> [f64; 3] {
    cross(sub(t[1], t[0]), sub(t[2], t[0]))
}

/// Twice the area of `t` over its longest side squared: 0 for a needle, √3/2 for an
/// equilateral triangle; 0 for a triangle of one point.
pub(crate) fn triangle_shape(t: [[f64; 3]; 3]) -> f64 {
    let longest = [sub(t[1], t[0]), sub(t[2], t[0]), sub(t[2], t[1])]
        .map(|d| dot(d, d))
        .into_iter()
        .fold(0.0, f64::max);
    if longest == 0.0 {
        0.0
    } else {
        norm(triangle_normal(t)) / longest
    }
}
