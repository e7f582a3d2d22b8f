//! Procedural meshes for tests, examples and benchmarks: exact, small, and free of any file.
//! Each returns an [`IndexedMesh`] with counter-clockwise (outward) winding.

use std::f32::consts::TAU;

use crate::mesh::IndexedMesh;

/// A regular tetrahedron: 4 vertices, 4 faces, closed, genus 0.
pub fn tetrahedron() -> IndexedMesh {
    IndexedMesh::from_triangles(
        vec![[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]],
        vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    )
}

/// An axis-aligned cube from `-half` to `+half` on every axis: 8 vertices, 12 triangles.
pub fn cube(half: f32) -> IndexedMesh {
    let h = half;
    let positions = (0..8)
        .map(|i| [if i & 1 == 0 { -h } else { h }, if i & 2 == 0 { -h } else { h }, if i & 4 == 0 { -h } else { h }])
        .collect();
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    IndexedMesh::from_triangles(positions, triangles)
}

/// A regular octahedron with its vertices on the unit axes.
pub fn octahedron() -> IndexedMesh {
    let positions =
        vec![[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    let triangles = vec![[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
    IndexedMesh::from_triangles(positions, triangles)
}

/// A flat `w` × `h` grid of quads in the XY plane (2·w·h triangles), an open disk. `flip`
/// picks each quad's diagonal, for irregular connectivity.
pub fn grid(w: usize, h: usize, flip: impl Fn(usize, usize) -> bool) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    for j in 0..=h {
        for i in 0..=w {
            m.positions.push([i as f32, j as f32, 0.0]);
        }
    }
    let id = |i: usize, j: usize| (j * (w + 1) + i) as u32;
    for j in 0..h {
        for i in 0..w {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if flip(i, j) {
                m.triangles.push([a, b, d]);
                m.triangles.push([b, c, d]);
            } else {
                m.triangles.push([a, b, c]);
                m.triangles.push([a, c, d]);
            }
        }
    }
    m
}

/// [`grid`] with texture coordinates (i/w, j/h) and a UV seam cut in from the left border
/// along row `h / 2`, ending inside at column `cut` (clamped to 1..w−1), like a dart in a
/// texture layout: the vertices left of the end are split, the copies above the cut mapping
/// 0.1·(cut − i)/cut higher in v (the gap closes at the end). The end vertex has one wedge
/// and one seam edge (a seam's end); the cut's border vertex is where the seam meets the
/// border. For `h` ≥ 2 and `w` ≥ 2.
pub fn cut_grid(w: usize, h: usize, cut: usize, flip: impl Fn(usize, usize) -> bool) -> IndexedMesh {
    let mut m = grid(w, h, &flip);
    let (row, cut) = (h / 2, cut.clamp(1, w.saturating_sub(1).max(1)));
    m.uvs = m.positions.iter().map(|p| [p[0] / w as f32, p[1] / h as f32]).collect();
    let id = |i: usize, j: usize| (j * (w + 1) + i) as u32;
    let copies: Vec<(u32, u32)> = (0..cut)
        .map(|i| {
            let copy = m.positions.len() as u32;
            m.positions.push(m.positions[id(i, row) as usize]);
            let [u, v] = m.uvs[id(i, row) as usize];
            m.uvs.push([u, v + 0.1 * (cut - i) as f32 / cut as f32]);
            (id(i, row), copy)
        })
        .collect();
    // The quads of row `row` lie just above the cut: 2 triangles each, in grid order.
    for t in &mut m.triangles[2 * row * w..2 * (row + 1) * w] {
        for v in t.iter_mut() {
            if let Some(&(_, copy)) = copies.iter().find(|&&(orig, _)| orig == *v) {
                *v = copy;
            }
        }
    }
    m
}

/// A torus of `rings` × `sides` quads (closed, genus 1), radii 1 and 0.3.
pub fn torus(rings: usize, sides: usize) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    for i in 0..rings {
        let (su, cu) = (i as f32 / rings as f32 * TAU).sin_cos();
        for j in 0..sides {
            let (sv, cv) = (j as f32 / sides as f32 * TAU).sin_cos();
            let r = 1.0 + 0.3 * cv;
            m.positions.push([r * cu, r * su, 0.3 * sv]);
        }
    }
    let id = |i: usize, j: usize| ((i % rings) * sides + j % sides) as u32;
    for i in 0..rings {
        for j in 0..sides {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m
}

/// A UV sphere with a texture seam along one meridian and split poles, the way exporters
/// write it: positions repeat at the seam with different UVs, normals are smooth.
/// Welded, it is a closed genus-0 surface.
pub fn uv_sphere(stacks: usize, slices: usize) -> IndexedMesh {
    let mut m = IndexedMesh::default();
    for i in 0..=stacks {
        let theta = i as f32 / stacks as f32 * std::f32::consts::PI;
        for j in 0..=slices {
            let phi = j as f32 / slices as f32 * TAU;
            let p = if i == 0 {
                [0.0, 0.0, 1.0]
            } else if i == stacks {
                [0.0, 0.0, -1.0]
            } else if j == slices {
                [theta.sin(), 0.0, theta.cos()] // exactly the j == 0 position
            } else {
                [theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()]
            };
            m.positions.push(p);
            m.normals.push(p);
            m.uvs.push([j as f32 / slices as f32, i as f32 / stacks as f32]);
        }
    }
    let id = |i: usize, j: usize| (i * (slices + 1) + j) as u32;
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if i != 0 {
                m.triangles.push([a, b, d]);
            }
            if i != stacks - 1 {
                m.triangles.push([b, c, d]);
            }
        }
    }
    m
}
