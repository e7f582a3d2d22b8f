fn main() {
    let p = std::env::args().nth(1).unwrap();
    let m = dynlod::load_mesh(&p, Default::default()).unwrap();
    let s = m.topology.stats();
    println!(
        "positions {} live {} stats.v {} faces {} edges {} be {} bl {} euler {} genus {:?}",
        m.positions.len(),
        m.topology.live_vertex_count(),
        s.vertices,
        s.faces,
        s.edges,
        s.boundary_edges,
        s.boundary_loops,
        s.euler,
        s.genus
    );
    println!("{:?}", m.repairs);
}
