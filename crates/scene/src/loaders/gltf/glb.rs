//! The GLB container (a 12-byte header, then a JSON chunk and an optional BIN chunk), read
//! as three.js reads it: chunks start before the header's total length and may run past
//! it to the file's end (a header whose length is not the file's, as exporters that patch
//! it after padding write, is a warning), chunks of unknown types are skipped, and padding
//! is not required. Every chunk must lie inside the file.

const JSON: u32 = 0x4E4F_534A;
const BIN: u32 = 0x004E_4942;

/// The JSON text and the binary chunk of a GLB file.
#[derive(Debug)]
pub(crate) struct Glb<'a> {
    pub(crate) json: &'a [u8],
    pub(crate) bin: Option<&'a [u8]>,
}

fn word(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB file's `bytes`; a header length that is not the file's is said in `warn`.
pub(crate) fn split<'a>(bytes: &'a [u8], warn: &mut dyn FnMut(String)) -> Result<Glb<'a>, String> {
    let (Some(version), Some(length)) = (word(bytes, 4), word(bytes, 8)) else {
        return Err("GLB header shorter than 12 bytes".into());
    };
    if version != 2 {
        return Err(format!("GLB version {version}; glview reads version 2"));
    }
    let length = length as usize;
    if length < 12 {
        return Err("GLB header shorter than 12 bytes".into());
    }
    let (mut json, mut bin) = (None, None);
    let mut at = 12;
    while at < length.min(bytes.len()) {
        let (Some(len), Some(kind)) = (word(bytes, at), word(bytes, at + 4)) else {
            return Err(format!("GLB chunk header at byte {at} is cut short"));
        };
        let start = at + 8;
        let data = start
            .checked_add(len as usize)
            .and_then(|end| bytes.get(start..end))
            .ok_or_else(|| {
                format!("GLB chunk at byte {at} says {len} bytes, past the file's end")
            })?;
        match kind {
            JSON if json.is_none() => json = Some(data),
            BIN if bin.is_none() && json.is_some() => bin = Some(data),
            _ => {}
        }
        at = start + len as usize;
    }
    if at != length {
        warn(format!(
            "the GLB header says the file has {length} bytes, its chunks end at byte {at}; \
             read to their end, as three.js reads it"
        ));
    }
    let json = json.ok_or("GLB without a JSON chunk")?;
    Ok(Glb { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(json: &[u8], bin: &[u8], length_delta: i64) -> Vec<u8> {
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(((total as i64 + length_delta) as u32).to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend(JSON.to_le_bytes());
        out.extend(json);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(BIN.to_le_bytes());
        out.extend(bin);
        out
    }

    #[test]
    fn a_header_length_past_the_end_is_read_to_the_end_with_a_warning() {
        let f = glb(b"{}", b"abc", 40);
        let mut warned = Vec::new();
        let g = split(&f, &mut |w| warned.push(w)).unwrap();
        assert_eq!((g.json, g.bin), (&b"{}"[..], Some(&b"abc"[..])));
        assert_eq!(warned.len(), 1);
        assert!(warned[0].contains("says the file has"), "{}", warned[0]);
        let f = glb(b"{}", b"abc", 0);
        let g = split(&f, &mut |w| panic!("{w}")).unwrap();
        assert_eq!(g.bin, Some(&b"abc"[..]));
    }

    #[test]
    fn chunks_past_the_end_and_missing_json_are_errors() {
        let mut f = glb(b"{}", b"abcd", 0);
        let n = f.len();
        f[20 + 2..24 + 2].copy_from_slice(&1000u32.to_le_bytes()); // the BIN chunk's length
        assert!(split(&f, &mut |_| {})
            .unwrap_err()
            .contains("past the file's end"));
        f.truncate(n - 6);
        assert!(split(&f[..12], &mut |_| {})
            .unwrap_err()
            .contains("without a JSON"));
        assert!(split(&f[..8], &mut |_| {}).is_err());
    }
}
