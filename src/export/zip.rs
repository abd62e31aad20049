//! A minimal zip writer (PKWARE APPNOTE 6.3: local headers, central directory, end record;
//! deflate through flate2, which the library already builds for PNG and the mesh cache):
//! a SCORM package has two files, so a zip crate's reader, encryption and zip64 would be
//! build time for nothing. Fixed timestamps make a package byte-identical between runs.
use std::io::Write;

/// 1980-01-01 00:00 in MS-DOS date form (the earliest a zip can say).
const DOS_DATE: u16 = (1 << 5) | 1;

/// Zip archive of `files` (name, bytes), deflated, in memory. Names are ASCII paths with `/`.
/// Each file and the archive must stay under 4 GiB (no zip64): a page is megabytes.
pub fn zip(files: &[(&str, &[u8])]) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut central = Vec::new();
    for (name, data) in files {
        let mut crc = flate2::Crc::new();
        crc.update(data);
        let mut enc = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
        enc.write_all(data)?;
        let packed = enc.finish()?;
        let offset = u32_of(out.len())?;
        let fields = Fields {
            crc: crc.sum(),
            packed: u32_of(packed.len())?,
            size: u32_of(data.len())?,
            name: name.as_bytes(),
        };
        out.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        fields.common(&mut out);
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&packed);
        central.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        central.extend_from_slice(&20u16.to_le_bytes()); // made by: version 2.0, MS-DOS
        fields.common(&mut central);
        // Comment length, disk, internal and external attributes, local header offset.
        central.extend_from_slice(&[0; 10]);
        central.extend_from_slice(&offset.to_le_bytes());
        central.extend_from_slice(name.as_bytes());
    }
    let (dir_at, dir_len) = (u32_of(out.len())?, u32_of(central.len())?);
    out.extend_from_slice(&central);
    let n = u16::try_from(files.len()).map_err(|_| too_large())?;
    out.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    out.extend_from_slice(&[0; 4]); // this disk, the directory's disk
    out.extend_from_slice(&n.to_le_bytes());
    out.extend_from_slice(&n.to_le_bytes());
    out.extend_from_slice(&dir_len.to_le_bytes());
    out.extend_from_slice(&dir_at.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes()); // no comment
    Ok(out)
}

/// What a local header and a central directory entry both say, in the same order.
struct Fields<'a> {
    crc: u32,
    packed: u32,
    size: u32,
    name: &'a [u8],
}

impl Fields<'_> {
    fn common(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&20u16.to_le_bytes()); // version needed: 2.0 (deflate)
        out.extend_from_slice(&0u16.to_le_bytes()); // flags
        out.extend_from_slice(&8u16.to_le_bytes()); // method: deflate
        out.extend_from_slice(&0u16.to_le_bytes()); // time 00:00
        out.extend_from_slice(&DOS_DATE.to_le_bytes());
        out.extend_from_slice(&self.crc.to_le_bytes());
        out.extend_from_slice(&self.packed.to_le_bytes());
        out.extend_from_slice(&self.size.to_le_bytes());
        out.extend_from_slice(&(self.name.len() as u16).to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes()); // no extra field
    }
}

fn too_large() -> std::io::Error {
    std::io::Error::other("too large for a zip without zip64 (4 GiB, 65535 files)")
}

fn u32_of(n: usize) -> std::io::Result<u32> {
    u32::try_from(n).map_err(|_| too_large())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// Reads the archive back by its central directory (as unzip does) and inflates each
    /// file: names, sizes, CRCs and bytes must all be what was written.
    #[test]
    fn archive_reads_back_by_its_central_directory() {
        let big: Vec<u8> = (0..100_000u32).map(|i| (i * 7 % 251) as u8).collect();
        let files: [(&str, &[u8]); 3] = [("a.txt", b"hello"), ("dir/b.bin", &big), ("empty", b"")];
        let z = zip(&files).unwrap();
        let le16 = |o: usize| u16::from_le_bytes([z[o], z[o + 1]]) as usize;
        let le32 = |o: usize| u32::from_le_bytes(z[o..o + 4].try_into().unwrap()) as usize;
        let end = z.len() - 22;
        assert_eq!(le32(end), 0x0605_4b50);
        assert_eq!(le16(end + 10), files.len());
        let mut at = le32(end + 16);
        for (name, data) in files {
            assert_eq!(le32(at), 0x0201_4b50);
            let (packed, size, nlen) = (le32(at + 20), le32(at + 24), le16(at + 28));
            assert_eq!(&z[at + 46..at + 46 + nlen], name.as_bytes());
            assert_eq!(size, data.len());
            let local = le32(at + 42);
            assert_eq!(le32(local), 0x0403_4b50);
            let start = local + 30 + le16(local + 26) + le16(local + 28);
            let mut back = Vec::new();
            flate2::read::DeflateDecoder::new(&z[start..start + packed])
                .read_to_end(&mut back)
                .unwrap();
            assert_eq!(back, data);
            let mut crc = flate2::Crc::new();
            crc.update(&back);
            assert_eq!(crc.sum() as usize, le32(at + 16));
            at += 46 + nlen;
        }
    }
}
