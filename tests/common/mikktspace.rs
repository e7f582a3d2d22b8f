//! The reference MikkTSpace (`bevy_mikktspace`, a port of Mikkelsen's C) run on a mesh, and
//! a mesh's `TANGENT` held against it corner by corner.

use dynlod::IndexedMesh;

struct Corners<'a> {
    m: &'a IndexedMesh,
    out: Vec<Option<[f32; 4]>>,
}

impl bevy_mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.m.triangles.len()
    }
    fn num_vertices_of_face(&self, _: usize) -> usize {
        3
    }
    fn position(&self, f: usize, v: usize) -> [f32; 3] {
        self.m.positions[self.m.triangles[f][v] as usize]
    }
    fn normal(&self, f: usize, v: usize) -> [f32; 3] {
        self.m.normals[self.m.triangles[f][v] as usize]
    }
    fn tex_coord(&self, f: usize, v: usize) -> [f32; 2] {
        self.m.uvs[self.m.triangles[f][v] as usize]
    }
    fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, f: usize, v: usize) {
        self.out[3 * f + v] = t.map(|t| t.tangent_encoded()).filter(|t| t[..3] != [0.0; 3]);
    }
}

/// How `m`'s `TANGENT` compares with the reference at every corner where the reference has
/// a frame: (corners compared, corners without a reference frame, the largest angle in
/// degrees over all but `skip` worst corners, corners whose handedness differs).
pub fn against_reference(m: &IndexedMesh, skip: usize) -> (usize, usize, f64, usize) {
    let ours = m.attributes.iter().find(|a| a.semantic == "TANGENT").expect("a TANGENT attribute");
    let mut c = Corners { m, out: vec![None; 3 * m.triangles.len()] };
    bevy_mikktspace::generate_tangents(&mut c).unwrap();
    let (mut angles, mut none, mut handedness) = (Vec::new(), 0, 0);
    for (k, reference) in c.out.iter().enumerate() {
        let Some(r) = reference else {
            none += 1;
            continue;
        };
        let a = ours.get(m.triangles[k / 3][k % 3] as usize);
        let dot: f64 = (0..3).map(|i| f64::from(a[i]) * f64::from(r[i])).sum();
        let length = (0..3).map(|i| f64::from(a[i]).powi(2)).sum::<f64>().sqrt()
            * (0..3).map(|i| f64::from(r[i]).powi(2)).sum::<f64>().sqrt();
        angles.push((dot / length).clamp(-1.0, 1.0).acos().to_degrees());
        handedness += usize::from(a[3] != r[3]);
    }
    angles.sort_by(f64::total_cmp);
    let worst = angles.len().checked_sub(skip + 1).map_or(0.0, |i| angles[i]);
    (angles.len(), none, worst, handedness)
}
