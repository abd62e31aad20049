//! A mesh in static GPU buffers, drawn through a vertex array object where the driver has
//! one, or with per-draw attribute binding on GL 2.1 drivers without VAOs.
use super::buffer::Buffer;
use super::instances::Instances;
use super::GpuRef;
use crate::scene::Vertex;
use crate::{Error, Result};
use glow::HasContext;

pub(crate) struct GpuMesh {
    gpu: GpuRef,
    vbo: Buffer,
    ibo: Buffer,
    /// Per-vertex tangents (xyz, w = handedness) for normal mapping, attribute 3.
    tangents: Option<Buffer>,
    /// Per-vertex colours (rgb, or rgba: a vec4 attribute fed three components reads alpha
    /// 1), attribute 4, and their component count.
    colors: Option<Buffer>,
    color_size: i32,
    /// Second UV set, attribute 5.
    uv1: Option<Buffer>,
    /// A skinned mesh's joint indices and weights, attributes 10 and 11.
    skin: Option<(Buffer, Buffer)>,
    /// Attributes 12 and up, with their component counts: a GPU-morphed mesh's targets'
    /// deltas (3), or a second joint set's joints and weights (4 and 4).
    high: Vec<(Buffer, i32)>,
    vao: Option<glow::VertexArray>,
    index_type: u32,
    /// GL_TRIANGLES, GL_LINES or GL_POINTS.
    mode: u32,
    pub(crate) index_count: i32,
    /// The indices [`GpuMesh::draw`] draws: the first ones, when levels of detail follow.
    pub(crate) whole_count: i32,
    /// Bytes of the vertex array and of each optional stream (0: none), as made.
    bytes: [usize; 4],
}

/// Attribute location of the optional tangent stream.
pub(crate) const TANGENT_ATTRIBUTE: u32 = 3;
/// Attribute location of the optional colour stream.
pub(crate) const COLOR_ATTRIBUTE: u32 = 4;
/// Attribute location of the optional second UV set.
pub(crate) const UV1_ATTRIBUTE: u32 = 5;
/// Attribute locations of a skinned mesh's joints and weights (`skin.glsl`).
pub(crate) const JOINTS_ATTRIBUTE: u32 = 10;
pub(crate) const WEIGHTS_ATTRIBUTE: u32 = 11;
/// Attribute location of a GPU-morphed mesh's first delta stream, or of a second joint
/// set's joints (its weights next) (`skin.glsl`), and how many deltas the shaders declare
/// at most.
pub(crate) const MORPH_ATTRIBUTE: u32 = 12;
pub(crate) const MORPH_ATTRIBUTES: usize = 4;

/// What the indices of a mesh describe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Primitive {
    Triangles,
    Lines,
    Points,
}

/// The optional per-vertex streams beside the interleaved [`Vertex`] array.
#[derive(Clone, Copy, Default)]
pub(crate) struct Streams<'a> {
    pub(crate) tangents: Option<&'a [[f32; 4]]>,
    pub(crate) colors: Option<&'a [[f32; 3]]>,
    /// Colours with alpha, used instead of `colors` when given.
    pub(crate) colors_rgba: Option<&'a [[f32; 4]]>,
    pub(crate) uv1: Option<&'a [[f32; 2]]>,
    /// Joint indices (as floats) and weights of a mesh skinned on the GPU.
    pub(crate) skin: Option<SkinStreams<'a>>,
    /// Morph target deltas of a mesh morphed on the GPU (at most [`MORPH_ATTRIBUTES`]).
    pub(crate) morph: &'a [Vec<[f32; 3]>],
    /// A second joint set (JOINTS_1, WEIGHTS_1) of a mesh skinned on the GPU, in the deltas'
    /// places (a mesh has one or the other).
    pub(crate) skin1: Option<SkinStreams<'a>>,
}

/// A skinned mesh's joint indices (as floats) and weights, one of each per vertex.
pub(crate) type SkinStreams<'a> = (&'a [[f32; 4]], &'a [[f32; 4]]);

fn set_attributes(
    gl: &glow::Context,
    vbo: &Buffer,
    extra: [(u32, i32, Option<&Buffer>); 5],
    high: &[(Buffer, i32)],
) {
    let stride = std::mem::size_of::<Vertex>() as i32;
    // SAFETY: offsets match the #[repr(C)] Vertex layout; extra streams are tightly packed
    // float vectors of the given size.
    unsafe {
        vbo.bind();
        for (loc, size, offset) in [(0u32, 3, 0), (1, 3, 12), (2, 2, 24)] {
            gl.enable_vertex_attrib_array(loc);
            gl.vertex_attrib_pointer_f32(loc, size, glow::FLOAT, false, stride, offset);
        }
        for (loc, size, buffer) in extra {
            match buffer {
                Some(b) => {
                    b.bind();
                    gl.enable_vertex_attrib_array(loc);
                    gl.vertex_attrib_pointer_f32(loc, size, glow::FLOAT, false, size * 4, 0);
                }
                // A disabled array reads the current generic value: (0, 0, 0, 1).
                None => gl.disable_vertex_attrib_array(loc),
            }
        }
        // Only a morphed mesh's (or a two-set skin's) programs declare these; without a VAO
        // the draw disables them again (attributes past 11 are touched only by the meshes
        // that have them).
        for (loc, (b, size)) in (MORPH_ATTRIBUTE..).zip(high) {
            b.bind();
            gl.enable_vertex_attrib_array(loc);
            gl.vertex_attrib_pointer_f32(loc, *size, glow::FLOAT, false, size * 4, 0);
        }
    }
}

impl GpuMesh {
    pub(crate) fn new(gpu: &GpuRef, vertices: &[Vertex], indices: &[u32]) -> Result<GpuMesh> {
        Self::with_streams(
            gpu,
            vertices,
            indices,
            Streams::default(),
            Primitive::Triangles,
        )
    }

    /// A mesh with optional streams of tangents and colours (one per vertex), whose indices
    /// describe `primitive`s.
    pub(crate) fn with_streams(
        gpu: &GpuRef,
        vertices: &[Vertex],
        indices: &[u32],
        streams: Streams,
        primitive: Primitive,
    ) -> Result<GpuMesh> {
        Self::with_levels(gpu, vertices, indices, &[], streams, primitive)
    }

    /// As [`GpuMesh::with_streams`], with `levels` (coarser levels of detail) after `indices`
    /// in the same index buffer; [`GpuMesh::draw`] draws `indices` only.
    pub(crate) fn with_levels(
        gpu: &GpuRef,
        vertices: &[Vertex],
        indices: &[u32],
        levels: &[u32],
        streams: Streams,
        primitive: Primitive,
    ) -> Result<GpuMesh> {
        let stream = |data: Option<&[u8]>| -> Result<Option<Buffer>> {
            data.map(|d| Buffer::new_static(gpu, glow::ARRAY_BUFFER, d))
                .transpose()
        };
        let tangents = stream(streams.tangents.map(bytemuck::cast_slice))?;
        let (colors, color_size) = match (streams.colors_rgba, streams.colors) {
            (Some(c), _) => (stream(Some(bytemuck::cast_slice(c)))?, 4),
            (None, c) => (stream(c.map(bytemuck::cast_slice))?, 3),
        };
        let uv1 = stream(streams.uv1.map(bytemuck::cast_slice))?;
        let skin = match streams.skin {
            Some((j, w)) => Some((
                Buffer::new_static(gpu, glow::ARRAY_BUFFER, bytemuck::cast_slice(j))?,
                Buffer::new_static(gpu, glow::ARRAY_BUFFER, bytemuck::cast_slice(w))?,
            )),
            None => None,
        };
        // A second joint set's joints and weights (vec4), else the morph deltas (vec3).
        let array = |d: &[u8], size: i32| -> Result<(Buffer, i32)> {
            Ok((Buffer::new_static(gpu, glow::ARRAY_BUFFER, d)?, size))
        };
        let high = match streams.skin1 {
            Some((j, w)) => vec![
                array(bytemuck::cast_slice(j), 4)?,
                array(bytemuck::cast_slice(w), 4)?,
            ],
            None => streams
                .morph
                .iter()
                .take(MORPH_ATTRIBUTES)
                .map(|d| array(bytemuck::cast_slice(d), 3))
                .collect::<Result<Vec<_>>>()?,
        };
        let vbo = Buffer::new_static(gpu, glow::ARRAY_BUFFER, bytemuck::cast_slice(vertices))?;
        // 16-bit indices where they suffice: half the memory, and the only kind ES 2 had.
        let index_type = if vertices.len() <= u16::MAX as usize + 1 {
            glow::UNSIGNED_SHORT
        } else if gpu.caps.uint_indices {
            glow::UNSIGNED_INT
        } else {
            return Err(Error::Unsupported(format!(
                "mesh with {} vertices needs 32-bit indices, which this driver lacks",
                vertices.len()
            )));
        };
        let ibo = index_buffer(gpu, index_type, indices, levels)?;
        let vao = if gpu.caps.vao {
            // SAFETY: recording the attribute layout into a new VAO, then unbinding it.
            unsafe {
                let vao = gpu.gl.create_vertex_array().map_err(Error::Unsupported)?;
                gpu.created();
                gpu.gl.bind_vertex_array(Some(vao));
                set_attributes(
                    &gpu.gl,
                    &vbo,
                    extra(&tangents, (&colors, color_size), &uv1, &skin),
                    &high,
                );
                ibo.bind();
                gpu.gl.bind_vertex_array(None);
                Some(vao)
            }
        } else {
            None
        };
        Ok(GpuMesh {
            gpu: gpu.clone(),
            vbo,
            ibo,
            tangents,
            colors,
            color_size,
            uv1,
            skin,
            high,
            vao,
            index_type,
            mode: match primitive {
                Primitive::Triangles => glow::TRIANGLES,
                Primitive::Lines => glow::LINES,
                Primitive::Points => glow::POINTS,
            },
            index_count: (indices.len() + levels.len()) as i32,
            whole_count: indices.len() as i32,
            bytes: stream_bytes(vertices, streams),
        })
    }

    /// Rewrites the mesh's buffers in place with `vertices`, `indices` and `streams` when
    /// they have the sizes, streams and index type it was made with and it has no levels
    /// after its indices; returns whether it did (else the caller makes a new mesh).
    pub(crate) fn rewrite(&self, vertices: &[Vertex], indices: &[u32], streams: Streams) -> bool {
        let index_type = if vertices.len() <= u16::MAX as usize + 1 {
            glow::UNSIGNED_SHORT
        } else {
            glow::UNSIGNED_INT
        };
        let color_size = if streams.colors_rgba.is_some() { 4 } else { 3 };
        let same = stream_bytes(vertices, streams) == self.bytes
            && index_type == self.index_type
            && indices.len() as i32 == self.whole_count
            && self.whole_count == self.index_count
            && (self.colors.is_none() || color_size == self.color_size);
        if !same {
            return false;
        }
        self.vbo.rewrite(bytemuck::cast_slice(vertices));
        let b = |x: Option<&[u8]>, buf: &Option<Buffer>| {
            if let (Some(x), Some(buf)) = (x, buf) {
                buf.rewrite(x);
            }
        };
        b(streams.tangents.map(bytemuck::cast_slice), &self.tangents);
        match streams.colors_rgba {
            Some(c) => b(Some(bytemuck::cast_slice(c)), &self.colors),
            None => b(streams.colors.map(bytemuck::cast_slice), &self.colors),
        }
        b(streams.uv1.map(bytemuck::cast_slice), &self.uv1);
        if index_type == glow::UNSIGNED_SHORT {
            let small: Vec<u16> = indices.iter().map(|&i| i as u16).collect();
            self.ibo.rewrite(bytemuck::cast_slice(&small));
        } else {
            self.ibo.rewrite(bytemuck::cast_slice(indices));
        }
        true
    }

    /// Replaces the levels of detail after the mesh's own `indices` (the ones it was made
    /// with): a new index buffer of both, the vertex streams kept. For levels built after
    /// the upload, when a draw first needs them.
    pub(crate) fn set_levels(&mut self, indices: &[u32], levels: &[u32]) -> Result<()> {
        debug_assert_eq!(indices.len(), self.whole_count as usize);
        let ibo = index_buffer(&self.gpu, self.index_type, indices, levels)?;
        if let Some(vao) = self.vao {
            // SAFETY: re-recording our own VAO's element buffer, then unbinding it.
            unsafe {
                self.gpu.gl.bind_vertex_array(Some(vao));
                ibo.bind();
                self.gpu.gl.bind_vertex_array(None);
            }
        }
        // The old buffer is deleted here, no VAO naming it any more.
        self.ibo = ibo;
        self.index_count = (indices.len() + levels.len()) as i32;
        Ok(())
    }

    pub(crate) fn draw(&self) {
        self.draw_ranges(&[(0, self.whole_count as u32)]);
    }

    /// Draws the index ranges (first index, count), one draw call each, with the attribute
    /// set-up done once. Ranges must lie within the index buffer.
    pub(crate) fn draw_ranges(&self, ranges: &[(u32, u32)]) {
        self.draw_ranges_of(ranges, None);
    }

    /// Draws the whole mesh once per instance of `instances` (`which` of them; None: all),
    /// in one instanced draw call.
    pub(crate) fn draw_instanced(&self, instances: &Instances, which: Option<&[u32]>) {
        let n = instances.hold(&self.gpu.gl, which);
        self.draw_ranges_of(&[(0, self.whole_count as u32)], Some((instances, n)));
    }

    fn draw_ranges_of(&self, ranges: &[(u32, u32)], instances: Option<(&Instances, i32)>) {
        let gl = &self.gpu.gl;
        let size = if self.index_type == glow::UNSIGNED_SHORT {
            2
        } else {
            4
        };
        // SAFETY: draws from our own buffers within their length (the caller's ranges come
        // from this mesh's clusters); the caller has bound a program.
        unsafe {
            match self.vao {
                Some(vao) => gl.bind_vertex_array(Some(vao)),
                None => {
                    set_attributes(
                        gl,
                        &self.vbo,
                        extra(
                            &self.tangents,
                            (&self.colors, self.color_size),
                            &self.uv1,
                            &self.skin,
                        ),
                        &self.high,
                    );
                    self.ibo.bind();
                }
            }
            if let Some((inst, _)) = instances {
                inst.bind(gl);
            }
            for &(first, count) in ranges {
                debug_assert!(first + count <= self.index_count as u32);
                let offset = (first * size) as i32;
                match instances {
                    Some((_, n)) => gl.draw_elements_instanced(
                        self.mode,
                        count as i32,
                        self.index_type,
                        offset,
                        n,
                    ),
                    None => gl.draw_elements(self.mode, count as i32, self.index_type, offset),
                }
            }
            if instances.is_some() {
                Instances::unbind(gl);
            }
            if self.vao.is_some() {
                gl.bind_vertex_array(None);
            } else {
                for loc in (MORPH_ATTRIBUTE..).take(self.high.len()) {
                    gl.disable_vertex_attrib_array(loc);
                }
            }
        }
    }
}

/// An element buffer of `indices` then `levels`, as `index_type` (16- or 32-bit).
/// Bytes of the vertex array and of the tangent, colour and second-UV streams (0: none).
fn stream_bytes(vertices: &[Vertex], s: Streams) -> [usize; 4] {
    let colors = match s.colors_rgba {
        Some(c) => std::mem::size_of_val(c),
        None => s.colors.map_or(0, std::mem::size_of_val),
    };
    [
        std::mem::size_of_val(vertices),
        s.tangents.map_or(0, std::mem::size_of_val),
        colors,
        s.uv1.map_or(0, std::mem::size_of_val),
    ]
}

fn index_buffer(gpu: &GpuRef, index_type: u32, indices: &[u32], levels: &[u32]) -> Result<Buffer> {
    if index_type == glow::UNSIGNED_SHORT {
        let small: Vec<u16> = indices.iter().chain(levels).map(|&i| i as u16).collect();
        Buffer::new_static(
            gpu,
            glow::ELEMENT_ARRAY_BUFFER,
            bytemuck::cast_slice(&small),
        )
    } else {
        Buffer::new_static_parts(
            gpu,
            glow::ELEMENT_ARRAY_BUFFER,
            &[bytemuck::cast_slice(indices), bytemuck::cast_slice(levels)],
        )
    }
}

fn extra<'a>(
    tangents: &'a Option<Buffer>,
    (colors, color_size): (&'a Option<Buffer>, i32),
    uv1: &'a Option<Buffer>,
    skin: &'a Option<(Buffer, Buffer)>,
) -> [(u32, i32, Option<&'a Buffer>); 5] {
    [
        (TANGENT_ATTRIBUTE, 4, tangents.as_ref()),
        (COLOR_ATTRIBUTE, color_size, colors.as_ref()),
        (UV1_ATTRIBUTE, 2, uv1.as_ref()),
        (JOINTS_ATTRIBUTE, 4, skin.as_ref().map(|s| &s.0)),
        (WEIGHTS_ATTRIBUTE, 4, skin.as_ref().map(|s| &s.1)),
    ]
}

impl Drop for GpuMesh {
    fn drop(&mut self) {
        if let Some(vao) = self.vao {
            // SAFETY: deleting our own VAO once.
            unsafe { self.gpu.gl.delete_vertex_array(vao) };
            self.gpu.deleted();
        }
    }
}
