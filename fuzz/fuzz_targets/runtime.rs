//! Fuzz the frame-to-frame runtime on whatever the Obj and GLB loaders and their repairs
//! accept. The first 16 bytes choose the options (an edit cap among them) and a camera walk
//! (eyes anywhere: far, near, inside the mesh, on the target; perspective, orthographic or
//! both); the rest is the file. A frame is refused exactly when one of its views fails
//! `View::check` (an eye on its target). Every frame is checked as
//! `fly --verify` checks it, the last one is written in the input's format and read back
//! (as a renderer exporting its current level of detail would), then a full refinement must
//! give back the built mesh exactly. Views may repeat (each shown twice, and the last one
//! held), and a second runtime with skipping off must then give the same figures frame by
//! frame and the same index buffer. Frames may show two views at once (this frame's and the
//! next's: `Runtime::update_views`), and the second runtime may get them in the other order.
//! Last, the runtime's offline cut (`Runtime::cut`, or for half the triangles
//! `Runtime::cut_to_triangles`) for the walk's first views must be a valid mesh with the
//! same Euler characteristic and borders, and written and read back.
#![no_main]

use dynlod::camera_path::frame_bounds;
use dynlod::lod::coarsen::Schedule;
use dynlod::lod::{Runtime, RuntimeOptions};
use dynlod::topology::HalfEdges;
use dynlod::view::View;
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|data: &[u8]| {
    let Some((ctl, format, mesh)) = common::controls_and_mesh(data, 16) else { return };
    let mut o = RuntimeOptions::default()
        .audit(true)
        .pixel_error([0.05, 0.5, 1.0, 8.0][usize::from(ctl[1] & 3)])
        .hysteresis(1.0 + f32::from(ctl[1] >> 4) / 8.0)
        .rebalance_moves(usize::from(ctl[2] & 7) * 4)
        .max_rounds(1 + usize::from(ctl[2] >> 3))
        .schedule(if ctl[0] & 2 != 0 { Schedule::AllCandidates } else { Schedule::LocalMinima })
        .compact_index_buffer(ctl[0] & 4 != 0);
    if ctl[0] & 8 != 0 {
        o = o.anchors(None);
    }
    if ctl[0] & 16 != 0 {
        o = o.budget(Some(usize::from(ctl[3]) * 4));
    }
    if ctl[0] & 128 != 0 {
        o = o.max_edits(Some(1 + usize::from(ctl[3] >> 2) * 8));
    }
    let (centre, diag) = frame_bounds(&mesh.positions);
    let stats = mesh.topology.stats();
    let mut expected = mesh.clone();
    let mut full = (ctl[4] & 16 != 0).then(|| Runtime::new(mesh.clone(), o.clone().skip_unchanged_frames(false)));
    let cut_options = o.clone();
    let cut_mesh = mesh.clone();
    let mut rt = Runtime::new(mesh, o);
    let distinct = 1 + usize::from(ctl[4] & 15);
    let (shown, held) = if ctl[4] & 32 != 0 { (2, 4) } else { (1, 0) };
    let view_of = |f: usize| {
        let b = |i: usize| f32::from(ctl[5 + (f * 3 + i) % 11]);
        // Eye at 0–8 diagonals from the centre (0: on the target itself), any direction.
        let (yaw, pitch) = (b(0) / 255.0 * std::f32::consts::TAU, (b(1) / 255.0 - 0.5) * 3.1);
        let dist = diag * (b(2) / 32.0);
        let eye = [
            centre[0] + dist * pitch.cos() * yaw.sin(),
            centre[1] + dist * pitch.sin(),
            centre[2] + dist * pitch.cos() * yaw.cos(),
        ];
        let fov = 5.0 + b(0) / 2.0;
        let mut view = View::perspective(eye, centre, [0.0, 1.0, 0.0], fov, (640, 480));
        // Orthographic views (every frame, or every other one), framing at the centre what
        // the perspective view frames there; a height of 0 when the eye sits on the target.
        if ctl[0] & 32 != 0 && (ctl[0] & 64 == 0 || f % 2 == 0) {
            view = view.orthographic_at(dist);
        }
        view
    };
    let (pairs, reversed) = (ctl[4] & 64 != 0, ctl[4] & 128 != 0);
    for k in 0..distinct * shown + held {
        let f = (k / shown).min(distinct - 1);
        let mut views = vec![view_of(f)];
        if pairs {
            views.push(view_of((f + 1) % distinct));
        }
        let frame = rt.update_views(&views);
        // A view on its target, or a height of 0, is refused and changes nothing; any other is used.
        let refused = matches!(frame.stop, dynlod::lod::FrameStop::Refused(_));
        assert_eq!(refused, views.iter().any(|v| v.check().is_err()), "refusal of {views:?}: {frame:?}");
        if let Some(full) = full.as_mut() {
            if reversed {
                views.reverse();
            }
            let other = full.update_views(&views);
            // A refusal names the first unusable view, which the other order may number
            // otherwise (or be another one): both refuse, or neither.
            let stop = |s: &dynlod::lod::FrameStats| match s.stop {
                dynlod::lod::FrameStop::Refused(_) => None,
                stop => Some(stop),
            };
            let figures = |s: &dynlod::lod::FrameStats| {
                (
                    s.collapses,
                    s.splits,
                    s.rebalanced,
                    s.rebalance_attempts,
                    s.triangles,
                    s.pixel_error.to_bits(),
                    stop(s),
                )
            };
            assert_eq!(figures(&frame), figures(&other), "skipping changed a frame: {frame:?}");
            let parts =
                |r: &Runtime| r.index_buffer().parts().iter().map(|p| p.triangles().to_vec()).collect::<Vec<_>>();
            assert!(parts(&rt) == parts(full), "skipping changed the index buffer");
        }
        let cap = rt.options().max_edits.unwrap_or(usize::MAX);
        assert!(frame.collapses + frame.splits <= cap, "over the edit cap: {frame:?}");
        let t = &rt.mesh().topology;
        t.validate().expect("the runtime's mesh validates");
        rt.hierarchy().check(t).expect("the hierarchy's stacks recount");
        rt.check_charges().expect("the stored charges recompute");
        let s = t.stats();
        assert_eq!((s.euler, s.boundary_loops), (stats.euler, stats.boundary_loops), "topology changed");
        assert_eq!(rt.index_buffer().live(), t.live_face_count(), "index buffer out of step");
        let (ib, m) = (rt.index_buffer(), rt.mesh());
        for f in (0..t.face_slots() as u32).filter(|&f| t.is_face_live(f)) {
            let part = &ib.parts()[m.primitive_of(f as usize) as usize];
            assert_eq!(part.face_in_slot(ib.slot_of_face(f)), Some(f), "face {f} not in its primitive's part");
        }
    }
    common::round_trip(rt.mesh(), format, "the last frame");
    let first: Vec<View> = if pairs { vec![view_of(0), view_of(1 % distinct)] } else { vec![view_of(0)] };
    let cut = if ctl[3] & 1 != 0 {
        let half = cut_mesh.topology.live_face_count() / 2;
        Runtime::cut_to_triangles(cut_mesh, &first, cut_options, half)
    } else {
        Runtime::cut(cut_mesh, &first, cut_options)
    };
    match cut {
        Ok(cut) => {
            cut.mesh.topology.validate().expect("the cut validates");
            let s = cut.mesh.topology.stats();
            assert_eq!(
                (s.euler, s.boundary_loops),
                (stats.euler, stats.boundary_loops),
                "the cut changed the topology"
            );
            common::round_trip(&cut.mesh, format, "the cut");
        }
        Err(e) => assert!(first.iter().any(|v| v.check().is_err()), "a cut refused usable views: {e}"),
    }
    rt.refine_fully();
    let mut got = rt.into_mesh();
    got.topology.rebuild_vertex_links();
    expected.topology.rebuild_vertex_links();
    assert!(got == expected, "a full refinement did not restore the built mesh");
});
