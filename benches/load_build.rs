//! Load + weld + connectivity on the bundled bunny and, when `../shared/meshes` exists,
//! `igea_triangles.ply` (268,686 triangles). Throughput is in triangles per second.
//!
//! Stages: `parse` (file bytes -> IndexedMesh), `build` (weld + repair + connectivity +
//! wedges: `Mesh::build`), `connectivity` (`Topology::from_faces` on already clean faces).
//! Beside them, `write_glb` on a 250k-triangle grid cut into 2,000 primitives (a CAD export
//! of many parts): the writer's cost should follow the triangles, not triangles × parts.

use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use dynlod::io::Format;
use dynlod::topology::Topology;
use dynlod::{BuildOptions, Mesh};

fn inputs() -> Vec<(&'static str, Vec<u8>, Format)> {
    let mut v = Vec::new();
    let gz = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz")).unwrap();
    let mut bunny = Vec::new();
    std::io::Read::read_to_end(&mut flate2::read::GzDecoder::new(&gz[..]), &mut bunny).unwrap();
    v.push(("bunny", bunny, Format::Ply));
    let igea = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes/scans/igea_triangles.ply");
    if let Ok(bytes) = std::fs::read(igea) {
        v.push(("igea", bytes, Format::Ply));
    }
    v
}

fn bench(c: &mut Criterion) {
    for (name, bytes, format) in inputs() {
        let indexed = dynlod::io::load_bytes(&bytes, format, None).unwrap();
        let mesh = Mesh::build(&indexed, BuildOptions::default()).unwrap();
        let tris = indexed.triangles.len() as u64;
        let mut g = c.benchmark_group(format!("load_build/{name}"));
        g.sample_size(20);
        g.throughput(Throughput::Elements(tris));
        g.bench_function(BenchmarkId::new("parse", tris), |b| {
            b.iter(|| dynlod::io::load_bytes(&bytes, format, None).unwrap())
        });
        g.bench_function(BenchmarkId::new("build", tris), |b| {
            b.iter(|| Mesh::build(&indexed, BuildOptions::default()).unwrap())
        });
        let faces = mesh.topology.faces.clone();
        let nv = mesh.positions.len();
        g.bench_function(BenchmarkId::new("connectivity", tris), |b| {
            b.iter(|| Topology::from_faces(nv, faces.clone()).unwrap())
        });
        g.finish();
    }
}

fn bench_write(c: &mut Criterion) {
    let mut grid = dynlod::procedural::grid(354, 354, |_, _| false);
    let parts = 2000;
    let per = grid.triangles.len().div_ceil(parts);
    grid.triangle_primitive = (0..grid.triangles.len()).map(|t| (t / per) as u32).collect();
    grid.primitives =
        (0..parts).map(|p| dynlod::mesh::Primitive { name: format!("part{p}"), ..Default::default() }).collect();
    let tris = grid.triangles.len() as u64;
    let mut g = c.benchmark_group("write_glb");
    g.sample_size(10);
    g.throughput(Throughput::Elements(tris));
    g.bench_function(BenchmarkId::new("2000_primitives", tris), |b| {
        b.iter(|| {
            let mut out = Vec::new();
            dynlod::io::write_glb(&mut out, &grid).unwrap();
            out
        })
    });
    g.finish();
}

criterion_group!(benches, bench, bench_write);
criterion_main!(benches);
