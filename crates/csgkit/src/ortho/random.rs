//! Deterministic random box sets for benchmarks, demos and tests.

/// `n` random integer boxes with sides 1–4 in the cube `[0, G]³`,
/// G = round((25n / 0.7)^⅓), about 70% expected coverage before overlap: the peers
/// harness's `boxes_union` family (same distribution, a different generator). The same `seed`
/// gives the same boxes on every platform.
pub fn random_grid_boxes(n: usize, seed: u64) -> Vec<[f64; 6]> {
    let g = ((n as f64 * 25.0 / 0.7).cbrt().round() as u64).max(4);
    let mut state = seed | 1;
    let mut next = move |m: u64| {
        // xorshift64*: small, fast and reproducible.
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) % m
    };
    (0..n)
        .map(|_| {
            let mut b = [0.0; 6];
            for k in 0..3 {
                let size = 1 + next(4);
                let lo = next(g - size + 1);
                b[k] = lo as f64;
                b[k + 3] = (lo + size) as f64;
            }
            b
        })
        .collect()
}
