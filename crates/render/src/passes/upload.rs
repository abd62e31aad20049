//! The scene in GPU buffers: one static mesh per scene mesh (with a tangent stream where its
//! material has a normal map, a second UV set where the file has one) and per-mesh bounds for
//! culling. Shared by every pass; textures are made on first use by the tier that reads them
//! (`textures.rs`). Where the context has instanced arrays, the written-out copies of an
//! `EXT_mesh_gpu_instancing` node ([`crate::scene::Instancing`]) become one mesh (the first
//! copy, its bounds those of every copy) drawn once per instance with a matrix each; the
//! other copies keep their draw-mesh slot, with no buffers, and are never drawn.
use super::instancing::{Copies, Role};
use crate::gpu::mesh::{GpuMesh, Primitive, Streams};
use crate::gpu::texture::Texture2d;
use crate::gpu::GpuRef;
use crate::scene::lod::clusters::Clusters;
use crate::scene::Scene;
use crate::Result;
use glam::Vec3;

pub(crate) struct DrawMesh {
    /// Its buffers: the whole mesh, or first only its whole-mesh levels.
    pub(crate) mesh: Resident,
    pub(crate) material: usize,
    pub(crate) center: Vec3,
    /// Bounding sphere radius around `center`, for frustum culling.
    pub(crate) radius: f32,
    pub(crate) triangles: u64,
    pub(crate) translucent: bool,
    pub(crate) has_uv: bool,
    pub(crate) has_tangents: bool,
    /// A second UV set (attribute 5, `HAS_UV1`).
    pub(crate) has_uv1: bool,
    /// Per-vertex colours multiply the diffuse colour (attribute 4, `HAS_COLOR`).
    pub(crate) has_colors: bool,
    /// Triangles, or the scene's lines and points (casting no shadow).
    pub(crate) primitive: Primitive,
    /// Points with normals are lit; without, drawn in their unlit colour (`UNLIT`).
    pub(crate) has_normals: bool,
    /// How far a shadow lookup rises in the terminator band (`uTerminatorLift`).
    pub(crate) terminator_lift: f32,
    /// Runs of triangles with bounds and normal cones, for meshes large enough that
    /// skipping what a pass cannot see pays ([`crate::scene::lod::clusters`]).
    pub(crate) clusters: Option<Clusters>,
    /// Drawn once per instance (`INSTANCED` programs); `triangles` counts every instance's.
    pub(crate) instances: Option<super::instancing::InstancedDraw>,
    /// Skinned on the GPU (`SKINNED` programs, [`super::skinning`]).
    pub(crate) skin: Option<super::skinning::SkinDraw>,
}

/// A mesh's buffers on the GPU.
pub(crate) enum Resident {
    /// The whole mesh, its levels after its own triangles.
    Full(GpuMesh),
    /// Only its whole-mesh levels (a mesh cache hit's compact copy), which are its index
    /// buffer's triangles from `first` on; the whole mesh is read and uploaded into `full`
    /// when a draw first needs more.
    Compact {
        levels: GpuMesh,
        first: u32,
        /// Boxed: a `GpuMesh` inline would make every draw mesh twice its size.
        full: Box<std::cell::OnceCell<GpuMesh>>,
    },
    /// A copy of an instanced mesh that another draw mesh draws as one of its instances.
    Absorbed,
}

impl DrawMesh {
    /// Replaces the levels after the mesh's own `indices` ([`GpuMesh::set_levels`]); only
    /// for a mesh uploaded whole (a compact one came with its levels).
    pub(crate) fn set_levels(&mut self, indices: &[u32], levels: &[u32]) -> Result<()> {
        match &mut self.mesh {
            Resident::Full(m) => m.set_levels(indices, levels),
            Resident::Compact { .. } | Resident::Absorbed => Ok(()),
        }
    }

    /// Translucent meshes, lines and points cast no shadow.
    pub(crate) fn casts_shadow(&self) -> bool {
        !self.translucent && self.primitive == Primitive::Triangles && !self.absorbed()
    }

    /// Draws instances `which` of an instanced mesh (a whole mesh: instanced ones never come
    /// compact).
    pub(crate) fn draw_instances(&self, which: &[u32]) {
        if let (Resident::Full(m), Some(inst)) = (&self.mesh, &self.instances) {
            // All of them is the buffer as uploaded: nothing to rewrite.
            let all = which.len() == inst.spheres.len();
            m.draw_instanced(&inst.gpu, (!all).then_some(which));
        }
    }

    /// Drawn by another draw mesh, as one of its instances: never drawn itself.
    pub(crate) fn absorbed(&self) -> bool {
        matches!(self.mesh, Resident::Absorbed)
    }

    /// Draws all of mesh `i` (its triangles, lines or points).
    pub(crate) fn draw(&self, scene: &SceneGpu, i: usize) -> Result<()> {
        match &self.mesh {
            // Its own count and primitive: lines and points have no triangles to count.
            Resident::Full(m) => {
                match &self.instances {
                    Some(inst) => m.draw_instanced(&inst.gpu, None),
                    None => m.draw(),
                }
                Ok(())
            }
            Resident::Absorbed => Ok(()),
            Resident::Compact { .. } => {
                let n = self.triangles as u32 * 3;
                self.draw_ranges(scene, i, &[(0, n)])
            }
        }
    }

    /// Draws the index ranges (first index, count) of mesh `i` (its triangles, then its
    /// levels): from its compact copy when they all lie in its whole levels, else from the
    /// whole mesh, uploaded now if it is not yet.
    pub(crate) fn draw_ranges(
        &self,
        scene: &SceneGpu,
        i: usize,
        ranges: &[(u32, u32)],
    ) -> Result<()> {
        let (levels, first, full) = match &self.mesh {
            Resident::Full(m) => {
                m.draw_ranges(ranges);
                return Ok(());
            }
            Resident::Absorbed => return Ok(()),
            Resident::Compact {
                levels,
                first,
                full,
            } => (levels, first * 3, full),
        };
        if full.get().is_none() && ranges.iter().all(|r| r.0 >= first) {
            let shifted: Vec<(u32, u32)> = ranges.iter().map(|r| (r.0 - first, r.1)).collect();
            levels.draw_ranges(&shifted);
            return Ok(());
        }
        let m = match full.get() {
            Some(m) => m,
            None => {
                let t = crate::clock::Mark::now();
                let mesh = &scene.scene.meshes[i];
                let lod = levels_read(&scene.scene, i)?;
                let mat = &scene.scene.materials[mesh.material];
                let (m, _, bytes) = upload_mesh(&scene.gpu, mesh, mat, lod)?;
                scene.uploaded.set(scene.uploaded.get() + bytes);
                scene.completed.set(scene.completed.get() + 1);
                log::debug!(
                    "mesh {i}: read and uploaded whole for a draw beyond its whole levels in {:.0} ms",
                    t.ms()
                );
                full.get_or_init(|| m)
            }
        };
        m.draw_ranges(ranges);
        Ok(())
    }
}

pub(crate) struct SceneGpu {
    pub(crate) scene: Scene,
    pub(crate) meshes: Vec<DrawMesh>,
    pub(crate) gpu: GpuRef,
    /// Bytes of vertex and index data uploaded so far (`--stats`).
    pub(crate) uploaded: std::cell::Cell<u64>,
    /// Meshes uploaded whole after a first view drew their compact copies.
    pub(crate) completed: std::cell::Cell<u32>,
    /// The meshes skinned on the GPU and their skins' joint matrices.
    pub(crate) skins: super::skinning::GpuSkins,
}

/// Makes a texture from `t`'s pixels (fitted to the driver's size limit) with `make`, and
/// records what it cost for `--stats` ([`crate::gpu::Gpu::take_texture_costs`]).
pub(crate) fn timed(
    gpu: &GpuRef,
    t: &crate::scene::Texture,
    make: impl FnOnce(u32, u32, &[u8]) -> Result<Texture2d>,
) -> Result<Texture2d> {
    // Work queued before (a frame's passes, when the PBR tier makes its textures mid-frame)
    // is not this texture's.
    gpu.finish();
    let start = crate::clock::Mark::now();
    let (w, h, rgba) = fit_texture(gpu, t)?;
    let tex = make(w, h, &rgba)?;
    // Drivers may queue the work (llvmpipe's glGenerateMipmap is a blit run at the next
    // flush): wait for it, so the cost lands on the texture that caused it.
    gpu.finish();
    gpu.record_texture(crate::gpu::TextureCost {
        name: t.path.display().to_string(),
        width: w,
        height: h,
        ms: start.ms(),
    });
    Ok(tex)
}

/// The texture's pixels, downscaled to the driver's maximum size where larger.
pub(crate) fn fit_texture<'a>(
    gpu: &GpuRef,
    t: &'a crate::scene::Texture,
) -> Result<(u32, u32, std::borrow::Cow<'a, [u8]>)> {
    let max = gpu.caps.max_texture_size.max(1);
    if t.width <= max && t.height <= max {
        return Ok((t.width, t.height, std::borrow::Cow::Borrowed(&t.rgba)));
    }
    let scale = f64::from(max) / f64::from(t.width.max(t.height));
    let (w, h) = (
        ((f64::from(t.width) * scale) as u32).clamp(1, max),
        ((f64::from(t.height) * scale) as u32).clamp(1, max),
    );
    log::warn!(
        "{}: {}x{} is larger than the driver's maximum texture size {max}: downscaled to {w}x{h}",
        t.path.display(),
        t.width,
        t.height
    );
    let img = image::RgbaImage::from_raw(t.width, t.height, t.rgba.clone()).ok_or_else(|| {
        crate::Error::Unsupported(format!("{}: bad pixel buffer", t.path.display()))
    })?;
    let small = image::imageops::resize(&img, w, h, image::imageops::FilterType::Triangle);
    Ok((w, h, std::borrow::Cow::Owned(small.into_raw())))
}

impl SceneGpu {
    /// Uploads `scene`; `clusters` are [`clusters::prepare`]'s for it (same mesh order).
    /// `gpu_skinning`: the meshes that can be are skinned on the GPU ([`super::skinning`]).
    pub(crate) fn new(
        gpu: &GpuRef,
        mut scene: Scene,
        clusters: Vec<Option<Clusters>>,
        gpu_skinning: bool,
    ) -> Result<SceneGpu> {
        let mut clusters = clusters.into_iter();
        // Lines and points are drawn with material 0; a file of only lines has none.
        if scene.materials.is_empty() {
            scene.materials.push(crate::scene::Material::default());
        }
        let mut meshes = Vec::with_capacity(scene.meshes.count());
        let mut uploaded = 0;
        let plan = super::instancing::plan(gpu, &scene);
        let (mut skins, skinned) = super::skinning::plan(gpu, &scene, gpu_skinning);
        // (A skinned mesh draws as its own: instanced copies are never skinned, and a moving
        // instanced node's copies are not shared.)
        skins
            .meshes
            .retain(|&i| matches!(plan.get(i), Some(Role::Own)));
        for (i, role) in plan.iter().enumerate() {
            // Whoever prepared them (a mesh cache entry too), a posed mesh has none.
            let c = clusters.next().flatten().filter(|_| !scene.mesh_moves(i));
            let (dm, bytes) = match role {
                Role::Own if skins.meshes.binary_search(&i).is_ok() => {
                    match skinned.binary_search_by_key(&i, |s| s.mesh) {
                        Ok(k) => skinned_mesh(gpu, &scene, &skinned[k])?,
                        Err(_) => draw_mesh(gpu, &scene, i, c)?,
                    }
                }
                Role::Own => draw_mesh(gpu, &scene, i, c)?,
                Role::Absorbed => (absorbed(), 0),
                Role::Head(copies) => instanced_head(gpu, &scene, i, copies)?,
            };
            uploaded += bytes;
            meshes.push(dm);
        }
        let (wire, bytes) = wire_meshes(gpu, &scene)?;
        meshes.extend(wire);
        uploaded += bytes;
        gpu.check_error("upload")?;
        let caps = &gpu.caps;
        if !caps.shadow_maps() {
            log::warn!(
                "{}: no depth textures or shadow compare: shadows off",
                caps.version
            );
        }
        Ok(SceneGpu {
            scene,
            meshes,
            gpu: gpu.clone(),
            uploaded: std::cell::Cell::new(uploaded),
            completed: std::cell::Cell::new(0),
            skins,
        })
    }

    /// Indices of the meshes whose bounding sphere touches the view frustum of `view_proj`:
    /// off-screen meshes cost a program bind and a draw call each for nothing.
    pub(crate) fn visible(&self, view_proj: &glam::Mat4) -> Vec<usize> {
        let view = crate::scene::lod::clusters::ClusterView::new(*view_proj);
        (0..self.meshes.len())
            .filter(|&i| {
                let m = &self.meshes[i];
                !m.absorbed() && !view.outside(m.center, m.radius)
            })
            .collect()
    }

    /// Uploads the lines and points again (a pose moved them): the draw meshes after the
    /// scene meshes are made anew, as a fresh upload makes them.
    pub(crate) fn refresh_wire(&mut self) -> Result<()> {
        let (wire, bytes) = wire_meshes(&self.gpu, &self.scene)?;
        self.meshes.truncate(self.scene.meshes.count());
        self.meshes.extend(wire);
        self.uploaded.set(self.uploaded.get() + bytes);
        self.gpu.check_error("upload lines and points")
    }

    /// Draw meshes that are drawn (every one but the copies drawn as instances).
    pub(crate) fn drawn_count(&self) -> usize {
        self.meshes.iter().filter(|m| !m.absorbed()).count()
    }
}

/// Uploads mesh `i` of `scene` as a first view draws it (its compact copy where it has
/// one, else whole, its levels after its triangles); returns it and the bytes uploaded.
fn draw_mesh(
    gpu: &GpuRef,
    scene: &Scene,
    i: usize,
    clusters: Option<Clusters>,
) -> Result<(DrawMesh, u64)> {
    use crate::scene::model::meshes::FirstView;
    let first = scene.meshes.first_view(i);
    let compact = match first {
        // Generated tangents are the whole mesh's: such a mesh is uploaded whole.
        Some(FirstView::Compact(c))
            if !(c.has_uv && scene.materials[c.material].needs_tangents()) =>
        {
            c
        }
        _ => return whole_draw_mesh(gpu, scene, i, clusters),
    };
    let mat = &scene.materials[compact.material];
    let (colors, rgba, uv1) = streams_of(
        &compact.vertices,
        &compact.colors,
        &compact.color_alpha,
        &compact.uv1,
    );
    let streams = Streams {
        tangents: None,
        colors,
        colors_rgba: rgba.as_deref(),
        uv1,
        skin: None,
        morph: &[],
        skin1: None,
    };
    let levels = GpuMesh::with_levels(
        gpu,
        &compact.vertices,
        &[],
        &compact.indices,
        streams,
        Primitive::Triangles,
    )?;
    let bytes = bytes_of(&compact.vertices, compact.indices.len(), streams);
    let dm = DrawMesh {
        mesh: Resident::Compact {
            levels,
            first: compact.first,
            full: Box::default(),
        },
        material: compact.material,
        center: Vec3::from(compact.center),
        radius: compact.radius,
        triangles: compact.triangles as u64,
        translucent: mat.is_translucent(),
        has_uv: compact.has_uv,
        has_tangents: false,
        has_uv1: uv1.is_some(),
        has_colors: colors.is_some(),
        primitive: Primitive::Triangles,
        has_normals: true,
        terminator_lift: compact.terminator_lift,
        clusters,
        instances: None,
        skin: None,
    };
    Ok((dm, bytes))
}

/// Uploads scene mesh `i`, the first of `copies`, to be drawn once per instance; returns it
/// and the bytes uploaded (one copy and the matrices).
pub(crate) fn instanced_head(
    gpu: &GpuRef,
    scene: &Scene,
    i: usize,
    copies: &Copies,
) -> Result<(DrawMesh, u64)> {
    // Clusters would cull one copy's triangles by that copy's bounds: the instanced draw is
    // culled whole instead.
    let (mut dm, bytes) = whole_draw_mesh(gpu, scene, i, None)?;
    let instances = crate::gpu::instances::Instances::new(gpu, &copies.matrices)?;
    let (spheres, (center, radius)) = super::instancing::spheres(scene, copies);
    dm.center = center;
    dm.radius = radius;
    dm.triangles *= copies.meshes.len() as u64;
    let extra = instances.bytes();
    dm.instances = Some(super::instancing::InstancedDraw {
        gpu: instances,
        spheres,
    });
    Ok((dm, bytes + extra))
}

pub(crate) fn absorbed() -> DrawMesh {
    DrawMesh {
        mesh: Resident::Absorbed,
        material: 0,
        center: Vec3::ZERO,
        radius: 0.0,
        triangles: 0,
        translucent: false,
        has_uv: false,
        has_tangents: false,
        has_uv1: false,
        has_colors: false,
        primitive: Primitive::Triangles,
        has_normals: true,
        terminator_lift: 0.0,
        clusters: None,
        instances: None,
        skin: None,
    }
}

/// As [`draw_mesh`] for a mesh uploaded whole (read now if it is still in a cache entry).
pub(crate) fn whole_draw_mesh(
    gpu: &GpuRef,
    scene: &Scene,
    i: usize,
    clusters: Option<Clusters>,
) -> Result<(DrawMesh, u64)> {
    whole_draw_mesh_into(gpu, scene, i, clusters, None)
}

/// As [`whole_draw_mesh`], into `old`'s buffers where they fit ([`GpuMesh::rewrite`]): a
/// mesh posed anew keeps its GL objects.
pub(crate) fn whole_draw_mesh_into(
    gpu: &GpuRef,
    scene: &Scene,
    i: usize,
    mut clusters: Option<Clusters>,
    old: Option<DrawMesh>,
) -> Result<(DrawMesh, u64)> {
    let old = old.and_then(|d| match d.mesh {
        Resident::Full(g) if d.instances.is_none() => Some(g),
        _ => None,
    });
    use crate::scene::model::meshes::FirstView;
    let m = match scene.meshes.first_view(i) {
        Some(FirstView::Whole(m)) => m,
        _ => &scene.meshes[i],
    };
    let mat = &scene.materials[m.material];
    // Levels of detail go in the same index buffer, after the mesh's own triangles: the
    // clusters' own, or those read with a compact mesh's full arrays.
    let levels = match &clusters {
        Some(c) if c.lod.indices.is_empty() && c.lod.index_count > 0 => levels_read(scene, i)?,
        Some(c) => &c.lod.indices[..],
        None => &[][..],
    };
    let (mesh, has, bytes) = upload_mesh_into(gpu, m, mat, levels, old, &[], &[])?;
    // The levels' indices now live on the GPU only.
    if let Some(c) = &mut clusters {
        c.lod.indices = Vec::new();
    }
    let sphere = crate::scene::bounding_sphere(&m.vertices);
    let dm = DrawMesh {
        clusters,
        ..triangles_draw_mesh(mesh, (m, mat), has, sphere)
    };
    Ok((dm, bytes))
}

/// The draw record of scene mesh `m`'s triangles uploaded whole as `mesh` (no clusters,
/// instances or GPU skin: the callers that have them set them), bounded by `sphere`.
fn triangles_draw_mesh(
    mesh: GpuMesh,
    (m, mat): (&crate::scene::Mesh, &crate::scene::Material),
    has: Has,
    (center, radius): (glam::Vec3, f32),
) -> DrawMesh {
    DrawMesh {
        mesh: Resident::Full(mesh),
        material: m.material,
        center,
        radius,
        triangles: m.triangle_count() as u64,
        translucent: mat.is_translucent(),
        has_uv: m.has_uv,
        has_tangents: has.tangents,
        has_uv1: has.uv1,
        has_colors: has.colors,
        primitive: Primitive::Triangles,
        has_normals: true,
        terminator_lift: crate::scene::terminator_lift(m) as f32,
        clusters: None,
        instances: None,
        skin: None,
    }
}

/// The levels' indices of mesh `i`, which came compact: read with its full arrays.
fn levels_read(scene: &Scene, i: usize) -> Result<&[u32]> {
    scene.meshes.levels_read(i).ok_or_else(|| {
        crate::Error::Unsupported(format!(
            "mesh {i}: its levels of detail were not read from the mesh cache"
        ))
    })
}

/// Which optional streams an upload has.
pub(crate) struct Has {
    pub(crate) tangents: bool,
    pub(crate) uv1: bool,
    pub(crate) colors: bool,
}

/// The colour (RGB, or RGBA where alpha is per vertex too) and second UV streams of a
/// mesh's per-vertex arrays, where they are per vertex.
#[allow(clippy::type_complexity)]
fn streams_of<'a>(
    vertices: &[crate::scene::Vertex],
    colors: &'a [[f32; 3]],
    alpha: &[f32],
    uv1: &'a [[f32; 2]],
) -> (
    Option<&'a [[f32; 3]]>,
    Option<Vec<[f32; 4]>>,
    Option<&'a [[f32; 2]]>,
) {
    let colors = (colors.len() == vertices.len()).then_some(colors);
    // COLOR_0's alpha goes up with the colour as a fourth component.
    let rgba = colors.filter(|_| alpha.len() == vertices.len()).map(|c| {
        c.iter()
            .zip(alpha)
            .map(|(c, &a)| [c[0], c[1], c[2], a])
            .collect()
    });
    let uv1 = (uv1.len() == vertices.len()).then_some(uv1);
    (colors, rgba, uv1)
}

/// Bytes of a mesh's vertex streams and `indices` indices (16-bit where they suffice).
fn bytes_of(vertices: &[crate::scene::Vertex], indices: usize, s: Streams) -> u64 {
    let index = if vertices.len() <= u16::MAX as usize + 1 {
        2
    } else {
        4
    };
    let len = |b: Option<&[u8]>| b.map_or(0, <[u8]>::len);
    let streams = match s.colors_rgba {
        Some(c) => len(Some(bytemuck::cast_slice(c))),
        None => len(s.colors.map(bytemuck::cast_slice)),
    } + len(s.tangents.map(bytemuck::cast_slice))
        + len(s.uv1.map(bytemuck::cast_slice));
    (std::mem::size_of_val(vertices) + streams + indices * index) as u64
}

/// Uploads mesh `m` (drawn with `mat`) with `levels` after its triangles; returns it, its
/// optional streams and the bytes uploaded.
fn upload_mesh(
    gpu: &GpuRef,
    m: &crate::scene::Mesh,
    mat: &crate::scene::Material,
    levels: &[u32],
) -> Result<(GpuMesh, Has, u64)> {
    upload_mesh_into(gpu, m, mat, levels, None, &[], &[])
}

/// As [`upload_mesh`], into `old`'s buffers when they fit (a posed mesh: same sizes, no
/// levels), else into new ones.
pub(crate) fn upload_mesh_into(
    gpu: &GpuRef,
    m: &crate::scene::Mesh,
    mat: &crate::scene::Material,
    levels: &[u32],
    old: Option<GpuMesh>,
    skin: &[crate::gpu::mesh::SkinStreams],
    morph: &[Vec<[f32; 3]>],
) -> Result<(GpuMesh, Has, u64)> {
    // The file's tangents where it has them (glTF TANGENT), else MikkTSpace's.
    let tangents = (m.has_uv && mat.needs_tangents()).then(|| {
        if m.tangents.len() == m.vertices.len() {
            std::borrow::Cow::Borrowed(m.tangents.as_slice())
        } else {
            std::borrow::Cow::Owned(crate::scene::geometry::tangents::generate(m))
        }
    });
    let (colors, rgba, uv1) = streams_of(&m.vertices, &m.colors, &m.color_alpha, &m.uv1);
    let streams = Streams {
        tangents: tangents.as_deref(),
        colors,
        colors_rgba: rgba.as_deref(),
        uv1,
        skin: skin.first().copied(),
        morph,
        skin1: skin.get(1).copied(),
    };
    let mesh = match old {
        Some(g) if levels.is_empty() && g.rewrite(&m.vertices, &m.indices, streams) => g,
        _ => GpuMesh::with_levels(
            gpu,
            &m.vertices,
            &m.indices,
            levels,
            streams,
            Primitive::Triangles,
        )?,
    };
    let has = Has {
        tangents: tangents.is_some(),
        uv1: uv1.is_some(),
        colors: colors.is_some(),
    };
    let skin_bytes: usize = skin
        .iter()
        .map(|(j, w)| std::mem::size_of_val(*j) + std::mem::size_of_val(*w))
        .sum();
    let morph_bytes: usize = morph
        .iter()
        .map(|d| std::mem::size_of_val(d.as_slice()))
        .sum();
    let bytes = bytes_of(&m.vertices, m.indices.len() + levels.len(), streams)
        + (skin_bytes + morph_bytes) as u64;
    Ok((mesh, has, bytes))
}

/// The scene's lines and points (`l`, `p`, glTF LINES and POINTS, a point cloud) as two
/// meshes of GL_LINES and GL_POINTS with material 0. Lines have zero normals: the lit
/// programs' `safeNormalize` turns them towards the eye, so a line is lit flat, as a face
/// looking at the camera. Points are lit with their normals where the file gives them, else
/// drawn unlit; per-point colours where given.
fn wire_meshes(gpu: &GpuRef, scene: &Scene) -> Result<(Vec<DrawMesh>, u64)> {
    let w = &scene.wire;
    let has_normals = w.normals.len() == w.positions.len() && !w.positions.is_empty();
    let vertices: Vec<crate::scene::Vertex> = w
        .positions
        .iter()
        .enumerate()
        .map(|(i, &position)| crate::scene::Vertex {
            position,
            normal: if has_normals { w.normals[i] } else { [0.0; 3] },
            uv: [0.0; 2],
        })
        .collect();
    let colors = (w.colors.len() == w.positions.len()).then_some(w.colors.as_slice());
    let mut b = crate::scene::Bounds::empty();
    for v in &w.positions {
        b.include((*v).into());
    }
    let center = b.center();
    let radius = w
        .positions
        .iter()
        .map(|v| (Vec3::from(*v) - center).length())
        .fold(0.0f32, f32::max);
    let segments: Vec<u32> = w.segments.iter().flatten().copied().collect();
    let mut out = Vec::new();
    let mut bytes = 0;
    for (indices, primitive) in [
        (segments, Primitive::Lines),
        (w.points.clone(), Primitive::Points),
    ] {
        if indices.is_empty() {
            continue;
        }
        let streams = Streams {
            colors,
            ..Streams::default()
        };
        let mesh = GpuMesh::with_streams(gpu, &vertices, &indices, streams, primitive)?;
        bytes += (std::mem::size_of_val(vertices.as_slice())
            + colors.map_or(0, std::mem::size_of_val)
            + std::mem::size_of_val(indices.as_slice())) as u64;
        out.push(DrawMesh {
            mesh: Resident::Full(mesh),
            material: 0,
            center,
            radius,
            triangles: 0,
            translucent: false,
            has_uv: false,
            has_tangents: false,
            has_uv1: false,
            has_colors: colors.is_some(),
            primitive,
            has_normals: primitive == Primitive::Lines || has_normals,
            terminator_lift: 0.0,
            clusters: None,
            instances: None,
            skin: None,
        });
    }
    Ok((out, bytes))
}

/// Uploads scene mesh `s.mesh` in bind space with its joints and weights: the scene mesh's
/// other streams (UVs, colours, indices, material) as they are. Its bounds are the scene
/// mesh's at the static pose, the animation's framing bounds at a moment (the scene's).
fn skinned_mesh(
    gpu: &GpuRef,
    scene: &Scene,
    s: &crate::scene::motion::gpu::GpuSkinned,
) -> Result<(DrawMesh, u64)> {
    let m = &scene.meshes[s.mesh];
    let mut bind = m.clone();
    for (v, (p, n)) in bind
        .vertices
        .iter_mut()
        .zip(s.positions.iter().zip(&s.normals))
    {
        v.position = *p;
        v.normal = *n;
    }
    bind.tangents = s.tangents.clone().unwrap_or_default();
    let mat = &scene.materials[m.material];
    let mut sets = vec![(s.joint_ids.as_slice(), s.weights.as_slice())];
    sets.extend(s.second.as_ref().map(|(j, w)| (j.as_slice(), w.as_slice())));
    let morph = s.morph.as_ref().map_or(&[][..], |m| m.deltas.as_slice());
    let (mesh, has, bytes) = upload_mesh_into(gpu, &bind, mat, &[], None, &sets, morph)?;
    let sphere = match scene.posed {
        Some(_) => super::skinning::framing_sphere(&scene.bounds),
        None => crate::scene::bounding_sphere(&m.vertices),
    };
    // Its terminator lift is the static pose's (`m`'s): skinning bends a mesh without
    // stretching its edges much.
    let dm = DrawMesh {
        skin: Some(super::skinning::SkinDraw {
            skin: s.skin,
            joints: s.joints,
            sets: sets.len(),
            morph: s.morph.as_ref().map(|m| (m.part, m.slots.len())),
        }),
        ..triangles_draw_mesh(mesh, (m, mat), has, sphere)
    };
    Ok((dm, bytes))
}
