//! Regenerates the committed scenes in `models/` from `glview::scene::generate`.

use glview::scene::generate;
use std::error::Error;
use std::fs::{self, File};
use std::io::BufWriter;
use std::path::Path;

fn main() -> Result<(), Box<dyn Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    fs::create_dir_all(&dir)?;
    for model in generate::all() {
        for (ext, text) in [("obj", &model.obj), ("mtl", &model.mtl)] {
            let path = dir.join(format!("{}.{ext}", model.name));
            fs::write(&path, text)?;
            println!("wrote {} ({} bytes)", path.display(), text.len());
        }
        println!("  triangles: {}", triangle_summary(&model.obj));
    }
    let (width, height, rgba) = generate::checker_png_rgba();
    let path = dir.join("checker.png");
    let mut encoder = png::Encoder::new(BufWriter::new(File::create(&path)?), width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&rgba)?;
    // Finishing explicitly reports a failed final write, which dropping would swallow.
    writer.finish()?;
    println!("wrote {} ({width}x{height} RGBA)", path.display());
    Ok(())
}

/// "total N (object n, ...)" counted from the OBJ text itself.
fn triangle_summary(obj: &str) -> String {
    let mut objects: Vec<(&str, usize)> = Vec::new();
    for line in obj.lines() {
        if let Some(name) = line.strip_prefix("o ") {
            objects.push((name, 0));
        } else if line.starts_with("f ") {
            if let Some(last) = objects.last_mut() {
                last.1 += 1;
            }
        }
    }
    let total: usize = objects.iter().map(|o| o.1).sum();
    let parts: Vec<String> = objects.iter().map(|(n, c)| format!("{n} {c}")).collect();
    format!("total {total} ({})", parts.join(", "))
}
