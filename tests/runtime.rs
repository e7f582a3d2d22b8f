//! The frame-to-frame runtime (papers/001 on top of papers/000): split legality, exact
//! restoration, fixed points, determinism, the index buffer.

mod common;

use common::runtime::{check, same_mesh, walk, FacingWatch};
use common::{check_source_triangles, surfaces};
use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::coarsen::Schedule;
use dynlod::lod::hierarchy::Unsplittable;
use dynlod::lod::{FrameStats, FrameStop, InputError, Runtime, RuntimeOptions};
use dynlod::topology::{HalfEdges, INVALID};
use dynlod::view::{View, ViewError};
use dynlod::{procedural, BuildOptions, Mesh};
use proptest::prelude::*;

fn build(m: &dynlod::IndexedMesh) -> Mesh {
    Mesh::build(m, BuildOptions::default()).unwrap()
}

fn bunny() -> Mesh {
    dynlod::load_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"), BuildOptions::default())
        .unwrap()
}

fn no_anchors() -> RuntimeOptions {
    RuntimeOptions::default().audit(true).anchors(None).rebalance_moves(0)
}

/// A 7×7 grid (flat, so every collapse is geometrically fine), its centre vertex.
fn grid() -> (Mesh, u32) {
    let m = build(&procedural::grid(7, 7, |_, _| false));
    let (mid, _) = frame_bounds(&m.positions);
    let c = (0..m.positions.len() as u32)
        .min_by(|&a, &b| {
            let d = |v: u32| {
                let p = m.positions[v as usize];
                (p[0] - mid[0]).powi(2) + (p[1] - mid[1]).powi(2)
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    (m, c)
}

#[test]
fn a_split_waits_for_the_split_above_it() {
    let (m, c) = grid();
    let original = m.clone();
    let mut rt = Runtime::new(m, no_anchors());
    let u = rt.mesh().topology.neighbors(c).next().unwrap();
    assert!(rt.collapse(u, c), "u → c");
    // c now holds u's old faces; collapsing c into a neighbour edits them again.
    let ring: Vec<u32> = rt.mesh().topology.neighbors(c).collect();
    let w = ring.into_iter().find(|&w| rt.collapse(c, w)).expect("some collapse of c");
    assert!(rt.hierarchy().is_collapsed(c));
    assert!(!rt.hierarchy().is_splittable(u), "u's faces are held by c's collapse");
    assert_eq!(rt.split(u), Err(Unsplittable::Buried));
    check(&rt, 1, 1);
    rt.split(c).unwrap();
    assert!(rt.hierarchy().is_splittable(u));
    rt.split(u).unwrap();
    check(&rt, 1, 1);
    assert!(same_mesh(rt.mesh(), &original), "w = {w}");
}

#[test]
fn a_split_after_a_neighbour_collapsed_elsewhere() {
    let (m, c) = grid();
    let original = m.clone();
    let mut rt = Runtime::new(m, no_anchors());
    let u = rt.mesh().topology.neighbors(c).next().unwrap();
    assert!(rt.collapse(u, c));
    let mine: Vec<u32> = rt.hierarchy().touched(&rt.mesh().topology, u).unwrap();
    // A vertex two rings out collapses away from c: no face in common with u's record.
    let t = &rt.mesh().topology;
    let ring1: Vec<u32> = t.neighbors(c).collect();
    let x = ring1
        .iter()
        .flat_map(|&w| t.neighbors(w).collect::<Vec<_>>())
        .find(|&x| x != c && !ring1.contains(&x) && !t.is_boundary_vertex(x))
        .unwrap();
    let y = t.neighbors(x).find(|&y| y != c && !ring1.contains(&y) && !t.is_boundary_vertex(y)).unwrap();
    assert!(rt.collapse(x, y));
    let theirs: Vec<u32> = rt.hierarchy().touched(&rt.mesh().topology, x).unwrap();
    assert!(mine.iter().all(|f| !theirs.contains(f)), "records share no face");
    // u's split is still legal, and undoing in the other order than LIFO restores exactly.
    assert!(rt.hierarchy().is_splittable(u));
    rt.split(u).unwrap();
    check(&rt, 1, 1);
    rt.split(x).unwrap();
    assert!(same_mesh(rt.mesh(), &original));
}

#[test]
fn deep_chains_are_rebalanced_without_changing_the_triangle_count() {
    // The bunny coarsened for a distant view without rebalancing, then rebalanced by hand.
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let view = CameraPath::Dolly.view(0, 100, centre, diag, (1920, 1080));
    let mut rt = Runtime::new(m.clone(), RuntimeOptions::default().audit(true).rebalance_moves(0));
    rt.update(Some(&view));
    let (max0, mean0, tris) = (rt.hierarchy().max_depth(), rt.hierarchy().mean_depth(), rt.triangles());
    assert!(max0 >= 6, "chain depth {max0}");
    let mut moved = 0;
    for _ in 0..20 {
        moved += rt.rebalance(256);
    }
    let (max1, mean1) = (rt.hierarchy().max_depth(), rt.hierarchy().mean_depth());
    assert!(moved > 50, "{moved} moves");
    assert!(max1 <= max0 && mean1 < mean0, "max {max0} → {max1}, mean {mean0:.3} → {mean1:.3}");
    assert_eq!(rt.triangles(), tris, "moves keep the triangle count");
    let s = m.topology.stats();
    check(&rt, s.euler, s.boundary_loops);
    rt.refine_fully();
    assert!(same_mesh(rt.mesh(), &m));
}

#[test]
fn a_static_camera_is_a_fixed_point() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let view = CameraPath::Orbit.view(30, 360, centre, diag, (1920, 1080));
    for sched in Schedule::ALL {
        let mut rt = Runtime::new(m.clone(), RuntimeOptions::default().audit(true).rebalance_moves(0).schedule(sched));
        let first = rt.update(Some(&view));
        assert!(first.collapses > 10_000, "{sched:?} {first:?}");
        // Every collapse of a still camera answered at most τc = 1 px / 1.5, and nothing split.
        let e = rt.screen_error();
        assert!(e > 0.3 && e <= 1.0 / 1.5, "{sched:?}: screen error {e}");
        let second = rt.update(Some(&view));
        assert_eq!((second.collapses, second.splits, second.changed_triangles), (0, 0, 0), "{sched:?} {second:?}");
    }
    // With rebalancing, moves stop after some frames (its potential falls with every move),
    // retries included.
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true));
    let mut quiet = 0;
    for _ in 0..60 {
        let s = rt.update(Some(&view));
        quiet = if s.collapses + s.splits + s.rebalanced == 0 && s.changed_triangles == 0 { quiet + 1 } else { 0 };
    }
    assert!(quiet >= 20, "still changing after {} frames", 60 - quiet);
    rt.mesh().topology.validate().unwrap();
}

/// Auditing keeps the faces of buried records for `check`; it must change nothing else: the
/// same frames come out with and without it, `check` passes after each either way, a record
/// names its faces without the audit exactly when it is on top, and the memory report differs
/// by the audit alone.
#[test]
fn auditing_changes_nothing_but_what_check_can_see() {
    let m = bunny();
    let n = m.positions.len() as u32;
    let (centre, diag) = frame_bounds(&m.positions);
    let mut plain = Runtime::new(m.clone(), RuntimeOptions::default());
    let mut audited = Runtime::new(m, RuntimeOptions::default().audit(true));
    for f in 0..30 {
        let view = CameraPath::Dolly.view(f * 3, 90, centre, diag, (1280, 720));
        let (a, b) = (plain.update(Some(&view)), audited.update(Some(&view)));
        assert_eq!((a.collapses, a.splits, a.triangles), (b.collapses, b.splits, b.triangles), "frame {f}");
        let parts = |rt: &Runtime| rt.index_buffer().parts().iter().map(|p| p.triangles().to_vec()).collect::<Vec<_>>();
        assert_eq!(parts(&plain), parts(&audited), "frame {f}");
        plain.hierarchy().check(&plain.mesh().topology).unwrap();
        audited.hierarchy().check(&audited.mesh().topology).unwrap();
    }
    let (h, t) = (plain.hierarchy(), &plain.mesh().topology);
    let (ha, ta) = (audited.hierarchy(), &audited.mesh().topology);
    let (mut on_top, mut buried) = (0, 0);
    for u in 0..n {
        if !h.is_collapsed(u) {
            assert_eq!((h.touched(t, u), ha.touched(ta, u)), (None, None));
            continue;
        }
        let full = ha.touched(ta, u).expect("the audit names every record's faces");
        assert_eq!(full.len(), usize::from(h.record(u).touched_count()));
        if h.is_splittable(u) {
            on_top += 1;
            assert_eq!(h.touched(t, u), Some(full), "record {u}: walked and audited faces differ");
        } else {
            buried += 1;
            assert_eq!(h.touched(t, u), None);
        }
    }
    assert!(on_top > 100 && buried > 1000, "{on_top} on top, {buried} buried");
    let audit_bytes = |rt: &Runtime| rt.memory_report().entries.iter().find(|e| e.0 == "hierarchy.audit").unwrap().1;
    assert_eq!(audit_bytes(&plain), 0);
    assert!(audit_bytes(&audited) > 0);
    assert_eq!(audited.memory_report().total() - audit_bytes(&audited), plain.memory_report().total());
}

#[test]
fn moving_closer_splits_and_moving_away_collapses() {
    let m = bunny();
    let n = m.topology.live_face_count();
    let (centre, diag) = frame_bounds(&m.positions);
    let mut rt = Runtime::new(m.clone(), RuntimeOptions::default().audit(true));
    let far = CameraPath::Dolly.view(0, 100, centre, diag, (1920, 1080));
    let near = CameraPath::Dolly.view(50, 100, centre, diag, (1920, 1080));
    let a = rt.update(Some(&far)).triangles;
    let mut b = 0;
    let mut splits = 0;
    for f in 1..=50 {
        let s = rt.update(Some(&CameraPath::Dolly.view(f, 100, centre, diag, (1920, 1080))));
        splits += s.splits;
        b = s.triangles;
    }
    assert!(splits > 1000 && b > 2 * a, "far {a}, near {b}, splits {splits}");
    let c = rt.update(Some(&far)).triangles;
    assert!(c < b / 2, "back far: {c}");
    check(&rt, m.topology.stats().euler, m.topology.stats().boundary_loops);
    let _ = near;
    // Fully refined again: the input exactly.
    rt.refine_fully();
    assert_eq!(rt.triangles(), n);
    assert!(same_mesh(rt.mesh(), &m));
    assert_eq!(rt.screen_error(), 0.0, "nothing collapsed, nothing to show");
}

/// Flies a dolly and checks, after every frame and in every part, what a renderer relies on:
/// copying only the reported ranges into last frame's buffer (cut to the new length) gives
/// this frame's buffer, live slots hold exactly the live faces of the part's primitive and the
/// rest are degenerate. Returns, per frame, each part's length and live count, and whether any
/// live face changed slot.
fn fly_index_buffer(m: Mesh, compact: bool) -> (Vec<Vec<(usize, usize)>>, bool) {
    let (centre, diag) = frame_bounds(&m.positions);
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true).compact_index_buffer(compact));
    let mut mirrors: Vec<Vec<[u32; 3]>> = rt.index_buffer().parts().iter().map(|p| p.triangles().to_vec()).collect();
    let mut slots: Vec<u32> =
        (0..rt.mesh().topology.face_slots() as u32).map(|f| rt.index_buffer().slot_of_face(f)).collect();
    let (mut sizes, mut moved) = (Vec::new(), false);
    for f in 0..40 {
        rt.update(Some(&CameraPath::Dolly.view(f * 2, 80, centre, diag, (1280, 720))));
        let (ib, m) = (rt.index_buffer(), rt.mesh());
        assert_eq!(ib.parts().len(), m.primitives.len());
        for (p, (part, mirror)) in ib.parts().iter().zip(&mut mirrors).enumerate() {
            let cur = part.triangles();
            mirror.resize(cur.len(), [0; 3]);
            for r in part.changed_ranges() {
                mirror[r.start as usize..r.end as usize].copy_from_slice(&cur[r.start as usize..r.end as usize]);
            }
            assert!(mirror == cur, "frame {f}, part {p}: uploading the reported ranges does not give the buffer");
        }
        let t = &m.topology;
        let mut live = vec![0; ib.parts().len()];
        for face in 0..t.face_slots() as u32 {
            let s = ib.slot_of_face(face);
            assert_eq!(s != INVALID, t.is_face_live(face));
            if s != INVALID {
                let p = m.primitive_of(face as usize) as usize;
                let c = |k: u32| m.corner_wedge(3 * face + k);
                assert_eq!(ib.parts()[p].triangles()[s as usize], [c(0), c(1), c(2)], "face {face} not in part {p}");
                assert_eq!(ib.parts()[p].face_in_slot(s), Some(face));
                live[p] += 1;
                moved |= slots[face as usize] != INVALID && slots[face as usize] != s;
            }
            slots[face as usize] = s;
        }
        let mut frame = Vec::new();
        for (part, live) in ib.parts().iter().zip(live) {
            let cur = part.triangles();
            let degenerate = cur.iter().filter(|t| t[0] == t[1] && t[1] == t[2]).count();
            assert_eq!(degenerate + live, cur.len());
            let free = (0..cur.len() as u32).filter(|&s| part.face_in_slot(s).is_none()).count();
            assert_eq!(free, degenerate, "a free slot names no face");
            assert_eq!(live, part.live());
            frame.push((cur.len(), live));
        }
        assert_eq!(ib.live(), frame.iter().map(|s| s.1).sum::<usize>());
        sizes.push(frame);
    }
    (sizes, moved)
}

/// The bundled bunny's triangles put in `k` primitives (materials 0..k) by bands of their
/// first vertex's x, as a glTF mesh with several materials would be.
fn banded_bunny(k: usize) -> Mesh {
    let mut input = dynlod::io::load(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz")).unwrap();
    let (lo, hi) = input.positions.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
    input.primitives = (0..k)
        .map(|i| dynlod::mesh::Primitive { name: format!("band {i}"), material: Some(i), ..Default::default() })
        .collect();
    input.triangle_primitive = input
        .triangles
        .iter()
        .map(|t| (((input.positions[t[0] as usize][0] - lo) / (hi - lo) * k as f32) as usize).min(k - 1) as u32)
        .collect();
    build(&input)
}

#[test]
fn the_index_buffer_tracks_the_mesh_and_reports_what_changed() {
    // Compacting: never more than twice the live triangles once past the smallest size.
    let (sizes, _) = fly_index_buffer(bunny(), true);
    for (f, parts) in sizes.iter().enumerate() {
        assert_eq!(parts.len(), 1, "a scan has one primitive");
        let (len, live) = parts[0];
        assert!(len <= (2 * live).max(1024), "frame {f}: {len} slots for {live} live triangles");
    }
    // Without compaction a live face keeps its slot, and the buffer keeps its input size.
    let (sizes, moved) = fly_index_buffer(bunny(), false);
    assert!(!moved, "a live face changed slot without compaction");
    assert!(sizes.iter().all(|s| s[0].0 >= 69_451));
    assert!(sizes[0][0].1 < 69_451 / 2, "the walk must free most slots for the compaction check to mean anything");
}

#[test]
fn each_primitive_gets_its_own_part_of_the_index_buffer() {
    let m = banded_bunny(3);
    let inputs: Vec<usize> =
        (0..3).map(|p| (0..m.topology.face_slots()).filter(|&f| m.primitive_of(f) == p).count()).collect();
    assert!(inputs.iter().all(|&n| n > 5_000), "{inputs:?}");
    let (sizes, _) = fly_index_buffer(m.clone(), true);
    for (f, parts) in sizes.iter().enumerate() {
        assert_eq!(parts.len(), 3);
        for (p, &(len, live)) in parts.iter().enumerate() {
            assert!(len <= (2 * live).max(1024), "frame {f}, part {p}: {len} slots for {live} live triangles");
        }
    }
    let compacted = sizes.last().unwrap();
    assert!((0..3).any(|p| compacted[p].0 < inputs[p] / 2), "the walk must compact some part: {compacted:?}");
    let (sizes, moved) = fly_index_buffer(m.clone(), false);
    assert!(!moved, "a live face changed slot without compaction");
    for parts in &sizes {
        for (p, &(len, _)) in parts.iter().enumerate() {
            assert_eq!(len, inputs[p], "a part never holds more slots than its primitive's triangles");
        }
    }
    // Refined fully, each part draws its primitive's input triangles again.
    let mut rt = Runtime::new(m, RuntimeOptions::default());
    let (centre, diag) = frame_bounds(&rt.mesh().positions);
    rt.update(Some(&CameraPath::Orbit.view(0, 360, centre, diag, (640, 360))));
    assert!(rt.triangles() < 69_451 / 2);
    rt.refine_fully();
    let lives: Vec<usize> = rt.index_buffer().parts().iter().map(|p| p.live()).collect();
    assert_eq!(lives, inputs);
}

/// What a renderer draws from the vertex buffer uploaded once (`wedge_positions` and the
/// wedges' normals and UVs) and each part's triangles, as (material, corner values) sorted.
fn drawn(rt: &Runtime) -> Vec<(Option<usize>, [[u32; 8]; 3])> {
    let m = rt.mesh();
    let positions = m.wedge_positions();
    assert_eq!(positions.len(), m.wedges.len());
    let corner = |w: u32| corner_bits(&positions, &m.wedges.normals, &m.wedges.uvs, w);
    let mut out = Vec::new();
    for (part, primitive) in rt.index_buffer().parts().iter().zip(&m.primitives) {
        for t in part.triangles().iter().filter(|t| t[0] != t[1]) {
            out.push((primitive.material, t.map(corner)));
        }
    }
    out.sort_unstable();
    out
}

/// The same of the mesh written out (`to_indexed`, what a GLB would hold).
fn written(m: &Mesh) -> Vec<(Option<usize>, [[u32; 8]; 3])> {
    let out = m.to_indexed();
    let corner = |v: u32| corner_bits(&out.positions, &out.normals, &out.uvs, v);
    let mut tris: Vec<_> = (0..out.triangles.len())
        .map(|t| (out.primitives[out.primitive_of(t) as usize].material, out.triangles[t].map(corner)))
        .collect();
    tris.sort_unstable();
    tris
}

/// Vertex `i`'s position, normal and UV (zeros where there are none), as bits.
fn corner_bits(positions: &[[f32; 3]], normals: &[[f32; 3]], uvs: &[[f32; 2]], i: u32) -> [u32; 8] {
    let (p, i) = (positions[i as usize], i as usize);
    let n = normals.get(i).copied().unwrap_or_default();
    let uv = uvs.get(i).copied().unwrap_or_default();
    [p[0], p[1], p[2], n[0], n[1], n[2], uv[0], uv[1]].map(f32::to_bits)
}

#[test]
fn a_renderer_draws_the_mesh_from_a_vertex_buffer_uploaded_once() {
    // A seamed sphere (wedges are not the vertices), the bunny in three materials.
    let mut sphere = procedural::uv_sphere(16, 32);
    sphere.primitives = vec![dynlod::mesh::Primitive { material: Some(7), ..Default::default() }];
    for m in [build(&sphere), banded_bunny(3)] {
        let (centre, diag) = frame_bounds(&m.positions);
        let positions = m.wedge_positions();
        let mut rt = Runtime::new(m, RuntimeOptions::default());
        let mut coarsened = false;
        for f in 0..20 {
            coarsened |= rt.update(Some(&CameraPath::Dolly.view(f * 4, 80, centre, diag, (1280, 720)))).collapses > 0;
            assert_eq!(drawn(&rt), written(rt.mesh()), "frame {f}");
            assert_eq!(rt.mesh().wedge_positions(), positions, "the vertex buffer never changes");
        }
        assert!(coarsened);
    }
}

#[test]
fn the_index_buffer_reads_in_input_vertex_ids() {
    // A sphere with a UV seam and split poles, in spatial order (wedges renumbered vertices),
    // and the bunny, whose wedges are its vertices (no normals or UVs).
    let sphere = procedural::uv_sphere(24, 48);
    let bunny_input =
        dynlod::io::load(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz")).unwrap();
    for (input, seams) in [(&sphere, true), (&bunny_input, false)] {
        let m = Mesh::build(input, BuildOptions::default().spatial_order(true)).unwrap();
        assert_eq!(m.wedges.is_identity(), !seams);
        let (centre, diag) = frame_bounds(&m.positions);
        let mut rt = Runtime::new(m, RuntimeOptions::default().compact_index_buffer(true));
        let mut mirror = Vec::new();
        let at_start = check_source_triangles(&rt, input, &mut mirror);
        let mut coarsened = false;
        for f in 0..24 {
            let stats = rt.update(Some(&CameraPath::Dolly.view(f * 3, 72, centre, diag, (1280, 720))));
            coarsened |= stats.collapses > 0;
            let drawn = check_source_triangles(&rt, input, &mut mirror);
            // The seam's two sides keep their own input vertices at every level of detail.
            assert_eq!(drawn > 0, seams, "frame {f}");
        }
        assert!(coarsened && (at_start > 0) == seams);
    }
}

#[test]
fn the_budget_mode_settles_under_its_budget() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true).budget(Some(8000)));
    let mut last = Vec::new();
    for f in 0..30 {
        last.push(rt.update(Some(&CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080)))).triangles);
    }
    for &t in &last[10..] {
        assert!((4000..=8000).contains(&t), "{last:?}");
    }
}

#[test]
fn memory_report_covers_the_structures() {
    let m = bunny();
    let n = m.positions.len();
    let (centre, diag) = frame_bounds(&m.positions);
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true));
    rt.update(Some(&CameraPath::Orbit.view(0, 360, centre, diag, (1920, 1080))));
    let r = rt.memory_report();
    assert_eq!(r.vertices, n);
    assert!(r.active_vertices < n);
    // Every structure holds something, but what a single-primitive mesh without normals or
    // UVs does not need: per-face primitive ids, and any wedge list (each wedge is its vertex).
    let bytes = |r: &dynlod::lod::MemoryReport, k: &str| r.entries.iter().find(|e| e.0 == k).unwrap().1;
    let optional = ["mesh.face_primitive", "wedges.corner", "wedges.source", "wedges.attributes"];
    assert!(r.entries.iter().all(|e| e.1 > 0 || optional.contains(&e.0)), "{:?}", r.entries);
    assert_eq!(optional.map(|k| bytes(&r, k)), [0, 0, 0, 0]);
    // Positions alone are 12 bytes per vertex; everything together is more.
    assert!(r.total() > 12 * n);
    // Two primitives with a UV seam: both are kept, and read back per face and corner.
    let mut two = procedural::uv_sphere(6, 8);
    two.primitives = vec![Default::default(), Default::default()];
    two.triangle_primitive = (0..two.triangles.len() as u32).map(|t| t % 2).collect();
    let m = build(&two);
    assert!((0..m.topology.faces.len()).any(|f| m.primitive_of(f) == 1));
    assert!(!m.wedges.is_identity());
    let r = Runtime::new(m, RuntimeOptions::default()).memory_report();
    assert!(optional.iter().all(|k| bytes(&r, k) > 0), "{:?}", r.entries);
    // Without the seam (UVs from the positions, one wedge per vertex) the wedges are the
    // vertices: their UVs are kept, but no corner, wedge-to-vertex or input-vertex list.
    let mut smooth = procedural::grid(6, 6, |_, _| false);
    smooth.uvs = smooth.positions.iter().map(|p| [p[0], p[1]]).collect();
    let m = build(&smooth);
    assert!(m.wedges.is_identity() && m.wedges.uvs.len() == m.positions.len());
    let r = Runtime::new(m, RuntimeOptions::default()).memory_report();
    assert_eq!(optional.map(|k| bytes(&r, k) > 0), [false, false, false, true]);
}

fn fly(m: &Mesh, views: &[View], px: f32, moves: usize, sched: Schedule) -> (Mesh, Vec<(usize, usize, usize, usize)>) {
    let options = RuntimeOptions::default().audit(true).pixel_error(px).rebalance_moves(moves).schedule(sched);
    let mut rt = Runtime::new(m.clone(), options);
    let stats = views
        .iter()
        .map(|v| {
            let s = rt.update(Some(v));
            (s.collapses, s.splits, s.triangles, s.rebalanced)
        })
        .collect();
    (rt.into_mesh(), stats)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(48), ..ProptestConfig::default() })]

    /// Any legal sequence of collapses and splits keeps the mesh valid with its Euler
    /// characteristic and border loops; counters agree with a recount; splitting everything
    /// back gives the input exactly.
    #[test]
    fn collapses_and_splits_in_any_legal_order_restore_the_input(m in surfaces(), ops in prop::collection::vec((any::<bool>(), any::<u32>(), any::<u32>()), 1..300)) {
        let mesh = build(&m);
        let s0 = mesh.topology.stats();
        let mut rt = Runtime::new(mesh.clone(), no_anchors());
        for (split, a, b) in ops {
            if split {
                let front: Vec<u32> = rt.hierarchy().front().collect();
                if !front.is_empty() {
                    rt.split(front[a as usize % front.len()]).unwrap();
                }
            } else {
                let t = &rt.mesh().topology;
                let live: Vec<u32> = (0..t.vertex_count() as u32).filter(|&v| t.vertex_he[v as usize] != INVALID).collect();
                let u = live[a as usize % live.len()];
                let ns: Vec<u32> = t.neighbors(u).collect();
                let w = ns[b as usize % ns.len()];
                rt.collapse(u, w);
            }
            check(&rt, s0.euler, s0.boundary_loops);
        }
        rt.refine_fully();
        check(&rt, s0.euler, s0.boundary_loops);
        prop_assert!(same_mesh(rt.mesh(), &mesh));
    }

    /// Random camera walks: valid after every frame, counters recount, no face that faced
    /// the eye turns away unless a split gave it back its original vertex; fully refined
    /// gives the input; 1 and 2 threads agree.
    #[test]
    fn camera_walks_keep_the_mesh_valid_and_facing(m in surfaces(), seed in any::<u64>(), px in 0.3f32..8.0, sched in prop::sample::select(Schedule::ALL.to_vec())) {
        let mesh = build(&m);
        let (centre, diag) = frame_bounds(&mesh.positions);
        walk_keeps_the_mesh_valid_and_facing(&mesh, &walk(seed, 120, centre, diag), px, sched)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(24), ..ProptestConfig::default() })]

    /// The same under orthographic views, and under walks that switch between the two
    /// projections every 15 frames (`lenses`, one bit per stretch): a face turns against
    /// −forward there, whatever its distance.
    #[test]
    fn orthographic_walks_keep_the_mesh_valid_and_facing(m in surfaces(), seed in any::<u64>(), px in 0.3f32..8.0, lenses in any::<u64>()) {
        let mesh = build(&m);
        let (centre, diag) = frame_bounds(&mesh.positions);
        let views = orthographic_stretches(walk(seed, 120, centre, diag), centre, lenses);
        walk_keeps_the_mesh_valid_and_facing(&mesh, &views, px, Schedule::LocalMinima)?;
    }
}

/// Stretch k of 15 frames of `views` made orthographic when bit k of `lenses` is set, each
/// framing at `centre` what its perspective view frames there.
fn orthographic_stretches(views: Vec<View>, centre: [f32; 3], lenses: u64) -> Vec<View> {
    let distance = |v: &View| glam::Vec3::from(v.eye).distance(glam::Vec3::from(centre));
    let ortho = |k: usize| lenses >> (k / 15 % 64) & 1 == 1;
    views.iter().enumerate().map(|(k, v)| if ortho(k) { v.orthographic_at(distance(v)) } else { *v }).collect()
}

/// The body of the walk proptests: after every frame the mesh is valid with its Euler
/// characteristic and border loops and the counters recount; no face that faced the camera
/// turns away unless a split gave it back its original vertex; fully refined the walk gives
/// the input; 1 and 2 threads agree.
fn walk_keeps_the_mesh_valid_and_facing(
    mesh: &Mesh,
    views: &[View],
    px: f32,
    sched: Schedule,
) -> Result<(), TestCaseError> {
    let s0 = mesh.topology.stats();
    let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().audit(true).pixel_error(px).schedule(sched));
    for v in views {
        let watch = FacingWatch::before(&rt, std::slice::from_ref(v));
        rt.update(Some(v));
        check(&rt, s0.euler, s0.boundary_loops);
        if let Some((f, _)) = watch.turned(&rt) {
            prop_assert!(false, "face {} turned away without a split", f);
        }
    }
    rt.refine_fully();
    prop_assert!(same_mesh(rt.mesh(), mesh));
    let one = common::on_threads(1, || fly(mesh, views, px, 64, sched));
    let two = common::on_threads(2, || fly(mesh, views, px, 64, sched));
    prop_assert!(one == two);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(24), ..ProptestConfig::default() })]

    /// Budget mode on random walks with budgets from far below the boundary planes' floor to
    /// above the input: valid after every frame (the hierarchy checked with and without the
    /// audit) with a finite threshold (no wind-up) and never out of attempts, a still camera
    /// settles to a fixed point, and 1 and 2 threads agree.
    #[test]
    fn budget_walks_stay_valid_finite_and_settle(m in surfaces(), seed in any::<u64>(), share in 0.0f64..1.2) {
        let mesh = build(&m);
        let s0 = mesh.topology.stats();
        let budget = (mesh.topology.live_face_count() as f64 * share) as usize;
        let (centre, diag) = frame_bounds(&mesh.positions);
        let views = walk(seed, 60, centre, diag);
        let run = || {
            // Half the walks without the audit: `check` then verifies buried records through
            // counts alone, and that reading must hold on random walks too.
            let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().audit(seed % 2 == 0).budget(Some(budget)));
            let mut out = Vec::new();
            for v in &views {
                let s = rt.update(Some(v));
                check(&rt, s0.euler, s0.boundary_loops);
                assert!(s.pixel_error.is_finite() && s.pixel_error > 0.0, "{s:?}");
                // A frame raises until under the budget or saturated; the cap is for bugs.
                assert!(s.stop != FrameStop::AttemptCap && s.attempts >= 1, "{s:?}");
                out.push((s.collapses, s.splits, s.triangles, s.pixel_error.to_bits()));
            }
            // A still camera: within 40 frames a frame changes nothing, and the next one too.
            let last = *views.last().unwrap();
            let mut quiet = 0;
            for _ in 0..40 {
                let s = rt.update(Some(&last));
                quiet = if s.collapses + s.splits == 0 { quiet + 1 } else { 0 };
                if quiet == 2 {
                    break;
                }
            }
            assert_eq!(quiet, 2, "no fixed point under a still camera (budget {budget})");
            (out, rt.into_mesh())
        };
        let one = common::on_threads(1, run);
        let two = common::on_threads(2, run);
        prop_assert!(one == two);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(24), ..ProptestConfig::default() })]

    /// An edit cap on random walks (pixel error and budget modes): no frame makes more edits
    /// than the cap, the mesh is valid after every frame, a still camera then reaches a fixed
    /// point, fully refined it gives the input, and 1 and 2 threads agree frame by frame.
    #[test]
    fn capped_walks_stay_valid_and_catch_up(m in surfaces(), seed in any::<u64>(), cap in 1usize..48, budget in any::<bool>()) {
        let mesh = build(&m);
        let s0 = mesh.topology.stats();
        let (centre, diag) = frame_bounds(&mesh.positions);
        let views = walk(seed, 60, centre, diag);
        let budget = budget.then_some(mesh.topology.live_face_count() / 3);
        let run = || {
            let options = RuntimeOptions::default().audit(true).max_edits(Some(cap)).budget(budget);
            let mut rt = Runtime::new(mesh.clone(), options);
            let mut out = Vec::new();
            for v in &views {
                let s = rt.update(Some(v));
                check(&rt, s0.euler, s0.boundary_loops);
                assert!(s.collapses + s.splits <= cap, "{s:?}");
                assert_eq!(s.stop == FrameStop::EditCap, s.collapses + s.splits == cap, "{s:?}");
                out.push((s.collapses, s.splits, s.triangles, s.graded_phases));
            }
            let last = *views.last().unwrap();
            let mut quiet = 0;
            for _ in 0..2000 {
                let s = rt.update(Some(&last));
                quiet = if s.collapses + s.splits == 0 { quiet + 1 } else { 0 };
                if quiet == 2 {
                    break;
                }
            }
            assert_eq!(quiet, 2, "no fixed point under a still camera (cap {cap})");
            if budget.is_none() {
                assert!(rt.screen_error() <= rt.options().pixel_error, "caught up, within the pixel error");
            }
            (out, rt)
        };
        let (one, mut rt) = common::on_threads(1, run);
        let (two, _) = common::on_threads(2, run);
        prop_assert!(one == two);
        rt.refine_fully();
        prop_assert!(same_mesh(rt.mesh(), &mesh));
    }
}

/// An edit cap spreads a camera cut over frames: the bunny, warmed close up without a cap,
/// then capped at 2,000 edits and cut to 40 diagonals away. Each frame makes at most 2,000
/// edits; the grading goes on where the cap stopped it (graded phases on the frames after
/// the cut); within 12 frames the mesh is where the uncapped cut leaves it (under 700
/// triangles, within the pixel error). Back close up, the splits spread the same way, the
/// largest pixel errors first, so the screen error falls from frame to frame.
#[test]
fn an_edit_cap_spreads_a_cut_over_frames() {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let stats = m.topology.stats();
    let at = |d: f32| from_front(c, diag, d);
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true));
    for _ in 0..2 {
        rt.update(Some(&at(0.6)));
    }
    rt.set_max_edits(Some(2000));
    let mut frames = Vec::new();
    loop {
        let f = rt.update(Some(&at(40.0)));
        check(&rt, stats.euler, stats.boundary_loops);
        assert!(f.collapses + f.splits <= 2000, "{f:?}");
        frames.push(f);
        if f.stop == FrameStop::Converged || frames.len() == 12 {
            break;
        }
    }
    let last = frames.last().unwrap();
    assert_eq!(last.stop, FrameStop::Converged, "{frames:?}");
    assert!(frames.len() >= 5 && frames[1].graded_phases > 0, "{frames:?}");
    assert!(last.triangles < 700 && rt.screen_error() <= 1.0 / 1.5, "{last:?}");
    // Back in, first to 3 diagonals at 100 edits a frame: the largest pixel errors are split
    // first, so the screen error falls every frame, and the first frame leaves 27.2 px
    // where splitting in id order left 29.3 (seen failing).
    rt.set_max_edits(Some(100));
    let first: Vec<f32> = (0..6).map(|_| (rt.update(Some(&at(3.0))), rt.screen_error()).1).collect();
    assert!(first[0] < 28.0 && first.windows(2).all(|w| w[1] < w[0]), "{first:?}");
    // Then to 0.6 diagonals at 2,000 a frame: about 20,000 splits, the error falling frame by
    // frame until it is within the pixel error.
    rt.set_max_edits(Some(2000));
    let mut errors = Vec::new();
    loop {
        let f = rt.update(Some(&at(0.6)));
        assert!(f.collapses + f.splits <= 2000, "{f:?}");
        errors.push(rt.screen_error());
        if f.stop != FrameStop::EditCap {
            break;
        }
        assert!(errors.len() < 40);
    }
    check(&rt, stats.euler, stats.boundary_loops);
    assert!(errors.len() >= 8 && *errors.last().unwrap() <= 1.0, "{errors:?}");
    assert!(errors.windows(2).all(|w| w[1] <= w[0]), "{errors:?}");
}

/// Under an orthographic camera nothing depends on how far back the eye sits along its axis:
/// pixel sizes, facing and the boundary planes read only the direction. Exactly so where the
/// camera's axes are exact in f32 (looking down a coordinate axis, the eye a power of two
/// away): two runtimes whose cameras differ only in that distance make the same frames, to
/// the face. Elsewhere the axes carry rounding of the eye's position, and an orbit from 2
/// and from 20 diagonals away makes the same frames up to it; a perspective camera moved
/// back the same way does not.
#[test]
fn an_orthographic_camera_sees_the_same_from_any_distance() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let fly = |views: &dyn Fn(usize) -> View, frames: usize| {
        let mut rt = Runtime::new(m.clone(), RuntimeOptions::default());
        let counts: Vec<_> = (0..frames)
            .map(|k| {
                let s = rt.update(Some(&views(k)));
                (s.collapses, s.splits, s.triangles)
            })
            .collect();
        (counts, rt.into_mesh())
    };
    // Down the six axis directions in turn, the target on the axis through the bunny's
    // centre: target − eye is ±d along one axis, so every camera axis is exact.
    let axis_views = |d: f32| {
        move |k: usize| {
            let (axis, sign) = (k % 3, if k / 3 % 2 == 0 { 1.0 } else { -1.0 });
            let mut target = centre;
            target[axis] = 0.0;
            let mut eye = target;
            eye[axis] = sign * d;
            let up = if axis == 1 { [0.0, 0.0, 1.0] } else { [0.0, 1.0, 0.0] };
            View::orthographic(eye, target, up, 0.4 * diag, (1920, 1080))
        }
    };
    let near = fly(&axis_views(2.0), 12);
    assert!(near.0.iter().map(|c| c.1).sum::<usize>() > 100, "{:?}", near.0);
    assert!(near == fly(&axis_views(16.0), 12), "the orthographic frames moved with the eye's distance");
    let orbit = |dist: f32, ortho: bool| {
        move |k: usize| {
            let a = (k as f32 * 3.0).to_radians();
            let eye =
                [centre[0] + dist * diag * a.sin(), centre[1] + 0.3 * dist * diag, centre[2] + dist * diag * a.cos()];
            if ortho {
                View::orthographic(eye, centre, [0.0, 1.0, 0.0], 0.4 * diag, (1920, 1080))
            } else {
                View::perspective(eye, centre, [0.0, 1.0, 0.0], 45.0, (1920, 1080))
            }
        }
    };
    let (near, far) = (fly(&orbit(2.0, true), 12).0, fly(&orbit(20.0, true), 12).0);
    for (a, b) in near.iter().zip(&far) {
        assert!(a.2.abs_diff(b.2) <= a.2 / 1000, "orthographic orbit from 2 and 20 diagonals: {near:?}\n{far:?}");
    }
    let (near, far) = (fly(&orbit(2.0, false), 12).0, fly(&orbit(20.0, false), 12).0);
    assert!(far[0].2 < near[0].2 / 2, "a perspective camera's distance should matter: {near:?}\n{far:?}");
}

#[test]
fn a_bunny_walk_is_the_same_with_one_and_two_threads() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let views = walk(7, 40, centre, diag);
    for sched in Schedule::ALL {
        let fly_on = |threads: usize| common::on_threads(threads, || fly(&m, &views, 1.0, 64, sched));
        let (one, two) = (fly_on(1), fly_on(2));
        assert!(one.1.iter().map(|s| s.0 + s.1).sum::<usize>() > 1000, "{sched:?}");
        assert!(one == two, "{sched:?}");
    }
}

/// A budget below what the mesh can reach (its anchors that always stay, the boundary planes)
/// must not wind the adapted pixel error up without end: while stuck, a still camera is a
/// fixed point (same threshold, same mesh), and a budget raised later is met the same way
/// however long it was stuck: after 20 frames or 40, the same frames. From the bunny's floor
/// of 179 triangles the threshold comes down from ~10⁵ px within the first frame under the
/// raised budget, to 18,497 triangles (the band's middle is 18,500): far under the budget
/// the lowering asks which records would fill the gap, and that count is exact, so the
/// frame splits to it at once. With the count model's √(triangles / target) per frame alone
/// it took 10 frames, and with the exact count for the next frame, 2 (both seen failing).
#[test]
fn an_unreachable_budget_does_not_wind_the_threshold_up() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let view = CameraPath::Orbit.view(0, 360, centre, diag, (1920, 1080));
    let stuck_for = |frames: usize| {
        let mut rt = Runtime::new(m.clone(), RuntimeOptions::default().audit(true).budget(Some(100)));
        let stuck: Vec<_> = (0..frames).map(|_| rt.update(Some(&view))).collect();
        rt.set_budget(Some(20_000));
        let after: Vec<(usize, f32)> = (0..14)
            .map(|_| {
                let f = rt.update(Some(&view));
                (f.triangles, f.pixel_error)
            })
            .collect();
        (stuck, after)
    };
    let (frames, after) = stuck_for(20);
    let floor = frames[19].triangles;
    // Above the budget, yet far below the ~2,000 the paper's infinite grid anchors kept,
    // and below the 405 where a raise at the largest step that changed nothing stopped
    // (the next removable vertex answered more than that step: seen failing).
    assert!(floor > 100 && floor < 250, "the floor: {floor}");
    for f in &frames[6..] {
        assert!(f.pixel_error.is_finite(), "{f:?}");
        assert_eq!((f.pixel_error, f.triangles), (frames[5].pixel_error, frames[5].triangles), "{f:?}");
        assert_eq!((f.collapses, f.splits), (0, 0), "{f:?}");
    }
    let met = after.iter().position(|a| a.0 > 10_000 && a.0 <= 20_000);
    assert_eq!(met, Some(0), "stuck at {floor} with budget 100, then {after:?}");
    assert_eq!(stuck_for(40).1, after, "the threshold wound up while stuck");
}

/// A distant bunny in one cold frame. The finer anchors leave (nested anchors), each anchor
/// taking the removals finer than itself before it goes into a coarser one
/// (`select::Stays`), and the frame coarsens at falling thresholds first (the graded start),
/// so it ends about where a camera moving out over 30 frames does (593). Without the
/// graded start it kept 1,611; with the paper's infinite grid anchors as well, 3,473; nested
/// anchors with targets in S only, 46,905. Exact, within the pixel error, the same on 1 and
/// 2 threads, and a second update changes nothing.
#[test]
fn a_far_cold_frame_coarsens_below_the_grid() {
    use dynlod::lod::passes::anchors::AnchorOptions;
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let stats = m.topology.stats();
    let (euler, loops) = (stats.euler, stats.boundary_loops);
    let eye = [c[0], c[1] + 12.0 * diag, c[2] + 40.0 * diag];
    let view = View::perspective(eye, c, [0.0, 1.0, 0.0], 45.0, (1920, 1080));
    let run = |threads: usize, options: RuntimeOptions| {
        common::on_threads(threads, || {
            let mut rt = Runtime::new(m.clone(), options.audit(true).rebalance_moves(0));
            let first = rt.update(Some(&view));
            check(&rt, euler, loops);
            let second = rt.update(Some(&view));
            assert_eq!((second.collapses, second.splits), (0, 0), "a still camera is a fixed point");
            (first.triangles, rt.screen_error(), rt.into_mesh())
        })
    };
    let (tris, error, one) = run(1, RuntimeOptions::default());
    assert!(tris < 800, "{tris} triangles");
    assert!(error <= 1.0 / 1.5, "{error} px");
    assert!(run(2, RuntimeOptions::default()).2 == one, "1 and 2 threads differ");
    let (ungraded, _, _) = run(2, RuntimeOptions::default().cold_grades(0));
    let (paper, _, _) =
        run(2, RuntimeOptions::default().cold_grades(0).anchors(Some(AnchorOptions::default().nested(None))));
    assert!(ungraded > 2 * tris && paper > 2 * ungraded, "graded {tris}, not graded {ungraded}, not nested {paper}");
}

/// A 1080p view of `centre` from `d` diagonals in front of it and a little above.
fn from_front(centre: [f32; 3], diag: f32, d: f32) -> View {
    let eye = [centre[0], centre[1] + 0.3 * d * diag, centre[2] + d * diag];
    View::perspective(eye, centre, [0.0, 1.0, 0.0], 45.0, (1920, 1080))
}

/// A camera cut: warm up close to the bunny, then jump to 40 diagonals away. The cut frame
/// grades its collapses like a first frame (the tolerance at the centre grew about 67×: six
/// doublings and one more phase), so it ends at 575 triangles, about where a cold start there
/// does (607), instead of at the ~1,270 it kept ungraded (seen failing with only the cut's
/// grading turned off), which no later frame lowered. Exact, within the pixel
/// error, the same on 1 and 2 threads, and the frame after it is a fixed point. A camera on
/// a path never grades after its first frame.
#[test]
fn a_camera_cut_is_graded_like_a_first_frame() {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let stats = m.topology.stats();
    let (euler, loops) = (stats.euler, stats.boundary_loops);
    let at = |d: f32| from_front(c, diag, d);
    let run = |threads: usize, options: RuntimeOptions| {
        common::on_threads(threads, || {
            let mut rt = Runtime::new(m.clone(), options.audit(true).rebalance_moves(0));
            for _ in 0..2 {
                rt.update(Some(&at(0.6)));
            }
            let cut = rt.update(Some(&at(40.0)));
            check(&rt, euler, loops);
            let after = rt.update(Some(&at(40.0)));
            assert_eq!(
                (after.collapses, after.splits, after.graded_phases),
                (0, 0, 0),
                "a still camera is a fixed point"
            );
            (cut, rt.screen_error(), rt.into_mesh())
        })
    };
    let (cut, error, one) = run(1, RuntimeOptions::default());
    assert_eq!(cut.graded_phases, 7, "{cut:?}");
    assert!(cut.triangles < 700, "{cut:?}");
    assert!(error <= 1.0 / 1.5, "{error} px");
    assert!(run(2, RuntimeOptions::default()).2 == one, "1 and 2 threads differ");
    let (ungraded, _, _) = run(2, RuntimeOptions::default().cold_grades(0));
    assert_eq!(ungraded.graded_phases, 0);
    assert!(ungraded.triangles > cut.triangles * 3 / 2, "graded {}, not graded {}", cut.triangles, ungraded.triangles);

    // A dolly out to the same distance over 30 frames, and an orbit: no frame after the first
    // is a cut.
    let mut rt = Runtime::new(m.clone(), RuntimeOptions::default());
    for i in 0..=30 {
        let f = rt.update(Some(&at(0.6 * (40.0f32 / 0.6).powf(i as f32 / 30.0))));
        assert_eq!(f.graded_phases, if i == 0 { 10 } else { 0 }, "{f:?}");
    }
    for frame in 0..30 {
        let f = rt.update(Some(&CameraPath::Orbit.view(frame, 360, c, diag, (1920, 1080))));
        assert!(f.graded_phases == 0 || frame == 0, "{f:?}");
    }
}

/// Raising the pixel error 8× is a cut too: three doublings and one more phase; lowering it
/// again is not (splits need no grading).
#[test]
fn a_raised_pixel_error_is_graded() {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let view = View::perspective([c[0], c[1], c[2] + 2.0 * diag], c, [0.0, 1.0, 0.0], 45.0, (1920, 1080));
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true));
    assert_eq!(rt.update(Some(&view)).graded_phases, 10);
    assert_eq!(rt.update(Some(&view)).graded_phases, 0);
    rt.set_pixel_error(8.0);
    let raised = rt.update(Some(&view));
    assert_eq!(raised.graded_phases, 4, "{raised:?}");
    assert!(rt.screen_error() <= 8.0 / 1.5);
    rt.set_pixel_error(1.0);
    let lowered = rt.update(Some(&view));
    assert!(lowered.graded_phases == 0 && lowered.splits > 0, "{lowered:?}");
}

/// Degenerate views (an orthographic height of 0, which allows no error, or infinite, from
/// which the growth of the tolerance is undefined) are refused and do not count as camera
/// cuts: the view after them is graded against the last view used, here the same one.
#[test]
fn degenerate_views_are_refused_and_are_no_cut() {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let stats = m.topology.stats();
    let eye = [c[0], c[1], c[2] + 2.0 * diag];
    let ortho = |h: f32| View::orthographic(eye, c, [0.0, 1.0, 0.0], h, (1920, 1080));
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true));
    let frames: Vec<(u32, bool)> = [ortho(diag), ortho(0.0), ortho(f32::INFINITY), ortho(diag), ortho(diag * 0.9)]
        .iter()
        .map(|v| {
            let f = rt.update(Some(v));
            check(&rt, stats.euler, stats.boundary_loops);
            (f.graded_phases, f.stop == FrameStop::Refused(InputError::View { index: 0, error: ViewError::Height }))
        })
        .collect();
    assert_eq!(frames, [(10, false), (0, true), (0, true), (0, false), (0, false)]);
}

/// The bunny under a triangle budget: ten frames at 0.6 diagonals, then a cut to 40 (the
/// mesh checked after it). Gives the runtime, the cut frame and the views by distance.
fn budget_cut_away(budget: usize) -> (Runtime, FrameStats, impl Fn(f32) -> View) {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let stats = m.topology.stats();
    let at = move |d| from_front(c, diag, d);
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true).budget(Some(budget)));
    for _ in 0..10 {
        rt.update(Some(&at(0.6)));
    }
    let away = rt.update(Some(&at(40.0)));
    check(&rt, stats.euler, stats.boundary_loops);
    (rt, away, at)
}

/// Budget mode across camera cuts: the threshold is rescaled to allow at the new view the
/// model-space error it allowed at the last, so the cut frame starts near the budget: the
/// bunny under a budget of 20,000 keeps 13,609 triangles on the jump away and makes 3,648
/// edits on the jump back in, to 18,646. Without it (seen failing) the jump away fell to 233
/// triangles (the close-up's threshold collapses nearly everything from afar) and the jump
/// in split 24,761 vertices and collapsed 30,347 within the frame, ending at 6,639.
#[test]
fn a_budget_carries_over_camera_cuts() {
    let (mut rt, away, at) = budget_cut_away(20_000);
    for _ in 0..10 {
        rt.update(Some(&at(40.0)));
    }
    let back = rt.update(Some(&at(0.6)));
    let stats = bunny().topology.stats();
    check(&rt, stats.euler, stats.boundary_loops);
    assert!(away.triangles > 10_000 && away.triangles <= 20_000, "{away:?}");
    assert!(back.triangles > 10_000 && back.triangles <= 20_000, "{back:?}");
    assert!(back.splits + back.collapses < 10_000, "{back:?}");
}

/// A small budget across camera cuts. Close to the bunny, a budget of 2,000 needs a
/// threshold of millions of pixels (records whose spheres hold the eye answer errors at the
/// near plane), and carried to a far view that threshold collapses nearly everything: the
/// cut frame showed 191 triangles before the next frame split back to 1,837 (seen failing).
/// Far under the budget the controller knows exactly which splits fill the gap, so the cut
/// frame makes them itself (836 splits) and ends in the band, at 1,856; the frame after
/// changes nothing.
#[test]
fn a_small_budget_fills_the_frame_of_a_cut_away() {
    let (mut rt, away, at) = budget_cut_away(2_000);
    assert!(away.triangles >= 1_700 && away.triangles <= 2_000, "{away:?}");
    assert!(away.splits > 0 && away.collapses > 0, "{away:?}");
    let next = rt.update(Some(&at(40.0)));
    assert_eq!((next.splits, next.collapses, next.triangles), (0, 0, away.triangles), "{next:?}");
}

/// A small budget close to the mesh, from the first frame: the first shot of `fly --path
/// cuts`, 0.6 diagonals from the bunny, under a budget of 2,000 needs a threshold of
/// millions of pixels (records whose spheres hold the eye answer at the near limit). The
/// raises, ×e² at most per attempt, take 10 attempts to get there (6.1 M px, 1,070
/// triangles); at 8 the frame ended over budget (2,331 triangles; seen failing).
#[test]
fn a_small_budget_close_up_is_met_from_the_first_frame() {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let stats = m.topology.stats();
    let mut rt = Runtime::new(m, RuntimeOptions::default().audit(true).budget(Some(2_000)));
    let view = |k| CameraPath::Cuts.view(k, 120, c, diag, (1920, 1080));
    let first = rt.update(Some(&view(0)));
    check(&rt, stats.euler, stats.boundary_loops);
    assert!(first.triangles >= 1_000 && first.triangles <= 2_000, "{first:?}");
    let second = rt.update(Some(&view(1)));
    assert!(second.triangles <= 2_000, "{second:?}");
}

/// The same shot under a budget of 1,000: the raises overshoot to 169 triangles, the floor
/// the eye allows, and under half the budget the frame fills the gap with the splits that
/// close it, then raises again where they overshoot. That takes 14 attempts; with at most
/// 12 the first frame showed the 169 triangles (seen failing). A frame now raises until it
/// is under the budget or the raises change nothing.
#[test]
fn a_small_budget_close_up_fills_its_first_frame() {
    let m = bunny();
    let (c, diag) = frame_bounds(&m.positions);
    let mut rt = Runtime::new(m, RuntimeOptions::default().budget(Some(1_000)));
    let first = rt.update(Some(&CameraPath::Cuts.view(0, 120, c, diag, (1920, 1080))));
    assert!(first.triangles >= 500 && first.triangles <= 1_000, "{first:?}");
    assert!(first.attempts > 12 && first.stop == FrameStop::Converged, "{first:?}");
}
