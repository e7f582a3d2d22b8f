//! papers/000 §7 redone: the bunny (69,451 triangles) coarsened by rounds of parallel
//! half-edge collapses to ≈ 48,831 / 29,014 / 17,565 triangles (the paper's three cases), with
//! `meshopt::simplify` to the same counts in the same run, under both schedules (the default
//! local minima, and every candidate every round as the paper does). The threshold u for each
//! case and schedule is found once (outside the timing) by `coarsen_to_triangles`; the timed
//! run coarsens a fresh copy with that u, view-independently, on the rayon pool (2 cores
//! here). Rounds and the symmetric Hausdorff error of every result are printed once per case.
//! The default schedule and meshopt run a second time on the same bunny in spatial order
//! (`BuildOptions::spatial_order`, what the command line does; meshopt gets that order too).

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use dynlod::lod::coarsen::{coarsen, coarsen_to_triangles, CoarsenOptions, Schedule};
use dynlod::metrics::{hausdorff, HausdorffOptions};
use dynlod::BuildOptions;

#[path = "support/meshopt_ref.rs"]
mod meshopt_ref;

fn bench(c: &mut Criterion) {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let input = dynlod::io::load(p).unwrap();
    let mut g = c.benchmark_group("parallel/bunny");
    g.sample_size(10);
    for (order, spatial) in [("", false), ("-spatial", true)] {
        let mesh = dynlod::Mesh::build(&input, BuildOptions::default().spatial_order(spatial)).unwrap();
        let flat = mesh.to_indexed();
        let (lo, hi) = mesh.bounds();
        let diag = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>().sqrt();
        // The paper's schedule in file order only: the orders compare on the default.
        let schedules = if spatial { &Schedule::ALL[..1] } else { &Schedule::ALL[..] };
        for target in [48_831usize, 29_014, 17_565] {
            let mut count = 0;
            for &schedule in schedules {
                let name = format!("{}{order}", schedule.name());
                let base = CoarsenOptions::default().schedule(schedule);
                let (result, stats, u) = coarsen_to_triangles(&mesh, &[], &base, target, 1e-7 * diag, diag);
                let ours = hausdorff(&flat, &result.to_indexed(), HausdorffOptions::default());
                eprintln!(
                    "case {target}, {name}: {} triangles in {} rounds (u = {u:.3e}), {} selections, RMS {:.4} % max {:.4} %",
                    stats.output_triangles,
                    stats.rounds.len(),
                    stats.rounds.iter().map(|r| r.candidates - r.waiting).sum::<usize>(),
                    ours.pct(ours.rms),
                    ours.pct(ours.max),
                );
                count = count.max(stats.output_triangles);
                let opts = base.threshold(u);
                g.bench_function(BenchmarkId::new(format!("rounds-{name}"), target), |b| {
                    b.iter_batched(|| mesh.clone(), |mut m| coarsen(&mut m, None, opts.clone()), BatchSize::LargeInput)
                });
            }
            let mo = meshopt_ref::simplify_mesh(&flat, count);
            let theirs = hausdorff(&flat, &mo, HausdorffOptions::default());
            eprintln!(
                "case {target}, meshopt{order}: {} triangles, RMS {:.4} % max {:.4} %",
                mo.triangles.len(),
                theirs.pct(theirs.rms),
                theirs.pct(theirs.max)
            );
            g.bench_function(BenchmarkId::new(format!("meshopt{order}"), target), |b| {
                b.iter(|| meshopt_ref::simplify_mesh(&flat, count))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
