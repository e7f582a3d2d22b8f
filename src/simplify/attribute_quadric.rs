//! Attribute error quadrics (Hoppe, "New quadric metric for simplifying meshes with
//! appearance attributes", IEEE Visualization 1999), as meshoptimizer's
//! `simplifyWithAttributes` weighs normals, texture coordinates and colours: over each face
//! an attribute channel is the linear function s(p) = g·p + d that takes the corners' values
//! (g in the face's plane), and a wedge w carries
//!
//! ```text
//!   A_w(p, s) = Σ_f area_f · Σ_k (g_fk·p + d_fk − s_k)²      over the faces of w's corners
//! ```
//! the area-weighted squared difference between the values s the wedge would show at p and
//! what its faces interpolated there. A half-edge collapse u → v moves each wedge of u onto
//! its wedge of v ([`crate::mesh::constraints::wedge_map`]): it costs A_wu(p_v, s_wv) for
//! every wedge of u, plus A_wv(p_v, s_wv) for every wedge of v it lands on (as the geometric
//! part costs (Q_u + Q_v)(p_v)), and leaves A_wv + A_wu at wv.
//!
//! The channels are scaled by their kind's weight ([`AttributeWeights`]), and the engine
//! adds W · ΣA to the geometric Q(p_v), W being Q's weight (the area around u and v): that is
//! W times meshoptimizer's ranking, Q/W + ΣA, as our geometric ranking is W times its Q/W.
//! Both parts are then lengths to the fourth power, whatever the model's units, and
//! meshoptimizer's reading of the weights holds: an area-weighted change of 1 in a weighted
//! attribute across a face of size d costs about as much as moving that face by d. The error
//! bound (`--error`) stays geometric.
//!
//! Storage per wedge, for k channels: Σ a Σ_k g gᵀ (6), Σ a Σ_k g d (3), Σ a Σ_k d² (1),
//! Σ a (1), and per channel Σ a g_k (3) and Σ a d_k (1): 11 + 4k doubles. Expanding the
//! square, `A(p, s) = pᵀ[gg]p + 2[gd]·p + [dd] + Σ_k (s_k²[a] − 2 s_k([g_k]·p + [d_k]))`.

use glam::DVec3;

use crate::mesh::{constraints, Mesh};
use crate::topology::{HalfEdgeCollapse, INVALID};

/// How much each kind of attribute counts in the quadric cost (0: not at all, the default).
/// Colours and texture coordinates are compared in their own units (colours 0–1), normals
/// and tangents as unit vectors. meshoptimizer's documentation suggests about 0.5 for
/// normals and 1 for colours; texture coordinates depend on the texture's detail.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AttributeWeights {
    /// `NORMAL`.
    pub normal: f32,
    /// Every texture coordinate set (`TEXCOORD_n`).
    pub uv: f32,
    /// Every colour set (`COLOR_n`).
    pub color: f32,
    /// `TANGENT` (its direction; the handedness is a seam).
    pub tangent: f32,
}

impl AttributeWeights {
    /// The same weight for every kind.
    pub fn all(w: f32) -> Self {
        Self { normal: w, uv: w, color: w, tangent: w }
    }

    /// Whether any kind counts.
    pub fn any(&self) -> bool {
        [self.normal, self.uv, self.color, self.tangent].iter().any(|&w| w > 0.0)
    }

    /// Parses `W` (every kind) or a comma-separated list of `KIND=W` with KIND one of
    /// `normal`, `uv`, `color` (or `colour`), `tangent`; kinds not named weigh 0.
    pub fn parse(s: &str) -> Result<Self, String> {
        let weight = |v: &str| match v.trim().parse::<f32>() {
            Ok(w) if w.is_finite() && w >= 0.0 => Ok(w),
            _ => Err(format!("attribute weight {v:?} is not a non-negative number")),
        };
        if !s.contains('=') {
            return weight(s).map(Self::all);
        }
        let mut out = Self::default();
        for part in s.split(',') {
            let (kind, w) = part.split_once('=').ok_or_else(|| format!("{part:?}: expected KIND=WEIGHT"))?;
            let slot = match kind.trim() {
                "normal" => &mut out.normal,
                "uv" => &mut out.uv,
                "color" | "colour" => &mut out.color,
                "tangent" => &mut out.tangent,
                other => return Err(format!("unknown attribute kind {other:?} (expected normal, uv, color, tangent)")),
            };
            *slot = weight(w)?;
        }
        Ok(out)
    }

    /// The weight of an attribute with glTF semantic `semantic` (`NORMAL`, `TEXCOORD_n`,
    /// `COLOR_n`, `TANGENT`; 0 for any other).
    pub fn of(&self, semantic: &str) -> f32 {
        match semantic {
            "NORMAL" => self.normal,
            "TANGENT" => self.tangent,
            s if s.starts_with("TEXCOORD_") => self.uv,
            s if s.starts_with("COLOR_") => self.color,
            _ => 0.0,
        }
    }

    /// The semantics of `mesh` these weights make count (`NORMAL`, `TEXCOORD_0`, then the
    /// further attributes in the mesh's order).
    pub fn weighted(&self, mesh: &Mesh) -> Vec<String> {
        sources(mesh, self).into_iter().map(|s| s.semantic).collect()
    }
}

/// One weighted attribute of the mesh's wedges.
struct Source<'m> {
    semantic: String,
    values: &'m [f32],
    stride: usize,
    /// Components read (a tangent's handedness is left out).
    read: usize,
    weight: f64,
}

fn sources<'m>(mesh: &'m Mesh, w: &AttributeWeights) -> Vec<Source<'m>> {
    let wd = &mesh.wedges;
    let mut out = Vec::new();
    let mut push = |semantic: &str, values: &'m [f32], stride: usize, read: usize, weight: f32| {
        if weight > 0.0 && !values.is_empty() {
            out.push(Source { semantic: semantic.into(), values, stride, read, weight: f64::from(weight) });
        }
    };
    push("NORMAL", wd.normals.as_flattened(), 3, 3, w.of("NORMAL"));
    push("TEXCOORD_0", wd.uvs.as_flattened(), 2, 2, w.of("TEXCOORD_0"));
    for a in &wd.attributes {
        push(&a.semantic, &a.values, a.components, a.varying_components(), w.of(&a.semantic));
    }
    out
}

/// The weighted channel values of every wedge, `k` per wedge.
struct Channels {
    k: usize,
    values: Vec<f64>,
}

fn channels(mesh: &Mesh, weights: &AttributeWeights) -> Channels {
    let srcs = sources(mesh, weights);
    let k: usize = srcs.iter().map(|s| s.read).sum();
    let n = mesh.wedges.len();
    let mut values = vec![0.0; n * k];
    let mut at = 0;
    for s in &srcs {
        for w in 0..n {
            for c in 0..s.read {
                values[w * k + at + c] = f64::from(s.values[w * s.stride + c]) * s.weight;
            }
        }
        at += s.read;
    }
    Channels { k, values }
}

/// Every wedge's attribute quadric.
pub(crate) struct AttributeQuadrics {
    k: usize,
    stride: usize,
    data: Vec<f64>,
    channels: Channels,
}

/// Offsets within a wedge's quadric.
const GG: usize = 0;
const GD: usize = 6;
const DD: usize = 9;
const AREA: usize = 10;
const PER_CHANNEL: usize = 11;

impl AttributeQuadrics {
    /// The quadrics of `mesh`'s live faces; `None` when the weights make nothing count.
    pub fn new(mesh: &Mesh, weights: &AttributeWeights) -> Option<Self> {
        let channels = channels(mesh, weights);
        let k = channels.k;
        if k == 0 {
            return None;
        }
        let stride = PER_CHANNEL + 4 * k;
        let mut data = vec![0.0; mesh.wedges.len() * stride];
        let t = &mesh.topology;
        let p = |v: u32| DVec3::from(mesh.positions[v as usize].map(f64::from));
        let mut face = vec![0.0; stride];
        for (fi, f) in t.faces.iter().enumerate() {
            if f[0] == INVALID {
                continue;
            }
            let [p0, p1, p2] = f.map(p);
            let (e1, e2) = (p1 - p0, p2 - p0);
            let (a11, a12, a22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
            let det = a11 * a22 - a12 * a12;
            let area = 0.5 * e1.cross(e2).length();
            if !(det > 0.0 && area > 0.0) {
                continue;
            }
            let w: [u32; 3] = std::array::from_fn(|c| mesh.corner_wedge((3 * fi + c) as u32));
            face.fill(0.0);
            face[AREA] = area;
            for c in 0..k {
                let s = w.map(|w| channels.values[w as usize * k + c]);
                let (b1, b2) = (s[1] - s[0], s[2] - s[0]);
                // g = α e1 + β e2 with g·e1 = b1, g·e2 = b2 (the gradient within the plane).
                let alpha = (b1 * a22 - b2 * a12) / det;
                let beta = (b2 * a11 - b1 * a12) / det;
                let g = e1 * alpha + e2 * beta;
                let d = s[0] - g.dot(p0);
                add_channel(&mut face, c, g, d, area);
            }
            for &w in &w {
                let q = &mut data[w as usize * stride..(w as usize + 1) * stride];
                q.iter_mut().zip(&face).for_each(|(a, b)| *a += b);
            }
        }
        Some(Self { k, stride, data, channels })
    }

    fn quadric(&self, w: u32) -> &[f64] {
        &self.data[w as usize * self.stride..(w as usize + 1) * self.stride]
    }

    /// A_w(p, s) with s the weighted values of wedge `at`.
    fn eval(&self, w: u32, p: DVec3, at: u32) -> f64 {
        let q = self.quadric(w);
        let s = &self.channels.values[at as usize * self.k..(at as usize + 1) * self.k];
        let (head, per_channel) = q.split_at(PER_CHANNEL);
        let h: &[f64; PER_CHANNEL] = head.try_into().expect("a quadric's fixed part");
        let [x, y, z] = p.to_array();
        let mut e = h[GG] * x * x
            + h[GG + 1] * 2.0 * x * y
            + h[GG + 2] * 2.0 * x * z
            + h[GG + 3] * y * y
            + h[GG + 4] * 2.0 * y * z
            + h[GG + 5] * z * z
            + 2.0 * (h[GD] * x + h[GD + 1] * y + h[GD + 2] * z)
            + h[DD];
        for (c, &s) in per_channel.chunks_exact(4).zip(s) {
            let lin = c[0] * x + c[1] * y + c[2] * z + c[3];
            e += s * s * h[AREA] - 2.0 * s * lin;
        }
        e.max(0.0)
    }

    /// The distinct (wedge of u, wedge of v) pairs of collapse `c` (u → v), by
    /// [`constraints::wedge_map`] (identity wedges give (u, v)), and how many there are: what
    /// the collapse costs ([`AttributeQuadrics::cost`]) and what it adds to which wedge
    /// ([`AttributeQuadrics::merge`], read before the collapse edits the connectivity).
    pub fn merges(mesh: &Mesh, c: HalfEdgeCollapse, v: u32) -> ([(u32, u32); 2], usize) {
        if mesh.wedges.is_identity() {
            return ([(c.remove, v), (INVALID, INVALID)], 1);
        }
        let (hu, hv) = constraints::halves(&mesh.topology, c);
        Self::distinct(constraints::wedge_map(mesh, hu, hv))
    }

    /// The distinct pairs of a wedge map (one side `INVALID` on a border), first, and how
    /// many there are.
    pub fn distinct([a, b]: [(u32, u32); 2]) -> ([(u32, u32); 2], usize) {
        match (a.0 != INVALID, b.0 != INVALID) {
            (true, true) if a != b => ([a, b], 2),
            (true, _) => ([a, b], 1),
            (false, _) => ([b, a], usize::from(b.0 != INVALID)),
        }
    }

    /// The attribute part of collapse `c`'s cost (see the module docs).
    pub fn cost(&self, mesh: &Mesh, c: HalfEdgeCollapse, v: u32) -> f64 {
        let pv = DVec3::from(mesh.positions[v as usize].map(f64::from));
        let (pairs, n) = Self::merges(mesh, c, v);
        self.cost_of(&pairs[..n], pv)
    }

    /// The attribute part of a collapse into a vertex at `pv` whose distinct wedge pairs
    /// ([`AttributeQuadrics::distinct`]) are `pairs`.
    pub fn cost_of(&self, pairs: &[(u32, u32)], pv: DVec3) -> f64 {
        self.cost_with(pairs, pv, |wv| self.eval(wv, pv, wv))
    }

    /// [`AttributeQuadrics::cost_of`] with each target wedge's own term read from `own`
    /// ([`AttributeQuadrics::own_cost`] of every wedge, kept up to date by the caller): the
    /// same bits, as a wedge of v sits at v.
    pub fn cost_of_kept(&self, pairs: &[(u32, u32)], pv: DVec3, own: &[f64]) -> f64 {
        self.cost_with(pairs, pv, |wv| own[wv as usize])
    }

    fn cost_with(&self, pairs: &[(u32, u32)], pv: DVec3, own: impl Fn(u32) -> f64) -> f64 {
        let mut e = 0.0;
        for (i, &(wu, wv)) in pairs.iter().enumerate() {
            e += self.eval(wu, pv, wv);
            if !pairs[..i].iter().any(|&(_, seen)| seen == wv) {
                e += own(wv);
            }
        }
        e
    }

    /// A_w at its own vertex with its own values: what a collapse onto w adds for w itself.
    pub fn own_cost(&self, mesh: &Mesh, w: u32) -> f64 {
        let v = mesh.wedges.vertex_of(w);
        self.eval(w, DVec3::from(mesh.positions[v as usize].map(f64::from)), w)
    }

    /// A_into += A_from for each pair.
    pub fn merge(&mut self, pairs: &[(u32, u32)]) {
        for &(from, into) in pairs {
            if from == into {
                continue;
            }
            let s = self.stride;
            let (f, t) = (from as usize * s, into as usize * s);
            for i in 0..s {
                self.data[t + i] += self.data[f + i];
            }
        }
    }
}

/// Adds channel `c`'s face term area · (g·p + d − s_c)² to `q`.
fn add_channel(q: &mut [f64], c: usize, g: DVec3, d: f64, area: f64) {
    let [x, y, z] = (g * area).to_array();
    let [gx, gy, gz] = g.to_array();
    for (i, v) in [x * gx, x * gy, x * gz, y * gy, y * gz, z * gz].into_iter().enumerate() {
        q[GG + i] += v;
    }
    q[GD] += x * d;
    q[GD + 1] += y * d;
    q[GD + 2] += z * d;
    q[DD] += area * d * d;
    let o = PER_CHANNEL + 4 * c;
    q[o] += x;
    q[o + 1] += y;
    q[o + 2] += z;
    q[o + 3] += area * d;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::VertexAttribute;
    use crate::{procedural, BuildOptions, IndexedMesh};

    /// A grid coloured by a linear ramp: every face interpolates the same plane, so moving
    /// any wedge to any other point with the ramp's value there costs nothing, and off the
    /// ramp the cost is the area times the squared colour difference.
    #[test]
    fn a_linear_ramp_costs_nothing_along_itself() {
        let mut g: IndexedMesh = procedural::grid(4, 4, |_, _| false);
        let ramp: Vec<f32> = g.positions.iter().flat_map(|p| [0.1 + 0.2 * p[0], 0.5, 0.3 - 0.1 * p[1]]).collect();
        g.attributes.push(VertexAttribute::new("COLOR_0", 3, ramp));
        let mesh = Mesh::build(&g, BuildOptions::default()).unwrap();
        let weights = AttributeWeights { color: 1.0, ..Default::default() };
        let q = AttributeQuadrics::new(&mesh, &weights).unwrap();
        assert_eq!(q.k, 3);
        let area: f64 = q.quadric(6)[AREA];
        assert!(area > 0.0);
        for w in 0..mesh.wedges.len() as u32 {
            for at in 0..mesh.wedges.len() as u32 {
                let p = DVec3::from(mesh.positions[at as usize].map(f64::from));
                let e = q.eval(w, p, at);
                assert!(e < 1e-9, "wedge {w} at {at}: {e}");
            }
        }
        // Off the ramp: wedge 6's own position with another wedge's colour.
        let p6 = DVec3::from(mesh.positions[6].map(f64::from));
        let (a, b) = (&q.channels.values[6 * 3..7 * 3], &q.channels.values[0..3]);
        let d2: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
        let e = q.eval(6, p6, 0);
        assert!((e - area * d2).abs() <= 1e-9 * e.max(1.0), "{e} vs {}", area * d2);
    }

    #[test]
    fn weights_parse_and_refuse() {
        assert_eq!(AttributeWeights::parse("0.5").unwrap(), AttributeWeights::all(0.5));
        let w = AttributeWeights::parse("normal=0.5,colour=2").unwrap();
        assert_eq!(w, AttributeWeights { normal: 0.5, color: 2.0, ..Default::default() });
        assert!(AttributeWeights::parse("normal=-1").unwrap_err().contains("non-negative"));
        assert!(AttributeWeights::parse("shine=1").unwrap_err().contains("unknown attribute kind"));
        assert!(AttributeWeights::parse("nan").is_err());
        assert!(!AttributeWeights::default().any());
    }
}
