//! Drawing one mesh with only the clusters the current view may see
//! ([`crate::scene::lod::clusters`]): clusters outside the view's frustum are skipped for every
//! mesh, and for a closed outward-facing mesh seen from outside (the whole of it past the
//! near plane) so are the clusters facing away, with GL back-face culling for the rest; a
//! draw that culls back faces anyway (single-sided materials) skips them for any mesh. The
//! image is the same: a ray from outside a closed surface meets a front face first, and
//! nothing outside the frustum is rasterised (but for a rare silhouette pixel where a back
//! face used to win a near-tie in depth: README, The frame). Passes set the view ([`FrameCx::cull`]):
//! the lit passes the camera's, the shadow pass each light view's.
use super::upload::SceneGpu;
use super::FrameCx;
use super::Lod;
use crate::gpu::state::{Blend, Cull, RenderState};
use crate::options::LodMode;
use crate::scene::model::meshes::FirstView;
use crate::Result;

/// Draws mesh `i` with `state`, whole or by its visible clusters.
pub(crate) fn draw(cx: &mut FrameCx, i: usize, state: &RenderState) -> Result<()> {
    let dm = &cx.scene.meshes[i];
    // glTF's single-sided materials show no back faces (in every pass, so their shadows
    // match what is seen); a pass that already chose a face (translucency's two passes) keeps it.
    let single_sided = !cx.scene.scene.materials[dm.material].double_sided;
    let sided = RenderState {
        cull: if single_sided && state.cull == Cull::None {
            Cull::Back
        } else {
            state.cull
        },
        ..*state
    };
    let state = &sided;
    if let (Some(inst), Some(view)) = (&dm.instances, cx.cull) {
        // Instance by instance, as the written-out copies would be culled.
        let which = super::instancing::visible(inst, &view);
        if which.is_empty() {
            return Ok(());
        }
        cx.gpu.apply(state);
        dm.draw_instances(&which);
        cx.stats.draw_calls += 1;
        let each = dm.triangles / inst.spheres.len().max(1) as u64;
        cx.stats.triangles += each * which.len() as u64;
        return Ok(());
    }
    let (Some(clusters), Some(view), true) = (&dm.clusters, cx.cull, cx.cull_clusters) else {
        cx.gpu.apply(state);
        dm.draw(cx.scene, i)?;
        cx.stats.draw_calls += 1;
        cx.stats.triangles += dm.triangles;
        return Ok(());
    };
    // Only where the draw would show every face anyway: opaque, unblended, no culling asked.
    let could_hide = !dm.translucent && state.cull == Cull::None && state.blend == Blend::Off;
    let outside = view.sees_from_outside(dm.center, dm.radius);
    // A draw that culls back faces (single-sided materials, a pass that chose front faces)
    // would drop every facet of a cluster facing away whatever the mesh's shape: skipping
    // the cluster is exact for open meshes and from inside too.
    let hide_back_faces = state.cull == Cull::Back || (could_hide && clusters.closed() && outside);
    if could_hide && !hide_back_faces {
        // A silent "0 skipped" hid an exporter's seam once; say which condition failed.
        let why = if clusters.closed() {
            "the viewer (camera or light) is inside its bounding sphere or the near plane cuts it"
                .to_string()
        } else {
            clusters.closure.reason()
        };
        let note = format!("mesh {i}: {why}");
        if !cx.stats.back_faces_kept.contains(&note) {
            cx.stats.back_faces_kept.push(note);
        }
    }
    let state = RenderState {
        cull: if hide_back_faces {
            Cull::Back
        } else {
            state.cull
        },
        ..*state
    };
    // Decided by the picture for the light views too, whose maps are larger.
    let pixels = u64::from(cx.viewport[2]) * u64::from(cx.viewport[3]);
    let view = if uses_lod(cx.lod, cx.cull_clusters, dm.triangles, pixels) {
        view
    } else {
        view.without_lod()
    };
    let mut ranges = std::mem::take(&mut cx.ranges);
    let drawn = clusters.visible(&view, hide_back_faces, &mut ranges);
    let result = if ranges.is_empty() {
        Ok(())
    } else {
        cx.gpu.apply(&state);
        dm.draw_ranges(cx.scene, i, &ranges)
    };
    cx.stats.draw_calls += ranges.len() as u32;
    cx.stats.triangles += drawn;
    cx.stats.triangles_skipped += dm.triangles.saturating_sub(drawn);
    cx.ranges = ranges;
    result
}

/// Whether a draw of a mesh of `triangles` into a picture of `pixels` uses its levels of
/// detail (when it has clusters): where asked, and with auto only where the mesh has more
/// triangles than the picture has pixels (most are then smaller than a pixel, and each
/// costs llvmpipe's set-up); never at error 0 or without cluster culling. The one rule:
/// the lit and shadow passes, the attribute pass and [`build_levels`] all ask it.
pub(crate) fn uses_lod(lod: Lod, cull_clusters: bool, triangles: u64, pixels: u64) -> bool {
    let wanted = match lod.mode {
        LodMode::On => true,
        LodMode::Auto => triangles > pixels,
        LodMode::Off => false,
    };
    wanted && lod.error > 0.0 && cull_clusters
}

/// Builds the levels of detail of every clustered mesh that a picture of `pixels` would
/// draw with levels ([`uses_lod`]) and has none yet (a cache miss brings clusters without
/// them), and keeps them for later frames. Built before the first picture that uses them,
/// so a picture never depends on whether the mesh cache held them: the cache's levels are
/// these same levels ([`crate::scene::lod::clusters::levels_of`]), it only saves building them.
/// Returns the meshes built.
pub(crate) fn build_levels(
    scene: &mut SceneGpu,
    lod: Lod,
    cull_clusters: bool,
    pixels: u64,
) -> Result<usize> {
    let mut built = 0;
    // Mesh i of the scene is draw mesh i (the lines and points follow, without clusters).
    for (i, dm) in scene.meshes.iter_mut().enumerate() {
        let Some(c) = &dm.clusters else { continue };
        if !c.lod.groups.is_empty() || !uses_lod(lod, cull_clusters, dm.triangles, pixels) {
            continue;
        }
        let t = crate::clock::Mark::now();
        // A mesh without levels came whole (a compact one brings its levels): looked up
        // without reading the other meshes' rest.
        let Some(FirstView::Whole(m)) = scene.scene.meshes.first_view(i) else {
            continue;
        };
        let mut levels = crate::scene::lod::clusters::levels_of(m, c);
        dm.set_levels(&m.indices, &levels.indices)?;
        let Some(c) = &mut dm.clusters else { continue };
        // As at upload: the levels' indices live on the GPU only.
        levels.indices = Vec::new();
        c.lod = levels;
        built += 1;
        log::debug!(
            "levels of detail of a {}-triangle mesh built for this picture in {:.0} ms",
            dm.triangles,
            t.ms()
        );
    }
    Ok(built)
}
