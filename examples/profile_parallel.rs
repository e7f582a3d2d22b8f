//! Profiling helper: the papers/000 rounds on the bundled bunny at a fixed threshold, five
//! times, printing the best time (`perf record` this binary).

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
    let mut best = f64::MAX;
    for _ in 0..5 {
        let mut m = base.clone();
        let s = coarsen(&mut m, None, CoarsenOptions::default().threshold(1.974e-4));
        best = best.min(s.milliseconds);
        eprintln!("{} triangles in {} rounds, {:.1} ms", s.output_triangles, s.rounds.len(), s.milliseconds);
    }
    eprintln!("best {best:.1} ms");
}
