//! Opening input files safely: only regular files are read (a directory, FIFO or device given as a scene, mesh,
//! texture or image is a clear error instead of a hang or a misleading "not found").

use crate::error::{PrismError, Result};
use std::path::Path;

/// Open `path` for reading if it is a regular file; returns the file and its length. `what` names the kind of
/// file in the not-found message ("image file", "environment map").
pub fn open_regular(path: &Path, what: &str) -> Result<(std::fs::File, u64)> {
    let meta = std::fs::metadata(path).map_err(|e| {
        let msg = if e.kind() == std::io::ErrorKind::NotFound { format!("{what} not found") } else { e.to_string() };
        PrismError::io(path, std::io::Error::new(e.kind(), msg))
    })?;
    if !meta.is_file() {
        return Err(PrismError::format(path, format!("{what} is {}, not a regular file", file_kind(&meta))));
    }
    let file = std::fs::File::open(path).map_err(|e| PrismError::io(path, e))?;
    Ok((file, meta.len()))
}

/// "a directory", "a named pipe (FIFO)", ... for messages about paths that are not regular files.
pub fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// The whole content of the regular file `path` (`what` names the kind of file in errors).
pub fn read_regular(path: &Path, what: &str) -> Result<Vec<u8>> {
    let (file, len) = open_regular(path, what)?;
    let mut bytes = Vec::with_capacity(len.min(1 << 30) as usize);
    std::io::Read::read_to_end(&mut std::io::BufReader::new(file), &mut bytes).map_err(|e| PrismError::io(path, e))?;
    Ok(bytes)
}

/// The content of the regular file `path` as UTF-8 text.
pub fn read_regular_text(path: &Path, what: &str) -> Result<String> {
    String::from_utf8(read_regular(path, what)?).map_err(|e| {
        PrismError::format(path, format!("{what} is not UTF-8 text (byte {})", e.utf8_error().valid_up_to()))
    })
}
