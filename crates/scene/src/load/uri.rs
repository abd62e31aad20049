//! One rule for every file a model refers to (OBJ's MTL textures, glTF buffers and images):
//! `data:` URIs are decoded in memory; anything else is percent-decoded, taken relative to the
//! model's folder, resolved through symlinks and `..`, and refused when the result lies outside
//! that folder unless `--allow-outside-paths` was given. Only local files are read: a URI with
//! a scheme other than `data:` and `file:` is refused.
use std::path::{Path, PathBuf};

/// Where the bytes of a URI are.
#[derive(Debug)]
pub(crate) enum Resolved {
    /// Decoded from a `data:` URI.
    Data(Vec<u8>),
    /// A file that exists and obeys the folder rule (canonical path).
    File(PathBuf),
}

/// Resolves `uri` (as written in a glTF file) against `dir`, the model's folder.
pub(crate) fn resolve(uri: &str, dir: &Path, allow_outside: bool) -> Result<Resolved, String> {
    if let Some(rest) = strip_prefix_ignore_case(uri, "data:") {
        return data_uri(rest).map(Resolved::Data);
    }
    let name = if let Some(rest) = strip_prefix_ignore_case(uri, "file://") {
        // file:///abs/path (an empty authority) or file://localhost/abs/path.
        rest.strip_prefix("localhost").unwrap_or(rest)
    } else if let Some(scheme) = scheme_of(uri) {
        return Err(format!(
            "URI scheme {scheme:?} is not supported (only relative paths, file: and data:)"
        ));
    } else {
        uri
    };
    let decoded = percent_decode(name.as_bytes());
    let name = String::from_utf8_lossy(&decoded);
    in_folder(&name, dir, allow_outside).map(Resolved::File)
}

fn strip_prefix_ignore_case<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| &s[prefix.len()..])
}

/// The scheme of an absolute URI (`http` in `http://…`); a single letter is a Windows drive.
fn scheme_of(uri: &str) -> Option<&str> {
    let colon = uri.find(':')?;
    let s = &uri[..colon];
    let ok = s.len() > 1
        && s.starts_with(|c: char| c.is_ascii_alphabetic())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c));
    ok.then_some(s)
}

/// `%20` → space; a `%` not followed by two hex digits stays as it is.
pub(crate) fn percent_decode(s: &[u8]) -> Vec<u8> {
    let hex = |c: u8| (c as char).to_digit(16).map(|d| d as u8);
    let mut out = Vec::with_capacity(s.len());
    let mut i = 0;
    while i < s.len() {
        if s[i] == b'%' && i + 2 < s.len() {
            if let (Some(h), Some(l)) = (hex(s[i + 1]), hex(s[i + 2])) {
                out.push(h << 4 | l);
                i += 3;
                continue;
            }
        }
        out.push(s[i]);
        i += 1;
    }
    out
}

/// The payload of `data:[<media type>][;base64],<data>` (after `data:`).
fn data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let (meta, payload) = rest
        .split_once(',')
        .ok_or("data: URI without a comma before its data")?;
    if meta.to_ascii_lowercase().ends_with(";base64") {
        base64(payload.as_bytes()).ok_or_else(|| "data: URI is not valid base64".to_string())
    } else {
        Ok(percent_decode(payload.as_bytes()))
    }
}

/// Standard or URL-safe base64, padding optional, whitespace ignored.
pub(crate) fn base64(s: &[u8]) -> Option<Vec<u8>> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        } as u32)
    };
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    let (mut acc, mut bits) = (0u32, 0u32);
    let mut ended = false;
    for &c in s {
        if c.is_ascii_whitespace() {
            continue;
        }
        if c == b'=' {
            ended = true;
            continue;
        }
        if ended {
            return None;
        }
        acc = (acc << 6) | val(c)?;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// A file named relative to `dir` (or absolute): as written, then by case-insensitive match of
/// each component; symlinks and `..` are resolved before the folder rule is applied.
pub(crate) fn in_folder(name: &str, dir: &Path, allow_outside: bool) -> Result<PathBuf, String> {
    if name.is_empty() {
        return Err("no file name".into());
    }
    let rel = Path::new(name);
    let files = crate::load::resources::current();
    let candidate = if rel.is_absolute() {
        rel.to_path_buf()
    } else {
        let direct = dir.join(rel);
        if files.kind(&direct).is_ok() {
            direct
        } else {
            find_case_insensitive(files.as_ref(), dir, rel)
                .ok_or_else(|| format!("file not found ({})", direct.display()))?
        }
    };
    let real = files
        .canonical(&candidate)
        .map_err(|e| format!("{}: {e}", candidate.display()))?;
    let base = files.canonical(dir).unwrap_or_else(|_| dir.to_path_buf());
    if !allow_outside && !real.starts_with(&base) {
        return Err(format!(
            "resolves to {} outside the model's folder; not read (use --allow-outside-paths)",
            real.display()
        ));
    }
    Ok(real)
}

fn find_case_insensitive(
    files: &dyn crate::load::resources::Resources,
    dir: &Path,
    rel: &Path,
) -> Option<PathBuf> {
    let mut cur = dir.to_path_buf();
    for comp in rel.components() {
        let want = comp.as_os_str().to_string_lossy().to_lowercase();
        if want == ".." || want == "." {
            cur.push(comp);
            continue;
        }
        let found = files
            .names(&cur)
            .ok()?
            .into_iter()
            .find(|n| n.to_lowercase() == want)?;
        cur.push(found);
    }
    Some(cur)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_percent_decoding() {
        assert_eq!(base64(b"aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64(b"aGVsbG8").unwrap(), b"hello");
        assert_eq!(base64(b"AAEC\n/w==").unwrap(), [0, 1, 2, 255]);
        assert!(base64(b"a*b").is_none());
        assert_eq!(percent_decode(b"a%20b%2"), b"a b%2");
        assert_eq!(percent_decode(b"%41%zz"), b"A%zz");
    }

    #[test]
    fn data_uris_and_schemes() {
        let r = resolve(
            "data:application/octet-stream;base64,AAE=",
            Path::new("."),
            false,
        );
        assert!(matches!(r, Ok(Resolved::Data(d)) if d == [0, 1]));
        let r = resolve("data:,a%20b", Path::new("."), false);
        assert!(matches!(r, Ok(Resolved::Data(d)) if d == b"a b"));
        let e = resolve("https://example.com/a.bin", Path::new("."), false).unwrap_err();
        assert!(e.contains("\"https\""), "{e}");
    }
}
