//! Nodes that stretch or shear their mesh, in a kept scene: the stretch baked into a copy of
//! the mesh, the rest of the transform kept as the copy's placement (a decision beyond the
//! papers, whose runtime works in one space where a length is a length).
//!
//! A runtime's error is a length in the mesh's space, and its pixels are that length seen at
//! a distance; under a stretch a length's pixels depend on its direction, so a view cannot be
//! carried into the mesh's space ([`View::in_model_space`](crate::view::View::in_model_space)
//! refuses). Any transform's linear part L splits as L = R·P (polar decomposition): R a
//! rotation, possibly with a mirror, and P symmetric positive definite, the stretch. P is
//! baked into a copy of the mesh (positions by P, normals by P⁻¹ renormalised, tangents by P
//! renormalised; P keeps orientation, so the winding stays), and the copy is placed with R and
//! the translation: a similarity, which carries views. The nodes with the same stretch share
//! one copy, so they stay instances of one runtime.

use glam::{DMat3, DVec3, Mat4, Vec3};

use crate::io::Placement;
use crate::mesh::IndexedMesh;

/// A stretch: a symmetric positive definite 3 × 3 matrix, column-major.
pub(super) type Stretch = [[f32; 3]; 3];

/// The stretch P of `world`'s linear part L = R·P and the placement `[R | t]` that draws the
/// stretched copy where the node drew the mesh; `None` when L is singular or not finite.
pub(super) fn split(world: [[f32; 4]; 4]) -> Option<(Stretch, [[f32; 4]; 4])> {
    let l = DMat3::from_mat4(Mat4::from_cols_array_2d(&world).as_dmat4());
    if !l.is_finite() || l.determinant().abs() < 1e-30 {
        return None;
    }
    // Higham's iteration X ← (X + X⁻ᵀ) / 2 converges quadratically to R.
    let mut r = l;
    for _ in 0..64 {
        let next = 0.5 * (r + r.inverse().transpose());
        let done = (next - r).to_cols_array().iter().all(|d| d.abs() < 1e-12);
        r = next;
        if done {
            break;
        }
    }
    // P = Rᵀ L, symmetric up to rounding: symmetrised so that equal stretches compare equal.
    let p = r.transpose() * l;
    let p = 0.5 * (p + p.transpose());
    let stretch = [p.x_axis, p.y_axis, p.z_axis].map(|c| c.as_vec3().to_array());
    let col = |c: DVec3, w: f32| [c.x as f32, c.y as f32, c.z as f32, w];
    let placed = [col(r.x_axis, 0.0), col(r.y_axis, 0.0), col(r.z_axis, 0.0), world[3]];
    Some((stretch, placed))
}

/// A copy of `mesh` with `stretch` applied: positions by it, normals by its inverse,
/// renormalised, tangents (`TANGENT`) as the glTF loader transforms them.
pub(super) fn bake(mesh: &IndexedMesh, stretch: Stretch) -> IndexedMesh {
    let p = glam::Mat3::from_cols_array_2d(&stretch);
    let normal_m = p.inverse().transpose();
    let mut out = mesh.clone();
    for x in &mut out.positions {
        *x = (p * Vec3::from(*x)).to_array();
    }
    for n in &mut out.normals {
        *n = (normal_m * Vec3::from(*n)).normalize_or_zero().to_array();
    }
    for a in out.attributes.iter_mut().filter(|a| a.semantic == "TANGENT" && a.components == 4) {
        crate::io::gltf_attributes::transform_tangents(&mut a.values, Mat4::from_mat3(p));
    }
    out
}

/// The placements of one stretch: where its copy is drawn, and by which nodes.
pub(super) struct Stretched {
    pub(super) stretch: Stretch,
    pub(super) placements: Vec<Placement>,
}

/// Splits `placements` into those a view can be carried through (kept) and, per distinct
/// stretch, those drawn by a stretched copy (each with the placement that draws the copy,
/// same node). A placement no decomposition serves (singular, not finite) stays among the
/// kept, for the caller's check to refuse by name.
pub(super) fn sort(placements: &[Placement]) -> (Vec<Placement>, Vec<Stretched>) {
    let (mut kept, mut stretched) = (Vec::new(), Vec::<Stretched>::new());
    for p in placements {
        let needs = matches!(
            crate::view::check_model_matrix(p.world),
            Err(crate::view::ModelMatrixError::NotSimilarity { .. })
        );
        match needs.then(|| split(p.world)).flatten() {
            Some((stretch, world)) => {
                let placed = Placement { world, ..*p };
                match stretched.iter_mut().find(|s| bits(&s.stretch) == bits(&stretch)) {
                    Some(s) => s.placements.push(placed),
                    None => stretched.push(Stretched { stretch, placements: vec![placed] }),
                }
            }
            None => kept.push(*p),
        }
    }
    (kept, stretched)
}

fn bits(m: &Stretch) -> [u32; 9] {
    let f = m.as_flattened();
    std::array::from_fn(|k| f[k].to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mul(a: [[f32; 4]; 4], p: [[f32; 3]; 3]) -> [[f32; 3]; 3] {
        let (r, p) = (glam::Mat3::from_mat4(Mat4::from_cols_array_2d(&a)), glam::Mat3::from_cols_array_2d(&p));
        (r * p).to_cols_array_2d()
    }

    #[test]
    fn a_stretch_turned_and_moved_splits_into_its_stretch_and_a_similarity() {
        // Scale (1, 3, 0.5), then a turn of 0.7 rad about z, a mirror in x and a move.
        let (s, c) = 0.7f32.sin_cos();
        let world = [[-c, s, 0.0, 0.0], [3.0 * s, 3.0 * c, 0.0, 0.0], [0.0, 0.0, 0.5, 0.0], [4.0, 5.0, 6.0, 1.0]];
        let (stretch, placed) = split(world).unwrap();
        assert!(crate::view::check_model_matrix(placed).is_ok(), "the placement is a similarity");
        assert_eq!(placed[3], world[3]);
        let back = mul(placed, stretch);
        for k in 0..3 {
            for j in 0..3 {
                assert!((back[k][j] - world[k][j]).abs() < 1e-5, "{back:?} against {world:?}");
            }
        }
        let p = glam::Mat3::from_cols_array_2d(&stretch);
        assert!(p.determinant() > 0.0 && (p - p.transpose()).abs_diff_eq(glam::Mat3::ZERO, 1e-6));
        let singular = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
        assert!(split(singular).is_none());
    }

    #[test]
    fn baking_keeps_normals_perpendicular_to_the_surface() {
        // A face in the plane x + y = 1 with its normal; stretched by 3 along y.
        let mut m =
            IndexedMesh::from_triangles(vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 1.0]], vec![[0, 1, 2]]);
        let n = [std::f32::consts::FRAC_1_SQRT_2, std::f32::consts::FRAC_1_SQRT_2, 0.0];
        m.normals = vec![n; 3];
        let out = bake(&m, [[1.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 1.0]]);
        assert_eq!(out.positions[1], [0.0, 3.0, 0.0]);
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(out.positions[k]));
        let normal = Vec3::from(out.normals[0]);
        assert!(
            normal.dot(b - a).abs() < 1e-6 && normal.dot(c - a).abs() < 1e-6 && (normal.length() - 1.0).abs() < 1e-6
        );
    }
}
