//! Profiling helper: the papers/000 rounds on the bundled bunny at a fixed threshold (the
//! 17,565-triangle case of `benches/parallel.rs`), fifteen times, printing the best and the
//! median time (`perf record` this binary).

use dynlod::lod::coarsen::{coarsen, CoarsenOptions};

fn main() {
    let base = dynlod::load_mesh(
        std::env::args()
            .nth(1)
            .as_deref()
            .unwrap_or(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz")),
        Default::default(),
    )
    .unwrap();
    let mut times = Vec::new();
    for _ in 0..15 {
        let mut m = base.clone();
        let s = coarsen(&mut m, None, CoarsenOptions::default().threshold(1.958e-4));
        times.push(s.milliseconds);
        eprintln!("{} triangles in {} rounds, {:.1} ms", s.output_triangles, s.rounds.len(), s.milliseconds);
    }
    times.sort_by(f64::total_cmp);
    eprintln!("best {:.1} ms, median {:.1} ms", times[0], times[times.len() / 2]);
}
