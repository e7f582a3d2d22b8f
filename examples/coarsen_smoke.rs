use dynlod::lod::coarsen::{coarsen, CoarsenOptions};
use dynlod::view::View;
fn main() {
    let base = dynlod::load_mesh("examples/data/bun_zipper.ply.gz", Default::default()).unwrap();
    for u in [1e-4f32, 3e-4, 1e-3] {
        let mut m = base.clone();
        let s = coarsen(&mut m, None, CoarsenOptions::default().threshold(u));
        m.topology.validate().unwrap();
        println!(
            "u={u}: {} -> {} tris, {} rounds, {:?}, {:.1} ms; collapsed per round {:?}",
            s.input_triangles,
            s.output_triangles,
            s.rounds.len(),
            s.stop,
            s.milliseconds,
            s.rounds.iter().map(|r| r.collapsed).collect::<Vec<_>>()
        );
    }
    let (lo, hi) = base.bounds();
    let c = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
    for (px, dist) in [(1.0f32, 0.3f32), (1.0, 1.0), (4.0, 0.3)] {
        let view = View::perspective([c[0], c[1], c[2] + dist], c, [0.0, 1.0, 0.0], 60.0, (1920, 1080));
        let mut m = base.clone();
        let s = coarsen(&mut m, Some(view), CoarsenOptions::default().threshold(px));
        m.topology.validate().unwrap();
        println!(
            "{px}px at {dist}: {} -> {} tris, {} rounds, {:?}, {:.1} ms; {:?}",
            s.input_triangles,
            s.output_triangles,
            s.rounds.len(),
            s.stop,
            s.milliseconds,
            s.rounds
                .iter()
                .map(|r| (r.candidates, r.collapsed, r.blocked, r.ignored, r.reclassified))
                .collect::<Vec<_>>()
        );
    }
}
