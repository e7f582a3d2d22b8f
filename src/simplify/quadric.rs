//! Garland–Heckbert error quadrics (SIGGRAPH 1997): each vertex carries the sum of the
//! area-weighted squared-distance forms of the planes of its faces; a half-edge collapse
//! u → v costs (Q_u + Q_v)(v) and leaves Q_v + Q_u at v. Border edges add a plane through the
//! edge perpendicular to its face, so borders keep their shape; seam edges (UV, normal or
//! colour seams, and edges between primitives) add one on each side, at half the weight, so
//! seams keep theirs and the texture layout along them (engine.rs, `SEAM_PLANE_WEIGHT`).
//!
//! The weight (total area) is carried along, so √(Q(p) / W) is an RMS distance in model
//! units: that is what `--error` bounds.

/// A symmetric 4×4 quadric in 10 coefficients, plus its accumulated weight.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quadric {
    /// xx 2xy 2xz 2xw yy 2yz 2yw zz 2zw ww: the off-diagonal terms are kept doubled, as
    /// [`Quadric::eval`] uses them. Doubling is exact in floating point, so every sum and
    /// value comes out bit for bit as with the plain terms, five multiplications sooner
    /// (the passes evaluate a quadric per edge).
    a: [f64; 10],
    w: f64,
}

impl Quadric {
    /// The quadric of plane n·x + d = 0 (n unit length), weighted by `weight`.
    pub fn plane(n: [f64; 3], d: f64, weight: f64) -> Self {
        let [x, y, z] = n;
        // (2x·y)·w is 2·((x·y)·w) exactly: doubling commutes with rounding.
        let (x2, y2, z2) = (2.0 * x, 2.0 * y, 2.0 * z);
        let a = [x * x, x2 * y, x2 * z, x2 * d, y * y, y2 * z, y2 * d, z * z, z2 * d, d * d].map(|c| c * weight);
        Self { a, w: weight }
    }

    /// Q(p) = pᵀ Q p with p = (x, y, z, 1).
    #[inline]
    pub fn eval(&self, p: [f64; 3]) -> f64 {
        let [x, y, z] = p;
        let a = &self.a;
        a[0] * x * x
            + a[1] * x * y
            + a[2] * x * z
            + a[3] * x
            + a[4] * y * y
            + a[5] * y * z
            + a[6] * y
            + a[7] * z * z
            + a[8] * z
            + a[9]
    }

    /// √(q / W) for a value q of this quadric (or of a sum with this weight): the RMS
    /// distance that value stands for.
    pub fn distance_of(q: f64, weight: f64) -> f64 {
        if weight > 0.0 {
            (q.max(0.0) / weight).sqrt()
        } else {
            0.0
        }
    }

    /// √(Q(p) / W): the RMS distance of p to the planes summed in Q.
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        Self::distance_of(self.eval(p), self.w)
    }

    /// Accumulated weight.
    pub fn weight(&self) -> f64 {
        self.w
    }
}

impl std::ops::Add for Quadric {
    type Output = Quadric;
    fn add(mut self, o: Quadric) -> Quadric {
        self += o;
        self
    }
}

impl std::ops::AddAssign for Quadric {
    fn add_assign(&mut self, o: Quadric) {
        for (a, b) in self.a.iter_mut().zip(o.a) {
            *a += b;
        }
        self.w += o.w;
    }
}
