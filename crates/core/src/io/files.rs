//! Opening input files safely: only regular files are read (a directory, FIFO or device given as a scene, mesh,
//! texture or image is a clear error instead of a hang or a misleading "not found"), and, once a process has called
//! [`restrict_reads`] (`prism render --allow-read DIR`), only files inside the folders it names, after following
//! every symbolic link: a scene from an untrusted source cannot make Prism read `/etc/passwd` as a mesh.

use crate::error::{PrismError, Result};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The folders reads are restricted to, canonical; unset: no restriction.
static ALLOWED_READS: OnceLock<Vec<PathBuf>> = OnceLock::new();

/// Restrict every later read of this process to files inside `dirs` (each must be an existing folder). Once per
/// process: the command line sets it before the scene is read.
pub fn restrict_reads(dirs: &[PathBuf]) -> Result<()> {
    let mut canonical = Vec::with_capacity(dirs.len());
    for d in dirs {
        let c = std::fs::canonicalize(d).map_err(|e| PrismError::io(d, e))?;
        if !c.is_dir() {
            return Err(PrismError::format(d, "--allow-read names a folder; this is not one"));
        }
        canonical.push(c);
    }
    ALLOWED_READS.set(canonical).map_err(|_| PrismError::invalid("the folders reads are restricted to are already set"))
}

/// Whether reading `path` is allowed: always without [`restrict_reads`]; otherwise when its canonical path (every
/// symbolic link followed) lies inside one of the folders.
fn check_allowed(path: &Path) -> Result<()> {
    let Some(dirs) = ALLOWED_READS.get() else { return Ok(()) };
    let inside = std::fs::canonicalize(path).is_ok_and(|c| dirs.iter().any(|d| c.starts_with(d)));
    if inside { Ok(()) } else { Err(PrismError::format(path, "outside the folders --allow-read permits: not read")) }
}

/// Open `path` for reading if it is a regular file; returns the file and its length. `what` names the kind of
/// file in the not-found message ("image file", "environment map").
pub fn open_regular(path: &Path, what: &str) -> Result<(std::fs::File, u64)> {
    check_allowed(path)?;
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
