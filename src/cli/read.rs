//! Bounded reads of the files a scene names: regular files only, at most a limit of bytes,
//! decoded as text where text is expected. Below every loader (scenes, foreign formats, meshes,
//! images, the inspector's file hook).

use raytree::input::MAX_OBJ_BYTES;
use std::io::Read;
use std::path::Path;

/// Read and parse the OBJ `file` (relative paths against the scene's directory `dir`); errors
/// name the file and, for bad contents, the line ([`raytree::mesh::parse_obj_read`]).
pub fn read_obj(dir: &Path, file: &str) -> Result<raytree::mesh::MeshData, String> {
    let path = dir.join(file);
    raytree::mesh::parse_obj_read(file, &path, read_text(&path, MAX_OBJ_BYTES))
}

/// [`read_limited`] decoded as text ([`raytree::input::decode`]: a byte-order mark dropped,
/// invalid UTF-8 reported at its line and column), for the inspector's file hook and meshes.
pub fn read_text(path: &Path, limit: u64) -> std::io::Result<String> {
    let bytes = read_limited(path, limit).map_err(std::io::Error::other)?;
    raytree::input::decode(bytes).map_err(std::io::Error::other)
}

/// The bytes of the regular file `path`, refused if larger than `limit`. Anything else (a
/// directory, a FIFO that would block, a device such as `/dev/zero` that never ends) is
/// refused before it is opened for reading; at most `limit + 1` bytes are read, so a file
/// that grows while it is read is refused too.
pub fn read_limited(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err(format!("not a regular file ({})", kind(&meta.file_type())));
    }
    let too_big = || {
        format!(
            "larger than the limit of {} MiB for this kind of file",
            limit >> 20
        )
    };
    if meta.len() > limit {
        return Err(too_big());
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    // The name may now point elsewhere: check what was opened.
    let meta = file.metadata().map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err(format!("not a regular file ({})", kind(&meta.file_type())));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(too_big());
    }
    Ok(bytes)
}

/// What a file that is not a regular file is, for messages.
fn kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("a.json");
        std::fs::write(&f, b"0123456789").unwrap();
        assert_eq!(read_limited(&f, 10).unwrap().len(), 10);
        let e = read_limited(&f, 9).unwrap_err();
        assert!(e.contains("larger than the limit"), "{e}");
        let e = read_limited(dir.path(), 10).unwrap_err();
        assert_eq!(e, "not a regular file (a directory)");
        let e = read_limited(Path::new("/dev/zero"), 10).unwrap_err();
        assert_eq!(e, "not a regular file (a character device)");
        assert!(read_limited(&dir.path().join("none"), 10).is_err());
    }
}
