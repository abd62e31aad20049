//! The SCORM package's zip, written by the `zip` crate (deflate through flate2, which the
//! library already builds for PNG and the mesh cache; no other codec, encryption or time
//! crate). Entries carry one fixed timestamp, so a package is byte-identical between runs.
use std::io::Write;

/// Zip archive of `files` (name, bytes), deflated, in memory. Names are paths with `/`.
pub fn zip(files: &[(&str, &[u8])]) -> std::io::Result<Vec<u8>> {
    let mut w = ::zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    // 1980-01-01 00:00, the earliest a zip can say: the build time would make every package
    // differ from the last.
    let options = ::zip::write::SimpleFileOptions::default()
        .compression_method(::zip::CompressionMethod::Deflated)
        .compression_level(Some(9))
        .last_modified_time(::zip::DateTime::default());
    for (name, data) in files {
        w.start_file(*name, options)
            .map_err(std::io::Error::other)?;
        w.write_all(data)?;
    }
    Ok(w.finish().map_err(std::io::Error::other)?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// Reads the archive back by its central directory (as unzip does) and inflates each
    /// file: names, sizes and bytes must be what was written (the reader checks CRCs), and a
    /// second archive of the same files is the same bytes.
    #[test]
    fn archive_reads_back_by_its_central_directory() {
        let big: Vec<u8> = (0..100_000u32).map(|i| (i * 7 % 251) as u8).collect();
        let files: [(&str, &[u8]); 3] = [("a.txt", b"hello"), ("dir/b.bin", &big), ("empty", b"")];
        let z = zip(&files).unwrap();
        assert_eq!(z, zip(&files).unwrap());
        let mut archive = ::zip::ZipArchive::new(std::io::Cursor::new(&z)).unwrap();
        assert_eq!(archive.len(), files.len());
        for (name, data) in files {
            let mut f = archive.by_name(name).unwrap();
            assert_eq!(f.compression(), ::zip::CompressionMethod::Deflated);
            let mut back = Vec::new();
            f.read_to_end(&mut back).unwrap();
            assert_eq!(back, data);
        }
        assert!(z.len() < big.len() / 2, "deflated: {} bytes", z.len());
    }
}
