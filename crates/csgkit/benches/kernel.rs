//! Predicates per second of the exact kernel, on random inputs (the filter decides) and on
//! degenerate ones (the filter abstains and the exact stages decide).
//!
//! Run: `cargo bench -p csgkit --bench kernel`. Ids are `kernel/<predicate>/<input>`; the
//! throughput is predicates (or constructions) per second over batches of `N` inputs.

use criterion::{BenchmarkId, Criterion, Throughput, black_box, criterion_group, criterion_main};
use csgkit::kernel::{
    Axis, Point, Point3, compare_lex, orient2d_projected, orient3d, orient3d_plane, orient3d_points,
};

const N: usize = 1000;

/// xorshift64*: a fixed-seed generator, so every run measures the same inputs.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn p3(&mut self) -> Point3 {
        [self.unit(), self.unit(), self.unit()]
    }
    fn int(&mut self) -> f64 {
        (self.next() % 7) as f64 - 3.0
    }
    fn ip3(&mut self) -> Point3 {
        [self.int(), self.int(), self.int()]
    }
}

fn add(a: Point3, b: Point3) -> Point3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A random LPI (retrying until the line is not parallel to the plane).
fn random_lpi(r: &mut Rng) -> Point {
    loop {
        if let Some(p) = Point::lpi(r.p3(), r.p3(), r.p3(), r.p3(), r.p3()) {
            return p;
        }
    }
}

fn random_tpi(r: &mut Rng) -> Point {
    loop {
        let t = [
            [r.p3(), r.p3(), r.p3()],
            [r.p3(), r.p3(), r.p3()],
            [r.p3(), r.p3(), r.p3()],
        ];
        if let Some(p) = Point::tpi(t) {
            return p;
        }
    }
}

/// An LPI through an integer point `x` against a plane through `x`, with another triangle
/// spanning that plane (so the structural shortcut does not apply and the exact stages run).
fn lpi_on_plane(r: &mut Rng) -> ([Point3; 3], Point) {
    loop {
        let (x, u, v) = (r.ip3(), r.ip3(), r.ip3());
        let tri = [x, add(x, u), add(x, v)];
        let other = [add(x, add(u, v)), add(x, add(u, u)), sub(x, v)];
        let d = r.ip3();
        if let Some(p) = Point::lpi(sub(x, d), add(x, d), tri[0], tri[1], tri[2]) {
            return (other, p);
        }
    }
}

/// An LPI of random coordinates against its own plane's triangle with one corner moved by one
/// ulp: a non-zero near-tie below what f64 resolves (as between the intersection points of
/// two cubes turned by 1e-7 rad), which the double-double stage decides.
fn lpi_near_plane(r: &mut Rng) -> ([Point3; 3], Point) {
    loop {
        let tri = [r.p3(), r.p3(), r.p3()];
        if let Some(p) = Point::lpi(r.p3(), r.p3(), tri[0], tri[1], tri[2]) {
            let mut other = tri;
            other[2][2] = f64::from_bits(other[2][2].to_bits() + 1);
            return (other, p);
        }
    }
}

/// A TPI of three planes through an integer point, with another triangle spanning one of
/// the planes.
fn tpi_on_plane(r: &mut Rng) -> ([Point3; 3], Point) {
    loop {
        let x = r.ip3();
        let d: Vec<Point3> = (0..6).map(|_| r.ip3()).collect();
        let t = [0, 2, 4].map(|i| [x, add(x, d[i]), add(x, d[i + 1])]);
        let other = [
            add(x, add(d[0], d[1])),
            add(x, add(d[0], d[0])),
            sub(x, d[1]),
        ];
        if let Some(p) = Point::tpi(t) {
            return (other, p);
        }
    }
}

fn bench_kernel(c: &mut Criterion) {
    let mut g = c.benchmark_group("kernel");
    g.throughput(Throughput::Elements(N as u64));
    let mut r = Rng(0x6b65_726e_656c_0b3c);

    let explicit: Vec<[Point3; 4]> = (0..N).map(|_| [r.p3(), r.p3(), r.p3(), r.p3()]).collect();
    g.bench_function(BenchmarkId::new("orient3d_explicit", "random"), |b| {
        b.iter(|| {
            for q in &explicit {
                black_box(orient3d(q[0], q[1], q[2], q[3]));
            }
        })
    });
    let coplanar: Vec<[Point3; 4]> = (0..N)
        .map(|_| {
            let (a, b2, c2) = (r.ip3(), r.ip3(), r.ip3());
            let d = add(a, add(sub(b2, a), sub(c2, a)));
            [a, b2, c2, d]
        })
        .collect();
    g.bench_function(BenchmarkId::new("orient3d_explicit", "coplanar"), |b| {
        b.iter(|| {
            for q in &coplanar {
                black_box(orient3d(q[0], q[1], q[2], q[3]));
            }
        })
    });

    let lpi_random: Vec<([Point3; 3], Point)> = (0..N)
        .map(|_| ([r.p3(), r.p3(), r.p3()], random_lpi(&mut r)))
        .collect();
    g.bench_function(BenchmarkId::new("orient3d_plane_lpi", "random"), |b| {
        b.iter(|| {
            for (t, p) in &lpi_random {
                black_box(orient3d_plane(t[0], t[1], t[2], p));
            }
        })
    });
    let lpi_degenerate: Vec<([Point3; 3], Point)> = (0..N).map(|_| lpi_on_plane(&mut r)).collect();
    g.bench_function(BenchmarkId::new("orient3d_plane_lpi", "on_plane"), |b| {
        b.iter(|| {
            for (t, p) in &lpi_degenerate {
                black_box(orient3d_plane(t[0], t[1], t[2], p));
            }
        })
    });

    let lpi_near: Vec<([Point3; 3], Point)> = (0..N).map(|_| lpi_near_plane(&mut r)).collect();
    g.bench_function(BenchmarkId::new("orient3d_plane_lpi", "near_plane"), |b| {
        b.iter(|| {
            for (t, p) in &lpi_near {
                black_box(orient3d_plane(t[0], t[1], t[2], p));
            }
        })
    });

    // The same LPIs against the very triangle that defines them (a structural shortcut).
    let lpi_own: Vec<([Point3; 3], Point)> = lpi_random
        .iter()
        .map(|(_, p)| match p {
            Point::Lpi(l) => (l.definition().2, p.clone()),
            _ => unreachable!("random_lpi builds LPIs"),
        })
        .collect();
    g.bench_function(BenchmarkId::new("orient3d_plane_lpi", "own_plane"), |b| {
        b.iter(|| {
            for (t, p) in &lpi_own {
                black_box(orient3d_plane(t[0], t[1], t[2], p));
            }
        })
    });

    let tpi_random: Vec<([Point3; 3], Point)> = (0..N)
        .map(|_| ([r.p3(), r.p3(), r.p3()], random_tpi(&mut r)))
        .collect();
    g.bench_function(BenchmarkId::new("orient3d_plane_tpi", "random"), |b| {
        b.iter(|| {
            for (t, p) in &tpi_random {
                black_box(orient3d_plane(t[0], t[1], t[2], p));
            }
        })
    });
    let tpi_degenerate: Vec<([Point3; 3], Point)> = (0..N).map(|_| tpi_on_plane(&mut r)).collect();
    g.bench_function(BenchmarkId::new("orient3d_plane_tpi", "on_plane"), |b| {
        b.iter(|| {
            for (t, p) in &tpi_degenerate {
                black_box(orient3d_plane(t[0], t[1], t[2], p));
            }
        })
    });

    let lpi3: Vec<[Point; 4]> = (0..N).map(|_| [0; 4].map(|_| random_lpi(&mut r))).collect();
    g.bench_function(BenchmarkId::new("orient2d_projected_lpi3", "random"), |b| {
        b.iter(|| {
            for q in &lpi3 {
                black_box(orient2d_projected(&q[0], &q[1], &q[2], Axis::Z));
            }
        })
    });
    g.bench_function(BenchmarkId::new("orient3d_points_lpi4", "random"), |b| {
        b.iter(|| {
            for q in &lpi3 {
                black_box(orient3d_points(&q[0], &q[1], &q[2], &q[3]));
            }
        })
    });
    // Three LPIs on one line: the segment p q against three planes.
    let collinear: Vec<[Point; 3]> = (0..N / 10)
        .map(|_| {
            loop {
                let (p, q) = (r.ip3(), r.ip3());
                let pts: Vec<Point> = (0..3)
                    .filter_map(|_| Point::lpi(p, q, r.ip3(), r.ip3(), r.ip3()))
                    .collect();
                if let Ok(three) = <[Point; 3]>::try_from(pts) {
                    break three;
                }
            }
        })
        .collect();
    g.throughput(Throughput::Elements((N / 10) as u64));
    g.bench_function(
        BenchmarkId::new("orient2d_projected_lpi3", "collinear"),
        |b| {
            b.iter(|| {
                for q in &collinear {
                    black_box(orient2d_projected(&q[0], &q[1], &q[2], Axis::Z));
                }
            })
        },
    );
    g.throughput(Throughput::Elements(N as u64));

    g.bench_function(BenchmarkId::new("compare_lex_lpi", "random"), |b| {
        b.iter(|| {
            for q in &lpi3 {
                black_box(compare_lex(&q[0], &q[1]));
            }
        })
    });
    // Each LPI against the vertex it passes through (the midpoint of its segment).
    let coincident: Vec<[Point; 2]> = lpi_degenerate
        .iter()
        .map(|(_, p)| match p {
            Point::Lpi(l) => {
                let (a, b, _) = l.definition();
                [
                    p.clone(),
                    Point::Explicit([0, 1, 2].map(|i| (a[i] + b[i]) * 0.5)),
                ]
            }
            _ => unreachable!("lpi_on_plane builds LPIs"),
        })
        .collect();
    g.bench_function(BenchmarkId::new("compare_lex_lpi", "coincident"), |b| {
        b.iter(|| {
            for q in &coincident {
                black_box(compare_lex(&q[0], &q[1]));
            }
        })
    });

    let defs: Vec<[Point3; 5]> = (0..N).map(|_| [0; 5].map(|_| r.p3())).collect();
    g.bench_function(BenchmarkId::new("construct_lpi", "random"), |b| {
        b.iter(|| {
            for d in &defs {
                black_box(Point::lpi(d[0], d[1], d[2], d[3], d[4]));
            }
        })
    });
    g.finish();
}

criterion_group!(benches, bench_kernel);
criterion_main!(benches);
