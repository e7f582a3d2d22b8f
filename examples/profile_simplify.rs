//! Profiling helper: simplifies a mesh (default: the bundled bunny) to 1 % seven times and
//! prints the best time
//! (`cargo run --release --example profile_simplify -- mca|qem|mca-qem|qem-batch|qem-flat [MESH [WEIGHTS]]`,
//! WEIGHTS as `--attribute-weights` takes them).
use dynlod::simplify::{simplify, AttributeWeights, Method, SimplifyOptions};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(2).map_or("examples/data/bun_zipper.ply.gz", |s| s.as_str());
    let base = dynlod::load_mesh(path, Default::default()).unwrap();
    let m = args.get(1).and_then(|a| Method::from_name(a)).unwrap_or(Method::Qem);
    let weights = args.get(3).map_or(AttributeWeights::default(), |w| AttributeWeights::parse(w).unwrap());
    let target = base.topology.live_face_count() / 100;
    let mut best = f64::MAX;
    for _ in 0..7 {
        let mut mesh = base.clone();
        let s = simplify(
            &mut mesh,
            SimplifyOptions::default().method(m).target_triangles(target).attribute_weights(weights),
        );
        best = best.min(s.init_ms + s.simplify_ms);
    }
    eprintln!("{m:?}: best of 7: {best:.1} ms");
}
