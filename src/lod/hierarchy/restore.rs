//! A vertex split's undo (papers/001): puts back every field its collapse wrote, reading
//! the wings and u's wedges from the removed faces, which nothing writes while they are removed.

use super::CollapseRecord;
use crate::mesh::{constraints, Mesh};
use crate::topology::{vflag, HalfEdges, Topology, INVALID};

/// u's wedge on the u→v side and on the v→u side of a collapse (one side's twice on a
/// border): the "from" wedges of [`constraints::wedge_map`]. Read before the collapse by the
/// plan, and from the removed faces' corners by the split.
pub(super) fn u_wedges(mesh: &Mesh, hu: u32, hv: u32) -> [u32; 2] {
    let [(w1, _), (w2, _)] = constraints::wedge_map(mesh, hu, hv);
    if hu == INVALID {
        [w2, w2]
    } else if hv == INVALID {
        [w1, w1]
    } else {
        [w1, w2]
    }
}

/// Puts the topology and wedges back exactly as they were before `r`'s collapse.
pub(super) fn restore(mesh: &mut Mesh, u: u32, r: &CollapseRecord) {
    let (hu, hv) = r.halves(&mesh.topology);
    let u_wedges = u_wedges(mesh, hu, hv);
    let t = &mut mesh.topology;
    let v = r.target;
    let [x1, y1, x2, y2] = r.outer(t);
    // Nothing has written the removed faces or the half-edges around them since the collapse
    // (the record is on top of all of them), so the wings and u's wedges are read back instead
    // of stored: a wing is the far end of the outside half-edges of its removed face (x runs
    // from the wing, y towards it; the link condition keeps one of them), and u's wedges are
    // still in the removed faces' corners (`constraints::collapse_with_wedges` leaves them).
    let wing = |t: &Topology, x: u32, y: u32| {
        debug_assert!(x != INVALID || y != INVALID, "a wing with both outside edges on the border");
        if x != INVALID {
            t.origin(x)
        } else {
            t.dest(y)
        }
    };
    let a = if hu != INVALID { wing(t, x1, y1) } else { INVALID };
    let b = if hv != INVALID { wing(t, x2, y2) } else { INVALID };
    let corner = &mut mesh.wedges.corner;
    // The arc: u's old faces, still counter-clockwise around v.
    // (Walked while written: the walk reads twins, which are written only after it.)
    let mut g = r.arc_start;
    for k in 0..r.arc_len() {
        t.faces[(g / 3) as usize][(g % 3) as usize] = u;
        // Identity wedges: the corner's wedge is the vertex just written.
        if let Some(c) = corner.get_mut(g as usize) {
            *c = u_wedges[usize::from(k >= r.wedge_switch)];
        }
        if k + 1 < r.arc_len() {
            g = t.twin[Topology::prev(g) as usize];
        }
    }
    let set_twin = |t: &mut Topology, p: u32, q: u32| {
        if p != INVALID {
            t.twin[p as usize] = q;
        }
        if q != INVALID {
            t.twin[q as usize] = p;
        }
    };
    if hu != INVALID {
        let f = (hu / 3) as usize;
        let c = (hu % 3) as usize;
        t.faces[f][c] = u;
        t.faces[f][(c + 1) % 3] = v;
        t.faces[f][(c + 2) % 3] = a;
    }
    if hv != INVALID {
        let f = (hv / 3) as usize;
        let c = (hv % 3) as usize;
        t.faces[f][c] = v;
        t.faces[f][(c + 1) % 3] = u;
        t.faces[f][(c + 2) % 3] = b;
    }
    set_twin(t, hu, hv);
    if hu != INVALID {
        let (n, p) = (Topology::next(hu), Topology::prev(hu));
        set_twin(t, n, x1);
        set_twin(t, p, y1);
    }
    if hv != INVALID {
        let (n, p) = (Topology::next(hv), Topology::prev(hv));
        set_twin(t, n, x2);
        set_twin(t, p, y2);
    }
    t.vflags[u as usize] &= !vflag::REMOVED;
    // Outgoing half-edges now known to belong to each endpoint and wing.
    let pick = |x: u32, y: u32| if x != INVALID { x } else { y };
    let hint_u = pick(hu, if hv != INVALID { Topology::next(hv) } else { INVALID });
    let hint_v = pick(hv, if hu != INVALID { Topology::next(hu) } else { INVALID });
    t.vertex_he[u as usize] = hint_u;
    t.relink_vertex(u, hint_u);
    t.relink_vertex(v, hint_v);
    if hu != INVALID {
        t.relink_vertex(a, Topology::prev(hu));
    }
    if hv != INVALID {
        t.relink_vertex(b, Topology::prev(hv));
    }
}
