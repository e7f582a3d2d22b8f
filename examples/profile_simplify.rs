//! Profiling helper: simplifies the bundled bunny to 1 % seven times and prints the best time
//! (`cargo run --release --example profile_simplify -- mca|qem|mca-qem|qem-batch|qem-flat`).
use dynlod::simplify::{simplify, Method, SimplifyOptions};
fn main() {
    let base = dynlod::load_mesh("examples/data/bun_zipper.ply.gz", Default::default()).unwrap();
    let m = std::env::args().nth(1).and_then(|a| Method::from_name(&a)).unwrap_or(Method::Qem);
    let mut best = f64::MAX;
    for _ in 0..7 {
        let mut mesh = base.clone();
        let s = simplify(&mut mesh, SimplifyOptions::default().method(m).target_triangles(694));
        best = best.min(s.init_ms + s.simplify_ms);
    }
    eprintln!("{m:?}: best of 7: {best:.1} ms");
}
