//! A scene whose meshes move: the renderer poses its scene at a moment ([`Scene::pose`],
//! on the CPU) and uploads again only the meshes the pose rewrote, with what depends on
//! their triangles made anew (bounding spheres, clusters, terminator lift, tangents), the
//! edge lines dropped, and the shadow maps drawn again where the moved meshes were and are
//! ([`super::shadow_rect`]). A pose draws what a fresh
//! renderer of the posed scene draws, byte for byte: the same upload code runs on the same
//! vertices. The meshes a rig poses never get clusters ([`crate::scene::lod::clusters::prepare`]
//! skips them): their triangles move every frame, and a cluster's bounds would not.
//! Meshes skinned on the GPU ([`super::skinning`]) are not posed on the CPU or uploaded: a
//! pose sets their skins' joint matrices and bounds them by the animation's framing bounds.
use super::instancing::Role;
use super::upload::{instanced_head, whole_draw_mesh_into, SceneGpu};
use super::Renderer;
use crate::scene::lod::clusters::{Clusters, MIN_TRIANGLES};
use crate::scene::motion::Moment;
use crate::scene::{Bounds, Scene};
use crate::Result;
use glam::Vec3;

/// What the last pose that changed the scene cost: the CPU pose ([`Scene::pose`]) and the
/// upload of the meshes it rewrote, apart (`glview bench --motion` prints both).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PoseCost {
    pub pose_ms: f64,
    pub upload_ms: f64,
    /// Meshes uploaded again.
    pub meshes: usize,
    /// Bytes of vertex and index data uploaded again.
    pub bytes: u64,
    /// Meshes skinned on the GPU (their joint matrices set, nothing uploaded).
    pub skinned: usize,
}

impl Renderer {
    /// Poses the scene at `moment` (None: the static pose) and uploads the meshes the pose
    /// rewrote; nothing when the scene is already at that moment (a kept renderer drawing
    /// the same moment again costs nothing).
    pub fn pose(&mut self, moment: Option<Moment>) -> Result<()> {
        if self.posed == moment {
            return Ok(());
        }
        let t = crate::clock::Mark::now();
        let bounds = self.scene.scene.bounds;
        let since = self.scene.scene.posed;
        let gpu = std::mem::take(&mut self.scene.skins.meshes);
        let changed = self.scene.scene.pose_except(moment, &gpu);
        self.scene.skins.meshes = gpu;
        let changed = changed?;
        let wire_moved =
            (self.scene.scene.motion.as_ref()).is_some_and(|r| r.wire_may_move(since, moment));
        if !self.scene.skins.meshes.is_empty() {
            let joints = self
                .scene
                .scene
                .motion
                .as_ref()
                .map(|r| r.gpu_pose(moment))
                .unwrap_or_default();
            let bounds = moment.map(|_| self.scene.scene.bounds);
            let was = self.boxes_were(&self.scene.skins.meshes);
            self.scene.pose_skins(moment, joints, bounds.as_ref());
            // The light views see them move; `--edges` lines are posed on the CPU.
            for (i, was) in was {
                let now = bounds.unwrap_or_else(|| self.draws_within(i, None));
                self.mark_moved(i, &was, now);
            }
            self.res.edges = Default::default();
        }
        let pose_ms = ms(t);
        // The shadow maps are fitted to the scene's bounds, which a pose may change (the
        // animation's framing) even where no mesh moved; and a cut-out (MASK) material's
        // animated alpha changes what casts a shadow.
        let materials = (self.scene.scene.motion.as_ref())
            .is_some_and(|r| r.materials_may_change(since, moment));
        if self.scene.scene.bounds != bounds || materials {
            self.res.shadow.invalidate();
        }
        // A failed upload leaves the scene posed but the GPU not: the next call poses again.
        self.posed = None;
        let before = self.scene.uploaded.get();
        let t = crate::clock::Mark::now();
        let uploaded = self
            .refresh_meshes(&changed)
            .and_then(|()| match wire_moved {
                true => self.scene.refresh_wire(),
                false => Ok(()),
            });
        if uploaded.is_err() {
            // The next pose starts over from the loaded scene's standing: every part is
            // placed and uploaded again, not only those the two moments' animations move.
            self.scene.scene.posed = None;
        }
        uploaded?;
        self.gpu.finish();
        self.pose_cost = PoseCost {
            pose_ms,
            upload_ms: ms(t),
            meshes: changed.len(),
            bytes: self.scene.uploaded.get() - before,
            skinned: self.scene.skins.meshes.len(),
        };
        self.posed = moment;
        Ok(())
    }

    /// The moment the scene is posed at (None: the static pose).
    pub fn posed(&self) -> Option<Moment> {
        self.posed
    }

    /// What the last pose that changed something cost.
    pub fn pose_cost(&self) -> PoseCost {
        self.pose_cost
    }

    /// The scene, to change its meshes' vertices in place; [`Renderer::refresh_meshes`]
    /// then uploads the ones changed (nothing is drawn from the change before that).
    pub fn scene_mut(&mut self) -> &mut Scene {
        &mut self.scene.scene
    }

    /// Uploads the scene's lines and points again after their positions (or normals)
    /// changed in place ([`Renderer::scene_mut`]); [`Renderer::pose`] does it itself when
    /// a pose moves them.
    pub fn refresh_wire(&mut self) -> Result<()> {
        self.scene.refresh_wire()
    }

    /// Uploads scene meshes `meshes` again after their vertices (and possibly their count
    /// and indices) changed: their buffers, bounding spheres and clusters are made anew as
    /// a fresh renderer makes them, the edge lines are made again at the next frame, and
    /// the shadow maps drawn again there over the meshes' old and new places. A copy drawn
    /// as an instance of another mesh refreshes that mesh.
    pub fn refresh_meshes(&mut self, meshes: &[usize]) -> Result<()> {
        if meshes.is_empty() {
            return Ok(());
        }
        let n = self.scene.scene.meshes.count();
        if let Some(&bad) = meshes.iter().find(|&&i| i >= n) {
            return Err(crate::Error::Unsupported(format!(
                "mesh {bad}: no such mesh to upload again (the scene has {n})"
            )));
        }
        // A mesh skinned on the GPU whose vertices the caller rewrote draws them: it leaves
        // the GPU path (a later pose poses it on the CPU).
        self.scene.skins.meshes.retain(|i| !meshes.contains(i));
        let roles = (!self.scene.scene.instancing.is_empty())
            .then(|| super::instancing::plan(&self.gpu, &self.scene.scene));
        let mut todo: Vec<usize> = meshes
            .iter()
            .map(|&i| head_of(roles.as_deref(), i))
            .collect();
        todo.sort_unstable();
        todo.dedup();
        let was = self.boxes_were(&todo);
        for (i, was) in was {
            let role = roles.as_ref().map(|r| &r[i]);
            refresh_one(&mut self.scene, i, role)?;
            if !matches!(role, Some(Role::Absorbed)) {
                let now = self.draws_within(i, role);
                self.mark_moved(i, &was, now);
            }
        }
        self.gpu.check_error("refresh meshes")?;
        // Edge lines are made from the triangles on the first frame that asks.
        self.res.edges = Default::default();
        Ok(())
    }
}

impl Renderer {
    /// Where draw meshes `meshes` were last drawn, before they move.
    fn boxes_were(&self, meshes: &[usize]) -> Vec<(usize, Bounds)> {
        meshes
            .iter()
            .map(|&i| {
                let sphere = self
                    .scene
                    .meshes
                    .get(i)
                    .map_or((Vec3::ZERO, f32::INFINITY), |d| (d.center, d.radius));
                (i, self.res.shadow.boxes.was(i, sphere))
            })
            .collect()
    }

    /// The box holding what draw mesh `i` draws now (its vertices; an instanced head's,
    /// every copy's).
    fn draws_within(&self, i: usize, role: Option<&Role>) -> Bounds {
        let scene = &self.scene.scene;
        let of = |m: usize| {
            let vertices = &scene.meshes[m].vertices;
            Bounds::around(vertices.iter().map(|v| Vec3::from(v.position)))
        };
        match role {
            Some(Role::Head(copies)) => copies
                .meshes
                .iter()
                .fold(Bounds::empty(), |b, &m| b.union(&of(m))),
            _ => of(i),
        }
    }

    /// Draw mesh `i` moved from box `was` to box `now`: the shadow maps are drawn again
    /// over both at the next frame ([`super::shadow_rect`]).
    fn mark_moved(&mut self, i: usize, was: &Bounds, now: Bounds) {
        self.res.shadow.moved(&was.union(&now));
        self.res.shadow.boxes.is(i, now);
    }
}

/// The draw mesh that draws scene mesh `i`: its own, or the head of its instances.
fn head_of(roles: Option<&[Role]>, i: usize) -> usize {
    let Some(roles) = roles else { return i };
    roles
        .iter()
        .position(|r| matches!(r, Role::Head(c) if c.meshes.contains(&i)))
        .unwrap_or(i)
}

/// Uploads draw mesh `i` again (its role as [`super::instancing::plan`] gives it; None:
/// its own), with clusters made anew where it had some and is not posed by the rig.
fn refresh_one(scene: &mut SceneGpu, i: usize, role: Option<&Role>) -> Result<()> {
    let (dm, bytes) = match role {
        Some(Role::Absorbed) => return Ok(()),
        Some(Role::Head(copies)) => instanced_head(&scene.gpu, &scene.scene, i, copies)?,
        Some(Role::Own) | None => {
            let clusters = if scene.meshes[i].clusters.is_some() {
                clusters_again(&mut scene.scene, i)
            } else {
                None
            };
            // Its buffers are rewritten in place where the sizes allow (a pose of a mesh
            // whose vertex count stays): no GL objects made and deleted per frame.
            let old = std::mem::replace(&mut scene.meshes[i], super::upload::absorbed());
            whole_draw_mesh_into(&scene.gpu, &scene.scene, i, clusters, Some(old))?
        }
    };
    scene.meshes[i] = dm;
    scene.uploaded.set(scene.uploaded.get() + bytes);
    Ok(())
}

/// Mesh `i`'s clusters for its new vertices, as [`crate::scene::lod::clusters::prepare`] makes
/// them (reordered, without levels: a picture that draws levels builds them first); None
/// for a mesh the rig poses or one now too small.
fn clusters_again(scene: &mut Scene, i: usize) -> Option<Clusters> {
    if scene.mesh_moves(i) {
        return None;
    }
    let m = &mut scene.meshes[i];
    (m.triangle_count() >= MIN_TRIANGLES).then(|| {
        crate::scene::lod::clusters::reorder(&m.vertices, &mut m.indices);
        Clusters::build(&m.vertices, &m.indices)
    })
}

fn ms(t: crate::clock::Mark) -> f64 {
    t.ms()
}

impl SceneGpu {
    /// Sets the joint matrices of `moment` and bounds the GPU-skinned meshes by `bounds`
    /// (the animation's framing bounds: every moment of it lies inside).
    pub(crate) fn pose_skins(
        &mut self,
        moment: Option<Moment>,
        (joints, weights): (Vec<Vec<glam::Mat4>>, Vec<Vec<f32>>),
        bounds: Option<&crate::scene::Bounds>,
    ) {
        self.skins.joints = joints;
        self.skins.weights = weights;
        self.skins.moment = moment;
        for &i in &self.skins.meshes {
            let (center, radius) = match bounds {
                Some(b) => super::skinning::framing_sphere(b),
                None => crate::scene::bounding_sphere(&self.scene.meshes[i].vertices),
            };
            if let Some(dm) = self.meshes.get_mut(i) {
                dm.center = center;
                dm.radius = radius;
            }
        }
    }
}

impl SceneGpu {
    /// The GPU-skinned meshes posed on the CPU at the renderer's moment, for what is made
    /// from triangles on the CPU (`--edges` lines): none at the static pose, which the scene
    /// meshes hold.
    pub(crate) fn cpu_posed_skins(&self) -> Result<Vec<(usize, crate::scene::Mesh)>> {
        let (Some(moment), Some(rig)) = (self.skins.moment, self.scene.motion.as_ref()) else {
            return Ok(Vec::new());
        };
        let others: Vec<usize> = rig
            .meshes()
            .iter()
            .copied()
            .filter(|i| self.skins.meshes.binary_search(i).is_err())
            .collect();
        // `rig.meshes()` is sorted, so its filtered part is too.
        Ok(rig.posed_meshes_except(Some(moment), &others)?)
    }
}
