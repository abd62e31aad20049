//! Which scene meshes are drawn instanced: the written-out copies of an
//! `EXT_mesh_gpu_instancing` node ([`crate::scene::Instancing`]) become one draw mesh, the
//! first copy, drawn once per instance, where the context has instanced arrays (GL 3.3,
//! ES 3.0). GL 2.1 draws the copies as they are; so does any context for a translucent
//! material (translucent meshes are sorted back to front one by one, which one instanced draw
//! cannot be) and for nodes whose copies cannot share a mesh. What the two paths share: the
//! scene (every copy, for bounds, the reference, `--check`, edges and picking), the programs
//! (one `INSTANCED` define in the vertex stage), the passes and the frustum culling (instance
//! by instance, by each copy's sphere, as the copies are: a view sends only the instances it
//! may see); what differs: the GPU holds one copy plus 64 bytes an instance instead of every
//! copy, and there is no cluster culling inside an instance.
use crate::gpu::instances::Instances;
use crate::gpu::GpuRef;
use crate::scene::lod::clusters::ClusterView;
use crate::scene::Scene;
use glam::Vec3;

/// What a scene mesh is on the GPU ([`plan`]).
pub(crate) enum Role {
    /// Its own draw mesh.
    Own,
    /// Drawn as one instance of another (`Resident::Absorbed` in upload.rs).
    Absorbed,
    /// The first copy of an instanced mesh, drawn once per matrix (instance `k`'s local
    /// coordinates from this copy's), and the scene meshes of every copy (for the bounds).
    Head(Copies),
}

/// An instanced mesh's copies: the relative matrices and the scene meshes, in instance order.
pub(crate) struct Copies {
    pub(crate) matrices: Vec<glam::Mat4>,
    pub(crate) meshes: Vec<usize>,
}

/// An instanced mesh's matrices on the GPU and each instance's bounding sphere (local
/// coordinates), by which a view culls instance by instance as it would the copies.
pub(crate) struct InstancedDraw {
    pub(crate) gpu: Instances,
    pub(crate) spheres: Vec<(Vec3, f32)>,
}

/// The instances of `draw` whose spheres touch `view`'s frustum, in order.
pub(crate) fn visible(draw: &InstancedDraw, view: &ClusterView) -> Vec<u32> {
    (0..draw.spheres.len() as u32)
        .filter(|&k| {
            let (c, r) = draw.spheres[k as usize];
            !view.outside(c, r)
        })
        .collect()
}

/// Each scene mesh's role on the GPU.
pub(crate) fn plan(gpu: &GpuRef, scene: &Scene) -> Vec<Role> {
    let n = scene.meshes.count();
    let mut roles: Vec<Role> = (0..n).map(|_| Role::Own).collect();
    if !gpu.caps.instancing {
        return roles;
    }
    for run in scene.instancing.iter().filter(|r| r.shareable()) {
        let copies_of = |j: usize| -> Vec<usize> {
            (0..run.count)
                .map(|k| run.first + k * run.per_instance + j)
                .collect()
        };
        for j in 0..run.per_instance {
            let meshes = copies_of(j);
            if meshes.iter().any(|&i| i >= n) {
                continue;
            }
            let material = &scene.materials[scene.meshes[meshes[0]].material];
            if material.is_translucent() {
                continue;
            }
            for &i in &meshes[1..] {
                roles[i] = Role::Absorbed;
            }
            let head = meshes[0];
            roles[head] = Role::Head(Copies {
                matrices: run.relative.clone(),
                meshes,
            });
        }
    }
    roles
}

/// Each copy's bounding sphere (local coordinates, instance order) and one sphere holding
/// them all, for the instanced draw's culling.
pub(crate) fn spheres(scene: &Scene, copies: &Copies) -> (Vec<(Vec3, f32)>, (Vec3, f32)) {
    let spheres: Vec<(Vec3, f32)> = copies
        .meshes
        .iter()
        .map(|&c| crate::scene::bounding_sphere(&scene.meshes[c].vertices))
        .collect();
    let all = enclosing(&spheres);
    (spheres, all)
}

/// A sphere holding every sphere (centre of their box, farthest reach from it).
fn enclosing(spheres: &[(Vec3, f32)]) -> (Vec3, f32) {
    let mut b = crate::scene::Bounds::empty();
    for &(c, r) in spheres {
        b.include(c - Vec3::splat(r));
        b.include(c + Vec3::splat(r));
    }
    let center = b.center();
    let radius = spheres
        .iter()
        .map(|&(c, r)| (c - center).length() + r)
        .fold(0.0f32, f32::max);
    (center, radius)
}

#[cfg(test)]
mod tests {
    use super::enclosing;
    use glam::Vec3;

    #[test]
    fn the_enclosing_sphere_holds_every_sphere() {
        let s = [
            (Vec3::new(-3.0, 0.0, 0.0), 1.0),
            (Vec3::new(4.0, 1.0, 0.0), 0.5),
            (Vec3::new(0.0, 0.0, 2.0), 2.0),
        ];
        let (c, r) = enclosing(&s);
        for (sc, sr) in s {
            assert!(
                (sc - c).length() + sr <= r + 1e-6,
                "{sc} {sr} outside {c} {r}"
            );
        }
    }
}
