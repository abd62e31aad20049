//! `glview --check`: what the loader made of a model, without rendering.

pub mod material;
use crate::model::Scene;
use std::fmt::Write;

/// What the loader made of `s`, read from a file of `format` (None: the built-in scene,
/// which is OBJ); feature edges are counted at `crease_deg` (the loader's crease angle,
/// which `--edges` draws at).
pub fn report(
    s: &Scene,
    format: Option<crate::loaders::formats::Format>,
    crease_deg: f32,
) -> String {
    let mut r = String::new();
    let coloured = summary(&mut r, s);
    edges(&mut r, s, crease_deg);
    let has_colours = coloured > 0;
    for m in &s.materials {
        material(&mut r, m, format, has_colours);
    }
    normals_and_culling(&mut r, s);
    // The loader's per-stage times for the load just done on this thread (see `profile`).
    if let Some(p) = crate::profile::last() {
        let _ = writeln!(r, "load: {p}");
    }
    for w in &s.warnings {
        let _ = writeln!(r, "warning: {w}");
    }
    let _ = writeln!(
        r,
        "result: renders{}",
        if s.warnings.is_empty() {
            ""
        } else {
            " with warnings"
        }
    );
    r
}

/// The model's name, counts, bounds, vertex colours, lines and points, and what became of
/// each MTL texture statement; returns how many vertices have a colour (the material model
/// lines depend on it).
fn summary(r: &mut String, s: &Scene) -> usize {
    let (lo, hi) = s.file_bounds;
    let _ = writeln!(r, "model: {}", s.name);
    let _ = writeln!(
        r,
        "objects: {}  triangles: {}  vertices: {}  materials: {}",
        s.meshes.len(),
        s.triangle_count(),
        s.vertex_count(),
        s.materials.len() - 1
    );
    let _ = writeln!(
        r,
        "bounds: ({:.6}, {:.6}, {:.6}) .. ({:.6}, {:.6}, {:.6})",
        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
    );
    let coloured: usize = s
        .meshes
        .iter()
        .filter(|m| !m.colors.is_empty())
        .map(|m| m.vertices.len())
        .sum();
    if coloured > 0 {
        let _ = writeln!(r, "vertex colours: {coloured} vertices");
    }
    if s.meshes.is_empty() && s.wire.is_cloud() {
        let w = &s.wire;
        let yes = |v: bool| if v { "yes" } else { "no" };
        let _ = writeln!(
            r,
            "point cloud: {} points  colours: {}  normals: {}  spacing: {}",
            w.points.len(),
            yes(!w.colors.is_empty()),
            yes(!w.normals.is_empty()),
            w.spacing().map_or("-".into(), |d| format!("{d:.4e}"))
        );
    } else if !s.wire.is_empty() {
        let _ = writeln!(
            r,
            "lines: {}  points: {}",
            s.wire.segments.len(),
            s.wire.points.len()
        );
    }
    for m in &s.maps {
        let _ = writeln!(r, "{m}");
    }
    // The file's lights, which replace the default kit (`--light kit` restores it).
    for l in &s.lights {
        let _ = writeln!(r, "light: {}", l.describe());
    }
    coloured
}

/// The model's edges (what `--edges` and `--wireframe` draw), summed over its objects.
fn edges(r: &mut String, s: &Scene, crease_deg: f32) {
    if s.meshes.is_empty() {
        return;
    }
    let mut c = crate::geometry::edges::EdgeCounts::default();
    for m in &s.meshes {
        c += crate::geometry::edges::count(m, crease_deg);
    }
    let _ = writeln!(
        r,
        "edges: {} feature at {crease_deg}° ({} creased, {} boundary, {} non-manifold) of {} \
         triangle edges",
        c.feature(),
        c.creased,
        c.boundary,
        c.non_manifold,
        c.total
    );
}

/// One material: its PBR terms, how they were made (glTF's own, or mapped from another
/// format's), its PBR maps and its base-colour texture.
fn material(
    r: &mut String,
    m: &crate::model::material::Material,
    format: Option<crate::loaders::formats::Format>,
    has_colours: bool,
) {
    let _ = writeln!(
        r,
        "pbr: material {}: base colour ({:.3}, {:.3}, {:.3}), metallic {:.2}, roughness {:.3} ({})",
        m.name,
        m.base_color[0],
        m.base_color[1],
        m.base_color[2],
        m.metallic,
        m.roughness,
        if m.phong.is_some_and(|p| p.mapped) {
            "mapped from Kd/Ks/Ns"
        } else {
            "from Pr/Pm"
        }
    );
    let _ = writeln!(
        r,
        "colour rule: material {}: {}",
        m.name,
        m.colour_rule.describe()
    );
    let format = format.unwrap_or(crate::loaders::formats::Format::Obj);
    if format == crate::loaders::formats::Format::Gltf {
        for line in crate::report::material::describe(m) {
            let _ = writeln!(r, "material {}: {line}", m.name);
        }
    } else {
        // How a format without glTF's material model maps into it (README, Loading).
        let _ = writeln!(
            r,
            "material model: material {}: {}",
            m.name,
            crate::report::material::mapping(m, format, has_colours)
        );
    }
    for (key, spec, what) in &m.check.maps {
        let _ = writeln!(r, "pbr map: material {}: {key} {spec:?} -> {what}", m.name);
    }
    if let Some(spec) = &m.check.base_color {
        match &m.base_color_texture {
            Some(slot) => {
                let t = &slot.image;
                let _ = writeln!(
                    r,
                    "texture: material {}: map_Kd {spec:?} -> {} ({}x{})",
                    m.name,
                    t.path.display(),
                    t.width,
                    t.height
                );
            }
            None => {
                let _ = writeln!(
                    r,
                    "texture: material {}: map_Kd {spec:?} -> not loaded (see warnings)",
                    m.name
                );
            }
        }
    }
}

/// Per object: how many normals were generated, and for large meshes (drawn by clusters)
/// whether their back faces can be skipped, and why not.
fn normals_and_culling(r: &mut String, s: &Scene) {
    for m in &s.meshes {
        if m.generated_normals > 0 {
            let _ = writeln!(
                r,
                "normals: object {:?}: {} of {} generated",
                m.name,
                m.generated_normals,
                m.vertices.len()
            );
        }
    }
    // Large meshes are drawn by clusters; whether their back faces can be skipped, and why not.
    for m in s
        .meshes
        .iter()
        .filter(|m| m.triangle_count() >= crate::lod::clusters::MIN_TRIANGLES)
    {
        let c = crate::geometry::closure::closure(&m.vertices, &m.indices);
        let _ = writeln!(
            r,
            "culling: object {:?}: {} triangles in clusters; back faces {}: {}",
            m.name,
            m.triangle_count(),
            if c.is_closed() {
                "skipped when seen from outside"
            } else {
                "drawn"
            },
            c.reason()
        );
    }
}
