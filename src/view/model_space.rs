//! A world-space camera carried into an object's own space, so that one runtime per mesh
//! definition serves an object drawn at any position, orientation and size.
//!
//! ```text
//!   world:  eye ────── d ──────► M·p          a runtime works in its mesh's space:
//!   model:  M⁻¹·eye ── d / s ──► p            one model unit is s world units, and its
//!                                             pixels at d / s are s times a world unit's
//! ```
//! Under a similarity (rotation, translation, uniform scale s, a mirror) distances shrink by
//! s and lengths too (an orthographic view's height with them), angles and the frustum are kept, so every pixel error the runtime works
//! out in model space is the screen's (to float rounding). A stretch or shear is refused:
//! there the screen size of an error depends on its direction, which the runtime's error (a
//! length) does not know.

use glam::{DMat3, DVec3};

use super::{Projection, View};
use crate::io::Placement;

/// How far a model matrix may be from a similarity and still count as one (relative).
const SIMILARITY_TOLERANCE: f64 = 1e-4;

/// Why a model matrix cannot carry a view into model space.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelMatrixError {
    /// An element is NaN or infinite.
    #[error("the model matrix holds a non-finite element (column {column}, row {row})")]
    NonFinite {
        /// Column of the element (the matrix is column-major).
        column: usize,
        /// Row of the element.
        row: usize,
    },
    /// The last row is not (0, 0, 0, 1): a projection, not a placement.
    #[error("the model matrix is not affine: its last row is {row:?}, not [0, 0, 0, 1]")]
    NotAffine {
        /// The last row as found.
        row: [f32; 4],
    },
    /// The matrix collapses space (a zero scale).
    #[error("the model matrix is singular: it scales by {scale}")]
    Singular {
        /// Its scale (the root mean square of its axes' lengths).
        scale: f32,
    },
    /// The axes are scaled unequally or sheared.
    #[error(
        "the model matrix is not a similarity: its axes are scaled by {scales:?} (or sheared), so an error's \
         size on screen would depend on its direction; scale the mesh's positions by that before building the \
         runtime, and pass the rest (rotation, translation, one uniform scale)"
    )]
    NotSimilarity {
        /// The lengths of the matrix's x, y and z axes.
        scales: [f32; 3],
    },
}

impl View {
    /// This view seen from the space of a mesh drawn with `model` (object → world, column-major
    /// as glTF and most engines store it: `model[column][row]`), for a
    /// [`Runtime`](crate::lod::Runtime) whose mesh is in its own space. Exact for
    /// rotations, translations, uniform scales and mirrors: every pixel error and frustum test
    /// comes out as it would on the mesh moved into the world. Refuses a stretch or a shear
    /// ([`ModelMatrixError::NotSimilarity`]: bake that part into the mesh's positions), a
    /// projection, a singular or a non-finite matrix.
    pub fn in_model_space(&self, model: [[f32; 4]; 4]) -> Result<View, ModelMatrixError> {
        let (linear, s2) = similarity(model)?;
        let translation = DVec3::new(model[3][0] as f64, model[3][1] as f64, model[3][2] as f64);
        // For a similarity L = s·Q (Q orthogonal): L⁻¹ = Lᵀ / s².
        let inverse = linear.transpose() / s2;
        let to_model = |v: [f32; 3]| inverse * DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        let eye = to_model(self.eye) - inverse * translation;
        let unit = |v: DVec3| v.normalize().as_vec3().to_array();
        // Angles are kept; an orthographic view's extent is a length, shrunk by s like all.
        let projection = match self.projection {
            Projection::Orthographic { height } => {
                Projection::Orthographic { height: (height as f64 / s2.sqrt()) as f32 }
            }
            perspective => perspective,
        };
        Ok(View {
            eye: eye.as_vec3().to_array(),
            forward: unit(to_model(self.forward)),
            up: unit(to_model(self.up)),
            projection,
            viewport: self.viewport,
        })
    }
}

/// `cameras` (world space) seen from a mesh's own space through each of `placements`
/// ([`View::in_model_space`]), into `out` (cleared first): one view per camera and
/// placement, for [`coarsen_views`](crate::lod::coarsen::coarsen_views) or
/// [`Runtime::update_views`](crate::lod::Runtime::update_views) (which count views that
/// coincide once). Refuses with the position of the first placement a camera cannot be
/// carried through.
pub fn views_through(
    cameras: &[View],
    placements: &[Placement],
    out: &mut Vec<View>,
) -> Result<(), (usize, ModelMatrixError)> {
    out.clear();
    for camera in cameras {
        for (k, p) in placements.iter().enumerate() {
            out.push(camera.in_model_space(p.world).map_err(|e| (k, e))?);
        }
    }
    Ok(())
}

/// Whether a camera can be carried through `model` into a mesh's space: what
/// [`View::in_model_space`] refuses, and it refuses nothing else, whatever the view. So a
/// placement checked once carries every camera after.
pub fn check_model_matrix(model: [[f32; 4]; 4]) -> Result<(), ModelMatrixError> {
    similarity(model).map(|_| ())
}

/// The linear part of `model` and its squared scale s², if `model` is a finite, affine,
/// non-singular similarity.
fn similarity(model: [[f32; 4]; 4]) -> Result<(DMat3, f64), ModelMatrixError> {
    for (column, c) in model.iter().enumerate() {
        if let Some(row) = c.iter().position(|x| !x.is_finite()) {
            return Err(ModelMatrixError::NonFinite { column, row });
        }
    }
    let last = [model[0][3], model[1][3], model[2][3], model[3][3]];
    if last != [0.0, 0.0, 0.0, 1.0] {
        return Err(ModelMatrixError::NotAffine { row: last });
    }
    let axis = |c: usize| DVec3::new(model[c][0] as f64, model[c][1] as f64, model[c][2] as f64);
    let linear = DMat3::from_cols(axis(0), axis(1), axis(2));
    let gram = linear.transpose() * linear;
    let s2 = (gram.x_axis.x + gram.y_axis.y + gram.z_axis.z) / 3.0;
    if s2 <= 1e-30 {
        return Err(ModelMatrixError::Singular { scale: s2.max(0.0).sqrt() as f32 });
    }
    let off = (gram - DMat3::from_diagonal(DVec3::splat(s2))).to_cols_array();
    if off.iter().any(|x| x.abs() > SIMILARITY_TOLERANCE * s2) {
        let scales = [0, 1, 2].map(|c| axis(c).length() as f32);
        return Err(ModelMatrixError::NotSimilarity { scales });
    }
    Ok((linear, s2))
}
