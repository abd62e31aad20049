//! `glview bench --instancing`: the frame time of a generated file of N cubes drawn through
//! `EXT_mesh_gpu_instancing` against its twin with the instances written out as nodes
//! (`glview::scene::generate::instanced_gltf`), at 1280×720 with the default lights and
//! shadow map, on the context glview picks (GL 3.3 core on Mesa: instanced) and on GL 2.1
//! (the copies, as the twin). The median of 30 frames per file, measured in interleaved
//! rounds after one warm-up frame; with the draw calls and the mesh bytes on the GPU.
use super::table::{num, Table};
use glview::options::Options;
use glview::render::Renderer;
use glview::Result;

pub fn run_instancing(work: &std::path::Path) -> Result<()> {
    let (w, h) = (1280, 720);
    super::ensure_dir(work)?;
    let mut table = Table::new(&[
        "instances",
        "file",
        "triangles",
        "draw calls",
        "mesh bytes on GPU",
        "frame ms (median)",
        "vs nodes",
    ]);
    let hl = super::open_headless(
        "instancing",
        (w, h),
        "default lights and shadow map, median of 30 frames",
    )?;
    for n in [125, 10_000] {
        let g = glview::scene::generate::instanced_gltf(n);
        let write = |name: &str, text: &[u8]| {
            let p = work.join(name);
            std::fs::write(&p, text).map_err(|e| glview::Error::io(&p, e))?;
            Ok::<_, glview::Error>(p)
        };
        write(g.uri, &g.bin)?;
        let files = [
            (
                "instanced",
                write(&format!("inst{n}.gltf"), g.instanced.as_bytes())?,
            ),
            (
                "as nodes",
                write(&format!("nodes{n}.gltf"), g.twin.as_bytes())?,
            ),
        ];
        let mut runs = Vec::new();
        for (label, path) in files {
            let mut o = Options::default();
            o.picture.size = (w, h);
            o.load.model = Some(path);
            let scene = glview::session::load_scene(&o)?;
            let (s, _) = glview::session::frame_settings(&o, &scene)?;
            let mut r = Renderer::new(&hl.gpu, scene)?;
            let first = r.render(&s, &hl.target())?;
            runs.push((label, s, r, first, Vec::new()));
        }
        // Interleaved, so the other processes' bursts spread over both files.
        for _round in 0..10 {
            for (_, s, r, _, times) in runs.iter_mut() {
                for _ in 0..3 {
                    times.push(r.render(s, &hl.target())?.ms);
                }
            }
        }
        let base = super::median(&runs[1].4);
        for (label, _, _, first, times) in &runs {
            let ms = super::median(times);
            table.row(vec![
                n.to_string(),
                label.to_string(),
                first.triangles.to_string(),
                first.draw_calls.to_string(),
                first.mesh_bytes_uploaded.to_string(),
                num(ms, 2),
                format!("{:.2}x", ms / base),
            ]);
        }
    }
    println!("{}", table.render());
    Ok(())
}
