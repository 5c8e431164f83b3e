//! Outputs are checked before any work starts, so a long render never fails at its end or overwrites what it
//! read: each output's directory must exist and accept a new file (a probe file is created and removed), the
//! output must not be a directory, and it must not be one of the scene's inputs (the scene file, meshes and their
//! MTL libraries, textures, environment maps: same file by path or by device and inode).

use crate::error::{PrismError, Result};
use std::path::{Path, PathBuf};

/// Check that every path of `outputs` can be written and is none of `inputs` (see the module doc).
pub fn check_outputs(outputs: &[PathBuf], inputs: &[PathBuf]) -> Result<()> {
    let inputs = with_mtl_libraries(inputs);
    for out in outputs {
        if out.is_dir() {
            return Err(PrismError::invalid(format!("{}: the output is a directory", out.display())));
        }
        if let Some(input) = inputs.iter().find(|i| same_file(out, i)) {
            return Err(PrismError::invalid(format!(
                "{}: the output would overwrite {}, an input of the scene",
                out.display(),
                input.display()
            )));
        }
        check_writable_dir(out)?;
    }
    Ok(())
}

/// The directory `out` will be written in exists and accepts new files.
pub fn check_writable_dir(out: &Path) -> Result<()> {
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(PrismError::invalid(format!(
            "{}: cannot write the output: directory {} does not exist",
            out.display(),
            dir.display()
        )));
    }
    let name = out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    let probe = dir.join(format!(".{name}.prism-write-check-{}", std::process::id()));
    match std::fs::OpenOptions::new().write(true).create_new(true).open(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => {
            Err(PrismError::invalid(format!("{}: cannot write in directory {}: {e}", out.display(), dir.display())))
        }
    }
}

/// True when `a` and `b` name the same existing file (same canonical path, or same device and inode).
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if ma.dev() == mb.dev() && ma.ino() == mb.ino() {
            return true;
        }
    }
    let _ = (ma, mb);
    matches!((std::fs::canonicalize(a), std::fs::canonicalize(b)), (Ok(x), Ok(y)) if x == y)
}

/// `inputs` plus the MTL libraries their OBJ files name (`mtllib` lines, relative to the OBJ).
fn with_mtl_libraries(inputs: &[PathBuf]) -> Vec<PathBuf> {
    let mut all = inputs.to_vec();
    for obj in inputs.iter().filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj"))) {
        let Ok(bytes) = crate::io::read_regular(obj, "mesh file") else { continue };
        let dir = obj.parent().unwrap_or(Path::new("."));
        for line in String::from_utf8_lossy(&bytes).lines() {
            if let Some(rest) = line.trim_start().strip_prefix("mtllib") {
                all.extend(rest.split_whitespace().map(|m| dir.join(m)));
            }
        }
    }
    all
}
