//! glTF primitive modes as triangle lists and line segments, by the spec's formulas (§3.7.2.1):
//! strips alternate their winding, fans share the first vertex, loops close. Under a mirroring
//! node transform (negative determinant) every triangle's winding is flipped, so front faces
//! stay front faces.
use gltf::mesh::Mode;

/// (triangle corners, line segments) of a primitive with these corner indices.
pub(crate) fn split(mode: Mode, c: &[u32], mirrored: bool) -> (Vec<u32>, Vec<[u32; 2]>) {
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut segs = Vec::new();
    match mode {
        Mode::Triangles => tris.extend(c.chunks_exact(3).map(|t| [t[0], t[1], t[2]])),
        Mode::TriangleStrip => {
            for i in 0..c.len().saturating_sub(2) {
                tris.push(if i % 2 == 0 {
                    [c[i], c[i + 1], c[i + 2]]
                } else {
                    [c[i + 1], c[i], c[i + 2]]
                });
            }
        }
        Mode::TriangleFan => {
            for i in 1..c.len().saturating_sub(1) {
                tris.push([c[i], c[i + 1], c[0]]);
            }
        }
        Mode::Lines => segs.extend(c.chunks_exact(2).map(|s| [s[0], s[1]])),
        Mode::LineStrip | Mode::LineLoop => {
            segs.extend(c.windows(2).map(|s| [s[0], s[1]]));
            if mode == Mode::LineLoop && c.len() > 2 {
                segs.push([c[c.len() - 1], c[0]]);
            }
        }
        Mode::Points => {}
    }
    // Strips and fans restart with degenerate triangles; they carry no area.
    if matches!(mode, Mode::TriangleStrip | Mode::TriangleFan) {
        tris.retain(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    }
    if mirrored {
        for t in &mut tris {
            t.swap(1, 2);
        }
    }
    (tris.into_iter().flatten().collect(), segs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_fans_and_loops() {
        let c = [0, 1, 2, 3];
        assert_eq!(split(Mode::TriangleStrip, &c, false).0, [0, 1, 2, 2, 1, 3]);
        assert_eq!(split(Mode::TriangleFan, &c, false).0, [1, 2, 0, 2, 3, 0]);
        assert_eq!(split(Mode::Triangles, &c[..3], true).0, [0, 2, 1]);
        assert_eq!(
            split(Mode::LineLoop, &c[..3], false).1,
            [[0, 1], [1, 2], [2, 0]]
        );
        assert_eq!(split(Mode::LineStrip, &c[..3], false).1, [[0, 1], [1, 2]]);
    }
}
