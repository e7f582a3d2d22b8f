use dynlod::simplify::{simplify, Method, SimplifyOptions};
fn main() {
    let path = std::env::args().nth(1).unwrap_or("examples/data/bun_zipper.ply.gz".into());
    let base = dynlod::load_mesh(&path, Default::default()).unwrap();
    let orig = base.to_indexed();
    for m in [Method::Mca, Method::Qem, Method::McaQem] {
        for ratio in [0.5, 0.1, 0.01, 0.0] {
            let mut mesh = base.clone();
            let target = (base.topology.live_face_count() as f64 * ratio) as usize;
            let s = simplify(&mut mesh, SimplifyOptions::default().method(m).target_triangles(target));
            mesh.topology.validate().unwrap();
            let h = dynlod::metrics::hausdorff(&orig, &mesh.to_indexed(), Default::default());
            println!(
                "{m:?} {ratio}: {} -> {} tris, init {:.1} ms, simplify {:.1} ms, {:?}; hausdorff max {:.3}% rms {:.4}%",
                s.input_triangles,
                s.output_triangles,
                s.init_ms,
                s.simplify_ms,
                s.stop,
                h.pct(h.max),
                h.pct(h.rms)
            );
        }
    }
}
