//! Profiling helper: builds connectivity for one mesh 30 times (`perf record` this binary).
fn main() {
    let p = std::env::args().nth(1).unwrap();
    let m = dynlod::io::load(&p).unwrap();
    for _ in 0..30 {
        std::hint::black_box(dynlod::Mesh::build(&m, Default::default()).unwrap());
    }
}
