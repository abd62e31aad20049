//! MikkTSpace tangents for normal mapping (the `bevy_mikktspace` crate), one per vertex: corners
//! that share a vertex get the normalised sum of their tangents (MikkTSpace would split such
//! a vertex where the tangents disagree; on smooth UV layouts they agree).
use crate::model::Mesh;

struct Geometry<'a> {
    mesh: &'a Mesh,
    sum: Vec<[f32; 4]>,
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.vertices[self.mesh.indices[face * 3 + vert] as usize].position
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.vertices[self.mesh.indices[face * 3 + vert] as usize].normal
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.mesh.vertices[self.mesh.indices[face * 3 + vert] as usize].uv
    }
    fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        let Some(t) = t else { return };
        let t = t.tangent_encoded();
        let s = &mut self.sum[self.mesh.indices[face * 3 + vert] as usize];
        for i in 0..3 {
            s[i] += t[i];
        }
        // The handedness of the last corner wins; mirrored UVs across one vertex are rare.
        s[3] = t[3];
    }
}

/// Tangents (xyz unit, w = ±1 bitangent sign) for every vertex of `mesh`; vertices whose
/// tangent cannot be made (no UV area) get (1, 0, 0, 1).
pub fn generate(mesh: &Mesh) -> Vec<[f32; 4]> {
    let mut g = Geometry {
        mesh,
        sum: vec![[0.0; 4]; mesh.vertices.len()],
    };
    // A mesh without UV area gets no tangents; the fallback below covers it.
    let _ = bevy_mikktspace::generate_tangents(&mut g);
    g.sum
        .into_iter()
        .map(|[x, y, z, w]| {
            let len = (x * x + y * y + z * z).sqrt();
            if len > 1e-12 && len.is_finite() {
                [x / len, y / len, z / len, if w < 0.0 { -1.0 } else { 1.0 }]
            } else {
                [1.0, 0.0, 0.0, 1.0]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Vertex;

    #[test]
    fn a_quad_in_xy_has_tangent_along_u() {
        let v = |x: f32, y: f32| Vertex {
            position: [x, y, 0.0],
            normal: [0.0, 0.0, 1.0],
            uv: [x, y],
        };
        let mesh = Mesh {
            vertices: vec![v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)],
            indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        };
        for t in generate(&mesh) {
            assert!((t[0] - 1.0).abs() < 1e-5 && t[1].abs() < 1e-5, "{t:?}");
            assert_eq!(t[3], 1.0);
        }
    }
}
