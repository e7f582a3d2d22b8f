//! papers/002 Table 2 redone on the bundled bunny (69,451 triangles): time to simplify to
//! 10 %, 1 % and as far as each method goes ("0 triangles"), for every method of
//! `dynlod::simplify` and, in the same run, `meshopt::simplify` from the same welded mesh.
//! Our figures include the initial cost evaluation (the paper's "initialization"); the
//! split is printed once per case before the measurements. mca-qem and meshopt also run on
//! the bunny in spatial order (`BuildOptions::spatial_order`, what the command line does;
//! meshopt gets that order too), labelled `-spatial`.
//!
//! Before the criterion runs, `qem-flat` and meshopt are timed alternately, one run each in
//! turn, on the spatial bunny at 10 % and 1 %: criterion times one side for seconds and then
//! the other, so on a shared machine a slow spell can land on one side only; alternating
//! puts both sides in the same spells, and the printed ratio is the steadier figure.
//!
//! `simplify/painted-bunny-10pct`: attributes weighed, beside meshopt's
//! `simplifyWithAttributes` (docs/BENCHMARKS.md, "Attribute-weighted simplification").

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use dynlod::simplify::{simplify, AttributeWeights, Method, SimplifyOptions};
use dynlod::{BuildOptions, Mesh};
use std::time::Instant;

#[path = "support/meshopt_ref.rs"]
mod meshopt_ref;
#[path = "support/painted.rs"]
mod painted;

fn bunny(spatial: bool) -> Mesh {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    dynlod::load_mesh(p, BuildOptions::default().spatial_order(spatial)).unwrap()
}

/// Alternating runs of `qem-flat` and meshopt (module docs): best and median of each, and
/// the ratio of the medians, on stderr.
fn alternating() {
    let mesh = bunny(true);
    let flat = mesh.to_indexed();
    let indices: Vec<u32> = flat.triangles.iter().flatten().copied().collect();
    let n = flat.triangles.len();
    for (label, target) in [("10pct", n / 10), ("1pct", n / 100)] {
        let opts = SimplifyOptions::default().method(Method::QemFlat).target_triangles(target);
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        for _ in 0..15 {
            let mut m = mesh.clone();
            let t = Instant::now();
            simplify(&mut m, opts);
            ours.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            std::hint::black_box(meshopt_ref::simplify_indices(&flat.positions, &indices, target));
            theirs.push(t.elapsed().as_secs_f64() * 1e3);
        }
        for v in [&mut ours, &mut theirs] {
            v.sort_by(f64::total_cmp);
        }
        let (mo, mt) = (ours[ours.len() / 2], theirs[theirs.len() / 2]);
        eprintln!(
            "alternating, spatial bunny to {label}: qem-flat best {:.1} median {mo:.1} ms, meshopt best {:.1} \
             median {mt:.1} ms: {:.2}x",
            ours[0],
            theirs[0],
            mo / mt
        );
    }
}

fn bench(c: &mut Criterion) {
    alternating();
    let mut g = c.benchmark_group("simplify/bunny");
    g.sample_size(10);
    for (order, spatial) in [("", false), ("-spatial", true)] {
        let mesh = bunny(spatial);
        let flat = mesh.to_indexed();
        let indices: Vec<u32> = flat.triangles.iter().flatten().copied().collect();
        let n = flat.triangles.len();
        let methods: &[(&str, Method)] = if spatial {
            &[("mca-qem", Method::McaQem), ("qem-batch", Method::QemBatch), ("qem-flat", Method::QemFlat)]
        } else {
            &[
                ("mca", Method::Mca),
                ("qem", Method::Qem),
                ("mca-qem", Method::McaQem),
                ("qem-batch", Method::QemBatch),
                ("qem-flat", Method::QemFlat),
            ]
        };
        for (label, target) in [("10pct", n / 10), ("1pct", n / 100), ("0", 0)] {
            for &(name, m) in methods {
                let name = format!("{name}{order}");
                let opts = SimplifyOptions::default().method(m).target_triangles(target);
                let mut once = mesh.clone();
                let s = simplify(&mut once, opts);
                eprintln!(
                    "{name:>16} to {label:>5}: {} triangles, init {:.1} ms + simplify {:.1} ms",
                    s.output_triangles, s.init_ms, s.simplify_ms
                );
                g.bench_function(BenchmarkId::new(name, label), |b| {
                    b.iter_batched(|| mesh.clone(), |mut m| simplify(&mut m, opts), BatchSize::LargeInput)
                });
            }
            let out = meshopt_ref::simplify_indices(&flat.positions, &indices, target);
            eprintln!("{:>16} to {label:>5}: {} triangles", format!("meshopt{order}"), out.len() / 3);
            g.bench_function(BenchmarkId::new(format!("meshopt{order}"), label), |b| {
                b.iter(|| meshopt_ref::simplify_indices(&flat.positions, &indices, target))
            });
        }
    }
    g.finish();
}

/// Attributes weighed (`--attribute-weights normal=0.5,color=1`) on the painted bunny
/// (smooth normals, a colour field) to 10 %, beside meshopt's `simplifyWithAttributes` with
/// the same weights and both unweighted, in the same run.
fn bench_weighted(c: &mut Criterion) {
    let input = painted::painted_bunny();
    let mesh = Mesh::build(&input, BuildOptions::default()).unwrap();
    let target = input.triangles.len() / 10;
    let weights = AttributeWeights { normal: 0.5, color: 1.0, ..Default::default() };
    let mut g = c.benchmark_group("simplify/painted-bunny-10pct");
    g.sample_size(10);
    for (name, m, w) in [
        ("qem", Method::Qem, AttributeWeights::default()),
        ("qem-weighted", Method::Qem, weights),
        ("mca-qem-weighted", Method::McaQem, weights),
        ("qem-batch-weighted", Method::QemBatch, weights),
        ("qem-flat", Method::QemFlat, AttributeWeights::default()),
        ("qem-flat-weighted", Method::QemFlat, weights),
    ] {
        let opts = SimplifyOptions::default().method(m).target_triangles(target).attribute_weights(w);
        g.bench_function(name, |b| {
            b.iter_batched(|| mesh.clone(), |mut m| simplify(&mut m, opts), BatchSize::LargeInput)
        });
    }
    for (name, w) in [("meshopt", AttributeWeights::default()), ("meshopt-weighted", weights)] {
        g.bench_function(name, |b| b.iter(|| meshopt_ref::simplify_mesh_with_attributes(&input, target, &w)));
    }
    g.finish();
}

criterion_group!(benches, bench, bench_weighted);
criterion_main!(benches);
