//! Where an MTL's texture statement points: its options stripped (`-s 1 1 1 file.png`), the
//! file found beside the MTL under the folder rule every format shares ([`crate::load::uri`]), then
//! decoded within the memory bounds of [`crate::textures`].
use crate::model::material::{Texture, TextureOptions};
use std::path::{Path, PathBuf};

/// Options of MTL texture statements and how many arguments each takes.
fn option_arity(opt: &str) -> Option<usize> {
    Some(match opt {
        "-blendu" | "-blendv" | "-cc" | "-clamp" | "-imfchan" | "-type" | "-bm" | "-boost"
        | "-texres" | "-colorspace" => 1,
        "-mm" => 2,
        "-o" | "-s" | "-t" => 3,
        _ => return None,
    })
}

/// Strips MTL texture options (`-s 1 1 1 file.png`) and returns the file name. `-o`, `-s` and
/// `-t` take 1 to 3 numbers, so numeric words after them are consumed greedily.
pub(crate) fn strip_texture_options(spec: &str) -> String {
    let words: Vec<&str> = spec.split_whitespace().collect();
    let mut i = 0;
    while i < words.len() {
        let Some(n) = option_arity(words[i]) else {
            break;
        };
        i += 1;
        let mut taken = 0;
        while taken < n && i < words.len() - 1 {
            if n == 3 && taken > 0 && words[i].parse::<f64>().is_err() {
                break;
            }
            i += 1;
            taken += 1;
        }
    }
    words[i.min(words.len())..].join(" ")
}

/// Finds a texture file: as written, with backslashes as separators, then by case-insensitive
/// match of each component. Refuses paths that leave `dir` unless allowed (the rule every
/// format shares: [`crate::load::uri`]).
pub(crate) fn resolve_texture_path(
    spec: &str,
    dir: &Path,
    allow_outside: bool,
) -> Result<PathBuf, String> {
    let name = strip_texture_options(spec).replace('\\', "/");
    crate::load::uri::in_folder(&name, dir, allow_outside)
}

/// Resolves and decodes the texture an MTL statement names.
pub(crate) fn load_texture(
    spec: &str,
    dir: &Path,
    opts: TextureOptions,
) -> Result<Texture, String> {
    let path = resolve_texture_path(spec, dir, opts.allow_outside_paths)?;
    decode_texture(path, opts)
}

/// Decodes an image file already resolved (and checked against the folder rule), within the
/// memory bounds of [`crate::textures`].
pub(crate) fn decode_texture(path: PathBuf, opts: TextureOptions) -> Result<Texture, String> {
    crate::textures::decode(path, opts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_stripped() {
        assert_eq!(strip_texture_options("-s 1 1 1 tex.png"), "tex.png");
        assert_eq!(
            strip_texture_options("-bm 2 -clamp on bump 01.png"),
            "bump 01.png"
        );
        assert_eq!(strip_texture_options("-o 0.1 tex.png"), "tex.png");
        assert_eq!(strip_texture_options("texture 01.png"), "texture 01.png");
    }
}
