//! The scene in GPU buffers: one static mesh per scene mesh (with a tangent stream where its
//! material has a normal map, a second UV set where the file has one) and per-mesh bounds for
//! culling. Shared by every pass; textures are made on first use by the tier that reads them
//! (`textures.rs`).
use crate::gpu::mesh::{GpuMesh, Primitive, Streams};
use crate::gpu::texture::Texture2d;
use crate::gpu::GpuRef;
use crate::scene::clusters::Clusters;
use crate::scene::Scene;
use crate::Result;
use glam::Vec3;

pub(crate) struct DrawMesh {
    pub(crate) mesh: GpuMesh,
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
    /// skipping what a pass cannot see pays ([`crate::scene::clusters`]).
    pub(crate) clusters: Option<Clusters>,
}

impl DrawMesh {
    /// Translucent meshes, lines and points cast no shadow.
    pub(crate) fn casts_shadow(&self) -> bool {
        !self.translucent && self.primitive == Primitive::Triangles
    }
}

pub(crate) struct SceneGpu {
    pub(crate) scene: Scene,
    pub(crate) meshes: Vec<DrawMesh>,
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
    let start = std::time::Instant::now();
    let (w, h, rgba) = fit_texture(gpu, t)?;
    let tex = make(w, h, &rgba)?;
    // Drivers may queue the work (llvmpipe's glGenerateMipmap is a blit run at the next
    // flush): wait for it, so the cost lands on the texture that caused it.
    gpu.finish();
    gpu.record_texture(crate::gpu::TextureCost {
        name: t.path.display().to_string(),
        width: w,
        height: h,
        ms: start.elapsed().as_secs_f64() * 1e3,
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
    pub(crate) fn new(
        gpu: &GpuRef,
        mut scene: Scene,
        clusters: Vec<Option<Clusters>>,
    ) -> Result<SceneGpu> {
        let mut clusters = clusters.into_iter();
        // Lines and points are drawn with material 0; a file of only lines has none.
        if scene.materials.is_empty() {
            scene.materials.push(crate::scene::Material::default());
        }
        let mut meshes = Vec::with_capacity(scene.meshes.len());

        for m in &scene.meshes {
            let mat = &scene.materials[m.material];
            let mut b = crate::scene::Bounds::empty();
            for v in &m.vertices {
                b.include(v.position.into());
            }
            let center = b.center();
            let radius = m
                .vertices
                .iter()
                .map(|v| (Vec3::from(v.position) - center).length())
                .fold(0.0f32, f32::max);
            // The file's tangents where it has them (glTF TANGENT), else MikkTSpace's.
            let tangents = (m.has_uv && mat.needs_tangents()).then(|| {
                if m.tangents.len() == m.vertices.len() {
                    std::borrow::Cow::Borrowed(m.tangents.as_slice())
                } else {
                    std::borrow::Cow::Owned(crate::scene::tangents::generate(m))
                }
            });
            let colors = (m.colors.len() == m.vertices.len()).then_some(m.colors.as_slice());
            // COLOR_0's alpha goes up with the colour as a fourth component.
            let rgba: Option<Vec<[f32; 4]>> = colors
                .filter(|_| m.color_alpha.len() == m.vertices.len())
                .map(|c| {
                    c.iter()
                        .zip(&m.color_alpha)
                        .map(|(c, &a)| [c[0], c[1], c[2], a])
                        .collect()
                });
            let uv1 = (m.uv1.len() == m.vertices.len()).then_some(m.uv1.as_slice());
            let mut clusters = clusters.next().flatten();
            // Levels of detail go in the same index buffer, after the mesh's own triangles.
            let levels = clusters.as_ref().map_or(&[][..], |c| &c.lod.indices[..]);
            let streams = Streams {
                tangents: tangents.as_deref(),
                colors,
                colors_rgba: rgba.as_deref(),
                uv1,
            };
            let mesh = GpuMesh::with_levels(
                gpu,
                &m.vertices,
                &m.indices,
                levels,
                streams,
                Primitive::Triangles,
            )?;
            // The levels' indices now live on the GPU only.
            if let Some(c) = &mut clusters {
                c.lod.indices = Vec::new();
            }
            meshes.push(DrawMesh {
                mesh,
                material: m.material,
                center,
                radius,
                triangles: m.triangle_count() as u64,
                translucent: mat.is_translucent(),
                has_uv: m.has_uv,
                has_tangents: tangents.is_some(),
                has_uv1: uv1.is_some(),
                has_colors: colors.is_some(),
                primitive: Primitive::Triangles,
                has_normals: true,
                terminator_lift: crate::scene::terminator_lift(m) as f32,
                clusters,
            });
        }
        meshes.extend(wire_meshes(gpu, &scene)?);
        gpu.check_error("upload")?;
        let caps = &gpu.caps;
        if !caps.depth_texture || !caps.shadow_compare {
            log::warn!(
                "{}: no depth textures or shadow compare: shadows off",
                caps.version
            );
        }
        Ok(SceneGpu { scene, meshes })
    }

    /// Indices of the meshes whose bounding sphere touches the view frustum of `view_proj`:
    /// off-screen meshes cost a program bind and a draw call each for nothing.
    pub(crate) fn visible(&self, view_proj: &glam::Mat4) -> Vec<usize> {
        let view = crate::scene::clusters::ClusterView::new(*view_proj);
        (0..self.meshes.len())
            .filter(|&i| !view.outside(self.meshes[i].center, self.meshes[i].radius))
            .collect()
    }
}

/// The scene's lines and points (`l`, `p`, glTF LINES and POINTS, a point cloud) as two
/// meshes of GL_LINES and GL_POINTS with material 0. Lines have zero normals: the lit
/// programs' `safeNormalize` turns them towards the eye, so a line is lit flat, as a face
/// looking at the camera. Points are lit with their normals where the file gives them, else
/// drawn unlit; per-point colours where given.
fn wire_meshes(gpu: &GpuRef, scene: &Scene) -> Result<Vec<DrawMesh>> {
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
        out.push(DrawMesh {
            mesh,
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
        });
    }
    Ok(out)
}
